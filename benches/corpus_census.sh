#!/usr/bin/env bash
# The corpus census of issue 40: every Adams dataset of ../shared/corpus run for a short
# span with the release CLI, one line each (exit code, dataset, the first error, what the
# run leaves out), then the counts. Usage: bash benches/corpus_census.sh [END] [OUT.tsv]
# (END defaults to 0.1 time units; OUT to census.tsv). Build first: cargo build --release.
set -uo pipefail
cd "$(dirname "$0")/.."
end=${1:-0.1}
out=$(realpath -m "${2:-census.tsv}")
mbfx=$(pwd)/target/release/mbfx
[ -x "$mbfx" ] || { echo "build first: cargo build --release" >&2; exit 1; }
: >"$out"
cd ../shared/corpus/adams
find . -name '*.adm' | sort | while read -r f; do
    err=$(timeout 120 "$mbfx" run --color never "$f" --end "$end" --csv /dev/null 2>&1 >/dev/null)
    rc=$?
    first=$(grep -m1 -E '^\[E[0-9]+\]' <<<"$err" | cut -c1-160)
    left=$(grep -m1 'not modelled' <<<"$err" | sed 's/.*not modelled: //' | cut -c1-120)
    printf '%s\t%s\t%s\t%s\n' "$rc" "${f#./}" "$first" "$left" >>"$out"
done
total=$(wc -l <"$out")
ran=$(awk -F'\t' '$1 == 0' "$out" | wc -l)
whole=$(awk -F'\t' '$1 == 0 && $4 == ""' "$out" | wc -l)
echo "$total datasets: $ran run to t = $end ($whole with nothing left out), $((total - ran)) stop"
echo "stops by first error code:"
awk -F'\t' '$1 != 0 {match($3, /E[0-9]+/); print "  " (RSTART ? substr($3, RSTART, 5) : "rc " $1)}' "$out" | sort | uniq -c | sort -rn
echo "left out by runs that finish:"
awk -F'\t' '$1 == 0 && $4 != "" {print "  " $4}' "$out" | sort | uniq -c | sort -rn

#!/usr/bin/env bash
# Peer points for `mbfx bench wp --peers DIR`: builds the reference scenes in Exudyn and
# MuJoCo, sweeps their settings, writes OUT/<scene>.csv (header: see README.md).
#   benches/peers/run.sh [OUT] [extra options for both scripts, e.g. --quick, --only SCENE]
# OUT defaults to target/peers (relative to the repository root). The truth files are read
# from examples/scenes/ (override with --scenes DIR). Not part of CI.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
out="${1:-$root/target/peers}"
[ $# -gt 0 ] && shift
source "$here/venv.sh"
mkdir -p "$out"
# each script appends its rows to OUT/<scene>.csv: start from empty files
for s in a01_pendulum chain_n100 impact_block_k1e5 impact_block_k1e7 slider_crank_driven; do
  rm -f "$out/$s.csv"
done
out="$(cd "$out" && pwd)"
# run from OUT: MuJoCo writes its MUJOCO_LOG.TXT (unstable coarse steps) to the working directory
cd "$out"
"$venv/bin/python" -u "$here/mujoco_scenes.py" "$out" "$@"
"$venv/bin/python" -u "$here/exudyn_scenes.py" "$out" "$@"
echo "peer points written to $out"

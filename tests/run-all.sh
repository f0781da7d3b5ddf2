#!/usr/bin/env bash
# Every test of mbfx, as README.md gives it: the Rust workspace (the C API's tests, which
# compile C programs with the system's cc, included), then the Python module installed
# with `pip install .` into a virtual environment (.venv, or $MBFX_VENV; made when
# missing) and its pytest suite. Run it from anywhere; ../shared must be beside the
# repository.
set -euo pipefail
cd "$(dirname "$0")/.."

echo "== Rust and C (cargo test --workspace --release)"
cargo test --workspace --release --locked

echo "== Python (pip install . into ${MBFX_VENV:-.venv}, then pytest)"
venv=${MBFX_VENV:-.venv}
if [ ! -x "$venv/bin/python" ]; then
    python3 -m venv "$venv"
fi
python=$(cd "$venv/bin" && pwd)/python
"$python" -m pip install --quiet --disable-pip-version-check -r python/requirements-test.txt
"$python" -m pip install --quiet --disable-pip-version-check .
# From the tests' folder, so the installed package (not python/mbfx) is what is imported.
(cd tests/python && "$python" -m pytest -q -p no:cacheprovider .)

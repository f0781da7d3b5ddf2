#!/usr/bin/env bash
# Every test of mbfx, as README.md gives it: the Rust workspace (the C API's tests, which
# compile C programs with the system's cc, included; the animation's tests with node's
# glTF validator and headless Chromium), then the Python module installed
# with `pip install .` into a virtual environment (.venv, or $MBFX_VENV; made when
# missing) and its pytest suite. Run it from anywhere; ../shared must be beside the
# repository.
set -euo pipefail
cd "$(dirname "$0")/.."

# What the tests of mbfx run --animate need beyond Rust and Python, looked at before the
# long build: the Khronos glTF validator (node, pinned in tests/node; installed here when
# missing) and Debian's headless Chromium (a system package, which a test script does not
# install behind the user's back: .ci/run installs it as root; here the command is told).
echo "== node packages and headless Chromium (the tests of mbfx run --animate)"
if [ ! -d tests/node/node_modules/gltf-validator ]; then
    if ! command -v npm >/dev/null; then
        echo "error: npm is missing (the glTF validator runs on node): sudo apt-get install npm" >&2
        exit 1
    fi
    npm ci --prefix tests/node --no-audit --no-fund
fi
if [ ! -x /usr/bin/chromium-headless-shell ]; then
    echo "error: /usr/bin/chromium-headless-shell is missing (the viewer's tests screenshot" >&2
    echo "the page in it); install Debian's package, then run this again:" >&2
    echo "    sudo apt-get install chromium-headless-shell" >&2
    exit 1
fi

echo "== Rust and C (cargo test --workspace --release)"
cargo test --workspace --release --locked
# The FMU's slave library beside the mbfx binary, where `mbfx fmu` takes it from
# (tests/python/test_fmu.py exports an FMU); the test run built it, this copies it up.
cargo build --release --locked -p mbfx-fmi

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
# The stubs (python/mbfx/_mbfx.pyi) against the installed module; allowlist: why each entry.
(cd tests/python && "$python" -m mypy.stubtest mbfx --mypy-config-file stubtest.ini --allowlist stubtest-allowlist.txt)

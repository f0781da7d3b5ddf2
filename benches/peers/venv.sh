# Sourced by run.sh and run_stability.sh (after they set `here`): the peers' virtual
# environment (${PEERS_VENV:-/tmp/mbfx-peers-venv}), made once, with requirements.txt.
venv="${PEERS_VENV:-/tmp/mbfx-peers-venv}"
if [ ! -x "$venv/bin/python" ]; then
  python3 -m venv "$venv"
fi
"$venv/bin/python" -m pip install -q -r "$here/requirements.txt"

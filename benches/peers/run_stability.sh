#!/usr/bin/env bash
# Stability cells of the peers: the cases of `mbfx bench stability` built in Exudyn and
# MuJoCo, every peer method on every case, each cell in its own subprocess (timeout 120 s),
# judged like the mbfx suite; writes OUT/stability.csv (see README.md, "Stability cells").
#   benches/peers/run_stability.sh [OUT] [--peer exudyn|mujoco] [--case ID]... [--timeout S]
# OUT defaults to target/peers. Uses the venv of run.sh (${PEERS_VENV:-/tmp/mbfx-peers-venv});
# the A02 datasets are generated with `mbfx bench generate` ($MBFX, default
# target/release/mbfx of this repository, built here when missing).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
out="${1:-$root/target/peers}"
[ $# -gt 0 ] && shift
source "$here/venv.sh"
if [ -z "${MBFX:-}" ] && [ ! -x "$root/target/release/mbfx" ]; then
  (cd "$root" && cargo build --release --bin mbfx)
fi
mkdir -p "$out"
out="$(cd "$out" && pwd)"
"$venv/bin/python" -u "$here/stability_peers.py" "$out" "$@"

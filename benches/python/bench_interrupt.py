"""How soon Ctrl-C stops `Model.run` (issue 43 §3): a child Python process starts a long
run of the slider (examples/slider.adm, GSTIFF, 10⁴ s of model time); this process waits
until it is running, a random 0.2–0.6 s more, sends SIGINT and reads back when the child
caught `KeyboardInterrupt`. Both read CLOCK_MONOTONIC (one clock for every process on
Linux), so the latency is the child's catch less the send. N trials, the median and
the worst.

    python benches/python/bench_interrupt.py [--trials N]
"""

from __future__ import annotations

import argparse
import os
import random
import signal
import statistics
import subprocess
import sys
import time
from pathlib import Path

SLIDER = Path(__file__).resolve().parents[2] / "examples" / "slider.adm"

CHILD = r"""
import sys, time, mbfx
m = mbfx.load(sys.argv[1])
m.run(0.01)                              # compiled and warm before the long run
print("running", flush=True)
try:
    m.run(1e4, output_step=0.01, integrator="gstiff")
except KeyboardInterrupt as e:
    caught = time.monotonic()
    rows = len(e.run) if getattr(e, "run", None) is not None else -1
    print(f"caught {caught!r} {rows}", flush=True)
else:
    print("finished", flush=True)
"""


def trial(rng: random.Random) -> float:
    child = subprocess.Popen([sys.executable, "-c", CHILD, str(SLIDER)], stdout=subprocess.PIPE, text=True)
    assert child.stdout is not None
    if child.stdout.readline().strip() != "running":
        raise SystemExit("the child did not start its run")
    time.sleep(rng.uniform(0.2, 0.6))
    sent = time.monotonic()
    os.kill(child.pid, signal.SIGINT)
    line = child.stdout.readline().split()
    child.wait(timeout=60)
    if not line or line[0] != "caught" or int(line[2]) < 1:
        raise SystemExit(f"the child did not stop with KeyboardInterrupt and its rows: {line}")
    return float(line[1]) - sent


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--trials", type=int, default=20)
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args()
    rng = random.Random(args.seed)
    ms = [1e3 * trial(rng) for _ in range(args.trials)]
    print("latencies (ms):", " ".join(f"{x:.1f}" for x in ms))
    print(
        f"{args.trials} trials: median {statistics.median(ms):.1f} ms, "
        f"best {min(ms):.1f} ms, worst {max(ms):.1f} ms"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())

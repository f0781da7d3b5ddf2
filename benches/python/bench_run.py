"""What `Model.run` adds to a run: the IMPACT block (k = 1e5) and the A01 pendulum of
examples/scenes, run from Python R times each. Python's share is the wall time of
`Model.run` less the session call it wraps (`run.stats["session_seconds"]`: reading,
building, compiling and integrating), reported against the integration's CPU
(`run.stats["cpu_seconds"]`), the median over the runs.

    python benches/python/bench_run.py [--repeat R]
"""

from __future__ import annotations

import argparse
import statistics
import time
from pathlib import Path

import mbfx

SCENES = Path(__file__).resolve().parents[2] / "examples" / "scenes"

CASES = [
    # name, dataset, end, output step, probes, settings (as the bench's curves run them)
    ("IMPACT block k = 1e5", "impact_block_k1e5.adm", 2.0, 0.01, {"y": "DY(201, 101)"},
     {"integrator": "dopri853", "error": 3e-6, "hmin": 1e-10}),
    ("A01 pendulum", "a01_pendulum.adm", 10.0, 0.01, {"x": "DX(201)", "y": "DY(201)"},
     {"integrator": "dopri853", "error": 3e-7}),
]


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repeat", type=int, default=21)
    args = ap.parse_args()
    print("| scene | rows | integration CPU (ms) | session call (ms) | Model.run wall (ms) | Python's share of the integration |")
    print("|---|---|---|---|---|---|")
    for name, file, end, dt, probes, settings in CASES:
        model = mbfx.load(SCENES / file)
        cpu, session, wall, share = [], [], [], []
        for _ in range(args.repeat):
            t0 = time.perf_counter()
            run = model.run(end, output_step=dt, probes=probes, **settings)
            w = time.perf_counter() - t0
            s = run.stats
            cpu.append(s["cpu_seconds"])
            session.append(s["session_seconds"])
            wall.append(w)
            share.append((w - s["session_seconds"]) / s["cpu_seconds"])
        m = statistics.median
        print(f"| {name} | {len(run)} | {m(cpu)*1e3:.3f} | {m(session)*1e3:.3f} | {m(wall)*1e3:.3f} | {m(share)*100:.1f} % |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

"""A design study's cost on Dask: the IMPACT block's peak force and rebound height over
stiffness × damping × drop height, N Latin-hypercube variants, on a LocalCluster of 1
and of 2 worker processes (one thread each), side by side in one run.

    python benches/python/bench_study.py [--n 1000] [--engine jit|interp] [--compile-once] [--plot DIR]
    python benches/python/bench_study.py --scene chain

With --compile-once the three factors are design variables (VARIABLE/1 the stiffness,
VARIABLE/2 the damping, VARIABLE/3 the stop's position, which sets the drop height with
the block's start fixed), so each worker builds the model once and reruns it; without,
they are templates of the IMPACT call and the block's start marker, and each variant
reads, checks and compiles the dataset. --scene chain runs the planar chain of 30 rods
instead: 64 variants (8 × 8, full factorial) of the first link's length and the joints'
damping (a design variable), 1 s each.

Prints, for each cluster size: the start-up (cluster start and first contact), the study's
wall time, the sum of the variants' own wall times (each timed in its worker), the
ideal (that sum / workers + start-up) and the ratio of wall to ideal, then the efficiency
from 1 to 2 workers (wall(1) / (2 · wall(2)), start-ups left out), and Dask's own cost
of a task on this machine (no-op tasks). With --plot, writes
the sensitivity chart and the response-against-factor plots of the 2-worker study.
"""

from __future__ import annotations

import argparse
import logging
import sys
import time
from pathlib import Path

import mbfx
from bench_variants import chain_dataset  # the chain with a damper at every joint
from mbfx import study

ROOT = Path(__file__).resolve().parents[2]
DATASET = ROOT / "examples" / "scenes" / "impact_block_k1e5.adm"
STOP = "IMPACT(DY(201, 101), VY(201, 101), 0.05, {k}, 1.5, {c}, 0.1)"


def impact_design_dataset() -> str:
    """The IMPACT block with k, c and the stop's position as VARIABLE/1, 2 and 3."""
    text = DATASET.read_text().replace(
        "IMPACT(DY(201, 101), VY(201, 101), 0.05, 1E5, 1.5, 50, 0.1)",
        "IMPACT(DY(201, 101), VY(201, 101), VARVAL(3), VARVAL(1), 1.5, VARVAL(2), 0.1)",
    )
    return text.replace(
        "ACCGRAV/JGRAV = -9.81",
        "VARIABLE/1, FUNCTION = 1E5\nVARIABLE/2, FUNCTION = 50\nVARIABLE/3, FUNCTION = 0.05\n"
        "ACCGRAV/JGRAV = -9.81",
    )


def run_study(model, n: int, workers: int, end: float, engine: str, study_of=None):
    """The study of `n` variants on a new cluster of `workers`: (Study, start-up, wall).
    The start-up holds the cluster's start and a warm-up study of one variant a worker
    (each worker imports mbfx and numpy and unpickles the model once)."""
    from distributed import Client, LocalCluster

    t0 = time.perf_counter()
    with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, silence_logs=logging.CRITICAL) as cluster, Client(cluster) as client:
        study_of = study_of or variants
        study_of(model, workers, end, client, engine, batch=1)
        startup = time.perf_counter() - t0
        t1 = time.perf_counter()
        s = study_of(model, n, end, client, engine)
        wall = time.perf_counter() - t1
    return s, startup, wall


def variants(model, n: int, end: float, client, engine: str, batch=None):
    """The study itself: stiffness (log scale), damping and drop height, Latin hypercube."""
    return study.run(
        model,
        # h: the block's start height (its CM marker's y), 0.1 to 0.3 m above the stop.
        factors={"k": study.log(1e4, 1e6), "c": (10.0, 100.0), "h": (0.15, 0.35)},
        templates={"SFORCE/1.FUNCTION": STOP, "MARKER/201.QP": "0, {h}, 0"},
        responses={
            "peak_force": study.max("f"),
            # The highest point above the stop in the second second.
            "rebound": lambda run: float(run["y"][len(run["y"]) // 2 :].max()) - 0.05,
        },
        probes={"y": "DY(201, 101)", "f": "SFORCE(1, 0, 1, 0)"},
        end=end,
        run_args={"integrator": "dopri853", "error": 3e-6, "hmin": 1e-10, "output_step": 0.01, "engine": engine},
        design="lhs",
        n=n,
        seed=7,
        client=client,
        batch=batch,
    )


def design_variants(model, n: int, end: float, client, engine: str, batch=None):
    """The same study with the factors as design variables: the drop height h moves the
    stop (VARIABLE/3 = 0.2 - h) under the block's fixed start at 0.15."""
    return study.run(
        model,
        design=_lhs_table(n),
        responses={
            "peak_force": study.max("f"),
            "rebound": lambda run: float(run["above"][len(run["above"]) // 2 :].max()),
        },
        probes={"above": "DY(201, 101) - VARVAL(3)", "f": "SFORCE(1, 0, 1, 0)"},
        end=end,
        run_args={"integrator": "dopri853", "error": 3e-6, "hmin": 1e-10, "output_step": 0.01, "engine": engine},
        client=client,
        batch=batch,
    )


def _lhs_table(n: int):
    """The Latin hypercube of `variants` over k (log), c and h, as design-variable values."""
    import pandas as pd
    from scipy.stats import qmc

    u = qmc.LatinHypercube(d=3, seed=7).random(n)
    k = 10 ** (4 + 2 * u[:, 0])
    c = 10 + 90 * u[:, 1]
    h = 0.15 + 0.2 * u[:, 2]
    return pd.DataFrame({"VARIABLE/1.FUNCTION": k, "VARIABLE/2.FUNCTION": c, "VARIABLE/3.FUNCTION": 0.2 - h})


def chain_variants(model, n: int, end: float, client, engine: str, batch=None):
    """The chain study: the first link's length (its end marker, the joint to the next
    rod; assembly moves the rest) and the joints' damping, 8 levels each."""
    return study.run(
        model,
        factors={"L": (0.08, 0.12), "VARIABLE/1.FUNCTION": (0.001, 0.02)},
        templates={"MARKER/203.QP": "{L}, 0, 0"},
        design="full" if n > 2 else _two_variants(),
        levels=8,
        responses={"tip_y_min": study.min("tip_y"), "tip_y_end": study.final("tip_y")},
        probes={"tip_y": "DY(3103)"},
        end=end,
        run_args={"integrator": "dopri853", "error": 1e-6, "output_step": 0.01, "engine": engine},
        client=client,
        batch=batch,
    )


def _two_variants():
    return [{"L": 0.1, "VARIABLE/1.FUNCTION": 0.01}, {"L": 0.11, "VARIABLE/1.FUNCTION": 0.005}]


def dask_task_overhead(tasks: int) -> float:
    """Seconds a no-op task costs the cluster (submit, schedule, run, gather), from
    `tasks` of them on a warm 2-worker LocalCluster: the scheduler's share that batching
    spreads over a batch's variants."""
    from distributed import Client, LocalCluster

    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, silence_logs=logging.CRITICAL) as cluster, Client(cluster) as client:
        client.gather(client.map(int, range(100)))
        t0 = time.perf_counter()
        client.gather(client.map(int, range(1, tasks + 1)))
        return (time.perf_counter() - t0) / tasks


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--n", type=int, default=1000)
    ap.add_argument("--engine", default="jit", choices=("jit", "interp"))
    ap.add_argument("--compile-once", action="store_true", help="the factors as design variables")
    ap.add_argument("--scene", default="impact", choices=("impact", "chain"))
    ap.add_argument("--plot", help="directory for the 2-worker study's charts")
    args = ap.parse_args()
    if args.scene == "chain":
        model, study_of, end, title = mbfx.load(chain_dataset(str(ROOT / "target" / "release" / "mbfx"), 30)), chain_variants, 1.0, "the planar chain of 30 rods (8 x 8 link length x damping), dopri853, 1 s each"
        args.n = 64
    elif args.compile_once:
        model, study_of, end, title = mbfx.load(impact_design_dataset()), design_variants, 2.0, "the IMPACT block (LHS over k, c and the drop height as design variables), dopri853, 2 s each"
    else:
        model, study_of, end, title = mbfx.load(DATASET), variants, 2.0, "the IMPACT block (LHS over k, c and the drop height), dopri853, 2 s each"
    rows = []
    studies = {}
    for workers in (1, 2):
        s, startup, wall = run_study(model, args.n, workers, end, args.engine, study_of)
        table = s.table
        ok = int((table["status"] == "ok").sum())
        cpu = float(table["seconds"].sum())
        ideal = cpu / workers + startup
        rows.append((workers, startup, wall, cpu, ideal, ok))
        studies[workers] = s
    per_task = dask_task_overhead(2000)
    print(f"{args.n} variants of {title}, engine {args.engine}")
    print("| workers | start-up s | study wall s | variants' own s | ideal s | wall / ideal | ok |")
    print("|---:|---:|---:|---:|---:|---:|---:|")
    for w, startup, wall, cpu, ideal, ok in rows:
        print(f"| {w} | {startup:.2f} | {wall:.2f} | {cpu:.2f} | {ideal - startup:.2f} | {wall / (ideal - startup):.2f} | {ok} |")
    eff = rows[0][2] / (2 * rows[1][2])
    print(f"efficiency 1 -> 2 workers: {eff:.1%}")
    print(f"Dask's own cost of a task here (2 000 no-op tasks on 2 workers): {per_task * 1e3:.3f} ms")
    if args.plot:
        out = Path(args.plot)
        out.mkdir(parents=True, exist_ok=True)
        for response in [c for c in ("peak_force", "rebound") if c in studies[2].table]:
            studies[2].plot_sensitivity(response, out / f"study_{response}_sensitivity.png")
            studies[2].plot(response, out / f"study_{response}.png")
            fit = studies[2].surface(response)
            effects = ", ".join(f"{k} {v:.4g}" for k, v in fit.main_effects.items())
            print(f"{response}: quadratic surface R² = {fit.r2:.3f}; main effects {effects}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

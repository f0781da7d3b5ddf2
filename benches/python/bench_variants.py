"""What a variant costs: from Python with compile once, run many, against a fresh
`mbfx run --set` process of the same variant, on the IMPACT block and the planar chain of
10 rods, at several run lengths.

    python benches/python/bench_variants.py [--variants 51] [--mbfx target/release/mbfx]

The IMPACT block's stiffness and damping and the chain's joint damping are design
variables (constant VARIABLEs read by VARVAL), so each variant from Python reruns the
simulation the first one built (`run.stats["reused"]`). Per variant it prints the
integration's CPU (`run.stats["cpu_seconds"]`), the wall time of `Model.run`, the overhead
(wall less integration) and its share of the wall, the fresh process's wall time and the
ratio fresh / Python. Each figure is the median over the variants (the overhead's of each
variant's own difference). A last row per scene
changes a statement field instead (a MARKER's QP, the chain's link length), which reads,
checks and builds the dataset again.
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import tempfile
import time
from pathlib import Path

import mbfx

ROOT = Path(__file__).resolve().parents[2]
IMPACT = ROOT / "examples" / "scenes" / "impact_block_k1e5.adm"


def impact_dataset() -> str:
    """The IMPACT block with k = VARVAL(1), c = VARVAL(2)."""
    text = IMPACT.read_text()
    text = text.replace(
        "IMPACT(DY(201, 101), VY(201, 101), 0.05, 1E5, 1.5, 50, 0.1)",
        "IMPACT(DY(201, 101), VY(201, 101), 0.05, VARVAL(1), 1.5, VARVAL(2), 0.1)",
    )
    return text.replace(
        "ACCGRAV/JGRAV = -9.81",
        "VARIABLE/1, FUNCTION = 1E5\nVARIABLE/2, FUNCTION = 50\nACCGRAV/JGRAV = -9.81",
    )


def chain_dataset(mbfx_bin: str, n: int) -> str:
    """The planar chain of `n` rods with a damper c = VARVAL(1) at every joint."""
    text = subprocess.run([mbfx_bin, "bench", "generate", "chain", str(n)], check=True,
                          capture_output=True, text=True).stdout
    dampers = ["VARIABLE/1, FUNCTION = 0.01"]
    for k in range(1, n + 1):
        i = 102 if k == 1 else k * 100 + 3
        j = (k + 1) * 100 + 2
        dampers.append(f"SFORCE/{k}, ROTATION, I = {j}, J = {i}, FUNCTION = -VARVAL(1)*WZ({j}, {i}, {i})")
    return text.replace("ACCGRAV/JGRAV", "\n".join(dampers) + "\nACCGRAV/JGRAV")


def scenes(mbfx_bin: str):
    """(name, dataset, probes, run settings, [(end, design settings per variant)], statement setting)."""
    impact = dict(integrator="dopri853", error=3e-6, hmin=1e-10)
    chain = dict(integrator="dopri853", error=1e-6)
    stiff = lambda v: {"VARIABLE/1.FUNCTION": 10 ** (4 + 2 * v), "VARIABLE/2.FUNCTION": 10 + 90 * v}
    damp = lambda v: {"VARIABLE/1.FUNCTION": 0.001 + 0.02 * v}
    return [
        ("IMPACT block", impact_dataset(), {"y": "DY(201, 101)"}, impact, [0.05, 0.1, 0.25, 2.0], stiff,
         lambda v: {"MARKER/201.QP": f"0, {0.15 + 0.1 * v!r}, 0"}),
        ("planar chain N = 10", chain_dataset(mbfx_bin, 10), {"x": "DX(1103)"}, chain, [0.02, 0.1, 1.0], damp,
         lambda v: {"MARKER/203.QP": f"{0.1 + 0.01 * v!r}, 0, 0"}),
    ]


def fresh(mbfx_bin: str, path: Path, end: float, probes, settings, sets) -> float:
    """Wall seconds of one `mbfx run` process of the variant."""
    args = [mbfx_bin, "run", str(path), "--end", str(end), "--output-step", str(end / 100), "--csv", "/dev/null"]
    for k, v in settings.items():
        args += [f"--{k.replace('_', '-')}", str(v)]
    for k, v in probes.items():
        args += ["--probe", f"{k}={v}"]
    for k, v in sets.items():
        args += ["--set", f"{k}={v!r}" if isinstance(v, float) else f"{k}={v}"]
    t = time.perf_counter()
    subprocess.run(args, check=True, capture_output=True)
    return time.perf_counter() - t


def measure(model, mbfx_bin, path, end, probes, settings, variants, sets_of):
    cpu, wall, proc, reused = [], [], [], 0
    model.run(end, output_step=end / 100, probes=probes, **settings)  # builds once
    variant_sets = [sets_of(n / max(variants - 1, 1)) for n in range(variants)]
    # The Python variants one after the other (as a study's worker runs them), then the
    # processes: a process between two variants would evict the caches they share.
    for sets in variant_sets:
        t = time.perf_counter()
        run = model.run(end, output_step=end / 100, probes=probes, set=sets, **settings)
        wall.append(time.perf_counter() - t)
        cpu.append(run.stats["cpu_seconds"])
        reused += bool(run.stats.get("reused"))
    for sets in variant_sets:
        proc.append(fresh(mbfx_bin, path, end, probes, settings, sets))
    med = statistics.median
    # The overhead per variant, then its median: variants differ in length, so the
    # difference of the medians of wall and CPU would mix two variants.
    over = med(w - c for w, c in zip(wall, cpu))
    share = med((w - c) / w for w, c in zip(wall, cpu))
    return med(wall), med(cpu), med(proc), reused, over, share


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--variants", type=int, default=51)
    ap.add_argument("--mbfx", default=str(ROOT / "target" / "release" / "mbfx"))
    args = ap.parse_args()
    print("| scene | end (s) | variants changing | reused | integration CPU (ms) | Model.run wall (ms) "
          "| overhead (share of wall) | fresh `mbfx run` (ms) | fresh / Python |")
    print("|---|---|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for name, text, probes, settings, ends, design, statement in scenes(args.mbfx):
            path = Path(tmp) / "scene.adm"
            path.write_text(text)
            model = mbfx.load(path)
            rows = [(end, "design variables", design) for end in ends]
            rows.append((ends[-1], "a statement field", statement))
            for end, what, sets_of in rows:
                w, c, p, reused, over, share = measure(model, args.mbfx, path, end, probes, settings, args.variants, sets_of)
                print(f"| {name} | {end:g} | {what} | {reused}/{args.variants} | {1e3 * c:.2f} | {1e3 * w:.2f} "
                      f"| {1e3 * over:.3f} ms ({100 * share:.1f} %) | {1e3 * p:.2f} | {p / w:.1f}× |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

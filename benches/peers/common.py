"""Shared helpers for the peer scripts: truth loading, scoring, timing, CSV rows.

The truth files are examples/scenes/<scene>.toml (format: examples/scenes/README.md).
Scoring, per group (position | reaction): max over every [[at]] row and probe of the
group of |y - r| / scale, or |y - r| / |r| for a `relative` probe.
"""
import argparse
import csv
import math
import os
import sys
import time
import tomllib

HEADER = ["scene", "method", "formulation", "control", "setting", "error_position",
          "error_reaction", "cpu_s", "steps", "rejected", "newton_iterations",
          "factorizations", "expression_evaluations", "status"]

REPO = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))

# The exact A01 values of reference-problems.md §4.1, used only when
# examples/scenes/a01_pendulum.toml is not in the scenes directory.
A01_FALLBACK = {
    "end": 10.0, "scale": 1.0,
    "probes": [{"name": "x", "group": "position", "relative": False},
               {"name": "y", "group": "position", "relative": False}],
    "at": [(0.5, {"x": 0.39104879155054639, "y": -0.9203699487851922}),
           (1.0, {"x": -0.98629175113187532, "y": -0.16501085312554117}),
           (2.0, {"x": 0.79356619534332175, "y": -0.60848393044379151}),
           (10.0, {"x": 0.27508746257611686, "y": -0.96141920509912506})],
    "source": "reference-problems.md §4.1 (built-in fallback)",
}


class Truth:
    def __init__(self, scene, d):
        self.scene = scene
        self.end = float(d["end"])
        self.scale = float(d.get("scale", 1.0))
        self.probes = d["probes"]
        self.at = sorted(d["at"], key=lambda r: r[0])
        self.times = [t for t, _ in self.at]
        self.source = d.get("source", "")
        self.names = [p["name"] for p in self.probes]


def load_truth(scenes_dir, scene):
    """Truth of `scene` from scenes_dir/<scene>.toml, or None when the file is missing."""
    path = os.path.join(scenes_dir, scene + ".toml")
    if not os.path.exists(path):
        if scene == "a01_pendulum":
            return Truth(scene, A01_FALLBACK)
        return None
    with open(path, "rb") as f:
        t = tomllib.load(f)
    probes = [{"name": p["name"], "group": p.get("group", "position"),
               "relative": bool(p.get("relative", False))} for p in t["probe"]]
    names = [p["name"] for p in probes]
    at = []
    for row in t["at"]:
        at.append((float(row["time"]), {n: float(row[n]) for n in names if n in row}))
    return Truth(scene, {"end": t["end"], "scale": t.get("scale", 1.0), "probes": probes,
                         "at": at, "source": path})


def score(truth, values):
    """values: {time: {probe: value}} at every truth time. Returns (err_position, err_reaction);
    a group without probes scores None."""
    err = {"position": None, "reaction": None}
    for t, ref in truth.at:
        got = values[t]
        for p in truth.probes:
            n = p["name"]
            if n not in ref:
                continue
            y, r = got[n], ref[n]
            e = abs(y - r) / abs(r) if p["relative"] else abs(y - r) / truth.scale
            if not math.isfinite(e):
                e = math.inf
            g = p["group"]
            err[g] = e if err[g] is None else max(err[g], e)
    return err["position"], err["reaction"]


class Run:
    """What one solve returns: probe values at the truth times, the CPU time of the solve
    (time.process_time around the integration only), and the counters the peer reports."""
    def __init__(self, values, cpu, steps=None, rejected=None, newton=None,
                 factorizations=None, evaluations=None, status="ok"):
        self.values, self.cpu = values, cpu
        self.steps, self.rejected, self.newton = steps, rejected, newton
        self.factorizations, self.evaluations, self.status = factorizations, evaluations, status


def fmt(x):
    if x is None:
        return ""
    if isinstance(x, float):
        return "%.6e" % x if math.isfinite(x) else "inf"
    return str(x)


class Sweep:
    """Runs a peer's configurations for a scene, keeps the best CPU time of `repeats`
    runs of each (model building excluded: `build` is called before each timed solve),
    scores them and collects CSV rows."""
    def __init__(self, args, scene, truth):
        self.args, self.scene, self.truth = args, scene, truth
        self.rows = []

    def point(self, method, formulation, control, setting, build, solve, note=None):
        """build() -> model (not timed); solve(model, truth) -> Run (times itself)."""
        best = None
        status = "ok"
        for _ in range(self.args.repeats):
            try:
                model = build()
                r = solve(model, self.truth)
            except Exception as e:  # a solver failure is a point with status failed
                msg = str(e).strip().splitlines()
                r = Run(None, None, status="failed: " + (type(e).__name__ + ": " + (msg[-1] if msg else "")).replace(",", ";")[:160])
            if r.status != "ok":
                best = r
                break
            if best is None or r.cpu < best.cpu:
                best = r
            if r.cpu > self.args.single_run_budget:   # long point: one run is enough
                break
        if best.status == "ok":
            ep, er = score(self.truth, best.values)
        else:
            ep = er = None
        row = [self.scene, method, formulation, control, setting, fmt(ep), fmt(er),
               fmt(best.cpu), fmt(best.steps), fmt(best.rejected), fmt(best.newton),
               fmt(best.factorizations), fmt(best.evaluations),
               best.status if note is None or best.status != "ok" else "ok"]
        self.rows.append(row)
        print(",".join(row), flush=True)
        return ep, er, best

    def write(self, out_dir):
        os.makedirs(out_dir, exist_ok=True)
        path = os.path.join(out_dir, self.scene + ".csv")
        new = not os.path.exists(path) or os.path.getsize(path) == 0
        with open(path, "a", newline="") as f:
            w = csv.writer(f, lineterminator="\n")
            if new:
                w.writerow(HEADER)
            w.writerows(self.rows)


def parse_args(peer, scenes):
    ap = argparse.ArgumentParser(description="%s peer points for mbfx bench wp" % peer)
    ap.add_argument("out", nargs="?", default=os.path.join(REPO, "target", "peers"),
                    help="output directory for <scene>.csv (rows are appended)")
    ap.add_argument("--scenes", default=os.path.join(REPO, "examples", "scenes"),
                    help="directory of the truth files <scene>.toml")
    ap.add_argument("--only", action="append", choices=scenes, help="run only these scenes")
    ap.add_argument("--repeats", type=int, default=3, help="runs per point; the best CPU is kept")
    ap.add_argument("--single-run-budget", type=float, default=2.0,
                    help="a point whose run takes longer than this (s) is run once")
    ap.add_argument("--max-cpu", type=float, default=20.0,
                    help="a sweep stops refining once one point takes longer than this (s)")
    ap.add_argument("--quick", action="store_true", help="fewer points (smoke test)")
    return ap.parse_args()


def main(peer, registry):
    """registry: {scene: function(sweep)}."""
    args = parse_args(peer, list(registry))
    for scene, fn in registry.items():
        if args.only and scene not in args.only:
            continue
        truth = load_truth(args.scenes, scene)
        if truth is None:
            print("%s: %s: no truth file %s/%s.toml; skipped" % (peer, scene, args.scenes, scene),
                  file=sys.stderr)
            continue
        sw = Sweep(args, scene, truth)
        fn(sw)
        sw.write(args.out)


def values_dict(times, rows):
    """rows: list of {probe: value} aligned with times."""
    return {t: r for t, r in zip(times, rows)}


def refine(sw, values_list, make_point, floor=1e-11):
    """Run make_point(v) for each v (coarse to fine); stop refining once a point is below
    `floor` in every group, the error stops falling below 1e-5 (a plateau: round-off or the
    peer's own floor), a point fails after an ok one, or the next point would cost more than --max-cpu."""
    seen_ok, prev, flat = False, None, 0
    for v in values_list:
        ep, er, best = make_point(v)
        if best.status != "ok":
            if seen_ok:
                break
            continue
        seen_ok = True
        errs = [e for e in (ep, er) if e is not None]
        err = max(errs) if errs else None
        if err is not None and err < floor:
            break
        if err is not None and prev is not None and err < 1e-5 and err > 0.7 * prev:
            flat += 1
            if flat >= 2:
                break
        else:
            flat = 0
        prev = err
        if best.cpu is not None and best.cpu * 3 > sw.args.max_cpu:
            break

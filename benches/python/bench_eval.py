"""Vectorised evaluation from Python: the eight expressions of
../shared/bench/expressions.md over 10^6 points, single thread, side by side in one run:
mbfx (JIT and interpreter), numexpr (one thread), plain numpy, and a per-point Python
loop (timed on 10^4 points and scaled). Also the overhead of a small call (`f(0.5)`).

    python benches/python/bench_eval.py [--points N] [--repeat R] [--threads T] [--out FILE.md]

`--threads T` gives mbfx (`compile(threads=T)`) and numexpr (`set_num_threads(T)`) T
threads each (default 1).

Prints a markdown table of ns per point (the fastest of R rounds, each timing every engine
in turn) with ratios to numexpr, and
the geometric mean of numexpr/mbfx over the rows numexpr can write (all eight: STEP,
IMPACT, BISTOP, IF and MIN/MAX are written with `where`). Inputs as the bench file says:
x uniform in [0, 2], v in [-2, 2], t in [-0.5, 1.5], fixed seed; `t` is a variable.
"""

from __future__ import annotations

import argparse
import math
import statistics
import sys
import time
import timeit

import numpy as np

import mbfx

EXPRESSIONS = {
    "arith": "3*x**3 - 2*x*v + v**2/(1 + t*t) - 4.5*x + 7",
    "trig": "SIN(2*PI*t)*COS(x) + ATAN2(v, x)",
    "step": "STEP(t, 0, 0, 1, 5)",
    "impact": "IMPACT(x, v, 1, 1e5, 1.5, 50, 0.1)",
    "bistop": "BISTOP(x, v, 0.5, 1.5, 1e5, 1.5, 50, 0.1)",
    "if3": "IF(x - 1: -x*v, 0, IF(v: x + t, x, IF(t - 0.5: x*t, t, v*x - t)))",
    "poly": "POLY(x, 0, 1, 2, 3, 4)",
    "long": "(x*v - 2.5*t)/(1 + x*x + v*v) + 3*SIN(x*t) - COS(v)*EXP(-0.5*t) + SQRT(ABS(x*v*t) + 1)"
    " - MIN(x, v)*MAX(t, 0.5) + (x - v)*(x + v)*(t - 1)/(2 + t*t) + 0.25*x**2 - 0.125*v**3"
    " + ABS(x - 1)*v - t/3 + 0.001*x*v*t",
}

# STEP's cubic with s = (t - 0)/(1 - 0), h0 = 0, h1 = 5 (spec §STEP).
_STEP = "where(t <= 0, 0.0, where(t >= 1, 5.0, 5*t*t*(3 - 2*t)))"


def _ramp(q: str) -> str:
    """STEP(q, 0, 0, 1, 1) as numexpr text (IMPACT/BISTOP's damping ramp over d)."""
    return f"where(({q}) <= 0, 0.0, where(({q}) >= 1, 1.0, ({q})*({q})*(3 - 2*({q}))))"


# IMPACT(x, v, x1 = 1, k = 1e5, e = 1.5, c = 50, d = 0.1): contact when x < x1, force
# k(x1 - x)^e - STEP(x, x1 - d, c, x1, 0)·v, never pulling (decision 5).
_IMPACT_DAMP = "50*" + _ramp("(1 - x)/0.1")
_IMPACT = f"where(x < 1, where(1e5*(1 - x)**1.5 - {_IMPACT_DAMP}*v > 0, 1e5*(1 - x)**1.5 - {_IMPACT_DAMP}*v, 0.0), 0.0)"
# BISTOP(x, v, 0.5, 1.5, ...): the same law at each end of the gap.
_LOW_DAMP = "50*" + _ramp("(0.5 - x)/0.1")
_HIGH_DAMP = "50*" + _ramp("(x - 1.5)/0.1")
_BISTOP = (
    f"where(x < 0.5, where(1e5*(0.5 - x)**1.5 - {_LOW_DAMP}*v > 0, 1e5*(0.5 - x)**1.5 - {_LOW_DAMP}*v, 0.0),"
    f" where(x > 1.5, where(-1e5*(x - 1.5)**1.5 - {_HIGH_DAMP}*v < 0, -1e5*(x - 1.5)**1.5 - {_HIGH_DAMP}*v, 0.0), 0.0))"
)

NUMEXPR = {
    "arith": "3*x**3 - 2*x*v + v**2/(1 + t*t) - 4.5*x + 7",
    "trig": "sin(2*3.141592653589793*t)*cos(x) + arctan2(v, x)",
    "step": _STEP,
    "impact": _IMPACT,
    "bistop": _BISTOP,
    "if3": "where(x - 1 < 0, -x*v, where(x - 1 == 0, 0.0, where(v < 0, x + t, where(v == 0, x,"
    " where(t - 0.5 < 0, x*t, where(t - 0.5 == 0, t, v*x - t))))))",
    "poly": "1 + x*(2 + x*(3 + x*4))",
    "long": "(x*v - 2.5*t)/(1 + x*x + v*v) + 3*sin(x*t) - cos(v)*exp(-0.5*t) + sqrt(abs(x*v*t) + 1)"
    " - where(x < v, x, v)*where(t > 0.5, t, 0.5) + (x - v)*(x + v)*(t - 1)/(2 + t*t) + 0.25*x**2"
    " - 0.125*v**3 + abs(x - 1)*v - t/3 + 0.001*x*v*t",
}


def numpy_forms():
    """The same expressions in plain numpy (temporaries and all)."""
    w = np.where

    def ramp(q):
        return w(q <= 0, 0.0, w(q >= 1, 1.0, q * q * (3 - 2 * q)))

    def impact(x, v, t):
        damp = 50 * ramp((1 - x) / 0.1)
        pen = np.maximum(1 - x, 0.0)
        f = 1e5 * pen**1.5 - damp * v
        return w(x < 1, np.maximum(f, 0.0), 0.0)

    def bistop(x, v, t):
        lo = 1e5 * np.maximum(0.5 - x, 0.0) ** 1.5 - 50 * ramp((0.5 - x) / 0.1) * v
        hi = -1e5 * np.maximum(x - 1.5, 0.0) ** 1.5 - 50 * ramp((x - 1.5) / 0.1) * v
        return w(x < 0.5, np.maximum(lo, 0.0), w(x > 1.5, np.minimum(hi, 0.0), 0.0))

    return {
        "arith": lambda x, v, t: 3 * x**3 - 2 * x * v + v**2 / (1 + t * t) - 4.5 * x + 7,
        "trig": lambda x, v, t: np.sin(2 * np.pi * t) * np.cos(x) + np.arctan2(v, x),
        "step": lambda x, v, t: w(t <= 0, 0.0, w(t >= 1, 5.0, 5 * t * t * (3 - 2 * t))),
        "impact": impact,
        "bistop": bistop,
        "if3": lambda x, v, t: w(x < 1, -x * v, w(x == 1, 0.0, w(v < 0, x + t, w(v == 0, x,
                              w(t < 0.5, x * t, w(t == 0.5, t, v * x - t)))))),
        "poly": lambda x, v, t: 1 + x * (2 + x * (3 + x * 4)),
        "long": lambda x, v, t: (x * v - 2.5 * t) / (1 + x * x + v * v) + 3 * np.sin(x * t)
        - np.cos(v) * np.exp(-0.5 * t) + np.sqrt(np.abs(x * v * t) + 1)
        - np.minimum(x, v) * np.maximum(t, 0.5) + (x - v) * (x + v) * (t - 1) / (2 + t * t)
        + 0.25 * x**2 - 0.125 * v**3 + np.abs(x - 1) * v - t / 3 + 0.001 * x * v * t,
    }


def best_of(fn, repeat: int) -> float:
    """Median seconds of `repeat` calls of fn (after one warm-up call)."""
    fn()
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def interleaved(fns: dict, repeat: int, n: int) -> dict:
    """Fastest ns per point of each callable, timed in turn round after round (so a
    change in the machine's load falls on all of them alike), after one warm-up each.
    The fastest round, not the median: on this shared machine other tenants only ever
    add time, and the median of one engine moved by 20 % from run to run."""
    for fn in fns.values():
        fn()
    times = {name: [] for name in fns}
    for _ in range(repeat):
        for name, fn in fns.items():
            t0 = time.perf_counter()
            fn()
            times[name].append(time.perf_counter() - t0)
    return {name: min(ts) / n * 1e9 for name, ts in times.items()}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--points", type=int, default=10**6)
    ap.add_argument("--repeat", type=int, default=7)
    ap.add_argument("--threads", type=int, default=1, help="threads of mbfx and of numexpr")
    ap.add_argument("--out", help="also write the table to this markdown file")
    args = ap.parse_args()
    import numexpr

    numexpr.set_num_threads(args.threads)
    n = args.points
    rng = np.random.default_rng(20261126)
    x = rng.uniform(0, 2, n)
    v = rng.uniform(-2, 2, n)
    t = rng.uniform(-0.5, 1.5, n)
    env = {"x": x, "v": v, "t": t}
    forms = numpy_forms()
    loop_n = min(n, 10**4)
    rows = []
    for name, text in EXPRESSIONS.items():
        jit = mbfx.compile(text, ("x", "v", "t"), threads=args.threads)
        interp = mbfx.compile(text, ("x", "v", "t"), engine="interp", threads=args.threads)
        want = jit(x, v, t)
        got_ne = numexpr.evaluate(NUMEXPR[name], local_dict=env)
        got_np = forms[name](x, v, t)
        for label, got in (("numexpr", got_ne), ("numpy", got_np)):
            bad = ~np.isclose(got, want, rtol=1e-9, atol=1e-9)
            if bad.any():
                k = int(np.argmax(bad))
                print(f"{name}: {label} differs from mbfx at x={x[k]}, v={v[k]}, t={t[k]}: {got[k]} vs {want[k]}",
                      file=sys.stderr)
                return 1
        cells = interleaved(
            {
                "mbfx jit": lambda: jit(x, v, t),
                "mbfx interp": lambda: interp(x, v, t),
                "numexpr": lambda: numexpr.evaluate(NUMEXPR[name], local_dict=env),
                "numpy": lambda: forms[name](x, v, t),
            },
            args.repeat,
            n,
        )
        xs, vs, ts = x[:loop_n].tolist(), v[:loop_n].tolist(), t[:loop_n].tolist()
        loop = best_of(lambda: [jit(a, b, c) for a, b, c in zip(xs, vs, ts)], 3)
        cells["python loop"] = loop / loop_n * 1e9
        rows.append((name, cells))
    small = mbfx.compile("SIN(x)", ("x",))
    calls = 200_000
    overhead = min(timeit.repeat(lambda: small(0.5), number=calls, repeat=5)) / calls * 1e9
    empty = min(timeit.repeat(lambda: None, number=calls, repeat=5)) / calls * 1e9
    cols = ["mbfx jit", "mbfx interp", "numexpr", "numpy", "python loop"]
    lines = [
        f"ns per point over {n} points, {args.threads} thread(s) each (fastest of {args.repeat} rounds); "
        "ratio = numexpr / mbfx jit",
        "",
        "| expression | " + " | ".join(cols) + " | numexpr / jit |",
        "|---|" + "---|" * (len(cols) + 1),
    ]
    ratios = []
    for name, cells in rows:
        r = cells["numexpr"] / cells["mbfx jit"]
        ratios.append(r)
        lines.append(f"| {name} | " + " | ".join(f"{cells[c]:.2f}" for c in cols) + f" | {r:.2f}× |")
    gm = math.exp(sum(map(math.log, ratios)) / len(ratios))
    lines += [
        "",
        f"geometric mean numexpr / mbfx jit: {gm:.2f}× (slowest row {min(ratios):.2f}×)",
        f"small call f(0.5): {overhead:.0f} ns (a Python lambda call: {empty:.0f} ns)",
    ]
    text = "\n".join(lines)
    print(text)
    if args.out:
        with open(args.out, "w") as f:
            f.write(text + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())

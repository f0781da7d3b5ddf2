"""SIN, COS and ATAN2 are mbfx's own (runtime/src/math/trig.rs): their error against the
true value, from mpmath at 200 bits, must stay under 1 ulp on the arrays' path and on
both scalar engines. The arguments cover every scale the fast paths take and the
multiples of pi/2 where the argument reduction cancels most."""

from __future__ import annotations

import mpmath
import numpy as np
import pytest

import mbfx

mpmath.mp.prec = 200


def ulp_error(got: float, exact: mpmath.mpf) -> float:
    """|got - exact| in units of the last place of the double nearest `exact`."""
    if exact == 0:
        return 0.0 if got == 0 else float("inf")
    _, e = mpmath.frexp(exact)  # exact = m * 2**e, 1/2 <= |m| < 1
    ulp = mpmath.ldexp(1, max(int(e), -1021) - 53)
    return float(abs(mpmath.mpf(got) - exact) / ulp)


def trig_arguments() -> np.ndarray:
    rng = np.random.default_rng(20261128)
    scales = (1e-8, 0.5, 1.0, 4.0, 10.0, 1e3, 1e6)
    xs = [rng.uniform(-s, s, 2000) for s in scales]
    # Nearest doubles to multiples of pi/2, and their neighbours.
    n = rng.integers(1, 600_000, 1500).astype(float)
    near = n * (np.pi / 2)
    xs += [near, np.nextafter(near, 0), np.nextafter(near, np.inf)]
    return np.concatenate(xs)


def atan2_arguments() -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(11)
    ys, xs = [], []
    for sy, sx in ((1.0, 1.0), (1.0, 1e-3), (1e-3, 1.0), (1e8, 1e-8), (1e-100, 1e100)):
        ys.append(rng.uniform(-sy, sy, 3000))
        xs.append(rng.uniform(-sx, sx, 3000))
    # Around the reduction's breakpoints |y/x| = 7/16, 11/16 and 1.
    r = np.repeat([0.4375, 0.6875, 1.0], 300) * (1 + rng.uniform(-1e-3, 1e-3, 900))
    x = rng.uniform(0.5, 2.0, 900) * rng.choice([-1.0, 1.0], 900)
    ys.append(r * x * rng.choice([-1.0, 1.0], 900))
    xs.append(x)
    return np.concatenate(ys), np.concatenate(xs)


@pytest.mark.parametrize(
    "name, exact", [("SIN", mpmath.sin), ("COS", mpmath.cos)], ids=["SIN", "COS"]
)
def test_sin_and_cos_are_under_one_ulp(name, exact):
    x = trig_arguments()
    f = mbfx.compile(f"{name}(x)", variables=("x",))
    got = f(x)
    worst = max(ulp_error(g, exact(mpmath.mpf(v))) for g, v in zip(got, x))
    assert worst < 1.0, f"{name}: {worst:.3f} ulp"
    for engine in ("jit", "interp"):
        g = mbfx.compile(f"{name}(x)", variables=("x",), engine=engine)
        assert all(g(float(v)) == w for v, w in zip(x[::7], got[::7])), engine


def test_atan2_is_under_one_ulp():
    y, x = atan2_arguments()
    f = mbfx.compile("ATAN2(y, x)", variables=("y", "x"))
    got = f(y, x)
    worst = max(
        ulp_error(g, mpmath.atan2(mpmath.mpf(a), mpmath.mpf(b)))
        for g, a, b in zip(got, y, x)
    )
    assert worst < 1.0, f"ATAN2: {worst:.3f} ulp"
    for engine in ("jit", "interp"):
        g = mbfx.compile("ATAN2(y, x)", variables=("y", "x"), engine=engine)
        assert all(g(float(a), float(b)) == w for a, b, w in zip(y[::7], x[::7], got[::7]))

"""An independent DOP853 on A01, to tell the method's convergence from mbfx's.

Not part of CI. Needs numpy, scipy (for the DOP853 tableau, as scipy ships Hairer's
coefficients in scipy.integrate._ivp.dop853_coefficients) and mpmath:

    python3 -m venv /tmp/dop-venv && /tmp/dop-venv/bin/pip install numpy scipy mpmath
    /tmp/dop-venv/bin/python benches/orders/dop853_reference.py

It integrates A01 (reference-problems.md §4.1: phi'' = -g cos(phi) for the angle from
+x, released at rest horizontal, g = 9.81, L = 1) with fixed steps h = 0.5/2^k by the
8th-order DOP853 formula (12 stages), in plain float64, and prints:

1. the error as `mbfx bench orders` scores it (max over the truth file's times 0.5, 1,
   2 and 10 s of |x - x_ref|, |y - y_ref|), and the slope between halvings: mbfx's
   dopri853-fixed must give the same errors (tests/bench.rs checks three of them);
2. the error at each truth time alone, with its slope;
3. the same formula on the damped pendulum phi'' = -g cos(phi) - 0.3 phi' (reference by
   mpmath's Taylor integrator at 30 digits), whose error at t = 10 s has no cancellation.

With --extended it runs the same formula in mpmath at 40 digits instead, with the
coefficients read from scipy's source at the 30 digits written there (the float64 ones
violate the order conditions by 1e-17, which floors the errors at about 4e-15), against
the exact solution at 40 digits (examples/scenes/truth/a01_pendulum.py), down to
h = 1/512: where DOP853's slope on A01 reaches 8 when rounding is out of the way.
"""
import re
import sys
from pathlib import Path

import numpy as np
import mpmath as mp
from scipy.integrate._ivp import dop853_coefficients as C

A = C.A[:12, :12]
B = C.B
G = 9.81
TRUTH = {  # examples/scenes/a01_pendulum.toml
    0.5: (0.39104879155054639, -0.9203699487851922),
    1.0: (-0.98629175113187532, -0.16501085312554117),
    2.0: (0.79356619534332175, -0.60848393044379151),
    10.0: (0.27508746257611686, -0.96141920509912506),
}


def rhs(damping):
    return lambda y: np.array([y[1], -G * np.cos(y[0]) - damping * y[1]])


def trajectory(f, h, end):
    y = np.zeros(2)
    out = [y.copy()]
    for _ in range(int(round(end / h))):
        k = np.zeros((12, 2))
        for i in range(12):
            k[i] = f(y + h * (A[i, :i] @ k[:i]))
        y = y + h * (B @ k)
        out.append(y.copy())
    return out


def errors(ys, h, truth):
    return {t: max(abs(np.cos(ys[int(round(t / h))][0]) - x),
                   abs(np.sin(ys[int(round(t / h))][0]) - y))
            for t, (x, y) in truth.items()}


def table(damping, truth, halvings=range(1, 6)):
    prev = None
    print(f"damping {damping}: h, max error (slope), then each time's error (slope)")
    for k in halvings:
        h = 0.5 / 2**k
        e = errors(trajectory(rhs(damping), h, 10.0), h, truth)
        worst = max(e.values())
        slope = lambda a, b: "" if a is None else f" ({np.log2(a / b):.2f})"
        line = f"  h = {h:<9g} {worst:.3e}{slope(prev and max(prev.values()), worst)}"
        for t in truth:
            line += f" | t={t:g}: {e[t]:.2e}{slope(prev and prev[t], e[t])}"
        print(line)
        prev = e


def damped_truth():
    mp.mp.dps = 30
    sol = mp.odefun(lambda t, y: [y[1], -mp.mpf("9.81") * mp.cos(y[0]) - mp.mpf("0.3") * y[1]],
                    0, [mp.mpf(0), mp.mpf(0)])
    return {t: (float(mp.cos(sol(t)[0])), float(mp.sin(sol(t)[0]))) for t in TRUTH}


def extended():
    """Errors and slopes at each truth time, in 40-digit arithmetic."""
    mp.mp.dps = 40
    sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "examples/scenes/truth"))
    from a01_pendulum import exact

    src = Path(C.__file__).read_text()
    a = {(int(i), int(j)): mp.mpf(v)
         for i, j, v in re.findall(r"^A\[(\d+), (\d+)\] = (\S+)$", src, re.M)}
    aa = [[a.get((i, j), mp.mpf(0)) for j in range(12)] for i in range(12)]
    b = [a.get((12, j), mp.mpf(0)) for j in range(12)]
    g = mp.mpf("9.81")
    ref = {t: exact(mp.mpf(t)) for t in TRUTH}
    print(f"40 digits; sum(b) - 1 = {mp.nstr(sum(b) - 1, 3)}; error (slope) at each time")
    prev = None
    for k in range(2, 10):
        h = mp.mpf(1) / 2**k
        y, at = [mp.mpf(0), mp.mpf(0)], {}
        for s in range(1, 10 * 2**k + 1):
            st = []
            for i in range(12):
                yi = [y[c] + h * mp.fsum(aa[i][j] * st[j][c] for j in range(i)) for c in range(2)]
                st.append([yi[1], -g * mp.cos(yi[0])])
            y = [y[c] + h * mp.fsum(b[j] * st[j][c] for j in range(12)) for c in range(2)]
            if s * h in ref:
                at[s * h] = y
        e = {t: max(abs(mp.cos(at[t][0]) - ref[t][0]), abs(mp.sin(at[t][0]) - ref[t][1]))
             for t in ref}
        line = f"  h = 1/{2**k:<4}"
        for t in ref:
            slope = f" ({float(mp.log(prev[t] / e[t], 2)):.2f})" if prev else ""
            line += f" | t={t:g}: {mp.nstr(e[t], 3)}{slope}"
        print(line, flush=True)
        prev = e


if __name__ == "__main__":
    if "--extended" in sys.argv[1:]:
        extended()
    else:
        table(0.0, TRUTH)
        table(0.3, damped_truth())

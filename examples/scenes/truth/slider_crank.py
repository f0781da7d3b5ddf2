#!/usr/bin/env python3
"""Truth for slider_crank_driven: the drive torque and the slider's position, exact.

The crank turns at the constant rate w = 2*pi rad/s, theta = w*t, so every position is a
closed form in theta (crank pin B = r(cos, sin), slider x_C = r cos + sqrt(l² - r² sin²),
rod angle phi = -asin(r sin/l)). With no friction and no free degree of freedom the
drive's power is the rate of change of the energy: tau*w = d(T + V)/dt. Since
T = (w²/2)*M(theta), M = sum m_i |dG_i/dtheta|² + I_i (dphi_i/dtheta)² (the generalized
inertia) and dtheta/dt = w:
    tau = (w²/2)*M'(theta) + V'(theta),     V = g*(m1*y_G1 + m2*y_G2).
It is evaluated with mpmath at 30 digits (mp.diff for the theta-derivatives), and checked
against d(T+V)/dt / w differentiated in time directly.

Usage: python3 slider_crank.py   # rewrites the [[at]] rows of ../slider_crank_driven.toml
"""
import pathlib
import mpmath as mp

mp.mp.dps = 30
R, L = mp.mpf("0.1"), mp.mpf("0.4")
M1, M2, M3 = mp.mpf(1), mp.mpf(2), mp.mpf("0.5")
I1, I2 = M1 * R**2 / 12, M2 * L**2 / 12
G = mp.mpf("9.81")
W = 2 * mp.pi


def xc(th):
    return R * mp.cos(th) + mp.sqrt(L**2 - R**2 * mp.sin(th) ** 2)


def positions(th):
    """(x, y) of the crank's CM, the rod's CM, the slider; the rod's angle."""
    bx, by = R * mp.cos(th), R * mp.sin(th)
    c = xc(th)
    return (bx / 2, by / 2), ((bx + c) / 2, by / 2), (c, mp.mpf(0)), -mp.asin(R * mp.sin(th) / L)


def inertia(th):
    """M(theta): 2T/w² at crank rate w."""
    d = [mp.diff(lambda t, i=i, j=j: positions(t)[i][j], th) for i in range(3) for j in range(2)]
    dphi = mp.diff(lambda t: positions(t)[3], th)
    return (M1 * (d[0] ** 2 + d[1] ** 2) + I1 + M2 * (d[2] ** 2 + d[3] ** 2) + I2 * dphi**2
            + M3 * (d[4] ** 2 + d[5] ** 2))


def potential(th):
    p = positions(th)
    return G * (M1 * p[0][1] + M2 * p[1][1])


def torque(t):
    th = W * t
    return W**2 / 2 * mp.diff(inertia, th) + mp.diff(potential, th)


def torque_by_time(t):
    """The same from d(T + V)/dt / w, differentiated in t."""
    return mp.diff(lambda s: W**2 / 2 * inertia(W * s) + potential(W * s), t) / W


def main():
    times = [mp.mpf(i) / 10 for i in range(1, 21)]
    path = pathlib.Path(__file__).resolve().parent.parent / "slider_crank_driven.toml"
    head = path.read_text().split("[[at]]")[0].rstrip() + "\n"
    body, worst = [], mp.mpf(0)
    for t in times:
        tau, x = torque(t), xc(W * t)
        worst = max(worst, abs(tau - torque_by_time(t)))
        print(f"t = {mp.nstr(t, 3)}: torque = {mp.nstr(tau, 25)}, slider_x = {mp.nstr(x, 25)}")
        body.append(f"\n[[at]]\ntime = {float(t)!r}\ntorque = {float(tau)!r}\nslider_x = {float(x)!r}\n")
    print(f"largest |torque - d(T+V)/dt/w| = {mp.nstr(worst, 3)}")
    assert worst < mp.mpf("1e-20")
    path.write_text(head + "".join(body))


if __name__ == "__main__":
    main()

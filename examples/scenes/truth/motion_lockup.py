#!/usr/bin/env python3
"""Truth for motion_lockup: a slider-crank driven at the slider, x = 0.35 + 0.15 t.

With the slider at x the crank angle is theta = acos((x² + r² - l²)/(2 r x)) (crank pin
above the axis, the branch the dataset starts on), so every position is a closed form in
t. The slider reaches the outer dead centre x = r + l = 0.5 at t_lock = (0.5 - 0.35)/0.15
= 1 exactly; there d theta/dt ~ 1/sqrt(1 - t) is unbounded, and after it no position
exists. The drive's force along x follows from the energy balance F*xdot = d(T + V)/dt
(no friction, no free degree of freedom). mpmath at 30 digits, mp.diff for the rates.

Usage: python3 motion_lockup.py   # rewrites the [[at]] rows of ../motion_lockup.toml
"""
import pathlib
import mpmath as mp

mp.mp.dps = 30
R, L = mp.mpf("0.1"), mp.mpf("0.4")
M1, M2, M3 = mp.mpf(1), mp.mpf(2), mp.mpf("0.5")
I1, I2 = M1 * R**2 / 12, M2 * L**2 / 12
G = mp.mpf("9.81")
X0, V = mp.mpf("0.35"), mp.mpf("0.15")
T_LOCK = (R + L - X0) / V


def theta(t):
    x = X0 + V * t
    return mp.acos((x**2 + R**2 - L**2) / (2 * R * x))


def pin(t):
    th = theta(t)
    return R * mp.cos(th), R * mp.sin(th)


def energy(t):
    def g(s):
        bx, by = pin(s)
        x = X0 + V * s
        return bx / 2, by / 2, (bx + x) / 2, by / 2, x, theta(s), mp.atan2(-by, x - bx)
    rates = [mp.diff(lambda s, i=i: g(s)[i], t) for i in range(7)]
    kin = (M1 * (rates[0] ** 2 + rates[1] ** 2) + I1 * rates[5] ** 2
           + M2 * (rates[2] ** 2 + rates[3] ** 2) + I2 * rates[6] ** 2 + M3 * rates[4] ** 2) / 2
    q = g(t)
    return kin + G * (M1 * q[1] + M2 * q[3])


def force(t):
    return mp.diff(energy, t) / V


def main():
    assert abs(T_LOCK - 1) < mp.mpf("1e-25")
    times = [mp.mpf(i) / 10 for i in range(1, 10)] + [mp.mpf("0.95"), mp.mpf("0.99")]
    path = pathlib.Path(__file__).resolve().parent.parent / "motion_lockup.toml"
    head = path.read_text().split("[[at]]")[0].rstrip() + "\n"
    body = []
    for t in times:
        bx, by = pin(t)
        f = force(t)
        print(f"t = {mp.nstr(t, 3)}: pin ({mp.nstr(bx, 20)}, {mp.nstr(by, 20)}), force {mp.nstr(f, 20)}")
        body.append(f"\n[[at]]\ntime = {float(t)!r}\nslider_x = {float(X0 + V * t)!r}\n"
                    f"pin_x = {float(bx)!r}\npin_y = {float(by)!r}\nforce = {float(f)!r}\n")
    path.write_text(head + "".join(body))


if __name__ == "__main__":
    main()

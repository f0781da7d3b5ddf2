#!/usr/bin/env python3
"""Truth for the contact scenes of examples/scenes/ (reference-problems.md §6.4-6.6).

Each scene is a 1 kg block on a translational joint: m*y'' = F(y, y') - m*g, with F the
IMPACT or BISTOP law of spec/expr-language.md §5.4-5.5 written out here (not mbfx's
runtime), including the max(0, .)/min(0, .) clamp and the cubic STEP damping ramp.

The right-hand side is continuous but not smooth where the block meets a stop (p**1.5),
where the STEP ramp ends (p = d) and where the clamp switches the force off or on. The
integration (scipy's DOP853) stops at each of these switches, located as events on its
dense output, and at each output time, and restarts there, so that no step straddles a
kink. It is run at rtol 1e-13 (the truth) and again at 1e-12 and 1e-11, and by Radau at
1e-12 (a different method), and the largest differences are printed: they bound the
truth's error (see each toml's `source`).

Usage: python3 contact_1dof.py [NAME…]  # rewrites the [[at]] rows of the scenes' .toml
       python3 contact_1dof.py --check  # also the convergence study (slower)
Needs numpy and scipy (a venv: python3 -m venv /tmp/v && /tmp/v/bin/pip install scipy).
"""
import sys
import pathlib
import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

HERE = pathlib.Path(__file__).resolve().parent.parent
MASS = 1.0
TRACE = False


def step(x, x0, h0, x1, h1):
    """Adams' cubic STEP (spec expr-language §5.1)."""
    if x <= x0:
        return h0
    if x >= x1:
        return h1
    a = (x - x0) / (x1 - x0)
    return h0 + (h1 - h0) * a * a * (3.0 - 2.0 * a)


class Law:
    """IMPACT (x2 None) or BISTOP: stops at x1 (force +) and x2 (force -)."""

    def __init__(self, x1, k, e, cmax, d, x2=None):
        self.x1, self.x2, self.k, self.e, self.cmax, self.d = x1, x2, k, e, cmax, d

    def lower(self, x, xd):
        """Unclamped lower-stop force k*(x1-x)^e - STEP(x, x1-d, cmax, x1, 0)*xd (x < x1)."""
        return self.k * (self.x1 - x) ** self.e - step(x, self.x1 - self.d, self.cmax, self.x1, 0.0) * xd

    def upper(self, x, xd):
        """Unclamped upper-stop force -k*(x-x2)^e - STEP(x, x2, 0, x2+d, cmax)*xd (x > x2)."""
        return -self.k * (x - self.x2) ** self.e - step(x, self.x2, 0.0, self.x2 + self.d, self.cmax) * xd

    def force(self, x, xd):
        if x < self.x1:
            return max(0.0, self.lower(x, xd))
        if self.x2 is not None and x > self.x2:
            return min(0.0, self.upper(x, xd))
        return 0.0

    def clamp_lo(self, y, v):
        """The lower stop's unclamped force, continued below 0 above the stop (where it is
        -k*(y-x1)^e): its sign change inside the stop is where the clamp switches."""
        q = self.x1 - y
        return (np.sign(q) * self.k * np.abs(q) ** self.e
                - step_v(y, self.x1 - self.d, self.cmax, self.x1, 0.0) * v)

    def clamp_hi(self, y, v):
        """Minus the upper stop's unclamped force (positive while it pushes), continued
        below 0 inside the gap."""
        q = y - self.x2
        return (np.sign(q) * self.k * np.abs(q) ** self.e
                + step_v(y, self.x2, 0.0, self.x2 + self.d, self.cmax) * v)

    def levels(self):
        """Positions where the law switches: the stops (w) and the ends of the ramps (r)."""
        lv = {"w1": self.x1, "r1": self.x1 - self.d}
        if self.x2 is not None:
            lv.update(w2=self.x2, r2=self.x2 + self.d)
        return lv

    def clamps(self, y, entering):
        """The clamp switch functions of the stop the block is inside (or `entering`)."""
        c = {}
        if y < self.x1 or entering == "w1":
            c["c1"] = self.clamp_lo
        if self.x2 is not None and (y > self.x2 or entering == "w2"):
            c["c2"] = self.clamp_hi
        return c


def step_v(x, x0, h0, x1, h1):
    """STEP on arrays (the same formula as `step`)."""
    a = np.clip((np.asarray(x, float) - x0) / (x1 - x0), 0.0, 1.0)
    return h0 + (h1 - h0) * a * a * (3.0 - 2.0 * a)


def first_crossing(fn, span, direction, n, fresh):
    """The first tau in (0, span] where fn(tau) changes sign in `direction` (+1 upward),
    by sampling n points and bisecting (brentq); fn(0) is taken on the side before the
    crossing when `fresh` (it was just crossed the other way, so it is ~0)."""
    tau = np.linspace(0.0, span, n + 1)
    f = fn(tau)
    before = f < 0 if direction > 0 else f > 0
    after = ~before
    if fresh:
        before[0], after[0] = True, False
    idx = np.nonzero(before[:-1] & after[1:])[0]
    if len(idx) == 0:
        return None
    i = idx[0]
    if f[i + 1] == 0.0:
        return tau[i + 1]
    a = tau[i]
    if fresh and i == 0:
        # fn(0) ~ 0: start the bracket at the first finer sample on the `before` side
        fine = np.linspace(0.0, tau[1], 1001)[1:]
        ff = fn(fine)
        ok = np.nonzero(ff < 0 if direction > 0 else ff > 0)[0]
        if len(ok) == 0 or ok[0] == len(fine) - 1:
            return None
        a = fine[ok[0]]
    return brentq(lambda x: float(fn(np.array([x]))[0]), a, tau[i + 1], xtol=1e-16, rtol=4 * np.finfo(float).eps)


def integrate(law, g, y0, v0, times, rtol, method="DOP853", scan=20000):
    """(y, v) at each of `times` (increasing, > 0), and the number of switches crossed.

    Two modes. Free (the force is 0: in flight, or inside a stop while the clamp holds it
    off): the exact parabola, its switches found on it (stops and ramp ends in closed
    form, the clamp by sampling `scan` points and bisecting), so that a short
    re-engagement cannot be stepped over. Contact: DOP853 (or `method`) at `rtol` with the
    switches as terminal events."""
    atol = rtol * 1e-3

    def rhs(t, s):
        return [s[1], law.force(s[0], s[1]) / MASS - g]

    t, s = 0.0, np.array([y0, v0], float)
    out, switches = [], 0
    last = None  # (key, direction) of the switch just crossed at t
    mode = None
    for target in times:
        while t < target:
            if last is None:
                mode = "contact" if law.force(s[0], s[1]) != 0.0 else "free"
            elif last[0] in ("w1", "w2"):
                mode = "contact" if last in (("w1", -1.0), ("w2", 1.0)) else "free"
            elif last[0] in ("c1", "c2"):
                mode = "contact" if last[1] > 0 else "free"
            entering = last[0] if last is not None and mode == "contact" and last[0][0] == "w" else None
            fns = {k: (lambda y, v, L=L: y - L) for k, L in law.levels().items()}
            fns.update(law.clamps(s[0], entering))
            dirs = {}
            for key, fn in fns.items():
                if last is not None and last[0] == key:
                    dirs[key] = -last[1]  # just crossed: next time the other way
                elif key[0] == "c" and entering is not None:
                    dirs[key] = -1.0      # the clamp just became active: it pushes
                else:
                    dirs[key] = 1.0 if fn(s[0], s[1]) < 0 else -1.0
            span = target - t
            if mode == "free":
                y0_, v0_ = s

                def path(tau, y0_=y0_, v0_=v0_):
                    return y0_ + v0_ * tau - 0.5 * g * tau * tau, v0_ - g * tau
                hits = []
                for key, fn in fns.items():
                    if key[0] == "c":
                        continue
                    L = law.levels()[key]
                    # y0 + v0 tau - g/2 tau^2 = L
                    roots = np.roots([-0.5 * g, v0_, y0_ - L]) if g != 0 else (
                        np.array([(L - y0_) / v0_]) if v0_ != 0 else np.array([]))
                    for r in np.real(roots[np.isreal(roots)]):
                        slope = v0_ - g * r
                        if 0 < r <= span and np.sign(slope) == dirs[key] and not (last and last[0] == key and r < 1e-12):
                            hits.append((r, key))
                inside_end = min([r for r, k in hits if k[0] == "w"], default=span)
                for key, fn in fns.items():
                    if key[0] != "c":
                        continue
                    r = first_crossing(lambda tau, fn=fn: fn(*path(tau)), inside_end, dirs[key],
                                       scan, last is not None and last[0] == key)
                    if r is not None:
                        hits.append((r, key))
                if hits:
                    r, key = min(hits)
                    t, s = t + r, np.array(path(r))
                    last = (key, dirs[key])
                    switches += 1
                    if TRACE:
                        print(f"    {t:.15f} {last} y={s[0]:.3e} v={s[1]:.6f} (free)")
                else:
                    t, s = target, np.array(path(span))
                    last = None
                continue
            keys = list(fns)
            evs = []
            for key in keys:
                def e(tt, ss, fn=fns[key]):
                    return fn(ss[0], ss[1])
                e.terminal = True
                e.direction = dirs[key]
                evs.append(e)
            sol = solve_ivp(rhs, (t, target), s, method=method, rtol=rtol, atol=atol, events=evs)
            assert sol.status in (0, 1), sol.message
            if sol.status == 1:
                hits = sorted((te[0], keys[i][0] != "w", i) for i, te in enumerate(sol.t_events) if len(te))
                te, _, i = hits[0]
                # a stop and its clamp switch together when the block leaves the stop
                for h in hits[1:]:
                    if keys[h[2]][0] == "w" and h[0] - te < 1e-10:
                        te, _, i = h
                s = np.array(sol.y_events[i][0])
                last = (keys[i], dirs[keys[i]])
                # the clamp's force reaches 0 with the penetration: within 1e-12 m of the
                # stop, moving out, this is the block leaving the stop
                lv = law.levels()
                if last == ("c1", -1.0) and lv["w1"] - s[0] < 1e-12 and s[1] > 0:
                    last = ("w1", 1.0)
                if last == ("c2", -1.0) and s[0] - lv["w2"] < 1e-12 and s[1] < 0:
                    last = ("w2", -1.0)
                t = te
                switches += 1
                if TRACE:
                    print(f"    {t:.15f} {last} y={s[0]:.3e} v={s[1]:.6f}")
            else:
                t, s = target, sol.y[:, -1]
                last = None
        out.append((s[0], s[1]))
    return out, switches


# name: (law, g, y0, v0, end, output_step, at times, probes {name: (expr, column)})
def grid(a, b, h):
    n = int(round((b - a) / h))
    return [round(a + i * h, 12) for i in range(n + 1)]


def vertical(law, g, y0, v0):
    return dict(law=law, g=g, y0=y0, v0=v0, axis="Y")


SCENES = {
    "impact_block_k1e5": dict(vertical(Law(0.05, 1e5, 1.5, 50.0, 0.1), 9.81, 0.15, 0.0),
                              times=grid(0.25, 2.0, 0.25), probes=["y"]),
    "impact_block_k1e7": dict(vertical(Law(0.05, 1e7, 1.5, 50.0, 0.1), 9.81, 0.15, 0.0),
                              times=grid(0.25, 2.0, 0.25), probes=["y"]),
    "impact_stiff_k1e9": dict(vertical(Law(0.05, 1e9, 1.5, 50.0, 0.1), 9.81, 0.15, 0.0),
                              times=grid(0.25, 2.0, 0.25), probes=["y"]),
    "impact_single": dict(vertical(Law(0.0, 1e5, 1.5, 50.0, 0.01), 0.0, 0.01, -1.0),
                          times=grid(0.05, 0.1, 0.01), probes=["y", "v"]),
    "bouncing_ball": dict(vertical(Law(0.0, 1e5, 1.5, 50.0, 0.01), 9.81, 1.0, 0.0),
                          times=grid(0.25, 3.0, 0.25), probes=["y", "v"]),
    "bistop_slider": dict(law=Law(-0.1, 1e5, 1.5, 50.0, 0.01, x2=0.1), g=0.0, y0=0.0, v0=1.0,
                          axis="X", times=grid(0.1, 2.0, 0.1), probes=["x", "v"]),
}


def rows(name, sc, rtol=1e-13, method="DOP853"):
    vals, n = integrate(sc["law"], sc["g"], sc["y0"], sc["v0"], sc["times"], rtol, method)
    return vals, n


def write_rows(name, sc, vals):
    """Replace everything from the first [[at]] in NAME.toml by the computed rows."""
    path = HERE / f"{name}.toml"
    if not path.exists():
        print(f"  ({path.name} missing: rows not written)")
        return
    text = path.read_text()
    head = text.split("[[at]]")[0].rstrip() + "\n"
    body = []
    for t, (y, v) in zip(sc["times"], vals):
        body.append(f"\n[[at]]\ntime = {t!r}\n")
        for p in sc["probes"]:
            body.append(f"{p} = {repr(float(v if p == 'v' else y))}\n")
    path.write_text(head + "".join(body))


def main():
    check = "--check" in sys.argv
    only = [a for a in sys.argv[1:] if not a.startswith("--")]
    for name, sc in SCENES.items():
        if only and name not in only:
            continue
        vals, n = rows(name, sc)
        print(f"{name}: {n} switches crossed")
        for t, (y, v) in zip(sc["times"], vals):
            print(f"  t = {t:<6} y = {y!r:<24} v = {v!r}")
        write_rows(name, sc, vals)
        if check:
            ys = np.array(vals)
            for rtol, method in [(3e-14, "DOP853"), (1e-12, "DOP853"), (1e-12, "Radau")]:
                try:
                    other, _ = rows(name, sc, rtol, method)
                except ValueError as err:
                    print(f"  vs {method} rtol {rtol:g}: failed ({err})")
                    continue
                d = np.abs(np.array(other) - ys).max(axis=0)
                print(f"  vs {method} rtol {rtol:g}: max |dy| {d[0]:.2e}, max |dv| {d[1]:.2e}")


if __name__ == "__main__":
    main()

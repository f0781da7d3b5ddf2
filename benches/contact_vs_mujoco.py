#!/usr/bin/env python3
"""A ball dropped to rest on a floor, in mbfx and in MuJoCo, in one run (issue 40, Cost).

Not part of CI: a bench. It needs the release CLI (`cargo build --release`) and a Python
with `benches/requirements-mujoco.txt` (see benches/README.md).

The scene: a sphere of mass M and radius R, its lowest point H above a floor, falls under
gravity G onto it. The contact is a linear spring–damper on the penetration x (K, C), a
force that pushes and never pulls:

    F = max(0, K x + C dx/dt)

- mbfx: a CONTACT between an ELLIPSOID (a ball) and a BOX, IMPACT with EXPONENT = 1,
  STIFFNESS = K, DAMPING = C and a DMAX small enough that its damping ramp (STEP over
  0..DMAX) changes the impact by less than the errors compared here (C·DMAX/(2·M·v0)).
- MuJoCo: a frictionless contact (condim 1) with the direct ("negative") solref
  (−K/M, −C/M) and a constant impedance d (solimp = d, d, …). For one contact of a free
  body its acceleration along the normal is a1 = (1 − d)·a0 + d·aref with
  aref = −(b·v + k·d·r), b = −solref[1]/d and k = −solref[0]/d² (MuJoCo's docs and
  engine_core_constraint.c), so in contact

      M x'' = (1 − d)·M·G − K x − C x'       (force K x + C x' + d·M·G, clamped at 0)

  the same spring–damper, with gravity scaled by (1 − d) while in contact. d at MuJoCo's
  smallest impedance (mjMINIMP = 1e-4) makes the two laws agree to 1e-4; the rest depth
  is then (1 − d)·M·G/K, and each side is scored against the closed form of its own law.

Scores, each against closed forms computed here (never against either simulator):
- the first impact's deepest penetration and the first rebound's apex (the transient);
- the depth at rest at T (M·G/K, and (1 − d)·M·G/K for MuJoCo).
At rest every method sits at its equilibrium, which both solve exactly, so the rest depth
alone cannot tell the methods apart: the "equal error" compared is the transient error,
the larger of the peak's and the apex's relative errors.

CPU, process time of the integration alone on both sides, the least of --repeats runs:
mbfx's CLI process (getrusage of the child) with two output rows, less the same process
run to T/10⁶ (reading, building, compiling); MuJoCo's `mj_step(m, d, nstep=N)` under
time.process_time (the loop in C, no Python per step). The trajectory scored comes from
a second run of each (mbfx: dense rows from its continuous extension, --interpolate,
which leaves the steps to error control; MuJoCo: every step), so recording costs nothing
in the CPU shown.
"""
import argparse
import math
import os
import re
import resource
import subprocess
import sys
import tempfile
import time

import numpy as np

import mujoco

# The scene (SI units).
M = 1.0  # ball mass, kg
R = 0.1  # ball radius, m
H = 0.1  # drop: the ball's lowest point above the floor at t = 0, m
G = 9.80665  # gravity, m/s²
K = 1e5  # contact stiffness, N/m
ZETA = 0.2  # damping ratio of the contact's spring–damper
C = 2.0 * ZETA * math.sqrt(K * M)  # contact damping, N·s/m
DMAX = 1e-9  # mbfx IMPACT: penetration over which the damping ramps in, m
T = 1.0  # simulated time, s: the ball is at rest well before (its bounces end near 0.5 s)
D_IMP = mujoco.mjMINIMP  # MuJoCo's constant impedance

LONG_RUN = 1.0  # a point whose run takes longer (CPU s) is not repeated
ROW_STEP = 5e-5  # mbfx: output step of the scored (dense) rows, s

ADM = """Ball dropped {h} m onto a box: IMPACT, a linear spring-damper (bench, issue 40)
UNITS/FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND
ACCGRAV/JGRAV = -{g:.17g}
PART/1, GROUND
MARKER/10, PART = 1, QP = -1, -0.2, -1
GRAPHICS/11, BOX, CORNER = 10, X = 2, Y = 0.2, Z = 2
PART/2, MASS = {m:.10g}, CM = 20, IP = {i:.10g}, {i:.10g}, {i:.10g}
, QG = 0, {y0:.10g}, 0
MARKER/20, PART = 2
GRAPHICS/21, ELLIPSOID, CM = 20, XSCALE = {dia:.10g}, YSCALE = {dia:.10g}
, ZSCALE = {dia:.10g}
CONTACT/1, IGEOM = 21, JGEOM = 11, IMPACT, STIFFNESS = {k:.17g}
, DAMPING = {c:.17g}, DMAX = {dmax:.17g}, EXPONENT = 1
END
"""

XML = """<mujoco model="ball drop">
  <option timestep="{dt!r}" integrator="{integrator}" gravity="0 0 -{g!r}"/>
  <default>
    <geom condim="1" solref="{sk!r} {sc!r}" solimp="{d!r} {d!r} 0.001 0.5 2"/>
  </default>
  <worldbody>
    <geom name="floor" type="plane" size="1 1 0.1"/>
    <body name="ball" pos="0 0 {z0!r}">
      <freejoint/>
      <geom type="sphere" size="{r!r}" mass="{m!r}"/>
    </body>
  </worldbody>
</mujoco>
"""


# ---------------------------------------------------------------------------------------
# Closed forms


def root(f, a, b):
    """A sign change of f in [a, b], bisected to the last bit."""
    fa = f(a)
    if fa == 0.0:
        return a
    if (fa > 0) == (f(b) > 0):
        raise ValueError("no sign change in [%g, %g]" % (a, b))
    for _ in range(200):
        mid = 0.5 * (a + b)
        if mid in (a, b):
            break
        fm = f(mid)
        if (fm > 0) == (fa > 0):
            a, fa = mid, fm
        else:
            b = mid
    return 0.5 * (a + b)


def closed_form(g_contact, bias):
    """The first impact's deepest penetration, the first rebound's apex (the lowest point's
    height over the floor) and the rest depth of M x'' = M g_contact − K x − C x', entered
    at x = 0 with the free fall's speed, left where K x + C x' + bias reaches 0."""
    if not 0.0 <= ZETA < 1.0:
        raise ValueError("the closed form is the underdamped one: 0 <= ZETA < 1")
    v0 = math.sqrt(2.0 * G * H)
    w = math.sqrt(K / M)
    s = C / (2.0 * M)
    wd = math.sqrt(w * w - s * s)
    xe = g_contact / (w * w)  # the equilibrium the damped oscillation decays to
    a = -xe
    b = (v0 + s * a) / wd

    def x(t):
        return xe + math.exp(-s * t) * (a * math.cos(wd * t) + b * math.sin(wd * t))

    def xd(t):
        c, n = math.cos(wd * t), math.sin(wd * t)
        return math.exp(-s * t) * ((wd * b - s * a) * c - (s * b + wd * a) * n)

    half = math.pi / wd
    t_peak = root(xd, 0.0, half)
    t_sep = root(lambda t: K * x(t) + C * xd(t) + bias, t_peak, t_peak + half)
    apex = xd(t_sep) ** 2 / (2.0 * G) - x(t_sep)
    return {"peak": x(t_peak), "apex": apex, "rest": M * g_contact / K}


TRUTH_MBFX = closed_form(G, 0.0)
TRUTH_MUJOCO = closed_form((1.0 - D_IMP) * G, D_IMP * M * G)


# ---------------------------------------------------------------------------------------
# Scores from a sampled trajectory


def vertex(y, i):
    """The extremum of the parabola through samples i−1, i, i+1 (equally spaced)."""
    if i <= 0 or i + 1 >= len(y):
        return y[i]
    den = y[i + 1] - 2.0 * y[i] + y[i - 1]
    if den == 0.0:
        return y[i]
    return y[i] - (y[i + 1] - y[i - 1]) ** 2 / (8.0 * den)


def scores(height, truth):
    """Peak depth, apex and rest depth from the lowest point's height over the floor at
    equal time intervals, each with its relative error against `truth`."""
    inside = np.flatnonzero(height < 0.0)
    if len(inside) == 0:
        return None
    first = inside[0]
    out = np.flatnonzero(height[first:] >= 0.0)
    if len(out) == 0:
        return None
    leave = first + out[0]
    peak = -vertex(height, first + int(np.argmin(height[first:leave])))
    back = np.flatnonzero(height[leave:] < 0.0)
    again = leave + back[0] if len(back) else len(height)
    apex = vertex(height, leave + int(np.argmax(height[leave:again])))
    rest = -height[-1]
    got = {"peak": peak, "apex": apex, "rest": rest}
    err = {key: abs(got[key] / truth[key] - 1.0) for key in got}
    return got, err


# ---------------------------------------------------------------------------------------
# mbfx


STEPS_RE = re.compile(r"^\w+: (\d+) steps", re.M)

# mbfx's methods compared: the name shown and the CLI's options. gstiff twice: Adams'
# default index-3 form keeps only positions under error control, SI2 velocities too.
MBFX_METHODS = {
    "gstiff": ["--integrator", "gstiff"],
    "gstiff si2": ["--integrator", "gstiff", "--formulation", "si2"],
    "hht": ["--integrator", "hht"],
    "dopri853": ["--integrator", "dopri853"],
}


def mbfx_run(binary, adm, method, error, end, rows):
    """One run of the CLI: the child's CPU (user + system, from getrusage), the steps
    its summary reports and its CSV (time, the ball centre's height Y).

    The summary's own "s CPU" is not used: it is a wall clock, which other processes on
    a loaded machine inflate, where MuJoCo's figure below is process time. Dense rows
    (--interpolate) leave the steps to error control. HMAX is T/100, what mbfx takes
    without --interpolate for T/100 rows: with no HMAX a free-flight step of dopri853
    jumped clean through the 0.2 m floor (no sign change of the contact's switch at
    either end of the step, so no event)."""
    args = [binary, "run", adm, "--end", repr(end), "--output-step", repr(rows),
            "--error", repr(error), "--interpolate", "--hmax", repr(T / 100), "--hmin", "1e-14",
            "--probe", "Y=DY(20)", "--color", "never", "--csv", "-"] + MBFX_METHODS[method]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    proc = subprocess.run(args, capture_output=True, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    if proc.returncode != 0:
        raise RuntimeError("mbfx failed (%d): %s" % (proc.returncode, proc.stderr.strip()[-400:]))
    m = STEPS_RE.search(proc.stderr)
    if not m:
        raise RuntimeError("no summary line in mbfx's stderr:\n" + proc.stderr)
    return cpu, int(m.group(1)), proc.stdout


def mbfx_point(binary, adm, method, error, repeats):
    """CPU to simulate T: the least over `repeats` of the process's CPU with two rows,
    less the least of as many runs to T/10⁶ (reading, building, compiling: about 2 ms),
    so that both sides count the integration alone. Then the scored run, rows every
    ROW_STEP."""
    full, start = math.inf, math.inf
    for _ in range(repeats):
        c, steps, _ = mbfx_run(binary, adm, method, error, T, T)
        full = min(full, c)
        start = min(start, mbfx_run(binary, adm, method, error, T * 1e-6, T * 1e-6)[0])
    _, scored_steps, csv = mbfx_run(binary, adm, method, error, T, ROW_STEP)
    lines = csv.strip().splitlines()
    col = lines[0].split(",").index("Y")
    t = np.array([float(l.split(",")[0]) for l in lines[1:]])
    y = np.array([float(l.split(",")[col]) for l in lines[1:]])
    # Rows at k·ROW_STEP and at T (which may sit closer than ROW_STEP to the last row).
    keep = np.concatenate([np.abs(np.diff(t) - ROW_STEP) < 1e-9 * ROW_STEP, [True]])
    s = scores(y[keep] - R, TRUTH_MBFX)
    return {"method": "mbfx " + method, "setting": "ERROR %g" % error, "steps": steps,
            "scored_steps": scored_steps, "cpu": max(full - start, 0.0), "scores": s}


# ---------------------------------------------------------------------------------------
# MuJoCo


def mujoco_model(integrator, dt):
    xml = XML.format(dt=dt, integrator=integrator, g=G, sk=-K / M, sc=-C / M, d=D_IMP,
                     z0=R + H, r=R, m=M)
    return mujoco.MjModel.from_xml_string(xml)


def mujoco_point(integrator, dt, repeats):
    model = mujoco_model(integrator, dt)
    data = mujoco.MjData(model)
    n = int(round(T / dt))
    cpu = math.inf
    for _ in range(repeats):
        mujoco.mj_resetData(model, data)
        t0 = time.process_time()
        mujoco.mj_step(model, data, nstep=n)
        cpu = min(cpu, time.process_time() - t0)
        if cpu > LONG_RUN:
            break
    mujoco.mj_resetData(model, data)
    z = np.empty(n + 1)
    z[0] = data.qpos[2]
    for i in range(1, n + 1):
        mujoco.mj_step(model, data)
        z[i] = data.qpos[2]
    s = scores(z - R, TRUTH_MUJOCO)
    return {"method": "MuJoCo " + integrator, "setting": "dt %g" % dt, "steps": n,
            "cpu": cpu, "scores": s}


def check_matching():
    """MuJoCo's rest depth against (1 − d)·M·G/K, which the matched law predicts."""
    model = mujoco_model("implicitfast", 1e-4)
    data = mujoco.MjData(model)
    mujoco.mj_step(model, data, nstep=int(round(T / 1e-4)))
    depth = R - data.qpos[2]
    want = TRUTH_MUJOCO["rest"]
    return depth, want, depth / want - 1.0


# ---------------------------------------------------------------------------------------
# Equal error


def front(points):
    """The points no other beats on both CPU and transient error, by CPU."""
    pts = sorted((p for p in points if p["scores"]), key=lambda p: p["cpu"])
    out, best = [], math.inf
    for p in pts:
        e = transient(p)
        if e < best:
            out.append(p)
            best = e
    return out


def transient(p):
    err = p["scores"][1]
    return max(err["peak"], err["apex"])


def cpu_at(points, target):
    """CPU at transient error `target`, interpolated log–log along the family's front, and
    whether it is only a bound: where even the family's cheapest point is more accurate
    than `target`, its CPU bounds the cost from above. None where no point reached it."""
    f = front(points)
    if not f:
        return None
    if target >= transient(f[0]):
        return f[0]["cpu"], True
    for a, b in zip(f, f[1:]):
        ea, eb = transient(a), transient(b)
        if eb <= target <= ea:
            u = (math.log(target) - math.log(ea)) / (math.log(eb) - math.log(ea))
            la, lb = math.log(a["cpu"]), math.log(b["cpu"])
            return math.exp(la + u * (lb - la)), False
    return None


def ratio(ours, theirs):
    """mbfx's least CPU over MuJoCo's at one error, '<' or '>' where one side is a bound."""
    ours = [c for c in ours if c]
    theirs = [c for c in theirs if c]
    if not ours or not theirs:
        return "-"
    a, b = min(ours), min(theirs)
    if a[1] and b[1]:
        return "-"
    return ("<" if a[1] else ">" if b[1] else "") + "%.3g" % (a[0] / b[0])


# ---------------------------------------------------------------------------------------


def cpu_model():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return "%s (%d logical CPUs)" % (line.split(":", 1)[1].strip(), os.cpu_count())
    except OSError:
        pass
    return "unknown CPU"


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--mbfx", default=os.path.join(here, "..", "target", "release", "mbfx"),
                    help="the release CLI (default: target/release/mbfx of this repository)")
    ap.add_argument("--repeats", type=int, default=5, help="timed runs per point, least CPU kept")
    ap.add_argument("--quick", action="store_true", help="fewer settings (a smoke test)")
    args = ap.parse_args()
    if not os.access(args.mbfx, os.X_OK):
        sys.exit("no mbfx CLI at %s: run `cargo build --release` first, or give --mbfx" % args.mbfx)

    errors = [1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10]
    steps = [2e-3, 1e-3, 5e-4, 2e-4, 1e-4, 5e-5, 2e-5, 1e-5, 5e-6]
    if args.quick:
        errors, steps = errors[::2], steps[::3]
    families = {}

    load = os.getloadavg()[0]
    when = time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())
    print("%s, %s, load average %.2f at the start" % (when, cpu_model(), load))
    print("ball: m = %g kg, r = %g m, dropped %g m, g = %g; contact k = %g N/m, c = %.6g N·s/m"
          " (damping ratio %g), %g s simulated" % (M, R, H, G, K, C, ZETA, T))
    print("mbfx:   IMPACT, EXPONENT 1, DMAX %g; truth: peak %.9g m, apex %.9g m, rest %.9g m"
          % (DMAX, TRUTH_MBFX["peak"], TRUTH_MBFX["apex"], TRUTH_MBFX["rest"]))
    print("MuJoCo %s: solref (%g, %.6g), solimp d = %g constant, condim 1; truth: peak %.9g m,"
          " apex %.9g m, rest (1 - d) m g / k = %.9g m"
          % (mujoco.__version__, -K / M, -C / M, D_IMP, TRUTH_MUJOCO["peak"], TRUTH_MUJOCO["apex"],
             TRUTH_MUJOCO["rest"]))
    depth, want, rel = check_matching()
    print("matching check: MuJoCo at rest %.9g m, predicted %.9g m (relative %.1e)"
          % (depth, want, rel))
    if abs(rel) > 1e-6:
        sys.exit("MuJoCo's rest depth is not the matched law's: the matching is off")
    print()

    with tempfile.TemporaryDirectory() as tmp:
        adm = os.path.join(tmp, "ball_drop.adm")
        with open(adm, "w") as f:
            f.write(ADM.format(h=H, g=G, m=M, i=0.4 * M * R * R, y0=R + H, dia=2 * R, k=K, c=C,
                               dmax=DMAX))
        for method in MBFX_METHODS:
            families["mbfx " + method] = [
                mbfx_point(args.mbfx, adm, method, e, args.repeats) for e in errors]
    for integrator in ["Euler", "implicitfast", "RK4"]:
        families["MuJoCo " + integrator] = [
            mujoco_point(integrator, dt, args.repeats) for dt in steps]

    head = "%-20s %-12s %7s %14s %9s %14s %9s %9s %9s %10s %12s %8s" % (
        "method", "setting", "steps", "rest depth m", "rel err", "peak depth m", "rel err",
        "apex m", "rel err", "CPU s", "CPU / sim s", "µs/step")
    print(head)
    print("-" * len(head))
    for name, points in families.items():
        for p in points:
            if not p["scores"]:
                print("%-20s %-12s %7d   (no bounce seen)" % (name, p["setting"], p["steps"]))
                continue
            got, err = p["scores"]
            print("%-20s %-12s %7d %14.9g %9.2e %14.9g %9.2e %9.6f %9.2e %10.3e %12.3e %8.2f" % (
                name, p["setting"], p["steps"], got["rest"], err["rest"], got["peak"], err["peak"],
                got["apex"], err["apex"], p["cpu"], p["cpu"] / T, 1e6 * p["cpu"] / p["steps"]))
        print()

    drift = max(abs(p["scored_steps"] / p["steps"] - 1.0) for n, f in families.items()
                if n.startswith("mbfx") for p in f)
    print("mbfx's scored runs (dense rows) took within %.1f %% of the timed runs' steps"
          % (100 * drift))
    print("load average %.2f at the end" % os.getloadavg()[0])
    print()
    print("At equal rest-depth error: the cheapest run of each side whose rest depth is that"
          " close (every run's is, so the rest depth alone ranks the cheapest settings)")
    for bound in [1e-5, 1e-8]:
        best = {}
        for side in ["mbfx", "MuJoCo"]:
            pts = [p for n, f in families.items() if n.startswith(side) for p in f
                   if p["scores"] and p["scores"][1]["rest"] <= bound]
            best[side] = min(pts, key=lambda p: p["cpu"]) if pts else None
        if best["mbfx"] and best["MuJoCo"]:
            a, b = best["mbfx"], best["MuJoCo"]
            print("  <= %.0e: %s %s %.3e s (transient %.1e), %s %s %.3e s"
                  " (transient %.1e): ratio %.3g" % (
                      bound, a["method"], a["setting"], a["cpu"], transient(a), b["method"],
                      b["setting"], b["cpu"], transient(b), a["cpu"] / b["cpu"]))
    print()
    targets = [1e-1, 3e-2, 1e-2, 3e-3, 1e-3, 3e-4, 1e-4, 3e-5, 1e-5, 3e-6, 1e-6]
    names = list(families)
    print("CPU (s) at equal transient error (max of the peak's and the apex's relative errors),"
          " log-log along each method's cheapest points;\n'<': even its cheapest point is more"
          " accurate (an upper bound); '-': not reached")
    print("%-9s" % "error" + "".join("%20s" % n for n in names) + "%14s" % "mbfx/MuJoCo")
    for e in targets:
        cpus = {n: cpu_at(families[n], e) for n in names}
        row = "%-9.0e" % e + "".join(
            "%20s" % (("<" if c[1] else "") + "%.3e" % c[0] if c else "-") for c in cpus.values())
        print(row + "%14s" % ratio([c for n, c in cpus.items() if n.startswith("mbfx")],
                                   [c for n, c in cpus.items() if n.startswith("MuJoCo")]))

if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""MuJoCo peer: the mbfx reference scenes built in MuJoCo, swept over its integrators and
time steps, scored against examples/scenes/<scene>.toml, written to OUT/<scene>.csv.

MuJoCo has fixed-step integrators only (Euler = semi-implicit Euler, implicitfast,
implicit, RK4; 'discrete' where the build has it). Open chains are built in joint
(minimal) coordinates, so A01 and the chain have no constraints at all. A closed loop
(the slider-crank) needs an equality constraint, which MuJoCo always treats as *soft*
(solref/solimp); the prescribed crank motion is a joint equality to a 'clock' joint.
"""
import math
import sys
import time

import numpy as np
import mujoco
import mujoco.rollout

from common import Run, main, refine

STATE = mujoco.mjtState.mjSTATE_FULLPHYSICS
INTEGRATORS = {"euler": "Euler", "implicitfast": "implicitfast", "implicit": "implicit",
               "rk4": "RK4"}
if hasattr(mujoco.mjtIntegrator, "mjINT_DISCRETE"):
    INTEGRATORS["discrete"] = "discrete"


def steps_list(quick, times):
    """time steps 0.1/n that land on every probe time, coarse to fine."""
    ns = [1, 2, 4, 5, 8, 10, 20, 25, 40, 50, 100, 200, 250, 400, 500, 1000, 2000, 2500, 4000,
          5000, 10000, 20000, 25000, 40000, 50000, 100000, 200000, 250000, 500000, 1000000]
    out = []
    for n in ns:
        h = 0.1 / n
        try:
            segment_steps(times, h)
        except ValueError:
            continue
        out.append((h, "%g" % h))
    return out[::3] if quick else out


def segment_steps(times, h):
    out, prev = [], 0.0
    for t in times:
        n = (t - prev) / h
        if abs(n - round(n)) > 1e-6 * max(1.0, n):
            raise ValueError("step %g does not divide the probe times" % h)
        out.append(int(round(n)))
        prev = t
    return out


def option_xml(integrator, h, extra=""):
    return ('<option timestep="%.17g" integrator="%s" gravity="0 -9.81 0" %s>'
            '<flag contact="disable"/></option>' % (h, integrator, extra))


# ---------------------------------------------------------------- models

def a01_xml(opt):
    # point mass: MuJoCo needs a positive inertia, so the body gets 1e-12 kg m^2 about its
    # CM (relative change of the pendulum's inertia about the pivot: 1e-12).
    return """<mujoco model="a01">%s<worldbody>
  <body name="link"><joint name="q" type="hinge" axis="0 0 1"/>
    <inertial pos="1 0 0" mass="1" diaginertia="1e-12 1e-12 1e-12"/>
    <site name="p" pos="1 0 0"/></body></worldbody></mujoco>""" % opt


def chain_xml(opt, n=100, l=0.1, m=0.1):
    izz = m * l * l / 12.0
    body = ""
    for k in range(n, 0, -1):
        pos = "0 0 0" if k == 1 else "%.17g 0 0" % l
        site = ""
        if k == n:
            site += '<site name="tip" pos="%.17g 0 0"/>' % l
        if k == n // 2:
            site += '<site name="mid" pos="%.17g 0 0"/>' % l
        body = ('<body name="r%d" pos="%s"><joint type="hinge" axis="0 0 1"/>'
                '<inertial pos="%.17g 0 0" mass="%.17g" diaginertia="%.17g %.17g %.17g"/>%s%s</body>'
                % (k, pos, l / 2, m, izz / 2, izz / 2, izz, site, body))
    return '<mujoco model="chain">%s<worldbody>%s</worldbody></mujoco>' % (opt, body)


def impact_xml(opt):
    return """<mujoco model="impact">%s<worldbody>
  <body name="block"><joint name="y" type="slide" axis="0 1 0"/>
    <inertial pos="0 0 0" mass="1" diaginertia="1 1 1"/></body></worldbody></mujoco>""" % opt


def slider_crank_xml(opt, eq_attr):
    ic = 1.0 * 0.1 ** 2 / 12
    ir = 2.0 * 0.4 ** 2 / 12
    return """<mujoco model="slider_crank">%s<worldbody>
  <body name="crank"><joint name="crank" type="hinge" axis="0 0 1"/>
    <inertial pos="0.05 0 0" mass="1" diaginertia="%.17g %.17g %.17g"/>
    <body name="rod" pos="0.1 0 0"><joint name="rod" type="hinge" axis="0 0 1"/>
      <inertial pos="0.2 0 0" mass="2" diaginertia="%.17g %.17g %.17g"/>
      <site name="rodend" pos="0.4 0 0"/></body></body>
  <body name="slider"><joint name="slider" type="slide" axis="1 0 0"/>
    <inertial pos="0 0 0" mass="0.5" diaginertia="1 1 1"/><site name="pin" pos="0 0 0"/></body>
  <body name="clock"><joint name="clock" type="slide" axis="0 0 1"/>
    <inertial pos="0 0 0" mass="1e14" diaginertia="1 1 1"/></body>
</worldbody><equality>
  <connect name="loop" site1="rodend" site2="pin" %s/>
  <joint name="drive" joint1="crank" joint2="clock" polycoef="0 %.17g 0 0 0" %s/>
</equality></mujoco>""" % (opt, ic / 2, ic / 2, ic, ir / 2, ir / 2, ir, eq_attr, 2 * math.pi, eq_attr)


# ---------------------------------------------------------------- solving

def rollout_solve(model, times, h, probe_fn, chunk=20000):
    """Integrate with mujoco.rollout (the stepping loop runs in C, no Python per step) from
    probe time to probe time; probe_fn(m, d) reads the probes after mj_forward (not timed)."""
    m, d = model[:2]
    nsegs = segment_steps(times, h)
    nstate = mujoco.mj_stateSize(m, STATE)
    state = np.empty(nstate)
    mujoco.mj_getState(m, d, state, STATE)
    values, cpu, total = {}, 0.0, 0
    for t, nseg in zip(times, nsegs):
        left = nseg
        while left > 0:
            k = min(left, chunk)
            t0 = time.process_time()
            out, _ = mujoco.rollout.rollout(m, d, state[None, :], nstep=k)
            cpu += time.process_time() - t0
            state = np.array(out[0, -1])
            left -= k
            total += k
        mujoco.mj_setState(m, d, state, STATE)
        vals = _probe(m, d, probe_fn)
        if vals is None:
            return _non_finite(cpu, total, t)
        values[t] = vals
    return Run(values, cpu, steps=total)


def _probe(m, d, probe_fn):
    """The probes at d's state, or None when one is not finite."""
    mujoco.mj_forward(m, d)
    vals = probe_fn(m, d)
    return vals if all(math.isfinite(v) for v in vals.values()) else None


def _non_finite(cpu, total, t):
    return Run(None, cpu, steps=total, status="failed: non-finite state at t = %g" % t)


def loop_solve(model, times, h, probe_fn):
    """Python loop of mj_step, for models with a Python callback (rollout cannot call it).
    model = (m, d, passive): the callback is installed only while this model runs (installed
    before compiling, MuJoCo calls it on the compiler's own model and fails)."""
    m, d, passive = model
    mujoco.set_mjcb_passive(passive)
    try:
        return _loop(m, d, times, h, probe_fn)
    finally:
        mujoco.set_mjcb_passive(None)


def _loop(m, d, times, h, probe_fn):
    nsegs = segment_steps(times, h)
    values, cpu, total = {}, 0.0, 0
    step = mujoco.mj_step
    mujoco.mj_forward(m, d)
    for t, nseg in zip(times, nsegs):
        t0 = time.process_time()
        for _ in range(nseg):
            step(m, d)
        cpu += time.process_time() - t0
        total += nseg
        vals = _probe(m, d, probe_fn)
        if vals is None:
            return _non_finite(cpu, total, t)
        values[t] = vals
    return Run(values, cpu, steps=total)


def site_xy(m, d, name):
    i = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_SITE, name)
    return d.site_xpos[i][0], d.site_xpos[i][1]


def check_probes(truth, known):
    missing = [n for n in truth.names if n not in known]
    if missing:
        raise SystemExit("%s: probes %s of the truth file are not built here" % (truth.scene, missing))


def sweep_fixed(sw, xml_fn, init_fn, probe_fn, solver, methods, formulation, floor=1e-11,
                callback=None):
    times = sw.truth.times
    for key in methods:
        integ = INTEGRATORS[key]

        def make(hs, integ=integ, key=key):
            h, label = hs

            def build():
                m = mujoco.MjModel.from_xml_string(xml_fn(integ, h))
                d = mujoco.MjData(m)
                init_fn(m, d)
                return (m, d, callback) if callback else (m, d)
            return sw.point("mujoco-" + key, formulation, "fixed-step", label, build,
                            lambda model, truth: solver(model, times, h, probe_fn))
        refine(sw, steps_list(sw.args.quick, times), make, floor)


# ---------------------------------------------------------------- scenes

def scene_a01(sw):
    check_probes(sw.truth, ["x", "y"])

    def probe(m, d):
        x, y = site_xy(m, d, "p")
        return {"x": x, "y": y}
    sweep_fixed(sw, lambda integ, h: a01_xml(option_xml(integ, h)), lambda m, d: None, probe,
                rollout_solve, ["euler", "implicitfast", "rk4"] + (["discrete"] if "discrete" in INTEGRATORS else []),
                "joint-coordinates")
    default_point(sw, a01_xml, lambda m, d: None, probe, rollout_solve, "joint-coordinates")


def default_point(sw, xml_fn, init_fn, probe, solver, formulation, callback=None):
    """MuJoCo's defaults: Euler, timestep 0.002, default solver and constraint settings."""
    def build():
        m = mujoco.MjModel.from_xml_string(xml_fn('<option gravity="0 -9.81 0"><flag contact="disable"/></option>'))
        d = mujoco.MjData(m)
        init_fn(m, d)
        return (m, d, callback) if callback else (m, d)
    sw.point("mujoco-default", formulation, "fixed-step", "0.002",
             build, lambda model, truth: solver(model, sw.truth.times, model[0].opt.timestep, probe))


def scene_chain(sw):
    check_probes(sw.truth, ["tip_x", "tip_y", "mid_x", "mid_y"])

    def probe(m, d):
        tx, ty = site_xy(m, d, "tip")
        mx, my = site_xy(m, d, "mid")
        return {"tip_x": tx, "tip_y": ty, "mid_x": mx, "mid_y": my}
    sweep_fixed(sw, lambda integ, h: chain_xml(option_xml(integ, h)), lambda m, d: None, probe,
                rollout_solve, ["euler", "implicitfast", "rk4"], "joint-coordinates")
    default_point(sw, chain_xml, lambda m, d: None, probe, rollout_solve, "joint-coordinates")


def step(x, x0, h0, x1, h1):
    if x <= x0:
        return h0
    if x >= x1:
        return h1
    s = (x - x0) / (x1 - x0)
    return h0 + (h1 - h0) * s * s * (3 - 2 * s)


def make_impact(k):
    def force(y, v):
        if y >= 0.05:
            return 0.0
        f = k * (0.05 - y) ** 1.5 - step(y, 0.05 - 0.1, 50.0, 0.05, 0.0) * v
        return f if f > 0 else 0.0
    return force


def scene_impact(k):
    def run(sw):
        check_probes(sw.truth, ["y"])
        force = make_impact(k)

        def passive(m, d):          # IMPACT(y, ydot, 0.05, k, 1.5, 50, 0.1) on the slide joint
            d.qfrc_passive[0] += force(d.qpos[0], d.qvel[0])

        def init(m, d):
            d.qpos[0] = 0.15

        def probe(m, d):
            return {"y": d.qpos[0]}
        sweep_fixed(sw, lambda integ, h: impact_xml(option_xml(integ, h)), init, probe,
                    loop_solve, ["euler", "implicitfast", "rk4"], "python-passive-callback",
                    callback=passive)
        default_point(sw, impact_xml, init, probe, loop_solve, "python-passive-callback",
                      callback=passive)
    return run


def scene_slider_crank(sw):
    check_probes(sw.truth, ["torque", "slider_x"])

    def init(m, d):
        d.qvel[:] = [2 * math.pi, -2.5 * math.pi, 0.0, 1.0]    # consistent with the loop
        d.qpos[2] = 0.5

    def probe(m, d):
        eq = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_EQUALITY, "drive")
        rows = [i for i in range(d.nefc) if d.efc_type[i] == mujoco.mjtConstraint.mjCNSTR_EQUALITY
                and d.efc_id[i] == eq]
        jac = np.array(d.efc_J).reshape(d.nefc, m.nv) if not mujoco.mj_isSparse(m) else None
        if jac is None:
            raise RuntimeError("sparse efc_J not handled")
        torque = sum(jac[i, 0] * d.efc_force[i] for i in rows)   # on the crank dof, about +z
        return {"torque": float(torque), "slider_x": float(d.qpos[2])}

    # 'best': Newton solver to 1e-15, many iterations, the stiffest constraints MuJoCo
    # allows (solimp at its maximum impedance 0.9999, solref time constant 0 so MuJoCo's
    # refsafe clamps it to 2 time steps, critical damping).
    best_opt = 'solver="Newton" tolerance="1e-15" iterations="1000" ls_iterations="200"'
    best_eq = 'solref="0.0000001 1" solimp="0.9999 0.9999 0.001 0.5 2"'
    sweep_fixed(sw, lambda integ, h: slider_crank_xml(option_xml(integ, h, best_opt), best_eq),
                init, probe, rollout_solve, ["euler", "implicitfast", "rk4"], "soft-equality-best")
    default_point(sw, lambda opt: slider_crank_xml(opt, ""), init, probe, rollout_solve,
                  "soft-equality-default")


REGISTRY = {
    "a01_pendulum": scene_a01,
    "chain_n100": scene_chain,
    "impact_block_k1e5": scene_impact(1e5),
    "impact_block_k1e7": scene_impact(1e7),
    "slider_crank_driven": scene_slider_crank,
}

if __name__ == "__main__":
    main("mujoco", REGISTRY)

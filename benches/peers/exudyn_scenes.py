#!/usr/bin/env python3
"""Exudyn peer: the mbfx reference scenes built in Exudyn, swept over its solvers,
scored against examples/scenes/<scene>.toml, written to OUT/<scene>.csv.

Solvers swept:
- implicit, fixed step: GeneralizedAlpha (index 3, spectral radius 0.9 = Exudyn's default)
  and TrapezoidalIndex2 (Newmark trapezoidal rule with index-2 constraints), Newton
  tolerances tightened (relative 1e-10, absolute 1e-12) so that they do not limit the error;
- explicit, adaptive step (automaticStepSize, rtol = atol = tol): DOPRI5, ODE23;
- explicit, fixed step: RK44 (classical RK4), RK67.
Explicit solvers cannot handle joint constraints (Exudyn only eliminates coordinate
constraints to ground), so they run on the minimal-coordinate formulations
(ObjectKinematicTree for the pendulum and the chain, a 1-coordinate body for the block)
and are not run on the closed-loop slider-crank.
Probes are read at the truth times: the solver is driven from probe time to probe time
(solver.it.endTime, SolveSteps), so adaptive steps land on them exactly.
"""
import math
import time

import numpy as np
import exudyn as exu
from exudyn.itemInterface import (NodeGenericODE2, NodePoint2D, NodeRigidBody2D, NodePointGround,
                                  Node1D, ObjectKinematicTree, ObjectMassPoint2D, ObjectRigidBody2D,
                                  ObjectMass1D, ObjectGround, ObjectConnectorDistance,
                                  ObjectJointRevolute2D, ObjectConnectorCoordinate,
                                  ObjectConnectorCoordinateSpringDamper, MarkerBodyPosition,
                                  MarkerNodePosition, MarkerNodeCoordinate, MarkerBodyMass,
                                  LoadForceVector, LoadMassProportional, LoadCoordinate,
                                  SensorKinematicTree)
from exudyn.advancedUtilities import CreateSymbolicUserFunction

from common import Run, main, refine

esym = exu.symbolic
DST = exu.DynamicSolverType
OVT = exu.OutputVariableType
G = 9.81

IMPLICIT = {"generalized-alpha": DST.GeneralizedAlpha, "trapezoidal-index2": DST.TrapezoidalIndex2}
ADAPTIVE = {"dopri5": DST.DOPRI5, "ode23": DST.ODE23}
FIXED_EXPLICIT = {"rk44": DST.RK44, "rk67": DST.RK67}


# ---------------------------------------------------------------- driver

class Model:
    """An assembled mbs and a probe reader probe(mbs) -> {name: value} (current state)."""
    def __init__(self, sc, mbs, probe, keep=None):
        self.sc, self.mbs, self.probe, self.keep = sc, mbs, probe, keep


def settings(end, solver, h=None, tol=None, tight_newton=True, sparse=False):
    ss = exu.SimulationSettings()
    ti = ss.timeIntegration
    ti.endTime = end
    ti.verboseMode = 0
    ss.solution.file.write = False
    ss.solution.sensors.active = False
    ti.solverType = solver
    if tol is not None:                      # explicit, automatic step size
        ti.automaticStepSize = True
        ti.absoluteTolerance = tol
        ti.relativeTolerance = tol
        ti.numberOfSteps = max(1, int(round(end / 0.1)))   # maximum step 0.1 s
        ti.minimumStepSize = 1e-8   # Exudyn default; below it the step is not reduced further
    else:
        ti.automaticStepSize = False
        ti.numberOfSteps = int(round(end / h))
    if tight_newton:
        ti.newton.relativeTolerance = 1e-10
        ti.newton.absoluteTolerance = 1e-12
    if sparse:
        ss.linearSolver.solverType = exu.LinearSolverType.EigenSparse
    if solver == DST.TrapezoidalIndex2:
        ti.generalizedAlpha.useNewmark = True
        ti.generalizedAlpha.useIndex2Constraints = True
    return ss


def solve(model, truth, ss):
    """Drive the solver from probe time to probe time; the CPU time covers InitializeSolver
    and SolveSteps (the integration), not the model building or the probe reading."""
    mbs = model.mbs
    st = ss.timeIntegration.solverType
    explicit = st not in (DST.GeneralizedAlpha, DST.TrapezoidalIndex2)
    solver = exu.MainSolverExplicit() if explicit else exu.MainSolverImplicitSecondOrder()
    values = {}
    steps = 0
    t0 = time.process_time()
    solver.InitializeSolver(mbs, ss)
    cpu = time.process_time() - t0
    for t in truth.times:
        solver.it.endTime = t
        t0 = time.process_time()
        ok = solver.SolveSteps(mbs, ss)
        cpu += time.process_time() - t0
        steps += solver.it.currentStepIndex - 1      # the index restarts at 1 in each SolveSteps
        if not ok or abs(solver.it.currentTime - t) > 1e-9:
            msg = solver.GetErrorString().strip().replace("\n", " ") or "solver stopped"
            return Run(None, cpu, status="failed: t = %.6g: %s" % (solver.it.currentTime, msg))
        vals = model.probe(mbs)
        if not all(math.isfinite(v) for v in vals.values()):
            return Run(None, cpu, status="failed: non-finite state at t = %g" % t)
        values[t] = vals
    solver.FinalizeSolver(mbs, ss)
    it = solver.it
    return Run(values, cpu, steps=steps,
               rejected=it.rejectedAutomaticStepSizeSteps if explicit else None,
               newton=None if explicit else it.newtonStepsCount,
               factorizations=None if explicit else it.newtonJacobiCount)


def steps_list(times, quick):
    ns = [1, 2, 4, 5, 10, 20, 25, 40, 50, 100, 200, 250, 500, 1000, 2000, 2500, 5000, 10000,
          20000, 25000, 50000, 100000, 200000, 500000, 1000000]
    out = []
    for n in ns:
        h = 0.1 / n
        if all(abs(t / h - round(t / h)) < 1e-6 for t in times):
            out.append(h)
    return out[::3] if quick else out


def tol_list(quick):
    tols = [10.0 ** (-e / 2) for e in range(4, 25)]      # 1e-2 ... 1e-12
    return tols[::3] if quick else tols


def sweep(sw, builders, implicit=True, explicit=True, floor=1e-11, sparse=()):
    """builders: {formulation: (build_fn, explicit_ok)}."""
    end = sw.truth.end
    times = sw.truth.times
    for form, (build, explicit_ok) in builders.items():
        runs = []
        if implicit:
            runs += [(name, st, "fixed-step") for name, st in IMPLICIT.items()]
        if explicit and explicit_ok:
            runs += [(name, st, "tolerance") for name, st in ADAPTIVE.items()]
            runs += [(name, st, "fixed-step") for name, st in FIXED_EXPLICIT.items()]
        for name, st, control in runs:
            if control == "tolerance":
                vals = tol_list(sw.args.quick)
                if name == "ode23":          # third order: tighter runs take minutes
                    vals = [v for v in vals if v >= 1e-10]
                mk = lambda v, st=st: settings(end, st, tol=v)
            else:
                vals = steps_list(times, sw.args.quick)
                mk = lambda v, st=st, sp=form in sparse: settings(end, st, h=v, sparse=sp)

            def make(v, name=name, mk=mk, build=build, form=form, control=control):
                return sw.point("exudyn-" + name, form, control, "%g" % v, build,
                                lambda model, truth: solve(model, truth, mk(v)))
            refine(sw, vals, make, floor)


def default_point(sw, build, form):
    """Exudyn's defaults: GeneralizedAlpha (spectral radius 0.9), endTime/100 fixed steps
    (numberOfSteps = 100), default Newton settings (modified Newton, rtol 1e-8)."""
    ss = exu.SimulationSettings()
    ss.timeIntegration.endTime = sw.truth.end
    ss.timeIntegration.verboseMode = 0
    ss.solution.file.write = False
    ss.solution.sensors.active = False
    n = ss.timeIntegration.numberOfSteps
    sw.point("exudyn-default", form, "fixed-step", "%g" % (sw.truth.end / n), build,
             lambda model, truth: solve(model, truth, ss))


def check_probes(truth, known):
    missing = [n for n in truth.names if n not in known]
    if missing:
        raise SystemExit("%s: probes %s of the truth file are not built here" % (truth.scene, missing))


# ---------------------------------------------------------------- open chains

def kinematic_tree(n, l, masses, coms, izz, gravity, sensors):
    """planar chain of n revolute-z joints, joint k at distance l from joint k-1, all at
    rest at angle 0 (along +x). sensors: {name: (link, local x)}."""
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    node = mbs.AddNode(NodeGenericODE2(referenceCoordinates=[0.] * n, initialCoordinates=[0.] * n,
                                       initialCoordinates_t=[0.] * n, numberOfODE2Coordinates=n))
    inert = [np.diag([0., 0., izz[k]]) for k in range(n)]
    obj = mbs.AddObject(ObjectKinematicTree(
        nodeNumber=node, jointTypes=[exu.JointType.RevoluteZ] * n, linkParents=list(range(-1, n - 1)),
        jointTransformations=exu.Matrix3DList([np.eye(3)] * n),
        jointOffsets=exu.Vector3DList([[0., 0., 0.]] + [[l, 0., 0.]] * (n - 1)),
        linkInertiasCOM=exu.Matrix3DList(inert), linkCOMs=exu.Vector3DList([[c, 0., 0.] for c in coms]),
        linkMasses=list(masses), gravity=[0., -gravity, 0.]))
    sens = {}
    for name, (link, x) in sensors.items():
        sens[name] = mbs.AddSensor(SensorKinematicTree(objectNumber=obj, linkNumber=link, localPosition=[x, 0., 0.],
                                                       storeInternal=False, writeToFile=False,
                                                       outputVariableType=OVT.Position))
    mbs.Assemble()
    return sc, mbs, sens


def pendulum_point_mass(mbs):
    """A01 in Cartesian coordinates in mbs: a 1 kg point mass released at rest at (1, 0),
    a distance constraint of 1 m to the pivot at the origin (index 3), gravity -y.
    Returns its node."""
    n = mbs.AddNode(NodePoint2D(referenceCoordinates=[1., 0.], initialCoordinates=[0., 0.],
                                initialVelocities=[0., 0.]))
    mbs.AddObject(ObjectMassPoint2D(nodeNumber=n, mass=1.0))
    g = mbs.AddObject(ObjectGround())
    mg = mbs.AddMarker(MarkerBodyPosition(bodyNumber=g, localPosition=[0., 0., 0.]))
    mn = mbs.AddMarker(MarkerNodePosition(nodeNumber=n))
    mbs.AddObject(ObjectConnectorDistance(markerNumbers=[mg, mn], distance=1.0))
    mbs.AddLoad(LoadForceVector(markerNumber=mn, loadVector=[0., -G, 0.]))
    return n


def scene_a01(sw):
    check_probes(sw.truth, ["x", "y"])

    def probe_kt(sens):
        def p(mbs):
            v = mbs.GetSensorValues(sens["p"])
            return {"x": v[0], "y": v[1]}
        return p

    def build_kt():
        sc, mbs, sens = kinematic_tree(1, 1.0, [1.0], [1.0], [0.0], G, {"p": (0, 1.0)})
        return Model(sc, mbs, probe_kt(sens))

    def build_red():
        # Cartesian point mass with a distance constraint to the pivot (index 3)
        sc = exu.SystemContainer()
        mbs = sc.AddSystem()
        n = pendulum_point_mass(mbs)
        mbs.Assemble()

        def p(mbs):
            q = mbs.GetNodeOutput(n, OVT.Position)
            return {"x": q[0], "y": q[1]}
        return Model(sc, mbs, p)
    sweep(sw, {"kinematic-tree": (build_kt, True), "redundant-distance-index3": (build_red, False)})
    default_point(sw, build_red, "redundant-distance-index3")


def scene_chain(sw):
    check_probes(sw.truth, ["tip_x", "tip_y", "mid_x", "mid_y"])
    N, L, M = 100, 0.1, 0.1
    IZZ = M * L * L / 12

    def build_kt():
        sc, mbs, sens = kinematic_tree(N, L, [M] * N, [L / 2] * N, [IZZ] * N, G,
                                       {"tip": (N - 1, L), "mid": (N // 2 - 1, L)})

        def p(mbs):
            a = mbs.GetSensorValues(sens["tip"])
            b = mbs.GetSensorValues(sens["mid"])
            return {"tip_x": a[0], "tip_y": a[1], "mid_x": b[0], "mid_y": b[1]}
        return Model(sc, mbs, p)

    def build_red():
        # 100 RigidBody2D (x, y, phi at the CM) and 100 RevoluteJoint2D (index 3)
        sc = exu.SystemContainer()
        mbs = sc.AddSystem()
        g = mbs.AddObject(ObjectGround())
        prev = mbs.AddMarker(MarkerBodyPosition(bodyNumber=g, localPosition=[0., 0., 0.]))
        bodies = []
        for k in range(N):
            nd = mbs.AddNode(NodeRigidBody2D(referenceCoordinates=[(k + 0.5) * L, 0., 0.],
                                             initialCoordinates=[0., 0., 0.], initialVelocities=[0., 0., 0.]))
            b = mbs.AddObject(ObjectRigidBody2D(nodeNumber=nd, mass=M, inertia=IZZ))
            bodies.append(b)
            m0 = mbs.AddMarker(MarkerBodyPosition(bodyNumber=b, localPosition=[-L / 2, 0., 0.]))
            mbs.AddObject(ObjectJointRevolute2D(markerNumbers=[prev, m0]))
            prev = mbs.AddMarker(MarkerBodyPosition(bodyNumber=b, localPosition=[L / 2, 0., 0.]))
            mbs.AddLoad(LoadMassProportional(markerNumber=mbs.AddMarker(MarkerBodyMass(bodyNumber=b)),
                                             loadVector=[0., -G, 0.]))
        mbs.Assemble()
        tip, mid = bodies[N - 1], bodies[N // 2 - 1]

        def p(mbs):
            a = mbs.GetObjectOutputBody(tip, OVT.Position, localPosition=[L / 2, 0., 0.])
            b = mbs.GetObjectOutputBody(mid, OVT.Position, localPosition=[L / 2, 0., 0.])
            return {"tip_x": a[0], "tip_y": a[1], "mid_x": b[0], "mid_y": b[1]}
        return Model(sc, mbs, p)

    sweep(sw, {"kinematic-tree": (build_kt, True), "redundant-revolute2d-index3": (build_red, False)},
          sparse=("redundant-revolute2d-index3",))
    default_point(sw, build_red, "redundant-revolute2d-index3")


# ---------------------------------------------------------------- IMPACT block

def impact_force_fn(k, lib):
    """The connector's 'spring force' f acts as -f on the block's coordinate y, so
    f = -IMPACT(y, ydot, 0.05, k, 1.5, 50, 0.1) (clamped: the contact never pulls)."""
    mx, mn = (esym.max, esym.min) if lib == "symbolic" else (max, min)

    def f(mbs, t, itemNumber, displacement, velocity, stiffness, damping, offset):
        y, v = displacement, velocity
        pen = mx(0.05 - y, 0.)
        s = mn(mx((y - (0.05 - 0.1)) / 0.1, 0.), 1.)
        c = 50. + (0. - 50.) * s * s * (3. - 2. * s)
        # y >= 0.05: pen = 0 and s = 1 (c = 0), so the clamp gives 0 there: no branch needed
        return -mx(k * pen ** 1.5 - c * v, 0.)
    return f


def scene_impact(k):
    def run(sw):
        check_probes(sw.truth, ["y"])

        def build(lib):
            def b():
                sc = exu.SystemContainer()
                mbs = sc.AddSystem()
                ng = mbs.AddNode(NodePointGround(referenceCoordinates=[0., 0., 0.]))
                n = mbs.AddNode(Node1D(referenceCoordinates=[0.], initialCoordinates=[0.15],
                                       initialVelocities=[0.]))
                mbs.AddObject(ObjectMass1D(nodeNumber=n, mass=1.0))
                mg = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=ng, coordinate=0))
                mc = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=n, coordinate=0))
                mbs.AddLoad(LoadCoordinate(markerNumber=mc, load=-G))
                fn = impact_force_fn(k, lib)
                keep = None
                if lib == "symbolic":
                    keep = CreateSymbolicUserFunction(mbs, fn, "springForceUserFunction",
                                                      itemTypeName="ObjectConnectorCoordinateSpringDamper")
                    uf = keep
                else:
                    uf = fn
                mbs.AddObject(ObjectConnectorCoordinateSpringDamper(markerNumbers=[mg, mc],
                                                                    springForceUserFunction=uf))
                mbs.Assemble()
                return Model(sc, mbs, lambda mbs: {"y": float(np.atleast_1d(mbs.GetNodeOutput(n, OVT.Coordinates))[0])}, keep)
            return b
        sweep(sw, {"symbolic-user-function": (build("symbolic"), True)})
        default_point(sw, build("symbolic"), "symbolic-user-function")
    return run


# ---------------------------------------------------------------- driven slider-crank

def slider_crank_2d(mbs, r, l, crank, rod, slider):
    """The scenes' slider-crank in mbs: crank (1 kg, length r, m r^2/12) pinned at the
    origin, rod (2 kg, length l), slider (0.5 kg point) held on the x axis, gravity -y.
    `crank`, `rod`: (reference coordinates [x, y, phi], initial velocities) of their CM
    nodes; `slider`: ([x, y], [vx, vy]). Returns the items a drive and probes need."""
    g = mbs.AddObject(ObjectGround())
    ng = mbs.AddNode(NodePointGround(referenceCoordinates=[0., 0., 0.]))
    nc = mbs.AddNode(NodeRigidBody2D(referenceCoordinates=crank[0], initialVelocities=crank[1]))
    crank_body = mbs.AddObject(ObjectRigidBody2D(nodeNumber=nc, mass=1.0, inertia=1.0 * r * r / 12))
    nr = mbs.AddNode(NodeRigidBody2D(referenceCoordinates=rod[0], initialVelocities=rod[1]))
    rod_body = mbs.AddObject(ObjectRigidBody2D(nodeNumber=nr, mass=2.0, inertia=2.0 * l * l / 12))
    ns = mbs.AddNode(NodePoint2D(referenceCoordinates=slider[0], initialVelocities=slider[1]))
    slider_body = mbs.AddObject(ObjectMassPoint2D(nodeNumber=ns, mass=0.5))
    mk = lambda b, x: mbs.AddMarker(MarkerBodyPosition(bodyNumber=b, localPosition=[x, 0., 0.]))
    mbs.AddObject(ObjectJointRevolute2D(markerNumbers=[mk(g, 0.), mk(crank_body, -r / 2)]))
    mbs.AddObject(ObjectJointRevolute2D(markerNumbers=[mk(crank_body, r / 2), mk(rod_body, -l / 2)]))
    ms = mbs.AddMarker(MarkerNodePosition(nodeNumber=ns))
    mbs.AddObject(ObjectJointRevolute2D(markerNumbers=[mk(rod_body, l / 2), ms]))
    mgc = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=ng, coordinate=0))
    mbs.AddObject(ObjectConnectorCoordinate(markerNumbers=[mgc, mbs.AddMarker(
        MarkerNodeCoordinate(nodeNumber=ns, coordinate=1))]))          # slider on the x axis
    for b in (crank_body, rod_body, slider_body):
        mbs.AddLoad(LoadMassProportional(markerNumber=mbs.AddMarker(MarkerBodyMass(bodyNumber=b)),
                                         loadVector=[0., -G, 0.]))
    return {"nc": nc, "crank": crank_body, "ns": ns, "mgc": mgc}


def scene_slider_crank(sw):
    check_probes(sw.truth, ["torque", "slider_x"])
    R, L = 0.1, 0.4
    W = 2 * math.pi

    def build():
        sc = exu.SystemContainer()
        mbs = sc.AddSystem()
        # crank: CM at (0.05, 0), omega = 2 pi; rod: CM at (0.3, 0), omega = -pi/2 (consistent)
        sc2 = slider_crank_2d(mbs, R, L, ([R / 2, 0., 0.], [0., W * R / 2, W]),
                              ([R + L / 2, 0., 0.], [0., W * R / 2, -W * R / L]),
                              ([R + L, 0.], [0., 0.]))
        nc, ns, mgc = sc2["nc"], sc2["ns"], sc2["mgc"]

        def off(mbs, t, itemNumber, lOffset):
            return W * t

        def off_t(mbs, t, itemNumber, lOffset):
            return W + 0. * t
        keep = [CreateSymbolicUserFunction(mbs, off, "offsetUserFunction",
                                           itemTypeName="ObjectConnectorCoordinate"),
                CreateSymbolicUserFunction(mbs, off_t, "offsetUserFunction_t",
                                           itemTypeName="ObjectConnectorCoordinate")]
        drive = mbs.AddObject(ObjectConnectorCoordinate(
            markerNumbers=[mgc, mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=nc, coordinate=2))],
            offsetUserFunction=keep[0], offsetUserFunction_t=keep[1]))     # phi_crank = 2 pi t
        mbs.Assemble()

        def p(mbs):
            lam = mbs.GetObjectOutput(drive, OVT.Force)
            lam = float(np.asarray(lam).ravel()[0])
            # the multiplier is the force on marker 1's coordinate (phi of the crank) with the
            # sign of Exudyn's convention: the driving torque on the crank about +z is -lambda
            return {"torque": -lam, "slider_x": mbs.GetNodeOutput(ns, OVT.Position)[0]}
        return Model(sc, mbs, p, keep)

    sweep(sw, {"redundant-revolute2d-index3": (build, False)}, explicit=False)
    # the explicit solvers do not handle the loop's joints; say so in one row
    sw.point("exudyn-dopri5", "redundant-revolute2d-index3", "tolerance", "1e-08", build,
             lambda model, truth: solve(model, truth, settings(sw.truth.end, DST.DOPRI5, tol=1e-8)))
    default_point(sw, build, "redundant-revolute2d-index3")


REGISTRY = {
    "a01_pendulum": scene_a01,
    "chain_n100": scene_chain,
    "impact_block_k1e5": scene_impact(1e5),
    "impact_block_k1e7": scene_impact(1e7),
    "slider_crank_driven": scene_slider_crank,
}

if __name__ == "__main__":
    main("exudyn", REGISTRY)

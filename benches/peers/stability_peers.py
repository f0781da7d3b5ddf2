#!/usr/bin/env python3
"""Stability cells of the peers: the cases of `mbfx bench stability` (read from its --list)
built in Exudyn and in MuJoCo, every peer method run on every case, each cell judged like
the mbfx suite: accurate | failed, named | crashed | wrong, silently | unsupported.

    stability_peers.py OUT [--scenes DIR] [--peer exudyn|mujoco] [--case ID] [--timeout S]

writes OUT/stability.csv (header below). Each cell runs in its own subprocess
(`stability_peers.py --cell PEER CASE METHOD FORMULATION`) with a timeout, so a segfault or a
hang is a `crashed`/`failed` cell, not the end of the sweep. The child prints its result
as one JSON line; everything else it (or the peer's C++ code) printed on stdout/stderr is
kept as the peer's warnings; MuJoCo's own warning counters (data.warning) and its
MUJOCO_LOG.TXT (the child runs in a fresh directory) are read too.

Scoring as common.py: max |y - r| / scale (or relative) over the judged group (position;
reaction only where the scene has no position probe), at every [[at]] time of the truth file.
"""
import argparse
import csv
import json
import math
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from common import REPO, load_truth  # noqa: E402

HEADER = ["case", "scene", "peer", "method", "formulation", "setting", "error", "status",
          "verdict", "note"]
MBFX = os.environ.get("MBFX", os.path.join(REPO, "target", "release", "mbfx"))
G = 9.81


def suite_cases():
    """The suite's cases as mbfx defines them (`mbfx bench stability --list`, one source
    for both): [(case id, scene, tolerance, fixed step or None)], and the ids of the cases
    whose motion must stop."""
    out = subprocess.run([MBFX, "bench", "stability", "--list", "--scenes",
                          os.path.join(REPO, "examples", "scenes")],
                         capture_output=True, text=True, check=True).stdout
    rows = list(csv.DictReader(out.splitlines()))
    cases = [(r["case"], r["scene"], float(r["tolerance"]),
              float(r["step"]) if r["step"] else None) for r in rows]
    return cases, {r["case"] for r in rows if r["must_stop"] == "true"}


CASES, MUST_STOP = suite_cases()
CASE = {c[0]: c for c in CASES}


# ================================================================ truth and scoring

def judged_group(truth):
    groups = {p["group"] for p in truth.probes}
    return "position" if "position" in groups else "reaction"


def score_group(truth, values, group):
    """max over the [[at]] rows and the probes of `group` (as common.score)."""
    err = None
    for t, ref in truth.at:
        got = values.get(t)
        if got is None:
            continue
        for p in truth.probes:
            n = p["name"]
            if p["group"] != group or n not in ref:
                continue
            y, r = got[n], ref[n]
            e = abs(y - r) / abs(r) if p["relative"] else abs(y - r) / truth.scale
            if not math.isfinite(e):
                e = math.inf
            err = e if err is None else max(err, e)
    return err


# ================================================================ the ADM datasets (planar parts)

def adm_statements(text):
    stmts, cur = [], None
    for line in text.splitlines():
        s = line.split("!")[0].rstrip()
        if not s.strip():
            continue
        if s.lstrip().startswith(","):
            cur += s
        else:
            if cur is not None:
                stmts.append(cur)
            cur = s.strip()
    if cur is not None:
        stmts.append(cur)
    return stmts


def adm_num(v):
    v = v.strip()
    if v.upper().endswith("D"):
        return math.radians(float(v[:-1]))
    return float(v)


def adm_parse(text):
    """The parts (mass, Izz, IP, CM, BCS), markers (part, global x, y), revolute joints and
    gravity of a planar dataset: enough for the A02 generator's output and Andrews."""
    parts, markers, joints, grav = {}, {}, [], (0.0, 0.0, 0.0)
    for st in adm_statements(text):
        head, *rest = [x.strip() for x in st.split(",")]
        if "/" in head and "=" in head:          # "ACCGRAV/JGRAV = -9.81"
            k, v = head.split("/", 1)
            head, rest = k + "/", [v] + rest
        kv, key = {}, None
        for tok in rest:
            if "=" in tok:
                key, val = [x.strip() for x in tok.split("=", 1)]
                kv[key.upper()] = [val] if val else []
            elif key is not None and tok:
                kv[key.upper()].append(tok)
        if "/" in head:
            kind, ident = head.split("/", 1)
            kind = kind.strip().upper()
            words = ident.split()
            ident = words[0] if words else ""
            flags = [w.upper() for w in words[1:]] + [t.upper() for t in rest if "=" not in t and t]
        else:
            kind, ident, flags = head.upper(), None, []
        if kind == "PART":
            pid = int(ident)
            if "GROUND" in flags or "GROUND" in st.upper().split(",")[0]:
                parts[pid] = {"ground": True, "qg": (0., 0.), "a": 0.}
                continue
            qg = [adm_num(x) for x in kv.get("QG", ["0", "0", "0"])]
            re_ = [adm_num(x) for x in kv.get("REULER", ["0", "0", "0"])]
            ip = [float(x) for x in kv.get("IP", ["0", "0", "0"])]
            parts[pid] = {"ground": False, "mass": float(kv["MASS"][0]), "ip": ip,
                          "cm": int(kv["CM"][0]), "qg": (qg[0], qg[1]), "a": re_[0],
                          "v": (float(kv.get("VX", ["0"])[0]), float(kv.get("VY", ["0"])[0])),
                          "w": float(kv.get("WZ", ["0"])[0])}
        elif kind == "MARKER":
            qp = [adm_num(x) for x in kv.get("QP", ["0", "0", "0"])]
            markers[int(ident)] = {"part": int(kv["PART"][0]), "qp": (qp[0], qp[1])}
        elif kind == "JOINT":
            if "REVOLUTE" not in flags:
                raise ValueError("only revolute joints are read here: " + st)
            joints.append((int(ident), int(kv["I"][0]), int(kv["J"][0])))
        elif kind == "ACCGRAV":
            grav = tuple(float(kv.get(k, ["0"])[0]) for k in ("IGRAV", "JGRAV", "KGRAV"))
    for mid, m in markers.items():
        p = parts[m["part"]]
        c, s = math.cos(p["a"]), math.sin(p["a"])
        x, y = m["qp"]
        m["g"] = (p["qg"][0] + c * x - s * y, p["qg"][1] + s * x + c * y)
    for pid, p in parts.items():
        if not p["ground"]:
            p["pos"] = markers[p["cm"]]["g"]
    return {"parts": parts, "markers": markers, "joints": joints, "gravity": grav}


def local_xy(part, g):
    """global point g in the frame of `part` (origin at its CM, x at its angle)."""
    c, s = math.cos(part["a"]), math.sin(part["a"])
    dx, dy = g[0] - part["pos"][0], g[1] - part["pos"][1]
    return (c * dx + s * dy, -s * dx + c * dy)


def scene_dataset(scenes_dir, scene):
    """The .adm text of a scene: its `model` file, or `mbfx bench generate` for a [generate] table."""
    import tomllib
    with open(os.path.join(scenes_dir, scene + ".toml"), "rb") as f:
        t = tomllib.load(f)
    if "generate" in t:
        g = t["generate"]
        out = subprocess.run([MBFX, "bench", "generate", g["kind"], str(g["n"])],
                             capture_output=True, text=True, check=True)
        return out.stdout, int(g.get("dim", t.get("dim", 2)))
    with open(os.path.join(scenes_dir, t["model"])) as f:
        return f.read(), int(t.get("dim", 2))


# ---------------------------------------------------------------- the motion_lockup kinematics

LK_R, LK_L = 0.1, 0.4


def lockup_state(x=0.35, xd=0.15):
    """Consistent positions and velocities of the slider-crank of motion_lockup.adm at slider x."""
    r, l = LK_R, LK_L
    c = (x * x + r * r - l * l) / (2 * r * x)
    th = math.acos(c)                     # pin above the axis
    s = math.sin(th)
    thd = -((x * x - r * r + l * l) / (2 * r * x * x)) * xd / s
    B = (r * c, r * s)
    Bd = (-r * s * thd, r * c * thd)
    dx, dy = x - B[0], -B[1]
    psi = math.atan2(dy, dx)
    psid = (dx * (-Bd[1]) - dy * (xd - Bd[0])) / (dx * dx + dy * dy)
    return {"th": th, "thd": thd, "B": B, "Bd": Bd, "psi": psi, "psid": psid,
            "rodcm": ((B[0] + x) / 2, B[1] / 2), "rodv": ((Bd[0] + xd) / 2, Bd[1] / 2)}


# ================================================================ Exudyn

def exudyn_cells(case):
    """[(method, formulation, setting)] of Exudyn for a case."""
    cid, scene, tol, step = CASE[case]
    implicit = ["exudyn-generalized-alpha", "exudyn-trapezoidal-index2"]
    if scene == "a01_pendulum":
        implicit = ["exudyn-generalized-alpha", "exudyn-generalized-alpha-rho1",
                    "exudyn-trapezoidal-index2"]
    explicit_fixed = ["exudyn-rk44", "exudyn-rk67"]
    adaptive = ["exudyn-dopri5", "exudyn-ode23"]
    forms = {  # formulation -> explicit solvers possible
        "cart_pole": [("kinematic-tree", True), ("redundant-masspoint2d-index3", False)],
        "a01_pendulum": [("kinematic-tree", True), ("redundant-distance-index3", False)],
        "a02_n1": [("redundant-revolute2d-index3", False)],
        "a02_n40": [("redundant-revolute2d-index3-sparse", False)],
        "a02_n1_3d": [("redundant-rigidbody3d-dense", False), ("redundant-rigidbody3d-sparse", False),
                      ("redundant-rigidbody3d-eigendense", False),
                      ("redundant-rigidbody3d-eigendense-fullpivot", False)],
        "andrews": [("redundant-revolute2d-index3", False)],
        "impact_stiff_k1e9": [("symbolic-user-function", True)],
        "impact_block_k1e5": [("symbolic-user-function", True)],
        "motion_lockup": [("redundant-revolute2d-index3", False)],
    }[scene]
    def runs(methods, setting):
        """Each method on the formulations it can run, or on the first to be refused."""
        out = []
        for m in methods:
            if any(e for _, e in forms):
                out += [(m, f, setting) for f, e in forms if e]
            else:
                out.append((m, forms[0][0], setting))   # to be refused: unsupported
        return out

    out = []
    hs = "h end/100 (default)" if step is None else "h %g" % step
    if step is None:
        out += runs(adaptive, "rtol %g" % tol)
    out += [(m, f, hs) for m in implicit for f, _ in forms]
    out += runs(explicit_fixed, hs)
    if step is None:
        # the defaults: on the formulation a user builds with Exudyn's body/joint items
        dform = [f for f, e in forms if not e] or [forms[0][0]]
        out += [("exudyn-default", f, hs) for f in dform]
    return out


def exudyn_run(case, method, form, scenes_dir):
    import numpy as np
    import exudyn as exu
    from exudyn.itemInterface import (NodePoint2D, NodeRigidBody2D, NodePointGround, Node1D,
                                      ObjectMassPoint2D, ObjectRigidBody2D, ObjectMass1D, ObjectGround,
                                      ObjectConnectorDistance, ObjectJointRevolute2D,
                                      ObjectConnectorCoordinate, ObjectConnectorCoordinateSpringDamper,
                                      ObjectConnectorSpringDamper, MarkerBodyPosition, MarkerBodyRigid,
                                      MarkerNodePosition, MarkerNodeCoordinate, MarkerBodyMass,
                                      LoadForceVector, LoadMassProportional, LoadCoordinate,
                                      LoadTorqueVector, ObjectKinematicTree, NodeGenericODE2,
                                      SensorKinematicTree)
    from exudyn.advancedUtilities import CreateSymbolicUserFunction
    import exudyn_scenes as ex

    cid, scene, tol, step = CASE[case]
    truth = load_truth(scenes_dir, scene)
    DST = exu.DynamicSolverType
    OVT = exu.OutputVariableType
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    keep = []
    sparse = "-sparse" in form
    eigendense = "-eigendense" in form
    fullpivot = form.endswith("-fullpivot")

    # ------------------------------------------------ build
    if scene == "a01_pendulum":
        if form == "kinematic-tree":
            m = ex.kinematic_tree(1, 1.0, [1.0], [1.0], [0.0], G, {"p": (0, 1.0)})
            sc, mbs, sens = m

            def probe():
                v = mbs.GetSensorValues(sens["p"])
                return {"x": v[0], "y": v[1]}
        else:
            n = ex.pendulum_point_mass(mbs)
            mbs.Assemble()

            def probe():
                q = mbs.GetNodeOutput(n, OVT.Position)
                return {"x": q[0], "y": q[1]}

    elif scene == "cart_pole":
        M, m_, L = 1e-6, 1.0, 1.0
        if form == "kinematic-tree":
            node = mbs.AddNode(NodeGenericODE2(referenceCoordinates=[0., 0.], initialCoordinates=[0., 0.],
                                               initialCoordinates_t=[0., 0.], numberOfODE2Coordinates=2))
            obj = mbs.AddObject(ObjectKinematicTree(
                nodeNumber=node, jointTypes=[exu.JointType.PrismaticX, exu.JointType.RevoluteZ],
                linkParents=[-1, 0], jointTransformations=exu.Matrix3DList([np.eye(3)] * 2),
                jointOffsets=exu.Vector3DList([[0., 0., 0.], [0., 0., 0.]]),
                linkInertiasCOM=exu.Matrix3DList([np.zeros((3, 3))] * 2),
                linkCOMs=exu.Vector3DList([[0., 0., 0.], [L, 0., 0.]]),
                linkMasses=[M, m_], gravity=[0., -G, 0.]))
            sc_ = mbs.AddSensor(SensorKinematicTree(objectNumber=obj, linkNumber=0, localPosition=[0., 0., 0.],
                                                    storeInternal=False, writeToFile=False,
                                                    outputVariableType=OVT.Position))
            sm = mbs.AddSensor(SensorKinematicTree(objectNumber=obj, linkNumber=1, localPosition=[L, 0., 0.],
                                                   storeInternal=False, writeToFile=False,
                                                   outputVariableType=OVT.Position))
            mbs.Assemble()

            def probe():
                c = mbs.GetSensorValues(sc_)
                p = mbs.GetSensorValues(sm)
                return {"theta": math.atan2(p[0] - c[0], -(p[1] - c[1])), "x_cart": c[0], "y_mass": p[1]}
        else:
            ng = mbs.AddNode(NodePointGround(referenceCoordinates=[0., 0., 0.]))
            nc = mbs.AddNode(NodePoint2D(referenceCoordinates=[0., 0.]))
            np_ = mbs.AddNode(NodePoint2D(referenceCoordinates=[L, 0.]))
            mbs.AddObject(ObjectMassPoint2D(nodeNumber=nc, mass=M))
            mbs.AddObject(ObjectMassPoint2D(nodeNumber=np_, mass=m_))
            mc = mbs.AddMarker(MarkerNodePosition(nodeNumber=nc))
            mp = mbs.AddMarker(MarkerNodePosition(nodeNumber=np_))
            mbs.AddObject(ObjectConnectorDistance(markerNumbers=[mc, mp], distance=L))
            mbs.AddObject(ObjectConnectorCoordinate(markerNumbers=[
                mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=ng, coordinate=0)),
                mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=nc, coordinate=1))]))   # cart on the x axis
            mbs.AddLoad(LoadForceVector(markerNumber=mc, loadVector=[0., -G * M, 0.]))
            mbs.AddLoad(LoadForceVector(markerNumber=mp, loadVector=[0., -G * m_, 0.]))
            mbs.Assemble()

            def probe():
                c = mbs.GetNodeOutput(nc, OVT.Position)
                p = mbs.GetNodeOutput(np_, OVT.Position)
                return {"theta": math.atan2(p[0] - c[0], -(p[1] - c[1])), "x_cart": c[0], "y_mass": p[1]}

    elif scene in ("a02_n1", "a02_n40", "a02_n1_3d", "andrews"):
        text, dim = scene_dataset(scenes_dir, scene)
        d = adm_parse(text)
        parts, markers = d["parts"], d["markers"]
        gy = d["gravity"][1]
        body, node = {}, {}
        if dim == 2:
            g = mbs.AddObject(ObjectGround())
            for pid, p in parts.items():
                if p["ground"]:
                    body[pid] = g
                    continue
                nd = mbs.AddNode(NodeRigidBody2D(referenceCoordinates=[p["pos"][0], p["pos"][1], p["a"]],
                                                 initialVelocities=[p["v"][0], p["v"][1], p["w"]]))
                node[pid] = nd
                body[pid] = mbs.AddObject(ObjectRigidBody2D(nodeNumber=nd, mass=p["mass"], inertia=p["ip"][2]))
                if gy:
                    mbs.AddLoad(LoadMassProportional(markerNumber=mbs.AddMarker(MarkerBodyMass(bodyNumber=body[pid])),
                                                     loadVector=[0., gy, 0.]))

            def mk(mid):
                m = markers[mid]
                p = parts[m["part"]]
                loc = m["g"] if p["ground"] else local_xy(p, m["g"])
                return mbs.AddMarker(MarkerBodyPosition(bodyNumber=body[m["part"]], localPosition=[loc[0], loc[1], 0.]))
            for _, i, j in d["joints"]:
                mbs.AddObject(ObjectJointRevolute2D(markerNumbers=[mk(j), mk(i)]))
            if scene == "andrews":
                # the motor (0.033 N m on body 1 about +z) and the spring D-C
                mbs.AddLoad(LoadTorqueVector(markerNumber=mbs.AddMarker(MarkerBodyRigid(bodyNumber=body[1])),
                                             loadVector=[0., 0., 0.033]))
                mbs.AddObject(ObjectConnectorSpringDamper(markerNumbers=[mk(1004), mk(304)], stiffness=4530.,
                                                          damping=0., referenceLength=0.07785))
        else:
            from exudyn.rigidBodyUtilities import RigidBodyInertia
            g = mbs.CreateGround(referencePosition=[0., 0., 0.])
            for pid, p in parts.items():
                if p["ground"]:
                    body[pid] = g
                    continue
                c, s = math.cos(p["a"]), math.sin(p["a"])
                body[pid] = mbs.CreateRigidBody(
                    inertia=RigidBodyInertia(mass=p["mass"], inertiaTensor=np.diag(p["ip"])),
                    referencePosition=[p["pos"][0], p["pos"][1], 0.],
                    referenceRotationMatrix=np.array([[c, -s, 0.], [s, c, 0.], [0., 0., 1.]]),
                    initialVelocity=[p["v"][0], p["v"][1], 0.], initialAngularVelocity=[0., 0., p["w"]],
                    gravity=[0., gy, 0.])
            for _, i, j in d["joints"]:
                pi, pj = markers[i]["part"], markers[j]["part"]
                pt = markers[i]["g"]
                mbs.CreateRevoluteJoint(itemNumbers=[body[pj], body[pi]], position=[pt[0], pt[1], 0.],
                                        axis=[0., 0., 1.], useGlobalFrame=True)
        mbs.Assemble()
        if scene == "andrews":
            def ang(pid):
                if dim == 2:
                    return parts[pid]["a"] + float(mbs.GetNodeOutput(node[pid], OVT.Coordinates)[2])
                raise RuntimeError("3D andrews not built")
            def probe():
                a = {k: ang(k) for k in range(1, 8)}
                return {"beta": a[1], "theta": a[2] - a[1], "gamma": a[3], "phi": a[4] - a[5],
                        "delta": a[5], "omega": a[6] - a[7], "epsilon": a[7]}
        else:
            m203 = markers[203]
            p2 = parts[m203["part"]]
            loc = local_xy(p2, m203["g"])

            def probe():
                q = mbs.GetObjectOutputBody(body[m203["part"]], OVT.Position, localPosition=[loc[0], loc[1], 0.])
                return {"b0x": q[0], "b0y": q[1]}

    elif scene in ("impact_stiff_k1e9", "impact_block_k1e5"):
        k = 1e9 if scene == "impact_stiff_k1e9" else 1e5
        ng = mbs.AddNode(NodePointGround(referenceCoordinates=[0., 0., 0.]))
        n = mbs.AddNode(Node1D(referenceCoordinates=[0.], initialCoordinates=[0.15], initialVelocities=[0.]))
        mbs.AddObject(ObjectMass1D(nodeNumber=n, mass=1.0))
        mg = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=ng, coordinate=0))
        mc = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=n, coordinate=0))
        mbs.AddLoad(LoadCoordinate(markerNumber=mc, load=-G))
        uf = CreateSymbolicUserFunction(mbs, ex.impact_force_fn(k, "symbolic"), "springForceUserFunction",
                                        itemTypeName="ObjectConnectorCoordinateSpringDamper")
        keep.append(uf)
        mbs.AddObject(ObjectConnectorCoordinateSpringDamper(markerNumbers=[mg, mc], springForceUserFunction=uf))
        mbs.Assemble()

        def probe():
            return {"y": float(np.atleast_1d(mbs.GetNodeOutput(n, OVT.Coordinates))[0])}

    elif scene == "motion_lockup":
        st = lockup_state()
        r = LK_R
        B = st["B"]
        th = st["th"]
        sc2 = ex.slider_crank_2d(mbs, r, LK_L,
                                 ([B[0] / 2, B[1] / 2, th], [st["Bd"][0] / 2, st["Bd"][1] / 2, st["thd"]]),
                                 ([st["rodcm"][0], st["rodcm"][1], st["psi"]],
                                  [st["rodv"][0], st["rodv"][1], st["psid"]]),
                                 ([0.35, 0.], [0.15, 0.]))
        crank, ns, mgc = sc2["crank"], sc2["ns"], sc2["mgc"]

        def off(mbs, t, itemNumber, lOffset):
            return 0.15 * t

        def off_t(mbs, t, itemNumber, lOffset):
            return 0.15 + 0. * t
        keep += [CreateSymbolicUserFunction(mbs, off, "offsetUserFunction", itemTypeName="ObjectConnectorCoordinate"),
                 CreateSymbolicUserFunction(mbs, off_t, "offsetUserFunction_t", itemTypeName="ObjectConnectorCoordinate")]
        mbs.AddObject(ObjectConnectorCoordinate(      # the MOTION: slider x = 0.35 + 0.15 t
            markerNumbers=[mgc, mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=ns, coordinate=0))],
            offsetUserFunction=keep[0], offsetUserFunction_t=keep[1]))
        mbs.Assemble()

        def probe():
            q = mbs.GetObjectOutputBody(crank, OVT.Position, localPosition=[r / 2, 0., 0.])
            return {"slider_x": mbs.GetNodeOutput(ns, OVT.Position)[0], "pin_x": q[0], "pin_y": q[1]}
    else:
        raise ValueError(scene)

    # ------------------------------------------------ settings
    name = method[len("exudyn-"):]
    end = truth.end
    ss = exu.SimulationSettings()
    ti = ss.timeIntegration
    ti.endTime = end
    ti.verboseMode = 1          # as Exudyn's examples: Newton failures and step reductions are printed
    ss.solution.file.write = False
    ss.solution.sensors.active = False
    if name == "default":
        solver_type = DST.GeneralizedAlpha
    else:
        solver_type = {"generalized-alpha": DST.GeneralizedAlpha, "generalized-alpha-rho1": DST.GeneralizedAlpha,
                       "trapezoidal-index2": DST.TrapezoidalIndex2, "dopri5": DST.DOPRI5, "ode23": DST.ODE23,
                       "rk44": DST.RK44, "rk67": DST.RK67}[name]
        ti.solverType = solver_type
        if name in ("dopri5", "ode23"):
            ti.automaticStepSize = True
            ti.absoluteTolerance = tol
            ti.relativeTolerance = tol          # maximum step end/100 (numberOfSteps default)
        else:
            ti.automaticStepSize = False
            if step is not None:
                ti.numberOfSteps = int(round(end / step))
        if solver_type in (DST.GeneralizedAlpha, DST.TrapezoidalIndex2):
            ti.newton.relativeTolerance = 1e-10      # as the wp sweep
            ti.newton.absoluteTolerance = 1e-12
        if solver_type == DST.TrapezoidalIndex2:
            ti.generalizedAlpha.useNewmark = True
            ti.generalizedAlpha.useIndex2Constraints = True
        if name == "generalized-alpha-rho1":
            ti.generalizedAlpha.spectralRadius = 1.0
    if sparse:
        ss.linearSolver.solverType = exu.LinearSolverType.EigenSparse
    if eigendense:            # Eigen's partial-pivot LU: does not detect a singular matrix
        ss.linearSolver.solverType = exu.LinearSolverType.EigenDense
    if fullpivot:             # Exudyn's documented remedy for redundant constraints: FullPivLU
        ss.linearSolver.ignoreSingularJacobian = True
    explicit = solver_type not in (DST.GeneralizedAlpha, DST.TrapezoidalIndex2)

    # ------------------------------------------------ solve, probe time to probe time
    solver = exu.MainSolverExplicit() if explicit else exu.MainSolverImplicitSecondOrder()
    values = {}
    try:
        solver.InitializeSolver(mbs, ss)
    except Exception as e:
        return {"values": None, "t": 0.0, "status": "failed: " + one_line(type(e).__name__ + ": " + str(e)),
                "explicit_refused": explicit}
    targets = list(truth.times)
    if case in MUST_STOP and targets[-1] < end:
        targets.append(end)                    # the run must not get there
    t_reached = 0.0
    for t in targets:
        solver.it.endTime = t
        try:
            ok = solver.SolveSteps(mbs, ss)
        except Exception as e:
            return {"values": values, "t": solver.it.currentTime,
                    "status": "failed: t = %.6g: %s" % (solver.it.currentTime, one_line(type(e).__name__ + ": " + str(e)))}
        t_reached = solver.it.currentTime
        if not ok or abs(solver.it.currentTime - t) > 1e-9:
            msg = one_line(solver.GetErrorString()) or "solver stopped"
            return {"values": values, "t": t_reached, "status": "failed: t = %.6g: %s" % (t_reached, msg)}
        if t in truth.times:
            try:
                vals = probe()
            except Exception as e:
                return {"values": values, "t": t_reached, "status": "failed: probe: " + one_line(str(e))}
            values[t] = {k: float(v) for k, v in vals.items()}
    solver.FinalizeSolver(mbs, ss)
    return {"values": values, "t": t_reached, "status": "ok"}


def one_line(s):
    s = re.sub(r"\s*\[Python file '[^']*'[,;] line \d+\]", "", " ".join(str(s).split()))
    return s.replace(",", ";")[:300]


# ================================================================ MuJoCo

def mujoco_cells(case):
    cid, scene, tol, step = CASE[case]
    form = {"cart_pole": "joint-coordinates", "a01_pendulum": "joint-coordinates",
            "a02_n1": "hinge-tree+soft-connect", "a02_n40": "hinge-tree+soft-connect",
            "a02_n1_3d": "hinge-tree+soft-connect-3d", "andrews": "hinge-tree+soft-connect",
            "impact_stiff_k1e9": "python-passive-callback", "impact_block_k1e5": "python-passive-callback",
            "motion_lockup": "hinge-tree+soft-equalities"}[scene]
    out = []
    hs = "h 2e-3 (default)" if step is None else "h %g" % step
    for m in ("mujoco-euler", "mujoco-implicitfast", "mujoco-rk4"):
        out.append((m, form, hs))
    if step is None:
        out.append(("mujoco-default", form, "h 2e-3 (default)"))
    return out


BEST_OPT = 'solver="Newton" tolerance="1e-15" iterations="1000" ls_iterations="200"'
BEST_EQ = 'solref="0.0000001 1" solimp="0.9999 0.9999 0.001 0.5 2"'


def mj_tree_xml(d, dim, opt, eq_attr, extra_sites=(), tendon=""):
    """Hinge tree of a planar ADM model (spanning tree from ground) plus `connect`
    equalities for the joints that close loops (dim 3: two connects on the joint's axis,
    ±0.1 m along z, i.e. a revolute closure). Every body's frame is its BCS (origin at
    the CM, x at its angle); every marker is a site m<id>."""
    parts, markers = d["parts"], d["markers"]
    ground = [pid for pid, p in parts.items() if p["ground"]][0]
    parent, hinge_at, loops, seen = {}, {}, [], {ground}
    frontier = [ground]
    used = set()
    while frontier:
        nxt = []
        for b in frontier:
            for jid, i, j in d["joints"]:
                if jid in used:
                    continue
                pi, pj = markers[i]["part"], markers[j]["part"]
                if b not in (pi, pj):
                    continue
                other = pj if pi == b else pi
                used.add(jid)
                if other in seen:
                    loops.append((jid, i, j))
                else:
                    seen.add(other)
                    parent[other] = b
                    hinge_at[other] = markers[i]["g"]
                    nxt.append(other)
        frontier = nxt
    children = {}
    for c, p in parent.items():
        children.setdefault(p, []).append(c)

    def body_xml(pid):
        p = parts[pid]
        par = parts[parent[pid]]
        if par["ground"]:
            pos, a = p["pos"], p["a"]
        else:
            pos = local_xy(par, p["pos"])
            a = p["a"] - par["a"]
        hx, hy = local_xy(p, hinge_at[pid])
        s = '<body name="b%d" pos="%.17g %.17g 0" euler="0 0 %.17g">' % (pid, pos[0], pos[1], a)
        s += '<joint name="q%d" type="hinge" axis="0 0 1" pos="%.17g %.17g 0"/>' % (pid, hx, hy)
        ip = [max(x, 1e-12) for x in p["ip"]]
        s += '<inertial pos="0 0 0" mass="%.17g" diaginertia="%.17g %.17g %.17g"/>' % (p["mass"], ip[0], ip[1], ip[2])
        for mid, m in markers.items():
            if m["part"] == pid:
                x, y = local_xy(p, m["g"])
                s += '<site name="m%d" pos="%.17g %.17g 0"/>' % (mid, x, y)
                if dim == 3:
                    s += '<site name="m%dzp" pos="%.17g %.17g 0.1"/><site name="m%dzm" pos="%.17g %.17g -0.1"/>' % (
                        mid, x, y, mid, x, y)
        for c in children.get(pid, []):
            s += body_xml(c)
        return s + "</body>"
    world = ""
    for mid, m in markers.items():
        if parts[m["part"]]["ground"]:
            world += '<site name="m%d" pos="%.17g %.17g 0"/>' % (mid, m["g"][0], m["g"][1])
            if dim == 3:
                world += '<site name="m%dzp" pos="%.17g %.17g 0.1"/><site name="m%dzm" pos="%.17g %.17g -0.1"/>' % (
                    mid, m["g"][0], m["g"][1], mid, m["g"][0], m["g"][1])
    for c in children.get(ground, []):
        world += body_xml(c)
    eq = ""
    for jid, i, j in loops:
        if dim == 2:
            eq += '<connect name="j%d" site1="m%d" site2="m%d" %s/>' % (jid, i, j, eq_attr)
        else:
            for z in ("zp", "zm"):
                eq += '<connect name="j%d%s" site1="m%d%s" site2="m%d%s" %s/>' % (jid, z, i, z, j, z, eq_attr)
    xml = ('<mujoco><compiler angle="radian"/>%s<worldbody>%s</worldbody><equality>%s</equality>%s</mujoco>'
           % (opt, world, eq, tendon))
    return xml, parent


def mujoco_run(case, method, form, scenes_dir, workdir):
    import numpy as np
    import mujoco
    import mujoco_scenes as mj

    cid, scene, tol, step = CASE[case]
    truth = load_truth(scenes_dir, scene)
    key = method[len("mujoco-"):]
    default = key == "default"
    integ = {"euler": "Euler", "implicitfast": "implicitfast", "rk4": "RK4", "default": "Euler"}[key]
    h = 0.002 if step is None else step
    gy = -G

    def opt(best=False, grav=-G):
        if default:
            return '<option gravity="0 %.17g 0"><flag contact="disable"/></option>' % grav
        return ('<option timestep="%.17g" integrator="%s" gravity="0 %.17g 0" %s><flag contact="disable"/></option>'
                % (h, integ, grav, BEST_OPT if best else ""))
    eq_attr = "" if default else BEST_EQ
    passive = None
    init = lambda m, d: None

    if scene == "a01_pendulum":
        xml = mj.a01_xml(opt())

        def probe(m, d):
            x, y = mj.site_xy(m, d, "p")
            return {"x": x, "y": y}
    elif scene == "cart_pole":
        xml = """<mujoco model="cart_pole">%s<worldbody>
  <body name="cart"><joint name="x" type="slide" axis="1 0 0"/>
    <inertial pos="0 0 0" mass="1e-6" diaginertia="1e-12 1e-12 1e-12"/><site name="c" pos="0 0 0"/>
    <body name="pole"><joint name="th" type="hinge" axis="0 0 1"/>
      <inertial pos="1 0 0" mass="1" diaginertia="1e-12 1e-12 1e-12"/><site name="p" pos="1 0 0"/></body>
  </body></worldbody></mujoco>""" % opt()

        def probe(m, d):
            cx, cy = mj.site_xy(m, d, "c")
            px, py = mj.site_xy(m, d, "p")
            return {"theta": math.atan2(px - cx, -(py - cy)), "x_cart": cx, "y_mass": py}
    elif scene in ("a02_n1", "a02_n40", "a02_n1_3d", "andrews"):
        text, dim = scene_dataset(scenes_dir, scene)
        dd = adm_parse(text)
        tendon = ""
        grav = dd["gravity"][1]
        if scene == "andrews":
            tendon = ('<tendon><spatial name="spring" stiffness="4530" springlength="0.07785">'
                      '<site site="m304"/><site site="m1004"/></spatial></tendon>')
        xml, parent = mj_tree_xml(dd, dim, opt(best=True, grav=grav), eq_attr, tendon=tendon)
        parts = dd["parts"]

        def init(m, d):
            for pid, par in parent.items():
                j = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_JOINT, "q%d" % pid)
                w = parts[pid]["w"] - (0. if parts[par]["ground"] else parts[par]["w"])
                d.qvel[m.jnt_dofadr[j]] = w
            if scene == "andrews":
                j = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_JOINT, "q1")
                d.qfrc_applied[m.jnt_dofadr[j]] = 0.033        # the motor on body 1
        if scene == "andrews":
            def ang(m, d, pid):
                a = parts[pid]["a"]
                j = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_JOINT, "q%d" % pid)
                s = d.qpos[m.jnt_qposadr[j]]
                par = parent[pid]
                return a + s + (0. if parts[par]["ground"] else ang(m, d, par) - parts[par]["a"])

            def probe(m, d):
                a = {k: ang(m, d, k) for k in range(1, 8)}
                return {"beta": a[1], "theta": a[2] - a[1], "gamma": a[3], "phi": a[4] - a[5],
                        "delta": a[5], "omega": a[6] - a[7], "epsilon": a[7]}
        else:
            def probe(m, d):
                x, y = mj.site_xy(m, d, "m203")
                return {"b0x": x, "b0y": y}
    elif scene in ("impact_stiff_k1e9", "impact_block_k1e5"):
        k = 1e9 if scene == "impact_stiff_k1e9" else 1e5
        force = mj.make_impact(k)
        xml = mj.impact_xml(opt())

        def passive(m, d):
            d.qfrc_passive[0] += force(d.qpos[0], d.qvel[0])

        def init(m, d):
            d.qpos[0] = 0.15

        def probe(m, d):
            return {"y": d.qpos[0]}
    elif scene == "motion_lockup":
        st = lockup_state()
        B = st["B"]
        xml = """<mujoco model="motion_lockup"><compiler angle="radian"/>%s<worldbody>
  <body name="crank" euler="0 0 %.17g"><joint name="crank" type="hinge" axis="0 0 1"/>
    <inertial pos="0.05 0 0" mass="1" diaginertia="1e-5 8.333333333333333e-4 8.333333333333333e-4"/>
    <site name="pin" pos="0.1 0 0"/>
    <body name="rod" pos="0.1 0 0" euler="0 0 %.17g"><joint name="rod" type="hinge" axis="0 0 1"/>
      <inertial pos="0.2 0 0" mass="2" diaginertia="1e-5 0.02666666666666667 0.02666666666666667"/>
      <site name="rodend" pos="0.4 0 0"/></body></body>
  <body name="slider" pos="0.35 0 0"><joint name="slider" type="slide" axis="1 0 0"/>
    <inertial pos="0 0 0" mass="0.5" diaginertia="1e-4 1e-4 1e-4"/><site name="spin" pos="0 0 0"/></body>
  <body name="clock"><joint name="clock" type="slide" axis="0 0 1"/>
    <inertial pos="0 0 0" mass="1e14" diaginertia="1 1 1"/></body>
</worldbody><equality>
  <connect name="loop" site1="rodend" site2="spin" %s/>
  <joint name="drive" joint1="slider" joint2="clock" polycoef="0 0.15 0 0 0" %s/>
</equality></mujoco>""" % (opt(best=True), st["th"], st["psi"] - st["th"], eq_attr, eq_attr)

        def init(m, d):
            d.qvel[:] = [st["thd"], st["psid"] - st["thd"], 0.15, 1.0]

        def probe(m, d):
            px, py = mj.site_xy(m, d, "pin")
            sx, _ = mj.site_xy(m, d, "spin")
            return {"slider_x": sx, "pin_x": px, "pin_y": py}
    else:
        raise ValueError(scene)

    m = mujoco.MjModel.from_xml_string(xml)
    d = mujoco.MjData(m)
    init(m, d)
    h = m.opt.timestep
    targets = list(truth.times)
    if case in MUST_STOP and targets[-1] < truth.end:
        targets.append(truth.end)
    if passive is not None:
        mujoco.set_mjcb_passive(passive)
    values, prev, nsteps = {}, 0.0, 0
    warn = []
    try:
        mujoco.mj_forward(m, d)
        for t in targets:
            n = int(round((t - prev) / h))
            if abs(n * h - (t - prev)) > 1e-9:
                raise ValueError("step %g does not land on t = %g" % (h, t))
            for _ in range(n):
                mujoco.mj_step(m, d)
            nsteps += n
            prev = t
            mujoco.mj_forward(m, d)
            if t in truth.times:
                vals = probe(m, d)
                if not all(math.isfinite(v) for v in vals.values()):
                    return {"values": values, "t": t, "status": "failed: non-finite state at t = %g" % t,
                            "warnings": mj_warnings(m, d, mujoco)}
                values[t] = {k: float(v) for k, v in vals.items()}
    finally:
        mujoco.set_mjcb_passive(None)
    res = {"values": values, "t": d.time, "status": "ok", "warnings": mj_warnings(m, d, mujoco),
           "info": "steps %d" % nsteps}
    if m.neq:
        # how far the soft equalities are from holding, at the end
        mujoco.mj_forward(m, d)
        rows = [i for i in range(d.nefc) if d.efc_type[i] == mujoco.mjtConstraint.mjCNSTR_EQUALITY]
        viol = max((abs(d.efc_pos[i]) for i in rows), default=0.0)
        res["info"] += "; max equality violation at end %.1e" % viol
    return res


def mj_warnings(m, d, mujoco):
    out = []
    for i in range(len(d.warning)):
        w = d.warning[i]
        if w.number > 0:
            out.append("%s x%d (info %d)" % (mujoco.mjtWarning(i).name, w.number, w.lastinfo))
    return out


# ================================================================ one cell (child process)

def run_cell(peer, case, method, form, scenes_dir):
    work = os.getcwd()
    try:
        if peer == "exudyn":
            r = exudyn_run(case, method, form, scenes_dir)
        else:
            r = mujoco_run(case, method, form, scenes_dir, work)
    except Exception as e:
        r = {"values": None, "t": None, "status": "failed: " + one_line(type(e).__name__ + ": " + str(e))}
    sys.stdout.flush()
    sys.stderr.flush()
    print("@@RESULT@@" + json.dumps(r, default=str), flush=True)


# ================================================================ the sweep (parent)

NOISE = re.compile(r"DeprecationWarning|warnings\.warn\(|^\s*$|^\+{5,}$|^\*{5,}$|^EXUDYN V[\d.]+ solver:"
                   r"|^STEP\d+, t = |^Solver terminated successfully")
WRONG = re.compile(r"warn|error|fail|not converge|singular|unstable|nan|inf\b|reduc|exceed", re.I)
# Exudyn prints these only at verboseMode >= 1 (its default is 0: silent)
VERBOSE_ONLY = re.compile(r"Newton \(time/load step|Solve steps: adaptive reduction")


def judge(case, status, error, went_wrong):
    """The suite's rule (src/bench/stability.rs `judge`), with the peers' extra outcomes."""
    cid, scene, tol, step = CASE[case]
    if status.startswith("unsupported"):
        return "unsupported"
    if status.startswith("crashed"):
        return "crashed"
    if status.startswith("failed"):
        return "failed, named"
    accurate = error is not None and error <= 10 * tol
    if case in MUST_STOP:
        return "failed, named" if went_wrong else "wrong, silently"
    if accurate:
        return "accurate"
    return "failed, named" if went_wrong else "wrong, silently"


def sweep(args):
    out_dir = os.path.abspath(args.out)
    os.makedirs(out_dir, exist_ok=True)
    path = os.path.join(out_dir, "stability.csv")
    rows = []
    peers = [args.peer] if args.peer else ["exudyn", "mujoco"]
    for case in [c[0] for c in CASES]:
        if args.case and case not in args.case:
            continue
        cid, scene, tol, step = CASE[case]
        truth = load_truth(args.scenes, scene)
        if truth is None:
            print("no truth file for %s; skipped" % scene, file=sys.stderr)
            continue
        group = judged_group(truth)
        for peer in peers:
            cells = exudyn_cells(case) if peer == "exudyn" else mujoco_cells(case)
            for method, form, setting in cells:
                row = run_one(args, peer, case, scene, method, form, setting, truth, group, tol)
                rows.append(row)
                print(",".join(str(x) for x in row), flush=True)
                write(path, rows, args)
    print("wrote %s (%d cells)" % (path, len(rows)))


def write(path, rows, args):
    old = []
    if (args.case or args.peer) and os.path.exists(path):   # partial run: replace its own cells only
        with open(path) as f:
            r = list(csv.reader(f))[1:]
        keys = {(x[0], x[2], x[3], x[4]) for x in rows}
        old = [x for x in r if (x[0], x[2], x[3], x[4]) not in keys]
    allrows = old + rows
    order = {c[0]: i for i, c in enumerate(CASES)}
    allrows.sort(key=lambda x: (order.get(x[0], 99), x[2]))
    with open(path, "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(HEADER)
        w.writerows(allrows)


def run_one(args, peer, case, scene, method, form, setting, truth, group, tol):
    work = tempfile.mkdtemp(prefix="stab-%s-" % peer)
    cmd = [sys.executable, "-u", os.path.abspath(__file__), "--cell", peer, case, method, form,
           "--scenes", args.scenes]
    t0 = time.time()
    try:
        p = subprocess.run(cmd, cwd=work, capture_output=True, text=True, timeout=args.timeout)
        rc, out, err = p.returncode, p.stdout, p.stderr
    except subprocess.TimeoutExpired as e:
        rc, out, err = None, (e.stdout or b""), (e.stderr or b"")
        out = out.decode() if isinstance(out, bytes) else out
        err = err.decode() if isinstance(err, bytes) else err
    wall = time.time() - t0
    res = None
    lines = []
    for ln in (out or "").splitlines() + (err or "").splitlines():
        if ln.startswith("@@RESULT@@"):
            res = json.loads(ln[len("@@RESULT@@"):])
        elif not NOISE.search(ln):
            lines.append(ln.strip())
    log = os.path.join(work, "MUJOCO_LOG.TXT")
    if os.path.exists(log):
        with open(log) as f:
            lines += ["MUJOCO_LOG: " + x.strip() for x in f if x.strip()]
    shutil.rmtree(work, ignore_errors=True)
    notes, error, went_wrong = [], None, False
    if rc is None:
        status = "failed: no result within %g s" % args.timeout
    elif res is None:
        sig = -rc if rc < 0 else None
        status = "crashed: %s" % (signal.Signals(sig).name if sig else "exit code %d" % rc)
    else:
        status = res["status"]
        if (peer == "exudyn" and res.get("explicit_refused") and status.startswith("failed")
                and "ModelError" in status):      # refused at InitializeSolver
            status = ("unsupported: Exudyn's explicit solvers eliminate only coordinate constraints to ground; "
                      "they refuse this model (%s)" % status[len("failed: "):])
        if res.get("values"):
            vals = {float(k): v for k, v in res["values"].items()}
            error = score_group(truth, vals, group)
            if status != "ok":
                if error is not None:
                    notes.append("error %.1e over the %d probe rows before the stop" % (error, len(vals)))
                error = None
            elif not all(math.isfinite(x) for v in vals.values() for x in v.values()):
                notes.append("non-finite state (NaN/inf) at the probe times; the peer reported success")
            if status == "ok" and scene.startswith("impact") and "y" in next(iter(vals.values())):
                top = max(v["y"] for t, v in vals.items() if t > 1.0)
                if not math.isfinite(top) or top > 0.15 + 1e-3:
                    notes.append("energy injected: y = %.4g after the first impacts (released at rest at 0.15)" % top)
        for w in res.get("warnings", []):
            lines.append("data.warning: " + w)
        if res.get("info"):
            notes.append(res["info"])
        if status == "ok" and res.get("t") is not None and peer == "exudyn":
            notes.append("reached t = %.6g" % float(res["t"]))
        if status.startswith("failed") and res.get("t") is not None:
            notes.append("stopped at t = %.6g" % float(res["t"]))
    lines = [re.sub(r"\s*\[file '[^']*'[,;] line \d+\]:?", "", x) for x in lines]
    lines = [x for x in lines if x.strip() not in ("Python WARNING", "Python WARNING:")]
    if any("BADQACC" in x or "BADQVEL" in x or "BADQPOS" in x for x in lines):
        notes.append("MuJoCo reset the state to the initial one (mj_resetData) and carried on")
    warn_lines = [x for x in lines if WRONG.search(x)]
    if status == "ok" and warn_lines:
        went_wrong = True
        only_verbose = all(VERBOSE_ONLY.search(x) for x in warn_lines)
        notes.append("peer warned%s: %s" % (" (verboseMode-1 messages only: silent at Exudyn's default verboseMode 0)"
                                            if only_verbose else "", summary(warn_lines)))
    elif lines:
        notes.append("peer printed: %s" % summary(lines))
    verdict = judge(case, status, error, went_wrong)
    if case in MUST_STOP and status.startswith("failed") and res and res.get("t") is not None:
        notes.append("lock-up is at t = 1")
    notes.append("wall %.1f s" % wall)
    note = "; ".join(notes).replace(",", ";").replace("\n", " ")[:600]
    return [case, scene, peer, method, form, setting,
            "" if error is None else ("%.3e" % error if math.isfinite(error) else "inf"),
            status.replace("\n", " ")[:400], verdict, note]


def summary(lines, k=3):
    """the distinct kinds of lines (numbers masked), each with its count and first instance."""
    kinds = {}
    for x in lines:
        key = re.sub(r"[-+]?\d[\d.e+-]*", "#", x)
        if key not in kinds:
            kinds[key] = [0, x[:160]]
        kinds[key][0] += 1
    items = list(kinds.values())[:k]
    more = len(kinds) - k
    return " | ".join("%dx %s" % (n, x) for n, x in items) + (" | (%d more kinds)" % more if more > 0 else "")


def uniq(xs):
    seen, out = set(), []
    for x in xs:
        k = re.sub(r"[-+]?\d[\d.e+-]*", "#", x)
        if k not in seen:
            seen.add(k)
            out.append(x[:200])
    return out


SHORT = {"kinematic-tree": "tree", "redundant-masspoint2d-index3": "red", "redundant-distance-index3": "red",
         "redundant-revolute2d-index3": "", "redundant-revolute2d-index3-sparse": "",
         "redundant-rigidbody3d-dense": "EXUdense", "redundant-rigidbody3d-sparse": "EigenSparse",
         "redundant-rigidbody3d-eigendense": "EigenDense",
         "redundant-rigidbody3d-eigendense-fullpivot": "EigenDense+FullPivLU",
         "symbolic-user-function": ""}
VERDICT = {"accurate": "accurate", "failed, named": "failed, named", "wrong, silently": "**wrong, silently**",
           "crashed": "crashed", "unsupported": "unsupported"}


def matrix(path):
    """The cell matrix of OUT/stability.csv as markdown: rows = case, columns = peer methods."""
    with open(path) as f:
        rows = list(csv.DictReader(f))
    methods = []
    for r in rows:
        if r["method"] not in methods:
            methods.append(r["method"])
    order = ["exudyn-dopri5", "exudyn-ode23", "exudyn-generalized-alpha", "exudyn-generalized-alpha-rho1",
             "exudyn-trapezoidal-index2", "exudyn-rk44", "exudyn-rk67", "exudyn-default",
             "mujoco-euler", "mujoco-implicitfast", "mujoco-rk4", "mujoco-default"]
    methods = [m for m in order if m in methods] + [m for m in methods if m not in order]
    out = "| case | setting | " + " | ".join(methods) + " |\n"
    out += "|---|---|" + "---|" * len(methods) + "\n"
    for c in CASES:
        rc = [r for r in rows if r["case"] == c[0]]
        if not rc:
            continue
        tol_setting = "tol %g" % c[2] if c[3] is None else "h %g" % c[3]
        cells = []
        for m in methods:
            rm = [r for r in rc if r["method"] == m]
            parts = []
            for r in rm:
                v = VERDICT.get(r["verdict"], r["verdict"])
                if r["error"]:
                    v += " (%.0e)" % float(r["error"])
                if r["verdict"] == "failed, named" and r["status"] == "ok":
                    v += " †" if "verboseMode-1" in r["note"] else " ‡"
                tag = SHORT.get(r["formulation"], r["formulation"])
                if len(rm) > 1 and tag:
                    v = tag + ": " + v
                if m.startswith("exudyn") and r["setting"].startswith("h end"):
                    pass
                parts.append(v)
            cells.append("<br>".join(parts) if parts else "–")
        out += "| %s | %s | %s |\n" % (c[0], tol_setting, " | ".join(cells))
    return out


def rho_trace():
    """Exudyn generalized-alpha on the index-3 pendulum (point mass + ConnectorDistance,
    h = 1e-2, Newton as the sweep): the rod force and the energy every 0.5 s for spectral
    radius 1 and 0.9 (exact: |F| <= 3 m g = 29.4 N, E = 0)."""
    import numpy as np
    import exudyn as exu
    from exudyn.itemInterface import (NodePoint2D, ObjectMassPoint2D, ObjectGround, MarkerBodyPosition,
                                      MarkerNodePosition, ObjectConnectorDistance, LoadForceVector)
    OVT = exu.OutputVariableType
    print("| t | " + " | ".join("rho %g: rod force N, energy J" % r for r in (1.0, 0.9)) + " |")
    print("|---|---|---|")
    cols = {}
    for rho in (1.0, 0.9):
        sc = exu.SystemContainer()
        mbs = sc.AddSystem()
        n = mbs.AddNode(NodePoint2D(referenceCoordinates=[1., 0.]))
        mbs.AddObject(ObjectMassPoint2D(nodeNumber=n, mass=1.0))
        g = mbs.AddObject(ObjectGround())
        mg = mbs.AddMarker(MarkerBodyPosition(bodyNumber=g, localPosition=[0., 0., 0.]))
        mn = mbs.AddMarker(MarkerNodePosition(nodeNumber=n))
        c = mbs.AddObject(ObjectConnectorDistance(markerNumbers=[mg, mn], distance=1.0))
        mbs.AddLoad(LoadForceVector(markerNumber=mn, loadVector=[0., -G, 0.]))
        mbs.Assemble()
        ss = exu.SimulationSettings()
        ti = ss.timeIntegration
        ti.endTime, ti.numberOfSteps, ti.verboseMode = 10., 1000, 0
        ti.newton.relativeTolerance, ti.newton.absoluteTolerance = 1e-10, 1e-12
        ti.generalizedAlpha.spectralRadius = rho
        ss.solution.file.write = False
        ss.solution.sensors.active = False
        s = exu.MainSolverImplicitSecondOrder()
        s.InitializeSolver(mbs, ss)
        for k in range(1, 21):
            t = 0.5 * k
            s.it.endTime = t
            ok = s.SolveSteps(mbs, ss)
            if not ok or abs(s.it.currentTime - t) > 1e-9:
                cols[(rho, t)] = "stopped at t = %.4g: %s" % (s.it.currentTime, one_line(s.GetErrorString())[:80])
                break
            f = float(np.ravel(mbs.GetObjectOutput(c, OVT.Force))[0])
            v = mbs.GetNodeOutput(n, OVT.Velocity)
            y = mbs.GetNodeOutput(n, OVT.Position)[1]
            cols[(rho, t)] = "%.3g, %.2g" % (f, 0.5 * (v[0] ** 2 + v[1] ** 2) + G * y)
    for k in range(1, 21):
        t = 0.5 * k
        print("| %g | %s | %s |" % (t, cols.get((1.0, t), ""), cols.get((0.9, t), "")))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("out", nargs="?", default=os.path.join(REPO, "target", "peers"))
    ap.add_argument("--scenes", default=os.path.join(REPO, "examples", "scenes"))
    ap.add_argument("--peer", choices=["exudyn", "mujoco"])
    ap.add_argument("--case", action="append", choices=[c[0] for c in CASES])
    ap.add_argument("--timeout", type=float, default=120.0)
    ap.add_argument("--cell", nargs=4, metavar=("PEER", "CASE", "METHOD", "FORMULATION"))
    ap.add_argument("--list", action="store_true", help="list the cells and exit")
    ap.add_argument("--matrix", action="store_true", help="print OUT/stability.csv as a markdown matrix")
    ap.add_argument("--rho-trace", action="store_true",
                    help="Exudyn generalized-alpha, rho 1 vs 0.9, on the index-3 pendulum: rod force and energy")
    args = ap.parse_args()
    args.scenes = os.path.abspath(args.scenes)
    if args.cell:
        run_cell(*args.cell, args.scenes)
        return
    if args.rho_trace:
        rho_trace()
        return
    if args.matrix:
        print(matrix(os.path.join(args.out, "stability.csv")), end="")
        return
    if args.list:
        for c in CASES:
            for peer, fn in (("exudyn", exudyn_cells), ("mujoco", mujoco_cells)):
                for cell in fn(c[0]):
                    print(c[0], peer, *cell)
        return
    sweep(args)


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Eigenvalues side by side (issue 26 §3): mbfx's LINEAR/EIGENSOL (`mbfx run --statics
--linear=FILE`) against Exudyn's ComputeODE2Eigenvalues and against the closed form or an
independent Lagrangian, on the models of tests/dynamics/linear.rs: a compound pendulum, a
spring-mass-damper, a double pendulum and a chain of N rods hanging at rest.

Exudyn builds the pendulums as kinematic trees (ObjectKinematicTree: joint angles, gravity
inside), so its stiffness is that of gravity in minimal coordinates; the spring-mass-damper
as a Mass1D on a CoordinateSpringDamper, its complex eigenvalues asked for.

    benches/peers/linear_peers.py [--mbfx target/release/mbfx]

Prints one row per mode: the reference ω (rad/s), mbfx's and Exudyn's, and the digits each
agrees with the reference (−log10 of the relative difference; 16 = to the last bit).
Not part of CI (it needs Exudyn: benches/peers/requirements.txt).
"""

import argparse
import math
import os
import subprocess
import sys
import tempfile

import numpy as np

G = 9.81


def pendulum_adm(m, d, i):
    return (
        "pendulum\nPART/1, GROUND\nMARKER/10, PART = 1\n"
        f"PART/2, MASS = {m}, CM = 20, IP = {i}, {i}, {i}\nMARKER/20, PART = 2, QP = 0, -{d}, 0\n"
        f"MARKER/21, PART = 2\nJOINT/1, REVOLUTE, I = 21, J = 10\nACCGRAV/JGRAV = -{G}\nEND\n"
    )


def chain_adm(rods):
    """rods: [(mass, inertia about CM, CM below its pin, length)], hanging from the origin."""
    t = "chain\nPART/1, GROUND\nMARKER/10, PART = 1\n"
    top = 0.0
    for k, (m, i, d, length) in enumerate(rods, start=1):
        p = 10 * (k + 1)
        t += (
            f"PART/{k + 1}, MASS = {m}, CM = {p}, IP = {i}, {i}, {i}\n"
            f"MARKER/{p}, PART = {k + 1}, QP = 0, -{top + d}, 0\n"
            f"MARKER/{p + 1}, PART = {k + 1}, QP = 0, -{top}, 0\n"
            f"MARKER/{p + 2}, PART = {k + 1}, QP = 0, -{top + length}, 0\n"
        )
        j = 10 if k == 1 else 10 * k + 2
        t += f"JOINT/{k}, REVOLUTE, I = {p + 1}, J = {j}\n"
        top += length
    return t + f"ACCGRAV/JGRAV = -{G}\nEND\n"


SMD_ADM = (
    "spring-mass-damper\nPART/1, GROUND\nMARKER/10, PART = 1\n"
    "MARKER/11, PART = 1, REULER = 0, -90D, 0\n"
    "PART/2, MASS = 2, CM = 20, IP = 0.1, 0.1, 0.1\nMARKER/20, PART = 2, QP = 0, -1, 0\n"
    "MARKER/21, PART = 2, QP = 0, -1, 0, REULER = 0, -90D, 0\n"
    "JOINT/1, TRANSLATIONAL, I = 21, J = 11\n"
    "SPRINGDAMPER/1, TRANSLATION, I = 20, J = 10, K = 500, C = 3, LENGTH = 1\n"
    "ACCGRAV/JGRAV = -9.81\nEQUILIBRIUM/ERROR = 1e-12, IMBALANCE = 1e-10\nEND\n"
)


def mbfx_eigenvalues(exe, text, scratch, name):
    """λ (Im ≥ 0) of every mode, from FILE_modes.csv."""
    adm = os.path.join(scratch, name + ".adm")
    with open(adm, "w") as f:
        f.write(text)
    base = os.path.join(scratch, name)
    subprocess.run(
        [exe, "run", adm, "--statics", f"--linear={base}", "--csv", base + ".csv"],
        check=True,
        capture_output=True,
    )
    rows = np.genfromtxt(base + "_modes.csv", delimiter=",", skip_header=1, usecols=(4, 5))
    rows = np.atleast_2d(rows)
    return [complex(r[0], r[1]) for r in rows]


def lagrangian_chain(rods):
    """ω of a hanging chain from its Lagrangian in absolute angles (as the Rust test)."""
    n = len(rods)
    lengths = [r[3] for r in rods]
    mass = np.zeros((n, n))
    stiffness = np.zeros((n, n))
    for i, (m, inertia, d, _) in enumerate(rods):
        # Rod i's CM moves sideways by Σ_{j<i} l_j θ_j + d_i θ_i.
        a = np.array([lengths[j] if j < i else (d if j == i else 0.0) for j in range(n)])
        mass += m * np.outer(a, a)
        mass[i, i] += inertia
        for j in range(i + 1):
            stiffness[j, j] += m * G * (lengths[j] if j < i else d)
    w2 = np.linalg.eigvals(np.linalg.solve(mass, stiffness))
    return sorted(math.sqrt(x.real) for x in w2)


def exudyn_chain(rods):
    import exudyn as exu
    from exudyn.utilities import NodeGenericODE2, ObjectKinematicTree

    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    n = len(rods)
    node = mbs.AddNode(
        NodeGenericODE2(
            referenceCoordinates=[0.0] * n,
            initialCoordinates=[0.0] * n,
            initialCoordinates_t=[0.0] * n,
            numberOfODE2Coordinates=n,
        )
    )
    transforms, offsets = exu.Matrix3DList(), exu.Vector3DList()
    inertias, coms, masses = exu.Matrix3DList(), exu.Vector3DList(), []
    for k, (m, inertia, d, _) in enumerate(rods):
        transforms.Append(np.eye(3))
        offsets.Append([0.0, 0.0 if k == 0 else -rods[k - 1][3], 0.0])
        inertias.Append(np.diag([inertia] * 3))
        coms.Append([0.0, -d, 0.0])
        masses.append(m)
    mbs.AddObject(
        ObjectKinematicTree(
            nodeNumber=node,
            jointTypes=[exu.JointType.RevoluteZ] * n,
            linkParents=list(range(-1, n - 1)),
            jointTransformations=transforms,
            jointOffsets=offsets,
            linkInertiasCOM=inertias,
            linkCOMs=coms,
            linkMasses=masses,
            baseOffset=[0.0, 0.0, 0.0],
            gravity=[0.0, -G, 0.0],
        )
    )
    mbs.Assemble()
    values, _ = mbs.ComputeODE2Eigenvalues(useAbsoluteValues=False)
    return sorted(math.sqrt(x) for x in values)


def exudyn_smd(m, k, c):
    import exudyn as exu
    from exudyn.utilities import (
        CoordinateSpringDamper,
        Mass1D,
        MarkerNodeCoordinate,
        Node1D,
        NodePointGround,
    )

    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    node = mbs.AddNode(Node1D(referenceCoordinates=[0.0], initialCoordinates=[0.0]))
    mbs.AddObject(Mass1D(nodeNumber=node, mass=m))
    ground = mbs.AddNode(NodePointGround())
    markers = [
        mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=ground, coordinate=0)),
        mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=node, coordinate=0)),
    ]
    mbs.AddObject(CoordinateSpringDamper(markerNumbers=markers, stiffness=k, damping=c))
    mbs.Assemble()
    values, _ = mbs.ComputeODE2Eigenvalues(computeComplexEigenvalues=True, useAbsoluteValues=False)
    return sorted((complex(v) for v in values), key=lambda z: (abs(z), z.imag))


def digits(x, ref):
    rel = abs(x - ref) / abs(ref)
    return 16.0 if rel == 0 else min(16.0, -math.log10(rel))


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--mbfx", default="target/release/mbfx")
    args = p.parse_args()
    scratch = tempfile.mkdtemp(prefix="mbfx-linear-peers-")
    print(f"{'model':<20} {'mode':>4} {'reference ω':>22} {'mbfx ω':>22} {'Exudyn ω':>22} {'mbfx digits':>11} {'Exudyn digits':>13}")

    def row(model, k, ref, ours, theirs):
        print(
            f"{model:<20} {k:>4} {ref:>22.15e} {ours:>22.15e} {theirs:>22.15e} "
            f"{digits(ours, ref):>11.1f} {digits(theirs, ref):>13.1f}"
        )

    m, d, i = 2.0, 1.5, 0.5
    ref = math.sqrt(m * G * d / (i + m * d * d))
    ours = abs(mbfx_eigenvalues(args.mbfx, pendulum_adm(m, d, i), scratch, "pendulum")[0])
    theirs = exudyn_chain([(m, i, d, 2 * d)])[0]
    row("pendulum", 1, ref, ours, theirs)

    mass, k, c = 2.0, 500.0, 3.0
    ref = complex(-c / (2 * mass), math.sqrt(k / mass - (c / (2 * mass)) ** 2))
    ours = mbfx_eigenvalues(args.mbfx, SMD_ADM, scratch, "smd")[0]
    theirs = [z for z in exudyn_smd(mass, k, c) if z.imag > 0][0]
    row("spring-mass-damper", 1, abs(ref), abs(ours), abs(theirs))
    row("  damped (Im λ)", 1, ref.imag, ours.imag, theirs.imag)

    for name, rods in [
        ("double pendulum", [(1.0, 0.1, 0.5, 1.0), (1.5, 0.05, 0.4, 0.8)]),
        ("chain of 6 rods", [(0.8, 0.8 * 0.25 / 12, 0.25, 0.5)] * 6),
    ]:
        refs = lagrangian_chain(rods)
        ours = sorted(abs(z) for z in mbfx_eigenvalues(args.mbfx, chain_adm(rods), scratch, name.replace(" ", "_")))
        theirs = exudyn_chain(rods)
        for k, (r, o, t) in enumerate(zip(refs, ours, theirs), start=1):
            row(name, k, r, o, t)
    return 0


if __name__ == "__main__":
    sys.exit(main())

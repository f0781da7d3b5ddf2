"""A run of a dataset with a CONTACT (issue 40 §1) has its four columns per contact, as
the command line's CSV: the normal force, friction force, penetration and slip speed. A
sphere at rest on a box carries its weight m g through the normal force (closed form);
meshes given with `geometry=` are the contacts' EXTERNAL geometry, recorded or not."""

from __future__ import annotations

from pathlib import Path

import mbfx

DATA = Path(__file__).resolve().parents[1] / "data"
G = 9.80665


def test_run_has_the_contact_columns():
    run = mbfx.load(DATA / "contact_sphere_rest.adm").run(0.5, 0.05, error=1e-5)
    for suffix in ("FN", "FF", "PEN", "SLIP"):
        assert f"CONTACT1.{suffix}" in run.columns, run.columns
    # At rest the normal force carries the sphere's weight (1 kg), and no friction is on.
    assert abs(run["CONTACT1.FN"][-1] - G) < 1e-2 * G
    assert run["CONTACT1.FF"][-1] == 0.0


def _write_box(path: Path, lo: tuple[float, float, float], hi: tuple[float, float, float]) -> None:
    """The OBJ of the box between `lo` and `hi` (12 triangles wound outward)."""
    corners = [[hi[i] if k >> i & 1 else lo[i] for i in range(3)] for k in range(8)]
    faces = [
        (0, 4, 6), (0, 6, 2), (1, 3, 7), (1, 7, 5), (0, 1, 5), (0, 5, 4),
        (2, 6, 7), (2, 7, 3), (0, 2, 3), (0, 3, 1), (4, 5, 7), (4, 7, 6),
    ]
    lines = [f"v {x} {y} {z}" for x, y, z in corners]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in faces]
    path.write_text("\n".join(lines) + "\n")


def test_geometry_gives_the_contacts_their_meshes_without_recording(tmp_path):
    # A mesh cube on a mesh slab, both EXTERNAL, their meshes given by `geometry=` with
    # nothing recorded: at rest at (m g / k)^(1/e) as a BOX would be.
    _write_box(tmp_path / "slab.obj", (-1.0, -0.2, -1.0), (1.0, 0.0, 1.0))
    _write_box(tmp_path / "cube.obj", (-0.1, -0.1, -0.1), (0.1, 0.1, 0.1))
    meshes = {11: tmp_path / "slab.obj", 21: tmp_path / "cube.obj"}
    model = mbfx.load(DATA / "contact_mesh_rest.adm")
    run = model.run(1.0, 0.01, error=1e-5, geometry=meshes, animation=False)
    want = (G / 1e5) ** (1 / 1.5)
    assert abs(run["CONTACT1.PEN"][-1] - want) < 1e-2 * want
    assert not any("without a mesh" in str(w) for w in run.warnings), run.warnings

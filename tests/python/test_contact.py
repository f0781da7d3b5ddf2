"""A run of a dataset with a CONTACT (issue 40 §1) has its four columns per contact, as
the command line's CSV: the normal force, friction force, penetration and slip speed. A
sphere at rest on a box carries its weight m g through the normal force (closed form)."""

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

"""A run never drops physics silently (issue 40 §0): statements the model leaves out
that could change the motion (a COUPLER) are listed in `Run.warnings`, as
`mbfx run` prints them in its summary; output and data statements stay quiet. The
datasets are written here: the truth is what Adams models, not what mbfx does."""

from __future__ import annotations

import mbfx
from conftest import run_cli

PENDULUM = """pendulum {title}
PART/1, GROUND
MARKER/10, PART = 1
PART/2, MASS = 1, CM = 20, IP = 1, 1, 1
MARKER/20, PART = 2, QP = 1, 0, 0
MARKER/21, PART = 2
JOINT/1, REVOLUTE, I = 21, J = 10
{extra}ACCGRAV/JGRAV = -9.81
END
"""

COUPLED = PENDULUM.format(
    title="with couplers",
    extra="COUPLER/1, JOINTS = 1, 1, SCALES = 1, -1\n"
    "COUPLER/2, JOINTS = 1, 1, SCALES = 1, -1\n",
)

QUIET = PENDULUM.format(
    title="with display and material",
    extra="PREFERENCES/CONTACT_GEOMETRY_LIBRARY = Default_library\n"
    "MATERIAL/1, NAME = steel, DENSITY = 7801, YOUNGS_MODULUS = 2.07E11, POISSONS_RATIO = 0.29\n"
    "GRAPHICS/1, CYLINDER, CM = 20, RADIUS = 0.1, LENGTH = 0.2\n",
)

LINE = "not modelled: 2 COUPLER — the results leave out their physics"


def test_run_warnings_list_the_physics_left_out_as_the_cli_prints_it(cli, tmp_path):
    run = mbfx.load(COUPLED).run(0.1)
    assert LINE in run.warnings, run.warnings
    assert f"warning: {LINE}" in run.summary
    path = tmp_path / "coupled.adm"
    path.write_text(COUPLED, encoding="utf-8")
    out = run_cli("run", str(path), "--end", "0.1", "--csv", "/dev/null", "--strict")
    assert out.returncode == 3, out.stderr
    assert f"warning: {LINE}\n" in out.stderr


def test_output_and_data_statements_leave_the_warnings_empty():
    run = mbfx.load(QUIET).run(0.1)
    assert not any("not modelled" in w for w in run.warnings), run.warnings

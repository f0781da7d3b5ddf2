"""Values set from outside a dataset: `Model.run(set=)`, `Model.with_values` and
`mbfx run --set` give the same run; bad settings are errors naming the statement; a
changed stiffness and mass move an undamped oscillator's frequency as sqrt(k/m) says."""

from __future__ import annotations

import math

import numpy as np
import pytest

import mbfx
from conftest import OSCILLATOR, ROOT
from test_model import CliRun, assert_same_run

SLIDER = ROOT / "examples" / "slider.adm"



def test_run_with_set_equals_the_cli_with_set(cli):
    m = mbfx.load(SLIDER)
    settings = {"PART/2.MASS": 5.0, "SFORCE/1.FUNCTION": "-3000*(DM(22, 11) - 0.25) - 20*VR(22, 11)"}
    run = m.run(0.5, output_step=0.01, probes={"x": "DX(22, 11)"}, set=settings)
    args = [f"--set={k}={v}" for k, v in settings.items()]
    want = CliRun(SLIDER, "--end", "0.5", "--output-step", "0.01", "--probe", "x=DX(22, 11)", *args)
    assert_same_run(run, want, "slider with --set")
    plain = m.run(0.5, output_step=0.01, probes={"x": "DX(22, 11)"})
    assert not np.array_equal(plain["x"], run["x"]), "the settings changed nothing"


def test_with_values_is_a_model_whose_run_equals_run_with_set():
    m = mbfx.load(SLIDER)
    heavier = m.with_values({"PART/2.MASS": 5})
    assert "MASS=5" in heavier.text and "MASS = 2.5" in m.text
    a = heavier.run(0.5, probes={"x": "DX(22, 11)"})
    b = m.run(0.5, probes={"x": "DX(22, 11)"}, set={"PART/2.MASS": 5})
    assert np.array_equal(a.data, b.data)
    assert heavier.check().dof == 1


@pytest.mark.parametrize("k, mass", [(100.0, 1.0), (400.0, 1.0), (100.0, 4.0), (2500.0, 0.25)])
def test_stiffness_and_mass_move_the_frequency_as_sqrt_k_over_m(k, mass):
    m = mbfx.load(OSCILLATOR)
    run = m.run(
        1.0,
        output_step=0.01,
        integrator="dopri853",
        error=1e-10,
        probes={"u": "DX(21, 11) - 1"},
        set={"SFORCE/1.FUNCTION": f"-{k!r}*(DM(21, 11) - 1)", "PART/2.MASS": mass},
    )
    exact = 0.1 * np.cos(math.sqrt(k / mass) * run.time)
    assert np.max(np.abs(run["u"] - exact)) < 1e-7


@pytest.mark.parametrize(
    "key, value, message, at",
    [
        ("SPRINGDAMPER/1.K", 2e4, "the dataset has no SPRINGDAMPER/1", "SPRINGDAMPER/1"),
        ("PART/2.COLOR", 3, "PART/2 takes no field COLOR", "COLOR"),
        ("PART/2.MASS", "heavy", "PART/2.MASS: MASS: expected a number", "heavy"),
        ("SFORCE/1.FUNCTION", "DX(22, 99)", "SFORCE/1.FUNCTION: MARKER/99 is not defined", "99"),
        ("PART.MASS", 1, "PART needs an id", "PART"),
    ],
)
def test_a_bad_setting_is_an_error_at_the_setting_naming_the_statement(cli, key, value, message, at):
    m = mbfx.load(SLIDER)
    with pytest.raises(mbfx.CheckError) as caught:
        m.with_values({key: value})
    d = caught.value.diagnostics[0]
    assert d.code == "E0611" and message in d.message, d.message
    line = f"{key}={value}"
    assert line[d.column - 1 :].startswith(at), (line, d.column)
    with pytest.raises(mbfx.RunError) as caught:
        m.run(0.5, set={key: value})
    assert caught.value.code == "E0611" and message in str(caught.value)
    want = CliRun(SLIDER, "--end", "0.5", f"--set={line}")
    assert want.code == 1 and want.first_error() == "E0611" and message in want.stderr


def test_values_must_be_numbers_or_text():
    m = mbfx.load(SLIDER)
    for bad in [True, None, [1.0]]:
        with pytest.raises(TypeError):
            m.with_values({"PART/2.MASS": bad})
    with pytest.raises(TypeError):
        m.with_values({2: 1.0})
    # numpy scalars are numbers, written exactly.
    assert "MASS=2.75" in m.with_values({"PART/2.MASS": np.float64(2.75)}).text


DESIGN_OSCILLATOR = OSCILLATOR.replace(
    "FUNCTION = -100*(DM(21, 11) - 1)", "FUNCTION = -VARVAL(1)*(DM(21, 11) - 1)\nVARIABLE/1, FUNCTION = 100"
)


def test_design_variables_rerun_the_built_simulation_with_the_sqrt_k_over_m_frequency():
    # VARIABLE/1 is a design variable: after the first run, a run that only gives it a
    # number reruns the same compiled simulation, and the frequency follows the value.
    m = mbfx.load(DESIGN_OSCILLATOR)
    args = dict(output_step=0.01, integrator="dopri853", error=1e-10, probes={"u": "DX(21, 11) - 1"})
    first = m.run(1.0, **args)
    for k in [400.0, 2500, 100.0]:
        run = m.run(1.0, set={"VARIABLE/1.FUNCTION": k}, **args)
        assert run.stats["reused"], k
        exact = 0.1 * np.cos(math.sqrt(k) * run.time)
        assert np.max(np.abs(run["u"] - exact)) < 1e-7, k
        # The same bits as the dataset written with that value and built afresh.
        written = mbfx.load(DESIGN_OSCILLATOR.replace("FUNCTION = 100", f"FUNCTION = {k!r}"))
        fresh = written.run(1.0, **args)
        assert not fresh.stats["reused"]
        assert np.array_equal(run.data, fresh.data), k
    assert np.array_equal(run.data, first.data)
    # Another field, or a value that is not a number, builds again.
    assert not m.run(1.0, set={"PART/2.MASS": 4}, **args).stats["reused"]
    assert not m.run(1.0, set={"VARIABLE/1.FUNCTION": "20**2"}, **args).stats["reused"]


@pytest.mark.parametrize(
    "key, nearest",
    [("PART/2.MASSS", "MASS"), ("MARKER/22.QPX", "QP"), ("SFORCE/1.FUNCTON", "FUNCTION")],
)
def test_a_misspelt_setting_is_an_error_naming_the_nearest_key(cli, key, nearest):
    # Issue 43 §3: MASSS was taken as MASS and QPX as QP. The CLI's --set says the same.
    m = mbfx.load(SLIDER)
    value = "0, 0, 0" if "QP" in key else "1"
    for call in (lambda: m.with_values({key: value}), lambda: m.run(0.1, set={key: value})):
        with pytest.raises(mbfx.MbfxError) as caught:
            call()
        assert f"did you mean {nearest}?" in str(caught.value), str(caught.value)
    want = CliRun(SLIDER, "--end", "0.1", f"--set={key}={value}")
    assert want.code == 1 and want.first_error() == "E0611", want.stderr
    assert f"did you mean {nearest}?" in want.stderr

"""mbfx.load and Model: loading from paths and text, the load errors, `check()` against
`mbfx check`, `evaluate` against closed forms, and `run` against `mbfx run`'s CSV bit for
bit on chrono's 19 joint datasets (two integrators, both engines), with every default and
every error path of `mbfx run`, failing runs included. The truths are closed forms and the
command line's own output, never what the Python module printed."""

from __future__ import annotations

import math
import re
from pathlib import Path
from typing import Dict, List, Optional, Sequence, Tuple

import numpy as np
import pytest

import mbfx
from conftest import ROOT, run_cli, same_bits

SLIDER = ROOT / "examples" / "slider.adm"
FOUR_BAR = ROOT / "tests" / "data" / "models" / "four_bar.adm"
FAILURES = ROOT / "tests" / "models" / "failures"
DATA = Path(__file__).resolve().parent / "data"
CHRONO = Path("corpus/adams/projectchrono__chrono/data/testing/joints/adams_models")
CHRONO_FILES = sorted(p.name for p in (ROOT.parent / "shared" / CHRONO).glob("*.adm"))

# Every chrono dataset has MARKER/201 on the moving part and MARKER/101 on ground. The
# probes come in an order that is not alphabetical, so the column order is checked too.
PROBES = {"x": "DX(201,101)", "vz": "VZ(201,101)", "psi": "AZ(201,101)"}
# 0-5 s at 0.01 s: the settings of chrono's own runs (tests/dynamics/run.rs).
END = 5.0
OUTPUT_STEP = 0.01

# A pendulum of length 2 at 30° from the downward vertical, pinned at the ground origin:
# its CM marker is at (L sin 30°, -L cos 30°, 0) = (1, -√3, 0), axes parallel to ground.
PENDULUM = """Pendulum at 30 degrees (tests/python/test_model.py)
UNITS/FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND
ACCGRAV/JGRAV = -9.80665
PART/1, GROUND
MARKER/11, PART = 1
PART/2, MASS = 1, CM = 21, IP = 0.1, 0.1, 0.1
MARKER/20, PART = 2
MARKER/21, PART = 2, QP = 1, -1.7320508075688772, 0
JOINT/1, REVOLUTE, I = 20, J = 11
END
"""


# ----------------------------------------------------------------------------- helpers


def first_difference(a: np.ndarray, b: np.ndarray, columns: Sequence[str]) -> str:
    """Where two tables first differ, for an assertion message."""
    if a.shape != b.shape:
        return f"shapes {a.shape} and {b.shape}"
    for i, j in zip(*np.nonzero(a.view(np.uint64) != b.view(np.uint64))):
        if not (math.isnan(a[i, j]) and math.isnan(b[i, j])):
            return f"row {i}, column {columns[j]}: {a[i, j]!r} and {b[i, j]!r}"
    return "no difference"


def parse_csv(text: str) -> Tuple[List[str], np.ndarray]:
    """The header and rows of `mbfx run`'s CSV (`{:?}` floats, read exactly by `float`)."""
    lines = text.splitlines()
    if not lines:
        return [], np.zeros((0, 0))
    header = lines[0].split(",")
    rows = [[float(x) for x in line.split(",")] for line in lines[1:]]
    return header, np.array(rows, dtype=np.float64).reshape(len(rows), len(header))


def probe_args(probes: Dict[str, str]) -> List[str]:
    return [arg for name, expr in probes.items() for arg in ("--probe", f"{name}={expr}")]


class CliRun:
    """`mbfx run MODEL ARGS… --csv -`: exit code, CSV header and rows, stderr."""

    def __init__(self, model: Path, *args: str) -> None:
        done = run_cli("run", str(model), "--color", "never", "--csv", "-", *args)
        self.code = done.returncode
        self.stderr = done.stderr
        self.columns, self.data = parse_csv(done.stdout)

    def first_error(self) -> Optional[str]:
        found = re.search(r"\[(E\d{4})\] Error", self.stderr)
        return found.group(1) if found else None


def assert_same_run(run: "mbfx.Run", cli: CliRun, what: str) -> None:
    assert cli.code == 0, f"{what}: mbfx run failed:\n{cli.stderr}"
    assert isinstance(run, mbfx.Run), what
    assert run.columns == cli.columns, f"{what}: columns {run.columns} and {cli.columns}"
    assert same_bits(run.data, cli.data), f"{what}: {first_difference(run.data, cli.data, cli.columns)}"


def chrono(shared: Path, name: str) -> Path:
    return shared / CHRONO / name


# ----------------------------------------------------------------------------- load


def test_load_from_a_str_path_a_pathlib_path_and_the_text():
    text = SLIDER.read_text(encoding="utf-8")
    by_str = mbfx.load(str(SLIDER))
    by_path = mbfx.load(SLIDER)
    by_text = mbfx.load(text)
    for m in (by_str, by_path, by_text):
        assert isinstance(m, mbfx.Model)
        assert m.title == text.splitlines()[0]
        assert m.parts == [1, 2]
        assert m.markers == {11: 1, 21: 2, 22: 2}
        assert m.text == text
    assert by_str.name == by_path.name == str(SLIDER)
    assert by_text.name == "dataset"
    assert repr(by_path) == f'mbfx.Model("{SLIDER}", 2 parts, 3 markers)'
    assert repr(by_text) == 'mbfx.Model("dataset", 2 parts, 3 markers)'
    four = mbfx.load(FOUR_BAR)
    assert four.parts == [1, 2, 3, 4] and len(four.markers) == 11
    assert four.markers[42] == 4 and four.markers[10] == 1


def test_a_relative_path_is_read_from_the_working_directory(monkeypatch):
    monkeypatch.chdir(ROOT)
    for source in ("examples/slider.adm", Path("examples/slider.adm")):
        m = mbfx.load(source)
        assert m.name == "examples/slider.adm" and m.markers == {11: 1, 21: 2, 22: 2}


def test_load_refuses_what_is_neither_a_path_nor_text_and_a_bad_dim():
    with pytest.raises(TypeError):
        mbfx.load(3)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="dim"):
        mbfx.load(SLIDER, dim=4)


@pytest.mark.parametrize("as_path", [False, True])
def test_a_missing_file_is_a_check_error_with_the_cli_code(cli, tmp_path, as_path):
    missing = tmp_path / "no" / "such.adm"
    with pytest.raises(mbfx.CheckError) as caught:
        mbfx.load(missing if as_path else str(missing))
    d = caught.value.diagnostics[0]
    assert d.severity == "error" and d.source == str(missing)
    assert str(missing) in d.message and str(missing) in str(caught.value)
    done = run_cli("check", "--color", "never", str(missing))
    assert done.returncode == 1
    assert re.search(r"\[(E\d{4})\] Error", done.stderr).group(1) == d.code == "E0501"


def test_a_dataset_with_errors_is_a_check_error_pointing_at_the_line(cli):
    path = DATA / "undefined_marker.adm"
    text = path.read_text(encoding="utf-8")
    # Where the error is, from the file itself: the 99 of DX(21, 99).
    line_no, line = next((n, l) for n, l in enumerate(text.splitlines(), 1) if "DX(21, 99)" in l)
    column = line.index("99") + 1
    for source, name in [(path, str(path)), (text, "dataset")]:
        with pytest.raises(mbfx.CheckError) as caught:
            mbfx.load(source)
        errors = [d for d in caught.value.diagnostics if d.severity == "error"]
        assert len(errors) == 1
        d = errors[0]
        assert (d.code, d.line, d.column, d.source) == ("E0311", line_no, column, name)
        assert text[d.span[0] : d.span[1]] == "99"
        assert "MARKER/99" in d.message
        assert line in str(caught.value) and f"{name}:{line_no}:{column}" in str(caught.value)
    # The command line says the same, at the same place.
    done = run_cli("check", "--color", "never", str(path))
    assert done.returncode == 1
    assert "[E0311] Error" in done.stderr and f"{path}:{line_no}:{column}" in done.stderr


# ----------------------------------------------------------------------------- check


def cli_check(*args: str) -> str:
    done = run_cli("check", "--color", "never", *args)
    assert done.returncode == 0, done.stderr
    return done.stdout


def test_the_slider_is_2d_with_one_dof_and_no_redundancy(cli):
    report = mbfx.load(SLIDER).check()
    assert isinstance(report, mbfx.Report)
    assert report.dimension == 2 and report.dimension_reason.startswith("2D")
    # One translational joint on one planar part: 3 coordinates, 2 equations.
    assert (report.dof, report.gruebler, report.equations) == (1, 1, 2)
    assert report.redundant == [] and report.advice == [] and report.warnings == []
    assert repr(report) == "Report(dimension=2, dof=1, redundant=0)"
    # str() is `mbfx check`'s report: its stdout but for the closing count line.
    out = cli_check(str(SLIDER))
    assert out.startswith(str(report))
    assert out[len(str(report)) :].strip() == f"{SLIDER}: 10 elements; 0 errors, 0 warnings"


def test_the_four_bar_in_3d_reports_its_redundancy_in_adams_words(cli):
    report = mbfx.load(FOUR_BAR, dim=3).check()
    out = cli_check("--dim", "3", str(FOUR_BAR))
    # The CLI's lines: "actual 1 (rank 17 of 20 equations; 3 redundant)" and
    # " -  deactivating constraint equation  Zi.Yj in model.JOINT_4" (Adams' wording).
    actual = re.search(r"actual (\d+) \(rank (\d+) of (\d+) equations; (\d+) redundant\)", out)
    dof, rank, equations, redundant = map(int, actual.groups())
    assert report.dimension == 3
    assert (report.dof, report.equations, len(report.redundant)) == (dof, equations, redundant)
    assert (dof, rank, equations, redundant) == (1, 17, 20, 3)
    # Gruebler: 6 coordinates × 3 moving parts − 20 equations.
    assert report.gruebler == 6 * 3 - 20
    cli_lines = [l.strip()[len("-  ") :] for l in out.splitlines() if l.strip().startswith("-  deactivating")]
    assert len(cli_lines) == 3
    assert report.redundant == cli_lines
    assert len(report.advice) == 1 and "JOINT_4" in report.advice[0] and "JPRIM INLINE" in report.advice[0]
    assert report.advice[0] in out
    text = str(report)
    for section in ("model:", "multibody:", "degrees of freedom:", "assembly:", "redundant constraints:"):
        assert f"\n  {section}\n" in text, section
    assert "Degree-of-freedom analysis identified redundant constraints in the model:" in text
    assert out.startswith(text)


def test_the_four_bar_built_in_2d_has_no_redundancy(cli):
    report = mbfx.load(FOUR_BAR).check()
    out = cli_check(str(FOUR_BAR))
    assert report.dimension == 2 and report.dof == 1 and report.redundant == []
    assert "actual 1 (" in out and "0 redundant" in out
    assert out.startswith(str(report))


# ----------------------------------------------------------------------------- evaluate


@pytest.mark.parametrize("engine", ["jit", "interp"])
@pytest.mark.parametrize("dim", [None, 3])
def test_evaluate_gives_closed_form_measures_at_the_assembled_configuration(engine, dim):
    m = mbfx.load(PENDULUM, dim=dim)
    root3 = math.sqrt(3.0)
    got = m.evaluate("DX(21, 11)", engine=engine)
    assert isinstance(got, float) and got == pytest.approx(1.0, rel=1e-14)
    assert m.evaluate("DY(21, 11)", engine=engine) == pytest.approx(-root3, rel=1e-14)
    assert m.evaluate("DM(21, 11)", engine=engine) == pytest.approx(2.0, rel=1e-14)
    assert m.evaluate("ATAN2(DX(21, 11), -DY(21, 11))", engine=engine) == pytest.approx(math.pi / 6, rel=1e-14)
    assert m.evaluate("VX(21, 11) + TIME", engine=engine) == 0.0  # at rest, t = 0
    vec = m.evaluate("DXYZ(21, 11)", engine=engine)
    assert isinstance(vec, np.ndarray) and vec.shape == (3,)
    assert vec == pytest.approx([1.0, -root3, 0.0], rel=1e-14, abs=1e-14)
    assert m.evaluate("UVX(21)", engine=engine) == pytest.approx([1.0, 0.0, 0.0], abs=1e-15)
    assert m.evaluate("[1, 2, PI]", engine=engine) == pytest.approx([1.0, 2.0, math.pi], rel=1e-16)


def test_evaluate_agrees_with_the_cli_on_a_dataset(cli):
    m = mbfx.load(SLIDER)
    for text in ("DX(22, 11)", "DM(22, 11) - 0.25", "VARVAL(1)", "DXYZ(21, 11)"):
        done = run_cli("eval", "--color", "never", "--model", str(SLIDER), "--", text)
        assert done.returncode == 0, done.stderr
        printed = done.stdout.strip()
        want = [float(x) for x in printed.strip("[]").split(",")]
        got = np.atleast_1d(m.evaluate(text))
        assert same_bits(got, np.array(want)), (text, printed, got)


def test_evaluate_refuses_a_bad_expression_with_a_check_error():
    m = mbfx.load(PENDULUM)
    with pytest.raises(mbfx.CheckError) as caught:
        m.evaluate("DX(21, 99)")
    d = caught.value.diagnostics[0]
    assert (d.code, d.line, d.column) == ("E0311", 1, len("DX(21, ") + 1)
    with pytest.raises(mbfx.CheckError) as caught:
        m.evaluate("SIN(DX(21, 11)")
    assert caught.value.diagnostics[0].code.startswith("E02")
    with pytest.raises(mbfx.CheckError) as caught:
        m.evaluate("FOO(1)")
    assert caught.value.diagnostics[0].code == "E0301"
    with pytest.raises(ValueError, match="engine"):
        m.evaluate("1", engine="gpu")


# ----------------------------------------------------------------------------- run


@pytest.mark.parametrize("name", CHRONO_FILES)
def test_chrono_runs_equal_the_cli_csv_with_the_default_integrator(cli, shared, name):
    path = chrono(shared, name)
    run = mbfx.load(path).run(END, output_step=OUTPUT_STEP, probes=PROBES)
    want = CliRun(path, "--end", repr(END), "--output-step", repr(OUTPUT_STEP), *probe_args(PROBES))
    assert_same_run(run, want, name)
    assert run.columns[:4] == ["time", "x", "vz", "psi"]
    assert len(run) == round(END / OUTPUT_STEP) + 1 and run.time[-1] == END
    assert run.integrator == "gstiff" and run.stats["steps"] > 0


@pytest.mark.parametrize("name", CHRONO_FILES)
def test_chrono_runs_equal_the_cli_csv_with_hht(cli, shared, name):
    path = chrono(shared, name)
    run = mbfx.load(path).run(END, output_step=OUTPUT_STEP, integrator="hht", probes=PROBES)
    want = CliRun(
        path, "--end", repr(END), "--output-step", repr(OUTPUT_STEP), "--integrator", "hht", *probe_args(PROBES)
    )
    assert_same_run(run, want, name)
    assert run.integrator == "hht"


@pytest.mark.parametrize(
    "name, integrator",
    [
        ("test_Revolute_Case01.adm", "gstiff"),
        ("test_Spherical_Case02.adm", "hht"),
        ("test_Universal_Case03.adm", "galpha"),
        ("test_RotSpring_Case01.adm", "gstiff"),
    ],
)
def test_chrono_runs_with_the_interpreter_equal_the_cli_and_the_jit(cli, shared, name, integrator):
    path = chrono(shared, name)
    m = mbfx.load(path)
    run = m.run(END, output_step=OUTPUT_STEP, integrator=integrator, probes=PROBES, engine="interp")
    want = CliRun(
        path,
        "--end",
        repr(END),
        "--output-step",
        repr(OUTPUT_STEP),
        "--integrator",
        integrator,
        "--engine",
        "interp",
        *probe_args(PROBES),
    )
    assert_same_run(run, want, name)
    # The invariant the engines share: the same bits.
    jit = m.run(END, output_step=OUTPUT_STEP, integrator=integrator, probes=PROBES)
    assert same_bits(run.data, jit.data)


def test_every_default_matches_mbfx_run(cli, shared):
    path = chrono(shared, "test_Revolute_Case01.adm")
    m = mbfx.load(path)
    run = m.run(1.0)
    # No options: END/100 output step, so 101 rows; the dataset has no INTEGRATOR: gstiff.
    assert_same_run(run, CliRun(path, "--end", "1"), "defaults")
    assert len(run) == 101 and run.time[0] == 0.0 and run.time[-1] == 1.0
    assert run.integrator == "gstiff"
    assert np.allclose(np.diff(run.time), 0.01, rtol=1e-12, atol=0)
    # The documented defaults, written out, give the same bits: ERROR 1e-3, HMAX the
    # output step, HINIT HMAX/20, HMIN 1e-6·HMAX, KMAX 6, I3, error per step, the JIT.
    h = 1.0 / 100
    explicit = m.run(
        1.0,
        output_step=h,
        integrator="gstiff",
        error=1e-3,
        hmax=h,
        hinit=h / 20,
        hmin=1e-6 * h,
        kmax=6,
        formulation="i3",
        error_per="step",
        engine="jit",
    )
    assert same_bits(explicit.data, run.data)
    # HHT's ALPHA is -0.3 unless given; generalized-α's ρ∞ is 0.9.
    hht = m.run(1.0, integrator="hht")
    assert same_bits(m.run(1.0, integrator="hht", alpha=-0.3).data, hht.data)
    assert_same_run(hht, CliRun(path, "--end", "1", "--integrator", "hht"), "hht defaults")
    galpha = m.run(1.0, integrator="galpha")
    assert same_bits(m.run(1.0, integrator="galpha", rho_inf=0.9).data, galpha.data)
    # Names are case-insensitive, as the dataset's are.
    assert same_bits(m.run(1.0, integrator="HHT").data, hht.data)


def test_the_other_options_reach_the_run_as_on_the_command_line(cli, shared):
    path = chrono(shared, "test_Prismatic_Case02.adm")
    m = mbfx.load(path)
    cases = [
        (dict(integrator="wstiff", error=1e-5, formulation="si2"), ["--integrator", "wstiff", "--error", "1e-5", "--formulation", "si2"]),
        (dict(hmax=2e-3, hinit=1e-4, hmin=1e-9, kmax=3), ["--hmax", "0.002", "--hinit", "0.0001", "--hmin", "1e-9", "--kmax", "3"]),
        (dict(fixed_step=1e-3), ["--fixed-step", "0.001"]),
        (dict(integrator="hht", alpha=-0.1), ["--integrator", "hht", "--alpha=-0.1"]),
        (dict(integrator="galpha", rho_inf=0.5), ["--integrator", "galpha", "--rho-inf", "0.5"]),
        (dict(integrator="newmark"), ["--integrator", "newmark"]),
        (dict(integrator="dopri853", error=1e-8), ["--integrator", "dopri853", "--error", "1e-8"]),
        (dict(integrator="dopri853", cartesian=True), ["--integrator", "dopri853", "--cartesian"]),
        (dict(error_per="run"), ["--error-per", "run"]),
        (dict(integrator="dopri853", interpolate=True), ["--integrator", "dopri853", "--interpolate"]),
        (dict(interpolate=True), ["--interpolate"]),
    ]
    for kwargs, args in cases:
        run = m.run(0.5, output_step=0.05, probes={"x": "DX(201,101)"}, **kwargs)
        want = CliRun(path, "--end", "0.5", "--output-step", "0.05", "--probe", "x=DX(201,101)", *args)
        assert_same_run(run, want, str(kwargs))


def test_estimate_error_keeps_the_rows_and_gives_the_clis_estimate_and_warning(cli):
    m = mbfx.load(SLIDER)
    plain = m.run(2.0, output_step=0.01)
    run = m.run(2.0, output_step=0.01, estimate_error=True)
    want = CliRun(SLIDER, "--end", "2", "--output-step", "0.01", "--estimate-error")
    assert_same_run(run, want, "estimate_error=True")
    assert same_bits(run.data, plain.data), "the second run changes no row"
    line = next(l for l in want.stderr.splitlines() if l.startswith("error estimate: "))
    assert run.stats["error_estimate"] == pytest.approx(float(line.split("×")[0].split()[-1]), rel=1e-2)
    assert run.stats["estimate_cpu_seconds"] > 0
    assert "error_estimate" not in plain.stats
    # The estimate judges the run instead of the local errors' sum.
    assert any(w.startswith("the answer's error is estimated at") for w in run.warnings), run.warnings
    assert not any("add up to" in w for w in run.warnings), run.warnings
    assert any("add up to" in w for w in plain.warnings), plain.warnings


def test_the_datasets_integrator_is_the_default(cli, tmp_path):
    text = SLIDER.read_text(encoding="utf-8").replace("\nEND", "\nINTEGRATOR/\n, HHT, ERROR = 1E-4\nEND")
    path = tmp_path / "slider_hht.adm"
    path.write_text(text, encoding="utf-8")
    m = mbfx.load(path)
    run = m.run(0.5)
    assert run.integrator == "hht"
    assert_same_run(run, CliRun(path, "--end", "0.5"), "INTEGRATOR/ HHT")
    assert same_bits(m.run(0.5, integrator="hht", error=1e-4).data, run.data)


def test_bad_arguments_fail_as_on_the_command_line(cli):
    m = mbfx.load(SLIDER)
    # Values the command line refuses (E0503) are a ValueError in Python's words: the
    # keyword and its value, never the option (issue 43 §3).
    for kwargs, args, words in [
        (dict(end=-1.0), ["--end=-1"], "end=-1 must be a positive time"),
        (dict(end=0.0), ["--end", "0"], "end=0 must be a positive time"),
        (dict(), [], "end is required"),  # no end: a dataset needs one
        (dict(end=1.0, integrator="hht", alpha=-0.5), ["--end", "1", "--integrator", "hht", "--alpha=-0.5"],
         "alpha=-0.5 must lie in [-1/3, 0]"),
        (dict(end=1.0, integrator="hht", alpha=0.1), ["--end", "1", "--integrator", "hht", "--alpha", "0.1"],
         "alpha=0.1 must lie"),
        (dict(end=1.0, integrator="galpha", rho_inf=1.5), ["--end", "1", "--integrator", "galpha", "--rho-inf", "1.5"],
         "rho_inf=1.5 must lie in [0, 1]"),
        (dict(end=1.0, output_step=-0.1), ["--end", "1", "--output-step=-0.1"], "output_step=-0.1 must be a positive"),
        (dict(end=1.0, error=-1.0), ["--end", "1", "--error=-1"], "error=-1 must be a positive"),
    ]:
        with pytest.raises(ValueError) as caught:
            m.run(**kwargs)
        message = str(caught.value)
        assert message.startswith(words), (kwargs, message)
        assert "--" not in message and "command line" not in message, message
        want = CliRun(SLIDER, *args)
        assert want.code == 1 and want.first_error() == "E0503", (args, want.stderr)
    # KMAX out of 1..6: the command line's parser refuses it.
    with pytest.raises(ValueError, match=r"^kmax=9 must be an order from 1 to 6"):
        m.run(1.0, kmax=9)
    want = CliRun(SLIDER, "--end", "1", "--kmax", "9")
    assert want.code != 0 and "1..=6" in want.stderr
    # A value of the wrong type names its argument.
    with pytest.raises(TypeError, match=r"^end must be a number \(a float or an int\), not str '2'"):
        m.run("2")
    with pytest.raises(TypeError, match="^hmax must be a number"):
        m.run(1.0, hmax=[1])
    with pytest.raises(ValueError, match=r"^end=-1 must be a positive time"):
        m.linearize(end=-1)
    # Names that are not options' values are Python's ValueError.
    with pytest.raises(ValueError, match="integrator"):
        m.run(1.0, integrator="rk4")
    with pytest.raises(ValueError, match="engine"):
        m.run(1.0, engine="gpu")
    with pytest.raises(ValueError, match="formulation"):
        m.run(1.0, formulation="i2")
    with pytest.raises(ValueError, match="error_per"):
        m.run(1.0, error_per="ever")
    with pytest.raises(TypeError):
        m.run(1.0, probes={"x": 3})  # type: ignore[dict-item]


@pytest.mark.parametrize(
    "expr, code, column",
    [("SIN(DX(22, 11)", "E0202", len("SIN(DX(22, 11)") + 1), ("DX(22, 99)", "E0311", len("DX(22, ") + 1)],
)
def test_a_probe_that_does_not_compile_is_a_run_error_pointing_into_it(cli, expr, code, column):
    m = mbfx.load(SLIDER)
    with pytest.raises(mbfx.RunError) as caught:
        m.run(1.0, probes={"ok": "DX(22, 11)", "bad": expr})
    e = caught.value
    assert e.code == code and e.probe == "bad" and e.run is None
    d = e.diagnostics[0]
    assert (d.code, d.line, d.column) == (code, 1, column)
    assert d.source == "--probe bad" and expr in str(e)
    want = CliRun(SLIDER, "--end", "1", "--probe", "ok=DX(22, 11)", "--probe", f"bad={expr}")
    assert want.code == 1 and want.first_error() == code and want.data.size == 0


# Each dataset of tests/models/failures fails at a known time (its header says why); the
# settings are tests/dynamics/failures.rs's: 0-1 s at 0.01 s in 3D, some in fixed steps.
FAILING = [
    ("nan_in_force.adm", 1e-3, "E0803", "SFORCE/1", (0.5, 0.51)),
    ("newton_divergence.adm", 1e-3, "E0802", "GCON/1", (0.45, 0.56)),
    ("singular_matrix.adm", 1e-3, "E0802", "GCON/1", (0.5, 0.51)),
    ("step_below_hmin.adm", None, "E0802", "PART/2", (0.49, 0.51)),
    ("dropped_row_violated.adm", None, "E0702", None, (0.5, 0.6)),
]


@pytest.mark.parametrize("name, fixed_step, code, element, window", FAILING)
def test_a_failing_run_raises_run_error_with_the_rows_the_cli_writes(cli, name, fixed_step, code, element, window):
    path = FAILURES / name
    probes = {"x": "DX(201,101)"}
    with pytest.raises(mbfx.RunError) as caught:
        mbfx.load(path, dim=3).run(1.0, output_step=0.01, probes=probes, fixed_step=fixed_step)
    e = caught.value
    args = ["--end", "1", "--output-step", "0.01", "--dim", "3", *probe_args(probes)]
    if fixed_step is not None:
        args += ["--fixed-step", repr(fixed_step)]
    want = CliRun(path, *args)
    assert want.code == 1 and want.first_error() == code == e.code, want.stderr
    assert e.diagnostics[0].code == code and e.diagnostics[0].source == str(path)
    assert window[0] <= e.time <= window[1], e.time
    if element is not None:
        assert e.element == element
    else:
        assert e.element in ("GCON/1", "GCON/2")  # which equal row is dropped is the pivoting's
    assert e.element in e.cause and e.cause in str(e)
    # The diagnostic is the command line's, word for word.
    assert str(e) in want.stderr
    # The rows before the failure, bit for bit as the CLI's CSV, all before the failure.
    assert isinstance(e.run, mbfx.Run)
    assert e.run.columns == want.columns == ["time", "x"]
    assert len(e.run) > 0 and same_bits(e.run.data, want.data), first_difference(e.run.data, want.data, want.columns)
    assert e.run.time[-1] <= e.time
    assert e.run.stats["steps"] > 0 and e.run.summary


def test_nan_in_a_force_says_when_and_why(cli):
    with pytest.raises(mbfx.RunError) as caught:
        mbfx.load(FAILURES / "nan_in_force.adm", dim=3).run(1.0, output_step=0.01, fixed_step=1e-3)
    e = caught.value
    # The force is 0 until t = 0.5, then SQRT of a negative number: the first fixed step
    # past 0.5 (of 1e-3) is where it fails; the frame points at the SFORCE's statement.
    assert e.time == pytest.approx(0.501, abs=1e-12)
    assert e.element == "SFORCE/1" and "NaN" in e.cause
    text = (FAILURES / "nan_in_force.adm").read_text(encoding="utf-8").splitlines()
    assert text[e.diagnostics[0].line - 1].startswith("SFORCE/1")
    assert len(e.run) == 51 and e.run.time[-1] == 0.5


def test_a_force_that_cannot_be_evaluated_fails_before_any_row(cli):
    path = FAILURES / "user_variable.adm"
    with pytest.raises(mbfx.RunError) as caught:
        mbfx.load(path).run(1.0)
    e = caught.value
    want = CliRun(path, "--end", "1")
    assert want.code == 1 and want.first_error() == e.code == "E0801"
    assert e.element == "SFORCE/1" and e.time is None
    assert want.data.size == 0 and (e.run is None or len(e.run) == 0)


# Undamped: x = 1 + 0.2 cos 10t (the spring's free length 1, released at 1.2).
OSCILLATOR = """oscillator
PART/1, GROUND
MARKER/10, PART = 1
MARKER/11, PART = 1, REULER = 90D, 90D, 0
PART/2, MASS = 1, CM = 20, IP = 1, 1, 1, QG = 1.2, 0, 0
MARKER/20, PART = 2
MARKER/21, PART = 2, REULER = 90D, 90D, 0
JOINT/1, TRANSLATIONAL, I = 21, J = 11
SPRINGDAMPER/1, TRANSLATION, I = 20, J = 10, K = 100, C = 0, LENGTH = 1
END
"""


def test_the_error_carried_through_the_steps_follows_the_closed_form(tmp_path):
    path = tmp_path / "oscillator.adm"
    path.write_text(OSCILLATOR)
    m = mbfx.load(str(path))
    error = 1e-5
    run = m.run(5.0, output_step=0.01, integrator="gstiff", error=error,
                probes={"x": "DX(20, 10)"}, estimate_error="steps")
    true = np.max(np.abs(run["x"] - (1 + 0.2 * np.cos(10 * run.time)))) / error
    assert run.error_estimate is not None
    assert 1 / 3 < run.error_estimate / true < 3, (run.error_estimate, true)
    assert 0 < run.stats["error_estimate_time"] <= 5.0
    assert "estimated error" in run.summary
    assert m.run(1.0).error_estimate is None
    with pytest.raises(ValueError, match="estimate_error"):
        m.run(1.0, estimate_error="twice")

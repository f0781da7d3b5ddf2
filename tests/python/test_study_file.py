"""Study files (TOML): `python -m mbfx.study FILE` and `mbfx study FILE` run the study
`mbfx.study.run` runs with the same arguments, bit for bit, and its responses agree with
the oscillator's closed form u(t) = 0.1 cos(sqrt(k/m) t); every mistake in a file is one
error naming its line and column, with exit code 1 and nothing run."""

from __future__ import annotations

import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import mbfx
from mbfx import study
from mbfx.study import __main__ as study_main
from mbfx.study import config
from conftest import OSCILLATOR, ROOT, cli_binary, missing_docstrings

STUDY = """model = "oscillator.adm"
end = 0.5
design = "full"
out = "results.csv"

[factors]
k = {{ levels = [100, 400] }}
"PART/2.MASS" = {{ levels = [1.0, 4.0] }}

[templates]
"SFORCE/1.FUNCTION" = "-{{k}}*(DM(21, 11) - 1)"

[probes]
u = "DX(21, 11) - 1"

[responses]
u_end = {{ final = "u" }}
u_min_late = {{ min = "u", after = 0.25 }}
t_zero = {{ first_crossing = ["u", 0.0] }}

[run]
integrator = "dopri853"
error = 1e-10
output_step = 0.01
"""


@pytest.fixture()
def study_dir(tmp_path: Path) -> Path:
    (tmp_path / "oscillator.adm").write_text(OSCILLATOR)
    (tmp_path / "study.toml").write_text(STUDY.format())
    return tmp_path


def test_a_study_file_runs_the_study_of_its_call(study_dir, client, monkeypatch, capsys):
    monkeypatch.chdir(study_dir)  # out= is relative to the working folder
    code = study_main.main(["study.toml", "--scheduler", client.scheduler.address])
    assert code == 0, capsys.readouterr().err
    printed = capsys.readouterr().out
    assert "4 variants: 4 ok, 0 failed" in printed and "results.csv" in printed
    table = pd.read_csv(study_dir / "results.csv").sort_values("variant")
    direct = study.run(
        mbfx.load(OSCILLATOR),
        factors={"k": [100, 400], "PART/2.MASS": [1.0, 4.0]},
        templates={"SFORCE/1.FUNCTION": "-{k}*(DM(21, 11) - 1)"},
        probes={"u": "DX(21, 11) - 1"},
        responses={"u_end": study.final("u"), "u_min_late": study.min("u", after=0.25), "t_zero": study.first_crossing("u", 0.0)},
        end=0.5, run_args={"integrator": "dopri853", "error": 1e-10, "output_step": 0.01}, client=client,
    ).table
    for column in ("k", "PART/2.MASS", "u_end", "u_min_late", "t_zero"):
        assert np.array_equal(table[column].to_numpy(), direct[column].to_numpy()), column
    # The closed form: u(0.5), the first zero at a quarter period, and the least u from
    # t = 0.25 on (-0.1 once half a period has passed by then, else u(0.5) or u(0.25)).
    for row in table.itertuples():
        w = math.sqrt(row.k / getattr(row, "_3"))
        u = lambda t: 0.1 * math.cos(w * t)  # noqa: E731
        assert row.u_end == pytest.approx(u(0.5), abs=1e-8)
        assert row.t_zero == pytest.approx(math.pi / (2 * w), abs=2e-4)  # linear between rows
        ts = np.arange(25, 51) * 0.01
        assert row.u_min_late == pytest.approx(min(u(t) for t in ts), abs=1e-8)


def test_mbfx_study_is_the_same_command(study_dir, client):
    env = dict(os.environ, MBFX_PYTHON=sys.executable)
    done = subprocess.run(
        [str(cli_binary()), "study", "study.toml", "--scheduler", client.scheduler.address, "--out", "cli.csv"],
        cwd=study_dir, env=env, capture_output=True, text=True, timeout=300,
    )
    assert done.returncode == 0, done.stderr
    assert "4 variants: 4 ok, 0 failed" in done.stdout
    assert len(pd.read_csv(study_dir / "cli.csv")) == 4


def test_mbfx_study_without_the_module_says_how_to_install_it(tmp_path):
    env = dict(os.environ, MBFX_PYTHON=str(tmp_path / "no-python"))
    done = subprocess.run([str(cli_binary()), "study", "x.toml"], env=env, capture_output=True, text=True, timeout=60)
    assert done.returncode == 1
    assert "cannot start" in done.stderr and "pip install '.[study,plot]'" in done.stderr


# (the file's text after the model line, the line and column of the error, its words)
MISTAKES = [
    ("end = = 1\n", 2, 7, "not TOML"),
    ("end = 1\nsteps = 3\n", 3, 1, "unknown key 'steps'"),
    ("", None, 0, "'end' is missing"),
    ('end = "long"\n', 2, 1, "end is a number"),
    ("end = 1\n[factors]\nk = 3\n", 4, 1, "factor 'k': a factor is"),
    ("end = 1\n[factors]\n  k = { range = [2, 1] }\n", 4, 3, "finite lo < hi"),
    ("end = 1\n[factors]\nk = { log = [0, 1] }\n", 4, 1, "lo > 0"),
    ('end = 1\n[factors]\nk = { levels = [1] }\n[responses]\npeak = { max = "u", at = 1 }\n', 6, 1, "a response is"),
    ('end = 1\n[factors]\nk = { levels = [1] }\n[responses]\npeak = { final = "u", after = 1 }\n', 6, 1, "a response is"),
    ('end = 1\n[factors]\nk = { levels = [1] }\n[run]\nsteps = 3\n', 6, 1, "not an argument of Model.run"),
    ('end = 1\ndesign = "table.csv"\n', 3, 1, "cannot read the table"),
]


@pytest.mark.parametrize("rest, line, column, words", MISTAKES)
def test_each_mistake_in_a_study_file_names_its_place(study_dir, rest, line, column, words, capsys):
    path = study_dir / "bad.toml"
    path.write_text('model = "oscillator.adm"\n' + rest)
    with pytest.raises(config.StudyFileError) as caught:
        config.read(path)
    e = caught.value
    assert words in e.reason and e.line == line
    if line is not None:
        assert e.column == column and str(e).startswith(f"{path}:{line}:{column}: ")
        assert str(e).endswith("\n     | " + " " * (column - 1) + "^")
    assert study_main.main([str(path)]) == 1
    assert words in capsys.readouterr().err


def test_a_missing_model_and_a_missing_file_are_errors(study_dir):
    with pytest.raises(config.StudyFileError, match="no file"):
        (study_dir / "m.toml").write_text('model = "none.adm"\nend = 1\n')
        config.read(study_dir / "m.toml")
    with pytest.raises(config.StudyFileError, match="cannot read it"):
        config.read(study_dir / "absent.toml")


def test_a_design_table_from_csv_and_its_factors(study_dir):
    (study_dir / "table.csv").write_text("k,PART/2.MASS\n100,1.0\n400,2.5\n")
    (study_dir / "t.toml").write_text('model = "oscillator.adm"\nend = 0.1\ndesign = "table.csv"\n')
    read = config.read(study_dir / "t.toml")
    assert read.design == [{"k": 100, "PART/2.MASS": 1.0}, {"k": 400, "PART/2.MASS": 2.5}]
    assert read.run_kwargs()["factors"] is None  # taken from the table's columns


def test_the_bundled_study_file_reads():
    read = config.read(ROOT / "examples" / "study" / "impact_block.toml")
    assert read.model.is_file() and read.design == "lhs" and read.n == 1000
    assert set(read.responses) == {"peak_force", "rebound"}


def test_the_study_file_modules_document_every_public_name():
    assert missing_docstrings(config) == []


def test_retry_failed_runs_the_failed_rows_of_the_results_file_again(study_dir, client, monkeypatch, capsys):
    # A results file whose variant 1 failed earlier (written here as a failed row): a
    # resumed study keeps it, `--retry-failed` runs it again and replaces its row.
    monkeypatch.chdir(study_dir)
    scheduler = ["--scheduler", client.scheduler.address]
    assert study_main.main(["study.toml", *scheduler]) == 0, capsys.readouterr().err
    path = study_dir / "results.csv"
    table = pd.read_csv(path)
    good = table.loc[table["variant"] == 1, "u_end"].item()
    table["message"] = table["message"].astype(object)
    failed = table["variant"] == 1
    table.loc[failed, "u_end"] = math.nan
    table.loc[failed, "status"] = "failed"
    table.loc[failed, "message"] = "an earlier failure"
    table.to_csv(path, index=False)
    assert study_main.main(["study.toml", *scheduler]) == 0
    assert "4 variants: 3 ok, 1 failed" in capsys.readouterr().out
    assert study_main.main(["study.toml", *scheduler, "--retry-failed"]) == 0
    assert "4 variants: 4 ok, 0 failed" in capsys.readouterr().out
    again = pd.read_csv(path)
    assert sorted(again["variant"]) == [0, 1, 2, 3] and (again["status"] == "ok").all()
    assert again.loc[again["variant"] == 1, "u_end"].item() == good

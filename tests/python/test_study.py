"""mbfx.study: designs of a model's variants run on Dask. Designs have their sizes and
values in range; every response of an undamped oscillator agrees with its closed form
u(t) = 0.1 cos(sqrt(k/m) t); failed variants are rows with their messages; a resumed
study runs only what its results file lacks; a quadratic surface is exact on a quadratic
response; a study survives a killed worker with every variant exactly once."""

from __future__ import annotations

import itertools
import math
import os
import signal
import threading
import time
from typing import Dict, List

import numpy as np
import pandas as pd
import psutil
import pytest

import mbfx
from mbfx import study
from mbfx.study.designs import factors_of_table
from conftest import OSCILLATOR, missing_docstrings

# u = DX - 1 = 0.1 cos(w t), w = sqrt(k/m), to ~1e-9 with these settings.
PROBES = {"u": "DX(21, 11) - 1"}
RUN_ARGS = {"integrator": "dopri853", "error": 1e-10, "output_step": 0.01}
STIFFNESS = {"SFORCE/1.FUNCTION": "-{k}*(DM(21, 11) - 1)"}
STEP = RUN_ARGS["output_step"]


def closed_form(t, k, m):
    return 0.1 * np.cos(np.sqrt(k / m) * t)


def grid(end: float) -> np.ndarray:
    return np.arange(round(end / STEP) + 1) * STEP


@pytest.fixture(scope="session")
def model():
    return mbfx.load(OSCILLATOR)


def oscillator_study(model, client, **kwargs) -> study.Study:
    args = dict(end=0.5, probes=PROBES, templates=STIFFNESS, run_args=RUN_ARGS, client=client)
    args.update(kwargs)
    return study.run(model, **args)


# ------------------------------------------------------------------- factors, designs


def test_setting_keys_are_told_from_template_names():
    for key in ("PART/2.MASS", "SFORCE/1.FUNCTION", "ACCGRAV.JGRAV", "acc.igrav", "IC.ERROR"):
        assert study.is_setting_key(key), key
    for name in ("k", "c_1", "mass"):
        assert not study.is_setting_key(name), name


def test_settings_set_keys_and_fill_templates_exactly():
    got = study.settings(
        {"PART/2.MASS": 2, "k": 0.1 + 0.2, "c": np.int64(10), "law": "STEP(TIME, 0, 0, 1, 1)"},
        {"SFORCE/1.FUNCTION": "-{k}*(DM(21, 11) - 1) - {c}*VR(21, 11)", "SFORCE/2.FUNCTION": "{law}*{k:.1f}"},
    )
    assert got == {
        "PART/2.MASS": 2,
        "SFORCE/1.FUNCTION": "-0.30000000000000004*(DM(21, 11) - 1) - 10*VR(21, 11)",
        "SFORCE/2.FUNCTION": "STEP(TIME, 0, 0, 1, 1)*0.3",
    }


@pytest.mark.parametrize(
    "factors, templates, fragment",
    [
        ({"k": (1, 2)}, {}, "neither a setting key nor used"),
        ({"PART/2.MASS": (1, 2)}, {"SFORCE/1.FUNCTION": "{k}"}, "not a template factor"),
        ({"a.b": (1, 2)}, {}, "neither a setting key"),
        ({"PART/2.MASS": (2, 1)}, {}, "lo < hi"),
    ],
)
def test_factors_that_do_not_fit_are_refused_before_any_run(model, factors, templates, fragment):
    with pytest.raises(ValueError, match=fragment):
        study.run(model, factors, {}, end=0.1, templates=templates)


def test_a_response_of_a_missing_probe_or_a_study_setting_in_run_args_is_refused(model):
    with pytest.raises(ValueError, match="not a probe"):
        study.run(model, {"PART/2.MASS": (1, 2)}, {"x": study.max("nope")}, end=0.1, probes=PROBES)
    with pytest.raises(ValueError, match="run_args"):
        study.run(model, {"PART/2.MASS": (1, 2)}, {}, end=0.1, run_args={"end": 2})


def test_full_factorial_is_every_combination():
    factors = {"PART/2.MASS": study.Range(0.5, 2.0), "c": study.Levels((10, 50, 100)), "k": study.log(1e4, 1e6)}
    plan = study.design(factors, "full", levels={"PART/2.MASS": 4, "k": 3})
    masses, dampings, stiffnesses = [0.5, 1.0, 1.5, 2.0], [10, 50, 100], [1e4, 1e5, 1e6]
    assert len(plan) == 4 * 3 * 3 and list(plan.columns) == list(factors)
    want = sorted(itertools.product(masses, dampings, stiffnesses))
    got = sorted(map(tuple, plan.to_numpy().tolist()))
    for g, w in zip(got, want):
        assert g == pytest.approx(w, rel=1e-12)


def test_latin_hypercube_puts_one_point_in_each_stratum_of_each_factor():
    factors = {"a": study.Range(2.0, 5.0), "k": study.log(1e2, 1e4), "c": study.Range(-1.0, 1.0)}
    n = 20
    plan = study.design(factors, "lhs", n=n, seed=7)
    assert len(plan) == n
    units = {
        "a": (plan["a"] - 2.0) / 3.0,
        "k": (np.log10(plan["k"]) - 2.0) / 2.0,
        "c": (plan["c"] + 1.0) / 2.0,
    }
    for name, u in units.items():
        assert ((u >= 0) & (u <= 1)).all(), name
        assert sorted(np.floor(u * n).astype(int)) == list(range(n)), name
    assert plan.equals(study.design(factors, "lhs", n=n, seed=7))
    assert not plan.equals(study.design(factors, "lhs", n=n, seed=8))


def test_sobol_points_lie_in_their_ranges_and_levels():
    plan = study.design({"a": (2.0, 5.0), "c": [10, 50, 100]}, "sobol", n=16, seed=1)
    assert len(plan) == 16
    assert plan["a"].between(2.0, 5.0).all() and plan["a"].nunique() == 16
    assert set(plan["c"]) == {10, 50, 100}


def test_a_table_is_the_design_and_gives_the_factors():
    rows = [{"PART/2.MASS": 1.0, "k": 100}, {"PART/2.MASS": 2.0, "k": 400}, {"PART/2.MASS": 4.0, "k": 400}]
    factors = factors_of_table(rows)
    assert factors == {"PART/2.MASS": study.Range(1.0, 4.0), "k": study.Range(100.0, 400.0)}
    assert study.design(factors, rows).to_dict("records") == rows
    with pytest.raises(ValueError, match="missing"):
        study.design(factors, [{"PART/2.MASS": 1.0}])


# ------------------------------------------------------------------------- responses


def synthetic_run(time_: np.ndarray, x: np.ndarray) -> mbfx.Run:
    return mbfx.Run(["time", "x"], np.column_stack([time_, x]), {"steps": 1})


def test_reductions_of_a_known_signal():
    t = np.linspace(0.0, 2.0, 21)  # rows 0.1 apart
    run = synthetic_run(t, 3.0 - 4.0 * t + t**2)  # the parabola (t - 2)^2 - 1: min -1 at t = 2
    assert study.max("x")(run) == 3.0 and study.min("x")(run) == -1.0 and study.final("x")(run) == -1.0
    # From t = 1 on: the parabola falls to -1 at t = 2, so its largest value is at t = 1.
    assert study.max("x", after=1.0)(run) == 3.0 - 4.0 * t[10] + t[10] ** 2
    assert study.min("x", after=2.0)(run) == -1.0 and math.isnan(study.max("x", after=2.5)(run))
    assert study.at(0.5, "x")(run) == pytest.approx(3.0 - 2.0 + 0.25, abs=1e-15)  # a row
    # Between rows 0.5 and 0.6 the line through 1.25 and 0.96, at a quarter of the way.
    assert study.at(0.525, "x")(run) == pytest.approx(1.25 + 0.25 * (0.96 - 1.25), abs=1e-14)
    assert math.isnan(study.at(2.5, "x")(run)) and math.isnan(study.at(-0.1, "x")(run))
    # x = 0 at t = 1 (a row) and nowhere before: the first crossing of 0 is exactly there.
    assert study.first_crossing("x", 0.0)(run) == pytest.approx(1.0, abs=1e-14)
    # x = 2 between rows 0.2 (x = 2.24) and 0.3 (x = 1.89): linear between them.
    assert study.first_crossing("x", 2.0)(run) == pytest.approx(0.2 + 0.1 * 0.24 / 0.35, abs=1e-14)
    assert math.isnan(study.first_crossing("x", 5.0)(run))


@pytest.fixture(scope="module")
def oscillator(model, client) -> study.Study:
    """Mass 0.5..2 (3 levels) times k in {100, 400, 900}; each response of u."""
    return oscillator_study(
        model,
        client,
        factors={"PART/2.MASS": (0.5, 2.0), "k": [100, 400, 900]},
        responses={
            "u_end": study.final("u"),
            "u_row": study.at(0.25, "u"),
            "u_between": study.at(0.255, "u"),
            "u_max": study.max("u"),
            "u_min": study.min("u"),
            "t_zero": study.first_crossing("u", 0.0),
            "energy": lambda run: float(np.max(run["u"] ** 2)),
        },
    )


def test_every_response_agrees_with_the_closed_form(oscillator):
    table = oscillator.table
    assert list(table["variant"]) == list(range(9)) and (table["status"] == "ok").all()
    assert (table["message"] == "").all() and (table["steps"] > 0).all() and (table["seconds"] > 0).all()
    combos = list(itertools.product([0.5, 1.25, 2.0], [100, 400, 900]))
    assert list(zip(table["PART/2.MASS"], table["k"])) == combos
    t = grid(0.5)
    for (m, k), (_, row) in zip(combos, table.iterrows()):
        u = closed_form(t, k, m)
        w = math.sqrt(k / m)
        assert row["u_end"] == pytest.approx(closed_form(0.5, k, m), abs=1e-7)
        assert row["u_row"] == pytest.approx(closed_form(0.25, k, m), abs=1e-7)
        # Linear between the rows at 0.25 and 0.26.
        between = 0.5 * (closed_form(0.25, k, m) + closed_form(0.26, k, m))
        assert row["u_between"] == pytest.approx(between, abs=1e-7)
        assert row["u_max"] == pytest.approx(0.1, abs=1e-7)
        assert row["u_min"] == pytest.approx(u.min(), abs=1e-7)
        assert row["energy"] == pytest.approx(0.01, abs=1e-7)
        # The zero of the chord of the closed form's rows around pi/(2w)...
        i = int(math.floor(math.pi / 2 / w / STEP))
        chord = t[i] + STEP * u[i] / (u[i] - u[i + 1])
        assert row["t_zero"] == pytest.approx(chord, abs=1e-7)
        # ...which is within the chord's error, h^3 w^2 / 8, of the true zero.
        assert abs(row["t_zero"] - math.pi / 2 / w) <= STEP**3 * w**2 / 8 + 1e-7


def test_failed_variants_are_rows_with_their_messages_and_the_rest_run(model, client):
    masses, ends_of_sqrt = [1.0, -1.0, 0.5, 2.0], [1.0, 0.2]
    s = oscillator_study(
        model,
        client,
        factors={"PART/2.MASS": masses, "t_nan": ends_of_sqrt},
        # 0*SQRT(t_nan - TIME) is 0 until TIME passes t_nan, then NaN: the run fails there.
        templates={"SFORCE/1.FUNCTION": "-100*(DM(21, 11) - 1) + 0*SQRT({t_nan} - TIME)"},
        responses={"u_end": study.final("u"), "positive": lambda run: 1.0 / float(run["u"][-1] > 0)},
    )
    table = s.table
    assert len(table) == 8
    kinds = []
    for (m, t_nan), (_, row) in zip(itertools.product(masses, ends_of_sqrt), table.iterrows()):
        assert (row["PART/2.MASS"], row["t_nan"]) == (m, t_nan)
        if m < 0:  # the reader refuses the mass: no run at all
            kinds.append("refused")
            assert row["status"] == "failed" and "E0611" in row["message"]
            assert "a mass cannot be negative" in row["message"] and math.isnan(row["steps"])
        elif t_nan < 0.5:  # the run fails at t_nan, its statistics up to there kept
            kinds.append("run")
            assert row["status"] == "failed" and "E0803" in row["message"] and "NaN" in row["message"]
            assert row["steps"] > 0
        elif math.cos(0.5 * math.sqrt(100 / m)) <= 0:  # u(0.5) <= 0: the response divides by 0
            kinds.append("response")
            assert row["status"] == "failed" and row["steps"] > 0
            assert row["message"].startswith("response 'positive': ZeroDivisionError")
        else:
            kinds.append("ok")
            assert row["status"] == "ok" and row["message"] == ""
            assert row["u_end"] == pytest.approx(closed_form(0.5, 100, m), abs=1e-7)
        if kinds[-1] != "ok":
            assert math.isnan(row["u_end"]) and math.isnan(row["positive"])
    assert sorted(kinds) == sorted(["ok", "run", "refused", "refused", "ok", "run", "response", "run"])
    assert len(s.ok) == 2 and len(s.failed) == 6


# ---------------------------------------------------------------------------- resume


def test_resume_runs_only_what_the_results_file_lacks(model, client, tmp_path):
    out = tmp_path / "results.csv"
    table = [{"PART/2.MASS": m, "k": k} for m in (0.5, 1.0, 2.0) for k in (100, 200, 400, 800)]
    kwargs = dict(
        factors={"PART/2.MASS": (0.5, 2.0), "k": (100, 800)},
        responses={"u_end": study.final("u")},
        out=out,
        batch=2,
    )
    first = oscillator_study(model, client, design=table[:6], **kwargs)
    assert list(first.table["variant"]) == list(range(6))
    assert sorted(pd.read_csv(out)["variant"]) == list(range(6))

    # A crash in the middle of writing the file's last row: the file ends inside it.
    text = out.read_text()
    last = text[:-1].rsplit("\n", 1)[1]
    cut = int(last.split(",")[0])
    out.write_text(text[: len(text) - 1 - len(last) // 2])

    full = oscillator_study(model, client, design=table, resume=True, **kwargs)
    assert sorted(pd.read_csv(out)["variant"]) == list(range(12))  # each variant once, none lost
    assert list(full.table["variant"]) == list(range(12)) and (full.table["status"] == "ok").all()
    # The complete rows were read back, not run again: the same wall times to the bit.
    kept = [v for v in range(6) if v != cut]
    before = first.table.set_index("variant")["seconds"]
    after = full.table.set_index("variant")["seconds"]
    assert after[kept].equals(before[kept]) and after[cut] != before[cut]
    for _, row in full.table.iterrows():
        assert row["u_end"] == pytest.approx(closed_form(0.5, row["k"], row["PART/2.MASS"]), abs=1e-7)

    again = oscillator_study(model, client, design=table, resume=True, **kwargs)
    assert again.table.equals(full.table) and len(pd.read_csv(out)) == 12
    with pytest.raises(ValueError, match="other values"):
        oscillator_study(model, client, design=table[::-1], resume=True, **kwargs)


def test_a_parquet_results_file_holds_the_table_and_resumes(model, client, tmp_path):
    out = tmp_path / "results.parquet"
    table = [{"PART/2.MASS": m, "k": k} for m in (0.5, 2.0) for k in (100, 400, 800)]
    kwargs = dict(
        factors={"PART/2.MASS": (0.5, 2.0), "k": (100, 800)},
        responses={"u_end": study.final("u")},
        out=out,
        batch=2,
    )
    first = oscillator_study(model, client, design=table[:3], **kwargs)
    assert pd.read_parquet(out).equals(first.table[list(pd.read_parquet(out).columns)])
    assert not (tmp_path / "results.parquet.rows.csv").exists()
    full = oscillator_study(model, client, design=table, resume=True, **kwargs)
    written = pd.read_parquet(out)
    assert list(written["variant"]) == list(range(6)) and (written["status"] == "ok").all()
    # The first three were read back, not run again.
    assert written.set_index("variant")["seconds"][[0, 1, 2]].equals(first.table.set_index("variant")["seconds"])
    for _, row in written.iterrows():
        assert row["u_end"] == pytest.approx(closed_form(0.5, row["k"], row["PART/2.MASS"]), abs=1e-7)
    assert full.table["variant"].tolist() == list(range(6))
    with pytest.raises(ValueError, match=".csv or .parquet"):
        oscillator_study(model, client, design=table, out=tmp_path / "results.json",
                         factors=kwargs["factors"], responses=kwargs["responses"])


# -------------------------------------------------------------------------- surfaces

# A quadratic in the scaled factors: x_m = (m - 1.25) / 0.75 (mass over 0.5..2) and
# x_k = log10(k) - 3 (k over 1e2..1e4, log-scaled).
QUADRATIC = {"1": 2.0, "PART/2.MASS": 0.25, "k": 3.0, "PART/2.MASS^2": -1.0, "k^2": 0.5, "PART/2.MASS*k": -1.5}


def quadratic_of_the_run(run: mbfx.Run) -> float:
    """The quadratic at the variant's own k and m, read off the run's first row: the
    spring's force -0.1 k and the block's acceleration -0.1 k / m."""
    force, acceleration = run["f"][0], run["a"][0]
    k, m = -force / 0.1, force / acceleration
    xm, xk = (m - 1.25) / 0.75, math.log10(k) - 3.0
    c = QUADRATIC
    return c["1"] + c["PART/2.MASS"] * xm + c["k"] * xk + c["PART/2.MASS^2"] * xm**2 + c["k^2"] * xk**2 + c["PART/2.MASS*k"] * xm * xk


def test_a_surface_is_exact_on_a_quadratic_response(model, client):
    s = oscillator_study(
        model,
        client,
        end=0.02,
        factors={"PART/2.MASS": (0.5, 2.0), "k": study.log(1e2, 1e4)},
        responses={"q": quadratic_of_the_run},
        probes={"f": "FX(21, 11)", "a": "ACCX(21, 11)"},
        design="lhs",
        n=12,
        seed=3,
    )
    assert (s.table["status"] == "ok").all(), s.failed["message"].tolist()
    surface = s.surface("q")
    assert surface.r2 == pytest.approx(1.0, abs=1e-9)
    assert list(surface.coefficients) == list(QUADRATIC)
    for term, value in QUADRATIC.items():
        assert surface.coefficients[term] == pytest.approx(value, abs=1e-9), term
    # At the centre (m 1.25, k 1e3) the constant; at a corner (m 2, k 1e4) the sum.
    assert surface.predict({"PART/2.MASS": 1.25, "k": 1e3}) == pytest.approx(2.0, abs=1e-9)
    corners = pd.DataFrame({"PART/2.MASS": [2.0, 0.5], "k": [1e4, 1e2]})
    assert surface.predict(corners) == pytest.approx([2 + 0.25 + 3 - 1 + 0.5 - 1.5, 2 - 0.25 - 3 - 1 + 0.5 - 1.5], abs=1e-9)
    # By hand: x_k alone, 3x + 0.5x^2 on [-1, 1], is monotonic: 3.5 - (-2.5) = 6. x_m
    # alone, 0.25x - x^2, peaks at x = 1/8 (1/64) and is least at x = -1 (-1.25).
    effects = surface.main_effects
    assert effects["k"] == pytest.approx(6.0, abs=1e-9)
    assert effects["PART/2.MASS"] == pytest.approx(1 / 64 + 1.25, abs=1e-9)


# ------------------------------------------------------------------------ a dying worker


def test_a_study_survives_a_killed_worker(model, client, tmp_path):
    out = tmp_path / "results.csv"
    pids: Dict[str, int] = client.run(os.getpid)
    n = 40
    # end = 30 makes each variant some 50 ms: the study takes about a second.
    args = dict(end=30.0, factors={"PART/2.MASS": (0.5, 2.0)}, templates={}, design="lhs", n=n)
    result: List[study.Study] = []
    runner = threading.Thread(
        target=lambda: result.append(
            oscillator_study(model, client, responses={"u_end": study.final("u")}, batch=2, out=out, **args)
        )
    )
    runner.start()
    deadline = time.monotonic() + 60
    while not (out.exists() and len(pd.read_csv(out)) > 0) and time.monotonic() < deadline:
        time.sleep(0.005)
    busy: List[str] = []
    while not busy and time.monotonic() < deadline:  # between two tasks none may be busy
        busy = [worker for worker, keys in client.processing().items() if keys]
    assert busy, "no worker is running a task"
    os.kill(pids[busy[0]], signal.SIGKILL)
    rows_at_kill = len(pd.read_csv(out))
    runner.join(120)
    assert rows_at_kill < n, "the study ended before the kill: make the variants slower"
    table = result[0].table
    assert list(table["variant"]) == list(range(n)) and (table["status"] == "ok").all()
    on_disk = pd.read_csv(out)
    assert sorted(on_disk["variant"]) == list(range(n))
    for _, row in table.iterrows():
        assert row["u_end"] == pytest.approx(closed_form(30.0, 100, row["PART/2.MASS"]), abs=1e-6)
    client.wait_for_workers(2, timeout=60)  # the nanny restarts it for later tests


def test_a_variant_that_kills_its_worker_fails_alone_after_one_retry(model, client, tmp_path):
    # The response of the variant with m = 2 ends its worker process, as a crash inside
    # a run would; it notes each attempt in a file first. The study's own cluster blames
    # only the task that was running.
    attempts = tmp_path / "attempts"
    deadly = 2.0
    masses = [0.5, 1.0, deadly, 4.0]

    def u_end_or_die(run):
        u = float(run["u"][-1])
        if abs(u - 0.1 * math.cos(math.sqrt(100 / deadly) * 0.5)) < 1e-6:
            with open(attempts, "a") as f:
                f.write("died\n")
            os._exit(3)
        return u

    out = tmp_path / "results.csv"
    args = dict(factors={"PART/2.MASS": masses}, templates={}, out=out)
    s = oscillator_study(model, None, responses={"u_end": u_end_or_die}, batch=4, **args)
    rows = s.table.set_index("variant")
    failed = rows[rows["status"] == "failed"]
    assert list(failed["PART/2.MASS"]) == [deadly], s.table
    message = failed["message"].iloc[0]
    assert message.startswith("the worker process running this variant died (2 attempts): KilledWorker"), message
    # Its batch ran once, then it ran alone twice.
    assert attempts.read_text().count("died") == 3
    for _, row in rows[rows["status"] == "ok"].iterrows():
        assert row["u_end"] == pytest.approx(closed_form(0.5, 100, row["PART/2.MASS"]), abs=1e-7)
    assert len(rows) == len(masses)

    # resume=True with retry_failed=True runs the failed row again (here it succeeds),
    # replacing it in the file; the others are not run again.
    again = oscillator_study(model, client, responses={"u_end": study.final("u")}, resume=True,
                             retry_failed=True, **args)
    assert (again.table["status"] == "ok").all() and len(again.table) == len(masses)
    assert again.table["u_end"].iloc[2] == pytest.approx(closed_form(0.5, 100, deadly), abs=1e-7)
    on_disk = pd.read_csv(out)
    assert sorted(on_disk["variant"]) == [0, 1, 2, 3] and (on_disk["status"] == "ok").all()


# --------------------------------------------------------------------- its own cluster


def test_without_a_client_a_study_starts_and_closes_its_own_cluster(model, client, capsys):
    before = {p.pid for p in psutil.Process().children(recursive=True)}
    s = oscillator_study(
        model, None, factors={"PART/2.MASS": [0.5, 2.0]}, templates={}, responses={"u_end": study.final("u")}, progress=True
    )
    assert (s.table["status"] == "ok").all()
    for _, row in s.table.iterrows():
        assert row["u_end"] == pytest.approx(closed_form(0.5, 100, row["PART/2.MASS"]), abs=1e-7)
    assert "2/2" in capsys.readouterr().err  # tqdm's bar
    deadline = time.monotonic() + 30
    while {p.pid for p in psutil.Process().children(recursive=True)} - before and time.monotonic() < deadline:
        time.sleep(0.05)
    assert not {p.pid for p in psutil.Process().children(recursive=True)} - before, "its workers outlived it"


# ------------------------------------------------------------------------------ plots


def test_plots_are_written(oscillator, tmp_path):
    pytest.importorskip("matplotlib")
    import matplotlib

    matplotlib.use("Agg")
    paths = [tmp_path / "t_zero.png", tmp_path / "sensitivity.png"]
    oscillator.plot("t_zero", paths[0])
    oscillator.plot_sensitivity("t_zero", paths[1])
    for path in paths:
        assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    with pytest.raises(KeyError):
        oscillator.plot("nope")


def test_every_public_name_of_mbfx_study_has_a_docstring():
    missing = missing_docstrings(study)
    assert not missing, f"no docstring: {missing}"

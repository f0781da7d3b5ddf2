"""mbfx beside the rest of Python: runs and array evaluations leave the GIL to other
threads and give the same bits from several threads at once; Ctrl-C stops a run within
0.1 s with the rows so far; the tqdm progress bar; expressions, models and runs through
pickle and a `spawn` process pool; `Run.to_pandas()` and `Run.plot()`."""

from __future__ import annotations

import multiprocessing
import os
import pickle
import signal
import sys
import threading
import time
from typing import Any, Dict, List, Tuple

import numpy as np
import pytest

import mbfx
from conftest import ROOT, same_bits

SLIDER = ROOT / "examples" / "slider.adm"
FOUR_BAR = ROOT / "tests" / "data" / "models" / "four_bar.adm"
# The slider in fixed steps of 1e-5: about half a second of CPU per simulated second.
SLOW = dict(output_step=0.01, fixed_step=1e-5)


def main_thread_progress(work) -> Tuple[float, int, float]:
    """Runs `work` in a thread while this thread counts loop iterations: the work's wall
    time, the iterations, and the longest pause between two of them. A call that held the
    GIL would pause this thread for about its whole duration."""
    done = threading.Event()
    span: List[float] = []

    def worker() -> None:
        start = time.perf_counter()
        try:
            work()
        finally:
            span.append(time.perf_counter() - start)
            done.set()

    thread = threading.Thread(target=worker)
    count, longest = 0, 0.0
    last = time.perf_counter()
    thread.start()
    while not done.is_set():
        count += 1
        now = time.perf_counter()
        longest = max(longest, now - last)
        last = now
    # The pause that ends the loop counts too: a call holding the GIL ends it.
    longest = max(longest, time.perf_counter() - last)
    thread.join()
    return span[0], count, longest


# ----------------------------------------------------------------------------- threads


def test_the_measure_sees_a_call_that_holds_the_gil():
    # A control: list.sort on floats runs in C without letting go of the GIL.
    rng = np.random.default_rng(3)
    values = rng.random(2_000_000).tolist()
    duration, _, longest = main_thread_progress(values.sort)
    assert duration > 0.3, f"the sort took {duration:.3f} s: too short to tell"
    assert longest > duration / 2, (duration, longest)


def test_a_run_leaves_the_gil_to_other_threads():
    m = mbfx.load(SLIDER)
    results: List[Any] = []
    duration, count, longest = main_thread_progress(lambda: results.append(m.run(1.5, **SLOW)))
    assert len(results[0]) == 151
    # The run takes most of a second; the main thread never waited for a large part of it.
    assert duration > 0.3, f"the run took {duration:.3f} s: too short to tell"
    assert count > 1000 and longest < duration / 3, (duration, count, longest)


def test_an_array_evaluation_leaves_the_gil_to_other_threads():
    # libm's functions, called point by point, so the call lasts most of a second (SIN,
    # COS and ATAN2 are mbfx's own and vectorised: too fast to tell).
    f = mbfx.compile(
        "TAN(x)*EXP(-x)*LOG(1 + x*x) + SINH(x)*COSH(2*x)*TANH(x) + ASIN(x/2) + ACOS(x/3)"
        " + ATAN(x)*EXP(x)*LOG10(2 + x) + STEP(x, 0, 0, 1, 1) + SQRT(ABS(x))**1.5",
        ("x",),
    )
    x = np.linspace(-1.0, 1.0, 8_000_000)
    out: List[np.ndarray] = []
    duration, count, longest = main_thread_progress(lambda: out.append(f(x)))
    assert out[0].shape == x.shape
    assert duration > 0.3, f"the evaluation took {duration:.3f} s: too short to tell"
    assert count > 1000 and longest < duration / 3, (duration, count, longest)


def test_two_threads_running_a_model_give_the_bits_of_one_run():
    m = mbfx.load(SLIDER)
    other = mbfx.load(FOUR_BAR, dim=3)
    kwargs = dict(end=0.6, probes={"x": "DX(22, 11)", "f": "VARVAL(1)"}, **SLOW)
    alone = m.run(**kwargs)
    alone_other = other.run(1.0, output_step=0.01, integrator="hht")
    results: Dict[str, Any] = {}

    def go(key: str, model: mbfx.Model, **kw: Any) -> None:
        results[key] = model.run(**kw)

    threads = [
        threading.Thread(target=go, args=("a", m), kwargs=kwargs),
        threading.Thread(target=go, args=("b", m), kwargs=kwargs),
        threading.Thread(target=go, args=("c", other), kwargs=dict(end=1.0, output_step=0.01, integrator="hht")),
    ]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert results["a"].columns == alone.columns == ["time", "x", "f", "REQ1.F2", "REQ1.F3", "REQ1.F4"]
    assert same_bits(results["a"].data, alone.data) and same_bits(results["b"].data, alone.data)
    assert same_bits(results["c"].data, alone_other.data)


# ----------------------------------------------------------------------------- Ctrl-C


def test_ctrl_c_stops_a_run_within_a_tenth_of_a_second_with_the_rows_so_far():
    m = mbfx.load(SLIDER)
    sent: List[float] = []

    def interrupt() -> None:
        sent.append(time.perf_counter())
        os.kill(os.getpid(), signal.SIGINT)

    timer = threading.Timer(0.5, interrupt)
    # Python turns SIGINT into KeyboardInterrupt only when it did not inherit the signal
    # ignored, which a test runner started in the background by a shell without job
    # control does inherit: install the standard handler for this test.
    inherited = signal.signal(signal.SIGINT, signal.default_int_handler)
    started = time.perf_counter()
    timer.start()
    try:
        # About 25 s of CPU if nothing stopped it.
        with pytest.raises(KeyboardInterrupt) as caught:
            m.run(50.0, **SLOW)
        stopped = time.perf_counter()
    finally:
        timer.cancel()
        signal.signal(signal.SIGINT, inherited)
    assert sent, "the timer did not fire"
    latency = stopped - sent[0]
    assert latency < 0.1, f"KeyboardInterrupt {latency:.3f} s after SIGINT"
    assert stopped - started < 5.0
    partial = caught.value.run
    assert isinstance(partial, mbfx.Run)
    assert partial.columns == ["time", "REQ1.F2", "REQ1.F3", "REQ1.F4"]
    n = len(partial)
    assert 0 < n < 5001
    # The rows are a prefix of the run asked for: its output times, and (fixed steps
    # split each output interval alike) the values of a run that ends at the last one.
    grid = m.run(50.0, output_step=0.01).time
    assert same_bits(partial.time, grid[:n])
    shorter = m.run(float(partial.time[-1]), **SLOW)
    assert same_bits(partial.data, shorter.data)
    assert "interrupted" in str(caught.value)
    # The module stays usable.
    assert mbfx.compile("x + 1", ("x",))(1.0) == 2.0
    again = m.run(0.2, output_step=0.01)
    assert len(again) == 21


# ----------------------------------------------------------------------------- progress


def test_progress_draws_a_tqdm_bar_and_returns_the_same_rows(capsys):
    pytest.importorskip("tqdm")
    m = mbfx.load(SLIDER)
    quiet = m.run(1.0, **SLOW)
    capsys.readouterr()
    shown = m.run(1.0, progress=True, **SLOW)
    err = capsys.readouterr().err
    assert "mbfx run" in err and "100%" in err and "1.0/1.0" in err, err
    assert same_bits(shown.data, quiet.data)


def test_progress_without_tqdm_prints_the_time_on_stderr(capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "tqdm", None)  # `from tqdm import tqdm` fails
    m = mbfx.load(SLIDER)
    shown = m.run(0.5, progress=True)
    err = capsys.readouterr().err
    assert "mbfx run: t = 0.5 of 0.5" in err, err
    assert same_bits(shown.data, m.run(0.5).data)


# ----------------------------------------------------------------------------- pickle


def test_expressions_and_gradients_pickle():
    for engine in ("jit", "interp"):
        f = mbfx.compile("k*STEP(x, 0, 0, 1, 1) + TIME", ("x", "k"), engine=engine)
        g = pickle.loads(pickle.dumps(f))
        assert (g.text, g.variables, g.engine) == (f.text, f.variables, f.engine)
        x = np.linspace(-0.5, 1.5, 101)
        assert same_bits(g(x, 2.0, time=0.25), f(x, 2.0, time=0.25))
        grad = f.gradient(wrt=("x",))
        back = pickle.loads(pickle.dumps(grad))
        assert back.wrt == ("x",) and back.outputs == 2 and back.engine == engine
        assert same_bits(back(x, 2.0), grad(x, 2.0))


def test_models_pickle_as_their_text_and_rebuild():
    for m in (mbfx.load(SLIDER), mbfx.load(SLIDER.read_text(encoding="utf-8")), mbfx.load(FOUR_BAR, dim=3)):
        back = pickle.loads(pickle.dumps(m))
        assert (back.text, back.name, back.title) == (m.text, m.name, m.title)
        assert back.parts == m.parts and back.markers == m.markers
        assert str(back.check()) == str(m.check())
        assert back.check().dimension == m.check().dimension  # dim=3 travels too
        assert same_bits(back.run(0.5).data, m.run(0.5).data)


def test_runs_pickle_as_their_arrays():
    run = mbfx.load(SLIDER).run(1.0, probes={"x": "DX(22, 11)"})
    back = pickle.loads(pickle.dumps(run))
    assert isinstance(back, mbfx.Run)
    assert back.columns == run.columns and same_bits(back.data, run.data)
    assert back.stats == run.stats and back.warnings == run.warnings and back.summary == run.summary
    assert back.integrator == run.integrator == "gstiff" and back.dimension == run.dimension
    assert same_bits(back["x"], run["x"])


def run_in_worker(job: Tuple[mbfx.Model, Dict[str, Any]]) -> Tuple[int, mbfx.Run]:
    """A pool worker: runs the model it received, and says which process it ran in."""
    model, kwargs = job
    return os.getpid(), model.run(**kwargs)


def evaluate_in_worker(job: Tuple[mbfx.Expression, np.ndarray]) -> np.ndarray:
    f, x = job
    return f(x, time=0.5)


def test_a_spawn_pool_runs_models_and_expressions_with_the_parents_bits():
    slider = mbfx.load(SLIDER)
    four = mbfx.load(FOUR_BAR, dim=3)
    jobs = [
        (slider, dict(end=1.0, probes={"x": "DX(22, 11)"})),
        (four, dict(end=1.0, integrator="hht")),
        (slider, dict(end=0.5, engine="interp", fixed_step=1e-4)),
    ]
    f = mbfx.compile("x**2*SIN(TIME) + IMPACT(x, 0, 1, 1e5, 1.5, 50, 0.1)", ("x",))
    x = np.linspace(0.0, 2.0, 1001)
    ctx = multiprocessing.get_context("spawn")
    with ctx.Pool(2) as pool:
        ran = pool.map(run_in_worker, jobs)
        values = pool.map(evaluate_in_worker, [(f, x), (f.gradient(), x)])
    for (pid, run), (model, kwargs) in zip(ran, jobs):
        assert pid != os.getpid()
        here = model.run(**kwargs)
        assert isinstance(run, mbfx.Run) and run.columns == here.columns
        assert same_bits(run.data, here.data), kwargs
    assert same_bits(values[0], f(x, time=0.5))
    assert same_bits(values[1], f.gradient()(x, time=0.5))


# ----------------------------------------------------------------------------- pandas, plot


def test_to_pandas_is_indexed_by_time_with_the_columns_by_name():
    pd = pytest.importorskip("pandas")
    run = mbfx.load(SLIDER).run(1.0, probes={"x": "DX(22, 11)", "v": "VX(22, 11)"})
    frame = run.to_pandas()
    assert isinstance(frame, pd.DataFrame)
    assert frame.index.name == "time" and same_bits(frame.index.to_numpy(), run.time)
    assert list(frame.columns) == ["x", "v", "REQ1.F2", "REQ1.F3", "REQ1.F4"] == run.columns[1:]
    for name in frame.columns:
        assert same_bits(frame[name].to_numpy(), run[name])
    # REQUEST/1's F2 is DX(22, 11), as the probe.
    assert same_bits(frame["x"].to_numpy(), frame["REQ1.F2"].to_numpy())


def test_plot_draws_one_line_per_column_on_agg():
    matplotlib = pytest.importorskip("matplotlib")
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    run = mbfx.load(SLIDER).run(1.0, probes={"x": "DX(22, 11)"})
    try:
        axes = run.plot()
        lines = [l for ax in axes for l in ax.get_lines()]
        assert sorted(l.get_label() for l in lines) == sorted(run.columns[1:])
        for line in lines:
            name = line.get_label()
            assert same_bits(line.get_xdata(), run.time) and same_bits(line.get_ydata(), run[name])
        # x and REQ1.F2 (both DX) share a panel; VX and the SFORCE have their own.
        assert [sorted(l.get_label() for l in ax.get_lines()) for ax in axes] == [
            ["REQ1.F2", "x"], ["REQ1.F3"], ["REQ1.F4"]]
        assert axes[-1].get_xlabel() == "time (second)"
        _, given = plt.subplots()
        assert run.plot(["x"], ax=given) == [given] and len(given.get_lines()) == 1
        with pytest.raises(KeyError):
            run.plot(["nope"])
    finally:
        plt.close("all")


def test_plot_gives_each_unit_a_panel_labelled_with_it():
    # The slider's dataset says UNITS/FORCE = NEWTON, LENGTH = METER: a position and a
    # force (SFORCE/1's x component, some 100 N against 0.3 m) go on two panels.
    matplotlib = pytest.importorskip("matplotlib")
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    run = mbfx.load(SLIDER).run(1.0, probes={"x": "DX(22, 11)", "f": "SFORCE(1, 0, 2, 0)"})
    assert [run.unit(c) for c in run.columns] == [
        "second", "meter", "newton", "meter", "meter/second", "newton"]
    try:
        axes = run.plot(["x", "f"])
        assert len(axes) == 2
        assert [ax.get_ylabel() for ax in axes] == ["meter", "newton"]
        assert [[l.get_label() for l in ax.get_lines()] for ax in axes] == [["x"], ["f"]]
        # Each panel's scale is its own column's.
        for ax, name in zip(axes, ["x", "f"]):
            lo, hi = ax.get_ylim()
            assert lo <= run[name].min() and run[name].max() <= hi
            assert hi - lo < 2 * (run[name].max() - run[name].min())
    finally:
        plt.close("all")
    # A dataset in millimetres and kilonewtons (KNEWTON) names its own units; a number alone has
    # none the checker can tell, and a ratio of lengths is dimensionless.
    text = SLIDER.read_text().replace(
        "UNITS/FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER",
        "UNITS/FORCE = KNEWTON, MASS = KILOGRAM, LENGTH = MILLIMETER",
    )
    mm = mbfx.load(text).run(0.01, probes={"x": "DX(22, 11)", "f": "SFORCE(1, 0, 2, 0)",
                                           "c": "2.5", "r": "DX(22, 11)/DM(22, 11)"})
    assert [mm.unit(c) for c in ("x", "f", "c", "r")] == ["millimeter", "knewton", "", "1"]
    try:
        axes = mm.plot(["x", "c", "r"])
        assert [ax.get_ylabel() for ax in axes] == ["millimeter", "c", "dimensionless"]
    finally:
        plt.close("all")


def test_run_columns_by_name():
    run = mbfx.load(SLIDER).run(1.0, probes={"x": "DX(22, 11)"})
    assert list(run) == run.columns and "x" in run and "y" not in run
    assert same_bits(run["time"], run.time) and len(run) == 101
    with pytest.raises(KeyError, match="no column"):
        run["y"]
    assert repr(run).startswith("mbfx.Run(101 rows to t = 1,")

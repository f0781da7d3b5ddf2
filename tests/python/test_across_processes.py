"""Every exception and result type of mbfx crosses a process boundary intact (issue 43
§3): pickled and back in this process, through a `spawn` process pool where one task
fails (the parent catches `mbfx.MbfxError`), and through Dask's LocalCluster with
processes."""

from __future__ import annotations

import multiprocessing
import pickle
from typing import Any, Dict, Tuple

import numpy as np
import pytest

import mbfx
from conftest import ROOT, same_bits

SLIDER = ROOT / "examples" / "slider.adm"
NAN_FORCE = ROOT / "tests" / "models" / "failures" / "nan_in_force.adm"


def test_every_public_type_lives_in_module_mbfx():
    for name in ("MbfxError", "CheckError", "RunError", "InternalError", "Diagnostic", "Report",
                 "Expression", "Model", "Run", "Linearization", "Graphic", "Animation"):
        t = getattr(mbfx, name)
        assert t.__module__ == "mbfx" or t.__module__.startswith("mbfx."), (name, t.__module__)
        # pickle finds a class by module and name: the pair must lead back to it.
        module = __import__(t.__module__, fromlist=[t.__qualname__])
        assert getattr(module, t.__qualname__) is t, name
    for name in ("MbfxError", "CheckError", "RunError", "InternalError", "Diagnostic", "Report",
                 "Expression", "Model"):
        assert getattr(mbfx, name).__module__ == "mbfx", name


def a_check_error() -> mbfx.CheckError:
    try:
        mbfx.compile("1 + ", variables=())
    except mbfx.CheckError as e:
        return e
    raise AssertionError("the expression compiled")


def a_run_error() -> mbfx.RunError:
    try:
        mbfx.load(NAN_FORCE, dim=3).run(1.0, output_step=0.01, fixed_step=1e-3)
    except mbfx.RunError as e:
        return e
    raise AssertionError("the run did not fail")


def same_diagnostic(a: mbfx.Diagnostic, b: mbfx.Diagnostic) -> bool:
    fields = ("code", "severity", "message", "span", "line", "column", "source", "help", "text")
    return type(a) is type(b) is mbfx.Diagnostic and all(getattr(a, f) == getattr(b, f) for f in fields)


def test_errors_pickle_with_everything_they_carry():
    e = a_check_error()
    back = pickle.loads(pickle.dumps(e))
    assert type(back) is mbfx.CheckError and str(back) == str(e) and back.args == e.args
    assert len(back.diagnostics) == len(e.diagnostics) == 1
    assert same_diagnostic(back.diagnostics[0], e.diagnostics[0])

    r = a_run_error()
    back = pickle.loads(pickle.dumps(r))
    assert type(back) is mbfx.RunError and str(back) == str(r)
    for name in ("time", "element", "cause", "code", "probe"):
        assert getattr(back, name) == getattr(r, name), name
    assert isinstance(back.run, mbfx.Run) and same_bits(back.run.data, r.run.data)
    assert all(same_diagnostic(a, b) for a, b in zip(back.diagnostics, r.diagnostics))

    for kind in (mbfx.MbfxError, mbfx.InternalError):
        back = pickle.loads(pickle.dumps(kind("a message")))
        assert type(back) is kind and str(back) == "a message"


def test_reports_diagnostics_and_linearizations_pickle():
    m = mbfx.load(SLIDER)
    report = m.check()
    back = pickle.loads(pickle.dumps(report))
    assert type(back) is mbfx.Report and str(back) == str(report)
    for name in ("dimension", "dimension_reason", "dof", "gruebler", "equations", "redundant", "advice"):
        assert getattr(back, name) == getattr(report, name), name
    assert len(back.warnings) == len(report.warnings)
    lin = m.linearize()
    back = pickle.loads(pickle.dumps(lin))
    assert isinstance(back, mbfx.Linearization) and back.text == lin.text
    assert same_bits(back.eigenvalues, lin.eigenvalues) and same_bits(back.A, lin.A)
    graphics = m.graphics
    assert pickle.loads(pickle.dumps(graphics)) is not None


# ------------------------------------------------------------------------ a spawn pool


def task(job: Tuple[str, Dict[str, Any]]) -> Any:
    """A pool task: a run, a check or an expression that compiles or does not."""
    kind, kwargs = job
    if kind == "run":
        return mbfx.load(SLIDER).run(**kwargs)
    if kind == "fail":
        return mbfx.load(NAN_FORCE, dim=3).run(1.0, output_step=0.01, fixed_step=1e-3)
    if kind == "check":
        return mbfx.load(SLIDER).check()
    return mbfx.compile(kwargs["text"])


def test_a_spawn_pool_with_a_failing_task_hands_the_parent_mbfx_errors():
    ctx = multiprocessing.get_context("spawn")
    with ctx.Pool(2) as pool:
        ok = pool.apply_async(task, (("run", {"end": 0.5}),))
        failing = pool.apply_async(task, (("fail", {}),))
        bad_text = pool.apply_async(task, (("compile", {"text": "1 +"}),))
        report = pool.apply_async(task, (("check", {}),))
        # Pool.map with one failing task: the parent gets the task's own exception.
        with pytest.raises(mbfx.MbfxError) as mapped:
            pool.map(task, [("run", {"end": 0.2}), ("fail", {})])
        run = ok.get(60)
        with pytest.raises(mbfx.RunError) as failed:
            failing.get(60)
        with pytest.raises(mbfx.CheckError) as refused:
            bad_text.get(60)
        got_report = report.get(60)
    assert isinstance(mapped.value, mbfx.RunError)
    assert same_bits(run.data, mbfx.load(SLIDER).run(0.5).data)
    here = a_run_error()
    e = failed.value
    assert str(e) == str(here) and e.code == here.code and e.time == here.time
    assert same_bits(e.run.data, here.run.data)
    assert same_diagnostic(refused.value.diagnostics[0], a_check_error().diagnostics[0])
    assert str(got_report) == str(mbfx.load(SLIDER).check())


# ------------------------------------------------------------------------------ Dask


def test_dask_hands_the_client_mbfx_errors_and_results(client):
    ok = client.submit(task, ("run", {"end": 0.5}), pure=False)
    failing = client.submit(task, ("fail", {}), pure=False)
    bad_text = client.submit(task, ("compile", {"text": "1 +"}), pure=False)
    report = client.submit(task, ("check", {}), pure=False)
    assert same_bits(ok.result(60).data, mbfx.load(SLIDER).run(0.5).data)
    with pytest.raises(mbfx.MbfxError) as failed:
        failing.result(60)
    assert type(failed.value) is mbfx.RunError
    assert str(failed.value) == str(a_run_error()) and isinstance(failed.value.run, mbfx.Run)
    with pytest.raises(mbfx.CheckError) as refused:
        bad_text.result(60)
    assert refused.value.diagnostics[0].code == a_check_error().diagnostics[0].code
    assert str(report.result(60)) == str(mbfx.load(SLIDER).check())
    expression = client.submit(mbfx.compile, "x**2", ("x",), pure=False).result(60)
    assert same_bits(expression(np.arange(4.0)), np.arange(4.0) ** 2)

"""`run`: a design study of a model's variants on a Dask cluster, start to finish.

It checks the factors, templates and responses, lays out the design, skips the variants
a results file already holds, runs the rest in batches, writes and collects each batch's
rows as it finishes (each variant once), and returns a `Study`.
"""

from __future__ import annotations

import os
import sys
from contextlib import contextmanager
from typing import TYPE_CHECKING, Any, Callable, Dict, Iterator, List, Mapping, Optional, Sequence, Set, Tuple, Union

from . import designs
from .execute import SECONDS, STATS, Job, Row, batches, connect, default_batch, stream
from .factors import Factor, FactorSpec, check_templates, factors_from, settings
from .outfile import ParquetResults, ResultsFile, results_file
from .responses import Response, check_columns
from .results import Study

if TYPE_CHECKING:
    import pandas as pd
    from distributed import Client

    from .. import Model

# Model.run arguments the study sets itself.
_OWN_RUN_ARGS = ("end", "probes", "set", "progress")


def run(
    model: Union["Model", str, "os.PathLike[str]"],
    factors: Optional[Mapping[str, FactorSpec]] = None,
    responses: Optional[Mapping[str, Response]] = None,
    *,
    end: float,
    design: Union[str, designs.Table] = "full",
    n: Optional[int] = None,
    levels: designs.LevelCount = 3,
    probes: Optional[Mapping[str, str]] = None,
    templates: Optional[Mapping[str, str]] = None,
    run_args: Optional[Mapping[str, Any]] = None,
    client: Optional["Client"] = None,
    batch: Optional[int] = None,
    out: Union[str, "os.PathLike[str]", None] = None,
    resume: bool = True,
    retry_failed: bool = False,
    progress: bool = False,
    seed: Optional[int] = 0,
) -> Study:
    """Runs `model` (a Model, or a dataset's path or text) once per variant of a design
    and returns the `Study` of their responses.

    `factors` maps names to a range `(lo, hi)`, `mbfx.study.log(lo, hi)` or a list of
    levels; a name that is a setting key (`PART/2.MASS`) is set directly, another is
    substituted into `templates` ({setting key: str.format text}). It may be omitted when
    `design` is a table (the factors are then its columns). `design` is "full" (`levels`
    values per range), "lhs" or "sobol" (`n` points, `seed`), or a DataFrame or list of
    dicts. `responses` maps names to functions of a Run (`mbfx.study.max("x")`, ...).
    Each variant runs `model.run(end, probes=probes, set=..., **run_args)`.

    The variants run in batches of `batch` (default: about eight tasks per worker thread)
    on `client`'s cluster, or on a LocalCluster of one process per core started and
    closed here. `out` (.csv, or .parquet written whole at the end) receives each
    batch's rows as it finishes; with `resume` the variants it already holds are not
    run again, and with `retry_failed` as well those it holds as failed run again (their
    rows are replaced). `progress` shows a progress bar.

    A variant that crashes its worker process fails alone: its batch runs again one
    variant a task, and a lone variant whose worker dies is retried once, then is a
    failed row naming the worker's death (docs/study.md, "Crashing variants").
    """
    for name, value in (("factors", factors), ("responses", responses), ("probes", probes),
                        ("templates", templates), ("run_args", run_args)):
        _check_mapping(name, value)
    model = _as_model(model)
    factor_map = factors_from(factors) if factors is not None else _factors_of(design)
    responses, probes, templates = dict(responses or {}), dict(probes or {}), dict(templates or {})
    check_templates(factor_map, templates)
    check_columns(responses, probes)
    job = Job(float(end), probes, _run_args(run_args), responses)
    plan = designs.design(factor_map, design, n, levels, seed)
    columns = table_columns(factor_map, responses)

    results = results_file(out, columns) if out is not None else None
    done = results.start(resume) if results is not None else _empty(columns)
    if retry_failed and results is not None and (done["status"] != "ok").any():
        done = done[done["status"] == "ok"].reset_index(drop=True)
        results.keep_only(done)
    _check_same_design(done, plan, out)
    seen: Set[int] = set(int(v) for v in done["variant"])
    values = plan.to_dict("records")  # per column types: an int level stays an int
    pending = [(v, settings(values[v], templates)) for v in range(len(plan)) if v not in seen]

    fresh = _run_pending(pending, model, job, plan, columns, client, batch, results, seen, progress)
    table = _table([done, *fresh], columns)
    if results is not None:
        results.finish(table)
    return Study(table, factor_map, list(responses))


def _run_pending(
    pending: List[Tuple[int, Dict[str, Any]]],
    model: "Model",
    job: Job,
    plan: "pd.DataFrame",
    columns: Sequence[str],
    client: Optional["Client"],
    batch: Optional[int],
    results: "Optional[Union[ResultsFile, ParquetResults]]",
    seen: Set[int],
    progress: bool,
) -> List["pd.DataFrame"]:
    """Runs the `pending` variants in batches, writing each batch's rows to `results` and
    keeping them as it finishes; a variant in `seen` is never kept twice."""
    fresh: List["pd.DataFrame"] = []
    if not pending:
        return fresh  # no cluster to start
    with connect(client) as c, _progress_bar(len(pending), progress) as advance:
        size = batch or default_batch(len(pending), sum(c.nthreads().values()))
        for rows in stream(c, model, job, batches(pending, size)):
            rows = [r for r in rows if r["variant"] not in seen]  # a rerun task's twin
            if not rows:
                continue
            seen.update(r["variant"] for r in rows)
            frame = _with_factors(rows, plan, columns)
            if results is not None:
                results.append(frame)
            fresh.append(frame)
            advance(len(rows))
    return fresh


def table_columns(factors: Mapping[str, Factor], responses: Mapping[str, Response]) -> List[str]:
    """The study table's columns, in order; ValueError when two share a name."""
    columns = ["variant", *factors, *responses, "status", "message", *STATS, SECONDS]
    clashes = sorted({c for c in columns if columns.count(c) > 1})
    if clashes:
        raise ValueError(f"factor and response names must differ from each other and from the table's columns: {clashes}")
    return columns


def _as_model(model: Any) -> "Model":
    from .. import Model, load

    return model if isinstance(model, Model) else load(model)


def _factors_of(design: Any) -> Dict[str, Factor]:
    if isinstance(design, str):
        raise ValueError(f'design="{design}" needs factors=')
    return designs.factors_of_table(design)


def _check_mapping(name: str, value: Any) -> None:
    """Raises TypeError unless `value` is None or a mapping (a bool or a list there raised
    AttributeError deep inside: found by tests/python/test_fuzz_models.py)."""
    if value is not None and not isinstance(value, Mapping):
        raise TypeError(f"{name} is a mapping (a dict), not {value!r}")


def _run_args(run_args: Optional[Mapping[str, Any]]) -> Dict[str, Any]:
    """The other Model.run keywords, refusing those the study sets itself."""
    args = dict(run_args or {})
    own = [k for k in _OWN_RUN_ARGS if k in args]
    if own:
        raise ValueError(f"run_args may not hold {own}: the study sets them (end=, probes=, factors)")
    return args


def _empty(columns: Sequence[str]) -> "pd.DataFrame":
    import pandas as pd

    return pd.DataFrame(columns=list(columns))


def _with_factors(rows: List[Row], plan: "pd.DataFrame", columns: Sequence[str]) -> "pd.DataFrame":
    """The workers' rows with their variants' factor values, in the table's columns (a
    row of a failed task lacks responses and statistics: NaN)."""
    import pandas as pd

    frame = pd.DataFrame(rows).reindex(columns=[c for c in columns if c not in plan.columns])
    values = plan.loc[frame["variant"].to_numpy()].reset_index(drop=True)
    return pd.concat([frame, values], axis=1)[list(columns)]


def _table(parts: Sequence["pd.DataFrame"], columns: Sequence[str]) -> "pd.DataFrame":
    """One table of the parts' rows, in variant order."""
    import pandas as pd

    parts = [p for p in parts if len(p)]
    if not parts:
        return _empty(columns)
    table = pd.concat(parts, ignore_index=True).sort_values("variant", kind="stable")
    table["variant"] = table["variant"].astype(int)
    table["message"] = table["message"].fillna("").astype(str)
    return table.reset_index(drop=True)


def _check_same_design(done: "pd.DataFrame", plan: "pd.DataFrame", out: Any) -> None:
    """ValueError unless every row read from `out` is a variant of `plan` with the same
    factor values (a resumed file must be this study's)."""
    if done.empty:
        return
    variants = done["variant"].astype(int).to_numpy()
    if (variants < 0).any() or (variants >= len(plan)).any():
        raise ValueError(f"{out} holds variants this design does not have: pass resume=False or another out=")
    expected = plan.loc[variants].reset_index(drop=True)
    for name in plan.columns:
        if not _same_values(done[name].reset_index(drop=True), expected[name]):
            raise ValueError(f"{out} holds other values of {name!r} than this design: pass resume=False or another out=")


def _same_values(a: "pd.Series", b: "pd.Series") -> bool:
    import numpy as np
    import pandas as pd

    if pd.api.types.is_numeric_dtype(a) and pd.api.types.is_numeric_dtype(b):
        return bool(np.array_equal(a.to_numpy(dtype=float), b.to_numpy(dtype=float)))
    return list(a.astype(str)) == list(b.astype(str))


@contextmanager
def _progress_bar(total: int, shown: bool) -> Iterator[Callable[[int], None]]:
    """A function to call with each batch's variant count: a tqdm bar when `shown`
    (a line on stderr without tqdm), else nothing."""
    if not shown:
        yield lambda count: None
        return
    try:
        from tqdm import tqdm
    except ImportError:
        counted = [0]

        def line(count: int) -> None:
            counted[0] += count
            print(f"\rmbfx study: {counted[0]} of {total} variants", end="", file=sys.stderr)

        yield line
        print(file=sys.stderr)
        return
    with tqdm(total=total, unit="variant", desc="mbfx study") as bar:
        yield bar.update

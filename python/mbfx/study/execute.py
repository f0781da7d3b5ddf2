"""Running variants on Dask: what a worker does with a batch, and how the client sends
batches out and streams their rows back.

The model travels to each worker once (scattered to all of them); a task is a batch of
variants, each `(variant number, settings)`, and returns one row per variant. A variant
that fails (a refused setting, a failed run, a response that raises) is a row with status
"failed": the study goes on.
"""

from __future__ import annotations

import math
import os
import time
from contextlib import contextmanager
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Dict, Iterable, Iterator, List, Mapping, Optional, Sequence, Tuple

from .responses import Response

if TYPE_CHECKING:
    from distributed import Client

    from .. import Model, Run

Batch = List[Tuple[int, Dict[str, Any]]]
Row = Dict[str, Any]

# The run statistics each row keeps, then the variant's wall seconds.
STATS = ("steps", "rejected")
SECONDS = "seconds"


@dataclass(frozen=True)
class Job:
    """What every variant of a study shares: `Model.run`'s arguments and the responses."""

    end: float
    probes: Dict[str, str] = field(default_factory=dict)
    run_args: Dict[str, Any] = field(default_factory=dict)
    responses: Dict[str, Response] = field(default_factory=dict)


class ResponseError(Exception):
    """A response function raised: which one, and what."""


# ------------------------------------------------------------------------ on a worker


def run_batch(model: "Model", job: Job, batch: Batch) -> List[Row]:
    """Runs each variant of `batch` on `model`: one row each, in order."""
    return [run_variant(model, job, variant, values) for variant, values in batch]


def run_variant(model: "Model", job: Job, variant: int, settings: Mapping[str, Any]) -> Row:
    """One variant's row: its responses and statistics, status "ok"; or NaN responses,
    status "failed" and the failure's text."""
    start = time.perf_counter()
    run = None
    try:
        run = simulate(model, job, settings)
        values = responses_of(run, job.responses)
        status, message = "ok", ""
    except Exception as error:  # noqa: BLE001 - any failure is this variant's, not the study's
        if run is None:
            run = getattr(error, "run", None)  # a RunError keeps the rows before the failure
        values = {name: math.nan for name in job.responses}
        status, message = "failed", failure_text(error)
    stats = run.stats if run is not None else {}
    row: Row = {"variant": variant, **values, "status": status, "message": message}
    row.update({k: stats.get(k, math.nan) for k in STATS})
    row[SECONDS] = time.perf_counter() - start
    return row


def simulate(model: "Model", job: Job, settings: Mapping[str, Any]) -> "Run":
    """One run of `model` with `settings`. The single place a worker turns settings into
    a run: a per-process cache of compiled models (keyed by the model's text) goes here."""
    # A variant's run is reduced to its responses here: no animation is recorded.
    args = {"animation": False, **job.run_args}
    return model.run(job.end, probes=job.probes, set=dict(settings), **args)


def responses_of(run: "Run", responses: Mapping[str, Response]) -> Dict[str, float]:
    """Each response of `run` as a float; ResponseError names the one that raised."""
    values = {}
    for name, response in responses.items():
        try:
            values[name] = float(response(run))
        except Exception as error:  # noqa: BLE001 - reported as the variant's failure
            raise ResponseError(f"response {name!r}: {type(error).__name__}: {error}") from error
    return values


def failure_text(error: BaseException) -> str:
    """The text a failed row keeps: mbfx's rendered diagnostic, else type and message."""
    from .. import MbfxError

    if isinstance(error, (MbfxError, ResponseError)):
        return str(error)
    return f"{type(error).__name__}: {error}"


# ------------------------------------------------------------------------ on the client


@contextmanager
def connect(client: Optional["Client"]) -> Iterator["Client"]:
    """`client`, or a client of a new LocalCluster (a process per core, one thread
    each) closed on leaving."""
    if client is not None:
        yield client
        return
    from distributed import Client, LocalCluster

    workers = os.cpu_count() or 1
    with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True) as cluster:
        with Client(cluster) as own:
            yield own


# Tasks per worker thread: the last batch to finish idles the other workers for about
# half a batch, 1/16 of a worker's share at 8 tasks; Dask's 2 ms a task stays small
# beside variants of milliseconds (16 tasks cost 1 000 variants of 4 ms on 2 workers 2 %).
TASKS_PER_THREAD = 8


def default_batch(pending: int, slots: int) -> int:
    """Variants per task: about eight tasks per worker thread, so scheduling costs little
    when variants take milliseconds and the load still balances when they take long."""
    return max(1, math.ceil(pending / (TASKS_PER_THREAD * max(1, slots))))


def batches(variants: Sequence[Tuple[int, Dict[str, Any]]], size: int) -> List[Batch]:
    """`variants` cut into batches of `size` (the last may be shorter)."""
    return [list(variants[i : i + size]) for i in range(0, len(variants), size)]


def stream(client: "Client", model: "Model", job: Job, work: Iterable[Batch]) -> Iterator[List[Row]]:
    """Runs the batches on `client`'s cluster, yielding each one's rows as it finishes.
    Dask reruns the tasks of a worker that dies elsewhere; a task that still fails gives
    its variants failed rows."""
    from distributed import as_completed

    # hash=False: a job may hold lambdas, which dask cannot tokenize deterministically.
    shared_model = client.scatter(model, broadcast=True, hash=False)
    shared_job = client.scatter(job, broadcast=True, hash=False)
    tasks = {client.submit(run_batch, shared_model, shared_job, b, pure=False): b for b in work}
    for future, result in as_completed(tasks, with_results=True, raise_errors=False):
        if future.status == "finished":
            yield result
        else:
            yield lost_batch(tasks[future], _exception(result))
        future.release()  # its rows are here: the worker may drop them


def lost_batch(batch: Batch, error: BaseException) -> List[Row]:
    """Failed rows for a batch whose task failed as a whole (its worker kept dying)."""
    message = f"the task running this variant failed: {type(error).__name__}: {error}"
    return [{"variant": variant, "status": "failed", "message": message} for variant, _ in batch]


def _exception(result: Any) -> BaseException:
    """The exception in what as_completed gives for a failed future: the exception
    itself, or an exc_info-like tuple."""
    if isinstance(result, BaseException):
        return result
    if isinstance(result, tuple) and len(result) >= 2 and isinstance(result[1], BaseException):
        return result[1]
    return RuntimeError(repr(result))

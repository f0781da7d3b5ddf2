"""Running variants on Dask: what a worker does with a batch, and how the client sends
batches out and streams their rows back.

A task is a batch of variants, each `(variant number, settings)`, and returns one row per
variant. A variant that fails (a refused setting, a failed run, a response that raises) is
a row with status "failed": the study goes on. A task that fails as a whole (its worker
died: a variant crashed the process, or the machine killed it) is not the end of its
variants: each of them runs again alone, so that the one that killed the worker fails
alone; a lone variant whose task fails is retried once, then it is a failed row whose
message names the worker's death.

The model travels with every task as its dataset text (a few kilobytes), and each worker
process keeps the model it built from it: no copy scattered beforehand, so nothing is
lost with a worker (Dask forgets scattered data whose every holder died).
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


class Shipped:
    """A model sent with each task: it pickles as the model's own pickle (its dataset
    text), and a worker unpickles it into the model it built from that text before."""

    def __init__(self, model: "Model") -> None:
        self.model = model

    def __reduce__(self) -> Tuple[Any, Tuple[Any, ...]]:
        _, args = self.model.__reduce__()
        return (built_model, tuple(args))


# The models this worker process built, by their pickles' arguments (text, name, dim):
# a few studies' worth.
_BUILT: Dict[Tuple[Any, ...], "Model"] = {}
_BUILT_KEPT = 4


def built_model(*args: Any) -> "Model":
    """The model `args` (a model's pickle) rebuild, built once per worker process."""
    model = _BUILT.get(args)
    if model is None:
        from .._mbfx import _load_text

        if len(_BUILT) >= _BUILT_KEPT:
            _BUILT.clear()
        model = _BUILT[args] = _load_text(*args)
    return model


# ------------------------------------------------------------------------ on the client


@contextmanager
def connect(client: Optional["Client"]) -> Iterator["Client"]:
    """`client`, or a client of a new LocalCluster (a process per core, one thread
    each) closed on leaving."""
    if client is not None:
        yield client
        return
    from distributed import Client, LocalCluster

    import dask

    workers = os.cpu_count() or 1
    with dask.config.set(OWN_CLUSTER_CONFIG):
        with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True) as cluster:
            with Client(cluster) as own:
                yield own


# The scheduler settings of a study's own cluster: a worker runs one task at a time (no
# task waits queued on it), and a task whose worker dies fails at once, so that only the
# task that was running is blamed and the study, not Dask, decides what runs again
# (Dask's default reruns it on up to three more workers, each of which a crashing variant
# kills). On a cluster of your own, Dask's retries come before the study's.
OWN_CLUSTER_CONFIG = {
    "distributed.scheduler.allowed-failures": 0,
    "distributed.scheduler.worker-saturation": 1.0,
}

# Times a lone variant whose task failed runs again before it is a failed row.
RETRIES = 1


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
    A batch whose task fails runs again one variant a task; a lone variant whose task
    fails runs again `RETRIES` times, then gives a failed row naming the cause."""
    from distributed import as_completed

    shipped = Shipped(model)
    tasks: Dict[Any, Tuple[Batch, int]] = {}
    running = as_completed()

    def submit(batch: Batch, attempt: int) -> None:
        future = client.submit(run_batch, shipped, job, batch, pure=False)
        tasks[future] = (batch, attempt)
        running.add(future)

    for b in work:
        submit(b, 0)
    for future in running:
        batch, attempt = tasks.pop(future)
        if future.status == "finished":
            yield future.result()
        elif len(batch) > 1:
            # One of them may have killed the worker: alone, it fails alone.
            for variant in batch:
                submit([variant], 0)
        elif attempt < RETRIES:
            submit(batch, attempt + 1)
        else:
            yield lost_batch(batch, _exception(future), attempt + 1)
        future.release()  # its rows are here: the worker may drop them


def lost_batch(batch: Batch, error: BaseException, attempts: int) -> List[Row]:
    """Failed rows for a batch whose task failed `attempts` times as a whole: its worker
    died running it (KilledWorker), or the task could not run."""
    from distributed import KilledWorker

    if isinstance(error, KilledWorker):
        cause = f"the worker process running this variant died ({attempts} attempts)"
    else:
        cause = f"the task running this variant failed ({attempts} attempts)"
    message = f"{cause}: {type(error).__name__}: {error}"
    return [{"variant": variant, "status": "failed", "message": message} for variant, _ in batch]


def _exception(future: Any) -> BaseException:
    """The exception of a failed future (a cancelled one has none to fetch)."""
    try:
        error = future.exception()
    except BaseException as e:  # noqa: BLE001 - a cancelled future raises its cause
        return e
    return error if isinstance(error, BaseException) else RuntimeError(repr(error))

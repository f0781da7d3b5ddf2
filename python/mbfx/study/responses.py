"""Responses: the numbers a study keeps of each run.

A response is any function of a `Run` returning a float. The reductions here are
picklable ones over one column: `max` and `min` (over the whole run or from a time on),
`final`, `at` and `first_crossing` (both interpolate linearly between output rows).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Callable, Mapping, Optional

import numpy as np

if TYPE_CHECKING:
    from .. import Run

Response = Callable[["Run"], float]


@dataclass(frozen=True)
class Reduction:
    """A reduction of one column of a run to a float; call it with the run."""

    column: str

    def __call__(self, run: "Run") -> float:
        """The reduction of the column `column` of `run`."""
        return float(self.reduce(np.asarray(run.time), np.asarray(run[self.column])))

    def reduce(self, time: np.ndarray, values: np.ndarray) -> float:
        """The reduction of `values` given at `time`."""
        raise NotImplementedError


@dataclass(frozen=True)
class Max(Reduction):
    """The largest value of a column over the output rows at or after `after`."""

    after: float = -np.inf

    def reduce(self, time: np.ndarray, values: np.ndarray) -> float:
        """The largest of `values` from `after` on (NaN when no row is that late)."""
        late = values[time >= self.after]
        return np.max(late) if late.size else np.nan


@dataclass(frozen=True)
class Min(Reduction):
    """The smallest value of a column over the output rows at or after `after`."""

    after: float = -np.inf

    def reduce(self, time: np.ndarray, values: np.ndarray) -> float:
        """The smallest of `values` from `after` on (NaN when no row is that late)."""
        late = values[time >= self.after]
        return np.min(late) if late.size else np.nan


@dataclass(frozen=True)
class Final(Reduction):
    """A column's value at the last output row."""

    def reduce(self, time: np.ndarray, values: np.ndarray) -> float:
        """The last of `values`."""
        return values[-1]


@dataclass(frozen=True)
class At(Reduction):
    """A column's value at time `t`, linear between output rows; NaN outside the run."""

    t: float = 0.0

    def reduce(self, time: np.ndarray, values: np.ndarray) -> float:
        """`values` interpolated at `t`."""
        # Output times carry rounding (0.1 * 5 may be 0.5000000000000001): a hair past an
        # end still counts as the end.
        slack = 1e-9 * np.max(np.abs(time[[0, -1]]), initial=1.0)
        if not time[0] - slack <= self.t <= time[-1] + slack:
            return np.nan
        return np.interp(self.t, time, values)


@dataclass(frozen=True)
class FirstCrossing(Reduction):
    """The first time a column crosses `level` (linear between output rows); NaN if it
    never does. Touching the level counts; starting on it does not."""

    level: float = 0.0

    def reduce(self, time: np.ndarray, values: np.ndarray) -> float:
        """The first time `values` crosses `level`."""
        s = values - self.level
        before, after = s[:-1], s[1:]
        finite = np.isfinite(before) & np.isfinite(after)
        hits = np.flatnonzero(finite & (before != 0) & (np.sign(before) != np.sign(after)))
        if hits.size == 0:
            return np.nan
        i = hits[0]
        return time[i] + (time[i + 1] - time[i]) * before[i] / (before[i] - after[i])


# The names below shadow builtins on purpose (mbfx.study.max("x")); nothing in this
# module uses the builtins.


def max(column: str, after: Optional[float] = None) -> Max:  # noqa: A001
    """The largest value of probe `column` over the output rows (those at or after time
    `after` when given: the rebound after an impact, say)."""
    return Max(column, -np.inf if after is None else float(after))


def min(column: str, after: Optional[float] = None) -> Min:  # noqa: A001
    """The smallest value of probe `column` over the output rows (those at or after time
    `after` when given)."""
    return Min(column, -np.inf if after is None else float(after))


def final(column: str) -> Final:
    """The value of probe `column` at the end of the run."""
    return Final(column)


def at(t: float, column: str) -> At:
    """The value of probe `column` at time `t`, linear between output rows (NaN outside)."""
    return At(column, float(t))


def first_crossing(column: str, level: float = 0.0) -> FirstCrossing:
    """The time probe `column` first crosses `level`, linear between rows (NaN if never)."""
    return FirstCrossing(column, float(level))


def check_columns(responses: Mapping[str, Any], probes: Mapping[str, str]) -> None:
    """Raises ValueError for a reduction of a column no run will have (a typo would
    otherwise fail every variant): the columns are time, the probes and REQ<id>.F<k>."""
    for name, response in responses.items():
        if not callable(response):
            raise TypeError(f"response {name!r} is not a function of a run: {response!r}")
        if isinstance(response, Reduction):
            column = response.column
            if column != "time" and column not in probes and not column.startswith("REQ"):
                raise ValueError(f"response {name!r} reads column {column!r}, which is not a probe")

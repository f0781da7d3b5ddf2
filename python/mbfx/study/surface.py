"""Quadratic response surfaces: a response fitted by least squares as a full quadratic
(constant, linear, square and pairwise-product terms) in the numerical factors, each
scaled to [-1, 1] over its range (a log range in log10)."""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Dict, List, Mapping, Tuple, Union, overload

import numpy as np

from .factors import Factor, Levels, Range

if TYPE_CHECKING:
    import numpy.typing as npt
    import pandas as pd


@dataclass(frozen=True)
class Scale:
    """How a factor maps onto [-1, 1]: `lo` to -1 and `hi` to 1, in log10 when `log`."""

    lo: float
    hi: float
    log: bool = False

    def unit(self, values: Any) -> np.ndarray:
        """`values` on [-1, 1] (outside it beyond the range)."""
        v = np.asarray(values, dtype=float)
        if self.log:
            v, lo, hi = np.log10(v), math.log10(self.lo), math.log10(self.hi)
        else:
            lo, hi = self.lo, self.hi
        return 2.0 * (v - lo) / (hi - lo) - 1.0


def scale_of(name: str, f: Factor) -> Scale:
    """The scale of a numerical factor: its range, or its least to greatest level."""
    if isinstance(f, Range):
        return Scale(f.lo, f.hi, f.log)
    if isinstance(f, Levels) and f.numeric and min(f.values) < max(f.values):
        return Scale(float(min(f.values)), float(max(f.values)))
    raise ValueError(f"factor {name!r} is not numerical with two values or more: no surface in it")


def term_names(names: List[str]) -> List[str]:
    """The quadratic's terms: "1", each factor, each "factor^2", each "a*b" (a before b)."""
    squares = [f"{a}^2" for a in names]
    products = [f"{a}*{b}" for i, a in enumerate(names) for b in names[i + 1 :]]
    return ["1", *names, *squares, *products]


def design_matrix(x: np.ndarray) -> np.ndarray:
    """The terms' values (columns in `term_names` order) at scaled points `x` (rows)."""
    k = x.shape[1]
    products = [x[:, i] * x[:, j] for i in range(k) for j in range(i + 1, k)]
    return np.column_stack([np.ones(len(x)), x, x**2, *products])


class Surface:
    """A full quadratic fitted to a response over the scaled factors (see `fit`)."""

    def __init__(self, response: str, scales: Dict[str, Scale], beta: np.ndarray, r2: float, points: int) -> None:
        self.response = response
        self.scales = scales
        self.beta = beta
        self.r2 = r2
        self.points = points

    @property
    def factors(self) -> List[str]:
        """The factors the surface is in, in order."""
        return list(self.scales)

    @property
    def coefficients(self) -> Dict[str, float]:
        """Each term's coefficient ("1", "k", "k^2", "k*m", ...) in the scaled factors."""
        return dict(zip(term_names(self.factors), map(float, self.beta)))

    @overload
    def predict(self, values: Mapping[str, float]) -> float: ...
    @overload
    def predict(self, values: Union[Mapping[str, Any], "pd.DataFrame"]) -> "npt.NDArray[np.float64]": ...
    def predict(self, values: Union[Mapping[str, Any], "pd.DataFrame"]) -> Union[float, "npt.NDArray[np.float64]"]:
        """The fitted response at factor values: a dict of numbers gives a float, a dict
        of arrays or a DataFrame an array."""
        columns = [np.atleast_1d(self.scales[name].unit(values[name])) for name in self.factors]
        x = np.column_stack(np.broadcast_arrays(*columns))
        fitted = design_matrix(x) @ self.beta
        scalar = isinstance(values, Mapping) and all(np.ndim(values[n]) == 0 for n in self.factors)
        return float(fitted[0]) if scalar else fitted

    @property
    def main_effects(self) -> Dict[str, float]:
        """For each factor, how far the fitted response ranges (max - min) while that
        factor sweeps its range and the others stay at their centres."""
        return {name: _sweep_range(*self._one_factor(i)) for i, name in enumerate(self.factors)}

    def _one_factor(self, i: int) -> Tuple[float, float]:
        """The linear and square coefficients of factor `i` (others at 0)."""
        k = len(self.factors)
        return float(self.beta[1 + i]), float(self.beta[1 + k + i])

    def __repr__(self) -> str:
        return f"mbfx.study.Surface({self.response!r} in {self.factors}, R² = {self.r2:.6g}, {self.points} points)"


def _sweep_range(b: float, a: float) -> float:
    """max - min of b x + a x² over x in [-1, 1]: at the ends, or the vertex inside."""
    xs = [-1.0, 1.0]
    if a != 0 and -1.0 < -b / (2 * a) < 1.0:
        xs.append(-b / (2 * a))
    ys = [b * x + a * x * x for x in xs]
    return max(ys) - min(ys)


def fit(x: np.ndarray, y: np.ndarray, response: str, scales: Dict[str, Scale]) -> Surface:
    """The least-squares quadratic through points `x` (scaled, one row each) and `y`."""
    matrix = design_matrix(x)
    if len(y) < matrix.shape[1]:
        raise ValueError(f"a quadratic in {len(scales)} factors needs {matrix.shape[1]} points, not {len(y)}")
    beta, _, rank, _ = np.linalg.lstsq(matrix, y, rcond=None)
    if rank < matrix.shape[1]:
        warnings.warn(
            f"the design cannot tell all {matrix.shape[1]} terms apart (rank {rank}): "
            "a square term needs three levels or more",
            RuntimeWarning,
            stacklevel=3,
        )
    residual = y - matrix @ beta
    spread = float(np.sum((y - y.mean()) ** 2))
    r2 = 1.0 - float(residual @ residual) / spread if spread > 0 else 1.0
    return Surface(response, scales, beta, r2, len(y))

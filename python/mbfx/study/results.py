"""`Study`: a finished study's table of variants, with response surfaces and plots."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any, Dict, List, Optional, Sequence, Union

import numpy as np

from . import plots
from .factors import Factor
from .surface import Surface, fit, scale_of

if TYPE_CHECKING:
    import pandas as pd


class Study:
    """The result of `mbfx.study.run`.

    `table` is a pandas DataFrame, one row per variant in variant order: `variant`, the
    factor values, each response, `status` ("ok" or "failed"), `message` (why it failed,
    empty when ok), `steps`, `rejected` (the integrator's counts) and `seconds` (the
    variant's wall time on its worker). `factors` maps each factor's name to its `Range`
    or `Levels`; `responses` lists the response names.
    """

    def __init__(self, table: "pd.DataFrame", factors: Dict[str, Factor], responses: Sequence[str]) -> None:
        self.table = table
        self.factors = factors
        self.responses: List[str] = list(responses)

    @property
    def ok(self) -> "pd.DataFrame":
        """The rows of the variants that ran and gave every response."""
        return self.table[self.table["status"] == "ok"]

    @property
    def failed(self) -> "pd.DataFrame":
        """The rows of the variants that failed, with their messages."""
        return self.table[self.table["status"] == "failed"]

    def surface(self, response: str, factors: Optional[Sequence[str]] = None) -> Surface:
        """The full quadratic in `factors` (default: every numerical factor) fitted by
        least squares to `response` over the ok variants with a finite value; the factors
        are scaled to [-1, 1] over their ranges (log10 for a log range)."""
        self._check_response(response)
        names = list(factors) if factors is not None else [n for n in self.factors if _numeric(self.factors[n])]
        if not names:
            raise ValueError("no numerical factor to fit a surface in")
        scales = {name: scale_of(name, self.factors[name]) for name in names}
        rows = self.ok[np.isfinite(self.ok[response].to_numpy(dtype=float))]
        x = np.column_stack([scales[n].unit(rows[n].to_numpy(dtype=float)) for n in names])
        return fit(x, rows[response].to_numpy(dtype=float), response, scales)

    def plot(self, response: str, path: Union[str, Path, None] = None) -> Any:
        """`response` against each factor, a subplot each (ok variants); saved to `path`
        when given. Returns the matplotlib figure."""
        self._check_response(response)
        return plots.response_against_factors(self.table, self.factors, response, path)

    def plot_sensitivity(self, response: str, path: Union[str, Path, None] = None) -> Any:
        """A bar chart of the main effects of `response`'s quadratic surface; saved to
        `path` when given. Returns the matplotlib figure."""
        return plots.main_effects(self.surface(response).main_effects, response, path)

    def _check_response(self, response: str) -> None:
        if response not in self.responses:
            raise KeyError(f"no response {response!r}; the responses are {self.responses}")

    def __repr__(self) -> str:
        return (
            f"mbfx.study.Study({len(self.table)} variants, {len(self.ok)} ok, "
            f"factors={list(self.factors)}, responses={self.responses})"
        )


def _numeric(f: Factor) -> bool:
    """True when a surface can be in `f`."""
    try:
        scale_of("", f)
    except ValueError:
        return False
    return True

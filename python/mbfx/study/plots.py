"""Plots of a study (matplotlib, imported only here): a response against each factor,
and a bar chart of a response surface's main effects."""

from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING, Any, Mapping, Optional, Union

from .factors import Factor, Range

if TYPE_CHECKING:
    import pandas as pd

PathLike = Union[str, Path]


def _pyplot() -> Any:
    try:
        import matplotlib.pyplot as plt
    except ImportError as e:  # pragma: no cover - depends on the environment
        raise ImportError("study plots need matplotlib: pip install mbfx[plot]") from e
    return plt


def response_against_factors(
    table: "pd.DataFrame", factors: Mapping[str, Factor], response: str, path: Optional[PathLike] = None
) -> Any:
    """One subplot per factor: `response` of each ok variant against the factor's value
    (a log axis for a log range). Saved to `path` (and closed) when given; returns the figure."""
    plt = _pyplot()
    ok = table[table["status"] == "ok"]
    columns = min(len(factors), 3)
    rows = math.ceil(len(factors) / columns)
    fig, axes = plt.subplots(rows, columns, figsize=(4 * columns, 3.2 * rows), squeeze=False, sharey=True)
    for ax, (name, f) in zip(axes.flat, factors.items()):
        ax.plot(ok[name], ok[response], "o", markersize=4)
        ax.set_xlabel(name)
        if isinstance(f, Range) and f.log:
            ax.set_xscale("log")
    for ax in axes[:, 0]:
        ax.set_ylabel(response)
    for ax in list(axes.flat)[len(factors) :]:
        ax.set_visible(False)
    fig.tight_layout()
    return _finish(plt, fig, path)


def main_effects(effects: Mapping[str, float], response: str, path: Optional[PathLike] = None) -> Any:
    """Horizontal bars of `effects` (factor: range of the response), largest on top.
    Saved to `path` (and closed) when given; returns the figure."""
    plt = _pyplot()
    ranked = sorted(effects.items(), key=lambda item: item[1])
    fig, ax = plt.subplots(figsize=(6, 0.5 * len(ranked) + 1.5))
    ax.barh([name for name, _ in ranked], [value for _, value in ranked])
    ax.set_xlabel(f"main effect on {response} (range over the factor's range)")
    fig.tight_layout()
    return _finish(plt, fig, path)


def _finish(plt: Any, fig: Any, path: Optional[PathLike]) -> Any:
    """Saves and closes `fig` when `path` is given (a script makes many); returns it."""
    if path is not None:
        fig.savefig(path)
        plt.close(fig)
    return fig

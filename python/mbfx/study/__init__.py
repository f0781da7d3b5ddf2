"""Design studies of a model's variants, run on Dask (dask.distributed).

    >>> import mbfx
    >>> from mbfx import study
    >>> s = study.run(
    ...     mbfx.load("oscillator.adm"),
    ...     factors={"PART/2.MASS": (0.5, 2.0), "k": study.log(1e2, 1e4)},
    ...     templates={"SFORCE/1.FUNCTION": "-{k}*(DM(21, 11) - 1)"},
    ...     responses={"peak": study.max("u"), "t0": study.first_crossing("u", 0.0)},
    ...     probes={"u": "DX(21, 11) - 1"}, end=1.0, design="lhs", n=64,
    ... )  # doctest: +SKIP
    >>> s.table; s.surface("t0").r2; s.plot_sensitivity("t0", "t0.png")  # doctest: +SKIP

`run` lays out the variants (a full factorial, a Latin hypercube, a Sobol sequence or
your own table), runs them in batches on a cluster, and returns a `Study`: its `table`
(one row per variant), response surfaces (`Study.surface`) and plots. Needs dask,
distributed, pandas and scipy (`pip install mbfx[study]`); matplotlib for the plots.
Nothing here imports them until it is used.
"""

from .factors import Levels, Range, is_setting_key, log, settings
from .designs import design
from .responses import Reduction, at, final, first_crossing, max, min  # noqa: A004 - mbfx.study.max("x")
from .results import Study
from .runner import run
from .surface import Surface

__all__ = [
    "Levels",
    "Range",
    "Reduction",
    "Study",
    "Surface",
    "at",
    "design",
    "final",
    "first_crossing",
    "is_setting_key",
    "log",
    "max",
    "min",
    "run",
    "settings",
]

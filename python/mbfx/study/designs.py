"""Designs: which factor values each variant of a study takes.

`design(...)` gives a pandas DataFrame, one row per variant (index 0, 1, ...) and one
column per factor: a full factorial, a Latin hypercube, a Sobol sequence, or the user's
own table.
"""

from __future__ import annotations

import itertools
from typing import TYPE_CHECKING, Any, Dict, List, Mapping, Optional, Sequence, Union

from .factors import Factor, FactorSpec, Levels, Range, factors_from, plain

if TYPE_CHECKING:
    import pandas as pd

Table = Union["pd.DataFrame", Sequence[Mapping[str, Any]]]
LevelCount = Union[int, Mapping[str, int]]


def design(
    factors: Mapping[str, FactorSpec],
    kind: Union[str, Table] = "full",
    n: Optional[int] = None,
    levels: LevelCount = 3,
    seed: Optional[int] = 0,
) -> "pd.DataFrame":
    """The variants' factor values: `kind` is "full" (every combination of the levels;
    `levels` values per range, an int or {name: int}), "lhs" or "sobol" (`n` points,
    scrambled with `seed`), or a table (DataFrame or list of dicts) with a column per factor.
    `factors` are as `run` takes them: (lo, hi), log(lo, hi) or a list of levels."""
    factors = factors_from(factors)
    if not isinstance(kind, str):
        return own_table(factors, kind)
    if kind == "full":
        if n is not None:
            raise ValueError("a full factorial's size follows from levels=; leave n unset")
        return full_factorial(factors, levels)
    if kind in ("lhs", "sobol"):
        if n is None or n < 1:
            raise ValueError(f'design="{kind}" needs n >= 1 points')
        return sampled(factors, kind, n, seed)
    raise ValueError(f'design is "full", "lhs", "sobol" or a table, not {kind!r}')


def full_factorial(factors: Mapping[str, Factor], levels: LevelCount = 3) -> "pd.DataFrame":
    """Every combination of the factors' levels (the last factor varies fastest); a
    range takes `levels` values from lo to hi."""
    import pandas as pd

    axes = [_levels_of(name, f, levels) for name, f in factors.items()]
    return _frame(pd.DataFrame(list(itertools.product(*axes)), columns=list(factors)))


def _levels_of(name: str, f: Factor, levels: LevelCount) -> List[Any]:
    if isinstance(f, Levels):
        return list(f.values)
    count = levels.get(name, 3) if isinstance(levels, Mapping) else levels
    return f.grid(int(count))


def sampled(factors: Mapping[str, Factor], kind: str, n: int, seed: Optional[int] = 0) -> "pd.DataFrame":
    """`n` points of a scrambled Latin hypercube ("lhs": each range cut into n equal
    strata, one point in each) or Sobol sequence ("sobol"; n a power of 2 keeps its
    balance), mapped from the unit cube onto the factors."""
    import pandas as pd
    from scipy.stats import qmc

    engine = qmc.LatinHypercube if kind == "lhs" else qmc.Sobol
    unit = engine(d=len(factors), rng=seed).random(n)
    columns = {name: list(f.from_unit(unit[:, j])) for j, (name, f) in enumerate(factors.items())}
    return _frame(pd.DataFrame(columns, columns=list(factors)))


def own_table(factors: Mapping[str, Factor], table: Table) -> "pd.DataFrame":
    """The user's table, its columns exactly the factors (in the factors' order)."""
    import pandas as pd

    frame = table.copy() if isinstance(table, pd.DataFrame) else pd.DataFrame(list(table))
    missing = [name for name in factors if name not in frame.columns]
    extra = [str(c) for c in frame.columns if c not in factors]
    if missing or extra:
        raise ValueError(f"the design table's columns must be the factors: missing {missing}, extra {extra}")
    if frame.isna().any().any():
        raise ValueError("the design table has empty cells")
    return _frame(frame[list(factors)])


def factors_of_table(table: Table) -> Dict[str, Factor]:
    """Factors read off a table: numeric columns are ranges from their least to their
    greatest value (levels when constant), others the distinct values."""
    import pandas as pd

    frame = table if isinstance(table, pd.DataFrame) else pd.DataFrame(list(table))
    specs: Dict[str, Factor] = {}
    for name in frame.columns:
        column = frame[name]
        lo, hi = (column.min(), column.max()) if pd.api.types.is_numeric_dtype(column) else (0, 0)
        if lo < hi:
            specs[str(name)] = Range(float(lo), float(hi))
        else:
            specs[str(name)] = Levels(tuple(plain(v) for v in pd.unique(column)))
    return factors_from(specs)


def _frame(frame: "pd.DataFrame") -> "pd.DataFrame":
    """`frame` with its index 0..n-1 (the variant numbers)."""
    return frame.reset_index(drop=True)

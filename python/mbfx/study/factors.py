"""Factors of a study and how a variant's factor values become `Model.run(set=)` settings.

A factor is a `Range` (continuous, optionally log-scaled) or `Levels` (discrete values).
Its name is either a setting key (`KIND/ID.FIELD`, or `KIND.FIELD` for a statement
without an id such as ACCGRAV), set directly, or a template name substituted into
`templates` with str.format.
"""

from __future__ import annotations

import math
import numbers
import string
from dataclasses import dataclass
from typing import Any, Dict, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np

# Statements without an id (src/model/keywords.rs): `KIND.FIELD` names one of them.
_SINGLE_STATEMENTS = (
    "ACCGRAV", "DEBUG", "END", "ENVIRONMENT", "EQUILIBRIUM", "IC", "INTEGRATOR",
    "KINEMATICS", "LSOLVER", "OUTPUT", "PREFERENCES", "RESULTS", "UNITS",
)  # fmt: skip


@dataclass(frozen=True)
class Range:
    """A continuous factor from `lo` to `hi`; `log=True` spreads values evenly in log10."""

    lo: float
    hi: float
    log: bool = False

    def __post_init__(self) -> None:
        if not (math.isfinite(self.lo) and math.isfinite(self.hi)) or self.lo >= self.hi:
            raise ValueError(f"a range needs finite lo < hi, not ({self.lo!r}, {self.hi!r})")
        if self.log and self.lo <= 0:
            raise ValueError(f"a log range needs lo > 0, not {self.lo!r}")

    def from_unit(self, u: np.ndarray) -> np.ndarray:
        """Maps points of [0, 1] onto the range (evenly in log10 when `log`)."""
        if self.log:
            a, b = math.log10(self.lo), math.log10(self.hi)
            return 10.0 ** (a + (b - a) * np.asarray(u, dtype=float))
        return self.lo + (self.hi - self.lo) * np.asarray(u, dtype=float)

    def grid(self, count: int) -> List[float]:
        """`count` values from lo to hi, both included (geometric when `log`)."""
        if count < 2:
            raise ValueError(f"a range needs at least 2 levels in a full factorial, not {count}")
        spread = np.geomspace if self.log else np.linspace
        values = spread(self.lo, self.hi, count)
        values[0], values[-1] = self.lo, self.hi  # exact ends, whatever the rounding
        return [float(v) for v in values]


@dataclass(frozen=True)
class Levels:
    """A discrete factor: the values it takes (numbers or text)."""

    values: Tuple[Any, ...]

    def __post_init__(self) -> None:
        if not self.values:
            raise ValueError("a discrete factor needs at least one level")

    def from_unit(self, u: np.ndarray) -> List[Any]:
        """Picks the level whose equal share of [0, 1] holds each point."""
        count = len(self.values)
        index = np.clip(np.floor(np.asarray(u, dtype=float) * count).astype(int), 0, count - 1)
        return [self.values[i] for i in index]

    @property
    def numeric(self) -> bool:
        """True when every level is a real number."""
        return all(isinstance(v, numbers.Real) and not isinstance(v, bool) for v in self.values)


Factor = Union[Range, Levels]
FactorSpec = Union[Range, Levels, Tuple[float, float], Sequence[Any]]


def log(lo: float, hi: float) -> Range:
    """A continuous factor from `lo` to `hi` spread evenly in log10 (both > 0)."""
    return Range(float(lo), float(hi), log=True)


def factor(spec: FactorSpec) -> Factor:
    """A factor from its spec: a tuple (lo, hi) is a range, a list the discrete levels."""
    if isinstance(spec, (Range, Levels)):
        return spec
    if isinstance(spec, tuple):
        if len(spec) != 2:
            raise ValueError(f"a range is a tuple (lo, hi), not {spec!r}")
        return Range(float(spec[0]), float(spec[1]))
    if isinstance(spec, (list, np.ndarray)):
        return Levels(tuple(plain(v) for v in spec))
    raise TypeError(f"a factor is (lo, hi), a list of levels or mbfx.study.log(lo, hi), not {spec!r}")


def factors_from(specs: Mapping[str, FactorSpec]) -> Dict[str, Factor]:
    """Every factor of `specs`, checked: a setting key or a template name each."""
    factors = {str(name): factor(spec) for name, spec in specs.items()}
    for name in factors:
        if not is_setting_key(name) and not name.isidentifier():
            raise ValueError(
                f"factor {name!r} is neither a setting key (KIND/ID.FIELD, KIND.FIELD) "
                "nor a template name (a Python identifier)"
            )
    return factors


def is_setting_key(name: str) -> bool:
    """True when `name` is a setting key (`PART/2.MASS`, `ACCGRAV.JGRAV`), not a template name."""
    if "/" in name:
        return True
    head, dot, _ = name.partition(".")
    # Adams abbreviates statement names (ACC for ACCGRAV); two letters is IC's whole name.
    return bool(dot) and len(head) >= 2 and any(k.startswith(head.upper()) for k in _SINGLE_STATEMENTS)


def plain(value: Any) -> Any:
    """`value` as a Python int, float or str (numpy scalars pickle and print badly)."""
    if isinstance(value, (bool, np.bool_)):
        raise TypeError(f"a factor value is a number or text, not {value!r}")
    if isinstance(value, numbers.Integral):
        return int(value)
    if isinstance(value, numbers.Real):
        return float(value)
    if isinstance(value, str):
        return value
    raise TypeError(f"a factor value is a number or text, not {value!r}")


class _ExactFormatter(string.Formatter):
    """str.format that writes a bare `{name}` number with repr, so no digit is lost."""

    def format_field(self, value: Any, format_spec: str) -> str:
        if not format_spec and isinstance(value, (int, float)):
            return repr(value)
        return super().format_field(value, format_spec)


_FORMATTER = _ExactFormatter()


def template_names(templates: Mapping[str, str]) -> List[str]:
    """The names `templates` substitute, in order of first use."""
    names: List[str] = []
    for text in templates.values():
        for _, field, _, _ in _FORMATTER.parse(text):
            if field is not None and field not in names:
                names.append(field)
    return names


def check_templates(factors: Mapping[str, Factor], templates: Mapping[str, str]) -> None:
    """Raises ValueError unless templates and factors fit: every template key is a setting
    no factor sets, every name a template uses is a factor and every factor is used."""
    for key in templates:
        if not is_setting_key(key):
            raise ValueError(f"template key {key!r} is not a setting key (KIND/ID.FIELD)")
        if key in factors:
            raise ValueError(f"{key!r} is both a factor and a template")
    used = template_names(templates)
    for name in used:
        if name not in factors or is_setting_key(name):
            raise ValueError(f"a template uses {{{name}}}, which is not a template factor")
    for name in factors:
        if not is_setting_key(name) and name not in used:
            raise ValueError(f"factor {name!r} is neither a setting key nor used in a template")


def settings(values: Mapping[str, Any], templates: Optional[Mapping[str, str]] = None) -> Dict[str, Any]:
    """The `Model.run(set=)` settings of one variant's factor values: setting keys as
    given, each template filled in with the other values."""
    named = {k: plain(v) for k, v in values.items() if not is_setting_key(k)}
    out = {key: _FORMATTER.format(text, **named) for key, text in (templates or {}).items()}
    out.update({k: plain(v) for k, v in values.items() if is_setting_key(k)})
    return out

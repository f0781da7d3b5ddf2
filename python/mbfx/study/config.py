"""A study file (TOML): what `python -m mbfx.study STUDY.toml` and `mbfx study` run.

    model = "impact.adm"          # relative to the study file
    end = 2.0
    design = "lhs"                # "full", "lhs", "sobol", or a CSV table's path
    n = 1000                      # points of lhs / sobol
    levels = 3                    # values per range of a full factorial (or a table)
    seed = 0
    out = "impact.csv"            # .csv or .parquet, relative to the working folder
    batch = 16                    # variants per task (default: 8 tasks per worker)
    scheduler = "tcp://host:8786" # an existing Dask cluster (default: a LocalCluster)

    [factors]                     # a setting key or a template name each
    "VARIABLE/1.FUNCTION" = { log = [1e4, 1e6] }
    "VARIABLE/2.FUNCTION" = { range = [10, 100] }
    "PART/2.MASS" = { levels = [1.0, 1.5, 2.0] }

    [templates]                   # setting key = str.format text over template names
    [probes]                      # column name = expression
    y = "DY(201, 101)"

    [responses]                   # name = one reduction of a probe
    peak = { max = "y" }
    rebound = { max = "y", after = 1.0 }  # from t = 1 on
    low = { min = "y" }
    last = { final = "y" }
    y1 = { at = ["y", 1.0] }      # probe, time
    hit = { first_crossing = ["y", 0.0] }  # probe, level

    [run]                         # Model.run's keyword arguments
    integrator = "dopri853"
    error = 3e-6

A mistake is a `StudyFileError` naming the file, the line of the key when it can be
found, and what the key takes; nothing runs before the whole file is read.
"""

from __future__ import annotations

import re
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Dict, List, Mapping, Optional, Tuple

from .factors import FactorSpec, Levels, Range, log
from .responses import Reduction, at, final, first_crossing, max, min  # noqa: A004

__all__ = ["StudyFile", "StudyFileError", "read", "responses_summary"]

_TOP_KEYS = {
    "model", "end", "design", "n", "levels", "seed", "out", "batch", "resume", "scheduler",
    "factors", "templates", "probes", "responses", "run",
}
_RUN_KEYS = {
    "output_step", "integrator", "error", "hmax", "hinit", "hmin", "fixed_step", "alpha",
    "rho_inf", "kmax", "formulation", "error_per", "cartesian", "interpolate", "engine",
    "estimate_error",
}
_REDUCTIONS = ("max", "min", "final", "at", "first_crossing")


class StudyFileError(ValueError):
    """A study file that cannot be run: `path`, `line` and `column` (1-based, or None) and
    `reason`; the message shows the line with a caret."""

    def __init__(self, path: Path, line: Optional[int], reason: str, text: str = "", column: int = 0) -> None:
        self.path, self.line, self.column, self.reason = path, line, column, reason
        lines = text.splitlines()
        shown = ""
        if line is not None and 1 <= line <= len(lines):
            source = lines[line - 1]
            column = column or len(source) - len(source.lstrip()) + 1
            self.column = column
            shown = f"\n{line:>4} | {source}\n     | {' ' * (column - 1)}^"
        where = f"{path}:{line}:{self.column}" if line is not None else str(path)
        super().__init__(f"{where}: {reason}{shown}")


@dataclass
class StudyFile:
    """A study file read and checked: `path` (the file), `model` (the dataset's path)
    and the arguments of `mbfx.study.run` (`run_kwargs()`), `scheduler` (a Dask
    cluster's address, or None for a LocalCluster)."""

    path: Path
    model: Path
    end: float
    factors: Dict[str, FactorSpec]
    responses: Dict[str, Reduction]
    probes: Dict[str, str] = field(default_factory=dict)
    templates: Dict[str, str] = field(default_factory=dict)
    run_args: Dict[str, Any] = field(default_factory=dict)
    design: Any = "full"
    n: Optional[int] = None
    levels: Any = 3
    seed: Optional[int] = 0
    out: Optional[Path] = None
    batch: Optional[int] = None
    resume: bool = True
    scheduler: Optional[str] = None

    def run_kwargs(self) -> Dict[str, Any]:
        """The keyword arguments of `mbfx.study.run` (all but the model and the client)."""
        return dict(
            factors=self.factors or None, responses=self.responses, end=self.end, design=self.design,
            n=self.n, levels=self.levels, probes=self.probes, templates=self.templates,
            run_args=self.run_args, batch=self.batch, out=self.out, resume=self.resume,
            seed=self.seed,
        )


def read(path: "str | Path") -> StudyFile:
    """The study file at `path`, checked; StudyFileError for any mistake in it."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as e:
        raise StudyFileError(path, None, f"cannot read it: {e}") from None
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        # Python 3.11's error has its place only in its text: "... (at line 2, column 7)".
        m = re.search(r"^(.*) \(at line (\d+), column (\d+)\)$", str(e))
        line, column, why = (int(m[2]), int(m[3]), m[1]) if m else (None, 0, str(e))
        raise StudyFileError(path, line, f"not TOML: {why}", text, column) from None
    return _Reader(path, text).study(doc)


class _Reader:
    """Checks one parsed study file, locating each mistake's key in `text`."""

    def __init__(self, path: Path, text: str) -> None:
        self.path, self.text = path, text
        self.base = path.parent

    def fail(self, reason: str, key: str = "", table: str = "") -> StudyFileError:
        return StudyFileError(self.path, self._line(key, table), reason, self.text)

    def _line(self, key: str, table: str) -> Optional[int]:
        """The line where `key` is set in `[table]` (the top level when empty)."""
        if not key:
            return None
        current = ""
        pattern = re.compile(r'\s*(?:"' + re.escape(key) + r'"|' + re.escape(key) + r")\s*=")
        for number, line in enumerate(self.text.splitlines(), start=1):
            header = re.match(r"\s*\[\s*([^\]]+?)\s*\]", line)
            if header:
                current = header.group(1)
            elif current == table and pattern.match(line):
                return number
        return None

    def study(self, doc: Mapping[str, Any]) -> StudyFile:
        for key in doc:
            if key not in _TOP_KEYS:
                raise self.fail(f"unknown key {key!r}; a study file takes {sorted(_TOP_KEYS)}", key)
        for key in ("model", "end"):
            if key not in doc:
                raise self.fail(f"{key!r} is missing")
        model = self.base / self._typed(doc, "model", str)
        if not model.is_file():
            raise self.fail(f"model: no file {model}", "model")
        end = self._number(doc, "end")
        design = doc.get("design", "full")
        if not isinstance(design, str):
            raise self.fail('design is "full", "lhs", "sobol" or a CSV table\'s path', "design")
        if design not in ("full", "lhs", "sobol"):
            design = self._table(design)
        factors = {name: self._factor(name, spec) for name, spec in self._section(doc, "factors").items()}
        if not factors and isinstance(design, str):
            raise self.fail("[factors] is missing or empty (needed unless design is a table)")
        out = doc.get("out")
        return StudyFile(
            path=self.path,
            model=model,
            end=end,
            factors=factors,
            responses={name: self._response(name, r) for name, r in self._section(doc, "responses").items()},
            probes=self._strings(doc, "probes"),
            templates=self._strings(doc, "templates"),
            run_args=self._run_args(self._section(doc, "run")),
            design=design,
            n=self._typed(doc, "n", int) if "n" in doc else None,
            levels=self._levels(doc.get("levels", 3)),
            seed=self._typed(doc, "seed", int) if "seed" in doc else 0,
            out=Path(self._typed(doc, "out", str)) if out is not None else None,
            batch=self._typed(doc, "batch", int) if "batch" in doc else None,
            resume=self._typed(doc, "resume", bool) if "resume" in doc else True,
            scheduler=self._typed(doc, "scheduler", str) if "scheduler" in doc else None,
        )

    def _typed(self, doc: Mapping[str, Any], key: str, kind: type, table: str = "") -> Any:
        value = doc[key]
        # TOML's booleans are not numbers here (True is an int to Python).
        if not isinstance(value, kind) or (kind is int and isinstance(value, bool)):
            raise self.fail(f"{key} is a {kind.__name__}, not {value!r}", key, table)
        return value

    def _number(self, doc: Mapping[str, Any], key: str, table: str = "") -> float:
        value = doc[key]
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise self.fail(f"{key} is a number, not {value!r}", key, table)
        return float(value)

    def _section(self, doc: Mapping[str, Any], name: str) -> Dict[str, Any]:
        value = doc.get(name, {})
        if not isinstance(value, dict):
            raise self.fail(f"{name} is a table ([{name}]), not {value!r}", name)
        return value

    def _strings(self, doc: Mapping[str, Any], name: str) -> Dict[str, str]:
        table = self._section(doc, name)
        for key, value in table.items():
            if not isinstance(value, str):
                raise self.fail(f"[{name}] {key}: a str, not {value!r}", key, name)
        return dict(table)

    def _factor(self, name: str, spec: Any) -> FactorSpec:
        shape = "{range = [lo, hi]}, {log = [lo, hi]} or {levels = [...]}"
        if not isinstance(spec, dict) or len(spec) != 1:
            raise self.fail(f"factor {name!r}: a factor is {shape}, not {spec!r}", name, "factors")
        ((kind, value),) = spec.items()
        if kind == "levels":
            if not isinstance(value, list) or not value:
                raise self.fail(f"factor {name!r}: levels is a non-empty list", name, "factors")
            return Levels(tuple(value))
        if kind in ("range", "log"):
            ok = isinstance(value, list) and len(value) == 2
            if not ok or any(isinstance(v, bool) or not isinstance(v, (int, float)) for v in value):
                raise self.fail(f"factor {name!r}: {kind} is [lo, hi], two numbers", name, "factors")
            try:
                return log(*value) if kind == "log" else Range(float(value[0]), float(value[1]))
            except ValueError as e:
                raise self.fail(f"factor {name!r}: {e}", name, "factors") from None
        raise self.fail(f"factor {name!r}: a factor is {shape}, not {kind!r}", name, "factors")

    def _response(self, name: str, spec: Any) -> Reduction:
        shape = (
            "{max = probe}, {min = probe} (either with after = t), {final = probe}, "
            "{at = [probe, t]} or {first_crossing = [probe, level]}"
        )
        if not isinstance(spec, dict):
            raise self.fail(f"response {name!r}: a response is {shape}", name, "responses")
        after = spec.get("after")
        if after is not None and (isinstance(after, bool) or not isinstance(after, (int, float))):
            raise self.fail(f"response {name!r}: after is a time, not {after!r}", name, "responses")
        reduction = [k for k in spec if k != "after"]
        if len(reduction) != 1 or reduction[0] not in _REDUCTIONS or (after is not None and reduction[0] not in ("max", "min")):
            raise self.fail(f"response {name!r}: a response is {shape}", name, "responses")
        kind, value = reduction[0], spec[reduction[0]]
        if kind in ("max", "min", "final"):
            if not isinstance(value, str):
                raise self.fail(f"response {name!r}: {kind} takes a probe's name", name, "responses")
            if kind == "final":
                return final(value)
            return (max if kind == "max" else min)(value, after)
        pair = isinstance(value, list) and len(value) == 2 and isinstance(value[0], str)
        if not pair or isinstance(value[1], bool) or not isinstance(value[1], (int, float)):
            second = "t" if kind == "at" else "level"
            raise self.fail(f"response {name!r}: {kind} is [probe, {second}]", name, "responses")
        return at(value[1], value[0]) if kind == "at" else first_crossing(value[0], value[1])

    def _run_args(self, table: Dict[str, Any]) -> Dict[str, Any]:
        for key in table:
            if key not in _RUN_KEYS:
                raise self.fail(f"[run] {key}: not an argument of Model.run; it takes {sorted(_RUN_KEYS)}", key, "run")
        return dict(table)

    def _levels(self, value: Any) -> Any:
        if isinstance(value, bool) or not isinstance(value, (int, dict)):
            raise self.fail(f"levels is a count or {{factor = count}}, not {value!r}", "levels")
        return value

    def _table(self, name: str) -> List[Dict[str, Any]]:
        """A design table from a CSV file with a header of factor names."""
        import csv

        path = self.base / name
        try:
            with open(path, newline="", encoding="utf-8") as f:
                rows = list(csv.DictReader(f))
        except (OSError, UnicodeDecodeError, csv.Error) as e:
            raise self.fail(f"design: cannot read the table {path}: {e}", "design") from None
        if not rows:
            raise self.fail(f"design: the table {path} has no rows", "design")
        return [{k: _cell(v) for k, v in row.items()} for row in rows]


def _cell(text: str) -> Any:
    """A CSV cell: a number when it reads as one, else the text (an expression)."""
    for kind in (int, float):
        try:
            return kind(text)
        except ValueError:
            pass
    return text


def responses_summary(study: Any) -> List[Tuple[str, str]]:
    """(response, text) lines: R² of its quadratic surface and each factor's main effect,
    or why there is no surface."""
    lines = []
    for response in study.responses:
        try:
            s = study.surface(response)
        except (ValueError, ArithmeticError, KeyError) as e:
            lines.append((response, f"no surface: {e}"))
            continue
        effects = ", ".join(f"{k} {v:.4g}" for k, v in s.main_effects.items())
        lines.append((response, f"R² = {s.r2:.4f}; main effects (its range over each factor's): {effects}"))
    return lines

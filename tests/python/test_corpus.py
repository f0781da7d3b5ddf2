"""Every expression of the shared corpus (`expressions.txt`, `expressions-cmd.txt`),
compiled from Python with no variables in both engines, against `mbfx eval` on the same
text: the same value bit for bit (NaN equal to NaN), or, where the command line refuses the
expression, a `CheckError` whose first error has the command line's code. The truth is the
command line's output, as issue 22 asks; nothing here comes from the Python module."""

from __future__ import annotations

import math
import re
import struct
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Dict, List, Optional, Tuple

import numpy as np
import pytest

import mbfx
from conftest import run_cli

ENGINES = ("jit", "interp")
CORPUS_FILES = ("expressions.txt", "expressions-cmd.txt")
FIRST_ERROR = re.compile(r"\[(E\d{4})\] Error")


def corpus(shared: Path) -> Dict[str, List[str]]:
    """Each distinct expression of the corpus files, with every place it comes from
    (`provenance<TAB>expression` a line)."""
    found: Dict[str, List[str]] = {}
    for name in CORPUS_FILES:
        for number, line in enumerate((shared / "corpus" / name).read_text(encoding="utf-8").splitlines(), 1):
            if not line.strip():
                continue
            provenance, tab, text = line.partition("\t")
            assert tab, f"{name}:{number}: no tab in {line!r}"
            found.setdefault(text, []).append(provenance)
    return found


def parse_value(printed: str) -> List[float]:
    """Rust's `{:?}` of an f64 (`1.5`, `1e-7`, `NaN`, `inf`, `-inf`) or of a vector
    (`[x, y, z]`), as floats: Python's `float` reads the shortest round-trip form exactly."""
    printed = printed.strip()
    if printed.startswith("[") and printed.endswith("]"):
        return [float(x) for x in printed[1:-1].split(",")]
    return [float(printed)]


def same_bits(a: float, b: float) -> bool:
    """Equal bit for bit, or both NaN (the command line prints every NaN as `NaN`)."""
    if math.isnan(a) and math.isnan(b):
        return True
    return struct.pack("<d", a) == struct.pack("<d", b)


def cli_eval(text: str, engine: str) -> Tuple[int, str, str]:
    """`mbfx eval --engine ENGINE -- TEXT`: exit code, stdout, stderr."""
    done = run_cli("eval", "--color", "never", "--engine", engine, "--", text)
    return done.returncode, done.stdout, done.stderr


def python_outcome(text: str, engine: str) -> Tuple[str, object]:
    """("value", [floats]) or ("error", first error code) or ("raised", repr) from Python."""
    try:
        value = mbfx.compile(text, engine=engine)()
    except mbfx.CheckError as e:
        errors = [d.code for d in e.diagnostics if d.severity == "error"]
        return ("error", errors[0] if errors else None)
    except Exception as e:  # noqa: BLE001 - any other exception is a mismatch to report
        return ("raised", f"{type(e).__name__}: {e}")
    return ("value", [float(x) for x in np.atleast_1d(np.asarray(value, dtype=np.float64))])


def compare(text: str, engine: str, cli: Tuple[int, str, str]) -> Tuple[Optional[str], str]:
    """A mismatch's description (None when Python agrees) and the outcome's kind."""
    code, out, err = cli
    py = python_outcome(text, engine)
    if code == 0:
        want = parse_value(out)
        if py[0] != "value":
            return f"the CLI prints {out.strip()}, Python gives {py}", "value"
        got = py[1]
        assert isinstance(got, list)
        if len(got) != len(want) or not all(same_bits(a, b) for a, b in zip(got, want)):
            return f"the CLI prints {out.strip()}, Python gives {[repr(x) for x in got]}", "value"
        return None, "value"
    if code != 1:
        return f"the CLI exits {code} (not 0 or 1): {err.strip()[:300]}", "usage"
    first = FIRST_ERROR.search(err)
    if first is None:
        return f"the CLI fails with no error code: {err.strip()[:300]}", "error"
    if py != ("error", first.group(1)):
        return f"the CLI fails with {first.group(1)}, Python gives {py}", "error"
    return None, "error"


def test_every_corpus_expression_evaluates_as_the_cli_does_in_both_engines(cli, shared):
    expressions = corpus(shared)
    jobs = [(text, engine) for text in expressions for engine in ENGINES]
    with ThreadPoolExecutor(max_workers=4) as pool:
        outputs = list(pool.map(lambda job: cli_eval(*job), jobs))
    mismatches = []
    kinds = {"value": 0, "error": 0, "usage": 0}
    for (text, engine), output in zip(jobs, outputs):
        problem, kind = compare(text, engine, output)
        kinds[kind] += 1
        if problem is not None:
            mismatches.append(f"{expressions[text][0]} [{engine}] {text!r}: {problem}")
    assert not mismatches, f"{len(mismatches)} of {len(jobs)} differ:\n" + "\n".join(mismatches)
    # The corpus exercises both outcomes (a check that the comparison is not vacuous).
    assert kinds["value"] >= 100 and kinds["error"] >= 100, kinds


@pytest.mark.parametrize("engine", ENGINES)
def test_printed_forms_of_the_cli_parse_back_to_the_same_bits(cli, engine):
    # Values whose `{:?}` form is special: NaN, infinities, exponents, a vector, -0.
    for text, want in [
        ("SQRT(-1)", [math.nan]),
        ("1/0", [math.inf]),
        ("-1/0", [-math.inf]),
        ("1e-300*1e-10", [1e-310]),
        ("2**70", [2.0**70]),
        ("-0*1", [-0.0]),
        ("[1, -2.5, 1e-9]", [1.0, -2.5, 1e-9]),
    ]:
        code, out, err = cli_eval(text, engine)
        assert code == 0, (text, err)
        got = parse_value(out)
        assert len(got) == len(want) and all(same_bits(a, b) for a, b in zip(got, want)), (text, out)
        assert compare(text, engine, (code, out, err))[0] is None, text


@pytest.mark.parametrize("engine", ENGINES)
def test_an_if_on_nan_is_an_error_in_the_cli_and_nan_from_python(cli, engine):
    """A known, deliberate difference (not in the corpus, which has no such expression):
    `mbfx eval` refuses an IF whose test is NaN (E0402, "no branch applies") because it
    evaluates one constant expression and can say so; an `Expression` is a function that
    numpy-style callers evaluate over arrays, where a NaN test gives NaN (as
    test_expression.py's IEEE test pins for a NaN variable)."""
    text = "IF(SQRT(-1): 1, 2, 3)"
    code, _, err = cli_eval(text, engine)
    assert code == 1 and FIRST_ERROR.search(err).group(1) == "E0402", err
    assert math.isnan(mbfx.compile(text, engine=engine)())

"""Fuzz tests (issue 41 §3): random expression texts and variable names through
`mbfx.compile`, the compiled expression called with random points (NaN and infinities
included, positional and keyword, TIME) and differentiated in random names. A finding is
a crash, an InternalError or a PanicException, or an exception that is not mbfx's
errors, ValueError or TypeError (`conftest.survives`). Sizes: conftest's profiles."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given
from hypothesis import strategies as st

import mbfx
from conftest import same_bits, survives

# Pieces of the language: builtins (a few of each kind), punctuation, numbers, names.
TOKENS = [
    "x", "v", "t", "TIME", "MODE", "PI", "DTOR", "1", "0", "-", "+", "*", "/", "**", "(", ")",
    ",", ":", "[", "]", "%", " ", "1E308", "1e-320", "0.5", "SIN(", "COS(", "SQRT(", "LOG(",
    "EXP(", "ABS(", "ATAN2(", "STEP(", "STEP5(", "IF(", "MIN(", "MAX(", "MOD(", "POLY(",
    "CHEBY(", "IMPACT(", "BISTOP(", "HAVSIN(", "SHF(", "SWEEP(", "FORCOS(", "MAG(", "DX(",
    "VZ(", "AKISPL(", "CUBSPL(", "SIGN(", "AINT(", "DIM(", "\n", "\t", "!", "é", "\x00",
]

texts = st.one_of(
    st.lists(st.sampled_from(TOKENS), max_size=24).map("".join),
    st.text(max_size=40),
    st.sampled_from(["x + v*t", "[x, v, t]", "STEP(x, 0, 0, 1, v)", "x**v", "IF(x: 1, 2, 3)"]),
)

names = st.one_of(
    st.sampled_from(["x", "v", "t", "X", "time", "TIME", "SIN", "PI", "", "1a", "a b", "é", "x\x00"]),
    st.from_regex(r"[A-Za-z_][A-Za-z0-9_]{0,6}", fullmatch=True),
    st.text(max_size=6),
)

values = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from([0.0, -0.0, 5e-324, -2.2e-308, math.inf, -math.inf, math.nan, 1e308]),
    st.integers(min_value=-(2**70), max_value=2**70),
    st.booleans(),
)

engines = st.one_of(st.sampled_from(["jit", "interp"]), st.text(max_size=6))


@given(text=texts, variables=st.lists(names, max_size=4), engine=engines)
def test_random_texts_and_names_compile_or_are_refused(text, variables, engine):
    e = survives(mbfx.compile, text, variables, engine)
    if e is None:
        return
    assert e.text == text
    assert len(e.variables) == len(variables)
    assert e.outputs >= 1
    for w in e.warnings:
        assert 0 <= w.span[0] <= w.span[1] <= len(text.encode())


@given(
    text=texts,
    engine=st.sampled_from(["jit", "interp"]),
    point=st.lists(values, min_size=0, max_size=5),
    time=st.one_of(st.none(), values),
    by_keyword=st.booleans(),
)
def test_random_points_evaluate_or_are_refused(text, engine, point, time, by_keyword):
    e = survives(mbfx.compile, text, ["x", "v", "t"], engine)
    if e is None:
        return
    kwargs = {} if time is None else {"time": time}
    if by_keyword:
        kwargs.update(zip(["x", "V", "t", "w", "x"], point))
        got = survives(e, **kwargs)
    else:
        got = survives(e, *point, **kwargs)
    right = len(point) == 3 and all(isinstance(p, float) for p in point)
    if right and not by_keyword:
        assert got is not None, f"{text!r} at {point}"
        # The array path gives the bits of the point path.
        arrays = survives(e, *(np.array([p]) for p in point), **kwargs)
        assert arrays is not None
        assert same_bits(np.reshape(arrays, -1), np.reshape(np.asarray(got), -1))


@given(
    text=texts,
    engine=st.sampled_from(["jit", "interp"]),
    wrt=st.one_of(st.none(), st.lists(names, max_size=4)),
    point=st.tuples(values, values, values),
)
def test_random_gradients_are_taken_or_refused(text, engine, wrt, point):
    e = survives(mbfx.compile, text, ["x", "v", "t"], engine)
    if e is None:
        return
    g = survives(e.gradient, wrt)
    if g is None:
        return
    n = 3 if wrt is None else len(wrt)
    assert g.outputs == e.outputs * (1 + n)
    survives(g, *point, time=0.5)

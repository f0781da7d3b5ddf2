"""Fuzz tests (issue 41 §3): compiled expressions called with numpy arrays of random
shapes, dtypes and strides (views, transposes, broadcasting, zero-size), values with
NaN and infinities, and huge arrays (at most 2·10⁷ elements, so memory stays bounded).
What an array call returns is checked against the same expression called point by
point with plain floats. A finding is as in test_fuzz_expressions.py."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

import mbfx
from conftest import same_bits, survives

TEXTS = ["x + v*t", "[x, v*TIME, x - v]", "STEP(x, 0, 0, 1, v) + SQRT(ABS(x))", "IF(x - v: x, t, v)"]

_compiled = {}


def expression(text: str, engine: str) -> mbfx.Expression:
    """One compiled expression per text and engine, kept across examples."""
    key = (text, engine)
    if key not in _compiled:
        _compiled[key] = mbfx.compile(text, ["x", "v", "t"], engine)
    return _compiled[key]


DTYPES = [
    np.float64, np.float32, np.float16, np.int8, np.int64, np.uint64, np.bool_,
    np.complex128, np.dtype(">f8"), np.dtype("<f4"), np.object_, np.str_, np.dtype("M8[s]"),
]


@st.composite
def arrays(draw):
    """An array of a random dtype and shape (0 to 3 axes, sides 0 to 5), maybe a
    strided, reversed or transposed view of a larger one."""
    dtype = np.dtype(draw(st.sampled_from(DTYPES)))
    shape = draw(hnp.array_shapes(min_dims=0, max_dims=3, min_side=0, max_side=5))
    if dtype.kind in "fc":
        elements = st.floats(allow_nan=True, allow_infinity=True, width=64 if dtype.itemsize >= 8 else 32)
        base = draw(hnp.arrays(np.float64, shape, elements=elements)).astype(dtype)
    elif dtype.kind == "O":
        base = np.empty(shape, dtype=object)
        flat = draw(st.lists(st.one_of(st.floats(), st.none(), st.text(max_size=3), st.integers()), min_size=base.size, max_size=base.size))
        for i, x in enumerate(flat):
            base.flat[i] = x
    elif dtype.kind == "U":
        base = draw(hnp.arrays(dtype, shape, elements=st.sampled_from(["1.5", "nan", "-inf", "x", ""])))
    else:
        base = draw(hnp.arrays(dtype, shape))
    view = draw(st.sampled_from(["as is", "step", "reverse", "transpose", "fortran"]))
    if view == "step" and base.ndim:
        base = np.repeat(base, 2, axis=0)[::2]
    elif view == "reverse" and base.ndim:
        base = base[::-1]
    elif view == "transpose":
        base = base.T
    elif view == "fortran":
        base = np.asfortranarray(base)
    return base


arguments = st.one_of(arrays(), st.floats(), st.integers(-5, 5), st.lists(st.floats(), max_size=4), st.none(), st.text(max_size=3))


@given(
    text=st.sampled_from(TEXTS),
    engine=st.sampled_from(["jit", "interp"]),
    args=st.tuples(arguments, arguments, arguments),
    time=st.one_of(st.none(), arguments),
)
def test_arrays_of_any_shape_dtype_and_stride_evaluate_or_are_refused(text, engine, args, time):
    e = expression(text, engine)
    kwargs = {} if time is None else {"time": time}
    got = survives(e, *args, **kwargs)
    if got is None:
        return
    # The same values point by point, as plain floats.
    try:
        parts = [np.asarray(a, dtype=np.float64) for a in (*args, 0.0 if time is None else time)]
        parts = np.broadcast_arrays(*parts)
    except (ValueError, TypeError):
        pytest.fail(f"numpy refuses {args!r} but mbfx evaluated them")
    shape = parts[0].shape
    got = np.asarray(got)
    outputs = e.outputs
    assert got.shape == (shape + (outputs,) if outputs > 1 else shape) or (shape == () and got.shape == (outputs,))
    flat = got.reshape(-1, outputs)
    for i, point in enumerate(zip(*(p.reshape(-1) for p in parts))):
        want = e(*(float(p) for p in point[:3]), time=float(point[3]))
        assert same_bits(flat[i], np.reshape(want, -1)), f"point {i}: {point}"


# Each example allocates up to 320 MB and takes a fraction of a second: few of them.
@settings(max_examples=min(40, max(6, settings.default.max_examples // 10)))
@given(
    engine=st.sampled_from(["jit", "interp"]),
    n=st.sampled_from([10**6, 10**7, 2 * 10**7]),
    text=st.sampled_from(TEXTS),
)
def test_huge_arrays_evaluate(engine, n, text):
    if engine == "interp" and n > 10**6:
        n = 10**6  # the interpreter at 10⁷ points takes seconds
    e = expression(text, engine)
    x = np.linspace(-2.0, 2.0, n)
    got = survives(e, x, 0.5, x[::-1], time=1.0)
    assert got is not None
    assert got.shape[0] == n
    for i in (0, n // 2, n - 1):
        assert same_bits(np.reshape(got[i], -1), np.reshape(e(float(x[i]), 0.5, float(x[n - 1 - i]), time=1.0), -1))


@pytest.mark.parametrize("engine", ["jit", "interp"])
def test_broadcasts_too_large_for_memory_are_refused(engine):
    e = expression("x + v*t", engine)
    # 10¹² points (8 TB of results): refused before anything is allocated.
    a = np.zeros((10**6, 1))
    b = np.zeros((1, 10**6))
    with pytest.raises((ValueError, MemoryError)):
        e(a, b, 1.0)
    # A broadcast view of 10¹⁸ points, zero bytes each: numpy's own limit.
    huge = np.broadcast_to(np.zeros(1), (10**9, 10**9))
    with pytest.raises((ValueError, MemoryError)):
        e(huge, 1.0, 1.0)

"""Units of measure for plain expressions from Python (issue 24): `compile(...,
units={...})` checks the text, names what does not fit, and never changes a value. The
expected dimensions come from the physics (a length over a time is a velocity), not from
mbfx's output."""

from __future__ import annotations

import pickle

import pytest

import mbfx

ENGINES = ("jit", "interp")


@pytest.mark.parametrize("engine", ENGINES)
def test_a_sum_of_a_length_and_a_velocity_warns_and_keeps_its_value(engine):
    e = mbfx.compile(
        "x + v", variables=("x", "v"), engine=engine, units={"x": "length", "v": "m/s"}
    )
    assert e(1.0, 2.0) == 3.0
    [w] = e.warnings
    assert w.code == "W0312"
    assert "adds a length to a velocity" in w.message
    assert w.line == 1 and w.column == 1


def test_a_consistent_expression_has_its_dimension_and_no_warning():
    e = mbfx.compile(
        "x + v*TIME", variables=("x", "v"), units={"x": "mm", "v": "length/time"}
    )
    assert e.warnings == []
    assert e.dimension == "a length"
    f = mbfx.compile("k*x", variables=("k", "x"), units={"k": "N/m", "x": "m"})
    assert f.dimension == "a force"
    g = mbfx.compile("SIN(w*TIME)", variables=("w",), units={"w": "rad/s"})
    assert g.warnings == [] and g.dimension == "a dimensionless quantity"


def test_a_transcendental_of_a_length_warns():
    e = mbfx.compile("SIN(x)", variables=("x",), units={"x": "length"})
    [w] = e.warnings
    assert "the argument of SIN is a length" in w.message


def test_without_units_nothing_is_checked():
    e = mbfx.compile("x + TIME", variables=("x",))
    assert e.warnings == [] and e.units == {} and e.dimension is None


def test_units_survive_pickling_and_gradients():
    e = mbfx.compile("x + v", variables=("x", "v"), units={"x": "m", "v": "m/s"})
    back = pickle.loads(pickle.dumps(e))
    assert back.units == {"x": "length", "v": "length/time"}
    assert [w.code for w in back.warnings] == ["W0312"]
    g = e.gradient(["x"])
    assert g.units == e.units
    assert pickle.loads(pickle.dumps(g)).units == e.units


def test_a_dimension_that_does_not_read_or_names_no_variable_is_an_error():
    with pytest.raises(ValueError, match="`furlong` is not a unit"):
        mbfx.compile("x", variables=("x",), units={"x": "furlong"})
    with pytest.raises(mbfx.CheckError, match="not one of the variables"):
        mbfx.compile("x", variables=("x",), units={"y": "m"})

"""Fuzz tests (issue 41 §3): random `.adm` text through `mbfx.load` (mutations of a
small model, statements put together from the language's words, any text), and random
keyword arguments to `Model.run`, `Model.linearize` and `mbfx.study.run`. A finding is as
in test_fuzz_expressions.py (`conftest.survives`).

Bounds that keep each example short, not the surface's: an end time at most 0.2 s or
not a positive finite number, and output and integrator steps of at least 10⁻³ s or not
positive finite numbers (a run to 10³⁰⁸ s, or one of 10¹⁵ output rows, is a valid request
that would only take long)."""

from __future__ import annotations

import math

from hypothesis import given, settings
from hypothesis import strategies as st

import mbfx
from conftest import OSCILLATOR, survives

LINES = OSCILLATOR.splitlines()

# Words of the dataset language: statements, arguments, values good and bad.
WORDS = [
    "PART/", "MARKER/", "JOINT/", "SFORCE/", "GFORCE/", "MOTION/", "VARIABLE/", "DIFF/",
    "SPLINE/", "CONTACT/", "FRICTION/", "REQUEST/", "OUTPUT/", "ACCGRAV/", "INTEGRATOR/",
    "GROUND", "MASS", "CM", "IP", "QP", "REULER", "ZP", "XP", "I", "J", "FUNCTION", "TRANSLATION",
    "ROTATION", "REVOLUTE", "TRANSLATIONAL", "SPHERICAL", "FIXED", "X", "Y", "IC", "=", ",", ", ",
    "1", "2", "11", "21", "0", "-1", "1E400", "1e-320", "90D", "NaN", "inf", "DM(21, 11)", "\n",
    "&\n", "!", "END", "UNITS/", "FORCE", "NEWTON", " ", "(", ")", "é", "\x00", "\t",
]

BAD_VALUES = ["0", "-1", "1E400", "-1E400", "1e-320", "nan", "inf", "", "abc", "1, 2", "(", "0D", "=", "&"]


@st.composite
def datasets(draw):
    """A dataset's text: the oscillator with a few lines changed, or words put together,
    or any text (with a line break, so that `load` reads it as text)."""
    kind = draw(st.sampled_from(["mutated", "words", "any"]))
    if kind == "mutated":
        lines = list(LINES)
        for _ in range(draw(st.integers(1, 4))):
            i = draw(st.integers(0, len(lines) - 1))
            op = draw(st.sampled_from(["drop", "copy", "value", "cut", "words"]))
            if op == "drop" and len(lines) > 1:
                del lines[i]
            elif op == "copy":
                lines.insert(i, lines[i])
            elif op == "value":
                tokens = lines[i].split(" ")
                j = draw(st.integers(0, len(tokens) - 1))
                tokens[j] = draw(st.sampled_from(BAD_VALUES))
                lines[i] = " ".join(tokens)
            elif op == "cut":
                lines[i] = lines[i][: draw(st.integers(0, len(lines[i])))]
            else:
                lines.insert(i, "".join(draw(st.lists(st.sampled_from(WORDS), max_size=12))))
        return "\n".join(lines) + "\n"
    if kind == "words":
        return "title\n" + "".join(draw(st.lists(st.sampled_from(WORDS), max_size=40))) + "\nEND\n"
    return draw(st.text(max_size=200)) + "\n"


@given(text=datasets(), dim=st.one_of(st.none(), st.integers(-300, 300), st.sampled_from([2, 3])))
def test_random_datasets_load_or_are_refused(text, dim):
    model = survives(mbfx.load, text, dim)
    if model is None:
        return
    survives(model.check)
    survives(model.run, 0.02)


# Values of keyword arguments: each of the right type or of a wrong one.
weird_numbers = st.sampled_from([0.0, -0.0, -1.0, math.nan, math.inf, -math.inf, 5e-324, 1e308, -(2**64)])
ends = st.one_of(st.none(), st.floats(0.001, 0.2), weird_numbers)
steps = st.one_of(st.none(), st.floats(1e-3, 0.1), weird_numbers)
anything = st.one_of(st.none(), st.booleans(), st.integers(-(2**70), 2**70), st.floats(), st.text(max_size=8), st.lists(st.integers(), max_size=2))
settings_keys = st.sampled_from(["PART/2.MASS", "SFORCE/1.FUNCTION", "PART/9.MASS", "MARKER/21.QP", "junk", "", "PART/2.NOPE"])
set_maps = st.one_of(st.none(), st.dictionaries(settings_keys, st.one_of(st.floats(), st.integers(-5, 5), st.text(max_size=12), st.sampled_from(["-10*(DM(21,11)-1)", "SIN(", "2"])), max_size=3), anything)

run_kwargs = st.fixed_dictionaries(
    {},
    optional={
        "end": ends,
        "output_step": steps,
        "integrator": st.one_of(st.sampled_from(["GSTIFF", "HHT", "dopri853", "WSTIFF", "SI2", "gstiff"]), anything),
        "error": st.one_of(st.floats(1e-8, 1e-2), weird_numbers, anything),
        "probes": st.one_of(st.dictionaries(st.sampled_from(["u", "", "time", "x y", "DX"]), st.sampled_from(["DX(21, 11)", "SIN(", "TIME", "DM(21, 99)", ""]), max_size=2), anything),
        "progress": st.booleans(),
        "hmax": steps,
        "hinit": steps,
        "hmin": st.one_of(st.none(), st.floats(1e-9, 1e-3), weird_numbers),
        "fixed_step": steps,
        "alpha": st.one_of(st.floats(-0.5, 0.1), weird_numbers),
        "rho_inf": st.one_of(st.floats(-0.5, 1.5), weird_numbers),
        "kmax": st.one_of(st.integers(-3, 8), st.sampled_from([2**31, 2**40, -(2**40)]), anything),
        "formulation": st.one_of(st.sampled_from(["I3", "SI2", "si1", "bogus"]), anything),
        "error_per": st.one_of(st.sampled_from(["step", "run", "bogus"]), anything),
        "cartesian": st.booleans(),
        "interpolate": st.booleans(),
        "engine": st.one_of(st.sampled_from(["jit", "interp"]), anything),
        "set": set_maps,
        "estimate_error": st.booleans(),
        "animation": st.one_of(st.none(), st.booleans()),
        "geometry": st.one_of(st.none(), st.dictionaries(st.integers(-2, 3), st.sampled_from(["/nonexistent.stl", "", "/dev/null"]), max_size=1)),
        "bogus": anything,
    },
)

_model = []


def oscillator() -> mbfx.Model:
    if not _model:
        _model.append(mbfx.load(OSCILLATOR))
    return _model[0]


@given(kwargs=run_kwargs)
def test_random_keyword_arguments_to_run(kwargs):
    kwargs.setdefault("end", 0.05)
    run = survives(oscillator().run, **kwargs)
    if run is not None:
        assert len(run.time) >= 1


@given(
    kwargs=st.fixed_dictionaries(
        {},
        optional={
            "statics": st.one_of(st.booleans(), anything),
            "end": ends,
            "damping": st.one_of(st.booleans(), anything),
            "engine": st.one_of(st.sampled_from(["jit", "interp"]), anything),
            "set": set_maps,
            "bogus": anything,
        },
    )
)
def test_random_keyword_arguments_to_linearize(kwargs):
    lin = survives(oscillator().linearize, **kwargs)
    if lin is not None:
        assert lin is not None


study_kwargs = st.fixed_dictionaries(
    {
        "factors": st.one_of(
            st.dictionaries(settings_keys, st.one_of(st.tuples(st.floats(), st.floats()), st.lists(st.floats(0.5, 2), min_size=1, max_size=2), anything), max_size=2),
            st.just({"PART/2.MASS": (0.5, 2.0)}),
            anything,
        ),
        "end": st.one_of(st.floats(0.001, 0.05), weird_numbers, anything),
    },
    optional={
        "responses": st.one_of(st.dictionaries(st.sampled_from(["peak", "", "variant"]), st.sampled_from(["max", "min", "final"]), max_size=2), anything),
        "design": st.one_of(st.sampled_from(["full", "lhs", "sobol", "bogus"]), anything),
        "n": st.one_of(st.integers(-2, 4), anything),
        "levels": st.one_of(st.integers(-1, 3), anything),
        "probes": st.one_of(st.just({"u": "DX(21, 11) - 1"}), anything),
        "templates": st.one_of(st.dictionaries(settings_keys, st.sampled_from(["-{k}*(DM(21, 11) - 1)", "{", "{}"]), max_size=1), anything),
        "run_args": st.one_of(st.dictionaries(st.sampled_from(["integrator", "error", "end", "bogus"]), anything, max_size=2), anything),
        "batch": st.one_of(st.integers(-1, 3), anything),
        "seed": st.one_of(st.integers(-1, 3), anything),
        "resume": st.booleans(),
    },
)


@settings(max_examples=max(5, settings.default.max_examples // 4))
@given(kwargs=study_kwargs)
def test_random_keyword_arguments_to_study(kwargs, client):
    from mbfx import study

    responses = kwargs.pop("responses", None)
    if isinstance(responses, dict):
        responses = {k: getattr(study, v)("u") for k, v in responses.items()}
    # A study of more than a few variants takes seconds: keep the designs small.
    if isinstance(kwargs.get("n"), int) and kwargs["n"] > 4:
        kwargs["n"] = 4
    survives(study.run, oscillator(), kwargs.pop("factors"), responses, client=client, **kwargs)

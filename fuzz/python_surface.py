"""The Python module's campaign fuzzer (issue 41 §3): atheris (libFuzzer for Python)
drives the calls of tests/python/test_fuzz_*.py, faster than hypothesis can, for the
10⁶-execution campaigns of docs/testing.md. Not run in CI (the hypothesis tests are).

Each input picks one call: `mbfx.compile` of random text over random names and engine,
then the expression called with random floats (NaN and infinities), numpy arrays of
random dtype, shape and stride, or keywords, and its gradient in random names; or
`mbfx.load` of random dataset text (the small oscillator mutated, or any text), checked,
and now and then run with random keyword arguments. A finding is what
`tests/python/conftest.survives` calls one: an InternalError, a PanicException or any
exception that is not mbfx's errors, ValueError or TypeError; it is raised out of the
target, so libFuzzer saves the input as a crash.

    pip install atheris==3.0.0
    cd tests/python && python ../../fuzz/python_surface.py -atheris_runs=1000000 /tmp/pycorpus
"""

import math
import sys

import atheris

with atheris.instrument_imports():
    import numpy as np

    import mbfx

sys.path.insert(0, ".")
from conftest import OSCILLATOR  # noqa: E402  (run from tests/python)

TEXTS = ["x + v*t", "[x, v, t]", "STEP(x, 0, 0, 1, v)", "x**v", "IF(x: 1, 2, 3)", "SIN(", "SQRT(x)*LOG(v)", "MAG([x, v, t])"]
NAMES = ["x", "v", "t", "X", "time", "TIME", "SIN", "PI", "", "1a", "a b", "é", "x\x00", "w"]
VALUES = [0.0, -0.0, 1.0, -1.0, 5e-324, 1e308, math.inf, -math.inf, math.nan, 0.5]
DTYPES = [np.float64, np.float32, np.int8, np.uint64, np.bool_, np.complex128, np.object_, np.str_, ">f8"]
LINES = OSCILLATOR.splitlines()
BAD = ["0", "-1", "1E400", "nan", "", "abc", "(", "=", "&", "1e-320"]
RUN_KEYS = ["output_step", "integrator", "error", "hmax", "hinit", "hmin", "kmax", "formulation", "error_per", "engine", "set", "probes", "alpha", "rho_inf"]
ANY = [None, True, -1, 0, 2**70, -(2**40), 0.0, -1.0, math.nan, math.inf, 1e-3, 0.01, "", "HHT", "GSTIFF", "bogus", [], {}, {"PART/2.MASS": "x"}, {"u": "SIN("}]

calls = 0


class Finding(Exception):
    """A result the surface must never give."""


def survives(call, *args, **kwargs):
    """As conftest.survives, but raising Finding (libFuzzer saves the input)."""
    global calls
    calls += 1
    try:
        return call(*args, **kwargs)
    except mbfx.InternalError as e:
        raise Finding(f"InternalError: {e}") from e
    except (mbfx.MbfxError, ValueError, TypeError):
        return None
    except (KeyboardInterrupt, SystemExit):
        raise
    except BaseException as e:  # noqa: B036 - pyo3's PanicException is a BaseException
        raise Finding(f"{type(e).__module__}.{type(e).__qualname__}: {e!r}") from e


def pick(fdp, items):
    return items[fdp.ConsumeIntInRange(0, len(items) - 1)]


def value(fdp):
    return pick(fdp, VALUES) if fdp.ConsumeBool() else fdp.ConsumeRegularFloat()


def array(fdp):
    shape = tuple(fdp.ConsumeIntInRange(0, 4) for _ in range(fdp.ConsumeIntInRange(0, 3)))
    a = np.full(shape, value(fdp))
    try:
        a = a.astype(pick(fdp, DTYPES))
    except (ValueError, OverflowError):
        pass
    if a.ndim and fdp.ConsumeBool():
        a = a[::-1]
    elif fdp.ConsumeBool():
        a = a.T
    return a


def argument(fdp):
    kind = fdp.ConsumeIntInRange(0, 3)
    if kind == 0:
        return value(fdp)
    if kind == 1:
        return array(fdp)
    if kind == 2:
        return fdp.ConsumeIntInRange(-5, 5)
    return pick(fdp, [None, "1.5", [1.0, 2.0], (), {}])


def expression_calls(fdp):
    text = pick(fdp, TEXTS) if fdp.ConsumeBool() else fdp.ConsumeUnicodeNoSurrogates(40)
    names = [pick(fdp, NAMES) for _ in range(fdp.ConsumeIntInRange(0, 4))]
    engine = pick(fdp, ["jit", "interp", "interp", "bogus"])
    e = survives(mbfx.compile, text, names, engine)
    if e is None:
        return
    for _ in range(fdp.ConsumeIntInRange(1, 4)):
        args = [argument(fdp) for _ in range(fdp.ConsumeIntInRange(0, len(names) + 1))]
        kwargs = {"time": argument(fdp)} if fdp.ConsumeBool() else {}
        if fdp.ConsumeBool() and names:
            kwargs[pick(fdp, NAMES)] = argument(fdp)
        survives(e, *args, **kwargs)
    if fdp.ConsumeBool():
        wrt = None if fdp.ConsumeBool() else [pick(fdp, NAMES) for _ in range(fdp.ConsumeIntInRange(0, 3))]
        g = survives(e.gradient, wrt)
        if g is not None:
            survives(g, *[value(fdp) for _ in names])


def model_calls(fdp):
    if fdp.ConsumeBool():
        lines = list(LINES)
        for _ in range(fdp.ConsumeIntInRange(1, 3)):
            i = fdp.ConsumeIntInRange(0, len(lines) - 1)
            tokens = lines[i].split(" ")
            tokens[fdp.ConsumeIntInRange(0, len(tokens) - 1)] = pick(fdp, BAD)
            lines[i] = " ".join(tokens)
        text = "\n".join(lines) + "\n"
    else:
        text = fdp.ConsumeUnicodeNoSurrogates(200) + "\n"
    dim = pick(fdp, [None, None, 2, 3, 0, -1, 300])
    model = survives(mbfx.load, text, dim)
    if model is None:
        return
    survives(model.check)
    if fdp.ConsumeIntInRange(0, 15) == 0:
        kwargs = {pick(fdp, RUN_KEYS): pick(fdp, ANY) for _ in range(fdp.ConsumeIntInRange(0, 3))}
        survives(model.run, 0.02, **kwargs)


def target(data):
    fdp = atheris.FuzzedDataProvider(data)
    if fdp.ConsumeIntInRange(0, 7) == 0:
        model_calls(fdp)
    else:
        expression_calls(fdp)


if __name__ == "__main__":
    import atexit

    atexit.register(lambda: print(f"python_surface: {calls} calls into mbfx", file=sys.stderr))
    atheris.Setup(sys.argv, target)
    atheris.Fuzz()

"""Shared fixtures of the Python suite: where the repository, `../shared` and the
command-line binary are, a helper that runs `mbfx` the way a user would, and the
hypothesis profiles of the fuzz tests (test_fuzz_*.py): "ci", the default, sized to
keep the suite's time, and "long" (HYPOTHESIS_PROFILE=long) for the campaigns."""

from __future__ import annotations

import os
import subprocess
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, settings

# The fuzz tests' sizes. "ci": a few seconds per test (the suite's added time stays
# under a minute); no deadline, since a first JIT compile or a loaded machine may take
# longer than hypothesis' 200 ms default. "long": the campaigns of docs/testing.md
# (`HYPOTHESIS_PROFILE=long`, with HYPOTHESIS_MAX_EXAMPLES to set the count).
settings.register_profile(
    "ci",
    max_examples=60,
    deadline=None,
    derandomize=True,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
    print_blob=True,
)
settings.register_profile(
    "long",
    max_examples=int(os.environ.get("HYPOTHESIS_MAX_EXAMPLES", "200000")),
    deadline=None,
    suppress_health_check=list(HealthCheck),
    print_blob=True,
)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))

ROOT = Path(__file__).resolve().parents[2]
SHARED = ROOT.parent / "shared"


def cli_binary() -> Path:
    """The release binary `cargo test --workspace --release` (the README's test command)
    builds before pytest runs; MBFX_BIN overrides it."""
    return Path(os.environ.get("MBFX_BIN", ROOT / "target" / "release" / "mbfx"))


def run_cli(*args: str, check: bool = False) -> subprocess.CompletedProcess:
    """Runs the command-line `mbfx` with `args`, capturing its output as text."""
    return subprocess.run(
        [str(cli_binary()), *args], capture_output=True, text=True, check=check, timeout=120
    )


@pytest.fixture(scope="session")
def cli() -> Path:
    path = cli_binary()
    if not path.exists():
        pytest.fail(f"{path} is missing: build it first (cargo build --release)")
    return path


@pytest.fixture(scope="session")
def client():
    """A LocalCluster of two worker processes for the study tests, shared by the session."""
    from distributed import Client, LocalCluster

    cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0")
    with cluster, Client(cluster) as c:
        yield c


@pytest.fixture(scope="session")
def shared() -> Path:
    if not (SHARED / "corpus").is_dir():
        pytest.fail(f"{SHARED} (spec and corpus) must be beside the repository")
    return SHARED


# A block on a frictionless rail held by a linear spring of free length 1 to a ground
# point 1 m away (so the line of action never degenerates), released 0.1 beyond it at
# rest: u(t) = DX(21, 11) - 1 = 0.1 cos(sqrt(k/m) t) exactly (no gravity along the rail).
OSCILLATOR = """Spring-mass oscillator
UNITS/FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND
PART/1, GROUND
MARKER/11, PART = 1, QP = -1, 0, 0, REULER = 90D, 90D, 0D
PART/2, MASS = 1, CM = 21, IP = 1, 1, 1
MARKER/21, PART = 2, QP = 0.1, 0, 0, REULER = 90D, 90D, 0D
JOINT/1, TRANSLATIONAL, I = 21, J = 11
SFORCE/1, TRANSLATION, I = 21, J = 11, FUNCTION = -100*(DM(21, 11) - 1)
END
"""


def missing_docstrings(module) -> list:
    """The names of `module.__all__`, and the public methods and properties of its
    classes, that have no docstring (a data attribute's doc would be its type's)."""
    missing = []
    for name in module.__all__:
        obj = getattr(module, name)
        if not isinstance(obj, str) and not (obj.__doc__ or "").strip():
            missing.append(name)
        if isinstance(obj, type):
            for attr, member in vars(obj).items():
                code = callable(member) or isinstance(member, (property, staticmethod, classmethod))
                if code and not attr.startswith("_") and not (getattr(member, "__doc__", None) or "").strip():
                    missing.append(f"{name}.{attr}")
    return missing


def same_bits(a: np.ndarray, b: np.ndarray) -> bool:
    """Equal shapes and every value equal bit for bit, NaN equal to NaN."""
    a, b = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
    if a.shape != b.shape:
        return False
    nan = np.isnan(a)
    return bool(np.array_equal(nan, np.isnan(b)) and np.array_equal(a[~nan].view(np.uint64), b[~nan].view(np.uint64)))


# Calls made through `survives` in this session (the fuzz campaigns' figure).
FUZZ_CALLS = 0


def pytest_terminal_summary(terminalreporter):
    if FUZZ_CALLS:
        terminalreporter.write_line(f"fuzz: {FUZZ_CALLS} calls into mbfx through conftest.survives")


def survives(call, *args, **kwargs):
    """`call(*args, **kwargs)`'s result, or None when it raised one of the errors a bad
    input may raise (mbfx's CheckError, RunError and MbfxError, ValueError, TypeError).
    Fails the test on anything else: an InternalError or a PanicException (a Rust panic,
    a BaseException) or any other exception type is a finding of the fuzz tests."""
    import mbfx

    global FUZZ_CALLS
    FUZZ_CALLS += 1
    try:
        return call(*args, **kwargs)
    except mbfx.InternalError as e:
        pytest.fail(f"InternalError (a panic inside mbfx): {e}")
    except (mbfx.MbfxError, ValueError, TypeError):
        return None
    except (KeyboardInterrupt, SystemExit):
        raise
    except BaseException as e:  # noqa: B036 - pyo3's PanicException is a BaseException
        pytest.fail(f"{type(e).__module__}.{type(e).__qualname__} is not an error mbfx may raise: {e!r}")

"""Shared fixtures of the Python suite: where the repository, `../shared` and the
command-line binary are, and a helper that runs `mbfx` the way a user would."""

from __future__ import annotations

import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

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
def shared() -> Path:
    if not (SHARED / "corpus").is_dir():
        pytest.fail(f"{SHARED} (spec and corpus) must be beside the repository")
    return SHARED


def same_bits(a: np.ndarray, b: np.ndarray) -> bool:
    """Equal shapes and every value equal bit for bit, NaN equal to NaN."""
    a, b = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
    if a.shape != b.shape:
        return False
    nan = np.isnan(a)
    return bool(np.array_equal(nan, np.isnan(b)) and np.array_equal(a[~nan].view(np.uint64), b[~nan].view(np.uint64)))

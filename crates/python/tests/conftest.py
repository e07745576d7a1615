"""Shared fixtures: the `wearsim` binary the Python results are compared with."""

import os
import shutil
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[3]


@pytest.fixture(scope="session")
def wearsim() -> str:
    """Path of the release `wearsim` (scripts/test sets WEARSIM; else the default target)."""
    candidates = [os.environ.get("WEARSIM"), shutil.which("wearsim")]
    target = os.environ.get("CARGO_TARGET_DIR", str(ROOT / "target"))
    candidates.append(str(Path(target) / "release" / "wearsim"))
    for c in candidates:
        if c and Path(c).is_file():
            return c
    pytest.fail("no wearsim binary: build it (cargo build --release) or set WEARSIM")

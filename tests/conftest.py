"""Shared pytest configuration for the pyrosgen test suite."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent

# Make the package importable even when pytest runs outside the venv's
# editable install (it is installed editable by `make venv`).
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))


@pytest.fixture(scope="session")
def repo_root() -> Path:
    """The repository root."""
    return ROOT

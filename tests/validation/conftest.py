"""Fixtures of the validation tests: the two example nodes, generated once
per session by the real pipeline (``pyrosgen.generate.generate``)."""

from __future__ import annotations

from pathlib import Path

import pytest

from pyrosgen.generate import generate

from support.validation import EXAMPLES, GeneratedNode


@pytest.fixture(scope="session")
def generated(tmp_path_factory) -> dict[str, GeneratedNode]:
    """``pyrosgen generate`` on LandShark and multi: key -> GeneratedNode."""
    out: dict[str, GeneratedNode] = {}
    base = tmp_path_factory.mktemp("validation_generated")
    for key, (model_path, node) in EXAMPLES.items():
        d = base / key
        res = generate(model_path, d)
        out[key] = GeneratedNode(key, node, Path(d), res)
    return out

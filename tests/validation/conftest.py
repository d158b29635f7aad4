"""Fixtures of the validation tests: the two example nodes, generated once
per session by the real pipeline (``pyrosgen.generate.generate``)."""

from __future__ import annotations

from pathlib import Path

import pytest

from pyrosgen.generate import generate

from support.validation import EXAMPLES, TIMED_EXAMPLES, GeneratedNode


def _generate(tmp_path_factory, examples: dict, what: str) -> dict[str, GeneratedNode]:
    out: dict[str, GeneratedNode] = {}
    base = tmp_path_factory.mktemp(what)
    for key, (model_path, node) in examples.items():
        d = base / key
        res = generate(model_path, d)
        out[key] = GeneratedNode(key, node, Path(d), res)
    return out


@pytest.fixture(scope="session")
def generated(tmp_path_factory) -> dict[str, GeneratedNode]:
    """``pyrosgen generate`` on LandShark and multi: key -> GeneratedNode."""
    return _generate(tmp_path_factory, EXAMPLES, "validation_generated")


@pytest.fixture(scope="session")
def generated_timed(tmp_path_factory) -> dict[str, GeneratedNode]:
    """``pyrosgen generate`` on the models with timed topics (rule 4.12)."""
    return _generate(tmp_path_factory, TIMED_EXAMPLES, "validation_generated_timed")

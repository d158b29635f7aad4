"""Helpers shared by the front-end tests."""

from __future__ import annotations

import re
from pathlib import Path

HERE = Path(__file__).resolve().parents[1] / "frontend"
MODELS = HERE / "models"
REPO = HERE.parent.parent
LANDSHARK = REPO / "examples" / "landshark" / "landshark_controller.yaml"
MULTI = MODELS / "ok_multi.yaml"

_EXPECT = re.compile(r"#\s*expect:\s*(?:(?P<file>[^:\s]+\.msg):)?(?P<line>\d+|-):\s*(?P<frag>.+?)\s*$")


def expectations(path: Path) -> list[tuple[str | None, int | None, str]]:
    """The ``# expect: [FILE.msg:]LINE: fragment`` comments of a ko file
    (``LINE`` is ``-`` for a diagnostic about a whole file)."""
    out = []
    for line in path.read_text(encoding="utf-8").splitlines():
        m = _EXPECT.match(line)
        if m:
            out.append(
                (m.group("file"), int(m.group("line")) if m.group("line") != "-" else None, m.group("frag"))
            )
    return out


# ---------------------------------------------------------------------------
# A model written from a test's text, and its diagnostics

def write(tmp_path: Path, text: str, name: str = "m.yaml") -> Path:
    """``text`` written as the model file ``name`` in ``tmp_path``."""
    p = tmp_path / name
    p.write_text(text, encoding="utf-8")
    return p


def load(tmp_path: Path, text: str):
    """The node model of ``text`` (raises InvalidNodeModel)."""
    from pyrosgen import load_model

    return load_model(write(tmp_path, text))


def diags(tmp_path: Path, text: str) -> list[tuple[int, int, str, str]]:
    """The diagnostics of the model ``text``, which must be refused, as
    (line, column, message, rule)."""
    import pytest

    from pyrosgen import InvalidNodeModel

    with pytest.raises(InvalidNodeModel) as info:
        load(tmp_path, text)
    return [(d.line, d.col, d.message, d.rule) for d in info.value.diagnostics]


def one(tmp_path: Path, text: str) -> tuple[int, int, str, str]:
    """The one diagnostic of the model ``text``."""
    found = diags(tmp_path, text)
    assert len(found) == 1, found
    return found[0]


def at(text: str, needle: str, nth: int = 0) -> tuple[int, int]:
    """The 1-based (line, column) of the ``nth`` (from 0) ``needle`` in
    ``text``."""
    i = -1
    for _ in range(nth + 1):
        i = text.index(needle, i + 1)
    return text.count("\n", 0, i) + 1, i - (text.rfind("\n", 0, i) + 1) + 1


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

"""The layout rules of the Coq library (coq/README.md, DESIGN.md sections 3
and 6): files of at most 1,500 lines, every file in ``_CoqProject``, and
the dependencies that keep the specification and the dump independent of
what they check."""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

import pytest

COQ = Path(__file__).resolve().parents[2] / "coq"
MAX_LINES = 1500


def _project_files() -> list[str]:
    return [ln.strip() for ln in (COQ / "_CoqProject").read_text().splitlines()
            if ln.strip().startswith("theories/")]


def _deps(vfile: str) -> set[str]:
    """The library modules ``vfile`` loads directly (coqdep)."""
    out = subprocess.run(["coqdep", "-R", "theories", "ROSGen", vfile], cwd=COQ,
                         capture_output=True, text=True, check=True).stdout
    first = next(ln for ln in out.splitlines() if ln.startswith(vfile[:-2] + ".vo "))
    return {Path(p).stem for p in re.findall(r"theories/\S+\.vo", first.split(":", 1)[1])}


def test_every_theory_file_is_listed():
    listed = set(_project_files())
    actual = {str(p.relative_to(COQ)) for p in (COQ / "theories").rglob("*.v")}
    assert listed == actual


@pytest.mark.parametrize("vfile", _project_files())
def test_file_at_most_1500_lines(vfile):
    n = len((COQ / vfile).read_text(encoding="utf-8").splitlines())
    assert n <= MAX_LINES, f"{vfile} has {n} lines (at most {MAX_LINES}: split it along its concerns)"


def test_specification_does_not_load_the_generator():
    """DDC.v states its own constants: it loads neither the generator nor
    anything that loads it (its direct dependencies are checked; none of
    them depends on Generator either)."""
    deps = _deps("theories/glue/DDC.v")
    assert "NodeModel" in deps and "Semantics" in deps
    assert "Generator" not in deps
    for d in deps:
        src = next(f for f in _project_files() if Path(f).stem == d)
        assert "Generator" not in _deps(src), (d, "loads Generator")


def test_dump_does_not_load_the_printer():
    deps = _deps("theories/clight/Dump.v")
    assert deps == {"Syntax"}

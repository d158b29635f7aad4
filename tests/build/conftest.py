"""Fixtures of the ``pyrosgen build`` tests: one command-line build of the
LandShark example per session, shared (tests copy it before changing it)."""

from __future__ import annotations

import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent.parent
LANDSHARK = ROOT / "examples" / "landshark" / "landshark_controller.yaml"
LANDSHARK_CTL = ROOT / "examples" / "landshark" / "controller"
MULTI = ROOT / "examples" / "multi" / "multi_node.yaml"
MULTI_CTL = ROOT / "examples" / "multi" / "controller"


@dataclass
class Run:
    returncode: int
    stdout: str
    stderr: str


def pyrosgen(*args: str, env: dict | None = None, cwd: Path = ROOT) -> Run:
    """Run the command line as a user would (``python -m pyrosgen``)."""
    r = subprocess.run([sys.executable, "-m", "pyrosgen", *map(str, args)], cwd=cwd, env=env,
                       capture_output=True, text=True, stdin=subprocess.DEVNULL, timeout=900)
    return Run(r.returncode, r.stdout, r.stderr)


@pytest.fixture(scope="session")
def landshark_build(tmp_path_factory) -> tuple[Run, Path]:
    """``pyrosgen build`` of examples/landshark into a fresh folder."""
    out = tmp_path_factory.mktemp("build") / "landshark"
    run = pyrosgen("build", LANDSHARK, "--controller", LANDSHARK_CTL, "-o", out)
    assert run.returncode == 0, run.stderr
    return run, out


def snapshot(root: Path) -> dict[str, tuple[bytes, int]]:
    """Every file under ``root``: content and mode."""
    return {str(p.relative_to(root)): (p.read_bytes(), p.stat().st_mode)
            for p in sorted(root.rglob("*")) if p.is_file()}


def assert_wrapper_refused(cpp: str, old: str, new: str, proved: str) -> None:
    """The wrapper ``cpp`` with ``old`` replaced by ``new`` (once) is
    refused by the wrapper check against the proved model text ``proved``,
    with the reasons listed."""
    from pyrosgen.verify.wrapper_check import WrapperMismatch, check_wrapper

    assert old in cpp, f"the wrapper template changed shape: {old!r}"
    with pytest.raises(WrapperMismatch) as info:
        check_wrapper(cpp.replace(old, new, 1), proved, wrapper_name="w.cpp")
    assert "does not implement the proved model's interface" in info.value.summary
    assert info.value.lines

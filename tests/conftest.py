"""Shared pytest configuration for the pyrosgen test suite."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent

# Make the package importable even when pytest runs outside the venv's
# editable install (it is installed editable by `make venv`).
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))
# Shared helpers are imported as support.<module> (tests/support).
if str(ROOT / "tests") not in sys.path:
    sys.path.insert(0, str(ROOT / "tests"))


@pytest.fixture(scope="session")
def repo_root() -> Path:
    """The repository root."""
    return ROOT


# --------------------------------------------------------------------------
# Markers: `ros` (a real master or a roscpp build), `wp` (Frama-C), `slow`.
# `pytest -m "not ros"` runs the fast part.  They are given by folder and
# file here, in one place, and registered in pyproject.toml
# (--strict-markers refuses an unknown one).

_BY_PATH = {
    ("ros",): ("ros",),
    ("build",): ("ros",),
    ("ros2",): ("ros2",),
    ("validation", "test_wp.py"): ("wp", "slow"),
    ("validation", "test_difftest.py"): ("slow",),
}


def pytest_collection_modifyitems(config, items):
    for item in items:
        try:
            rel = Path(str(item.fspath)).resolve().relative_to(ROOT / "tests").parts
        except ValueError:
            continue
        for key, marks in _BY_PATH.items():
            if rel[: len(key)] == key:
                for mark in marks:
                    item.add_marker(getattr(pytest.mark, mark))


# --------------------------------------------------------------------------
# No process left behind, checked once at the end of the session, whatever
# the order of the tests: every process the real-ROS tests started (their
# PIDs are recorded by tests/support/ros.py) must be gone.


def _survivors() -> list[tuple[int, str]]:
    out = []
    for mod in list(sys.modules.values()):
        started = getattr(mod, "STARTED", None)
        alive = getattr(mod, "alive", None)
        if getattr(mod, "__name__", "") == "support.ros" and started is not None and alive is not None:
            out += [(pid, what) for pid, what in started if alive(pid)]
    return out


#: With pytest-xdist (``make test`` runs ``-n 2``), the survivors each
#: worker found, reported to the controlling process.
_WORKER_SURVIVORS: list[tuple[int, str]] = []


@pytest.hookimpl(optionalhook=True)
def pytest_testnodedown(node, error):
    """(xdist, in the controlling process) a worker ended: keep what it
    found still running."""
    _WORKER_SURVIVORS.extend((int(p), str(w)) for p, w in getattr(node, "workeroutput", {}).get("survivors", []))


def pytest_sessionfinish(session, exitstatus):
    survivors = _survivors()
    workeroutput = getattr(session.config, "workeroutput", None)
    if workeroutput is not None:
        # an xdist worker: its exit status is not the run's, so the
        # controlling process reports (pytest_testnodedown)
        workeroutput["survivors"] = [[pid, what] for pid, what in survivors]
        return
    survivors += _WORKER_SURVIVORS
    if survivors:
        session.config.pluginmanager.get_plugin("terminalreporter").write_line(
            f"error: processes started by the tests still running: {survivors}", red=True
        )
        session.exitstatus = pytest.ExitCode.TESTS_FAILED


@pytest.fixture
def mount_point(tmp_path):
    """A tmpfs mounted on a fresh folder (needs root, as on the project's
    machines); unmounted afterwards."""
    mnt = tmp_path / "mnt"
    mnt.mkdir()
    r = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=64m", "tmpfs", str(mnt)], capture_output=True, text=True)
    assert r.returncode == 0, f"cannot mount a tmpfs (this test needs root): {r.stderr.strip()}"
    try:
        yield mnt
    finally:
        subprocess.run(["umount", "-l", str(mnt)], check=False)

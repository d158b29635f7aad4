"""Fixtures for the ROS 2 tests (marker ``ros2``): the ROS 2 installation
(``make ros2-deps``), the environment of every ROS 2 process (one module
sets it: :func:`pyrosgen.ros2.env.ros2_env`, loopback discovery and a
domain of this test session's own, set here before any ROS 2 process
starts), nodes built once per session, and the process helpers: every
process is started in a group of its own, recorded in ``support.ros.STARTED``
(the session fails if one survives) and stopped by its PID."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import threading
import time
from pathlib import Path

import pytest

from pyrosgen.ros2.env import find_ros2, ros2_env

from support import ros as rosutil



def _session_domain() -> int | None:
    """Under pytest-xdist (``make test``: ``-n 2``), one domain per worker,
    derived from the controlling process's id, so that the workers' nodes
    and peers (same topic names) never meet; else ros2_env's own (from this
    process's id)."""
    worker = os.environ.get("PYTEST_XDIST_WORKER", "")
    if worker.startswith("gw") and worker[2:].isdigit():
        return 102 + (os.getppid() % 40) * 3 + int(worker[2:]) % 3
    return None


# The whole session's environment: loopback discovery, a domain of its own.
os.environ.update(ros2_env(domain_id=_session_domain()))

PEER = Path(__file__).resolve().parent / "peer.py"
SHM = Path("/dev/shm")


@pytest.fixture(scope="session")
def ros2_install():
    """The ROS 2 installation (``make ros2-deps``); the tests fail, never
    skip, without it."""
    return find_ros2()


@pytest.fixture(scope="session")
def ros2_nodes(tmp_path_factory) -> Path:
    return tmp_path_factory.mktemp("ros2nodes")


def fastdds_segments() -> set[str]:
    """Fast DDS's shared-memory segments and their semaphores."""
    return {p.name for p in [*SHM.glob("fastdds_*"), *SHM.glob("sem.fastdds_*")]}


def segments_of(pid: int) -> set[str]:
    """The Fast DDS segments process ``pid`` has mapped (its /proc maps)."""
    try:
        text = Path(f"/proc/{pid}/maps").read_text()
    except OSError:
        return set()
    out = set()
    for line in text.splitlines():
        path = line.split(maxsplit=5)[5] if len(line.split(maxsplit=5)) == 6 else ""
        if path.startswith("/dev/shm/") and ("/fastdds_" in path or "/sem.fastdds_" in path):
            out.add(path.split("/dev/shm/", 1)[1].split(" ", 1)[0])
    return out


def in_use() -> set[str]:
    """The Fast DDS segments some live process maps."""
    out: set[str] = set()
    for d in Path("/proc").iterdir():
        if d.name.isdigit():
            out |= segments_of(int(d.name))
    return out


#: every Fast DDS segment a process started by these tests was seen to map
#: (sampled while it ran): the only ones the tests may call theirs
OWNED: set[str] = set()


def _watch(p: subprocess.Popen) -> None:
    while p.poll() is None:
        OWNED.update(segments_of(p.pid))
        time.sleep(0.1)


def leftover_segments() -> set[str]:
    """Segments that processes these tests started mapped, still present,
    and mapped by no live process: left behind by them."""
    return (OWNED & fastdds_segments()) - in_use()


def settled_leftovers(timeout: float = 15.0) -> set[str]:
    """:func:`leftover_segments`, once given ``timeout`` s to go: under
    pytest -n 2 a semaphore that both workers' processes mapped (a port's
    mutex, ``sem.fastdds_port7000_mutex``) is unlinked by the last of them
    to close it, which may be the other worker's, seconds after ours exited;
    what is still there after ``timeout`` was left behind."""
    left = leftover_segments()
    deadline = time.monotonic() + timeout
    while left and time.monotonic() < deadline:
        time.sleep(0.5)
        left = leftover_segments()
    return left


@pytest.fixture
def shm_guard():
    """After the test, the shared-memory segments its processes left behind
    (:func:`leftover_segments`: by ownership, never another process's) are
    removed."""
    yield
    for name in leftover_segments():
        try:
            (SHM / name).unlink()
        except OSError:
            pass


def spawn(argv, log: Path, extra_env: dict | None = None) -> subprocess.Popen:
    """Start a ROS 2 process in the ROS 2 environment (no LD_LIBRARY_PATH:
    a node finds its libraries by its DT_RPATH), in a process group of its
    own, its output into ``log``; its PID is recorded."""
    out = open(log, "wb")
    p = subprocess.Popen([str(a) for a in argv], stdout=out, stderr=subprocess.STDOUT,
                         env={**ros2_env(), **(extra_env or {})}, start_new_session=True)
    out.close()
    rosutil.STARTED.append((p.pid, " ".join(str(a) for a in argv)))
    threading.Thread(target=_watch, args=(p,), daemon=True).start()
    return p


def start_launch(text: str, out: Path, install: Path | None, work: Path, procs: list) -> None:
    """Start every node of the ROS 2 launch file ``text`` as ``ros2
    launch`` would (:func:`pyrosgen.system.launch.read_ros2_launch`), from
    ``system build``'s binaries (``out/<folder>/bin/<exec>``) or, with
    ``install``, from those colcon installed (``install/PKG/lib/PKG/EXEC``,
    where ``ros2 launch`` finds a node's ``pkg`` and ``exec``); each
    process's output into ``work/<folder>.log``.  Appends (full name,
    process) to ``procs`` as each starts: the caller stops them."""
    from pyrosgen.system.launch import read_ros2_launch

    for n in read_ros2_launch(text):
        exe = install / n.pkg / "lib" / n.pkg / n.exec if install is not None else out / n.folder / "bin" / n.exec
        procs.append((n.full_name, spawn(n.argv(exe), work / f"{n.folder}.log")))


def stop(p: subprocess.Popen, sig: int = signal.SIGTERM, timeout: float = 15.0) -> int | None:
    """Send ``sig`` to the process; its exit status if it ended within
    ``timeout`` s, else it is killed (its group) and ``None`` returned."""
    if p.poll() is not None:
        return p.returncode
    p.send_signal(sig)
    try:
        return p.wait(timeout=timeout)
    except subprocess.TimeoutExpired:
        os.killpg(p.pid, signal.SIGKILL)
        p.wait()
        return None


def start_peer(plan: dict, work: Path, install, name: str = "peer") -> subprocess.Popen:
    """Start the rclpy peer (peer.py) on ``plan``; :func:`run_peer` waits for it."""
    plan_file, result_file = work / f"{name}.plan.json", work / f"{name}.result.json"
    plan_file.write_text(json.dumps(plan))
    return spawn([install.python, PEER, plan_file, result_file], work / f"{name}.log")


def run_peer(plan: dict, work: Path, install, name: str = "peer", timeout: float = 120,
             started: subprocess.Popen | None = None) -> dict:
    """Run the rclpy peer (peer.py) on ``plan`` (or wait for the one
    ``started``); its result."""
    result_file = work / f"{name}.result.json"
    p = started if started is not None else start_peer(plan, work, install, name)
    try:
        rc = p.wait(timeout=timeout)
    except subprocess.TimeoutExpired:
        stop(p, signal.SIGKILL)
        raise AssertionError(f"the rclpy peer did not finish within {timeout} s")
    log = (work / f"{name}.log").read_text(errors="replace")
    assert result_file.is_file(), f"the rclpy peer wrote no result (exit {rc}):\n{log[-3000:]}"
    result = json.loads(result_file.read_text())
    if not plan.get("run_anyway"):
        assert result["matched_after"] is not None, f"no discovery match within {plan['match_timeout']} s:\n{log[-3000:]}"
    return result


def wait_for(pred, timeout: float) -> bool:
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if pred():
            return True
        time.sleep(0.05)
    return pred()

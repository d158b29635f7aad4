"""Start and stop a private ROS 1 master on 127.0.0.1 at a free port.

Used by the real-ROS tests and by ``make demo``.  Only processes started here
are ever stopped, by their PID (each in its own process group, so that their
children go too), and they are stopped even when the caller fails.
"""

from __future__ import annotations

import contextlib
import os
import signal
import socket
import subprocess
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Iterator

ROSMASTER = "/usr/bin/rosmaster"


def free_port() -> int:
    """A TCP port on 127.0.0.1 that is free right now."""
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _port_open(port: int) -> bool:
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.settimeout(0.2)
        return s.connect_ex(("127.0.0.1", port)) == 0


def stop_process(proc: subprocess.Popen, timeout: float = 5.0) -> None:
    """Stop ``proc`` and its process group: SIGINT, then SIGTERM, then SIGKILL."""
    if proc.poll() is not None:
        return
    for sig, wait in ((signal.SIGINT, timeout), (signal.SIGTERM, 2.0), (signal.SIGKILL, 2.0)):
        try:
            os.killpg(proc.pid, sig)
        except ProcessLookupError:
            return
        try:
            proc.wait(wait)
            return
        except subprocess.TimeoutExpired:
            continue


@dataclass
class RosEnv:
    """A running private master and the environment that points at it."""

    port: int
    home: Path
    proc: subprocess.Popen | None = None
    children: list[subprocess.Popen] = field(default_factory=list)

    @property
    def uri(self) -> str:
        return f"http://127.0.0.1:{self.port}"

    @property
    def env(self) -> dict[str, str]:
        e = dict(os.environ)
        e.update(ROS_MASTER_URI=self.uri, ROS_IP="127.0.0.1", ROS_HOSTNAME="127.0.0.1",
                 ROS_HOME=str(self.home), ROS_LOG_DIR=str(self.home / "log"))
        e.pop("ROS_NAMESPACE", None)
        return e

    def start_master(self, timeout: float = 20.0) -> None:
        """(Re)start the master on ``self.port`` and wait until it accepts calls."""
        if not Path(ROSMASTER).exists():
            raise RuntimeError(f"{ROSMASTER} not found: install python3-rosmaster (make deps)")
        log = open(self.home / "rosmaster.log", "ab")
        self.proc = subprocess.Popen(
            [ROSMASTER, "--core", "-p", str(self.port), "-w", "2"],
            env=self.env, stdout=log, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL,
            start_new_session=True)
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            if self.proc.poll() is not None:
                raise RuntimeError(f"rosmaster exited with {self.proc.returncode}; "
                                   f"see {self.home / 'rosmaster.log'}")
            if _port_open(self.port):
                return
            time.sleep(0.1)
        raise RuntimeError(f"rosmaster did not listen on port {self.port} within {timeout} s")

    def stop_master(self) -> None:
        if self.proc is not None:
            stop_process(self.proc)
            self.proc = None

    def spawn(self, argv: list[str], **kw) -> subprocess.Popen:
        """Start a process (a node, a driver) against this master; it is
        stopped by :meth:`close` if still running."""
        kw.setdefault("env", self.env)
        kw.setdefault("stdin", subprocess.DEVNULL)
        p = subprocess.Popen(argv, start_new_session=True, **kw)
        self.children.append(p)
        return p

    def close(self) -> None:
        for p in reversed(self.children):
            stop_process(p)
        self.children.clear()
        self.stop_master()


@contextlib.contextmanager
def ros_master(home: Path | None = None) -> Iterator[RosEnv]:
    """A private master for the duration of the ``with`` block."""
    tmp = None
    if home is None:
        tmp = tempfile.TemporaryDirectory(prefix="pyrosgen-ros-")
        home = Path(tmp.name)
    (home / "log").mkdir(parents=True, exist_ok=True)
    env = RosEnv(port=free_port(), home=home)
    try:
        env.start_master()
        yield env
    finally:
        env.close()
        if tmp is not None:
            tmp.cleanup()

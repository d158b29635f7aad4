"""No process left behind: a master and a node started and stopped by this
test are gone, with every process the real-ROS tests started so far
(recorded by PID in ``rosutil.STARTED``).  The same check runs once more at
the very end of the session, whatever the order of the tests
(``pytest_sessionfinish`` in ``tests/conftest.py``)."""

from __future__ import annotations

import os
from pathlib import Path

from support import ros as rosutil
from support.ros import RecordingRosEnv
from pyrosgen.ros.rosmaster import free_port


def _cmdlines() -> dict[int, str]:
    out = {}
    for d in Path("/proc").iterdir():
        if d.name.isdigit():
            try:
                out[int(d.name)] = (d / "cmdline").read_bytes().replace(b"\0", b" ").decode(errors="replace")
            except OSError:
                pass
    return out


def test_no_process_left_behind(tmp_path, landshark_echo, nodes_dir):
    home = tmp_path / "ros"
    (home / "log").mkdir(parents=True)
    env = RecordingRosEnv(port=free_port(), home=home)
    try:
        env.start_master()
        mine = [env.proc.pid, rosutil.start_node(env, landshark_echo / "bin" / "landshark_controller",
                                                 tmp_path / "node.log").pid]
        assert all(rosutil.alive(p) for p in mine)
    finally:
        env.close()
    assert {p for p, _ in rosutil.STARTED} >= set(mine)
    survivors = [(p, what) for p, what in rosutil.STARTED if rosutil.alive(p)]
    assert not survivors, f"processes started by the tests still running: {survivors}"
    # nothing runs a node binary built for these tests, whoever started it
    built = str(nodes_dir)
    strays = [(p, c) for p, c in _cmdlines().items() if built in c and p != os.getpid()]
    assert not strays, strays

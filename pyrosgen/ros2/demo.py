"""The run phase of ``make demo-ros2``: the LandShark node on ROS 2.

    python -m pyrosgen.ros2.demo OUT [--duration S] [--spoof FROM:TO]

``OUT`` is a ``pyrosgen build --ros2`` output of examples/landshark.  Starts
the node ``OUT/bin/landshark_controller`` and the simulated robot
(``demo_sim.py``, run by the ROS 2 installation's interpreter), both in the
environment of :func:`pyrosgen.ros2.env.ros2_env` (discovery on the loopback
only, a domain of the demo's own; no master: DDS discovers the peers),
forwards the simulator's table and stops both by PID whatever happens (also
on Ctrl-C and SIGTERM), the node by SIGTERM, so that it shuts rcl down and
leaves no /dev/shm segment.  Exit code: the simulator's (0: the median
rejected the spoofed GPS).
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from pyrosgen.ros.demo import demo_main
from pyrosgen.ros2.env import find_ros2, ros2_env

SIM = Path(__file__).resolve().parent / "demo_sim.py"
NODE = "landshark_controller"


def say(line: str) -> None:
    """A line of the demo's own (``demo: ...``), at once."""
    print(f"demo: {line}", flush=True)


def stop_node(p: subprocess.Popen, timeout: float = 15.0) -> None:
    """SIGTERM to a node or peer the demo started (a clean rcl shutdown),
    SIGKILL to its process group after ``timeout`` seconds."""
    if p.poll() is not None:
        return
    p.send_signal(signal.SIGTERM)
    try:
        p.wait(timeout)
    except subprocess.TimeoutExpired:
        os.killpg(p.pid, signal.SIGKILL)
        p.wait()


def run(out_dir: Path, duration: float = 12.0, spoof: str = "5:10") -> int:
    binary = out_dir / "bin" / NODE
    if not binary.is_file():
        say(f"error: {binary} not found: run pyrosgen build --ros2 first")
        return 2
    inst = find_ros2()
    env = ros2_env()
    say(f"ROS 2 (rcl, Fast DDS): ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST ROS_DOMAIN_ID={env['ROS_DOMAIN_ID']}")
    started: list[subprocess.Popen] = []
    code = 2
    with tempfile.TemporaryDirectory(prefix="pyrosgen-demo-ros2-") as tmp:
        node_log = Path(tmp) / "node.log"
        try:
            with open(node_log, "wb") as log:
                node = subprocess.Popen([str(binary)], stdout=log, stderr=subprocess.STDOUT, env=env,
                                        start_new_session=True)
            started.append(node)
            say(f"node {binary} (pid {node.pid}), 50 Hz")
            sim = subprocess.Popen([str(inst.python), str(SIM), "--duration", str(duration), "--spoof", spoof],
                                   stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, bufsize=1,
                                   env=env, start_new_session=True)
            started.append(sim)
            say(f"simulated robot, rclpy (pid {sim.pid})")
            deadline = time.monotonic() + duration + 60
            assert sim.stdout is not None
            for line in sim.stdout:
                print(line.rstrip("\n"), flush=True)
                if time.monotonic() > deadline:
                    break
            try:
                code = sim.wait(max(1.0, deadline - time.monotonic()))
            except subprocess.TimeoutExpired:
                say("error: the simulator did not finish in time")
                code = 2
            if node.poll() is not None:
                say(f"error: the node exited with {node.returncode}; its log:")
                print(node_log.read_text(errors="replace")[-2000:], flush=True)
                code = code or 2
            say("stopping the simulator and the node (SIGTERM: rcl shut down, no /dev/shm left)")
        finally:
            for p in reversed(started):
                stop_node(p)
    say("all processes stopped")
    return code


def main(argv: list[str] | None = None) -> int:
    return demo_main(argv, prog="python -m pyrosgen.ros2.demo", description="Run the LandShark demo node on ROS 2.",
                     out_help="pyrosgen build --ros2 output folder of examples/landshark", run_demo=run)


if __name__ == "__main__":
    sys.exit(main())

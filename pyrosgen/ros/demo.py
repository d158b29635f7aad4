"""The run phase of ``make demo``: the LandShark node on a real master.

    python -m pyrosgen.ros.demo OUT [--duration S]

``OUT`` is a ``pyrosgen build`` output of examples/landshark.  Starts a
private rosmaster on 127.0.0.1 at a free port (:mod:`pyrosgen.ros.rosmaster`),
the node ``OUT/bin/landshark_controller``, and the simulated robot
(``demo_sim.py``, run by Debian's /usr/bin/python3), forwards the
simulator's live table, and stops everything it started, by PID, whatever
happens (also on Ctrl-C and SIGTERM).  Needs no terminal.  Exit code: the
simulator's (0: the median rejected the spoofed GPS).
"""

from __future__ import annotations

import argparse
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from pyrosgen.ros.rosmaster import ros_master, stop_process

SIM = Path(__file__).resolve().parent / "demo_sim.py"
NODE = "landshark_controller"


def _say(line: str) -> None:
    print(f"demo: {line}", flush=True)


def run(out_dir: Path, duration: float = 12.0, spoof: str = "5:10") -> int:
    binary = out_dir / "bin" / NODE
    if not binary.is_file():
        _say(f"error: {binary} not found: run pyrosgen build first")
        return 2
    return run_node_with_driver(
        binary, "50 Hz", [str(SIM), "--duration", str(duration), "--spoof", spoof],
        "simulated robot", "the simulator", duration, "pyrosgen-demo-")


def run_node_with_driver(binary: Path, node_note: str, driver: list[str], driver_name: str,
                         driver_the: str, duration: float, prefix: str) -> int:
    """Start a private rosmaster, the node ``binary`` and the driver script
    (``driver``: its path and arguments, run by Debian's /usr/bin/python3),
    forward the driver's lines (not rospy's log lines) while it runs (at
    most ``duration`` + 60 s), and stop everything started, by PID.  The
    exit code is the driver's, 2 if it did not finish in time or the node
    died (its log's end is shown).  ``driver_name`` and ``driver_the``
    name the driver in the progress lines."""
    with tempfile.TemporaryDirectory(prefix=prefix) as tmp:
        home = Path(tmp)
        with ros_master(home) as env:
            _say(f"rosmaster on {env.uri} (pid {env.proc.pid})")
            node_log = home / "node.log"
            with open(node_log, "wb") as log:
                node = env.spawn([str(binary)], stdout=log, stderr=subprocess.STDOUT)
            _say(f"node {binary} (pid {node.pid}), {node_note}")
            drv = env.spawn(["/usr/bin/python3", *driver],
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, bufsize=1)
            _say(f"{driver_name} (pid {drv.pid})")
            deadline = time.monotonic() + duration + 60
            assert drv.stdout is not None
            for line in drv.stdout:
                if not line.startswith("[") and "rospy" not in line:  # skip rospy's log lines
                    print(line.rstrip("\n"), flush=True)
                if time.monotonic() > deadline:
                    break
            try:
                code = drv.wait(max(1.0, deadline - time.monotonic()))
            except subprocess.TimeoutExpired:
                stop_process(drv)
                _say(f"error: {driver_the} did not finish in time")
                code = 2
            if node.poll() is not None:
                _say(f"error: the node exited with {node.returncode}; its log:")
                print(node_log.read_text(errors="replace")[-2000:], flush=True)
                code = code or 2
            _say(f"stopping {driver_the}, the node and rosmaster")
        _say("all processes stopped")
    return code


def demo_main(argv: list[str] | None, *, prog: str, description: str, out_help: str, run_demo) -> int:
    """The command line of a LandShark demo (ROS 1's, and ROS 2's in
    :mod:`pyrosgen.ros2.demo`): the build folder, ``--duration`` and
    ``--spoof``; ``run_demo(out, duration, spoof)`` runs it; SIGTERM and
    Ctrl-C stop everything it started (exit 130)."""
    ap = argparse.ArgumentParser(prog=prog, description=description)
    ap.add_argument("out", type=Path, help=out_help)
    ap.add_argument("--duration", type=float, default=12.0, help="simulated seconds (default 12)")
    ap.add_argument("--spoof", default="5:10", help="GPS spoofing window FROM:TO in seconds")
    args = ap.parse_args(argv)

    def _terminated(signum, frame):
        raise KeyboardInterrupt

    signal.signal(signal.SIGTERM, _terminated)
    try:
        return run_demo(args.out, args.duration, args.spoof)
    except KeyboardInterrupt:
        _say("interrupted; everything started was stopped")
        return 130


def main(argv: list[str] | None = None) -> int:
    return demo_main(argv, prog="python -m pyrosgen.ros.demo", description="Run the LandShark demo node.",
                     out_help="pyrosgen build output folder of examples/landshark", run_demo=run)


if __name__ == "__main__":
    sys.exit(main())

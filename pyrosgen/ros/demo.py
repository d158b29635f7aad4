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
    with tempfile.TemporaryDirectory(prefix="pyrosgen-demo-") as tmp:
        home = Path(tmp)
        with ros_master(home) as env:
            _say(f"rosmaster on {env.uri} (pid {env.proc.pid})")
            node_log = home / "node.log"
            with open(node_log, "wb") as log:
                node = env.spawn([str(binary)], stdout=log, stderr=subprocess.STDOUT)
            _say(f"node {binary} (pid {node.pid}), 50 Hz")
            sim = env.spawn(["/usr/bin/python3", str(SIM), "--duration", str(duration), "--spoof", spoof],
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, bufsize=1)
            _say(f"simulated robot (pid {sim.pid})")
            deadline = time.monotonic() + duration + 60
            assert sim.stdout is not None
            for line in sim.stdout:
                if not line.startswith("[") and "rospy" not in line:  # skip rospy's log lines
                    print(line.rstrip("\n"), flush=True)
                if time.monotonic() > deadline:
                    break
            try:
                code = sim.wait(max(1.0, deadline - time.monotonic()))
            except subprocess.TimeoutExpired:
                stop_process(sim)
                _say("error: the simulator did not finish in time")
                code = 2
            if node.poll() is not None:
                _say(f"error: the node exited with {node.returncode}; its log:")
                print(node_log.read_text(errors="replace")[-2000:], flush=True)
                code = code or 2
            _say("stopping the simulator, the node and rosmaster")
        _say("all processes stopped")
    return code


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m pyrosgen.ros.demo", description="Run the LandShark demo node.")
    ap.add_argument("out", type=Path, help="pyrosgen build output folder of examples/landshark")
    ap.add_argument("--duration", type=float, default=12.0, help="simulated seconds (default 12)")
    ap.add_argument("--spoof", default="5:10", help="GPS spoofing window FROM:TO in seconds")
    args = ap.parse_args(argv)

    def _terminated(signum, frame):
        raise KeyboardInterrupt

    signal.signal(signal.SIGTERM, _terminated)
    try:
        return run(args.out, args.duration, args.spoof)
    except KeyboardInterrupt:
        _say("interrupted; everything started was stopped")
        return 130


if __name__ == "__main__":
    sys.exit(main())

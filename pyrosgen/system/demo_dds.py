"""The system part of ``make demo ROS=2``: the three-node chain of
examples/system_chain built for ROS 2, on Fast DDS (loopback only).

    python -m pyrosgen.system.demo_dds OUT [--phase S]

``OUT`` is a ``pyrosgen system build --ros2`` output of
examples/system_chain/system.yaml.  Starts each node's binary with the
command line its ROS 2 launch file gives it
(:func:`pyrosgen.system.launch.read_ros2_launch`: its name, namespace and
remappings as ROS arguments, as ``ros2 launch`` would), and the sensors
(``demo_chain_sim_rclpy.py``, rclpy, run by the ROS 2 installation's
interpreter), every process in the environment of
:func:`pyrosgen.ros2.env.ros2_env` (discovery on the loopback only, a
domain of the demo's own); forwards the live table of wheel speeds; stops
everything it started by PID (the nodes by SIGTERM: rcl shut down, no
/dev/shm left), also on Ctrl-C.  Exit code: the sensors' (0: every phase
ended at the speeds the controllers compute, 1: not, 2: the chain could
not be reached); 1 for bad usage or a folder without the nodes.
"""

from __future__ import annotations

import argparse
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from pyrosgen.ros2.demo import say as _say
from pyrosgen.ros2.demo import stop_node as _stop
from pyrosgen.ros2.env import find_ros2, ros2_env
from pyrosgen.system.launch import read_ros2_launch

SIM = Path(__file__).resolve().parent / "demo_chain_sim_rclpy.py"
LAUNCH = "guard_chain.launch.xml"


def _commands(out: Path) -> list[tuple[str, list[str]]] | None:
    """Each node's resolved name and command line, from OUT's launch file;
    None (said) when OUT is not a ROS 2 system build of the chain."""
    launch = out / LAUNCH
    if not launch.is_file():
        _say(f"error: {launch} not found: run pyrosgen system build --ros2 "
             f"examples/system_chain/system.yaml -o {out} first")
        return None
    try:
        nodes = read_ros2_launch(launch.read_text(encoding="utf-8"))
    except (ValueError, SyntaxError) as exc:
        _say(f"error: {launch}: not a launch file pyrosgen wrote: {exc}")
        return None
    cmds = []
    for n in nodes:
        binary = out / n.folder / "bin" / n.exec
        if not binary.is_file():
            _say(f"error: {binary} not found: run pyrosgen system build --ros2 first")
            return None
        cmds.append((n.full_name, n.argv(binary)))
    return cmds


def run(out: Path, phase: float = 2.0) -> int:
    cmds = _commands(out)
    if cmds is None:
        return 1
    inst = find_ros2()
    env = ros2_env()
    _say(f"ROS 2 (rcl, Fast DDS): ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST ROS_DOMAIN_ID={env['ROS_DOMAIN_ID']}")
    started: list[tuple[str, subprocess.Popen, Path]] = []
    code = 2
    with tempfile.TemporaryDirectory(prefix="pyrosgen-demo-chain-ros2-") as tmp:
        try:
            for name, argv in cmds:
                log = Path(tmp) / f"{name.strip('/').replace('/', '.')}.log"
                with open(log, "wb") as f:
                    p = subprocess.Popen(argv, stdout=f, stderr=subprocess.STDOUT, env=env, start_new_session=True)
                started.append((name, p, log))
                _say(f"node {name} (pid {p.pid}): {Path(argv[0]).name} {' '.join(argv[1:])}")
            sim = subprocess.Popen([str(inst.python), str(SIM), "--phase", str(phase)], stdout=subprocess.PIPE,
                                   stderr=subprocess.STDOUT, text=True, bufsize=1, env=env, start_new_session=True)
            started.append(("sensors", sim, Path(tmp) / "sensors.log"))
            _say(f"sensors: laser scanner and joystick, rclpy (pid {sim.pid})")
            deadline = time.monotonic() + 3 * phase + 60
            assert sim.stdout is not None
            for line in sim.stdout:
                print(line.rstrip("\n"), flush=True)
                if time.monotonic() > deadline:
                    break
            try:
                code = sim.wait(max(1.0, deadline - time.monotonic()))
            except subprocess.TimeoutExpired:
                _say("error: the sensors did not finish in time")
                code = 2
            for name, p, log in started[:-1]:
                if p.poll() is not None:
                    _say(f"error: {name} exited with {p.returncode}; its log:")
                    print(log.read_text(errors="replace")[-2000:], flush=True)
                    code = code or 2
            _say("stopping the sensors and the nodes (SIGTERM: rcl shut down, no /dev/shm left)")
        finally:
            for _, p, _ in reversed(started):
                _stop(p)
    _say("all processes stopped")
    return code


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m pyrosgen.system.demo_dds")
    ap.add_argument("out", metavar="OUT", help="a pyrosgen system build --ros2 output of examples/system_chain")
    ap.add_argument("--phase", type=float, default=2.0, help="seconds per phase (default 2)")
    try:
        args = ap.parse_args(argv)
    except SystemExit as exc:
        return 1 if exc.code else 0

    def _terminated(signum, frame):
        raise KeyboardInterrupt

    signal.signal(signal.SIGTERM, _terminated)
    try:
        return run(Path(args.out), args.phase)
    except KeyboardInterrupt:
        _say("interrupted; everything started was stopped")
        return 130


if __name__ == "__main__":
    sys.exit(main())

"""The system part of ``make demo``: the three-node chain of
examples/system_chain on a private master.

    python -m pyrosgen.system.demo OUT [--phase S]

``OUT`` is a ``pyrosgen system build`` output of
examples/system_chain/system.yaml.  Starts a private rosmaster on
127.0.0.1 at a free port, each node's binary with its namespace, name and
remappings (as the system's launch file does), and the sensors
(``demo_chain_sim.py``, run by Debian's /usr/bin/python3); forwards the
live table of wheel speeds; stops everything it started, by PID.  Exit
code: the sensors' (0: every phase ended at the speeds the controllers
compute, 1: not, 2: the chain could not be reached); 1 for bad usage or a
folder without the nodes.
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from pyrosgen.ros.rosmaster import ros_master, stop_process

SIM = Path(__file__).resolve().parent / "demo_chain_sim.py"
SYSTEM = Path(__file__).resolve().parents[2] / "examples" / "system_chain" / "system.yaml"


def _say(line: str) -> None:
    print(f"demo: {line}", flush=True)


def run(out: Path, phase: float = 2.0, system: Path = SYSTEM) -> int:
    from pyrosgen.system.checks import check_system
    from pyrosgen.system.model import load_system

    sysm = load_system(system)
    check_system(sysm)
    nodes = []
    for sn in sysm.nodes:
        binary = out / sn.folder / "bin" / sn.model.name
        if not binary.is_file():
            _say(f"error: {binary} not found: run pyrosgen system build {system} -o {out} first")
            return 1
        args = [f"__ns:={sn.namespace}", f"__name:={sn.name}"] + [f"{s}:={t}" for s, t in sorted(sn.remap.items())]
        nodes.append((sn.full_name, binary, args))
    code = 2
    with tempfile.TemporaryDirectory(prefix="pyrosgen-demo-chain-") as tmp:
        home = Path(tmp)
        with ros_master(home) as env:
            _say(f"rosmaster on {env.uri} (pid {env.proc.pid})")
            procs = []
            for name, binary, args in nodes:
                log = home / f"{name.strip('/').replace('/', '.')}.log"
                with open(log, "wb") as f:
                    p = env.spawn([str(binary), *args], stdout=f, stderr=subprocess.STDOUT)
                procs.append((name, p, log))
                _say(f"node {name} (pid {p.pid}): {binary.name} {' '.join(args)}")
            drv = env.spawn(["/usr/bin/python3", str(SIM), "--phase", str(phase)],
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, bufsize=1)
            _say(f"sensors: laser scanner and joystick (pid {drv.pid})")
            deadline = time.monotonic() + 3 * phase + 60
            assert drv.stdout is not None
            for line in drv.stdout:
                if not line.startswith("[") and "rospy" not in line:
                    print(line.rstrip("\n"), flush=True)
                if time.monotonic() > deadline:
                    break
            try:
                code = drv.wait(max(1.0, deadline - time.monotonic()))
            except subprocess.TimeoutExpired:
                stop_process(drv)
                _say("error: the sensors did not finish in time")
                code = 2
            for name, p, log in procs:
                if p.poll() is not None:
                    _say(f"error: {name} exited with {p.returncode}; its log:")
                    print(log.read_text(errors="replace")[-2000:], flush=True)
                    code = code or 2
            _say("stopping the sensors, the nodes and rosmaster")
        _say("all processes stopped")
    return code


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m pyrosgen.system.demo")
    ap.add_argument("out", metavar="OUT", help="a pyrosgen system build output of examples/system_chain")
    ap.add_argument("--phase", type=float, default=2.0, help="seconds per phase (default 2)")
    try:
        args = ap.parse_args(argv)
    except SystemExit as exc:
        return 1 if exc.code else 0
    return run(Path(args.out), args.phase)


if __name__ == "__main__":
    sys.exit(main())

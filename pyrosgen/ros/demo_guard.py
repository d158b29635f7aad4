"""The second run phase of ``make demo``: the velocity guard's timeouts
(rule 4.12) on a real master.

    python -m pyrosgen.ros.demo_guard OUT [--teleop-stop S] [--nav-stop S] [--duration S]

``OUT`` is a ``pyrosgen build`` output of examples/velocity_guard.  Starts
a private rosmaster on 127.0.0.1 at a free port
(:mod:`pyrosgen.ros.rosmaster`), the node ``OUT/bin/velocity_guard``, and
its two command sources (``demo_guard_sim.py``, run by Debian's
/usr/bin/python3), which stop one after the other; forwards the sources'
live table (the command before and after each source stops, and how late
after its last message), and stops everything it started, by PID,
whatever happens (also on Ctrl-C and SIGTERM).  Needs no terminal.  Exit
code: the sources' (0: each silent source was replaced once its timeout
passed, 1: it was not, 2: the node could not be reached); 1 for bad usage
or a folder without the node.
"""

from __future__ import annotations

import argparse
import signal
import sys
from pathlib import Path

from pyrosgen.ros.demo import run_node_with_driver

SOURCES = Path(__file__).resolve().parent / "demo_guard_sim.py"
NODE = "velocity_guard"
GUARD_MODEL = "examples/velocity_guard/velocity_guard.yaml"


def _say(line: str) -> None:
    print(f"demo: {line}", flush=True)


def run(out_dir: Path, teleop_stop: float = 2.0, nav_stop: float = 4.0, duration: float = 5.0) -> int:
    binary = out_dir / "bin" / NODE
    if not binary.is_file():
        _say(f"error: {binary} not found: run pyrosgen build {GUARD_MODEL} -o {out_dir} first")
        return 1
    return run_node_with_driver(
        binary, "50 Hz, teleop and nav time out after 500 ms",
        [str(SOURCES), "--teleop-stop", str(teleop_stop), "--nav-stop", str(nav_stop), "--duration", str(duration)],
        "command sources", "the command sources", duration, "pyrosgen-demo-guard-")


class _Parser(argparse.ArgumentParser):
    """Bad usage is a user error: exit status 1, no traceback."""

    def error(self, message: str):  # noqa: D102 - argparse hook
        self.print_usage(sys.stderr)
        print(f"{self.prog}: error: {message}", file=sys.stderr)
        sys.exit(1)


def main(argv: list[str] | None = None) -> int:
    ap = _Parser(prog="python -m pyrosgen.ros.demo_guard",
                 description="Run the velocity guard demo node (timeouts, rule 4.12).")
    ap.add_argument("out", type=Path, help="pyrosgen build output folder of examples/velocity_guard")
    ap.add_argument("--teleop-stop", type=float, default=2.0, help="when teleop falls silent, s (default 2)")
    ap.add_argument("--nav-stop", type=float, default=4.0, help="when nav falls silent, s (default 4)")
    ap.add_argument("--duration", type=float, default=5.0, help="length of the run, s (default 5)")
    args = ap.parse_args(argv)
    if not 0 < args.teleop_stop < args.nav_stop < args.duration:
        ap.error("need 0 < --teleop-stop < --nav-stop < --duration")

    def _terminated(signum, frame):
        raise KeyboardInterrupt

    signal.signal(signal.SIGTERM, _terminated)
    try:
        return run(args.out, args.teleop_stop, args.nav_stop, args.duration)
    except KeyboardInterrupt:
        _say("interrupted; everything started was stopped")
        return 130


if __name__ == "__main__":
    sys.exit(main())

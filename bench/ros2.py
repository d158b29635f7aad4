"""ROS 2 (issue 31): ``pyrosgen build --ros2`` time and the round trip of
the LandShark node over rcl on Fast DDS (loopback).

usage: .venv/bin/python bench/ros2.py [--rounds N] [--builds N]

- **build**: ``pyrosgen build --ros2`` of examples/landshark (C controller)
  into a fresh folder, ``--builds`` times; the total and its phases;
- **round trip** at a 1 ms period (bench/models/landshark_1ms.yaml, built
  for ROS 2 with the bit-exact echo controller of tests/ros), against
  bench/handwritten/landshark_handwritten_rcl.c (the same over rcl by hand,
  the same controller, reading the rosidl messages where they lie): an
  rclpy peer (bench/runtime/ros2_latency_peer.py) publishes one value on
  the three inputs and measures the time to the first base velocity
  computed from all three; ``--rounds`` rounds per node and turn, the two
  nodes in turn (``--turns``), each alone.

Every ROS 2 process runs in the environment of
``pyrosgen.ros2.env.ros2_env`` (loopback discovery, a domain of its own)
and is stopped by its PID; the Fast DDS segments it leaves in /dev/shm, if
any, are removed.  Results: bench/results/ros2.json."""

from __future__ import annotations

import argparse
import json
import shutil
import signal
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from common import REPO, loadavg, machine, save_json  # noqa: E402

from pyrosgen.ros2.build import build_ros2, compile_flags, link_flags  # noqa: E402
from pyrosgen.ros2.frontend import load_model_ros2  # noqa: E402
from pyrosgen.ros2.env import find_ros2, ros2_env  # noqa: E402

EXAMPLE = REPO / "examples" / "landshark" / "landshark_controller.yaml"
CTL = REPO / "examples" / "landshark" / "controller"
MODEL_1MS = REPO / "bench" / "models" / "landshark_1ms.yaml"
ECHO = REPO / "tests" / "ros" / "controllers" / "landshark_echo"
PEER = REPO / "bench" / "runtime" / "ros2_latency_peer.py"
HANDWRITTEN = REPO / "bench" / "handwritten" / "landshark_handwritten_rcl.c"
SHM = Path("/dev/shm")


def _segments() -> set[str]:
    return {p.name for p in [*SHM.glob("fastdds_*"), *SHM.glob("sem.fastdds_*")]}


def _pct(xs: list[float], q: float) -> float:
    s = sorted(xs)
    return s[min(len(s) - 1, int(q * len(s)))]


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--rounds", type=int, default=300)
    ap.add_argument("--builds", type=int, default=3)
    ap.add_argument("--turns", type=int, default=3)
    args = ap.parse_args()
    inst = find_ros2()
    work = Path(tempfile.mkdtemp(prefix="pyrosgen-bench-ros2-"))
    before = _segments()
    try:
        builds = []
        for i in range(args.builds):
            out = work / f"build{i}"
            t0 = time.monotonic()
            res = build_ros2(EXAMPLE, CTL, out, install=inst)
            builds.append({"total_s": time.monotonic() - t0, "phases": res.times})
            print(f"build {i}: {builds[-1]['total_s']:.2f} s", file=sys.stderr)
        generated = build_ros2(MODEL_1MS, ECHO, work / "node1ms", install=inst).binary
        hand = work / "landshark_handwritten_rcl"
        subprocess.run(["gcc", "-std=c11", "-O2", "-Wall", "-Wextra", "-Werror", "-I", str(ECHO),
                        *compile_flags(inst), str(HANDWRITTEN), str(ECHO / "Controller.c"), "-o", str(hand),
                        *link_flags(inst, load_model_ros2(EXAMPLE, inst)), "-lm"], check=True)
        env = ros2_env()
        lats: dict[str, list[float]] = {"generated": [], "handwritten": []}
        turns = []
        for turn in range(args.turns):
            row = {}
            for name, argv in (("generated", [str(generated)]), ("handwritten", [str(hand), "1"])):
                p = subprocess.Popen(argv, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                                     start_new_session=True)
                try:
                    r = subprocess.run([str(inst.python), str(PEER), str(args.rounds)], env=env,
                                       capture_output=True, text=True, timeout=60 + args.rounds)
                finally:
                    p.send_signal(signal.SIGTERM)
                    try:
                        p.wait(timeout=15)
                    except subprocess.TimeoutExpired:
                        p.kill()
                        p.wait()
                if r.returncode != 0:
                    print(r.stderr, file=sys.stderr)
                    return 2
                got = json.loads(r.stdout)["latency_ms"]
                lats[name] += got
                row[name] = statistics.median(got)
            row["ratio"] = row["generated"] / row["handwritten"]
            row["load"] = loadavg()
            turns.append(row)
            print(f"turn {turn}: {row}", file=sys.stderr)
        lat = lats["generated"]
        result = {
            "machine": machine(), "loadavg": loadavg(), "when": time.strftime("%Y-%m-%d %H:%M"),
            "build_s": {"median": statistics.median(b["total_s"] for b in builds),
                        "runs": [round(b["total_s"], 2) for b in builds],
                        "phases_first": {k: round(v, 2) for k, v in builds[0]["phases"].items()}},
            "round_trip_ms_1ms_period": {
                name: {"rounds": args.rounds * args.turns, "answered": len(xs), "median": statistics.median(xs),
                       "p10": _pct(xs, 0.10), "p90": _pct(xs, 0.90), "p99": _pct(xs, 0.99), "max": max(xs)}
                for name, xs in lats.items()},
            "turns": turns,
            "ratio_of_medians": statistics.median(lats["generated"]) / statistics.median(lats["handwritten"]),
        }
        save_json("ros2.json", result)
        print(json.dumps(result, indent=1))
        return 0
    finally:
        shutil.rmtree(work, ignore_errors=True)
        for name in _segments() - before:
            try:
                (SHM / name).unlink()
            except OSError:
                pass


if __name__ == "__main__":
    sys.exit(main())

"""How fast a timed input goes stale: the velocity guard's detection latency
(BENCHMARKS.md, section "Freshness").

The node of examples/velocity_guard/velocity_guard.yaml (``pyrosgen
build``: the timed glue printed by Coq, the controller C from its block
diagram) runs at 50 Hz against a private master; both of its command
sources time out after 500 ms.  bench/runtime/freshness_driver.cpp feeds
teleop (linear.x 1.0) and nav (2.0) at 50 Hz and, in each trial, stops
teleop at a random phase of the node's cycle: the latency is the time from
the publication of the last teleop command to the receipt of the first
/cmd_vel that no longer follows it (which must be nav's 2.0).

What the design promises: a message's age is measured from its receipt by
the node to the start of a cycle, and a source is replaced in the first
cycle where its age reaches 500 ms, so the latency is at least the timeout
and at most the timeout plus one period, plus the two transports and the
cycle's own jitter.  Goal: every trial within [500 ms, 500 + 20 + 2 ms].

What the timed glue costs: the instructions per cycle of the glue
(callgrind, exact, as bench/runtime.py counts LandShark's: the glue linked
with a fake ROS, ``-O2 -fno-inline``, only the callbacks, ``input_glue``
and ``output_glue_*`` counted; ``ros_now``, a ROS function, is not) of
LandShark against LandShark with a timeout and a derived input
(bench/models/landshark_fresh.yaml: the GPS topic times out after 100 ms,
its age feeds a fourth input).  Both run the same fake ROS: the GPS
message arrives in 8 cycles of 16, so the timed node sees its topic
fresh, and stale in 3 cycles of 16; both with the same stub controller.

usage: .venv/bin/python bench/freshness.py [--trials 200] [--node BINARY]
       [--seed 12345] [--quiet-ms 0] [--no-latency] [--no-instructions]
``--node`` measures a node already built (otherwise it is built into
build/bench/freshness/).  Writes freshness.json into bench/results/ and
prints Markdown tables.
"""

from __future__ import annotations

import argparse
import math
import os
import subprocess
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from common import BENCH, PYROSGEN, REPO, WORK, load_json, loadavg, machine, median, run, save_json  # noqa: E402

MODEL = REPO / "examples" / "velocity_guard" / "velocity_guard.yaml"
LANDSHARK = REPO / "examples" / "landshark" / "landshark_controller.yaml"
LANDSHARK_FRESH = BENCH / "models" / "landshark_fresh.yaml"
DRIVER_SRC = BENCH / "runtime" / "freshness_driver.cpp"
FR = WORK / "freshness"
TIMEOUT_MS = 500
PERIOD_MS = 20
SLACK_MS = 2
NAV = 2.0


def log(msg: str) -> None:
    print(f"freshness: {msg}", flush=True)


def _pkg(*names: str) -> list[str]:
    out = subprocess.run(["pkg-config", "--cflags", "--libs", *names], capture_output=True, text=True, check=True)
    return out.stdout.split()


def build_node() -> tuple[Path, dict]:
    """``pyrosgen build`` of the velocity guard; its binary and timings."""
    out = FR / "node"
    log(f"pyrosgen build {MODEL.relative_to(REPO)}")
    p = run([PYROSGEN, "build", MODEL, "-o", out, "-q"], env=dict(os.environ), timeout=1800, check=False)
    if p.rc != 0:
        raise SystemExit(f"freshness: pyrosgen build failed (exit {p.rc}):\n{p.stderr.strip()[-3000:]}")
    return out / "bin" / "velocity_guard", {"wall": p.wall, "cpu": p.cpu}


def build_driver() -> Path:
    drv = FR / "freshness_driver"
    if not drv.exists() or DRIVER_SRC.stat().st_mtime > drv.stat().st_mtime:
        log("g++ freshness_driver.cpp")
        run(["g++", "-std=c++14", "-O2", "-Wall", "-Wextra", DRIVER_SRC, "-o", drv, "-pthread",
             *_pkg("roscpp", "geometry_msgs")])
    return drv


def stats(xs: list[float]) -> dict:
    s = sorted(xs)
    n = len(s)

    def q(p: float) -> float:  # nearest rank
        return s[min(n - 1, max(0, math.ceil(p * n) - 1))]

    return {"n": n, "min": s[0], "median": median(s), "mean": sum(s) / n, "p90": q(0.90), "p99": q(0.99),
            "max": s[-1]}


def measure(node: Path, driver: Path, trials: int, seed: int, quiet_ms: float) -> dict:
    from pyrosgen.ros.rosmaster import ros_master, stop_process

    FR.mkdir(parents=True, exist_ok=True)
    with ros_master() as ros:
        la0 = loadavg()
        node_log = open(FR / "node.log", "wb")
        proc = ros.spawn([str(node)], stdout=node_log, stderr=subprocess.STDOUT)
        try:
            t0 = time.monotonic()
            p = run([driver, str(trials), str(PERIOD_MS), str(seed), str(quiet_ms)], env=ros.env,
                    timeout=60 + trials * 5, check=False)
            wall = time.monotonic() - t0
        finally:
            stop_process(proc)
            node_log.close()
        la1 = loadavg()
    lat, values, lost, commands = [], [], None, None
    for ln in p.stdout.splitlines():
        f = ln.split()
        if f and f[0] == "latency_us":
            lat.append(float(f[2]) / 1000.0)
            values.append(float(f[3]))
        elif f and f[0] == "lost":
            lost = int(f[1])
        elif f and f[0] == "commands":
            commands = int(f[1])
    if p.rc != 0 or lost is None or not lat:
        raise RuntimeError(f"freshness driver failed ({p.rc}):\n{p.stdout[-2000:]}\n{p.stderr[-2000:]}")
    lo, hi = TIMEOUT_MS, TIMEOUT_MS + PERIOD_MS + SLACK_MS
    outside = [x for x in lat if not lo <= x <= hi]
    return {"trials": trials, "answered": len(lat), "lost": lost, "commands": commands,
            "latency_ms": stats(lat), "samples_ms": [round(x, 3) for x in lat],
            "goal_ms": [lo, hi], "outside_goal": len(outside), "outside_samples_ms": outside,
            "not_nav": sum(1 for v in values if v != NAV), "wall_s": wall, "load": [la0, la1],
            "seed": seed, "quiet_ms": quiet_ms, "period_ms": PERIOD_MS, "timeout_ms": TIMEOUT_MS}


def check_fresh_model() -> None:
    """bench/models/landshark_fresh.yaml is the example plus the GPS
    topic's timeout and the derived input GpsAge, and nothing else."""
    import yaml

    a = yaml.safe_load(LANDSHARK.read_text())
    b = yaml.safe_load(LANDSHARK_FRESH.read_text())
    a["controller"]["inputs"]["fields"]["GpsAge"] = "uint32"
    gps = a["topics"][2]
    assert gps["name"] == "/landshark/gps_velocity"
    gps.update(timeout_ms=100, on_timeout="zero")
    a["relations"]["inputs"].append({"topic": "/landshark/gps_velocity", "derived": "age_ms", "input": "GpsAge"})
    if a != b:
        raise SystemExit(f"freshness: {LANDSHARK_FRESH} differs from {LANDSHARK} in more than the timed GPS topic")


def instructions() -> dict:
    """Glue instructions per cycle of LandShark without and with the timed
    GPS topic (see the module's documentation)."""
    from runtime import glue_per_cycle  # bench/runtime.py

    check_fresh_model()
    out = {}
    for label, model, fresh in (("plain", LANDSHARK, False), ("timed", LANDSHARK_FRESH, True)):
        defs = ["-DBENCH_GPS_GAPS"] + (["-DBENCH_FRESH"] if fresh else [])
        r = glue_per_cycle(label, model, FR, defs, log)
        funcs = {f: v for f, v in r["functions"].items() if f != "ros_now"}
        out[label] = {"model": r["model"], "per_cycle": sum(funcs.values()), "functions": funcs,
                      "ros_now_per_cycle": r["functions"].get("ros_now", 0.0), "check": r["check"]}
        log(f"  glue instructions per cycle, {label}: {sum(funcs.values()):.1f} "
            f"({', '.join(f'{k} {v:.1f}' for k, v in sorted(funcs.items()))})")
    return out


def instructions_table(ins: dict) -> str:
    from runtime import glue_table  # bench/runtime.py

    t = ins["timed"]
    return glue_table(ins["plain"], t, "with the timed GPS topic", "percent") + (
        f"\n\n(`ros_now`, the ROS API's, not counted: {t['ros_now_per_cycle']:.1f} "
        "instructions per cycle in the fake ROS.)")


def table(res: dict) -> str:
    s = res["latency_ms"]
    lo, hi = res["goal_ms"]
    met = res["outside_goal"] == 0 and res["lost"] == 0 and res["not_nav"] == 0
    lines = [
        f"| velocity guard, 50 Hz, timeout {res['timeout_ms']} ms | ms |",
        "|---|---|",
        f"| trials (answered / lost) | {res['answered']} / {res['lost']} |",
        f"| detection latency: min | {s['min']:.2f} |",
        f"| median | {s['median']:.2f} |",
        f"| mean | {s['mean']:.2f} |",
        f"| p99 | {s['p99']:.2f} |",
        f"| max | {s['max']:.2f} |",
        f"| goal: every trial within [{lo}, {hi}] | {'met' if met else 'NOT met'} "
        f"({res['outside_goal']} outside; {res['not_nav']} not switched to nav) |",
    ]
    return "\n".join(lines) + f"\n\nload average (1 min) before / after: {res['load'][0].split()[0]} / {res['load'][1].split()[0]}"


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--trials", type=int, default=200)
    ap.add_argument("--node", type=Path, help="a velocity_guard binary already built")
    ap.add_argument("--seed", type=int, default=12345)
    ap.add_argument("--quiet-ms", type=float, default=0.0,
                    help="the last teleop command at least this long after the one before it")
    ap.add_argument("--no-latency", action="store_true", help="only count the instructions")
    ap.add_argument("--no-instructions", action="store_true", help="only measure the latency")
    a = ap.parse_args(argv)
    if a.trials < 1:
        ap.error("--trials must be positive")
    FR.mkdir(parents=True, exist_ok=True)
    # a part not run keeps its last results
    res: dict = dict(load_json("freshness.json") or {})
    res["machine"] = machine()
    ok = True
    if not a.no_latency:
        build = None
        node = a.node
        if node is None:
            node, build = build_node()
        driver = build_driver()
        log(f"{a.trials} trials (about {a.trials * 0.7:.0f} s)")
        res.update(measure(node, driver, a.trials, a.seed, a.quiet_ms))
        res["node"] = str(node)
        res["build"] = build
        ok = res["outside_goal"] == 0 and res["lost"] == 0 and res["not_nav"] == 0
    if not a.no_instructions:
        res["instructions"] = instructions()
    save_json("freshness.json", res)
    if not a.no_latency:
        print()
        print(table(res))
    if not a.no_instructions:
        print()
        print(instructions_table(res["instructions"]))
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())

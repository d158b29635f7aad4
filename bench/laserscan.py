"""Run time of the LaserScan node: the generated laser guard against a
hand-written roscpp node (BENCHMARKS.md, section 10; issue 15).

The node of examples/laser_guard/laser_guard.yaml (one ``sensor_msgs/LaserScan``
subscription carrying ``ranges`` as at most 1081 float32, a block-diagram
controller, a ``TwistStamped`` command with ``frame_id`` and ``stamp: now``)
against bench/handwritten/laser_guard_handwritten.cpp, idiomatic roscpp
doing the same with the same controller (the C pyrosgen generates from the
diagram):

- **glue instructions per cycle** (callgrind, exact), counted as
  bench/runtime.py counts LandShark's (its ``glue_per_cycle`` and
  ``per_cycle``): the generated glue (``-O2 -fno-inline``) linked with
  bench/runtime/fake_ros_laser_guard.c, the hand-written callback and
  ``make_command`` (separate translation units) driven by
  bench/runtime/hw_harness_laser_guard.cpp; one scan per cycle, scans of
  0 to 2000 ranges in turn (bench/runtime/laser_scans.h); only the glue's
  functions and what they call are counted (generated: the callback,
  ``input_glue``, ``output_glue_cmd_vel`` and the fake ROS's
  ``ros_time_sec``/``ros_time_nsec``, which are the wrapper's code;
  hand-written: ``scanCallback`` and the building and destruction of the
  command, ``ros::Time::now()`` included).  Per cycle = (count at 2000
  cycles - count at 1000) / 1000.  The two harnesses must publish the same
  commands (checksums compared).  For scale, roscpp's serialization plus
  deserialization of the same scans.
- **latency** at a 1 ms period (bench/models/laser_guard_1ms.yaml, checked
  to differ from the example in the period only; the hand-written node with
  ``_period_ms:=1``), both nodes side by side against a private master, the
  driver (bench/runtime/latency_driver.cpp, scenario ``laser``) alternating
  edges between them: from the publication of a scan whose front sector
  is clear (after scans with an obstacle) to the receipt of the first
  command of 0.5 m/s.

Nothing here depends on how the generator copies messages: re-run after a
change of the generator to get its numbers.

usage: .venv/bin/python bench/laserscan.py [--no-latency | --no-instructions]
       [--rounds 3] [--edges 1500] [--no-report]
(``make bench`` runs it too, as bench/run.py's ``laserscan``, against the
benchmarks' private copy of the Coq library; run on its own, pyrosgen uses
``PYROSGEN_COQLIB`` if set, else coq/.)  Writes laserscan.json into
bench/results/, prints Markdown tables, and rewrites the ``laserscan``
block of BENCHMARKS.md (bench/report.py).
"""

from __future__ import annotations

import argparse
import os
import shutil
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from common import BENCH, PYROSGEN, REPO, WORK, load_json, machine, run, save_json  # noqa: E402

EXAMPLE = REPO / "examples" / "laser_guard" / "laser_guard.yaml"
MODEL_1MS = BENCH / "models" / "laser_guard_1ms.yaml"
HANDWRITTEN = BENCH / "handwritten" / "laser_guard_handwritten.cpp"
HARNESS = BENCH / "runtime" / "hw_harness_laser_guard.cpp"
FAKE = BENCH / "runtime" / "fake_ros_laser_guard.c"
LS = WORK / "laserscan"
NODE = "laser_guard"
#: The topics of the node, remapped under /gen and /hw for the latency.
REMAPS = ("/scan", "/cmd_vel")


def log(msg: str) -> None:
    print(f"laserscan: {msg}", file=sys.stderr, flush=True)


def check_model_1ms() -> None:
    """bench/models/laser_guard_1ms.yaml is the example with another period."""
    import yaml

    a = yaml.safe_load(EXAMPLE.read_text())
    b = yaml.safe_load(MODEL_1MS.read_text())
    if b["node"]["period_ms"] != 1:
        raise SystemExit(f"laserscan: {MODEL_1MS}: period_ms must be 1")
    a["node"]["period_ms"] = 1
    if a != b:
        raise SystemExit(f"laserscan: {MODEL_1MS} differs from {EXAMPLE} in more than the period: update it")


def build(env: dict) -> dict:
    """``pyrosgen build`` of the 1 ms model (the node for the latency; its
    controller/Guard.h and Guard.c, the diagram's C, for the hand-written
    node), the hand-written node and the latency driver."""
    from runtime import _pkg, _stale

    LS.mkdir(parents=True, exist_ok=True)
    gen = LS / "generated_1ms"
    log(f"pyrosgen build {MODEL_1MS.relative_to(REPO)}")
    p = run([PYROSGEN, "build", MODEL_1MS, "-o", gen, "-q"], env=env, timeout=1800, check=False)
    if p.rc != 0:
        raise SystemExit(f"laserscan: pyrosgen build failed (exit {p.rc}):\n{p.stderr.strip()[-3000:]}")
    ctrl_dir = gen / "controller"
    ctrl_o = LS / "Guard.o"
    run(["gcc", "-std=c11", "-O2", "-I", ctrl_dir, "-c", ctrl_dir / "Guard.c", "-o", ctrl_o])
    ros = _pkg("roscpp")
    hw = LS / "laser_guard_handwritten"
    if _stale(hw, HANDWRITTEN, ctrl_dir / "Guard.h", ctrl_dir / "Guard.c"):
        log("g++ laser_guard_handwritten.cpp")
        run(["g++", "-std=c++14", "-O2", "-Wall", "-Wextra", "-I", ctrl_dir, HANDWRITTEN, ctrl_o, "-o", hw,
             "-pthread", *ros])
    drv = LS / "latency_driver"
    src = BENCH / "runtime" / "latency_driver.cpp"
    if _stale(drv, src):
        log("g++ latency_driver.cpp")
        run(["g++", "-std=c++14", "-O2", "-Wall", src, "-o", drv, "-pthread", *ros])
    return {"generated": gen / "bin" / NODE, "handwritten": hw, "driver": drv, "ctrl_dir": ctrl_dir,
            "ctrl_o": ctrl_o, "build": {"wall": p.wall, "cpu": p.cpu}}


def _time_source(exe: Path) -> float:
    """Instructions per cycle of ``ros::Time::now()`` with what it calls, in
    the hand-written harness's last two callgrind runs (part of
    ``make_command``'s count)."""
    from runtime import RT, _inclusive

    pat = {"now": r"ros::Time::now\(\)"}
    c1 = _inclusive(RT / f"callgrind.{exe.name}.1000.out", pat)["now"]
    c2 = _inclusive(RT / f"callgrind.{exe.name}.2000.out", pat)["now"]
    return (c2 - c1) / 1000


def instructions(nodes: dict, env: dict) -> dict:
    from runtime import _pkg, glue_per_cycle, per_cycle

    gen = glue_per_cycle("laser_guard", EXAMPLE, LS, [], log, node=NODE, fake=FAKE,
                         controller=f"{NODE}_controller.c", env=env)
    glue_dir = LS / "glue_laser_guard"
    # both sides run the same controller: the diagram's C
    if (glue_dir / f"{NODE}_controller.c").read_text() != (nodes["ctrl_dir"] / "Guard.c").read_text():
        raise SystemExit("laserscan: the diagram's C of the example and of the 1 ms model differ")
    ros = _pkg("roscpp")
    cflags = [f for f in ros if not f.startswith("-l")]
    node_o, harness_o, hw_exe = LS / "hw_node.o", LS / "hw_harness.o", LS / "hw_fake"
    run(["g++", "-std=c++14", "-O2", "-DLASER_GUARD_HANDWRITTEN_NO_MAIN", "-I", nodes["ctrl_dir"], "-c",
         HANDWRITTEN, "-o", node_o, *cflags])
    run(["g++", "-std=c++14", "-O2", "-I", nodes["ctrl_dir"], "-I", HARNESS.parent, "-c", HARNESS,
         "-o", harness_o, *cflags])
    run(["g++", harness_o, node_o, nodes["ctrl_o"], "-o", hw_exe, *ros])
    hw_check = run([hw_exe]).stdout.strip()
    if gen["check"] != hw_check:
        raise SystemExit(f"laserscan: the fake-ROS harnesses disagree: generated {gen['check']!r}, "
                         f"hand-written {hw_check!r}")
    log("hand-written callback and command (callgrind)")
    hw = per_cycle(hw_exe, ["scanCallback*", "hw_output*"], ("sink",))
    hw["time_source"] = _time_source(hw_exe)
    rt = per_cycle(hw_exe, ["roscpp_roundtrip*"], (), {"BENCH_MODE": "roscpp"})
    g = {"model": gen["model"], "functions": gen["functions"], "per_cycle": sum(gen["functions"].values()),
         "time_source": sum(v for f, v in gen["functions"].items() if f in ("ros_time_sec", "ros_time_nsec"))}
    res = {"generated": g, "handwritten": hw, "roscpp_roundtrip": rt, "check": hw_check,
           "ratio": g["per_cycle"] / hw["per_cycle"],
           # without reading the clock (the generated node reads it in its
           # wrapper's ros_spinOnce, outside the glue; ros::Time::now()'s
           # cost depends on simulated or wall time)
           "ratio_without_time": (g["per_cycle"] - g["time_source"]) / (hw["per_cycle"] - hw["time_source"])}
    for k in ("generated", "handwritten", "roscpp_roundtrip"):
        d = res[k]
        log(f"  instructions per cycle, {k}: {d['per_cycle']:.1f} "
            f"({', '.join(f'{f} {v:.1f}' for f, v in sorted(d['functions'].items(), key=lambda kv: -kv[1]))})")
    log(f"  ratio generated / hand-written: {res['ratio']:.2f} ({res['ratio_without_time']:.2f} without the time stamp)")
    return res


def latency(nodes: dict, rounds: int, edges: int) -> dict:
    from runtime import latency as runtime_latency

    return runtime_latency({"generated": nodes["generated"], "handwritten": nodes["handwritten"],
                            "driver": nodes["driver"]}, rounds=rounds, edges=edges, log=log,
                           remaps=REMAPS, scenario="laser")


def run_laserscan(env: dict, *, instructions_too: bool = True, latency_too: bool = True, rounds: int = 3,
                  edges: int = 1500, previous: dict | None = None, log=log) -> dict:
    """Both parts (or one: a part not run keeps its ``previous`` results);
    ``env``: pyrosgen's environment (``PYROSGEN_COQLIB``)."""
    for tool in ("valgrind", "callgrind_annotate", "g++", "pkg-config"):
        if shutil.which(tool) is None:
            raise SystemExit(f"laserscan: {tool} not found")
    check_model_1ms()
    res: dict = dict(previous or {})
    res["machine"] = machine()
    nodes = build(env)
    res["build"] = nodes["build"]
    if instructions_too:
        res["instructions"] = instructions(nodes, env)
    if latency_too:
        log(f"latency at 1 ms, {rounds} round(s) of {edges} edges per node (private master)")
        res["latency"] = latency(nodes, rounds, edges)
    return res


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--no-latency", action="store_true", help="only count the instructions")
    ap.add_argument("--no-instructions", action="store_true", help="only measure the latency")
    ap.add_argument("--rounds", type=int, default=3, help="latency rounds (fresh nodes each)")
    ap.add_argument("--edges", type=int, default=1500, help="latency edges per node and round")
    ap.add_argument("--no-report", action="store_true", help="do not rewrite BENCHMARKS.md")
    a = ap.parse_args(argv)
    res = run_laserscan(dict(os.environ), instructions_too=not a.no_instructions, latency_too=not a.no_latency,
                        rounds=a.rounds, edges=a.edges, previous=load_json("laserscan.json"))
    save_json("laserscan.json", res)
    import report

    print(report.block_laserscan(lambda name: res if name == "laserscan.json" else None))
    if not a.no_report:
        report.write_blocks(load_json, ["laserscan"], log=log)
    return 0


if __name__ == "__main__":
    sys.exit(main())

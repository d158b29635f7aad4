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

The code is that of any laser node against its hand-written counterpart,
described by a ``Guard`` (``LASER_GUARD`` here); bench/scan_guard.py
measures the scan guard with it, adding the count with the wrapper's
conversions (its ``more_instructions``).

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
import re
import shutil
import sys
from dataclasses import dataclass
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from common import BENCH, PYROSGEN, REPO, WORK, load_json, loadavg, machine, run, save_json  # noqa: E402

@dataclass(frozen=True)
class Guard:
    """One laser node of the benchmark and its hand-written counterpart
    (the laser guard here; bench/scan_guard.py has the scan guard)."""

    tag: str                    #: log prefix, results file <tag>.json, report block
    node: str                   #: the node's name (bin/<node>, <node>_glue.c)
    example: Path               #: the example's model
    model_1ms: Path             #: the same with period_ms 1 (checked)
    controller: str             #: the controller's C name: <controller>.h, .c
    controller_dir: Path | None  #: pyrosgen build --controller (None: the diagram's C)
    handwritten: Path
    no_main: str                #: the macro that leaves main() out of the hand-written node
    fake_defs: tuple = ()       #: for fake_ros_laser_guard.c (and the controller)
    hw_defs: tuple = ()         #: for hw_harness_laser_guard.cpp
    remaps: tuple = ("/scan", "/cmd_vel")  #: the topics, remapped under /gen and /hw for the latency

    @property
    def work(self) -> Path:
        return WORK / self.tag

    def log(self, msg: str) -> None:
        print(f"{self.tag}: {msg}", file=sys.stderr, flush=True)


HARNESS = BENCH / "runtime" / "hw_harness_laser_guard.cpp"
FAKE = BENCH / "runtime" / "fake_ros_laser_guard.c"
LASER_GUARD = Guard(tag="laserscan", node="laser_guard",
                    example=REPO / "examples" / "laser_guard" / "laser_guard.yaml",
                    model_1ms=BENCH / "models" / "laser_guard_1ms.yaml", controller="Guard", controller_dir=None,
                    handwritten=BENCH / "handwritten" / "laser_guard_handwritten.cpp",
                    no_main="LASER_GUARD_HANDWRITTEN_NO_MAIN")


def check_model_1ms(g: Guard) -> None:
    """``g.model_1ms`` is the example with another period."""
    import yaml

    a = yaml.safe_load(g.example.read_text())
    b = yaml.safe_load(g.model_1ms.read_text())
    if b["node"]["period_ms"] != 1:
        raise SystemExit(f"{g.tag}: {g.model_1ms}: period_ms must be 1")
    a["node"]["period_ms"] = 1
    if a != b:
        raise SystemExit(f"{g.tag}: {g.model_1ms} differs from {g.example} in more than the period: update it")


def build(g: Guard, env: dict) -> dict:
    """``pyrosgen build`` of the 1 ms model (the node for the latency; its
    controller/<controller>.h and .c, for the hand-written node), the
    hand-written node and the latency driver."""
    from runtime import _pkg, _stale

    g.work.mkdir(parents=True, exist_ok=True)
    gen = g.work / "generated_1ms"
    g.log(f"pyrosgen build {g.model_1ms.relative_to(REPO)}")
    ctrl_arg = ["--controller", g.controller_dir] if g.controller_dir else []
    p = run([PYROSGEN, "build", g.model_1ms, *ctrl_arg, "-o", gen, "-q"], env=env, timeout=1800, check=False)
    if p.rc != 0:
        raise SystemExit(f"{g.tag}: pyrosgen build failed (exit {p.rc}):\n{p.stderr.strip()[-3000:]}")
    ctrl_dir = gen / "controller"
    ctrl_o = g.work / f"{g.controller}.o"
    run(["gcc", "-std=c11", "-O2", "-I", ctrl_dir, "-c", ctrl_dir / f"{g.controller}.c", "-o", ctrl_o])
    ros = _pkg("roscpp")
    hw = g.work / f"{g.node}_handwritten"
    if _stale(hw, g.handwritten, ctrl_dir / f"{g.controller}.h", ctrl_dir / f"{g.controller}.c"):
        g.log(f"g++ {g.handwritten.name}")
        run(["g++", "-std=c++14", "-O2", "-Wall", "-Wextra", "-I", ctrl_dir, g.handwritten, ctrl_o, "-o", hw,
             "-pthread", *ros])
    drv = g.work / "latency_driver"
    src = BENCH / "runtime" / "latency_driver.cpp"
    if _stale(drv, src):
        g.log("g++ latency_driver.cpp")
        run(["g++", "-std=c++14", "-O2", "-Wall", src, "-o", drv, "-pthread", *ros])
    return {"generated": gen / "bin" / g.node, "handwritten": hw, "driver": drv, "ctrl_dir": ctrl_dir,
            "ctrl_o": ctrl_o, "gen_dir": gen, "build": {"wall": p.wall, "cpu": p.cpu}}


def _time_source(exe: Path) -> float:
    """Instructions per cycle of ``ros::Time::now()`` with what it calls, in
    the hand-written harness's last two callgrind runs (part of
    ``make_command``'s count)."""
    from runtime import RT, _inclusive

    pat = {"now": r"ros::Time::now\(\)"}
    c1 = _inclusive(RT / f"callgrind.{exe.name}.1000.out", pat)["now"]
    c2 = _inclusive(RT / f"callgrind.{exe.name}.2000.out", pat)["now"]
    return (c2 - c1) / 1000


def callgrind_inclusive(path: Path) -> dict[str, int]:
    """The inclusive count (the function and what it calls, as collected)
    of each function of a callgrind dump, read from the dump itself
    (``callgrind_annotate --inclusive`` leaves out functions past a
    cumulative threshold of 100 %, which inclusive counts reach at once)."""
    names: dict[str, str] = {}
    own: dict[str, int] = {}
    calls: dict[str, int] = {}
    cur = callee = None
    in_call = False
    for ln in path.read_text(errors="replace").splitlines():
        m = re.match(r"^(c?fn)=(?:\((\d+)\))?\s*(.*)$", ln)
        if m:
            kind, ident, name = m.groups()
            if ident is not None:
                if name:
                    names[ident] = name
                name = names.get(ident, name)
            if kind == "fn":
                cur = name
            else:
                callee = name
            continue
        if ln.startswith("calls="):
            in_call = True
            continue
        if ln[:1] in "0123456789+-*" and cur is not None:
            f = ln.split()
            cost = int(f[1]) if len(f) > 1 else 0
            if in_call:
                if callee != cur:  # no recursion here; a recursive call is in its own count already
                    calls[cur] = calls.get(cur, 0) + cost
                in_call = False
            else:
                own[cur] = own.get(cur, 0) + cost
    return {f: own.get(f, 0) + calls.get(f, 0) for f in set(own) | set(calls)}


def inclusive_per_cycle(exe: Path, patterns: dict[str, str]) -> dict[str, float]:
    """Inclusive instructions per cycle of the functions ``patterns`` (name:
    regular expression of callgrind's function names, every match summed)
    in the last two callgrind runs of ``exe`` (``runtime.per_cycle``)."""
    from runtime import RT

    out = {}
    c1 = callgrind_inclusive(RT / f"callgrind.{exe.name}.1000.out")
    c2 = callgrind_inclusive(RT / f"callgrind.{exe.name}.2000.out")
    for k, pat in patterns.items():
        def total(c):
            return sum(v for f, v in c.items() if re.fullmatch(pat, f))
        out[k] = (total(c2) - total(c1)) / 1000
    return out


def glue_controller(g: Guard) -> str | Path:
    """The controller the glue is linked with (``runtime.glue_per_cycle``):
    the diagram's C that ``pyrosgen generate`` wrote, or the example's."""
    return g.controller_dir / f"{g.controller}.c" if g.controller_dir else f"{g.node}_controller.c"


def handwritten_harness(g: Guard, nodes: dict, extra_env: dict | None = None) -> tuple[Path, str]:
    """The hand-written callback and command builders (their own
    translation unit) linked with hw_harness_laser_guard.cpp; the program
    and its checksum line."""
    from runtime import _pkg

    ros = _pkg("roscpp")
    cflags = [f for f in ros if not f.startswith("-l")]
    node_o, harness_o = g.work / "hw_node.o", g.work / "hw_harness.o"
    hw_exe = g.work / f"{g.node}_hw_fake"
    run(["g++", "-std=c++14", "-O2", f"-D{g.no_main}", "-I", nodes["ctrl_dir"], "-c", g.handwritten,
         "-o", node_o, *cflags])
    run(["g++", "-std=c++14", "-O2", *g.hw_defs, "-I", nodes["ctrl_dir"], "-I", HARNESS.parent, "-c", HARNESS,
         "-o", harness_o, *cflags])
    run(["g++", harness_o, node_o, nodes["ctrl_o"], "-o", hw_exe, *ros])
    return hw_exe, run([hw_exe], env=dict(os.environ, **(extra_env or {}))).stdout.strip()


def instructions(g: Guard, nodes: dict, env: dict) -> dict:
    from runtime import glue_per_cycle, per_cycle

    gen = glue_per_cycle(g.node, g.example, g.work, list(g.fake_defs), g.log, node=g.node, fake=FAKE,
                         controller=glue_controller(g), env=env)
    ctrl = glue_controller(g)
    ctrl = ctrl if isinstance(ctrl, Path) else g.work / f"glue_{g.node}" / ctrl
    # both sides run the same controller
    if ctrl.read_text() != (nodes["ctrl_dir"] / f"{g.controller}.c").read_text():
        raise SystemExit(f"{g.tag}: the controller of the example and of the 1 ms model differ")
    hw_exe, hw_check = handwritten_harness(g, nodes)
    if gen["check"] != hw_check:
        raise SystemExit(f"{g.tag}: the fake-ROS harnesses disagree: generated {gen['check']!r}, "
                         f"hand-written {hw_check!r}")
    g.log("hand-written callback and command (callgrind)")
    hw = per_cycle(hw_exe, ["scanCallback*", "hw_output*"], ("sink",))
    hw["time_source"] = _time_source(hw_exe)
    rt = per_cycle(hw_exe, ["roscpp_roundtrip*"], (), {"BENCH_MODE": "roscpp"})
    gl = {"model": gen["model"], "functions": gen["functions"], "per_cycle": sum(gen["functions"].values()),
          "time_source": sum(v for f, v in gen["functions"].items() if f in ("ros_time_sec", "ros_time_nsec"))}
    res = {"generated": gl, "handwritten": hw, "roscpp_roundtrip": rt, "check": hw_check,
           "ratio": gl["per_cycle"] / hw["per_cycle"],
           # without reading the clock (the generated node reads it in its
           # wrapper's ros_spinOnce, outside the glue; ros::Time::now()'s
           # cost depends on simulated or wall time)
           "ratio_without_time": (gl["per_cycle"] - gl["time_source"]) / (hw["per_cycle"] - hw["time_source"]),
           "_exes": {"generated": g.work / f"{g.node}_{g.node}_fake", "handwritten": hw_exe}}
    for k in ("generated", "handwritten", "roscpp_roundtrip"):
        d = res[k]
        g.log(f"  instructions per cycle, {k}: {d['per_cycle']:.1f} "
              f"({', '.join(f'{f} {v:.1f}' for f, v in sorted(d['functions'].items(), key=lambda kv: -kv[1]))})")
    g.log(f"  ratio generated / hand-written: {res['ratio']:.2f} ({res['ratio_without_time']:.2f} without the time stamp)")
    return res


def latency(g: Guard, nodes: dict, rounds: int, edges: int) -> dict:
    from runtime import latency as runtime_latency

    return runtime_latency({"generated": nodes["generated"], "handwritten": nodes["handwritten"],
                            "driver": nodes["driver"]}, rounds=rounds, edges=edges, log=g.log,
                           remaps=g.remaps, scenario="laser")


def run_laserscan(env: dict, *, instructions_too: bool = True, latency_too: bool = True, rounds: int = 3,
                  edges: int = 1500, previous: dict | None = None, guard: Guard = LASER_GUARD,
                  more_instructions=None) -> dict:
    """Both parts (or one: a part not run keeps its ``previous`` results);
    ``env``: pyrosgen's environment (``PYROSGEN_COQLIB``);
    ``more_instructions(guard, nodes, env, res)``: further counts (the scan
    guard's, with the wrapper) added to the instruction results ``res``."""
    g = guard
    for tool in ("valgrind", "callgrind_annotate", "g++", "pkg-config"):
        if shutil.which(tool) is None:
            raise SystemExit(f"{g.tag}: {tool} not found")
    check_model_1ms(g)
    res: dict = dict(previous or {})
    res["machine"] = machine()
    nodes = build(g, env)
    res["build"] = nodes["build"]
    if instructions_too:
        ins = instructions(g, nodes, env)
        if more_instructions:
            more_instructions(g, nodes, env, ins)
        ins.pop("_exes")
        res["instructions"] = ins
    if latency_too:
        g.log(f"latency at 1 ms, {rounds} round(s) of {edges} edges per node (private master)")
        res["latency"] = latency(g, nodes, rounds, edges)
    res["machine"]["load_at_end"] = loadavg()
    return res


def guard_main(argv: list[str] | None, doc: str, guard: Guard, report_block, more_instructions=None) -> int:
    """The command line of bench/laserscan.py and bench/scan_guard.py."""
    ap = argparse.ArgumentParser(description=doc.splitlines()[0])
    ap.add_argument("--no-latency", action="store_true", help="only count the instructions")
    ap.add_argument("--no-instructions", action="store_true", help="only measure the latency")
    ap.add_argument("--rounds", type=int, default=3, help="latency rounds (fresh nodes each)")
    ap.add_argument("--edges", type=int, default=1500, help="latency edges per node and round")
    ap.add_argument("--no-report", action="store_true", help="do not rewrite BENCHMARKS.md")
    a = ap.parse_args(argv)
    name = f"{guard.tag}.json"
    res = run_laserscan(dict(os.environ), instructions_too=not a.no_instructions, latency_too=not a.no_latency,
                        rounds=a.rounds, edges=a.edges, previous=load_json(name), guard=guard,
                        more_instructions=more_instructions)
    save_json(name, res)
    import report

    print(report_block(lambda n: res if n == name else None))
    if not a.no_report:
        report.write_blocks(load_json, [guard.tag], log=guard.log)
    return 0


def main(argv: list[str] | None = None) -> int:
    import report

    return guard_main(argv, __doc__, LASER_GUARD, report.block_laserscan)


if __name__ == "__main__":
    sys.exit(main())

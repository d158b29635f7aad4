"""ROS 2 (issue 31, BENCHMARKS.md section 13): the generated rcl nodes of
LandShark and the scan guard against the same nodes written by hand over
rcl, and ``pyrosgen build --ros2`` against ROS 1's ``pyrosgen build``, in
one run.

usage: .venv/bin/python bench/ros2.py [--quick] [--rounds N] [--turns N] [--builds N] [--no-report]
       .venv/bin/python bench/ros2.py --what-if
       .venv/bin/python bench/ros2.py --by-function

- **instructions per cycle, glue + rcl wrapper together** (callgrind,
  exact): each node linked with bench/runtime/fake_rcl.c (a fake rcl
  layer: no DDS; rcl_take hands the node a rosidl message built in process
  by the node's driver, bench/runtime/fake_rcl_<node>.c, rcl_publish folds
  what the node publishes into a checksum); the generated node is its
  glue, its rcl wrapper ``<node>_rcl.c`` and its controller as ``pyrosgen
  build --ros2`` wrote and compiles them (the same flags), the hand-written
  one bench/handwritten/<node>_handwritten_rcl.c (the rosidl message read
  where it lies) with the same controller.  Counted: every instruction
  from ``main`` on (callgrind ``--toggle-collect``) except inside
  ``rcl_take`` and ``rcl_publish`` (the middleware), ``clock_nanosleep``
  (the sleep; the fake returns at once and ends the cycle) and the
  controller's step function (the same code on both sides), and the fake's
  own instructions in ``clock_gettime`` (``FAKE_SELF``: it calls libc's,
  which is counted, then answers the simulated steady clock).  Per cycle =
  (count at 2N cycles - count at N) / N; a cycle is one message on every
  input and one on every output.  Both must publish the same messages
  (checksums compared).  The scan guard twice: the scan guard's scans of
  bench/runtime/laser_scans.h (0 to 2,000 ranges), and every scan 1,081
  ranges.
- **round trip** at a 1 ms period: an rclpy peer
  (bench/runtime/ros2_latency_peer.py) publishes and times the first
  output reflecting it; LandShark (bench/models/landshark_1ms.yaml with the
  bit-exact echo controller of tests/ros, against
  bench/handwritten/landshark_handwritten_rcl.c) and the scan guard (its
  example at 1 ms, against bench/handwritten/scan_guard_handwritten_rcl.c);
  ``--rounds`` rounds per node and turn, the generated and hand-written
  node in turn (``--turns``), each alone.
- **build**: ``pyrosgen build --ros2`` and ``pyrosgen build`` (ROS 1) of
  examples/landshark (C controller) into fresh folders, alternating,
  ``--builds`` times each (the command line, as a user runs it).

The scan guard is built from its example with the ``stamp: now`` of
/cmd_vel, which the ROS 2 target builds since ROS 2 stamps are proved
(DESIGN.md rules 4.13, 4.17), and the hand-written node stamps too.  A
model the ROS 2 target refuses and that builds without its one ``stamp:
now`` would still be built without it (the hand-written node then does not
stamp either: ``-DSCAN_GUARD_NO_STAMP``), the variant derived from the
example at run time and checked to differ in the period and that key
only; no example needs it any more.

Every ROS 2 process runs in the environment of
``pyrosgen.ros2.env.ros2_env`` (loopback discovery, a domain of its own)
and is stopped by its PID; the Fast DDS segments that appeared during the
run and that no live process maps (``leftover_segments``: other people's
running nodes keep theirs) are removed.  Results: bench/results/ros2.json (``--quick``: fewer
rounds and builds, into build/bench/results-quick/); the ``ros2`` block of
BENCHMARKS.md is rewritten from them (``report_block``).

``--what-if``: only the instruction counts of the generated nodes with the
changes to the rcl wrapper of ``WHAT_IF`` (applied to the generated
``<node>_rcl.c``: section 13's proposals, or, as now, what one of the
environment model's promises costs, measured by dropping it), each and all
together, into bench/results/ros2_what_if.json.

``--by-function``: only the generated nodes' instructions per cycle by
function of their ``<node>_rcl.c`` as written (the wrapper compiled with
``-g`` added, otherwise as ``build --ros2`` does; ``callgrind_annotate``'s
count of each source line summed over the lines of each function, so that
code the compiler inlined counts where it is written: section 13's
account), with the glue's and the libraries' functions as callgrind names
them, into bench/results/ros2_by_function.json.

``--floor``: LandShark's generated node changed by hand as no proved
design makes it yet, to measure how far those designs could go: the glue's
callbacks reading the rosidl message where it lies (their parameter
rosidl's type, the wrapper's conversion into the C struct gone; the glue
reads ``twist.linear.x`` only, so the same messages are published), the glue
and wrapper compiled as one translation unit, and then also without
``ros::Rate``'s late-cycle rule; into bench/results/ros2_floor.json.  The
checksums must equal the unchanged node's."""

from __future__ import annotations

import argparse
import json
import os
import re
import shutil
import signal
import statistics
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from common import REPO, loadavg, machine, save_json  # noqa: E402

BENCH = REPO / "bench"
RT = BENCH / "runtime"
HW = BENCH / "handwritten"
EXAMPLE = REPO / "examples" / "landshark" / "landshark_controller.yaml"
CTL = REPO / "examples" / "landshark" / "controller"
PEER = RT / "ros2_latency_peer.py"
SHM = Path("/dev/shm")
#: The scan guard's model: what ROS 2 refuses for now (rule 4.17).
STAMP_NOW = "stamp: now, "


@dataclass(frozen=True)
class Node:
    """One node of the comparison."""

    tag: str
    controller: Path          #: the controller folder (both nodes)
    step: str                 #: the controller's step function (not counted)
    handwritten: Path
    driver: Path              #: bench/runtime/fake_rcl_<tag>.c
    driver_defs: tuple = ()
    model: Path | None = None  #: None: derived from ``example`` (derive_model)
    example: Path | None = None


LANDSHARK = Node(tag="landshark", controller=REPO / "tests" / "ros" / "controllers" / "landshark_echo",
                 step="Controller_step", handwritten=HW / "landshark_handwritten_rcl.c",
                 driver=RT / "fake_rcl_landshark.c", model=BENCH / "models" / "landshark_1ms.yaml")
SCAN_GUARD = Node(tag="scan_guard", controller=REPO / "examples" / "scan_guard" / "controller",
                  step="ScanGuard_step", handwritten=HW / "scan_guard_handwritten_rcl.c",
                  driver=RT / "fake_rcl_scan_guard.c", driver_defs=("-DSCAN_GUARD_SCANS",),
                  example=REPO / "examples" / "scan_guard" / "scan_guard.yaml")
NODES = (LANDSHARK, SCAN_GUARD)


def log(msg: str) -> None:
    print(f"bench ros2: {msg}", file=sys.stderr, flush=True)


# ---------------------------------------------------------------------------
# Parsing and aggregation (pure; tests/bench/test_ros2_bench.py)

_ANN = re.compile(r"^\s*([\d,]+) \(\s*[\d.]+%\)\s+(\S*?):(\S.*?)(?: \[(.*)\])?\s*$")


def parse_annotate(text: str) -> dict[str, int]:
    """The self count of each function in ``callgrind_annotate`` output
    (``file:function [object]`` lines, the object left out for some of
    libc's; the same function in several files summed), without the
    PROGRAM TOTALS line."""
    out: dict[str, int] = {}
    for ln in text.splitlines():
        m = _ANN.match(ln)
        if m:
            fn = m.group(3).strip()
            out[fn] = out.get(fn, 0) + int(m.group(1).replace(",", ""))
    return out


def program_total(text: str) -> int:
    """The PROGRAM TOTALS of ``callgrind_annotate`` output."""
    m = re.search(r"^\s*([\d,]+) \(\s*[\d.]+%\)\s+PROGRAM TOTALS", text, re.M)
    if not m:
        raise ValueError("no PROGRAM TOTALS in callgrind_annotate output")
    return int(m.group(1).replace(",", ""))


def per_cycle(short: dict[str, int], long: dict[str, int], n_short: int, n_long: int) -> dict:
    """Per-cycle counts from two runs of ``n_short`` and ``n_long`` cycles:
    ``total`` and, by function, (count in the long run - count in the
    short) / (n_long - n_short), the functions that cost nothing per cycle
    left out; a function cheaper in the longer run is an error (the two
    runs did not do the same thing per cycle)."""
    if n_long <= n_short:
        raise ValueError(f"the long run ({n_long} cycles) must be longer than the short one ({n_short})")
    funcs: dict[str, float] = {}
    for fn in set(short) | set(long):
        d = long.get(fn, 0) - short.get(fn, 0)
        if d < 0:
            raise ValueError(f"{fn}: {long.get(fn, 0)} instructions in {n_long} cycles, "
                             f"{short.get(fn, 0)} in {n_short}")
        if d:
            funcs[fn] = d / (n_long - n_short)
    funcs = dict(sorted(funcs.items(), key=lambda kv: (-kv[1], kv[0])))
    return {"total": sum(funcs.values()), "functions": funcs}


#: Functions of bench/runtime/fake_rcl.c that run on the counted side of
#: the toggles: their own instructions are the fake's, not the node's, and
#: are left out (fake_rcl.c's clock_gettime wraps the real one, libc's
#: ``clock_gettime@@GLIBC_2.17``, which is counted).
FAKE_SELF = ("clock_gettime",)


def without_fake(res: dict) -> dict:
    """``res`` (a ``per_cycle`` result) without the fake layer's own
    instructions (``FAKE_SELF``), which it records as ``fake_left_out``."""
    funcs = {f: v for f, v in res["functions"].items() if f not in FAKE_SELF}
    left = sum(v for f, v in res["functions"].items() if f in FAKE_SELF)
    return {**res, "total": res["total"] - left, "functions": funcs, "fake_left_out": left}


def latency_summary(xs: list[float], rounds: int) -> dict:
    """Median and percentiles (ms) of the answered rounds."""
    if not xs:
        raise ValueError("no round answered")
    s = sorted(xs)

    def pct(q: float) -> float:
        return s[min(len(s) - 1, int(q * len(s)))]
    return {"rounds": rounds, "answered": len(xs), "median": statistics.median(s), "p10": pct(0.10),
            "p90": pct(0.90), "p99": pct(0.99), "max": s[-1]}


# ---------------------------------------------------------------------------
# Building

def derive_model(node: Node, work: Path, inst) -> tuple[Path, bool]:
    """The model file of ``node`` at a 1 ms period, and whether ``stamp:
    now`` was dropped from it (only if the ROS 2 target refuses the model
    with it: no example since ROS 2 stamps are proved)."""
    from pyrosgen.errors import PyrosgenError
    from pyrosgen.ros2.frontend import load_model_ros2

    if node.model is not None:
        return node.model, False
    text = node.example.read_text()
    new = re.sub(r"(\n  period_ms: )\d+", r"\g<1>1", text, count=1)
    if new == text:
        raise SystemExit(f"{node.example}: no period_ms to set to 1")
    dropped = False
    try:
        load_model_ros2(node.example, inst)
    except PyrosgenError:
        if new.count(STAMP_NOW) != 1:
            raise SystemExit(f"{node.example} does not build for ROS 2, and not for want of one `{STAMP_NOW}`")
        new = new.replace(STAMP_NOW, "")
        dropped = True
    out = work / f"{node.tag}_1ms.yaml"
    out.write_text(new)
    return out, dropped


def _run(argv: list, **kw) -> subprocess.CompletedProcess:
    r = subprocess.run([str(a) for a in argv], capture_output=True, text=True, **kw)
    if r.returncode != 0:
        raise SystemExit(f"{' '.join(str(a) for a in argv)}: exit {r.returncode}\n{r.stderr[-3000:]}{r.stdout[-2000:]}")
    return r


def build_pair(node: Node, model: Path, dropped: bool, work: Path, inst, env: dict) -> dict:
    """``pyrosgen build --ros2`` of ``model``, and the hand-written node:
    their real binaries, and both again linked with the fake rcl layer."""
    from pyrosgen.ros.wrapper import GLUE_CFLAGS
    from pyrosgen.ros2.build import compile_flags, link_flags
    from pyrosgen.ros2.frontend import load_model_ros2

    out = work / f"{node.tag}_gen"
    _run([sys.executable, "-m", "pyrosgen", "build", model, "--controller", node.controller, "-o", out, "--ros2"],
         env=env, timeout=1800)
    m = load_model_ros2(model, inst)
    cf, lf = compile_flags(inst), link_flags(inst, m)
    obj = work / f"{node.tag}_obj"
    obj.mkdir(exist_ok=True)
    ctl_src = sorted(node.controller.glob("*.c"))
    ctl_objs = []
    for src in ctl_src:
        o = obj / f"ctl_{src.stem}.o"
        _run(["gcc", "-std=c11", "-O2", "-Wall", "-Wextra", "-I", node.controller, "-c", src, "-o", o])
        ctl_objs.append(o)
    hw_defs = ["-DSCAN_GUARD_NO_STAMP"] if dropped else []
    objs = {}
    for name, src, flags in (
            ("glue", out / f"{m.name}_glue.c", [*GLUE_CFLAGS, "-I", out]),
            ("rcl", out / f"{m.name}_rcl.c", [*GLUE_CFLAGS, "-I", out, *cf]),
            ("fake", RT / "fake_rcl.c", ["-std=c11", "-O2", "-Wall", "-Wextra", "-Werror", "-I", RT, *cf]),
            ("driver", node.driver, ["-std=c11", "-O2", "-Wall", "-Wextra", "-Werror", *node.driver_defs,
                                     "-I", RT, *cf]),
            ("hw", node.handwritten, ["-std=c11", "-O2", "-Wall", "-Wextra", "-Werror", *hw_defs,
                                      "-I", node.controller, *cf])):
        objs[name] = obj / f"{name}.o"
        _run(["gcc", *flags, "-c", src, "-o", objs[name]])
    exes = {"generated": obj / f"{node.tag}_generated_fake", "handwritten": obj / f"{node.tag}_handwritten_fake",
            "handwritten_real": obj / f"{node.tag}_handwritten_rcl"}
    fake = [objs["fake"], objs["driver"]]
    _run(["gcc", objs["glue"], objs["rcl"], *ctl_objs, *fake, "-o", exes["generated"], *lf, "-lm"])
    _run(["gcc", objs["hw"], *ctl_objs, *fake, "-o", exes["handwritten"], *lf, "-lm"])
    _run(["gcc", objs["hw"], *ctl_objs, "-o", exes["handwritten_real"], *lf, "-lm"])
    exes["generated_real"] = out / "bin" / m.name
    res = {k: Path(v) for k, v in exes.items()}
    # what what_if needs to link the generated node again with another wrapper
    res["parts"] = {"rcl_source": out / f"{m.name}_rcl.c", "include": out, "cflags": cf, "lflags": lf,
                    "objects": [objs["glue"], *ctl_objs, *fake]}
    return res


# ---------------------------------------------------------------------------
# Instructions

def _callgrind(exe: Path, cycles: int, toggles: list[str], extra_env: dict) -> tuple[str, str]:
    """One callgrind run of ``exe`` (``cycles`` cycles): its stdout (the
    checksum line) and ``callgrind_annotate``'s output."""
    outf = exe.parent / f"callgrind.{exe.name}.{cycles}.out"
    env = dict(os.environ, BENCH_CYCLES=str(cycles), **extra_env)
    r = _run(["valgrind", "--tool=callgrind", f"--callgrind-out-file={outf}",
              *[f"--toggle-collect={t}" for t in toggles], exe], env=env, timeout=900)
    ann = _run(["callgrind_annotate", "--threshold=100", outf]).stdout
    return r.stdout.strip(), ann


_SRC_LINE = re.compile(r"^\s*([\d,]+|\.)\s")
_FUNC_START = re.compile(r"^(?:static )?(?:inline )?[A-Za-z_][\w ]*?[ *](\w+)\((?!.*;\s*$)")


def source_line_counts(ann: str, source_name: str) -> list[int]:
    """The instruction count of each line (index 0: line 1) of the source
    file named ``source_name`` in ``callgrind_annotate --auto=yes
    --context=N`` output with N at least the file's length (every line
    printed once, in order; the calls' ``=>`` lines left out)."""
    parts = re.split(r"^-- Auto-annotated source: (.*)$", ann, flags=re.M)
    texts = [parts[i + 1] for i in range(1, len(parts), 2) if Path(parts[i].strip()).name == source_name]
    if len(texts) != 1:
        raise ValueError(f"{source_name}: {len(texts)} annotated sources in callgrind_annotate's output")
    counts: list[int] = []
    for ln in texts[0].splitlines():
        if ln.startswith("--"):
            if counts:
                break   # the end of the file's lines (a summary follows)
            continue
        if "=>" in ln[:40]:
            continue
        m = _SRC_LINE.match(ln)
        if m:
            counts.append(0 if m.group(1) == "." else int(m.group(1).replace(",", "")))
    return counts


def function_spans(source: str) -> dict[str, tuple[int, int]]:
    """The top-level functions of the C ``source``: name -> (index of its
    definition's first line, index of its closing ``}`` at the start of a
    line)."""
    out: dict[str, tuple[int, int]] = {}
    name, first = None, 0
    for i, text in enumerate(source.splitlines()):
        m = _FUNC_START.match(text)
        if name is None and m:
            name, first = m.group(1), i
        elif name is not None and text == "}":
            out[name] = (first, i)
            name = None
    return out


def function_counts(source: str, counts: list[int]) -> dict[str, int]:
    """``counts`` (per source line) summed over each top-level function of
    the C ``source`` (``function_spans``); the functions with no count
    left out."""
    out = {name: sum(counts[a:b + 1]) for name, (a, b) in function_spans(source).items()}
    return {name: c for name, c in out.items() if c}


def by_function(node: Node, pair: dict, cycles: int) -> dict:
    """``--by-function`` for one node (see the module documentation): per
    cycle, (count at 2N cycles - count at N) / N, by function of the
    wrapper's source, and the other functions' self counts."""
    from pyrosgen.ros.wrapper import GLUE_CFLAGS

    parts = pair["parts"]
    src = Path(parts["rcl_source"])
    o, exe = (pair["generated"].parent / f"{node.tag}_generated_g{ext}" for ext in (".o", ""))
    _run(["gcc", *GLUE_CFLAGS, "-g", "-I", parts["include"], *parts["cflags"], "-c", src, "-o", o])
    _run(["gcc", o, *parts["objects"], "-o", exe, *parts["lflags"], "-lm"])
    extra = {"BENCH_SCAN_LENGTH": "1081"} if node is SCAN_GUARD else {}
    toggles = ["main", "rcl_take", "rcl_publish", "clock_nanosleep", node.step]
    lines, selfs = [], []
    for n in (cycles, 2 * cycles):
        outf = exe.parent / f"callgrind.{exe.name}.{n}.out"
        _run(["valgrind", "--tool=callgrind", f"--callgrind-out-file={outf}",
              *[f"--toggle-collect={t}" for t in toggles], exe],
             env=dict(os.environ, BENCH_CYCLES=str(n), **extra), timeout=900)
        ann = _run(["callgrind_annotate", "--auto=yes", f"--context={len(src.read_text().splitlines()) + 10}",
                    "--threshold=100", outf]).stdout
        lines.append(function_counts(src.read_text(), source_line_counts(ann, src.name)))
        selfs.append(parse_annotate(ann))
    wrapper = per_cycle(lines[0], lines[1], cycles, 2 * cycles)
    others = without_fake(per_cycle(selfs[0], selfs[1], cycles, 2 * cycles))
    # the wrapper's functions by source line; every other function (glue, libraries) by its self count
    # (gcc's clones of a wrapper function, such as qos_event.constprop.0, are the wrapper's)
    names = set(function_spans(src.read_text()))
    rest = {f: v for f, v in others["functions"].items() if f.split(".")[0] not in names}
    total = wrapper["total"] + sum(rest.values())
    return {"total": total, "wrapper": wrapper["functions"], "wrapper_total": wrapper["total"], "others": rest}


def run_by_function(cycles: int = 1000) -> dict:
    """``--by-function``: both generated nodes built, then only
    ``by_function``; saved as ros2_by_function.json."""
    from pyrosgen.ros2.env import find_ros2

    inst = find_ros2()
    work = Path(tempfile.mkdtemp(prefix="pyrosgen-bench-ros2-"))
    try:
        out = {"when": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()), "load": loadavg(), "nodes": {}}
        for node in NODES:
            model, dropped = derive_model(node, work, inst)
            out["nodes"][node.tag] = by_function(node, build_pair(node, model, dropped, work, inst, dict(os.environ)),
                                                 cycles)
        save_json("ros2_by_function.json", out)
        return out
    finally:
        shutil.rmtree(work, ignore_errors=True)


def count(exe: Path, node: Node, cycles: int, extra_env: dict) -> dict:
    """Instructions per cycle of ``exe`` (see the module documentation)."""
    toggles = ["main", "rcl_take", "rcl_publish", "clock_nanosleep", node.step]
    out1, a1 = _callgrind(exe, cycles, toggles, extra_env)
    out2, a2 = _callgrind(exe, 2 * cycles, toggles, extra_env)
    res = per_cycle(parse_annotate(a1), parse_annotate(a2), cycles, 2 * cycles)
    if abs(res["total"] - (program_total(a2) - program_total(a1)) / cycles) > 0.5:
        raise SystemExit(f"{exe.name}: the functions do not add up to the program's total")
    return {**without_fake(res), "check": [out1, out2]}


def instructions(node: Node, exes: dict, cycles: int) -> dict:
    """Both fake-rcl nodes, same checksums, per-cycle counts; the scan guard
    also with every scan 1,081 ranges."""
    regimes = {"mixed": {}}
    if node is SCAN_GUARD:
        regimes["full"] = {"BENCH_SCAN_LENGTH": "1081"}
    res = {}
    for regime, extra in regimes.items():
        row = {}
        for side in ("generated", "handwritten"):
            log(f"{node.tag} {regime}: callgrind of the {side} node")
            row[side] = count(exes[side], node, cycles, extra)
        if row["generated"]["check"] != row["handwritten"]["check"]:
            raise SystemExit(f"{node.tag} ({regime}): the two nodes published different messages: "
                             f"{row['generated']['check']} against {row['handwritten']['check']}")
        row["ratio"] = row["generated"]["total"] / row["handwritten"]["total"]
        res[regime] = row
    return res


# ---------------------------------------------------------------------------
# What if: changes to the rcl wrapper, measured on the generated file

#: Changes to ``<node>_rcl.c`` measured, not made in
#: pyrosgen/templates/rcl_api.c.j2: name -> (regular expression,
#: replacement).  Section 13's earlier proposals are made (no memset of the
#: take buffer, only the message info's received_timestamp zeroed, since
#: 9f0193d; the ROS time read only when the glue asks, since 2026-11-29);
#: this one drops a promise of the environment model (DESIGN.md section
#: 6.1) to measure what it costs, and stays out of the wrapper.
WHAT_IF = {
    "no steady clock read in ros_rate_sleep (ros::Rate's rule for a late cycle)": (
        r"long long now = steady_ns\(\);(\n    g_next_ns \+= PYROSGEN_PERIOD_NS;)", r"long long now = 0;\1"),
}


def patched(text: str, names: list[str]) -> str:
    """``text`` with the changes ``names`` of WHAT_IF; an error if one of
    them does not apply (the wrapper changed: the proposal is stale)."""
    for name in names:
        pat, rep = WHAT_IF[name]
        text, n = re.subn(pat, rep, text)
        if n == 0:
            raise ValueError(f"what-if change {name!r} does not apply to this wrapper")
    return text


def what_if(node: Node, pair: dict, cycles: int) -> dict:
    """Instructions per cycle of the generated node with each WHAT_IF change
    and with all of them, against the unchanged node and the hand-written
    one (the scan guard with scans of 1,081 ranges); same checksums."""
    from pyrosgen.ros.wrapper import GLUE_CFLAGS

    parts = pair["parts"]
    extra = {"BENCH_SCAN_LENGTH": "1081"} if node is SCAN_GUARD else {}
    hw = count(pair["handwritten"], node, cycles, extra)
    res = {"handwritten": hw["total"], "unchanged": count(pair["generated"], node, cycles, extra)["total"]}
    text = parts["rcl_source"].read_text()
    for label, names in [*((n, [n]) for n in WHAT_IF), ("all of them", list(WHAT_IF))]:
        try:
            src = patched(text, names)
        except ValueError as exc:
            res[label] = str(exc)
            continue
        tag = re.sub(r"\W+", "_", label)
        c, o, exe = (pair["generated"].parent / f"what_if_{tag}{ext}" for ext in (".c", ".o", ""))
        c.write_text(src)
        _run(["gcc", *GLUE_CFLAGS, "-I", parts["include"], *parts["cflags"], "-c", c, "-o", o])
        _run(["gcc", o, *parts["objects"], "-o", exe, *parts["lflags"], "-lm"])
        got = count(exe, node, cycles, extra)
        if got["check"] != hw["check"]:
            raise SystemExit(f"{node.tag}, {label}: the changed node publishes other messages")
        res[label] = got["total"]
        log(f"{node.tag} what if {label}: {got['total']:.0f} (unchanged {res['unchanged']:.0f})")
    return res


def run_what_if(cycles: int = 1000) -> dict:
    """``--what-if``: both nodes built, then only ``what_if``; saved as
    ros2_what_if.json (ros2.json is left alone)."""
    from pyrosgen.ros2.env import find_ros2

    inst = find_ros2()
    work = Path(tempfile.mkdtemp(prefix="pyrosgen-bench-ros2-"))
    try:
        out = {"when": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()), "load": loadavg(), "nodes": {}}
        for node in NODES:
            model, dropped = derive_model(node, work, inst)
            out["nodes"][node.tag] = what_if(node, build_pair(node, model, dropped, work, inst, dict(os.environ)),
                                             cycles)
        save_json("ros2_what_if.json", out)
        return out
    finally:
        shutil.rmtree(work, ignore_errors=True)


# ---------------------------------------------------------------------------
# Floor: LandShark with the designs that are not made

def floor_variants(glue: str, rcl: str) -> dict[str, tuple[str, str]]:
    """The (glue, wrapper) texts of ``--floor``'s variants of LandShark's
    generated node; a ``ValueError`` if a change does not apply (the
    generated files changed: the measurement is stale)."""
    def subn(pat: str, rep: str, text: str, want: int) -> str:
        text, n = re.subn(pat, rep, text)
        if n != want:
            raise ValueError(f"floor: {pat!r} applies {n} times, not {want}")
        return text

    msg = "geometry_msgs_TwistStamped"
    g = subn(rf"_callback\(struct {msg} \*msg\)", "_callback(geometry_msgs__msg__TwistStamped *msg)", glue, 6)
    g = subn(r"ros_subscribe_(\w+)\(&(\w+)\)", rf"ros_subscribe_\1((void (*)(struct {msg} *))&\2)", g, 3)
    r = subn(rf"        to_c_{msg}\(&g_take_(\w+), &g_buf_\w+\);\n", "", rcl, 3)
    r = subn(r"g_cb_(\w+)\(&g_buf_\w+\);", rf"g_cb_\1((struct {msg} *)(void *)&g_take_\1);", r, 3)
    late = subn(r"long long now = steady_ns\(\);", "long long now = 0;", r, 1)
    return {"one translation unit": (glue, rcl),
            "in place, one translation unit": (g, r),
            "in place, one translation unit, no late-cycle rule": (g, late)}


def run_floor(cycles: int = 1000) -> dict:
    """``--floor`` (see the module documentation); saved as ros2_floor.json."""
    from pyrosgen.ros.wrapper import GLUE_CFLAGS
    from pyrosgen.ros2.env import find_ros2

    inst = find_ros2()
    work = Path(tempfile.mkdtemp(prefix="pyrosgen-bench-ros2-"))
    try:
        node = LANDSHARK
        model, dropped = derive_model(node, work, inst)
        pair = build_pair(node, model, dropped, work, inst, dict(os.environ))
        parts = pair["parts"]
        out_dir = Path(parts["include"])
        glue = next(out_dir.glob("*_glue.c"))
        hw = count(pair["handwritten"], node, cycles, {})
        base = count(pair["generated"], node, cycles, {})
        res = {"when": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()), "load": loadavg(),
               "handwritten": hw["total"], "unchanged": base["total"], "variants": {}}
        flags = [f for f in GLUE_CFLAGS if f not in ("-Werror", "-pedantic")]   # the callbacks' pointer casts
        objects = [o for o in parts["objects"] if Path(o).name != "glue.o"]
        for k, (name, (g, r)) in enumerate(floor_variants(glue.read_text(), Path(parts["rcl_source"]).read_text())
                                           .items()):
            d = work / f"floor{k}"
            d.mkdir()
            (d / "rcl.c").write_text(r)
            (d / "glue.c").write_text(g)
            (d / "unity.c").write_text('#include "rcl.c"\n#include "glue.c"\n')
            _run(["gcc", *flags, "-I", out_dir, *parts["cflags"], "-c", d / "unity.c", "-o", d / "unity.o"])
            _run(["gcc", d / "unity.o", *objects, "-o", d / "node", *parts["lflags"], "-lm"])
            c = count(d / "node", node, cycles, {})
            if c["check"] != base["check"]:
                raise SystemExit(f"floor: {name}: the node published other messages")
            res["variants"][name] = c["total"]
            log(f"landshark floor: {name}: {c['total']:.0f} (unchanged {base['total']:.0f}, "
                f"hand-written {hw['total']:.0f})")
        save_json("ros2_floor.json", res)
        return res
    finally:
        shutil.rmtree(work, ignore_errors=True)


# ---------------------------------------------------------------------------
# Latency

def _segments() -> set[str]:
    return {p.name for p in [*SHM.glob("fastdds_*"), *SHM.glob("sem.fastdds_*")]}


def _mapped() -> set[str]:
    """The /dev/shm files some live process has mapped (others' running
    ROS 2 processes: their segments are not ours to remove)."""
    names = set()
    for maps in Path("/proc").glob("[0-9]*/maps"):
        try:
            text = maps.read_text()
        except OSError:
            continue
        names.update(m.group(1) for m in re.finditer(r"/dev/shm/(\S+)", text))
    return names


def leftover_segments(before: set[str]) -> list[str]:
    """The Fast DDS segments that appeared since ``before`` and that no live
    process maps: those our stopped nodes and peers left."""
    mapped = _mapped()
    return sorted(n for n in _segments() - before if n not in mapped and n.removeprefix("sem.") not in mapped)


def latency(node: Node, exes: dict, inst, rounds: int, turns: int) -> dict:
    """The round trip of both real nodes, alternating (see the module documentation)."""
    from pyrosgen.ros2.env import ros2_env

    env = ros2_env()
    lats: dict[str, list[float]] = {"generated": [], "handwritten": []}
    per_turn = []
    for _ in range(turns):
        row = {}
        for side, argv in (("generated", [exes["generated_real"]]), ("handwritten", [exes["handwritten_real"], "1"])):
            p = subprocess.Popen([str(a) for a in argv], env=env, stdout=subprocess.DEVNULL,
                                 stderr=subprocess.DEVNULL, start_new_session=True)
            try:
                r = subprocess.run([str(inst.python), str(PEER), str(rounds), node.tag], env=env,
                                   capture_output=True, text=True, timeout=60 + rounds)
            finally:
                p.send_signal(signal.SIGTERM)
                try:
                    p.wait(timeout=15)
                except subprocess.TimeoutExpired:
                    p.kill()
                    p.wait()
            if r.returncode != 0:
                raise SystemExit(f"{node.tag}: the rclpy peer failed against the {side} node:\n{r.stderr[-2000:]}")
            got = json.loads(r.stdout)["latency_ms"]
            lats[side] += got
            row[side] = statistics.median(got) if got else None
        row["ratio"] = row["generated"] / row["handwritten"] if row["generated"] and row["handwritten"] else None
        row["load"] = loadavg()
        per_turn.append(row)
        log(f"{node.tag} round trip: {row}")
    res = {side: latency_summary(xs, rounds * turns) for side, xs in lats.items()}
    res["turns"] = per_turn
    res["ratio_of_medians"] = res["generated"]["median"] / res["handwritten"]["median"]
    return res


# ---------------------------------------------------------------------------
# Build times

def build_times(builds: int, work: Path, env: dict) -> dict:
    """``pyrosgen build`` for ROS 2 and for ROS 1 of examples/landshark,
    alternating, each into a fresh folder: wall seconds of the command."""
    res: dict[str, list[float]] = {"ros2": [], "ros1": []}
    for i in range(builds):
        for target, extra in (("ros2", ["--ros2"]), ("ros1", [])):
            out = work / f"build_{target}_{i}"
            t0 = time.monotonic()
            _run([sys.executable, "-m", "pyrosgen", "build", EXAMPLE, "--controller", CTL, "-o", out, *extra],
                 env=env, timeout=1800)
            res[target].append(time.monotonic() - t0)
            log(f"build {target} {i}: {res[target][-1]:.2f} s (load {loadavg()})")
            shutil.rmtree(out, ignore_errors=True)
    return {t: {"median": statistics.median(xs), "runs": [round(x, 2) for x in xs]} for t, xs in res.items()} | {
        "ratio": statistics.median(res["ros2"]) / statistics.median(res["ros1"])}


# ---------------------------------------------------------------------------

def run_ros2(env: dict | None = None, *, quick: bool = False, rounds: int | None = None, turns: int | None = None,
             builds: int | None = None, cycles: int = 1000) -> dict:
    """Everything of the module documentation; the result saved as ros2.json."""
    from pyrosgen.ros2.env import find_ros2

    env = dict(env or os.environ)
    rounds = rounds or (100 if quick else 300)
    turns = turns or (1 if quick else 3)
    builds = builds or (1 if quick else 3)
    for tool in ("valgrind", "callgrind_annotate", "gcc"):
        if shutil.which(tool) is None:
            raise SystemExit(f"bench/ros2.py needs {tool}")
    inst = find_ros2()
    work = Path(tempfile.mkdtemp(prefix="pyrosgen-bench-ros2-"))
    before = _segments()
    result: dict = {"machine": machine(), "when": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
                    "load_at_start": loadavg(), "mode": "quick" if quick else "full", "nodes": {}}
    try:
        result["build_s"] = build_times(builds, work, env)
        for node in NODES:
            model, dropped = derive_model(node, work, inst)
            log(f"{node.tag}: building ({model.name}{', without stamp: now' if dropped else ''})")
            exes = build_pair(node, model, dropped, work, inst, env)
            result["nodes"][node.tag] = {
                "model": str(model.relative_to(REPO)) if model.is_relative_to(REPO) else
                f"{node.example.relative_to(REPO)} at 1 ms" + (" without `stamp: now`" if dropped else ""),
                "stamp_dropped": dropped,
                "instructions": instructions(node, exes, cycles),
                "latency": latency(node, exes, inst, rounds, turns)}
        result["load_at_end"] = loadavg()
        save_json("ros2.json", result)
        return result
    finally:
        shutil.rmtree(work, ignore_errors=True)
        for name in leftover_segments(before):
            try:
                (SHM / name).unlink()
            except OSError:
                pass


# ---------------------------------------------------------------------------
# Report

def _top(funcs: dict, k: int = 6) -> str:
    return ", ".join(f"`{f}` {v:.0f}" for f, v in list(funcs.items())[:k])


def report_block(res: dict | None) -> str:
    """The ``ros2`` block of BENCHMARKS.md from ros2.json's contents."""
    if not res or "nodes" not in res:
        return "No ROS 2 run recorded yet: `.venv/bin/python bench/ros2.py`.\n"
    b = res["build_s"]
    lines = [f"Run of {res['when']} ({res['mode']}), load {res['load_at_start']} at the start and "
             f"{res.get('load_at_end', '?')} at the end (1, 5, 15 min; other work shared the 2 cores).", "",
             "| figure | target | measured | |", "|---|---|---|---|"]
    for tag, n in res["nodes"].items():
        lat = n["latency"]
        ok = lat["ratio_of_medians"] <= 1.05
        lines.append(f"| {tag}: round-trip ratio generated / hand-written (medians, 1 ms period) | ≤ 1.05 | "
                     f"{lat['ratio_of_medians']:.3f} | {'met' if ok else 'missed'} |")
        for regime, row in n["instructions"].items():
            what = "mixed scans" if regime == "mixed" and tag == "scan_guard" else \
                "scans of 1,081 ranges" if regime == "full" else "per cycle"
            ok = row["ratio"] <= 1.0
            lines.append(f"| {tag}: instructions per cycle, glue + rcl wrapper / hand-written ({what}) | ≤ 1.0 | "
                         f"{row['generated']['total']:.0f} / {row['handwritten']['total']:.0f} = {row['ratio']:.2f}"
                         f" | {'met' if ok else 'missed'} |")
    lines.append(f"| `pyrosgen build --ros2` / `pyrosgen build` (ROS 1), LandShark | | "
                 f"{b['ros2']['median']:.2f} s / {b['ros1']['median']:.2f} s = {b['ratio']:.2f} | |")
    lines += ["", "Instructions per cycle (callgrind, exact; fake rcl layer, no DDS; everything from `main` "
              "but `rcl_take`, `rcl_publish`, `clock_nanosleep` and the controller's step), by function:", "",
              "| node | scans | side | per cycle | largest functions |", "|---|---|---|---|---|"]
    for tag, n in res["nodes"].items():
        for regime, row in n["instructions"].items():
            scans = {"mixed": "0–2,000 ranges" if tag == "scan_guard" else "–", "full": "1,081 ranges"}[regime]
            for side in ("generated", "handwritten"):
                lines.append(f"| {tag} | {scans} | {side} | {row[side]['total']:.0f} | "
                             f"{_top(row[side]['functions'])} |")
    lines += ["", "Round trip (ms) at a 1 ms period, rclpy peer on Fast DDS (loopback), the two nodes in turn:", "",
              "| node | side | rounds | answered | median | p10 | p90 | p99 | max | per turn (median) |",
              "|---|---|---|---|---|---|---|---|---|---|"]
    for tag, n in res["nodes"].items():
        lat = n["latency"]
        for side in ("generated", "handwritten"):
            s = lat[side]
            turns = ", ".join(f"{t[side]:.3f}" if t[side] else "–" for t in lat["turns"])
            lines.append(f"| {tag} | {side} | {s['rounds']} | {s['answered']} | {s['median']:.3f} | {s['p10']:.3f} | "
                         f"{s['p90']:.3f} | {s['p99']:.3f} | {s['max']:.2f} | {turns} |")
    lines += ["", f"Build of `examples/landshark` (C controller), the command line, alternating: ROS 2 "
              f"{', '.join(f'{x:.2f}' for x in b['ros2']['runs'])} s; ROS 1 "
              f"{', '.join(f'{x:.2f}' for x in b['ros1']['runs'])} s."]
    for tag, n in res["nodes"].items():
        lines.append("")
        lines.append(f"{tag}: model {n['model']}.")
    if res.get("note"):
        lines += ["", f"Note: {res['note']}."]
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="fewer rounds and builds, results in build/bench/")
    ap.add_argument("--rounds", type=int, default=None)
    ap.add_argument("--turns", type=int, default=None)
    ap.add_argument("--builds", type=int, default=None)
    ap.add_argument("--no-report", action="store_true", help="do not rewrite the ros2 block of BENCHMARKS.md")
    ap.add_argument("--what-if", action="store_true",
                    help="only the instruction counts of the proposed wrapper changes (ros2_what_if.json)")
    ap.add_argument("--by-function", action="store_true",
                    help="only the generated nodes' instructions by function of the rcl wrapper (ros2_by_function.json)")
    ap.add_argument("--floor", action="store_true",
                    help="only LandShark with the designs not made: in place, one translation unit (ros2_floor.json)")
    a = ap.parse_args(argv)
    import common

    if a.floor:
        print(json.dumps(run_floor(), indent=1))
        return 0
    if a.by_function:
        print(json.dumps(run_by_function(), indent=1))
        return 0
    if a.what_if:
        print(json.dumps(run_what_if(), indent=1))
        return 0
    if a.quick:
        common.use_results(common.WORK / "results-quick")
    res = run_ros2(quick=a.quick, rounds=a.rounds, turns=a.turns, builds=a.builds)
    print(report_block(res))
    if not a.no_report and not a.quick:
        import report

        report.write_blocks(common.load_json, ["ros2"], log=log)
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""Run time of the scan guard: the generated node against a hand-written
roscpp node (BENCHMARKS.md, section 11; issue 15).

The node of examples/scan_guard/scan_guard.yaml (the whole scan, at most
1,081 ranges, into the Embedded Coder controller's ``ScanGuard_U.Scan[1081]``
with its length in ``NScan``; a ``TwistStamped`` command with ``frame_id``
and ``stamp: now``, and the closest range on ``/closest``) against
bench/handwritten/scan_guard_handwritten.cpp, idiomatic roscpp doing the
same with the same controller (examples/scan_guard/controller).  Measured
as bench/laserscan.py measures the laser guard (same code, its ``Guard``
description of this node):

- **glue instructions per cycle** (callgrind, exact): the generated glue
  (``-O2 -fno-inline``) with bench/runtime/fake_ros_laser_guard.c built with
  ``-DFAKE_SCAN_GUARD``, which hands the glue scans already converted (as
  section 10: the wrapper's conversion is not counted), against the
  hand-written callback, ``make_command`` and ``make_closest`` (their own
  translation unit) driven by bench/runtime/hw_harness_laser_guard.cpp built
  with ``-DHW_SCAN_GUARD``; one scan per cycle, the scan guard's lengths
  (0, 1, 600, 601, 1080, 1081 three times, 1082, 2000:
  bench/runtime/laser_scans.h with ``-DSCAN_GUARD_SCANS``), and again with
  every scan 1,081 ranges (``BENCH_SCAN_LENGTH``);
- **glue + the wrapper's per-message code**: the same glue object with
  bench/runtime/fake_ros_scan_guard_wrapper.cpp, into which this script
  pastes, verbatim, the conversions and per-message functions of the
  wrapper that ``pyrosgen build`` wrote for the node (scan_guard_ros.cpp:
  the subscription lambda, which zeroes the C struct and converts the
  ``sensor_msgs::LaserScan`` into it with ``to_c``, ``ros_spinOnce``'s
  clock read, ``ros_time_sec``/``nsec``, and ``ros_publish_cmd_vel``/
  ``ros_publish_closest``, which build the roscpp messages from the C
  structs): everything the generated node runs per message between roscpp
  handing it a scan and roscpp's ``publish``, as the hand-written side
  counts everything between its ``ConstPtr`` and ``publish``;
- where the instructions go: inclusive counts of each part (callback,
  ``input_glue``, output glue; the wrapper's conversion in, clock read,
  conversion out; the hand-written callback and message builders);
- **latency** at a 1 ms period (bench/models/scan_guard_1ms.yaml, checked
  to differ from the example in the period only), scenario ``laser`` of
  bench/runtime/latency_driver.cpp (scans of 1,081 ranges with an obstacle
  at 0.5 m in the sector, then a clear one: the first command of 0.5 m/s).

All harnesses must publish the same commands (checksums compared).

usage: .venv/bin/python bench/scan_guard.py [--no-latency | --no-instructions]
       [--rounds 3] [--edges 1500] [--no-report]
Writes scan_guard.json into bench/results/, prints Markdown tables and
rewrites the ``scan_guard`` block of BENCHMARKS.md.
"""

from __future__ import annotations

import os
import re
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from common import BENCH, REPO, run  # noqa: E402
from laserscan import Guard, guard_main, inclusive_per_cycle  # noqa: E402

SCAN_GUARD = Guard(tag="scan_guard", node="scan_guard",
                   example=REPO / "examples" / "scan_guard" / "scan_guard.yaml",
                   model_1ms=BENCH / "models" / "scan_guard_1ms.yaml", controller="ScanGuard",
                   controller_dir=REPO / "examples" / "scan_guard" / "controller",
                   handwritten=BENCH / "handwritten" / "scan_guard_handwritten.cpp",
                   no_main="SCAN_GUARD_HANDWRITTEN_NO_MAIN",
                   fake_defs=("-DFAKE_SCAN_GUARD", "-DSCAN_GUARD_SCANS"),
                   hw_defs=("-DHW_SCAN_GUARD", "-DSCAN_GUARD_SCANS"),
                   remaps=("/scan", "/cmd_vel", "/closest"))
WRAPPER_FAKE = BENCH / "runtime" / "fake_ros_scan_guard_wrapper.cpp"

#: Every scan of this length in the second count (a UTM-30LX's scan).
FULL_SCAN = 1081
#: The totals again for scans all of one length, each of these.
LENGTHS = (0, 1, 600, 601, 1080, 1081, 1082, 2000)

#: What each harness's count covers (callgrind --toggle-collect; ``sink``
#: stands for roscpp's publish and is left out).
TOGGLES = {
    "generated": ["input_glue", "*_callback", "output_glue_*"],
    "generated_wrapper": ["wrapper_scan_received*", "wrapper_ros_spinOnce*", "input_glue", "output_glue_*",
                          "ros_publish_*"],
    "handwritten": ["scanCallback*", "hw_output*"],
}
_SINK_CMD = r"sink\(geometry_msgs::TwistStamped.*"
_SINK_CLOSEST = r"sink\(std_msgs::Float32.*"
#: The parts of each count: inclusive counts (regular expressions of
#: callgrind's function names), and how the parts are made of them.
INCLUSIVE = {
    "generated": {"scan_callback": r"scan_callback", "input_glue": r"input_glue",
                  "output_glue_cmd_vel": r"output_glue_cmd_vel", "output_glue_closest": r"output_glue_closest"},
    "generated_wrapper": {"scan_callback": r"scan_callback", "input_glue": r"input_glue",
                          "output_glue_cmd_vel": r"output_glue_cmd_vel",
                          "output_glue_closest": r"output_glue_closest",
                          "received": r"wrapper_scan_received\(.*", "spin": r"wrapper_ros_spinOnce\(\)",
                          "pub_cmd_vel": r"ros_publish_cmd_vel", "pub_closest": r"ros_publish_closest",
                          "sink_cmd": _SINK_CMD, "sink_closest": _SINK_CLOSEST},
    "handwritten": {"scanCallback": r"scanCallback\(.*", "make_command": r"make_command\(\)",
                    "make_closest": r"make_closest\(\)", "hw_output": r"hw_output\(\)",
                    "sink_cmd": _SINK_CMD, "sink_closest": _SINK_CLOSEST},
}


def parts(which: str, inc: dict[str, float]) -> dict[str, float]:
    """The parts of a count from its inclusive counts (their sum is the
    count)."""
    if which == "handwritten":
        return {"scanCallback": inc["scanCallback"], "make_command": inc["make_command"],
                "make_closest": inc["make_closest"],
                "hw_output: handing over and destroying the messages":
                    inc["hw_output"] - inc["make_command"] - inc["make_closest"] - inc["sink_cmd"]
                    - inc["sink_closest"]}
    p = {"scan_callback": inc["scan_callback"], "input_glue": inc["input_glue"],
         "output_glue_cmd_vel": inc["output_glue_cmd_vel"], "output_glue_closest": inc["output_glue_closest"]}
    if which == "generated_wrapper":
        p["wrapper: scan into the C struct (subscription lambda)"] = inc["received"] - inc["scan_callback"]
        p["wrapper: clock read (ros_spinOnce)"] = inc["spin"]
        p["wrapper: commands out of the C structs (ros_publish_*)"] = (
            inc["pub_cmd_vel"] + inc["pub_closest"] - inc["sink_cmd"] - inc["sink_closest"])
    return p


def wrapper_sources(wrapper_cpp: Path, out: Path) -> None:
    """From the wrapper of the built node, verbatim: its conversions
    (scan_guard_wrapper_conversions.inc) and its per-message code
    (scan_guard_wrapper_functions.inc), for fake_ros_scan_guard_wrapper.cpp."""
    text = wrapper_cpp.read_text()

    def need(m, what):
        if not m:
            raise SystemExit(f"scan_guard: {wrapper_cpp}: {what} not found (the wrapper template changed: "
                             f"update bench/scan_guard.py)")
        return m

    a = text.index("// Conversions between roscpp messages and the C structs")
    b = text.index("// ROS remapping arguments")
    conv = text[a:b]
    need("inline void to_c(const std::vector<float> &r, struct ros_seq_float32_1081 *c)" in conv,
         "the conversion of ranges")
    lam = need(re.search(r"\[cb\]\(const ros::MessageEvent<sensor_msgs::LaserScan const> &e\) \{\n(.*?)\n\s*\};",
                         text, re.S), "the subscription lambda of /scan").group(1)

    def function(sig: str) -> str:
        return need(re.search(rf"^{re.escape(sig)}\n\{{\n.*?\n\}}\n", text, re.S | re.M), sig).group(0)

    spin = function("void ros_spinOnce(void)")
    body = spin[spin.index("{\n") + 2:spin.rindex("}")]
    need("    ros::spinOnce();\n" in body, "ros::spinOnce() in ros_spinOnce")
    body = body.replace("    ros::spinOnce();\n", "")
    funcs = [function(s) for s in ("unsigned long long ros_now(void)", "unsigned int ros_time_sec(void)",
                                   "unsigned int ros_time_nsec(void)",
                                   "void ros_publish_cmd_vel(struct geometry_msgs_TwistStamped *msg)",
                                   "void ros_publish_closest(struct std_msgs_Float32 *msg)")]
    out.mkdir(parents=True, exist_ok=True)
    src = f"// extracted verbatim from {wrapper_cpp} by bench/scan_guard.py\n"
    (out / "scan_guard_wrapper_conversions.inc").write_text(src + conv)
    (out / "scan_guard_wrapper_functions.inc").write_text(
        src + "// the body of the lambda that ros_subscribe_scan hands roscpp\n"
        "void wrapper_scan_received(void (*cb)(struct sensor_msgs_LaserScan *),\n"
        "                           const ros::MessageEvent<sensor_msgs::LaserScan const> &e)\n{\n"
        f"{lam}\n}}\n\n// ros_spinOnce without its ros::spinOnce() (fake_spin_once ran just before)\n"
        f"void wrapper_ros_spinOnce()\n{{\n{body}}}\n\nextern \"C\" {{\n\n" + "\n".join(funcs) + "\n}\n")


def wrapper_harness(g: Guard, nodes: dict) -> Path:
    """The generated glue (the object the first count used) with the
    wrapper's own per-message code over a fake transport."""
    from runtime import _pkg

    ros = _pkg("roscpp")
    gen_dir = nodes["gen_dir"]
    glue_dir = g.work / f"glue_{g.node}"
    for f in (f"{g.node}_glue.c", f"{g.node}_types.h"):
        if (glue_dir / f).read_text() != (gen_dir / f).read_text():
            raise SystemExit(f"scan_guard: {f} of the example and of the 1 ms build differ")
    inc = g.work / "wrapper_inc"
    wrapper_sources(gen_dir / f"{g.node}_ros.cpp", inc)
    obj = g.work / "fake_ros_scan_guard_wrapper.o"
    run(["g++", "-std=c++14", "-O2", "-Wall", "-Wextra", "-DSCAN_GUARD_SCANS", "-I", inc, "-I", gen_dir, "-c",
         WRAPPER_FAKE, "-o", obj, *[f for f in ros if not f.startswith("-l")]])
    exe = g.work / f"{g.node}_wrapper_fake"
    run(["g++", g.work / f"{g.node}_{g.node}_glue.o", g.work / f"{g.node}_{g.controller}.o", obj, "-o", exe, *ros])
    return exe


def more_instructions(g: Guard, nodes: dict, env: dict, ins: dict) -> None:
    """The counts with the wrapper, the parts of each count, and all of it
    again with every scan 1,081 ranges."""
    from runtime import per_cycle

    exes = dict(ins["_exes"])
    exes["generated_wrapper"] = wrapper_harness(g, nodes)
    # what was measured: the revision, and the sources of pyrosgen and the
    # library that differed from it (a shared working tree)
    git = ["git", "-C", REPO]
    ins["source"] = {"commit": run([*git, "rev-parse", "HEAD"]).stdout.strip(),
                     "modified": run([*git, "status", "--porcelain", "--", "pyrosgen", "coq"]).stdout.splitlines(),
                     "wrapper_functions": (g.work / "wrapper_inc" / "scan_guard_wrapper_functions.inc").read_text()}
    for scans, extra in (("mixed", {}), ("full", {"BENCH_SCAN_LENGTH": str(FULL_SCAN)})):
        checks = {w: run([e], env=dict(os.environ, **extra)).stdout.strip() for w, e in exes.items()}
        if len(set(checks.values())) != 1:
            raise SystemExit(f"scan_guard: the harnesses disagree ({scans} scans): {checks}")
        counts = {}
        for w, e in exes.items():
            g.log(f"{w} ({scans} scans, callgrind)")
            c = per_cycle(e, TOGGLES[w], ("sink",), extra)
            c["parts"] = parts(w, inclusive_per_cycle(e, INCLUSIVE[w]))
            if abs(sum(c["parts"].values()) - c["per_cycle"]) > 0.05:
                raise SystemExit(f"scan_guard: the parts of {w} ({c['parts']}) do not add up to {c['per_cycle']}")
            counts[w] = c
            g.log(f"  {c['per_cycle']:.1f} per cycle: "
                  + ", ".join(f"{k} {v:.1f}" for k, v in c["parts"].items()))
        for w in ("generated", "handwritten"):
            if scans == "mixed" and abs(counts[w]["per_cycle"] - ins[w]["per_cycle"]) > 0.05:
                raise SystemExit(f"scan_guard: {w} counted {counts[w]['per_cycle']} then {ins[w]['per_cycle']}")
        h = counts["handwritten"]["per_cycle"]
        ins[scans] = {"check": checks["generated"], "counts": counts,
                      "ratio_glue": counts["generated"]["per_cycle"] / h,
                      "ratio_glue_wrapper": counts["generated_wrapper"]["per_cycle"] / h}
        g.log(f"  {scans} scans: glue / hand-written {ins[scans]['ratio_glue']:.2f}, "
              f"glue + wrapper / hand-written {ins[scans]['ratio_glue_wrapper']:.2f}")
    ins["generated_wrapper"] = ins["mixed"]["counts"]["generated_wrapper"]
    by_length = {}
    for n in LENGTHS:
        extra = {"BENCH_SCAN_LENGTH": str(n)}
        checks = {w: run([e], env=dict(os.environ, **extra)).stdout.strip() for w, e in exes.items()}
        if len(set(checks.values())) != 1:
            raise SystemExit(f"scan_guard: the harnesses disagree (scans of {n} ranges): {checks}")
        by_length[str(n)] = {w: per_cycle(e, TOGGLES[w], ("sink",), extra)["per_cycle"] for w, e in exes.items()}
        g.log(f"  scans of {n} ranges: " + ", ".join(f"{w} {v:.1f}" for w, v in by_length[str(n)].items()))
    ins["by_length"] = by_length
    ins["avx2"] = glue_avx2(g)
    if ins["avx2"] and ins["avx2"]["check"] != ins["mixed"]["check"]:
        raise SystemExit(f"scan_guard: the glue compiled with -mavx2 publishes {ins['avx2']['check']!r}")


def glue_avx2(g: Guard) -> dict | None:
    """For reference: the same glue compiled with ``-mavx2`` too (32-byte
    moves; ``pyrosgen build`` compiles it without, for any x86-64), with
    the same fake ROS; None on a CPU without AVX2."""
    from runtime import per_cycle

    if " avx2" not in Path("/proc/cpuinfo").read_text():
        return None
    glue_dir = g.work / f"glue_{g.node}"
    obj, exe = g.work / f"{g.node}_glue_avx2.o", g.work / f"{g.node}_avx2_fake"
    run(["gcc", "-std=c11", "-O2", "-mavx2", "-fno-inline", "-I", glue_dir, "-c", glue_dir / f"{g.node}_glue.c",
         "-o", obj])
    run(["gcc", obj, g.work / f"{g.node}_fake_ros_laser_guard.o", g.work / f"{g.node}_{g.controller}.o", "-o", exe])
    out = {"check": run([exe]).stdout.strip()}
    for scans, extra in (("mixed", {}), ("full", {"BENCH_SCAN_LENGTH": str(FULL_SCAN)})):
        c = per_cycle(exe, TOGGLES["generated"], (), extra)
        out[scans] = {"per_cycle": c["per_cycle"], "functions": c["functions"]}
        g.log(f"  glue -mavx2 ({scans} scans): {c['per_cycle']:.1f} per cycle")
    return out


def main(argv: list[str] | None = None) -> int:
    import report

    return guard_main(argv, __doc__, SCAN_GUARD, report.block_scan_guard, more_instructions)


if __name__ == "__main__":
    sys.exit(main())

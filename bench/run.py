"""``make bench``: every benchmark of BENCHMARKS.md, then its tables and the
plots in bench/results/.

usage: run.py [--quick] [--only proofs,pipeline,runtime,laserscan,scan_guard,ros2] [--report-only]

- ``proofs``: ``make proofs`` from clean in a private copy of coq/
  (bench/proofs.py); the copy is the library the other benchmarks use;
- ``pipeline``: ``pyrosgen generate`` on LandShark and on synthetic nodes
  with N relations (bench/pipeline.py);
- ``runtime``: the generated LandShark node against a hand-written roscpp
  node: latency at a 1 ms period, and instructions per cycle of the glue
  (bench/runtime.py);
- ``laserscan``: the same for the laser guard (LaserScan), against a
  hand-written node: instructions per cycle of the glue and latency at a
  1 ms period (bench/laserscan.py);
- ``scan_guard``: the same for the scan guard (the whole scan into a
  controller array), with the wrapper's conversions counted too
  (bench/scan_guard.py);
- ``ros2``: LandShark and the scan guard over rcl (ROS 2) against the same
  nodes written by hand over rcl: instructions per cycle of glue and
  wrapper, round trip at 1 ms, and ``pyrosgen build --ros2`` against ROS
  1's ``pyrosgen build`` (bench/ros2.py).

``--quick`` is for iteration: N up to 400, one run each, a short latency
run; the library copy is rebuilt only when the sources changed; its
results and report go to build/bench/results-quick/ and
build/bench/BENCHMARKS-quick.md, leaving the recorded ones alone.
Otherwise results go to bench/results/*.json (each benchmark's last run),
and the tables of BENCHMARKS.md are rewritten from them
(``--report-only`` does only that).
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import common  # noqa: E402
from common import WORK, load_json, loadavg, machine, save_json  # noqa: E402

ALL = ("proofs", "pipeline", "runtime", "laserscan", "scan_guard", "ros2")


def log(msg: str) -> None:
    print(f"bench: {msg}", flush=True)


def ensure_matplotlib() -> None:
    """matplotlib is a bench-only dependency: install it into the venv if
    it is missing (not a dependency of pyrosgen)."""
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        import subprocess

        log("installing matplotlib into the virtual environment (bench only)")
        subprocess.run([sys.executable, "-m", "pip", "install", "-q", "--disable-pip-version-check",
                        "matplotlib"], check=True)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="short runs, for iteration")
    ap.add_argument("--only", default=",".join(ALL), help="comma-separated subset of " + ",".join(ALL))
    ap.add_argument("--report-only", action="store_true", help="only rewrite BENCHMARKS.md and the plots")
    a = ap.parse_args(argv)
    only = [x for x in a.only.split(",") if x]
    for x in only:
        if x not in ALL:
            ap.error(f"unknown benchmark {x}")
    ensure_matplotlib()
    import report

    doc = report.DOC
    if a.quick:
        common.use_results(WORK / "results-quick")
        doc = WORK / "BENCHMARKS-quick.md"

    if not a.report_only:
        t0 = time.monotonic()
        mach = machine()
        mach["mode"] = "quick" if a.quick else "full"
        log(f"machine: {mach['cpu']}, {mach['cores']} cores, {mach['ram']}, load {mach['load_at_start']}")
        import proofs

        theories, proofs_res = proofs.private_library(log, rebuild=("proofs" in only and not a.quick))
        if proofs_res is not None:
            proofs_res["machine"] = mach
            save_json("proofs.json", proofs_res)
        env = dict(os.environ, PYROSGEN_COQLIB=str(theories))
        if "pipeline" in only:
            import pipeline

            res = pipeline.run_pipeline(env, quick=a.quick, log=log)
            res["machine"] = mach
            save_json("pipeline.json", res)
        if "runtime" in only:
            import runtime

            res = runtime.run_runtime(env, quick=a.quick, log=log)
            res["machine"] = mach
            save_json("runtime.json", res)
        if "laserscan" in only:
            import laserscan

            res = laserscan.run_laserscan(env, rounds=1 if a.quick else 3, edges=300 if a.quick else 1500)
            res["machine"] = mach
            save_json("laserscan.json", res)
        if "scan_guard" in only:
            import laserscan
            import scan_guard

            res = laserscan.run_laserscan(env, rounds=1 if a.quick else 3, edges=300 if a.quick else 1500,
                                          guard=scan_guard.SCAN_GUARD,
                                          more_instructions=scan_guard.more_instructions)
            res["machine"] = mach
            save_json("scan_guard.json", res)
        if "ros2" in only:
            import ros2

            res = ros2.run_ros2(env, quick=a.quick)
            res["machine"] = mach
            save_json("ros2.json", res)
        mach["load_at_end"] = loadavg()
        mach["bench_seconds"] = time.monotonic() - t0
        save_json("machine.json", mach)
    report.write_report(load_json, log=log, doc=doc)
    return 0


if __name__ == "__main__":
    sys.exit(main())

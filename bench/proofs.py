"""Benchmark 2: ``make proofs`` from clean (BENCHMARKS.md, section 2).

The sources of ``coq/`` are copied into ``build/bench/coq`` (so that the
shared build is not disturbed) and built there from clean, one target of
``coq/Makefile`` at a time, each timed: the no-admit grep, the library
(``build``, sequential: ``-j1``), ``coqchk`` (``check-proof``), the
``Print Assumptions`` checks (``check-assumptions``) and the test files
(``tests``).  The time of each library file comes from coq_makefile's
``TIMED=1`` output.

The finished copy is then the library the pipeline benchmark runs against
(``PYROSGEN_COQLIB``), so that other people's rebuilds of ``coq/`` during a
run do not change it.
"""

from __future__ import annotations

import re
from pathlib import Path

from common import WORK, copy_coq_sources, loadavg, private_coq_is_current, run

PRIVATE = WORK / "coq"
TARGETS = ("check-admitted", "build", "check-proof", "check-assumptions", "tests")


def run_proofs(log) -> dict:
    """Build the copy from clean; the time of every target."""
    dest = copy_coq_sources(PRIVATE)
    steps = []
    per_file: list[dict] = []
    for target in TARGETS:
        la = loadavg()
        extra = ["TIMED=1"] if target == "build" else []
        p = run(["make", "--no-print-directory", "-j1", "-C", dest, target, *extra], timeout=3600)
        steps.append({"target": target, "wall": p.wall, "cpu": p.cpu, "maxrss_kb": p.maxrss_kb, "load": la})
        log(f"  make {target}: {p.wall:.1f} s (cpu {p.cpu:.1f} s, peak {p.maxrss_kb / 1024:.0f} MB) load {la}")
        if target == "build":
            # coq_makefile TIMED=1: "theories/X.vo (real: 12.34, user: ..., sys: ..., mem: 123456 ko)"
            for m in re.finditer(r"(\S+\.vo) \(real: ([\d.]+), user: ([\d.]+), sys: ([\d.]+), mem: (\d+) ko\)",
                                 p.stdout + p.stderr):
                per_file.append({"file": m.group(1), "wall": float(m.group(2)),
                                 "cpu": float(m.group(3)) + float(m.group(4)), "mem_kb": int(m.group(5))})
    (dest / ".bench-built").write_text((dest / ".bench-digest").read_text())
    total = sum(s["wall"] for s in steps)
    per_file.sort(key=lambda r: -r["wall"])
    return {"steps": steps, "total_wall": total, "total_cpu": sum(s["cpu"] for s in steps),
            "files": per_file, "n_files": len(per_file)}


def private_library(log, *, rebuild: bool) -> tuple[Path, dict | None]:
    """The private library's theories/ (built now if asked or out of date)
    and the proofs benchmark if it was run."""
    if rebuild or not private_coq_is_current(PRIVATE):
        log("proofs: make proofs from clean in a private copy of coq/")
        return PRIVATE / "theories", run_proofs(log)
    log("proofs: private copy of coq/ is up to date (not rebuilt)")
    return PRIVATE / "theories", None

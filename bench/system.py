"""Systems of nodes (BENCHMARKS.md section 14): ``pyrosgen system
generate`` of a synthetic chain of N relay nodes, N in 5, 10, 20 (and 50
with ``--large``): cold (empty cache), warm (nothing changed), one node
changed (its period: the node and the system's proof redone); ``-j`` the
number of cores; wall and CPU time (user + system of every process).  Run on its own (not part of ``make
bench``):

    .venv/bin/python bench/system.py [--large] [--sizes 5,10]

writes bench/results/system.json and prints a Markdown table."""

from __future__ import annotations

import argparse
import json
import os
import resource
import shutil
import subprocess
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from common import PY, REPO, RESULTS, WORK, loadavg  # noqa: E402


def relay(folder: Path, k: int, n: int) -> Path:
    """Node k of the chain: /t<k-1> (or /src) -> /t<k> (or /out), a
    controller with one input and one output (Embedded Coder style)."""
    src = "/src" if k == 0 else f"/t{k - 1}"
    dst = "/out" if k == n - 1 else f"/t{k}"
    text = f"""# relay {k} of a synthetic chain of {n} (bench/system.py)
node: {{name: relay{k}, period_ms: 20}}
controller:
  name: Ctl
  inputs: {{name: Ctl_U, fields: {{In1: float64}}}}
  outputs: {{name: Ctl_Y, fields: {{Out1: float64}}}}
topics:
  - {{name: {src}, direction: subscribe, type: geometry_msgs/Twist, queue_size: 1}}
  - {{name: {dst}, direction: publish, type: geometry_msgs/Twist, queue_size: 1}}
relations:
  inputs:  [{{topic: {src}, field: linear.x, input: In1}}]
  outputs: [{{output: Out1, topic: {dst}, field: linear.x}}]
"""
    p = folder / f"relay{k}.yaml"
    p.write_text(text)
    return p


def system(folder: Path, n: int) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    for k in range(n):
        relay(folder, k, n)
    nodes = "\n".join(f"  - model: relay{k}.yaml" for k in range(n))
    p = folder / "system.yaml"
    p.write_text(f"system: {{name: chain{n}}}\nnodes:\n{nodes}\nexternal: {{inputs: [/src], outputs: [/out]}}\n")
    return p


def timed(argv: list[str]) -> tuple[float, float]:
    """Wall time and CPU time (user + system of the command and all its
    children, from the kernel's accounting) of ``argv``."""
    c0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.monotonic()
    r = subprocess.run(argv, capture_output=True, text=True, cwd=REPO)
    wall = time.monotonic() - t0
    c1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    if r.returncode != 0:
        raise SystemExit(f"failed: {' '.join(argv)}\n{r.stderr}")
    return wall, (c1.ru_utime - c0.ru_utime) + (c1.ru_stime - c0.ru_stime)


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--large", action="store_true", help="also N = 50")
    ap.add_argument("--sizes", help="comma-separated sizes (default 5,10,20)")
    args = ap.parse_args()
    sizes = [int(x) for x in args.sizes.split(",")] if args.sizes else [5, 10, 20] + ([50] if args.large else [])
    jobs = os.cpu_count() or 1
    rows = []
    for n in sizes:
        work = WORK / "system" / f"n{n}"
        shutil.rmtree(work, ignore_errors=True)
        sysf = system(work / "src", n)
        cache = work / "cache"
        gen = [str(PY), "-m", "pyrosgen", "system", "generate", str(sysf), "-o", str(work / "out"),
               "--cache", str(cache), "-j", str(jobs), "-q"]
        load0 = loadavg()
        cold, cold_cpu = timed(gen)
        warm, warm_cpu = timed(gen)
        # a real change of the middle node (its period): the node proved
        # again to another module, and the system's proof redone (a comment
        # would leave its module, hence the system's proof, as they were)
        changed = work / "src" / f"relay{n // 2}.yaml"
        changed.write_text(changed.read_text().replace("period_ms: 20", "period_ms: 25"))
        one, one_cpu = timed(gen)
        rows.append({"nodes": n, "jobs": jobs, "cold_s": round(cold, 2), "warm_s": round(warm, 2),
                     "one_changed_s": round(one, 2), "cold_cpu_s": round(cold_cpu, 2),
                     "warm_cpu_s": round(warm_cpu, 2), "one_changed_cpu_s": round(one_cpu, 2),
                     "load_start": load0, "load_end": loadavg()})
        print(f"N={n}: cold {cold:.1f} s ({cold_cpu:.1f} s CPU), warm {warm:.2f} s, one changed {one:.1f} s "
              f"({one_cpu:.1f} s CPU)", flush=True)
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / "system.json").write_text(json.dumps({"date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
                                                     "rows": rows}, indent=1) + "\n")
    print("| nodes | cold: wall (CPU) | warm | one node changed: wall (CPU) | load average (start / end) |")
    print("|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['nodes']} | {r['cold_s']} s ({r['cold_cpu_s']} s) | {r['warm_s']} s "
              f"| {r['one_changed_s']} s ({r['one_changed_cpu_s']} s) | {r['load_start']} / {r['load_end']} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())

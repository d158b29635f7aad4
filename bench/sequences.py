"""What a carried variable-length array costs `pyrosgen generate` (rule 4.15).

The wall time (and CPU, peak memory) of ``pyrosgen generate`` on
examples/laser_guard/laser_guard.yaml (a LaserScan's ranges carried as at
most 1081 float32, a block diagram), on examples/arm/arm.yaml (a
JointState's position and velocity and a target's data read, at most 6
float64 each, six efforts and their length published, a block diagram
of 38 blocks), and on synthetic models: a
``sensor_msgs/LaserScan`` subscribed with ``max_length: {ranges: N}``, one
input relation to ``ranges[0]``, one output relation, a controller
brought in C (so only the glue is proved), for N = 128, 1024 and 8192.  The
callback copies the whole bounded struct (N + 2 leaves) and the proof
follows every copy, so the time grows with N; the table says how.

usage: .venv/bin/python bench/sequences.py [--repeat K] [--examples-only] [N ...]
Writes sequences.json (with --examples-only, the two examples alone:
sequences_examples.json) into bench/results/ and prints a Markdown table.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from common import PY, REPO, WORK, loadavg, machine, run, save_json  # noqa: E402

LASER_GUARD = REPO / "examples" / "laser_guard" / "laser_guard.yaml"
ARM = REPO / "examples" / "arm" / "arm.yaml"
SQ = WORK / "sequences"

SYNTH = """\
node: {{name: seq{n}, period_ms: 20}}
controller:
  name: Controller
  inputs: {{name: Controller_U, fields: {{R0: float32}}}}
  outputs: {{name: Controller_Y, fields: {{Out1: float64}}}}
topics:
  - {{name: /scan, direction: subscribe, type: sensor_msgs/LaserScan, queue_size: 1, max_length: {{ranges: {n}}}}}
  - {{name: /cmd, direction: publish, type: geometry_msgs/Twist, queue_size: 1}}
relations:
  inputs: [{{topic: /scan, field: "ranges[0]", input: R0}}]
  outputs: [{{output: Out1, topic: /cmd, field: linear.x}}]
"""


def log(msg: str) -> None:
    print(f"sequences: {msg}", file=sys.stderr, flush=True)


def generate(model: Path, out: Path) -> dict:
    p = run([PY, "-m", "pyrosgen", "generate", str(model), "-o", str(out)], cwd=REPO, timeout=3600)
    times = {}
    for line in p.stdout.splitlines():
        if line.strip().startswith("time"):
            times["pyrosgen"] = line.strip()
    return {"wall": round(p.wall, 2), "cpu": round(p.cpu, 2), "maxrss_mb": round(p.maxrss_kb / 1024),
            "summary": times.get("pyrosgen", ""), "load": loadavg()}


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=1)
    ap.add_argument("--examples-only", action="store_true", help="the laser guard and the arm, no synthetic model")
    ap.add_argument("sizes", nargs="*", type=int, default=[128, 1024, 8192])
    args = ap.parse_args()
    if args.examples_only:
        args.sizes = []
    SQ.mkdir(parents=True, exist_ok=True)
    rows = []
    for k in range(args.repeat):
        log(f"laser_guard, run {k + 1}")
        rows.append({"model": "laser_guard (N = 1081)", "n": 1081, **generate(LASER_GUARD, SQ / "laser_guard")})
        log(f"arm, run {k + 1}")
        rows.append({"model": "arm (N = 6)", "n": 6, **generate(ARM, SQ / "arm")})
        for n in args.sizes:
            model = SQ / f"seq{n}.yaml"
            model.write_text(SYNTH.format(n=n), encoding="utf-8")
            log(f"N = {n}, run {k + 1}")
            rows.append({"model": f"synthetic, N = {n}", "n": n, **generate(model, SQ / f"seq{n}")})
    save_json("sequences_examples.json" if args.examples_only else "sequences.json", {"machine": machine(), "rows": rows})
    print("| model | N | wall (s) | CPU (s) | peak RSS (MB) | load |")
    print("|---|---:|---:|---:|---:|---|")
    for r in rows:
        print(f"| {r['model']} | {r['n']} | {r['wall']} | {r['cpu']} | {r['maxrss_mb']} | {r['load']} |")


if __name__ == "__main__":
    main()

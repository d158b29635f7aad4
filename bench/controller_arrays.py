"""What a controller array costs `pyrosgen generate` (rule 4.15).

A synthetic node in the Embedded Coder style: a ``sensor_msgs/LaserScan``
subscribed with ``max_length: {ranges: N}`` whose ``ranges`` go whole into
the controller input ``Scan`` (``float32[N]``) with its length, and the
controller output ``Echo`` (``float32[N]``) going whole, with a length,
into a published ``std_msgs/Float32MultiArray`` (at most N).  The front end
expands each whole-array relation into N element relations, the
generator prints one copy per element (no loop), and the node's
well-formedness check, computed by ``vm_compute`` in ``coqc`` and again
by ``coqchk``, follows every relation: the time grows with N, and the
table says how (for N = 128, 1024, 1081 and 8192 by default).

usage: .venv/bin/python bench/controller_arrays.py [--repeat K] [N ...]
Writes controller_arrays.json into bench/results/ and prints a Markdown table.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from common import WORK, machine, save_json  # noqa: E402
from sequences import generate  # noqa: E402  (the same measurement of one `pyrosgen generate`)

CA = WORK / "controller_arrays"

SYNTH = """\
node: {{name: arr{n}, period_ms: 20}}
controller:
  name: Controller
  inputs: {{name: Controller_U, fields: {{Scan: "float32[{n}]", NScan: uint32}}}}
  outputs: {{name: Controller_Y, fields: {{Echo: "float32[{n}]", NEcho: uint32}}}}
topics:
  - {{name: /scan, direction: subscribe, type: sensor_msgs/LaserScan, queue_size: 1, max_length: {{ranges: {n}}}}}
  - {{name: /echo, direction: publish, type: std_msgs/Float32MultiArray, queue_size: 1, max_length: {{data: {n}}}}}
relations:
  inputs:
    - {{topic: /scan, field: ranges, input: Scan}}
    - {{topic: /scan, field: ranges, derived: length, input: NScan}}
  outputs:
    - {{output: Echo, topic: /echo, field: data}}
    - {{output: NEcho, topic: /echo, field: data, derived: length}}
"""


def log(msg: str) -> None:
    print(f"controller_arrays: {msg}", file=sys.stderr, flush=True)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=1)
    ap.add_argument("sizes", nargs="*", type=int, default=[128, 1024, 1081, 8192])
    args = ap.parse_args()
    CA.mkdir(parents=True, exist_ok=True)
    rows = []
    for k in range(args.repeat):
        for n in args.sizes:
            model = CA / f"arr{n}.yaml"
            model.write_text(SYNTH.format(n=n), encoding="utf-8")
            log(f"N = {n}, run {k + 1}")
            rows.append({"model": f"Scan[{n}] in, Echo[{n}] out", "n": n, **generate(model, CA / f"arr{n}")})
    save_json("controller_arrays.json", {"machine": machine(), "rows": rows})
    print("| model | N | wall (s) | CPU (s) | peak RSS (MB) | pyrosgen's split | load |")
    print("|---|---:|---:|---:|---:|---|---|")
    for r in rows:
        print(f"| {r['model']} | {r['n']} | {r['wall']} | {r['cpu']} | {r['maxrss_mb']} | {r['summary']} | {r['load']} |")


if __name__ == "__main__":
    main()

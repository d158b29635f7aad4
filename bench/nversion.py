"""The cost of the second, independent reading of the model file
(N-version, BENCHMARKS.md section 12; DESIGN.md section 7).

usage: nversion.py [--runs N]

In process, for every example model and for a synthetic node at the
leaf limit of rule 4.5 (a 9,800-element controller array fed from a
bounded ``ranges``: about 9,900 items of model text), the median time of
``pyrosgen.nversion.check.check_model_file`` (read the YAML and the
``.msg`` files again, compute the model text and, for a block diagram,
the diagram text, compare them with the proved ones) next to the front
end's own reading (``load_model`` and ``model_text``); then ``pyrosgen generate`` on LandShark once, end to
end, for the ratio.  Prints a Markdown table and saves
bench/results/nversion.json.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from common import PY, REPO, loadavg, run, save_json  # noqa: E402

sys.path.insert(0, str(REPO))

from pyrosgen.frontend.validate import load_model  # noqa: E402
from pyrosgen.nversion.check import check_model_file  # noqa: E402
from pyrosgen.proof.modeltext import diagram_text, model_text  # noqa: E402

LANDSHARK = REPO / "examples" / "landshark" / "landshark_controller.yaml"

SYNTHETIC = """\
node: {name: big, period_ms: 20}
controller:
  name: C
  inputs: {name: C_U, fields: {Scan: "float32[9800]", Cov: "float64[36]"}}
  outputs: {name: C_Y, fields: {V: float64}}
topics:
  - {name: /scan, direction: subscribe, type: sensor_msgs/LaserScan, queue_size: 1,
     max_length: {ranges: 9800}, timeout_ms: 100, on_timeout: hold}
  - {name: /odom, direction: subscribe, type: nav_msgs/Odometry, queue_size: 1}
  - {name: /cmd, direction: publish, type: geometry_msgs/TwistStamped, queue_size: 1, stamp: now, frame_id: base}
relations:
  inputs:
    - {topic: /scan, field: ranges, input: Scan}
    - {topic: /odom, field: pose.covariance, input: Cov}
  outputs:
    - {output: V, topic: /cmd, field: twist.linear.x}
"""


def _median_ms(fn, runs: int) -> float:
    ts = []
    for _ in range(runs):
        t = time.perf_counter()
        fn()
        ts.append(time.perf_counter() - t)
    return statistics.median(ts) * 1000


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=21)
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        synth = Path(tmp) / "synthetic_9800.yaml"
        synth.write_text(SYNTHETIC, encoding="utf-8")
        rows = []
        for f in [*sorted(REPO.glob("examples/*/*.yaml")), synth]:
            m = load_model(f)
            proved = model_text(m)
            diagram = diagram_text(m) if m.controller.diagram is not None else None
            nv = _median_ms(lambda: check_model_file(f, proved, diagram, vfile="node.v"), args.runs)
            fe = _median_ms(lambda: model_text(load_model(f)), args.runs)
            name = f.name if f == synth else str(f.relative_to(REPO))
            rows.append({"model": name, "items": len(proved.splitlines()), "nversion_ms": round(nv, 1),
                         "front_end_ms": round(fe, 1)})
        out = Path(tmp) / "out"
        t = time.perf_counter()
        run([str(PY), "-m", "pyrosgen", "generate", str(LANDSHARK), "-o", str(out), "-q"], cwd=REPO)
        gen_s = time.perf_counter() - t
    print(f"load average: {loadavg()}\n")
    print("| model | items of model text | second reading and comparison, ms | front end (load_model, model_text), ms |")
    print("|---|---|---|---|")
    for r in rows:
        print(f"| `{r['model']}` | {r['items']} | {r['nversion_ms']} | {r['front_end_ms']} |")
    ls = next(r for r in rows if r["model"].endswith("landshark_controller.yaml"))
    print(f"\nLandShark, `pyrosgen generate` end to end: {gen_s:.2f} s; the second reading is "
          f"{ls['nversion_ms'] / (gen_s * 1000) * 100:.2f} % of it")
    save_json("nversion.json", {"rows": rows, "landshark_generate_s": gen_s, "load": loadavg()})
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""Benchmark 6: block-diagram controllers (BENCHMARKS.md, section 6).

- **Instructions per ``Controller_step``** (callgrind, exact): the C that
  pyrosgen generates from examples/landshark/landshark_diagram.yaml against
  the hand-written Embedded-Coder-style controller of
  examples/landshark/controller/Controller.c, both compiled with ``gcc -O2``
  and stepped 10,000 times on the same three readings by one harness; only
  the step function is counted (``--toggle-collect``).  Goal: at most 1.2×.
- **``pyrosgen generate``** wall time: LandShark with its diagram (median of
  5 runs; goal ≤ 5 s), and synthetic diagrams of 200 and 1,000 blocks (a
  chain of Gain and Sum blocks over three inputs; goal: 1,000 blocks ≤ 60 s,
  growth from 200 to 1,000 at most linear: ratio ≤ 5).

usage: .venv/bin/python bench/diagram_controller.py   (writes bench/results/diagram_controller.json
and prints the BENCHMARKS.md section)
"""

from __future__ import annotations

import json
import re
import statistics
import tempfile
import time
from pathlib import Path

from common import PYROSGEN, REPO, RESULTS, loadavg, run

STEPS = 10_000
DIAGRAM = REPO / "examples" / "landshark" / "landshark_diagram.yaml"
HANDWRITTEN = REPO / "examples" / "landshark" / "controller"

HARNESS = r"""
#include <stdlib.h>
struct U3 { double In1, In2, In3; };
extern struct U3 Controller_U;
void Controller_initialize(void);
void Controller_step(void);
int main(void)
{
    Controller_initialize();
    for (int i = 0; i < %d; i++) {
        Controller_U.In1 = 1.4 + (i %% 7) * 0.01;
        Controller_U.In2 = 1.5 - (i %% 5) * 0.01;
        Controller_U.In3 = (i / 1000) %% 2 ? 4.5 : 1.55;
        Controller_step();
    }
    return 0;
}
"""


def instructions(work: Path, controller_c: Path, includes: list[Path]) -> float:
    """Instructions per Controller_step of ``controller_c`` (callgrind)."""
    h = work / "harness.c"
    h.write_text(HARNESS % STEPS)
    exe = work / f"bench_{controller_c.stem}"
    run(["gcc", "-std=c11", "-O2", *[a for i in includes for a in ("-I", str(i))], str(h), str(controller_c),
         "-o", str(exe)])
    out = work / f"callgrind.{exe.name}"
    run(["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}", "--toggle-collect=Controller_step",
         str(exe)], timeout=600)
    total = 0
    for ln in run(["callgrind_annotate", "--inclusive=yes", str(out)]).stdout.splitlines():
        m = re.match(r"^\s*([\d,]+) .*Controller_step", ln)
        if m:
            total = max(total, int(m.group(1).replace(",", "")))
    return total / STEPS


def synthetic(n: int, path: Path) -> None:
    """A LandShark node whose diagram is a chain of ``n`` blocks."""
    base = DIAGRAM.read_text().split("  blocks:")[0]
    tail = DIAGRAM.read_text().split("  outports:")[1].split("\n", 1)[1]
    blocks = []
    prev = "In1"
    for i in range(n):
        if i % 2 == 0:
            blocks.append(f"    - {{name: g{i}, block: Gain, input: {prev}, gain: 0.5}}")
        else:
            blocks.append(f"    - {{name: g{i}, block: Sum, inputs: [{prev}, In{1 + i % 3}], signs: \"+-\"}}")
        prev = f"g{i}"
    path.write_text(base + "  blocks:\n" + "\n".join(blocks) + f"\n  outports: {{Out1: {prev}}}\n" + tail)


def generate_time(model: Path, out: Path) -> float:
    t = time.monotonic()
    run([str(PYROSGEN), "generate", str(model), "-o", str(out), "-q"], timeout=3600)
    return time.monotonic() - t


def main() -> None:
    res: dict = {"date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()), "load_start": loadavg()}
    with tempfile.TemporaryDirectory(prefix="bench-diagram-") as tmp:
        work = Path(tmp)
        gen = work / "gen"
        run([str(PYROSGEN), "generate", str(DIAGRAM), "-o", str(gen), "-q"])
        res["instr_generated"] = instructions(work, gen / "landshark_controller_controller.c", [])
        res["instr_handwritten"] = instructions(work, HANDWRITTEN / "Controller.c", [HANDWRITTEN])
        res["instr_ratio"] = res["instr_generated"] / res["instr_handwritten"]
        times = [generate_time(DIAGRAM, work / f"t{i}") for i in range(5)]
        res["generate_landshark"] = statistics.median(times)
        for n in (200, 1000):
            m = work / f"chain{n}.yaml"
            synthetic(n, m)
            res[f"generate_{n}"] = generate_time(m, work / f"c{n}")
        res["growth_200_1000"] = res["generate_1000"] / res["generate_200"]
    res["load_end"] = loadavg()
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / "diagram_controller.json").write_text(json.dumps(res, indent=2) + "\n")
    print(json.dumps(res, indent=2))


if __name__ == "__main__":
    main()

"""What a constant frame_id costs (BENCHMARKS.md, section "Constant strings").

Glue instructions per cycle (callgrind, exact, counted as bench/runtime.py
counts LandShark's: the glue linked with the fake ROS of
bench/runtime/fake_ros_landshark.c, ``-O2 -fno-inline``, only the callbacks,
``input_glue`` and ``output_glue_*`` counted, per cycle = (count at 2000
cycles - count at 1000) / 1000) of LandShark against
bench/models/landshark_framed.yaml: the same model (checked) whose published
command carries ``header.frame_id = base_link`` (rule 4.14).  Carrying the
string gives every ``std_msgs/Header`` of the node a ``ros_string128`` (132
bytes), the subscribed ones included, so the callbacks copy it too: the
table shows where the instructions go.

usage: .venv/bin/python bench/strings.py
Writes strings.json into bench/results/ and prints a Markdown table.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from common import BENCH, REPO, WORK, machine, save_json  # noqa: E402

LANDSHARK = REPO / "examples" / "landshark" / "landshark_controller.yaml"
FRAMED = BENCH / "models" / "landshark_framed.yaml"
ST = WORK / "strings"


def log(msg: str) -> None:
    print(f"strings: {msg}", file=sys.stderr, flush=True)


def check_framed_model() -> None:
    """bench/models/landshark_framed.yaml is the example plus the command's
    frame_id, and nothing else."""
    import yaml

    a = yaml.safe_load(LANDSHARK.read_text())
    b = yaml.safe_load(FRAMED.read_text())
    cmd = a["topics"][3]
    assert cmd["name"] == "/landshark_control/base_velocity"
    cmd["frame_id"] = "base_link"
    if a != b:
        raise SystemExit(f"strings: {FRAMED} differs from {LANDSHARK} in more than the command's frame_id")


def instructions() -> dict:
    from runtime import glue_per_cycle  # bench/runtime.py

    check_framed_model()
    out = {}
    for label, model in (("plain", LANDSHARK), ("framed", FRAMED)):
        r = glue_per_cycle(label, model, ST, [], log)
        out[label] = dict(r, per_cycle=sum(r["functions"].values()))
        log(f"  glue instructions per cycle, {label}: {out[label]['per_cycle']:.1f} "
            f"({', '.join(f'{k} {v:.1f}' for k, v in sorted(r['functions'].items()))})")
    if out["plain"]["check"] != out["framed"]["check"]:
        raise SystemExit(f"strings: the two nodes publish different commands: {out['plain']['check']} "
                         f"against {out['framed']['check']}")
    return out


def table(ins: dict) -> str:
    from runtime import glue_table  # bench/runtime.py

    return glue_table(ins["plain"], ins["framed"], "with `frame_id: base_link`", "times")


def main(argv: list[str] | None = None) -> int:
    ins = instructions()
    save_json("strings.json", {"machine": machine(), "instructions": ins})
    print(table(ins))
    return 0


if __name__ == "__main__":
    sys.exit(main())

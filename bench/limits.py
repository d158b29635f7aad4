"""The time and memory that the size limits of DESIGN.md rules 4.3 and 4.5
imply (BENCHMARKS.md section 5).

usage: limits.py

Writes node models at the limits into build/bench/limits/ and runs
``pyrosgen generate`` on each once (wall time, peak memory of the largest
process, the phases generate reports):

- ``width_256``: one subscribed message of 256 float64 fields (the widest
  message definition allowed);
- ``width_2000``: the same with 2,000 fields, refused since rule 4.5 got
  its width limit (run with the limit lifted, to show why it is there);
- ``leaves_20000``: 20,000 carried leaves over all topics (four messages
  of 16 x 256 fields, one float64[3615], the published Float64);
- ``controller_2000``: 2,000 controller inputs and 2,000 outputs, each
  related to an element of a float64[2000] (the largest controller
  structs);
- ``all_limits``: the last two together, as far as the total allows
  (three of the 16 x 256 messages and the two float64[2000]: 16,288
  leaves; 2 x 2,000 controller fields).

Saves bench/results/limits.json and prints a Markdown table.
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from common import PY, WORK, loadavg, run, save_json  # noqa: E402

HEAD = "node: {{name: big, period_ms: 10}}\ncontroller:\n  name: C\n"


def _msg(root: Path, name: str, text: str) -> None:
    f = root / "msg" / "big_msgs" / "msg" / f"{name}.msg"
    f.parent.mkdir(parents=True, exist_ok=True)
    f.write_text(text)


def _fields(n: int, ty: str = "float64", prefix: str = "f") -> str:
    return "".join(f"{ty} {prefix}{i}\n" for i in range(n))


def model(root: Path, *, inputs: list[tuple[str, str]], outputs: list[tuple[str, str, str]],
          topics: list[tuple[str, str, str]]) -> Path:
    """inputs: (topic, field) per controller input; outputs: (topic, field)
    per output; topics: (name, direction, type)."""
    ins = "".join(f"      I{i}: float64\n" for i in range(len(inputs)))
    outs = "".join(f"      O{i}: float64\n" for i in range(len(outputs)))
    text = HEAD.format() + f"  inputs:\n    name: C_U\n    fields:\n{ins}  outputs:\n    name: C_Y\n    fields:\n{outs}"
    text += "msg_paths: [msg]\ntopics:\n"
    text += "".join(f"  - {{name: {n}, direction: {d}, type: {t}, queue_size: 1}}\n" for n, d, t in topics)
    text += "relations:\n  inputs:\n"
    text += "".join(f'    - {{topic: {t}, field: "{f}", input: I{i}}}\n' for i, (t, f) in enumerate(inputs))
    text += "  outputs:\n"
    text += "".join(f'    - {{output: O{i}, topic: {t}, field: "{f}"}}\n' for i, (t, f, _) in enumerate(outputs))
    root.mkdir(parents=True, exist_ok=True)
    (root / "m.yaml").write_text(text)
    return root / "m.yaml"


def build_models(base: Path) -> dict[str, Path]:
    out: dict[str, Path] = {}
    pub = [("/out", "data", "")]
    pub_topic = ("/out", "publish", "std_msgs/Float64")
    for w in (256, 2000):
        r = base / f"width_{w}"
        _msg(r, "Big", _fields(w))
        out[f"width_{w}"] = model(r, inputs=[("/a", "f0")], outputs=pub,
                                  topics=[("/a", "subscribe", "big_msgs/Big"), pub_topic])

    def leaves(r: Path) -> tuple[list, list]:
        _msg(r, "Sub", _fields(256))
        _msg(r, "Big", _fields(16, "big_msgs/Sub", "s"))
        _msg(r, "Arr", "float64[3615] data\n")
        topics = [(f"/b{i}", "subscribe", "big_msgs/Big") for i in range(4)] + [("/a", "subscribe", "big_msgs/Arr")]
        return topics, [(f"/b{i}", f"s{i}.f{i}") for i in range(4)] + [("/a", "data[3614]")]

    r = base / "leaves_20000"
    topics, ins = leaves(r)
    out["leaves_20000"] = model(r, inputs=ins, outputs=pub, topics=topics + [pub_topic])

    def ctl(r: Path) -> tuple[list, list, list]:
        _msg(r, "Arr2k", "float64[2000] data\n")
        return ([("/c", "subscribe", "big_msgs/Arr2k"), ("/d", "publish", "big_msgs/Arr2k")],
                [("/c", f"data[{i}]") for i in range(2000)], [("/d", f"data[{i}]", "") for i in range(2000)])

    r = base / "controller_2000"
    t2, i2, o2 = ctl(r)
    out["controller_2000"] = model(r, inputs=i2, outputs=o2, topics=t2)

    r = base / "all_limits"
    topics, ins = leaves(r)
    t2, i2, o2 = ctl(r)
    # 4 x 4096 + 3615 + 2 x 2000 > 20000: keep three of the 16 x 256 messages
    # (3 x 4096 + 2 x 2000 = 16288 leaves, 2,000 + 2,000 controller fields)
    topics = [t for t in topics if t[0] not in ("/a", "/b3")]
    ins = [x for x in ins if x[0] not in ("/a", "/b3")]
    out["all_limits"] = model(r, inputs=(ins + i2)[:2000], outputs=o2, topics=topics + t2)
    return out


def main() -> int:
    base = WORK / "limits"
    models = build_models(base)
    rows = {}
    for name, path in models.items():
        argv = [str(PY), "-m", "pyrosgen", "generate", str(path), "-o", str(path.parent / "out")]
        env = None
        if name == "width_2000":  # beyond the limit: lift it for this one run
            argv = [str(PY), "-c", "import sys, pyrosgen.frontend.validate as v, pyrosgen.frontend.msgmodel as m;"
                    "m.MAX_STRUCT_FIELDS = v.MAX_STRUCT_FIELDS = 10**6; from pyrosgen.cli import main;"
                    "sys.exit(main(sys.argv[1:]))", *argv[3:]]
        p = run(argv, env=env, check=False)
        phases = re.search(r"time +(.*); total", p.stdout)
        rows[name] = {"rc": p.rc, "wall": p.wall, "maxrss_mb": p.maxrss_kb / 1024, "load": loadavg(),
                      "phases": phases.group(1) if phases else p.stderr.strip().splitlines()[-1:]}
        print(f"limits: {name}: exit {p.rc}, {p.wall:.1f} s, {p.maxrss_kb / 1024:.0f} MB", flush=True)
    save_json("limits.json", rows)
    print("\n| model | exit | wall | peak MB | phases |\n|---|---|---|---|---|")
    for name, r in rows.items():
        print(f"| `{name}` | {r['rc']} | {r['wall']:.1f} s | {r['maxrss_mb']:.0f} | {r['phases']} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())

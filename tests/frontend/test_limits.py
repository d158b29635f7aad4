"""The size limits of DESIGN.md rule 4.5 bound the work of generate: the
width of a message definition, the leaves of a message, the leaves of all
topics together, the fields of the controller's structs (times at the
limits in BENCHMARKS.md section 5)."""

from __future__ import annotations

from pathlib import Path

import pytest

from pyrosgen.errors import InvalidNodeModel
from pyrosgen.frontend.msgmodel import MAX_STRUCT_FIELDS, MAX_TOTAL_LEAVES
from pyrosgen.frontend.validate import MAX_CONTROLLER_FIELDS, load_model

MODEL = """node: {{name: big, period_ms: 10}}
controller:
  name: C
  inputs: {{name: C_U, fields: {{{inputs}}}}}
  outputs: {{name: C_Y, fields: {{Out1: float64}}}}
msg_paths: [msg]
topics:
{topics}  - {{name: /out, direction: publish, type: std_msgs/Float64, queue_size: 1}}
relations:
  inputs:
{relations}  outputs:
    - {{output: Out1, topic: /out, field: data}}
"""


def _model(tmp_path: Path, msgs: dict[str, str], topics: list[tuple[str, str, str]],
           inputs: int | None = None) -> Path:
    """``topics``: (name, type, related field); one controller input per topic."""
    for name, text in msgs.items():
        f = tmp_path / "msg" / "big_msgs" / "msg" / f"{name}.msg"
        f.parent.mkdir(parents=True, exist_ok=True)
        f.write_text(text)
    n = inputs if inputs is not None else len(topics)
    m = tmp_path / "m.yaml"
    m.write_text(MODEL.format(
        inputs=", ".join(f"In{i}: float64" for i in range(n)),
        topics="".join(f"  - {{name: {t}, direction: subscribe, type: {ty}, queue_size: 1}}\n" for t, ty, _ in topics),
        relations="".join(f"    - {{topic: {topics[i % len(topics)][0]}, field: \"{topics[i % len(topics)][2] if i < len(topics) else f'data[{i}]'}\", input: In{i}}}\n"
                          for i in range(n)),
    ))
    return m


def _fields(n: int) -> str:
    return "".join(f"float64 f{i}\n" for i in range(n))


def _errors(path: Path) -> list[str]:
    with pytest.raises(InvalidNodeModel) as e:
        load_model(path)
    return [str(d) for d in e.value.diagnostics]


def test_message_width_at_the_limit_passes(tmp_path):
    load_model(_model(tmp_path, {"Big": _fields(MAX_STRUCT_FIELDS)}, [("/a", "big_msgs/Big", "f0")]))


def test_wider_message_is_refused(tmp_path):
    errs = _errors(_model(tmp_path, {"Big": _fields(MAX_STRUCT_FIELDS + 1)}, [("/a", "big_msgs/Big", "f0")]))
    assert len(errs) == 1
    assert f"message type big_msgs/Big has {MAX_STRUCT_FIELDS + 1} carried fields; at most {MAX_STRUCT_FIELDS}" in errs[0]
    assert errs[0].endswith("[rule 4.5]") and ":8:" in errs[0]


def test_wide_nested_message_is_named(tmp_path):
    msgs = {"Wide": _fields(MAX_STRUCT_FIELDS + 1), "Big": "float64 x\nbig_msgs/Wide w\n"}
    errs = _errors(_model(tmp_path, msgs, [("/a", "big_msgs/Big", "x")]))
    assert "message type big_msgs/Wide (in big_msgs/Big) has" in errs[0]


def test_total_leaves(tmp_path):
    # /out carries 1 leaf, three arrays the rest
    per = (MAX_TOTAL_LEAVES - 1) // 3
    last = MAX_TOTAL_LEAVES - 1 - 2 * per
    msgs = {"A": f"float64[{per}] data\n", "B": f"float64[{per}] data\n", "C": f"float64[{last}] data\n"}
    ok = _model(tmp_path, msgs, [("/a", "big_msgs/A", "data[0]"), ("/b", "big_msgs/B", "data[0]"),
                                 ("/c", "big_msgs/C", "data[0]")])
    load_model(ok)
    (tmp_path / "msg" / "big_msgs" / "msg" / "C.msg").write_text(f"float64[{last + 1}] data\n")
    errs = _errors(ok)
    assert len(errs) == 1 and f"carry {MAX_TOTAL_LEAVES + 1} scalar leaves in all; a node carries at most" in errs[0]


def test_controller_fields(tmp_path):
    msgs = {"A": f"float64[{MAX_CONTROLLER_FIELDS + 1}] data\n"}
    load_model(_model(tmp_path, msgs, [("/a", "big_msgs/A", "data[0]")], inputs=MAX_CONTROLLER_FIELDS))
    errs = _errors(_model(tmp_path, msgs, [("/a", "big_msgs/A", "data[0]")], inputs=MAX_CONTROLLER_FIELDS + 1))
    assert any(f"declares {MAX_CONTROLLER_FIELDS + 1} fields; at most {MAX_CONTROLLER_FIELDS}" in e for e in errs), errs

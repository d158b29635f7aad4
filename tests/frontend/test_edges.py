"""Hostile input at the edges of the front end (issue 30): each case is
refused with the file, line, column and rule (exit 1), never an internal
error."""

from __future__ import annotations

import pytest

from pyrosgen import cli

# --------------------------------------------------------------------------
# Rule 4.1: a refused number spelling as a block parameter, at the top of
# the diagram or inside a subsystem (it was "internal error: AssertionError
# ... accepted incomplete", exit 2).

_HEAD = """\
node: {name: n, period_ms: 20}
controller:
  name: Controller
  inputs: {name: Controller_U, fields: {In1: float64}}
  outputs: {name: Controller_Y, fields: {Out1: float64}}
"""
_TAIL = """\
  outports: {Out1: x}
topics:
  - {name: /u_in, direction: subscribe, type: std_msgs/Float64, queue_size: 1}
relations:
  inputs:
    - {topic: /u_in, field: data, input: In1}
"""

#: (block kind, parameter) -> the block, reading signal ``u``, with the
#: parameter written as ``@``.
_BLOCKS = {
    ("Constant", "value"): ["{name: c, block: Constant, type: float64, value: @}",
                            "{name: x, block: Sum, inputs: [u, c]}"],
    ("Gain", "gain"): "{name: x, block: Gain, input: u, gain: @}",
    ("Saturation", "lower"): "{name: x, block: Saturation, input: u, lower: @, upper: 2.0}",
    ("Saturation", "upper"): "{name: x, block: Saturation, input: u, lower: 0.0, upper: @}",
    ("Switch", "threshold"): "{name: x, block: Switch, inputs: [u, u, u], criterion: u2 >= threshold, threshold: @}",
    ("UnitDelay", "initial"): "{name: x, block: UnitDelay, input: u, initial: @}",
    ("DiscreteIntegrator", "gain"): "{name: x, block: DiscreteIntegrator, input: u, gain: @}",
    ("DiscreteIntegrator", "initial"): "{name: x, block: DiscreteIntegrator, input: u, initial: @}",
    ("DiscreteIntegrator", "lower"): "{name: x, block: DiscreteIntegrator, input: u, lower: @, upper: 1.0, initial: 0.75}",
    ("DiscreteIntegrator", "upper"): "{name: x, block: DiscreteIntegrator, input: u, lower: -1.0, upper: @, initial: 0.25}",
}


def _diagram_model(blocks: str | list[str], in_subsystem: bool) -> str:
    blocks = [blocks] if isinstance(blocks, str) else blocks
    if in_subsystem:
        body = ("  subsystems:\n    s:\n      inputs: [u]\n      blocks:\n"
                + "".join(f"        - {b}\n" for b in blocks) + "      outputs: {y: x}\n"
                "  blocks:\n    - {name: x, block: Subsystem, subsystem: s, inputs: [In1]}\n")
    else:
        body = ("  blocks:\n    - {name: u, block: Gain, input: In1, gain: 1.0}\n"
                + "".join(f"    - {b}\n" for b in blocks))
    return _HEAD + body + _TAIL


def _run(capsys, argv):
    code = cli.main(argv)
    out, err = capsys.readouterr()
    return code, out + err


@pytest.mark.parametrize("value", ["010", "0x10", "1:30", ".nan"])
@pytest.mark.parametrize("kind, param", list(_BLOCKS))
@pytest.mark.parametrize("in_subsystem", [False, True], ids=["diagram", "subsystem"])
def test_refused_number_as_block_parameter(capsys, tmp_path, kind, param, value, in_subsystem):
    text = _diagram_model(_BLOCKS[kind, param], in_subsystem)
    m = tmp_path / "m.yaml"
    m.write_text(text.replace("@", value))
    line = next(i for i, t in enumerate(text.splitlines(), 1) if "@" in t)
    col = text.splitlines()[line - 1].index("@") + 1
    code, out = _run(capsys, ["check", str(m)])
    assert code == 1, out
    assert "internal error" not in out
    # the one problem of the model, where it is written
    [diag] = out.splitlines()
    assert diag.startswith(f"{m}:{line}:{col}: error: {param}: number '{value}':")
    assert diag.endswith("[rule 4.1]")


@pytest.mark.parametrize("in_subsystem", [False, True], ids=["diagram", "subsystem"])
def test_block_parameters_in_plain_decimal_pass(capsys, tmp_path, in_subsystem):
    """The same models with a plain decimal are accepted (the test above
    fails on the number, nothing else)."""
    for kind, param in _BLOCKS:
        m = tmp_path / "m.yaml"
        m.write_text(_diagram_model(_BLOCKS[kind, param], in_subsystem).replace("@", "0.5"))
        code, out = _run(capsys, ["check", str(m)])
        assert code == 0, (kind, param, out)


# --------------------------------------------------------------------------
# Rule 4.6: a field path's index with a leading zero (C reads 010 as 8; it
# was read as element 10).

_SCAN = """\
node: {name: n, period_ms: 20}
controller:
  name: Controller
  inputs: {name: Controller_U, fields: {R: float32}}
  outputs: {name: Controller_Y, fields: {Out1: float64}}
topics:
  - {name: /scan, direction: subscribe, type: sensor_msgs/LaserScan, queue_size: 1, max_length: {ranges: 16}}
  - {name: /out, direction: publish, type: std_msgs/Float64, queue_size: 1}
relations:
  inputs:
    - {topic: /scan, field: "ranges[@]", input: R}
  outputs:
    - {output: Out1, topic: /out, field: data}
"""


@pytest.mark.parametrize("index", ["010", "00", "07"])
def test_field_path_index_with_leading_zero_is_refused(capsys, tmp_path, index):
    m = tmp_path / "m.yaml"
    m.write_text(_SCAN.replace("@", index))
    code, out = _run(capsys, ["check", str(m)])
    assert code == 1, out
    [diag] = out.splitlines()
    assert diag.startswith(f"{m}:11:29: error: relations.inputs[0].field: field path 'ranges[{index}]': "
                           f"index [{index}] has a leading zero (C reads 010 as octal 8); write the index "
                           f"in plain decimal, [{int(index)}]")
    assert diag.endswith("[rule 4.6]")


@pytest.mark.parametrize("index", ["10", "0", "7"])
def test_field_path_index_in_plain_decimal_is_read(tmp_path, index):
    from pyrosgen import load_model

    m = tmp_path / "m.yaml"
    m.write_text(_SCAN.replace("@", index))
    [rel] = load_model(m).input_relations
    assert rel.path.steps == ("ranges", "data", int(index))

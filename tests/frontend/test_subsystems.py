"""Subsystems of block diagrams (DESIGN.md rule 4.11, README section 6):
``controller.subsystems`` and the ``Subsystem`` block, expanded by the
front end (pyrosgen/frontend/subsystems.py) into ordinary blocks before
the diagram is checked.

The LandShark diagram written with subsystems
(examples/landshark/landshark_subsystem.yaml) expands to the blocks of the
flat one (landshark_diagram.yaml) under the prefixed names, and the
reference interpreter steps both bit for bit alike; nested subsystems and
several instances of one subsystem with state; every refusal with its
file:line:col and rule, through the command line too."""

from __future__ import annotations

import dataclasses
import random
import re
import subprocess
import sys
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pyrosgen import InvalidNodeModel, load_model
from pyrosgen.frontend import blocksim as bs
from pyrosgen.frontend import ieee
from pyrosgen.frontend.blocks import MAX_BLOCKS
from pyrosgen.frontend.subsystems import MAX_NESTING

from support.frontend import REPO

FLAT = REPO / "examples" / "landshark" / "landshark_diagram.yaml"
SUBSYS = REPO / "examples" / "landshark" / "landshark_subsystem.yaml"

# --------------------------------------------------------------------------
# A model around a controller section: inputs In1, In2, In3 (float64) and I
# (int32), output Out1 (float64); `body` is the rest of `controller:`.

HEAD = """node:
  name: n
  period_ms: 20
controller:
  name: Controller
  inputs:
    name: Controller_U
    fields: {In1: float64, In2: float64, In3: float64, I: int32}
  outputs:
    name: Controller_Y
    fields: {Out1: float64}
"""
TAIL = """topics:
  - {name: /a, direction: subscribe, type: std_msgs/Float64, queue_size: 1}
  - {name: /b, direction: subscribe, type: std_msgs/Float64, queue_size: 1}
  - {name: /c, direction: subscribe, type: std_msgs/Float64, queue_size: 1}
  - {name: /i, direction: subscribe, type: std_msgs/Int32, queue_size: 1}
relations:
  inputs:
    - {topic: /a, field: data, input: In1}
    - {topic: /b, field: data, input: In2}
    - {topic: /c, field: data, input: In3}
    - {topic: /i, field: data, input: I}
"""

MEDIAN3 = """    median3:
      inputs: [a, b, c]
      blocks:
        - {name: lo_ab, block: MinMax, function: min, inputs: [a, b]}
        - {name: hi_ab, block: MinMax, function: max, inputs: [a, b]}
        - {name: lo,    block: MinMax, function: min, inputs: [hi_ab, c]}
        - {name: med,   block: MinMax, function: max, inputs: [lo_ab, lo]}
      outputs: {m: med}
"""


def write(tmp_path: Path, body: str) -> tuple[Path, str]:
    text = HEAD + body + TAIL
    p = tmp_path / "m.yaml"
    p.write_text(text)
    return p, text


def diagram_of(tmp_path: Path, body: str):
    return load_model(write(tmp_path, body)[0]).controller.diagram


def at(text: str, line_has: str, col_at: str | None = None) -> tuple[int, int]:
    """The 1-based (line, column) of ``col_at`` (default: ``line_has``)
    on the one line of ``text`` that contains ``line_has``."""
    lines = [i for i, ln in enumerate(text.splitlines()) if line_has in ln]
    assert len(lines) == 1, (line_has, lines)
    ln = text.splitlines()[lines[0]]
    needle = line_has if col_at is None else col_at
    assert ln.count(needle) == 1, (needle, ln)
    return lines[0] + 1, ln.index(needle) + 1


def refused(tmp_path: Path, body: str) -> tuple[list[tuple[int, int, str, str]], str]:
    path, text = write(tmp_path, body)
    with pytest.raises(InvalidNodeModel) as info:
        load_model(path)
    return [(d.line, d.col, d.message, d.rule) for d in info.value.diagnostics], text


def renamed(block, names: dict[str, str]):
    """``block`` with its name and inputs renamed by ``names``, without
    its position."""
    return dataclasses.replace(block, name=names.get(block.name, block.name),
                               inputs=tuple(names.get(s, s) for s in block.inputs), pos=None)


# --------------------------------------------------------------------------
# The LandShark example: the flat diagram, modulo the names


def test_example_expands_to_the_flat_diagram():
    flat = load_model(FLAT).controller.diagram
    sub = load_model(SUBSYS).controller.diagram
    assert len(sub.blocks) == len(flat.blocks)
    # the renaming, block for block in the model's order: a bijection that
    # keeps the names of the blocks written outside any subsystem
    names = {f.name: s.name for f, s in zip(flat.blocks, sub.blocks)}
    assert len(set(names.values())) == len(names)
    top = {"setpoint", "err_raw", "integ", "p_term", "command", "out"}
    assert {f: s for f, s in names.items() if f in top} == {n: n for n in top}
    # the others are <instance>_<block of the subsystem>
    assert {f: s for f, s in names.items() if f not in top} == {
        "lo12": "median_lo_ab", "hi12": "median_hi_ab", "lo": "median_lo", "median": "median_med",
        "err_ok": "err_ok", "zero": "err_zero", "err": "err_out"}
    for f, s in zip(flat.blocks, sub.blocks):
        assert renamed(f, names) == dataclasses.replace(s, pos=None)
    assert tuple(names[n] for n in flat.order) == sub.order
    assert [(p, names.get(s, s)) for p, s in flat.outports] == list(sub.outports)
    assert flat.inports == sub.inports and flat.period_ms == sub.period_ms
    # each expanded block keeps the position of the block it copies
    text = SUBSYS.read_text()
    assert sub.block("median_lo").pos[0] == at(text, "{name: lo,    block: MinMax")[0]
    assert sub.block("err_out").pos[0] == at(text, "{name: out,  block: Switch")[0]


def test_example_reads_an_outport_both_ways(tmp_path):
    """`median.m` and `median` (the only outport) read the same signal."""
    text = SUBSYS.read_text()
    assert "inputs: [setpoint, median.m]" in text
    p = tmp_path / "m.yaml"
    p.write_text(text.replace("inputs: [setpoint, median.m]", "inputs: [setpoint, median]"))
    assert load_model(p).controller.diagram == load_model(SUBSYS).controller.diagram


_F64 = st.integers(min_value=0, max_value=(1 << 64) - 1)           # any bit pattern
_SPECIAL = st.sampled_from([0, 1 << 63, ieee.bits_of_double(float("inf")), ieee.bits_of_double(float("-inf")),
                            0x7FF8000000000000, 0xFFF0000000000001, 1, ieee.bits_of_double(1.0),
                            ieee.bits_of_double(0.9), ieee.bits_of_double(-3.5)])
_STEP = st.tuples(*[st.one_of(_F64, _SPECIAL, st.floats(-4, 4).map(ieee.bits_of_double))] * 3)


@settings(max_examples=200, deadline=None)
@given(st.lists(_STEP, min_size=1, max_size=12))
def test_example_steps_bit_for_bit_like_the_flat_diagram(steps):
    flat = load_model(FLAT).controller.diagram
    sub = load_model(SUBSYS).controller.diagram
    sf, ss = bs.initial_state(flat), bs.initial_state(sub)
    for a, b, c in steps:
        u = {"In1": a, "In2": b, "In3": c}
        sf, yf = bs.step(flat, sf, u)
        ss, ys = bs.step(sub, ss, u)
        assert yf == ys and sf == ss      # the state `integ` keeps its name


# --------------------------------------------------------------------------
# Nesting, several instances, state


NESTED = MEDIAN3 + """    clamped_median:
      inputs: [x, y, z, hi]
      blocks:
        - {name: m, block: Subsystem, subsystem: median3, inputs: [x, y, z]}
        - {name: c, block: MinMax, function: min, inputs: [m, hi]}
      outputs: {out: c, raw: m.m}
"""


def test_nested_subsystems(tmp_path):
    body = ("  subsystems:\n" + NESTED
            + "  blocks:\n"
              "    - {name: top, block: Constant, type: float64, value: 1.5}\n"
              "    - {name: k1, block: Subsystem, subsystem: clamped_median, inputs: [In1, In2, In3, top]}\n"
              "    - {name: k2, block: Subsystem, subsystem: clamped_median, inputs: [In3, k1.out, k1.raw, In1]}\n"
              "    - {name: s, block: Sum, inputs: [k1.out, k2], signs: '+-'}\n"
              "  outports: {Out1: s}\n")
    with pytest.raises(InvalidNodeModel) as info:   # k2 has two outports: `k2` alone is refused
        load_model(write(tmp_path, body)[0])
    assert "'k2' is a Subsystem block with 2 outports (out, raw)" in str(info.value)
    d = diagram_of(tmp_path, body.replace("inputs: [k1.out, k2]", "inputs: [k1.out, k2.raw]"))
    assert [b.name for b in d.blocks] == [
        "top", "k1_m_lo_ab", "k1_m_hi_ab", "k1_m_lo", "k1_m_med", "k1_c",
        "k2_m_lo_ab", "k2_m_hi_ab", "k2_m_lo", "k2_m_med", "k2_c", "s"]
    assert d.block("k1_m_lo_ab").inputs == ("In1", "In2")
    assert d.block("k1_c").inputs == ("k1_m_med", "top")
    assert d.block("k2_m_lo_ab").inputs == ("In3", "k1_c")          # k1.out
    assert d.block("k2_m_lo").inputs == ("k2_m_hi_ab", "k1_m_med")  # c <- z <- k1.raw
    assert d.block("k2_c").inputs == ("k2_m_med", "In1")
    assert d.block("s").inputs == ("k1_c", "k2_m_med")
    # the same diagram written flat, by hand
    flat = ("  blocks:\n"
            "    - {name: top, block: Constant, type: float64, value: 1.5}\n"
            + "".join(
                f"    - {{name: {p}_m_lo_ab, block: MinMax, function: min, inputs: [{x}, {y}]}}\n"
                f"    - {{name: {p}_m_hi_ab, block: MinMax, function: max, inputs: [{x}, {y}]}}\n"
                f"    - {{name: {p}_m_lo, block: MinMax, function: min, inputs: [{p}_m_hi_ab, {z}]}}\n"
                f"    - {{name: {p}_m_med, block: MinMax, function: max, inputs: [{p}_m_lo_ab, {p}_m_lo]}}\n"
                f"    - {{name: {p}_c, block: MinMax, function: min, inputs: [{p}_m_med, {hi}]}}\n"
                for p, x, y, z, hi in (("k1", "In1", "In2", "In3", "top"), ("k2", "In3", "k1_c", "k1_m_med", "In1")))
            + "    - {name: s, block: Sum, inputs: [k1_c, k2_m_med], signs: '+-'}\n"
              "  outports: {Out1: s}\n")
    f = diagram_of(tmp_path, flat)
    assert [dataclasses.replace(b, pos=None) for b in f.blocks] == [dataclasses.replace(b, pos=None) for b in d.blocks]
    assert f.order == d.order


ACC = """    acc:
      inputs: [u]
      blocks:
        - {name: i, block: DiscreteIntegrator, input: u, gain: 1.0}
        - {name: d, block: UnitDelay, input: u, type: float64}
        - {name: y, block: Sum, inputs: [i, d]}
      outputs: {y: y, i: i}
"""


def test_two_instances_have_independent_states(tmp_path):
    body = ("  subsystems:\n" + ACC
            + "  blocks:\n"
              "    - {name: a, block: Subsystem, subsystem: acc, inputs: [In1]}\n"
              "    - {name: b, block: Subsystem, subsystem: acc, inputs: [In2]}\n"
              "    - {name: s, block: Sum, inputs: [a.y, b.y], signs: '+-'}\n"
              "  outports: {Out1: s}\n")
    d = diagram_of(tmp_path, body)
    assert [b.name for b in d.states] == ["a_i", "a_d", "b_i", "b_d"]
    assert d.block("a_i").kt == d.block("b_i").kt and d.block("a_i").kt.n == ieee.bits_of_double(0.02)
    state = bs.initial_state(d)
    f = bs.value_of
    seq = [(1.0, 0.0), (2.0, 0.5), (0.0, 4.0), (3.0, 3.0)]
    ia = ib = da = db = 0.0
    for x, y in seq:
        state, out = bs.step(d, state, {"In1": f("float64", x), "In2": f("float64", y)})
        assert out["Out1"] == f("float64", (ia + da) - (ib + db))
        assert state == {"a_i": f("float64", ia + 0.02 * x), "a_d": f("float64", x),
                         "b_i": f("float64", ib + 0.02 * y), "b_d": f("float64", y)}
        ia, da, ib, db = ia + 0.02 * x, x, ib + 0.02 * y, y


def test_names_are_scoped_to_their_subsystem(tmp_path):
    """Blocks and inputs of a subsystem may reuse names of the top level
    and of other subsystems (In1 as an input name, `y` twice); a block
    of the top level reads its own `y`."""
    body = ("  subsystems:\n"
            "    twice: {inputs: [In1], blocks: [{name: y, block: Gain, input: In1, gain: 2}], outputs: {o: y}}\n"
            "    neg: {inputs: [y], blocks: [{name: x, block: Gain, input: y, gain: -1}], outputs: {o: x}}\n"
            "  blocks:\n"
            "    - {name: y, block: Subsystem, subsystem: twice, inputs: [In2]}\n"
            "    - {name: n, block: Subsystem, subsystem: neg, inputs: [y]}\n"
            "    - {name: x, block: Sum, inputs: [y, n.o]}\n"
            "  outports: {Out1: x}\n")
    d = diagram_of(tmp_path, body)
    assert [(b.name, b.inputs) for b in d.blocks] == [("y_y", ("In2",)), ("n_x", ("y_y",)),
                                                      ("x", ("y_y", "n_x"))]


def test_an_instance_with_no_inputs(tmp_path):
    body = ("  subsystems:\n"
            "    one: {blocks: [{name: k, block: Constant, type: float64, value: 1.0}], outputs: {o: k}}\n"
            "  blocks:\n"
            "    - {name: c, block: Subsystem, subsystem: one}\n"
            "    - {name: x, block: Sum, inputs: [In1, c]}\n"
            "  outports: {Out1: c}\n")
    d = diagram_of(tmp_path, body)
    assert [b.name for b in d.blocks] == ["c_k", "x"] and d.outports[0][1] == "c_k"


def test_the_block_limit_counts_expanded_blocks(tmp_path):
    """Ten instances of ten instances of ... : the list is short, the
    expansion is refused at `controller.blocks` once it has more than
    MAX_BLOCKS blocks, and the limit itself is accepted."""
    def body(levels: int, top: int) -> str:
        out = "  subsystems:\n    s0: {inputs: [a], blocks: [{name: g, block: Gain, input: a, gain: 2}], outputs: {o: g}}\n"
        for k in range(1, levels):
            insts = ", ".join(f"{{name: i{j}, block: Subsystem, subsystem: s{k - 1}, inputs: [{'a' if j == 0 else f'i{j - 1}'}]}}"
                              for j in range(10))
            out += f"    s{k}: {{inputs: [a], blocks: [{insts}], outputs: {{o: i9}}}}\n"
        out += "  blocks:\n"
        for j in range(top):
            out += f"    - {{name: t{j}, block: Subsystem, subsystem: s{levels - 1}, inputs: [{'In1' if j == 0 else f't{j - 1}'}]}}\n"
        return out + f"  outports: {{Out1: t{top - 1}}}\n"
    assert MAX_BLOCKS == 5000
    d = diagram_of(tmp_path, body(4, 5))
    assert len(d.blocks) == MAX_BLOCKS and d.blocks[-1].name == "t4_i9_i9_i9_g"
    got, text = refused(tmp_path, body(4, 6))
    assert got == [(*at(text, "- {name: t0,", "-"), f"controller.blocks lists 6000 blocks once its Subsystem "
                    f"blocks are expanded; a diagram has at most {MAX_BLOCKS}", "4.11")]


# --------------------------------------------------------------------------
# Refusals: each case gives the controller body and every diagnostic
# expected, as (text on the line, text at the column or None, a fragment
# of the message).

OK_TOP = ("  blocks:\n"
          "    - {name: m, block: Subsystem, subsystem: median3, inputs: [In1, In2, In3]}\n"
          "  outports: {Out1: m}\n")

REFUSED = {
    "unknown_subsystem": (
        "  subsystems:\n" + MEDIAN3 + "  blocks:\n"
        "    - {name: m, block: Subsystem, subsystem: median4, inputs: [In1, In2, In3]}\n"
        "    - {name: n, block: Subsystem, subsystem: median3, inputs: [In1, In2, In3]}\n"
        "  outports: {Out1: m}\n",
        [("subsystem: median4", "median4", "controller.blocks[0] (m): unknown subsystem 'median4' (did you "
          "mean 'median3'?); the subsystems are median3")]),
    "no_subsystems_section": (
        OK_TOP,
        [("subsystem: median3", "median3", "controller.blocks[0] (m): unknown subsystem 'median3'; define it "
          "under controller.subsystems")]),
    "too_few_inputs": (
        "  subsystems:\n" + MEDIAN3 + OK_TOP.replace("[In1, In2, In3]", "[In1, In2]"),
        [("[In1, In2]", None, "controller.blocks[0] (m): subsystem 'median3' takes 3 inputs [a, b, c], got 2")]),
    "missing_inputs": (
        "  subsystems:\n" + MEDIAN3 + OK_TOP.replace(", inputs: [In1, In2, In3]", ""),
        [("- {name: m, block: Subsystem", "{name: m", "controller.blocks[0] (m): subsystem 'median3' takes 3 "
          "inputs [a, b, c], got 0")]),
    "unknown_outport": (
        "  subsystems:\n" + MEDIAN3 + OK_TOP.replace("{Out1: m}", "{Out1: m.median}"),
        [("{Out1: m.median}", "m.median", "controller.outports.Out1: 'm.median': subsystem 'median3' of 'm' has "
          "no outport 'median'; its outports are m")]),
    "outport_of_a_block": (
        "  subsystems:\n" + MEDIAN3 + OK_TOP.replace("{Out1: m}", "{Out1: In1.m}"),
        [("{Out1: In1.m}", "In1.m", "controller.outports.Out1: unknown signal 'In1.m': 'In1' is not a Subsystem "
          "block (<instance>.<outport> reads an outport of a Subsystem block)")]),
    "unused_input": (
        "  subsystems:\n" + MEDIAN3.replace("inputs: [a, b, c]", "inputs: [a, b, c, d]")
        + OK_TOP.replace("[In1, In2, In3]", "[In1, In2, In3, I]"),
        [("inputs: [a, b, c, d]", "d]", "controller.subsystems.median3.inputs: input 'd' is read by none of the "
          "subsystem's blocks or outputs")]),
    "undefined_signal_inside": (
        "  subsystems:\n" + MEDIAN3.replace("inputs: [hi_ab, c]", "inputs: [hi_ac, c]") + OK_TOP,
        [("inputs: [hi_ac, c]", "hi_ac", "controller.subsystems.median3.blocks[2] (lo): unknown signal 'hi_ac' "
          "in subsystem 'median3'; a subsystem reads its inputs (a, b, c) and its own blocks (did you mean "
          "'hi_ab'?)")]),
    "controller_input_inside": (
        "  subsystems:\n" + MEDIAN3.replace("inputs: [hi_ab, c]", "inputs: [hi_ab, In3]").replace(
            "[a, b, c]", "[a, b]") + OK_TOP.replace("[In1, In2, In3]", "[In1, In2]"),
        [("inputs: [hi_ab, In3]", "In3", "unknown signal 'In3' in subsystem 'median3'; a subsystem reads its "
          "inputs (a, b) and its own blocks (controller input 'In3' is not seen inside a subsystem")]),
    "undefined_output_signal": (
        "  subsystems:\n" + MEDIAN3.replace("{m: med}", "{m: mid}") + OK_TOP,
        [("{m: mid}", "mid", "controller.subsystems.median3.outputs.m: unknown signal 'mid' in subsystem "
          "'median3'")]),
    "pass_through_output": (
        "  subsystems:\n" + MEDIAN3.replace("{m: med}", "{m: med, first: a}") + OK_TOP,
        [("{m: med, first: a}", "a}", "controller.subsystems.median3.outputs.first: outport 'first' passes "
          "input 'a' on unchanged")]),
    "no_outputs": (
        "  subsystems:\n" + MEDIAN3.replace("{m: med}", "{}") + OK_TOP,
        [("outputs: {}", "{}", "controller.subsystems.median3: a subsystem has at least one output")]),
    "missing_outputs": (
        "  subsystems:\n" + MEDIAN3.replace("      outputs: {m: med}\n", "") + OK_TOP,
        [("    median3:", "median3", "controller.subsystems.median3: a subsystem has at least one output")]),
    "recursion": (
        "  subsystems:\n"
        "    ra: {inputs: [u], blocks: [{name: x, block: Subsystem, subsystem: rb, inputs: [u]}], outputs: {o: x}}\n"
        "    rb: {inputs: [u], blocks: [{name: x, block: Subsystem, subsystem: ra, inputs: [u]}], outputs: {o: x}}\n"
        "  blocks:\n    - {name: r, block: Subsystem, subsystem: ra, inputs: [In1]}\n  outports: {Out1: r}\n",
        [("subsystem: ra, inputs: [u]", "ra", "controller.subsystems.rb.blocks[0] (x): subsystem 'ra' contains "
          "itself: ra -> rb -> ra; a subsystem cannot instantiate itself, directly or through others")]),
    "self_recursion": (
        "  subsystems:\n"
        "    ra: {inputs: [u], blocks: [{name: x, block: Subsystem, subsystem: ra, inputs: [u]}], outputs: {o: x}}\n"
        "  blocks:\n    - {name: r, block: Subsystem, subsystem: ra, inputs: [In1]}\n  outports: {Out1: r}\n",
        [("subsystem: ra, inputs: [u]", "ra, inputs: [u]", "subsystem 'ra' contains itself: ra -> ra")]),
    "clash_with_a_block": (
        "  subsystems:\n" + MEDIAN3 + OK_TOP.replace(
            "  outports", "    - {name: m_lo, block: Abs, input: In1}\n  outports"),
        [("{name: m, block", "m, block", "controller.blocks[0] (m): the expansion of this Subsystem block names "
          "controller.subsystems.median3.blocks[2] (lo, line {line:name: lo, }) 'm_lo', which is already the name of "
          "controller.blocks[1] (m_lo) (line {line:name: m_lo,}); rename the instance or one of the blocks")]),
    "clash_between_instances": (
        "  subsystems:\n"
        "    one: {inputs: [a], blocks: [{name: x_y, block: Abs, input: a}, {name: y, block: Abs, input: x_y}], outputs: {o: y}}\n"
        "  blocks:\n"
        "    - {name: p, block: Subsystem, subsystem: one, inputs: [In1]}\n"
        "    - {name: p_x, block: Subsystem, subsystem: one, inputs: [In2]}\n"
        "  outports: {Out1: p}\n",
        [("{name: p_x,", "p_x", "controller.blocks[1] (p_x): the expansion of this Subsystem block names "
          "controller.subsystems.one.blocks[1] (y, line {line:    one: }) 'p_x_y', which is already the name of "
          "controller.subsystems.one.blocks[0] (x_y) in instance 'p' (line {line:    one: })")]),
    "clash_with_an_input": (
        "  subsystems:\n" + MEDIAN3 + OK_TOP.replace("{name: m,", "{name: In3,").replace("{Out1: m}", "{Out1: In3}"),
        [("{name: In3,", "In3,", "controller.blocks[0] (In3): signal 'In3' is driven twice: by this block and by "
          "controller input 'In3' (line {line:fields: {In1})")]),
    "instance_named_like_a_block": (
        "  subsystems:\n" + MEDIAN3 + OK_TOP.replace(
            "  outports", "    - {name: m, block: Abs, input: In1}\n  outports"),
        [("{name: m, block: Abs", "m, block", "controller.blocks[1] (m): signal 'm' is driven twice: by this "
          "block and by the Subsystem block controller.blocks[0] (m) (line {line:{name: m, block: Subsystem})")]),
    "expanded_name_reserved": (
        "  subsystems:\n" + MEDIAN3 + OK_TOP.replace("{name: m,", "{name: m_,").replace("{Out1: m}", "{Out1: m_}"),
        [("{name: m_,", "m_", "controller.blocks[0] (m_): the expansion of this Subsystem block names "
          "controller.subsystems.median3.blocks[0] (lo_ab, line {line:name: lo_ab}) 'm__lo_ab', which cannot be used: it is "
          "reserved by the C++ standard (contains '__')")]),
    "expanded_name_too_long": (
        "  subsystems:\n" + MEDIAN3 + OK_TOP.replace("{name: m,", "{name: " + "m" * 54 + ",").replace(
            "{Out1: m}", "{Out1: " + "m" * 54 + "}"),
        [("{name: mmm", "m" * 54, "the expansion of this Subsystem block names controller.subsystems.median3."
          "blocks[0] (lo_ab, line {line:name: lo_ab}) '" + "m" * 54 + "_lo_ab', which cannot be used: it is longer than 59 "
          "characters (60; its C temporary is rtb_<name>); use a shorter instance name")]),
    "several_outports_read_as_one": (
        "  subsystems:\n" + MEDIAN3.replace("{m: med}", "{m: med, low: lo}") + OK_TOP,
        [("{Out1: m}", "m}", "controller.outports.Out1: 'm' is a Subsystem block with 2 outports (m, low); read "
          "one of them as m.<outport>, e.g. m.m")]),
    "unused_subsystem": (
        "  subsystems:\n" + MEDIAN3 + "    spare: {inputs: [u], blocks: [{name: x, block: Abs, input: u}], outputs: {o: x}}\n" + OK_TOP,
        [("    spare:", "spare", "controller.subsystems.spare: subsystem 'spare' is instantiated by no block")]),
    "subsystems_without_blocks": (
        "  subsystems:\n" + MEDIAN3,
        [("  subsystems:", "subsystems", "controller.subsystems without controller.blocks")]),
    # wrong types of fields
    "subsystems_a_list": (
        "  subsystems: [median3]\n" + OK_TOP,
        [("subsystems: [median3]", "[", "controller.subsystems must be a mapping (subsystem name: definition), "
          "got a list"),
         ("subsystem: median3", "median3,", "controller.blocks[0] (m): unknown subsystem 'median3'")]),
    "definition_a_list": (
        "  subsystems:\n    median3: [a, b, c]\n" + OK_TOP,
        [("median3: [a, b, c]", "[", "controller.subsystems.median3 must be a mapping (inputs: [...], blocks: "
          "[...], outputs: {...}), got a list"),
         ("subsystem: median3", "median3,", "unknown subsystem 'median3'")]),
    "inputs_a_mapping": (
        "  subsystems:\n" + MEDIAN3.replace("inputs: [a, b, c]", "inputs: {a: 1}") + OK_TOP,
        [("inputs: {a: 1}", "{", "controller.subsystems.median3.inputs must be a list of input names, got a "
          "mapping")]),
    "blocks_a_mapping": (
        "  subsystems:\n    s: {inputs: [u], blocks: {x: 1}, outputs: {o: x}}\n"
        "  blocks:\n    - {name: r, block: Subsystem, subsystem: s, inputs: [In1]}\n  outports: {Out1: r}\n",
        [("blocks: {x: 1}", "{x", "controller.subsystems.s.blocks must be a list of blocks, got a mapping")]),
    "outputs_a_list": (
        "  subsystems:\n" + MEDIAN3.replace("{m: med}", "[med]") + OK_TOP,
        [("outputs: [med]", "[", "controller.subsystems.median3.outputs must be a mapping (outport name: "
          "signal), got a list")]),
    "instance_inputs_a_string": (
        "  subsystems:\n" + MEDIAN3 + OK_TOP.replace("[In1, In2, In3]", "In1"),
        [("inputs: In1", "In1", "controller.blocks[0] (m).inputs must be a list of signal names, got string "
          "'In1'")]),
    "subsystem_not_a_string": (
        "  subsystems:\n" + MEDIAN3 + OK_TOP.replace("subsystem: median3", "subsystem: 3"),
        [("subsystem: 3", "3,", "controller.blocks[0] (m).subsystem must be a string, got int '3'"),
         ("    median3:", "median3", "subsystem 'median3' is instantiated by no block")]),
    "unknown_key_of_an_instance": (
        "  subsystems:\n" + MEDIAN3 + OK_TOP.replace("inputs: [In1, In2, In3]}", "inputs: [In1, In2, In3], input: x}"),
        [("input: x", "input: x", "controller.blocks[0] (m): a Subsystem block has no key 'input' (did you mean "
          "'inputs'?); its keys are name, block, subsystem, inputs")]),
    "unknown_key_of_a_definition": (
        "  subsystems:\n" + MEDIAN3.replace("      outputs: {m: med}", "      outputs: {m: med}\n      output: x")
        + OK_TOP,
        [("      output: x", "output", "controller.subsystems.median3: a subsystem has no key 'output' (did you "
          "mean 'outputs'?); its keys are inputs, blocks, outputs")]),
    "subsystem_name_not_an_identifier": (
        "  subsystems:\n" + MEDIAN3.replace("median3:", "median-3:") + OK_TOP,
        [("median-3:", "median-3", "controller.subsystems: subsystem name 'median-3' cannot be used: it is not a "
          "C identifier"),
         ("subsystem: median3", "median3,", "unknown subsystem 'median3'")]),
    "nested_too_deep": (
        "  subsystems:\n    s0: {inputs: [a], blocks: [{name: g, block: Gain, input: a, gain: 2}], outputs: {o: g}}\n"
        + "".join(f"    s{k}: {{inputs: [a], blocks: [{{name: i, block: Subsystem, subsystem: s{k - 1}, "
                  f"inputs: [a]}}], outputs: {{o: i}}}}\n" for k in range(1, MAX_NESTING + 3))
        + f"  blocks:\n    - {{name: b, block: Subsystem, subsystem: s{MAX_NESTING + 2}, inputs: [In1]}}\n"
          "  outports: {Out1: b}\n",
        [(f"    s{MAX_NESTING}:", f"s{MAX_NESTING}", f"controller.subsystems.s{MAX_NESTING}: subsystem "
          f"'s{MAX_NESTING}' nests subsystems {MAX_NESTING + 1} deep; at most {MAX_NESTING} levels")]),
}


@pytest.mark.parametrize("case", sorted(REFUSED), ids=str)
def test_refused(tmp_path, case):
    body, expected = REFUSED[case]
    got, text = refused(tmp_path, body)
    want = sorted((*at(text, line_has, col_at), re.sub(r"\{line:(.+?)\}", lambda m: str(at(text, m.group(1))[0]), frag))
                  for line_has, col_at, frag in expected)
    rendered = "\n".join(map(str, got))
    assert len(got) == len(want), rendered
    for (line, col, frag), (gl, gc, gm, rule) in zip(want, sorted(got)):
        assert (gl, gc) == (line, col) and frag in gm, f"expected {line}:{col}: {frag}\ngot:\n{rendered}"
        assert rule == "4.11", rendered


def test_a_problem_of_a_subsystem_block_is_reported_once(tmp_path):
    """A problem of a block's shape is the same in every copy: it is
    reported once, at the block; a type problem that depends on what an
    instance is given is reported for each instance that has it, naming
    the expanded block."""
    body = ("  subsystems:\n"
            "    neg: {inputs: [u], blocks: [{name: x, block: Gain, input: u, gain: -1, bias: 1}], outputs: {o: x}}\n"
            "    inv: {inputs: [u], blocks: [{name: x, block: Logic, operator: NOT, inputs: [u]}], outputs: {o: x}}\n"
            "  blocks:\n"
            "    - {name: a, block: Subsystem, subsystem: neg, inputs: [In1]}\n"
            "    - {name: b, block: Subsystem, subsystem: neg, inputs: [In2]}\n"
            "    - {name: c, block: Subsystem, subsystem: inv, inputs: [In1]}\n"
            "    - {name: d, block: Subsystem, subsystem: inv, inputs: [I]}\n"
            "    - {name: s, block: Sum, inputs: [a, b]}\n"
            "  outports: {Out1: s}\n")
    got, text = refused(tmp_path, body)
    assert [(l, c, m) for l, c, m, _ in got] == [
        (*at(text, "bias: 1", "bias"), "controller.subsystems.neg.blocks[0] (a_x): a Gain block has no key 'bias'; "
         "its keys are name, block, input, gain"),
        (*at(text, "{name: c,", "In1"), "controller.subsystems.inv.blocks[0] (c_x): type mismatch: input 'In1' is "
         "float64 but a Logic block's inputs are bool (compare it with a RelationalOperator first)"),
        (*at(text, "{name: d,", "I]"), "controller.subsystems.inv.blocks[0] (d_x): type mismatch: input 'I' is "
         "int32 but a Logic block's inputs are bool (compare it with a RelationalOperator first)"),
    ]


def test_dotted_names_without_subsystems_are_unknown_signals(tmp_path):
    """Without subsystems, the diagram is read as before."""
    body = "  blocks:\n    - {name: x, block: Abs, input: m.m}\n  outports: {Out1: x}\n"
    got, text = refused(tmp_path, body)
    assert [(l, c, m) for l, c, m, _ in got] == [(*at(text, "input: m.m", "m.m"), "controller.blocks[0] (x): "
                                                  "unknown signal 'm.m'")]


def test_check_command_line(tmp_path):
    """`pyrosgen check`: one compiler-style line per problem, [rule 4.11],
    exit 1, no traceback; the example is accepted, its size expanded."""
    body = REFUSED["recursion"][0].replace("inputs: [In1]}", "inputs: [In1, In2]}")
    path, text = write(tmp_path, body)
    p = subprocess.run([sys.executable, "-m", "pyrosgen", "check", str(path)], capture_output=True, text=True,
                       cwd=REPO, timeout=120)
    assert p.returncode == 1 and p.stdout == "" and "Traceback" not in p.stderr
    (l1, c1), (l2, c2) = at(text, "subsystem: ra, inputs: [u]", "ra"), at(text, "inputs: [In1, In2]", "[In1")
    assert p.stderr.splitlines() == [
        f"{path}:{l1}:{c1}: error: controller.subsystems.rb.blocks[0] (x): subsystem 'ra' contains itself: "
        "ra -> rb -> ra; a subsystem cannot instantiate itself, directly or through others [rule 4.11]",
        f"{path}:{l2}:{c2}: error: controller.blocks[0] (r): subsystem 'ra' takes 1 input [u], got 2 [rule 4.11]",
    ]
    p = subprocess.run([sys.executable, "-m", "pyrosgen", "check", str(SUBSYS)], capture_output=True, text=True,
                       cwd=REPO, timeout=120)
    assert p.returncode == 0, p.stderr
    assert p.stdout.rstrip().endswith("; controller: a block diagram of 13 blocks (1 state)")
    assert re.search(r"landshark_subsystem\.yaml: ok", p.stdout)


def test_an_instance_named_like_an_input_read_by_another_instance(tmp_path):
    """The refused instance's name stays the controller input's: the
    other instance reads the input (a crash found by mutating models)."""
    body = ("  subsystems:\n" + MEDIAN3 + "  blocks:\n"
            "    - {name: In2, block: Subsystem, subsystem: median3, inputs: [In1, In2, In3]}\n"
            "    - {name: m, block: Subsystem, subsystem: median3, inputs: [In1, In2, In3]}\n"
            "  outports: {Out1: m}\n")
    got, text = refused(tmp_path, body)
    assert [(l, c) for l, c, _, _ in got] == [at(text, "{name: In2,", "In2, block")]
    assert "signal 'In2' is driven twice: by this block and by controller input 'In2'" in got[0][2]


def _mutants(text: str, seed: int, count: int):
    """Models made from ``text`` by deleting or copying a line, or
    replacing a word or a list by another of the model's."""
    rng = random.Random(seed)
    toks = sorted(set(re.findall(r"[A-Za-z_][A-Za-z0-9_.]*", text))) + ["", "[]", "{}", "[a]", "x.y", "1"]
    lines = text.splitlines(keepends=True)
    for _ in range(count):
        mutant = list(lines)
        for _ in range(rng.randint(1, 3)):
            k = rng.randrange(len(mutant))
            op = rng.random()
            if op < 0.15:
                del mutant[k]
            elif op < 0.25:
                mutant.insert(k, mutant[rng.randrange(len(mutant))])
            else:
                words = list(re.finditer(r"[A-Za-z_][A-Za-z0-9_.]*|\[[^\]]*\]|\{\}", mutant[k]))
                if words:
                    m = rng.choice(words)
                    mutant[k] = mutant[k][:m.start()] + rng.choice(toks) + mutant[k][m.end():]
        yield "".join(mutant)


@pytest.mark.parametrize("seed", range(4))
def test_mutated_models_are_accepted_or_refused_never_crash(tmp_path, seed):
    """Every mutant of a model with nested subsystems, several instances
    and both ways of reading an outport is accepted or refused with
    diagnostics (rule 4.1 or 4.11 for the diagram's part), never a crash."""
    text = SUBSYS.read_text().replace("  subsystems:\n", "  subsystems:\n" + NESTED.replace(MEDIAN3, ""), 1)
    text = text.replace("    - {name: setpoint,",
                        "    - {name: w, block: Subsystem, subsystem: clamped_median, inputs: [In1, In2, In3, err]}\n"
                        "    - {name: v, block: Sum, inputs: [w.out, w.raw, median]}\n"
                        "    - {name: setpoint,")
    p = tmp_path / "m.yaml"
    p.write_text(text)
    assert len(load_model(p).controller.diagram.blocks) == 13 + 5 + 1   # w: median3 and c; v
    refused_count = 0
    for mutant in _mutants(text, seed, 400):
        p.write_text(mutant)
        try:
            load_model(p)
        except InvalidNodeModel as exc:
            refused_count += 1
            assert all(d.line is not None and d.message for d in exc.diagnostics)
    assert refused_count > 100

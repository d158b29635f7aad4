"""Block diagrams (DESIGN.md rule 4.11): every refusal with its message,
line and column; the model objects; exact numbers; the reference
interpreter (pyrosgen/frontend/blocksim.py) on hand-computed cases; the
emitted Coq diagram, which must pass ``Diagram.dg_wf``; and the
interpreter against Coq's own ``Diagram.dg_step``, bit for bit."""

from __future__ import annotations

import dataclasses
import math
import random
import re
import struct
import subprocess
import sys
from decimal import Decimal, localcontext
from fractions import Fraction
from pathlib import Path

import pytest

from pyrosgen import InvalidNodeModel, load_model
from pyrosgen.frontend import blocksim as bs
from pyrosgen.frontend import ieee
from pyrosgen.frontend.blocks import MAX_BLOCKS
from pyrosgen.proof.coqdiagram import ASSUMED_PRELUDE, EmitError, coq_comment, coq_val, emit_diagram

from support.frontend import LANDSHARK, MODELS, REPO

LANDSHARK_DIAGRAM = REPO / "examples" / "landshark" / "landshark_diagram.yaml"
ALL = MODELS / "ok_blocks_all.yaml"
ORDER = MODELS / "ok_blocks_order.yaml"

# --------------------------------------------------------------------------
# A model around a diagram: the controller's inputs are fed by std_msgs
# topics; `blocks` is written from line FIRST on, `outports` after it.

INPUTS = {"In1": "float64", "In2": "float64", "In3": "float64", "I": "int32", "J": "int32",
          "U": "uint32", "B": "bool", "C": "bool", "D": "bool", "F": "float32", "L": "int64",
          "UL": "uint64"}
_MSG = {"float64": "Float64", "float32": "Float32", "int32": "Int32", "uint32": "UInt32", "bool": "Bool",
        "int64": "Int64", "uint64": "UInt64", "int8": "Int8", "uint16": "UInt16"}
FIRST = 13


def model_text(blocks: str | None, outports: str | None = "  outports: {Out1: x}\n", *,
               outputs: str = "{Out1: float64}", inputs: dict | None = None, ctrl: str = "Controller",
               uvar: str = "Controller_U", yvar: str = "Controller_Y", period: int = 20) -> str:
    inputs = INPUTS if inputs is None else inputs
    fields = ", ".join(f"{k}: {v}" for k, v in inputs.items())
    head = (f"node:\n  name: n\n  period_ms: {period}\ncontroller:\n  name: {ctrl}\n"
            f"  inputs:\n    name: {uvar}\n    fields: {{{fields}}}\n"
            f"  outputs:\n    name: {yvar}\n    fields: {outputs}\n")
    assert head.count("\n") == FIRST - 2
    body = ("  blocks:\n" + blocks if blocks is not None else "") + (outports or "")
    topics = "topics:\n" + "".join(
        f"  - {{name: /in_{k}, direction: subscribe, type: std_msgs/{_MSG[v]}, queue_size: 1}}\n"
        for k, v in inputs.items())
    rels = "relations:\n  inputs:\n" + "".join(
        f"    - {{topic: /in_{k}, field: data, input: {k}}}\n" for k in inputs)
    return head + body + topics + rels


def write(tmp_path: Path, *args, **kw) -> Path:
    p = tmp_path / "m.yaml"
    p.write_text(model_text(*args, **kw))
    return p


def diags(tmp_path: Path, *args, **kw) -> list:
    """The diagnostics of the model, as (line relative to the first
    block, column, message, rule)."""
    with pytest.raises(InvalidNodeModel) as info:
        load_model(write(tmp_path, *args, **kw))
    return [(d.line - FIRST + 1, d.col, d.message, d.rule) for d in info.value.diagnostics]


def diagram_of(tmp_path: Path, *args, **kw):
    return load_model(write(tmp_path, *args, **kw)).controller.diagram


# --------------------------------------------------------------------------
# Refusals: each case gives the blocks, the outports (default {Out1: x})
# and options, and every diagnostic expected: (line from the first block,
# column, a fragment of the message).

B = "    - {name: x, block: Abs, input: In1}\n"

REFUSED = {
    # names
    "name_not_identifier": ("    - {name: my-x, block: Abs, input: In1}\n", "  outports: {Out1: my_x}\n", {}, [
        (1, 14, "block name 'my-x' cannot be used: it is not a C identifier"),
        (2, 20, "unknown signal 'my_x'")]),
    "name_keyword": ("    - {name: int, block: Abs, input: In1}\n", None, {}, [
        (1, 14, "block name 'int' cannot be used: it is a C keyword"),
        (0, 3, "controller.blocks without controller.outports")]),
    "name_too_long": ("    - {name: " + "a" * 60 + ", block: Abs, input: In1}\n", "  outports: {Out1: " + "a" * 60 + "}\n", {}, [
        (1, 14, "is longer than 59 characters (60; its C temporary is rtb_<name>)")]),
    "name_reserved": ("    - {name: _x, block: Abs, input: In1}\n", "  outports: {Out1: _x}\n", {}, [
        (1, 14, "block name '_x' cannot be used: it is reserved by the C standard at file scope")]),
    "driven_twice_blocks": (B + "    - {name: x, block: Gain, input: In1, gain: 2}\n", "  outports: {Out1: x}\n", {}, [
        (2, 14, "signal 'x' is driven twice: by this block and by controller.blocks[0] (x) (line 13)")]),
    "driven_twice_input": ("    - {name: In2, block: Abs, input: In1}\n" + B, "  outports: {Out1: x}\n", {}, [
        (1, 14, "signal 'In2' is driven twice: by this block and by controller input 'In2' (line 8)")]),
    # kinds and keys
    "unknown_kind": ("    - {name: x, block: Gian, input: In1, gain: 2}\n", "  outports: {Out1: x}\n", {}, [
        (1, 24, "unknown block kind 'Gian' (did you mean 'Gain'?)")]),
    "unknown_key": ("    - {name: x, block: MinMax, fuction: min, inputs: [In1]}\n", "  outports: {Out1: x}\n", {}, [
        (1, 7, "missing key 'function'"),
        (1, 32, "a MinMax block has no key 'fuction' (did you mean 'function'?)")]),
    "input_for_inputs": ("    - {name: x, block: Gain, inputs: [In1], gain: 2}\n", "  outports: {Out1: x}\n", {}, [
        (1, 7, "missing key 'input'"),
        (1, 30, "a Gain block has no key 'inputs' (did you mean 'input'?)")]),
    "missing_key": ("    - {name: x, block: Gain, input: In1}\n", "  outports: {Out1: x}\n", {}, [
        (1, 7, "missing key 'gain' (a Gain block needs input, gain)")]),
    "missing_block": ("    - {name: x, input: In1}\n", "  outports: {Out1: x}\n", {}, [
        (1, 7, "missing key 'block'")]),
    "not_a_list": ("    x\n", "  outports: {Out1: x}\n", {}, [
        (1, 5, "controller.blocks must be a list of blocks, got string 'x'")]),
    "empty": ("    []\n", "  outports: {Out1: In1}\n", {}, [
        (1, 5, "controller.blocks must list at least one block")]),
    "method": ("    - {name: x, block: DiscreteIntegrator, input: In1, method: BackwardEuler}\n", "  outports: {Out1: x}\n", {}, [
        (1, 64, "unknown integration method 'BackwardEuler' (did you mean 'ForwardEuler'?)")]),
    "minmax_function": ("    - {name: x, block: MinMax, function: mean, inputs: [In1]}\n", "  outports: {Out1: x}\n", {}, [
        (1, 42, "unknown function 'mean'; expected min, max")]),
    "logic_lowercase": ("    - {name: x, block: Logic, operator: and, inputs: [B, C]}\n", "  outports: {Out1: In1}\n", {}, [
        (1, 41, "unknown operator 'and' (did you mean 'AND'?)")]),
    "relational_operator": ("    - {name: x, block: RelationalOperator, operator: =<, inputs: [In1, In2]}\n", "  outports: {Out1: In1}\n", {}, [
        (1, 54, "unknown operator '=<' (did you mean '<'?)")]),
    "folded_operator": ("    - name: x\n      block: RelationalOperator\n      operator: >\n      inputs: [In1, In2]\n",
                        "  outports: {Out1: In1}\n", {}, [
        (3, 17, "operator is empty (a bare '>' starts a folded text in YAML: quote the operator")]),
    "criterion": ("    - {name: x, block: Switch, inputs: [In1, I, In2], criterion: u2 == 0}\n", "  outports: {Out1: x}\n", {}, [
        (1, 66, "unknown criterion 'u2 == 0' (did you mean 'u2 ~= 0'?)")]),
    # signals
    "unknown_signal": ("    - {name: x, block: Gain, input: In4, gain: 2}\n", "  outports: {Out1: x}\n", {}, [
        (1, 37, "unknown signal 'In4' (did you mean 'In3'?)")]),
    "signal_is_output": ("    - {name: x, block: Gain, input: Out1, gain: 2}\n", "  outports: {Out1: x}\n", {}, [
        (1, 37, "unknown signal 'Out1' ('Out1' is a controller output")]),
    "input_not_signal_type": ("    - {name: x, block: Gain, input: S, gain: 2}\n", "  outports: {Out1: In1}\n",
                              {"inputs": {"In1": "float64", "S": "int8", "T": "uint16"}}, [
        (-4, 28, "controller input 'S' is int8: the inputs and outputs of a controller written as a block "
                 "diagram have the signal types bool, int32, uint32, int64, uint64, float32, float64"),
        (-4, 37, "controller input 'T' is uint16")]),
    # arity
    "arity_product": ("    - {name: x, block: Product, inputs: [In1, In2, In3]}\n", "  outports: {Out1: x}\n", {}, [
        (1, 41, "a Product block takes 2 inputs [a, b], got 3")]),
    "arity_switch": ("    - {name: x, block: Switch, inputs: [In1, In2], criterion: u2 ~= 0}\n", "  outports: {Out1: x}\n", {}, [
        (1, 40, "a Switch block takes 3 inputs [a, control, b]")]),
    "arity_sum": ("    - {name: x, block: Sum, inputs: []}\n", "  outports: {Out1: x}\n", {}, [
        (1, 37, "a Sum block takes at least one input, got 0")]),
    "arity_not": ("    - {name: x, block: Logic, operator: NOT, inputs: [B, C]}\n", "  outports: {Out1: In1}\n", {}, [
        (1, 54, "a Logic block with operator NOT takes exactly 1 input, got 2")]),
    "arity_xor": ("    - {name: x, block: Logic, operator: XOR, inputs: [B]}\n", "  outports: {Out1: In1}\n", {}, [
        (1, 54, "a Logic block with operator XOR takes at least 2 inputs, got 1")]),
    "single_input_list": ("    - {name: x, block: Abs, input: [In1]}\n", "  outports: {Out1: x}\n", {}, [
        (1, 36, "input must be one signal name; an Abs block has one input")]),
    "signs_length": ("    - {name: x, block: Sum, inputs: [In1, In2], signs: \"+\"}\n", "  outports: {Out1: x}\n", {}, [
        (1, 56, "signs has 1 signs for 2 inputs")]),
    "signs_chars": ("    - {name: x, block: Sum, inputs: [In1, In2], signs: \"+*\"}\n", "  outports: {Out1: x}\n", {}, [
        (1, 56, "signs must be a string of '+' and '-', one per input, got '+*'")]),
    # types
    "sum_mismatch": ("    - {name: x, block: Sum, inputs: [In1, I]}\n", "  outports: {Out1: x}\n", {}, [
        (1, 43, "type mismatch: input 'I' is int32 but input 'In1' is float64; the inputs of a Sum block have one type")]),
    "gain_bool": ("    - {name: x, block: Gain, input: B, gain: 2}\n", "  outports: {Out1: x}\n", {}, [
        (1, 37, "a Gain block computes on numbers; its input is bool")]),
    "abs_int": ("    - {name: x, block: Abs, input: I}\n", "  outports: {Out1: x}\n", {}, [
        (1, 36, "an Abs block computes on float32 or float64; its input is int32")]),
    "divide_int": ("    - {name: x, block: Divide, inputs: [I, J]}\n", "  outports: {Out1: x}\n", {}, [
        (1, 41, "a Divide block computes on float32 or float64; its input is int32")]),
    "integrator_int": ("    - {name: x, block: DiscreteIntegrator, input: I}\n", "  outports: {Out1: x}\n", {}, [
        (1, 51, "a DiscreteIntegrator block computes on float32 or float64; its input is int32")]),
    "cascade_reported_once": ("    - {name: a, block: Abs, input: I}\n    - {name: x, block: Sum, inputs: [a, In1]}\n",
                              "  outports: {Out1: x}\n", {}, [
        (1, 36, "an Abs block computes on float32 or float64; its input is int32")]),
    "error_in_a_loop_is_reported": ("    - {name: a, block: Gain, input: d, gain: 2}\n"
                                    "    - {name: d, block: UnitDelay, input: a, type: bool}\n",
                                    "  outports: {Out1: In1}\n", {}, [
        (1, 37, "a Gain block computes on numbers; its input is bool")]),
    "relational_mismatch": ("    - {name: x, block: RelationalOperator, operator: \"<\", inputs: [In1, I]}\n", "  outports: {Out1: In1}\n", {}, [
        (1, 73, "type mismatch: input 'I' is int32 but input 'In1' is float64")]),
    "relational_bool": ("    - {name: x, block: RelationalOperator, operator: \"<\", inputs: [B, C]}\n", "  outports: {Out1: In1}\n", {}, [
        (1, 68, "a RelationalOperator block compares numbers; its inputs are bool")]),
    "logic_float": ("    - {name: x, block: Logic, operator: OR, inputs: [B, In1]}\n", "  outports: {Out1: In1}\n", {}, [
        (1, 57, "type mismatch: input 'In1' is float64 but a Logic block's inputs are bool")]),
    "switch_mismatch": ("    - {name: x, block: Switch, inputs: [In1, B, I], criterion: u2 ~= 0}\n", "  outports: {Out1: x}\n", {}, [
        (1, 49, "type mismatch: input 'I' is int32 but input 'In1' is float64")]),
    "switch_bool_threshold": ("    - {name: x, block: Switch, inputs: [In1, B, In2], criterion: u2 >= threshold, threshold: 1}\n",
                              "  outports: {Out1: x}\n", {}, [
        (1, 46, "control input 'B' is bool; criterion 'u2 >= threshold' compares numbers")]),
    "switch_missing_threshold": ("    - {name: x, block: Switch, inputs: [In1, I, In2], criterion: u2 >= threshold}\n",
                                 "  outports: {Out1: x}\n", {}, [
        (1, 7, "missing key 'threshold' (criterion 'u2 >= threshold' compares the control input with it)")]),
    "switch_extra_threshold": ("    - {name: x, block: Switch, inputs: [In1, I, In2], criterion: u2 ~= 0, threshold: 1}\n",
                               "  outports: {Out1: x}\n", {}, [
        (1, 75, "criterion 'u2 ~= 0' takes no threshold")]),
    "switch_threshold_type": ("    - {name: x, block: Switch, inputs: [In1, I, In2], criterion: u2 > threshold, threshold: 1.5}\n",
                              "  outports: {Out1: x}\n", {}, [
        (1, 93, "threshold: '1.5' is not an integer, and the type is int32")]),
    "delay_type_mismatch": ("    - {name: x, block: UnitDelay, input: In1, type: float32}\n", "  outports: {Out1: In1}\n", {}, [
        (1, 42, "type mismatch: input 'In1' is float64 but this UnitDelay has type float32")]),
    "delay_type_unknown": ("    - {name: d, block: UnitDelay, input: g}\n    - {name: g, block: Gain, input: d, gain: 2}\n",
                           "  outports: {Out1: In1}\n", {}, [
        (1, 14, "cannot infer the type of this UnitDelay: its input is computed from its own output only, "
                "with no typed signal; give it a type (for example type: float64)")]),
    "integrator_type_unknown": ("    - {name: i, block: DiscreteIntegrator, input: g}\n    - {name: g, block: Gain, input: i, gain: 2}\n",
                                "  outports: {Out1: In1}\n", {}, [
        (1, 14, "cannot infer the type of this DiscreteIntegrator")]),
    "type_not_signal_type": ("    - {name: x, block: Constant, type: int8, value: 1}\n", "  outports: {Out1: In1}\n", {}, [
        (1, 40, "type: 'int8' is not a signal type (did you mean 'int64'?)")]),
    # constants
    "float_for_int": ("    - {name: x, block: Constant, type: int32, value: 1.5}\n", "  outports: {Out1: In1}\n", {}, [
        (1, 54, "value: '1.5' is not an integer, and the type is int32")]),
    "int32_range": ("    - {name: x, block: Constant, type: int32, value: 2147483648}\n", "  outports: {Out1: In1}\n", {}, [
        (1, 54, "value: 2147483648 is out of the range of int32 (-2147483648 to 2147483647)")]),
    "uint32_negative": ("    - {name: x, block: Constant, type: uint32, value: -1}\n", "  outports: {Out1: In1}\n", {}, [
        (1, 55, "value: -1 is out of the range of uint32 (0 to 4294967295)")]),
    "uint64_range": ("    - {name: x, block: Constant, type: uint64, value: 18446744073709551616}\n", "  outports: {Out1: In1}\n", {}, [
        (1, 55, "value: 18446744073709551616 is out of the range of uint64")]),
    "bool_number": ("    - {name: x, block: Constant, type: bool, value: 1}\n", "  outports: {Out1: In1}\n", {}, [
        (1, 53, "a bool constant is true or false, got int '1'")]),
    "float64_overflow": ("    - {name: x, block: Constant, type: float64, value: 1.8e+308}\n", "  outports: {Out1: In1}\n", {}, [
        (1, 56, "value: '1.8e+308' is out of the range of float64 (it rounds to infinity)")]),
    "float32_overflow": ("    - {name: x, block: Constant, type: float32, value: 3.5e+38}\n", "  outports: {Out1: In1}\n", {}, [
        (1, 56, "value: '3.5e+38' is out of the range of float32 (it rounds to infinity)")]),
    "exponent_as_text": ("    - {name: x, block: Constant, type: float64, value: 1e-3}\n", "  outports: {Out1: In1}\n", {}, [
        (1, 56, "expected a number of type float64, got string '1e-3' (YAML 1.1 reads a number with an exponent as "
                "text unless it has a dot and a signed exponent: write 1.0e-3 or 1.0e+5)")]),
    "gain_string": ("    - {name: x, block: Gain, input: In1, gain: two}\n", "  outports: {Out1: x}\n", {}, [
        (1, 48, "gain: expected a number of type float64, got string 'two'")]),
    "saturation_bounds": ("    - {name: x, block: Saturation, input: In1, lower: 2, upper: 1}\n", "  outports: {Out1: x}\n", {}, [
        (1, 55, "lower 2 is above upper 1")]),
    "saturation_bounds_float32": ("    - {name: x, block: Saturation, input: F, lower: 0.1, upper: 0.1000000001}\n",
                                  "  outports: {Out1: In1}\n", {}, []),
    "integrator_one_limit": ("    - {name: x, block: DiscreteIntegrator, input: In1, lower: -1}\n", "  outports: {Out1: x}\n", {}, [
        (1, 56, "lower without upper: give both limits or neither")]),
    "integrator_initial": ("    - {name: x, block: DiscreteIntegrator, input: In1, lower: 1, upper: 2}\n", "  outports: {Out1: x}\n", {}, [
        (1, 63, "initial 0 is outside [lower, upper] = [1, 2]")]),
    "integrator_kt_overflow": ("    - {name: x, block: DiscreteIntegrator, input: In1, gain: 1.0e+308}\n", "  outports: {Out1: x}\n",
                               {"period": 3600000}, [
        (1, 62, "gain * sample time (1.0e+308 * 3600000 / 1000) is out of the range of float64")]),
    # loops
    "algebraic_loop": ("    - {name: a, block: Gain, input: c, gain: 2}\n    - {name: b, block: Gain, input: a, gain: 2}\n"
                       "    - {name: c, block: Sum, inputs: [b, In1]}\n", "  outports: {Out1: c}\n", {}, [
        (1, 14, "algebraic loop: a -> b -> c -> a: each of these blocks needs the output of the one before it")]),
    "algebraic_loop_self": ("    - {name: x, block: Sum, inputs: [In1, x]}\n", "  outports: {Out1: x}\n", {}, [
        (1, 14, "algebraic loop: x -> x")]),
    "algebraic_loop_named_at_first": ("    - {name: p, block: Abs, input: In1}\n    - {name: q, block: Gain, input: r, gain: 2}\n"
                                      "    - {name: r, block: Gain, input: q, gain: 3}\n", "  outports: {Out1: r}\n", {}, [
        (2, 14, "algebraic loop: q -> r -> q")]),
    # outports
    "blocks_without_outports": (B, None, {}, [
        (0, 3, "controller.blocks without controller.outports")]),
    "outports_without_blocks": (None, "  outports: {Out1: In1}\n", {}, [
        (0, 3, "controller.outports without controller.blocks")]),
    "outports_not_mapping": (B, "  outports: [x]\n", {}, [
        (2, 13, "controller.outports must be a mapping (output field: signal), got a list")]),
    "outport_missing": (B, "  outports: {Out: x}\n", {}, [
        (2, 3, "controller.outports: output 'Out1' takes no signal; every controller output takes exactly one"),
        (2, 14, "controller.outports: 'Out' is not a controller output (did you mean 'Out1'?)")]),
    "outport_is_input": (B, "  outports: {Out1: x, In1: x}\n", {}, [
        (2, 23, "'In1' is not a controller output ('In1' is a controller input)")]),
    "outport_unknown_signal": (B, "  outports: {Out1: y}\n", {}, [
        (2, 20, "controller.outports.Out1: unknown signal 'y'")]),
    "outport_type": ("    - {name: x, block: Abs, input: F}\n", "  outports: {Out1: x}\n", {}, [
        (2, 20, "controller.outports.Out1: type mismatch: output 'Out1' is float64 but signal 'x' is float32")]),
    "output_not_signal_type": (B, "  outports: {Out1: x, Y: x}\n", {"outputs": "{Out1: float64, Y: int8}"}, [
        (-1, 29, "controller output 'Y' is int8: the inputs and outputs of a controller written as a block diagram")]),
    # C names
    "state_var_clash": (B, "  outports: {Out1: x}\n", {"uvar": "Controller_DW"}, [
        (0, 3, "the C name 'Controller_DW' derived from the block diagram of controller 'Controller' (its state) "
               "collides with the one derived from controller.inputs.name")]),
    "state_struct_clash": (B, "  outports: {Out1: x}\n", {"yvar": "DW_Controller_T"}, [
        (0, 3, "the C name 'DW_Controller_T' derived from the block diagram of controller 'Controller' (its state) "
               "collides with the one derived from controller.outputs.name")]),
    "temporary_clash": (B, "  outports: {Out1: x}\n", {"yvar": "rtb_x"}, [
        (1, 14, "its C temporary 'rtb_x' collides with the name derived from controller.outputs.name")]),
    "inport_temporary_too_long": ("    - {name: x, block: Abs, input: " + "V" * 60 + "}\n", "  outports: {Out1: x}\n",
                                  {"inputs": {"V" * 60: "float64"}}, None),
}


@pytest.mark.parametrize("case", sorted(REFUSED), ids=str)
def test_refused(tmp_path, case):
    blocks, outports, kw, expected = REFUSED[case]
    if expected == []:  # a near miss that is accepted
        assert load_model(write(tmp_path, blocks, outports, **kw)).controller.diagram is not None
        return
    got = diags(tmp_path, blocks, outports, **kw)
    if expected is None:  # only the diagram's diagnostics are checked
        got = [d for d in got if d[3] == "4.11"]
        expected = [(-4, 14, "controller input '" + "V" * 60 + "' is read by the diagram: its C temporary "
                     "'rtb_" + "V" * 60 + "' would be longer than 63 characters")]
    rendered = "\n".join(map(str, got))
    assert len(got) == len(expected), rendered
    for (line, col, frag), (gl, gc, gm, rule) in zip(sorted(expected), sorted(got)):
        assert (gl, gc) == (line, col) and frag in gm, f"expected {line}:{col}: {frag}\ngot:\n{rendered}"
        assert rule == "4.11", rendered


def test_every_problem_at_once_through_the_command_line(tmp_path):
    """`pyrosgen check`: one compiler-style line per problem, [rule 4.11],
    exit 1, no traceback."""
    blocks = ("    - {name: x, block: Gian, input: In1}\n"
              "    - {name: y, block: Sum, inputs: [In1, I]}\n"
              "    - {name: z, block: Gain, input: z, gain: 2}\n")
    path = write(tmp_path, blocks, "  outports: {Out1: nothing}\n")
    p = subprocess.run([sys.executable, "-m", "pyrosgen", "check", str(path)], capture_output=True, text=True,
                       cwd=REPO, timeout=120)
    assert p.returncode == 1, p.stderr
    assert "Traceback" not in p.stderr and p.stdout == ""
    lines = p.stderr.splitlines()
    assert lines == [
        f"{path}:13:24: error: controller.blocks[0] (x): unknown block kind 'Gian' (did you mean 'Gain'?); "
        "expected one of Constant, Gain, Sum, Product, Divide, Abs, MinMax, Saturation, RelationalOperator, "
        "Logic, Switch, UnitDelay, DiscreteIntegrator, Subsystem [rule 4.11]",
        f"{path}:14:43: error: controller.blocks[1] (y): type mismatch: input 'I' is int32 but input 'In1' is "
        "float64; the inputs of a Sum block have one type [rule 4.11]",
        f"{path}:15:14: error: controller.blocks[2] (z): algebraic loop: z -> z: each of these blocks needs the "
        "output of the one before it within the same step; break the loop with a UnitDelay [rule 4.11]",
        f"{path}:16:20: error: controller.outports.Out1: unknown signal 'nothing' [rule 4.11]",
    ]


def test_too_many_blocks(tmp_path):
    chain = "".join(f"    - {{name: b{i}, block: Gain, input: b{i + 1}, gain: 2}}\n" for i in range(MAX_BLOCKS - 1))
    chain += f"    - {{name: b{MAX_BLOCKS - 1}, block: Abs, input: In1}}\n"
    # the limit itself, written against the data flow, is accepted and sorted
    d = diagram_of(tmp_path, chain, "  outports: {Out1: b0}\n")
    assert len(d.blocks) == MAX_BLOCKS and d.order[0] == f"b{MAX_BLOCKS - 1}" and d.order[-1] == "b0"
    got = diags(tmp_path, chain + "    - {name: extra, block: Abs, input: In1}\n", "  outports: {Out1: b0}\n")
    assert got == [(1, 5, f"controller.blocks lists {MAX_BLOCKS + 1} blocks; a diagram has at most {MAX_BLOCKS}",
                    "4.11")]


def test_quote_hints_for_yaml_operators(tmp_path):
    """`operator: !=` and `operator: >=` unquoted are YAML syntax (rule
    4.1); the messages say to quote them."""
    blocks = "    - name: x\n      block: RelationalOperator\n      operator: !=\n      inputs: [In1, In2]\n"
    got = diags(tmp_path, blocks, "  outports: {Out1: In1}\n")
    assert [(l, c, r) for l, c, _, r in got] == [(3, 17, "4.1")]
    assert "a value that starts with '!' must be quoted, e.g. '!='" in got[0][2]
    got = diags(tmp_path, blocks.replace("!=", ">="), "  outports: {Out1: In1}\n")
    assert "a value that starts with '>' must be quoted, e.g. operator: '>='" in got[0][2]


# --------------------------------------------------------------------------
# The model objects


def test_landshark_diagram_model():
    m = load_model(LANDSHARK_DIAGRAM)
    d = m.controller.diagram
    assert load_model(LANDSHARK).controller.diagram is None
    assert (m.controller.state_var, m.controller.state_struct) == ("Controller_DW", "DW_Controller_T")
    assert [f.name for f in d.inports] == ["In1", "In2", "In3"]
    assert [(f.name, s) for f, s in d.outports] == [("Out1", "out")]
    assert [b.name for b in d.states] == ["integ"]
    assert d.evaluation_order()[:4] == ("In1", "In2", "In3", "integ")
    integ = d.block("integ")
    # kt = KI * T = 0.5 * 20 ms, rounded once: the double nearest 0.01
    assert integ.kt.n == ieee.bits_of_double(0.01) == 0x3F847AE147AE147B
    assert (integ.lower.n, integ.upper.n, integ.initial.n) == (ieee.bits_of_double(-0.5), ieee.bits_of_double(0.5), 0)
    assert d.block("err_ok").input_prim == "float64" and d.block("err_ok").prim == "bool"
    assert d.block("err_raw").signs == "+-" and d.block("command").signs == "+++"
    assert d.signal_type("err_ok") == "bool" and d.signal_type("In2") == "float64"
    with pytest.raises(dataclasses.FrozenInstanceError):
        d.blocks[0].name = "other"  # type: ignore[misc]
    assert hash(d) == hash(load_model(LANDSHARK_DIAGRAM).controller.diagram)


def test_evaluation_order_is_the_data_flow_and_stable():
    d = load_model(ORDER).controller.diagram
    assert d.evaluation_order() == ("In1", "d", "x", "y", "z")
    assert [f.name for f in d.inports] == ["In1"]      # In2 is not read
    assert [(f.name, s) for f, s in d.outports] == [("Out1", "z"), ("Out2", "In1")]
    d = load_model(ALL).controller.diagram
    order = d.order
    # already in order in the model: kept, but for `one`, read by `cnt` above it
    plain = [b.name for b in d.blocks if not b.is_state]
    assert [n for n in order if n != "one"] == [n for n in plain if n != "one"]
    assert order.index("one") == order.index("cnt") - 1
    assert {b.name: b.prim for b in d.states} == {"if32": "float32", "i64": "float64", "dly": "float64",
                                                   "dly2": "int32", "dlyb": "bool"}


# --------------------------------------------------------------------------
# Numbers


def _exact_decimal(q: Fraction) -> str:
    with localcontext() as ctx:
        ctx.prec = 200
        return str(Decimal(q.numerator) / Decimal(q.denominator))


def test_float32_constants_are_rounded_once():
    """1 + 2^-24 + 2^-60 is just above the midpoint of two floats: it
    rounds up to 1 + 2^-23; rounded to a double first, it becomes the
    midpoint 1 + 2^-24, which ties to even, 1.0."""
    text = _exact_decimal(1 + Fraction(1, 2**24) + Fraction(1, 2**60))
    assert ieee.decimal_bits(text, ieee.F32) == 0x3F800001
    via_double = struct.unpack("<I", struct.pack("<f", float(text)))[0]
    assert via_double == 0x3F800000
    # the same below the midpoint, and the midpoint itself (ties to even)
    assert ieee.decimal_bits(_exact_decimal(1 + Fraction(1, 2**24) - Fraction(1, 2**60)), ieee.F32) == 0x3F800000
    assert ieee.decimal_bits(_exact_decimal(1 + Fraction(1, 2**24)), ieee.F32) == 0x3F800000
    assert ieee.decimal_bits(_exact_decimal(1 + Fraction(3, 2**24)), ieee.F32) == 0x3F800002


@pytest.mark.parametrize("text, fmt, bits", [
    ("0.1", ieee.F64, 0x3FB999999999999A),
    ("0.1", ieee.F32, 0x3DCCCCCD),
    ("-0.0", ieee.F64, 0x8000000000000000),
    ("-0", ieee.F32, 0x80000000),
    ("+2", ieee.F64, 0x4000000000000000),
    (".5", ieee.F64, 0x3FE0000000000000),
    ("1.", ieee.F64, 0x3FF0000000000000),
    ("1.7976931348623157e+308", ieee.F64, 0x7FEFFFFFFFFFFFFF),
    ("4.9406564584124654e-324", ieee.F64, 0x1),
    ("2.4703282292062328e-324", ieee.F64, 0x1),            # just above half the least subnormal
    ("2.4703282292062327e-324", ieee.F64, 0x0),            # just below
    ("1.0e-400", ieee.F64, 0x0),
    ("-1.0e-99999999999999", ieee.F64, 0x8000000000000000),
    ("3.4028234663852886e+38", ieee.F32, 0x7F7FFFFF),
    ("1.401298464324817e-45", ieee.F32, 0x1),
    ("16777217", ieee.F32, 0x4B800000),                   # 2^24 + 1: ties to even, down
    ("16777219", ieee.F32, 0x4B800002),                   # 2^24 + 3: ties to even, up
])
def test_decimal_bits(text, fmt, bits):
    assert ieee.decimal_bits(text, fmt) == bits


def test_float_ops_agree_with_exact_rounding():
    """binary64 through Python's floats and binary32 through rationals
    both equal the exact result rounded once (random patterns, subnormal
    and huge ones included); the NaN rules are FloatOps'."""
    rng = random.Random(411)
    for f in (ieee.F64, ieee.F32):
        for _ in range(3000):
            x = rng.getrandbits(f.width)
            y = rng.getrandbits(f.width) if rng.random() < 0.7 else x ^ rng.getrandbits(3)
            for op in "+-*/":
                r = ieee.fop(f, op, x, y)
                if ieee.is_nan(f, x) or ieee.is_nan(f, y) or ieee.is_inf(f, x) or ieee.is_inf(f, y) or (
                        op == "/" and ieee.is_zero(f, y)):
                    continue
                a, b = ieee.to_fraction(f, x), ieee.to_fraction(f, y)
                exact = {"+": a + b, "-": a - b, "*": a * b, "/": a / b if b else None}[op]
                if exact == 0:
                    continue
                assert r == ieee.round_fraction(abs(exact), exact < 0, f), (f, hex(x), op, hex(y))
    f = ieee.F64
    snan = 0x7FF0000000000001
    assert ieee.fop(f, "*", snan, 0x3FF0000000000000) == 0x7FF8000000000001       # quieted, kept
    assert ieee.fop(f, "+", 0x3FF0000000000000, 0xFFF0000000000002) == 0xFFF8000000000002
    assert ieee.fop(f, "/", 0, 0) == 0xFFF8000000000000                           # the default NaN
    assert ieee.fop(ieee.F32, "-", 0x7F800000, 0x7F800000) == 0xFFC00000
    assert ieee.fop(f, "+", 0x8000000000000000, 0x8000000000000000) == 0x8000000000000000
    assert ieee.fop(f, "-", 0x3FF0000000000000, 0x3FF0000000000000) == 0
    assert ieee.fop(ieee.F32, "*", 0x80000000, 0x3F800000) == 0x80000000
    assert ieee.fop(f, "/", 0x3FF0000000000000, 0x8000000000000000) == 0xFFF0000000000000


# --------------------------------------------------------------------------
# The reference interpreter, on hand-computed cases

D = lambda x: bs.value_of("float64", x)  # noqa: E731
NAN = 0x7FF8000000000000
NEG0 = 0x8000000000000000

MEDIAN = ("    - {name: lo12,   block: MinMax, function: min, inputs: [In1, In2]}\n"
          "    - {name: hi12,   block: MinMax, function: max, inputs: [In1, In2]}\n"
          "    - {name: lo,     block: MinMax, function: min, inputs: [hi12, In3]}\n"
          "    - {name: x,      block: MinMax, function: max, inputs: [lo12, lo]}\n")


def one_step(d, **inputs):
    _, y = bs.step(d, bs.initial_state(d), inputs)
    return y


@pytest.mark.parametrize("a, b, c, want", [
    (D(1.0), D(2.0), D(3.0), D(2.0)),
    (D(3.0), D(1.0), D(2.0), D(2.0)),
    (D(2.0), D(3.0), D(1.0), D(2.0)),
    (D(-1.0), D(-1.0), D(5.0), D(-1.0)),
    (NAN, D(1.0), D(2.0), NAN),            # a NaN first is kept by min and max ...
    (D(1.0), NAN, D(2.0), D(1.0)),         # ... and skipped when it comes later
    (D(1.0), D(2.0), NAN, D(2.0)),
    (0, NEG0, 0, 0),                       # -0 < +0 is false: the first zero wins
    (NEG0, 0, NEG0, NEG0),
    (NEG0, 0, 0, NEG0),
])
def test_median_of_three(tmp_path, a, b, c, want):
    d = diagram_of(tmp_path, MEDIAN)
    assert one_step(d, In1=a, In2=b, In3=c)["Out1"] == want


def test_saturation(tmp_path):
    d = diagram_of(tmp_path, "    - {name: x, block: Saturation, input: In1, lower: -1, upper: 1}\n")
    payload = 0x7FF4000000000123
    for x, want in [(D(5.0), D(1.0)), (D(-5.0), D(-1.0)), (D(0.5), D(0.5)), (payload, payload),
                    (NEG0, NEG0), (D(math.inf), D(1.0)), (D(-math.inf), D(-1.0))]:
        assert one_step(d, In1=x)["Out1"] == want
    d = diagram_of(tmp_path, "    - {name: x, block: Saturation, input: I, lower: -3, upper: 7}\n",
                   "  outports: {Out1: x}\n", outputs="{Out1: int32}")
    assert [one_step(d, I=v)["Out1"] for v in (-2**31, -3, 0, 7, 8)] == [-3, -3, 0, 7, 7]


def test_integrator_with_limits_over_five_steps(tmp_path):
    """kt = 2 * 100 ms = 0.2; the output of a step is the state at its
    start; the state is clamped to [-0.5, 0.5] after each update."""
    d = diagram_of(tmp_path, "    - {name: x, block: DiscreteIntegrator, input: In1, gain: 2, lower: -0.5, upper: 0.5, "
                             "initial: 0.25}\n", period=100)
    assert d.block("x").kt.n == D(0.2)
    state = bs.initial_state(d)
    outs = []
    for u in (1.0, 1.0, -1.0, -10.0, 0.0):
        state, y = bs.step(d, state, {"In1": D(u)})
        outs.append(bs.python_of("float64", y["Out1"]))
    assert outs == [0.25, 0.25 + 0.2, 0.5, 0.5 - 0.2, -0.5]
    assert outs == [0.25, 0.45, 0.5, 0.3, -0.5]
    assert state == {"x": D(-0.5)}


def test_unit_delay_and_counter(tmp_path):
    blocks = ("    - {name: x, block: Sum, inputs: [d, one]}\n"
              "    - {name: d, block: UnitDelay, input: x, initial: 2147483646}\n"
              "    - {name: one, block: Constant, type: int32, value: 1}\n")
    d = diagram_of(tmp_path, blocks, "  outports: {Out1: d}\n", outputs="{Out1: int32}")
    assert [y["Out1"] for y in bs.run(d, [{}] * 4)] == [2147483646, 2147483647, -2147483648, -2147483647]


def test_int32_wrap_around(tmp_path):
    blocks = ("    - {name: g, block: Gain, input: I, gain: 2}\n"
              "    - {name: s, block: Sum, inputs: [I, J]}\n"
              "    - {name: p, block: Product, inputs: [I, J]}\n"
              "    - {name: n, block: Sum, inputs: [I], signs: \"-\"}\n"
              "    - {name: u, block: Sum, inputs: [U, U, U], signs: \"-++\"}\n"
              "    - {name: w, block: Sum, inputs: [U], signs: \"-\"}\n")
    d = diagram_of(tmp_path, blocks, "  outports: {G: g, S: s, P: p, N: n, W: w, V: u}\n",
                   outputs="{G: int32, S: int32, P: int32, N: int32, W: uint32, V: uint32}")
    y = one_step(d, I=2**30, J=2**30, U=1)
    assert y == {"G": -2**31, "S": -2**31, "P": 0, "N": -2**30, "W": 2**32 - 1, "V": 1}
    y = one_step(d, I=-2**31, J=-1, U=0)
    assert y == {"G": 0, "S": 2**31 - 1, "P": -2**31, "N": -2**31, "W": 0, "V": 0}


def test_sum_with_a_leading_minus(tmp_path):
    d = diagram_of(tmp_path, "    - {name: x, block: Sum, inputs: [In1, In2], signs: \"-+\"}\n")
    assert one_step(d, In1=D(3.0), In2=D(1.0))["Out1"] == D(-2.0)
    assert one_step(d, In1=0, In2=0)["Out1"] == 0                 # -0 + +0 = +0
    assert one_step(d, In1=0, In2=NEG0)["Out1"] == NEG0           # -0 + -0 = -0
    # a NaN is negated (sign flipped), then quieted by the addition
    assert one_step(d, In1=0x7FF0000000000001, In2=D(1.0))["Out1"] == 0xFFF8000000000001


def test_logic(tmp_path):
    blocks = "".join(f"    - {{name: l_{op.lower()}, block: Logic, operator: {op}, inputs: [B, C, D]}}\n"
                     for op in ("AND", "OR", "NAND", "NOR", "XOR"))
    blocks += "    - {name: l_not, block: Logic, operator: NOT, inputs: [B]}\n"
    d = diagram_of(tmp_path, blocks, "  outports: {A: l_and, O: l_or, NA: l_nand, NO: l_nor, X: l_xor, N: l_not}\n",
                   outputs="{A: bool, O: bool, NA: bool, NO: bool, X: bool, N: bool}")
    for b in (0, 1, 2):
        for c in (0, 1):
            for e in (0, 1):
                t = [b != 0, c != 0, e != 0]
                y = one_step(d, B=b, C=c, D=e)
                assert y == {"A": int(all(t)), "O": int(any(t)), "NA": int(not all(t)), "NO": int(not any(t)),
                             "X": sum(t) % 2, "N": int(not t[0])}, (b, c, e)


def test_switch_criteria(tmp_path):
    blocks = ("    - {name: ge, block: Switch, inputs: [In1, I, In2], criterion: u2 >= threshold, threshold: 0}\n"
              "    - {name: gt, block: Switch, inputs: [In1, In3, In2], criterion: u2 > threshold, threshold: 0}\n"
              "    - {name: nz, block: Switch, inputs: [In1, In3, In2], criterion: u2 ~= 0}\n"
              "    - {name: nzi, block: Switch, inputs: [In1, I, In2], criterion: u2 ~= 0}\n"
              "    - {name: nzb, block: Switch, inputs: [In1, B, In2], criterion: u2 ~= 0}\n")
    d = diagram_of(tmp_path, blocks, "  outports: {GE: ge, GT: gt, NZ: nz, NZI: nzi, NZB: nzb}\n",
                   outputs="{GE: float64, GT: float64, NZ: float64, NZI: float64, NZB: float64}")
    a, b = D(1.0), D(2.0)

    def run(i, c, flag):
        return one_step(d, In1=a, In2=b, I=i, In3=c, B=flag)

    assert run(0, D(0.0), 0) == {"GE": a, "GT": b, "NZ": b, "NZI": b, "NZB": b}
    assert run(-1, NEG0, 2) == {"GE": b, "GT": b, "NZ": b, "NZI": a, "NZB": a}
    assert run(5, NAN, 1) == {"GE": a, "GT": b, "NZ": a, "NZI": a, "NZB": a}    # NaN: unordered, but non-zero
    assert run(5, D(5e-324), 0)["GT"] == a


def test_float32_and_nan_payloads(tmp_path):
    blocks = ("    - {name: c, block: Constant, type: float32, value: 0.1}\n"
              "    - {name: x, block: Product, inputs: [F, c]}\n"
              "    - {name: q, block: Divide, inputs: [F, F]}\n"
              "    - {name: g, block: Gain, input: In1, gain: 3}\n"
              "    - {name: a, block: Abs, input: In1}\n")
    d = diagram_of(tmp_path, blocks, "  outports: {X: x, Q: q, G: g, A: a}\n",
                   outputs="{X: float32, Q: float32, G: float64, A: float64}")
    y = one_step(d, F=bs.value_of("float32", 3.0), In1=0xFFF0000000000005)
    assert y["X"] == 0x3E99999A                       # 0.1f * 3.0f, as FloatOps.mul32_example
    assert y["Q"] == bs.value_of("float32", 1.0)
    assert y["G"] == 0xFFF8000000000005               # the NaN operand, quieted
    assert y["A"] == 0x7FF0000000000005               # the sign bit cleared, nothing else
    y = one_step(d, F=0, In1=NEG0)
    assert (y["Q"], y["A"]) == (0xFFC00000, 0)        # 0/0: the default NaN; |-0| = +0


# --------------------------------------------------------------------------
# The emitted Coq diagram


def test_emitted_text():
    t = emit_diagram(load_model(ALL))
    assert t.startswith("Definition the_diagram : diagram := mkdiagram\n")
    assert t.rstrip().endswith(".") and t.count("Definition") == 1
    assert 'mkeq "c_l" Pint64 (Bconst (Vlong (-9223372036854775808)%Z))' in t
    assert 'mkeq "c_ul" Puint64 (Bconst (Vlong 18446744073709551615%Z))' in t
    assert 'mkeq "c_f" Pfloat32 (Bconst (Vsingle (float32_of_bits 0x3DCCCCCD%Z)))' in t
    assert 'mkeq "c_d" Pfloat64 (Bconst (Vfloat (float64_of_bits 0x8000000000000000%Z)))' in t
    assert 'mkeq "c_b" Pbool (Bconst (Vint 1%Z))' in t
    assert 'mkeq "si" Pint32 (Bsum [(false, "gi"); (true, "J"); (true, "c_i")])' in t
    assert 'mkeq "sw3" Pbool (Bswitch Cne0 Pbool (Vint 0%Z) "B" "lg_xor" "C")' in t
    assert 'mkeq "sw2" Pfloat32 (Bswitch Cgt Pfloat64 (Vfloat (float64_of_bits 0x3FE0000000000000%Z)) "pf" "In1" "G")' in t
    assert 'mkeq "rel_u" Pbool (Brelational Rne Puint32 "U" "c_u")' in t
    assert 'mkeq "rel_f" Pbool (Brelational Rne Pfloat32 "F" "G")' in t
    assert 'mkeq "lg_not" Pbool (Blogical Lnot ["C"])' in t
    assert 'mkeq "m64" Pfloat64 (Bminmax false ["In1"; "In2"; "c_d"])' in t
    assert ('mkstate "i64" Pfloat64 (Vfloat (float64_of_bits 0x3FD0000000000000%Z)) "sat64" (Kintegrator '
            '(Vfloat (float64_of_bits 0x3F747AE147AE147B%Z)) (Some (Vfloat (float64_of_bits 0xBFF0000000000000%Z), '
            'Vfloat (float64_of_bits 0x3FF0000000000000%Z))))') in t        # kt: 0.5 * 10 ms = 0.005
    assert 'mkstate "if32" Pfloat32 (Vsingle (float32_of_bits 0x00000000%Z)) "af" (Kintegrator (Vsingle (float32_of_bits 0x3CCCCCCD%Z)) None)' in t
    assert 'mkstate "dly2" Pint32 (Vint 0%Z) "cnt" Kdelay' in t
    # equations: the inputs read (S is not), the states, then the blocks
    sigs = re.findall(r'mkeq "(\w+)"', t)
    d = load_model(ALL).controller.diagram
    assert sigs == list(d.evaluation_order())
    assert sigs[:12] == ["In1", "In2", "F", "G", "I", "J", "U", "L", "UL", "B", "C", "if32"]
    assert '("YIn", "In2")' in t and '("YCount", "dly2")' in t
    with pytest.raises(EmitError):
        emit_diagram(load_model(LANDSHARK))


def test_coq_literals_are_checked():
    assert coq_comment('x (*) "y" \\ \u00e9\u2028') == "x \\x28\\x2a\\x29 \\x22y\\x22 \\x5c \\xe9\\u2028"
    m = load_model(ORDER)
    d = m.controller.diagram
    assert d.blocks[3].name == "d"   # the UnitDelay, printed before the other blocks
    hostile = dataclasses.replace(d, blocks=d.blocks[:3] + (dataclasses.replace(d.blocks[3], name='d" ; Axiom x'),))
    with pytest.raises(EmitError):
        emit_diagram(dataclasses.replace(m, controller=dataclasses.replace(m.controller, diagram=hostile)))


def test_coq_val_refuses_values_out_of_range():
    from pyrosgen.frontend.model import Scalar
    assert coq_val(Scalar("int32", -1)) == "Vint (-1)%Z"
    for bad in (Scalar("int32", 2**31), Scalar("uint32", -1), Scalar("float32", 2**32), Scalar("bool", 2),
                Scalar("int8", 0)):
        with pytest.raises(EmitError):
            coq_val(bad)


def _coq_file(tmp_path: Path, parts: list[str]) -> Path:
    v = tmp_path / "Dg.v"
    v.write_text(ASSUMED_PRELUDE + "From Flocq Require Import IEEE754.Bits.\n" + "\n".join(parts))
    return v


def _run_coqc(v: Path) -> str:
    from support.generate import coqc, require_library
    require_library()
    return coqc(v).stdout


def test_emitted_diagrams_pass_dg_wf(tmp_path):
    """The Coq text of three diagrams compiles and Diagram.dg_wf accepts
    it (by vm_compute); the same diagram with its equations out of order
    is refused, so the check can fail."""
    models = [load_model(p) for p in (LANDSHARK_DIAGRAM, ALL, ORDER)]
    parts = []
    for i, m in enumerate(models):
        parts.append(f"Module D{i}.\n{emit_diagram(m)}\n"
                     "Lemma wf : dg_wf the_diagram = true. Proof. vm_compute. reflexivity. Qed.\n"
                     f"End D{i}.\n")
    m = models[2]
    d = m.controller.diagram
    bad = dataclasses.replace(m, controller=dataclasses.replace(
        m.controller, diagram=dataclasses.replace(d, order=tuple(reversed(d.order)))))
    parts.append(f"Module Bad.\n{emit_diagram(bad)}\n"
                 "Lemma not_wf : dg_wf the_diagram = false. Proof. vm_compute. reflexivity. Qed.\nEnd Bad.\n")
    _run_coqc(_coq_file(tmp_path, parts))


def _random_value(prim: str, rng: random.Random) -> int:
    specials = {
        "float64": [0, NEG0, D(1.0), D(-2.5), D(0.5), D(1e-310), NAN, 0xFFF0000000000009, D(math.inf),
                    D(-math.inf), D(1e308), D(3.0)],
        "float32": [0, 0x80000000, 0x3F800000, 0x7FC00000, 0xFF800001, 0x7F800000, 0x00000001, 0x40400000],
        "int32": [0, 1, -1, 2**31 - 1, -2**31, 3, -100, 101],
        "uint32": [0, 1, 2**32 - 1, 2**31, 7],
        "int64": [0, -1, 2**63 - 1, -2**63, 12345],
        "uint64": [0, 2**64 - 1, 2**64 - 2, 2**63, 9],
        "bool": [0, 1, 2],
    }[prim]
    if rng.random() < 0.5:
        return rng.choice(specials)
    if prim in ("float64", "float32"):
        return rng.getrandbits(64 if prim == "float64" else 32)
    lo, hi = {"int32": (-2**31, 2**31 - 1), "uint32": (0, 2**32 - 1), "int64": (-2**63, 2**63 - 1),
              "uint64": (0, 2**64 - 1), "bool": (0, 255)}[prim]
    return rng.randint(lo, hi)


_COQ_RUN = """
Definition bits (v : val) : Z :=
  match v with
  | Vint n | Vlong n => n
  | Vfloat f => bits_of_b64 f
  | Vsingle f => bits_of_b32 f
  | _ => (-424242)%Z
  end.
Definition mv_bits (mv : mval) : list Z :=
  match mv with
  | MVstruct fs => map (fun fv => match snd fv with MVscalar v => bits v | _ => (-434343)%Z end) fs
  | _ => []
  end.
Fixpoint run (s : mval) (us : list mval) : list (list Z) :=
  match us with
  | [] => []
  | u :: us' =>
      let (s', y) := dg_step the_diagram s u in
      app (map (fun xv => bits (snd xv)) (rev (step_signals the_diagram s u))) (app (mv_bits y) (mv_bits s'))
      :: run s' us'
  end.
"""


STEPS = 30


def test_interpreter_agrees_with_coq_dg_step(tmp_path):
    """Diagram.dg_step computed by Coq and blocksim.step, bit for bit, on
    random inputs (NaNs, zeros of both signs, infinities, extreme
    integers among them) over 30 steps of three diagrams: every signal
    of every step (Diagram.step_signals), the outputs and the next
    state."""
    from pyrosgen.frontend.model import Scalar
    rng = random.Random(4_11)
    models = [load_model(p) for p in (LANDSHARK_DIAGRAM, ALL, ORDER)]
    parts, expected = [], []
    for i, m in enumerate(models):
        d = m.controller.diagram
        fields = m.controller.inputs.fields
        seq = [{f.name: _random_value(f.prim, rng) for f in fields} for _ in range(STEPS)]

        def mv(u):
            # (a bool input may hold any byte: 2 is true too)
            return "MVstruct [" + "; ".join(
                f'("{f.name}", MVscalar ({coq_val(Scalar(f.prim, u[f.name])) if f.prim != "bool" else f"Vint {u[f.name]}%Z"}))'
                for f in fields) + "]"

        parts.append(f"Module D{i}.\n{emit_diagram(m)}\n{_COQ_RUN}\n"
                     f"Eval vm_compute in run (dg_init the_diagram) [{'; '.join(mv(u) for u in seq)}].\n"
                     f"End D{i}.\n")
        state, rows = bs.initial_state(d), []
        for u in seq:
            env = bs.signals(d, state, u)
            assert tuple(env) == d.evaluation_order()
            state, y = bs.step(d, state, u)
            rows.append(list(env.values()) + [y[f.name] for f in m.controller.outputs.fields]
                        + [state[b.name] for b in d.states])
        expected.append(rows)
    out = _run_coqc(_coq_file(tmp_path, parts))
    printed = re.findall(r"=\s*(\[.*?\])\s*:\s*list \(list Z\)", out, flags=re.S)
    assert len(printed) == len(models), out
    assert [len(r) for r in expected] == [STEPS] * 3
    for text, rows in zip(printed, expected):
        got = [[int(n) for n in re.findall(r"-?\d+", row)] for row in re.findall(r"\[([^\[\]]*)\]", text)]
        assert got == rows


# --------------------------------------------------------------------------
# Random diagrams: whatever the front end accepts, Coq's dg_wf accepts


_NUM_TYPES = ("int32", "uint32", "int64", "uint64", "float32", "float64")
_SIG_OF_TYPE = {"float64": ["In1", "In2", "In3"], "int32": ["I", "J"], "uint32": ["U"], "bool": ["B", "C", "D"],
                "float32": ["F"], "int64": ["L"], "uint64": ["UL"]}


def _number(t: str, rng: random.Random, lo=None, hi=None) -> str:
    if t == "bool":
        return rng.choice(["true", "false"])
    if t in ("float32", "float64"):
        return rng.choice([f"{rng.uniform(-10, 10):.3f}", "0.1", "-0.0", "1.0e+3", "2", "-7.25e-2"])
    lo_t, hi_t = {"int32": (-2**31, 2**31 - 1), "uint32": (0, 2**32 - 1), "int64": (-2**63, 2**63 - 1),
                  "uint64": (0, 2**64 - 1)}[t]
    return str(rng.choice([rng.randint(lo_t, hi_t), rng.randint(max(lo_t, -50), 50), lo_t, hi_t]))


def random_diagram(rng: random.Random) -> tuple[str, str, str]:
    """A random diagram over INPUTS: mostly well typed by construction,
    with a few wrong inputs, forward references of delays (loops) and
    delays without a type."""
    n = rng.randint(1, 9)
    types = [rng.choice(("bool",) + _NUM_TYPES) for _ in range(n)]
    names = [f"s{i}" for i in range(n)]
    lines = []

    def pick(t: str, upto: int, any_block: bool = False) -> str:
        pool = list(_SIG_OF_TYPE[t]) + [names[j] for j in range(n if any_block else upto) if types[j] == t]
        if rng.random() < 0.08:
            pool = list(INPUTS) + names      # possibly a wrong type, or a loop
        return rng.choice(pool)

    for i, t in enumerate(types):
        num = t != "bool"
        flt = t in ("float32", "float64")
        kinds = ["Constant", "Switch", "UnitDelay"] + (
            ["Gain", "Sum", "Product", "MinMax", "Saturation"] if num else ["RelationalOperator", "Logic"]) + (
            ["Divide", "Abs", "DiscreteIntegrator"] if flt else [])
        k = rng.choice(kinds)
        nm = names[i]
        if k == "Constant":
            lines.append(f"{{name: {nm}, block: Constant, type: {t}, value: {_number(t, rng)}}}")
        elif k == "Gain":
            lines.append(f"{{name: {nm}, block: Gain, input: {pick(t, i)}, gain: {_number(t, rng)}}}")
        elif k in ("Sum", "MinMax"):
            m = rng.randint(1, 4)
            ins = ", ".join(pick(t, i) for _ in range(m))
            extra = (f", signs: \"{''.join(rng.choice('+-') for _ in range(m))}\"" if k == "Sum"
                     else f", function: {rng.choice(['min', 'max'])}")
            lines.append(f"{{name: {nm}, block: {k}, inputs: [{ins}]{extra}}}")
        elif k in ("Product", "Divide"):
            lines.append(f"{{name: {nm}, block: {k}, inputs: [{pick(t, i)}, {pick(t, i)}]}}")
        elif k == "Abs":
            lines.append(f"{{name: {nm}, block: Abs, input: {pick(t, i)}}}")
        elif k == "Saturation":
            a, b = sorted([_number(t, rng), _number(t, rng)], key=lambda x: float(x))
            lines.append(f"{{name: {nm}, block: Saturation, input: {pick(t, i)}, lower: {a}, upper: {b}}}")
        elif k == "RelationalOperator":
            qa = rng.choice(_NUM_TYPES)
            op = rng.choice(["'=='", "'~='", "'!='", "'<'", "'<='", "'>'", "'>='"])
            lines.append(f"{{name: {nm}, block: RelationalOperator, operator: {op}, "
                         f"inputs: [{pick(qa, i)}, {pick(qa, i)}]}}")
        elif k == "Logic":
            op = rng.choice(["AND", "OR", "NAND", "NOR", "XOR", "NOT"])
            m = 1 if op == "NOT" else rng.randint(2, 4)
            lines.append(f"{{name: {nm}, block: Logic, operator: {op}, inputs: [{', '.join(pick('bool', i) for _ in range(m))}]}}")
        elif k == "Switch":
            qc = rng.choice(("bool",) + _NUM_TYPES)
            crit = "u2 ~= 0" if qc == "bool" else rng.choice(["u2 ~= 0", "u2 >= threshold", "u2 > threshold"])
            thr = "" if crit == "u2 ~= 0" else f", threshold: {_number(qc, rng)}"
            lines.append(f"{{name: {nm}, block: Switch, inputs: [{pick(t, i)}, {pick(qc, i)}, {pick(t, i)}], "
                         f"criterion: {crit}{thr}}}")
        elif k == "UnitDelay":
            typ = f", type: {t}" if rng.random() < 0.5 else ""
            init = f", initial: {_number(t, rng)}" if rng.random() < 0.5 else ""
            lines.append(f"{{name: {nm}, block: UnitDelay, input: {pick(t, i, any_block=True)}{typ}{init}}}")
        else:
            lim = ""
            if rng.random() < 0.5:
                lim = f", lower: -{rng.randint(1, 5)}, upper: {rng.randint(0, 5)}"
            gain = f", gain: {_number(t, rng)}" if rng.random() < 0.7 else ""
            lines.append(f"{{name: {nm}, block: DiscreteIntegrator, input: {pick(t, i, any_block=True)}{gain}{lim}}}")
    outs = []
    for j in range(rng.randint(1, 3)):
        s = rng.choice(names + list(INPUTS))
        t = types[names.index(s)] if s in names else INPUTS[s]
        outs.append((f"O{j}", s, t))
    blocks = "".join(f"    - {line}\n" for line in lines)
    outports = "  outports: {" + ", ".join(f"{o}: {s}" for o, s, _ in outs) + "}\n"
    outputs = "{" + ", ".join(f"{o}: {t}" for o, _, t in outs) + "}"
    return blocks, outports, outputs


def test_random_diagrams_accepted_by_the_front_end_pass_dg_wf(tmp_path):
    rng = random.Random(20_411)
    accepted, refused = [], 0
    for k in range(160):
        blocks, outports, outputs = random_diagram(rng)
        path = tmp_path / f"r{k}.yaml"
        path.write_text(model_text(blocks, outports, outputs=outputs))
        try:
            m = load_model(path)
        except InvalidNodeModel as exc:
            refused += 1
            assert {d.rule for d in exc.diagnostics} == {"4.11"}, "\n".join(map(str, exc.diagnostics))
            continue
        d = m.controller.diagram
        # the interpreter runs it (random inputs, a few steps)
        state = bs.initial_state(d)
        for _ in range(3):
            state, _y = bs.step(d, state, {f.name: _random_value(f.prim, rng) for f in m.controller.inputs.fields})
        accepted.append(m)
    assert len(accepted) >= 40 and refused >= 20, (len(accepted), refused)
    parts = [f"Module R{i}.\n{emit_diagram(m)}\n"
             "Lemma wf : dg_wf the_diagram = true. Proof. vm_compute. reflexivity. Qed.\n"
             f"End R{i}.\n" for i, m in enumerate(accepted)]
    _run_coqc(_coq_file(tmp_path, parts))

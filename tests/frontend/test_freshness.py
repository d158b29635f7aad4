"""Freshness (DESIGN.md rule 4.12): topics' ``timeout_ms`` and
``on_timeout``, input relations' fallbacks (``on_timeout``) and derived
inputs (``derived: is_new | received | age_ms``).  Every refusal with its
message, line and column; the model objects; the numbers of the
fallbacks; coverage (4.8) and names (4.9) with derived inputs and timed
topics; the model text (the seam with Coq's ``ModelText.print_model``);
and the three record fields emitted into the per-node Coq file."""

from __future__ import annotations

import dataclasses
import re
import struct
from pathlib import Path

import pytest

from pyrosgen import InvalidNodeModel, cli, load_model
from pyrosgen.frontend.model import DerivedRelation, InputRelation, Scalar
from pyrosgen.frontend.validate import FIXED_C_NAMES, LOCAL_C_NAMES
from pyrosgen.proof.coqmodel import EmitError, coq_fallback, emit_model, render_node_file
from pyrosgen.proof.modeltext import MalformedModelText, model_text, parse_model_text

from support.frontend import LANDSHARK, REPO

# --------------------------------------------------------------------------
# The design's example, with all features: a topic timeout with the zero
# policy, a per-relation constant, the three derived inputs.

VELOCITY_GUARD = """\
node: {name: velocity_guard, period_ms: 20}
controller:
  name: Controller
  inputs:
    name: Controller_U
    fields: {V1: float64, W1: float64, New1: bool, Rcv1: bool, Age1: uint32, S: float64}
  outputs:
    name: Controller_Y
    fields: {Out1: float64}
topics:
  - name: /teleop/cmd_vel
    direction: subscribe
    type: geometry_msgs/Twist
    queue_size: 1
    timeout_ms: 500        # stale after half a second
    on_timeout: zero
  - {name: /speed, direction: subscribe, type: std_msgs/Float64, queue_size: 1}
  - {name: /out, direction: publish, type: std_msgs/Float64, queue_size: 1}
relations:
  inputs:
    - {topic: /teleop/cmd_vel, field: linear.x, input: V1}
    - {topic: /teleop/cmd_vel, field: angular.z, input: W1, on_timeout: 0.5}
    - {topic: /teleop/cmd_vel, derived: is_new,   input: New1}
    - {topic: /speed, field: data, input: S}
    - {topic: /teleop/cmd_vel, derived: received, input: Rcv1}
    - {topic: /teleop/cmd_vel, derived: age_ms,   input: Age1}
  outputs:
    - {output: Out1, topic: /out, field: data}
"""


def write(tmp_path: Path, text: str, name: str = "m.yaml") -> Path:
    p = tmp_path / name
    p.write_text(text)
    return p


def load(tmp_path: Path, text: str):
    return load_model(write(tmp_path, text))


def diags(tmp_path: Path, text: str) -> list[tuple[int, int, str, str]]:
    """The model's diagnostics as (line, col, message, rule)."""
    with pytest.raises(InvalidNodeModel) as info:
        load_model(write(tmp_path, text))
    return [(d.line, d.col, d.message, d.rule) for d in info.value.diagnostics]


def at(text: str, needle: str, occurrence: int = 1, after: str = "") -> tuple[int, int]:
    """1-based (line, col) of the ``occurrence``-th ``needle`` in ``text``
    (after the first ``after``)."""
    i = text.index(after) - 1 if after else -1
    for _ in range(occurrence):
        i = text.index(needle, i + 1)
    line = text.count("\n", 0, i) + 1
    return line, i - (text.rfind("\n", 0, i) + 1) + 1


# --------------------------------------------------------------------------
# A small model to vary: topic /a (geometry_msgs/Twist) with TOPIC_EXTRA
# in its flow mapping, a published /out, controller inputs FIELDS and the
# input relations RELS (one per line).

def small(fields: str = "V: float64", topic_extra: str = ", timeout_ms: 100",
          rels: tuple[str, ...] = ("{topic: /a, field: linear.x, input: V}",), period: int = 20,
          more_topics: tuple[str, ...] = (), uvar: str = "Controller_U") -> str:
    return (
        f"node: {{name: n, period_ms: {period}}}\n"
        "controller:\n"
        "  name: Controller\n"
        "  inputs:\n"
        f"    name: {uvar}\n"
        f"    fields: {{{fields}}}\n"
        "  outputs:\n"
        "    name: Controller_Y\n"
        "    fields: {Out1: float64}\n"
        "topics:\n"
        f"  - {{name: /a, direction: subscribe, type: geometry_msgs/Twist, queue_size: 1{topic_extra}}}\n"
        "  - {name: /out, direction: publish, type: std_msgs/Float64, queue_size: 1}\n"
        + "".join(f"  - {t}\n" for t in more_topics)
        + "relations:\n"
        "  inputs:\n"
        + "".join(f"    - {r}\n" for r in rels)
        + "  outputs:\n"
        "    - {output: Out1, topic: /out, field: data}\n"
    )


# --------------------------------------------------------------------------
# Accepted models and the model objects


def test_velocity_guard_model_objects(tmp_path):
    m = load(tmp_path, VELOCITY_GUARD)
    cmd, speed, out = m.topics
    assert (cmd.timeout_ms, cmd.on_timeout) == (500, "zero")
    assert (speed.timeout_ms, speed.on_timeout) == (None, None)
    assert (out.timeout_ms, out.on_timeout) == (None, None)
    assert m.timeouts == (("teleop_cmd_vel", 500),)
    # the plain relations only, in the model's order
    assert [r.input_field for r in m.input_relations] == ["V1", "W1", "S"]
    # the derived ones, in the model's order, are not among them
    assert [(r.topic.name, r.kind, r.input_field) for r in m.derived_relations] == [
        ("/teleop/cmd_vel", "is_new", "New1"),
        ("/teleop/cmd_vel", "received", "Rcv1"),
        ("/teleop/cmd_vel", "age_ms", "Age1"),
    ]
    # V1 gets the topic's zero (+0.0), W1 its own 0.5; S (no timeout) none
    assert [(f, s.prim, s.n) for f, s in m.fallbacks] == [
        ("V1", "float64", 0),
        ("W1", "float64", struct.unpack("<Q", struct.pack("<d", 0.5))[0]),
    ]
    assert m.input_relation("S").fallback is None
    assert [t.name for t in m.timed_topics] == ["/teleop/cmd_vel"]
    assert cmd.timed_names() == ("teleop_cmd_vel_time", "teleop_cmd_vel_new", "teleop_cmd_vel_rcvd")
    assert m.derived_relation("Age1").kind == "age_ms"
    with pytest.raises(KeyError):
        m.derived_relation("V1")
    with pytest.raises(KeyError):
        m.input_relation("New1")


def test_model_objects_are_immutable(tmp_path):
    m = load(tmp_path, VELOCITY_GUARD)
    for obj, attr in ((m.topics[0], "timeout_ms"), (m.input_relations[0], "fallback"),
                      (m.derived_relations[0], "kind"), (m, "derived_relations")):
        with pytest.raises(dataclasses.FrozenInstanceError):
            setattr(obj, attr, None)
    hash(m.derived_relations[0])
    assert isinstance(m.derived_relations[0], DerivedRelation)
    assert isinstance(m.input_relations[0], InputRelation)


def test_plain_models_have_no_freshness(tmp_path):
    m = load_model(LANDSHARK)
    assert m.timeouts == () and m.fallbacks == () and m.derived_relations == () and m.timed_topics == ()
    assert all(t.timeout_ms is None and t.on_timeout is None for t in m.topics)


@pytest.mark.parametrize("topic_policy, rel_policy, expected", [
    (None, None, [("V", 0)]),                  # default: zero
    ("zero", None, [("V", 0)]),
    ("hold", None, []),                        # hold: no entry
    ("hold", "zero", [("V", 0)]),              # the relation says otherwise
    ("zero", "hold", []),
    ("hold", "-2.5", [("V", struct.unpack("<Q", struct.pack("<d", -2.5))[0])]),
    (None, "-0.0", [("V", 1 << 63)]),          # -0.0 keeps its sign
])
def test_policies(tmp_path, topic_policy, rel_policy, expected):
    extra = ", timeout_ms: 100" + (f", on_timeout: {topic_policy}" if topic_policy else "")
    rel = "{topic: /a, field: linear.x, input: V" + (f", on_timeout: {rel_policy}" if rel_policy else "") + "}"
    m = load(tmp_path, small(topic_extra=extra, rels=(rel,)))
    assert [(f, s.n) for f, s in m.fallbacks] == expected
    assert m.topics[0].on_timeout == (topic_policy or "zero")


# One topic per primitive type (std_msgs/<T>, field data), a relation
# with a constant fallback for each.
_STD = {"bool": "Bool", "int8": "Int8", "uint8": "UInt8", "int16": "Int16", "uint16": "UInt16",
        "int32": "Int32", "uint32": "UInt32", "int64": "Int64", "uint64": "UInt64",
        "float32": "Float32", "float64": "Float64"}


def typed(values: dict[str, str], period: int = 20) -> str:
    fields = ", ".join(f"F_{p}: {p}" for p in values)
    topics = "".join(f"  - {{name: /t_{p}, direction: subscribe, type: std_msgs/{_STD[p]}, queue_size: 1, "
                     f"timeout_ms: 1000}}\n" for p in values)
    rels = "".join(f"    - {{topic: /t_{p}, field: data, input: F_{p}, on_timeout: {v}}}\n"
                   for p, v in values.items())
    return (f"node: {{name: n, period_ms: {period}}}\ncontroller:\n  name: Controller\n"
            f"  inputs:\n    name: Controller_U\n    fields: {{{fields}}}\n"
            "  outputs:\n    name: Controller_Y\n    fields: {Out1: float64}\n"
            "topics:\n" + topics
            + "  - {name: /out, direction: publish, type: std_msgs/Float64, queue_size: 1}\n"
            "relations:\n  inputs:\n" + rels
            + "  outputs:\n    - {output: Out1, topic: /out, field: data}\n")


CONSTANTS = {"bool": "true", "int8": "-128", "uint8": "255", "int16": "-32768", "uint16": "65535",
             "int32": "-2147483648", "uint32": "4294967295", "int64": "-9223372036854775808",
             "uint64": "18446744073709551615", "float32": "0.1", "float64": "0.1"}


def test_constants_of_every_type(tmp_path):
    m = load(tmp_path, typed(CONSTANTS))
    got = {f: (s.prim, s.n) for f, s in m.fallbacks}
    assert got == {
        "F_bool": ("bool", 1), "F_int8": ("int8", -128), "F_uint8": ("uint8", 255),
        "F_int16": ("int16", -32768), "F_uint16": ("uint16", 65535),
        "F_int32": ("int32", -(1 << 31)), "F_uint32": ("uint32", (1 << 32) - 1),
        "F_int64": ("int64", -(1 << 63)), "F_uint64": ("uint64", (1 << 64) - 1),
        # 0.1 rounded once to each format
        "F_float32": ("float32", 0x3DCCCCCD), "F_float64": ("float64", 0x3FB999999999999A),
    }


def test_float32_is_rounded_once_from_the_decimal(tmp_path):
    # 1 + 2^-24 + 2^-60: to binary32 directly it rounds up (above the
    # halfway point); through a double first it would be exactly halfway
    # (1 + 2^-24) and round to even, i.e. down to 1.0
    text = "1.00000005960464477539062500086736173798840354720596224069595336914062500"
    m = load(tmp_path, typed({"float32": text}))
    assert m.fallbacks[0][1].n == 0x3F800001
    assert struct.unpack("<I", struct.pack("<f", float(text)))[0] == 0x3F800000


def test_zero_of_every_type(tmp_path):
    m = load(tmp_path, typed({p: "zero" for p in CONSTANTS}))
    assert [(f, s.prim, s.n) for f, s in m.fallbacks] == [(f"F_{p}", p, 0) for p in CONSTANTS]


def test_bool_false_and_hold(tmp_path):
    m = load(tmp_path, typed({"bool": "false", "int32": "hold", "float64": "3"}))
    assert [(f, s.n) for f, s in m.fallbacks] == [("F_bool", 0), ("F_float64", 0x4008000000000000)]


def test_derived_inputs_need_no_timeout(tmp_path):
    text = small(fields="V: float64, N: bool, A: uint32", topic_extra="",
                 rels=("{topic: /a, field: linear.x, input: V}",
                       "{topic: /a, derived: is_new, input: N}",
                       "{topic: /a, derived: age_ms, input: A}"))
    m = load(tmp_path, text)
    assert m.timeouts == () and m.fallbacks == ()
    assert [t.name for t in m.timed_topics] == ["/a"]
    assert [r.kind for r in m.derived_relations] == ["is_new", "age_ms"]


@pytest.mark.parametrize("ms", [20, 86_400_000])
def test_timeout_bounds_accepted(tmp_path, ms):
    m = load(tmp_path, small(topic_extra=f", timeout_ms: {ms}", period=20))
    assert m.timeouts == (("a", ms),)


def test_derived_inputs_in_a_diagram_controller(tmp_path):
    text = """\
node: {name: n, period_ms: 20}
controller:
  name: Controller
  inputs:
    name: Controller_U
    fields: {V: float64, N: bool, R: bool, A: uint32}
  outputs:
    name: Controller_Y
    fields: {Out1: float64, Fresh: bool, Age: uint32}
  blocks:
    - {name: both, block: Logic, operator: AND, inputs: [N, R]}
    - {name: v2, block: Gain, input: V, gain: 2.0}
  outports: {Out1: v2, Fresh: both, Age: A}
topics:
  - {name: /a, direction: subscribe, type: geometry_msgs/Twist, queue_size: 1, timeout_ms: 100}
  - {name: /out, direction: publish, type: std_msgs/Float64, queue_size: 1}
relations:
  inputs:
    - {topic: /a, field: linear.x, input: V, on_timeout: 1.5}
    - {topic: /a, derived: is_new, input: N}
    - {topic: /a, derived: received, input: R}
    - {topic: /a, derived: age_ms, input: A}
  outputs:
    - {output: Out1, topic: /out, field: data}
"""
    m = load(tmp_path, text)
    d = m.controller.diagram
    assert d is not None
    assert [f.name for f in d.inports] == ["V", "N", "R", "A"]
    assert [r.input_field for r in m.derived_relations] == ["N", "R", "A"]


# --------------------------------------------------------------------------
# Refusals (rule 4.12): each at the offending value


def only(tmp_path, text: str) -> tuple[int, int, str, str]:
    ds = diags(tmp_path, text)
    assert len(ds) == 1, ds
    return ds[0]


@pytest.mark.parametrize("extra, needle, message", [
    (", timeout_ms: true", "true",
     "topics[0].timeout_ms must be an integer number of milliseconds, got boolean 'true'"),
    (", timeout_ms: 500.0", "500.0",
     "topics[0].timeout_ms must be an integer number of milliseconds, got float '500.0'"),
    (", timeout_ms: '500'", "'500'",
     "topics[0].timeout_ms must be an integer number of milliseconds, got string '500'"),
    (", timeout_ms: 0", "0}",
     "topics[0].timeout_ms must be a positive number of milliseconds, got '0'"),
    (", timeout_ms: -5", "-5",
     "topics[0].timeout_ms must be a positive number of milliseconds, got '-5'"),
    (", timeout_ms: 19", "19",
     "topics[0].timeout_ms: 19 ms is a timeout shorter than the period (node.period_ms is 20)"),
    (", timeout_ms: 86400001", "86400001",
     "topics[0].timeout_ms: 86400001 ms is longer than a day (at most 86400000)"),
    (", on_timeout: hold", "hold",
     "topics[0].on_timeout is only allowed together with timeout_ms (the topic has no timeout)"),
    (", timeout_ms: 100, on_timeout: zeros", "zeros",
     "topics[0].on_timeout must be 'hold' or 'zero', got string 'zeros' (did you mean 'zero'?)"),
    (", timeout_ms: 100, on_timeout: 0.5", "0.5",
     "topics[0].on_timeout must be 'hold' or 'zero', got float '0.5' "
     "(a constant fallback is given by an input relation's on_timeout)"),
])
def test_topic_refusals(tmp_path, extra, needle, message):
    text = small(topic_extra=extra, rels=("{topic: /a, field: linear.x, input: V}",))
    line, col = at(text, needle, after="queue_size: 1")
    assert only(tmp_path, text) == (line, col, message, "4.12")


def test_timeout_on_a_published_topic(tmp_path):
    text = small(more_topics=("{name: /p, direction: publish, type: std_msgs/Float64, queue_size: 1, "
                              "timeout_ms: 100}",))
    line, col = at(text, "100}", 2)
    assert only(tmp_path, text) == (
        line, col, "topics[2].timeout_ms: topic '/p' is published by the node; a timeout is for a "
        "subscribed topic", "4.12")


def test_topic_on_timeout_without_timeout_and_bad(tmp_path):
    """Both problems of one value are reported."""
    text = small(topic_extra=", on_timeout: hodl")
    line, col = at(text, "hodl")
    assert diags(tmp_path, text) == [
        (line, col, "topics[0].on_timeout is only allowed together with timeout_ms (the topic has no timeout)",
         "4.12"),
        (line, col, "topics[0].on_timeout must be 'hold' or 'zero', got string 'hodl' (did you mean 'hold'?)",
         "4.12"),
    ]


@pytest.mark.parametrize("prim, value, message", [
    ("float64", "hodl",
     "relations.inputs[0].on_timeout must be 'hold', 'zero' or a constant of type float64 (the type of "
     "controller input 'V'), got string 'hodl' (did you mean 'hold'?)"),
    ("int32", "0.5",
     "relations.inputs[0].on_timeout: the fallback of controller input 'V' (int32): '0.5' is not an "
     "integer, and the type is int32"),
    ("int8", "300",
     "relations.inputs[0].on_timeout: the fallback of controller input 'V' (int8): 300 is out of the "
     "range of int8 (-128 to 127)"),
    ("int8", "2.0",
     "relations.inputs[0].on_timeout: the fallback of controller input 'V' (int8): '2.0' is not an "
     "integer, and the type is int8"),
    ("uint16", "65536",
     "relations.inputs[0].on_timeout: the fallback of controller input 'V' (uint16): 65536 is out of the "
     "range of uint16 (0 to 65535)"),
    ("uint32", "-1",
     "relations.inputs[0].on_timeout: the fallback of controller input 'V' (uint32): -1 is out of the "
     "range of uint32 (0 to 4294967295)"),
    ("uint64", "18446744073709551616",
     "relations.inputs[0].on_timeout: the fallback of controller input 'V' (uint64): 18446744073709551616 "
     "is out of the range of uint64 (0 to 18446744073709551615)"),
    ("float64", "true",
     "relations.inputs[0].on_timeout: the fallback of controller input 'V' (float64): expected a number "
     "of type float64, got boolean 'true'"),
    ("bool", "1",
     "relations.inputs[0].on_timeout: the fallback of controller input 'V' (bool): a bool constant is "
     "true or false, got int '1'"),
    ("bool", "yes",
     "relations.inputs[0].on_timeout: the fallback of controller input 'V' (bool): a bool constant is "
     "true or false, got boolean 'yes'"),
    ("float32", "1.0e+39",
     "relations.inputs[0].on_timeout: the fallback of controller input 'V' (float32): '1.0e+39' is out "
     "of the range of float32 (it rounds to infinity)"),
    ("float64", "1e-3",
     "relations.inputs[0].on_timeout: the fallback of controller input 'V' (float64): expected a number "
     "of type float64, got string '1e-3' (YAML 1.1 reads a number with an exponent as text unless it has "
     "a dot and a signed exponent: write 1.0e-3 or 1.0e+5)"),
])
def test_relation_constant_refusals(tmp_path, prim, value, message):
    # a std_msgs topic of the input's type, so that only the fallback is wrong
    text = small(fields=f"V: {prim}", topic_extra="", rels=(
        f"{{topic: /t, field: data, input: V, on_timeout: {value}}}",),
        more_topics=(f"{{name: /t, direction: subscribe, type: std_msgs/{_STD[prim]}, queue_size: 1, "
                     "timeout_ms: 100}",))
    line, col = at(text, f"on_timeout: {value}")
    assert only(tmp_path, text) == (line, col + len("on_timeout: "), message, "4.12")


def test_relation_fallback_needs_a_timeout(tmp_path):
    text = small(topic_extra="", rels=("{topic: /a, field: linear.x, input: V, on_timeout: zero}",))
    line, col = at(text, "zero")
    assert only(tmp_path, text) == (
        line, col, "relations.inputs[0].on_timeout: topic '/a' has no timeout_ms; a fallback needs one", "4.12")


def test_derived_refusals(tmp_path):
    text = small(
        fields="V: float64, N: float64, R: int32, A: int32, B: bool, C: bool, D: bool",
        rels=("{topic: /a, field: linear.x, input: V}",
              "{topic: /a, derived: is_new, input: N}",
              "{topic: /a, derived: received, input: R}",
              "{topic: /a, derived: age_ms, input: A}",
              "{topic: /a, derived: is_new, input: B, field: linear.y}",
              "{topic: /a, derived: received, input: C, on_timeout: hold}",
              "{topic: /a, derived: is_newer, input: D}"))
    assert diags(tmp_path, text) == [
        (*at(text, "N}"), "relations.inputs[1].input: is_new related to a non-bool field: controller input "
                          "'N' is float64 (is_new is a bool)", "4.12"),
        (*at(text, "R}"), "relations.inputs[2].input: received related to a non-bool field: controller input "
                          "'R' is int32 (received is a bool)", "4.12"),
        (*at(text, "A}"), "relations.inputs[3].input: age_ms related to a non-uint32 field: controller input "
                          "'A' is int32 (age_ms is a uint32)", "4.12"),
        (*at(text, "linear.y"), "relations.inputs[4].field: a derived input reads no message field "
                                "(a relation has either field or derived; field goes with derived: length or "
                                "truncated only)", "4.12"),
        (*at(text, "hold"), "relations.inputs[5].on_timeout: a derived input has no fallback "
                            "(it does not read a message field)", "4.12"),
        (*at(text, "is_newer"), "relations.inputs[6].derived must be 'is_new', 'received' or 'age_ms' (or, "
                                "with a field, 'length' or 'truncated'), got string 'is_newer' (did you mean "
                                "'is_new'?)", "4.12"),
    ]


def test_derived_input_of_a_published_topic(tmp_path):
    text = small(fields="V: float64, N: bool",
                 rels=("{topic: /a, field: linear.x, input: V}", "{topic: /out, derived: is_new, input: N}"))
    line, col = at(text, "/out, derived")
    assert only(tmp_path, text) == (
        line, col, "relations.inputs[1].topic: topic '/out' is published by the node; a derived input reads "
        "a subscribed topic", "4.12")


def test_misspelt_keys_get_suggestions(tmp_path):
    text = small(fields="V: float64, N: bool", topic_extra=", timout_ms: 100",
                 rels=("{topic: /a, field: linear.x, input: V, on_timout: zero}",
                       "{topic: /a, derivd: is_new, input: N}"))
    ds = diags(tmp_path, text)
    assert (*at(text, "timout_ms"), "topics[0]: unknown key 'timout_ms' (did you mean 'timeout_ms'?); "
            "expected name, direction, type, queue_size, timeout_ms, on_timeout, stamp, frame_id, strings, "
            "max_length, policy, qos", "4.4") in ds
    assert (*at(text, "on_timout"), "relations.inputs[0]: unknown key 'on_timout' (did you mean "
            "'on_timeout'?); expected topic, field, input, on_timeout, derived", "4.7") in ds
    assert (*at(text, "derivd"), "relations.inputs[1]: unknown key 'derivd' (did you mean 'derived'?); "
            "expected topic, field, input, on_timeout, derived", "4.7") in ds


def test_all_errors_at_once_on_the_command_line(tmp_path, capsys):
    text = small(fields="V: float64, N: float64", topic_extra=", timeout_ms: 5, on_timeout: zeros",
                 rels=("{topic: /a, field: linear.x, input: V, on_timeout: hodl}",
                       "{topic: /a, derived: is_new, input: N}"))
    path = write(tmp_path, text)
    code = cli.main(["check", str(path)])
    out, err = capsys.readouterr()
    assert code == 1 and out == ""
    assert "Traceback" not in err
    lines = err.splitlines()
    assert len(lines) == 4
    for line, needle in zip(lines, ("5,", "zeros", "hodl", "N}")):
        ln, col = at(text, needle)
        assert line.startswith(f"{path}:{ln}:{col}: error: ") and line.endswith(" [rule 4.12]"), line


def test_exact_positions(tmp_path, capsys):
    """Positions written out: the value of a block-style key, of a flow one."""
    text = VELOCITY_GUARD.replace("timeout_ms: 500 ", "timeout_ms: 10  ").replace(
        "on_timeout: 0.5}", "on_timeout: 0.5x}")
    path = write(tmp_path, text)
    assert cli.main(["check", str(path)]) == 1
    out, err = capsys.readouterr()
    assert err.splitlines() == [
        f"{path}:15:17: error: topics[0].timeout_ms: 10 ms is a timeout shorter than the period "
        "(node.period_ms is 20) [rule 4.12]",
        f"{path}:22:73: error: relations.inputs[1].on_timeout must be 'hold', 'zero' or a constant of type "
        "float64 (the type of controller input 'W1'), got string '0.5x' [rule 4.12]",
    ]


def test_check_summary(tmp_path, capsys):
    path = write(tmp_path, VELOCITY_GUARD)
    assert cli.main(["check", str(path)]) == 0
    out, _ = capsys.readouterr()
    assert out == (f"{path}: ok: node velocity_guard, 3 topics, 3 input relations, 1 output relation; "
                   "freshness: 1 timed topic, 3 derived inputs\n")


# --------------------------------------------------------------------------
# Coverage (rule 4.8) and names (rule 4.9)


def test_coverage_counts_derived_relations(tmp_path):
    text = small(fields="V: float64, N: bool, M: bool",
                 rels=("{topic: /a, field: linear.x, input: V}",
                       "{topic: /a, derived: is_new, input: N}",
                       "{topic: /a, derived: received, input: N}"))
    ln, _ = at(text, "{topic: /a, derived: is_new")
    assert diags(tmp_path, text) == [
        (*at(text, "M: bool"), "controller input 'M' is not fed by any input relation", "4.8"),
        (*at(text, "N}", 2), f"controller input 'N' is fed twice (first by the relation at line {ln})", "4.8"),
    ]


def test_plain_and_derived_feeding_one_input(tmp_path):
    text = small(fields="V: float64, B: bool",
                 rels=("{topic: /a, field: linear.x, input: V}",
                       "{topic: /a, derived: is_new, input: V}",
                       "{topic: /a, derived: received, input: B}"))
    ds = diags(tmp_path, text)
    ln, _ = at(text, "{topic: /a, field")
    assert (*at(text, "V}", 2), f"controller input 'V' is fed twice (first by the relation at line {ln})",
            "4.8") in ds


@pytest.mark.parametrize("fields, topic_extra, rels, var", [
    ("V: float64", ", timeout_ms: 100", ("{topic: /a, field: linear.x, input: V}",), "a_rcvd"),
    ("V: float64, N: bool", "", ("{topic: /a, field: linear.x, input: V}",
                                 "{topic: /a, derived: is_new, input: N}"), "a_time"),
    ("V: float64", ", timeout_ms: 100", ("{topic: /a, field: linear.x, input: V}",), "a_new"),
])
def test_timed_topic_names_collide(tmp_path, fields, topic_extra, rels, var):
    """A timed topic /a (a timeout or a derived input) has the globals
    a_time, a_new and a_rcvd."""
    text = small(fields=fields, topic_extra=topic_extra, rels=rels, uvar=var)
    assert only(tmp_path, text) == (
        *at(text, "/a,"), f"the C name '{var}' derived from topic '/a' (its receipt time and flags, rule 4.12) "
        "collides with the one derived from controller.inputs.name", "4.9")


def test_untimed_topic_reserves_no_time_names(tmp_path):
    m = load(tmp_path, small(topic_extra="", uvar="a_time"))
    assert m.controller.inputs.var_name == "a_time" and m.timed_topics == ()


def test_ros_now_is_reserved(tmp_path):
    text = small(uvar="ros_now")
    assert only(tmp_path, text) == (
        *at(text, "ros_now"), "the C name 'ros_now' derived from controller.inputs.name collides with the one "
        "derived from the generated glue", "4.9")


@pytest.mark.parametrize("name", ["_now", "_age"])
@pytest.mark.parametrize("key", ["inputs", "outputs"])
def test_glue_temporaries_are_refused(tmp_path, capsys, name, key):
    """The timed glue's temporaries (input_glue's cycle time ``_now`` and
    a topic's age ``_age``) cannot name a global of the model: refused at
    the name's line and column, exit 1, no traceback."""
    text = small(uvar=name) if key == "inputs" else small().replace("name: Controller_Y", f"name: {name}")
    path = write(tmp_path, text)
    assert cli.main(["check", str(path)]) == 1
    out, err = capsys.readouterr()
    ln, col = at(text, f"name: {name}")
    assert out == "" and err == (
        f"{path}:{ln}:{col + 6}: error: controller.{key}.name '{name}' cannot be used: it is reserved by the C "
        "standard at file scope (starts with '_') [rule 4.9]\n")


def test_coq_fixed_names_are_reserved():
    """Every fixed identifier of Coq's generator (``Wellformed.v``: the ROS
    functions, the glue's functions, parameters and temporaries, rule
    4.12's ``ros_now``, ``_now`` and ``_age`` included) is reserved by the
    front end, so that a model is refused there rather than by Coq."""
    src = (REPO / "coq" / "theories" / "glue" / "Wellformed.v").read_text()
    coq = set(re.findall(r'^Definition \w+ : ident := "([^"]+)"\.$', src, re.M))
    assert {"ros_now", "_ok", "_now", "_age", "msg", "loop"} <= coq, coq
    assert coq <= set(FIXED_C_NAMES) | set(LOCAL_C_NAMES), coq - set(FIXED_C_NAMES) - set(LOCAL_C_NAMES)


# --------------------------------------------------------------------------
# The model text (the seam with Coq's ModelText.print_model)


def test_model_text_lines(tmp_path):
    m = load(tmp_path, VELOCITY_GUARD)
    text = model_text(m)
    lines = text.splitlines()
    tail = lines[lines.index("output_relation Out1 out data") + 1:]
    assert tail == [
        "timeout teleop_cmd_vel 500",
        "fallback V1 0x0000000000000000",
        "fallback W1 0x3fe0000000000000",
        "derived_input teleop_cmd_vel is_new New1",
        "derived_input teleop_cmd_vel received Rcv1",
        "derived_input teleop_cmd_vel age_ms Age1",
    ]
    assert [ln for ln in lines if ln.startswith("input_relation ")] == [
        "input_relation teleop_cmd_vel linear.x V1",
        "input_relation teleop_cmd_vel angular.z W1",
        "input_relation speed data S",
    ]
    pm = parse_model_text(text)
    assert pm.timeouts == [("teleop_cmd_vel", 500)]
    assert pm.fallbacks == [("V1", "0x0000000000000000"), ("W1", "0x3fe0000000000000")]
    assert pm.derived_inputs == [("teleop_cmd_vel", "is_new", "New1"), ("teleop_cmd_vel", "received", "Rcv1"),
                                 ("teleop_cmd_vel", "age_ms", "Age1")]


def test_model_text_values_of_every_type(tmp_path):
    m = load(tmp_path, typed(CONSTANTS))
    fallbacks = [ln for ln in model_text(m).splitlines() if ln.startswith("fallback ")]
    assert fallbacks == [
        "fallback F_bool 1", "fallback F_int8 -128", "fallback F_uint8 255", "fallback F_int16 -32768",
        "fallback F_uint16 65535", "fallback F_int32 -2147483648", "fallback F_uint32 4294967295",
        "fallback F_int64 -9223372036854775808", "fallback F_uint64 18446744073709551615",
        "fallback F_float32 0x3dcccccd", "fallback F_float64 0x3fb999999999999a",
    ]
    timeouts = [ln for ln in model_text(m).splitlines() if ln.startswith("timeout ")]
    assert timeouts == [f"timeout t_{p} 1000" for p in CONSTANTS]


def test_plain_model_text_is_unchanged():
    text = model_text(load_model(LANDSHARK))
    assert not re.search(r"^(timeout|fallback|derived_input) ", text, re.M)
    assert text.splitlines()[-1].startswith("output_relation ")


@pytest.mark.parametrize("line", [
    "timeout a", "timeout a b", "fallback V 0.5", "fallback V 0x123", "derived_input a is_old N",
    "derived_input a is_new",
])
def test_malformed_freshness_lines(line):
    head = "pyrosgen-model 1\nnode n\nperiod_ms 20\ncontroller C\ninputs U S\noutputs Y T\n"
    parse_model_text(head)
    with pytest.raises(MalformedModelText):
        parse_model_text(head + line + "\n")


# --------------------------------------------------------------------------
# The Coq terms (ROSGen.NodeModel: nm_timeouts, nm_fallbacks, nm_drels)


def test_emitted_coq_fields(tmp_path):
    v = render_node_file(load(tmp_path, VELOCITY_GUARD), ddc_available=True)
    i = v.index("    nm_timeouts :=")
    j = v.index("  |}", i)
    assert v[i:j] == (
        '    nm_timeouts :=\n'
        '      [("teleop_cmd_vel", 500%Z)];\n'
        '    nm_fallbacks :=\n'
        '      [(* V1 when stale: zero *)\n'
        '       ("V1", Vfloat (float64_of_bits 0x0000000000000000%Z));\n'
        '       (* W1 when stale: 0.5 *)\n'
        '       ("W1", Vfloat (float64_of_bits 0x3FE0000000000000%Z))];\n'
        '    nm_drels :=\n'
        '      [(* /teleop/cmd_vel is_new -> New1 *)\n'
        '       mkdrel "teleop_cmd_vel" Dis_new "New1";\n'
        '       (* /teleop/cmd_vel received -> Rcv1 *)\n'
        '       mkdrel "teleop_cmd_vel" Dreceived "Rcv1";\n'
        '       (* /teleop/cmd_vel age_ms -> Age1 *)\n'
        '       mkdrel "teleop_cmd_vel" Dage_ms "Age1"];\n'
        '    nm_stamps :=\n'
        '      [];\n'
        '    nm_stamp_from :=\n'
        '      [];\n'
        '    nm_strings :=\n'
        '      []\n'
    )
    # the fields come last in the record, after nm_outrels
    assert v.index("nm_outrels :=") < i
    # the per-node file imports what the values are written with
    assert re.search(r"^From ROSGen Require Import .*\bValues FloatBits\b", v, re.M)


def test_emitted_coq_fields_are_always_there():
    v = render_node_file(load_model(LANDSHARK), ddc_available=True)
    i = v.index("nm_outrels :=")
    assert ("\n    nm_timeouts :=\n      [];\n    nm_fallbacks :=\n      [];\n    nm_drels :=\n      [];"
            "\n    nm_stamps :=\n      [];\n    nm_stamp_from :=\n      [];\n    nm_strings :=\n      []\n  |}") in v[i:]


def test_emitted_values_of_every_type(tmp_path):
    e = emit_model(load(tmp_path, typed(CONSTANTS)))
    assert [(f, val) for f, val, _ in e.fallbacks] == [
        ('"F_bool"', "Vint 1%Z"), ('"F_int8"', "Vint (-128)%Z"), ('"F_uint8"', "Vint 255%Z"),
        ('"F_int16"', "Vint (-32768)%Z"), ('"F_uint16"', "Vint 65535%Z"),
        ('"F_int32"', "Vint (-2147483648)%Z"), ('"F_uint32"', "Vint 4294967295%Z"),
        ('"F_int64"', "Vlong (-9223372036854775808)%Z"), ('"F_uint64"', "Vlong 18446744073709551615%Z"),
        ('"F_float32"', "Vsingle (float32_of_bits 0x3DCCCCCD%Z)"),
        ('"F_float64"', "Vfloat (float64_of_bits 0x3FB999999999999A%Z)"),
    ]
    assert e.timeouts == tuple((f'"t_{p}"', "1000%Z") for p in CONSTANTS)


def test_one_constant_printer():
    """Fallbacks and diagram constants are printed by the same helper."""
    from pyrosgen.proof import coqdiagram, coqmodel

    assert coqdiagram.coq_val is coqmodel.coq_val
    assert coq_fallback(Scalar("float32", 0x3DCCCCCD)) == coqmodel.coq_val(Scalar("float32", 0x3DCCCCCD))
    assert coq_fallback(Scalar("int8", -1)) == coqmodel.coq_val(Scalar("int32", -1)) == "Vint (-1)%Z"
    assert coq_fallback(Scalar("uint16", 65535)) == "Vint 65535%Z"


def test_emitter_refuses_unprintable_freshness(tmp_path):
    m = load(tmp_path, VELOCITY_GUARD)
    bad_kind = dataclasses.replace(m, derived_relations=(
        dataclasses.replace(m.derived_relations[0], kind="is_old"),))
    with pytest.raises(EmitError):
        emit_model(bad_kind)
    bad_field = dataclasses.replace(m, input_relations=(
        dataclasses.replace(m.input_relations[0], input_field='V1" ++ "x'),) + m.input_relations[1:])
    with pytest.raises(EmitError):
        emit_model(bad_field)
    with pytest.raises(EmitError):
        coq_fallback(Scalar("float128", 0))
    with pytest.raises(EmitError):
        coq_fallback(Scalar("uint8", 1 << 32))

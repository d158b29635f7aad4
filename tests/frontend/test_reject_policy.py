"""Policy reject (DESIGN.md rule 4.15, issue 15): a subscribed topic's
``policy: {<field path>: reject}`` makes a carried variable-length array or
string of its message type a bounded struct of policy reject
(``ros_rseq_<T>_<N>``, ``ros_rstring<N>``: ``Environment.reject_name``);
a received message holding it longer than ``N`` is not delivered
(``Environment.accepted``).  The accepted models and their structs; every
refusal with its message, line, column and rule; the wrapper's reject test
and the wrapper check that holds it to the letter."""

from __future__ import annotations

import pytest

from pyrosgen.frontend.msgmodel import bounded_type, is_bounded_type, seq_type_name, string_type_name
from pyrosgen.proof.coqmodel import emit_model
from pyrosgen.proof.modeltext import model_text
from pyrosgen.ros.wrapper import render_wrapper
from pyrosgen.verify.wrapper_check import WrapperMismatch, check_wrapper

from support.frontend import at, diags, load, one

BASE = """\
node: {name: scanner, period_ms: 20}
controller:
  name: Controller
  inputs: {name: Controller_U, fields: {R: float32, NR: uint32, FL: uint32}}
  outputs: {name: Controller_Y, fields: {Out1: float64}}
topics:
  - {name: /scan, direction: subscribe, type: sensor_msgs/LaserScan, queue_size: 1, max_length: {ranges: 4},
     policy: {ranges: reject}}
  - {name: /cmd, direction: publish, type: geometry_msgs/Twist, queue_size: 1}
relations:
  inputs:
    - {topic: /scan, field: "ranges[3]", input: R}
    - {topic: /scan, field: ranges, derived: length, input: NR}
    - {topic: /scan, field: header.frame_id, derived: length, input: FL}
  outputs:
    - {output: Out1, topic: /cmd, field: linear.x}
"""

_SCAN = "(topic '/scan', sensor_msgs/LaserScan)"


def _msg_fields(model, name):
    return {f.name: f.msg for f in model.message(name).fields if f.kind == "msg"}


# --------------------------------------------------------------------------
# Accepted models


def test_the_struct_names_say_the_policy(tmp_path):
    m = load(tmp_path, BASE)
    assert _msg_fields(m, "sensor_msgs/LaserScan")["ranges"] == "ros_rseq_float32_4"
    assert _msg_fields(m, "std_msgs/Header")["frame_id"] == "ros_string128"   # truncate by default
    t = m.message("ros_rseq_float32_4")
    assert t.reject and t.is_seq and t.capacity == 4 and t.c_name == "ros_rseq_float32_4"
    assert [(f.name, f.prim, f.array_len) for f in t.fields] == [
        ("len", "uint32", None), ("truncated", "bool", None), ("data", "float32", 4)]
    assert [(r.input_field, str(r.path)) for r in m.input_relations] == [
        ("R", "ranges.data[3]"), ("NR", "ranges.len"), ("FL", "header.frame_id.len")]
    text = model_text(m)
    assert "message ros_rseq_float32_4" in text.splitlines()
    e = emit_model(m)
    names = [d.name for d in e.msgs]
    assert names.index('"ros_rseq_float32_4"') < names.index('"sensor_msgs_LaserScan"')
    assert ('"ranges"', 'FTmsg "ros_rseq_float32_4"') in e.msgs[names.index('"sensor_msgs_LaserScan"')].fields


def test_a_string_of_policy_reject_and_explicit_truncate(tmp_path):
    m = load(tmp_path, BASE.replace("policy: {ranges: reject}",
                                    "policy: {ranges: truncate, header.frame_id: reject}"))
    assert _msg_fields(m, "sensor_msgs/LaserScan")["ranges"] == "ros_seq_float32_4"
    assert _msg_fields(m, "std_msgs/Header")["frame_id"] == "ros_rstring128"
    assert m.message("ros_rstring128").reject and m.message("ros_rstring128").is_string


def test_names_and_their_inverse():
    assert seq_type_name("uint8", 7, True) == "ros_rseq_uint8_7"
    assert string_type_name(16, True) == "ros_rstring16"
    for name in ("ros_rseq_uint8_7", "ros_rstring16", "ros_seq_uint8_7", "ros_string16"):
        assert is_bounded_type(name) and bounded_type(name).name == name
        assert bounded_type(name).reject == name.startswith("ros_r")
    assert not is_bounded_type("ros_rseq_string_4") and not is_bounded_type("ros_rstring0")


def test_the_same_policy_on_two_topics_of_the_type(tmp_path):
    text = BASE.replace("  - {name: /cmd,", "  - {name: /scan2, direction: subscribe, type: sensor_msgs/LaserScan, "
                                          "queue_size: 1, policy: {ranges: reject}}\n  - {name: /cmd,")
    m = load(tmp_path, text)
    assert [t.name for t in m.topics if t.msg_type == "sensor_msgs/LaserScan"] == ["/scan", "/scan2"]
    # one topic saying nothing takes the type's policy: one struct per type
    load(tmp_path, text.replace(", policy: {ranges: reject}}\n  - {name: /cmd,", "}\n  - {name: /cmd,"))


# --------------------------------------------------------------------------
# Refusals


@pytest.mark.parametrize("value, got", [
    ("drop", "string 'drop'"), ("Reject", "string 'Reject' (did you mean 'reject'?)"),
    ("1", "int '1'"), ("[reject]", "a list")])
def test_unknown_policy_values(tmp_path, value, got):
    text = BASE.replace("policy: {ranges: reject}", f"policy: {{ranges: {value}}}")
    line, col, msg, rule = one(tmp_path, text)
    assert (line, col, rule) == (*at(text, value + "}"), "4.15")
    assert msg.startswith("topics[0].policy['ranges'] must be truncate or reject, got "), msg
    assert got.split(" (")[0] in msg, msg


def test_policy_paths_that_name_no_carried_sequence(tmp_path):
    text = BASE.replace("policy: {ranges: reject}",
                        "policy: {rangez: reject, angle_min: reject, \"ranges[3]\": reject, intensities: reject}")
    found = diags(tmp_path, text)
    head = "topics[0].policy"
    assert found == [
        (*at(text, "rangez"), f"{head}['rangez']: field path 'rangez': message type sensor_msgs/LaserScan has no "
                              f"field 'rangez' (did you mean 'ranges'?) {_SCAN}", "4.15"),
        (*at(text, "angle_min: r"), f"{head}['angle_min']: field path 'angle_min': 'angle_min' is a float32, not a "
                                    f"variable-length array or a string (policy is for those) {_SCAN}", "4.15"),
        (*at(text, '"ranges[3]"'), f"{head}['ranges[3]']: field path 'ranges[3]': 'ranges[3]' is one element of a "
                                   f"variable-length array (float32[]); policy names the whole array ('ranges') "
                                   f"{_SCAN}", "4.15"),
        (*at(text, "intensities"), f"{head}['intensities']: intensities of sensor_msgs/LaserScan is not carried (no "
                                   "relation reads it), so it has no policy (topic '/scan')", "4.15"),
    ]


def test_policy_not_a_mapping(tmp_path):
    text = BASE.replace("policy: {ranges: reject}", "policy: reject")
    assert one(tmp_path, text) == (*at(text, "reject}"), "topics[0].policy must be a mapping of field paths to "
                                   "truncate or reject (e.g. {ranges: reject}), got string 'reject'", "4.15")


def test_policy_on_a_published_topic(tmp_path):
    text = BASE.replace("type: geometry_msgs/Twist, queue_size: 1}",
                        "type: geometry_msgs/Twist, queue_size: 1, policy: {linear: reject}}")
    assert one(tmp_path, text) == (*at(text, "{linear"), "topics[1].policy: topic '/cmd' is published by the node; "
                                   "a policy says what a subscribed topic does with received data longer than its "
                                   "maximum", "4.15")


def test_two_policies_for_one_field_are_refused_with_both_positions(tmp_path):
    text = BASE.replace("  - {name: /cmd,", "  - {name: /scan2, direction: subscribe, type: sensor_msgs/LaserScan, "
                                          "queue_size: 1, policy: {ranges: truncate}}\n  - {name: /cmd,")
    first = at(text, "ranges: reject")
    assert one(tmp_path, text) == (
        *at(text, "ranges: truncate"),
        f"topics[1].policy['ranges']: truncate differs from the policy reject given to the same field (ranges of "
        f"sensor_msgs/LaserScan) at line {first[0]}, column {first[1]} (topics[0].policy['ranges']); one C "
        "struct holds the field in every topic of type sensor_msgs/LaserScan, so it has one policy", "4.15")


def test_truncated_of_a_reject_field_is_refused(tmp_path):
    text = BASE.replace("FL: uint32}", "FL: uint32, TR: bool}").replace(
        "    - {topic: /scan, field: header.frame_id,",
        "    - {topic: /scan, field: ranges, derived: truncated, input: TR}\n"
        "    - {topic: /scan, field: header.frame_id,")
    assert one(tmp_path, text) == (
        *at(text, "truncated, input"),
        "relations.inputs[2].derived: truncated of ranges, whose policy is reject, is always 0 (a longer message is "
        "not delivered): use derived: length, or policy truncate (ranges of sensor_msgs/LaserScan)", "4.15")
    # with policy truncate it is accepted
    load(tmp_path, text.replace("policy: {ranges: reject}", "policy: {ranges: truncate}"))


def test_packages_that_could_name_a_reject_struct_are_refused(tmp_path):
    for pkg in ("ros_rseq", "ros_rstring", "ros_rseq_x"):
        d = tmp_path / pkg / "msgs" / pkg / "msg"
        d.mkdir(parents=True)
        (d / "Thing.msg").write_text("uint32 n\n")
        text = BASE.replace("relations:", f"msg_paths: [{pkg}/msgs]\nrelations:")
        line, col, msg, rule = one(tmp_path, text)
        assert (line, col, rule) == (*at(text, f"{pkg}/msgs]"), "4.15")
        assert "ros_rseq_<T>_<N>, ros_rstring<N>" in msg and f"the package '{pkg}'" in msg


# --------------------------------------------------------------------------
# The wrapper's reject test and the wrapper check


def _wrapper(model) -> str:
    return next(v for k, v in render_wrapper(model).items() if k.endswith(".cpp"))


REJECT = ("        [cb](const ros::MessageEvent<sensor_msgs::LaserScan const> &e) {\n"
          "            if (e.getConstMessage()->ranges.size() > 4) return;\n"
          "            g_now_ns = e.getReceiptTime().toNSec();\n")


def test_the_wrapper_drops_over_long_messages_first_thing(tmp_path):
    m = load(tmp_path, BASE)
    cpp = _wrapper(m)
    assert cpp.count(REJECT) == 1
    check_wrapper(cpp, model_text(m), wrapper_name="scanner_ros.cpp")
    both = load(tmp_path, BASE.replace("policy: {ranges: reject}", "policy: {ranges: reject, header.frame_id: reject}"))
    cpp2 = _wrapper(both)
    assert ("            if (e.getConstMessage()->header.frame_id.size() > 128) return;\n"
            "            if (e.getConstMessage()->ranges.size() > 4) return;\n"
            "            g_now_ns") in cpp2
    check_wrapper(cpp2, model_text(both), wrapper_name="scanner_ros.cpp")
    # a truncate model has no test
    plain = load(tmp_path, BASE.replace("policy: {ranges: reject}", "policy: {ranges: truncate}"))
    assert ".size() > 4) return;" not in _wrapper(plain)


LINE = "            if (e.getConstMessage()->ranges.size() > 4) return;\n"
# the mutants of the reject test: tests/build/test_wrapper_check.py (make mutants)


def test_the_wrapper_check_refuses_a_reject_test_on_a_truncate_field(tmp_path):
    plain = load(tmp_path, BASE.replace("policy: {ranges: reject}", "policy: {ranges: truncate}"))
    cpp = _wrapper(plain)
    bad = cpp.replace("        [cb](const ros::MessageEvent<sensor_msgs::LaserScan const> &e) {\n",
                      "        [cb](const ros::MessageEvent<sensor_msgs::LaserScan const> &e) {\n" + LINE)
    assert bad != cpp
    with pytest.raises(WrapperMismatch) as info:
        check_wrapper(bad, model_text(plain), wrapper_name="w")
    assert any("policy reject drops" in line for line in info.value.lines), info.value.lines

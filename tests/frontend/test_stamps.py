"""Stamps (DESIGN.md rule 4.13): ``stamp: now`` on a published topic makes
its messages carry the cycle's ROS time in ``header.stamp``, and
``stamp: {from: <subscribed topic>}`` the stamp of that topic's newest
message.  The
accepted model and its objects, every refusal with its message, line,
column and rule, the model text (the seam with Coq's
``ModelText.print_model``), the ``nm_stamps`` field emitted into the
per-node Coq file, and the reserved names of the time functions."""

from __future__ import annotations

import pytest

from pyrosgen import load_model
from pyrosgen.proof.coqmodel import emit_model
from pyrosgen.proof.modeltext import model_text, parse_model_text

from support.frontend import at, diags, load

STAMPED = """\
node: {name: stamper, period_ms: 20}
controller:
  name: Controller
  inputs: {name: Controller_U, fields: {In1: float64}}
  outputs: {name: Controller_Y, fields: {Out1: float64}}
topics:
  - {name: /cmd_in, direction: subscribe, type: geometry_msgs/TwistStamped, queue_size: 1}
  - {name: /cmd_out, direction: publish, type: geometry_msgs/TwistStamped, queue_size: 1, stamp: now}
  - {name: /plain_out, direction: publish, type: geometry_msgs/TwistStamped, queue_size: 1}
relations:
  inputs: [{topic: /cmd_in, field: twist.linear.x, input: In1}]
  outputs:
    - {output: Out1, topic: /cmd_out, field: twist.linear.x}
    - {output: Out1, topic: /plain_out, field: twist.linear.x}
"""


def test_stamped_topic_is_read(tmp_path):
    m = load(tmp_path, STAMPED)
    by_name = {t.name: t for t in m.topics}
    assert by_name["/cmd_out"].stamped and not by_name["/plain_out"].stamped
    assert not by_name["/cmd_in"].stamped
    assert m.stamps == (("cmd_out", ("header", "stamp")),)


def test_model_text_has_the_stamp_line(tmp_path):
    text = model_text(load(tmp_path, STAMPED))
    assert text.splitlines()[-1] == "stamp cmd_out header.stamp"
    assert parse_model_text(text).stamps == [("cmd_out", "header.stamp")]


def test_coq_field_is_emitted(tmp_path):
    cm = emit_model(load(tmp_path, STAMPED))
    assert cm.stamps == (('"cmd_out"', '[PField "header"; PField "stamp"]'),)
    plain = emit_model(load(tmp_path, STAMPED.replace(", stamp: now", "")))
    assert plain.stamps == ()


_NOW_OR_FROM = ("topics[1].stamp must be 'now' (the cycle's ROS time) or {from: <topic>} "
                "(the stamp of a subscribed topic's newest message), got ")


@pytest.mark.parametrize("value, expected", [
    ("later", _NOW_OR_FROM + "string 'later'"),
    ("nwo", _NOW_OR_FROM + "string 'nwo' (did you mean 'now'?)"),
    ("1", _NOW_OR_FROM + "int '1'"),
    ("[/cmd_in]", _NOW_OR_FROM + "a list"),
])
def test_stamp_value_is_now_or_a_source(tmp_path, value, expected):
    text = STAMPED.replace("stamp: now", f"stamp: {value}")
    (d,) = diags(tmp_path, text)
    line, col = at(text, f"stamp: {value}")
    assert (d[0], d[1], d[3]) == (line, col + len("stamp: "), "4.13")
    assert d[2] == expected


COPIED = STAMPED.replace("stamp: now", "stamp: {from: /cmd_in}")


def test_copied_stamp_is_read(tmp_path):
    m = load(tmp_path, COPIED)
    by_name = {t.name: t for t in m.topics}
    assert by_name["/cmd_out"].stamped and by_name["/cmd_out"].stamp_from == "/cmd_in"
    assert m.stamps == (("cmd_out", ("header", "stamp")),)
    assert m.stamp_from == (("cmd_out", ("cmd_in", ("header", "stamp"))),)
    # a topic stamped with the time has no source
    assert load(tmp_path, STAMPED).stamp_from == ()


def test_copied_stamp_model_text_and_coq_field(tmp_path):
    m = load(tmp_path, COPIED)
    text = model_text(m)
    assert text.splitlines()[-2:] == ["stamp cmd_out header.stamp", "stamp_from cmd_out cmd_in header.stamp"]
    assert parse_model_text(text).stamp_from == [("cmd_out", "cmd_in", "header.stamp")]
    assert emit_model(m).stamp_from == (('"cmd_out"', '"cmd_in"', '[PField "header"; PField "stamp"]'),)


@pytest.mark.parametrize("source, expected", [
    ("/cmd_inn", "topics[1].stamp.from: '/cmd_inn' is not a topic of the node (did you mean '/cmd_in'?)"),
    ("/plain_out", "topics[1].stamp.from: topic '/plain_out' is published by the node; "
                   "a stamp is copied from a subscribed topic"),
    ("''", "topics[1].stamp.from must not be empty"),
])
def test_stamp_source_must_be_a_subscribed_topic(tmp_path, source, expected):
    text = STAMPED.replace("stamp: now", f"stamp: {{from: {source}}}")
    (d,) = diags(tmp_path, text)
    line, col = at(text, f"from: {source}")
    assert (d[0], d[1], d[2]) == (line, col + len("from: "), expected)


def test_stamp_source_needs_a_header(tmp_path):
    text = COPIED.replace("{name: /cmd_in, direction: subscribe, type: geometry_msgs/TwistStamped",
                          "{name: /cmd_in, direction: subscribe, type: geometry_msgs/Twist")
    text = text.replace("{topic: /cmd_in, field: twist.linear.x, input: In1}", "{topic: /cmd_in, field: linear.x, input: In1}")
    (d,) = diags(tmp_path, text)
    line, col = at(text, "from: /cmd_in")
    assert d == (line, col + len("from: "), "topics[1].stamp.from: message type geometry_msgs/Twist of topic "
                                             "'/cmd_in' has no header.stamp of type time to copy", "4.13")


def test_stamp_source_has_one_key(tmp_path):
    text = STAMPED.replace("stamp: now", "stamp: {from: /cmd_in, form: x}")
    found = diags(tmp_path, text)
    line, col = at(text, "form: x")
    assert (line, col, "topics[1].stamp: unknown key 'form' (did you mean 'from'?); expected from") in \
        [(a, b, c) for a, b, c, _ in found]


def test_subscribed_topic_is_not_stamped(tmp_path):
    text = STAMPED.replace("type: geometry_msgs/TwistStamped, queue_size: 1}\n  - {name: /cmd_out",
                           "type: geometry_msgs/TwistStamped, queue_size: 1, stamp: now}\n  - {name: /cmd_out", 1)
    text = text.replace(", queue_size: 1, stamp: now}\n  - {name: /plain_out", ", queue_size: 1}\n  - {name: /plain_out")
    (d,) = diags(tmp_path, text)
    line, col = at(text, "stamp: now")
    assert d == (line, col + len("stamp: "), "topics[0].stamp: topic '/cmd_in' is subscribed by the node; "
                                              "only a published message is stamped", "4.13")


def test_message_without_header_is_not_stamped(tmp_path):
    text = STAMPED.replace("{name: /cmd_out, direction: publish, type: geometry_msgs/TwistStamped",
                           "{name: /cmd_out, direction: publish, type: geometry_msgs/Twist")
    text = text.replace("{output: Out1, topic: /cmd_out, field: twist.linear.x}",
                        "{output: Out1, topic: /cmd_out, field: linear.x}")
    (d,) = diags(tmp_path, text)
    line, col = at(text, "stamp: now")
    assert d == (line, col + len("stamp: "), "topics[1].stamp: message type geometry_msgs/Twist of topic "
                                              "'/cmd_out' has no header.stamp of type time to stamp", "4.13")


def test_output_relation_may_not_write_the_stamp(tmp_path):
    text = STAMPED.replace("fields: {Out1: float64}", "fields: {Out1: float64, Sec: uint32}")
    text = text.replace("    - {output: Out1, topic: /plain_out",
                        "    - {output: Sec, topic: /cmd_out, field: header.stamp.sec}\n    - {output: Out1, topic: /plain_out")
    (d,) = diags(tmp_path, text)
    line, col = at(text, "header.stamp.sec")
    assert d == (line, col, "field 'header.stamp.sec' of topic '/cmd_out' is written by the stamp; "
                            "an output relation may not write it too", "4.13")


@pytest.mark.parametrize("name", ["ros_time_sec", "ros_time_nsec"])
def test_time_function_names_are_reserved(tmp_path, name):
    text = STAMPED.replace("{name: Controller_U,", f"{{name: {name},")
    found = diags(tmp_path, text)
    assert any(rule == "4.9" and name in msg for _, _, msg, rule in found), found

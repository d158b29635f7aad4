"""Constant strings (DESIGN.md rule 4.14): ``frame_id: <string>`` and
``strings: {<field path>: <string>}`` on a published topic make each of
its messages carry the constant in that ``string`` field, held in C by
``struct ros_string128`` (``len``, ``truncated``, ``data[128]``).

The accepted models and their objects (which string fields are carried,
and that every other one stays dropped); every refusal with its message,
line, column and rule; hostile input (no traceback, exit 1, nothing
written); the model text (the seam with Coq's ``ModelText.print_model``)
and its parser; the ``nm_strings`` field and the ``ros_string128``
definition emitted into the per-node Coq file; and the Python side of
the running node: the wrapper's conversions (and the wrapper check that
holds them to the letter), the ACSL contracts, ``check`` and ``diagram``."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from pyrosgen import cli, load_model
from pyrosgen.frontend.msgmodel import STRING_CAPACITY, string_type
from pyrosgen.proof.coqmodel import emit_model, render_node_file
from pyrosgen.proof.modeltext import (
    MalformedModelText, ModelMismatch, compare_model_texts, model_text, parse_model_text,
)
from pyrosgen.ros.wrapper import render_wrapper
from pyrosgen.verify.wrapper_check import WrapperMismatch, check_wrapper

from support.frontend import LANDSHARK, REPO, at, diags, load, one, write

STAMPED = REPO / "examples" / "landshark" / "landshark_stamped.yaml"

BASE = """\
node: {name: stringer, period_ms: 20}
controller:
  name: Controller
  inputs: {name: Controller_U, fields: {In1: float64}}
  outputs: {name: Controller_Y, fields: {Out1: float64}}
topics:
  - {name: /cmd_in, direction: subscribe, type: geometry_msgs/TwistStamped, queue_size: 1}
  - {name: /cmd_out, direction: publish, type: geometry_msgs/TwistStamped, queue_size: 1, frame_id: base_link}
  - {name: /odom, direction: publish, type: nav_msgs/Odometry, queue_size: 1}
relations:
  inputs: [{topic: /cmd_in, field: twist.linear.x, input: In1}]
  outputs:
    - {output: Out1, topic: /cmd_out, field: twist.linear.x}
"""

#: The constant of /cmd_out, and where BASE writes it.
CONST = "frame_id: base_link"

#: ``base_link`` in UTF-8, as the model text writes it.
BASE_LINK = "98,97,115,101,95,108,105,110,107"


def with_const(const: str, text: str = BASE) -> str:
    """BASE with /cmd_out's constant replaced by ``const``."""
    assert CONST in text
    return text.replace(CONST, const)


def odom(const: str) -> str:
    """BASE with ``const`` on /odom (nav_msgs/Odometry) and none on /cmd_out."""
    return with_const("stamp: now").replace("type: nav_msgs/Odometry, queue_size: 1}",
                                            f"type: nav_msgs/Odometry, queue_size: 1, {const}}}")


def fields_of(model, name: str) -> list[tuple[str, str, str | None, int | None]]:
    return [(f.name, f.kind, f.prim or f.msg, f.array_len) for f in model.message(name).fields]


# --------------------------------------------------------------------------
# Accepted models


def test_frame_id_is_read(tmp_path):
    m = load(tmp_path, BASE)
    by_name = {t.name: t for t in m.topics}
    (c,) = by_name["/cmd_out"].strings
    assert (c.path, c.value, c.data, c.path_text) == (("header", "frame_id"), "base_link", b"base_link",
                                                      "header.frame_id")
    assert by_name["/cmd_in"].strings == () and by_name["/odom"].strings == ()
    assert m.strings == (("cmd_out", ("header", "frame_id"), b"base_link"),)


def test_the_string_struct_is_the_interface_with_coq(tmp_path):
    m = load(tmp_path, BASE)
    names = [t.name for t in m.messages]
    # before the first message that uses it
    assert names.index("ros_string128") < names.index("std_msgs/Header")
    assert fields_of(m, "ros_string128") == [("len", "prim", "uint32", None), ("truncated", "prim", "bool", None),
                                            ("data", "prim", "uint8", 128)]
    assert STRING_CAPACITY == 128 and string_type().c_name == "ros_string128"
    assert string_type(16).fields[2].array_len == 16 and string_type(16).name == "ros_string16"
    # the field is carried in the type that defines it, so in every topic of that type
    assert fields_of(m, "std_msgs/Header") == [("seq", "prim", "uint32", None), ("stamp", "msg", "time", None),
                                              ("frame_id", "msg", "ros_string128", None)]
    # Odometry's other string is named by no constant: dropped
    assert [f.name for f in m.message("nav_msgs/Odometry").fields] == ["header", "pose", "twist"]
    # a subscribed topic of the type carries it too (the wrapper converts it)
    assert any(str(p) == "header.frame_id.data[127]" for p in m.leaf_paths("geometry_msgs/TwistStamped"))


def test_strings_on_odometry(tmp_path):
    text = odom("strings: {child_frame_id: base_link, header.frame_id: odom}")
    m = load(tmp_path, text)
    assert m.strings == (("odom", ("child_frame_id",), b"base_link"), ("odom", ("header", "frame_id"), b"odom"))
    assert [f.name for f in m.message("nav_msgs/Odometry").fields] == ["header", "child_frame_id", "pose", "twist"]


def test_order_is_topic_order_then_the_models(tmp_path):
    text = odom("strings: {child_frame_id: b}, frame_id: a").replace("stamp: now", "strings: {header.frame_id: c}")
    m = load(tmp_path, text)
    # /cmd_out before /odom; in /odom, strings before frame_id as written
    assert m.strings == (("cmd_out", ("header", "frame_id"), b"c"), ("odom", ("child_frame_id",), b"b"),
                         ("odom", ("header", "frame_id"), b"a"))


def test_empty_non_ascii_and_longest_constants(tmp_path):
    m = load(tmp_path, with_const("frame_id: ''"))
    assert m.strings[0][2] == b""
    m = load(tmp_path, with_const("frame_id: 'bäse ☃'"))
    assert m.strings[0][2] == "bäse ☃".encode()
    # letters, symbols, marks and spaces of any script are printable (rule
    # 4.14 refuses categories Cc, Cf, Cs, Co, Cn, Zl, Zp only)
    m = load(tmp_path, with_const('frame_id: "ロボット 😀\\u00a0e\\u0301"'))
    assert m.strings[0][2] == "ロボット 😀\u00a0e\u0301".encode()
    longest = "é" * 64  # 128 bytes
    m = load(tmp_path, with_const(f"frame_id: '{longest}'"))
    assert len(m.strings[0][2]) == 128
    m = load(tmp_path, with_const("frame_id: 'a b/c#d:e'"))
    assert m.strings[0][2] == b"a b/c#d:e"
    # text that YAML reads otherwise, quoted
    assert load(tmp_path, with_const("frame_id: '1'")).strings[0][2] == b"1"


def _fleet(tmp_path: Path) -> None:
    """Custom messages with strings in nested messages, fixed-size and
    variable-length arrays."""
    d = tmp_path / "msgs" / "fleet_msgs" / "msg"
    d.mkdir(parents=True)
    (d / "Leg.msg").write_text("Header header\nstring label\nfloat64 speed\n")
    (d / "Convoy.msg").write_text("Header header\nLeg[2] legs\nLeg[] spare\nstring[3] tags\nstring[] notes\nfloat64 x\n")
    (d / "Tag.msg").write_text("string frame_id\nuint32 seq\n")
    (d / "Odd.msg").write_text("Tag header\nfloat64 x\n")


CONVOY = """\
node: {name: convoy, period_ms: 20}
controller:
  name: Controller
  inputs: {name: Controller_U, fields: {In1: float64}}
  outputs: {name: Controller_Y, fields: {Out1: float64}}
msg_paths: [msgs]
topics:
  - {name: /convoy_in, direction: subscribe, type: fleet_msgs/Convoy, queue_size: 1}
  - {name: /convoy_out, direction: publish, type: fleet_msgs/Convoy, queue_size: 1,
     STRINGS}
relations:
  inputs: [{topic: /convoy_in, field: x, input: In1}]
  outputs: [{output: Out1, topic: /convoy_out, field: x}]
"""


def test_nested_through_a_fixed_size_array(tmp_path):
    _fleet(tmp_path)
    text = CONVOY.replace("STRINGS", 'frame_id: map, strings: {"legs[1].label": second, '
                                     '"legs[0].header.frame_id": leg0}')
    m = load(tmp_path, text)
    assert m.strings == (("convoy_out", ("header", "frame_id"), b"map"),
                         ("convoy_out", ("legs", 1, "label"), b"second"),
                         ("convoy_out", ("legs", 0, "header", "frame_id"), b"leg0"))
    assert [f.name for f in m.message("fleet_msgs/Leg").fields] == ["header", "label", "speed"]
    # the arrays of strings and the variable-length arrays stay dropped
    assert [f.name for f in m.message("fleet_msgs/Convoy").fields] == ["header", "legs", "x"]
    lines = model_text(m).splitlines()
    assert lines[-3:] == ["string convoy_out header.frame_id 109,97,112",
                          "string convoy_out legs[1].label 115,101,99,111,110,100",
                          "string convoy_out legs[0].header.frame_id 108,101,103,48"]
    assert emit_model(m).strings[1][1] == '[PField "legs"; PIndex 1; PField "label"]'


def test_strings_stay_dropped_without_constants(tmp_path):
    """LandShark names no string: its structs, model text and Coq text are
    what they were (no ros_string128, Header without frame_id)."""
    m = load_model(LANDSHARK)
    assert "ros_string128" not in [t.name for t in m.messages]
    assert [f.name for f in m.message("std_msgs/Header").fields] == ["seq", "stamp"]
    assert m.strings == () and all(t.strings == () for t in m.topics)
    text = model_text(m)
    assert "ros_string128" not in text and not any(ln.startswith("string ") for ln in text.splitlines())
    v = render_node_file(m, ddc_available=True)
    assert "ros_string128" not in v and "nm_strings :=\n      []\n  |}" in v
    # a model whose constant is on Odometry's child_frame_id leaves TwistStamped's header alone
    m = load(tmp_path, odom("strings: {child_frame_id: base}"))
    assert [f.name for f in m.message("std_msgs/Header").fields] == ["seq", "stamp"]
    assert [f.name for f in m.message("nav_msgs/Odometry").fields] == ["header", "child_frame_id", "pose", "twist"]


def test_the_example_sends_its_command_in_base_link():
    m = load_model(STAMPED)
    assert m.strings == (("landshark_control_base_velocity", ("header", "frame_id"), b"base_link"),)
    assert model_text(m).splitlines()[-1] == f"string landshark_control_base_velocity header.frame_id {BASE_LINK}"


# --------------------------------------------------------------------------
# The model text and the Coq text


def test_model_text_round_trip(tmp_path):
    text = model_text(load(tmp_path, odom("strings: {child_frame_id: '', header.frame_id: 'ä'}")))
    lines = text.splitlines()
    assert lines[-2:] == ["string odom child_frame_id -", "string odom header.frame_id 195,164"]
    # the string lines come after the stamp lines
    assert lines.index("stamp cmd_out header.stamp") < lines.index("string odom child_frame_id -")
    assert "message ros_string128" in lines
    assert lines[lines.index("message ros_string128") + 1:][:3] == [
        "field len uint32", "field truncated bool", "field data array 128 uint8"]
    pm = parse_model_text(text)
    assert pm.strings == [("odom", "child_frame_id", b""), ("odom", "header.frame_id", b"\xc3\xa4")]
    assert pm.messages["ros_string128"] == [("len", "uint32"), ("truncated", "bool"), ("data", "array 128 uint8")]


def test_model_text_comparison_sees_the_constant(tmp_path):
    text = model_text(load(tmp_path, BASE))
    for proved in (text.replace(BASE_LINK, BASE_LINK + ",0"),                # one byte more
                   text.replace(f" {BASE_LINK}\n", " -\n"),                  # emptied
                   text.replace("string cmd_out", "string odom"),            # another topic
                   text.replace(f"string cmd_out header.frame_id {BASE_LINK}\n", "")):  # dropped
        with pytest.raises(ModelMismatch) as info:
            compare_model_texts(text, proved, vfile="stringer.v")
        assert "string" in "\n".join(info.value.lines)


@pytest.mark.parametrize("line", [
    "string cmd_out header.frame_id 256",
    "string cmd_out header.frame_id 1,,2",
    "string cmd_out header.frame_id 01",
    "string cmd_out header.frame_id -1",
    "string cmd_out header.frame_id 1, 2",
    "string cmd_out header.frame_id",
    "string cmd_out header.frame_id 1 2",
    "string cmd_out header.frame_id ",
])
def test_malformed_string_lines_are_refused(tmp_path, line):
    text = model_text(load(tmp_path, BASE))
    bad = text.replace(f"string cmd_out header.frame_id {BASE_LINK}", line)
    with pytest.raises(MalformedModelText):
        parse_model_text(bad)


def test_coq_field_and_definition_are_emitted(tmp_path):
    m = load(tmp_path, BASE)
    cm = emit_model(m)
    assert cm.strings == (('"cmd_out"', '[PField "header"; PField "frame_id"]',
                           "[98%Z; 97%Z; 115%Z; 101%Z; 95%Z; 108%Z; 105%Z; 110%Z; 107%Z]",
                           "/cmd_out header.frame_id = base_link"),)
    v = render_node_file(m, ddc_available=True)
    assert ('   mkmsgdef "ros_string128"\n     [("len", FTprim Puint32);\n      ("truncated", FTprim Pbool);\n'
            '      ("data", FTarray (FTprim Puint8) 128)];\n') in v
    assert v.index('mkmsgdef "ros_string128"') < v.index('mkmsgdef "std_msgs_Header"')
    assert '("frame_id", FTmsg "ros_string128")' in v
    # nm_strings is the last field of the record, after nm_stamp_from
    tail = v[v.index("nm_stamp_from :="):]
    assert tail.index("nm_strings :=") > 0
    assert ('    nm_strings :=\n      [(* /cmd_out header.frame_id = base_link *)\n'
            '       ("cmd_out", ([PField "header"; PField "frame_id"], '
            '[98%Z; 97%Z; 115%Z; 101%Z; 95%Z; 108%Z; 105%Z; 110%Z; 107%Z]))]\n  |}') in v
    assert emit_model(load(tmp_path, with_const("frame_id: ''"))).strings[0][2] == "[]"


def test_a_hostile_constant_cannot_leave_its_coq_comment(tmp_path):
    m = load(tmp_path, with_const('frame_id: "*) Axiom x : False. (*"'))
    comment = emit_model(m).strings[0][3]
    assert "*)" not in comment and "(*" not in comment and '"' not in comment
    v = render_node_file(m, ddc_available=True)
    assert "*) Axiom" not in v and f"(* {comment} *)" in v


# --------------------------------------------------------------------------
# Refusals: each at its place, rule 4.14


def test_subscribed_topic_has_no_constant(tmp_path):
    text = with_const("stamp: now").replace(
        "type: geometry_msgs/TwistStamped, queue_size: 1}\n  - {name: /cmd_out",
        "type: geometry_msgs/TwistStamped, queue_size: 1, frame_id: x}\n  - {name: /cmd_out", 1)
    line, col = at(text, "frame_id: x")
    assert one(tmp_path, text) == (line, col + len("frame_id: "), "topics[0].frame_id: topic '/cmd_in' is "
                                   "subscribed by the node; a constant string is for a published topic", "4.14")
    text = text.replace("frame_id: x", "strings: {header.frame_id: x}")
    line, col = at(text, "{header.frame_id: x}")
    assert one(tmp_path, text) == (line, col, "topics[0].strings: topic '/cmd_in' is subscribed by the node; "
                                              "a constant string is for a published topic", "4.14")


@pytest.mark.parametrize("value, got", [
    ("5", "int '5' (quote it if you mean the text)"),
    ("2.5", "float '2.5' (quote it if you mean the text)"),
    ("true", "boolean 'true' (quote it if you mean the text)"),
    ("2001-01-01", "date '2001-01-01' (quote it if you mean the text)"),
    ("~", "null (an empty value) (write '' for the empty string)"),
    ("null", "null (an empty value) (write '' for the empty string)"),
    ("[base_link]", "a list"),
    ("{a: b}", "a mapping"),
])
def test_value_must_be_a_string(tmp_path, value, got):
    text = with_const(f"frame_id: {value}")
    line, col = at(text, f"frame_id: {value}")
    assert one(tmp_path, text) == (line, col + len("frame_id: "), f"topics[1].frame_id must be a string, got {got}",
                                   "4.14")
    text = odom(f"strings: {{child_frame_id: {value}}}")
    line, col = at(text, f"child_frame_id: {value}")
    assert one(tmp_path, text) == (line, col + len("child_frame_id: "),
                                   f"topics[2].strings['child_frame_id'] must be a string, got {got}", "4.14")


@pytest.mark.parametrize("value, problem", [
    ("'" + "a" * 129 + "'", "is 129 bytes long in UTF-8; a carried string holds at most 128 bytes"),
    ("'" + "é" * 64 + "a'", "is 129 bytes long in UTF-8; a carried string holds at most 128 bytes"),
    ('"a\\tb"', ": the string contains the control character U+0009 (character 2); a constant string holds "
                "printable text"),
    ('"\\n"', ": the string contains the control character U+000A (character 1); a constant string holds "
              "printable text"),
    ('"nul\\0"', ": the string contains the control character U+0000 (character 4); a constant string holds "
                 "printable text"),
    ('"\\x7f"', ": the string contains the control character U+007F (character 1); a constant string holds "
                "printable text"),
    ('"\\e"', ": the string contains the control character U+001B (character 1); a constant string holds "
              "printable text"),
    ('"a\\ud800"', " is not valid Unicode text: it holds the lone surrogate U+D800 (character 2)"),
    # issue 30: C1 controls, invisible format characters (a bidi override,
    # a byte-order mark, a zero-width space), line and paragraph
    # separators, private-use and unassigned code points (rule 4.14)
    ('"a\\x85"', ": the string contains the control character U+0085 (character 2); a constant string holds "
                 "printable text"),
    ('"\\u009b"', ": the string contains the control character U+009B (character 1); a constant string holds "
                  "printable text"),
    ('"base\\u202elink"', ": the string contains the invisible format character U+202E (character 5); a "
                          "constant string holds printable text"),
    ('"\\ufeffbase"', ": the string contains the invisible format character U+FEFF (character 1); a constant "
                      "string holds printable text"),
    ('"a\\u200bb"', ": the string contains the invisible format character U+200B (character 2); a constant "
                    "string holds printable text"),
    ('"a\\u2028b"', ": the string contains the line separator U+2028 (character 2); a constant string holds "
                    "printable text"),
    ('"a\\u2029b"', ": the string contains the paragraph separator U+2029 (character 2); a constant string "
                    "holds printable text"),
    ('"a\\ufffe"', ": the string contains the unassigned code point U+FFFE (character 2); a constant string "
                   "holds printable text"),
    ('"\\uffff"', ": the string contains the unassigned code point U+FFFF (character 1); a constant string "
                  "holds printable text"),
    ('"\\ue000"', ": the string contains the private-use character U+E000 (character 1); a constant string "
                  "holds printable text"),
])
def test_value_is_printable_text_of_at_most_128_bytes(tmp_path, value, problem):
    text = with_const(f"frame_id: {value}")
    line, col = at(text, f"frame_id: {value}")
    sep = "" if problem.startswith((":", " ")) else " "
    assert one(tmp_path, text) == (line, col + len("frame_id: "), f"topics[1].frame_id{sep}{problem}", "4.14")


_TS = "(topic '/cmd_out', geometry_msgs/TwistStamped)"


@pytest.mark.parametrize("key, problem", [
    ("header.frame_idd", "field path 'header.frame_idd': message type std_msgs/Header (at 'header') has no field "
                         "'frame_idd' (did you mean 'frame_id'?)"),
    ("heder.frame_id", "field path 'heder.frame_id': message type geometry_msgs/TwistStamped has no field 'heder' "
                       "(did you mean 'header'?)"),
    ("header.seq", "field path 'header.seq': 'header.seq' is an uint32, not a string"),
    ("twist.linear.x", "field path 'twist.linear.x': 'twist.linear.x' is a float64, not a string"),
    ("header.stamp", "field path 'header.stamp': 'header.stamp' is a whole sub-message (time), not a string field"),
    ("header", "field path 'header': 'header' is a whole sub-message (std_msgs/Header), not a string field; "
               "e.g. 'header.frame_id'"),
    ('"header.frame_id[0]"', "field path 'header.frame_id[0]': 'header.frame_id' is a string, not an array: a "
                             "constant sets the whole string (name 'header.frame_id')"),
    ("header.frame_id.len", "field path 'header.frame_id.len': 'header.frame_id' is a string; a constant sets the "
                            "whole string, a path does not go inside it (len, truncated and data are fields of its "
                            "C struct, not of the ROS message)"),
    ("header.frame_id.truncated", "field path 'header.frame_id.truncated': 'header.frame_id' is a string; a "
                                  "constant sets the whole string, a path does not go inside it (len, truncated "
                                  "and data are fields of its C struct, not of the ROS message)"),
    ('"header.frame_id.data[3]"', "field path 'header.frame_id.data[3]': 'header.frame_id' is a string; a constant "
                                  "sets the whole string, a path does not go inside it (len, truncated and data "
                                  "are fields of its C struct, not of the ROS message)"),
    ("header..frame_id", "field path 'header..frame_id' is malformed: expected field names, each optionally "
                         "followed by [INDEX], separated by '.'"),
    ("5", "field path '5' is malformed: expected field names, each optionally followed by [INDEX], separated by '.'"),
])
def test_path_names_a_string_field(tmp_path, key, problem):
    text = with_const(f"strings: {{{key}: base_link}}")
    line, col = at(text, key)
    shown = key.strip('"')
    assert one(tmp_path, text) == (line, col, f"topics[1].strings['{shown}']: {problem} {_TS}", "4.14")


@pytest.mark.parametrize("key, problem", [
    ('"spare[0].label"', "field path 'spare[0].label': 'spare' is a variable-length array (fleet_msgs/Leg[]); a constant "
                         "string is not reached through a variable-length array"),
    ("notes", "field path 'notes': 'notes' is a variable-length array (string[]); a constant string is not "
              "reached through a variable-length array"),
    ('"tags[1]"', "field path 'tags[1]': 'tags' is an array of strings (string[3]); a constant is given to a "
                  "single string field"),
    ("legs.label", "field path 'legs.label': 'legs' is an array (fleet_msgs/Leg[2]); name one element with a constant "
                   "index, e.g. 'legs[0].label'"),
    ('"legs[2].label"', "field path 'legs[2].label': index 2 is out of range for 'legs' (fleet_msgs/Leg[2]; valid indices "
                        "are 0..1)"),
    ('"x[0]"', "field path 'x[0]': 'x' is not an array (it is a float64), it cannot be indexed"),
])
def test_path_through_arrays(tmp_path, key, problem):
    _fleet(tmp_path)
    text = CONVOY.replace("STRINGS", f"strings: {{{key}: s}}")
    line, col = at(text, key)
    assert one(tmp_path, text) == (line, col, f"topics[1].strings['{key.strip(chr(34))}']: {problem} "
                                              "(topic '/convoy_out', fleet_msgs/Convoy)", "4.14")


@pytest.mark.parametrize("msg_type, field, shown", [
    ("geometry_msgs/Twist", "linear.x", "geometry_msgs/Twist"),
    ("fleet_msgs/Odd", "x", "fleet_msgs/Odd"),   # its header is not a std_msgs/Header
])
def test_frame_id_needs_a_std_msgs_header(tmp_path, msg_type, field, shown):
    _fleet(tmp_path)
    text = with_const("frame_id: base_link").replace(
        "{name: /cmd_out, direction: publish, type: geometry_msgs/TwistStamped",
        f"{{name: /cmd_out, direction: publish, type: {msg_type}")
    text = text.replace("{output: Out1, topic: /cmd_out, field: twist.linear.x}",
                        f"{{output: Out1, topic: /cmd_out, field: {field}}}")
    text = text.replace("relations:", "msg_paths: [msgs]\nrelations:")
    line, col = at(text, CONST)
    assert one(tmp_path, text) == (line, col + len("frame_id: "), f"topics[1].frame_id: message type {shown} has "
                                   "no field 'header' of type std_msgs/Header (frame_id sets header.frame_id; "
                                   f"strings sets any other string field) (topic '/cmd_out', {shown})", "4.14")
    # the Odd header's string is reached through strings
    if msg_type == "fleet_msgs/Odd":
        m = load(tmp_path, text.replace(CONST, "strings: {header.frame_id: base_link}"))
        assert m.strings == (("cmd_out", ("header", "frame_id"), b"base_link"),)
        assert [f.name for f in m.message("fleet_msgs/Tag").fields] == ["frame_id", "seq"]


def test_a_field_is_named_once(tmp_path):
    text = with_const("frame_id: a, strings: {header.frame_id: b}")
    line, col = at(text, "header.frame_id: b")
    fline = at(text, "frame_id: a")[0]
    assert one(tmp_path, text) == (line, col, "topics[1].strings['header.frame_id']: field 'header.frame_id' of "
                                   f"topic '/cmd_out' already has a constant (topics[1].frame_id, line {fline})",
                                   "4.14")
    _fleet(tmp_path)
    text = CONVOY.replace("STRINGS", 'strings: {"legs[1].label": a, "legs[01].label": b}')
    line, col = at(text, '"legs[01].label"')
    # legs[01] was read as legs[1] and so found a second constant of that
    # field; an index with a leading zero is now refused (rule 4.6: C
    # reads 010 as 8), before any comparison
    assert one(tmp_path, text)[:3] == (line, col, "topics[1].strings['legs[01].label']: field path "
                                       "'legs[01].label': index [01] has a leading zero (C reads 010 as octal 8); "
                                       "write the index in plain decimal, [1] (topic '/convoy_out', "
                                       "fleet_msgs/Convoy)")


def test_strings_is_a_mapping(tmp_path):
    text = with_const("strings: [header.frame_id, base_link]")
    line, col = at(text, "[header.frame_id, base_link]")
    assert one(tmp_path, text) == (line, col, "topics[1].strings must be a mapping of field paths to strings, "
                                              "got a list", "4.14")
    # an empty mapping gives no constant
    assert load(tmp_path, with_const("strings: {}")).strings == ()


def test_misspelt_keys_get_suggestions(tmp_path):
    found = diags(tmp_path, with_const("frame_idd: base_link"))
    assert any("unknown key 'frame_idd' (did you mean 'frame_id'?)" in msg and rule == "4.4"
               for _, _, msg, rule in found), found
    found = diags(tmp_path, with_const("string: {header.frame_id: x}"))
    assert any("unknown key 'string' (did you mean 'strings'?)" in msg for _, _, msg, _ in found), found


_REL_PROBLEM = ("is a string; strings are not carried by the glue to or from the controller (a published topic "
                "gives a string field a constant with its frame_id or strings key)")


@pytest.mark.parametrize("field", ["header.frame_id", "header.frame_id.len", "header.frame_id.truncated",
                                   '"header.frame_id.data[3]"'])
def test_relations_never_name_a_string(tmp_path, field):
    """No relation names a whole string or the fields of its C struct
    (/cmd_out: the Header of TwistStamped carries frame_id here): an
    input relation reads a string byte by byte (``header.frame_id[0]``,
    rule 4.15, tests/frontend/test_sequences.py), an output relation
    writes one byte by byte with its length
    (tests/frontend/test_published_sequences.py)."""
    text = BASE.replace("fields: {Out1: float64}", "fields: {Out1: float64, Len: uint32}")
    text = text.replace("    - {output: Out1, topic: /cmd_out, field: twist.linear.x}",
                        "    - {output: Out1, topic: /cmd_out, field: twist.linear.x}\n"
                        f"    - {{output: Len, topic: /cmd_out, field: {field}}}")
    line, col = at(text, field)
    shown = field.strip('"')
    got = one(tmp_path, text)
    assert got[:2] == (line, col) and got[3] == "4.15", got
    assert got[2].startswith(f"relations.outputs[1].field: field path '{shown}': 'header.frame_id' is a string; "), got
    assert got[2].endswith(_TS), got
    if shown == "header.frame_id":   # a published string is written byte by byte (rule 4.15)
        assert ("an output relation writes one of its bytes ('header.frame_id[0]', a uint8) or its length "
                "(derived: length, from a uint32 output)") in got[2], got
    else:
        assert "a path does not go inside it" in got[2] and "or use derived: length (" in got[2], got
    text = BASE.replace("fields: {In1: float64}", "fields: {In1: float64, L: uint32}")
    text = text.replace("inputs: [{topic: /cmd_in, field: twist.linear.x, input: In1}]",
                        f"inputs: [{{topic: /cmd_in, field: twist.linear.x, input: In1}}, "
                        f"{{topic: /cmd_in, field: {field}, input: L}}]")
    line, col = at(text, f"field: {field}")
    got = one(tmp_path, text)
    assert got[:2] == (line, col + len("field: ")) and got[3] == "4.15", got
    assert got[2].startswith(f"relations.inputs[1].field: field path '{shown}': 'header.frame_id' is a string; "), got
    if shown == "header.frame_id":
        assert "a relation reads one of its bytes ('header.frame_id[0]', a uint8)" in got[2], got
    else:
        assert "a path does not go inside it" in got[2] and "fields of its C struct" in got[2], got


def test_every_problem_is_reported_at_once(tmp_path):
    text = odom("frame_id: 5, strings: {child_frame_idd: x, header.frame_id: '\\t'}").replace(
        "stamp: now", "frame_id: " + "x" * 200)
    found = diags(tmp_path, text)
    assert [rule for *_, rule in found] == ["4.14"] * 4
    assert [m.split(":")[0].split(" ")[0] for _, _, m, _ in found] == [
        "topics[1].frame_id", "topics[2].frame_id", "topics[2].strings['child_frame_idd']",
        "topics[2].strings['header.frame_id']"]


# --------------------------------------------------------------------------
# Hostile input


def test_hostile_inputs_are_clean_errors(tmp_path, capsys):
    """A 10 MB string, a 1 MB one, binary garbage, keys that are not
    strings: exit 1, a one-line message per problem citing its rule,
    never a traceback, and nothing written by generate."""
    cases = {
        "ten_mb": with_const("frame_id: '" + "a" * 10_000_000 + "'"),
        "one_mb": with_const("frame_id: '" + "a" * 1_000_000 + "'"),
        "binary": with_const("frame_id: 'a\x01\x02'"),
        "complex_key": with_const("strings: {? [header, frame_id] : x}"),
        "mapping_key": with_const("strings: {? {a: 1} : x}"),
        "int_key": with_const("strings: {7: x}"),
        "huge_key": with_const("strings: {" + "a" * 500_000 + ": x}"),
    }
    garbage = bytes(range(256)) * 8
    out = tmp_path / "out"
    for name, text in cases.items():
        p = tmp_path / f"{name}.yaml"
        p.write_text(text, encoding="utf-8")
        for argv in (["check", str(p)], ["generate", str(p), "-o", str(out), "-q"]):
            code = cli.main(argv)
            o, err = capsys.readouterr()
            assert code == 1, (name, err[:300])
            assert "Traceback" not in err and "internal error" not in err, err[:500]
            assert re.search(r"\[rule 4\.1\d?\]", err), (name, err[:300])
            assert max(len(line) for line in err.splitlines()) < 1000, name
            assert not out.exists()
    raw = tmp_path / "garbage.yaml"
    raw.write_bytes(BASE.replace(CONST, "frame_id: '").encode() + garbage + b"'")
    code = cli.main(["check", str(raw)])
    err = capsys.readouterr().err
    assert code == 1 and "Traceback" not in err and "[rule 4.1]" in err


def test_a_struct_name_collision_is_refused(tmp_path):
    """A custom type whose C name could be the string struct's is refused,
    not silently merged: its package, ``ros``, is (rule 4.15)."""
    d = tmp_path / "msgs" / "ros" / "msg"
    d.mkdir(parents=True)
    (d / "string128.msg").write_text("uint32 n\n")
    text = BASE.replace("relations:", "msg_paths: [msgs]\nrelations:").replace(
        "type: nav_msgs/Odometry", "type: ros/string128")
    found = diags(tmp_path, text)
    assert any(rule == "4.15" and "holds the package 'ros'" in msg and "ros_string<N>" in msg
               for _, _, msg, rule in found), found


# --------------------------------------------------------------------------
# The Python side of the running node


def test_check_prints_the_constants(tmp_path, capsys):
    p = write(tmp_path, odom("strings: {child_frame_id: 'bäse'}").replace("stamp: now", CONST))
    assert cli.main(["check", str(p)]) == 0
    out = capsys.readouterr().out
    assert out.rstrip().endswith("; 2 constant strings: /cmd_out header.frame_id = 'base_link', "
                                 "/odom child_frame_id = 'b\\xe4se'"), out


def test_diagram_shows_the_constants(tmp_path):
    from pyrosgen.diagram import render_dot

    dot = render_dot(load(tmp_path, with_const('frame_id: "a<b>&\\"c"')))
    assert "<br/>header.frame_id = &quot;a&lt;b&gt;&amp;&quot;c&quot;>" in dot


def _wrapper(m) -> str:
    return render_wrapper(m)[f"{m.name}_ros.cpp"]


def test_wrapper_converts_carried_strings(tmp_path):
    m = load(tmp_path, BASE)
    cpp = _wrapper(m)
    assert ("inline void to_c(const std::string &r, struct ros_string128 *c)\n{\n"
            "    const std::size_t n = r.size();\n"
            "    const std::size_t len = std::min<std::size_t>(n, 128);\n"
            "    c->len = static_cast<unsigned int>(len);\n"
            "    c->truncated = n > 128 ? 1 : 0;\n"
            "    std::memcpy(c->data, r.data(), len);\n"
            "    std::memset(c->data + len, 0, 128 - len);\n}\n") in cpp
    assert ("inline void from_c(const struct ros_string128 *c, std::string &r)\n{\n"
            "    r.assign(reinterpret_cast<const char *>(c->data), std::min<std::size_t>(c->len, 128));\n}\n") in cpp
    # the Header converters go through them
    assert "    to_c(r.frame_id, &c->frame_id);\n" in cpp and "    from_c(&c->frame_id, r.frame_id);\n" in cpp
    check_wrapper(cpp, model_text(m), wrapper_name="stringer_ros.cpp")
    # LandShark's wrapper has no string conversion
    ls = load_model(LANDSHARK)
    assert "std::string &r" not in _wrapper(ls)
    check_wrapper(_wrapper(ls), model_text(ls), wrapper_name="landshark_controller_ros.cpp")


@pytest.mark.parametrize("name, old, new", [
    ("no clamp when received", "std::min<std::size_t>(n, 128)", "n"),
    ("no clamp when published", "std::min<std::size_t>(c->len, 128)", "c->len"),
    ("truncated never set", "c->truncated = n > 128 ? 1 : 0;", "c->truncated = 0;"),
    ("garbage past len", "    std::memset(c->data + len, 0, 128 - len);\n", ""),
    ("another capacity", "std::min<std::size_t>(n, 128)", "std::min<std::size_t>(n, 127)"),
    ("published from data + 1", "reinterpret_cast<const char *>(c->data)", "reinterpret_cast<const char *>(c->data + 1)"),
])
def test_wrapper_check_refuses_a_corrupted_string_conversion(tmp_path, name, old, new):
    m = load(tmp_path, BASE)
    cpp = _wrapper(m)
    assert old in cpp
    with pytest.raises(WrapperMismatch) as info:
        check_wrapper(cpp.replace(old, new, 1), model_text(m), wrapper_name="stringer_ros.cpp")
    assert any("rule 4.14" in line for line in info.value.lines), info.value.lines


def test_wrapper_check_refuses_strings_the_proof_does_not_have(tmp_path):
    """A wrapper converting a string the proved model does not carry (its
    model text has no ros_string128) is refused, and so is a second
    conversion."""
    m = load(tmp_path, BASE)
    cpp = _wrapper(m)
    plain = load(tmp_path, with_const("stamp: now"))
    with pytest.raises(WrapperMismatch) as info:
        check_wrapper(cpp, model_text(plain), wrapper_name="stringer_ros.cpp")
    assert any("not a string struct of the proved model" in line for line in info.value.lines), info.value.lines
    extra = cpp.replace("inline void from_c(const struct ros_string128 *c, std::string &r);\n",
                        "inline void from_c(const struct ros_string128 *c, std::string &r);\n"
                        "inline void to_c(const std::string &r, struct ros_string128 *c, int);\n")
    with pytest.raises(WrapperMismatch) as info:
        check_wrapper(extra, model_text(m), wrapper_name="stringer_ros.cpp")
    assert any("string conversions of struct ros_string128" in line for line in info.value.lines)


def test_acsl_contracts_state_the_constant(tmp_path):
    from pyrosgen.verify.acsl import contracts

    m = load(tmp_path, with_const("frame_id: 'ab'"))
    (og,) = [c for c in contracts(m) if c.name == "output_glue_cmd_out"]
    assert "command->header.frame_id.len == 2" in og.ensures
    assert "command->header.frame_id.data[0] == 97" in og.ensures
    assert "command->header.frame_id.data[1] == 98" in og.ensures
    assert "command->header.frame_id.data[2] == 0" in og.ensures
    assert "command->header.frame_id.truncated == 0" in og.ensures

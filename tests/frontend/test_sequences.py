"""Variable-length arrays and strings into the controller (DESIGN.md rule
4.15): an input relation reads an element of a subscribed message's
``T[]`` (``ranges[540]``) or a byte of its ``string``
(``header.frame_id[0]``), and ``derived: length`` / ``derived:
truncated`` with a ``field`` the received length and whether it was
longer than the maximum; a topic's ``max_length: {<field path>: N}``
sets the maximum (default 128).  Such a field is carried as the bounded
struct ``ros_seq_<T>_<N>`` / ``ros_string<N>`` (``len``, ``truncated``,
``data[N]``), and the relations are ordinary input relations on its
leaves (``ranges.data[540]``, ``ranges.len``, ``ranges.truncated``).

The accepted models and their objects (structs, relations, the model
text, the emitted Coq); every refusal with its message, line, column and
rule; LandShark unchanged; and the Python side of the running node: the
wrapper's conversions and the wrapper check that holds them to the
letter (a wrapper without the clamp, the zero fill or the truncated flag
is refused), the differential-test harness's clamp, ``check`` and
``diagram``."""

from __future__ import annotations

from pathlib import Path

import pytest

from pyrosgen import cli, load_model
from pyrosgen.frontend.msgmodel import (
    DEFAULT_MAX_LENGTH, MAX_SEQUENCE_LENGTH, bounded_type, is_seq_type, seq_type, seq_type_name,
)
from pyrosgen.proof.coqmodel import emit_model, render_node_file
from pyrosgen.proof.modeltext import model_text, parse_model_text
from pyrosgen.ros.wrapper import render_wrapper
from pyrosgen.verify.wrapper_check import WrapperMismatch, check_wrapper

from support.frontend import LANDSHARK, REPO, at, diags, load, one, write

LASER_GUARD = REPO / "examples" / "laser_guard" / "laser_guard.yaml"

BASE = """\
node: {name: scanner, period_ms: 20}
controller:
  name: Controller
  inputs: {name: Controller_U, fields: {R: float32, NR: uint32, TR: bool}}
  outputs: {name: Controller_Y, fields: {Out1: float64}}
topics:
  - {name: /scan, direction: subscribe, type: sensor_msgs/LaserScan, queue_size: 1, max_length: {ranges: 1081}}
  - {name: /cmd, direction: publish, type: geometry_msgs/Twist, queue_size: 1}
relations:
  inputs:
    - {topic: /scan, field: "ranges[540]", input: R}
    - {topic: /scan, field: ranges, derived: length, input: NR}
    - {topic: /scan, field: ranges, derived: truncated, input: TR}
  outputs:
    - {output: Out1, topic: /cmd, field: linear.x}
"""

_SCAN = "(topic '/scan', sensor_msgs/LaserScan)"


def fields_of(model, name: str) -> list[tuple[str, str, str | None, int | None]]:
    return [(f.name, f.kind, f.prim or f.msg, f.array_len) for f in model.message(name).fields]


def rels(model) -> list[tuple[str, tuple, str, str]]:
    return [(r.input_field, r.path.steps, r.path.prim, r.field_text) for r in model.input_relations]


# --------------------------------------------------------------------------
# Accepted models


def test_a_sequence_element_its_length_and_truncation_are_leaf_relations(tmp_path):
    m = load(tmp_path, BASE)
    assert rels(m) == [
        ("R", ("ranges", "data", 540), "float32", "ranges[540]"),
        ("NR", ("ranges", "len"), "uint32", "ranges (length)"),
        ("TR", ("ranges", "truncated"), "bool", "ranges (truncated)"),
    ]
    # ordinary input relations: no derived input, no timed topic
    assert m.derived_relations == () and m.timed_topics == ()
    names = [t.name for t in m.messages]
    # the struct comes before the message that uses it
    assert names.index("ros_seq_float32_1081") < names.index("sensor_msgs/LaserScan")
    assert fields_of(m, "ros_seq_float32_1081") == [("len", "prim", "uint32", None),
                                                   ("truncated", "prim", "bool", None),
                                                   ("data", "prim", "float32", 1081)]
    scan = fields_of(m, "sensor_msgs/LaserScan")
    assert ("ranges", "msg", "ros_seq_float32_1081", None) in scan
    # what no relation names stays dropped: intensities, the header's frame_id
    assert [f[0] for f in scan] == ["header", "angle_min", "angle_max", "angle_increment", "time_increment",
                                    "scan_time", "range_min", "range_max", "ranges"]
    assert [f[0] for f in fields_of(m, "std_msgs/Header")] == ["seq", "stamp"]
    assert m.bounded_fields == (("sensor_msgs/LaserScan", "ranges", seq_type("float32", 1081)),)
    assert len(m.leaf_paths("sensor_msgs/LaserScan")) == 3 + 7 + 2 + 1081


def test_the_sequence_struct(tmp_path):
    t = seq_type("float32", 1081)
    assert (t.name, t.c_name, t.seq_of, t.capacity, t.is_seq, t.is_string, t.is_bounded, t.is_pseudo) == (
        "ros_seq_float32_1081", "ros_seq_float32_1081", ("float32", 1081), 1081, True, False, True, True)
    assert t.cpp_name == "std::vector<float>"
    assert seq_type("bool", 3).cpp_name == "std::vector<uint8_t>"   # ROS 1's bool[] is a uint8_t vector
    assert seq_type("int64", 3).cpp_name == "std::vector<int64_t>"
    assert seq_type_name("uint8", 128) == "ros_seq_uint8_128" and is_seq_type("ros_seq_uint8_128")
    assert not is_seq_type("ros_seq_string_4") and not is_seq_type("ros_seq_float32_0")
    assert bounded_type("ros_seq_int16_7") == seq_type("int16", 7)
    assert bounded_type("ros_string16").capacity == 16
    assert (DEFAULT_MAX_LENGTH, MAX_SEQUENCE_LENGTH) == (128, 65536)


def test_the_default_maximum_is_128(tmp_path):
    m = load(tmp_path, BASE.replace(", max_length: {ranges: 1081}", "").replace("ranges[540]", "ranges[127]"))
    assert "ros_seq_float32_128" in [t.name for t in m.messages]
    assert rels(m)[0] == ("R", ("ranges", "data", 127), "float32", "ranges[127]")


def test_model_text_prints_the_leaves(tmp_path):
    m = load(tmp_path, BASE)
    lines = model_text(m).splitlines()
    i = lines.index("message ros_seq_float32_1081")
    assert lines[i:i + 4] == ["message ros_seq_float32_1081", "field len uint32", "field truncated bool",
                              "field data array 1081 float32"]
    assert i < lines.index("message sensor_msgs_LaserScan")
    assert "field ranges msg ros_seq_float32_1081" in lines
    assert [ln for ln in lines if ln.startswith("input_relation")] == [
        "input_relation scan ranges.data[540] R", "input_relation scan ranges.len NR",
        "input_relation scan ranges.truncated TR"]
    # the text reads back
    pm = parse_model_text(model_text(m))
    assert pm.messages["ros_seq_float32_1081"] == [("len", "uint32"), ("truncated", "bool"),
                                                  ("data", "array 1081 float32")]


def test_emitted_coq(tmp_path):
    m = load(tmp_path, BASE)
    e = emit_model(m)
    names = [d.name for d in e.msgs]
    seq = e.msgs[names.index('"ros_seq_float32_1081"')]
    assert seq.fields == (('"len"', "FTprim Puint32"), ('"truncated"', "FTprim Pbool"),
                          ('"data"', "FTarray (FTprim Pfloat32) 1081"))
    assert names.index('"ros_seq_float32_1081"') < names.index('"sensor_msgs_LaserScan"')
    scan = e.msgs[names.index('"sensor_msgs_LaserScan"')]
    assert ('"ranges"', 'FTmsg "ros_seq_float32_1081"') in scan.fields
    assert [(t, p, i) for t, p, i, _, _ in e.inrels] == [
        ('"scan"', '[PField "ranges"; PField "data"; PIndex 540]', '"R"'),
        ('"scan"', '[PField "ranges"; PField "len"]', '"NR"'),
        ('"scan"', '[PField "ranges"; PField "truncated"]', '"TR"')]
    v = render_node_file(m, ddc_available=True)
    assert 'mkmsgdef "ros_seq_float32_1081"' in v or '"ros_seq_float32_1081"' in v
    assert 'mkinrel "scan" [PField "ranges"; PField "data"; PIndex 540] "R"' in v


def test_landshark_is_unchanged():
    m = load_model(LANDSHARK)
    assert [ln for ln in model_text(m).splitlines() if ln.startswith(("message", "field"))] == [
        "message ros_time", "field sec uint32", "field nsec uint32", "message std_msgs_Header",
        "field seq uint32", "field stamp msg ros_time", "message geometry_msgs_Vector3", "field x float64",
        "field y float64", "field z float64", "message geometry_msgs_Twist",
        "field linear msg geometry_msgs_Vector3", "field angular msg geometry_msgs_Vector3",
        "message geometry_msgs_TwistStamped", "field header msg std_msgs_Header",
        "field twist msg geometry_msgs_Twist"]
    assert m.bounded_fields == ()
    assert all(r.written is None and r.field_text == str(r.path) for r in m.input_relations)


def test_the_example(tmp_path):
    m = load_model(LASER_GUARD)
    assert [(r.input_field, str(r.path)) for r in m.input_relations] == [
        ("R538", "ranges.data[538]"), ("R539", "ranges.data[539]"), ("R540", "ranges.data[540]"),
        ("R541", "ranges.data[541]"), ("R542", "ranges.data[542]"), ("NR", "ranges.len"),
        ("TR", "ranges.truncated")]
    assert [f.name for f in m.controller.outputs.fields] == ["Vx"]
    cmd = m.topic("/cmd_vel")
    assert cmd.stamped and [(s.path_text, s.value) for s in cmd.strings] == [("header.frame_id", "base_link")]
    assert [b.name for _, _, b in m.bounded_fields] == ["ros_string128", "ros_seq_float32_1081"]


def test_a_string_byte_and_its_length(tmp_path):
    """``header.frame_id[0]`` is a uint8 input; ``derived: length`` and
    ``truncated`` work on strings too; ``max_length`` sets the string's
    capacity (``ros_string16``)."""
    text = BASE.replace("fields: {R: float32, NR: uint32, TR: bool}",
                        "fields: {R: float32, NR: uint32, TR: bool, F0: uint8, F15: uint8, FL: uint32, FT: bool}")
    text = text.replace("max_length: {ranges: 1081}", "max_length: {ranges: 1081, header.frame_id: 16}")
    text = text.replace("  outputs:\n", "    - {topic: /scan, field: \"header.frame_id[0]\", input: F0}\n"
                                         "    - {topic: /scan, field: \"header.frame_id[15]\", input: F15}\n"
                                         "    - {topic: /scan, field: header.frame_id, derived: length, input: FL}\n"
                                         "    - {topic: /scan, field: header.frame_id, derived: truncated, "
                                         "input: FT}\n  outputs:\n")
    m = load(tmp_path, text)
    assert rels(m)[3:] == [
        ("F0", ("header", "frame_id", "data", 0), "uint8", "header.frame_id[0]"),
        ("F15", ("header", "frame_id", "data", 15), "uint8", "header.frame_id[15]"),
        ("FL", ("header", "frame_id", "len"), "uint32", "header.frame_id (length)"),
        ("FT", ("header", "frame_id", "truncated"), "bool", "header.frame_id (truncated)")]
    assert ("frame_id", "msg", "ros_string16", None) in fields_of(m, "std_msgs/Header")
    assert fields_of(m, "ros_string16")[2] == ("data", "prim", "uint8", 16)
    # the default: 128 bytes
    m = load(tmp_path, BASE.replace("  outputs:\n", "    - {topic: /scan, field: header.frame_id, derived: length,"
                                                     " input: FL}\n  outputs:\n").replace(
        "TR: bool}", "TR: bool, FL: uint32}"))
    assert ("frame_id", "msg", "ros_string128", None) in fields_of(m, "std_msgs/Header")


def test_a_constant_string_with_a_max_length(tmp_path):
    """A published string's capacity is its field's max_length too: the
    constant must fit it."""
    text = BASE.replace("type: geometry_msgs/Twist, queue_size: 1}",
                        "type: geometry_msgs/TwistStamped, queue_size: 1, frame_id: base_link, "
                        "max_length: {header.frame_id: 9}}").replace("field: linear.x", "field: twist.linear.x")
    m = load(tmp_path, text)
    assert ("frame_id", "msg", "ros_string9", None) in fields_of(m, "std_msgs/Header")
    assert m.strings == (("cmd", ("header", "frame_id"), b"base_link"),)
    bad = text.replace("frame_id: 9}", "frame_id: 8}")
    assert one(tmp_path, bad) == (*at(bad, "base_link"), "topics[1].frame_id is 9 bytes long in UTF-8; a carried "
                                  "string holds at most 8 bytes (its field's max_length)", "4.14")


def test_a_sequence_shared_by_two_topics(tmp_path):
    """One struct per message type: a second LaserScan topic without a
    max_length gets the first one's; a published LaserScan carries the
    sequence too (its output glue zeroes it: an empty ranges)."""
    text = BASE.replace("  - {name: /cmd,", "  - {name: /scan2, direction: subscribe, type: sensor_msgs/LaserScan, "
                                          "queue_size: 1}\n"
                                          "  - {name: /scan_out, direction: publish, type: sensor_msgs/LaserScan, "
                                          "queue_size: 1}\n  - {name: /cmd,")
    text = text.replace("field: ranges, derived: truncated", "field: ranges, derived: truncated").replace(
        "{topic: /scan, field: ranges, derived: length", "{topic: /scan2, field: ranges, derived: length")
    m = load(tmp_path, text)
    assert [t.msg_struct for t in m.topics[:3]] == ["sensor_msgs_LaserScan"] * 3
    assert [b.name for _, _, b in m.bounded_fields] == ["ros_seq_float32_1081"]
    assert rels(m)[1][:2] == ("NR", ("ranges", "len"))
    assert m.input_relations[1].topic.name == "/scan2"


def _custom(tmp_path: Path) -> None:
    d = tmp_path / "msgs" / "arm_msgs" / "msg"
    d.mkdir(parents=True)
    (d / "Joint.msg").write_text("string name\nfloat64[] position\nbool[] flags\n")
    (d / "Arm.msg").write_text("Header header\nJoint[2] joints\nJoint[] spare\nchar[] codes\nbyte[] deltas\n"
                               "int64[] ticks\nfloat64 x\n")


ARM = """\
node: {name: arm, period_ms: 20}
controller:
  name: Controller
  inputs: {name: Controller_U, fields: {IN}}
  outputs: {name: Controller_Y, fields: {Out1: float64}}
msg_paths: [msgs]
topics:
  - {name: /arm, direction: subscribe, type: arm_msgs/Arm, queue_size: 1MAX}
  - {name: /cmd, direction: publish, type: geometry_msgs/Twist, queue_size: 1}
relations:
  inputs:
RELS
  outputs:
    - {output: Out1, topic: /cmd, field: linear.x}
"""


def arm(inputs: str, rels_: list[str], max_length: str = "") -> str:
    return (ARM.replace("IN", inputs).replace("MAX", f", max_length: {max_length}" if max_length else "")
            .replace("RELS", "\n".join(f"    - {r}" for r in rels_)))


def test_nested_sequences_and_every_element_type(tmp_path):
    """Sequences inside a nested message and a fixed-size array of
    messages; the ROS 1 aliases (char[] is uint8[], byte[] int8[]), bool[]
    and int64[]; max_length through the same paths."""
    _custom(tmp_path)
    text = arm("P: float64, F: bool, C: uint8, D: int8, T: int64, L: uint32, N: uint8",
               ['{topic: /arm, field: "joints[1].position[3]", input: P}',
                '{topic: /arm, field: "joints[0].flags[0]", input: F}',
                '{topic: /arm, field: "codes[2]", input: C}',
                '{topic: /arm, field: "deltas[1]", input: D}',
                '{topic: /arm, field: "ticks[0]", input: T}',
                '{topic: /arm, field: "joints[1].position", derived: length, input: L}',
                '{topic: /arm, field: "joints[0].name[0]", input: N}'],
               '{"joints[0].position": 6, codes: 3}')
    m = load(tmp_path, text)
    assert [(i, s, p) for i, s, p, _ in rels(m)] == [
        ("P", ("joints", 1, "position", "data", 3), "float64"),
        ("F", ("joints", 0, "flags", "data", 0), "bool"),
        ("C", ("codes", "data", 2), "uint8"),
        ("D", ("deltas", "data", 1), "int8"),
        ("T", ("ticks", "data", 0), "int64"),
        ("L", ("joints", 1, "position", "len"), "uint32"),
        ("N", ("joints", 0, "name", "data", 0), "uint8")]
    assert fields_of(m, "arm_msgs/Joint") == [("name", "msg", "ros_string128", None),
                                             ("position", "msg", "ros_seq_float64_6", None),
                                             ("flags", "msg", "ros_seq_bool_128", None)]
    assert fields_of(m, "arm_msgs/Arm") == [("header", "msg", "std_msgs/Header", None),
                                           ("joints", "msg", "arm_msgs/Joint", 2),
                                           ("codes", "msg", "ros_seq_uint8_3", None),
                                           ("deltas", "msg", "ros_seq_int8_128", None),
                                           ("ticks", "msg", "ros_seq_int64_128", None),
                                           ("x", "prim", "float64", None)]


def test_check_and_diagram_show_the_sequences(tmp_path, capsys):
    p = write(tmp_path, BASE)
    assert cli.main(["check", str(p)]) == 0
    out = capsys.readouterr().out
    assert out.rstrip().endswith("; 1 variable-length array: sensor_msgs/LaserScan ranges (float32[], at most 1081)")
    from pyrosgen.diagram import diagram_context

    ctx = diagram_context(load(tmp_path, BASE))
    assert [r["path"] for r in ctx["in_rels"]] == ["ranges[540]", "ranges (length)", "ranges (truncated)"]


# --------------------------------------------------------------------------
# Refusals


@pytest.mark.parametrize("value, problem", [
    ("0", "must be an integer from 1 to 65536, got '0' (a carried array holds at least one element; its received "
          "length may still be 0)"),
    ("-5", "must be an integer from 1 to 65536, got '-5' (a carried array holds at least one element; its received "
           "length may still be 0)"),
    ("65537", "must be an integer from 1 to 65536, got '65537'"),
    ("true", "must be an integer from 1 to 65536 (the most elements carried), got boolean 'true'"),
    ("1081.0", "must be an integer from 1 to 65536 (the most elements carried), got float '1081.0'"),
    ("'1081'", "must be an integer from 1 to 65536 (the most elements carried), got string '1081'"),
    ("null", "must be an integer from 1 to 65536 (the most elements carried), got null (an empty value)"),
])
def test_bad_maxima(tmp_path, value, problem):
    text = BASE.replace("max_length: {ranges: 1081}", f"max_length: {{ranges: {value}}}").replace(
        "ranges[540]", "ranges[0]")
    found = diags(tmp_path, text)
    line, col = at(text, f"ranges: {value}}}")
    want = (line, col + len("ranges: "), f"topics[0].max_length['ranges'] {problem}", "4.15")
    assert want in found, found
    assert all(rule == "4.15" for *_, rule in found), found


def test_max_length_problems_with_their_paths(tmp_path):
    text = BASE.replace("max_length: {ranges: 1081}",
                        "max_length: {rangez: 5, angle_min: 5, \"ranges[3]\": 5, header: 5, ranges.len: 5, "
                        "header.frame_id.len: 5, 7: 5}").replace("ranges[540]", "ranges[5]")
    found = diags(tmp_path, text)
    head = "topics[0].max_length"
    assert found == [
        (*at(text, "rangez"), f"{head}['rangez']: field path 'rangez': message type sensor_msgs/LaserScan has no "
                              f"field 'rangez' (did you mean 'ranges'?) {_SCAN}", "4.15"),
        (*at(text, "angle_min"), f"{head}['angle_min']: field path 'angle_min': 'angle_min' is a float32, not a "
                                 f"variable-length array or a string (max_length is for those) {_SCAN}", "4.15"),
        (*at(text, '"ranges[3]"'), f"{head}['ranges[3]']: field path 'ranges[3]': 'ranges[3]' is one element of a "
                                   f"variable-length array (float32[]); max_length names the whole array ('ranges') "
                                   f"{_SCAN}", "4.15"),
        (*at(text, "header: 5"), f"{head}['header']: field path 'header': 'header' is a whole sub-message "
                                 f"(std_msgs/Header), not a variable-length array or a string (max_length is for "
                                 f"those) {_SCAN}", "4.15"),
        (*at(text, "ranges.len"), f"{head}['ranges.len']: field path 'ranges.len': 'ranges' is a variable-length "
                                  "array (float32[]); a path does not go inside it ('len': len, truncated and data "
                                  f"are fields of its C struct, not of the ROS message) {_SCAN}", "4.15"),
        (*at(text, "header.frame_id.len"), f"{head}['header.frame_id.len']: field path 'header.frame_id.len': "
                                           "'header.frame_id' is a string; a path does not go inside it ('len': "
                                           "len, truncated and data are fields of its C struct, not of the ROS "
                                           f"message) {_SCAN}", "4.15"),
        (*at(text, "7: 5"), f"{head}['7']: field path '7' is malformed: expected field names, each optionally "
                            f"followed by [INDEX], separated by '.' {_SCAN}", "4.15"),
    ]


def test_max_length_of_a_sequence_of_messages_and_not_a_mapping(tmp_path):
    """A max_length key reaches into every element of an array of messages
    with [] (one struct holds them all): a constant index is refused."""
    text = BASE.replace("  - {name: /cmd,", "  - {name: /path, direction: subscribe, type: nav_msgs/Path, "
                                          "queue_size: 1, max_length: {poses: 10, "
                                          "\"poses[0].header.frame_id\": 8}}\n  - {name: /cmd,")
    (line, col, msg, rule), = diags(tmp_path, text)
    assert (line, col, rule) == (*at(text, '"poses[0].header.frame_id"'), "4.15")
    assert msg == ("topics[1].max_length['poses[0].header.frame_id']: field path 'poses[0].header.frame_id': "
                   "'poses[0]': a max_length key names every element of 'poses' (a variable-length array of "
                   "messages (geometry_msgs/PoseStamped[])) with [] ('poses[]'): one struct holds them all "
                   "(topic '/path', nav_msgs/Path)")
    text = BASE.replace("max_length: {ranges: 1081}", "max_length: 1081").replace("ranges[540]", "ranges[0]")
    assert one(tmp_path, text) == (*at(text, "1081}"), "topics[0].max_length must be a mapping of field paths to "
                                   "maximum lengths (e.g. {ranges: 1081}), got int '1081'", "4.15")


def test_two_maxima_for_one_field_are_refused_with_both_positions(tmp_path):
    text = BASE.replace("  - {name: /cmd,", "  - {name: /scan2, direction: subscribe, type: sensor_msgs/LaserScan, "
                                          "queue_size: 1, max_length: {ranges: 720}}\n  - {name: /cmd,")
    first = at(text, "ranges: 1081")
    assert one(tmp_path, text) == (
        *at(text, "ranges: 720"),
        f"topics[1].max_length['ranges']: 720 differs from the maximum 1081 given to the same field (ranges of "
        f"sensor_msgs/LaserScan) at line {first[0]}, column {first[1]} (topics[0].max_length['ranges']); one C "
        "struct holds the field in every topic of type sensor_msgs/LaserScan, so it has one maximum", "4.15")
    # the same maximum twice is fine
    load(tmp_path, text.replace("ranges: 720", "ranges: 1081"))


def test_an_index_beyond_the_maximum_names_it(tmp_path):
    text = BASE.replace("ranges[540]", "ranges[1081]")
    assert one(tmp_path, text) == (*at(text, '"ranges[1081]"'), "relations.inputs[0].field: field path "
                                   "'ranges[1081]': index 1081 is beyond the maximum length of 'ranges': the node "
                                   "carries at most 1081 of its elements (max_length, default 128); valid indices "
                                   f"are 0..1080 {_SCAN}", "4.15")
    text = BASE.replace(", max_length: {ranges: 1081}", "").replace("ranges[540]", "ranges[128]")
    assert "at most 128 of its elements" in one(tmp_path, text)[2]
    text = BASE.replace("  outputs:\n", "    - {topic: /scan, field: \"header.frame_id[128]\", input: F}\n"
                                        "  outputs:\n").replace("TR: bool}", "TR: bool, F: uint8}")
    assert one(tmp_path, text)[2:] == (
        "relations.inputs[3].field: field path 'header.frame_id[128]': index 128 is beyond the maximum length of "
        "'header.frame_id': the node carries at most 128 of its bytes (max_length, default 128); valid indices are "
        f"0..127 {_SCAN}", "4.15")


def test_element_types_must_match(tmp_path):
    text = BASE.replace("R: float32", "R: float64")
    assert one(tmp_path, text) == (*at(text, '{topic: /scan, field: "ranges[540]"'),
                                   "relations.inputs[0]: type mismatch: field 'ranges[540]' of topic '/scan' is "
                                   "float32 but controller input 'R' is float64 (relations never convert)", "4.15")


def test_length_and_truncated_have_their_types(tmp_path):
    text = BASE.replace("NR: uint32, TR: bool", "NR: float64, TR: uint32")
    assert diags(tmp_path, text) == [
        (*at(text, "NR}"), "relations.inputs[1].input: length related to a non-uint32 field: controller input "
                           "'NR' is float64 (length is a uint32)", "4.15"),
        (*at(text, "TR}"), "relations.inputs[2].input: truncated related to a non-bool field: controller input "
                           "'TR' is uint32 (truncated is a bool)", "4.15"),
    ]


def test_length_of_what_is_not_a_sequence(tmp_path):
    text = BASE.replace("field: ranges, derived: length", "field: angle_min, derived: length")
    assert one(tmp_path, text) == (*at(text, "angle_min"), "relations.inputs[1].field: field path 'angle_min': "
                                   "'angle_min' is a float32, not a variable-length array or a string (derived: "
                                   f"length is for those) {_SCAN}", "4.15")
    text = BASE.replace("field: ranges, derived: length", "field: \"ranges[2]\", derived: length")
    assert one(tmp_path, text) == (*at(text, '"ranges[2]"'), "relations.inputs[1].field: field path 'ranges[2]': "
                                   "'ranges[2]' is one element of a variable-length array (float32[]); derived: "
                                   f"length names the whole array ('ranges') {_SCAN}", "4.15")
    text = BASE.replace("{topic: /scan, field: ranges, derived: length, input: NR}",
                        "{topic: /scan, derived: length, input: NR}")
    assert one(tmp_path, text) == (*at(text, "length, input: NR"), "relations.inputs[1].derived: length reads a "
                                   "variable-length array or a string: name it with field (e.g. field: ranges)",
                                   "4.15")


def test_other_derived_kinds_still_refuse_a_field(tmp_path):
    text = BASE.replace("TR: bool}", "TR: bool, N: bool}").replace(
        "  outputs:\n", "    - {topic: /scan, field: ranges, derived: is_new, input: N}\n  outputs:\n")
    assert one(tmp_path, text) == (*at(text, "ranges, derived: is_new"), "relations.inputs[3].field: a derived "
                                   "input reads no message field (a relation has either field or derived; field "
                                   "goes with derived: length or truncated only)", "4.12")


@pytest.mark.parametrize("field, problem", [
    ("ranges", "'ranges' is a variable-length array (float32[]); a relation reads one of its elements "
               "('ranges[0]', a float32), or its length or whether it was truncated (derived: length, derived: "
               "truncated)"),
    ("ranges.len", "'ranges' is a variable-length array (float32[]); a path does not go inside it ('len': len, "
                   "truncated and data are fields of its C struct, not of the ROS message); name one of its "
                   "elements ('ranges[0]') or use derived: length or derived: truncated"),
    ('"ranges.data[3]"', "'ranges' is a variable-length array (float32[]); a path does not go inside it ('data': "
                         "len, truncated and data are fields of its C struct, not of the ROS message); name one of "
                         "its elements ('ranges[0]') or use derived: length or derived: truncated"),
    ('"ranges[3].x"', "'ranges[3]' is a float32, it has no field 'x'"),
    ("header.frame_id", "'header.frame_id' is a string; a relation reads one of its bytes ('header.frame_id[0]', "
                        "a uint8), or its length or whether it was truncated (derived: length, derived: truncated)"),
])
def test_whole_sequences_and_struct_fields_are_refused(tmp_path, field, problem):
    text = BASE.replace('field: "ranges[540]"', f"field: {field}")
    shown = field.strip('"')
    line, col = at(text, f"field: {field}")
    assert one(tmp_path, text) == (line, col + len("field: "),
                                   f"relations.inputs[0].field: field path '{shown}': {problem} {_SCAN}", "4.15")


def test_a_string_into_a_numeric_input(tmp_path):
    text = BASE.replace("TR: bool}", "TR: bool, F: float64}").replace(
        "  outputs:\n", "    - {topic: /scan, field: \"header.frame_id[0]\", input: F}\n  outputs:\n")
    assert one(tmp_path, text) == (*at(text, '{topic: /scan, field: "header.frame_id[0]"'),
                                   "relations.inputs[3]: a string related to a non-uint8 field: "
                                   "'header.frame_id[0]' of topic '/scan' is a byte of a string (uint8) but "
                                   "controller input 'F' is float64 (a string reaches the controller byte by byte, "
                                   "as uint8, with its length from derived: length)", "4.15")


def test_sequences_of_messages_are_carried(tmp_path):
    """An element's leaf of an array of messages (rule 4.15;
    tests/frontend/test_elem_sequences.py has the rest)."""
    text = BASE.replace("  - {name: /cmd,", "  - {name: /path, direction: subscribe, type: nav_msgs/Path, "
                                          "queue_size: 1}\n  - {name: /cmd,").replace(
        "TR: bool}", "TR: bool, X: float64}").replace(
        "  outputs:\n", "    - {topic: /path, field: \"poses[0].pose.position.x\", input: X}\n  outputs:\n")
    m = load(tmp_path, text)
    assert rels(m)[-1] == ("X", ("poses", "data", 0, "pose", "position", "x"), "float64", "poses[0].pose.position.x")
    assert ("poses", "msg", "ros_seq_geometry_msgs_PoseStamped_128", None) in fields_of(m, "nav_msgs/Path")


def test_output_relations_write_a_sequence_with_its_length(tmp_path):
    """An output relation writes an element of a published sequence only
    with its length (tests/frontend/test_published_sequences.py has the
    rest of the publish side)."""
    text = BASE.replace("  - {name: /cmd,", "  - {name: /scan_out, direction: publish, type: sensor_msgs/LaserScan, "
                                          "queue_size: 1}\n  - {name: /cmd,").replace(
        "fields: {Out1: float64}", "fields: {Out1: float64, O: float32}").replace(
        "    - {output: Out1, topic: /cmd, field: linear.x}",
        "    - {output: Out1, topic: /cmd, field: linear.x}\n    - {output: O, topic: /scan_out, field: \"ranges[0]\"}")
    assert one(tmp_path, text) == (*at(text, '"ranges[0]"}'), "relations.outputs[1].field: the controller writes "
                                   "elements of the published variable-length array 'ranges' of topic '/scan_out' "
                                   "but not its length: add {output: <a uint32 output>, topic: /scan_out, field: "
                                   "ranges, derived: length} (the subscriber receives the first min(length, N) "
                                   "elements, N its max_length)", "4.15")
    m = load(tmp_path, text.replace("O: float32}", "O: float32, NS: uint32}").replace(
        "field: \"ranges[0]\"}", "field: \"ranges[0]\"}\n    - {output: NS, topic: /scan_out, field: ranges, "
        "derived: length}"))
    assert [(r.output_field, str(r.path), r.field_text) for r in m.output_relations[1:]] == [
        ("O", "ranges.data[0]", "ranges[0]"), ("NS", "ranges.len", "ranges (length)")]


def test_a_package_named_ros_is_refused(tmp_path):
    for pkg in ("ros", "ros_seq_x", "ros_string"):
        d = tmp_path / pkg / "msgs" / pkg / "msg"
        d.mkdir(parents=True)
        (d / "Thing.msg").write_text("uint32 n\n")
        text = BASE.replace("relations:", f"msg_paths: [{pkg}/msgs]\nrelations:")
        assert one(tmp_path, text) == (
            *at(text, f"{pkg}/msgs]"), f"msg_paths[0]: folder '{pkg}/msgs' holds the package '{pkg}': a package named "
            "ros (or starting with ros_seq, ros_string, ros_rseq or ros_rstring) is refused, its C structs could "
            "collide with the glue's own (ros_time, ros_duration, ros_seq_<T>_<N>, ros_string<N>, ros_rseq_<T>_<N>, "
            "ros_rstring<N>)", "4.15")


def test_every_problem_is_reported_at_once(tmp_path):
    text = BASE.replace("max_length: {ranges: 1081}", "max_length: {ranges: 0}").replace(
        "ranges[540]", "ranges[2000]").replace("NR: uint32", "NR: int32")
    found = diags(tmp_path, text)
    assert [(m.split(":")[0].split(" ")[0], rule) for _, _, m, rule in found] == [
        ("topics[0].max_length['ranges']", "4.15"), ("relations.inputs[0].field", "4.15"),
        ("relations.inputs[1].input", "4.15")]


# --------------------------------------------------------------------------
# The Python side of the running node: the wrapper and the harness


def _wrapper(model) -> str:
    return next(v for k, v in render_wrapper(model).items() if k.endswith(".cpp"))


TO_C = """\
inline void to_c(const std::vector<float> &r, struct ros_seq_float32_1081 *c)
{
    const std::size_t n = r.size();
    const std::size_t len = std::min<std::size_t>(n, 1081);
    c->len = static_cast<unsigned int>(len);
    c->truncated = n > 1081 ? 1 : 0;
    std::copy(r.begin(), r.begin() + len, c->data);
    std::fill(c->data + len, c->data + 1081, 0);
}
"""

FROM_C = """\
inline void from_c(const struct ros_seq_float32_1081 *c, std::vector<float> &r)
{
    r.assign(c->data, c->data + std::min<std::size_t>(c->len, 1081));
}
"""


def test_the_wrapper_converts_as_the_environment_model_says(tmp_path):
    m = load(tmp_path, BASE)
    cpp = _wrapper(m)
    assert cpp.count(TO_C) == 1 and cpp.count(FROM_C) == 1
    assert "    to_c(r.ranges, &c->ranges);\n" in cpp and "    from_c(&c->ranges, r.ranges);\n" in cpp
    assert "inline void to_c(const std::vector<float> &r, struct ros_seq_float32_1081 *c);\n" in cpp
    check_wrapper(cpp, model_text(m), wrapper_name="scanner_ros.cpp")
    # a wrong conversion is refused: tests/build/test_wrapper_check.py (make mutants)


def test_the_wrapper_check_refuses_a_stray_or_duplicate_conversion(tmp_path):
    m = load(tmp_path, BASE)
    cpp = _wrapper(m)
    extra = TO_C.replace("ros_seq_float32_1081", "ros_seq_float32_99").replace("1081", "99")
    with pytest.raises(WrapperMismatch) as info:
        check_wrapper(cpp + "\n" + extra, model_text(m), wrapper_name="w")
    assert any("struct ros_seq_float32_99, which is not a sequence struct of the proved model" in line
               for line in info.value.lines), info.value.lines
    with pytest.raises(WrapperMismatch) as info:
        check_wrapper(cpp + "\n" + TO_C, model_text(m), wrapper_name="w")
    assert any("does not convert a received float32[] into struct ros_seq_float32_1081 once" in line
               for line in info.value.lines), info.value.lines
    # another capacity in the proved model than in the wrapper
    other = model_text(load(tmp_path, BASE.replace("ranges: 1081", "ranges: 1000")))
    with pytest.raises(WrapperMismatch):
        check_wrapper(cpp, other, wrapper_name="w")

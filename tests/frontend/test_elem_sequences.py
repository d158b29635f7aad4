"""Variable-length arrays of messages and of strings into the controller
(DESIGN.md rule 4.15): an input relation reads a leaf of an element of
``poses`` (``geometry_msgs/PoseStamped[]`` of ``nav_msgs/Path``:
``"poses[3].pose.position.x"``, through nested messages, fixed-size
arrays, and sequences and strings inside the element), a byte of an
element of ``name`` (``string[]`` of ``sensor_msgs/JointState``:
``"name[0][3]"``), the lengths and truncation flags of both (``derived:
length`` / ``truncated`` of ``poses``, ``name``, ``"name[0]"``), and a
whole element string into a ``uint8[M]`` controller array.  Such an
array is carried as ``ros_seq_<pkg>_<Type>_<N>`` /
``ros_seq_string<M>_<N>``, whose ``data`` is an array of the element's
struct; ``max_length: {poses: N, "name[]": M, "poses[].header.frame_id":
K}`` sets the maxima (``[]``: every element).

The accepted models and their objects (structs, relation paths, the
model text and its parser, the emitted Coq, ``check``), every refusal
with its message, line, column and rule, and policy reject: accepted on
the array itself, refused on a string or sequence inside an element."""

from __future__ import annotations

import pytest

from pyrosgen import cli
from pyrosgen.frontend.msgmodel import (
    bounded_type, is_bounded_type, is_seq_type, seq_elem_type, seq_msg_type_name, seq_string_type_name,
)
from pyrosgen.proof.coqmodel import emit_model, render_node_file
from pyrosgen.proof.modeltext import model_text, parse_model_text

from support.frontend import at, diags, load, one, write

BASE = """\
node: {name: walker, period_ms: 20}
controller:
  name: Controller
  inputs: {name: Controller_U, fields: {X: float64, NP: uint32, B: uint8, NL: uint32, NJ: uint32}}
  outputs: {name: Controller_Y, fields: {Out1: float64}}
topics:
  - {name: /path, direction: subscribe, type: nav_msgs/Path, queue_size: 1, max_length: {poses: 4}}
  - {name: /joints, direction: subscribe, type: sensor_msgs/JointState, queue_size: 1, max_length: {name: 6, "name[]": 32}}
  - {name: /cmd, direction: publish, type: geometry_msgs/Twist, queue_size: 1}
relations:
  inputs:
    - {topic: /path, field: "poses[3].pose.position.x", input: X}
    - {topic: /path, field: poses, derived: length, input: NP}
    - {topic: /joints, field: "name[0][3]", input: B}
    - {topic: /joints, field: "name[0]", derived: length, input: NL}
    - {topic: /joints, field: name, derived: length, input: NJ}
  outputs:
    - {output: Out1, topic: /cmd, field: linear.x}
"""

_PATH = "(topic '/path', nav_msgs/Path)"
_JOINTS = "(topic '/joints', sensor_msgs/JointState)"


def fields_of(model, name: str) -> list[tuple[str, str, str | None, int | None]]:
    return [(f.name, f.kind, f.prim or f.msg, f.array_len) for f in model.message(name).fields]


def rels(model) -> list[tuple[str, tuple, str]]:
    return [(r.input_target, r.path.steps, r.path.prim) for r in model.input_relations]


# --------------------------------------------------------------------------
# Accepted models


def test_element_leaves_lengths_and_bytes_are_leaf_relations(tmp_path):
    m = load(tmp_path, BASE)
    assert rels(m) == [
        ("X", ("poses", "data", 3, "pose", "position", "x"), "float64"),
        ("NP", ("poses", "len"), "uint32"),
        ("B", ("name", "data", 0, "data", 3), "uint8"),
        ("NL", ("name", "data", 0, "len"), "uint32"),
        ("NJ", ("name", "len"), "uint32"),
    ]
    assert [r.field_text for r in m.input_relations] == [
        "poses[3].pose.position.x", "poses (length)", "name[0][3]", "name[0] (length)", "name (length)"]
    names = [t.name for t in m.messages]
    assert names.index("geometry_msgs/PoseStamped") < names.index("ros_seq_geometry_msgs_PoseStamped_4") \
        < names.index("nav_msgs/Path")
    assert names.index("ros_string32") < names.index("ros_seq_string32_6") < names.index("sensor_msgs/JointState")
    assert fields_of(m, "ros_seq_geometry_msgs_PoseStamped_4") == [
        ("len", "prim", "uint32", None), ("truncated", "prim", "bool", None),
        ("data", "msg", "geometry_msgs/PoseStamped", 4)]
    assert fields_of(m, "ros_seq_string32_6") == [
        ("len", "prim", "uint32", None), ("truncated", "prim", "bool", None), ("data", "msg", "ros_string32", 6)]
    assert fields_of(m, "nav_msgs/Path") == [("header", "msg", "std_msgs/Header", None),
                                            ("poses", "msg", "ros_seq_geometry_msgs_PoseStamped_4", None)]
    # what no relation reads stays dropped: JointState's position, velocity,
    # effort; every header's frame_id
    assert fields_of(m, "sensor_msgs/JointState") == [("header", "msg", "std_msgs/Header", None),
                                                     ("name", "msg", "ros_seq_string32_6", None)]
    assert [f[0] for f in fields_of(m, "std_msgs/Header")] == ["seq", "stamp"]
    assert [(o, f, b.name) for o, f, b in m.bounded_fields] == [
        ("nav_msgs/Path", "poses", "ros_seq_geometry_msgs_PoseStamped_4"),
        ("sensor_msgs/JointState", "name", "ros_seq_string32_6")]


def test_struct_names_and_types():
    t = seq_elem_type("geometry_msgs/PoseStamped", 4)
    assert (t.name, t.seq_of, t.capacity, t.is_seq, t.is_bounded, t.elem_struct, t.cpp_name) == (
        "ros_seq_geometry_msgs_PoseStamped_4", ("geometry_msgs/PoseStamped", 4), 4, True, True,
        "geometry_msgs/PoseStamped", "std::vector<geometry_msgs::PoseStamped>")
    s = seq_elem_type("string", 6, elem_capacity=32)
    assert (s.name, s.elem_struct, s.cpp_name) == ("ros_seq_string32_6", "ros_string32", "std::vector<std::string>")
    assert seq_msg_type_name("time", 3, True) == "ros_rseq_ros_time_3"
    assert bounded_type("ros_rseq_ros_time_3").cpp_name == "std::vector<ros::Time>"
    assert seq_string_type_name(32, 6, True) == "ros_rseq_string32_6"
    for name in ("ros_seq_geometry_msgs_PoseStamped_4", "ros_rseq_string32_6", "ros_seq_my_pkg_Thing_1"):
        assert is_bounded_type(name) and bounded_type(name).name == name and not is_seq_type(name)
    # a package called ros is refused (rule 4.15): no such element; no prefix collides
    for name in ("ros_seq_ros_string32_4", "ros_seq_string_4", "ros_seq_string32_0", "ros_seq_geometry_msgs_0"):
        assert not is_bounded_type(name), name
    with pytest.raises(ValueError):
        seq_msg_type_name("ros_string32")


def test_model_text_round_trip_and_emitted_coq(tmp_path):
    m = load(tmp_path, BASE)
    text = model_text(m)
    lines = text.splitlines()
    for want in ("input_relation path poses.data[3].pose.position.x X", "input_relation path poses.len NP",
                 "input_relation joints name.data[0].data[3] B", "input_relation joints name.data[0].len NL",
                 "message ros_seq_geometry_msgs_PoseStamped_4", "field data array 4 msg geometry_msgs_PoseStamped",
                 "message ros_seq_string32_6", "field data array 6 msg ros_string32"):
        assert want in lines, want
    pm = parse_model_text(text)
    assert pm.messages["ros_seq_string32_6"][2] == ("data", "array 6 msg ros_string32")
    e = emit_model(m)
    assert ('"path"', '[PField "poses"; PField "data"; PIndex 3; PField "pose"; PField "position"; PField "x"]',
            '"X"') == e.inrels[0][:3]
    assert e.inrels[2][1] == '[PField "name"; PField "data"; PIndex 0; PField "data"; PIndex 3]'
    v = render_node_file(m, ddc_available=True)
    assert 'FTarray (FTmsg "geometry_msgs_PoseStamped") 4' in v and 'FTarray (FTmsg "ros_string32") 6' in v


def test_nested_sequences_and_strings_inside_elements(tmp_path):
    """Inside an element: a variable-length array of primitives
    (``points[1].positions[2]`` of trajectory_msgs/JointTrajectory), an
    array of messages holding strings (``status[0].values[1].key[0]`` of
    diagnostic_msgs/DiagnosticArray), a string (``status[2].name``), each
    with its max_length through ``[]``."""
    text = BASE.replace(
        "  - {name: /cmd,",
        "  - {name: /traj, direction: subscribe, type: trajectory_msgs/JointTrajectory, queue_size: 1,\n"
        '     max_length: {points: 3, "points[].positions": 5}}\n'
        "  - {name: /diag, direction: subscribe, type: diagnostic_msgs/DiagnosticArray, queue_size: 1,\n"
        '     max_length: {status: 3, "status[].values": 2, "status[].values[].key": 8, "status[].name": 4}}\n'
        "  - {name: /cmd,").replace(
        "NJ: uint32}", "NJ: uint32, P: float64, K: uint8, SL: uint32, NV: uint32}").replace(
        "  outputs:\n    - {output: Out1",
        '    - {topic: /traj, field: "points[1].positions[2]", input: P}\n'
        '    - {topic: /diag, field: "status[0].values[1].key[7]", input: K}\n'
        '    - {topic: /diag, field: "status[2].name", derived: length, input: SL}\n'
        '    - {topic: /diag, field: "status[1].values", derived: length, input: NV}\n'
        "  outputs:\n    - {output: Out1")
    m = load(tmp_path, text)
    assert rels(m)[5:] == [
        ("P", ("points", "data", 1, "positions", "data", 2), "float64"),
        ("K", ("status", "data", 0, "values", "data", 1, "key", "data", 7), "uint8"),
        ("SL", ("status", "data", 2, "name", "len"), "uint32"),
        ("NV", ("status", "data", 1, "values", "len"), "uint32")]
    assert fields_of(m, "trajectory_msgs/JointTrajectoryPoint") == [
        ("positions", "msg", "ros_seq_float64_5", None), ("time_from_start", "msg", "duration", None)]
    assert fields_of(m, "diagnostic_msgs/DiagnosticStatus") == [
        ("level", "prim", "int8", None), ("name", "msg", "ros_string4", None),
        ("values", "msg", "ros_seq_diagnostic_msgs_KeyValue_2", None)]
    assert fields_of(m, "diagnostic_msgs/KeyValue") == [("key", "msg", "ros_string8", None)]


def test_a_whole_element_string_into_a_controller_array(tmp_path):
    text = BASE.replace("NJ: uint32", 'NJ: "uint8[32]"').replace(
        "field: name, derived: length, input: NJ", 'field: "name[1]", input: NJ')
    m = load(tmp_path, text)
    got = [(r.input_target, r.path.steps) for r in m.input_relations if r.input_field == "NJ"]
    assert got == [(f"NJ[{i}]", ("name", "data", 1, "data", i)) for i in range(32)]
    text = text.replace('"uint8[32]"', '"uint8[31]"')
    assert one(tmp_path, text) == (
        *at(text, '{topic: /joints, field: "name[1]"'),
        "relations.inputs[4]: field 'name[1]' of topic '/joints' is a string of at most 32 bytes (uint8) but "
        "controller input 'NJ' is uint8[31]: the sizes differ: give the field max_length 31 on the topic "
        '(max_length: {"name[]": 31}), or declare NJ uint8[32]', "4.15")


def test_policy_reject_on_the_array_itself(tmp_path):
    text = BASE.replace("max_length: {poses: 4}", "max_length: {poses: 4}, policy: {poses: reject}").replace(
        '"name[]": 32}', '"name[]": 32}, policy: {name: reject}')
    m = load(tmp_path, text)
    assert [b.name for _, _, b in m.bounded_fields] == ["ros_rseq_geometry_msgs_PoseStamped_4", "ros_rseq_string32_6"]
    # the truncation flag of such an array is always 0: refused (rule 4.15)
    bad = text.replace("field: poses, derived: length", "field: poses, derived: truncated").replace(
        "NP: uint32", "NP: bool")
    line, col, msg, rule = one(tmp_path, bad)
    assert (line, col, rule) == (*at(bad, "truncated, input: NP"), "4.15") and "whose policy is reject" in msg


def test_check_counts_the_arrays(tmp_path, capsys):
    assert cli.main(["check", str(write(tmp_path, BASE))]) == 0
    out = capsys.readouterr().out
    assert ("2 variable-length arrays: nav_msgs/Path poses (geometry_msgs/PoseStamped[], at most 4), "
            "sensor_msgs/JointState name (string[], at most 6 of at most 32 bytes)") in out, out


def test_published_elements_lengths_and_strings(tmp_path):
    """The publish side (tests/ros/models/elem_seq_pub.yaml): output
    relations into element leaves, element strings (bytes, whole from a
    uint8[M] controller array) and the lengths of the arrays and strings."""
    from support.frontend import REPO

    m = load(tmp_path, (REPO / "tests" / "ros" / "models" / "elem_seq_pub.yaml").read_text())
    outs = [(r.output_source, r.path.steps) for r in m.output_relations]
    assert outs[:3] == [("NP", ("poses", "len")), ("X0", ("poses", "data", 0, "pose", "position", "x")),
                        ("X1", ("poses", "data", 1, "pose", "position", "x"))]
    assert ("FL1", ("poses", "data", 1, "header", "frame_id", "len")) in outs
    assert ("N0[3]", ("name", "data", 0, "data", 3)) in outs and ("N2L", ("name", "data", 2, "len")) in outs
    assert fields_of(m, "nav_msgs/Path")[1] == ("poses", "msg", "ros_seq_geometry_msgs_PoseStamped_3", None)


PUB = BASE.replace("type: geometry_msgs/Twist, queue_size: 1}", "type: nav_msgs/Path, queue_size: 1, "
                   "max_length: {poses: 4}}").replace("Out1: float64}", "Out1: uint32, F: uint8, FL: uint32}").replace(
    "    - {output: Out1, topic: /cmd, field: linear.x}\n",
    "    - {output: Out1, topic: /cmd, field: poses, derived: length}\n"
    "    - {output: F, topic: /cmd, field: \"poses[1].header.frame_id[0]\"}\n"
    "    - {output: FL, topic: /cmd, field: \"poses[1].header.frame_id\", derived: length}\n")


def test_published_lengths_inside_elements(tmp_path):
    """A string written inside a published element needs its own length
    and the array's; a length inside an element needs the array's."""
    load(tmp_path, PUB)
    text = _swap('    - {output: FL, topic: /cmd, field: "poses[1].header.frame_id", derived: length}\n', "", PUB)
    text = text.replace(", FL: uint32}", "}")
    assert one(tmp_path, text) == (
        *at(text, '"poses[1].header.frame_id[0]"'), "relations.outputs[1].field: the controller writes elements of "
        "the published string 'poses[1].header.frame_id' of topic '/cmd' but not its length: add {output: <a uint32 "
        'output>, topic: /cmd, field: "poses[1].header.frame_id", derived: length} (the subscriber receives the '
        "first min(length, N) elements, N its max_length)", "4.15")
    text = _swap("    - {output: Out1, topic: /cmd, field: poses, derived: length}\n", "", PUB).replace(
        "Out1: uint32, ", "")
    found = diags(tmp_path, text)
    assert found[0] == (*at(text, '"poses[1].header.frame_id[0]"'), "relations.outputs[0].field: the controller writes "
                        "inside the published variable-length array of messages 'poses' of topic '/cmd' but not its "
                        "length: add {output: <a uint32 output>, topic: /cmd, field: poses, derived: length} (the "
                        "subscriber receives the first min(length, N) elements, N its max_length)", "4.15")
    assert len(found) == 1  # the missing length is reported once, at its first relation


# --------------------------------------------------------------------------
# Refusals: each at its place, citing rule 4.15


def _swap(old: str, new: str, text: str = BASE) -> str:
    assert old in text, old
    return text.replace(old, new)


REFUSALS = {
    "element index not below N": (
        _swap("poses[3]", "poses[4]"), '"poses[4]', "relations.inputs[0].field: field path "
        "'poses[4].pose.position.x': index 4 is beyond the maximum length of 'poses': the node carries at most 4 "
        f"of its elements (max_length, default 128); valid indices are 0..3 {_PATH}"),
    "byte index not below M": (
        _swap('"name[0][3]"', '"name[0][32]"'), '"name[0][32]"', "relations.inputs[2].field: field path "
        "'name[0][32]': index 32 is beyond the maximum length of the strings of 'name': the node carries at most 32 "
        f"bytes of each (max_length 'name[]', default 128); valid indices are 0..31 {_JOINTS}"),
    "a whole element": (
        _swap('"poses[3].pose.position.x"', '"poses[3]"'), '"poses[3]"', "relations.inputs[0].field: field path "
        "'poses[3]': 'poses[3]' is a whole element (geometry_msgs/PoseStamped) of 'poses', not a leaf field; name "
        f"one of its leaf fields, e.g. 'poses[3].header.seq' {_PATH}"),
    "no element index": (
        _swap('"poses[3].pose.position.x"', "poses.pose.position.x"), "poses.pose.position.x",
        "relations.inputs[0].field: field path 'poses.pose.position.x': 'poses' is a variable-length array of "
        "messages (geometry_msgs/PoseStamped[]); a relation reads a leaf of one of its elements ('poses[0].pose') "
        f"or its length or whether it was truncated (derived: length, derived: truncated) {_PATH}"),
    "[] in a relation": (
        _swap('"poses[3].pose.position.x"', '"poses[].pose.position.x"'), '"poses[]',
        "relations.inputs[0].field: field path 'poses[].pose.position.x': 'poses[]': a relation names one element "
        f"with a constant index ('poses[0]'); [] (every element) is for max_length and policy keys {_PATH}"),
    "an element message indexed again": (
        _swap('"poses[3].pose.position.x"', '"poses[3][1].pose.position.x"'), '"poses[3][1]',
        "relations.inputs[0].field: field path 'poses[3][1].pose.position.x': 'poses[3]' is a message "
        f"(geometry_msgs/PoseStamped), not an array: it cannot be indexed again {_PATH}"),
    "a whole element string to a scalar": (
        _swap('field: name, derived: length, input: NJ', 'field: "name[1]", input: NJ'), '"name[1]"',
        "relations.inputs[4].field: field path 'name[1]': 'name[1]' is a string (an element of a variable-length "
        "array of strings (string[])); a relation reads one of its bytes ('name[1][0]', a uint8) or its length "
        f"(derived: length), or relates it whole to a uint8 controller array {_JOINTS}"),
    "a whole array of strings": (
        _swap("NJ: uint32", 'NJ: "uint8[6]"', _swap("field: name, derived: length, input: NJ", "field: name, input: NJ")),
        "name, input: NJ", "relations.inputs[4].field: field path 'name': 'name' is a variable-length array of "
        "strings (string[]); a relation reads a byte of one of its strings ('name[0][0]') or its length or whether "
        f"it was truncated (derived: length, derived: truncated) {_JOINTS}"),
    "an element string's byte into a float64": (
        _swap('"name[0][3]", input: B', '"name[0][3]", input: X', _swap('"poses[3].pose.position.x", input: X',
                                                                         '"poses[3].header.seq", input: NL',
                                                                         _swap('field: "name[0]", derived: length, input: NL',
                                                                               'field: "name[0]", derived: length, input: B'))),
        None, None),
    "derived length of one byte": (
        _swap('field: "name[0]", derived: length', 'field: "name[0][1]", derived: length'), '"name[0][1]"',
        "relations.inputs[3].field: field path 'name[0][1]': 'name[0][1]' is one element of a string; derived: "
        f"length names a whole string ('name[0]') {_JOINTS}"),
    "max_length of the strings 0": (
        _swap('"name[]": 32', '"name[]": 0'), "0}}", "topics[1].max_length['name[]'] must be an integer from 1 to "
        "65536, got '0' (a carried array holds at least one element; its received length may still be 0)"),
    "max_length with a constant index": (
        _swap('"name[]": 32', '"name[0]": 32'), '"name[0]": 32', "topics[1].max_length['name[0]']: field path "
        "'name[0]': 'name[0]': a max_length key names every element of 'name' (a variable-length array of strings "
        f"(string[])) with [] ('name[]'): one struct holds them all {_JOINTS}"),
    "[] on a message": (
        _swap("max_length: {poses: 4}", 'max_length: {poses: 4, "header[]": 3}'), '"header[]"',
        "topics[0].max_length['header[]']: field path 'header[]': 'header' (std_msgs/Header) is not a "
        f"variable-length array of messages or strings: [] is for those {_PATH}"),
    "[] then an index": (
        _swap('"name[]": 32', '"name[][1]": 32'), '"name[][1]"', "topics[1].max_length['name[][1]']: field path "
        "'name[][1]' is malformed: expected field names, each optionally followed by [INDEX], separated by '.'; "
        f"array indices are non-negative integer constants, e.g. covariance[35] {_JOINTS}"),
    "policy reject of the element strings": (
        _swap('"name[]": 32}', '"name[]": 32}, policy: {"name[]": reject}'), '"name[]": reject',
        "topics[1].policy['name[]']: 'name[]' is inside an element of a variable-length array: policy reject is "
        "refused there (the environment model's Environment.too_long would test it in every element the node can "
        "hold, received or not, the wrapper in the received ones only); use truncate, or reject on the array "
        "itself"),
    "policy reject of a string in the elements": (
        _swap("max_length: {poses: 4}", 'max_length: {poses: 4}, policy: {"poses[].header.frame_id": reject}',
              _swap('"poses[3].pose.position.x", input: X', '"poses[3].header.frame_id[0]", input: B',
                    _swap('"name[0][3]", input: B', '"name[0][3]", input: X', _swap("X: float64", "X: uint8")))),
        '"poses[].header.frame_id": reject', "topics[0].policy['poses[].header.frame_id']: 'poses[].header.frame_id' "
        "is inside an element of a variable-length array: policy reject is refused there (the environment model's "
        "Environment.too_long would test it in every element the node can hold, received or not, the wrapper in "
        "the received ones only); use truncate, or reject on the array itself"),
    "policy reject of a field of a type inside the elements": (
        _swap("max_length: {poses: 4}", "max_length: {poses: 4}, policy: {header.frame_id: reject}",
              _swap('"poses[3].pose.position.x", input: X', '"poses[3].header.frame_id[0]", input: B',
                    _swap('"name[0][3]", input: B', '"name[0][3]", input: X', _swap("X: float64", "X: uint8")))),
        "header.frame_id: reject", "topics[0].policy['header.frame_id']: frame_id of std_msgs/Header is also inside "
        "the elements of poses of nav_msgs/Path: policy reject is refused there (the environment model's "
        "Environment.too_long would test it in every element the node can hold, received or not, the wrapper in "
        "the received ones only); use truncate, or reject on the array itself"),
    "an element of a published array of messages without its length": (
        _swap("type: geometry_msgs/Twist", "type: nav_msgs/Path", _swap("field: linear.x", 'field: "poses[0].pose.position.x"')),
        '"poses[0].pose.position.x"}', "relations.outputs[0].field: the controller writes elements of the published "
        "variable-length array of messages 'poses' of topic '/cmd' but not its length: add {output: <a uint32 "
        "output>, topic: /cmd, field: poses, derived: length} (the subscriber receives the first min(length, N) "
        "elements, N its max_length)"),
}


@pytest.mark.parametrize("name", sorted(REFUSALS))
def test_refused_at_its_place(tmp_path, name):
    text, needle, message = REFUSALS[name]
    if needle is None:  # two diagnostics
        found = diags(tmp_path, text)
        assert [d[3] for d in found] == ["4.15", "4.15"], found
        assert any("a string related to a non-uint8 field: 'name[0][3]' of topic '/joints' is a byte of a string "
                   "(uint8) but controller input 'X' is float64" in d[2] for d in found), found
        return
    line, col, msg, rule = one(tmp_path, text)
    assert (line, col, rule) == (*at(text, needle), "4.15"), (line, col, msg)
    assert msg == message


def test_too_many_leaves_names_the_maxima(tmp_path):
    """Every element of an array of strings carries all its bytes: at the
    default maxima (128 strings of 128 bytes) a JointState is too big."""
    text = _swap('max_length: {name: 6, "name[]": 32}', "max_length: {}")
    line, col, msg, rule = one(tmp_path, text)
    assert (line, col, rule) == (*at(text, "sensor_msgs/JointState"), "4.5")
    assert msg.startswith("topics[1].type: message type sensor_msgs/JointState has 16645 scalar leaves; the glue "
                          "carries at most 10000 per message (lower the max_length of its variable-length arrays")


def test_an_array_struct_name_too_long_is_refused(tmp_path):
    """The struct of an array of messages is named after its element's C
    struct: a name longer than C's 63 significant characters is refused
    (rule 4.9) at the topic's type."""
    pkg = tmp_path / "msgs" / "long_package_name_abcdefgh" / "msg"
    pkg.mkdir(parents=True)
    (pkg / "AnExtremelyLongTypeNameXYZ.msg").write_text("float64 x\n")
    (pkg / "Holder.msg").write_text("long_package_name_abcdefgh/AnExtremelyLongTypeNameXYZ[] items\n")
    text = BASE.replace("node: {name: walker, period_ms: 20}\n", "node: {name: walker, period_ms: 20}\nmsg_paths: [msgs]\n")
    text = text.replace("  - {name: /cmd,", "  - {name: /h, direction: subscribe, type: long_package_name_abcdefgh/Holder, "
                                           "queue_size: 1}\n  - {name: /cmd,")
    text = text.replace('field: "poses[3].pose.position.x"', 'field: "items[0].x"').replace("topic: /path, field: \"items", "topic: /h, field: \"items")
    name = "ros_seq_long_package_name_abcdefgh_AnExtremelyLongTypeNameXYZ_128"
    assert one(tmp_path, text) == (*at(text, "long_package_name_abcdefgh/Holder"),
                                   f"the C name '{name}' derived from message type {name} cannot be used: it is longer "
                                   "than 63 characters (65)", "4.9")

"""Published variable-length arrays and strings from the controller
(DESIGN.md rule 4.15, publish side): an output relation writes one
element of a published message's ``T[]`` (``field: "data[3]"``, an
output of type ``T``) or one byte of its ``string`` (a ``uint8``
output), and, with ``derived: length``, its length (a ``uint32``
output).  They are ordinary output relations on the leaves of the
bounded struct (``data.data[3]``, ``data.len``): the output glue zeroes
every leaf, then stores each related output, so unrelated elements are
zero, and the wrapper publishes the first min(len, N) elements (the
environment model's ``Environment.clamp``).

The accepted models and their objects (the model text, the carried
structs, the wrapper's conversion and its check, ``check`` and
``diagram``); every refusal with its message, line, column and rule;
hostile field texts and names."""

from __future__ import annotations

import re

import pytest

from pyrosgen import cli
from pyrosgen.proof.modeltext import model_text
from pyrosgen.ros.wrapper import render_wrapper, wrapper_files
from pyrosgen.verify.wrapper_check import WrapperMismatch, check_wrapper

from support.frontend import at, diags, load, one, write

BASE = """\
node: {name: pubseq, period_ms: 20}
controller:
  name: Controller
  inputs: {name: Controller_U, fields: {X: float64}}
  outputs: {name: Controller_Y, fields: {NS: uint32, E0: float64, E3: float64, B0: uint8, BL: uint32}}
topics:
  - {name: /vals, direction: subscribe, type: geometry_msgs/Point, queue_size: 1}
  - {name: /out, direction: publish, type: std_msgs/Float64MultiArray, queue_size: 1, max_length: {data: 4}}
  - {name: /cmd, direction: publish, type: geometry_msgs/TwistStamped, queue_size: 1}
relations:
  inputs:
    - {topic: /vals, field: x, input: X}
  outputs:
    - {output: NS, topic: /out, field: data, derived: length}
    - {output: E0, topic: /out, field: "data[0]"}
    - {output: E3, topic: /out, field: "data[3]"}
    - {output: B0, topic: /cmd, field: "header.frame_id[0]"}
    - {output: BL, topic: /cmd, field: header.frame_id, derived: length}
"""

_OUT = "(topic '/out', std_msgs/Float64MultiArray)"


def swap(text: str, old: str, new: str) -> str:
    assert text.count(old) == 1, old
    return text.replace(old, new)


# --------------------------------------------------------------------------
# Accepted


def test_elements_and_length_are_output_relations_on_the_bounded_struct(tmp_path):
    m = load(tmp_path, BASE)
    assert [(r.output_field, r.topic.name, str(r.path), r.path.prim, r.field_text) for r in m.output_relations] == [
        ("NS", "/out", "data.len", "uint32", "data (length)"),
        ("E0", "/out", "data.data[0]", "float64", "data[0]"),
        ("E3", "/out", "data.data[3]", "float64", "data[3]"),
        ("B0", "/cmd", "header.frame_id.data[0]", "uint8", "header.frame_id[0]"),
        ("BL", "/cmd", "header.frame_id.len", "uint32", "header.frame_id (length)"),
    ]
    text = model_text(m).splitlines()
    assert text[-5:] == ["output_relation NS out data.len", "output_relation E0 out data.data[0]",
                         "output_relation E3 out data.data[3]", "output_relation B0 cmd header.frame_id.data[0]",
                         "output_relation BL cmd header.frame_id.len"]
    # the published sequence and string are carried, with their maxima
    assert "message ros_seq_float64_4" in text and "field data msg ros_seq_float64_4" in text
    assert "message ros_string128" in text and "field frame_id msg ros_string128" in text
    assert sorted(b.name for _, _, b in m.bounded_fields) == ["ros_seq_float64_4", "ros_string128"]
    # nothing is a constant: the string comes from the controller
    assert m.strings == ()


def test_the_wrapper_publishes_the_first_min_len_n_elements(tmp_path):
    """The wrapper's conversion of the published struct is the clamp's
    (first min(len, N) elements), and the wrapper check holds it to that
    text: without the min, with another bound, or from the whole array,
    it is refused."""
    m = load(tmp_path, BASE)
    cpp = render_wrapper(m)[wrapper_files(m).api_source]
    conv = ("inline void from_c(const struct ros_seq_float64_4 *c, std::vector<double> &r)\n{\n"
            "    r.assign(c->data, c->data + std::min<std::size_t>(c->len, 4));\n}\n")
    assert cpp.count(conv) == 1
    assert ("    r.assign(reinterpret_cast<const char *>(c->data), std::min<std::size_t>(c->len, 128));\n"
            in cpp)
    check_wrapper(cpp, model_text(m), wrapper_name="w.cpp")
    for old, new in (("std::min<std::size_t>(c->len, 4)", "c->len"),
                     ("std::min<std::size_t>(c->len, 4)", "std::min<std::size_t>(c->len, 5)"),
                     ("std::min<std::size_t>(c->len, 4)", "std::min<std::size_t>(c->len, 3)"),
                     ("r.assign(c->data, c->data + std::min<std::size_t>(c->len, 4));",
                      "r.assign(c->data, c->data + 4);"),
                     ("std::min<std::size_t>(c->len, 128)", "c->len")):
        assert cpp.count(old) == 1, old
        with pytest.raises(WrapperMismatch) as exc:
            check_wrapper(cpp.replace(old, new), model_text(m), wrapper_name="w.cpp")
        assert "into a published" in "\n".join(exc.value.lines), exc.value.lines


def test_a_length_alone_publishes_zeros(tmp_path):
    """A length relation without element relations is allowed: the
    elements are the output glue's zeros."""
    text = swap(BASE, '    - {output: E0, topic: /out, field: "data[0]"}\n', "")
    text = swap(text, '    - {output: E3, topic: /out, field: "data[3]"}\n', "")
    m = load(tmp_path, text)
    assert [str(r.path) for r in m.output_relations if r.topic.name == "/out"] == ["data.len"]


def test_subscribed_and_published_topics_of_one_type_share_the_struct(tmp_path):
    """One struct per message type: a subscribed Float64MultiArray gets the
    published one's maximum; the input relation reads the element the
    output relation writes on the other topic."""
    text = swap(BASE, "  - {name: /cmd,", "  - {name: /seq_in, direction: subscribe, type: std_msgs/Float64MultiArray, "
                                         "queue_size: 1}\n  - {name: /cmd,")
    text = swap(text, "    - {topic: /vals, field: x, input: X}", '    - {topic: /seq_in, field: "data[3]", input: X}')
    m = load(tmp_path, text)
    assert {t.msg_struct for t in m.topics if t.msg_type == "std_msgs/Float64MultiArray"} == {
        "std_msgs_Float64MultiArray"}
    assert [b.name for _, _, b in m.bounded_fields if b.is_seq] == ["ros_seq_float64_4"]
    assert str(m.input_relations[0].path) == "data.data[3]"


def test_check_and_diagram_name_the_published_fields(tmp_path, capsys):
    p = write(tmp_path, BASE)
    assert cli.main(["check", str(p)]) == 0
    out = capsys.readouterr().out
    assert "5 output relations" in out and "std_msgs/Float64MultiArray data (float64[], at most 4)" in out
    dot = tmp_path / "d.dot"
    assert cli.main(["diagram", str(p), "-o", str(dot), "--format", "dot"]) == 0
    text = dot.read_text()
    for label in ("data (length) : uint32", "data[3] : float64", "header.frame_id[0] : uint8",
                  "header.frame_id (length) : uint32"):
        assert label in text, label


# --------------------------------------------------------------------------
# Refused


def test_an_index_at_or_past_the_maximum(tmp_path):
    for index in ("4", "5", "999999999"):
        text = swap(BASE, '"data[3]"', f'"data[{index}]"')
        assert one(tmp_path, text) == (
            *at(text, f'"data[{index}]"'),
            f"relations.outputs[2].field: field path 'data[{index}]': index {index} is beyond the maximum length of "
            f"'data': the node carries at most 4 of its elements (max_length, default 128); valid indices are "
            f"0..3 {_OUT}", "4.15")
    text = swap(BASE, '"header.frame_id[0]"', '"header.frame_id[128]"')
    got = one(tmp_path, text)
    assert got[3] == "4.15" and "index 128 is beyond the maximum length of 'header.frame_id'" in got[2], got


@pytest.mark.parametrize("prim", ["float64", "uint8", "int32", "uint64", "bool"])
def test_the_length_comes_from_a_uint32_output(tmp_path, prim):
    text = swap(BASE, "NS: uint32", f"NS: {prim}")
    assert one(tmp_path, text) == (*at(text, "NS, topic: /out"), "relations.outputs[0].output: the length of a "
                                   f"published variable-length array is a uint32: controller output 'NS' is {prim} "
                                   "(relations never convert)", "4.15")
    text = swap(BASE, "BL: uint32", f"BL: {prim}")
    got = one(tmp_path, text)
    assert got[:2] == at(text, "BL, topic: /cmd") and got[3] == "4.15", got
    assert "the length of a published string is a uint32" in got[2], got


def test_truncated_is_not_written(tmp_path):
    text = swap(BASE, "field: data, derived: length}", "field: data, derived: truncated}")
    line, col = at(text, "truncated}")
    assert one(tmp_path, text) == (line, col, "relations.outputs[0].derived: an output relation does not write truncated: on "
                        "publish it is meaningless (the subscriber receives the first min(length, N) elements and the "
                        "environment model recomputes the flag); write the length with derived: length", "4.15")
    # a path into the C struct's flag is refused too
    text = swap(BASE, "field: data, derived: length}", "field: data.truncated}")
    got = one(tmp_path, text)
    assert got[3] == "4.15" and "a path does not go inside it ('truncated': len, truncated and data are fields " \
        "of its C struct, not of the ROS message); name one of its elements ('data[0]') or use derived: length (" \
        in got[2], got


@pytest.mark.parametrize("value, shown", [("is_new", "'is_new'"), ("age_ms", "'age_ms'"), ("Length", "'Length'"),
                                          ("[length]", "a list"), ("7", "int '7'")])
def test_other_derived_kinds_are_refused(tmp_path, value, shown):
    text = swap(BASE, "field: data, derived: length}", f"field: data, derived: {value}}}")
    found = diags(tmp_path, text)
    line, col = at(text, f"derived: {value}}}")
    assert found[0][:2] == (line, col + len("derived: ")) and found[0][3] == "4.15", found
    assert found[0][2].startswith("relations.outputs[0].derived: an output relation takes derived: length only "
                                  "(the length of a published variable-length array or string, from a uint32 "
                                  f"output), got {shown}"), found


def test_a_whole_array_or_string_into_a_scalar(tmp_path):
    text = swap(BASE, '{output: E0, topic: /out, field: "data[0]"}', "{output: E0, topic: /out, field: data}")
    assert one(tmp_path, text) == (*at(text, "data}"), "relations.outputs[1].field: field path 'data': 'data' is a "
                                   "variable-length array (float64[]); an output relation writes one of its elements "
                                   "('data[0]', a float64) or its length (derived: length, from a uint32 output) "
                                   f"{_OUT}", "4.15")
    text = swap(BASE, '{output: B0, topic: /cmd, field: "header.frame_id[0]"}',
                "{output: B0, topic: /cmd, field: header.frame_id}")
    got = one(tmp_path, text)
    assert got[3] == "4.15" and "'header.frame_id' is a string; an output relation writes one of its bytes " \
        "('header.frame_id[0]', a uint8) or its length" in got[2], got


@pytest.mark.parametrize("prim", ["float32", "int64", "uint8"])
def test_an_element_takes_an_output_of_its_type(tmp_path, prim):
    text = swap(BASE, "E3: float64", f"E3: {prim}")
    assert one(tmp_path, text) == (*at(text, '{output: E3, topic: /out'), "relations.outputs[2]: type mismatch: "
                                   f"controller output 'E3' is {prim} but field 'data.data[3]' of topic '/out' is "
                                   "float64 (relations never convert)", "4.15")


@pytest.mark.parametrize("prim", ["int8", "uint32", "float64", "bool"])
def test_a_string_byte_takes_a_uint8_output(tmp_path, prim):
    text = swap(BASE, "B0: uint8", f"B0: {prim}")
    assert one(tmp_path, text) == (*at(text, '{output: B0, topic: /cmd'), "relations.outputs[3]: a string related to "
                                   f"a non-uint8 field: controller output 'B0' is {prim} but 'header.frame_id[0]' of "
                                   "topic '/cmd' is a byte of a string (uint8) (a published string takes its bytes "
                                   "from uint8 outputs and its length from a uint32 output, derived: length)", "4.15")


def test_elements_need_a_length(tmp_path):
    text = swap(BASE, "    - {output: NS, topic: /out, field: data, derived: length}\n", "")
    assert one(tmp_path, text) == (*at(text, '"data[0]"'), "relations.outputs[0].field: the controller writes "
                                   "elements of the published variable-length array 'data' of topic '/out' but not "
                                   "its length: add {output: <a uint32 output>, topic: /out, field: data, derived: "
                                   "length} (the subscriber receives the first min(length, N) elements, N its "
                                   "max_length)", "4.15")
    text = swap(BASE, "    - {output: BL, topic: /cmd, field: header.frame_id, derived: length}\n", "")
    got = one(tmp_path, text)
    assert got[:2] == at(text, '"header.frame_id[0]"') and got[3] == "4.15", got
    assert "elements of the published string 'header.frame_id' of topic '/cmd' but not its length" in got[2], got


@pytest.mark.parametrize("const", ["frame_id: base_link", "strings: {header.frame_id: base_link}"])
def test_a_string_from_the_controller_has_no_constant(tmp_path, const):
    text = swap(BASE, "type: geometry_msgs/TwistStamped, queue_size: 1}",
                f"type: geometry_msgs/TwistStamped, queue_size: 1, {const}}}")
    found = diags(tmp_path, text)
    assert [d[3] for d in found] == ["4.15", "4.15"], found
    key = "topics[2].frame_id" if const.startswith("frame_id") else "topics[2].strings['header.frame_id']"
    assert found[0] == (*at(text, '"header.frame_id[0]"'), "relations.outputs[3].field: the string "
                        f"'header.frame_id' of topic '/cmd' has a constant ({key}, line {at(text, const)[0]}); a published string comes "
                        "from a constant or from controller outputs, not both", "4.15")
    assert found[1][:2] == at(text, "header.frame_id, derived: length"), found


def test_a_field_is_written_once(tmp_path):
    text = swap(BASE, '"data[3]"', '"data[0]"')
    got = one(tmp_path, text)
    assert got == (*at(text, '"data[0]"}\n    - {output: B0'), "field 'data[0]' of topic '/out' is fed twice (first "
                   f"by the relation at line {at(text, '{output: E0')[0]})", "4.8")
    text = swap(BASE, "    - {output: E0, topic: /out, field: \"data[0]\"}",
                "    - {output: E0, topic: /out, field: \"data[0]\"}\n"
                "    - {output: BL, topic: /out, field: data, derived: length}")
    got = one(tmp_path, text)
    assert got[3] == "4.8" and "field 'data (length)' of topic '/out' is fed twice" in got[2], got


def test_a_length_of_something_that_is_no_sequence(tmp_path):
    text = swap(BASE, "{output: NS, topic: /out, field: data, derived: length}",
                "{output: NS, topic: /out, field: layout.data_offset, derived: length}")
    found = diags(tmp_path, text)
    line, col = at(text, "layout.data_offset")
    assert found[0] == (line, col, "relations.outputs[0].field: field path 'layout.data_offset': 'layout.data_offset' "
                        "is an uint32, not a variable-length array or a string (derived: length is for those) "
                        f"{_OUT}", "4.15")


def test_sequences_of_messages_and_strings_need_their_lengths(tmp_path):
    """``layout.dim`` (MultiArrayDimension[]) and JointState's ``name``
    (string[]) are written element by element with their lengths (rule
    4.15; tests/frontend/test_elem_sequences.py has the rest)."""
    text = swap(BASE, '"data[3]"', '"layout.dim[0].size"').replace("E3: float64", "E3: uint32")
    assert one(tmp_path, text) == (*at(text, '"layout.dim[0].size"'), "relations.outputs[2].field: the controller "
                                   "writes elements of the published variable-length array of messages 'layout.dim' "
                                   "of topic '/out' but not its length: add {output: <a uint32 output>, topic: /out, "
                                   "field: layout.dim, derived: length} (the subscriber receives the first "
                                   "min(length, N) elements, N its max_length)", "4.15")
    text = swap(BASE, "type: std_msgs/Float64MultiArray, queue_size: 1, max_length: {data: 4}",
                'type: sensor_msgs/JointState, queue_size: 1, max_length: {position: 4, name: 2, "name[]": 8}')
    text = swap(text, '"data[3]"', '"name[0]"').replace("field: data, derived", "field: position, derived").replace(
        '"data[0]"', '"position[0]"')
    got = one(tmp_path, text)
    assert got == (*at(text, '"name[0]"'), "relations.outputs[2].field: field path 'name[0]': 'name[0]' is a string "
                   "(an element of a variable-length array of strings (string[])); an output relation writes one of "
                   "its bytes ('name[0][0]', a uint8) or its length (derived: length), or relates it whole to a "
                   "uint8 controller array (topic '/out', sensor_msgs/JointState)", "4.15")


# --------------------------------------------------------------------------
# Hostile input: refused at its place, never reaching C or Coq text


@pytest.mark.parametrize("field", ['"data[0]; abort()"', '"data[-1]"', '"data[0x1]"', '"data[ 1]"', '"data[1]]"',
                                   '"data[\u0661]"', '"data[1].x"', '"data.data[1]"', '"data[1]\\n"', "''"])
def test_hostile_field_texts(tmp_path, capsys, field):
    text = swap(BASE, '"data[3]"', field)
    p = write(tmp_path, text)
    assert cli.main(["check", str(p)]) == 1
    err = capsys.readouterr().err
    assert "Traceback" not in err
    assert re.search(rf"m\.yaml:{at(text, field)[0]}:\d+: error: relations\.outputs\[2\]", err), err
    assert not (tmp_path / "out").exists()


def test_hostile_sequence_field_names_in_a_custom_message(tmp_path, capsys):
    """A custom message whose published sequence has a name that C or Coq
    cannot take is refused when the relation makes it carried."""
    d = tmp_path / "msgs" / "arm_msgs" / "msg"
    d.mkdir(parents=True)
    (d / "Cmd.msg").write_text("float64[] Definition\nfloat64 x\n")
    text = swap(BASE, "type: std_msgs/Float64MultiArray, queue_size: 1, max_length: {data: 4}",
                "type: arm_msgs/Cmd, queue_size: 1")
    text = text.replace('"data[0]"', '"Definition[0]"').replace('"data[3]"', '"Definition[3]"').replace(
        "field: data, derived", "field: Definition, derived").replace("relations:", "msg_paths: [msgs]\nrelations:")
    found = diags(tmp_path, text)
    assert any(rule == "4.5" and "field name 'Definition' of arm_msgs/Cmd cannot be used in generated code" in msg
               for _, _, msg, rule in found), found
    # unread, the same field is dropped and the model is fine
    text = re.sub(r'    - \{output: (NS|E0|E3), topic: /out[^\n]*\n', "", text)
    text = text.replace("{output: E0", "{output: X").replace("max_length: {data: 4}", "")
    text += "    - {output: E0, topic: /out, field: x}\n"
    m = load(tmp_path, text)
    assert [f.name for f in m.message("arm_msgs/Cmd").fields] == ["x"]

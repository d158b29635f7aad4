"""Controller arrays (DESIGN.md rule 4.15, issue 15): a controller input
or output may be a one-dimensional array of a primitive type
(``Scan: float32[8]``, Embedded Coder's ``real32_T Scan[8];``).  A
relation between a whole array of a message (a carried variable-length
array of primitives, a string's bytes, a fixed-size array of primitives)
and a whole controller array of as many elements of the same type
expands into one relation per element (``ranges.data[i] -> Scan[i]``);
``"Scan[3]"`` names one element, so that an array can be fed piecewise.
Every element is fed exactly once.

The accepted models and what they become (relations, the model text and
its parser, the emitted Coq, the layout check, the ACSL contracts,
``check`` and ``diagram``); every refusal with its message, line, column
and rule; ``init`` from an Embedded Coder header with arrays."""

from __future__ import annotations

import re
import shutil
import subprocess
from pathlib import Path

import pytest
import yaml

from pyrosgen import cli
from pyrosgen.frontend.model import ControllerField, MAX_CONTROLLER_ARRAY
from pyrosgen.proof.coqmodel import EmitError, coq_ctrl_ftype, emit_model, render_node_file
from pyrosgen.proof.modeltext import MalformedModelText, model_text, parse_model_text
from pyrosgen.verify.acsl import contracts

from support.frontend import REPO, at, diags, load, one, write

BASE = """\
node: {name: ctrlarr, period_ms: 20}
controller:
  name: Controller
  inputs:
    name: Controller_U
    fields:
      Scan: float32[8]
      N: uint32
      Cov: float64[36]
      Frame: uint8[16]
      Pc: float32[2]
  outputs:
    name: Controller_Y
    fields:
      Min: float32
      Echo: float32[8]
      Len: uint32
      E2: float64[3]
      F: uint8[16]
      FL: uint32
topics:
  - {name: /scan, direction: subscribe, type: sensor_msgs/LaserScan, queue_size: 1,
     max_length: {ranges: 8, header.frame_id: 16}}
  - {name: /pose, direction: subscribe, type: geometry_msgs/PoseWithCovarianceStamped, queue_size: 1}
  - {name: /echo, direction: publish, type: std_msgs/Float32MultiArray, queue_size: 1, max_length: {data: 8}}
  - {name: /min, direction: publish, type: std_msgs/Float32, queue_size: 1}
  - {name: /hdr, direction: publish, type: std_msgs/Header, queue_size: 1, max_length: {frame_id: 16}}
  - {name: /cov, direction: publish, type: geometry_msgs/PoseWithCovariance, queue_size: 1}
relations:
  inputs:
    - {topic: /scan, field: ranges, input: Scan}
    - {topic: /scan, field: ranges, derived: length, input: N}
    - {topic: /pose, field: pose.covariance, input: Cov}
    - {topic: /scan, field: header.frame_id, input: Frame}
    - {topic: /scan, field: "ranges[0]", input: "Pc[1]"}
    - {topic: /scan, field: "ranges[1]", input: "Pc[0]"}
  outputs:
    - {output: Echo, topic: /echo, field: data}
    - {output: Len, topic: /echo, field: data, derived: length}
    - {output: Min, topic: /min, field: data}
    - {output: F, topic: /hdr, field: frame_id}
    - {output: FL, topic: /hdr, field: frame_id, derived: length}
    - {output: "E2[2]", topic: /cov, field: pose.position.x}
"""

#: the relation rows of BASE, by what they relate
ROW_SCAN = "    - {topic: /scan, field: ranges, input: Scan}\n"
ROW_PC1 = '    - {topic: /scan, field: "ranges[0]", input: "Pc[1]"}\n'
ROW_PC0 = '    - {topic: /scan, field: "ranges[1]", input: "Pc[0]"}\n'


def swap(text: str, old: str, new: str) -> str:
    assert text.count(old) == 1, old
    return text.replace(old, new)


def row_at(text: str, row: str) -> tuple[int, int]:
    """The position of a relation row's mapping (its ``{``)."""
    line, col = at(text, row)
    return line, col + row.index("{")


# --------------------------------------------------------------------------
# Accepted


def test_controller_fields_with_arrays(tmp_path):
    m = load(tmp_path, BASE)
    u, y = m.controller.inputs, m.controller.outputs
    assert [(f.name, f.prim, f.size) for f in u.fields] == [
        ("Scan", "float32", 8), ("N", "uint32", None), ("Cov", "float64", 36), ("Frame", "uint8", 16),
        ("Pc", "float32", 2)]
    assert [f.type_text for f in y.fields] == ["float32", "float32[8]", "uint32", "float64[3]", "uint8[16]",
                                               "uint32"]
    assert [f.name for f in u.arrays] == ["Scan", "Cov", "Frame", "Pc"]
    assert u.field("Scan").c_decl == "float Scan[8]" and u.field("N").c_decl == "unsigned int N"
    assert u.field("Pc").leaves == ("Pc[0]", "Pc[1]") and u.field("N").leaves == ("N",)


def test_a_whole_array_expands_into_element_relations(tmp_path):
    m = load(tmp_path, BASE)
    rels = [(r.topic.name, str(r.path), r.input_target, r.field_text) for r in m.input_relations]
    assert rels[:8] == [("/scan", f"ranges.data[{i}]", f"Scan[{i}]", f"ranges[{i}]") for i in range(8)]
    assert rels[8] == ("/scan", "ranges.len", "N", "ranges (length)")
    # a fixed-size array: its elements are leaves of the message itself
    assert rels[9:45] == [("/pose", f"pose.covariance[{i}]", f"Cov[{i}]", f"pose.covariance[{i}]")
                          for i in range(36)]
    # a string: its bytes, zero past its received length (the clamp)
    assert rels[45:61] == [("/scan", f"header.frame_id.data[{i}]", f"Frame[{i}]", f"header.frame_id[{i}]")
                           for i in range(16)]
    # element targets, in any order
    assert rels[61:] == [("/scan", "ranges.data[0]", "Pc[1]", "ranges[0]"),
                         ("/scan", "ranges.data[1]", "Pc[0]", "ranges[1]")]
    assert len(m.input_relations) == 63
    # the relations of one row remember it (the diagram draws one edge)
    assert {r.row for r in m.input_relations[:8]} == {("ranges", "Scan")}
    assert m.input_relations[8].row is None and m.input_relations[61].row is None
    assert m.input_relation("Scan[3]").path.steps == ("ranges", "data", 3)
    assert m.input_relation("Pc[1]").input_index == 1 and m.input_relation("N").input_elem == ()


def test_outputs_expand_too(tmp_path):
    m = load(tmp_path, BASE)
    rels = [(r.output_source, r.topic.name, str(r.path)) for r in m.output_relations]
    assert rels[:8] == [(f"Echo[{i}]", "/echo", f"data.data[{i}]") for i in range(8)]
    assert rels[8:10] == [("Len", "/echo", "data.len"), ("Min", "/min", "data")]
    assert rels[10:26] == [(f"F[{i}]", "/hdr", f"frame_id.data[{i}]") for i in range(16)]
    assert rels[26:] == [("FL", "/hdr", "frame_id.len"), ("E2[2]", "/cov", "pose.position.x")]
    assert m.output_relations[0].output_elem == (0,) and m.output_relations[8].output_elem == ()
    assert {r.row for r in m.output_relations[:8]} == {("Echo", "data")}


def test_a_fixed_size_array_into_a_published_message(tmp_path):
    text = swap(BASE, "      E2: float64[3]\n", "      E2: float64[3]\n      C36: float64[36]\n")
    text += "    - {output: C36, topic: /cov, field: covariance}\n"
    m = load(tmp_path, text)
    cov = [(r.output_source, str(r.path)) for r in m.output_relations if r.output_field == "C36"]
    assert cov == [(f"C36[{i}]", f"covariance[{i}]") for i in range(36)]


def test_an_array_fed_element_by_element_from_several_topics(tmp_path):
    text = swap(BASE, ROW_PC0, '    - {topic: /pose, field: "pose.pose.position.z", input: "Pc[0]"}\n')
    text = swap(text, "Pc: float32[2]", "Pc: float64[2]")
    text = swap(text, ROW_PC1, '    - {topic: /pose, field: "pose.covariance[7]", input: "Pc[1]"}\n')
    m = load(tmp_path, text)
    assert [(r.topic.name, str(r.path), r.input_target) for r in m.input_relations if r.input_field == "Pc"] == [
        ("/pose", "pose.covariance[7]", "Pc[1]"), ("/pose", "pose.pose.position.z", "Pc[0]")]


def test_a_timed_topic_feeds_an_array_with_hold(tmp_path):
    """A relation feeding a controller array has no fallback: on_timeout
    hold (on the topic or the relation) is accepted."""
    text = swap(BASE, "queue_size: 1,\n     max_length", "queue_size: 1, timeout_ms: 100, on_timeout: hold,\n"
                                                          "     max_length")
    m = load(tmp_path, text)
    assert m.fallbacks == () and m.topic("/scan").timeout_ms == 100
    text = swap(BASE, "queue_size: 1,\n     max_length", "queue_size: 1, timeout_ms: 100,\n     max_length")
    for row in (ROW_SCAN, ROW_PC0, ROW_PC1, "    - {topic: /scan, field: header.frame_id, input: Frame}\n"):
        text = swap(text, row, row.replace("}\n", ", on_timeout: hold}\n"))
    text = swap(text, "input: N}", "input: N, on_timeout: 7}")
    m = load(tmp_path, text)
    assert [(f, s.n) for f, s in m.fallbacks] == [("N", 7)]


def test_model_text_and_its_parser(tmp_path):
    m = load(tmp_path, BASE)
    text = model_text(m)
    lines = text.splitlines()
    assert lines[4:18] == [
        "inputs Controller_U ExtU_Controller_T", "input Scan array 8 float32", "input N uint32",
        "input Cov array 36 float64", "input Frame array 16 uint8", "input Pc array 2 float32",
        "outputs Controller_Y ExtY_Controller_T", "output Min float32", "output Echo array 8 float32",
        "output Len uint32", "output E2 array 3 float64", "output F array 16 uint8", "output FL uint32",
        "message ros_time"]
    assert "input_relation scan ranges.data[5] Scan[5]" in lines
    assert "input_relation scan header.frame_id.data[15] Frame[15]" in lines
    assert "input_relation pose pose.covariance[35] Cov[35]" in lines
    assert "input_relation scan ranges.data[0] Pc[1]" in lines
    assert "output_relation Echo[3] echo data.data[3]" in lines
    assert "output_relation E2[2] cov pose.position.x" in lines
    assert "output_relation Min min data" in lines and "input_relation scan ranges.len N" in lines
    pm = parse_model_text(text)
    assert pm.inputs[:2] == [("Scan", "array 8 float32"), ("N", "uint32")]
    assert pm.input_type("Scan[3]") == "float32" and pm.input_type("Scan") == "float32[8]"
    assert pm.input_type("N") == "uint32" and pm.input_type("N[0]") == "?" and pm.input_type("X") == "?"
    assert pm.output_type("E2[2]") == "float64" and pm.output_type("F") == "uint8[16]"
    assert ("scan", "ranges.data[0]", "Pc[1]") in pm.input_relations
    assert ("Echo[7]", "echo", "data.data[7]") in pm.output_relations
    for bad in ("input Scan array 0 float32", "input Scan array 65537 float32", "input Scan array x float32",
                "input Scan array 8", "input Scan list 8 float32", "output Echo array 08 float32"):
        with pytest.raises(MalformedModelText):
            parse_model_text(text.replace("input Scan array 8 float32", bad).replace(
                "output Echo array 8 float32", bad if bad.startswith("output") else "output Echo array 8 float32"))


def test_emitted_coq(tmp_path):
    m = load(tmp_path, BASE)
    e = emit_model(m)
    assert e.inputs[:3] == (('"Scan"', "FTarray (FTprim Pfloat32) 8"), ('"N"', "FTprim Puint32"),
                            ('"Cov"', "FTarray (FTprim Pfloat64) 36"))
    assert e.outputs[0] == ('"Min"', "FTprim Pfloat32")
    v = render_node_file(m, ddc_available=True)
    assert '("Scan", FTarray (FTprim Pfloat32) 8);' in v and '("N", FTprim Puint32);' in v
    # a whole array: one map over zrange, which Coq computes into the
    # element relations (the seam compares the model text it prints)
    assert ('       map (fun i => mkinrel_at "scan" ([PField "ranges"; PField "data"] ++ [PIndex i]) "Scan" [PIndex i])'
            ' (zrange 8) ++\n' in v)
    assert 'mkinrel "scan" [PField "ranges"; PField "len"] "N"]' in v
    assert 'mkinrel_at "scan" [PField "ranges"; PField "data"; PIndex 0] "Pc" [PIndex 1];' in v
    assert ('       map (fun i => mkoutrel_at "Echo" [PIndex i] "echo" ([PField "data"; PField "data"] ++ [PIndex i]))'
            ' (zrange 8) ++\n' in v)
    assert 'mkoutrel "Min" "min" [PField "data"]' in v
    assert 'mkoutrel_at "E2" [PIndex 2] "cov" [PField "pose"; PField "position"; PField "x"]' in v
    # Scan, Cov, Frame as maps, Pc's two elements one by one; Echo and F as maps, E2 one by one
    assert v.count("map (fun i => mkinrel_at ") == 3 and v.count("mkinrel_at ") == 5
    assert v.count("map (fun i => mkoutrel_at ") == 2 and v.count("mkoutrel_at ") == 3
    assert sum(int(seg[1][3]) if seg[0] == "map" else len(seg[1]) for seg in e.inrel_segments) == len(e.inrels)
    # the emitter refuses sizes Coq's well-formedness refuses
    for size in (0, MAX_CONTROLLER_ARRAY + 1, True, "8"):
        with pytest.raises(EmitError):
            coq_ctrl_ftype(ControllerField("X", "float32", size))
    assert coq_ctrl_ftype(ControllerField("X", "uint8", MAX_CONTROLLER_ARRAY)) == "FTarray (FTprim Puint8) 65536"


def test_scalar_models_keep_mkinrel(tmp_path):
    """A model without controller arrays emits what it did (but scalars in
    FTprim): no mkinrel_at, no array line."""
    from pyrosgen import load_model

    m = load_model(REPO / "examples" / "landshark" / "landshark_controller.yaml")
    v = render_node_file(m, ddc_available=True)
    assert "_at " not in v and '("In1", FTprim Pfloat64)' in v
    assert "array" not in "".join(ln for ln in model_text(m).splitlines() if ln.startswith(("input ", "output ")))


def test_acsl_contracts_name_the_elements(tmp_path):
    """The element relations are direct (rule 4.16: untimed topics): the
    callbacks' contracts assign and state them, from ``*msg``; input_glue's
    only the length."""
    m = load(tmp_path, BASE)
    cs = {c.name: c for c in contracts(m)}
    glue = cs["input_glue"]
    assert glue.assigns == ("Controller_U.N",)
    assert glue.ensures == ("Controller_U.N == \\old(scan_msg.ranges.len)",)
    scan = cs["scan_callback"]
    assert "Controller_U.Scan[7]" in scan.assigns and "Controller_U.Pc[1]" in scan.assigns
    assert ("{ rosgen_wp_f32 \\with .v = Controller_U.Scan[2] } == "
            "{ rosgen_wp_f32 \\with .v = \\old(msg->ranges.data[2]) }") in scan.ensures
    assert ("{ rosgen_wp_f32 \\with .v = Controller_U.Pc[1] } == "
            "{ rosgen_wp_f32 \\with .v = \\old(msg->ranges.data[0]) }") in scan.ensures
    assert "Controller_U.Frame[3] == \\old(msg->header.frame_id.data[3])" in scan.ensures
    assert "\\valid_read(&msg->header.frame_id.data[15])" in scan.requires
    assert "Controller_U.Cov[35]" in cs["pose_callback"].assigns
    echo = cs["output_glue_echo"]
    assert ("{ rosgen_wp_f32 \\with .v = command->data.data[6] } == "
            "{ rosgen_wp_f32 \\with .v = \\old(Controller_Y.Echo[6]) }") in echo.ensures
    assert any("\\old(Controller_Y.E2[2])" in e for e in cs["output_glue_cov"].ensures)


def test_layout_check_compares_arrays_by_address(tmp_path):
    """The layout check compares an array member through its address
    (element type and size) and is compiled against headers that agree
    or not."""
    from pyrosgen.ros.layout import render_layout_check, render_reference_header

    m = load(tmp_path, BASE)
    types_h = _types_header(m)
    check = render_layout_check(m, types_h, "ctrlarr_types.h")
    assert ("_Static_assert(_Generic(&Controller_U.Scan, __typeof__(&((struct pyrosgen_glue_ExtU_Controller_T *)0)"
            "->Scan): 1, default: 0),\n               \"pyrosgen layout: Controller_U.Scan: type is not float[8] "
            "(the model says float32[8])\");") in check
    assert "_Generic(Controller_U.N, __typeof__(((struct pyrosgen_glue_ExtU_Controller_T *)0)->N)" in check
    work = tmp_path / "layout"
    work.mkdir()
    (work / "check.c").write_text(check)
    (work / "ref").mkdir()
    (work / "ref" / "Controller.h").write_text(render_reference_header(m, types_h))
    assert _gcc(work / "check.c", work / "ref").returncode == 0
    good = _user_header(m)
    for name, text, problem in (
            ("ok", good, None),
            ("size", good.replace("real32_T Scan[8];", "real32_T Scan[9];"), "Controller_U.Scan: type is not float[8]"),
            ("elem", good.replace("real32_T Scan[8];", "real_T Scan[8];"), "Controller_U.Scan: type is not float[8]"),
            ("scalar", good.replace("real32_T Scan[8];", "real32_T Scan;"), "Controller_U.Scan: type is not"),
            ("bytes", good.replace("uint8_T F[16];", "int8_T F[16];"), "Controller_Y.F: type is not unsigned char[16]")):
        d = work / name
        d.mkdir()
        shutil.copyfile(REPO / "examples" / "landshark" / "controller" / "rtwtypes.h", d / "rtwtypes.h")
        (d / "Controller.h").write_text(text)
        r = _gcc(work / "check.c", d)
        if problem is None:
            assert r.returncode == 0, r.stderr
        else:
            assert r.returncode != 0 and problem in r.stderr, (name, r.stderr)


def _types_header(m) -> str:
    """The structs Coq would print for ``m``'s controller (enough for the
    layout check, which reads only ExtU/ExtY): each field as C declares it."""
    out = ["#ifndef T_H", "#define T_H"]
    for io in (m.controller.inputs, m.controller.outputs):
        out.append(f"struct {io.struct_name} {{")
        out += [f"  {f.c_decl};" for f in io.fields]
        out.append("};")
    out.append("#endif")
    return "\n".join(out) + "\n"


def _user_header(m) -> str:
    lines = ['#include "rtwtypes.h"']
    for io, tag in ((m.controller.inputs, "ExtU"), (m.controller.outputs, "ExtY")):
        lines.append("typedef struct {")
        lines += [f"  {f.simulink_type} {f.name}{'' if f.size is None else f'[{f.size}]'};" for f in io.fields]
        lines.append(f"}} {tag}_Controller_T;")
    lines += ["extern ExtU_Controller_T Controller_U;", "extern ExtY_Controller_T Controller_Y;",
              "extern void Controller_initialize(void);", "extern void Controller_step(void);"]
    return "\n".join(lines) + "\n"


def _gcc(src: Path, include: Path) -> subprocess.CompletedProcess:
    return subprocess.run(["gcc", "-std=c11", "-Wall", "-Wextra", "-pedantic", "-fsyntax-only", "-I", str(include),
                           str(src)], capture_output=True, text=True, check=False)


def test_check_and_diagram(tmp_path, capsys):
    p = write(tmp_path, BASE)
    assert cli.main(["check", str(p)]) == 0
    out = capsys.readouterr().out
    assert "63 input relations (from 6 rows), 28 output relations (from 6 rows)" in out
    assert ("7 controller arrays: input Scan (float32[8]), input Cov (float64[36]), input Frame (uint8[16]), "
            "input Pc (float32[2]), output Echo (float32[8]), output E2 (float64[3]), output F (uint8[16])") in out
    dot = tmp_path / "d.dot"
    assert cli.main(["diagram", str(p), "-o", str(dot)]) == 0
    text = dot.read_text()
    assert "Scan : float32[8]" in text and "E2 : float64[3]" in text
    # one edge per row as written, not one per element
    assert len(re.findall(r'id="in_rel\d+"', text)) == 6 and len(re.findall(r'id="out_rel\d+"', text)) == 6
    assert "label=<ranges : float32[8]>" in text and "label=<pose.covariance : float64[36]>" in text
    assert "label=<ranges[0] (element 1) : float32>" in text
    assert "label=<data : float32[8]>" in text and "label=<frame_id : uint8[16]>" in text
    assert "label=<pose.position.x (element 2) : float64>" in text


# --------------------------------------------------------------------------
# Refused: the controller's types


@pytest.mark.parametrize("written, problem", [
    ("float32[0]", "type 'float32[0]': a controller array has a size from 1 to 65536, got 0"),
    ("float32[65537]", "type 'float32[65537]': a controller array has a size from 1 to 65536, got 65537"),
    ("float32[2][4]", "type 'float32[2][4]' is an array of 2 dimensions; a controller array has one"),
    ("float32[]", "type 'float32[]' is a variable-length array; a controller array has a fixed size"),
    ("float32[x]", "type 'float32[x]': the size 'x' is not an integer"),
    ("float32[-1]", "the size '-1' is not an integer"),
    ("float32[010]", "the size '010' is not an integer"),
])
def test_bad_array_types(tmp_path, written, problem):
    text = swap(BASE, "Scan: float32[8]", f"Scan: {written}")
    line, col, msg, rule = one(tmp_path, text)
    assert (line, col, rule) == (*at(text, written), "4.15")
    assert msg.startswith("controller.inputs.fields.Scan: ") and problem in msg, msg


@pytest.mark.parametrize("written, problem", [
    ("string[8]", "type 'string[8]' is not allowed: a controller array has elements of a primitive type"),
    ("char[8]", "type 'char[8]': 'char' is a deprecated ROS alias; write uint8[8]"),
    ("geometry_msgs/Point[8]", "is not allowed: a controller array has elements of a primitive type"),
    ("float[8]", "unknown element type 'float' in 'float[8]' (did you mean 'float64'?)"),
])
def test_bad_element_types(tmp_path, written, problem):
    """Rule 4.3's element types; the relations naming the refused field
    are not checked further (no cascade)."""
    text = swap(BASE, "Scan: float32[8]", f"Scan: {written}")
    line, col, msg, rule = one(tmp_path, text)
    assert (line, col, rule) == (*at(text, written), "4.3") and problem in msg, msg


def test_the_largest_array_is_accepted(tmp_path):
    text = swap(BASE, "      Min: float32\n", f"      Min: float32\n      Big: uint8[{MAX_CONTROLLER_ARRAY}]\n")
    m = load(tmp_path, text)
    assert m.controller.outputs.field("Big").size == MAX_CONTROLLER_ARRAY


def test_a_block_diagram_has_scalar_fields(tmp_path):
    text = """\
node: {name: dg, period_ms: 20}
controller:
  name: Controller
  inputs: {name: Controller_U, fields: {A: float64, V: "float64[2]"}}
  outputs: {name: Controller_Y, fields: {Y: float64}}
  blocks:
    - {name: G, type: Gain, input: A, gain: 2}
  outports: {Y: G}
topics:
  - {name: /p, direction: subscribe, type: geometry_msgs/Point, queue_size: 1}
  - {name: /q, direction: publish, type: geometry_msgs/Point, queue_size: 1}
relations:
  inputs:
    - {topic: /p, field: x, input: A}
    - {topic: /p, field: y, input: "V[0]"}
    - {topic: /p, field: z, input: "V[1]"}
  outputs:
    - {output: Y, topic: /q, field: x}
"""
    line, col, msg, rule = one(tmp_path, text)
    assert (line, col, rule) == (*at(text, "V: "), "4.15")
    assert "a block diagram's inputs and outputs are scalars; the array V (float64[2]) is for a controller " \
           "brought in C" in msg


# --------------------------------------------------------------------------
# Refused: relations


def test_sizes_must_agree(tmp_path):
    text = swap(BASE, "max_length: {ranges: 8,", "max_length: {ranges: 7,")
    line, col, msg, rule = one(tmp_path, text)
    assert (line, col, rule) == (*row_at(text, ROW_SCAN), "4.15")
    assert msg == ("relations.inputs[0]: field 'ranges' of topic '/scan' is float32[] of at most 7 but controller "
                   "input 'Scan' is float32[8]: the sizes differ: give the field max_length 8 on the topic "
                   "(max_length: {ranges: 8}), or declare Scan float32[7]")
    text = swap(BASE, "Cov: float64[36]", "Cov: float64[35]")
    line, col, msg, rule = one(tmp_path, text)
    assert (line, rule) == (at(text, "field: pose.covariance, input: Cov")[0], "4.15")
    assert "field 'pose.covariance' of topic '/pose' is float64[36] but controller input 'Cov' is float64[35]: " \
           "the sizes differ" in msg
    text = swap(BASE, "Echo: float32[8]", "Echo: float32[7]")
    line, col, msg, rule = one(tmp_path, text)
    assert (line, rule) == (at(text, "{output: Echo, topic: /echo, field: data}")[0], "4.15")
    assert msg == ("relations.outputs[0]: controller output 'Echo' is float32[7] but field 'data' of topic '/echo' "
                   "is float32[] of at most 8: the sizes differ: give the field max_length 7 on the topic "
                   "(max_length: {data: 7}), or declare Echo float32[8]")


def test_element_types_must_agree(tmp_path):
    for old, new, want in (
            ("Scan: float32[8]", "Scan: float64[8]",
             "field 'ranges' of topic '/scan' is float32[] of at most 8 but controller input 'Scan' is float64[8]: "
             "the element types differ (relations never convert)"),
            ("Cov: float64[36]", "Cov: float32[36]",
             "field 'pose.covariance' of topic '/pose' is float64[36] but controller input 'Cov' is float32[36]: "
             "the element types differ"),
            ("Frame: uint8[16]", "Frame: int8[16]",
             "field 'header.frame_id' of topic '/scan' is a string of at most 16 bytes (uint8) but controller input "
             "'Frame' is int8[16]: a string meets a controller array as its bytes, uint8"),
            ("Echo: float32[8]", "Echo: float64[8]",
             "controller output 'Echo' is float64[8] but field 'data' of topic '/echo' is float32[] of at most 8: "
             "the element types differ"),
            ("F: uint8[16]", "F: uint16[16]",
             "controller output 'F' is uint16[16] but field 'frame_id' of topic '/hdr' is a string of at most 16 "
             "bytes (uint8): a string meets a controller array as its bytes, uint8")):
        text = swap(BASE, old, new)
        _, _, msg, rule = one(tmp_path, text)
        assert rule == "4.15" and want in msg, msg
    # an element of another type than the message leaf's (rule 4.7's message)
    text = swap(BASE, "Pc: float32[2]", "Pc: float64[2]")
    found = diags(tmp_path, text)
    assert [(ln, r) for ln, _, _, r in found] == [(at(text, ROW_PC1)[0], "4.15"), (at(text, ROW_PC0)[0], "4.15")]
    assert "field 'ranges[0]' of topic '/scan' is float32 but controller input 'Pc' is float64" in found[0][2]


def test_a_whole_array_and_a_scalar(tmp_path):
    # a controller array related to a scalar field
    text = swap(BASE, ROW_SCAN, '    - {topic: /scan, field: "ranges[3]", input: Scan}\n')
    line, col, msg, rule = one(tmp_path, text)
    assert (line, col, rule) == (*row_at(text, '    - {topic: /scan, field: "ranges[3]"'), "4.15")
    assert msg == ("relations.inputs[0]: controller input 'Scan' is an array (float32[8]) but field 'ranges[3]' of "
                   "topic '/scan' is one float32: relate a whole array of 8 float32 to it, or the field to one "
                   "element ('Scan[0]')")
    text = swap(BASE, "{output: \"E2[2]\", topic: /cov, field: pose.position.x}",
                "{output: E2, topic: /cov, field: pose.position.x}")
    _, _, msg, rule = one(tmp_path, text)
    assert rule == "4.15" and "controller output 'E2' is an array (float64[3]) but field 'pose.position.x'" in msg
    # a whole fixed-size array related to a scalar input (and the array left unfed)
    text = swap(BASE, "field: pose.covariance, input: Cov}", "field: pose.covariance, input: N}")
    found = diags(tmp_path, text)
    assert (at(text, "pose.covariance, input: N")[0], at(text, "pose.covariance, input: N")[1], "4.15") in [
        (ln, c, r) for ln, c, _, r in found]
    assert any("'pose.covariance' of topic '/pose' is a whole array (float64[36]) but controller input 'N' is one "
               "uint32: relate one element ('pose.covariance[0]'), or the whole array to a controller array of 36 "
               "float64" in m for _, _, m, _ in found)
    assert any("controller input 'Cov' (float64[36]) is not fed by any input relation" in m for _, _, m, _ in found)
    # a whole variable-length array related to a scalar: as before (rule 4.15)
    text = swap(BASE, "field: ranges, derived: length, input: N}", "field: ranges, input: N}")
    _, _, msg, rule = one(tmp_path, text)
    assert rule == "4.15" and "'ranges' is a variable-length array (float32[]); a relation reads one of its" in msg
    # the whole published array into a scalar output
    text = swap(BASE, "{output: Min, topic: /min, field: data}", "{output: Min, topic: /echo, field: data}")
    found = diags(tmp_path, text)
    assert any(r == "4.15" and "'data' is a variable-length array" in m for _, _, m, r in found), found
    # derived: length into a whole array
    text = swap(BASE, "derived: length, input: N}", "derived: length, input: Scan}")
    found = diags(tmp_path, text)
    assert ("relations.inputs[1].input: length is one uint32 but controller input 'Scan' is an array "
            "(float32[8]): relate it to a scalar input, or to one element ('Scan[0]')") in [m for _, _, m, _ in found]
    assert "controller input 'N' is not fed by any input relation" in [m for _, _, m, _ in found]


def test_element_names(tmp_path):
    # an index beyond the array (the element it meant is left unfed)
    text = swap(BASE, 'input: "Pc[1]"', 'input: "Pc[2]"')
    found = diags(tmp_path, text)
    assert found == [
        (*at(text, "Pc: "), "element 1 of controller input 'Pc' (float32[2]) is not fed by any input relation; "
                            "each element of a controller array is fed exactly once", "4.15"),
        (*at(text, '"Pc[2]"'), "relations.inputs[4].input: index 2 is beyond controller input 'Pc' (float32[2]): "
                               "valid indices are 0..1", "4.15")]
    text = swap(BASE, 'output: "E2[2]"', 'output: "E2[3]"')
    assert one(tmp_path, text) == (*at(text, '"E2[3]"'), "relations.outputs[5].output: index 3 is beyond "
                                   "controller output 'E2' (float64[3]): valid indices are 0..2", "4.15")
    # Name[i] on a scalar
    text = swap(BASE, "{output: Min, topic: /min, field: data}", '{output: "Min[0]", topic: /min, field: data}')
    assert one(tmp_path, text) == (*at(text, '"Min[0]"'), "relations.outputs[2].output: 'Min[0]' names an element "
                                   "of controller output 'Min', which is not an array (it is a float32): write "
                                   "'Min'", "4.15")
    text = swap(BASE, "derived: length, input: N}", 'derived: length, input: "N[0]"}')
    assert one(tmp_path, text) == (*at(text, '"N[0]"'), "relations.inputs[1].input: 'N[0]' names an element of "
                                   "controller input 'N', which is not an array (it is a uint32): write 'N'", "4.15")
    # other spellings name no field (rule 4.7)
    for bad in ('"Pc[ 1]"', '"Pc[1][0]"', '"Pc[-1]"', '"Pc[01]"', '"Pc [1]"'):
        found = diags(tmp_path, swap(BASE, '"Pc[1]"', bad))
        assert any(r == "4.7" and "is not a controller input" in m for _, _, m, r in found), (bad, found)


def test_each_element_is_fed_exactly_once(tmp_path):
    # two relations into one element
    text = swap(BASE, 'input: "Pc[1]"', 'input: "Pc[0]"')
    found = diags(tmp_path, text)
    assert found == [
        (*at(text, "Pc: "), "element 1 of controller input 'Pc' (float32[2]) is not fed by any input relation; "
                            "each element of a controller array is fed exactly once", "4.15"),
        (*at(text, '"Pc[0]"', 1), "element 0 of controller input 'Pc' is fed twice (first by the relation at line "
                                  f"{at(text, ROW_PC1.replace('Pc[1]', 'Pc[0]'))[0]}); each element of a controller "
                                  "array is fed exactly once", "4.15")]
    # an element of a whole row fed again
    extra = '    - {topic: /scan, field: "ranges[5]", input: "Scan[5]"}\n'
    text = swap(BASE, ROW_PC1, ROW_PC1 + extra)
    assert one(tmp_path, text) == (*at(text, '"Scan[5]"'), "element 5 of controller input 'Scan' is fed twice (first "
                                   f"by the relation at line {at(text, ROW_SCAN)[0]}); each element of a controller "
                                   "array is fed exactly once", "4.15")
    # a whole row after element rows
    text = swap(BASE, ROW_SCAN, "")
    text = swap(text, ROW_PC1, ROW_PC1 + '    - {topic: /scan, field: "ranges[2]", input: "Scan[2]"}\n'
                + '    - {topic: /scan, field: "ranges[3]", input: "Scan[3]"}\n' + ROW_SCAN)
    line, col, msg, rule = one(tmp_path, text)
    assert (line, rule) == (at(text, ROW_SCAN)[0], "4.15")
    assert msg == ("elements 2..3 of controller input 'Scan' are fed twice (also by the relations at lines "
                   f"{at(text, 'Scan[2]')[0]}, {at(text, 'Scan[3]')[0]}); each element of a controller array is "
                   "fed exactly once")
    # two whole rows
    text = swap(BASE, ROW_PC0, ROW_PC0 + ROW_SCAN)
    _, _, msg, rule = one(tmp_path, text)
    assert rule == "4.15" and msg.startswith("elements 0..7 of controller input 'Scan' are fed twice")


def test_elements_not_fed(tmp_path):
    text = swap(BASE, ROW_PC0, "")
    assert one(tmp_path, text) == (*at(text, "Pc: "), "element 0 of controller input 'Pc' (float32[2]) is not fed "
                                   "by any input relation; each element of a controller array is fed exactly once",
                                   "4.15")
    text = swap(swap(BASE, ROW_PC0, ""), ROW_PC1, "")
    assert one(tmp_path, text) == (*at(text, "Pc: "), "controller input 'Pc' (float32[2]) is not fed by any input "
                                   "relation (relate a whole array to it, or each element Pc[i])", "4.15")
    text = swap(BASE, "Pc: float32[2]", "Pc: float32[6]")
    text = swap(text, ROW_PC1, ROW_PC1 + '    - {topic: /scan, field: "ranges[4]", input: "Pc[4]"}\n')
    assert one(tmp_path, text) == (*at(text, "Pc: "), "elements 2..3, 5 of controller input 'Pc' (float32[6]) are "
                                   "not fed by any input relation; each element of a controller array is fed "
                                   "exactly once", "4.15")


def test_no_fallback_into_an_array(tmp_path):
    timed = swap(BASE, "queue_size: 1,\n     max_length", "queue_size: 1, timeout_ms: 100,\n     max_length")
    found = diags(tmp_path, timed)
    assert [(ln, r) for ln, _, _, r in found] == [(at(timed, ROW_SCAN)[0], "4.15"),
                                                  (at(timed, "field: header.frame_id, input: Frame")[0], "4.15"),
                                                  (at(timed, ROW_PC1)[0], "4.15"), (at(timed, ROW_PC0)[0], "4.15")]
    assert found[0][2] == ("relations.inputs[0].input: topic '/scan' has a timeout with on_timeout zero, which "
                           "gives each input it feeds a fallback, but 'Scan' is the array Scan (float32[8]), which "
                           "has none (fallbacks feed scalar inputs): write on_timeout: hold on this relation or on "
                           "the topic")
    assert "'Pc[1]' is an element of the array Pc (float32[2])" in found[2][2]
    timed_hold = swap(BASE, "queue_size: 1,\n     max_length", "queue_size: 1, timeout_ms: 100, on_timeout: hold,\n"
                                                                "     max_length")
    for value in ("zero", "0.5", "[1, 2]"):
        for base in (BASE, timed_hold):
            text = swap(base, 'input: "Pc[1]"}', f'input: "Pc[1]", on_timeout: {value}}}')
            line, col, msg, rule = one(tmp_path, text)
            key_line, key_col = at(text, f"on_timeout: {value}")
            assert (line, col, rule) == (key_line, key_col + len("on_timeout: "), "4.15")  # at the value
            assert msg == ("relations.inputs[4].on_timeout: controller input 'Pc[1]' is an element of the array Pc "
                           "(float32[2]), which has no fallback (fallbacks feed scalar inputs): write on_timeout: hold")
    text = swap(BASE, ROW_SCAN, ROW_SCAN.replace("}\n", ", on_timeout: hold}\n"))
    _, _, msg, rule = one(tmp_path, text)
    assert rule == "4.12" and "topic '/scan' has no timeout_ms; a fallback needs one" in msg


def test_no_derived_input_into_an_array(tmp_path):
    text = swap(BASE, ROW_PC0, '    - {topic: /scan, derived: is_new, input: "Pc[0]"}\n')
    assert one(tmp_path, text) == (*at(text, '"Pc[0]"'), "relations.inputs[5].input: a derived input feeds a "
                                   "scalar controller input; 'Pc[0]' is an element of the array Pc (float32[2])",
                                   "4.15")
    text = swap(BASE, ROW_SCAN, "    - {topic: /scan, derived: age_ms, input: Scan}\n")
    line, col, msg, rule = one(tmp_path, text)
    assert (line, col, rule) == (*at(text, "Scan}"), "4.15")
    assert msg.endswith("a derived input feeds a scalar controller input; 'Scan' is the array Scan (float32[8])")


def test_published_arrays_still_need_their_length(tmp_path):
    text = swap(BASE, "    - {output: Len, topic: /echo, field: data, derived: length}\n", "")
    line, col, msg, rule = one(tmp_path, text)
    assert (line, col, rule) == (*at(text, "data}"), "4.15")
    assert "the controller writes elements of the published variable-length array 'data' of topic '/echo' but " \
           "not its length" in msg
    # a string from the controller has no constant too
    text = swap(BASE, "max_length: {frame_id: 16}}", "max_length: {frame_id: 16}, strings: {frame_id: base}}")
    found = diags(tmp_path, text)
    assert any(r == "4.15" and "has a constant" in m for _, _, m, r in found), found


def test_a_published_element_written_twice(tmp_path):
    text = swap(BASE, '{output: "E2[2]", topic: /cov, field: pose.position.x}',
                '{output: Min, topic: /echo, field: "data[4]"}')
    assert one(tmp_path, text) == (*at(text, '"data[4]"'), "field 'data[4]' of topic '/echo' is fed twice (first "
                                   f"by the relation at line {at(text, '{output: Echo')[0]})", "4.8")
    text = swap(BASE, "    - {output: Len, topic: /echo, field: data, derived: length}\n",
                "    - {output: Len, topic: /echo, field: data, derived: length}\n"
                "    - {output: Echo, topic: /echo, field: data}\n")
    line, col, msg, rule = one(tmp_path, text)
    assert rule == "4.8" and msg == ("field 'data' of topic '/echo' is fed twice: elements 0..7 are also written by "
                                     f"the relation at line {at(text, '{output: Echo')[0]}")


# --------------------------------------------------------------------------
# init: arrays from the Embedded Coder header


HEADER = """#include "rtwtypes.h"
typedef real_T vec3_T[3];
typedef struct {
  real32_T Scan[8];                    /* '<Root>/Scan' */
  uint32_T N;
  uint8_T Frame[0x10];
%s
} ExtU_Scanner_T;
typedef struct {
  real_T Cmd[6];                       /* '<Root>/Cmd' */
  uint32_T NC;
  vec3_T V;
} ExtY_Scanner_T;
extern ExtU_Scanner_T Scanner_U;
extern ExtY_Scanner_T Scanner_Y;
extern void Scanner_initialize(void);
extern void Scanner_step(void);
"""


def _folder(tmp_path: Path, extra: str = "") -> Path:
    d = tmp_path / "ctl"
    d.mkdir(exist_ok=True)
    shutil.copyfile(REPO / "examples" / "landshark" / "controller" / "rtwtypes.h", d / "rtwtypes.h")
    (d / "Scanner.h").write_text(HEADER % extra)
    return d


def test_init_reads_array_members(tmp_path, capsys):
    d = _folder(tmp_path)
    out = tmp_path / "m.yaml"
    assert cli.main(["init", "--controller", str(d), "-o", str(out)]) == 0
    said = capsys.readouterr().out
    assert "inputs    3: Scan (float32[8]), N (uint32), Frame (uint8[16])" in said
    assert "outputs   3: Cmd (float64[6]), NC (uint32), V (float64[3])" in said
    text = out.read_text()
    got = yaml.safe_load(text)["controller"]
    assert got["inputs"]["fields"] == {"Scan": "float32[8]", "N": "uint32", "Frame": "uint8[16]"}
    assert got["outputs"]["fields"] == {"Cmd": "float64[6]", "NC": "uint32", "V": "float64[3]"}
    assert "      Scan:  float32[8]  # real32_T[8]: '<Root>/Scan'" in text
    assert "      V:     float64[3]  # vec3_T" in text
    assert ('    # - {topic: /scan, field: ranges, input: Scan}    # float32[8]: a whole array of 8 float32 '
            '(max_length 8), or element by element: input: "Scan[0]"') in text
    assert '    # - {topic: /scan, field: header.frame_id, input: Frame}' in text
    assert "max_length: {ranges: 8}" in text
    assert '    # - {output: Cmd, topic: /command, field: data}' in text
    # filled in, the skeleton's controller section is a valid model's
    filled = text.replace("period_ms:    #", "period_ms: 20    #").replace("topics:\n", (
        "topics:\n  - {name: /scan, direction: subscribe, type: sensor_msgs/LaserScan, queue_size: 1, "
        "max_length: {ranges: 8, header.frame_id: 16}}\n"
        "  - {name: /cmd, direction: publish, type: std_msgs/Float64MultiArray, queue_size: 1, "
        "max_length: {data: 6}}\n"
        "  - {name: /pt, direction: publish, type: geometry_msgs/Point, queue_size: 1}\n")).replace("  inputs:      #", (
            "  inputs:\n    - {topic: /scan, field: ranges, input: Scan}\n"
            "    - {topic: /scan, field: ranges, derived: length, input: N}\n"
            "    - {topic: /scan, field: header.frame_id, input: Frame}\n    #")).replace("  outputs:     #", (
                "  outputs:\n    - {output: Cmd, topic: /cmd, field: data}\n"
                "    - {output: NC, topic: /cmd, field: data, derived: length}\n"
                '    - {output: "V[0]", topic: /pt, field: x}\n    #'))
    model = load(tmp_path, filled)
    assert len(model.input_relations) == 8 + 1 + 16 and len(model.output_relations) == 6 + 1 + 1


@pytest.mark.parametrize("member, problem", [
    ("  real_T Z[0];", "ExtU_Scanner_T.Z (real_T[0]): an array of 0 elements: a controller array has 1 to 65536 "
                       "elements (rule 4.15)"),
    ("  real_T Z[65537];", "an array of 65537 elements: a controller array has 1 to 65536 elements (rule 4.15)"),
    ("  real_T Z[2][3];", "ExtU_Scanner_T.Z (real_T[2][3]): an array of arrays: a controller array has one "
                          "dimension (rule 4.15); flatten it"),
    ("  vec3_T Z[2];", "an array of arrays: a controller array has one dimension (rule 4.15)"),
    ("  real_T Z[];", "an array without a size: a controller array has a fixed size (rule 4.15)"),
    ("  real_T Z[2 * 3];", "an array whose size (2 * 3) is not an integer constant (rule 4.15)"),
    ("  creal_T Z[3];", "an array whose elements are not carried: a complex number"),
    ("  char Z[3];", "an array whose elements are not carried: plain char"),
    ("  real_T *Z[3];", "an array whose elements are not carried: a pointer"),
])
def test_init_refuses_arrays_the_glue_cannot_carry(tmp_path, capsys, member, problem):
    d = _folder(tmp_path, member)
    if "creal_T" in member:
        (d / "rtwtypes.h").write_text((d / "rtwtypes.h").read_text().replace(
            "#endif", "typedef struct { real_T re; real_T im; } creal_T;\n#endif"))
    out = tmp_path / "m.yaml"
    assert cli.main(["init", "--controller", str(d), "-o", str(out)]) == 1
    err = capsys.readouterr().err
    assert "(1 problems)" in err and problem in err, err
    assert "Traceback" not in err and not out.exists()


def test_the_largest_header_array(tmp_path, capsys):
    d = _folder(tmp_path, "  uint8_T Z[65536];")
    out = tmp_path / "m.yaml"
    assert cli.main(["init", "--controller", str(d), "-o", str(out)]) == 0
    assert yaml.safe_load(out.read_text())["controller"]["inputs"]["fields"]["Z"] == "uint8[65536]"


def test_the_readme_example(tmp_path, capsys):
    """README section 9's controller-array model (with a node line) is
    accepted, and check says what the README says it says."""
    readme = (REPO / "README.md").read_text()
    start = readme.index("#### Controller arrays")
    block = readme[readme.index("```yaml\n", start) + 8:readme.index("```\n", readme.index("```yaml\n", start))]
    p = write(tmp_path, "node: {name: ex, period_ms: 20}\n" + block)
    assert cli.main(["check", str(p)]) == 0
    out = capsys.readouterr().out
    said = " ".join(readme[start:readme.index("\n#### ", start + 1)].split())
    for part in ("1134 input relations (from 4 rows), 7 output relations (from 2 rows)",
                 "4 controller arrays: input Scan (float32[1081]), input Cov (float64[36]), input Frame (uint8[16]), "
                 "output Cmd (float64[6])"):
        assert part in out and part in said, part


def test_lengths_into_elements(tmp_path):
    """derived: length and truncated are ordinary input relations: they
    may feed elements of a controller array of their type."""
    text = swap(BASE, "      Pc: float32[2]\n", "      Pc: float32[2]\n      Lens: uint32[2]\n      Tr: bool[1]\n")
    text = swap(text, ROW_PC0, ROW_PC0 + '    - {topic: /scan, field: ranges, derived: length, input: "Lens[1]"}\n'
                '    - {topic: /scan, field: header.frame_id, derived: length, input: "Lens[0]"}\n'
                '    - {topic: /scan, field: ranges, derived: truncated, input: "Tr[0]"}\n')
    m = load(tmp_path, text)
    assert [(str(r.path), r.input_target) for r in m.input_relations[-3:]] == [
        ("ranges.len", "Lens[1]"), ("header.frame_id.len", "Lens[0]"), ("ranges.truncated", "Tr[0]")]
    assert "input_relation scan ranges.truncated Tr[0]" in model_text(m).splitlines()
    # of another type: the message of rule 4.15's lengths
    bad = swap(text, "Lens: uint32[2]", "Lens: int32[2]")
    found = diags(tmp_path, bad)
    assert [r for _, _, _, r in found] == ["4.15", "4.15"]
    assert "length related to a non-uint32 field: controller input 'Lens' is int32" in found[0][2]


def test_a_flow_mapping_needs_the_type_quoted(tmp_path):
    """In a flow mapping ``[`` opens a list: the type is quoted there, and
    YAML's error says so."""
    text = swap(BASE, "    fields:\n      Scan: float32[8]\n      N: uint32\n",
                "    fields: {Scan: float32[8], N: uint32,\n             ")
    text = swap(text, "      Cov: float64[36]\n      Frame: uint8[16]\n      Pc: float32[2]\n",
                "Cov: \"float64[36]\", Frame: \"uint8[16]\", Pc: \"float32[2]\"}\n")
    line, col, msg, rule = one(tmp_path, text)
    assert (line, rule) == (at(text, "float32[8]")[0], "4.1")
    assert 'a controller array\'s type, e.g. "float32[8]"' in msg
    m = load(tmp_path, text.replace("{Scan: float32[8],", '{Scan: "float32[8]",'))
    assert m.controller.inputs.field("Scan").size == 8 and m.controller.inputs.field("Cov").size == 36


def test_the_scan_guard_example(capsys):
    """examples/scan_guard: the whole scan into ScanGuard's Scan[1081];
    check says what the README says it says, and the model text lists the
    1081 element relations in index order."""
    path = REPO / "examples" / "scan_guard" / "scan_guard.yaml"
    assert cli.main(["check", str(path)]) == 0
    out = capsys.readouterr().out
    readme = " ".join((REPO / "README.md").read_text().split())
    for part in ("1082 input relations (from 2 rows), 2 output relations",
                 "1 controller array: input Scan (float32[1081])"):
        assert part in out and part in readme, part
    from pyrosgen.frontend.validate import load_model

    lines = model_text(load_model(path)).splitlines()
    rels = [ln for ln in lines if ln.startswith("input_relation scan ranges.data[")]
    assert rels == [f"input_relation scan ranges.data[{i}] Scan[{i}]" for i in range(1081)]
    assert "input Scan array 1081 float32" in lines


def test_the_arm_named_example(capsys):
    """examples/arm_named: each JointState name whole into a uint8[32]
    controller array, positions, velocities and target whole, the efforts
    whole back; check says what the README says, and the model text
    relates byte j of name i to Name_i[j] for every i < 6, j < 32."""
    path = REPO / "examples" / "arm_named" / "arm_named.yaml"
    assert cli.main(["check", str(path)]) == 0
    out = capsys.readouterr().out
    readme = " ".join((REPO / "README.md").read_text().split())
    for part in ("214 input relations (from 13 rows), 7 output relations (from 2 rows)",
                 "4 variable-length arrays: sensor_msgs/JointState name (string[], at most 6 of at most 32 bytes)"):
        assert part in out and part in readme, part
    from pyrosgen.frontend.validate import load_model

    lines = model_text(load_model(path)).splitlines()
    names = [ln for ln in lines if ln.startswith("input_relation joint_states name.data[")]
    assert names == [f"input_relation joint_states name.data[{i}].data[{j}] Name{i}[{j}]"
                     for i in range(6) for j in range(32)]
    assert "input_relation joint_states name.len NNames" in lines
    assert [ln for ln in lines if ln.startswith("output_relation Effort[")] == [
        f"output_relation Effort[{i}] arm_effort data.data[{i}]" for i in range(6)]

"""Unit tests of the Coq emitter (pyrosgen/proof/coqmodel.py) and of the driver's
parsing of Coq's output (pyrosgen/proof/coqdriver.py).  No Coq run here except
one that checks the string escape against Coq itself."""

from __future__ import annotations

from dataclasses import replace

import jinja2
import pytest

from pyrosgen.proof.coqdriver import REFUSAL_MARKER, CoqDriver, CoqError, coq_messages, refusal_message
from pyrosgen.proof.coqmodel import (
    NODE_TEMPLATE,
    TEMPLATE_DIR,
    EmitError,
    coq_comment,
    coq_ident,
    coq_nat,
    coq_path,
    coq_prim,
    coq_ros_name,
    coq_string,
    coq_z,
    emit_model,
    node_file_names,
    render_node_file,
    template_env,
)
from pyrosgen.frontend.model import ControllerField
from pyrosgen.frontend.validate import load_model
from pyrosgen.frontend.msgmodel import FieldPath

from support.generate import LANDSHARK, MULTI, coqc, printed_strings, require_library


# ---------------------------------------------------------------------------
# Literals


def test_coq_string_doubles_quotes():
    assert coq_string("a") == '"a"'
    assert coq_string('a"b') == '"a""b"'
    assert coq_string('""') == '""""""'
    assert coq_string("") == '""'


@pytest.mark.parametrize("bad", ["a\nb", "tab\there", "caf\u00e9", "\x00", "\x7f", 3, None])
def test_coq_string_refuses_non_printable(bad):
    with pytest.raises(EmitError):
        coq_string(bad)


def test_coq_string_escape_agrees_with_coq(tmp_path):
    """Coq reads the literals back as the original strings."""
    require_library()
    samples = ['a"b', '"', 'x""y', "(* not a comment *)", "back\\slash", " sp ace "]
    v = tmp_path / "Esc.v"
    v.write_text(
        "From Coq Require Import String.\nLocal Open Scope string_scope.\n"
        + "".join(f"Eval vm_compute in {coq_string(s)}.\n" for s in samples)
        + "".join(f"Example len{i} : String.length {coq_string(s)} = {len(s)}.\nProof. reflexivity. Qed.\n"
                  for i, s in enumerate(samples))
    )
    assert printed_strings(coqc(v).stdout) == samples


@pytest.mark.parametrize("bad", ['a"b', "a b", "1abc", "", "a-b", "x*)", "\u00e9t\u00e9", "a" * 64, None])
def test_coq_ident_refuses(bad):
    with pytest.raises(EmitError):
        coq_ident(bad)


def test_coq_ident_accepts():
    assert coq_ident("In1") == '"In1"'
    assert coq_ident("_x") == '"_x"'
    assert coq_ident("a" * 63) == '"' + "a" * 63 + '"'


@pytest.mark.parametrize("bad", ['/a"', "/a b", "//a", "/a/", "~p", "/1a", "/a;b", ""])
def test_coq_ros_name_refuses(bad):
    with pytest.raises(EmitError):
        coq_ros_name(bad)


def test_coq_ros_name_accepts():
    assert coq_ros_name("/landshark/gps_velocity") == '"/landshark/gps_velocity"'
    assert coq_ros_name("rel/name") == '"rel/name"'


def test_coq_comment_is_inert():
    c = coq_comment('a (* b *) "c" \\ d\ne \u00e9 -> [35]')
    for token in ("(*", "*)", '"', "\n"):
        assert token not in c
    assert "->" in c and "[35]" in c
    assert c.startswith("a \\x28\\x2a b \\x2a\\x29 \\x22c\\x22 \\x5c d\\x0ae \\xe9")


def test_numbers_and_constructors():
    assert coq_z(35) == "35" and coq_z(-1) == "(-1)" and coq_z(0) == "0"
    assert coq_nat(0) == "0"
    for bad in (-1, 1.5, True, "3"):
        with pytest.raises(EmitError):
            coq_nat(bad)
    with pytest.raises(EmitError):
        coq_z(2.0)
    assert coq_prim("float64") == "Pfloat64" and coq_prim("bool") == "Pbool"
    with pytest.raises(EmitError):
        coq_prim("string")
    assert coq_path(FieldPath(("pose", "covariance", 35), "float64")) == (
        '[PField "pose"; PField "covariance"; PIndex 35]')
    assert coq_path(("a", -2)) == '[PField "a"; PIndex (-2)]'
    with pytest.raises(EmitError):
        coq_path(("a", 'b"'))


# ---------------------------------------------------------------------------
# The model


def test_emit_landshark():
    m = emit_model(load_model(LANDSHARK))
    assert m.name == '"landshark_controller"' and m.period_ms == "20"
    assert m.inputs == (('"In1"', "FTprim Pfloat64"), ('"In2"', "FTprim Pfloat64"), ('"In3"', "FTprim Pfloat64"))
    assert [md.name for md in m.msgs] == [
        '"ros_time"', '"std_msgs_Header"', '"geometry_msgs_Vector3"', '"geometry_msgs_Twist"',
        '"geometry_msgs_TwistStamped"']
    assert m.msgs[1].fields == (('"seq"', "FTprim Puint32"), ('"stamp"', 'FTmsg "ros_time"'))
    t = m.topics[0]
    assert (t.name, t.c_name, t.direction, t.msg, t.queue) == (
        '"/landshark/left_wheel_velocity"', '"landshark_left_wheel_velocity"', "Subscribe",
        '"geometry_msgs_TwistStamped"', "1")
    assert m.inrels[0][:3] == ('"landshark_left_wheel_velocity"',
                               '[PField "twist"; PField "linear"; PField "x"]', '"In1"')
    assert m.outrels[0][:3] == ('"Out1"', '"landshark_control_base_velocity"',
                                '[PField "twist"; PField "linear"; PField "x"]')


def test_emit_arrays_and_durations():
    m = emit_model(load_model(MULTI))
    fields = {md.name: dict(md.fields) for md in m.msgs}
    assert fields['"geometry_msgs_PoseWithCovariance"']['"covariance"'] == "FTarray (FTprim Pfloat64) 36"
    assert fields['"robot_msgs_FusionStatus"']['"wheels"'] == 'FTarray (FTmsg "robot_msgs_WheelState") 2'
    assert fields['"robot_msgs_EStop"']['"hold_time"'] == 'FTmsg "ros_duration"'
    assert fields['"ros_duration"'] == {'"sec"': "FTprim Pint32", '"nsec"': "FTprim Pint32"}


@pytest.mark.parametrize("mutate", [
    lambda m: replace(m, name='x"); Axiom x'),
    lambda m: replace(m, topics=(replace(m.topics[0], name='/a" ++ "b'),) + m.topics[1:]),
    lambda m: replace(m, topics=(replace(m.topics[0], c_name="a b"),) + m.topics[1:]),
    lambda m: replace(m, topics=(replace(m.topics[0], msg_type="geometry_msgs/Twist*)"),) + m.topics[1:]),
    lambda m: replace(m, topics=(replace(m.topics[0], direction="both"),) + m.topics[1:]),
    lambda m: replace(m, topics=(replace(m.topics[0], queue_size=-1),) + m.topics[1:]),
    lambda m: replace(m, controller=replace(m.controller, name="C\n")),
    lambda m: replace(m, controller=replace(m.controller, inputs=replace(
        m.controller.inputs, fields=(ControllerField('In"1', "float64"),)))),
    lambda m: replace(m, controller=replace(m.controller, inputs=replace(
        m.controller.inputs, fields=(ControllerField("In1", "float128"),)))),
    lambda m: replace(m, input_relations=(replace(
        m.input_relations[0], path=FieldPath(("twist", "li near"), "float64")),)),
    lambda m: replace(m, period_ms="20"),
])
def test_emitter_refuses_unprintable_values(mutate):
    """Defence in depth: what the front end should have refused never
    reaches Coq text."""
    with pytest.raises(EmitError):
        emit_model(mutate(load_model(LANDSHARK)))


def test_emitter_prints_semantically_bad_but_printable_models():
    """Semantic rules are Coq's to check: a C keyword or a zero queue is
    printed (and refused by generate, see test_coq_agreement)."""
    m = load_model(LANDSHARK)
    bad = replace(m, period_ms=0, topics=(replace(m.topics[0], queue_size=0),) + m.topics[1:])
    e = emit_model(bad)
    assert e.period_ms == "0" and e.topics[0].queue == "0"


# ---------------------------------------------------------------------------
# The template


def test_template_lists_its_context():
    text = (TEMPLATE_DIR / "node.v.j2").read_text()
    assert text.startswith("{#-")
    head = text.split("#}")[0]
    for var in ("template", "source", "m ", "names", "guard", "ddc_available"):
        assert var in head, var
    assert NODE_TEMPLATE == "coq/templates/node.v.j2"


def test_template_is_strict():
    env = template_env()
    assert env.undefined is jinja2.StrictUndefined and env.trim_blocks and env.lstrip_blocks
    with pytest.raises(jinja2.UndefinedError):
        env.get_template("node.v.j2").render()


@pytest.mark.parametrize("ddc", [True, False])
def test_render_node_file(ddc):
    model = load_model(LANDSHARK)
    text = render_node_file(model, ddc_available=ddc)
    assert text.splitlines()[0] == (
        "(* generated from coq/templates/node.v.j2 with input from landshark_controller.yaml *)")
    assert ("From ROSGen Require DDC Loopproof." in text) == ddc
    assert ("Theorem landshark_controller_ddc" in text) == ddc
    assert "Theorem landshark_controller_wf : Wellformed.wf model = true." in text
    assert 'Definition types_guard : string := "PYROSGEN_LANDSHARK_CONTROLLER_TYPES_H".' in text
    assert text.endswith("\n") and "\t" not in text
    assert "{{" not in text and "{%" not in text


def test_render_source_label_is_inert():
    text = render_node_file(load_model(LANDSHARK), ddc_available=False, source='evil *) "x" (*.yaml')
    first = text.splitlines()[0]
    assert first.startswith("(* generated from") and first.endswith(" *)")
    assert first.count("*)") == 1 and '"' not in first


def test_node_file_names():
    n = node_file_names("landshark_controller")
    assert (n.v_file, n.types_header, n.glue_c, n.sexp) == (
        "landshark_controller.v", "landshark_controller_types.h", "landshark_controller_glue.c",
        "landshark_controller.sexp")
    assert n.guard == "PYROSGEN_LANDSHARK_CONTROLLER_TYPES_H"
    assert (n.theorem_ddc, n.theorem_wf) == ("landshark_controller_ddc", "landshark_controller_wf")
    with pytest.raises(EmitError):
        node_file_names("../x")


# ---------------------------------------------------------------------------
# The driver's parsing


def test_coq_messages():
    out = (
        'File "./Node.v", line 110, characters 2-179:\n'
        "Error: Tactic failure: ROSGen.Generator.generate refused the model:\n"
        '"Generator: period_ms must be positive".\n'
        "\n"
        'File "./Node.v", line 3, characters 0-5:\n'
        "Warning: Notation overridden\n"
        "[notation-overridden,parsing]\n"
        "\n"
        "Error: Compiled library ROSGen.X makes inconsistent assumptions\n"
    )
    msgs = coq_messages(out, lambda f: "shown.v" if f.endswith("Node.v") else f)
    assert msgs == [
        'shown.v:110:3: error: Tactic failure: ROSGen.Generator.generate refused the model: '
        '"Generator: period_ms must be positive".',
        "shown.v:3:1: warning: Notation overridden [notation-overridden,parsing]",
        "error: Compiled library ROSGen.X makes inconsistent assumptions",
    ]
    assert coq_messages("Error: Cannot find a physical path bound to logical path ROSGen.\n") == [
        "error: Cannot find a physical path bound to logical path ROSGen."]
    assert refusal_message(out) == "Generator: period_ms must be positive"
    assert refusal_message(REFUSAL_MARKER + '\n "a ""q"" b".') == 'a "q" b'
    assert refusal_message("Error: something else") is None


def test_check_assumptions():
    CoqDriver.check_assumptions("Closed under the global context\nClosed under the global context\n", ["a", "b"])
    with pytest.raises(CoqError) as info:
        CoqDriver.check_assumptions(
            "Closed under the global context\nAxioms:\nfoo : nat\nbar\n  : forall x, x = x\n", ["a", "b"])
    assert "1 of the theorems a, b depend on axioms" in info.value.summary
    assert info.value.lines == ("  foo : nat", "  bar")
    with pytest.raises(CoqError):
        CoqDriver.check_assumptions("", ["a"])


def test_driver_tool_missing(monkeypatch, tmp_path):
    monkeypatch.setenv("PATH", str(tmp_path))
    with pytest.raises(CoqError, match="coqc not found: run make deps"):
        CoqDriver().check_tools()


# ---------------------------------------------------------------------------
# Runs of element relations (rule 4.15): one map over zrange


SCAN_ARRAY = LANDSHARK.parents[2] / "tests" / "ros" / "models" / "scan_array.yaml"


def test_whole_array_rows_are_printed_as_one_map():
    """`ranges` whole into Scan[8] and Echo[8] whole into `data` are each
    one `map` over `zrange 8`; the element relations written one by one
    (Last[0], Last[1], Pt[0..2]) stay literal."""
    model = load_model(SCAN_ARRAY)
    m = emit_model(model)
    ins = [seg for seg in m.inrel_segments if seg[0] == "map"]
    outs = [seg for seg in m.outrel_segments if seg[0] == "map"]
    assert [s[1][:4] for s in ins] == [('"scan"', '[PField "ranges"; PField "data"]', '"Scan"', "8")]
    assert [s[1][:4] for s in outs] == [('"Echo"', '"echo"', '[PField "data"; PField "data"]', "8")]
    # the segments are the rows again: 8 in the map, the others literal
    assert sum(int(s[1][3]) if s[0] == "map" else len(s[1]) for s in m.inrel_segments) == len(m.inrels)
    assert sum(int(s[1][3]) if s[0] == "map" else len(s[1]) for s in m.outrel_segments) == len(m.outrels)
    text = render_node_file(model, ddc_available=True)
    assert ('map (fun i => mkinrel_at "scan" ([PField "ranges"; PField "data"] ++ [PIndex i]) "Scan" [PIndex i]) '
            "(zrange 8)") in text
    assert '"Scan" [PIndex 3]' not in text
    assert 'mkinrel_at "scan" [PField "ranges"; PField "data"; PIndex 7] "Last" [PIndex 0]' in text


class _Rel:
    def __init__(self, topic, steps, field, index):
        self.topic = type("T", (), {"c_name": topic})()
        self.path = FieldPath(tuple(steps), "float32")
        self.input_field = field
        self.input_index = index


@pytest.mark.parametrize("rels, runs", [
    # a whole array of 5, then a scalar
    ([_Rel("s", ("d", i), "A", i) for i in range(5)] + [_Rel("s", ("n",), "N", None)], [(0, 5)]),
    # too short for a map
    ([_Rel("s", ("d", i), "A", i) for i in range(3)], []),
    # not from index 0: literal
    ([_Rel("s", ("d", i + 1), "A", i + 1) for i in range(5)], []),
    # message index and controller index differ (d[i+1] -> A[i]): literal
    ([_Rel("s", ("d", i + 1), "A", i) for i in range(5)], []),
    # a gap breaks the run: 0..3 is one, 5.. is not from 0
    ([_Rel("s", ("d", i), "A", i) for i in (0, 1, 2, 3, 5, 6, 7, 8)], [(0, 4)]),
    # two arrays back to back
    ([_Rel("s", ("d", i), "A", i) for i in range(4)] + [_Rel("s", ("e", i), "B", i) for i in range(4)],
     [(0, 4), (4, 4)]),
    # another topic or another prefix ends the run
    ([_Rel("s", ("d", i), "A", i) for i in range(4)] + [_Rel("t", ("d", 4), "A", 4)], [(0, 4)]),
])
def test_runs_of_element_relations(rels, runs):
    from pyrosgen.proof.coqmodel import _in_key, _runs
    assert _runs(rels, _in_key) == runs

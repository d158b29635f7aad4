"""Python's validation and Coq's ``generate`` agree.

- Every ``ok_*`` model (tests/frontend/models, tests/generate/models) and
  every example is accepted by Coq's ``generate`` (and ``wf`` holds),
  those with timeouts, fallbacks and derived inputs (rule 4.12) too, and
  Coq's model of them is the front end's.
- Semantically bad models are refused by Coq even when Python's checks are
  bypassed: valid models are mutated in Python (``dataclasses.replace``),
  emitted as Coq terms, and Coq's ``generate`` must compute an ``Error``
  whose message names the culprit.
- Through the whole pipeline, such a model is refused at the coqc step and
  nothing is written.

Each group is checked in one coqc run (a batch file with one ``Example``
and one ``Eval`` per model).
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import pytest

from pyrosgen.proof.coqdriver import ModelRefused
from pyrosgen.proof.coqmodel import render_model_definitions
from pyrosgen.errors import InvalidNodeModel
from pyrosgen.generate import generate_model
from pyrosgen.frontend.model import ControllerField, DerivedRelation, InputRelation, OutputRelation, Scalar
from pyrosgen.frontend.validate import load_model
from pyrosgen.frontend.msgmodel import FieldPath
from pyrosgen.proof.modeltext import compare_model_texts, model_text

from support.generate import (FRESHNESS_MODELS, LANDSHARK, MULTI, OK_MODELS, REPO, coqc, printed_strings,
                              require_library)

VELOCITY_GUARD = REPO / "examples" / "velocity_guard" / "velocity_guard.yaml"

PREAMBLE = """\
From Coq Require Import String List ZArith.
From ROSGen Require Import Errors Syntax Values FloatBits NodeModel Generator.
Import ListNotations.
Local Open Scope string_scope.
Local Open Scope list_scope.

Definition verdict (m : node_model) : string :=
  match generate m with OK _ => "OK" | Error msg => string_of_errmsg msg end.
Definition accepted (m : node_model) : bool :=
  match generate m with OK _ => true | Error _ => false end.
"""


def _batch(tmp_path: Path, models: list, accepted: bool) -> list[str]:
    """Check ``models`` in one coqc run: each is accepted (and ``wf``) or
    refused, by an ``Example``; return the verdicts Coq printed."""
    require_library()
    defs = [(f"m{i}", m) for i, m in enumerate(models)]
    text = [PREAMBLE, render_model_definitions(defs)]
    want = "true" if accepted else "false"
    for name, _ in defs:
        text.append(f"Example {name}_verdict : accepted {name} = {want}.\nProof. vm_compute. reflexivity. Qed.")
        text.append(f"Example {name}_wf : wf {name} = {want}.\nProof. vm_compute. reflexivity. Qed.")
        text.append(f"Eval vm_compute in verdict {name}.")
    v = tmp_path / "Batch.v"
    v.write_text("\n".join(text) + "\n")
    out = coqc(v).stdout
    verdicts = printed_strings(out)
    assert len(verdicts) == len(models), out
    return verdicts


# ---------------------------------------------------------------------------
# Accepted models


def test_ok_models_accepted_by_coq(tmp_path):
    assert len(OK_MODELS) >= 4, OK_MODELS
    models = [load_model(p) for p in OK_MODELS]
    verdicts = _batch(tmp_path, models, accepted=True)
    assert verdicts == ["OK"] * len(models), dict(zip(map(str, OK_MODELS), verdicts))


def test_freshness_models_accepted_by_coq(tmp_path):
    """Rule 4.12 is generated: every model the front end accepts with
    timeouts, fallbacks or derived inputs (the velocity guard, the
    tests/generate/models/ok_fresh_*.yaml) is accepted by Coq's generate
    too, and Coq's model has the front end's timeouts, fallbacks and
    derived inputs (the model text it prints back, compared item by item)."""
    names = {p.name for p in FRESHNESS_MODELS}
    assert {"velocity_guard.yaml", "ok_fresh_policies.yaml", "ok_fresh_flags.yaml",
            "ok_fresh_constants.yaml"} <= names, names
    models = [load_model(p) for p in FRESHNESS_MODELS]
    verdicts = _batch(tmp_path, models, accepted=True)
    assert verdicts == ["OK"] * len(models), dict(zip(map(str, FRESHNESS_MODELS), verdicts))
    texts = _model_texts(tmp_path, models)
    for path, m, text in zip(FRESHNESS_MODELS, models, texts):
        compare_model_texts(model_text(m), text, vfile=path.name)
        assert any(ln.startswith("timeout ") or ln.startswith("derived_input ") for ln in text.splitlines())


def _model_texts(tmp_path: Path, models: list) -> list[str]:
    """The model text (``ModelText.print_model``) Coq prints of each model."""
    require_library()
    defs = [(f"t{i}", m) for i, m in enumerate(models)]
    text = [PREAMBLE.replace("NodeModel Generator.", "NodeModel Generator ModelText."),
            render_model_definitions(defs)]
    text += [f"Eval vm_compute in print_model {name}." for name, _ in defs]
    v = tmp_path / "Texts.v"
    v.write_text("\n".join(text) + "\n")
    return printed_strings(coqc(v).stdout)


# ---------------------------------------------------------------------------
# Mutated models


def _landshark():
    return load_model(LANDSHARK)


def _multi():
    return load_model(MULTI)


def _set_input(m, name, prim=None, new_name=None):
    c = m.controller
    fields = tuple(
        ControllerField(new_name or f.name, prim or f.prim) if f.name == name else f for f in c.inputs.fields
    )
    return replace(m, controller=replace(c, inputs=replace(c.inputs, fields=fields)))


def _set_output(m, name, prim):
    c = m.controller
    fields = tuple(ControllerField(f.name, prim) if f.name == name else f for f in c.outputs.fields)
    return replace(m, controller=replace(c, outputs=replace(c.outputs, fields=fields)))


def _type_mismatch_in():
    return _set_input(_landshark(), "In1", prim="float32")


def _bool_to_uint8():
    return _set_input(_multi(), "EStop", prim="uint8")


def _type_mismatch_out():
    return _set_output(_multi(), "CmdV", "float32")


def _input_fed_twice():
    m = _landshark()
    r = m.input_relations[0]
    extra = InputRelation(r.topic, FieldPath(("twist", "linear", "y"), "float64"), "In1")
    return replace(m, input_relations=m.input_relations + (extra,))


def _input_not_fed():
    m = _landshark()
    return replace(m, input_relations=m.input_relations[:2])


def _unknown_field():
    m = _landshark()
    r = m.input_relations[0]
    bad = replace(r, path=FieldPath(("twist", "linear", "w"), "float64"))
    return replace(m, input_relations=(bad,) + m.input_relations[1:])


def _index_out_of_range():
    m = _multi()
    rels = tuple(
        replace(r, path=FieldPath(("pose", "covariance", 36), "float64")) if r.input_field == "YawVar" else r
        for r in m.input_relations
    )
    return replace(m, input_relations=rels)


def _negative_index():
    m = _multi()
    rels = tuple(
        replace(r, path=FieldPath(("pose", "covariance", -1), "float64")) if r.input_field == "YawVar" else r
        for r in m.input_relations
    )
    return replace(m, input_relations=rels)


def _path_to_struct():
    m = _landshark()
    r = m.input_relations[1]
    bad = replace(r, path=FieldPath(("twist", "linear"), "float64"))
    return replace(m, input_relations=(m.input_relations[0], bad, m.input_relations[2]))


def _subscribed_as_output():
    m = _landshark()
    o = m.output_relations[0]
    return replace(m, output_relations=(replace(o, topic=m.topics[0]),))


def _published_as_input():
    m = _landshark()
    r = m.input_relations[2]
    return replace(m, input_relations=m.input_relations[:2] + (replace(r, topic=m.topics[3]),))


def _published_field_fed_twice():
    m = _landshark()
    o = m.output_relations[0]
    return replace(m, output_relations=(o, OutputRelation("Out1", o.topic, o.path)))


def _unknown_output():
    m = _landshark()
    o = m.output_relations[0]
    return replace(m, output_relations=(replace(o, output_field="Out9"),))


def _duplicate_topic_cname():
    m = _landshark()
    t0, t1 = m.topics[0], m.topics[1]
    return replace(m, topics=(t0, replace(t1, c_name=t0.c_name)) + m.topics[2:])


def _c_keyword_field():
    m = _set_input(_landshark(), "In1", new_name="int")
    r = m.input_relations[0]
    return replace(m, input_relations=(replace(r, input_field="int"),) + m.input_relations[1:])


def _queue_zero():
    m = _landshark()
    return replace(m, topics=(replace(m.topics[0], queue_size=0),) + m.topics[1:])


def _period_zero():
    return replace(_landshark(), period_ms=0)


def _coq_keyword_node():
    return replace(_landshark(), name="fix")


def _messages_out_of_order():
    m = _multi()
    return replace(m, messages=tuple(reversed(m.messages)))


def _guard():
    return load_model(VELOCITY_GUARD)


def _set_topic(m, name, **changes):
    """The model with topic ``name`` changed (in the topics and in the
    relations that name it)."""
    old = m.topic(name)
    new = replace(old, **changes)
    sub = lambda t: new if t is old else t  # noqa: E731
    return replace(m, topics=tuple(map(sub, m.topics)),
                   input_relations=tuple(replace(r, topic=sub(r.topic)) for r in m.input_relations),
                   output_relations=tuple(replace(r, topic=sub(r.topic)) for r in m.output_relations),
                   derived_relations=tuple(replace(r, topic=sub(r.topic)) for r in m.derived_relations))


def _timeout_below_period():
    return _set_topic(_guard(), "/teleop/cmd_vel", timeout_ms=19)


def _timeout_above_a_day():
    return _set_topic(_guard(), "/nav/cmd_vel", timeout_ms=86_400_001)


def _timeout_on_published():
    return _set_topic(_guard(), "/cmd_vel", timeout_ms=500)


def _fallback_of_another_type():
    m = _guard()
    rels = tuple(replace(r, fallback=Scalar("float32", 0)) if r.input_field == "TVx" else r
                 for r in m.input_relations)
    return replace(m, input_relations=rels)


def _fallback_without_timeout():
    # teleop stays timed (its age_ms) but has no timeout: its fallbacks are refused
    return _set_topic(_guard(), "/teleop/cmd_vel", timeout_ms=None)


def _derived_of_another_type():
    m = _guard()
    return replace(m, derived_relations=tuple(replace(r, kind="is_new") if r.input_field == "TAge" else r
                                              for r in m.derived_relations))


def _derived_of_published():
    m = _guard()
    return replace(m, derived_relations=tuple(replace(r, topic=m.topic("/cmd_vel")) if r.input_field == "NAge"
                                              else r for r in m.derived_relations))


def _fed_by_relation_and_derived():
    m = _guard()
    extra = DerivedRelation(m.topic("/nav/cmd_vel"), "age_ms", "TAge")
    return replace(m, derived_relations=m.derived_relations + (extra,))


def _derived_dropped():
    m = _guard()
    return replace(m, derived_relations=m.derived_relations[1:])


#: (mutation, fragment of Coq's message naming the culprit)
MUTATIONS = [
    (_type_mismatch_in, "type mismatch in input relation: 'landshark_left_wheel_velocity.twist.linear.x' "
                        "is float64 but controller input 'In1' is float32"),
    (_bool_to_uint8, "'safety_estop.engaged' is bool but controller input 'EStop' is uint8"),
    (_type_mismatch_out, "type mismatch in output relation: controller output 'CmdV' is float32 "
                         "but 'cmd_vel.linear.x' is float64"),
    (_input_fed_twice, "controller input fed by several input relations: 'In1'"),
    (_input_not_fed, "controller input not fed by any input relation: 'In3'"),
    (_unknown_field, "'.twist.linear.w' is not a carried scalar field of message 'geometry_msgs_TwistStamped'"),
    (_index_out_of_range, "'.pose.covariance[36]' is not a carried scalar field of message 'nav_msgs_Odometry'"),
    (_negative_index, "'.pose.covariance[-1]' is not a carried scalar field"),
    (_path_to_struct, "'.twist.linear' is not a carried scalar field"),
    (_subscribed_as_output, "output relation writes topic 'landshark_left_wheel_velocity', which is not published"),
    (_published_as_input, "input relation reads topic 'landshark_control_base_velocity', which is not subscribed"),
    (_published_field_fed_twice, "published field fed twice: 'landshark_control_base_velocity.twist.linear.x'"),
    (_unknown_output, "output relation from unknown controller output 'Out9'"),
    (_duplicate_topic_cname, "two topics with the C name 'landshark_left_wheel_velocity'"),
    (_c_keyword_field, "is not a valid C identifier: 'int'"),
    (_queue_zero, "queue size must be at least 1 for topic '/landshark/left_wheel_velocity'"),
    (_period_zero, "period_ms must be positive"),
    (_coq_keyword_node, "the node name is a Coq keyword: 'fix'"),
    (_messages_out_of_order, "which is not defined before it"),
    # rule 4.12
    (_timeout_below_period, "bad timeout (rule 4.12) on topic 'teleop_cmd_vel': 19 ms"),
    (_timeout_above_a_day, "bad timeout (rule 4.12) on topic 'nav_cmd_vel': 86400001 ms"),
    (_timeout_on_published, "bad timeout (rule 4.12) on topic 'cmd_vel': 500 ms must be on a subscribed topic"),
    (_fallback_of_another_type, "bad fallback (rule 4.12) for controller input 'TVx'"),
    (_fallback_without_timeout, "bad fallback (rule 4.12) for controller input 'TVx'"),
    (_derived_of_another_type, "bad derived input (rule 4.12) 'TAge'"),
    (_derived_of_published, "bad derived input (rule 4.12) 'NAge': it must be of topic 'cmd_vel'"),
    (_fed_by_relation_and_derived, "controller input fed by several input relations: 'TAge'"),
    (_derived_dropped, "controller input not fed by any input relation: 'TAge'"),
]


def test_mutated_models_refused_by_coq(tmp_path):
    models = [mut() for mut, _ in MUTATIONS]
    verdicts = _batch(tmp_path, models, accepted=False)
    for (mut, fragment), verdict in zip(MUTATIONS, verdicts):
        assert verdict.startswith("Generator: "), (mut.__name__, verdict)
        assert fragment in verdict, (mut.__name__, verdict)


def test_mutated_model_refused_by_the_pipeline(tmp_path):
    """Through ``generate``: Coq refuses at the coqc step, the message
    names the culprit, and nothing is written (the directory is not even
    created); no work directory is left behind."""
    require_library()
    out = tmp_path / "out"
    with pytest.raises(ModelRefused) as info:
        generate_model(_type_mismatch_in(), out)
    assert "controller input 'In1' is float32" in info.value.message
    assert any("error: Tactic failure" in ln and "refused the model" in ln for ln in info.value.lines)
    assert not out.exists()
    assert list(tmp_path.iterdir()) == []


# ---------------------------------------------------------------------------
# Edge names: whatever Python accepts, Coq accepts


EDGE_NAMES = [
    ("node", "mod"),          # in Coq's list of keywords of the term language
    ("node", "Generator"),    # a module of the ROSGen library
    ("node", "loop"),         # a generated function, but the node name is no C name
    ("input_var", "msg"),     # the callbacks' parameter
    ("input_var", "command"), # the output glues' parameter
    ("output_var", "msg"),
    ("input_var", "U"),
]


def _edge_model(tmp_path: Path, what: str, name: str) -> Path:
    text = LANDSHARK.read_text()
    if what == "node":
        text = text.replace("name: landshark_controller", f"name: {name}")
    elif what == "input_var":
        text = text.replace("name: Controller_U", f"name: {name}")
    else:
        text = text.replace("name: Controller_Y", f"name: {name}")
    p = tmp_path / f"edge_{what}_{name}.yaml"
    p.write_text(text)
    return p


def test_python_accepts_only_what_coq_accepts(tmp_path):
    accepted = []
    for what, name in EDGE_NAMES:
        try:
            accepted.append(((what, name), load_model(_edge_model(tmp_path, what, name))))
        except InvalidNodeModel:
            pass
    assert accepted
    verdicts = printed_strings(_verdicts_only(tmp_path, [m for _, m in accepted]))
    disagree = {case: v for (case, _), v in zip(accepted, verdicts) if v != "OK"}
    assert not disagree, f"the front end accepts models that Coq's generate refuses: {disagree}"


def _verdicts_only(tmp_path: Path, models: list) -> str:
    require_library()
    defs = [(f"e{i}", m) for i, m in enumerate(models)]
    text = [PREAMBLE, render_model_definitions(defs)]
    text += [f"Eval vm_compute in verdict {name}." for name, _ in defs]
    v = tmp_path / "Edges.v"
    v.write_text("\n".join(text) + "\n")
    return coqc(v).stdout

"""The seam between the YAML file and the proof: the model Coq proves things
about is the user's model (DESIGN.md section 7).

The per-node ``.v`` is tampered with between its emission and ``coqc``
(as an emitter bug or a hand edit would do).  Each tampered file still
proves its theorem -- about another model -- so only the comparison of the
model text Coq prints with the front end's reading of the YAML catches it:
``pyrosgen generate`` must exit 2, name the differing items, and write
nothing.
"""

from __future__ import annotations

import pytest

import pyrosgen.generate as gen
from pyrosgen import cli
from pyrosgen.frontend.validate import load_model
from pyrosgen.proof.modeltext import ModelMismatch, compare_model_texts, model_text

from support.generate import LANDSHARK, MULTI, require_library

IN1 = 'mkinrel "landshark_left_wheel_velocity" [PField "twist"; PField "linear"; PField "x"] "In1"'
IN2 = 'mkinrel "landshark_right_wheel_velocity" [PField "twist"; PField "linear"; PField "x"] "In2"'

TAMPERINGS = {
    # the inputs of two relations swapped: In1 fed from the right wheel
    "swapped inputs": [(IN1, IN1.replace('"In1"', '"In2"')), (IN2, IN2.replace('"In2"', '"In1"'))],
    "topic name changed": [('mktopic "/landshark/gps_velocity"', 'mktopic "/landshark/gps_velocity2"')],
    "queue size changed": [('Subscribe "geometry_msgs_TwistStamped" 1;\n       (* geometry_msgs/TwistStamped *)\n'
                            '       mktopic "/landshark/gps_velocity"',
                            'Subscribe "geometry_msgs_TwistStamped" 2;\n       (* geometry_msgs/TwistStamped *)\n'
                            '       mktopic "/landshark/gps_velocity"')],
    "period changed": [("nm_period_ms := 20;", "nm_period_ms := 21;")],
    # a relation dropped (Out1 then feeds nothing: still a well-formed model)
    "relation dropped": [('[(* Out1 -> /landshark_control/base_velocity twist.linear.x *)\n'
                          '       mkoutrel "Out1" "landshark_control_base_velocity" [PField "twist"; PField "linear"; '
                          'PField "x"]]', "[]")],
}


@pytest.mark.parametrize("name", sorted(TAMPERINGS))
def test_tampered_model_is_refused(name, monkeypatch, capsys, tmp_path):
    require_library()
    original = gen.render_node_file

    def tampered(model, **kw):
        text = original(model, **kw)
        for old, new in TAMPERINGS[name]:
            assert old in text, f"the emitted .v changed shape: {old!r} not found"
            text = text.replace(old, new, 1)
        return text

    monkeypatch.setattr(gen, "render_node_file", tampered)
    out = tmp_path / "out"
    code = cli.main(["generate", str(LANDSHARK), "-o", str(out), "-q"])
    err = capsys.readouterr().err
    assert code == 2, err
    assert "is not the model of the YAML file" in err
    assert "the proved model says" in err
    assert not out.exists()
    assert [p for p in tmp_path.iterdir() if p.name.startswith(".pyrosgen-")] == []


def test_untampered_models_agree(tmp_path):
    """The comparison passes on the examples (also run by every generate)."""
    require_library()
    for m in (LANDSHARK, MULTI):
        res = gen.generate(m, tmp_path / m.stem)
        assert res.files


def test_model_text_names_every_item():
    text = model_text(load_model(MULTI))
    lines = text.splitlines()
    assert lines[0] == "pyrosgen-model 1" and text.endswith("\n")
    model = load_model(MULTI)
    assert sum(ln.startswith("input_relation ") for ln in lines) == len(model.input_relations)
    assert sum(ln.startswith("output_relation ") for ln in lines) == len(model.output_relations)
    assert sum(ln.startswith("topic ") for ln in lines) == len(model.topics)
    assert any("[35]" in ln for ln in lines if ln.startswith("input_relation "))


def test_compare_names_the_items():
    a = "pyrosgen-model 1\nnode n\nperiod_ms 20\n"
    b = "pyrosgen-model 1\nnode n\nperiod_ms 21\nextra\n"
    with pytest.raises(ModelMismatch) as info:
        compare_model_texts(a, b, vfile="n.v")
    assert "2 differing items" in info.value.summary
    assert "item 3: the model file says 'period_ms 20'; the proved model says 'period_ms 21'" in info.value.lines[0]
    assert "item 4: the model file says '(nothing)'" in info.value.lines[1]
    compare_model_texts(a, a, vfile="n.v")

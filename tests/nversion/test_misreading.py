"""Issue 29's attack on the front end as a single point of trust: a front
end that misreads the model file (``timeout_ms: 500`` read as 5000) feeds
both sides of the model-text comparison (the text it renders and the
model Coq proves), so only the second, independent reading of the file
(``pyrosgen.nversion``) can see it.  ``pyrosgen generate`` must then exit
2, show both readings of the differing line, and write nothing; the
function that ``verify --model`` calls refuses the same way."""

from __future__ import annotations

from pathlib import Path

import pytest

from pyrosgen import cli
from pyrosgen.frontend import rule_freshness, validate
from pyrosgen.frontend.validate import load_model
from pyrosgen.nversion.check import NVersionMismatch, check_model_file
from pyrosgen.proof.modeltext import diagram_text, model_text

from support.generate import LANDSHARK, require_library

REPO = Path(__file__).resolve().parents[2]
GUARD = REPO / "examples" / "velocity_guard" / "velocity_guard.yaml"


def _timeout_times_ten(monkeypatch):
    real = rule_freshness._timeout

    def misread(*args, **kw):
        v = real(*args, **kw)
        return None if v is None else v * 10

    monkeypatch.setattr(rule_freshness, "_timeout", misread)


def _period_plus_one(monkeypatch):
    real = validate.node_section

    def misread(ck, m):
        name, period = real(ck, m)
        return name, None if period is None else period + 1

    monkeypatch.setattr(validate, "node_section", misread)


def _topic_c_name_wrong(monkeypatch):
    real = validate.topic_c_name
    monkeypatch.setattr(validate, "topic_c_name", lambda name: real(name) + "_x")


def _diagram(model_file):
    """The front end's diagram text of ``model_file`` (``None`` without a
    block diagram): what generate proves next to the model."""
    m = load_model(model_file)
    return diagram_text(m) if m.controller.diagram is not None else None


MISREADINGS = {
    "timeout x10": (_timeout_times_ten, GUARD, "timeout"),
    "period + 1": (_period_plus_one, LANDSHARK, "period_ms"),
    "topic C name": (_topic_c_name_wrong, LANDSHARK, "topic"),
}


@pytest.mark.parametrize("name", sorted(MISREADINGS))
def test_check_refuses_a_front_end_misreading(name, monkeypatch):
    """What a misreading front end proves (its own text, which its own
    comparison passes) is refused by the second reading, naming the line."""
    patch, model, keyword = MISREADINGS[name]
    honest = model_text(load_model(model))
    check_model_file(model, honest, _diagram(model), vfile="node.v")   # the honest front end passes
    patch(monkeypatch)
    misread = model_text(load_model(model))
    assert misread != honest
    with pytest.raises(NVersionMismatch) as exc:
        check_model_file(model, misread, _diagram(model), vfile="node.v")
    assert exc.value.exit_code == 2
    assert "the two readings of the model disagree" in exc.value.summary
    shown = "\n".join(exc.value.lines)
    assert f"independently says '{keyword} " in shown and f"the proved model says '{keyword} " in shown


def test_check_names_both_timeout_lines(monkeypatch):
    _timeout_times_ten(monkeypatch)
    with pytest.raises(NVersionMismatch) as exc:
        check_model_file(GUARD, model_text(load_model(GUARD)), _diagram(GUARD), vfile="velocity_guard.v")
    lines = [ln for ln in exc.value.lines if "timeout" in ln]
    assert lines and all("500'" in ln and "5000'" in ln for ln in lines), exc.value.lines
    # each names the place of its timeout_ms in the file (FILE:LINE:COL)
    text = GUARD.read_text(encoding="utf-8").splitlines()
    places = [f"{GUARD}:{n}:{ln.index('timeout_ms: 500') + len('timeout_ms: ') + 1}"
              for n, ln in enumerate(text, start=1) if "timeout_ms: 500" in ln]
    assert len(places) == len(lines) and all(p in ln for p, ln in zip(places, lines)), (places, lines)


def test_an_unreadable_file_is_a_disagreement(tmp_path):
    bad = tmp_path / "m.yaml"
    bad.write_text("node: {name: n, period_ms: 20}\ncontroller: {name: C}\ntopics:\n"
                   "  - {name: /a, direction: subscribe, type: nosuch_msgs/Thing, queue_size: 1}\n")
    with pytest.raises(NVersionMismatch) as exc:
        check_model_file(bad, "pyrosgen-model 1\n", vfile="n.v")
    assert "cannot read it" in exc.value.summary
    assert "nosuch_msgs/Thing" in "\n".join(exc.value.lines)


def test_generate_refuses_a_front_end_misreading(monkeypatch, capsys, tmp_path):
    """Through ``pyrosgen generate``: Coq proves the misread model, the
    front end's own comparison passes, the second reading refuses: exit 2,
    both readings of the timeout shown, nothing written."""
    require_library()
    _timeout_times_ten(monkeypatch)
    out = tmp_path / "out"
    code = cli.main(["generate", str(GUARD), "-o", str(out), "-q"])
    err = capsys.readouterr().err
    assert code == 2, err
    assert "the two readings of the model disagree" in err
    assert "independently says 'timeout " in err and "500'" in err and "5000'" in err
    assert not out.exists()
    assert [p for p in tmp_path.iterdir() if p.name.startswith(".pyrosgen-")] == []


LASER = REPO / "examples" / "laser_guard" / "laser_guard.yaml"


def _greater_as_greater_equal(monkeypatch):
    """A front end that reads a RelationalOperator's '>' as '>='."""
    from pyrosgen.frontend import blocks

    monkeypatch.setitem(blocks.RELOPS, ">", ">=")


def test_check_refuses_a_misread_diagram(monkeypatch):
    """The diagram text too: the model texts agree, the diagram Coq would
    prove (the front end's) is refused, naming the block's equation."""
    check_model_file(LASER, model_text(load_model(LASER)), _diagram(LASER), vfile="laser_guard.v")
    _greater_as_greater_equal(monkeypatch)
    with pytest.raises(NVersionMismatch) as exc:
        check_model_file(LASER, model_text(load_model(LASER)), _diagram(LASER), vfile="laser_guard.v")
    assert "the controller diagram proved in laser_guard.v" in exc.value.summary
    shown = "\n".join(exc.value.lines)
    assert "independently says 'eq clear bool relational > float32 closest safe'" in shown
    assert "the proved diagram says 'eq clear bool relational >= float32 closest safe'" in shown
    line = next(n for n, ln in enumerate(LASER.read_text(encoding="utf-8").splitlines(), start=1)
                if "name: clear," in ln)
    assert f"{LASER}:{line}:" in shown


def test_generate_refuses_a_misread_diagram(monkeypatch, capsys, tmp_path):
    require_library()
    _greater_as_greater_equal(monkeypatch)
    out = tmp_path / "out"
    code = cli.main(["generate", str(LASER), "-o", str(out), "-q"])
    err = capsys.readouterr().err
    assert code == 2, err
    assert "the controller diagram proved in laser_guard.v is not the diagram of laser_guard.yaml" in err
    assert "relational >= float32 closest safe" in err
    assert not out.exists()


def test_the_verify_function_refuses_a_folder_proved_from_a_misreading(monkeypatch, tmp_path):
    """What ``verify --model`` checks: a folder made by a misreading front
    end without the second reading (as an older pyrosgen made it) holds a
    proved model text (``<node>.model``, printed by Coq) that the same
    misreading front end agrees with; the second reading refuses it."""
    require_library()
    import pyrosgen.generate as gen

    _timeout_times_ten(monkeypatch)
    monkeypatch.setattr(gen, "check_model_file", lambda *a, **k: None)
    out = tmp_path / "out"
    assert cli.main(["generate", str(GUARD), "-o", str(out), "-q"]) == 0
    proved = (out / "velocity_guard.model").read_text(encoding="utf-8")
    assert "timeout teleop_cmd_vel 5000\n" in proved
    assert proved == model_text(load_model(GUARD))        # the front end's own comparison passes
    with pytest.raises(NVersionMismatch) as exc:
        check_model_file(GUARD, proved, None, vfile="velocity_guard.v")
    assert "independently says 'timeout teleop_cmd_vel 500'" in "\n".join(exc.value.lines)

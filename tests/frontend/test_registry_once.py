"""DESIGN.md section 3: the message registry is loaded once, before the
rules run (``rule_messages.load_messages``: the ``msg_paths`` folders, then
the strings and variable-length arrays the glue carries); the rules only
query it.  Checked by recording every call that changes the registry
(``add_msg_dir``, ``set_carried``) and the moment the rules start."""

from __future__ import annotations

from pathlib import Path

import pytest

import pyrosgen.frontend.validate as validate
from pyrosgen.errors import InvalidNodeModel
from pyrosgen.frontend.msgload import MsgRegistry

REPO = Path(__file__).resolve().parents[2]


@pytest.fixture
def events(monkeypatch):
    """The registry's changes and the start of the rules, in order."""
    out: list[str] = []

    def spy(name, real):
        def wrapper(*args, **kwargs):
            out.append(name)
            return real(*args, **kwargs)
        return wrapper

    monkeypatch.setattr(MsgRegistry, "add_msg_dir", spy("add_msg_dir", MsgRegistry.add_msg_dir))
    monkeypatch.setattr(MsgRegistry, "set_carried", spy("set_carried", MsgRegistry.set_carried))
    monkeypatch.setattr(validate, "_run_rules", spy("rules", validate._run_rules))
    return out


@pytest.mark.parametrize("model, expected", [
    ("examples/multi/multi_node.yaml", ["add_msg_dir", "set_carried", "rules"]),    # one msg_paths folder
    ("examples/scan_guard/scan_guard.yaml", ["set_carried", "rules"]),              # carries ranges
    ("examples/landshark/landshark_controller.yaml", ["set_carried", "rules"]),
])
def test_the_registry_is_loaded_once_before_the_rules(events, model, expected):
    assert validate.load_model(REPO / model).name
    assert events == expected


def test_a_refused_model_loads_it_once_too(events, tmp_path):
    """Refused or not, the rules never change the registry."""
    text = (REPO / "examples/multi/multi_node.yaml").read_text().replace("period_ms: ", "period_ms: -")
    bad = tmp_path / "multi_node.yaml"
    bad.write_text(text)
    (tmp_path / "msg").symlink_to(REPO / "examples/multi/msg")
    with pytest.raises(InvalidNodeModel) as exc:
        validate.load_model(bad)
    assert any("period_ms" in d.message for d in exc.value.diagnostics)
    assert events == ["add_msg_dir", "set_carried", "rules"]

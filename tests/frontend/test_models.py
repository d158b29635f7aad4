"""Every ok_*.yaml model loads; every ko_*.yaml model fails with exactly the
diagnostics its ``# expect:`` comments announce (line and message fragment)."""

from __future__ import annotations

import pytest

from pyrosgen import InvalidNodeModel, NodeModel, load_model

from support.frontend import LANDSHARK, MODELS, expectations

OK = sorted(MODELS.glob("ok_*.yaml")) + [LANDSHARK]
KO = sorted(MODELS.glob("ko_*.yaml"))


def test_there_are_many_ko_cases():
    assert len(KO) >= 100
    for path in KO:
        assert expectations(path), f"{path.name} has no # expect: comment"


@pytest.mark.parametrize("path", OK, ids=lambda p: p.name)
def test_ok_model_loads(path):
    model = load_model(path)
    assert isinstance(model, NodeModel)
    assert model.topics and model.input_relations


@pytest.mark.parametrize("path", KO, ids=lambda p: p.name)
def test_ko_model_fails_as_expected(path):
    expected = expectations(path)
    with pytest.raises(InvalidNodeModel) as info:
        load_model(path)
    diags = list(info.value.diagnostics)
    rendered = "\n".join(str(d) for d in diags)
    unmatched = list(diags)
    for file, line, frag in expected:
        for d in unmatched:
            in_file = d.file.endswith(file) if file else d.file == str(path)
            if in_file and d.line == line and frag in d.message:
                unmatched.remove(d)
                break
        else:
            pytest.fail(f"expected {file or path.name}:{line}: {frag!r}\ngot:\n{rendered}")
    assert not unmatched, "unexpected diagnostics:\n" + "\n".join(str(d) for d in unmatched)
    # Every diagnostic is one line and names a position.
    for d in diags:
        assert "\n" not in str(d)
        assert d.message

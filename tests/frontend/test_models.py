"""Every ok_*.yaml model loads; every ko_*.yaml model fails with exactly the
diagnostics its ``# expect:`` comments announce (line and message fragment)."""

from __future__ import annotations

import re

import pytest

from pyrosgen import InvalidNodeModel, NodeModel, load_model

from support.frontend import LANDSHARK, MODELS, REPO, expectations

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


_RULES = set(re.findall(r"^- \*\*(4\.\d+) ", (REPO / "DESIGN.md").read_text(), flags=re.M))


@pytest.mark.parametrize("path", KO, ids=lambda p: p.name)
def test_ko_diagnostics_cite_their_rule(path):
    """Every diagnostic names the rule of DESIGN.md section 4 it enforces,
    and the rule exists; the rendered line ends with it."""
    with pytest.raises(InvalidNodeModel) as info:
        load_model(path)
    for d in info.value.diagnostics:
        assert d.rule in _RULES, f"{d} cites no rule of DESIGN.md section 4"
        assert str(d).endswith(f" [rule {d.rule}]")


@pytest.mark.parametrize("path, rule", [
    ("ko_period_zero.yaml", "4.2"),
    ("ko_rel_type_mismatch_in.yaml", "4.7"),
    ("ko_rel_input_not_fed.yaml", "4.8"),
])
def test_some_rules_by_name(path, rule):
    if not (MODELS / path).is_file():
        pytest.fail(f"{path} is gone from the corpus: pick another example of rule {rule}")
    with pytest.raises(InvalidNodeModel) as info:
        load_model(MODELS / path)
    assert rule in {d.rule for d in info.value.diagnostics}

"""The QoS of rule 4.18 read twice: the front end's record
(``pyrosgen.ros2.wrapper.qos_text``) and the second, independent reading
(``pyrosgen.nversion.qos``) agree on every spelling, random ones included;
the second reading of the model text accepts the same files (the QoS is
not in the proved model text: a ``qos`` leaves it unchanged), and a
record that says otherwise is a disagreement (exit 2)."""

from __future__ import annotations

import tempfile
from pathlib import Path

import pytest
import yaml
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from pyrosgen.errors import InvalidNodeModel
from pyrosgen.frontend.validate import load_model
from pyrosgen.nversion.msgs import ReadingError
from pyrosgen.nversion.check import NVersionMismatch, check_model_file
from pyrosgen.nversion.qos import check_qos_record, qos_text as second_reading
from pyrosgen.proof.modeltext import model_text
from pyrosgen.ros2.wrapper import qos_text

BASE = {
    "node": {"name": "n", "period_ms": 20},
    "controller": {"name": "Controller", "inputs": {"name": "Controller_U", "fields": {"In1": "float64"}},
                   "outputs": {"name": "Controller_Y", "fields": {"Out1": "float64"}}},
    "topics": [{"name": "/sensor", "direction": "subscribe", "type": "std_msgs/Float64", "queue_size": 3},
               {"name": "/cmd", "direction": "publish", "type": "std_msgs/Float64", "queue_size": 7}],
    "relations": {"inputs": [{"topic": "/sensor", "field": "data", "input": "In1"}],
                  "outputs": [{"output": "Out1", "topic": "/cmd", "field": "data"}]},
}

QOS = st.one_of(
    st.none(), st.sampled_from(["default", "sensor_data"]),
    st.fixed_dictionaries({}, optional={"profile": st.sampled_from(["default", "sensor_data"]),
                                        "reliability": st.sampled_from(["reliable", "best_effort"]),
                                        "durability": st.sampled_from(["volatile", "transient_local"])}))


def _write(folder: Path, qin, qout) -> Path:
    doc = yaml.safe_load(yaml.safe_dump(BASE))
    for t, q in zip(doc["topics"], (qin, qout)):
        if q is not None:
            t["qos"] = q
    p = folder / "m.yaml"
    p.write_text(yaml.safe_dump(doc, sort_keys=False), encoding="utf-8")
    return p


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(qin=QOS, qout=QOS)
def test_both_readings_agree(qin, qout):
    with tempfile.TemporaryDirectory() as d:
        p = _write(Path(d), qin, qout)
        m = load_model(p)
        record = qos_text(m)
        assert record == second_reading(p)
        check_qos_record(p, record, what="the front end's QoS record")
        # the model text, read independently, is the front end's: the qos changes nothing in it
        check_model_file(p, model_text(m), vfile="n.v")


def test_the_record_says_depth_reliability_durability(tmp_path):
    p = _write(tmp_path, "sensor_data", {"durability": "transient_local"})
    assert second_reading(p) == ("pyrosgen-qos 1\n"
                                 "topic /sensor subscribe keep_last 3 best_effort volatile\n"
                                 "topic /cmd publish keep_last 7 reliable transient_local\n")
    assert qos_text(load_model(p)) == second_reading(p)


@pytest.mark.parametrize("old, new", [
    ("best_effort volatile", "reliable volatile"),
    ("reliable transient_local", "reliable volatile"),
    ("keep_last 3", "keep_last 4"),
])
def test_a_record_that_says_otherwise_is_a_disagreement(tmp_path, old, new):
    p = _write(tmp_path, "sensor_data", {"durability": "transient_local"})
    record = qos_text(load_model(p))
    with pytest.raises(NVersionMismatch) as info:
        check_qos_record(p, record.replace(old, new), what="the folder's n.qos")
    assert "is not the QoS of m.yaml read independently" in info.value.summary
    assert any(new in line for line in info.value.lines)


_SCALARS = st.one_of(st.none(), st.booleans(), st.integers(-3, 3), st.floats(allow_nan=False, width=32),
                     st.sampled_from(["reliable", "best_effort", "volatile", "transient_local", "default",
                                      "sensor_data", "profile", "yes", "", "Reliable"]),
                     st.text(max_size=8))
_HOSTILE = st.recursive(_SCALARS, lambda inner: st.one_of(
    st.lists(inner, max_size=3),
    st.dictionaries(st.sampled_from(["profile", "reliability", "durability", "depth"]) | st.text(max_size=5),
                    inner, max_size=3)), max_leaves=6)


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(q=_HOSTILE)
def test_both_readings_accept_and_refuse_the_same_qos(q):
    """Whatever the ``qos`` value: the front end accepts it exactly when
    the second reading reads it, and then both give the same record."""
    with tempfile.TemporaryDirectory() as d:
        doc = yaml.safe_load(yaml.safe_dump(BASE))
        doc["topics"][0]["qos"] = q
        p = Path(d) / "m.yaml"
        p.write_text(yaml.safe_dump(doc, sort_keys=False, allow_unicode=True), encoding="utf-8")
        try:
            record = qos_text(load_model(p))
        except InvalidNodeModel as exc:
            # rule 4.18, or 4.1 for a number YAML reads unlike a user means (.inf)
            assert all(x.rule in ("4.18", "4.1") for x in exc.diagnostics), [str(x) for x in exc.diagnostics]
            record = None
        try:
            second = second_reading(p)
        except ReadingError:
            second = None
        assert record == second, (q, record, second)

"""Per-topic QoS for ROS 2 (DESIGN.md rule 4.18, issue 31): a topic's
``qos`` (a profile name, or a mapping of ``profile``, ``reliability`` and
``durability``); the history is KEEP_LAST of depth ``queue_size``.  The
accepted spellings and what they mean; the ROS 1 target's warning (it
ignores the QoS); every refusal with its line, column and rule; hostile
values (hypothesis) never give anything but a model or rule 4.18
diagnostics; the QoS is not in the proved model text."""

from __future__ import annotations

import contextlib
import io
import re

import pytest
import yaml
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from pyrosgen import InvalidNodeModel
from pyrosgen.cli import main
from pyrosgen.frontend.model import DEFAULT_QOS, Qos
from pyrosgen.proof.modeltext import model_text

from support.frontend import at, diags, load, one, write

BASE = """\
node: {name: n, period_ms: 20}
controller:
  name: Controller
  inputs: {name: Controller_U, fields: {In1: float64}}
  outputs: {name: Controller_Y, fields: {Out1: float64}}
topics:
  - {name: /sensor, direction: subscribe, type: std_msgs/Float64, queue_size: 3QIN}
  - {name: /cmd, direction: publish, type: std_msgs/Float64, queue_size: 2QOUT}
relations:
  inputs:
    - {topic: /sensor, field: data, input: In1}
  outputs:
    - {output: Out1, topic: /cmd, field: data}
"""


def model(qin: str = "", qout: str = "") -> str:
    """BASE with ``qos: <qin>`` on /sensor and ``qos: <qout>`` on /cmd (none when empty)."""
    return BASE.replace("QIN", f", qos: {qin}" if qin else "").replace("QOUT", f", qos: {qout}" if qout else "")


BE = Qos("best_effort", "volatile")


@pytest.mark.parametrize("written, meant", [
    ("", DEFAULT_QOS),
    ("default", DEFAULT_QOS),
    ("sensor_data", BE),
    ("{}", DEFAULT_QOS),
    ("{reliability: best_effort}", BE),
    ("{reliability: reliable}", DEFAULT_QOS),
    ("{durability: transient_local}", Qos("reliable", "transient_local")),
    ("{reliability: best_effort, durability: transient_local}", Qos("best_effort", "transient_local")),
    ("{profile: sensor_data}", BE),
    ("{profile: sensor_data, durability: transient_local}", Qos("best_effort", "transient_local")),
    ("{profile: sensor_data, reliability: reliable}", DEFAULT_QOS),
    ("{profile: default, reliability: best_effort}", BE),
])
def test_each_spelling_means_one_qos(tmp_path, written, meant):
    m = load(tmp_path, model(qin=written))
    assert m.topic("/sensor").qos == meant
    assert m.topic("/cmd").qos == DEFAULT_QOS
    # the depth is the queue size, the only one the model has
    assert m.topic("/sensor").queue_size == 3


def test_the_defaults_are_rclcpp_s():
    assert (DEFAULT_QOS.reliability, DEFAULT_QOS.durability) == ("reliable", "volatile")


def test_qos_is_not_in_the_proved_model_text(tmp_path):
    """Coq's model does not see the QoS (it decides which messages arrive,
    section 6.1): the model text, and so the proof, is the same."""
    plain = model_text(load(tmp_path, model()))
    (tmp_path / "q").mkdir()
    with_qos = model_text(load(tmp_path / "q", model(qin="sensor_data", qout="{durability: transient_local}")))
    assert with_qos == plain


# --------------------------------------------------------------------------
# The target ROS 1: accepted, with a warning naming the place


def test_ros1_warns_at_each_qos(tmp_path):
    text = model(qin="sensor_data", qout="{durability: transient_local}")
    m = load(tmp_path, text)
    ws = [(w.line, w.col, w.severity, w.rule) for w in m.warnings]
    assert ws == [(*at(text, "sensor_data"), "warning", "4.18"), (*at(text, "{durability"), "warning", "4.18")]
    assert "roscpp's TCPROS transport is reliable and volatile" in m.warnings[0].message
    assert "'/sensor'" in m.warnings[0].message and "best_effort, volatile" in m.warnings[0].message
    assert "'/cmd'" in m.warnings[1].message and "reliable, transient_local" in m.warnings[1].message


def test_no_qos_no_warning(tmp_path):
    assert load(tmp_path, model()).warnings == ()


def _check(path) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(["check", str(path)])
    return code, out.getvalue(), err.getvalue()


def test_check_prints_the_warning_and_accepts(tmp_path):
    text = model(qin="{reliability: best_effort}")
    p = write(tmp_path, text)
    code, out, err = _check(p)
    line, col = at(text, "{reliability")
    assert code == 0 and ": ok: node n" in out
    assert err.startswith(f"{p}:{line}:{col}: warning: topic '/sensor': qos (best_effort, volatile) is for the "
                          "target ros2 (--ros2); the ROS 1 target ignores it"), err
    assert err.rstrip().endswith("[rule 4.18]") and len(err.splitlines()) == 1


# --------------------------------------------------------------------------
# Refused, each at its place, rule 4.18


@pytest.mark.parametrize("written, needle, fragment", [
    ("{reliability: sometimes}", "sometimes", "topics[0].qos.reliability must be one of reliable, best_effort, "
                                             "got 'sometimes'"),
    ("{durability: transient}", "transient", "topics[0].qos.durability must be one of volatile, transient_local, "
                                             "got 'transient' (did you mean 'transient_local'?)"),
    ("{durability: 5}", "5}", "topics[0].qos.durability must be one of volatile, transient_local, got int"),
    ("{reliability: true}", "true", "qos.reliability must be one of reliable, best_effort, got bool"),
    ("{reliability: null}", "null", "qos.reliability must be one of reliable, best_effort, got null"),
    ("{reliability: [reliable]}", "[reliable]", "qos.reliability must be one of reliable, best_effort, got a list"),
    ("{profile: fast}", "fast", "topics[0].qos.profile must be one of default, sensor_data, got 'fast'"),
    ("sensordata", "sensordata", "topics[0].qos (a profile) must be one of default, sensor_data, got 'sensordata' "
                                 "(did you mean 'sensor_data'?)"),
    ("best_effort", "best_effort", "topics[0].qos (a profile) must be one of default, sensor_data"),
    ("{depth: 5}", "depth", "topics[0].qos: unknown key 'depth'; expected profile, reliability, durability (the "
                            "history depth is the topic's queue_size)"),
    ("{history: keep_all}", "history", "topics[0].qos: unknown key 'history'"),
    ("{reliabilty: best_effort}", "reliabilty", "unknown key 'reliabilty' (did you mean 'reliability'?)"),
    ("[sensor_data]", "[sensor_data]", "topics[0].qos must be a profile name (default, sensor_data) or a mapping "
                                       "of profile, reliability, durability, got a list"),
    ("5", "5}", "topics[0].qos must be a profile name (default, sensor_data) or a mapping"),
    ("null", "null", "topics[0].qos must be a profile name (default, sensor_data) or a mapping"),
])
def test_a_bad_qos_is_refused_at_its_place(tmp_path, written, needle, fragment):
    text = model(qin=written)
    line, col, message, rule = one(tmp_path, text)
    start = text.index("qos: ") + len("qos: ")
    assert (line, col) == at(text[:start] + text[start:].replace(needle, "\0" + needle[1:], 1), "\0"), message
    assert fragment in message and rule == "4.18"


@pytest.mark.parametrize("where, old, new", [
    ("node", "node: {name: n, period_ms: 20}", "node: {name: n, period_ms: 20, qos: sensor_data}"),
    ("relations.inputs[0]", "{topic: /sensor, field: data, input: In1}",
     "{topic: /sensor, field: data, input: In1, qos: sensor_data}"),
    ("relations.outputs[0]", "{output: Out1, topic: /cmd, field: data}",
     "{output: Out1, topic: /cmd, field: data, qos: default}"),
    ("the node model", "relations:\n", "qos: sensor_data\nrelations:\n"),
    ("controller.inputs", "{name: Controller_U, fields", "{qos: default, name: Controller_U, fields"),
])
def test_qos_on_what_is_not_a_topic_is_refused(tmp_path, where, old, new):
    text = model().replace(old, new)
    line, col, message, rule = one(tmp_path, text)
    assert (line, col) == at(text, "qos")
    assert message == (f"{where}: unknown key 'qos': qos is a key of a topic declaration "
                       "(topics: [{name: ..., qos: ...}])") and rule == "4.18"


def test_every_bad_qos_reported_at_once(tmp_path):
    text = model(qin="{reliability: sometimes}", qout="{profile: fast, durability: forever}")
    found = diags(tmp_path, text)
    assert [(d[0], d[1]) for d in found] == [at(text, "sometimes"), at(text, "fast"), at(text, "forever")]
    assert {d[3] for d in found} == {"4.18"}


def test_cli_refusal_is_exit_1_without_traceback(tmp_path):
    text = model(qout="{reliability: sometimes}")
    p = write(tmp_path, text)
    code, out, err = _check(p)
    line, col = at(text, "sometimes")
    assert code == 1 and out == ""
    assert err.startswith(f"{p}:{line}:{col}: error: topics[1].qos.reliability must be one of reliable, best_effort, "
                          "got 'sometimes' [rule 4.18]"), err
    assert "Traceback" not in err


# --------------------------------------------------------------------------
# Hostile values: a model or diagnostics, never anything else

_DIAG = re.compile(r"^\S+:\d+:\d+: (error|warning): .* \[rule 4\.\d+\]$")
_SCALARS = st.one_of(st.none(), st.booleans(), st.integers(-10, 10), st.floats(allow_nan=False, width=32),
                     st.sampled_from(["reliable", "best_effort", "volatile", "transient_local", "default",
                                      "sensor_data", "keep_last", "", "\u202e", "0x10"]),
                     st.text(max_size=12))
_VALUES = st.recursive(_SCALARS, lambda inner: st.one_of(
    st.lists(inner, max_size=3),
    st.dictionaries(st.sampled_from(["profile", "reliability", "durability", "depth", "qos"]) | st.text(max_size=6),
                    inner, max_size=4)), max_leaves=8)


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(value=_VALUES)
def test_hostile_qos_values(tmp_path, value):
    doc = yaml.safe_load(model())
    doc["topics"][0]["qos"] = value
    p = write(tmp_path, yaml.safe_dump(doc, allow_unicode=True), "h.yaml")
    try:
        m = load(tmp_path, p.read_text(encoding="utf-8"))
    except InvalidNodeModel as exc:
        assert exc.diagnostics
        for d in exc.diagnostics:
            assert d.line is not None and _DIAG.match(str(d)), str(d)
        return
    q = m.topic("/sensor").qos
    assert q.reliability in ("reliable", "best_effort") and q.durability in ("volatile", "transient_local")
    assert len(m.warnings) == 1 and m.warnings[0].rule == "4.18"

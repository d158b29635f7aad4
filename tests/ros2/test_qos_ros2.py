"""Per-topic QoS on ROS 2 (DESIGN.md rule 4.18, issue 31).

One node, built once by ``build --ros2`` from a model whose eight topics
have the QoS of every kind (default, best effort, transient local, the
sensor-data profile), each output twice its input (a Gain diagram):

- the build writes the QoS record ``<node>.qos``, the wrapper sets each
  topic's QoS literally, and ``check_rcl_wrapper`` and ``verify`` refuse a
  wrapper whose QoS was edited, a record that says otherwise, and (``verify
  --model``) a model file with another QoS;
- on a real DDS (Fast DDS on the loopback, rclpy peers of
  ``qos_peer.py``): a best-effort publisher and a reliable subscription
  are incompatible (nothing is delivered; the node keeps running on the
  zero input and says so on standard error, as it does of a reliable
  subscriber to its best-effort publisher); a best-effort subscription
  receives from a reliable publisher, and the sensor-data profile talks to
  rclpy's ``qos_profile_sensor_data``; a late-joining transient-local
  subscriber receives the node's last ``queue_size`` samples; the node's
  transient-local subscription receives a sample published before the
  node started.
"""

from __future__ import annotations

import hashlib
import json
import shutil
import signal
import subprocess
import sys
import time
from collections import Counter
from pathlib import Path

import pytest

from pyrosgen.frontend.model import DEFAULT_QOS
from pyrosgen.proof.modeltext import parse_model_text
from pyrosgen.ros2.build import build_ros2
from pyrosgen.ros2.frontend import load_model_ros2
from pyrosgen.ros2.wrapper import Ros2WrapperMismatch, check_rcl_wrapper, qos_text, render_rcl_wrapper

from support import ros as rosutil

from .conftest import settled_leftovers, spawn, stop

QOS_PEER = Path(__file__).resolve().parent / "qos_peer.py"
NODE = "qos_node"

MODEL = """\
node: {name: qos_node, period_ms: 20}
controller:
  name: Controller
  inputs: {name: Controller_U, fields: {In1: float64, In2: float64, In3: float64, In4: float64}}
  outputs: {name: Controller_Y, fields: {Out1: float64, Out2: float64, Out3: float64, Out4: float64}}
  blocks:
    - {name: g1, block: Gain, input: In1, gain: 2.0}
    - {name: g2, block: Gain, input: In2, gain: 2.0}
    - {name: g3, block: Gain, input: In3, gain: 2.0}
    - {name: g4, block: Gain, input: In4, gain: 2.0}
  outports: {Out1: g1, Out2: g2, Out3: g3, Out4: g4}
topics:
  - {name: /qos/rel_in, direction: subscribe, type: std_msgs/Float64, queue_size: 1}
  - {name: /qos/be_in,  direction: subscribe, type: std_msgs/Float64, queue_size: 1, qos: {reliability: best_effort}}
  - {name: /qos/tl_in,  direction: subscribe, type: std_msgs/Float64, queue_size: 1, qos: {durability: transient_local}}
  - {name: /qos/sd_in,  direction: subscribe, type: std_msgs/Float64, queue_size: 5, qos: sensor_data}
  - {name: /qos/rel_out, direction: publish, type: std_msgs/Float64, queue_size: 1}
  - {name: /qos/tl_out,  direction: publish, type: std_msgs/Float64, queue_size: 5, qos: {durability: transient_local}}
  - {name: /qos/x_out,   direction: publish, type: std_msgs/Float64, queue_size: 1}
  - {name: /qos/sd_out,  direction: publish, type: std_msgs/Float64, queue_size: 5, qos: sensor_data}
relations:
  inputs:
    - {topic: /qos/rel_in, field: data, input: In1}
    - {topic: /qos/be_in,  field: data, input: In2}
    - {topic: /qos/tl_in,  field: data, input: In3}
    - {topic: /qos/sd_in,  field: data, input: In4}
  outputs:
    - {output: Out1, topic: /qos/rel_out, field: data}
    - {output: Out2, topic: /qos/tl_out,  field: data}
    - {output: Out3, topic: /qos/x_out,   field: data}
    - {output: Out4, topic: /qos/sd_out,  field: data}
"""

RECORD = """\
pyrosgen-qos 1
topic /qos/rel_in subscribe keep_last 1 reliable volatile
topic /qos/be_in subscribe keep_last 1 best_effort volatile
topic /qos/tl_in subscribe keep_last 1 reliable transient_local
topic /qos/sd_in subscribe keep_last 5 best_effort volatile
topic /qos/rel_out publish keep_last 1 reliable volatile
topic /qos/tl_out publish keep_last 5 reliable transient_local
topic /qos/x_out publish keep_last 1 reliable volatile
topic /qos/sd_out publish keep_last 5 best_effort volatile
"""


@pytest.fixture(scope="module")
def qos_node(ros2_install, ros2_nodes):
    """The QoS node built for ROS 2 (a diagram controller: no C brought)."""
    folder = ros2_nodes / "qos"
    folder.mkdir(exist_ok=True)
    model = folder / "qos_node.yaml"
    model.write_text(MODEL, encoding="utf-8")
    return build_ros2(model, None, folder / "out", install=ros2_install)


def _cli(*args):
    return subprocess.run([sys.executable, "-m", "pyrosgen", *map(str, args)], capture_output=True, text=True,
                          cwd=str(rosutil.ROOT))


# --------------------------------------------------------------------------
# The record, the wrapper, the checks


def test_the_ros2_reading_has_the_qos_and_no_ros1_warning(qos_node, ros2_install):
    m = load_model_ros2(qos_node.out_dir.parent / "qos_node.yaml", ros2_install)
    assert m.warnings == ()
    assert qos_text(m) == RECORD
    r = _cli("check", "--ros2", qos_node.out_dir.parent / "qos_node.yaml")
    assert r.returncode == 0 and "warning" not in r.stderr, r.stderr
    assert r.stdout.rstrip().endswith(
        "; QoS other than the default: /qos/be_in (best_effort, volatile), /qos/tl_in (reliable, transient_local), "
        "/qos/sd_in (best_effort, volatile), /qos/tl_out (reliable, transient_local), "
        "/qos/sd_out (best_effort, volatile)"), r.stdout
    r = _cli("check", qos_node.out_dir.parent / "qos_node.yaml")  # ROS 1: one warning per qos
    assert r.returncode == 0 and r.stderr.count("warning: ") == 5 and r.stderr.count("[rule 4.18]") == 5, r.stderr


def test_build_writes_the_record_and_sets_each_qos(qos_node):
    out = qos_node.out_dir
    assert (out / f"{NODE}.qos").read_text() == RECORD
    wrapper = (out / f"{NODE}_rcl.c").read_text()
    sub = wrapper[wrapper.index("void ros_subscribe_qos_sd_in("):]
    sub = sub[: sub.index("\n}\n")]
    assert ("    options.qos.history = RMW_QOS_POLICY_HISTORY_KEEP_LAST;\n    options.qos.depth = 5;\n"
            "    options.qos.reliability = RMW_QOS_POLICY_RELIABILITY_BEST_EFFORT;\n"
            "    options.qos.durability = RMW_QOS_POLICY_DURABILITY_VOLATILE;\n") in sub
    pub = wrapper[wrapper.index("void ros_advertise_qos_tl_out("):]
    pub = pub[: pub.index("\n}\n")]
    assert ("    options.qos.reliability = RMW_QOS_POLICY_RELIABILITY_RELIABLE;\n"
            "    options.qos.durability = RMW_QOS_POLICY_DURABILITY_TRANSIENT_LOCAL;\n") in pub
    # the record is listed in the certificate like every file of the node
    assert f"`{NODE}.qos`" in (out / f"{NODE}.certificate.md").read_text()


_TL = "ros_advertise_qos_tl_out(void)\n{\n    rcl_publisher_options_t options = rcl_publisher_get_default_options();"


@pytest.mark.parametrize("old, new", [
    ("options.qos.durability = RMW_QOS_POLICY_DURABILITY_TRANSIENT_LOCAL;",
     "options.qos.durability = RMW_QOS_POLICY_DURABILITY_VOLATILE;"),
    ("options.qos.reliability = RMW_QOS_POLICY_RELIABILITY_BEST_EFFORT;",
     "options.qos.reliability = RMW_QOS_POLICY_RELIABILITY_RELIABLE;"),
    ("options.qos.depth = 5;", "options.qos.depth = 4;"),
    ("options.qos.durability = RMW_QOS_POLICY_DURABILITY_TRANSIENT_LOCAL;",
     "options.qos.durability = RMW_QOS_POLICY_DURABILITY_TRANSIENT_LOCAL;\n    options.qos.depth = 1;"),
    ("options.qos.durability = RMW_QOS_POLICY_DURABILITY_TRANSIENT_LOCAL;",
     "options.qos.durability = RMW_QOS_POLICY_DURABILITY_TRANSIENT_LOCAL;\n"
     "    options.qos.history = RMW_QOS_POLICY_HISTORY_KEEP_ALL;"),
    ("options.qos.durability = RMW_QOS_POLICY_DURABILITY_TRANSIENT_LOCAL;", ""),
    (_TL, _TL.replace("rcl_publisher_get_default_options()", "g_other_options")),
])
def test_check_rcl_wrapper_refuses_an_edited_qos(qos_node, old, new):
    out = qos_node.out_dir
    wrapper = (out / f"{NODE}_rcl.c").read_text()
    proved = (out / f"{NODE}.model").read_text()
    check_rcl_wrapper(wrapper, proved, wrapper_name="w.c", qos_record=RECORD)
    # the edit in the setup functions of the model's topics (not in /clock's, ros_init's own)
    cut = wrapper.index("\nvoid ros_subscribe_")
    head, tail = wrapper[:cut], wrapper[cut:]
    assert tail.count(old) >= 1
    with pytest.raises(Ros2WrapperMismatch) as info:
        check_rcl_wrapper(head + tail.replace(old, new, 1), proved, wrapper_name="w.c", qos_record=RECORD)
    assert "rule 4.18" in " ".join(info.value.lines) or "depth" in " ".join(info.value.lines), info.value.lines
    # without a record every topic must have the default QoS: this wrapper's non-default ones are refused
    with pytest.raises(Ros2WrapperMismatch):
        check_rcl_wrapper(wrapper, proved, wrapper_name="w.c")


@pytest.mark.parametrize("old, new, says", [
    ("keep_last 5 best_effort volatile\n", "keep_last 5 reliable volatile\n", None),
    ("topic /qos/be_in subscribe keep_last 1", "topic /qos/be_in subscribe keep_last 2", "queue 1"),
    ("topic /qos/x_out publish keep_last 1 reliable volatile\n", "", "7 topics, the proved model has 8"),
    ("pyrosgen-qos 1\n", "", "not a QoS record"),
    ("best_effort volatile\n", "sometimes volatile\n", "is not 'topic NAME"),
])
def test_a_record_that_does_not_fit_is_refused(qos_node, old, new, says):
    out = qos_node.out_dir
    wrapper = (out / f"{NODE}_rcl.c").read_text()
    proved = (out / f"{NODE}.model").read_text()
    with pytest.raises(Ros2WrapperMismatch) as info:
        check_rcl_wrapper(wrapper, proved, wrapper_name="w.c", qos_record=RECORD.replace(old, new, 1))
    if says is not None:
        assert says in " ".join(info.value.lines), info.value.lines


def test_render_takes_the_qos_of_a_record_read_back(qos_node, ros2_install):
    """The wrapper rendered from the front end's model and from the record
    read back (what a re-render in ``verify`` does) is the same text."""
    from pyrosgen.ros2.wrapper import parse_qos_text

    out = qos_node.out_dir
    proved = parse_model_text((out / f"{NODE}.model").read_text())
    model = load_model_ros2(out.parent / "qos_node.yaml", ros2_install)
    plain = {t.name: t.qos for t in model.topics}
    assert parse_qos_text(RECORD, proved) == plain
    assert render_rcl_wrapper(model, proved, qos=parse_qos_text(RECORD, proved)) == \
        render_rcl_wrapper(model, proved, qos=plain)
    assert render_rcl_wrapper(model, proved, qos=plain)[f"{NODE}_rcl.c"] == (out / f"{NODE}_rcl.c").read_text()
    # the QoS is the record's: another record renders another wrapper, which the check refuses
    other = render_rcl_wrapper(model, proved, qos={name: DEFAULT_QOS for name in plain})[f"{NODE}_rcl.c"]
    with pytest.raises(Ros2WrapperMismatch):
        check_rcl_wrapper(other, (out / f"{NODE}.model").read_text(), wrapper_name="w.c", qos_record=RECORD)
    check_rcl_wrapper(other, (out / f"{NODE}.model").read_text(), wrapper_name="w.c")


def _forge(copy: Path, name: str) -> None:
    """Rewrite the digest of ``name`` in the manifest, the digest file and
    the certificate of the folder ``copy`` (a forger who edits a file)."""
    m = copy / f"{NODE}.manifest.json"
    data = json.loads(m.read_text())
    cert = copy / f"{NODE}.certificate.md"
    text = cert.read_text()
    new = hashlib.sha256((copy / name).read_bytes()).hexdigest()
    cert.write_text(text.replace(f"| `{name}` | `{data['files'][name]}` |", f"| `{name}` | `{new}` |"))
    data["files"][name] = new
    m.write_text(json.dumps(data, indent=2, sort_keys=True) + "\n")
    (copy / f"{NODE}.sha256").write_text("".join(f"{v}  {n}\n" for n, v in sorted(data["files"].items())))


@pytest.mark.parametrize("name, old, new, failed", [
    (f"{NODE}_rcl.c", "options.qos.durability = RMW_QOS_POLICY_DURABILITY_TRANSIENT_LOCAL;",
     "options.qos.durability = RMW_QOS_POLICY_DURABILITY_VOLATILE;", "package"),
    (f"{NODE}.qos", "/qos/tl_out publish keep_last 5 reliable transient_local",
     "/qos/tl_out publish keep_last 5 reliable volatile", "package"),
    ("model", "/qos/rel_in, direction: subscribe, type: std_msgs/Float64, queue_size: 1}",
     "/qos/rel_in, direction: subscribe, type: std_msgs/Float64, queue_size: 1, qos: sensor_data}", "model"),
], ids=["wrapper", "record", "model"])
def test_verify_refuses_an_edited_qos(qos_node, tmp_path, name, old, new, failed):
    """``verify`` of a copy whose wrapper QoS (or QoS record) was edited
    and its digest forged: the package check refuses it; ``verify --model``
    with a model file of another QoS: the model check refuses it."""
    copy = tmp_path / "copy"
    shutil.copytree(qos_node.out_dir, copy)
    args = ["verify", "-q", copy]
    if name == "model":
        (tmp_path / "m").mkdir()
        other = tmp_path / "m" / "qos_node.yaml"   # the same name: the .v names its model file
        other.write_text(MODEL.replace(old, new, 1), encoding="utf-8")
        assert other.read_text() != MODEL
        args += ["--model", other]
    else:
        text = (copy / name).read_text()
        assert text.count(old) >= 1
        (copy / name).write_text(text.replace(old, new, 1))
        _forge(copy, name)
    r = _cli(*args)
    assert r.returncode == 1, r.stdout + r.stderr
    failed_lines = [line for line in r.stdout.splitlines() if line.lstrip().startswith("FAILED")]
    assert [line.split()[1] for line in failed_lines] == [failed], r.stdout
    assert "rule 4.18" in r.stdout or "tl_out" in r.stdout, r.stdout


# --------------------------------------------------------------------------
# On a real DDS


def _run(qos_node, ros2_install, tmp_path: Path, plan: dict, node_first: bool = True, delay: float = 0.0):
    """Run the node and the QoS peer on ``plan``; (the peer's result, the
    node's output).  With ``node_first`` false the peer starts first and the
    node ``delay`` seconds later."""
    plan_file, result_file = tmp_path / "plan.json", tmp_path / "result.json"
    plan_file.write_text(json.dumps(plan))
    peer_argv = [ros2_install.python, QOS_PEER, plan_file, result_file]
    node = peer = None
    try:
        if node_first:
            node = spawn([qos_node.binary], tmp_path / "node.log")
            peer = spawn(peer_argv, tmp_path / "peer.log")
        else:
            peer = spawn(peer_argv, tmp_path / "peer.log")
            time.sleep(delay)
            node = spawn([qos_node.binary], tmp_path / "node.log")
        rc = peer.wait(timeout=plan["duration"] + 60)
    finally:
        if peer is not None and peer.poll() is None:
            stop(peer, signal.SIGKILL)
        status = stop(node, signal.SIGTERM) if node is not None else None
    log = (tmp_path / "node.log").read_text(errors="replace")
    assert rc == 0, (tmp_path / "peer.log").read_text(errors="replace")[-3000:]
    assert status == 0, f"the node did not end cleanly (status {status}):\n{log[-2000:]}"
    assert not (left := settled_leftovers()), left
    return json.loads(result_file.read_text()), log


def _values(result: dict, topic: str) -> Counter:
    return Counter(d for t, d, *_ in result["received"] if t == topic)


def test_incompatible_qos_delivers_nothing_and_the_node_says_so(qos_node, ros2_install, tmp_path, shm_guard):
    """A best-effort publisher for the node's reliable subscription, and a
    reliable subscriber to its best-effort (sensor-data) publisher: DDS
    never matches them, nothing is exchanged; the node runs on, its input
    the zero of the environment model's "no message yet" (twice 0 on
    /qos/rel_out), and reports each incompatibility once on standard error
    (and so does the peer, from its own events)."""
    plan = {"publishers": [{"topic": "/qos/rel_in", "qos": {"reliability": "best_effort"}, "value": 1.5}],
            "subscribers": [{"topic": "/qos/rel_out", "qos": {}},
                            {"topic": "/qos/sd_out", "qos": {"reliability": "reliable"}}],
            "duration": 40.0, "until": {"/qos/rel_out": 150}}   # 3 s of the node's output
    result, log = _run(qos_node, ros2_install, tmp_path, plan)
    assert result["published"]["/qos/rel_in"] > 50
    rel_out = _values(result, "/qos/rel_out")
    assert sum(rel_out.values()) >= 150 and set(rel_out) == {0.0}, rel_out   # the node runs; 1.5 never arrives
    assert not _values(result, "/qos/sd_out"), "a reliable subscriber received from a best-effort publisher"
    assert ("qos_node: warning: subscription /qos/rel_in: 1 publisher(s) with an incompatible QoS (policy "
            "reliability; this subscription is reliable, volatile): nothing is exchanged with it") in log, log
    assert ("qos_node: warning: publisher /qos/sd_out: 1 subscription(s) with an incompatible QoS (policy "
            "reliability; this publisher is best_effort, volatile)") in log, log
    assert log.count("incompatible QoS") == 2, log
    assert sorted((t, side) for t, side, _n in result["incompatible"]) == [
        ("/qos/rel_in", "publisher"), ("/qos/sd_out", "subscription")]


def test_compatible_qos_and_the_sensor_data_profile(qos_node, ros2_install, tmp_path, shm_guard):
    """A reliable publisher for the node's best-effort subscription
    (compatible: reliable offers more), rclpy's sensor-data profile for the
    node's (``qos: sensor_data``) in both directions: every value arrives,
    doubled, and nothing is reported."""
    plan = {"publishers": [{"topic": "/qos/be_in", "qos": {"reliability": "reliable"}, "value": 2.5},
                           {"topic": "/qos/sd_in", "qos": "sensor_data", "value": 3.5}],
            "subscribers": [{"topic": "/qos/tl_out", "qos": {}},   # volatile asks less than transient local
                            {"topic": "/qos/sd_out", "qos": "sensor_data"}],
            "duration": 40.0, "until": {"/qos/tl_out": 100, "/qos/sd_out": 100}}
    result, log = _run(qos_node, ros2_install, tmp_path, plan)
    tl, sd = _values(result, "/qos/tl_out"), _values(result, "/qos/sd_out")
    assert tl[5.0] > 50 and set(tl) <= {0.0, 5.0}, tl
    assert sd[7.0] > 50 and set(sd) <= {0.0, 7.0}, sd
    # ... and the values came after the zeros of the cycles before the first input
    for topic, v in (("/qos/tl_out", 5.0), ("/qos/sd_out", 7.0)):
        seq = [d for t, d, *_ in result["received"] if t == topic]
        assert seq[seq.index(v):].count(0.0) == 0, seq
    assert "incompatible" not in log and result["incompatible"] == [], (log, result["incompatible"])


def test_transient_local_late_joiner_gets_the_last_samples(qos_node, ros2_install, tmp_path, shm_guard):
    """The node's transient-local publisher (queue_size 5) and a
    transient-local rclpy subscriber that joins 3 s after the node: its
    first messages are the node's history, the last 5 samples published
    before it joined, delivered at once (their source timestamps a period
    apart, their receipt within a few milliseconds); a volatile late joiner
    on the same topic gets no history (it receives each sample as it is
    published)."""
    plan = {"publishers": [{"topic": "/qos/be_in", "qos": {}, "value": 4.0}],
            "subscribers": [{"topic": "/qos/tl_out", "qos": {"durability": "transient_local", "depth": 10},
                             "start_after": 3.0}],
            "duration": 40.0, "until": {"/qos/tl_out": 60}}
    result, _log = _run(qos_node, ros2_install, tmp_path, plan)
    got = [r for r in result["received"] if r[0] == "/qos/tl_out"]
    assert len(got) >= 60, len(got)
    first = got[:5]
    src = [s for _t, _d, s, _r in first]
    rcv = [r for _t, _d, _s, r in first]
    assert src == sorted(src)
    # the history: 5 samples published over about 4 periods (80 ms), received together
    assert src[-1] - src[0] >= 60_000_000, src
    assert rcv[-1] - rcv[0] <= 30_000_000, rcv
    # each was published before the first was received (published before the subscriber joined)
    assert all(s < rcv[0] for s in src), (src, rcv)


def test_transient_local_subscription_gets_a_sample_published_before_the_node(qos_node, ros2_install, tmp_path,
                                                                              shm_guard):
    """An rclpy transient-local publisher sends one value, once, then the
    node starts: its transient-local subscription receives the value (the
    publisher's history), so its output is twice that value; nothing is
    sent on the volatile topic the peer publishes once, too (its one
    sample was gone before the node joined)."""
    plan = {"publishers": [{"topic": "/qos/tl_in", "qos": {"durability": "transient_local", "depth": 1},
                            "value": 6.25, "once": True},
                           {"topic": "/qos/rel_in", "qos": {}, "value": 9.0, "once": True}],
            "subscribers": [{"topic": "/qos/x_out", "qos": {}}, {"topic": "/qos/rel_out", "qos": {}}],
            "duration": 40.0, "until": {"/qos/x_out": 60, "/qos/rel_out": 60}}
    result, _log = _run(qos_node, ros2_install, tmp_path, plan, node_first=False, delay=1.5)
    assert result["published"] == {"/qos/tl_in": 1, "/qos/rel_in": 1}
    x, rel = _values(result, "/qos/x_out"), _values(result, "/qos/rel_out")
    assert x[12.5] > 20, x
    assert set(rel) == {0.0} and sum(rel.values()) >= 60, rel


@pytest.mark.parametrize("old, new, fragment", [
    ("qos: {reliability: best_effort}}", "qos: {reliability: sometimes}}",
     "topics[1].qos.reliability must be one of reliable, best_effort, got 'sometimes' [rule 4.18]"),
    ("qos: sensor_data}\n  - {name: /qos/rel_out", "qos: {depth: 5}}\n  - {name: /qos/rel_out",
     "topics[3].qos: unknown key 'depth'; expected profile, reliability, durability (the history depth is the "
     "topic's queue_size) [rule 4.18]"),
])
def test_check_ros2_refuses_a_bad_qos_under_its_rule(tmp_path, ros2_install, old, new, fragment):
    """A bad QoS is refused for ROS 2 as for ROS 1, at its place, under
    rule 4.18 (not relabelled as a target difference, rule 4.17)."""
    assert MODEL.count(old) == 1
    p = tmp_path / "bad.yaml"
    p.write_text(MODEL.replace(old, new), encoding="utf-8")
    text = p.read_text()
    line = text[: text.index(new)].count("\n") + 1
    for args in (("check", "--ros2", p), ("check", p)):
        r = _cli(*args)
        assert r.returncode == 1 and r.stdout == "" and "Traceback" not in r.stderr, r.stderr
        errors = [x for x in r.stderr.splitlines() if ": error: " in x]
        assert len(errors) == 1 and errors[0].startswith(f"{p}:{line}:") and errors[0].endswith(fragment), r.stderr


def test_verify_refuses_a_folder_without_its_qos_record(qos_node, tmp_path):
    """The record removed, and from the manifest, the digest file and the
    certificate too: the package check refuses the folder (a ROS 2 build
    has one; without it the wrapper's QoS would be held to nothing)."""
    copy = tmp_path / "copy"
    shutil.copytree(qos_node.out_dir, copy)
    name = f"{NODE}.qos"
    (copy / name).unlink()
    m = copy / f"{NODE}.manifest.json"
    data = json.loads(m.read_text())
    digest = data["files"].pop(name)
    m.write_text(json.dumps(data, indent=2, sort_keys=True) + "\n")
    (copy / f"{NODE}.sha256").write_text("".join(f"{v}  {n}\n" for n, v in sorted(data["files"].items())))
    cert = copy / f"{NODE}.certificate.md"
    lines = [x for x in cert.read_text().splitlines(keepends=True) if f"| `{name}` | `{digest}` |" not in x]
    cert.write_text("".join(lines))
    r = _cli("verify", "-q", copy)
    assert r.returncode == 1, r.stdout + r.stderr
    failed = [line.split()[1] for line in r.stdout.splitlines() if line.lstrip().startswith("FAILED")]
    assert "package" in failed, r.stdout
    assert f"{name}: missing (or not covered by the manifest): a ROS 2 build's QoS record" in r.stdout, r.stdout

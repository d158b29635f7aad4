"""Direct input relations (DESIGN.md rule 4.16), without Coq.

An input relation is direct when its topic is not timed (rule 4.12: no
``timeout_ms``, no derived input) and its message path has an index step
(an element of a variable-length array, of a string or of a fixed-size
array).  The predicate (``pyrosgen.frontend.model.is_direct``, through
``NodeModel.is_direct`` and the proved model's ``ProvedModel.is_direct``),
the leaves a callback keeps in its topic's global
(``NodeModel.read_leaves``: non-direct relations and copied stamps), and
the WP contracts: a callback assigns and ensures its direct relations,
from ``*msg``; ``input_glue`` only the others.  The printed C, the
certificate and Frama-C on it are in
tests/generate/test_direct_generate.py."""

from __future__ import annotations

import pytest

from pyrosgen import load_model
from pyrosgen.frontend.model import is_direct
from pyrosgen.proof.modeltext import model_text, parse_model_text
from pyrosgen.verify.acsl import contracts

from support.frontend import LANDSHARK, REPO, load

MODEL = REPO / "tests" / "generate" / "models" / "ok_direct.yaml"

#: The model's relations, by controller input: whether each is direct.
DIRECT = {
    **{f"Scan[{i}]": True for i in range(4)},  # /scan ranges.data[i]
    "N": False,          # /scan ranges.len: no index
    "PX": False,         # /pose pose.pose.position.x: no index
    "R1": True,          # /scan ranges.data[1], a second reader of the leaf
    "Cov3": True,        # /pose pose.covariance[3]: a fixed-size array
    "F0": True,          # /scan header.frame_id.data[0]: a string byte
    "T2": False,         # /tscan ranges.data[2]: the topic has a timeout
    "TN": False,
    "D1": False,         # /dscan ranges.data[1]: the topic has a derived input
}


@pytest.fixture(scope="module")
def model():
    return load_model(MODEL)


def test_the_predicate_on_paths():
    assert is_direct("ranges.data[5]", timed=False)
    assert is_direct("poses.data[0].pose.position.x", timed=False)
    assert is_direct("header.frame_id.data[3]", timed=False)
    assert is_direct("covariance[3]", timed=False)
    for path in ("ranges.len", "ranges.truncated", "twist.linear.x", "header.stamp.sec"):
        assert not is_direct(path, timed=False), path
    for path in ("ranges.data[5]", "covariance[3]"):
        assert not is_direct(path, timed=True), path


def test_which_relations_are_direct(model):
    assert {r.input_target: model.is_direct(r) for r in model.input_relations} == DIRECT
    assert [t.name for t in model.timed_topics] == ["/tscan", "/dscan"]
    direct = {t.name: [r.input_target for r in model.direct_relations(t)] for t in model.subscribed}
    # model order (the whole scan's elements first, then R1, then F0)
    assert direct == {"/scan": ["Scan[0]", "Scan[1]", "Scan[2]", "Scan[3]", "R1", "F0"], "/pose": ["Cov3"],
                      "/tscan": [], "/dscan": []}
    assert model.direct_relations("/pose") == model.direct_relations(model.topic("/pose"))
    assert [r.input_target for r in model.glue_relations] == ["N", "PX", "T2", "TN", "D1"]


def test_the_proved_model_decides_the_same(model):
    """The certificate reads the model Coq printed: its predicate (the
    same function) agrees with the front end's on every relation."""
    pm = parse_model_text(model_text(model))
    assert pm.timed == {"tscan", "dscan"}
    got = {fld: pm.is_direct(c, path) for c, path, fld in pm.input_relations}
    assert got == DIRECT


def test_read_leaves_leave_out_the_direct_relations(model):
    """A callback keeps in its global the leaves of the non-direct
    relations and of a stamp copied from the topic, in leaf order; no
    element of an untimed topic.  A timed topic keeps its elements."""
    leaves = {t.name: [str(p) for p in model.read_leaves(t)] for t in model.subscribed}
    assert leaves == {
        "/scan": ["header.stamp.sec", "header.stamp.nsec", "ranges.len"],
        "/pose": ["pose.pose.position.x"],
        "/tscan": ["ranges.len", "ranges.data[2]"],
        "/dscan": ["ranges.data[1]"],
    }


def test_a_timeout_makes_every_relation_of_the_topic_go_through_input_glue(tmp_path):
    text = MODEL.read_text().replace(
        "{name: /pose, direction: subscribe, type: geometry_msgs/PoseWithCovarianceStamped, queue_size: 1}",
        "{name: /pose, direction: subscribe, type: geometry_msgs/PoseWithCovarianceStamped, queue_size: 1, "
        "timeout_ms: 100, on_timeout: hold}")
    assert text != MODEL.read_text()
    m = load(tmp_path, text)
    assert not m.direct_relations("/pose")
    assert [str(p) for p in m.read_leaves(m.topic("/pose"))] == ["pose.pose.position.x", "pose.covariance[3]"]
    assert "Cov3" in [r.input_target for r in m.glue_relations]


def test_models_without_elements_have_no_direct_relation():
    m = load_model(LANDSHARK)
    assert m.glue_relations == m.input_relations
    assert all(not m.direct_relations(t) for t in m.subscribed)


def test_contracts_of_the_callbacks_and_input_glue(model):
    cs = {c.name: c for c in contracts(model)}
    scan = cs["scan_callback"]
    assert scan.assigns == ("scan_msg.header.stamp.sec", "scan_msg.header.stamp.nsec", "scan_msg.ranges.len",
                            "D_U.Scan[0]", "D_U.Scan[1]", "D_U.Scan[2]", "D_U.Scan[3]", "D_U.R1", "D_U.F0")
    assert scan.ensures[:3] == ("scan_msg.header.stamp.sec == \\old(msg->header.stamp.sec)",
                                "scan_msg.header.stamp.nsec == \\old(msg->header.stamp.nsec)",
                                "scan_msg.ranges.len == \\old(msg->ranges.len)")
    assert scan.ensures[3:] == (
        *(f"{{ rosgen_wp_f32 \\with .v = D_U.Scan[{i}] }} == {{ rosgen_wp_f32 \\with .v = \\old(msg->ranges.data[{i}]) }}"
          for i in range(4)),
        "{ rosgen_wp_f32 \\with .v = D_U.R1 } == { rosgen_wp_f32 \\with .v = \\old(msg->ranges.data[1]) }",
        "D_U.F0 == \\old(msg->header.frame_id.data[0])")
    # every leaf read is valid, each stated once (ranges.data[1] has two readers)
    assert scan.requires[2:] == ("\\valid_read(&msg->header.stamp.sec)", "\\valid_read(&msg->header.stamp.nsec)",
                                 "\\valid_read(&msg->ranges.len)",
                                 *(f"\\valid_read(&msg->ranges.data[{i}])" for i in range(4)),
                                 "\\valid_read(&msg->header.frame_id.data[0])")
    assert "&D_U" in scan.separated
    assert cs["pose_callback"].assigns == ("pose_msg.pose.pose.position.x", "D_U.Cov3")
    # the timed topics' callbacks write no input: their elements are in the global
    assert cs["tscan_callback"].assigns == ("tscan_msg.ranges.len", "tscan_msg.ranges.data[2]",
                                            "tscan_time", "tscan_new", "tscan_rcvd")
    assert cs["dscan_callback"].assigns == ("dscan_msg.ranges.data[1]", "dscan_time", "dscan_new", "dscan_rcvd")
    glue = cs["input_glue"]
    assert glue.assigns == ("D_U.N", "D_U.PX", "D_U.T2", "D_U.TN", "D_U.D1", "D_U.DNew", "tscan_new", "dscan_new")
    assert not any("D_U.Scan" in e or "D_U.R1" in e or "D_U.Cov3" in e or "D_U.F0" in e for e in glue.ensures)
    assert "{ rosgen_wp_f32 \\with .v = D_U.D1 } == { rosgen_wp_f32 \\with .v = \\old(dscan_msg.ranges.data[1]) }" \
        in glue.ensures

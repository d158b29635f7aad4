"""``pyrosgen diagram`` draws timing (issue 30): derived inputs (rule 4.12)
as edges from the topic's callback to the input they feed, each topic's
timeout and on_timeout, each input's value while its topic is stale, and
the stamps of published topics (rule 4.13), with an edge from the topic a
stamp is copied from."""

from __future__ import annotations

from pathlib import Path

import pytest

from pyrosgen.diagram import render_dot
from pyrosgen.frontend.validate import load_model

from support.diagram import LANDSHARK, REPO, parse_with_dot

VELOCITY_GUARD = REPO / "examples" / "velocity_guard" / "velocity_guard.yaml"
STAMPED = REPO / "examples" / "landshark" / "landshark_stamped.yaml"
GPS_STAMPED = REPO / "examples" / "landshark" / "landshark_gps_stamped.yaml"

#: Every policy of rule 4.12 and every derived kind, on one timed topic and
#: one topic with derived inputs only (the README's example, completed).
TIMED = """\
node: {name: timed, period_ms: 20}
controller:
  name: Guard
  inputs: {name: Guard_U, fields: {TVx: float64, TWz: float64, TVy: float64, TAge: uint32, TNew: bool,
                                   TSeen: bool, NVx: float64, NNew: bool}}
  outputs: {name: Guard_Y, fields: {Vx: float64}}
topics:
  - {name: /teleop/cmd_vel, direction: subscribe, type: geometry_msgs/Twist, queue_size: 1,
     timeout_ms: 500, on_timeout: zero}
  - {name: /nav/cmd_vel, direction: subscribe, type: geometry_msgs/Twist, queue_size: 2}
  - {name: /cmd_vel, direction: publish, type: geometry_msgs/Twist, queue_size: 1}
relations:
  inputs:
    - {topic: /teleop/cmd_vel, field: linear.x,  input: TVx}
    - {topic: /teleop/cmd_vel, field: angular.z, input: TWz, on_timeout: hold}
    - {topic: /teleop/cmd_vel, field: linear.y,  input: TVy, on_timeout: -1.5}
    - {topic: /teleop/cmd_vel, derived: age_ms,  input: TAge}
    - {topic: /teleop/cmd_vel, derived: is_new,  input: TNew}
    - {topic: /teleop/cmd_vel, derived: received, input: TSeen}
    - {topic: /nav/cmd_vel,    field: linear.x,  input: NVx}
    - {topic: /nav/cmd_vel,    derived: is_new,  input: NNew}
  outputs:
    - {output: Vx, topic: /cmd_vel, field: linear.x}
"""


@pytest.fixture(scope="module")
def timed(tmp_path_factory):
    p = tmp_path_factory.mktemp("timed") / "timed.yaml"
    p.write_text(TIMED)
    return parse_with_dot(render_dot(load_model(p)))


def test_derived_inputs_are_edges_from_the_callback(timed):
    got = sorted((e["tail"], e["head"], e["headport"].split(":")[0], e["label"])
                 for e in timed.edges_with_id("derived"))
    assert got == sorted([
        ("cb0", "ctrl_u", "f3", "age_ms (derived) : uint32"),
        ("cb0", "ctrl_u", "f4", "is_new (derived) : bool"),
        ("cb0", "ctrl_u", "f5", "received (derived) : bool"),
        ("cb1", "ctrl_u", "f7", "is_new (derived) : bool"),
    ])
    # every controller input is fed once: by an input relation or a derived input
    fed = [e["headport"].split(":")[0] for e in timed.edges_with_id("in_rel") + timed.edges_with_id("derived")]
    assert sorted(fed) == [f"f{i}" for i in range(8)]


def test_timeouts_and_what_a_stale_input_gets(timed):
    assert timed.nodes["sub0"] == ["/teleop/cmd_vel", "geometry_msgs/Twist", "queue 1",
                                   "timeout 500 ms, on_timeout zero"]
    assert timed.nodes["sub1"] == ["/nav/cmd_vel", "geometry_msgs/Twist", "queue 2"]
    got = sorted((e["tail"], e["headport"].split(":")[0], e["label"]) for e in timed.edges_with_id("in_rel"))
    assert got == sorted([
        ("msg0", "f0", "linear.x : float64 stale: zero"),      # the topic's policy
        ("msg0", "f1", "angular.z : float64 stale: hold"),     # its own
        ("msg0", "f2", "linear.y : float64 stale: -1.5"),      # a constant
        ("msg1", "f6", "linear.x : float64"),                  # no timeout: nothing stale
    ])


def test_velocity_guard_example():
    model = load_model(VELOCITY_GUARD)
    g = parse_with_dot(render_dot(model))
    u = model.controller.inputs.names
    got = sorted((e["tail"], e["headport"].split(":")[0], e["label"]) for e in g.edges_with_id("derived"))
    assert got == [("cb0", f"f{u.index('TAge')}", "age_ms (derived) : uint32"),
                   ("cb1", f"f{u.index('NAge')}", "age_ms (derived) : uint32")]
    for i in (0, 1):
        assert g.nodes[f"sub{i}"][-1] == "timeout 500 ms, on_timeout zero"


def test_stamp_now():
    g = parse_with_dot(render_dot(load_model(STAMPED)))
    assert "header.stamp: now (the cycle's ROS time)" in g.nodes["pub0"]
    assert g.edges_with_id("stamp") == []


def test_stamp_from_a_subscribed_topic():
    model = load_model(GPS_STAMPED)
    g = parse_with_dot(render_dot(model))
    assert "header.stamp: from /landshark/gps_velocity" in g.nodes["pub0"]
    src = [t.name for t in model.subscribed].index("/landshark/gps_velocity")
    assert [(e["tail"], e["head"], e["label"]) for e in g.edges_with_id("stamp")] == [
        (f"msg{src}", "og0", "header.stamp")]


def test_untimed_node_draws_no_timing():
    g = parse_with_dot(render_dot(load_model(LANDSHARK)))
    assert g.edges_with_id("derived") == [] and g.edges_with_id("stamp") == []
    texts = " ".join(" ".join(t) for t in g.nodes.values())
    assert "timeout" not in texts and "stamp" not in texts and "stale" not in " ".join(e["label"] for e in g.edges)

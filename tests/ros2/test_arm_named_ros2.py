"""The arm that finds its joints by name (examples/arm_named: an array of
strings into controller arrays, rule 4.15; its Embedded Coder controller)
built for ROS 2 and driven by an rclpy peer on Fast DDS: the rcl wrapper
converts rosidl's sequence of strings element by element (at most 6
names of at most 32 bytes, each capped, zeros after).  The cases and the
reference are those of tests/ros/test_arm_named_node.py (ROS 1): entries
in the controller's order, reversed, shuffled, with a gripper before or
after, 0, 1, N-1, N, N+1 and 2N names, a name one byte too long, names
longer than the 32 bytes carried; every effort message bit for bit."""

from __future__ import annotations

import signal
import struct

import pytest

from pyrosgen.ros2.build import build_ros2

from .conftest import run_peer, settled_leftovers, spawn, stop
from ros.test_arm_named_node import CASES, EFFORT, EMAX, EXAMPLE, JS, TARGET, _state, efforts

SETTLE, HOLD = 0.3, 0.8


def bits(x: float) -> int:
    return struct.unpack("<Q", struct.pack("<d", x))[0]


@pytest.fixture(scope="module")
def arm_named2(ros2_install, ros2_nodes):
    res = build_ros2(EXAMPLE / "arm_named.yaml", EXAMPLE / "controller", ros2_nodes / "arm_named",
                     install=ros2_install)
    assert "rosidl_runtime_c__String__Sequence" in (res.out_dir / "arm_named_rcl.c").read_text()
    return res.binary


def test_arm_named_ros2_matches_joints_by_name(arm_named2, ros2_install, tmp_path, shm_guard):
    steps, wants = [{"sleep": 0.5}], []
    for k, (_, names, npos, scale, ntgt) in enumerate(CASES):
        state = _state(list(names), k, npos)
        targets = [scale * (0.3 * i - 0.6) for i in range(ntgt)]
        steps += [{"publish": {JS: {"name": state["name"], "position": [bits(x) for x in state["position"]],
                                    "velocity": [bits(x) for x in state["velocity"]],
                                    "header.frame_id": "base_link"},
                               TARGET: {"data": [bits(x) for x in targets]}}},
                  {"sleep": HOLD}]
        wants.append(efforts(state["name"], state["position"], state["velocity"], targets))
    assert sum(1 for w in wants if w) >= 5 and sum(1 for w in wants if not w) >= 5
    node = spawn([arm_named2], tmp_path / "node.log")
    try:
        result = run_peer({"publishers": {JS: "sensor_msgs/JointState", TARGET: "std_msgs/Float64MultiArray"},
                           "subscribers": {EFFORT: "std_msgs/Float64MultiArray"}, "match_timeout": 20.0,
                           "steps": steps}, tmp_path, ros2_install)
    finally:
        status = stop(node, signal.SIGTERM)
    assert status == 0, (tmp_path / "node.log").read_text(errors="replace")[-2000:]
    got_all = [(t, lv) for t, topic, lv in result["received"] if topic == EFFORT]
    first_pub = result["steps"][1]["t0"]
    before = [lv for t, lv in got_all if t < first_pub]
    assert before and all(lv == {"layout.dim": [], "layout.data_offset": 0, "data": []} for lv in before)
    for k, ((what, *_), want) in enumerate(zip(CASES, wants)):
        t0, t1 = result["steps"][1 + 2 * k]["t1"] + SETTLE, result["steps"][2 + 2 * k]["t1"]
        expect = {"layout.dim": [], "layout.data_offset": 0, "data": [bits(e) for e in want]}
        got = [lv for t, lv in got_all if t0 <= t <= t1]
        assert len(got) >= 10, (what, len(got))
        assert all(g == expect for g in got), (what, got[-1], expect)
    assert any(w and max(w) == EMAX for w in wants) and any(w and min(w) == -EMAX for w in wants)
    assert not (left := settled_leftovers()), left

"""examples/multi on ROS 2, end to end on a real DDS (Fast DDS from the
wheels, loopback only): odometry, IMU, range and a custom e-stop message
in, a velocity command and a custom status message out.

The example is written for ROS 1 (``header.seq``, a bare ``Header`` and
``duration`` in its ``.msg`` files), which the ROS 2 reading refuses
(rule 4.17, README "ROS 2"); its ROS 2 twin is made here from it with the
fewest edits, each asserted to apply once: ``header.seq`` becomes
``header.stamp.nanosec`` (the uint32 of ROS 2's header) on both sides, and
the ``.msg`` files say ``std_msgs/Header`` and
``builtin_interfaces/Duration``.  Built with ``--ros2``, the custom package
robot_msgs by rosidl, with the bit-exact test controller of tests/ros
(multi_echo's Fusion.c); an rclpy peer that imports the build's Python
types publishes random messages in rounds (a round changing only the IMU
too) and checks every leaf of both published messages, bit for bit,
against the controller's twin (support.expect.multi_echo)."""

from __future__ import annotations

import json
import random
import shutil
import signal
import struct

import pytest

from pyrosgen.ros2.build import build_ros2
from pyrosgen.ros2.rosidl import peer_env

from support import expect
from support import ros as rosutil

from .conftest import PEER, run_peer, settled_leftovers, spawn, stop

EDITS = [  # (file relative to examples/multi, old, new)
    ("multi_node.yaml", "field: header.seq,               input: OdomSeq",
     "field: header.stamp.nanosec,     input: OdomSeq"),
    ("multi_node.yaml", "{output: SeqOut,    topic: /fusion/status, field: header.seq}",
     "{output: SeqOut,    topic: /fusion/status, field: header.stamp.nanosec}"),
    ("msg/robot_msgs/msg/EStop.msg", "\nHeader header\n", "\nstd_msgs/Header header\n"),
    ("msg/robot_msgs/msg/EStop.msg", "\nduration hold_time ", "\nbuiltin_interfaces/Duration hold_time "),
    ("msg/robot_msgs/msg/FusionStatus.msg", "\nHeader header\n", "\nstd_msgs/Header header\n"),
]
MULTI = rosutil.ROOT / "examples" / "multi"
#: the ROS 2 twin's inputs: (topic, ROS 2 type, {leaf: (controller input, primitive)})
INPUTS = {
    "/odom": ("nav_msgs/Odometry", {"pose.pose.position.x": ("X", "float64"), "pose.pose.position.y": ("Y", "float64"),
                                    "twist.twist.angular.z": ("YawRate", "float64"),
                                    "header.stamp.nanosec": ("OdomSeq", "uint32")}),
    "/imu/data": ("sensor_msgs/Imu", {"angular_velocity.z": ("GyroZ", "float64"),
                                      "linear_acceleration.x": ("AccX", "float64")}),
    "/range_front": ("sensor_msgs/Range", {"range": ("FrontRange", "float32"), "radiation_type": ("RangeType", "uint8")}),
    "/safety/estop": ("robot_msgs/EStop", {"engaged": ("EStop", "bool"), "hold_time.sec": ("HoldSec", "int32")}),
}
CMD, STATUS = "/cmd_vel", "/fusion/status"
SETTLE, HOLD = 0.3, 0.7


def f32_as_f64(b: int) -> int:
    return rosutil.dbits(struct.unpack("<f", struct.pack("<I", b))[0])


@pytest.fixture(scope="module")
def multi2(ros2_install, ros2_nodes, tmp_path_factory):
    src = tmp_path_factory.mktemp("multi_ros2")
    shutil.copy(MULTI / "multi_node.yaml", src / "multi_node.yaml")
    shutil.copytree(MULTI / "msg", src / "msg")
    for rel, old, new in EDITS:
        text = (src / rel).read_text()
        assert text.count(old) == 1, (rel, old)
        (src / rel).write_text(text.replace(old, new))
    return build_ros2(src / "multi_node.yaml", rosutil.CONTROLLERS / "multi_echo", ros2_nodes / "multi",
                      install=ros2_install)


def _round(rng: random.Random, mode: str, topics) -> tuple[dict, dict]:
    """One message per topic of ``topics``: what the peer publishes (floats
    as the bits of their double) and the leaves as controller input bits."""
    pub, u = {}, {}
    for topic in topics:
        _ty, leaves = INPUTS[topic]
        msg = {}
        for leaf, (inp, prim) in leaves.items():
            v = rosutil.random_value(prim, rng, mode, leaf)
            if prim == "float64":
                u[inp] = msg[leaf] = rosutil.bits_of(v)
            elif prim == "float32":
                u[inp] = rosutil.bits_of(v)
                msg[leaf] = f32_as_f64(u[inp])
            else:
                u[inp] = msg[leaf] = v
        if topic == "/odom":   # pose.covariance[35] -> YawVar: the whole array, the others distinct
            cov = [rosutil.bits_of(rosutil.random_value("float64", rng, mode)) for _ in range(36)]
            msg["pose.covariance"], u["YawVar"] = cov, cov[35]
        pub[topic] = msg
    return pub, u


def _published(y: dict) -> dict:
    """Both published messages for controller outputs ``y``, as the peer
    reports them (the output relations; every other leaf zero or empty)."""
    w = f32_as_f64(y["WheelCmd"])
    zero = {"velocity": 0, "current": 0, "temperature": 0, "name": ""}
    return {
        CMD: {"linear.x": y["CmdV"], "linear.y": 0, "linear.z": 0, "angular.x": 0, "angular.y": 0,
              "angular.z": y["CmdW"]},
        STATUS: {"header.stamp.sec": 0, "header.stamp.nanosec": y["SeqOut"], "header.frame_id": "",
                 "yaw_variance": y["YawVarOut"], "stopped": bool(y["Stopped"]), "odom_seq": y["SeqOut"],
                 "wheel_speeds": [w, w, 0, 0], "wheels": [zero, {**zero, "velocity": w}], "note": ""},
    }


def test_multi_ros2_end_to_end_bit_exact(multi2, ros2_install, tmp_path, shm_guard):
    rng = random.Random(31)
    rounds = [_round(rng, m, INPUTS) for m in ("random", "special", "max", "min", "random")]
    rounds.append(_round(rng, "random", ["/imu/data"]))   # only the IMU changes: the others stay
    steps = [{"sleep": 0.5}]
    for pub, _u in rounds:
        steps += [{"publish": pub}, {"sleep": HOLD}]
    plan = {"publishers": {t: ty for t, (ty, _) in INPUTS.items()},
            "subscribers": {CMD: "geometry_msgs/Twist", STATUS: "robot_msgs/FusionStatus"},
            "match_timeout": 20.0, "steps": steps}
    (tmp_path / "peer.plan.json").write_text(json.dumps(plan))
    node = spawn([multi2.binary], tmp_path / "node.log")
    try:
        peer = spawn([ros2_install.python, PEER, tmp_path / "peer.plan.json", tmp_path / "peer.result.json"],
                     tmp_path / "peer.log", peer_env(multi2.out_dir))
        result = run_peer(plan, tmp_path, ros2_install, started=peer)
    finally:
        status = stop(node, signal.SIGTERM)
    assert status == 0, (tmp_path / "node.log").read_text(errors="replace")[-2000:]
    rsteps, received = result["steps"], result["received"]
    u = {f.name: 0 for f in multi2.model.controller.inputs.fields}
    problems = []
    want = _published(expect.multi_echo(u))
    for topic in (CMD, STATUS):
        got = [lv for t, tp, lv in received if tp == topic and t < rsteps[1]["t0"]]
        assert len(got) >= 5, (topic, len(got))
        problems += [f"before any input, {topic}: {g}" for g in got if g != want[topic]][:2]
    for k, (_pub, uk) in enumerate(rounds):
        u.update(uk)
        want = _published(expect.multi_echo(u))
        t0, t1 = rsteps[1 + 2 * k]["t1"] + SETTLE, rsteps[2 + 2 * k]["t1"]
        for topic in (CMD, STATUS):
            got = [lv for t, tp, lv in received if tp == topic and t0 <= t <= t1]
            assert len(got) >= 10, (k, topic, len(got))
            problems += [f"round {k}, {topic}: {g} != {want[topic]}" for g in got if g != want[topic]][:2]
    assert not problems, "\n".join(problems[:10])
    assert not (left := settled_leftovers()), left

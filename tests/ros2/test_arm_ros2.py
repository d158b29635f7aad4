"""The 6-joint arm (examples/arm: variable-length arrays both ways, rule
4.15, policy truncate; the controller from its block diagram) built for
ROS 2 and driven by an rclpy peer on Fast DDS: the rcl wrapper converts
rosidl sequences into the bounded structs (the first 6 elements, len,
truncated, zeros after) and back (the first len elements).  Every effort
message is checked bit for bit against the PD law computed here in IEEE
binary64, as tests/ros/test_arm_node.py does on ROS 1: 6 elements when the
newest joint state has at least 6 positions and 6 velocities and the newest
target at least 6 angles, else none (also before the first messages).  The
same under AddressSanitizer and UndefinedBehaviorSanitizer (the glue, the
controller and the wrapper's conversions compiled with them): any error
ends the node with a non-zero status, which fails the test."""

from __future__ import annotations

import signal
import struct

import pytest

from pyrosgen.ros2.build import build_ros2

from support import ros as rosutil

from .conftest import run_peer, settled_leftovers, spawn, stop

MODEL = rosutil.ROOT / "examples" / "arm" / "arm.yaml"
JS, TARGET, EFFORT = "/joint_states", "/arm/target", "/arm/effort"
KP, KD, UMAX = 20.0, 2.0, 50.0
SETTLE, HOLD = 0.3, 0.8

CASES = [
    ("6 joints, 6 targets", 6, 6, 6, 1.0),
    ("5 positions", 5, 6, 6, 1.0),
    ("6 joints again, saturated", 6, 6, 6, 10.0),
    ("5 velocities", 6, 5, 6, 1.0),
    ("7 joints: the first 6", 7, 7, 6, 1.0),
    ("3 targets", 6, 6, 3, 1.0),
    ("8 targets: the first 6", 6, 6, 8, -10.0),
    ("12 joints (2N): the first 6", 12, 12, 6, 1.0),
    ("no joint at all", 0, 0, 6, 1.0),
    ("1 joint", 1, 1, 1, 1.0),
    ("6 joints, 6 targets, small errors", 6, 6, 6, 0.5),
]


def bits(x: float) -> int:
    return struct.unpack("<Q", struct.pack("<d", x))[0]


def pd(target: float, pos: float, vel: float) -> float:
    u = KP * (target - pos) - KD * vel
    return min(max(u, -UMAX), UMAX)


def _joints(n: int, k: int) -> tuple[list[float], list[float]]:
    return [0.1 * (i + 1) + 0.01 * k for i in range(n)], [0.5 - 0.125 * i + 0.25 * k for i in range(n)]


#: the sanitized build: the glue, the controller and the rcl wrapper's
#: conversions under ASan and UBSan, any error fatal (the node's exit status)
SANITIZED_CC = "gcc -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer"
SANITIZED_ENV = {"ASAN_OPTIONS": "detect_leaks=0:abort_on_error=0:exitcode=86",
                 "UBSAN_OPTIONS": "print_stacktrace=1:halt_on_error=1:exitcode=87"}


@pytest.fixture(scope="module", params=["gcc", "sanitizers"])
def arm2(request, ros2_install, ros2_nodes):
    """The arm built for ROS 2, plain and under ASan/UBSan: (binary, extra
    environment of the node)."""
    import os
    sanitized = request.param == "sanitizers"
    old = os.environ.get("CC")
    if sanitized:
        os.environ["CC"] = SANITIZED_CC
    try:
        res = build_ros2(MODEL, None, ros2_nodes / f"arm_{request.param}", install=ros2_install)
    finally:
        if old is None:
            os.environ.pop("CC", None)
        else:
            os.environ["CC"] = old
    proved = res.generated.proved_model.splitlines()
    assert "output_relation NE arm_effort data.len" in proved
    return res.binary, (SANITIZED_ENV if sanitized else {})


def test_arm_ros2_pd_effort_per_joint(arm2, ros2_install, tmp_path, shm_guard):
    steps, wants = [{"sleep": 0.5}], []
    for k, (_, npos, nvel, ntgt, scale) in enumerate(CASES):
        pos, _ = _joints(npos, k)
        _, vel = _joints(nvel, k)
        targets = [scale * (0.3 * i - 0.6) for i in range(ntgt)]
        names = [f"joint_{i + 1}" for i in range(max(npos, nvel))]
        steps += [{"publish": {JS: {"name": names, "position": [bits(x) for x in pos],
                                    "velocity": [bits(x) for x in vel],
                                    "effort": [bits(1.0)] * len(names), "header.frame_id": "base_link"},
                               TARGET: {"data": [bits(x) for x in targets]}}},
                  {"sleep": HOLD}]
        wants.append([pd(targets[i], pos[i], vel[i]) for i in range(6)]
                     if npos >= 6 and nvel >= 6 and ntgt >= 6 else [])
    binary, extra_env = arm2
    node = spawn([binary], tmp_path / "node.log", extra_env)
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
    assert before and all(lv == {"layout.dim": [], "layout.data_offset": 0, "data": []} for lv in before), before[:2]
    saturated = 0
    for k, ((what, *_), want) in enumerate(zip(CASES, wants)):
        t0, t1 = result["steps"][1 + 2 * k]["t1"] + SETTLE, result["steps"][2 + 2 * k]["t1"]
        expect = {"layout.dim": [], "layout.data_offset": 0, "data": [bits(e) for e in want]}
        got = [lv for t, lv in got_all if t0 <= t <= t1]
        assert len(got) >= 10, (what, len(got))
        assert all(g == expect for g in got), (what, got[-1], expect)
        saturated += sum(abs(e) == UMAX for e in want)
    assert saturated >= 6
    assert not (left := settled_leftovers()), left

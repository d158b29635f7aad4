"""The velocity guard (examples/velocity_guard: timed topics, rule 4.12;
the controller from its block diagram) built for ROS 2 and driven by an
rclpy peer on Fast DDS: the rcl wrapper's ``ros_now`` (a message's receipt
time from rmw's message info, the cycle's time from the ROS clock) must
make the proved freshness glue switch sources as on ROS 1 under wall time:
teleop's command while it is fresh; nav's once teleop has been silent for
more than 500 ms (never before); zero once nav too has been silent for more
than 500 ms (never before).  How late after the timeout a switch comes is
not tested (a measurement)."""

from __future__ import annotations

import signal
import struct

import pytest

from pyrosgen.ros2.build import build_ros2

from support import ros as rosutil

from .conftest import run_peer, settled_leftovers, spawn, stop

MODEL = rosutil.ROOT / "examples" / "velocity_guard" / "velocity_guard.yaml"
TELEOP, NAV, OUT = "/teleop/cmd_vel", "/nav/cmd_vel", "/cmd_vel"
TWIST = "geometry_msgs/Twist"
TELEOP_CMD, NAV_CMD, ZERO = (1.0, 0.1), (2.0, 0.2), (0.0, 0.0)
TIMEOUT_S = 0.5
#: a cycle (20 ms) and delivery, past which the switch must have happened
MARGIN_S = 0.25


def bits(x: float) -> int:
    return struct.unpack("<Q", struct.pack("<d", x))[0]


def cmd(vx: float, wz: float) -> dict:
    return {"linear.x": bits(vx), "angular.z": bits(wz)}


def value(lv: dict) -> tuple[float, float]:
    assert all(v == 0 for k, v in lv.items() if k not in ("linear.x", "angular.z")), lv
    f = {k: struct.unpack("<d", struct.pack("<Q", lv[k]))[0] for k in ("linear.x", "angular.z")}
    return f["linear.x"], f["angular.z"]


@pytest.fixture(scope="module")
def guard2(ros2_install, ros2_nodes):
    res = build_ros2(MODEL, None, ros2_nodes / "velocity_guard", install=ros2_install)
    return res.binary


def test_velocity_guard_ros2_timeouts_wall_time(guard2, ros2_install, tmp_path, shm_guard):
    node = spawn([guard2], tmp_path / "node.log")
    try:
        plan = {"publishers": {TELEOP: TWIST, NAV: TWIST}, "subscribers": {OUT: TWIST}, "match_timeout": 20.0,
                "steps": [{"stream": {TELEOP: cmd(*TELEOP_CMD), NAV: cmd(*NAV_CMD)}, "period": 0.05, "duration": 1.5},
                          {"stream": {NAV: cmd(*NAV_CMD)}, "period": 0.05, "duration": 1.5},
                          {"sleep": 1.5}]}
        result = run_peer(plan, tmp_path, ros2_install)
    finally:
        status = stop(node, signal.SIGTERM)
    assert status == 0, (tmp_path / "node.log").read_text(errors="replace")[-2000:]
    both, nav_only, silent = result["steps"]
    out = [(t, value(lv)) for t, topic, lv in result["received"] if topic == OUT]
    last_teleop = max(t for t, topic in both["published"] if topic == TELEOP)
    last_nav = max(t for t, topic in nav_only["published"] if topic == NAV)
    problems = []

    def expect(lo: float, hi: float, want: tuple, what: str, at_least: int = 5) -> None:
        window = [(t, v) for t, v in out if lo <= t <= hi]
        if len(window) < at_least:
            problems.append(f"{what}: only {len(window)} messages")
        problems.extend(f"{what}: at +{t - lo:.3f} s got {v}, expected {want}" for t, v in window if v != want)

    expect(both["t1"] - 0.5, both["t1"], TELEOP_CMD, "both sources")
    # teleop silent: never nav's before the timeout; nav's once past it
    expect(both["t1"], last_teleop + TIMEOUT_S, TELEOP_CMD, "teleop within its timeout", at_least=1)
    expect(last_teleop + TIMEOUT_S + MARGIN_S, nav_only["t1"], NAV_CMD, "teleop stale, nav fresh")
    # nav silent too: never zero before its timeout; zero once past it, and it stays so
    expect(nav_only["t1"], last_nav + TIMEOUT_S, NAV_CMD, "nav within its timeout", at_least=1)
    expect(last_nav + TIMEOUT_S + MARGIN_S, silent["t1"], ZERO, "both stale")
    assert not problems, "\n".join(problems[:20])
    assert not (left := settled_leftovers()), left


def _clock(sec: float) -> dict:
    ns = round(sec * 1e9)
    return {"clock.sec": ns // 1000000000, "clock.nanosec": ns % 1000000000}


def test_velocity_guard_ros2_timeouts_follow_clock_under_use_sim_time(guard2, ros2_install, tmp_path, shm_guard):
    """``--ros-args -p use_sim_time:=true``: the ROS clock is /clock's, so a
    message's age is simulated time: the clock standing still for 1.5 s of
    wall time (three timeouts) keeps teleop's command fresh; teleop becomes
    stale only when /clock passes 500 ms after its receipt, nav likewise."""
    clock = "/clock"
    steps = [{"stream": {clock: _clock(100.0)}, "period": 0.05, "duration": 0.3},
             {"publish": {TELEOP: cmd(*TELEOP_CMD)}},
             {"stream": {clock: _clock(100.0)}, "period": 0.05, "duration": 1.5},
             {"stream": {clock: _clock(100.3)}, "period": 0.05, "duration": 0.3},
             {"publish": {NAV: cmd(*NAV_CMD)}},
             {"stream": {clock: _clock(100.45)}, "period": 0.05, "duration": 0.6},
             {"stream": {clock: _clock(100.6)}, "period": 0.05, "duration": 0.6},
             {"stream": {clock: _clock(100.9)}, "period": 0.05, "duration": 0.6}]
    node = spawn([guard2, "--ros-args", "-p", "use_sim_time:=true"], tmp_path / "node.log")
    try:
        result = run_peer({"publishers": {clock: "rosgraph_msgs/Clock", TELEOP: TWIST, NAV: TWIST},
                           "subscribers": {OUT: TWIST}, "match_timeout": 20.0, "steps": steps},
                          tmp_path, ros2_install)
    finally:
        status = stop(node, signal.SIGTERM)
    assert status == 0, (tmp_path / "node.log").read_text(errors="replace")[-2000:]
    out = [(t, value(lv)) for t, topic, lv in result["received"] if topic == OUT]
    problems = []
    for k, want, what in ((2, TELEOP_CMD, "clock still at 100.0 s for 1.5 s of wall time"),
                          (5, TELEOP_CMD, "clock at 100.45 s: teleop 450 ms old"),
                          (6, NAV_CMD, "clock at 100.6 s: teleop 600 ms old, nav 300 ms"),
                          (7, ZERO, "clock at 100.9 s: nav 600 ms old")):
        s = result["steps"][k]
        window = [v for t, v in out if s["t0"] + 0.2 <= t <= s["t1"]]
        if len(window) < 5:
            problems.append(f"{what}: only {len(window)} messages")
        problems += [f"{what}: got {v}, expected {want}" for v in window if v != want]
    assert not problems, "\n".join(problems[:20])
    assert not (left := settled_leftovers()), left

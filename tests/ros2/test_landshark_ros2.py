"""LandShark on ROS 2, end to end on a real DDS (Fast DDS from the wheels,
loopback only): the node built by ``pyrosgen build --ros2`` (the proved
glue, the rcl wrapper, the bit-exact test controller of tests/ros) is driven
by an rclpy peer, which waits for the discovery match, publishes the three
wheel velocities and checks, bit for bit, that the published base velocity
is what the controller computes from the newest messages; then the node is
stopped by a signal and leaves no process and no shared-memory segment."""

from __future__ import annotations

import random
import signal
import time

import pytest

from pyrosgen.ros2.build import build_ros2
from pyrosgen.ros2.frontend import load_model_ros2

from support import expect
from support import ros as rosutil

from .conftest import fastdds_segments, in_use, run_peer, segments_of, settled_leftovers, spawn, stop, wait_for

LEFT, RIGHT, GPS = "/landshark/left_wheel_velocity", "/landshark/right_wheel_velocity", "/landshark/gps_velocity"
BASE = "/landshark_control/base_velocity"
TS = "geometry_msgs/TwistStamped"


@pytest.fixture(scope="module")
def landshark2(ros2_install, ros2_nodes):
    """The LandShark model built for ROS 2 with the bit-exact echo controller."""
    out = ros2_nodes / "landshark_echo"
    res = build_ros2(rosutil.LANDSHARK, rosutil.CONTROLLERS / "landshark_echo", out, install=ros2_install)
    return res


def test_build_installs_node_target_and_certificate(landshark2):
    out = landshark2.out_dir
    node = landshark2.model.name
    assert (out / f"{node}.target").read_text().startswith("target: ros2")
    cert = (out / f"{node}.certificate.md").read_text()
    assert f"{node}.target" in cert and f"{node}_rcl.c" in cert and f"bin/{node}" in cert
    assert landshark2.generated.assumptions == "Closed under the global context"
    # the ROS 2 structs were proved: Header has no seq, Time is int32 sec + uint32 nanosec
    types_h = (out / f"{node}_types.h").read_text()
    assert "struct builtin_interfaces_Time {\n    int sec;\n    unsigned int nanosec;\n};" in types_h
    assert "seq" not in types_h
    # DT_RPATH (not RUNPATH) to the wheels' libraries
    import subprocess
    dyn = subprocess.run(["readelf", "-d", str(landshark2.binary)], capture_output=True, text=True).stdout
    assert "(RPATH)" in dyn and "(RUNPATH)" not in dyn and "ros_rcl.libs" in dyn


def _bits_rounds(rng):
    modes = ["special", "random", "min", "max", "random", "zero"]
    model = load_model_ros2(rosutil.LANDSHARK)
    return model, [{t: rosutil.random_value("float64", rng, m) for t in (LEFT, RIGHT, GPS)} for m in modes]


def test_landshark_ros2_end_to_end_bit_exact(landshark2, ros2_install, tmp_path, shm_guard):
    rng = random.Random(20261128)
    _model, rounds = _bits_rounds(rng)
    node = spawn([landshark2.binary], tmp_path / "node.log")
    try:
        steps = [{"sleep": 0.6}]
        for r in rounds:
            steps.append({"publish": {t: {"twist.linear.x": rosutil.bits_of(v)} for t, v in r.items()}})
            steps.append({"sleep": 0.6})
        result = run_peer({"publishers": {t: TS for t in (LEFT, RIGHT, GPS)}, "subscribers": {BASE: TS},
                           "match_timeout": 20.0, "steps": steps}, tmp_path, ros2_install)
    finally:
        status = stop(node, signal.SIGTERM)
    log = (tmp_path / "node.log").read_text(errors="replace")
    assert status == 0, f"the node did not end cleanly on SIGTERM (status {status}):\n{log[-2000:]}"
    received = result["received"]
    problems = []
    # before any input: the controller's answer to all-zero inputs
    zero = expect.landshark_echo({"In1": 0, "In2": 0, "In3": 0})["Out1"]
    first_pub = result["steps"][1]["t0"]
    before = [lv for t, _topic, lv in received if t < first_pub]
    assert len(before) >= 5, f"too few outputs before any input: {len(before)}"
    problems += [f"before any input: {lv}" for lv in before if lv["twist.linear.x"] != zero]
    for i, r in enumerate(rounds):
        bits = {t: rosutil.bits_of(v) for t, v in r.items()}
        want = expect.landshark_echo({"In1": bits[LEFT], "In2": bits[RIGHT], "In3": bits[GPS]})["Out1"]
        wait = result["steps"][2 + 2 * i]
        window = [lv for t, _topic, lv in received if wait["t0"] + 0.3 <= t <= wait["t1"]]
        assert len(window) >= 5, f"round {i}: only {len(window)} messages on {BASE}"
        for lv in window:
            if lv["twist.linear.x"] != want:
                problems.append(f"round {i}: twist.linear.x bits {lv['twist.linear.x']:#x}, expected {want:#x}")
            others = {k: v for k, v in lv.items() if k != "twist.linear.x"}
            if others != {"header.stamp.sec": 0, "header.stamp.nanosec": 0, "header.frame_id": "",
                          "twist.linear.y": 0, "twist.linear.z": 0, "twist.angular.x": 0,
                          "twist.angular.y": 0, "twist.angular.z": 0}:
                problems.append(f"round {i}: a field the model does not write is not zero: {others}")
    assert not problems, "\n".join(problems[:20])
    assert not (left := settled_leftovers()), left


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"])
def test_node_stops_cleanly_on_signal(landshark2, tmp_path, shm_guard, sig):
    node = spawn([landshark2.binary], tmp_path / "node.log")
    # running: its shared-memory transport is up
    assert wait_for(lambda: node.poll() is not None or bool(segments_of(node.pid)), 10.0)
    assert node.poll() is None, (tmp_path / "node.log").read_text(errors="replace")
    time.sleep(0.5)
    mapped = segments_of(node.pid)
    assert any(not n.startswith("sem.") for n in mapped), f"no Fast DDS shared-memory segment mapped: {mapped}"
    status = stop(node, sig)
    log = (tmp_path / "node.log").read_text(errors="replace")
    assert status == 0, f"exit status {status} after {sig!r}:\n{log[-2000:]}"
    assert not rosutil.alive(node.pid)
    # what it mapped is gone, or still used by another live process
    left = (mapped & fastdds_segments()) - in_use()
    assert not left, f"shared memory left behind: {left}"


def test_constant_frame_id_published_over_rcl(ros2_install, ros2_nodes, tmp_path, shm_guard):
    """Rule 4.14 on ROS 2: LandShark with ``frame_id: base_link`` on its
    command; the rcl wrapper converts the glue's bounded string into
    rosidl's string: every command carries exactly 'base_link', and the
    controller's value."""
    text = rosutil.LANDSHARK.read_text()
    old = "{name: /landshark_control/base_velocity, direction: publish,   type: geometry_msgs/TwistStamped, queue_size: 1}"
    assert text.count(old) == 1
    model = tmp_path / "landshark_framed.yaml"
    model.write_text(text.replace(old, old[:-1] + ", frame_id: base_link}"))
    res = build_ros2(model, rosutil.CONTROLLERS / "landshark_echo", ros2_nodes / "landshark_framed",
                     install=ros2_install)
    assert "struct ros_string" in (res.out_dir / "landshark_controller_types.h").read_text()
    node = spawn([res.binary], tmp_path / "node.log")
    v = 0x400921FB54442D18  # pi
    try:
        result = run_peer({"publishers": {t: TS for t in (LEFT, RIGHT, GPS)}, "subscribers": {BASE: TS},
                           "match_timeout": 20.0,
                           "steps": [{"sleep": 0.3}, {"publish": {t: {"twist.linear.x": v} for t in (LEFT, RIGHT, GPS)}},
                                     {"sleep": 0.6}]}, tmp_path, ros2_install)
    finally:
        status = stop(node, signal.SIGTERM)
    assert status == 0
    got = [lv for _t, _topic, lv in result["received"]]
    assert len(got) >= 10 and all(lv["header.frame_id"] == "base_link" for lv in got), got[:3]
    want = expect.landshark_echo({"In1": v, "In2": v, "In3": v})["Out1"]
    late = [lv for t, _topic, lv in result["received"] if t >= result["steps"][2]["t0"] + 0.3]
    assert late and all(lv["twist.linear.x"] == want for lv in late)
    assert not (left := settled_leftovers()), left


def test_a_burst_delivers_the_newest_last(ros2_install, ros2_nodes, tmp_path, shm_guard):
    """Queue size 3 (the reader's KEEP_LAST depth): a burst of 5 messages per
    topic between two cycles; the spin takes the newest 3 and runs the
    callbacks in arrival order, so the controller sees the last value of
    each topic (a wrapper delivering them in another order, or keeping the
    oldest, would leave an older one)."""
    text = rosutil.LANDSHARK.read_text()
    assert text.count("direction: subscribe, type: geometry_msgs/TwistStamped, queue_size: 1}") == 3
    model = tmp_path / "landshark_q3.yaml"
    model.write_text(text.replace("direction: subscribe, type: geometry_msgs/TwistStamped, queue_size: 1}",
                                  "direction: subscribe, type: geometry_msgs/TwistStamped, queue_size: 3}"))
    res = build_ros2(model, rosutil.CONTROLLERS / "landshark_echo", ros2_nodes / "landshark_q3",
                     install=ros2_install)
    assert "options.qos.depth = 3;" in (res.out_dir / "landshark_controller_rcl.c").read_text()
    rng = random.Random(7)
    bursts = [[{t: rosutil.bits_of(rosutil.random_value("float64", rng, "random")) for t in (LEFT, RIGHT, GPS)}
               for _ in range(5)] for _ in range(4)]
    steps = [{"sleep": 0.3}]
    for burst in bursts:
        steps += [{"publish": {t: {"twist.linear.x": b} for t, b in msg.items()}} for msg in burst]
        steps.append({"sleep": 0.5})
    node = spawn([res.binary], tmp_path / "node.log")
    try:
        result = run_peer({"publishers": {t: TS for t in (LEFT, RIGHT, GPS)}, "subscribers": {BASE: TS},
                           "match_timeout": 20.0, "steps": steps}, tmp_path, ros2_install)
    finally:
        status = stop(node, signal.SIGTERM)
    assert status == 0
    for i, burst in enumerate(bursts):
        last = burst[-1]
        want = expect.landshark_echo({"In1": last[LEFT], "In2": last[RIGHT], "In3": last[GPS]})["Out1"]
        wait = result["steps"][6 * (i + 1)]
        window = [lv["twist.linear.x"] for t, _topic, lv in result["received"] if wait["t0"] + 0.2 <= t <= wait["t1"]]
        assert len(window) >= 5 and all(b == want for b in window), (i, [hex(b) for b in window[:3]], hex(want))
    assert not (left := settled_leftovers()), left


def test_best_effort_publisher_does_not_reach_the_node(landshark2, ros2_install, tmp_path, shm_guard):
    """QoS (not yet a model key): the node's subscriptions are reliable, as
    rclcpp's default; a best-effort publisher (a sensor driver with
    SensorDataQoS) does not match them (DDS's request/offered rule), so
    nothing reaches the node: within 10 s the publishers see no
    subscription, and the node keeps answering all-zero inputs while they
    publish."""
    node = spawn([landshark2.binary], tmp_path / "node.log")
    try:
        result = run_peer({"publishers": {t: TS for t in (LEFT, RIGHT, GPS)}, "subscribers": {BASE: TS},
                           "best_effort": [LEFT, RIGHT, GPS], "match_timeout": 10.0, "run_anyway": True,
                           "steps": [{"stream": {t: {"twist.linear.x": 0x4000000000000000} for t in (LEFT, RIGHT, GPS)},
                                      "period": 0.02, "duration": 1.0}]}, tmp_path, ros2_install)
    finally:
        status = stop(node, signal.SIGTERM)
    assert status == 0
    assert result["matched_after"] is None
    zero = expect.landshark_echo({"In1": 0, "In2": 0, "In3": 0})["Out1"]
    during = [lv["twist.linear.x"] for t, _topic, lv in result["received"]
              if result["steps"][0]["t0"] <= t <= result["steps"][0]["t1"]]
    assert len(during) >= 20 and all(b == zero for b in during)
    assert not (left := settled_leftovers()), left


def test_node_restarted_under_a_running_peer(landshark2, ros2_install, tmp_path, shm_guard):
    """The node stopped (SIGTERM) and started again while the peer keeps
    publishing: DDS discovers the new node by itself (no master), and it
    answers the peer's messages again (each input from the moment its topic
    is matched); no segment of either node left."""
    from .conftest import start_peer
    v = 0x3FF8000000000000  # 1.5
    want = expect.landshark_echo({"In1": v, "In2": v, "In3": v})["Out1"]
    first = spawn([landshark2.binary], tmp_path / "node1.log")
    plan = {"publishers": {t: TS for t in (LEFT, RIGHT, GPS)}, "subscribers": {BASE: TS}, "match_timeout": 20.0,
            "steps": [{"stream": {t: {"twist.linear.x": v} for t in (LEFT, RIGHT, GPS)}, "period": 0.05,
                       "duration": 9.0}]}
    peer = start_peer(plan, tmp_path, ros2_install)
    second = None
    try:
        assert wait_for(lambda: (tmp_path / "peer.log").exists() and first.poll() is None, 5.0)
        import time
        time.sleep(4.0)   # matched (0.2 to 3 s) and answering
        assert stop(first, signal.SIGTERM) == 0
        t_stopped = time.monotonic()
        time.sleep(0.5)
        second = spawn([landshark2.binary], tmp_path / "node2.log")
        result = run_peer(plan, tmp_path, ros2_install, started=peer)
    finally:
        stop(first, signal.SIGTERM)
        status2 = stop(second, signal.SIGTERM) if second is not None else None
        stop(peer, signal.SIGTERM)
    assert status2 == 0
    received = [(t, lv["twist.linear.x"]) for t, _topic, lv in result["received"]]
    before = [b for t, b in received if t < t_stopped]
    after = [b for t, b in received if t > t_stopped + 0.5]
    assert before and before[-1] == want, "the first node did not answer"
    assert after and after[-1] == want, "the restarted node did not answer the running peer"
    # DDS matches the restarted node's three readers with the peer's writers
    # one by one: until all three have delivered, the controller sees some
    # inputs at 1.5 and the others still at 0 (their "no message yet"), and
    # once all three have, 1.5 on each for good
    partial = {expect.landshark_echo({"In1": a, "In2": b, "In3": c})["Out1"]
               for a in (0, v) for b in (0, v) for c in (0, v)}
    assert set(after) <= partial, sorted(set(after) - partial)
    first_full = after.index(want)
    assert all(b == want for b in after[first_full:]), "an input went back to 0 once received"
    assert not (left := settled_leftovers()), left

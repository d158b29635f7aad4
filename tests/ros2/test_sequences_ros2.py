"""Sequences and strings on ROS 2, both policies of rule 4.15, on a real DDS
(Fast DDS from the wheels, loopback only): tests/ros2/models/seq_policies.yaml
built with ``--ros2`` and its echo controller (each output an input,
unchanged), driven by an rclpy peer.  Each round publishes a LaserScan of
policy truncate (ranges of lengths 0, 1, N-1, N, N+1 and 2N for N = 4,
frame_ids of 0 to 16 bytes for N = 8), a Float64MultiArray and a String of
policy reject (the same lengths) and the length of the published sequence
(0 to 2N and 2^32 - 1).  What the node publishes is checked field by
field, bit for bit, against what the model says the glue receives
(:func:`expected`: ``Environment.clamp``, ``len = min(size, N)``,
``truncated = size > N``, the first ``len`` elements, zeros past them;
under reject a too long message is not delivered and the previous one
stays) and sends (the first ``min(len, N)`` elements).  The same cases go
through the wrapper's conversions without a middleware in
tests/ros2/test_rcl_conversions_ros2.py."""

from __future__ import annotations

import signal
import struct

import pytest

from pyrosgen.ros2.build import build_ros2

from support import ros as rosutil

from .conftest import run_peer, settled_leftovers, spawn, stop

MODEL = rosutil.ROOT / "tests" / "ros2" / "models" / "seq_policies.yaml"
CONTROLLER = rosutil.ROOT / "tests" / "ros2" / "controllers" / "seq_policies"
N, F = 4, 8   # the maxima of ranges and data (4), of frame_id and the string (8)
TRUNC, REJ, REJ_STR, PUBLEN = "/trunc", "/rej", "/rej_str", "/publen"
SETTLE, HOLD = 0.3, 0.7

#: per round: (ranges length, frame_id length, /rej length, /rej_str length, published length)
CASES = [
    (N, F, N, F, N),
    (N + 1, F + 1, N + 1, F + 1, N + 1),        # /rej and /rej_str rejected: round 0's stay
    (0, 0, 0, 0, 0),
    (2 * N, 2 * F, 2 * N, 2 * F, 2 * N),        # rejected: round 2's (empty) stay
    (1, 1, 1, 1, 1),
    (N - 1, F - 1, N - 1, F - 1, N - 1),
    (N, 2, 2 * N, F + 1, 0xFFFFFFFF),            # rejected: round 5's stay
]


def f32(x: float) -> int:
    """The float32 bits of ``x``."""
    return struct.unpack("<I", struct.pack("<f", x))[0]


def f64(x: float) -> int:
    return struct.unpack("<Q", struct.pack("<d", x))[0]


def f32_as_f64(b: int) -> int:
    """A float32 (bits) as the peer reports it: the double of its value."""
    return f64(struct.unpack("<f", struct.pack("<I", b))[0])


def message(k: int) -> dict:
    """Round ``k``'s messages: every element distinct from every other
    round's (exact in float32), bytes printable."""
    lr, lf, lj, ls, pl = CASES[k]
    return {
        TRUNC: {"ranges": [10.0 * (k + 1) + i + 0.25 for i in range(lr)],
                "header.frame_id": "".join(chr(97 + (k + i) % 26) for i in range(lf))},
        REJ: {"data": [-(k + 1) - 0.5 * i for i in range(lj)]},
        REJ_STR: {"data": "".join(chr(65 + (k + 3 * i) % 26) for i in range(ls))},
        PUBLEN: {"data": pl},
    }


def controller_inputs(k: int | None) -> dict:
    """Echo_U after round ``k`` (``None``: before any message), as the
    environment model delivers the messages: truncate clamps, reject keeps
    the newest accepted message (float32 and float64 as their bits)."""
    u = {f"R{i}": 0 for i in range(4)} | {"RN": 0, "RT": 0} | {f"B{i}": 0 for i in range(8)} | {"BN": 0, "BT": 0}
    u |= {f"J{i}": 0 for i in range(4)} | {"JN": 0, "S0": 0, "S7": 0, "SN": 0, "PL": 0}
    if k is None:
        return u
    m = message(k)
    ranges, frame = m[TRUNC]["ranges"], m[TRUNC]["header.frame_id"].encode()
    for i in range(min(len(ranges), N)):
        u[f"R{i}"] = f32(ranges[i])
    u["RN"], u["RT"] = min(len(ranges), N), int(len(ranges) > N)
    for i in range(min(len(frame), F)):
        u[f"B{i}"] = frame[i]
    u["BN"], u["BT"] = min(len(frame), F), int(len(frame) > F)
    u["PL"] = m[PUBLEN]["data"]
    accepted = [j for j in range(k + 1) if len(message(j)[REJ]["data"]) <= N]
    if accepted:
        data = message(accepted[-1])[REJ]["data"]
        u |= {f"J{i}": f64(data[i]) for i in range(len(data))} | {"JN": len(data)}
    accepted = [j for j in range(k + 1) if len(message(j)[REJ_STR]["data"]) <= F]
    if accepted:
        s = message(accepted[-1])[REJ_STR]["data"].encode()
        u |= {"S0": s[0] if len(s) > 0 else 0, "S7": s[7] if len(s) > 7 else 0, "SN": len(s)}
    return u


def expected(u: dict) -> dict:
    """What the node publishes for the inputs ``u`` (the echo controller:
    each output its input), as the peer reports it: the published sequence
    and string are the first min(len, N) elements (Environment.clamp on
    publish); floats as the bits of their double value."""
    frame = bytes(u[f"B{i}"] for i in range(min(u["BN"], F))).decode()
    return {
        "/echo/ranges": {"layout.dim": [], "layout.data_offset": 0,
                         "data": [f32_as_f64(u[f"R{i}"]) for i in range(min(u["PL"], N))]},
        "/echo/frame": {"stamp.sec": 0, "stamp.nanosec": 0, "frame_id": frame},
        "/echo/flags": {"x_offset": u["RN"], "y_offset": 0, "height": u["JN"], "width": u["SN"],
                        "do_rectify": bool(u["RT"])},
        "/echo/rej": {"x": u["J0"], "y": u["J1"], "z": u["J2"], "w": u["J3"]},
        "/echo/str": {"type": u["S0"], "id": u["S7"], "intensity": 0},
        "/echo/frame_truncated": {"data": bool(u["BT"])},
    }


ECHOES = {"/echo/ranges": "std_msgs/Float32MultiArray", "/echo/frame": "std_msgs/Header",
          "/echo/flags": "sensor_msgs/RegionOfInterest", "/echo/rej": "geometry_msgs/Quaternion",
          "/echo/str": "sensor_msgs/JoyFeedback", "/echo/frame_truncated": "std_msgs/Bool"}


@pytest.fixture(scope="module")
def seq2(ros2_install, ros2_nodes):
    res = build_ros2(MODEL, CONTROLLER, ros2_nodes / "seq_policies", install=ros2_install)
    text = (res.out_dir / "seq_policies_rcl.c").read_text()
    # policy reject tested on the rosidl message, truncate converted by to_c
    assert "if (!accept_rej(&g_take_rej)) continue;" in text and "if (!accept_rej_str(&g_take_rej_str)) continue;" in text
    assert "r->data.size > 4) return 0;" in text and "r->data.size > 8) return 0;" in text
    assert "static inline void to_c_ros_seq_float32_4(" in text and "static inline void to_c_ros_string8(" in text
    return res


def _peer_values(k: int) -> dict:
    m = message(k)
    return {TRUNC: {"ranges": [f64(x) for x in m[TRUNC]["ranges"]], "header.frame_id": m[TRUNC]["header.frame_id"],
                    "angle_max": f64(1.5), "range_max": f64(30.0)},
            REJ: {"data": [f64(x) for x in m[REJ]["data"]]}, REJ_STR: m[REJ_STR], PUBLEN: m[PUBLEN]}


def test_sequences_both_policies_over_rcl(seq2, ros2_install, tmp_path, shm_guard):
    steps = [{"sleep": 0.5}]
    for k in range(len(CASES)):
        steps += [{"publish": _peer_values(k)}, {"sleep": HOLD}]
    node = spawn([seq2.binary], tmp_path / "node.log")
    try:
        result = run_peer({"publishers": {TRUNC: "sensor_msgs/LaserScan", REJ: "std_msgs/Float64MultiArray",
                                          REJ_STR: "std_msgs/String", PUBLEN: "std_msgs/UInt32"},
                           "subscribers": ECHOES, "match_timeout": 20.0, "steps": steps}, tmp_path, ros2_install)
    finally:
        status = stop(node, signal.SIGTERM)
    assert status == 0, (tmp_path / "node.log").read_text(errors="replace")[-2000:]
    rsteps, received = result["steps"], result["received"]
    problems = []
    before = expected(controller_inputs(None))
    for topic in ECHOES:
        got = [lv for t, tp, lv in received if tp == topic and t < rsteps[1]["t0"]]
        assert len(got) >= 5, (topic, len(got))
        problems += [f"before any input, {topic}: {g} != {before[topic]}" for g in got if g != before[topic]][:2]
    for k in range(len(CASES)):
        want = expected(controller_inputs(k))
        t0, t1 = rsteps[1 + 2 * k]["t1"] + SETTLE, rsteps[2 + 2 * k]["t1"]
        for topic in ECHOES:
            got = [lv for t, tp, lv in received if tp == topic and t0 <= t <= t1]
            assert len(got) >= 10, (k, topic, len(got))
            problems += [f"round {k} {CASES[k]}, {topic}: {g} != {want[topic]}" for g in got if g != want[topic]][:2]
    assert not problems, "\n".join(problems[:20])
    assert not (left := settled_leftovers()), left

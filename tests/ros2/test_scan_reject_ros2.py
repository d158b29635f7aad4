"""Policy reject on ROS 2 (rule 4.15, ``policy: {ranges: reject,
header.frame_id: reject}``; tests/ros/models/scan_reject.yaml): the rcl
wrapper takes each scan and does not deliver one holding more than N = 4
ranges or more than 8 bytes of frame_id (``Environment.accepted``), so the
echo stays on the previous accepted scan; every other is delivered as the
clamp gives it.  Same cases and reference as tests/ros/test_scan_reject_node.py."""

from __future__ import annotations

import signal
import struct

import pytest

from pyrosgen.ros2.build import build_ros2

from .conftest import run_peer, settled_leftovers, spawn, stop
from ros.test_scan_reject_node import CASES, F, MODEL, N, SCAN, _element

SETTLE, HOLD = 0.3, 0.8


def bits(x: float) -> int:
    return struct.unpack("<Q", struct.pack("<d", x))[0]


@pytest.fixture(scope="module")
def reject2(ros2_install, ros2_nodes):
    res = build_ros2(MODEL, None, ros2_nodes / "scan_reject", install=ros2_install)
    text = (res.out_dir / "scan_reject_rcl.c").read_text()
    assert "r->ranges.size > 4) return 0;" in text and "r->header.frame_id.size > 8) return 0;" in text
    return res.binary


def test_over_long_scans_are_not_delivered_over_rcl(reject2, ros2_install, tmp_path, shm_guard):
    steps = [{"sleep": 0.5}]
    for k, (length, frame) in enumerate(CASES):
        steps += [{"publish": {SCAN: {"ranges": [bits(_element(k, i)) for i in range(length)],
                                      "header.frame_id": "f" * frame}}},
                  {"sleep": HOLD}]
    node = spawn([reject2], tmp_path / "node.log")
    try:
        result = run_peer({"publishers": {SCAN: "sensor_msgs/LaserScan"},
                           "subscribers": {"/echo/ranges": "geometry_msgs/Point32",
                                           "/echo/lengths": "sensor_msgs/RegionOfInterest"},
                           "match_timeout": 20.0, "steps": steps}, tmp_path, ros2_install)
    finally:
        status = stop(node, signal.SIGTERM)
    assert status == 0, (tmp_path / "node.log").read_text(errors="replace")[-2000:]
    rsteps = result["steps"]
    last = None
    for k, (length, frame) in enumerate(CASES):
        if length <= N and frame <= F:
            last = k
        assert last is not None
        alen, aframe = CASES[last]

        def elem(i: int) -> int:
            return bits(_element(last, i)) if i < alen else 0

        want = {"/echo/ranges": {"x": elem(0), "y": elem(3), "z": 0},
                "/echo/lengths": {"x_offset": 0, "y_offset": 0, "width": alen, "height": aframe,
                                  "do_rectify": False}}
        t0, t1 = rsteps[1 + 2 * k]["t1"] + SETTLE, rsteps[2 + 2 * k]["t1"]
        for topic, leaves in want.items():
            got = [lv for t, tp, lv in result["received"] if tp == topic and t0 <= t <= t1]
            assert len(got) >= 10, (k, topic, len(got))
            assert all(g == leaves for g in got), (k, length, frame, topic, got[-1], leaves)
    assert not (left := settled_leftovers()), left

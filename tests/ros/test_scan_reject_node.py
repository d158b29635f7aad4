"""Policy reject on a real master (rule 4.15, ``policy: {ranges: reject}``).

tests/ros/models/scan_reject.yaml carries at most N = 4 ranges and 8
bytes of ``header.frame_id`` of ``/scan`` (``sensor_msgs/LaserScan``),
both of policy reject, and echoes ranges[0], ranges[3] and both lengths
to ordinary published fields.  A rospy driver publishes scans with
ranges of lengths 0, 1, N-1, N, N+1 and 2N and frame_ids of 0 to 16
bytes; each scan's ranges differ from every other's.  A scan holding
more than N ranges or more than 8 bytes of frame_id is not delivered
(``Environment.accepted``: the callback is not called), so the echo
stays on the previous scan's values; every other is delivered as the
clamp gives it (its length, its elements, zero past them).
"""

from __future__ import annotations

import pytest

from pyrosgen.ros.build import build

from support import ros as rosutil
from support.ros import fbits, run_driver, start_node

pytestmark = pytest.mark.ros

MODEL = rosutil.ROOT / "tests" / "ros" / "models" / "scan_reject.yaml"
N, F = 4, 8
SCAN = "/scan"
SETTLE, HOLD = 0.3, 0.8

#: (ranges length, frame_id length): accepted unless a length exceeds its
#: maximum; every rejected scan follows an accepted one it must not replace
CASES = [
    (N, 2),          # accepted
    (N + 1, 2),      # rejected: the ranges
    (0, 0),          # accepted
    (2 * N, 1),      # rejected: the ranges
    (1, F),          # accepted (frame_id of exactly its maximum)
    (N - 1, F + 1),  # rejected: the frame_id
    (N - 1, 7),      # accepted
    (N, 2 * F),      # rejected: the frame_id
    (N, F),          # accepted
]


@pytest.fixture(scope="module")
def node_bin(nodes_dir):
    out = nodes_dir / "scan_reject"
    res = build(MODEL, None, out)
    binary = out / "bin" / "scan_reject"
    assert binary.is_file()
    assert "message ros_rseq_float32_4" in res.generated.proved_model.splitlines()
    assert "message ros_rstring8" in res.generated.proved_model.splitlines()
    return binary


def _element(k: int, i: int) -> float:
    """The i-th range of the k-th scan: distinct, exact in float32."""
    return 10.0 * (k + 1) + i + 0.25


def test_over_long_scans_are_not_delivered(ros, node_bin, tmp_path):
    node = start_node(ros, node_bin, tmp_path / "node.log")
    steps = []
    for k, (length, frame) in enumerate(CASES):
        steps += [{"publish": {"topic": SCAN, "values": {"ranges": [_element(k, i) for i in range(length)],
                                                         "header.frame_id": "f" * frame}}},
                  {"sleep": HOLD}]
    plan = {"publishers": [{"topic": SCAN, "type": "sensor_msgs/LaserScan", "queue_size": 10}],
            "subscribers": [{"topic": "/echo/ranges", "type": "geometry_msgs/Point32"},
                            {"topic": "/echo/lengths", "type": "sensor_msgs/RegionOfInterest"}],
            "wait_messages": True, "steps": steps, "linger": 0.2}
    result = run_driver(ros, plan, tmp_path)
    assert node.poll() is None, (tmp_path / "node.log").read_text()[-2000:]
    rsteps = result["steps"]
    assert len(rsteps) == len(steps)
    last = None
    for k, (length, frame) in enumerate(CASES):
        if length <= N and frame <= F:
            last = k
        assert last is not None
        alen, aframe = CASES[last]

        def elem(i: int) -> str:
            return f"f:{fbits(_element(last, i)) if i < alen else 0:08x}"

        want = {
            "/echo/ranges": {"x": elem(0), "y": elem(3), "z": "f:00000000"},
            "/echo/lengths": {"x_offset": 0, "y_offset": 0, "width": alen, "height": aframe, "do_rectify": 0},
        }
        t0, t1 = rsteps[2 * k]["t1"] + SETTLE, rsteps[2 * k + 1]["t1"]
        for topic, leaves in want.items():
            got = [r["leaves"] for r in rosutil.received(result, topic, t0, t1)]
            assert len(got) >= 10, (k, topic, len(got))
            assert all(g == leaves for g in got), (k, length, frame, topic, got[-1], leaves)

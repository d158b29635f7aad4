"""Controller arrays on a real master (rule 4.15).

tests/ros/models/scan_array.yaml, built with its Embedded Coder-style
controller (tests/ros/controllers/scan_array: vector inports and outports
as array members, ``real32_T Scan[8];``), relates a LaserScan's
``ranges`` (at most N = 8) whole to ``Scan[8]`` and ``ranges[7]``,
``ranges[6]`` to ``Last[0]``, ``Last[1]``; the controller echoes ``Scan``
whole into a published ``Float32MultiArray`` (``/echo``, at most 8, its
length the received one) and publishes the minimum of the received
ranges and ``Last`` element by element on a ``Point32`` (``/pt``).  A
rospy driver sends scans of lengths 0, 1, N-1, N, N+1 and 2N: every
``/echo`` on the wire holds exactly the first min(length, N) ranges, bit
for bit, and ``/pt`` the minimum of those (-1 for none) and ranges 7 and
6 when the scan holds them, else 0 -- what T2 says the controller
receives (``Environment.clamp``: zeros past the received length)."""

from __future__ import annotations

import pytest

from pyrosgen.ros.build import build

from support import ros as rosutil
from support.ros import f, fbits, run_driver, start_node

pytestmark = pytest.mark.ros

MODEL = rosutil.ROOT / "tests" / "ros" / "models" / "scan_array.yaml"
CONTROLLER = rosutil.CONTROLLERS / "scan_array"
N = 8
LENGTHS = (0, 1, N - 1, N, N + 1, 2 * N)
#: how long after a scan is published its messages are checked, and how
#: long each scan is the newest
SETTLE, HOLD = 0.3, 0.8


@pytest.fixture(scope="module")
def arrays(nodes_dir):
    out = nodes_dir / "scan_array"
    res = build(MODEL, CONTROLLER, out)
    binary = out / "bin" / "scan_array"
    assert binary.is_file()
    proved = res.generated.proved_model.splitlines()
    assert "input Scan array 8 float32" in proved and "input_relation scan ranges.data[7] Scan[7]" in proved
    assert "output_relation Echo[7] echo data.data[7]" in proved and "output_relation Pt[0] pt x" in proved
    return binary


def _range(case: int, i: int) -> float:
    """Range i of a case: distinct, exact in float32, the smallest not
    always first."""
    return 1.0 + case + ((i * 5) % 11) * 0.25


def test_whole_arrays_on_the_wire(ros, arrays, tmp_path):
    node = start_node(ros, arrays, tmp_path / "node.log")
    steps = []
    for c, length in enumerate(LENGTHS):
        steps += [{"publish": {"topic": "/scan", "values": {"ranges": [_range(c, i) for i in range(length)],
                                                               "header.frame_id": "laser"}}},
                  {"sleep": HOLD}]
    plan = {"publishers": [{"topic": "/scan", "type": "sensor_msgs/LaserScan", "queue_size": 10}],
            "subscribers": [{"topic": "/echo", "type": "std_msgs/Float32MultiArray", "record": "elements"},
                            {"topic": "/pt", "type": "geometry_msgs/Point32"}],
            "wait_messages": True, "steps": steps, "linger": 0.2}
    result = run_driver(ros, plan, tmp_path)
    assert node.poll() is None, (tmp_path / "node.log").read_text()[-2000:]
    assert len(result["steps"]) == len(steps)
    # before the first scan: nothing received, the length is 0 and Pt is -1, 0, 0
    assert rosutil.received(result, "/echo")[0]["leaves"] == {"layout.dim": {"var": 0}, "layout.data_offset": 0,
                                                              "data": {"var": 0}}
    assert rosutil.received(result, "/pt")[0]["leaves"] == {"x": f(fbits(-1.0)), "y": f(0), "z": f(0)}
    for c, length in enumerate(LENGTHS):
        t0, t1 = result["steps"][2 * c]["t1"] + SETTLE, result["steps"][2 * c + 1]["t1"]
        k = min(length, N)
        ranges = [_range(c, i) for i in range(k)]
        want = {"layout.dim": {"var": 0}, "layout.data_offset": 0, "data": {"var": k},
                **{f"data[{i}]": f(fbits(r)) for i, r in enumerate(ranges)}}
        got = [r["leaves"] for r in rosutil.received(result, "/echo", t0, t1)]
        assert len(got) >= 10, (length, len(got))
        assert all(g == want for g in got), (length, got[-1], want)
        held = ranges + [0.0] * (N - k)     # what the controller receives: zeros past the length
        want = {"x": f(fbits(min(ranges) if ranges else -1.0)), "y": f(fbits(held[7])), "z": f(fbits(held[6]))}
        got = [r["leaves"] for r in rosutil.received(result, "/pt", t0, t1)]
        assert len(got) >= 10, (length, len(got))
        assert all(g == want for g in got), (length, got[-1], want)

"""Published variable-length arrays and strings on a real master (rule
4.15, publish side).

tests/ros/models/seq_echo.yaml, built with its test controller
(tests/ros/controllers/seq_echo: no arithmetic), subscribes to a length
(``/len``, ``std_msgs/UInt32``) and four values (``/vals``,
``geometry_msgs/Quaternion``) and publishes a ``std_msgs/Float64MultiArray``
(``/out``, ``data`` carried as at most N = 4 float64) whose length is the
received one and whose elements are the four values, and a
``PointStamped`` (``/tagged``) whose frame_id is "ab" written byte by byte
with the same length.  A rospy driver sends lengths 0, 1, N-1, N, N+1, 2N
(and 129 and 2^32-1): every message on the wire has exactly min(L, N)
elements, the values bit for bit, and a frame_id of min(L, 128) bytes
("a", "b", then NULs) -- what the wrapper sends and what the environment
model says of publications (``Environment.clamp``: the first min(len, N)
elements)."""

from __future__ import annotations

import pytest

from pyrosgen.ros.build import build

from support import ros as rosutil
from support.ros import d, dbits, run_driver, start_node

pytestmark = pytest.mark.ros

MODEL = rosutil.ROOT / "tests" / "ros" / "models" / "seq_echo.yaml"
CONTROLLER = rosutil.CONTROLLERS / "seq_echo"
N = 4
LENGTHS = (0, 1, N - 1, N, N + 1, 2 * N, 129, 2 ** 32 - 1)
#: how long after a case is published its messages are checked, and how
#: long each case holds
SETTLE, HOLD = 0.3, 0.8


@pytest.fixture(scope="module")
def echo(nodes_dir):
    out = nodes_dir / "seq_echo"
    res = build(MODEL, CONTROLLER, out)
    binary = out / "bin" / "seq_echo"
    assert binary.is_file()
    proved = res.generated.proved_model.splitlines()
    assert "output_relation NS out data.len" in proved and "output_relation E3 out data.data[3]" in proved
    return binary


def _value(case: int, i: int) -> float:
    """Element i of a case: distinct, exact in float64."""
    return case * 8 + i + 0.25


def test_published_lengths_on_the_wire(ros, echo, tmp_path):
    node = start_node(ros, echo, tmp_path / "node.log")
    steps = []
    for c, length in enumerate(LENGTHS):
        vals = {k: d(dbits(_value(c, i))) for i, k in enumerate("xyzw")}
        steps += [{"publish": {"topic": "/vals", "values": vals}},
                  {"publish": {"topic": "/len", "values": {"data": length}}},
                  {"sleep": HOLD}]
    plan = {"publishers": [{"topic": "/len", "type": "std_msgs/UInt32", "queue_size": 10},
                           {"topic": "/vals", "type": "geometry_msgs/Quaternion", "queue_size": 10}],
            "subscribers": [{"topic": "/out", "type": "std_msgs/Float64MultiArray", "record": "elements"},
                            {"topic": "/tagged", "type": "geometry_msgs/PointStamped"}],
            "wait_messages": True, "steps": steps, "linger": 0.2}
    result = run_driver(ros, plan, tmp_path)
    assert node.poll() is None, (tmp_path / "node.log").read_text()[-2000:]
    assert len(result["steps"]) == len(steps)
    # before the first case: nothing received yet, so the length is 0
    first = rosutil.received(result, "/out")[0]["leaves"]
    assert first == {"layout.dim": {"var": 0}, "layout.data_offset": 0, "data": {"var": 0}}, first
    for c, length in enumerate(LENGTHS):
        t0, t1 = result["steps"][3 * c + 1]["t1"] + SETTLE, result["steps"][3 * c + 2]["t1"]
        k = min(length, N)
        want = {"layout.dim": {"var": 0}, "layout.data_offset": 0, "data": {"var": k},
                **{f"data[{i}]": d(dbits(_value(c, i))) for i in range(k)}}
        got = [r["leaves"] for r in rosutil.received(result, "/out", t0, t1)]
        assert len(got) >= 10, (length, len(got))
        assert all(g == want for g in got), (length, got[-1], want)
        kf = min(length, 128)
        frame = ("ab" + "\0" * 126)[:kf]
        want = {"header.seq": 0, "header.stamp.sec": 0, "header.stamp.nsec": 0, "header.frame_id": {"str": frame},
                "point.x": d(dbits(_value(c, 0))), "point.y": d(0), "point.z": d(0)}
        got = [r["leaves"] for r in rosutil.received(result, "/tagged", t0, t1)]
        assert len(got) >= 10, (length, len(got))
        assert all(g == want for g in got), (length, got[-1], want)

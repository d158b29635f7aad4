"""Published variable-length arrays of messages and of strings on a real
master (rule 4.15, publish side).

tests/ros/models/elem_seq_pub.yaml, built with its Embedded Coder-style
controller (tests/ros/controllers/elem_seq_pub: no arithmetic), publishes
a ``nav_msgs/Path`` (at most N = 3 poses; its own frame_id the constant
"map") whose length is the received ``L``, whose poses' x are three
received values and whose pose 1 has seq ``L`` and a frame_id of the
received length ``S`` with bytes "ab"; and a ``sensor_msgs/JointState`` of
``L`` names (at most 3 of at most M = 4 bytes): name 0 of length ``S``
with bytes "wxyz", name 2 of length ``S`` with byte "z".  A rospy driver
sends ``L`` = 0, 1, N-1, N, N+1, 2N with ``S`` = 0, 1, M-1, M, M+1, 2M:
every message on the wire holds exactly the first min(L, N) elements, each
string its first min(S, M) bytes, bit for bit -- what the wrapper sends
and what the environment model says of publications
(``Environment.clamp``)."""

from __future__ import annotations

import pytest

from pyrosgen.ros.build import build

from support import ros as rosutil
from support.ros import d, dbits, run_driver, start_node

pytestmark = pytest.mark.ros

MODEL = rosutil.ROOT / "tests" / "ros" / "models" / "elem_seq_pub.yaml"
CONTROLLER = rosutil.CONTROLLERS / "elem_seq_pub"
N, M = 3, 4
CASES = tuple(zip((0, 1, N - 1, N, N + 1, 2 * N), (M + 1, 0, 1, M - 1, M, 2 * M)))
SETTLE, HOLD = 0.3, 0.7


@pytest.fixture(scope="module")
def pub_node(nodes_dir):
    out = nodes_dir / "elem_seq_pub"
    res = build(MODEL, CONTROLLER, out)
    binary = out / "bin" / "elem_seq_pub"
    assert binary.is_file()
    proved = res.generated.proved_model.splitlines()
    assert "output_relation X1 path poses.data[1].pose.position.x" in proved
    assert "output_relation N0[3] joints name.data[0].data[3]" in proved
    return binary


def _values(c: int) -> list[float]:
    return [c * 4 + i + 0.5 for i in range(3)]


def _want(c: int, length: int, slen: int) -> tuple[dict, dict]:
    k, s = min(length, N), min(slen, M)
    zero = d(dbits(0.0))
    path = {"header.seq": 0, "header.stamp.sec": 0, "header.stamp.nsec": 0, "header.frame_id": {"str": "map"},
            "poses": {"var": k}}
    for i in range(k):
        p = f"poses[{i}]"
        path.update({f"{p}.header.seq": length if i == 1 else 0, f"{p}.header.stamp.sec": 0,
                     f"{p}.header.stamp.nsec": 0,
                     f"{p}.header.frame_id": {"str": "ab\0\0"[:s] if i == 1 else ""},
                     f"{p}.pose.position.x": d(dbits(_values(c)[i])), f"{p}.pose.position.y": zero,
                     f"{p}.pose.position.z": zero, **{f"{p}.pose.orientation.{a}": zero for a in "xyzw"}})
    joints = {"header.seq": 0, "header.stamp.sec": 0, "header.stamp.nsec": 0, "header.frame_id": {"str": ""},
              "name": {"var": k}, "position": {"var": 0}, "velocity": {"var": 0}, "effort": {"var": 0}}
    names = ["wxyz"[:s], "", "z\0\0\0"[:s]]
    joints.update({f"name[{i}]": {"str": names[i]} for i in range(k)})
    return path, joints


def test_published_paths_and_joint_states_on_the_wire(ros, pub_node, tmp_path):
    node = start_node(ros, pub_node, tmp_path / "node.log")
    steps = []
    for c, (length, slen) in enumerate(CASES):
        x, y, z = _values(c)
        steps += [{"publish": {"topic": "/vals", "values": {"x": d(dbits(x)), "y": d(dbits(y)), "z": d(dbits(z))}}},
                  {"publish": {"topic": "/slen", "values": {"data": slen}}},
                  {"publish": {"topic": "/len", "values": {"data": length}}},
                  {"sleep": HOLD}]
    plan = {"publishers": [{"topic": t, "type": ty, "queue_size": 10}
                           for t, ty in (("/len", "std_msgs/UInt32"), ("/slen", "std_msgs/UInt32"),
                                         ("/vals", "geometry_msgs/Point"))],
            "subscribers": [{"topic": "/path", "type": "nav_msgs/Path", "record": "deep"},
                            {"topic": "/joints", "type": "sensor_msgs/JointState", "record": "deep"}],
            "wait_messages": True, "steps": steps, "linger": 0.2}
    result = run_driver(ros, plan, tmp_path)
    assert node.poll() is None, (tmp_path / "node.log").read_text()[-2000:]
    assert len(result["steps"]) == len(steps)
    # before any input: empty arrays
    assert rosutil.received(result, "/path")[0]["leaves"]["poses"] == {"var": 0}
    assert rosutil.received(result, "/joints")[0]["leaves"]["name"] == {"var": 0}
    for c, (length, slen) in enumerate(CASES):
        t0, t1 = result["steps"][4 * c + 2]["t1"] + SETTLE, result["steps"][4 * c + 3]["t1"]
        want_path, want_joints = _want(c, length, slen)
        for topic, want in (("/path", want_path), ("/joints", want_joints)):
            got = [r["leaves"] for r in rosutil.received(result, topic, t0, t1)]
            assert len(got) >= 5, (topic, length, len(got))
            assert all(g == want for g in got), (topic, length, slen, got[-1], want)

"""Variable-length arrays of messages and of strings on a real master
(rule 4.15, subscribe side).

tests/ros/models/elem_seq.yaml, built with its Embedded Coder-style
controller (tests/ros/controllers/elem_seq: no arithmetic, exact
conversions to double), reads of a ``nav_msgs/Path`` (``poses`` at most
N = 3, each element's ``header.frame_id`` at most M = 4 bytes) the
length and truncation flag of ``poses``, leaves of poses 0, 1 and 2, the
first byte, length and flag of pose 1's frame_id and pose 2's frame_id
whole (``uint8[4]``); and of a ``sensor_msgs/JointState`` (``name`` at
most 3 strings of at most 4 bytes) the length and flag of ``name``, the
length and flag of ``name[0]``, byte 3 of ``name[2]`` and ``name[1]``
whole.  It publishes all of them back as one ``Float64MultiArray``.  A
rospy driver sends paths of 0, 1, N-1, N, N+1 and 2N poses and joint
states of as many names, with frame_ids and names of 0, 1, M-1, M, M+1
and 2M bytes: every echo on the wire is, bit for bit, what T2 says the
controller receives (``Environment.clamp``: the first min(len, N)
elements, each with its strings capped at M, zeros past the lengths).
The same node with ``policy: {poses: reject}`` keeps the previous path
when one of N+1 or 2N poses arrives (``Environment.too_long``), while the
JointState still arrives."""

from __future__ import annotations

import pytest

from pyrosgen.ros.build import build

from support import ros as rosutil
from support.ros import d, dbits, run_driver, start_node

pytestmark = pytest.mark.ros

MODEL = rosutil.ROOT / "tests" / "ros" / "models" / "elem_seq.yaml"
CONTROLLER = rosutil.CONTROLLERS / "elem_seq"
N, M = 3, 4
LENGTHS = (0, 1, N - 1, N, N + 1, 2 * N)
STR_LENGTHS = (0, 1, M - 1, M, M + 1, 2 * M)
#: how long after a case is published its messages are checked, and how
#: long each case holds
SETTLE, HOLD = 0.3, 0.7


@pytest.fixture(scope="module")
def elem_seq(nodes_dir):
    out = nodes_dir / "elem_seq"
    res = build(MODEL, CONTROLLER, out)
    binary = out / "bin" / "elem_seq"
    assert binary.is_file()
    proved = res.generated.proved_model.splitlines()
    assert "input_relation path poses.data[0].pose.position.x P0X" in proved
    assert "input_relation joints name.data[2].data[3] N2B3" in proved
    return binary


def _text(c: int, i: int, n: int) -> str:
    """A string of ``n`` printable bytes, distinct per case and element."""
    return "".join(chr(ord("a") + (c * 7 + i * 3 + j) % 26) for j in range(n))


def _case(c: int, length: int):
    """The Path and JointState of case ``c`` (``length`` poses and names;
    element ``i``'s frame_id and name of the ``i``-th next string length)
    and the 21 values the controller must publish back."""
    slen = [STR_LENGTHS[(c + i) % len(STR_LENGTHS)] for i in range(length)]
    path = {"poses": {"elems": length}, "header.frame_id": "map"}
    for i in range(length):
        path[f"poses[{i}].header.seq"] = 1000 * c + i
        path[f"poses[{i}].header.frame_id"] = _text(c, i, slen[i])
        path[f"poses[{i}].pose.position.x"] = d(dbits(c + i + 0.5))
        path[f"poses[{i}].pose.orientation.w"] = d(dbits(-(c + i) - 0.25))
    names = [_text(c + 1, i, slen[length - 1 - i]) for i in range(length)]
    joints = {"name": names, "position": [0.5] * length}
    k = min(length, N)
    real = [i < k for i in range(N)]

    def frame(i: int) -> list[int]:
        s = path[f"poses[{i}].header.frame_id"] if real[i] else ""
        b = [ord(ch) for ch in s[:M]]
        return b + [0] * (M - len(b))

    def name(i: int) -> list[int]:
        b = [ord(ch) for ch in (names[i] if real[i] else "")[:M]]
        return b + [0] * (M - len(b))

    out = [k, int(length > N),
           c + 0.5 if real[0] else 0.0,
           -(c + 2) - 0.25 if real[2] else 0.0,
           1000 * c + 1 if real[1] else 0,
           frame(1)[0],
           min(slen[1], M) if real[1] else 0,
           int(real[1] and slen[1] > M),
           *frame(2),
           k, int(length > N),
           min(len(names[0]), M) if real[0] else 0,
           int(real[0] and len(names[0]) > M),
           name(2)[3],
           *name(1)]
    assert len(out) == 21
    return path, joints, out


def _drive(ros, node, steps, tmp_path):
    """Run the driver's ``steps`` (publishing on /path and /joints) with
    /echo recorded; the node must still run and every step be done."""
    plan = {"publishers": [{"topic": "/path", "type": "nav_msgs/Path", "queue_size": 10},
                           {"topic": "/joints", "type": "sensor_msgs/JointState", "queue_size": 10}],
            "subscribers": [{"topic": "/echo", "type": "std_msgs/Float64MultiArray", "record": "elements"}],
            "wait_messages": True, "steps": steps, "linger": 0.2}
    result = run_driver(ros, plan, tmp_path)
    assert node.poll() is None, (tmp_path / "node.log").read_text()[-2000:]
    assert len(result["steps"]) == len(steps)
    return result


def test_paths_and_joint_states_on_the_wire(ros, elem_seq, tmp_path):
    node = start_node(ros, elem_seq, tmp_path / "node.log")
    steps, wants = [], []
    for c, length in enumerate(LENGTHS):
        path, joints, want = _case(c, length)
        steps += [{"publish": {"topic": "/path", "values": path}},
                  {"publish": {"topic": "/joints", "values": joints}},
                  {"sleep": HOLD}]
        wants.append(want)
    result = _drive(ros, node, steps, tmp_path)
    # before the first messages: every input is 0
    first = rosutil.received(result, "/echo")[0]["leaves"]
    assert first["data"] == {"var": 21} and all(first[f"data[{i}]"] == d(dbits(0.0)) for i in range(21)), first
    for c, length in enumerate(LENGTHS):
        t0, t1 = result["steps"][3 * c + 1]["t1"] + SETTLE, result["steps"][3 * c + 2]["t1"]
        want = {"layout.dim": {"var": 0}, "layout.data_offset": 0, "data": {"var": 21},
                **{f"data[{i}]": d(dbits(float(v))) for i, v in enumerate(wants[c])}}
        got = [r["leaves"] for r in rosutil.received(result, "/echo", t0, t1)]
        assert len(got) >= 5, (length, len(got))
        assert all(g == want for g in got), (length, got[-1], want)


# --------------------------------------------------------------------------
# Policy reject on the array of messages


@pytest.fixture(scope="module")
def elem_seq_reject(nodes_dir, tmp_path_factory):
    """The same node with ``policy: {poses: reject}`` (``poses`` carried as
    ``ros_rseq_geometry_msgs_PoseStamped_3``); ``TP`` then reads whether
    pose 0's frame_id was truncated (the array's own flag would always be
    0, and is refused)."""
    text = MODEL.read_text()
    swaps = [('max_length: {poses: 3, "poses[].header.frame_id": 4}}',
              'max_length: {poses: 3, "poses[].header.frame_id": 4}, policy: {poses: reject}}'),
             ("{topic: /path, field: poses, derived: truncated, input: TP}",
              '{topic: /path, field: "poses[0].header.frame_id", derived: truncated, input: TP}')]
    for old, new in swaps:
        assert text.count(old) == 1, old
        text = text.replace(old, new)
    model = tmp_path_factory.mktemp("elem_seq_reject") / "elem_seq_reject.yaml"
    model.write_text(text)
    out = nodes_dir / "elem_seq_reject"
    res = build(model, CONTROLLER, out)
    assert "ros_rseq_geometry_msgs_PoseStamped_3" in (out / "elem_seq_types.h").read_text()
    assert "input_relation path poses.data[0].header.frame_id.truncated TP" in res.generated.proved_model.splitlines()
    return out / "bin" / "elem_seq"


def test_policy_reject_keeps_the_previous_path(ros, elem_seq_reject, tmp_path):
    """Paths of N+1 and 2N poses are not delivered: the controller keeps
    the previous path's values (the JointState, not of policy reject,
    still arrives), bit for bit what T2 says with ``Environment.too_long``."""
    node = start_node(ros, elem_seq_reject, tmp_path / "node.log")
    steps, wants = [], []
    kept = None
    for c, length in enumerate(LENGTHS):
        path, joints, want = _case(c, length)
        slen0 = STR_LENGTHS[c % len(STR_LENGTHS)]
        want[1] = int(length > 0 and slen0 > M)          # TP: pose 0's frame_id truncated
        if length > N:
            want[:12] = kept                             # the path is dropped: the previous one stays
        else:
            kept = want[:12]
        steps += [{"publish": {"topic": "/path", "values": path}},
                  {"publish": {"topic": "/joints", "values": joints}},
                  {"sleep": HOLD}]
        wants.append(want)
    # a delivered N+1 or 2N path would show: its own values differ from those kept
    assert all(_case(c, n)[2][:12] != wants[c][:12] for c, n in enumerate(LENGTHS) if n > N)
    result = _drive(ros, node, steps, tmp_path)
    for c, length in enumerate(LENGTHS):
        t0, t1 = result["steps"][3 * c + 1]["t1"] + SETTLE, result["steps"][3 * c + 2]["t1"]
        want = {"layout.dim": {"var": 0}, "layout.data_offset": 0, "data": {"var": 21},
                **{f"data[{i}]": d(dbits(float(v))) for i, v in enumerate(wants[c])}}
        got = [r["leaves"] for r in rosutil.received(result, "/echo", t0, t1)]
        assert len(got) >= 5, (length, len(got))
        assert all(g == want for g in got), (length, got[-1], want)

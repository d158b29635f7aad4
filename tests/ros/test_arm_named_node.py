"""The arm that finds its joints by name, on a real master (rule 4.15: an
array of strings into controller arrays; whole arrays both ways).

``examples/arm_named/arm_named.yaml``, built with its Embedded Coder
controller (``examples/arm_named/controller``), carries JointState's
``name`` as at most 6 strings of at most 32 bytes and hands each name
whole to the controller (``"name[i]"`` into ``uint8 Name_i[32]``), the
positions, velocities and target whole into ``Pos[6]``, ``Vel[6]``,
``Target[6]``, and publishes ``Effort[6]`` whole with the length
``NEffort``.  A rospy driver publishes joint states whose entries come in
the driver's order: the controller's order, reversed, shuffled, with a
gripper before or after the arm, with 0, 1, N-1, N, N+1 and 2N names, a
name one byte too long, a name longer than the 32 bytes carried.  Every
effort message is checked bit for bit against the PD law computed here
in binary64, the joints matched by name as the controller does with what
the glue delivers: name ``i`` counts only if ``i`` is below the number of
names, positions and velocities received (each capped at 6), and a name
is its first 32 bytes."""

from __future__ import annotations

import pytest

from pyrosgen.ros.build import build

from support import ros as rosutil
from support.ros import d, dbits, run_driver, start_node

pytestmark = pytest.mark.ros

EXAMPLE = rosutil.ROOT / "examples" / "arm_named"
JS, TARGET, EFFORT = "/joint_states", "/arm/target", "/arm/effort"
JOINTS = ["shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint",
          "wrist_1_joint", "wrist_2_joint", "wrist_3_joint"]
N, NAME = 6, 32
KP, KD, EMAX = 20.0, 2.0, 50.0
SETTLE, HOLD = 0.3, 0.8


@pytest.fixture(scope="module")
def arm(nodes_dir):
    out = nodes_dir / "arm_named"
    res = build(EXAMPLE / "arm_named.yaml", EXAMPLE / "controller", out)
    binary = out / "bin" / "arm_named"
    assert binary.is_file()
    proved = res.generated.proved_model.splitlines()
    assert "input Name5 array 32 uint8" in proved
    assert "input_relation joint_states name.data[5].data[31] Name5[31]" in proved
    assert "output_relation Effort[5] arm_effort data.data[5]" in proved
    return binary


def efforts(names: list[str], pos: list[float], vel: list[float], target: list[float]) -> list[float]:
    """What the controller computes from what the glue delivers."""
    seen = min(len(names), len(pos), len(vel), N)
    carried = [n.encode()[:NAME] for n in names[:seen]]
    if len(target) < N:
        return []
    out = []
    for j, joint in enumerate(JOINTS):
        hits = [i for i, n in enumerate(carried) if n == joint.encode()]
        if not hits:
            return []
        i = hits[0]
        e = KP * (target[j] - pos[i]) - KD * vel[i]
        out.append(min(max(e, -EMAX), EMAX))
    return out


def _state(names: list[str], k: int, npos: int | None = None) -> dict:
    n = len(names)
    pos = [0.1 * (i + 1) + 0.01 * k for i in range(n if npos is None else npos)]
    vel = [0.5 - 0.125 * i + 0.25 * k for i in range(n)]
    return {"name": names, "position": pos, "velocity": vel}


REV = JOINTS[::-1]
SHUF = [JOINTS[i] for i in (3, 0, 5, 1, 4, 2)]
#: (what, names, positions if fewer than names, the targets' scale and count)
CASES = [
    ("N names, the controller's order", JOINTS, None, 1.0, 6),
    ("N names, reversed", REV, None, 1.0, 6),
    ("no name", [], None, 1.0, 6),
    ("N names, shuffled, saturated", SHUF, None, 10.0, 6),
    ("one name", JOINTS[:1], None, 1.0, 6),
    ("N-1 names", SHUF[:5], None, 1.0, 6),
    ("N+1 names, the gripper last", JOINTS + ["gripper_joint"], None, -10.0, 6),
    ("N+1 names, the gripper first: wrist_3 not carried", ["gripper_joint"] + JOINTS, None, 1.0, 6),
    ("2N names, the arm first", REV + [f"tool_{i}" for i in range(6)], None, 1.0, 6),
    ("N names, 5 positions", SHUF, 5, 1.0, 6),
    ("N names, 5 targets", JOINTS, None, 1.0, 5),
    ("a name one byte longer", JOINTS[:2] + ["elbow_joint2"] + JOINTS[3:], None, 1.0, 6),
    ("names beyond 32 bytes elsewhere", REV + ["x" * 40, "y" * 33], None, 0.5, 6),
]


def test_the_arm_matches_its_joints_by_name(ros, arm, tmp_path):
    node = start_node(ros, arm, tmp_path / "node.log")
    steps, wants = [], []
    for k, (_, names, npos, scale, ntgt) in enumerate(CASES):
        state = _state(list(names), k, npos)
        targets = [scale * (0.3 * i - 0.6) for i in range(ntgt)]
        steps += [{"publish": {"topic": JS, "values": {**state, "header.frame_id": "base_link"}}},
                  {"publish": {"topic": TARGET, "values": {"data": targets}}},
                  {"sleep": HOLD}]
        wants.append(efforts(state["name"], state["position"], state["velocity"], targets))
    # the cases exercise both answers, and the matching by name
    assert sum(1 for w in wants if w) >= 5 and sum(1 for w in wants if not w) >= 5
    plan = {"publishers": [{"topic": JS, "type": "sensor_msgs/JointState", "queue_size": 10},
                           {"topic": TARGET, "type": "std_msgs/Float64MultiArray", "queue_size": 10}],
            "subscribers": [{"topic": EFFORT, "type": "std_msgs/Float64MultiArray", "record": "elements"}],
            "wait_messages": True, "steps": steps, "linger": 0.2}
    result = run_driver(ros, plan, tmp_path)
    assert node.poll() is None, (tmp_path / "node.log").read_text()[-2000:]
    assert len(result["steps"]) == len(steps)
    first = rosutil.received(result, EFFORT)[0]["leaves"]
    assert first == {"layout.dim": {"var": 0}, "layout.data_offset": 0, "data": {"var": 0}}, first
    for k, ((what, *_), want) in enumerate(zip(CASES, wants)):
        t0, t1 = result["steps"][3 * k + 1]["t1"] + SETTLE, result["steps"][3 * k + 2]["t1"]
        leaves = {"layout.dim": {"var": 0}, "layout.data_offset": 0, "data": {"var": len(want)},
                  **{f"data[{i}]": d(dbits(e)) for i, e in enumerate(want)}}
        got = [r["leaves"] for r in rosutil.received(result, EFFORT, t0, t1)]
        assert len(got) >= 20, (what, len(got))
        assert all(g == leaves for g in got), (what, got[-1], leaves)
    assert any(w and max(w) == EMAX for w in wants) and any(w and min(w) == -EMAX for w in wants)

"""The 6-joint arm example on a real master (rules 4.15, both sides).

``examples/arm/arm.yaml``, built by ``pyrosgen build`` (the controller's C
from its block diagram: a saturated PD law per joint, a Subsystem used six
times), subscribes to ``/joint_states`` (``sensor_msgs/JointState``,
``position`` and ``velocity`` carried as at most 6 float64; ``name``, an
array of strings, and ``effort`` are not carried) and ``/arm/target``
(``std_msgs/Float64MultiArray``), and publishes ``/arm/effort``
(``std_msgs/Float64MultiArray``).  A rospy driver publishes joint states
and targets: 6 joints and 6 targets, fewer positions, velocities or
targets, more joints than 6 (truncated: the first 6 are used), large
errors (saturated).  Every effort message is checked bit for bit against
the PD law computed here in IEEE binary64 (round to nearest even, as
``Diagram.dg_step`` says): 6 elements when the newest joint state has at
least 6 positions and 6 velocities and the newest target at least 6
angles, else none (also before the first messages)."""

from __future__ import annotations

import pytest

from pyrosgen.ros.build import build

from support import ros as rosutil
from support.ros import d, dbits, run_driver, start_node

pytestmark = pytest.mark.ros

MODEL = rosutil.ROOT / "examples" / "arm" / "arm.yaml"
JS, TARGET, EFFORT = "/joint_states", "/arm/target", "/arm/effort"
KP, KD, UMAX = 20.0, 2.0, 50.0
SETTLE, HOLD = 0.3, 0.8


@pytest.fixture(scope="module")
def arm(nodes_dir):
    out = nodes_dir / "arm"
    res = build(MODEL, None, out)
    binary = out / "bin" / "arm_pd"
    assert binary.is_file()
    proved = res.generated.proved_model.splitlines()
    assert "output_relation NE arm_effort data.len" in proved
    assert "input_relation joint_states position.data[5] P5" in proved
    return binary


def pd(target: float, pos: float, vel: float) -> float:
    """The diagram's law for one joint, in binary64 like Diagram.dg_step."""
    u = KP * (target - pos) - KD * vel
    return min(max(u, -UMAX), UMAX)


def _joints(n: int, k: int) -> tuple[list[float], list[float]]:
    """n joints' positions and velocities in case k: distinct values."""
    return [0.1 * (i + 1) + 0.01 * k for i in range(n)], [0.5 - 0.125 * i + 0.25 * k for i in range(n)]


#: (what, joints with a position, joints with a velocity, targets, a scale
#: of the targets: large ones saturate); the number of efforts follows
CASES = [
    ("6 joints, 6 targets", 6, 6, 6, 1.0),
    ("5 positions", 5, 6, 6, 1.0),
    ("6 joints again, saturated", 6, 6, 6, 10.0),
    ("5 velocities", 6, 5, 6, 1.0),
    ("7 joints: the first 6", 7, 7, 6, 1.0),
    ("3 targets", 6, 6, 3, 1.0),
    ("8 targets: the first 6", 6, 6, 8, -10.0),
    ("no joint at all", 0, 0, 6, 1.0),
    ("6 joints, 6 targets, small errors", 6, 6, 6, 0.5),
]


def test_the_arm_commands_a_saturated_pd_effort_per_joint(ros, arm, tmp_path):
    node = start_node(ros, arm, tmp_path / "node.log")
    steps, wants = [], []
    for k, (_, npos, nvel, ntgt, scale) in enumerate(CASES):
        pos, _ = _joints(npos, k)
        _, vel = _joints(nvel, k)
        targets = [scale * (0.3 * i - 0.6) for i in range(ntgt)]
        names = [f"joint_{i + 1}" for i in range(max(npos, nvel))]
        steps += [{"publish": {"topic": JS, "values": {"name": names, "position": pos, "velocity": vel,
                                                        "effort": [1.0] * len(names),
                                                        "header.frame_id": "base_link"}}},
                  {"publish": {"topic": TARGET, "values": {"data": targets}}},
                  {"sleep": HOLD}]
        if npos >= 6 and nvel >= 6 and ntgt >= 6:
            wants.append([pd(targets[i], pos[i], vel[i]) for i in range(6)])
        else:
            wants.append([])
    plan = {"publishers": [{"topic": JS, "type": "sensor_msgs/JointState", "queue_size": 10},
                           {"topic": TARGET, "type": "std_msgs/Float64MultiArray", "queue_size": 10}],
            "subscribers": [{"topic": EFFORT, "type": "std_msgs/Float64MultiArray", "record": "elements"}],
            "wait_messages": True, "steps": steps, "linger": 0.2}
    result = run_driver(ros, plan, tmp_path)
    assert node.poll() is None, (tmp_path / "node.log").read_text()[-2000:]
    assert len(result["steps"]) == len(steps)
    # before the first messages: no command
    first = rosutil.received(result, EFFORT)[0]["leaves"]
    assert first == {"layout.dim": {"var": 0}, "layout.data_offset": 0, "data": {"var": 0}}, first
    saturated = 0
    for k, ((what, *_), want) in enumerate(zip(CASES, wants)):
        t0, t1 = result["steps"][3 * k + 1]["t1"] + SETTLE, result["steps"][3 * k + 2]["t1"]
        leaves = {"layout.dim": {"var": 0}, "layout.data_offset": 0, "data": {"var": len(want)},
                  **{f"data[{i}]": d(dbits(e)) for i, e in enumerate(want)}}
        got = [r["leaves"] for r in rosutil.received(result, EFFORT, t0, t1)]
        assert len(got) >= 20, (what, len(got))
        assert all(g == leaves for g in got), (what, got[-1], leaves)
        saturated += sum(abs(e) == UMAX for e in want)
    assert saturated >= 6   # the saturation is exercised, both ways
    assert any(w and max(w) == UMAX for w in wants) and any(w and min(w) == -UMAX for w in wants)

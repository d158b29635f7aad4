"""A node whose controller is a block diagram, on a real master:
``pyrosgen build`` without ``--controller`` (the controller C printed by
Coq from examples/landshark/landshark_diagram.yaml), driven by rospy.

With steady readings, one of them a spoofed GPS at 3x the wheel speed, the
published command settles on the value the diagram's reference
interpreter (pyrosgen/frontend/blocksim.py, written independently of the
C) computes after the same number of steady steps, bit for bit; the
median makes it the command for an honest GPS."""

from __future__ import annotations

import struct

import pytest

from pyrosgen.frontend import blocksim
from pyrosgen.frontend.validate import load_model
from pyrosgen.ros.build import build

from support import ros as rosutil
from support.ros import dbits, received, run_driver, start_node

LEFT, RIGHT, GPS = "/landshark/left_wheel_velocity", "/landshark/right_wheel_velocity", "/landshark/gps_velocity"
BASE = "/landshark_control/base_velocity"
TS = "geometry_msgs/TwistStamped"
DIAGRAM = rosutil.ROOT / "examples" / "landshark" / "landshark_diagram.yaml"

pytestmark = pytest.mark.ros


@pytest.fixture(scope="module")
def diagram_node(nodes_dir):
    """The LandShark diagram node: built without a controller folder."""
    out = nodes_dir / "landshark_diagram"
    res = build(DIAGRAM, None, out)
    assert (out / "bin" / "landshark_controller").is_file()
    assert res.generated.record.controller["e2e"] == "Ctrl.landshark_controller_e2e"
    return out


def _steady(diagram, inputs, steps=2000) -> int:
    """The command after ``steps`` steps on constant inputs (blocksim)."""
    u = {f"In{i + 1}": dbits(x) for i, x in enumerate(inputs)}
    state = blocksim.initial_state(diagram)
    for _ in range(steps):
        state, y = blocksim.step(diagram, state, u)
    return y["Out1"]


def test_diagram_node_steady_state(ros, diagram_node, tmp_path):
    diagram = load_model(DIAGRAM).controller.diagram
    left, right, gps = 1.4, 1.5, 4.5
    expected = _steady(diagram, (left, right, gps))
    assert expected == _steady(diagram, (left, right, 1.55))          # honest GPS: same command
    assert expected != _steady(diagram, ((left + right + gps) / 3,) * 3)  # a mean would differ
    start_node(ros, diagram_node / "bin" / "landshark_controller", tmp_path / "node.log")
    plan = {
        "publishers": [{"topic": t, "type": TS} for t in (LEFT, RIGHT, GPS)],
        "subscribers": [{"topic": BASE, "type": TS}],
        "wait_messages": True,
        "steps": [
            {"publish": {"topic": LEFT, "values": {"twist.linear.x": rosutil.d(dbits(left))}}},
            {"publish": {"topic": RIGHT, "values": {"twist.linear.x": rosutil.d(dbits(right))}}},
            {"publish": {"topic": GPS, "values": {"twist.linear.x": rosutil.d(dbits(gps))}}},
            # the integrator goes from 0 to its bound -0.5 in 100 steps (2 s)
            {"sleep": 5.0},
        ],
    }
    result = run_driver(ros, plan, tmp_path)
    t_end = result["steps"][-1]["t1"]
    tail = received(result, BASE, t_end - 1.0, t_end)
    assert len(tail) >= 20
    got = {rosutil.bits_of(r["leaves"]["twist.linear.x"]) for r in tail}
    assert got == {expected}, (f"expected {expected:#x} "
                               f"({struct.unpack('<d', struct.pack('<Q', expected))[0]})")

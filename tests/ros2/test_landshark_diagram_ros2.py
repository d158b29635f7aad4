"""LandShark's diagram variant on ROS 2, end to end on a real DDS (Fast DDS
from the wheels, loopback only): examples/landshark/landshark_diagram.yaml
built with ``--ros2`` and no controller folder (the controller C printed by
Coq from the block diagram, rule 4.11), driven by an rclpy peer.

Every published command is checked bit for bit against the diagram's
reference interpreter (pyrosgen/frontend/blocksim.py, written independently
of the C) run on the same history: before any reading, a value of the
all-zero trajectory (the integrator climbing to its bound +0.5); then
rounds of steady readings whose median is below the set point or NaN, so
that the integrator stays at its bound whatever the cycles the three
messages of a round straddle, and the command is the one blocksim gives
after the history (a spoofed GPS at 3x and at -5, all readings NaN: the
error is replaced by 0, the command is the set point plus the integral)."""

from __future__ import annotations

import math
import signal

import pytest

from pyrosgen.frontend import blocksim
from pyrosgen.ros2.build import build_ros2
from pyrosgen.ros2.frontend import load_model_ros2

from support import ros as rosutil
from support.ros import dbits

from .conftest import run_peer, settled_leftovers, spawn, stop

DIAGRAM = rosutil.ROOT / "examples" / "landshark" / "landshark_diagram.yaml"
LEFT, RIGHT, GPS = "/landshark/left_wheel_velocity", "/landshark/right_wheel_velocity", "/landshark/gps_velocity"
BASE = "/landshark_control/base_velocity"
TS = "geometry_msgs/TwistStamped"
NAN = math.nan
#: (left, right, gps) per round: medians below the set point 1.0, or NaN
ROUNDS = [(NAN, NAN, NAN), (0.6, 0.7, 3.0 * 0.7), (0.9, 0.8, -5.0), (0.25, 0.5, 0.75), (NAN, NAN, NAN)]
SETTLE, HOLD = 0.3, 0.7
STEADY = 400   # blocksim steps per phase: more than any transient (the integrator moves 0.01 a step at most)


@pytest.fixture(scope="module")
def diagram2(ros2_install, ros2_nodes):
    res = build_ros2(DIAGRAM, None, ros2_nodes / "landshark_diagram", install=ros2_install)
    assert res.generated.record.controller["e2e"] == "Ctrl.landshark_controller_e2e"
    return res


def _run(diagram, state, readings, steps: int) -> tuple[object, list[int]]:
    u = {f"In{i + 1}": dbits(x) for i, x in enumerate(readings)}
    ys = []
    for _ in range(steps):
        state, y = blocksim.step(diagram, state, u)
        ys.append(y["Out1"])
    return state, ys


def test_landshark_diagram_ros2_bit_exact_against_blocksim(diagram2, ros2_install, tmp_path, shm_guard):
    diagram = load_model_ros2(DIAGRAM, ros2_install).controller.diagram
    state, zero_phase = _run(diagram, blocksim.initial_state(diagram), (0.0, 0.0, 0.0), STEADY)
    wants = []
    for r in ROUNDS:
        state, ys = _run(diagram, state, r, STEADY)
        assert ys[-1] == ys[-2]   # steady
        wants.append(ys[-1])
    assert len(set(wants)) == 4 and wants[0] == wants[-1] == dbits(1.5)   # NaN readings: 1.0 + 0.5
    steps = [{"sleep": 1.2}]   # more than the 50 cycles the integrator takes to reach its bound
    for r in ROUNDS:
        steps += [{"publish": {t: {"twist.linear.x": dbits(x)} for t, x in zip((LEFT, RIGHT, GPS), r)}},
                  {"sleep": HOLD}]
    node = spawn([diagram2.binary], tmp_path / "node.log")
    try:
        result = run_peer({"publishers": {t: TS for t in (LEFT, RIGHT, GPS)}, "subscribers": {BASE: TS},
                           "match_timeout": 20.0, "steps": steps}, tmp_path, ros2_install)
    finally:
        status = stop(node, signal.SIGTERM)
    assert status == 0, (tmp_path / "node.log").read_text(errors="replace")[-2000:]
    rsteps = result["steps"]
    got = [(t, lv["twist.linear.x"]) for t, _topic, lv in result["received"]]
    before = [b for t, b in got if t < rsteps[1]["t0"]]
    assert len(before) >= 20 and set(before) <= set(zero_phase) and before[-1] == zero_phase[-1], \
        [hex(b) for b in before[-5:]]
    for k, want in enumerate(wants):
        t0, t1 = rsteps[1 + 2 * k]["t1"] + SETTLE, rsteps[2 + 2 * k]["t1"]
        window = [b for t, b in got if t0 <= t <= t1]
        assert len(window) >= 10 and all(b == want for b in window), (k, ROUNDS[k], [hex(b) for b in window[:4]],
                                                                      hex(want))
    assert not (left := settled_leftovers()), left

"""A node whose controller is a block diagram, on a real master:
``pyrosgen build`` without ``--controller`` (the controller C printed by
Coq from examples/landshark/landshark_diagram.yaml, and from
landshark_subsystem.yaml, the same diagram with subsystems), driven by
rospy.

With steady readings, one of them a spoofed GPS at 3x the wheel speed, the
published command settles on the value the diagram's reference
interpreter (pyrosgen/frontend/blocksim.py, written independently of the
C) computes after the same number of steady steps, bit for bit; the
median makes it the command for an honest GPS."""

from __future__ import annotations


import pytest

from pyrosgen.frontend import blocksim
from pyrosgen.frontend.validate import load_model
from pyrosgen.ros.build import build

from support import ros as rosutil
from support.ros import dbits, start_node

DIAGRAM = rosutil.ROOT / "examples" / "landshark" / "landshark_diagram.yaml"
SUBSYSTEM = rosutil.ROOT / "examples" / "landshark" / "landshark_subsystem.yaml"

pytestmark = pytest.mark.ros


@pytest.fixture(scope="module")
def diagram_node(nodes_dir):
    """The LandShark diagram node: built without a controller folder."""
    out = nodes_dir / "landshark_diagram"
    res = build(DIAGRAM, None, out)
    assert (out / "bin" / "landshark_controller").is_file()
    assert res.generated.record.controller["e2e"] == "Ctrl.landshark_controller_e2e"
    assert res.generated.record.controller["linked"] == "Ctrl.landshark_controller_linked"
    return out


def _steady(diagram, inputs, steps=2000) -> int:
    """The command after ``steps`` steps on constant inputs (blocksim)."""
    u = {f"In{i + 1}": dbits(x) for i, x in enumerate(inputs)}
    state = blocksim.initial_state(diagram)
    for _ in range(steps):
        state, y = blocksim.step(diagram, state, u)
    return y["Out1"]


@pytest.fixture(scope="module")
def subsystem_node(nodes_dir):
    """The same diagram written with subsystems (median3, nan_to_zero)."""
    out = nodes_dir / "landshark_subsystem"
    build(SUBSYSTEM, None, out)
    return out


@pytest.mark.parametrize("which", ["flat", "subsystems"])
def test_diagram_node_steady_state(ros, which, request, tmp_path):
    """The node settles on blocksim's command, for the flat diagram and for
    the one with subsystems (blocksim runs the flat diagram in both)."""
    node = request.getfixturevalue("diagram_node" if which == "flat" else "subsystem_node")
    diagram = load_model(DIAGRAM).controller.diagram
    left, right, gps = 1.4, 1.5, 4.5
    expected = _steady(diagram, (left, right, gps))
    assert expected == _steady(diagram, (left, right, 1.55))          # honest GPS: same command
    assert expected != _steady(diagram, ((left + right + gps) / 3,) * 3)  # a mean would differ
    start_node(ros, node / "bin" / "landshark_controller", tmp_path / "node.log")
    # the integrator goes from 0 to its bound -0.5 in 100 steps (2 s)
    rosutil.landshark_settles_on(ros, tmp_path, (left, right, gps), expected, settle=5.0)


def test_demo_with_the_diagram_controller(diagram_node, tmp_path):
    """``make demo DIAGRAM=1``'s run phase: the node whose controller is
    the proved diagram keeps the simulated LandShark at its set speed while
    the GPS is spoofed, and everything started is stopped."""
    import re
    import subprocess
    import sys

    env = {"CI": "true", "PATH": "/usr/bin:/bin", "HOME": str(tmp_path)}
    r = subprocess.run([sys.executable, "-m", "pyrosgen.ros.demo", str(diagram_node), "--duration", "7",
                        "--spoof", "3:6"], cwd=rosutil.ROOT, env=env, stdin=subprocess.DEVNULL,
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stdout + r.stderr
    out = r.stdout
    assert "sim: OK: the spoofed GPS was rejected" in out
    rows = [line.split() for line in out.splitlines() if re.match(r"^\s*\d+\.\d\d\s", line)]
    spoofed = [row for row in rows if "SPOOFED" in row]
    assert spoofed and all(float(row[3]) > 2.5 for row in spoofed)
    assert all(0.85 <= float(row[5]) <= 1.15 for row in spoofed)
    pids = [int(p) for p in re.findall(r"\(pid (\d+)\)", out)]
    assert len(pids) == 3 and not any(rosutil.alive(p) for p in pids)

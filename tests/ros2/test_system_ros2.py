"""The three-node chain of examples/system_chain on a real DDS (Fast DDS
from the wheels, loopback only), built by ``pyrosgen system build
--ros2``: OUT/src holds each node's ament_cmake package, the system's
launch file is in ROS 2's XML launch format, and the three binaries are
started with the command lines read from it
(:func:`pyrosgen.system.launch.read_ros2_launch`: ``--ros-args -r
__node:= -r __ns:= -r FROM:=TO -p use_sim_time:=``), as ``ros2 launch``
would start them.  An rclpy peer drives the external inputs and listens to
the external output, with the expectations of
tests/system/test_chain_ros.py for ROS 1: a clear scan drives the wheels
at the guard's cruise speed through the velocity mux, an obstacle stops
them, a teleop command takes over; the values on /base/wheels are the ones
the controllers compute (bit for bit)."""

from __future__ import annotations

import signal
import struct
import xml.etree.ElementTree as ET

import pytest

from pyrosgen.system.checks import check_system
from pyrosgen.system.generate import generate_system
from pyrosgen.system.launch import read_ros2_launch
from pyrosgen.system.model import load_system

from support import ros as rosutil

from .conftest import fastdds_segments, in_use, run_peer, settled_leftovers, start_launch, stop

pytestmark = pytest.mark.ros2

SYSTEM = rosutil.ROOT / "examples" / "system_chain" / "system.yaml"
N = 1081
SCAN, TELEOP, WHEELS = "/scan", "/teleop/cmd_vel", "/base/wheels"
#: after a phase starts, the chain's three cycles (20 ms each) and deliveries
SETTLE = 0.6
PHASE = 1.5


def bits(x: float) -> int:
    return struct.unpack("<Q", struct.pack("<d", x))[0]


def wheels(vx: float, wz: float) -> tuple[int, int, int]:
    """What diff_drive computes (its diagram, in float64): left, right, 0."""
    turn = wz * 0.25
    clamp = lambda v: min(max(v, -1.0), 1.0)  # noqa: E731
    return bits(clamp(vx - turn)), bits(clamp(vx + turn)), 0


@pytest.fixture(scope="module")
def system_out(ros2_install, tmp_path_factory):
    """``pyrosgen system build --ros2`` of the chain (a fresh cache, -j 2)."""
    root = tmp_path_factory.mktemp("chain2")
    res = generate_system(SYSTEM, root / "out", jobs=2, cache=root / "cache", build=True, target="ros2")
    assert [n.cached for n in res.nodes] == [False, False, False]
    assert res.files[-2:] == ["guard_chain.launch.xml", "src"]
    return root / "out"


def test_workspace_holds_the_ament_packages(system_out):
    """OUT/src: one link per node package, each ``build --ros2``'s
    ament_cmake package (package.xml format 3), next to its node's binary."""
    src = system_out / "src"
    assert sorted(p.name for p in src.iterdir()) == ["diff_drive", "laser_guard", "velocity_guard"]
    for pkg in src.iterdir():
        assert pkg.is_symlink() and (pkg / "CMakeLists.txt").is_file()
        xml = ET.parse(pkg / "package.xml").getroot()
        assert xml.get("format") == "3" and xml.findtext("name") == pkg.name
        assert xml.findtext("buildtool_depend") == "ament_cmake"
        assert xml.find("export").findtext("build_type") == "ament_cmake"
        folder = pkg.resolve().parent
        assert (folder / "bin" / pkg.name).is_file()
        assert (folder / f"{pkg.name}.target").read_text().startswith("target: ros2")
        assert (folder / f"{pkg.name}_rcl.c").is_file() and not (folder / f"{pkg.name}_ros.cpp").exists()
    assert not (system_out / "guard_chain.launch").exists()


def test_launch_file_starts_every_node_with_its_namespace_and_remaps(system_out):
    """The launch file in ROS 2's XML format, read back: every node of the
    system with its package, executable, name, namespace and remappings as
    the system's resolution has them; use_sim_time a launch argument."""
    text = (system_out / "guard_chain.launch.xml").read_text()
    root = ET.fromstring(text)
    assert [a.attrib for a in root.findall("arg")] == [{"name": "use_sim_time", "default": "false"}]
    sysm = load_system(SYSTEM, "ros2")
    check_system(sysm)
    nodes = read_ros2_launch(text)
    assert [(n.pkg, n.exec, n.name, n.namespace, dict(n.remaps)) for n in nodes] == [
        (sn.model.name, sn.model.name, sn.name, sn.namespace, sn.remap) for sn in sysm.nodes]
    assert [n.folder for n in nodes] == [sn.folder for sn in sysm.nodes] == [
        "safety.laser_guard", "velocity_mux", "diff_drive"]
    mux = nodes[1]
    assert mux.argv("bin/velocity_guard") == [
        "bin/velocity_guard", "--ros-args", "-r", "__node:=velocity_mux", "-r", "__ns:=/",
        "-r", "/nav/cmd_vel:=/safety/cmd_vel", "-p", "use_sim_time:=false"]
    assert read_ros2_launch(text, {"use_sim_time": "true"})[0].argv("x")[-2:] == ["-p", "use_sim_time:=true"]
    assert nodes[0].argv("x")[:6] == ["x", "--ros-args", "-r", "__node:=laser_guard", "-r", "__ns:=/safety"]


def _scan(r: float) -> dict:
    return {"ranges": [bits(r)] * N}


def _teleop(vx: float, wz: float) -> dict:
    return {"linear.x": bits(vx), "angular.z": bits(wz)}


@pytest.fixture(scope="module")
def colcon_install(system_out, ros2_install, tmp_path_factory):
    """``colcon build`` of OUT/src copied into a workspace (colcon of
    requirements-ros2.txt, ``make ros2-deps``; no ament_cmake here: each
    package's CMake fallback finds the wheels from PYROSGEN_ROS2_PREFIX):
    the workspace's ``install`` folder."""
    import shutil
    import subprocess

    colcon = ros2_install.prefix / "bin" / "colcon"
    assert colcon.is_file(), f"{colcon}: no colcon; `make ros2-deps` installs it (requirements-ros2.txt)"
    ws = tmp_path_factory.mktemp("chain2_ws")
    shutil.copytree(system_out / "src", ws / "src", symlinks=False)
    env = {"PATH": f"{colcon.parent}:/usr/bin:/bin", "HOME": str(ws),
           "PYROSGEN_ROS2_PREFIX": str(ros2_install.prefix)}
    r = subprocess.run([str(colcon), "build"], cwd=ws, env=env, capture_output=True, text=True, timeout=900)
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
    finished = sorted(line.split()[2] for line in r.stdout.splitlines() if line.startswith("Finished <<< "))
    assert finished == sorted(p.name for p in (system_out / "src").iterdir()), r.stdout[-3000:]
    assert "Failed" not in r.stdout, r.stdout[-3000:]
    return ws / "install"


@pytest.mark.parametrize("binaries", ["system_build", "colcon"])
def test_chain_runs_end_to_end_on_dds(binaries, system_out, ros2_install, tmp_path, shm_guard, request):
    """The three nodes started as the launch file says; the peer streams
    /scan (and then /teleop/cmd_vel) every 100 ms; in each phase, once the
    chain has settled, every message on /base/wheels carries what the three
    controllers compute.  The binaries are ``system build``'s, or those
    that ``colcon build`` of OUT/src installs where ``ros2 launch`` finds a
    node's ``pkg`` and ``exec`` (``install/PKG/lib/PKG/EXEC``)."""
    text = (system_out / "guard_chain.launch.xml").read_text()
    install = request.getfixturevalue("colcon_install") if binaries == "colcon" else None
    procs = []
    try:
        start_launch(text, system_out, install, tmp_path, procs)
        steps = [{"stream": {SCAN: _scan(5.0)}, "period": 0.1, "duration": 2.0},      # discovery inside the chain
                 {"stream": {SCAN: _scan(5.0)}, "period": 0.1, "duration": PHASE},
                 {"stream": {SCAN: _scan(0.5)}, "period": 0.1, "duration": PHASE},
                 {"stream": {TELEOP: _teleop(0.2, 1.0)}, "period": 0.1, "duration": PHASE}]
        plan = {"publishers": {SCAN: "sensor_msgs/LaserScan", TELEOP: "geometry_msgs/Twist"},
                "subscribers": {WHEELS: "geometry_msgs/Vector3"}, "match_timeout": 30.0, "steps": steps}
        result = run_peer(plan, tmp_path, ros2_install, timeout=120)
        for name, p in procs:
            assert p.poll() is None, f"{name} exited: " + (tmp_path / f"{name.strip('/').replace('/', '.')}.log"
                                                            ).read_text(errors="replace")[-2000:]
    finally:
        statuses = [(name, stop(p, signal.SIGTERM)) for name, p in procs]
    assert [s for _, s in statuses] == [0, 0, 0], statuses
    got = [(t, (lv["x"], lv["y"], lv["z"])) for t, topic, lv in result["received"] if topic == WHEELS]
    problems = []
    for k, want, what in ((1, wheels(0.5, 0.0), "clear: the guard's cruise 0.5 m/s through the mux"),
                          (2, wheels(0.0, 0.0), "an obstacle at 0.5 m: stop"),
                          (3, wheels(0.2, 1.0), "teleop (0.2 m/s, 1 rad/s) takes over")):
        s = result["steps"][k]
        window = [v for t, v in got if s["t0"] + SETTLE <= t <= s["t1"]]
        if len(window) < 10:
            problems.append(f"{what}: only {len(window)} messages")
        problems += [f"{what}: got {v}, expected {want}" for v in sorted(set(window)) if v != want]
    assert not problems, "\n".join(problems[:20])
    assert not (left := settled_leftovers()), left


def test_system_demo_ros2(system_out, tmp_path, shm_guard):
    """``make demo ROS=2``'s system part: python -m pyrosgen.system.demo_dds
    OUT starts the nodes from the launch file's command lines and rclpy
    sensors, checks every phase and stops everything it started (no
    process, no /dev/shm segment left)."""
    import os
    import re
    import subprocess
    import sys
    import time

    before = fastdds_segments()
    env = {**os.environ, "CI": "true", "HOME": str(tmp_path)}
    r = subprocess.run([sys.executable, "-m", "pyrosgen.system.demo_dds", str(system_out), "--phase", "1.5"],
                       cwd=rosutil.ROOT, env=env, stdin=subprocess.DEVNULL, capture_output=True, text=True,
                       timeout=180)
    assert r.returncode == 0, r.stdout + r.stderr
    out = r.stdout
    assert "sim: OK: the chain computed every phase's wheel speeds" in out
    assert len(re.findall(r"^sim: [^\n]*the controllers compute [^\n]*: OK$", out, re.M)) == 3
    assert "-r /nav/cmd_vel:=/safety/cmd_vel" in out and "-r __ns:=/safety" in out
    pids = [int(p) for p in re.findall(r"\(pid (\d+)\)", out)]
    assert len(pids) == 4 and not any(rosutil.alive(p) for p in pids)
    assert "demo: all processes stopped" in out
    # a segment that appeared during the run and that no live process maps
    # was left behind (as tests/ros2/test_demo_ros2.py reads it)
    left = (fastdds_segments() - before) - in_use()
    deadline = time.monotonic() + 15.0
    while left and time.monotonic() < deadline:
        time.sleep(0.5)
        left = (fastdds_segments() - before) - in_use()
    assert not left, left
    # bad usage: a folder without the system
    r = subprocess.run([sys.executable, "-m", "pyrosgen.system.demo_dds", str(tmp_path / "nothing")],
                       cwd=rosutil.ROOT, env=env, capture_output=True, text=True, timeout=60)
    assert r.returncode == 1 and "not found" in r.stdout and "Traceback" not in r.stderr

"""Custom messages in a ROS 2 system (rule 10.10) on a real DDS: the two
relays of tests/system/test_custom_messages.py, ``k6a`` (Y = 2 X) from
/src (``geometry_msgs/Twist``) to /mid (``k6_msgs/Level``, a custom
message each node's ``msg_paths`` defines, alike but for a comment) and
``k6b`` (Y = 2 X) from /mid to /out (``geometry_msgs/Vector3``), built by
``pyrosgen system build --ros2``.  Each node's folder holds its own build
of k6_msgs (``build --ros2``: rosidl's code compiled into ``lib/``, its
interface package ``k6_msgs/``); OUT/src links the first one's interface
package with the two node packages, and ``colcon build --base-paths src``
builds the workspace (no ament_cmake here: each package's CMake fallback).
The nodes, started as the launch file says (from ``system build``'s
binaries and from colcon's), exchange /mid between two separate builds of
the type: an rclpy peer, which knows nothing of k6_msgs, sees /out = 4 X
bit for bit."""

from __future__ import annotations

import shutil
import signal
import struct
import subprocess
import sys

import pytest


from system.test_custom_messages import system

from .conftest import run_peer, settled_leftovers, start_launch, stop

pytestmark = pytest.mark.ros2

X = 1.25


def bits(x: float) -> int:
    return struct.unpack("<Q", struct.pack("<d", x))[0]


@pytest.fixture(scope="module")
def levels_run(ros2_install, tmp_path_factory):
    """``pyrosgen system build --ros2`` of the two relays, the command line
    as a user runs it (a fresh cache): OUT and what it printed."""
    root = tmp_path_factory.mktemp("levels2")
    p = system(root / "src")
    r = subprocess.run([sys.executable, "-m", "pyrosgen", "system", "build", str(p), "--ros2", "-o",
                        str(root / "out"), "-j", "2", "--cache", str(root / "cache")],
                       capture_output=True, text=True, timeout=1800)
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
    return root / "out", r.stdout


@pytest.fixture(scope="module")
def levels(levels_run):
    return levels_run[0]


def test_system_build_says_how_to_build_the_workspace(levels_run):
    out, text = levels_run
    assert "levels_system.v, levels.certificate.md, levels.system.json, levels.launch.xml, src;" in text, text
    assert f"  ament: in {out}, colcon build --base-paths src (its links kept: a node's package finds its custom " \
           f"messages in its own folder), then ros2 launch {out}/levels.launch.xml;" in text, text


def test_workspace_links_one_interface_package(levels):
    """OUT/src: the two node packages and one k6_msgs, the first node's
    interface package; each node folder holds its own build of the type."""
    src = levels / "src"
    assert sorted(p.name for p in src.iterdir()) == ["k6_msgs", "k6a", "k6b"]
    assert all(p.is_symlink() for p in src.iterdir())
    assert (src / "k6_msgs").resolve() == (levels / "k6a" / "k6_msgs").resolve()
    assert not (levels / "msgs").exists()   # ROS 1's catkin message packages
    for node in ("k6a", "k6b"):
        folder = levels / node
        assert (folder / "lib" / "libk6_msgs__rosidl_typesupport_c.so").is_file()
        assert (folder / "k6_msgs" / "msg" / "Level.msg").is_file()
        assert "<depend>k6_msgs</depend>" in (folder / node / "package.xml").read_text()


def test_levels_system_verify(levels):
    """``system verify --ros2`` re-checks both node folders, their interface
    packages included, and the system's proof; a tampered interface
    package of the second node is found."""
    from pyrosgen.system.verify import SystemVerifyFailed, verify_system

    system_file = levels.parent / "src" / "system.yaml"
    report = verify_system(levels, system_file, jobs=2, target="ros2")
    assert report.ok, report.lines()
    cmake = levels / "k6b" / "k6_msgs" / "CMakeLists.txt"
    text = cmake.read_text()
    try:
        cmake.write_text(text.replace("  ament_package()", "  execute_process(COMMAND id)\n  ament_package()"))
        with pytest.raises(SystemVerifyFailed) as info:
            verify_system(levels, system_file, jobs=2, target="ros2")
    finally:
        cmake.write_text(text)
    failed = {name: why for name, ok, why in info.value.verify_report.checks if not ok}
    assert set(failed) == {"node k6b", "system proof"}, info.value.verify_report.lines()
    assert failed["system proof"] == "not run: a check above failed"
    assert "package" in failed["node k6b"], failed


@pytest.fixture(scope="module")
def levels_colcon(levels, ros2_install):
    """``colcon build --base-paths src`` in OUT (colcon of
    requirements-ros2.txt; the packages' CMake fallback, the node packages
    finding k6_msgs's libraries in their own folders): OUT/install."""
    colcon = ros2_install.prefix / "bin" / "colcon"
    assert colcon.is_file(), f"{colcon}: no colcon; `make ros2-deps` installs it (requirements-ros2.txt)"
    env = {"PATH": f"{colcon.parent}:/usr/bin:/bin", "HOME": str(levels),
           "PYROSGEN_ROS2_PREFIX": str(ros2_install.prefix)}
    r = subprocess.run([str(colcon), "build", "--base-paths", "src"], cwd=levels, env=env, capture_output=True,
                       text=True, timeout=900)
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
    finished = sorted(line.split()[2] for line in r.stdout.splitlines() if line.startswith("Finished <<< "))
    assert finished == ["k6_msgs", "k6a", "k6b"], r.stdout[-3000:]
    yield levels / "install"
    for d in ("build", "install", "log"):
        shutil.rmtree(levels / d, ignore_errors=True)


@pytest.mark.parametrize("binaries", ["system_build", "colcon"])
def test_levels_run_on_dds(binaries, levels, ros2_install, tmp_path, shm_guard, request):
    """The two nodes started as the launch file says; the peer streams /src
    every 50 ms; once the chain has settled every /out is 4 X, which only a
    /mid delivered from k6a's build of k6_msgs to k6b's gives."""
    text = (levels / "levels.launch.xml").read_text()
    install = request.getfixturevalue("levels_colcon") if binaries == "colcon" else None
    procs = []
    try:
        start_launch(text, levels, install, tmp_path, procs)
        steps = [{"stream": {"/src": {"linear.x": bits(X)}}, "period": 0.05, "duration": 2.0},
                 {"stream": {"/src": {"linear.x": bits(X)}}, "period": 0.05, "duration": 1.5}]
        plan = {"publishers": {"/src": "geometry_msgs/Twist"}, "subscribers": {"/out": "geometry_msgs/Vector3"},
                "match_timeout": 30.0, "steps": steps}
        result = run_peer(plan, tmp_path, ros2_install, timeout=120)
        for name, p in procs:
            assert p.poll() is None, f"{name} exited"
    finally:
        statuses = [(name, stop(p, signal.SIGTERM)) for name, p in procs]
    assert [s for _, s in statuses] == [0, 0], statuses
    s = result["steps"][1]
    window = [lv["x"] for t, topic, lv in result["received"] if topic == "/out" and s["t0"] + 0.3 <= t <= s["t1"]]
    assert len(window) >= 10, window
    assert set(window) == {bits(4 * X)}, sorted(set(window))
    assert not (left := settled_leftovers()), left

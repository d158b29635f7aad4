"""The ament_cmake package ``build --ros2`` writes (README "ROS 2", DESIGN.md
section 5, "The ROS 2 package"): ``package.xml`` holds to format 3 (read by
catkin_pkg's parser, which implements REP 149, and element by element
here); the launch file is ROS 2's XML launch format with the arguments of
the ROS 1 launch file; and ``CMakeLists.txt``, configured and built with
plain ``cmake`` and ``make`` through its fallback branch against the wheels
(no ament_cmake here), makes a node that an rclpy peer talks to on a real
DDS, with the launch file's remapping, and that stops cleanly on SIGINT;
and ``colcon build --packages-select`` builds it in a workspace (colcon of
requirements-ros2.txt, in the ROS 2 prefix: ``make ros2-deps``)."""

from __future__ import annotations

import os
import shutil
import signal
import subprocess
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from pyrosgen.ros2.build import build_ros2

from support import expect
from support import ros as rosutil

from .conftest import run_peer, spawn, stop

NODE = PKG = "landshark_controller"
LEFT, RIGHT, GPS = "/landshark/left_wheel_velocity", "/landshark/right_wheel_velocity", "/landshark/gps_velocity"
BASE = "/landshark_control/base_velocity"
TS = "geometry_msgs/TwistStamped"


@pytest.fixture(scope="module")
def built(ros2_install, ros2_nodes):
    out = ros2_nodes / "landshark_package"
    return build_ros2(rosutil.LANDSHARK, rosutil.CONTROLLERS / "landshark_echo", out, install=ros2_install)


def test_package_xml_is_format_3_with_the_node_dependencies(built):
    from catkin_pkg.package import parse_package_string

    text = (built.out_dir / PKG / "package.xml").read_text()
    pkg = parse_package_string(text)  # catkin_pkg's REP 149 parser: raises on a violation
    pkg.validate()
    assert pkg.package_format == 3 and pkg.name == PKG
    assert [d.name for d in pkg.buildtool_depends] == ["ament_cmake"]
    want = {"rcl", "rcutils", "rmw", "rosidl_runtime_c", "rosgraph_msgs", "builtin_interfaces", "std_msgs",
            "geometry_msgs"}
    assert {d.name for d in pkg.build_depends} == want and {d.name for d in pkg.exec_depends} >= want
    assert [e.content for e in pkg.exports if e.tagname == "build_type"] == ["ament_cmake"]
    # REP 149's order: name, version, description, maintainer(s), license(s), then the rest
    root = ET.fromstring(text)
    assert root.tag == "package" and root.get("format") == "3"
    tags = [c.tag for c in root]
    assert tags[:5] == ["name", "version", "description", "maintainer", "license"], tags
    assert set(tags[5:]) <= {"buildtool_depend", "depend", "exec_depend", "export"}, tags


def test_launch_file_is_ros2_xml_with_sim_time_namespace_and_remaps(built):
    root = ET.fromstring((built.out_dir / PKG / "launch" / f"{NODE}.launch.xml").read_bytes())
    assert root.tag == "launch"
    args = {a.get("name"): a.get("default") for a in root.findall("arg")}
    topics = [LEFT, RIGHT, GPS, BASE]
    c_names = {t: t.strip("/").replace("/", "_") for t in topics}
    assert args == {"use_sim_time": "false", "ns": "/", **{f"topic_{c_names[t]}": t for t in topics}}
    (node,) = root.findall("node")
    # launch_ros's XML attributes of <node>
    assert node.attrib == {"pkg": PKG, "exec": NODE, "name": NODE, "namespace": "$(var ns)", "output": "screen",
                           "ros_args": "-p use_sim_time:=$(var use_sim_time)"}
    assert sorted((r.get("from"), r.get("to")) for r in node.findall("remap")) == sorted(
        (t, f"$(var topic_{c_names[t]})") for t in topics)
    assert [c.tag for c in node] == ["remap"] * 4


def _cmake(args, cwd, env=None):
    r = subprocess.run(args, cwd=cwd, capture_output=True, text=True, timeout=600, env=env)
    return r


def test_cmake_without_a_prefix_says_what_to_give(built, tmp_path):
    env = {k: v for k, v in os.environ.items() if k != "PYROSGEN_ROS2_PREFIX"}
    r = _cmake(["cmake", "-S", str(built.out_dir / PKG), "-B", str(tmp_path / "b")], tmp_path, env)
    assert r.returncode != 0
    said = " ".join(r.stderr.split())
    assert "-DPYROSGEN_ROS2_PREFIX=<prefix>" in said and "is not a ROS 2 installation of wheels" in said, r.stderr


def test_cmake_builds_the_package_and_the_node_talks_to_rclpy(built, ros2_install, tmp_path, shm_guard):
    """The package configured and built with cmake and make (the fallback
    branch, the wheels' prefix from the environment), installed; the
    installed node, run with the arguments the launch file passes (a
    remapped output, use_sim_time false), computes LandShark's base
    velocity for an rclpy peer, bit for bit, and ends with status 0 on
    SIGINT."""
    src, bld, inst = built.out_dir / PKG, tmp_path / "build", tmp_path / "install"
    env = {**os.environ, "PYROSGEN_ROS2_PREFIX": str(ros2_install.prefix)}
    r = _cmake(["cmake", "-S", str(src), "-B", str(bld), f"-DCMAKE_INSTALL_PREFIX={inst}"], tmp_path, env)
    assert r.returncode == 0, r.stdout + r.stderr
    assert "ament_cmake_DIR:PATH=ament_cmake_DIR-NOTFOUND" in (bld / "CMakeCache.txt").read_text()  # the fallback
    r = _cmake(["make", "-C", str(bld), "install"], tmp_path, env)
    assert r.returncode == 0, r.stdout + r.stderr
    # the layout check ran as a build step
    assert f"{NODE}_layout_check" in r.stdout
    binary = inst / "lib" / PKG / NODE
    assert binary.is_file() and (inst / "share" / PKG / "launch" / f"{NODE}.launch.xml").is_file()
    assert (inst / "share" / PKG / "package.xml").read_text() == (src / "package.xml").read_text()
    dyn = subprocess.run(["readelf", "-d", str(binary)], capture_output=True, text=True).stdout
    rpath = next(line for line in dyn.splitlines() if "(RPATH)" in line).split("[", 1)[1].rstrip("]")
    assert "(RUNPATH)" not in dyn and "libpython3" in dyn
    assert "" not in rpath.split(":") and str(ros2_install.lib_dir) in rpath.split(":"), rpath
    assert all(str(p) in rpath.split(":") for p in ros2_install.library_path())

    remapped = "/package_test/base_velocity"
    node = spawn([binary, "--ros-args", "-r", "__ns:=/", "-p", "use_sim_time:=false", "-r", f"{BASE}:={remapped}"],
                 tmp_path / "node.log")
    v = {LEFT: 0x400921FB54442D18, RIGHT: 0x3FF8000000000000, GPS: 0xC000000000000000}
    want = expect.landshark_echo({"In1": v[LEFT], "In2": v[RIGHT], "In3": v[GPS]})["Out1"]
    try:
        result = run_peer({"publishers": {t: TS for t in (LEFT, RIGHT, GPS)}, "subscribers": {remapped: TS},
                           "match_timeout": 20.0,
                           "steps": [{"sleep": 0.3}, {"publish": {t: {"twist.linear.x": v[t]} for t in v}},
                                     {"sleep": 0.8}]}, tmp_path, ros2_install)
    finally:
        status = stop(node, signal.SIGINT)
    log = (tmp_path / "node.log").read_text(errors="replace")
    assert status == 0, f"exit status {status} after SIGINT:\n{log[-2000:]}"
    t_pub = result["steps"][1]["t1"]
    after = [lv["twist.linear.x"] for t, topic, lv in result["received"] if topic == remapped and t > t_pub + 0.3]
    assert after and all(x == want for x in after), (len(after), after[:5], want)


def _colcon(install) -> Path:
    """colcon of requirements-ros2.txt, installed by ``make ros2-deps`` in
    the ROS 2 prefix (``PYROSGEN_TEST_COLCON`` names another one)."""
    colcon = Path(os.environ.get("PYROSGEN_TEST_COLCON") or install.prefix / "bin" / "colcon")
    assert colcon.is_file(), f"{colcon}: no colcon; `make ros2-deps` installs it (requirements-ros2.txt)"
    return colcon


def test_colcon_builds_the_package_in_a_workspace(built, ros2_install, tmp_path, shm_guard):
    """A workspace with the package under ``src/``: ``colcon build
    --packages-select`` (no ament_cmake here: colcon runs the package's
    CMake, whose fallback branch finds the wheels from
    PYROSGEN_ROS2_PREFIX) builds it, runs the layout check and installs
    the node, the launch file and package.xml; the installed node answers
    an rclpy peer bit for bit and ends with status 0 on SIGTERM."""
    colcon = _colcon(ros2_install)
    ws = tmp_path / "ws"
    shutil.copytree(built.out_dir / PKG, ws / "src" / PKG)
    env = {"PATH": f"{colcon.parent}:/usr/bin:/bin", "HOME": str(tmp_path),
           "PYROSGEN_ROS2_PREFIX": str(ros2_install.prefix)}
    r = subprocess.run([str(colcon), "build", "--packages-select", PKG], cwd=ws, env=env, capture_output=True,
                       text=True, timeout=600)
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
    assert f"Finished <<< {PKG}" in r.stdout and "Failed" not in r.stdout, r.stdout[-3000:]
    assert f"Built target {NODE}_layout_check" in r.stdout, r.stdout[-3000:]
    assert "ament_cmake_DIR:PATH=ament_cmake_DIR-NOTFOUND" in (ws / "build" / PKG / "CMakeCache.txt").read_text()
    prefix = ws / "install" / PKG
    binary = prefix / "lib" / PKG / NODE
    assert binary.is_file() and (prefix / "share" / PKG / "launch" / f"{NODE}.launch.xml").is_file()
    assert (prefix / "share" / PKG / "package.xml").read_text() == (ws / "src" / PKG / "package.xml").read_text()
    node = spawn([binary], tmp_path / "node.log")
    v = {LEFT: 0x3FF0000000000001, RIGHT: 0x7FF8000000000123, GPS: 0x8000000000000000}
    want = expect.landshark_echo({"In1": v[LEFT], "In2": v[RIGHT], "In3": v[GPS]})["Out1"]
    try:
        result = run_peer({"publishers": {t: TS for t in (LEFT, RIGHT, GPS)}, "subscribers": {BASE: TS},
                           "match_timeout": 20.0,
                           "steps": [{"sleep": 0.3}, {"publish": {t: {"twist.linear.x": v[t]} for t in v}},
                                     {"sleep": 0.8}]}, tmp_path, ros2_install)
    finally:
        status = stop(node, signal.SIGTERM)
    assert status == 0, (tmp_path / "node.log").read_text(errors="replace")[-2000:]
    t_pub = result["steps"][1]["t1"]
    after = [lv["twist.linear.x"] for t, topic, lv in result["received"] if topic == BASE and t > t_pub + 0.3]
    assert len(after) >= 10 and all(x == want for x in after), (len(after), after[:5], want)

"""The catkin packages written by ``pyrosgen build`` for examples/multi:
``OUT/multi_node/`` (sources only) and ``OUT/robot_msgs/`` (its custom
messages, built by message_generation). ``catkin_make`` in a fresh
workspace builds them; ``rosrun`` and ``roslaunch`` start the node on a
private master, and it publishes what the node ``pyrosgen build`` linked
publishes; the layout check is a build step that stops a mismatching
controller header."""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

from pyrosgen.ros.rosmaster import stop_process

NODE = "multi_node"


def _workspace(multi_echo: Path, ws: Path) -> Path:
    (ws / "src").mkdir(parents=True)
    for pkg in (NODE, "robot_msgs"):
        shutil.copytree(multi_echo / pkg, ws / "src" / pkg)
    return ws


def _catkin_make(ws: Path) -> subprocess.CompletedProcess:
    return subprocess.run(["catkin_make", "-C", str(ws), "-DPYTHON_EXECUTABLE=/usr/bin/python3"],
                          capture_output=True, text=True, stdin=subprocess.DEVNULL, timeout=900)


def _in_ws(ws: Path, command: str) -> list[str]:
    return ["bash", "-c", f"source {ws}/devel/setup.bash && exec {command}"]


def _echo_one(ros, ws: Path, topic: str) -> str:
    r = subprocess.run(_in_ws(ws, f"rostopic echo -n 1 {topic}"), env=ros.env, capture_output=True, text=True,
                       stdin=subprocess.DEVNULL, timeout=60)
    assert r.returncode == 0, r.stderr
    return r.stdout


def test_catkin_make_rosrun_roslaunch(ros, multi_echo, tmp_path):
    assert not list((multi_echo / NODE).rglob("*.o")) and not (multi_echo / NODE / "bin").exists()
    assert "message_generation" in (multi_echo / "robot_msgs" / "package.xml").read_text()
    ws = _workspace(multi_echo, tmp_path / "ws")
    r = _catkin_make(ws)
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
    assert f"Built target {NODE}_layout_check" in r.stdout
    assert (ws / "devel" / "lib" / NODE / NODE).is_file()
    assert (ws / "devel" / "include" / "robot_msgs" / "FusionStatus.h").is_file()

    # the node pyrosgen linked: what it publishes before any input
    ref = ros.spawn([str(multi_echo / "bin" / NODE)], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    expected = {t: _echo_one(ros, ws, t) for t in ("/cmd_vel", "/fusion/status")}
    stop_process(ref)
    assert "wheel_speeds" in expected["/fusion/status"]

    for how in (f"rosrun {NODE} {NODE}", f"roslaunch {NODE} {NODE}.launch"):
        p = ros.spawn(_in_ws(ws, how), stdout=open(tmp_path / "node.log", "ab"), stderr=subprocess.STDOUT)
        try:
            for topic, text in expected.items():
                assert _echo_one(ros, ws, topic) == text, (how, topic)
        finally:
            stop_process(p)
    # the launch file's arguments: a namespace for the node, a topic remapped
    how = f"roslaunch {NODE} {NODE}.launch ns:=robot1 topic_cmd_vel:=/robot1/cmd_vel"
    p = ros.spawn(_in_ws(ws, how), stdout=open(tmp_path / "node.log", "ab"), stderr=subprocess.STDOUT)
    try:
        assert _echo_one(ros, ws, "/robot1/cmd_vel") == expected["/cmd_vel"]
        assert _echo_one(ros, ws, "/fusion/status") == expected["/fusion/status"]  # absolute: not moved
        r = subprocess.run(_in_ws(ws, "rosnode list"), env=ros.env, capture_output=True, text=True,
                           stdin=subprocess.DEVNULL, timeout=60)
        assert f"/robot1/{NODE}" in r.stdout.split(), r.stdout
    finally:
        stop_process(p)


def test_layout_check_is_a_build_step(multi_echo, tmp_path):
    ws = _workspace(multi_echo, tmp_path / "ws")
    header = ws / "src" / NODE / "controller" / "Fusion.h"
    text = header.read_text()
    assert "  real_T X;" in text
    header.write_text(text.replace("  real_T X;", "  real32_T X;"))
    r = _catkin_make(ws)
    assert r.returncode != 0
    assert "layout_check" in r.stdout + r.stderr and "static assertion failed" in r.stdout + r.stderr
    assert not (ws / "devel" / "lib" / NODE / NODE).exists()

"""The ROS tools a user watches a node with (installed by ``make deps``):
``rostopic echo`` and ``rostopic hz`` see the built node's output, and a
remapping on the node's command line (``topic:=other``) moves it."""

from __future__ import annotations

import subprocess

from pyrosgen.ros.rosmaster import stop_process

from support.ros import start_node

OUT_TOPIC = "/landshark_control/base_velocity"


def _echo_one(ros, topic: str) -> str:
    r = subprocess.run(["rostopic", "echo", "-n", "1", topic], env=ros.env, capture_output=True, text=True,
                       stdin=subprocess.DEVNULL, timeout=60)
    assert r.returncode == 0, r.stderr
    return r.stdout


def test_rostopic_sees_the_node(ros, landshark_real, tmp_path):
    start_node(ros, landshark_real / "bin" / "landshark_controller", tmp_path / "node.log")
    text = _echo_one(ros, OUT_TOPIC)
    # one TwistStamped: the controller's command in twist.linear.x, every other field zero
    assert "twist:" in text and "linear:" in text and "frame_id: ''" in text
    listed = subprocess.run(["rostopic", "list"], env=ros.env, capture_output=True, text=True, timeout=60).stdout
    assert OUT_TOPIC in listed.split() and "/landshark/gps_velocity" in listed.split()
    info = subprocess.run(["rostopic", "info", OUT_TOPIC], env=ros.env, capture_output=True, text=True, timeout=60).stdout
    assert "Type: geometry_msgs/TwistStamped" in info and "/landshark_controller" in info
    hz = ros.spawn(["rostopic", "hz", OUT_TOPIC], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    try:
        for line in hz.stdout:
            if "average rate:" in line:
                assert float(line.split(":")[1]) > 0
                break
        else:
            raise AssertionError("rostopic hz printed no rate")
    finally:
        stop_process(hz)


def test_remapping_on_the_command_line(ros, landshark_real, tmp_path):
    ros.spawn([str(landshark_real / "bin" / "landshark_controller"), f"{OUT_TOPIC}:=/robot/cmd"],
              stdout=open(tmp_path / "node.log", "ab"), stderr=subprocess.STDOUT)
    text = _echo_one(ros, "/robot/cmd")
    assert "twist:" in text
    listed = subprocess.run(["rostopic", "list"], env=ros.env, capture_output=True, text=True, timeout=60).stdout
    assert OUT_TOPIC not in listed.split()



#!/usr/bin/python3
"""The simulated LandShark of ``make demo`` (run by Debian's /usr/bin/python3,
which has rospy): the robot of ``demo_robot.py`` (first-order dynamics, two
wheel encoders and a GPS spoofed for part of the run) over rospy.

    /usr/bin/python3 demo_sim.py [--duration S] [--spoof FROM:TO] [--rows-per-s N]

Prints a live table (time, left, right, GPS, commanded velocity, true
speed), then a summary; exits 0 if the commanded velocity stayed sane while
the GPS was spoofed (the median of the three readings rejected it), 1 if
not, 2 if the node could not be reached.  Standalone: it does not import
pyrosgen (``demo_robot.py``, next to it, is loaded by its path).
"""

import importlib.util
import sys
import time
from pathlib import Path

import rospy
from geometry_msgs.msg import TwistStamped


def _robot():
    path = Path(__file__).resolve().parent / "demo_robot.py"
    spec = importlib.util.spec_from_file_location("demo_robot", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def main() -> int:
    robot = _robot()
    args = robot.parse_args(__doc__)
    rospy.init_node("landshark_sim", anonymous=True, disable_signals=True)
    pubs = {t: rospy.Publisher(t, TwistStamped, queue_size=1) for t in (robot.LEFT, robot.RIGHT, robot.GPS)}
    command = robot.Command()
    rospy.Subscriber(robot.CMD, TwistStamped, lambda msg: command.heard(msg.twist.linear.x), queue_size=1)

    def publish(topic: str, value: float) -> None:
        m = TwistStamped()
        m.header.stamp = rospy.Time.now()
        m.twist.linear.x = value
        pubs[topic].publish(m)

    try:
        if not robot.connect(command, lambda: all(p.get_num_connections() > 0 for p in pubs.values()), time.sleep):
            return 2
        return robot.drive(args, command, publish, time.sleep)
    finally:
        rospy.signal_shutdown("done")


if __name__ == "__main__":
    sys.exit(main())

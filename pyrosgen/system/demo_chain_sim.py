#!/usr/bin/python3
"""The sensors of ``make demo``'s system part (run by Debian's
/usr/bin/python3, which has rospy): a laser scanner and a joystick drive
the three-node chain of examples/system_chain (laser guard -> velocity
mux -> differential-drive base), and the wheel speeds are read on
/base/wheels.

    /usr/bin/python3 demo_chain_sim.py [--phase S]

The phases, the live table and the verdicts are ``chain_phases.py``'s
(shared with the rclpy sensors); exits 0 if every phase ends at its
expected speeds, 1 if not, 2 if the chain could not be reached.
Standalone: it does not import pyrosgen.
"""

import sys
import threading
import time

import rospy
from geometry_msgs.msg import Twist, Vector3
from sensor_msgs.msg import LaserScan

from chain_phases import N, drive, phase_seconds


def main() -> int:
    phase = phase_seconds()
    rospy.init_node("chain_sensors", anonymous=True, disable_signals=True)
    scan_pub = rospy.Publisher("/scan", LaserScan, queue_size=1)
    teleop_pub = rospy.Publisher("/teleop/cmd_vel", Twist, queue_size=1)
    lock = threading.Lock()
    last = {"w": None}

    def on_wheels(m):
        with lock:
            last["w"] = (m.x, m.y)

    def latest():
        with lock:
            return last["w"]

    def publish_scan(r):
        s = LaserScan()
        s.ranges = [r] * N
        scan_pub.publish(s)

    def publish_teleop(vx, wz):
        t = Twist()
        t.linear.x, t.angular.z = vx, wz
        teleop_pub.publish(t)

    rospy.Subscriber("/base/wheels", Vector3, on_wheels, queue_size=100)
    return drive(lambda: bool(scan_pub.get_num_connections() and teleop_pub.get_num_connections()
                              and latest() is not None),
                 publish_scan, publish_teleop, time.sleep, latest, phase)


if __name__ == "__main__":
    sys.exit(main())

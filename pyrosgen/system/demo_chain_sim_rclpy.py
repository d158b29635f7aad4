"""The sensors of ``make demo ROS=2``'s system part (run by the ROS 2
installation's interpreter, which has rclpy): a laser scanner and a
joystick drive the three-node chain of examples/system_chain, built for
ROS 2 (laser guard -> velocity mux -> differential-drive base), and the
wheel speeds are read on /base/wheels; the ROS 2 twin of
``demo_chain_sim.py`` (the same phases, table and verdicts:
``chain_phases.py``).

    .venv-ros2/bin/python demo_chain_sim_rclpy.py [--phase S]

Exits 0 if every phase ends at the speeds the chain's controllers
compute, 1 if not, 2 if the chain could not be reached within 30 s.
Standalone: it does not import pyrosgen.
"""

import sys
import time

import rclpy
from geometry_msgs.msg import Twist, Vector3
from sensor_msgs.msg import LaserScan

from chain_phases import N, drive, phase_seconds


def main() -> int:
    phase = phase_seconds()
    rclpy.init()
    node = rclpy.create_node("chain_sensors")
    scan_pub = node.create_publisher(LaserScan, "/scan", 10)
    teleop_pub = node.create_publisher(Twist, "/teleop/cmd_vel", 10)
    last = {"w": None}

    def on_wheels(m):
        last["w"] = (m.x, m.y)

    def spin_for(s):
        end = time.monotonic() + s
        while time.monotonic() < end:
            rclpy.spin_once(node, timeout_sec=max(0.0, min(0.01, end - time.monotonic())))

    def publish_scan(r):
        s = LaserScan()
        s.ranges = [r] * N
        scan_pub.publish(s)

    def publish_teleop(vx, wz):
        t = Twist()
        t.linear.x, t.angular.z = vx, wz
        teleop_pub.publish(t)

    node.create_subscription(Vector3, "/base/wheels", on_wheels, 10)
    try:
        return drive(lambda: bool(scan_pub.get_subscription_count() and teleop_pub.get_subscription_count()
                                  and last["w"] is not None),
                     publish_scan, publish_teleop, spin_for, lambda: last["w"], phase)
    finally:
        node.destroy_node()
        rclpy.shutdown()


if __name__ == "__main__":
    sys.exit(main())

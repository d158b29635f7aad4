"""The simulated LandShark of ``make demo-ros2`` (run by the ROS 2
installation's interpreter, ``.venv-ros2/bin/python``, which has rclpy, in the
environment of :func:`pyrosgen.ros2.env.ros2_env`): the robot of
``pyrosgen/ros/demo_robot.py`` (the ROS 1 demo's: first-order dynamics, two
wheel encoders and a GPS spoofed for part of the run) over rclpy.

    .venv-ros2/bin/python demo_sim.py [--duration S] [--spoof FROM:TO] [--rows-per-s N]

Prints a live table (time, left, right, GPS, commanded velocity, true
speed), then a summary; exits 0 if the commanded velocity stayed sane while
the GPS was spoofed (the median of the three readings rejected it), 1 if
not, 2 if the node could not be reached.  Standalone: it does not import
pyrosgen (``demo_robot.py`` is loaded by its path).
"""

import importlib.util
import sys
import time
from pathlib import Path

import rclpy
from geometry_msgs.msg import TwistStamped


def _robot():
    path = Path(__file__).resolve().parent.parent / "ros" / "demo_robot.py"
    spec = importlib.util.spec_from_file_location("demo_robot", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def main() -> int:
    robot = _robot()
    args = robot.parse_args(__doc__)
    rclpy.init()
    node = rclpy.create_node("landshark_sim")
    pubs = {t: node.create_publisher(TwistStamped, t, 1) for t in (robot.LEFT, robot.RIGHT, robot.GPS)}
    command = robot.Command()
    node.create_subscription(TwistStamped, robot.CMD, lambda msg: command.heard(msg.twist.linear.x), 1)

    def pump(seconds: float) -> None:
        """Run the node's callbacks for ``seconds`` (one thread: no executor
        thread to stop at the end)."""
        end = time.monotonic() + seconds
        while True:
            left = end - time.monotonic()
            rclpy.spin_once(node, timeout_sec=max(0.0, left))
            if left <= 0:
                return

    def publish(topic: str, value: float) -> None:
        m = TwistStamped()
        m.header.stamp = node.get_clock().now().to_msg()
        m.twist.linear.x = value
        pubs[topic].publish(m)

    try:
        if not robot.connect(command, lambda: all(p.get_subscription_count() > 0 for p in pubs.values()), pump):
            return 2
        return robot.drive(args, command, publish, pump)
    finally:
        node.destroy_node()
        rclpy.shutdown()


if __name__ == "__main__":
    sys.exit(main())

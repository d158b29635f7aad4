"""The sensors of ``make demo ROS=2``'s system part (run by the ROS 2
installation's interpreter, which has rclpy): a laser scanner and a
joystick drive the three-node chain of examples/system_chain, built for
ROS 2 (laser guard -> velocity mux -> differential-drive base), and the
wheel speeds are read on /base/wheels; the ROS 2 twin of
``demo_chain_sim.py`` (the same phases, table and verdicts).

    .venv-ros2/bin/python demo_chain_sim_rclpy.py [--phase S]

Exits 0 if every phase ends at the speeds the chain's controllers
compute, 1 if not, 2 if the chain could not be reached within 30 s.
Standalone: it does not import pyrosgen.
"""

import argparse
import sys
import time

import rclpy
from geometry_msgs.msg import Twist, Vector3
from sensor_msgs.msg import LaserScan

N = 1081


def wheels(vx, wz):
    turn = wz * 0.25
    return (min(max(vx - turn, -1.0), 1.0), min(max(vx + turn, -1.0), 1.0))


PHASES = [("clear scan", 5.0, None, wheels(0.5, 0.0)),
          ("obstacle 0.5 m", 0.5, None, wheels(0.0, 0.0)),
          ("teleop 0.2 m/s, 1 rad/s", 0.5, (0.2, 1.0), wheels(0.2, 1.0))]


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--phase", type=float, default=2.0)
    args = ap.parse_args()
    rclpy.init()
    node = rclpy.create_node("chain_sensors")
    scan_pub = node.create_publisher(LaserScan, "/scan", 10)
    teleop_pub = node.create_publisher(Twist, "/teleop/cmd_vel", 10)
    last = {"w": None}

    def on_wheels(m):
        last["w"] = (m.x, m.y)

    node.create_subscription(Vector3, "/base/wheels", on_wheels, 10)

    def spin_for(s):
        end = time.monotonic() + s
        while time.monotonic() < end:
            rclpy.spin_once(node, timeout_sec=max(0.0, min(0.01, end - time.monotonic())))

    try:
        t0 = time.monotonic()
        while time.monotonic() - t0 < 30:
            if scan_pub.get_subscription_count() and teleop_pub.get_subscription_count() and last["w"] is not None:
                break
            spin_for(0.05)
        else:
            print("sim: error: the chain did not connect within 30 s", flush=True)
            return 2
        print(f"{'t (s)':>6}  {'phase':<26} {'left':>8} {'right':>8}", flush=True)
        ok = True
        start = time.monotonic()
        for name, rng, tele, expected in PHASES:
            p0 = time.monotonic()
            k = 0
            seen = set()
            while time.monotonic() - p0 < args.phase:
                if k % 2 == 0:
                    s = LaserScan()
                    s.ranges = [rng] * N
                    scan_pub.publish(s)
                if tele is not None:
                    t = Twist()
                    t.linear.x, t.angular.z = tele
                    teleop_pub.publish(t)
                spin_for(0.05)
                k += 1
                w = last["w"]
                if time.monotonic() - p0 > args.phase / 2 and w is not None:
                    seen.add(w)
                if k % 5 == 0 and w is not None:
                    print(f"{time.monotonic() - start:6.2f}  {name:<26} {w[0]:8.3f} {w[1]:8.3f}", flush=True)
            good = seen == {expected}
            ok = ok and good
            print(f"sim: {name}: wheels {sorted(seen)} once settled; the controllers compute {expected}: "
                  f"{'OK' if good else 'WRONG'}", flush=True)
        print("sim: OK: the chain computed every phase's wheel speeds" if ok else "sim: FAILED", flush=True)
        return 0 if ok else 1
    finally:
        node.destroy_node()
        rclpy.shutdown()


if __name__ == "__main__":
    sys.exit(main())

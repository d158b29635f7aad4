"""The simulated LandShark of ``make demo-ros2`` (run by the ROS 2
installation's interpreter, ``.venv-ros2/bin/python``, which has rclpy, in the
environment of :func:`pyrosgen.ros2.env.ros2_env`): the robot of
``pyrosgen/ros/demo_sim.py`` over rclpy: a robot whose speed follows the commanded velocity with
first-order dynamics, two wheel encoders and a GPS, the GPS spoofed (it reports
three times the true speed) for part of the run.

    .venv-ros2/bin/python demo_sim.py [--duration S] [--spoof FROM:TO] [--rows-per-s N]

Prints a live table (time, left, right, GPS, commanded velocity, true
speed), then a summary; exits 0 if the commanded velocity stayed sane while
the GPS was spoofed (the median of the three readings rejected it), 1 if
not, 2 if the node could not be reached.  Standalone: it does not import
pyrosgen.
"""

import argparse
import random
import sys
import threading
import time

import rclpy
from geometry_msgs.msg import TwistStamped

LEFT = "/landshark/left_wheel_velocity"
RIGHT = "/landshark/right_wheel_velocity"
GPS = "/landshark/gps_velocity"
CMD = "/landshark_control/base_velocity"

TAU = 0.3          # s, time constant of the robot's speed
RATE = 50.0        # Hz, sensor rate (the node's rate)
NOISE = 0.01       # m/s, encoder noise amplitude
SETPOINT = 1.0     # m/s, the controller's cruise speed (Controller.h)
SANE = (0.85, 1.15)  # m/s, what the true speed must stay within while spoofed


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--duration", type=float, default=12.0)
    ap.add_argument("--spoof", default="5:10", help="spoofing window FROM:TO in seconds")
    ap.add_argument("--rows-per-s", type=float, default=2.0)
    args = ap.parse_args()
    spoof_from, spoof_to = (float(x) for x in args.spoof.split(":"))

    rclpy.init()
    node = rclpy.create_node("landshark_sim")
    pubs = {t: node.create_publisher(TwistStamped, t, 1) for t in (LEFT, RIGHT, GPS)}
    lock = threading.Lock()
    last = {"cmd": None, "n": 0}

    def on_cmd(msg):
        with lock:
            last["cmd"] = msg.twist.linear.x
            last["n"] += 1

    node.create_subscription(TwistStamped, CMD, on_cmd, 1)

    def pump(seconds: float) -> None:
        """Run the node's callbacks for ``seconds`` (one thread: no executor
        thread to stop at the end)."""
        end = time.monotonic() + seconds
        while True:
            left = end - time.monotonic()
            rclpy.spin_once(node, timeout_sec=max(0.0, left))
            if left <= 0:
                return
    deadline = time.monotonic() + 30.0
    while time.monotonic() < deadline:
        with lock:
            heard = last["n"] > 0
        if heard and all(p.get_subscription_count() > 0 for p in pubs.values()):
            break
        pump(0.05)
    else:
        print("sim: the node did not connect within 30 s", flush=True)
        _shutdown(node)
        return 2

    rng = random.Random(42)
    v = 0.0                       # true speed, m/s
    rows = []
    print(f"sim: robot at rest; cruise set point {SETPOINT} m/s; GPS spoofed (x3) "
          f"from {spoof_from:g} s to {spoof_to:g} s", flush=True)
    print(f"{'time':>6} {'left':>7} {'right':>7} {'gps':>7} {'':8} {'command':>8} {'speed':>7}", flush=True)
    t0 = time.monotonic()
    prev = t0
    next_row = 0.0
    k = 0
    while True:
        now = time.monotonic()
        t = now - t0
        if t >= args.duration:
            break
        with lock:
            cmd = last["cmd"]
        v += (cmd - v) * min(1.0, (now - prev) / TAU)
        prev = now
        left = v + rng.uniform(-NOISE, NOISE)
        right = v + rng.uniform(-NOISE, NOISE)
        spoofed = spoof_from <= t < spoof_to
        gps = 3.0 * v if spoofed else v + rng.uniform(-NOISE, NOISE)
        for topic, value in ((LEFT, left), (RIGHT, right), (GPS, gps)):
            m = TwistStamped()
            m.header.stamp = node.get_clock().now().to_msg()
            m.twist.linear.x = value
            pubs[topic].publish(m)
        rows.append((t, left, right, gps, spoofed, cmd, v))
        if t >= next_row:
            print(f"{t:6.2f} {left:7.3f} {right:7.3f} {gps:7.3f} {'SPOOFED' if spoofed else '':8} "
                  f"{cmd:8.3f} {v:7.3f}", flush=True)
            next_row += 1.0 / args.rows_per_s
        k += 1
        wait = t0 + k / RATE - time.monotonic()
        if wait > 0:
            pump(wait)

    settled = [r for r in rows if spoof_from + 0.5 <= r[0] < spoof_to]
    if not settled:
        print("sim: no sample in the spoofing window", flush=True)
        _shutdown(node)
        return 1
    speeds = [r[6] for r in settled]
    cmds = [r[5] for r in settled]
    mean_est = sum((r[1] + r[2] + r[3]) / 3 for r in settled) / len(settled)
    gps_est = sum(r[3] for r in settled) / len(settled)
    ok = SANE[0] <= min(speeds) and max(speeds) <= SANE[1]
    print(f"sim: while the GPS was spoofed it read {gps_est:.2f} m/s on average; the mean of the "
          f"three readings would have been {mean_est:.2f} m/s", flush=True)
    print(f"sim: the median kept the command in [{min(cmds):.3f}, {max(cmds):.3f}] m/s and the "
          f"speed in [{min(speeds):.3f}, {max(speeds):.3f}] m/s (sane: {SANE[0]}-{SANE[1]})", flush=True)
    print("sim: " + ("OK: the spoofed GPS was rejected" if ok else "FAILED: the spoofed GPS moved the command"),
          flush=True)
    _shutdown(node)
    return 0 if ok else 1


def _shutdown(node) -> None:
    node.destroy_node()
    rclpy.shutdown()


if __name__ == "__main__":
    sys.exit(main())

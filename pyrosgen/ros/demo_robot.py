"""The simulated LandShark of ``make demo`` and ``make demo-ros2``, without
its ROS client library: a robot whose speed follows the commanded velocity
with first-order dynamics, two wheel encoders and a GPS, the GPS spoofed
(it reports three times the true speed) for part of the run; the live
table, the summary and the verdict.  ``pyrosgen/ros/demo_sim.py`` runs it
over rospy (Debian's /usr/bin/python3), ``pyrosgen/ros2/demo_sim.py`` over
rclpy (the ROS 2 installation's interpreter); both load this file by its
path and give it the transport (publish a reading, wait, the last
command).  The standard library only: neither interpreter imports
pyrosgen.
"""

import argparse
import random
import threading
import time

LEFT = "/landshark/left_wheel_velocity"
RIGHT = "/landshark/right_wheel_velocity"
GPS = "/landshark/gps_velocity"
CMD = "/landshark_control/base_velocity"

TAU = 0.3          # s, time constant of the robot's speed
RATE = 50.0        # Hz, sensor rate (the node's rate)
NOISE = 0.01       # m/s, encoder noise amplitude
SETPOINT = 1.0     # m/s, the controller's cruise speed (Controller.h)
SANE = (0.85, 1.15)  # m/s, what the true speed must stay within while spoofed
CONNECT_S = 30.0   # s, how long to wait for the node


def parse_args(doc: str) -> argparse.Namespace:
    """``--duration S``, ``--spoof FROM:TO``, ``--rows-per-s N``
    (``spoof_from``, ``spoof_to`` in seconds)."""
    ap = argparse.ArgumentParser(description=doc.splitlines()[0])
    ap.add_argument("--duration", type=float, default=12.0)
    ap.add_argument("--spoof", default="5:10", help="spoofing window FROM:TO in seconds")
    ap.add_argument("--rows-per-s", type=float, default=2.0)
    args = ap.parse_args()
    args.spoof_from, args.spoof_to = (float(x) for x in args.spoof.split(":"))
    return args


class Command:
    """The last commanded velocity the node published, and how many."""

    def __init__(self):
        self._lock = threading.Lock()
        self.value = None
        self.count = 0

    def heard(self, value: float) -> None:
        with self._lock:
            self.value = value
            self.count += 1

    def last(self):
        with self._lock:
            return self.value, self.count


def connect(command: Command, matched, wait) -> bool:
    """Wait until the node publishes and every sensor topic is matched
    (``matched()``), ``wait(s)`` at a time, at most :data:`CONNECT_S`."""
    deadline = time.monotonic() + CONNECT_S
    while time.monotonic() < deadline:
        if command.last()[1] > 0 and matched():
            return True
        wait(0.05)
    print(f"sim: the node did not connect within {CONNECT_S:g} s", flush=True)
    return False


def drive(args: argparse.Namespace, command: Command, publish, wait) -> int:
    """The run: ``publish(topic, value)`` each reading at :data:`RATE`,
    ``wait(s)`` in between; the table, then the summary; 0 if the true
    speed stayed sane while the GPS was spoofed, else 1."""
    rng = random.Random(42)
    v = 0.0                       # true speed, m/s
    rows = []
    print(f"sim: robot at rest; cruise set point {SETPOINT} m/s; GPS spoofed (x3) "
          f"from {args.spoof_from:g} s to {args.spoof_to:g} s", flush=True)
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
        cmd = command.last()[0]
        v += (cmd - v) * min(1.0, (now - prev) / TAU)
        prev = now
        left = v + rng.uniform(-NOISE, NOISE)
        right = v + rng.uniform(-NOISE, NOISE)
        spoofed = args.spoof_from <= t < args.spoof_to
        gps = 3.0 * v if spoofed else v + rng.uniform(-NOISE, NOISE)
        for topic, value in ((LEFT, left), (RIGHT, right), (GPS, gps)):
            publish(topic, value)
        rows.append((t, left, right, gps, spoofed, cmd, v))
        if t >= next_row:
            print(f"{t:6.2f} {left:7.3f} {right:7.3f} {gps:7.3f} {'SPOOFED' if spoofed else '':8} "
                  f"{cmd:8.3f} {v:7.3f}", flush=True)
            next_row += 1.0 / args.rows_per_s
        k += 1
        pause = t0 + k / RATE - time.monotonic()
        if pause > 0:
            wait(pause)
    return summary(args, rows)


def summary(args: argparse.Namespace, rows: list) -> int:
    settled = [r for r in rows if args.spoof_from + 0.5 <= r[0] < args.spoof_to]
    if not settled:
        print("sim: no sample in the spoofing window", flush=True)
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
    return 0 if ok else 1

#!/usr/bin/python3
"""The sensors of ``make demo``'s system part (run by Debian's
/usr/bin/python3, which has rospy): a laser scanner and a joystick drive
the three-node chain of examples/system_chain (laser guard -> velocity
mux -> differential-drive base), and the wheel speeds are read on
/base/wheels.

    /usr/bin/python3 demo_chain_sim.py [--phase S]

Phases of ``--phase`` seconds each: a clear scan (5 m everywhere), an
obstacle at 0.5 m, then a teleop command (0.2 m/s, 1 rad/s) with the
obstacle still there.  Scans at 10 Hz, teleop at 20 Hz.  Prints a live
table (time, phase, the wheel speeds) and, per phase, the speeds seen once
it settled against the ones the chain's controllers compute; exits 0 if
every phase ends at its expected speeds, 1 if not, 2 if the chain could
not be reached.  Standalone: it does not import pyrosgen.
"""

import argparse
import sys
import threading
import time

import rospy
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
    rospy.init_node("chain_sensors", anonymous=True, disable_signals=True)
    scan_pub = rospy.Publisher("/scan", LaserScan, queue_size=1)
    teleop_pub = rospy.Publisher("/teleop/cmd_vel", Twist, queue_size=1)
    lock = threading.Lock()
    last = {"w": None}

    def on_wheels(m):
        with lock:
            last["w"] = (m.x, m.y)

    rospy.Subscriber("/base/wheels", Vector3, on_wheels, queue_size=100)
    t0 = time.monotonic()
    while time.monotonic() - t0 < 30:
        if scan_pub.get_num_connections() and teleop_pub.get_num_connections() and last["w"] is not None:
            break
        time.sleep(0.05)
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
            time.sleep(0.05)
            k += 1
            with lock:
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


if __name__ == "__main__":
    sys.exit(main())

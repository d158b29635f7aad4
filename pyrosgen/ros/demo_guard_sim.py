#!/usr/bin/python3
"""The command sources of ``make demo``'s second part (run by Debian's
/usr/bin/python3, which has rospy): a teleoperation joystick and a
navigation stack drive the velocity guard (examples/velocity_guard), then
fall silent one after the other.

    /usr/bin/python3 demo_guard_sim.py [--teleop-stop S] [--nav-stop S] [--duration S] [--rows-per-s N]

Both publish at 50 Hz: teleop linear.x 1.0, angular.z 0.1; nav 2.0, 0.2.
Teleop stops at ``--teleop-stop`` (a crashed joystick driver), nav at
``--nav-stop`` (a hung planner).  Prints a live table (time, which source
publishes, the command the node publishes) and each change of the
command with how long after the source's last message it came; then a
summary.  Exits 0 if the guard followed teleop, then nav not before 500 ms
after teleop's last message, then zero not before 500 ms after nav's; 1
if not; 2 if the node could not be reached.  Standalone: it does not
import pyrosgen.
"""

import argparse
import sys
import threading
import time

import rospy
from geometry_msgs.msg import Twist

TELEOP = "/teleop/cmd_vel"
NAV = "/nav/cmd_vel"
OUT = "/cmd_vel"
RATE = 50.0              # Hz
TIMEOUT = 0.5            # s, the model's timeout_ms
TELEOP_CMD = (1.0, 0.1)
NAV_CMD = (2.0, 0.2)
ZERO = (0.0, 0.0)
NAMES = {TELEOP_CMD: "teleop's", NAV_CMD: "nav's", ZERO: "zero"}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--teleop-stop", type=float, default=2.0)
    ap.add_argument("--nav-stop", type=float, default=4.0)
    ap.add_argument("--duration", type=float, default=5.0)
    ap.add_argument("--rows-per-s", type=float, default=4.0)
    args = ap.parse_args()

    rospy.init_node("guard_sources", anonymous=True, disable_signals=True)
    pubs = {t: rospy.Publisher(t, Twist, queue_size=1) for t in (TELEOP, NAV)}
    lock = threading.Lock()
    heard: list[tuple[float, tuple[float, float]]] = []   # (monotonic time, command)

    def on_cmd(msg):
        with lock:
            heard.append((time.monotonic(), (msg.linear.x, msg.angular.z)))

    rospy.Subscriber(OUT, Twist, on_cmd, queue_size=100, tcp_nodelay=True)
    deadline = time.monotonic() + 30.0
    while time.monotonic() < deadline:
        with lock:
            ok = bool(heard)
        if ok and all(p.get_num_connections() > 0 for p in pubs.values()):
            break
        time.sleep(0.05)
    else:
        print("sources: the node did not connect within 30 s", flush=True)
        return 2

    def command() -> tuple[float, float] | None:
        with lock:
            return heard[-1][1] if heard else None

    def show(c) -> str:
        return "-" if c is None else f"{c[0]:5.2f} {c[1]:5.2f}  {NAMES.get(c, '')}"

    print(f"sources: teleop {TELEOP_CMD} and nav {NAV_CMD} at {RATE:g} Hz; teleop stops at "
          f"{args.teleop_stop:g} s, nav at {args.nav_stop:g} s; the guard's timeouts: {TIMEOUT * 1000:g} ms",
          flush=True)
    print(f"{'time':>6}  {'teleop':6}  {'nav':6}  command (linear.x angular.z)", flush=True)
    t0 = time.monotonic()
    last_pub = {TELEOP: None, NAV: None}
    events = []                  # (t, what)
    shown = command()
    next_row = 0.0
    k = 0
    while True:
        now = time.monotonic()
        t = now - t0
        if t >= args.duration:
            break
        on = {TELEOP: t < args.teleop_stop, NAV: t < args.nav_stop}
        for topic, c in ((TELEOP, TELEOP_CMD), (NAV, NAV_CMD)):
            if on[topic]:
                m = Twist()
                m.linear.x, m.angular.z = c
                pubs[topic].publish(m)
                last_pub[topic] = time.monotonic()
        c = command()
        if c != shown:
            events.append((t, c))
            print(f"{t:6.2f}  command changed to {show(c)}", flush=True)
            shown = c
        if t >= next_row:
            print(f"{t:6.2f}  {'on' if on[TELEOP] else 'off':6}  {'on' if on[NAV] else 'off':6}  {show(c)}",
                  flush=True)
            next_row += 1.0 / args.rows_per_s
        k += 1
        wait = t0 + k / RATE - time.monotonic()
        if wait > 0:
            time.sleep(wait)
    time.sleep(0.1)
    rospy.signal_shutdown("done")

    # the command the node published after each source's last message
    with lock:
        trace = list(heard)

    def first_after(t_last: float, old) -> tuple[float, tuple] | None:
        for ts, c in trace:
            if ts > t_last and c != old:
                return ts, c
        return None

    ok = True
    before = [c for ts, c in trace if t0 + 0.3 <= ts <= last_pub[TELEOP]]
    if not before or set(before) != {TELEOP_CMD}:
        print("sources: FAILED: the guard did not follow teleop while both published", flush=True)
        ok = False
    for src, old, new in ((TELEOP, TELEOP_CMD, NAV_CMD), (NAV, NAV_CMD, ZERO)):
        ch = first_after(last_pub[src], old)
        name = "teleop" if src == TELEOP else "nav"
        if ch is None or ch[1] != new:
            print(f"sources: FAILED: after {name}'s last message the command did not become {NAMES[new]}", flush=True)
            ok = False
            continue
        late = (ch[0] - last_pub[src]) * 1000
        print(f"sources: {name} stopped: the command became {NAMES[new]} {late:.0f} ms after {name}'s last "
              f"message (the timeout: {TIMEOUT * 1000:g} ms)", flush=True)
        if late < TIMEOUT * 1000:
            print(f"sources: FAILED: {name} was replaced before its timeout", flush=True)
            ok = False
    if trace and trace[-1][1] != ZERO:
        print("sources: FAILED: the command is not zero once both sources are silent", flush=True)
        ok = False
    print("sources: " + ("OK: each silent source was replaced once its timeout passed, and the robot stops"
                         if ok else "FAILED"), flush=True)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())

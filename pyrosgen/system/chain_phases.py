"""The phases that the system demo's sensors drive through the three-node
chain of examples/system_chain, for both middlewares: the rospy sensors
(``demo_chain_sim.py``, ROS 1) and the rclpy ones
(``demo_chain_sim_rclpy.py``, ROS 2) import this module from their own
folder, so it imports nothing but the standard library (not pyrosgen).

Phases of ``--phase`` seconds each: a clear scan (5 m everywhere), an
obstacle at 0.5 m, then a teleop command (0.2 m/s, 1 rad/s) with the
obstacle still there.  Scans at 10 Hz, teleop at 20 Hz.  :func:`drive`
prints a live table (time, phase, the wheel speeds) and, per phase, the
speeds seen once it settled against the ones the chain's controllers
compute."""

from __future__ import annotations

import argparse
import time

#: the scan's length (a Hokuyo UTM-30LX's 1,081 ranges)
N = 1081


def wheels(vx: float, wz: float) -> tuple[float, float]:
    """What diff_drive computes from the velocity (vx, wz): left, right."""
    turn = wz * 0.25
    return (min(max(vx - turn, -1.0), 1.0), min(max(vx + turn, -1.0), 1.0))


#: (name, every range of the scan, the teleop command or None, the wheels expected)
PHASES = [("clear scan", 5.0, None, wheels(0.5, 0.0)),
          ("obstacle 0.5 m", 0.5, None, wheels(0.0, 0.0)),
          ("teleop 0.2 m/s, 1 rad/s", 0.5, (0.2, 1.0), wheels(0.2, 1.0))]


def phase_seconds() -> float:
    """The command line of both sensor scripts: ``[--phase S]``."""
    ap = argparse.ArgumentParser()
    ap.add_argument("--phase", type=float, default=2.0)
    return ap.parse_args().phase


def drive(connected, publish_scan, publish_teleop, wait, latest, phase: float) -> int:
    """Wait (at most 30 s) until ``connected()``, then run the phases:
    ``publish_scan(r)`` a scan of ``N`` ranges ``r``, ``publish_teleop(vx,
    wz)`` a command, ``wait(s)`` lets ``s`` seconds pass (spinning if the
    middleware needs it), ``latest()`` the newest wheels (left, right) or
    None.  0 if every phase ends at its expected speeds, 1 if not, 2 if the
    chain could not be reached."""
    t0 = time.monotonic()
    while time.monotonic() - t0 < 30:
        if connected():
            break
        wait(0.05)
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
        while time.monotonic() - p0 < phase:
            if k % 2 == 0:
                publish_scan(rng)
            if tele is not None:
                publish_teleop(*tele)
            wait(0.05)
            k += 1
            w = latest()
            if time.monotonic() - p0 > phase / 2 and w is not None:
                seen.add(w)
            if k % 5 == 0 and w is not None:
                print(f"{time.monotonic() - start:6.2f}  {name:<26} {w[0]:8.3f} {w[1]:8.3f}", flush=True)
        good = seen == {expected}
        ok = ok and good
        print(f"sim: {name}: wheels {sorted(seen)} once settled; the controllers compute {expected}: "
              f"{'OK' if good else 'WRONG'}", flush=True)
    print("sim: OK: the chain computed every phase's wheel speeds" if ok else "sim: FAILED", flush=True)
    return 0 if ok else 1

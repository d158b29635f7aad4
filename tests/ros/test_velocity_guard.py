"""The velocity guard (examples/velocity_guard) on a real master: a node
with timed inputs (rule 4.12), built by ``pyrosgen build`` (the timed glue
printed by Coq, the controller C from the block diagram), driven by rospy.

- wall time: teleop (linear.x 1.0, angular.z 0.1) and nav (2.0, 0.2) both
  publishing: the output is teleop's; teleop stops: the output switches
  to nav's, never before 500 ms after the last teleop command was
  published (a message is received after it is published, and the glue
  finds it stale only when its age exceeds the timeout), and while nav
  still publishes; nav stops too: the output becomes zero, never before
  500 ms after its last command, and stays zero.  How late after the
  timeout the switch comes is a measurement, not a test
  (bench/freshness.py, BENCHMARKS.md section "Freshness");
- simulated time (``use_sim_time`` and a /clock publisher): the timeouts
  follow /clock and not the wall clock.  Teleop publishes once; the clock
  advances 400 ms and then stands still for 1.5 s of wall time, more than
  the timeout: when it moves on to 450 ms the output is still teleop's; at
  600 ms it is nav's; when nav too has been silent for 750 ms of
  simulated time, zero.
"""

from __future__ import annotations

import struct
import xmlrpc.client

import pytest

from support import ros as rosutil
from support.ros import d, dbits, run_driver, start_node

pytestmark = pytest.mark.ros

MODEL = rosutil.ROOT / "examples" / "velocity_guard" / "velocity_guard.yaml"
TELEOP, NAV, OUT = "/teleop/cmd_vel", "/nav/cmd_vel", "/cmd_vel"
TWIST = "geometry_msgs/Twist"
TELEOP_CMD = (1.0, 0.1)
NAV_CMD = (2.0, 0.2)
ZERO = (0.0, 0.0)
TIMEOUT_S = 0.5


@pytest.fixture(scope="module")
def guard(velocity_guard_node):
    """The velocity guard's binary (no controller folder: the diagram)."""
    return velocity_guard_node / "bin" / "velocity_guard"


def cmd(vx: float, wz: float) -> dict:
    return {"linear.x": d(dbits(vx)), "angular.z": d(dbits(wz))}


def value(r: dict) -> tuple[float, float]:
    """(linear.x, angular.z) of a received /cmd_vel; every other field 0."""
    lv = r["leaves"]
    f = {k: struct.unpack("<d", struct.pack("<Q", rosutil.bits_of(v)))[0] for k, v in lv.items()}
    assert all(f[k] == 0.0 and rosutil.bits_of(lv[k]) == 0 for k in f if k not in ("linear.x", "angular.z")), lv
    return f["linear.x"], f["angular.z"]


def outputs(result: dict, t0: float | None = None, t1: float | None = None) -> list[tuple[float, tuple]]:
    return [(r["t"], value(r)) for r in rosutil.received(result, OUT, t0, t1)]


class Plan:
    """Driver steps with names, to find their times in the result."""

    def __init__(self):
        self.steps: list[dict] = []
        self.names: dict[str, int] = {}

    def add(self, step: dict, name: str | None = None) -> None:
        if name is not None:
            self.names[name] = len(self.steps)
        self.steps.append(step)

    def at(self, result: dict, name: str) -> dict:
        return result["steps"][self.names[name]]


def first_change(outs, after: float, old: tuple) -> tuple[float, tuple]:
    for t, v in outs:
        if t > after and v != old:
            return t, v
    raise AssertionError(f"the output never changed from {old} after t={after}")


def test_guard_switches_to_nav_then_stops(ros, guard, tmp_path):
    start_node(ros, guard, tmp_path / "node.log")
    p = Plan()
    p.add({"flood": {"messages": {TELEOP: cmd(*TELEOP_CMD), NAV: cmd(*NAV_CMD)}, "rate": 50, "duration": 1.5}},
          "both")
    p.add({"publish": {"topic": TELEOP, "values": cmd(*TELEOP_CMD)}}, "last_teleop")
    p.add({"flood": {"messages": {NAV: cmd(*NAV_CMD)}, "rate": 50, "duration": 1.5}}, "nav")
    p.add({"publish": {"topic": NAV, "values": cmd(*NAV_CMD)}}, "last_nav")
    p.add({"sleep": 1.5}, "silence")
    plan = {"publishers": [{"topic": TELEOP, "type": TWIST}, {"topic": NAV, "type": TWIST}],
            "subscribers": [{"topic": OUT, "type": TWIST}], "wait_messages": True, "steps": p.steps}
    result = run_driver(ros, plan, tmp_path)
    outs = outputs(result)
    both, last_teleop, nav = p.at(result, "both"), p.at(result, "last_teleop"), p.at(result, "nav")
    last_nav, silence = p.at(result, "last_nav"), p.at(result, "silence")
    # before any command: zero (nothing received yet)
    assert all(v == ZERO for t, v in outs if t < both["t0"])
    # both sources: teleop's command, every cycle (after the first few)
    steady = [v for t, v in outs if both["t0"] + 0.2 <= t <= last_teleop["t0"]]
    assert len(steady) >= 40 and set(steady) == {TELEOP_CMD}
    # teleop silent: nav's command, not before the timeout, while nav publishes
    t_nav, v = first_change(outs, last_teleop["t0"], TELEOP_CMD)
    assert v == NAV_CMD, v
    lat_teleop = (t_nav - last_teleop["t0"]) * 1000
    assert lat_teleop >= TIMEOUT_S * 1000, f"teleop replaced {lat_teleop:.1f} ms after its last command"
    assert t_nav < last_nav["t0"]
    assert {v for t, v in outs if t_nav <= t <= last_nav["t0"]} == {NAV_CMD}
    assert nav["t1"] - nav["t0"] > 1.0
    # both silent: zero, not before the timeout, and it stays zero
    t_zero, v = first_change(outs, last_nav["t0"], NAV_CMD)
    assert v == ZERO, v
    lat_nav = (t_zero - last_nav["t0"]) * 1000
    assert lat_nav >= TIMEOUT_S * 1000, f"nav replaced {lat_nav:.1f} ms after its last command"
    tail = [v for t, v in outs if t_zero <= t <= silence["t1"]]
    assert len(tail) >= 30 and set(tail) == {ZERO}
    print(f"teleop -> nav after {lat_teleop:.1f} ms, nav -> zero after {lat_nav:.1f} ms")


def _set_param(ros, name: str, value) -> None:
    code, msg, _ = xmlrpc.client.ServerProxy(ros.uri).setParam("/pyrosgen_test", name, value)
    assert code == 1, msg


def test_guard_follows_simulated_time(ros, guard, tmp_path):
    _set_param(ros, "/use_sim_time", True)
    start_node(ros, guard, tmp_path / "node.log")
    base = 1000 * 10**9
    p = Plan()

    def clock(ns: int, name: str | None = None) -> None:
        p.add({"publish": {"topic": "/clock", "values": {"clock.sec": ns // 10**9, "clock.nsec": ns % 10**9}}},
              name)

    def tick(ns: int, *msgs: tuple[str, tuple], name: str | None = None) -> None:
        """The clock at ``ns``; 3 ms (wall) later the messages; 10 ms in all."""
        clock(ns, name)
        p.add({"sleep": 0.003})
        for topic, c in msgs:
            p.add({"publish": {"topic": topic, "values": cmd(*c)}})
        p.add({"sleep": 0.007})

    ms = 10**6
    # 500 ms of simulated time with nav only (the node connects to /clock)
    for k in range(50):
        tick(base + k * 10 * ms, (NAV, NAV_CMD), name="nav_only_end" if k == 49 else None)
    T = base + 500 * ms
    # teleop once, at T; nav goes on; the clock runs to T + 400 ms
    tick(T, (TELEOP, TELEOP_CMD), (NAV, NAV_CMD), name="teleop")
    for k in range(1, 41):
        tick(T + k * 10 * ms, (NAV, NAV_CMD), name="at_400" if k == 40 else None)
    # the clock stands still for 1.5 s of wall time (three timeouts' worth)
    p.add({"sleep": 1.5}, "still")
    # then: T + 450 ms (fresh), T + 600 ms (stale), each held for 0.4 s (wall)
    clock(T + 450 * ms, "jump_450")
    p.add({"sleep": 0.003})
    p.add({"publish": {"topic": NAV, "values": cmd(*NAV_CMD)}})   # nav's last, at T + 450 ms
    p.add({"sleep": 0.4}, "hold_450")
    clock(T + 600 * ms, "jump_600")
    p.add({"sleep": 0.4}, "hold_600")
    # nav silent for 750 ms of simulated time: zero
    clock(T + 1200 * ms, "jump_1200")
    p.add({"sleep": 0.4}, "hold_1200")
    plan = {"publishers": [{"topic": "/clock", "type": "rosgraph_msgs/Clock", "queue_size": 1000},
                           {"topic": TELEOP, "type": TWIST}, {"topic": NAV, "type": TWIST}],
            "subscribers": [{"topic": OUT, "type": TWIST}],
            # (no wait for a message: the node publishes nothing until the clock runs)
            "steps": p.steps, "linger": 0.2}
    result = run_driver(ros, plan, tmp_path)
    outs = outputs(result)
    # nav only: nav's command, once the node has it
    nav_only = [v for t, v in outs if p.at(result, "nav_only_end")["t0"] - 0.2 <= t <= p.at(result, "teleop")["t0"]]
    assert nav_only and set(nav_only) == {NAV_CMD}, nav_only
    # teleop at T: from T + 100 ms to T + 400 ms, teleop's command
    running = [v for t, v in outs
               if p.names["teleop"] < _step_of(result, t) and t <= p.at(result, "still")["t0"]
               and _clock_before(p, result, t) >= T + 100 * ms]
    assert len(running) >= 5 and set(running) == {TELEOP_CMD}, running
    # after 1.5 s of wall time with the clock still, at T + 450 ms: still teleop's
    at_450 = [v for t, v in outs if p.at(result, "jump_450")["t0"] <= t <= p.at(result, "hold_450")["t1"]]
    assert at_450 and set(at_450) == {TELEOP_CMD}, at_450
    # T + 600 ms: stale (simulated time), nav's (its last at T + 450 ms)
    at_600 = [v for t, v in outs if p.at(result, "jump_600")["t0"] <= t <= p.at(result, "hold_600")["t1"]]
    assert at_600 and set(at_600) == {NAV_CMD}, at_600
    # T + 1200 ms: nav's last is 750 ms old: zero
    at_1200 = [v for t, v in outs if p.at(result, "jump_1200")["t0"] <= t <= p.at(result, "hold_1200")["t1"]]
    assert at_1200 and set(at_1200) == {ZERO}, at_1200
    # the clock standing still: no cycle, so no output, for most of the 1.5 s
    # (each jump gives a cycle, and one more: ros::Rate does not sleep after
    # an overrun)
    still = p.at(result, "still")
    assert not [t for t, v in outs if still["t0"] + 0.2 <= t <= still["t1"]]
    print(f"simulated time: {len(running)} teleop commands up to T+400 ms; after 1.5 s of wall time at "
          f"T+450 ms {at_450[-1]}, at T+600 ms {at_600[-1]}, at T+1200 ms {at_1200[-1]}")


def _step_of(result: dict, t: float) -> int:
    """The index of the last step that started at or before ``t``."""
    k = -1
    for i, s in enumerate(result["steps"]):
        if s["t0"] <= t:
            k = i
    return k


def _clock_before(p: Plan, result: dict, t: float) -> int:
    """The last clock value whose publication finished before ``t``."""
    last = 0
    for i, s in enumerate(p.steps):
        if "publish" in s and s["publish"]["topic"] == "/clock" and result["steps"][i]["t1"] <= t:
            v = s["publish"]["values"]
            last = v["clock.sec"] * 10**9 + v["clock.nsec"]
    return last

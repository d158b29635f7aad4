"""A generated node that stamps its command (rule 4.13), on a real master.

``examples/landshark/landshark_stamped.yaml`` is LandShark with
``stamp: now`` on ``/landshark_control/base_velocity``: T2 says each
published command carries, in ``header.stamp``, the ROS time of its cycle
(``DDC.published_value``, ``ctx_time (S i)``: the time read when the
cycle's ``ros_spinOnce`` returned).  Built by ``pyrosgen build`` with
the bit-exact test controller (``Out1`` mixes every bit of the three
speeds, tests/ros/test_e2e.py), run here:

- in simulated time (``use_sim_time`` and a /clock from 1000 s in 10 ms
  steps): every stamp is a clock value the test published, never wall
  time, and consecutive commands are 20 ms of simulated time apart
  (median);
- in wall time: every stamp lies between the test's clock before the node
  started and after the last command was received, 20 ms apart (median);

and the command itself is still the controller's, bit for bit, so the
stamp did not disturb the data.
"""

from __future__ import annotations

import statistics
import time
import xmlrpc.client

import pytest

from pyrosgen.ros.build import build

from support import ros as rosutil
from support.ros import d, dbits, run_driver, start_node

pytestmark = pytest.mark.ros

MODEL = rosutil.ROOT / "examples" / "landshark" / "landshark_stamped.yaml"
#: the bit-exact test controller (tests/ros/controllers/landshark_echo): every input bit reaches Out1
CONTROLLER = rosutil.CONTROLLERS / "landshark_echo"
CMD = "/landshark_control/base_velocity"
WHEELS = ("/landshark/left_wheel_velocity", "/landshark/right_wheel_velocity", "/landshark/gps_velocity")
PERIOD_NS = 20_000_000


@pytest.fixture(scope="module")
def stamped_node(nodes_dir):
    out = nodes_dir / "landshark_stamped"
    res = build(MODEL, CONTROLLER, out)
    binary = out / "bin" / "landshark_stamped"
    assert binary.is_file()
    # the proved model says the topic is stamped
    assert "stamp landshark_control_base_velocity header.stamp" in res.generated.proved_model.splitlines()
    return binary


def _stamps(result) -> list[tuple[float, int, float]]:
    """(time received, stamp in ns, twist.linear.x) of each command."""
    out = []
    for r in rosutil.received(result, CMD):
        lv = r["leaves"]
        x = rosutil.bits_of(lv["twist.linear.x"])
        out.append((r["t"], lv["header.stamp.sec"] * 10**9 + lv["header.stamp.nsec"], x))
    return out


def _echo(values: tuple[float, float, float]) -> int:
    """The test controller's Out1 (bits) on these speeds."""
    def rotl(b: int, n: int) -> int:
        return ((b << n) | (b >> (64 - n))) & 0xFFFFFFFFFFFFFFFF
    a, b, c = (dbits(v) for v in values)
    return a ^ rotl(b, 21) ^ rotl(c, 42) ^ dbits(1.0)


def _wheels(values: tuple[float, float, float]) -> list[dict]:
    return [{"publish": {"topic": t, "values": {"twist.linear.x": d(dbits(v))}}} for t, v in zip(WHEELS, values)]


def _publishers() -> list[dict]:
    return [{"topic": t, "type": "geometry_msgs/TwistStamped", "queue_size": 10} for t in WHEELS]


def test_stamps_follow_simulated_time(ros, stamped_node, tmp_path):
    code, msg, _ = xmlrpc.client.ServerProxy(ros.uri).setParam("/pyrosgen_test", "/use_sim_time", True)
    assert code == 1, msg
    start_node(ros, stamped_node, tmp_path / "node.log")
    base, step_ns, ticks = 1000 * 10**9, 10_000_000, 250
    clock = [base + k * step_ns for k in range(ticks)]
    steps = []
    for k, t in enumerate(clock):
        steps.append({"publish": {"topic": "/clock", "values": {"clock.sec": t // 10**9, "clock.nsec": t % 10**9}}})
        if k == 20:
            steps += _wheels((1.0, 1.5, 4.0))
        steps.append({"sleep": 0.01})
    plan = {"publishers": [{"topic": "/clock", "type": "rosgraph_msgs/Clock", "queue_size": 1000}] + _publishers(),
            "subscribers": [{"topic": CMD, "type": "geometry_msgs/TwistStamped"}],
            "steps": steps, "linger": 0.5}
    got = _stamps(run_driver(ros, plan, tmp_path))
    allowed = set(clock)
    timed = [s for _, s, _ in got if s]
    assert len(timed) >= 30, f"only {len(timed)} stamped commands in simulated time"
    # every stamp is a clock value (0 before the node read the first one)
    assert all(s in allowed for s in timed), [s for s in timed if s not in allowed][:5]
    diffs = [b - a for a, b in zip(timed, timed[1:])]
    assert all(x >= 0 for x in diffs), diffs
    assert statistics.median(diffs) == PERIOD_NS, f"median {statistics.median(diffs) / 1e6} ms of simulated time"
    # the data is the controller's, once the wheels reported
    assert got[-1][2] == _echo((1.0, 1.5, 4.0))
    print(f"simulated time: {len(timed)} stamped commands from {timed[0] / 1e9:.3f} s to {timed[-1] / 1e9:.3f} s")


def test_stamps_follow_wall_time(ros, stamped_node, tmp_path):
    t0 = time.time_ns()
    start_node(ros, stamped_node, tmp_path / "node.log")
    steps = _wheels((2.0, 1.0, 3.0)) + [{"sleep": 2.0}]
    plan = {"publishers": _publishers(), "subscribers": [{"topic": CMD, "type": "geometry_msgs/TwistStamped"}],
            "wait_messages": True, "steps": steps, "linger": 0.2}
    got = _stamps(run_driver(ros, plan, tmp_path))
    t1 = time.time_ns()
    assert len(got) >= 20
    for _, stamp, _ in got:
        assert t0 <= stamp <= t1, (t0, stamp, t1)
    diffs = [b[1] - a[1] for a, b in zip(got, got[1:])]
    assert all(x > 0 for x in diffs)
    assert abs(statistics.median(diffs) - PERIOD_NS) <= 2_000_000, f"median {statistics.median(diffs) / 1e6} ms"
    assert got[-1][2] == _echo((2.0, 1.0, 3.0))


# --------------------------------------------------------------------------
# A stamp copied from the newest GPS message (``stamp: {from: ...}``)

COPIED = rosutil.ROOT / "examples" / "landshark" / "landshark_gps_stamped.yaml"


@pytest.fixture(scope="module")
def copied_node(nodes_dir):
    out = nodes_dir / "landshark_gps_stamped"
    res = build(COPIED, CONTROLLER, out)
    binary = out / "bin" / "landshark_gps_stamped"
    assert binary.is_file()
    assert ("stamp_from landshark_control_base_velocity landshark_gps_velocity header.stamp"
            in res.generated.proved_model.splitlines())
    return binary


def _gps(value: float, sec: int, nsec: int) -> dict:
    return {"publish": {"topic": WHEELS[2], "values": {"twist.linear.x": d(dbits(value)),
                                                     "header.stamp.sec": sec, "header.stamp.nsec": nsec}}}


def test_stamp_is_the_newest_gps_stamp(ros, copied_node, tmp_path):
    """T2 (``published_value`` with ``newest_by``): each command carries the
    ``header.stamp`` of the newest GPS message received before its cycle,
    zero before the first; the wheels' stamps never reach it."""
    start_node(ros, copied_node, tmp_path / "node.log")
    first, second = 5 * 10**9 + 7, 6 * 10**9 + 8
    steps = [{"sleep": 0.3}]
    steps += [{"publish": {"topic": t, "values": {"twist.linear.x": d(dbits(1.0)), "header.stamp.sec": 99,
                                                  "header.stamp.nsec": 99}}} for t in WHEELS[:2]]
    steps += [{"sleep": 0.3}, _gps(4.0, 5, 7), {"sleep": 0.4}, _gps(2.0, 6, 8), {"sleep": 0.4}]
    plan = {"publishers": _publishers(), "subscribers": [{"topic": CMD, "type": "geometry_msgs/TwistStamped"}],
            "wait_messages": True, "steps": steps, "linger": 0.2}
    got = [s for _, s, _ in _stamps(run_driver(ros, plan, tmp_path))]
    assert len(got) >= 20, got
    # only these stamps, in this order: zero, then the first GPS stamp, then the second
    assert set(got) <= {0, first, second}, sorted(set(got) - {0, first, second})[:5]
    order = [s for i, s in enumerate(got) if i == 0 or got[i - 1] != s]
    assert order == [0, first, second], order
    assert got.count(first) >= 5 and got.count(second) >= 5, (got.count(first), got.count(second))

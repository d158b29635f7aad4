"""examples/dock on ROS 1 (a real master): the same model as the ROS 2
test (tests/ros2/test_custom_msgs_ros2.py) built with catkin's message
generation for its custom package dock_msgs and driven by rospy with the
same beacons; every command bit for bit as the diagram says (speed =
sat(0.5 range, 0, 0.5), zero and stop when range < 0.2 or the link level is
0; the beacon's id, its quality into ``seen[0]`` and ``links``, its first 3
samples into ``trace``): one model, two targets (rule 4.17)."""

from __future__ import annotations

import pytest

from pyrosgen.ros.build import build

from support import ros as rosutil
from support.ros import d, dbits, f, fbits, run_driver, start_node

pytestmark = pytest.mark.ros

DOCK = rosutil.ROOT / "examples" / "dock"
BEACON, COMMAND = "/dock/beacon", "/dock/command"
SETTLE, HOLD = 0.3, 0.7

#: (range, id, link level, snr, samples), as in the ROS 2 test
CASES = [
    (1.3, 7, 2, 12.5, [1.0, 2.0, 3.5, -4.25]),
    (0.6, 8, 3, -2.0, [0.5, 0.25, 8.0]),
    (0.15, 9, 2, 1.0, [7.0]),
    (2.0, 10, 0, 3.0, []),
    (0.8, -11, 1, 0.5, [1.0, 2.0]),
    (0.3, 12, 3, 6.0, [9.0, 8.0, 7.0, 6.0, 5.0, 4.0]),
]


def want(rng: float, ident: int, level: int, snr: float, samples: list[float]) -> dict:
    stop = rng < 0.2 or level == 0
    speed = 0.0 if stop else min(max(0.5 * rng, 0.0), 0.5)
    out = {"speed": d(dbits(speed)), "stop": stop, "beacon_id": ident,
           "seen[0].level": level, "seen[0].snr": f(fbits(snr)), "seen[1].level": 0, "seen[1].snr": f(0),
           "trace": {"var": min(len(samples), 3)}, "links": {"var": 1},
           "links[0].level": level, "links[0].snr": f(fbits(snr))}
    out.update({f"trace[{i}]": f(fbits(x)) for i, x in enumerate(samples[:3])})
    return out


@pytest.fixture(scope="module")
def dock1(nodes_dir):
    out = nodes_dir / "dock"
    build(DOCK / "dock.yaml", None, out)
    return out / "bin" / "dock"


def test_dock_ros1_custom_messages(ros, dock1, tmp_path):
    node = start_node(ros, dock1, tmp_path / "node.log")
    steps = []
    for rng, ident, level, snr, samples in CASES:
        steps += [{"publish": {"topic": BEACON, "fill_noncarried": True,
                               "values": {"range": d(dbits(rng)), "id": ident, "quality.level": level,
                                          "quality.snr": f(fbits(snr)), "samples": samples}}},
                  {"sleep": HOLD}]
    plan = {"msg_paths": {"dock_msgs": str(DOCK / "msg" / "dock_msgs" / "msg")},
            "publishers": [{"topic": BEACON, "type": "dock_msgs/Beacon", "queue_size": 10}],
            "subscribers": [{"topic": COMMAND, "type": "dock_msgs/DockCommand", "record": "deep"}],
            "wait_messages": True, "steps": steps, "linger": 0.2}
    result = run_driver(ros, plan, tmp_path)
    assert node.poll() is None, (tmp_path / "node.log").read_text()[-2000:]
    first = rosutil.received(result, COMMAND)[0]["leaves"]
    assert {k: first.get(k) for k in want(0.0, 0, 0, 0.0, [])} == want(0.0, 0, 0, 0.0, []), first
    for k, case in enumerate(CASES):
        t0, t1 = result["steps"][2 * k]["t1"] + SETTLE, result["steps"][2 * k + 1]["t1"]
        got = [r["leaves"] for r in rosutil.received(result, COMMAND, t0, t1)]
        expect = want(*case)
        assert len(got) >= 5, (case, len(got))
        assert all({n: g.get(n) for n in expect} == expect for g in got), (case, got[-1], expect)

"""Variable-length arrays on a real master (rule 4.15).

``examples/laser_guard/laser_guard.yaml``, built by ``pyrosgen build`` (the
controller's C from its block diagram), subscribes to ``/scan``
(``sensor_msgs/LaserScan``, ``ranges`` carried as at most N = 1081
float32) and commands ``/cmd_vel``.  A rospy driver publishes scans of
lengths 0, 1, N-1, N, N+1 and 2N (and 542 and 543, the shortest scans
without and with the whole sector 538..542), every range 2.0 m or one
range 0.5 m in or beside the sector; after each, every command is
checked: 0.5 m/s forward when the sector is clear and the scan contains
it, else 0, and always in frame ``base_link`` with the other twist fields
zero.  What T2 says the controller receives (``Environment.clamp``: the
element when the scan has it within N, else 0; the length capped at N;
truncated when longer) is what decides, so a scan of N+1 or 2N ranges
still drives (its first N ranges hold the sector).

The round trip of the conversion itself: tests/ros/models/scan_echo.yaml
passes ranges[0], ranges[1079] and ranges[1080], the scan's length and
truncation flag, and its frame_id's length and truncation flag (strings of
0, 1, 127, 128, 129 and 256 bytes) to ordinary published fields; for the
six lengths each is exactly what the clamp gives.
"""

from __future__ import annotations

import struct

import pytest

from pyrosgen.ros.build import build

from support import ros as rosutil
from support.ros import bits_of, dbits, fbits, run_driver, start_node

pytestmark = pytest.mark.ros

MODEL = rosutil.ROOT / "examples" / "laser_guard" / "laser_guard.yaml"
ECHO = rosutil.ROOT / "tests" / "ros" / "models" / "scan_echo.yaml"
N = 1081
LENGTHS = (0, 1, N - 1, N, N + 1, 2 * N)
SCAN, CMD = "/scan", "/cmd_vel"
FAR, NEAR = 2.0, 0.5
#: how long after a scan is published its commands are checked, and how
#: long each scan is the newest
SETTLE, HOLD = 0.3, 0.8


@pytest.fixture(scope="module")
def guard(nodes_dir):
    out = nodes_dir / "laser_guard"
    res = build(MODEL, None, out)
    binary = out / "bin" / "laser_guard"
    assert binary.is_file()
    assert "input_relation scan ranges.data[540] R540" in res.generated.proved_model.splitlines()
    return binary


@pytest.fixture(scope="module")
def echo(nodes_dir):
    out = nodes_dir / "scan_echo"
    build(ECHO, None, out)
    binary = out / "bin" / "scan_echo"
    assert binary.is_file()
    return binary


def _scan(length: int, near: int | None = None, frame: str = "laser", value=None) -> dict:
    ranges = [value(i) if value else (NEAR if i == near else FAR) for i in range(length)]
    return {"publish": {"topic": SCAN, "values": {"ranges": ranges, "header.frame_id": frame}}}


def _windows(plan_steps: int, result: dict) -> list[tuple[float, float]]:
    """For each scan (a publish step followed by a sleep): the time from
    SETTLE after its publication to the end of its sleep."""
    steps = result["steps"]
    assert len(steps) == plan_steps
    return [(steps[k]["t1"] + SETTLE, steps[k + 1]["t1"]) for k in range(0, plan_steps, 2)]


#: (what, length, the near range or None, the expected speed); the speeds
#: alternate so that every case shows a change
CASES = [
    ("N ranges, clear", N, None, 0.5),
    ("no range", 0, None, 0.0),
    ("N-1 ranges, clear", N - 1, None, 0.5),
    ("one range", 1, None, 0.0),
    ("N+1 ranges (truncated), clear", N + 1, None, 0.5),
    ("N ranges, an obstacle straight ahead", N, 540, 0.0),
    ("2N ranges (truncated), clear", 2 * N, None, 0.5),
    ("2N ranges, an obstacle at the sector's edge", 2 * N, 542, 0.0),
    ("N ranges, an obstacle beside the sector", N, 537, 0.5),
    ("542 ranges: the sector cut short", 542, None, 0.0),
    ("543 ranges: just long enough", 543, None, 0.5),
    ("N+1 ranges, an obstacle at the sector's other edge", N + 1, 538, 0.0),
]


def test_the_guard_drives_only_when_the_sector_is_clear(ros, guard, tmp_path):
    node = start_node(ros, guard, tmp_path / "node.log")
    steps = []
    for _, length, near, _ in CASES:
        steps += [_scan(length, near), {"sleep": HOLD}]
    plan = {"publishers": [{"topic": SCAN, "type": "sensor_msgs/LaserScan", "queue_size": 10}],
            "subscribers": [{"topic": CMD, "type": "geometry_msgs/TwistStamped"}],
            "wait_messages": True, "steps": steps, "linger": 0.2}
    result = run_driver(ros, plan, tmp_path)
    assert node.poll() is None, (tmp_path / "node.log").read_text()[-2000:]
    cmds = rosutil.received(result, CMD)
    assert len(cmds) >= 50
    for r in cmds:
        lv = r["leaves"]
        assert lv["header.frame_id"] == {"str": "base_link"}, lv["header.frame_id"]
        others = {k: v for k, v in lv.items() if k.startswith("twist.") and k != "twist.linear.x"}
        assert all(bits_of(v) == 0 for v in others.values()), others
    for (what, length, near, speed), (t0, t1) in zip(CASES, _windows(len(steps), result)):
        got = [bits_of(r["leaves"]["twist.linear.x"]) for r in rosutil.received(result, CMD, t0, t1)]
        assert len(got) >= 10, (what, len(got))
        assert set(got) == {dbits(speed)}, (what, [struct.unpack("<d", struct.pack("<Q", b))[0] for b in got])


FRAMES = (0, 1, 127, 128, 129, 256)


def _element(i: int) -> float:
    """The i-th range of the round trip's scans: distinct, exact in float32."""
    return i + 0.25


def test_round_trip_of_the_conversion(ros, echo, tmp_path):
    node = start_node(ros, echo, tmp_path / "node.log")
    steps = []
    for length, frame in zip(LENGTHS, FRAMES):
        steps += [_scan(length, frame="f" * frame, value=_element), {"sleep": HOLD}]
    plan = {"publishers": [{"topic": SCAN, "type": "sensor_msgs/LaserScan", "queue_size": 10}],
            "subscribers": [{"topic": "/echo/ranges", "type": "geometry_msgs/Point32"},
                            {"topic": "/echo/lengths", "type": "sensor_msgs/RegionOfInterest"},
                            {"topic": "/echo/frame_truncated", "type": "std_msgs/Bool"}],
            "wait_messages": True, "steps": steps, "linger": 0.2}
    result = run_driver(ros, plan, tmp_path)
    assert node.poll() is None, (tmp_path / "node.log").read_text()[-2000:]
    for (length, frame), (t0, t1) in zip(zip(LENGTHS, FRAMES), _windows(len(steps), result)):
        k = min(length, N)

        def elem(i: int) -> str:
            return f"f:{fbits(_element(i)) if i < k else 0:08x}"

        want = {
            "/echo/ranges": {"x": elem(0), "y": elem(1079), "z": elem(1080)},
            "/echo/lengths": {"x_offset": 0, "y_offset": 0, "width": k, "height": min(frame, 128),
                              "do_rectify": int(length > N)},
            "/echo/frame_truncated": {"data": int(frame > 128)},
        }
        for topic, leaves in want.items():
            got = [r["leaves"] for r in rosutil.received(result, topic, t0, t1)]
            assert len(got) >= 10, (length, topic, len(got))
            assert all(g == leaves for g in got), (length, frame, topic, got[-1], leaves)

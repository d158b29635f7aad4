"""A whole scan into an Embedded Coder controller array, on a real master
(rule 4.15).

``examples/scan_guard/scan_guard.yaml``, built by ``pyrosgen build`` with
its controller folder (``ScanGuard.h`` declares ``real32_T Scan[1081];``),
hands the controller the whole of each ``/scan`` (``ranges`` into ``Scan``,
its length into ``NScan``).  A rospy driver publishes scans of lengths 0,
1, N-1, N, N+1 and 2N (and 600 and 601, the shortest scans without and
with the whole sector 480..600), every range 2.0 m or one range 0.5 m (or
0.03 m, below the scanner's minimum) in or beside the sector.  After
each, every command on ``/cmd_vel`` and every ``/closest`` is checked:
0.5 m/s while the closest valid range of the sector is beyond 1 m and the
scan holds the sector, else 0, always in frame ``base_link``; ``/closest``
is that range (100 m when none).  What T2 says the controller receives
(``Environment.clamp``: the first min(length, N) ranges, zeros after; the
length capped at N) is what decides: a scan of 2N ranges drives on its
first N, a scan of 600 does not reach the sector's last range.
"""

from __future__ import annotations

import struct

import pytest

from pyrosgen.ros.build import build

from support import ros as rosutil
from support.ros import bits_of, dbits, fbits, run_driver, start_node

pytestmark = pytest.mark.ros

EXAMPLE = rosutil.ROOT / "examples" / "scan_guard"
N = 1081
SCAN, CMD, CLOSEST = "/scan", "/cmd_vel", "/closest"
FAR, NEAR, TOO_NEAR, NONE = 2.0, 0.5, 0.03, 100.0
SETTLE, HOLD = 0.3, 0.8


@pytest.fixture(scope="module")
def guard(nodes_dir):
    out = nodes_dir / "scan_guard"
    res = build(EXAMPLE / "scan_guard.yaml", EXAMPLE / "controller", out)
    binary = out / "bin" / "scan_guard"
    assert binary.is_file()
    lines = res.generated.proved_model.splitlines()
    assert "input ScanGuard_U.Scan" not in lines  # the model text names fields, not the global
    assert "input Scan array 1081 float32" in lines
    assert "input_relation scan ranges.data[1080] Scan[1080]" in lines
    return binary


#: (what, length, (index, range) of the one near range or None, speed, closest)
CASES = [
    ("N ranges, clear", N, None, 0.5, FAR),
    ("no range", 0, None, 0.0, NONE),
    ("N-1 ranges, clear", N - 1, None, 0.5, FAR),
    ("one range", 1, None, 0.0, NONE),
    ("N+1 ranges (truncated), clear", N + 1, None, 0.5, FAR),
    ("N ranges, an obstacle straight ahead", N, (540, NEAR), 0.0, NEAR),
    ("2N ranges (truncated), clear", 2 * N, None, 0.5, FAR),
    ("2N ranges, an obstacle at the sector's last range", 2 * N, (600, NEAR), 0.0, NEAR),
    ("N ranges, an obstacle beside the sector", N, (479, NEAR), 0.5, FAR),
    ("600 ranges: the sector cut short", 600, None, 0.0, FAR),
    ("601 ranges: just long enough", 601, None, 0.5, FAR),
    ("N ranges, an obstacle at the sector's first range", N, (480, NEAR), 0.0, NEAR),
    ("N ranges, a range below the scanner's minimum", N, (540, TOO_NEAR), 0.5, FAR),
]


def _scan(length: int, near) -> dict:
    ranges = [FAR] * length
    if near is not None and near[0] < length:
        ranges[near[0]] = near[1]
    return {"publish": {"topic": SCAN, "values": {"ranges": ranges, "header.frame_id": "laser"}}}


def test_the_guard_reads_the_whole_scan(ros, guard, tmp_path):
    node = start_node(ros, guard, tmp_path / "node.log")
    steps = []
    for _, length, near, _, _ in CASES:
        steps += [_scan(length, near), {"sleep": HOLD}]
    plan = {"publishers": [{"topic": SCAN, "type": "sensor_msgs/LaserScan", "queue_size": 10}],
            "subscribers": [{"topic": CMD, "type": "geometry_msgs/TwistStamped"},
                            {"topic": CLOSEST, "type": "std_msgs/Float32"}],
            "wait_messages": True, "steps": steps, "linger": 0.2}
    result = run_driver(ros, plan, tmp_path)
    assert node.poll() is None, (tmp_path / "node.log").read_text()[-2000:]
    cmds = rosutil.received(result, CMD)
    assert len(cmds) >= 50
    for r in cmds:
        assert r["leaves"]["header.frame_id"] == {"str": "base_link"}, r["leaves"]["header.frame_id"]
    got_steps = result["steps"]
    assert len(got_steps) == len(steps)
    for k, (what, _, _, speed, closest) in enumerate(CASES):
        t0, t1 = got_steps[2 * k]["t1"] + SETTLE, got_steps[2 * k + 1]["t1"]
        vx = [bits_of(r["leaves"]["twist.linear.x"]) for r in rosutil.received(result, CMD, t0, t1)]
        assert len(vx) >= 8, (what, len(vx))
        assert set(vx) == {dbits(speed)}, (what, [struct.unpack("<d", struct.pack("<Q", b))[0] for b in vx])
        near = [bits_of(r["leaves"]["data"]) for r in rosutil.received(result, CLOSEST, t0, t1)]
        assert len(near) >= 8, (what, len(near))
        assert set(near) == {fbits(closest)}, (what, near)

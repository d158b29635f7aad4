"""The three-node chain of examples/system_chain on a real master: each
node built by ``pyrosgen build``, started with the namespace and the
remappings of the system file (as the system's launch file says), driven
by rospy: a clear scan drives the wheels at the guard's cruise speed
through the velocity mux, an obstacle stops them, a teleop command takes
over; the values on /base/wheels are the ones the controllers compute
(bit for bit)."""

from __future__ import annotations

import struct

import pytest

from pyrosgen.ros.build import build
from pyrosgen.ros.rosmaster import free_port
from pyrosgen.system.checks import check_system
from pyrosgen.system.model import load_system

from support import ros as rosutil
from support.ros import RecordingRosEnv, bits_of, d, dbits, run_driver

pytestmark = pytest.mark.ros

SYSTEM = rosutil.ROOT / "examples" / "system_chain" / "system.yaml"
N = 1081
SETTLE, HOLD = 0.6, 1.5


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    """Each node of the system built, and its ROS arguments (namespace,
    node name, remappings) from the system's resolution."""
    sysm = load_system(SYSTEM)
    check_system(sysm)
    root = tmp_path_factory.mktemp("chain")
    nodes = []
    for sn in sysm.nodes:
        out = root / sn.folder
        build(sn.model_path, None, out)
        binary = out / "bin" / sn.model.name
        assert binary.is_file()
        args = [f"__ns:={sn.namespace}", f"__name:={sn.name}"] + [f"{s}:={t}" for s, t in sorted(sn.remap.items())]
        nodes.append((sn.full_name, binary, args))
    return nodes


@pytest.fixture
def ros(tmp_path):
    home = tmp_path / "ros"
    (home / "log").mkdir(parents=True, exist_ok=True)
    env = RecordingRosEnv(port=free_port(), home=home)
    try:
        env.start_master()
        yield env
    finally:
        env.close()


def scan(value: float) -> dict:
    return {"publish": {"topic": "/scan", "values": {"ranges": [value] * N}}}


def teleop(vx: float, wz: float) -> dict:
    return {"publish": {"topic": "/teleop/cmd_vel", "values": {"linear.x": d(dbits(vx)), "angular.z": d(dbits(wz))}}}


def wheels(vx: float, wz: float) -> tuple[int, int]:
    """What diff_drive computes (its diagram, in float64): left, right."""
    turn = wz * 0.25
    clamp = lambda v: min(max(v, -1.0), 1.0)  # noqa: E731
    return dbits(clamp(vx - turn)), dbits(clamp(vx + turn))


def test_chain_end_to_end(ros, built, tmp_path):
    procs = []
    for name, binary, args in built:
        log = open(tmp_path / f"{name.strip('/').replace('/', '.')}.log", "ab")
        procs.append((name, ros.spawn([str(binary), *args], stdout=log, stderr=log.fileno())))
    # scans every 100 ms (the mux's nav timeout is 500 ms: the guard keeps
    # publishing every 20 ms whatever the scan rate)
    steps, cases = [], []

    def hold(step_of, what, expected, n=int(HOLD / 0.1)):
        first = len(steps)
        for _ in range(n):
            steps.extend([step_of(), {"sleep": 0.1}])
        cases.append((what, first, len(steps) - 1, expected))

    hold(lambda: scan(5.0), "clear: the guard's cruise 0.5 m/s through the mux", wheels(0.5, 0.0))
    hold(lambda: scan(0.5), "an obstacle at 0.5 m: stop", wheels(0.0, 0.0))
    hold(lambda: teleop(0.2, 1.0), "teleop (0.2 m/s, 1 rad/s) takes over", wheels(0.2, 1.0))
    plan = {"publishers": [{"topic": "/scan", "type": "sensor_msgs/LaserScan", "queue_size": 10},
                           {"topic": "/teleop/cmd_vel", "type": "geometry_msgs/Twist", "queue_size": 10}],
            "subscribers": [{"topic": "/base/wheels", "type": "geometry_msgs/Vector3"}],
            "wait_messages": True, "steps": steps, "linger": 0.2}
    result = run_driver(ros, plan, tmp_path, timeout=180)
    for name, p in procs:
        assert p.poll() is None, f"{name} exited: " + (tmp_path / f"{name.strip('/').replace('/', '.')}.log").read_text()[-2000:]
    for what, first, last, (left, right) in cases:
        t0 = result["steps"][first]["t1"] + SETTLE
        t1 = result["steps"][last]["t1"]
        got = {(bits_of(r["leaves"]["x"]), bits_of(r["leaves"]["y"]), bits_of(r["leaves"]["z"]))
               for r in rosutil.received(result, "/base/wheels", t0, t1)}
        shown = [tuple(struct.unpack("<d", struct.pack("<Q", b))[0] for b in g) for g in got]
        assert got == {(left, right, 0)}, (what, shown)

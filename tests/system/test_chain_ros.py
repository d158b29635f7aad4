"""The three-node chain of examples/system_chain on a real master, built
by ``pyrosgen system build``: ``catkin_make`` builds its workspace as it
is, and the chain runs twice, its nodes started by the system's launch
file (roslaunch, from the workspace) and then each binary of OUT started
by hand with the namespace and the remappings of the system's resolution,
each run driven by rospy: a clear scan drives the wheels at the guard's
cruise speed through the velocity mux, an obstacle stops them, a teleop
command takes over; the values on /base/wheels are the ones the
controllers compute (bit for bit)."""

from __future__ import annotations

import struct

import pytest

import subprocess

from pyrosgen.ros.rosmaster import free_port
from pyrosgen.system.checks import check_system
from pyrosgen.system.generate import generate_system
from pyrosgen.system.model import load_system

from support import ros as rosutil
from support.ros import RecordingRosEnv, bits_of, d, dbits, run_driver

pytestmark = pytest.mark.ros

SYSTEM = rosutil.ROOT / "examples" / "system_chain" / "system.yaml"
N = 1081
SETTLE, HOLD = 0.6, 1.5


@pytest.fixture(scope="module")
def system_out(tmp_path_factory):
    """``pyrosgen system build`` of the chain (a fresh cache, -j 2)."""
    root = tmp_path_factory.mktemp("chain")
    res = generate_system(SYSTEM, root / "out", jobs=2, cache=root / "cache", build=True)
    assert [n.cached for n in res.nodes] == [False, False, False]
    assert "src" in res.files and "guard_chain.launch" in res.files
    return root / "out"


@pytest.fixture(scope="module")
def built(system_out):
    """Each node's binary in OUT, and its ROS arguments (namespace, node
    name, remappings) from the system's resolution."""
    sysm = load_system(SYSTEM)
    check_system(sysm)
    nodes = []
    for sn in sysm.nodes:
        binary = system_out / sn.folder / "bin" / sn.model.name
        assert binary.is_file()
        args = [f"__ns:={sn.namespace}", f"__name:={sn.name}"] + [f"{s}:={t}" for s, t in sorted(sn.remap.items())]
        nodes.append((sn.full_name, binary, args))
    return nodes


@pytest.fixture(scope="module")
def workspace(system_out, tmp_path_factory):
    """A catkin workspace whose src is OUT/src, built by catkin_make."""
    ws = tmp_path_factory.mktemp("ws")
    (ws / "src").symlink_to(system_out / "src")
    assert sorted(p.name for p in (system_out / "src").iterdir() if p.is_symlink()) == [
        "diff_drive", "laser_guard", "velocity_guard"]
    r = subprocess.run(["catkin_make", "-C", str(ws), "-DPYTHON_EXECUTABLE=/usr/bin/python3"],
                       capture_output=True, text=True, timeout=900)
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
    for pkg in ("diff_drive", "laser_guard", "velocity_guard"):
        assert (ws / "devel" / "lib" / pkg / pkg).is_file()
    return ws


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


def drive(ros, tmp_path, procs):
    steps, cases = [], []

    def hold(step_of, what, expected, n=int(HOLD / 0.1)):
        first = len(steps)
        for _ in range(n):
            steps.extend([step_of(), {"sleep": 0.1}])
        cases.append((what, first, len(steps) - 1, expected))

    # scans every 100 ms (the mux's nav timeout is 500 ms: the guard keeps
    # publishing every 20 ms whatever the scan rate)
    hold(lambda: scan(5.0), "clear: the guard's cruise 0.5 m/s through the mux", wheels(0.5, 0.0))
    hold(lambda: scan(0.5), "an obstacle at 0.5 m: stop", wheels(0.0, 0.0))
    hold(lambda: teleop(0.2, 1.0), "teleop (0.2 m/s, 1 rad/s) takes over", wheels(0.2, 1.0))
    plan = {"publishers": [{"topic": "/scan", "type": "sensor_msgs/LaserScan", "queue_size": 10},
                           {"topic": "/teleop/cmd_vel", "type": "geometry_msgs/Twist", "queue_size": 10}],
            "subscribers": [{"topic": "/base/wheels", "type": "geometry_msgs/Vector3"}],
            "connect_timeout": 60, "wait_messages": True, "steps": steps, "linger": 0.2}
    result = run_driver(ros, plan, tmp_path, timeout=240)
    for name, p, log in procs:
        assert p.poll() is None, f"{name} exited: " + log.read_text()[-2000:]
    for what, first, last, (left, right) in cases:
        t0 = result["steps"][first]["t1"] + SETTLE
        t1 = result["steps"][last]["t1"]
        got = {(bits_of(r["leaves"]["x"]), bits_of(r["leaves"]["y"]), bits_of(r["leaves"]["z"]))
               for r in rosutil.received(result, "/base/wheels", t0, t1)}
        shown = [tuple(struct.unpack("<d", struct.pack("<Q", b))[0] for b in g) for g in got]
        assert got == {(left, right, 0)}, (what, shown)


def test_chain_binaries_with_the_resolution(ros, built, tmp_path):
    procs = []
    for name, binary, args in built:
        log = tmp_path / f"{name.strip('/').replace('/', '.')}.log"
        f = open(log, "ab")
        procs.append((name, ros.spawn([str(binary), *args], stdout=f, stderr=subprocess.STDOUT), log))
    drive(ros, tmp_path, procs)


def test_chain_roslaunch_of_the_system(ros, workspace, system_out, tmp_path):
    log = tmp_path / "roslaunch.log"
    f = open(log, "ab")
    launch = system_out / "guard_chain.launch"
    p = ros.spawn(["bash", "-c", f"source {workspace}/devel/setup.bash && exec roslaunch {launch}"],
                  stdout=f, stderr=subprocess.STDOUT)
    drive(ros, tmp_path, [("roslaunch", p, log)])


def test_system_demo(system_out, tmp_path):
    """``make demo``'s system part: python -m pyrosgen.system.demo OUT."""
    import re
    import sys

    env = {"CI": "true", "PATH": "/usr/bin:/bin", "HOME": str(tmp_path)}
    r = subprocess.run([sys.executable, "-m", "pyrosgen.system.demo", str(system_out), "--phase", "1.5"],
                       cwd=rosutil.ROOT, env=env, stdin=subprocess.DEVNULL, capture_output=True, text=True,
                       timeout=180)
    assert r.returncode == 0, r.stdout + r.stderr
    out = r.stdout
    assert "sim: OK: the chain computed every phase's wheel speeds" in out
    assert len(re.findall(r"^sim: [^\n]*the controllers compute [^\n]*: OK$", out, re.M)) == 3
    assert "/nav/cmd_vel:=/safety/cmd_vel" in out
    pids = [int(p) for p in re.findall(r"\(pid (\d+)\)", out)]
    assert len(pids) == 5 and not any(rosutil.alive(p) for p in pids)
    assert "demo: all processes stopped" in out
    # bad usage: a folder without the nodes
    r = subprocess.run([sys.executable, "-m", "pyrosgen.system.demo", str(tmp_path / "nothing")],
                       cwd=rosutil.ROOT, env=env, capture_output=True, text=True, timeout=60)
    assert r.returncode == 1 and "not found" in r.stdout and "Traceback" not in r.stderr

"""Stamps on ROS 2 (rules 4.13, 4.17), end to end on a real DDS (Fast DDS
from the wheels, loopback only): ``header.stamp`` is a
``builtin_interfaces/Time`` (``int32 sec``, ``uint32 nanosec``), which the
proved glue fills with the cycle's ROS time (``(int)ros_time_sec()``,
``ros_time_nsec()``; ``DDC.stamp_sec``).

- LandShark stamped (examples/landshark/landshark_stamped.yaml, the
  bit-exact echo controller) under wall time: every command an rclpy peer
  receives carries a stamp within the ROS time (the system clock) between
  the node's start and the peer's end, ``nanosec`` below 10^9, strictly
  increasing from one command to the next, in frame ``base_link``, with the
  controller's value;
- the same node under ``use_sim_time`` with a ``/clock`` publisher: the
  stamp is the clock's value (100.25 s, then 2,147,483,000.123456789 s, the
  largest seconds ``/clock``'s own ``int32 sec`` carries are near);
- LandShark with its command stamped from the GPS (``stamp: {from:
  ...}``, examples/landshark/landshark_gps_stamped.yaml): the newest GPS
  stamp, a negative ``sec`` included, never a wheel's;
- the laser guard and the scan guard (their ``stamp: now``) built for
  ROS 2: a scan in, the command out, with its stamp;
- the differential test of the stamp code: the Coq interpreter, the glue
  compiled by gcc -O2 and by gcc with ASan/UBSan run the same schedule
  (cycle times up to 2^64 - 1 ns, past 2038; copied stamps with negative
  seconds) and print the same stamps, the ones computed here.

Every process goes through ``ros2_env()`` (conftest) and is stopped by its
PID; the shared memory its processes leave is removed (``shm_guard``)."""

from __future__ import annotations

import shutil
import signal
import struct
import subprocess
import sys
import time

import pytest

from pyrosgen.ros2.build import build_ros2
from pyrosgen.ros2.frontend import load_model_ros2
from pyrosgen.verify.acsl import WPError, contracts, run_wp
from pyrosgen.verify.difftest import (
    Message, NodeDump, Schedule, build_c_harness, build_coq_runner, leaf_token, run_side)
from pyrosgen.ros2.wrapper import Ros2WrapperMismatch, check_rcl_wrapper

from support import expect
from support import ros as rosutil

from .conftest import run_peer, settled_leftovers, spawn, stop

LEFT, RIGHT, GPS = "/landshark/left_wheel_velocity", "/landshark/right_wheel_velocity", "/landshark/gps_velocity"
BASE = "/landshark_control/base_velocity"
TS = "geometry_msgs/TwistStamped"
STAMPED = rosutil.ROOT / "examples" / "landshark" / "landshark_stamped.yaml"
GPS_STAMPED = rosutil.ROOT / "examples" / "landshark" / "landshark_gps_stamped.yaml"
LASER = rosutil.ROOT / "examples" / "laser_guard" / "laser_guard.yaml"
SCAN_GUARD = rosutil.ROOT / "examples" / "scan_guard"
SCAN, CMD, CLOSEST = "/scan", "/cmd_vel", "/closest"
N = 1081
FAR, NEAR = 2.0, 0.5


def bits(x: float) -> int:
    return struct.unpack("<Q", struct.pack("<d", x))[0]


def stamp_ns(lv: dict) -> int:
    return lv["header.stamp.sec"] * 1_000_000_000 + lv["header.stamp.nanosec"]


def check_wall_stamps(cmds: list[dict], before_ns: int, after_ns: int) -> list[str]:
    """Every stamp within [before, after] of the system clock, its
    nanoseconds below 10^9, strictly increasing; in frame base_link."""
    problems = []
    last = None
    for lv in cmds:
        s, ns = lv["header.stamp.sec"], lv["header.stamp.nanosec"]
        if not 0 <= ns < 1_000_000_000:
            problems.append(f"nanosec {ns} out of range")
        if not before_ns <= stamp_ns(lv) <= after_ns:
            problems.append(f"stamp {s}.{ns:09d} outside the run [{before_ns / 1e9:.3f}, {after_ns / 1e9:.3f}]")
        if last is not None and stamp_ns(lv) <= last:
            problems.append(f"stamp {s}.{ns:09d} not after the previous one")
        last = stamp_ns(lv)
        if lv["header.frame_id"] != "base_link":
            problems.append(f"frame_id {lv['header.frame_id']!r}")
    return problems


@pytest.fixture(scope="module")
def stamped2(ros2_install, ros2_nodes):
    """LandShark stamped, built for ROS 2 with the bit-exact echo controller."""
    res = build_ros2(STAMPED, rosutil.CONTROLLERS / "landshark_echo", ros2_nodes / "landshark_stamped",
                     install=ros2_install)
    glue = (res.out_dir / "landshark_stamped_glue.c").read_text()
    assert "(*command).header.stamp.sec = (int)_t_uint;" in glue
    assert "(*command).header.stamp.nanosec = _t_uint;" in glue
    return res


@pytest.mark.parametrize(("old", "new", "says"), [
    ("c->sec = r->sec;\n    c->nanosec = r->nanosec;", "c->sec = r->nanosec;\n    c->nanosec = r->sec;",
     "to_c_builtin_interfaces_Time"),
    ("r->sec = c->sec;", "r->sec = (c->sec < 0 ? 0x7fffffff : c->sec);", "from_c_builtin_interfaces_Time"),
    ("return (unsigned int)(ros_now() / 1000000000ULL);", "return (unsigned int)(ros_now() / 1000000ULL);",
     "ros_time_sec()"),
    ("return (unsigned int)(ros_now() % 1000000000ULL);", "return (unsigned int)(ros_now() / 1000000000ULL);",
     "ros_time_nsec()"),
    ("            g_now_ns = ros_time_ns();", "            g_now_ns = steady_ns();", "ros_now()"),
    ("        g_now_state = 1;\n    }\n    return g_now_ns;", "    }\n    return g_now_ns;", "ros_now()"),
], ids=["sec-nanosec-swapped-in", "sec-saturated-out", "sec-in-ms", "nsec-is-sec", "now-steady-clock",
        "now-read-at-every-call"])
def test_rcl_wrapper_check_holds_the_stamp(stamped2, old, new, says):
    """check_rcl_wrapper (every build --ros2, verify) refuses a wrapper whose
    time functions or time conversions depart from the ROS time a stamp
    holds; the wrapper as rendered passes."""
    out = stamped2.out_dir
    text = (out / "landshark_stamped_rcl.c").read_text()
    proved = (out / "landshark_stamped.model").read_text()
    qos = (out / "landshark_stamped.qos").read_text()
    check_rcl_wrapper(text, proved, wrapper_name="w.c", qos_record=qos)
    assert text.count(old) == 1
    with pytest.raises(Ros2WrapperMismatch) as info:
        check_rcl_wrapper(text.replace(old, new), proved, wrapper_name="w.c", qos_record=qos)
    assert any(says in line for line in info.value.lines), info.value.lines


def test_landshark_stamped_ros2_wall_time(stamped2, ros2_install, tmp_path, shm_guard):
    v = {LEFT: 1.5, RIGHT: -2.25, GPS: 0.125}
    before = time.time_ns()
    node = spawn([stamped2.binary], tmp_path / "node.log")
    try:
        result = run_peer({"publishers": {t: TS for t in (LEFT, RIGHT, GPS)}, "subscribers": {BASE: TS},
                           "match_timeout": 20.0,
                           "steps": [{"sleep": 0.3},
                                     {"publish": {t: {"twist.linear.x": bits(x)} for t, x in v.items()}},
                                     {"sleep": 1.0}]}, tmp_path, ros2_install)
    finally:
        status = stop(node, signal.SIGTERM)
    after = time.time_ns()
    assert status == 0, (tmp_path / "node.log").read_text(errors="replace")[-2000:]
    cmds = [lv for _t, topic, lv in result["received"] if topic == BASE]
    assert len(cmds) >= 20, f"only {len(cmds)} commands"
    problems = check_wall_stamps(cmds, before, after)
    want = expect.landshark_echo({"In1": bits(v[LEFT]), "In2": bits(v[RIGHT]), "In3": bits(v[GPS])})["Out1"]
    late = [lv for t, topic, lv in result["received"] if topic == BASE and t >= result["steps"][2]["t0"] + 0.3]
    assert len(late) >= 10, f"only {len(late)} commands after the inputs"
    problems += [f"twist.linear.x {lv['twist.linear.x']:#x}, expected {want:#x}" for lv in late
                 if lv["twist.linear.x"] != want]
    assert not problems, "\n".join(problems[:20])
    assert not (left := settled_leftovers()), left


def test_landshark_gps_stamped_ros2_copies_the_gps_stamp(ros2_install, ros2_nodes, tmp_path, shm_guard):
    """``stamp: {from: /landshark/gps_velocity}`` on ROS 2: every command
    carries the stamp of the newest GPS message (zero before the first),
    a negative ``sec`` and the largest ``nanosec`` included; never a
    wheel's."""
    res = build_ros2(GPS_STAMPED, rosutil.CONTROLLERS / "landshark_echo", ros2_nodes / "landshark_gps_stamped",
                     install=ros2_install)
    gps = [(-5, 7), (2_147_483_647, 999_999_999), (1_700_000_000, 123)]
    steps = [{"sleep": 0.5}]
    for k, (sec, ns) in enumerate(gps):
        steps += [{"publish": {LEFT: {"header.stamp.sec": 11 + k, "header.stamp.nanosec": 13},
                               GPS: {"header.stamp.sec": sec, "header.stamp.nanosec": ns}}},
                  {"sleep": 0.6}]
    node = spawn([res.binary], tmp_path / "node.log")
    try:
        result = run_peer({"publishers": {t: TS for t in (LEFT, RIGHT, GPS)}, "subscribers": {BASE: TS},
                           "match_timeout": 20.0, "steps": steps}, tmp_path, ros2_install)
    finally:
        status = stop(node, signal.SIGTERM)
    assert status == 0, (tmp_path / "node.log").read_text(errors="replace")[-2000:]
    s = result["steps"]
    cmds = [(t, (lv["header.stamp.sec"], lv["header.stamp.nanosec"])) for t, tp, lv in result["received"] if tp == BASE]
    problems = [f"before any GPS message: {st}" for t, st in cmds if t < s[1]["t0"] and st != (0, 0)]
    for k, want in enumerate(gps):
        window = [st for t, st in cmds if s[1 + 2 * k]["t1"] + 0.3 <= t <= s[2 + 2 * k]["t1"]]
        if len(window) < 10:
            problems.append(f"GPS stamp {k}: only {len(window)} commands")
        problems += [f"GPS stamp {k}: got {st}, expected {want}" for st in window if st != want]
    assert not problems, "\n".join(problems[:20])
    assert not (left := settled_leftovers()), left


def _clock(sec: int, nanosec: int) -> dict:
    return {"clock.sec": sec, "clock.nanosec": nanosec}


def test_landshark_stamped_ros2_stamp_is_clock_under_use_sim_time(stamped2, ros2_install, tmp_path, shm_guard):
    clocks = [(100, 250_000_000), (2_147_483_000, 123_456_789)]
    steps = [{"stream": {"/clock": _clock(*c)}, "period": 0.05, "duration": 1.2} for c in clocks]
    node = spawn([stamped2.binary, "--ros-args", "-p", "use_sim_time:=true"], tmp_path / "node.log")
    try:
        result = run_peer({"publishers": {"/clock": "rosgraph_msgs/Clock"}, "subscribers": {BASE: TS},
                           "match_timeout": 20.0, "steps": steps}, tmp_path, ros2_install)
    finally:
        status = stop(node, signal.SIGTERM)
    assert status == 0, (tmp_path / "node.log").read_text(errors="replace")[-2000:]
    problems = []
    for (sec, ns), s in zip(clocks, result["steps"]):
        window = [lv for t, topic, lv in result["received"] if topic == BASE and s["t0"] + 0.4 <= t <= s["t1"]]
        if len(window) < 10:
            problems.append(f"clock {sec}.{ns:09d}: only {len(window)} commands")
        problems += [f"clock {sec}.{ns:09d}: stamp {lv['header.stamp.sec']}.{lv['header.stamp.nanosec']:09d}"
                     for lv in window if (lv["header.stamp.sec"], lv["header.stamp.nanosec"]) != (sec, ns)]
    assert not problems, "\n".join(problems[:20])
    assert not (left := settled_leftovers()), left


def _scan_steps(cases: list[tuple[int, tuple[int, float] | None]], hold: float) -> list[dict]:
    steps: list[dict] = [{"sleep": 0.3}]
    for length, near in cases:
        ranges = [FAR] * length
        if near is not None:
            ranges[near[0]] = near[1]
        steps += [{"publish": {SCAN: {"ranges": [bits(r) for r in ranges], "header.frame_id": "laser"}}},
                  {"sleep": hold}]
    return steps


def _run_guard(binary, ros2_install, tmp_path, cases, subscribers: dict, hold: float = 0.8):
    before = time.time_ns()
    node = spawn([binary], tmp_path / "node.log")
    try:
        result = run_peer({"publishers": {SCAN: "sensor_msgs/LaserScan"}, "subscribers": subscribers,
                           "match_timeout": 20.0, "steps": _scan_steps(cases, hold)}, tmp_path, ros2_install)
    finally:
        status = stop(node, signal.SIGTERM)
    after = time.time_ns()
    assert status == 0, (tmp_path / "node.log").read_text(errors="replace")[-2000:]
    return result, before, after


def _windows(result, topic: str, ncases: int, settle: float = 0.3) -> list[list[dict]]:
    """The messages on ``topic`` while case ``k``'s scan is the newest."""
    s = result["steps"]
    return [[lv for t, tp, lv in result["received"] if tp == topic and s[1 + 2 * k]["t1"] + settle <= t <= s[2 + 2 * k]["t1"]]
            for k in range(ncases)]


def test_laser_guard_ros2_scan_in_stamped_command_out(ros2_install, ros2_nodes, tmp_path, shm_guard):
    res = build_ros2(LASER, None, ros2_nodes / "laser_guard", install=ros2_install)
    cases = [(N, None), (N, (540, NEAR)), (N, None), (500, None)]
    speeds = [0.5, 0.0, 0.5, 0.0]  # clear; an obstacle ahead; clear; too short to reach ranges[542]
    result, before, after = _run_guard(res.binary, ros2_install, tmp_path, cases, {CMD: TS})
    problems = check_wall_stamps([lv for _t, tp, lv in result["received"] if tp == CMD], before, after)
    for k, (window, vx) in enumerate(zip(_windows(result, CMD, len(cases)), speeds)):
        if len(window) < 10:
            problems.append(f"case {k}: only {len(window)} commands")
        problems += [f"case {k}: twist.linear.x {lv['twist.linear.x']:#x}, expected {bits(vx):#x}"
                     for lv in window if lv["twist.linear.x"] != bits(vx)]
    assert not problems, "\n".join(problems[:20])
    assert not (left := settled_leftovers()), left


def test_scan_guard_ros2_scan_in_stamped_command_out(ros2_install, ros2_nodes, tmp_path, shm_guard):
    res = build_ros2(SCAN_GUARD / "scan_guard.yaml", SCAN_GUARD / "controller", ros2_nodes / "scan_guard",
                     install=ros2_install)
    cases = [(N, None), (N, (540, NEAR)), (2 * N, None), (600, None)]
    want = [(0.5, FAR), (0.0, NEAR), (0.5, FAR), (0.0, FAR)]  # (Vx, Closest); 600 ranges: the sector cut short
    result, before, after = _run_guard(res.binary, ros2_install, tmp_path, cases,
                                       {CMD: TS, CLOSEST: "std_msgs/Float32"})
    problems = check_wall_stamps([lv for _t, tp, lv in result["received"] if tp == CMD], before, after)
    for k, (cmds, closest, (vx, c)) in enumerate(zip(_windows(result, CMD, len(cases)),
                                                     _windows(result, CLOSEST, len(cases)), want)):
        if len(cmds) < 5 or len(closest) < 5:
            problems.append(f"case {k}: only {len(cmds)} commands, {len(closest)} closest")
        problems += [f"case {k}: twist.linear.x {lv['twist.linear.x']:#x}, expected {bits(vx):#x}"
                     for lv in cmds if lv["twist.linear.x"] != bits(vx)]
        problems += [f"case {k}: closest {lv['data']:#x}, expected {bits(c):#x}" for lv in closest if lv["data"] != bits(c)]
    assert not problems, "\n".join(problems[:20])
    assert not (left := settled_leftovers()), left

#: cycle times (ns): before 2038, the last second of 2^31 - 1, the first past it, 3e9 s, 2^32 s, 2^64 - 1 ns
TIMES = [500_000_000, (1 << 31) * 10**9 - 1, (1 << 31) * 10**9, 3_000_000_000 * 10**9 + 7, (1 << 32) * 10**9 + 5,
         (1 << 64) - 1]
#: the GPS stamps (sec, nanosec) received before each cycle (stamp_from)
GPS_STAMPS = [(-5, 7), (-(1 << 31), 999_999_999), ((1 << 31) - 1, 0), (0, 1), (7, (1 << 32) - 1), (-1, 5)]


def _signed32(x: int) -> int:
    x %= 1 << 32
    return x - (1 << 32) if x >= 1 << 31 else x


def _stamps(trace: str) -> list[tuple[int, int]]:
    out, cur = [], {}
    for line in trace.splitlines():
        parts = line.split()
        if parts[:2] == ["m", "header.stamp.sec"]:
            cur["sec"] = int(parts[2])
        elif parts[:2] == ["m", "header.stamp.nanosec"]:
            out.append((cur.pop("sec"), int(parts[2])))
    return out


@pytest.mark.parametrize(("model", "expected"), [
    (STAMPED, [(_signed32(t // 10**9), t % 10**9) for t in TIMES]),
    (GPS_STAMPED, GPS_STAMPS),
], ids=["stamp-now", "stamp-from"])
def test_difftest_ros2_stamps(model, expected, tmp_path):
    out = tmp_path / "out"
    proc = subprocess.run([sys.executable, "-m", "pyrosgen", "generate", "--ros2", "-q", str(model), "-o", str(out)],
                          cwd=rosutil.ROOT, capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    node = model.stem
    dump = NodeDump.from_text((out / f"{node}.sexp").read_text())
    (gps_struct,) = [s for _, t, s, _ in dump.subs if t == GPS]
    y = tuple(leaf_token(leaf, 0x3FF0000000000000) for leaf in dump.leaves(dump.y[1]))
    cycles = []
    for t, (sec, ns) in zip(TIMES, GPS_STAMPS):
        leaves = tuple(leaf_token(leaf, {"header.stamp.sec": sec, "header.stamp.nanosec": ns}.get(leaf.path, 0))
                       for leaf in dump.leaves(gps_struct))
        cycles.append(((Message(GPS, leaves, t),), y))
    sched = Schedule(tuple(cycles), tuple(TIMES), 0).text()
    work = tmp_path / "work"
    work.mkdir()
    traces = [run_side(exe, sched) for exe in (build_c_harness(out, node, work, opt="-O2"),
                                               build_c_harness(out, node, work, sanitize=True),
                                               build_coq_runner(out, node, work))]
    assert traces[0] == traces[1] == traces[2]
    assert _stamps(traces[0]) == expected


@pytest.mark.parametrize("extra", [[], ["--rebuild"], ["--model", str(STAMPED)]], ids=["verify", "rebuild", "model"])
def test_verify_stamped_ros2_folder(stamped2, extra):
    """``pyrosgen verify`` of the ROS 2 build of LandShark stamped: the .v,
    the C re-printed from the proof (the stamp's ``(int)`` cast), the
    certificate, the rcl wrapper and the package; with ``--rebuild`` the
    node compiled again bit for bit; with ``--model`` the two readings."""
    proc = subprocess.run([sys.executable, "-m", "pyrosgen", "verify", *extra, str(stamped2.out_dir)],
                          cwd=rosutil.ROOT, capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "verifies (node landshark_stamped)" in proc.stdout + proc.stderr
    if extra[:1] == ["--rebuild"]:
        assert "the same, bit for bit" in proc.stdout


SEC_STORE = "(*command).header.stamp.sec = (int)_t_uint;"


@pytest.mark.parametrize(("old", "new"), [
    (None, None),
    (SEC_STORE, "(*command).header.stamp.sec = _t_uint > 2147483647U ? 2147483647 : (int)_t_uint;"),
], ids=["proved", "sec-saturated"])
def test_wp_ros2_stamp(stamped2, ros2_install, tmp_path, old, new):
    """Frama-C WP on the ROS 2 output glue (``generate --wp``'s contracts):
    ``sec == (int)\\old(rosgen_wp_sec)`` (ACSL's cast to int wraps modulo
    2^32, as gcc's) and ``nanosec == \\old(rosgen_wp_nsec)`` are proved of
    the glue, and refused of a glue that saturates the seconds instead of
    wrapping them (the fields swapped: refuted by Coq,
    coq/tests/MutantsStampRos2.v, and by WP on ROS 1,
    tests/validation/test_wp.py)."""
    model = load_model_ros2(STAMPED, ros2_install)
    (t,) = model.published
    (c,) = [c for c in contracts(model) if c.name == t.output_glue]
    assert "command->header.stamp.sec == (int)\\old(rosgen_wp_sec)" in c.ensures
    assert "command->header.stamp.nanosec == \\old(rosgen_wp_nsec)" in c.ensures
    glue, header = stamped2.out_dir / "landshark_stamped_glue.c", stamped2.out_dir / "landshark_stamped_types.h"
    work = tmp_path / "wp"
    work.mkdir()
    text = glue.read_text()
    assert text.count(SEC_STORE) == 1
    if old is not None:
        assert text.count(old) == 1
        text = text.replace(old, new)
    (work / glue.name).write_text(text)
    shutil.copyfile(header, work / header.name)
    if old is None:
        res = run_wp(model, work / glue.name, work / header.name, work, functions=(t.output_glue,))
        assert res.ok and res.proved == res.total
        assert f"typed_{t.output_glue}_ensures : Valid" in res.output
    else:
        with pytest.raises(WPError) as info:
            run_wp(model, work / glue.name, work / header.name, work, timeout=3, functions=(t.output_glue,))
        assert "goals proved, not all" in str(info.value) and f"{t.output_glue}_ensures" in str(info.value)


@pytest.mark.parametrize("model", [STAMPED, GPS_STAMPED, LASER, SCAN_GUARD / "scan_guard.yaml"],
                         ids=lambda p: p.stem)
def test_two_readings_agree_on_ros2_stamps(model, ros2_install):
    """The N-version reading (pyrosgen/nversion, ROS 2's .msg files) and the
    front end's ROS 2 reading give the same model text for the stamped
    examples: the stamp lines, ROS 2's time message (int32 sec, uint32
    nanosec) and no ROS 1 time."""
    from pyrosgen.nversion.reader import model_text as second_reading
    from pyrosgen.proof.modeltext import model_text as first_reading

    first = first_reading(load_model_ros2(model, ros2_install))
    assert first == second_reading(model, standard_root=ros2_install.share_dir)
    lines = first.splitlines()
    assert any(line.startswith("stamp ") for line in lines)
    k = lines.index("message builtin_interfaces_Time")
    assert lines[k + 1:k + 3] == ["field sec int32", "field nanosec uint32"]
    assert "message ros_time" not in lines

"""Helpers of the real-ROS tests: the process registry, running the rospy
driver (``helpers/rosdriver.py``), bit-level value helpers, random values
for every primitive type, and the C echo harness of the wrapper round trip."""

from __future__ import annotations

import json
import os
import random
import struct
import subprocess
import time
from pathlib import Path

from pyrosgen.ros.rosmaster import RosEnv, stop_process

HERE = Path(__file__).resolve().parents[1] / "ros"
ROOT = HERE.parent.parent
DRIVER = HERE / "helpers" / "rosdriver.py"
PYTHON = "/usr/bin/python3"
CONTROLLERS = HERE / "controllers"
LANDSHARK = ROOT / "examples" / "landshark" / "landshark_controller.yaml"
LANDSHARK_CTL = ROOT / "examples" / "landshark" / "controller"
MULTI = ROOT / "examples" / "multi" / "multi_node.yaml"
MULTI_MSG = ROOT / "examples" / "multi" / "msg"
CUSTOM_MSG_PATHS = {"robot_msgs": str(MULTI_MSG / "robot_msgs" / "msg")}

#: The message types of every node in the real-ROS tests (round-tripped).
ROUNDTRIP_TYPES = {
    "twiststamped": "geometry_msgs/TwistStamped",
    "twist": "geometry_msgs/Twist",
    "odometry": "nav_msgs/Odometry",
    "imu": "sensor_msgs/Imu",
    "range": "sensor_msgs/Range",
    "estop": "robot_msgs/EStop",
    "fusionstatus": "robot_msgs/FusionStatus",
}


#: Every process (master or spawned) started by the real-ROS tests, by PID.
STARTED: list[tuple[int, str]] = []


class RecordingRosEnv(RosEnv):
    """A :class:`RosEnv` that records the PID of every process it starts."""

    def start_master(self, timeout: float = 20.0) -> None:
        try:
            super().start_master(timeout)
        finally:
            if self.proc is not None:
                STARTED.append((self.proc.pid, "rosmaster"))

    def spawn(self, argv, **kw):
        p = super().spawn(argv, **kw)
        STARTED.append((p.pid, " ".join(str(a) for a in argv)))
        return p


def alive(pid: int) -> bool:
    """Whether ``pid`` is a live (not zombie) process."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().rsplit(")", 1)[1].split()[0] != "Z"
    except (FileNotFoundError, IndexError):
        return False


# -- running things against the master ------------------------------------------

def start_node(env: RosEnv, binary: Path, log: Path) -> subprocess.Popen:
    """Start a built node (stdout and stderr to ``log``)."""
    f = open(log, "ab")
    return env.spawn([str(binary)], stdout=f, stderr=subprocess.STDOUT)


def run_driver(env: RosEnv, plan: dict, work: Path, name: str = "driver", timeout: float = 120) -> dict:
    """Run the rospy driver on ``plan``; return its result (fails the test
    on a driver error)."""
    work.mkdir(parents=True, exist_ok=True)
    plan_file, result_file, log = work / f"{name}.plan.json", work / f"{name}.result.json", work / f"{name}.log"
    plan_file.write_text(json.dumps(plan))
    with open(log, "wb") as f:
        p = env.spawn([PYTHON, str(DRIVER), str(plan_file), str(result_file)], stdout=f, stderr=subprocess.STDOUT)
        try:
            p.wait(timeout)
        except subprocess.TimeoutExpired:
            stop_process(p)
            raise AssertionError(f"the driver did not finish within {timeout} s; log:\n{log.read_text()[-3000:]}")
    assert result_file.is_file(), f"the driver wrote no result (exit {p.returncode}); log:\n{log.read_text()[-3000:]}"
    result = json.loads(result_file.read_text())
    assert "error" not in result, f"driver error:\n{result['error']}\nlog:\n{log.read_text()[-3000:]}"
    return result


def start_driver(env: RosEnv, plan: dict, work: Path, name: str) -> tuple[subprocess.Popen, Path]:
    """Start the driver in the background; :func:`finish_driver` collects it."""
    work.mkdir(parents=True, exist_ok=True)
    plan_file, result_file = work / f"{name}.plan.json", work / f"{name}.result.json"
    plan_file.write_text(json.dumps(plan))
    f = open(work / f"{name}.log", "wb")
    p = env.spawn([PYTHON, str(DRIVER), str(plan_file), str(result_file)], stdout=f, stderr=subprocess.STDOUT)
    return p, result_file


def finish_driver(p: subprocess.Popen, result_file: Path, timeout: float = 120) -> dict:
    try:
        p.wait(timeout)
    except subprocess.TimeoutExpired:
        stop_process(p)
        raise AssertionError(f"the driver did not finish within {timeout} s")
    log = result_file.with_name(result_file.name.replace(".result.json", ".log"))
    assert result_file.is_file(), f"the driver wrote no result; log:\n{log.read_text()[-3000:]}"
    result = json.loads(result_file.read_text())
    assert "error" not in result, f"driver error:\n{result['error']}\nlog:\n{log.read_text()[-3000:]}"
    return result


def received(result: dict, topic: str, t0: float | None = None, t1: float | None = None) -> list[dict]:
    """Messages received on ``topic`` between ``t0`` and ``t1``."""
    return [r for r in result["received"] if r["topic"] == topic
            and (t0 is None or r["t"] >= t0) and (t1 is None or r["t"] <= t1)]


# -- bits -----------------------------------------------------------------------------

def d(bits: int) -> str:
    """A float64 by its bits, in the driver's notation."""
    return f"d:{bits & 0xFFFFFFFFFFFFFFFF:016x}"


def f(bits: int) -> str:
    """A float32 by its bits."""
    return f"f:{bits & 0xFFFFFFFF:08x}"


def dbits(x: float) -> int:
    return struct.unpack("<Q", struct.pack("<d", x))[0]


def fbits(x: float) -> int:
    return struct.unpack("<I", struct.pack("<f", x))[0]


def bits_of(value: str) -> int:
    assert isinstance(value, str) and value[:2] in ("d:", "f:"), value
    return int(value[2:], 16)


def rotl64(b: int, n: int) -> int:
    b &= 0xFFFFFFFFFFFFFFFF
    return ((b << n) | (b >> (64 - n))) & 0xFFFFFFFFFFFFFFFF


# -- random values of every primitive type ------------------------------------------------

INT_RANGES = {
    "int8": (-2**7, 2**7 - 1), "uint8": (0, 2**8 - 1),
    "int16": (-2**15, 2**15 - 1), "uint16": (0, 2**16 - 1),
    "int32": (-2**31, 2**31 - 1), "uint32": (0, 2**32 - 1),
    "int64": (-2**63, 2**63 - 1), "uint64": (0, 2**64 - 1),
}

F64_SPECIAL = [
    0x0000000000000000, 0x8000000000000000,              # +0, -0
    0x7FF0000000000000, 0xFFF0000000000000,              # +inf, -inf
    0x7FF8000000000000, 0xFFF8000000000001,              # quiet NaNs
    0x7FF8DEADBEEF1234, 0x7FF0000000000001,              # NaN payload, signalling NaN
    0x7FF4000000C0FFEE,                                  # signalling NaN with payload
    0x0000000000000001, 0x800FFFFFFFFFFFFF,              # subnormals
    0x7FEFFFFFFFFFFFFF, 0xFFEFFFFFFFFFFFFF,              # largest finite
    0x3FF0000000000000,                                  # 1.0
]
F32_SPECIAL = [
    0x00000000, 0x80000000, 0x7F800000, 0xFF800000,
    0x7FC00000, 0xFFC00001, 0x7FC0BEEF,                  # quiet NaNs with payloads
    0x00000001, 0x807FFFFF, 0x7F7FFFFF, 0xFF7FFFFF, 0x3F800000,
]


def is_f32_snan(b: int) -> bool:
    return (b & 0x7F800000) == 0x7F800000 and (b & 0x007FFFFF) != 0 and not (b & 0x00400000)


def random_value(prim: str, rng: random.Random, mode: str = "random", path: str = ""):
    """A value of ROS primitive ``prim`` in the driver's notation.

    ``mode``: ``min``, ``max``, ``zero``, ``special`` or ``random``.
    float32 signalling NaNs are excluded: rospy holds floats as Python
    floats (doubles), and widening a float32 signalling NaN quiets it, so
    the test peer cannot send or receive one.  ``time``/``duration``
    nanoseconds stay below 10^9 (genpy normalises larger ones).
    """
    nsec = path.endswith(".nsec") or path == "nsec"
    if prim == "bool":
        return {"min": False, "max": True, "zero": False}.get(mode, rng.random() < 0.5)
    if prim in INT_RANGES:
        lo, hi = INT_RANGES[prim]
        if nsec:
            lo, hi = 0, 999_999_999
        if mode == "min":
            return lo
        if mode == "max":
            return hi
        if mode == "zero":
            return 0
        if mode == "special":
            return rng.choice([lo, hi, 0, lo + 1, hi - 1, 1 if hi > 0 else 0])
        return rng.randint(lo, hi)
    if prim == "float64":
        if mode == "zero":
            return d(0)
        if mode == "min":
            return d(0xFFEFFFFFFFFFFFFF)
        if mode == "max":
            return d(0x7FEFFFFFFFFFFFFF)
        if mode == "special":
            return d(rng.choice(F64_SPECIAL))
        return d(rng.getrandbits(64))
    if prim == "float32":
        if mode == "zero":
            return f(0)
        if mode == "min":
            return f(0xFF7FFFFF)
        if mode == "max":
            return f(0x7F7FFFFF)
        if mode == "special":
            return f(rng.choice(F32_SPECIAL))
        b = rng.getrandbits(32)
        if is_f32_snan(b):
            b |= 0x00400000
        return f(b)
    raise ValueError(prim)


def same_leaf(prim: str, sent, got) -> bool:
    """Whether the received leaf is the sent value, bit for bit."""
    if prim in ("float64", "float32"):
        return bits_of(sent) == bits_of(got)
    if prim == "bool":
        return int(sent) == got
    return sent == got


# -- the C echo harness of the wrapper round trip -----------------------------------------------

def echo_harness(model, pairs: list[tuple[str, str]]) -> str:
    """C source of a node that echoes every message of ``in`` topic on the
    ``out`` topic of each pair, through the generated C API: each callback
    copies the struct into a global ring, the loop publishes what arrived."""
    lines = [
        "/* Echo harness of the wrapper round-trip test (tests/support/ros.py). */",
        f'#include "{model.name}_ros.h"',
        "",
        "#define RING 512u",
        "unsigned long dropped;",
    ]
    main_sub, main_adv, loop = [], [], []
    for src, dst in pairs:
        ti, to = model.topic(src), model.topic(dst)
        assert ti.msg_type == to.msg_type
        s = ti.msg_struct
        c = ti.c_name
        lines += [
            f"struct {s} {c}_ring[RING];",
            f"unsigned {c}_head, {c}_tail;",
            f"static void {c}_cb(struct {s} *m)",
            "{",
            f"    if ({c}_head - {c}_tail < RING) {{",
            f"        {c}_ring[{c}_head % RING] = *m;",
            f"        {c}_head++;",
            "    } else {",
            "        dropped++;",
            "    }",
            "}",
        ]
        main_sub.append(f"    {ti.subscribe_fn}(&{c}_cb);")
        main_adv.append(f"    {to.advertise_fn}();")
        loop += [
            f"        while ({c}_tail != {c}_head) {{",
            f"            {to.publish_fn}(&{c}_ring[{c}_tail % RING]);",
            f"            {c}_tail++;",
            "        }",
        ]
    lines += ["", "int main(void)", "{", "    ros_init();", *main_sub, *main_adv,
              "    while (ros_ok()) {", "        ros_spinOnce();", *loop,
              "        ros_rate_sleep();", "    }", "    return 0;", "}", ""]
    return "\n".join(lines)


def wait_until(pred, timeout: float, step: float = 0.05) -> bool:
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if pred():
            return True
        time.sleep(step)
    return pred()


LANDSHARK_INPUTS = ("/landshark/left_wheel_velocity", "/landshark/right_wheel_velocity", "/landshark/gps_velocity")
LANDSHARK_OUTPUT = "/landshark_control/base_velocity"


def landshark_settles_on(env, work: Path, readings: tuple[float, float, float], expected: int, settle: float) -> None:
    """Publish one steady reading on each LandShark input topic of the node
    running on ``env``, wait ``settle`` seconds, and assert that every
    command of the last second is the double with bits ``expected``."""
    ts = "geometry_msgs/TwistStamped"
    plan = {
        "publishers": [{"topic": t, "type": ts} for t in LANDSHARK_INPUTS],
        "subscribers": [{"topic": LANDSHARK_OUTPUT, "type": ts}],
        "wait_messages": True,
        "steps": [{"publish": {"topic": t, "values": {"twist.linear.x": d(dbits(x))}}}
                  for t, x in zip(LANDSHARK_INPUTS, readings)] + [{"sleep": settle}],
    }
    result = run_driver(env, plan, work)
    t_end = result["steps"][-1]["t1"]
    tail = received(result, LANDSHARK_OUTPUT, t_end - 1.0, t_end)
    assert len(tail) >= 20
    got = {bits_of(r["leaves"]["twist.linear.x"]) for r in tail}
    assert got == {expected}, (f"expected {expected:#x} "
                               f"({struct.unpack('<d', struct.pack('<Q', expected))[0]}), got {sorted(got)}")

"""A generated node that sends its command in a frame (rule 4.14), on a
real master.

``examples/landshark/landshark_stamped.yaml`` gives
``/landshark_control/base_velocity`` the constant ``frame_id:
base_link``: T2 says each published command carries, in
``header.frame_id``, ``len`` 9 and the bytes of ``base_link``, every
other byte and ``truncated`` zero; the wrapper publishes the first
``len`` bytes.  The three subscribed topics are TwistStamped too, so
their ``header.frame_id`` is carried (the same ``std_msgs/Header``
struct) and converted by the wrapper, truncated to 128 bytes.  Built by
``pyrosgen build`` with the bit-exact test controller
(tests/ros/controllers/landshark_echo), run here:

- every command the node publishes has ``header.frame_id ==
  'base_link'``, from its first cycle;
- while a driver sends wheel messages whose ``header.frame_id`` is 0, 1,
  127, 128, 129 and 256 bytes long (ASCII, and multi-byte UTF-8 cut in
  the middle of a character at 128 bytes), the node keeps running and,
  after each round, publishes the controller's command for that round's
  speeds, bit for bit, still in ``base_link``.

A unit harness compiles the generated wrapper's conversions (the
``ros_api.cpp`` of the built node, included as is) with a small C++
``main`` and checks them on strings of every interesting length.
"""

from __future__ import annotations

import subprocess

import pytest

from pyrosgen.ros.build import build, pkg_config

from support import ros as rosutil
from support.ros import alive, d, dbits, run_driver, start_node

pytestmark = pytest.mark.ros

MODEL = rosutil.ROOT / "examples" / "landshark" / "landshark_stamped.yaml"
CONTROLLER = rosutil.CONTROLLERS / "landshark_echo"
CMD = "/landshark_control/base_velocity"
WHEELS = ("/landshark/left_wheel_velocity", "/landshark/right_wheel_velocity", "/landshark/gps_velocity")
TS = "geometry_msgs/TwistStamped"
#: the lengths in bytes of the frame_ids the driver sends, and what they are made of
ROUNDS = [(0, "a"), (1, "a"), (127, "a"), (128, "a"), (129, "a"), (256, "a"), (129, "é"), (256, "é")]


@pytest.fixture(scope="module")
def strings_node(nodes_dir):
    out = nodes_dir / "landshark_strings"
    res = build(MODEL, CONTROLLER, out)
    binary = out / "bin" / "landshark_stamped"
    assert binary.is_file()
    # the proved model says the command carries the constant
    assert ("string landshark_control_base_velocity header.frame_id 98,97,115,101,95,108,105,110,107"
            in res.generated.proved_model.splitlines())
    return out


def _echo(values: tuple[float, float, float]) -> int:
    """The test controller's Out1 (bits) on these speeds."""
    def rotl(b: int, n: int) -> int:
        return ((b << n) | (b >> (64 - n))) & 0xFFFFFFFFFFFFFFFF
    a, b, c = (dbits(v) for v in values)
    return a ^ rotl(b, 21) ^ rotl(c, 42) ^ dbits(1.0)


def _frame(length: int, unit: str) -> str:
    """A frame_id of ``length`` bytes in UTF-8 (``é`` is two bytes: an odd
    length ends with an ``x``)."""
    if unit == "a":
        return "a" * length
    return "é" * (length // 2) + "x" * (length % 2)


def test_every_command_is_in_base_link(ros, strings_node, tmp_path):
    node = start_node(ros, strings_node / "bin" / "landshark_stamped", tmp_path / "node.log")
    plan = {"publishers": [{"topic": t, "type": TS, "queue_size": 10} for t in WHEELS],
            "subscribers": [{"topic": CMD, "type": TS}], "wait_messages": True,
            "steps": [{"sleep": 1.0}], "linger": 0.1}
    got = rosutil.received(run_driver(ros, plan, tmp_path), CMD)
    assert len(got) >= 30, len(got)
    frames = [r["leaves"]["header.frame_id"] for r in got]
    assert all(f == {"str": "base_link"} for f in frames), [f for f in frames if f != {"str": "base_link"}][:3]
    assert alive(node.pid)


def test_received_strings_of_every_length(ros, strings_node, tmp_path):
    """The wheels' frame_ids, from empty to twice the capacity, are
    converted by the wrapper (truncated past 128 bytes); the node runs on
    and each round's command is the controller's on that round's speeds."""
    node = start_node(ros, strings_node / "bin" / "landshark_stamped", tmp_path / "node.log")
    steps, speeds = [], []
    for k, (length, unit) in enumerate(ROUNDS):
        frame = _frame(length, unit)
        assert len(frame.encode()) == length
        values = (1.0 + k, 0.5 * k - 2.0, 3.25 + k / 8)
        speeds.append(values)
        for t, v in zip(WHEELS, values):
            steps.append({"publish": {"topic": t, "values": {"twist.linear.x": d(dbits(v)),
                                                             "header.frame_id": frame}}})
        steps.append({"sleep": 0.4})
    plan = {"publishers": [{"topic": t, "type": TS, "queue_size": 10} for t in WHEELS],
            "subscribers": [{"topic": CMD, "type": TS}], "wait_messages": True,
            "steps": steps, "linger": 0.1}
    result = run_driver(ros, plan, tmp_path)
    assert alive(node.pid), (tmp_path / "node.log").read_text()[-2000:]
    got = rosutil.received(result, CMD)
    assert all(r["leaves"]["header.frame_id"] == {"str": "base_link"} for r in got)
    # the end of each round's sleep: the command is the controller's on its speeds
    per_round = len(WHEELS) + 1
    for k, values in enumerate(speeds):
        sleep = result["steps"][k * per_round + len(WHEELS)]
        tail = rosutil.received(result, CMD, sleep["t1"] - 0.15, sleep["t1"])
        assert len(tail) >= 3, (k, len(tail))
        bits = {rosutil.bits_of(r["leaves"]["twist.linear.x"]) for r in tail}
        assert bits == {_echo(values)}, (ROUNDS[k], sorted(bits))


HARNESS = r"""
#include "landshark_stamped_ros.cpp"
#include <cstdio>

// the generated conversions, on strings of every interesting length
static int check(const std::string &s)
{
    struct ros_string128 c;
    std::memset(&c, 0xAB, sizeof c);           // garbage first: the conversion must clear it
    to_c(s, &c);
    std::size_t n = s.size() < 128 ? s.size() : 128;
    if (c.len != n) return 1;
    if (c.truncated != (s.size() > 128 ? 1 : 0)) return 2;
    if (std::memcmp(c.data, s.data(), n) != 0) return 3;
    for (std::size_t i = n; i < 128; ++i) if (c.data[i] != 0) return 4;
    std::string back;
    from_c(&c, back);
    if (back != s.substr(0, 128)) return 5;
    // a corrupted len is clamped when published
    c.len = 100000;
    from_c(&c, back);
    if (back.size() != 128) return 6;
    // through the whole message
    geometry_msgs::TwistStamped r, r2;
    r.header.frame_id = s;
    struct geometry_msgs_TwistStamped m;
    std::memset(&m, 0xAB, sizeof m);
    to_c(r, &m);
    from_c(&m, r2);
    if (r2.header.frame_id != s.substr(0, 128) || m.header.frame_id.truncated != (s.size() > 128)) return 7;
    return 0;
}

int main()
{
    const std::size_t lengths[] = {0, 1, 2, 127, 128, 129, 255, 256, 1000, 100000};
    int bad = 0;
    for (std::size_t k = 0; k < sizeof lengths / sizeof lengths[0]; ++k) {
        std::string s;
        for (std::size_t i = 0; i < lengths[k]; ++i) s.push_back(char(1 + (i * 7) % 255));  // every byte but 0
        int r = check(s);
        std::printf("%zu %d\n", lengths[k], r);
        bad |= r;
    }
    std::string nul("a\0b", 3);                 // a NUL inside: bytes, not C text
    int r = check(nul);
    std::printf("nul %d\n", r);
    return bad | r;
}
"""


def test_wrapper_conversions_unit(strings_node, tmp_path):
    """The conversions of the built node's wrapper, compiled as they are
    with g++ -Wall -Wextra -Werror, on strings of 0 to 100000 bytes."""
    out = strings_node
    (tmp_path / "harness.cpp").write_text(HARNESS)
    cflags, libs = pkg_config(["roscpp", "geometry_msgs", "std_msgs"])
    exe = tmp_path / "harness"
    cmd = ["g++", "-std=c++14", "-O1", "-Wall", "-Wextra", "-Werror", "-Wno-unused-function", "-pthread",
           f"-I{out}", f"-I{out / 'include'}", *cflags, str(tmp_path / "harness.cpp"), "-o", str(exe), *libs]
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr[-3000:]
    r = subprocess.run([str(exe)], capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stdout + r.stderr
    assert r.stdout.split() == ["0", "0", "1", "0", "2", "0", "127", "0", "128", "0", "129", "0", "255", "0",
                                "256", "0", "1000", "0", "100000", "0", "nul", "0"]

"""The wrapper's ROS time on a real master, without the generator.

The wrapper of tests/ros/time_probe/time_probe.yaml (pyrosgen/ros/wrapper.py,
checked by pyrosgen.verify.wrapper_check) is linked with a hand-written C
"glue" (time_probe/time_probe_glue.c; its struct header is written here from
the model's messages) that records what ``ros_now()`` answers: in the
callback of /probe/in (the receipt time of the message), before and after
each ``ros_spinOnce()`` (the previous and this cycle's time) and after
``ros_init()``, and publishes it on /probe/out every cycle.  The design
(TIME_DESIGN, "Semantics") says:

- inside a callback: the receipt time of the message being delivered (the
  same on every read), so <= the time of the cycle whose spin delivered it;
- otherwise the time read right after the last ``ros_spinOnce()`` returned:
  before cycle i's spin, cycle i-1's time; before the first, ros_init's;
- ROS time: wall time normally; with ``use_sim_time`` and a /clock
  publisher, exactly the simulated time (roscpp's own), not wall time;
- ``ros_time_sec()``/``ros_time_nsec()`` (a stamp's fields) are the
  seconds and nanoseconds of ``ros_now()``.

Measured here: with wall time, cycle times 20 ms apart (median) and every
message's receipt time at most its delivering cycle's time; with a /clock
from 1000 s in 10 ms steps, every time ros_now() answers is one of the
published clock values (or 0 before the first), cycles 20 ms of simulated
time apart (median), receipts at the clock of their publication.
"""

from __future__ import annotations

import statistics
import struct
import subprocess
import time
import xmlrpc.client
from pathlib import Path

import pytest

from pyrosgen.frontend.validate import load_model
from pyrosgen.proof.modeltext import model_text
from pyrosgen.ros import wrapper as rosgen
from pyrosgen.ros.build import pkg_config
from pyrosgen.verify.wrapper_check import check_glue_externals, check_wrapper

from support import ros as rosutil
from support.ros import d, dbits, run_driver, start_node

pytestmark = pytest.mark.ros

PROBE = Path(__file__).resolve().parent / "time_probe"
MODEL = PROBE / "time_probe.yaml"
GLUE = PROBE / "time_probe_glue.c"
IN, OUT = "/probe/in", "/probe/out"
PERIOD_NS = 20_000_000


def types_header(model) -> str:
    """The message structs of ``model`` as Coq prints them (the real build
    takes them from Coq; this test does without the generator)."""
    lines = ["/* time_probe_types.h: written by tests/ros/test_ros_time.py */",
             "#ifndef TIME_PROBE_TYPES_H", "#define TIME_PROBE_TYPES_H", ""]
    for m in model.messages:
        lines.append(f"struct {m.c_name} {{")
        for f in m.fields:
            lines.append(f"    {f.c_type} {f.name}{f'[{f.array_len}]' if f.is_array else ''};")
        lines += ["};", ""]
    return "\n".join(lines + ["#endif", ""])


@pytest.fixture(scope="module")
def probe(tmp_path_factory) -> Path:
    """The time probe's binary: the wrapper (checked) and the hand-written glue."""
    d_ = tmp_path_factory.mktemp("time_probe")
    model = load_model(MODEL)
    files = rosgen.render_wrapper(model)
    names = rosgen.wrapper_files(model)
    check_wrapper(files[names.api_source], model_text(model), wrapper_name=names.api_source)
    check_glue_externals(GLUE.read_text(), files[names.api_header], glue_name=GLUE.name,
                         header_name=names.api_header)
    for name, text in files.items():
        (d_ / name).write_text(text)
    (d_ / names.types_header).write_text(types_header(model))
    (d_ / GLUE.name).write_text(GLUE.read_text())
    cflags, libs = pkg_config(rosgen.ros_pkg_config_modules(model))

    def run(argv):
        r = subprocess.run(argv, cwd=d_, capture_output=True, text=True)
        assert r.returncode == 0, f"{' '.join(argv)}:\n{r.stderr}"

    run(["gcc", *rosgen.GLUE_CFLAGS, "-I", ".", "-c", GLUE.name, "-o", "glue.o"])
    run(["g++", *rosgen.WRAPPER_CXXFLAGS, "-I", ".", *cflags, "-c", names.api_source, "-o", "ros.o"])
    run(["g++", "-pthread", "glue.o", "ros.o", "-o", "time_probe", *libs])
    return d_ / "time_probe"


# -- reading the probe's messages ------------------------------------------------

def _num(leaves: dict, path: str) -> float:
    return struct.unpack("<d", struct.pack("<Q", rosutil.bits_of(leaves[path])))[0]


def _time(leaves: dict, k: int) -> int:
    hi, lo = _num(leaves, f"pose.covariance[{k}]"), _num(leaves, f"pose.covariance[{k + 1}]")
    assert hi == int(hi) and lo == int(lo) and 0 <= lo < 2**32
    return (int(hi) << 32) | int(lo)


def cycles(result: dict) -> list[dict]:
    """The probe's cycles, in order, as dicts of integers (ns)."""
    out = []
    for r in rosutil.received(result, OUT):
        lv = r["leaves"]
        out.append({
            "cycle": lv["header.seq"],
            "now": lv["header.stamp.sec"] * 10**9 + lv["header.stamp.nsec"],
            "receipt": _time(lv, 0),
            "seq": _num(lv, "pose.covariance[2]"),
            "before": _time(lv, 3),
            "init": _time(lv, 5),
            "callbacks": int(_num(lv, "pose.covariance[7]")),
            "spin_callbacks": int(_num(lv, "pose.covariance[8]")),
            "spin_min_receipt": _time(lv, 9),
            "unstable": int(_num(lv, "pose.covariance[11]")),
            "backwards": int(_num(lv, "pose.covariance[12]")),
            "first_before": _time(lv, 13),
            "split_errors": int(_num(lv, "pose.covariance[15]")),
            "t": r["t"],
        })
    return out


def check_common(cs: list[dict], sent: int) -> None:
    """What holds in wall and in simulated time alike."""
    assert len(cs) >= 10, f"only {len(cs)} cycles"
    # (the node's first cycles publish before the test's subscriber is connected)
    assert [c["cycle"] for c in cs] == list(range(cs[0]["cycle"], cs[0]["cycle"] + len(cs))), "a cycle was lost"
    init = cs[0]["init"]
    assert all(c["init"] == init and c["first_before"] == init for c in cs)
    # before the first spin: ros_init's time; before cycle i's: cycle i-1's
    for prev, c in zip(cs, cs[1:]):
        assert c["before"] == prev["now"], (prev, c)
    assert init <= cs[0]["before"] <= cs[0]["now"]
    # ros_now() inside a callback: the same on every read; receipts in order
    assert cs[-1]["unstable"] == 0 and cs[-1]["backwards"] == 0
    # ros_time_sec()/ros_time_nsec() (the stamp, header.stamp here): the same time
    assert cs[-1]["split_errors"] == 0
    # receipt time <= the time of the cycle whose spin delivered the message
    for c in cs:
        if c["spin_callbacks"]:
            assert c["spin_min_receipt"] <= c["receipt"] <= c["now"], c
        if c["callbacks"]:
            assert c["receipt"] <= c["now"]
    # every message arrived, the newest last
    assert cs[-1]["callbacks"] == sent and cs[-1]["seq"] == sent - 1


# -- the tests --------------------------------------------------------------------

def test_ros_now_in_wall_time(ros, probe, tmp_path):
    wall0 = time.time_ns()
    start_node(ros, probe, tmp_path / "node.log")
    n = 40
    steps = []
    for k in range(n):
        steps += [{"publish": {"topic": IN, "values": {"linear.x": d(dbits(float(k)))}}}, {"sleep": 0.037}]
    plan = {"publishers": [{"topic": IN, "type": "geometry_msgs/Twist", "queue_size": 1000}],
            "subscribers": [{"topic": OUT, "type": "nav_msgs/Odometry"}],
            "wait_messages": True, "steps": steps, "linger": 0.3}
    result = run_driver(ros, plan, tmp_path)
    wall1 = time.time_ns()
    cs = cycles(result)
    check_common(cs, n)
    # wall time: between the test's own readings of the clock
    assert wall0 <= cs[0]["init"] and cs[-1]["now"] <= wall1
    for c in cs:
        if c["callbacks"]:
            assert wall0 <= c["receipt"] <= wall1
    # cycle times increase, by the period
    diffs = [b["now"] - a["now"] for a, b in zip(cs, cs[1:])]
    assert all(x > 0 for x in diffs)
    med = statistics.median(diffs)
    assert abs(med - PERIOD_NS) <= 2_000_000, f"median cycle {med / 1e6:.3f} ms"
    # a message sent every 37 ms: the cycle that delivers it comes within a period or so
    lags = [c["now"] - c["receipt"] for c in cs if c["spin_callbacks"]]
    assert len(lags) >= n * 0.9
    assert statistics.median(lags) <= PERIOD_NS + 2_000_000, f"median lag {statistics.median(lags) / 1e6:.3f} ms"
    print(f"wall time: {len(cs)} cycles, median {med / 1e6:.3f} ms, max {max(diffs) / 1e6:.3f} ms; "
          f"receipt -> cycle median {statistics.median(lags) / 1e6:.3f} ms, max {max(lags) / 1e6:.3f} ms")


def _set_param(ros, name: str, value) -> None:
    code, msg, _ = xmlrpc.client.ServerProxy(ros.uri).setParam("/pyrosgen_test", name, value)
    assert code == 1, msg


def test_ros_now_follows_simulated_time(ros, probe, tmp_path):
    """use_sim_time with a /clock from 1000 s, 10 ms per step: ros_now()
    answers only published clock values (0 before the first), never wall
    time; cycles are 20 ms of simulated time apart; a message's receipt
    time is the clock published just before it."""
    _set_param(ros, "/use_sim_time", True)
    start_node(ros, probe, tmp_path / "node.log")
    base, step_ns, ticks = 1000 * 10**9, 10_000_000, 250
    clock = [base + k * step_ns for k in range(ticks)]
    steps, sent_at = [], []
    for k, t in enumerate(clock):
        steps.append({"publish": {"topic": "/clock", "values": {"clock.sec": t // 10**9, "clock.nsec": t % 10**9}}})
        if k % 10 == 5:
            # a message 3 ms (wall) after this clock value, 7 ms before the next
            steps.append({"sleep": 0.003})
            steps.append({"publish": {"topic": IN, "values": {"linear.x": d(dbits(float(len(sent_at))))}}})
            steps.append({"sleep": 0.007})
            sent_at.append(t)
        else:
            steps.append({"sleep": 0.01})
    plan = {"publishers": [{"topic": "/clock", "type": "rosgraph_msgs/Clock", "queue_size": 1000},
                           {"topic": IN, "type": "geometry_msgs/Twist", "queue_size": 1000}],
            "subscribers": [{"topic": OUT, "type": "nav_msgs/Odometry"}],
            # (no wait for a message: the node publishes nothing until the clock runs)
            "steps": steps, "linger": 0.5}
    result = run_driver(ros, plan, tmp_path)
    cs = cycles(result)
    check_common(cs, len(sent_at))
    allowed = set(clock)
    # every time ros_now() answered is a published clock value, or 0 before the first
    assert cs[0]["init"] == 0 or cs[0]["init"] in allowed
    for c in cs:
        assert c["now"] == 0 or c["now"] in allowed, c
        assert c["before"] == 0 or c["before"] in allowed, c
        if c["callbacks"]:
            assert c["receipt"] in allowed, c
    timed = [c for c in cs if c["now"]]
    assert len(timed) >= 30, f"only {len(timed)} cycles in simulated time"
    assert timed[0]["now"] >= base and timed[-1]["now"] <= clock[-1]
    # the node cannot run more cycles than the simulated time allows
    assert len(timed) <= (clock[-1] - timed[0]["now"]) // PERIOD_NS + 2
    diffs = [b["now"] - a["now"] for a, b in zip(timed, timed[1:])]
    # (ros::Rate does not sleep after an overrun, such as the clock's jump from
    # 0 to 1000 s: then two cycles see the same simulated time)
    assert all(x >= 0 and x % step_ns == 0 for x in diffs), diffs
    assert sum(1 for x in diffs if x == 0) <= 2, diffs
    assert statistics.median(diffs) == PERIOD_NS, f"median cycle {statistics.median(diffs) / 1e6} ms (simulated)"
    # each message's receipt time: the clock published just before it.  roscpp
    # takes /clock on a thread of its own, so under load the node may not have
    # read that clock value yet, or already the next: one step either side.
    receipts: dict[int, int] = {}
    for c in cs:
        if c["spin_callbacks"] == 1:  # one message in this spin: the newest is it
            receipts[int(c["seq"])] = c["receipt"]
    assert len(receipts) >= len(sent_at) * 0.8
    off = [receipts[k] - sent_at[k] for k in sorted(receipts)]
    assert all(abs(o) <= step_ns for o in off), off
    exact = sum(1 for o in off if o == 0)
    assert exact >= len(off) * 0.5, off
    print(f"simulated time: {len(timed)} cycles from {timed[0]['now'] / 1e9:.3f} s to {timed[-1]['now'] / 1e9:.3f} s, "
          f"median {statistics.median(diffs) / 1e6:.1f} ms; receipts exactly at the clock of publication: "
          f"{exact}/{len(off)}")

"""Robustness of a built node on a real master: outputs before any input,
its period under a message flood, a master restart, bounded memory."""

from __future__ import annotations

import random
import time
import xmlrpc.client

from pyrosgen.frontend.validate import load_model

from support import expect
from support import ros as rosutil
from support.ros import finish_driver, received, run_driver, start_driver, start_node

LEFT, RIGHT, GPS = "/landshark/left_wheel_velocity", "/landshark/right_wheel_velocity", "/landshark/gps_velocity"
BASE = "/landshark_control/base_velocity"
TS = "geometry_msgs/TwistStamped"
NODE = "landshark_controller"


def test_zero_based_outputs_before_any_input(ros, multi_echo, tmp_path):
    """The subscriber is up before the node starts and nobody publishes its
    inputs: every output the node publishes, from the first one, is the
    controller's response to all-zero inputs."""
    model = load_model(rosutil.MULTI)
    plan = {
        "msg_paths": rosutil.CUSTOM_MSG_PATHS,
        "subscribers": [{"topic": t.name, "type": t.msg_type} for t in model.published],
        "connect_timeout": 60,
        "steps": [{"wait_count": {"topic": t.name, "count": 20, "timeout": 20}} for t in model.published],
    }
    p, result_file = start_driver(ros, plan, tmp_path, "zero")
    time.sleep(1.0)  # the driver subscribes first
    start_node(ros, multi_echo / "bin" / "multi_node", tmp_path / "node.log")
    result = finish_driver(p, result_file)
    y = expect.multi_echo(expect.zero_inputs(model))
    problems = []
    for t in model.published:
        msgs = received(result, t.name)
        assert len(msgs) >= 20
        for r in msgs:
            problems += expect.check_published(model, t.name, y, r["leaves"])
    assert not problems, "\n".join(problems[:20])
    # and the response to zeros is not all zeros: the check has teeth
    assert y["CmdV"] == rosutil.dbits(1.0) and y["SeqOut"] == 0xA5A5A5A5


def test_period_kept_under_a_10x_flood(ros, landshark_echo, tmp_path):
    """Every input topic flooded at 10x the node's rate (500 Hz each): the
    node's mean output period, measured at the subscriber over 5 s, stays
    within 10% of period_ms, and every output is still the controller's
    response to the newest messages."""
    model = load_model(rosutil.LANDSHARK)
    period = model.period_ms / 1000.0
    rng = random.Random(99)
    msgs = {t: expect.random_message(model, TS, rng, "random") for t in (LEFT, RIGHT, GPS)}
    plan = {
        "publishers": [{"topic": t, "type": TS, "queue_size": 1000} for t in (LEFT, RIGHT, GPS)],
        "subscribers": [{"topic": BASE, "type": TS}],
        "wait_messages": True,
        "steps": [{"flood": {"messages": msgs, "rate": 10 / period, "duration": 6.0}}],
    }
    start_node(ros, landshark_echo / "bin" / NODE, tmp_path / "node.log")
    result = run_driver(ros, plan, tmp_path)
    flood = result["steps"][0]
    assert result["published"] >= 3 * 500 * 6.0 * 0.8, f"the flood was too thin: {result['published']} messages"
    window = received(result, BASE, flood["t0"] + 1.0, flood["t1"])
    assert len(window) > 100
    mean = (window[-1]["t"] - window[0]["t"]) / (len(window) - 1)
    print(f"flood: {result['published']} messages in {flood['t1'] - flood['t0']:.1f} s; mean output period {mean * 1000:.3f} ms over {len(window)} outputs")
    assert abs(mean - period) <= 0.1 * period, f"mean period {mean * 1000:.2f} ms under the flood"
    y = expect.landshark_echo(expect.inputs_from(model, msgs))
    problems = [p for r in window for p in expect.check_published(model, BASE, y, r["leaves"])]
    assert not problems, "\n".join(problems[:10])


def test_master_restart(ros, landshark_echo, tmp_path):
    """Stop the master and start it again on the same port while the node
    runs.  roscpp alone keeps its existing connections but never registers
    again with the new master; the wrapper's watchdog does: a peer that
    starts after the restart finds the node, feeds it and gets its outputs."""
    model = load_model(rosutil.LANDSHARK)
    node = start_node(ros, landshark_echo / "bin" / NODE, tmp_path / "node.log")
    # A: an old peer, connected before the restart, listening throughout
    old_plan = {"subscribers": [{"topic": BASE, "type": TS, "record": "time"}],
                "wait_messages": True, "steps": [{"sleep": 9.0}]}
    pa, fa = start_driver(ros, old_plan, tmp_path, "old")
    time.sleep(3.0)
    t_stop = time.monotonic()
    old_master = {ros.proc.pid}
    ros.stop_master()
    time.sleep(1.0)
    ros.start_master()
    t_start = time.monotonic()
    master = xmlrpc.client.ServerProxy(ros.uri)
    # a new master process: it can only learn of the node from the node
    assert ros.proc.pid not in old_master

    def registered():
        _, _, (pubs, subs, _srv) = master.getSystemState("/test")
        return any(t == BASE and f"/{NODE}" in n for t, n in pubs) and \
            sum(1 for t, n in subs if f"/{NODE}" in n) == 3

    assert rosutil.wait_until(registered, 10.0), f"the node did not register again: {master.getSystemState('/test')}"
    # B: a new peer
    rng = random.Random(5)
    msgs = {t: expect.random_message(model, TS, rng, "random") for t in (LEFT, RIGHT, GPS)}
    new_plan = {
        "publishers": [{"topic": t, "type": TS} for t in (LEFT, RIGHT, GPS)],
        "subscribers": [{"topic": BASE, "type": TS}],
        "wait_messages": True,
        "steps": [*({"publish": {"topic": t, "values": v}} for t, v in msgs.items()), {"sleep": 1.0}],
    }
    rb = run_driver(ros, new_plan, tmp_path, "new")
    y = expect.landshark_echo(expect.inputs_from(model, msgs))
    last = received(rb, BASE, rb["steps"][-1]["t0"] + 0.5, rb["steps"][-1]["t1"])
    assert len(last) >= 10
    problems = [p for r in last for p in expect.check_published(model, BASE, y, r["leaves"])]
    assert not problems, "\n".join(problems[:10])
    ra = finish_driver(pa, fa)
    times = [r["t"] for r in received(ra, BASE)]
    around = [t for t in times if t_stop - 1.0 <= t <= t_start + 1.0]
    gaps = [b - a for a, b in zip(around, around[1:])]
    assert around and max(gaps) < 0.5, f"the old peer's stream stopped around the restart (max gap {max(gaps, default=None)})"
    assert node.poll() is None


def _rss_kib(pid: int) -> int:
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
    raise AssertionError("no VmRSS")


def test_memory_bounded_over_60_s(ros, landshark_echo, tmp_path):
    """Under steady traffic (every input at the node's rate, one subscriber),
    the node's resident memory does not grow between 10 s and 60 s by more
    than 256 KiB."""
    model = load_model(rosutil.LANDSHARK)
    rng = random.Random(3)
    msgs = {t: expect.random_message(model, TS, rng, "random") for t in (LEFT, RIGHT, GPS)}
    node = start_node(ros, landshark_echo / "bin" / NODE, tmp_path / "node.log")
    plan = {
        "publishers": [{"topic": t, "type": TS} for t in (LEFT, RIGHT, GPS)],
        "subscribers": [{"topic": BASE, "type": TS, "record": "time"}],
        "wait_messages": True,
        "steps": [{"flood": {"messages": msgs, "rate": 1000.0 / model.period_ms, "duration": 62.0}}],
    }
    t0 = time.monotonic()
    p, rf = start_driver(ros, plan, tmp_path, "traffic")
    samples = []
    while p.poll() is None and time.monotonic() - t0 < 90:
        samples.append((time.monotonic() - t0, _rss_kib(node.pid)))
        time.sleep(1.0)
    result = finish_driver(p, rf)
    assert len(received(result, BASE)) > 2500
    base = [kib for t, kib in samples if 9.0 <= t <= 11.0]
    late = [kib for t, kib in samples if 11.0 < t <= 62.0]
    assert base and len(late) > 40, samples
    growth = max(late) - min(base)
    print(f"RSS at ~10 s: {min(base)} KiB; max 11-62 s: {max(late)} KiB; growth {growth} KiB")
    assert growth < 256, f"RSS grew by {growth} KiB: {samples}"

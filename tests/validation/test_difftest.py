"""Differential tests (pyrosgen/verify/difftest.py): the Coq interpreter
(``Interp.run_program``, extracted to OCaml) and the printed glue compiled by
gcc (with a fake ROS C API and a table-driven test controller) run the same
random message schedules and must print the same trace, byte for byte.

Schedules have 0 to 5 cycles; each cycle gets bursts of 1 to 7 messages on
random topics (subscribed ones, published ones and a topic nobody
subscribes to; bursts are longer than the queues of size 1 and 5), or none;
leaf values include NaNs with payloads (quiet and signalling, both signs),
infinities, -0.0, subnormals and the integer extremes.  The C side runs
twice: built with -O2, and with -fsanitize=address,undefined
-fno-sanitize-recover=all; both built with -std=c11 -Wall -Wextra -Werror
-pedantic.  The C trace is also checked against an oracle computed here
from the model (the newest message's fields, the outputs' fields, zeros;
for timed topics, rule 4.12, the fallbacks of stale topics and the derived
inputs).

Every message has a receipt time and every cycle a time (what ``ros_now``
answers), drawn so that the models with timed topics (the velocity guard,
tests/generate/models/ok_fresh_*.yaml) meet each case: a topic fresh,
stale, exactly at its timeout, never received, a clock that went back (a
receipt after the cycle's time: age 0), an age too large for ``age_ms``;
the tests count the cases the oracle saw and require each.
"""

from __future__ import annotations

import random
import re
import shutil
import struct
from dataclasses import dataclass
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from pyrosgen.verify.difftest import (
    GCC_STRICT, MAX_TIME, Message, NodeDump, Schedule, build_c_harness, build_coq_runner, leaf_token, run_side)
from pyrosgen.frontend.validate import load_model

from support.validation import EXAMPLES, TIMED_EXAMPLES

EXAMPLES_PER_MODEL = 100
NOBODY = "/difftest/nobody"

F64_SPECIAL = [0, 1 << 63, 1, 0x8000000000000001, 0x000FFFFFFFFFFFFF, 0x0010000000000000,
               0x7FEFFFFFFFFFFFFF, 0xFFEFFFFFFFFFFFFF, 0x7FF0000000000000, 0xFFF0000000000000,
               0x7FF8000000000000, 0xFFF8000000000000, 0x7FF8000000000123, 0x7FF0000000000001,
               0xFFF4000000000abc, 0x3FF0000000000000, 0x3FB999999999999A]
F32_SPECIAL = [0, 1 << 31, 1, 0x80000001, 0x007FFFFF, 0x00800000, 0x7F7FFFFF, 0xFF7FFFFF,
               0x7F800000, 0xFF800000, 0x7FC00000, 0xFFC00000, 0x7FC00123, 0x7F800001,
               0xFFA00abc, 0x3F800000, 0x3DCCCCCD]


@dataclass
class Sides:
    dump: NodeDump
    model: object
    c: Path
    c_san: Path
    coq: Path


ALL = {**EXAMPLES, **TIMED_EXAMPLES}


@pytest.fixture(scope="session")
def sides(generated, generated_timed, tmp_path_factory) -> dict[str, Sides]:
    """Each model's three executables, built once per session."""
    out = {}
    for key, node in {**generated, **generated_timed}.items():
        work = tmp_path_factory.mktemp(f"difftest_{key}")
        out[key] = Sides(
            dump=NodeDump.from_text(node.sexp.read_text()),
            model=load_model(ALL[key][0]),
            c=build_c_harness(node.out, node.node, work, opt="-O2"),
            c_san=build_c_harness(node.out, node.node, work, sanitize=True),
            coq=build_coq_runner(node.out, node.node, work),
        )
    return out


# ---------------------------------------------------------------------------
# Schedules

def _value(rnd: random.Random, leaf) -> int:
    if leaf.kind == "f64":
        return rnd.choice(F64_SPECIAL) if rnd.random() < 0.4 else rnd.getrandbits(64)
    if leaf.kind == "f32":
        return rnd.choice(F32_SPECIAL) if rnd.random() < 0.4 else rnd.getrandbits(32)
    lo, hi = (-(1 << (leaf.bits - 1)), (1 << (leaf.bits - 1)) - 1) if leaf.kind == "signed" else (0, (1 << leaf.bits) - 1)
    if rnd.random() < 0.4:
        return rnd.choice([lo, hi, 0, 1, hi - 1] + ([-1, lo + 1] if lo else []))
    return rnd.randint(lo, hi)


def _values(rnd: random.Random, leaves) -> tuple[str, ...]:
    return tuple(leaf_token(leaf, _value(rnd, leaf)) for leaf in leaves)


MS = 1_000_000                 # ns
MAX_AGE = 4294967295999999     # the largest age (ns) whose milliseconds fit in a uint32
NO_AGE = MAX_TIME              # the age of a topic without message


def _clamp(t: int) -> int:
    return min(max(t, 0), MAX_TIME)


def _step(rnd: random.Random, timeouts: list[int]) -> int:
    """How far a cycle's time is from the previous one: the period, an
    exact timeout (and one nanosecond either side), nothing, a jump back,
    or beyond what age_ms can say."""
    t = rnd.choice(timeouts or [20]) * MS
    return rnd.choice([20 * MS, rnd.randint(0, 3 * t), t, t + 1, t - 1, 0, -rnd.randint(1, 2 * t),
                       MAX_AGE, MAX_AGE + 1, 1 << 62])


def _receipt(rnd: random.Random, prev: int, now: int, timeouts: list[int]) -> int:
    """A receipt time: between the previous cycle's time and this one's
    (mostly), exactly a timeout before this cycle's time (and 1 ns either
    side), after it (a clock that goes back), or far from it."""
    t = rnd.choice(timeouts or [20]) * MS
    lo, hi = min(prev, now), max(prev, now)
    return _clamp(rnd.choice([rnd.randint(lo, hi), rnd.randint(lo, hi), now - t, now - t - 1, now - t + 1,
                              now, now + rnd.randint(1, t), 0, rnd.getrandbits(64)]))


@st.composite
def schedules(draw, dump: NodeDump, timeouts: tuple[int, ...] = ()) -> Schedule:
    """Random schedules; the structure (cycles, bursts, topics) is drawn by
    hypothesis, the leaf values and times by a hypothesis-seeded generator
    biased towards special values (``timeouts``: the model's, in ms)."""
    rnd = draw(st.randoms(use_true_random=False))
    tos = list(timeouts)
    topics = [(t, st_) for _, t, st_, _ in dump.subs] + [(t, st_) for _, t, st_ in dump.pubs] + [(NOBODY, None)]
    cycles, times = [], []
    now = t0 = rnd.choice([0, 1, rnd.getrandbits(40), MAX_TIME - rnd.getrandbits(20), rnd.getrandbits(64)])
    for _ in range(draw(st.integers(0, 8 if tos else 5))):
        prev, now = now, _clamp(now + _step(rnd, tos))
        msgs: list[Message] = []
        for _ in range(draw(st.integers(0, 3))):          # bursts
            topic, struct = draw(st.sampled_from(topics))
            for _ in range(draw(st.integers(1, 10))):   # a burst
                if struct is None:
                    leaves = tuple(str(rnd.randint(-5, 5)) for _ in range(rnd.randint(0, 4)))
                else:
                    leaves = _values(rnd, dump.leaves(struct))
                msgs.append(Message(topic, leaves, _receipt(rnd, prev, now, tos)))
        if msgs and draw(st.booleans()):
            rnd.shuffle(msgs)                              # interleave the bursts
        cycles.append((tuple(msgs), _values(rnd, dump.leaves(dump.y[1]))))
        times.append(now)
    return Schedule(tuple(cycles), tuple(times), t0)


# ---------------------------------------------------------------------------
# The oracle: what the C trace must say, computed from the model

def _zero(leaf) -> str:
    return leaf_token(leaf, 0)


def expected_trace(model, dump: NodeDump, sched: Schedule, seen: dict | None = None) -> str:
    """The trace the glue must print.  ``seen`` counts the freshness cases
    met (``fresh``, ``stale``, ``boundary``, ``never``, ``back``,
    ``saturated``, ``new``), per timed topic and cycle."""
    lines: list[str] = []
    newest: dict[str, tuple[str, ...]] = {}
    received: dict[str, int] = {}                      # topic -> newest receipt time
    new: set[str] = set()
    u_leaves = dump.leaves(dump.u[1])
    y_leaves = dump.leaves(dump.y[1])
    rel_in = {r.input_field: r for r in model.input_relations}
    der_in = {r.input_field: r for r in model.derived_relations}
    subscribed = {t.name for t in model.subscribed}
    timed = model.timed_topics
    count = (lambda case: seen.__setitem__(case, seen.get(case, 0) + 1)) if seen is not None else (lambda c: None)
    for k, (msgs, y) in enumerate(sched.cycles):
        for m in msgs:
            if m.topic in subscribed:   # the newest message is always delivered
                newest[m.topic] = m.leaves
                received[m.topic] = m.time
                new.add(m.topic)
        now = sched.cycle_time(k)
        age: dict[str, int] = {}
        for t in timed:
            if t.name not in received:
                age[t.name] = NO_AGE
                count("never")
            else:
                back = received[t.name] > now
                age[t.name] = 0 if back else now - received[t.name]
                count("back" if back else "received")
                if t.timeout_ms is not None:
                    limit = t.timeout_ms * MS
                    count("boundary" if age[t.name] == limit else "stale" if age[t.name] > limit else "fresh")
            count("saturated" if age[t.name] > MAX_AGE else "in range")
            count("new" if t.name in new else "not new")
        lines.append("step")
        for leaf in u_leaves:
            r, d = rel_in.get(leaf.path), der_in.get(leaf.path)
            if d is not None:
                a = age[d.topic.name]
                v = {"is_new": int(d.topic.name in new), "received": int(d.topic.name in received),
                     "age_ms": a // MS if a <= MAX_AGE else 4294967295}[d.kind]
                lines.append(f"  u {leaf.path} {v}")
            elif r is not None and r.fallback is not None and r.topic.timeout_ms * MS < age[r.topic.name]:
                lines.append(f"  u {leaf.path} {leaf_token(leaf, r.fallback.n)}")
            elif r is not None and r.topic.name in newest:
                src = dump.leaves(r.topic.msg_struct)
                k_ = [s.path for s in src].index(str(r.path))
                lines.append(f"  u {leaf.path} {newest[r.topic.name][k_]}")
            else:
                lines.append(f"  u {leaf.path} {_zero(leaf)}")
        new.clear()
        ytab = {leaf.path: v for leaf, v in zip(y_leaves, y)}
        lines += [f"  y {leaf.path} {v}" for leaf, v in zip(y_leaves, y)]
        for t in model.published:
            rels = {str(r.path): r.output_field for r in model.output_relations_of(t)}
            lines.append(f"publish {t.name}")
            for leaf in dump.leaves(t.msg_struct):
                v = ytab[rels[leaf.path]] if leaf.path in rels else _zero(leaf)
                lines.append(f"  m {leaf.path} {v}")
        lines.append("cycle")
    return "\n".join(lines) + ("\n" if lines else "")


def _check(s: Sides, sched: Schedule, seen: dict | None = None) -> str:
    text = sched.text()
    c = run_side(s.c, text)
    coq = run_side(s.coq, text)
    assert c == coq, f"C and Coq traces differ on the schedule:\n{text}"
    assert run_side(s.c_san, text) == c, f"the sanitized build differs on:\n{text}"
    assert c == expected_trace(s.model, s.dump, sched, seen), f"the trace is not the oracle's on:\n{text}"
    return c


def _timeouts(model) -> tuple[int, ...]:
    return tuple(t.timeout_ms for t in model.topics if t.timeout_ms is not None)


def _freshness_schedule(s: Sides, rnd: random.Random) -> Schedule:
    """One schedule that meets every freshness case of every timed topic:
    a cycle before any message (never), messages received after their
    cycle's time (a clock that went back), then one period later (in
    range, fresh), messages exactly a timeout old (boundary), one
    nanosecond later (stale), and an age beyond what ``age_ms`` can say
    (saturated).  The random schedules meet them by chance only (how often
    depends on what hypothesis draws)."""
    subs = [(t, st_) for _, t, st_, _ in s.dump.subs]
    timeout = {t.name: t.timeout_ms for t in s.model.timed_topics if t.timeout_ms is not None}
    y = lambda: _values(rnd, s.dump.leaves(s.dump.y[1]))  # noqa: E731
    msgs = lambda receipt: tuple(Message(t, _values(rnd, s.dump.leaves(st_)), receipt(t))  # noqa: E731
                                 for t, st_ in subs)
    t0 = rnd.randint(1, 1 << 40) * MS
    t1, t2, t3 = t0 + 10 * MS, t0 + 30 * MS, t0 + 50 * MS
    t4 = t3 + 10_000 * MS
    cycles = [((), y()),                                              # never
              (msgs(lambda t: t2 + 1), y()),                          # back
              ((), y()),                                              # received, in range
              (msgs(lambda t: t4 - timeout.get(t, 20) * MS), y()),    # boundary
              ((), y()),                                              # stale
              ((), y())]                                              # saturated
    return Schedule(tuple(cycles), (t1, t2, t3, t4, t4 + 1, t4 + MAX_AGE + 1), t0)


# ---------------------------------------------------------------------------

@pytest.mark.parametrize("key", list(ALL))
def test_random_schedules(sides, key):
    s = sides[key]
    seen = {"cycles": 0, "messages": 0, "empty": 0}

    @settings(max_examples=EXAMPLES_PER_MODEL, deadline=None, derandomize=True,
              suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
    @given(schedules(s.dump, _timeouts(s.model)))
    def run(sched: Schedule) -> None:
        _check(s, sched, seen)
        seen["cycles"] += len(sched.cycles)
        seen["messages"] += sum(len(m) for m, _ in sched.cycles)
        seen["empty"] += sum(1 for m, _ in sched.cycles if not m)

    run()
    if key in TIMED_EXAMPLES:
        # and, whatever hypothesis drew, each freshness case on purpose
        for k in range(3):
            _check(s, _freshness_schedule(s, random.Random(k)), seen)
    # the schedules did exercise something: more than one cycle and five
    # messages per schedule on average (what hypothesis draws varies with
    # what it drew before in the process: bursts of up to 7 messages gave
    # multi 543 messages in 100 schedules in one run, too close to 500;
    # bursts go up to 10)
    assert seen["cycles"] > EXAMPLES_PER_MODEL and seen["messages"] > 5 * EXAMPLES_PER_MODEL, seen
    assert seen["empty"] > 0, seen
    if key in TIMED_EXAMPLES:
        # every freshness case, several times
        cases = ["never", "received", "back", "saturated", "in range", "new", "not new"]
        if _timeouts(s.model):
            cases += ["fresh", "stale", "boundary"]
        assert all(seen.get(c, 0) >= 3 for c in cases), {c: seen.get(c, 0) for c in cases}


@pytest.mark.parametrize("key", list(ALL))
def test_edge_schedules(sides, key):
    """Hand-made schedules: no cycle, cycles without messages, bursts far
    beyond the queues, only unsubscribed topics, every special value."""
    s = sides[key]
    d = s.dump
    rnd = random.Random(5)
    subs = [(t, st_) for _, t, st_, _ in d.subs]
    y = lambda: _values(rnd, d.leaves(d.y[1]))  # noqa: E731

    def msg(topic, struct):
        return Message(topic, _values(rnd, d.leaves(struct)))

    scheds = [
        Schedule(()),
        Schedule((((), y()), ((), y()))),
        Schedule(((tuple(msg(t, st_) for t, st_ in subs for _ in range(12)), y()), ((), y()))),
        Schedule((((Message(NOBODY, ("1", "2")), Message(d.pubs[0][1], _values(rnd, d.leaves(d.pubs[0][2])))), y()),)),
    ]
    # every special float in every float leaf of every subscribed message
    for t, st_ in subs:
        leaves = d.leaves(st_)
        for k in range(len(F64_SPECIAL)):
            vals = tuple(leaf_token(l, (F64_SPECIAL if l.kind == "f64" else F32_SPECIAL)[k % len(F32_SPECIAL)])
                         if l.kind in ("f32", "f64") else leaf_token(l, 0) for l in leaves)
            scheds.append(Schedule((((Message(t, vals),), y()),)))
    for sched in scheds:
        out = _check(s, sched)
        assert out.count("cycle\n") == len(sched.cycles)


def _msg(d: NodeDump, msg_struct: str, topic: str, time: int, **values) -> Message:
    """A message whose leaves are 0 but ``values`` (leaf path with ``__``
    for ``.`` -> float or int)."""
    vals = {k.replace("__", "."): v for k, v in values.items()}
    toks = []
    for leaf in d.leaves(msg_struct):
        v = vals.get(leaf.path, 0)
        if leaf.kind == "f64":
            v = _f64(v)
        toks.append(leaf_token(leaf, v))
    return Message(topic, tuple(toks), time)


def _f64(x: float) -> int:
    return struct.unpack("<Q", struct.pack("<d", x))[0]


def _inputs(trace: str) -> list[dict[str, str]]:
    """The controller inputs of each step of a trace."""
    return [dict(re.findall(r"^  u (\S+) (\S+)$", step, re.M)) for step in trace.split("step\n")[1:]]


def test_freshness_edges_velocity_guard(sides):
    """By hand, on the velocity guard (teleop and nav time out after 500
    ms; zero fallbacks; age_ms): never received, fresh, exactly at the
    timeout (fresh), 1 ns after it (stale), a clock that went back (age
    0), an age beyond age_ms (saturated)."""
    s = sides["velocity_guard"]
    d = s.dump
    y = tuple(leaf_token(leaf, 0) for leaf in d.leaves(d.y[1]))
    T, base = 500 * MS, 10**12
    teleop = lambda t, vx: _msg(d, "geometry_msgs_Twist", "/teleop/cmd_vel", t, linear__x=vx)  # noqa: E731
    sched = Schedule(
        (((), y), ((teleop(base, 1.0),), y), ((), y), ((), y), ((teleop(base + 5 * T, 2.0),), y), ((), y)),
        times=(base - 1, base, base + T, base + T + 1, base + T + 2, MAX_TIME), t0=0)
    u = _inputs(_check(s, sched))
    zero, one, two = f"0x{0:016x}", f"0x{_f64(1.0):016x}", f"0x{_f64(2.0):016x}"
    assert [x["TAge"] for x in u] == ["4294967295", "0", "500", "500", "0", "4294967295"]
    assert [x["TVx"] for x in u] == [zero, one, one, zero, two, zero]
    assert {x["NAge"] for x in u} == {"4294967295"} and {x["NVx"] for x in u} == {zero}


def test_freshness_edges_policies(sides):
    """By hand, on ok_fresh_policies (/cmd: 20 ms, zero by default, Wz
    holds, Vy -1.5; /count: a day, hold; /ok: no timeout, received):
    before any message, at the timeout, past it, a clock gone back before
    the receipt (fresh again), is_new for one cycle."""
    s = sides["fresh_policies"]
    d = s.dump
    y = tuple(leaf_token(leaf, 0) for leaf in d.leaves(d.y[1]))
    T = 20 * MS
    cmd = _msg(d, "geometry_msgs_Twist", "/cmd", 100, linear__x=1.0, linear__y=2.0, angular__z=3.0)
    ok = _msg(d, "std_msgs_Bool", "/ok", 5, data=1)
    count = _msg(d, "std_msgs_Int32", "/count", 7, data=-9)
    sched = Schedule((((), y), ((cmd, count), y), ((), y), ((ok,), y)),
                     times=(0, 100 + T, 100 + T + 1, 1), t0=3)
    u = _inputs(_check(s, sched))
    f = lambda x: f"0x{_f64(x):016x}"  # noqa: E731
    assert [x["Vx"] for x in u] == [f(0.0), f(1.0), f(0.0), f(1.0)]
    assert [x["Vy"] for x in u] == [f(-1.5), f(2.0), f(-1.5), f(2.0)]
    assert [x["Wz"] for x in u] == [f(0.0), f(3.0), f(3.0), f(3.0)]
    assert [x["New"] for x in u] == ["0", "1", "0", "0"]
    assert [x["Rcvd"] for x in u] == ["0", "1", "1", "1"]
    assert [x["Age"] for x in u] == ["4294967295", "20", "20", "0"]
    assert [x["Count"] for x in u] == ["0", "-9", "-9", "-9"]
    assert [(x["Ok"], x["Seen"]) for x in u] == [("0", "0"), ("0", "0"), ("0", "0"), ("1", "1")]


def test_time_is_the_semantics_of_ros_now(generated_timed, sides, tmp_path):
    """A glue whose age reads the receipt time the other way round
    (``_now - time`` turned into ``time - _now``), compiled with the same
    harness: its trace differs from the Coq interpreter's."""
    node = generated_timed["velocity_guard"]
    s = sides["velocity_guard"]
    mut = tmp_path / "mutant"
    mut.mkdir()
    for f in (node.header, node.sexp):
        shutil.copyfile(f, mut / f.name)
    glue = node.glue.read_text()
    a = "_age = (_now - teleop_cmd_vel_time);"
    assert a in glue  # once per item that reads teleop's age
    (mut / node.glue.name).write_text(glue.replace(a, "_age = (teleop_cmd_vel_time - _now);"))
    exe = build_c_harness(mut, node.node, tmp_path / "work")
    d = s.dump
    y = tuple(leaf_token(leaf, 0) for leaf in d.leaves(d.y[1]))
    sched = Schedule((((_msg(d, "geometry_msgs_Twist", "/teleop/cmd_vel", 1000, linear__x=1.0),), y),),
                     times=(1000 + 7 * MS,))
    assert run_side(exe, sched.text()) != run_side(s.coq, sched.text()) == run_side(s.c, sched.text())


def test_nan_payloads_survive(sides):
    """A signalling NaN with a payload goes through callback, input glue,
    controller and output glue unchanged, on both sides."""
    s = sides["landshark"]
    d = s.dump
    leaves = d.leaves("geometry_msgs_TwistStamped")
    snan = 0x7FF0000000000123
    vals = tuple(leaf_token(l, snan if l.kind == "f64" else 7) for l in leaves)
    sched = Schedule((((Message("/landshark/left_wheel_velocity", vals),), (leaf_token(d.leaves(d.y[1])[0], 0xFFF4000000000abc),)),))
    out = _check(s, sched)
    assert "  u In1 0x7ff0000000000123\n" in out
    assert "  m twist.linear.x 0xfff4000000000abc\n" in out


def test_difference_is_detected(generated, sides, tmp_path):
    """A glue with two sources swapped, compiled with the same harness,
    gives a trace different from the Coq interpreter's."""
    node = generated["landshark"]
    s = sides["landshark"]
    mut = tmp_path / "mutant"
    mut.mkdir()
    for f in (node.header, node.sexp):
        shutil.copyfile(f, mut / f.name)
    glue = node.glue.read_text()
    a = "_t_double = landshark_left_wheel_velocity_msg.twist.linear.x;"
    b = "_t_double = landshark_right_wheel_velocity_msg.twist.linear.x;"
    assert glue.count(a) == glue.count(b) == 1
    (mut / node.glue.name).write_text(glue.replace(a, "@").replace(b, a).replace("@", b))
    exe = build_c_harness(mut, node.node, tmp_path / "work")
    rnd = random.Random(1)
    leaves = s.dump.leaves("geometry_msgs_TwistStamped")
    sched = Schedule((((Message("/landshark/left_wheel_velocity", _values(rnd, leaves)),
                        Message("/landshark/right_wheel_velocity", _values(rnd, leaves))),
                       _values(rnd, s.dump.leaves(s.dump.y[1]))),))
    assert run_side(exe, sched.text()) != run_side(s.coq, sched.text())


def test_strict_flags():
    assert set(GCC_STRICT) >= {"-Wall", "-Wextra", "-Werror", "-pedantic", "-std=c11"}

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
from the model (the newest message's fields, the outputs' fields, zeros).
"""

from __future__ import annotations

import random
import shutil
from dataclasses import dataclass
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from pyrosgen.verify.difftest import (
    GCC_STRICT, Message, NodeDump, Schedule, build_c_harness, build_coq_runner, leaf_token, run_side)
from pyrosgen.frontend.validate import load_model

from support.validation import EXAMPLES

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


@pytest.fixture(scope="session")
def sides(generated, tmp_path_factory) -> dict[str, Sides]:
    """Each model's three executables, built once per session."""
    out = {}
    for key, node in generated.items():
        work = tmp_path_factory.mktemp(f"difftest_{key}")
        out[key] = Sides(
            dump=NodeDump.from_text(node.sexp.read_text()),
            model=load_model(EXAMPLES[key][0]),
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


@st.composite
def schedules(draw, dump: NodeDump) -> Schedule:
    """Random schedules; the structure (cycles, bursts, topics) is drawn by
    hypothesis, the leaf values by a hypothesis-seeded generator biased
    towards special values."""
    rnd = draw(st.randoms(use_true_random=False))
    topics = [(t, st_) for _, t, st_, _ in dump.subs] + [(t, st_) for _, t, st_ in dump.pubs] + [(NOBODY, None)]
    cycles = []
    for _ in range(draw(st.integers(0, 5))):
        msgs: list[Message] = []
        for _ in range(draw(st.integers(0, 3))):          # bursts
            topic, struct = draw(st.sampled_from(topics))
            for _ in range(draw(st.integers(1, 7))):
                if struct is None:
                    leaves = tuple(str(rnd.randint(-5, 5)) for _ in range(rnd.randint(0, 4)))
                else:
                    leaves = _values(rnd, dump.leaves(struct))
                msgs.append(Message(topic, leaves))
        if msgs and draw(st.booleans()):
            rnd.shuffle(msgs)                              # interleave the bursts
        cycles.append((tuple(msgs), _values(rnd, dump.leaves(dump.y[1]))))
    return Schedule(tuple(cycles))


# ---------------------------------------------------------------------------
# The oracle: what the C trace must say, computed from the model

def _zero(leaf) -> str:
    return leaf_token(leaf, 0)


def expected_trace(model, dump: NodeDump, sched: Schedule) -> str:
    lines: list[str] = []
    newest: dict[str, tuple[str, ...]] = {}
    u_leaves = dump.leaves(dump.u[1])
    y_leaves = dump.leaves(dump.y[1])
    rel_in = {r.input_field: r for r in model.input_relations}
    for msgs, y in sched.cycles:
        for m in msgs:
            newest[m.topic] = m.leaves
        lines.append("step")
        for leaf in u_leaves:
            r = rel_in.get(leaf.path)
            if r is not None and r.topic.name in newest:
                src = dump.leaves(r.topic.msg_struct)
                k = [s.path for s in src].index(str(r.path))
                lines.append(f"  u {leaf.path} {newest[r.topic.name][k]}")
            else:
                lines.append(f"  u {leaf.path} {_zero(leaf)}")
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


def _check(s: Sides, sched: Schedule) -> str:
    text = sched.text()
    c = run_side(s.c, text)
    coq = run_side(s.coq, text)
    assert c == coq, f"C and Coq traces differ on the schedule:\n{text}"
    assert run_side(s.c_san, text) == c, f"the sanitized build differs on:\n{text}"
    assert c == expected_trace(s.model, s.dump, sched), f"the trace is not the oracle's on:\n{text}"
    return c


# ---------------------------------------------------------------------------

@pytest.mark.parametrize("key", list(EXAMPLES))
def test_random_schedules(sides, key):
    s = sides[key]
    seen = {"cycles": 0, "messages": 0, "empty": 0}

    @settings(max_examples=EXAMPLES_PER_MODEL, deadline=None, derandomize=True,
              suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
    @given(schedules(s.dump))
    def run(sched: Schedule) -> None:
        _check(s, sched)
        seen["cycles"] += len(sched.cycles)
        seen["messages"] += sum(len(m) for m, _ in sched.cycles)
        seen["empty"] += sum(1 for m, _ in sched.cycles if not m)

    run()
    # the schedules did exercise something
    assert seen["cycles"] > EXAMPLES_PER_MODEL and seen["messages"] > 5 * EXAMPLES_PER_MODEL
    assert seen["empty"] > 0


@pytest.mark.parametrize("key", list(EXAMPLES))
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

"""Differential tests of the rcl wrapper's conversions (rule 4.15, DESIGN.md
section 6.1 "The ROS 2 wrapper"): the node of tests/ros2/models/seq_policies.yaml
(its proved glue, its generated ``<node>_rcl.c`` and its echo controller)
linked, instead of Fast DDS, with bench/runtime/fake_rcl.c and the driver
tests/ros2/fake_rcl_seq.c, which hands ``rcl_take`` rosidl messages built
from a schedule (sequences and strings of exactly the given length) and
prints what ``rcl_publish`` gets.  Built twice, with gcc -O2 and with
``-fsanitize=address,undefined``; both must print, byte for byte, what the
environment model says (:func:`oracle`): each message as
``Environment.clamp`` delivers it (``len = min(size, N)``, ``truncated =
size > N``, the first ``len`` elements, zeros past them), a message of
policy reject holding a longer one not delivered (``Environment.accepted``:
the previous one stays), and each published sequence and string the first
``min(len, N)`` elements.  The schedules: the lengths 0, 1, N-1, N, N+1
and 2N of every field in turn, then random ones (up to 1,000 elements;
NaNs with payloads, infinities, subnormals, -0.0; bytes 0 to 255 and
lengths of the published sequence up to 2^32 - 1), with cycles without a
message.  No middleware: exact and fast.

And against the Coq interpreter (``Interp.run_program`` extracted, as
tests/validation/test_difftest.py runs it for ROS 1): the harness of the
ROS 1 differential tests with the generated wrapper's ``to_c``/``from_c``
and reject test compiled in for its C clamp (tests/ros2/rcl_bridge.py),
the glue compiled by gcc -O2 and under the sanitizers, prints the same
trace, byte for byte, as the interpreter running the proved program with
the environment model's ``clamp`` and ``accepted``, on random schedules
(bursts longer than the queues, every length class, NaN payloads)."""

from __future__ import annotations

import os
import random
import subprocess

import pytest

from pyrosgen.ros.wrapper import GLUE_CFLAGS
from pyrosgen.ros2.build import build_ros2, compile_flags, link_flags
from pyrosgen.ros2.env import ros2_env
from pyrosgen.proof.modeltext import parse_model_text
from pyrosgen.ros2.wrapper import _T, _context, parse_qos_text
from pyrosgen.verify.difftest import (SANITIZE, Message, NodeDump, Schedule, build_coq_runner, leaf_token,
                                      run_side, run_tool)

from . import rcl_bridge

from support import ros as rosutil

from .test_arm_ros2 import SANITIZED_ENV
from .test_sequences_ros2 import CONTROLLER, MODEL, N, F

RT = rosutil.ROOT / "bench" / "runtime"
DRIVER = rosutil.ROOT / "tests" / "ros2" / "fake_rcl_seq.c"
PUBLISHED = ("/echo/ranges", "/echo/frame", "/echo/flags", "/echo/rej", "/echo/str", "/echo/frame_truncated")
CFLAGS = ("-std=c11", "-Wall", "-Wextra", "-Werror")

F32_SPECIAL = [0, 1 << 31, 1, 0x80000001, 0x007FFFFF, 0x00800000, 0x7F7FFFFF, 0xFF7FFFFF, 0x7F800000,
               0xFF800000, 0x7FC00000, 0xFFC00000, 0x7FC00123, 0x7F800001, 0xFFA00ABC, 0x3F800000]
F64_SPECIAL = [0, 1 << 63, 1, 0x000FFFFFFFFFFFFF, 0x7FEFFFFFFFFFFFFF, 0x7FF0000000000000, 0xFFF0000000000000,
               0x7FF8000000000000, 0x7FF8000000000123, 0x7FF0000000000001, 0xFFF4000000000ABC, 0x3FF0000000000000]


@pytest.fixture(scope="module")
def fake_nodes(ros2_install, ros2_nodes, tmp_path_factory):
    """The node linked with the fake rcl layer: gcc -O2, and sanitized."""
    res = build_ros2(MODEL, CONTROLLER, ros2_nodes / "seq_policies", install=ros2_install)
    out, cf, lf = res.out_dir, compile_flags(ros2_install), link_flags(ros2_install, res.model)
    work = tmp_path_factory.mktemp("rcl_conversions")
    exes = {}
    for variant, extra in (("gcc", ("-O2",)), ("sanitizers", ("-O1", *SANITIZE))):
        objs = []
        for name, src, flags in (("glue", out / "seq_policies_glue.c", [*GLUE_CFLAGS, "-I", str(out)]),
                                 ("rcl", out / "seq_policies_rcl.c", [*GLUE_CFLAGS, "-I", str(out), *cf]),
                                 ("ctl", out / "controller" / "Echo.c", [*CFLAGS, "-O2"]),
                                 ("fake", RT / "fake_rcl.c", [*CFLAGS, "-I", str(RT), *cf]),
                                 ("driver", DRIVER, [*CFLAGS, "-I", str(RT), *cf])):
            o = work / f"{variant}_{name}.o"
            r = subprocess.run(["gcc", *flags, *extra, "-c", str(src), "-o", str(o)], capture_output=True, text=True)
            assert r.returncode == 0, f"{src}: {r.stderr[-3000:]}"
            objs.append(str(o))
        exe = work / f"seq_policies_{variant}"
        san = list(SANITIZE) if variant == "sanitizers" else []
        r = subprocess.run(["gcc", *san, *objs, "-o", str(exe), *lf, "-lm", "-ldl"], capture_output=True, text=True)
        assert r.returncode == 0, r.stderr[-3000:]
        exes[variant] = exe
    return exes


# ---------------------------------------------------------------------------
# Schedules: {cycle: {topic index: message}}; /trunc (ranges, frame), /rej
# (data), /rej_str (bytes), /publen (value)


def boundary_schedule() -> dict:
    """Every field at the lengths 0, 1, N-1, N, N+1 and 2N in turn (each
    rejected message follows an accepted one it must not replace), the
    published length from 0 to 2^32 - 1."""
    sched, k = {}, 0
    lens = lambda n: [n, n + 1, 0, 2 * n, 1, n - 1, n]  # noqa: E731
    for lr, lf, lj, ls, pl in zip(lens(N), lens(F), lens(N), lens(F), [N, N + 1, 0, 2 * N, 1, 0xFFFFFFFF, 2 ** 31]):
        sched[2 * k] = {0: ([0x41200000 + 0x10000 * k + i for i in range(lr)], [97 + (k + i) % 26 for i in range(lf)]),
                        1: [0x4024000000000000 + (k << 32) + i for i in range(lj)],
                        2: [65 + (k + 3 * i) % 26 for i in range(ls)], 3: pl}
        k += 1   # odd cycles: no message, the inputs stay
    return sched


def _f32(rnd: random.Random) -> int:
    return rnd.choice(F32_SPECIAL) if rnd.random() < 0.4 else rnd.getrandbits(32)


def _f64(rnd: random.Random) -> int:
    return rnd.choice(F64_SPECIAL) if rnd.random() < 0.4 else rnd.getrandbits(64)


def _length(rnd: random.Random, n: int) -> int:
    return rnd.choice([0, 1, n - 1, n, n + 1, 2 * n, rnd.randint(0, 3 * n), rnd.randint(0, 1000)])


def random_schedule(seed: int, cycles: int = 150) -> dict:
    rnd = random.Random(seed)
    sched = {}
    for k in range(cycles):
        msgs = {}
        if rnd.random() < 0.7:
            msgs[0] = ([_f32(rnd) for _ in range(_length(rnd, N))], [rnd.randint(0, 255) for _ in range(_length(rnd, F))])
        if rnd.random() < 0.6:
            msgs[1] = [_f64(rnd) for _ in range(_length(rnd, N))]
        if rnd.random() < 0.6:
            msgs[2] = [rnd.randint(0, 255) for _ in range(_length(rnd, F))]
        if rnd.random() < 0.5:
            msgs[3] = rnd.choice([0, 1, N - 1, N, N + 1, 2 * N, 2 ** 31, 2 ** 32 - 1, rnd.getrandbits(32)])
        if msgs:
            sched[k] = msgs
    return sched


def schedule_text(sched: dict) -> str:
    lines = []
    for k, msgs in sorted(sched.items()):
        for topic, m in sorted(msgs.items()):
            if topic == 0:
                ranges, frame = m
                lines.append(f"{k} 0 {len(ranges)} {' '.join(f'{b:x}' for b in ranges)} "
                             f"{len(frame)} {' '.join(f'{b:x}' for b in frame)}")
            elif topic == 3:
                lines.append(f"{k} 3 {m}")
            else:
                lines.append(f"{k} {topic} {len(m)} {' '.join(f'{b:x}' for b in m)}")
    return "".join(line + "\n" for line in lines)


# ---------------------------------------------------------------------------
# The oracle: what the environment model says the node publishes


def _clamp(xs: list, n: int) -> tuple[list, int, int]:
    """Environment.clamp: the first min(size, n) elements, zeros past them;
    the length; the truncated flag."""
    m = min(len(xs), n)
    return list(xs[:m]) + [0] * (n - m), m, int(len(xs) > n)


def oracle(sched: dict, cycles: int) -> str:
    trunc, rej, rej_str, publen = ([], []), [], [], 0
    lines = []
    for k in range(cycles):
        msgs = sched.get(k, {})
        if 0 in msgs:
            trunc = msgs[0]
        if 1 in msgs and len(msgs[1]) <= N:        # policy reject: Environment.accepted
            rej = msgs[1]
        if 2 in msgs and len(msgs[2]) <= F:
            rej_str = msgs[2]
        if 3 in msgs:
            publen = msgs[3]
        r, rn, rt = _clamp(trunc[0], N)
        b, bn, bt = _clamp(trunc[1], F)
        j, jn, _ = _clamp(rej, N)
        s, sn, _ = _clamp(rej_str, F)
        pn = min(publen, N)                         # published: the first min(len, N) elements
        lines += [f"{k} /echo/ranges 0 0 {pn}" + "".join(f" {x:08x}" for x in r[:pn]),
                  f"{k} /echo/frame 0 0 {bn}" + "".join(f" {x}" for x in b[:bn]),
                  f"{k} /echo/flags {rn} 0 {jn} {sn} {rt}",
                  f"{k} /echo/rej " + " ".join(f"{x:016x}" for x in j),
                  f"{k} /echo/str {s[0]} {s[7]} 00000000",
                  f"{k} /echo/frame_truncated {bt}"]
    return "".join(line + "\n" for line in lines) + f"cycles {cycles}\n"


def run_fake(exe, sched: dict, cycles: int, tmp_path, extra_env: dict | None = None) -> str:
    path = tmp_path / f"schedule_{exe.name}.txt"
    path.write_text(schedule_text(sched))
    env = {**ros2_env(), "BENCH_CYCLES": str(cycles), "SEQ_SCHEDULE": str(path), **(extra_env or {})}
    r = subprocess.run([str(exe)], capture_output=True, text=True, env=env, timeout=120)
    assert r.returncode == 0, f"{exe.name}: exit {r.returncode}\n{r.stderr[-3000:]}"
    return r.stdout


def _first_difference(got: str, want: str) -> str:
    for i, (g, w) in enumerate(zip(got.splitlines(), want.splitlines())):
        if g != w:
            return f"line {i + 1}:\n  got  {g}\n  want {w}"
    return f"{len(got.splitlines())} lines, want {len(want.splitlines())}"


@pytest.mark.parametrize("variant", ["gcc", "sanitizers"])
def test_rcl_conversions_at_the_boundary_lengths(fake_nodes, variant, tmp_path):
    sched = boundary_schedule()
    cycles = 2 * len(sched) + 1
    want = oracle(sched, cycles)
    # the cases met: every length of both policies, a rejected message after an accepted one
    assert {len(m[0][0]) for m in sched.values()} == {0, 1, N - 1, N, N + 1, 2 * N}
    assert {len(m[2]) for m in sched.values()} == {0, 1, F - 1, F, F + 1, 2 * F}
    got = run_fake(fake_nodes[variant], sched, cycles, tmp_path, SANITIZED_ENV if variant == "sanitizers" else {})
    assert got == want, _first_difference(got, want)


def test_rcl_conversions_random_gcc_against_sanitizers_and_model(fake_nodes, tmp_path):
    for seed in (1, 2, 3):
        sched = random_schedule(seed)
        want = oracle(sched, 150)
        got = run_fake(fake_nodes["gcc"], sched, 150, tmp_path)
        assert got == want, f"seed {seed}: " + _first_difference(got, want)
        san = run_fake(fake_nodes["sanitizers"], sched, 150, tmp_path, SANITIZED_ENV)
        assert san == got, f"seed {seed}: the sanitized build differs: " + _first_difference(san, got)


# ---------------------------------------------------------------------------
# Against the Coq interpreter


@pytest.fixture(scope="module")
def coq_sides(ros2_install, ros2_nodes, tmp_path_factory):
    """The interpreter's runner, and the ROS 1 harness over the wrapper's
    conversions (gcc -O2, sanitized); the node's AST dump."""
    res = build_ros2(MODEL, CONTROLLER, ros2_nodes / "seq_policies", install=ros2_install)
    out, node = res.out_dir, res.model.name
    proved = parse_model_text((out / f"{node}.model").read_text())
    ctx = _context(res.model, proved, parse_qos_text((out / f"{node}.qos").read_text(), proved))
    ctx["messages"] = [_T(m, fields=[_T(f) for f in m["fields"]]) for m in ctx["messages"]]
    work = tmp_path_factory.mktemp("rcl_difftest")
    cf, lf = compile_flags(ros2_install), link_flags(ros2_install, res.model)
    dump = NodeDump.from_text((out / f"{node}.sexp").read_text())
    bools = {st: _bool_leaves(proved, st) for _f, _t, st, _q in dump.subs}
    bools[dump.y[1]] = {f.name for f in res.model.controller.outputs.fields if f.prim == "bool"}
    def mutant(rcl_text: str, where: Path) -> Path:
        """The gcc harness over another wrapper text (the harness includes
        the ``<node>_rcl.c`` of its own folder first)."""
        (where / f"{node}_rcl.c").write_text(rcl_text)
        return rcl_bridge.build_rcl_harness(out, node, ctx, where, cf, lf, sanitize=False, run_tool=run_tool)

    return {"dump": dump, "bools": bools, "coq": build_coq_runner(out, node, work), "mutant": mutant,
            "rcl_text": (out / f"{node}_rcl.c").read_text(),
            "gcc": rcl_bridge.build_rcl_harness(out, node, ctx, work, cf, lf, sanitize=False, run_tool=run_tool),
            "sanitizers": rcl_bridge.build_rcl_harness(out, node, ctx, work, cf, lf, sanitize=True,
                                                       run_tool=run_tool)}


def _bool_leaves(pm, struct: str, prefix: str = "") -> set[str]:
    """The leaf paths of ``struct`` whose type is bool (a bounded struct's
    ``truncated`` flag is not on the wire: left out)."""
    out: set[str] = set()
    for name, typ in pm.messages.get(struct, []):
        parts, path = typ.split(), f"{prefix}{name}"
        count = int(parts[1]) if parts[0] == "array" else None
        base = parts[2:] if count is not None else parts
        for p in [path] if count is None else [f"{path}[{i}]" for i in range(count)]:
            if base[0] == "msg":
                out |= _bool_leaves(pm, base[1], p + ".")
            elif base == ["bool"] and not (name == "truncated" and struct.startswith(("ros_seq", "ros_rseq",
                                                                                        "ros_string", "ros_rstring"))):
                out.add(p)
    return out


def _leaf_value(rnd: random.Random, leaf, is_bool: bool = False) -> int:
    """A random value of ``leaf``; a bool 0 or 1 (rosidl's bool is C's
    ``bool``: see test_a_published_bool_is_0_or_1_on_ros2)."""
    if is_bool:
        return rnd.randint(0, 1)
    if leaf.kind == "f64":
        return _f64(rnd)
    if leaf.kind == "f32":
        return _f32(rnd)
    lo, hi = (-(1 << (leaf.bits - 1)), (1 << (leaf.bits - 1)) - 1) if leaf.kind == "signed" else (0, (1 << leaf.bits) - 1)
    return rnd.choice([lo, hi, 0, 1]) if rnd.random() < 0.4 else rnd.randint(lo, hi)


def _message_leaves(rnd: random.Random, dump: NodeDump, struct: str, bools: set[str]) -> tuple[str, ...]:
    """A message as sent: every leaf random, each bounded length from the
    classes 0, 1, N-1, N, N+1, 2N, up to 3N, 2^32 - 1."""
    leaves = dump.leaves(struct)
    values = [_leaf_value(rnd, leaf, leaf.path in bools) for leaf in leaves]
    for b in dump.bounded(struct):
        n = b.capacity
        values[b.first_leaf] = rnd.choice([0, 1, n - 1, n, n + 1, 2 * n, rnd.randint(0, 3 * n), 2 ** 32 - 1])
    return tuple(leaf_token(leaf, v) for leaf, v in zip(leaves, values))


def coq_schedule(seed: int, dump: NodeDump, bools: dict[str, set[str]]) -> Schedule:
    rnd = random.Random(seed)
    cycles, times, t = [], [], rnd.getrandbits(40)
    for _ in range(rnd.randint(1, 12)):
        msgs = []
        for _ in range(rnd.randint(0, 4)):
            _fn, topic, struct, _q = rnd.choice(dump.subs)
            for _ in range(rnd.randint(1, 3)):           # bursts longer than the queues of 1
                t += rnd.randint(1, 10 ** 6)
                msgs.append(Message(topic, _message_leaves(rnd, dump, struct, bools[struct]), t))
        t += rnd.randint(1, 10 ** 7)
        times.append(t)
        y = dump.leaves(dump.y[1])
        cycles.append((tuple(msgs), tuple(leaf_token(leaf, _leaf_value(rnd, leaf, leaf.path in bools[dump.y[1]]))
                                          for leaf in y)))
    return Schedule(tuple(cycles), tuple(times), 0)


def test_rcl_conversions_against_the_coq_interpreter(coq_sides):
    dump = coq_sides["dump"]
    lengths, published = set(), 0
    for seed in range(40):
        sched = coq_schedule(seed, dump, coq_sides["bools"])
        text = sched.text()
        coq = run_side(coq_sides["coq"], text)
        c = run_side(coq_sides["gcc"], text)
        assert c == coq, f"seed {seed}: the rcl wrapper's conversions and Coq differ on:\n{text}\n" + \
            _first_difference(c, coq)
        assert run_side(coq_sides["sanitizers"], text) == c, f"seed {seed}: the sanitized build differs"
        published += c.count("\npublish ")
        for msgs, _y in sched.cycles:
            for m in msgs:
                struct = next(st for _f, tp, st, _q in dump.subs if tp == m.topic)
                lengths |= {(struct, int(m.leaves[b.first_leaf]) - b.capacity) for b in dump.bounded(struct)}
    # every length class of every received sequence and string was met, and messages were published
    for struct, n in {(st, b.capacity) for _f, _t, st, _q in dump.subs for b in dump.bounded(st)}:
        assert {d for s, d in lengths if s == struct} >= {-n, 1 - n, -1, 0, 1, n}, struct
    assert published >= 100


@pytest.mark.parametrize("mutant", ["reject-at-the-maximum", "reject-never", "string-reject-never"])
def test_the_coq_comparison_sees_a_wrong_reject_test(coq_sides, tmp_path, mutant):
    """The harness runs the wrapper's own reject test (``accept_<topic>``),
    so a wrapper that rejects at the maximum instead of past it, or never
    rejects, publishes what the Coq interpreter does not."""
    old, new = {"reject-at-the-maximum": ("r->data.size > 4) return 0;", "r->data.size >= 4) return 0;"),
                "reject-never": ("r->data.size > 4) return 0;", "r->data.size > 4 && 0) return 0;"),
                "string-reject-never": ("r->data.size > 8) return 0;", "r->data.size > 8 && 0) return 0;")}[mutant]
    text = coq_sides["rcl_text"]
    assert text.count(old) == 1
    exe = coq_sides["mutant"](text.replace(old, new), tmp_path)
    dump = coq_sides["dump"]
    for seed in range(40):
        sched = coq_schedule(seed, dump, coq_sides["bools"]).text()
        if run_side(exe, sched) != run_side(coq_sides["coq"], sched):
            return
    raise AssertionError(f"the mutant {mutant} agrees with the Coq interpreter on 40 schedules")


def test_a_published_bool_is_0_or_1_on_ros2(coq_sides):
    """rosidl's bool is C's ``bool``: the wrapper's ``from_c`` stores a
    controller's bool output of 150 as true, so the message on the wire
    holds 1 where the environment model (and the ROS 1 wrapper, whose bool
    is a uint8 on the wire) says 150; 0 and 1 go through unchanged.  T2 on
    ROS 2 speaks of bool outputs 0 and 1 (DESIGN.md section 7, the rcl
    wrapper's row); every other line of the trace is the interpreter's."""
    dump = coq_sides["dump"]
    y = dump.leaves(dump.y[1])
    at = [leaf.path for leaf in y].index("CT")
    for v, wire in ((0, 0), (1, 1), (150, 1), (255, 1)):
        tokens = tuple(leaf_token(leaf, v if i == at else 0) for i, leaf in enumerate(y))
        text = Schedule((((), tokens),), (7,), 0).text()
        coq, c = run_side(coq_sides["coq"], text), run_side(coq_sides["gcc"], text)
        model_says = f"publish /echo/frame_truncated\n  m data {v}\n"
        assert coq.count(model_says) == 1, coq
        assert c == coq.replace(model_says, f"publish /echo/frame_truncated\n  m data {wire}\n"), (v, c)

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
message.  No middleware: exact and fast."""

from __future__ import annotations

import os
import random
import subprocess

import pytest

from pyrosgen.ros.wrapper import GLUE_CFLAGS
from pyrosgen.ros2.build import build_ros2, compile_flags, link_flags
from pyrosgen.ros2.env import ros2_env
from pyrosgen.verify.difftest import SANITIZE

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

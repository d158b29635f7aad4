"""Policy reject through the whole pipeline (rule 4.15, ``policy``):
``generate`` on tests/ros/models/scan_reject.yaml (a LaserScan's ``ranges``
carried as ``ros_rseq_float32_4`` and its ``header.frame_id`` as
``ros_rstring8``, both of policy reject; two elements and both lengths
feed a block diagram) closes its theorems, prints the reject structs, the
C compiles with ``-Wall -Wextra -Werror``, ``verify`` accepts the folder
(the wrapper check among the rest when built: tests/ros), and the seam
refuses a per-node file whose struct has policy truncate.

The differential test runs scans of lengths 0, 1, N-1, N, N+1 and 2N (N =
4) and frame_ids of 0 to 16 bytes, with junk past their length, through
the Coq interpreter (``Environment.accepted``: a scan holding a sequence
of policy reject longer than its maximum is dropped after the queue) and
the printed glue under gcc -O2 and ASan/UBSan (whose fake ROS API makes
the wrapper's test): the traces agree bit for bit, the controller keeps
the previous scan after a rejected one, also when, in a burst on the queue
of size 1, a rejected scan pushed an accepted one out; a harness that
delivers over-long scans truncated is caught."""

from __future__ import annotations

import random
import re
import subprocess

import pytest

import pyrosgen.generate as gen
from pyrosgen import cli
from pyrosgen.proof.coqdriver import CLOSED
from pyrosgen.verify.difftest import (
    GCC_STRICT, Message, NodeDump, Schedule, leaf_token, run_side,
)

from support.generate import (
    REPO as ROOT, difftest_sides, generate_with_tampered_node_file, require_library, sides_agree,
)

MODEL = ROOT / "tests" / "ros" / "models" / "scan_reject.yaml"
NODE = "scan_reject"
N, F = 4, 8
LENGTHS = (0, 1, N - 1, N, N + 1, 2 * N)


@pytest.fixture(scope="module")
def gen_out(tmp_path_factory):
    require_library()
    out = tmp_path_factory.mktemp("reject") / "out"
    result = gen.generate(MODEL, out)
    return out, result


def test_theorems_are_closed(gen_out):
    out, result = gen_out
    assert result.ddc and result.theorem == f"{NODE}_ddc"
    assert set(result.theorems) >= {f"{NODE}_ddc", f"Ctrl.{NODE}_controller_wf", f"Ctrl.{NODE}_e2e", f"Ctrl.{NODE}_linked"}
    assert result.record.assumptions.count(CLOSED) == 1  # one Print Assumptions of their conjunction
    assert all(t in result.record.assumptions for t in result.theorems)


def test_types_header_has_the_reject_structs(gen_out):
    out, _ = gen_out
    h = (out / f"{NODE}_types.h").read_text()
    for name, data in (("ros_rseq_float32_4", "float data[4];"), ("ros_rstring8", "unsigned char data[8];")):
        m = re.search(r"struct " + name + r" \{\n(.*?)\n\};", h, re.S)
        assert m, h[:2000]
        assert [ln.strip() for ln in m.group(1).splitlines()] == [
            "unsigned int len;", "unsigned char truncated;", data]
    assert "struct ros_rseq_float32_4 ranges;" in h and "struct ros_rstring8 frame_id;" in h
    proved = (out / f"{NODE}.model").read_text().splitlines()
    i = proved.index("message ros_rseq_float32_4")
    assert proved[i + 1:i + 4] == ["field len uint32", "field truncated bool", "field data array 4 float32"]


def test_certificate_says_what_is_dropped(gen_out):
    out, _ = gen_out
    cert = (out / f"{NODE}.certificate.md").read_text()
    assert ("a message holding a sequence of policy\n  reject (`ros_rstring8`, `ros_rseq_float32_4`) longer than its "
            "maximum is not\n  received") in cert, cert[:3000]
    assert "dropped after the queue, its callback not called (`Environment.accepted`)" in cert
    assert "each subscription callback first returns, before the receipt time and any conversion" in cert


def test_printed_c_compiles_with_warnings_as_errors(gen_out, tmp_path):
    out, _ = gen_out
    for src in (f"{NODE}_glue.c",):   # (the echo's diagram has an unused block: its C is the test's)
        r = subprocess.run(["gcc", *GCC_STRICT, "-O2", "-c", str(out / src), "-I", str(out),
                            "-o", str(tmp_path / (src + ".o"))], capture_output=True, text=True, timeout=600)
        assert r.returncode == 0, r.stderr


def test_verify_accepts_the_folder(gen_out, capsys):
    out, _ = gen_out
    assert cli.main(["verify", str(out), "--model", str(MODEL)]) == 0, capsys.readouterr().err


def test_a_per_node_file_with_policy_truncate_is_refused(monkeypatch, capsys, tmp_path):
    """The per-node file proves its theorem about a node whose ranges have
    policy truncate (``ros_seq_float32_4``): the seam refuses it."""
    require_library()
    out = tmp_path / "out"
    code, err = generate_with_tampered_node_file(MODEL, '"ros_rseq_float32_4"', '"ros_seq_float32_4"',
                                                 monkeypatch, capsys, out, count=-1)
    assert code == 2 and not out.exists(), err
    assert "is not the model of the YAML file" in err and "ros_seq_float32_4" in err, err


# --------------------------------------------------------------------------
# The differential test


@pytest.fixture(scope="module")
def sides(gen_out, tmp_path_factory):
    out, _ = gen_out
    work = tmp_path_factory.mktemp("reject_difftest")
    return difftest_sides(out, NODE, work, mutant="no_reject")


F32_JUNK = 0x41100000          # 9.0, past the length


def _scan(dump: NodeDump, rnd: random.Random, length: int, frame_len: int) -> tuple[Message, dict | None]:
    """A LaserScan as sent: ``length`` ranges (the first N represented,
    distinct, junk past the length), a frame_id of ``frame_len`` bytes
    (junk past it), the other leaves random; with the inputs the controller
    must receive if it is delivered, or ``None`` when it is rejected."""
    st = "sensor_msgs_LaserScan"
    leaves = dump.leaves(st)
    bounded = {b.path: b for b in dump.bounded(st)}
    vals = [leaf_token(lf, rnd.getrandbits(lf.bits)) for lf in leaves]
    seq = bounded["ranges"]
    vals[seq.first_leaf] = str(length)
    vals[seq.first_leaf + 1] = str(rnd.randint(0, 255))           # truncated as sent: anything
    data = [rnd.getrandbits(31) if i < length else F32_JUNK for i in range(N)]
    for i, bits in enumerate(data):
        vals[seq.first_leaf + 2 + i] = leaf_token(leaves[seq.first_leaf + 2 + i], bits)
    frame = bounded["header.frame_id"]
    assert frame.capacity == F and seq.capacity == N
    vals[frame.first_leaf] = str(frame_len)
    for i in range(frame.capacity):
        vals[frame.first_leaf + 2 + i] = str(rnd.randint(32, 126) if i < frame_len else rnd.randint(1, 255))
    if length > N or frame_len > F:
        return Message("/scan", tuple(vals), 0), None
    want = {"R0": f"0x{(data[0] if length > 0 else 0):08x}", "R3": f"0x{(data[3] if length > 3 else 0):08x}",
            "NR": str(length), "FL": str(frame_len)}
    return Message("/scan", tuple(vals), 0), want


def _steps(trace: str) -> list[dict]:
    out = []
    for line in trace.splitlines():
        if line == "step":
            out.append({})
        elif line.startswith("  u "):
            _, name, value = line.split()
            out[-1][name] = value
    return out


ZERO = {"R0": "0x00000000", "R3": "0x00000000", "NR": "0", "FL": "0"}


def test_difftest_at_the_lengths_and_bursts(sides):
    dump = sides["dump"]
    rnd = random.Random(15)
    y0 = tuple(leaf_token(lf, 0) for lf in dump.leaves(dump.y[1]))
    cycles, wants = [], []
    current = ZERO
    frames = (0, 1, F - 1, F, F + 1, 2 * F)
    # every length with a valid frame_id, then every frame_id length with
    # valid ranges, each after an accepted scan
    plan = [(n, 2) for n in LENGTHS] + [(2, f) for f in frames]
    for length, frame_len in plan:
        for msg, want in (_scan(dump, rnd, 2, 3), _scan(dump, rnd, length, frame_len)):
            cycles.append(((msg,), y0))
            current = want if want is not None else current
            wants.append(current)
    # bursts on the queue of size 1: a rejected scan after an accepted one
    # in the same spin pushes it out, so neither is delivered
    for length, frame_len in ((N + 1, 0), (2 * N, 1), (1, F + 1), (0, 2 * F)):
        ok, want_ok = _scan(dump, rnd, N, F)
        cycles.append(((ok,), y0))
        wants.append(want_ok)
        current = want_ok
        second, _ = _scan(dump, rnd, N - 1, 1)
        bad, none = _scan(dump, rnd, length, frame_len)
        assert none is None
        cycles.append(((second, bad), y0))
        wants.append(current)
        # the other order: the accepted one is the newest, delivered
        bad2, _ = _scan(dump, rnd, length, frame_len)
        third, want3 = _scan(dump, rnd, N - 1, F - 1)
        cycles.append(((bad2, third), y0))
        current = want3
        wants.append(current)
    # a cycle without a message keeps the newest one
    cycles.append(((), y0))
    wants.append(current)
    sched = Schedule(tuple(cycles)).text()
    coq = sides_agree(sides, sched)
    steps = _steps(coq)
    assert len(steps) == len(wants)
    for k, (got, want) in enumerate(zip(steps, wants)):
        assert got == want, (k, got, want)
    # a harness that delivers over-long scans truncated is caught
    assert run_side(sides["c_mutant"], sched) != coq


def test_difftest_random_lengths(sides):
    """Random scans and bursts: lengths around 0, N and 2N, and any."""
    dump = sides["dump"]
    rnd = random.Random(4)
    y0 = tuple(leaf_token(lf, 0) for lf in dump.leaves(dump.y[1]))
    cycles = []
    for _ in range(30):
        msgs = []
        for _ in range(rnd.randint(0, 3)):
            length = rnd.choice([rnd.randint(0, 3), rnd.randint(N - 2, N + 2), rnd.randint(0, 4 * N),
                                 rnd.getrandbits(32)])
            frame_len = rnd.choice([0, 5, F, F + 1, rnd.getrandbits(32)])
            msgs.append(_scan(dump, rnd, length, frame_len)[0])
        cycles.append((tuple(msgs), y0))
    sched = Schedule(tuple(cycles)).text()
    coq = sides_agree(sides, sched)

"""Variable-length arrays through the whole pipeline (rule 4.15):
``generate`` on examples/laser_guard/laser_guard.yaml (a LaserScan's
``ranges`` carried as ``ros_seq_float32_1081``; five of its elements,
its length and its truncation flag feed a block diagram) closes its
theorems (T2 and the diagram's), prints the bounded struct and the
relations' reads of its leaves, the C compiles with ``-Wall -Wextra
-Werror``, ``verify`` accepts the folder, and the seam refuses a
per-node file that reads another element.

The differential test runs scans of lengths 0, 1, N-1, N, N+1 and 2N
(N = 1081) with junk past their length, and frame_ids of 0 to 256 bytes,
through the Coq interpreter (which receives the raw message and
converts it as ``Environment.clamp`` says) and the printed glue under gcc
-O2 and ASan/UBSan (whose fake ROS API converts it with a C clamp that
does what the wrapper does): the traces agree bit for bit and give the
controller exactly the clamped values; a harness whose clamp leaves the
elements past the length as they came (no zero fill) is caught."""

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

LASER = ROOT / "examples" / "laser_guard" / "laser_guard.yaml"
NODE = "laser_guard"
N = 1081
SECTOR = (538, 539, 540, 541, 542)
LENGTHS = (0, 1, N - 1, N, N + 1, 2 * N)


@pytest.fixture(scope="module")
def laser(tmp_path_factory):
    require_library()
    out = tmp_path_factory.mktemp("laser") / "out"
    result = gen.generate(LASER, out)
    return out, result


def test_theorems_are_closed(laser):
    out, result = laser
    assert result.ddc and result.theorem == f"{NODE}_ddc"
    assert set(result.theorems) >= {f"{NODE}_ddc", f"Ctrl.{NODE}_controller_wf", f"Ctrl.{NODE}_e2e", f"Ctrl.{NODE}_linked"}
    assert result.record.assumptions.count(CLOSED) == 1  # one Print Assumptions of their conjunction
    assert all(t in result.record.assumptions for t in result.theorems)
    print(f"generate {NODE}: " + ", ".join(f"{k} {v:.2f} s" for k, v in result.times.items()))


def test_types_header_has_the_sequence_struct(laser):
    out, _ = laser
    h = (out / f"{NODE}_types.h").read_text()
    m = re.search(r"struct ros_seq_float32_1081 \{\n(.*?)\n\};", h, re.S)
    assert m, h[:2000]
    assert [ln.strip() for ln in m.group(1).splitlines()] == [
        "unsigned int len;", "unsigned char truncated;", "float data[1081];"]
    assert h.index("struct ros_seq_float32_1081 {") < h.index("struct sensor_msgs_LaserScan {")
    scan = re.search(r"struct sensor_msgs_LaserScan \{\n(.*?)\n\};", h, re.S).group(1)
    assert scan.strip().splitlines()[-1].strip() == "struct ros_seq_float32_1081 ranges;"


def test_input_glue_reads_the_leaves(laser):
    out, _ = laser
    c = (out / f"{NODE}_glue.c").read_text()
    body = c[c.index("void input_glue(void)\n{"):]
    body = body[:body.index("\n}\n")]
    lines = [ln.strip() for ln in body.splitlines()]
    k = lines.index("_t_uint = scan_msg.ranges.len;")
    assert lines[k + 1] == "Guard_U.NR = _t_uint;"
    k = lines.index("_t_uchar = scan_msg.ranges.truncated;")
    assert lines[k + 1] == "Guard_U.TR = _t_uchar;"
    # the sector's elements are direct relations (rule 4.16: /scan is not
    # timed): the callback copies each once, from *msg into Guard_U, and
    # input_glue does not
    assert not any("ranges.data" in ln or ln.startswith("Guard_U.R5") for ln in lines)
    cb = c[c.index("void scan_callback(struct sensor_msgs_LaserScan *msg)\n{"):]
    cb = [ln.strip() for ln in cb[:cb.index("\n}\n")].splitlines()]
    assert cb[-2 * len(SECTOR):] == [ln for i in SECTOR for ln in (f"_t_float = (*msg).ranges.data[{i}];",
                                                                    f"Guard_U.R{i} = _t_float;")]
    # the callback keeps in the global only the length and the flag (not
    # the 1,081 elements, nor the sector's)
    stores = sorted(ln.split(" = ")[0] for ln in cb if ln.startswith("scan_msg."))
    assert stores == ["scan_msg.ranges.len", "scan_msg.ranges.truncated"]


def test_printed_c_compiles_with_warnings_as_errors(laser, tmp_path):
    out, _ = laser
    for src in (f"{NODE}_glue.c", f"{NODE}_controller.c"):
        r = subprocess.run(["gcc", *GCC_STRICT, "-O2", "-c", str(out / src), "-I", str(out),
                            "-o", str(tmp_path / (src + ".o"))], capture_output=True, text=True, timeout=600)
        assert r.returncode == 0, r.stderr


def test_model_text_and_certificate(laser):
    out, _ = laser
    proved = (out / f"{NODE}.model").read_text().splitlines()
    assert [ln for ln in proved if ln.startswith("input_relation")] == [
        *(f"input_relation scan ranges.data[{i}] R{i}" for i in SECTOR),
        "input_relation scan ranges.len NR", "input_relation scan ranges.truncated TR"]
    i = proved.index("message ros_seq_float32_1081")
    assert proved[i + 1:i + 4] == ["field len uint32", "field truncated bool", "field data array 1081 float32"]
    cert = (out / f"{NODE}.certificate.md").read_text()
    assert "### `/scan ranges.data[540]` → `Guard_U.R540` (float32)" in cert
    assert "converts every carried variable-length array (`ros_seq_float32_1081`) as rule 4.15 says" in cert
    assert "a received variable-length array is delivered converted (`Environment.clamp`" in cert


def test_verify_accepts_the_folder(laser, capsys):
    out, _ = laser
    assert cli.main(["verify", str(out), "--model", str(LASER)]) == 0, capsys.readouterr().err


def test_a_per_node_file_reading_another_element_is_refused(monkeypatch, capsys, tmp_path):
    """The per-node file proves its theorem about a node that reads
    ranges[541] for R540: the seam (the model Coq printed against the
    YAML's) refuses it."""
    require_library()
    want = 'mkinrel "scan" [PField "ranges"; PField "data"; PIndex 540] "R540"'
    out = tmp_path / "out"
    code, err = generate_with_tampered_node_file(LASER, want, want.replace("PIndex 540", "PIndex 541"),
                                                 monkeypatch, capsys, out)
    assert code == 2 and not out.exists(), err
    assert "is not the model of the YAML file" in err and "ranges.data[541]" in err, err


# --------------------------------------------------------------------------
# The differential test


@pytest.fixture(scope="module")
def sides(laser, tmp_path_factory):
    out, _ = laser
    work = tmp_path_factory.mktemp("laser_difftest")
    return difftest_sides(out, NODE, work, mutant="no_zero_fill")


F32_JUNK = 0x41100000          # 9.0, past the length
F32_NEAR = 0x3F000000          # 0.5 m
F32_FAR = 0x40000000           # 2.0 m


def _scan(dump: NodeDump, rnd: random.Random, length: int, frame_len: int) -> tuple[Message, dict]:
    """A LaserScan as sent: ``length`` ranges (the first N represented,
    far, one of the sector's near sometimes, junk past the length), a
    frame_id of ``frame_len`` bytes (junk past it), the other leaves
    random; with the values the controller must receive."""
    st = "sensor_msgs_LaserScan"
    leaves = dump.leaves(st)
    bounded = {b.path: b for b in dump.bounded(st)}
    vals = [leaf_token(lf, rnd.getrandbits(lf.bits)) for lf in leaves]
    seq = bounded["ranges"]
    vals[seq.first_leaf] = str(length)
    vals[seq.first_leaf + 1] = str(rnd.randint(0, 255))           # truncated as sent: anything
    near = rnd.choice(SECTOR + (None,))
    data = [(F32_NEAR if i == near else F32_FAR) if i < length else F32_JUNK for i in range(N)]
    for i, bits in enumerate(data):
        vals[seq.first_leaf + 2 + i] = leaf_token(leaves[seq.first_leaf + 2 + i], bits)
    frame = bounded["header.frame_id"]
    vals[frame.first_leaf] = str(frame_len)
    for i in range(frame.capacity):
        vals[frame.first_leaf + 2 + i] = str(rnd.randint(32, 126) if i < frame_len else rnd.randint(1, 255))
    k = min(length, N)
    want = {f"R{i}": f"0x{(data[i] if i < k else 0):08x}" for i in SECTOR}
    want.update(NR=str(k), TR=str(int(length > N)))
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


def test_difftest_at_the_lengths(sides):
    dump = sides["dump"]
    rnd = random.Random(15)
    y0 = tuple(leaf_token(lf, 0) for lf in dump.leaves(dump.y[1]))
    cycles, wants = [], []
    frames = [0, 1, 127, 128, 129, 256]
    for k, length in enumerate(LENGTHS * 2):
        msg, want = _scan(dump, rnd, length, frames[k % len(frames)])
        cycles.append(((msg,), y0))
        wants.append(want)
    # a cycle without a message keeps the newest one
    cycles.append(((), y0))
    wants.append(wants[-1])
    sched = Schedule(tuple(cycles)).text()
    coq = sides_agree(sides, sched)
    steps = _steps(coq)
    assert len(steps) == len(wants)
    for k, (got, want) in enumerate(zip(steps, wants)):
        assert got == want, (k, got, want)
    # a harness that does not zero past the length is caught
    assert run_side(sides["c_mutant"], sched) != coq


def test_difftest_random_lengths(sides):
    """Random scans and bursts: lengths around 0, N and 2N, and any."""
    dump = sides["dump"]
    rnd = random.Random(1081)
    y0 = tuple(leaf_token(lf, 0) for lf in dump.leaves(dump.y[1]))
    cycles = []
    for _ in range(20):
        msgs = []
        for _ in range(rnd.randint(0, 3)):
            length = rnd.choice([rnd.randint(0, 3), rnd.randint(N - 3, N + 3), rnd.randint(0, 4 * N),
                                 rnd.getrandbits(32)])
            msgs.append(_scan(dump, rnd, length, rnd.choice([0, 5, 128, 129, rnd.getrandbits(32)]))[0])
        cycles.append((tuple(msgs), y0))
    sched = Schedule(tuple(cycles)).text()
    coq = sides_agree(sides, sched)

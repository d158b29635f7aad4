"""Published variable-length arrays and strings through the whole pipeline
(rule 4.15, publish side): ``generate`` on tests/ros/models/seq_echo.yaml
(a ``std_msgs/Float64MultiArray`` whose ``data`` is carried as
``ros_seq_float64_4``, its length and its four elements written by
controller outputs; a ``PointStamped`` whose ``header.frame_id`` is
written byte by byte with its length) closes T2, prints the output
glue's stores into the bounded structs' leaves, the C compiles with
``-Wall -Wextra -Werror``, and ``verify`` accepts the folder.

The differential test runs the controller's length output through 0, 1,
N-1, N, N+1, 2N (N = 4) and extremes, with random elements, through the
Coq interpreter and the printed glue under gcc -O2 and ASan/UBSan; both
print each published message as the wrapper puts it on the wire (the
first min(len, N) elements, what ``Environment.clamp`` keeps on
publish): the traces agree bit for bit and are exactly the first min(L,
N) outputs, zero bytes past the string's two."""

from __future__ import annotations

import random
import re
import subprocess

import pytest

import pyrosgen.generate as gen
from pyrosgen import cli
from pyrosgen.proof.coqdriver import CLOSED
from pyrosgen.verify.difftest import (
    GCC_STRICT, Message, NodeDump, Schedule, leaf_token,
)

from support.generate import REPO as ROOT, difftest_sides, require_library, sides_agree

MODEL = ROOT / "tests" / "ros" / "models" / "seq_echo.yaml"
NODE = "seq_echo"
N = 4
LENGTHS = (0, 1, N - 1, N, N + 1, 2 * N)


@pytest.fixture(scope="module")
def echo(tmp_path_factory):
    require_library()
    out = tmp_path_factory.mktemp("seq_echo") / "out"
    result = gen.generate(MODEL, out)
    return out, result


def test_theorem_is_closed(echo):
    out, result = echo
    assert result.ddc and result.theorem == f"{NODE}_ddc"
    assert result.record.assumptions.count(CLOSED) == 1  # one Print Assumptions of their conjunction
    assert all(t in result.record.assumptions for t in result.theorems)


def test_output_glue_zeroes_then_stores_the_leaves(echo):
    out, _ = echo
    c = (out / f"{NODE}_glue.c").read_text()
    body = c[c.index("void output_glue_out(struct std_msgs_Float64MultiArray *command)\n{"):]
    lines = [ln.strip() for ln in body[:body.index("\n}\n")].splitlines()]
    zeros = ["(*command).data.len = 0U;", "(*command).data.truncated = 0;",
             *(f"(*command).data.data[{i}] = 0x0p+0;" for i in range(N))]
    assert all(z in lines for z in zeros), lines
    k = lines.index("_t_uint = Echo_Y.NS;")
    assert lines[k + 1] == "(*command).data.len = _t_uint;"
    for i in range(N):
        k = lines.index(f"_t_double = Echo_Y.E{i};")
        assert lines[k + 1] == f"(*command).data.data[{i}] = _t_double;"
        assert lines.index(zeros[2 + i]) < k
    # nothing writes truncated but the zeroing
    assert [ln for ln in lines if ".truncated" in ln] == ["(*command).data.truncated = 0;"]
    body = c[c.index("void output_glue_tagged(struct geometry_msgs_PointStamped *command)\n{"):]
    lines = [ln.strip() for ln in body[:body.index("\n}\n")].splitlines()]
    for out_, leaf in (("FL", "header.frame_id.len"), ("F0", "header.frame_id.data[0]"),
                       ("F1", "header.frame_id.data[1]")):
        k = next(i for i, ln in enumerate(lines) if ln.endswith(f"= Echo_Y.{out_};"))
        assert re.fullmatch(rf"\(\*command\)\.{re.escape(leaf)} = _t_\w+;", lines[k + 1]), lines[k + 1]


def test_model_text_and_verify(echo, capsys):
    out, _ = echo
    proved = (out / f"{NODE}.model").read_text().splitlines()
    assert [ln for ln in proved if ln.startswith("output_relation")] == [
        "output_relation NS out data.len", *(f"output_relation E{i} out data.data[{i}]" for i in range(N)),
        "output_relation FL tagged header.frame_id.len", "output_relation F0 tagged header.frame_id.data[0]",
        "output_relation F1 tagged header.frame_id.data[1]", "output_relation X tagged point.x"]
    assert cli.main(["verify", str(out), "--model", str(MODEL)]) == 0, capsys.readouterr().err


def test_printed_c_compiles_with_warnings_as_errors(echo, tmp_path):
    out, _ = echo
    r = subprocess.run(["gcc", *GCC_STRICT, "-O2", "-c", str(out / f"{NODE}_glue.c"), "-I", str(out),
                        "-o", str(tmp_path / "glue.o")], capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr


# --------------------------------------------------------------------------
# The differential test


@pytest.fixture(scope="module")
def sides(echo, tmp_path_factory):
    out, _ = echo
    work = tmp_path_factory.mktemp("seq_echo_difftest")
    return difftest_sides(out, NODE, work)


def _outputs(dump: NodeDump, rnd: random.Random, length: int, frame_len: int) -> tuple[tuple[str, ...], dict]:
    """The controller's outputs of a cycle (the schedule's table) and what
    the two published messages must carry on the wire."""
    leaves = dump.leaves(dump.y[1])
    elems = [rnd.getrandbits(64) for _ in range(N)]
    x = rnd.getrandbits(64)
    vals = {"NS": length, **{f"E{i}": e for i, e in enumerate(elems)}, "FL": frame_len, "F0": 97, "F1": 98, "X": x}
    y = tuple(leaf_token(lf, vals[lf.path]) for lf in leaves)
    k, kf = min(length, N), min(frame_len, 128)
    out = ["layout.data_offset 0", f"data.len {k}", *(f"data.data[{i}] 0x{elems[i]:016x}" for i in range(k))]
    frame = [97, 98] + [0] * 126
    tagged = ["header.seq 0", "header.stamp.sec 0", "header.stamp.nsec 0", f"header.frame_id.len {kf}",
              *(f"header.frame_id.data[{i}] {frame[i]}" for i in range(kf)),
              f"point.x 0x{x:016x}", "point.y 0x0000000000000000", "point.z 0x0000000000000000"]
    return y, {"/out": out, "/tagged": tagged}


def _published(trace: str) -> list[dict]:
    """Per cycle, each published topic's lines (without the "  m ")."""
    out: list[dict] = [{}]
    topic = None
    for line in trace.splitlines():
        if line.startswith("publish "):
            topic = line.split()[1]
            out[-1][topic] = []
        elif line.startswith("  m "):
            out[-1][topic].append(line[4:])
        elif line == "cycle":
            out.append({})
    return out[:-1]


def test_difftest_at_the_lengths(sides):
    dump = sides["dump"]
    rnd = random.Random(15)
    lengths = LENGTHS + (2 ** 32 - 1, 128, 129, 7)
    frames = (0, 1, 127, 128, 129, 256, 2 ** 32 - 1, 2, 3, 130)
    cycles, wants = [], []
    for length, frame_len in zip(lengths, frames):
        y, want = _outputs(dump, rnd, length, frame_len)
        cycles.append(((), y))
        wants.append(want)
    sched = Schedule(tuple(cycles)).text()
    coq = sides_agree(sides, sched)
    got = _published(coq)
    assert len(got) == len(wants)
    for k, (g, w) in enumerate(zip(got, wants)):
        assert g == w, (k, lengths[k], g, w)


def test_difftest_random_lengths(sides):
    dump = sides["dump"]
    rnd = random.Random(4)
    cycles = []
    for _ in range(30):
        length = rnd.choice([rnd.randint(0, 2 * N + 1), rnd.getrandbits(32)])
        frame_len = rnd.choice([rnd.randint(0, 3), rnd.randint(126, 130), rnd.getrandbits(32)])
        cycles.append(((), _outputs(dump, rnd, length, frame_len)[0]))
    sched = Schedule(tuple(cycles)).text()
    coq = sides_agree(sides, sched)
    assert len(_published(coq)) == 30


# --------------------------------------------------------------------------
# The 6-joint arm example: certificate, diagram, verify

ARM = ROOT / "examples" / "arm" / "arm.yaml"


@pytest.fixture(scope="module")
def arm(tmp_path_factory):
    require_library()
    out = tmp_path_factory.mktemp("arm") / "out"
    return out, gen.generate(ARM, out)


def test_arm_theorems_certificate_and_verify(arm, capsys):
    out, result = arm
    assert set(result.theorems) >= {"arm_pd_ddc", "Ctrl.arm_pd_controller_wf", "Ctrl.arm_pd_e2e", "Ctrl.arm_pd_linked"}
    assert result.record.assumptions.count(CLOSED) == 1  # one Print Assumptions of their conjunction
    assert all(t in result.record.assumptions for t in result.theorems)
    cert = (out / "arm_pd.certificate.md").read_text()
    assert "### `ArmPD_Y.NE` → `/arm/effort data.len` (uint32)" in cert
    for i in range(6):
        assert f"### `ArmPD_Y.E{i}` → `/arm/effort data.data[{i}]` (float64)" in cert
        assert f"### `/joint_states position.data[{i}]` → `ArmPD_U.P{i}` (float64)" in cert
    assert "`ros_seq_float64_6`" in cert
    # name[] (an array of strings), effort[] and the frame_id are not
    # carried: the JointState struct holds its header's seq and stamp,
    # position and velocity
    h = (out / "arm_pd_types.h").read_text()
    js = re.search(r"struct sensor_msgs_JointState \{\n(.*?)\n\};", h, re.S).group(1)
    assert [ln.strip() for ln in js.splitlines()] == ["struct std_msgs_Header header;",
                                                      "struct ros_seq_float64_6 position;",
                                                      "struct ros_seq_float64_6 velocity;"]
    hd = re.search(r"struct std_msgs_Header \{\n(.*?)\n\};", h, re.S).group(1)
    assert "frame_id" not in hd and "ros_string" not in h
    assert cli.main(["verify", str(out), "--model", str(ARM)]) == 0, capsys.readouterr().err


def test_arm_diagram(tmp_path, capsys):
    dot = tmp_path / "arm.dot"
    assert cli.main(["diagram", str(ARM), "-o", str(dot), "--format", "dot"]) == 0, capsys.readouterr().err
    text = dot.read_text()
    for label in ("data (length) : uint32", "data[5] : float64", "position[0] : float64", "velocity (length) : uint32"):
        assert label in text, label

"""Variable-length arrays of messages and of strings through the whole
pipeline (rule 4.15): ``generate`` on tests/ros/models/elem_seq.yaml (a
``nav_msgs/Path`` whose ``poses`` is carried as
``ros_seq_geometry_msgs_PoseStamped_3``, each element's header with its
``frame_id`` as ``ros_string4``; a ``sensor_msgs/JointState`` whose
``name`` is carried as ``ros_seq_string4_3``) closes T2, prints the
bounded structs (the array's ``data`` an array of the element's struct),
the C compiles with ``-Wall -Wextra -Werror``, ``verify`` accepts the
folder, and the seam refuses a per-node file that reads another element.

The differential test sends paths of 0, 1, N-1, N, N+1 and 2N poses (N =
3) whose element frame_ids have 0, 1, M-1, M, M+1 and 2M bytes (M = 4),
and joint states with as many names of those lengths, with junk past
every length, through the Coq interpreter (which receives the raw message
and converts it as ``Environment.clamp`` says: each of the first min(len,
N) elements converted in turn, its own string capped, the others zero)
and the printed glue under gcc -O2 and ASan/UBSan (whose fake ROS API
converts it as the wrapper does): the traces agree bit for bit and give
the controller exactly the expected values; a harness that does not zero
past the length is caught.

Published (tests/ros/models/elem_seq_pub.yaml): both sides print a
published Path and JointState as the wrapper puts them on the wire, the
first min(len, N) elements, each string its first min(len, M) bytes, for
lengths 0, 1, N-1, N, N+1, 2N and 2^32-1 of the arrays and of the strings,
and that is exactly what the controller's outputs say.

With policy reject on both arrays (``poses``, ``name``:
``ros_rseq_...``), a Path or JointState holding more than N elements is
not delivered (``Environment.too_long``, ``accepted``: the array's own
length, and no reject field inside its elements, which the front end
refuses): both sides keep the previous message, and a harness that
delivers it truncated is caught."""

from __future__ import annotations

import random
import re
import subprocess

import pytest

import pyrosgen.generate as gen
from pyrosgen import cli
from pyrosgen.proof.coqdriver import CLOSED
from pyrosgen.verify.difftest import GCC_STRICT, Message, Schedule, leaf_token, run_side

from support.generate import (
    REPO as ROOT, difftest_sides, generate_with_tampered_node_file, require_library, sides_agree,
)

from build.test_elem_seq_wrapper_check import reject_model

MODEL = ROOT / "tests" / "ros" / "models" / "elem_seq.yaml"
NODE = "elem_seq"
N, M = 3, 4
LENGTHS = (0, 1, N - 1, N, N + 1, 2 * N)
STR_LENGTHS = (0, 1, M - 1, M, M + 1, 2 * M)


@pytest.fixture(scope="module")
def node(tmp_path_factory):
    require_library()
    out = tmp_path_factory.mktemp("elem_seq") / "out"
    result = gen.generate(MODEL, out)
    return out, result


def test_theorem_is_closed(node):
    _, result = node
    assert result.ddc and result.theorem == f"{NODE}_ddc"
    assert result.record.assumptions.count(CLOSED) == 1
    print(f"generate {NODE}: " + ", ".join(f"{k} {v:.2f} s" for k, v in result.times.items()))


def _struct(h: str, name: str) -> list[str]:
    m = re.search(rf"struct {name} \{{\n(.*?)\n\}};", h, re.S)
    assert m, (name, h[:3000])
    return [ln.strip() for ln in m.group(1).splitlines()]


def test_types_header_has_the_element_structs(node):
    out, _ = node
    h = (out / f"{NODE}_types.h").read_text()
    assert _struct(h, "ros_seq_geometry_msgs_PoseStamped_3") == [
        "unsigned int len;", "unsigned char truncated;", "struct geometry_msgs_PoseStamped data[3];"]
    assert _struct(h, "ros_seq_string4_3") == [
        "unsigned int len;", "unsigned char truncated;", "struct ros_string4 data[3];"]
    assert _struct(h, "ros_string4") == ["unsigned int len;", "unsigned char truncated;", "unsigned char data[4];"]
    # the element's struct: its header carries the frame_id a relation reads
    assert _struct(h, "std_msgs_Header") == ["unsigned int seq;", "struct ros_time stamp;",
                                             "struct ros_string4 frame_id;"]
    assert _struct(h, "nav_msgs_Path")[-1] == "struct ros_seq_geometry_msgs_PoseStamped_3 poses;"
    assert _struct(h, "sensor_msgs_JointState") == ["struct std_msgs_Header header;", "struct ros_seq_string4_3 name;"]
    # each struct before those that use it
    assert h.index("struct ros_string4 {") < h.index("struct std_msgs_Header {") \
        < h.index("struct geometry_msgs_PoseStamped {") < h.index("struct ros_seq_geometry_msgs_PoseStamped_3 {") \
        < h.index("struct nav_msgs_Path {")


def test_model_text_and_glue_read_the_element_leaves(node):
    out, _ = node
    text = (out / f"{NODE}.model").read_text().splitlines()
    for rel in ("input_relation path poses.len NP", "input_relation path poses.truncated TP",
                "input_relation path poses.data[0].pose.position.x P0X",
                "input_relation path poses.data[1].header.frame_id.data[0] P1F0",
                "input_relation path poses.data[1].header.frame_id.len P1FL",
                "input_relation path poses.data[2].header.frame_id.data[3] F2[3]",
                "input_relation joints name.data[0].len N0L", "input_relation joints name.data[0].truncated N0T",
                "input_relation joints name.data[2].data[3] N2B3", "input_relation joints name.data[1].data[0] N1[0]"):
        assert rel in text, rel
    c = (out / f"{NODE}_glue.c").read_text()
    assert "(*msg).poses.data[2].pose.orientation.w" in c and "(*msg).name.data[2].data[3]" in c
    # the callback copies only what relations read: no other element's leaf
    assert "poses.data[0].header" not in c and "name.data[0].data" not in c


def test_printed_c_compiles_with_warnings_as_errors(node, tmp_path):
    out, _ = node
    r = subprocess.run(["gcc", *GCC_STRICT, "-c", str(out / f"{NODE}_glue.c"), "-I", str(out),
                        "-o", str(tmp_path / "glue.o")], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr


def test_verify_accepts_the_folder(node, capsys):
    out, _ = node
    assert cli.main(["verify", str(out), "--model", str(MODEL)]) == 0, capsys.readouterr().err


def test_a_per_node_file_reading_another_element_is_refused(monkeypatch, capsys, tmp_path):
    """The per-node file proves its theorem about a node that reads pose 1
    for P0X: the seam (the model Coq printed against the YAML's) refuses it."""
    require_library()
    want = 'PField "poses"; PField "data"; PIndex 0; PField "pose"'
    out = tmp_path / "out"
    code, err = generate_with_tampered_node_file(MODEL, want, want.replace("PIndex 0", "PIndex 1"),
                                                 monkeypatch, capsys, out)
    assert code == 2 and not out.exists(), err
    assert "is not the model of the YAML file" in err and "poses.data[1].pose.position.x" in err, err


# --------------------------------------------------------------------------
# The differential test


@pytest.fixture(scope="module")
def sides(node, tmp_path_factory):
    out, _ = node
    return difftest_sides(out, NODE, tmp_path_factory.mktemp("elem_seq_difftest"), mutant="no_zero_fill")


def _fill(dump, st: str, rnd: random.Random, values: dict[str, int]) -> tuple[str, ...]:
    """The leaves of a message of struct ``st``: ``values`` by leaf path,
    every other leaf random (junk past every length)."""
    leaves = dump.leaves(st)
    known = {lf.path for lf in leaves}
    assert set(values) <= known, sorted(set(values) - known)
    return tuple(leaf_token(lf, values[lf.path] if lf.path in values else rnd.getrandbits(lf.bits))
                 for lf in leaves)


def _path_msg(dump, rnd: random.Random, length: int, frames: list[int]) -> tuple[Message, dict]:
    """A Path as sent: ``length`` poses (the first N represented), pose
    ``i``'s frame_id of ``frames[i]`` bytes; with what the controller must
    receive."""
    vals: dict[str, int] = {"poses.len": length, "header.frame_id.len": rnd.getrandbits(32)}
    elems = []
    for i in range(N):
        e = {"x": rnd.getrandbits(64), "w": rnd.getrandbits(64), "seq": rnd.getrandbits(32),
             "flen": frames[i], "frame": [rnd.randint(1, 255) for _ in range(M)]}
        elems.append(e)
        p = f"poses.data[{i}]"
        vals[f"{p}.pose.position.x"] = e["x"]
        vals[f"{p}.pose.orientation.w"] = e["w"]
        vals[f"{p}.header.seq"] = e["seq"]
        vals[f"{p}.header.frame_id.len"] = e["flen"]
        for j in range(M):
            vals[f"{p}.header.frame_id.data[{j}]"] = e["frame"][j]
    k = min(length, N)
    real = [i < k for i in range(N)]
    want = {"NP": str(k), "TP": str(int(length > N)),
            "P0X": f"0x{elems[0]['x'] if real[0] else 0:016x}",
            "P2W": f"0x{elems[2]['w'] if real[2] else 0:016x}",
            "P1S": str(elems[1]["seq"] if real[1] else 0),
            "P1F0": str(elems[1]["frame"][0] if real[1] and frames[1] > 0 else 0),
            "P1FL": str(min(frames[1], M) if real[1] else 0),
            "P1FT": str(int(real[1] and frames[1] > M))}
    for j in range(M):
        want[f"F2[{j}]"] = str(elems[2]["frame"][j] if real[2] and j < min(frames[2], M) else 0)
    return Message("/path", _fill(dump, "nav_msgs_Path", rnd, vals), 0), want


def _joints_msg(dump, rnd: random.Random, count: int, lens: list[int]) -> tuple[Message, dict]:
    """A JointState as sent: ``count`` names, name ``i`` of ``lens[i]`` bytes."""
    vals: dict[str, int] = {"name.len": count}
    names = []
    for i in range(N):
        b = [rnd.randint(1, 255) for _ in range(M)]
        names.append(b)
        vals[f"name.data[{i}].len"] = lens[i]
        for j in range(M):
            vals[f"name.data[{i}].data[{j}]"] = b[j]
    k = min(count, N)
    real = [i < k for i in range(N)]
    want = {"NJ": str(k), "TJ": str(int(count > N)),
            "N0L": str(min(lens[0], M) if real[0] else 0), "N0T": str(int(real[0] and lens[0] > M)),
            "N2B3": str(names[2][3] if real[2] and lens[2] > 3 else 0)}
    for j in range(M):
        want[f"N1[{j}]"] = str(names[1][j] if real[1] and j < min(lens[1], M) else 0)
    return Message("/joints", _fill(dump, "sensor_msgs_JointState", rnd, vals), 0), want


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
    """Every outer length with every nested string length (at each
    element position), one Path and one JointState per cycle."""
    dump = sides["dump"]
    rnd = random.Random(15)
    y0 = tuple(leaf_token(lf, 0) for lf in dump.leaves(dump.y[1]))
    cycles, wants = [], []
    for a, length in enumerate(LENGTHS):
        for b in range(len(STR_LENGTHS)):
            frames = [STR_LENGTHS[(b + i) % len(STR_LENGTHS)] for i in range(N)]
            path, wp = _path_msg(dump, rnd, length, frames)
            joints, wj = _joints_msg(dump, rnd, LENGTHS[(a + b) % len(LENGTHS)], frames[::-1])
            cycles.append(((path, joints), y0))
            wants.append({**wp, **wj})
    # huge lengths: the wrapper caps them as well
    path, wp = _path_msg(dump, rnd, 2**32 - 1, [2**32 - 1, 2**31, M + 1])
    joints, wj = _joints_msg(dump, rnd, 2**32 - 1, [2**32 - 1, M, 2**31])
    cycles.append(((path, joints), y0))
    wants.append({**wp, **wj})
    # a cycle without a message keeps the newest ones
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


# --------------------------------------------------------------------------
# Policy reject on the arrays themselves


@pytest.fixture(scope="module")
def reject_sides(tmp_path_factory):
    require_library()
    work = tmp_path_factory.mktemp("elem_seq_reject")
    out = work / "out"
    result = gen.generate(reject_model(work), out)
    assert result.ddc and result.record.assumptions.count(CLOSED) == 1
    h = (out / f"{NODE}_types.h").read_text()
    assert "struct ros_rseq_geometry_msgs_PoseStamped_3 poses;" in h and "struct ros_rseq_string4_3 name;" in h
    return difftest_sides(out, NODE, work / "sides", mutant="no_reject")


def test_difftest_reject_keeps_the_previous_message(reject_sides):
    """Lengths 0, 1, N-1, N, N+1, 2N and 2^32-1 of each array: the
    over-long messages are dropped (the controller keeps the previous
    values, its element strings capped as under truncate)."""
    dump = reject_sides["dump"]
    rnd = random.Random(16)
    y0 = tuple(leaf_token(lf, 0) for lf in dump.leaves(dump.y[1]))
    cycles, wants = [], []
    current = {}
    for k, length in enumerate(LENGTHS + (2**32 - 1,) + LENGTHS[::-1]):
        frames = [STR_LENGTHS[(k + i) % len(STR_LENGTHS)] for i in range(N)]
        path, wp = _path_msg(dump, rnd, length, frames)
        joints, wj = _joints_msg(dump, rnd, LENGTHS[(k + 2) % len(LENGTHS)], frames[::-1])
        cycles.append(((path, joints), y0))
        # TP and TJ read the truncated flags of pose 0's frame_id and of name[1]
        if length <= N:
            current.update({x: v for x, v in wp.items() if x != "TP"})
            current["TP"] = str(int(length > 0 and frames[0] > M))
        jl = LENGTHS[(k + 2) % len(LENGTHS)]
        if jl <= N:
            current.update({x: v for x, v in wj.items() if x != "TJ"})
            current["TJ"] = str(int(jl > 1 and frames[::-1][1] > M))
        assert "NP" in current and "NJ" in current  # the first cycle's messages are both accepted
        wants.append(dict(current))
    sched = Schedule(tuple(cycles)).text()
    coq = sides_agree(reject_sides, sched)
    steps = _steps(coq)
    assert len(steps) == len(wants)
    for k, (got, want) in enumerate(zip(steps, wants)):
        assert got == want, (k, got, want)
    assert run_side(reject_sides["c_mutant"], sched) != coq


# --------------------------------------------------------------------------
# Published arrays of messages and strings (tests/ros/models/elem_seq_pub.yaml)

PUB_MODEL = ROOT / "tests" / "ros" / "models" / "elem_seq_pub.yaml"


@pytest.fixture(scope="module")
def pub_sides(tmp_path_factory):
    require_library()
    work = tmp_path_factory.mktemp("elem_seq_pub")
    result = gen.generate(PUB_MODEL, work / "out")
    assert result.ddc and result.record.assumptions.count(CLOSED) == 1
    text = (work / "out" / "elem_seq_pub.model").read_text().splitlines()
    assert "output_relation NP path poses.len" in text and "output_relation N2B0 joints name.data[2].data[0]" in text
    return difftest_sides(work / "out", "elem_seq_pub", work / "sides")


def _published(trace: str) -> list[tuple[str, list[str]]]:
    """The published messages of a trace: (topic, their lines)."""
    out: list[tuple[str, list[str]]] = []
    for line in trace.splitlines():
        if line.startswith("publish "):
            out.append((line.split()[1], []))
        elif line.startswith("  m ") and out:
            out[-1][1].append(line[4:])
    return out


def _wire(length: int, slen: int, x: list[int]) -> tuple[list[str], list[str]]:
    """The Path and JointState the controller's outputs make, as they go
    on the wire: the first min(length, N) elements, each string its first
    min(slen, M) bytes (Environment.clamp on publish)."""
    k, s = min(length, N), min(slen, M)
    path = ["header.seq 0", "header.stamp.sec 0", "header.stamp.nsec 0", "header.frame_id.len 3",
            "header.frame_id.data[0] 109", "header.frame_id.data[1] 97", "header.frame_id.data[2] 112",
            f"poses.len {k}"]
    for i in range(k):
        p = f"poses.data[{i}]"
        path += [f"{p}.header.seq {length if i == 1 else 0}", f"{p}.header.stamp.sec 0", f"{p}.header.stamp.nsec 0"]
        fb = [97, 98, 0, 0] if i == 1 else []
        flen = s if i == 1 else 0
        path += [f"{p}.header.frame_id.len {flen}"] + [f"{p}.header.frame_id.data[{j}] {fb[j]}" for j in range(flen)]
        path += [f"{p}.pose.position.x 0x{x[i]:016x}"] + [f"{p}.pose.{f} 0x{0:016x}" for f in (
            "position.y", "position.z", "orientation.x", "orientation.y", "orientation.z", "orientation.w")]
    joints = ["header.seq 0", "header.stamp.sec 0", "header.stamp.nsec 0", "header.frame_id.len 0", f"name.len {k}"]
    names = [[119, 120, 121, 122], [], [122, 0, 0, 0]]
    for i in range(k):
        n = s if i != 1 else 0
        joints += [f"name.data[{i}].len {n}"] + [f"name.data[{i}].data[{j}] {names[i][j]}" for j in range(n)]
    return path, joints


def test_difftest_published_elements(pub_sides):
    """Lengths 0, 1, N-1, N, N+1, 2N and 2^32-1 of the arrays with string
    lengths 0, 1, M-1, M, M+1, 2M and 2^32-1: both sides print exactly the
    first min(len, N) elements, each string's first min(len, M) bytes."""
    dump = pub_sides["dump"]
    ys = dump.leaves(dump.y[1])
    rnd = random.Random(17)
    cycles, wants = [], []
    for length in LENGTHS + (2**32 - 1,):
        for slen in STR_LENGTHS + (2**32 - 1,):
            x = [rnd.getrandbits(64) for _ in range(3)]
            vals = {"NP": length, "X0": x[0], "X1": x[1], "X2": x[2], "Q1": length, "FL1": slen, "F10": 97,
                    "F11": 98, "NJ": length, "N0L": slen, "N0[0]": 119, "N0[1]": 120, "N0[2]": 121, "N0[3]": 122,
                    "N2L": slen, "N2B0": 122}
            cycles.append(((), tuple(leaf_token(lf, vals[lf.path]) for lf in ys)))
            wants.append(_wire(length, slen, x))
    sched = Schedule(tuple(cycles)).text()
    coq = sides_agree(pub_sides, sched)
    pubs = _published(coq)
    # one Path and one JointState per cycle, from the cycle's outputs
    got = [(pubs[i][1], pubs[i + 1][1]) for i in range(0, len(pubs), 2)]
    assert [t for t, _ in pubs[::2]] == ["/path"] * len(got) and [t for t, _ in pubs[1::2]] == ["/joints"] * len(got)
    assert len(got) == len(wants)
    for k, (g, w) in enumerate(zip(got, wants)):
        assert g == w, (k, g, w)

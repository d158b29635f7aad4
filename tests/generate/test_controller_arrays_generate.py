"""Controller arrays through the whole pipeline (rule 4.15):
``generate`` on tests/ros/models/scan_array.yaml (a LaserScan's
``ranges``, at most N = 8, related whole to the controller array
``Scan[8]``, two of its elements to the elements of ``Last[2]``; the
controller array ``Echo[8]`` related whole to a published
``Float32MultiArray``'s ``data``, the elements of ``Pt[3]`` to a
``Point32``) closes T2 on the element relations (``mkinrel_at``,
``mkoutrel_at``), prints the array members and the element copies, the
C compiles with ``-Wall -Wextra -Werror``, the layout check accepts the
Embedded Coder-style header of tests/ros/controllers/scan_array and
refuses one whose array has another size or element type, Frama-C WP
proves the contracts, ``verify`` accepts the folder, and the seam refuses
a per-node file that relates another element.

The differential test runs scans of lengths 0, 1, N-1, N, N+1 and 2N
(junk past the length) and output lengths 0, 1, N-1, N, N+1, 2N and
2^32-1 through the Coq interpreter and the printed glue under gcc -O2
and ASan/UBSan: the traces agree bit for bit; the controller receives
exactly ``Scan[i]`` = the i-th range below min(length, N) and 0 past it,
``Last`` the 7th and 6th; the published array is exactly the first
min(NEcho, N) elements of ``Echo``; a harness that does not zero past
the length is caught."""

from __future__ import annotations

import random
import re
import shutil
import subprocess

import pytest

import pyrosgen.generate as gen
from pyrosgen import cli, load_model
from pyrosgen.proof.coqdriver import CLOSED
from pyrosgen.ros.layout import LayoutMismatch, check_layout, render_layout_check
from pyrosgen.verify.acsl import contracts, run_wp
from pyrosgen.verify.certificate import read_manifest, write_certificate
from pyrosgen.verify.difftest import GCC_STRICT, Message, NodeDump, Schedule, leaf_token, run_side

from support.generate import (
    REPO as ROOT, difftest_sides, generate_with_tampered_node_file, require_library, sides_agree,
)

MODEL = ROOT / "tests" / "ros" / "models" / "scan_array.yaml"
CONTROLLER = ROOT / "tests" / "ros" / "controllers" / "scan_array"
NODE = "scan_array"
N = 8
LENGTHS = (0, 1, N - 1, N, N + 1, 2 * N)


@pytest.fixture(scope="module")
def arrays(tmp_path_factory):
    require_library()
    out = tmp_path_factory.mktemp("scan_array") / "out"
    result = gen.generate(MODEL, out)
    return out, result


def test_theorem_is_closed(arrays):
    out, result = arrays
    assert result.ddc and result.theorem == f"{NODE}_ddc"
    assert result.record.assumptions.count(CLOSED) == 1
    assert all(t in result.record.assumptions for t in result.theorems)
    v = (out / f"{NODE}.v").read_text()
    assert '("Scan", FTarray (FTprim Pfloat32) 8)' in v and '("NScan", FTprim Puint32)' in v
    # Scan and Echo whole: one map over zrange N each (Coq computes the N
    # element relations); Last's and Pt's elements one by one
    assert ('map (fun i => mkinrel_at "scan" ([PField "ranges"; PField "data"] ++ [PIndex i]) "Scan" [PIndex i]) '
            f"(zrange {N})") in v
    assert ('map (fun i => mkoutrel_at "Echo" [PIndex i] "echo" ([PField "data"; PField "data"] ++ [PIndex i])) '
            f"(zrange {N})") in v
    assert v.count("mkinrel_at ") == 1 + 2 and v.count("mkoutrel_at ") == 1 + 3


def test_types_header_declares_the_arrays(arrays):
    out, _ = arrays
    h = (out / f"{NODE}_types.h").read_text()
    u = re.search(r"struct ExtU_ScanArr_T \{\n(.*?)\n\};", h, re.S).group(1)
    assert [ln.strip() for ln in u.splitlines()] == ["float Scan[8];", "unsigned int NScan;", "float Last[2];"]
    y = re.search(r"struct ExtY_ScanArr_T \{\n(.*?)\n\};", h, re.S).group(1)
    assert [ln.strip() for ln in y.splitlines()] == ["float Echo[8];", "unsigned int NEcho;", "float Pt[3];"]


def _body(c: str, head: str) -> list[str]:
    body = c[c.index(head + "\n{"):]
    return [ln.strip() for ln in body[:body.index("\n}\n")].splitlines()]


def test_the_glue_copies_element_by_element(arrays):
    out, _ = arrays
    c = (out / f"{NODE}_glue.c").read_text()
    # the elements are direct relations (rule 4.16: /scan is not timed):
    # the callback copies them once, from *msg into ScanArr_U, after the
    # length into scan_msg; input_glue copies only the length
    lines = _body(c, "void scan_callback(struct sensor_msgs_LaserScan *msg)")
    assert lines[2:] == ["unsigned int _t_uint;", "float _t_float;", "_t_uint = (*msg).ranges.len;",
                         "scan_msg.ranges.len = _t_uint;",
                         *(ln for i in range(N) for ln in (f"_t_float = (*msg).ranges.data[{i}];",
                                                           f"ScanArr_U.Scan[{i}] = _t_float;")),
                         "_t_float = (*msg).ranges.data[7];", "ScanArr_U.Last[0] = _t_float;",
                         "_t_float = (*msg).ranges.data[6];", "ScanArr_U.Last[1] = _t_float;"]
    lines = _body(c, "void input_glue(void)")
    assert lines[2:] == ["unsigned int _t_uint;", "_t_uint = scan_msg.ranges.len;", "ScanArr_U.NScan = _t_uint;"]
    lines = _body(c, "void output_glue_echo(struct std_msgs_Float32MultiArray *command)")
    for i in range(N):
        k = lines.index(f"_t_float = ScanArr_Y.Echo[{i}];")
        assert lines[k + 1] == f"(*command).data.data[{i}] = _t_float;"
    lines = _body(c, "void output_glue_pt(struct geometry_msgs_Point32 *command)")
    for i, f in enumerate("xyz"):
        k = lines.index(f"_t_float = ScanArr_Y.Pt[{i}];")
        assert lines[k + 1] == f"(*command).{f} = _t_float;"


def test_model_text_certificate_and_verify(arrays, capsys):
    out, _ = arrays
    proved = (out / f"{NODE}.model").read_text().splitlines()
    assert proved[4:12] == ["inputs ScanArr_U ExtU_ScanArr_T", "input Scan array 8 float32", "input NScan uint32",
                            "input Last array 2 float32", "outputs ScanArr_Y ExtY_ScanArr_T",
                            "output Echo array 8 float32", "output NEcho uint32", "output Pt array 3 float32"]
    assert [ln for ln in proved if ln.startswith("input_relation")] == [
        *(f"input_relation scan ranges.data[{i}] Scan[{i}]" for i in range(N)), "input_relation scan ranges.len NScan",
        "input_relation scan ranges.data[7] Last[0]", "input_relation scan ranges.data[6] Last[1]"]
    assert [ln for ln in proved if ln.startswith("output_relation")] == [
        *(f"output_relation Echo[{i}] echo data.data[{i}]" for i in range(N)), "output_relation NEcho echo data.len",
        "output_relation Pt[0] pt x", "output_relation Pt[1] pt y", "output_relation Pt[2] pt z"]
    cert = (out / f"{NODE}.certificate.md").read_text()
    # a whole-array relation is one section: its count, its first and last copies
    scan = _section(cert, f"### `/scan ranges.data[0..{N - 1}]` → `ScanArr_U.Scan[0..{N - 1}]` (float32)")
    assert f"one section for its {N} elements" in scan
    assert "_t_float = (*msg).ranges.data[0];" in scan and f"ScanArr_U.Scan[{N - 1}] = _t_float;" in scan
    assert "ranges.data[3]" not in scan  # the middle elements: checked, not quoted
    last = _section(cert, "### `/scan ranges.data[7..6]` → `ScanArr_U.Last[0..1]` (float32)")  # reversed
    assert "one section for its 2 elements" in last and "ScanArr_U.Last[1] = _t_float;" in last
    echo = _section(cert, f"### `ScanArr_Y.Echo[0..{N - 1}]` → `/echo data.data[0..{N - 1}]` (float32)")
    assert f"(*command).data.data[{N - 1}] = _t_float;" in echo
    assert "### `ScanArr_Y.Pt[2]` → `/pt z` (float32)" in cert
    assert cli.main(["verify", str(out), "--model", str(MODEL)]) == 0, capsys.readouterr().err


def test_printed_c_compiles_with_warnings_as_errors(arrays, tmp_path):
    out, _ = arrays
    for src in (out / f"{NODE}_glue.c", CONTROLLER / "ScanArr.c"):
        r = subprocess.run(["gcc", *GCC_STRICT, "-O2", "-c", str(src), "-I", str(out), "-I", str(CONTROLLER),
                            "-o", str(tmp_path / (src.name + ".o"))], capture_output=True, text=True, timeout=600)
        assert r.returncode == 0, r.stderr


def test_layout_check_against_the_controller_header(arrays, tmp_path):
    """The printed structs and the Embedded Coder header agree (same
    array sizes and element types); a header with another size or
    element type is refused, naming the field."""
    out, _ = arrays
    model = load_model(MODEL)
    types_h = (out / f"{NODE}_types.h").read_text()
    check_c = tmp_path / "check.c"
    check_c.write_text(render_layout_check(model, types_h, f"{NODE}_types.h"))
    check_layout(model, check_c, CONTROLLER, tmp_path / "work", types_h)
    for old, new, field in (("real32_T Scan[8];", "real32_T Scan[9];", "ScanArr_U.Scan"),
                            ("real32_T Pt[3];", "real_T Pt[3];", "ScanArr_Y.Pt"),
                            ("real32_T Last[2];", "real32_T Last;", "ScanArr_U.Last")):
        bad = tmp_path / f"bad_{field.replace('.', '_')}"
        shutil.copytree(CONTROLLER, bad)
        h = bad / "ScanArr.h"
        assert old in h.read_text()
        h.write_text(h.read_text().replace(old, new))
        with pytest.raises(LayoutMismatch) as exc:
            check_layout(model, check_c, bad, tmp_path / f"work_{field}", types_h)
        assert any(field in p for p in exc.value.problems), exc.value.problems


def test_wp_proves_the_contracts(arrays, tmp_path):
    out, _ = arrays
    model = load_model(MODEL)
    res = run_wp(model, out / f"{NODE}_glue.c", out / f"{NODE}_types.h", tmp_path / "wp")
    assert res.ok and res.proved == res.total
    cs = {c.name: c for c in contracts(model)}
    assert "ScanArr_U.Scan[7]" in cs["scan_callback"].assigns    # rule 4.16
    assert cs["input_glue"].assigns == ("ScanArr_U.NScan",)
    for c in cs.values():
        assert f"typed_{c.name}_ensures : Valid" in res.output, c.name


def test_a_per_node_file_relating_another_element_is_refused(monkeypatch, capsys, tmp_path):
    """The per-node file proves its theorem about a node that publishes
    Echo reversed (Echo[7 - i] as data[i], a well-formed model): the seam
    (the model Coq printed against the YAML's) refuses it."""
    require_library()
    want = 'mkoutrel_at "Echo" [PIndex i] "echo"'
    out = tmp_path / "out"
    code, err = generate_with_tampered_node_file(MODEL, want, want.replace("PIndex i", f"PIndex ({N - 1} - i)"),
                                                 monkeypatch, capsys, out)
    assert code == 2 and not out.exists(), err
    assert "is not the model of the YAML file" in err and "Echo[7] echo data.data[0]" in err, err


# --------------------------------------------------------------------------
# The differential test


@pytest.fixture(scope="module")
def sides(arrays, tmp_path_factory):
    out, _ = arrays
    work = tmp_path_factory.mktemp("scan_array_difftest")
    return difftest_sides(out, NODE, work, mutant="no_zero_fill")


F32_JUNK = 0x41100000          # 9.0, past the length


def _scan(dump: NodeDump, rnd: random.Random, length: int) -> tuple[Message, dict]:
    """A LaserScan as sent: ``length`` ranges (the first N represented,
    random bits, junk past the length), the other leaves random; with the
    inputs the controller must receive."""
    st = "sensor_msgs_LaserScan"
    leaves = dump.leaves(st)
    seq = {b.path: b for b in dump.bounded(st)}["ranges"]
    vals = [leaf_token(lf, rnd.getrandbits(lf.bits)) for lf in leaves]
    vals[seq.first_leaf] = str(length)
    vals[seq.first_leaf + 1] = str(rnd.randint(0, 255))
    data = [rnd.getrandbits(32) if i < length else F32_JUNK for i in range(N)]
    for i, bits in enumerate(data):
        vals[seq.first_leaf + 2 + i] = leaf_token(leaves[seq.first_leaf + 2 + i], bits)
    k = min(length, N)
    got = [data[i] if i < k else 0 for i in range(N)]
    want = {f"Scan[{i}]": f"0x{got[i]:08x}" for i in range(N)}
    want.update({"NScan": str(k), "Last[0]": f"0x{got[7]:08x}", "Last[1]": f"0x{got[6]:08x}"})
    return Message("/scan", tuple(vals), 0), want


def _outputs(dump: NodeDump, rnd: random.Random, length: int) -> tuple[tuple[str, ...], dict]:
    """The controller's outputs of a cycle and what the published
    messages must carry on the wire."""
    echo = [rnd.getrandbits(32) for _ in range(N)]
    pt = [rnd.getrandbits(32) for _ in range(3)]
    vals = {**{f"Echo[{i}]": e for i, e in enumerate(echo)}, "NEcho": length,
            **{f"Pt[{i}]": p for i, p in enumerate(pt)}}
    y = tuple(leaf_token(lf, vals[lf.path]) for lf in dump.leaves(dump.y[1]))
    k = min(length, N)
    return y, {"/echo": ["layout.data_offset 0", f"data.len {k}", *(f"data.data[{i}] 0x{echo[i]:08x}"
                                                                    for i in range(k))],
               "/pt": [f"{f} 0x{pt[i]:08x}" for i, f in enumerate("xyz")]}


def _trace(trace: str) -> tuple[list[dict], list[dict]]:
    """Per step, the controller inputs (``  u`` lines); per cycle, each
    published topic's lines."""
    steps: list[dict] = []
    pubs: list[dict] = [{}]
    topic = None
    for line in trace.splitlines():
        if line == "step":
            steps.append({})
        elif line.startswith("  u "):
            _, name, value = line.split()
            steps[-1][name] = value
        elif line.startswith("publish "):
            topic = line.split()[1]
            pubs[-1][topic] = []
        elif line.startswith("  m "):
            pubs[-1][topic].append(line[4:])
        elif line == "cycle":
            pubs.append({})
    return steps, pubs[:-1]


def test_the_dump_has_the_array_members(sides):
    dump = sides["dump"]
    assert [lf.path for lf in dump.leaves(dump.u[1])] == [*(f"Scan[{i}]" for i in range(N)), "NScan",
                                                          "Last[0]", "Last[1]"]
    assert [lf.path for lf in dump.leaves(dump.y[1])] == [*(f"Echo[{i}]" for i in range(N)), "NEcho",
                                                          "Pt[0]", "Pt[1]", "Pt[2]"]


def test_difftest_at_the_lengths(sides):
    dump = sides["dump"]
    rnd = random.Random(15)
    cycles, wants, pub_wants = [], [], []
    out_lengths = LENGTHS + (2 ** 32 - 1,)
    for k, length in enumerate(LENGTHS * 2):
        msg, want = _scan(dump, rnd, length)
        y, pub = _outputs(dump, rnd, out_lengths[k % len(out_lengths)])
        cycles.append(((msg,), y))
        wants.append(want)
        pub_wants.append(pub)
    # a cycle without a message keeps the newest scan
    y, pub = _outputs(dump, rnd, 3)
    cycles.append(((), y))
    wants.append(wants[-1])
    pub_wants.append(pub)
    sched = Schedule(tuple(cycles)).text()
    coq = sides_agree(sides, sched)
    steps, pubs = _trace(coq)
    assert len(steps) == len(wants) and len(pubs) == len(pub_wants)
    for k, (got, want) in enumerate(zip(steps, wants)):
        assert got == want, (k, got, want)
    for k, (got, want) in enumerate(zip(pubs, pub_wants)):
        assert got == want, (k, got, want)
    # a harness that does not zero past the length is caught
    assert run_side(sides["c_mutant"], sched) != coq


def test_difftest_random(sides):
    dump = sides["dump"]
    rnd = random.Random(8)
    cycles = []
    for _ in range(30):
        msgs = tuple(_scan(dump, rnd, rnd.choice([rnd.randint(0, 2 * N + 1), rnd.getrandbits(32)]))[0]
                     for _ in range(rnd.randint(0, 3)))
        length = rnd.choice([rnd.randint(0, 2 * N + 1), rnd.getrandbits(32)])
        cycles.append((msgs, _outputs(dump, rnd, length)[0]))
    sched = Schedule(tuple(cycles)).text()
    steps, pubs = _trace(sides_agree(sides, sched))
    assert len(steps) == 30 and len(pubs) == 30


def _section(cert: str, head: str) -> str:
    assert head in cert, head
    return cert.split(head, 1)[1].split("\n## ", 1)[0].split("\n### ", 1)[0]


def test_a_whole_array_section_holds_every_element(arrays, tmp_path):
    """The one section of a whole-array relation stands for every element
    only when each is copied in the first one's form: printed C in which
    element 5 of Echo is copied from Echo[4] breaks the run there, and
    the odd copy is quoted in a section of its own."""
    out, _ = arrays
    c = tmp_path / "copy"
    shutil.copytree(out, c)
    glue = c / f"{NODE}_glue.c"
    text = glue.read_text()
    assert text.count("_t_float = ScanArr_Y.Echo[5];") == 1
    glue.write_text(text.replace("_t_float = ScanArr_Y.Echo[5];", "_t_float = ScanArr_Y.Echo[4];"))
    rec, files = read_manifest(c / f"{NODE}.manifest.json")
    write_certificate(rec, c, list(files))
    cert = (c / f"{NODE}.certificate.md").read_text()
    assert "### `ScanArr_Y.Echo[0..4]` → `/echo data.data[0..4]` (float32)" in cert
    odd = _section(cert, "### `ScanArr_Y.Echo[5]` → `/echo data.data[5]` (float32)")
    assert "_t_float = ScanArr_Y.Echo[4];" in odd and "(*command).data.data[5] = _t_float;" in odd
    assert f"### `ScanArr_Y.Echo[6..{N - 1}]` → `/echo data.data[6..{N - 1}]` (float32)" in cert

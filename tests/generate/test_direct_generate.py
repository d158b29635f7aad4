"""Direct input relations (DESIGN.md rule 4.16) through the whole
pipeline, on tests/generate/models/ok_direct.yaml: the array elements of
untimed topics (a whole scan into ``Scan[4]``, a range read twice, a
string byte, an element of a fixed-size array) are copied by their
callbacks straight from ``*msg`` into ``D_U`` and by nothing else; the
lengths, a scalar leaf and every relation of the timed topics take the
two copies (callback into the topic's global, then ``input_glue``); the
stamp source keeps its stamp in its global.

T2 is closed; the printed callbacks and ``input_glue`` are exactly the
rule's; the certificate shows a direct relation's two lines in its
callback and refuses a C whose direct copy reads another leaf or that
``input_glue`` copies too; Frama-C WP proves the contracts of every
function (the output glue's with the stamp copied from ``/scan``, rule
4.13) and refuses glues with a direct copy one index off, a direct
relation copied again by ``input_glue`` or its leaf still kept in the
global (a stamp copied from another topic: tests/validation/test_wp.py);
the Coq interpreter and the glue under gcc (and the
sanitizers) print the same traces, in which the controller receives the
newest message's elements, also in cycles without a message."""

from __future__ import annotations

import random
import re
import shutil

import pytest

import pyrosgen.generate as gen
from pyrosgen import cli, load_model
from pyrosgen.proof.coqdriver import CLOSED
from pyrosgen.verify.acsl import WPError, contract_frame, contracts, render_wrapper, run_wp_file
from pyrosgen.verify.certificate import CertificateError, write_certificate
from pyrosgen.verify.difftest import Message, Schedule, leaf_token

from support.generate import MODELS, difftest_sides, require_library, sides_agree

MODEL = MODELS / "ok_direct.yaml"
NODE = "direct"
N = 4          # max_length of ranges
FN = 8         # max_length of header.frame_id


@pytest.fixture(scope="module")
def direct(tmp_path_factory):
    require_library()
    out = tmp_path_factory.mktemp("direct") / "out"
    result = gen.generate(MODEL, out)
    return out, result


def _body(c: str, head: str) -> list[str]:
    body = c[c.index(head + "\n{"):]
    return [ln.strip() for ln in body[:body.index("\n}\n")].splitlines()[2:]]


def _copy(src: str, dst: str, t: str) -> list[str]:
    return [f"_t_{t} = {src};", f"{dst} = _t_{t};"]


def test_theorem_is_closed(direct):
    out, result = direct
    assert result.ddc and result.theorem == f"{NODE}_ddc"
    assert result.record.assumptions.count(CLOSED) == 1


def test_the_callbacks_write_the_direct_relations(direct):
    out, _ = direct
    c = (out / f"{NODE}_glue.c").read_text()
    # the leaves other readers need (the stamp, the length), into the
    # global, in leaf order; then the direct relations, in model order
    assert _body(c, "void scan_callback(struct sensor_msgs_LaserScan *msg)") == [
        "unsigned char _t_uchar;", "unsigned int _t_uint;", "float _t_float;",
        *_copy("(*msg).header.stamp.sec", "scan_msg.header.stamp.sec", "uint"),
        *_copy("(*msg).header.stamp.nsec", "scan_msg.header.stamp.nsec", "uint"),
        *_copy("(*msg).ranges.len", "scan_msg.ranges.len", "uint"),
        *(ln for i in range(N) for ln in _copy(f"(*msg).ranges.data[{i}]", f"D_U.Scan[{i}]", "float")),
        *_copy("(*msg).ranges.data[1]", "D_U.R1", "float"),
        *_copy("(*msg).header.frame_id.data[0]", "D_U.F0", "uchar")]
    assert _body(c, "void pose_callback(struct geometry_msgs_PoseWithCovarianceStamped *msg)") == [
        "double _t_double;",
        *_copy("(*msg).pose.pose.position.x", "pose_msg.pose.pose.position.x", "double"),
        *_copy("(*msg).pose.covariance[3]", "D_U.Cov3", "double")]
    # a timed topic's callback keeps its elements in its global, as before
    assert _body(c, "void tscan_callback(struct sensor_msgs_LaserScan *msg)")[3:7] == [
        *_copy("(*msg).ranges.len", "tscan_msg.ranges.len", "uint"),
        *_copy("(*msg).ranges.data[2]", "tscan_msg.ranges.data[2]", "float")]
    assert _body(c, "void dscan_callback(struct sensor_msgs_LaserScan *msg)")[2:4] == [
        *_copy("(*msg).ranges.data[1]", "dscan_msg.ranges.data[1]", "float")]
    # input_glue copies the relations that are not direct, and only those
    glue = _body(c, "void input_glue(void)")
    assert glue[:16] == [
        "unsigned long long _now;", "unsigned long long _age;", "unsigned char _t_uchar;", "unsigned int _t_uint;",
        "float _t_float;", "double _t_double;",
        *_copy("scan_msg.ranges.len", "D_U.N", "uint"),
        *_copy("pose_msg.pose.pose.position.x", "D_U.PX", "double"),
        *_copy("tscan_msg.ranges.data[2]", "D_U.T2", "float"),
        *_copy("tscan_msg.ranges.len", "D_U.TN", "uint"),
        *_copy("dscan_msg.ranges.data[1]", "D_U.D1", "float")]
    for dst in (*(f"D_U.Scan[{i}]" for i in range(N)), "D_U.R1", "D_U.F0", "D_U.Cov3"):
        assert not any(ln.startswith(dst + " = ") for ln in glue), dst
    # no element of an untimed topic is kept in its global
    assert not re.search(r"\b(scan_msg\.ranges\.data|scan_msg\.header\.frame_id|pose_msg\.pose\.covariance)", c)


def _sections(cert: str) -> dict[tuple[str, str, str], tuple[str, int, int]]:
    """Each relation's section of the certificate, by (source, target,
    type): the section, the relation's place in it and its number of
    elements (1, or the count of a whole-array relation's one section,
    whose ends read ``x[a..b]``)."""
    out = {}
    for part in cert.split("\n### `")[1:]:
        m = re.match(r"(.+?)` → `(.+?)` \((\w+)\)\n", part)
        if m is None:
            continue
        src, dst, prim = m.groups()
        block = part[m.end():].split("\n## ", 1)[0]
        rs, rd = re.search(r"\[(\d+)\.\.(\d+)\]", src), re.search(r"\[(\d+)\.\.(\d+)\]", dst)
        if rs is None:
            out[(src, dst, prim)] = (block, 0, 1)
            continue
        (a, b), (c, d) = map(int, rs.groups()), map(int, rd.groups())
        n = abs(b - a) + 1
        assert abs(d - c) + 1 == n
        for k in range(n):
            out[(src[:rs.start()] + f"[{a + (k if b >= a else -k)}]" + src[rs.end():],
                 dst[:rd.start()] + f"[{c + (k if d >= c else -k)}]" + dst[rd.end():], prim)] = (block, k, n)
    return out


def test_certificate_rows(direct):
    out, _ = direct
    cert = (out / f"{NODE}.certificate.md").read_text()
    glue = (out / f"{NODE}_glue.c").read_text().splitlines()
    model = load_model(MODEL)
    written, copied = 0, 0
    sections = _sections(cert)
    for r in model.input_relations:
        block, k, n = sections[(f"{r.topic.name} {r.path}", f"D_U.{r.input_target}", r.path.prim)]
        quoted = re.findall(r"^/\* \S+:(\d+) \*/ (.*)$", block, re.M)
        assert all(glue[int(n) - 1].strip() == text for n, text in quoted)
        texts = [text for _, text in quoted]
        if n > 1:  # an element of a whole-array relation: its one section quotes the first and last copies
            assert f"one section for its {n} elements" in block and len(texts) % 2 == 0
            if k not in (0, n - 1):
                written += model.is_direct(r)
                copied += not model.is_direct(r)
                continue
            texts = texts[:len(texts) // 2] if k == 0 else texts[len(texts) // 2:]
        if model.is_direct(r):
            written += 1
            assert f"Written by the callback `{r.topic.callback}` alone" in block and "rule 4.16" in block
            assert len(texts) == 2 and texts[0].endswith(f" = (*msg).{r.path};")
            assert texts[1].startswith(f"D_U.{r.input_target} = _t_")
        else:
            copied += 1
            assert f"Copied by the callback `{r.topic.callback}`" in block and "then by `input_glue`" in block
            assert len(texts) == 4 and texts[0].endswith(f" = (*msg).{r.path};")
            assert texts[1].startswith(f"{r.topic.msg_var}.{r.path} = ") and texts[3].startswith(f"D_U.{r.input_target} = ")
    assert (written, copied) == (7, 5)


@pytest.mark.parametrize("old,new,message", [
    ("_t_float = (*msg).ranges.data[2];\n    D_U.Scan[2]", "_t_float = (*msg).ranges.data[3];\n    D_U.Scan[2]",
     "does not copy D_U.Scan[2] from (*msg).ranges.data[2]"),
    ("    D_U.N = _t_uint;\n", "    D_U.N = _t_uint;\n    _t_float = scan_msg.ranges.data[1];\n    D_U.R1 = _t_float;\n",
     "input_glue copies D_U.R1, a direct relation"),
], ids=["another-index", "input-glue-copies-it-too"])
def test_certificate_refuses_a_c_that_is_not_the_rule(direct, tmp_path, old, new, message):
    out, result = direct
    copy = tmp_path / "copy"
    shutil.copytree(out, copy)
    c = copy / f"{NODE}_glue.c"
    text = c.read_text()
    assert text.count(old) == 1
    c.write_text(text.replace(old, new))
    with pytest.raises(CertificateError, match=re.escape(message)):
        write_certificate(result.record, copy, result.covered)


def test_verify_accepts_the_folder(direct, capsys):
    out, _ = direct
    assert cli.main(["verify", str(out), "--model", str(MODEL)]) == 0, capsys.readouterr().err


# --------------------------------------------------------------------------
# Frama-C WP

def _wp(out, tmp_path, old: str | None = None, new: str | None = None, function: str | None = None,
        timeout: int = 5):
    """WP on the glue (``old`` replaced by ``new``), with the contracts of
    every function (or only of ``function``): the callbacks, ``input_glue``
    and the output glue (whose stamp, rule 4.13, is ``/scan``'s, kept in
    ``scan_msg``)."""
    model = load_model(MODEL)
    work = tmp_path / "wp"
    work.mkdir()
    text = (out / f"{NODE}_glue.c").read_text()
    if old is not None:
        assert text.count(old) == 1, old
        text = text.replace(old, new)
    (work / f"{NODE}_glue.c").write_text(text)
    shutil.copyfile(out / f"{NODE}_types.h", work / f"{NODE}_types.h")
    cs = contracts(model)
    wrapper = work / f"{NODE}_wp.c"
    wrapper.write_text(render_wrapper(model, f"{NODE}_glue.c", f"{NODE}_types.h", cs), encoding="ascii")
    frames = [contract_frame(c) for c in cs if function is None or c.name == function]
    assert frames, function
    return run_wp_file(wrapper, frames, timeout=timeout), cs


def test_wp_proves_every_function(direct, tmp_path):
    out, _ = direct
    res, cs = _wp(out, tmp_path)
    assert res.ok and res.proved == res.total
    assert [c.name for c in cs] == ["scan_callback", "pose_callback", "tscan_callback", "dscan_callback", "input_glue",
                                    "output_glue_out"]
    assert set(res.functions) == {c.name for c in cs}
    og = cs[-1]
    assert "command->header.stamp.sec == \\old(scan_msg.header.stamp.sec)" in og.ensures
    assert "command->header.stamp.nsec == \\old(scan_msg.header.stamp.nsec)" in og.ensures
    for c in cs:
        assert f"typed_{c.name}_ensures : Valid" in res.output, c.name
        assert f"typed_{c.name}_assigns" in res.output, c.name


@pytest.mark.parametrize("old,new,failing", [
    ("_t_float = (*msg).ranges.data[2];\n    D_U.Scan[2]", "_t_float = (*msg).ranges.data[3];\n    D_U.Scan[2]",
     "scan_callback_ensures"),
    ("_t_double = (*msg).pose.covariance[3];", "_t_double = (*msg).pose.covariance[4];", "pose_callback_ensures"),
    ("    D_U.N = _t_uint;\n", "    D_U.N = _t_uint;\n    D_U.Scan[0] = 0x0p+0f;\n", "input_glue_assigns"),
    ("    D_U.R1 = _t_float;\n", "    D_U.R1 = _t_float;\n    scan_msg.ranges.data[1] = _t_float;\n",
     "scan_callback_assigns"),
], ids=["callback-reads-another-index", "callback-reads-another-covariance", "input-glue-writes-a-direct-input",
        "callback-keeps-the-element-in-the-global"])
def test_wp_refuses_glues_that_break_the_rule(direct, tmp_path, old, new, failing):
    out, _ = direct
    with pytest.raises(WPError) as info:
        # only the function of the mutant (the glue unchanged is proved above)
        # (test_wp_proves_every_function proves the unchanged glue with the
        # same contracts; the broken goal would otherwise be tried for 5 s)
        _wp(out, tmp_path, old, new, function=failing.rsplit("_", 1)[0], timeout=2)
    msg = str(info.value)
    assert "goals proved, not all" in msg and failing in msg, msg


# --------------------------------------------------------------------------
# The differential test: the Coq interpreter against gcc on the printed C

@pytest.fixture(scope="module")
def sides(direct, tmp_path_factory):
    out, _ = direct
    return difftest_sides(out, NODE, tmp_path_factory.mktemp("direct_difftest"))


def _msg(dump, topic: str, struct: str, rnd: random.Random, lengths: dict[str, int], time: int = 0):
    """A message as sent on ``topic``: random leaves, each bounded field
    of ``lengths`` of that length (junk past it); with the values the
    node must see, converted (``Environment.clamp``), by leaf path."""
    leaves = dump.leaves(struct)
    vals = [rnd.getrandbits(lf.bits) for lf in leaves]
    seen = dict(zip((lf.path for lf in leaves), vals))
    for b in dump.bounded(struct):
        n = lengths.get(b.path, rnd.randint(0, 2 * b.capacity))
        vals[b.first_leaf] = n
        k = min(n, b.capacity)
        seen[f"{b.path}.len"] = k
        for i in range(b.capacity):
            if i >= n:
                vals[b.first_leaf + 2 + i] = 9   # junk past the length
            seen[f"{b.path}.data[{i}]"] = vals[b.first_leaf + 2 + i] if i < k else 0
    return Message(topic, tuple(leaf_token(lf, v) for lf, v in zip(leaves, vals)), time), seen


def _inputs(trace: str) -> list[dict[str, int]]:
    steps: list[dict[str, int]] = []
    for line in trace.splitlines():
        if line == "step":
            steps.append({})
        elif line.startswith("  u "):
            _, name, value = line.split()
            steps[-1][name] = int(value, 0)
    return steps


def test_difftest_the_newest_elements_reach_the_controller(sides):
    """Scans of lengths 0 to 2N, frame ids of 0 to 2FN bytes, bursts on a
    queue of 1 (only the newest is delivered) and cycles without a
    message (the direct inputs keep the newest message's elements)."""
    dump = sides["dump"]
    subs = {topic: struct for _, topic, struct, _ in dump.subs}
    rnd = random.Random(416)
    y = lambda: tuple(leaf_token(lf, rnd.getrandbits(lf.bits)) for lf in dump.leaves(dump.y[1]))  # noqa: E731
    zero = {f"Scan[{i}]": 0 for i in range(N)} | {"N": 0, "PX": 0, "R1": 0, "Cov3": 0, "F0": 0}
    cycles, wants = [((), y())], [dict(zero)]
    want = dict(zero)
    for length in (0, 1, N - 1, N, N + 1, 2 * N, 2, 3):
        msgs = []
        for burst in range(rnd.randint(1, 3)):
            scan, s = _msg(dump, "/scan", subs["/scan"], rnd,
                           {"ranges": length, "header.frame_id": rnd.choice([0, 1, FN, 2 * FN])})
            pose, p = _msg(dump, "/pose", subs["/pose"], rnd, {})
            msgs += [scan, pose]
        want = {**{f"Scan[{i}]": s[f"ranges.data[{i}]"] for i in range(N)}, "N": s["ranges.len"],
                "PX": p["pose.pose.position.x"], "R1": s["ranges.data[1]"], "Cov3": p["pose.covariance[3]"],
                "F0": s["header.frame_id.data[0]"]}
        cycles.append((tuple(msgs), y()))
        wants.append(want)
        cycles.append(((), y()))          # no message: the same inputs
        wants.append(want)
    sched = Schedule(tuple(cycles)).text()
    steps = _inputs(sides_agree(sides, sched))
    assert len(steps) == len(wants)
    for k, (got, want) in enumerate(zip(steps, wants)):
        assert {name: got[name] for name in want} == want, k


def test_difftest_random_schedules(sides):
    """Random schedules on every topic (also the timed ones): the two
    sides agree byte for byte."""
    dump = sides["dump"]
    subs = [(topic, struct) for _, topic, struct, _ in dump.subs]
    rnd = random.Random(16)
    for _ in range(5):
        cycles, times, now = [], [], 0
        for _ in range(rnd.randint(1, 8)):
            now += rnd.choice([0, 20, 99, 100, 101, 250]) * 1_000_000
            msgs = tuple(_msg(dump, topic, struct, rnd, {}, time=max(0, now - rnd.randint(0, 150) * 1_000_000))[0]
                         for topic, struct in (rnd.choice(subs) for _ in range(rnd.randint(0, 6))))
            cycles.append((msgs, tuple(leaf_token(lf, rnd.getrandbits(lf.bits)) for lf in dump.leaves(dump.y[1]))))
            times.append(now)
        sides_agree(sides, Schedule(tuple(cycles), tuple(times)).text())

"""Constant strings through the whole pipeline (rule 4.14):
``generate`` on examples/landshark/landshark_stamped.yaml (``frame_id:
base_link`` on its command) proves its theorems, prints ``struct
ros_string128`` and, at the end of the command's output glue, the stores
of the constant's length and bytes; the printed C compiles with ``-Wall
-Wextra -Werror``; the certificate quotes those lines; ``verify`` accepts
the folder and refuses a tampered certificate or glue; the seam refuses a
per-node file whose constant was changed or dropped, and Coq one that
puts a constant on a subscribed topic.  The certificate's reading of the
printed C is also tested on hand-made C (a byte, the length or the
zeroing wrong)."""

from __future__ import annotations

import re
import subprocess

import pytest

from pyrosgen import cli
from pyrosgen.proof.modeltext import parse_model_text
from pyrosgen.verify.certificate import CertificateError, _strings

from support.generate import REPO as ROOT, generate_with_tampered_node_file, require_library

STAMPED = ROOT / "examples" / "landshark" / "landshark_stamped.yaml"
NODE = "landshark_stamped"
OG = "output_glue_landshark_control_base_velocity"
BASE_LINK = b"base_link"
#: nm_strings as the emitter writes it for the example
NM_STRINGS = ('("landshark_control_base_velocity", ([PField "header"; PField "frame_id"], '
              '[98%Z; 97%Z; 115%Z; 101%Z; 95%Z; 108%Z; 105%Z; 110%Z; 107%Z]))')


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    require_library()
    out = tmp_path_factory.mktemp("strings") / "out"
    assert cli.main(["generate", str(STAMPED), "-o", str(out), "-q"]) == 0
    return out


def _output_glue(c: str) -> list[str]:
    body = c[c.index(f"void {OG}(struct geometry_msgs_TwistStamped *command)\n{{"):]
    return [ln.strip() for ln in body[:body.index("\n}\n")].splitlines()]


def _value(rhs: str) -> int:
    m = re.fullmatch(r"\(?(?:\((?:unsigned )?(?:char|int)\)\s*)?(\d+)[uU]?\)?;", rhs)
    assert m, rhs
    return int(m.group(1))


def test_types_header_has_the_string_struct(folder):
    h = (folder / f"{NODE}_types.h").read_text()
    m = re.search(r"struct ros_string128 \{\n(.*?)\n\};", h, re.S)
    assert m, h[:2000]
    assert [ln.strip() for ln in m.group(1).splitlines()] == [
        "unsigned int len;", "unsigned char truncated;", "unsigned char data[128];"]
    assert h.index("struct ros_string128 {") < h.index("struct std_msgs_Header {")
    header = re.search(r"struct std_msgs_Header \{\n(.*?)\n\};", h, re.S).group(1)
    assert "struct ros_string128 frame_id;" in header


def test_glue_stores_the_constant_after_the_stamp(folder):
    c = (folder / f"{NODE}_glue.c").read_text()
    lines = _output_glue(c)
    stamp = lines.index("(*command).header.stamp.nsec = _t_uint;")
    stores = lines[stamp + 1:]
    assert len(stores) == 1 + len(BASE_LINK), stores
    leaf, rhs = stores[0].split(" = ")
    assert leaf == "(*command).header.frame_id.len" and _value(rhs) == 9
    for i, (line, byte) in enumerate(zip(stores[1:], BASE_LINK)):
        leaf, rhs = line.split(" = ")
        assert leaf == f"(*command).header.frame_id.data[{i}]" and _value(rhs) == byte, line
    # zeroed first: truncated and every byte
    zeroing = lines[:stamp]
    for leaf in ["(*command).header.frame_id.len", "(*command).header.frame_id.truncated",
                 *(f"(*command).header.frame_id.data[{i}]" for i in range(128))]:
        (z,) = [ln for ln in zeroing if ln.startswith(leaf + " = ")]
        assert _value(z.split(" = ")[1]) == 0, z
    # a callback does not copy a received frame_id that the node does not read
    cb = c[c.index("void landshark_gps_velocity_callback(struct geometry_msgs_TwistStamped *msg)\n{"):]
    cb = cb[:cb.index("\n}\n")]
    assert "landshark_gps_velocity_msg.twist.linear.x = " in cb
    assert "frame_id" not in cb


def test_printed_c_compiles_with_warnings_as_errors(folder, tmp_path):
    r = subprocess.run(["gcc", "-std=c11", "-O2", "-Wall", "-Wextra", "-Werror", "-pedantic", "-c",
                        str(folder / f"{NODE}_glue.c"), "-I", str(folder), "-o", str(tmp_path / "glue.o")],
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr


def test_model_text_and_certificate(folder):
    proved = (folder / f"{NODE}.model").read_text()
    assert proved.splitlines()[-1] == ("string landshark_control_base_velocity header.frame_id "
                                       "98,97,115,101,95,108,105,110,107")
    cert = (folder / f"{NODE}.certificate.md").read_text()
    section = cert[cert.index("## Strings"):cert.index("## Trusted, not proved")]
    assert "### `/landshark_control/base_velocity header.frame_id` = `base_link` (9 bytes of 128)" in section
    assert "Bytes (UTF-8): `98,97,115,101,95,108,105,110,107`" in section
    glue = (folder / f"{NODE}_glue.c").read_text().splitlines()
    quoted = re.findall(rf"^/\* {NODE}_glue\.c:(\d+) \*/ (.*)$", section, re.M)
    assert len(quoted) == 10
    for n, text in quoted:
        assert glue[int(n) - 1].strip() == text
    assert quoted[0][1].startswith("(*command).header.frame_id.len = ")
    # the verdict and the wrapper's row say it
    assert 'in each string field of section\n  "Strings" its constant' in cert
    assert "converts every carried string (`ros_string128`)" in cert


def test_verify_accepts_the_folder(folder, capsys):
    assert cli.main(["verify", str(folder), "--model", str(STAMPED)]) == 0, capsys.readouterr().err
    out = capsys.readouterr()
    assert "ok      certificate" in out.out + out.err


def _copy(folder, tmp_path):
    import shutil

    dst = tmp_path / "copy"
    shutil.copytree(folder, dst)
    return dst


def test_verify_refuses_a_tampered_certificate(folder, tmp_path, capsys):
    copy = _copy(folder, tmp_path)
    cert = copy / f"{NODE}.certificate.md"
    text = cert.read_text()
    cert.write_text(text.replace("= `base_link` (9 bytes of 128)", "= `base_lynx` (9 bytes of 128)", 1))
    assert cli.main(["verify", str(copy)]) == 1
    out = capsys.readouterr()
    text = out.out + out.err
    assert "FAILED  certificate" in text and "base_lynx" in text, text


def test_verify_refuses_a_tampered_glue(folder, tmp_path, capsys):
    copy = _copy(folder, tmp_path)
    glue = copy / f"{NODE}_glue.c"
    text = glue.read_text()
    (line,) = [ln for ln in text.splitlines() if ln.strip().startswith("(*command).header.frame_id.data[0] = ")
               and _value(ln.strip().split(" = ")[1]) == 98]
    glue.write_text(text.replace(line, line.replace("98", "99"), 1))
    assert cli.main(["verify", str(copy)]) == 1
    out = capsys.readouterr()
    text = out.out + out.err
    assert "FAILED  hashes" in text and "FAILED  re-print" in text, text


@pytest.mark.parametrize("name, new, code, says", [
    ("constant dropped", "", 2, "is not the model of the YAML file"),
    ("another constant", NM_STRINGS.replace("98%Z; 97%Z", "98%Z; 98%Z"), 2, "is not the model of the YAML file"),
    ("a subscribed topic", NM_STRINGS.replace("landshark_control_base_velocity", "landshark_gps_velocity"), 1,
     "rule 4.14"),
])
def test_tampered_per_node_file_is_refused(name, new, code, says, monkeypatch, capsys, tmp_path):
    """A per-node file whose constant was dropped or changed still proves
    its theorems, about another node: the seam refuses it; a constant on a
    subscribed topic is refused by Coq (``Wellformed.string_ok``)."""
    require_library()
    out = tmp_path / "out"
    got, err = generate_with_tampered_node_file(STAMPED, NM_STRINGS, new, monkeypatch, capsys, out)
    assert not out.exists()
    assert got == code, err
    assert says in err, err
    if code == 2:
        assert "string landshark_control_base_velocity" in err, err


# --------------------------------------------------------------------------
# The certificate's reading of the printed C, on hand-made C

MODEL_TEXT = """\
pyrosgen-model 1
node n
period_ms 20
controller C
inputs U ExtU_C_T
input In1 float64
outputs Y ExtY_C_T
output Out1 float64
message ros_string128
field len uint32
field truncated bool
field data array 128 uint8
message std_msgs_Header
field seq uint32
field frame_id msg ros_string128
message pkg_T
field header msg std_msgs_Header
field x float64
topic /out out publish pkg/T 1
output_relation Out1 out x
string out header.frame_id 97,98
"""


def _c(stores: dict[str, str], extra: list[str] = ()) -> str:
    """An output glue zeroing the string, copying x, then ``stores``."""
    body = ["(*command).header.seq = 0U;", "(*command).header.frame_id.len = 0U;",
            "(*command).header.frame_id.truncated = 0;"]
    body += [f"(*command).header.frame_id.data[{i}] = 0;" for i in range(128)]
    body += ["(*command).x = 0.0;", "_t_double = Y.Out1;", "(*command).x = _t_double;"]
    body += [f"{k} = {v};" for k, v in stores.items()] + list(extra)
    return "void output_glue_out(struct pkg_T *command)\n{\n" + "".join(f"    {b}\n" for b in body) + "}\n"


GOOD = {"(*command).header.frame_id.len": "2U", "(*command).header.frame_id.data[0]": "97",
        "(*command).header.frame_id.data[1]": "98"}


def test_certificate_reads_the_stores():
    (row,) = _strings(parse_model_text(MODEL_TEXT), _c(GOOD))
    assert (row["length"], row["capacity"], row["text"], row["bytes"]) == (2, 128, "ab", "97,98")
    assert [t for _, t in row["lines"]] == [f"{k} = {v};" for k, v in GOOD.items()]
    assert row["zeroed"] == (5, 133)  # truncated, then data[2..127]
    # casts and parentheses are read too
    assert _strings(parse_model_text(MODEL_TEXT),
                    _c({**GOOD, "(*command).header.frame_id.data[0]": "((unsigned char)97)"}))


@pytest.mark.parametrize("stores, extra, says", [
    ({**GOOD, "(*command).header.frame_id.data[1]": "99"}, [], "data[1]: ends as 99"),
    ({**GOOD, "(*command).header.frame_id.len": "3U"}, [], ".len: ends as 3"),
    ({k: v for k, v in GOOD.items() if "data[1]" not in k}, [], "data[1]: ends as 0"),
    (GOOD, ["(*command).header.frame_id.truncated = 1;"], ".truncated: ends as 1"),
    (GOOD, ["(*command).header.frame_id.data[100] = 7;"], "data[100]: ends as 7"),
    (GOOD, ["(*command).header.frame_id.data[0] = _t_uchar;"], "not a constant"),
])
def test_certificate_refuses_c_that_is_not_the_constant(stores, extra, says):
    with pytest.raises(CertificateError) as info:
        _strings(parse_model_text(MODEL_TEXT), _c(stores, extra))
    assert says in str(info.value), str(info.value)


# --------------------------------------------------------------------------
# Several constants, nested in a fixed-size array, empty, multi-byte

NESTED = ROOT / "tests" / "generate" / "models" / "ok_strings.yaml"


def test_nested_constants_generate_and_verify(tmp_path, capsys):
    """tests/generate/models/ok_strings.yaml: five constants on two
    topics (one empty, one with a two-byte character, one in
    ``legs[1]``, one in ``legs[0].header``) are proved, printed in model
    order, quoted by the certificate, and the folder verifies."""
    require_library()
    out = tmp_path / "out"
    assert cli.main(["generate", str(NESTED), "-o", str(out), "-q"]) == 0, capsys.readouterr().err
    capsys.readouterr()
    proved = (out / "strings_node.model").read_text().splitlines()
    assert [ln for ln in proved if ln.startswith("string ")] == [
        "string odom header.frame_id 111,100,111,109",
        "string odom child_frame_id -",
        "string convoy_out legs[1].label 195,169,50",
        "string convoy_out header.frame_id 109,97,112",
        "string convoy_out legs[0].header.frame_id 97,32,98,47,99",
    ]
    c = (out / "strings_node_glue.c").read_text()
    og = c[c.index("void output_glue_convoy_out(struct fleet_msgs_Convoy *command)\n{"):]
    og = [ln.strip() for ln in og[:og.index("\n}\n")].splitlines()]
    copy = og.index("(*command).legs[1].speed = _t_double;")
    assert [ln.split(" = ")[0] for ln in og[copy + 1:]] == [
        "(*command).legs[1].label.len", *(f"(*command).legs[1].label.data[{i}]" for i in range(3)),
        "(*command).header.frame_id.len", *(f"(*command).header.frame_id.data[{i}]" for i in range(3)),
        "(*command).legs[0].header.frame_id.len", *(f"(*command).legs[0].header.frame_id.data[{i}]" for i in range(5)),
    ]
    # the empty constant: its length only
    odom = c[c.index("void output_glue_odom(struct nav_msgs_Odometry *command)\n{"):]
    odom = [ln.strip() for ln in odom[:odom.index("\n}\n")].splitlines()]
    assert [ln for ln in odom if ln.startswith("(*command).child_frame_id.len = ")][-1] == \
        "(*command).child_frame_id.len = 0U;"
    cert = (out / "strings_node.certificate.md").read_text()
    section = cert[cert.index("## Strings"):cert.index("## Trusted, not proved")]
    assert section.count("\n### ") == 5
    assert "### `/odom child_frame_id` = `\"\"` (0 bytes of 128)" in section
    assert '### `/convoy_out legs[1].label` = `"\\u00e92"` (3 bytes of 128)' in section
    assert cli.main(["verify", str(out), "--model", str(NESTED)]) == 0, capsys.readouterr().err
    assert subprocess.run(["gcc", "-std=c11", "-Wall", "-Wextra", "-Werror", "-pedantic", "-c",
                           str(out / "strings_node_glue.c"), "-I", str(out), "-o", str(tmp_path / "g.o")],
                          capture_output=True, timeout=300).returncode == 0


# --------------------------------------------------------------------------
# Coq refuses what the front end refuses, when the front end is bypassed

PREAMBLE = """\
From Coq Require Import String List ZArith.
From ROSGen Require Import Errors Syntax Values FloatBits NodeModel Generator.
Import ListNotations.
Local Open Scope string_scope.
Local Open Scope list_scope.

Definition verdict (m : node_model) : string :=
  match generate m with OK _ => "OK" | Error msg => string_of_errmsg msg end.
"""


def _mutants():
    from dataclasses import replace

    from pyrosgen.frontend.model import StringConstant
    from pyrosgen.frontend.validate import load_model

    m = load_model(STAMPED)
    cmd = m.topic("/landshark_control/base_velocity")
    gps = m.topic("/landshark/gps_velocity")

    def with_topics(**changes):
        topics = tuple(replace(t, **changes[t.name]) if t.name in changes else t for t in m.topics)
        return replace(m, topics=topics)

    const = cmd.strings[0]
    return {
        "on a subscribed topic": with_topics(**{gps.name: {"strings": (const,)},
                                                cmd.name: {"strings": ()}}),
        "longer than the capacity": with_topics(**{cmd.name: {"strings": (StringConstant(const.path, "a" * 129),)}}),
        "not a string field": with_topics(**{cmd.name: {"strings": (StringConstant(("twist", "linear"), "a"),)}}),
        "inside the string": with_topics(**{cmd.name: {"strings": (StringConstant(("header", "frame_id", "data"),
                                                                                  "a"),)}}),
        "named twice": with_topics(**{cmd.name: {"strings": (const, StringConstant(const.path, "b"))}}),
    }


def test_coq_refuses_bad_constants(tmp_path):
    """Models past the front end's checks (``dataclasses.replace``),
    emitted as Coq terms: ``generate`` refuses each with an error that
    cites rule 4.14 (``Wellformed.string_ok``)."""
    from pyrosgen.proof.coqdriver import CoqDriver
    from pyrosgen.proof.coqmodel import render_model_definitions

    from support.generate import printed_strings, run

    require_library()
    mutants = _mutants()
    defs = [(f"m{i}", mm) for i, mm in enumerate(mutants.values())]
    text = [PREAMBLE, render_model_definitions(defs)] + [f"Eval vm_compute in verdict {n}." for n, _ in defs]
    v = tmp_path / "Strings.v"
    v.write_text("\n".join(text) + "\n")
    # the library pyrosgen generates with (PYROSGEN_COQLIB, else coq/theories)
    out = run(["coqc", "-R", str(CoqDriver().theories), "ROSGen", "-R", str(tmp_path), "T", v.name], cwd=tmp_path)
    verdicts = printed_strings(out.stdout)
    assert len(verdicts) == len(mutants)
    for name, verdict in zip(mutants, verdicts):
        assert verdict != "OK" and ("4.14" in verdict or "constant string" in verdict), (name, verdict)

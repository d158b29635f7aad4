"""The certificate is rendered from proved data (the model Coq printed and
the C Coq printed), never from the front end's model; user strings in it
are escaped; the manifest and the digest file agree with the folder."""

from __future__ import annotations

import hashlib
import json
import re
import shutil
import subprocess
from dataclasses import replace
from pathlib import Path

import pytest

from pyrosgen.errors import DetailedFailure
from pyrosgen.generate import generate
from pyrosgen.render import source_label
from pyrosgen.verify.certificate import md_code, read_manifest, write_certificate

from support.generate import LANDSHARK, require_library

NODE = "landshark_controller"


@pytest.fixture(scope="module")
def landshark(tmp_path_factory):
    require_library()
    d = tmp_path_factory.mktemp("cert") / "out"
    res = generate(LANDSHARK, d)
    return res, d


def _copy(d: Path, tmp_path: Path) -> Path:
    c = tmp_path / "copy"
    shutil.copytree(d, c)
    return c


def test_certificate_follows_the_proved_model_text(landshark, tmp_path):
    """Rendered again from a folder whose proved model text says another
    period and another queue size, the certificate says what that text says
    (so it is drawn from it, not from the YAML's model)."""
    res, d = landshark
    c = _copy(d, tmp_path)
    model = c / f"{NODE}.model"
    text = model.read_text()
    assert "period_ms 20\n" in text and " geometry_msgs/TwistStamped 1\n" in text
    model.write_text(text.replace("period_ms 20\n", "period_ms 35\n")
                     .replace("/landshark/gps_velocity landshark_gps_velocity subscribe geometry_msgs/TwistStamped 1",
                              "/landshark/gps_velocity landshark_gps_velocity subscribe geometry_msgs/TwistStamped 7"))
    write_certificate(res.record, c, res.covered)
    cert = (c / f"{NODE}.certificate.md").read_text()
    assert "| period | 35 ms |" in cert and "sleep of 35 ms" in cert
    assert "(`geometry_msgs/TwistStamped`, queue 7)" in cert
    original = (d / f"{NODE}.certificate.md").read_text()
    assert "| period | 20 ms |" in original and "queue 7" not in original


def test_certificate_refuses_a_relation_the_c_does_not_implement(landshark, tmp_path):
    """A proved model text whose relation the printed C does not copy
    (two inputs swapped) cannot be certified: the C lines are looked up
    from the C, and the lookup fails instead of citing a wrong line."""
    res, d = landshark
    c = _copy(d, tmp_path)
    model = c / f"{NODE}.model"
    text = model.read_text()
    swapped = (text.replace("landshark_left_wheel_velocity twist.linear.x In1", "@L")
               .replace("landshark_right_wheel_velocity twist.linear.x In2",
                        "landshark_right_wheel_velocity twist.linear.x In1")
               .replace("@L", "landshark_left_wheel_velocity twist.linear.x In2"))
    assert swapped != text
    model.write_text(swapped)
    # the C copies In1 from the left wheel: the certificate's lookup of the
    # right wheel's copy into In1 finds the left wheel's line, and the
    # test of test_generate.py checks the quoted line; here the quoted
    # line must name the left wheel's global, exposing the swap
    write_certificate(res.record, c, res.covered)
    cert = (c / f"{NODE}.certificate.md").read_text()
    block = cert.split("### `/landshark/right_wheel_velocity twist.linear.x` → `Controller_U.In1`", 1)[1]
    block = block.split("###", 1)[0]
    assert "landshark_left_wheel_velocity_msg.twist.linear.x" in block
    # a relation whose copy is not in the C at all is refused
    model.write_text(text.replace("input_relation landshark_gps_velocity twist.linear.x In3",
                                  "input_relation landshark_gps_velocity twist.linear.x In9"))
    with pytest.raises(DetailedFailure, match="no copy into Controller_U.In9"):
        write_certificate(res.record, c, res.covered)


def test_manifest_and_digest_file(landshark):
    res, d = landshark
    rec, files = read_manifest(d / f"{NODE}.manifest.json")
    assert rec == res.record
    assert set(files) == {f"{NODE}.v", f"{NODE}_types.h", f"{NODE}_glue.c", f"{NODE}.sexp", f"{NODE}.model"}
    for name, digest in files.items():
        assert hashlib.sha256((d / name).read_bytes()).hexdigest() == digest
    assert len(rec.library_sha256) == 64 and rec.library_sha256 in (d / f"{NODE}.certificate.md").read_text()
    # runs as written in the folder
    ok = subprocess.run(["sha256sum", "-c", f"{NODE}.sha256"], cwd=d, capture_output=True, text=True)
    assert ok.returncode == 0, ok.stdout + ok.stderr
    assert ok.stdout.count(": OK") == len(files)


def test_manifest_rejects_other_json(tmp_path):
    p = tmp_path / "x.manifest.json"
    p.write_text(json.dumps({"format": 99}))
    with pytest.raises(ValueError, match="not a pyrosgen manifest"):
        read_manifest(p)


@pytest.mark.parametrize("name", [
    "a\nb.yaml", "x`$(touch pwned)`.yaml", "a|b.yaml", "évil.yaml", "<script>.yaml", "a\u202eb.yaml",
])
def test_user_strings_are_escaped(landshark, tmp_path, name):
    """A model file name with a newline, a backtick, a bar or non-ASCII
    text stays inside its code span, on one line."""
    res, d = landshark
    shown = md_code(name)
    assert "\n" not in shown and shown.count("`") == 2 and "|" not in shown
    assert shown.isascii()
    c = _copy(d, tmp_path)
    write_certificate(replace(res.record, source_name=name), c, res.covered)
    cert = (c / f"{NODE}.certificate.md").read_text()
    label = md_code(source_label(name))  # as in every generated file's header comment
    assert label.isascii() and "\n" not in label and label.count("`") == 2 and "|" not in label
    assert label in cert and name not in cert


def test_recheck_commands_run_as_written(landshark, tmp_path):
    """The certificate's step-by-step commands, run as written by a shell in
    (a copy of) the output folder, with pyrosgen on the PATH: every one
    succeeds, and coqc prints one closed theorem per checked theorem."""
    import os
    import sys

    res, d = landshark
    c = _copy(d, tmp_path)
    cert = (c / f"{NODE}.certificate.md").read_text()
    block = cert.split("Step by step, by hand", 1)[1].split("```sh\n", 1)[1].split("```", 1)[0]
    commands = [ln for ln in block.splitlines() if ln.strip() and not ln.startswith("#")]
    assert any(ln.startswith("coqc ") for ln in commands) and any(ln.startswith("coqchk ") for ln in commands)
    env = dict(os.environ, PATH=f"{Path(sys.executable).parent}:{os.environ['PATH']}")
    r = subprocess.run(["bash", "-e", "-c", "\n".join(commands)], cwd=c, env=env, capture_output=True, text=True,
                       timeout=600)
    assert r.returncode == 0, r.stdout[-2000:] + r.stderr[-2000:]
    assert r.stdout.count("Closed under the global context") == 1  # the conjunction of res.theorems
    assert r.stdout.count(": OK") == len(res.covered)


def _first_cells(table_text: str, header: str) -> list[str]:
    """The first cells of the Markdown table that starts with ``header``,
    normalised: Jinja tags, parenthesised remarks and backticks removed,
    lower case, one space between words."""
    rows = table_text.split(header, 1)[1].split("\n")[2:]
    out = []
    for row in rows:
        if not row.startswith("| "):
            break
        cell = row[2:].split(" | ", 1)[0]
        cell = re.sub(r"\{[%{].*?[%}]\}", "", cell)
        while re.search(r"\([^()]*\)", cell):
            cell = re.sub(r"\([^()]*\)", "", cell)
        out.append(" ".join(cell.replace("`", "").lower().split()))
    return out


def test_trusted_table_matches_the_design_trust_base(landshark):
    """Every row of DESIGN.md section 7's trust base has its row in the
    certificate's "Trusted, not proved" table, and the certificate trusts
    nothing that section does not list (rows matched by their first cell,
    normalised); a rendered certificate holds every row."""
    root = Path(__file__).resolve().parents[2]
    design = (root / "DESIGN.md").read_text(encoding="utf-8")
    section = design.split("\n## 7. The trust base\n", 1)[1].split("\n## 8.", 1)[0]
    want = _first_cells(section, "| trusted part | how it is checked |")
    assert len(want) >= 15 and len(set(want)) == len(want)
    template = (root / "pyrosgen" / "templates" / "CERTIFICATE.md.j2").read_text(encoding="utf-8")
    header = "| trusted part | what is assumed | how it is checked |"
    got = _first_cells(template, header)
    assert [w for w in want if w not in got] == [], "DESIGN.md section 7 rows missing from the certificate"
    assert [g for g in got if g not in want] == [], "certificate rows that DESIGN.md section 7 does not list"
    _, d = landshark
    cert = (d / f"{NODE}.certificate.md").read_text()
    assert sorted(_first_cells(cert, header)) == sorted(want)


def test_first_screen_says_proved_assumed_not_covered(landshark):
    """The certificate opens, before the verdict and within one screen,
    with what is proved, what is assumed and what is not covered: the
    controller's logic, timing, the transport, the controller's flags and
    the operating system."""
    _, d = landshark
    cert = (d / f"{NODE}.certificate.md").read_text()
    assert cert.index("## In one screen") < cert.index("## Verdict")
    screen = cert.split("## In one screen\n", 1)[1].split("\n## ", 1)[0]
    assert len(screen.strip().splitlines()) <= 40
    flat = " ".join(screen.split())
    assert "**Proved**" in flat and f"`{NODE}_ddc` (T2)" in flat and "sleep of 20 ms" in flat
    assert "the 3 input relations" in flat and "the 1 output relation" in flat
    assert "**Assumed**" in flat and "**Not covered**" in flat
    for item in ("- the controller's logic: `Controller_step` is hand-written", "- timing:", "- the transport:",
                 "- the compile flags of the hand-written controller", "- the operating system"):
        assert item in flat, item

"""``build`` is reproducible (the same folder built twice gives the same
``bin/<node>`` bit for bit) and ``verify --rebuild`` compiles the binary
again from the folder's files with the recorded commands and compares it."""

from __future__ import annotations

import hashlib
import json
import shutil

from .conftest import LANDSHARK, LANDSHARK_CTL, MULTI, MULTI_CTL, pyrosgen

NODE = "landshark_controller"
BIN = f"bin/{NODE}"


def _rewrite_digests(d, name: str) -> None:
    """The digest of ``d/name`` rewritten in the manifest, the digest file
    and the certificate (only the checks that read the file can refuse it)."""
    m = d / f"{NODE}.manifest.json"
    data = json.loads(m.read_text())
    old = data["files"][name]
    data["files"][name] = new = hashlib.sha256((d / name).read_bytes()).hexdigest()
    m.write_text(json.dumps(data))
    (d / f"{NODE}.sha256").write_text("".join(f"{v}  {n}\n" for n, v in sorted(data["files"].items())))
    cert = d / f"{NODE}.certificate.md"
    assert old in cert.read_text()
    cert.write_text(cert.read_text().replace(old, new))


def test_two_builds_give_the_same_binary(landshark_build, tmp_path):
    """Another output folder, the controller folder copied elsewhere: the
    same bytes (no temporary or controller path, no time stamp in it)."""
    _, out = landshark_build
    ctl = tmp_path / "elsewhere" / "ctl"
    shutil.copytree(LANDSHARK_CTL, ctl)
    run = pyrosgen("build", LANDSHARK, "--controller", ctl, "-o", tmp_path / "again", "-q")
    assert run.returncode == 0, run.stderr
    a, b = (out / BIN).read_bytes(), (tmp_path / "again" / BIN).read_bytes()
    assert a == b, next(i for i in range(min(len(a), len(b))) if a[i] != b[i])
    assert str(tmp_path).encode() not in b and b".pyrosgen-build" not in b
    cmds = json.loads((out / f"{NODE}.manifest.json").read_text())["build"]["commands"]
    glue = next(c for c in cmds if f"{NODE}_glue.c" in c and "-o" in c)
    assert glue[-1] == "-ffile-prefix-map=.=." and not any(w.endswith("=controller") for w in glue)
    controller = next(c for c in cmds if "controller/Controller.c" in c and "-o" in c)
    assert controller[-2:] == ["-ffile-prefix-map=.=.", "-ffile-prefix-map=controller=controller"]


def test_verify_rebuild_of_a_build_folder(landshark_build):
    _, out = landshark_build
    run = pyrosgen("verify", out, "--rebuild", "-q")
    assert run.returncode == 0, run.stdout + run.stderr
    assert (f"  ok      rebuild   {BIN} rebuilt from the folder's files with the 4 recorded commands: "
            "the same, bit for bit") in run.stdout


def test_verify_rebuild_with_custom_messages(tmp_path):
    """The wrapper of a node with a message package of its own includes the
    gencpp headers of ``include/``: rebuilt from the folder's copies."""
    out = tmp_path / "multi"
    run = pyrosgen("build", MULTI, "--controller", MULTI_CTL, "-o", out, "-q")
    assert run.returncode == 0, run.stderr
    wrapper = next(c for c in json.loads((out / "multi_node.manifest.json").read_text())["build"]["commands"]
                   if "multi_node_ros.cpp" in c)
    assert wrapper[wrapper.index("include") - 1] == "-I"
    run = pyrosgen("verify", out, "--rebuild", "-q")
    assert run.returncode == 0, run.stdout + run.stderr
    assert "  ok      rebuild   bin/multi_node rebuilt from the folder's files" in run.stdout


def test_a_patched_binary_is_refused(landshark_build, tmp_path):
    """One byte of the binary changed, its digests rewritten: only the
    rebuild refuses it, naming the binary."""
    _, out = landshark_build
    c = tmp_path / "c"
    shutil.copytree(out, c, symlinks=True)
    data = bytearray((c / BIN).read_bytes())
    data[len(data) // 2] ^= 0x01
    (c / BIN).write_bytes(bytes(data))
    _rewrite_digests(c, BIN)
    run = pyrosgen("verify", c, "-q")
    assert run.returncode == 0, run.stdout   # without --rebuild, the digests vouch for it
    run = pyrosgen("verify", c, "--rebuild", "-q")
    assert run.returncode == 1, run.stdout + run.stderr
    assert f"  FAILED  rebuild   {BIN} is not the binary its recorded commands build from the folder's files" \
        in run.stdout, run.stdout
    assert f"first difference at byte {len(data) // 2}" in run.stdout
    assert "1 of 9 checks failed: rebuild" in run.stderr, run.stderr


def test_a_recorded_command_verify_does_not_run_is_refused(landshark_build, tmp_path):
    """``-wrapper PROG`` in a recorded command would run PROG: refused
    before any command runs, the program not run."""
    _, out = landshark_build
    c = tmp_path / "c"
    shutil.copytree(out, c, symlinks=True)
    mark = tmp_path / "ran"
    prog = tmp_path / "prog.sh"
    prog.write_text(f"#!/bin/sh\ntouch {mark}\nexec \"$@\"\n")
    prog.chmod(0o755)
    m = c / f"{NODE}.manifest.json"
    data = json.loads(m.read_text())
    cmds = data["build"]["commands"]
    glue = next(k for k, cmd in enumerate(cmds) if f"{NODE}_glue.c" in cmd and "-o" in cmd)
    cmds[glue] += ["-wrapper", str(prog)]
    m.write_text(json.dumps(data))
    run = pyrosgen("verify", c, "--rebuild", "-q")
    assert run.returncode == 1, run.stdout + run.stderr
    assert f"  FAILED  rebuild   not run: build.commands[{glue}] has '-wrapper', which verify does not run" \
        in run.stdout, run.stdout
    assert not mark.exists()

"""``pyrosgen generate`` on the command line: exit codes (DESIGN.md section
8), nothing written on failure, idempotence, progress and summary."""

from __future__ import annotations

import os
import shutil
import stat
import subprocess
import sys
from pathlib import Path

import pytest

from pyrosgen import cli
from pyrosgen.proof.coqdriver import CLOSED, DEFAULT_THEORIES

from support.generate import LANDSHARK, MULTI, ddc_in_coqproject, require_library

NODE = "landshark_controller"
OUTPUTS = [f"{NODE}.v", f"{NODE}_types.h", f"{NODE}_glue.c", f"{NODE}.sexp", f"{NODE}.model",
           f"{NODE}.certificate.md", f"{NODE}.manifest.json", f"{NODE}.sha256"]


def run(capsys, *argv):
    code = cli.main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def _snapshot(d: Path) -> dict[str, tuple[int, bytes]]:
    return {p.name: (p.stat().st_mtime_ns, p.read_bytes()) for p in sorted(d.iterdir())}


def _no_work_dirs(parent: Path) -> bool:
    return not list(parent.glob(".pyrosgen-*"))


@pytest.fixture
def outdir(tmp_path):
    """An existing output folder holding a file of the user's."""
    d = tmp_path / "out"
    d.mkdir()
    (d / "keep.txt").write_text("mine\n")
    return d


def test_generate_then_idempotent(capsys, tmp_path, outdir):
    require_library()
    code, out, err = run(capsys, "generate", LANDSHARK, "-o", outdir)
    assert code == 0, err
    thm = f"{NODE}_ddc" if ddc_in_coqproject() else f"{NODE}_wf"
    # summary: files, theorem, closedness, times per phase
    for name in OUTPUTS:
        assert f"  written   {outdir / name}\n" in out
    assert f"  theorem   {thm}: " in out
    assert CLOSED in out
    for phase in ("front end", "coqc", "checking", "printing", "total"):
        assert phase in out.split("  time      ")[1]
    if not ddc_in_coqproject():
        assert "fallback" in out
    # progress on stderr, five steps
    assert [ln.split()[1] for ln in err.splitlines() if ln.startswith("pyrosgen: [")] == [
        "[1/5]", "[2/5]", "[3/5]", "[4/5]", "[5/5]"]
    assert f"pyrosgen: [2/5] coqc: generating the glue and proving {thm} ..." in err
    assert sorted(p.name for p in outdir.iterdir()) == sorted(OUTPUTS + ["keep.txt"])
    assert (outdir / "keep.txt").read_text() == "mine\n"
    assert _no_work_dirs(tmp_path)

    # second run: nothing rewritten, mtimes unchanged; --quiet: no progress
    before = _snapshot(outdir)
    code, out, err = run(capsys, "generate", LANDSHARK, "-o", outdir, "--quiet")
    assert code == 0, err
    assert err == ""
    for name in OUTPUTS:
        assert f"  unchanged {outdir / name}\n" in out
    assert _snapshot(outdir) == before

    # a file changed by hand is rewritten, and only that one
    glue = outdir / f"{NODE}_glue.c"
    glue.write_text("/* edited */\n")
    edited = _snapshot(outdir)
    code, out, err = run(capsys, "generate", LANDSHARK, "-o", outdir, "-q")
    assert code == 0, err
    assert f"  written   {glue}\n" in out and out.count("  unchanged ") == len(OUTPUTS) - 1
    after = _snapshot(outdir)
    assert after[glue.name][1] == before[glue.name][1]
    assert {k: v for k, v in after.items() if k != glue.name} == {
        k: v for k, v in edited.items() if k != glue.name}


def test_invalid_model_exit_1_nothing_written(capsys, tmp_path, outdir):
    bad = tmp_path / "bad.yaml"
    bad.write_text(LANDSHARK.read_text().replace("period_ms: 20", "period_ms: 0"))
    before = _snapshot(outdir)
    code, out, err = run(capsys, "generate", bad, "-o", outdir)
    assert code == 1
    assert out == ""
    assert f"{bad}:6:" in err and "error: node.period_ms" in err
    assert _snapshot(outdir) == before
    # a folder that does not exist is not created
    code, _, _ = run(capsys, "generate", bad, "-o", tmp_path / "new")
    assert code == 1 and not (tmp_path / "new").exists()
    assert _no_work_dirs(tmp_path)


def test_output_is_a_file_exit_1(capsys, tmp_path):
    f = tmp_path / "file"
    f.write_text("x")
    code, out, err = run(capsys, "generate", LANDSHARK, "-o", f)
    assert code == 1 and "exists and is not a directory" in err
    assert f.read_text() == "x"


def test_coq_refusal_exit_1_nothing_written(capsys, tmp_path, outdir, monkeypatch):
    """A model that Coq's generate refuses after the front end let it
    through is a user error: exit 1, Coq's message, nothing written.  The
    front end now refuses every model Coq refuses, so the front end is
    bypassed here: it returns LandShark renamed to the Coq keyword 'mod'."""
    require_library()
    import dataclasses

    import pyrosgen.generate as gen
    from pyrosgen.errors import InvalidNodeModel
    from pyrosgen.frontend.validate import load_model

    m = tmp_path / "mod.yaml"
    m.write_text(LANDSHARK.read_text().replace("name: landshark_controller", "name: mod"))
    with pytest.raises(InvalidNodeModel):
        load_model(m)  # the front end refuses it on its own
    bypass = dataclasses.replace(load_model(LANDSHARK), name="mod", source=m)
    monkeypatch.setattr(gen, "load_model", lambda _path: bypass)
    before = _snapshot(outdir)
    code, out, err = run(capsys, "generate", m, "-o", outdir, "-q")
    assert code == 1
    assert f"{m}: error: Coq's generate refused the model: Generator: the node name is a Coq keyword: 'mod'" in err
    assert _snapshot(outdir) == before
    assert _no_work_dirs(tmp_path)


def _fake_tool(d: Path, name: str, script: str) -> None:
    p = d / name
    p.write_text("#!/bin/sh\n" + script)
    p.chmod(p.stat().st_mode | stat.S_IXUSR | stat.S_IXGRP | stat.S_IXOTH)


def test_coqc_failure_exit_2_located_messages(capsys, tmp_path, outdir, monkeypatch):
    """A coqc that fails: exit 2, its messages as file:line:col, nothing
    written, no work directory left."""
    require_library()
    fake = tmp_path / "bin"
    fake.mkdir()
    _fake_tool(fake, "coqc", (
        'echo "File \\"./landshark_controller.v\\", line 12, characters 4-9:" >&2\n'
        'echo "Error: The reference boom was not found" >&2\n'
        'echo "in the current environment." >&2\n'
        "exit 1\n"))
    monkeypatch.setenv("PATH", f"{fake}{os.pathsep}{os.environ['PATH']}")
    before = _snapshot(outdir)
    code, out, err = run(capsys, "generate", LANDSHARK, "-o", outdir, "-q")
    assert code == 2
    assert out == ""
    lines = err.splitlines()
    assert lines[0].startswith("pyrosgen: error: coqc failed on landshark_controller.v")
    assert lines[0].endswith(f"nothing written to {outdir}")
    assert lines[1] == (
        "landshark_controller.v (generated; not written, see --keep-work):12:5: "
        "error: The reference boom was not found in the current environment.")
    assert _snapshot(outdir) == before
    assert _no_work_dirs(tmp_path)


def test_coqc_missing_exit_2(capsys, tmp_path, outdir, monkeypatch):
    empty = tmp_path / "empty"
    empty.mkdir()
    monkeypatch.setenv("PATH", str(empty))
    code, out, err = run(capsys, "generate", LANDSHARK, "-o", outdir)
    assert code == 2
    assert "pyrosgen: error: coqc not found: run make deps" in err
    assert (outdir / "keep.txt").exists() and len(list(outdir.iterdir())) == 1


def test_library_not_built_exit_2(capsys, tmp_path, outdir, monkeypatch):
    empty = tmp_path / "nolib"
    empty.mkdir()
    monkeypatch.setenv("PYROSGEN_COQLIB", str(empty))
    code, out, err = run(capsys, "generate", LANDSHARK, "-o", outdir)
    assert code == 2
    assert "the Coq library is not built: run make proofs" in err
    assert len(list(outdir.iterdir())) == 1


def test_library_stale_exit_2(capsys, tmp_path, outdir, monkeypatch):
    """A library whose NodeModel.v is newer than its NodeModel.vo."""
    lib = tmp_path / "lib" / "theories"
    lib.mkdir(parents=True)
    shutil.copy(DEFAULT_THEORIES.parent / "_CoqProject", lib.parent / "_CoqProject")
    for p in DEFAULT_THEORIES.rglob("*"):
        if p.suffix in (".v", ".vo"):
            (lib / p.relative_to(DEFAULT_THEORIES)).parent.mkdir(parents=True, exist_ok=True)
            os.symlink(p, lib / p.relative_to(DEFAULT_THEORIES))
    (lib / "glue" / "NodeModel.v").unlink()
    shutil.copy(DEFAULT_THEORIES / "glue" / "NodeModel.v", lib / "glue" / "NodeModel.v")
    later = (DEFAULT_THEORIES / "glue" / "NodeModel.vo").stat().st_mtime + 10
    os.utime(lib / "glue" / "NodeModel.v", (later, later))
    monkeypatch.setenv("PYROSGEN_COQLIB", str(lib))
    code, out, err = run(capsys, "generate", LANDSHARK, "-o", outdir)
    assert code == 2
    assert "the Coq library is not built: run make proofs" in err
    assert "ROSGen/glue/NodeModel.vo is older than NodeModel.v" in err
    assert len(list(outdir.iterdir())) == 1


def test_corrupt_library_exit_2(capsys, tmp_path, outdir, monkeypatch):
    """A library whose compiled files are garbage: coqc fails, exit 2."""
    require_library()
    lib = tmp_path / "lib" / "theories"
    lib.mkdir(parents=True)
    shutil.copy(DEFAULT_THEORIES.parent / "_CoqProject", lib.parent / "_CoqProject")
    for p in DEFAULT_THEORIES.rglob("*"):
        dest = lib / p.relative_to(DEFAULT_THEORIES)
        if p.suffix in (".v", ".vo"):
            dest.parent.mkdir(parents=True, exist_ok=True)
        if p.suffix == ".v":
            os.symlink(p, dest)
        elif p.suffix == ".vo":
            dest.write_bytes(b"not a Coq library\n")
    monkeypatch.setenv("PYROSGEN_COQLIB", str(lib))
    code, out, err = run(capsys, "generate", MULTI, "-o", outdir, "-q")
    assert code == 2
    assert err.startswith("pyrosgen: error: coqc failed on multi_node.v")
    assert len(list(outdir.iterdir())) == 1
    assert _no_work_dirs(tmp_path)


def test_keep_work(capsys, tmp_path):
    require_library()
    code, out, err = run(capsys, "generate", LANDSHARK, "-o", tmp_path / "o", "--keep-work")
    assert code == 0, err
    kept = list(tmp_path.glob(".pyrosgen-landshark_controller-*"))
    assert len(kept) == 1 and f"work directory kept: {kept[0]}" in err
    assert (kept[0] / "coq" / f"{NODE}.vo").is_file()
    shutil.rmtree(kept[0])


@pytest.mark.parametrize("empty", ["", " "])
def test_empty_output_folder_exit_1(capsys, tmp_path, monkeypatch, empty):
    """``-o ""`` was read as the current folder (exit 0, files written
    there); it is refused, and nothing is written."""
    monkeypatch.chdir(tmp_path)
    code, out, err = run(capsys, "generate", LANDSHARK, "-o", empty)
    assert code == 1, err
    assert f"the output folder '{empty}' is empty; give a folder name (-o . for the current folder)" in err
    assert "Traceback" not in err
    assert list(tmp_path.iterdir()) == []


def _make_link_to_zero(p: Path) -> None:
    p.symlink_to("/dev/zero")


def _make_dangling_link(p: Path) -> None:
    p.symlink_to(p.parent / "nowhere")


def _make_fifo(p: Path) -> None:
    os.mkfifo(p)


def _make_folder(p: Path) -> None:
    p.mkdir()


@pytest.mark.parametrize("make, what", [
    (_make_link_to_zero, "a symbolic link"),
    (_make_dangling_link, "a symbolic link"),
    (_make_fifo, "a special file (a device, FIFO or socket)"),
    (_make_folder, "a folder"),
], ids=["link-to-dev-zero", "dangling-link", "fifo", "folder"])
def test_output_name_taken_by_a_link_or_special_file_exit_1(tmp_path, outdir, make, what):
    """A link to /dev/zero named like an output file made generate copy
    without end (the old file is backed up before it is replaced); it is
    refused without being followed, read or replaced, and nothing is
    written.  In a subprocess with a timeout, so that a regression fails
    instead of hanging the suite."""
    require_library()
    target = outdir / f"{NODE}.v"
    make(target)
    before = sorted(p.name for p in outdir.iterdir())
    res = subprocess.run([sys.executable, "-m", "pyrosgen", "generate", str(LANDSHARK), "-o", str(outdir), "-q"],
                         capture_output=True, text=True, timeout=300)
    assert res.returncode == 1, res.stderr
    assert (f"{target}: is {what}; pyrosgen writes its output files only as regular files and does not "
            "follow or replace it: remove it, or choose another output folder") in res.stderr
    assert "Traceback" not in res.stderr
    assert sorted(p.name for p in outdir.iterdir()) == before
    assert os.path.islink(target) == (what == "a symbolic link")
    assert _no_work_dirs(tmp_path)


_INSTALL_OVER_A_LARGE_FILE = """
import resource, sys
from pathlib import Path
resource.setrlimit(resource.RLIMIT_AS, (1 << 30, 1 << 30))   # 1 GiB: the old file is 4 GiB
from pyrosgen.generate import _install
out, stage = Path(sys.argv[1]), Path(sys.argv[2])
[(target, rewritten)] = _install([(stage / "new.v", "node.v")], out)
print(target.name, rewritten)
"""


def test_large_old_output_is_replaced_without_being_read(tmp_path):
    """An old output file is compared by size first and backed up by a
    hard link: a (sparse) 4 GiB file named like an output was read whole
    and copied before being replaced.  In a subprocess whose address space
    is limited to 1 GiB, so that reading it fails at once."""
    out, stage = tmp_path / "out", tmp_path / "stage"
    out.mkdir()
    stage.mkdir()
    with open(out / "node.v", "wb") as fh:
        fh.truncate(4 << 30)
    (stage / "new.v").write_text("(* new *)\n")
    old_inode = os.stat(out / "node.v").st_ino
    res = subprocess.run([sys.executable, "-c", _INSTALL_OVER_A_LARGE_FILE, str(out), str(stage)],
                         capture_output=True, text=True, timeout=120, cwd=Path(__file__).resolve().parents[2])
    assert res.returncode == 0, res.stderr[-2000:]
    assert res.stdout.split() == ["node.v", "True"]
    assert (out / "node.v").read_text() == "(* new *)\n"
    # the backup kept for an undo is the old file under a second name, not
    # a copy of its 4 GiB
    assert os.stat(stage / "new.v.old").st_ino == old_inode


def test_usage_errors(capsys):
    code, out, err = run(capsys, "generate", LANDSHARK)
    assert code == 1 and "-o" in err
    code, out, err = run(capsys, "check", LANDSHARK)
    assert code == 0

"""``pyrosgen diagram -o PATH`` (issue 13): only a regular file is written
or replaced, atomically; what else is at PATH (a symbolic link, a FIFO, a
device, a socket, a directory) is refused and left as it is; a missing or
non-folder parent is an error, never created; a failure leaves the old
file as it was and no temporary file behind.  Complements
test_output_path.py."""

from __future__ import annotations

import builtins
import io
import os
import pathlib
import socket
import stat
from pathlib import Path

import pytest

from pyrosgen import cli, diagram

LANDSHARK = Path(__file__).resolve().parents[2] / "examples/landshark/landshark_controller.yaml"


def _diagram(capsys, out, *extra: str) -> tuple[int, str]:
    code = cli.main(["diagram", str(LANDSHARK), "-o", str(out), "--format", "dot", *extra])
    o, e = capsys.readouterr()
    return code, o + e


def test_device_is_refused_and_untouched(capsys):
    before = os.stat("/dev/null")
    code, text = _diagram(capsys, "/dev/null")
    assert code == 1
    assert "/dev/null: exists and is a device, not a regular file" in text
    after = os.stat("/dev/null")
    assert stat.S_ISCHR(after.st_mode) and after.st_ino == before.st_ino


def test_socket_is_refused_as_a_socket(capsys, tmp_path):
    path = tmp_path / "d.dot"
    s = socket.socket(socket.AF_UNIX)
    try:
        s.bind(str(path))
        code, text = _diagram(capsys, path)
    finally:
        s.close()
    assert code == 1 and "d.dot: exists and is a socket, not a regular file" in text
    assert stat.S_ISSOCK(os.lstat(path).st_mode)


def test_symlink_to_a_directory_is_refused(capsys, tmp_path):
    (tmp_path / "dir").mkdir()
    (tmp_path / "d.dot").symlink_to(tmp_path / "dir")
    code, text = _diagram(capsys, tmp_path / "d.dot")
    assert code == 1 and "Traceback" not in text
    assert (tmp_path / "d.dot").is_symlink() and list((tmp_path / "dir").iterdir()) == []


def test_parent_that_is_a_file_is_named(capsys, tmp_path):
    """Was "afile/d.dot: Not a directory"."""
    (tmp_path / "afile").write_text("keep\n")
    code, text = _diagram(capsys, tmp_path / "afile" / "d.dot")
    assert code == 1
    assert "afile: not a folder, so it cannot hold the output file" in text
    assert (tmp_path / "afile").read_text() == "keep\n"


def test_missing_parent_is_an_error_not_created(capsys, tmp_path):
    code, text = _diagram(capsys, tmp_path / "no" / "d.dot")
    assert code == 1
    assert "no: the output folder does not exist (pyrosgen diagram does not create it)" in text
    assert list(tmp_path.iterdir()) == []


def test_trailing_slash_names_a_folder(capsys, tmp_path):
    """``-o new.dot/`` wrote a file new.dot: Path() drops the final '/'."""
    code, text = _diagram(capsys, f"{tmp_path}/new.dot/")
    assert code == 1 and "new.dot/' names a folder, not a file; give a file name" in text
    assert list(tmp_path.iterdir()) == []


def test_control_characters_in_the_path_are_escaped(capsys, tmp_path):
    """The error printed the path raw: a file name could drive the terminal."""
    code, text = _diagram(capsys, tmp_path / "no\x1b[31m" / "d.dot")
    assert code == 1
    assert "\x1b" not in text and "no\\x1b[31m: the output folder does not exist" in text


def test_replaced_file_keeps_its_permissions(capsys, tmp_path):
    out = tmp_path / "d.dot"
    out.write_text("old\n")
    out.chmod(0o600)
    code, text = _diagram(capsys, out)
    assert code == 0, text
    assert "digraph" in out.read_text()
    assert stat.S_IMODE(out.stat().st_mode) == 0o600


def test_new_file_follows_the_umask(capsys, tmp_path):
    old = os.umask(0o027)
    try:
        code, text = _diagram(capsys, tmp_path / "d.dot")
    finally:
        os.umask(old)
    assert code == 0, text
    assert stat.S_IMODE((tmp_path / "d.dot").stat().st_mode) == 0o640


def test_failed_rename_leaves_the_old_file_and_no_temporary(capsys, tmp_path, monkeypatch):
    out = tmp_path / "d.dot"
    out.write_text("old\n")

    def no_space(src, dst):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(diagram.os, "replace", no_space)
    code, text = _diagram(capsys, out)
    assert code == 1 and "No space left on device" in text
    assert out.read_text() == "old\n"
    assert [p.name for p in tmp_path.iterdir()] == ["d.dot"]


def test_failed_dot_leaves_the_old_file(capsys, tmp_path, monkeypatch):
    fake = tmp_path / "fake-dot"
    fake.write_text("#!/bin/sh\necho 'dot: out of memory' >&2\nexit 3\n")
    fake.chmod(0o755)
    monkeypatch.setenv("PYROSGEN_DOT", str(fake))
    out = tmp_path / "d.svg"
    out.write_text("old\n")
    code = cli.main(["diagram", str(LANDSHARK), "-o", str(out)])
    text = "".join(capsys.readouterr())
    assert code == 2 and "dot: out of memory" in text
    assert out.read_text() == "old\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["d.svg", "fake-dot"]


def test_unchanged_file_is_not_rewritten(capsys, tmp_path):
    out = tmp_path / "d.dot"
    assert _diagram(capsys, out)[0] == 0
    ino = out.stat().st_ino
    assert _diagram(capsys, out)[0] == 0
    assert out.stat().st_ino == ino


def test_existing_file_of_another_size_is_not_read(capsys, tmp_path, monkeypatch):
    """Comparing with the old content read all of it, whatever its size."""
    out = tmp_path / "d.dot"
    out.write_bytes(b"x" * 100_000)
    reads = []
    real_open, real_read_bytes = io.open, pathlib.Path.read_bytes

    def spy_open(file, mode="r", *a, **k):
        if isinstance(file, (str, os.PathLike)) and os.fspath(file) == str(out) and "r" in mode:
            reads.append(mode)
        return real_open(file, mode, *a, **k)

    def spy_read_bytes(self):
        if str(self) == str(out):
            reads.append("read_bytes")
        return real_read_bytes(self)

    monkeypatch.setattr(io, "open", spy_open)
    monkeypatch.setattr(builtins, "open", spy_open)
    monkeypatch.setattr(pathlib.Path, "read_bytes", spy_read_bytes)
    code, text = _diagram(capsys, out)
    assert code == 0, text
    assert reads == [] and "digraph" in out.read_text()


@pytest.mark.parametrize("name", ["", ".", ".."])
def test_write_diagram_refuses_folder_names(tmp_path, name):
    with pytest.raises(diagram.DiagramOutputError, match="names a folder"):
        diagram.write_diagram(None, f"{tmp_path}/{name}" if name else "", "dot")

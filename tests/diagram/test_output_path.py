"""``pyrosgen diagram -o PATH`` writes or replaces only a regular file:
a symbolic link, a FIFO or a directory at PATH is refused and left as it
is, and a missing output folder is an error, not created."""

from __future__ import annotations

import os
from pathlib import Path

from pyrosgen import cli

LANDSHARK = Path(__file__).resolve().parents[2] / "examples/landshark/landshark_controller.yaml"


def _diagram(capsys, out: Path) -> tuple[int, str]:
    code = cli.main(["diagram", str(LANDSHARK), "-o", str(out), "--format", "dot"])
    o, e = capsys.readouterr()
    return code, o + e


def test_symlink_is_not_followed(capsys, tmp_path):
    target = tmp_path / "precious.txt"
    target.write_text("keep me\n")
    link = tmp_path / "d.dot"
    link.symlink_to(target)
    code, text = _diagram(capsys, link)
    assert code == 1 and "is a symbolic link, not a regular file" in text
    assert link.is_symlink() and target.read_text() == "keep me\n"


def test_fifo_is_not_replaced(capsys, tmp_path):
    fifo = tmp_path / "d.dot"
    os.mkfifo(fifo)
    code, text = _diagram(capsys, fifo)
    assert code == 1 and "is a FIFO" in text
    assert fifo.is_fifo()


def test_missing_folder_is_not_created(capsys, tmp_path):
    code, text = _diagram(capsys, tmp_path / "no" / "such" / "d.dot")
    assert code == 1 and "the output folder does not exist" in text
    assert not (tmp_path / "no").exists()


def test_regular_file_is_replaced_atomically(capsys, tmp_path):
    out = tmp_path / "d.dot"
    out.write_text("old\n")
    code, text = _diagram(capsys, out)
    assert code == 0, text
    assert out.read_text().startswith("//") or "digraph" in out.read_text()
    assert [p.name for p in tmp_path.iterdir()] == ["d.dot"]  # no temporary left

"""An output folder on another file system than its parent (a mount point,
as ``-o /out`` in a container): the staged files cannot be renamed into
it, and are copied into place instead, each atomically."""

from __future__ import annotations

import errno
import os
from pathlib import Path

from pyrosgen import cli
from pyrosgen.files import move

from support.generate import LANDSHARK, require_library

NODE = "landshark_controller"


def test_move_across_file_systems(tmp_path, monkeypatch):
    src, dst = tmp_path / "a", tmp_path / "d" / "b"
    dst.parent.mkdir()
    src.write_text("new")
    dst.write_text("old")
    real = os.replace
    calls = []

    def cross(a, b):
        calls.append((Path(a).parent, Path(b).parent))
        if Path(a).parent != Path(b).parent:  # a different file system, as far as rename knows
            raise OSError(errno.EXDEV, "Invalid cross-device link")
        return real(a, b)

    monkeypatch.setattr(os, "replace", cross)
    move(src, dst)
    assert dst.read_text() == "new" and not src.exists()
    assert sorted(p.name for p in dst.parent.iterdir()) == ["b"]  # no temporary left
    assert calls[-1] == (dst.parent, dst.parent)  # the last step renames inside the destination's folder


def test_generate_into_a_mount_point(mount_point, capsys):
    require_library()
    assert os.stat(mount_point).st_dev != os.stat(mount_point.parent).st_dev
    code = cli.main(["generate", str(LANDSHARK), "-o", str(mount_point), "-q"])
    out, err = capsys.readouterr()
    assert code == 0, err
    names = sorted(p.name for p in mount_point.iterdir())
    assert f"{NODE}_glue.c" in names and f"{NODE}.certificate.md" in names
    assert not [n for n in names if n.startswith(".")]  # no temporaries
    # again, unchanged: nothing rewritten; then verified from the mount point
    assert cli.main(["generate", str(LANDSHARK), "-o", str(mount_point), "-q"]) == 0
    assert "written" not in capsys.readouterr().out.replace("0 written", "")
    assert cli.main(["verify", str(mount_point), "-q"]) == 0
    assert not list(mount_point.parent.glob(".pyrosgen-*"))

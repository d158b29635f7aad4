"""Moving files into an output folder, across file systems.

The pipelines stage their outputs in a work folder next to the output
folder and move them in only when everything succeeded.  When the output
folder is a mount point (``-o /out`` in a container), the work folder is on
another file system and ``rename`` fails with ``EXDEV``; :func:`move` then
copies the file into a temporary name in the destination's own folder and
renames it into place, so that the destination still changes atomically
(a reader sees the old file or the new one, never a part)."""

from __future__ import annotations

import errno
import os
import shutil
import tempfile
from pathlib import Path

__all__ = ["move"]


def move(src: Path, dst: Path) -> None:
    """Move ``src`` to ``dst`` (replacing it), atomically for ``dst``."""
    try:
        os.replace(src, dst)
        return
    except OSError as exc:
        if exc.errno != errno.EXDEV:
            raise
    fd, tmp = tempfile.mkstemp(prefix=f".{dst.name}.", suffix=".pyrosgen-tmp", dir=str(dst.parent))
    os.close(fd)
    try:
        shutil.copy2(src, tmp)
        os.replace(tmp, dst)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise
    os.unlink(src)

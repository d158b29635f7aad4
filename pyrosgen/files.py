"""Moving files into an output folder, across file systems.

The pipelines stage their outputs in a work folder next to the output
folder and move them in only when everything succeeded.  When the output
folder is a mount point (``-o /out`` in a container), the work folder is on
another file system and ``rename`` fails with ``EXDEV``; :func:`move` then
copies the file into a temporary name in the destination's own folder and
renames it into place, so that the destination still changes atomically
(a reader sees the old file or the new one, never a part)."""

from __future__ import annotations

import contextlib
import errno
import fcntl
import os
import shutil
import tempfile
from pathlib import Path

__all__ = ["move", "locked_folder"]


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


@contextlib.contextmanager
def locked_folder(folder: Path, on_wait=None):
    """Hold an exclusive lock on ``folder`` (``flock`` on the folder
    itself: no lock file is left behind) while its contents are replaced,
    so that concurrent runs into one output folder install one after the
    other, each its complete set of files.  ``on_wait`` is called once if
    another run holds the lock."""
    fd = os.open(str(folder), os.O_RDONLY | os.O_DIRECTORY)
    try:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            if on_wait is not None:
                on_wait()
            fcntl.flock(fd, fcntl.LOCK_EX)
        yield
    finally:
        os.close(fd)  # releases the lock

"""Reading a received output folder as hostile input.

``pyrosgen verify`` checks a folder that it must not trust: every name the
folder's manifest gives is a relative path inside the folder, of a regular
file that is not a symbolic link (nor behind one), of bounded size; a FIFO,
a device or a link to ``/dev/zero`` is refused before anything reads it, so
that no name in the folder can make ``verify`` hang, fill the memory or the
disk, or read or write outside the folder.

One entry point reads everything: :func:`read_file`.  It opens the file
with ``O_NOFOLLOW | O_NONBLOCK`` (a FIFO opens without blocking, a link is
not followed), checks with ``fstat`` on the open descriptor that it is a
regular file of at most ``limit`` bytes (no race between the check and the
read), and reads at most ``limit + 1`` bytes.
"""

from __future__ import annotations

import os
import re
import stat
from pathlib import Path, PurePosixPath

from pyrosgen.errors import UserError

__all__ = ["UnsafeFile", "MAX_FILE_BYTES", "check_name", "read_file", "read_text"]

#: The largest file of an output folder that ``verify`` reads (64 MiB): the
#: largest real one, a node with two controller arrays of 8,192 elements,
#: has an AST dump of about 10 MB.
MAX_FILE_BYTES = 64 << 20

#: A name of the folder: relative, '/'-separated, each part a portable file
#: name (no NUL, no control character, no '..').
_PART = re.compile(r"^[A-Za-z0-9_.+-]{1,255}$")


class UnsafeFile(UserError):
    """A name of the folder that ``verify`` refuses to read (exit 1)."""


def check_name(name: object, what: str = "file") -> PurePosixPath:
    """``name`` as a relative path inside the folder, or :class:`UnsafeFile`."""
    if not isinstance(name, str) or not name:
        raise UnsafeFile(f"{what} name {name!r}: not a non-empty string")
    if len(name) > 1024:
        raise UnsafeFile(f"{what} name of {len(name)} characters: longer than 1024")
    p = PurePosixPath(name)
    if p.is_absolute() or name.startswith("/"):
        raise UnsafeFile(f"{what} {name!r}: an absolute path, not a name inside the folder")
    parts = name.split("/")
    for part in parts:
        if part in ("", ".", ".."):
            raise UnsafeFile(f"{what} {name!r}: not a plain relative path ('{part}' in it)")
        if not _PART.match(part):
            raise UnsafeFile(f"{what} {name!r}: the part {part!r} is not a portable file name "
                             "(letters, digits, '_', '.', '+', '-')")
    return p


def read_file(folder: str | Path, name: object, *, limit: int = MAX_FILE_BYTES, what: str = "file") -> bytes:
    """The bytes of the regular file ``folder/name``; :class:`UnsafeFile`
    if ``name`` is not a plain relative name, if the file or a folder on its
    way is a symbolic link, if it is not a regular file, or if it is larger
    than ``limit`` bytes; ``FileNotFoundError`` if it is missing."""
    rel = check_name(name, what)
    base = Path(folder)
    # every folder on the way is a real folder of the output folder, not a link
    cur = base
    for part in rel.parts[:-1]:
        cur = cur / part
        try:
            st = os.lstat(cur)
        except FileNotFoundError:
            raise FileNotFoundError(f"{name}: missing") from None
        if not stat.S_ISDIR(st.st_mode):
            raise UnsafeFile(f"{what} {name}: {cur.relative_to(base)} is not a folder "
                             "(a symbolic link or another kind of file)")
    path = base / rel
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NOFOLLOW | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0))
    except FileNotFoundError:
        raise FileNotFoundError(f"{name}: missing") from None
    except OSError as exc:
        if os.path.islink(path):
            raise UnsafeFile(f"{what} {name}: a symbolic link (to {os.readlink(path)!r}), not a file") from None
        raise UnsafeFile(f"{what} {name}: cannot open: {exc.strerror or exc}") from None
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode):
            kind = ("a FIFO" if stat.S_ISFIFO(st.st_mode) else "a device" if stat.S_ISCHR(st.st_mode)
                    or stat.S_ISBLK(st.st_mode) else "a socket" if stat.S_ISSOCK(st.st_mode)
                    else "a folder" if stat.S_ISDIR(st.st_mode) else "not a regular file")
            raise UnsafeFile(f"{what} {name}: {kind}, not a regular file")
        if st.st_size > limit:
            raise UnsafeFile(f"{what} {name}: {st.st_size} bytes, more than the {limit} bytes verify reads")
        chunks, left = [], limit + 1
        while left > 0:
            b = os.read(fd, min(left, 1 << 20))
            if not b:
                break
            chunks.append(b)
            left -= len(b)
        data = b"".join(chunks)
        if len(data) > limit:
            raise UnsafeFile(f"{what} {name}: more than the {limit} bytes verify reads")
        return data
    finally:
        os.close(fd)


def read_text(folder: str | Path, name: object, *, limit: int = MAX_FILE_BYTES, what: str = "file") -> str:
    """:func:`read_file` decoded as UTF-8 (:class:`UnsafeFile` if it is not)."""
    data = read_file(folder, name, limit=limit, what=what)
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise UnsafeFile(f"{what} {name}: not UTF-8 text (byte {exc.start})") from None

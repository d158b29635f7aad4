"""Where pyrosgen finds its templates and the Coq library.

Both ship with the package: the templates as ``pyrosgen/templates`` and the
Coq library's sources (``coq/`` of the repository) as ``pyrosgen/_coq``
(package data, see ``pyproject.toml``).  In a source checkout (an editable
install, ``make``), the checkout's own ``coq/`` is used, built by
``make proofs``.  In a regular install, the library's sources are inside the
package, and the compiled library is built once, on first use, into a cache
folder (:func:`coq_theories`).
"""

from __future__ import annotations

import fcntl
import hashlib
import os
import shutil
import subprocess
import sys
import tempfile
from importlib import resources as _res
from pathlib import Path

__all__ = [
    "PACKAGE_DIR",
    "templates_dir",
    "coq_dir",
    "coq_templates_dir",
    "in_checkout",
    "cache_root",
    "coq_sources_digest",
    "coq_theories",
    "LibraryBuildError",
]

#: The installed (or checked-out) package folder.
PACKAGE_DIR = Path(str(_res.files("pyrosgen")))

#: Environment variable naming the cache folder of compiled libraries.
CACHE_ENV = "PYROSGEN_CACHE"

#: Files of the Coq library that its build and its digest depend on.
_COQ_PATTERNS = ("_CoqProject", "Makefile", "theories/**/*.v", "checks/*", "extraction/*", "templates/*.j2")


class LibraryBuildError(RuntimeError):
    """Building the packaged Coq library into the cache failed."""


def templates_dir() -> Path:
    """``pyrosgen/templates``: the templates of every non-Coq output."""
    return PACKAGE_DIR / "templates"


def in_checkout() -> bool:
    """Whether pyrosgen runs from a source checkout (``coq/`` next to the
    package folder)."""
    return (PACKAGE_DIR.parent / "coq" / "_CoqProject").is_file()


def coq_dir() -> Path:
    """The Coq library's sources: ``coq/`` of the checkout, else the
    packaged copy ``pyrosgen/_coq``."""
    if in_checkout():
        return PACKAGE_DIR.parent / "coq"
    return PACKAGE_DIR / "_coq"


def coq_templates_dir() -> Path:
    """``coq/templates``: the per-node Coq file's templates."""
    return coq_dir() / "templates"


def _coq_files(src: Path) -> list[Path]:
    files: set[Path] = set()
    for pat in _COQ_PATTERNS:
        files.update(p for p in src.glob(pat) if p.is_file())
    return sorted(files)


def coq_sources_digest(src: Path | None = None) -> str:
    """SHA-256 over the library's source files (names and contents)."""
    src = coq_dir() if src is None else src
    h = hashlib.sha256()
    for p in _coq_files(src):
        h.update(p.relative_to(src).as_posix().encode() + b"\0")
        h.update(p.read_bytes() + b"\0")
    return h.hexdigest()


def cache_root() -> Path:
    """``$PYROSGEN_CACHE``, else ``${XDG_CACHE_HOME:-~/.cache}/pyrosgen``."""
    env = os.environ.get(CACHE_ENV)
    if env:
        return Path(env)
    xdg = os.environ.get("XDG_CACHE_HOME")
    return (Path(xdg) if xdg else Path.home() / ".cache") / "pyrosgen"


def _version() -> str:
    from pyrosgen import __version__

    return __version__


def coq_theories(*, build: bool = True, src: Path | None = None, progress=None) -> Path:
    """The ``theories`` folder of the compiled library.

    In a checkout: ``coq/theories`` (built by ``make proofs``; the driver
    says so when it is not).  Otherwise the cache folder
    ``<cache>/coq-<version>-<digest>/theories``, built now if it is missing
    and ``build`` is true: the packaged sources are copied into a temporary
    folder next to it, compiled with ``make``, and renamed into place, under
    a lock so that concurrent runs build it once.  ``progress`` receives one
    line before a build."""
    if src is None and in_checkout():
        return coq_dir() / "theories"
    src = coq_dir() if src is None else src
    root = cache_root()
    final = root / f"coq-{_version()}-{coq_sources_digest(src)[:16]}"
    if (final / ".built").is_file() or not build:
        return final / "theories"
    root.mkdir(parents=True, exist_ok=True)
    with open(root / ".lock", "a") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        try:
            if (final / ".built").is_file():
                return final / "theories"
            if progress is not None:
                progress(f"building the Coq library once into {final} (about 1 min)")
            tmp = Path(tempfile.mkdtemp(prefix=".coq-build-", dir=root))
            try:
                for p in _coq_files(src):
                    dest = tmp / p.relative_to(src)
                    dest.parent.mkdir(parents=True, exist_ok=True)
                    shutil.copy2(p, dest)
                proc = subprocess.run(
                    ["make", "--no-print-directory", "-C", str(tmp), "build", "check-proof", "check-assumptions"],
                    capture_output=True, text=True, check=False,
                )
                if proc.returncode != 0:
                    tail = (proc.stdout + proc.stderr).strip().splitlines()[-20:]
                    raise LibraryBuildError(
                        "building the Coq library failed:\n" + "\n".join(f"  {ln}" for ln in tail)
                    )
                (tmp / ".built").write_text(coq_sources_digest(src) + "\n")
                if final.exists():
                    shutil.rmtree(final)
                os.replace(tmp, final)
            finally:
                if tmp.exists():
                    shutil.rmtree(tmp, ignore_errors=True)
        finally:
            fcntl.flock(lock, fcntl.LOCK_UN)
    return final / "theories"


if __name__ == "__main__":  # pragma: no cover - a helper for `make`
    print(coq_theories(progress=lambda s: print(s, file=sys.stderr)))

"""Generating a system: every node through the node pipeline
(:func:`pyrosgen.generate.generate`), in parallel processes, with a
content-addressed cache, into ``OUT/<node folder>/``, plus the system's
files (DESIGN.md section 10).

The cache (``--cache DIR``, default ``nodes/`` in ``$PYROSGEN_CACHE`` or
``~/.cache/pyrosgen``) holds one entry per key, a folder
``<key>/`` with the node's output files under ``files/`` and
``entry.json``: the key, each file's SHA-256 and the digest of that list.
The key is the SHA-256 of what the node's output depends on: the node
model's bytes and file name, the message definitions it uses (as the
front end read them), the bytes of every ``.msg`` file under its
``msg_paths`` and of its controller folder, the ROSGen library's digest,
the versions of coqc, ocamlopt and gcc, and the digest of pyrosgen's own
sources and templates.  An entry is written under a temporary name
(``.tmp-<pid>-...``, locked by its worker) and renamed into place only
once complete; a reader trusts an entry only when ``entry.json`` names its
key and every file's digest matches, so a killed run leaves nothing a
later run trusts (its temporary folders are removed by the next run, whose
lock they no longer hold).  A corrupted entry is a miss (the node is proved again).

Nothing is written into ``OUT`` unless every node succeeded: the nodes are
staged next to ``OUT`` and moved in at the end.
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
import tempfile
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path

from pyrosgen.errors import PyrosgenError, ToolFailure, UserError, show
from pyrosgen.files import locked_folder

__all__ = ["SystemGenerateResult", "NodeOutcome", "generate_system", "default_cache", "node_key",
           "entry_valid", "SystemNodeFailure"]

ENTRY = "entry.json"


class SystemNodeFailure(PyrosgenError):
    """One or more nodes failed: their reports, each line prefixed with the
    node; the exit code is the worst (2 over 1)."""

    def __init__(self, lines: list[str], exit_code: int):
        self.lines = lines
        self.exit_code = exit_code
        super().__init__("\n".join(lines))

    def report(self, ctx) -> list[str]:
        tail = f"; {ctx.nothing}" if ctx.nothing else ""
        return [*self.lines, f"pyrosgen: error: the system was not generated{tail}"]


@dataclass
class NodeOutcome:
    """What happened to one node."""

    folder: str
    name: str
    key: str
    cached: bool
    seconds: float = 0.0


@dataclass
class SystemGenerateResult:
    out_dir: Path
    nodes: list[NodeOutcome]
    files: list[str] = field(default_factory=list)
    seconds: float = 0.0

    @property
    def hits(self) -> int:
        return sum(1 for n in self.nodes if n.cached)


def default_cache() -> Path:
    """``nodes/`` of pyrosgen's cache folder
    (:func:`pyrosgen.resources.cache_root`: ``$PYROSGEN_CACHE``, else
    ``${XDG_CACHE_HOME:-~/.cache}/pyrosgen``)."""
    from pyrosgen.resources import cache_root

    return cache_root() / "nodes"


def _sha(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


def _sha_file(p: Path) -> str:
    h = hashlib.sha256()
    with open(p, "rb") as fh:
        for chunk in iter(lambda: fh.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest()


def _tree_digest(h, root: Path, suffixes: tuple[str, ...] | None = None) -> None:
    files = sorted(p for p in root.rglob("*") if p.is_file() and not p.is_symlink()
                   and (suffixes is None or p.name.endswith(suffixes)))
    for p in files:
        h.update(p.relative_to(root).as_posix().encode() + b"\0" + _sha_file(p).encode() + b"\0")


_ENV_DIGEST: str | None = None


def _environment_digest() -> str:
    """The library digest, the tools' versions and pyrosgen's own sources
    (computed once per process)."""
    global _ENV_DIGEST
    if _ENV_DIGEST is None:
        import pyrosgen
        from pyrosgen.proof.coqdriver import CoqDriver
        from pyrosgen.verify.certificate import tool_versions

        h = hashlib.sha256()
        drv = CoqDriver()
        h.update(b"library\0" + drv.library_digest().encode() + b"\0")
        for name, version in tool_versions():
            h.update(f"{name}\0{version}\0".encode())
        h.update(f"pyrosgen\0{pyrosgen.__version__}\0".encode())
        _tree_digest(h, Path(pyrosgen.__file__).parent, (".py", ".j2", ".sh", ".ml", ".v"))
        from pyrosgen.resources import coq_templates_dir

        if coq_templates_dir().is_dir():
            _tree_digest(h, coq_templates_dir())
        _ENV_DIGEST = h.hexdigest()
    return _ENV_DIGEST


def node_key(sn) -> str:
    """The cache key of system node ``sn`` (its model loaded)."""
    m = sn.model
    h = hashlib.sha256()
    h.update(b"pyrosgen-system-node-1\0")
    h.update(b"env\0" + _environment_digest().encode() + b"\0")
    h.update(b"model\0" + Path(m.source).name.encode() + b"\0" + _sha_file(Path(m.source)).encode() + b"\0")
    h.update(b"messages\0" + repr(m.messages).encode() + b"\0")
    for p in m.msg_paths:
        h.update(b"msg_path\0")
        if Path(p).is_dir():
            _tree_digest(h, Path(p), (".msg",))
    if sn.controller is not None and sn.controller.is_dir():
        h.update(b"controller\0")
        _tree_digest(h, sn.controller)
    return h.hexdigest()


def _entry_digest(files: dict[str, str]) -> str:
    return _sha(json.dumps(sorted(files.items())).encode())


def entry_valid(entry: Path, key: str) -> bool:
    """Whether the cache entry folder ``entry`` can be trusted for ``key``:
    complete, naming its key, every file present with its digest, no other
    file."""
    try:
        meta = json.loads((entry / ENTRY).read_text(encoding="utf-8"))
        files = meta["files"]
        if meta.get("key") != key or meta.get("digest") != _entry_digest(files):
            return False
        root = entry / "files"
        present = sorted(p.relative_to(root).as_posix() for p in root.rglob("*") if p.is_file())
        if present != sorted(files):
            return False
        return all(not (root / n).is_symlink() and _sha_file(root / n) == d for n, d in files.items())
    except (OSError, ValueError, KeyError, TypeError, AttributeError):
        return False


def _clean_dead_temps(cache: Path) -> None:
    """Remove the temporary folders of runs that are gone: each worker
    holds an exclusive ``flock`` on its folder's ``.lock`` while it works
    (the kernel releases it when the process dies, however it dies), so a
    folder whose lock can be taken belongs to nobody.  A folder without a
    lock (killed between its creation and the lock's) is removed once it
    is ten minutes old."""
    import fcntl

    try:
        names = os.listdir(cache)
    except OSError:
        return
    for n in names:
        if not n.startswith(".tmp-"):
            continue
        folder = cache / n
        try:
            fd = os.open(folder / ".lock", os.O_RDONLY)
        except FileNotFoundError:
            try:
                if time.time() - folder.stat().st_mtime > 600:
                    shutil.rmtree(folder, ignore_errors=True)
            except OSError:
                pass
            continue
        except OSError:
            continue
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            os.close(fd)
            continue            # its worker is still at work
        try:
            shutil.rmtree(folder, ignore_errors=True)
        finally:
            os.close(fd)


def _gen_node(model_path: str, dest: str) -> tuple[str, float, int, list[str]]:
    """Worker: the node pipeline into ``dest`` (a fresh folder).  Returns
    (status, seconds, exit code, report lines); never raises."""
    from pyrosgen.errors import Context
    from pyrosgen.generate import generate

    t0 = time.monotonic()
    try:
        generate(model_path, dest)
        return ("ok", time.monotonic() - t0, 0, [])
    except PyrosgenError as exc:
        return ("error", time.monotonic() - t0, exc.exit_code, exc.report(Context()))
    except Exception as exc:  # noqa: BLE001 - reported, never a traceback
        return ("error", time.monotonic() - t0, 2, [f"pyrosgen: internal error: {type(exc).__name__}: {exc}"])


def _gen_cached(model_path: str, cache: str, key: str) -> tuple[str, float, int, list[str]]:
    """Worker: generate the node into a temporary folder of the cache and
    rename it into place as entry ``key``."""
    import fcntl

    tmp = Path(tempfile.mkdtemp(prefix=f".tmp-{os.getpid()}-", dir=cache))
    lock = os.open(tmp / ".lock", os.O_RDWR | os.O_CREAT, 0o600)
    fcntl.flock(lock, fcntl.LOCK_EX)
    try:
        status = _gen_node(model_path, str(tmp / "files"))
        if status[0] != "ok":
            return status
        root = tmp / "files"
        files = {p.relative_to(root).as_posix(): _sha_file(p) for p in sorted(root.rglob("*")) if p.is_file()}
        meta = {"format": 1, "key": key, "files": files, "digest": _entry_digest(files)}
        with open(tmp / ENTRY, "w", encoding="utf-8") as fh:
            json.dump(meta, fh, indent=1, sort_keys=True)
            fh.flush()
            os.fsync(fh.fileno())
        target = Path(cache) / key
        try:
            os.rename(tmp, target)
        except OSError:
            # another run installed the same key meanwhile, or a bad entry
            # sits there: replace a bad one, keep a good one
            if not entry_valid(target, key):
                shutil.rmtree(target, ignore_errors=True)
                os.rename(tmp, target)
        return status
    finally:
        if tmp.exists():
            shutil.rmtree(tmp, ignore_errors=True)
        os.close(lock)


def generate_system(system_path: str | Path, out_dir: str | Path, *, jobs: int | None = None,
                    cache: Path | None = None, use_cache: bool = True, progress=None) -> SystemGenerateResult:
    """Check the system, generate every node (``jobs`` processes, default
    the number of cores), write the system's files, install into
    ``out_dir``."""
    from pyrosgen.system.checks import check_system
    from pyrosgen.system.model import load_system
    from pyrosgen.system.certificate import system_files

    say = progress or (lambda _l: None)
    t0 = time.monotonic()
    if not str(out_dir).strip():
        raise UserError("the output folder is empty; give a folder name")
    out = Path(out_dir)
    if out.exists() and not out.is_dir():
        raise UserError(f"{out}: exists and is not a directory")
    sysm = load_system(system_path)
    graph = check_system(sysm)
    jobs = jobs or os.cpu_count() or 1
    base = out.absolute().parent
    base.mkdir(parents=True, exist_ok=True)
    stage = Path(tempfile.mkdtemp(prefix=f".pyrosgen-system-{sysm.name}-", dir=str(base)))
    try:
        outcomes: list[NodeOutcome] = []
        todo: list[tuple[NodeOutcome, object]] = []
        if use_cache:
            cache = Path(cache) if cache is not None else default_cache()
            try:
                cache.mkdir(parents=True, exist_ok=True)
            except OSError as exc:
                raise UserError(f"cannot create the cache folder {cache}: {exc.strerror or exc}") from None
            _clean_dead_temps(cache)
        keys: dict[str, str] = {}
        for sn in sysm.nodes:
            key = node_key(sn)
            oc = NodeOutcome(sn.folder, sn.model.name, key, False)
            outcomes.append(oc)
            if use_cache and entry_valid(cache / key, key):
                oc.cached = True
                continue
            if use_cache and key in keys:
                continue        # the same node under another name: proved once
            keys[key] = sn.folder
            todo.append((oc, sn))
        say(f"system {sysm.name}: {len(outcomes)} nodes, {len(outcomes) - len(todo)} from the cache, "
            f"{len(todo)} to prove ({min(jobs, max(len(todo), 1))} in parallel)")
        failures: list[str] = []
        code = 0
        if todo:
            with ProcessPoolExecutor(max_workers=min(jobs, len(todo))) as pool:
                futs = []
                for oc, sn in todo:
                    if use_cache:
                        futs.append(pool.submit(_gen_cached, str(sn.model_path), str(cache), oc.key))
                    else:
                        futs.append(pool.submit(_gen_node, str(sn.model_path), str(stage / sn.folder)))
                for (oc, sn), fut in zip(todo, futs):
                    status, secs, ec, lines = fut.result()
                    oc.seconds = secs
                    if status != "ok":
                        code = max(code, ec)
                        failures.append(f"pyrosgen: node {sn.full_name} ({sn.model_path}):")
                        failures.extend("  " + ln for ln in lines)
                    else:
                        say(f"  {sn.full_name}: proved in {secs:.1f} s")
        if failures:
            raise SystemNodeFailure(failures, code or 2)
        if use_cache:
            for oc in outcomes:
                entry = cache / oc.key
                if not entry_valid(entry, oc.key):
                    raise ToolFailure(f"the cache entry of {oc.folder} ({entry}) is not valid after its generation")
                shutil.copytree(entry / "files", stage / oc.folder)
                if oc.cached:
                    say(f"  {oc.folder}: from the cache ({oc.key[:16]})")
        files = system_files(sysm, graph, stage)
        _install(stage, out, [oc.folder for oc in outcomes] + files)
    finally:
        shutil.rmtree(stage, ignore_errors=True)
    return SystemGenerateResult(out, outcomes, files, time.monotonic() - t0)


def _install(stage: Path, out: Path, names: list[str]) -> None:
    """Move the staged entries ``names`` into ``out`` (each replaced as a
    whole: a node folder from an earlier run is not mixed with this one's)."""
    created = not out.exists()
    out.mkdir(parents=True, exist_ok=True)
    with locked_folder(out):
        for n in names:
            src, dst = stage / n, out / n
            if dst.is_symlink() or (dst.exists() and not (dst.is_dir() if src.is_dir() else dst.is_file())):
                if created:
                    shutil.rmtree(out, ignore_errors=True)
                raise UserError(f"{dst}: exists and is not a {'folder' if src.is_dir() else 'file'}; "
                                "not replaced")
        old = stage / ".old"
        old.mkdir()
        for n in names:
            src, dst = stage / n, out / n
            if dst.exists():
                os.rename(dst, old / n)
            os.rename(src, dst)

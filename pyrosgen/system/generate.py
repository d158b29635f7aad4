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

A node is proved into the run's staging area (``.pending/<key>``) without
its ``coqchk``; the modules of every node proved in the run are re-checked
by one ``coqchk`` (:meth:`~pyrosgen.proof.coqdriver.CoqDriver.coqchk_many`,
which loads the library once), and only then are their entries written.

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
    #: whether the system's proof came from the cache
    proof_cached: bool = False

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


def node_key(sn, target: str = "ros1") -> str:
    """The cache key of system node ``sn`` (its model loaded) for
    ``target`` (rule 4.17): the target is part of the key, so that a ROS 1
    and a ROS 2 run never share an entry (the same model file gives two
    different nodes: other message structs, another wrapper)."""
    m = sn.model
    h = hashlib.sha256()
    h.update(b"pyrosgen-system-node-1\0")
    h.update(b"target\0" + target.encode() + b"\0")
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
        present = sorted(p.relative_to(entry).as_posix() for p in entry.rglob("*") if p.is_file()
                         and p.relative_to(entry).as_posix() not in (ENTRY, ".lock"))
        if present != sorted(files):
            return False
        return all(not (entry / n).is_symlink() and _sha_file(entry / n) == d for n, d in files.items())
    except (OSError, ValueError, KeyError, TypeError, AttributeError):
        return False


def _pid_runs(name: str) -> bool:
    """Whether the process whose pid a temporary folder's name holds
    (``.tmp-<pid>-...``) still runs; ``True`` when the name holds none."""
    parts = name.split("-")
    if len(parts) < 3 or not parts[1].isdigit():
        return True
    try:
        os.kill(int(parts[1]), 0)
    except ProcessLookupError:
        return False
    except OSError:
        return True             # it runs, as another user
    return True


def _clean_dead_temps(cache: Path) -> None:
    """Remove the temporary folders of runs that are gone: each worker
    holds an exclusive ``flock`` on its folder's ``.lock`` while it works
    (the kernel releases it when the process dies, however it dies), so a
    folder whose lock can be taken belongs to nobody.  A folder without a
    lock (its worker killed between its creation and the lock's) is removed
    when the worker named in it (``.tmp-<pid>-...``) no longer runs, else
    once it is ten minutes old."""
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
                if not _pid_runs(n) or time.time() - folder.stat().st_mtime > 600:
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


def _generate(model_path: str, out: str, *, target: str, progress, defer_coqchk: bool):
    """``pyrosgen generate`` (``target`` ``"ros2"``: ``generate --ros2``,
    the model read with ROS 2's message definitions) with its work
    directory kept."""
    from pyrosgen.generate import generate

    if target != "ros2":
        return generate(model_path, out, keep_work=True, progress=progress, defer_coqchk=defer_coqchk)
    from pyrosgen.generate import generate_model
    from pyrosgen.ros2.env import find_ros2
    from pyrosgen.ros2.frontend import load_model_ros2

    inst = find_ros2()
    return generate_model(load_model_ros2(model_path, inst), out, progress=progress, keep_work=True,
                          defer_coqchk=defer_coqchk, msg_root=inst.share_dir, target="ros2")


def _gen_node(model_path: str, tmp: Path, defer_coqchk: bool = False,
              target: str = "ros1") -> tuple[str, float, int, list[str]]:
    """Worker: the node pipeline into ``tmp/files`` (its output folder)
    and the compiled per-node module into ``tmp/coq/<node>.vo`` (for the
    system's proof).  Returns (status, seconds, exit code, report
    lines); never raises.  ``defer_coqchk``: the module is not re-checked
    here (:func:`_check_pending` does it for every node of the run at
    once, before anything is trusted)."""
    from pyrosgen.errors import Context

    t0 = time.monotonic()
    lines: list[str] = []
    try:
        res = _generate(model_path, str(tmp / "files"), target=target, progress=lines.append,
                        defer_coqchk=defer_coqchk)
        kept = [ln.split(": ", 1)[1] for ln in lines if ln.startswith("work directory kept: ")]
        if len(kept) != 1:
            return ("error", time.monotonic() - t0, 2, ["pyrosgen: error: the node's work directory was not kept"])
        work = Path(kept[0])
        try:
            (tmp / "coq").mkdir()
            shutil.copyfile(work / "coq" / f"{res.model.name}.vo", tmp / "coq" / f"{res.model.name}.vo")
        finally:
            shutil.rmtree(work, ignore_errors=True)
        return ("ok", time.monotonic() - t0, 0, [])
    except PyrosgenError as exc:
        return ("error", time.monotonic() - t0, exc.exit_code, exc.report(Context()))
    except Exception as exc:  # noqa: BLE001 - reported, never a traceback
        return ("error", time.monotonic() - t0, 2, [f"pyrosgen: internal error: {type(exc).__name__}: {exc}"])


def _build_node(model_path: str, controller: str | None, tmp: Path,
                target: str = "ros1") -> tuple[str, float, int, list[str]]:
    """Worker: ``pyrosgen build`` of the node into ``tmp/files`` (the
    node's build folder: binary, catkin package, certificate; ``target``
    ``"ros2"``: ``build --ros2``, a node over rcl and its ament_cmake
    package) and its compiled per-node module into ``tmp/coq/<node>.vo``."""
    from pyrosgen.errors import Context

    t0 = time.monotonic()
    lines: list[str] = []
    kept: list[Path] = []
    try:
        if target == "ros2":
            from pyrosgen.ros2.build import build_ros2 as build
        else:
            from pyrosgen.ros.build import build
        res = build(model_path, controller, str(tmp / "files"), keep_work=True, progress=lines.append)
        kept = [Path(ln.split("work directory kept: ", 1)[1].strip()) for ln in lines if "work directory kept: " in ln]
        name = res.model.name if hasattr(res, "model") else Path(model_path).stem
        vos = [k / "coq" / f"{name}.vo" for k in kept if (k / "coq" / f"{name}.vo").is_file()]
        if len(vos) != 1:
            return ("error", time.monotonic() - t0, 2, ["pyrosgen: error: the node's compiled module was not kept"])
        (tmp / "coq").mkdir()
        shutil.copyfile(vos[0], tmp / "coq" / f"{name}.vo")
        return ("ok", time.monotonic() - t0, 0, [])
    except PyrosgenError as exc:
        return ("error", time.monotonic() - t0, exc.exit_code, exc.report(Context()))
    except Exception as exc:  # noqa: BLE001 - reported, never a traceback
        return ("error", time.monotonic() - t0, 2, [f"pyrosgen: internal error: {type(exc).__name__}: {exc}"])
    finally:
        for k in kept:
            shutil.rmtree(k, ignore_errors=True)


def _build_entry(model_path: str, controller: str | None, parent: str, key: str,
                 target: str = "ros1") -> tuple[str, float, int, list[str]]:
    """Worker: the node's build entry ``key`` of ``parent``."""
    return _put_entry(Path(parent), key, lambda tmp: _build_node(model_path, controller, tmp, target))


def _listing(root: Path) -> dict[str, str]:
    return {p.relative_to(root).as_posix(): _sha_file(p) for p in sorted(root.rglob("*"))
            if p.is_file() and p.relative_to(root).as_posix() not in (ENTRY, ".lock")}


def _put_entry(parent: Path, key: str, fill) -> tuple[str, float, int, list[str]]:
    """Write entry ``key`` of ``parent`` (a cache, or the run's staging
    folder): ``fill(tmp)`` writes the entry's files into a temporary
    folder, locked while it works, which gets ``entry.json`` (each file's
    digest, and the digest of that list) and is renamed into place only
    when complete.  ``fill`` returns (status, seconds, exit code, report
    lines); nothing is installed unless the status is ``ok``."""
    import fcntl

    tmp = Path(tempfile.mkdtemp(prefix=f".tmp-{os.getpid()}-", dir=str(parent)))
    lock = os.open(tmp / ".lock", os.O_RDWR | os.O_CREAT, 0o600)
    fcntl.flock(lock, fcntl.LOCK_EX)
    try:
        status = fill(tmp)
        if status[0] != "ok":
            return status
        files = _listing(tmp)
        meta = {"format": 1, "key": key, "files": files, "digest": _entry_digest(files)}
        with open(tmp / ENTRY, "w", encoding="utf-8") as fh:
            json.dump(meta, fh, indent=1, sort_keys=True)
            fh.flush()
            os.fsync(fh.fileno())
        target = Path(parent) / key
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


def _gen_pending(model_path: str, folder: str, target: str = "ros1") -> tuple[str, float, int, list[str]]:
    """Worker: the node into ``folder`` (``files/``, ``coq/``), a folder of
    the run's staging area, its module not yet re-checked by ``coqchk``."""
    Path(folder).mkdir()
    return _gen_node(model_path, Path(folder), defer_coqchk=True, target=target)


def _check_pending(pending: Path, proved: list[tuple[str, str]], work: Path) -> None:
    """``coqchk`` of every node proved in this run (``proved``: (key,
    node name), their folders in ``pending``) in one process, which loads
    the library once (one per node loads it again for each: 1.1 s of CPU
    every time, BENCHMARKS.md section 14); the same check as ``pyrosgen
    generate``'s (``-norec``, the bytecode machine, the context summary),
    done before any of them enters the cache or ``OUT``.  Raises
    :class:`~pyrosgen.proof.coqdriver.CoqError` naming the module
    rejected."""
    from pyrosgen.proof.coqdriver import CoqDriver

    # one batch per folder of distinct module names (a node model run with
    # two controller folders has two keys and one name)
    batches: list[dict[str, str]] = []
    for key, name in proved:
        batch = next((b for b in batches if name not in b), None)
        if batch is None:
            batches.append(batch := {})
        batch[name] = key
    drv = CoqDriver()
    drv.check_tools()
    for i, batch in enumerate(batches):
        folder = work / str(i)
        folder.mkdir(parents=True)
        for name, key in batch.items():
            shutil.copyfile(pending / key / "coq" / f"{name}.vo", folder / f"{name}.vo")
        drv.coqchk_many([f"RosgenNode.{name}" for name in batch], (folder, "RosgenNode"))


def _system_key(vo_files: dict[str, Path], vtext: str) -> str:
    """The cache key of the system's proof: what it depends on, the
    environment (library, tools, pyrosgen), the nodes' compiled modules
    (name and SHA-256 of each ``.vo``: ``coqc`` writes the same bytes for
    the same ``.v``, so a node proved again to the same module, after a
    comment in its model, leaves the system's proof a cache hit) and the
    system's ``.v``."""
    h = hashlib.sha256()
    h.update(b"pyrosgen-system-proof-2\0" + _environment_digest().encode() + b"\0")
    for name, vo in sorted(vo_files.items()):
        h.update(name.encode() + b"\0" + _sha_file(vo).encode() + b"\0")
    h.update(vtext.encode())
    return h.hexdigest()


def generate_system(system_path: str | Path, out_dir: str | Path, *, jobs: int | None = None,
                    cache: Path | None = None, use_cache: bool = True, progress=None,
                    build: bool = False, target: str = "ros1") -> SystemGenerateResult:
    """Check the system, generate every node (``jobs`` processes, default
    the number of cores), write the system's files, install into
    ``out_dir``.  With ``build``, each node is built as ``pyrosgen
    build`` does (its folder holds its binary and its catkin package), and
    ``OUT/src/`` is a catkin workspace's source folder linking every
    node's package.  ``target``: ``"ros1"`` or ``"ros2"`` (``--ros2``,
    rule 4.17): every node read, generated and built for it; for ROS 2
    each node's folder is ``build --ros2``'s (a node over rcl, an
    ament_cmake package) and the launch file is in ROS 2's XML launch
    format."""
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
    sysm = load_system(system_path, target)
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
            entries = cache
        else:
            entries = stage / ".nodes"
            entries.mkdir()
        keys: dict[str, str] = {}
        for sn in sysm.nodes:
            key = node_key(sn, target) if not build else hashlib.sha256(
                ("pyrosgen-system-build-1\0" + node_key(sn, target)).encode()).hexdigest()
            oc = NodeOutcome(sn.folder, sn.model.name, key, False)
            outcomes.append(oc)
            if use_cache and entry_valid(cache / key, key):
                oc.cached = True
                continue
            if key in keys:
                continue        # the same node under another name: proved once
            keys[key] = sn.folder
            todo.append((oc, sn))
        verb = "build" if build else "prove"
        say(f"system {sysm.name}: {len(outcomes)} nodes, {len(outcomes) - len(todo)} from the cache, "
            f"{len(todo)} to {verb} ({min(jobs, max(len(todo), 1))} in parallel)")
        _run_nodes(todo, entries, stage, jobs, build, say, target)
        vo_files: dict[str, Path] = {}
        for oc in outcomes:
            entry = entries / oc.key
            if not entry_valid(entry, oc.key):
                raise ToolFailure(f"the entry of node {oc.folder} ({entry}) is not valid after its generation")
            shutil.copytree(entry / "files", stage / oc.folder)
            vo_files[oc.name] = entry / "coq" / f"{oc.name}.vo"
            if oc.cached:
                say(f"  {oc.folder}: from the cache ({oc.key[:16]})")
        # the system's theorem: every link, from the nodes' T2
        from pyrosgen.system.coqsystem import prove_system, render_system_file, system_v_name

        vname = system_v_name(sysm.name)
        vtext = render_system_file(sysm, graph)
        skey = _system_key(vo_files, vtext)
        proof_cached = use_cache and entry_valid(cache / skey, skey)
        if proof_cached:
            say(f"  system proof: from the cache ({skey[:16]})")
        else:
            say(f"  system proof: {len(graph.links)} links from the nodes' T2 ...")

            def fill(tmp: Path):
                t1 = time.monotonic()
                text, _ = prove_system(sysm, graph, vo_files, tmp / "work")
                shutil.rmtree(tmp / "work")
                (tmp / "files").mkdir()
                (tmp / "files" / vname).write_text(text, encoding="ascii")
                return ("ok", time.monotonic() - t1, 0, [])

            _put_entry(entries, skey, fill)
        if not entry_valid(entries / skey, skey):
            raise ToolFailure(f"the entry of the system's proof ({entries / skey}) is not valid")
        shutil.copyfile(entries / skey / "files" / vname, stage / vname)
        files = [vname] + system_files(sysm, graph, stage)
        if build:
            files += _workspace(sysm, outcomes, stage)
        _install(stage, out, [oc.folder for oc in outcomes] + files)
    finally:
        shutil.rmtree(stage, ignore_errors=True)
    return SystemGenerateResult(out, outcomes, files, time.monotonic() - t0, proof_cached)


def _run_nodes(todo: list, entries: Path, stage: Path, jobs: int, build: bool, say, target: str = "ros1") -> None:
    """Prove (or build) the nodes of ``todo`` in ``jobs`` processes; a
    proved node's module is re-checked by one ``coqchk`` for all of them
    (:func:`_check_pending`) before its entry is written into ``entries``;
    a built node writes its own (``pyrosgen build`` checks its module).
    Raises :class:`SystemNodeFailure` naming every node that failed."""
    failures: list[str] = []
    code = 0
    pending = stage / ".pending"
    pending.mkdir()
    if not todo:
        return
    with ProcessPoolExecutor(max_workers=min(jobs, len(todo))) as pool:
        futs = [pool.submit(_gen_pending, str(sn.model_path), str(pending / oc.key), target) if not build else
                pool.submit(_build_entry, str(sn.model_path), str(sn.controller) if sn.controller else None,
                            str(entries), oc.key, target)
                for oc, sn in todo]
        for (oc, sn), fut in zip(todo, futs):
            status, secs, ec, lines = fut.result()
            oc.seconds = secs
            if status != "ok":
                code = max(code, ec)
                failures.append(f"pyrosgen: node {sn.full_name} ({sn.model_path}):")
                failures.extend("  " + ln for ln in lines)
            else:
                say(f"  {sn.full_name}: {'built' if build else 'proved'} in {secs:.1f} s")
    if failures:
        raise SystemNodeFailure(failures, code or 2)
    if not build:
        say(f"  coqchk: the {len(todo)} new node module(s) in one run")
        _check_pending(pending, [(oc.key, oc.name) for oc, _ in todo], stage / ".check")
        for oc, _ in todo:
            _put_entry(entries, oc.key, lambda tmp, src=pending / oc.key: _copy_into(src, tmp))


def _workspace(sysm, outcomes: list, stage: Path) -> list[str]:
    """``stage/src``, a catkin workspace's source folder: one link per node
    package, and one per custom message package (``msgs/<pkg>``, shared by
    the nodes, rule 10.10); for ROS 2 a colcon workspace's, each custom
    message package the interface package ``build --ros2`` wrote into the
    first node's folder that has it.  Returns the names to install."""
    src = stage / "src"
    src.mkdir()
    for oc in outcomes:
        pkg = stage / oc.folder / oc.name
        if pkg.is_dir() and not (src / oc.name).exists():
            os.symlink(Path("..") / oc.folder / oc.name, src / oc.name)
    if sysm.target == "ros2":
        # build --ros2 wrote each node's custom message packages as interface
        # packages in its folder (and compiled them there for the node); the
        # definitions agree (rule 10.10): src/ links the first node's
        from pyrosgen.ros2.rosidl import custom_packages

        for sn, oc in zip(sysm.nodes, outcomes):
            for pkg in custom_packages(sn.model):
                if not (src / pkg).exists():
                    os.symlink(Path("..") / oc.folder / pkg, src / pkg)
        return ["src"]
    msg_pkgs = _write_message_packages(sysm, stage / "msgs")
    for pkg in msg_pkgs:
        os.symlink(Path("..") / "msgs" / pkg, src / pkg)
    return (["msgs"] if msg_pkgs else []) + ["src"]


def _copy_into(src: Path, tmp: Path) -> tuple[str, float, int, list[str]]:
    """Fill an entry's temporary folder with the checked node folder
    ``src`` (``files/``, ``coq/``)."""
    for part in ("files", "coq"):
        shutil.copytree(src / part, tmp / part)
    return ("ok", 0.0, 0, [])


def _write_message_packages(sysm, folder: Path) -> list[str]:
    """The system's custom message packages (each node's ``msg_paths``,
    rule 10.10: one definition of each type), each a catkin package
    ``folder/<pkg>/`` (``message_generation``, as ROS 1 builds messages:
    ``package.xml``, ``CMakeLists.txt``, ``msg/*.msg``) that the nodes'
    packages depend on; two nodes sharing a package share this one.
    Returns the package names."""
    from pyrosgen.ros.wrapper import render_msg_package
    from pyrosgen.system.checks import custom_message_packages

    packages = custom_message_packages(sysm)
    for pkg, files in sorted(packages.items()):
        texts = {name: f.read_text(encoding="utf-8", errors="replace") for name, (_, f) in sorted(files.items())}
        (folder / pkg / "msg").mkdir(parents=True)
        for rel, text in render_msg_package(sysm.source.name, pkg, texts).items():
            (folder / pkg / rel).write_text(text, encoding="utf-8")
        for name, (_, f) in sorted(files.items()):
            shutil.copyfile(f, folder / pkg / "msg" / name)
    return sorted(packages)


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

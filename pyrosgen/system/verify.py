"""``pyrosgen system verify OUT --system SYSTEM.yaml``: re-check a system's
output folder against its system file (DESIGN.md section 10).

1. The system's own files (``<system>_system.v``, ``.certificate.md``,
   ``.system.json``, ``.launch``) are rendered again from the system file
   and the node folders, and must equal OUT's byte for byte: the ``.v`` is
   then exactly the template's, so compiling it runs nothing else.
2. Each node folder is re-checked as ``pyrosgen verify FOLDER --model
   MODEL`` does (in parallel processes), its ``.v`` held byte for byte to
   the one generated from the node model.
3. The nodes' ``.v`` (now known to be the template's) are compiled again,
   and the system's ``.v`` against them: every link and chain proved,
   ``Print Assumptions`` closed, ``coqchk``.

Exit 0 only when every check holds; 1 when one fails (each is named).
"""

from __future__ import annotations

import shutil
import tempfile
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path

from pyrosgen.errors import PyrosgenError, UserError

__all__ = ["SystemVerifyFailed", "SystemVerifyReport", "verify_system"]

#: Largest system file of OUT read back (the certificate of 256 nodes and
#: 1,000 chains is far below).
MAX_SYSTEM_FILE = 16 * 1024 * 1024


@dataclass
class SystemVerifyReport:
    folder: Path
    system: str
    checks: list[tuple[str, bool, str]] = field(default_factory=list)
    seconds: float = 0.0

    @property
    def ok(self) -> bool:
        return bool(self.checks) and all(ok for _, ok, _ in self.checks)

    def lines(self) -> list[str]:
        return [f"  {'ok  ' if ok else 'FAIL'}    {name}: {text}" for name, ok, text in self.checks]


class SystemVerifyFailed(UserError):
    """At least one check failed (exit 1)."""

    def __init__(self, report: SystemVerifyReport):
        self.verify_report = report
        failed = [n for n, ok, _ in report.checks if not ok]
        super().__init__(f"{report.folder}: {len(failed)} of {len(report.checks)} checks failed: {', '.join(failed)}")

    def report(self, ctx) -> list[str]:
        return [f"pyrosgen: {self.verify_report.folder} does NOT verify (system {self.verify_report.system})",
                *self.verify_report.lines()]


def _read(path: Path) -> bytes | None:
    try:
        if path.is_symlink() or not path.is_file() or path.stat().st_size > MAX_SYSTEM_FILE:
            return None
        return path.read_bytes()
    except OSError:
        return None


def _verify_node(folder: str, model: str) -> tuple[bool, str]:
    """Worker: ``pyrosgen verify folder --model model``."""
    from pyrosgen.verify.recheck import verify_folder

    try:
        rep = verify_folder(folder, model=model)
        return (rep.ok, f"{len(rep.checks)} checks hold ({rep.seconds:.1f} s)")
    except PyrosgenError as exc:
        text = " ".join(str(exc).split())
        return (False, text[:500])
    except Exception as exc:  # noqa: BLE001 - reported, never a traceback
        return (False, f"internal error: {type(exc).__name__}: {exc}")


def _compile_node(vfile: str, work: str) -> tuple[bool, str]:
    """Worker: ``coqc`` of a node's ``.v`` (already held to the template)."""
    from pyrosgen.proof.coqdriver import CoqDriver

    try:
        w = Path(work)
        w.mkdir(parents=True)
        shutil.copyfile(vfile, w / Path(vfile).name)
        drv = CoqDriver()
        drv.coqc(w / Path(vfile).name, (w, "RosgenNode"))
        return (True, "")
    except PyrosgenError as exc:
        return (False, " ".join(str(exc).split())[:500])


def _check_target(out: Path, sysm, rep: SystemVerifyReport) -> None:
    """The target ``OUT``'s graph records (``<system>.system.json``) is the
    one verified for (``--ros2``); a folder of the other target is named
    as such rather than only failing the comparisons below."""
    import json

    data = _read(out / f"{sysm.name}.system.json")
    try:
        got = json.loads(data)["target"] if data is not None else None
    except (ValueError, KeyError, TypeError):
        got = None
    if got in ("ros1", "ros2") and got != sysm.target:
        hint = "verify it with --ros2" if got == "ros2" else "verify it without --ros2"
        rep.checks.append(("target", False, f"{out} was generated for the target {got}, not {sysm.target}: {hint}"))


def verify_system(out: str | Path, system_path: str | Path, *, jobs: int | None = None,
                  progress=None, target: str = "ros1") -> SystemVerifyReport:
    import os

    from pyrosgen.system.certificate import rendered_files
    from pyrosgen.system.checks import check_system
    from pyrosgen.system.coqsystem import prove_system, render_system_file, system_v_name
    from pyrosgen.system.model import load_system

    say = progress or (lambda _l: None)
    t0 = time.monotonic()
    out = Path(out)
    if not out.is_dir() or out.is_symlink():
        raise UserError(f"{out}: not a folder")
    sysm = load_system(system_path, target)
    graph = check_system(sysm)
    rep = SystemVerifyReport(out, sysm.name)
    jobs = jobs or os.cpu_count() or 1

    # 1. the system's own files, rendered again
    vname = system_v_name(sysm.name)
    expected = {vname: render_system_file(sysm, graph).encode("ascii"), **rendered_files(sysm, graph, out)}
    _check_target(out, sysm, rep)
    for name, data in expected.items():
        got = _read(out / name)
        rep.checks.append((name, got == data, "as rendered from the system file" if got == data else
                           ("missing, a link or not a regular file" if got is None else "differs from the one "
                            "rendered from the system file and the node folders")))
    say(f"system files: {sum(ok for _, ok, _ in rep.checks)} of {len(expected)} as rendered")

    # 2. each node folder, as `pyrosgen verify FOLDER --model MODEL`
    distinct = {}
    for sn in sysm.nodes:
        distinct.setdefault(sn.folder, sn)
    with ProcessPoolExecutor(max_workers=min(jobs, len(distinct))) as pool:
        futs = {f: pool.submit(_verify_node, str(out / f), str(sn.model_path)) for f, sn in distinct.items()}
        for f, fut in futs.items():
            ok, text = fut.result()
            rep.checks.append((f"node {f}", ok, text))
            say(f"node {f}: {'ok' if ok else 'FAILED'}")

    # 3. the system's proof, against the nodes' modules compiled again
    if rep.ok:
        work = Path(tempfile.mkdtemp(prefix=f"pyrosgen-system-verify-{sysm.name}-"))
        try:
            by_name = {sn.model.name: sn for sn in sysm.nodes}
            with ProcessPoolExecutor(max_workers=min(jobs, len(by_name))) as pool:
                futs = {n: pool.submit(_compile_node, str(out / sn.folder / f"{n}.v"), str(work / "nodes" / n))
                        for n, sn in by_name.items()}
                results = {n: fut.result() for n, fut in futs.items()}
            bad = [f"{n}: {t}" for n, (ok, t) in results.items() if not ok]
            if bad:
                rep.checks.append(("system proof", False, "; ".join(bad)))
            else:
                vo = {n: work / "nodes" / n / f"{n}.vo" for n in by_name}
                try:
                    _, thms = prove_system(sysm, graph, vo, work / "system")
                    rep.checks.append(("system proof", True, f"{len(thms)} theorems ({', '.join(thms[:3])}"
                                       f"{', ...' if len(thms) > 3 else ''}): Closed under the global context; "
                                       "coqchk OK"))
                except PyrosgenError as exc:
                    rep.checks.append(("system proof", False, " ".join(str(exc).split())[:500]))
        finally:
            shutil.rmtree(work, ignore_errors=True)
    else:
        rep.checks.append(("system proof", False, "not run: a check above failed"))
    rep.seconds = time.monotonic() - t0
    if not rep.ok:
        raise SystemVerifyFailed(rep)
    return rep

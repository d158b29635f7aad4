"""``pyrosgen verify OUT``: re-check an output folder on its own.

For a reviewer who receives an output folder of ``pyrosgen generate`` or
``build`` and trusts neither the machine that produced it nor its
certificate.  The folder is hostile input: every file is read through
:func:`pyrosgen.verify.folder.read_file` (a plain relative name, a regular
file, no link on the way, bounded size), the manifest is validated field
by field (:func:`pyrosgen.verify.certificate.read_manifest`), everything
verify writes is in its temporary folder under names it checked, and every
tool runs with a timeout and an address-space limit.  The checks, from the folder's manifest
(``<node>.manifest.json``, :mod:`pyrosgen.verify.certificate`):

1. **hashes**: every file the manifest covers is present and has its
   recorded SHA-256; the digest file ``<node>.sha256`` says the same;
2. **library**: the installed ROSGen library has the recorded identity
   (its sources' digest), since the ``.v`` recomputes ``generate model``
   against the library when it is checked;
3. **v-file**: the ``.v`` is the template's with only literal bodies free
   (:mod:`pyrosgen.verify.vfile`), and with ``--model`` the one ``generate``
   renders from that model, byte for byte; nothing compiles a ``.v``
   refused here;
4. **coqc**: the folder's ``.v`` is compiled afresh (in a temporary
   folder; the output folder is never written), every theorem prints
   "Closed under the global context", Coq confirms each theorem's
   statement and that their conjunction is closed
   (:meth:`CoqDriver.confirm_theorems`), and ``coqchk`` re-checks the
   compiled file and lists no axiom (while step 5 prints: a module it
   rejects fails both checks);
5. **re-print**: the C header, the glue, the AST dump and the model text
   are printed again from the freshly checked term and must equal the
   folder's files byte for byte; the printed C is validated against the
   dump (pycparser);
6. **certificate**: the folder's certificate is the one rendered from the
   texts the proof printed and the manifest (its relations' and
   constants' C lines are in the printed C, its digests the recorded ones);
7. **model** (with ``--model MODEL.yaml``): the model text Coq printed is
   the front end's reading of that file; of a ROS 2 build, the QoS record
   ``<node>.qos`` is that file's QoS (rule 4.18), read by both readings;
8. **wrapper** (a ``build`` folder): the C++ wrapper registers exactly the
   proved topics, types and queue sizes and sleeps with the proved period;
9. **WP** (with ``--wp``): Frama-C WP proves the folder's ACSL contracts
   file on the folder's C, every goal; with ``--model`` too, the contracts
   file must be the one generated from that model (without it, only its
   digest vouches that the contracts were not weakened);
10. **rebuild** (with ``--rebuild``, a ``build`` folder): the binary is
    compiled again from the folder's files with the recorded commands
    (checked word by word first) and equals ``bin/<node>`` bit for bit
    (:func:`_check_rebuild`).

Each check reports ``ok`` or ``FAILED`` with its reasons; a failed check
does not stop the others.  Exit status: 0 when every check holds, 1 when
one failed (or OUT is not an output folder), 2 when a tool is missing.
"""

from __future__ import annotations

import contextlib
import hashlib
import re
import shutil
import subprocess
import tempfile
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path, PurePosixPath

from pyrosgen.errors import PyrosgenError, UserError
from pyrosgen.procs import DEFAULT_MAX_MEMORY
from pyrosgen.proof.coqdriver import CLOSED, CoqDriver, CoqError
from pyrosgen.proof.coqmodel import coq_target, node_file_names
from pyrosgen.proof.modeltext import ModelMismatch, compare_model_texts, model_text
from pyrosgen.verify.certificate import (MANIFEST_MAX_BYTES, ManifestError, ProofRecord, certificate_files,
                                         read_manifest)
from pyrosgen.verify.folder import UnsafeFile, check_name, read_file, read_text
from pyrosgen.verify.check import Check
from pyrosgen.verify.package_check import check_package, check_qos_of_model, is_build_folder
from pyrosgen.nversion.check import check_model_file

#: The default limit of each tool run of ``verify`` (``--timeout``), in
#: seconds: LandShark's coqc takes 2 s, the largest model of BENCHMARKS.md
#: (two controller arrays of 8,192 elements) about 30 s.
DEFAULT_TIMEOUT = 600.0

__all__ = ["DEFAULT_TIMEOUT", "Check", "VerifyReport", "NotAnOutputFolder", "VerifyFailed", "verify_folder",
           "find_manifest"]


class NotAnOutputFolder(UserError):
    """OUT has no (single, readable) pyrosgen manifest."""


class VerifyFailed(UserError):
    """At least one check failed (exit code 1; the report names them)."""

    def __init__(self, report: "VerifyReport"):
        self.verify_report = report
        failed = [c.name for c in report.checks if not c.ok]
        super().__init__(f"{report.folder}: {len(failed)} of {len(report.checks)} checks failed: "
                         f"{', '.join(failed)}")


@dataclass
class VerifyReport:
    folder: Path
    node: str
    checks: list[Check] = field(default_factory=list)
    seconds: float = 0.0

    @property
    def ok(self) -> bool:
        return bool(self.checks) and all(c.ok for c in self.checks)


def find_manifest(folder: Path, node: str | None = None) -> Path:
    """The manifest of ``node`` in ``folder``, or its only manifest."""
    if not folder.is_dir():
        raise NotAnOutputFolder(f"{folder}: not a directory")
    if node is not None:
        if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", node):
            raise NotAnOutputFolder(f"--node {node!r}: not a node name (a C identifier)")
        p = folder / certificate_files(node)[1]
        if not p.is_file():
            raise NotAnOutputFolder(f"{folder}: no manifest {p.name} (is {node!r} the node's name?)")
        return p
    found = sorted(folder.glob("*.manifest.json"))
    if not found:
        raise NotAnOutputFolder(f"{folder}: no *.manifest.json: not an output folder of pyrosgen generate or "
                                "build (or one made before version 0.1.0 wrote manifests)")
    if len(found) > 1:
        names = ", ".join(p.name.removesuffix(".manifest.json") for p in found)
        raise NotAnOutputFolder(f"{folder}: several nodes ({names}); choose one with --node")
    return found[0]


def _inside(work: Path, name: str) -> Path:
    """``work/name`` for a name checked by :func:`folder.check_name`,
    asserted to stay inside ``work`` (nothing verify writes leaves its
    temporary folder)."""
    p = work / check_name(name)
    if not p.resolve().is_relative_to(work.resolve()):
        raise UnsafeFile(f"{name}: leaves the temporary folder")  # pragma: no cover - check_name prevents it
    return p


def _digest(folder: Path, name: str) -> str | None:
    """The SHA-256 of the folder's file ``name`` read through
    :func:`folder.read_file` (``None`` if it is missing)."""
    try:
        return hashlib.sha256(read_file(folder, name)).hexdigest()
    except FileNotFoundError:
        return None


def _check_hashes(folder: Path, rec: ProofRecord, files: dict[str, str]) -> Check:
    bad = []
    for name, digest in sorted(files.items()):
        have = _digest(folder, name)
        if have is None:
            bad.append(f"  {name}: missing")
        elif have != digest:
            bad.append(f"  {name}: SHA-256 {have}, recorded {digest}")
    sums = certificate_files(rec.node)[2]
    try:
        lines = read_text(folder, sums, limit=MANIFEST_MAX_BYTES, what="digest file").splitlines()
        listed = dict(reversed(line.split("  ", 1)) for line in lines)
    except (FileNotFoundError, ValueError):
        listed = None
    if listed != files:
        bad.append(f"  {sums}: does not list the manifest's files and digests")
    for needed in (rec.node_v, rec.types_h, rec.glue_c, rec.sexp, rec.model_file):
        if needed not in files:
            bad.append(f"  {needed}: not covered by the manifest")
    if bad:
        return Check("hashes", False, f"{len(bad)} problems", bad)
    return Check("hashes", True, f"{len(files)} files as recorded")


def _check_certificate(folder: Path, rec: ProofRecord, files: dict[str, str], proved_text: str | None,
                       proved_glue: str | None, proved_diagram: str | None) -> Check:
    """The folder's certificate is the one rendered from the texts the
    proof printed (the model text, the glue, the diagram) and the
    manifest's record and digests."""
    from pyrosgen.verify.certificate import CertificateError, render_certificate

    name = certificate_files(rec.node)[0]
    if proved_text is None or proved_glue is None:
        return Check("certificate", False, "not run: no proved model text")
    try:
        want = render_certificate(rec, proved_text, proved_glue, sorted(files.items()),
                                  proved_diagram.rstrip("\n") if proved_diagram is not None else None)
        have = read_text(folder, name, what="certificate")
    except CertificateError as exc:
        return Check("certificate", False, exc.summary, list(exc.lines))
    except FileNotFoundError:
        return Check("certificate", False, f"cannot read {name}: missing")
    if have != want:
        a, b = have.splitlines(), want.splitlines()
        k = next((i for i in range(min(len(a), len(b))) if a[i] != b[i]), min(len(a), len(b)))
        return Check("certificate", False, f"{name} is not the certificate of the proof", [
            f"  line {k + 1}: the folder's {a[k] if k < len(a) else '(nothing)'!r}",
            f"  line {k + 1}: rendered   {b[k] if k < len(b) else '(nothing)'!r}"])
    return Check("certificate", True, f"{name} is the one rendered from the proof and the manifest")


class _NotRun(Exception):
    """A check that is not run (its reason)."""


#: What the statements of :func:`_statements` need.
_CONFIRM_IMPORTS = ("From Coq Require Import String List ZArith.\n"
                    "From ROSGen Require Import Errors Syntax NodeModel Wellformed Generator.\n"
                    "From ROSGen Require Environment DDC Loopproof.\n")
_CONFIRM_IMPORTS_CTRL = "From ROSGen Require Diagram Endtoend Link.\n"


def _statements(rec: ProofRecord) -> list[tuple[str, str]]:
    """Each theorem of the node with its statement in
    ``coq/templates/node.v.j2``, for :meth:`CoqDriver.confirm_theorems`:
    ``generate_ok`` (the printed program is ``generate model``), T2, T4
    and, for a diagram, its well-formedness, T2 with the diagram and T8.
    The names are the node's (:func:`node_file_names`), not the
    manifest's."""
    names = node_file_names(rec.node)
    m = f"RosgenNode.{rec.node}"
    out = [("generate_ok", f"Generator.generate {m}.model = OK {m}.the_program")]
    if rec.ddc:
        out.append((names.theorem_ddc, f"DDC.node_ddc {m}.model {m}.the_program"))
        # the target stated, not the .v's [target]: a .v of another target is refused
        out.append((names.theorem_target,
                    f"DDC.node_ddc_on Environment.{coq_target(rec.target)} {m}.model {m}.the_program"))
    out.append((names.theorem_wf, f"Wellformed.wf {m}.model = true"))
    if rec.controller:
        d = f"{m}.Ctrl.the_diagram"
        out += [(f"Ctrl.{names.theorem_ctrl_wf}", f"Diagram.dg_wf {d} = true"),
                (f"Ctrl.{names.theorem_e2e}", f"Endtoend.diagram_node_ok {m}.model {m}.the_program {d}"),
                (f"Ctrl.{names.theorem_linked}", f"Link.linked_node_ok {m}.model {m}.the_program {d}")]
    return out


#: What ``<node>.target`` of a ROS 2 build says (pyrosgen.ros2.build.TARGET_TEXT).
_ROS2_TARGET = b"target: ros2 (ROS 2 Kilted, rcl, rmw_fastrtps_cpp)\n"


def _target_file_ros2(folder: Path, rec: ProofRecord) -> bool:
    """Whether the folder's ``<node>.target`` says ros2 (a ROS 2 build)."""
    try:
        return read_file(folder, f"{rec.node}.target", limit=4096) == _ROS2_TARGET
    except (FileNotFoundError, UnsafeFile):
        return False


def _load_for_target(folder: Path, rec: ProofRecord, model: str | Path):
    """The front end's reading of ``model`` for the folder's target (rule
    4.17: ROS 2's message definitions when the folder's ``<node>.target``
    or its manifest's ``target`` says ros2, which the hashes cover) and the folder of the target's
    standard ``.msg`` files for the second reading (``None``: ROS 1's)."""
    from pyrosgen.frontend.validate import load_model

    if not (_target_file_ros2(folder, rec) or rec.target == "ros2"):
        return load_model(model), None
    from pyrosgen.ros2.env import find_ros2
    from pyrosgen.ros2.frontend import load_model_ros2

    inst = find_ros2()
    return load_model_ros2(model, inst), inst.share_dir


def _check_vfile(folder: Path, rec: ProofRecord, drv: CoqDriver, model: str | Path | None) -> tuple[Check, str | None]:
    """The folder's ``.v`` is the template's, with only its literal bodies
    free (:func:`vfile.check_structure`), and with ``model`` the one
    ``generate`` renders from it, byte for byte; its text if so (what
    coqc compiles: nothing compiles a ``.v`` refused here)."""
    from pyrosgen.verify.vfile import VFileError, check_rendering, check_structure

    try:
        text = read_text(folder, rec.node_v, what=".v")
    except FileNotFoundError:
        return Check("v-file", False, f"cannot read {rec.node_v}: missing"), None
    except UnsafeFile as exc:
        if "UTF-8" not in str(exc):
            raise
        return Check("v-file", False, f"{rec.node_v} is not the template's .v", [f"  {exc}"]), None
    ddc = drv.ddc_available()
    if rec.ddc != ddc:
        return Check("v-file", False, f"the manifest says ddc={str(rec.ddc).lower()}, but the library "
                     f"{'has' if ddc else 'has not'} the node DDC theorem"), None
    if _target_file_ros2(folder, rec) and rec.target != "ros2":
        return Check("v-file", False, f"{rec.node}.target says ros2, but the manifest's target is "
                                      f"{rec.target}: the .v must name the target ros2"), None
    try:
        n = check_structure(text, rec.node_v, rec.node, ddc_available=ddc, diagram=rec.controller is not None,
                            target=rec.target)
    except VFileError as exc:
        return Check("v-file", False, exc.summary, list(exc.lines)), None
    if model is None:
        return Check("v-file", True, f"the template's .v of node {rec.node} ({n} tokens), "
                                     "literals only in its model"), text
    from pyrosgen.proof.coqmodel import render_node_file

    try:
        loaded, _ = _load_for_target(folder, rec, model)
        diagram = ""
        if loaded.controller.diagram is not None:
            from pyrosgen.proof.coqdiagram import emit_diagram

            diagram = emit_diagram(loaded)
        # line 1 names the model file generate read: the manifest's record of it
        rendered = render_node_file(loaded, ddc_available=ddc, source=rec.source_name, diagram=diagram,
                                    target=rec.target)
        check_rendering(text, rec.node_v, str(model), rendered)
    except VFileError as exc:
        return Check("v-file", False, exc.summary, list(exc.lines)), None
    except PyrosgenError as exc:
        return Check("v-file", False, f"not compared with {Path(model).name}: "
                     f"{getattr(exc, 'summary', str(exc).splitlines()[0])}"), None
    return Check("v-file", True, f"the .v that generate renders from {Path(model).name}, byte for byte"), text


@dataclass
class _Reprint:
    """The re-print check and, when it ran, the texts the proof printed."""

    check: Check
    text: str | None = None      #: the model text
    glue: str | None = None      #: the glue's C
    diagram: str | None = None   #: the diagram text (a diagram controller)


def _reprint(drv: CoqDriver, folder: Path, rec: ProofRecord, module: str, lib: tuple[Path, str],
             work: Path) -> _Reprint:
    """Print the texts of the compiled ``module`` again and compare them
    with the folder's; validate the C against the AST dump."""
    printed = work / "printed"
    printed.mkdir()
    names = [rec.types_h, rec.glue_c, rec.sexp, rec.model_file]
    if rec.controller:
        names += [rec.controller["c"], rec.controller["sexp"], rec.controller["text"]]
    outs = tuple(_inside(printed, n) for n in names)
    texts: dict[str, str | None] = {}
    try:
        try:
            proved = read_file(folder, rec.model_file).decode("utf-8", errors="replace")
        except FileNotFoundError:
            proved = ""
        relations = sum(1 for line in proved.splitlines()
                        if line.startswith(("input_relation ", "output_relation ")))
        drv.print_texts(module, lib, outs, relations=relations)
        differ = []
        for n, p in zip(names, outs):
            try:
                same = read_file(folder, n) == p.read_bytes()
            except FileNotFoundError:
                same = False
            if not same:
                differ.append(f"  {n}: differs from what the proof prints")
        from pyrosgen.verify.printer_validation import validate_glue

        validate_glue(outs[1].read_text(encoding="utf-8"), outs[0].read_text(encoding="utf-8"),
                      outs[2].read_text(encoding="utf-8"), glue_name=rec.glue_c, header_name=rec.types_h)
        texts = dict(text=outs[3].read_text(encoding="utf-8"), glue=outs[1].read_text(encoding="utf-8"),
                     diagram=outs[6].read_text(encoding="utf-8") if rec.controller else None)
        if rec.controller:
            from pyrosgen.verify.printer_validation import validate_program

            validate_program(outs[4].read_text(encoding="utf-8"), outs[5].read_text(encoding="utf-8"),
                             name=rec.controller["c"])
        if differ:
            return _Reprint(Check("re-print", False, f"{len(differ)} files are not the proof's", differ), **texts)
        return _Reprint(Check("re-print", True, f"{len(outs)} files equal to the proof's; C = AST dump (pycparser)"),
                        **texts)
    except CoqError as exc:
        return _Reprint(Check("re-print", False, getattr(exc, "summary", str(exc)), list(getattr(exc, "lines", ()))),
                        **texts)


#: The compilers ``verify --rebuild`` runs: the first word of a recorded
#: command, looked up in ``PATH`` (GCC's, as ``build`` runs them).
_REBUILD_TOOL = re.compile(r"^(gcc|g\+\+|cc|c\+\+)(-[0-9]+)?$")
#: The options of a recorded command that ``verify --rebuild`` passes on;
#: any other word (``-fplugin``, ``-wrapper``, ``-B``, ``-specs``,
#: ``@file``, ``-Wl,--plugin``, an output file outside ``obj/`` and
#: ``bin/``, ...) is refused, so that nothing of the folder's choosing
#: runs a program, loads a plugin or writes outside the temporary folder.
_REBUILD_OPTION = re.compile(
    r"^(-c|-pthread|-pedantic|-std=[a-z0-9+]+|-O[0-3sgz]?|-g[a-z0-9]*|-W(?![lap],)[a-z0-9=+-]+"
    r"|-f(?!plugin|dump|opt-info|module|use-ld|profile|auto-profile|save|callgraph|stack-usage|lto|ltrans"
    r"|[a-z-]*prefix-map)[a-z0-9=+,.-]+"
    r"|-m[a-z0-9=+,.-]+|-[DU][A-Za-z_][A-Za-z0-9_]*(=[A-Za-z0-9_.+-]*)?|-l[A-Za-z0-9_.+-]+|-l:[A-Za-z0-9_.+-]+"
    r"|-Wl,-rpath,/[A-Za-z0-9_./+-]+|-Wl,--(no-)?as-needed|-Wl,--disable-new-dtags|-Wl,-O[0-3])$")
#: An absolute path a recorded command may name (an include or library
#: folder, a library of ``pkg-config --libs``: read by the compiler only).
_REBUILD_ABS = re.compile(r"^/(?!.*/\.\.?(/|$))[A-Za-z0-9_./+-]+$")


def _check_rebuild(folder: Path, rec: ProofRecord, files: dict[str, str], work: Path, timeout: float,
                   max_memory: int | None) -> Check:
    """``verify --rebuild``: the folder's files (those the manifest covers,
    read through :func:`folder.read_file`) copied into ``work``, the
    recorded commands that make ``obj/*.o`` and ``bin/<node>``
    (``build.commands``) checked word by word (:data:`_REBUILD_TOOL`,
    :data:`_REBUILD_OPTION`, :data:`_REBUILD_ABS`, names of the folder),
    run in ``work`` (``-ffile-prefix-map=.=.`` and
    ``-ffile-prefix-map=controller=controller`` naming ``work``'s folders,
    as ``build`` named its staging folder's), and the binary compared with
    the folder's ``bin/<node>`` byte for byte (``build`` is reproducible,
    :func:`pyrosgen.ros.build._reproducible`)."""
    from pyrosgen import procs

    binary = f"bin/{rec.node}"
    cmds = rec.build.get("commands") if isinstance(rec.build, dict) else None
    if binary not in files or not isinstance(cmds, list):
        return Check("rebuild", False, f"not run: the folder has no {binary} and build.commands to rebuild it from")
    cmds = [(k, c) for k, c in enumerate(cmds) if isinstance(c, list) and "-o" in c]
    made: set[str] = set()
    runs: list[list[str]] = []
    folders = {str(d) for f in files for d in PurePosixPath(f).parents}

    def outside(w: str) -> bool:
        """An absolute path, not in the folder (nothing of the folder's is read but by its name)."""
        return bool(_REBUILD_ABS.match(w)) and not Path(w).resolve().is_relative_to(folder.resolve())

    for n, (k, c) in enumerate(cmds):
        bad = None if all(isinstance(w, str) for w in c) and c and _REBUILD_TOOL.match(c[0]) else f"{c[:1]!r}"
        argv, i = [shutil.which(c[0]) or c[0]] if bad is None else [], 1
        while bad is None and i < len(c):
            w, arg = c[i], c[i + 1] if i + 1 < len(c) else ""
            if w == "-o" and (re.fullmatch(r"obj/[A-Za-z0-9_.+-]+\.o", arg) or arg == binary and n == len(cmds) - 1):
                argv += [w, arg]
                made.add(arg)
                i += 2
                continue
            if w in ("-I", "-L", "-isystem", "-iquote") and (outside(arg) or arg in folders):
                argv += [w, arg]
                i += 2
                continue
            if w in ("-ffile-prefix-map=.=.", "-ffile-prefix-map=controller=controller"):
                local = w.split("=")[1]
                argv.append(f"-ffile-prefix-map={(work / local) if local != '.' else work}={local}")
            elif _REBUILD_OPTION.match(w) or outside(w) and w.endswith((".so", ".a")) or (
                    w in made or w in files and not w.startswith(("bin/", "-"))):
                argv.append(w)
            else:
                bad = repr(w)
            i += 1
        if bad is not None:
            return Check("rebuild", False, f"not run: build.commands[{k}] has {bad}, which verify does not run", [
                "  " + " ".join(map(str, c))])
        runs.append(argv)
    if binary not in made:
        return Check("rebuild", False, f"not run: no recorded command links {binary}")
    for name in files:
        if not name.startswith("bin/"):
            dest = _inside(work, name)
            dest.parent.mkdir(parents=True, exist_ok=True)
            dest.write_bytes(read_file(folder, name))
    (work / "obj").mkdir(exist_ok=True)
    (work / "bin").mkdir(exist_ok=True)
    for argv in runs:
        try:
            r = procs.run(argv, cwd=work, timeout=timeout, max_memory=max_memory)
        except OSError as exc:
            return Check("rebuild", False, f"cannot run {argv[0]}: {exc.strerror or exc}")
        except subprocess.TimeoutExpired:
            return Check("rebuild", False, f"{Path(argv[0]).name} did not finish within {timeout:g} s")
        if r.returncode != 0:
            return Check("rebuild", False, f"{Path(argv[0]).name} failed (exit status {r.returncode}) on "
                         f"{argv[argv.index('-o') + 1]}", ["  " + line for line in (r.stderr + r.stdout)
                                                          .replace(str(work), ".").splitlines()[:20]])
    have, want = read_file(folder, binary), _inside(work, binary).read_bytes()
    if have != want:
        at = next((i for i in range(min(len(have), len(want))) if have[i] != want[i]), min(len(have), len(want)))
        return Check("rebuild", False, f"{binary} is not the binary its recorded commands build from the folder's "
                     f"files", [f"  {binary}: {len(have)} bytes, rebuilt {len(want)} bytes, first difference at "
                                f"byte {at} (another compiler or library than the build's, or the binary was "
                                "changed)"])
    return Check("rebuild", True, f"{binary} rebuilt from the folder's files with the {len(runs)} recorded "
                 "commands: the same, bit for bit")


def verify_folder(folder: str | Path, *, node: str | None = None, model: str | Path | None = None,
                  wp: bool = False, kernel: bool = False, driver: CoqDriver | None = None,
                  progress: Callable[[str], None] | None = None,
                  timeout: float = DEFAULT_TIMEOUT, max_memory: int | None = DEFAULT_MAX_MEMORY,
                  rebuild: bool = False) -> VerifyReport:
    """Run the checks of the module documentation on ``folder``; raise
    :class:`VerifyFailed` unless all hold (the report is its
    ``verify_report``).  Every tool run (coqc, coqchk, the OCaml compiler,
    the extracted printer) is stopped after ``timeout`` seconds, and its
    check fails ("did not finish within N s"), and may use at most
    ``max_memory`` bytes of address space (its check fails: "ran out of
    memory"); Frama-C (``wp``) is stopped after ``timeout`` seconds too.
    ``rebuild``: the node's binary is compiled again from the folder's
    files with the recorded commands and compared bit for bit
    (:func:`_check_rebuild`).  A file of the folder that
    is not a plain regular file of it (a link, a FIFO, a device, too
    large: :mod:`pyrosgen.verify.folder`) stops the run at once with
    :class:`UnsafeFile` naming it (exit 1)."""
    try:
        return _verify_folder(Path(folder), node=node, model=model, wp=wp, kernel=kernel, driver=driver,
                              progress=progress, timeout=timeout, max_memory=max_memory, rebuild=rebuild)
    except UnsafeFile as exc:
        raise UnsafeFile(f"{folder}: refusing the folder: {exc}") from None


def _verify_folder(folder: Path, *, node: str | None, model: str | Path | None, wp: bool, kernel: bool,
                   driver: CoqDriver | None, progress: Callable[[str], None] | None, timeout: float,
                   max_memory: int | None, rebuild: bool) -> VerifyReport:
    say = progress or (lambda _line: None)
    folder = Path(folder)
    t0 = time.monotonic()
    mpath = find_manifest(folder, node)
    try:
        rec, files = read_manifest(mpath)
    except ManifestError as exc:
        raise NotAnOutputFolder(f"{folder}: unreadable manifest: {exc}") from None
    report = VerifyReport(folder, rec.node)
    checks = report.checks
    total = 6 + (model is not None) + (wp is True) + rebuild + any(n.endswith("_ros.cpp") for n in files) \
        + is_build_folder(rec, files)
    step = 0

    def begin(what: str) -> None:
        nonlocal step
        step += 1
        say(f"[{step}/{total}] {what}")

    begin("hashes")
    checks.append(_check_hashes(folder, rec, files))

    drv = driver or CoqDriver(timeout=timeout, max_memory=max_memory)
    if drv.timeout is None:
        drv.timeout = timeout
    if drv.max_memory is None:
        drv.max_memory = max_memory
    drv.check_tools()
    drv.check_library()
    begin("library identity")
    digest = drv.library_digest()
    if digest == rec.library_sha256:
        checks.append(Check("library", True, f"ROSGen sources {digest[:16]}... as recorded"))
    else:
        checks.append(Check("library", False, "the installed ROSGen library is not the one that proved the node", [
            f"  recorded  {rec.library_sha256} (pyrosgen {rec.pyrosgen_version})",
            f"  installed {digest} ({drv.theories})"]))

    work = Path(tempfile.mkdtemp(prefix=f"pyrosgen-verify-{rec.node}-"))
    try:
        coq_dir = work / "coq"
        coq_dir.mkdir()
        lib = (coq_dir, "RosgenNode")
        module = f"RosgenNode.{Path(rec.node_v).stem}"
        begin(f"the .v against the template: {rec.node_v}")
        vcheck, vtext = _check_vfile(folder, rec, drv, model)
        checks.append(vcheck)
        begin(f"coqc and coqchk: {rec.node_v}")
        coq_check: Check | None = None
        chk = None
        try:
            if vtext is None:
                raise _NotRun(f"not run: {rec.node_v} is not the template's .v")
            vpath = _inside(coq_dir, rec.node_v)
            vpath.write_text(vtext, encoding="ascii")
            res = drv.coqc(vpath, lib)
            drv.check_assumptions(res.stdout, rec.theorems, node_file_names(rec.node).theorem_all)
            # coqchk re-checks the module while the texts are re-printed
            # from it (both only read it); its verdict decides both checks
            chk = drv.coqchk_start(module, lib, vm=not kernel)
        except _NotRun as exc:
            coq_check = Check("coqc", False, str(exc))
        except FileNotFoundError:
            coq_check = Check("coqc", False, f"cannot read {rec.node_v}: missing")
        except CoqError as exc:
            coq_check = Check("coqc", False, getattr(exc, "summary", str(exc)), list(getattr(exc, "lines", ())))

        with chk if chk is not None else contextlib.nullcontext():
            begin("re-printing the C, the AST dump and the model from the proof")
            confirmed: CoqError | None = None
            if chk is not None:
                # Coq confirms the theorems' statements and that they use
                # no axiom (while coqchk runs: both only read the module)
                try:
                    drv.confirm_theorems(module, lib, _statements(rec), work / "confirm", imports=_CONFIRM_IMPORTS
                                         + (_CONFIRM_IMPORTS_CTRL if rec.controller else ""))
                except CoqError as exc:
                    confirmed = exc
            if confirmed is not None:
                coq_check = Check("coqc", False, confirmed.summary, list(confirmed.lines))
                reprinted = _Reprint(Check("re-print", False, "not run: Coq does not confirm the theorems"))
            elif chk is None:
                reprinted = _Reprint(Check("re-print", False, "not run: the .v did not check"))
            else:
                reprinted = _reprint(drv, folder, rec, module, lib, work)
                try:
                    chk.result()
                    how = " (kernel conversion, no bytecode machine)" if kernel else ""
                    coq_check = Check("coqc", True, f"{', '.join(rec.theorems)}: {CLOSED}; statements confirmed "
                                      f"by Coq; coqchk OK, no axiom{how}")
                except CoqError as exc:
                    coq_check = Check("coqc", False, getattr(exc, "summary", str(exc)),
                                      list(getattr(exc, "lines", ())))
                    reprinted = _Reprint(Check("re-print", False, "not run: coqchk rejected the module"))
        checks += [coq_check, reprinted.check]
        proved_text, proved_glue, proved_diagram = reprinted.text, reprinted.glue, reprinted.diagram

        begin("certificate")
        checks.append(_check_certificate(folder, rec, files, proved_text, proved_glue, proved_diagram))

        loaded = None  # the front end's model of --model
        if model is not None:
            begin(f"model: {model}")
            if proved_text is None:
                checks.append(Check("model", False, "not run: no proved model text"))
            else:
                try:
                    loaded, msg_root = _load_for_target(folder, rec, model)
                    compare_model_texts(model_text(loaded), proved_text, vfile=rec.node_v)
                    if proved_diagram is not None:
                        from pyrosgen.proof.modeltext import compare_diagram_texts, diagram_text

                        if loaded.controller.diagram is None:
                            raise ModelMismatch(f"{Path(model).name} has no block diagram, "
                                                f"but {rec.node_v} proves one", [])
                        compare_diagram_texts(diagram_text(loaded), proved_diagram, vfile=rec.node_v)
                    # the second, independent reading of the model file (N-version, DESIGN.md section 7)
                    check_model_file(model, proved_text, proved_diagram, vfile=rec.node_v,
                                     **({"standard_root": msg_root} if msg_root is not None else {}))
                    qos = msg_root is not None and is_build_folder(rec, files)
                    if qos:
                        check_qos_of_model(folder, rec, loaded, model)  # rule 4.18: the ROS 2 build's QoS
                    checks.append(Check("model", True, f"the proved model is the model of {Path(model).name}, "
                                        "read by the front end and read independently"
                                        + (f"; so is the QoS record {rec.node}.qos" if qos else "")))
                except PyrosgenError as exc:
                    checks.append(Check("model", False, getattr(exc, "summary", str(exc).splitlines()[0]),
                                        list(getattr(exc, "lines", ())) or str(exc).splitlines()[1:]))

        wrapper = next((n for n in files if n.endswith("_ros.cpp") and "/" not in n), None)
        if wrapper is not None:
            begin(f"wrapper: {wrapper}")
            from pyrosgen.verify.wrapper_check import WrapperMismatch, check_glue_externals, check_wrapper

            header = wrapper[: -len(".cpp")] + ".h"
            try:
                text = proved_text if proved_text is not None else read_text(folder, rec.model_file)
                check_wrapper(read_text(folder, wrapper), text, wrapper_name=wrapper)
                if header in files:
                    # the ROS functions the glue calls, with the glue's C types
                    check_glue_externals(read_text(folder, rec.glue_c), read_text(folder, header),
                                         glue_name=rec.glue_c, header_name=header)
                checks.append(Check("wrapper", True, "registers, sleeps and tells the time as the proved model says"
                                    + (", and declares the glue's ROS functions with its types" if header in files else "")))
            except WrapperMismatch as exc:
                checks.append(Check("wrapper", False, exc.summary, list(exc.lines)))
            except FileNotFoundError as exc:
                checks.append(Check("wrapper", False, f"cannot read {exc}"))

        if is_build_folder(rec, files):
            begin("package: every file of the node rendered again from the proof")
            checks.append(check_package(folder, rec, files, proved_text))

        if rebuild:
            begin(f"rebuild: bin/{rec.node} compiled again and compared bit for bit")
            checks.append(_check_rebuild(folder, rec, files, work / "rebuild", timeout, max_memory))

        if wp:
            begin("Frama-C WP")
            if not rec.wp:
                checks.append(Check("wp", False, "no ACSL contracts in the folder: it was generated without --wp"))
            else:
                from pyrosgen.verify.acsl import WPError, run_wp_file

                wdir = work / "wp"
                wdir.mkdir()
                for n in (rec.wp["contracts"], rec.glue_c, rec.types_h):
                    # by checked names only, into the temporary folder
                    _inside(wdir, n).write_bytes(read_file(folder, n))
                frames = [(f[0], f[1], tuple(f[2])) for f in rec.wp.get("functions", [])]
                problems = []
                if loaded is not None:
                    # the contracts are the model's, not weakened ones
                    from pyrosgen.verify.acsl import contract_frame, contracts, render_wrapper

                    cs = contracts(loaded)
                    if read_text(folder, rec.wp["contracts"]) != render_wrapper(
                            loaded, rec.glue_c, rec.types_h, cs):
                        problems.append(f"  {rec.wp['contracts']}: not the contracts of {Path(model).name}")
                    if frames != [contract_frame(c) for c in cs]:
                        problems.append(f"  the manifest's WP functions are not those of {Path(model).name}")
                try:
                    r = run_wp_file(_inside(wdir, rec.wp["contracts"]), frames, limit=timeout)
                    if problems:
                        checks.append(Check("wp", False, r.summary(), problems))
                    else:
                        checks.append(Check("wp", True, r.summary() + (
                            f"; contracts are those of {Path(model).name}" if loaded is not None else "")))
                except WPError as exc:
                    if "not found" in str(exc) or "install" in str(exc):
                        raise
                    checks.append(Check("wp", False, getattr(exc, "summary", str(exc)),
                                        list(getattr(exc, "lines", ()))))
    finally:
        shutil.rmtree(work, ignore_errors=True)
    report.seconds = time.monotonic() - t0
    if not report.ok:
        raise VerifyFailed(report)
    return report


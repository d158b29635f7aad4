"""``pyrosgen verify OUT``: re-check an output folder on its own.

For a reviewer who receives an output folder of ``pyrosgen generate`` or
``build`` and trusts neither the machine that produced it nor its
certificate.  The checks, from the folder's manifest
(``<node>.manifest.json``, :mod:`pyrosgen.verify.certificate`):

1. **hashes**: every file the manifest covers is present and has its
   recorded SHA-256; the digest file ``<node>.sha256`` says the same;
2. **library**: the installed ROSGen library has the recorded identity
   (its sources' digest), since the ``.v`` recomputes ``generate model``
   against the library when it is checked;
3. **coqc**: the folder's ``.v`` is compiled afresh (in a temporary
   folder; the output folder is never written), every theorem of the
   manifest prints "Closed under the global context", and ``coqchk``
   re-checks the compiled file (while step 4 prints: a module it rejects
   fails both checks);
4. **re-print**: the C header, the glue, the AST dump and the model text
   are printed again from the freshly checked term and must equal the
   folder's files byte for byte; the printed C is validated against the
   dump (pycparser);
5. **certificate**: the folder's certificate is the one rendered from the
   texts the proof printed and the manifest (its relations' and
   constants' C lines are in the printed C, its digests the recorded ones);
6. **model** (with ``--model MODEL.yaml``): the model text Coq printed is
   the front end's reading of that file;
7. **wrapper** (a ``build`` folder): the C++ wrapper registers exactly the
   proved topics, types and queue sizes and sleeps with the proved period;
8. **WP** (with ``--wp``): Frama-C WP proves the folder's ACSL contracts
   file on the folder's C, every goal; with ``--model`` too, the contracts
   file must be the one generated from that model (without it, only its
   digest vouches that the contracts were not weakened).

Each check reports ``ok`` or ``FAILED`` with its reasons; a failed check
does not stop the others.  Exit status: 0 when every check holds, 1 when
one failed (or OUT is not an output folder), 2 when a tool is missing.
"""

from __future__ import annotations

import contextlib
import shutil
import tempfile
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

from pyrosgen.errors import PyrosgenError, UserError
from pyrosgen.proof.coqdriver import CLOSED, CoqDriver, CoqError
from pyrosgen.proof.coqmodel import node_file_names
from pyrosgen.proof.modeltext import ModelMismatch, compare_model_texts, model_text
from pyrosgen.verify.certificate import ProofRecord, certificate_files, read_manifest, sha256_file
from pyrosgen.verify.package_check import check_package, is_build_folder

__all__ = ["Check", "VerifyReport", "NotAnOutputFolder", "VerifyFailed", "verify_folder", "find_manifest"]


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
class Check:
    name: str
    ok: bool
    summary: str
    details: list[str] = field(default_factory=list)


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


def _check_hashes(folder: Path, rec: ProofRecord, files: dict[str, str]) -> Check:
    bad = []
    for name, digest in sorted(files.items()):
        p = folder / name
        if Path(name).is_absolute() or ".." in Path(name).parts:
            bad.append(f"  {name}: not a file of the folder")
        elif not p.is_file():
            bad.append(f"  {name}: missing")
        elif sha256_file(p) != digest:
            bad.append(f"  {name}: SHA-256 {sha256_file(p)}, recorded {digest}")
    sums = folder / certificate_files(rec.node)[2]
    try:
        listed = dict(reversed(line.split("  ", 1)) for line in sums.read_text(encoding="utf-8").splitlines())
    except (OSError, ValueError, UnicodeDecodeError):
        listed = None
    if listed != files:
        bad.append(f"  {sums.name}: does not list the manifest's files and digests")
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
        have = (folder / name).read_text(encoding="utf-8")
    except CertificateError as exc:
        return Check("certificate", False, exc.summary, list(exc.lines))
    except (OSError, UnicodeDecodeError) as exc:
        return Check("certificate", False, f"cannot read {name}: {getattr(exc, 'strerror', None) or exc}")
    if have != want:
        a, b = have.splitlines(), want.splitlines()
        k = next((i for i in range(min(len(a), len(b))) if a[i] != b[i]), min(len(a), len(b)))
        return Check("certificate", False, f"{name} is not the certificate of the proof", [
            f"  line {k + 1}: the folder's {a[k] if k < len(a) else '(nothing)'!r}",
            f"  line {k + 1}: rendered   {b[k] if k < len(b) else '(nothing)'!r}"])
    return Check("certificate", True, f"{name} is the one rendered from the proof and the manifest")


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
    outs = tuple(printed / n for n in (rec.types_h, rec.glue_c, rec.sexp, rec.model_file))
    if rec.controller:
        outs += (printed / rec.controller["c"], printed / rec.controller["sexp"], printed / rec.controller["text"])
    texts: dict[str, str | None] = {}
    try:
        proved = folder / rec.model_file
        relations = sum(1 for line in proved.read_text(encoding="utf-8", errors="replace").splitlines()
                        if line.startswith(("input_relation ", "output_relation "))) if proved.is_file() else 0
        drv.print_texts(module, lib, outs, relations=relations)
        differ = []
        for p in outs:
            mine = folder / p.name
            if not mine.is_file() or mine.read_bytes() != p.read_bytes():
                differ.append(f"  {p.name}: differs from what the proof prints")
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


def verify_folder(folder: str | Path, *, node: str | None = None, model: str | Path | None = None,
                  wp: bool = False, kernel: bool = False, driver: CoqDriver | None = None,
                  progress: Callable[[str], None] | None = None) -> VerifyReport:
    """Run the checks of the module documentation on ``folder``; raise
    :class:`VerifyFailed` unless all hold (the report is its
    ``verify_report``)."""
    say = progress or (lambda _line: None)
    folder = Path(folder)
    t0 = time.monotonic()
    mpath = find_manifest(folder, node)
    try:
        rec, files = read_manifest(mpath)
    except (OSError, ValueError, UnicodeDecodeError) as exc:
        raise NotAnOutputFolder(f"{mpath}: unreadable manifest: {exc}") from None
    report = VerifyReport(folder, rec.node)
    checks = report.checks
    total = 5 + (model is not None) + (wp is True) + any(n.endswith("_ros.cpp") for n in files) \
        + is_build_folder(rec, files)
    step = 0

    def begin(what: str) -> None:
        nonlocal step
        step += 1
        say(f"[{step}/{total}] {what}")

    begin("hashes")
    checks.append(_check_hashes(folder, rec, files))

    drv = driver or CoqDriver()
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
        begin(f"coqc and coqchk: {rec.node_v}")
        coq_check: Check | None = None
        chk = None
        try:
            shutil.copyfile(folder / rec.node_v, coq_dir / rec.node_v)
            res = drv.coqc(coq_dir / rec.node_v, lib)
            drv.check_assumptions(res.stdout, rec.theorems, node_file_names(rec.node).theorem_all)
            # coqchk re-checks the module while the texts are re-printed
            # from it (both only read it); its verdict decides both checks
            chk = drv.coqchk_start(module, lib, vm=not kernel)
        except OSError as exc:
            coq_check = Check("coqc", False, f"cannot read {rec.node_v}: {exc.strerror or exc}")
        except CoqError as exc:
            coq_check = Check("coqc", False, getattr(exc, "summary", str(exc)), list(getattr(exc, "lines", ())))

        with chk if chk is not None else contextlib.nullcontext():
            begin("re-printing the C, the AST dump and the model from the proof")
            if chk is None:
                reprinted = _Reprint(Check("re-print", False, "not run: the .v did not check"))
            else:
                reprinted = _reprint(drv, folder, rec, module, lib, work)
                try:
                    chk.result()
                    how = " (kernel conversion, no bytecode machine)" if kernel else ""
                    coq_check = Check("coqc", True, f"{', '.join(rec.theorems)}: {CLOSED}; coqchk OK{how}")
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
                from pyrosgen.frontend.validate import load_model

                try:
                    loaded = load_model(model)
                    compare_model_texts(model_text(loaded), proved_text, vfile=rec.node_v)
                    if proved_diagram is not None:
                        from pyrosgen.proof.modeltext import compare_diagram_texts, diagram_text

                        if loaded.controller.diagram is None:
                            raise ModelMismatch(f"{Path(model).name} has no block diagram, "
                                                f"but {rec.node_v} proves one", [])
                        compare_diagram_texts(diagram_text(loaded), proved_diagram, vfile=rec.node_v)
                    checks.append(Check("model", True, f"the proved model is the model of {Path(model).name}"))
                except PyrosgenError as exc:
                    checks.append(Check("model", False, getattr(exc, "summary", str(exc).splitlines()[0]),
                                        list(getattr(exc, "lines", ())) or str(exc).splitlines()[1:]))

        wrapper = next((n for n in files if n.endswith("_ros.cpp") and "/" not in n), None)
        if wrapper is not None:
            begin(f"wrapper: {wrapper}")
            from pyrosgen.verify.wrapper_check import WrapperMismatch, check_glue_externals, check_wrapper

            text = proved_text if proved_text is not None else (folder / rec.model_file).read_text(encoding="utf-8")
            header = wrapper[: -len(".cpp")] + ".h"
            try:
                check_wrapper((folder / wrapper).read_text(encoding="utf-8"), text, wrapper_name=wrapper)
                if header in files:
                    # the ROS functions the glue calls, with the glue's C types
                    check_glue_externals((folder / rec.glue_c).read_text(encoding="utf-8"),
                                         (folder / header).read_text(encoding="utf-8"),
                                         glue_name=rec.glue_c, header_name=header)
                checks.append(Check("wrapper", True, "registers, sleeps and tells the time as the proved model says"
                                    + (", and declares the glue's ROS functions with its types" if header in files else "")))
            except WrapperMismatch as exc:
                checks.append(Check("wrapper", False, exc.summary, list(exc.lines)))
            except OSError as exc:
                checks.append(Check("wrapper", False, f"cannot read {wrapper}: {exc.strerror or exc}"))

        if is_build_folder(rec, files):
            begin("package: every file of the node rendered again from the proof")
            checks.append(check_package(folder, rec, files, proved_text))

        if wp:
            begin("Frama-C WP")
            if not rec.wp:
                checks.append(Check("wp", False, "no ACSL contracts in the folder: it was generated without --wp"))
            else:
                from pyrosgen.verify.acsl import WPError, run_wp_file

                wdir = work / "wp"
                wdir.mkdir()
                for n in (rec.wp["contracts"], rec.glue_c, rec.types_h):
                    shutil.copyfile(folder / n, wdir / n)
                frames = [(f[0], f[1], tuple(f[2])) for f in rec.wp.get("functions", [])]
                problems = []
                if loaded is not None:
                    # the contracts are the model's, not weakened ones
                    from pyrosgen.verify.acsl import contract_frame, contracts, render_wrapper

                    cs = contracts(loaded)
                    if (folder / rec.wp["contracts"]).read_text(encoding="utf-8") != render_wrapper(
                            loaded, rec.glue_c, rec.types_h, cs):
                        problems.append(f"  {rec.wp['contracts']}: not the contracts of {Path(model).name}")
                    if frames != [contract_frame(c) for c in cs]:
                        problems.append(f"  the manifest's WP functions are not those of {Path(model).name}")
                try:
                    r = run_wp_file(wdir / rec.wp["contracts"], frames)
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


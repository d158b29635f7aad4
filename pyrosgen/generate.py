"""``pyrosgen generate MODEL.yaml -o DIR``: the pipeline of DESIGN.md section 1.

1. front end: read and validate the model (:func:`pyrosgen.frontend.model.load_model`),
   render the per-node Coq file (:func:`pyrosgen.proof.coqmodel.render_node_file`);
2. coqc: Coq computes ``generate model``, checks that it is ``OK``, and proves
   the node's theorem (``<node>_ddc``, or ``<node>_wf`` while the node DDC
   theorem is not in the library);
3. checking: ``Print Assumptions`` must say "Closed under the global
   context" for every theorem of the file, and ``coqchk`` re-checks the
   compiled file, in the background while step 4 runs (both only read the
   compiled file; its verdict is awaited before anything is written, and
   reported first when both fail);
4. printing: the C texts and the AST dump are printed from ``the_program``
   through extraction (:meth:`pyrosgen.proof.coqdriver.CoqDriver.print_texts`),
   and the printed C is validated against the dump with pycparser
   (:mod:`pyrosgen.verify.printer_validation`); with ``wp=True`` (``--wp``), Frama-C WP
   also proves ACSL contracts generated from the model on the printed C
   (:mod:`pyrosgen.verify.acsl`);
5. writing: ``<node>.v``, ``<node>_types.h``, ``<node>_glue.c``,
   ``<node>.sexp``, ``<node>.model`` (the model Coq printed), with ``--wp``
   ``<node>_wp.c`` (the ACSL contracts), and the certificate
   (:mod:`pyrosgen.verify.certificate`: ``<node>.certificate.md``,
   ``<node>.manifest.json``, ``<node>.sha256``), rendered from the proved
   model text and the printed C, go into ``DIR``.

Everything is produced in a temporary directory next to ``DIR`` and moved
into ``DIR`` only when every step succeeded: on failure, ``DIR`` gets
nothing new (and keeps its other files).  A file is rewritten only when its
content changed.
"""

from __future__ import annotations

import contextlib
import os
import shutil
import stat
import tempfile
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

from pyrosgen.files import locked_folder, move
from pyrosgen.proof.coqdriver import CLOSED, CoqDriver, CoqError
from pyrosgen.proof.coqmodel import EmitError, node_file_names, render_node_file
from pyrosgen.errors import ToolFailure, UserError, show
from pyrosgen.proof.modeltext import compare_model_texts, model_text
from pyrosgen.nversion.check import check_model_file
from pyrosgen.verify.certificate import ProofRecord, sha256_file, tool_versions, write_certificate
from pyrosgen.frontend.model import NodeModel
from pyrosgen.frontend.validate import load_model

__all__ = ["OutputDirError", "GenerateResult", "generate", "generate_model", "STEPS"]

#: Number of progress steps.
STEPS = 5


class OutputDirError(UserError):
    """The output directory cannot be used (a user error: exit code 1)."""


@dataclass
class GenerateResult:
    """What :func:`generate` did."""

    model: NodeModel
    out_dir: Path
    files: list[tuple[Path, bool]]     #: (path, rewritten?) in writing order
    theorem: str                       #: the main theorem checked
    theorem_kind: str                  #: what it states, for the summary
    theorems: list[str]                #: every theorem whose assumptions were printed
    ddc: bool                          #: whether it is the node DDC theorem (T2)
    assumptions: str = CLOSED
    times: dict[str, float] = field(default_factory=dict)
    validation: object = None          #: :class:`pyrosgen.verify.printer_validation.ValidationReport`
    wp: object = None                  #: :class:`pyrosgen.verify.acsl.WPResult` (``--wp`` only)
    #: The model the theorems are about, as Coq printed it (``ModelText``).
    proved_model: str = ""
    #: What the certificate says (``build`` re-renders it with its own files).
    record: ProofRecord | None = None
    #: The files of the output folder the certificate covers.
    covered: list[str] = field(default_factory=list)

    @property
    def written(self) -> list[Path]:
        return [p for p, w in self.files if w]


def _check_out_dir(out_dir: str | Path) -> Path:
    """``out_dir`` as a path, refused when it is empty (``-o ""``, which
    ``Path`` would read as the current folder)."""
    if str(out_dir) == "" or not str(out_dir).strip():
        raise OutputDirError(f"the output folder {show(str(out_dir))} is empty; give a folder name "
                             "(-o . for the current folder)")
    return Path(out_dir)


def _existing_ancestor(p: Path) -> Path:
    p = p.absolute()
    while not p.exists():
        p = p.parent
    return p


def _same_content(path: Path, data: bytes) -> bool:
    """Whether ``path``, a regular file (never followed if a link), holds
    ``data``; its size is compared first, so a large file is not read."""
    try:
        st = os.lstat(path)
        if not stat.S_ISREG(st.st_mode) or st.st_size != len(data):
            return False
        return path.read_bytes() == data
    except OSError:
        return False


def _check_targets(staged: list[tuple[Path, str]], out_dir: Path) -> None:
    """Refuse (exit 1) an output file's name taken by anything but a
    regular file: a link (to /dev/zero, a FIFO, a file elsewhere) is never
    followed, read or replaced, and nor is a folder or a device."""
    for _, name in staged:
        target = out_dir / name
        try:
            st = os.lstat(target)
        except FileNotFoundError:
            continue
        except OSError as exc:
            raise OutputDirError(f"{target}: cannot be examined: {exc.strerror or exc}") from None
        if stat.S_ISLNK(st.st_mode):
            what = "a symbolic link"
        elif stat.S_ISDIR(st.st_mode):
            what = "a folder"
        elif not stat.S_ISREG(st.st_mode):
            what = "a special file (a device, FIFO or socket)"
        else:
            continue
        raise OutputDirError(f"{target}: is {what}; pyrosgen writes its output files only as regular files "
                             "and does not follow or replace it: remove it, or choose another output folder")


def _install(staged: list[tuple[Path, str]], out_dir: Path, on_wait=None) -> list[tuple[Path, bool]]:
    """Move the staged files into ``out_dir`` (created if missing), each
    only if its content changed; on an error, undo what was done."""
    created = not out_dir.exists()
    try:
        out_dir.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise ToolFailure(f"cannot create {out_dir}: {exc.strerror or exc}") from None
    # one run at a time installs into a folder (concurrent runs would mix
    # their files: a .v of one next to the certificate of the other)
    with locked_folder(out_dir, on_wait):
        _check_targets(staged, out_dir)
        return _install_files(staged, out_dir, created)


def _install_files(staged: list[tuple[Path, str]], out_dir: Path, created: bool) -> list[tuple[Path, bool]]:
    done: list[tuple[Path, Path | None]] = []  # (target, backup of the old file)
    result: list[tuple[Path, bool]] = []
    try:
        for src, name in staged:
            target = out_dir / name
            if _same_content(target, src.read_bytes()):
                result.append((target, False))
                continue
            backup = None
            if target.exists():
                backup = src.with_name(src.name + ".old")
                try:
                    # a second name for the old file, not a copy of its
                    # bytes (it may be large)
                    os.link(target, backup)
                except OSError:
                    shutil.copy2(target, backup)   # another file system
            move(src, target)
            done.append((target, backup))
            result.append((target, True))
    except OSError as exc:
        for target, backup in reversed(done):
            try:
                if backup is not None:
                    move(backup, target)
                else:
                    target.unlink()
            except OSError:
                pass
        if created:
            shutil.rmtree(out_dir, ignore_errors=True)
        raise ToolFailure(f"cannot write into {out_dir}: {exc.strerror or exc}") from None
    return result


def generate(
    model_path: str | Path,
    out_dir: str | Path,
    *,
    progress: Callable[[str], None] | None = None,
    keep_work: bool = False,
    driver: CoqDriver | None = None,
    ddc_available: bool | None = None,
    wp: bool = False,
    defer_coqchk: bool = False,
) -> GenerateResult:
    """Run the whole pipeline on the model file ``model_path``; see the
    module documentation.

    ``defer_coqchk``: do not run ``coqchk`` here; the caller re-checks the
    compiled module (kept with ``keep_work``) before it trusts or installs
    anything (``pyrosgen system generate`` checks every new node of a run
    in one ``coqchk``, which loads the library once,
    :meth:`~pyrosgen.proof.coqdriver.CoqDriver.coqchk_many`).

    ``progress`` receives one line per step.  ``ddc_available`` forces the
    choice of the main theorem (default: whether the library has it).
    Raises :class:`~pyrosgen.errors.InvalidNodeModel` (exit 1),
    :class:`OutputDirError` (exit 1), :class:`~pyrosgen.proof.coqdriver.CoqError`
    and other :class:`~pyrosgen.errors.ToolFailure` (exit 2).
    """
    say = progress or (lambda _line: None)
    t_start = time.monotonic()
    _check_out_dir(out_dir)
    say(f"[1/{STEPS}] front end: reading {model_path}")
    model = load_model(model_path)
    return generate_model(
        model, out_dir, progress=progress, keep_work=keep_work, driver=driver,
        ddc_available=ddc_available, wp=wp, defer_coqchk=defer_coqchk, _t_start=t_start,
    )


def _print_and_validate(drv: CoqDriver, model: NodeModel, module: str, lib: tuple[Path, str], names, work: Path,
                        stage: Path, has_diagram: bool, msg_root: Path | None = None):
    """Step 4: print the texts of the compiled ``module`` into ``stage``
    (the model text into ``work``), hold the model text to the YAML's and
    the C to the AST dump; returns (the proved model text, the validation
    report)."""
    out_h, out_c, out_s = stage / names.types_header, stage / names.glue_c, stage / names.sexp
    out_m = work / f"{model.name}.model"
    outputs = (out_h, out_c, out_s, out_m)
    if has_diagram:
        outputs += (stage / names.controller_c, stage / names.controller_sexp, stage / names.controller_text)
    drv.print_texts(module, lib, outputs, relations=len(model.input_relations) + len(model.output_relations))
    # The model the theorems are about is the model of the YAML file
    # (raises ModelMismatch, exit 2, naming the differing items).
    proved_model = out_m.read_text(encoding="utf-8")
    compare_model_texts(model_text(model), proved_model, vfile=names.v_file)
    proved_diagram = None
    if has_diagram:
        # The diagram the controller theorems are about is the diagram of
        # the YAML file (raises ModelMismatch, exit 2).
        from pyrosgen.proof.modeltext import compare_diagram_texts, diagram_text

        proved_diagram = (stage / names.controller_text).read_text(encoding="utf-8")
        compare_diagram_texts(diagram_text(model), proved_diagram, vfile=names.v_file)
    # ... and of the YAML file as a second reading, which shares no code
    # with the front end, understands it (N-version, DESIGN.md section 7;
    # raises NVersionMismatch, exit 2, naming the differing items).
    check_model_file(model.source, proved_model, proved_diagram, vfile=names.v_file,
                     **({"standard_root": msg_root} if msg_root is not None else {}))
    from pyrosgen.verify.printer_validation import validate_glue  # raises PrinterValidationError (a CoqError)

    validation = validate_glue(
        out_c.read_text(encoding="utf-8"), out_h.read_text(encoding="utf-8"),
        out_s.read_text(encoding="utf-8"), glue_name=names.glue_c, header_name=names.types_header)
    if has_diagram:
        from pyrosgen.verify.printer_validation import validate_program

        validate_program((stage / names.controller_c).read_text(encoding="utf-8"),
                         (stage / names.controller_sexp).read_text(encoding="utf-8"),
                         name=names.controller_c)
    return proved_model, validation


def library_theorems_of(ddc: bool, has_diagram: bool) -> tuple[str, ...]:
    """The library's theorems that a node's theorems apply
    (``<theorem>_of_library`` in ``coq/templates/node.v.j2``)."""
    from pyrosgen.proof.coqdriver import LIBRARY_THEOREMS_CTRL, LIBRARY_THEOREMS_DDC, LIBRARY_THEOREMS_WF

    return (LIBRARY_THEOREMS_DDC if ddc else LIBRARY_THEOREMS_WF) + (LIBRARY_THEOREMS_CTRL if has_diagram else ())


def _check_and_print(drv: CoqDriver, model: NodeModel, module: str, lib: tuple[Path, str], names, work: Path,
                     stage: Path, has_diagram: bool, msg_root: Path | None, *, theorems: list[str],
                     library_theorems: tuple[str, ...], defer_coqchk: bool, say, times: dict[str, float]):
    """Steps 3 and 4 after the node's own ``Print Assumptions``: ``coqchk``
    of the module (unless ``defer_coqchk``) and, when ``make proofs``'s
    stamp does not cover them, the assumptions of the ``library_theorems``,
    both in the background while the texts are printed and validated
    (:func:`_print_and_validate`); every verdict is awaited before
    returning (proved model text, validation report, whether pyrosgen
    printed the library theorems' assumptions itself)."""
    with contextlib.ExitStack() as running:
        # each background tool is stopped on leaving, however it is left
        chk = None if defer_coqchk else running.enter_context(drv.coqchk_start(module, lib))
        lib_chk = (None if drv.library_assumptions_stamped(library_theorems) else running.enter_context(
            drv.library_assumptions_start(library_theorems, work / "library",
                                          report=(theorems, names.theorem_all))))
        # 4. printing
        say(f"[4/{STEPS}] printing: extraction, ocamlopt, run; validation against the AST dump")
        t1 = time.monotonic()
        try:
            proved_model, validation = _print_and_validate(drv, model, module, lib, names, work, stage,
                                                          has_diagram, msg_root)
        except Exception:
            # the verdicts of the earlier step come first: the library's
            # assumptions (the step before coqchk), then coqchk's
            if lib_chk is not None:
                lib_chk.result()
            if chk is not None:
                chk.result()
            raise
        times["printing"] = time.monotonic() - t1
        if lib_chk is not None:
            lib_chk.result()
        if chk is not None:
            chk.result()
    return proved_model, validation, lib_chk is not None


def theorem_kind(ddc: bool) -> str:
    """What the main theorem states, for the summary (``ddc``: whether it
    is the node DDC theorem T2)."""
    return ("node data delivery correctness, T2 (DDC.node_ddc)" if ddc else
            "well-formedness, T4 (Wellformed.wf); fallback: the node DDC theorem T2 "
            "(Loopproof.generate_node_ddc) is not in the ROSGen library")


#: How the certificate writes the conjunction of the node's theorems.
CONJ = " /\\ "


def generate_model(
    model: NodeModel,
    out_dir: str | Path,
    *,
    progress: Callable[[str], None] | None = None,
    keep_work: bool = False,
    driver: CoqDriver | None = None,
    ddc_available: bool | None = None,
    wp: bool = False,
    msg_root: Path | None = None,
    defer_coqchk: bool = False,
    target: str = "ros1",
    _t_start: float | None = None,
) -> GenerateResult:
    """The pipeline after the front end, on an already built ``model``.

    ``msg_root``: the folder of the target's standard ``<pkg>/msg/*.msg``
    files that the second reading of the model file reads (``None``:
    Debian's ROS 1 packages in ``/usr/share``; the target ROS 2 passes its
    installation's ``share`` folder, rule 4.17).  ``target``: ``"ros1"`` or
    ``"ros2"``, the target named by the ``.v`` (``target``,
    ``<node>_ddc_target``) and the manifest.

    ``model`` is trusted for printability only (the emitter re-checks every
    name lexically); whether it is well formed is decided by Coq's
    ``generate``, so a model that bypassed the front end's checks is
    refused at the coqc step (:class:`~pyrosgen.proof.coqdriver.CoqError`).
    """
    say = progress or (lambda _line: None)
    times: dict[str, float] = {}
    t_start = _t_start if _t_start is not None else time.monotonic()
    out_dir = _check_out_dir(out_dir)

    # 1. front end (continued): output folder, tools, library, the .v
    if out_dir.exists() and not out_dir.is_dir():
        raise OutputDirError(f"{out_dir}: exists and is not a directory")
    names = node_file_names(model.name)
    drv = driver or CoqDriver()
    drv.check_tools()
    drv.check_library()
    ddc = drv.ddc_available() if ddc_available is None else ddc_available
    diagram = ""
    if getattr(model.controller, "diagram", None) is not None:
        # The controller's theorems are instances of T7, which needs T2.
        if not ddc:
            raise EmitError("the controller is a block diagram, but the ROSGen library has no node "
                            "DDC theorem (Loopproof) to prove it with")
        from pyrosgen.proof.coqdiagram import emit_diagram

        diagram = emit_diagram(model)
    vtext = render_node_file(model, ddc_available=ddc, diagram=diagram, target=target)
    theorems = [names.theorem_ddc, names.theorem_target, names.theorem_wf] if ddc else [names.theorem_wf]
    has_diagram = getattr(model.controller, "diagram", None) is not None
    if has_diagram:
        # printed in this order by coq/templates/node.v.j2 (the Ctrl module
        # comes after the node's theorems)
        theorems += [f"Ctrl.{names.theorem_ctrl_wf}", f"Ctrl.{names.theorem_e2e}", f"Ctrl.{names.theorem_linked}"]
    main_thm = theorems[0]
    kind = theorem_kind(ddc)
    times["front end"] = time.monotonic() - t_start

    base = _existing_ancestor(out_dir.parent if out_dir.name else out_dir)
    try:
        work = Path(tempfile.mkdtemp(prefix=f".pyrosgen-{model.name}-", dir=str(base)))
    except OSError as exc:
        raise ToolFailure(f"cannot create a work directory in {base}: {exc.strerror or exc}") from None
    try:
        coq_dir = work / "coq"
        stage = work / "out"
        coq_dir.mkdir()
        stage.mkdir()
        vfile = coq_dir / names.v_file
        vfile.write_text(vtext, encoding="ascii")
        lib = (coq_dir, "RosgenNode")
        module = f"RosgenNode.{model.name}"
        shown_v = str(vfile) if keep_work else f"{names.v_file} (generated; not written, see --keep-work)"

        # 2. coqc
        say(f"[2/{STEPS}] coqc: generating the glue and proving {main_thm} ...")
        res = drv.coqc(vfile, lib, display=lambda f: shown_v if Path(f).name == names.v_file else f)
        times["coqc"] = res.seconds

        # 3. assumptions, and coqchk in the background while 4. prints
        say(f"[3/{STEPS}] checking: Print Assumptions, coqchk (alongside the printing)")
        t0 = time.monotonic()
        drv.check_assumptions(res.stdout, theorems, names.theorem_all + "_local")
        library_theorems = library_theorems_of(ddc, has_diagram)
        proved_model, validation, library_printed = _check_and_print(
            drv, model, module, lib, names, work, stage, has_diagram, msg_root, theorems=theorems,
            library_theorems=library_theorems, defer_coqchk=defer_coqchk, say=say, times=times)
        times["checking"] = time.monotonic() - t0
        out_h, out_c = stage / names.types_header, stage / names.glue_c
        out_m = work / f"{model.name}.model"
        wp_result = None
        if wp:
            from pyrosgen.verify.acsl import run_wp  # raises WPError (a CoqError) unless every goal is proved

            say(f"[4/{STEPS}] Frama-C WP: proving the ACSL contracts of the model on the printed C ...")
            t0 = time.monotonic()
            wp_result = run_wp(model, out_c, out_h, work / "wp")
            times["wp"] = time.monotonic() - t0
        out_v = stage / names.v_file
        shutil.copyfile(vfile, out_v)
        model_file = f"{model.name}.model"
        shutil.copyfile(out_m, stage / model_file)
        covered = [names.v_file, names.types_header, names.glue_c, names.sexp, model_file]
        if has_diagram:
            covered += [names.controller_c, names.controller_sexp, names.controller_text]
        wp_record = None
        if wp_result is not None:
            contracts = f"{model.name}_wp.c"
            shutil.copyfile(wp_result.wrapper, stage / contracts)
            covered.append(contracts)
            from pyrosgen.verify.acsl import contract_frame, contracts as acsl_contracts

            wp_record = {"proved": wp_result.proved, "total": wp_result.total,
                         "prover": wp_result.prover, "contracts": contracts,
                         "functions": [[n, ptr, list(sep)] for n, ptr, sep in map(contract_frame, acsl_contracts(model))]}
        from pyrosgen import __version__

        record = ProofRecord(
            node=model.name, model_file=model_file, node_v=names.v_file, types_h=names.types_header,
            glue_c=names.glue_c, sexp=names.sexp, theorem=main_thm, theorems=theorems, ddc=ddc, target=target,
            assumptions=(f"Print Assumptions {names.theorem_all}_local.  (* {CONJ.join(theorems)}, "
                         f"each applying one of {', '.join(library_theorems)}: "
                         f"{'pyrosgen' if library_printed else 'make proofs'} printed their assumptions, closed *)"
                         f"\n{CLOSED}"),
            library_sha256=drv.library_digest(), pyrosgen_version=__version__,
            source_name=Path(model.source).name, source_sha256=sha256_file(Path(model.source)) if Path(model.source).is_file() else "",
            wp=wp_record, tools=tool_versions(wp=wp_result is not None),
            controller=({"c": names.controller_c, "sexp": names.controller_sexp, "text": names.controller_text,
                         "wf": f"Ctrl.{names.theorem_ctrl_wf}", "e2e": f"Ctrl.{names.theorem_e2e}",
                         "linked": f"Ctrl.{names.theorem_linked}"}
                        if has_diagram else None),
        )
        cert_files = write_certificate(record, stage, covered)

        # 5. writing
        say(f"[5/{STEPS}] writing into {out_dir}")
        staged = [(stage / name, name) for name in covered + cert_files]
        for p, _ in staged:
            if not p.is_file():
                raise CoqError(f"the printer did not write {p.name}")
        files = _install(staged, out_dir, on_wait=lambda: say(
            f"[5/{STEPS}] waiting for another pyrosgen run writing into {out_dir}"))
    finally:
        if keep_work:
            say(f"work directory kept: {work}")
        else:
            shutil.rmtree(work, ignore_errors=True)
    times["total"] = time.monotonic() - t_start
    return GenerateResult(
        model=model,
        out_dir=out_dir,
        files=files,
        theorem=main_thm,
        theorem_kind=kind,
        theorems=theorems,
        ddc=ddc,
        times=times,
        validation=validation,
        wp=wp_result,
        proved_model=proved_model,
        record=record,
        covered=covered,
    )

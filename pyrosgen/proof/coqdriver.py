"""The driver of the Coq tool chain: ``coqc``, ``coqchk``, extraction,
``ocamlopt`` (in the manner of alectryon's and coq-tools' drivers).

One class, :class:`CoqDriver`:

- finds the tools (a clear error when one is missing: ``coqc not found: run
  make deps``);
- locates the ROSGen library (``coq/theories`` of the repository, or the
  directory named by the environment variable ``PYROSGEN_COQLIB``) and checks
  that it is built: every ``.v`` of ``coq/_CoqProject`` has a ``.vo`` that is
  not older (else ``the Coq library is not built: run make proofs``);
- runs the tools with ``check=False`` and turns Coq's
  ``File "...", line N, characters a-b:`` reports into compiler-style
  ``file:line:col: error: message`` lines;
- checks ``Print Assumptions`` output ("Closed under the global context");
- prints a compiled per-node module through the fast path of
  ``coq/extraction/print_program.sh``: extraction with
  ``ExtrOcamlNativeString`` of the module's ``types_h``, ``glue_c`` and
  ``ast_sexp`` (the printer applied to ``the_program``), compiled by
  ``ocamlopt`` (``ocamlc`` when it is small: :data:`BYTECODE_MAX_BYTES`)
  with a small driver, and run (the extraction is done by a second
  ``coqc`` of pyrosgen's own file, alongside ``coqchk``).

Every failure raises :class:`CoqError` (exit code 2 in the command line).
"""

from __future__ import annotations

import hashlib
import os
import re
import shutil
import subprocess
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

from pyrosgen import console, procs, resources
from pyrosgen.errors import Context, DetailedFailure, UserError, escape

__all__ = [
    "CoqError",
    "ModelRefused",
    "REFUSAL_MARKER",
    "refusal_message",
    "CoqcResult",
    "CoqDriver",
    "DEFAULT_THEORIES",
    "COQLIB_ENV",
    "CLOSED",
    "coq_messages",
    "parse_assumptions",
    "coqchk_summary_problems",
    "LIBRARY_THEOREMS_DDC",
    "LIBRARY_THEOREMS_WF",
    "LIBRARY_THEOREMS_CTRL",
]

#: The ROSGen library's sources and compiled files: ``coq/theories`` of a
#: checkout, or the cache folder of an installed package
#: (:func:`pyrosgen.resources.coq_theories`).
DEFAULT_THEORIES = resources.coq_theories(build=False)
#: Environment variable naming another directory holding the compiled
#: ROSGen library (its ``_CoqProject`` is looked up in the parent).
COQLIB_ENV = "PYROSGEN_COQLIB"
#: What ``Print Assumptions`` prints for a theorem that uses no axiom.
CLOSED = "Closed under the global context"
#: The logical prefix of Coq's standard library, whose axioms ``coqchk -o``
#: lists because the library loads them (:func:`coqchk_summary_problems`).
STDLIB_PREFIX = "Coq."
#: Logical name of the library.
LIBRARY = "ROSGen"

_LOCATION = re.compile(r'^File "(?P<file>[^"]*)", line (?P<line>\d+), characters (?P<a>\d+)-(?P<b>\d+):\s*$')
_SEVERITY = re.compile(r"^(?P<sev>Error|Warning)(?::|\s*\(in proof[^)]*\):)\s?(?P<msg>.*)$")
_MAX_MESSAGE = 2000
#: Extracted printers (``job.ml``) smaller than this are compiled to
#: bytecode: ``ocamlc`` compiles LandShark's (93 KB) in 0.2 s against 0.5 s
#: for ``ocamlopt``, and either runs it in 0.02 s; a large one runs much
#: faster native (2000 relations, 485 KB: 0.2 s against 1.6 s, for 1.2 s
#: against 0.5 s of compilation).  Measured in BENCHMARKS.md, section 1.
BYTECODE_MAX_BYTES = 256 * 1024
#: A model with at least this many relations is printed by a native
#: printer whatever the size of ``job.ml``: the element relations of a
#: whole array are one ``map`` in the model (rule 4.15), so the file stays
#: small while the printer has every element to print (two controller
#: arrays of 8,192: 28.2 s of bytecode against 6.9 s native, for 0.8 s of
#: compilation; BENCHMARKS.md, section 11).
NATIVE_MIN_RELATIONS = 500


#: The library's theorems that a node's theorems apply
#: (``coq/templates/node.v.j2``: ``<theorem>_of_library``), each restated
#: in ``Main.v`` as ``Proof. exact <it>. Qed.``, whose assumptions ``make
#: proofs`` prints (``coq/Makefile``, ``.stamp-assumptions``).
LIBRARY_THEOREMS_DDC = ("Generatorproof.generate_sound", "Loopproof.generate_node_ddc")
LIBRARY_THEOREMS_WF = ("Generatorproof.generate_sound",)
LIBRARY_THEOREMS_CTRL = ("Endtoend.diagram_node_ddc", "Link.linked_node_ddc")
#: The stamp ``make proofs`` leaves next to ``theories`` when every
#: theorem of ``Main.v`` printed "Closed under the global context".
ASSUMPTIONS_STAMP = ".stamp-assumptions"


class CoqError(DetailedFailure):
    """A Coq tool failed, or its output was not what was required (exit 2).

    ``summary`` is one line; ``lines`` are compiler-style diagnostics
    (``file:line:col: error: ...``) or tool output, shown after it.
    """


class ModelRefused(UserError):
    """Coq's ``generate`` refused the model (its message in ``message``):
    the model is invalid although the front end accepted it (exit 1)."""

    def __init__(self, message: str, lines: Sequence[str] = ()):
        self.message = message
        self.summary = f"Coq's generate refused the model: {message}"
        self.lines = tuple(lines)
        super().__init__(self.summary)

    def report(self, ctx: Context) -> list[str]:
        return [f"{ctx.model}: error: {self.summary} (the front end accepted it: please report this); "
                f"{ctx.nothing}"]


#: What the per-node file's proof of [generate_accepts] fails with.
REFUSAL_MARKER = "ROSGen.Generator.generate refused the model:"
_REFUSAL = re.compile(re.escape(REFUSAL_MARKER) + r'\s*"((?:[^"]|"")*)"')


def refusal_message(output: str) -> str | None:
    """The generator's message if ``output`` reports a refusal."""
    m = _REFUSAL.search(output)
    if m is None:
        return None
    return _one_line(m.group(1).replace('""', '"'))


@dataclass(frozen=True)
class CoqcResult:
    """The outcome of one tool run."""

    argv: tuple[str, ...]
    returncode: int
    stdout: str
    stderr: str
    seconds: float

    @property
    def ok(self) -> bool:
        return self.returncode == 0

    @property
    def output(self) -> str:
        """stdout then stderr."""
        return self.stdout + ("\n" if self.stdout and not self.stdout.endswith("\n") else "") + self.stderr


#: The sections of ``Print Assumptions`` other than "Axioms:" (each one
#: means the theorem is not closed).
_ASSUMPTION_SECTIONS = re.compile(
    r"^(Section Variables:|Axioms:|Opaque constants:|Transparent constants:|"
    r"Constants \(and their types\) that rely on|.*assumed to be (?:positive|guarded)|"
    r".*relying on type-in-type|.*type-in-type)")


def parse_assumptions(output: str) -> tuple[int, list[str], list[str]]:
    """What ``Print Assumptions`` printed in ``output``: the number of
    whole lines "Closed under the global context", the axioms listed under
    "Axioms:" (one line each, their types left out), and the headers of
    any other section."""
    closed, axioms, sections = 0, [], []
    lines = output.splitlines()
    i = 0
    while i < len(lines):
        line = lines[i]
        if line.strip() == CLOSED and line == line.rstrip() and not line.startswith(" "):
            closed += 1
        elif line.strip() == "Axioms:":
            i += 1
            while i < len(lines) and lines[i].strip() and lines[i].strip() != CLOSED \
                    and not _ASSUMPTION_SECTIONS.match(lines[i]):
                if not lines[i].startswith(" "):
                    axioms.append(_one_line(lines[i]))
                i += 1
            continue
        elif _ASSUMPTION_SECTIONS.match(line):
            sections.append(_one_line(line))
        i += 1
    return closed, axioms, sections


def coqchk_summary_problems(output: str) -> list[str]:
    """What ``coqchk -o``'s context summary lists that a closed module may
    not have: an axiom outside Coq's standard library, a constant relying
    on type-in-type or unsafe (co)fixpoints, an inductive whose positivity
    is assumed, an impredicative Set (nothing when there is no summary:
    the exit status alone decides, as before ``-o``).

    The summary lists the axioms of the whole environment ``coqchk``
    loaded, not those a theorem uses: the ROSGen library loads parts of the
    standard library that declare axioms (``Coq.Reals``, ``Coq.Logic``,
    ``Coq.ssr``: 30 for LandShark), which no theorem of a node uses
    (``Print Assumptions``, parsed by :func:`parse_assumptions`, says so);
    an axiom of any other name (the node's module, the ROSGen library) is
    refused."""
    lines = output.splitlines()
    try:
        start = next(i for i, ln in enumerate(lines) if ln.strip() == "CONTEXT SUMMARY")
    except StopIteration:
        return []
    out: list[str] = []
    head, items = None, []

    def close() -> None:
        if head is None:
            return
        title, rest = head
        if title == "Theory":
            if rest != "Set is predicative":
                out.append(f"  {title}: {_one_line(rest)}")
        elif rest != "<none>" or items:
            listed = items or [rest]
            if title == "Axioms":
                listed = [x for x in listed if not x.startswith(STDLIB_PREFIX)]
            out.extend(f"  {title}: {_one_line(x)}" for x in listed)

    for ln in lines[start + 1:]:
        m = re.match(r"^\* ([^:]+):\s*(.*)$", ln)
        if m:
            close()
            head, items = (m.group(1).strip(), m.group(2).strip()), []
        elif head is not None and ln.strip() and not set(ln.strip()) <= {"="}:
            items.append(ln.strip())
    close()
    return out


def _one_line(text: str) -> str:
    s = " ".join(escape(text, keep_quotes=True).split())
    return s if len(s) <= _MAX_MESSAGE else s[: _MAX_MESSAGE - 3] + "..."


def coq_messages(text: str, display: Callable[[str], str] = lambda f: f) -> list[str]:
    """Coq's located messages in ``text`` as ``file:line:col: severity: msg``.

    Coq reports ``File "F", line N, characters A-B:`` and, on the next
    lines, ``Error: ...`` or ``Warning: ...`` possibly continued on further
    lines (up to the next location or a blank line); the column is ``A+1``.
    ``display`` maps Coq's file name to the one to show.  Unlocated
    ``Error:`` lines are kept as ``error: ...``.
    """
    out: list[str] = []
    lines = text.splitlines()
    i = 0
    while i < len(lines):
        m = _LOCATION.match(lines[i])
        if m:
            body: list[str] = []
            i += 1
            while i < len(lines) and not _LOCATION.match(lines[i]) and lines[i].strip():
                body.append(lines[i])
                i += 1
            sev, msg = "error", " ".join(body)
            if body:
                s = _SEVERITY.match(body[0])
                if s:
                    sev = "warning" if s.group("sev") == "Warning" else "error"
                    msg = " ".join([s.group("msg"), *body[1:]])
            where = f"{display(m.group('file'))}:{m.group('line')}:{int(m.group('a')) + 1}"
            out.append(f"{where}: {sev}: {_one_line(msg)}")
            continue
        s = _SEVERITY.match(lines[i])
        if s and s.group("sev") == "Error":
            body = [s.group("msg")]
            i += 1
            while i < len(lines) and lines[i].strip() and not _LOCATION.match(lines[i]):
                body.append(lines[i])
                i += 1
            out.append(f"error: {_one_line(' '.join(body))}")
            continue
        i += 1
    return out


_DRIVER_ML = """\
(* Driver of pyrosgen's printing path (pyrosgen/proof/coqdriver.py, after
   coq/extraction/print_program.sh).  [Job] is the OCaml extraction of the
   per-node module's [types_h], [glue_c] and [ast_sexp] (ROSGen.Printer
   applied to [the_program]) and [model_text] (ROSGen.ModelText applied to
   [model]), as native OCaml strings (ExtrOcamlNativeString).  This
   driver only writes them. *)

let write path text =
  let oc = open_out_bin path in
  output_string oc text;
  close_out oc

let () =
  match Sys.argv with
  | [| _; out_h; out_c; out_sexp |] ->
      write out_h (Job.types_h ());
      write out_c (Job.glue_c ());
      write out_sexp (Job.ast_sexp ())
  | [| _; out_h; out_c; out_sexp; out_model |] ->
      write out_h (Job.types_h ());
      write out_c (Job.glue_c ());
      write out_sexp (Job.ast_sexp ());
      write out_model (Job.model_text ())
  | _ ->
      prerr_endline "usage: print_job OUT.h OUT.c OUT.sexp [OUT.model]";
      exit 2
"""

#: The driver for a node whose controller is a block diagram: its module
#: also extracts the controller's C and dump (``Ctrl.controller_c``,
#: ``Ctrl.controller_sexp``, coq/templates/node.v.j2).
_DRIVER_CTRL_ML = _DRIVER_ML.replace(
    """  | _ ->
      prerr_endline "usage: print_job OUT.h OUT.c OUT.sexp [OUT.model]";""",
    """  | [| _; out_h; out_c; out_sexp; out_model; ctrl_c; ctrl_sexp; ctrl_text |] ->
      write out_h (Job.types_h ());
      write out_c (Job.glue_c ());
      write out_sexp (Job.ast_sexp ());
      write out_model (Job.model_text ());
      write ctrl_c (Job.Ctrl.controller_c ());
      write ctrl_sexp (Job.Ctrl.controller_sexp ());
      write ctrl_text (Job.Ctrl.diagram_text ())
  | _ ->
      prerr_endline "usage: print_job OUT.h OUT.c OUT.sexp OUT.model CTRL.c CTRL.sexp CTRL.diagram";""")


def _check_memory(argv: Sequence[str], proc, max_memory: int | None) -> None:
    """:class:`CoqError` if the tool ``argv`` stopped for want of memory
    under the address-space limit ``max_memory``
    (:func:`pyrosgen.procs.out_of_memory`)."""
    if max_memory is not None and proc.returncode != 0 and procs.out_of_memory(
            proc.returncode, (proc.stdout or "") + (proc.stderr or "")):
        size = f"{max_memory >> 30} GiB" if max_memory % (1 << 30) == 0 else f"{max_memory >> 20} MiB"
        output = (proc.stdout or "") + (proc.stderr or "")
        raise CoqError(f"{Path(argv[0]).name} ran out of memory: it stopped at the limit of {size} of address "
                       f"space (exit status {proc.returncode})", [_one_line(output)])


class Running:
    """A tool the driver started in the background
    (:meth:`CoqDriver.coqchk_start`)."""

    def __init__(self, started: "procs.Started", t0: float, timeout: float | None,
                 verdict: Callable[[CoqcResult], CoqcResult], max_memory: int | None = None):
        self._started, self._t0, self._timeout, self._verdict = started, t0, timeout, verdict
        self._max_memory = max_memory

    def result(self) -> CoqcResult:
        """Wait for the tool; its result, or :class:`CoqError` if it failed
        or did not finish within the driver's timeout (counted from its
        start)."""
        argv = [str(a) for a in self._started.args]
        left = None if self._timeout is None else max(0.0, self._timeout - (time.monotonic() - self._t0))
        try:
            proc = self._started.finish(timeout=left)
        except subprocess.TimeoutExpired:
            raise CoqError(f"{Path(argv[0]).name} did not finish within {self._timeout} s") from None
        seconds = time.monotonic() - self._t0
        console.trace_result(argv, proc.returncode, seconds)
        _check_memory(argv, proc, self._max_memory)
        return self._verdict(CoqcResult(tuple(argv), proc.returncode, proc.stdout, proc.stderr, seconds))

    def __enter__(self) -> "Running":
        return self

    def __exit__(self, *exc) -> None:
        self._started.__exit__(*exc)


class CoqDriver:
    """Runs the Coq tool chain against the ROSGen library.

    ``theories`` is the directory of the compiled library (default:
    ``$PYROSGEN_COQLIB`` if set, else ``coq/theories`` of the checkout, or,
    for an installed package, the library built once into the cache).
    Tools are looked up in ``PATH`` when first needed.
    """

    def __init__(self, theories: str | Path | None = None, *, timeout: float | None = None,
                 max_memory: int | None = None):
        if theories is None:
            env = os.environ.get(COQLIB_ENV)
            theories = Path(env) if env else self._default_theories()
        self.theories = Path(theories).absolute()
        self.timeout = timeout
        #: the address-space limit of every tool run, in bytes (``None``: none)
        self.max_memory = max_memory
        self._tools: dict[str, str] = {}

    @staticmethod
    def _default_theories() -> Path:
        try:
            return resources.coq_theories(
                progress=lambda line: print(f"pyrosgen: {line}", file=sys.stderr, flush=True)
            )
        except (resources.LibraryBuildError, OSError) as exc:
            raise CoqError(str(exc)) from None

    # -- tools ---------------------------------------------------------------

    def tool(self, name: str) -> str:
        """The path of tool ``name`` (``CoqError`` if it is not installed)."""
        if name not in self._tools:
            path = shutil.which(name)
            if path is None:
                raise CoqError(f"{name} not found: run make deps")
            self._tools[name] = path
        return self._tools[name]

    def ocamlopt(self) -> list[str]:
        """``ocamlfind ocamlopt`` if ocamlfind is installed, else ``ocamlopt``."""
        if shutil.which("ocamlfind") is not None:
            return [self.tool("ocamlfind"), "ocamlopt"]
        return [self.tool("ocamlopt")]

    def ocamlc(self) -> list[str]:
        """The bytecode compiler, like :meth:`ocamlopt` (``ocamlopt`` if
        there is no ``ocamlc``)."""
        if shutil.which("ocamlfind") is not None:
            return [self.tool("ocamlfind"), "ocamlc"]
        if shutil.which("ocamlc") is not None:
            return [self.tool("ocamlc")]
        return self.ocamlopt()

    def check_tools(self) -> None:
        """Find every tool now, so that a missing one is reported first."""
        self.tool("coqc")
        self.tool("coqchk")
        self.ocamlopt()

    # -- the library ---------------------------------------------------------

    @property
    def coqproject(self) -> Path:
        """``_CoqProject`` next to the library directory."""
        return self.theories.parent / "_CoqProject"

    def library_sources(self) -> list[Path]:
        """The library's ``.v`` files, in the order of ``_CoqProject``
        (every ``.v`` of the directory if there is no ``_CoqProject``)."""
        if self.coqproject.is_file():
            out = []
            for line in self.coqproject.read_text(encoding="utf-8").splitlines():
                line = line.split("#", 1)[0].strip()
                if line.endswith(".v") and not line.startswith("-"):
                    # normalised, not resolved: the library may be made of links
                    p = Path(os.path.normpath(self.coqproject.parent / line))
                    if Path(os.path.normpath(self.theories)) in p.parents:
                        out.append(p)
            return out
        return sorted(self.theories.rglob("*.v"))

    def library_digest(self) -> str:
        """SHA-256 of the library's sources (each ``.v`` file's path under
        ``theories`` and content, in path order): the identity of the
        library a node was proved with.  The per-node ``.v`` recomputes
        ``generate model`` against it when it is checked, so a certificate
        records it and ``pyrosgen verify`` refuses another library."""
        h = hashlib.sha256()
        for v in sorted(self.library_sources(), key=lambda p: p.relative_to(self.theories).as_posix()):
            h.update(v.relative_to(self.theories).as_posix().encode() + b"\0")
            h.update(v.read_bytes() + b"\0")
        return h.hexdigest()

    def check_library(self) -> None:
        """Require the library to be built: each ``X.v`` has an ``X.vo``
        at least as recent."""
        if not self.theories.is_dir():
            raise CoqError(f"the Coq library is not built: run make proofs (no directory {self.theories})")
        sources = self.library_sources()
        if not sources:
            raise CoqError(f"the Coq library is not built: run make proofs (no .v file in {self.theories})")
        stale = []
        for v in sources:
            vo = v.with_suffix(".vo")
            if not vo.is_file():
                stale.append(f"{self._rel(vo)} is missing")
            elif v.is_file() and vo.stat().st_mtime < v.stat().st_mtime:
                stale.append(f"{self._rel(vo)} is older than {v.name}")
        if stale:
            raise CoqError("the Coq library is not built: run make proofs", [f"  {s}" for s in stale])

    def _rel(self, p: Path) -> str:
        """``ROSGen/<layer>/<File>.vo``: a library file as messages name it."""
        try:
            return f"{LIBRARY}/{p.relative_to(self.theories).as_posix()}"
        except ValueError:
            return str(p)

    def has_module(self, name: str) -> bool:
        """Whether a module of base name ``name`` (``theories/<layer>/<name>.v``)
        is part of the library (listed in ``_CoqProject``, or present as
        ``<name>.vo`` if there is none)."""
        if self.coqproject.is_file():
            return any(p.name == f"{name}.v" for p in self.library_sources())
        return any(self.theories.rglob(f"{name}.vo"))

    def ddc_available(self) -> bool:
        """Whether the node DDC theorem T2 (``ROSGen.DDC.node_ddc``,
        ``ROSGen.Loopproof.generate_node_ddc``) is in the library."""
        return self.has_module("DDC") and self.has_module("Loopproof")

    # -- running -------------------------------------------------------------

    def run(self, argv: Sequence[str], cwd: Path, *, big_stack: bool = False) -> CoqcResult:
        """Run a tool (``check=False``); a tool that cannot be started or
        times out raises :class:`CoqError`.  ``big_stack``: see
        :func:`pyrosgen.procs.run`."""
        t0 = time.monotonic()
        console.trace_command(argv)
        try:
            proc = procs.run(argv, cwd=cwd, timeout=self.timeout, big_stack=big_stack, max_memory=self.max_memory)
        except OSError as exc:
            raise CoqError(f"cannot run {argv[0]}: {exc.strerror or exc}") from None
        except subprocess.TimeoutExpired:
            raise CoqError(f"{Path(argv[0]).name} did not finish within {self.timeout} s") from None
        console.trace_result(argv, proc.returncode, time.monotonic() - t0)
        _check_memory(argv, proc, self.max_memory)
        return CoqcResult(tuple(argv), proc.returncode, proc.stdout, proc.stderr, time.monotonic() - t0)

    def load_path(self, extra: Sequence[tuple[Path, str]] = ()) -> list[str]:
        """``-R <theories> ROSGen`` and ``-R DIR LIB`` for each extra pair."""
        args = ["-R", str(self.theories), LIBRARY]
        for d, lib in extra:
            args += ["-R", str(d), lib]
        return args

    def coqc(self, vfile: Path, lib: tuple[Path, str], *, display: Callable[[str], str] | None = None) -> CoqcResult:
        """Compile ``vfile`` (inside ``lib[0]``, logical prefix ``lib[1]``);
        a failure raises :class:`CoqError` with Coq's messages located."""
        argv = [self.tool("coqc"), *self.load_path([lib]), vfile.name]
        res = self.run(argv, vfile.parent)
        if not res.ok:
            shown = display or (lambda f: f)
            msgs = coq_messages(res.output, shown) or [_one_line(res.output) or f"exit status {res.returncode}"]
            refused = refusal_message(res.output)
            if refused is not None:
                raise ModelRefused(refused, msgs)
            raise CoqError(f"coqc failed on {shown(vfile.name)} (exit status {res.returncode})", msgs)
        return res

    @staticmethod
    def check_assumptions(output: str, theorems: Sequence[str], conjunction: str | None = None) -> None:
        """Require one "Closed under the global context" per theorem whose
        assumptions the file printed (``Print Assumptions``, in order), or,
        when the file printed those of their ``conjunction`` (one
        traversal of the library for all), one for it; and no "Axioms:"
        (nor any other section of ``Print Assumptions``: section
        variables, type-in-type, unsafe fixpoints, assumed positivity).
        The output is parsed line by line: "Closed under the global
        context" counts only as a whole line, as Coq prints it (not inside
        a printed string)."""
        closed, axioms, sections = parse_assumptions(output)
        want = 1 if conjunction else len(theorems)
        if closed != want or axioms or sections:
            what = (f"the theorems {', '.join(theorems)} (their conjunction {conjunction}) depend"
                    if conjunction else f"{max(len(theorems) - closed, 1)} of the theorems {', '.join(theorems)} depend")
            raise CoqError(f"{what} on axioms (Print Assumptions did not say \"{CLOSED}\")",
                           [f"  {a}" for a in axioms] + [f"  {x}" for x in sections])

    def confirm_theorems(self, module: str, lib: tuple[Path, str], statements: Sequence[tuple[str, str]],
                         work: Path, *, imports: str = "") -> CoqcResult:
        """Coq itself confirms what a compiled per-node ``module`` proves:
        a file of pyrosgen's own (``Confirm.v`` in ``work``, a folder of
        its own) ``Require``s the module and defines, for each ``(name,
        statement)``, a constant of type ``statement`` equal to
        ``module.name`` (a type error unless the theorem proves exactly
        that), then prints the assumptions of their conjunction, which
        must be exactly "Closed under the global context" (the module's
        own output is not replayed by ``Require``: all this file prints is
        its own).  ``imports``: ``Require`` lines for the statements."""
        work.mkdir(exist_ok=True)
        defs, names = [], []
        for k, (thm, stmt) in enumerate(statements):
            defs.append(f"Definition confirm_{k} : {stmt} := {module}.{thm}.")
            names.append(f"confirm_{k}")
        conj = names[-1]
        for x in reversed(names[:-1]):
            conj = f"(conj {x} {conj})"
        (work / "Confirm.v").write_text(
            "(* Generated by pyrosgen verify (coqdriver.py): the theorems of the\n"
            f"   checked module {module} have the template's statements. *)\n"
            f"{imports}Require {module}.\n" + "\n".join(defs) + "\n"
            f"Definition confirm_all := {conj}.\n"
            "Print Assumptions confirm_all.\n", encoding="ascii")
        argv = [self.tool("coqc"), "-q", *self.load_path([lib, (work, "RosgenConfirm")]), "Confirm.v"]
        res = self.run(argv, work)
        if not res.ok:
            raise CoqError("Coq does not confirm the theorems' statements",
                           coq_messages(res.output) or [_one_line(res.output)])
        closed, axioms, sections = parse_assumptions(res.stdout)
        rest = [ln for ln in res.stdout.splitlines() if ln.strip() and ln.strip() != CLOSED]
        if closed != 1 or axioms or sections or rest:
            raise CoqError(f"Print Assumptions of the theorems is not \"{CLOSED}\"",
                           [f"  axiom {a}" for a in axioms] + [f"  {_one_line(x)}" for x in (sections or rest)][:20])
        return res

    def library_assumptions_stamped(self, theorems: Sequence[str]) -> bool:
        """Whether ``make proofs`` printed the assumptions of the library's
        ``theorems`` (``Layer.name``) and found them closed, for the
        library as it is now: its stamp (:data:`ASSUMPTIONS_STAMP`, left
        only when every theorem of ``Main.v`` printed "Closed under the
        global context") is no older than any ``.vo`` of the library, and
        ``Main.v`` restates each theorem as ``Proof. exact <it>. Qed.``
        (so that its assumptions include the theorem's)."""
        try:
            stamp = (self.theories.parent / ASSUMPTIONS_STAMP).stat().st_mtime
            main = (self.theories / "Main.v").read_text(encoding="utf-8")
            if any(v.with_suffix(".vo").stat().st_mtime > stamp for v in self.library_sources()):
                return False
        except (OSError, UnicodeDecodeError):
            return False
        for thm in theorems:
            at = re.search(rf"^Theorem {re.escape(thm.rsplit('.', 1)[-1])}\b", main, re.M)
            proof = main.find("Proof.", at.end()) if at else -1
            if proof < 0 or not main.startswith(f"Proof. exact {thm}. Qed.", proof):
                return False
        return True

    def library_assumptions_start(self, theorems: Sequence[str], work: Path, *,
                                  report: tuple[Sequence[str], str] | None = None) -> "Running":
        """Print the assumptions of the library's ``theorems`` in the
        background (when :meth:`library_assumptions_stamped` is false): a
        file of pyrosgen's own in ``work`` (a folder of its own)
        ``Require``s their modules and prints the assumptions of their
        conjunction, which must be "Closed under the global context".
        ``report``: the node's theorems that apply them and their
        conjunction, named in the error (as :meth:`check_assumptions`)."""
        work.mkdir(exist_ok=True)
        conj = theorems[-1]
        for x in reversed(theorems[:-1]):
            conj = f"(conj {x} {conj})"
        modules = " ".join(sorted({t.rsplit(".", 1)[0] for t in theorems}))
        (work / "LibraryAssumptions.v").write_text(
            "(* Generated by pyrosgen (coqdriver.py): the assumptions of the\n"
            "   library's theorems that the node's theorems apply. *)\n"
            f"From ROSGen Require {modules}.\n"
            f"Definition library_theorems := {conj}.\n"
            "Print Assumptions library_theorems.\n", encoding="ascii")
        argv = [self.tool("coqc"), "-q", *self.load_path([(work, "RosgenLibrary")]), "LibraryAssumptions.v"]
        console.trace_command(argv)
        t0 = time.monotonic()
        try:
            started = procs.start(argv, cwd=work, max_memory=self.max_memory)
        except OSError as exc:
            raise CoqError(f"cannot run {argv[0]}: {exc.strerror or exc}") from None

        def verdict(res: CoqcResult) -> CoqcResult:
            if not res.ok:
                raise CoqError("coqc failed on the library's theorems",
                               coq_messages(res.output) or [_one_line(res.output)])
            self.check_assumptions(res.stdout, *(report or (list(theorems), "library_theorems")))
            return res

        return Running(started, t0, self.timeout, verdict, self.max_memory)

    def _coqchk_argv(self, module: str, lib: tuple[Path, str], vm: bool) -> list[str]:
        return [self.tool("coqchk"), "-silent", "-o", *(["-bytecode-compiler", "yes"] if vm else []),
                *self.load_path([lib]), "-norec", module]

    @staticmethod
    def _coqchk_verdict(module: str, res: CoqcResult) -> CoqcResult:
        """``coqchk``'s exit status, then its context summary (``-o``):
        ``coqchk`` accepts a module that uses an axiom, and lists it there,
        so any axiom listed (or any constant relying on type-in-type,
        unsafe fixpoints or assumed positivity) is a rejection too."""
        if not res.ok:
            raise CoqError(
                f"coqchk rejected {module} (exit status {res.returncode})",
                coq_messages(res.output) or [_one_line(res.output)],
            )
        problems = coqchk_summary_problems(res.output)
        if problems:
            raise CoqError(f"coqchk: {module} is not closed under the global context", problems)
        return res

    def coqchk(self, module: str, lib: tuple[Path, str], *, vm: bool = True) -> CoqcResult:
        """Re-check the compiled ``module`` with ``coqchk`` (the library
        itself is checked by ``make proofs``: ``-norec``).

        With ``vm`` (the default), ``coqchk`` re-runs the module's
        ``vm_compute`` steps in Coq's bytecode machine
        (``-bytecode-compiler yes``), the machine that ``coqc`` ran them
        in; without it, in its own lazy conversion, independent of that
        machine but slower: a node's well-formedness check follows every
        relation, and for 2,166 relations it takes 8.9 s instead of 1.5 s
        (BENCHMARKS.md, section 11).  ``pyrosgen verify --kernel`` asks
        for the latter."""
        res = self.run(self._coqchk_argv(module, lib, vm), lib[0])
        return self._coqchk_verdict(module, res)

    def coqchk_many(self, modules: Sequence[str], lib: tuple[Path, str], *, vm: bool = True) -> CoqcResult:
        """:meth:`coqchk` of several modules of ``lib`` in one ``coqchk``
        (each ``-norec``: the library is loaded once, where one ``coqchk``
        per module loads it again for each, about 1 s).  When it rejects
        them, each module is checked on its own, so that the error names
        the one (or those) rejected."""
        argv = self._coqchk_argv(modules[0], lib, vm)[:-2]
        for m in modules:
            argv += ["-norec", m]
        res = self.run(argv, lib[0])
        try:
            return self._coqchk_verdict(" ".join(modules), res)
        except CoqError:
            if len(modules) == 1:
                raise
        for m in modules:
            self.coqchk(m, lib, vm=vm)      # raises for the first rejected
        raise CoqError(f"coqchk rejected {', '.join(modules)} together (exit status {res.returncode}), "
                       "each on its own accepted", coq_messages(res.output) or [_one_line(res.output)])

    def coqchk_start(self, module: str, lib: tuple[Path, str], *, vm: bool = True) -> "Running":
        """:meth:`coqchk`, started in the background: ``generate`` prints
        the texts while ``coqchk`` re-checks the module (they are
        independent, and nothing is written before both succeeded).  Use
        the result as a context manager (leaving it stops ``coqchk`` if
        it still runs) and ask for the verdict with
        :meth:`Running.result`."""
        argv = self._coqchk_argv(module, lib, vm)
        console.trace_command(argv)
        t0 = time.monotonic()
        try:
            started = procs.start(argv, cwd=lib[0], max_memory=self.max_memory)
        except OSError as exc:
            raise CoqError(f"cannot run {argv[0]}: {exc.strerror or exc}") from None
        return Running(started, t0, self.timeout, lambda res: self._coqchk_verdict(module, res), self.max_memory)

    def print_texts(self, module: str, lib: tuple[Path, str], outputs: tuple[Path, ...], *,
                    relations: int = 0) -> dict[str, float]:
        """Print the compiled per-node ``module`` through extraction: write
        its ``types_h``, ``glue_c`` and ``ast_sexp`` texts, and with a fourth
        output its ``model_text`` (the model its theorem is about), to
        ``outputs``.  ``relations``, the model's number of (element)
        relations, chooses a native printer from
        :data:`NATIVE_MIN_RELATIONS` on.  Returns the time of each step."""
        work = lib[0]
        times: dict[str, float] = {}
        # A coqc of pyrosgen's own file extracts the texts (not the per-node
        # file: then coqchk, which needs the compiled module, would wait for
        # the extraction; here the two run side by side, BENCHMARKS.md
        # section 1).
        times["extraction"] = self._extract(module, lib, outputs)
        driver = _DRIVER_CTRL_ML if len(outputs) == 7 else _DRIVER_ML
        (work / "driver.ml").write_text(driver, encoding="ascii")
        small = (work / "job.ml").stat().st_size < BYTECODE_MAX_BYTES and relations < NATIVE_MIN_RELATIONS
        compiler = self.ocamlc() if small else self.ocamlopt()
        res = self.run([*compiler, "-w", "-a", "job.mli", "job.ml", "driver.ml", "-o", "print_job"], work,
                       big_stack=True)
        if not res.ok:
            raise CoqError(f"{Path(compiler[-1]).name} failed on the extracted printer", [_one_line(res.output)])
        times["ocamlopt"] = res.seconds
        res = self.run([str(work / "print_job"), *(str(p) for p in outputs)], work)
        if not res.ok:
            raise CoqError(f"the extracted printer failed (exit status {res.returncode})", [_one_line(res.output)])
        times["run"] = res.seconds
        return times

    def _extract(self, module: str, lib: tuple[Path, str], outputs: tuple[Path, ...] = ()) -> float:
        """Extract ``module``'s texts into ``job.ml`` with a second coqc run
        (the per-node file does not extract them itself); returns its
        time."""
        work = lib[0]
        (work / "Extract.v").write_text(
            "(* Generated by pyrosgen (coqdriver.py): extraction of the printed\n"
            f"   texts of {module}, after coq/extraction/print_program.sh. *)\n"
            "From Coq Require Import extraction.ExtrOcamlBasic extraction.ExtrOcamlNativeString.\n"
            f"Require {module}.\n"
            f'Extraction "job.ml" {module}.types_h {module}.glue_c {module}.ast_sexp {module}.model_text'
            + (f" {module}.Ctrl.controller_c {module}.Ctrl.controller_sexp {module}.Ctrl.diagram_text"
               if len(outputs) == 7 else "")
            + ".\n",
            encoding="ascii",
        )
        res = self.run([self.tool("coqc"), "-q", *self.load_path([lib]), "Extract.v"], work)
        if not res.ok:
            raise CoqError("extraction failed", coq_messages(res.output) or [_one_line(res.output)])
        return res.seconds

"""``pyrosgen build MODEL.yaml --controller DIR -o OUT``: a runnable ROS node.

The steps (each one progress line):

1. front end: read and validate the model; find the controller folder,
   its header ``<Controller>.h`` and its ``*.c`` sources;
2. generate: the pipeline of :mod:`pyrosgen.generate` (coqc proves the
   node's DDC theorem, Coq prints the C), into the staging folder;
3. wrapper: the C API over roscpp (:func:`pyrosgen.ros.wrapper.render_wrapper`),
   gencpp headers for custom messages (``include/``), a copy of the
   controller (``controller/``), the catkin package (``package.xml``,
   ``CMakeLists.txt``, the launch file); the wrapper, the layout check and
   the catkin files are rendered from the proved model alone
   (:func:`pyrosgen.ros.wrapper.proved_node`) and a record of the build's
   options kept in the manifest (``build.package``), so that ``verify``
   renders them again (:mod:`pyrosgen.verify.package_check`);
4. layout check: ``<node>_layout_check.c`` (:mod:`pyrosgen.ros.layout`);
5. compile the glue: ``gcc -std=c11 -Wall -Wextra -Werror -pedantic
   -ffp-contract=off -fexcess-precision=standard``;
6. compile the controller: every ``.c`` of ``DIR`` and its subfolders
   with ``-std=<--std, default c11> -O2 -Wall -Wextra`` and ``--cflags``
   (a controller generated from a block diagram: then
   ``-ffp-contract=off -fexcess-precision=standard``, and ``--cflags``
   that change floating-point semantics are refused, :data:`FP_FLAGS`),
   every ``.cpp`` with ``g++ -std=c++14`` and ``--cxxflags``, ``-I`` each
   folder holding headers and each ``--include`` (user code: warnings are
   shown, not errors); sources defining ``main`` (``ert_main.c``) are left
   out with a note;
7. compile the wrapper: ``g++ -std=c++14 -Wall -Wextra -Werror`` with the
   flags of ``pkg-config roscpp <message packages>``;
8. link ``bin/<node>`` (with ``--ldflags`` and ``--libs``) and install
   everything into ``OUT``; the manifest records every compiler command
   (``build.commands``, paths relative to ``OUT``) and the certificate
   lists them.

Nothing partial: everything is built in a staging folder next to ``OUT``
and moved into ``OUT`` only when every step succeeded (files whose content
did not change are left alone; files of a previous build that this one no
longer produces are removed; other files in ``OUT`` are kept).

Compiling roscpp code is slow (about 4 s for the wrapper), so an object
file, and the binary, is reused from the previous build in ``OUT`` when the
hash of everything it is made from is unchanged: the compiler command (with
the staging folder abstracted), the compiler's identity, the source, the
headers it can include from the build (the generated headers, the
controller folder's files) and the pkg-config flags.  The hashes are kept in
``OUT/.pyrosgen-build.json``.  System headers are assumed not to change
between builds (delete the stamp file to force a full rebuild).

Exit codes (see :mod:`pyrosgen.cli`): a model, controller folder or
controller source error, or a layout mismatch, is a user error (1); a
proof, tool or generated-code compilation failure is exit 2.
"""

from __future__ import annotations

import hashlib
import json
import os
import re
import shlex
import shutil
import subprocess
import tempfile
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from pyrosgen import console, procs
from pyrosgen.files import locked_folder, move
from pyrosgen.ros import layout
from pyrosgen.ros import wrapper as ros
from pyrosgen.errors import Context, DetailedFailure, UserError, escape
from pyrosgen.proof.modeltext import parse_model_text
from pyrosgen.verify.certificate import ManifestError, certificate_files, read_manifest, sha256_file, write_certificate
from pyrosgen.verify.wrapper_check import check_glue_externals, check_wrapper
from pyrosgen.generate import GenerateResult, OutputDirError, _check_out_dir, generate_model, theorem_kind
from pyrosgen.proof.coqdriver import CoqDriver
from pyrosgen.proof.coqmodel import node_file_names
from pyrosgen.frontend import csource, msgdeb
from pyrosgen.frontend.coder import find_period
from pyrosgen.frontend.csource import C_SUFFIXES, CXX_SUFFIXES, HEADER_SUFFIXES
from pyrosgen.frontend.model import NodeModel
from pyrosgen.frontend.validate import load_model

__all__ = [
    "BuildError",
    "ControllerError",
    "BuildToolError",
    "BuildResult",
    "STEPS",
    "STAMP",
    "build",
    "build_model",
]

#: Number of progress steps.
STEPS = 8
#: The stamp file (hashes of the inputs of each object and of the binary).
STAMP = ".pyrosgen-build.json"
_STAMP_VERSION = 1

GLUE_CFLAGS = ros.GLUE_CFLAGS
WRAPPER_CXXFLAGS = ros.WRAPPER_CXXFLAGS
CONTROLLER_CFLAGS = ("-O2", "-Wall", "-Wextra")     # after -std=<--std, default c11>
CONTROLLER_CXXFLAGS = ("-std=c++14", "-O2", "-Wall", "-Wextra")
LDFLAGS = ("-pthread",)
LDLIBS = ("-lm",)

_FILE_NAME = re.compile(r"^[A-Za-z0-9_][A-Za-z0-9_.-]*$")
_MAX_OUTPUT = 12000


class BuildError(UserError):
    """A user error found by ``build`` (exit 1): the controller folder, a
    controller source that does not compile, the output folder."""


class ControllerError(BuildError):
    """The user's controller code does not compile (exit 1); ``lines`` are
    the compiler's messages."""

    def __init__(self, summary: str, lines: Sequence[str] = ()):
        self.summary = summary
        self.lines = tuple(lines)
        super().__init__(summary + ("\n" + "\n".join(self.lines) if self.lines else ""))

    def report(self, ctx: Context) -> list[str]:
        return [f"{self.summary}; {ctx.nothing}", *self.lines]


class BuildToolError(DetailedFailure):
    """A tool failed on generated code, or could not be run (exit 2)."""


@dataclass
class BuildResult:
    """What :func:`build` did."""

    model: NodeModel
    out_dir: Path
    binary: Path
    generated: GenerateResult
    files: list[tuple[Path, bool]]              #: (path, rewritten?)
    steps: list[tuple[str, bool]]               #: (object or binary, rebuilt?)
    warnings: list[str] = field(default_factory=list)
    times: dict[str, float] = field(default_factory=dict)


# -- small helpers --------------------------------------------------------------

def _sha(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


def _clip(text: str) -> str:
    text = text.strip()
    return text if len(text) <= _MAX_OUTPUT else text[:_MAX_OUTPUT] + "\n[... output cut ...]"


def _existing_ancestor(p: Path) -> Path:
    p = p.absolute()
    while not p.exists():
        p = p.parent
    return p


def _tool(env_var: str, default: str) -> list[str]:
    value = os.environ.get(env_var, "").strip()
    return shlex.split(value) if value else [default]


def _run(argv: Sequence[str], what: str, cwd: Path | None = None, timeout: int = 900) -> subprocess.CompletedProcess:
    console.trace_command(argv)
    t0 = time.monotonic()
    try:
        r = procs.run(argv, timeout=timeout, cwd=cwd)
        console.trace_result(argv, r.returncode, time.monotonic() - t0)
        return r
    except OSError as exc:
        raise BuildToolError(f"cannot run {argv[0]} ({what}): {exc.strerror or exc}") from None
    except subprocess.TimeoutExpired:
        raise BuildToolError(f"{argv[0]} did not finish {what} within {timeout} s") from None


def _compiler_identity(cc: list[str]) -> str:
    path = shutil.which(cc[0]) or cc[0]
    r = _run([*cc, "--version"], "--version")
    first = (r.stdout or r.stderr).splitlines()[:1]
    return f"{path} {' '.join(cc[1:])} {first[0] if first else r.returncode}"


def pkg_config(modules: Sequence[str]) -> tuple[list[str], list[str]]:
    """``(cflags, libs)`` of ``pkg-config`` for ``modules``."""
    pc = _tool("PKG_CONFIG", "pkg-config")
    r = _run([*pc, "--cflags", *modules], "pkg-config")
    if r.returncode != 0:
        raise BuildToolError(
            f"pkg-config does not know {' '.join(modules)}: install the ROS development "
            "packages (make deps)", [_clip(r.stderr or r.stdout)])
    cflags = shlex.split(r.stdout)
    r = _run([*pc, "--libs", *modules], "pkg-config")
    if r.returncode != 0:
        raise BuildToolError(f"pkg-config --libs {' '.join(modules)} failed", [_clip(r.stderr or r.stdout)])
    return cflags, shlex.split(r.stdout)


# -- the controller folder -------------------------------------------------------

@dataclass(frozen=True)
class ControllerDir:
    """The user's controller: its folder, header and sources."""

    path: Path
    header: Path
    sources: tuple[Path, ...]        #: the .c and .cpp files compiled
    files: tuple[Path, ...]          #: every source and header (copied into OUT/controller)
    include_dirs: tuple[Path, ...]   #: the folders holding headers (the top folder first)
    left_out: tuple[tuple[Path, str], ...] = ()  #: sources not compiled, with the reason

    def rel(self, p: Path) -> str:
        return p.relative_to(self.path).as_posix()


#: C standards a controller may be compiled with (``--std``).
C_STANDARDS = ("c89", "c90", "c99", "c11", "c17", "c18", "gnu89", "gnu99", "gnu11", "gnu17", "gnu18")
#: What a user flag may contain (it reaches argv and CMakeLists.txt).
_FLAG = re.compile(r"^[A-Za-z0-9_=+,./:@%-]+$")


@dataclass(frozen=True)
class ControllerOptions:
    """How the controller is compiled and linked (``pyrosgen build``'s
    ``--std``, ``--cflags``, ``--cxxflags``, ``--include``, ``--ldflags``,
    ``--libs``)."""

    std: str = "c11"
    cflags: tuple[str, ...] = ()
    cxxflags: tuple[str, ...] = ()
    includes: tuple[str, ...] = ()
    ldflags: tuple[str, ...] = ()
    libs: tuple[str, ...] = ()
    #: ``--maintainer``: the maintainer of the catkin package (``package.xml``)
    maintainer: str = ros.DEFAULT_MAINTAINER

    def check(self) -> None:
        if self.std not in C_STANDARDS:
            raise BuildError(f"--std {self.std}: not one of {', '.join(C_STANDARDS)}")
        if ros.parse_maintainer(self.maintainer) is None:
            raise BuildError(f"--maintainer {escape(self.maintainer)!s}: not \"Name <email>\" (a name of letters, "
                             "digits, spaces and . , ' ( ) _ + -, and an e-mail address such as "
                             "jane.doe@example.com in angle brackets)")
        for what, flags in (("--cflags", self.cflags), ("--cxxflags", self.cxxflags), ("--include", self.includes),
                            ("--ldflags", self.ldflags), ("--libs", self.libs)):
            for f in flags:
                if not _FLAG.match(f):
                    raise BuildError(f"{what}: {escape(f)!s}: unsupported characters (letters, digits and "
                                     "_ = + , . / : @ % - only; flags reach the compiler's command line and "
                                     "CMakeLists.txt)")


#: Flags that change what a floating-point (or any) operation of C computes,
#: refused for a generated (block-diagram) controller, whose C is proved
#: with IEEE 754 semantics (T6), and at link time (``--ldflags``: linking
#: with ``-ffast-math`` adds ``crtfastmath.o``, which turns on flush-to-zero
#: for the whole process, the glue included); by prefix, with the reason.
#: ``-march``/``-mtune``/``-mfma`` are allowed: ``-ffp-contract=off`` is
#: always passed after the user's flags, so no ``a*b+c`` is fused
#: (``build --cflags=-march=haswell`` has no ``vfmadd``, tests/build).
#: ``-frounding-math``/``-fno-rounding-math`` are allowed: neither changes a
#: result in the default rounding mode, the only one the node runs in.
FP_FLAGS: tuple[tuple[str, str], ...] = (
    ("-ffast-math", "turns on -funsafe-math-optimizations, -ffinite-math-only and others"),
    ("-Ofast", "turns on -ffast-math"),
    ("-funsafe-math-optimizations", "reassociates and approximates floating-point operations"),
    ("-fassociative-math", "reassociates floating-point operations ((a+b)+c as a+(b+c))"),
    ("-freciprocal-math", "replaces x/y by x*(1/y)"),
    ("-ffinite-math-only", "assumes no NaN or infinity (comparisons and guards with them change)"),
    ("-fno-signed-zeros", "ignores the sign of zero (x+0.0 folded to x, -0.0 to 0.0)"),
    ("-fno-trapping-math", "lets GCC move or drop operations as if none could trap; refused in "
                           "doubt, since with the flags it enables it changes results"),
    ("-fcx-limited-range", "computes complex division without the IEEE range checks"),
    ("-fcx-fortran-rules", "computes complex division without the IEEE range checks"),
    ("-fsingle-precision-constant", "rounds double constants to float"),
    ("-ffp-contract=fast", "fuses a*b+c into one rounding (fused multiply-add)"),
    ("-ffp-contract=on", "fuses a*b+c into one rounding (fused multiply-add)"),
    ("-fexcess-precision=fast", "keeps values wider than their type (double rounding)"),
    ("-mfpmath=387", "computes with the x87's 80-bit registers (double rounding)"),
    ("-mfpmath=both", "computes with the x87's 80-bit registers (double rounding)"),
    ("-mfpmath=sse+387", "computes with the x87's 80-bit registers (double rounding)"),
    ("-mno-sse", "computes with the x87's 80-bit registers (double rounding)"),
    ("-m32", "computes with the x87's 80-bit registers (double rounding), another ABI"),
    ("-mpc", "changes the x87's precision"),
    ("-mdaz-ftz", "sets flush-to-zero and denormals-are-zero for the whole process"),
    ("-fpack-struct", "changes the layout of the structs the glue shares with the controller"),
    ("-funsigned-char", "changes what char means"),
    ("-fsigned-char", "changes what char means"),
    ("-D", "defines a macro in the proved C"),
    ("-U", "undefines a macro in the proved C"),
    ("-include", "inserts a file into the proved C"),
    ("-imacros", "inserts macros into the proved C"),
    ("-fno-fp-int-builtin-inexact", "changes the rounding functions' results"),
)

#: The rule of the message refusing a flag of :data:`FP_FLAGS`.
FP_RULE = "DESIGN.md section 7, compile flags"


def fp_flag_problem(flag: str, *, link: bool = False) -> str | None:
    """Why ``flag`` may not compile a generated controller (or, with
    ``link``, link the node), or ``None``."""
    for prefix, why in FP_FLAGS:
        if link and prefix not in _LINK_FLAGS:
            continue
        if flag == prefix or prefix in _PREFIXES and flag.startswith(prefix):
            return why
    return None


#: The flags of :data:`FP_FLAGS` that are refused with any suffix (``-DX=1``, ``-mpc64``).
_PREFIXES = ("-D", "-U", "-mpc", "-include", "-imacros", "-fpack-struct")
#: Those that change the process when linking (``crtfastmath.o``).
_LINK_FLAGS = ("-ffast-math", "-Ofast", "-funsafe-math-optimizations", "-mdaz-ftz")


def check_flags(opts: "ControllerOptions", *, generated: bool) -> None:
    """Refuse (:class:`BuildError`, exit 1) a ``--cflags`` flag of
    :data:`FP_FLAGS` for a ``generated`` controller, and a ``--ldflags``
    flag that links ``crtfastmath.o`` in any case: what was proved with
    IEEE 754 semantics must run with them."""
    bad = [("--ldflags", f, fp_flag_problem(f, link=True)) for f in opts.ldflags]
    if generated:
        bad += [("--cflags", f, fp_flag_problem(f)) for f in opts.cflags]
    for what, f, why in bad:
        if why is not None:
            kind = ("the node links it into every object, the proved glue included" if what == "--ldflags"
                    else "the controller is generated from the block diagram and proved with IEEE 754 semantics (T6)")
            raise BuildError(f"{what}: {escape(f)!s}: refused: it {why}; {kind} [{FP_RULE}]")


def defines_main(p: Path, includes: Sequence[Path] = ()) -> bool:
    """Whether the source ``p`` defines ``main`` (Embedded Coder's
    ``ert_main.c``, a test harness), found by the preprocessor and a C
    parser (:func:`pyrosgen.frontend.csource.defines_main`)."""
    return csource.defines_main(p, includes)


def find_controller(model: NodeModel, directory: str | Path,
                    user_includes: Sequence[Path] = ()) -> ControllerDir:
    """Check the controller folder: it holds ``<Controller>.h`` (at its top)
    and at least one source; its sources (``.c``, ``.cpp``) and headers are
    found in its subfolders too (hidden folders excepted,
    :func:`pyrosgen.frontend.csource.controller_files`); sources that
    define ``main`` (``ert_main.c``), found by parsing each source
    preprocessed with the folder's include path and ``user_includes``
    (``--include``), are left out; file and folder names are plain (they
    go into CMakeLists.txt)."""
    d = Path(directory)
    if not d.is_dir():
        raise BuildError(f"{d}: controller folder not found")
    header = d / layout.controller_header_name(model)
    if not header.is_file():
        raise BuildError(
            f"{d}: no {header.name} in the controller folder (the model's controller "
            f"is {model.controller.name}: {model.controller.step_fn}() and "
            f"{model.controller.inputs.var_name}/{model.controller.outputs.var_name} "
            f"must be declared in {header.name})")
    files = csource.controller_files(d)
    for p in files:
        for part in p.relative_to(d).parts:
            if not _FILE_NAME.match(part):
                raise BuildError(f"{p}: unsupported file or folder name in the controller folder "
                                 "(letters, digits, '_', '.', '-' only)")
    includes = csource.include_dirs(d, files)
    search = [*includes, *(user_includes or ())]
    left_out, sources = [], []
    for p in files:
        if p.suffix in HEADER_SUFFIXES:
            continue
        if defines_main(p, search):
            left_out.append((p, "defines main (the node has its own)"))
        else:
            sources.append(p)
    if not sources:
        raise BuildError(f"{d}: no .c or .cpp file in the controller folder (the controller must define "
                         f"{model.controller.initialize_fn}() and {model.controller.step_fn}())")
    return ControllerDir(d, header, tuple(sources), tuple(files), tuple(includes), tuple(left_out))


def controller_setup(model: NodeModel, ctl: ControllerDir,
                     opts: ControllerOptions) -> tuple[list[str], list[str], list[str]]:
    """The notes on the controller folder (sources left out, a base rate
    that is not the model's period), the ``--include`` folders (absolute)
    and the ``-I`` options of the controller's compile commands."""
    warnings = [f"pyrosgen: note: {p}: left out of the build: {why}" for p, why in ctl.left_out]
    # the base rate the controller was generated for, as init reads it (ert_main.c too)
    rate, where, _ = find_period(ctl.path, [ctl.header, *(p for p in ctl.files if p != ctl.header)])
    if rate is not None and rate != model.period_ms:
        warnings.append(f"pyrosgen: note: the node steps the controller every {model.period_ms} ms "
                        f"(period_ms), but it was generated for {rate} ms ({where})")
    user_includes = [str(Path(i) if Path(i).is_absolute() else (ctl.path / i).absolute()) for i in opts.includes]
    ctl_includes = [a for inc in ctl.include_dirs for a in ("-I", str(inc.absolute()))] + \
        [a for inc in user_includes for a in ("-I", inc)]
    return warnings, user_includes, ctl_includes


def write_catkin_packages(model: NodeModel, node: ros.ProvedNode, stage: Path, ctl: ControllerDir,
                          opts: ControllerOptions, user_includes: list[str], sources: dict[str, Path],
                          generated: bool = False) -> dict:
    """Write the node's catkin package into ``stage/<package>/``: copies of
    the glue, the wrapper, the layout check and the headers (``src/``,
    ``include/``), the controller (``controller/``), ``package.xml``,
    ``CMakeLists.txt`` (the same flags as this build, the layout check as a
    build step) and ``launch/<node>.launch``, rendered from the proved
    ``node`` and the returned record (:func:`pyrosgen.ros.wrapper.package_record`,
    kept in the manifest so that ``verify`` renders them again); and a
    message package (``message_generation``) for each package of custom
    messages of the front end's ``model``."""
    pkg_dir = stage / ros.catkin_package_name(node)
    include_dirs, controller = copy_package_sources(pkg_dir, ros.catkin_paths(node), sources, ctl, opts,
                                                    user_includes, generated)
    custom = ros.custom_message_packages(model)
    record = ros.package_record(include_dirs, controller, sorted(custom), opts.maintainer)
    texts = ros.render_package_record(node, record)
    for pkg, msg_dir in sorted(custom.items()):
        msgs = {f.name: f.read_text(encoding="utf-8", errors="replace") for f in sorted(msg_dir.glob("*.msg"))}
        for rel, text in ros.render_msg_package(model.source.name, pkg, msgs).items():
            texts[f"../{pkg}/{rel}"] = text
    for rel, text in texts.items():
        dest = Path(os.path.normpath(pkg_dir / rel))
        dest.parent.mkdir(parents=True, exist_ok=True)
        dest.write_text(text, encoding="utf-8")
    for pkg, msg_dir in custom.items():
        (stage / pkg / "msg").mkdir(parents=True, exist_ok=True)
        for f in sorted(msg_dir.glob("*.msg")):
            shutil.copyfile(f, stage / pkg / "msg" / f.name)
    return record


def copy_package_sources(pkg_dir: Path, paths: dict[str, str], sources: dict[str, Path], ctl: ControllerDir,
                         opts: ControllerOptions, user_includes: list[str],
                         generated: bool) -> tuple[list[str], ros.CatkinController]:
    """Copy a node package's sources into ``pkg_dir`` (catkin's or ROS 2's):
    each of ``sources`` (by key) to its package-relative path in ``paths``,
    the controller's files under ``controller/``; return the package's
    include folders and how it compiles the controller (as this build does)."""
    for key, src in sources.items():
        dest = pkg_dir / paths[key]
        dest.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(src, dest)
    for p in ctl.files:
        dest = pkg_dir / "controller" / ctl.rel(p)
        dest.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(p, dest)
    ctl_c = [f"controller/{ctl.rel(p)}" for p in ctl.sources if p.suffix in C_SUFFIXES]
    ctl_cxx = [f"controller/{ctl.rel(p)}" for p in ctl.sources if p.suffix in CXX_SUFFIXES]
    include_dirs = ["include"] + ["controller" if inc == ctl.path else
                                  f"controller/{inc.relative_to(ctl.path).as_posix()}" for inc in ctl.include_dirs]
    return include_dirs, ros.CatkinController(
        c_sources=ctl_c, cxx_sources=ctl_cxx, std=opts.std, cflags=list(opts.cflags),
        cxxflags=list(opts.cxxflags), includes=user_includes, ldflags=list(opts.ldflags), libs=list(opts.libs),
        generated=generated)


#: The option that maps a folder's name in what the compiler writes into the
#: object (``__FILE__``, debugging information) to another (GCC 8).
PREFIX_MAP = "-ffile-prefix-map="


def _reproducible(argv: Sequence[str], stage: Path, controller: Path | None, *, compile: bool) -> list[str]:
    """A compile (or link) command that gives the same object (or binary),
    bit for bit, wherever the staging folder and the controller folder are,
    so that ``verify --rebuild`` can compare the binary: the command runs
    in the staging folder and names its files relative to it; a compile
    command ends with ``-ffile-prefix-map`` options that write the staging
    folder as ``.`` and, for a source of the ``controller`` folder, that
    folder as ``controller`` (its copy in ``OUT``, compiled under that name
    by ``verify --rebuild``; only there, so that the glue's and the
    wrapper's objects are reused when the controller folder moves).  The rest
    is deterministic already: no generated file uses ``__DATE__`` or
    ``__TIME__``, the objects are linked in a fixed order, and the linker's
    build-id is a hash of the binary's contents."""
    s = str(stage)
    out = [a[len(s) + 1:] if a.startswith(s + "/") else "." if a == s else a for a in argv]
    if compile:
        out.append(f"{PREFIX_MAP}{s}=.")
    if compile and controller is not None:
        out.append(f"{PREFIX_MAP}{controller.absolute()}=controller")
    return out


def _shown_argv(argv: Sequence[str], stage: Path, controller: Path) -> list[str]:
    """A compiler command as the certificate shows it: paths in the staging
    folder relative to ``OUT`` (the command runs in it), the controller
    folder as ``OUT``'s copy ``controller`` (in a ``-ffile-prefix-map``
    option too)."""
    out = []
    for a in argv:
        if a.startswith(PREFIX_MAP) and "=" in a[len(PREFIX_MAP):]:
            old, new = a[len(PREFIX_MAP):].rsplit("=", 1)
            out.append(PREFIX_MAP + _shown_argv([old], stage, controller)[0] + "=" + new)
            continue
        for folder, shown in ((str(stage), "."), (str(controller.absolute()), "controller")):
            if a == folder:
                a = shown
                break
            if a.startswith(folder + "/"):
                a = a[len(folder) + 1:] if shown == "." else shown + a[len(folder):]
                break
        out.append(a)
    return out


# -- the stamp file and the object cache -------------------------------------------

class _Cache:
    """Objects and binary of the previous build in ``OUT``, by input hash."""

    def __init__(self, out_dir: Path):
        self.out_dir = out_dir
        self.old: dict = {}
        try:
            data = json.loads((out_dir / STAMP).read_text(encoding="utf-8"))
            if isinstance(data, dict) and data.get("version") == _STAMP_VERSION:
                self.old = data
        except (OSError, ValueError):
            pass
        self.entries: dict[str, str] = {}
        #: the digest of what the proof in ``OUT`` was made from (:func:`_proof_key`)
        self.proof: str | None = None

    @property
    def old_files(self) -> list[str]:
        files = self.old.get("files", [])
        return [f for f in files if isinstance(f, str)]

    def reuse(self, rel: str, key: str, dest: Path) -> bool:
        """Copy ``OUT/rel`` to ``dest`` if it was made from inputs with hash ``key``."""
        self.entries[rel] = key
        if self.old.get("entries", {}).get(rel) != key:
            return False
        src = self.out_dir / rel
        if not src.is_file():
            return False
        dest.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(src, dest)
        return True

    def stamp(self, files: list[str]) -> str:
        return json.dumps({"version": _STAMP_VERSION, "entries": self.entries, "files": files,
                           **({"proof": self.proof} if self.proof else {})},
                          indent=1, sort_keys=True) + "\n"


# -- reusing the proof of the previous build ------------------------------------------

def _proof_key(model: NodeModel, drv: CoqDriver, target: str | None = None) -> str | None:
    """The digest of everything the proof folder is made from: the model
    file's name and bytes, the front end's reading of it (the model text,
    which holds every message type it uses, field by field), the library's
    digest, pyrosgen's version and the ``target`` (``None``: ROS 1).  A
    controller-only change leaves it unchanged."""
    from pyrosgen import __version__
    from pyrosgen.proof.modeltext import model_text

    h = hashlib.sha256()
    src = Path(model.source)
    try:
        parts = (b"pyrosgen-proof-1", __version__.encode(), drv.library_digest().encode(), src.name.encode(),
                 src.read_bytes() if src.is_file() else b"", model_text(model).encode(),
                 *((f"target {target}".encode(),) if target else ()))
    except OSError:
        return None  # no library, an unreadable model file: generate proves (and says what is wrong)
    for part in parts:
        h.update(_sha(part).encode())
    return h.hexdigest()


def prove(model: NodeModel, out_dir: Path, stage: Path, cache: "_Cache", say: Callable[[str], None], *,
          keep_work: bool, driver, wp: bool, msg_root: Path | None = None, target: str | None = None,
          steps: int = STEPS) -> GenerateResult:
    """Step 2 of both targets' builds: the proof of the previous build in
    ``OUT`` when the model, its messages, the library, pyrosgen and the
    ``target`` are unchanged (a controller-only change), else the pipeline
    of :mod:`pyrosgen.generate` into ``stage`` (``msg_root``: the target's
    standard ``.msg`` files for the second reading)."""

    def sub(line: str) -> None:
        say(f"[2/{steps}] generate: " + re.sub(r"^\[\d+/\d+\] ", "", line).replace(str(stage), str(out_dir)))

    drv = driver or CoqDriver()
    cache.proof = _proof_key(model, drv, target)
    gen = None if wp or cache.proof is None else _reuse_proof(model, out_dir, stage, cache, cache.proof)
    if gen is not None:
        say(f"[2/{steps}] generate: proof reused from {out_dir} (the model, its messages, the library "
            "and pyrosgen are unchanged)")
        return gen
    return generate_model(model, stage, progress=sub, keep_work=keep_work, driver=drv, wp=wp,
                          target=target or "ros1", **({"msg_root": msg_root} if msg_root is not None else {}))


def _reuse_proof(model: NodeModel, out_dir: Path, stage: Path, cache: "_Cache", key: str) -> GenerateResult | None:
    """The previous build's proof, copied from ``OUT`` into ``stage``, when
    ``OUT``'s stamp records the same :func:`_proof_key` and every file of
    the proof in ``OUT`` has the digest its manifest records; else
    ``None`` (then ``generate`` proves again)."""
    if cache.old.get("proof") != key:
        return None
    try:
        rec, digests = read_manifest(out_dir / certificate_files(model.name)[1])
    except (ManifestError, ValueError, OSError):
        return None
    if rec.node != model.name or rec.wp is not None:
        return None
    covered = [rec.node_v, rec.types_h, rec.glue_c, rec.sexp, rec.model_file]
    if rec.controller:
        covered += [rec.controller["c"], rec.controller["sexp"], rec.controller["text"]]
    for name in covered:
        p = out_dir / name
        if p.is_symlink() or not p.is_file() or digests.get(name) != sha256_file(p):
            return None
    for name in covered:
        shutil.copyfile(out_dir / name, stage / name)
    rec.build = None
    return GenerateResult(
        model=model, out_dir=out_dir, files=[(out_dir / name, False) for name in covered], theorem=rec.theorem,
        theorem_kind=theorem_kind(rec.ddc), theorems=list(rec.theorems), ddc=rec.ddc,
        proved_model=(stage / rec.model_file).read_text(encoding="utf-8"), record=rec, covered=covered)


def _key(argv: Sequence[str], stage: Path, identity: str, inputs: Sequence[Path], extra: Sequence[str] = ()) -> str:
    h = hashlib.sha256()
    s = str(stage)
    h.update(json.dumps([a.replace(s, "$OUT") for a in argv]).encode())
    h.update(identity.encode())
    for x in extra:
        h.update(b"\0" + x.encode())
    for p in inputs:
        h.update(b"\0" + str(p).replace(s, "$OUT").encode() + b"\0" + _sha(p.read_bytes()).encode())
    return h.hexdigest()


# -- installing into OUT ----------------------------------------------------------

def _all_files(root: Path) -> list[str]:
    return sorted(str(p.relative_to(root)) for p in root.rglob("*") if p.is_file() or p.is_symlink())


def _same(a: Path, b: Path) -> bool:
    try:
        return b.is_file() and a.stat().st_size == b.stat().st_size and a.read_bytes() == b.read_bytes() \
            and (a.stat().st_mode & 0o111) == (b.stat().st_mode & 0o111)
    except OSError:
        return False


def _install(stage: Path, out_dir: Path, old_files: list[str], backup_dir: Path,
             on_wait=None) -> list[tuple[Path, bool]]:
    """Move every file of ``stage`` into ``out_dir`` (only the changed
    ones), then remove the files of ``old_files`` not produced any more;
    undo everything on an error."""
    files = _all_files(stage)
    created = not out_dir.exists()
    try:
        out_dir.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise BuildError(f"cannot create {out_dir}: {exc.strerror or exc}") from None
    try:
        # one run at a time installs into a folder (see pyrosgen.files.locked_folder)
        with locked_folder(out_dir, on_wait):
            return _install_files(stage, out_dir, files, old_files, backup_dir)
    except BaseException:
        if created:
            shutil.rmtree(out_dir, ignore_errors=True)
        raise


def _install_files(stage: Path, out_dir: Path, files: list[str], old_files: list[str],
                   backup_dir: Path) -> list[tuple[Path, bool]]:
    done: list[tuple[Path, Path | None]] = []
    result: list[tuple[Path, bool]] = []
    removed: list[tuple[Path, Path]] = []
    try:
        for rel in files:
            src, target = stage / rel, out_dir / rel
            if _same(src, target):
                result.append((target, False))
                continue
            backup = None
            if target.exists() or target.is_symlink():
                backup = backup_dir / rel
                backup.parent.mkdir(parents=True, exist_ok=True)
                move(target, backup)
            target.parent.mkdir(parents=True, exist_ok=True)
            move(src, target)
            done.append((target, backup))
            result.append((target, True))
        new = set(files)
        for rel in old_files:
            target = out_dir / rel
            if rel in new or ".." in Path(rel).parts or Path(rel).is_absolute():
                continue
            if target.is_file():
                backup = backup_dir / "removed" / rel
                backup.parent.mkdir(parents=True, exist_ok=True)
                move(target, backup)
                removed.append((target, backup))
    except OSError as exc:
        for target, backup in reversed(removed):
            try:
                move(backup, target)
            except OSError:
                pass
        for target, backup in reversed(done):
            try:
                if backup is not None:
                    move(backup, target)
                else:
                    target.unlink()
            except OSError:
                pass
        raise BuildError(f"cannot write into {out_dir}: {exc.strerror or exc}") from None
    for target, _ in removed:  # drop folders left empty by removed files
        parent = target.parent
        while parent != out_dir and parent.is_dir() and not any(parent.iterdir()):
            parent.rmdir()
            parent = parent.parent
    return result


def proved_node_of(gen: GenerateResult, model: NodeModel):
    """The proved model and node (:func:`pyrosgen.ros.wrapper.proved_node`)
    of a proof, which both targets render their files from; checked equal
    to the front end's ``model`` (messages and controller structs)."""
    proved = parse_model_text(gen.proved_model)
    pnode = ros.proved_node(proved, gen.record.source_name)
    if (pnode.messages != tuple(model.messages) or pnode.controller.inputs != model.controller.inputs
            or pnode.controller.outputs != model.controller.outputs):
        raise BuildToolError("the proved model's messages or controller structs are not the front end's "
                             "(a pyrosgen bug: the model texts were compared equal)")
    return proved, pnode


def write_wrapper(stage: Path, glue_c: str, api_header: str, api_source: str, texts: dict[str, str],
                  check_source: Callable[[str, str], None]) -> None:
    """Write the wrapper files ``texts`` (by name) into ``stage``: the
    source held to the proved model by ``check_source(text, name)``, the
    header's functions to the glue's externals (the ROS functions the glue
    calls, with the glue's C types)."""
    for fname, text in texts.items():
        if fname == api_source:
            check_source(text, fname)
        if fname == api_header:
            check_glue_externals((stage / glue_c).read_text(encoding="utf-8"), text,
                                 glue_name=glue_c, header_name=fname)
        (stage / fname).write_text(text, encoding="ascii")


# -- compiling and linking a node (both targets) -----------------------------------------

class NodeCompiler:
    """The compile and link steps of a node, shared by the ROS 1 build and
    the ROS 2 build (:mod:`pyrosgen.ros2.build`): each command made
    reproducible (:func:`_reproducible`) and recorded as the certificate
    shows it (``commands``, the manifest's ``build.commands``, which
    ``verify --rebuild`` runs again), an object and the binary reused from
    the previous build in ``OUT`` when the hash of everything they are made
    from is unchanged (:class:`_Cache`), a failure classified: the user's
    controller (:class:`ControllerError`, exit 1) or generated code
    (:class:`BuildToolError`, exit 2).  Objects go to ``stage/obj``."""

    def __init__(self, stage: Path, out_dir: Path, ctl: ControllerDir, cache: "_Cache",
                 say: Callable[[str], None], warnings: list[str], steps: list[tuple[str, bool]],
                 commands: list[list[str]] | None = None, total: int = STEPS):
        self.stage, self.out_dir, self.ctl, self.cache, self.say = stage, out_dir, ctl, cache, say
        self.warnings, self.steps, self.total = warnings, steps, total
        self.commands: list[list[str]] = list(commands or [])
        self.objects: list[Path] = []
        self.keys: list[str] = []
        self.obj = stage / "obj"
        self.obj.mkdir(exist_ok=True)

    def _shown(self, text: str) -> str:
        return text.replace(str(self.stage), str(self.out_dir))

    def compile(self, step: int, what: str, tool: list[str], ident: str, flags: Sequence[str],
                src: Path, out_name: str, inputs: Sequence[Path], user: bool) -> None:
        """Compile ``src`` into ``obj/out_name`` (or reuse it); ``user``: a
        source of the controller (its errors are the user's, its warnings
        shown)."""
        out = self.obj / out_name
        ctl_path = self.ctl.path
        argv = _reproducible([*tool, *flags, "-c", str(src), "-o", str(out)], self.stage,
                             ctl_path if user else None, compile=True)
        self.commands.append(_shown_argv(argv, self.stage, ctl_path))
        key = _key(argv, self.stage, ident, [src, *inputs])
        self.keys.append(key)
        self.objects.append(out)
        if self.cache.reuse(f"obj/{out_name}", key, out):
            self.say(f"[{step}/{self.total}] {what}: {src.name} unchanged, reusing obj/{out_name}")
            self.steps.append((f"obj/{out_name}", False))
            return
        self.say(f"[{step}/{self.total}] {what}: {' '.join(tool)} {src.name}")
        r = _run(argv, f"compiling {src.name}", cwd=self.stage)
        if r.returncode != 0:
            msg = _clip(self._shown(r.stderr + r.stdout))
            if user:
                raise ControllerError(f"{ctl_path / src.name}: error: the controller source does not compile "
                                      f"({' '.join(tool)} exit status {r.returncode})", msg.splitlines())
            raise BuildToolError(f"{' '.join(tool)} failed on generated code {self.out_dir / src.name} "
                                 f"(exit status {r.returncode})", msg.splitlines())
        if user and (r.stderr.strip() or r.stdout.strip()):
            self.warnings.extend(_clip(r.stderr + r.stdout).splitlines())
        self.steps.append((f"obj/{out_name}", True))

    def compile_controller(self, step: int, cc: tuple[list[str], str], cxx: tuple[list[str], str],
                           opts: ControllerOptions, ctl_includes: list[str], *, generated: bool) -> None:
        """Every source of the controller: C with ``-std=<--std>``,
        :data:`CONTROLLER_CFLAGS`, ``--cflags`` (and, when ``generated``
        from a block diagram, the IEEE flags after them), C++ with
        :data:`CONTROLLER_CXXFLAGS` and ``--cxxflags``; ``-I`` each folder
        holding headers and each ``--include``."""
        ctl = self.ctl
        for src in ctl.sources:
            cxx_src = src.suffix in CXX_SUFFIXES
            flags = ([*CONTROLLER_CXXFLAGS, *opts.cxxflags] if cxx_src else
                     [f"-std={opts.std}", *CONTROLLER_CFLAGS, *opts.cflags,
                      *(ros.IEEE_CFLAGS if generated else ())]) + ctl_includes
            tool, ident = cxx if cxx_src else cc
            self.compile(step, "compile controller", tool, ident, flags, src.absolute(), _controller_object(ctl, src),
                         [p.absolute() for p in ctl.files if p != src], user=True)

    def link(self, step: int, model: NodeModel, tool: list[str], ident: str, before: Sequence[str],
             after: Sequence[str], own_libs: Sequence[str] = ()) -> Path:
        """Link ``bin/<node>``: ``tool before OBJECTS -o bin/<node> after``
        (or reuse it); a failure the controller causes (a symbol it does not
        define, ``main`` twice, a library of ``--libs`` not found: any
        ``-l`` but ``own_libs``) is the user's."""
        node = model.name
        (self.stage / "bin").mkdir(exist_ok=True)
        binary = self.stage / "bin" / node
        argv = _reproducible([*tool, *before, *(str(o) for o in self.objects), "-o", str(binary), *after],
                             self.stage, None, compile=False)
        self.commands.append(_shown_argv(argv, self.stage, self.ctl.path))
        key = _key(argv, self.stage, ident, [], extra=self.keys)
        if self.cache.reuse(f"bin/{node}", key, binary):
            self.say(f"[{step}/{self.total}] link: objects unchanged, reusing bin/{node}")
            self.steps.append((f"bin/{node}", False))
            return binary
        self.say(f"[{step}/{self.total}] link: bin/{node}")
        r = _run(argv, f"linking {node}", cwd=self.stage)
        if r.returncode != 0:
            _link_failure(model, self.ctl, _clip(self._shown(r.stderr + r.stdout)), r.returncode, own_libs)
        self.steps.append((f"bin/{node}", True))
        return binary


def _controller_object(ctl: ControllerDir, src: Path) -> str:
    return "controller_" + ctl.rel(src).replace("/", "__").rsplit(".", 1)[0] + ".o"


def _link_failure(model: NodeModel, ctl: ControllerDir, msg: str, status: int, own_libs: Sequence[str]):
    """Raise the error of a failed link: the controller's (exit 1) when it
    is at fault, else :class:`BuildToolError`."""
    node = model.name
    # An undefined controller symbol is the user's; anything else is ours.
    ctl_names = (model.controller.step_fn, model.controller.initialize_fn,
                 model.controller.inputs.var_name, model.controller.outputs.var_name)
    if any(f"undefined reference to `{n}'" in msg for n in ctl_names):
        raise ControllerError(f"{ctl.path}: error: the controller does not define what "
                              "the glue uses", msg.splitlines())
    # a link error in the controller's objects (a symbol defined twice, a
    # library missing) is the user's too: name the source at fault
    at_fault = [src for src in ctl.sources if _controller_object(ctl, src) in msg]
    if "multiple definition of `main'" in msg:
        where = ", ".join(str(p) for p in at_fault) or str(ctl.path)
        raise ControllerError(
            f"{where}: error: the controller defines main, and so does the node (exit status "
            f"{status}); pyrosgen leaves out a source that defines main, but did not "
            "recognise this definition: move that main out of the controller folder (a file "
            "of its own outside it, or under #ifndef PYROSGEN_NODE with --cflags=-DPYROSGEN_NODE)",
            msg.splitlines())
    missing_own = any(f"cannot find -l{lib}" in msg for lib in own_libs)
    if at_fault or "cannot find -l" in msg and not missing_own:
        where = ", ".join(str(p) for p in at_fault) or str(ctl.path)
        raise ControllerError(f"{where}: error: the controller does not link (exit status "
                              f"{status})", msg.splitlines())
    raise BuildToolError(f"linking {node} failed (exit status {status})", msg.splitlines())


def finish_build(gen: GenerateResult, node: str, stage: Path, out_dir: Path, work: Path, cache: "_Cache",
                 say: Callable[[str], None], record: dict, step: int = STEPS) -> list[tuple[Path, bool]]:
    """The last step of both targets' builds: the manifest's build
    ``record`` (what the package files are rendered from, the compile
    commands), the certificate again, now covering what the build added
    (the wrapper, the layout check, the controller, the package, the
    binary; not ``obj/``), the stamp file, then everything installed into
    ``out_dir``."""
    gen.record.build = record
    cert_files = set(certificate_files(node))
    covered = [f for f in _all_files(stage) if not f.startswith("obj/") and f not in cert_files]
    write_certificate(gen.record, stage, covered)
    files = _all_files(stage) + [STAMP]
    (stage / STAMP).write_text(cache.stamp(sorted(files)), encoding="utf-8")
    say(f"[{step}/{step}] installing into {out_dir}")
    return _install(stage, out_dir, cache.old_files, work / "backup", on_wait=lambda: say(
        f"[{step}/{step}] waiting for another pyrosgen run writing into {out_dir}"))


# -- the build ----------------------------------------------------------------------

def build(model_path: str | Path, controller_dir: str | Path, out_dir: str | Path, *,
          progress: Callable[[str], None] | None = None, keep_work: bool = False,
          driver=None, wp: bool = False, options: ControllerOptions | None = None) -> BuildResult:
    """Build the node of the model file ``model_path`` with the controller
    in ``controller_dir`` into ``out_dir``; see the module documentation.

    Raises :class:`~pyrosgen.errors.InvalidNodeModel`, :class:`BuildError`,
    :class:`~pyrosgen.ros.layout.LayoutMismatch`,
    :class:`~pyrosgen.generate.OutputDirError` (exit 1), and
    :class:`BuildToolError`, :class:`~pyrosgen.ros.layout.LayoutToolError`,
    :class:`~pyrosgen.proof.coqdriver.CoqError` (exit 2).
    """
    say = progress or (lambda _line: None)
    t0 = time.monotonic()
    _check_out_dir(out_dir)  # -o "" is refused, as generate refuses it
    say(f"[1/{STEPS}] front end: reading {model_path}")
    model = load_model(model_path)
    return build_model(model, controller_dir, out_dir, progress=progress, keep_work=keep_work,
                       driver=driver, wp=wp, options=options, _t_start=t0)


def check_build_request(model: NodeModel, out_dir: str | Path, controller_dir: str | Path | None,
                        options: "ControllerOptions | None") -> tuple[Path, "ControllerOptions", bool]:
    """What every target's ``build`` checks before anything runs: the output
    folder (``-o ""`` refused, as ``generate`` does), the options (the
    floating-point flags of DESIGN.md section 7), and that a block-diagram
    controller takes no ``--controller`` and a C one needs it.  Returns the
    output folder, the options and whether the controller is a diagram."""
    out_dir = _check_out_dir(out_dir)
    if out_dir.exists() and not out_dir.is_dir():
        raise OutputDirError(f"{out_dir}: exists and is not a directory")
    opts = options or ControllerOptions()
    opts.check()
    diagram = getattr(model.controller, "diagram", None) is not None
    # what was proved with IEEE 754 semantics runs with them
    check_flags(opts, generated=diagram)
    if diagram and controller_dir is not None:
        raise BuildError(f"{model.source}: the controller is a block diagram (controller.blocks): "
                         "pyrosgen generates its C; --controller is for a controller written in C")
    if not diagram and controller_dir is None:
        raise BuildError("--controller DIR is required: the model's controller is not a block diagram")
    return out_dir, opts, diagram


def build_model(model: NodeModel, controller_dir: str | Path, out_dir: str | Path, *,
                progress: Callable[[str], None] | None = None, keep_work: bool = False,
                driver=None, wp: bool = False, options: ControllerOptions | None = None,
                _t_start: float | None = None) -> BuildResult:
    """:func:`build` on an already loaded ``model``; ``wp`` also proves
    the ACSL contracts with Frama-C WP (as ``generate --wp``)."""
    say = progress or (lambda _line: None)
    t_start = _t_start if _t_start is not None else time.monotonic()
    times: dict[str, float] = {}
    out_dir, opts, diagram = check_build_request(model, out_dir, controller_dir, options)
    missing = msgdeb.missing_headers(model)
    if missing:
        # refused before proving: the wrapper could not be compiled
        raise BuildToolError(
            f"{model.source}: the C++ headers of {len(missing)} message type{'s' if len(missing) > 1 else ''} "
            "of the model are not installed", [
                f"{model.source}:{m.pos.line}:{m.pos.col}: error: {m.message()}" if m.pos.line else
                f"{model.source}: error: {m.message()}" for m in missing])
    ctl = find_controller(model, controller_dir, [
        Path(i) if Path(i).is_absolute() else Path(controller_dir, i).absolute() for i in opts.includes
    ]) if not diagram else None
    cc, cxx = _tool("CC", "gcc"), _tool("CXX", "g++")
    names = ros.wrapper_files(model)
    node = model.name
    glue_c = f"{node}_glue.c"
    check_c = f"{node}_layout_check.c"
    times["front end"] = time.monotonic() - t_start

    base = _existing_ancestor(out_dir.parent if out_dir.name else out_dir)
    try:
        work = Path(tempfile.mkdtemp(prefix=f".pyrosgen-build-{node}-", dir=str(base)))
    except OSError as exc:
        raise BuildError(f"cannot create a work directory in {base}: {exc.strerror or exc}") from None
    stage = work / "out"
    cache = _Cache(out_dir)
    steps: list[tuple[str, bool]] = []
    if ctl is not None:
        warnings, user_includes, ctl_includes = controller_setup(model, ctl, opts)

    def shown(text: str) -> str:
        return text.replace(str(stage), str(out_dir))

    try:
        stage.mkdir()
        # 2. generate (its own steps, as sub-steps)
        t = time.monotonic()

        gen = prove(model, out_dir, stage, cache, say, keep_work=keep_work, driver=driver, wp=wp)
        times["generate"] = time.monotonic() - t
        types_h = (stage / names.types_header).read_text(encoding="ascii")
        if diagram:
            # The controller Coq printed from the diagram, as an Embedded
            # Coder folder: <Controller>.c and a <Controller>.h that the
            # layout check holds against the glue.
            cdir = work / "controller"
            cdir.mkdir()
            (cdir / f"{model.controller.name}.c").write_bytes(
                (stage / node_file_names(node).controller_c).read_bytes())
            (cdir / layout.controller_header_name(model)).write_text(
                layout.render_reference_header(ros.proved_node(parse_model_text(gen.proved_model),
                                                               gen.record.source_name), types_h), encoding="ascii")
            ctl = find_controller(model, cdir)
            warnings, user_includes, ctl_includes = controller_setup(model, ctl, opts)

        # 3. wrapper, custom messages, controller copy, catkin files
        say(f"[3/{STEPS}] wrapper: C API over roscpp, gencpp, catkin package")
        t = time.monotonic()
        # the wrapper, the layout check and the catkin files are rendered
        # from the proved model alone (verify renders them again from it)
        _, pnode = proved_node_of(gen, model)
        # The node registers and sleeps as the proved model says.
        write_wrapper(stage, glue_c, names.api_header, names.api_source, ros.render_wrapper(pnode),
                      lambda text, fname: check_wrapper(text, gen.proved_model, wrapper_name=fname))
        include = stage / "include"
        try:
            custom_headers = ros.generate_custom_cpp(model, include)
        except ros.ToolError as exc:
            raise BuildToolError(str(exc).splitlines()[0], str(exc).splitlines()[1:]) from None
        (stage / "controller").mkdir()
        for p in ctl.files:
            dest = stage / "controller" / ctl.rel(p)
            dest.parent.mkdir(parents=True, exist_ok=True)
            shutil.copyfile(p, dest)
        modules = ros.ros_pkg_config_modules(model)
        pc_cflags, pc_libs = pkg_config(modules)
        times["wrapper"] = time.monotonic() - t

        # 4. layout check
        say(f"[4/{STEPS}] layout check: "
            f"{ctl.header.name + ' (generated from the diagram)' if diagram else ctl.header} against {names.types_header}")
        t = time.monotonic()
        (stage / check_c).write_text(layout.render_layout_check(pnode, types_h, names.types_header), encoding="ascii")
        layout_cmds = layout.check_layout(model, stage / check_c, ctl.path, work, types_h, cc=cc,
                            shown_check=str(out_dir / check_c), includes=ctl_includes)
        times["layout check"] = time.monotonic() - t

        # the catkin package OUT/<package>/ (sources only) and, for custom
        # messages, their message packages OUT/<pkg>/
        package = write_catkin_packages(model, pnode, stage, ctl, opts, user_includes,
                              {"glue": stage / glue_c, "wrapper": stage / names.api_source,
                               "layout_check": stage / check_c, "types_header": stage / names.types_header,
                               "api_header": stage / names.api_header}, generated=diagram)

        cc_id, cxx_id = _compiler_identity(cc), _compiler_identity(cxx)
        # every compiler call, as the certificate shows it (the layout check's
        # reference header is in the work folder: shown as layout-reference)
        comp = NodeCompiler(stage, out_dir, ctl, cache, say, warnings, steps, commands=[
            [str(Path("layout-reference") / a[len(str(work / "layout-reference")) + 1:])
             if a.startswith(str(work / "layout-reference") + "/") else
             "layout-reference" if a == str(work / "layout-reference") else a
             for a in _shown_argv(c, stage, ctl.path)] for c in layout_cmds])
        # 5. glue
        t = time.monotonic()
        comp.compile(5, "compile glue", cc, cc_id, [*GLUE_CFLAGS, "-I", str(stage)],
                     stage / glue_c, f"{node}_glue.o", [stage / names.types_header], user=False)
        times["glue"] = time.monotonic() - t
        # 6. controller (before the slow wrapper: user errors first)
        t = time.monotonic()
        comp.compile_controller(6, (cc, cc_id), (cxx, cxx_id), opts, ctl_includes, generated=diagram)
        times["controller"] = time.monotonic() - t

        # 7. wrapper
        t = time.monotonic()
        wrapper_inputs = [stage / names.types_header, stage / names.api_header, *custom_headers]
        wflags = [*WRAPPER_CXXFLAGS, "-I", str(stage)] + (["-I", str(include)] if custom_headers else []) + pc_cflags
        comp.compile(7, "compile wrapper", cxx, cxx_id, wflags, stage / names.api_source,
                     f"{node}_ros.o", wrapper_inputs, user=False)
        times["wrapper compile"] = time.monotonic() - t
        # 8. link and install
        t = time.monotonic()
        comp.link(8, model, cxx, cxx_id, [*LDFLAGS, *opts.ldflags], [*pc_libs, *opts.libs, *LDLIBS])
        # what the catkin files are rendered from, and the compile commands
        installed = finish_build(gen, node, stage, out_dir, work, cache, say,
                                 {"package": package, "commands": comp.commands})
        times["link and install"] = time.monotonic() - t
    finally:
        if keep_work:
            say(f"work directory kept: {work}")
        else:
            shutil.rmtree(work, ignore_errors=True)
    times["total"] = time.monotonic() - t_start
    return BuildResult(model=model, out_dir=out_dir, binary=out_dir / "bin" / node, generated=gen,
                       files=installed, steps=steps, warnings=warnings, times=times)

"""Reading a controller folder as Embedded Coder writes it: its files, its
include folders, the C preprocessor, and which sources define ``main``.

Embedded Coder writes a model's code into ``<Model>_ert_rtw/`` and the
code it shares between models into ``slprj/ert/_sharedutils/`` (``rtwtypes.h``,
``rt_*`` utilities), a referenced model's code into ``slprj/ert/<Ref>/``,
and an example main program, ``ert_main.c``.  ``pyrosgen init`` and
``pyrosgen build`` see a folder the same way (:func:`controller_files`,
:func:`include_dirs`): every source and header of the folder and of its
subfolders (hidden folders excepted), with every folder that holds a header
on the include path, the folder itself first, then the user's
``--include`` folders.

A source that *defines* ``main`` (``ert_main.c``, a test harness) is left
out of the node, which has its own.  Whether it does is found by parsing,
not by pattern matching (:func:`defines_main`): the source is run through
the C preprocessor (the folder's include path and pyrosgen's minimal
standard headers ``fake_libc/``, so that a ``main`` behind a macro is
seen and comments are gone), then parsed by pycparser (a ``FuncDef``
named ``main`` at file scope: ``int_T main(int_T argc, const char
*argv[])``, ``int main(void)``, K&R forms); when pycparser cannot parse the
file (C++, compiler extensions), a token scan of the preprocessed text
finds the identifier ``main`` at brace depth 0 followed by a parenthesised
list and then ``{`` (after K&R parameter declarations, if any).  When the
preprocessor fails with the minimal headers (a system header they lack),
the system's headers are used; when it fails even so, the token scan reads
the source with its comments and string literals removed.
"""

from __future__ import annotations

import re
import subprocess
from collections.abc import Iterable, Sequence
from pathlib import Path

from pyrosgen import procs

__all__ = [
    "FAKE_LIBC",
    "C_SUFFIXES",
    "CXX_SUFFIXES",
    "HEADER_SUFFIXES",
    "PreprocessorError",
    "controller_files",
    "include_dirs",
    "preprocess",
    "defines_main",
]

#: Minimal standard headers used instead of the system's.
FAKE_LIBC = Path(__file__).resolve().parent / "fake_libc"

#: Suffixes of the controller's sources and headers.
C_SUFFIXES = (".c",)
CXX_SUFFIXES = (".cpp", ".cc", ".cxx")
HEADER_SUFFIXES = (".h", ".hpp", ".hh")

#: The C standard the preprocessor is run in (``__STDC_VERSION__`` 201112L,
#: set by ``-std``, not by a ``-D`` that the preprocessor reports as a
#: redefinition of a built-in macro).
CPP_STD = "-std=c11"
#: Seconds the preprocessor may take on one file.
CPP_TIMEOUT = 60


class PreprocessorError(Exception):
    """The C preprocessor could not be run, or failed (``args[0]``: why;
    ``lines``: its first messages)."""

    def __init__(self, message: str, lines: Sequence[str] = ()):
        super().__init__(message)
        self.lines = tuple(lines)


def controller_files(folder: Path) -> list[Path]:
    """The sources and headers of ``folder`` and of its subfolders (hidden
    files and folders excepted), sorted."""
    wanted = C_SUFFIXES + CXX_SUFFIXES + HEADER_SUFFIXES
    return sorted(p for p in folder.rglob("*")
                  if p.suffix in wanted and p.is_file()
                  and not any(part.startswith(".") for part in p.relative_to(folder).parts))


def include_dirs(folder: Path, files: Iterable[Path]) -> list[Path]:
    """The include path of a controller folder: the folder first, then
    every subfolder that holds a header (``slprj/ert/_sharedutils``, a
    referenced model's ``slprj/ert/<Ref>``), sorted."""
    return [folder] + sorted({p.parent for p in files if p.suffix in HEADER_SUFFIXES and p.parent != folder})


def preprocess(source: Path, includes: Sequence[Path], *, system_headers: bool = False) -> str:
    """The text of ``source`` after the C preprocessor, with ``includes``
    on the include path; the standard headers are pyrosgen's minimal ones
    (``fake_libc/``) unless ``system_headers``.  Raises
    :class:`PreprocessorError`."""
    argv = ["cpp", CPP_STD]
    if not system_headers:
        argv += ["-nostdinc", "-undef", "-I", str(FAKE_LIBC)]
    for inc in includes:
        argv += ["-I", str(inc)]
    argv.append(str(source))
    try:
        r = procs.run(argv, timeout=CPP_TIMEOUT)
    except OSError as exc:
        raise PreprocessorError(f"cannot run the C preprocessor cpp: {exc.strerror or exc} (install gcc)") from None
    except subprocess.TimeoutExpired:
        raise PreprocessorError(f"{source}: the C preprocessor did not finish within {CPP_TIMEOUT} s") from None
    if r.returncode != 0:
        raise PreprocessorError(f"{source}: error: the C preprocessor failed", r.stderr.strip().splitlines()[:10])
    return r.stdout


# -- does a source define main? ------------------------------------------------

_TOKEN = re.compile(r"""
    (?P<skip>\s+|//[^\n]*|/\*.*?\*/)
  | (?P<str>[uUL]?(?:u8)?"(?:\\.|[^"\\\n])*"|[uUL]?'(?:\\.|[^'\\\n])*')
  | (?P<id>[A-Za-z_$][A-Za-z0-9_$]*)
  | (?P<num>\.?[0-9](?:[eEpP][+-]|[A-Za-z0-9_.])*)
  | (?P<punct>::|->|\.\.\.|[^\sA-Za-z0-9_])
""", re.S | re.X)


def _tokens(text: str) -> list[str]:
    """The C tokens of ``text`` (comments, string and character literals
    kept as one token each, then dropped; preprocessor line markers and
    directives dropped)."""
    text = "\n".join("" if ln.lstrip().startswith("#") else ln for ln in text.split("\n"))
    out = []
    for m in _TOKEN.finditer(text):
        if m.lastgroup in ("skip", "str"):
            continue
        out.append(m.group())
    return out


def _skip_parens(toks: list[str], i: int) -> int | None:
    """The index after the parenthesis that closes ``toks[i] == '('``."""
    depth = 0
    for j in range(i, len(toks)):
        if toks[j] == "(":
            depth += 1
        elif toks[j] == ")":
            depth -= 1
            if depth == 0:
                return j + 1
        elif toks[j] in ("{", "}"):
            return None
    return None


def _scan_defines_main(text: str) -> bool:
    """The token scan: the identifier ``main`` at brace depth 0 (file
    scope, or inside ``extern "C" { ... }``; not a member, not an
    argument), a parenthesised list, then ``{``, either
    at once or after attributes, or after K&R parameter declarations (each
    ending with ``;``, with no ``=`` and no braces)."""
    toks = _tokens(text)
    depth = 0
    braces: list[bool] = []  # per open brace: whether it is a block (not extern "C" { ... })
    for i, tok in enumerate(toks):
        if tok == "{":
            block = not (i > 0 and toks[i - 1] == "extern")  # the "C" was dropped with the literals
            braces.append(block)
            depth += block
        elif tok == "}":
            if braces:
                depth -= braces.pop()
        elif tok == "main" and depth == 0 and i + 1 < len(toks) and toks[i + 1] == "(" \
                and (i == 0 or toks[i - 1] not in (".", "->", "::", "(", ",")):
            j = _skip_parens(toks, i + 1)
            if j is None:
                continue
            # attributes, exception specifications: __attribute__((...)), throw(), noexcept
            while j < len(toks) and toks[j] in ("__attribute__", "throw", "noexcept", "const"):
                j += 1
                if j < len(toks) and toks[j] == "(":
                    j = _skip_parens(toks, j) or len(toks)
            if j < len(toks) and toks[j] == "{":
                return True
            if j >= len(toks) or toks[j] == ";":
                continue  # a declaration
            # K&R: declarations of the parameters, then the body
            k = j
            while k < len(toks) and toks[k] not in ("{", "}", "=", ",", ")"):
                k += 1
            if k < len(toks) and toks[k] == "{" and toks[k - 1] == ";":
                return True
    return False


def _parse_defines_main(text: str, name: str) -> bool | None:
    """Whether pycparser finds a function definition ``main`` at file scope
    in the preprocessed ``text``; ``None`` when it cannot parse it."""
    from pycparser import c_ast, c_parser

    try:
        from pycparser.c_parser import ParseError
    except ImportError:  # pycparser 2.x
        from pycparser.plyparser import ParseError
    try:
        ast = c_parser.CParser().parse(text, filename=name)
    except ParseError:
        return None
    except Exception:  # noqa: BLE001 - any other failure of the parser: the token scan decides
        return None
    return any(isinstance(ext, c_ast.FuncDef) and ext.decl.name == "main" for ext in ast.ext)


_MAIN_WORD = re.compile(r"\bmain\b")


def defines_main(source: Path, includes: Sequence[Path] = ()) -> bool:
    """Whether the source ``source`` defines ``main`` (see the module
    documentation); ``includes`` is the folder's include path."""
    includes = list(includes) or [source.parent]
    text = None
    for system in (False, True):
        try:
            text = preprocess(source, includes, system_headers=system)
            break
        except PreprocessorError:
            continue
    if text is None:
        # the source cannot be preprocessed: read it as written
        try:
            return _scan_defines_main(source.read_text(encoding="utf-8", errors="replace"))
        except OSError:
            return False
    if not _MAIN_WORD.search(text):
        return False
    if source.suffix in C_SUFFIXES:
        parsed = _parse_defines_main(text, str(source))
        if parsed is not None:
            return parsed
    return _scan_defines_main(text)

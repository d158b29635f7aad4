"""The layout check of DESIGN.md section 7: does the user's controller header
agree with the glue about ``Controller_U`` and ``Controller_Y``?

The glue declares ``extern struct ExtU_Controller_T Controller_U;`` with the
struct that Coq printed (``<node>_types.h``); the controller (Simulink
Embedded Coder output, or hand-written code in its style) defines
``ExtU_Controller_T Controller_U;`` with its own header's type, typically a
typedef of an anonymous struct.  The two declarations meet only at link
time, where nothing compares them.  The check is a generated C file,
``<node>_layout_check.c``, that includes the user's ``<Controller>.h`` and a
copy of the Coq-printed structs whose tags are all renamed (so that no name
can clash with the header's, whatever it declares), with static assertions:

- ``sizeof(Controller_U) == sizeof(struct <renamed glue struct>)``;
- for every field: a compatible type (``_Generic`` on the header's field
  against ``__typeof__`` of the glue's field; for an array, rule 4.15, on
  its address, so that the element type and the size are both compared)
  and the same ``offsetof``;
- ``<Controller>_initialize`` and ``<Controller>_step`` have type
  ``void (void)``.

Compiled with ``gcc -fsyntax-only``; nothing is linked.  Each failed
assertion names the field.  Before the user's header is tried, the check is
compiled against a reference header that agrees with the glue by
construction (:func:`render_reference_header`): if that fails, the check
itself is wrong (a tool failure, exit 2), not the user's header.
"""

from __future__ import annotations

import re
import subprocess
from dataclasses import dataclass
from pathlib import Path

from pyrosgen.errors import Context, ToolFailure, UserError
from pyrosgen.render import render, source_label
from pyrosgen.frontend.model import IOStruct, NodeModel
from pyrosgen import procs

__all__ = [
    "LayoutMismatch",
    "LayoutToolError",
    "MARKER",
    "rename_tags",
    "render_layout_check",
    "render_reference_header",
    "check_layout",
]

#: Tag prefix of the glue's structs inside the layout check.
GLUE_PREFIX = "pyrosgen_glue_"
#: Tag prefix of the glue's structs inside the reference header.
REF_PREFIX = "pyrosgen_ref_"
#: Start of every static-assertion message of the check.
MARKER = "pyrosgen layout: "

_C_IDENT = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")
_STRUCT_TAG = re.compile(r"\bstruct\s+([A-Za-z_][A-Za-z0-9_]*)")
_ASSERT = re.compile(r'static assertion failed: "' + re.escape(MARKER) + r'([^"]*)"')
_GCC_DIAG = re.compile(r"^(?P<file>[^:\n]+):(?P<line>\d+):(?P<col>\d+): (?P<sev>error|fatal error): (?P<msg>.*)$")


class LayoutMismatch(UserError):
    """The user's controller header does not agree with the glue (a user
    error: exit 1).  ``problems`` are one line each, naming the field."""

    def __init__(self, header: Path, problems: list[str]):
        self.header = header
        self.problems = problems
        super().__init__(f"{header}: the controller header does not match the model: " + "; ".join(problems))

    def report(self, ctx: Context) -> list[str]:
        return [f"{self.header}: error: the controller header does not match the node model "
                f"(layout check); {ctx.nothing}",
                *(f"{self.header}: error: {problem}" for problem in self.problems)]


class LayoutToolError(ToolFailure):
    """The layout check could not be run, or is wrong (exit 2)."""


def _ident(name: str) -> str:
    if not _C_IDENT.match(name):
        raise ValueError(f"refusing to print {name!r} as a C identifier")
    return name


def rename_tags(types_h: str, prefix: str) -> str:
    """The struct definitions of the Coq-printed ``types_h`` with every tag
    ``T`` renamed ``<prefix>T`` and the include guard removed.

    Only the guard (``#ifndef``/``#define``/``#endif``) may be a
    preprocessor line in the printed text; anything else is refused.
    """
    _ident(prefix)
    out: list[str] = []
    for line in types_h.splitlines():
        s = line.strip()
        if s.startswith("#"):
            if re.match(r"^#\s*(ifndef|define|endif)\b", s):
                continue
            raise LayoutToolError(f"unexpected preprocessor line in the printed structs: {s!r}")
        out.append(_STRUCT_TAG.sub(lambda m: f"struct {prefix}{m.group(1)}", line))
    return "\n".join(out).strip("\n") + "\n"


@dataclass(frozen=True)
class _IO:
    var: str
    tag: str
    typedef: str
    fields: list[dict]


def _ios(model: NodeModel, prefix: str, types_h: str) -> list[_IO]:
    out = []
    for io in (model.controller.inputs, model.controller.outputs):
        io: IOStruct
        if not re.search(r"\bstruct\s+" + re.escape(io.struct_name) + r"\s*\{", types_h):
            raise LayoutToolError(f"struct {io.struct_name} is not in the printed structs")
        out.append(_IO(
            var=_ident(io.var_name),
            tag=_ident(prefix + io.struct_name),
            typedef=_ident(io.struct_name),
            fields=[{"name": _ident(f.name), "prim": f.type_text,
                     "c_type": f.c_type if f.size is None else f"{f.c_type}[{f.size}]",
                     "array": f.size is not None} for f in io.fields],
        ))
    return out


def _functions(model: NodeModel) -> list[str]:
    c = model.controller
    return [_ident(c.initialize_fn), _ident(c.step_fn)]


def controller_header_name(model: NodeModel) -> str:
    """``<Controller>.h``: the header the controller folder must hold."""
    return f"{_ident(model.controller.name)}.h"


def render_layout_check(model: NodeModel, types_h: str, types_header_name: str) -> str:
    """The text of ``<node>_layout_check.c`` (see the module documentation)."""
    return render("layout_check.c.j2",
        source=source_label(model.source.name),
        node=model,
        types_header=types_header_name,
        controller_header=controller_header_name(model),
        prefix=GLUE_PREFIX,
        glue_structs=rename_tags(types_h, GLUE_PREFIX).rstrip("\n"),
        ios=[io.__dict__ for io in _ios(model, GLUE_PREFIX, types_h)],
        functions=_functions(model),
        marker=MARKER,
    )


def render_reference_header(model: NodeModel, types_h: str) -> str:
    """A ``<Controller>.h`` that agrees with the glue by construction: the
    layout check must compile against it."""
    return render("controller_ref.h.j2",
        source=source_label(model.source.name),
        node=model,
        controller=model.controller,
        glue_structs=rename_tags(types_h, REF_PREFIX).rstrip("\n"),
        ios=[io.__dict__ for io in _ios(model, REF_PREFIX, types_h)],
        functions=_functions(model),
    )


def _argv(cc: list[str], check_c: Path, include: Path, extra: list[str] = ()) -> list[str]:
    return [*cc, "-std=c11", "-Wall", "-Wextra", "-pedantic", "-fsyntax-only", "-I", str(include), *extra,
            str(check_c)]


def _compile(cc: list[str], check_c: Path, include: Path, extra: list[str] = ()) -> subprocess.CompletedProcess:
    argv = _argv(cc, check_c, include, extra)
    try:
        return procs.run(argv, timeout=300)
    except OSError as exc:
        raise LayoutToolError(f"cannot run {cc[0]}: {exc.strerror or exc}") from None
    except subprocess.TimeoutExpired:
        raise LayoutToolError(f"{cc[0]} did not finish the layout check within 300 s") from None


def _problems(output: str, check_c: Path, shown_check: str) -> list[str]:
    """The failed assertions (by field) and the other errors of ``output``."""
    problems: list[str] = []
    for line in output.splitlines():
        m = _ASSERT.search(line)
        if m:
            problems.append(m.group(1))
            continue
        d = _GCC_DIAG.match(line)
        if d:
            where = d.group("file")
            if Path(where).name == check_c.name:
                where = shown_check
            problems.append(f"{where}:{d.group('line')}:{d.group('col')}: {d.group('msg')}")
    return problems


def check_layout(model: NodeModel, check_c: Path, controller_dir: Path, work: Path,
                 types_h: str, *, cc: list[str] | None = None, shown_check: str | None = None,
                 includes: list[str] = ()) -> list[list[str]]:
    """Compile ``check_c`` (already written) against the reference header,
    then against the user's header in ``controller_dir`` (``includes``:
    ``-I`` options for the folders its own includes need); return the two
    commands run.

    Raises :class:`LayoutToolError` if the check fails against the reference
    header (or the compiler cannot be run), :class:`LayoutMismatch` naming
    each disagreeing field if it fails against the user's header.
    """
    cc = cc or ["gcc"]
    shown = shown_check or check_c.name
    ref_dir = work / "layout-reference"
    ref_dir.mkdir(parents=True, exist_ok=True)
    (ref_dir / controller_header_name(model)).write_text(render_reference_header(model, types_h), encoding="ascii")
    r = _compile(cc, check_c, ref_dir)
    if r.returncode != 0:
        raise LayoutToolError(
            "the layout check does not compile against the reference header "
            f"(a pyrosgen bug):\n{(r.stderr or r.stdout).strip()}")
    header = controller_dir / controller_header_name(model)
    r = _compile(cc, check_c, controller_dir, list(includes))  # the controller's other header folders
    if r.returncode != 0:
        problems = _problems(r.stderr + r.stdout, check_c, shown) or [(r.stderr or r.stdout).strip()]
        raise LayoutMismatch(header, problems)
    return [_argv(cc, check_c, ref_dir), _argv(cc, check_c, controller_dir, list(includes))]

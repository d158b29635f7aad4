"""Printer validation: the printed C text says exactly what the AST says.

This module compares the two sides and is the entry point
(:func:`validate_glue`, :func:`validate_output_dir`); the vocabulary is in
:mod:`printer_types`, the dump side in :mod:`printer_dump`, the C side in
:mod:`printer_c`.

The C glue is printed by Coq (``ROSGen.Printer``), which is trusted and not
proved.  Every ``pyrosgen generate`` run checks its output independently:
the printed C (the glue ``<node>_glue.c`` with the struct header
``<node>_types.h`` it includes) is parsed with ``pycparser``, normalised to
the shape of the AST dump ``<node>.sexp`` (printed by Coq from the same
term by ``ROSGen.Dump``, a printer that shares no code with
``ROSGen.Printer``, so that one error of the C printer is not repeated in
the dump), and compared with the dump, completely:

- structs: the same set, each with the same members, in the same order,
  of the same types; each defined before it is used;
- globals: the same variables in the same order, of the same types,
  ``extern`` exactly for the dump's ``externs``, without initialiser;
- prototypes: the external functions (name, parameter types, result
  type) and the internal functions (also the parameter names), in order;
- functions: return type, parameters (names, types), locals (the dump's
  ``vars`` then ``temps``, names and types), and the body, statement by
  statement, every expression with its type.  The C side's types are
  recovered from the declarations (a variable's declared type, the member
  type of a field, the pointee of a dereference, the element of an
  index, the type named by a cast, the type of a literal by C11's rules
  for its suffix and value on an LP64 target, the type of an operation
  by C11's rules for its operator and operands), and compared with the
  dump's type annotations.

Normalisation accounts exactly for the printing conventions documented in
``Printer.v`` and nothing else:

- sequences are flattened and ``Sskip`` prints nothing: both sides become
  lists of statements (a C ``{ }`` is the empty list);
- ``while (c) s`` is ``Sloop (Ssequence (Sifthenelse c Sskip Sbreak) s)``,
  ``for (;;) s`` is ``Sloop s``, an ``if`` without ``else`` has ``Sskip``
  as else branch;
- ``Sset x e`` and ``Sassign x e`` both print ``x = e`` (C has no
  temporaries): a local is a local.  Names are resolved on each side by
  its own rules (the semantics': [Etempvar] in the temporaries, [Evar] in
  the addressable locals, then the globals, then the functions; C's: the
  block scope, then file scope, declared before use), so a name that C
  would resolve to something else than the semantics does is a
  difference.  Since C converts the right-hand side of ``x = e`` to the
  type of ``x`` and the semantics' [Sset] does not, an [Sset] (or a call
  result) whose type is not the temporary's type is a difference;
- integer constants denote their value wrapped to their type (the dump
  shows the AST's unwrapped integer); an 8- or 16-bit constant prints as an
  ``int`` literal of that value, so it is compared as an ``int`` constant
  (C converts it exactly where it is used), except as the operand of an
  operation, where C does not convert it (there it keeps its own type,
  which the C side never has: a difference); ``(-2147483647 - 1)`` and
  ``(-9223372036854775807LL - 1)`` are the minimum values;
- float constants are compared by IEEE bit pattern: a hexadecimal literal
  must denote its value exactly (an inexact or decimal literal is
  refused), a ``-`` directly before the literal flips the sign bit, and
  ``rosgen_f64_of_bits(0x...ULL)`` / ``rosgen_f32_of_bits(0x...U)``
  denote the pattern they reinterpret;
- a constant whose type annotation is not its kind's type prints as a
  cast of the constant;
- operations: ``(e1 OP e2)`` is [Ebinop] (``+ - * / % & | ^ == != < >
  <= >=``), ``(-e)`` and ``(!e)`` are [Eunop Oneg] and [Eunop Onotbool],
  ``rosgen_fabs(e)`` / ``rosgen_fabsf(e)`` are [Eunop Oabsfloat] of a
  ``double`` / ``float``.  The comparison is on parsed trees, so the
  parentheses the printer puts around every operation need no check of
  their own (a pair whose absence changes the grouping changes the tree).
  The C side computes the type of each operation by C11's rules and
  accepts only what the typing rules of the subset
  ([Operators.unop_type], [binop_type]) allow, where C converts nothing:
  both operands of a binary operator of the same type, one of ``int``,
  ``unsigned int``, ``long long``, ``unsigned long long``, ``float``,
  ``double`` (so the integer promotions and the usual arithmetic
  conversions change nothing), ``% & | ^`` on the integer types only,
  the comparisons and ``!`` of type ``int``, ``-`` and ``!`` on the same
  six types, ``rosgen_fabs`` / ``rosgen_fabsf`` on a ``double`` /
  ``float`` without conversion.  Operands of different types, of a type C
  promotes (``unsigned char``, ``short``, ...), pointers, structs, and
  every other operator (``&& || << >> ~``, unary ``+``, ``++``, ``?:``,
  ``,``, ``sizeof``, compound assignments, ...) are differences;
- a ``-`` directly before a literal is part of the constant (the printer
  prints a negative ``int``, ``long long`` or finite float constant so:
  ``-5``, ``-5LL``, ``-0x1p+0``).  So [Eunop Oneg] of such a constant
  without its sign (``5``, ``5LL``, ``0x1p+0``, ``0x0p+0``), printed
  ``(-5)``, which C parses to the same tree, is that negative constant on
  the dump side too (the value negated, or the sign bit flipped).  Every
  other [Oneg] stays an operation: of a negative constant ``(-(-5))`` and
  ``(-(-0x1p+0))``, of an unsigned constant ``(-5U)``, of a non-finite
  one ``(-rosgen_f64_of_bits(...))``, of a cast constant, of anything
  else.  Likewise [Ebinop Osub] of the ``int`` constants ``-2147483647``
  and ``1`` prints as ``(-2147483647 - 1)``, the printer's ``INT_MIN``: it
  is that constant (the same value and type);
- the ``static`` helpers ``rosgen_f64_of_bits``, ``rosgen_f32_of_bits``,
  ``rosgen_fabs``, ``rosgen_fabsf`` must be defined, token for token as
  documented, in this order, exactly when used.

Any construct outside this printed subset (other operators, implicit
conversions other than an exact integer constant, declarations after
statements, other preprocessor directives, K&R definitions, qualifiers,
``long``, plain ``char``, ...) is a difference too.  The first difference
is reported with the function, the statement and the C line, and raises
:class:`PrinterValidationError` (a :class:`~pyrosgen.proof.coqdriver.CoqError`:
exit code 2, nothing written).

What the C text cannot show is not compared: the meaning tags of the
external functions (``ros_subscribe "/odom" ...``: the C text only has
their names and types) and the dump's item order between kinds.  Except
where the name says the meaning: the wrapper over roscpp defines
``ros_now`` (ROS time, ``unsigned long long ros_now(void);``), so in the
dump the external named ``ros_now`` must have the tag ``(ros_now)`` and
that type, and the tag ``(ros_now)`` must be on the external of that name;
likewise ``ros_time_sec`` and ``ros_time_nsec`` (its seconds and
nanoseconds, ``unsigned int ros_time_sec(void);``) with their tags
(:data:`printer_dump.FIXED_EXTERNALS`); their prototypes and calls
(``_now = ros_now();``) are then compared like any other.
"""


from __future__ import annotations

import contextlib
import gc
from pathlib import Path
from pyrosgen.verify.printer_types import (
    F32_HELPER,
    F64_HELPER,
    FABS_HELPER,
    FABSF_HELPER,
    PrinterValidationError,
    ValidationReport,
    _Diff,
    show_expr,
    show_stmt,
    show_type,
)
from pyrosgen.verify.printer_dump import (
    _DumpProgram,
)
from pyrosgen.verify.printer_c import (
    _CProgram,
    _header_body,
    _parse_error,
    _translation_unit,
)


__all__ = [
    "PrinterValidationError",
    "ValidationReport",
    "validate_glue",
    "validate_program",
    "validate_output_dir",
    "F64_HELPER",
    "F32_HELPER",
    "FABS_HELPER",
    "FABSF_HELPER",
]

# ---------------------------------------------------------------------------
# Comparison

def _first_diff(a, b, path=()):
    """The path of the first sub-term where [a] and [b] differ, or None."""
    if a == b:
        return None
    same_tag = not (a and isinstance(a[0], str)) or a[:1] == b[:1] if isinstance(a, tuple) else False
    if isinstance(a, tuple) and isinstance(b, tuple) and len(a) == len(b) and same_tag:
        for k, (x, y) in enumerate(zip(a, b)):
            d = _first_diff(x, y, path + (k,))
            if d is not None:
                return d
    return path


def _sub(t, path):
    for k in path:
        t = t[k]
    return t


def _show_any(x) -> str:
    if isinstance(x, tuple) and x and x[0] in ("assign", "call", "if", "loop", "break", "return"):
        return show_stmt(x)
    if isinstance(x, tuple) and x and x[0] in ("const", "constf", "ref", "deref", "addrof", "field", "index", "cast",
                                               "unop", "binop"):
        return show_expr(x)
    if isinstance(x, tuple) and x and isinstance(x[0], str) and x[0] in ("int", "long", "float", "ptr", "array", "fun", "struct", "void"):
        return show_type(x)
    if isinstance(x, tuple):
        return f"[{len(x)} items]"
    return str(x)


def _compare_bodies(fname: str, dump: tuple, c: tuple, coords: dict, c_node) -> None:
    def walk(ds, cs, path, label):
        for k in range(max(len(ds), len(cs))):
            here = path + (k,)
            where = f"function {fname}, {label}statement {k + 1}"
            if k >= len(cs):
                raise _Diff(f"{where}: the C text lacks it", coords.get(path + (len(cs) - 1,), c_node.coord),
                            detail=(f"AST: {show_stmt(ds[k])}",))
            if k >= len(ds):
                raise _Diff(f"{where}: the C text has a statement the AST lacks", coords.get(here, c_node.coord),
                            detail=(f"C:   {show_stmt(cs[k])}",))
            d, s = ds[k], cs[k]
            if d == s:
                continue
            if d[0] == s[0] == "if" and d[1] == s[1]:
                if d[2] != s[2]:
                    walk(d[2], s[2], here + ("then",), f"{label}statement {k + 1}, then-branch, ")
                walk(d[3], s[3], here + ("else",), f"{label}statement {k + 1}, else-branch, ")
                continue
            if d[0] == s[0] == "loop":
                walk(d[1], s[1], here + ("body",), f"{label}statement {k + 1}, loop body, ")
                continue
            p = _first_diff(d, s)
            detail = [f"C:   {show_stmt(s)}", f"AST: {show_stmt(d)}"]
            if p:
                detail += [f"first difference: C has {_show_any(_sub(s, p))}",
                           f"                  AST has {_show_any(_sub(d, p))}"]
            raise _Diff(f"{where} differs", coords.get(here, c_node.coord), detail=tuple(detail))
    walk(dump, c, (), "")


def _compare(dp: _DumpProgram, cp: _CProgram, require_main: str | None) -> None:
    it = dp.items
    # structs: same set, same members; C order is a valid definition order (checked while parsing)
    for name, members in dp.structs.items():
        if name not in cp.structs:
            raise _Diff(f"struct {name} of the AST is not defined in the C text")
        if cp.structs[name] != members:
            cm = cp.structs[name]
            k = next((j for j, (x, y) in enumerate(zip(members, cm)) if x != y), min(len(cm), len(members)))
            raise _Diff(f"struct {name}: member {k + 1} differs", cp.struct_coord[name],
                        detail=(f"C:   {' '.join(f'{m} : {show_type(t)};' for m, t in cm[k:k + 1]) or '(none)'}",
                                f"AST: {' '.join(f'{m} : {show_type(t)};' for m, t in members[k:k + 1]) or '(none)'}"))
    extra = [s for s in cp.struct_order if s not in dp.structs]
    if extra:
        raise _Diff(f"struct {extra[0]} of the C text is not in the AST", cp.struct_coord[extra[0]])
    # globals, in order
    externs = set(it["externs"])
    want = [(n, t, n in externs) for n, t in dp.gvars.items()]
    have = [(n, t, ext) for n, t, ext, _ in cp.gvars]
    for k in range(max(len(want), len(have))):
        if k >= len(have):
            raise _Diff(f"global {want[k][0]} of the AST is not declared in the C text")
        node = cp.gvars[k][3]
        if k >= len(want):
            raise _Diff(f"global {have[k][0]} of the C text is not in the AST", node.coord)
        if want[k] != have[k]:
            w, h = want[k], have[k]
            raise _Diff(f"global variable {k + 1} differs", node.coord,
                        detail=(f"C:   {'extern ' if h[2] else ''}{h[0]} : {show_type(h[1])}",
                                f"AST: {'extern ' if w[2] else ''}{w[0]} : {show_type(w[1])}"))
    cp.report.globals = len(have)
    # prototypes: the externals, then the internal functions, in order
    want_p = [(n, t, [None] * len(t[1])) for n, t in dp.externals.items()]
    want_p += [(n, ("fun", tuple(t for _, t in f.params), f.ret), [x for x, _ in f.params])
               for n, f in dp.functions.items()]
    have_p = [(n, t, names) for n, t, names, _ in cp.protos]
    for k in range(max(len(want_p), len(have_p))):
        if k >= len(have_p):
            raise _Diff(f"prototype of {want_p[k][0]} missing in the C text")
        node = cp.protos[k][3]
        if k >= len(want_p):
            raise _Diff(f"prototype of {have_p[k][0]} of the C text is not in the AST", node.coord)
        if want_p[k] != have_p[k]:
            w, h = want_p[k], have_p[k]
            raise _Diff(f"prototype {k + 1} differs", node.coord,
                        detail=(f"C:   {h[0]} : {show_type(h[1])}" + f" ({', '.join(x or '_' for x in h[2])})",
                                f"AST: {w[0]} : {show_type(w[1])}" + f" ({', '.join(x or '_' for x in w[2])})"))
    cp.report.externals = len(dp.externals)
    # function definitions, in order
    names_d, names_c = list(dp.functions), [d[0] for d in cp.defs]
    for k in range(max(len(names_d), len(names_c))):
        if k >= len(names_c):
            raise _Diff(f"function {names_d[k]} of the AST is not defined in the C text")
        name, t, pnames, locals_, body, node = cp.defs[k]
        if k >= len(names_d) or names_d[k] != name:
            raise _Diff(f"function definition {k + 1}: C defines {name}, AST "
                        f"{names_d[k] if k < len(names_d) else 'nothing'}", node.coord)
        f = dp.functions[name]
        if t != ("fun", tuple(x for _, x in f.params), f.ret) or pnames != [x for x, _ in f.params]:
            raise _Diff(f"function {name}: header differs", node.coord,
                        detail=(f"C:   {show_type(t)} ({', '.join(pnames)})",
                                f"AST: {show_type(('fun', tuple(x for _, x in f.params), f.ret))} "
                                f"({', '.join(x for x, _ in f.params)})"))
        if locals_ != f.vars + f.temps:
            want_l = f.vars + f.temps
            j = next((i for i, (x, y) in enumerate(zip(want_l, locals_)) if x != y), min(len(want_l), len(locals_)))
            raise _Diff(f"function {name}: local {j + 1} differs", node.coord,
                        detail=(f"C:   {locals_[j][0] + ' : ' + show_type(locals_[j][1]) if j < len(locals_) else '(none)'}",
                                f"AST: {want_l[j][0] + ' : ' + show_type(want_l[j][1]) if j < len(want_l) else '(none)'}"))
        c_body, coords = body()
        _compare_bodies(name, f.stmts(f.body), c_body, coords, node)
    # helpers: defined exactly when used
    for h, node in cp.helpers_defined.items():
        if h not in cp.helpers_used:
            raise _Diff(f"helper {h} defined but not used", node.coord)
    cp.report.helpers = sorted(cp.helpers_used)
    if require_main is not None:
        if it["main"] != require_main or require_main not in dp.functions:
            raise _Diff(f"the AST's entry point is {it['main']!r}, the C program's is {require_main!r}")


@contextlib.contextmanager
def _without_cyclic_gc():
    """Python's cyclic garbage collector off for the block: parsing builds
    hundreds of thousands of objects (pycparser's AST, the dump's tree),
    none garbage, and the collector would traverse them again and again (a
    third of the validation's time; BENCHMARKS.md section 11).  Reference
    counting still frees everything; the collector is re-enabled after."""
    was = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if was:
            gc.enable()


def _validate(tu_text: str, sexp_text: str, require_main: str | None, label: str) -> ValidationReport:
    with _without_cyclic_gc():
        return _validate_parsed(tu_text, sexp_text, require_main, label)


def _validate_parsed(tu_text: str, sexp_text: str, require_main: str | None, label: str) -> ValidationReport:
    from pycparser import c_parser
    ParseError = _parse_error()

    report = ValidationReport()
    try:
        dump = _DumpProgram(sexp_text, report)
        try:
            ast = c_parser.CParser().parse(tu_text, filename=label)
        except ParseError as exc:
            raise _Diff(f"pycparser cannot parse the C text: {exc}") from None
        cprog = _CProgram(ast, report)
        _compare(dump, cprog, require_main)
        # what was compared: the dump side's counts (the C side's are equal)
        report.statements, report.expressions, report.constants = _recount(dump)
    except _Diff as d:
        where = f"{_coord_of(d.coord)}: " if d.coord is not None else ""
        raise PrinterValidationError(
            f"printer validation failed: {where}{d.message}",
            [f"  {line}" for line in d.detail]) from None
    return report


def _recount(dump: _DumpProgram) -> tuple[int, int, int]:
    r = ValidationReport()
    saved = dump.report
    dump.report = r
    for f in dump.functions.values():
        f.stmts(f.body)
    dump.report = saved
    return r.statements, r.expressions, r.constants


def _coord_of(c) -> str:
    if c is None:
        return "?"
    if isinstance(c, str):
        return c
    return f"{c.file}:{c.line}"


def validate_glue(glue_text: str, header_text: str, sexp_text: str, *, glue_name: str,
                  header_name: str, require_main: str | None = "main") -> ValidationReport:
    """Validate a glue printed with its struct header
    ([Printer.print_program_with_header] and [Printer.print_types_header])
    against the dump ([Dump.print_sexp]).  Raises
    :class:`PrinterValidationError` on the first difference."""
    try:
        tu = _translation_unit(glue_text, glue_name, header_text, header_name)
        body, _ = _header_body(header_text, header_name)
        _header_only_structs(body, header_name)
    except _Diff as d:
        raise PrinterValidationError(f"printer validation failed: {d.message}",
                                     [f"  {line}" for line in d.detail]) from None
    return _validate(tu, sexp_text, require_main, glue_name)


def _header_only_structs(body: str, header_name: str) -> None:
    from pycparser import c_ast, c_parser
    ParseError = _parse_error()

    try:
        ast = c_parser.CParser().parse(body, filename=header_name)
    except ParseError as exc:
        raise _Diff(f"pycparser cannot parse {header_name}: {exc}") from None
    for ext in ast.ext:
        if not (isinstance(ext, c_ast.Decl) and isinstance(ext.type, c_ast.Struct) and ext.name is None):
            raise _Diff(f"{header_name} contains something else than struct definitions", ext.coord)


def validate_program(c_text: str, sexp_text: str, *, name: str = "program.c",
                     require_main: str | None = None) -> ValidationReport:
    """Validate a self-contained C text ([Printer.print_program]) against
    its dump."""
    try:
        tu = _translation_unit(c_text, name, None, None)
    except _Diff as d:
        raise PrinterValidationError(f"printer validation failed: {d.message}") from None
    return _validate(tu, sexp_text, require_main, name)


def validate_output_dir(out_dir: str | Path, node: str) -> ValidationReport:
    """Validate the files ``<node>_glue.c``, ``<node>_types.h`` and
    ``<node>.sexp`` of a ``pyrosgen generate`` output directory."""
    d = Path(out_dir)
    glue, header, sexp = f"{node}_glue.c", f"{node}_types.h", f"{node}.sexp"
    return validate_glue((d / glue).read_text(), (d / header).read_text(), (d / sexp).read_text(),
                         glue_name=glue, header_name=header)

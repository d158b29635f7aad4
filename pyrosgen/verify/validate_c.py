"""Printer validation: the printed C text says exactly what the AST says.

The C glue is printed by Coq (``ROSGen.Printer``), which is trusted and not
proved.  Every ``pyrosgen generate`` run checks its output independently:
the printed C (the glue ``<node>_glue.c`` with the struct header
``<node>_types.h`` it includes) is parsed with ``pycparser``, normalised to
the shape of the AST dump ``<node>.sexp`` (printed by Coq from the same
term), and compared with the dump, completely:

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
  for its suffix and value on an LP64 target), and compared with the
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
  (C converts it exactly where it is used); ``(-2147483647 - 1)`` and
  ``(-9223372036854775807LL - 1)`` are the minimum values;
- float constants are compared by IEEE bit pattern: a hexadecimal literal
  must denote its value exactly (an inexact or decimal literal is
  refused), ``-`` flips the sign bit, and ``rosgen_f64_of_bits(0x...ULL)``
  / ``rosgen_f32_of_bits(0x...U)`` denote the pattern they reinterpret;
  these two ``static`` helpers must be defined, token for token as
  documented, exactly when used;
- a constant whose type annotation is not its kind's type prints as a
  cast of the constant.

Any construct outside this printed subset (other operators, implicit
conversions other than an exact integer constant, declarations after
statements, other preprocessor directives, K&R definitions, qualifiers,
``long``, plain ``char``, ...) is a difference too.  The first difference
is reported with the function, the statement and the C line, and raises
:class:`PrinterValidationError` (a :class:`~pyrosgen.proof.coqdriver.CoqError`:
exit code 2, nothing written).

What the C text cannot show is not compared: the meaning tags of the
external functions (``ros_subscribe "/odom" ...``: the C text only has
their names and types) and the dump's item order between kinds.
"""

from __future__ import annotations

import re
import struct
from dataclasses import dataclass, field
from fractions import Fraction
from pathlib import Path

from pyrosgen.proof.coqdriver import CoqError
from pyrosgen.proof.sexp import SexpError, parse_sexp, program_items

__all__ = [
    "PrinterValidationError",
    "ValidationReport",
    "validate_glue",
    "validate_program",
    "validate_output_dir",
    "F64_HELPER",
    "F32_HELPER",
]

F64_HELPER = "rosgen_f64_of_bits"
F32_HELPER = "rosgen_f32_of_bits"

#: The helpers' definitions as ROSGen.Printer prints them ([helper_lines]).
_HELPER_TEXT = {
    F64_HELPER: (
        "static double rosgen_f64_of_bits(unsigned long long b)\n{\n"
        "    union { unsigned long long u; double d; } x;\n    x.u = b;\n    return x.d;\n}\n"
    ),
    F32_HELPER: (
        "static float rosgen_f32_of_bits(unsigned int b)\n{\n"
        "    union { unsigned int u; float f; } x;\n    x.u = b;\n    return x.f;\n}\n"
    ),
}

INT = ("int", "I32", "signed")
UINT = ("int", "I32", "unsigned")
LLONG = ("long", "signed")
ULLONG = ("long", "unsigned")
F64 = ("float", "F64")
F32 = ("float", "F32")
VOID = ("void",)


class PrinterValidationError(CoqError):
    """The printed C text and the AST dump differ (exit code 2).

    ``summary`` names the first difference; ``lines`` give the C line and
    both sides."""


class _Diff(Exception):
    """A difference (or an unsupported C construct), with where it is."""

    def __init__(self, message: str, coord=None, detail: tuple[str, ...] = ()):
        self.message = message
        self.coord = coord
        self.detail = detail
        super().__init__(message)


@dataclass
class ValidationReport:
    """What was compared."""

    structs: int = 0
    globals: int = 0
    externals: int = 0
    functions: int = 0
    statements: int = 0
    expressions: int = 0
    constants: int = 0
    helpers: list[str] = field(default_factory=list)

    def summary(self) -> str:
        return (f"{self.structs} structs, {self.globals} globals, {self.externals} external and "
                f"{self.functions} internal functions, {self.statements} statements, "
                f"{self.expressions} expressions ({self.constants} constants)")


# ---------------------------------------------------------------------------
# Types

def _dump_type(t) -> tuple:
    """A type of the dump as a tuple: ``('int', 'I32', 'unsigned')``,
    ``('ptr', ('struct', 'M'))``, ``('fun', (args...), res)``, ..."""
    if t == "void":
        return VOID
    if not isinstance(t, list) or not t:
        raise _Diff(f"malformed type {t!r} in the dump")
    k = t[0]
    if k == "int" and len(t) == 3 and t[1] in ("I8", "I16", "I32") and t[2] in ("signed", "unsigned"):
        return ("int", t[1], t[2])
    if k == "long" and len(t) == 2 and t[1] in ("signed", "unsigned"):
        return ("long", t[1])
    if k == "float" and len(t) == 2 and t[1] in ("F32", "F64"):
        return ("float", t[1])
    if k == "ptr" and len(t) == 2:
        return ("ptr", _dump_type(t[1]))
    if k == "array" and len(t) == 3:
        return ("array", _dump_type(t[1]), int(t[2]))
    if k == "fun" and len(t) == 3 and isinstance(t[1], list):
        return ("fun", tuple(_dump_type(a) for a in t[1]), _dump_type(t[2]))
    if k == "struct" and len(t) == 2 and isinstance(t[1], str):
        return ("struct", t[1])
    raise _Diff(f"malformed type {t!r} in the dump")


_INT_NAMES = {
    ("I8", "signed"): "signed char", ("I8", "unsigned"): "unsigned char",
    ("I16", "signed"): "short", ("I16", "unsigned"): "unsigned short",
    ("I32", "signed"): "int", ("I32", "unsigned"): "unsigned int",
}


def show_type(t: tuple) -> str:
    """A type as C would write it (for messages)."""
    k = t[0]
    if k == "void":
        return "void"
    if k == "int":
        return _INT_NAMES[(t[1], t[2])]
    if k == "long":
        return "long long" if t[1] == "signed" else "unsigned long long"
    if k == "float":
        return "float" if t[1] == "F32" else "double"
    if k == "ptr":
        return show_type(t[1]) + " *"
    if k == "array":
        return f"{show_type(t[1])}[{t[2]}]"
    if k == "fun":
        return f"{show_type(t[2])} ({', '.join(map(show_type, t[1])) or 'void'})"
    if k == "struct":
        return f"struct {t[1]}"
    return repr(t)


def _bits(t: tuple) -> int:
    return {"I8": 8, "I16": 16, "I32": 32}[t[1]] if t[0] == "int" else 64


def _wrap(t: tuple, n: int) -> int:
    """[n] wrapped to the integer type [t] (two's complement)."""
    b = _bits(t)
    u = n % (1 << b)
    if t[-1] == "signed" and u >= 1 << (b - 1):
        return u - (1 << b)
    return u


def _usual_arith(t1: tuple, t2: tuple) -> tuple:
    """C11 6.3.1.8 on the promoted integer types of the printed subset
    ([int], [unsigned int], [long long], [unsigned long long]; LP64)."""
    rank = {INT: 1, UINT: 1, LLONG: 2, ULLONG: 2}
    if t1 not in rank or t2 not in rank:
        raise _Diff(f"arithmetic on {show_type(t1)} and {show_type(t2)}")
    if t1 == t2:
        return t1
    big, small = (t1, t2) if rank[t1] >= rank[t2] else (t2, t1)
    if rank[big] == rank[small]:          # same rank, different signedness: unsigned
        return big if big[-1] == "unsigned" else small
    return big                            # the 64-bit type holds every 32-bit value


def _is_int(t: tuple) -> bool:
    return t[0] in ("int", "long")


def _is_arith(t: tuple) -> bool:
    return t[0] in ("int", "long", "float")


def _is_scalar(t: tuple) -> bool:
    return _is_arith(t) or t[0] == "ptr"


# C's integer type names (any order / equivalent spelling) -> our types.
_C_INT_TYPES = {
    ("char", "signed"): ("int", "I8", "signed"),
    ("char", "unsigned"): ("int", "I8", "unsigned"),
    ("short",): ("int", "I16", "signed"),
    ("int", "short"): ("int", "I16", "signed"),
    ("short", "signed"): ("int", "I16", "signed"),
    ("int", "short", "signed"): ("int", "I16", "signed"),
    ("short", "unsigned"): ("int", "I16", "unsigned"),
    ("int", "short", "unsigned"): ("int", "I16", "unsigned"),
    ("int",): INT,
    ("signed",): INT,
    ("int", "signed"): INT,
    ("unsigned",): UINT,
    ("int", "unsigned"): UINT,
    ("long", "long"): LLONG,
    ("int", "long", "long"): LLONG,
    ("long", "long", "signed"): LLONG,
    ("int", "long", "long", "signed"): LLONG,
    ("long", "long", "unsigned"): ULLONG,
    ("int", "long", "long", "unsigned"): ULLONG,
    ("float",): F32,
    ("double",): F64,
    ("void",): VOID,
}


# ---------------------------------------------------------------------------
# Constants

_INT_LIT = re.compile(
    r"^(?P<num>0[xX][0-9a-fA-F]+|0[0-7]*|[1-9][0-9]*)"
    r"(?P<sfx>|[uU]|ll|LL|[uU](?:ll|LL)|(?:ll|LL)[uU])$")
_HEX_FLOAT = re.compile(
    r"^0[xX](?P<int>[0-9a-fA-F]*)(?:\.(?P<frac>[0-9a-fA-F]*))?[pP](?P<exp>[+-]?[0-9]+)(?P<sfx>[fF]?)$")

_LIMITS = {"int": (32, True), "uint": (32, False), "long": (64, True), "ulong": (64, False),
           "llong": (64, True), "ullong": (64, False)}
_OURS = {"int": INT, "uint": UINT, "llong": LLONG, "ullong": ULLONG}


def _int_literal(text: str) -> tuple[int, tuple]:
    """The value and type of a C integer constant (C11 6.4.4.1, LP64)."""
    m = _INT_LIT.match(text)
    if not m:
        raise _Diff(f"integer constant {text} is not in the printed subset")
    num, sfx = m.group("num"), m.group("sfx").lower()
    decimal = not num.startswith("0") or num == "0"
    value = int(num, 16) if num[:2].lower() == "0x" else int(num, 8) if num.startswith("0") else int(num)
    has_u, has_ll = "u" in sfx, "ll" in sfx
    if has_u and has_ll:
        cands = ["ullong"]
    elif has_u:
        cands = ["uint", "ulong", "ullong"]
    elif has_ll:
        cands = ["llong"] if decimal else ["llong", "ullong"]
    else:
        cands = ["int", "long", "llong"] if decimal else ["int", "uint", "long", "ulong", "llong", "ullong"]
    for c in cands:
        bits, signed = _LIMITS[c]
        hi = (1 << (bits - 1)) - 1 if signed else (1 << bits) - 1
        if value <= hi:
            if c not in _OURS:
                raise _Diff(f"integer constant {text} has type {'unsigned ' if c == 'ulong' else ''}long, "
                            "which the printed subset does not use")
            return value, _OURS[c]
    raise _Diff(f"integer constant {text} is too large for any C type")


def _f64_bits(x: float) -> int:
    return struct.unpack("<Q", struct.pack("<d", x))[0]


def _f32_bits(x: float) -> int:
    return struct.unpack("<I", struct.pack("<f", x))[0]


def _float_literal(text: str) -> tuple[int, tuple]:
    """The IEEE bit pattern and type of an exact hexadecimal floating
    constant."""
    m = _HEX_FLOAT.match(text)
    if not m or not (m.group("int") or m.group("frac")):
        raise _Diff(f"floating constant {text} is not an exact hexadecimal constant")
    digits = (m.group("int") or "") + (m.group("frac") or "")
    value = Fraction(int(digits, 16)) * Fraction(2) ** (int(m.group("exp")) - 4 * len(m.group("frac") or ""))
    single = m.group("sfx") != ""
    try:
        x = float(value)
    except OverflowError:
        raise _Diff(f"floating constant {text} overflows") from None
    if Fraction(x) != value:
        raise _Diff(f"floating constant {text} is not exactly representable as a double")
    if single:
        try:
            b = _f32_bits(x)
        except OverflowError:
            raise _Diff(f"floating constant {text} overflows a float") from None
        if struct.unpack("<f", struct.pack("<I", b))[0] != x:
            raise _Diff(f"floating constant {text} is not exactly representable as a float")
        return b, F32
    return _f64_bits(x), F64


# Normalised expressions (tuples, compared with ==):
#   ('const', value, type)       integer constant (value wrapped to its type)
#   ('constf', bits, type)       floating constant (IEEE pattern)
#   ('ref', kind, name, type)    kind: local | global | function (| unbound...)
#   ('deref', e, type) ('addrof', e, type) ('field', e, f, type)
#   ('index', e, i, type) ('cast', e, type)
# Normalised statements:
#   ('assign', lhs, rhs)  ('call', dest|None, f, (args...))
#   ('if', c, (then...), (else...))  ('loop', (body...))  ('break',)
#   ('return', e|None)


def typeof(e: tuple) -> tuple:
    return e[-1]


def show_expr(e) -> str:
    """A normalised expression as C-like text (for messages)."""
    if e is None:
        return "<none>"
    k = e[0]
    if k == "const":
        return f"{e[1]} : {show_type(e[2])}"
    if k == "constf":
        return f"<bits 0x{e[1]:0{16 if e[2] == F64 else 8}x}> : {show_type(e[2])}"
    if k == "ref":
        return f"{e[2]} ({e[1]}) : {show_type(e[3])}"
    if k == "deref":
        return f"*({show_expr(e[1])}) : {show_type(e[2])}"
    if k == "addrof":
        return f"&({show_expr(e[1])}) : {show_type(e[2])}"
    if k == "field":
        return f"({show_expr(e[1])}).{e[2]} : {show_type(e[3])}"
    if k == "index":
        return f"({show_expr(e[1])})[{show_expr(e[2])}] : {show_type(e[3])}"
    if k == "cast":
        return f"({show_type(e[2])})({show_expr(e[1])})"
    return repr(e)


def show_stmt(s) -> str:
    """A normalised statement as C-like text (for messages)."""
    k = s[0]
    if k == "assign":
        return f"{show_expr(s[1])} = {show_expr(s[2])};"
    if k == "call":
        call = f"{show_expr(s[2])}({', '.join(show_expr(a) for a in s[3])});"
        return call if s[1] is None else f"{show_expr(s[1])} = {call}"
    if k == "if":
        return f"if ({show_expr(s[1])}) {{ {len(s[2])} statements }} else {{ {len(s[3])} statements }}"
    if k == "loop":
        return f"for (;;) {{ {len(s[1])} statements }}"
    if k == "break":
        return "break;"
    if k == "return":
        return "return;" if s[1] is None else f"return {show_expr(s[1])};"
    return repr(s)


# ---------------------------------------------------------------------------
# The dump side

class _DumpFunction:
    """Normalises one function of the dump."""

    def __init__(self, prog: "_DumpProgram", item):
        self.prog = prog
        try:
            _, self.name, ret, params, vars_, temps, body = item
            assert params[0] == "params" and vars_[0] == "vars" and temps[0] == "temps" and body[0] == "body"
            assert len(body) == 2
        except (ValueError, AssertionError, TypeError, IndexError):
            raise _Diff(f"malformed function item in the dump: {item!r:.100}") from None
        self.ret = _dump_type(ret)
        self.params = [(p[0], _dump_type(p[1])) for p in params[1:]]
        self.vars = [(p[0], _dump_type(p[1])) for p in vars_[1:]]
        self.temps = [(p[0], _dump_type(p[1])) for p in temps[1:]]
        self.body = body[1]
        self.temp_types = dict(self.params + self.temps)
        self.var_types = dict(self.vars)

    def expr(self, e) -> tuple:
        p = self.prog
        p.report.expressions += 1
        if not isinstance(e, list) or not e:
            raise _Diff(f"malformed expression {e!r:.80} in the dump")
        k = e[0]
        if k == "const_int":
            p.report.constants += 1
            n, t = int(e[1]), _dump_type(e[2])
            if t[0] == "int":
                v = _wrap(t, n)
                return ("const", v, t if t[1] == "I32" else INT)
            return ("cast", ("const", _wrap(INT, n), INT), t)
        if k == "const_long":
            p.report.constants += 1
            n, t = int(e[1]), _dump_type(e[2])
            if t[0] == "long":
                return ("const", _wrap(t, n), t)
            return ("cast", ("const", _wrap(LLONG, n), LLONG), t)
        if k in ("const_float", "const_single"):
            p.report.constants += 1
            bits, t = int(e[1], 16), _dump_type(e[2])
            own = F64 if k == "const_float" else F32
            c = ("constf", bits, own)
            return c if t == own else ("cast", c, t)
        if k == "var":
            x, t = e[1], _dump_type(e[2])
            if x in self.var_types:
                return ("ref", "local", x, t)
            if x in p.gvars:
                return ("ref", "global", x, t)
            if x in p.funcs:
                return ("ref", "function", x, t)
            return ("ref", "unbound variable", x, t)
        if k == "tempvar":
            x, t = e[1], _dump_type(e[2])
            return ("ref", "local" if x in self.temp_types else "unbound temporary", x, t)
        if k in ("deref", "addrof", "cast"):
            return (k, self.expr(e[1]), _dump_type(e[2]))
        if k == "field":
            return ("field", self.expr(e[1]), e[2], _dump_type(e[3]))
        if k == "index":
            return ("index", self.expr(e[1]), self.expr(e[2]), _dump_type(e[3]))
        raise _Diff(f"unknown expression {k!r} in the dump")

    def temp(self, x: str, value_type: tuple) -> tuple:
        """The destination of [Sset x _] / [Scall (Some x) _ _]: C converts
        to the declared type, the semantics does not."""
        t = self.temp_types.get(x)
        if t is None:
            return ("ref", "unbound temporary", x, None)
        if t != value_type:
            return ("ref", f"temporary of type {show_type(t)} set without conversion", x, value_type)
        return ("ref", "local", x, t)

    def stmts(self, s) -> tuple:
        """The flattened, skip-free list of statements of [s]."""
        out: list = []
        stack = [s]
        while stack:  # iterative over sequences (they can be long)
            s = stack.pop()
            if not isinstance(s, list) or not s:
                raise _Diff(f"malformed statement {s!r:.80} in the dump")
            k = s[0]
            if k == "seq":
                stack.extend(reversed(s[1:]))
                continue
            if k == "skip":
                continue
            self.prog.report.statements += 1
            if k == "assign":
                out.append(("assign", self.expr(s[1]), self.expr(s[2])))
            elif k == "set":
                rhs = self.expr(s[2])
                out.append(("assign", self.temp(s[1], typeof(rhs)), rhs))
            elif k == "call":
                f = self.expr(s[2])
                args = tuple(self.expr(a) for a in s[3])
                dest = None
                if s[1]:
                    ft = typeof(f)
                    dest = self.temp(s[1][0], ft[2] if ft[0] == "fun" else None)
                out.append(("call", dest, f, args))
            elif k == "if":
                out.append(("if", self.expr(s[1]), self.stmts(s[2]), self.stmts(s[3])))
            elif k == "loop":
                out.append(("loop", self.stmts(s[1])))
            elif k == "break":
                out.append(("break",))
            elif k == "return":
                out.append(("return", self.expr(s[1]) if len(s) > 1 else None))
            else:
                raise _Diff(f"unknown statement {k!r} in the dump")
        return tuple(out)


class _DumpProgram:
    def __init__(self, sexp_text: str, report: ValidationReport):
        self.report = report
        try:
            self.items = program_items(parse_sexp(sexp_text))
        except (SexpError, ValueError, TypeError, IndexError) as exc:
            raise _Diff(f"the AST dump does not parse: {exc}") from None
        it = self.items
        self.structs = {n: [(m, _dump_type(t)) for m, t in ms] for n, ms in it["structs"].items()}
        if len(self.structs) != sum(1 for k, _ in it["order"] if k == "struct"):
            raise _Diff("the dump defines a struct twice")
        self.gvars = {n: _dump_type(t) for n, t in it["gvars"].items()}
        self.externals = {n: ("fun", tuple(_dump_type(a) for a in v[1]), _dump_type(v[2]))
                          for n, v in it["externals"].items()}
        self.functions = {n: _DumpFunction(self, item) for n, item in it["functions"].items()}
        self.funcs = set(self.externals) | set(self.functions)
        names = [n for k, n in it["order"] if k != "struct"]
        if len(names) != len(set(names)):
            raise _Diff("the dump defines a global name twice")


# ---------------------------------------------------------------------------
# The C side

def _strip_comments(text: str) -> str:
    """Comments replaced by spaces (newlines kept, so lines keep their
    numbers)."""
    out, i, n = [], 0, len(text)
    while i < n:
        if text.startswith("/*", i):
            j = text.find("*/", i + 2)
            if j < 0:
                raise _Diff("unterminated comment")
            out.append("".join(c if c == "\n" else " " for c in text[i:j + 2]))
            i = j + 2
        elif text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            out.append(" " * (j - i))
            i = j
        elif text[i] in "\"'":
            q, j = text[i], i + 1
            while j < n and text[j] != q:
                if text[j] == "\n":
                    raise _Diff("unterminated literal")
                j += 2 if text[j] == "\\" else 1
            out.append(text[i:j + 1])
            i = j + 1
        else:
            out.append(text[i])
            i += 1
    return "".join(out)


def _directives(text: str) -> list[tuple[int, str]]:
    return [(k, line.strip()) for k, line in enumerate(text.split("\n"), 1) if line.lstrip().startswith("#")]


def _header_body(header_text: str, header_name: str) -> tuple[str, int]:
    """The text inside the include guard of the types header (directives
    blanked), and the line where it starts."""
    text = _strip_comments(header_text)
    dirs = _directives(text)
    if len(dirs) != 3:
        raise _Diff(f"{header_name}: expected exactly #ifndef/#define/#endif, found {len(dirs)} directives")
    (l1, d1), (l2, d2), (l3, d3) = dirs
    m1 = re.fullmatch(r"#\s*ifndef\s+([A-Za-z_]\w*)", d1)
    m2 = re.fullmatch(r"#\s*define\s+([A-Za-z_]\w*)", d2)
    if not (m1 and m2 and m1.group(1) == m2.group(1) and l2 == l1 + 1 and re.fullmatch(r"#\s*endif", d3)):
        raise _Diff(f"{header_name}: not an include-guarded header (#ifndef G / #define G ... #endif)",
                    detail=(d1, d2, d3))
    lines = text.split("\n")
    if any(line.strip() for line in lines[: l1 - 1] + lines[l3:]):
        raise _Diff(f"{header_name}: text outside the include guard")
    body = "\n".join(lines[l2:l3 - 1])
    return body, l2 + 1


def _translation_unit(glue_text: str, glue_name: str, header_text: str | None,
                      header_name: str | None) -> str:
    """The glue with the types header inlined, with line markers so that
    pycparser reports the original files and lines."""
    text = _strip_comments(glue_text)
    dirs = _directives(text)
    if header_name is None:
        if dirs:
            raise _Diff(f"{glue_name}:{dirs[0][0]}: unexpected directive {dirs[0][1]}")
        return f'# 1 "{glue_name}"\n' + text
    if len(dirs) != 1:
        raise _Diff(f"{glue_name}: expected exactly one directive (#include \"{header_name}\"), "
                    f"found {len(dirs)}")
    line, d = dirs[0]
    m = re.fullmatch(r'#\s*include\s+"([^"]+)"', d)
    if not m or m.group(1) != header_name:
        raise _Diff(f"{glue_name}:{line}: expected #include \"{header_name}\", found {d}")
    body, start = _header_body(header_text, header_name)
    lines = text.split("\n")
    return "\n".join([f'# 1 "{glue_name}"', *lines[: line - 1],
                      f'# {start} "{header_name}"', body,
                      f'# {line + 1} "{glue_name}"', *lines[line:]])


def _parse_error() -> type:
    """pycparser's ParseError (its module moved in pycparser 3)."""
    try:
        from pycparser.c_parser import ParseError
    except ImportError:  # pycparser 2.x
        from pycparser.plyparser import ParseError
    return ParseError


class _CProgram:
    """Normalises a translation unit parsed by pycparser."""

    def __init__(self, ast, report: ValidationReport):
        from pycparser import c_ast

        self.c_ast = c_ast
        self.report = report
        self.structs: dict[str, list] = {}
        self.struct_order: list[str] = []
        self.struct_coord: dict[str, object] = {}
        self.gvars: list[tuple[str, tuple, bool, object]] = []   # name, type, extern, node
        self.protos: list[tuple[str, tuple, list, object]] = []  # name, type, param names, node
        self.defs: list[tuple] = []   # name, type, param names, locals, body(), node
        self.scope: dict[str, tuple[str, tuple]] = {}            # file scope: name -> (kind, type)
        self.helpers_defined: dict[str, object] = {}
        self.helpers_used: set[str] = set()
        for ext in ast.ext:
            self._external(ext)

    # -- types ---------------------------------------------------------------

    def ctype(self, node, *, param: bool = False) -> tuple:
        a = self.c_ast
        if isinstance(node, a.TypeDecl):
            if node.quals:
                raise _Diff(f"qualifier {' '.join(node.quals)} is not in the printed subset", node.coord)
            inner = node.type
            if isinstance(inner, a.IdentifierType):
                key = tuple(sorted(inner.names))
                t = _C_INT_TYPES.get(key)
                if t is None:
                    raise _Diff(f"type {' '.join(inner.names)} is not in the printed subset", node.coord)
                return t
            if isinstance(inner, a.Struct):
                if inner.decls is not None:
                    raise _Diff(f"struct {inner.name} defined inside a declaration", node.coord)
                if inner.name not in self.structs:
                    raise _Diff(f"struct {inner.name} used before its definition", node.coord)
                return ("struct", inner.name)
            raise _Diff(f"type {type(inner).__name__} is not in the printed subset", node.coord)
        if isinstance(node, a.PtrDecl):
            if node.quals:
                raise _Diff("qualified pointer is not in the printed subset", node.coord)
            t = ("ptr", self.ctype(node.type))
        elif isinstance(node, a.ArrayDecl):
            if node.dim_quals or not isinstance(node.dim, a.Constant):
                raise _Diff("array without a constant size", node.coord)
            n, _ = _int_literal(node.dim.value)
            t = ("array", self.ctype(node.type), n)
        elif isinstance(node, a.FuncDecl):
            t = ("fun", tuple(p for _, p in self.params(node)), self.ctype(node.type))
        else:
            raise _Diff(f"declarator {type(node).__name__} is not in the printed subset", node.coord)
        if param and t[0] == "array":       # C11 6.7.6.3p7-8: parameter adjustment
            t = ("ptr", t[1])
        elif param and t[0] == "fun":
            t = ("ptr", t)
        return t

    def params(self, fdecl) -> list[tuple[str | None, tuple]]:
        a = self.c_ast
        if fdecl.args is None:
            raise _Diff("function declarator without a prototype", fdecl.coord)
        ps = fdecl.args.params
        if (len(ps) == 1 and isinstance(ps[0], a.Typename) and isinstance(ps[0].type, a.TypeDecl)
                and isinstance(ps[0].type.type, a.IdentifierType) and ps[0].type.type.names == ["void"]
                and not ps[0].quals):
            return []
        out = []
        for p in ps:
            if isinstance(p, a.EllipsisParam):
                raise _Diff("variadic function", p.coord)
            if isinstance(p, a.Decl):
                if p.storage or p.init is not None or p.funcspec or p.quals:
                    raise _Diff(f"parameter {p.name} with a storage class, qualifier or initialiser", p.coord)
                out.append((p.name, self.ctype(p.type, param=True)))
            elif isinstance(p, a.Typename):
                if p.quals:
                    raise _Diff("qualified parameter", p.coord)
                out.append((None, self.ctype(p.type, param=True)))
            else:
                raise _Diff(f"parameter {type(p).__name__}", p.coord)
        return out

    # -- file scope ------------------------------------------------------------

    def _declare(self, name: str, kind: str, t: tuple, node) -> None:
        if name in self.scope:
            old_kind, old_t = self.scope[name]
            # a function definition after its prototype is the one allowed redeclaration
            if not (kind == "function" and old_kind == "function" and old_t == t):
                raise _Diff(f"{name} declared twice", node.coord)
        self.scope[name] = (kind, t)

    def _external(self, ext) -> None:
        a = self.c_ast
        if isinstance(ext, a.Decl) and isinstance(ext.type, a.Struct):
            st = ext.type
            if ext.name is not None or ext.storage or ext.quals or st.decls is None or st.name is None:
                raise _Diff("a declaration other than a struct definition", ext.coord)
            if st.name in self.structs:
                raise _Diff(f"struct {st.name} defined twice", ext.coord)
            members = []
            for d in st.decls:
                if not isinstance(d, a.Decl) or d.bitsize is not None or d.init is not None or d.quals:
                    raise _Diff(f"member of struct {st.name} not in the printed subset", d.coord)
                t = self.ctype(d.type)
                if t[0] in ("fun", "void"):
                    raise _Diff(f"member {d.name} of struct {st.name} has type {show_type(t)}", d.coord)
                members.append((d.name, t))
            self.structs[st.name] = members
            self.struct_order.append(st.name)
            self.struct_coord[st.name] = ext.coord
            self.report.structs += 1
            return
        if isinstance(ext, a.Decl) and isinstance(ext.type, a.FuncDecl):
            if ext.storage or ext.funcspec or ext.quals or ext.init is not None:
                raise _Diff(f"prototype of {ext.name} with a storage class or specifier", ext.coord)
            ps = self.params(ext.type)
            t = ("fun", tuple(p for _, p in ps), self.ctype(ext.type.type))
            self._declare(ext.name, "function", t, ext)
            self.protos.append((ext.name, t, [n for n, _ in ps], ext))
            return
        if isinstance(ext, a.Decl):
            if ext.storage not in ([], ["extern"]) or ext.funcspec or ext.quals:
                raise _Diff(f"global {ext.name} with storage class {' '.join(ext.storage)}", ext.coord)
            if ext.init is not None:
                raise _Diff(f"global {ext.name} has an initialiser", ext.coord)
            t = self.ctype(ext.type)
            if t[0] == "void":
                raise _Diff(f"global {ext.name} of type void", ext.coord)
            self._declare(ext.name, "global", t, ext)
            self.gvars.append((ext.name, t, ext.storage == ["extern"], ext))
            return
        if isinstance(ext, a.FuncDef):
            self._function(ext)
            return
        raise _Diff(f"{type(ext).__name__} at file scope is not in the printed subset", ext.coord)

    def _function(self, fd) -> None:
        a = self.c_ast
        decl = fd.decl
        name = decl.name
        if fd.param_decls:
            raise _Diff(f"K&R definition of {name}", fd.coord)
        if name in _HELPER_TEXT:
            self._helper(fd)
            return
        if decl.storage or decl.funcspec or decl.quals:
            raise _Diff(f"function {name} with a storage class or specifier", fd.coord)
        ps = self.params(decl.type)
        if any(n is None for n, _ in ps):
            raise _Diff(f"function {name} has an unnamed parameter", fd.coord)
        t = ("fun", tuple(p for _, p in ps), self.ctype(decl.type.type))
        self._declare(name, "function", t, fd)
        items = fd.body.block_items or []
        local_types: dict[str, tuple] = {}
        for n, pt in ps:
            if n in local_types:
                raise _Diff(f"parameter {n} of {name} declared twice", fd.coord)
            local_types[n] = pt
        locals_: list[tuple[str, tuple]] = []
        k = 0
        while k < len(items) and isinstance(items[k], a.Decl):
            d = items[k]
            if d.storage or d.init is not None or d.funcspec or d.quals or isinstance(d.type, a.FuncDecl):
                raise _Diff(f"local {d.name} of {name} not in the printed subset", d.coord)
            lt = self.ctype(d.type)
            if d.name in local_types:
                raise _Diff(f"local {d.name} of {name} declared twice", d.coord)
            local_types[d.name] = lt
            locals_.append((d.name, lt))
            k += 1
        # the body is normalised when it is compared (after the declarations),
        # with the file-scope names declared before the definition
        fn = _CFunction(self, name, t, local_types, frozenset(self.scope))
        stmts = items[k:]

        def body() -> tuple[tuple, dict]:
            coords: dict[tuple, object] = {}
            try:
                return fn.stmts(stmts, (), coords), coords
            except _Diff as d:
                raise _Diff(f"function {name}: {d.message}", d.coord, d.detail) from None

        self.defs.append((name, t, [n for n, _ in ps], locals_, body, fd))
        self.report.functions += 1

    def _helper(self, fd) -> None:
        from pycparser import c_generator, c_parser

        name = fd.decl.name
        expected = c_parser.CParser().parse(_HELPER_TEXT[name]).ext[0]
        gen = c_generator.CGenerator()
        if gen.visit(fd) != gen.visit(expected):
            raise _Diff(f"helper {name} is not the documented definition", fd.coord,
                        detail=("C:  " + " ".join(gen.visit(fd).split()),
                                "doc: " + " ".join(gen.visit(expected).split())))
        if name in self.scope:
            raise _Diff(f"{name} declared twice", fd.coord)
        self.scope[name] = ("helper", ("fun", (ULLONG if name == F64_HELPER else UINT,),
                                       F64 if name == F64_HELPER else F32))
        self.helpers_defined[name] = fd


class _CFunction:
    """Normalises the body of one C function."""

    def __init__(self, prog: _CProgram, name: str, ftype: tuple, local_types: dict,
                 visible: frozenset):
        self.prog = prog
        self.visible = visible
        self.a = prog.c_ast
        self.name = name
        self.ret = ftype[2]
        self.locals = local_types

    # -- expressions -------------------------------------------------------------

    def const(self, node) -> tuple | None:
        """The value of a constant expression of the printed subset, or
        None if [node] is not one."""
        a = self.a
        if isinstance(node, a.Constant):
            self.prog.report.constants += 1
            if node.type in ("float", "double", "long double"):
                b, t = _float_literal(node.value)
                return ("constf", b, t)
            if "char" in node.type or "string" in node.type:
                raise _Diff(f"constant {node.value} is not in the printed subset", node.coord)
            v, t = _int_literal(node.value)
            return ("const", v, t)
        if isinstance(node, a.UnaryOp) and node.op == "-":
            c = self.const(node.expr)
            if c is None:
                raise _Diff("unary minus of a non-constant", node.coord)
            if c[0] == "constf":
                return ("constf", c[1] ^ (1 << (63 if c[2] == F64 else 31)), c[2])
            t = c[2]
            v = -c[1]
            if t[-1] == "signed" and _wrap(t, v) != v:
                raise _Diff("signed overflow in a constant", node.coord)
            return ("const", _wrap(t, v), t)
        if isinstance(node, a.BinaryOp) and node.op == "-":
            l, r = self.const(node.left), self.const(node.right)
            if l is None or r is None or l[0] != "const" or r[0] != "const":
                raise _Diff("subtraction other than of two integer constants", node.coord)
            t = _usual_arith(l[2], r[2])
            v = _wrap(t, l[1]) - _wrap(t, r[1])
            if t[-1] == "signed" and _wrap(t, v) != v:
                raise _Diff("signed overflow in a constant", node.coord)
            return ("const", _wrap(t, v), t)
        return None

    def expr(self, node) -> tuple:
        a = self.a
        self.prog.report.expressions += 1
        c = self.const(node)
        if c is not None:
            return c
        if isinstance(node, a.ID):
            x = node.name
            if x in self.locals:
                return ("ref", "local", x, self.locals[x])
            if x in self.visible:
                kind, t = self.prog.scope[x]
                if kind == "helper":
                    raise _Diff(f"{x} used other than as a constant", node.coord)
                return ("ref", kind, x, t)
            raise _Diff(f"{x} is not declared", node.coord)
        if isinstance(node, a.UnaryOp) and node.op == "*":
            e = self.expr(node.expr)
            if typeof(e)[0] != "ptr":
                raise _Diff(f"dereference of a {show_type(typeof(e))}", node.coord)
            return ("deref", e, typeof(e)[1])
        if isinstance(node, a.UnaryOp) and node.op == "&":
            e = self.expr(node.expr)
            if e[0] not in ("ref", "deref", "field", "index") or (e[0] == "ref" and e[1] not in ("local", "global", "function")):
                raise _Diff("address of a non-lvalue", node.coord)
            return ("addrof", e, ("ptr", typeof(e)))
        if isinstance(node, a.StructRef):
            e = self.expr(node.name)
            if node.type == "->":
                if typeof(e)[0] != "ptr":
                    raise _Diff(f"-> applied to a {show_type(typeof(e))}", node.coord)
                e = ("deref", e, typeof(e)[1])
            t = typeof(e)
            if t[0] != "struct":
                raise _Diff(f"field {node.field.name} of a {show_type(t)}", node.coord)
            members = dict(self.prog.structs[t[1]])
            f = node.field.name
            if f not in members:
                raise _Diff(f"struct {t[1]} has no member {f}", node.coord)
            return ("field", e, f, members[f])
        if isinstance(node, a.ArrayRef):
            e, i = self.expr(node.name), self.expr(node.subscript)
            if typeof(e)[0] != "array" or not _is_int(typeof(i)):
                raise _Diff("subscript other than of an array by an integer", node.coord)
            return ("index", e, i, typeof(e)[1])
        if isinstance(node, a.Cast):
            if node.to_type.quals:
                raise _Diff("qualified cast", node.coord)
            e = self.expr(node.expr)
            return ("cast", e, self.prog.ctype(node.to_type.type))
        if isinstance(node, a.FuncCall) and isinstance(node.name, a.ID) and node.name.name in _HELPER_TEXT:
            h = node.name.name
            if h not in self.visible:
                raise _Diff(f"{h} used before its definition", node.coord)
            args = node.args.exprs if node.args is not None else []
            arg = self.const(args[0]) if len(args) == 1 else None
            want = ULLONG if h == F64_HELPER else UINT
            if arg is None or arg[0] != "const" or arg[2] != want:
                raise _Diff(f"{h} applied to something else than one {show_type(want)} constant", node.coord)
            self.prog.helpers_used.add(h)
            return ("constf", arg[1], F64 if h == F64_HELPER else F32)
        raise _Diff(f"expression {type(node).__name__}"
                    f"{' ' + node.op if hasattr(node, 'op') else ''} is not in the printed subset", node.coord)

    def converted(self, e: tuple, target: tuple, node, what: str, *, assignment: bool) -> None:
        """Check the implicit conversion of [e] to [target] that C performs
        in an assignment (or argument passing, or return)."""
        t = typeof(e)
        if t == target:
            return
        if e[0] == "const" and t == INT and target[0] == "int" and _wrap(target, e[1]) == e[1]:
            return  # an 8/16-bit constant, printed as an int literal of the same value
        if not assignment and _is_arith(t) and _is_arith(target):
            return  # arguments: converted as by a cast, as eval_exprlist does
        raise _Diff(f"{what}: implicit conversion from {show_type(t)} to {show_type(target)}", node.coord)

    # -- statements ----------------------------------------------------------------

    def block(self, node, path, coords) -> tuple:
        a = self.a
        if node is None:
            return ()
        if isinstance(node, a.Compound):
            return self.stmts(node.block_items or [], path, coords)
        return self.stmts([node], path, coords)

    def stmts(self, items, path: tuple, coords: dict) -> tuple:
        a = self.a
        out: list = []
        for node in items:
            if isinstance(node, a.Compound):
                for s in self.block(node, path + (len(out),), {}):
                    coords[path + (len(out),)] = node.coord
                    out.append(s)
                continue
            if isinstance(node, a.EmptyStatement):
                continue
            here = path + (len(out),)
            coords[here] = node.coord
            self.prog.report.statements += 1
            out.append(self.stmt(node, here, coords))
        return tuple(out)

    def stmt(self, node, path, coords) -> tuple:
        a = self.a
        if isinstance(node, a.Assignment):
            if node.op != "=":
                raise _Diff(f"compound assignment {node.op}", node.coord)
            lhs = self.expr(node.lvalue)
            if lhs[0] not in ("ref", "deref", "field", "index") or (lhs[0] == "ref" and lhs[1] not in ("local", "global")):
                raise _Diff("assignment to a non-lvalue", node.coord)
            if typeof(lhs)[0] in ("array", "fun", "void"):
                raise _Diff(f"assignment of a {show_type(typeof(lhs))}", node.coord)
            if isinstance(node.rvalue, a.FuncCall) and not (
                    isinstance(node.rvalue.name, a.ID) and node.rvalue.name.name in _HELPER_TEXT):
                if lhs[0] != "ref" or lhs[1] != "local":
                    raise _Diff("a call result stored elsewhere than in a local", node.coord)
                f, args = self.call(node.rvalue)
                self.converted(("call-result", typeof(f)[2]), typeof(lhs), node, "call result", assignment=True)
                return ("call", lhs, f, args)
            rhs = self.expr(node.rvalue)
            self.converted(rhs, typeof(lhs), node, "assignment", assignment=True)
            return ("assign", lhs, rhs)
        if isinstance(node, a.FuncCall):
            f, args = self.call(node)
            return ("call", None, f, args)
        if isinstance(node, a.If):
            c = self.expr(node.cond)
            if not _is_scalar(typeof(c)):
                raise _Diff(f"condition of type {show_type(typeof(c))}", node.coord)
            return ("if", c, self.block(node.iftrue, path + ("then",), coords),
                    self.block(node.iffalse, path + ("else",), coords))
        if isinstance(node, a.For):
            if node.init is not None or node.cond is not None or node.next is not None:
                raise _Diff("for loop other than for (;;)", node.coord)
            return ("loop", self.block(node.stmt, path + ("body",), coords))
        if isinstance(node, a.While):
            c = self.expr(node.cond)
            if not _is_scalar(typeof(c)):
                raise _Diff(f"condition of type {show_type(typeof(c))}", node.coord)
            body = self.block(node.stmt, path + ("body",), coords)
            # while (c) s  =  for (;;) { if (c) { } else { break; } s }
            shifted = {k[:len(path) + 1] + (k[len(path) + 1] + 1,) + k[len(path) + 2:]: v
                       for k, v in coords.items() if k[:len(path) + 1] == path + ("body",) and len(k) > len(path) + 1}
            for k in [k for k in coords if k[:len(path) + 1] == path + ("body",) and len(k) > len(path) + 1]:
                del coords[k]
            coords.update(shifted)
            coords[path + ("body", 0)] = node.coord
            return ("loop", (("if", c, (), (("break",),)),) + body)
        if isinstance(node, a.Break):
            return ("break",)
        if isinstance(node, a.Return):
            if node.expr is None:
                if self.ret != VOID:
                    raise _Diff("return without a value in a non-void function", node.coord)
                return ("return", None)
            e = self.expr(node.expr)
            if self.ret == VOID:
                raise _Diff("return with a value in a void function", node.coord)
            self.converted(e, self.ret, node, "return", assignment=False)
            return ("return", e)
        raise _Diff(f"statement {type(node).__name__} is not in the printed subset", node.coord)

    def call(self, node) -> tuple[tuple, tuple]:
        f = self.expr(node.name)
        ft = typeof(f)
        if ft[0] != "fun":
            raise _Diff(f"call of a {show_type(ft)}", node.coord)
        args = tuple(self.expr(x) for x in (node.args.exprs if node.args is not None else []))
        if len(args) != len(ft[1]):
            raise _Diff(f"call with {len(args)} arguments of a function of {len(ft[1])} parameters", node.coord)
        for k, (arg, pt) in enumerate(zip(args, ft[1])):
            if typeof(arg) != pt and not (_is_arith(typeof(arg)) and _is_arith(pt)):
                raise _Diff(f"argument {k + 1}: implicit conversion from {show_type(typeof(arg))} "
                            f"to {show_type(pt)}", node.coord)
        return f, args


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
    if isinstance(x, tuple) and x and x[0] in ("const", "constf", "ref", "deref", "addrof", "field", "index", "cast"):
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


def _validate(tu_text: str, sexp_text: str, require_main: str | None, label: str) -> ValidationReport:
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
    against the dump ([Printer.print_sexp]).  Raises
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

"""Printer validation, part 1: the shared vocabulary — the error and the
report, types of the C subset, constants (integer and float literals), and
the normalised expressions and statements both sides are turned into.

The whole method is described in :mod:`pyrosgen.verify.printer_validation`.
"""

from __future__ import annotations

import re
import struct
from dataclasses import dataclass, field
from fractions import Fraction
from pyrosgen.proof.coqdriver import CoqError

__all__ = [
    "PrinterValidationError",
    "ValidationReport",
    "F64_HELPER",
    "F32_HELPER",
    "FABS_HELPER",
    "FABSF_HELPER",
    "UNOPS",
    "BINOPS",
    "show_type",
    "show_expr",
    "show_stmt",
    "typeof",
]

F64_HELPER = "rosgen_f64_of_bits"
F32_HELPER = "rosgen_f32_of_bits"
FABS_HELPER = "rosgen_fabs"      # [Oabsfloat] on a double
FABSF_HELPER = "rosgen_fabsf"    # [Oabsfloat] on a float

#: The helpers' definitions as ROSGen.Printer prints them ([helper_lines]),
#: in the order it prints them (those used).
_HELPER_TEXT = {
    F64_HELPER: (
        "static double rosgen_f64_of_bits(unsigned long long b)\n{\n"
        "    union { unsigned long long u; double d; } x;\n    x.u = b;\n    return x.d;\n}\n"
    ),
    F32_HELPER: (
        "static float rosgen_f32_of_bits(unsigned int b)\n{\n"
        "    union { unsigned int u; float f; } x;\n    x.u = b;\n    return x.f;\n}\n"
    ),
    FABS_HELPER: (
        "static double rosgen_fabs(double d)\n{\n"
        "    union { unsigned long long u; double d; } x;\n    x.d = d;\n"
        "    x.u &= 0x7fffffffffffffffULL;\n    return x.d;\n}\n"
    ),
    FABSF_HELPER: (
        "static float rosgen_fabsf(float f)\n{\n"
        "    union { unsigned int u; float f; } x;\n    x.f = f;\n"
        "    x.u &= 0x7fffffffU;\n    return x.f;\n}\n"
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


def _is_int(t: tuple) -> bool:
    return t[0] in ("int", "long")


def _is_arith(t: tuple) -> bool:
    return t[0] in ("int", "long", "float")


def _is_scalar(t: tuple) -> bool:
    return _is_arith(t) or t[0] == "ptr"


#: The helpers' C types.
_HELPER_TYPE = {
    F64_HELPER: ("fun", (ULLONG,), F64),
    F32_HELPER: ("fun", (UINT,), F32),
    FABS_HELPER: ("fun", (F64,), F64),
    FABSF_HELPER: ("fun", (F32,), F32),
}


# ---------------------------------------------------------------------------
# Operators ([Syntax.unary_operation], [Syntax.binary_operation])

#: Unary operators: the dump's atom -> the C text ([Printer.expr_doc]).
UNOPS = {"neg": "-", "notbool": "!", "absfloat": "fabs"}
#: Binary operators: the dump's atom -> the C token ([Printer.binop_token]).
BINOPS = {"add": "+", "sub": "-", "mul": "*", "div": "/", "mod": "%",
          "and": "&", "or": "|", "xor": "^",
          "eq": "==", "ne": "!=", "lt": "<", "gt": ">", "le": "<=", "ge": ">="}
#: The C token of a binary operator -> its name.
C_BINOPS = {tok: op for op, tok in BINOPS.items()}
#: The C unary operators of the subset (besides [*] and [&]) -> their names.
C_UNOPS = {"-": "neg", "!": "notbool"}

_COMPARISONS = frozenset({"eq", "ne", "lt", "gt", "le", "ge"})
_INTEGER_ONLY = frozenset({"mod", "and", "or", "xor"})
#: The operand types [Operators.arith_type] allows: exactly the types that
#: C's integer promotions and usual arithmetic conversions leave unchanged.
_OPERAND_TYPES = (INT, UINT, LLONG, ULLONG, F32, F64)


def _operand_type(what: str, t: tuple) -> None:
    """[t] must be one of the six operand types."""
    if t in _OPERAND_TYPES:
        return
    if t[0] == "int":
        raise _Diff(f"{what}: operand of type {show_type(t)}, which C promotes to int")
    raise _Diff(f"{what}: operand of type {show_type(t)}")


def _unop_type(op: str, t: tuple) -> tuple:
    """The C11 type of [op e] for [e] of type [t], when the subset allows
    it ([Operators.unop_type]); a :class:`_Diff` otherwise."""
    what = f"operator {UNOPS[op]}"
    if op == "absfloat":
        if t not in (F32, F64):
            raise _Diff(f"{what}: operand of type {show_type(t)}")
        return t
    _operand_type(what, t)
    return INT if op == "notbool" else t     # C11 6.5.3.3: [!e] is an int


def _binop_type(op: str, t1: tuple, t2: tuple) -> tuple:
    """The C11 type of [e1 op e2] for operands of types [t1], [t2], when the
    subset allows it ([Operators.binop_type]: the same type on both sides,
    one of the six, so that C converts nothing); a :class:`_Diff`
    otherwise."""
    what = f"operator {BINOPS[op]}"
    _operand_type(what, t1)
    _operand_type(what, t2)
    if t1 != t2:
        raise _Diff(f"{what}: operands of different types, {show_type(t1)} and {show_type(t2)}")
    if op in _INTEGER_ONLY and not _is_int(t1):
        raise _Diff(f"{what}: operands of type {show_type(t1)}")
    return INT if op in _COMPARISONS else t1   # C11 6.5.8-9: comparisons give an int


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
#   ('unop', op, e, type)        op: a key of UNOPS
#   ('binop', op, e1, e2, type)  op: a key of BINOPS
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
    if k == "unop":
        if e[1] == "absfloat":
            return f"fabs({show_expr(e[2])}) : {show_type(e[3])}"
        return f"({UNOPS[e[1]]}({show_expr(e[2])})) : {show_type(e[3])}"
    if k == "binop":
        return f"(({show_expr(e[2])}) {BINOPS[e[1]]} ({show_expr(e[3])})) : {show_type(e[4])}"
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

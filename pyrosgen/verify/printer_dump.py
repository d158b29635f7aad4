"""Printer validation, part 2: the AST side — the S-expression dump that
Coq printed (``<node>.sexp``, ``ROSGen.Dump.print_sexp``: independent of the
C printer), normalised (:mod:`printer_types`).
"""

from __future__ import annotations

from pyrosgen.proof.sexp import SexpError, parse_sexp, program_items
from pyrosgen.verify.printer_types import (
    BINOPS,
    F32,
    F64,
    INT,
    LLONG,
    UINT,
    ULLONG,
    UNOPS,
    ValidationReport,
    _Diff,
    _dump_type,
    _wrap,
    show_type,
    typeof,
)

# ---------------------------------------------------------------------------
# The dump side

_SIGN = {F64: 1 << 63, F32: 1 << 31}
_EXP = {F64: 0x7FF << 52, F32: 0xFF << 23}


def _fold_neg(op: str, e: tuple, t: tuple) -> tuple:
    """[('unop', op, e, t)], except where the printed text is the text of a
    constant.  [Oneg] of a constant the printer prints as a literal without
    a sign ([5], [5LL], [0x1p+0], [0x1p+0f]) prints as [(-5)]: in C that
    is the negative constant [-5] (the printer's own form of it, a sign
    before the literal), so it is normalised to it, the value negated
    exactly (no overflow: the literal is at most the type's maximum) or the
    sign bit flipped.  A negative or non-finite operand, or one of an
    unsigned type, stays an operation: [(-(-5))], [(-rosgen_f64_of_bits(...))],
    [(-5U)]."""
    if op == "neg" and e[0] in ("const", "constf") and typeof(e) == t:
        if e[0] == "const" and t in (INT, LLONG) and e[1] >= 0:
            return ("const", -e[1], t)
        if e[0] == "constf" and t in (F64, F32) and not e[1] & _SIGN[t] and e[1] & _EXP[t] != _EXP[t]:
            return ("constf", e[1] | _SIGN[t], t)
    return ("unop", op, e, t)


_INT_MIN = (-(1 << 31), ("const", -(1 << 31) + 1, INT), ("const", 1, INT), INT)


def _fold_min(op: str, e1: tuple, e2: tuple, t: tuple) -> tuple:
    """[('binop', op, e1, e2, t)], except [Osub] of the [int] constants
    [-2147483647] and [1]: it prints as [(-2147483647 - 1)], the printer's
    form of the constant [INT_MIN], of the same value and type, so it is
    that constant.  (The [long long] form [(-9223372036854775807LL - 1)]
    subtracts an [int]: as an operation it is ill-typed and refused.)"""
    v, c1, c2, ty = _INT_MIN
    if op == "sub" and (e1, e2, t) == (c1, c2, ty):
        return ("const", v, INT)
    return ("binop", op, e1, e2, t)


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
        if k == "unop":
            if len(e) != 4 or not isinstance(e[1], str) or e[1] not in UNOPS:
                raise _Diff(f"malformed unop {e!r:.80} in the dump")
            return _fold_neg(e[1], self.operand(e[2]), _dump_type(e[3]))
        if k == "binop":
            if len(e) != 5 or not isinstance(e[1], str) or e[1] not in BINOPS:
                raise _Diff(f"malformed binop {e!r:.80} in the dump")
            return _fold_min(e[1], self.operand(e[2]), self.operand(e[3]), _dump_type(e[4]))
        raise _Diff(f"unknown expression {k!r} in the dump")

    def operand(self, e) -> tuple:
        """An operand of an operation.  An 8- or 16-bit integer constant
        keeps its own type here: it prints as an [int] literal, which C
        does not convert to the narrow type in an operation, so the C side
        (an [int] operand) differs from it."""
        n = self.expr(e)
        if isinstance(e, list) and e[:1] == ["const_int"] and n[0] == "const":
            t = _dump_type(e[2])
            if t != n[2]:
                return ("const", n[1], t)
        return n

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


#: The external functions whose C name is fixed, with their meaning tag and
#: signature ([Typing.ef_signature]): the C text shows only the name and the
#: type, and the wrapper over roscpp defines the function of that name, so
#: the tag, the name and the type must agree.  ``ros_now``: ROS time in
#: nanoseconds, ``unsigned long long ros_now(void)``; ``ros_time_sec`` and
#: ``ros_time_nsec``: its seconds and nanoseconds, ``unsigned int``.
FIXED_EXTERNALS: dict[str, tuple[list, tuple]] = {
    "ros_now": (["ros_now"], ("fun", (), ULLONG)),
    "ros_time_sec": (["ros_time_sec"], ("fun", (), UINT)),
    "ros_time_nsec": (["ros_time_nsec"], ("fun", (), UINT)),
}


def _check_fixed_external(name: str, ef, ty: tuple) -> None:
    """An external of :data:`FIXED_EXTERNALS`, by name or by tag, has the
    other two (name, tag, type) of that entry."""
    tag = ef[0] if isinstance(ef, list) and ef and isinstance(ef[0], str) else None
    for fixed, (want_ef, want_ty) in FIXED_EXTERNALS.items():
        if name != fixed and tag != want_ef[0]:
            continue
        if name != fixed:
            raise _Diff(f"external {name} of the dump has the meaning tag ({tag}) of {fixed}")
        if ef != want_ef:
            raise _Diff(f"external {name} of the dump has the meaning tag {_show_ef(ef)}, not "
                        f"{_show_ef(want_ef)}")
        if ty != want_ty:
            raise _Diff(f"external {name} of the dump has the type {show_type(ty)}, not {show_type(want_ty)}")


def _show_ef(ef) -> str:
    if isinstance(ef, list):
        return "(" + " ".join(_show_ef(x) for x in ef) + ")"
    return str(ef)


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
        for n, v in it["externals"].items():
            _check_fixed_external(n, v[0], self.externals[n])
        self.functions = {n: _DumpFunction(self, item) for n, item in it["functions"].items()}
        self.funcs = set(self.externals) | set(self.functions)
        names = [n for k, n in it["order"] if k != "struct"]
        if len(names) != len(set(names)):
            raise _Diff("the dump defines a global name twice")

"""Printer validation of the arithmetic operators ([Eunop], [Ebinop]),
on hand-written pairs of a C text and a dump (no Coq involved).

The program is one function ``f`` whose temporaries ``a_K``, ``b_K`` have
each type ``K`` (the six operand types, and ``unsigned char``, ``short``
and ``int *``), and globals ``r_K`` that receive the results.  Each case
gives the statement as the printer prints it (``(e1 OP e2)``, ``(-e)``,
``(!e)``, ``rosgen_fabs(e)``) and as the dump shows it.

- every operator on every type it allows is accepted, and the same C
  text against a dump with another operator, or another result type, is
  refused;
- the sign of constants: ``(-5)`` is the constant ``-5`` whether the AST
  has [Oneg 5] or [-5]; ``(-(-5))`` and ``(-(-0x1p+0))`` are [Oneg] of the
  negative constant; ``(-2147483647 - 1)`` is ``INT_MIN``;
- refused: swapped operands, a comparison annotated with a type other
  than ``int``, operands of different types, operands that C promotes
  (``unsigned char``, ``short``) and their 8/16-bit constants, pointer
  operands, ``%`` on doubles, ``&&``, ``||``, ``<<``, ``~``, unary ``+``;
- the helpers ``rosgen_fabs`` / ``rosgen_fabsf``: accepted when defined
  as documented and used on their own type; refused when used but not
  defined, defined but not used, altered, out of order, or applied to the
  other floating type.
"""

from __future__ import annotations

import pytest

from pyrosgen.verify.printer_validation import PrinterValidationError, validate_program

# K -> (C type, dump type)
TYPES = {
    "int": ("int", "(int I32 signed)"),
    "uint": ("unsigned int", "(int I32 unsigned)"),
    "ll": ("long long", "(long signed)"),
    "ull": ("unsigned long long", "(long unsigned)"),
    "f": ("float", "(float F32)"),
    "d": ("double", "(float F64)"),
    "uc": ("unsigned char", "(int I8 unsigned)"),
    "s": ("short", "(int I16 signed)"),
    "p": ("int *", "(ptr (int I32 signed))"),
}
ALLOWED = ["int", "uint", "ll", "ull", "f", "d"]
INTEGERS = ["int", "uint", "ll", "ull"]

ARITH = {"add": "+", "sub": "-", "mul": "*", "div": "/"}
BITWISE = {"mod": "%", "and": "&", "or": "|", "xor": "^"}
COMPARE = {"eq": "==", "ne": "!=", "lt": "<", "gt": ">", "le": "<=", "ge": ">="}
ALL_BINOPS = {**ARITH, **BITWISE, **COMPARE}

# The helpers, as the printer prints them (the documented text, written
# out here independently of the validator's copy).
HELPERS = {
    "rosgen_f64_of_bits": """static double rosgen_f64_of_bits(unsigned long long b)
{
    union { unsigned long long u; double d; } x;
    x.u = b;
    return x.d;
}
""",
    "rosgen_f32_of_bits": """static float rosgen_f32_of_bits(unsigned int b)
{
    union { unsigned int u; float f; } x;
    x.u = b;
    return x.f;
}
""",
    "rosgen_fabs": """static double rosgen_fabs(double d)
{
    union { unsigned long long u; double d; } x;
    x.d = d;
    x.u &= 0x7fffffffffffffffULL;
    return x.d;
}
""",
    "rosgen_fabsf": """static float rosgen_fabsf(float f)
{
    union { unsigned int u; float f; } x;
    x.f = f;
    x.u &= 0x7fffffffU;
    return x.f;
}
""",
}


def _decl(k: str, name: str) -> str:
    c = TYPES[k][0]
    return f"{c}{name}" if c.endswith("*") else f"{c} {name}"


def program(c_stmts: list[str], dump_stmts: list[str], helpers=(), helper_text=None) -> tuple[str, str]:
    """The C text and the dump of the program whose function ``f`` runs
    the given statements."""
    text = helper_text if helper_text is not None else "".join(HELPERS[h] + "\n" for h in helpers)
    c = [text + "".join(f"{_decl(k, 'r_' + k)};\n" for k in TYPES) + "\nvoid f(void);\n\nvoid f(void)\n{"]
    c += [f"    {_decl(k, x + '_' + k)};" for k in TYPES for x in "ab"]
    c += [f"    {s}" for s in c_stmts]
    c += ["}", ""]
    temps = " ".join(f"({x}_{k} {t})" for k, (_, t) in TYPES.items() for x in "ab")
    gvars = "\n".join(f"(gvar r_{k} {t})" for k, (_, t) in TYPES.items())
    dump = (f"(program\n(externs)\n(main f)\n{gvars}\n(function f void\n  (params)\n  (vars)\n"
            f"  (temps {temps})\n  (body\n    (seq\n      " + "\n      ".join(dump_stmts + ["(skip)"])
            + "))))\n")
    return "\n".join(c), dump


def t(k: str) -> str:
    return TYPES[k][1]


def tv(x: str, k: str) -> str:
    return f"(tempvar {x}_{k} {t(k)})"


def assign(k: str, e: str) -> str:
    return f"(assign (var r_{k} {t(k)}) {e})"


def check(c_stmts, dump_stmts, helpers=(), **kw):
    c, s = program(c_stmts, dump_stmts, helpers, **kw)
    return validate_program(c, s, name="arith.c")


def refused(match: str, c_stmts, dump_stmts, helpers=(), **kw) -> str:
    with pytest.raises(PrinterValidationError, match=match) as info:
        check(c_stmts, dump_stmts, helpers, **kw)
    return str(info.value)


def test_the_frame_validates():
    """The program without operations (so that each failure below is due
    to its operation)."""
    rep = check([f"r_{k} = a_{k};" for k in ALLOWED], [assign(k, tv("a", k)) for k in ALLOWED])
    assert rep.statements == len(ALLOWED) and rep.functions == 1 and rep.helpers == []


# ---------------------------------------------------------------------------
# Every operator on every type it allows

BINOP_CASES = ([(op, k) for op in ARITH for k in ALLOWED] + [(op, k) for op in BITWISE for k in INTEGERS]
               + [(op, k) for op in COMPARE for k in ALLOWED])


@pytest.mark.parametrize("op,k", BINOP_CASES)
def test_binop_accepted(op, k):
    res = "int" if op in COMPARE else k
    c = [f"r_{res} = (a_{k} {ALL_BINOPS[op]} b_{k});"]
    d = [assign(res, f"(binop {op} {tv('a', k)} {tv('b', k)} {t(res)})")]
    rep = check(c, d)
    assert rep.statements == 1 and rep.expressions == 4
    # the same C text against the dump of another operator: refused
    other = "sub" if op != "sub" else "add"
    if op in COMPARE:
        other = "ne" if op != "ne" else "eq"
    d2 = [assign(res, f"(binop {other} {tv('a', k)} {tv('b', k)} {t(res)})")]
    msg = refused(r"function f, statement 1 differs", c, d2)
    assert f"first difference: C has {op}" in msg and f"AST has {other}" in msg


@pytest.mark.parametrize("op", list(BITWISE))
@pytest.mark.parametrize("k", ["f", "d"])
def test_integer_operator_on_floats_refused(op, k):
    refused(rf"operator \{ALL_BINOPS[op]}: operands of type {TYPES[k][0]}",
            [f"r_{k} = (a_{k} {ALL_BINOPS[op]} b_{k});"],
            [assign(k, f"(binop {op} {tv('a', k)} {tv('b', k)} {t(k)})")])


@pytest.mark.parametrize("k", ALLOWED)
def test_unops_accepted(k):
    c = [f"r_{k} = (-a_{k});", f"r_int = (!a_{k});", f"r_{k} = (-(-a_{k}));"]
    d = [assign(k, f"(unop neg {tv('a', k)} {t(k)})"),
         assign("int", f"(unop notbool {tv('a', k)} {t('int')})"),
         assign(k, f"(unop neg (unop neg {tv('a', k)} {t(k)}) {t(k)})")]
    assert check(c, d).statements == 3
    # [!] is an int, whatever its operand
    if k != "int":
        refused(r"statement 2 differs", c, [d[0], assign("int", f"(unop notbool {tv('a', k)} {t(k)})"), d[2]])
    # [-] is not [!]
    refused(r"statement 1 differs", c, [d[0].replace("unop neg", "unop notbool")] + d[1:])


@pytest.mark.parametrize("k,helper", [("d", "rosgen_fabs"), ("f", "rosgen_fabsf")])
def test_absfloat_accepted(k, helper):
    c = [f"r_{k} = {helper}(a_{k});", f"r_{k} = {helper}((-(a_{k} * b_{k})));"]
    d = [assign(k, f"(unop absfloat {tv('a', k)} {t(k)})"),
         assign(k, f"(unop absfloat (unop neg (binop mul {tv('a', k)} {tv('b', k)} {t(k)}) {t(k)}) {t(k)})")]
    rep = check(c, d, [helper])
    assert rep.helpers == [helper]
    # [fabs] is not [-]
    refused(r"statement 1 differs", c, [d[0].replace("unop absfloat", "unop neg")] + d[1:], [helper])


def test_all_helpers_in_order():
    c = ["r_d = rosgen_fabs(rosgen_f64_of_bits(0x7ff0000000000000ULL));",
         "r_f = rosgen_fabsf(rosgen_f32_of_bits(0xff800000U));"]
    d = [assign("d", f"(unop absfloat (const_float 0x7ff0000000000000 {t('d')}) {t('d')})"),
         assign("f", f"(unop absfloat (const_single 0xff800000 {t('f')}) {t('f')})")]
    order = ["rosgen_f64_of_bits", "rosgen_f32_of_bits", "rosgen_fabs", "rosgen_fabsf"]
    assert check(c, d, order).helpers == sorted(order)
    refused(r"helper rosgen_f32_of_bits defined after rosgen_fabs", c, d,
            ["rosgen_f64_of_bits", "rosgen_fabs", "rosgen_f32_of_bits", "rosgen_fabsf"])
    refused(r"helper rosgen_fabs defined after rosgen_fabsf", c, d,
            ["rosgen_f64_of_bits", "rosgen_f32_of_bits", "rosgen_fabsf", "rosgen_fabs"])


def test_nested_operations_and_grouping():
    """Operands print at their own precedence: a binop operand carries its
    parentheses.  The comparison is on trees: dropping a pair of
    parentheses that C does not need is the same tree; dropping one that
    changes the grouping is a difference."""
    d = [assign("int", f"(binop sub {tv('a', 'int')} (binop sub {tv('b', 'int')} {tv('a', 'int')} {t('int')})"
                       f" {t('int')})"),
         assign("int", f"(binop lt (binop add {tv('a', 'int')} (binop mul {tv('b', 'int')} {tv('b', 'int')} "
                       f"{t('int')}) {t('int')}) (unop neg {tv('a', 'int')} {t('int')}) {t('int')})")]
    printed = ["r_int = (a_int - (b_int - a_int));", "r_int = ((a_int + (b_int * b_int)) < (-a_int));"]
    check(printed, d)
    check(["r_int = a_int - (b_int - a_int);", "r_int = a_int + b_int * b_int < -a_int;"], d)
    refused(r"statement 1 differs", ["r_int = a_int - b_int - a_int;", printed[1]], d)
    refused(r"statement 2 differs", [printed[0], "r_int = ((a_int + b_int) * b_int < (-a_int));"], d)


# ---------------------------------------------------------------------------
# The sign of constants

I, LL, D, F = t("int"), t("ll"), t("d"), t("f")


@pytest.mark.parametrize("c,dump", [
    # [Oneg] of a constant printed without a sign is the negative constant
    ("r_int = (-5);", f"(unop neg (const_int 5 {I}) {I})"),
    ("r_int = (-5);", f"(const_int -5 {I})"),
    ("r_int = (-0);", f"(unop neg (const_int 0 {I}) {I})"),
    ("r_ll = (-5LL);", f"(unop neg (const_long 5 {LL}) {LL})"),
    ("r_d = (-0x1p+0);", f"(unop neg (const_float 0x3ff0000000000000 {D}) {D})"),
    ("r_d = (-0x0p+0);", f"(unop neg (const_float 0x0000000000000000 {D}) {D})"),
    ("r_d = -0x0p+0;", f"(unop neg (const_float 0x0000000000000000 {D}) {D})"),
    ("r_f = (-0x1.8p+1f);", f"(unop neg (const_single 0x40400000 {F}) {F})"),
    # [Oneg] of a negative constant: an operation on the negative constant
    ("r_int = (-(-5));", f"(unop neg (const_int -5 {I}) {I})"),
    ("r_int = (-(-5));", f"(unop neg (unop neg (const_int 5 {I}) {I}) {I})"),
    ("r_ll = (-(-5LL));", f"(unop neg (const_long -5 {LL}) {LL})"),
    ("r_d = (-(-0x1p+0));", f"(unop neg (const_float 0xbff0000000000000 {D}) {D})"),
    ("r_d = (-(-0x1p+0));", f"(unop neg (unop neg (const_float 0x3ff0000000000000 {D}) {D}) {D})"),
    ("r_f = (-(-0x1p+0f));", f"(unop neg (const_single 0xbf800000 {F}) {F})"),
    ("r_int = (-(-2147483647 - 1));", f"(unop neg (const_int -2147483648 {I}) {I})"),
    # unsigned and non-finite constants: an operation
    ("r_uint = (-5U);", f"(unop neg (const_int 5 {t('uint')}) {t('uint')})"),
    ("r_ull = (-5ULL);", f"(unop neg (const_long 5 {t('ull')}) {t('ull')})"),
    ("r_d = (-rosgen_f64_of_bits(0x7ff0000000000000ULL));",
     f"(unop neg (const_float 0x7ff0000000000000 {D}) {D})"),
    ("r_d = (-rosgen_f64_of_bits(0xfff8000000000001ULL));",
     f"(unop neg (const_float 0xfff8000000000001 {D}) {D})"),
    # the printer's INT_MIN
    ("r_int = (-2147483647 - 1);", f"(const_int -2147483648 {I})"),
    ("r_int = (-2147483647 - 1);", f"(binop sub (const_int -2147483647 {I}) (const_int 1 {I}) {I})"),
    ("r_int = ((-2147483647) - 1);",
     f"(binop sub (unop neg (const_int 2147483647 {I}) {I}) (const_int 1 {I}) {I})"),
    ("r_int = (-2147483647 - 2);", f"(binop sub (const_int -2147483647 {I}) (const_int 2 {I}) {I})"),
    ("r_ll = (-9223372036854775807LL - 1);", f"(const_long -9223372036854775808 {LL})"),
    ("r_ll = (-9223372036854775807LL - 1LL);",
     f"(binop sub (const_long -9223372036854775807 {LL}) (const_long 1 {LL}) {LL})"),
    ("r_int = (7 % (-b_int));", f"(binop mod (const_int 7 {I}) (unop neg {tv('b', 'int')} {I}) {I})"),
])
def test_constant_signs_accepted(c, dump):
    k = c.split()[0][2:]
    helpers = ["rosgen_f64_of_bits"] if "rosgen_f64_of_bits" in c else []
    check([c], [assign(k, dump)], helpers)


@pytest.mark.parametrize("c,dump", [
    ("r_int = (-(-5));", f"(const_int 5 {I})"),
    ("r_int = (-5);", f"(unop neg (const_int -5 {I}) {I})"),
    ("r_d = (-(-0x1p+0));", f"(const_float 0x3ff0000000000000 {D})"),
    ("r_d = (-0x1p+0);", f"(unop neg (const_float 0xbff0000000000000 {D}) {D})"),
    ("r_uint = (-5U);", f"(const_int -5 {t('uint')})"),
    ("r_d = (-rosgen_f64_of_bits(0x7ff0000000000000ULL));", f"(const_float 0xfff0000000000000 {D})"),
    ("r_int = (-2147483647 - 2);", f"(const_int -2147483649 {I})"),
    # [Oneg] annotated with another type than its operand's
    ("r_int = (-5);", f"(unop neg (const_int 5 {I}) {t('uint')})"),
    ("r_ll = (-9223372036854775807LL - 1LL);", f"(const_long -9223372036854775808 {LL})"),
])
def test_constant_signs_refused(c, dump):
    k = c.split()[0][2:]
    helpers = ["rosgen_f64_of_bits"] if "rosgen_f64_of_bits" in c else []
    refused(r"statement 1 differs|implicit conversion", [c], [assign(k, dump)], helpers)


def test_long_long_minimum_as_an_operation_is_refused():
    """[Osub] of the [long long] constant and the [int] constant 1 prints
    like the printer's LLONG_MIN, but it is ill-typed: a difference."""
    refused(r"statement 1 differs",
            ["r_ll = (-9223372036854775807LL - 1);"],
            [assign("ll", f"(binop sub (const_long -9223372036854775807 {LL}) (const_int 1 {I}) {LL})")])


# ---------------------------------------------------------------------------
# Refused: differences between the C text and the dump

def test_swapped_operands():
    c = ["r_int = (b_int - a_int);"]
    msg = refused(r"function f, statement 1 differs", c,
                  [assign("int", f"(binop sub {tv('a', 'int')} {tv('b', 'int')} {I})")])
    assert "C has b_int" in msg and "AST has a_int" in msg
    check(c, [assign("int", f"(binop sub {tv('b', 'int')} {tv('a', 'int')} {I})")])


@pytest.mark.parametrize("res", ["uint", "ll", "d"])
def test_comparison_annotated_with_another_type(res):
    msg = refused(r"statement 1 differs|implicit conversion",
                  [f"r_{res} = (a_d < b_d);"],
                  [assign(res, f"(binop lt {tv('a', 'd')} {tv('b', 'd')} {t(res)})")])
    assert "int" in msg


def test_comparison_result_is_int():
    """The same comparison into an [int]: accepted; annotated [double]:
    the first difference is the type of the operation."""
    c = ["r_int = (a_d < b_d);"]
    check(c, [assign("int", f"(binop lt {tv('a', 'd')} {tv('b', 'd')} {I})")])
    msg = refused(r"statement 1 differs", c, [assign("int", f"(binop lt {tv('a', 'd')} {tv('b', 'd')} {D})")])
    assert "C has int" in msg and "AST has double" in msg


def test_arithmetic_annotated_with_another_type():
    refused(r"statement 1 differs", ["r_int = (a_int + b_int);"],
            [assign("int", f"(binop add {tv('a', 'int')} {tv('b', 'int')} {t('uint')})")])


@pytest.mark.parametrize("k1,k2", [("int", "uint"), ("int", "ll"), ("uint", "ull"), ("f", "d"), ("int", "d"),
                                   ("ll", "ull")])
def test_operands_of_different_types(k1, k2):
    for res in (k1, k2):
        refused(rf"operands of different types, {TYPES[k1][0]} and {TYPES[k2][0]}",
                [f"r_{res} = (a_{k1} + b_{k2});"],
                [assign(res, f"(binop add {tv('a', k1)} {tv('b', k2)} {t(res)})")])
    refused(r"operands of different types",
            [f"r_int = (a_{k1} == b_{k2});"],
            [assign("int", f"(binop eq {tv('a', k1)} {tv('b', k2)} {I})")])


def test_constant_of_another_type():
    """[(a_ll + 1)]: the literal [1] is an [int]; the AST's [1LL] prints
    [1LL]."""
    d = [assign("ll", f"(binop add {tv('a', 'll')} (const_long 1 {LL}) {LL})")]
    check(["r_ll = (a_ll + 1LL);"], d)
    refused(r"operands of different types, long long and int", ["r_ll = (a_ll + 1);"], d)


@pytest.mark.parametrize("k", ["uc", "s"])
def test_promoted_operands(k):
    name = TYPES[k][0]
    refused(rf"operand of type {name}, which C promotes to int",
            [f"r_int = (a_{k} + b_{k});"],
            [assign("int", f"(binop add {tv('a', k)} {tv('b', k)} {I})")])
    refused(rf"operand of type {name}, which C promotes to int",
            [f"r_{k} = (a_{k} & b_{k});"],
            [assign(k, f"(binop and {tv('a', k)} {tv('b', k)} {t(k)})")])
    refused(rf"operand of type {name}, which C promotes to int",
            [f"r_int = (-a_{k});"], [assign("int", f"(unop neg {tv('a', k)} {I})")])
    refused(rf"operand of type {name}, which C promotes to int",
            [f"r_int = (!a_{k});"], [assign("int", f"(unop notbool {tv('a', k)} {I})")])


def test_narrow_constant_operand():
    """An 8-bit constant prints as an [int] literal: as an assignment's
    right-hand side that is the same (C converts it), as an operand it is
    not (C computes in [int])."""
    c8 = f"(const_int 5 {t('uc')})"
    check(["r_uc = 5;"], [assign("uc", c8)])
    msg = refused(r"statement 1 differs", ["r_int = (a_int + 5);"],
                  [assign("int", f"(binop add {tv('a', 'int')} {c8} {I})")])
    assert "unsigned char" in msg
    refused(r"statement 1 differs", ["r_int = (-5);"], [assign("int", f"(unop neg {c8} {I})")])


def test_pointer_operands():
    refused(r"operand of type int \*", ["r_int = (a_p == b_p);"],
            [assign("int", f"(binop eq {tv('a', 'p')} {tv('b', 'p')} {I})")])
    refused(r"operand of type int \*", ["r_int = (!a_p);"], [assign("int", f"(unop notbool {tv('a', 'p')} {I})")])


@pytest.mark.parametrize("c", [
    "r_int = (a_int && b_int);",
    "r_int = (a_int || b_int);",
    "r_int = (a_int << b_int);",
    "r_int = (a_int >> b_int);",
    "r_int = (~a_int);",
    "r_int = (+a_int);",
    "r_int = (a_int ? b_int : a_int);",
    "r_int = (a_int , b_int);",
])
def test_other_operators_refused(c):
    # the dump is an operation the printer would print otherwise
    d = [assign("int", f"(binop and {tv('a', 'int')} {tv('b', 'int')} {I})")]
    check(["r_int = (a_int & b_int);"], d)
    refused(r"not in the printed subset", [c], d)


def test_compound_assignment_refused():
    refused(r"compound assignment", ["r_int += a_int;"],
            [assign("int", f"(binop add (var r_int {I}) {tv('a', 'int')} {I})")])


def test_malformed_dump_operations():
    refused(r"malformed binop", ["r_int = (a_int & b_int);"],
            [assign("int", f"(binop shl {tv('a', 'int')} {tv('b', 'int')} {I})")])
    refused(r"malformed unop", ["r_int = (-a_int);"], [assign("int", f"(unop not {tv('a', 'int')} {I})")])
    refused(r"malformed binop", ["r_int = (a_int + b_int);"],
            [assign("int", f"(binop add {tv('a', 'int')} {I})")])


# ---------------------------------------------------------------------------
# The fabs helpers

FABS_C = ["r_d = rosgen_fabs(a_d);"]
FABS_D = [assign("d", f"(unop absfloat {tv('a', 'd')} {D})")]


def test_helper_used_but_not_defined():
    refused(r"rosgen_fabs used before its definition", FABS_C, FABS_D)
    refused(r"rosgen_fabsf used before its definition", ["r_f = rosgen_fabsf(a_f);"],
            [assign("f", f"(unop absfloat {tv('a', 'f')} {F})")], ["rosgen_fabs"])


@pytest.mark.parametrize("helper", ["rosgen_fabs", "rosgen_fabsf"])
def test_helper_defined_but_not_used(helper):
    refused(rf"helper {helper} defined but not used", ["r_d = a_d;"], [assign("d", tv("a", "d"))], [helper])
    # both defined, one used
    other = "rosgen_fabsf" if helper == "rosgen_fabs" else "rosgen_fabs"
    k = "d" if other == "rosgen_fabs" else "f"
    refused(rf"helper {helper} defined but not used", [f"r_{k} = {other}(a_{k});"],
            [assign(k, f"(unop absfloat {tv('a', k)} {t(k)})")], ["rosgen_fabs", "rosgen_fabsf"])


@pytest.mark.parametrize("helper,old,new", [
    ("rosgen_fabs", "0x7fffffffffffffffULL", "0x7ffffffffffffffeULL"),
    ("rosgen_fabs", "x.u &= ", "x.u |= "),
    ("rosgen_fabs", "x.u &= 0x7fffffffffffffffULL;\n", ""),
    ("rosgen_fabs", "    return x.d;", "    return -x.d;"),
    ("rosgen_fabs", "x.d = d;", "x.u = d;"),
    ("rosgen_fabs", "static double", "double"),
    ("rosgen_fabs", "union { unsigned long long u; double d; }", "union { unsigned int u; double d; }"),
    ("rosgen_fabsf", "0x7fffffffU", "0xffffffffU"),
    ("rosgen_fabsf", "(float f)", "(double f)"),
    ("rosgen_fabsf", "x.u &= 0x7fffffffU;", "x.u &= 0x7fffffffU; x.u &= 0x7fffffffU;"),
])
def test_helper_text_altered(helper, old, new):
    k = "d" if helper == "rosgen_fabs" else "f"
    c = [f"r_{k} = {helper}(a_{k});"]
    d = [assign(k, f"(unop absfloat {tv('a', k)} {t(k)})")]
    check(c, d, [helper])
    text = HELPERS[helper]
    assert old in text
    refused(rf"helper {helper} is not the documented definition", c, d, helper_text=text.replace(old, new, 1) + "\n")


def test_helper_on_the_other_type():
    refused(r"rosgen_fabs applied to a float", ["r_d = rosgen_fabs(a_f);"],
            [assign("d", f"(unop absfloat {tv('a', 'f')} {D})")], ["rosgen_fabs"])
    refused(r"rosgen_fabsf applied to a double", ["r_f = rosgen_fabsf(a_d);"],
            [assign("f", f"(unop absfloat {tv('a', 'd')} {F})")], ["rosgen_fabsf"])
    refused(r"rosgen_fabs applied to a int", ["r_d = rosgen_fabs(a_int);"],
            [assign("d", f"(unop absfloat {tv('a', 'int')} {D})")], ["rosgen_fabs"])


def test_helper_used_otherwise():
    refused(r"rosgen_fabs applied to 2 arguments", ["r_d = rosgen_fabs(a_d, b_d);"], FABS_D, ["rosgen_fabs"])
    refused(r"rosgen_fabs used other than called", ["r_d = (rosgen_fabs == rosgen_fabs);"], FABS_D,
            ["rosgen_fabs"])

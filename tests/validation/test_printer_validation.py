"""Printer validation (pyrosgen/verify/printer_validation.py): the printed C is parsed with
pycparser and compared with the AST dump on every ``pyrosgen generate``.

- it passes on the generated LandShark and multi nodes, on the nodes
  with timed topics (rule 4.12: the velocity guard, the ok_fresh_* test
  models), and on the
  printer's example program (every construct: while loops, constants at
  the limits of their types, casts, non-finite float helpers, calls with
  results, every arithmetic operator and the fabs helpers) and on a
  program of 300 float constants (the operators on hand-written programs:
  ``test_printer_arith.py``);
- each kind of corruption of the C text (swapped assignments, a changed
  field name, a changed constant, a dropped statement, a changed type, ...)
  and of the dump is reported, naming the function and statement;
- ``pyrosgen generate`` exits with status 2 and writes nothing when the
  printed text does not match the dump.
"""

from __future__ import annotations

import random
import re
import subprocess

import pytest

from pyrosgen import cli
from pyrosgen.proof.coqdriver import CoqDriver
from pyrosgen.proof.sexp import parse_sexp, program_items
from pyrosgen.verify.printer_validation import PrinterValidationError, validate_glue, validate_program

from support.validation import EXAMPLES, LANDSHARK, REPO, TIMED_EXAMPLES


def _validate(node, glue=None, header=None, sexp=None):
    g, h, s = node.texts()
    return validate_glue(glue if glue is not None else g, header if header is not None else h,
                         sexp if sexp is not None else s, glue_name=node.glue.name,
                         header_name=node.header.name)


def _replace(text: str, old: str, new: str, count: int = 1) -> str:
    """Replace the first ``count`` occurrences; the mutation must apply."""
    assert text.count(old) >= count, f"mutation target not found: {old!r}"
    return text.replace(old, new, count)


def _fails(node, match: str, **texts) -> str:
    with pytest.raises(PrinterValidationError) as info:
        _validate(node, **texts)
    msg = str(info.value)
    assert re.search(match, msg), msg
    return msg


# ---------------------------------------------------------------------------
# The generated nodes

_STATEMENTS = {"assign", "set", "call", "if", "loop", "break", "return"}


def _statements(items) -> int:
    """The number of statements (sequences and skips not counted) in the
    bodies of the dump's functions."""
    def count(t) -> int:
        if not isinstance(t, list) or not t:
            return 0
        return (isinstance(t[0], str) and t[0] in _STATEMENTS) + sum(count(x) for x in t)
    return sum(count(f) for f in items["functions"].values())


@pytest.mark.parametrize("key", list(EXAMPLES))
def test_generated_nodes_validate(generated, key):
    node = generated[key]
    rep = node.result.validation
    assert rep is not None, "generate did not run the printer validation"
    items = program_items(parse_sexp(node.sexp.read_text()))
    # what was compared is the whole program
    assert rep.structs == len(items["structs"])
    assert rep.globals == len(items["gvars"])
    assert rep.externals == len(items["externals"])
    assert rep.functions == len(items["functions"])
    assert rep.statements == _statements(items) and rep.expressions > 3 * rep.statements
    again = _validate(node)
    assert again.summary() == rep.summary()


@pytest.mark.parametrize("key", list(TIMED_EXAMPLES))
def test_timed_nodes_validate(generated_timed, key):
    """Nodes with timed topics (rule 4.12): the whole program is compared,
    ``ros_now`` among its externals, the clock globals among its globals;
    a corrupted age comparison, timeout or reset is reported."""
    node = generated_timed[key]
    rep = node.result.validation
    items = program_items(parse_sexp(node.sexp.read_text()))
    assert (rep.structs, rep.globals, rep.externals, rep.functions) == (
        len(items["structs"]), len(items["gvars"]), len(items["externals"]), len(items["functions"]))
    assert "ros_now" in items["externals"] and any(g.endswith("_rcvd") for g in items["gvars"])
    assert _validate(node).summary() == rep.summary()
    glue = node.glue.read_text()
    for old, new in (("_time <= _now", "_time < _now"), ("ULL < _age", "ULL <= _age"), ("_new = 0;", "_new = 1;"),
                     ("_rcvd = 1;", "_rcvd = 0;")):
        if old in glue:
            _fails(node, r"function (input_glue|\w+_callback)", glue=_replace(glue, old, new))


def test_multi_compares_constants_and_narrow_types(generated):
    """multi has 8-bit and 16-bit leaves (bool, uint8, int16) and float32."""
    node = generated["multi"]
    g, _, _ = node.texts()
    assert "(*command).stopped = 0;" in g and "(*command).wheels[0].temperature = 0;" in g
    assert "0x0p+0f" in g
    rep = _validate(node)
    # every zero the output glues store is a constant compared
    zeros = re.findall(r"^\s*\(\*command\)\.\S+ = (0|0U|0x0p\+0f?|0L+U*);$", g, re.M)
    assert len(zeros) > 20 and rep.constants >= len(zeros)


# ---------------------------------------------------------------------------
# Corruptions of the C text, each caught

LS_IN1 = ("    _t_double = landshark_left_wheel_velocity_msg.twist.linear.x;\n"
          "    Controller_U.In1 = _t_double;\n")
LS_IN2 = ("    _t_double = landshark_right_wheel_velocity_msg.twist.linear.x;\n"
          "    Controller_U.In2 = _t_double;\n")


def test_swap_two_assignments(generated):
    node = generated["landshark"]
    g = _replace(node.texts()[0], LS_IN1 + LS_IN2, LS_IN2 + LS_IN1)
    msg = _fails(node, r"function input_glue, statement 1 differs", glue=g)
    assert "landshark_glue.c" not in msg and f"{node.glue.name}:" in msg  # C line given


def test_swap_sources_only(generated):
    node = generated["landshark"]
    g = node.texts()[0]
    g = _replace(g, "_t_double = landshark_left_wheel_velocity_msg.twist.linear.x;\n    Controller_U.In1",
                 "_t_double = landshark_gps_velocity_msg.twist.linear.x;\n    Controller_U.In1")
    _fails(node, r"input_glue, statement 1 differs", glue=g)


def test_change_field_name(generated):
    node = generated["landshark"]
    g = _replace(node.texts()[0], "    landshark_gps_velocity_msg.twist.linear.x = _t_double;",
                 "    landshark_gps_velocity_msg.twist.linear.y = _t_double;")
    _fails(node, r"function landshark_gps_velocity_callback, statement 2 differs", glue=g)


def test_unknown_field_name(generated):
    node = generated["landshark"]
    g = _replace(node.texts()[0], "Controller_U.In3 = _t_double;", "Controller_U.In4 = _t_double;")
    _fails(node, r"struct ExtU_Controller_T has no member In4", glue=g)


@pytest.mark.parametrize("old,new", [
    ("(*command).header.seq = 0U;", "(*command).header.seq = 1U;"),
    ("(*command).header.seq = 0U;", "(*command).header.seq = 0;"),          # type of the constant
    ("(*command).twist.linear.x = 0x0p+0;", "(*command).twist.linear.x = -0x0p+0;"),  # sign of zero
    ("(*command).twist.linear.x = 0x0p+0;", "(*command).twist.linear.x = 0x1p-1074;"),
    ("(*command).twist.linear.x = 0x0p+0;", "(*command).twist.linear.x = 0x0p+0f;"),  # float, not double
])
def test_change_constant(generated, old, new):
    node = generated["landshark"]
    g = _replace(node.texts()[0], old, new)
    _fails(node, r"output_glue_landshark_control_base_velocity, statement \d+ |implicit conversion", glue=g)


def test_change_narrow_constant(generated):
    node = generated["multi"]
    g = _replace(node.texts()[0], "(*command).stopped = 0;", "(*command).stopped = 256;")
    _fails(node, r"implicit conversion from int to unsigned char", glue=g)
    g = _replace(node.texts()[0], "(*command).stopped = 0;", "(*command).stopped = 1;")
    _fails(node, r"output_glue_fusion_status, statement 5 differs", glue=g)


def test_drop_statement(generated):
    node = generated["landshark"]
    g = _replace(node.texts()[0], "    (*command).twist.angular.y = 0x0p+0;\n", "")
    _fails(node, r"output_glue_landshark_control_base_velocity, statement 8 differs", glue=g)
    g = _replace(node.texts()[0], "        ros_rate_sleep();\n", "")
    _fails(node, r"function loop, statement 1, loop body, statement 8: the C text lacks it", glue=g)


def test_extra_statement(generated):
    node = generated["landshark"]
    g = _replace(node.texts()[0], "    Controller_U.In3 = _t_double;\n",
                 "    Controller_U.In3 = _t_double;\n    Controller_U.In1 = _t_double;\n")
    _fails(node, r"input_glue, statement 7: the C text has a statement the AST lacks", glue=g)


def test_change_type_in_header(generated):
    node = generated["landshark"]
    h = _replace(node.texts()[1], "struct geometry_msgs_Vector3 {\n    double x;",
                 "struct geometry_msgs_Vector3 {\n    float x;")
    _fails(node, r"struct geometry_msgs_Vector3: member 1 differs", header=h)


def test_change_type_of_local_and_global(generated):
    node = generated["landshark"]
    g = _replace(node.texts()[0], "void input_glue(void)\n{\n    double _t_double;",
                 "void input_glue(void)\n{\n    float _t_double;")
    _fails(node, r"function input_glue: local 1 differs", glue=g)
    g = _replace(node.texts()[0], "struct geometry_msgs_TwistStamped landshark_gps_velocity_msg;",
                 "struct geometry_msgs_Twist landshark_gps_velocity_msg;")
    _fails(node, r"global variable 5 differs", glue=g)
    g = _replace(node.texts()[0], "void ros_publish_landshark_control_base_velocity(struct geometry_msgs_TwistStamped *);",
                 "void ros_publish_landshark_control_base_velocity(struct geometry_msgs_Twist *);")
    _fails(node, r"prototype \d+ differs", glue=g)


def test_extern_and_order(generated):
    node = generated["landshark"]
    g = _replace(node.texts()[0], "extern struct ExtY_Controller_T Controller_Y;",
                 "struct ExtY_Controller_T Controller_Y;")
    _fails(node, r"global variable 2 differs", glue=g)
    g = node.texts()[0]
    a = "void input_glue(void);\n"
    b = "void loop(void);\n"
    g = _replace(_replace(g, a, "@A@"), b, a).replace("@A@", b)
    _fails(node, r"prototype \d+ differs", glue=g)


def test_control_flow(generated):
    node = generated["landshark"]
    g = _replace(node.texts()[0], "        if (_ok) {\n        } else {\n            break;\n        }\n",
                 "        if (_ok) {\n            break;\n        }\n")
    _fails(node, r"function loop, statement 1, loop body, statement 2", glue=g)
    g = _replace(node.texts()[0], "    for (;;) {\n        _ok = ros_ok();\n        if (_ok) {\n        } else {\n"
                 "            break;\n        }\n", "    while (ros_ok()) {\n")
    _fails(node, r"loop", glue=g)


def test_arrow_and_parentheses_are_the_same_c(generated):
    """Changes that keep the meaning of the C text are accepted: the
    comparison is on the parsed program, not on its spelling."""
    node = generated["landshark"]
    g = _replace(node.texts()[0], "_t_double = (*msg).twist.linear.x;", "_t_double = msg->twist.linear.x;", 3)
    g = _replace(g, "    (*command).header.seq = 0U;", "    (((*command)).header.seq) = (0U);")
    _validate(node, glue=g)


def test_preprocessor_and_header_checks(generated):
    node = generated["landshark"]
    g, h, _ = node.texts()
    _fails(node, r"expected exactly one directive", glue="#define X 1\n" + g)
    _fails(node, r'expected #include "landshark_controller_types.h"',
           glue=g.replace('#include "landshark_controller_types.h"', '#include "other_types.h"'))
    _fails(node, r"include-guarded", header=h.replace("#define PYROSGEN", "#define OTHER"))
    _fails(node, r"something else than struct definitions",
           header=h.replace("#endif", "int injected;\n#endif"))


def test_c_that_pycparser_rejects_is_an_error(generated):
    node = generated["landshark"]
    g = _replace(node.texts()[0], "    Controller_U.In1 = _t_double;", "    Controller_U.In1 = = _t_double;")
    _fails(node, r"pycparser cannot parse", glue=g)


def test_corrupted_dump(generated):
    node = generated["landshark"]
    s = node.texts()[2]
    s2 = _replace(s, "(assign (field (var Controller_U (struct ExtU_Controller_T)) In2 (float F64))",
                  "(assign (field (var Controller_U (struct ExtU_Controller_T)) In3 (float F64))")
    _fails(node, r"input_glue, statement 4 differs", sexp=s2)
    s3 = _replace(s, "(const_int 0 (int I32 unsigned))", "(const_int 4294967296 (int I32 unsigned))")
    _validate(node, sexp=s3)   # 2^32 wraps to 0U: the same C constant
    s4 = _replace(s, "(const_int 0 (int I32 unsigned))", "(const_int 4294967297 (int I32 unsigned))")
    _fails(node, r"statement 1 differs", sexp=s4)
    # the type of a temporary
    s5 = _replace(s, "(temps (_t_double (float F64)))\n  (body\n    (seq\n      (set _t_double (field (field (field (var landshark_left",
                  "(temps (_t_double (int I32 signed)))\n  (body\n    (seq\n      (set _t_double (field (field (field (var landshark_left")
    _fails(node, r"function input_glue: local 1 differs", sexp=s5)
    # and with the C local changed too: C converts, the semantics' Sset does not
    g5 = _replace(node.texts()[0], "void input_glue(void)\n{\n    double _t_double;",
                  "void input_glue(void)\n{\n    int _t_double;")
    _fails(node, r"function input_glue: assignment: implicit conversion from double to int", sexp=s5, glue=g5)


# ---------------------------------------------------------------------------
# The printer's example program and float constants (print_program, no header)

@pytest.fixture(scope="module")
def printed_examples(tmp_path_factory):
    """coq/tests/PrinterExamples.v printed through the fast path."""
    CoqDriver().check_library()
    work = tmp_path_factory.mktemp("printer_examples")
    subprocess.run(["sh", str(REPO / "coq" / "extraction" / "print_program.sh"), "-o", str(work / "ex"),
                    str(REPO / "coq" / "tests" / "PrinterExamples.v")], check=True, capture_output=True)
    return (work / "ex.c").read_text(), (work / "ex.sexp").read_text()


def test_printer_examples_validate(printed_examples):
    c, s = printed_examples
    rep = validate_program(c, s, name="ex.c")
    assert rep.helpers == ["rosgen_f32_of_bits", "rosgen_f64_of_bits", "rosgen_fabs", "rosgen_fabsf"]
    assert rep.constants > 50 and rep.functions >= 5
    # the operations of [arith] (f_arith): every operator was compared
    body = c[c.index("void arith(void)\n{"):]
    body = body[:body.index("\n}\n")]
    for token in (" + ", " - ", " * ", " / ", " % ", " & ", " | ", " ^ ", " == ", " != ", " < ", " > ",
                  " <= ", " >= ", "(-", "(!", "rosgen_fabs(", "rosgen_fabsf(", "(-(-"):
        assert token in body, token
    assert s.count("(binop ") + s.count("(unop ") >= 60


@pytest.mark.parametrize("old,new,match", [
    ("g_i32 = (-2147483647 - 1);", "g_i32 = (-2147483647 - 2);", "overflow|differs"),
    ("g_i64 = (-9223372036854775807LL - 1);", "g_i64 = (-9223372036854775807LL);", "differs"),
    ("g_u32 = 4294967295U;", "g_u32 = 4294967295;", "long|differs"),
    ("g_d[2] = 0x1.999999999999ap-4;", "g_d[2] = 0x1.999999999999bp-4;", "differs"),
    ("g_d[2] = 0x1.999999999999ap-4;", "g_d[2] = 0.1;", "not an exact hexadecimal"),
    ("g_f[0] = 0x1.99999ap-4f;", "g_f[0] = 0x1.999999999999ap-4f;", "not exactly representable as a float"),
    ("    while (g_flag) {", "    while (~g_flag) {", "not in the printed subset"),
    ("    while (g_flag) {", "    while (!g_flag) {", r"function loops, statement \d+, loop body, statement 1 differs"),
    # the operations of [arith]
    ("    g_ai[0] = (a + b);", "    g_ai[0] = (a - b);", r"function arith, statement 4 differs"),
    ("    g_ai[3] = (c - b);", "    g_ai[3] = (b - c);", r"function arith, statement 7 differs"),
    ("    g_ai[0] = (a + b);", "    g_ai[0] = (a && b);", "not in the printed subset"),
    ("    g_ai[0] = (a + b);", "    g_ai[0] = (a + ub);", "operands of different types, int and unsigned int"),
    ("    g_ac[2] = (ub > ua);", "    g_ac[2] = (ub > a);", "operands of different types"),
    ("    g_au[4] = (-ub);", "    g_au[4] = (!ub);", "implicit conversion from int to unsigned int"),
    ("    g_ai[9] = (-(-3));", "    g_ai[9] = (-3);", r"function arith, statement 13 differs"),
    ("    g_ai[9] = (-(-3));", "    g_ai[9] = 3;", r"function arith, statement 13 differs"),
    ("    g_ad[11] = (-(-0x1p+0));", "    g_ad[11] = 0x1p+0;", r"function arith, statement \d+ differs"),
    ("    g_ad[11] = (-(-0x1p+0));", "    g_ad[11] = (-0x1p+0);", r"function arith, statement \d+ differs"),
    ("    g_ai[11] = ((b * b) - (c / 1000));", "    g_ai[11] = (b * (b - c) / 1000);",
     r"function arith, statement 15 differs"),
    ("    g_ad[5] = rosgen_fabs((-y));", "    g_ad[5] = rosgen_fabsf((-y));", "rosgen_fabsf applied to a double"),
    ("    g_ad[5] = rosgen_fabs((-y));", "    g_ad[5] = (-y);", r"function arith, statement \d+ differs"),
    ("    x.u &= 0x7fffffffU;", "    x.u &= 0xffffffffU;", "helper rosgen_fabsf is not the documented definition"),
    ("static double rosgen_fabs(double d)\n{\n    union { unsigned long long u; double d; } x;\n    x.d = d;\n"
     "    x.u &= 0x7fffffffffffffffULL;\n    return x.d;\n}\n\n", "", "rosgen_fabs used before its definition"),
    ("    union { unsigned long long u; double d; } x;", "    union { unsigned long long u; double d; } y; double x;",
     "helper rosgen_f64_of_bits is not the documented definition"),
])
def test_printer_examples_corrupted(printed_examples, old, new, match):
    c, s = printed_examples
    with pytest.raises(PrinterValidationError, match=match):
        validate_program(_replace(c, old, new), s, name="ex.c")


def _float_program(bits64, bits32) -> str:
    assigns = [f'Sassign (Eindex (Evar "g_d" (Tarray tdouble {len(bits64)})) (Econst_int {i} tint) tdouble) '
               f'(Econst_float (float64_of_bits {b}) tdouble)' for i, b in enumerate(bits64)]
    assigns += [f'Sassign (Eindex (Evar "g_f" (Tarray tfloat {len(bits32)})) (Econst_int {i} tint) tfloat) '
                f'(Econst_single (float32_of_bits {b}) tfloat)' for i, b in enumerate(bits32)]
    body = "Sreturn None"
    for a in reversed(assigns):
        body = f"Ssequence ({a})\n  ({body})"
    return f"""From Coq Require Import String List ZArith.
From ROSGen Require Import Syntax FloatBits.
Import ListNotations.
Local Open Scope string_scope.
Local Open Scope Z_scope.
Definition the_program : program := {{|
  prog_types := [];
  prog_defs := [("g_d", Gvar (Tarray tdouble {len(bits64)}));
                ("g_f", Gvar (Tarray tfloat {len(bits32)}));
                ("set_all", Gfun (Internal (mkfunction Tvoid [] [] [] ({body}))))];
  prog_main := "set_all" |}}.
"""


def test_float_constants(tmp_path):
    """300 float constants (edge cases, NaN payloads, random patterns): the
    validator reads every literal back to its exact bit pattern."""
    CoqDriver().check_library()
    rng = random.Random(6)
    bits64 = [0, 1 << 63, 1, 0x000FFFFFFFFFFFFF, 0x7FEFFFFFFFFFFFFF, 0x7FF0000000000000,
              0xFFF0000000000000, 0x7FF8000000000000, 0xFFF4000000000001] + [rng.getrandbits(64) for _ in range(140)]
    bits32 = [0, 1 << 31, 1, 0x007FFFFF, 0x7F7FFFFF, 0x7F800000, 0xFF800000, 0x7FC00000,
              0xFFA00001] + [rng.getrandbits(32) for _ in range(140)]
    v = tmp_path / "Floats.v"
    v.write_text(_float_program(bits64, bits32))
    subprocess.run(["sh", str(REPO / "coq" / "extraction" / "print_program.sh"), "-o", str(tmp_path / "fl"),
                    str(v)], check=True, capture_output=True)
    c, s = (tmp_path / "fl.c").read_text(), (tmp_path / "fl.sexp").read_text()
    rep = validate_program(c, s, name="fl.c")
    assert rep.constants >= len(bits64) + len(bits32)
    # one bit changed in one literal (finite or not) is caught
    lits = re.findall(r"^    (g_[df]\[\d+\]) = (.*);$", c, re.M)
    assert len(lits) == len(bits64) + len(bits32)
    changed = 0
    for target, lit in lits:
        m = re.fullmatch(r"(rosgen_f(?:64|32)_of_bits\(0x|-?0x1\.)([0-9a-f]+)(.*)", lit)
        if m is None:
            continue
        # the last hex digit XOR 2: still an exact literal, another value
        digits = m.group(2)[:-1] + f"{int(m.group(2)[-1], 16) ^ 2:x}"
        mutated = c.replace(f"    {target} = {lit};", f"    {target} = {m.group(1)}{digits}{m.group(3)};", 1)
        with pytest.raises(PrinterValidationError, match=r"set_all, statement \d+ differs"):
            validate_program(mutated, s, name="fl.c")
        changed += 1
        if changed == 12:
            break
    assert changed == 12


# ---------------------------------------------------------------------------
# In the pipeline: a mismatch is exit 2 and nothing is written

def test_generate_refuses_a_mismatched_print(monkeypatch, capsys, tmp_path):
    """The printed glue corrupted after printing (two assignments swapped):
    ``pyrosgen generate`` exits 2, names the difference, writes nothing."""
    original = CoqDriver.print_texts

    def corrupting(self, module, lib, outputs, **kw):
        times = original(self, module, lib, outputs, **kw)
        glue = outputs[1]
        glue.write_text(_replace(glue.read_text(), LS_IN1 + LS_IN2, LS_IN2 + LS_IN1))
        return times

    monkeypatch.setattr(CoqDriver, "print_texts", corrupting)
    out = tmp_path / "out"
    code = cli.main(["generate", str(LANDSHARK), "-o", str(out)])
    err = capsys.readouterr().err
    assert code == 2
    assert "printer validation failed" in err and "function input_glue, statement 1 differs" in err
    assert "C:   " in err and "AST: " in err
    assert not out.exists()


def test_generate_reports_validation(capsys, tmp_path):
    out = tmp_path / "out"
    assert cli.main(["generate", str(LANDSHARK), "-o", str(out), "-q"]) == 0
    stdout = capsys.readouterr().out
    assert re.search(r"  printer   C text = AST dump \(pycparser\): 7 structs, 5 globals, 11 external and "
                     r"7 internal functions, \d+ statements", stdout)

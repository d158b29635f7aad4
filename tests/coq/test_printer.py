"""Tests of the Coq C printer (ROSGen.Printer) and its fast printing path.

The example program is ``coq/tests/PrinterExamples.v`` (``the_program``).
It is printed through extraction (coq/extraction/print_program.sh), the C
text is compiled with gcc -std=c11 -pedantic -Werror, run by a harness that
prints every global, and the output is compared with the Coq interpreter's
run of the same AST (``interp_dump``, Interp.run_program under vm_compute)
and with values computed by hand here.
"""

from __future__ import annotations

import random
import re
import struct
import subprocess
import time
from pathlib import Path

import pytest

from support.printer import (
    EXAMPLES_V, GCC_STRICT, build_coq_library, coq_eval_strings, compile_and_run,
    harness_source, parse_sexp, print_via_extraction, program_items, run, SString)

# The externals of the example program, defined by the harness as the
# interpreter's environment model has them with ros_ok answering false:
# ros_ok() returns 0, ros_subscribe_t() registers (nothing observable here).
EXAMPLE_STUBS = """
int g_ext;
int ros_ok(void) { return 0; }
void ros_subscribe_t(void (*cb)(struct Msg *)) { (void)cb; }
"""


@pytest.fixture(scope="module")
def work(tmp_path_factory) -> Path:
    build_coq_library()
    return tmp_path_factory.mktemp("printer")


@pytest.fixture(scope="module")
def printed(work):
    """(C text, sexp text, C file) of the example program, via extraction."""
    c_text, sexp_text = print_via_extraction(EXAMPLES_V, work / "examples")
    return c_text, sexp_text, work / "examples.c"


@pytest.fixture(scope="module")
def coq_side(work):
    """What Coq itself computes with vm_compute: the interpreter's dump and
    the two printed texts."""
    dump, c_text, sexp_text = coq_eval_strings(
        EXAMPLES_V,
        ["interp_dump", "Printer.print_program the_externs the_program",
         "Dump.print_sexp the_externs the_program"],
        work / "coqside")
    return dump, c_text, sexp_text


def parse_dump(text: str) -> dict[str, str]:
    out = {}
    for line in text.strip().splitlines():
        key, _, val = line.partition(" = ")
        assert key not in out, f"duplicate line for {key}"
        out[key] = val
    return out


def f64_bits(x: float) -> str:
    return "0x%016x" % struct.unpack("<Q", struct.pack("<d", x))[0]


def f32_bits(x: float) -> str:
    return "0x%08x" % struct.unpack("<I", struct.pack("<f", x))[0]


# ---------------------------------------------------------------------------

def test_compiles_strict(printed, work):
    _, _, c_file = printed
    run(GCC_STRICT + ["-c", str(c_file), "-o", str(work / "examples.o")])


def test_extraction_prints_what_coq_computes(printed, coq_side):
    """The fast path (extracted OCaml) and Coq's own evaluation of
    print_program / print_sexp give byte-identical texts."""
    c_text, sexp_text, _ = printed
    _, coq_c, coq_sexp = coq_side
    assert c_text == coq_c
    assert sexp_text == coq_sexp


def test_deterministic(printed, work):
    c_text, sexp_text, _ = printed
    c2, s2 = print_via_extraction(EXAMPLES_V, work / "examples_again")
    assert (c2, s2) == (c_text, sexp_text)


@pytest.mark.parametrize("opt", ["-O0", "-O2"])
def test_run_matches_interpreter(printed, coq_side, work, opt):
    """The compiled C and the Coq interpreter leave every global with the
    same value, bit for bit."""
    _, sexp_text, c_file = printed
    items = program_items(parse_sexp(sexp_text))
    out = compile_and_run(harness_source(c_file, items, EXAMPLE_STUBS), work, opt)
    c_values = parse_dump(out)
    interp_values = parse_dump(coq_side[0])
    assert len(c_values) > 80
    assert c_values == interp_values


def test_run_hand_values(printed, work):
    """Values computed by hand (independently of both the printer and the
    interpreter)."""
    _, sexp_text, c_file = printed
    items = program_items(parse_sexp(sexp_text))
    v = parse_dump(compile_and_run(harness_source(c_file, items, EXAMPLE_STUBS), work,
                                   name="hand"))
    expected = {
        "result": "0",
        "g_i32": str(-2**31), "g_u32": str(2**32 - 1),
        "g_i64": str(-2**63), "g_u64": str(2**64 - 1),
        "g_i8": "-128", "g_u8": str(300 % 256), "g_i16": str(40000 - 65536),
        "g_u16": "65535", "g_i32b": str(-2**31), "g_i64b": str(2**63 - 1),
        "g_c1": str(200 - 256), "g_c2": str(5000000007 % 2**32), "g_c3": "7",
        "g_c4": str(2**64 - 3), "g_c5": str(65536 - 3),
        "g_d[0]": f64_bits(-0.0), "g_d[1]": f64_bits(5e-324), "g_d[2]": f64_bits(0.1),
        "g_d[3]": f64_bits(1.7976931348623157e308), "g_d[4]": f64_bits(-3.0),
        "g_d[5]": f64_bits(2.225073858507201e-308), "g_d[6]": f64_bits(float("inf")),
        "g_d[7]": "0x7ff8000000000123",
        "g_f[0]": f32_bits(0.1), "g_f[1]": f32_bits(1.401298464324817e-45),
        "g_f[2]": f32_bits(-0.0), "g_f[3]": f32_bits(float("-inf")),
        "g_in.lin.x": f64_bits(1.5), "g_in.cov[0]": f64_bits(2.0),
        "g_in.cov[3]": f64_bits(0.0),            # written through msg after the copy
        "g_in.u64": str(2**64 - 1), "g_in.s16": "-32768", "g_in.f32": f32_bits(1.0),
        "g_out.lin.z": f64_bits(1.5), "g_out.lin.x": f64_bits(0.0),
        "g_out2.lin.y": f64_bits(1.5), "g_out2.cov[3]": f64_bits(1.5),
        "g_x": f64_bits(1.5), "g_r": "-7",
        "g_flag": "0", "g_count": "11", "g_count2": "22",
        "g_branch": "2", "g_branch2": "0", "g_branch3": "1", "g_ok": "0", "g_ext": "5",
    }
    for key, val in expected.items():
        assert v[key] == val, key


def _f32(x: float) -> float:
    """``x`` rounded to the nearest binary32 (ties to even)."""
    return struct.unpack("<f", struct.pack("<f", x))[0]


def _c_div(a: int, b: int) -> int:
    """C's division: the quotient truncated toward zero."""
    q = abs(a) // abs(b)
    return q if (a >= 0) == (b >= 0) else -q


def test_run_hand_arith(printed, work):
    """The operators of ``arith`` (PrinterExamples.v), on values computed
    here by Python's own integer and IEEE arithmetic: C's truncating
    division and remainder, unsigned wrap-around, signed results at the
    edges, binary64/binary32 rounding, -0.0, infinity, NaN propagation
    and NaN comparisons.  The compiled C must give them (the interpreter
    is compared with the C by test_run_matches_interpreter)."""
    _, sexp_text, c_file = printed
    items = program_items(parse_sexp(sexp_text))
    v = parse_dump(compile_and_run(harness_source(c_file, items, EXAMPLE_STUBS), work,
                                   name="hand_arith"))
    a, b, c = -7, 2, 2**31 - 1
    ints = [a + b, _c_div(a, b), a - b * _c_div(a, b), c - b, a * -6, a & 12, a | 12, a ^ 12,
            -a, 3, int(not b), b * b - _c_div(c, 1000), 7 - (-b) * _c_div(7, -b),
            _c_div(c, -c), 0, 1]
    ua, ub, M32 = 0, 4000000000, 2**32
    uints = [(ua - 1) % M32, (ub + ub) % M32, ub // 7, ub % 7, (-ub) % M32, (ub * ub) % M32]
    la, lb = -9, 2**63 - 1
    longs = [_c_div(la, 4), la - 4 * _c_div(la, 4), lb - 1, la * 10**12, -lb, la ^ lb]
    ula, ulb, M64 = 2**64 - 1, 2, 2**64
    ulongs = [(ula + ulb) % M64, (ula * ulb) % M64, ula // ulb, (-ulb) % M64]
    x, y = 0.1, 3.0
    nan = "0x7ff8000000000123"
    doubles = [f64_bits(x * y), f64_bits(x + 0.2), f64_bits(1.0 / y), f64_bits(x - x),
               f64_bits(0.0), f64_bits(3.0), f64_bits(float("inf")), nan,
               "0xfff8000000000123", nan, f64_bits(1e-323), f64_bits(1.0)]
    f, g = _f32(0.1), 3.0
    floats = [f32_bits(_f32(f * g)), f32_bits(_f32(f / g)), f32_bits(_f32(f - g)),
              f32_bits(float("inf")), f32_bits(-f)]
    cmps = [1, 0, 1, 0, 1, 0, 1, 0, 0, 1, 0, 1, 0, 1, 0, 0]
    expected = {}
    for name, vals in (("g_ai", ints), ("g_au", uints), ("g_al", longs), ("g_aul", ulongs),
                       ("g_ad", doubles), ("g_af", floats), ("g_ac", cmps)):
        for i, val in enumerate(vals):
            expected[f"{name}[{i}]"] = str(val)
    assert len(expected) == 16 + 6 + 6 + 4 + 12 + 5 + 16
    wrong = {k: (v.get(k), e) for k, e in expected.items() if v.get(k) != e}
    assert not wrong


def test_c_text_shape(printed):
    """Figure 11's forms, declarators and constants as documented."""
    c_text, _, _ = printed
    for needle in [
        "    t = (*msg).lin.x;\n",
        "    p = &(*msg).lin;\n",
        "void copy_msg(struct Msg *msg);\n",
        "void ros_subscribe_t(void (*)(struct Msg *));\n",
        "    double cov[4];\n",
        "    signed char s8;\n",
        "    unsigned long long u64;\n",
        "extern int g_ext;\n",
        "    g_i32 = (-2147483647 - 1);\n",
        "    g_i64 = (-9223372036854775807LL - 1);\n",
        "    g_u32 = 4294967295U;\n",
        "    g_d[0] = -0x0p+0;\n",
        "    g_d[1] = 0x1p-1074;\n",
        "    g_d[2] = 0x1.999999999999ap-4;\n",
        "    g_f[1] = 0x1p-149f;\n",
        "    while (g_flag) {\n",
        "    for (;;) {\n",
        "    d = get_x(&g_in.lin);\n",
        "    ros_subscribe_t(&copy_msg);\n",
    ]:
        assert needle in c_text, needle
    assert "#include" not in c_text
    # struct Vec3 is defined before struct Msg, which contains it
    assert c_text.index("struct Vec3 {") < c_text.index("struct Msg {")
    # four spaces per level, no tabs
    assert "\t" not in c_text


def test_sexp_parses_and_matches_c(printed):
    """The dump parses and names exactly the globals, structs and functions
    of the C text (pycparser's view of it)."""
    from pycparser import c_parser, c_ast

    c_text, sexp_text, c_file = printed
    items = program_items(parse_sexp(sexp_text))
    assert items["externs"] == ["g_ext"]
    assert items["main"] == "run_all"
    assert list(items["structs"]) == ["Vec3", "Msg"]
    assert items["externals"]["ros_subscribe_t"][0] == [
        "ros_subscribe", SString("/t"), "Msg", "1"]
    f = items["functions"]["copy_msg"]
    assert f[2] == "void" and f[3] == ["params", ["msg", ["ptr", ["struct", "Msg"]]]]
    body = f[6]
    assert body[0] == "body" and body[1][0] == "seq"
    assert body[1][1] == ["set", "t", [
        "field", ["field", ["deref", ["tempvar", "msg", ["ptr", ["struct", "Msg"]]],
                            ["struct", "Msg"]], "lin", ["struct", "Vec3"]],
        "x", ["float", "F64"]]]

    pre = run(["gcc", "-E", "-P", str(c_file)]).stdout
    ast = c_parser.CParser().parse(pre, filename=str(c_file))
    funcdefs, gvars, externs, protos, structs = {}, set(), set(), set(), []
    for ext in ast.ext:
        if isinstance(ext, c_ast.FuncDef):
            funcdefs[ext.decl.name] = ext
        elif isinstance(ext, c_ast.Decl) and isinstance(ext.type, c_ast.FuncDecl):
            protos.add(ext.name)
        elif isinstance(ext, c_ast.Decl) and ext.name is None:
            structs.append(ext.type.name)
        elif isinstance(ext, c_ast.Decl):
            (externs if "extern" in ext.storage else gvars).add(ext.name)
    helpers = {"rosgen_f64_of_bits", "rosgen_f32_of_bits", "rosgen_fabs", "rosgen_fabsf"}
    assert set(funcdefs) - helpers == set(items["functions"])
    assert protos == set(items["functions"]) | set(items["externals"])
    assert gvars | externs == set(items["gvars"]) and externs == {"g_ext"}
    assert structs == ["Vec3", "Msg"]
    # locals: fn_vars then fn_temps, in order
    for name, item in items["functions"].items():
        decls = [d.name for d in funcdefs[name].body.block_items or []
                 if isinstance(d, c_ast.Decl)]
        assert decls == [b[0] for b in item[4][1:]] + [b[0] for b in item[5][1:]], name


def test_sexp_parser_rejects_garbage():
    assert parse_sexp('(a "b\\"c" (d))') == ["a", SString('b"c'), ["d"]]
    for bad in ["(a", "a)", "(a) (b)", '("x)', '("\\n")']:
        with pytest.raises(ValueError):
            parse_sexp(bad)


# ---------------------------------------------------------------------------
# Float constants: exact for any bit pattern

def _float_program(bits64: list[int], bits32: list[int]) -> str:
    assigns = [f'Sassign (Eindex (Evar "g_d" (Tarray tdouble {len(bits64)})) '
               f'(Econst_int {i} tint) tdouble) (Econst_float (float64_of_bits {b}) tdouble)'
               for i, b in enumerate(bits64)]
    assigns += [f'Sassign (Eindex (Evar "g_f" (Tarray tfloat {len(bits32)})) '
                f'(Econst_int {i} tint) tfloat) (Econst_single (float32_of_bits {b}) tfloat)'
                for i, b in enumerate(bits32)]
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
                ("set_all", Gfun (Internal (mkfunction Tvoid [] [] []
  ({body}))))];
  prog_main := "set_all" |}}.
"""


HEXFLOAT = re.compile(r"^(-?)0x([01])(?:\.([0-9a-f]*[1-9a-f]))?p([+-]\d+)(f?)$")


def test_float_constants_exact(work):
    rng = random.Random(20240611)
    edge64 = [0, 1 << 63, 1, 0x000FFFFFFFFFFFFF, 0x0010000000000000, 0x7FEFFFFFFFFFFFFF,
              0x3FF0000000000000, 0x3FB999999999999A, 0x7FF0000000000000,
              0xFFF0000000000000, 0x7FF8000000000000, 0xFFF8000000000001,
              0x7FF4000000000000, 0x8000000000000001]
    edge32 = [0, 1 << 31, 1, 0x007FFFFF, 0x00800000, 0x7F7FFFFF, 0x3F800000, 0x3DCCCCCD,
              0x7F800000, 0xFF800000, 0x7FC00000, 0xFFC00001, 0x7FA00000]
    bits64 = edge64 + [rng.getrandbits(64) for _ in range(150)] \
        + [rng.getrandbits(52) | (rng.choice([0, 1, 2, 0x7FE, 0x400]) << 52) for _ in range(50)]
    bits32 = edge32 + [rng.getrandbits(32) for _ in range(150)]
    v_file = work / "Floats.v"
    v_file.write_text(_float_program(bits64, bits32))
    c_text, sexp_text = print_via_extraction(v_file, work / "floats")
    c_file = work / "floats.c"
    run(GCC_STRICT + ["-c", str(c_file), "-o", str(work / "floats.o")])

    # each literal denotes exactly its bit pattern (checked by Python)
    lits = re.findall(r"^    g_([df])\[(\d+)\] = (.*);$", c_text, re.M)
    assert len(lits) == len(bits64) + len(bits32)
    for kind, idx, lit in lits:
        b = (bits64 if kind == "d" else bits32)[int(idx)]
        width = 64 if kind == "d" else 32
        exp_mask = 0x7FF if kind == "d" else 0xFF
        mant_bits = 52 if kind == "d" else 23
        if (b >> mant_bits) & exp_mask == exp_mask:
            helper = "rosgen_f64_of_bits" if kind == "d" else "rosgen_f32_of_bits"
            sfx = "ULL" if kind == "d" else "U"
            assert lit == f"{helper}(0x{b:0{width // 4}x}{sfx})"
            continue
        m = HEXFLOAT.match(lit)
        assert m, lit
        assert (m.group(5) == "f") == (kind == "f"), lit
        assert m.group(2) == "1" or (m.group(3) is None and m.group(4) == "+0"), lit
        value = float.fromhex(lit.rstrip("f"))
        if kind == "d":
            assert struct.unpack("<Q", struct.pack("<d", value))[0] == b, lit
        else:
            assert struct.unpack("<I", struct.pack("<f", value))[0] == b, lit
            assert struct.unpack("<f", struct.pack("<f", value))[0] == value  # exact

    # and gcc reads them the same way, NaN payloads included
    items = program_items(parse_sexp(sexp_text))
    for opt in ["-O0", "-O2"]:
        out = parse_dump(compile_and_run(
            harness_source(c_file, items, "", entry="set_all", entry_returns_int=False),
            work, opt, name="floats_harness"))
        for i, b in enumerate(bits64):
            assert out[f"g_d[{i}]"] == f"0x{b:016x}", (opt, i)
        for i, b in enumerate(bits32):
            assert out[f"g_f[{i}]"] == f"0x{b:08x}", (opt, i)


# ---------------------------------------------------------------------------
# Size: the benchmark's N = 2000 relations

BIG_V = """From Coq Require Import String List ZArith.
From ROSGen Require Import Syntax Printer.
Import ListNotations.
Local Open Scope string_scope.
Definition V3 := Tstruct "geometry_msgs_Vector3".
Definition TW := Tstruct "geometry_msgs_Twist".
Definition TS := Tstruct "geometry_msgs_TwistStamped".
Definition U := Tstruct "ExtU_Controller_T".
Definition num (k : nat) := string_of_nonneg (Z.of_nat k).
Definition lin (e : expr) := Efield (Efield (Efield e "twist" TW) "linear" V3) "x" tdouble.
Fixpoint rels (k : nat) : statement :=
  match k with
  | O => Sreturn None
  | S k' => Ssequence (Sset "temp" (lin (Evar ("topic_" ++ num k ++ "_msg") TS)))
             (Ssequence (Sassign (Efield (Evar "Controller_U" U) ("In" ++ num k) tdouble)
                                 (Etempvar "temp" tdouble)) (rels k'))
  end.
Fixpoint fields (k : nat) : list (ident * type) :=
  match k with O => [] | S k' => fields k' ++ [("In" ++ num k, tdouble)] end.
Fixpoint globals (k : nat) : list (ident * globdef) :=
  match k with O => [] | S k' => ("topic_" ++ num k ++ "_msg", Gvar TS) :: globals k' end.
Definition the_program : program :=
  mkprogram [Composite "geometry_msgs_Vector3" [("x", tdouble); ("y", tdouble); ("z", tdouble)];
             Composite "geometry_msgs_Twist" [("linear", V3); ("angular", V3)];
             Composite "geometry_msgs_TwistStamped" [("twist", TW)];
             Composite "ExtU_Controller_T" (fields @N@)]
    (("Controller_U", Gvar U) :: globals @N@ ++
     [("input_glue", Gfun (Internal (mkfunction Tvoid [] [] [("temp", tdouble)] (rels @N@))))])
    "main".
Definition the_externs : list ident := ["Controller_U"].
"""


def test_large_program(work):
    n = 2000
    v_file = work / "Big.v"
    v_file.write_text(BIG_V.replace("@N@", str(n)))
    start = time.monotonic()
    c_text, sexp_text = print_via_extraction(v_file, work / "big")
    elapsed = time.monotonic() - start
    assert c_text.count("    temp = topic_") == n
    assert c_text.count("    Controller_U.In") == n
    assert "extern struct ExtU_Controller_T Controller_U;\n" in c_text
    items = program_items(parse_sexp(sexp_text))
    assert len(items["gvars"]) == n + 1
    # sequences are flattened: one (seq ...) with 2n + 1 statements
    assert len(items["functions"]["input_glue"][6][1]) == 2 * n + 2
    run(GCC_STRICT + ["-c", str(work / "big.c"), "-o", str(work / "big.o")])
    # the whole fast path (coqc of the file, extraction, ocamlopt, run)
    # takes a few seconds; vm_compute of the same string takes minutes
    assert elapsed < 120, elapsed

"""Three-way differential tests of diagram controllers
(pyrosgen/verify/ctrl_difftest.py).

Coq's ``Diagram.dg_step`` on the node's ``the_diagram`` (extracted to
OCaml), the controller C that ``pyrosgen generate`` printed (compiled by
``gcc -std=c11 -O2 -ffp-contract=off -fno-fast-math``, and at ``-O0``
under ``-fsanitize=address,undefined -fno-sanitize-recover=all``) and the
reference interpreter ``blocksim`` run 2,000 steps of the same inputs: an
edge sweep (±0, ±inf, quiet and signalling NaNs with payloads, the
smallest and largest subnormals, ±the largest finite value, ±1; integer
extremes; bools 0, 1, 2, 255), then seeded random values.  They must print
the same outputs and states after every step, bit for bit, except that
two NaNs may differ in sign and payload.

- LandShark's diagram (examples/landshark/landshark_diagram.yaml), and
  the same with subsystems (landshark_subsystem.yaml): bit for bit the
  flat diagram's outputs and states;
- tests/validation/models/ctrl_all_blocks.yaml: every block kind and
  every signal type, every signal an output;
- mutants of the printed C (operands of a ``-`` swapped, a MinMax's ``<``
  made ``<=``, a signed product computed in ``int``) are caught: the
  report names the first step and column that differ, or the sanitized
  build stops on the undefined behaviour.

One generated folder and one set of executables per model (module-scoped
fixtures).
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from pyrosgen.frontend.model import BLOCK_KINDS, SIGNAL_TYPES
from pyrosgen.frontend.validate import load_model
from pyrosgen.verify.ctrl_difftest import (
    BLOCKSIM, COQ, GCC_O2, GCC_SAN, SIDES, CtrlDifftest, columns, compare, edge_values, input_line, make_steps)
from pyrosgen.verify.difftest import DifftestError

from support.generate import REPO, require_library

LANDSHARK = REPO / "examples" / "landshark" / "landshark_diagram.yaml"
SUBSYSTEM = REPO / "examples" / "landshark" / "landshark_subsystem.yaml"
ALL_BLOCKS = Path(__file__).resolve().parent / "models" / "ctrl_all_blocks.yaml"
STEPS = 2000
SEED = 20261125

NEG_ZERO_64 = 0x8000000000000000


@pytest.fixture(scope="module")
def landshark(tmp_path_factory) -> CtrlDifftest:
    require_library()
    return CtrlDifftest(load_model(LANDSHARK), tmp_path_factory.mktemp("ctrl_difftest_landshark"))


@pytest.fixture(scope="module")
def all_blocks(tmp_path_factory) -> CtrlDifftest:
    require_library()
    return CtrlDifftest(load_model(ALL_BLOCKS), tmp_path_factory.mktemp("ctrl_difftest_all_blocks"))


def _agree(t: CtrlDifftest) -> None:
    steps = make_steps(t.model, STEPS, SEED)
    report = t.run(steps)
    assert report.sides == SIDES
    assert report.steps == STEPS
    for side in SIDES:
        assert len(report.outputs[side]) == STEPS, side
    assert report.ok, report.summary()
    # blocksim implements FloatOps' choice of NaN too: it agrees with Coq
    # even on NaN payloads
    assert report.outputs[BLOCKSIM] == report.outputs[COQ]


# ---------------------------------------------------------------------------
# (a) and (b): the three descriptions agree


def test_landshark_sides_agree(landshark):
    _agree(landshark)


def test_subsystem_example_agrees_with_the_flat_diagram(landshark, tmp_path):
    """LandShark with its median and NaN guard as subsystems: the four
    sides agree, and each step's outputs and states are, bit for bit, the
    flat diagram's (the expansion is a renaming)."""
    sub = CtrlDifftest(load_model(SUBSYSTEM), tmp_path / "sub")
    steps = make_steps(sub.model, 500, SEED)
    assert steps == make_steps(landshark.model, 500, SEED)
    got, flat = sub.run(steps), landshark.run(steps)
    assert got.ok, got.summary()
    assert got.outputs[COQ] == flat.outputs[COQ]
    assert got.outputs[GCC_O2] == flat.outputs[GCC_O2]


def test_all_blocks_model_covers_every_block_kind_and_type():
    """The model of the next test has what it claims: if it loses a block
    kind or a signal type, this fails."""
    model = load_model(ALL_BLOCKS)
    d = model.controller.diagram
    assert {b.kind for b in d.blocks} == set(BLOCK_KINDS)
    assert {b.prim for b in d.blocks} == set(SIGNAL_TYPES)
    assert {f.prim for f in model.controller.inputs.fields} == set(SIGNAL_TYPES)
    ops = {(b.kind, b.op) for b in d.blocks}
    for op in ("==", "!=", "<", "<=", ">", ">="):
        assert ("RelationalOperator", op) in ops
    for op in ("AND", "OR", "NAND", "NOR", "XOR", "NOT"):
        assert ("Logic", op) in ops
    for op in ("u2 >= threshold", "u2 > threshold", "u2 ~= 0"):
        assert ("Switch", op) in ops
    assert {("MinMax", "min"), ("MinMax", "max")} <= ops
    integrators = [b for b in d.blocks if b.kind == "DiscreteIntegrator"]
    assert {b.lower is None for b in integrators} == {True, False}
    assert {"bool", "int32"} <= {b.prim for b in d.blocks if b.kind == "UnitDelay"}
    for q in ("int32", "uint32", "int64", "uint64", "float32"):
        assert {"Sum", "Gain", "Product"} <= {b.kind for b in d.blocks if b.prim == q}, q
    # every signal is observed
    assert len(model.controller.outputs.fields) >= len(d.blocks) - 2


def test_all_blocks_sides_agree(all_blocks):
    _agree(all_blocks)


# ---------------------------------------------------------------------------
# (c): a wrong controller is caught


def _mutant(t: CtrlDifftest, name: str, pattern: str, repl) -> Path:
    text = t.controller_c.read_text()
    new, n = re.subn(pattern, repl, text, count=1)
    assert n == 1, f"no match for {pattern!r} in the printed controller"
    path = t.work / "mutants" / name / t.controller_c.name
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(new)
    return path


def _run_mutant(t: CtrlDifftest, path: Path, steps):
    exe = t.build_c(path, name=f"mutant_{path.parent.name}")
    return t.run(steps, sides=(COQ, BLOCKSIM), extra={"mutant gcc -O2": exe})


def test_swapped_subtraction_is_caught(landshark):
    """LandShark's error ``setpoint - median`` computed as ``median -
    setpoint``: the first step differs, in the command and the integral."""
    mutant = _mutant(landshark, "swap_sub", r"\((rtb_setpoint) - (rtb_median)\)", r"(\2 - \1)")
    steps = make_steps(landshark.model, STEPS, SEED)
    report = _run_mutant(landshark, mutant, steps)
    assert not report.ok
    first = report.first
    assert first.column in ("out:Out1", "state:integ")
    assert first.values[COQ] == first.values[BLOCKSIM] != first.values["mutant gcc -O2"]
    assert str(first).startswith(f"step {first.step}, {first.column}: coq ")
    assert f"step {first.step}" in report.summary()
    assert report.differences > STEPS // 10


def test_minmax_with_le_is_caught(all_blocks):
    """``min(A, B)`` with ``<=`` for ``<`` only differs when A and B are
    equal with different bits: +0.0 then -0.0.  The edge sweep has that
    step, and the report names it and the output."""
    mutant = _mutant(all_blocks, "min_le", r"if \(\(rtb_B < rtb_d_min\)\)", "if ((rtb_B <= rtb_d_min))")
    steps = make_steps(all_blocks.model, STEPS, SEED)
    report = _run_mutant(all_blocks, mutant, steps)
    assert not report.ok
    first = report.first
    assert first.column == "out:Y_d_min"
    a, b = steps[first.step]["A"], steps[first.step]["B"]
    assert {a, b} == {0, NEG_ZERO_64}                 # +0.0 and -0.0, in some order
    coq, bad = f"0x{a:016x}", f"0x{b:016x}"           # min keeps the first; the mutant takes the second
    assert (first.values[COQ], first.values[BLOCKSIM], first.values["mutant gcc -O2"]) == (coq, coq, bad)
    assert report.summary().endswith(
        f"first: step {first.step}, out:Y_d_min: coq {coq}, blocksim {coq}, mutant gcc -O2 {bad}")


def test_signed_overflow_is_stopped_by_the_sanitizers(all_blocks):
    """An ``int32`` product computed in ``int`` instead of ``unsigned
    int``: C's undefined signed overflow, which the sanitized build
    stops at (the -O2 build happens to wrap around)."""
    mutant = _mutant(all_blocks, "signed_mul", r"\(int\)\(\(unsigned int\)rtb_I \* \(unsigned int\)rtb_J\)",
                     "(rtb_I * rtb_J)")
    exe = all_blocks.build_c(mutant, sanitize=True, name="mutant_signed_mul_san")
    steps = make_steps(all_blocks.model, 100, SEED)
    with pytest.raises(DifftestError) as err:
        all_blocks.run(steps, sides=(COQ,), extra={"mutant asan/ubsan": exe})
    text = str(err.value)
    assert "mutant asan/ubsan" in text
    assert "signed integer overflow" in text


# ---------------------------------------------------------------------------
# The comparison and the inputs


def test_compare_allows_only_nan_against_nan():
    model = load_model(LANDSHARK)
    nan1, nan2, one = "0x7ff8000000000000", "0xfff8000000000123", "0x3ff0000000000000"
    ok = compare(model, {COQ: [f"{nan1} {one}"], GCC_O2: [f"{nan2} {one}"]})
    assert ok.ok and ok.nan_payloads == 1
    bad = compare(model, {COQ: [f"{nan1} {one}", f"{one} {one}"], GCC_O2: [f"{one} {one}", f"{one} {nan1}"]})
    assert not bad.ok and bad.differences == 2
    assert (bad.first.step, bad.first.column) == (0, "out:Out1")
    # -0.0 is not +0.0; a missing step is a difference
    zeros = compare(model, {COQ: ["0x0000000000000000 0x0000000000000000"],
                            GCC_SAN: ["0x8000000000000000 0x0000000000000000"]})
    assert not zeros.ok
    short = compare(model, {COQ: [f"{one} {one}"] * 2, GCC_O2: [f"{one} {one}"]}, 2)
    assert not short.ok and short.first.step == 1 and short.first.values[GCC_O2] is None


def test_inputs_are_reproducible_and_cover_the_edges():
    model = load_model(ALL_BLOCKS)
    a, b = make_steps(model, 500, 7), make_steps(model, 500, 7)
    assert a == b and a != make_steps(model, 500, 8)
    for f in model.controller.inputs.fields:
        seen = {s[f.name] for s in a}
        assert set(edge_values(f.prim)) <= seen, f.name
    # neighbours of one type meet in every pair of edges
    pairs = {(s["A"], s["B"]) for s in a}
    assert {(x, y) for x in edge_values("float64") for y in edge_values("float64")} <= pairs
    assert input_line(model, a[0]).split()[5] == "0x80000000"   # I = INT_MIN, its two's complement
    assert len(columns(model)) == len(model.controller.outputs.fields) + len(model.controller.diagram.states)

"""Differential tests of block-diagram controllers (issue: the controller
proved): Coq's ``Diagram.dg_step`` extracted to OCaml, the controller C
that ``pyrosgen generate`` printed compiled by gcc -O2
(``-ffp-contract=off``) and at -O0 under ASan and UBSan, and the reference
interpreter ``blocksim`` run the same random and edge inputs (±0, ±inf,
quiet and signalling NaNs with payloads, subnormals, the largest finite
values, integer extremes, bools 2 and 255) and must print the same
outputs and states, bit for bit but for NaN payloads
(tests/support/ctrldiff.py)."""

from __future__ import annotations

import os
import re

import pytest

from pyrosgen.frontend.validate import load_model
from pyrosgen.generate import generate_model

from support import ctrldiff
from support.generate import REPO, require_library

MODELS = {
    "landshark": REPO / "examples" / "landshark" / "landshark_diagram.yaml",
    "all_blocks": REPO / "tests" / "frontend" / "models" / "ok_blocks_all.yaml",
}
STEPS = 600


@pytest.fixture(scope="module", params=sorted(MODELS))
def setup(request, tmp_path_factory):
    require_library()
    model = load_model(MODELS[request.param])
    work = tmp_path_factory.mktemp(f"ctrldiff_{request.param}")
    generate_model(model, work / "out")
    ctrl = work / "out" / f"{model.name}_controller.c"
    rows = ctrldiff.input_rows(model, STEPS, seed=20261125)
    return model, work, ctrl, rows


def test_coq_c_and_blocksim_agree(setup):
    model, work, ctrl, rows = setup
    coq = ctrldiff.run_c(ctrldiff.build_coq(model, work), rows)
    c_o2 = ctrldiff.run_c(ctrldiff.build_c(model, ctrl, work, ["-O2", "-ffp-contract=off"], "c_o2"), rows)
    env = dict(os.environ, ASAN_OPTIONS="detect_leaks=0", UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1")
    c_san = ctrldiff.run_c(ctrldiff.build_c(model, ctrl, work, [
        "-O0", "-fsanitize=address,undefined", "-fno-sanitize-recover=all", "-ffp-contract=off"], "c_san"),
        rows, env=env)
    py = ctrldiff.run_blocksim(model, rows)
    assert len(coq) == STEPS
    assert ctrldiff.compare(model, coq, c_o2, ("Coq", "gcc -O2")) == []
    assert ctrldiff.compare(model, coq, c_san, ("Coq", "gcc -O0 ASan/UBSan")) == []
    assert ctrldiff.compare(model, coq, py, ("Coq", "blocksim")) == []


def test_a_wrong_controller_is_caught(setup):
    """The comparison has teeth: the printed C with the operands of one
    comparison in a MinMax or Saturation reversed differs from Coq's
    dg_step at a named step and field."""
    model, work, ctrl, rows = setup
    text = ctrl.read_text()
    m = re.search(r"if \(\((rtb_\w+) ([<>]) (rtb_\w+)\)\)", text)
    assert m, "no MinMax comparison in the printed controller"
    flipped = {"<": ">", ">": "<"}[m.group(2)]
    bad = work / "bad" / ctrl.name
    bad.parent.mkdir(exist_ok=True)
    bad.write_text(text[:m.start()] + f"if (({m.group(1)} {flipped} {m.group(3)}))" + text[m.end():])
    coq_step = work / "coq_step"
    coq = ctrldiff.run_c(coq_step if coq_step.exists() else ctrldiff.build_coq(model, work), rows)
    wrong = ctrldiff.run_c(ctrldiff.build_c(model, bad, work / "bad", ["-O2"], "c_bad"), rows)
    diffs = ctrldiff.compare(model, coq, wrong, ("Coq", "mutated C"))
    assert diffs and diffs[0].startswith("step ")

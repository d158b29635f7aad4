"""The layout check (DESIGN.md section 7) against controller headers that
agree, and that disagree in every way that matters, with the glue's structs
(those Coq printed for the LandShark build)."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from pyrosgen.ros import layout
from pyrosgen.frontend.validate import load_model

from .conftest import LANDSHARK, LANDSHARK_CTL

NODE = "landshark_controller"

GOOD = LANDSHARK_CTL / "Controller.h"


@pytest.fixture(scope="module")
def checker(landshark_build, tmp_path_factory):
    _, out = landshark_build
    model = load_model(LANDSHARK)
    types_h = (out / f"{NODE}_types.h").read_text()
    work = tmp_path_factory.mktemp("layout")
    check_c = work / f"{NODE}_layout_check.c"
    check_c.write_text(layout.render_layout_check(model, types_h, f"{NODE}_types.h"))
    n = [0]

    def check(header_text: str | None, edit=None) -> list[str] | None:
        """None if the header passes, else the problems."""
        n[0] += 1
        d = work / f"ctl{n[0]}"
        shutil.copytree(LANDSHARK_CTL, d)
        if header_text is not None:
            (d / "Controller.h").write_text(header_text)
        try:
            layout.check_layout(model, check_c, d, work / f"w{n[0]}", types_h)
        except layout.LayoutMismatch as exc:
            assert exc.header == d / "Controller.h"
            return exc.problems
        return None

    return check


def _edit(old: str, new: str) -> str:
    text = GOOD.read_text()
    assert old in text
    return text.replace(old, new)


def test_example_header_passes(checker):
    assert checker(None) is None


def test_same_tag_as_the_glue_does_not_clash(checker):
    # Simulink may name the struct's tag; even the glue's own tag is fine
    text = _edit("typedef struct {\n  real_T In1;", "typedef struct ExtU_Controller_T {\n  real_T In1;")
    assert checker(text) is None


def test_type_mismatch_names_the_field(checker):
    problems = checker(_edit("  real_T In2;", "  real32_T In2;"))
    assert problems == ["Controller_U.In2: type is not double (the model says float64)"]


def test_same_size_other_type_is_caught(checker):
    problems = checker(_edit("  real_T Out1;", "  int64_T Out1;"))
    assert problems == ["Controller_Y.Out1: type is not double (the model says float64)"]


def test_field_order_names_the_moved_fields(checker):
    text = _edit("  real_T In1;                          /* '<Root>/In1': left wheel velocity */\n"
                 "  real_T In2;                          /* '<Root>/In2': right wheel velocity */\n",
                 "  real_T In2;\n  real_T In1;\n")
    problems = checker(text)
    assert problems == ["Controller_U.In1: offset differs from the glue struct",
                        "Controller_U.In2: offset differs from the glue struct"]


def test_extra_field_changes_the_size(checker):
    problems = checker(_edit("  real_T Out1;", "  real_T Out1;\n  real_T Out2;"))
    assert problems == ["Controller_Y: size differs from the glue struct (1 field)"]


def test_missing_field_is_reported(checker):
    problems = checker(_edit("  real_T In3;", ""))
    assert any("In3" in p for p in problems), problems
    assert any("Controller_U: size differs" in p for p in problems), problems


def test_step_signature_is_checked(checker):
    problems = checker(_edit("extern void Controller_step(void);", "extern int Controller_step(void);"))
    assert problems == ["Controller_step: not declared as void Controller_step(void)"]


def test_missing_global_is_reported(checker):
    problems = checker(_edit("extern ExtY_Controller_T Controller_Y;", ""))
    assert problems and any("Controller_Y" in p and "undeclared" in p for p in problems), problems


def test_rename_tags_refuses_unexpected_preprocessor_lines():
    with pytest.raises(layout.LayoutToolError):
        layout.rename_tags("#include <evil.h>\nstruct a { int x; };\n", "p_")
    assert layout.rename_tags("#ifndef G\n#define G\nstruct a { struct b x; };\n#endif\n", "p_") == \
        "struct p_a { struct p_b x; };\n"


def test_reference_header_agrees_by_construction(landshark_build, tmp_path):
    _, out = landshark_build
    model = load_model(LANDSHARK)
    types_h = (out / f"{NODE}_types.h").read_text()
    ref = layout.render_reference_header(model, types_h)
    assert "typedef struct pyrosgen_ref_ExtU_Controller_T ExtU_Controller_T;" in ref
    d = tmp_path / "ref"
    d.mkdir()
    (d / "Controller.h").write_text(ref)
    check_c = tmp_path / "check.c"
    check_c.write_text(layout.render_layout_check(model, types_h, f"{NODE}_types.h"))
    layout.check_layout(model, check_c, d, tmp_path / "w", types_h)  # passes
    # a broken check is the tool's fault (exit 2), not the user's
    check_c.write_text(check_c.read_text().replace("_Static_assert(sizeof(Controller_U)", "_Static_assert(0*sizeof(Controller_U)"))
    with pytest.raises(layout.LayoutToolError):
        layout.check_layout(model, check_c, Path(LANDSHARK_CTL), tmp_path / "w2", types_h)

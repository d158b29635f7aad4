"""The choice of the main theorem, against stand-in ROSGen libraries (links
to the real compiled files, with some modules left out or replaced):

- without ``DDC``/``Loopproof`` the per-node file proves the fallback
  ``<node>_wf`` (T4) and says so, and the C is the same;
- with them, ``<node>_ddc`` is proved by instantiating
  ``Loopproof.generate_node_ddc`` (here a stand-in with the same
  signature, so that this branch is tested whatever the state of the real
  library);
- if that theorem rests on an axiom, ``Print Assumptions`` says so and
  pyrosgen refuses to write anything (exit 2).
"""

from __future__ import annotations



from pyrosgen import cli
from pyrosgen.proof.coqdriver import CLOSED, CoqDriver

from support.generate import GOLDEN, LANDSHARK, make_standin_library, require_library

NODE = "landshark_controller"
DDC_MODULES = ("DDC", "Copyproof", "Glueproof", "Loopproof")

STUB_DDC = """\
(* A stand-in for ROSGen.DDC, for tests only: same name and type. *)
From ROSGen Require Import Errors Syntax NodeModel Generator Environment.
Definition node_ddc (m : node_model) (p : program) : Prop := generate m = OK p.
Definition node_ddc_on (tg : target) (m : node_model) (p : program) : Prop := generate m = OK p.
Lemma node_ddc_on_target : forall tg m p, node_ddc m p -> node_ddc_on tg m p.
Proof. intros tg m p H. exact H. Qed.
"""

STUB_LOOPPROOF = """\
(* A stand-in for ROSGen.Loopproof, for tests only: same name and type. *)
From ROSGen Require Import Errors Syntax NodeModel Generator DDC.
Theorem generate_node_ddc : forall m p, generate m = OK p -> DDC.node_ddc m p.
Proof. intros m p H. exact H. Qed.
"""

UNPROVED_LOOPPROOF = """\
(* A stand-in for ROSGen.Loopproof resting on an axiom, for tests only. *)
From ROSGen Require Import Errors Syntax NodeModel Generator DDC.
""" + "Ax" + """iom generate_node_ddc : forall m p, generate m = OK p -> DDC.node_ddc m p.
"""


def run(capsys, *argv):
    code = cli.main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def test_fallback_without_the_ddc_theorem(capsys, tmp_path, monkeypatch):
    require_library()
    lib = make_standin_library(tmp_path / "lib", drop=DDC_MODULES)
    assert not CoqDriver(lib).ddc_available()
    monkeypatch.setenv("PYROSGEN_COQLIB", str(lib))
    out_dir = tmp_path / "out"
    code, out, err = run(capsys, "generate", LANDSHARK, "-o", out_dir)
    assert code == 0, err
    assert f"  theorem   {NODE}_wf: well-formedness, T4 (Wellformed.wf); fallback: the node DDC theorem T2" in out
    assert f"proving {NODE}_wf ..." in err
    assert CLOSED in out
    v = (out_dir / f"{NODE}.v").read_text()
    assert "DDC" not in v.split("(** ** Message definitions")[1]
    assert f"Definition {NODE}_theorems := {NODE}_wf." in v and f"{NODE}_ddc" not in v
    # the same C as with the full library
    assert (out_dir / f"{NODE}_glue.c").read_bytes() == (GOLDEN / f"{NODE}_glue.c").read_bytes()


def test_ddc_theorem_instantiated(capsys, tmp_path, monkeypatch):
    require_library()
    lib = make_standin_library(
        tmp_path / "lib", drop=DDC_MODULES, extra={"DDC": STUB_DDC, "Loopproof": STUB_LOOPPROOF})
    assert CoqDriver(lib).ddc_available()
    monkeypatch.setenv("PYROSGEN_COQLIB", str(lib))
    out_dir = tmp_path / "out"
    code, out, err = run(capsys, "generate", LANDSHARK, "-o", out_dir)
    assert code == 0, err
    assert f"  theorem   {NODE}_ddc: node data delivery correctness, T2 (DDC.node_ddc)" in out
    assert "fallback" not in out
    v = (out_dir / f"{NODE}.v").read_text()
    assert "From ROSGen Require DDC Loopproof." in v
    assert f"Theorem {NODE}_ddc : DDC.node_ddc model the_program." in v
    assert f"Definition {NODE}_theorems := (conj {NODE}_ddc (conj {NODE}_ddc_target {NODE}_wf))." in v
    assert f"Print Assumptions {NODE}_theorems_local." in v
    assert (out_dir / f"{NODE}_glue.c").read_bytes() == (GOLDEN / f"{NODE}_glue.c").read_bytes()
    # the stand-in library has no make proofs stamp: pyrosgen printed the
    # assumptions of the library's theorems itself, and says so
    cert = (out_dir / f"{NODE}.certificate.md").read_text()
    assert ("each applying one of Generatorproof.generate_sound, Loopproof.generate_node_ddc: "
            "pyrosgen printed their assumptions, closed") in cert


def test_theorem_resting_on_an_axiom_is_refused(capsys, tmp_path, monkeypatch):
    require_library()
    lib = make_standin_library(
        tmp_path / "lib", drop=DDC_MODULES, extra={"DDC": STUB_DDC, "Loopproof": UNPROVED_LOOPPROOF})
    monkeypatch.setenv("PYROSGEN_COQLIB", str(lib))
    out_dir = tmp_path / "out"
    out_dir.mkdir()
    code, out, err = run(capsys, "generate", LANDSHARK, "-o", out_dir, "-q")
    assert code == 2
    assert out == ""
    assert f"the theorems {NODE}_ddc, {NODE}_ddc_target, {NODE}_wf (their conjunction {NODE}_theorems) depend on axioms" in err
    assert "generate_node_ddc" in err  # the axiom is named
    assert list(out_dir.iterdir()) == []
    assert not list(tmp_path.glob(".pyrosgen-*"))

"""The axiom gate of ``make -C coq check-assumptions``
(coq/checks/assumptions.sh): it passes when every theorem is closed under
the global context, and otherwise names each theorem that is not, with the
axioms it depends on, and fails.

Scratch theorems are written into ``tmp_path`` (never into coq/theories):
one that uses the excluded middle, one that computes with Flocq's
real-number-based ``Bmult``, one that mentions Flocq's ``b64_of_bits``
(whose proofs use the classical reals), and closed ones.  Only the scratch
files are compiled; the ROSGen library is used as built by ``make -C coq``.
"""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

import pytest

from support.printer import COQ_DIR, THEORIES, build_coq_library, run

SCRIPT = COQ_DIR / "checks" / "assumptions.sh"
MAIN_V = THEORIES / "Main.v"

#: Without the ROSGen library: the standard library and Flocq only.
PLAIN_V = """\
From Coq Require Import ZArith Classical_Prop.
From Flocq Require Import IEEE754.Binary IEEE754.BinarySingleNaN.

Theorem closed_one : forall n : nat, n + 0 = n.
Proof. intros n; rewrite <- plus_n_O; reflexivity. Qed.

Theorem excluded : forall P : Prop, P \\/ ~ P.
Proof. exact classic. Qed.

(* Multiplication with Flocq's Bmult: its validity proofs use the reals. *)
Definition mul (x y : Binary.binary_float 53 1024) : Binary.binary_float 53 1024 :=
  Binary.Bmult 53 1024 eq_refl eq_refl
    (fun _ _ => exist _ (Binary.B754_nan 53 1024 false 1 eq_refl) eq_refl) mode_NE x y.

Theorem mul_refl : forall x y, mul x y = mul x y.
Proof. intros; reflexivity. Qed.
"""

#: Against the built ROSGen library.
LIBRARY_V = """\
From Coq Require Import ZArith.
From Flocq Require Import IEEE754.Bits.
From ROSGen Require Import FloatBits.

(* Flocq's own decoder: its proofs use the classical reals. *)
Theorem flocq_decoder : b64_of_bits 0%Z = b64_of_bits 0%Z.
Proof. reflexivity. Qed.

(* The library's decoder is closed. *)
Theorem rosgen_decoder : float64_of_bits 0%Z = float64_of_bits 0%Z.
Proof. reflexivity. Qed.
"""


def check(*args: str, cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run(["sh", str(SCRIPT), *args], cwd=cwd, capture_output=True, text=True,
                          timeout=600, check=False)


@pytest.fixture(scope="module")
def plain(tmp_path_factory) -> Path:
    d = tmp_path_factory.mktemp("plain")
    (d / "S.v").write_text(PLAIN_V)
    run(["coqc", "-q", "-Q", ".", "Scratch", "S.v"], cwd=d)
    return d


def test_closed_theorems_pass(plain):
    proc = check("-Q", ".", "Scratch", "-r", "Scratch.S", "S.closed_one", cwd=plain)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip() == "proofs: 1 main theorems closed under the global context"
    assert proc.stderr == ""


def test_axioms_are_named_per_theorem(plain):
    proc = check("-Q", ".", "Scratch", "-r", "Scratch.S",
                  "S.closed_one", "S.excluded", "S.mul_refl", cwd=plain)
    assert proc.returncode == 1
    lines = proc.stderr.splitlines()
    assert "proofs: error: S.excluded depends on: Classical_Prop.classic" in lines
    bmult = [ln for ln in lines if ln.startswith("proofs: error: S.mul_refl depends on: ")]
    assert len(bmult) == 1
    deps = bmult[0].split(": ", 2)[2].split(", ")
    assert "ClassicalDedekindReals.sig_forall_dec" in deps
    assert "Classical_Prop.classic" in deps
    assert not any("closed_one" in ln for ln in lines)
    assert lines[-1] == "proofs: error: 2 of 3 main theorems depend on axioms"
    assert "closed under the global context" not in proc.stdout


def test_names_from_a_file(plain):
    (plain / "names.txt").write_text("# theorems\nS.closed_one\n\nS.excluded\n")
    proc = check("-Q", ".", "Scratch", "-r", "Scratch.S", "-f", "names.txt", cwd=plain)
    assert proc.returncode == 1
    assert "proofs: error: S.excluded depends on: Classical_Prop.classic" in proc.stderr
    assert "1 of 2 main theorems" in proc.stderr


def test_unknown_theorem_or_none_is_an_error(plain):
    proc = check("-Q", ".", "Scratch", "-r", "Scratch.S", "S.no_such_theorem", cwd=plain)
    assert proc.returncode == 2
    assert "S.no_such_theorem" in proc.stderr
    assert "Print Assumptions failed" in proc.stderr
    proc = check("-Q", ".", "Scratch", "-r", "Scratch.S", cwd=plain)
    assert proc.returncode == 2
    assert "no theorem given" in proc.stderr
    proc = check("-r", "Scratch.S", "S.closed_one; Admitted", cwd=plain)
    assert proc.returncode == 2
    assert "not a qualified name" in proc.stderr


def test_against_the_library(tmp_path):
    build_coq_library()
    (tmp_path / "L.v").write_text(LIBRARY_V)
    run(["coqc", "-q", "-R", str(THEORIES), "ROSGen", "-Q", ".", "Scratch", "L.v"], cwd=tmp_path)
    proc = check("-R", str(THEORIES), "ROSGen", "-Q", ".", "Scratch", "-r", "Scratch.L",
                 "L.flocq_decoder", "L.rosgen_decoder", "FloatBits.bits_of_float64_of_bits",
                 cwd=tmp_path)
    assert proc.returncode == 1
    errors = [ln for ln in proc.stderr.splitlines() if "depends on" in ln]
    assert len(errors) == 1 and errors[0].startswith("proofs: error: L.flocq_decoder depends on: ")
    assert "ClassicalDedekindReals.sig_forall_dec" in errors[0]


def test_makefile_sees_every_main_theorem():
    """The Makefile lists the theorems of Main.v with a sed on lines that
    start with `Theorem NAME`: every theorem of Main.v must be written so,
    and Main.v must hold the main results T1-T5."""
    text = MAIN_V.read_text(encoding="utf-8")
    code = re.sub(r"\(\*.*?\*\)", "", text, flags=re.S)  # Main.v has no nested comments
    keywords = re.findall(r"^\s*(Theorem|Lemma|Corollary|Proposition|Fact|Remark)\b", code, re.M)
    assert keywords and set(keywords) == {"Theorem"}
    names = re.findall(r"^Theorem ([A-Za-z0-9_']+)", code, re.M)
    assert len(names) == len(keywords) == len(set(names))
    for t in ["generate_callback_ddc", "generate_input_glue_ddc", "generate_output_glue_ddc",
              "generate_node_ddc", "relation_consistency_input_glue", "generate_valid_assignments",
              "generate_complete", "generate_sound", "wf_check_wf", "interp_sound",
              "run_program_sound"]:
        assert t in names, t
    # the recipe of the axiom gate's stamp, printed (-n) even when the stamp
    # is up to date (-B)
    out = run(["make", "--no-print-directory", "-C", str(COQ_DIR), "-n", "-B", ".stamp-assumptions"]).stdout
    line = [ln for ln in out.splitlines() if "assumptions.sh" in ln]
    assert len(line) == 1, out
    assert re.findall(r"(?<= )Main\.([A-Za-z0-9_']+)", line[0]) == names

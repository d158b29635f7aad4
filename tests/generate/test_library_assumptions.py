"""The library's assumptions, printed once by ``make proofs`` rather than
by every node (DESIGN.md section 7): a node's ``.v`` prints the
assumptions of its theorems as functions of the library's
(``<theorem>_of_library``), and pyrosgen trusts the library's own
``.stamp-assumptions`` for the library's theorems only when the stamp is
no older than any compiled library file and ``Main.v`` restates each of
them (``Proof. exact <it>. Qed.``); otherwise it prints them itself
(``test_ddc_branches.py``: a stand-in library without the stamp whose
theorem rests on an axiom is refused).

The stamp's conditions are checked on a fake library (files only, no Coq)."""

from __future__ import annotations

import os

from pyrosgen.proof.coqdriver import ASSUMPTIONS_STAMP, LIBRARY_THEOREMS_DDC, CoqDriver
from pyrosgen.generate import library_theorems_of

MAIN = """\
Theorem generate_node_ddc:
  forall m p, generate m = OK p -> node_ddc m p.
Proof. exact Loopproof.generate_node_ddc. Qed.

Theorem generate_sound: forall m p, generate m = OK p -> wf m = true.
Proof. exact Generatorproof.generate_sound. Qed.
"""


def fake_library(root, main=MAIN):
    theories = root / "theories"
    (theories / "glue").mkdir(parents=True)
    files = ["theories/glue/Loopproof.v", "theories/glue/Generatorproof.v", "theories/Main.v"]
    for f in files:
        (root / f).write_text("(* *)\n")
        (root / f).with_suffix(".vo").write_bytes(b"vo")
    (theories / "Main.v").write_text(main)
    (root / "_CoqProject").write_text("-R theories ROSGen\n" + "\n".join(files) + "\n")
    stamp = root / ASSUMPTIONS_STAMP
    stamp.write_text("")
    t = os.stat(theories / "Main.vo").st_mtime + 10
    os.utime(stamp, (t, t))
    return CoqDriver(theories), stamp


def test_a_fresh_stamp_is_trusted(tmp_path):
    drv, _ = fake_library(tmp_path)
    assert drv.library_assumptions_stamped(LIBRARY_THEOREMS_DDC)


def test_no_stamp_is_not_trusted(tmp_path):
    drv, stamp = fake_library(tmp_path)
    stamp.unlink()
    assert not drv.library_assumptions_stamped(LIBRARY_THEOREMS_DDC)


def test_a_stamp_older_than_a_compiled_file_is_not_trusted(tmp_path):
    drv, stamp = fake_library(tmp_path)
    vo = tmp_path / "theories" / "glue" / "Loopproof.vo"
    t = os.stat(stamp).st_mtime + 5
    os.utime(vo, (t, t))
    assert not drv.library_assumptions_stamped(LIBRARY_THEOREMS_DDC)


def test_a_theorem_main_does_not_restate_is_not_covered(tmp_path):
    # Main.v proves generate_node_ddc otherwise than by the library's theorem
    drv, _ = fake_library(tmp_path, MAIN.replace("Proof. exact Loopproof.generate_node_ddc. Qed.",
                                                 "Proof. intros. apply other. Qed."))
    assert not drv.library_assumptions_stamped(LIBRARY_THEOREMS_DDC)
    assert drv.library_assumptions_stamped(("Generatorproof.generate_sound",))
    # a diagram node also needs T7 and T8, which this Main.v does not restate
    assert not drv.library_assumptions_stamped(library_theorems_of(True, True))


def test_the_real_library_covers_every_theorem_a_node_applies():
    """The library of this checkout restates all four in Main.v (whether
    its stamp is fresh depends on make proofs, not tested here)."""
    drv = CoqDriver()
    main = (drv.theories / "Main.v").read_text()
    for thm in library_theorems_of(True, True):
        assert f"Proof. exact {thm}. Qed." in main, thm

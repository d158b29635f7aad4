"""A consistent error of the C printer is caught by the printer validation
(issue 29): the AST dump (``coq/theories/clight/Dump.v``) is printed by a
path of its own, so a wrong token in ``Printer.v`` changes the C text but
not the dump, and ``pyrosgen generate`` refuses the node.

The test copies the built library to its temporary folder, mutates the C
token of ``Olt`` in the copy's ``Printer.v`` (``"<"`` printed ``"<="``),
recompiles only the files that load ``Printer`` and that a node needs
(``Printer``, ``ModelText``, ``DiagramText``; ``Dump.vo`` is *not*
recompiled: it loads against the mutated ``Printer.vo`` only because it
does not depend on it), and generates a diagram node whose controller
compares with ``<`` (``tests/validation/models/ctrl_all_blocks.yaml``)
against the copy (``PYROSGEN_COQLIB``).  ``generate`` must exit 2, name
the disagreement, and write nothing.  (That ``Dump.v`` loads nothing but
``Syntax`` is ``tests/coq/test_layout.py``.)  The same run against the unmutated
copy succeeds, so the refusal is the mutation's.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys

import pytest

from support.validation import REPO

MODEL = REPO / "tests" / "validation" / "models" / "ctrl_all_blocks.yaml"
LIB = REPO / "coq"
#: The files of the library that load ``Printer``, that a node's ``.v``
#: loads, in build order.
REBUILT = ["clight/Printer.v", "glue/ModelText.v", "ctrl/DiagramText.v"]


def _copy_library(dst):
    """The built library (sources and .vo) and its _CoqProject, in ``dst``."""
    shutil.copy2(LIB / "_CoqProject", dst / "_CoqProject")
    shutil.copytree(LIB / "theories", dst / "theories",
                    ignore=shutil.ignore_patterns("*.glob", ".*.aux", "*.vos", "*.vok"))
    return dst / "theories"


def _rebuild(theories):
    for rel in REBUILT:
        res = subprocess.run(["coqc", "-q", "-R", ".", "ROSGen", rel], cwd=theories,
                             capture_output=True, text=True, timeout=300)
        assert res.returncode == 0, res.stdout + res.stderr


def _generate(theories, out):
    env = dict(os.environ, PYROSGEN_COQLIB=str(theories))
    return subprocess.run([sys.executable, "-m", "pyrosgen", "generate", str(MODEL), "-o", str(out)],
                          cwd=REPO, env=env, capture_output=True, text=True, timeout=600)


@pytest.fixture(scope="module")
def mutated_library(tmp_path_factory):
    base = tmp_path_factory.mktemp("printer_mutation")
    theories = _copy_library(base)
    printer = theories / "clight" / "Printer.v"
    text = printer.read_text()
    token = '| Olt => "<" |'
    assert text.count(token) == 1, "the mutation target is gone from Printer.v"
    printer.write_text(text.replace(token, '| Olt => "<=" |'))
    _rebuild(theories)
    return theories


def test_consistent_printer_error_is_refused(mutated_library, tmp_path):
    out = tmp_path / "out"
    res = _generate(mutated_library, out)
    assert res.returncode == 2, res.stdout + res.stderr
    assert "Traceback" not in res.stderr
    err = res.stderr
    # the disagreement is named: the file and function, the C's operator
    # and the dump's
    assert "error: printer validation failed: ctrl_all_blocks_controller.c:" in err, err
    assert "function Ctl_step" in err, err
    assert "C has le" in err and "AST has lt" in err, err
    assert "nothing written" in err, err
    assert not out.exists() or not any(out.iterdir())


def test_unmutated_copy_generates(tmp_path):
    """Control: the same copy without the mutation generates the node."""
    theories = _copy_library(tmp_path)
    out = tmp_path / "out"
    res = _generate(theories, out)
    assert res.returncode == 0, res.stdout + res.stderr
    c_text = (out / "ctrl_all_blocks_controller.c").read_text()
    assert " < " in c_text

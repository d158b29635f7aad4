"""``pyrosgen generate`` on a model whose controller is a block diagram
(examples/landshark/landshark_diagram.yaml): the controller's C is printed
by Coq from the diagram and validated against its dump; the node file
proves three more theorems (the diagram is well formed; the node with the
diagram as its controller, T2 end to end; the same of the glue and the
generated controller linked into one program, T8), each closed; the certificate
says what they mean; ``pyrosgen verify`` re-prints the controller and
refuses a tampered one; Coq, not the front end, is the authority on the
diagram; ``build`` takes no controller folder for such a model."""

from __future__ import annotations

import hashlib
import json
import shutil
import subprocess
from pathlib import Path

import pytest

from pyrosgen import cli
from pyrosgen.frontend.validate import load_model
from pyrosgen.generate import generate, generate_model
from pyrosgen.proof import coqdiagram
from pyrosgen.proof.coqdriver import CoqError

from support.generate import LANDSHARK, REPO, require_library

DIAGRAM = REPO / "examples" / "landshark" / "landshark_diagram.yaml"
NODE = "landshark_controller"


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    require_library()
    d = tmp_path_factory.mktemp("diagram") / "out"
    res = generate(DIAGRAM, d)
    assert res.record.controller is not None
    return d


def _rehash(d: Path) -> None:
    m = d / f"{NODE}.manifest.json"
    data = json.loads(m.read_text())
    data["files"] = {n: hashlib.sha256((d / n).read_bytes()).hexdigest() for n in data["files"]}
    m.write_text(json.dumps(data))
    (d / f"{NODE}.sha256").write_text("".join(f"{v}  {n}\n" for n, v in data["files"].items()))


def test_files_theorems_and_certificate(folder):
    v = (folder / f"{NODE}.v").read_text()
    assert "Module Ctrl." in v and "Definition the_diagram : diagram := mkdiagram" in v
    for thm in (f"Theorem {NODE}_controller_wf : dg_wf the_diagram = true.",
                f"Theorem {NODE}_e2e : Endtoend.diagram_node_ok model the_program the_diagram.",
                f"Theorem {NODE}_linked : Link.linked_node_ok model the_program the_diagram."):
        assert thm in v
    manifest = json.loads((folder / f"{NODE}.manifest.json").read_text())
    assert manifest["theorems"] == [f"{NODE}_ddc", f"{NODE}_ddc_target", f"{NODE}_wf", f"Ctrl.{NODE}_controller_wf",
                                    f"Ctrl.{NODE}_e2e", f"Ctrl.{NODE}_linked"]
    assert manifest["controller"]["linked"] == f"Ctrl.{NODE}_linked"
    assert manifest["controller"]["c"] in manifest["files"]
    assert manifest["assumptions"].count("Closed under the global context") == 1
    assert manifest["assumptions"].count(" /\\ ") == 5  # the conjunction of the 6 theorems
    cert = (folder / f"{NODE}.certificate.md").read_text()
    assert f"`Ctrl.{NODE}_e2e : Endtoend.diagram_node_ok model the_program" in cert
    assert f"`Ctrl.{NODE}_linked : Link.linked_node_ok model the_program" in cert
    assert "Not modelled" not in cert
    # the proved diagram, as Coq printed it, is in the certificate
    text = (folder / f"{NODE}_controller.diagram").read_text()
    assert text.startswith("pyrosgen-diagram 1\n") and "eq median float64 max lo12 lo\n" in text
    assert text.rstrip("\n") in cert


def test_controller_c_is_embedded_coder_shaped_and_compiles(folder, tmp_path):
    c = (folder / f"{NODE}_controller.c").read_text()
    for needle in ("struct ExtU_Controller_T Controller_U;", "struct ExtY_Controller_T Controller_Y;",
                   "struct DW_Controller_T Controller_DW;", "void Controller_step(void)\n{",
                   "void Controller_initialize(void)\n{", "Controller_Y.Out1 = rtb_out;"):
        assert needle in c
    r = subprocess.run(["gcc", "-std=c11", "-pedantic", "-Wall", "-Wextra", "-Werror", "-c",
                        str(folder / f"{NODE}_controller.c"), "-o", str(tmp_path / "c.o")],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr


def test_verify_reprints_the_controller(folder, capsys):
    code = cli.main(["verify", str(folder), "--model", str(DIAGRAM), "-q"])
    out = capsys.readouterr().out
    assert code == 0, out
    assert "7 files equal to the proof's" in out
    assert "the proved model is the model of landshark_diagram.yaml" in out
    assert f"Ctrl.{NODE}_e2e, Ctrl.{NODE}_linked: Closed under the global context" in out


def test_verify_refuses_a_tampered_controller(folder, tmp_path, capsys):
    d = tmp_path / "copy"
    shutil.copytree(folder, d)
    p = d / f"{NODE}_controller.c"
    text = p.read_text()
    assert "(rtb_setpoint - rtb_median)" in text
    p.write_text(text.replace("(rtb_setpoint - rtb_median)", "(rtb_median - rtb_setpoint)"))
    _rehash(d)  # a careful forger: the digests agree with the folder
    code = cli.main(["verify", str(d), "-q"])
    out = capsys.readouterr().out
    assert code == 1, out
    assert f"{NODE}_controller.c: differs from what the proof prints" in out


def test_coq_refuses_an_ill_formed_diagram(tmp_path, monkeypatch):
    """The emitted diagram is checked by Coq's dg_wf, not trusted: a
    diagram whose output takes a signal of another type (here the bool
    err_ok for the float64 Out1), as a broken emitter would write it, is
    refused by coqc and nothing is written."""
    require_library()
    model = load_model(DIAGRAM)
    real = coqdiagram.emit_diagram

    def broken(m):
        return real(m).replace('[("Out1", "out")]', '[("Out1", "err_ok")]')

    monkeypatch.setattr(coqdiagram, "emit_diagram", broken)
    out = tmp_path / "out"
    with pytest.raises(CoqError):
        generate_model(model, out)
    assert not out.exists()


def test_a_state_global_named_like_the_glue_is_refused_by_coq(tmp_path, monkeypatch):
    """The linked program's theorem needs the diagram's state global to
    name no global of the glue (Link.link_fresh; the front end refuses
    such a model first, rule 4.11).  An emitter that names it after the
    glue's main function is stopped by coqc, with the reason, and nothing
    is written."""
    require_library()
    model = load_model(DIAGRAM)
    real = coqdiagram.emit_diagram

    def clashing(m):
        text = real(m)
        assert '"Controller_DW"' in text
        return text.replace('"Controller_DW"', '"main"')

    monkeypatch.setattr(coqdiagram, "emit_diagram", clashing)
    out = tmp_path / "out"
    with pytest.raises(CoqError) as exc:
        generate_model(model, out)
    assert "ROSGen.Link.link_fresh" in str(exc.value)
    assert not out.exists()


def test_a_diagram_emitted_wrong_is_refused(tmp_path, monkeypatch):
    """The seam: an emitter that writes another constant than the model's
    (the Gain 0.8 as 0.9) yields a well-formed diagram that Coq proves,
    but the diagram Coq prints differs from the front end's reading of the
    YAML, so generate stops (exit 2) naming the item, and writes nothing."""
    require_library()
    model = load_model(DIAGRAM)
    real = coqdiagram.emit_diagram
    k08, k09 = "0x3FE999999999999A", "0x3FECCCCCCCCCCCCD"  # 0.8, 0.9

    def wrong(m):
        text = real(m)
        assert k08 in text
        return text.replace(k08, k09)

    monkeypatch.setattr(coqdiagram, "emit_diagram", wrong)
    out = tmp_path / "out"
    from pyrosgen.proof.modeltext import ModelMismatch

    with pytest.raises(ModelMismatch) as exc:
        generate_model(model, out)
    assert "eq p_term float64 gain 0x3fe999999999999a err" in "\n".join(exc.value.lines)
    assert "0x3feccccccccccccd" in "\n".join(exc.value.lines)
    assert not out.exists()


def test_build_controller_folder_rules(tmp_path, capsys):
    """A diagram model takes no --controller; any other model needs one.
    Both are refused before any work, with exit 1."""
    code = cli.main(["build", str(DIAGRAM), "--controller", str(REPO / "examples" / "landshark" / "controller"),
                     "-o", str(tmp_path / "a")])
    err = capsys.readouterr().err
    assert code == 1 and "block diagram" in err and "--controller" in err
    code = cli.main(["build", str(LANDSHARK), "-o", str(tmp_path / "b")])
    err = capsys.readouterr().err
    assert code == 1 and "--controller DIR is required" in err
    assert not (tmp_path / "a").exists() and not (tmp_path / "b").exists()


@pytest.mark.parametrize("name", ["ok_blocks_all", "ok_blocks_order"])
def test_every_block_kind_generates_and_compiles(name, tmp_path):
    """The front end's test diagrams (every block kind and signal type;
    blocks written against their data flow) are proved by Coq, their
    controller C validated against its dump and compiled strictly."""
    require_library()
    model = REPO / "tests" / "frontend" / "models" / f"{name}.yaml"
    res = generate(model, tmp_path / "out")
    node = res.model.name
    assert res.record.controller["e2e"] == f"Ctrl.{node}_e2e"
    c = tmp_path / "out" / f"{node}_controller.c"
    # a block whose output nothing reads is allowed (rule 4.11): its
    # temporary is set and not used
    r = subprocess.run(["gcc", "-std=c11", "-pedantic", "-Wall", "-Wextra", "-Werror",
                        "-Wno-unused-but-set-variable", "-c", str(c),
                        "-o", str(tmp_path / "c.o")], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr


def test_check_says_the_controller_is_a_diagram(capsys):
    code = cli.main(["check", str(DIAGRAM)])
    out = capsys.readouterr().out
    assert code == 0
    assert out.rstrip().endswith("; controller: a block diagram of 13 blocks (1 state)")
    code = cli.main(["check", str(LANDSHARK)])
    assert "block diagram" not in capsys.readouterr().out

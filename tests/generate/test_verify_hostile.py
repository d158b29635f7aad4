"""``pyrosgen verify OUT`` treats OUT as hostile (issue 29): one test per
attack, each on a copy of one real LandShark folder inside the test's
``tmp_path``, run through the command line (a subprocess with a timeout,
its temporary folder inside ``tmp_path`` too).  Each asserts exit 1 and a
message naming what failed; the attacks that would run a command or
write a file point at a sentinel inside ``tmp_path`` and assert that it
is unchanged (or was never created)."""

from __future__ import annotations

import hashlib
import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from pyrosgen.proof.coqdriver import CLOSED, CoqDriver, CoqError, parse_assumptions
from pyrosgen.verify import vfile
from pyrosgen.verify.recheck import VerifyFailed, verify_folder

from support.generate import LANDSHARK, OK_MODELS, REPO, require_library

NODE = "landshark_controller"
V = f"{NODE}.v"
MANIFEST = f"{NODE}.manifest.json"


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    require_library()
    from pyrosgen.generate import generate

    d = tmp_path_factory.mktemp("hostile") / "out"
    generate(LANDSHARK, d)
    return d


@pytest.fixture
def copy(folder, tmp_path):
    c = tmp_path / "copy"
    shutil.copytree(folder, c)
    return c


def _verify(d: Path, *args: str, timeout: float = 300) -> tuple[int, str]:
    """``pyrosgen verify d ARGS -q`` in a subprocess (its temporary folder
    in d's parent): exit status and output."""
    tmp = d.parent / "verify-tmp"
    tmp.mkdir(exist_ok=True)
    env = {**os.environ, "TMPDIR": str(tmp)}
    p = subprocess.run([sys.executable, "-m", "pyrosgen", "verify", str(d), "-q", *args], cwd=REPO, env=env,
                       capture_output=True, text=True, timeout=timeout, check=False)
    out = p.stdout + p.stderr
    assert "Traceback" not in out and "internal error" not in out, out
    return p.returncode, out


def _manifest(d: Path) -> dict:
    return json.loads((d / MANIFEST).read_text())


def _write_manifest(d: Path, data) -> None:
    (d / MANIFEST).write_text(json.dumps(data))


def _rehash(d: Path) -> None:
    """Make the three records (manifest, digest file, certificate) agree
    with the folder's files again, as a careful forger would."""
    data = _manifest(d)
    cert = d / f"{NODE}.certificate.md"
    text = cert.read_text()
    for n, old in data["files"].items():
        new = hashlib.sha256((d / n).read_bytes()).hexdigest()
        text = text.replace(old, new)
        data["files"][n] = new
    cert.write_text(text)
    _write_manifest(d, data)
    (d / f"{NODE}.sha256").write_text("".join(f"{v}  {n}\n" for n, v in data["files"].items()))


def _edit_v(d: Path, old: str, new: str, count: int = 1) -> None:
    v = d / V
    text = v.read_text()
    assert old in text, f"{old!r} not in the .v: the template changed; update the test"
    v.write_text(text.replace(old, new, count))
    _rehash(d)


def _line_of(d: Path, needle: str) -> int:
    text = (d / V).read_text()
    return text[:text.index(needle)].count("\n") + 1


DDC_PROOF = (f"Theorem {NODE}_ddc : DDC.node_ddc model the_program.\n"
             f"Proof. exact ({NODE}_ddc_of_library Loopproof.generate_node_ddc). Qed.")


# -- the .v: commands, axioms, weaker theorems --------------------------------------------------


def test_axiom_forgery_is_refused_before_coqc(copy):
    """Issue 29: the proof of <node>_ddc replaced by an axiom, a fake
    "Closed under" printed, the digests rewritten in the three records."""
    _edit_v(copy, DDC_PROOF, f"Axiom cheat : False.\nTheorem {NODE}_ddc : DDC.node_ddc model the_program.\n"
                             "Proof. destruct cheat. Qed.")
    v = copy / V
    v.write_text(v.read_text() + f'\nEval compute in "{CLOSED}"%string.\n')
    _rehash(copy)
    line = _line_of(copy, "Axiom cheat")
    code, out = _verify(copy)
    assert code == 1, out
    assert "FAILED  v-file" in out
    assert f"{V}:{line}:1: error: ident 'Axiom' where the template has ident 'Theorem'" in out, out
    assert "FAILED  coqc      not run:" in out


def test_axiom_forgery_is_refused_by_coq_itself(copy, monkeypatch):
    """The same forgery with the template check switched off: Print
    Assumptions, parsed (not a string count), refuses it, and so would
    coqchk's list of axioms (next tests).  The .v's own Print Assumptions
    covers only its [_of_library] functions (the forged theorem does not
    go through them); Coq's confirmation prints the assumptions of the
    theorems themselves, library and all, and names the axiom."""
    _edit_v(copy, DDC_PROOF, f"Axiom cheat : False.\nTheorem {NODE}_ddc : DDC.node_ddc model the_program.\n"
                             "Proof. destruct cheat. Qed.")
    v = copy / V
    v.write_text(v.read_text() + f'\nEval compute in "{CLOSED}"%string.\n')
    _rehash(copy)
    monkeypatch.setattr(vfile, "check_structure", lambda *a, **kw: 0)
    with pytest.raises(VerifyFailed) as e:
        verify_folder(copy)
    coqc = next(c for c in e.value.verify_report.checks if c.name == "coqc")
    assert not coqc.ok and f'Print Assumptions of the theorems is not "{CLOSED}"' in coqc.summary
    assert any("cheat : False" in line for line in coqc.details), coqc.details


#: Issue 29's other-model forgery: the theorems and the printed program are
#: about the user's model plus one output relation, while [model] (whose
#: text the model check compares with the YAML) is left as the user's.
MODEL2 = ("\n\nDefinition model2 : node_model := mknode_model (nm_name model) (nm_period_ms model) (nm_ctrl model)"
          " (nm_in_var model) (nm_in_struct model) (nm_inputs model) (nm_out_var model) (nm_out_struct model)"
          " (nm_outputs model) (nm_msgs model) (nm_topics model) (nm_inrels model)"
          ' (nm_outrels model ++ [mkoutrel "Out1" "landshark_control_base_velocity"'
          ' [PField "twist"; PField "angular"; PField "z"]]) (nm_timeouts model) (nm_fallbacks model)'
          " (nm_drels model) (nm_stamps model) (nm_stamp_from model) (nm_strings model).\n")


def _other_model_forgery(d: Path) -> None:
    v = d / V
    text = v.read_text()
    end = text.index("  |}.\n", text.index("Definition model : node_model")) + len("  |}.")
    text = text[:end] + MODEL2 + text[end:]
    # (the theorems and their <theorem>_of_library functions: two of each statement)
    for old, new, count in [("Generator.generate model.", "Generator.generate model2.", 1),
                            ("Wellformed.wf_check model = OK tt", "Wellformed.wf_check model2 = OK tt", 1),
                            ("Generator.generate model = OK the_program", "Generator.generate model2 = OK the_program", 1),
                            ("Wellformed.wf model = true", "Wellformed.wf model2 = true", 2),
                            ("T4 model the_program", "T4 model2 the_program", 1),
                            ("DDC.node_ddc model the_program", "DDC.node_ddc model2 the_program", 2),
                            ("DDC.node_ddc_on target model the_program", "DDC.node_ddc_on target model2 the_program", 2),
                            ("node_ddc_on_target target model the_program", "node_ddc_on_target target model2 the_program", 1),
                            ("T2 model the_program", "T2 model2 the_program", 2)]:
        assert text.count(old) == count, old
        text = text.replace(old, new)
    v.write_text(text)
    _rehash(d)


def test_other_model_forgery_is_refused(copy, monkeypatch):
    """The .v proves DDC of the user's model plus one output relation: the
    template check refuses the extra definition; with that check switched
    off, the .v compiles, but Coq does not confirm the statements (T2 and
    generate_ok are not about [model])."""
    _other_model_forgery(copy)
    line = _line_of(copy, "Definition model2")
    code, out = _verify(copy, "--model", str(LANDSHARK))
    assert code == 1, out
    assert f"{V}:{line}:12: error: ident 'model2' where the template has ident 'program_result'" in out, out
    monkeypatch.setattr(vfile, "check_structure", lambda *a, **kw: 0)
    with pytest.raises(VerifyFailed) as e:
        verify_folder(copy)
    coqc = next(c for c in e.value.verify_report.checks if c.name == "coqc")
    assert coqc.summary == "Coq does not confirm the theorems' statements", coqc
    assert any("generate_ok" in ln or "model2" in ln or "confirm_0" in ln for ln in coqc.details), coqc.details


def test_coq_confirms_statements_and_refuses_an_axiom(folder, tmp_path):
    """CoqDriver.confirm_theorems on the compiled real node: its
    statements are confirmed; a statement it does not prove (DDC of a
    model with one output relation more) is refused by Coq; a module whose
    theorem uses an axiom is refused by the parsed Print Assumptions."""
    drv = CoqDriver()
    lib = tmp_path / "lib"
    lib.mkdir()
    shutil.copy(folder / V, lib / V)
    drv.coqc(lib / V, (lib, "RosgenNode"))
    m = f"RosgenNode.{NODE}"
    imports = "From ROSGen Require Import Errors Syntax NodeModel Wellformed Generator.\nFrom ROSGen Require DDC.\n"
    drv.confirm_theorems(m, (lib, "RosgenNode"), [(f"{NODE}_ddc", f"DDC.node_ddc {m}.model {m}.the_program")],
                         tmp_path / "c1", imports=imports)
    other = (f"(let md := {m}.model in mknode_model md.(nm_name) md.(nm_period_ms) md.(nm_ctrl) md.(nm_in_var) "
             f"md.(nm_in_struct) md.(nm_inputs) md.(nm_out_var) md.(nm_out_struct) md.(nm_outputs) md.(nm_msgs) "
             f"md.(nm_topics) md.(nm_inrels) (app md.(nm_outrels) md.(nm_outrels)) md.(nm_timeouts) "
             f"md.(nm_fallbacks) md.(nm_drels) md.(nm_stamps) md.(nm_stamp_from) md.(nm_strings))")
    with pytest.raises(CoqError, match="does not confirm the theorems' statements"):
        drv.confirm_theorems(m, (lib, "RosgenNode"), [(f"{NODE}_ddc", f"DDC.node_ddc {other} {m}.the_program")],
                             tmp_path / "c2", imports=imports)
    ax = tmp_path / "ax"
    ax.mkdir()
    (ax / "Ax.v").write_text("Axiom cheat : False.\nTheorem t : 1 = 2. Proof. destruct cheat. Qed.\n")
    drv.coqc(ax / "Ax.v", (ax, "AxLib"))
    with pytest.raises(CoqError, match="is not \"Closed under the global context\"") as e:
        drv.confirm_theorems("AxLib.Ax", (ax, "AxLib"), [("t", "1 = 2")], tmp_path / "c3")
    assert any("cheat" in line for line in e.value.lines)


def test_coqchk_lists_an_axiom_and_it_is_refused(tmp_path):
    """coqchk exits 0 on a module with an axiom; its context summary
    (-o) lists it, and the driver refuses it."""
    drv = CoqDriver()
    (tmp_path / "Ax.v").write_text("Axiom cheat : False.\nTheorem t : 1 = 2. Proof. destruct cheat. Qed.\n")
    drv.coqc(tmp_path / "Ax.v", (tmp_path, "AxLib"))
    raw = drv.run(drv._coqchk_argv("AxLib.Ax", (tmp_path, "AxLib"), True), tmp_path)
    assert raw.ok and "AxLib.Ax.cheat" in raw.output  # coqchk itself accepts it
    with pytest.raises(CoqError, match="not closed under the global context") as e:
        drv.coqchk("AxLib.Ax", (tmp_path, "AxLib"))
    assert e.value.lines == ("  Axioms: AxLib.Ax.cheat",)
    (tmp_path / "Ok.v").write_text("Theorem u : 1 = 1. Proof. reflexivity. Qed.\n")
    drv.coqc(tmp_path / "Ok.v", (tmp_path, "AxLib"))
    assert drv.coqchk("AxLib.Ok", (tmp_path, "AxLib")).ok


def test_a_printed_closed_string_is_not_a_closed_theorem():
    out = f'Axioms:\ncheat : False\n     = "{CLOSED}"%string\n     : string\n'
    assert parse_assumptions(out) == (0, ["cheat : False"], [])
    assert parse_assumptions(f'     = "{CLOSED}"%string\n     : string\n') == (0, [], [])
    with pytest.raises(CoqError):
        CoqDriver.check_assumptions(f'     = "{CLOSED}"%string\n', ["a"], "all")
    with pytest.raises(CoqError):  # the count is right, but an axiom is listed
        CoqDriver.check_assumptions(f"Axioms:\ncheat : False\n{CLOSED}\n", ["a"], "all")


def test_extract_constant_cannot_run_a_command(copy, tmp_path):
    sentinel = tmp_path / "pwned"
    # (pyrosgen's own Extract.v, which Requires the module, would honour it)
    _edit_v(copy, 'Definition model_text (_ : unit)',
            f'Extract Constant types_h => "(fun _ -> ignore (Sys.command ""touch {sentinel}""); """")".\n'
            'Definition model_text (_ : unit)')
    line = _line_of(copy, "Extract Constant")
    code, out = _verify(copy)
    assert code == 1, out
    assert f"{V}:{line}:1: error: ident 'Extract' where the template has ident 'Definition'" in out, out
    assert not sentinel.exists()


def test_a_theorem_of_true_is_refused(copy, monkeypatch):
    """<node>_ddc stated as True: the template check refuses it; without
    that check, Coq's confirmation of the statements does."""
    _edit_v(copy, DDC_PROOF, f"Theorem {NODE}_ddc : True.\nProof. exact I. Qed.")
    line = _line_of(copy, f"Theorem {NODE}_ddc : True")
    code, out = _verify(copy)
    assert code == 1, out
    assert f"{V}:{line}:" in out and "ident 'True' where the template has ident 'DDC.node_ddc'" in out, out
    monkeypatch.setattr(vfile, "check_structure", lambda *a, **kw: 0)
    with pytest.raises(VerifyFailed) as e:
        verify_folder(copy)
    coqc = next(c for c in e.value.verify_report.checks if c.name == "coqc")
    assert coqc.summary == "Coq does not confirm the theorems' statements", coqc
    assert any(f"{NODE}_ddc" in line or "True" in line for line in coqc.details), coqc.details


def test_a_manifest_naming_other_theorems_is_refused(copy):
    """A .v proving only `hack : True` and a manifest naming it: the
    theorems come from the node's name, not from the manifest."""
    _edit_v(copy, DDC_PROOF, "Theorem hack : True.\nProof. exact I. Qed.")
    data = _manifest(copy)
    data["theorems"], data["theorem"] = ["hack", f"{NODE}_wf"], "hack"
    _write_manifest(copy, data)
    code, out = _verify(copy)
    assert code == 1, out
    assert "field 'theorems'" in out and f"not the node's theorems ['{NODE}_ddc', '{NODE}_ddc_target', '{NODE}_wf']" in out, out


TARGET_DEF = "Definition target : Environment.target := Environment.Ros1."


def test_a_v_naming_another_target_is_refused(copy, monkeypatch):
    """Rule 4.17: a ROS 1 folder whose .v says it was generated for ROS 2
    (so that <node>_ddc_target would be about ROS 2's environments): the
    template check refuses the target; without that check, Coq does not
    confirm <node>_ddc_target against the statement for the manifest's
    target ROS 1."""
    _edit_v(copy, TARGET_DEF, TARGET_DEF.replace("Ros1.", "Ros2."))
    line = _line_of(copy, TARGET_DEF.replace("Ros1.", "Ros2."))
    code, out = _verify(copy)
    assert code == 1, out
    assert (f"{V}:{line}:43: error: ident 'Environment.Ros2' where the template has ident "
            "'Environment.Ros1'") in out, out
    monkeypatch.setattr(vfile, "check_structure", lambda *a, **kw: 0)
    with pytest.raises(VerifyFailed) as e:
        verify_folder(copy)
    coqc = next(c for c in e.value.verify_report.checks if c.name == "coqc")
    assert coqc.summary == "Coq does not confirm the theorems' statements", coqc
    assert any("Ros1" in ln or "Ros2" in ln or "confirm_1" in ln for ln in coqc.details), coqc.details


def test_a_manifest_target_that_is_not_a_target_is_refused(copy):
    data = _manifest(copy)
    assert data["target"] == "ros1"
    data["target"] = "ros3"
    _write_manifest(copy, data)
    code, out = _verify(copy)
    assert code == 1, out
    assert "field 'target': 'ros3', not ros1 or ros2" in out, out


@pytest.mark.parametrize("command", ["Redirect", "Extraction"])
def test_the_v_cannot_write_a_file(copy, tmp_path, command):
    sentinel = tmp_path / "written"
    text = (f'Redirect "{sentinel}" Print model.\n' if command == "Redirect"
            else f'Extraction "{sentinel}.ml" model.\n')
    _edit_v(copy, "(** ** The printed texts *)", text + "(** ** The printed texts *)")
    line = _line_of(copy, text)
    code, out = _verify(copy)
    assert code == 1, out
    assert f"{V}:{line}:1: error: ident '{command}' where the template has ident 'Definition'" in out, out
    assert not list(tmp_path.glob("written*"))


@pytest.mark.parametrize("text,what", [
    ("Require Import Extraction", "ident 'Require'"),
    ("ltac:(idtac)", "ident 'ltac'"),
    ("(Eval compute in 1)", "ident 'Eval'"),
    # the '.' ends the model's body early; what follows is not the template's
    ("\"a\". Axiom x : False. Definition y := \"b\"", "ident 'Axiom' where the template has ident 'Definition'"),
])
def test_only_literals_in_the_model(copy, text, what):
    """The model's body is free, but only for literals: a command, a tactic
    or a sentence end there is refused with its place."""
    _edit_v(copy, 'nm_ctrl := "Controller"', f"nm_ctrl := {text}")
    line = _line_of(copy, f"nm_ctrl := {text}")
    code, out = _verify(copy)
    assert code == 1, out
    assert f"{V}:{line}:" in out, out
    if "template" in what:
        assert what in out, out
    else:
        assert f"{what} in the body of model, where only literals are allowed" in out, out


@pytest.mark.parametrize("old,new,message", [
    ("nm_period_ms := 20;", "nm_period_ms := 1000000000000;", "the numeral 1000000000000 in the body of model"),
    ('("x", FTprim Pfloat64)', '("x", FTarray (FTprim Pfloat64) 1000000000000)', "the numeral 1000000000000"),
])
def test_literal_sizes_are_bounded(copy, old, new, message):
    """Without --model, a model of the template's shape cannot ask Coq
    for an array of 10^12 elements (memory): sizes are bounded by what
    the emitter writes."""
    _edit_v(copy, old, new)
    line = _line_of(copy, new)
    code, out = _verify(copy, timeout=120)
    assert code == 1, out
    assert f"{V}:{line}:" in out and message in out, out


def test_zrange_is_bounded():
    text = vfile.skeleton(NODE, ddc_available=True, diagram=False)
    body = '{| nm_inrels := (map (fun i => mkinrel_at "t" ([PField "a"] ++ [PIndex i]) "In1" [PIndex i]) (zrange %d))%%list |}'
    ok = text.replace("PYROSGEN_FREE_MESSAGES", "[]").replace("PYROSGEN_FREE_MODEL", body % 65536)
    assert vfile.check_structure(ok, V, NODE, ddc_available=True, diagram=False)
    with pytest.raises(vfile.VFileError, match="the numeral 65537 in the body of model: more than 65,536"):
        vfile.check_structure(ok.replace("zrange 65536", "zrange 65537"), V, NODE, ddc_available=True, diagram=False)


def test_every_model_renders_a_v_of_the_template():
    """The structural check accepts what generate writes, for every model
    the front end and Coq accept (no coqc: the rendering only)."""
    from pyrosgen.frontend.validate import load_model
    from pyrosgen.proof.coqdiagram import emit_diagram
    from pyrosgen.proof.coqmodel import render_node_file

    seen_diagram = False
    for p in OK_MODELS:
        m = load_model(p)
        dg = m.controller.diagram is not None
        seen_diagram |= dg
        text = render_node_file(m, ddc_available=True, diagram=emit_diagram(m) if dg else "")
        assert vfile.check_structure(text, p.name, m.name, ddc_available=True, diagram=dg) > 100
        with pytest.raises(vfile.VFileError):  # and not a diagram node's skeleton for the other
            vfile.check_structure(text, p.name, m.name, ddc_available=True, diagram=not dg)
    assert seen_diagram


def test_the_lexer_reads_comments_and_strings_as_coq_does():
    toks = list(vfile.tokens('(* a (* "*)" *) b *) Definition x := "a""b". (* "(*" *)'))
    assert [(t.kind, t.text) for t in toks] == [
        ("comment", '(* a (* "*)" *) b *)'), ("ident", "Definition"), ("ident", "x"), ("punct", ":="),
        ("string", '"a""b"'), ("dot", "."), ("comment", '(* "(*" *)')]
    for bad, where in [("(* open", "1:1"), ('x := "open', "1:6"), ("x := caf\u00e9", "1:9"), ("x\t", "1:2"),
                       ("x := 1e5", "1:6")]:
        with pytest.raises(vfile.VFileError) as e:
            list(vfile.tokens(bad, "f.v"))
        assert e.value.lines[0].startswith(f"f.v:{where}: error:"), e.value.lines


# -- names in the manifest ---------------------------------------------------------------------


@pytest.mark.parametrize("field", ["types_h", "sexp", "model_file"])
def test_absolute_names_are_refused_and_nothing_is_written(copy, tmp_path, field):
    sentinel = tmp_path / "system_file"
    sentinel.write_text("precious\n")
    data = _manifest(copy)
    data[field] = str(sentinel)
    _write_manifest(copy, data)
    code, out = _verify(copy)
    assert code == 1, out
    assert f"field '{field}': {str(sentinel)!r}: an absolute path" in out, out
    assert sentinel.read_text() == "precious\n"


def test_a_node_v_outside_the_folder_is_refused(copy, tmp_path):
    data = _manifest(copy)
    data["node_v"] = "../../x.v"
    data["files"]["../../x.v"] = data["files"].pop(V)
    _write_manifest(copy, data)
    code, out = _verify(copy)
    assert code == 1, out
    assert "field 'node_v': '../../x.v': not a plain relative path" in out, out
    assert not list(tmp_path.rglob("x.vo")) and not (tmp_path.parent / "x.v").exists()


def test_wp_contracts_outside_the_folder_are_refused_without_frama_c(copy):
    data = _manifest(copy)
    data["wp"] = {"proved": 1, "total": 1, "prover": "alt-ergo", "contracts": "../x", "functions": []}
    _write_manifest(copy, data)
    code, out = _verify(copy, "--wp", timeout=60)
    assert code == 1, out
    assert "field 'wp.contracts':" in out and "'../x': not a plain relative path" in out, out


@pytest.mark.parametrize("what,edit,message", [
    ("no files", lambda d: d.pop("files"), "field 'files': missing"),
    ("wrong type", lambda d: d.update(ddc="yes"), "field 'ddc': str, not true or false"),
    ("theorems not a list", lambda d: d.update(theorems=5), "field 'theorems': int, not a list"),
    ("node with /", lambda d: d.update(node="../evil"), "field 'node': '../evil' is not a C identifier"),
    ("bad digest", lambda d: d["files"].update({V: "x" * 64}), f"field 'files.{V}'"),
    ("file name", lambda d: d["files"].update({"/etc/passwd": "0" * 64}), "'/etc/passwd': an absolute path"),
    ("unknown field", lambda d: d.update(extra=1), "field 'extra': not a field of a pyrosgen manifest"),
    ("a list", lambda d: (d.clear(), d.update(format=[1])), "not a pyrosgen manifest of format 1"),
])
def test_malformed_manifests_are_exit_1(copy, what, edit, message):
    data = _manifest(copy)
    edit(data)
    _write_manifest(copy, data)
    code, out = _verify(copy, timeout=60)
    assert code == 1, out
    assert "unreadable manifest" in out and message in out, out


def test_every_field_of_the_wrong_type_is_a_manifest_error(folder, tmp_path):
    """Each field of a real manifest (and of its nested objects) replaced
    by a value of each JSON type: read_manifest accepts it or raises
    ManifestError naming the field, never anything else."""
    from pyrosgen.verify.certificate import ManifestError, read_manifest

    good = _manifest(folder)
    values = [None, 0, -1, 1.5, True, "", "x", "../x", "/x", [], [[]], ["a", "b"], {}, {"a": 1}, "a" * 5000]
    paths = [(k,) for k in good] + [(k, j) for k in ("files", "wp", "controller") if isinstance(good.get(k), dict)
                                    for j in good[k]] + [("tools", 0), ("theorems", 0)]
    p = tmp_path / MANIFEST
    tried = refused = 0
    for path in paths:
        for v in values:
            data = json.loads(json.dumps(good))
            target = data
            for key in path[:-1]:
                target = target[key]
            target[path[-1]] = v
            p.write_text(json.dumps(data))
            tried += 1
            try:
                read_manifest(p)
            except ManifestError as exc:
                refused += 1
                assert repr(path[0])[1:-1] in str(exc) or "format" in str(exc) or "files" in str(exc), (path, v, exc)
    assert tried > 200 and refused > tried * 0.8, (tried, refused)


def test_a_manifest_nested_10000_deep_is_exit_1(copy):
    (copy / MANIFEST).write_text('{"format": 1, "files": ' + "[" * 10000 + "]" * 10000 + "}")
    code, out = _verify(copy, timeout=60)
    assert code == 1, out
    assert f"{MANIFEST}: nested more than 8 deep" in out, out


# -- files that are not regular files of the folder ---------------------------------------------


@pytest.mark.parametrize("name,message", [
    (f"{NODE}.sha256", "digest file"),
    (MANIFEST, "manifest"),
    (f"{NODE}.certificate.md", "certificate"),
])
def test_a_fifo_is_refused_without_hanging(copy, name, message):
    (copy / name).unlink()
    os.mkfifo(copy / name)
    code, out = _verify(copy, timeout=120)
    assert code == 1, out
    assert f"{message} {name}: a FIFO, not a regular file" in out, out


@pytest.mark.parametrize("name", [V, f"{NODE}_glue.c"])
def test_a_link_to_dev_zero_is_refused(copy, name):
    (copy / name).unlink()
    (copy / name).symlink_to("/dev/zero")
    code, out = _verify(copy, timeout=120)
    assert code == 1, out
    assert f"{name}: a symbolic link (to '/dev/zero'), not a file" in out, out


def test_a_sparse_20_gb_file_is_not_read(copy):
    glue = copy / f"{NODE}_glue.c"
    glue.unlink()
    subprocess.run(["truncate", "-s", "20G", str(glue)], check=True)
    code, out = _verify(copy, timeout=120)
    assert code == 1, out
    assert f"{NODE}_glue.c: 21474836480 bytes, more than the" in out, out


def test_a_link_to_a_file_outside_is_refused(copy, tmp_path):
    """The glue replaced by a link to an identical file outside the folder:
    the digests match, but verify reads no file through a link."""
    outside = tmp_path / "outside_glue.c"
    shutil.copy(copy / f"{NODE}_glue.c", outside)
    (copy / f"{NODE}_glue.c").unlink()
    (copy / f"{NODE}_glue.c").symlink_to(outside)
    code, out = _verify(copy, timeout=120)
    assert code == 1, out
    assert f"{NODE}_glue.c: a symbolic link (to {str(outside)!r}), not a file" in out, out


def test_a_folder_on_the_way_that_is_a_link_is_refused(copy, tmp_path):
    outside = tmp_path / "elsewhere"
    outside.mkdir()
    (outside / "x.txt").write_text("x\n")
    (copy / "pkg").symlink_to(outside)
    data = _manifest(copy)
    data["files"]["pkg/x.txt"] = hashlib.sha256(b"x\n").hexdigest()
    _write_manifest(copy, data)
    code, out = _verify(copy, timeout=120)
    assert code == 1, out
    assert "pkg/x.txt: pkg is not a folder (a symbolic link or another kind of file)" in out, out


# -- time ---------------------------------------------------------------------------------------


def test_a_tool_that_does_not_finish_is_stopped(copy):
    """--timeout: coqc (2 s for LandShark) stopped after 0.3 s, its check
    failed with the limit named."""
    code, out = _verify(copy, "--timeout", "0.3", timeout=120)
    assert code == 1, out
    assert re.search(r"FAILED  coqc +coqc did not finish within 0\.3 s", out), out


def test_timeout_must_be_positive(copy):
    code, out = _verify(copy, "--timeout", "0", timeout=60)
    assert code == 1, out
    assert "not a positive number of seconds" in out


# -- memory -------------------------------------------------------------------------------------


def test_a_tool_over_the_memory_limit_is_stopped(copy, tmp_path, monkeypatch):
    """Every tool verify runs has an address-space limit: coqc under
    256 MiB (LandShark needs more; the largest model of BENCHMARKS.md
    passes under 1 GiB, the default is 8 GiB) stops with "Out of memory",
    and its check fails naming the limit, instead of the machine swapping."""
    import tempfile

    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
    with pytest.raises(VerifyFailed) as info:
        verify_folder(copy, max_memory=256 << 20)
    failed = {c.name: c for c in info.value.verify_report.checks if not c.ok}
    assert failed["coqc"].summary.startswith("coqc ran out of memory: it stopped at the limit of 256 MiB "
                                             "of address space"), failed["coqc"]
    assert "Out of memory" in failed["coqc"].details[0]


def test_procs_run_limits_the_address_space():
    from pyrosgen import procs

    grab = [sys.executable, "-c", "x = bytearray(512 << 20); print(len(x))"]
    r = procs.run(grab, max_memory=128 << 20)
    assert r.returncode != 0 and "MemoryError" in r.stderr
    r = procs.run(grab, max_memory=2 << 30)
    assert r.returncode == 0 and r.stdout.strip() == str(512 << 20)
    assert not procs.out_of_memory(r.returncode, r.stderr + r.stdout)
    assert procs.out_of_memory(2, "Fatal error: exception Out_of_memory")


def test_frama_c_is_stopped_by_the_timeout(tmp_path, monkeypatch):
    """verify --wp --timeout N: Frama-C stopped after N s (coqc given the
    usual time by the driver), its check failed with the limit named."""
    import tempfile

    from pyrosgen.generate import generate

    require_library()
    if shutil.which("frama-c") is None:
        pytest.fail("Frama-C is not installed (make deps)")
    d = tmp_path / "wp"
    generate(LANDSHARK, d, wp=True)
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
    with pytest.raises(VerifyFailed) as info:
        verify_folder(d, wp=True, timeout=0.5, driver=CoqDriver(timeout=300))
    failed = {c.name: c for c in info.value.verify_report.checks if not c.ok}
    assert set(failed) == {"wp"}, failed
    assert failed["wp"].summary == "frama-c did not finish within 0.5 s"

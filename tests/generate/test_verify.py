"""``pyrosgen verify OUT``: an output folder re-checked on its own; every
kind of tampering is refused (exit 1) with the failed checks named, and
the folder is never written."""

from __future__ import annotations

import hashlib
import json
import shutil
from pathlib import Path

import pytest

from pyrosgen import cli, procs
from pyrosgen.generate import generate
from pyrosgen.proof.coqdriver import CoqDriver
from pyrosgen.verify.recheck import VerifyFailed, verify_folder

from support.generate import LANDSHARK, MULTI, require_library

NODE = "landshark_controller"


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    require_library()
    d = tmp_path_factory.mktemp("verify") / "out"
    generate(LANDSHARK, d)
    return d


@pytest.fixture
def copy(folder, tmp_path):
    c = tmp_path / "copy"
    shutil.copytree(folder, c)
    return c


def _snapshot(d: Path) -> dict[str, bytes]:
    return {str(p.relative_to(d)): p.read_bytes() for p in sorted(d.rglob("*")) if p.is_file()}


def _failed(d: Path, **kw) -> dict[str, list[str]]:
    with pytest.raises(VerifyFailed) as e:
        verify_folder(d, **kw)
    return {c.name: c.details for c in e.value.verify_report.checks if not c.ok}


def _rehash(d: Path) -> None:
    """Make the manifest and the digest file agree with the folder again
    (what a careful forger would do)."""
    m = d / f"{NODE}.manifest.json"
    data = json.loads(m.read_text())
    data["files"] = {n: hashlib.sha256((d / n).read_bytes()).hexdigest() for n in data["files"]}
    m.write_text(json.dumps(data))
    (d / f"{NODE}.sha256").write_text("".join(f"{v}  {n}\n" for n, v in data["files"].items()))


def test_a_fresh_folder_verifies(folder, capsys):
    before = _snapshot(folder)
    code = cli.main(["verify", str(folder), "--model", str(LANDSHARK), "-q"])
    out = capsys.readouterr().out
    assert code == 0, out
    for name in ("hashes", "library", "v-file", "coqc", "re-print", "certificate", "model"):
        assert f"  ok      {name:<10}" in out, out
    assert "the .v that generate renders from landshark_controller.yaml, byte for byte" in out
    assert (f"{NODE}_ddc, {NODE}_ddc_target, {NODE}_wf: Closed under the global context; statements confirmed by Coq; "
            "coqchk OK, no axiom") in out
    assert "FAILED" not in out
    assert _snapshot(folder) == before  # nothing written


def test_edited_glue_is_refused(copy, capsys):
    glue = copy / f"{NODE}_glue.c"
    glue.write_text(glue.read_text().replace("Controller_U.In1 = ", "Controller_U.In2 = ", 1))
    code = cli.main(["verify", str(copy), "-q"])
    out, err = capsys.readouterr()
    assert code == 1
    assert "  FAILED  hashes" in out and f"{NODE}_glue.c: SHA-256" in out
    assert "  FAILED  re-print" in out and f"{NODE}_glue.c: differs from what the proof prints" in out
    assert "  ok      coqc" in out
    assert "checks failed: hashes, re-print" in err


def test_rehashed_edit_is_still_refused(copy):
    """Digests updated after the edit: the re-printing still refuses it,
    and the certificate, which lists the old digest, is no longer the one
    the manifest's digests give."""
    h = copy / f"{NODE}_types.h"
    h.write_text(h.read_text().replace("double", "float", 1))
    _rehash(copy)
    failed = _failed(copy)
    assert set(failed) == {"re-print", "certificate"}
    assert any(f"{NODE}_types.h: differs" in line for line in failed["re-print"])
    assert any(f"{NODE}_types.h" in line for line in failed["certificate"]), failed["certificate"]


def test_swapped_model_in_the_v_is_refused(copy):
    """The .v edited to swap two relations (only literals change, so it
    has the template's structure): without --model coqc accepts it and the
    re-print refuses the glue; with --model the .v is not the one generate
    renders from the model, and nothing compiles it."""
    v = copy / f"{NODE}.v"
    text = v.read_text()
    a, b = "mkinrel \"landshark_left_wheel_velocity\"", "mkinrel \"landshark_right_wheel_velocity\""
    assert a in text and b in text, "the emitter's relation syntax changed; update the test"
    v.write_text(text.replace(a, "@A").replace(b, a).replace("@A", b))
    failed = _failed(copy)
    assert {"hashes", "re-print"} <= set(failed)
    assert "coqc" not in failed and "v-file" not in failed
    failed = _failed(copy, model=LANDSHARK)
    assert {"hashes", "v-file", "coqc"} <= set(failed)
    line = text[:text.index(a)].count("\n") + 1
    assert any(f"{NODE}.v:{line}:" in ln and "the folder's" in ln for ln in failed["v-file"]), failed["v-file"]


def test_missing_file_and_broken_v(copy):
    (copy / f"{NODE}.sexp").unlink()
    v = copy / f"{NODE}.v"
    v.write_text(v.read_text() + "\nLemma broken : False. Proof. exact I. Qed.\n")
    failed = _failed(copy)
    assert any(f"{NODE}.sexp: missing" in line for line in failed["hashes"])
    assert "coqc" in failed and "re-print" in failed


def test_edited_certificate_is_refused(copy):
    """The certificate is not covered by the digests (it lists them), but
    verify renders it again from the proof's texts and the manifest: a
    reworded relation is refused, and nothing else fails."""
    cert = copy / f"{NODE}.certificate.md"
    text = cert.read_text()
    assert "(cycle property `DDC.input_values`)" in text
    cert.write_text(text.replace("(cycle property `DDC.input_values`)", "(cycle property `DDC.anything`)", 1))
    failed = _failed(copy)
    assert set(failed) == {"certificate"}
    assert any("DDC.anything" in line for line in failed["certificate"]), failed["certificate"]


def test_other_library_is_refused(copy, monkeypatch):
    monkeypatch.setattr(CoqDriver, "library_digest", lambda self: "0" * 64)
    failed = _failed(copy)
    assert set(failed) == {"library"}
    assert any("0" * 64 in line for line in failed["library"])


def test_not_an_output_folder(tmp_path, capsys):
    assert cli.main(["verify", str(tmp_path)]) == 1
    assert "no *.manifest.json" in capsys.readouterr().err
    (tmp_path / "x.manifest.json").write_text("{not json")
    assert cli.main(["verify", str(tmp_path)]) == 1
    assert "unreadable manifest" in capsys.readouterr().err
    (tmp_path / "x.manifest.json").write_bytes(b"\xff\xfe\x00garbage")
    assert cli.main(["verify", str(tmp_path)]) == 1
    assert cli.main(["verify", str(tmp_path / "nowhere")]) == 1


def test_two_nodes_in_one_folder(copy):
    """Certificates are per node: a second node in the same folder keeps
    the first one's, and verify checks the node it is asked about."""
    generate(MULTI, copy)
    assert (copy / f"{NODE}.certificate.md").is_file()
    with pytest.raises(Exception, match="several nodes"):
        verify_folder(copy)
    assert verify_folder(copy, node=NODE).ok
    assert verify_folder(copy, node="multi_node").ok


def test_wp_without_contracts_is_a_failed_check(copy):
    failed = _failed(copy, wp=True)
    assert set(failed) == {"wp"}


def test_kernel_rechecks_without_the_bytecode_machine(folder, capsys, monkeypatch):
    """`generate` and `verify` run coqchk with Coq's bytecode machine
    (`-bytecode-compiler yes`, as coqc ran the node's vm_compute);
    `verify --kernel` without it, and says so."""
    seen = []
    orig, orig_start = CoqDriver.run, procs.start

    def spy(self, argv, *a, **kw):
        seen.append([str(x) for x in argv])
        return orig(self, argv, *a, **kw)

    def spy_start(argv, *a, **kw):  # coqchk runs alongside the re-printing
        seen.append([str(x) for x in argv])
        return orig_start(argv, *a, **kw)

    monkeypatch.setattr(CoqDriver, "run", spy)
    monkeypatch.setattr(procs, "start", spy_start)
    assert cli.main(["verify", str(folder), "--kernel", "-q"]) == 0
    out = capsys.readouterr().out
    assert f"{NODE}_ddc, {NODE}_ddc_target, {NODE}_wf: Closed under the global context; statements confirmed by Coq; coqchk OK, no axiom (kernel conversion" in out
    chk = [a for a in seen if Path(a[0]).name == "coqchk"]
    assert len(chk) == 1 and "-bytecode-compiler" not in chk[0]
    seen.clear()
    assert cli.main(["verify", str(folder), "-q"]) == 0
    assert "kernel conversion" not in capsys.readouterr().out
    chk = [a for a in seen if Path(a[0]).name == "coqchk"]
    assert len(chk) == 1 and chk[0][chk[0].index("-bytecode-compiler") + 1] == "yes"


def test_a_coqchk_rejection_fails_the_proof_and_the_re_print(copy, monkeypatch):
    """coqchk runs while the texts are re-printed: when it rejects the
    module, the coqc check fails with its messages and the re-print does
    not count (it came from a module coqchk refused); a slow verdict is
    waited for."""
    monkeypatch.setattr(CoqDriver, "_coqchk_argv",
                        lambda self, module, lib, vm: ["sh", "-c", "sleep 1; echo 'Error: bad module' >&2; exit 1"])
    with pytest.raises(VerifyFailed) as e:
        verify_folder(copy)
    checks = {c.name: c for c in e.value.verify_report.checks}
    assert not checks["coqc"].ok and "coqchk rejected" in checks["coqc"].summary
    assert any("bad module" in ln for ln in checks["coqc"].details)
    assert not checks["re-print"].ok and checks["re-print"].summary == "not run: coqchk rejected the module"
    assert [c.name for c in e.value.verify_report.checks][:5] == ["hashes", "library", "v-file", "coqc", "re-print"]

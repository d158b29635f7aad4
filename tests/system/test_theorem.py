"""The system theorems of coq/theories/sys/System.v are closed under the
global context, and the system mutation catalogue (coq/tests/SystemMutants.v)
builds: a link proved from two nodes' T2, the wiring mutants refused."""

from __future__ import annotations

import re
import subprocess


def coqc(repo_root, tmp_path, text: str) -> str:
    f = tmp_path / "Check.v"
    f.write_text(text)
    r = subprocess.run(["coqc", "-R", str(repo_root / "coq/theories"), "ROSGen", "-R", str(repo_root / "coq/tests"),
                        "ROSGenTests", str(f)], capture_output=True, text=True, cwd=tmp_path, timeout=600)
    assert r.returncode == 0, r.stderr + r.stdout
    return r.stdout


THEOREMS = ("link_value", "system_link", "chain_runs", "chain_value", "chain_run_value")


def test_system_theorems_closed(repo_root, tmp_path):
    out = coqc(repo_root, tmp_path, "From ROSGen Require Import System.\n"
               + "".join(f"Print Assumptions System.{t}.\n" for t in THEOREMS))
    assert out.splitlines() == ["Closed under the global context"] * len(THEOREMS)


def test_system_mutants(repo_root, tmp_path):
    src = (repo_root / "coq/tests/SystemMutants.v").read_text()
    refuted = re.findall(r"^Theorem ([a-z0-9_]+_refuted)\s*:\s*link_ok [^.]*= false\.", src, re.M)
    assert refuted == ["crossed_inputs_refuted", "crossed_fields_refuted", "wrong_remap_refuted",
                       "no_remap_refuted", "from_subscription_refuted"]
    out = coqc(repo_root, tmp_path, src + "\nPrint Assumptions cascade_link.\n"
               + "".join(f"Check {t}.\n" for t in refuted))
    assert "Closed under the global context" in out
    for t in refuted:
        assert re.search(rf"^{t}\s*:\s*link_ok [^:]*=\s*false$", out, re.M), out
    # the wirings are wrong, not only refused: their semantic property is false on a concrete run
    semantic = re.findall(r"^Theorem ([a-z0-9_]+_run_refuted)\s*:\s*~ (link_holds|wired_link_holds) ", src, re.M)
    assert semantic == [("crossed_inputs_run_refuted", "link_holds"), ("crossed_fields_run_refuted", "link_holds"),
                        ("wrong_remap_run_refuted", "wired_link_holds")]
    # ... and the same property holds for the right wiring on that run (it is not false of every wiring)
    assert re.search(r"^Theorem cascade_wired : wired_link_holds g_leader g_follower ", src, re.M)
    out = coqc(repo_root, tmp_path, src + "".join(f"Print Assumptions {t}.\n" for t, _ in semantic)
               + "Print Assumptions cascade_wired.\n")
    assert out.splitlines()[-4:] == ["Closed under the global context"] * 4, out
    # the mutant file is part of the Coq tests and of `make mutants`
    assert "tests/" "SystemMutants.v" in (repo_root / "coq/Makefile").read_text()   # as coq/Makefile names it
    assert "coq/tests/SystemMutants.v" in (repo_root / "Makefile").read_text()

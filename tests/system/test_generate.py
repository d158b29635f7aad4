"""``pyrosgen system generate``: nodes in parallel, the content-addressed
cache (a second run all hits; one node changed, only it proved; a corrupted
or partial entry never trusted; a killed run leaves no entry a later run
trusts), nothing written into OUT on failure."""

from __future__ import annotations

import json
import re
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from pyrosgen import cli
from pyrosgen.system.generate import ENTRY, entry_valid, generate_system

from .sysfiles import chain


def tree(folder: Path) -> dict[str, bytes]:
    return {p.relative_to(folder).as_posix(): p.read_bytes() for p in sorted(folder.rglob("*")) if p.is_file()}


def entries(cache: Path) -> list[Path]:
    return sorted(p for p in cache.iterdir() if not p.name.startswith("."))


@pytest.fixture(scope="module")
def cold(tmp_path_factory):
    """One cold run of the two-node chain (both nodes proved)."""
    d = tmp_path_factory.mktemp("cold")
    src = d / "src"
    src.mkdir()
    p = chain(src)
    cache = d / "cache"
    res = generate_system(p, d / "out", jobs=2, cache=cache)
    return p, cache, d / "out", res


def test_cold_run(cold):
    p, cache, out, res = cold
    assert [(n.folder, n.cached) for n in res.nodes] == [("a", False), ("b", False)]
    names = tree(out)
    for node in ("a", "b"):
        for suffix in (".v", "_glue.c", ".certificate.md", ".manifest.json", ".model"):
            assert f"{node}/{node}{suffix}" in names
    cert = names["sys.certificate.md"].decode()
    assert "`/src` -> `/a` -> `/mid` -> `/b` -> `/out`" in cert
    assert "`O1` -> `linear.x`" in cert and "`linear.x` -> `I1`" in cert
    assert "## Transport assumption" in cert
    assert "| `sys_link_1` | `/mid` | `/a`: `O1` -> `linear.x` | `/b`: `linear.x` -> `I1` |" in cert
    v = names["sys_system.v"].decode()
    assert "Require RosgenNode.a.\nRequire RosgenNode.b." in v
    assert "Theorem sys_link_1 : link_1_holds." in v and "Theorem sys_link_2 : link_2_holds." in v
    assert "RosgenNode.a.a_ddc RosgenNode.b.b_ddc link_2_ok" in v
    # the chain's theorem is System.chain_runs over the nodes' runs, not a conjunction of its links
    assert "Definition chain_1_nodes : list cnode := [node_0; node_1]." in v
    assert "Theorem sys_chain_1 : chain_holds chain_1_nodes chain_1_links chain_1_outs.\nProof.\n  apply chain_runs." in v
    assert "Theorem sys_system : sys_links /\\ sys_chains." in v
    assert "Definition chain_1_path : list nat := [0]." in v
    assert "Theorem sys_chain_1_composed :\n  chain_composed chain_1_nodes " in v
    assert "  apply (chain_run_value chain_1_nodes chain_1_links chain_1_outs).\n  - exact sys_chain_1." in v
    assert "theorem `sys_chain_1`, through links `sys_link_1`, `sys_link_2`; composed back to the external " in cert
    assert "`sys_chain_1_composed`" in cert
    assert "`System.chain_runs`" in cert and "`System.transported`" in cert
    graph = json.loads(names["sys.system.json"])
    assert graph["chains"] == [[{"node": "/a", "from": "/src", "to": "/mid"}, {"node": "/b", "from": "/mid", "to": "/out"}]]
    assert b'<node pkg="a" type="a" name="a"' in names["sys.launch"]
    # two node entries (each with its compiled module) and the system's proof
    assert len(entries(cache)) == 3 and all(entry_valid(e, e.name) for e in entries(cache))
    assert sorted(p.name for e in entries(cache) for p in (e / "coq").glob("*.vo")) == ["a.vo", "b.vo"]


def test_warm_run_all_hits(cold, tmp_path, capsys):
    p, cache, out, _ = cold
    stamps = {e.name: (e / ENTRY).stat().st_mtime_ns for e in entries(cache)}
    code = cli.main(["system", "generate", str(p), "-o", str(tmp_path / "out"), "--cache", str(cache), "-j", "2"])
    o, err = capsys.readouterr()
    assert code == 0, err
    assert "2 nodes (2 from the cache, 0 proved)" in o
    assert tree(tmp_path / "out") == tree(out)
    assert {e.name: (e / ENTRY).stat().st_mtime_ns for e in entries(cache)} == stamps


def test_one_node_changed(cold, tmp_path):
    p, cache, out, _ = cold
    src = tmp_path / "src"
    src.mkdir()
    for f in ("a.yaml", "b.yaml", "system.yaml"):
        (src / f).write_bytes((p.parent / f).read_bytes())
    # b's model changes (a comment: its bytes, hence its key)
    (src / "b.yaml").write_text("# changed\n" + (src / "b.yaml").read_text())
    res = generate_system(src / "system.yaml", tmp_path / "out", jobs=2, cache=cache)
    assert [(n.folder, n.cached) for n in res.nodes] == [("a", True), ("b", False)]
    # b's module is the same (coqc writes the same .vo for the same .v):
    # the system's proof, keyed by the modules, is a cache hit
    assert res.proof_cached
    assert len(entries(cache)) == 4   # b's new entry
    assert (tmp_path / "out" / "sys_system.v").read_bytes() == (out / "sys_system.v").read_bytes()
    # b's period changes: b proved again to another module, the system's
    # proof redone; a still from the cache
    (src / "b.yaml").write_text((src / "b.yaml").read_text().replace("period_ms: 20", "period_ms: 25"))
    res = generate_system(src / "system.yaml", tmp_path / "out2", jobs=2, cache=cache)
    assert [(n.folder, n.cached) for n in res.nodes] == [("a", True), ("b", False)]
    assert not res.proof_cached
    assert len(entries(cache)) == 6   # b's and the system proof's new entries


def test_corrupted_and_partial_entries_are_not_trusted(cold, tmp_path):
    p, cache, out, first = cold
    c2 = tmp_path / "cache"
    import shutil

    shutil.copytree(cache, c2)
    by_node = {n.folder: c2 / n.key for n in first.nodes}
    # a: one file's bytes changed (a disk error, a hand edit)
    glue = by_node["a"] / "files" / "a_glue.c"
    glue.write_text(glue.read_text() + "\n/* tampered */\n")
    assert not entry_valid(by_node["a"], by_node["a"].name)
    # b: the entry of a run killed before it wrote entry.json
    (by_node["b"] / ENTRY).unlink()
    assert not entry_valid(by_node["b"], by_node["b"].name)
    # and the temporary folder of a run that is gone (its lock is free)
    dead = c2 / f".tmp-{2**22 + 1}-x"
    (dead / "files").mkdir(parents=True)
    (dead / ".lock").write_text("")
    res = generate_system(p, tmp_path / "out", jobs=2, cache=c2)
    assert [(n.folder, n.cached) for n in res.nodes] == [("a", False), ("b", False)]
    assert tree(tmp_path / "out") == tree(out)
    assert not dead.exists()
    assert all(entry_valid(e, e.name) for e in entries(c2))


def test_killed_run_leaves_nothing_trusted(cold, tmp_path):
    p, cache, out, _ = cold
    c3 = tmp_path / "cache"
    c3.mkdir()
    target = tmp_path / "out"
    proc = subprocess.Popen([sys.executable, "-m", "pyrosgen", "system", "generate", str(p), "-o", str(target),
                             "--cache", str(c3), "-j", "2", "-q"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
    try:
        # kill it while a node is being proved (its folder in the run's
        # staging area exists: entries are written after the run's coqchk)
        def proving() -> bool:
            return (any(x.name.startswith(".tmp-") for x in c3.iterdir())
                    or any(tmp_path.glob(".pyrosgen-system-*/.pending/*")))

        deadline = time.monotonic() + 120
        while time.monotonic() < deadline and not proving():
            time.sleep(0.05)
        assert proving(), "no node started"
        time.sleep(1.0)
        os.killpg(proc.pid, signal.SIGKILL)
    finally:
        proc.wait(timeout=60)
    assert proc.returncode == -signal.SIGKILL
    # nothing in OUT, and no entry a later run would trust that is not complete
    assert not target.exists()
    for e in entries(c3):
        assert entry_valid(e, e.name)   # only completed entries were renamed into place
    res = generate_system(p, target, jobs=2, cache=c3)
    assert tree(target) == tree(out)
    assert not any(x.name.startswith(".tmp-") for x in c3.iterdir())
    assert res.hits + sum(1 for n in res.nodes if not n.cached) == 2


def test_failure_writes_nothing(tmp_path, capsys):
    src = tmp_path / "src"
    src.mkdir()
    p = chain(src)
    out = tmp_path / "out"
    out.write_text("a file, not a folder")
    code = cli.main(["system", "generate", str(p), "-o", str(out), "--no-cache", "-q"])
    _, err = capsys.readouterr()
    assert code == 1 and "exists and is not a directory" in err
    assert out.read_text() == "a file, not a folder"
    # an invalid system: exit 1, OUT not created
    (src / "system.yaml").write_text((src / "system.yaml").read_text().replace("/out", "/nope"))
    code = cli.main(["system", "generate", str(p), "-o", str(tmp_path / "o2"), "--no-cache", "-q"])
    _, err = capsys.readouterr()
    assert code == 1 and "[rule 10.5]" in err
    assert not (tmp_path / "o2").exists()
    assert [x.name for x in tmp_path.iterdir() if x.name.startswith(".pyrosgen")] == []


@pytest.mark.parametrize("mutant", ["crossed", "remap"])
def test_system_proof_refuses_wrong_wiring(cold, tmp_path, mutant):
    """The system's Coq file cannot prove a wrong link: two relations
    crossed between the nodes, or a remapping to the wrong topic (the
    checks would refuse both; here they are forced into the .v)."""
    from dataclasses import replace

    from pyrosgen.proof.coqdriver import CoqError
    from pyrosgen.system.checks import check_system
    from pyrosgen.system.coqsystem import prove_system
    from pyrosgen.system.model import load_system

    p, cache, out, first = cold
    sysm = load_system(p)
    graph = check_system(sysm)
    vo = {n.name: cache / n.key / "coq" / f"{n.name}.vo" for n in first.nodes}
    # the right wiring is proved
    text, thms = prove_system(sysm, graph, vo, tmp_path / "ok")
    assert thms == ["sys_system", "sys_target", "sys_link_1", "sys_link_2", "sys_chain_1", "sys_chain_1_composed"]
    l1, l2 = graph.links
    if mutant == "crossed":
        graph.links = [replace(l1, inp=l2.inp), replace(l2, inp=l1.inp)]
    else:
        sysm.nodes[1].remap = {"/mid": "/elsewhere"}
    with pytest.raises(CoqError) as exc:
        prove_system(sysm, graph, vo, tmp_path / "bad")
    assert exc.value.exit_code == 2
    # refused where a link's facts are decided: link_ok computes false
    assert 'Unable to unify "true" with "false"' in str(exc.value)


@pytest.mark.parametrize("tamper", ["order", "link", "out", "drop"])
def test_system_proof_refuses_tampered_chain(cold, tmp_path, monkeypatch, tamper):
    """The chain's theorem is proved by System.chain_runs from the chain as
    the certificate lists it: the nodes in another order, a link moved to
    a pair of nodes it does not join, an output relation of another node,
    or the chain's theorem stated of a weaker chain while the system
    theorem claims the real one: Coq refuses each."""
    from pyrosgen.proof.coqdriver import CoqError
    from pyrosgen.system import coqsystem
    from pyrosgen.system.checks import check_system
    from pyrosgen.system.model import load_system

    p, cache, out, first = cold
    sysm = load_system(p)
    graph = check_system(sysm)
    vo = {n.name: cache / n.key / "coq" / f"{n.name}.vo" for n in first.nodes}
    good = coqsystem.render_system_file(sysm, graph)
    edits = {
        "order": ("[node_0; node_1].", "[node_1; node_0]."),
        "link": ("[link_1_at 0; link_2_at 0]", "[link_1_at 1; link_2_at 0]"),
        "out": ("exists node_1; split; [reflexivity|exact chain_1_out_1_ok]",
                "exists node_0; split; [reflexivity|exact chain_1_out_1_ok]"),
        # a weaker chain theorem (no link, no output), proved: the system theorem no longer follows
        "drop": (good[good.index("Theorem sys_chain_1 :"):good.index("Qed.", good.index("Theorem sys_chain_1 :")) + 4],
                 "Theorem sys_chain_1 : chain_holds chain_1_nodes [] [].\nProof.\n  apply chain_runs. split; [|split].\n"
                 "  - constructor; [exact RosgenNode.a.a_ddc|]. constructor; [exact RosgenNode.b.b_ddc|]. constructor.\n"
                 "  - constructor.\n  - constructor.\nQed."),
    }
    old, new = edits[tamper]
    assert old in good
    monkeypatch.setattr(coqsystem, "render_system_file", lambda s, g: good.replace(old, new, 1))
    with pytest.raises(CoqError) as exc:
        coqsystem.prove_system(sysm, graph, vo, tmp_path / "bad")
    assert exc.value.exit_code == 2


COMPOSED = """From Coq Require Import String List Lia.
From ROSGen Require Import NodeModel System.
Require RosgenNode.sys_system.
Import ListNotations.
Local Open Scope string_scope.

Definition pick : nat -> clink := path_pick RosgenNode.sys_system.chain_1_links [0].
Definition co : cout := hd (mkcout (mktopic "" "" "" Publish "" 0) (mkoutrel "" "" [])) RosgenNode.sys_system.chain_1_outs.

(* the system's chain theorem, composed here through the chain: /b's input I1 at every cycle is /a's output O1
   at the delivered cycle, and /b publishes on /out what its controller computed *)
Definition composed_here :=
  chain_run_value _ _ _ co pick RosgenNode.sys_system.sys_chain_1 (or_introl eq_refl)
    (fun l H => match l return (S l < 2)%nat -> In (pick l) RosgenNode.sys_system.chain_1_links /\\ cl_from (pick l) = l with
                | O => fun _ => conj (or_introl eq_refl) eq_refl
                | S l' => fun H => ltac:(exfalso; lia)
                end H).
(* and the system's file proves the same composition itself *)
Definition same : chain_composed RosgenNode.sys_system.chain_1_nodes co pick := RosgenNode.sys_system.sys_chain_1_composed.
Check composed_here.
Print Assumptions composed_here.
Print Assumptions same.
"""


def test_chain_theorem_composes(cold, tmp_path, repo_root):
    """The system's chain theorem is a System.chain_holds that
    System.chain_run_value composes along the chain (it would not typecheck
    if sys_chain_1 were the conjunction of its links, or missing), and the
    system's file proves that composition as sys_chain_1_composed."""
    from pyrosgen.system.checks import check_system
    from pyrosgen.system.coqsystem import prove_system
    from pyrosgen.system.model import load_system

    p, cache, out, first = cold
    sysm = load_system(p)
    graph = check_system(sysm)
    vo = {n.name: cache / n.key / "coq" / f"{n.name}.vo" for n in first.nodes}
    prove_system(sysm, graph, vo, tmp_path / "ok")
    coq = tmp_path / "ok" / "coq"
    (coq / "Composed.v").write_text(COMPOSED)
    r = subprocess.run(["coqc", "-R", str(repo_root / "coq/theories"), "ROSGen", "-R", str(coq), "RosgenNode",
                        str(coq / "Composed.v")], capture_output=True, text=True, cwd=coq, timeout=600)
    assert r.returncode == 0, r.stderr + r.stdout
    assert r.stdout.splitlines() == ["composed_here", "     : chain_composed sys_system.chain_1_nodes co pick",
                                     "Closed under the global context", "Closed under the global context"], r.stdout


def test_system_verify(cold, tmp_path, capsys):
    """``pyrosgen system verify``: the folder as generated verifies; a
    tampered system .v (an extra line) and a tampered node file fail,
    each named."""
    import shutil

    p, cache, out, _ = cold
    code = cli.main(["system", "verify", str(out), "--system", str(p), "-j", "2", "-q"])
    o, err = capsys.readouterr()
    assert code == 0, o + err
    assert "verifies (system sys)" in o
    assert "ok      system proof: 6 theorems (sys_system, sys_target, sys_link_1, ...): Closed under the global context" in o
    bad = tmp_path / "bad"
    shutil.copytree(out, bad)
    v = bad / "sys_system.v"
    v.write_text(v.read_text() + "Axiom cheat : False.\n")
    glue = bad / "b" / "b_glue.c"
    glue.write_text(glue.read_text().replace("Ctl_Y", "Ctl_Y ", 1))
    code = cli.main(["system", "verify", str(bad), "--system", str(p), "-j", "2", "-q"])
    o, err = capsys.readouterr()
    assert code == 1
    assert "FAIL    sys_system.v: differs from the one rendered" in err
    assert re.search(r"FAIL    node b: ", err) and re.search(r"ok      node a: ", err)
    assert "FAIL    system proof: not run" in err

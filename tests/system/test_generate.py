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
    assert "Theorem sys_chain_1 : link_1_holds /\\ link_2_holds." in v
    assert "theorem `sys_chain_1`: links `sys_link_1`, `sys_link_2`" in cert
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
    assert thms == ["sys_system", "sys_link_1", "sys_link_2"]
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
    assert "ok      system proof: 3 theorems (sys_system, sys_link_1, sys_link_2): Closed under the global context" in o
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

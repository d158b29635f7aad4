"""Systems for the target ROS 2 (``--ros2``, DESIGN.md section 10):
every node read with ROS 2's message definitions (rule 4.17, reported in
the node's file), rule 10.11 (QoS compatibility across a link: every
combination of reliability and of durability with its verdict), custom
messages checked (rule 10.10), the cache key naming the target (a ROS 1 and a ROS 2
run never share an entry), and ``system verify --ros2``."""

from __future__ import annotations

import json
import re

import pytest

from pyrosgen import cli
from pyrosgen.system.checks import check_system, qos_problems
from pyrosgen.system.generate import generate_system, node_key
from pyrosgen.frontend.model import Qos
from pyrosgen.system.model import load_system

from .sysfiles import TWIST, VEC3, chain, node_model, system_file

pytestmark = pytest.mark.ros2

DIAG = re.compile(r"^(?P<file>.+?):(?P<line>\d+):(?P<col>\d+): error: (?P<msg>.+) \[rule (?P<rule>[0-9.]+)\]$")

RELIABILITY = [  # (publisher, subscriber, delivered)
    ("reliable", "reliable", True),
    ("reliable", "best_effort", True),
    ("best_effort", "best_effort", True),
    ("best_effort", "reliable", False),
]
DURABILITY = [
    ("volatile", "volatile", True),
    ("transient_local", "volatile", True),
    ("transient_local", "transient_local", True),
    ("volatile", "transient_local", False),
]


def run(capsys, *argv):
    code = cli.main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def qos_chain(folder, pub_qos, sub_qos):
    """The two-node chain of sysfiles with ``/mid``'s QoS on each side."""
    node_model(folder, "a", subs=[("/src", TWIST, ["linear.x"], None)], pubs=[("/mid", TWIST, ["linear.x"])],
               qos={"/mid": pub_qos})
    node_model(folder, "b", subs=[("/mid", TWIST, ["linear.x"], None)], pubs=[("/out", VEC3, ["x"])],
               qos={"/mid": sub_qos})
    return system_file(folder, [{"model": "a.yaml"}, {"model": "b.yaml"}], inputs=["/src"], outputs=["/out"])


@pytest.mark.parametrize("rel", RELIABILITY, ids=lambda r: f"{r[0]}-pub-{r[1]}-sub")
@pytest.mark.parametrize("dur", DURABILITY, ids=lambda d: f"{d[0]}-pub-{d[1]}-sub")
def test_qos_compatibility(tmp_path, capsys, rel, dur):
    """Rule 10.11: a reliable subscription of a best_effort publisher and a
    transient_local subscription of a volatile publisher deliver nothing
    (each an error, at the subscriber's entry of the system file, naming
    both node files' lines); every other combination is accepted.  The
    target ROS 1 ignores QoS: the same system checks for it."""
    (prel, srel, rel_ok), (pdur, sdur, dur_ok) = rel, dur
    p = qos_chain(tmp_path, {"reliability": prel, "durability": pdur}, {"reliability": srel, "durability": sdur})
    assert len(qos_problems(Qos(prel, pdur), Qos(srel, sdur))) == (not rel_ok) + (not dur_ok)
    code, out, err = run(capsys, "system", "check", str(p), "--ros2")
    if rel_ok and dur_ok:
        assert code == 0, err
        assert out.startswith(f"{p}: ok: system sys (target ros2), 2 nodes")
    else:
        assert code == 1 and out == "" and "Traceback" not in err
        diags = [DIAG.match(ln) for ln in err.splitlines()]
        assert all(diags), err
        assert {d["rule"] for d in diags} == {"10.11"}
        entry = p.read_text().splitlines().index("- model: b.yaml") + 1
        assert {(d["file"], int(d["line"]), int(d["col"])) for d in diags} == {(str(p), entry, 10)}
        text = " ".join(d["msg"] for d in diags)
        b_line = next(i for i, ln in enumerate((tmp_path / "b.yaml").read_text().splitlines(), 1) if "/mid" in ln)
        assert f"b.yaml:{b_line}" in text and "node '/a' publishes it with" in text
        assert ("a reliable subscription does not match a best_effort publisher" in text) == (not rel_ok)
        assert ("a transient_local subscription does not match a volatile publisher" in text) == (not dur_ok)
        assert len(diags) == (not rel_ok) + (not dur_ok)
    # ROS 1: no QoS (rule 4.18 warns that it is ignored); no rule 10.11
    code, out, err = run(capsys, "system", "check", str(p))
    assert code == 0 and "10.11" not in err, err


@pytest.mark.parametrize("pub,sub,ok", [("sensor_data", "default", False), ("default", "sensor_data", True),
                                        ("sensor_data", "sensor_data", True), ("default", "default", True)])
def test_qos_profiles(tmp_path, ok, pub, sub):
    """The profiles resolve as rule 4.18 says (sensor_data: best_effort,
    volatile; default: reliable, volatile) before rule 10.11 compares them."""
    from pyrosgen.errors import InvalidNodeModel

    p = qos_chain(tmp_path, pub, sub)
    sysm = load_system(p, "ros2")
    if ok:
        assert len(check_system(sysm).links) == 1
    else:
        with pytest.raises(InvalidNodeModel) as exc:
            check_system(sysm)
        assert [d.rule for d in exc.value.diagnostics] == ["10.11"]


def test_ros2_reading_reported_in_the_node_file(tmp_path, capsys):
    """A node that ROS 1 accepts and ROS 2 refuses (std_msgs/Header's seq)
    is reported under rule 4.17 at its own file's place, after the system
    file's line naming the entry."""
    p = chain(tmp_path)
    a = tmp_path / "a.yaml"
    text = a.read_text().replace("type: geometry_msgs/Twist\n  queue_size: 1\n- name: /mid",
                                 "type: geometry_msgs/TwistStamped\n  queue_size: 1\n- name: /mid", 1)
    text = text.replace("field: linear.x\n    input: I1", "field: header.seq\n    input: I1", 1)
    text = text.replace("I1: float64", "I1: uint32", 1)
    a.write_text(text)
    assert run(capsys, "system", "check", str(p))[0] == 0
    code, out, err = run(capsys, "system", "check", str(p), "--ros2")
    assert code == 1 and "Traceback" not in err, err
    lines = err.splitlines()
    assert re.match(rf"^{re.escape(str(p))}:\d+:\d+: error: nodes\[0\]\.model: node model 'a.yaml' is invalid "
                    r"for the target ros2 \(its problems follow\) \[rule 10.2\]$", lines[0]), lines
    seq = next(i for i, ln in enumerate(text.splitlines(), 1) if "header.seq" in ln)
    assert any(ln.startswith(f"{a}:{seq}:") and ln.endswith("[rule 4.17]") and "target ros2" in ln
               for ln in lines[1:]), lines


def test_custom_messages_checked_for_ros2(tmp_path, capsys):
    """A ROS 2 system takes nodes with custom messages (rule 10.10: built
    by each node's ``build --ros2``, one interface package in the
    workspace), and two definitions of one type are still refused."""
    from .test_custom_messages import system

    p = system(tmp_path / "same")
    code, out, err = run(capsys, "system", "check", str(p), "--ros2")
    assert code == 0, err
    p = system(tmp_path / "other", level_b="float64 value\nfloat64 extra\n")
    code, out, err = run(capsys, "system", "check", str(p), "--ros2")
    assert code == 1 and "Traceback" not in err
    assert "defines the message 'k6_msgs/Level'" in err and "[rule 10.10]" in err, err


@pytest.fixture(scope="module")
def two_targets(tmp_path_factory):
    """The two-node chain generated for ROS 1, then for ROS 2 into the
    same cache, then for ROS 2 again."""
    root = tmp_path_factory.mktemp("targets")
    p = chain(root)
    cache = root / "cache"
    r1 = generate_system(p, root / "out1", jobs=2, cache=cache)
    r2 = generate_system(p, root / "out2", jobs=2, cache=cache, target="ros2")
    r3 = generate_system(p, root / "out3", jobs=2, cache=cache, target="ros2")
    return p, cache, (r1, r2, r3), root


def test_cache_key_names_the_target(two_targets):
    p, cache, (r1, r2, r3), root = two_targets
    s1, s2 = load_system(p), load_system(p, "ros2")
    for a, b in zip(s1.nodes, s2.nodes):
        assert node_key(a, "ros1") != node_key(b, "ros2")
        assert node_key(a, "ros1") == node_key(b, "ros1")   # the key is the target's, not the reading's
    assert [n.cached for n in r1.nodes] == [False, False]
    assert [n.cached for n in r2.nodes] == [False, False]  # no ROS 1 entry is taken for ROS 2
    assert {n.key for n in r1.nodes}.isdisjoint({n.key for n in r2.nodes})
    assert [n.cached for n in r3.nodes] == [True, True] and r3.proof_cached
    assert [n.key for n in r3.nodes] == [n.key for n in r2.nodes]
    for n in r2.nodes:
        v = (root / "out2" / n.folder / f"{n.name}.v").read_text()
        assert "Definition target : Environment.target := Environment.Ros2." in v
        v1 = (root / "out1" / n.folder / f"{n.name}.v").read_text()
        assert "Definition target : Environment.target := Environment.Ros1." in v1


def test_ros2_system_files_name_the_target(two_targets):
    p, cache, rs, root = two_targets
    out = root / "out2"
    assert rs[1].files == ["sys_system.v", "sys.certificate.md", "sys.system.json", "sys.launch.xml"]
    assert rs[0].files == ["sys_system.v", "sys.certificate.md", "sys.system.json", "sys.launch"]
    v = (out / "sys_system.v").read_text()
    assert "Definition system_target : Environment.target := Environment.Ros2." in v
    assert "Theorem sys_target : sys_targets." in v
    assert "RosgenNode.a.target = system_target /\\ RosgenNode.b.target = system_target" in v
    assert "Environment.Ros1." in (root / "out1" / "sys_system.v").read_text()
    cert = (out / "sys.certificate.md").read_text()
    assert "Target: ROS 2 (Kilted, rcl, Fast DDS)" in cert and "`sys_target`" in cert
    assert "ROS 2 name resolution, as rcl applies" in cert and "rule 10.11" in cert
    assert "Target: ROS 1 (roscpp)" in (root / "out1" / "sys.certificate.md").read_text()
    assert json.loads((out / "sys.system.json").read_text())["target"] == "ros2"


def test_system_proof_refuses_a_node_of_the_other_target(two_targets, tmp_path):
    """The per-system .v of ROS 2 against a ROS 1 node's module: Coq
    refuses <system>_target (the module's target is Ros1)."""
    from pyrosgen.proof.coqdriver import CoqError
    from pyrosgen.system.coqsystem import prove_system

    p, cache, (r1, r2, r3), root = two_targets
    sysm = load_system(p, "ros2")
    graph = check_system(sysm)
    vo1 = {n.name: cache / n.key / "coq" / f"{n.name}.vo" for n in r1.nodes}
    vo2 = {n.name: cache / n.key / "coq" / f"{n.name}.vo" for n in r2.nodes}
    _, thms = prove_system(sysm, graph, vo2, tmp_path / "ok")
    assert thms[:2] == ["sys_system", "sys_target"]
    mixed = {"a": vo2["a"], "b": vo1["b"]}
    with pytest.raises(CoqError) as exc:
        prove_system(sysm, graph, mixed, tmp_path / "mixed")
    assert 'Unable to unify "system_target" with "b.target"' in str(exc.value)


def test_system_verify_ros2(two_targets, capsys):
    p, cache, rs, root = two_targets
    out = root / "out2"
    code, o, err = run(capsys, "system", "verify", str(out), "--system", str(p), "--ros2", "-j", "2", "-q")
    assert code == 0, o + err
    assert "ok      sys.launch.xml: as rendered from the system file" in o
    assert re.search(r"ok      system proof: 6 theorems \(sys_system, sys_target, sys_link_1, \.\.\.\)", o), o
    # verified for the wrong target: named
    code, o, err = run(capsys, "system", "verify", str(out), "--system", str(p), "-j", "2", "-q")
    assert code == 1
    assert f"FAIL    target: {out} was generated for the target ros2, not ros1: verify it with --ros2" in err


def test_missing_ros2_installation_is_exit_2(tmp_path):
    """``--ros2`` without a ROS 2 installation: exit 2 naming the command
    that installs it, before any node is read; nothing written."""
    import os
    import subprocess
    import sys

    p = chain(tmp_path)
    env = {**os.environ, "PYROSGEN_ROS2_PREFIX": str(tmp_path / "no-ros2")}
    for argv in (["check", str(p)], ["generate", str(p), "-o", str(tmp_path / "out"), "--no-cache", "-q"]):
        r = subprocess.run([sys.executable, "-m", "pyrosgen", "system", *argv, "--ros2"], env=env,
                           capture_output=True, text=True, timeout=120)
        assert r.returncode == 2, r.stderr
        assert "make ros2-deps" in r.stderr and "Traceback" not in r.stderr
    assert not (tmp_path / "out").exists()


def test_diagram_ros2(tmp_path, capsys):
    p = qos_chain(tmp_path, "sensor_data", "sensor_data")
    code, out, err = run(capsys, "system", "diagram", str(p), "-o", str(tmp_path / "g.dot"), "--ros2")
    assert code == 0, err
    dot = (tmp_path / "g.dot").read_text()
    assert "/mid" in dot and "digraph" in dot
    # refused for ROS 2 as check refuses it
    p = qos_chain(tmp_path, "sensor_data", "default")
    code, out, err = run(capsys, "system", "diagram", str(p), "-o", str(tmp_path / "h.dot"), "--ros2")
    assert code == 1 and "[rule 10.11]" in err and not (tmp_path / "h.dot").exists()

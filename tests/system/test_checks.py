"""``pyrosgen system check``: the system model and the rules across nodes
(DESIGN.md rules 10.1 to 10.9), each with file:line:col and its rule."""

from __future__ import annotations

import re
import subprocess
import sys

import pytest
import yaml

from pyrosgen import cli
from pyrosgen.system.checks import check_system
from pyrosgen.system.model import MAX_NODES, load_system
from pyrosgen.system.names import resolve

from .sysfiles import TWIST, VEC3, chain, node_model, system_file

DIAG = re.compile(r"^(?P<file>.+?):(?P<line>\d+):(?P<col>\d+): error: (?P<msg>.+) \[rule (?P<rule>[0-9.]+)\]$")


def run(capsys, *argv):
    code = cli.main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def errors(capsys, path):
    """The diagnostics of ``system check path`` (exit 1 required), as
    (file, line, col, message, rule)."""
    code, out, err = run(capsys, "system", "check", str(path))
    assert code == 1, (out, err)
    assert out == ""
    assert "Traceback" not in err
    found = []
    for line in err.splitlines():
        m = DIAG.match(line)
        assert m, line
        found.append((m["file"], int(m["line"]), int(m["col"]), m["msg"], m["rule"]))
    return found


def line_of(path, text):
    for i, ln in enumerate(path.read_text().splitlines(), 1):
        if text in ln:
            return i
    raise AssertionError(text)


def test_chain_ok(tmp_path, capsys):
    p = chain(tmp_path)
    code, out, err = run(capsys, "system", "check", str(p))
    assert code == 0, err
    assert out == f"{p}: ok: system sys, 2 nodes, 3 topics, 2 links, 1 chain from an external input to an external output\n"
    g = check_system(load_system(p))
    assert [(ln.topic, ln.out.output_source, ln.inp.input_target) for ln in g.links] == [
        ("/mid", "O1", "I1"), ("/mid", "O2", "I2")]
    assert [[(h.src, h.node.full_name, h.dst) for h in c.hops] for c in g.chains] == [
        [("/src", "/a", "/mid"), ("/mid", "/b", "/out")]]


def test_example_chain(repo_root):
    g = check_system(load_system(repo_root / "examples/system_chain/system.yaml"))
    names = {sn.full_name: sn for sn in g.system.nodes}
    assert sorted(names) == ["/diff_drive", "/safety/laser_guard", "/velocity_mux"]
    # relative cmd_vel in /safety; the mux's /nav/cmd_vel remapped onto it
    assert names["/safety/laser_guard"].graph_name("cmd_vel") == "/safety/cmd_vel"
    assert names["/velocity_mux"].graph_name("/nav/cmd_vel") == "/safety/cmd_vel"
    chains = [[h.node.full_name for h in c.hops] for c in g.chains]
    assert chains == [["/safety/laser_guard", "/velocity_mux", "/diff_drive"], ["/velocity_mux", "/diff_drive"]]
    assert {(ln.pub.full_name, ln.out.output_source, ln.sub.full_name, ln.inp.input_target) for ln in g.links} == {
        ("/safety/laser_guard", "Vx", "/velocity_mux", "NVx"), ("/safety/laser_guard", "Wz", "/velocity_mux", "NWz"),
        ("/velocity_mux", "Vx", "/diff_drive", "Vx"), ("/velocity_mux", "Wz", "/diff_drive", "Wz")}


def test_resolution_rules():
    assert resolve("/", "scan") == "/scan"
    assert resolve("/robot", "scan") == "/robot/scan"
    assert resolve("/robot", "laser/scan") == "/robot/laser/scan"
    assert resolve("/robot", "/scan") == "/scan"


def test_unfed_subscription(tmp_path, capsys):
    node_model(tmp_path, "a", subs=[("/src", TWIST, ["linear.x"], None)], pubs=[("/out", TWIST, ["linear.x"])])
    p = system_file(tmp_path, [{"model": "a.yaml"}], inputs=[], outputs=["/out"])
    errs = errors(capsys, p)
    assert [(e[1], e[4]) for e in errs] == [(line_of(p, "a.yaml"), "10.5")]
    assert "subscribes to '/src'" in errs[0][3] and "not an external input" in errs[0][3]


def test_external_output_unpublished_and_input_published(tmp_path, capsys):
    chain(tmp_path)
    p = system_file(tmp_path, [{"model": "a.yaml"}, {"model": "b.yaml"}], inputs=["/src", "/mid"],
                    outputs=["/out", "/nowhere"])
    errs = errors(capsys, p)
    assert sorted((e[1], e[4]) for e in errs) == sorted([(line_of(p, "- /mid"), "10.5"),
                                                          (line_of(p, "/nowhere"), "10.5")])


def test_two_publishers(tmp_path, capsys):
    node_model(tmp_path, "a", subs=[("/src", TWIST, ["linear.x"], None)], pubs=[("/out", TWIST, ["linear.x"])])
    node_model(tmp_path, "b", subs=[("/src", TWIST, ["linear.x"], None)], pubs=[("/out", TWIST, ["linear.x"])])
    p = system_file(tmp_path, [{"model": "a.yaml"}, {"model": "b.yaml"}], inputs=["/src"], outputs=["/out"])
    errs = errors(capsys, p)
    assert [(e[1], e[4]) for e in errs] == [(line_of(p, "b.yaml"), "10.6")]
    assert "published by node '/b'" in errs[0][3] and "and by node '/a'" in errs[0][3]
    # declared shared: accepted
    p = system_file(tmp_path, [{"model": "a.yaml"}, {"model": "b.yaml"}], inputs=["/src"], outputs=["/out"],
                    shared=["/out"])
    assert run(capsys, "system", "check", str(p))[0] == 0


def test_type_mismatch(tmp_path, capsys):
    node_model(tmp_path, "a", subs=[("/src", TWIST, ["linear.x"], None)], pubs=[("/mid", VEC3, ["x"])])
    node_model(tmp_path, "b", subs=[("/mid", TWIST, ["linear.x"], None)], pubs=[("/out", VEC3, ["x"])])
    p = system_file(tmp_path, [{"model": "a.yaml"}, {"model": "b.yaml"}], inputs=["/src"], outputs=["/out"])
    errs = errors(capsys, p)
    assert [(e[1], e[4]) for e in errs] == [(line_of(p, "b.yaml"), "10.7")]
    assert "as geometry_msgs/Twist" in errs[0][3] and "as geometry_msgs/Vector3" in errs[0][3]


def test_leaf_never_written(tmp_path, capsys):
    node_model(tmp_path, "a", subs=[("/src", TWIST, ["linear.x"], None)], pubs=[("/mid", TWIST, ["linear.x"])])
    node_model(tmp_path, "b", subs=[("/mid", TWIST, ["linear.x", "angular.z"], None)],
               pubs=[("/out", VEC3, ["x"])])
    p = system_file(tmp_path, [{"model": "a.yaml"}, {"model": "b.yaml"}], inputs=["/src"], outputs=["/out"])
    errs = errors(capsys, p)
    assert [(e[1], e[4]) for e in errs] == [(line_of(p, "b.yaml"), "10.8")]
    assert "input 'I2'" in errs[0][3] and "'angular.z'" in errs[0][3] and "never writes" in errs[0][3]


def test_timeout_shorter_than_period(tmp_path, capsys):
    node_model(tmp_path, "a", subs=[("/src", TWIST, ["linear.x"], None)], pubs=[("/mid", TWIST, ["linear.x"])],
               period_ms=100)
    node_model(tmp_path, "b", subs=[("/mid", TWIST, ["linear.x"], 50)], pubs=[("/out", VEC3, ["x"])])
    p = system_file(tmp_path, [{"model": "a.yaml"}, {"model": "b.yaml"}], inputs=["/src"], outputs=["/out"])
    errs = errors(capsys, p)
    assert [(e[1], e[4]) for e in errs] == [(line_of(p, "b.yaml"), "10.9")]
    assert "(50 ms" in errs[0][3] and "(100 ms)" in errs[0][3]
    # a timeout of the period or longer is accepted
    node_model(tmp_path, "b", subs=[("/mid", TWIST, ["linear.x"], 100)], pubs=[("/out", VEC3, ["x"])])
    assert run(capsys, "system", "check", str(p))[0] == 0


def test_node_name_twice_and_listed_twice(tmp_path, capsys):
    chain(tmp_path)
    node_model(tmp_path / ".." / tmp_path.name, "a2", subs=[("/src", TWIST, ["linear.x"], None)],
               pubs=[("/mid2", TWIST, ["linear.x"])])
    p = system_file(tmp_path, [{"model": "a.yaml"}, {"model": "b.yaml"}, {"model": "a.yaml"},
                               {"model": "a2.yaml", "name": "b"}], inputs=["/src"], outputs=["/out"])
    errs = errors(capsys, p)
    rules = sorted((e[1], e[4]) for e in errs)
    assert rules == [(6, "10.3"), (7, "10.3")]
    msgs = " ".join(e[3] for e in errs)
    assert "is listed twice" in msgs and "node name '/b' is used twice" in msgs


def test_same_model_in_two_namespaces(tmp_path, capsys):
    chain(tmp_path)
    p = system_file(tmp_path, [{"model": "a.yaml", "namespace": "/left"}, {"model": "b.yaml"},
                               {"model": "a.yaml", "namespace": "/right", "remap": {"/mid": "/mid_r"}}],
                    inputs=["/src"], outputs=["/out"])
    # /mid_r has no subscriber: fine; /right/a and /left/a are distinct
    code, out, err = run(capsys, "system", "check", str(p))
    assert code == 0, err
    g = check_system(load_system(p))
    assert [sn.folder for sn in g.system.nodes] == ["left.a", "b", "right.a"]


def test_topics_collide_after_remap(tmp_path, capsys):
    node_model(tmp_path, "a", subs=[("/src", TWIST, ["linear.x"], None)],
               pubs=[("/x", TWIST, ["linear.x"]), ("/y", TWIST, ["linear.x"])])
    p = system_file(tmp_path, [{"model": "a.yaml", "remap": {"/x": "/y"}}], inputs=["/src"], outputs=["/y"])
    errs = errors(capsys, p)
    assert [(e[1], e[4]) for e in errs] == [(line_of(p, "a.yaml"), "10.3")]


@pytest.mark.parametrize("remap,kind", [({"/p": "/q", "/q": "/p"}, "a cycle"),
                                        ({"/p": "/q", "/q": "/r"}, "a chain")])
def test_remapping_cycle_or_chain(tmp_path, capsys, remap, kind):
    node_model(tmp_path, "a", subs=[("/src", TWIST, ["linear.x"], None)],
               pubs=[("/p", TWIST, ["linear.x"]), ("/q", TWIST, ["linear.x"])])
    p = system_file(tmp_path, [{"model": "a.yaml", "remap": remap}], inputs=["/src"], outputs=["/p", "/q"])
    errs = errors(capsys, p)
    assert errs and all(e[4] == "10.4" for e in errs)
    assert kind in errs[0][3]


def test_remapping_of_no_topic(tmp_path, capsys):
    chain(tmp_path)
    p = system_file(tmp_path, [{"model": "a.yaml", "remap": {"/nope": "/x"}}, {"model": "b.yaml"}],
                    inputs=["/src"], outputs=["/out"])
    errs = errors(capsys, p)
    assert [(e[1], e[4]) for e in errs] == [(line_of(p, "/nope"), "10.4")]


def test_missing_node_file_and_bad_namespace(tmp_path, capsys):
    chain(tmp_path)
    p = system_file(tmp_path, [{"model": "nothere.yaml"}, {"model": "b.yaml", "namespace": "/bad name"},
                               {"model": "a.yaml", "namespace": "~priv"}], inputs=["/src"], outputs=["/out"])
    errs = errors(capsys, p)
    assert sorted((e[1], e[4]) for e in errs) == [(line_of(p, "nothere.yaml"), "10.2"),
                                                   (line_of(p, "/bad name"), "10.2"),
                                                   (line_of(p, "~priv"), "10.2")]
    assert "does not exist" in " ".join(e[3] for e in errs)


def test_invalid_node_model_reported_in_its_file(tmp_path, capsys):
    chain(tmp_path)
    (tmp_path / "a.yaml").write_text((tmp_path / "a.yaml").read_text().replace("period_ms: 20", "period_ms: -1"))
    p = tmp_path / "system.yaml"
    errs = errors(capsys, p)
    assert errs[0][0] == str(p) and errs[0][4] == "10.2"
    assert any(e[0] == str(tmp_path / "a.yaml") for e in errs[1:])


@pytest.mark.parametrize("n", [MAX_NODES + 1, 1000])
def test_too_many_nodes(tmp_path, capsys, n):
    chain(tmp_path)
    p = system_file(tmp_path, [{"model": "a.yaml", "name": f"n{i}"} for i in range(n)],
                    inputs=["/src"], outputs=["/out"])
    errs = errors(capsys, p)
    assert len(errs) == 1 and errs[0][4] == "10.1"
    assert f"{n} nodes; a system has at most {MAX_NODES}" in errs[0][3]


def test_shape_errors(tmp_path, capsys):
    p = tmp_path / "system.yaml"
    p.write_text(yaml.safe_dump({"system": {"name": "s"}, "nodes": "a.yaml", "external": [], "extra": 1}))
    errs = errors(capsys, p)
    assert {e[4] for e in errs} == {"10.1"}
    msgs = " ".join(e[3] for e in errs)
    assert "unknown key 'extra'" in msgs and "nodes: expected a list" in msgs and "external: expected a mapping" in msgs


def test_cli_subprocess_exit_codes(tmp_path):
    chain(tmp_path)
    p = system_file(tmp_path, [{"model": "missing.yaml"}], inputs=["/src"], outputs=["/out"])
    r = subprocess.run([sys.executable, "-m", "pyrosgen", "system", "check", str(p)], capture_output=True, text=True)
    assert r.returncode == 1
    assert r.stderr.startswith(f"{p}:") and "[rule 10.2]" in r.stderr and "Traceback" not in r.stderr


def test_two_models_one_node_name(tmp_path, capsys):
    chain(tmp_path)
    sub = tmp_path / "other"
    sub.mkdir()
    node_model(sub, "a", subs=[("/src", TWIST, ["linear.x"], None)], pubs=[("/side", TWIST, ["linear.x"])])
    p = system_file(tmp_path, [{"model": "a.yaml"}, {"model": "b.yaml"}, {"model": "other/a.yaml", "namespace": "/x"}],
                    inputs=["/src"], outputs=["/out"])
    errs = errors(capsys, p)
    assert [(e[1], e[4]) for e in errs] == [(line_of(p, "other/a.yaml"), "10.3")]
    assert "both name their node 'a'" in errs[0][3]

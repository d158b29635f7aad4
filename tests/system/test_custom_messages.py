"""Custom messages in a system (rule 10.10, DESIGN.md section 10): two
nodes whose ``msg_paths`` define the same ``pkg/Type`` must define it alike
(comments and blanks aside), else ``system check`` refuses at the second
node's entry; no custom message package may take a node's package name.
``system build`` writes one catkin package per custom message package
(``OUT/msgs/<pkg>``, ``message_generation``) shared by the nodes, linked
into ``OUT/src``, and ``catkin_make`` builds the workspace as it is (marked
``ros``)."""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import pytest

from pyrosgen import cli
from pyrosgen.system.checks import check_system, msg_definition
from pyrosgen.system.model import load_system

LEVEL = """\
# A level, from {who}
float64 value   # the level
uint8 KIND_A=1
string NAME=a # b
"""


def relay(folder: Path, name: str, src: tuple[str, str, str], dst: tuple[str, str, str], msgs: str) -> Path:
    """A node ``name`` with a block-diagram controller (Y = 2 X): ``src``
    and ``dst`` are (topic, type, field); ``msgs`` its msg_paths folder."""
    (folder / f"{name}.yaml").write_text(f"""\
node: {{name: {name}, period_ms: 20}}
controller:
  name: Ctl_{name}
  inputs: {{name: Ctl_{name}_U, fields: {{X: float64}}}}
  outputs: {{name: Ctl_{name}_Y, fields: {{Y: float64}}}}
  blocks:
    - {{name: twice, block: Gain, input: X, gain: 2.0}}
  outports: {{Y: twice}}
topics:
  - {{name: {src[0]}, direction: subscribe, type: {src[1]}, queue_size: 1}}
  - {{name: {dst[0]}, direction: publish, type: {dst[1]}, queue_size: 1}}
relations:
  inputs:  [{{topic: {src[0]}, field: {src[2]}, input: X}}]
  outputs: [{{output: Y, topic: {dst[0]}, field: {dst[2]}}}]
msg_paths: [{msgs}]
""")
    return folder / f"{name}.yaml"


def system(folder: Path, level_b: str | None = None) -> Path:
    """``k6a`` publishes /mid as ``k6_msgs/Level``, ``k6b`` reads it; each
    node has its own copy of the message (``level_b``: b's text)."""
    for who in ("a", "b"):
        d = folder / f"msg_{who}" / "k6_msgs" / "msg"
        d.mkdir(parents=True, exist_ok=True)
        (d / "Level.msg").write_text(LEVEL.format(who=who) if who == "a" or level_b is None else level_b)
    relay(folder, "k6a", ("/src", "geometry_msgs/Twist", "linear.x"), ("/mid", "k6_msgs/Level", "value"), "msg_a")
    relay(folder, "k6b", ("/mid", "k6_msgs/Level", "value"), ("/out", "geometry_msgs/Vector3", "x"), "msg_b")
    p = folder / "system.yaml"
    p.write_text("system: {name: levels}\nnodes:\n  - model: k6a.yaml\n  - model: k6b.yaml\n"
                 "external: {inputs: [/src], outputs: [/out]}\n")
    return p


def run(capsys, *argv):
    code = cli.main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def test_the_same_definition_with_other_comments_is_one_package(tmp_path):
    p = system(tmp_path)
    graph = check_system(load_system(p))
    assert [(ln.pub.model.name, ln.sub.model.name, ln.topic) for ln in graph.links] == [("k6a", "k6b", "/mid")]


def test_msg_definition_ignores_comments_and_blanks_only():
    a = msg_definition(LEVEL.format(who="a"))
    assert a == ("float64 value", "uint8 KIND_A = 1", "string NAME=a # b")
    assert msg_definition("float64   value\n\n# x\nuint8 KIND_A = 1 # y\nstring NAME=a # b\n") == a
    assert msg_definition(LEVEL.format(who="a").replace("float64", "float32")) != a
    assert msg_definition(LEVEL.format(who="a").replace("KIND_A=1", "KIND_A=2")) != a
    assert msg_definition(LEVEL.format(who="a").replace("NAME=a # b", "NAME=a")) != a


def test_two_definitions_of_one_type_are_refused(tmp_path, capsys):
    p = system(tmp_path, level_b="float64 value\nfloat64 extra\n")
    code, out, err = run(capsys, "system", "check", p)
    assert code == 1, err
    b_msg = tmp_path / "msg_b" / "k6_msgs" / "msg" / "Level.msg"
    a_msg = tmp_path / "msg_a" / "k6_msgs" / "msg" / "Level.msg"
    # at the second node's entry (line 4, its "model:" value)
    assert (f"{p}:4:12: error: nodes[1]: node '/k6b' defines the message 'k6_msgs/Level' ({b_msg}) otherwise "
            f"than node '/k6a' ({a_msg})") in err, err
    assert "[rule 10.10]" in err
    assert "Traceback" not in err


def test_a_message_package_named_like_a_node_is_refused(tmp_path, capsys):
    p = system(tmp_path)
    for who in ("a", "b"):
        shutil.move(tmp_path / f"msg_{who}" / "k6_msgs", tmp_path / f"msg_{who}" / "k6a")
    for f in ("k6a.yaml", "k6b.yaml"):
        (tmp_path / f).write_text((tmp_path / f).read_text().replace("k6_msgs/Level", "k6a/Level"))
    code, out, err = run(capsys, "system", "check", p)
    assert code == 1, err
    assert "the custom message package 'k6a' of node '/k6a'" in err and "[rule 10.10]" in err


@pytest.mark.ros
def test_system_build_writes_one_message_package_catkin_builds(tmp_path):
    from pyrosgen.system.generate import generate_system

    if shutil.which("catkin_make") is None:
        pytest.fail("catkin_make is not installed (make ros-deps)")
    p = system(tmp_path / "src")
    out = tmp_path / "out"
    res = generate_system(p, out, jobs=2, cache=tmp_path / "cache", build=True)
    assert "msgs" in res.files
    links = sorted(x.name for x in (out / "src").iterdir())
    assert links == ["k6_msgs", "k6a", "k6b"]
    assert (out / "src" / "k6_msgs").resolve() == (out / "msgs" / "k6_msgs").resolve()
    pkg = out / "msgs" / "k6_msgs"
    assert sorted(x.name for x in (pkg / "msg").iterdir()) == ["Level.msg"]
    assert "<build_depend>message_generation</build_depend>" in (pkg / "package.xml").read_text()
    assert "Level.msg" in (pkg / "CMakeLists.txt").read_text()
    for node in ("k6a", "k6b"):
        assert "k6_msgs" in (out / node / node / "package.xml").read_text()
    ws = tmp_path / "ws"
    ws.mkdir()
    (ws / "src").symlink_to(out / "src")
    r = subprocess.run(["catkin_make", "-C", str(ws), "-DPYTHON_EXECUTABLE=/usr/bin/python3"],
                       capture_output=True, text=True, timeout=900)
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
    assert (ws / "devel" / "include" / "k6_msgs" / "Level.h").is_file()
    for node in ("k6a", "k6b"):
        assert (ws / "devel" / "lib" / node / node).is_file()

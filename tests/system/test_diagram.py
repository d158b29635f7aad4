"""``pyrosgen system diagram``: the nodes, the topics between them, one
chain with its relations."""

from __future__ import annotations

import re

from pyrosgen import cli


def test_system_diagram_dot(repo_root, tmp_path, capsys):
    out = tmp_path / "sys.dot"
    assert cli.main(["system", "diagram", str(repo_root / "examples/system_chain/system.yaml"), "-o", str(out)]) == 0
    dot = out.read_text()
    nodes = re.findall(r"label=<<b>([^<]+)</b><br/><i>([a-z_]+)</i>", dot)
    assert nodes == [("/safety/laser_guard", "laser_guard"), ("/velocity_mux", "velocity_guard"),
                     ("/diff_drive", "diff_drive")]
    topics = re.findall(r"label=<(/[a-z_/]+)<br/>", dot)
    assert topics == ["/base/wheels", "/cmd_vel", "/safety/cmd_vel", "/scan", "/teleop/cmd_vel"]
    edges = re.findall(r"^  (\w+) -> (\w+) \[", dot, re.M)
    assert len(edges) == 7          # 3 publications, 4 subscriptions
    assert "label=<Vx" not in dot   # relations only on a chain


def test_system_diagram_chain(repo_root, tmp_path, capsys):
    out = tmp_path / "chain.dot"
    sysf = str(repo_root / "examples/system_chain/system.yaml")
    assert cli.main(["system", "diagram", sysf, "-o", str(out), "--chain", "2"]) == 0
    dot = out.read_text()
    assert "chain 2, /teleop/cmd_vel -&gt; /velocity_mux -&gt; /cmd_vel -&gt; /diff_drive -&gt; /base/wheels" in dot
    assert "label=<linear.x -&gt; TVx<br/>angular.z -&gt; TWz>" in dot
    assert "label=<Left -&gt; x<br/>Right -&gt; y>" in dot
    assert "NVx" not in dot         # the laser guard's link is not on chain 2
    code = cli.main(["system", "diagram", sysf, "-o", str(tmp_path / "x.dot"), "--chain", "3"])
    assert code == 1 and "the system has 2 chain(s)" in capsys.readouterr().err
    assert not (tmp_path / "x.dot").exists()

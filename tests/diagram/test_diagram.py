"""``pyrosgen diagram``: the graph drawn for LandShark and the multi-topic
example, escaping of model text, output formats, atomic writes, exit codes."""

from __future__ import annotations

import dataclasses
import os
import stat
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from pyrosgen import cli
from pyrosgen.diagram import dot_html, output_format, render_dot, write_atomic
from pyrosgen.errors import escape
from pyrosgen.frontend.model import ControllerField
from pyrosgen.frontend.validate import load_model

from support.diagram import KO_MODEL, LANDSHARK, MULTI, parse_with_dot

LANDSHARK_SUBS = [
    "/landshark/left_wheel_velocity",
    "/landshark/right_wheel_velocity",
    "/landshark/gps_velocity",
]
LANDSHARK_PUB = "/landshark_control/base_velocity"


def run(capsys, *argv):
    code = cli.main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def svg_texts(path: Path) -> list[str]:
    """Every text of an SVG file (which must be well-formed XML)."""
    root = ET.parse(path).getroot()
    return ["".join(el.itertext()) for el in root.iter("{http://www.w3.org/2000/svg}text")]


def leftovers(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.iterdir() if p.name.endswith(".tmp"))


# --------------------------------------------------------------------------
# The LandShark graph (paper Table 1, Figures 4 and 9)


@pytest.fixture(scope="module")
def landshark():
    return load_model(LANDSHARK)


@pytest.fixture(scope="module")
def landshark_graph(landshark):
    return parse_with_dot(render_dot(landshark))


def test_landshark_nodes(landshark_graph):
    g = landshark_graph
    assert set(g.nodes) == {
        "sub0", "sub1", "sub2", "cb0", "cb1", "cb2", "msg0", "msg1", "msg2",
        "ctrl_u", "step", "ctrl_y", "og0", "pub0",
    }
    for i, topic in enumerate(LANDSHARK_SUBS):
        c = topic.strip("/").replace("/", "_")
        assert g.nodes[f"sub{i}"] == [topic, "geometry_msgs/TwistStamped", "queue 1"]
        assert g.nodes[f"cb{i}"] == [f"{c}_callback"]
        assert g.nodes[f"msg{i}"] == ["struct geometry_msgs_TwistStamped", f"{c}_msg"]
    assert g.nodes["pub0"] == [LANDSHARK_PUB, "geometry_msgs/TwistStamped", "queue 1"]
    assert g.nodes["ctrl_u"] == [
        "Controller_U", "struct ExtU_Controller_T", "In1 : float64", "In2 : float64", "In3 : float64",
    ]
    assert g.nodes["ctrl_y"] == ["Controller_Y", "struct ExtY_Controller_T", "Out1 : float64"]
    assert "".join(g.nodes["step"]) == "Controller_step()"
    assert "".join(g.nodes["og0"]) == (
        "output_glue_landshark_control_base_velocity(&landshark_control_base_velocity_cmd)"
    )
    assert "".join(g.title) == "landshark_controller: period 20 ms (50 Hz)"


def test_landshark_clusters(landshark_graph):
    g = landshark_graph
    labels = {name: " ".join(t) for name, t in g.clusters.items()}
    assert labels == {
        "cluster_ros_subscribed": "ROS: subscribed topics",
        "cluster_glue_input": "glue (proved): callbacks, message globals, input_glue",
        "cluster_controller": "controller",
        "cluster_glue_output": "glue (proved): output_glue",
        "cluster_ros_published": "ROS: published topics",
    }
    assert g.cluster_nodes["cluster_ros_subscribed"] == {"sub0", "sub1", "sub2"}
    assert g.cluster_nodes["cluster_glue_input"] == {"cb0", "cb1", "cb2", "msg0", "msg1", "msg2"}
    assert g.cluster_nodes["cluster_controller"] == {"ctrl_u", "step", "ctrl_y"}
    assert g.cluster_nodes["cluster_glue_output"] == {"og0"}
    assert g.cluster_nodes["cluster_ros_published"] == {"pub0"}


def test_landshark_edges(landshark_graph):
    g = landshark_graph
    # 3 deliveries, 3 callback copies, 3 input relations, step in and out,
    # 1 output relation, 1 publication.
    assert len(g.edges) == 13
    inputs = g.edges_with_id("in_rel")
    assert len(inputs) == 3
    for i, e in enumerate(sorted(inputs, key=lambda e: e["id"])):
        assert (e["tail"], e["head"]) == (f"msg{i}", "ctrl_u")
        assert e["headport"].split(":")[0] == f"f{i}"  # In1, In2, In3 rows
        assert e["label"] == "twist.linear.x : float64"
    outputs = g.edges_with_id("out_rel")
    assert len(outputs) == 1
    (e,) = outputs
    assert (e["tail"], e["tailport"].split(":")[0], e["head"]) == ("ctrl_y", "f0", "og0")
    assert e["label"] == "twist.linear.x : float64"
    chain = {(e["tail"], e["head"]) for e in g.edges if not e["id"].startswith(("in_rel", "out_rel"))}
    assert chain == {
        ("sub0", "cb0"), ("sub1", "cb1"), ("sub2", "cb2"),
        ("cb0", "msg0"), ("cb1", "msg1"), ("cb2", "msg2"),
        ("ctrl_u", "step"), ("step", "ctrl_y"), ("og0", "pub0"),
    }
    copies = {e["tail"]: e["label"] for e in g.edges_with_id("copy_")}
    # each callback copies the one field the node reads (twist.linear.x), of the 9 TwistStamped carries
    assert copies == {"cb0": "1 field", "cb1": "1 field", "cb2": "1 field"}
    publish = g.edges_with_id("publish_")
    assert [e["label"] for e in publish] == ["ros_publish_landshark_control_base_velocity"]


def test_multi_edges_follow_relations():
    model = load_model(MULTI)
    g = parse_with_dot(render_dot(model))
    sub_index = {t.name: i for i, t in enumerate(model.subscribed)}
    pub_index = {t.name: i for i, t in enumerate(model.published)}
    u_rows = model.controller.inputs.names
    y_rows = model.controller.outputs.names
    got_in = sorted(
        (e["tail"], e["headport"].split(":")[0], e["label"]) for e in g.edges_with_id("in_rel")
    )
    # a direct relation (rule 4.16) comes from the callback, any other from
    # the topic's global
    want_in = sorted(
        (f"{'cb' if model.is_direct(r) else 'msg'}{sub_index[r.topic.name]}", f"f{u_rows.index(r.input_field)}",
         f"{r.path} : {r.path.prim}")
        for r in model.input_relations
    )
    assert got_in == want_in and len(got_in) == 11
    got_out = sorted(
        (e["tailport"].split(":")[0], e["head"], e["label"]) for e in g.edges_with_id("out_rel")
    )
    want_out = sorted(
        (f"f{y_rows.index(r.output_field)}", f"og{pub_index[r.topic.name]}", f"{r.path} : {r.path.prim}")
        for r in model.output_relations
    )
    assert got_out == want_out and len(got_out) == 9
    assert ("f2", "og1", "pose.covariance[35] : float64") not in got_out
    assert ("cb0", "f2", "pose.covariance[35] : float64") in got_in
    assert ("msg0", "f0", "pose.pose.position.x : float64") in got_in


def test_direct_relations_come_from_the_callback():
    """A direct relation (rule 4.16: an element of an untimed topic) is
    drawn from its callback, which copies it into the inputs; the others
    from the topic's global, which input_glue reads (a timed topic's
    elements too)."""
    model = load_model(Path(__file__).resolve().parents[1] / "generate" / "models" / "ok_direct.yaml")
    g = parse_with_dot(render_dot(model))
    got = sorted((e["tail"], e["label"]) for e in g.edges_with_id("in_rel"))
    assert got == sorted([
        ("cb0", "ranges : float32[4]"), ("msg0", "ranges (length) : uint32"),
        ("msg1", "pose.pose.position.x : float64"), ("cb0", "ranges[1] : float32"),
        ("cb1", "pose.covariance[3] : float64"), ("cb0", "header.frame_id[0] : uint8"),
        ("msg2", "ranges[2] : float32 stale: zero"), ("msg2", "ranges (length) : uint32 stale: zero"),
        ("msg3", "ranges[1] : float32")])
    # what each callback keeps in its global (the msg<i> edges above): /scan its
    # length and its stamp's sec and nsec (the output's source, rule 4.13),
    # /pose position.x, the timed topic with a timeout ranges[2] and the
    # length, the one with a derived input ranges[1]
    copies = {e["tail"]: e["label"] for e in g.edges_with_id("copy_")}
    assert copies == {"cb0": "3 fields", "cb1": "1 field", "cb2": "2 fields", "cb3": "1 field"}, copies


def test_dot_is_deterministic(tmp_path):
    first = render_dot(load_model(LANDSHARK))
    second = render_dot(load_model(LANDSHARK))
    assert first == second
    # Same model from another folder (same file name): same text.
    copy = tmp_path / LANDSHARK.name
    copy.write_bytes(LANDSHARK.read_bytes())
    assert render_dot(load_model(copy)) == first
    # Through the command line, byte for byte, twice.
    out1, out2 = tmp_path / "a.dot", tmp_path / "b.dot"
    assert cli.main(["diagram", str(LANDSHARK), "-o", str(out1)]) == 0
    assert cli.main(["diagram", str(copy), "-o", str(out2)]) == 0
    assert out1.read_bytes() == out2.read_bytes() == first.encode()
    assert first.startswith(
        "// generated from pyrosgen/templates/diagram.dot.j2 with input from landshark_controller.yaml\n"
    )


# --------------------------------------------------------------------------
# Output formats


def test_multi_svg_is_xml_with_every_topic(capsys, tmp_path):
    out = tmp_path / "multi.svg"
    code, stdout, err = run(capsys, "diagram", MULTI, "-o", out)
    assert code == 0, err
    assert err == ""
    assert stdout == f"{out}: svg diagram of node multi_node\n"
    texts = svg_texts(out)
    model = load_model(MULTI)
    assert len(model.topics) == 6
    for t in model.topics:
        assert t.name in texts, t.name
        assert t.msg_type in texts
    for r in model.input_relations:
        assert f"{r.path} : {r.path.prim}" in texts
    assert "Debug : float64" in texts  # unused outputs are drawn too
    assert leftovers(tmp_path) == []


@pytest.mark.parametrize(
    "name, fmt, magic",
    [("n.png", None, b"\x89PNG\r\n\x1a\n"), ("n.pdf", None, b"%PDF-"), ("n.PDF", None, b"%PDF-"),
     ("n.svg", None, b"<?xml"), ("n.out", "png", b"\x89PNG"), ("n.svg", "dot", b"// generated from")],
)
def test_formats(capsys, tmp_path, name, fmt, magic):
    out = tmp_path / name
    argv = ["diagram", LANDSHARK, "-o", out] + (["--format", fmt] if fmt else [])
    code, _, err = run(capsys, *argv)
    assert code == 0, err
    assert out.read_bytes().startswith(magic)
    assert leftovers(tmp_path) == []


def test_dot_format_is_the_rendered_text(tmp_path):
    out = tmp_path / "sub" / "dir" / "n.gv"
    out.parent.mkdir(parents=True)  # missing folders are not created (test_output_path.py)
    assert cli.main(["diagram", str(LANDSHARK), "-o", str(out)]) == 0
    assert out.read_text() == render_dot(load_model(LANDSHARK))


def test_output_format():
    assert output_format("a/b.SVG") == "svg"
    assert output_format("x.gv") == "dot"
    assert output_format("x.jpg", "pdf") == "pdf"
    with pytest.raises(ValueError, match="cannot tell the output format"):
        output_format("x.jpg")
    with pytest.raises(ValueError, match="cannot tell the output format"):
        output_format("noext")
    with pytest.raises(ValueError, match="unknown format"):
        output_format("x.svg", "gif")


# --------------------------------------------------------------------------
# Escaping of every text from the model

HOSTILE = [
    'q"uote',
    "a<b>&c",
    "x\"]; evil -> pwn; y [label=\"",
    "h>]; evil2 -> pwn2; z [label=<",
    "back\\slash \\N \\G \\L",
    "new\nline 'tick' caf\u00e9",
    "&amp; &#92; </td></tr></table>",
]


def hostile_model(base, tag: str):
    """LandShark with every name replaced by hostile text (``tag`` in it),
    built with dataclasses.replace, bypassing validation."""
    hostile = {t.name: f"{tag}/topic{i}/{t.name}" for i, t in enumerate(base.topics)}
    topics = tuple(
        dataclasses.replace(t, name=hostile[t.name], c_name=f"{tag}c{i}", msg_type=t.msg_type)
        for i, t in enumerate(base.topics)
    )
    by_name = {t.name: t for t in topics}
    ins = dataclasses.replace(
        base.controller.inputs,
        var_name=f"U{tag}",
        struct_name=f"S{tag}",
        fields=tuple(ControllerField(f"{f.name}{tag}", f.prim) for f in base.controller.inputs.fields),
    )
    outs = dataclasses.replace(
        base.controller.outputs,
        var_name=f"Y{tag}",
        fields=tuple(ControllerField(f"{f.name}{tag}", f.prim) for f in base.controller.outputs.fields),
    )
    ctrl = dataclasses.replace(base.controller, name=f"C{tag}", inputs=ins, outputs=outs)
    in_rels = tuple(
        dataclasses.replace(
            r,
            topic=by_name[hostile[r.topic.name]],
            input_field=f"{r.input_field}{tag}",
            path=dataclasses.replace(r.path, steps=r.path.steps + (f"p{tag}",)),
        )
        for r in base.input_relations
    )
    out_rels = tuple(
        dataclasses.replace(r, topic=by_name[hostile[r.topic.name]], output_field=f"{r.output_field}{tag}")
        for r in base.output_relations
    )
    return dataclasses.replace(
        base,
        name=f"node{tag}",
        controller=ctrl,
        topics=topics,
        input_relations=in_rels,
        output_relations=out_rels,
        source=Path(f"dir/model{tag}.yaml"),
    )


@pytest.mark.parametrize("tag", HOSTILE, ids=range(len(HOSTILE)))
def test_hostile_names_are_escaped(landshark, landshark_graph, tmp_path, tag):
    model = hostile_model(landshark, tag)
    text = render_dot(model)
    shown = escape(tag, keep_quotes=True)  # what the picture must show
    # Graphviz parses it into exactly the LandShark graph: no injected node or edge.
    g = parse_with_dot(text)
    assert set(g.nodes) == set(landshark_graph.nodes)
    assert set(g.clusters) == set(landshark_graph.clusters)
    assert sorted((e["tail"], e["head"], e["id"]) for e in g.edges) == sorted(
        (e["tail"], e["head"], e["id"]) for e in landshark_graph.edges
    )
    # ...and shows every name exactly, nothing expanded (\N, \G) or lost.
    assert g.nodes["sub0"][0] == f"{shown}/topic0//landshark/left_wheel_velocity"
    assert g.nodes["pub0"][0] == f"{shown}/topic3//landshark_control/base_velocity"
    assert g.nodes["cb0"] == [f"{shown}c0_callback"]
    assert g.nodes["ctrl_u"][:3] == [f"U{shown}", f"struct S{shown}", f"In1{shown} : float64"]
    assert g.nodes["ctrl_y"][0] == f"Y{shown}"
    assert "".join(g.nodes["step"]) == f"C{shown}_step()"
    assert "".join(g.title) == f"node{shown}: period 20 ms (50 Hz)"
    labels = sorted(e["label"] for e in g.edges_with_id("in_rel"))
    assert labels == [f"twist.linear.x.p{shown} : float64"] * 3
    # The raw text never appears in the DOT text (only its escaped form),
    # except inside the one-line comment, where it cannot end anything.
    body = text.split("\n", 1)[1]
    if any(ch in tag for ch in "\"<>&\\\n"):
        assert tag not in body
    assert "\n" not in text.split("\n", 1)[0]
    # The SVG is well-formed XML and shows the names.
    out = tmp_path / "h.svg"
    from pyrosgen.diagram import write_diagram

    write_diagram(model, out, "svg")
    texts = svg_texts(out)
    assert f"{shown}/topic1//landshark/right_wheel_velocity" in texts


def test_dot_html():
    assert dot_html('a"b') == "a&quot;b"
    assert dot_html("<&>'") == "&lt;&amp;&gt;&#x27;"
    assert dot_html("\\N") == "\\\\N"
    assert dot_html("a\nb\x00") == "a\\\\x0ab\\\\x00"
    assert dot_html(12) == "12"


# --------------------------------------------------------------------------
# Exit codes, and nothing written on failure


def test_invalid_model_exit_1_nothing_written(capsys, tmp_path):
    out = tmp_path / "ko.svg"
    code, stdout, err = run(capsys, "diagram", KO_MODEL, "-o", out)
    assert code == 1
    assert stdout == ""
    lines = err.splitlines()
    assert len(lines) == 3 and all(line.startswith(f"{KO_MODEL}:") and ": error: " in line for line in lines)
    assert list(tmp_path.iterdir()) == []


def test_missing_model_exit_1(capsys, tmp_path):
    code, _, err = run(capsys, "diagram", tmp_path / "none.yaml", "-o", tmp_path / "n.svg")
    assert code == 1
    assert "error" in err
    assert list(tmp_path.iterdir()) == []


def test_unknown_suffix_exit_1(capsys, tmp_path):
    code, stdout, err = run(capsys, "diagram", LANDSHARK, "-o", tmp_path / "n.jpg")
    assert code == 1 and stdout == ""
    assert "cannot tell the output format" in err and "--format" in err
    assert list(tmp_path.iterdir()) == []


def test_bad_format_option_exit_1(capsys, tmp_path):
    code, _, err = run(capsys, "diagram", LANDSHARK, "-o", tmp_path / "n.svg", "--format", "gif")
    assert code == 1
    assert "invalid choice" in err
    assert list(tmp_path.iterdir()) == []


def test_missing_output_option_exit_1(capsys):
    code, _, err = run(capsys, "diagram", LANDSHARK)
    assert code == 1
    assert "-o" in err


def test_output_is_a_directory_exit_1(capsys, tmp_path):
    code, _, err = run(capsys, "diagram", LANDSHARK, "-o", tmp_path, "--format", "svg")
    assert code == 1
    assert "is a directory" in err


def test_dot_missing_exit_2(capsys, tmp_path, monkeypatch):
    empty = tmp_path / "bin"
    empty.mkdir()
    monkeypatch.setenv("PATH", str(empty))
    monkeypatch.delenv("PYROSGEN_DOT", raising=False)
    out = tmp_path / "n.svg"
    code, stdout, err = run(capsys, "diagram", LANDSHARK, "-o", out)
    assert code == 2 and stdout == ""
    assert "'dot'" in err and "graphviz" in err
    assert not out.exists() and leftovers(tmp_path) == []
    # The .dot format needs no Graphviz.
    code, _, err = run(capsys, "diagram", LANDSHARK, "-o", tmp_path / "n.dot")
    assert code == 0, err


def test_dot_failure_exit_2_keeps_old_file(capsys, tmp_path, monkeypatch):
    fake = tmp_path / "fakedot"
    fake.write_text("#!/bin/sh\necho 'fakedot: syntax error in line 1' >&2\nexit 1\n")
    fake.chmod(fake.stat().st_mode | stat.S_IXUSR)
    monkeypatch.setenv("PYROSGEN_DOT", str(fake))
    out = tmp_path / "n.svg"
    out.write_text("old picture")
    code, _, err = run(capsys, "diagram", LANDSHARK, "-o", out)
    assert code == 2
    assert "fakedot: syntax error in line 1" in err
    assert out.read_text() == "old picture"
    assert leftovers(tmp_path) == []


def test_dot_success_replaces_old_file(tmp_path):
    out = tmp_path / "n.svg"
    out.write_text("old picture")
    assert cli.main(["diagram", str(LANDSHARK), "-o", str(out)]) == 0
    assert "/landshark/gps_velocity" in svg_texts(out)
    mode = stat.S_IMODE(out.stat().st_mode)
    umask = os.umask(0)
    os.umask(umask)
    assert mode == 0o666 & ~umask


def test_write_atomic_only_when_changed(tmp_path):
    out = tmp_path / "f.dot"
    assert write_atomic(out, b"one") is True
    before = out.stat().st_mtime_ns
    os.utime(out, ns=(before - 10**9, before - 10**9))
    assert write_atomic(out, b"one") is False
    assert out.stat().st_mtime_ns == before - 10**9
    assert write_atomic(out, b"two") is True
    assert out.read_bytes() == b"two"
    assert leftovers(tmp_path) == []

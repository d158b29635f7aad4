"""The second reading of the model file (``pyrosgen.nversion``) against the
front end: for every model file in the repository that the front end
accepts, the model text read without the front end is byte for byte the
front end's (``modeltext.model_text(load_model(f))``), and the standard
message definitions it reads from Debian's ROS 1 packages are those the
front end reads from rosbags' Noetic set.  The front end is used here, in
the test, never in the package (``test_independent_imports``)."""

from __future__ import annotations

import ast
import difflib
from pathlib import Path

import pytest

from pyrosgen.errors import InvalidNodeModel
from pyrosgen.frontend.validate import load_model
from pyrosgen.nversion import reader
from pyrosgen.nversion.msgs import Messages, ReadingError, parse_msg
from pyrosgen.proof.modeltext import model_text

REPO = Path(__file__).resolve().parents[2]
PACKAGE = REPO / "pyrosgen" / "nversion"


def _model_files() -> list[Path]:
    files = {*REPO.glob("examples/**/*.yaml"), *REPO.glob("tests/**/*.yaml")}
    return sorted(f for f in files if ".venv" not in f.parts)


def _accepted() -> list[Path]:
    out = []
    for f in _model_files():
        try:
            load_model(f)
        except InvalidNodeModel:
            continue
        out.append(f)
    return out


def test_every_accepted_model_file_reads_the_same():
    accepted = _accepted()
    # the examples are among them (the list is found, not written here)
    assert {p.parent.name for p in accepted if "examples" in p.parts} >= {"landshark", "laser_guard", "multi"}
    differ = []
    for f in accepted:
        expected = model_text(load_model(f))
        try:
            got = reader.model_text(f)
        except ReadingError as exc:
            differ.append(f"{f.relative_to(REPO)}: cannot read: {exc}")
            continue
        if got != expected:
            diff = difflib.unified_diff(expected.splitlines(), got.splitlines(), "front end", "nversion",
                                        lineterm="", n=0)
            differ.append(f"{f.relative_to(REPO)}:\n    " + "\n    ".join(list(diff)[:12]))
    assert not differ, f"{len(differ)} of {len(accepted)} model files read differently:\n" + "\n".join(differ)


def test_standard_message_definitions_agree_with_rosbags():
    """Every standard type that a Debian ROS 1 package installs has, in the
    second reading's ``.msg`` parser, the fields (name, kind, type, array
    size) that the front end reads from rosbags."""
    from pyrosgen.frontend.msgload import _standard_defs

    msgs = Messages()
    compared, differ = 0, []
    for name, raw in sorted(_standard_defs().items()):
        try:
            mine = msgs.raw(name)
        except ReadingError:
            continue  # its package is not installed (it is named when a model uses it)
        compared += 1
        theirs = [(f.name, "other" if f.base_kind == "unsupported" else f.base_kind, f.base, f.card, f.size)
                  for f in raw.fields]
        if theirs != [(f.name, f.kind, f.base, f.card, f.size) for f in mine]:
            differ.append(name)
    assert compared >= 100 and not differ, (compared, differ)


def test_msg_parser_reads_the_ros1_forms():
    text = ("# comment\nHeader header\nuint8 A=1  # a constant\nstring S=a # b=c\n"
            "byte b\nchar c\nfloat32[] r  # ranges\nint16[4] q\ntime t\nduration[] d\n"
            "Point p\ngeometry_msgs/Vector3[2] v\nstring[] names\n")
    got = [(f.name, f.kind, f.base, f.card, f.size) for f in parse_msg(text, "pkg", "t.msg")]
    assert got == [
        ("header", "msg", "std_msgs/Header", "scalar", 0), ("b", "prim", "int8", "scalar", 0),
        ("c", "prim", "uint8", "scalar", 0), ("r", "prim", "float32", "sequence", 0),
        ("q", "prim", "int16", "array", 4), ("t", "msg", "time", "scalar", 0),
        ("d", "msg", "duration", "sequence", 0), ("p", "msg", "pkg/Point", "scalar", 0),
        ("v", "msg", "geometry_msgs/Vector3", "array", 2), ("names", "string", "string", "sequence", 0)]
    with pytest.raises(ReadingError, match="t.msg:1"):
        parse_msg("float64 x y\n", "pkg", "t.msg")


def test_msg_parser_skips_the_defaults_of_the_installed_ros2_definitions(tmp_path):
    """ROS 2's standard ``.msg`` files give defaults (``float64 w 1`` in
    geometry_msgs/Quaternion, ``int8 status -2 # ...`` in
    sensor_msgs/NavSatStatus): the standard definitions are read with
    them skipped; a model's own ``.msg`` text still refuses them."""
    text = "float64 x 0\nfloat64 w 1\nint8 status -2 # STATUS_UNKNOWN\nint8 A=1\n"
    got = [(f.name, f.base) for f in parse_msg(text, "pkg", "q.msg", defaults=True)]
    assert got == [("x", "float64"), ("w", "float64"), ("status", "int8")]
    with pytest.raises(ReadingError, match="q.msg:1"):
        parse_msg(text, "pkg", "q.msg")
    (tmp_path / "geometry_msgs" / "msg").mkdir(parents=True)
    (tmp_path / "geometry_msgs" / "msg" / "Quaternion.msg").write_text(text)
    assert [f.name for f in Messages(standard_root=tmp_path).raw("geometry_msgs/Quaternion")] == ["x", "w", "status"]
    custom = tmp_path / "custom" / "my_msgs" / "msg"
    custom.mkdir(parents=True)
    (custom / "Q.msg").write_text(text)
    with pytest.raises(ReadingError, match="Q.msg:1"):
        Messages([tmp_path / "custom"], standard_root=tmp_path)


def test_an_unknown_standard_type_is_named(tmp_path):
    msgs = Messages(standard_root=tmp_path)
    with pytest.raises(ReadingError, match="std_msgs/Float64") as exc:
        msgs.raw("std_msgs/Float64")
    assert "ros-std-msgs" in str(exc.value) and str(tmp_path / "std_msgs" / "msg") in str(exc.value)


def test_independent_imports():
    """The package shares no code with the front end: it imports PyYAML,
    the standard library, itself and pyrosgen.errors (the exit-code family)
    only."""
    import sys

    allowed_pyrosgen = {"pyrosgen.errors"}
    for f in sorted(PACKAGE.glob("*.py")):
        for node in ast.walk(ast.parse(f.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Import):
                names = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom):
                assert node.level == 0, f"{f.name}: relative import"
                names = [node.module]
            else:
                continue
            for n in names:
                top = n.split(".")[0]
                if n.startswith("pyrosgen.nversion") or n in allowed_pyrosgen:
                    continue
                assert top == "yaml" or top in sys.stdlib_module_names or top == "__future__", (f.name, n)


def test_keys_are_their_text(tmp_path):
    """A controller field named like a YAML 1.1 boolean (NO, On, y) is a
    name in both readings, not ``False``."""
    f = tmp_path / "m.yaml"
    f.write_text(
        "node: {name: n, period_ms: 20}\n"
        "controller:\n  name: C\n  inputs: {name: C_U, fields: {NO: float64, On: float64}}\n"
        "  outputs: {name: C_Y, fields: {y: float64}}\n"
        "topics:\n  - {name: /a, direction: subscribe, type: std_msgs/Float64, queue_size: 1}\n"
        "  - {name: /b, direction: subscribe, type: std_msgs/Float64, queue_size: 1}\n"
        "  - {name: /c, direction: publish, type: std_msgs/Float64, queue_size: 1}\n"
        "relations:\n  inputs:\n    - {topic: /a, field: data, input: 'NO'}\n"
        "    - {topic: /b, field: data, input: 'On'}\n"
        "  outputs:\n    - {output: y, topic: /c, field: data}\n")
    text = reader.model_text(f)
    assert text == model_text(load_model(f))
    assert "input NO float64\ninput On float64\n" in text and "output y float64\n" in text


def test_every_accepted_diagram_reads_the_same():
    """The diagram text (``DiagramText.print_diagram``'s grammar) of every
    block-diagram model file the front end accepts, subsystems expanded,
    equals the front end's."""
    from pyrosgen.nversion import diagram
    from pyrosgen.proof.modeltext import diagram_text

    seen, differ = 0, []
    for f in _accepted():
        m = load_model(f)
        assert diagram.has_diagram(f) == (m.controller.diagram is not None), f
        if m.controller.diagram is None:
            continue
        seen += 1
        expected = diagram_text(m)
        try:
            got = diagram.diagram_text(f)
        except ReadingError as exc:
            differ.append(f"{f.relative_to(REPO)}: cannot read: {exc}")
            continue
        if got != expected:
            diff = difflib.unified_diff(expected.splitlines(), got.splitlines(), "front end", "nversion",
                                        lineterm="", n=0)
            differ.append(f"{f.relative_to(REPO)}:\n    " + "\n    ".join(list(diff)[:12]))
    assert seen >= 5 and not differ, (seen, differ)

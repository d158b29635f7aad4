"""The front end for the target ros2 (DESIGN.md rule 4.17): the same model
read with ROS 2's message definitions from the installed wheels; a field
path or a feature that holds for ROS 1 and not for ROS 2 is refused for
ROS 2 with file:line:col and the rule; a missing installation is exit 2."""

from __future__ import annotations

import subprocess
import sys

import pytest

from pyrosgen.errors import InvalidNodeModel
from pyrosgen.frontend.validate import load_model
from pyrosgen.proof.modeltext import parse_model_text
from pyrosgen.ros2.frontend import load_model_ros2
from pyrosgen.ros2.wrapper import Ros2WrapperMismatch, check_rcl_wrapper, render_rcl_wrapper

from support import ros as rosutil

MODEL = """\
node: {{name: n2, period_ms: 10}}
controller:
  name: C
  inputs: {{name: C_U, fields: {{In1: {in_type}}}}}
  outputs: {{name: C_Y, fields: {{Out1: float64}}}}
topics:
  - {{name: /cmd_in, direction: subscribe, type: {in_msg}, queue_size: 3}}
  - {{name: /out, direction: publish, type: geometry_msgs/TwistStamped, queue_size: 2{extra}}}
relations:
  inputs:
    - {{topic: /cmd_in, field: {field}, input: In1}}
  outputs:
    - {{output: Out1, topic: /out, field: twist.linear.x}}
"""


def _model(tmp_path, field="twist.linear.x", in_type="float64", in_msg="geometry_msgs/TwistStamped", extra=""):
    p = tmp_path / "m.yaml"
    p.write_text(MODEL.format(field=field, in_type=in_type, in_msg=in_msg, extra=extra), encoding="utf-8")
    return p


def _refused(path, install) -> list:
    with pytest.raises(InvalidNodeModel) as info:
        load_model_ros2(path, install)
    return list(info.value.diagnostics)


def test_ros2_reads_ros2_messages(tmp_path, ros2_install):
    m = load_model_ros2(_model(tmp_path, field="header.stamp.nanosec", in_type="uint32"), ros2_install)
    by = {t.name: [(f.name, f.prim or f.msg) for f in t.fields] for t in m.messages}
    assert by["builtin_interfaces/Time"] == [("sec", "int32"), ("nanosec", "uint32")]
    assert by["std_msgs/Header"] == [("stamp", "builtin_interfaces/Time")]


def test_header_seq_refused_for_ros2_with_position_and_rule(tmp_path, ros2_install):
    path = _model(tmp_path, field="header.seq", in_type="uint32")
    load_model(path)  # ROS 1 has header.seq
    (d,) = _refused(path, ros2_install)
    assert (d.file, d.line, d.col, d.rule) == (str(path), 11, 31, "4.17")
    assert "seq" in d.message and "target ros2" in d.message and "the ROS 1 target accepts it" in d.message
    assert str(d).startswith(f"{path}:11:31: error: ") and str(d).endswith("[rule 4.17]")


def test_stamp_nsec_refused_for_ros2(tmp_path, ros2_install):
    path = _model(tmp_path, field="header.stamp.nsec", in_type="uint32")
    load_model(path)
    (d,) = _refused(path, ros2_install)
    assert (d.line, d.col, d.rule) == (11, 31, "4.17") and "nsec" in d.message


def test_ros2_only_path_refused_for_ros1(tmp_path, ros2_install):
    path = _model(tmp_path, field="header.stamp.nanosec", in_type="uint32")
    load_model_ros2(path, ros2_install)
    with pytest.raises(InvalidNodeModel) as info:
        load_model(path)
    (d,) = info.value.diagnostics
    assert d.line == 11 and "nanosec" in d.message


def test_type_missing_from_ros2_refused(tmp_path, ros2_install):
    # std_msgs/Time exists in ROS 1 Noetic, not in ROS 2
    path = _model(tmp_path, field="data.sec", in_type="uint32", in_msg="std_msgs/Time")
    load_model(path)
    diags = _refused(path, ros2_install)
    assert diags and all(d.rule == "4.17" for d in diags)
    assert any(d.line == 7 and "std_msgs/Time" in d.message for d in diags)


def test_queue_size_zero_refused_for_ros2(tmp_path, ros2_install):
    """A history of depth 0 would hold nothing (Environment.rcl_deliverable,
    the wrapper takes at most 0 messages; rcl would read 0 as the
    middleware's default depth): queue_size 0 is refused for ROS 2 as for
    ROS 1 (rule 4.4), at its place."""
    path = _model(tmp_path)
    path.write_text(path.read_text().replace("queue_size: 3}", "queue_size: 0}"), encoding="utf-8")
    diags = _refused(path, ros2_install)
    assert [(d.line, d.rule) for d in diags] == [(7, "4.4")], [str(d) for d in diags]
    assert "queue_size" in diags[0].message and str(diags[0]).startswith(f"{path}:7:")


def test_stamp_now_accepted_for_ros2(tmp_path, ros2_install):
    """Rule 4.13 on ROS 2: header.stamp is a builtin_interfaces/Time (int32
    sec, uint32 nanosec), which the proved glue stamps (DDC.stamp_sec)."""
    m = load_model_ros2(_model(tmp_path, extra=", stamp: now"), ros2_install)
    assert m.stamps == (("out", ("header", "stamp")),) and m.stamp_from == ()
    by = {t.name: [(f.name, f.prim or f.msg) for f in t.fields] for t in m.messages}
    assert by["builtin_interfaces/Time"] == [("sec", "int32"), ("nanosec", "uint32")]
    assert "time" not in by  # ROS 1's time is not carried: Coq's NodeModel.time_is_ros2


def test_stamp_from_accepted_for_ros2_reads_sec_and_nanosec(tmp_path, ros2_install):
    m = load_model_ros2(_model(tmp_path, extra=", stamp: {from: /cmd_in}"), ros2_install)
    assert m.stamp_from == (("out", ("cmd_in", ("header", "stamp"))),)
    (src,) = [t for t in m.topics if t.name == "/cmd_in"]
    read = [str(p) for p in m.read_leaves(src)]
    assert "header.stamp.sec" in read and "header.stamp.nanosec" in read and "header.stamp.nsec" not in read


@pytest.mark.parametrize(("extra", "out_type", "field", "expect"), [
    # a published message without a header.stamp of ROS 2's time type
    (", stamp: now", "geometry_msgs/Twist", None, "has no header.stamp of type builtin_interfaces/Time to stamp"),
    # the source of a copied stamp has no header
    (", stamp: {from: /cmd_in}", None, None, "has no header.stamp of type builtin_interfaces/Time to copy"),
    # an output relation writing into the stamp
    (", stamp: now", None, "header.stamp.sec", "is written by the stamp"),
    # not a stamp value
    (", stamp: later", None, None, "must be 'now'"),
])
def test_bad_stamps_still_refused_for_ros2(tmp_path, ros2_install, extra, out_type, field, expect):
    path = _model(tmp_path, extra=extra, in_msg="geometry_msgs/Twist" if "from" in extra else "geometry_msgs/TwistStamped")
    text = path.read_text(encoding="utf-8")
    if out_type:
        text = text.replace("type: geometry_msgs/TwistStamped, queue_size: 2", f"type: {out_type}, queue_size: 2")
        text = text.replace("field: twist.linear.x}\n", "field: linear.x}\n").replace(
            "topic: /out, field: twist.linear.x", "topic: /out, field: linear.x")
    if field:
        text = text.replace("outputs: {name: C_Y, fields: {Out1: float64}}",
                            "outputs: {name: C_Y, fields: {Out1: float64, Sec: int32}}")
        text += f"    - {{output: Sec, topic: /out, field: {field}}}\n"
    path.write_text(text, encoding="utf-8")
    diags = _refused(path, ros2_install)
    assert any(d.rule == "4.13" and expect in d.message for d in diags), [str(d) for d in diags]
    assert all(str(d).startswith(f"{path}:") and d.line is not None for d in diags), [str(d) for d in diags]


def test_sequence_of_strings_accepted_for_ros2(ros2_install):
    m = load_model_ros2(rosutil.ROOT / "examples" / "arm_named" / "arm_named.yaml", ros2_install)
    assert any(t.is_seq and t.seq_of == ("string", 6) for t in m.messages)


def test_sequence_of_numbers_accepted_for_ros2(tmp_path, ros2_install):
    path = _model(tmp_path, field='"ranges[0]"', in_type="float32", in_msg="sensor_msgs/LaserScan")
    m = load_model_ros2(path, ros2_install)
    assert any(t.is_seq and t.seq_of == ("float32", 128) for t in m.messages)


def test_msg_paths_ros1_only_types_refused_for_ros2(ros2_install):
    """msg_paths is read for ROS 2 (rosidl builds the custom messages,
    tests/ros2/test_custom_msgs_ros2.py); multi's say what only ROS 1
    accepts: a bare Header, ROS 1's duration, each at its place."""
    diags = _refused(rosutil.MULTI, ros2_install)
    estop = [d for d in diags if d.file.endswith("EStop.msg")]
    assert [(d.line, d.col, d.rule) for d in estop] == [(2, 1, "4.17"), (8, 1, "4.17")]
    assert "std_msgs/Header" in estop[0].message and "builtin_interfaces/Duration" in estop[1].message


def _cli(*args, env_extra=None):
    import os
    env = dict(os.environ, **(env_extra or {}))
    return subprocess.run([sys.executable, "-m", "pyrosgen", *args], capture_output=True, text=True, env=env,
                          cwd=str(rosutil.ROOT))


def test_generate_ros2_names_the_target_and_verifies(tmp_path, ros2_install):
    """``generate --ros2``: the .v names the target ROS 2 (``target :=
    Environment.Ros2``, ``<node>_ddc_target``), the manifest records it, and
    ``verify`` (with and without the model, read for ROS 2) passes; the
    same model generated for ROS 1 names Ros1."""
    import json
    out2, out1 = tmp_path / "g2", tmp_path / "g1"
    r = _cli("generate", "--ros2", "-q", str(rosutil.LANDSHARK), "-o", str(out2))
    assert r.returncode == 0, r.stdout + r.stderr
    v = (out2 / "landshark_controller.v").read_text()
    assert "Definition target : Environment.target := Environment.Ros2." in v
    assert "Theorem landshark_controller_ddc_target : DDC.node_ddc_on target model the_program." in v
    assert json.loads((out2 / "landshark_controller.manifest.json").read_text())["target"] == "ros2"
    assert "Target: ROS 2 (rcl)" in (out2 / "landshark_controller.certificate.md").read_text()
    for extra in ([], ["--model", str(rosutil.LANDSHARK)]):
        ok = _cli("verify", "-q", str(out2), *extra)
        assert ok.returncode == 0, ok.stdout + ok.stderr
    r = _cli("generate", "-q", str(rosutil.LANDSHARK), "-o", str(out1))
    assert r.returncode == 0, r.stdout + r.stderr
    v1 = (out1 / "landshark_controller.v").read_text()
    assert "Definition target : Environment.target := Environment.Ros1." in v1
    assert "Target: ROS 1 (roscpp)" in (out1 / "landshark_controller.certificate.md").read_text()


def test_check_cli_ros2(tmp_path, ros2_install):
    ok = _cli("check", "--ros2", str(rosutil.LANDSHARK))
    assert ok.returncode == 0 and "ok: node landshark_controller" in ok.stdout
    bad = _cli("check", "--ros2", str(_model(tmp_path, field="header.seq", in_type="uint32")))
    assert bad.returncode == 1 and ":11:31: error:" in bad.stderr and "[rule 4.17]" in bad.stderr
    assert "Traceback" not in bad.stderr


def test_missing_ros2_installation_is_exit_2_with_the_install_command(tmp_path):
    for cmd in (["check", "--ros2", str(rosutil.LANDSHARK)],
                ["build", "--ros2", str(rosutil.LANDSHARK), "--controller", str(rosutil.LANDSHARK_CTL),
                 "-o", str(tmp_path / "out")]):
        r = _cli(*cmd, env_extra={"PYROSGEN_ROS2_PREFIX": str(tmp_path / "none")})
        assert r.returncode == 2, r.stderr
        assert "make ros2-deps" in r.stderr and "Traceback" not in r.stderr
    assert not (tmp_path / "out").exists()


PROVED = """\
pyrosgen-model 1
node n2
period_ms 10
controller C
inputs C_U ExtU_C_T
input In1 float64
outputs C_Y ExtY_C_T
output Out1 float64
message builtin_interfaces_Time
field sec int32
field nanosec uint32
message std_msgs_Header
field stamp msg builtin_interfaces_Time
message geometry_msgs_Vector3
field x float64
field y float64
field z float64
message geometry_msgs_Twist
field linear msg geometry_msgs_Vector3
field angular msg geometry_msgs_Vector3
message geometry_msgs_TwistStamped
field header msg std_msgs_Header
field twist msg geometry_msgs_Twist
topic /cmd_in cmd_in subscribe geometry_msgs/TwistStamped 3
topic /out out publish geometry_msgs/TwistStamped 2
input_relation cmd_in twist.linear.x In1
output_relation Out1 out twist.linear.x
"""


@pytest.mark.parametrize("tamper", [
    ("options.qos.depth = 3;", "options.qos.depth = 1;"),
    ('"/cmd_in", &options', '"/other", &options'),
    ("#define PYROSGEN_PERIOD_NS 10000000LL", "#define PYROSGEN_PERIOD_NS 20000000LL"),
    ("ROSIDL_GET_MSG_TYPE_SUPPORT(geometry_msgs, msg, TwistStamped),\n                            \"/out\"",
     "ROSIDL_GET_MSG_TYPE_SUPPORT(geometry_msgs, msg, Twist),\n                            \"/out\""),
])
def test_rcl_wrapper_check_refuses_a_tampered_wrapper(tmp_path, ros2_install, tamper):
    model = load_model_ros2(_model(tmp_path), ros2_install)
    from pyrosgen.proof.modeltext import model_text
    assert model_text(model) == PROVED  # the proved text the wrapper is rendered from
    text = render_rcl_wrapper(model, parse_model_text(PROVED), qos={t.name: t.qos for t in model.topics})["n2_rcl.c"]
    check_rcl_wrapper(text, PROVED, wrapper_name="n2_rcl.c")
    old, new = tamper
    assert text.count(old) == 1
    with pytest.raises(Ros2WrapperMismatch):
        check_rcl_wrapper(text.replace(old, new), PROVED, wrapper_name="n2_rcl.c")


def test_build_ros2_cli_nothing_partial_on_a_controller_error(tmp_path, ros2_install):
    import shutil
    ctl = tmp_path / "ctl"
    shutil.copytree(rosutil.CONTROLLERS / "landshark_echo", ctl)
    (ctl / "Controller.c").write_text((ctl / "Controller.c").read_text() + "\nint broken(void) { return }\n")
    out = tmp_path / "out"
    r = _cli("build", "--ros2", "-q", str(rosutil.LANDSHARK), "--controller", str(ctl), "-o", str(out))
    assert r.returncode == 1, r.stderr
    assert "Controller.c: error: the controller source does not compile" in r.stderr
    assert "Traceback" not in r.stderr
    assert not out.exists() and not list(tmp_path.glob(".pyrosgen-build-*"))


def test_verify_covers_the_ros2_files(tmp_path, ros2_install):
    """``pyrosgen verify`` on a ``build --ros2`` folder: every check holds
    (the recorded hashes cover the rcl wrapper and ``<node>.target``); a
    tampered rcl wrapper or target file is refused."""
    import shutil
    from pyrosgen.ros2.build import build_ros2
    out = tmp_path / "out"
    build_ros2(rosutil.LANDSHARK, rosutil.CONTROLLERS / "landshark_echo", out, install=ros2_install)
    ok = _cli("verify", "-q", str(out))
    assert ok.returncode == 0, ok.stdout + ok.stderr
    # --model: the model file read for the folder's target (ROS 2's messages)
    ok = _cli("verify", str(out), "--model", str(rosutil.LANDSHARK))
    assert ok.returncode == 0, ok.stdout + ok.stderr
    assert "read by the front end and read independently" in ok.stdout, ok.stdout
    for name, edit in (("landshark_controller_rcl.c", lambda t: t.replace("options.qos.depth = 1;", "options.qos.depth = 2;", 1)),
                       ("landshark_controller.target", lambda t: t.replace("ros2", "ros1"))):
        bad = tmp_path / f"bad_{name}"
        shutil.copytree(out, bad)
        text = (bad / name).read_text()
        assert edit(text) != text
        (bad / name).write_text(edit(text))
        r = _cli("verify", "-q", str(bad))
        assert r.returncode == 1 and name in r.stdout + r.stderr, (name, r.stdout, r.stderr)
        # the same edit with its digest rewritten in the three records: the
        # package check refuses it (the rcl wrapper check, the target's text)
        _digests(bad, name)
        r = _cli("verify", "-q", str(bad))
        assert r.returncode == 1 and "package" in r.stdout and name in r.stdout, (name, r.stdout, r.stderr)
        assert "hashes    " in r.stdout and " FAILED  hashes" not in r.stdout, r.stdout
    # the .v names the target ROS 2 (rule 4.17); a .v naming ROS 1 instead,
    # its digest rewritten, is refused by the template check (the manifest's
    # target is ros2), and so is a manifest that says ros1 with it (the
    # folder's <node>.target says ros2)
    v = (out / "landshark_controller.v").read_text()
    assert "Definition target : Environment.target := Environment.Ros2." in v
    assert "Theorem landshark_controller_ddc_target : DDC.node_ddc_on target model the_program." in v
    bad = tmp_path / "bad_v"
    shutil.copytree(out, bad)
    (bad / "landshark_controller.v").write_text(v.replace("Environment.Ros2.", "Environment.Ros1."))
    _digests(bad, "landshark_controller.v")
    r = _cli("verify", "-q", str(bad))
    assert r.returncode == 1 and "FAILED  v-file" in r.stdout, (r.stdout, r.stderr)
    assert "ident 'Environment.Ros1' where the template has ident 'Environment.Ros2'" in r.stdout, r.stdout
    import json
    m = bad / "landshark_controller.manifest.json"
    data = json.loads(m.read_text())
    assert data["target"] == "ros2"
    m.write_text(json.dumps({**data, "target": "ros1"}))
    r = _cli("verify", "-q", str(bad))
    assert r.returncode == 1 and "FAILED  v-file" in r.stdout, (r.stdout, r.stderr)
    assert "landshark_controller.target says ros2, but the manifest's target is ros1" in r.stdout, r.stdout


def _digests(copy, name: str) -> None:
    """Rewrite the digest of ``name`` in the manifest, the digest file and
    the certificate of the folder ``copy`` (a forger who edits a file)."""
    import hashlib
    import json

    node = "landshark_controller"
    m = copy / f"{node}.manifest.json"
    data = json.loads(m.read_text())
    cert = copy / f"{node}.certificate.md"
    text = cert.read_text()
    new = hashlib.sha256((copy / name).read_bytes()).hexdigest()
    text = text.replace(f"| `{name}` | `{data['files'][name]}` |", f"| `{name}` | `{new}` |")
    data["files"][name] = new
    cert.write_text(text)
    m.write_text(json.dumps(data, indent=2, sort_keys=True) + "\n")
    (copy / f"{node}.sha256").write_text("".join(f"{v}  {n}\n" for n, v in sorted(data["files"].items())))


def test_build_ros2_refuses_an_empty_output_folder(tmp_path, ros2_install, monkeypatch):
    """``-o ""`` is refused for ROS 2 as for ROS 1 (the one check of every
    target's build, ``ros.build.check_build_request``): nothing is written
    into the current folder."""
    from pyrosgen.generate import OutputDirError
    from pyrosgen.ros2.build import build_ros2

    monkeypatch.chdir(tmp_path)
    with pytest.raises(OutputDirError):
        build_ros2(rosutil.LANDSHARK, rosutil.CONTROLLERS / "landshark_echo", "", install=ros2_install)
    assert list(tmp_path.iterdir()) == []

"""Custom messages for ROS 2 (``msg_paths``, rule 4.17): examples/dock built
with ``--ros2``, its custom package dock_msgs generated and compiled by
rosidl's generators from the wheels (pyrosgen/ros2/rosidl.py), and driven
on Fast DDS by an rclpy peer that imports the Python types the build made
(``OUT/python``).  Every command is checked bit for bit against the
diagram computed here in IEEE binary64: speed = sat(0.5 range, 0, 0.5),
zero and stop when range < 0.2 or the link level is 0; the beacon's id,
its quality into ``seen[0]`` (``seen[1]`` zero) and into ``links`` (a
sequence of one custom message), its first 3 samples into ``trace``
(lengths 0, 1, N-1, N, N+1 and 2N).  Then ``verify`` of the
folder (the generated sources made again from its ``.msg`` copies; a
carried field whose rosidl type changed is found), and bad input: what a
ROS 1 ``.msg`` may say and ROS 2 may not, refused at its place."""

from __future__ import annotations

import json
import shutil
import signal
import struct
import subprocess
import sys

import pytest

from pyrosgen.errors import InvalidNodeModel
from pyrosgen.ros2.build import build_ros2
from pyrosgen.ros2.env import Ros2Install, Ros2Missing
from pyrosgen.ros2.frontend import load_model_ros2
from pyrosgen.ros2.rosidl import _check_generators, _order, check_rosidl_folder, peer_env
from pyrosgen.verify.certificate import read_manifest

from support import ros as rosutil

from .conftest import PEER, run_peer, settled_leftovers, spawn, stop

DOCK = rosutil.ROOT / "examples" / "dock"
MODEL = DOCK / "dock.yaml"
BEACON, COMMAND = "/dock/beacon", "/dock/command"
SETTLE, HOLD = 0.3, 0.7

#: (what, range, id, link level, snr, samples)
CASES = [
    ("far: saturated, 4 samples (N+1)", 1.3, 7, 2, 12.5, [1.0, 2.0, 3.5, -4.25]),
    ("3 samples (N)", 0.6, 8, 3, -2.0, [0.5, 0.25, 8.0]),
    ("near: stop, 1 sample", 0.15, 9, 2, 1.0, [7.0]),
    ("link lost: stop, no sample", 2.0, 10, 0, 3.0, []),
    ("2 samples (N-1)", 0.8, -11, 1, 0.5, [1.0, 2.0]),
    ("6 samples (2N)", 0.3, 12, 3, 6.0, [9.0, 8.0, 7.0, 6.0, 5.0, 4.0]),
]


def bits(x: float) -> int:
    return struct.unpack("<Q", struct.pack("<d", x))[0]


def command(rng: float, ident: int, level: int, snr: float, samples: list[float]) -> dict:
    """The DockCommand the diagram computes, as the peer reports it."""
    stop_now = rng < 0.2 or level == 0
    speed = 0.0 if stop_now else min(max(0.5 * rng, 0.0), 0.5)
    return {"speed": bits(speed), "stop": stop_now, "beacon_id": ident,
            "seen": [{"level": level, "snr": bits(snr)}, {"level": 0, "snr": 0}],
            "trace": [bits(x) for x in samples[:3]], "links": [{"level": level, "snr": bits(snr)}]}


@pytest.fixture(scope="module")
def dock2(ros2_install, ros2_nodes):
    """examples/dock built for ROS 2 (with its custom package)."""
    return build_ros2(MODEL, None, ros2_nodes / "dock", install=ros2_install)


def test_dock_ros2_custom_messages_round_trip(dock2, ros2_install, tmp_path, shm_guard):
    out = dock2.out_dir
    # what the build wrote: the libraries, the Python types, the sources; no staging path in them
    for lib in ("generator_c", "typesupport_c", "typesupport_fastrtps_c", "typesupport_introspection_c",
                "generator_py"):
        assert (out / "lib" / f"libdock_msgs__rosidl_{lib}.so").is_file(), lib
    assert sorted(p.name for p in (out / "rosidl" / "interfaces" / "dock_msgs" / "msg").glob("*.msg")) == \
        ["Beacon.msg", "DockCommand.msg", "Quality.msg"]
    leaked = [p for p in out.rglob("*") if p.is_file() and p.name != ".pyrosgen-build-ros2.txt"
              and b".pyrosgen-build-" in p.read_bytes()]
    assert not leaked, leaked
    steps, wants = [{"sleep": 0.5}], []
    for _what, rng, ident, level, snr, samples in CASES:
        steps += [{"publish": {BEACON: {"range": bits(rng), "id": ident, "quality.level": level,
                                        "quality.snr": bits(snr), "samples": [bits(x) for x in samples],
                                        "bearing": bits(0.25), "note": "not carried",
                                        "header.frame_id": "dock"}}},
                  {"sleep": HOLD}]
        wants.append(command(rng, ident, level, snr, samples))
    plan = {"publishers": {BEACON: "dock_msgs/Beacon"}, "subscribers": {COMMAND: "dock_msgs/DockCommand"},
            "match_timeout": 20.0, "steps": steps}
    (tmp_path / "peer.plan.json").write_text(json.dumps(plan))
    node = spawn([dock2.binary], tmp_path / "node.log")
    try:
        peer = spawn([ros2_install.python, PEER, tmp_path / "peer.plan.json", tmp_path / "peer.result.json"],
                     tmp_path / "peer.log", peer_env(out))  # PYTHONPATH only, no LD_LIBRARY_PATH
        result = run_peer(plan, tmp_path, ros2_install, started=peer)
    finally:
        status = stop(node, signal.SIGTERM)
    assert status == 0, (tmp_path / "node.log").read_text(errors="replace")[-2000:]
    got_all = [(t, lv) for t, topic, lv in result["received"] if topic == COMMAND]
    first = result["steps"][1]["t0"]
    before = [lv for t, lv in got_all if t < first]
    assert before and all(lv == command(0.0, 0, 0, 0.0, []) for lv in before), before[:2]
    for k, ((what, *_), want) in enumerate(zip(CASES, wants)):
        t0, t1 = result["steps"][1 + 2 * k]["t1"] + SETTLE, result["steps"][2 + 2 * k]["t1"]
        got = [lv for t, lv in got_all if t0 <= t <= t1]
        assert len(got) >= 10, (what, len(got))
        assert all(g == want for g in got), (what, got[-1], want)
    assert not (left := settled_leftovers()), left


def test_dock_ros2_folder_verifies(dock2):
    r = subprocess.run([sys.executable, "-m", "pyrosgen", "verify", str(dock2.out_dir)], capture_output=True,
                       text=True, cwd=str(rosutil.ROOT))
    assert r.returncode == 0, r.stdout + r.stderr
    assert "ok      package" in r.stdout and "Traceback" not in r.stderr


def test_dock_ros2_tampered_rosidl_files_found(dock2, tmp_path, ros2_install):
    folder = tmp_path / "dock"
    shutil.copytree(dock2.out_dir, folder, symlinks=True)
    _rec, files = read_manifest(folder / "dock.manifest.json")
    assert check_rosidl_folder(folder, files, (folder / "dock.model").read_text(), ros2_install) == []
    # the custom messages' files left out of the manifest: the proved model still carries their types
    bare = [n for n in files if not n.startswith(("rosidl/", "python/"))]
    assert dict(check_rosidl_folder(folder, bare, (folder / "dock.model").read_text(), ros2_install)).keys() == \
        {f"rosidl/interfaces/dock_msgs/msg/{t}.msg" for t in ("Beacon", "DockCommand", "Quality")}
    # rosidl's C struct declares `range` as a float: the carried float64 would be narrowed silently
    header = folder / "rosidl" / "c" / "dock_msgs" / "msg" / "detail" / "beacon__struct.h"
    header.write_text(header.read_text().replace("  double range;", "  float range;"))
    # a generated source changed, a file added
    fn = folder / "rosidl" / "c" / "dock_msgs" / "msg" / "detail" / "quality__functions.c"
    fn.write_text(fn.read_text() + "/* changed */\n")
    problems = dict(check_rosidl_folder(folder, [*files, "rosidl/c/dock_msgs/extra.h"],
                                        (folder / "dock.model").read_text(), ros2_install))
    name = "rosidl/c/dock_msgs/msg/detail/beacon__struct.h"
    assert "dock_msgs__msg__Beacon.range: declared float, the proved model carries float64" in problems[name]
    assert "differs" in problems["rosidl/c/dock_msgs/msg/detail/quality__functions.c"]
    assert "not a file rosidl's generators make" in problems["rosidl/c/dock_msgs/extra.h"]
    assert set(problems) == {name, "rosidl/c/dock_msgs/msg/detail/quality__functions.c",
                             "rosidl/c/dock_msgs/extra.h"}


MSGS = ["Beacon.msg", "DockCommand.msg", "Quality.msg"]


def test_dock_ros2_interface_package(dock2):
    """Next to the node's package, OUT/dock_msgs is dock_msgs's ROS 2
    interface package: its .msg files (the bytes rosidl built from), a
    package.xml of the rosidl_interface_packages group that depends on the
    packages its messages use, and a CMakeLists.txt whose ament branch
    generates the interfaces; the node's package depends on it."""
    import xml.etree.ElementTree as ET

    out = dock2.out_dir
    pkg = out / "dock_msgs"
    assert sorted(str(p.relative_to(pkg)) for p in pkg.rglob("*") if p.is_file()) == \
        ["CMakeLists.txt", *(f"msg/{m}" for m in MSGS), "package.xml"]
    for m in MSGS:
        assert (pkg / "msg" / m).read_bytes() == (out / "rosidl" / "interfaces" / "dock_msgs" / "msg" / m).read_bytes()
    xml = ET.parse(pkg / "package.xml").getroot()
    assert xml.get("format") == "3" and xml.findtext("name") == "dock_msgs"
    assert xml.findtext("member_of_group") == "rosidl_interface_packages"
    assert sorted(d.text for d in xml.findall("buildtool_depend")) == ["ament_cmake", "rosidl_default_generators"]
    assert [d.text for d in xml.findall("depend")] == ["std_msgs"]   # Beacon has a std_msgs/Header
    assert xml.findtext("exec_depend") == "rosidl_default_runtime"
    cmake = (pkg / "CMakeLists.txt").read_text()
    assert "rosidl_generate_interfaces(${PROJECT_NAME}\n" + "".join(f'    "msg/{m}"\n' for m in MSGS) + \
        "    DEPENDENCIES std_msgs\n  )" in cmake
    node_xml = ET.parse(out / "dock" / "package.xml").getroot()
    assert "dock_msgs" in [d.text for d in node_xml.findall("depend")]
    assert json.loads((out / "dock.manifest.json").read_text())["build"]["package"]["custom_pkgs"] == ["dock_msgs"]


def test_dock_ros2_package_builds_and_runs_without_ament(dock2, ros2_install, tmp_path, shm_guard):
    """The node's ament_cmake package builds with plain CMake against the
    wheels (no ament_cmake here: its fallback), its custom messages' C
    headers and libraries found in the build folder that holds it; the
    binary resolves them there, starts (its dock_msgs subscription and
    publisher created, which needs the type supports) and stops on SIGTERM.
    The interface package configures too (nothing to build without
    ament_cmake)."""
    out = dock2.out_dir
    env = {"PATH": "/usr/bin:/bin", "HOME": str(tmp_path)}
    for src, build in ((out / "dock", tmp_path / "b"), (out / "dock_msgs", tmp_path / "m")):
        r = subprocess.run(["cmake", "-S", str(src), "-B", str(build), f"-DPYROSGEN_ROS2_PREFIX={ros2_install.prefix}"],
                           capture_output=True, text=True, env=env, timeout=300)
        assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
    assert "dock_msgs: no ament_cmake" in r.stdout
    r = subprocess.run(["cmake", "--build", str(tmp_path / "b")], capture_output=True, text=True, env=env, timeout=600)
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
    exe = tmp_path / "b" / "dock"
    ldd = subprocess.run(["ldd", str(exe)], capture_output=True, text=True).stdout
    assert "not found" not in ldd, ldd
    for kind in ("generator_c", "typesupport_c", "typesupport_fastrtps_c", "typesupport_introspection_c"):
        assert f"libdock_msgs__rosidl_{kind}.so => {out / 'lib'}/" in ldd, (kind, ldd)
    node = spawn([exe], tmp_path / "node.log")
    try:
        import time

        time.sleep(2.0)
        assert node.poll() is None, (tmp_path / "node.log").read_text(errors="replace")[-2000:]
    finally:
        status = stop(node, signal.SIGTERM)
    assert status == 0, (tmp_path / "node.log").read_text(errors="replace")[-2000:]
    assert not (left := settled_leftovers()), left


def test_dock_ros2_cli_names_the_interface_package(tmp_path, capsys, ros2_install):
    """``pyrosgen build --ros2`` says where the custom types and their
    interface package are."""
    from pyrosgen import cli

    out = tmp_path / "out"
    assert cli.main(["build", str(MODEL), "--ros2", "-o", str(out)]) == 0
    text = capsys.readouterr().out
    assert f"  messages  custom types by rosidl in {out / 'lib'}; for rclpy: PYTHONPATH={out / 'python'}" in text
    assert f"  interface {out / 'dock_msgs'} (ROS 2 interface package, next to the node's package)" in text
    assert (out / "dock_msgs" / "package.xml").is_file()


def _package_check(folder):
    from pyrosgen.verify.package_check import check_package

    rec, files = read_manifest(folder / "dock.manifest.json")
    return check_package(folder, rec, files, (folder / "dock.model").read_text())


@pytest.mark.parametrize("tamper", ["msg-edited", "cmake-edited", "file-added", "record-without-it"])
def test_dock_ros2_interface_package_tampered(dock2, tmp_path, tamper):
    """``verify``'s package check renders the interface package again from
    its .msg files and holds these to the ones rosidl built: each tampering
    is refused, naming the file (the unchanged copy passes)."""
    folder = tmp_path / "dock"
    shutil.copytree(dock2.out_dir, folder, symlinks=True)
    assert _package_check(folder).ok
    pkg = folder / "dock_msgs"
    if tamper == "msg-edited":
        (pkg / "msg" / "Quality.msg").write_text((pkg / "msg" / "Quality.msg").read_text() + "float64 extra\n")
        says = "dock_msgs/msg/Quality.msg: not the file rosidl built"
    elif tamper == "cmake-edited":
        (pkg / "CMakeLists.txt").write_text((pkg / "CMakeLists.txt").read_text().replace(
            "  ament_package()", "  execute_process(COMMAND sh -c id)\n  ament_package()"))
        says = "dock_msgs/CMakeLists.txt: not rendered from its .msg files"
    elif tamper == "file-added":
        (pkg / "msg" / "Extra.msg").write_text("int32 x\n")
        says = "dock_msgs/msg/Extra.msg: not a file of the node's package"
    else:
        m = folder / "dock.manifest.json"
        data = json.loads(m.read_text())
        data["build"]["package"]["custom_pkgs"] = []
        m.write_text(json.dumps(data, indent=2, sort_keys=True) + "\n")
        says = "rosidl/interfaces/dock_msgs: a custom message package that the build record does not name"
    check = _package_check(folder)
    assert not check.ok
    assert any(says in d for d in check.details), check.details


def _dock_copy(tmp_path, msg_line: str | None = None, model_edit: tuple[str, str] | None = None):
    d = tmp_path / "dock"
    shutil.copytree(DOCK / "msg", d / "msg")
    text = MODEL.read_text()
    if model_edit:
        assert model_edit[0] in text
        text = text.replace(*model_edit)
    (d / "dock.yaml").write_text(text)
    if msg_line is not None:
        q = d / "msg" / "dock_msgs" / "msg" / "Quality.msg"
        q.write_text(q.read_text() + msg_line + "\n")
    return d / "dock.yaml"


@pytest.mark.parametrize("line, col, says", [
    ("time stamp", 1, "builtin_interfaces/Time (int32 sec, uint32 nanosec)"),
    ("duration[2] held", 1, "builtin_interfaces/Duration"),
    ("  Header header", 3, "write std_msgs/Header"),
    ("byte b", 1, "write int8 or uint8"),
    ("char c", 1, "deprecated in ROS 2"),
    ("float64 lastSeen", 9, "not a ROS 2 field name"),
], ids=["time", "duration", "Header", "byte", "char", "camelCase"])
def test_ros1_only_msg_refused_for_ros2(tmp_path, ros2_install, line, col, says):
    model = _dock_copy(tmp_path, line)
    ros1 = subprocess.run([sys.executable, "-m", "pyrosgen", "check", str(model)], capture_output=True, text=True)
    assert ros1.returncode == 0, ros1.stderr
    r = subprocess.run([sys.executable, "-m", "pyrosgen", "check", "--ros2", str(model)], capture_output=True,
                       text=True)
    assert r.returncode == 1 and "Traceback" not in r.stderr, r.stderr
    where = f"{model.parent / 'msg' / 'dock_msgs' / 'msg' / 'Quality.msg'}:4:{col}: error: "
    lines = [x for x in r.stderr.splitlines() if "Quality.msg" in x]
    assert len(lines) == 1 and lines[0].startswith(where) and says in lines[0] and lines[0].endswith("[rule 4.17]"), \
        r.stderr


def test_check_ros2_of_dock(ros2_install):
    """``check --ros2`` of examples/dock: ok, and no note about ROS 1's C++
    headers (a ROS 2 build uses rosidl's, from the wheels)."""
    r = subprocess.run([sys.executable, "-m", "pyrosgen", "check", "--ros2", str(MODEL)], capture_output=True,
                       text=True, cwd=str(rosutil.ROOT))
    assert r.returncode == 0 and "ok: node dock" in r.stdout, r.stderr
    assert r.stderr == "", r.stderr


def test_header_seq_of_custom_message_refused_for_ros2(tmp_path, ros2_install):
    model = _dock_copy(tmp_path, model_edit=("field: samples, derived: length, input: NS",
                                             "field: header.seq, input: NS"))
    with pytest.raises(InvalidNodeModel) as info:
        load_model_ros2(model, ros2_install)
    [d] = info.value.diagnostics
    line = next(i for i, x in enumerate(model.read_text().splitlines(), 1) if "header.seq" in x)
    assert (d.file, d.line, d.rule) == (str(model), line, "4.17") and d.col is not None
    assert "has no field 'seq'" in d.message and "the ROS 1 target accepts it" in d.message


def test_installed_package_name_refused_for_ros2(tmp_path, ros2_install):
    model = _dock_copy(tmp_path)
    shutil.copytree(model.parent / "msg" / "dock_msgs", model.parent / "msg" / "std_msgs")
    for f in (model.parent / "msg" / "std_msgs" / "msg").glob("*.msg"):
        f.rename(f.with_name("Dock" + f.name))
    with pytest.raises(InvalidNodeModel) as info:
        load_model_ros2(model, ros2_install)
    ds = [d for d in info.value.diagnostics if "package of the ROS 2 installation" in d.message]
    assert len(ds) == 3 and all(d.rule == "4.17" and d.file.endswith(".msg") for d in ds)


@pytest.mark.parametrize("name", ["rosidl", "dock"])
def test_custom_package_named_like_a_build_entry_refused(tmp_path, ros2_install, capsys, name):
    """The interface package is written next to the node's package
    (``OUT/<pkg>/``): a custom package named like an entry of the build
    folder or like the node's package is refused before anything is
    generated (exit 1, rule 4.17, naming the package's folder)."""
    from pyrosgen import cli

    model = _dock_copy(tmp_path)
    msg = model.parent / "msg"
    (msg / "dock_msgs").rename(msg / name)
    for f in [model, *(msg / name / "msg").glob("*.msg")]:
        f.write_text(f.read_text().replace("dock_msgs/", f"{name}/"))
    load_model_ros2(model, ros2_install)   # the front end accepts it
    out = tmp_path / "out"
    code = cli.main(["build", str(model), "--ros2", "-o", str(out)])
    err = capsys.readouterr().err
    assert code == 1 and not out.exists(), err
    assert f"{msg / name}: error: the custom message package '{name}' takes the name of " in err, err
    assert "[rule 4.17]" in err and "Traceback" not in err


def test_custom_packages_in_dependency_order(tmp_path):
    def msg(pkg, typ, text):
        f = tmp_path / pkg / "msg" / f"{typ}.msg"
        f.parent.mkdir(parents=True, exist_ok=True)
        f.write_text(text)
        return f
    a = msg("a_msgs", "A", "b_msgs/B b\nstd_msgs/Header header\nC c\n")
    c = msg("a_msgs", "C", "int32 x  # uses nothing\nint32 K=3\n")
    b = msg("b_msgs", "B", "float64[3] y\n")
    order, deps = _order({"a_msgs": [a, c], "b_msgs": [b]})
    assert order == ["b_msgs", "a_msgs"] and deps == {"a_msgs": {"b_msgs", "std_msgs"}, "b_msgs": set()}
    loop = msg("b_msgs", "D", "a_msgs/C c\n")
    with pytest.raises(InvalidNodeModel) as info:
        _order({"a_msgs": [a, c], "b_msgs": [b, loop]})
    assert "a_msgs -> b_msgs -> a_msgs" in info.value.diagnostics[0].message


def test_missing_generators_is_exit_2(tmp_path):
    (tmp_path / "lib" / "python3.11" / "site-packages").mkdir(parents=True)
    with pytest.raises(Ros2Missing) as info:
        _check_generators(Ros2Install(tmp_path))
    assert "make ros2-deps" in str(info.value) and "rosidl_adapter" in str(info.value)


def test_custom_message_with_ros2_types(tmp_path, ros2_install):
    """A custom message that uses ROS 2's builtin_interfaces/Time (which
    rosbags' ROS 1 parser takes for ROS 1's time) and geometry_msgs/Twist:
    read with ROS 2's definitions, nanosec and all."""
    model = _dock_copy(tmp_path, "builtin_interfaces/Time stamp\ngeometry_msgs/Twist cmd")
    m = load_model_ros2(model, ros2_install)
    by = {t.name: {f.name: (f.prim or f.msg) for f in t.fields} for t in m.messages}
    assert by["dock_msgs/Quality"] == {"level": "uint32", "snr": "float32", "stamp": "builtin_interfaces/Time",
                                       "cmd": "geometry_msgs/Twist"}
    assert by["builtin_interfaces/Time"] == {"sec": "int32", "nanosec": "uint32"}

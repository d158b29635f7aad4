"""``pyrosgen verify`` checks every file that goes into the node (issue 29):
the wrapper, the layout check and the catkin package are rendered again
from the proved model (and the manifest's build record) and compared byte
for byte.  Each tampering below rewrites the file's digest in the three
records (``<node>.sha256``, the manifest, the certificate), so that only
the package check can refuse it."""

from __future__ import annotations

import hashlib
import json
import shutil
import xml.etree.ElementTree as ET

import pytest

from .conftest import pyrosgen

NODE = "landshark_controller"
PKG = NODE


def _digests(copy, names) -> None:
    """Rewrite the digests of ``names`` in the manifest, the digest file and
    the certificate of the folder ``copy``."""
    m = copy / f"{NODE}.manifest.json"
    data = json.loads(m.read_text())
    cert = copy / f"{NODE}.certificate.md"
    text = cert.read_text()
    for name in names:
        new = hashlib.sha256((copy / name).read_bytes()).hexdigest()
        old = data["files"][name]
        text = text.replace(f"| `{name}` | `{old}` |", f"| `{name}` | `{new}` |")
        data["files"][name] = new
    cert.write_text(text)
    m.write_text(json.dumps(data, indent=2, sort_keys=True) + "\n")
    (copy / f"{NODE}.sha256").write_text("".join(f"{v}  {n}\n" for n, v in sorted(data["files"].items())))


def _tamper(out, copy, name: str, old: str, new: str):
    shutil.copytree(out, copy, symlinks=True)
    f = copy / name
    text = f.read_text()
    assert old in text, f"{name} changed shape: {old!r}"
    f.write_text(text.replace(old, new, 1))
    _digests(copy, [name])
    return copy


def _refused(folder, name: str) -> str:
    run = pyrosgen("verify", folder, "-q")
    assert run.returncode == 1, run.stdout + run.stderr
    assert "  ok      hashes" in run.stdout and "  ok      certificate" in run.stdout, run.stdout
    assert "  FAILED  package" in run.stdout, run.stdout
    lines = run.stdout.split("  FAILED  package", 1)[1]
    assert f"  {name}: " in lines, run.stdout
    assert "Traceback" not in run.stderr
    return run.stdout


def test_a_build_folder_verifies_with_its_package(landshark_build):
    _, out = landshark_build
    run = pyrosgen("verify", out, "-q")
    assert run.returncode == 0, run.stdout + run.stderr
    assert "  ok      package   14 files of the node rendered again from the proved model and equal" in run.stdout


# the wrapper mutations, in the top-level wrapper and in the package's copy
WRAPPER = f"{NODE}_ros.cpp"
MUTATIONS = {
    "publish dropped": ("g_pub_landshark_control_base_velocity.publish(r);", ";"),
    "sleep emptied": ("g_rate->sleep();", ";"),
    "ros_ok stops after 1,000 cycles": ("return ros::ok() ? 1 : 0;",
                                        "static int n = 0; return ros::ok() && ++n <= 1000 ? 1 : 0;"),
    "topic renamed": ('"/landshark/gps_velocity"', '"/landshark/gps_velocitx"'),
    "ros::Time conversion": ("c->sec = r.sec;", "c->sec = r.sec + 1;"),
    "has_header": ("ops.has_header = false;", "ops.has_header = true;"),
}


@pytest.mark.parametrize("where", [WRAPPER, f"{PKG}/src/{WRAPPER}"])
@pytest.mark.parametrize("mutation", sorted(MUTATIONS))
def test_wrapper_mutations_refused(landshark_build, tmp_path, where, mutation):
    _, out = landshark_build
    old, new = MUTATIONS[mutation]
    _refused(_tamper(out, tmp_path / "c", where, old, new), where)


@pytest.mark.parametrize("name, old, new", [
    (f"{PKG}/src/{NODE}_glue.c", "Controller_U.In1 = ", "Controller_U.In2 = "),
    (f"{PKG}/include/{NODE}_types.h", "double x;", "float x;"),
    (f"{PKG}/include/{NODE}_ros.h", "void ros_spinOnce(void);", "void ros_spinOnce(void); /* */"),
    (f"{PKG}/src/{NODE}_layout_check.c", "_Static_assert", "/* */ _Static_assert"),
    (f"{PKG}/CMakeLists.txt", ";-ffp-contract=off", ""),
    (f"{PKG}/package.xml", "<depend>roscpp</depend>", ""),
    (f"{PKG}/launch/{NODE}.launch", 'default="/landshark/gps_velocity"', 'default="/other"'),
    (f"{NODE}_layout_check.c", "_Static_assert", "/* */ _Static_assert"),
    (f"{PKG}/controller/Controller.c", "Controller_step(void)", "Controller_step(void) /* */"),
])
def test_package_files_refused(landshark_build, tmp_path, name, old, new):
    """The package's copies, its catkin files, the layout check and the
    package's copy of the controller (a hand-written one: held to the
    top-level copy, whose digest is recorded)."""
    _, out = landshark_build
    _refused(_tamper(out, tmp_path / "c", name, old, new), name)


def test_build_record_tampering_refused(landshark_build, tmp_path):
    """The build record is what the catkin files are rendered from: a record
    that says another maintainer than package.xml's, or no record at all,
    is refused."""
    _, out = landshark_build
    c = tmp_path / "c"
    shutil.copytree(out, c, symlinks=True)
    m = c / f"{NODE}.manifest.json"
    data = json.loads(m.read_text())
    data["build"]["package"]["maintainer"] = "Mallory <mallory@example.com>"
    m.write_text(json.dumps(data))
    _refused(c, f"{PKG}/package.xml")
    del data["build"]
    m.write_text(json.dumps(data))
    run = pyrosgen("verify", c, "-q")
    assert run.returncode == 1
    assert "  FAILED  package   the folder holds a build but the manifest has no build record" in run.stdout


def test_certificate_lists_the_compile_commands(landshark_build):
    _, out = landshark_build
    data = json.loads((out / f"{NODE}.manifest.json").read_text())
    cmds = data["build"]["commands"]
    glue = next(c for c in cmds if f"{NODE}_glue.c" in c)
    assert glue[:10] == ["gcc", "-std=c11", "-O2", "-Wall", "-Wextra", "-Werror", "-pedantic",
                         "-ffp-contract=off", "-fexcess-precision=standard", "-I"]
    assert not any(str(out) in w or "/tmp" in w or ".pyrosgen-build" in w for c in cmds for w in c)
    assert cmds[-1][-3:] != cmds[0][-3:] and "bin/" + NODE in cmds[-1]
    cert = (out / f"{NODE}.certificate.md").read_text()
    section = cert.split("## Compile commands", 1)[1].split("## Tools", 1)[0]
    assert " ".join(glue) in section
    assert "gcc -std=c11 -O2 -Wall -Wextra -I controller -c controller/Controller.c -o obj/controller_Controller.o" \
        in section


def test_launch_file_namespace_and_remaps(landshark_build):
    _, out = landshark_build
    text = (out / PKG / "launch" / f"{NODE}.launch").read_text()
    root = ET.fromstring(text.split("\n", 1)[1] if text.startswith("<?xml") else text)
    args = {a.get("name"): a.get("default") for a in root.findall("arg")}
    assert args["ns"] == "/"
    assert args["topic_landshark_gps_velocity"] == "/landshark/gps_velocity"
    assert args["topic_landshark_control_base_velocity"] == "/landshark_control/base_velocity"
    group = root.find("group")
    assert group.get("ns") == "$(arg ns)"
    remaps = {r.get("from"): r.get("to") for r in group.find("node").findall("remap")}
    assert remaps == {"/landshark/left_wheel_velocity": "$(arg topic_landshark_left_wheel_velocity)",
                      "/landshark/right_wheel_velocity": "$(arg topic_landshark_right_wheel_velocity)",
                      "/landshark/gps_velocity": "$(arg topic_landshark_gps_velocity)",
                      "/landshark_control/base_velocity": "$(arg topic_landshark_control_base_velocity)"}
    assert "not parameters: they are constants of the\n     proved model" in text


def test_maintainer_option(tmp_path):
    from pyrosgen.ros import wrapper

    from .conftest import LANDSHARK, LANDSHARK_CTL

    assert wrapper.parse_maintainer("Jane Doe <jane.doe@example.com>") == ("Jane Doe", "jane.doe@example.com")
    for bad in ("Jane", "Jane <jane>", "<a@b.c>", 'J"</maintainer><x> <a@b.c>', "Jane <a@b.c> ", "J\n <a@b.c>"):
        assert wrapper.parse_maintainer(bad) is None, bad
    run = pyrosgen("build", LANDSHARK, "--controller", LANDSHARK_CTL, "-o", tmp_path / "o", "-q",
                   "--maintainer", "Jane <jane>")
    assert run.returncode == 1 and "--maintainer Jane <jane>: not \"Name <email>\"" in run.stderr, run.stderr
    assert not (tmp_path / "o").exists()


def test_proved_node_renders_what_the_front_end_renders():
    """The wrapper rendered from the proved model alone is the one rendered
    from the front end's model, for every example model (strings,
    sequences, arrays, stamps included)."""
    from pyrosgen.frontend.validate import load_model
    from pyrosgen.proof.modeltext import model_text, parse_model_text
    from pyrosgen.ros import wrapper

    from .conftest import ROOT

    models = sorted((ROOT / "examples").rglob("*.yaml")) + sorted((ROOT / "tests").rglob("*.yaml"))
    n = 0
    for f in models:
        try:
            m = load_model(f)
        except Exception:  # not a node model (a fixture of the front-end tests)
            continue
        node = wrapper.proved_node(parse_model_text(model_text(m)), m.source.name)
        assert node.messages == tuple(m.messages), f
        assert wrapper.render_wrapper(node) == wrapper.render_wrapper(m), f
        assert node.controller.inputs == m.controller.inputs and node.controller.outputs == m.controller.outputs
        n += 1
    assert n >= 20


@pytest.mark.parametrize("where, value, message", [
    ("package", {"cflags": 5}, "cannot render the node's files again: build.package: not a record of the keys"),
    ("cflags", 5, "cannot render the node's files again: build.package.cflags: malformed"),
    ("include_dirs", ["include", "../../etc"], "refusing to print '../../etc' as a package-relative path"),
    ("custom_pkgs", ["../x"], "refusing to print '../x' as a C identifier"),
    ("maintainer", "x\" onload=\"y <a@b.c>", "refusing to print"),
])
def test_malformed_build_record_is_a_failed_check(landshark_build, tmp_path, where, value, message):
    """A build record of the wrong shape, or naming paths outside the
    package, fails the package check with what is wrong (exit 1, no
    traceback, nothing read or written outside the folder)."""
    _, out = landshark_build
    c = tmp_path / "c"
    shutil.copytree(out, c, symlinks=True)
    m = c / f"{NODE}.manifest.json"
    data = json.loads(m.read_text())
    if where == "package":
        data["build"]["package"] = value
    else:
        data["build"]["package"][where] = value
    m.write_text(json.dumps(data))
    run = pyrosgen("verify", c, "-q")
    assert run.returncode == 1, run.stdout + run.stderr
    assert "  FAILED  package" in run.stdout and message in run.stdout, run.stdout
    assert "Traceback" not in run.stderr and "internal error" not in run.stderr


def test_malformed_commands_fail_the_certificate_and_package_checks(landshark_build, tmp_path):
    _, out = landshark_build
    c = tmp_path / "c"
    shutil.copytree(out, c, symlinks=True)
    m = c / f"{NODE}.manifest.json"
    data = json.loads(m.read_text())
    data["build"]["commands"] = [["gcc", 1]]
    m.write_text(json.dumps(data))
    run = pyrosgen("verify", c, "-q")
    assert run.returncode == 1, run.stdout + run.stderr
    assert "  FAILED  certificate certificate: the manifest's build.commands is not a list of commands" in run.stdout
    assert "build.commands: not a list of commands" in run.stdout
    assert "Traceback" not in run.stderr


def test_certificate_lists_the_layout_check_calls(landshark_build):
    """Every gcc call of the build, the layout check's two syntax-only
    compilations included, with no temporary path."""
    _, out = landshark_build
    cmds = json.loads((out / f"{NODE}.manifest.json").read_text())["build"]["commands"]
    layout = [c for c in cmds if "-fsyntax-only" in c]
    assert [c[c.index("-I") + 1] for c in layout] == ["layout-reference", "controller"]
    assert all(c[-1] == f"{NODE}_layout_check.c" for c in layout)


def test_a_file_added_to_the_package_is_refused(landshark_build, tmp_path):
    """A header added to the package's include/ (listed in the manifest or
    not) would shadow a system header in the catkin build: refused."""
    _, out = landshark_build
    c = tmp_path / "c"
    shutil.copytree(out, c, symlinks=True)
    (c / PKG / "include" / "cstring").write_text("#error shadowed\n")
    (c / PKG / "src" / "etc").symlink_to("/etc")
    run = pyrosgen("verify", c, "-q")
    assert run.returncode == 1, run.stdout + run.stderr
    assert "  ok      hashes" in run.stdout, run.stdout
    lines = run.stdout.split("  FAILED  package", 1)[1]
    assert f"  {PKG}/include/cstring: not a file of the node's package" in lines
    assert f"  {PKG}/src/etc: not a file of the node's package" in lines


def test_an_embedded_coder_build_with_flags_verifies(tmp_path):
    """Subfolders, a C++ source, a left-out ert_main.c, user flags and an
    include folder: the package is rendered again from the build record,
    and a flag changed in CMakeLists.txt is refused."""
    from .conftest import LANDSHARK
    from .test_controller_folder import _folder

    d = _folder(tmp_path)
    inc = tmp_path / "vendor"
    inc.mkdir()
    out = tmp_path / "out"
    run = pyrosgen("build", LANDSHARK, "--controller", d, "-o", out, "-q", "--std=gnu99",
                   "--cflags=-DROBOT_VARIANT=2 -ffast-math", "--include", str(inc),
                   "--maintainer", "Jane Doe <jane.doe@example.com>")
    assert run.returncode == 0, run.stderr
    run = pyrosgen("verify", out, "-q")
    assert run.returncode == 0, run.stdout + run.stderr
    record = json.loads((out / f"{NODE}.manifest.json").read_text())["build"]["package"]
    assert record["cxx_sources"] == ["controller/helper.cpp"] and record["includes"] == [str(inc)]
    assert record["cflags"] == ["-DROBOT_VARIANT=2", "-ffast-math"] and record["generated"] is False
    c = _tamper(out, tmp_path / "c", f"{PKG}/CMakeLists.txt", ";-DROBOT_VARIANT=2;", ";-DROBOT_VARIANT=3;")
    _refused(c, f"{PKG}/CMakeLists.txt")

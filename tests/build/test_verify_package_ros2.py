"""``pyrosgen verify`` of a ``build --ros2`` folder renders the node's files
again from the proved model and the manifest's build record, by the
functions ``build --ros2`` renders them with, and compares them byte for
byte: the rcl wrapper and its API header, the layout check, the ament_cmake
package (its copies, ``package.xml``, ``CMakeLists.txt``, the launch file),
and no other file in the package.  Each tampering below rewrites the
file's digest in the three records (``<node>.sha256``, the manifest, the
certificate), so that only the package check can refuse it; each is
refused with exit 1, naming the file.  ``verify --rebuild`` compiles the
ROS 2 node again from the recorded commands, bit for bit."""

from __future__ import annotations

import json
import shutil

import pytest

from .conftest import LANDSHARK, LANDSHARK_CTL, pyrosgen
from .test_verify_package import _digests, _refused, _tamper

pytestmark = pytest.mark.ros2

NODE = PKG = "landshark_controller"
RCL = f"{NODE}_rcl.c"


@pytest.fixture(scope="module")
def ros2_build(tmp_path_factory):
    out = tmp_path_factory.mktemp("ros2build") / "landshark"
    run = pyrosgen("build", "--ros2", LANDSHARK, "--controller", LANDSHARK_CTL, "-o", out)
    assert run.returncode == 0, run.stderr
    return out


def test_a_ros2_build_folder_verifies_with_its_package(ros2_build):
    run = pyrosgen("verify", ros2_build, "-q")
    assert run.returncode == 0, run.stdout + run.stderr
    assert ("  ok      package   a ROS 2 build (target file as written by build --ros2): 14 files of the node "
            "(the rcl wrapper, the ament_cmake package) rendered again from the proved model and equal") in run.stdout


def test_verify_rebuild_compiles_the_ros2_node_again_bit_for_bit(ros2_build, tmp_path):
    run = pyrosgen("verify", ros2_build, "-q", "--rebuild")
    assert run.returncode == 0, run.stdout + run.stderr
    assert f"  ok      rebuild   bin/{NODE} rebuilt from the folder's files with the 4 recorded commands" in run.stdout
    # a binary that is not what the commands build is refused
    bad = tmp_path / "bad"
    shutil.copytree(ros2_build, bad, symlinks=True)
    b = bad / "bin" / NODE
    data = bytearray(b.read_bytes())
    data[-1] ^= 1
    b.write_bytes(bytes(data))
    _digests(bad, [f"bin/{NODE}"])
    run = pyrosgen("verify", bad, "-q", "--rebuild")
    assert run.returncode == 1 and "  FAILED  rebuild" in run.stdout, run.stdout + run.stderr


# one byte, a dependency, a remap, a flag: each in the file it belongs to
TAMPERINGS = {
    "a byte of the wrapper": (RCL, "rcl_publish(", "rcl_publish ("),
    "a byte of the package's wrapper": (f"{PKG}/src/{RCL}", "PYROSGEN_PERIOD_NS 20000000LL", "PYROSGEN_PERIOD_NS 20000001LL"),
    "another dependency": (f"{PKG}/package.xml", "  <depend>rcl</depend>\n", "  <depend>rcl</depend>\n  <depend>rclcpp</depend>\n"),
    "another remap": (f"{PKG}/launch/{NODE}.launch.xml", 'to="$(var topic_landshark_gps_velocity)"',
                      'to="/spoofed/gps_velocity"'),
    "a fast-math glue": (f"{PKG}/CMakeLists.txt", "-ffp-contract=off", "-ffast-math"),
    "the wheels' rpath dropped": (f"{PKG}/CMakeLists.txt", '"LINKER:--disable-new-dtags"', '"LINKER:--enable-new-dtags"'),
    "the API header": (f"{NODE}_ros.h", "void ros_rate_sleep(void);", "void ros_rate_sleep(void); void x(void);"),
}


@pytest.mark.parametrize("case", sorted(TAMPERINGS))
def test_a_tampered_ros2_file_is_refused(ros2_build, tmp_path, case):
    name, old, new = TAMPERINGS[case]
    bad = _tamper(ros2_build, tmp_path / "bad", name, old, new)
    _refused(bad, name)


def test_an_extra_file_in_the_ros2_package_is_refused(ros2_build, tmp_path):
    bad = tmp_path / "bad"
    shutil.copytree(ros2_build, bad, symlinks=True)
    extra = bad / PKG / "include" / "rcl" / "rcl.h"
    extra.parent.mkdir(parents=True)
    extra.write_text("#error shadowed\n")
    # not listed in the manifest, and listed: refused either way
    _refused(bad, f"{PKG}/include/rcl/rcl.h")
    m = bad / f"{NODE}.manifest.json"
    data = json.loads(m.read_text())
    data["files"][f"{PKG}/include/rcl/rcl.h"] = "0" * 64
    m.write_text(json.dumps(data, indent=2, sort_keys=True) + "\n")
    _digests(bad, [f"{PKG}/include/rcl/rcl.h"])
    run = pyrosgen("verify", bad, "-q")
    assert run.returncode == 1 and "  ok      hashes" in run.stdout, run.stdout + run.stderr
    assert f"  {PKG}/include/rcl/rcl.h: not a file of the node's package" in run.stdout.split("FAILED  package")[1]


def test_a_second_package_in_a_ros2_folder_is_refused(ros2_build, tmp_path):
    """A ROS 2 build writes one package: another package.xml in the folder,
    even listed in the manifest with its digest, is refused."""
    bad = tmp_path / "bad"
    shutil.copytree(ros2_build, bad, symlinks=True)
    other = bad / "other_pkg" / "package.xml"
    other.parent.mkdir()
    shutil.copyfile(bad / PKG / "package.xml", other)
    m = bad / f"{NODE}.manifest.json"
    data = json.loads(m.read_text())
    data["files"]["other_pkg/package.xml"] = "0" * 64
    m.write_text(json.dumps(data, indent=2, sort_keys=True) + "\n")
    _digests(bad, ["other_pkg/package.xml"])
    run = pyrosgen("verify", bad, "-q")
    assert run.returncode == 1 and "  ok      hashes" in run.stdout, run.stdout + run.stderr
    assert "  other_pkg/package.xml: a package file outside the node's package" in run.stdout, run.stdout


def test_a_ros2_build_record_of_another_maintainer_is_refused(ros2_build, tmp_path):
    """The build record is what package.xml is rendered from: a record
    changed under an unchanged package.xml does not render it."""
    bad = tmp_path / "bad"
    shutil.copytree(ros2_build, bad, symlinks=True)
    m = bad / f"{NODE}.manifest.json"
    data = json.loads(m.read_text())
    data["build"]["package"]["maintainer"] = "Mallory <mallory@example.com>"
    m.write_text(json.dumps(data, indent=2, sort_keys=True) + "\n")
    run = pyrosgen("verify", bad, "-q")
    assert run.returncode == 1 and f"  {PKG}/package.xml: not rendered" in run.stdout, run.stdout + run.stderr
    assert "Traceback" not in run.stderr


@pytest.mark.parametrize("value, message", [
    (["../x"], "refusing to print '../x' as a C identifier"),
    ("geometry_msgs", "build.package.custom_pkgs: malformed"),
    (5, "cannot render the node's files again"),
    (["geometry_msgs"], f"{PKG}/CMakeLists.txt: not rendered"),
    (["nope_msgs"], "custom_pkgs: 'nope_msgs' is not a message package of the node"),
], ids=["path", "string", "number", "installed-package", "unused-package"])
def test_a_ros2_record_with_hostile_custom_pkgs_is_refused(ros2_build, tmp_path, value, message):
    """The record's custom message packages (rule 4.17: the interface
    packages written next to the node's) of the wrong shape, naming a path,
    or naming an installed package: the package check fails saying so
    (exit 1, no traceback, nothing read outside the folder)."""
    bad = tmp_path / "bad"
    shutil.copytree(ros2_build, bad, symlinks=True)
    m = bad / f"{NODE}.manifest.json"
    data = json.loads(m.read_text())
    data["build"]["package"]["custom_pkgs"] = value
    m.write_text(json.dumps(data, indent=2, sort_keys=True) + "\n")
    run = pyrosgen("verify", bad, "-q")
    assert run.returncode == 1 and "  FAILED  package" in run.stdout, run.stdout + run.stderr
    assert message in run.stdout, run.stdout
    assert "Traceback" not in run.stderr and "internal error" not in run.stderr


def test_a_ros2_folder_without_its_build_record_is_refused(ros2_build, tmp_path):
    bad = tmp_path / "bad"
    shutil.copytree(ros2_build, bad, symlinks=True)
    m = bad / f"{NODE}.manifest.json"
    data = json.loads(m.read_text())
    data["build"].pop("target")
    m.write_text(json.dumps(data, indent=2, sort_keys=True) + "\n")
    run = pyrosgen("verify", bad, "-q")
    assert run.returncode == 1 and "no ROS 2 build record" in run.stdout, run.stdout + run.stderr


def test_a_ros1_folder_built_again_for_ros2_holds_no_ros1_file(tmp_path):
    """Both targets' builds keep one stamp file, so a ROS 2 build into a
    folder of a ROS 1 build removes what only the ROS 1 build wrote (the
    roscpp wrapper, the catkin launch file) and the folder verifies."""
    out = tmp_path / "out"
    run = pyrosgen("build", LANDSHARK, "--controller", LANDSHARK_CTL, "-o", out)
    assert run.returncode == 0, run.stderr
    assert (out / f"{NODE}_ros.cpp").is_file() and (out / PKG / "launch" / f"{NODE}.launch").is_file()
    run = pyrosgen("build", "--ros2", LANDSHARK, "--controller", LANDSHARK_CTL, "-o", out)
    assert run.returncode == 0, run.stderr
    assert "proof reused" not in run.stderr  # the ROS 1 proof is not the ROS 2 one
    assert not (out / f"{NODE}_ros.cpp").exists() and not (out / PKG / "launch" / f"{NODE}.launch").exists()
    assert (out / PKG / "launch" / f"{NODE}.launch.xml").is_file()
    run = pyrosgen("verify", out, "-q")
    assert run.returncode == 0, run.stdout + run.stderr


def test_a_second_ros2_build_reuses_the_proof_and_the_objects(ros2_build, tmp_path):
    """As for ROS 1: building again into the folder reuses the proof and
    every object and the binary (the same inputs), and the folder still
    verifies, the binary too (--rebuild)."""
    out = tmp_path / "again"
    shutil.copytree(ros2_build, out, symlinks=True)
    run = pyrosgen("build", "--ros2", LANDSHARK, "--controller", LANDSHARK_CTL, "-o", out)
    assert run.returncode == 0, run.stderr
    assert "generate: proof reused from" in run.stderr, run.stderr
    assert run.stderr.count("unchanged, reusing obj/") == 3 and f"objects unchanged, reusing bin/{NODE}" in run.stderr
    assert "  files     0 written" in run.stdout, run.stdout
    run = pyrosgen("verify", out, "-q", "--rebuild")
    assert run.returncode == 0, run.stdout + run.stderr

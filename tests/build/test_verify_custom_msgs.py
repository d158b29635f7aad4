"""``pyrosgen verify`` of a build with custom messages (examples/multi):
the message package is rendered again from its ``.msg`` files, and each
``.msg`` declares every field the proved model carries, with its type
(a changed type would compile: C++ converts ``double`` to ``float``)."""

from __future__ import annotations

import hashlib
import json
import shutil

import pytest

from .conftest import MULTI, MULTI_CTL, pyrosgen

NODE = "multi_node"


@pytest.fixture(scope="module")
def multi_build(tmp_path_factory):
    out = tmp_path_factory.mktemp("multi") / "out"
    run = pyrosgen("build", MULTI, "--controller", MULTI_CTL, "-o", out, "-q")
    assert run.returncode == 0, run.stderr
    return out


def _tampered(out, copy, edits: dict[str, tuple[str, str]]):
    """A copy of ``out`` with each file's ``old`` replaced by ``new``, its
    digests rewritten in the manifest, the digest file and the certificate."""
    shutil.copytree(out, copy, symlinks=True)
    m = copy / f"{NODE}.manifest.json"
    data = json.loads(m.read_text())
    cert = copy / f"{NODE}.certificate.md"
    text = cert.read_text()
    for name, (old, new) in edits.items():
        f = copy / name
        assert old in f.read_text(), (name, old)
        f.write_text(f.read_text().replace(old, new, 1))
        digest = hashlib.sha256(f.read_bytes()).hexdigest()
        text = text.replace(f"| `{name}` | `{data['files'][name]}` |", f"| `{name}` | `{digest}` |")
        data["files"][name] = digest
    cert.write_text(text)
    m.write_text(json.dumps(data, indent=2, sort_keys=True) + "\n")
    (copy / f"{NODE}.sha256").write_text("".join(f"{v}  {n}\n" for n, v in sorted(data["files"].items())))
    return copy


def _package_lines(folder) -> str:
    run = pyrosgen("verify", folder, "-q")
    assert run.returncode == 1, run.stdout + run.stderr
    assert "  ok      hashes" in run.stdout and "  ok      certificate" in run.stdout, run.stdout
    assert "  FAILED  package" in run.stdout, run.stdout
    return run.stdout.split("  FAILED  package", 1)[1]


def test_multi_verifies_with_its_message_package(multi_build):
    run = pyrosgen("verify", multi_build, "-q")
    assert run.returncode == 0, run.stdout + run.stderr
    assert "  ok      package   16 files of the node rendered again" in run.stdout


def test_message_package_files_refused(multi_build, tmp_path):
    c = _tampered(multi_build, tmp_path / "c", {"robot_msgs/package.xml": ("<depend>", "<!-- --><depend>")})
    assert "  robot_msgs/package.xml: not rendered from its .msg files" in _package_lines(c)


def test_msg_types_changed_refused(multi_build, tmp_path):
    c = _tampered(multi_build, tmp_path / "c", {
        "robot_msgs/msg/FusionStatus.msg": ("float64 yaw_variance", "float32 yaw_variance"),
        "robot_msgs/msg/WheelState.msg": ("float32 velocity", "float64 velocity"),
    })
    lines = _package_lines(c)
    assert ("  robot_msgs/msg/FusionStatus.msg: field yaw_variance: declared float32, the proved model carries "
            "float64") in lines
    assert ("  robot_msgs/msg/WheelState.msg: field velocity: declared float64, the proved model carries "
            "float32") in lines


def test_msg_field_dropped_or_array_resized_refused(multi_build, tmp_path):
    c = _tampered(multi_build, tmp_path / "c", {
        "robot_msgs/msg/FusionStatus.msg": ("WheelState[2] wheels", "WheelState[3] wheels"),
        "robot_msgs/msg/EStop.msg": ("bool engaged", "bool engaged_now"),
    })
    lines = _package_lines(c)
    assert ("field wheels: declared robot_msgs/WheelState[3], the proved model carries robot_msgs/WheelState[2]"
            in lines)
    assert "  robot_msgs/msg/EStop.msg: field engaged: not declared, the proved model carries bool" in lines


def test_msg_comments_and_uncarried_fields_are_free(multi_build, tmp_path):
    """What the proved model does not carry may change (a comment, a
    string the glue drops): the node reads the same fields."""
    c = _tampered(multi_build, tmp_path / "c", {
        "robot_msgs/msg/FusionStatus.msg": ("string note             # not carried",
                                            "string note             # not carried, a new comment"),
    })
    run = pyrosgen("verify", c, "-q")
    assert run.returncode == 0, run.stdout + run.stderr

"""The certificate of a ``build`` folder covers what the build added, and
``pyrosgen verify`` checks the wrapper against the proved model."""

from __future__ import annotations

import hashlib
import json
import shutil
import subprocess

from .conftest import pyrosgen

NODE = "landshark_controller"


def test_certificate_covers_the_build(landshark_build):
    _, out = landshark_build
    files = json.loads((out / f"{NODE}.manifest.json").read_text())["files"]
    for name in (f"bin/{NODE}", f"{NODE}_ros.cpp", f"{NODE}_ros.h", f"{NODE}_layout_check.c",
                 "controller/Controller.c", "controller/Controller.h", f"{NODE}/CMakeLists.txt", f"{NODE}/package.xml",
                 f"{NODE}.v", f"{NODE}_glue.c"):
        assert files[name] == hashlib.sha256((out / name).read_bytes()).hexdigest(), name
    assert not any(n.startswith("obj/") for n in files)
    cert = (out / f"{NODE}.certificate.md").read_text()
    assert f"| `bin/{NODE}` | `{files[f'bin/{NODE}']}` |" in cert
    ok = subprocess.run(["sha256sum", "-c", f"{NODE}.sha256"], cwd=out, capture_output=True, text=True)
    assert ok.returncode == 0 and ok.stdout.count(": OK") == len(files), ok.stdout + ok.stderr


def _tampered(out, copy, name: str, old: str, new: str):
    """A copy of build folder ``out`` with ``old`` replaced by ``new`` in
    file ``name``, its digests updated (only the checks can refuse it)."""
    shutil.copytree(out, copy, symlinks=True)
    f = copy / name
    text = f.read_text()
    assert old in text
    f.write_text(text.replace(old, new))
    m = copy / f"{NODE}.manifest.json"
    data = json.loads(m.read_text())
    data["files"][name] = hashlib.sha256(f.read_bytes()).hexdigest()
    m.write_text(json.dumps(data))
    (copy / f"{NODE}.sha256").write_text("".join(f"{v}  {n}\n" for n, v in sorted(data["files"].items())))
    return copy


def test_verify_a_build_folder(landshark_build, tmp_path):
    _, out = landshark_build
    run = pyrosgen("verify", out, "-q")
    assert run.returncode == 0, run.stdout + run.stderr
    assert ("  ok      wrapper   registers, sleeps and tells the time as the proved model says, "
            "and declares the glue's ROS functions with its types") in run.stdout
    # a wrapper that subscribes with another queue size, digests updated
    c = _tampered(out, tmp_path / "c", f"{NODE}_ros.cpp",
                  '("/landshark/gps_velocity", 1, f)', '("/landshark/gps_velocity", 2, f)')
    run = pyrosgen("verify", c, "-q")
    assert run.returncode == 1
    assert "  FAILED  wrapper" in run.stdout and "/landshark/gps_velocity" in run.stdout, run.stdout
    assert "  ok      hashes" in run.stdout
    # a header that declares a ROS function with another type than the glue's
    h = _tampered(out, tmp_path / "h", f"{NODE}_ros.h", "void ros_spinOnce(void);", "int ros_spinOnce(void);")
    run = pyrosgen("verify", h, "-q")
    assert run.returncode == 1
    assert "  FAILED  wrapper" in run.stdout and "ros_spinOnce" in run.stdout, run.stdout


def test_build_into_a_mount_point(mount_point):
    """``-o`` a mount point: the staged build is copied into it."""
    from .conftest import LANDSHARK, LANDSHARK_CTL

    run = pyrosgen("build", LANDSHARK, "--controller", LANDSHARK_CTL, "-o", mount_point, "-q")
    assert run.returncode == 0, run.stderr
    assert (mount_point / "bin" / NODE).stat().st_mode & 0o100
    run = pyrosgen("verify", mount_point, "-q")
    assert run.returncode == 0, run.stdout + run.stderr
    assert not [p for p in mount_point.rglob(".*pyrosgen-tmp")]

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


def test_verify_a_build_folder(landshark_build, tmp_path):
    _, out = landshark_build
    run = pyrosgen("verify", out, "-q")
    assert run.returncode == 0, run.stdout + run.stderr
    assert ("  ok      wrapper   registers, sleeps and tells the time as the proved model says, "
            "and declares the glue's ROS functions with its types") in run.stdout
    # a wrapper that subscribes with another queue size, digests updated
    c = tmp_path / "c"
    shutil.copytree(out, c, symlinks=True)
    cpp = c / f"{NODE}_ros.cpp"
    text = cpp.read_text()
    assert '("/landshark/gps_velocity", 1, f)' in text
    cpp.write_text(text.replace('("/landshark/gps_velocity", 1, f)', '("/landshark/gps_velocity", 2, f)'))
    m = c / f"{NODE}.manifest.json"
    data = json.loads(m.read_text())
    data["files"][cpp.name] = hashlib.sha256(cpp.read_bytes()).hexdigest()
    m.write_text(json.dumps(data))
    (c / f"{NODE}.sha256").write_text("".join(f"{v}  {n}\n" for n, v in sorted(data["files"].items())))
    run = pyrosgen("verify", c, "-q")
    assert run.returncode == 1
    assert "  FAILED  wrapper" in run.stdout and "/landshark/gps_velocity" in run.stdout, run.stdout
    assert "  ok      hashes" in run.stdout
    # a header that declares a ROS function with another type than the glue's
    h = tmp_path / "h"
    shutil.copytree(out, h, symlinks=True)
    hdr = h / f"{NODE}_ros.h"
    text = hdr.read_text()
    assert "void ros_spinOnce(void);" in text
    hdr.write_text(text.replace("void ros_spinOnce(void);", "int ros_spinOnce(void);"))
    m = h / f"{NODE}.manifest.json"
    data = json.loads(m.read_text())
    data["files"][hdr.name] = hashlib.sha256(hdr.read_bytes()).hexdigest()
    m.write_text(json.dumps(data))
    (h / f"{NODE}.sha256").write_text("".join(f"{v}  {n}\n" for n, v in sorted(data["files"].items())))
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

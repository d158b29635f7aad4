"""Compile flags cannot change what was proved: flags that change
floating-point semantics are refused for a generated (block-diagram)
controller and at link time, ``-ffp-contract=off`` is always passed for the
glue and a generated controller (issue 29)."""

from __future__ import annotations

import subprocess

import pytest

from pyrosgen.ros.build import BuildError, ControllerOptions, check_flags

from .conftest import LANDSHARK, LANDSHARK_CTL, ROOT, pyrosgen

DIAGRAM = ROOT / "examples" / "landshark" / "landshark_diagram.yaml"
NODE = "landshark_controller"


@pytest.fixture(scope="module")
def haswell(tmp_path_factory):
    """The diagram controller built with ``--std gnu11 --cflags=-march=haswell``."""
    out = tmp_path_factory.mktemp("haswell") / "out"
    run = pyrosgen("build", DIAGRAM, "--std", "gnu11", "--cflags=-march=haswell", "-o", out, "-q")
    assert run.returncode == 0, run.stderr
    return out


def _fmas(obj) -> int:
    r = subprocess.run(["objdump", "-d", str(obj)], capture_output=True, text=True, check=True)
    return r.stdout.count("vfmadd") + r.stdout.count("vfmsub") + r.stdout.count("vfnmadd")


def test_march_haswell_fuses_nothing(haswell, tmp_path):
    """-march=haswell has fused multiply-adds; -ffp-contract=off, passed
    after the user's flags, keeps every a*b+c rounded twice."""
    assert _fmas(haswell / "obj" / "controller_Controller.o") == 0
    assert _fmas(haswell / "obj" / f"{NODE}_glue.o") == 0
    # the same source and flags without -ffp-contract=off do fuse (the check can fail)
    plain = tmp_path / "plain.o"
    subprocess.run(["gcc", "-std=gnu11", "-O2", "-march=haswell", "-I", str(haswell / "controller"), "-c",
                    str(haswell / "controller" / "Controller.c"), "-o", str(plain)], check=True)
    assert _fmas(plain) > 0
    # the catkin package compiles it the same way
    cmake = (haswell / NODE / "CMakeLists.txt").read_text()
    assert '"-std=gnu11;-O2;-Wall;-Wextra;-march=haswell;-ffp-contract=off;-fexcess-precision=standard"' in cmake
    assert ";-pedantic;-ffp-contract=off;-fexcess-precision=standard\")" in cmake


@pytest.mark.parametrize("flag, reason", [
    ("-ffast-math", "turns on -funsafe-math-optimizations"),
    ("-Ofast", "turns on -ffast-math"),
    ("-ffp-contract=fast", "fused multiply-add"),
    ("-fno-signed-zeros", "sign of zero"),
    ("-ffinite-math-only", "no NaN or infinity"),
    ("-DController_step=x", "defines a macro"),
    ("-mfpmath=387", "80-bit"),
])
def test_fp_flags_refused_for_a_generated_controller(flag, reason, tmp_path):
    out = tmp_path / "out"
    run = pyrosgen("build", DIAGRAM, f"--cflags=-O3 {flag}", "-o", out, "-q")
    assert run.returncode == 1, run.stderr
    assert f"--cflags: {flag}: refused: it " in run.stderr and reason in run.stderr, run.stderr
    assert "[DESIGN.md section 7, compile flags]" in run.stderr
    assert "Traceback" not in run.stderr and not out.exists()


def test_fast_math_link_refused_for_any_controller(tmp_path):
    """Linking with -ffast-math adds crtfastmath.o (flush-to-zero for the
    whole process, the glue included): refused even for a hand-written controller."""
    out = tmp_path / "out"
    run = pyrosgen("build", LANDSHARK, "--controller", LANDSHARK_CTL, "--ldflags=-ffast-math", "-o", out, "-q")
    assert run.returncode == 1
    assert "--ldflags: -ffast-math: refused" in run.stderr and "the proved glue" in run.stderr, run.stderr
    assert not out.exists()


def test_hand_written_controller_flags_are_the_users():
    """A hand-written controller's --cflags are the user's (the certificate
    lists them); only a generated controller's are checked."""
    opts = ControllerOptions(cflags=("-ffast-math", "-DX=1"))
    check_flags(opts, generated=False)
    with pytest.raises(BuildError, match="-ffast-math: refused"):
        check_flags(opts, generated=True)
    # allowed for a generated controller: target selection and the rounding-mode flag
    check_flags(ControllerOptions(cflags=("-march=haswell", "-mtune=native", "-mfma", "-O3",
                                          "-fno-rounding-math", "-ffp-contract=off")), generated=True)


def test_verify_refuses_a_record_with_fast_math(haswell, tmp_path):
    """A folder whose build record and CMakeLists.txt say -ffast-math for
    the generated controller (digests rewritten) does not verify: the
    flags are checked again, not only the bytes."""
    import hashlib
    import json
    import shutil

    c = tmp_path / "c"
    shutil.copytree(haswell, c, symlinks=True)
    cmake = c / NODE / "CMakeLists.txt"
    cmake.write_text(cmake.read_text().replace(";-march=haswell;", ";-march=haswell;-ffast-math;"))
    m = c / f"{NODE}.manifest.json"
    data = json.loads(m.read_text())
    data["build"]["package"]["cflags"].append("-ffast-math")
    name = f"{NODE}/CMakeLists.txt"
    old, new = data["files"][name], hashlib.sha256(cmake.read_bytes()).hexdigest()
    data["files"][name] = new
    m.write_text(json.dumps(data))
    (c / f"{NODE}.sha256").write_text("".join(f"{v}  {n}\n" for n, v in sorted(data["files"].items())))
    cert = c / f"{NODE}.certificate.md"
    cert.write_text(cert.read_text().replace(old, new))
    run = pyrosgen("verify", c, "-q")
    assert run.returncode == 1, run.stdout
    assert "  ok      hashes" in run.stdout and "  ok      certificate" in run.stdout, run.stdout
    assert "  FAILED  package" in run.stdout
    assert "build.package: --cflags: -ffast-math: refused" in run.stdout, run.stdout


def test_certificate_of_a_generated_controller_lists_its_flags(haswell):
    cert = (haswell / f"{NODE}.certificate.md").read_text()
    section = cert.split("## Compile commands", 1)[1].split("## Tools", 1)[0]
    assert ("gcc -std=gnu11 -O2 -Wall -Wextra -march=haswell -ffp-contract=off -fexcess-precision=standard "
            "-I controller -c controller/Controller.c -o obj/controller_Controller.o") in section
    assert "The controller's own flags are the user's" not in section
    run = pyrosgen("verify", haswell, "-q")
    assert run.returncode == 0, run.stdout + run.stderr
    assert "the glue and the generated controller compiled with -ffp-contract=off" in run.stdout

"""``pyrosgen build``: what OUT holds, progress and exit codes, the object
cache, nothing partial on failure, the catkin package."""

from __future__ import annotations

import json
import os
import re
import shutil
import stat
import subprocess
from pathlib import Path

from pyrosgen.ros.build import STAMP

from .conftest import LANDSHARK, LANDSHARK_CTL, MULTI, ROOT, pyrosgen, snapshot

NODE = "landshark_controller"
#: What build adds to generate's files (listed on the "generated" line).
PKG = f"{NODE}/"  # the catkin package: sources only
BUILD_FILES = {
    ".pyrosgen-build.json",
    PKG + "package.xml", PKG + "CMakeLists.txt", PKG + f"launch/{NODE}.launch",
    PKG + f"src/{NODE}_glue.c", PKG + f"src/{NODE}_ros.cpp", PKG + f"src/{NODE}_layout_check.c",
    PKG + f"include/{NODE}_types.h", PKG + f"include/{NODE}_ros.h",
    PKG + "controller/Controller.c", PKG + "controller/Controller.h", PKG + "controller/rtwtypes.h",
    f"{NODE}_ros.h", f"{NODE}_ros.cpp", f"{NODE}_layout_check.c",
    "controller/Controller.c", "controller/Controller.h", "controller/rtwtypes.h",
    f"obj/{NODE}_glue.o", f"obj/{NODE}_ros.o", "obj/controller_Controller.o", f"bin/{NODE}",
}


def _line(stdout: str, key: str) -> str:
    for line in stdout.splitlines():
        if line.startswith(f"  {key} "):
            return line[len(key) + 2:].strip()
    raise AssertionError(f"no {key} line in:\n{stdout}")


def _leftovers(parent: Path) -> list[str]:
    return [p.name for p in parent.iterdir() if p.name.startswith(".pyrosgen-")]


def test_build_writes_a_node(landshark_build):
    run, out = landshark_build
    files = {str(p.relative_to(out)) for p in out.rglob("*") if p.is_file()}
    generated = set(_line(run.stdout, "generated").split(", "))
    assert {f"{NODE}.v", f"{NODE}_types.h", f"{NODE}_glue.c", f"{NODE}.sexp"} <= generated
    assert files == BUILD_FILES | generated
    binary = out / "bin" / NODE
    assert binary.stat().st_mode & stat.S_IXUSR
    assert subprocess.run(["file", str(binary)], capture_output=True, text=True).stdout.count("ELF") == 1
    for k in range(1, 9):
        assert f"pyrosgen: [{k}/8] " in run.stderr, run.stderr
    assert f"built node {NODE} into {out}" in run.stdout
    assert f"theorem   {NODE}_ddc" in run.stdout and "Closed under the global context" in run.stdout
    assert not _leftovers(out.parent)
    stamp = json.loads((out / STAMP).read_text())
    assert set(stamp["entries"]) == {f"obj/{NODE}_glue.o", f"obj/{NODE}_ros.o", "obj/controller_Controller.o", f"bin/{NODE}"}
    assert set(stamp["files"]) == files
    # the controller copy is the user's controller
    for name in ("Controller.c", "Controller.h", "rtwtypes.h"):
        assert (out / "controller" / name).read_bytes() == (LANDSHARK_CTL / name).read_bytes()
    # the binary links the glue, the wrapper and the controller
    syms = subprocess.run(["nm", str(binary)], capture_output=True, text=True).stdout
    for sym in ("input_glue", "loop", "Controller_step", "ros_publish_landshark_control_base_velocity"):
        assert f" T {sym}\n" in syms, sym


def test_layout_check_file_is_the_coq_structs_renamed(landshark_build):
    _, out = landshark_build
    check = (out / f"{NODE}_layout_check.c").read_text()
    assert '#include "Controller.h"' in check
    types_h = (out / f"{NODE}_types.h").read_text()
    for line in types_h.splitlines():
        if line.startswith("struct ") and line.endswith("{"):
            assert line.replace("struct ", "struct pyrosgen_glue_") in check
    for field in ("Controller_U.In1", "Controller_U.In2", "Controller_U.In3", "Controller_Y.Out1"):
        assert f'"pyrosgen layout: {field}: offset differs from the glue struct' in check
        assert f'"pyrosgen layout: {field}: type is not double' in check


def test_rebuild_reuses_everything(landshark_build, tmp_path):
    _, out = landshark_build
    copy = tmp_path / "out"
    shutil.copytree(out, copy)
    before = snapshot(copy)
    mtimes = {p: p.stat().st_mtime_ns for p in copy.rglob("*") if p.is_file()}
    run = pyrosgen("build", LANDSHARK, "--controller", LANDSHARK_CTL, "-o", copy)
    assert run.returncode == 0, run.stderr
    assert "compiled  nothing (all up to date)" in run.stdout
    assert "[5/8] compile glue: landshark_controller_glue.c unchanged, reusing" in run.stderr
    assert snapshot(copy) == before
    assert {p: p.stat().st_mtime_ns for p in copy.rglob("*") if p.is_file()} == mtimes


def test_controller_change_recompiles_only_the_controller(landshark_build, tmp_path):
    _, out = landshark_build
    copy = tmp_path / "out"
    shutil.copytree(out, copy)
    ctl = tmp_path / "ctl"
    shutil.copytree(LANDSHARK_CTL, ctl)
    src = ctl / "Controller.c"
    src.write_text(src.read_text() + "\nint Controller_marker(void);\nint Controller_marker(void) { return 42; }\n")
    run = pyrosgen("build", LANDSHARK, "--controller", ctl, "-o", copy)
    assert run.returncode == 0, run.stderr
    assert "compiled  obj/controller_Controller.o, bin/landshark_controller" in run.stdout
    assert f"reused    obj/{NODE}_glue.o, obj/{NODE}_ros.o" in run.stdout
    assert (copy / "controller" / "Controller.c").read_bytes() == src.read_bytes()
    syms = subprocess.run(["nm", str(copy / "bin" / NODE)], capture_output=True, text=True).stdout
    assert " T Controller_marker\n" in syms


def test_catkin_package_holds_only_sources(landshark_build, tmp_path):
    """OUT/<package>/: package.xml, CMakeLists.txt, src/, include/,
    controller/, launch/ -- no object, binary or proof file; its sources are
    the ones pyrosgen built the node from; it configures with cmake."""
    _, out = landshark_build
    pkg = out / NODE
    for p in pkg.rglob("*"):
        assert p.is_dir() or p.suffix in (".xml", ".txt", ".c", ".cpp", ".h", ".launch"), p
    for name, rel in ((f"{NODE}_glue.c", "src"), (f"{NODE}_ros.cpp", "src"), (f"{NODE}_layout_check.c", "src"),
                      (f"{NODE}_types.h", "include"), (f"{NODE}_ros.h", "include")):
        assert (pkg / rel / name).read_bytes() == (out / name).read_bytes(), name
    cml = (pkg / "CMakeLists.txt").read_text()
    assert f"add_library({NODE}_layout_check OBJECT src/{NODE}_layout_check.c)" in cml
    assert f"add_dependencies({NODE} {NODE}_layout_check" in cml
    assert ('COMPILE_OPTIONS "-std=c11;-O2;-Wall;-Wextra;-Werror;-pedantic;-ffp-contract=off;'
            '-fexcess-precision=standard"') in cml  # the glue, as pyrosgen build
    assert "<name>landshark_controller</name>" in (pkg / "package.xml").read_text()
    assert f'<node pkg="{NODE}" type="{NODE}" name="{NODE}"' in (pkg / "launch" / f"{NODE}.launch").read_text()
    r = subprocess.run(["cmake", "-S", str(pkg), "-B", str(tmp_path / "cmake"), "-DPYTHON_EXECUTABLE=/usr/bin/python3"],
                       capture_output=True, text=True, stdin=subprocess.DEVNULL, timeout=300)
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]

# -- user errors (exit 1) ---------------------------------------------------------------

def test_layout_mismatch_is_a_user_error(tmp_path):
    ctl = tmp_path / "ctl"
    shutil.copytree(LANDSHARK_CTL, ctl)
    h = ctl / "Controller.h"
    h.write_text(h.read_text().replace("  real_T In2;", "  real32_T In2;"))
    out = tmp_path / "out"
    run = pyrosgen("build", LANDSHARK, "--controller", ctl, "-o", out)
    assert run.returncode == 1, run.stderr
    assert f"{h}: error: Controller_U.In2: type is not double (the model says float64)" in run.stderr
    assert "Controller_U.In1" not in run.stderr and "Controller_U.In3" not in run.stderr
    assert "[4/8] layout check" in run.stderr and "[5/8]" not in run.stderr
    assert not out.exists() and not _leftovers(tmp_path)


def test_controller_compile_error_names_the_file(tmp_path):
    ctl = tmp_path / "ctl"
    shutil.copytree(LANDSHARK_CTL, ctl)
    src = ctl / "Controller.c"
    src.write_text(src.read_text().replace("return b;", "return b"))
    out = tmp_path / "out"
    run = pyrosgen("build", LANDSHARK, "--controller", ctl, "-o", out)
    assert run.returncode == 1, run.stderr
    assert f"{src}: error: the controller source does not compile" in run.stderr
    assert re.search(r"/ctl/Controller\.c:\d+:\d+: error: expected", run.stderr), run.stderr
    assert not out.exists() and not _leftovers(tmp_path)


def test_failed_build_leaves_existing_out_untouched(landshark_build, tmp_path):
    """A controller that does not define Controller_step: the link fails
    (exit 1, the user's error); the previous build in OUT is intact."""
    _, out = landshark_build
    copy = tmp_path / "out"
    shutil.copytree(out, copy)
    (copy / "notes.txt").write_text("mine")
    before = snapshot(copy)
    ctl = tmp_path / "ctl"
    shutil.copytree(LANDSHARK_CTL, ctl)
    src = ctl / "Controller.c"
    src.write_text(src.read_text().replace("void Controller_step(void)", "void Controller_stop(void)"))
    run = pyrosgen("build", LANDSHARK, "--controller", ctl, "-o", copy)
    assert run.returncode == 1, run.stderr
    assert f"{ctl}: error: the controller does not define what the glue uses" in run.stderr
    assert "undefined reference to `Controller_step'" in run.stderr
    assert snapshot(copy) == before
    assert not _leftovers(tmp_path)


def test_fast_user_errors(tmp_path):
    out = tmp_path / "out"
    r = pyrosgen("build", LANDSHARK, "--controller", tmp_path / "nope", "-o", out)
    assert r.returncode == 1 and "controller folder not found" in r.stderr
    empty = tmp_path / "empty"
    empty.mkdir()
    r = pyrosgen("build", LANDSHARK, "--controller", empty, "-o", out)
    assert r.returncode == 1 and "no Controller.h in the controller folder" in r.stderr
    (empty / "Controller.h").write_text("/* */\n")
    r = pyrosgen("build", LANDSHARK, "--controller", empty, "-o", out)
    assert r.returncode == 1 and "no .c or .cpp file in the controller folder" in r.stderr
    a_file = tmp_path / "file"
    a_file.write_text("x")
    r = pyrosgen("build", LANDSHARK, "--controller", LANDSHARK_CTL, "-o", a_file)
    assert r.returncode == 1 and "exists and is not a directory" in r.stderr
    bad = tmp_path / "bad.yaml"
    bad.write_text(LANDSHARK.read_text().replace("period_ms: 20", "period_ms: 0"))
    r = pyrosgen("build", bad, "--controller", LANDSHARK_CTL, "-o", out)
    assert r.returncode == 1 and f"{bad}:" in r.stderr and "period_ms" in r.stderr
    r = pyrosgen("build", LANDSHARK, "-o", out)
    assert r.returncode == 1 and "--controller" in r.stderr
    r = pyrosgen("build", MULTI, "--controller", LANDSHARK_CTL, "-o", out)  # Fusion.h expected
    assert r.returncode == 1 and "no Fusion.h in the controller folder" in r.stderr
    assert not out.exists() and not _leftovers(tmp_path)


# -- tool failures (exit 2) -----------------------------------------------------------------

def test_compiler_failure_on_generated_code_is_exit_2(tmp_path):
    """A C++ compiler that fails (here: one that rejects everything) on the
    generated wrapper: exit 2 with the compiler's message, nothing written."""
    fake = tmp_path / "fakecxx"
    fake.write_text("#!/bin/sh\nfor a; do :; done\necho \"fakecxx: internal compiler error: $a\" >&2\nexit 4\n")
    fake.chmod(0o755)
    env = dict(os.environ, CXX=str(fake))
    out = tmp_path / "out"
    run = pyrosgen("build", LANDSHARK, "--controller", LANDSHARK_CTL, "-o", out, env=env)
    assert run.returncode == 2, run.stderr
    assert f"failed on generated code {out / (NODE + '_ros.cpp')}" in run.stderr
    assert "fakecxx: internal compiler error" in run.stderr
    assert not out.exists() and not _leftovers(tmp_path)


def test_missing_pkg_config_module_is_exit_2(tmp_path):
    fake = tmp_path / "pkg-config"
    fake.write_text("#!/bin/sh\necho \"Package roscpp was not found\" >&2\nexit 1\n")
    fake.chmod(0o755)
    env = dict(os.environ, PKG_CONFIG=str(fake))
    out = tmp_path / "out"
    run = pyrosgen("build", LANDSHARK, "--controller", LANDSHARK_CTL, "-o", out, env=env)
    assert run.returncode == 2, run.stderr
    assert "pkg-config does not know roscpp" in run.stderr and "Package roscpp was not found" in run.stderr
    assert not out.exists() and not _leftovers(tmp_path)


def test_help_lists_build():
    r = pyrosgen("--help")
    assert r.returncode == 0 and "build" in r.stdout
    r = pyrosgen("build", "--help")
    assert r.returncode == 0 and "--controller DIR" in r.stdout
    assert ROOT.is_dir()


def test_empty_output_folder_exit_1(tmp_path):
    """``build -o ""`` is refused as ``generate -o ""`` is (it was read as
    the current folder), before anything is read or written."""
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    for empty in ("", " "):
        r = pyrosgen("build", LANDSHARK, "--controller", LANDSHARK_CTL, "-o", empty, env=env, cwd=tmp_path)
        assert r.returncode == 1, r.stderr
        assert f"the output folder '{empty}' is empty; give a folder name (-o . for the current folder)" in r.stderr
        assert "Traceback" not in r.stderr and "[1/8]" not in r.stderr
    assert list(tmp_path.iterdir()) == []


def test_controller_only_change_reuses_the_proof(tmp_path):
    """A build after a change of the controller alone reuses the proof
    folder (the model file, its messages, the library and pyrosgen are
    unchanged: the stamp's digest says so) and the node still verifies;
    a change of the model proves again."""
    ctl = tmp_path / "ctl"
    shutil.copytree(LANDSHARK_CTL, ctl)
    model = tmp_path / "landshark_controller.yaml"
    shutil.copyfile(LANDSHARK, model)
    out = tmp_path / "out"
    first = pyrosgen("build", model, "--controller", ctl, "-o", out)
    assert first.returncode == 0, first.stderr
    assert "proof reused" not in first.stderr and "[2/8] generate: coqc:" in first.stderr
    key = json.loads((out / STAMP).read_text())["proof"]
    assert re.fullmatch(r"[0-9a-f]{64}", key)
    src = ctl / "Controller.c"
    src.write_text(src.read_text() + "\nint Controller_marker(void);\nint Controller_marker(void) { return 7; }\n")
    second = pyrosgen("build", model, "--controller", ctl, "-o", out)
    assert second.returncode == 0, second.stderr
    assert "[2/8] generate: proof reused from" in second.stderr
    assert "generate: coqc" not in second.stderr and "generate: printing" not in second.stderr
    assert "compiled  obj/controller_Controller.o, bin/landshark_controller" in second.stdout
    assert json.loads((out / STAMP).read_text())["proof"] == key
    assert (out / "controller" / "Controller.c").read_bytes() == src.read_bytes()
    check = pyrosgen("verify", out, "--model", model)
    assert check.returncode == 0, check.stdout + check.stderr
    # a changed model (another period) is proved again
    model.write_text(model.read_text().replace("period_ms: 20", "period_ms: 25"))
    assert "period_ms: 25" in model.read_text()
    third = pyrosgen("build", model, "--controller", ctl, "-o", out)
    assert third.returncode == 0, third.stderr
    assert "proof reused" not in third.stderr and "[2/8] generate: coqc:" in third.stderr
    assert json.loads((out / STAMP).read_text())["proof"] != key
    assert "period_ms 25" in (out / f"{NODE}.model").read_text()

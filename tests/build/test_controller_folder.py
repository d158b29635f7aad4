"""Controller folders as Embedded Coder writes them: ``ert_main.c`` (any
source defining ``main``) left out with a note; sources in subfolders and
``.cpp`` sources compiled; the C standard, flags, include folders and
libraries given on the command line reach the compiler, the linker and the
catkin package; a controller that does not link is a user error naming the
file at fault."""

from __future__ import annotations

import re
import shutil
import subprocess
from pathlib import Path

import pytest

from .conftest import LANDSHARK, LANDSHARK_CTL, pyrosgen

NODE = "landshark_controller"

ERT_MAIN = """/* ert_main.c: Embedded Coder's example main program */
#include <stdio.h>
#include "Controller.h"
int main(int argc, const char *argv[])
{
  (void)argc; (void)argv;
  Controller_initialize();
  return 0;
}
"""


def _folder(tmp_path: Path) -> Path:
    d = tmp_path / "Controller_ert_rtw"
    shutil.copytree(LANDSHARK_CTL, d)
    (d / "ert_main.c").write_text(ERT_MAIN)
    (d / "shared").mkdir()
    (d / "shared" / "rt_util.h").write_text("#ifndef RT_UTIL_H\n#define RT_UTIL_H\ndouble rt_util_twice(double x);\n#endif\n")
    (d / "shared" / "rt_util.c").write_text('#include "rt_util.h"\ndouble rt_util_twice(double x) { return 2.0 * x; }\n')
    (d / "helper.cpp").write_text('extern "C" {\n#include "rt_util.h"\n}\nextern "C" double helper_cpp(double x) { return rt_util_twice(x); }\n')
    return d


def test_embedded_coder_folder_builds(tmp_path):
    d = _folder(tmp_path)
    out = tmp_path / "out"
    run = pyrosgen("build", LANDSHARK, "--controller", d, "-o", out, "-q")
    assert run.returncode == 0, run.stderr
    assert f"note: {d / 'ert_main.c'}: left out of the build: defines main" in run.stderr
    objs = {p.name for p in (out / "obj").iterdir()}
    assert {"controller_Controller.o", "controller_shared__rt_util.o", "controller_helper.o"} <= objs
    assert "controller_ert_main.o" not in objs
    syms = subprocess.run(["nm", str(out / "bin" / NODE)], capture_output=True, text=True).stdout
    assert " T rt_util_twice\n" in syms and " T helper_cpp\n" in syms
    cml = (out / NODE / "CMakeLists.txt").read_text()
    for f in ("controller/Controller.c", "controller/shared/rt_util.c", "controller/helper.cpp", "controller/shared"):
        assert f"  {f}\n" in cml, f
    assert "ert_main" not in cml
    r = subprocess.run(["cmake", "-S", str(out / NODE), "-B", str(tmp_path / "cmake"), "-DPYTHON_EXECUTABLE=/usr/bin/python3"],
                       capture_output=True, text=True, stdin=subprocess.DEVNULL, timeout=300)
    assert r.returncode == 0, r.stdout[-2000:] + r.stderr[-2000:]


def test_flags_reach_the_compiler_and_the_package(tmp_path):
    d = _folder(tmp_path)
    (d / "needs_flags.c").write_text(
        "#ifndef ROBOT_VARIANT\n#error ROBOT_VARIANT is not defined\n#endif\n"
        "#if __STDC_VERSION__ != 199901L\n#error not C99\n#endif\n"
        '#include "extra.h"\nint needs_flags_value(void) { return ROBOT_VARIANT + EXTRA; }\n')
    inc = tmp_path / "extra_include"
    inc.mkdir()
    (inc / "extra.h").write_text("#define EXTRA 1\n")
    out = tmp_path / "out"
    run = pyrosgen("build", LANDSHARK, "--controller", d, "-o", out, "-q")
    assert run.returncode == 1
    assert "needs_flags.c: error: the controller source does not compile" in run.stderr
    assert "ROBOT_VARIANT is not defined" in run.stderr
    run = pyrosgen("build", LANDSHARK, "--controller", d, "-o", out, "-q", "--std", "c99",
                   "--cflags=-DROBOT_VARIANT=2 -O1", "--include", str(inc), "--libs=-lrt")
    assert run.returncode == 0, run.stderr
    cml = (out / NODE / "CMakeLists.txt").read_text()
    assert 'COMPILE_OPTIONS "-std=c99;-O2;-Wall;-Wextra;-DROBOT_VARIANT=2;-O1")' in cml
    assert f"  {inc}\n" in cml and " -lrt m pthread)" in cml


def test_controller_that_does_not_link_is_a_user_error(tmp_path):
    d = _folder(tmp_path)
    (d / "dup.c").write_text("double rt_util_twice(double x) { return x; }\n")
    run = pyrosgen("build", LANDSHARK, "--controller", d, "-o", tmp_path / "out", "-q")
    assert run.returncode == 1, run.stderr
    assert "error: the controller does not link" in run.stderr and "dup.c" in run.stderr.splitlines()[0]
    assert "multiple definition of `rt_util_twice'" in run.stderr
    (d / "dup.c").unlink()
    run = pyrosgen("build", LANDSHARK, "--controller", d, "-o", tmp_path / "out", "-q", "--libs=-lno_such_lib")
    assert run.returncode == 1 and "cannot find -lno_such_lib" in run.stderr
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("argv, message", [
    (["--cflags=-DX=$(touch y)"], "unsupported characters"),
    (["--libs=-lm;rm"], "unsupported characters"),
    (["--std", "c++17"], "--std c++17: not one of"),
    (["--cflags='-DX"], "controller flags: No closing quotation"),
])
def test_bad_flags_are_refused(tmp_path, argv, message):
    run = pyrosgen("build", LANDSHARK, "--controller", LANDSHARK_CTL, "-o", tmp_path / "out", "-q", *argv)
    assert run.returncode == 1 and message in run.stderr, run.stderr
    assert not (tmp_path / "out").exists() and not list(tmp_path.glob("y"))


def test_headers_in_subfolders(tmp_path):
    """Embedded Coder puts shared headers (rtwtypes.h) into
    slprj/ert/_sharedutils: the layout check and the compiles find them."""
    d = tmp_path / "ctl"
    shutil.copytree(LANDSHARK_CTL, d)
    shared = d / "slprj" / "ert" / "_sharedutils"
    shared.mkdir(parents=True)
    (d / "rtwtypes.h").rename(shared / "rtwtypes.h")
    run = pyrosgen("build", LANDSHARK, "--controller", d, "-o", tmp_path / "out", "-q")
    assert run.returncode == 0, run.stderr
    assert (tmp_path / "out" / "controller" / "slprj" / "ert" / "_sharedutils" / "rtwtypes.h").is_file()


def test_init_then_build_gives_the_same_node(landshark_build, tmp_path):
    """pyrosgen init on the example controller, the example's topics and
    relations filled in, then build: the same node as the example's (the
    same glue, wrapper, layout check and headers)."""
    import yaml

    _, example_out = landshark_build
    model = tmp_path / "m" / LANDSHARK.name
    model.parent.mkdir()
    assert pyrosgen("init", "--controller", LANDSHARK_CTL, "-o", model).returncode == 0
    skeleton = yaml.safe_load(model.read_text())
    example = yaml.safe_load(LANDSHARK.read_text())
    skeleton["node"]["name"] = example["node"]["name"]
    skeleton["topics"], skeleton["relations"] = example["topics"], example["relations"]
    model.write_text(yaml.safe_dump(skeleton, sort_keys=False))
    out = tmp_path / "out"
    run = pyrosgen("build", model, "--controller", LANDSHARK_CTL, "-o", out, "-q")
    assert run.returncode == 0, run.stderr
    for rel in ("src", "include", "controller"):
        for f in sorted((example_out / NODE / rel).rglob("*")):
            if f.is_file():
                mine = out / NODE / rel / f.relative_to(example_out / NODE / rel)
                assert mine.read_bytes() == f.read_bytes(), f
    assert (out / f"{NODE}.model").read_bytes() == (example_out / f"{NODE}.model").read_bytes()


#: Folders in the shapes Embedded Coder writes (tests/support/ert), each with
#: <model>.h/.c, <model>_private.h, <model>_types.h and ert_main.c defining
#: ``int_T main(int_T argc, const char *argv[])``: Rover with rtwtypes.h and
#: rt_* utilities in slprj/ert/_sharedutils/ and the referenced model Wheel in
#: slprj/ert/Wheel/; Robot flat, as for a model that references none
#: (rtwtypes.h, rt_nonfinite, rtGetInf, <model>_data.c with its parameters,
#: a controller array, ``int_T`` and ``main`` on two lines).
ERT_DIR = LANDSHARK.parents[2] / "tests" / "support" / "ert"
ERT = ERT_DIR / "Rover_ert_rtw"

ROBOT_TOPICS = [
    {"name": "/scan", "direction": "subscribe", "type": "sensor_msgs/LaserScan", "queue_size": 1,
     "max_length": {"ranges": 4}},
    {"name": "/enable", "direction": "subscribe", "type": "std_msgs/Bool", "queue_size": 1},
    {"name": "/cmd_vel", "direction": "publish", "type": "geometry_msgs/Twist", "queue_size": 1},
    {"name": "/mode", "direction": "publish", "type": "std_msgs/UInt8", "queue_size": 1},
]
ROBOT_RELATIONS = {
    "inputs": [{"topic": "/scan", "field": "ranges", "input": "Sectors"},
               {"topic": "/enable", "field": "data", "input": "Enable"}],
    "outputs": [{"output": "Speed", "topic": "/cmd_vel", "field": "linear.x"},
                {"output": "Mode", "topic": "/mode", "field": "data"}],
}
#: folder -> (node, period line of init, objects compiled, symbols linked)
ERT_FOLDERS = {
    "Rover_ert_rtw": ("rover_node", "period    20 ms, from the rate of rt_OneStep, ert_main.c:50",
                      {"controller_Rover.o", "controller_slprj__ert__Wheel__Wheel.o",
                       "controller_slprj__ert___sharedutils__rt_minsector.o",
                       "controller_slprj__ert___sharedutils__rt_nonfinite.o"},
                      ("Wheel", "rt_minsector", "Rover_step")),
    "Robot_ert_rtw": ("robot_node", "period    50 ms, from the rate of rt_OneStep, ert_main.c:64",
                      {"controller_Robot.o", "controller_Robot_data.o", "controller_rtGetInf.o",
                       "controller_rt_nonfinite.o"},
                      ("Robot_P", "rtGetInfF", "Robot_step")),
}


def _ert_model(tmp_path: Path, ctl: Path, said: str) -> Path:
    """pyrosgen init on ``ctl``, the topics and relations filled in
    (Rover: LandShark's)."""
    import yaml

    model = tmp_path / f"{ctl.name}.yaml"
    run = pyrosgen("init", "--controller", ctl, "-o", model)
    assert run.returncode == 0, run.stderr
    assert said in run.stdout, run.stdout
    skeleton = yaml.safe_load(model.read_text())
    if skeleton["controller"]["name"] == "Rover":
        example = yaml.safe_load(LANDSHARK.read_text())
        skeleton["topics"], skeleton["relations"] = example["topics"], example["relations"]
    else:
        skeleton["topics"], skeleton["relations"] = ROBOT_TOPICS, ROBOT_RELATIONS
    model.write_text(yaml.safe_dump(skeleton, sort_keys=False))
    return model


@pytest.mark.parametrize("folder", list(ERT_FOLDERS))
def test_embedded_coder_folder_init_then_build(tmp_path, folder):
    """An Embedded Coder folder goes through init and build unchanged:
    ert_main.c (int_T main) left out with a note, the shared utilities,
    the parameters and the referenced model compiled and linked, the
    period agreeing with ert_main.c's (no note)."""
    node, said, want_objs, want_syms = ERT_FOLDERS[folder]
    ctl = tmp_path / folder
    shutil.copytree(ERT_DIR / folder, ctl)
    before = {p: p.read_bytes() for p in ctl.rglob("*") if p.is_file()}
    model = _ert_model(tmp_path, ctl, said)
    out = tmp_path / "out"
    run = pyrosgen("build", model, "--controller", ctl, "-o", out, "-q")
    assert run.returncode == 0, run.stderr
    assert f"note: {ctl / 'ert_main.c'}: left out of the build: defines main" in run.stderr
    assert "generated for" not in run.stderr
    objs = {p.name for p in (out / "obj").iterdir()}
    assert want_objs <= objs, objs
    assert not any("ert_main" in o for o in objs)
    syms = subprocess.run(["nm", str(out / "bin" / node)], capture_output=True, text=True).stdout
    for sym in want_syms:
        assert re.search(rf" [TDB] {sym}\n", syms), sym
    assert {p: p.read_bytes() for p in ctl.rglob("*") if p.is_file()} == before
    if folder != "Rover_ert_rtw":
        return
    # a period that differs from the controller's base rate is noted
    text = model.read_text().replace("period_ms: 20", "period_ms: 10")
    assert text != model.read_text()
    model.write_text(text)
    run = pyrosgen("build", model, "--controller", ctl, "-o", tmp_path / "out10", "-q")
    assert run.returncode == 0, run.stderr
    assert ("note: the node steps the controller every 10 ms (period_ms), but it was generated for 20 ms "
            "(the rate of rt_OneStep, ert_main.c:50: 0.02 s)") in run.stderr


def test_main_not_recognised_is_named_with_the_fix(tmp_path):
    """A main the parser cannot see (defined in assembly): the link error
    names the file and says what to do."""
    d = _folder(tmp_path)
    (d / "asm_main.c").write_text('__asm__(".globl main\\n.type main, @function\\nmain:\\n  xorl %eax, %eax\\n  ret\\n");\n')
    run = pyrosgen("build", LANDSHARK, "--controller", d, "-o", tmp_path / "out", "-q")
    assert run.returncode == 1, run.stderr
    first = run.stderr.splitlines()[0]
    assert f"{d / 'asm_main.c'}: error: the controller defines main, and so does the node" in first, run.stderr
    assert "move that main out of the controller folder" in first
    assert "multiple definition of `main'" in run.stderr
    assert not (tmp_path / "out").exists()

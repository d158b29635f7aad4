"""``pyrosgen init --controller DIR -o MODEL.yaml``: the controller
section read from the Embedded Coder header with pycparser; round trip on
the examples; unsupported fields reported; nothing written on failure."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest
import yaml

from pyrosgen import cli

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = {
    "landshark": (ROOT / "examples/landshark/landshark_controller.yaml", ROOT / "examples/landshark/controller"),
    "multi": (ROOT / "examples/multi/multi_node.yaml", ROOT / "examples/multi/controller"),
    # controller arrays (rule 4.15): real32_T Scan[1081]; uint8_T Name0[32], real_T Pos[6], ...
    "scan_guard": (ROOT / "examples/scan_guard/scan_guard.yaml", ROOT / "examples/scan_guard/controller"),
    "arm_named": (ROOT / "examples/arm_named/arm_named.yaml", ROOT / "examples/arm_named/controller"),
}
#: where init finds each example's period (None: nowhere)
PERIODS = {
    "landshark": (20, "period    20 ms, from a #define commented as the sample time, Controller.h:36"),
    "multi": None,
    "scan_guard": (50, "period    50 ms, from a sample time comment, ScanGuard.h:6: 0.05 s"),
    "arm_named": (10, "period    10 ms, from a sample time comment, ArmNamed.h:6: 0.01 s"),
}

HEADER = """#include "rtwtypes.h"
typedef struct {{
{inputs}
}} ExtU_{m}_T;
typedef struct {{
  real_T Out1;
}} ExtY_{m}_T;
extern ExtU_{m}_T {m}_U;
extern ExtY_{m}_T {m}_Y;
extern void {m}_initialize(void);
extern void {m}_step(void);
"""


def run(capsys, *argv):
    code = cli.main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def _controller_folder(tmp_path: Path, inputs: str, m: str = "Robot", extra: dict[str, str] | None = None) -> Path:
    d = tmp_path / "ctl"
    d.mkdir(exist_ok=True)
    shutil.copyfile(EXAMPLES["landshark"][1] / "rtwtypes.h", d / "rtwtypes.h")
    (d / f"{m}.h").write_text(HEADER.format(inputs=inputs, m=m))
    for name, text in (extra or {}).items():
        (d / name).write_text(text)
    return d


@pytest.mark.parametrize("key", list(EXAMPLES))
def test_init_reads_the_example_controllers(capsys, tmp_path, key):
    model_file, ctl = EXAMPLES[key]
    out = tmp_path / "skeleton.yaml"
    code, text, err = run(capsys, "init", "--controller", ctl, "-o", out)
    assert code == 0, err
    got = yaml.safe_load(out.read_text())
    want = yaml.safe_load(model_file.read_text())
    assert got["controller"] == want["controller"]  # names, field order, types
    assert list(got["controller"]["inputs"]["fields"]) == list(want["controller"]["inputs"]["fields"])
    if PERIODS[key] is not None:
        period, said = PERIODS[key]
        assert got["node"]["period_ms"] == want["node"]["period_ms"] == period
        assert said in text, text
    else:
        assert got["node"]["period_ms"] is None and "period    not found" in text
    assert got["topics"] is None and got["relations"] == {"inputs": None, "outputs": None}
    # the header's comments come along
    assert "# real_T: '<Root>/In1'" in out.read_text() or key != "landshark"


@pytest.mark.parametrize("key", list(EXAMPLES))
def test_round_trip_gives_the_same_node(capsys, tmp_path, key):
    """init, then the example's node name, period, topics and relations
    filled in: generate prints the very same C and model as for the
    example itself."""
    model_file, ctl = EXAMPLES[key]
    filled = tmp_path / "model" / model_file.name
    filled.parent.mkdir()
    code, _, err = run(capsys, "init", "--controller", ctl, "-o", filled)
    assert code == 0, err
    skeleton = yaml.safe_load(filled.read_text())
    example = yaml.safe_load(model_file.read_text())
    skeleton["node"] = example["node"] if key == "multi" else {**skeleton["node"], "name": example["node"]["name"]}
    for k in ("topics", "relations", "msg_paths"):
        if k in example:
            skeleton[k] = example[k]
    if "msg_paths" in example:
        for p in example["msg_paths"]:
            shutil.copytree(model_file.parent / p, filled.parent / p)
    filled.write_text(yaml.safe_dump(skeleton, sort_keys=False))
    outs = {}
    for name, path in (("example", model_file), ("init", filled)):
        outs[name] = tmp_path / name
        code, _, err = run(capsys, "generate", path, "-o", outs[name], "-q")
        assert code == 0, err
    node = example["node"]["name"]
    for f in (f"{node}_glue.c", f"{node}_types.h", f"{node}.model", f"{node}.sexp", f"{node}.v"):
        assert (outs["init"] / f).read_bytes() == (outs["example"] / f).read_bytes(), f


def test_unsupported_fields_are_reported(capsys, tmp_path):
    inputs = "\n".join([
        "  real_T Ok;",
        "  real_T Vec[3][2];",
        "  creal_T Z;",
        "  struct { real_T a; } Bus;",
        "  char C;",
        "  long L;",
    ])
    extra = {"rtwtypes_c.h": ""}
    d = _controller_folder(tmp_path, inputs, extra=extra)
    (d / "rtwtypes.h").write_text((d / "rtwtypes.h").read_text().replace(
        "#endif", "typedef struct { real_T re; real_T im; } creal_T;\n#endif"))
    out = tmp_path / "m.yaml"
    code, _, err = run(capsys, "init", "--controller", d, "-o", out)
    assert code == 1
    assert "(5 problems)" in err
    assert "  Robot.h:4: ExtU_Robot_T.Vec (real_T[3][2]): an array of arrays" in err
    assert "  Robot.h:5: ExtU_Robot_T.Z (creal_T): a complex number" in err
    assert "  Robot.h:6: ExtU_Robot_T.Bus" in err and "a bus" in err
    assert "  Robot.h:7: ExtU_Robot_T.C (char): plain char: its signedness is the compiler's" in err
    assert "  Robot.h:8: ExtU_Robot_T.L (long): long: its size differs" in err
    assert "Ok" not in err.split("problems)")[1]
    assert not out.exists() and not list(tmp_path.glob(".m.yaml*"))


@pytest.mark.parametrize("text, period", [
    ("/* Attach rt_OneStep to a timer or interrupt service routine with\n * period 0.05 seconds (the model's base sample time) here. */", 50),
    ("/* Sample time: [0.1s, 0.0s] */", 100),
    ("/*  Fixed-step size: 0.004 */", 4),
])
def test_period_from_the_generated_code(capsys, tmp_path, text, period):
    d = _controller_folder(tmp_path, "  real_T In1;", extra={"ert_main.c": text + "\nint main(void) { return 0; }\n"})
    out = tmp_path / "m.yaml"
    code, _, err = run(capsys, "init", "--controller", d, "-o", out)
    assert code == 0, err
    assert yaml.safe_load(out.read_text())["node"]["period_ms"] == period


def test_period_that_is_not_whole_milliseconds(capsys, tmp_path):
    d = _controller_folder(tmp_path, "  real_T In1;", extra={"Robot.c": "/* Sample time: [0.0005s, 0.0s] */\n"})
    out = tmp_path / "m.yaml"
    code, text, err = run(capsys, "init", "--controller", d, "-o", out)
    assert code == 0, err
    assert yaml.safe_load(out.read_text())["node"]["period_ms"] is None
    assert "not a whole number of milliseconds" in text


def test_refusals(capsys, tmp_path):
    d = _controller_folder(tmp_path, "  real_T In1;")
    out = tmp_path / "m.yaml"
    out.write_text("mine\n")
    code, _, err = run(capsys, "init", "--controller", d, "-o", out)
    assert code == 1 and "does not overwrite" in err and out.read_text() == "mine\n"
    assert run(capsys, "init", "--controller", d, "-o", out, "--force")[0] == 0
    # two models in one folder
    (d / "Other.h").write_text(HEADER.format(inputs="  real_T A;", m="Other"))
    code, _, err = run(capsys, "init", "--controller", d, "-o", tmp_path / "n.yaml")
    assert code == 1 and "several models (Other, Robot); choose one with --name" in err
    assert run(capsys, "init", "--controller", d, "--name", "Other", "-o", tmp_path / "n.yaml")[0] == 0
    # no interface, no folder, a garbage header, an output folder that does not exist
    empty = tmp_path / "empty"
    empty.mkdir()
    code, _, err = run(capsys, "init", "--controller", empty, "-o", tmp_path / "e.yaml")
    assert code == 1 and "no header defines ExtU_<Model>_T" in err
    assert run(capsys, "init", "--controller", tmp_path / "nowhere", "-o", tmp_path / "e.yaml")[0] == 1
    (d / "Other.h").write_bytes(b"typedef struct { \xff\xfe\x00 ExtU_Other_T; ExtY_Other_T;")
    code, _, err = run(capsys, "init", "--controller", d, "--name", "Other", "-o", tmp_path / "g.yaml")
    assert code == 1 and "Other.h" in err and "Traceback" not in err
    assert run(capsys, "init", "--controller", d, "-o", tmp_path / "no" / "m.yaml")[0] == 1
    assert not (tmp_path / "e.yaml").exists() and not (tmp_path / "g.yaml").exists()


# -- Embedded Coder folders as Embedded Coder writes them -------------------------

#: A folder in the shape Embedded Coder writes (tests/support/ert): Rover.h,
#: Rover.c, Rover_private.h, Rover_types.h, ert_main.c with
#: ``int_T main(int_T argc, const char *argv[])``, shared utilities (rtwtypes.h,
#: rt_nonfinite, rt_minsector) in slprj/ert/_sharedutils/ and the referenced
#: model Wheel in slprj/ert/Wheel/.
ERT = ROOT / "tests" / "support" / "ert" / "Rover_ert_rtw"


ERT_FOLDERS = {
    "Rover_ert_rtw": ({"name": "Rover",
                       "inputs": {"name": "Rover_U", "fields": {"In1": "float64", "In2": "float64", "In3": "float64"}},
                       "outputs": {"name": "Rover_Y", "fields": {"Out1": "float64"}}},
                      {"name": "rover_node", "period_ms": 20},
                      "period    20 ms, from the rate of rt_OneStep, ert_main.c:50: 0.02 s"),
    # flat, as for a model that references none; a controller array; parameters in Robot_data.c
    "Robot_ert_rtw": ({"name": "Robot",
                       "inputs": {"name": "Robot_U", "fields": {"Sectors": "float32[4]", "Enable": "bool"}},
                       "outputs": {"name": "Robot_Y", "fields": {"Speed": "float64", "Mode": "uint8"}}},
                      {"name": "robot_node", "period_ms": 50},
                      "period    50 ms, from the rate of rt_OneStep, ert_main.c:64: 0.05 s"),
}


@pytest.mark.parametrize("folder", list(ERT_FOLDERS))
def test_init_reads_an_embedded_coder_folder(capsys, tmp_path, folder):
    """The shared headers in slprj/ert/_sharedutils and the referenced
    model's in slprj/ert/Wheel are on the include path; the period is
    ert_main.c's (which build leaves out)."""
    controller, node, said = ERT_FOLDERS[folder]
    out = tmp_path / "model.yaml"
    code, text, err = run(capsys, "init", "--controller", ERT.parent / folder, "-o", out)
    assert code == 0, err
    got = yaml.safe_load(out.read_text())
    assert got["controller"] == controller
    assert got["node"] == node
    assert said in text


def test_init_include_folders(capsys, tmp_path):
    """Shared headers outside the folder: a clear error naming the missing
    header without --include, the skeleton with it (relative to the folder,
    or absolute)."""
    codegen = tmp_path / "codegen"
    shutil.copytree(ERT, codegen / "Rover_ert_rtw")
    (codegen / "Rover_ert_rtw" / "slprj").rename(codegen / "slprj")
    d = codegen / "Rover_ert_rtw"
    out = tmp_path / "rover.yaml"
    code, _, err = run(capsys, "init", "--controller", d, "-o", out)
    assert code == 1 and "Rover.h: error: the C preprocessor failed" in err
    assert "rtwtypes.h: No such file or directory" in err and "Traceback" not in err
    assert not out.exists()
    shared = codegen / "slprj" / "ert" / "_sharedutils"
    code, _, err = run(capsys, "init", "--controller", d, "-o", out,
                       "--include", "../slprj/ert/_sharedutils", "--include", codegen / "slprj" / "ert" / "Wheel")
    assert code == 0, err
    assert yaml.safe_load(out.read_text())["controller"]["name"] == "Rover"
    code, _, err = run(capsys, "init", "--controller", d, "-o", tmp_path / "x.yaml",
                       "--include", shared / "rtwtypes.h")
    assert code == 1 and "is not a folder" in err and not (tmp_path / "x.yaml").exists()


def test_preprocessor_reports_no_redefinition(monkeypatch, tmp_path):
    """init runs the preprocessor in C11 (``__STDC_VERSION__`` 201112L) by
    ``-std``, with nothing on stderr (no "redefined" warning)."""
    from pyrosgen import procs
    from pyrosgen.frontend import csource

    seen = []
    real = procs.run

    def spy(argv, **kw):
        r = real(argv, **kw)
        seen.append((argv, r.stderr))
        return r

    monkeypatch.setattr(procs, "run", spy)
    h = tmp_path / "h.h"
    h.write_text("#if __STDC_VERSION__ != 201112L\n#error not C11\n#endif\nint c11;\n")
    assert "int c11;" in csource.preprocess(h, [tmp_path])
    assert seen and all(not err.strip() for _, err in seen), seen
    assert not any(a.startswith("-D__STDC_VERSION__") for argv, _ in seen for a in argv)


MAIN_FORMS = {
    "ert_main.c": ('#include <stdio.h>\n#include "rtwtypes.h"\n'
                   "int_T main(int_T argc, const char *argv[])\n{\n  (void)(argc);\n  return 0;\n}\n"),
    "void.c": "int main(void) { return 0; }\n",
    "kr.c": "int main(argc, argv)\n  int argc;\n  char **argv;\n{\n  return 0;\n}\n",
    "implicit_int.c": "main() { return 0; }\n",
    "macro.c": "#define ENTRY main\n#define DEFINE(f) int f(void)\nDEFINE(ENTRY) { return 0; }\n",
    "pasted.c": "#define CAT(a, b) a##b\nint CAT(ma, in)(void) { return 0; }\n",
    "comments.c": "int\n/* the */ main /* entry */ (\n  void // none\n  )\n/* body */ {\n  return 0;\n}\n",
    "attribute.c": "int main(void) __attribute__((used));\nint __attribute__((used)) main(void) { return 0; }\n",
    "system_headers.c": "#include <signal.h>\n#include <time.h>\nint main(void) { struct timespec t; (void)t; return 0; }\n",
    "missing_header.c": '#include "nowhere.h"\nint main(void) { return 0; }\n',
    "harness.cpp": "#include <vector>\nint main(int, char **) { std::vector<int> v; return 0; }\n",
    "extern_c.cpp": 'extern "C" {\nint main(int argc, char **argv) { return 0; }\n}\n',
}
NOT_MAIN = {
    "prototype.c": "int main(void);\nint f(void) { return main(); }\n",
    "comment.c": "/* int main(void) { return 0; } */\n// int main(void) {\nint f(void) { return 0; }\n",
    "string.c": 'const char *s = "int main(void) { return 0; }";\n',
    "member.c": "struct s { int (*main)(void); };\nint g(struct s *p) { return p->main(); }\n",
    "domain.c": "int domain(void) { return 0; }\nint main_loop(void) { return 0; }\n",
    "disabled.c": "#if 0\nint main(void) { return 0; }\n#endif\nint f(void) { return 0; }\n",
    "namespace.cpp": "namespace app { int main() { return 1; } }\nint f() { return 0; }\n",
    "method.cpp": "struct App { int main() { return 1; } };\n",
}


@pytest.mark.parametrize("name", list(MAIN_FORMS) + list(NOT_MAIN))
def test_defines_main_by_parsing(tmp_path, name):
    """A source defines main whatever its form (parsed after the
    preprocessor; a token scan when pycparser cannot parse it); a main
    only declared, called, commented out, in a string, a member or
    disabled by #if is not a definition."""
    from pyrosgen.frontend.csource import defines_main

    shutil.copyfile(ERT / "slprj" / "ert" / "_sharedutils" / "rtwtypes.h", tmp_path / "rtwtypes.h")
    src = tmp_path / name
    src.write_text(MAIN_FORMS.get(name) or NOT_MAIN[name])
    assert defines_main(src, [tmp_path]) is (name in MAIN_FORMS)

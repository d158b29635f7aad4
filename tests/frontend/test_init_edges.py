"""``pyrosgen init`` on hostile controller folders (issue 30): a sample
time too large or too long to convert, a source file larger than init
reads, a bitfield, a model whose name YAML 1.1 reads as a null or a
boolean.  Each is refused with a clear message (exit 1) or noted and
bounded, never an internal error."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

from pyrosgen import cli
#: The largest source file init reads (README, `pyrosgen init`).
MAX_SOURCE_SIZE = 16 * 1024 * 1024

ROOT = Path(__file__).resolve().parents[2]
RTWTYPES = ROOT / "examples/landshark/controller/rtwtypes.h"

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


def _folder(tmp_path: Path, inputs: str = "  real_T In1;", m: str = "Robot",
            extra: dict[str, str] | None = None) -> Path:
    d = tmp_path / "ctl"
    d.mkdir()
    shutil.copyfile(RTWTYPES, d / "rtwtypes.h")
    (d / f"{m}.h").write_text(HEADER.format(inputs=inputs, m=m))
    for name, text in (extra or {}).items():
        (d / name).write_text(text)
    return d


# --------------------------------------------------------------------------
# The sample time


@pytest.mark.parametrize("seconds, note", [
    ("1e5000", "Robot.c:2: sample time 1e5000 s is not a number init reads (too long, or its exponent is "
               "beyond +/-20); period_ms left for you to set"),
    ("1e999999999", "Robot.c:2: sample time 1e999999999 s is not a number init reads"),
    ("0." + "0" * 40 + "1", "Robot.c:2: sample time 0.000000000000000000000000000000... s is not a number"),
    ("5000.0", "Robot.c:2: sample time 5000.0 s is longer than 3,600,000 ms, the longest period (rule 4.2); "
               "period_ms left for you to set"),
])
def test_sample_time_out_of_reach_is_noted(tmp_path, seconds, note):
    """``[1e5000s`` was an internal error (int() of 5,000 digits) and
    ``[1e999999999s`` ran for more than a minute; the skeleton is written
    without a period and the note says why.  In a subprocess with a
    timeout, so that a regression fails instead of hanging the suite."""
    d = _folder(tmp_path, extra={"Robot.c": f"/* Robot step */\n/* Sample time: [{seconds}s, 0.0s] */\n"})
    out = tmp_path / "m.yaml"
    res = subprocess.run([sys.executable, "-m", "pyrosgen", "init", "--controller", str(d), "-o", str(out)],
                         capture_output=True, text=True, timeout=30, cwd=ROOT)
    assert res.returncode == 0, res.stderr
    assert "  note      " + note in res.stdout, res.stdout
    assert yaml.safe_load(out.read_text())["node"]["period_ms"] is None


# --------------------------------------------------------------------------
# Source files of bounded size


@pytest.mark.parametrize("name", ["Big.c", "Big.h", "Robot.h"])
def test_source_file_larger_than_the_limit_is_refused(capsys, tmp_path, name):
    """Every .h and .c was read whole (a sparse 20 GB file: MemoryError);
    one over 16 MiB is refused, naming the file and the limit, and
    nothing is written."""
    d = _folder(tmp_path)
    big = d / name
    with open(big, "ab") as fh:
        fh.truncate(MAX_SOURCE_SIZE + 1)   # sparse: no disk used
    size = os.path.getsize(big)
    out = tmp_path / "m.yaml"
    code, text, err = run(capsys, "init", "--controller", d, "-o", out)
    assert code == 1, text
    assert (f"pyrosgen: error: {big}: is {size:,} bytes; init reads source files of at most 16 MiB "
            "(move it out of the controller folder)") in err
    assert not out.exists()


def test_source_file_at_the_limit_is_read(capsys, tmp_path):
    d = _folder(tmp_path, extra={"Robot.c": "/* Sample time: [0.02s, 0.0s] */\n"})
    with open(d / "Robot.c", "ab") as fh:
        fh.truncate(MAX_SOURCE_SIZE)
    out = tmp_path / "m.yaml"
    code, _, err = run(capsys, "init", "--controller", d, "-o", out)
    assert code == 0, err
    assert yaml.safe_load(out.read_text())["node"]["period_ms"] == 20


# --------------------------------------------------------------------------
# Bitfields


def test_bitfield_is_refused(capsys, tmp_path):
    """``uint32_T A : 3;`` became a whole uint32 field."""
    d = _folder(tmp_path, inputs="  real_T In1;\n  uint32_T A : 3;\n  boolean_T B : 1;")
    out = tmp_path / "m.yaml"
    code, _, err = run(capsys, "init", "--controller", d, "-o", out)
    assert code == 1
    assert "(2 problems)" in err
    assert ("  Robot.h:4: ExtU_Robot_T.A (uint32_T): a bitfield of 3 bits: its layout is the compiler's; "
            "the glue carries whole fields") in err
    assert "  Robot.h:5: ExtU_Robot_T.B (boolean_T): a bitfield of 1 bits" in err
    assert not out.exists()


# --------------------------------------------------------------------------
# Names YAML 1.1 reads as something else


_FILLED = """\
topics:
  - {name: /u, direction: subscribe, type: std_msgs/Float64, queue_size: 1}
  - {name: /y, direction: subscribe, type: std_msgs/Float64, queue_size: 1}
  - {name: /z, direction: publish, type: std_msgs/Float64, queue_size: 1}
relations:
  inputs:
    - {topic: /u, field: data, input: 'on'}
    - {topic: /y, field: data, input: 'yes'}
  outputs:
    - {output: Out1, topic: /z, field: data}
"""


@pytest.mark.parametrize("model", ["null", "on", "yes", "off", "True", "NULL", "n_on"])
def test_names_yaml_would_misread_are_quoted(capsys, tmp_path, model):
    """A model named ``null``, ``on`` or ``yes`` was written unquoted, so
    ``check`` refused the skeleton (controller.name: got null / boolean);
    the skeleton, completed with topics and relations, checks."""
    d = _folder(tmp_path, inputs="  real_T on;\n  real_T yes;", m=model,
                extra={f"{model}.c": "/* Sample time: [0.02s, 0.0s] */\n"})
    out = tmp_path / "m.yaml"
    code, _, err = run(capsys, "init", "--controller", d, "-o", out)
    assert code == 0, err
    skeleton = out.read_text()
    got = yaml.safe_load(skeleton)
    assert got["controller"]["name"] == model
    assert list(got["controller"]["inputs"]["fields"]) == ["on", "yes"]
    out.write_text(skeleton[:skeleton.index("\ntopics:\n") + 1] + _FILLED)
    code, text, err = run(capsys, "check", out)
    assert code == 0, err
    from pyrosgen import load_model

    assert load_model(out).controller.name == model

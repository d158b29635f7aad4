"""``pyrosgen check``: exit codes, message format, streams."""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

from pyrosgen import cli

from support.frontend import LANDSHARK, MODELS, MULTI, REPO

DIAG = re.compile(r"^(?P<file>.+?):(?P<line>\d+):(?P<col>\d+): error: (?P<msg>.+)$")


def run(capsys, *argv):
    code = cli.main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_check_ok(capsys):
    code, out, err = run(capsys, "check", str(LANDSHARK))
    assert code == 0
    assert out == (
        f"{LANDSHARK}: ok: node landshark_controller, 4 topics, "
        "3 input relations, 1 output relation\n"
    )
    assert err == ""


def test_check_ok_multi(capsys):
    code, out, err = run(capsys, "check", str(MULTI))
    assert code == 0
    assert out.endswith(": ok: node multi_node, 6 topics, 11 input relations, 9 output relations\n")
    assert err == ""


def test_check_reports_every_error(capsys):
    path = MODELS / "ko_three_errors.yaml"
    code, out, err = run(capsys, "check", str(path))
    assert code == 1
    assert out == ""
    lines = err.splitlines()
    assert len(lines) == 3
    parsed = [DIAG.match(line) for line in lines]
    assert all(parsed), lines
    assert [m.group("file") for m in parsed] == [str(path)] * 3
    assert [int(m.group("line")) for m in parsed] == [7, 14, 51]
    assert "period_ms" in parsed[0].group("msg")
    assert "unknown type 'real'" in parsed[1].group("msg")
    assert "has no field 'w'" in parsed[2].group("msg")


@pytest.mark.parametrize("path", sorted(MODELS.glob("ko_*.yaml")), ids=lambda p: p.name)
def test_every_ko_model_exits_1_with_compiler_style_lines(capsys, path):
    code, out, err = run(capsys, "check", str(path))
    assert code == 1
    assert out == ""
    assert err.endswith("\n")
    for line in err.splitlines():
        assert DIAG.match(line) or re.match(r"^.+\.msg: error: .+$", line), line
    assert "Traceback" not in err


def test_missing_file(capsys, tmp_path):
    missing = tmp_path / "nope.yaml"
    code, out, err = run(capsys, "check", str(missing))
    assert code == 1
    assert out == ""
    assert err == f"{missing}: error: cannot read file: No such file or directory [rule 4.1]\n"


def test_directory(capsys, tmp_path):
    code, out, err = run(capsys, "check", str(tmp_path))
    assert code == 1
    assert err == f"{tmp_path}: error: cannot read file: it is a directory [rule 4.1]\n"


def test_usage_errors_exit_1(capsys):
    code, out, err = run(capsys)
    assert code == 1 and out == "" and "usage: pyrosgen" in err
    code, out, err = run(capsys, "frobnicate")
    assert code == 1 and "invalid choice" in err
    code, out, err = run(capsys, "check")
    assert code == 1 and "MODEL.yaml" in err
    code, out, err = run(capsys, "check", "a.yaml", "b.yaml")
    assert code == 1 and "unrecognized arguments" in err


def test_help_exits_0(capsys):
    code, out, err = run(capsys, "--help")
    assert code == 0 and "check" in out
    code, out, err = run(capsys, "check", "--help")
    assert code == 0 and "MODEL.yaml" in out


def test_internal_error_exits_2_without_traceback(capsys, monkeypatch):
    import pyrosgen.frontend.validate

    def boom(path):
        raise RuntimeError("boom\nsecond line")

    monkeypatch.setattr(pyrosgen.frontend.validate, "load_model", boom)
    monkeypatch.delenv("PYROSGEN_DEBUG", raising=False)
    code, out, err = run(capsys, "check", str(LANDSHARK))
    assert code == 2
    assert out == ""
    assert err.startswith("pyrosgen: internal error: RuntimeError: boom second line")
    assert "Traceback" not in err
    assert len(err.splitlines()) == 1


def test_internal_error_traceback_with_debug(monkeypatch):
    import pyrosgen.frontend.validate

    def boom(path):
        raise RuntimeError("boom")

    monkeypatch.setattr(pyrosgen.frontend.validate, "load_model", boom)
    monkeypatch.setenv("PYROSGEN_DEBUG", "1")
    with pytest.raises(RuntimeError, match="boom"):
        cli.main(["check", str(LANDSHARK)])


def test_parser_has_subcommands():
    parser = cli.build_parser()
    sub = [a for a in parser._actions if a.__class__.__name__ == "_SubParsersAction"]
    assert sub and "check" in sub[0].choices


# --------------------------------------------------------------------------
# Real processes


def _env():
    env = dict(os.environ)
    env.pop("PYROSGEN_DEBUG", None)
    return env


def test_python_m_pyrosgen_ok():
    p = subprocess.run(
        [sys.executable, "-m", "pyrosgen", "check", str(LANDSHARK)],
        capture_output=True,
        text=True,
        cwd=REPO,
        env=_env(),
        timeout=120,
    )
    assert p.returncode == 0, p.stderr
    assert p.stdout.startswith(f"{LANDSHARK}: ok: node landshark_controller")
    assert p.stderr == ""


def test_python_m_pyrosgen_ko_relative_paths():
    rel = Path("tests/frontend/models/ko_msg_cycle.yaml")
    p = subprocess.run(
        [sys.executable, "-m", "pyrosgen", "check", str(rel)],
        capture_output=True,
        text=True,
        cwd=REPO,
        env=_env(),
        timeout=120,
    )
    assert p.returncode == 1
    assert p.stdout == ""
    # The .msg file is named relative to the working directory, like the model.
    assert p.stderr == (
        "tests/frontend/badmsgs/cycle/bad_msgs/msg/B.msg:2:1: error: message type "
        "bad_msgs/B contains itself (bad_msgs/A -> bad_msgs/B -> bad_msgs/A) [rule 4.5]\n"
    )


def test_console_script():
    script = Path(sys.executable).parent / "pyrosgen"
    assert script.exists(), "make venv installs the pyrosgen console script"
    p = subprocess.run(
        [str(script), "check", str(MODELS / "ko_three_errors.yaml")],
        capture_output=True,
        text=True,
        env=_env(),
        timeout=120,
    )
    assert p.returncode == 1
    assert p.stdout == ""
    assert len(p.stderr.splitlines()) == 3


def test_odd_file_names(capsys, tmp_path):
    code, out, err = run(capsys, "check", "a\x00b.yaml")
    assert code == 1 and "cannot read file: invalid file name" in err
    long_name = str(tmp_path / ("x" * 5000))
    code, out, err = run(capsys, "check", long_name)
    assert code == 1 and "cannot read file: File name too long" in err
    unicode_name = tmp_path / "m\u00f6del.yaml"
    unicode_name.write_text((REPO / "examples/landshark/landshark_controller.yaml").read_text())
    code, out, err = run(capsys, "check", str(unicode_name))
    assert code == 0 and out.startswith(str(unicode_name))


def test_model_from_a_pipe():
    # /dev/stdin is not a regular file: the size limit still holds while reading.
    text = LANDSHARK.read_text()
    p = subprocess.run(
        [sys.executable, "-m", "pyrosgen", "check", "/dev/stdin"],
        input=text,
        capture_output=True,
        text=True,
        cwd=LANDSHARK.parent,
        env=_env(),
        timeout=120,
    )
    assert p.returncode == 0, p.stderr
    assert p.stdout.startswith("/dev/stdin: ok: node landshark_controller")
    p = subprocess.run(
        [sys.executable, "-m", "pyrosgen", "check", "/dev/stdin"],
        input="#" * (2 * 1024 * 1024),
        capture_output=True,
        text=True,
        env=_env(),
        timeout=120,
    )
    assert p.returncode == 1
    assert p.stderr == "/dev/stdin: error: file too large (more than 1048576 bytes) [rule 4.1]\n"

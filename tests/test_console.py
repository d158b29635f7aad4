"""Command-line polish: colour only on a terminal (or when forced), NO_COLOR,
--verbose showing external commands, examples in every --help."""

from __future__ import annotations

import io
import subprocess
import sys
from pathlib import Path

import pytest

from pyrosgen import console
from pyrosgen.cli import main

ROOT = Path(__file__).resolve().parents[1]
LANDSHARK = ROOT / "examples/landshark/landshark_controller.yaml"
BAD = "node: {name: x, period_ms: 0}\n"


class _Tty(io.StringIO):
    def isatty(self) -> bool:
        return True


def test_colour_only_on_a_terminal(monkeypatch):
    monkeypatch.delenv("NO_COLOR", raising=False)
    monkeypatch.delenv("PYROSGEN_COLOR", raising=False)
    monkeypatch.setenv("TERM", "xterm")
    text = "m.yaml:1:1: error: bad"
    assert console.colourize(text, io.StringIO()) == text          # a pipe or file: plain
    coloured = console.colourize(text, _Tty())
    assert "\033[1;31merror:\033[0m" in coloured and coloured != text
    monkeypatch.setenv("NO_COLOR", "")                              # https://no-color.org
    assert console.colourize(text, _Tty()) == text
    monkeypatch.delenv("NO_COLOR")
    monkeypatch.setenv("TERM", "dumb")
    assert console.colourize(text, _Tty()) == text
    monkeypatch.setenv("PYROSGEN_COLOR", "always")
    assert "\033[" in console.colourize(text, io.StringIO())
    monkeypatch.setenv("PYROSGEN_COLOR", "never")
    assert console.colourize(text, _Tty()) == text


def test_cli_errors_plain_when_piped(tmp_path):
    m = tmp_path / "bad.yaml"
    m.write_text(BAD)
    r = subprocess.run([sys.executable, "-m", "pyrosgen", "check", str(m)],
                       capture_output=True, text=True, env={"PATH": "/usr/bin:/bin", "TERM": "xterm"})
    assert r.returncode == 1
    assert "error:" in r.stderr and "\033[" not in r.stderr
    r = subprocess.run([sys.executable, "-m", "pyrosgen", "check", str(m)], capture_output=True, text=True,
                       env={"PATH": "/usr/bin:/bin", "PYROSGEN_COLOR": "always"})
    assert r.returncode == 1 and "\033[1;31merror:" in r.stderr


@pytest.mark.parametrize("cmd", ["check", "diagram", "generate", "build"])
def test_help_has_examples(cmd, capsys):
    assert main([cmd, "--help"]) == 0
    out = capsys.readouterr().out
    assert "examples:" in out and f"pyrosgen {cmd} " in out


def test_top_level_help_lists_exit_codes(capsys):
    assert main(["--help"]) == 0
    out = capsys.readouterr().out
    assert "exit codes: 0 success, 1 invalid model or usage, 2 proof or tool failure" in out


def test_verbose_shows_external_commands(tmp_path, capsys):
    """`pyrosgen -v generate` prints each external command and how it ended;
    without -v it prints none."""
    try:
        assert main(["-v", "generate", str(LANDSHARK), "-o", str(tmp_path / "v"), "-q"]) == 0
        err = capsys.readouterr().err
        assert "pyrosgen: $ /usr/bin/coqc " in err and "pyrosgen:   coqc: exit 0" in err
        assert "pyrosgen: $ /usr/bin/coqchk " in err and "pyrosgen:   coqchk: exit 0" in err
        assert main(["generate", str(LANDSHARK), "-o", str(tmp_path / "q"), "-q"]) == 0
        assert "pyrosgen: $" not in capsys.readouterr().err
    finally:
        console.VERBOSE = False


"""YAML 1.1 number forms a user does not mean (``020`` is octal 16, ``1:20``
is 80) are refused with the key, the line and the reason, not read
silently; plain decimals (with a sign) and quoted strings behave as
before."""

from __future__ import annotations

from pathlib import Path

import pytest

from pyrosgen import cli

LANDSHARK = Path(__file__).resolve().parents[2] / "examples/landshark/landshark_controller.yaml"


def _check(capsys, tmp_path, old, new):
    text = LANDSHARK.read_text()
    assert old in text
    m = tmp_path / "m.yaml"
    m.write_text(text.replace(old, new, 1))
    code = cli.main(["check", str(m)])
    out, err = capsys.readouterr()
    return code, out + err


@pytest.mark.parametrize("value, reason", [
    ("020", "a leading zero makes it octal in YAML 1.1 (it would be read as 16)"),
    ("0020", "a leading zero makes it octal in YAML 1.1 (it would be read as 16)"),
    ("1:20", "YAML 1.1 reads it as a base-60 (sexagesimal) number"),
    ("0x14", "it is hexadecimal"),
    ("0b10100", "it is binary"),
    ("2_0", "it has '_' separators"),
    ("1:20.5", "YAML 1.1 reads it as a base-60 (sexagesimal) number"),
    (".inf", "it is not a finite number"),
    ("-.inf", "it is not a finite number"),
    (".NaN", "it is not a finite number"),
])
def test_refused_number_forms(capsys, tmp_path, value, reason):
    code, text = _check(capsys, tmp_path, "period_ms: 20", f"period_ms: {value}")
    assert code == 1
    assert f":6:14: error: period_ms: number '{value}': {reason}; write" in text
    assert text.rstrip().endswith("[rule 4.1]") and "Traceback" not in text


def test_queue_size_in_octal_is_refused_on_every_line(capsys, tmp_path):
    text = LANDSHARK.read_text().replace("queue_size: 1}", "queue_size: 010}")
    m = tmp_path / "m.yaml"
    m.write_text(text)
    assert cli.main(["check", str(m)]) == 1
    err = capsys.readouterr().err
    assert err.count("queue_size: number '010': a leading zero makes it octal") == 4


@pytest.mark.parametrize("value", ["20", "+20"])
def test_plain_decimals_pass(capsys, tmp_path, value):
    code, text = _check(capsys, tmp_path, "period_ms: 20", f"period_ms: {value}")
    assert code == 0, text


def test_quoted_number_is_a_string(capsys, tmp_path):
    code, text = _check(capsys, tmp_path, "period_ms: 20", "period_ms: '020'")
    assert code == 1 and "got string '020'" in text

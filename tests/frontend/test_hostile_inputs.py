"""Hostile inputs to the front end (issue 13).

Numbers: every plain scalar YAML 1.1 would read unlike what a user means,
or reads as text although it looks like a number (``08``, ``0o20``,
``1:60``), is refused with the file, line, column and key, rule 4.1, and
is never constructed (a 1 MiB base-60 number took 18 s to construct).

Message files: a ``.msg`` in ``msg_paths`` that is not a regular file (a
FIFO, a socket, a device) is refused without being opened; the checks run
in a subprocess with a timeout, so that a regression fails instead of
hanging the suite.
"""

from __future__ import annotations

import os
import socket
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest
import yaml

from pyrosgen import cli
from pyrosgen.frontend.yamlsrc import parse_yaml

ROOT = Path(__file__).resolve().parents[2]
LANDSHARK = ROOT / "examples/landshark/landshark_controller.yaml"


def _check(capsys, tmp_path, old, new):
    text = LANDSHARK.read_text()
    assert old in text
    m = tmp_path / "m.yaml"
    m.write_text(text.replace(old, new, 1))
    code = cli.main(["check", str(m)])
    out, err = capsys.readouterr()
    return code, out + err


# --------------------------------------------------------------------------
# Numbers


@pytest.mark.parametrize("value, reason", [
    ("08", "a leading zero makes it ambiguous (YAML 1.1 reads 010 as octal 8 and 08 as text)"),
    ("019", "a leading zero makes it ambiguous (YAML 1.1 reads 010 as octal 8 and 019 as text)"),
    ("-09", "a leading zero makes it ambiguous (YAML 1.1 reads 010 as octal 8 and -09 as text)"),
    ("0o20", "it is octal in YAML 1.2's form, which YAML 1.1 reads as text"),
    ("1:60", "it looks like a base-60 (sexagesimal) number (YAML 1.1 reads 1:20 as 80)"),
    ("0:20", "it looks like a base-60 (sexagesimal) number (YAML 1.1 reads 1:20 as 80)"),
    ("-020", "a leading zero makes it octal in YAML 1.1 (it would be read as -16)"),
    ("0x_", "it is hexadecimal"),
])
def test_number_like_forms_are_refused_as_numbers(capsys, tmp_path, value, reason):
    """These were read as text (or octal -16, or failed construction) and
    reported as "got string '08'" under rule 4.2, or without the key."""
    code, text = _check(capsys, tmp_path, "period_ms: 20", f"period_ms: {value}")
    assert code == 1
    assert f"m.yaml:6:14: error: period_ms: number '{value}': {reason}; write numbers in plain decimal" in text
    assert text.rstrip().endswith("[rule 4.1]") and "Traceback" not in text


@pytest.mark.parametrize("value, shown, reason", [
    ("!!int '020'", "020", "a leading zero makes it octal in YAML 1.1 (it would be read as 16)"),
    ('!!int "0x14"', "0x14", "it is hexadecimal"),
    ("!!int 08", "08", "a leading zero makes it ambiguous"),
    ("!!float '1:20.5'", "1:20.5", "YAML 1.1 reads it as a base-60 (sexagesimal) number"),
])
def test_explicit_tags_do_not_bypass_the_check(capsys, tmp_path, value, shown, reason):
    """``!!int '020'`` was constructed as 16 and accepted as a period."""
    code, text = _check(capsys, tmp_path, "period_ms: 20", f"period_ms: {value}")
    assert code == 1
    assert f"m.yaml:6:14: error: period_ms: number '{shown}': {reason}" in text
    assert "[rule 4.1]" in text


def test_refused_forms_are_never_constructed(monkeypatch):
    """Refusing must not first compute the value: a long base-60 number
    costs quadratic time to construct."""
    seen = []
    for kind in ("int", "float"):
        original = getattr(yaml.SafeLoader, f"construct_yaml_{kind}")

        def spy(self, node, _original=original):
            seen.append(node.value)
            return _original(self, node)

        monkeypatch.setattr(yaml.SafeLoader, f"construct_yaml_{kind}", spy)
    doc = parse_yaml("a: 1:20\nb: 0x10\nc: 1:20.5\nd: 020\ne: 20\n", "t.yaml")
    assert seen == ["20"]
    assert [d.line for d in doc.diagnostics] == [1, 2, 3, 4]
    assert all(d.rule == "4.1" for d in doc.diagnostics)


def test_huge_base60_number_is_refused_quickly(tmp_path):
    """A 900 kB base-60 number: refused in well under the timeout (it took
    18 s before); a regression fails here instead of hanging."""
    text = LANDSHARK.read_text().replace("period_ms: 20", "period_ms: 1" + ":59" * 300_000)
    m = tmp_path / "m.yaml"
    m.write_text(text)
    r = subprocess.run([sys.executable, "-m", "pyrosgen", "check", str(m)], cwd=ROOT, capture_output=True,
                       text=True, stdin=subprocess.DEVNULL, timeout=30)
    assert r.returncode == 1
    assert "m.yaml:6:14: error: period_ms: number '1:59:59" in r.stderr
    assert "YAML 1.1 reads it as a base-60 (sexagesimal) number" in r.stderr


def test_long_decimal_names_the_key(capsys, tmp_path):
    """Python refuses to convert more than 4300 digits; this was reported as
    "invalid int value" without the key."""
    code, text = _check(capsys, tmp_path, "period_ms: 20", "period_ms: 1" + "0" * 5000)
    assert code == 1
    assert "m.yaml:6:14: error: period_ms: number '1000" in text
    assert "is too long (5001 characters) [rule 4.1]" in text


def test_list_items_name_their_list(capsys, tmp_path):
    code, text = _check(capsys, tmp_path, "msg_paths: []", "msg_paths: [msg, 08]")
    assert code == 1
    assert "error: msg_paths[1]: number '08': a leading zero makes it ambiguous" in text
    assert "(quote it if it is meant as text) [rule 4.1]" in text


def test_quoted_forms_are_text(capsys, tmp_path):
    code, text = _check(capsys, tmp_path, "period_ms: 20", "period_ms: '08'")
    assert code == 1
    assert "node.period_ms must be an integer from 1 to 3600000 (milliseconds), got string '08' [rule 4.2]" in text


@pytest.mark.parametrize("value", ["20", "+20", "!!int 20"])
def test_plain_decimals_still_pass(capsys, tmp_path, value):
    code, text = _check(capsys, tmp_path, "period_ms: 20", f"period_ms: {value}")
    assert code == 0, text


def test_number_like_keys_are_names():
    """Keys are names: their text is kept as written and checked as a name."""
    doc = parse_yaml("fields: {010: float64, 1:20: float64}\n", "t.yaml")
    assert doc.diagnostics == []
    assert doc.root.get("fields").keys() == ["010", "1:20"]


# --------------------------------------------------------------------------
# Message files that are not regular files

MODEL = """node: {name: big, period_ms: 10}
controller:
  name: C
  inputs: {name: C_U, fields: {In1: float64}}
  outputs: {name: C_Y, fields: {Out1: float64}}
msg_paths: [msg]
topics:
  - {name: /big, direction: subscribe, type: big_msgs/Big, queue_size: 1}
  - {name: /out, direction: publish, type: std_msgs/Float64, queue_size: 1}
relations:
  inputs:
    - {topic: /big, field: x, input: In1}
  outputs:
    - {output: Out1, topic: /out, field: data}
"""

# Runs ``pyrosgen check`` with os.open watched: prints every path opened
# whose name ends in .msg, one per line, after the command's own output.
_SPY = textwrap.dedent("""
    import os, sys
    opened = []
    _open = os.open
    def spy(path, *a, **k):
        if str(path).endswith(".msg"):
            opened.append(str(path))
        return _open(path, *a, **k)
    os.open = spy
    from pyrosgen import cli
    code = cli.main(["check", sys.argv[1]])
    sys.stdout.write("".join(f"OPENED {p}\\n" for p in opened))
    sys.exit(code)
""")


def _check_watched(model: Path) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-c", _SPY, str(model)], cwd=ROOT, capture_output=True, text=True,
                          stdin=subprocess.DEVNULL, timeout=30)


def _model_with(tmp_path: Path, make) -> Path:
    folder = tmp_path / "msg" / "big_msgs" / "msg"
    folder.mkdir(parents=True)
    make(folder / "Big.msg")
    (tmp_path / "m.yaml").write_text(MODEL)
    return tmp_path / "m.yaml"


def test_fifo_is_refused_without_being_opened(tmp_path):
    model = _model_with(tmp_path, os.mkfifo)
    r = _check_watched(model)
    assert r.returncode == 1, r.stderr
    assert "Big.msg: error: cannot read message definition: it is a FIFO, not a regular file [rule 4.5]" in r.stderr
    assert "OPENED" not in r.stdout


def test_device_is_refused_without_being_opened(tmp_path):
    model = _model_with(tmp_path, lambda p: p.symlink_to("/dev/null"))
    r = _check_watched(model)
    assert r.returncode == 1, r.stderr
    assert "Big.msg: error: cannot read message definition: it is a device, not a regular file [rule 4.5]" in r.stderr
    assert "OPENED" not in r.stdout


def test_socket_is_refused_as_a_socket(tmp_path):
    """Opening a socket failed with "No such device or address"."""
    sockets = []

    def make(p: Path) -> None:
        s = socket.socket(socket.AF_UNIX)
        sockets.append(s)
        s.bind(str(p))

    try:
        model = _model_with(tmp_path, make)
        r = _check_watched(model)
    finally:
        for s in sockets:
            s.close()
    assert r.returncode == 1, r.stderr
    assert "Big.msg: error: cannot read message definition: it is a socket, not a regular file [rule 4.5]" in r.stderr
    assert "OPENED" not in r.stdout


def test_directory_named_like_a_message_is_named_as_such(tmp_path):
    model = _model_with(tmp_path, lambda p: p.mkdir())
    r = _check_watched(model)
    assert r.returncode == 1, r.stderr
    assert "Big.msg: error: cannot read message definition: it is a directory, not a regular file [rule 4.5]" \
        in r.stderr
    assert "Traceback" not in r.stderr


def test_regular_message_file_is_read(tmp_path):
    model = _model_with(tmp_path, lambda p: p.write_text("float64 x\n"))
    r = _check_watched(model)
    assert r.returncode == 0, r.stderr
    assert "OPENED" in r.stdout and "m.yaml: ok: node big" in r.stdout


def test_symlink_to_a_regular_message_file_is_read(tmp_path):
    (tmp_path / "Real.msg").write_text("float64 x\n")
    model = _model_with(tmp_path, lambda p: p.symlink_to(tmp_path / "Real.msg"))
    r = _check_watched(model)
    assert r.returncode == 0, r.stderr


# --------------------------------------------------------------------------
# The YAML 1.1 forms of the first version of the check, and the model file

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


def test_model_file_that_is_a_device(tmp_path):
    """A model named by the user may be a pipe (check /dev/stdin, tested in
    test_cli.py); a device is read up to the size limit, then refused."""
    r = subprocess.run([sys.executable, "-m", "pyrosgen", "check", "/dev/zero"], cwd=ROOT, capture_output=True,
                       text=True, stdin=subprocess.DEVNULL, timeout=60)
    assert r.returncode == 1 and "too large" in r.stderr and "Traceback" not in r.stderr

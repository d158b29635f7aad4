"""Hostile inputs: huge files, YAML bombs, deep nesting, binary data, and
names crafted to break the generated C, C++ or Coq text.  Every one must end
in a clear one-line error (exit 1), quickly, and never a traceback."""

from __future__ import annotations

import re
import time

import pytest
import yaml

from pyrosgen import InvalidNodeModel, load_model
from pyrosgen.cli import main
from pyrosgen.frontend.yamlsrc import MAX_DEPTH, MAX_FILE_SIZE

from support.frontend import LANDSHARK

LS_TEXT = LANDSHARK.read_text(encoding="utf-8")


def fails(path, fragment, line=None):
    """load_model(path) raises InvalidNodeModel with a diagnostic containing
    ``fragment`` (at ``line`` when given); return the diagnostics."""
    start = time.monotonic()
    with pytest.raises(InvalidNodeModel) as info:
        load_model(path)
    assert time.monotonic() - start < 10
    diags = info.value.diagnostics
    assert any(fragment in d.message and (line is None or d.line == line) for d in diags), "\n".join(
        map(str, diags)
    )
    for d in diags:
        text = str(d)
        assert "\n" not in text and "\r" not in text
        assert text.isprintable()
    return diags


def cli_fails(capsys, path):
    code = main(["check", str(path)])
    out, err = capsys.readouterr()
    assert code == 1
    assert out == ""
    assert "Traceback" not in err
    return err


def test_50_mb_file(tmp_path, capsys):
    p = tmp_path / "huge.yaml"
    with open(p, "wb") as fh:
        chunk = b"# padding padding padding padding padding padding padding\n" * 1000
        for _ in range(50 * 1024 * 1024 // len(chunk) + 1):
            fh.write(chunk)
    d = fails(p, "file too large")
    assert d[0].line is None
    err = cli_fails(capsys, p)
    assert err.startswith(f"{p}: error: file too large (")


def test_just_over_the_limit_is_refused_and_at_the_limit_is_read(tmp_path):
    body = LS_TEXT.encode()
    pad = b"#" * 99 + b"\n"
    ok = tmp_path / "ok.yaml"
    data = body + pad * ((MAX_FILE_SIZE - len(body)) // len(pad))
    data += b"#" * (MAX_FILE_SIZE - len(data))
    assert len(data) == MAX_FILE_SIZE
    ok.write_bytes(data)
    assert load_model(ok).name == "landshark_controller"
    big = tmp_path / "big.yaml"
    big.write_bytes(data + b"#")
    fails(big, "file too large")


def test_billion_laughs(tmp_path, capsys):
    lol = ['a: &a ["lol","lol","lol","lol","lol","lol","lol","lol","lol"]']
    for i, name in enumerate("bcdefghij"):
        prev = "abcdefghij"[i]
        lol.append(f"{name}: &{name} [" + ",".join([f"*{prev}"] * 9) + "]")
    p = tmp_path / "lol.yaml"
    p.write_text("\n".join(lol) + "\n")
    fails(p, "anchor &a is not allowed", line=1)
    cli_fails(capsys, p)


def test_alias_only_reference(tmp_path):
    p = tmp_path / "alias.yaml"
    p.write_text(LS_TEXT.replace("period_ms: 20", "period_ms: &p 20\n  other: *p"))
    fails(p, "anchor &p is not allowed")


@pytest.mark.parametrize(
    "text",
    [
        "[" * 10000 + "]" * 10000,
        "a: " + "[" * 10000 + "]" * 10000,
        "{a: " * 10000 + "1" + "}" * 10000,
        "- " * 10000 + "x\n",
        "".join(f"{' ' * i}k:\n" for i in range(500)) + " " * 500 + "x\n",
    ],
    ids=["flow-seq", "flow-seq-value", "flow-map", "block-seq", "block-map"],
)
def test_deep_nesting(tmp_path, capsys, text):
    p = tmp_path / "deep.yaml"
    p.write_text(text)
    with pytest.raises(InvalidNodeModel) as info:
        load_model(p)
    msg = str(info.value)
    assert ("nesting too deep" in msg) or ("YAML syntax error" in msg), msg
    cli_fails(capsys, p)


def test_nesting_just_within_the_limit_is_fine(tmp_path):
    # MAX_DEPTH levels parse (and are then refused by the schema, not the parser).
    p = tmp_path / "d.yaml"
    p.write_text("x: " + "[" * (MAX_DEPTH - 1) + "]" * (MAX_DEPTH - 1) + "\n")
    d = fails(p, "unknown key 'x'")
    assert not any("too deep" in x.message for x in d)


def test_nul_bytes(tmp_path, capsys):
    p = tmp_path / "nul.yaml"
    p.write_bytes(LS_TEXT.encode().replace(b"period_ms: 20", b"period_ms: 2\x000"))
    fails(p, "NUL byte", line=6)
    cli_fails(capsys, p)


def test_invalid_utf8(tmp_path, capsys):
    p = tmp_path / "latin1.yaml"
    p.write_bytes(LS_TEXT.encode().replace(b"name: landshark_controller", b"name: landsh\xe4rk"))
    fails(p, "not valid UTF-8 (byte 0xe4)", line=5)
    cli_fails(capsys, p)


def test_utf16(tmp_path):
    p = tmp_path / "u16.yaml"
    p.write_bytes(LS_TEXT.encode("utf-16"))
    fails(p, "UTF-16")


def test_utf8_bom_is_accepted(tmp_path):
    p = tmp_path / "bom.yaml"
    p.write_bytes(b"\xef\xbb\xbf" + LS_TEXT.encode())
    assert load_model(p).name == "landshark_controller"


def test_control_characters(tmp_path):
    p = tmp_path / "bell.yaml"
    p.write_text(LS_TEXT.replace("name: landshark_controller", "name: landshark\x07controller"))
    fails(p, "non-printable character U+0007", line=5)


def test_random_binary(tmp_path):
    import random

    rnd = random.Random(1234)
    for i in range(20):
        p = tmp_path / f"bin{i}.yaml"
        p.write_bytes(bytes(rnd.randrange(256) for _ in range(2000)))
        with pytest.raises(InvalidNodeModel):
            load_model(p)


# Names crafted to break out of C strings or comments, C++ or Coq text.
HOSTILE = [
    'a"b',
    "a*/b",
    "a/*b",
    "a;b",
    "a\nb",
    "a\\b",
    "abc\u00e9",
    "\u202eabc",
    "a b",
    "a(*b",
    "a.b",
    "a'b",
    "{{ x }}",
    "${HOME}",
    "%s%n",
    "a\tb",
]


def _dump_with(key_path, value):
    data = yaml.safe_load(LS_TEXT)
    cur = data
    for k in key_path[:-1]:
        cur = cur[k]
    cur[key_path[-1]] = value
    return yaml.safe_dump(data, allow_unicode=True, sort_keys=False)


@pytest.mark.parametrize("name", HOSTILE)
@pytest.mark.parametrize(
    "where",
    [
        ("node", "name"),
        ("controller", "name"),
        ("controller", "inputs", "name"),
        ("topics", 0, "name"),
        ("relations", "inputs", 0, "field"),
    ],
    ids=lambda w: ".".join(map(str, w)),
)
def test_hostile_names(tmp_path, capsys, name, where):
    p = tmp_path / "m.yaml"
    p.write_text(_dump_with(where, name), encoding="utf-8")
    diags = fails(p, "")
    assert len(diags) >= 1
    # The user's text appears escaped: no raw control or non-ASCII character.
    for d in diags:
        assert re.fullmatch(r"[ -~]*", d.message), d.message
    err = cli_fails(capsys, p)
    assert all(re.fullmatch(r"[ -~]*", line) for line in err.splitlines())


@pytest.mark.parametrize("name", HOSTILE)
def test_hostile_controller_field_names(tmp_path, name):
    data = yaml.safe_load(LS_TEXT)
    data["controller"]["inputs"]["fields"] = {name: "float64", "In2": "float64", "In3": "float64"}
    data["relations"]["inputs"][0]["input"] = name
    p = tmp_path / "m.yaml"
    p.write_text(yaml.safe_dump(data, allow_unicode=True, sort_keys=False), encoding="utf-8")
    diags = fails(p, "cannot be used")
    assert all(re.fullmatch(r"[ -~]*", d.message) for d in diags)


def test_hostile_msg_field_names(tmp_path):
    # rosbags would accept these names in a .msg file; the glue must not.
    (tmp_path / "p/msg").mkdir(parents=True)
    (tmp_path / "p/msg/T.msg").write_text("float64 x\nfloat64 auto\nint8 Qed\n")
    data = yaml.safe_load(LS_TEXT)
    data["msg_paths"] = [str(tmp_path)]
    data["topics"][3]["type"] = "p/T"
    data["relations"]["outputs"][0]["field"] = "x"
    p = tmp_path / "m.yaml"
    p.write_text(yaml.safe_dump(data, sort_keys=False))
    diags = fails(p, "field name 'auto' of p/T cannot be used in generated code: it is a C keyword", line=2)
    assert any("'Qed'" in d.message and d.line == 3 for d in diags)


def test_many_errors_stay_fast(tmp_path):
    # 2000 bad relations: all reported, quickly.
    data = yaml.safe_load(LS_TEXT)
    data["relations"]["inputs"] += [
        {"topic": "/landshark/gps_velocity", "field": f"twist.linear.q{i}", "input": "In1"} for i in range(2000)
    ]
    p = tmp_path / "m.yaml"
    p.write_text(yaml.safe_dump(data, sort_keys=False))
    start = time.monotonic()
    with pytest.raises(InvalidNodeModel) as info:
        load_model(p)
    assert time.monotonic() - start < 30
    assert len(info.value.diagnostics) == 4000  # a path error and a "fed twice" each

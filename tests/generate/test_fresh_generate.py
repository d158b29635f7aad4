"""Timed nodes through the whole pipeline (rule 4.12): ``generate`` on the
velocity guard and on small models with each feature (every policy,
flags only, constant fallbacks of every type) proves their theorem,
prints the timed glue in the order of the design (the clock update after
the callback's copies; in ``input_glue``, after the copies, the cycle's
time if an age is read, then each fallback and derived input, a
fallback or ``age_ms`` just after its topic's age, then the ``_new``
resets), compiles with the build's flags and against the
wrapper's header, shows it in the certificate with its C lines, and
``verify`` accepts the folder; the seam catches a per-node file that
drops or changes a timeout, a fallback or a derived input (it still
proves a theorem, about another node: exit 2), and Coq refuses one that
leaves an input unfed (exit 1)."""

from __future__ import annotations

import re
import subprocess

import pytest

import pyrosgen.generate as gen
from pyrosgen import cli
from pyrosgen.frontend.validate import load_model
from pyrosgen.ros import wrapper as rosgen
from pyrosgen.verify.certificate import CertificateError, _freshness
from pyrosgen.proof.modeltext import parse_model_text
from pyrosgen.verify.wrapper_check import check_glue_externals

from support.generate import MODELS, REPO, require_library

GUARD = REPO / "examples" / "velocity_guard" / "velocity_guard.yaml"
POLICIES = MODELS / "ok_fresh_policies.yaml"
FLAGS = MODELS / "ok_fresh_flags.yaml"
CONSTANTS = MODELS / "ok_fresh_constants.yaml"
NODES = {"velocity_guard": GUARD, "fresh_policies": POLICIES, "fresh_flags": FLAGS,
         "fresh_constants": CONSTANTS}


@pytest.fixture(scope="module")
def folders(tmp_path_factory):
    """Each node generated once: name -> output folder."""
    require_library()
    base = tmp_path_factory.mktemp("fresh")
    out = {}
    for node, path in NODES.items():
        d = base / node
        assert cli.main(["generate", str(path), "-o", str(d), "-q"]) == 0, node
        out[node] = d
    return out


def body(c: str, head: str) -> list[str]:
    """The statements of the function whose definition starts with ``head``
    (without the declarations of its temporaries), stripped."""
    text = c[c.index(head + "\n{\n") + len(head) + 3:]
    lines = [ln.strip() for ln in text[:text.index("\n}\n")].splitlines()]
    return [ln for ln in lines if not re.fullmatch(r"(unsigned |signed )?(char|short|int|long long|float|double) "
                                                   r"_\w+;", ln)]


def temps(c: str, head: str) -> list[str]:
    text = c[c.index(head + "\n{\n"):]
    return re.findall(r"^    [a-z ]+ (_\w+);$", text[:text.index("\n}\n")], re.M)


def age_block(c: str) -> list[str]:
    return [f"if ({c}_rcvd) {{", f"if (({c}_time <= _now)) {{", f"_age = (_now - {c}_time);", "} else {",
            "_age = 0ULL;", "}", "} else {", "_age = 18446744073709551615ULL;", "}"]


def expected_timed_part(model) -> list[str]:
    """What ``input_glue`` does after the copies, from the front end's
    model: a regular expression per statement line.  The cycle's time is
    read once if some item reads an age; then each fallback (in the order
    of the input relations) and each derived input (in model order), a
    fallback or an ``age_ms`` computing its topic's age just before it;
    then the ``_new`` resets of the timed topics."""
    u = model.controller.inputs.var_name
    timed = model.timed_topics
    items: list[list[str]] = []
    for r in model.input_relations:
        if r.fallback is None:
            continue
        t = r.topic
        items.append([re.escape(x) for x in age_block(t.c_name)]
                     + [re.escape(f"if (({t.timeout_ms * 1000000}ULL < _age)) {{"),
                        re.escape(f"{u}.{r.input_field} = ") + r"[^;]+;", r"\}"])
    for r in model.derived_relations:
        t = r.topic
        if r.kind == "age_ms":
            items.append([re.escape(x) for x in age_block(t.c_name)]
                         + [re.escape(x) for x in ("if ((_age <= 4294967295999999ULL)) {",
                                                   f"{u}.{r.input_field} = (unsigned int)(_age / 1000000ULL);",
                                                   "} else {", f"{u}.{r.input_field} = 4294967295U;", "}")])
        else:
            flag = "new" if r.kind == "is_new" else "rcvd"
            items.append([re.escape(f"_t_uchar = {t.c_name}_{flag};"),
                          re.escape(f"{u}.{r.input_field} = _t_uchar;")])
    out: list[str] = []
    if any(p[0].startswith("if") for p in items):
        out.append(re.escape("_now = ros_now();"))
    for p in items:
        out += p
    out += [re.escape(f"{t.c_name}_new = 0;") for t in timed]
    return out


@pytest.mark.parametrize("node", list(NODES))
def test_input_glue_order(folders, node):
    """The copies of every input relation first (as without freshness),
    then the timed part, exactly as the design says, in model order."""
    model = load_model(NODES[node])
    c = (folders[node] / f"{node}_glue.c").read_text()
    got = body(c, "void input_glue(void)")
    n_copies = 2 * len(model.input_relations)
    u = model.controller.inputs.var_name
    assert [ln for ln in got[:n_copies] if ln.startswith(u + ".")] == [
        f"{u}.{r.input_field} = _t_{ln.split('_t_')[1]}" for r, ln in
        zip(model.input_relations, got[1:n_copies:2])]
    want = expected_timed_part(model)
    rest = got[n_copies:]
    assert len(rest) == len(want), "\n".join(rest)
    for line, pattern in zip(rest, want):
        assert re.fullmatch(pattern, line), (line, pattern)


@pytest.mark.parametrize("node", list(NODES))
def test_callbacks_end_with_the_clock_update(folders, node):
    model = load_model(NODES[node])
    c = (folders[node] / f"{node}_glue.c").read_text()
    timed = {t.name for t in model.timed_topics}
    assert timed
    for t in model.subscribed:
        lines = body(c, f"void {t.callback}(struct {t.msg_struct} *msg)")
        clock = ["_t_ullong = ros_now();", f"{t.c_name}_time = _t_ullong;", f"{t.c_name}_new = 1;",
                 f"{t.c_name}_rcvd = 1;"]
        if t.name in timed:
            assert lines[-4:] == clock
            # the copies come first: the leaves the node reads, in leaf order
            read = model.read_leaves(t)
            assert read, t.name
            assert len(lines) == 2 * len(read) + 4
            for k, p in enumerate(read):
                tmp = re.fullmatch(rf"(_t_\w+) = {re.escape(p.c_access('(*msg)'))};", lines[2 * k])
                assert tmp, (lines[2 * k], str(p))
                assert lines[2 * k + 1] == f"{p.c_access(t.msg_var)} = {tmp.group(1)};"
        else:
            assert not set(clock) & set(lines)
    # the globals, after the messages', and ros_now declared
    globs = [f"unsigned long long {t.c_name}_time;\nunsigned char {t.c_name}_new;\nunsigned char {t.c_name}_rcvd;"
             for t in model.timed_topics]
    assert "\n".join(globs) in c
    assert c.index(globs[0]) > max(c.index(f"struct {t.msg_struct} {t.msg_var};") for t in model.subscribed)
    assert re.search(r"^unsigned long long ros_now\(void\);$", c, re.M)


def test_temporaries_are_the_ones_used(folders):
    """No temporary is declared that is not used (gcc -Wall refuses a set
    but unread ``_age``, an unused ``_t_uchar``): flags only, no age."""
    c = (folders["fresh_flags"] / "fresh_flags_glue.c").read_text()
    assert temps(c, "void input_glue(void)") == ["_t_uchar", "_t_float"]
    assert not re.search(r"\b_now\b|\b_age\b", c)
    g = (folders["velocity_guard"] / "velocity_guard_glue.c").read_text()
    assert temps(g, "void input_glue(void)") == ["_now", "_age", "_t_double"]


def test_constant_fallbacks_in_c(folders):
    c = (folders["fresh_constants"] / "fresh_constants_glue.c").read_text()
    for line in ("K_U.B = 1;", "K_U.I8 = -128;", "K_U.U8 = 255;", "K_U.I16 = -32768;", "K_U.U16 = 65535;",
                 "K_U.I32 = (-2147483647 - 1);", "K_U.U32 = 4294967295U;",
                 "K_U.I64 = (-9223372036854775807LL - 1);", "K_U.U64 = 18446744073709551615ULL;",
                 "K_U.F32 = 0x1.99999ap-4f;", "K_U.F64 = -0x0p+0;"):
        assert f"    if ((1000000ULL < _age)) {{\n        {line}\n    }}\n" in c, line
    # the held inputs have no fallback
    assert "K_U.C = " not in c.replace("K_U.C = _t_uchar;", "")


@pytest.mark.parametrize("node", list(NODES))
def test_glue_compiles_as_the_build_compiles_it(folders, node, tmp_path):
    """gcc with the build's flags (-Werror among them), and the ROS
    functions the glue declares are the wrapper header's."""
    d = folders[node]
    model = load_model(NODES[node])
    files = rosgen.render_wrapper(model)
    names = rosgen.wrapper_files(model)
    glue = (d / f"{node}_glue.c").read_text()
    check_glue_externals(glue, files[names.api_header], glue_name=f"{node}_glue.c", header_name=names.api_header)
    r = subprocess.run(["gcc", *rosgen.GLUE_CFLAGS, "-I", str(d), "-c", str(d / f"{node}_glue.c"),
                        "-o", str(tmp_path / "glue.o")], capture_output=True, text=True, check=False)
    assert r.returncode == 0, r.stderr


def test_certificate_freshness_section(folders):
    d = folders["velocity_guard"]
    cert = (d / "velocity_guard.certificate.md").read_text()
    glue = (d / "velocity_guard_glue.c").read_text().splitlines()
    section = cert[cert.index("## Freshness"):cert.index("## Trusted, not proved")]
    assert "### `/teleop/cmd_vel` (timeout 500 ms)" in section and "### `/nav/cmd_vel` (timeout 500 ms)" in section
    assert "| `Guard_U.TVx` (float64) | `/teleop/cmd_vel linear.x` | the fallback 0.0 (bits 0x0000000000000000) |" \
        in section
    assert "| `Guard_U.TAge` (uint32) | derived: `age_ms` | `age_ms` too |" in section
    # every quoted line is the glue's line of that number
    quoted = re.findall(r"^/\* velocity_guard_glue\.c:(\d+) \*/ (.*)$", section, re.M)
    assert len(quoted) > 40
    for n, text in quoted:
        assert glue[int(n) - 1].strip() == text.strip(), (n, text)
    texts = [t.strip() for _, t in quoted]
    for line in ("_now = ros_now();", "teleop_cmd_vel_time = _t_ullong;", "if (nav_cmd_vel_rcvd) {",
                 "Guard_U.NWz = 0x0p+0;", "Guard_U.TAge = (unsigned int)(_age / 1000000ULL);",
                 "teleop_cmd_vel_new = 0;", "nav_cmd_vel_new = 0;"):
        assert line in texts, line
    assert "or its fallback\n  while the topic is stale" in cert


def test_certificate_sections_of_each_feature(folders):
    pol = (folders["fresh_policies"] / "fresh_policies.certificate.md").read_text()
    assert "| `F_U.Wz` (float64) | `/cmd angular.z` | hold: the newest message's field |" in pol
    assert "| `F_U.Vy` (float64) | `/cmd linear.y` | the fallback -1.5 (bits 0xbff8000000000000) |" in pol
    assert "### `/ok` (no timeout)" in pol and "| `F_U.Seen` (bool) | derived: `received` |" in pol
    assert "### `/count` (timeout 86400000 ms)" in pol
    plain = (REPO / "examples" / "landshark" / "landshark_controller.yaml")
    assert "timeout" not in plain.read_text()
    const = (folders["fresh_constants"] / "fresh_constants.certificate.md").read_text()
    assert "| `K_U.B` (bool) | `prims_in b` | the fallback true |" in const
    assert "| `K_U.F32` (float32) | `prims_in f32` | the fallback 0.10000000149011612 (bits 0x3dcccccd) |" in const
    assert "| `K_U.I64` (int64) | `prims_in i64` | the fallback -9223372036854775808 |" in const


def test_certificate_refuses_a_glue_without_a_proved_line(folders):
    """The certificate quotes the printed C for what the proved model
    says; a C text without one of those lines stops it."""
    d = folders["velocity_guard"]
    pm = parse_model_text((d / "velocity_guard.model").read_text())
    glue = (d / "velocity_guard_glue.c").read_text()
    assert _freshness(pm, glue)["topics"]
    for line in ("        Guard_U.TWz = 0x0p+0;\n", "    nav_cmd_vel_new = 0;\n", "    teleop_cmd_vel_rcvd = 1;\n",
                 "        Guard_U.NAge = (unsigned int)(_age / 1000000ULL);\n", "    _now = ros_now();\n"):
        assert line in glue
        with pytest.raises(CertificateError):
            _freshness(pm, glue.replace(line, "", 1))
    # a fallback that reads the other topic's age
    tw = "    if ((500000000ULL < _age)) {\n        Guard_U.TWz = 0x0p+0;\n    }\n"
    moved = glue.replace(tw, "", 1).replace("    nav_cmd_vel_new = 0;\n", tw + "    nav_cmd_vel_new = 0;\n")
    with pytest.raises(CertificateError, match="the age of /teleop/cmd_vel is not computed as proved"):
        _freshness(pm, moved)


@pytest.mark.parametrize("node", list(NODES))
def test_verify_accepts_the_folder(folders, node, capsys):
    assert cli.main(["verify", str(folders[node])]) == 0, capsys.readouterr().err


# ---------------------------------------------------------------------------
# The seam: a per-node .v whose model is not the YAML file's

TELEOP_TIMEOUT = '[("teleop_cmd_vel", 500%Z);\n       ("nav_cmd_vel", 500%Z)]'
TVX_FALLBACK = '[(* TVx when stale: zero *)\n       ("TVx", Vfloat (float64_of_bits 0x0000000000000000%Z));\n       '


TAMPERINGS = [
    # a timeout dropped (the topic holds: no fallback depends on it)
    ("timeout dropped", POLICIES, '("count", 86400000%Z)', None, 2, "timeout count 86400000"),
    ("timeout changed", GUARD, TELEOP_TIMEOUT, TELEOP_TIMEOUT.replace("500", "5000", 1), 2,
     "timeout teleop_cmd_vel"),
    ("fallback dropped", GUARD, TVX_FALLBACK, "[", 2, "fallback TVx"),
    ("fallback changed", POLICIES, "0xBFF8000000000000", "0x3FF8000000000000", 2, "fallback Vy"),
    ("derived changed", POLICIES, 'mkdrel "cmd" Dis_new "New"', 'mkdrel "cmd" Dreceived "New"', 2,
     "derived_input cmd is_new New"),
    ("derived moved", GUARD, 'mkdrel "teleop_cmd_vel" Dage_ms "TAge"', 'mkdrel "nav_cmd_vel" Dage_ms "TAge"', 2,
     "derived_input teleop_cmd_vel age_ms TAge"),
    # a derived input dropped: its input is fed by nothing, Coq refuses
    ("derived dropped", GUARD, '(* /teleop/cmd_vel age_ms -> TAge *)\n       mkdrel "teleop_cmd_vel" Dage_ms "TAge";'
     '\n       ', "", 1, "controller input not fed by any input relation: 'TAge'"),
]


@pytest.mark.parametrize("name, model, old, new, code, needle", TAMPERINGS, ids=[t[0] for t in TAMPERINGS])
def test_tampered_freshness_is_refused(name, model, old, new, code, needle, monkeypatch, capsys, tmp_path):
    require_library()
    original = gen.render_node_file

    def tampered(m, **kw):
        text = original(m, **kw)
        assert text.count(old) == 1, (name, old)
        if new is None:  # drop the item from its list
            text = re.sub(r"\[\s*" + re.escape(old) + r"\s*;\s*", "[", text)
            text = re.sub(r";\s*" + re.escape(old) + r"\s*\]", "]", text)
            text = re.sub(r"\[\s*" + re.escape(old) + r"\s*\]", "[]", text)
            assert old not in text
            return text
        return text.replace(old, new, 1)

    monkeypatch.setattr(gen, "render_node_file", tampered)
    out = tmp_path / "out"
    got = cli.main(["generate", str(model), "-o", str(out), "-q"])
    err = capsys.readouterr().err
    assert got == code, err
    assert not out.exists()
    if code == 2:
        # the node still proves its theorem, about another node: the seam refuses it
        assert "is not the model of the YAML file" in err and needle in err, err
    else:
        assert needle in err, err

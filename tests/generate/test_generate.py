"""``pyrosgen generate`` on LandShark (the paper's Table 1) and on the multi
example: the files written, the golden glue (Figures 8 and 11), the C
compiled strictly, the per-node Coq file re-checked, the AST dump against
the C text."""

from __future__ import annotations

import json
import re
import shutil

import pytest

from pyrosgen.proof.coqdriver import CLOSED
from pyrosgen.generate import generate
from pyrosgen.frontend.validate import load_model
from pyrosgen.ros.wrapper import render_wrapper, wrapper_files
from pyrosgen.proof.sexp import parse_sexp, program_items

from support.generate import (
    GCC_STRICT,
    GOLDEN,
    LANDSHARK,
    MULTI,
    coqc,
    ddc_in_coqproject,
    require_library,
    run,
)

NODES = {"landshark": (LANDSHARK, "landshark_controller"), "multi": (MULTI, "multi_node")}


@pytest.fixture(scope="module")
def generated(tmp_path_factory):
    """Both example nodes generated once: name -> (result, out dir)."""
    require_library()
    out = {}
    for key, (model, _node) in NODES.items():
        d = tmp_path_factory.mktemp(key) / "out"
        lines: list[str] = []
        res = generate(model, d, progress=lines.append)
        out[key] = (res, d, lines)
    return out


def _files(generated, key):
    res, d, _ = generated[key]
    node = NODES[key][1]
    return {
        "v": d / f"{node}.v",
        "h": d / f"{node}_types.h",
        "c": d / f"{node}_glue.c",
        "sexp": d / f"{node}.sexp",
        "model": d / f"{node}.model",
        "cert": d / f"{node}.certificate.md",
        "manifest": d / f"{node}.manifest.json",
        "sums": d / f"{node}.sha256",
    }


def _function(c_text: str, header: str) -> list[str]:
    """The body lines of the C function whose definition starts with ``header``."""
    lines = c_text.splitlines()
    i = lines.index(header)
    assert lines[i + 1] == "{"
    j = lines.index("}", i + 1)
    return [ln.strip() for ln in lines[i + 2 : j]]


# ---------------------------------------------------------------------------
# Files and theorem


@pytest.mark.parametrize("key", list(NODES))
def test_files_written_and_theorem(generated, key):
    res, d, lines = generated[key]
    node = NODES[key][1]
    files = _files(generated, key)
    assert sorted(p.name for p in d.iterdir()) == sorted(p.name for p in files.values())
    assert [p for p, _ in res.files] == [files[k] for k in
                                         ("v", "h", "c", "sexp", "model", "cert", "manifest", "sums")]
    assert all(rewritten for _, rewritten in res.files)
    # the main theorem: T2 when the library has it, else the T4 fallback
    if ddc_in_coqproject():
        assert res.ddc and res.theorem == f"{node}_ddc" and res.theorems == [f"{node}_ddc", f"{node}_ddc_target",
                                                                            f"{node}_wf"]
        # the .v names the target it was generated for (rule 4.17): ROS 1 here
        v = (d / f"{node}.v").read_text()
        assert "Definition target : Environment.target := Environment.Ros1." in v
        assert f"Theorem {node}_ddc_target : DDC.node_ddc_on target model the_program." in v
        assert json.loads((d / f"{node}.manifest.json").read_text())["target"] == "ros1"
    else:
        assert not res.ddc and res.theorem == f"{node}_wf" and res.theorems == [f"{node}_wf"]
    assert res.assumptions == CLOSED
    assert set(res.times) == {"front end", "coqc", "checking", "printing", "total"}
    # progress: five numbered steps
    assert [ln[:5] for ln in lines] == ["[1/5]", "[2/5]", "[3/5]", "[4/5]", "[5/5]"]
    assert res.theorem in lines[1]
    # no work directory left next to the output
    assert not list(d.parent.glob(".pyrosgen-*"))


@pytest.mark.parametrize("key", list(NODES))
def test_v_file(generated, key):
    files = _files(generated, key)
    node = NODES[key][1]
    text = files["v"].read_text()
    first = text.splitlines()[0]
    assert first == f"(* generated from coq/templates/node.v.j2 with input from {NODES[key][0].name} *)"
    assert "Lemma generate_ok : Generator.generate model = OK the_program." in text
    assert "Definition the_program : program := program_of program_result." in text
    assert f"Theorem {node}_wf : Wellformed.wf model = true." in text
    if ddc_in_coqproject():
        assert f"Theorem {node}_ddc : DDC.node_ddc model the_program." in text
        assert f"Proof. exact ({node}_ddc_of_library Loopproof.generate_node_ddc). Qed." in text
        assert f"Proof. exact ({node}_ddc_target_of_library Loopproof.generate_node_ddc). Qed." in text
        assert f"(T2 : forall m p, Generator.generate m = OK p -> DDC.node_ddc m p)" in text
        assert "  T2 model the_program generate_ok." in text
        assert f"Print Assumptions {node}_theorems_local." in text
        assert f"Definition {node}_theorems := (conj {node}_ddc (conj {node}_ddc_target {node}_wf))." in text
        assert (f"Definition {node}_theorems_local := (conj {node}_ddc_of_library "
                f"(conj {node}_ddc_target_of_library {node}_wf_of_library)).") in text
    for word in ("Admitted", "admit", "Axiom", "Parameter", "Conjecture"):
        assert not re.search(rf"\b{word}\b", text), word


@pytest.mark.parametrize("key", list(NODES))
def test_v_file_checks_on_its_own(generated, key, tmp_path):
    """The per-node file written to DIR compiles by itself, its theorems
    closed under the global context."""
    files = _files(generated, key)
    res = generated[key][0]
    v = tmp_path / files["v"].name
    shutil.copy(files["v"], v)
    out = coqc(v).stdout
    assert out.count(CLOSED) == 1  # Print Assumptions of the conjunction of res.theorems


# ---------------------------------------------------------------------------
# The glue C of LandShark (Figures 8 and 11)


def test_landshark_golden(generated):
    c = _files(generated, "landshark")["c"]
    assert c.read_bytes() == (GOLDEN / "landshark_controller_glue.c").read_bytes()


def test_landshark_types_golden(generated):
    h = _files(generated, "landshark")["h"]
    assert h.read_bytes() == (GOLDEN / "landshark_controller_types.h").read_bytes()


def test_landshark_callback_figure_11(generated):
    """Each callback copies the one leaf that the node reads of its
    message (Figure 11's copy), through one temporary, and nothing else:
    the eight other leaves of TwistStamped are not copied."""
    c = _files(generated, "landshark")["c"].read_text()
    for wheel in ("left_wheel", "right_wheel", "gps"):
        body = _function(c, f"void landshark_{wheel}_velocity_callback(struct geometry_msgs_TwistStamped *msg)")
        assert body == [
            "double _t_double;",
            "_t_double = (*msg).twist.linear.x;",
            f"landshark_{wheel}_velocity_msg.twist.linear.x = _t_double;",
        ]


def test_landshark_input_glue_figure_8(generated):
    c = _files(generated, "landshark")["c"].read_text()
    body = _function(c, "void input_glue(void)")
    assert body == [
        "double _t_double;",
        "_t_double = landshark_left_wheel_velocity_msg.twist.linear.x;",
        "Controller_U.In1 = _t_double;",
        "_t_double = landshark_right_wheel_velocity_msg.twist.linear.x;",
        "Controller_U.In2 = _t_double;",
        "_t_double = landshark_gps_velocity_msg.twist.linear.x;",
        "Controller_U.In3 = _t_double;",
    ]
    out = _function(
        c, "void output_glue_landshark_control_base_velocity(struct geometry_msgs_TwistStamped *command)"
    )
    assert out[-2:] == ["_t_double = Controller_Y.Out1;", "(*command).twist.linear.x = _t_double;"]
    # the other leaves are zeroed first
    assert "(*command).twist.angular.z = 0x0p+0;" in out
    assert "(*command).header.seq = 0U;" in out


def test_landshark_loop_and_main(generated):
    c = _files(generated, "landshark")["c"].read_text()
    loop = _function(c, "void loop(void)")
    calls = [ln for ln in loop if ln.endswith(");")]
    assert calls == [
        "_ok = ros_ok();",
        "ros_spinOnce();",
        "input_glue();",
        "Controller_step();",
        "output_glue_landshark_control_base_velocity(&landshark_control_base_velocity_cmd);",
        "ros_publish_landshark_control_base_velocity(&landshark_control_base_velocity_cmd);",
        "ros_rate_sleep();",
    ]
    main = _function(c, "int main(void)")
    assert main[:2] == ["ros_init();", "Controller_initialize();"]
    assert main[-2:] == ["loop();", "return 0;"]


def test_structs_only_in_the_header(generated):
    for key, (_m, node) in NODES.items():
        f = _files(generated, key)
        c, h = f["c"].read_text(), f["h"].read_text()
        assert f'#include "{node}_types.h"' in c.splitlines()
        assert not re.search(r"^struct \w+ \{", c, re.M)
        guard = f"PYROSGEN_{node.upper()}_TYPES_H"
        assert h.splitlines()[2:4] == [f"#ifndef {guard}", f"#define {guard}"]
        assert h.rstrip("\n").splitlines()[-1] == f"#endif /* {guard} */"
        model = load_model(NODES[key][0])
        for m in model.messages:
            assert f"struct {m.c_name} {{" in h
        assert f"struct {model.controller.inputs.struct_name} {{" in h
        # the controller's globals are declared, not defined
        assert f"extern struct {model.controller.inputs.struct_name} {model.controller.inputs.var_name};" in c
        assert f"extern struct {model.controller.outputs.struct_name} {model.controller.outputs.var_name};" in c


def test_multi_glue_shape(generated):
    c = _files(generated, "multi")["c"].read_text()
    body = _function(c, "void input_glue(void)")
    # pose.covariance[35] of the untimed /odom is a direct relation (rule
    # 4.16): its callback copies it into Fusion_U, input_glue does not
    odom = _function(c, "void odom_callback(struct nav_msgs_Odometry *msg)")
    assert odom[odom.index("_t_double = (*msg).pose.covariance[35];") + 1] == "Fusion_U.YawVar = _t_double;"
    assert not any("covariance" in ln or ln.startswith("Fusion_U.YawVar") for ln in body)
    assert "odom_msg.pose.covariance[35] = _t_double;" not in odom
    assert "_t_uchar = safety_estop_msg.engaged;" in body
    assert "_t_float = range_front_msg.range;" in body
    assert "_t_int = safety_estop_msg.hold_time.sec;" in body
    status = _function(c, "void output_glue_fusion_status(struct robot_msgs_FusionStatus *command)")
    assert "(*command).wheels[1].velocity = _t_float;" in status
    assert status.count("_t_uint = Fusion_Y.SeqOut;") == 2
    # two published topics, in order, each glued then published
    loop = _function(c, "void loop(void)")
    calls = [ln for ln in loop if ln.startswith(("output_glue_", "ros_publish_"))]
    assert calls == [
        "output_glue_cmd_vel(&cmd_vel_cmd);",
        "ros_publish_cmd_vel(&cmd_vel_cmd);",
        "output_glue_fusion_status(&fusion_status_cmd);",
        "ros_publish_fusion_status(&fusion_status_cmd);",
    ]


# ---------------------------------------------------------------------------
# Compilation


@pytest.mark.parametrize("key", list(NODES))
def test_glue_compiles_strictly(generated, key, tmp_path):
    f = _files(generated, key)
    run([*GCC_STRICT, "-c", str(f["c"]), "-o", str(tmp_path / "glue.o")])
    # the header twice (include guard), in C and in C++ (the wrapper's view)
    twice = tmp_path / "twice.c"
    twice.write_text(f'#include "{f["h"]}"\n#include "{f["h"]}"\nint main(void) {{ return 0; }}\n')
    run([*GCC_STRICT, "-c", str(twice), "-o", str(tmp_path / "twice.o")])
    run(["g++", "-std=c++11", "-Wall", "-Wextra", "-Werror", "-pedantic", "-fsyntax-only", "-x", "c++", str(f["h"])])


@pytest.mark.parametrize("key", list(NODES))
def test_wrapper_header_includes_the_coq_types(generated, key, tmp_path):
    """The C API header of the C++ wrapper includes the very header Coq
    printed, and compiles with it (as C and as C++)."""
    f = _files(generated, key)
    model = load_model(NODES[key][0])
    assert wrapper_files(model).types_header == f["h"].name
    files = render_wrapper(model)
    api_h = wrapper_files(model).api_header
    (tmp_path / api_h).write_text(files[api_h])
    shutil.copy(f["h"], tmp_path / f["h"].name)
    use = tmp_path / "use.c"
    use.write_text(f'#include "{api_h}"\n#include "{f["h"].name}"\nint main(void) {{ return 0; }}\n')
    run([*GCC_STRICT, "-c", str(use), "-o", str(tmp_path / "use.o")], cwd=tmp_path)
    run(["g++", "-std=c++11", "-Wall", "-Werror", "-fsyntax-only", "-x", "c++", str(use)], cwd=tmp_path)


# ---------------------------------------------------------------------------
# The dump against the C (printer validation, DESIGN.md section 7)


@pytest.mark.parametrize("key", list(NODES))
def test_dump_matches_c(generated, key):
    from pycparser import c_ast, c_parser

    f = _files(generated, key)
    model = load_model(NODES[key][0])
    items = program_items(parse_sexp(f["sexp"].read_text()))
    assert items["externs"] == [model.controller.inputs.var_name, model.controller.outputs.var_name]
    assert items["main"] == "main"
    pre = run(["gcc", "-E", "-P", f"-I{f['c'].parent}", str(f["c"])]).stdout
    ast = c_parser.CParser().parse(pre, filename=str(f["c"]))
    funcdefs, gvars, externs, protos, structs = {}, set(), set(), set(), []
    for ext in ast.ext:
        if isinstance(ext, c_ast.FuncDef):
            funcdefs[ext.decl.name] = ext
        elif isinstance(ext, c_ast.Decl) and isinstance(ext.type, c_ast.FuncDecl):
            protos.add(ext.name)
        elif isinstance(ext, c_ast.Decl) and ext.name is None:
            structs.append(ext.type.name)
        elif isinstance(ext, c_ast.Decl):
            (externs if "extern" in ext.storage else gvars).add(ext.name)
    assert set(funcdefs) == set(items["functions"])
    assert protos == set(items["functions"]) | set(items["externals"])
    assert gvars | externs == set(items["gvars"])
    assert externs == set(items["externs"])
    assert sorted(structs) == sorted(items["structs"])
    assert set(structs) == {m.c_name for m in model.messages} | {
        model.controller.inputs.struct_name,
        model.controller.outputs.struct_name,
    }
    for name, item in items["functions"].items():
        decls = [d.name for d in funcdefs[name].body.block_items or [] if isinstance(d, c_ast.Decl)]
        assert decls == [b[0] for b in item[4][1:]] + [b[0] for b in item[5][1:]], name
        # one C assignment per Sset, Sassign and call with a result
        n_c = sum(1 for _ in _assignments(funcdefs[name].body))
        assert _count_ast_assignments(item[6]) == n_c, name


def _count_ast_assignments(tree) -> int:
    if not isinstance(tree, list) or not tree:
        return 0
    here = tree[0] in ("set", "assign") or (tree[0] == "call" and tree[1] != [])
    return int(here) + sum(_count_ast_assignments(t) for t in tree[1:])


def _assignments(node):
    from pycparser import c_ast

    if isinstance(node, c_ast.Assignment):
        yield node
    for _name, child in node.children():
        yield from _assignments(child)


# --------------------------------------------------------------------------
# The DDC certificate


@pytest.mark.parametrize("key", list(NODES))
def test_certificate_claims_match_the_files(generated, key):
    """Every relation of the model is listed with C lines that really are
    those lines of the glue and really copy the related fields; the digests
    are those of the files; the theorem is the one checked."""
    import hashlib

    res, d, _ = generated[key]
    files = _files(generated, key)
    cert = files["cert"].read_text()
    glue = files["c"].read_text().splitlines()
    model = res.model
    assert f"`{res.theorem}" in cert and "Closed under the global context" in cert
    # each quoted line is the line of the glue it claims to be
    quoted = re.findall(r"^/\* (\S+):(\d+) \*/ (.*)$", cert, re.M)
    assert quoted, "no C lines quoted"
    for fname, n, text in quoted:
        assert fname == files["c"].name
        assert glue[int(n) - 1].strip() == text
    uvar, yvar = model.controller.inputs.var_name, model.controller.outputs.var_name
    for r in model.input_relations:
        head = f"### `{r.topic.name} {r.path}` → `{uvar}.{r.input_field}` ({r.path.prim})"
        assert head in cert
        block = cert.split(head, 1)[1].split("###", 1)[0]
        # a direct relation (rule 4.16) is copied by its callback, from *msg
        src = r.path.c_access("(*msg)" if model.is_direct(r) else r.topic.msg_var)
        assert ("Written by the callback" in block) == model.is_direct(r)
        assert re.search(rf"\*/ (_t_\w+) = {re.escape(src)};\n/\* \S+ \*/ {re.escape(uvar)}\.{r.input_field} = \1;", block)
    for r in model.output_relations:
        head = f"### `{yvar}.{r.output_field}` → `{r.topic.name} {r.path}` ({r.path.prim})"
        assert head in cert
        block = cert.split(head, 1)[1].split("###", 1)[0]
        dst = r.path.c_access("(*command)")
        assert re.search(rf"\*/ (_t_\w+) = {re.escape(yvar)}\.{r.output_field};\n/\* \S+ \*/ {re.escape(dst)} = \1;", block)
    digests = dict(re.findall(r"^\| `([^`]+)` \| `([0-9a-f]{64})` \|$", cert, re.M))
    expected = {p.name: p for p in (files["v"], files["h"], files["c"], files["sexp"], files["model"])}
    assert set(digests) == set(expected)
    for name, path in expected.items():
        assert digests[name] == hashlib.sha256(path.read_bytes()).hexdigest()
    assert hashlib.sha256(model.source.read_bytes()).hexdigest() in cert
    # the digest file is sha256sum's format and agrees with the table
    sums = dict(reversed(line.split("  ", 1)) for line in files["sums"].read_text().splitlines())
    assert sums == digests
    # the proved model as Coq printed it is the one shown: period and topics
    assert f"| period | {model.period_ms} ms |" in cert
    for t in model.topics:
        assert f"| {t.direction} | `{t.name}` (`{t.msg_type}`, queue {t.queue_size}) |" in cert

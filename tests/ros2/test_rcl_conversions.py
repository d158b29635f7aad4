"""The rcl wrapper's conversion of a taken message into the glue's struct
(``to_c_<struct>`` of ``<node>_rcl.c``, pyrosgen/templates/rcl_api.c.j2)
writes every field of the struct: the wrapper does not zero the struct
before converting into it (BENCHMARKS.md section 13), so a field it left
alone would keep the previous message's value.  For each subscription of
four ROS 2 builds (TwistStamped; a LaserScan under policy reject, with its
string and float sequence; a JointState, sequences of strings and of
numbers; a trajectory_msgs/JointTrajectory, a sequence of messages each
with its own sequences, and a sequence of strings), a
C harness includes the node's own ``<node>_rcl.c`` and converts rosidl
messages (every carried leaf set, sequences and strings of lengths 0, 1, N
and N+2) twice: into a zeroed struct (the wrapper before the change) and
into one filled with 0xA5.  Every scalar leaf of the two, as the
Coq-printed ``<node>_types.h`` declares the struct (parsed here, not the
wrapper's own list of fields), is copied into a zeroed struct, and the two
copies must be byte for byte equal (padding bytes are no leaf: gcc 12's
``__builtin_clear_padding`` misses some in arrays of structs, hence the
copies).  A control checks that the comparison sees a leaf to_c did not
write.  The harness is compiled at -O0 (no store merging over padding)."""

from __future__ import annotations

import re
import subprocess

import pytest

from pyrosgen.proof.modeltext import parse_model_text
from pyrosgen.ros.wrapper import GLUE_CFLAGS
from pyrosgen.ros2.build import build_ros2, compile_flags, link_flags
from pyrosgen.ros2.wrapper import _context, parse_qos_text, qos_file_name

from support import ros as rosutil

ROOT = rosutil.ROOT

#: rounds per subscription: the lengths of sequences and strings cycle through 0, 1, N, N + 2
ROUNDS = 8


def _length(cap: int) -> str:
    return f"(s % 4 == 0 ? 0 : s % 4 == 1 ? 1 : s % 4 == 2 ? {cap} : {cap} + 2)"


def _filler(m) -> str:
    """A C function setting every carried leaf of rosidl message ``m`` from a seed."""
    c, r = m["c_name"], m["rosidl"]
    if m["bounded"] == "string":
        return (f"static void fill_{c}({r} *r, unsigned s)\n{{\n"
                f"    char b[{m['capacity']} + 2];\n    size_t n = {_length(m['capacity'])};\n"
                "    for (size_t i = 0; i < n; ++i) b[i] = (char)('a' + (s + i) % 26);\n"
                "    if (!rosidl_runtime_c__String__assignn(r, b, n)) abort();\n}\n")
    if m["bounded"] in ("seq", "seqelem"):
        elem = (f"fill_{m['elem_c']}(&r->data[i], s + (unsigned)i)" if m["bounded"] == "seqelem"
                else "r->data[i] = (__typeof__(r->data[i]))(s + i + 1)")
        return (f"static void fill_{c}({r} *r, unsigned s)\n{{\n    size_t n = {_length(m['capacity'])};\n"
                f"    {r}__fini(r);\n    if (!{r}__init(r, n)) abort();\n"
                f"    for (size_t i = 0; i < n; ++i) {elem};\n}}\n")
    body = []
    for k, f in enumerate(m["fields"]):
        one = (f"fill_{f['c_name']}(&r->{f['name']}{{i}}, s + {k}u)" if f["kind"] == "msg"
               else f"r->{f['name']}{{i}} = (__typeof__(r->{f['name']}{{i}}))(s + {k + 1}u)")
        if f["array_len"] is None:
            body.append(f"    {one.format(i='')};")
        else:
            body.append(f"    for (size_t i = 0; i < {f['array_len']}; ++i) {one.format(i='[i]')};")
    return f"static void fill_{c}({r} *r, unsigned s)\n{{\n" + "\n".join(body) + "\n}\n"


_STRUCT = re.compile(r"^struct (\w+) \{\n(.*?)^\};", re.M | re.S)
_MEMBER = re.compile(r"^    (struct \w+|[a-zA-Z_][\w ]*?) (\w+)((?:\[\d+\])*);$")


def leaf_copies(types_h: str) -> str:
    """For each struct of a Coq-printed types header, a C function copying
    every scalar leaf (through nested structs and arrays) of one struct into
    another, member by member."""
    out = []
    for name, body in _STRUCT.findall(types_h):
        lines = [f"static void leaves_{name}(struct {name} *d, const struct {name} *s)", "{"]
        for decl in body.splitlines():
            m = _MEMBER.match(decl)
            assert m, f"struct {name}: a member line not understood: {decl!r}"
            typ, field, dims = m.group(1), m.group(2), [int(n) for n in re.findall(r"\d+", m.group(3))]
            idx = "".join(f"[i{k}]" for k in range(len(dims)))
            loops = "".join(f"for (size_t i{k} = 0; i{k} < {n}; ++i{k}) " for k, n in enumerate(dims))
            copy = (f"leaves_{typ.split()[1]}(&d->{field}{idx}, &s->{field}{idx});" if typ.startswith("struct ")
                    else f"d->{field}{idx} = s->{field}{idx};")
            lines.append(f"    {loops}{copy}")
        out.append("\n".join(lines + ["}", ""]))
    assert out, "no struct in the types header"
    return "\n".join(out)


def harness(res) -> str:
    """The C program checking every subscription's to_c of build ``res``."""
    proved = parse_model_text(res.generated.proved_model)
    qos = parse_qos_text((res.out_dir / qos_file_name(res.model.name)).read_text(), proved)
    ctx = _context(res.model, proved, qos)
    protos = "".join(f"static void fill_{m['c_name']}({m['rosidl']} *r, unsigned s);\n" for m in ctx["messages"])
    fills = "\n".join(_filler(m) for m in ctx["messages"])
    checks = []
    for t in ctx["subs"]:
        s, r = t["c_struct"], t["rosidl"]
        checks.append(f"""    {{
        static {r} m;
        static struct {s} a, b, la, lb;
        memset(&m, 0, sizeof m);
        if (!{r}__init(&m)) abort();
        for (unsigned s = 0; s < {ROUNDS}; ++s) {{
            fill_{s}(&m, s);
            memset(&a, 0, sizeof a);
            to_c_{s}(&m, &a);
            memset(&b, 0xA5, sizeof b);
            to_c_{s}(&m, &b);
            memset(&la, 0, sizeof la);
            memset(&lb, 0, sizeof lb);
            leaves_{s}(&la, &a);
            leaves_{s}(&lb, &b);
            differ("{t['name']}", s, (const unsigned char *)&la, (const unsigned char *)&lb, sizeof la);
            checked++;
        }}
        memset(&b, 0xA5, sizeof b);
        memset(&lb, 0, sizeof lb);
        leaves_{s}(&lb, &b);
        if (memcmp(&la, &lb, sizeof la) == 0) {{ printf("control: {t['name']}: no byte told apart\\n"); bad = 1; }}
        {r}__fini(&m);
    }}""")
    copies = leaf_copies((res.out_dir / f"{res.model.name}_types.h").read_text())
    return (f'#include "{res.model.name}_rcl.c"\n\nstatic int bad = 0, checked = 0;\n\n' + copies + "\n"
            + 
            "static void differ(const char *topic, unsigned s, const unsigned char *a, const unsigned char *b, "
            "size_t n)\n{\n    for (size_t i = 0; i < n; ++i)\n        if (a[i] != b[i]) {\n"
            '            printf("%s round %u: byte %zu of the struct, a leaf, not written by to_c\\n", topic, s, i);\n'
            "            bad = 1;\n            return;\n        }\n}\n\n"
            + protos + "\n" + fills + "\nint main(void)\n{\n" + "\n".join(checks)
            + '\n    printf("checked %d\\n", checked);\n    return bad;\n}\n')


#: a sequence of messages holding sequences and a duration, and a sequence of strings
TRAJECTORY = """\
node: {name: traj, period_ms: 20}
controller:
  name: Echo
  inputs:
    name: Echo_U
    fields: {NP: uint32, P0: float64, N0: uint32, T1: int32}
  outputs:
    name: Echo_Y
    fields: {X: float64, Y: float64, Z: float64}
  blocks: [{name: unused, block: Constant, type: bool, value: false}]   # a diagram has at least one block
  outports: {X: P0, Y: P0, Z: P0}
topics:
  - {name: /trajectory, direction: subscribe, type: trajectory_msgs/JointTrajectory, queue_size: 2,
     max_length: {points: 3, "points[].positions": 4, "points[].velocities": 2, joint_names: 2,
                  "joint_names[]": 5, header.frame_id: 6}}
  - {name: /echo, direction: publish, type: geometry_msgs/Point, queue_size: 1}
relations:
  inputs:
    - {topic: /trajectory, field: points, derived: length, input: NP}
    - {topic: /trajectory, field: "points[0].positions[0]", input: P0}
    - {topic: /trajectory, field: "joint_names[0]", derived: length, input: N0}
    - {topic: /trajectory, field: "points[1].time_from_start.sec", input: T1}
  outputs:
    - {output: X, topic: /echo, field: x}
    - {output: Y, topic: /echo, field: y}
    - {output: Z, topic: /echo, field: z}
"""


def _trajectory(tmp_path):
    out = tmp_path / "traj.yaml"
    out.write_text(TRAJECTORY)
    return out


CASES = {
    "landshark": lambda tmp: (ROOT / "bench" / "models" / "landshark_1ms.yaml",
                              ROOT / "tests" / "ros" / "controllers" / "landshark_echo", 3),
    "scan_reject": lambda tmp: (ROOT / "tests" / "ros" / "models" / "scan_reject.yaml", None, 1),
    "arm_named": lambda tmp: (ROOT / "examples" / "arm_named" / "arm_named.yaml",
                              ROOT / "examples" / "arm_named" / "controller", 2),
    "trajectory": lambda tmp: (_trajectory(tmp), None, 1),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_to_c_writes_every_leaf_of_the_struct(case, ros2_install, ros2_nodes, tmp_path):
    model, controller, subs = CASES[case](tmp_path)
    res = build_ros2(model, controller, ros2_nodes / f"conv_{case}", install=ros2_install)
    src = tmp_path / "harness.c"
    src.write_text(harness(res))
    exe = tmp_path / "harness"
    cflags = [f for f in GLUE_CFLAGS if f not in ("-Werror", "-pedantic", "-O2")] + ["-O0"]
    cc = subprocess.run(["gcc", *cflags, "-I", str(res.out_dir), *compile_flags(ros2_install), str(src), "-o",
                         str(exe), *link_flags(ros2_install, res.model), "-lm"], capture_output=True, text=True)
    assert cc.returncode == 0, cc.stderr[-3000:]
    run = subprocess.run([str(exe)], capture_output=True, text=True, timeout=60)
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-2000:]
    assert run.stdout.strip() == f"checked {subs * ROUNDS}"

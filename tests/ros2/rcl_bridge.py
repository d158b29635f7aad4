"""The C side of the differential tests (pyrosgen/verify/difftest.py) with
the rcl wrapper's own conversions in place of the harness's C clamp.

The ROS 1 harness (:func:`pyrosgen.verify.difftest.harness_source`) decodes
each scheduled message into the glue's struct, whose bounded sequences and
strings hold the *real* length in ``len`` and the first ``N`` elements in
``data``, and converts them with a C clamp that does what the wrapper
does.  Here that conversion is the generated ``<node>_rcl.c``'s, compiled
into the harness (its API functions renamed away, so that the harness's
fake API stays the one the glue calls):

- received: the struct is turned into the rosidl message that rmw would
  deliver (:func:`raw_functions`: each sequence and string of its real
  length, capped at ``N + 8`` elements, which keeps ``size > N`` exactly
  when ``len > N``; the first ``N`` elements the schedule's, the others a
  non-zero filler the conversion must not let through), a message holding a
  sequence or string of policy reject longer than its maximum is not
  delivered (the wrapper's own test on the rosidl message,
  ``accept_<topic>``), and the others are converted by the wrapper's
  ``to_c_<struct>`` into a zeroed struct, as its take does;
- published: the glue's struct goes through the wrapper's
  ``from_c_<struct>`` (what ``rcl_publish`` gets) and back through
  ``to_c_<struct>`` (faithful below the maximum), and is printed as the
  harness prints a message on the wire.

So the Coq interpreter's trace (``Environment.clamp``, ``accepted``)
and this one must agree byte for byte."""

from __future__ import annotations

import re
from pathlib import Path

from pyrosgen.verify.difftest import harness_source

FILLER = 0xA5   # bytes past the first N elements: never what the model delivers


def _raw_message(m) -> list[str]:
    c, r = m.c_name, m.rosidl
    head = f"static inline void raw_{c}(const struct {c} *c, {r} *r)\n{{"
    if m.bounded in ("string", "seq", "seqelem"):
        cap = m.capacity
        lines = [head, f"    const size_t n = c->len <= {cap + 8}u ? c->len : {cap + 8}u;",
                 f"    const size_t k = n < {cap}u ? n : {cap}u;"]
        if m.bounded == "string":
            lines += [f"    char buf[{cap + 8}];", f"    memset(buf, {FILLER:#x}, sizeof buf);",
                      "    for (size_t i = 0; i < k; ++i) buf[i] = (char)c->data[i];",
                      "    if (!rosidl_runtime_c__String__assignn(r, buf, n)) abort();"]
        else:
            lines += [f"    {r}__fini(r);", f"    if (!{r}__init(r, n)) abort();"]
            if m.bounded == "seq":
                lines += [f"    if (n > 0) memset(r->data, {FILLER:#x}, n * sizeof r->data[0]);",
                          "    for (size_t i = 0; i < k; ++i) r->data[i] = c->data[i];"]
            else:
                lines += [f"    for (size_t i = 0; i < k; ++i) raw_{m.elem_c}(&c->data[i], &r->data[i]);"]
        return lines + ["}", ""]
    lines = [head]
    for f in m.fields:
        src, dst = f"c->{f.name}", f"r->{f.name}"
        one = (lambda s, d: f"{d} = {s};") if f.kind == "prim" else \
            (lambda s, d, cn=f.c_name: f"raw_{cn}(&{s}, &{d});")
        if f.array_len is not None:
            lines.append(f"    for (size_t i = 0; i < {f.array_len}; ++i) {one(src + '[i]', dst + '[i]')}")
        else:
            lines.append(f"    {one(src, dst)}")
    if not m.fields:
        lines += ["    (void)c;", "    (void)r;"]
    return lines + ["}", ""]


def raw_functions(messages) -> str:
    """``raw_<struct>``: a struct whose bounded members hold their real
    length, as the rosidl message rmw would deliver (see the module)."""
    out: list[str] = []
    for m in messages:
        out += _raw_message(m)
    return "\n".join(out)


_API = re.compile(r"^(?:void|int|unsigned (?:long long|int)) (ros_\w+)\(", re.M)


def bridge_source(ctx: dict, api_header: str, rcl_source: str) -> str:
    """The wrapper compiled in (API renamed ``rclw_*``), ``raw_*`` and, per
    subscribed and published struct, ``rclw_deliver_<struct>`` and
    ``rclw_wire_<struct>``.  ``ctx``: :func:`pyrosgen.ros2.wrapper._context`."""
    api = _API.findall(api_header)
    lines = ["#define _POSIX_C_SOURCE 200809L", "#include <stdlib.h>", "#include <string.h>",
             *[f"#define {n} rclw_{n}" for n in api], "#define fail rclw_fail",
             f'#include "{rcl_source}"', "#undef fail", *[f"#undef {n}" for n in api], "",
             raw_functions(ctx["messages"])]
    rosidl = {t["c_struct"]: t["rosidl"] for t in [*ctx["subs"], *ctx["pubs"]]}
    for t in ctx["subs"]:
        st, r = t["c_struct"], t["rosidl"]
        lines += [f"static int rclw_deliver_{t['c_name']}(struct {st} *msg)", "{",
                  f"    static {r} r;", "    static int up = 0;",
                  f"    if (!up) {{ memset(&r, 0, sizeof r); if (!{r}__init(&r)) abort(); up = 1; }}",
                  f"    raw_{st}(msg, &r);",
                  *([f"    if (!accept_{t['c_name']}(&r)) return 0;   /* the wrapper's own reject test */"]
                    if t["rejects"] else []),
                  "    memset(msg, 0, sizeof *msg);", f"    to_c_{st}(&r, msg);", "    return 1;", "}", ""]
    for st in sorted({t["c_struct"] for t in ctx["pubs"]}):
        r = rosidl[st]
        lines += [f"static void rclw_wire_{st}(const struct {st} *m, struct {st} *back)", "{",
                  f"    static {r} r;", "    static int up = 0;",
                  f"    if (!up) {{ memset(&r, 0, sizeof r); if (!{r}__init(&r)) abort(); up = 1; }}",
                  f"    from_c_{st}(m, &r);", "    memset(back, 0, sizeof *back);", f"    to_c_{st}(&r, back);",
                  "}", ""]
    return "\n".join(lines)


def rcl_harness_source(sexp_text: str, types_header: str, ctx: dict, api_header: str, rcl_source: str) -> str:
    """The ROS 1 harness with the wrapper's conversions (see the module);
    every replacement is checked to apply."""
    text = harness_source(sexp_text, types_header, "the AST dump")
    for t in ctx["subs"]:
        fn, st = f"ros_subscribe_{t['c_name']}", t["c_struct"]
        pat = re.compile(rf"(static void deliver_{fn}\(const struct message \*m\)\n\{{\n.*?    fill_{st}\(&msg\);\n)"
                         rf"(.*?)(    callback_{fn}\(&msg\);\n)", re.S)
        text, n = pat.subn(lambda mo, c=t["c_name"]: mo.group(1) + f"    if (!rclw_deliver_{c}(&msg))\n"
                           "        return;   /* the wrapper's reject test */\n" + mo.group(3), text)
        assert n == 1, fn
    for t in ctx["pubs"]:
        st, fn = t["c_struct"], f"ros_publish_{t['c_name']}"
        old = f'void {fn}(struct {st} *m)\n{{\n    require_advertised("{t["name"]}");\n' \
              f'    printf("publish {t["name"]}\\n");\n    print_{st}(m, "m");\n'
        new = old.replace(f'    print_{st}(m, "m");\n', f"    {{\n        struct {st} back;\n"
                          f"        rclw_wire_{st}(m, &back);\n        print_{st}(&back, \"m\");\n    }}\n")
        assert text.count(old) == 1, fn
        text = text.replace(old, new)
    # the harness's C clamps stay defined, called by nobody
    text = text.replace("static void clamp_", "static inline void clamp_")
    delivers = re.findall(r"static void deliver_\w+\(const struct message \*m\)\n\{\n.*?\n\}\n", text, re.S)
    assert len(delivers) == len(ctx["subs"]) and not any("clamp_" in d for d in delivers), "a C clamp is still called"
    return bridge_source(ctx, api_header, rcl_source) + "\n" + text


def build_rcl_harness(out: Path, node: str, ctx: dict, work: Path, cflags: list[str], lflags: list[str],
                      *, sanitize: bool, run_tool) -> Path:
    """Compile the glue with :func:`rcl_harness_source`; the executable."""
    from pyrosgen.verify.difftest import GCC_STRICT, SANITIZE

    src = work / f"{node}_difftest_rcl{'_san' if sanitize else ''}.c"
    src.write_text(rcl_harness_source((out / f"{node}.sexp").read_text(), f"{node}_types.h", ctx,
                                      (out / f"{node}_ros.h").read_text(), f"{node}_rcl.c"), encoding="ascii")
    exe = work / f"{node}_rcl{'_san' if sanitize else ''}"
    flags = [*GCC_STRICT, "-O1" if sanitize else "-O2", *(SANITIZE if sanitize else ())]
    run_tool(["gcc", *flags, "-I", str(out), *cflags, str(out / f"{node}_glue.c"), str(src), "-o", str(exe),
              *lflags, "-lm"], work, "gcc (differential-test harness over the rcl wrapper)")
    return exe

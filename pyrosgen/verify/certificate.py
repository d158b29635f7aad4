"""The DDC certificate of a node and its machine-readable manifest.

``pyrosgen generate`` (and ``build``) write three files next to the glue:

- ``<node>.certificate.md``: for an auditor, what was proved and how to
  re-check it.  It is rendered from *proved data only*: the model Coq
  printed from the model term its theorem is about (``<node>.model``, read
  back with :func:`pyrosgen.proof.modeltext.parse_model_text`) and the C
  Coq printed (validated against the AST dump); never from the front end's
  model.  It names the theorems and their printed assumptions, the Coq
  library that checked them (a digest of its sources and the pyrosgen
  version, since the ``.v`` recomputes ``generate model`` against that
  library), each relation with the C lines that implement it, the trusted
  parts and how each is checked, the tools, and the SHA-256 of every file
  that matters (after ``build``: the wrapper, the layout check, the
  controller sources, the catkin files and the binary too);
- ``<node>.manifest.json``: the same facts for ``pyrosgen verify``;
- ``<node>.sha256``: the digests in ``sha256sum`` format, so that
  ``sha256sum -c <node>.sha256`` runs as written in the output folder.

The files are per node (two nodes can share an output folder) and
deterministic (no dates, no timings): regenerating an unchanged node leaves
them untouched.  Names that came from the user (the model file's name) are
shown through :func:`md_code`, never raw.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import re
import shutil
import struct
import subprocess
from dataclasses import asdict, dataclass, field
from pathlib import Path

from pyrosgen.errors import DetailedFailure, UserError
from pyrosgen.proof.modeltext import ProvedModel, parse_model_text
from pyrosgen.render import render, source_label

__all__ = [
    "MANIFEST_FORMAT", "ProofRecord", "certificate_files", "sha256_file", "tool_versions",
    "md_code", "render_certificate", "write_certificate", "read_manifest", "CertificateError",
    "ManifestError", "MANIFEST_MAX_BYTES",
]

#: Version of the manifest's format.
MANIFEST_FORMAT = 1


class CertificateError(DetailedFailure):
    """The printed C does not contain what the proved model says it should
    (a relation's copy is missing): pyrosgen's own chain is broken."""


def certificate_files(node: str) -> tuple[str, str, str]:
    """The certificate, manifest and digest file names of ``node``."""
    return f"{node}.certificate.md", f"{node}.manifest.json", f"{node}.sha256"


@dataclass
class ProofRecord:
    """What was checked about a node, gathered by :mod:`pyrosgen.generate`
    from the proof run (nothing here comes from the front end's model but
    the model file's own name and digest)."""

    node: str
    model_file: str          #: the proved model text's file name (``<node>.model``)
    node_v: str
    types_h: str
    glue_c: str
    sexp: str
    theorem: str
    theorems: list[str]
    ddc: bool
    assumptions: str         #: what ``Print Assumptions`` printed for the conjunction of the theorems
    library_sha256: str      #: :meth:`pyrosgen.proof.coqdriver.CoqDriver.library_digest`
    pyrosgen_version: str
    source_name: str         #: the YAML file's name (user input: shown escaped)
    source_sha256: str
    wp: dict | None = None   #: proved, total, prover, contracts (file name)
    tools: list[tuple[str, str]] = field(default_factory=list)
    #: when the controller is a block diagram: ``c`` and ``sexp`` (file
    #: names of its printed C and dump), ``wf``, ``e2e`` and ``linked`` (theorem names)
    controller: dict | None = None
    #: after ``build``: ``package``, what the catkin files are rendered from
    #: besides the proved model (:func:`pyrosgen.ros.wrapper.package_record`),
    #: and ``commands``, the argv of every compiler call (paths relative to
    #: the output folder)
    build: dict | None = None
    #: the target the node was generated for (rule 4.17): ``ros1`` or ``ros2``
    target: str = "ros1"


def sha256_file(path: Path) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for chunk in iter(lambda: f.read(1 << 16), b""):
            h.update(chunk)
    return h.hexdigest()


def tool_version(argv: list[str]) -> str:
    """The first line a tool prints about its version, or ``not found``."""
    if shutil.which(argv[0]) is None:
        return "not found"
    try:
        r = subprocess.run(argv, capture_output=True, text=True, timeout=30, check=False)
    except (OSError, subprocess.TimeoutExpired):
        return "not runnable"
    text = (r.stdout or r.stderr).strip().splitlines()
    return text[0].strip() if text else "unknown"


def tool_versions(wp: bool = False) -> list[tuple[str, str]]:
    out = [
        ("coqc", tool_version(["coqc", "--version"]).replace("The Coq Proof Assistant, ", "")),
        ("ocamlfind ocamlopt", tool_version(["ocamlfind", "ocamlopt", "-version"])),
        ("gcc", tool_version(["gcc", "--version"])),
    ]
    if wp:
        out.append(("frama-c", tool_version(["frama-c", "-version"])))
    return out


_PLAIN = re.compile(r"[A-Za-z0-9._+/\\-]+(?: [A-Za-z0-9._+/\\-]+)*")


def md_code(text: str) -> str:
    """``text`` as inline Markdown code: as is when it is made of plain
    characters, otherwise as a JSON string literal with every character
    outside printable ASCII, the backtick, the bar, ``<``, ``>`` and ``&``
    escaped (a file
    name with a newline, a backtick or ``|`` cannot leave its table cell
    or code span)."""
    if _PLAIN.fullmatch(text):
        return f"`{text}`"
    lit = json.dumps(text, ensure_ascii=True)
    for ch in "`|<>&":
        lit = lit.replace(ch, f"\\u{ord(ch):04x}")
    return f"`{lit}`"


def _function_spans(c_text: str) -> dict[str, tuple[int, int]]:
    """Line spans (1-based, inclusive) of the function definitions in the
    printed C: a line ``<type> name(...)`` followed by ``{`` ... ``}``."""
    lines = c_text.splitlines()
    spans: dict[str, tuple[int, int]] = {}
    head = re.compile(r"^[A-Za-z_][A-Za-z0-9_ ]*?\b([A-Za-z_][A-Za-z0-9_]*)\(.*\)$")
    i = 0
    while i < len(lines):
        m = head.match(lines[i])
        if m and i + 1 < len(lines) and lines[i + 1] == "{":
            j = i + 2
            while j < len(lines) and lines[j] != "}":
                j += 1
            spans[m.group(1)] = (i + 1, j + 1)
            i = j
        i += 1
    return spans


def _span(spans: dict[str, tuple[int, int]], fn: str) -> tuple[int, int]:
    try:
        return spans[fn]
    except KeyError:
        raise CertificateError(f"certificate: the printed C has no function {fn}") from None


class _Copies(list):
    """The lines of a printed C text, with the line numbers of its copies
    ``dst = _t_...;`` (``dst = (int)_t_uint;``: a ROS 2 stamp's seconds)
    indexed by ``dst`` (built once: a node with a
    controller array of 8,192 elements has 16,384 relations to look up)."""

    def __init__(self, lines: list[str]):
        super().__init__(lines)
        self.by_dst: dict[str, list[int]] = {}
        for n, line in enumerate(lines, 1):
            text = line.strip()
            k = text.find(" = _t_")
            if k < 0:
                k = text.find(" = (int)_t_")  # a ROS 2 stamp's seconds (rule 4.13)
            if k > 0:
                self.by_dst.setdefault(text[:k], []).append(n)


def _copy_lines(lines: list[str], span: tuple[int, int], dst: str) -> list[tuple[int, str]]:
    """The two lines of the relation's copy into ``dst`` inside ``span``:
    ``_t = src;`` then ``dst = _t;`` (the last such assignment: an output
    glue first zeroes every field, then copies the related ones)."""
    first, last = span
    if isinstance(lines, _Copies):
        ns = [n for n in lines.by_dst.get(dst, ()) if first < n <= last]
        if ns:
            n = ns[-1]
            return [(n - 1, lines[n - 2].strip()), (n, lines[n - 1].strip())]
    else:
        for n in range(last, first, -1):
            text = lines[n - 1].strip()
            if text.startswith((dst + " = _t_", dst + " = (int)_t_")):
                prev = lines[n - 2].strip()
                return [(n - 1, prev), (n, text)]
    raise CertificateError(f"certificate: no copy into {dst} in lines {first}-{last}")


def _stamps(pm: ProvedModel, c_text: str) -> list[dict]:
    """The rows of the stamps section (rule 4.13): each stamped topic with
    the four lines of its output glue that write the time."""
    lines = c_text.splitlines()
    spans = _function_spans(c_text)
    out = []
    sources = {c: (src, p) for c, src, p in pm.stamp_from}
    # ROS 1's time has nsec; ROS 2's builtin_interfaces/Time (no ros_time in the model), nanosec
    nsec = "nsec" if "ros_time" in pm.messages else "nanosec"
    for topic_c, path in pm.stamps:
        t = pm.topic(topic_c)
        span = _span(spans, t.output_glue)
        src = sources.get(topic_c)
        out.append({"topic": t.name, "path": path, "function": t.output_glue, "nsec": nsec,
                    "time": "time" if nsec == "nsec" else "builtin_interfaces/Time",
                    "source": pm.topic(src[0]).name if src else None, "source_path": src[1] if src else None,
                    "lines": (_copy_lines(lines, span, f"(*command).{path}.sec")
                              + _copy_lines(lines, span, f"(*command).{path}.{nsec}"))})
    return out


_CAST = re.compile(r"^\((?:unsigned |signed )?(?:char|short|int|long long|long)\)\s*")


def _int_constant(text: str) -> int | None:
    """The value of the integer constant ``text`` as the printer writes
    it (``9U``, ``98``, an optional cast), else ``None``."""
    t = text.strip()
    while t.startswith("(") and t.endswith(")") and not _CAST.match(t):
        t = t[1:-1].strip()
    t = _CAST.sub("", t)
    m = re.fullmatch(r"(0|[1-9][0-9]*)[uU]?[lL]{0,2}", t)
    return int(m.group(1)) if m else None


def _string_field_capacity(pm: ProvedModel, struct: str, path: str) -> int:
    """The capacity of the string field at ``path`` of message ``struct``
    in the proved model (its ``ros_string<N>`` struct: ``len``,
    ``truncated``, ``data`` of ``N`` bytes)."""
    cur = struct
    for name, index in re.findall(r"([A-Za-z_][A-Za-z0-9_]*)((?:\[[0-9]+\])?)", path):
        ftype = dict(pm.messages.get(cur, [])).get(name)
        m = re.fullmatch(r"(?:array [0-9]+ )?msg (\w+)", ftype or "")
        if m is None or (bool(index) != ftype.startswith("array ")):
            raise CertificateError(f"certificate: {path} is not a string field of struct {struct} in the proved model")
        cur = m.group(1)
    fields = pm.messages.get(cur, [])
    m = re.fullmatch(r"array ([0-9]+) uint8", dict(fields).get("data", ""))
    if [f for f, _ in fields] != ["len", "truncated", "data"] or m is None:
        raise CertificateError(f"certificate: {path} of struct {struct} is not a carried string in the proved model")
    return int(m.group(1))


def _strings(pm: ProvedModel, c_text: str) -> list[dict]:
    """The rows of the strings section (rule 4.14): each constant string
    with the lines of its topic's output glue that store it, its length
    and each of its bytes; the final value of every leaf of the string
    (the last store into it in the output glue, which first zeroes every
    leaf) must be the constant's, ``truncated`` and the bytes past the
    length zero, or the printed C is not what the proved model says (a
    :class:`CertificateError`)."""
    lines = c_text.splitlines()
    spans = _function_spans(c_text)
    out = []
    for topic_c, path, data in pm.strings:
        t = pm.topic(topic_c)
        first, last = _span(spans, t.output_glue)
        n = _string_field_capacity(pm, t.struct, path)
        base = f"(*command).{path}"
        stores: dict[str, tuple[int, int]] = {}  # leaf -> (line, value) of its last store
        for k in range(first, last + 1):
            text = lines[k - 1].strip()
            if text.startswith(base + ".") and " = " in text and text.endswith(";"):
                leaf, rhs = text[:-1].split(" = ", 1)
                value = _int_constant(rhs)
                if value is None:
                    raise CertificateError(f"certificate: {t.output_glue} stores {rhs!r} into {leaf}, not a constant",
                                           [f"  line {k} of the printed C"])
                stores[leaf] = (k, value)
        want = {f"{base}.len": len(data), f"{base}.truncated": 0}
        want.update({f"{base}.data[{i}]": (data[i] if i < len(data) else 0) for i in range(n)})
        wrong = [f"  {leaf}: {'never stored' if leaf not in stores else f'ends as {stores[leaf][1]} (line {stores[leaf][0]})'}"
                 f", the constant needs {v}" for leaf, v in want.items() if stores.get(leaf, (0, None))[1] != v]
        extra = sorted(set(stores) - set(want))
        if wrong or extra:
            raise CertificateError(f"certificate: {t.output_glue} does not leave {t.name} {path} as the proved "
                                   "constant", wrong + [f"  {leaf}: not a leaf of the string" for leaf in extra])
        numbered = [stores[f"{base}.len"]] + [stores[f"{base}.data[{i}]"] for i in range(len(data))]
        if any(a >= b for (a, _), (b, _) in zip(numbered, numbered[1:])):
            raise CertificateError(f"certificate: {t.output_glue} does not store {t.name} {path} in order")
        zero_lines = sorted(k for leaf, (k, _) in stores.items()
                            if leaf == f"{base}.truncated" or leaf.startswith(f"{base}.data[")
                            and int(leaf[len(base) + 6:-1]) >= len(data))
        out.append({
            "topic": t.name, "path": path, "function": t.output_glue, "length": len(data), "capacity": n,
            "text": data.decode("utf-8", "replace"), "bytes": ",".join(str(b) for b in data) or "-",
            "lines": _indented(lines, [(k, "") for k, _ in numbered]),
            "zeroed": (zero_lines[0], zero_lines[-1]) if zero_lines else None,
        })
    return out


def _block(lines: list[str], start: int) -> list[tuple[int, str]]:
    """The statement starting at line ``start`` (1-based) through the line
    that closes its braces (an ``if`` with its ``else``), numbered."""
    out, depth, n = [], 0, start
    while n <= len(lines):
        text = lines[n - 1].strip()
        out.append((n, text))
        depth += text.count("{") - text.count("}")
        if depth <= 0:
            return out
        n += 1
    raise CertificateError(f"certificate: unbalanced braces from line {start}")


def _value_text(prim: str, val: str) -> str:
    """A fallback as the proved model prints it (``DiagramText.val_text``:
    decimal integers, the bits of a float), for a reader."""
    if prim in ("float32", "float64") and val.startswith("0x"):
        fmt, ifmt = ("<f", "<I") if prim == "float32" else ("<d", "<Q")
        x = struct.unpack(fmt, struct.pack(ifmt, int(val, 16)))[0]
        return f"{x!r} (bits {val})"
    if prim == "bool":
        return {"0": "false", "1": "true"}.get(val, val)
    return val


def _indented(lines: list[str], numbered: list[tuple[int, str]]) -> list[tuple[int, str]]:
    """The numbered lines as printed, less the function body's indentation."""
    return [(n, lines[n - 1][4:] if lines[n - 1].startswith("    ") else lines[n - 1]) for n, _ in numbered]


#: The largest ``unsigned long long``: ``_age`` of a topic with no message yet.
_NO_AGE = "18446744073709551615ULL"


def _freshness(pm: ProvedModel, c_text: str) -> dict:
    """The freshness section (rule 4.12), empty without timed topics:
    ``now``, the line of ``input_glue`` that reads the cycle's time (none
    when no fallback or ``age_ms`` reads an age), and ``topics``, each timed topic
    (a timeout or a derived input), in topic order, with its timeout, its
    inputs' fallbacks (or ``hold``), its derived inputs and the C lines
    that implement them: the clock update at the end of its callback, its
    fallbacks and derived inputs in ``input_glue`` (a fallback or an
    ``age_ms`` first computes its topic's age into ``_age``), and the
    reset of its ``_new`` flag.  A line the proved model calls for and the
    printed C lacks is a :class:`CertificateError`."""
    lines = c_text.splitlines()
    spans = _function_spans(c_text)
    timeouts = dict(pm.timeouts)
    fallbacks = dict(pm.fallbacks)
    derived_topics = {c for c, _, _ in pm.derived_inputs}
    timed = [t for t in pm.topics if t.c_name in timeouts or t.c_name in derived_topics]
    if not timed:
        return {}
    first, last = _span(spans, "input_glue")
    glue = [(n, lines[n - 1].strip()) for n in range(first, last + 1)]
    u = pm.inputs_var

    def find(text: str, lo: int = first, hi: int = last, what: str = "") -> int:
        for n, t in glue:
            if lo <= n <= hi and t == text:
                return n
        raise CertificateError(f"certificate: input_glue has no line {text!r}" + (f" ({what})" if what else ""),
                               [f"  lines {lo}-{hi} of the printed C"])

    def age_before(c: str, end: int, name: str) -> list[tuple[int, str]]:
        """The age computation of topic ``c`` that ends at line ``end``
        (each fallback and ``age_ms`` computes its topic's age just before
        it reads ``_age``)."""
        for a in range(end, first - 1, -1):
            if lines[a - 1].strip() == f"if ({c}_rcvd) {{":
                block = _block(lines, a)
                if block[-1][0] == end and block[-2][1] == f"_age = {_NO_AGE};":
                    return block
                break
        raise CertificateError(f"certificate: the age of {name} is not computed as proved before line {end + 1}")

    age_starts: list[int] = []
    out = []
    for t in timed:
        c = t.c_name
        cb = _span(spans, t.callback)
        n_time = next((n for n in range(cb[0], cb[1] + 1) if lines[n - 1].strip() == f"{c}_time = _t_ullong;"),
                      None)
        clock = [(n, lines[n - 1].strip()) for n in range(n_time - 1, n_time + 3)] if n_time else []
        if [x for _, x in clock] != ["_t_ullong = ros_now();", f"{c}_time = _t_ullong;", f"{c}_new = 1;",
                                     f"{c}_rcvd = 1;"]:
            raise CertificateError(f"certificate: the callback {t.callback} does not update the clock of {t.name}")
        rels = [(path, fld) for tc, path, fld in pm.input_relations if tc == c]
        drels = [(kind, fld) for tc, kind, fld in pm.derived_inputs if tc == c]
        aged = False
        fb_rows, fb_lines, hold = [], [], []
        for path, fld in rels:
            dst = f"{u}.{fld}"
            if fld in fallbacks and c in timeouts:
                n = next((n for n, text in glue if text.startswith(dst + " = ")
                          and lines[n - 2].strip() == f"if (({timeouts[c] * 1000000}ULL < _age)) {{"), None)
                if n is None:
                    raise CertificateError(f"certificate: input_glue has no fallback for {dst}",
                                           [f"  lines {first}-{last} of the printed C"])
                age = age_before(c, n - 2, t.name)
                age_starts.append(age[0][0])
                aged = True
                fb_rows.append({"dst": dst, "src": f"{t.name} {path}", "type": pm.input_type(fld),
                                "value": _value_text(pm.input_type(fld), fallbacks[fld])})
                fb_lines += age + _block(lines, n - 1)
            else:
                hold.append({"dst": dst, "src": f"{t.name} {path}", "type": pm.input_type(fld)})
        d_rows, d_lines = [], []
        for kind, fld in drels:
            dst = f"{u}.{fld}"
            d_rows.append({"dst": dst, "kind": kind, "type": pm.input_type(fld)})
            if kind == "age_ms":
                n = find(f"{dst} = (unsigned int)(_age / 1000000ULL);", first, last, f"{t.name} age_ms")
                age = age_before(c, n - 2, t.name)
                age_starts.append(age[0][0])
                aged = True
                d_lines += age + _block(lines, n - 1)
            else:
                flag = f"{c}_new" if kind == "is_new" else f"{c}_rcvd"
                n = find(f"{dst} = _t_uchar;", first, last, f"{t.name} {kind}")
                if lines[n - 2].strip() != f"_t_uchar = {flag};":
                    raise CertificateError(f"certificate: {dst} is not copied from {flag}")
                d_lines += [(n - 1, lines[n - 2].strip()), (n, lines[n - 1].strip())]
        reset = find(f"{c}_new = 0;", what=f"the reset of {t.name}'s flag")
        parts = (["the fallbacks, each after its topic's age"] if fb_lines else []) \
            + (["the derived inputs" + (" (age_ms after the age)" if aged and d_lines else "")] if d_lines else []) \
            + [f"the reset of `{c}_new`, after every timed topic's"]
        out.append({
            "topic": t.name, "c_name": c, "timeout": timeouts.get(c), "callback": t.callback,
            "fallbacks": fb_rows, "hold": hold, "derived": d_rows, "parts": ", ".join(parts[:-1]) +
            (" and " if len(parts) > 1 else "") + parts[-1], "clock": _indented(lines, clock),
            "glue": _indented(lines, fb_lines + d_lines + [(reset, "")]),
        })
    now = [(n, text) for n, text in glue if text == "_now = ros_now();"]
    if age_starts and (len(now) != 1 or now[0][0] > min(age_starts)):
        raise CertificateError("certificate: input_glue does not read the cycle's time once, before the ages")
    if not age_starts and now:
        raise CertificateError("certificate: input_glue reads the cycle's time but no age")
    return {"now": _indented(lines, now), "topics": out}


def _relations(pm: ProvedModel, c_text: str) -> tuple[list[dict], list[dict]]:
    """The rows of the relation sections, from the proved model and the
    printed C.  An input relation is copied by its topic's callback into
    the topic's global (``cb_lines``), then by ``input_glue`` into the
    controller's inputs (``lines``); a direct one (rule 4.16:
    :meth:`ProvedModel.is_direct`) by its callback alone, from ``*msg``
    straight into the controller's inputs (``cb_lines``; ``direct`` is
    true, ``lines`` empty).  A direct relation whose callback does not
    read its leaf of ``*msg``, or that ``input_glue`` copies too, is a
    :class:`CertificateError`."""
    lines = _Copies(c_text.splitlines())
    spans = _function_spans(c_text)
    glue = _span(spans, "input_glue")
    inputs = []
    for topic_c, path, fld in pm.input_relations:
        t = pm.topic(topic_c)
        cb = _span(spans, t.callback)
        dst = f"{pm.inputs_var}.{fld}"
        row = {"src": f"{t.name} {path}", "dst": dst, "type": pm.input_type(fld), "callback": t.callback,
               "direct": pm.is_direct(topic_c, path)}
        if row["direct"]:
            row["cb_lines"] = _copy_lines(lines, cb, dst)
            row["lines"] = []
            src = row["cb_lines"][0][1]
            if not (src.startswith("_t_") and src.endswith(f" = (*msg).{path};")):
                raise CertificateError(f"certificate: the callback {t.callback} does not copy {dst} from "
                                       f"(*msg).{path}", [f"  line {row['cb_lines'][0][0]}: {src}"])
            if any(glue[0] < n <= glue[1] for n in lines.by_dst.get(dst, ())):
                raise CertificateError(f"certificate: input_glue copies {dst}, a direct relation (rule 4.16) "
                                       f"that only the callback {t.callback} writes")
        else:
            row["cb_lines"] = _copy_lines(lines, cb, f"{t.msg_var}.{path}")
            row["lines"] = _copy_lines(lines, glue, dst)
        inputs.append(row)
    outputs = []
    for fld, topic_c, path in pm.output_relations:
        t = pm.topic(topic_c)
        outputs.append({
            "src": f"{pm.outputs_var}.{fld}", "dst": f"{t.name} {path}", "type": pm.output_type(fld),
            "function": t.output_glue,
            "lines": _copy_lines(lines, _span(spans, t.output_glue), f"(*command).{path}"),
        })
    return _runs(inputs), _runs(outputs)


#: The last index of a relation's end (``ranges.data[12]``, ``Scan[3]``).
_LAST_INDEX = re.compile(r"\[(0|[1-9][0-9]*)\](?=[^\[]*$)")


def _split_index(text: str) -> tuple[str, int, str] | None:
    """``text`` as (before, index, after) around its last index, else ``None``."""
    m = _LAST_INDEX.search(text)
    return (text[:m.start()], int(m.group(1)), text[m.end():]) if m else None


def _element_of(first: dict, row: dict, k: int, step: int = 1) -> bool:
    """Whether ``row`` is element ``k`` of the run that ``first`` starts:
    its ends are ``first``'s with the controller's last index ``k``
    further and the message's ``step * k`` (``step`` 1, or -1 for a
    reversed array), of the same type, copied by the same function, and
    its C lines are ``first``'s with those indices changed (the same copy
    form)."""
    a, b = _split_index(first["src"]), _split_index(first["dst"])
    c, d = _split_index(row["src"]), _split_index(row["dst"])
    if None in (a, b, c, d) or (c[0], c[2], d[0], d[2]) != (a[0], a[2], b[0], b[2]) \
            or (c[1], d[1]) != ((a[1] + step * k, b[1] + k) if first["src"].startswith("/")
                                else (a[1] + k, b[1] + step * k)):
        return False
    if any(row.get(key) != first.get(key) for key in ("type", "callback", "function", "direct")):
        return False
    # the C lines: the message side (a path after ".") and the controller
    # side (``var.field``) of the first element, with their indices moved
    src_path = first["src"].split(" ", 1)[1] if first["src"].startswith("/") else first["src"]
    dst_path = first["dst"].split(" ", 1)[1] if first["dst"].startswith("/") else first["dst"]
    msg_first = first["src"].startswith("/")  # an input relation: the message is the source
    moves = [(p, f"{_split_index(p)[0]}[{_split_index(p)[1] + (step if is_msg else 1) * k}]{_split_index(p)[2]}")
             for p, is_msg in ((src_path, msg_first), (dst_path, not msg_first))]

    def moved(text: str) -> str:
        # both ends replaced in one pass (one end's new index may be the other's old one)
        pattern = "|".join(r"(?<![0-9A-Za-z_])" + re.escape(old) for old, _ in moves)
        table = dict(moves)
        return re.sub(pattern, lambda m: table[m.group(0)], text)

    for key in ("cb_lines", "lines"):
        mine, theirs = row.get(key, []), first.get(key, [])
        if len(mine) != len(theirs) or any(t != moved(f) for (_, t), (_, f) in zip(mine, theirs)):
            return False
    return True


def _runs(rows: list[dict]) -> list[dict]:
    """The relation rows with every run of two or more elements of one
    whole-array relation (rule 4.15: consecutive elements, same copy form)
    made one row: ``first`` and ``last`` (the rows of its first and last
    elements), ``count``, and ``src``/``dst`` with the index ranges.  Every
    element's copy was looked up in the C (:func:`_relations`) and is
    checked here to be the first's with the indices changed."""
    out: list[dict] = []
    i = 0
    while i < len(rows):
        j = i + 1
        step = 1 if j < len(rows) and _element_of(rows[i], rows[j], 1, 1) else -1
        while j < len(rows) and _element_of(rows[i], rows[j], j - i, step):
            j += 1
        if j - i >= 2:
            first, last = rows[i], rows[j - 1]
            a, b = _split_index(first["src"]), _split_index(last["src"])
            c, d = _split_index(first["dst"]), _split_index(last["dst"])
            out.append({**first, "count": j - i, "first": first, "last": last,
                        "src": f"{a[0]}[{a[1]}..{b[1]}]{a[2]}", "dst": f"{c[0]}[{c[1]}..{d[1]}]{c[2]}"})
        else:
            out.append({**rows[i], "count": 0})
        i = j
    return out


def _hashes(folder: Path, files: list[str]) -> list[tuple[str, str]]:
    return [(name, sha256_file(folder / name)) for name in sorted(set(files))]


def _commands(build: object) -> list[str]:
    """The compiler commands of a ``build`` record, one shell line each
    (``shlex.join``; a JSON list when a word holds a backtick or a control
    character, which a Markdown code block could not show as is)."""
    import shlex

    if build is None:
        return []
    cmds = build.get("commands") if isinstance(build, dict) else None
    if not isinstance(cmds, list) or not all(isinstance(c, list) and c and all(isinstance(w, str) for w in c)
                                             for c in cmds):
        raise CertificateError("certificate: the manifest's build.commands is not a list of commands")
    out = []
    for c in cmds:
        line = shlex.join(c)
        out.append(json.dumps(c) if re.search(r"[`\x00-\x1f\x7f]", line) else line)
    return out


def render_certificate(rec: ProofRecord, proved: str, glue_text: str, hashes: list[tuple[str, str]],
                       diagram: str | None = None) -> str:
    """The certificate of ``rec``: rendered from the proved model text
    ``proved``, the printed glue ``glue_text``, the digests ``hashes``
    ((file, SHA-256), sorted by file) and the proved diagram's text.
    Deterministic: ``pyrosgen verify`` renders it again from the proof's
    texts and the manifest and compares."""
    cert_name, manifest_name, sums_name = certificate_files(rec.node)
    pm = parse_model_text(proved, origin=rec.model_file)
    inputs, outputs = _relations(pm, glue_text)
    stamps = _stamps(pm, glue_text)
    freshness = _freshness(pm, glue_text)
    strings = _strings(pm, glue_text)
    built = any(name.startswith("bin/") for name, _ in hashes)
    string_structs = sorted(name for name, fields in pm.messages.items()
                            if name.startswith(("ros_string", "ros_rstring")) and [f for f, _ in fields] == ["len", "truncated", "data"])
    seq_structs = sorted(name for name, fields in pm.messages.items()
                         if name.startswith(("ros_seq_", "ros_rseq_")) and [f for f, _ in fields] == ["len", "truncated", "data"])
    return render(
        "CERTIFICATE.md.j2",
        rec=rec, pm=pm, md=md_code, source=md_code(source_label(rec.source_name)), diagram=diagram,
        inputs=inputs, outputs=outputs, stamps=stamps, freshness=freshness, strings=strings,
        string_structs=string_structs, seq_structs=seq_structs,
        reject_structs=[n for n in string_structs + seq_structs if n.startswith(("ros_rseq_", "ros_rstring"))],
        hashes=hashes, built=built, commands=_commands(rec.build),
        generated=bool(isinstance(rec.build, dict) and isinstance(rec.build.get("package"), dict)
                       and rec.build["package"].get("generated") is True),
        manifest=manifest_name, sums=sums_name, certificate=cert_name,
    )


def write_certificate(rec: ProofRecord, folder: Path, files: list[str]) -> list[str]:
    """Write the certificate, the manifest and the digest file of ``rec``
    into ``folder``, covering ``files`` (paths relative to ``folder``, each
    present); return the three names."""
    cert_name, manifest_name, sums_name = certificate_files(rec.node)
    proved = (folder / rec.model_file).read_text(encoding="utf-8")
    glue_text = (folder / rec.glue_c).read_text(encoding="utf-8")
    hashes = _hashes(folder, files)
    # the proved diagram as Coq printed it (names checked by the front end
    # and Coq; a line is shown in a code block, never as Markdown)
    diagram = ((folder / rec.controller["text"]).read_text(encoding="utf-8").rstrip("\n")
               if rec.controller and rec.controller.get("text") else None)
    text = render_certificate(rec, proved, glue_text, hashes, diagram)
    manifest = {
        "format": MANIFEST_FORMAT,
        **{k: v for k, v in asdict(rec).items() if k != "tools"},
        "tools": [list(t) for t in rec.tools],
        "files": dict(hashes),
    }
    (folder / cert_name).write_text(text, encoding="utf-8")
    (folder / manifest_name).write_text(json.dumps(manifest, indent=2, sort_keys=True) + "\n", encoding="utf-8")
    (folder / sums_name).write_text("".join(f"{d}  {n}\n" for n, d in hashes), encoding="utf-8")
    return [cert_name, manifest_name, sums_name]


#: The largest manifest ``verify`` reads (4 MiB: a node with two controller
#: arrays of 8,192 elements has one of a few KB).
MANIFEST_MAX_BYTES = 4 << 20
#: The deepest nesting of arrays and objects in a manifest (a real one has 4).
MANIFEST_MAX_DEPTH = 8

_HEX64 = re.compile(r"[0-9a-f]{64}")
_NODE = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
_THEOREM = re.compile(r"(?:Ctrl\.)?[A-Za-z_][A-Za-z0-9_]*")


class ManifestError(UserError, ValueError):
    """A manifest that is not one ``write_certificate`` writes (exit 1):
    its message names the field that is wrong."""


def _json_depth(text: str) -> int:
    """The deepest nesting of ``[`` and ``{`` in the JSON ``text``,
    outside its strings (computed without recursion, before any parse)."""
    depth = deepest = 0
    in_str = esc = False
    for ch in text:
        if in_str:
            if esc:
                esc = False
            elif ch == "\\":
                esc = True
            elif ch == '"':
                in_str = False
        elif ch == '"':
            in_str = True
        elif ch in "[{":
            depth += 1
            deepest = max(deepest, depth)
        elif ch in "]}":
            depth -= 1
    return deepest


def read_manifest(path: Path) -> tuple[ProofRecord, dict[str, str]]:
    """The record and the file digests of a manifest written by
    :func:`write_certificate`, read as hostile input (through
    :func:`pyrosgen.verify.folder.read_text`: a regular file of at most
    :data:`MANIFEST_MAX_BYTES`, no link); every field's type and shape is
    checked (the node a C identifier, every file name a plain relative name
    and the one the node's name gives, digests 64 hex digits, the theorems
    those of the node): :class:`ManifestError` (exit 1) names what is
    wrong."""
    from pyrosgen.proof.coqmodel import node_file_names
    from pyrosgen.verify.folder import UnsafeFile, check_name, read_text

    path = Path(path)
    name = path.name
    try:
        text = read_text(path.parent, name, limit=MANIFEST_MAX_BYTES, what="manifest")
    except FileNotFoundError:
        raise ManifestError(f"{path}: missing") from None
    except UnsafeFile as exc:
        raise ManifestError(f"{path.parent}/{exc}") from None
    if _json_depth(text) > MANIFEST_MAX_DEPTH:
        raise ManifestError(f"{name}: nested more than {MANIFEST_MAX_DEPTH} deep: not a pyrosgen manifest")
    try:
        data = json.loads(text)
    except (ValueError, RecursionError) as exc:
        raise ManifestError(f"{name}: not JSON: {exc}") from None
    if not isinstance(data, dict) or type(data.get("format")) is not int or data["format"] != MANIFEST_FORMAT:
        raise ManifestError(f"{name}: not a pyrosgen manifest of format {MANIFEST_FORMAT}")

    def bad(field_: str, what: str) -> ManifestError:
        return ManifestError(f"{name}: field {field_!r}: {what}")

    def get(key: str, typ: type | tuple[type, ...], what: str):
        if key not in data:
            raise bad(key, "missing")
        v = data[key]
        if not isinstance(v, typ) or (typ is int and isinstance(v, bool)):
            raise bad(key, f"{type(v).__name__}, not {what}")
        return v

    def short(key: str, v: object, limit: int = 4096) -> None:
        if isinstance(v, str) and len(v) > limit:
            raise bad(key, f"a string of {len(v)} characters, more than {limit}")

    known = {f.name for f in dataclasses.fields(ProofRecord)} | {"format", "files"}
    extra = sorted(set(data) - known)
    if extra:
        raise bad(extra[0], "not a field of a pyrosgen manifest")
    node = get("node", str, "a string")
    if not _NODE.fullmatch(node) or len(node) > 200:
        raise bad("node", f"{node[:80]!r} is not a C identifier")
    names = node_file_names(node)
    derived = {"node_v": names.v_file, "types_h": names.types_header, "glue_c": names.glue_c,
               "sexp": names.sexp, "model_file": f"{node}.model"}
    for key, want in derived.items():
        v = get(key, str, "a file name")
        try:
            check_name(v, f"field {key!r}:")
        except UnsafeFile as exc:
            raise ManifestError(f"{name}: {exc}") from None
        if v != want:
            raise bad(key, f"{v!r}, not the node's file {want!r}")
    ddc = get("ddc", bool, "true or false")
    target = data.get("target", "ros1")
    if target not in ("ros1", "ros2"):
        raise bad("target", f"{str(target)[:80]!r}, not ros1 or ros2")
    theorems = get("theorems", list, "a list of theorem names")
    for key in ("theorem", "assumptions", "pyrosgen_version", "source_name"):
        short(key, get(key, str, "a string"), 1 << 16)
    for key in ("library_sha256", "source_sha256"):
        v = get(key, str, "a SHA-256")
        if not _HEX64.fullmatch(v) and not (key == "source_sha256" and v == ""):
            raise bad(key, f"{v[:80]!r} is not 64 hexadecimal digits")
    controller = data.get("controller")
    if controller is not None:
        if not isinstance(controller, dict):
            raise bad("controller", f"{type(controller).__name__}, not an object or null")
        want_ctrl = {"c": names.controller_c, "sexp": names.controller_sexp, "text": names.controller_text,
                     "wf": f"Ctrl.{names.theorem_ctrl_wf}", "e2e": f"Ctrl.{names.theorem_e2e}",
                     "linked": f"Ctrl.{names.theorem_linked}"}
        if controller != want_ctrl:
            k = next((k for k in sorted(set(controller) | set(want_ctrl))
                      if controller.get(k) != want_ctrl.get(k)), "?")
            got = controller.get(k)
            raise bad(f"controller.{k}", f"{str(got)[:80]!r}, not the node's {want_ctrl.get(k)!r}")
    want_thms = ([names.theorem_ddc, names.theorem_target] if ddc else []) + [names.theorem_wf] + (
        [controller["wf"], controller["e2e"], controller["linked"]] if controller else [])
    if theorems != want_thms:
        raise bad("theorems", f"{str(theorems)[:200]}, not the node's theorems {want_thms}")
    if data["theorem"] != want_thms[0]:
        raise bad("theorem", f"{data['theorem'][:80]!r}, not the node's main theorem {want_thms[0]!r}")
    wp = data.get("wp")
    if wp is not None:
        if not isinstance(wp, dict) or set(wp) - {"proved", "total", "prover", "contracts", "functions"}:
            raise bad("wp", "not an object of proved, total, prover, contracts, functions")
        if wp.get("contracts") != f"{node}_wp.c":
            c = wp.get("contracts")
            try:
                check_name(c, "field 'wp.contracts':")
            except UnsafeFile as exc:
                raise ManifestError(f"{name}: {exc}") from None
            raise bad("wp.contracts", f"{str(c)[:80]!r}, not the node's contracts file {node}_wp.c")
        for k in ("proved", "total"):
            if not isinstance(wp.get(k), int) or isinstance(wp.get(k), bool):
                raise bad(f"wp.{k}", "not an integer")
        if not isinstance(wp.get("prover"), str):
            raise bad("wp.prover", "not a string")
        fs = wp.get("functions", [])
        if not isinstance(fs, list) or not all(
                isinstance(f, list) and len(f) == 3 and isinstance(f[0], str) and (f[1] is None or isinstance(f[1], str))
                and isinstance(f[2], list) and all(isinstance(s, str) for s in f[2]) for f in fs):
            raise bad("wp.functions", "not a list of [name, pointer, [separated]]")
    tools = data.get("tools", [])
    if not isinstance(tools, list) or not all(
            isinstance(t, list) and len(t) == 2 and all(isinstance(s, str) and len(s) < 4096 for s in t)
            for t in tools):
        raise bad("tools", "not a list of [tool, version] pairs of strings")
    files = get("files", dict, "an object of file names and digests")
    for fname, digest in files.items():
        try:
            check_name(fname, "field 'files':")
        except UnsafeFile as exc:
            raise ManifestError(f"{name}: {exc}") from None
        if not isinstance(digest, str) or not _HEX64.fullmatch(digest):
            raise bad(f"files.{fname}", f"{str(digest)[:80]!r} is not 64 hexadecimal digits")
    data = {k: v for k, v in data.items() if k not in ("format", "files", "tools")}
    rec = ProofRecord(**data, tools=[tuple(t) for t in tools])
    return rec, files

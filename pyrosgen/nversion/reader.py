"""The model text read a second time from the YAML file (N-version,
DESIGN.md section 7, issue 29).

``pyrosgen generate`` compares the model text that Coq printed from the
model term its theorems are about (``coq/theories/glue/ModelText.v``) with
the front end's reading of the YAML (``pyrosgen.proof.modeltext``).  Both
sides of that comparison come from the front end's ``load_model``: a
front-end bug that reads ``timeout_ms: 500`` as 5000 would reach the proof,
the node and the certificate unseen.  This module is the second,
independent reading: it shares no code with the front end beyond the YAML
parser (PyYAML's ``compose``), imports nothing from ``pyrosgen``, and
computes the same text from DESIGN.md section 4 (the meaning) and
``ModelText.v`` (the format).  It does not validate: it is called only
after the front end accepted the model, and raises :class:`ReadingError`
on anything it does not understand.
"""

from __future__ import annotations

import re
import struct
from fractions import Fraction
from pathlib import Path

import yaml

from pyrosgen.nversion.msgs import DEFAULT_MAX, STANDARD_ROOT, Messages, ReadingError, c_name

__all__ = ["model_text", "model_lines", "Line", "ReadingError", "read_yaml"]

HEADER = "pyrosgen-model 1"


# --------------------------------------------------------------------------
# The YAML tree, with the text of every number


class Num:
    """A YAML number with its text (``0.5``, ``+20``, ``1.0e-3``) and its
    line in the file (``None`` for a default)."""

    __slots__ = ("text", "value", "line", "col")

    def __init__(self, text: str, value, line: int | None = None, col: int | None = None):
        self.text = text
        self.value = value
        self.line = line
        self.col = col

    def __repr__(self) -> str:
        return f"Num({self.text})"


class YDict(dict):
    """A YAML mapping, with its line and column in the file."""

    line: int | None = None
    col: int | None = None


class YList(list):
    """A YAML sequence, with its line and column in the file."""

    line: int | None = None
    col: int | None = None


class Line(str):
    """A line of model text, with the place in the YAML file it comes from
    (``at``: ``(line, column)``, ``None`` when it has none of its own)."""

    at: tuple[int, int] | None = None


def _line(text: str, where=None) -> Line:
    out = Line(text)
    line = getattr(where, "line", None)
    out.at = (line, getattr(where, "col", None) or 1) if line is not None else None
    return out


class _Loader(yaml.SafeLoader):
    pass


def _plain(node, loader: yaml.SafeLoader):
    line, col = node.start_mark.line + 1, node.start_mark.column + 1
    if isinstance(node, yaml.MappingNode):
        out = YDict()
        out.line, out.col = line, col
        for k, v in node.value:
            # a key is its text: a field named NO or On is not a boolean
            key = k.value if isinstance(k, yaml.ScalarNode) else _plain(k, loader)
            out[key] = _plain(v, loader)
        return out
    if isinstance(node, yaml.SequenceNode):
        seq = YList(_plain(v, loader) for v in node.value)
        seq.line, seq.col = line, col
        return seq
    value = loader.construct_object(node, deep=True)
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        return Num(node.value, value, line, col)
    return value


def read_yaml(path: Path):
    """The YAML file at ``path`` as dicts, lists and scalars (numbers as
    :class:`Num`)."""
    text = Path(path).read_text(encoding="utf-8")
    loader = _Loader(text)
    try:
        node = loader.get_single_node()
        if node is None:
            raise ReadingError(f"{path}: empty")
        return _plain(node, loader)
    finally:
        loader.dispose()


def _int(x) -> int:
    if isinstance(x, Num) and isinstance(x.value, int):
        return int(x.text)
    raise ReadingError(f"expected an integer, got {x!r}")


# --------------------------------------------------------------------------
# Numbers (rules 4.11, 4.12): a decimal rounded once to its type

_DEC = re.compile(r"([+-]?)([0-9]*)(?:\.([0-9]*))?(?:[eE]([+-]?[0-9]+))?")


def _float_bits(text: str, prim: str, scale: Fraction | None = None) -> int:
    """The IEEE bits of decimal ``text`` (times ``scale``, exactly)
    rounded once, to nearest even, to ``float64`` (53-bit significand) or
    ``float32`` (24 bits)."""
    m = _DEC.fullmatch(text)
    if m is None or not (m.group(2) or m.group(3)):
        raise ReadingError(f"not a decimal number: {text!r}")
    neg = m.group(1) == "-"
    q = Fraction(int((m.group(2) or "") + (m.group(3) or "") or "0")) * Fraction(10) ** (
        int(m.group(4) or 0) - len(m.group(3) or ""))
    if scale is not None:
        q *= scale
    if prim == "float64":
        p, emin, ebits, width = 53, -1022, 11, 64
    else:
        p, emin, ebits, width = 24, -126, 8, 32
    sign = (1 << (width - 1)) if neg else 0
    if q == 0:
        return sign
    # find e with 2^e <= q < 2^(e+1)
    e = q.numerator.bit_length() - q.denominator.bit_length()
    while Fraction(2) ** e > q:
        e -= 1
    while Fraction(2) ** (e + 1) <= q:
        e += 1
    e = max(e, emin)
    scaled = q / Fraction(2) ** (e - (p - 1))      # the significand, p bits before rounding
    sig = round(scaled)                              # Python rounds halves to even
    if sig == 1 << p:
        sig, e = sig >> 1, e + 1
    emax = (1 << (ebits - 1)) - 1
    if e > emax:
        raise ReadingError(f"{text} is out of the range of {prim}")
    if sig < 1 << (p - 1):                           # subnormal
        return sign | sig
    return sign | ((e + emax) << (p - 1)) | (sig - (1 << (p - 1)))


def _val_text(x, prim: str) -> str:
    """A fallback constant as ``ModelText.val_text`` prints it."""
    if prim == "bool":
        if x is True or x is False:
            return "1" if x else "0"
        raise ReadingError(f"not a bool: {x!r}")
    if prim in ("float32", "float64"):
        if not isinstance(x, Num):
            raise ReadingError(f"not a number: {x!r}")
        return f"0x{_float_bits(x.text, prim):0{16 if prim == 'float64' else 8}x}"
    return str(_int(x))


def _zero_text(prim: str) -> str:
    return {"float64": "0x" + "0" * 16, "float32": "0x" + "0" * 8}.get(prim, "0")


# --------------------------------------------------------------------------
# Field paths

_STEP = re.compile(r"([A-Za-z][A-Za-z0-9_]*)((?:\[[0-9]*\])*)")


def parse_path(text: str) -> list[tuple[str, list[int | None]]]:
    """``poses[3].pose.x`` -> ``[('poses', [3]), ('pose', []), ('x', [])]``
    (``None`` for ``[]``)."""
    if not isinstance(text, str):
        raise ReadingError(f"a field path is a string, got {text!r}")
    out = []
    for seg in text.split("."):
        m = _STEP.fullmatch(seg)
        if m is None:
            raise ReadingError(f"cannot read the field path {text!r}")
        idx = [int(i) if i else None for i in re.findall(r"\[([0-9]*)\]", m.group(2))]
        out.append((m.group(1), idx))
    return out


def _walk(msgs: Messages, ros_type: str, text: str):
    """Walk field path ``text`` of ``ros_type`` on the definitions as
    written: ``(marks, steps, end)`` where ``marks`` are the (type, field)
    keys of the strings and variable-length arrays reached, outermost
    first (``(type, 'name[]')`` for the strings of an array of strings),
    ``steps`` the path in the carried C struct (``ranges.data[540]``) and
    ``end`` what it ends on: ``('prim', T)``, ``('seq', T, key)`` (a whole
    array of primitives), ``('seqmsg', T, key)``, ``('seqstring', key)``,
    ``('string', key)``, ``('array', T, n)`` (a whole fixed-size array of
    primitives), ``('msgarray', T)`` or ``('msg', T)``."""
    marks: list[tuple[str, str]] = []
    steps: list[str | int] = []
    cur = ros_type
    end = ("msg", ros_type)
    for name, idx in parse_path(text):
        if end[0] != "msg":
            raise ReadingError(f"field path {text!r} goes on past {end}")
        f = msgs.field(cur, name)
        steps.append(name)
        key = (cur, name)
        idx = list(idx)
        if f.card == "sequence":
            marks.append(key)
            if not idx:   # the whole array: of primitives, messages or strings
                end = {"prim": ("seq", f.base, key), "msg": ("seqmsg", f.base, key)}.get(f.kind, ("seqstring", key))
                continue
            i = idx.pop(0)
            steps += ["data", i if i is not None else 0]
            if f.kind == "prim":
                end = ("prim", f.base)
            elif f.kind == "string":
                skey = (cur, name + "[]")
                marks.append(skey)
                if idx:
                    j = idx.pop(0)
                    steps += ["data", j if j is not None else 0]
                    end = ("prim", "uint8")
                else:
                    end = ("string", skey)
            elif f.kind == "msg":
                cur, end = f.base, ("msg", f.base)
            else:
                raise ReadingError(f"field path {text!r}: {name} has type {f.base}[]")
        elif f.kind == "string":
            if f.card != "scalar":
                raise ReadingError(f"field path {text!r}: {name} is an array of strings")
            marks.append(key)
            if idx:
                steps += ["data", idx.pop(0)]
                end = ("prim", "uint8")
            else:
                end = ("string", key)
        elif f.card == "array":
            if idx:
                i = idx.pop(0)
                if i is None:
                    raise ReadingError(f"field path {text!r}: [] on a fixed-size array")
                steps.append(i)
                end = ("prim", f.base) if f.kind == "prim" else ("msg", f.base)
                cur = f.base
            elif f.kind == "prim":
                end = ("array", f.base, f.size)
            else:
                end = ("msgarray", f.base)
        elif f.kind == "prim":
            end = ("prim", f.base)
        elif f.kind == "msg":
            cur, end = f.base, ("msg", f.base)
        else:
            raise ReadingError(f"field path {text!r}: {name} has type {f.base}")
        if idx:
            raise ReadingError(f"field path {text!r}: too many indices after {name}")
    return marks, steps, end


def _path_text(steps) -> str:
    out = ""
    for s in steps:
        out += f"[{s}]" if isinstance(s, int) else ("." if out else "") + s
    return out


# --------------------------------------------------------------------------
# The model text


def _get(d, *keys, default=None):
    for k in keys:
        if not isinstance(d, dict) or k not in d:
            return default
        d = d[k]
    return d


_CTYPE = re.compile(r"([a-z0-9]+)(?:\[([0-9]+)\])?")


def _ctrl_fields(fields) -> list[tuple[str, str, int | None]]:
    out = []
    for name, t in (fields or {}).items():
        m = _CTYPE.fullmatch(t) if isinstance(t, str) else None
        if m is None:
            raise ReadingError(f"controller field {name}: cannot read the type {t!r}")
        out.append((name, m.group(1), int(m.group(2)) if m.group(2) else None))
    return out


def _ftext(prim: str, size: int | None) -> str:
    return prim if size is None else f"array {size} {prim}"


def _topic_c(name: str) -> str:
    return name.lstrip("/").replace("/", "_")


_TARGET = re.compile(r"([A-Za-z][A-Za-z0-9_]*)(?:\[([0-9]+)\])?")


def model_text(path, *, standard_root: Path = STANDARD_ROOT, doc=None) -> str:
    """The canonical model text (the grammar of ``ModelText.print_model``)
    of the model file at ``path``, read without the front end (``doc``:
    the file as :func:`read_yaml` read it, if it was)."""
    return "".join(line + "\n" for line in model_lines(path, standard_root=standard_root, doc=doc))


def model_lines(path, *, standard_root: Path = STANDARD_ROOT, doc=None) -> list[Line]:
    """The lines of :func:`model_text`, each with the line of the YAML
    file it comes from (:class:`Line`)."""
    path = Path(path)
    if doc is None:
        doc = read_yaml(path)
    if not isinstance(doc, dict):
        raise ReadingError(f"{path}: not a mapping")
    msg_dirs = [path.parent / d for d in (doc.get("msg_paths") or [])]
    msgs = Messages(msg_dirs, standard_root)

    node, ctrl = doc.get("node") or {}, doc.get("controller") or {}
    cname = ctrl["name"]
    inputs = _ctrl_fields(_get(ctrl, "inputs", "fields"))
    outputs = _ctrl_fields(_get(ctrl, "outputs", "fields"))
    in_size = {n: s for n, _, s in inputs}
    out_size = {n: s for n, _, s in outputs}
    in_prim = {n: p for n, p, _ in inputs}

    topics = list(doc.get("topics") or [])
    by_name = {t["name"]: t for t in topics}
    rels = doc.get("relations") or {}
    in_rows = list(rels.get("inputs") or [])
    out_rows = list(rels.get("outputs") or [])

    # -- which strings and variable-length arrays are carried (4.14, 4.15)
    named: set[tuple[str, str]] = set()
    maxima: dict[tuple[str, str], int] = {}
    reject: set[tuple[str, str]] = set()
    constants: dict[str, list[tuple[list, bytes]]] = {}
    for t in topics:
        ty = t["type"]
        consts = []
        for key, value in t.items():
            if key == "frame_id":
                consts.append(("header.frame_id", value))
            elif key == "strings":
                consts += list(value.items())
        cl = []
        for ptext, value in consts:
            marks, steps, end = _walk(msgs, ty, ptext)
            if end[0] != "string" or not isinstance(value, str):
                raise ReadingError(f"topic {t['name']}: constant string {ptext!r}: not a string field or value")
            named.add(end[1])
            cl.append((steps, value.encode("utf-8")))
        constants[t["name"]] = cl
        for ptext, n in (t.get("max_length") or {}).items():
            marks, _, _ = _walk(msgs, ty, ptext)
            if not marks:
                raise ReadingError(f"topic {t['name']}: max_length {ptext!r} names no array or string")
            maxima.setdefault(marks[-1], _int(n))
        if t.get("direction") == "subscribe":
            for ptext, pol in (t.get("policy") or {}).items():
                marks, _, _ = _walk(msgs, ty, ptext)
                if pol == "reject":
                    reject.add(marks[-1])
    for rows, direction in ((in_rows, "subscribe"), (out_rows, "publish")):
        for r in rows:
            if "field" in r and r.get("topic") in by_name and by_name[r["topic"]]["direction"] == direction:
                marks, _, _ = _walk(msgs, by_name[r["topic"]]["type"], r["field"])
                named.update(marks)
    msgs.carried = {k: maxima.get(k, DEFAULT_MAX) for k in named}
    msgs.reject = reject & named

    ufields, yfields = _get(ctrl, "inputs", "fields"), _get(ctrl, "outputs", "fields")
    lines = [
        _line(HEADER),
        _line(f"node {node['name']}", node),
        _line(f"period_ms {_int(node['period_ms'])}", node["period_ms"]),
        _line(f"controller {cname}", ctrl),
        _line(f"inputs {_get(ctrl, 'inputs', 'name')} ExtU_{cname}_T", ctrl.get("inputs")),
        *(_line(f"input {n} {_ftext(p, s)}", ufields) for n, p, s in inputs),
        _line(f"outputs {_get(ctrl, 'outputs', 'name')} ExtY_{cname}_T", ctrl.get("outputs")),
        *(_line(f"output {n} {_ftext(p, s)}", yfields) for n, p, s in outputs),
    ]
    for struct_name in msgs.used(t["type"] for t in topics):
        lines.append(_line(f"message {struct_name}"))
        lines += [_line(f"field {f.name} {f.text()}") for f in msgs.structs[struct_name]]
    for t in topics:
        q = _int(t.get("queue_size")) if "queue_size" in t else None
        if q is None:
            raise ReadingError(f"topic {t['name']}: no queue_size")
        lines.append(_line(f"topic {t['name']} {_topic_c(t['name'])} {t['direction']} {t['type']} {q}", t))

    # -- relations, expanded (rule 4.15: whole arrays element by element)
    def expand(r, ty, size):
        """(message path steps, controller elem suffix) of relation row ``r``."""
        marks, steps, end = _walk(msgs, ty, r["field"])
        derived = r.get("derived")
        if derived in ("length", "truncated"):
            return [(steps + ["len" if derived == "length" else "truncated"], None)]
        if derived is not None:
            raise ReadingError(f"relation {r!r}: derived {derived!r} with a field")
        if size is None:
            if end[0] != "prim":
                raise ReadingError(f"relation {r!r}: field is not a primitive leaf ({end[0]})")
            return [(steps, "")]
        if end[0] in ("seq", "string"):
            return [(steps + ["data", i], f"[{i}]") for i in range(size)]
        if end[0] == "array":
            return [(steps + [i], f"[{i}]") for i in range(size)]
        raise ReadingError(f"relation {r!r}: a whole controller array related to {end[0]}")

    def target(text, sizes):
        m = _TARGET.fullmatch(text) if isinstance(text, str) else None
        if m is None or m.group(1) not in sizes:
            raise ReadingError(f"cannot read the controller field {text!r}")
        if m.group(2) is not None:
            return m.group(1), f"[{int(m.group(2))}]", None
        return m.group(1), "", sizes[m.group(1)]

    in_lines, fallbacks, derived_lines = [], [], []
    for r in in_rows:
        t = by_name[r["topic"]]
        tc = _topic_c(t["name"])
        if "field" not in r:
            derived_lines.append(_line(f"derived_input {tc} {r['derived']} {r['input']}", r))
            continue
        name, suffix, size = target(r["input"], in_size)
        for steps, elem in expand(r, t["type"], size):
            in_lines.append(_line(f"input_relation {tc} {_path_text(steps)} "
                                  f"{name}{suffix if elem is None else (elem or suffix)}", r))
            if "timeout_ms" in t:
                policy = r.get("on_timeout", t.get("on_timeout", "zero"))
                if policy == "zero":
                    fallbacks.append(_line(f"fallback {name} {_zero_text(in_prim[name])}",
                                           r if "on_timeout" in r else t))
                elif policy != "hold":
                    fallbacks.append(_line(f"fallback {name} {_val_text(policy, in_prim[name])}", r))
    lines += in_lines
    for r in out_rows:
        t = by_name[r["topic"]]
        name, suffix, size = target(r["output"], out_size)
        for steps, elem in expand(r, t["type"], size):
            lines.append(_line(f"output_relation {name}{suffix if elem is None else (elem or suffix)} "
                               f"{_topic_c(t['name'])} {_path_text(steps)}", r))
    lines += [_line(f"timeout {_topic_c(t['name'])} {_int(t['timeout_ms'])}", t["timeout_ms"])
              for t in topics if "timeout_ms" in t]
    lines += fallbacks
    lines += derived_lines
    stamped = [t for t in topics if "stamp" in t]
    lines += [_line(f"stamp {_topic_c(t['name'])} header.stamp", t) for t in stamped]
    for t in stamped:
        s = t["stamp"]
        if isinstance(s, dict):
            lines.append(_line(f"stamp_from {_topic_c(t['name'])} {_topic_c(s['from'])} header.stamp", s))
        elif s != "now":
            raise ReadingError(f"topic {t['name']}: cannot read the stamp {s!r}")
    for t in topics:
        for steps, data in constants[t["name"]]:
            lines.append(_line(f"string {_topic_c(t['name'])} {_path_text(steps)} "
                               f"{','.join(str(b) for b in data) if data else '-'}", t))
    return lines

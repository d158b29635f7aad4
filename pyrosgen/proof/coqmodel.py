"""The Coq emitter: a :class:`~pyrosgen.frontend.model.NodeModel` as terms of
``ROSGen.NodeModel`` (``coq/theories/glue/NodeModel.v``), and the per-node Coq
file rendered from ``coq/templates/node.v.j2``.

The layers are kept apart as in rosidl: this module turns model values into
Coq *literals* (strings, primitive constructors, paths, field types), each
checked again before it is printed, and the templates in ``coq/templates``
lay those literals out as Coq definitions.

Defence in depth: the front end already refuses hostile names, but nothing
reaches Coq text unchecked here either.  Every identifier must match the C
identifier regex, every topic name the ROS graph-name regex, every string is
printable ASCII with its ``"`` doubled (Coq's string escape), and every
comment is reduced to a harmless character set.  A violation raises
:class:`EmitError` (exit code 2: it means the front end let something
through).  Semantic rules (keywords, types of relations, ...) are *not*
re-checked here: that is the job of Coq's ``generate``, which refuses an
ill-formed model with a message naming the culprit.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

import jinja2

from pyrosgen.errors import ToolFailure
from pyrosgen.render import environment, source_label
from pyrosgen.resources import coq_templates_dir
from pyrosgen.frontend.model import NodeModel, Scalar
from pyrosgen.frontend.msgmodel import PRIMITIVES, FieldPath, MsgField, MsgType, msg_c_name

__all__ = [
    "EmitError",
    "TEMPLATE_DIR",
    "NODE_TEMPLATE",
    "PRIM_CONSTRUCTORS",
    "coq_string",
    "coq_ident",
    "coq_ros_name",
    "coq_comment",
    "coq_z",
    "coq_nat",
    "coq_prim",
    "coq_path",
    "coq_bytes",
    "coq_ftype",
    "coq_ctrl_ftype",
    "coq_val",
    "coq_fallback",
    "DERIVED_CONSTRUCTORS",
    "CoqMsgdef",
    "CoqTopic",
    "CoqNodeModel",
    "emit_model",
    "NodeFile",
    "node_file_names",
    "render_node_file",
    "coq_target",
    "TARGETS",
    "render_model_definitions",
    "template_env",
]

#: ``coq/templates``: the Coq library's templates (:mod:`pyrosgen.resources`).
TEMPLATE_DIR = coq_templates_dir()

#: The per-node template, relative to the repository root (for the
#: "generated from" line).
NODE_TEMPLATE = "coq/templates/node.v.j2"

#: ``ROSGen.NodeModel.prim`` constructor of each ROS primitive.
PRIM_CONSTRUCTORS: dict[str, str] = {
    "bool": "Pbool",
    "int8": "Pint8",
    "uint8": "Puint8",
    "int16": "Pint16",
    "uint16": "Puint16",
    "int32": "Pint32",
    "uint32": "Puint32",
    "int64": "Pint64",
    "uint64": "Puint64",
    "float32": "Pfloat32",
    "float64": "Pfloat64",
}
assert tuple(PRIM_CONSTRUCTORS) == PRIMITIVES

_C_IDENT = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
_ROS_NAME = re.compile(r"/?[A-Za-z][A-Za-z0-9_]*(/[A-Za-z][A-Za-z0-9_]*)*")
_MSG_NAME = re.compile(r"[a-z][a-z0-9_]*/[A-Za-z][A-Za-z0-9]*|time|duration|ros_r?string[1-9][0-9]{0,5}"
                       r"|ros_r?seq_(?:" + "|".join(PRIMITIVES) + r")_[1-9][0-9]{0,5}"
                       r"|ros_r?seq_string[1-9][0-9]{0,5}_[1-9][0-9]{0,5}"
                       r"|ros_r?seq_[a-z][a-z0-9_]*_[A-Za-z][A-Za-z0-9]*_[1-9][0-9]{0,5}")
_PRINTABLE = re.compile(r"[ -~]*")
#: Characters kept as they are in Coq comments: printable ASCII but the
#: double quote (Coq lexes strings inside comments), the star and the
#: parentheses (no comment can be opened or closed) and the backslash (our
#: escape); any other character is written \xNN.
_COMMENT_SAFE = re.compile(r'[ -~]')
_COMMENT_UNSAFE = frozenset('"()*\\')
#: Longest identifier accepted (as the front end: C's 63 significant
#: characters); a little slack for derived names is not needed here.
_MAX_IDENT = 63


class EmitError(ToolFailure):
    """A value the emitter refuses to print into Coq text (it should have
    been refused by the front end: this is a tool failure, exit code 2)."""


# --------------------------------------------------------------------------
# Literals


def coq_string(value: str, what: str = "string") -> str:
    """A Coq string literal: printable ASCII only, ``"`` doubled."""
    if not isinstance(value, str) or not _PRINTABLE.fullmatch(value):
        raise EmitError(f"refusing to print {value!r} as a Coq string ({what}): not printable ASCII")
    return '"' + value.replace('"', '""') + '"'


def coq_ident(name: str, what: str = "identifier") -> str:
    """A C identifier as a Coq string literal (checked against the regex)."""
    if not isinstance(name, str) or not _C_IDENT.fullmatch(name) or len(name) > _MAX_IDENT:
        raise EmitError(f"refusing to print {name!r} as a C identifier ({what})")
    return coq_string(name, what)


def coq_ros_name(name: str, what: str = "topic name") -> str:
    """A ROS graph name as a Coq string literal (checked against the regex)."""
    if not isinstance(name, str) or not _ROS_NAME.fullmatch(name):
        raise EmitError(f"refusing to print {name!r} as a ROS graph name ({what})")
    return coq_string(name, what)


def coq_comment(text: str) -> str:
    """``text`` reduced to characters that are harmless inside a Coq comment."""
    return "".join(
        ch if _COMMENT_SAFE.fullmatch(ch) and ch not in _COMMENT_UNSAFE else f"\\x{ord(ch):02x}" if ord(ch) < 256 else f"\\u{ord(ch):04x}"
        for ch in str(text)
    )


def coq_z(n: int) -> str:
    """An integer literal of type ``Z`` (negative ones parenthesised)."""
    if isinstance(n, bool) or not isinstance(n, int):
        raise EmitError(f"refusing to print {n!r} as an integer")
    return str(n) if n >= 0 else f"({n})"


def coq_nat(n: int) -> str:
    """A natural-number literal (type ``nat``)."""
    if isinstance(n, bool) or not isinstance(n, int) or n < 0:
        raise EmitError(f"refusing to print {n!r} as a natural number")
    return str(n)


def coq_bytes(data: bytes) -> str:
    """The bytes of a constant string (rule 4.14) as a ``list Z``:
    ``[98%Z; 97%Z]``, ``[]`` for none; each a byte."""
    if not isinstance(data, (bytes, bytearray)):
        raise EmitError(f"refusing to print {data!r} as the bytes of a string")
    return "[" + "; ".join(f"{coq_z(b)}%Z" for b in data) + "]"


def coq_prim(prim: str) -> str:
    """The ``prim`` constructor of a ROS primitive type name."""
    try:
        return PRIM_CONSTRUCTORS[prim]
    except (KeyError, TypeError):
        raise EmitError(f"refusing to print {prim!r} as a primitive type") from None


def coq_path(path: FieldPath | tuple) -> str:
    """A field path as a ``NodeModel.path``: ``[PField "twist"; PIndex 35]``."""
    steps = path.steps if isinstance(path, FieldPath) else tuple(path)
    out = []
    for s in steps:
        if isinstance(s, int) and not isinstance(s, bool):
            out.append(f"PIndex {coq_z(s)}")
        else:
            out.append(f"PField {coq_ident(s, 'field name')}")
    return "[" + "; ".join(out) + "]"


def coq_ftype(f: MsgField) -> str:
    """The ``ftype`` of a carried message field."""
    if f.kind == "prim":
        base = f"FTprim {coq_prim(f.prim)}"
    elif f.kind == "msg":
        base = f"FTmsg {coq_ident(msg_c_name(_msg_name(f.msg)), 'message struct name')}"
    else:
        raise EmitError(f"refusing to print field {f.name!r} of kind {f.kind!r}")
    if f.array_len is None:
        return base
    return f"FTarray ({base}) {coq_z(f.array_len)}"


#: The largest size of a controller array (``Wellformed``'s bound).
_MAX_CTRL_ARRAY = 65536


def coq_ctrl_ftype(f) -> str:
    """The ``ftype`` of a controller field (``nm_inputs``, ``nm_outputs``):
    ``FTprim Pfloat64``, or ``FTarray (FTprim Pfloat32) 1081`` for a
    one-dimensional array (rule 4.15), of 1 to 65,536 elements."""
    base = f"FTprim {coq_prim(f.prim)}"
    size = getattr(f, "size", None)
    if size is None:
        return base
    if isinstance(size, bool) or not isinstance(size, int) or not 1 <= size <= _MAX_CTRL_ARRAY:
        raise EmitError(f"refusing to print {size!r} as the size of controller array {f.name!r}")
    return f"FTarray ({base}) {coq_z(size)}"


#: The types of a diagram's constants (``Diagram.sig_prim``) and the
#: range of each one's ``Scalar.n`` (a float's bit pattern).
_VAL_RANGES = {
    "bool": (0, 1),
    "int32": (-(1 << 31), (1 << 31) - 1),
    "uint32": (0, (1 << 32) - 1),
    "int64": (-(1 << 63), (1 << 63) - 1),
    "uint64": (0, (1 << 64) - 1),
    "float32": (0, (1 << 32) - 1),
    "float64": (0, (1 << 64) - 1),
}


def _zlit(n: int) -> str:
    """``n%Z``, a negative number in parentheses: ``(-5)%Z``."""
    return f"{coq_z(n)}%Z"


def coq_val(s: Scalar) -> str:
    """A diagram's constant as a ``Values.val``: ``Vfloat (float64_of_bits
    0x...%Z)``, ``Vsingle (float32_of_bits 0x...%Z)``, ``Vint n%Z``
    (``int32``, ``uint32``, ``bool`` 0/1), ``Vlong n%Z`` (``int64``,
    ``uint64``).  Every integer carries its ``%Z``, so the text means the
    same whichever scope is open (:mod:`pyrosgen.proof.coqdiagram`)."""
    if not isinstance(s, Scalar) or s.prim not in _VAL_RANGES or isinstance(s.n, bool) or not isinstance(s.n, int):
        raise EmitError(f"refusing to print {s!r} as a diagram constant")
    lo, hi = _VAL_RANGES[s.prim]
    if not lo <= s.n <= hi:
        raise EmitError(f"refusing to print {s!r}: out of the range of {s.prim}")
    if s.prim == "float64":
        return f"Vfloat (float64_of_bits 0x{s.n:016X}%Z)"
    if s.prim == "float32":
        return f"Vsingle (float32_of_bits 0x{s.n:08X}%Z)"
    if s.prim in ("int64", "uint64"):
        return f"Vlong {_zlit(s.n)}"
    return f"Vint {_zlit(s.n)}"


#: ``ROSGen.NodeModel.derived`` constructor of each derived input kind
#: (rule 4.12).
DERIVED_CONSTRUCTORS: dict[str, str] = {"is_new": "Dis_new", "received": "Dreceived", "age_ms": "Dage_ms"}

#: The 8- and 16-bit integer types, whose values are ``Vint`` as the
#: 32-bit ones' (``Values.val``: a C value as its type reads it, a signed
#: char holding -1 is ``Vint (-1)``).
_VINT_AS = {"int8": "int32", "int16": "int32", "uint8": "uint32", "uint16": "uint32"}


def coq_fallback(s: Scalar) -> str:
    """A fallback (rule 4.12) as a ``Values.val``, printed by the very
    helper that prints a diagram's constants (:func:`coq_val`): ``Vint
    n%Z`` for ``bool`` to ``uint32``, ``Vlong n%Z`` for the 64-bit
    integers, ``Vfloat``/``Vsingle`` of the bit pattern for the floats."""
    if isinstance(s, Scalar) and s.prim in _VINT_AS:
        s = Scalar(_VINT_AS[s.prim], s.n, s.text)
    return coq_val(s)


def coq_derived(kind: str) -> str:
    """The ``derived`` constructor of a derived input kind."""
    try:
        return DERIVED_CONSTRUCTORS[kind]
    except (KeyError, TypeError):
        raise EmitError(f"refusing to print {kind!r} as a derived input kind") from None


def _msg_name(name: str) -> str:
    if not isinstance(name, str) or not _MSG_NAME.fullmatch(name):
        raise EmitError(f"refusing to print {name!r} as a message type name")
    return name


# --------------------------------------------------------------------------
# The model as Coq literals


@dataclass(frozen=True)
class CoqMsgdef:
    """A message definition: ``comment`` (the ROS type, comment-safe),
    ``name`` (the struct name literal) and ``fields`` (pairs of literals)."""

    comment: str
    name: str
    fields: tuple[tuple[str, str], ...]


@dataclass(frozen=True)
class CoqTopic:
    """A topic as the literals of ``mktopic``."""

    comment: str
    name: str
    c_name: str
    ros_type: str   #: the ROS message type ``pkg/Type`` (``NodeModel.tp_type``)
    direction: str
    msg: str
    queue: str


@dataclass(frozen=True)
class CoqNodeModel:
    """Every part of a ``NodeModel.node_model`` record as Coq literals."""

    node: str                       #: the node name (a checked identifier, unquoted)
    name: str
    period_ms: str
    ctrl: str
    in_var: str
    in_struct: str
    inputs: tuple[tuple[str, str], ...]
    out_var: str
    out_struct: str
    outputs: tuple[tuple[str, str], ...]
    msgs: tuple[CoqMsgdef, ...]
    topics: tuple[CoqTopic, ...]
    #: (topic, path, input, comment, element path or ``None``: rule 4.15)
    inrels: tuple[tuple[str, str, str, str, str | None], ...]
    #: (output, topic, path, comment, element path or ``None``: rule 4.15)
    outrels: tuple[tuple[str, str, str, str, str | None], ...]
    timeouts: tuple[tuple[str, str], ...] = ()       #: (topic C name, ms as ``Z``)
    fallbacks: tuple[tuple[str, str, str], ...] = ()  #: (input, val, comment)
    drels: tuple[tuple[str, str, str, str], ...] = ()  #: (topic C name, kind, input, comment)
    stamps: tuple[tuple[str, str], ...] = ()          #: (topic C name, path), rule 4.13
    stamp_from: tuple[tuple[str, str, str], ...] = ()  #: (topic C name, source C name, path), rule 4.13
    #: (topic C name, path, bytes as a Coq ``list Z``, comment), rule 4.14
    strings: tuple[tuple[str, str, str, str], ...] = ()
    #: ``inrels`` as the template writes them: runs of element relations
    #: that a whole-array row stands for (``ranges.data[i] -> Scan[i]``
    #: for ``i`` from 0 to ``n - 1``, rule 4.15) as one ``map`` over
    #: ``zrange n``, the others one by one (:func:`_segments`)
    inrel_segments: tuple[tuple[str, tuple], ...] = ()
    outrel_segments: tuple[tuple[str, tuple], ...] = ()


def _msgdef(m: MsgType) -> CoqMsgdef:
    return CoqMsgdef(
        comment=coq_comment(_msg_name(m.name)),
        name=coq_ident(m.c_name, "message struct name"),
        fields=tuple((coq_ident(f.name, "message field name"), coq_ftype(f)) for f in m.fields),
    )


def emit_model(model: NodeModel) -> CoqNodeModel:
    """The model as Coq literals.

    It does not require ``model`` to be well formed (tests feed it models
    mutated past the front end's checks, to see Coq refuse them); it only
    requires every value to be printable safely.
    """
    if not isinstance(model.name, str) or not _C_IDENT.fullmatch(model.name):
        raise EmitError(f"refusing to print {model.name!r} as a node name")
    c = model.controller
    ins, outs = list(model.input_relations), list(model.output_relations)
    inrel_rows = tuple(
        (
            coq_ident(r.topic.c_name, "topic C name"),
            coq_path(r.path),
            coq_ident(r.input_field, "controller input"),
            coq_comment(f"{r.topic.name} {r.path} -> {_target(r.input_field, r.input_index)}"),
            _elem(r.input_index),
        )
        for r in ins
    )
    outrel_rows = tuple(
        (
            coq_ident(r.output_field, "controller output"),
            coq_ident(r.topic.c_name, "topic C name"),
            coq_path(r.path),
            coq_comment(f"{_target(r.output_field, r.output_index)} -> {r.topic.name} {r.path}"),
            _elem(r.output_index),
        )
        for r in outs
    )

    def in_run(r, n):
        # (topic, path prefix, input, n, comment): i ranges over zrange n
        return (coq_ident(r.topic.c_name, "topic C name"), coq_path(r.path.steps[:-1]),
                coq_ident(r.input_field, "controller input"), coq_z(n),
                coq_comment(f"{r.topic.name} {_path_text(r.path.steps[:-1])}[i] -> {r.input_field}[i], i < {n}"))

    def out_run(r, n):
        return (coq_ident(r.output_field, "controller output"), coq_ident(r.topic.c_name, "topic C name"),
                coq_path(r.path.steps[:-1]), coq_z(n),
                coq_comment(f"{r.output_field}[i] -> {r.topic.name} {_path_text(r.path.steps[:-1])}[i], i < {n}"))

    return CoqNodeModel(
        node=model.name,
        name=coq_ident(model.name, "node name"),
        period_ms=coq_z(model.period_ms),
        ctrl=coq_ident(c.name, "controller name"),
        in_var=coq_ident(c.inputs.var_name, "controller input variable"),
        in_struct=coq_ident(c.inputs.struct_name, "controller input struct"),
        inputs=tuple((coq_ident(f.name, "controller input"), coq_ctrl_ftype(f)) for f in c.inputs.fields),
        out_var=coq_ident(c.outputs.var_name, "controller output variable"),
        out_struct=coq_ident(c.outputs.struct_name, "controller output struct"),
        outputs=tuple((coq_ident(f.name, "controller output"), coq_ctrl_ftype(f)) for f in c.outputs.fields),
        msgs=tuple(_msgdef(m) for m in model.messages),
        topics=tuple(
            CoqTopic(
                comment=coq_comment(_msg_name(t.msg_type)),
                name=coq_ros_name(t.name),
                c_name=coq_ident(t.c_name, "topic C name"),
                ros_type=coq_string(_msg_name(t.msg_type), "message type name"),
                direction={"subscribe": "Subscribe", "publish": "Publish"}[_direction(t.direction)],
                msg=coq_ident(msg_c_name(_msg_name(t.msg_type)), "message struct name"),
                queue=coq_nat(t.queue_size),
            )
            for t in model.topics
        ),
        inrels=inrel_rows,
        outrels=outrel_rows,
        inrel_segments=_segments(ins, inrel_rows, _in_key, in_run),
        outrel_segments=_segments(outs, outrel_rows, _out_key, out_run),
        timeouts=tuple(
            (coq_ident(c_name, "topic C name"), f"{coq_z(ms)}%Z") for c_name, ms in model.timeouts
        ),
        fallbacks=tuple(
            (
                coq_ident(f, "controller input"),
                coq_fallback(s),
                coq_comment(f"{f} when stale: {s.text}" if s.text else f"{f} when stale"),
            )
            for f, s in model.fallbacks
        ),
        drels=tuple(
            (
                coq_ident(r.topic.c_name, "topic C name"),
                coq_derived(r.kind),
                coq_ident(r.input_field, "controller input"),
                coq_comment(f"{r.topic.name} {r.kind} -> {r.input_field}"),
            )
            for r in model.derived_relations
        ),
        stamps=tuple((coq_ident(c_name, "topic C name"), coq_path(p)) for c_name, p in model.stamps),
        stamp_from=tuple((coq_ident(c_name, "topic C name"), coq_ident(src, "topic C name"), coq_path(p))
                         for c_name, (src, p) in model.stamp_from),
        strings=tuple(
            (
                coq_ident(c_name, "topic C name"),
                coq_path(p),
                coq_bytes(data),
                coq_comment(f"{_topic_name(model, c_name)} {_path_text(p)} = {data.decode('utf-8', 'replace')}"),
            )
            for c_name, p, data in model.strings
        ),
    )


#: The shortest run of element relations printed as one ``map``.
MIN_RUN = 4


def _runs(rels, key) -> list[tuple[int, int]]:
    """Maximal runs ``(start, length)`` of ``rels`` (at least
    :data:`MIN_RUN` long) in which relation ``start + i`` has
    ``key(rel) == (k, prefix, i)`` for one ``k`` and one ``prefix``: the
    element relations of a whole array, ``prefix ++ [i] -> X[i]``, in
    index order from 0.  ``key`` gives ``None`` for a relation that is no
    element relation."""
    out = []
    i = 0
    while i < len(rels):
        k = key(rels[i])
        if k is None or k[2] != 0:
            i += 1
            continue
        j = i + 1
        while j < len(rels):
            kj = key(rels[j])
            if kj is None or kj[:2] != k[:2] or kj[2] != j - i:
                break
            j += 1
        if j - i >= MIN_RUN:
            out.append((i, j - i))
        i = j
    return out


def _elem_key(r, field: str, index):
    """The run key of a relation between element ``index`` of controller
    field ``field`` and the leaf ``r.path`` of ``r.topic``: its topic and
    field, the path without its last step, the index; ``None`` unless the
    path ends with that same index (``ranges.data[i] -> Scan[i]``)."""
    steps = r.path.steps
    if index is None or not steps or isinstance(steps[-1], bool) or steps[-1] != index:
        return None
    return ((r.topic.c_name, field), tuple(steps[:-1]), index)


def _in_key(r):
    return _elem_key(r, r.input_field, r.input_index)


def _out_key(r):
    return _elem_key(r, r.output_field, r.output_index)


def _segments(rels, rows, key, run_row) -> tuple[tuple[str, tuple], ...]:
    """``rows`` (the printed relations) cut into segments: ``("list",
    rows)`` printed one by one, ``("map", run_row(rel, n))`` for a run
    of ``n`` element relations from :func:`_runs`.  The segments
    concatenated are ``rows`` again, once Coq computes the ``map``s."""
    segs: list[tuple[str, tuple]] = []
    pos = 0
    for start, n in _runs(rels, key):
        if start > pos:
            segs.append(("list", tuple(rows[pos:start])))
        segs.append(("map", run_row(rels[start], n)))
        pos = start + n
    if pos < len(rows) or not segs:
        segs.append(("list", tuple(rows[pos:])))
    return tuple(segs)


def _elem(index) -> str | None:
    """The path inside a controller field of a relation (rule 4.15), as a
    ``NodeModel.path``: ``[PIndex 540]`` for an element, ``None`` for a
    scalar (``mkinrel``, ``mkoutrel``: the empty path)."""
    if index is None:
        return None
    if isinstance(index, bool) or not isinstance(index, int) or index < 0:
        raise EmitError(f"refusing to print {index!r} as the index of a controller array element")
    return coq_path((index,))


def _target(name: str, index) -> str:
    """A controller field or one element of it, for comments: ``Scan[540]``."""
    return name if index is None else f"{name}[{index}]"


def _topic_name(model: NodeModel, c_name: str) -> str:
    """The ROS name of the topic whose C name is ``c_name`` (for comments)."""
    return next((t.name for t in model.topics if t.c_name == c_name), c_name)


def _path_text(steps) -> str:
    return str(FieldPath(tuple(steps), "uint8"))


def _direction(d: str) -> str:
    if d not in ("subscribe", "publish"):
        raise EmitError(f"refusing to print {d!r} as a topic direction")
    return d


# --------------------------------------------------------------------------
# Rendering


def template_env() -> jinja2.Environment:
    """The project's jinja2 environment (:mod:`pyrosgen.render`), which
    also finds ``coq/templates``."""
    if not TEMPLATE_DIR.is_dir():
        raise EmitError(f"the Coq templates are missing: {TEMPLATE_DIR}")
    return environment()


@dataclass(frozen=True)
class NodeFile:
    """Names in and around the per-node Coq file of a node."""

    node: str             #: the node name
    v_file: str           #: ``<node>.v``
    types_header: str     #: ``<node>_types.h``
    glue_c: str           #: ``<node>_glue.c``
    sexp: str             #: ``<node>.sexp``
    guard: str            #: include guard of the types header
    theorem_wf: str       #: ``<node>_wf`` (T4 instance)
    theorem_ddc: str      #: ``<node>_ddc`` (T2 instance)
    theorem_target: str   #: ``<node>_ddc_target`` (T2 on the target the node was generated for)
    theorem_ctrl_wf: str  #: ``<node>_controller_wf`` (the diagram is well formed)
    theorem_e2e: str      #: ``<node>_e2e`` (T2 with the diagram as the controller)
    theorem_linked: str   #: ``<node>_linked`` (T8: the glue and the generated controller linked)
    theorem_all: str      #: ``<node>_theorems`` (their conjunction, for one ``Print Assumptions``)
    controller_c: str     #: ``<node>_controller.c`` (printed from the diagram)
    controller_sexp: str  #: ``<node>_controller.sexp``
    controller_text: str  #: ``<node>_controller.diagram`` (the proved diagram as text)


def node_file_names(node: str) -> NodeFile:
    """The file and theorem names derived from the node name."""
    if not isinstance(node, str) or not _C_IDENT.fullmatch(node):
        raise EmitError(f"refusing to use {node!r} as a node name")
    return NodeFile(
        node=node,
        v_file=f"{node}.v",
        types_header=f"{node}_types.h",
        glue_c=f"{node}_glue.c",
        sexp=f"{node}.sexp",
        guard=f"PYROSGEN_{node.upper()}_TYPES_H",
        theorem_wf=f"{node}_wf",
        theorem_ddc=f"{node}_ddc",
        theorem_target=f"{node}_ddc_target",
        theorem_ctrl_wf=f"{node}_controller_wf",
        theorem_e2e=f"{node}_e2e",
        theorem_linked=f"{node}_linked",
        theorem_all=f"{node}_theorems",
        controller_c=f"{node}_controller.c",
        controller_sexp=f"{node}_controller.sexp",
        controller_text=f"{node}_controller.diagram",
    )


#: The targets (rule 4.17) and their constructors of ``Environment.target``.
TARGETS = {"ros1": "Ros1", "ros2": "Ros2"}


def coq_target(target: str) -> str:
    """The constructor of ``Environment.target`` for ``target`` (``"ros1"`` or ``"ros2"``)."""
    if target not in TARGETS:
        raise EmitError(f"unknown target {target!r}: not one of {', '.join(sorted(TARGETS))}")
    return TARGETS[target]


def render_node_file(model: NodeModel, *, ddc_available: bool, source: str | None = None,
                     diagram: str = "", target: str = "ros1") -> str:
    """The per-node Coq file of ``model`` (``coq/templates/node.v.j2``).

    ``diagram`` is the controller's block diagram as the Coq definition
    of ``the_diagram`` (:func:`pyrosgen.proof.coqdiagram.emit_diagram`), or
    ``""`` for a controller brought in C.
    ``ddc_available`` selects the main theorem: the node DDC theorem
    ``<node>_ddc`` (T2, from ``ROSGen.DDC`` / ``ROSGen.Loopproof``) when true;
    otherwise only ``<node>_wf`` (T4's soundness instance) is proved.
    ``source`` is the model file shown in the first line (default: the
    model's file name).  ``target``: ``"ros1"`` or ``"ros2"``, the target
    the node is generated for (rule 4.17), which the file's ``target`` and
    ``<node>_ddc_target`` name.
    """
    m = emit_model(model)
    names = node_file_names(model.name)
    label = source_label(source if source is not None else Path(model.source).name)
    return template_env().get_template("node.v.j2").render(
        template=NODE_TEMPLATE,
        source=label,
        m=m,
        names=names,
        guard=coq_string(names.guard, "include guard"),
        ddc_available=bool(ddc_available),
        diagram=diagram,
        target=coq_target(target),
    )


def render_model_definitions(models: list[tuple[str, NodeModel]]) -> str:
    """Coq definitions ``<def>_msgs : list msgdef`` and ``<def> : node_model``
    for each ``(def, model)`` (``coq/templates/models.v.j2``), for files that
    check several models at once (the agreement tests)."""
    defs = []
    for name, model in models:
        if not _C_IDENT.fullmatch(name) or "__" in name:
            raise EmitError(f"refusing to use {name!r} as a Coq definition name")
        defs.append((name, emit_model(model)))
    return template_env().get_template("models.v.j2").render(defs=defs)

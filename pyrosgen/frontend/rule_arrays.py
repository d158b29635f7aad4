"""Rule 4.15, controller arrays: a relation between a whole array of a
message (a carried variable-length array of primitives, a carried string's
bytes, or a fixed-size array of primitives) and a whole controller array of
as many elements of the same type, expanded into one relation per element.
"""

from __future__ import annotations

from dataclasses import dataclass

from pyrosgen.errors import show
from pyrosgen.frontend.checker import Checker, Rel
from pyrosgen.frontend.model import ControllerField
from pyrosgen.frontend.msgload import BoundedTarget, MsgRegistry, PathError
from pyrosgen.frontend.msgmodel import FieldPath


def whole_array_row(ck: Checker, rel: Rel, ptext: str, registry: MsgRegistry, kind: str,
                    cf: ControllerField) -> None:
    """Rule 4.15: a relation between field ``ptext`` of its topic's
    message and the whole controller array ``cf`` (``kind``: ``input``
    or ``output``).  The field must be a whole array of as many
    elements of the same type: a carried variable-length array of
    primitives or string whose maximum is the controller array's size,
    or a fixed-size array of primitives of that size.  Sets the row's
    elements (each a relation on one leaf) or reports why not."""
    w, topic, msg_type = rel.what, rel.topic.name, rel.topic.msg_type
    arr = whole_array(registry, msg_type, ptext)
    if arr is None:
        try:
            leaf = registry.walk_path(msg_type, ptext, bounded=True, writes=kind == "output")
        except PathError:
            raise  # reported by the caller, as for any path
        ck.err_rule("4.15", rel.node,
                    f"{w}: controller {kind} {show(cf.name)} is an array ({cf.type_text}) but field "
                    f"{show(ptext)} of topic {show(topic)} is one {leaf.prim}: relate a whole array of "
                    f"{cf.size} {cf.prim} to it, or the field to one element ({show(cf.name + '[0]')})")
        rel.ok = False
        if kind == "output":
            rel.bounded = registry.bounded_in_path(msg_type, ptext)
        return
    rel.bounded = arr.target
    if arr.prim != cf.prim or arr.size != cf.size:
        field_ = f"field {show(ptext)} of topic {show(topic)} is {arr.type_text}"
        ctrl_ = f"controller {kind} {show(cf.name)} is {cf.type_text}"
        first, second = (field_, ctrl_) if kind == "input" else (ctrl_, field_)
        if arr.prim != cf.prim and arr.kind == "string":
            why = "a string meets a controller array as its bytes, uint8"
        elif arr.prim != cf.prim:
            why = "the element types differ (relations never convert)"
        elif arr.kind == "fixed":
            why = "the sizes differ"
        else:
            key = _max_length_key(registry, msg_type, ptext)
            why = (f"the sizes differ: give the field max_length {cf.size} on the topic "
                   f"(max_length: {{{key}: {cf.size}}}), or declare {cf.name} {cf.prim}[{arr.size}]")
        ck.err_rule("4.15", rel.node, f"{w}: {first} but {second}: {why}")
        rel.ok = False
        return
    rel.elements = [(arr.element(i), i, None if arr.kind == "fixed" else f"{ptext}[{i}]")
                    for i in range(arr.size)]
    rel.path = rel.elements[0][0]
    rel.row = (ptext, cf.name)


@dataclass(frozen=True)
class _WholeArray:
    """A whole array of a message that a relation relates to a controller
    array (rule 4.15): ``kind`` ``seq`` (a carried variable-length array
    of primitives), ``string`` (a carried string, its bytes) or ``fixed``
    (a fixed-size array of primitives); ``steps`` from the message to the
    field, ``prim`` its element type, ``size`` its maximum (``seq``,
    ``string``) or size (``fixed``), ``target`` the bounded field
    (``None`` for ``fixed``)."""

    kind: str
    steps: tuple[str | int, ...]
    prim: str
    size: int
    target: BoundedTarget | None = None

    def element(self, i: int) -> FieldPath:
        """The leaf of element ``i``: ``ranges.data[i]``, ``covariance[i]``."""
        if self.kind == "fixed":
            return FieldPath((*self.steps, i), self.prim)
        return FieldPath((*self.steps, "data", i), self.prim)

    @property
    def type_text(self) -> str:
        """The field's type, read aloud: ``float32[] of at most 8``,
        ``a string of at most 16 bytes``, ``float64[36]``."""
        if self.kind == "fixed":
            return f"{self.prim}[{self.size}]"
        if self.kind == "string":
            return f"a string of at most {self.size} bytes (uint8)"
        return f"{self.prim}[] of at most {self.size}"


def whole_array(registry: MsgRegistry, msg_type: str, text: object) -> _WholeArray | None:
    """The whole array that field path ``text`` of ``msg_type`` names, if
    it names one a controller array can be related to (rule 4.15): a
    carried variable-length array of primitives or string (through nested
    messages and fixed-size arrays of messages), or a fixed-size array of
    primitives; ``None`` otherwise (nothing is reported)."""
    try:
        t = registry.walk_bounded(msg_type, text, "a relation to a controller array")
    except PathError:
        t = None
    if t is not None and t.seq_of is not None:
        return None  # an array of messages or strings: no controller array holds it
    if t is not None:
        n = registry.capacity(*t.key)
        if n is None:  # pragma: no cover - the front end carries what relations name
            return None
        return _WholeArray("string" if t.is_string else "seq", t.steps, "uint8" if t.is_string else t.elem, n, t)
    if not isinstance(text, str) or text.endswith("]"):
        return None
    try:
        p = registry.walk_path(msg_type, f"{text}[0]")
    except PathError:
        return None
    steps = p.steps[:-1]
    cur, f = registry.raw(msg_type), None
    for s in steps:
        if isinstance(s, int):
            continue
        f = cur.field(s) if cur is not None else None
        if f is None:  # pragma: no cover - walk_path resolved it
            return None
        if f.base_kind == "msg":
            cur = registry.raw(f.base)
    if f is None or f.card != "array" or f.base_kind != "prim":
        return None
    return _WholeArray("fixed", tuple(steps), p.prim, f.size)


def _max_length_key(registry: MsgRegistry, msg_type: str, text: str) -> str:
    """The ``max_length`` key of the field that path ``text`` names: the
    path itself, but with ``[]`` for the element of each variable-length
    array of messages or strings it goes through (``name[0]`` gives
    ``"name[]"``, rule 4.15), quoted when it holds brackets."""
    from pyrosgen.frontend.msgload import parse_path

    cur, parts = registry.raw(msg_type), []
    for fname, index in parse_path(text, extended=True):
        f = cur.field(fname) if cur is not None else None
        if f is not None and f.card == "sequence" and f.base_kind in ("msg", "string") and index is not None:
            parts.append(f"{fname}[]")
        else:
            parts.append(fname if index is None else f"{fname}[{index}]")
        cur = registry.raw(f.base) if f is not None and f.base_kind == "msg" else None
    key = ".".join(parts)
    return f'"{key}"' if "[" in key else key

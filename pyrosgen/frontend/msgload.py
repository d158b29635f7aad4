"""Loading ROS 1 message types: the message LOADER.

Definitions come from ``rosbags`` (its ROS 1 Noetic store) and from custom
``<pkg>/msg/<Type>.msg`` files in the model's ``msg_paths``.  This module
turns them into the *carried* view that the generators use:

- primitive fields (``bool``, ``int8`` .. ``uint64``, ``float32``,
  ``float64``; the ROS 1 aliases ``char`` and ``byte`` become ``uint8`` and
  ``int8``) and fixed-size arrays of them are carried;
- nested messages and fixed-size arrays of messages are carried when the
  nested message carries at least one field;
- ``time`` and ``duration`` are the pseudo message types :data:`TIME` and
  :data:`DURATION` (``sec``/``nsec``, 32-bit);
- a ``string`` field is carried, as the bounded struct ``ros_string<N>``
  (:func:`~pyrosgen.frontend.msgmodel.string_type`), exactly when the
  model gives it a constant (rule 4.14) or an input relation reads it
  (rule 4.15): :attr:`MsgRegistry.carry_bounded` names it by its message
  type and field name, with its capacity ``N``; every other string is
  dropped;
- a variable-length array ``T[]`` of a primitive ``T`` is carried, as the
  bounded struct ``ros_seq_<T>_<N>``
  (:func:`~pyrosgen.frontend.msgmodel.seq_type`), exactly when an input
  relation reads it (rule 4.15, :attr:`MsgRegistry.carry_bounded`);
- a variable-length array of messages ``T[]`` or of strings is carried
  the same way, as ``ros_seq_<pkg>_<Type>_<N>`` or
  ``ros_seq_string<M>_<N>`` (:func:`~pyrosgen.frontend.msgmodel.seq_elem_type`),
  whose ``data`` is an array of the element's carried struct (the key
  ``(type, 'name[]')`` of :attr:`MsgRegistry.carry_bounded` holds the
  element strings' ``M``);
- every other variable-length (or bounded) array, fixed-size arrays of
  strings and fields of other base types are dropped.

It also resolves field paths such as ``pose.covariance[35]`` against the
original definitions, so that naming a dropped field is reported with the
reason it is not carried.
"""

from __future__ import annotations

import dataclasses
import re
from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path

from pyrosgen.errors import Diagnostic, InvalidNodeModel, show
from pyrosgen.frontend.names import did_you_mean, identifier_problem
from pyrosgen.frontend.msgmodel import (
    FieldPath,
    MAX_MSG_DEPTH,
    MAX_MSG_FILES,
    MsgField,
    MsgType,
    PRIMITIVES,
    ROS1_ALIASES,
    DEFAULT_MAX_LENGTH,
    _PSEUDO,
    bounded_type,
    is_bounded_type,
    leaf_paths,
    msg_c_name,
    seq_msg_type_name,
    seq_string_type_name,
    seq_type_name,
    string_type_name,
)

__all__ = [
    "MsgRegistry",
    "PathError",
    "StringPathError",
    "StringTarget",
    "BoundedPathError",
    "BoundedTarget",
]

# --------------------------------------------------------------------------
# Original definitions (before dropping)


@dataclass(frozen=True)
class _RawField:
    """A field as defined: ``base_kind`` is ``prim``, ``string``, ``msg`` or
    ``unsupported``; ``card`` is ``scalar``, ``array`` or ``sequence``."""

    name: str
    base_kind: str
    base: str
    card: str
    size: int
    line: int | None = None
    col: int | None = None

    def type_text(self) -> str:
        """The type as a ``.msg`` file writes it (ROS 1 style)."""
        t = self.base
        if self.card == "array":
            return f"{t}[{self.size}]"
        if self.card == "sequence":
            return f"{t}[<={self.size}]" if self.size else f"{t}[]"
        return t


@dataclass(frozen=True)
class _RawMsg:
    """A message definition as written; ``file`` is set for custom types."""

    name: str
    fields: tuple[_RawField, ...]
    file: str | None = None

    def field(self, name: str) -> _RawField | None:
        for f in self.fields:
            if f.name == name:
                return f
        return None


_RAW_PSEUDO = {
    "time": _RawMsg(
        "time",
        (_RawField("sec", "prim", "uint32", "scalar", 0), _RawField("nsec", "prim", "uint32", "scalar", 0)),
    ),
    "duration": _RawMsg(
        "duration",
        (_RawField("sec", "prim", "int32", "scalar", 0), _RawField("nsec", "prim", "int32", "scalar", 0)),
    ),
}

#: rosbags gives ROS 2-style names; these are ROS 1's ``time``/``duration``.
_ROSBAGS_PSEUDO = {
    "builtin_interfaces/msg/Time": "time",
    "builtin_interfaces/msg/Duration": "duration",
}

# rosbags fills empty messages with this ROS 2 placeholder; ROS 1 has none.
_PLACEHOLDER = "structure_needs_at_least_one_member"


def _ros1_name(name: str) -> str:
    """``pkg/msg/Type`` to ``pkg/Type`` (and the time/duration pseudo names)."""
    if name in _ROSBAGS_PSEUDO:
        return _ROSBAGS_PSEUDO[name]
    parts = name.split("/")
    if len(parts) == 3 and parts[1] in ("msg", "action"):
        return f"{parts[0]}/{parts[2]}"
    return name


def _convert_field(fname: str, desc, line=None, col=None) -> _RawField:
    from rosbags.interfaces import Nodetype

    nodetype, payload = desc
    card, size = "scalar", 0
    if nodetype in (Nodetype.ARRAY, Nodetype.SEQUENCE):
        card = "array" if nodetype == Nodetype.ARRAY else "sequence"
        (nodetype, payload), size = payload
    if nodetype == Nodetype.BASE:
        base, _bound = payload
        if base == "string":
            return _RawField(fname, "string", "string", card, size, line, col)
        base = ROS1_ALIASES.get(base, base)
        if base in PRIMITIVES:
            return _RawField(fname, "prim", base, card, size, line, col)
        return _RawField(fname, "unsupported", base, card, size, line, col)
    return _RawField(fname, "msg", _ros1_name(payload), card, size, line, col)


def _convert_fielddefs(fielddefs) -> dict[str, _RawMsg]:
    out = {}
    for name, (_consts, fields) in fielddefs.items():
        r1 = _ros1_name(name)
        if r1 in _RAW_PSEUDO or "/" not in r1:
            continue
        if len(fields) == 1 and fields[0][0] == _PLACEHOLDER:
            fields = []
        out[r1] = _RawMsg(r1, tuple(_convert_field(n, d) for n, d in fields))
    return out


_STANDARD: dict[str, _RawMsg] | None = None


def _standard_defs() -> dict[str, _RawMsg]:
    """The ROS 1 Noetic definitions shipped with rosbags (read once)."""
    global _STANDARD
    if _STANDARD is None:
        from rosbags.typesys import Stores, get_typestore

        _STANDARD = _convert_fielddefs(get_typestore(Stores.ROS1_NOETIC).fielddefs)
    return _STANDARD


# --------------------------------------------------------------------------
# Custom .msg files

_PKG_RE = re.compile(r"[a-z][a-z0-9_]*")
_TYPE_RE = re.compile(r"[A-Za-z][A-Za-z0-9]*")
_FIELD_LINE_RE = re.compile(r"\s*([A-Za-z0-9_/\[\]<=]+)\s+([A-Za-z][A-Za-z0-9_]*)\s*(?:#.*)?")
_TYPE_NAME_RE = re.compile(r"([a-z][a-z0-9_]*)/([A-Za-z][A-Za-z0-9]*)")


class PathError(Exception):
    """A field path that does not name a carried leaf (message in ``args[0]``)."""


class StringPathError(PathError):
    """A relation's field path that names a ``string`` field or goes inside
    one: strings never meet the controller (rule 4.14)."""


class BoundedPathError(PathError):
    """A field path that names a variable-length array or a string in a
    way rule 4.15 refuses (a whole sequence, an index past its maximum, a
    sequence of messages or strings, a path inside its C struct)."""


@dataclass(frozen=True)
class BoundedTarget:
    """A variable-length array of a primitive type or a ``string`` field
    (rule 4.15): ``steps`` from the topic's message to the field (names
    and constant indices), ``owner`` the message type that defines the
    field, ``field`` its name, ``elem`` its element type (a primitive, or
    ``'string'``)."""

    steps: tuple[str | int, ...]
    owner: str
    field: str
    elem: str
    #: a variable-length array of messages (``'msg'``, ``elem`` the
    #: element's type) or of strings (``'string'``), rule 4.15; ``None``
    #: for an array of primitives or a string.  The strings of an array of
    #: strings are the target ``field`` ``name[]`` (``elem`` ``'string'``)
    seq_of: str | None = None
    #: the path reaches it through an element of a variable-length array
    #: (``poses[2].header.frame_id``, ``name[0]``)
    in_element: bool = False
    #: the path to it as a model writes it (``poses[2].header.frame_id``);
    #: set by :meth:`MsgRegistry.bounded_along`
    shown: str = ""

    @property
    def key(self) -> tuple[str, str]:
        """``(owner, field)``: the field of its message type, which one
        bounded struct holds in every topic of the type (``(owner,
        'name[]')``: the strings of the array of strings ``name``)."""
        return (self.owner, self.field)

    @property
    def is_string(self) -> bool:
        return self.elem == "string" and self.seq_of is None


@dataclass(frozen=True)
class StringTarget:
    """A ``string`` field named by a constant (rule 4.14): ``steps`` from
    the topic's message to the field (names and constant indices),
    ``owner`` the message type that defines the field, ``field`` its name."""

    steps: tuple[str | int, ...]
    owner: str
    field: str


@dataclass
class MsgRegistry:
    """The message definitions one model can use: the standard ROS 1 Noetic
    set plus the custom types found in its ``msg_paths``.

    Problems in custom ``.msg`` files are appended to ``diagnostics``.
    """

    diagnostics: list[Diagnostic] = field(default_factory=list)
    custom: dict[str, _RawMsg] = field(default_factory=dict)
    _carried: dict[str, MsgType | None] = field(default_factory=dict)
    _broken: set[str] = field(default_factory=set)
    _typestore: object = None
    failed: set[str] = field(default_factory=set)
    #: the ``string`` fields and variable-length arrays of primitives that
    #: are carried (rules 4.14, 4.15), as (message type, field name) ->
    #: capacity: those the model's constants and input relations name
    carry_bounded: dict[tuple[str, str], int] = field(default_factory=dict)
    #: those of ``carry_bounded`` with policy reject (rule 4.15,
    #: ``policy``): carried as ``ros_rseq_<T>_<N>`` / ``ros_rstring<N>``
    carry_reject: frozenset[tuple[str, str]] = frozenset()
    #: the standard definitions (``pkg/Type`` -> definition) of the target:
    #: ``None`` for ROS 1 Noetic's (rosbags); the ROS 2 target (rule 4.17)
    #: sets ROS 2's, read from the installed wheels (pyrosgen.ros2.msgdefs)
    standard: dict[str, _RawMsg] | None = None

    def _standard(self) -> dict[str, _RawMsg]:
        return self.standard if self.standard is not None else _standard_defs()

    @property
    def carry_strings(self) -> frozenset[tuple[str, str]]:
        """The carried fields (strings and sequences alike), as (message
        type, field name) pairs."""
        return frozenset(self.carry_bounded)

    def set_carried_strings(self, fields) -> None:
        """Carry the ``string`` fields ``fields`` ((message type, field
        name) pairs) with the default capacity, and forget the carried
        views computed so far."""
        self.set_carried({f: DEFAULT_MAX_LENGTH for f in fields})

    def set_carried(self, fields: dict[tuple[str, str], int], reject=frozenset()) -> None:
        """Carry the strings and variable-length arrays ``fields``
        ((message type, field name) -> capacity), those of ``reject`` with
        policy reject, and forget the carried views computed so far."""
        self.carry_bounded = dict(fields)
        self.carry_reject = frozenset(k for k in reject if k in self.carry_bounded)
        self._carried.clear()
        self._broken.clear()

    def capacity(self, owner: str, field_name: str) -> int | None:
        """The capacity of carried string or sequence ``field_name`` of
        ``owner``, or ``None`` when it is not carried."""
        return self.carry_bounded.get((owner, field_name))

    # -- loading -----------------------------------------------------------

    def add_msg_dir(self, folder: Path) -> int:
        """Read every ``<pkg>/msg/<Type>.msg`` under ``folder``; return how many."""
        files = sorted(folder.glob("*/msg/*.msg"))
        if len(files) + len(self.custom) > MAX_MSG_FILES:
            raise InvalidNodeModel(
                [Diagnostic(str(folder), None, None, f"more than {MAX_MSG_FILES} .msg files", rule="4.5")]
            )
        for f in files:
            self._add_msg_file(f)
        return len(files)

    def _diag(self, file, line, col, message) -> None:
        self.diagnostics.append(Diagnostic(_display(file), line, col, message, rule="4.5"))

    def _add_msg_file(self, path: Path) -> None:
        from pyrosgen.frontend.yamlsrc import read_text

        pkg, typ = path.parent.parent.name, path.stem
        if not _PKG_RE.fullmatch(pkg) or "__" in pkg:
            self._diag(path, None, None, f"package name {show(pkg)} is not a ROS package name (lower-case letters, digits and '_', starting with a letter)")
            return
        if not _TYPE_RE.fullmatch(typ):
            self._diag(path, None, None, f"message name {show(typ)} is not a ROS message name (letters and digits, starting with a letter)")
            return
        name = f"{pkg}/{typ}"
        try:
            text = read_text(path, what="message definition", rule="4.5", regular_only=True)
        except InvalidNodeModel as exc:
            for d in exc.diagnostics:
                self._diag(path, d.line, d.col, d.message)
            self.failed.add(name)
            return
        defs = self._parse_msg(path, text, f"{pkg}/msg/{typ}")
        if defs is None or not self._check_ros1_lines(path, text):
            self.failed.add(name)
            return
        if name in self.custom:
            prev = self.custom[name]
            self._diag(path, None, None, f"message type {name} is defined twice (also in {prev.file})")
            return
        _consts, fields = defs[f"{pkg}/msg/{typ}"]
        lines = _field_lines(text)
        raw = []
        seen: dict[str, int] = {}
        for fname, desc in fields:
            occurrence = seen.get(fname, 0)
            seen[fname] = occurrence + 1
            places = lines.get(fname, [])
            line, col = places[occurrence] if occurrence < len(places) else (None, None)
            if occurrence:
                self._diag(path, line, col, f"field {show(fname)} is defined twice in {name}")
                continue
            f = _convert_field(fname, desc, line, col)
            if self.standard is not None and f.base in _RAW_PSEUDO:
                # the target ROS 2 (rule 4.17): rosbags reads builtin_interfaces/Time as ROS 1's
                # time; ROS 2's is the message (int32 sec, uint32 nanosec)
                f = dataclasses.replace(f, base=f"builtin_interfaces/{f.base.capitalize()}")
            raw.append(f)
        if any(n > 1 for n in seen.values()):
            self.failed.add(name)
            return
        try:
            self._store().register(defs)
        except Exception as exc:  # noqa: BLE001 - rosbags raises several kinds
            reason = " ".join(str(exc).split())
            if "already present with different definition" in reason:
                reason = f"{name} is already defined differently (a standard ROS type or another msg_paths folder)"
            self._diag(path, 1, 1, f"cannot register message type {name}: {reason}")
            self.failed.add(name)
            return
        self.custom[name] = _RawMsg(name, tuple(raw), _display(path))

    def _check_ros1_lines(self, path: Path, text: str) -> bool:
        """Refuse what rosbags accepts but ROS 1 does not (field defaults)."""
        for i, line in enumerate(text.split("\n"), start=1):
            code = line.split("#", 1)[0].strip()
            if not code or "=" in code.replace("<=", ""):
                continue
            if not _FIELD_LINE_RE.fullmatch(line.rstrip("\r")):
                self._diag(
                    path,
                    i,
                    1,
                    f"cannot parse message definition line {show(line.strip())} "
                    "(a ROS 1 field is TYPE NAME, a constant TYPE NAME=VALUE)",
                )
                return False
        return True

    def _store(self):
        if self._typestore is None:
            from rosbags.typesys import Stores, get_typestore

            self._typestore = get_typestore(Stores.ROS1_NOETIC)
        return self._typestore

    def _parse_msg(self, path: Path, text: str, rname: str):
        from rosbags.typesys import get_types_from_msg

        try:
            defs = get_types_from_msg(text, rname)
        except Exception:  # noqa: BLE001 - TypesysError and parser failures
            line = _first_bad_line(text, rname)
            bad = text.split("\n")[line - 1].strip() if line else ""
            self._diag(
                path,
                line,
                1,
                f"cannot parse message definition line {show(bad)} "
                "(a ROS 1 field is TYPE NAME, a constant TYPE NAME=VALUE)",
            )
            return None
        if list(defs) != [rname]:
            self._diag(path, 1, 1, "a .msg file must define exactly one message (no '====' separators)")
            return None
        return defs

    # -- lookups ------------------------------------------------------------

    def raw(self, name: str) -> _RawMsg | None:
        """The definition of ``name`` (``pkg/Type``, ``time`` or ``duration``)."""
        if name in _RAW_PSEUDO:
            return _RAW_PSEUDO[name]
        if name in self.custom:
            return self.custom[name]
        return self._standard().get(name)

    def known_names(self) -> list[str]:
        """All ``pkg/Type`` names available."""
        return sorted(set(self._standard()) | set(self.custom))

    def check_type_name(self, name: str) -> str | None:
        """Why ``name`` does not name a known message type, or ``None``."""
        if not isinstance(name, str) or not _TYPE_NAME_RE.fullmatch(name):
            hint = ""
            if isinstance(name, str):
                parts = name.split("/")
                if len(parts) == 3 and parts[1] == "msg":
                    hint = f" (did you mean {show(parts[0] + '/' + parts[2])}?)"
                elif len(parts) == 1 and parts[0]:
                    cands = [n for n in self.known_names() if n.split("/")[1] == parts[0]]
                    if cands:
                        hint = f" (did you mean {show(cands[0])}?)"
            return f"message type {show(name)} is not of the form package/Type{hint}"
        if self.raw(name) is None:
            return f"unknown message type {show(name)}{did_you_mean(name, self.known_names())}"
        return None

    # -- carried view -------------------------------------------------------

    def carried(self, name: str, _stack: tuple[str, ...] = ()) -> MsgType | None:
        """The carried view of ``name``; ``None`` when it carries nothing or is
        broken (see :meth:`is_broken`; the problem is in ``diagnostics``)."""
        if name in _PSEUDO:
            return _PSEUDO[name]
        if is_bounded_type(name):
            return bounded_type(name)
        if name in self._carried:
            return self._carried[name]
        raw = self.raw(name)
        if raw is None:  # reported by the caller, which knows where
            self._broken.add(name)
            return None
        fields = []
        broken = False
        for f in raw.fields:
            if f.base_kind == "msg":
                if f.base in _stack or f.base == name:
                    cycle = " -> ".join((*_stack, name, f.base))
                    self._report(raw, f, f"message type {name} contains itself ({cycle})")
                    broken = True
                    continue
                if f.base in self.failed:
                    broken = True  # its own .msg file is reported
                    continue
                if self.raw(f.base) is None:
                    self._report(raw, f, f"field {show(f.name)} of {name} has unknown message type {show(f.base)}{did_you_mean(f.base, self.known_names())}")
                    broken = True
                    continue
                if len(_stack) + 1 >= MAX_MSG_DEPTH:
                    self._report(raw, f, f"message types nested more than {MAX_MSG_DEPTH} levels deep (field {show(f.name)} of {name})")
                    broken = True
                    continue
                sub = self.carried(f.base, (*_stack, name))
                if f.base in self._broken:
                    broken = True
                    continue
                if f.card == "sequence" and sub is not None and (name, f.name) in self.carry_bounded:
                    mf = MsgField(f.name, "msg", msg=seq_msg_type_name(f.base, self.carry_bounded[(name, f.name)],
                                                                     (name, f.name) in self.carry_reject))
                elif sub is None or f.card == "sequence" or (f.card == "array" and f.size == 0):
                    continue
                else:
                    mf = MsgField(f.name, "msg", msg=f.base, array_len=f.size if f.card == "array" else None)
            elif f.base_kind == "prim":
                if f.card == "sequence" and (name, f.name) in self.carry_bounded:
                    mf = MsgField(f.name, "msg", msg=seq_type_name(f.base, self.carry_bounded[(name, f.name)],
                                                                    (name, f.name) in self.carry_reject))
                elif f.card == "sequence" or (f.card == "array" and f.size == 0):
                    continue
                else:
                    mf = MsgField(f.name, "prim", prim=f.base, array_len=f.size if f.card == "array" else None)
            elif f.base_kind == "string" and f.card == "scalar" and (name, f.name) in self.carry_bounded:
                mf = MsgField(f.name, "msg", msg=string_type_name(self.carry_bounded[(name, f.name)],
                                                                (name, f.name) in self.carry_reject))
            elif f.base_kind == "string" and f.card == "sequence" and (name, f.name) in self.carry_bounded:
                elem_n = self.carry_bounded.get((name, f.name + "[]"), DEFAULT_MAX_LENGTH)
                mf = MsgField(f.name, "msg", msg=seq_string_type_name(elem_n, self.carry_bounded[(name, f.name)],
                                                                    (name, f.name) in self.carry_reject))
            else:
                continue
            if raw.file is not None:
                problem = identifier_problem(f.name)
                if problem:
                    self._report(raw, f, f"field name {show(f.name)} of {name} cannot be used in generated code: {problem}")
                    broken = True
                    continue
            fields.append(mf)
        if broken:
            self._broken.add(name)
            self._carried[name] = None
            return None
        result = MsgType(name, msg_c_name(name), tuple(fields)) if fields else None
        self._carried[name] = result
        return result

    def is_broken(self, name: str) -> bool:
        """Whether ``name`` (or a type it contains) has a reported problem."""
        return name in self._broken

    def _report(self, raw: _RawMsg, f: _RawField, message: str) -> None:
        if raw.file is not None:
            d = Diagnostic(raw.file, f.line, f.col, message, rule="4.5")
            if d not in self.diagnostics:
                self.diagnostics.append(d)

    def messages(self) -> dict[str, MsgType]:
        """All carried types computed so far, by name."""
        return {k: v for k, v in self._carried.items() if v is not None}

    def used_types(self, roots: Iterable[str]) -> tuple[MsgType, ...]:
        """The carried types reachable from ``roots``, each after the types
        it contains (dependency order)."""
        order: list[MsgType] = []
        done: set[str] = set()

        def visit(name: str) -> None:
            if name in done:
                return
            done.add(name)
            t = self.carried(name)
            if t is None:
                return
            for f in t.fields:
                if f.kind == "msg":
                    visit(f.msg)
            order.append(t)

        for r in roots:
            visit(r)
        return tuple(order)

    # -- field paths ----------------------------------------------------------

    def walk_path(self, type_name: str, text: object, *, bounded: bool = False,
                  writes: bool = False) -> FieldPath:
        """Resolve field path ``text`` in message type ``type_name`` to a
        carried scalar leaf; raises :class:`PathError` saying why not.

        With ``bounded`` (a relation, rule 4.15), an element of a carried
        variable-length array of primitives (``ranges[540]``) or a byte of
        a carried string (``header.frame_id[0]``) is a leaf: the element
        ``data[540]`` of its bounded struct, within its capacity
        (``writes``: an output relation's, which the messages say).
        Without it, a path into a variable-length array is refused as rule
        4.15 says."""
        steps = parse_path(text, extended=bounded)
        cur = self.raw(type_name)
        assert cur is not None
        out: list[str | int] = []
        shown = ""
        for i, (fname, index) in enumerate(steps):
            last = i == len(steps) - 1
            step = steps[i]
            f, shown = _field_step(cur, text, fname, shown)
            out.append(fname)
            if step.any:
                raise BoundedPathError(
                    f"field path {show(text)}: {show(shown + '[]')}: a relation names one element with a "
                    f"constant index ({show(shown + '[0]')}); [] (every element) is for max_length and policy keys")
            if f.card == "sequence" and f.base_kind in ("msg", "string") and bounded:
                nxt_name = steps[i + 1][0] if not last else None
                leaf = self._element_step(text, cur, f, step, nxt_name, out, shown, writes)
                if leaf is not None:
                    return leaf
                shown = f"{shown}[{index}]"
                cur = self.raw(f.base)
                assert cur is not None
                continue
            if step.more:
                raise BoundedPathError(
                    f"field path {show(text)}: {show(shown + f'[{index}]')} is not an array "
                    f"({show(shown)} is {_article(f.base)} {f.type_text()}), it cannot be indexed again")
            if f.card == "sequence" or (bounded and f.base_kind == "string" and f.card == "scalar"):
                nxt_name = steps[i + 1][0] if not last else None
                return self._bounded_leaf(text, cur, f, index, nxt_name, tuple(out), shown, bounded, writes)
            shown = _index_step(text, steps, i, f, index, shown, out)
            if f.base_kind == "string":
                raise StringPathError(
                    f"field path {show(text)}: {show(shown)} is a string; "
                    "strings are not carried by the glue to or from the controller (a published "
                    "topic gives a string field a constant with its frame_id or strings key)"
                )
            if f.base_kind == "unsupported":
                raise PathError(
                    f"field path {show(text)}: {show(shown)} has type {f.base}, "
                    "which the glue does not carry"
                )
            if f.base_kind == "prim":
                if not last:
                    raise PathError(
                        f"field path {show(text)}: {show(shown)} is {_article(f.base)} "
                        f"{f.base}, it has no field {show(steps[i + 1][0])}"
                    )
                return FieldPath(tuple(out), f.base)
            # a nested message
            sub = self.carried(f.base)
            if last:
                example = ""
                leaf = _ros_leaf(sub, self.messages()) if sub is not None else None
                if leaf is not None:
                    example = f"; name one of its leaf fields, e.g. {show(shown + '.' + str(leaf))}"
                raise PathError(
                    f"field path {show(text)}: {show(shown)} is a whole sub-message "
                    f"({f.base}), not a leaf field{example}"
                )
            if sub is None:
                raise PathError(
                    f"field path {show(text)}: {show(shown)} ({f.base}) carries no field "
                    "(strings and variable-length arrays are not carried by the glue)"
                )
            nxt = self.raw(f.base)
            assert nxt is not None
            cur = nxt
        raise PathError(f"field path {show(text)} is empty")  # pragma: no cover

    def _element_step(self, text: object, cur: _RawMsg, f: _RawField, step, nxt: str | None,
                      out: list[str | int], shown: str, writes: bool) -> FieldPath | None:
        """One step of :meth:`walk_path` into ``f``, a variable-length
        array of messages or strings of ``cur`` (rule 4.15), written
        ``step`` (its index, and a second one for a string's byte), ``nxt``
        the next step's name: appends ``data`` and the element's index to
        ``out``; returns the leaf when the path ends in the element (a byte
        of an element string), ``None`` when it goes on into an element
        message; raises :class:`PathError` saying why not."""
        ftype = f.type_text()
        string = f.base_kind == "string"
        what = f"a variable-length array of {'strings' if string else 'messages'} ({ftype})"
        index = step[1]
        if index is None:
            example = f"{shown}[0]" + ("[0]" if string else "." + (nxt or "<field>"))
            raise BoundedPathError(
                f"field path {show(text)}: {show(shown)} is {what}; "
                + ("an output relation writes " if writes else "a relation reads ")
                + ("a byte of one of its strings" if string else "a leaf of one of its elements")
                + f" ({show(example)}) or its length "
                + ("(derived: length)" if writes else "or whether it was truncated (derived: length, "
                   "derived: truncated)"))
        self._check_index(text, cur, f, index, shown, what, "elements")
        out += ["data", index]
        shown_i = f"{shown}[{index}]"
        if not string:
            if step.more:
                raise BoundedPathError(
                    f"field path {show(text)}: {show(shown_i)} is a message ({f.base}), not an array: "
                    "it cannot be indexed again")
            if nxt is None:
                sub = self.carried(f.base)
                leaf = _ros_leaf(sub, self.messages()) if sub is not None else None
                example = f"; name one of its leaf fields, e.g. {show(shown_i + '.' + str(leaf))}" if leaf else ""
                raise BoundedPathError(
                    f"field path {show(text)}: {show(shown_i)} is a whole element ({f.base}) of {show(shown)}, "
                    f"not a leaf field{example}")
            if self.carried(f.base) is None:
                raise BoundedPathError(
                    f"field path {show(text)}: the elements of {show(shown)} ({f.base}) carry no field")
            return None
        m = self.capacity(cur.name, f.name + "[]") or DEFAULT_MAX_LENGTH
        if not step.more:
            if nxt is None:
                raise BoundedPathError(
                    f"field path {show(text)}: {show(shown_i)} is a string (an element of {what}); "
                    + ("an output relation writes" if writes else "a relation reads")
                    + f" one of its bytes ({show(shown_i + '[0]')}, a uint8) or its length (derived: length), "
                    "or relates it whole to a uint8 controller array")
            raise BoundedPathError(
                f"field path {show(text)}: {show(shown_i)} is a string; a path does not go inside it "
                f"({show(nxt)}: len, truncated and data are fields of its C struct, not of the ROS message); "
                f"name one of its bytes ({show(shown_i + '[0]')}) or use derived: length")
        if len(step.more) > 1:  # pragma: no cover - parse_path takes two indices at most
            raise BoundedPathError(f"field path {show(text)}: too many indices after {show(shown)}")
        j = step.more[0]
        if nxt is not None:
            raise BoundedPathError(
                f"field path {show(text)}: {show(shown_i + f'[{j}]')} is a uint8, it has no field {show(nxt)}")
        if j >= m:
            raise BoundedPathError(
                f"field path {show(text)}: index {j} is beyond the maximum length of the strings of "
                f"{show(shown)}: the node carries at most {m} bytes of each (max_length "
                f"{show(f.name + '[]')}, default {DEFAULT_MAX_LENGTH}); valid indices are 0..{m - 1}")
        return FieldPath((*out, "data", j), "uint8")

    def _bounded_leaf(self, text: object, cur: _RawMsg, f: _RawField, index: int | None, nxt: str | None,
                      out: tuple[str | int, ...], shown: str, bounded: bool, writes: bool = False) -> FieldPath:
        """The leaf of :meth:`walk_path` when the path reaches ``f``, a
        variable-length array or (``bounded``) a string field of ``cur``
        (rule 4.15): ``index`` the index written after it, ``nxt`` the
        name of the next step (``None`` when ``f`` ends the path);
        ``writes``: the path is an output relation's."""
        ftype = f.type_text()
        _refuse_sequence_of_non_prims(text, f, shown)
        if not bounded:
            raise BoundedPathError(
                f"field path {show(text)}: {show(shown)} is a variable-length array ({ftype}); "
                "a path does not go through it"
            )
        string = f.base_kind == "string"
        what = "a string" if string else f"a variable-length array ({ftype})"
        elem = "uint8" if string else f.base
        items = "bytes" if string else "elements"
        derived = "derived: length" if writes else "derived: length or derived: truncated"
        if index is None:
            if nxt is None:
                if writes:
                    raise BoundedPathError(
                        f"field path {show(text)}: {show(shown)} is {what}; an output relation writes one of "
                        f"its {items} ({show(shown + '[0]')}, {_prim_article(elem)} {elem}) or its length "
                        "(derived: length, from a uint32 output)"
                    )
                raise BoundedPathError(
                    f"field path {show(text)}: {show(shown)} is {what}; a relation reads one of its {items} "
                    f"({show(shown + '[0]')}, {_prim_article(elem)} {elem}), or its length or whether it was "
                    "truncated (derived: length, derived: truncated)"
                )
            raise BoundedPathError(
                f"field path {show(text)}: {show(shown)} is {what}; a path does not go inside it "
                f"({show(nxt)}: len, truncated and data are fields of its C struct, not of the ROS message); "
                f"name one of its {items} ({show(shown + '[0]')}) or use {derived}"
            )
        shown_i = f"{shown}[{index}]"
        if nxt is not None:
            raise BoundedPathError(
                f"field path {show(text)}: {show(shown_i)} is {_prim_article(elem)} {elem}, it has no field {show(nxt)}"
            )
        self._check_index(text, cur, f, index, shown, what, items)
        return FieldPath((*out, "data", index), elem)

    def _check_index(self, text: object, cur: _RawMsg, f: _RawField, index: int, shown: str, what: str,
                     items: str) -> None:
        """Refuse ``index`` of the carried field ``f`` of ``cur`` (``shown``
        in the path ``text``, ``what`` it is, ``items`` what its elements
        are called) unless it is below the field's maximum length."""
        n = self.capacity(cur.name, f.name)
        if n is None:  # pragma: no cover - the front end carries what relations name
            raise BoundedPathError(f"field path {show(text)}: {show(shown)} ({what}) is not carried")
        if index >= n:
            raise BoundedPathError(
                f"field path {show(text)}: index {index} is beyond the maximum length of {show(shown)}: "
                f"the node carries at most {n} of its {items} (max_length, default {DEFAULT_MAX_LENGTH}); "
                f"valid indices are 0..{n - 1}"
            )

    def bounded_in_path(self, type_name: str, text: object) -> BoundedTarget | None:
        """The variable-length array or ``string`` field that field path
        ``text`` of ``type_name`` reaches last (through nested messages,
        fixed-size arrays of messages and elements of variable-length
        arrays of messages, on the definitions as written), whether the
        path ends there or names an element; ``None`` when it reaches none
        (nothing is reported here: the path is checked again when it is
        resolved)."""
        along = self.bounded_along(type_name, text)
        return along[-1] if along else None

    def bounded_along(self, type_name: str, text: object) -> list[BoundedTarget]:
        """Every variable-length array or ``string`` field that field path
        ``text`` of ``type_name`` reaches, outermost first: ``poses[2].
        header.frame_id`` reaches ``poses`` and the ``frame_id`` of its
        element's header; ``name[0][3]`` reaches ``name`` and its strings
        (``name[]``).  Nothing is reported here."""
        try:
            steps = parse_path(text, extended=True)
        except PathError:
            return []
        acc: list[BoundedTarget] = []
        cur = self.raw(type_name)
        out: list[str | int] = []
        inside = False
        shown = ""
        for fname, index in steps:
            f = cur.field(fname) if cur is not None else None
            if f is None:
                return acc
            out.append(fname)
            shown = f"{shown}.{fname}" if shown else fname
            if f.card == "sequence":
                if f.base_kind == "prim":
                    acc.append(BoundedTarget(tuple(out), cur.name, f.name, f.base, in_element=inside, shown=shown))
                    return acc
                if f.base_kind not in ("msg", "string"):
                    return acc
                acc.append(BoundedTarget(tuple(out), cur.name, f.name, f.base, f.base_kind, inside, shown))
                if index is None:
                    return acc
                out += ["data", index]
                shown += f"[{index}]"
                inside = True
                if f.base_kind == "string":
                    acc.append(BoundedTarget(tuple(out), cur.name, f.name + "[]", "string", None, True, shown))
                    return acc
                cur = self.raw(f.base)
                continue
            if f.base_kind == "string":
                if f.card == "scalar":
                    acc.append(BoundedTarget(tuple(out), cur.name, f.name, "string", in_element=inside, shown=shown))
                return acc
            if f.card == "array":
                if index is None or index >= f.size:
                    return acc
                out.append(index)
                shown += f"[{index}]"
            elif index is not None:
                return acc
            if f.base_kind != "msg":
                return acc
            cur = self.raw(f.base)
        return acc

    def walk_bounded(self, type_name: str, text: object, what: str) -> BoundedTarget:
        """Resolve field path ``text`` of ``type_name`` to a whole
        variable-length array of primitives or ``string`` field (rule
        4.15: the key of a ``max_length``, the field of a ``derived:
        length`` or ``truncated``; ``what`` names it in messages), through
        nested messages and fixed-size arrays of messages; raises
        :class:`PathError` saying why not."""
        steps = parse_path(text, extended=True)
        cur = self.raw(type_name)
        assert cur is not None
        out: list[str | int] = []
        shown = ""
        inside = False
        for i, (fname, index) in enumerate(steps):
            last = i == len(steps) - 1
            step = steps[i]
            f, shown = _field_step(cur, text, fname, shown)
            out.append(fname)
            ftype = f.type_text()
            bounded = f.card == "sequence" or (f.base_kind == "string" and f.card == "scalar")
            if f.card == "sequence" and f.base_kind in ("msg", "string"):
                found = self._into_elements(text, steps, i, cur, f, out, shown, what, inside)
                if isinstance(found, BoundedTarget):
                    return found
                cur, shown = found
                inside = True
                continue
            if step.any or step.more:
                raise BoundedPathError(
                    f"field path {show(text)}: {show(shown)} ({ftype}) is not a variable-length array of messages "
                    f"or strings: {'[]' if step.any else 'a second index'} is for those")
            if bounded:
                kind = "a string" if f.base_kind == "string" else f"a variable-length array ({ftype})"
                if index is not None:
                    raise BoundedPathError(
                        f"field path {show(text)}: {show(shown + f'[{index}]')} is one element of {kind}; "
                        f"{what} names the whole {'string' if f.base_kind == 'string' else 'array'} ({show(shown)})"
                    )
                if not last:
                    raise BoundedPathError(
                        f"field path {show(text)}: {show(shown)} is {kind}; a path does not go inside it "
                        f"({show(steps[i + 1][0])}: len, truncated and data are fields of its C struct, not of "
                        f"the ROS message)"
                    )
                if f.card == "sequence" and f.base_kind != "prim":
                    _refuse_sequence_of_non_prims(text, f, shown)
                return BoundedTarget(tuple(out), cur.name, f.name, "string" if f.base_kind == "string" else f.base,
                                     in_element=inside)
            if f.card == "array" and f.base_kind == "string":
                raise BoundedPathError(
                    f"field path {show(text)}: {show(shown)} is an array of strings ({ftype}); "
                    "arrays of strings are not carried yet (issue 15)"
                )
            if f.card != "array" or f.base_kind == "msg":  # a fixed-size array of primitives is refused below
                shown = _index_step(text, steps, i, f, index, shown, out)
            if f.base_kind != "msg" or f.card == "array" and index is None:
                raise BoundedPathError(
                    f"field path {show(text)}: {show(shown)} is {_article(f.base)} {ftype}, "
                    f"not a variable-length array or a string ({what} is for those)"
                )
            nxt = self.raw(f.base)
            if nxt is None:  # pragma: no cover - the type was loaded
                raise PathError(f"field path {show(text)}: {show(shown)} has the unknown message type {show(f.base)}")
            if last:
                raise BoundedPathError(
                    f"field path {show(text)}: {show(shown)} is a whole sub-message ({f.base}), "
                    f"not a variable-length array or a string ({what} is for those)"
                )
            cur = nxt
        raise PathError(f"field path {show(text)} is empty")  # pragma: no cover

    def _into_elements(self, text: object, steps, i: int, cur: _RawMsg, f: _RawField, out: list[str | int],
                       shown: str, what: str, inside: bool) -> BoundedTarget | tuple[_RawMsg, str]:
        """Step ``i`` of :meth:`walk_bounded`: field ``f`` of ``cur``, a
        variable-length array of messages or strings (``out`` gets its
        steps).  Returns the target when the path names it (or one
        element's string), else the element's type and the path shown so
        far; raises :class:`BoundedPathError` saying why not."""
        keys = what in ("max_length", "policy")
        last = i == len(steps) - 1
        step = steps[i]
        index = step[1]
        ftype = f.type_text()
        string = f.base_kind == "string"
        kind = f"a variable-length array of {'strings' if string else 'messages'} ({ftype})"
        if index is None and not step.any:
            if last:
                return BoundedTarget(tuple(out), cur.name, f.name, f.base, f.base_kind, inside)
            raise BoundedPathError(
                f"field path {show(text)}: {show(shown)} is {kind}; "
                + (f"a {what} key reaches into every element with [] ({show(shown + '[].' + steps[i + 1][0])})"
                   if keys else f"name one element with a constant index ({show(shown + '[0].' + steps[i + 1][0])})"))
        if keys and not step.any:
            raise BoundedPathError(
                f"field path {show(text)}: {show(shown + f'[{index}]')}: a {what} key names every element "
                f"of {show(shown)} ({kind}) with [] ({show(shown + '[]')}): one struct holds them all")
        if not keys and step.any:
            raise BoundedPathError(
                f"field path {show(text)}: {show(shown + '[]')}: {what} names one element with a constant "
                f"index ({show(shown + '[0]')}); [] (every element) is for max_length and policy keys")
        if index is not None:
            n = self.capacity(cur.name, f.name)
            if n is not None and index >= n:
                raise BoundedPathError(
                    f"field path {show(text)}: index {index} is beyond the maximum length of {show(shown)}: "
                    f"the node carries at most {n} of its elements (max_length, default "
                    f"{DEFAULT_MAX_LENGTH}); valid indices are 0..{n - 1}")
        out += ["data", index if index is not None else 0]
        shown += f"[{index}]" if index is not None else "[]"
        if step.more:
            raise BoundedPathError(
                f"field path {show(text)}: {show(shown + f'[{step.more[0]}]')} is one element of "
                + ("a string" if string else f"an array of messages") + f"; {what} names a whole "
                + ("string" if string else "array") + f" ({show(shown)})")
        if string:
            if not last:
                raise BoundedPathError(
                    f"field path {show(text)}: {show(shown)} is a string; a path does not go inside it "
                    f"({show(steps[i + 1][0])}: len, truncated and data are fields of its C struct, not "
                    "of the ROS message)")
            return BoundedTarget(tuple(out), cur.name, f.name + "[]", "string", None, True)
        if last:
            raise BoundedPathError(
                f"field path {show(text)}: {show(shown)} is a whole element ({f.base}) of {kind}, "
                f"not a variable-length array or a string ({what} is for those)")
        cur = self.raw(f.base)
        assert cur is not None
        return cur, shown

    def walk_string_path(self, type_name: str, text: object) -> StringTarget:
        """Resolve field path ``text`` in message type ``type_name`` to a
        ``string`` field (rule 4.14), through nested messages and
        fixed-size arrays of messages, on the definitions as written (a
        string need not be carried yet); raises :class:`PathError` saying
        why not."""
        steps = parse_path(text)
        cur = self.raw(type_name)
        assert cur is not None
        out: list[str | int] = []
        shown = ""
        for i, (fname, index) in enumerate(steps):
            last = i == len(steps) - 1
            f, shown = _field_step(cur, text, fname, shown)
            out.append(fname)
            ftype = f.type_text()
            if f.card == "sequence":
                raise PathError(
                    f"field path {show(text)}: {show(shown)} is a variable-length array "
                    f"({ftype}); a constant string is not reached through a variable-length array"
                )
            if f.card == "array" and f.base_kind == "string":
                raise PathError(
                    f"field path {show(text)}: {show(shown)} is an array of strings ({ftype}); "
                    "a constant is given to a single string field"
                )
            if f.card != "array" and index is not None and f.base_kind == "string":
                raise PathError(
                    f"field path {show(text)}: {show(shown)} is a string, not an array: "
                    f"a constant sets the whole string (name {show(shown)})"
                )
            shown = _index_step(text, steps, i, f, index, shown, out)
            if f.base_kind == "string":
                if not last:
                    raise PathError(
                        f"field path {show(text)}: {show(shown)} is a string; a constant sets the "
                        "whole string, a path does not go inside it (len, truncated and data are "
                        "fields of its C struct, not of the ROS message)"
                    )
                return StringTarget(tuple(out), cur.name, f.name)
            if f.base_kind in ("prim", "unsupported"):
                if last:
                    raise PathError(
                        f"field path {show(text)}: {show(shown)} is {_article(f.base)} {f.base}, "
                        "not a string"
                    )
                raise PathError(
                    f"field path {show(text)}: {show(shown)} is {_article(f.base)} "
                    f"{f.base}, it has no field {show(steps[i + 1][0])}"
                )
            nxt = self.raw(f.base)
            if nxt is None:
                raise PathError(
                    f"field path {show(text)}: {show(shown)} has the unknown message type {show(f.base)}"
                )
            if last:
                example = next((x.name for x in nxt.fields if x.base_kind == "string" and x.card == "scalar"),
                               None)
                hint = f"; e.g. {show(shown + '.' + example)}" if example else ""
                raise PathError(
                    f"field path {show(text)}: {show(shown)} is a whole sub-message "
                    f"({f.base}), not a string field{hint}"
                )
            cur = nxt
        raise PathError(f"field path {show(text)} is empty")  # pragma: no cover


def _field_step(cur: _RawMsg, text: object, fname: str, shown: str) -> tuple[_RawField, str]:
    """One step of a path walker: the field ``fname`` of ``cur`` and the
    path shown so far with it; raises :class:`PathError` when ``cur`` has
    no such field (``shown`` is where the walk stands, for the message)."""
    f = cur.field(fname)
    if f is None:
        names = [x.name for x in cur.fields]
        owner = f"{cur.name} (at {show(shown)})" if shown else cur.name
        raise PathError(
            f"field path {show(text)}: message type {owner} has no field "
            f"{show(fname)}{did_you_mean(fname, names)}"
        )
    return f, (f"{shown}.{fname}" if shown else fname)


def _index_step(text: object, steps: list[tuple[str, int | None]], i: int, f: _RawField,
                index: int | None, shown: str, out: list[str | int]) -> str:
    """The index ``index`` written after field ``f`` (step ``i`` of
    ``steps``, ``shown`` the path up to it): a fixed-size array needs a
    constant index within its size (appended to ``out``), any other field
    none; returns the path shown with the index; raises
    :class:`PathError` saying why not."""
    if f.card == "array":
        if index is None:
            last = i == len(steps) - 1
            hint = f"{shown}[0]" + ("" if last else "." + ".".join(s for s, _ in steps[i + 1 :]))
            raise PathError(
                f"field path {show(text)}: {show(shown)} is an array ({f.type_text()}); "
                f"name one element with a constant index, e.g. {show(hint)}"
            )
        if index >= f.size:
            valid = f"valid indices are 0..{f.size - 1}" if f.size else "it has no elements"
            raise PathError(
                f"field path {show(text)}: index {index} is out of range for "
                f"{show(shown)} ({f.type_text()}; {valid})"
            )
        out.append(index)
        return f"{shown}[{index}]"
    if index is not None:
        raise PathError(
            f"field path {show(text)}: {show(shown)} is not an array "
            f"(it is {_article(f.base)} {f.base}), it cannot be indexed"
        )
    return shown


def _refuse_sequence_of_non_prims(text: object, f: _RawField, shown: str) -> None:
    """Raise :class:`BoundedPathError` when ``f`` (reached as ``shown``) is a
    variable-length array of a type the glue does not carry (rule 4.15:
    of primitives, messages and strings only)."""
    if f.card == "sequence" and f.base_kind not in ("prim", "msg", "string"):
        raise BoundedPathError(
            f"field path {show(text)}: {show(shown)} is a variable-length array of {f.base} ({f.type_text()}), "
            "which the glue does not carry"
        )


def _ros_leaf(t: MsgType, messages) -> FieldPath | None:
    """The first leaf of ``t`` that is a field of the ROS message (not one
    of a carried string's or sequence's struct), or ``None``."""
    for p in leaf_paths(t, messages):
        if not _inside_string(t, p, messages):
            return p
    return None


def _inside_string(t: MsgType, p: FieldPath, messages) -> bool:
    """Whether leaf path ``p`` of ``t`` goes through a carried string or
    sequence (a bounded struct)."""
    cur: MsgType | None = t
    for s in p.steps:
        if isinstance(s, int) or cur is None:
            continue
        f = cur.field(s)
        if f is None or f.kind != "msg":
            return False
        if is_bounded_type(f.msg):
            return True
        cur = _PSEUDO.get(f.msg) or messages.get(f.msg)
    return False


def _display(path) -> str:
    """A path for messages: relative to the working directory when it lies
    below it, absolute otherwise."""
    import os

    text = str(path)
    try:
        rel = os.path.relpath(text)
    except ValueError:  # pragma: no cover - other drive on Windows
        return text
    return text if rel.startswith("..") else rel


def _prim_article(prim: str) -> str:
    """The article of a primitive type's name as read aloud: an int8, a uint8."""
    return "an" if prim[:1] in "aeio" else "a"


def _article(word: str) -> str:
    return "an" if word[:1] in "aeiou" else "a"


_STEP_RE = re.compile(r"([A-Za-z_][A-Za-z0-9_]*)((?:\[[0-9]{0,9}\])*)")
_INDEX_RE = re.compile(r"\[([0-9]{0,9})\]")


class _Step(tuple):
    """One step of a field path: ``(name, index)`` (``index`` ``None``
    when none is written), with ``more``, the indices written after the
    first (``name[0][3]``: a byte of an element of an array of strings,
    rule 4.15), and ``any``, whether the first index is written ``[]``
    (every element: a ``max_length`` or ``policy`` key reaching into the
    elements of a variable-length array, rule 4.15)."""

    more: tuple[int, ...] = ()
    any: bool = False

    def __new__(cls, name: str, index: int | None, more: tuple[int, ...] = (), any_: bool = False):
        t = super().__new__(cls, (name, index))
        t.more = more
        t.any = any_
        return t


def parse_path(text: object, *, extended: bool = False) -> list[tuple[str, int | None]]:
    """Split ``a.b[3].c`` into ``[('a', None), ('b', 3), ('c', None)]``;
    raises :class:`PathError` when ``text`` is not of that form.  With
    ``extended`` (rule 4.15), a step may also carry a second index
    (``name[0][3]``) or ``[]`` (``poses[].header.frame_id``), kept in the
    step's ``more`` and ``any`` (:class:`_Step`)."""
    if not isinstance(text, str) or not text:
        raise PathError(f"field path {show(text)} is empty")
    out = []
    for part in text.split("."):
        m = _STEP_RE.fullmatch(part)
        indices = _INDEX_RE.findall(m.group(2)) if m else []
        ok = m is not None and (
            "" not in indices[1:] and not (indices and indices[0] == "" and len(indices) > 1) and (extended or (len(indices) <= 1 and "" not in indices))
            and len(indices) <= 2)
        if not ok:
            hint = ""
            if re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*\[.*\]", part):
                hint = "; array indices are non-negative integer constants, e.g. covariance[35]"
            raise PathError(
                f"field path {show(text)} is malformed: expected field names, each "
                f"optionally followed by [INDEX], separated by '.'{hint}"
            )
        zeros = [x for x in indices if len(x) > 1 and x.startswith("0")]
        if zeros:
            # rule 4.1: C reads 010 as octal 8, a reader of the model as 10
            raise PathError(
                f"field path {show(text)}: index [{zeros[0]}] has a leading zero (C reads 010 as octal 8); "
                f"write the index in plain decimal, [{int(zeros[0])}]"
            )
        first = indices[0] if indices else None
        out.append(_Step(m.group(1), int(first) if first else None,
                         tuple(int(x) for x in indices[1:]), first == ""))
    return out


def _field_lines(text: str) -> dict[str, list[tuple[int, int]]]:
    """Line and column of each definition of each field in a ``.msg`` text."""
    out: dict[str, list[tuple[int, int]]] = {}
    for i, line in enumerate(text.split("\n"), start=1):
        code = line.split("#", 1)[0]
        if "=" in code and "<=" not in code:
            continue  # a constant
        m = _FIELD_LINE_RE.fullmatch(line.rstrip("\r"))
        if m:
            out.setdefault(m.group(2), []).append((i, m.start(1) + 1))
    return out


def _first_bad_line(text: str, rname: str) -> int:
    """The first line of a ``.msg`` text that does not parse on its own."""
    from rosbags.typesys import get_types_from_msg

    for i, line in enumerate(text.split("\n"), start=1):
        if not line.strip() or line.strip().startswith("#"):
            continue
        try:
            get_types_from_msg(line, rname)
        except Exception:  # noqa: BLE001
            return i
    return 1

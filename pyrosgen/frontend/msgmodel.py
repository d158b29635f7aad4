"""ROS 1 message types as the glue carries them: the message MODEL.

The primitive types and their C and Simulink names, the limits of DESIGN.md
rule 4.5, the carried view of a message type (:class:`MsgType`,
:class:`MsgField`), the pseudo types ``time`` and ``duration``, field paths
(:class:`FieldPath`) and the scalar leaves of a message.  This module
imports nothing from the loader (:mod:`pyrosgen.frontend.msgload`), which
builds these values from rosbags and ``.msg`` files.
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Mapping
from dataclasses import dataclass


__all__ = [
    "PRIMITIVES",
    "ROS1_ALIASES",
    "C_TYPES",
    "SIMULINK_TYPES",
    "PRIM_SIZES",
    "MAX_LEAVES",
    "MAX_STRUCT_FIELDS",
    "MAX_TOTAL_LEAVES",
    "widest_struct",
    "MAX_MSG_FILES",
    "MAX_MSG_DEPTH",
    "MsgField",
    "MsgType",
    "STRING_CAPACITY",
    "string_type_name",
    "string_type",
    "is_string_type",
    "DEFAULT_MAX_LENGTH",
    "MAX_SEQUENCE_LENGTH",
    "seq_type_name",
    "seq_type",
    "seq_msg_type_name",
    "seq_string_type_name",
    "seq_elem_type",
    "is_seq_type",
    "bounded_type",
    "is_bounded_type",
    "FieldPath",
    "TIME",
    "DURATION",
    "msg_c_name",
    "leaf_paths",
    "leaf_count",
]

# --------------------------------------------------------------------------
# Primitive types

#: The ROS primitive types the glue carries, in the order of DESIGN.md 4.
PRIMITIVES: tuple[str, ...] = (
    "bool",
    "int8",
    "uint8",
    "int16",
    "uint16",
    "int32",
    "uint32",
    "int64",
    "uint64",
    "float32",
    "float64",
)

#: ROS 1's deprecated aliases (``char`` is unsigned, ``byte`` signed).
ROS1_ALIASES: dict[str, str] = {"char": "uint8", "byte": "int8"}

#: The C type of each primitive.
C_TYPES: dict[str, str] = {
    "bool": "unsigned char",
    "int8": "signed char",
    "uint8": "unsigned char",
    "int16": "short",
    "uint16": "unsigned short",
    "int32": "int",
    "uint32": "unsigned int",
    "int64": "long long",
    "uint64": "unsigned long long",
    "float32": "float",
    "float64": "double",
}

#: The Simulink (``rtwtypes.h``) name of each primitive's C type.
SIMULINK_TYPES: dict[str, str] = {
    "bool": "boolean_T",
    "int8": "int8_T",
    "uint8": "uint8_T",
    "int16": "int16_T",
    "uint16": "uint16_T",
    "int32": "int32_T",
    "uint32": "uint32_T",
    "int64": "int64_T",
    "uint64": "uint64_T",
    "float32": "real32_T",
    "float64": "real_T",
}

#: Size in bytes of each primitive's C type (LP64 and ILP32 alike).
PRIM_SIZES: dict[str, int] = {
    "bool": 1,
    "int8": 1,
    "uint8": 1,
    "int16": 2,
    "uint16": 2,
    "int32": 4,
    "uint32": 4,
    "int64": 8,
    "uint64": 8,
    "float32": 4,
    "float64": 8,
}

#: Largest number of carried scalar leaves in one topic's message type (each
#: leaf is one copy statement in a callback, and one proof obligation).
MAX_LEAVES = 10000
#: At most this many carried fields in one message definition (struct).
#: The cost of checking the proof grows with the square of a struct's width
#: (each field access walks the field list; BENCHMARKS.md section 5).
MAX_STRUCT_FIELDS = 256
#: At most this many carried leaves over all topics of a node (every
#: callback and output glue copies its whole message).
MAX_TOTAL_LEAVES = 20000

#: Largest number of ``.msg`` files read from the ``msg_paths`` of one model.
MAX_MSG_FILES = 2000

#: Deepest nesting of message types (the standard ones nest at most 6 deep).
MAX_MSG_DEPTH = 32

# --------------------------------------------------------------------------
# The carried view


@dataclass(frozen=True)
class MsgField:
    """A carried field of a message type.

    ``kind`` is ``'prim'`` (then ``prim`` is the ROS primitive name, aliases
    already resolved) or ``'msg'`` (then ``msg`` is the full type name, e.g.
    ``'std_msgs/Header'``, or ``'time'``/``'duration'``).  ``array_len`` is the
    length of a fixed-size array, ``None`` for a scalar field.
    """

    name: str
    kind: str
    prim: str | None = None
    msg: str | None = None
    array_len: int | None = None

    @property
    def is_array(self) -> bool:
        """Whether the field is a fixed-size array."""
        return self.array_len is not None

    @property
    def c_type(self) -> str:
        """The C type of one element: a primitive's C type or ``struct <c_name>``."""
        if self.kind == "prim":
            return C_TYPES[self.prim]
        return f"struct {msg_c_name(self.msg)}"


@dataclass(frozen=True)
class MsgType:
    """A message type as carried by the glue: ``fields`` are the carried
    fields in definition order (never empty)."""

    name: str
    c_name: str
    fields: tuple[MsgField, ...]
    #: a carried ROS ``string`` (rule 4.14): the bounded struct
    #: ``ros_string<N>`` of :func:`string_type`, ``N`` its capacity in
    #: bytes; ``None`` for every other type
    string_capacity: int | None = None
    #: a carried variable-length array ``T[]`` (rule 4.15): the bounded
    #: struct ``ros_seq_<T>_<N>`` of :func:`seq_type`, ``(T, N)``, ``T`` a
    #: primitive, or of :func:`seq_elem_type`, ``T`` a message type
    #: (``geometry_msgs/PoseStamped``) or ``'string'``; ``None`` for every
    #: other type
    seq_of: tuple[str, int] | None = None
    #: a bounded struct of policy reject (rule 4.15, ``policy``): named
    #: ``ros_rseq_<T>_<N>`` or ``ros_rstring<N>`` (``Environment.reject_name``);
    #: a received message holding it longer than ``N`` is not delivered
    reject: bool = False

    @property
    def is_pseudo(self) -> bool:
        """Whether this is a pseudo type: ``time``, ``duration`` or a
        carried string's struct (no ROS package, no roscpp header)."""
        return "/" not in self.name

    @property
    def is_string(self) -> bool:
        """Whether this is the struct of a carried string (rule 4.14)."""
        return self.string_capacity is not None

    @property
    def is_seq(self) -> bool:
        """Whether this is the struct of a carried variable-length array
        of a primitive type (rule 4.15)."""
        return self.seq_of is not None

    @property
    def is_bounded(self) -> bool:
        """Whether this is a bounded struct (``len``, ``truncated``,
        ``data``): a carried string or variable-length array."""
        return self.is_string or self.is_seq

    @property
    def capacity(self) -> int | None:
        """The capacity of a bounded struct (bytes of a string, elements
        of a sequence), else ``None``."""
        if self.is_string:
            return self.string_capacity
        return self.seq_of[1] if self.seq_of is not None else None

    @property
    def element_cpp(self) -> str | None:
        """The C++ element type roscpp gives a carried sequence
        (``std::vector<element_cpp>``), else ``None``."""
        if self.seq_of is None:
            return None
        elem = self.seq_of[0]
        if elem in CPP_ELEMENT_TYPES:
            return CPP_ELEMENT_TYPES[elem]
        return {"string": "std::string", "time": "ros::Time", "duration": "ros::Duration"}.get(
            elem, elem.replace("/", "::"))

    @property
    def elem_struct(self) -> str | None:
        """The element type of a carried sequence of messages or strings
        (rule 4.15): the message type (``geometry_msgs/PoseStamped``,
        ``time``) or the element string's struct (``ros_string32``) that
        its ``data`` array holds; ``None`` for every other type (a
        sequence of primitives included)."""
        if self.seq_of is None or len(self.fields) != 3 or self.fields[2].kind != "msg":
            return None
        return self.fields[2].msg

    @property
    def elem_string_capacity(self) -> int | None:
        """The capacity in bytes of each string of a carried array of
        strings (``M`` of ``ros_seq_string<M>_<N>``), else ``None``."""
        if self.seq_of is None or self.seq_of[0] != "string" or self.elem_struct is None:
            return None
        m = re.fullmatch(r"ros_r?string(\d+)", self.elem_struct)
        return int(m.group(1)) if m else None

    @property
    def package(self) -> str | None:
        """The ROS package (``None`` for ``time``/``duration``)."""
        return self.name.split("/")[0] if "/" in self.name else None

    @property
    def short_name(self) -> str:
        """The type name without its package."""
        return self.name.split("/")[-1]

    @property
    def cpp_name(self) -> str:
        """The roscpp C++ type: ``geometry_msgs::TwistStamped``, ``ros::Time``."""
        if self.name == "time":
            return "ros::Time"
        if self.name == "duration":
            return "ros::Duration"
        if self.is_string:
            return "std::string"
        if self.is_seq:
            return f"std::vector<{self.element_cpp}>"
        return self.name.replace("/", "::")

    def field(self, name: str) -> MsgField | None:
        """The carried field ``name``, or ``None``."""
        for f in self.fields:
            if f.name == name:
                return f
        return None


#: ROS 1 ``time``: ``{sec: uint32, nsec: uint32}``.
TIME = MsgType(
    "time",
    "ros_time",
    (MsgField("sec", "prim", prim="uint32"), MsgField("nsec", "prim", prim="uint32")),
)

#: ROS 1 ``duration``: ``{sec: int32, nsec: int32}``.
DURATION = MsgType(
    "duration",
    "ros_duration",
    (MsgField("sec", "prim", prim="int32"), MsgField("nsec", "prim", prim="int32")),
)

_PSEUDO = {"time": TIME, "duration": DURATION}

#: The capacity in bytes of a carried ROS ``string`` (rule 4.14): the
#: bytes a string field can hold in the C struct, Simulink's default
#: maximum length of a ROS string.  Every carried string has it in this
#: version; :func:`string_type_name` builds the struct's name from it.
STRING_CAPACITY = 128

_STRING_NAME = re.compile(r"ros_(r?)string([1-9][0-9]{0,5})")


def string_type_name(capacity: int = STRING_CAPACITY, reject: bool = False) -> str:
    """The name (and C struct name) of a carried string of ``capacity``
    bytes: ``ros_string128`` (``ros_rstring128`` of policy reject)."""
    return f"ros_{'r' if reject else ''}string{capacity}"


def string_type(capacity: int = STRING_CAPACITY, reject: bool = False) -> MsgType:
    """The C struct of a carried ROS ``string`` of at most ``capacity``
    bytes (rule 4.14; ``Wellformed.string_msg``): ``len`` (``uint32``, the
    number of bytes), ``truncated`` (``bool``, set when a received string
    was longer than the capacity) and ``data`` (``uint8[capacity]``, the
    bytes, zero past ``len``)."""
    name = string_type_name(capacity, reject)
    return MsgType(
        name,
        name,
        (
            MsgField("len", "prim", prim="uint32"),
            MsgField("truncated", "prim", prim="bool"),
            MsgField("data", "prim", prim="uint8", array_len=capacity),
        ),
        string_capacity=capacity,
        reject=reject,
    )


def is_string_type(name: str) -> bool:
    """Whether ``name`` is the name of a carried string's struct."""
    return isinstance(name, str) and _STRING_NAME.fullmatch(name) is not None


#: The maximum number of elements (bytes for a string) carried of a
#: variable-length array or string that the model gives none (rule 4.15,
#: ``max_length``): 128, Simulink's default for both.
DEFAULT_MAX_LENGTH = 128

#: The largest ``max_length`` a model may give (rule 4.15).  (The leaf
#: limits of rule 4.5 bound it further: a message carries at most
#: :data:`MAX_LEAVES` leaves.)
MAX_SEQUENCE_LENGTH = 65536

#: The element type that roscpp gives a ``T[]`` of each primitive ``T``
#: (``std::vector<...>``; ROS 1's ``bool`` is a ``uint8_t``).
CPP_ELEMENT_TYPES: dict[str, str] = {
    "bool": "uint8_t",
    "int8": "int8_t",
    "uint8": "uint8_t",
    "int16": "int16_t",
    "uint16": "uint16_t",
    "int32": "int32_t",
    "uint32": "uint32_t",
    "int64": "int64_t",
    "uint64": "uint64_t",
    "float32": "float",
    "float64": "double",
}

_SEQ_NAME = re.compile(r"ros_(r?)seq_(" + "|".join(PRIMITIVES) + r")_([1-9][0-9]{0,5})")


def seq_type_name(prim: str, capacity: int = DEFAULT_MAX_LENGTH, reject: bool = False) -> str:
    """The name (and C struct name) of a carried ``prim[]`` of at most
    ``capacity`` elements: ``ros_seq_float32_1081`` (``ros_rseq_float32_1081``
    of policy reject)."""
    if prim not in PRIMITIVES:
        raise ValueError(f"not a primitive type: {prim!r}")
    return f"ros_{'r' if reject else ''}seq_{prim}_{capacity}"


def seq_type(prim: str, capacity: int = DEFAULT_MAX_LENGTH, reject: bool = False) -> MsgType:
    """The C struct of a carried variable-length array of ``prim`` of at
    most ``capacity`` elements (rule 4.15; the environment model's bounded
    sequence, ``Environment.bounded_name``, ``clamp``): ``len``
    (``uint32``, the number of elements received, at most ``capacity``),
    ``truncated`` (``bool``, set when more were received) and ``data``
    (``prim[capacity]``, the elements, zero past ``len``)."""
    name = seq_type_name(prim, capacity, reject)
    return MsgType(
        name,
        name,
        (
            MsgField("len", "prim", prim="uint32"),
            MsgField("truncated", "prim", prim="bool"),
            MsgField("data", "prim", prim=prim, array_len=capacity),
        ),
        seq_of=(prim, capacity),
        reject=reject,
    )


def is_seq_type(name: str) -> bool:
    """Whether ``name`` is the name of a carried sequence's struct."""
    return isinstance(name, str) and _SEQ_NAME.fullmatch(name) is not None


#: The struct of a carried variable-length array of strings (rule 4.15):
#: ``ros_seq_string<M>_<N>``, at most ``N`` strings of at most ``M`` bytes.
_SEQ_STRING_NAME = re.compile(r"ros_(r?)seq_string([1-9][0-9]{0,5})_([1-9][0-9]{0,5})")
#: The struct of a carried variable-length array of messages (rule 4.15):
#: ``ros_seq_<pkg>_<Type>_<N>`` (the element's C struct name, ``ros_time``
#: and ``ros_duration`` included: a ROS type name has no '_').
_SEQ_MSG_NAME = re.compile(r"ros_(r?)seq_([a-z][a-z0-9_]*_[A-Za-z][A-Za-z0-9]*)_([1-9][0-9]{0,5})")


def seq_msg_type_name(elem: str, capacity: int = DEFAULT_MAX_LENGTH, reject: bool = False) -> str:
    """The name (and C struct name) of a carried variable-length array of
    at most ``capacity`` messages of type ``elem`` (``pkg/Type``, ``time``
    or ``duration``): ``ros_seq_geometry_msgs_PoseStamped_128``
    (``ros_rseq_...`` of policy reject)."""
    c = msg_c_name(elem)
    if _elem_msg_name(c) != elem:
        raise ValueError(f"not a message type: {elem!r}")
    return f"ros_{'r' if reject else ''}seq_{c}_{capacity}"


def seq_string_type_name(elem_capacity: int, capacity: int = DEFAULT_MAX_LENGTH, reject: bool = False) -> str:
    """The name (and C struct name) of a carried variable-length array of
    at most ``capacity`` strings of at most ``elem_capacity`` bytes each:
    ``ros_seq_string32_6`` (``ros_rseq_string32_6`` of policy reject)."""
    return f"ros_{'r' if reject else ''}seq_string{elem_capacity}_{capacity}"


def _elem_msg_name(c_name: str) -> str | None:
    """The message type whose C struct name is ``c_name`` (``pkg_Type``
    gives ``pkg/Type``; ``ros_time``, ``ros_duration``), ``None`` if none
    can be (a package called ``ros`` or ``ros_...`` is refused, rule 4.15)."""
    if c_name == "ros_time":
        return "time"
    if c_name == "ros_duration":
        return "duration"
    pkg, _, typ = c_name.rpartition("_")
    if not pkg or pkg == "ros" or pkg.startswith("ros_") or not re.fullmatch(r"[A-Za-z][A-Za-z0-9]*", typ):
        return None
    return f"{pkg}/{typ}"


def seq_elem_type(elem: str, capacity: int = DEFAULT_MAX_LENGTH, reject: bool = False,
                  elem_capacity: int | None = None) -> MsgType:
    """The C struct of a carried variable-length array of messages of type
    ``elem`` or, with ``elem == 'string'``, of strings of at most
    ``elem_capacity`` bytes (rule 4.15; ``Environment.bounded_name``,
    ``clamp``, ``clamp_bounded_elems``): ``len`` (``uint32``), ``truncated``
    (``bool``) and ``data``, an array of ``capacity`` element structs (the
    element message's carried struct, or ``ros_string<M>``): the first
    ``len`` converted in turn (their own sequences and strings capped),
    every other one zero."""
    if elem == "string":
        if elem_capacity is None:
            raise ValueError("a sequence of strings needs the strings' capacity")
        name = seq_string_type_name(elem_capacity, capacity, reject)
        data = MsgField("data", "msg", msg=string_type_name(elem_capacity), array_len=capacity)
    else:
        name = seq_msg_type_name(elem, capacity, reject)
        data = MsgField("data", "msg", msg=elem, array_len=capacity)
    return MsgType(
        name,
        name,
        (MsgField("len", "prim", prim="uint32"), MsgField("truncated", "prim", prim="bool"), data),
        seq_of=(elem, capacity),
        reject=reject,
    )


def is_bounded_type(name: str) -> bool:
    """Whether ``name`` is the name of a bounded struct: a carried string
    (``ros_string<N>``) or sequence (``ros_seq_<T>_<N>``, of strings
    ``ros_seq_string<M>_<N>``, of messages ``ros_seq_<pkg>_<Type>_<N>``)."""
    if not isinstance(name, str):
        return False
    if is_string_type(name) or is_seq_type(name) or _SEQ_STRING_NAME.fullmatch(name):
        return True
    m = _SEQ_MSG_NAME.fullmatch(name)
    return m is not None and _elem_msg_name(m.group(2)) is not None


def bounded_type(name: str) -> MsgType:
    """The bounded struct called ``name`` (:func:`is_bounded_type`)."""
    m = _SEQ_NAME.fullmatch(name)
    if m is not None:
        return seq_type(m.group(2), int(m.group(3)), m.group(1) == "r")
    m = _STRING_NAME.fullmatch(name)
    if m is not None:
        return string_type(int(m.group(2)), m.group(1) == "r")
    m = _SEQ_STRING_NAME.fullmatch(name)
    if m is not None:
        return seq_elem_type("string", int(m.group(3)), m.group(1) == "r", int(m.group(2)))
    m = _SEQ_MSG_NAME.fullmatch(name)
    if m is not None and _elem_msg_name(m.group(2)) is not None:
        return seq_elem_type(_elem_msg_name(m.group(2)), int(m.group(3)), m.group(1) == "r")
    raise KeyError(name)


def msg_c_name(name: str) -> str:
    """The C struct name of a message type: ``pkg/Type`` gives ``pkg_Type``,
    ``time`` gives ``ros_time`` and ``duration`` gives ``ros_duration``."""
    if name in _PSEUDO:
        return _PSEUDO[name].c_name
    return name.replace("/", "_")


@dataclass(frozen=True)
class FieldPath:
    """A path from a message to one scalar leaf: field names and constant
    array indices, e.g. ``('pose', 'covariance', 35)``; ``prim`` is the
    leaf's primitive type."""

    steps: tuple[str | int, ...]
    prim: str

    def __str__(self) -> str:
        out = ""
        for s in self.steps:
            if isinstance(s, int):
                out += f"[{s}]"
            else:
                out += ("." if out else "") + s
        return out

    @property
    def c_type(self) -> str:
        """The C type of the leaf."""
        return C_TYPES[self.prim]

    def c_access(self, base: str, arrow: bool = False) -> str:
        """C text selecting the leaf from ``base`` (``base->`` when ``arrow``)."""
        out = base
        first = True
        for s in self.steps:
            if isinstance(s, int):
                out += f"[{s}]"
            else:
                out += ("->" if (first and arrow) else ".") + s
            first = False
        return out


def leaf_paths(msg: str | MsgType, messages: Mapping[str, MsgType]) -> tuple[FieldPath, ...]:
    """Every carried scalar leaf of ``msg``, in definition order, arrays
    expanded element by element: what a callback copies.

    ``messages`` maps type names to carried types (``time``/``duration`` need
    not be in it).
    """
    root = msg if isinstance(msg, MsgType) else _get(messages, msg)
    out: list[FieldPath] = []

    def go(t: MsgType, prefix: tuple[str | int, ...]) -> None:
        for f in t.fields:
            indices: Iterable[tuple[str | int, ...]]
            if f.array_len is None:
                indices = [(f.name,)]
            else:
                indices = [(f.name, i) for i in range(f.array_len)]
            for steps in indices:
                if f.kind == "prim":
                    out.append(FieldPath(prefix + steps, f.prim))
                else:
                    go(_get(messages, f.msg), prefix + steps)

    go(root, ())
    return tuple(out)


def leaf_count(msg: str | MsgType, messages: Mapping[str, MsgType]) -> int:
    """The number of carried scalar leaves of ``msg`` (without listing them)."""
    memo: dict[str, int] = {}

    def count(t: MsgType) -> int:
        if t.name in memo:
            return memo[t.name]
        n = 0
        for f in t.fields:
            k = 1 if f.kind == "prim" else count(_get(messages, f.msg))
            n += k * (f.array_len if f.array_len is not None else 1)
        memo[t.name] = n
        return n

    return count(msg if isinstance(msg, MsgType) else _get(messages, msg))


def widest_struct(msg: str | MsgType, messages: Mapping[str, MsgType]) -> tuple[str, int]:
    """The message type with the most carried fields among ``msg`` and the
    types it contains, and that number."""
    seen: dict[str, int] = {}

    def visit(t: MsgType) -> None:
        if t.name in seen:
            return
        seen[t.name] = len(t.fields)
        for f in t.fields:
            if f.kind != "prim":
                visit(_get(messages, f.msg))

    visit(msg if isinstance(msg, MsgType) else _get(messages, msg))
    name = max(seen, key=lambda k: (seen[k], k))
    return name, seen[name]


def _get(messages: Mapping[str, MsgType], name: str) -> MsgType:
    if name in _PSEUDO and name not in messages:
        return _PSEUDO[name]
    if name not in messages and is_bounded_type(name):
        return bounded_type(name)
    return messages[name]

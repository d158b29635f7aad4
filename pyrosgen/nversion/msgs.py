"""ROS 1 message definitions, read a second time (N-version, DESIGN.md
section 7): a ``.msg`` parser and the carried view of a message type,
written without the front end's code (``pyrosgen.frontend.msgload``),
from DESIGN.md rules 4.5, 4.14 and 4.15.

The standard definitions are the ``.msg`` files of Debian's ROS 1
packages (``/usr/share/<pkg>/msg/<Type>.msg``); a model's ``msg_paths``
add ``<pkg>/msg/<Type>.msg`` files, which take precedence.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

PRIMITIVES = ("bool", "int8", "uint8", "int16", "uint16", "int32", "uint32",
              "int64", "uint64", "float32", "float64")
ALIASES = {"char": "uint8", "byte": "int8"}
#: The default maximum of a carried string or variable-length array (rule 4.15).
DEFAULT_MAX = 128
#: Where Debian's ROS 1 packages put their message definitions.
STANDARD_ROOT = Path("/usr/share")


class ReadingError(Exception):
    """Something this second reading does not understand (the two readings
    of the model then disagree: ``pyrosgen generate`` exits 2)."""


@dataclass(frozen=True)
class Raw:
    """A field as a ``.msg`` file writes it: ``kind`` is ``prim``,
    ``string``, ``msg`` or ``other``; ``card`` ``scalar``, ``array`` (then
    ``size``) or ``sequence``."""

    name: str
    kind: str
    base: str
    card: str
    size: int = 0


_PSEUDO = {
    "time": (Raw("sec", "prim", "uint32", "scalar"), Raw("nsec", "prim", "uint32", "scalar")),
    "duration": (Raw("sec", "prim", "int32", "scalar"), Raw("nsec", "prim", "int32", "scalar")),
}

_TYPE = re.compile(r"([A-Za-z0-9_/]+)(?:\[([0-9]*)\])?")


def parse_msg(text: str, pkg: str, origin: str, *, defaults: bool = False) -> tuple[Raw, ...]:
    """The fields of a ROS 1 ``.msg`` text of package ``pkg`` (constants
    and comments skipped).  ``defaults``: a field may have a default value
    after its name, as ROS 2's ``.msg`` files of the installation write
    (``float64 w 1`` in ``geometry_msgs/Quaternion``); it says nothing of
    the field's type, so it is skipped.  Only the installation's standard
    definitions are read so; ROS 1 has no such syntax, and the front end
    refuses it in a model's own ``.msg`` files."""
    out = []
    for n, line in enumerate(text.splitlines(), start=1):
        body = line.strip()
        if not body or body.startswith("#"):
            continue
        m = re.match(r"(\S+)\s+([A-Za-z][A-Za-z0-9_]*)\s*(=)?", body)
        if m is None:
            raise ReadingError(f"{origin}:{n}: cannot read the line {body!r}")
        if m.group(3):  # a constant: TYPE NAME=VALUE
            continue
        rest = body[m.end():].strip()
        if rest and not rest.startswith("#") and not (defaults and body[m.end() - 1:m.end()].isspace()):
            raise ReadingError(f"{origin}:{n}: cannot read the line {body!r}")
        tm = _TYPE.fullmatch(m.group(1))
        if tm is None:
            raise ReadingError(f"{origin}:{n}: cannot read the type {m.group(1)!r}")
        base, size = tm.group(1), tm.group(2)
        card = "scalar" if size is None else ("sequence" if size == "" else "array")
        base = ALIASES.get(base, base)
        if base in PRIMITIVES:
            kind = "prim"
        elif base == "string":
            kind = "string"
        elif base in ("time", "duration"):
            kind = "msg"
        elif base == "Header":
            kind, base = "msg", "std_msgs/Header"
        elif re.fullmatch(r"[a-z][a-z0-9_]*/[A-Za-z][A-Za-z0-9]*", base):
            kind = "msg"
        elif re.fullmatch(r"[A-Za-z][A-Za-z0-9]*", base):
            kind, base = "msg", f"{pkg}/{base}"
        else:
            kind = "other"
        out.append(Raw(m.group(2), kind, base, card, int(size) if size else 0))
    return tuple(out)


@dataclass(frozen=True)
class Field:
    """A carried field: ``prim`` (a primitive) or ``msg`` (a C struct name),
    ``count`` the size of a fixed-size array (``None``: a scalar)."""

    name: str
    prim: str | None
    msg: str | None
    count: int | None = None

    def text(self) -> str:
        base = self.prim if self.prim is not None else f"msg {self.msg}"
        return base if self.count is None else f"array {self.count} {base}"


def c_name(ros_type: str) -> str:
    """The C struct of a message type: ``pkg_Type``, ``ros_time``."""
    if ros_type in ("time", "duration"):
        return f"ros_{ros_type}"
    return ros_type.replace("/", "_")


class Messages:
    """The message definitions of one model, and their carried view
    given the carried strings and sequences (``carried``: (type, field)
    -> maximum, ``(type, 'name[]')`` the strings of an array of strings;
    ``reject``: those of policy reject)."""

    def __init__(self, msg_dirs=(), standard_root: Path = STANDARD_ROOT):
        self.standard_root = Path(standard_root)
        self.custom: dict[str, tuple[Raw, ...]] = {}
        self._std: dict[str, tuple[Raw, ...] | None] = {}
        for d in msg_dirs:
            for f in sorted(Path(d).glob("*/msg/*.msg")):
                pkg = f.parent.parent.name
                self.custom[f"{pkg}/{f.stem}"] = parse_msg(f.read_text(encoding="utf-8"), pkg, str(f))
        self.carried: dict[tuple[str, str], int] = {}
        self.reject: set[tuple[str, str]] = set()
        #: C struct name -> its carried fields, for every struct seen
        self.structs: dict[str, tuple[Field, ...]] = {}
        #: C struct name -> the structs its fields use (in field order)
        self._view: dict[str, str | None] = {}

    def raw(self, ros_type: str) -> tuple[Raw, ...]:
        if ros_type in _PSEUDO:
            return _PSEUDO[ros_type]
        if ros_type in self.custom:
            return self.custom[ros_type]
        if ros_type not in self._std:
            pkg, _, typ = ros_type.partition("/")
            f = self.standard_root / pkg / "msg" / f"{typ}.msg"
            self._std[ros_type] = (parse_msg(f.read_text(encoding="utf-8"), pkg, str(f), defaults=True)
                                   if f.is_file() else None)
        got = self._std[ros_type]
        if got is None:
            pkg = ros_type.partition("/")[0]
            raise ReadingError(f"no definition of message type {ros_type!r}: not in {self.standard_root}/{pkg}/msg "
                               f"(Debian's ROS 1 package ros-{pkg.replace('_', '-')}) nor in the model's msg_paths")
        return got

    def field(self, ros_type: str, name: str) -> Raw:
        for f in self.raw(ros_type):
            if f.name == name:
                return f
        raise ReadingError(f"message type {ros_type} has no field {name!r}")

    # -- the carried view ----------------------------------------------------

    def _bounded(self, name: str, data: Field) -> str:
        self.structs[name] = (Field("len", "uint32", None), Field("truncated", "bool", None), data)
        return name

    def _string(self, n: int, reject: bool) -> str:
        return self._bounded(f"ros_{'r' if reject else ''}string{n}", Field("data", "uint8", None, n))

    def view(self, ros_type: str, depth: int = 0) -> str | None:
        """The C struct name of ``ros_type``'s carried view (recorded in
        :attr:`structs`), ``None`` when it carries nothing."""
        if ros_type in self._view:
            return self._view[ros_type]
        if depth > 64:
            raise ReadingError(f"message type {ros_type} nests too deep")
        fields = []
        for f in self.raw(ros_type):
            key = (ros_type, f.name)
            rej = "r" if key in self.reject else ""
            if f.card == "array" and f.size == 0:
                continue
            if f.kind == "prim":
                if f.card == "sequence":
                    if key in self.carried:
                        n = self.carried[key]
                        fields.append(Field(f.name, None, self._bounded(
                            f"ros_{rej}seq_{f.base}_{n}", Field("data", f.base, None, n))))
                    continue
                fields.append(Field(f.name, f.base, None, f.size if f.card == "array" else None))
            elif f.kind == "string":
                if key not in self.carried:
                    continue
                n = self.carried[key]
                if f.card == "scalar":
                    fields.append(Field(f.name, None, self._string(n, bool(rej))))
                elif f.card == "sequence":
                    m = self.carried.get((ros_type, f.name + "[]"), DEFAULT_MAX)
                    elem = self._string(m, False)
                    fields.append(Field(f.name, None, self._bounded(
                        f"ros_{rej}seq_string{m}_{n}", Field("data", None, elem, n))))
            elif f.kind == "msg":
                sub = self.view(f.base, depth + 1)
                if sub is None:
                    continue
                if f.card == "sequence":
                    if key in self.carried:
                        n = self.carried[key]
                        fields.append(Field(f.name, None, self._bounded(
                            f"ros_{rej}seq_{sub}_{n}", Field("data", None, sub, n))))
                    continue
                fields.append(Field(f.name, None, sub, f.size if f.card == "array" else None))
        name = c_name(ros_type) if fields else None
        if name is not None:
            self.structs[name] = tuple(fields)
        self._view[ros_type] = name
        return name

    def used(self, roots) -> list[str]:
        """The C structs that the message types ``roots`` use, each after
        the structs it contains (depth first, in field order)."""
        order: list[str] = []
        done: set[str] = set()

        def visit(struct: str) -> None:
            if struct in done:
                return
            done.add(struct)
            for f in self.structs[struct]:
                if f.msg is not None:
                    visit(f.msg)
            order.append(struct)

        for r in roots:
            s = self.view(r)
            if s is not None:
                visit(s)
        return order

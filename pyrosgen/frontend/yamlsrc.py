"""Loading a YAML file into a small tree that remembers where each node was.

The node model is read with pyyaml's *composer* (SafeLoader), not its
constructor, so that every mapping, sequence and scalar keeps its line and
column for error messages.  Only the part of YAML a node model needs is
accepted:

- one document whose top level is a mapping;
- the core tags only (str, int, float, bool, null, timestamp, seq, map);
- no anchors or aliases (they have no use in a node model, and refusing them
  also defeats "billion laughs" expansion bombs);
- no duplicate mapping keys (YAML silently keeps the last one; we refuse);
- at most :data:`MAX_DEPTH` levels of nesting and :data:`MAX_FILE_SIZE` bytes;
- UTF-8 text without NUL or other non-printable characters.

Problems that stop parsing are raised as :class:`InvalidNodeModel` with one
diagnostic; problems found while walking the tree (bad tags, duplicate keys)
are collected and returned with the tree so that later checks can add theirs.
"""

from __future__ import annotations

import os
import stat
import re
from dataclasses import dataclass, field
from pathlib import Path

import yaml

from pyrosgen.errors import Diagnostic, InvalidNodeModel, escape, show

__all__ = [
    "MAX_FILE_SIZE",
    "MAX_DEPTH",
    "YNode",
    "YScalar",
    "YSeq",
    "YMap",
    "YBad",
    "YamlDoc",
    "read_text",
    "parse_yaml",
    "load_yaml",
]

#: Largest accepted model file, in bytes (checked before parsing).
MAX_FILE_SIZE = 1024 * 1024

#: Deepest accepted nesting of YAML collections.
MAX_DEPTH = 64

_CORE = "tag:yaml.org,2002:"
_SCALAR_TAGS = {
    _CORE + "str": "str",
    _CORE + "int": "int",
    _CORE + "float": "float",
    _CORE + "bool": "bool",
    _CORE + "null": "null",
    _CORE + "timestamp": "timestamp",
}
_SEQ_TAG = _CORE + "seq"
_MAP_TAG = _CORE + "map"

# The characters pyyaml's reader refuses (its NON_PRINTABLE set).
_NON_PRINTABLE = re.compile(
    "[^\x09\x0a\x0d\x20-\x7e\x85\xa0-\ud7ff\ue000-\ufffd\U00010000-\U0010ffff]"
)


# --------------------------------------------------------------------------
# The tree


@dataclass(frozen=True)
class YNode:
    """A YAML node with its 1-based position in the source file."""

    line: int
    col: int

    @property
    def pos(self) -> tuple[int, int]:
        """``(line, col)`` of the node."""
        return (self.line, self.col)


@dataclass(frozen=True)
class YScalar(YNode):
    """A scalar: ``value`` is the constructed Python value, ``text`` the source
    text, ``kind`` one of ``str int float bool null timestamp``."""

    value: object
    text: str
    kind: str

    def describe(self) -> str:
        """A short description for "expected X, got Y" messages."""
        if self.kind == "str":
            return f"string {show(self.value)}"
        if self.kind == "null":
            return "null (an empty value)"
        if self.kind == "bool":
            return f"boolean {show(self.text)}"
        if self.kind == "timestamp":
            return f"date {show(self.text)}"
        return f"{self.kind} {show(self.text)}"


@dataclass(frozen=True)
class YSeq(YNode):
    """A sequence."""

    items: tuple[YNode, ...]

    def describe(self) -> str:
        """A short description for "expected X, got Y" messages."""
        return "a list"


@dataclass(frozen=True)
class YMap(YNode):
    """A mapping whose keys are the source text of scalar keys.

    Duplicate and non-scalar keys have already been reported and dropped; the
    first occurrence of a key wins.
    """

    items: tuple[tuple[YScalar, YNode], ...]
    owner: tuple[int, int] | None = None

    def describe(self) -> str:
        """A short description for "expected X, got Y" messages."""
        return "a mapping"

    @property
    def owner_pos(self) -> tuple[int, int]:
        """Position of the key this mapping is the value of (the mapping's own
        position for the top level and list items): where a missing key is
        reported."""
        return self.owner if self.owner is not None else (self.line, self.col)

    def keys(self) -> list[str]:
        """The keys in source order."""
        return [k.text for k, _ in self.items]

    def get(self, key: str) -> YNode | None:
        """The value at ``key``, or ``None``."""
        for k, v in self.items:
            if k.text == key:
                return v
        return None

    def key_node(self, key: str) -> YScalar | None:
        """The key node of ``key``, or ``None``."""
        for k, _ in self.items:
            if k.text == key:
                return k
        return None


@dataclass(frozen=True)
class YBad(YNode):
    """A node that was already reported as invalid (for example an unsupported
    tag); later checks skip it silently."""

    def describe(self) -> str:
        """A short description for "expected X, got Y" messages."""
        return "an invalid node"


@dataclass
class YamlDoc:
    """A parsed model file: its root node and the problems found on the way."""

    file: str
    root: YMap
    diagnostics: list[Diagnostic] = field(default_factory=list)


# --------------------------------------------------------------------------
# Reading bytes


class _Fatal(Exception):
    """Internal: a problem that stops parsing."""

    def __init__(self, line: int | None, col: int | None, message: str):
        super().__init__(message)
        self.line = line
        self.col = col
        self.message = message


def _line_col_of_byte(data: bytes, index: int) -> tuple[int, int]:
    before = data[:index]
    line = before.count(b"\n") + 1
    last = before.rsplit(b"\n", 1)[-1]
    return line, len(last.decode("utf-8", errors="replace")) + 1


def _line_col_of_char(text: str, index: int) -> tuple[int, int]:
    before = text[:index]
    line = before.count("\n") + 1
    return line, index - (before.rfind("\n") + 1) + 1


def read_text(path: str | Path, what: str = "file", limit: int = MAX_FILE_SIZE, rule: str = "4.1",
              regular_only: bool = False) -> str:
    """Read a UTF-8 text file of at most ``limit`` bytes.

    Raises :class:`InvalidNodeModel` (one diagnostic) when the file cannot be
    read, is too large, contains NUL bytes or is not valid UTF-8, and, with
    ``regular_only`` (files pyrosgen finds itself, such as the ``.msg``
    files of ``msg_paths``), when it is not a regular file: a FIFO is then
    refused before anything waits for its writer.  A file the user names
    (the model) may be a pipe (``pyrosgen check /dev/stdin``).
    """
    name = str(path)

    def fail(message: str, line: int | None = None, col: int | None = None):
        raise InvalidNodeModel([Diagnostic(name, line, col, message, rule=rule)])

    def refuse(st: os.stat_result) -> None:
        kind = ("a directory" if stat.S_ISDIR(st.st_mode) else "a FIFO" if stat.S_ISFIFO(st.st_mode)
                else "a device" if stat.S_ISCHR(st.st_mode) or stat.S_ISBLK(st.st_mode)
                else "a socket" if stat.S_ISSOCK(st.st_mode) else "not a regular file")
        fail(f"cannot read {what}: it is {kind}, not a regular file")

    try:
        before = None
        if regular_only:
            # stat (through symbolic links) before opening: a FIFO, a
            # device or a socket is refused without being opened at all
            # (opening a device can have effects of its own)
            before = os.stat(path)
            if not stat.S_ISREG(before.st_mode):
                refuse(before)
        # O_NONBLOCK: should the path have become a FIFO since, opening it
        # must not wait for a writer; it is then refused by the fstat below
        flags = os.O_RDONLY | os.O_NOCTTY | getattr(os, "O_CLOEXEC", 0) | (os.O_NONBLOCK if regular_only else 0)
        fd = os.open(path, flags)
        with open(fd, "rb") as fh:
            st = os.fstat(fh.fileno())
            if stat.S_ISDIR(st.st_mode) or (regular_only and not stat.S_ISREG(st.st_mode)):
                refuse(st)
            if before is not None and (st.st_dev, st.st_ino) != (before.st_dev, before.st_ino):
                fail(f"cannot read {what}: it was replaced while being read")
            size = st.st_size if stat.S_ISREG(st.st_mode) else 0
            if size > limit:
                fail(f"{what} too large ({size} bytes; the limit is {limit} bytes)")
            data = fh.read(limit + 1)
    except IsADirectoryError:
        fail(f"cannot read {what}: it is a directory")
    except OSError as exc:
        reason = exc.strerror or type(exc).__name__
        fail(f"cannot read {what}: {reason}")
    except ValueError:  # e.g. a NUL character in the path
        fail(f"cannot read {what}: invalid file name")
    if len(data) > limit:
        fail(f"{what} too large (more than {limit} bytes)")
    return decode_text(data, name, what, rule)


def decode_text(data: bytes, name: str, what: str = "file", rule: str = "4.1") -> str:
    """Decode UTF-8 bytes, refusing NUL bytes, other encodings and binary data."""

    def fail(message: str, line: int | None = None, col: int | None = None):
        raise InvalidNodeModel([Diagnostic(name, line, col, message, rule=rule)])

    if data.startswith((b"\xff\xfe", b"\xfe\xff")):
        fail(f"{what} is not UTF-8 (it starts with a UTF-16 byte-order mark)", 1, 1)
    nul = data.find(b"\x00")
    if nul >= 0:
        line, col = _line_col_of_byte(data, nul)
        fail(f"{what} contains a NUL byte (binary file?)", line, col)
    if data.startswith(b"\xef\xbb\xbf"):
        data = data[3:]
    try:
        text = data.decode("utf-8", errors="strict")
    except UnicodeDecodeError as exc:
        line, col = _line_col_of_byte(data, exc.start)
        fail(f"{what} is not valid UTF-8 (byte 0x{data[exc.start]:02x})", line, col)
    bad = _NON_PRINTABLE.search(text)
    if bad:
        line, col = _line_col_of_char(text, bad.start())
        fail(
            f"{what} contains the non-printable character "
            f"U+{ord(bad.group()):04X} (binary file?)",
            line,
            col,
        )
    return text


# --------------------------------------------------------------------------
# Parsing


class _Loader(yaml.SafeLoader):
    """SafeLoader's composer, refusing anchors, aliases and deep nesting."""

    def __init__(self, stream):
        super().__init__(stream)
        self._depth = 0

    def compose_node(self, parent, index):  # noqa: D102 - pyyaml hook
        event = self.peek_event()
        if isinstance(event, yaml.AliasEvent):
            m = event.start_mark
            raise _Fatal(
                m.line + 1,
                m.column + 1,
                f"YAML alias *{_anchor(event.anchor)} is not allowed: "
                "a node model uses no anchors or aliases",
            )
        if getattr(event, "anchor", None) is not None:
            m = event.start_mark
            raise _Fatal(
                m.line + 1,
                m.column + 1,
                f"YAML anchor &{_anchor(event.anchor)} is not allowed: "
                "a node model uses no anchors or aliases",
            )
        self._depth += 1
        if self._depth > MAX_DEPTH:
            m = event.start_mark
            raise _Fatal(
                m.line + 1,
                m.column + 1,
                f"YAML nesting too deep (more than {MAX_DEPTH} levels)",
            )
        try:
            return super().compose_node(parent, index)
        finally:
            self._depth -= 1

    def resolve(self, kind, value, implicit):  # noqa: D102 - pyyaml hook
        # Only plain scalars without an explicit tag get here with
        # implicit[0]; a number form a node model refuses gets a tag of its
        # own, so that it is reported (and never constructed) by the walker.
        tag = super().resolve(kind, value, implicit)
        if kind is yaml.ScalarNode and implicit[0] and _refused_number_form(value, tag):
            return _NUMBER_FORM
        return tag


_PLAIN_KEY = re.compile(r"[A-Za-z_][A-Za-z0-9_]{0,63}")
#: The integers a node model writes: decimal, no leading zero, no "_".
_DECIMAL_INT = re.compile(r"[-+]?(?:0|[1-9][0-9]*)")
_DECIMAL_FLOAT = re.compile(r"[-+]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][-+]?[0-9]+)?")
#: Plain scalars that YAML 1.1 reads as text but that look like numbers
#: written in a form a user may mean otherwise: ``08`` (a leading zero),
#: ``0o20`` (YAML 1.2's octal), ``1:60`` or ``0:20`` (base 60).
_LEADING_ZERO = re.compile(r"[-+]?0[0-9_]+")
_OCTAL_12 = re.compile(r"[-+]?0[oO][0-7_]+")
_SEXAGESIMAL_LIKE = re.compile(r"[-+]?[0-9][0-9_]*(?::[0-9_]+)+(?:\.[0-9_]*)?")

#: The tag the loader's resolver gives a plain scalar written in a number
#: form that is refused (rule 4.1): such a scalar is never constructed, so
#: neither its value nor the time to compute it (``1:59:59:...``) matters.
_NUMBER_FORM = "tag:pyrosgen,2026:refused-number-form"

#: Longest integer text constructed (rule 4.2's and 4.4's ranges need 7).
_MAX_INT_TEXT = 100


def _refused_number_form(value: str, tag: str) -> bool:
    """Whether the plain scalar ``value``, resolved by YAML 1.1 to ``tag``,
    is written in a number form a node model refuses."""
    if tag == _CORE + "int":
        return not _DECIMAL_INT.fullmatch(value)
    if tag == _CORE + "float":
        return not _DECIMAL_FLOAT.fullmatch(value)
    if tag == _CORE + "str":
        return bool(_LEADING_ZERO.fullmatch(value) or _OCTAL_12.fullmatch(value)
                    or _SEXAGESIMAL_LIKE.fullmatch(value))
    return False


def _number_form_problem(text: str, key: str | None = None) -> str:
    """Why the plain scalar ``text`` (see :func:`_refused_number_form`) is
    refused.  YAML 1.1 reads some plain numbers unlike what a user means:
    ``020`` is octal 16, ``1:20`` is sexagesimal 80, ``0x10``, ``0b11`` and
    ``1_000`` are numbers too, and ``08`` is text.  A node model's numbers
    are plain decimals; any other form is refused (rule 4.1) rather than
    read silently."""
    where = f"{key}: " if key else ""
    body = text.lstrip("+-")
    if re.fullmatch(r"0[0-7_]+", body) and re.search(r"[0-7]", body):
        value = int(body.replace("_", ""), 8) * (-1 if text.startswith("-") else 1)
        why = f"a leading zero makes it octal in YAML 1.1 (it would be read as {value})"
    elif re.fullmatch(r"0[0-9_]+", body):
        why = ("a leading zero makes it ambiguous (YAML 1.1 reads 010 as octal 8 "
               f"and {text} as text)")
    elif _OCTAL_12.fullmatch(text):
        why = "it is octal in YAML 1.2's form, which YAML 1.1 reads as text"
    elif ":" in body:
        if re.fullmatch(r"[1-9][0-9_]*(?::[0-5]?[0-9])+(?:\.[0-9_]*)?", body):
            why = "YAML 1.1 reads it as a base-60 (sexagesimal) number"
        else:
            why = "it looks like a base-60 (sexagesimal) number (YAML 1.1 reads 1:20 as 80)"
    elif re.fullmatch(r"0[xX].*", body):
        why = "it is hexadecimal"
    elif re.fullmatch(r"0[bB].*", body):
        why = "it is binary"
    elif body.lower() in (".inf", ".nan"):
        why = "it is not a finite number"
    elif "_" in body:
        why = "it has '_' separators"
    else:
        why = "it is not a plain decimal number"
    return (f"{where}number {show(text)}: {why}; write numbers in plain decimal, without "
            "leading zeros (quote it if it is meant as text)")


def _tag(tag: str) -> str:
    if tag.startswith(_CORE):
        tag = "!!" + tag[len(_CORE):]
    return show(tag)


def _anchor(name: object) -> str:
    return show(name)[1:-1]


def _mark_pos(mark) -> tuple[int | None, int | None]:
    if mark is None:
        return None, None
    return mark.line + 1, mark.column + 1


def _yaml_error_message(exc: yaml.YAMLError) -> str:
    if isinstance(exc, yaml.MarkedYAMLError):
        problem = exc.problem or "invalid YAML"
        if "expected a single document" in f"{problem} {exc.context}":
            return "several YAML documents in one file: a node model is a single document"
        text = f"YAML syntax error: {problem}"
        if exc.context:
            text += f" ({exc.context})"
        if "but got '['" in problem and "flow" in (exc.context or ""):
            text += ('; inside {...} a field path with an index must be quoted, e.g. "pose.covariance[35]" '
                     '(and a controller array\'s type, e.g. "float32[8]")')
        if "found character '>' that cannot start any token" in problem or (
                "chomping or indentation indicators" in problem):
            text += "; a value that starts with '>' must be quoted, e.g. operator: '>='"
    else:
        text = f"YAML error: {exc}"
    return escape(" ".join(text.split()), keep_quotes=True)


def parse_yaml(text: str, name: str) -> YamlDoc:
    """Parse ``text`` (the content of file ``name``) into a :class:`YamlDoc`.

    Raises :class:`InvalidNodeModel` for problems that stop parsing.
    """
    loader = _Loader(text)
    try:
        try:
            node = loader.get_single_node()
        finally:
            loader.dispose()
    except _Fatal as exc:
        raise InvalidNodeModel([Diagnostic(name, exc.line, exc.col, exc.message, rule="4.1")]) from None
    except yaml.MarkedYAMLError as exc:
        mark = exc.problem_mark or exc.context_mark
        line, col = _mark_pos(mark)
        raise InvalidNodeModel(
            [Diagnostic(name, line, col, _yaml_error_message(exc), rule="4.1")]
        ) from None
    except yaml.reader.ReaderError as exc:
        line, col = _line_col_of_char(text, exc.position)
        raise InvalidNodeModel(
            [Diagnostic(name, line, col, f"unreadable character: {' '.join(str(exc).split())}", rule="4.1")]
        ) from None
    except yaml.YAMLError as exc:
        raise InvalidNodeModel([Diagnostic(name, 1, 1, _yaml_error_message(exc), rule="4.1")]) from None
    except RecursionError:
        raise InvalidNodeModel(
            [Diagnostic(name, 1, 1, "YAML nesting too deep", rule="4.1")]
        ) from None

    if node is None:
        raise InvalidNodeModel(
            [
                Diagnostic(
                    name,
                    1,
                    1,
                    "empty document: a node model is a mapping with the keys "
                    "node, controller, topics and relations",
                    rule="4.1",
                )
            ]
        )
    walker = _Walker(name)
    root = walker.walk(node)
    if not isinstance(root, YMap):
        if isinstance(root, YBad):
            raise InvalidNodeModel(walker.diagnostics)
        raise InvalidNodeModel(
            walker.diagnostics
            + [
                Diagnostic(
                    name,
                    root.line,
                    root.col,
                    f"the top level of a node model must be a mapping, not {root.describe()}",
                    rule="4.1",
                )
            ]
        )
    return YamlDoc(name, root, walker.diagnostics)


def load_yaml(path: str | Path) -> YamlDoc:
    """Read and parse the model file at ``path``."""
    return parse_yaml(read_text(path), str(path))


class _Walker:
    """Turns pyyaml nodes into Y* nodes, collecting problems."""

    def __init__(self, name: str):
        self.name = name
        self.diagnostics: list[Diagnostic] = []
        self._constructor = yaml.SafeLoader("")

    def error(self, node: yaml.Node, message: str) -> None:
        line, col = _mark_pos(node.start_mark)
        self.diagnostics.append(Diagnostic(self.name, line, col, message, rule="4.1"))

    def walk(self, node: yaml.Node, owner: tuple[int, int] | None = None, key: str | None = None) -> YNode:
        # Depth was bounded by the composer, so recursion here is shallow.
        line, col = _mark_pos(node.start_mark)
        if isinstance(node, yaml.ScalarNode):
            if node.tag == _NUMBER_FORM:
                self.error(node, _number_form_problem(node.value, key))
                return YBad(line, col)
            kind = _SCALAR_TAGS.get(node.tag)
            if kind is None:
                hint = ""
                if node.tag.startswith("!") and not node.tag.startswith("!!") and node.value == "":
                    # `operator: !=` reads as the local tag !=
                    hint = f"; a value that starts with '!' must be quoted, e.g. {show(node.tag)}"
                self.error(node, f"unsupported YAML tag {_tag(node.tag)}: only plain values are allowed{hint}")
                return YBad(line, col)
            if kind == "str":
                return YScalar(line, col, node.value, node.value, kind)
            if kind in ("int", "float") and _refused_number_form(
                    node.value, self._constructor.resolve(yaml.ScalarNode, node.value, (True, False))):
                # an explicit tag (!!int 020) is not seen by the resolver
                self.error(node, _number_form_problem(node.value, key))
                return YBad(line, col)
            where = f"{key}: " if key else ""
            if kind == "int" and len(node.value) > _MAX_INT_TEXT:
                # int() of a long decimal takes quadratic time (and Python
                # refuses more than 4300 digits); no node model number is
                # anywhere near this long
                self.error(node, f"{where}number {show(node.value)} is too long "
                                 f"({len(node.value)} characters)")
                return YBad(line, col)
            try:
                ctor = getattr(self._constructor, f"construct_yaml_{kind}")
                value = ctor(node)
            except Exception:  # noqa: BLE001 - any failure is a user error here
                self.error(node, f"{where}invalid {kind} value {show(node.value)}")
                return YBad(line, col)
            return YScalar(line, col, value, node.value, kind)
        if isinstance(node, yaml.SequenceNode):
            if node.tag != _SEQ_TAG:
                self.error(node, f"unsupported YAML tag {_tag(node.tag)} on a list")
                return YBad(line, col)
            return YSeq(line, col, tuple(self.walk(n, None, f"{key}[{i}]" if key else None)
                                         for i, n in enumerate(node.value)))
        if isinstance(node, yaml.MappingNode):
            if node.tag != _MAP_TAG:
                self.error(node, f"unsupported YAML tag {_tag(node.tag)} on a mapping")
                return YBad(line, col)
            seen: dict[str, YScalar] = {}
            items: list[tuple[YScalar, YNode]] = []
            for knode, vnode in node.value:
                if not isinstance(knode, yaml.ScalarNode):
                    self.error(knode, "mapping keys must be plain names, not lists or mappings")
                    continue
                if knode.tag == _CORE + "merge":
                    self.error(knode, "YAML merge keys (<<) are not allowed in a node model")
                    continue
                if knode.tag not in _SCALAR_TAGS and knode.tag != _NUMBER_FORM:
                    self.error(knode, f"unsupported YAML tag {_tag(knode.tag)} on a key")
                    continue
                kl, kc = _mark_pos(knode.start_mark)
                key = YScalar(kl, kc, knode.value, knode.value, "str")
                if knode.value in seen:
                    first = seen[knode.value]
                    self.error(
                        knode,
                        f"duplicate key {show(knode.value)} (first defined at line {first.line})",
                    )
                    continue
                seen[knode.value] = key
                items.append((key, self.walk(vnode, (kl, kc), knode.value if _PLAIN_KEY.fullmatch(knode.value) else None)))
            return YMap(line, col, tuple(items), owner)
        # pragma: no cover - pyyaml composes only the three node kinds
        self.error(node, "unsupported YAML node")
        return YBad(line, col)

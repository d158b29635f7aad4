"""Rule 4.14 (constant strings): ``frame_id`` and ``strings`` on a published
topic, each a string of printable text that fits its field.
"""

from __future__ import annotations

from dataclasses import dataclass
import unicodedata

from pyrosgen.errors import show
from pyrosgen.frontend.checker import Checker, TopicDecl
from pyrosgen.frontend.model import PUBLISH, Pos, StringConstant
from pyrosgen.frontend.msgload import MsgRegistry, PathError, StringTarget
from pyrosgen.frontend.msgmodel import STRING_CAPACITY
from pyrosgen.frontend.yamlsrc import YBad, YMap, YNode, YScalar


#: The field ``frame_id: <string>`` gives a constant (rule 4.14), and the
#: type of the ``header`` it needs.
FRAME_ID_FIELD = "header.frame_id"


HEADER_TYPE = "std_msgs/Header"


@dataclass
class _StrItem:
    """A constant string as written: ``what`` names it in messages,
    ``key`` is where a problem of its path is reported, ``value`` its
    value's node; ``target`` the string field it names, or ``problem``
    why its path names none."""

    what: str
    key: YNode
    value: YNode
    target: StringTarget | None = None
    problem: str | None = None


def string_items(m: YMap, msg_type: str, registry: MsgRegistry, what: str) -> list[_StrItem]:
    """The constant strings of the topic declared by ``m``, whose message
    type is ``msg_type`` (a known type), with the field each names: its
    ``frame_id`` (``header.frame_id``, in a ``std_msgs/Header header``) and
    each entry of its ``strings`` mapping (not checked here to be one)."""
    out: list[_StrItem] = []
    for key, value in m.items:
        if key.text == "frame_id":
            it = _StrItem(f"{what}.frame_id", value, value)
            raw = registry.raw(msg_type)
            header = raw.field("header") if raw is not None else None
            if header is None or header.card != "scalar" or header.base != HEADER_TYPE:
                it.problem = (f"message type {msg_type} has no field 'header' of type {HEADER_TYPE} "
                              f"(frame_id sets {FRAME_ID_FIELD}; strings sets any other string field)")
            else:
                it.target = registry.walk_string_path(msg_type, FRAME_ID_FIELD)
            out.append(it)
        elif key.text == "strings" and isinstance(value, YMap):
            for k, v in value.items:
                it = _StrItem(f"{what}.strings[{show(k.text)}]", k, v)
                if k.kind != "str":
                    it.problem = f"a key of strings is a field path, got {k.describe()}"
                else:
                    try:
                        it.target = registry.walk_string_path(msg_type, k.value)
                    except PathError as exc:
                        it.problem = exc.args[0]
                out.append(it)
    return out


#: The Unicode categories a constant string may not hold (rule 4.14), and
#: how a message names them: controls (C0, DEL, C1 such as U+0085 and
#: U+009B), invisible format characters (U+202E reverses the text shown
#: after it, U+FEFF), surrogates, private-use and unassigned code points
#: (U+FFFE), line and paragraph separators (U+2028, U+2029).
_NOT_PRINTABLE = {
    "Cc": "control character",
    "Cf": "invisible format character",
    "Cs": "surrogate",
    "Co": "private-use character",
    "Cn": "unassigned code point",
    "Zl": "line separator",
    "Zp": "paragraph separator",
}


def _string_value(node: YNode, capacity: int = STRING_CAPACITY) -> tuple[str | None, str | None]:
    """The constant written at ``node`` and why it is not one: a YAML
    string of printable text, at most ``capacity`` bytes in UTF-8 (the
    capacity of its field: :data:`STRING_CAPACITY` unless a
    ``max_length`` says otherwise, rule 4.15; ``''``, the empty string, is
    one)."""
    if not (isinstance(node, YScalar) and node.kind == "str"):
        hint = ""
        if isinstance(node, YScalar) and node.kind in ("bool", "int", "float", "timestamp"):
            hint = " (quote it if you mean the text)"
        elif isinstance(node, YScalar) and node.kind == "null":
            hint = " (write '' for the empty string)"
        return None, f"must be a string, got {node.describe()}{hint}"
    value = node.value
    try:
        data = value.encode("utf-8")
    except UnicodeEncodeError as exc:
        return None, (f"is not valid Unicode text: it holds the lone surrogate U+{ord(value[exc.start]):04X} "
                      f"(character {exc.start + 1})")
    for i, ch in enumerate(value):
        kind = _NOT_PRINTABLE.get(unicodedata.category(ch))
        if kind is not None:
            return None, (f"contains the {kind} U+{ord(ch):04X} (character {i + 1}); "
                          "a constant string holds printable text")
    if len(data) > capacity:
        extra = "" if capacity == STRING_CAPACITY else " (its field's max_length)"
        return None, (f"is {len(data)} bytes long in UTF-8; a carried string holds at most "
                      f"{capacity} bytes{extra}")
    return value, None


def check_strings(ck: Checker, decls: list[TopicDecl], registry: MsgRegistry) -> None:
    """Rule 4.14: ``frame_id: <string>`` (the constant of
    ``header.frame_id``, in a ``std_msgs/Header header``) and ``strings:
    {<field path>: <string>}`` (any ``string`` field, through nested
    messages and fixed-size arrays of messages) on a published topic:
    each value a string of printable text of at most
    :data:`STRING_CAPACITY` bytes in UTF-8, each field named once.  Sets
    ``strings`` on the topics whose constants all pass, in the order the
    model writes them.  (A relation naming a string field is refused
    where relations are checked.)"""
    rule = "4.14"
    for d in decls:
        fnode, snode = d.node.get("frame_id"), d.node.get("strings")
        if fnode is None and snode is None:
            continue
        ok = True
        for key, node in (("frame_id", fnode), ("strings", snode)):
            if node is None or isinstance(node, YBad):
                continue
            if d.direction is not None and d.direction != PUBLISH:
                ck.err_rule(rule, node, f"{d.what}.{key}: topic {show(d.name)} is subscribed by the node; "
                                        "a constant string is for a published topic")
                ok = False
            elif key == "strings" and not isinstance(node, YMap):
                ck.err_rule(rule, node, f"{d.what}.strings must be a mapping of field paths to strings, "
                                        f"got {node.describe()}")
                ok = False
        if not ok or d.direction != PUBLISH:
            continue
        msg_type = d.msg_type if d.type_ok else None
        if msg_type is not None:
            items = string_items(d.node, msg_type, registry, d.what)
        else:  # the type is reported; the values are checked all the same
            items = [_StrItem(f"{d.what}.frame_id", fnode, fnode)] if fnode is not None else []
            items += [_StrItem(f"{d.what}.strings[{show(k.text)}]", k, v)
                      for k, v in (snode.items if isinstance(snode, YMap) else ())]
        seen: dict[tuple, _StrItem] = {}
        found: list[StringConstant] = []
        for it in items:
            if isinstance(it.value, YBad):
                ok = False
                continue
            capacity = (registry.capacity(it.target.owner, it.target.field) if it.target is not None
                         else None) or STRING_CAPACITY
            value, problem = _string_value(it.value, capacity)
            if problem is not None:
                ck.err_rule(rule, it.value, f"{it.what} {problem}" if problem.startswith(("must", "is ")) else
                            f"{it.what}: the string {problem}")
                ok = False
            if msg_type is None:
                ok = False  # the topic's type is reported
                continue
            if it.problem is not None:
                ck.err_rule(rule, it.key, f"{it.what}: {it.problem} (topic {show(d.name)}, {msg_type})")
                ok = False
                continue
            steps = it.target.steps
            d.constant_steps.setdefault(steps, (it.what, it.key.line))
            if steps in seen:
                first = seen[steps]
                ck.err_rule(rule, it.key, f"{it.what}: field {show(steps_text(steps))} of topic {show(d.name)} "
                                          f"already has a constant ({first.what}, line {first.key.line})")
                ok = False
                continue
            seen[steps] = it
            if value is not None:
                found.append(StringConstant(steps, value, Pos(it.key.line, it.key.col)))
        if ok:
            d.strings = found


def steps_text(steps) -> str:
    """Steps of a field path as the model writes them: ``header.frame_id``,
    ``poses[0].header``."""
    out = ""
    for s in steps:
        out += f"[{s}]" if isinstance(s, int) else ("." if out else "") + s
    return out

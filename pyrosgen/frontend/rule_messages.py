"""Rule 4.5 (message types): the message registry of one model, loaded
once, before the rules run.

:func:`load_messages` reads the custom ``.msg`` folders of ``msg_paths``
(:func:`msg_paths`) and tells the registry which strings and
variable-length arrays the glue carries, with their maxima and policies
(rules 4.14 and 4.15: the fields that constants name and that relations
read or write, read from the model as written, before the topics are
checked).  The rules then only query the registry; the problems it finds
in ``.msg`` files are collected once, at the end
(:func:`pyrosgen.frontend.validate.build_model`).
"""

from __future__ import annotations

from pathlib import Path

from pyrosgen.errors import InvalidNodeModel, show
from pyrosgen.frontend.checker import Checker
from pyrosgen.frontend.model import PUBLISH, SUBSCRIBE
from pyrosgen.frontend.msgload import MsgRegistry
from pyrosgen.frontend.msgmodel import DEFAULT_MAX_LENGTH
from pyrosgen.frontend.rule_sequences import max_length_items, policy_items
from pyrosgen.frontend.rule_strings import string_items
from pyrosgen.frontend.yamlsrc import YBad, YMap, YNode, YScalar, YSeq


def reserved_package(pkg: str) -> bool:
    """Whether a custom package may not be called ``pkg``: its C structs
    (``<pkg>_<Type>``) could be the glue's own ``ros_time``,
    ``ros_duration``, or names that the environment model takes for
    bounded sequences and strings (``ros_seq_...``, ``ros_string...``,
    of policy reject ``ros_rseq_...``, ``ros_rstring...``:
    ``Environment.bounded_name``, ``reject_name``; rule 4.15)."""
    return pkg == "ros" or pkg.startswith(("ros_seq", "ros_string", "ros_rseq", "ros_rstring"))


def msg_paths(ck: Checker, node: YNode | None, registry: MsgRegistry) -> list[Path]:
    """The custom message folders of ``msg_paths`` (rule 4.5), each read into
    ``registry``; returns those that exist, resolved (relative paths are
    relative to the model file)."""
    if node is None or isinstance(node, YBad):
        return []
    if isinstance(node, YScalar) and node.kind == "null":
        return []
    if not isinstance(node, YSeq):
        ck.err(node, f"msg_paths must be a list of folders, got {node.describe()}")
        return []
    out: list[Path] = []
    for i, item in enumerate(node.items):
        what = f"msg_paths[{i}]"
        text = ck.string(item, what)
        if text is None:
            continue
        if "\x00" in text:  # pragma: no cover - refused when reading the file
            ck.err(item, f"{what}: invalid path")
            continue
        p = Path(text)
        folder = p if p.is_absolute() else ck.base_dir / p
        try:
            resolved = folder.resolve()
            is_dir = folder.is_dir()
        except (OSError, RuntimeError, ValueError):
            resolved, is_dir = folder, False
        if not is_dir:
            ck.err(
                item,
                f"{what}: no such folder {show(text)} (relative paths are relative to the model file)",
            )
            continue
        if resolved in out:
            ck.err(item, f"{what}: folder {show(text)} is listed twice")
            continue
        out.append(resolved)
        reserved = sorted({f.parent.parent.name for f in resolved.glob("*/msg/*.msg")
                           if reserved_package(f.parent.parent.name)})
        if reserved:
            ck.err_rule("4.15", item,
                        f"{what}: folder {show(text)} holds the package {show(reserved[0])}: a package named "
                        "ros (or starting with ros_seq, ros_string, ros_rseq or ros_rstring) is refused, "
                        "its C structs could collide with the glue's own (ros_time, ros_duration, "
                        "ros_seq_<T>_<N>, ros_string<N>, ros_rseq_<T>_<N>, ros_rstring<N>)")
            continue
        try:
            n = registry.add_msg_dir(resolved)
        except InvalidNodeModel as exc:
            ck.err(item, f"{what}: {exc.diagnostics[0].message}")
            continue
        if n == 0:
            ck.err(
                item,
                f"{what}: folder {show(text)} contains no <package>/msg/<Type>.msg files",
            )
    return out


def _known_type(registry: MsgRegistry, node: YNode | None) -> str | None:
    """The message type written at ``node`` if it is a known one."""
    if not (isinstance(node, YScalar) and node.kind == "str"):
        return None
    t = node.value
    if t in registry.failed or registry.check_type_name(t) is not None or registry.raw(t) is None:
        return None
    return t


def _topic_types(node: YNode | None, registry: MsgRegistry) -> dict[str, tuple[YMap, str | None, str]]:
    """The topics as written, read before they are checked: name ->
    (declaration, direction, known message type)."""
    out: dict[str, tuple[YMap, str | None, str]] = {}
    if not isinstance(node, YSeq):
        return out
    for item in node.items:
        if not isinstance(item, YMap):
            continue
        name, dnode = item.get("name"), item.get("direction")
        msg_type = _known_type(registry, item.get("type"))
        if isinstance(name, YScalar) and name.kind == "str" and msg_type is not None and name.value not in out:
            direction = dnode.value if isinstance(dnode, YScalar) and dnode.kind == "str" else None
            out[name.value] = (item, direction, msg_type)
    return out


def carried_string_fields(node: YNode | None, registry: MsgRegistry) -> set[tuple[str, str]]:
    """The ``string`` fields that the constants of the published topics
    name (rule 4.14), as (message type, field name): the fields the glue
    carries.  Read before the topics are checked (a message type's carried
    view depends on it); nothing is reported here, :func:`check_strings`
    reports every problem of the same items."""
    out: set[tuple[str, str]] = set()
    if not isinstance(node, YSeq):
        return out
    for item in node.items:
        if not isinstance(item, YMap) or (item.get("frame_id") is None and item.get("strings") is None):
            continue
        dnode = item.get("direction")
        if not (isinstance(dnode, YScalar) and dnode.kind == "str" and dnode.value == PUBLISH):
            continue
        msg_type = _known_type(registry, item.get("type"))
        if msg_type is None:
            continue
        for it in string_items(item, msg_type, registry, ""):
            if it.target is not None:
                out.add((it.target.owner, it.target.field))
    return out


def carried_bounded_fields(topics: YNode | None, relations: YNode | None, registry: MsgRegistry,
                           declared: dict | None = None) -> dict[tuple[str, str], int]:
    """The strings and variable-length arrays of primitives the glue
    carries, as (message type, field name) -> capacity: the string fields
    that constants name (rule 4.14) and the strings and sequences that
    the input relations of subscribed topics read and the output
    relations of published topics write (rule 4.15), each with
    the ``max_length`` a topic gives it, or :data:`DEFAULT_MAX_LENGTH`.
    Read before the topics are checked (a message type's carried view
    depends on it); nothing is reported here, :func:`check_max_length` and
    the relations' checks report every problem of the same items.
    (``declared``: the topics' :func:`_topic_types`, when already read.)"""
    named = set(carried_string_fields(topics, registry))
    if declared is None:
        declared = _topic_types(topics, registry)
    maxima: dict[tuple[str, str], int] = {}
    for item, _direction, msg_type in declared.values():
        mnode = item.get("max_length")
        if isinstance(mnode, YMap):
            for it in max_length_items(mnode, msg_type, registry, ""):
                if it.target is not None and it.n is not None:
                    maxima.setdefault(it.target.key, it.n)
    for section, direction in (("inputs", SUBSCRIBE), ("outputs", PUBLISH)):
        rows = relations.get(section) if isinstance(relations, YMap) else None
        for row in rows.items if isinstance(rows, YSeq) else ():
            if not isinstance(row, YMap):
                continue
            tnode, fnode = row.get("topic"), row.get("field")
            if not (isinstance(tnode, YScalar) and tnode.kind == "str" and isinstance(fnode, YScalar)
                    and fnode.kind == "str"):
                continue
            info = declared.get(tnode.value)
            if info is None or info[1] != direction:
                continue
            for target in registry.bounded_along(info[2], fnode.value):
                named.add(target.key)
    return {key: maxima.get(key, DEFAULT_MAX_LENGTH) for key in sorted(named)}


def carried_reject_fields(topics: YNode | None, registry: MsgRegistry,
                          declared: dict | None = None) -> set[tuple[str, str]]:
    """The (message type, field name) pairs that a subscribed topic's
    ``policy`` gives policy reject (rule 4.15); read before the topics are
    checked, nothing is reported here (:func:`check_policy` does).
    (``declared``: the topics' :func:`_topic_types`, when already read.)"""
    out: set[tuple[str, str]] = set()
    if declared is None:
        declared = _topic_types(topics, registry)
    for item, direction, msg_type in declared.values():
        pnode = item.get("policy")
        if direction != SUBSCRIBE or not isinstance(pnode, YMap):
            continue
        for it in policy_items(pnode, msg_type, registry, ""):
            if it.target is not None and it.value == "reject":
                out.add(it.target.key)
    return out


def load_messages(ck: Checker, root: YMap, standard_msgs=None) -> tuple[MsgRegistry, list[Path]]:
    """The message registry of the model ``root``, loaded once, before the
    rules run: the standard ROS 1 Noetic types, the custom ones of its
    ``msg_paths`` folders (checked here, rule 4.5), and the strings and
    variable-length arrays the glue carries, with their maxima and
    policies (rules 4.14, 4.15), read from the model as written.  Returns
    the registry and the folders."""
    registry = MsgRegistry(standard=standard_msgs)
    folders = msg_paths(ck, root.get("msg_paths"), registry)
    topics, relations = root.get("topics"), root.get("relations")
    declared = _topic_types(topics, registry)
    registry.set_carried(carried_bounded_fields(topics, relations, registry, declared),
                         carried_reject_fields(topics, registry, declared))
    return registry, folders

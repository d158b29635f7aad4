"""Validation of a node model file against every rule of DESIGN.md section 4.

:func:`load_model` reads the YAML (:mod:`pyrosgen.frontend.yamlsrc`), checks the
structure, resolves message types and field paths (:mod:`pyrosgen.frontend.msgmodel`),
checks relations and the C names the generators will derive, and builds a
:class:`pyrosgen.frontend.model.NodeModel`.  Every problem is collected; if there is
any, :class:`pyrosgen.errors.InvalidNodeModel` is raised with all of them.
"""

from __future__ import annotations

import re
import unicodedata
from dataclasses import dataclass, field, replace
from pathlib import Path

from pyrosgen.errors import Diagnostic, InvalidNodeModel, show
from pyrosgen.frontend.model import (
    DERIVED_KINDS,
    DERIVED_PRIMS,
    MAX_CONTROLLER_ARRAY,
    MAX_TIMEOUT_MS,
    ON_TIMEOUT_POLICIES,
    PUBLISH,
    SUBSCRIBE,
    Controller,
    ControllerField,
    DerivedRelation,
    InputRelation,
    IOStruct,
    NodeModel,
    OutputRelation,
    Pos,
    SEQUENCE_DERIVED,
    Scalar,
    StringConstant,
    Topic,
)
from pyrosgen.frontend.msgmodel import (
    DEFAULT_MAX_LENGTH, MAX_LEAVES, MAX_SEQUENCE_LENGTH, MAX_STRUCT_FIELDS, MAX_TOTAL_LEAVES, PRIMITIVES,
    ROS1_ALIASES, STRING_CAPACITY, FieldPath, leaf_count, widest_struct,
)
from pyrosgen.frontend.blocks import check_diagram, scalar_of, zero
from pyrosgen.frontend.msgload import (
    BoundedPathError, BoundedTarget, MsgRegistry, PathError, StringPathError, StringTarget,
)
from pyrosgen.frontend.names import (
    MAX_NAME_LEN,
    did_you_mean,
    identifier_problem,
    topic_c_name,
    topic_name_problem,
)
from pyrosgen.frontend.yamlsrc import YBad, YMap, YNode, YScalar, YSeq, load_yaml

__all__ = ["load_model", "MAX_PERIOD_MS", "MAX_QUEUE_SIZE", "FIXED_C_NAMES"]

#: Longest accepted period (one hour).
MAX_PERIOD_MS = 3_600_000

#: Largest accepted subscriber/publisher queue.
MAX_QUEUE_SIZE = 10_000
#: At most this many fields in each of the controller's structs (rule 4.3;
#: times at the limits in BENCHMARKS.md section 5).
MAX_CONTROLLER_FIELDS = 2000

#: Names the generated C defines or calls whatever the model says.
FIXED_C_NAMES = (
    "input_glue",
    "loop",
    "main",
    "ros_init",
    "ros_ok",
    "ros_spinOnce",
    "ros_rate_sleep",
    "ros_now",
    "ros_time_sec",
    "ros_time_nsec",
    # temporaries: loop's answer of ros_ok; input_glue's cycle time and a
    # timed topic's age (rule 4.12)
    "_ok",
    "_now",
    "_age",
)

#: Local names of the generated functions (parameters of the callbacks and
#: output glues).  Coq's ``generate`` requires every global name to differ
#: from every local one, so that no local hides a global.  (The temporaries
#: ``_t_<type>``, like those of :data:`FIXED_C_NAMES`, start with '_',
#: which no global may.)
LOCAL_C_NAMES = ("msg", "command")

_TOP_REQUIRED = ("node", "controller", "topics", "relations")
_TOP_OPTIONAL = ("msg_paths",)


@dataclass
class _TopicDecl:
    """A topic declaration as far as it could be checked."""

    name: str
    node: YMap
    name_node: YNode
    what: str = "topics"  # topics[i]
    direction: str | None = None
    msg_type: str | None = None
    type_node: YNode | None = None
    queue_size: int | None = None
    usable: bool = False  # name, direction and type all valid
    type_ok: bool = False  # message type resolved and carries fields
    timeout_ms: int | None = None  # a valid timeout_ms (rule 4.12)
    policy: str = "zero"           # its on_timeout: hold or zero
    stamped: bool = False          # a valid `stamp` (rule 4.13)
    stamp_from: str | None = None  # `stamp: {from: topic}`: the source topic's name
    strings: list[StringConstant] = field(default_factory=list)  # valid constant strings (rule 4.14)
    #: the steps of every string field a constant names (valid or not), with
    #: what names it (rule 4.14): no output relation writes into one (4.15)
    constant_steps: dict[tuple, tuple[str, int]] = field(default_factory=dict)


@dataclass
class _Rel:
    """A relation row as far as it could be checked."""

    node: YMap
    topic: _TopicDecl | None = None
    path: FieldPath | None = None
    ctrl_field: str | None = None
    ctrl_node: YNode | None = None
    path_node: YNode | None = None
    ok: bool = True
    derived: str | None = None       # the kind of a derived input (rule 4.12)
    is_derived: bool = False         # the row has a `derived` key (not length or truncated)
    fallback: Scalar | None = None   # its value when stale (rule 4.12)
    seq_kind: str | None = None      # `derived: length` or `truncated` with a field (rule 4.15)
    bounded: BoundedTarget | None = None  # the sequence or string its field reads (rule 4.15)
    written: str | None = None       # the field as the model writes it, when it is not the leaf's path
    what: str = ""                   # relations.inputs[i], relations.outputs[i]
    ctrl_index: int | None = None    # the element of a controller array it names (Scan[540], rule 4.15)
    #: a whole array related to a whole controller array (rule 4.15): each
    #: element's leaf, the element of the controller array, and how the
    #: model would write the element's field (None: the leaf's path)
    elements: list[tuple[FieldPath, int, str | None]] | None = None
    row: tuple[str, str] | None = None  # such a row as written: (field, controller field)

    def leaves(self) -> list[tuple[FieldPath | None, int | None]]:
        """The (leaf, element of the controller field) pairs the row
        relates: one for a scalar or an element, one per element for a
        whole array (rule 4.15)."""
        if self.elements is not None:
            return [(p, i) for p, i, _ in self.elements]
        return [(self.path, self.ctrl_index)]


#: The rule of DESIGN.md section 4 that governs each section of the model,
#: by the prefix that messages about it start with.
_SECTION_RULES = (
    ("the node model", "4.1"),
    ("node", "4.2"),
    ("type of controller", "4.3"),
    ("controller.blocks", "4.11"),
    ("controller.outports", "4.11"),
    ("controller.subsystems", "4.11"),
    ("controller", "4.3"),
    ("topics", "4.4"),
    ("msg_paths", "4.5"),
    ("relations", "4.7"),
)


def reserved_package(pkg: str) -> bool:
    """Whether a custom package may not be called ``pkg``: its C structs
    (``<pkg>_<Type>``) could be the glue's own ``ros_time``,
    ``ros_duration``, or names that the environment model takes for
    bounded sequences and strings (``ros_seq_...``, ``ros_string...``,
    of policy reject ``ros_rseq_...``, ``ros_rstring...``:
    ``Environment.bounded_name``, ``reject_name``; rule 4.15)."""
    return pkg == "ros" or pkg.startswith(("ros_seq", "ros_string", "ros_rseq", "ros_rstring"))


def _rule_of(message: str) -> str | None:
    for prefix, rule in _SECTION_RULES:
        if message.startswith(prefix):
            return rule
    return None


@dataclass
class _Checker:
    file: str
    base_dir: Path
    diags: list[Diagnostic] = field(default_factory=list)
    inputs_listed: bool = False  # relations.inputs is a list (so coverage is checked)
    topics_listed: bool = False  # topics is a list (so unknown topics are errors)
    #: controller fields whose type is refused: a relation naming one is
    #: not checked further (its field's type is unknown)
    refused_fields: set[str] = field(default_factory=set)
    #: the controller's array fields (rule 4.15): when a struct is refused,
    #: a relation naming one is not checked further either (whether it
    #: relates a whole array or an element is unknown without the struct)
    array_fields: set[str] = field(default_factory=set)

    # -- reporting ----------------------------------------------------------

    def err(self, where: YNode | tuple[int, int] | None, message: str, rule: str | None = None) -> None:
        """Report ``message`` at ``where``, citing ``rule`` (DESIGN.md
        section 4), by default the rule of the model section the message
        names (:func:`_rule_of`)."""
        rule = rule or _rule_of(message)
        if where is None:
            self.diags.append(Diagnostic(self.file, None, None, message, rule=rule))
        elif isinstance(where, tuple):
            self.diags.append(Diagnostic(self.file, where[0], where[1], message, rule=rule))
        else:
            self.diags.append(Diagnostic(self.file, where.line, where.col, message, rule=rule))

    def err_rule(self, rule: str, where: YNode | tuple[int, int] | None, message: str) -> None:
        """:meth:`err` citing a given rule."""
        self.err(where, message, rule)

    # -- structure helpers ----------------------------------------------------

    def mapping(self, node: YNode | None, what: str) -> YMap | None:
        if node is None or isinstance(node, YBad):
            return None
        if not isinstance(node, YMap):
            self.err(node, f"{what} must be a mapping, got {node.describe()}")
            return None
        return node

    def keys(self, m: YMap, what: str, required, optional=()) -> None:
        allowed = tuple(required) + tuple(optional)
        for k in m.keys():
            if k not in allowed:
                kn = m.key_node(k)
                self.err(
                    kn,
                    f"{what}: unknown key {show(k)}{did_you_mean(k, allowed)}; "
                    f"expected {_list(allowed)}",
                )
        for k in required:
            if m.get(k) is None:
                self.err(m.owner_pos, f"{what}: missing key {show(k)}")

    def string(self, node: YNode | None, what: str) -> str | None:
        if node is None or isinstance(node, YBad):
            return None
        if isinstance(node, YScalar) and node.kind == "str":
            if node.value == "":
                self.err(node, f"{what} must not be empty")
                return None
            return node.value
        hint = ""
        if isinstance(node, YScalar) and node.kind in ("bool", "null", "int", "float"):
            hint = " (quote it if you mean the text)"
        self.err(node, f"{what} must be a string, got {node.describe()}{hint}")
        return None

    def integer(self, node: YNode | None, what: str, lo: int, hi: int, unit: str = "") -> int | None:
        if node is None or isinstance(node, YBad):
            return None
        expected = f"an integer from {lo} to {hi}{unit}"
        if not (isinstance(node, YScalar) and node.kind == "int"):
            self.err(node, f"{what} must be {expected}, got {node.describe()}")
            return None
        v = node.value
        if not lo <= v <= hi:
            self.err(node, f"{what} must be {expected}, got {show(node.text)}")
            return None
        return v

    def ident(self, node: YNode | None, what: str, *, global_scope: bool) -> str | None:
        name = self.string(node, what)
        if name is None:
            return None
        problem = identifier_problem(name, global_scope=global_scope)
        if problem:
            self.err_rule("4.9", node, f"{what} {show(name)} cannot be used: {problem}")
            return None
        return name

    # -- sections ---------------------------------------------------------------

    def node_section(self, m: YMap | None) -> tuple[str | None, int | None]:
        if m is None:
            return None, None
        self.keys(m, "node", ("name", "period_ms"))
        name = self.ident(m.get("name"), "node.name", global_scope=True)
        period = self.integer(m.get("period_ms"), "node.period_ms", 1, MAX_PERIOD_MS, " (milliseconds)")
        return name, period

    def io_struct(self, m: YMap | None, what: str) -> tuple[str | None, list[tuple[YScalar, ControllerField]] | None]:
        if m is None:
            return None, None
        self.keys(m, what, ("name", "fields"))
        var = self.ident(m.get("name"), f"{what}.name", global_scope=True)
        fnode = self.mapping(m.get("fields"), f"{what}.fields")
        if fnode is None:
            return var, None
        fields: list[tuple[YScalar, ControllerField]] = []
        ok = True
        if not fnode.items:
            self.err(fnode, f"{what}.fields must declare at least one field")
            ok = False
        elif len(fnode.items) > MAX_CONTROLLER_FIELDS:
            self.err_rule("4.3", fnode, f"{what}.fields declares {len(fnode.items)} fields; at most "
                          f"{MAX_CONTROLLER_FIELDS} (the time to check the proof grows with the square "
                          "of a struct's width)")
            return var, None
        for knode, vnode in fnode.items:
            fname = knode.text
            problem = identifier_problem(fname)
            if problem:
                self.err_rule("4.9", knode, f"{what}.fields: field name {show(fname)} cannot be used: {problem}")
                ok = False
                continue
            ftype = self.controller_type(vnode, f"{what}.fields.{fname}")
            if ftype is None:
                ok = False
                self.refused_fields.add(fname)
                continue
            fields.append((knode, ControllerField(fname, *ftype)))
            if ftype[1] is not None:
                self.array_fields.add(fname)
        return var, fields if ok else None

    def controller_type(self, node: YNode, what: str) -> tuple[str, int | None] | None:
        """The type of a controller field written at ``node``: a primitive
        (``float64``: ``(prim, None)``) or a one-dimensional array of one
        (``float32[1081]``: ``(prim, 1081)``, rule 4.15); ``None``
        (reported) when it is neither."""
        t = self.string(node, f"type of {what}")
        if t is None:
            return None
        m = _ARRAY_TYPE.fullmatch(t)
        if m is None:
            prim = self.prim_type(node, what)
            return (prim, None) if prim is not None else None
        base, dims = m.group(1), _DIMS.findall(m.group(2))
        rule = "4.15"
        example = f"{base}[8]" if base in PRIMITIVES else "float32[8]"
        if base not in PRIMITIVES:
            # the element type's problem, as for a scalar field (rule 4.3)
            if base in ROS1_ALIASES:
                self.err_rule("4.3", node, f"{what}: type {show(t)}: {show(base)} is a deprecated ROS alias; "
                                           f"write {ROS1_ALIASES[base]}{m.group(2)}")
            elif base in ("string", "time", "duration") or "/" in base:
                self.err_rule("4.3", node, f"{what}: type {show(t)} is not allowed: a controller array has "
                                           f"elements of a primitive type (expected one of {', '.join(PRIMITIVES)})")
            else:
                self.err_rule("4.3", node, f"{what}: unknown element type {show(base)} in {show(t)}"
                                           f"{did_you_mean(base, PRIMITIVES)}; expected one of "
                                           f"{', '.join(PRIMITIVES)}")
            return None
        if len(dims) > 1:
            self.err_rule(rule, node, f"{what}: type {show(t)} is an array of {len(dims)} dimensions; a "
                                      f"controller array has one (e.g. {show(example)}: flatten it)")
            return None
        dim = dims[0]
        if dim == "":
            self.err_rule(rule, node, f"{what}: type {show(t)} is a variable-length array; a controller "
                                      f"array has a fixed size, an integer from 1 to {MAX_CONTROLLER_ARRAY} "
                                      f"(e.g. {show(example)}; a variable-length array of a message is read "
                                      "into one, rule 4.15)")
            return None
        if not re.fullmatch(r"0|[1-9][0-9]{0,8}", dim):
            self.err_rule(rule, node, f"{what}: type {show(t)}: the size {show(dim)} is not an integer; a "
                                      f"controller array has a size from 1 to {MAX_CONTROLLER_ARRAY} "
                                      f"(e.g. {show(example)})")
            return None
        n = int(dim)
        if not 1 <= n <= MAX_CONTROLLER_ARRAY:
            self.err_rule(rule, node, f"{what}: type {show(t)}: a controller array has a size from 1 to "
                                      f"{MAX_CONTROLLER_ARRAY}, got {n}")
            return None
        return base, n

    def whole_array_row(self, rel: _Rel, ptext: str, registry: MsgRegistry, kind: str,
                        cf: ControllerField) -> None:
        """Rule 4.15: a relation between field ``ptext`` of its topic's
        message and the whole controller array ``cf`` (``kind``: ``input``
        or ``output``).  The field must be a whole array of as many
        elements of the same type: a carried variable-length array of
        primitives or string whose maximum is the controller array's size,
        or a fixed-size array of primitives of that size.  Sets the row's
        elements (each a relation on one leaf) or reports why not."""
        w, topic, msg_type = rel.what, rel.topic.name, rel.topic.msg_type
        arr = _whole_array(registry, msg_type, ptext)
        if arr is None:
            try:
                leaf = registry.walk_path(msg_type, ptext, bounded=True, writes=kind == "output")
            except PathError:
                raise  # reported by the caller, as for any path
            self.err_rule("4.15", rel.node,
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
            self.err_rule("4.15", rel.node, f"{w}: {first} but {second}: {why}")
            rel.ok = False
            return
        rel.elements = [(arr.element(i), i, None if arr.kind == "fixed" else f"{ptext}[{i}]")
                        for i in range(arr.size)]
        rel.path = rel.elements[0][0]
        rel.row = (ptext, cf.name)

    def prim_type(self, node: YNode, what: str) -> str | None:
        t = self.string(node, f"type of {what}")
        if t is None:
            return None
        if t in PRIMITIVES:
            return t
        expected = f"expected one of {', '.join(PRIMITIVES)}"
        if t in ROS1_ALIASES:
            self.err_rule("4.3", node, f"{what}: type {show(t)} is a deprecated ROS alias; write {ROS1_ALIASES[t]}")
        elif t in ("string", "time", "duration") or "/" in t or "[" in t:
            self.err_rule("4.3", node, f"{what}: type {show(t)} is not allowed: controller fields have primitive types ({expected})")
        else:
            self.err_rule("4.3", node, f"{what}: unknown type {show(t)}{did_you_mean(t, PRIMITIVES)}; {expected}")
        return None

    def controller_section(self, m: YMap | None):
        if m is None:
            return None, None, (None, None), (None, None)
        self.keys(m, "controller", ("name", "inputs", "outputs"), ("blocks", "outports", "subsystems"))
        name = self.ident(m.get("name"), "controller.name", global_scope=True)
        uvar, ufields = self.io_struct(self.mapping(m.get("inputs"), "controller.inputs"), "controller.inputs")
        yvar, yfields = self.io_struct(self.mapping(m.get("outputs"), "controller.outputs"), "controller.outputs")
        return m, name, (uvar, ufields), (yvar, yfields)

    def msg_paths(self, node: YNode | None, registry: MsgRegistry) -> list[Path]:
        if node is None or isinstance(node, YBad):
            return []
        if isinstance(node, YScalar) and node.kind == "null":
            return []
        if not isinstance(node, YSeq):
            self.err(node, f"msg_paths must be a list of folders, got {node.describe()}")
            return []
        out: list[Path] = []
        for i, item in enumerate(node.items):
            what = f"msg_paths[{i}]"
            text = self.string(item, what)
            if text is None:
                continue
            if "\x00" in text:  # pragma: no cover - refused when reading the file
                self.err(item, f"{what}: invalid path")
                continue
            p = Path(text)
            folder = p if p.is_absolute() else self.base_dir / p
            try:
                resolved = folder.resolve()
                is_dir = folder.is_dir()
            except (OSError, RuntimeError, ValueError):
                resolved, is_dir = folder, False
            if not is_dir:
                self.err(
                    item,
                    f"{what}: no such folder {show(text)} (relative paths are relative to the model file)",
                )
                continue
            if resolved in out:
                self.err(item, f"{what}: folder {show(text)} is listed twice")
                continue
            out.append(resolved)
            reserved = sorted({f.parent.parent.name for f in resolved.glob("*/msg/*.msg")
                               if reserved_package(f.parent.parent.name)})
            if reserved:
                self.err_rule("4.15", item,
                              f"{what}: folder {show(text)} holds the package {show(reserved[0])}: a package named "
                              "ros (or starting with ros_seq, ros_string, ros_rseq or ros_rstring) is refused, "
                              "its C structs could collide with the glue's own (ros_time, ros_duration, "
                              "ros_seq_<T>_<N>, ros_string<N>, ros_rseq_<T>_<N>, ros_rstring<N>)")
                continue
            try:
                n = registry.add_msg_dir(resolved)
            except InvalidNodeModel as exc:
                self.err(item, f"{what}: {exc.diagnostics[0].message}")
                continue
            if n == 0:
                self.err(
                    item,
                    f"{what}: folder {show(text)} contains no <package>/msg/<Type>.msg files",
                )
        return out

    def topics_section(self, node: YNode | None, registry: MsgRegistry) -> list[_TopicDecl]:
        if node is None or isinstance(node, YBad):
            return []
        if not isinstance(node, YSeq):
            self.err(node, f"topics must be a list of topic declarations, got {node.describe()}")
            return []
        self.topics_listed = True
        if not node.items:
            self.err(node, "topics must declare at least one topic")
        decls: list[_TopicDecl] = []
        by_name: dict[str, _TopicDecl] = {}
        total_leaves, total_reported = 0, False
        for i, item in enumerate(node.items):
            what = f"topics[{i}]"
            m = self.mapping(item, what)
            if m is None:
                continue
            self.keys(m, what, ("name", "direction", "type", "queue_size"),
                      ("timeout_ms", "on_timeout", "stamp", "frame_id", "strings", "max_length", "policy"))
            name_node = m.get("name")
            name = self.string(name_node, f"{what}.name")
            usable = name is not None
            if name is not None:
                problem = topic_name_problem(name)
                if problem:
                    self.err_rule("4.4", name_node, f"{what}.name: topic name {show(name)} is not a valid ROS topic name: {problem}")
                    usable = False
                if name in by_name:
                    first = by_name[name]
                    self.err_rule("4.4", name_node, f"{what}.name: topic {show(name)} is declared twice (first at line {first.name_node.line})")
                    continue
            d = _TopicDecl(name if name is not None else f"<topics[{i}]>", m, name_node or m, what)
            if name is not None:
                by_name[name] = d
            decls.append(d)
            dnode = m.get("direction")
            direction = self.string(dnode, f"{what}.direction")
            if direction is not None and direction not in (SUBSCRIBE, PUBLISH):
                self.err(
                    dnode,
                    f"{what}.direction must be 'subscribe' or 'publish', got {show(direction)}"
                    f"{did_you_mean(direction, (SUBSCRIBE, PUBLISH))}",
                )
                direction = None
            d.direction = direction
            d.queue_size = self.integer(m.get("queue_size"), f"{what}.queue_size", 1, MAX_QUEUE_SIZE)
            tnode = m.get("type")
            d.type_node = tnode
            t = self.string(tnode, f"{what}.type")
            type_ok = False
            if t is not None:
                problem = registry.check_type_name(t)
                if t in registry.failed:
                    pass  # its .msg file could not be read: reported there
                elif problem:
                    self.err_rule("4.5", tnode, f"{what}.type: {problem}")
                else:
                    d.msg_type = t
                    carried = registry.carried(t)
                    if registry.is_broken(t):
                        pass  # reported in the .msg file
                    elif carried is None:
                        self.err_rule(
                            "4.5",
                            tnode,
                            f"{what}.type: message type {t} carries no field "
                            "(strings and variable-length arrays are not carried by the glue)",
                        )
                    else:
                        n = leaf_count(carried, registry.messages())
                        wide, width = widest_struct(carried, registry.messages())
                        if n > MAX_LEAVES:
                            self.err_rule(
                                "4.5",
                                tnode,
                                f"{what}.type: message type {t} has {n} scalar leaves; "
                                f"the glue carries at most {MAX_LEAVES} per message"
                                + (" (lower the max_length of its variable-length arrays and strings: each "
                                   "carries its maximum, every element of an array of messages or strings "
                                   "all of its element's leaves)" if _has_bounded(carried, registry) else ""),
                            )
                        elif width > MAX_STRUCT_FIELDS:
                            self.err_rule(
                                "4.5",
                                tnode,
                                f"{what}.type: message type {wide}{' (in ' + t + ')' if wide != t else ''} "
                                f"has {width} carried fields; at most {MAX_STRUCT_FIELDS} per message "
                                "definition (nest them in sub-messages, or use an array)",
                            )
                        else:
                            type_ok = True
                            total_leaves += n
                            if total_leaves > MAX_TOTAL_LEAVES and not total_reported:
                                total_reported = True
                                self.err_rule(
                                    "4.5",
                                    tnode,
                                    f"{what}.type: the topics up to this one carry {total_leaves} scalar leaves "
                                    f"in all; a node carries at most {MAX_TOTAL_LEAVES}",
                                )
            d.type_ok = type_ok
            d.usable = usable and type_ok and direction is not None and d.queue_size is not None
        return decls

    def relations_section(
        self,
        node: YNode | None,
        topics: dict[str, _TopicDecl],
        inputs: dict[str, ControllerField] | None,
        outputs: dict[str, ControllerField] | None,
        registry: MsgRegistry,
    ) -> tuple[list[_Rel], list[_Rel]]:
        m = self.mapping(node, "relations")
        if m is None:
            return [], []
        self.keys(m, "relations", ("inputs",), ("outputs",))
        rows = m.get("inputs")
        self.inputs_listed = isinstance(rows, YSeq) or (isinstance(rows, YScalar) and rows.kind == "null")
        ins = self.rows(m.get("inputs"), "relations.inputs", "input", topics, inputs, outputs, registry)
        outs = self.rows(m.get("outputs"), "relations.outputs", "output", topics, outputs, inputs, registry)
        return ins, outs

    def rows(self, node, what, kind, topics, ctrl, other, registry) -> list[_Rel]:
        if node is None or isinstance(node, YBad):
            return []
        if isinstance(node, YScalar) and node.kind == "null":
            return []
        if not isinstance(node, YSeq):
            self.err(node, f"{what} must be a list of relations, got {node.describe()}")
            return []
        want_dir = SUBSCRIBE if kind == "input" else PUBLISH
        out = []
        for i, item in enumerate(node.items):
            w = f"{what}[{i}]"
            m = self.mapping(item, w)
            if m is None:
                continue
            rel = _Rel(m)
            if kind == "input":
                # a derived input (rule 4.12) has no field; `field` and
                # `on_timeout` with it are refused by check_freshness; but
                # `derived: length` and `derived: truncated` name the
                # variable-length array or string they read with `field`
                # (rule 4.15)
                dnode = m.get("derived")
                if isinstance(dnode, YScalar) and dnode.kind == "str" and dnode.value in SEQUENCE_DERIVED:
                    rel.seq_kind = dnode.value
                rel.is_derived = dnode is not None and rel.seq_kind is None
                required = (("topic", "derived", "input") if rel.is_derived else ("topic", "input")
                            if rel.seq_kind else ("topic", "field", "input"))
                self.keys(m, w, required, tuple(k for k in _INPUT_KEYS if k not in required))
            else:
                # an output relation into a published variable-length array
                # or string writes one element (field: "data[3]") or, with
                # derived: length, its length (rule 4.15)
                dnode = m.get("derived")
                if dnode is not None:
                    if isinstance(dnode, YScalar) and dnode.kind == "str" and dnode.value == "length":
                        rel.seq_kind = "length"
                    else:
                        self.err_rule("4.15", dnode, f"{w}.derived: {_output_derived_problem(dnode)}")
                        rel.ok = False
                self.keys(m, w, ("output", "topic", "field"), ("derived",))
            rel.what = w
            out.append(rel)
            # topic
            tnode = m.get("topic")
            tname = self.string(tnode, f"{w}.topic")
            if tname is None:
                rel.ok = False
            elif tname not in topics:
                if self.topics_listed:
                    self.err(
                        tnode,
                        f"{w}.topic: unknown topic {show(tname)}{did_you_mean(tname, list(topics))}; declare it under topics",
                    )
                rel.ok = False
            else:
                decl = topics[tname]
                if decl.direction is not None and decl.direction != want_dir:
                    if rel.is_derived:
                        self.err_rule("4.12", tnode, f"{w}.topic: topic {show(tname)} is published by the node; "
                                                     "a derived input reads a subscribed topic")
                    elif kind == "input":
                        self.err(tnode, f"{w}.topic: topic {show(tname)} is published by the node; "
                                        "an input relation reads a subscribed topic")
                    else:
                        self.err(tnode, f"{w}.topic: topic {show(tname)} is subscribed by the node; "
                                        "an output relation writes a published topic")
                    rel.ok = False
                elif not decl.usable:
                    rel.ok = False
                else:
                    rel.topic = decl
            # controller field
            cnode = m.get(kind)
            cname = self.string(cnode, f"{w}.{kind}")
            rel.ctrl_node = cnode
            if cname is None:
                rel.ok = False
            elif ctrl is not None:
                base, index = _split_target(cname)
                if base in ctrl and index is not None and not ctrl[base].is_array:
                    self.err_rule("4.15", cnode,
                                  f"{w}.{kind}: {show(cname)} names an element of controller {kind} {show(base)}, "
                                  f"which is not an array (it is {_prim_article(ctrl[base].prim)} "
                                  f"{ctrl[base].prim}): write {show(base)}")
                    rel.ok = False
                    rel.ctrl_field = base  # it is fed (by a refused relation)
                elif base in ctrl and index is not None and index >= ctrl[base].size:
                    f = ctrl[base]
                    self.err_rule("4.15", cnode,
                                  f"{w}.{kind}: index {index} is beyond controller {kind} {show(base)} "
                                  f"({f.type_text}): valid indices are 0..{f.size - 1}")
                    rel.ok = False
                elif base in ctrl:
                    rel.ctrl_field, rel.ctrl_index = base, index
                else:
                    hint = ""
                    if other is not None and cname in other:
                        otherkind = "output" if kind == "input" else "input"
                        hint = f" ({show(cname)} is a controller {otherkind})"
                    else:
                        hint = did_you_mean(cname, list(ctrl))
                    self.err_rule(
                        "4.7",
                        cnode,
                        f"{w}.{kind}: {show(cname)} is not a controller {kind}{hint}; "
                        f"controller {kind}s are {_list(ctrl)}",
                    )
                    rel.ok = False
            else:
                rel.ok = False
                if cname is not None and _split_target(cname)[0] in self.refused_fields | self.array_fields:
                    continue  # its type is refused or its struct is: what it relates to is unknown
            if rel.is_derived:
                continue  # its kind and type: check_freshness
            # field path
            pnode = m.get("field")
            rel.path_node = pnode
            ptext = None
            if rel.seq_kind is not None and pnode is None and kind == "input":
                self.err_rule("4.15", m.get("derived"),
                              f"{w}.derived: {rel.seq_kind} reads a variable-length array or a string: name it "
                              "with field (e.g. field: ranges)")
            if pnode is not None and not isinstance(pnode, YBad):
                ptext = self.string(pnode, f"{w}.field")
            if ptext is None:
                rel.ok = False
            elif kind == "output" and m.get("derived") is not None and rel.seq_kind is None:
                if rel.topic is not None:  # the relation is refused; what it names (check_published_sequences)
                    rel.bounded = registry.bounded_in_path(rel.topic.msg_type, ptext)
            elif rel.topic is not None:
                try:
                    if rel.seq_kind is not None:
                        target = registry.walk_bounded(rel.topic.msg_type, ptext, f"derived: {rel.seq_kind}")
                        leaf, prim = SEQUENCE_DERIVED[rel.seq_kind]
                        rel.path = FieldPath((*target.steps, leaf), prim)
                        rel.bounded = target
                        rel.written = f"{ptext} ({rel.seq_kind})"
                        if rel.seq_kind == "truncated" and target.key in registry.carry_reject:
                            self.err_rule("4.15", m.get("derived"),
                                          f"{w}.derived: truncated of {ptext}, whose policy is reject, is always 0 "
                                          f"(a longer message is not delivered): use derived: length, or policy "
                                          f"truncate ({target.field} of {target.owner})")
                            rel.ok = False
                    elif rel.ctrl_field is not None and ctrl[rel.ctrl_field].is_array and rel.ctrl_index is None:
                        self.whole_array_row(rel, ptext, registry, kind, ctrl[rel.ctrl_field])
                    else:
                        rel.path = registry.walk_path(rel.topic.msg_type, ptext, bounded=True,
                                                      writes=kind == "output")
                        rel.bounded = registry.bounded_in_path(rel.topic.msg_type, ptext)
                        if rel.bounded is not None:
                            rel.written = ptext
                except PathError as exc:
                    if kind == "output":  # refused; what it names (check_published_sequences)
                        rel.bounded = registry.bounded_in_path(rel.topic.msg_type, ptext)
                    arr = (_whole_array(registry, rel.topic.msg_type, ptext)
                           if rel.ctrl_field is not None and rel.seq_kind is None else None)
                    if arr is not None and arr.kind == "fixed":
                        # a whole fixed-size array and a scalar (rule 4.15)
                        cf = ctrl[rel.ctrl_field]
                        target = f"{rel.ctrl_field}[{rel.ctrl_index}]" if rel.ctrl_index is not None else rel.ctrl_field
                        self.err_rule("4.15", pnode,
                                      f"{w}.field: {show(ptext)} of topic {show(rel.topic.name)} is a whole array "
                                      f"({arr.type_text}) but controller {kind} {show(target)} is one {cf.prim}: "
                                      f"relate one element ({show(ptext + '[0]')}), or the whole array to a "
                                      f"controller array of {arr.size} {arr.prim}")
                    else:
                        rule = ("4.15" if isinstance(exc, BoundedPathError) or rel.seq_kind is not None
                                else "4.14" if isinstance(exc, StringPathError) else "4.6")
                        self.err_rule(rule, pnode, f"{w}.field: {exc.args[0]} (topic {show(rel.topic.name)}, {rel.topic.msg_type})")
                    rel.ok = False
            # types
            if rel.elements is not None:
                continue  # a whole array: checked by whole_array_row
            if (rel.seq_kind is not None and rel.ctrl_field is not None and ctrl[rel.ctrl_field].is_array
                    and rel.ctrl_index is None):
                cf = ctrl[rel.ctrl_field]
                self.err_rule("4.15", rel.ctrl_node,
                              f"{w}.{kind}: {rel.seq_kind} is one {SEQUENCE_DERIVED[rel.seq_kind][1]} but controller "
                              f"{kind} {show(cf.name)} is an array ({cf.type_text}): relate it to a scalar {kind}, "
                              f"or to one element ({show(cf.name + '[0]')})")
                rel.ok = False
                continue
            if rel.path is not None and rel.ctrl_field is not None:
                cprim = ctrl[rel.ctrl_field].prim
                if cprim != rel.path.prim and rel.seq_kind is not None and kind == "output":
                    what_ = "string" if rel.bounded.is_string else "variable-length array"
                    self.err_rule("4.15", rel.ctrl_node,
                                  f"{w}.output: the length of a published {what_} is a uint32: controller output "
                                  f"{show(rel.ctrl_field)} is {cprim} (relations never convert)")
                    rel.ok = False
                elif cprim != rel.path.prim and rel.seq_kind is not None:
                    self.err_rule("4.15", rel.ctrl_node,
                                  f"{w}.input: {rel.seq_kind} related to a non-{rel.path.prim} field: controller "
                                  f"input {show(rel.ctrl_field)} is {cprim} ({rel.seq_kind} is a {rel.path.prim})")
                    rel.ok = False
                elif cprim != rel.path.prim and rel.bounded is not None and rel.bounded.is_string:
                    if kind == "input":
                        msg = (f"{w}: a string related to a non-uint8 field: {show(ptext)} of topic "
                               f"{show(rel.topic.name)} is a byte of a string (uint8) but controller input "
                               f"{show(rel.ctrl_field)} is {cprim} (a string reaches the controller byte by "
                               "byte, as uint8, with its length from derived: length)")
                    else:
                        msg = (f"{w}: a string related to a non-uint8 field: controller output "
                               f"{show(rel.ctrl_field)} is {cprim} but {show(ptext)} of topic "
                               f"{show(rel.topic.name)} is a byte of a string (uint8) (a published string "
                               "takes its bytes from uint8 outputs and its length from a uint32 output, "
                               "derived: length)")
                    self.err_rule("4.15", m, msg)
                    rel.ok = False
                elif cprim != rel.path.prim:
                    if kind == "input":
                        msg = (
                            f"{w}: type mismatch: field {show(rel.written or str(rel.path))} of topic "
                            f"{show(rel.topic.name)} is {rel.path.prim} but controller input "
                            f"{show(rel.ctrl_field)} is {cprim} (relations never convert)"
                        )
                    else:
                        msg = (
                            f"{w}: type mismatch: controller output {show(rel.ctrl_field)} is "
                            f"{cprim} but field {show(str(rel.path))} of topic "
                            f"{show(rel.topic.name)} is {rel.path.prim} (relations never convert)"
                        )
                    # an element of a variable-length array: rule 4.15's
                    self.err_rule("4.15" if rel.bounded is not None else "4.7", m, msg)
                    rel.ok = False
        return out


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


def _whole_array(registry: MsgRegistry, msg_type: str, text: object) -> _WholeArray | None:
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


def _split_target(text: str) -> tuple[str, int | None]:
    """A relation's controller field as written: ``Scan[540]`` is element
    540 of ``Scan`` (rule 4.15), ``In1`` the field itself; anything else is
    returned as it is (and is no controller field)."""
    m = re.fullmatch(r"([A-Za-z_][A-Za-z0-9_]*)\[(0|[1-9][0-9]{0,8})\]", text)
    return (m.group(1), int(m.group(2))) if m else (text, None)


def _prim_article(prim: str) -> str:
    """The article of a primitive type's name as read aloud: an int8, a uint8."""
    return "an" if prim[:1] in "aeio" else "a"


def _index_ranges(indices) -> str:
    """Sorted indices as ranges: ``0..2, 5, 7..9``."""
    out, run = [], []
    for i in sorted(indices):
        if run and i == run[-1] + 1:
            run.append(i)
            continue
        if run:
            out.append(str(run[0]) if len(run) == 1 else f"{run[0]}..{run[-1]}")
        run = [i]
    if run:
        out.append(str(run[0]) if len(run) == 1 else f"{run[0]}..{run[-1]}")
    return ", ".join(out)


#: A controller field's type written as an array: ``float32[1081]``
#: (rule 4.15), and each of its dimensions.
_ARRAY_TYPE = re.compile(r"([^\[\]]*)((?:\[[^\[\]]*\])+)")
_DIMS = re.compile(r"\[([^\[\]]*)\]")


#: The keys of an input relation: `field` for a plain one, `derived` for a
#: derived input (rule 4.12).
_INPUT_KEYS = ("topic", "field", "input", "on_timeout", "derived")


def _output_derived_problem(dnode: YNode) -> str:
    """Why the ``derived`` of an output relation, written at ``dnode``, is
    not ``length`` (the only kind on the publish side, rule 4.15)."""
    if isinstance(dnode, YScalar) and dnode.kind == "str" and dnode.value == "truncated":
        return ("an output relation does not write truncated: on publish it is meaningless (the subscriber "
                "receives the first min(length, N) elements and the environment model recomputes the flag); "
                "write the length with derived: length")
    got = show(dnode.value) if isinstance(dnode, YScalar) and dnode.kind == "str" else dnode.describe()
    return (f"an output relation takes derived: length only (the length of a published variable-length "
            f"array or string, from a uint32 output), got {got}")


def check_published_sequences(ck: "_Checker", out_rels: list[_Rel], registry: MsgRegistry) -> None:
    """Rule 4.15, publish side: a published variable-length array or
    string whose elements output relations write also has its length
    written (``derived: length``), and so has every array a written leaf
    or length is inside (``poses`` for ``poses[0].pose.position.x`` and
    for the length of ``poses[0].header.frame_id``); a published string
    written by the controller has no constant (rule 4.14)."""
    # a refused relation on the field (its path, its derived) may have
    # meant the length: it is not reported again as a missing one
    lengths = {(r.topic.name, r.bounded.steps) for r in out_rels
               if (r.seq_kind == "length" or r.path is None) and r.topic is not None and r.bounded is not None}
    reported: set[tuple] = set()
    for r in out_rels:
        if r.topic is None or r.bounded is None or r.path is None:
            continue
        field_text = _steps_text(r.bounded.steps)
        kind = "string" if r.bounded.is_string else "variable-length array"
        first = r.topic.constant_steps.get(r.bounded.steps)
        if first is not None:
            ck.err_rule("4.15", r.path_node,
                        f"{r.what}.field: the {kind} {show(field_text)} of topic {show(r.topic.name)} has a "
                        f"constant ({first[0]}, line {first[1]}); a published string comes from a constant or "
                        "from controller outputs, not both")
            r.ok = False
            continue
        fnode = r.node.get("field")
        along = registry.bounded_along(r.topic.msg_type, fnode.value) if isinstance(fnode, YScalar) else []
        if not along or along[-1].steps != r.bounded.steps:  # pragma: no cover - the same walk
            along = [r.bounded]
        need = along if r.seq_kind is None else along[:-1]
        for t in need:
            key = (r.topic.name, t.steps)
            if key in lengths or key in reported:
                continue
            reported.add(key)
            what = ("string" if t.is_string else "variable-length array of messages" if t.seq_of == "msg"
                    else "variable-length array of strings" if t.seq_of == "string" else "variable-length array")
            writes = "elements of" if t is along[-1] and r.seq_kind is None else "inside"
            ck.err_rule("4.15", r.path_node,
                        f"{r.what}.field: the controller writes {writes} the published {what} "
                        f"{show(t.shown)} of topic {show(r.topic.name)} but not its length: add "
                        f"{{output: <a uint32 output>, topic: {r.topic.name}, field: {_flow(t.shown)}, "
                        "derived: length} (the subscriber receives the first min(length, N) elements, N its "
                        "max_length)")
            r.ok = False
            break


def _flow(text: str) -> str:
    """A field path as a YAML flow mapping's value: quoted when it holds
    brackets."""
    return f'"{text}"' if "[" in text else text


#: The field a stamped topic's message carries the time in (rule 4.13).
STAMP_FIELD = ("header", "stamp")


def _has_stamp(registry: MsgRegistry, msg_type: str) -> bool:
    """Whether messages of ``msg_type`` have a ``header.stamp`` of type ``time``."""
    raw = registry.raw(msg_type)
    header = raw.field("header") if raw is not None else None
    hraw = registry.raw(header.base) if header is not None and header.card == "scalar" else None
    stamp = hraw.field("stamp") if hraw is not None else None
    return stamp is not None and stamp.card == "scalar" and stamp.base == "time"


def _stamp_source(ck: _Checker, d: _TopicDecl, snode: YMap, what: str,
                  decls: list[_TopicDecl], registry: MsgRegistry) -> tuple[bool, str | None]:
    """``stamp: {from: <topic>}``: the named topic is subscribed by the node
    and its message has a ``header.stamp`` of type ``time``.  Returns
    whether it passed and the source topic's name."""
    rule = "4.13"
    ck.keys(snode, what, ("from",))
    fnode = snode.get("from")
    name = ck.string(fnode, f"{what}.from")
    if name is None:
        return False, None
    by_name = {e.name: e for e in decls if e.name is not None}
    src = by_name.get(name)
    if src is None:
        ck.err_rule(rule, fnode, f"{what}.from: {show(name)} is not a topic of the node"
                                 f"{did_you_mean(name, list(by_name))}")
        return False, None
    if src.direction is not None and src.direction != "subscribe":
        ck.err_rule(rule, fnode, f"{what}.from: topic {show(name)} is published by the node; "
                                 "a stamp is copied from a subscribed topic")
        return False, None
    if src.usable and src.type_ok and src.msg_type is not None and not _has_stamp(registry, src.msg_type):
        ck.err_rule(rule, fnode, f"{what}.from: message type {src.msg_type} of topic {show(name)} has no "
                                 "header.stamp of type time to copy")
        return False, None
    return src.usable and src.type_ok, name


def check_stamps(ck: _Checker, decls: list[_TopicDecl], out_rels: list[_Rel], registry: MsgRegistry) -> None:
    """Rule 4.13: ``stamp: now`` or ``stamp: {from: <subscribed topic>}``
    on a published topic whose message has a ``header.stamp`` of type
    ``time``, which no output relation writes.  Sets ``stamped`` (and
    ``stamp_from``) on the topics that pass."""
    rule = "4.13"
    for d in decls:
        snode = d.node.get("stamp")
        if snode is None or isinstance(snode, YBad):
            continue
        what = f"{d.what}.stamp"
        source = None
        if isinstance(snode, YMap):
            ok_src, source = _stamp_source(ck, d, snode, what, decls, registry)
            if not ok_src:
                continue
        elif not (isinstance(snode, YScalar) and snode.kind == "str" and snode.value == "now"):
            hint = (did_you_mean(snode.value, ("now",)) if isinstance(snode, YScalar) and snode.kind == "str" else "")
            ck.err_rule(rule, snode, f"{what} must be 'now' (the cycle's ROS time) or {{from: <topic>}} "
                                     f"(the stamp of a subscribed topic's newest message), got {snode.describe()}{hint}")
            continue
        if d.direction is not None and d.direction != "publish":
            ck.err_rule(rule, snode, f"{what}: topic {show(d.name)} is subscribed by the node; "
                                     "only a published message is stamped")
            continue
        if not (d.usable and d.type_ok and d.msg_type is not None):
            continue
        if not _has_stamp(registry, d.msg_type):
            ck.err_rule(rule, snode, f"{what}: message type {d.msg_type} of topic {show(d.name)} has no "
                                     "header.stamp of type time to stamp")
            continue
        ok = True
        for r in out_rels:
            if r.topic is d and r.path is not None and tuple(r.path.steps[:2]) == STAMP_FIELD:
                ck.err_rule(rule, r.path_node, f"field {show(str(r.path))} of topic {show(d.name)} is written "
                                               "by the stamp; an output relation may not write it too")
                ok = False
        d.stamped = ok
        d.stamp_from = source if ok else None


#: The field ``frame_id: <string>`` gives a constant (rule 4.14), and the
#: type of the ``header`` it needs.
FRAME_ID_FIELD = "header.frame_id"
HEADER_TYPE = "std_msgs/Header"


def _has_bounded(t, registry: MsgRegistry) -> bool:
    """Whether carried type ``t`` holds a variable-length array or a string."""
    return any(m.is_bounded for m in registry.used_types([t.name]))


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


def _string_items(m: YMap, msg_type: str, registry: MsgRegistry, what: str) -> list[_StrItem]:
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


def _known_type(registry: MsgRegistry, node: YNode | None) -> str | None:
    """The message type written at ``node`` if it is a known one."""
    if not (isinstance(node, YScalar) and node.kind == "str"):
        return None
    t = node.value
    if t in registry.failed or registry.check_type_name(t) is not None or registry.raw(t) is None:
        return None
    return t


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
        for it in _string_items(item, msg_type, registry, ""):
            if it.target is not None:
                out.add((it.target.owner, it.target.field))
    return out


@dataclass
class _MaxItem:
    """An entry of a topic's ``max_length`` (rule 4.15): ``what`` names it
    in messages, ``key`` is its field path's node, ``value`` its value's;
    ``target`` the sequence or string it names, or ``problem`` why its
    path names none; ``n`` its maximum, or ``value_problem`` why it is not
    one."""

    what: str
    key: YNode
    value: YNode
    target: BoundedTarget | None = None
    problem: str | None = None
    n: int | None = None
    value_problem: str | None = None


def _max_value(node: YNode) -> tuple[int | None, str | None]:
    """The maximum length written at ``node``, or why it is not one: an
    integer from 1 to :data:`MAX_SEQUENCE_LENGTH`."""
    expected = f"an integer from 1 to {MAX_SEQUENCE_LENGTH}"
    if not (isinstance(node, YScalar) and node.kind == "int"):
        return None, f"must be {expected} (the most elements carried), got {node.describe()}"
    if node.value < 1:
        return None, (f"must be {expected}, got {show(node.text)} (a carried array holds at least one "
                      "element; its received length may still be 0)")
    if node.value > MAX_SEQUENCE_LENGTH:
        return None, f"must be {expected}, got {show(node.text)}"
    return node.value, None


def _max_length_items(mnode: YMap, msg_type: str | None, registry: MsgRegistry, what: str) -> list[_MaxItem]:
    """The entries of the ``max_length`` mapping ``mnode`` of a topic of
    ``msg_type`` (``None``: unknown, the paths are not resolved)."""
    out = []
    for k, v in mnode.items:
        it = _MaxItem(f"{what}.max_length[{show(k.text)}]", k, v)
        if not isinstance(v, YBad):
            it.n, it.value_problem = _max_value(v)
        if k.kind != "str":
            it.problem = f"a key of max_length is a field path, got {k.describe()}"
        elif msg_type is not None:
            try:
                it.target = registry.walk_bounded(msg_type, k.value, "max_length")
            except PathError as exc:
                it.problem = exc.args[0]
        out.append(it)
    return out


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


def carried_bounded_fields(topics: YNode | None, relations: YNode | None,
                           registry: MsgRegistry) -> dict[tuple[str, str], int]:
    """The strings and variable-length arrays of primitives the glue
    carries, as (message type, field name) -> capacity: the string fields
    that constants name (rule 4.14) and the strings and sequences that
    the input relations of subscribed topics read and the output
    relations of published topics write (rule 4.15), each with
    the ``max_length`` a topic gives it, or :data:`DEFAULT_MAX_LENGTH`.
    Read before the topics are checked (a message type's carried view
    depends on it); nothing is reported here, :func:`check_max_length` and
    the relations' checks report every problem of the same items."""
    named = set(carried_string_fields(topics, registry))
    declared = _topic_types(topics, registry)
    maxima: dict[tuple[str, str], int] = {}
    for item, _direction, msg_type in declared.values():
        mnode = item.get("max_length")
        if isinstance(mnode, YMap):
            for it in _max_length_items(mnode, msg_type, registry, ""):
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


#: The policies of a carried variable-length array or string for received
#: data longer than its maximum (rule 4.15, ``policy``).
POLICIES = ("truncate", "reject")


@dataclass
class _PolicyItem:
    """An entry of a topic's ``policy`` (rule 4.15): as :class:`_MaxItem`,
    with ``value`` the policy or ``value_problem`` why it is not one."""

    what: str
    key: YNode
    node: YNode
    target: BoundedTarget | None = None
    problem: str | None = None
    value: str | None = None
    value_problem: str | None = None


def _policy_items(pnode: YMap, msg_type: str | None, registry: MsgRegistry, what: str) -> list[_PolicyItem]:
    """The entries of the ``policy`` mapping ``pnode`` of a topic of
    ``msg_type`` (``None``: unknown, the paths are not resolved)."""
    out = []
    for k, v in pnode.items:
        it = _PolicyItem(f"{what}.policy[{show(k.text)}]", k, v)
        if isinstance(v, YScalar) and v.kind == "str" and v.value in POLICIES:
            it.value = v.value
        elif not isinstance(v, YBad):
            hint = did_you_mean(v.value, POLICIES) if isinstance(v, YScalar) and v.kind == "str" else ""
            it.value_problem = f"must be truncate or reject, got {v.describe()}{hint}"
        if k.kind != "str":
            it.problem = f"a key of policy is a field path, got {k.describe()}"
        elif msg_type is not None:
            try:
                it.target = registry.walk_bounded(msg_type, k.value, "policy")
            except PathError as exc:
                it.problem = exc.args[0]
        out.append(it)
    return out


def carried_reject_fields(topics: YNode | None, registry: MsgRegistry) -> set[tuple[str, str]]:
    """The (message type, field name) pairs that a subscribed topic's
    ``policy`` gives policy reject (rule 4.15); read before the topics are
    checked, nothing is reported here (:func:`check_policy` does)."""
    out: set[tuple[str, str]] = set()
    for item, direction, msg_type in _topic_types(topics, registry).values():
        pnode = item.get("policy")
        if direction != SUBSCRIBE or not isinstance(pnode, YMap):
            continue
        for it in _policy_items(pnode, msg_type, registry, ""):
            if it.target is not None and it.value == "reject":
                out.add(it.target.key)
    return out


def _one_value_per_field(ck: _Checker, rule: str, seen: dict, it: _PolicyItem | _MaxItem,
                         value: str | int, noun: str) -> None:
    """One field of a message type (one C struct in every topic of the
    type) gets one value (rule 4.15): the entry ``it`` of a ``policy`` or
    ``max_length`` gives ``value`` (a ``noun``: policy, maximum) to the
    field ``it.target.key``; it is refused, with the position of the first
    entry, if an earlier one gave the field another value.  ``seen`` maps
    each field to its first entry and value (``it`` is added when it is
    the first)."""
    first = seen.get(it.target.key)
    if first is None:
        seen[it.target.key] = (it, value)
        return
    first_it, first_value = first
    if first_value != value:
        owner, fname = it.target.key
        ck.err_rule(rule, it.key,
                    f"{it.what}: {value} differs from the {noun} {first_value} given to the same field "
                    f"({fname} of {owner}) at line {first_it.key.line}, column {first_it.key.col} "
                    f"({first_it.what}); one C struct holds the field in every topic of type {owner}, "
                    f"so it has one {noun}")


def check_policy(ck: _Checker, decls: list[_TopicDecl], registry: MsgRegistry) -> None:
    """Rule 4.15: a subscribed topic's ``policy: {<field path>: truncate |
    reject}`` names carried variable-length arrays or strings of its
    message; one field of a message type (one C struct in every topic of
    the type) gets one policy."""
    rule = "4.15"
    seen: dict[tuple[str, str], tuple[_PolicyItem, str]] = {}
    inner = _element_types(registry)
    for d in decls:
        pnode = d.node.get("policy")
        if pnode is None or isinstance(pnode, YBad):
            continue
        if not isinstance(pnode, YMap):
            ck.err_rule(rule, pnode, f"{d.what}.policy must be a mapping of field paths to truncate or reject "
                                     f"(e.g. {{ranges: reject}}), got {pnode.describe()}")
            continue
        if d.direction == PUBLISH:
            ck.err_rule(rule, pnode, f"{d.what}.policy: topic {show(d.name)} is published by the node; a policy "
                                     "says what a subscribed topic does with received data longer than its maximum")
            continue
        msg_type = d.msg_type if d.msg_type is not None and registry.raw(d.msg_type) is not None else None
        for it in _policy_items(pnode, msg_type, registry, d.what):
            if it.value_problem is not None:
                ck.err_rule(rule, it.node, f"{it.what} {it.value_problem}")
            if msg_type is None:
                continue
            if it.problem is not None:
                ck.err_rule(rule, it.key, f"{it.what}: {it.problem} (topic {show(d.name)}, {msg_type})")
                continue
            if it.target.key not in registry.carry_bounded:
                owner, fname = it.target.key
                ck.err_rule(rule, it.key, f"{it.what}: {fname} of {owner} is not carried (no relation reads it), "
                                          f"so it has no policy (topic {show(d.name)})")
                continue
            if it.value is None:
                continue
            if it.value == "reject" and (it.target.in_element or it.target.owner in inner):
                owner, fname = it.target.key
                where = (f"{show(it.key.value)} is inside an element of a variable-length array" if it.target.in_element
                         else f"{fname} of {owner} is also inside the elements of {inner[owner]}")
                ck.err_rule(rule, it.key,
                            f"{it.what}: {where}: policy reject is refused there (the environment model's "
                            "Environment.too_long would test it in every element the node can hold, received or "
                            "not, the wrapper in the received ones only); use truncate, or reject on the array "
                            "itself")
                continue
            _one_value_per_field(ck, rule, seen, it, it.value, "policy")


def _element_types(registry: MsgRegistry) -> dict[str, str]:
    """The message types inside the elements of the carried
    variable-length arrays of messages (rule 4.15), each with the array
    it is in (``poses of nav_msgs/Path``): a string or sequence of these
    types is in every element of such an array."""
    out: dict[str, str] = {}
    for owner, fname in sorted(registry.carry_bounded):
        raw = registry.raw(owner)
        f = raw.field(fname) if raw is not None else None
        if f is None or f.card != "sequence" or f.base_kind != "msg":
            continue
        for t in registry.used_types([f.base]):
            out.setdefault(t.name, f"{fname} of {owner}")
    return out


def check_max_length(ck: _Checker, decls: list[_TopicDecl], registry: MsgRegistry) -> None:
    """Rule 4.15: a topic's ``max_length: {<field path>: N}`` names
    variable-length arrays of primitives or ``string`` fields of its
    message (through nested messages and fixed-size arrays of messages),
    each with an integer ``N`` from 1 to :data:`MAX_SEQUENCE_LENGTH`; one
    field of a message type (held by one C struct in every topic of the
    type) gets one maximum."""
    rule = "4.15"
    seen: dict[tuple[str, str], tuple[_MaxItem, int]] = {}
    for d in decls:
        mnode = d.node.get("max_length")
        if mnode is None or isinstance(mnode, YBad):
            continue
        if not isinstance(mnode, YMap):
            ck.err_rule(rule, mnode, f"{d.what}.max_length must be a mapping of field paths to maximum lengths "
                                     f"(e.g. {{ranges: 1081}}), got {mnode.describe()}")
            continue
        msg_type = d.msg_type if d.msg_type is not None and registry.raw(d.msg_type) is not None else None
        for it in _max_length_items(mnode, msg_type, registry, d.what):
            if it.value_problem is not None:
                ck.err_rule(rule, it.value, f"{it.what} {it.value_problem}")
            if msg_type is None:
                continue  # the type is reported
            if it.problem is not None:
                ck.err_rule(rule, it.key, f"{it.what}: {it.problem} (topic {show(d.name)}, {msg_type})")
                continue
            if it.n is None:
                continue
            _one_value_per_field(ck, rule, seen, it, it.n, "maximum")


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


def check_strings(ck: _Checker, decls: list[_TopicDecl], registry: MsgRegistry) -> None:
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
            items = _string_items(d.node, msg_type, registry, d.what)
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
                ck.err_rule(rule, it.key, f"{it.what}: field {show(_steps_text(steps))} of topic {show(d.name)} "
                                          f"already has a constant ({first.what}, line {first.key.line})")
                ok = False
                continue
            seen[steps] = it
            if value is not None:
                found.append(StringConstant(steps, value, Pos(it.key.line, it.key.col)))
        if ok:
            d.strings = found


def _steps_text(steps) -> str:
    out = ""
    for s in steps:
        out += f"[{s}]" if isinstance(s, int) else ("." if out else "") + s
    return out


def check_freshness(ck: _Checker, decls: list[_TopicDecl], in_rels: list[_Rel],
                    inputs: dict[str, ControllerField] | None, period: int | None) -> set[str]:
    """Rule 4.12: topics' ``timeout_ms`` and ``on_timeout``, input
    relations' ``on_timeout`` (their fallbacks, set on each relation) and
    derived inputs.  Returns the names of the *timed* topics (a
    ``timeout_ms`` or a derived input): the glue keeps the globals
    ``<c>_time``, ``<c>_new`` and ``<c>_rcvd`` for each (rule 4.9)."""
    rule = "4.12"
    timed: set[str] = set()
    for d in decls:
        what = d.what
        tnode, pnode = d.node.get("timeout_ms"), d.node.get("on_timeout")
        if tnode is not None:
            timed.add(d.name)
            d.timeout_ms = _timeout(ck, d, tnode, what, period)
        if pnode is not None and not isinstance(pnode, YBad):
            if tnode is None:
                ck.err_rule(rule, pnode, f"{what}.on_timeout is only allowed together with timeout_ms "
                                         "(the topic has no timeout)")
            if isinstance(pnode, YScalar) and pnode.kind == "str" and pnode.value in ON_TIMEOUT_POLICIES:
                d.policy = pnode.value
            else:
                hint = (did_you_mean(pnode.value, ON_TIMEOUT_POLICIES) if isinstance(pnode, YScalar)
                        and pnode.kind == "str" else "")
                if not hint and isinstance(pnode, YScalar) and pnode.kind in ("int", "float", "bool"):
                    hint = " (a constant fallback is given by an input relation's on_timeout)"
                ck.err_rule(rule, pnode, f"{what}.on_timeout must be 'hold' or 'zero', got {pnode.describe()}{hint}")

    for i, r in enumerate(in_rels):
        w = f"relations.inputs[{i}]"
        m = r.node
        onode = m.get("on_timeout")
        if r.is_derived:
            fnode = m.get("field")
            if fnode is not None:
                ck.err_rule(rule, fnode, f"{w}.field: a derived input reads no message field "
                                         "(a relation has either field or derived; field goes with derived: "
                                         "length or truncated only)")
                r.ok = False
            if onode is not None:
                ck.err_rule(rule, onode, f"{w}.on_timeout: a derived input has no fallback "
                                         "(it does not read a message field)")
                r.ok = False
            dnode = m.get("derived")
            if isinstance(dnode, YBad):
                r.ok = False
            elif isinstance(dnode, YScalar) and dnode.kind == "str" and dnode.value in DERIVED_KINDS:
                r.derived = dnode.value
            else:
                hint = (did_you_mean(dnode.value, DERIVED_KINDS)
                        if isinstance(dnode, YScalar) and dnode.kind == "str" else "")
                hint = hint or (did_you_mean(dnode.value, tuple(SEQUENCE_DERIVED))
                                if isinstance(dnode, YScalar) and dnode.kind == "str" else "")
                ck.err_rule(rule, dnode, f"{w}.derived must be 'is_new', 'received' or 'age_ms' (or, with a "
                                         f"field, 'length' or 'truncated'), got {dnode.describe()}{hint}")
                r.ok = False
            if r.ctrl_field is not None and inputs is not None and inputs[r.ctrl_field].is_array:
                f = inputs[r.ctrl_field]
                target = f.name if r.ctrl_index is None else f"{f.name}[{r.ctrl_index}]"
                ck.err_rule("4.15", r.ctrl_node,
                            f"{w}.input: a derived input feeds a scalar controller input; {show(target)} is "
                            f"{'an element of ' if r.ctrl_index is not None else ''}the array {f.name} "
                            f"({f.type_text})")
                r.ok = False
            elif r.derived is not None and r.ctrl_field is not None and inputs is not None:
                need, prim = DERIVED_PRIMS[r.derived], inputs[r.ctrl_field].prim
                if prim != need:
                    ck.err_rule(rule, r.ctrl_node,
                                f"{w}.input: {r.derived} related to a non-{need} field: controller input "
                                f"{show(r.ctrl_field)} is {prim} ({r.derived} is a {need})")
                    r.ok = False
            if r.topic is not None:
                timed.add(r.topic.name)
            continue
        if r.ctrl_field is not None and inputs is not None and inputs[r.ctrl_field].is_array:
            _array_fallback(ck, r, w, inputs[r.ctrl_field])
            continue
        if onode is None or isinstance(onode, YBad):
            continue
        if r.topic is not None and r.topic.node.get("timeout_ms") is None:
            ck.err_rule(rule, onode, f"{w}.on_timeout: topic {show(r.topic.name)} has no timeout_ms; "
                                     "a fallback needs one")
            r.ok = False
        if isinstance(onode, YScalar) and onode.kind == "str" and onode.value in ON_TIMEOUT_POLICIES:
            continue
        if r.ctrl_field is None or inputs is None:
            continue  # the input is reported, and its type unknown
        prim = inputs[r.ctrl_field].prim
        value, problem = fallback_constant(onode, prim)
        if problem is not None:
            hint = (did_you_mean(onode.value, ON_TIMEOUT_POLICIES)
                    if isinstance(onode, YScalar) and onode.kind == "str" else "")
            if hint or (isinstance(onode, YScalar) and onode.kind == "str" and "YAML 1.1" not in problem):
                ck.err_rule(rule, onode, f"{w}.on_timeout must be 'hold', 'zero' or a constant of type {prim} "
                                         f"(the type of controller input {show(r.ctrl_field)}), "
                                         f"got {onode.describe()}{hint}")
            else:
                ck.err_rule(rule, onode, f"{w}.on_timeout: the fallback of controller input "
                                         f"{show(r.ctrl_field)} ({prim}): {problem}")
            r.ok = False
        else:
            r.fallback = value
    return timed


def _array_fallback(ck: _Checker, r: _Rel, w: str, f: ControllerField) -> None:
    """Rule 4.15 (and 4.12): a relation feeding a controller array, whole or
    one element, has no fallback: its ``on_timeout`` (or else its topic's,
    when the topic has a timeout) is ``hold``."""
    onode = r.node.get("on_timeout")
    target = f.name if r.ctrl_index is None else f"{f.name}[{r.ctrl_index}]"
    if isinstance(onode, YBad):
        r.ok = False
        return
    if onode is not None:
        if isinstance(onode, YScalar) and onode.kind == "str" and onode.value == "hold":
            if r.topic is not None and r.topic.node.get("timeout_ms") is None:
                ck.err_rule("4.12", onode, f"{w}.on_timeout: topic {show(r.topic.name)} has no timeout_ms; "
                                           "a fallback needs one")
                r.ok = False
            return
        ck.err_rule("4.15", onode, f"{w}.on_timeout: controller input {show(target)} is "
                                   f"{'an element of ' if r.ctrl_index is not None else ''}the array {f.name} "
                                   f"({f.type_text}), which has no fallback (fallbacks feed scalar inputs): "
                                   "write on_timeout: hold")
        r.ok = False
        return
    if r.topic is not None and r.topic.timeout_ms is not None and r.topic.policy != "hold":
        ck.err_rule("4.15", r.ctrl_node, f"{w}.input: topic {show(r.topic.name)} has a timeout with on_timeout "
                                         f"{r.topic.policy}, which gives each input it feeds a fallback, but "
                                         f"{show(target)} is {'an element of ' if r.ctrl_index is not None else ''}"
                                         f"the array {f.name} ({f.type_text}), which has none (fallbacks feed "
                                         "scalar inputs): write on_timeout: hold on this relation or on the topic")
        r.ok = False


def _timeout(ck: _Checker, d: _TopicDecl, node: YNode, what: str, period: int | None) -> int | None:
    """The ``timeout_ms`` of topic ``d`` written at ``node``, or ``None``
    (reported) when it is not a valid one (rule 4.12)."""
    rule = "4.12"
    if isinstance(node, YBad):
        return None
    if d.direction == PUBLISH:
        ck.err_rule(rule, node, f"{what}.timeout_ms: topic {show(d.name)} is published by the node; "
                                "a timeout is for a subscribed topic")
        return None
    if not (isinstance(node, YScalar) and node.kind == "int"):
        ck.err_rule(rule, node, f"{what}.timeout_ms must be an integer number of milliseconds, "
                                f"got {node.describe()}")
        return None
    v = node.value
    if v <= 0:
        ck.err_rule(rule, node, f"{what}.timeout_ms must be a positive number of milliseconds, got {show(node.text)}")
        return None
    if v > MAX_TIMEOUT_MS:
        ck.err_rule(rule, node, f"{what}.timeout_ms: {node.text} ms is longer than a day "
                                f"(at most {MAX_TIMEOUT_MS})")
        return None
    if period is not None and v < period:
        ck.err_rule(rule, node, f"{what}.timeout_ms: {node.text} ms is a timeout shorter than the period "
                                f"(node.period_ms is {period})")
        return None
    return v


#: The ranges of the integer types that a fallback may have but a
#: diagram's constant may not (:func:`pyrosgen.frontend.blocks.scalar_of`
#: reads the others).
_NARROW_INT_RANGES = {
    "int8": (-(1 << 7), (1 << 7) - 1),
    "uint8": (0, (1 << 8) - 1),
    "int16": (-(1 << 15), (1 << 15) - 1),
    "uint16": (0, (1 << 16) - 1),
}


def fallback_constant(node: YNode, prim: str) -> tuple[Scalar | None, str | None]:
    """The constant of type ``prim`` (any ROS primitive) written at
    ``node``, or why it is not one: read as rule 4.11 reads a diagram's
    constants (:func:`pyrosgen.frontend.blocks.scalar_of`): an integer in
    the type's range (a float is refused for an integer type), a float
    rounded once, to nearest even, from the exact decimal, ``true`` or
    ``false`` for ``bool``."""
    if prim in _NARROW_INT_RANGES and isinstance(node, YScalar) and node.kind in ("int", "float"):
        if node.kind != "int":
            return None, f"{show(node.text)} is not an integer, and the type is {prim}"
        lo, hi = _NARROW_INT_RANGES[prim]
        if not lo <= node.value <= hi:
            return None, f"{node.text} is out of the range of {prim} ({lo} to {hi})"
        return Scalar(prim, node.value, node.text), None
    return scalar_of(node, prim)


def _list(names) -> str:
    names = list(names)
    if len(names) > 12:
        names = names[:12] + ["..."]
    return ", ".join(names) if names else "(none)"


def load_model(path: str | Path, standard_msgs=None) -> NodeModel:
    """Read, parse and validate the node model file at ``path``.

    ``standard_msgs``: the target's standard message definitions (rule
    4.17; ``None``: ROS 1 Noetic's; ROS 2's come from
    :func:`pyrosgen.ros2.frontend.load_model_ros2`).
    Raises :class:`InvalidNodeModel` with every problem found.
    """
    path = Path(path)
    doc = load_yaml(path)
    return build_model(doc.root, doc.file, path, list(doc.diagnostics), standard_msgs=standard_msgs)


def build_model(root: YMap, file: str, path: Path, diags: list[Diagnostic], standard_msgs=None) -> NodeModel:
    """Validate a parsed model tree and build the :class:`NodeModel`."""
    ck = _Checker(file, path.parent, diags)
    ck.keys(root, "the node model", _TOP_REQUIRED, _TOP_OPTIONAL)

    registry = MsgRegistry(standard=standard_msgs)
    msg_paths = ck.msg_paths(root.get("msg_paths"), registry)

    node_name, period = ck.node_section(ck.mapping(root.get("node"), "node"))
    cm, ctrl_name, (uvar, ufields), (yvar, yfields) = ck.controller_section(
        ck.mapping(root.get("controller"), "controller")
    )
    # The string fields the constants name (rule 4.14) and the strings and
    # variable-length arrays the input relations read (rule 4.15) are
    # carried, with their maxima: known before any message type's carried
    # view is computed.
    registry.set_carried(carried_bounded_fields(root.get("topics"), root.get("relations"), registry),
                         carried_reject_fields(root.get("topics"), registry))
    decls = ck.topics_section(root.get("topics"), registry)
    check_max_length(ck, decls, registry)
    check_policy(ck, decls, registry)
    ck.diags.extend(registry.diagnostics)
    registry.diagnostics.clear()
    topics = {d.name: d for d in decls}
    inputs = {f.name: f for _, f in ufields} if ufields is not None else None
    outputs = {f.name: f for _, f in yfields} if yfields is not None else None
    in_rels, out_rels = ck.relations_section(root.get("relations"), topics, inputs, outputs, registry)
    ck.diags.extend(registry.diagnostics)

    # Timeouts, fallbacks and derived inputs (rule 4.12).
    timed = check_freshness(ck, decls, in_rels, inputs, period)

    # Stamps (rule 4.13).
    check_stamps(ck, decls, out_rels, registry)

    # Constant strings (rule 4.14).
    check_strings(ck, decls, registry)

    # Published sequences and strings from the controller (rule 4.15).
    check_published_sequences(ck, out_rels, registry)

    # Every controller input (each element of an array input, rule 4.15)
    # is fed by exactly one relation, plain or derived.
    check_fed(ck, in_rels, ufields, inputs)

    # A published field is fed at most once.
    written: dict[tuple[str, str], _Rel] = {}
    for r in out_rels:
        if r.topic is None or r.path is None:
            continue
        twice: dict[int, list[str]] = {}
        for leaf, _ in r.leaves():
            key = (r.topic.name, str(leaf))
            if key in written:
                twice.setdefault(written[key].node.line, []).append(str(leaf))
            else:
                written[key] = r
        for line, leaves in twice.items():
            if r.elements is not None:
                ck.err_rule("4.8", r.path_node,
                            f"field {show(r.row[0])} of topic {show(r.topic.name)} is fed twice: elements "
                            f"{_index_ranges(i for p, i, _ in r.elements if str(p) in leaves)} are also written "
                            f"by the relation at line {line}")
            else:
                ck.err_rule("4.8", r.path_node,
                            f"field {show(r.written or str(r.path))} of topic {show(r.topic.name)} is fed twice "
                            f"(first by the relation at line {line})")
            r.ok = False

    # A controller written as a block diagram (rule 4.11): scalar inputs and
    # outputs only (rule 4.15).
    arrays = [(knode, f, side) for side, fields in (("inputs", ufields), ("outputs", yfields))
              for knode, f in (fields or ()) if f.is_array]
    if cm is not None and (cm.get("blocks") is not None or cm.get("outports") is not None) and arrays:
        for knode, f, side in arrays:
            ck.err_rule("4.15", knode,
                        f"controller.{side}.fields.{f.name}: a block diagram's inputs and outputs are scalars; "
                        f"the array {f.name} ({f.type_text}) is for a controller brought in C (declare "
                        f"{f.size} scalar fields for the diagram)")
        diagram = None
    else:
        diagram = check_diagram(ck, cm, ctrl_name, ufields, yfields, uvar, yvar, period)

    # Derived C names: valid, short enough, pairwise distinct.
    check_c_names(ck, decls, ctrl_name, cm, uvar, yvar, registry, timed)

    if ck.diags:
        raise InvalidNodeModel(_sorted(ck.diags, file))

    # Everything checked: build the immutable model.
    assert node_name is not None and period is not None and ctrl_name is not None
    assert uvar is not None and yvar is not None and ufields is not None and yfields is not None
    topic_objs: dict[str, Topic] = {}
    for d in decls:
        assert d.usable and d.msg_type is not None and d.queue_size is not None and d.direction
        topic_objs[d.name] = Topic(
            name=d.name,
            c_name=topic_c_name(d.name),
            direction=d.direction,
            msg_type=d.msg_type,
            queue_size=d.queue_size,
            pos=Pos(d.node.line, d.node.col),
            timeout_ms=d.timeout_ms,
            on_timeout=d.policy if d.timeout_ms is not None else None,
            stamped=d.stamped,
            stamp_from=d.stamp_from,
            strings=tuple(d.strings),
        )
    controller = Controller(
        name=ctrl_name,
        inputs=IOStruct(uvar, f"ExtU_{ctrl_name}_T", tuple(f for _, f in ufields)),
        outputs=IOStruct(yvar, f"ExtY_{ctrl_name}_T", tuple(f for _, f in yfields)),
        diagram=diagram,
    )
    irs = tuple(
        InputRelation(topic_objs[r.topic.name], path, r.ctrl_field, Pos(r.node.line, r.node.col),
                      fallback=_fallback(r, inputs[r.ctrl_field].prim), written=written,
                      input_index=index, row=r.row)
        for r in in_rels if not r.is_derived
        for path, index, written in (r.elements or [(r.path, r.ctrl_index, r.written)])
    )
    drs = tuple(
        DerivedRelation(topic_objs[r.topic.name], r.derived, r.ctrl_field, Pos(r.node.line, r.node.col))
        for r in in_rels if r.is_derived
    )
    ors = tuple(
        OutputRelation(r.ctrl_field, topic_objs[r.topic.name], path, Pos(r.node.line, r.node.col),
                       written=written, output_index=index, row=(r.row[1], r.row[0]) if r.row else None)
        for r in out_rels
        for path, index, written in (r.elements or [(r.path, r.ctrl_index, r.written)])
    )
    messages = registry.used_types(t.msg_type for t in topic_objs.values())
    return NodeModel(
        name=node_name,
        period_ms=period,
        controller=controller,
        topics=tuple(topic_objs.values()),
        input_relations=irs,
        output_relations=ors,
        messages=messages,
        source=path,
        msg_paths=tuple(msg_paths),
        derived_relations=drs,
    )


def check_fed(ck: _Checker, in_rels: list[_Rel], ufields, inputs) -> None:
    """Rules 4.8 and 4.15: every controller input, and every element of an
    array input, is fed by exactly one relation (an input relation,
    element by element for a whole array, or a derived input)."""
    fed: dict[tuple[str, int | None], _Rel] = {}
    for r in in_rels:
        if r.ctrl_field is None:
            continue
        f = inputs[r.ctrl_field] if inputs is not None else None
        if f is not None and f.is_array and r.ctrl_index is None and r.elements is None:
            # a refused relation to a whole array: it stands for all of it
            for i in range(f.size):
                fed.setdefault((r.ctrl_field, i), r)
            continue
        twice: dict[int, list[int | None]] = {}
        for _, index in r.leaves():
            key = (r.ctrl_field, index)
            if key in fed:
                twice.setdefault(fed[key].node.line, []).append(index)
            else:
                fed[key] = r
        if not twice:
            continue
        r.ok = False
        line, indices = next(iter(twice.items()))
        if indices == [None]:
            ck.err_rule("4.8", r.ctrl_node,
                        f"controller input {show(r.ctrl_field)} is fed twice (first by the relation at line {line})")
        elif r.elements is None:
            ck.err_rule("4.15", r.ctrl_node,
                        f"element {indices[0]} of controller input {show(r.ctrl_field)} is fed twice (first by "
                        f"the relation at line {line}); each element of a controller array is fed exactly once")
        else:
            lines = sorted(twice)
            where = f"line {lines[0]}" if len(lines) == 1 else f"lines {', '.join(map(str, lines))}"
            ck.err_rule("4.15", r.ctrl_node,
                        f"elements {_index_ranges(i for ix in twice.values() for i in ix)} of controller input "
                        f"{show(r.ctrl_field)} are fed twice (also by the relations at {where}); each element "
                        "of a controller array is fed exactly once")
    if ufields is None or not ck.inputs_listed:
        return
    for knode, f in ufields:
        if not f.is_array:
            if (f.name, None) not in fed:
                ck.err_rule("4.8", knode, f"controller input {show(f.name)} is not fed by any input relation")
            continue
        missing = [i for i in range(f.size) if (f.name, i) not in fed]
        if len(missing) == f.size:
            ck.err_rule("4.15", knode, f"controller input {show(f.name)} ({f.type_text}) is not fed by any input "
                                       f"relation (relate a whole array to it, or each element {f.name}[i])")
        elif len(missing) == 1:
            ck.err_rule("4.15", knode, f"element {missing[0]} of controller input {show(f.name)} ({f.type_text}) "
                                       "is not fed by any input relation; each element of a controller array is "
                                       "fed exactly once")
        elif missing:
            ck.err_rule("4.15", knode, f"elements {_index_ranges(missing)} of controller input {show(f.name)} "
                                       f"({f.type_text}) are not fed by any input relation; each element of a "
                                       "controller array is fed exactly once")


def _fallback(r: _Rel, prim: str) -> Scalar | None:
    """The value a plain input relation's input gets when its topic is
    stale (rule 4.12): the relation's ``on_timeout`` or else its topic's
    (default ``zero``: the zero of the input's type); ``None`` for
    ``hold`` and for a topic without a timeout."""
    if r.topic.timeout_ms is None:
        return None
    if r.fallback is not None:
        return r.fallback
    onode = r.node.get("on_timeout")
    policy = onode.value if isinstance(onode, YScalar) and onode.kind == "str" else r.topic.policy
    return replace(zero(prim), text="zero") if policy == "zero" else None


def check_c_names(ck: _Checker, decls, ctrl_name, cm, uvar, yvar, registry: MsgRegistry,
                  timed: set[str] = frozenset()) -> None:
    """Check that every C name the generators derive is a usable identifier
    of at most :data:`MAX_NAME_LEN` characters and that no two coincide
    (``timed``: the names of the timed topics, whose glue has three more
    globals, rule 4.12)."""
    seen: dict[str, str] = {}

    def claim(name: str, origin: str, where, rule: str = "4.9") -> None:
        problem = identifier_problem(name, global_scope=True)
        if problem:
            ck.err_rule(rule, where, f"the C name {show(name)} derived from {origin} cannot be used: {problem}")
            return
        if name in seen:
            ck.err_rule(rule, where, f"the C name {show(name)} derived from {origin} collides with the one derived from {seen[name]}")
            return
        seen[name] = origin

    for n in FIXED_C_NAMES:
        seen[n] = "the generated glue (a temporary)" if n.startswith("_") else "the generated glue"
    for n in LOCAL_C_NAMES:
        seen[n] = "the generated glue (a parameter name)"
    if ctrl_name is not None:
        where = cm.get("name") if cm is not None else None
        for n in (f"{ctrl_name}_step", f"{ctrl_name}_initialize", f"ExtU_{ctrl_name}_T", f"ExtY_{ctrl_name}_T"):
            claim(n, f"controller {show(ctrl_name)}", where)
    if cm is not None:
        for var, key in ((uvar, "inputs"), (yvar, "outputs")):
            sub = cm.get(key)
            if var is not None and isinstance(sub, YMap):
                claim(var, f"controller.{key}.name", sub.get("name"))
    if ctrl_name is not None and cm is not None and cm.get("blocks") is not None:
        # the state global and struct of a diagram's C (rule 4.11)
        for n in (f"{ctrl_name}_DW", f"DW_{ctrl_name}_T"):
            claim(n, f"the block diagram of controller {show(ctrl_name)} (its state)", cm.key_node("blocks"),
                  rule="4.11")

    c_names: dict[str, _TopicDecl] = {}
    for d in decls:
        if d.name.startswith("<") or topic_name_problem(d.name):
            continue
        c = topic_c_name(d.name)
        if c in c_names:
            ck.err_rule(
                "4.9",
                d.name_node,
                f"topics {show(c_names[c].name)} (line {c_names[c].name_node.line}) and "
                f"{show(d.name)} have the same C name {show(c)}",
            )
            continue
        c_names[c] = d
        problem = identifier_problem(c, global_scope=True)
        if problem and not problem.startswith("it is longer"):
            ck.err_rule("4.9", d.name_node, f"topic {show(d.name)}: its C name {show(c)} cannot be used: {problem}")
            continue
        longest = max(
            (f"ros_subscribe_{c}", f"ros_advertise_{c}", f"output_glue_{c}", f"{c}_callback"),
            key=len,
        )
        if len(longest) > MAX_NAME_LEN:
            ck.err_rule(
                "4.9",
                d.name_node,
                f"topic {show(d.name)}: the derived C name {show(longest)} is longer than "
                f"{MAX_NAME_LEN} characters; use a shorter topic name",
            )
            continue
        t = Topic(d.name, c, d.direction or SUBSCRIBE, "", 1)
        for n in t.derived_names():
            claim(n, f"topic {show(d.name)}", d.name_node)
        if d.name in timed:
            for n in t.timed_names():
                claim(n, f"topic {show(d.name)} (its receipt time and flags, rule 4.12)", d.name_node)

    used = registry.used_types(d.msg_type for d in decls if d.type_ok and d.msg_type)
    type_nodes = {}
    for d in decls:
        if d.type_ok and d.msg_type and d.msg_type not in type_nodes:
            type_nodes[d.msg_type] = d.type_node
    for mt in used:
        # Report at the first topic whose type uses it.
        where = None
        for tname, tnode in type_nodes.items():
            if mt.name == tname or mt.name in _contained(registry, tname):
                where = tnode
                break
        claim(mt.c_name, f"message type {mt.name}", where)


def _contained(registry: MsgRegistry, name: str) -> set[str]:
    return {m.name for m in registry.used_types([name])}


def _sorted(diags: list[Diagnostic], file: str) -> list[Diagnostic]:
    unique = list(dict.fromkeys(diags))
    return sorted(
        unique,
        key=lambda d: (d.file != file, d.file, d.line or 0, d.col or 0),
    )

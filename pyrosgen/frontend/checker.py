"""The checker every rule module reports through (DESIGN.md section 4).

:class:`Checker` collects the diagnostics of one model file (each citing its
rule, by default the rule of the model section its message names) and reads
the structure every section shares: mappings, known keys (rule 4.1: "no
other key anywhere in the model", a misspelt one with a suggestion),
strings, integers and identifiers (rule 4.9).  :class:`TopicDecl` and
:class:`Rel` are a topic declaration and a relation row as far as the
rules have checked them; the rule modules fill them in, pass after pass,
and :mod:`pyrosgen.frontend.validate` builds the model from them.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from pyrosgen.errors import Diagnostic, show
from pyrosgen.frontend.model import Scalar, StringConstant
from pyrosgen.frontend.msgload import BoundedTarget
from pyrosgen.frontend.msgmodel import FieldPath
from pyrosgen.frontend.names import did_you_mean, identifier_problem
from pyrosgen.frontend.yamlsrc import YBad, YMap, YNode, YScalar


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


def _rule_of(message: str) -> str | None:
    """The rule of the model section ``message`` names (by its prefix)."""
    for prefix, rule in _SECTION_RULES:
        if message.startswith(prefix):
            return rule
    return None


def name_list(names) -> str:
    """``names`` for a message: comma-separated, at most 12 of them."""
    names = list(names)
    if len(names) > 12:
        names = names[:12] + ["..."]
    return ", ".join(names) if names else "(none)"


@dataclass
class TopicDecl:
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
class Rel:
    """A relation row as far as it could be checked."""

    node: YMap
    topic: TopicDecl | None = None
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


@dataclass
class Checker:
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
        """``node`` if it is a mapping; else ``None``, reported unless it is
        missing or already refused (a :class:`YBad`)."""
        if node is None or isinstance(node, YBad):
            return None
        if not isinstance(node, YMap):
            self.err(node, f"{what} must be a mapping, got {node.describe()}")
            return None
        return node

    def keys(self, m: YMap, what: str, required, optional=()) -> None:
        """Report the keys of ``m`` that are neither ``required`` nor
        ``optional``, and each missing required one."""
        allowed = tuple(required) + tuple(optional)
        for k in m.keys():
            if k not in allowed:
                kn = m.key_node(k)
                if k == "qos":  # rule 4.18: a key of a topic only
                    self.err_rule("4.18", kn, f"{what}: unknown key {show(k)}: qos is a key of a topic "
                                              "declaration (topics: [{name: ..., qos: ...}])")
                    continue
                self.err(
                    kn,
                    f"{what}: unknown key {show(k)}{did_you_mean(k, allowed)}; "
                    f"expected {name_list(allowed)}",
                )
        for k in required:
            if m.get(k) is None:
                self.err(m.owner_pos, f"{what}: missing key {show(k)}")

    def string(self, node: YNode | None, what: str) -> str | None:
        """The non-empty string written at ``node``, or ``None`` (reported
        unless missing or already refused)."""
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
        """The integer from ``lo`` to ``hi`` written at ``node``, or ``None``
        (reported unless missing or already refused)."""
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
        """The C identifier written at ``node`` (rule 4.9; ``global_scope``: a
        global name), or ``None`` (reported)."""
        name = self.string(node, what)
        if name is None:
            return None
        problem = identifier_problem(name, global_scope=global_scope)
        if problem:
            self.err_rule("4.9", node, f"{what} {show(name)} cannot be used: {problem}")
            return None
        return name

"""Validation of a node model file against every rule of DESIGN.md section 4:
the orchestrator.

:func:`load_model` reads the YAML (:mod:`pyrosgen.frontend.yamlsrc`, rule
4.1) and :func:`build_model` runs the rules, one module per rule or group
of closely related rules, in this order:

1. the top-level keys (rule 4.1, :mod:`pyrosgen.frontend.checker`);
2. the message registry, loaded once, before the rules run
   (:func:`pyrosgen.frontend.rule_messages.load_messages`: ``msg_paths``,
   rule 4.5; the strings and variable-length arrays the glue carries,
   rules 4.14 and 4.15); the rules below only query it;
3. the node and the controller (rules 4.2, 4.3: :mod:`~pyrosgen.frontend.rule_node`);
4. the topics and their message types (rules 4.4, 4.5:
   :mod:`~pyrosgen.frontend.rule_topics`), their ``max_length`` and
   ``policy`` (rule 4.15: :mod:`~pyrosgen.frontend.rule_sequences`), their
   ``qos`` (rule 4.18: :mod:`~pyrosgen.frontend.rule_qos`);
5. the relations and their field paths (rules 4.6, 4.7:
   :mod:`~pyrosgen.frontend.rule_relations`; whole controller arrays, rule
   4.15: :mod:`~pyrosgen.frontend.rule_arrays`);
6. freshness (rule 4.12: :mod:`~pyrosgen.frontend.rule_freshness`), stamps
   (4.13: :mod:`~pyrosgen.frontend.rule_stamps`), constant strings (4.14:
   :mod:`~pyrosgen.frontend.rule_strings`), published sequences (4.15);
7. coverage (rule 4.8: :mod:`~pyrosgen.frontend.rule_coverage`);
8. a block diagram (rule 4.11: :mod:`pyrosgen.frontend.blocks`);
9. the derived C names (rule 4.9: :mod:`~pyrosgen.frontend.rule_c_names`).

Every problem is collected; if there is any,
:class:`pyrosgen.errors.InvalidNodeModel` is raised with all of them.
Otherwise the checked declarations become a
:class:`pyrosgen.frontend.model.NodeModel`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from pyrosgen.errors import Diagnostic, InvalidNodeModel
from pyrosgen.frontend.checker import Checker, Rel, TopicDecl
from pyrosgen.frontend.model import (
    Controller, ControllerField, DerivedRelation, Diagram, InputRelation, IOStruct, NodeModel, OutputRelation,
    DEFAULT_QOS, Pos, Qos, Topic,
)
from pyrosgen.frontend.msgload import MsgRegistry
from pyrosgen.frontend.names import topic_c_name
# Besides the passes, the names other code imported from here before the rules
# had modules of their own are imported (and so still importable) here.
from pyrosgen.frontend.rule_c_names import FIXED_C_NAMES, LOCAL_C_NAMES, check_c_names
from pyrosgen.frontend.rule_coverage import check_fed, check_written_once
from pyrosgen.frontend.rule_freshness import check_freshness, fallback_constant, fallback_of
from pyrosgen.frontend.rule_messages import (
    carried_bounded_fields, carried_reject_fields, carried_string_fields, load_messages, reserved_package,
)
from pyrosgen.frontend.rule_node import (
    MAX_CONTROLLER_FIELDS, MAX_PERIOD_MS, check_controller_diagram, controller_section, node_section,
)
from pyrosgen.frontend.rule_relations import relations_section
from pyrosgen.frontend.rule_qos import check_qos, ros1_qos_warning
from pyrosgen.frontend.rule_sequences import POLICIES, check_max_length, check_policy, check_published_sequences
from pyrosgen.frontend.rule_stamps import STAMP_FIELD, check_stamps
from pyrosgen.frontend.rule_strings import FRAME_ID_FIELD, HEADER_TYPE, check_strings
from pyrosgen.frontend.rule_topics import MAX_QUEUE_SIZE, topics_section
from pyrosgen.frontend.yamlsrc import YMap, load_yaml

__all__ = ["load_model", "MAX_PERIOD_MS", "MAX_QUEUE_SIZE", "FIXED_C_NAMES"]

_TOP_REQUIRED = ("node", "controller", "topics", "relations")
_TOP_OPTIONAL = ("msg_paths",)


@dataclass
class _Checked:
    """What the rules found in one model, section by section: each part is
    ``None`` (or empty) when its section is refused."""

    node_name: str | None = None
    period: int | None = None
    cm: YMap | None = None  # the controller section
    ctrl_name: str | None = None
    uvar: str | None = None
    ufields: list | None = None  # (key node, ControllerField) pairs
    yvar: str | None = None
    yfields: list | None = None
    decls: list[TopicDecl] = field(default_factory=list)
    in_rels: list[Rel] = field(default_factory=list)
    out_rels: list[Rel] = field(default_factory=list)
    diagram: Diagram | None = None
    qos: dict = field(default_factory=dict)  # topic name -> (Qos, node), rule 4.18

    def fields(self, side: str) -> dict[str, ControllerField] | None:
        """The controller's inputs or outputs by name (``None``: refused)."""
        pairs = self.ufields if side == "inputs" else self.yfields
        return {f.name: f for _, f in pairs} if pairs is not None else None


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
    ck = Checker(file, path.parent, diags)
    ck.keys(root, "the node model", _TOP_REQUIRED, _TOP_OPTIONAL)
    registry, msg_paths = load_messages(ck, root, standard_msgs)
    checked = _run_rules(ck, root, registry)
    if ck.diags:
        raise InvalidNodeModel(_sorted(ck.diags, file))
    return _assemble(checked, registry, path, msg_paths)


def _run_rules(ck: Checker, root: YMap, registry: MsgRegistry) -> _Checked:
    """Run the rules of DESIGN.md section 4 on ``root``, in order, each
    pass on what the passes before it accepted; every problem goes to
    ``ck``."""
    c = _Checked()
    c.node_name, c.period = node_section(ck, ck.mapping(root.get("node"), "node"))
    c.cm, c.ctrl_name, (c.uvar, c.ufields), (c.yvar, c.yfields) = controller_section(
        ck, ck.mapping(root.get("controller"), "controller"))
    c.decls = topics_section(ck, root.get("topics"), registry)
    check_max_length(ck, c.decls, registry)
    check_policy(ck, c.decls, registry)
    c.qos = check_qos(ck, c.decls)
    inputs, outputs = c.fields("inputs"), c.fields("outputs")
    topics = {d.name: d for d in c.decls}
    c.in_rels, c.out_rels = relations_section(ck, root.get("relations"), topics, inputs, outputs, registry)
    # the problems found in .msg files while the types and paths resolved
    ck.diags.extend(registry.diagnostics)
    timed = check_freshness(ck, c.decls, c.in_rels, inputs, c.period)
    check_stamps(ck, c.decls, c.out_rels, registry)
    check_strings(ck, c.decls, registry)
    check_published_sequences(ck, c.out_rels, registry)
    check_fed(ck, c.in_rels, c.ufields, inputs)
    check_written_once(ck, c.out_rels)
    c.diagram = check_controller_diagram(ck, c.cm, c.ctrl_name, c.ufields, c.yfields, c.uvar, c.yvar, c.period)
    check_c_names(ck, c.decls, c.ctrl_name, c.cm, c.uvar, c.yvar, registry, timed)
    return c


def _assemble(c: _Checked, registry: MsgRegistry, path: Path, msg_paths: list[Path]) -> NodeModel:
    """The immutable model of a model file whose every rule passed."""
    assert c.node_name is not None and c.period is not None and c.ctrl_name is not None
    assert c.uvar is not None and c.yvar is not None and c.ufields is not None and c.yfields is not None
    topic_objs = _topics(c.decls, {name: q for name, (q, _) in c.qos.items()})
    controller = Controller(
        name=c.ctrl_name,
        inputs=IOStruct(c.uvar, f"ExtU_{c.ctrl_name}_T", tuple(f for _, f in c.ufields)),
        outputs=IOStruct(c.yvar, f"ExtY_{c.ctrl_name}_T", tuple(f for _, f in c.yfields)),
        diagram=c.diagram,
    )
    irs, drs, ors = _relations(c, topic_objs)
    messages = registry.used_types(t.msg_type for t in topic_objs.values())
    return NodeModel(
        name=c.node_name,
        period_ms=c.period,
        controller=controller,
        topics=tuple(topic_objs.values()),
        input_relations=irs,
        output_relations=ors,
        messages=messages,
        source=path,
        msg_paths=tuple(msg_paths),
        derived_relations=drs,
        # rule 4.18: read here for the target ROS 1, which ignores it (the ROS 2 front end drops these)
        warnings=tuple(ros1_qos_warning(str(path), name, q, qnode) for name, (q, qnode) in c.qos.items()),
    )


def _topics(decls: list[TopicDecl], qos: dict[str, Qos]) -> dict[str, Topic]:
    """The topics of checked declarations, by name, in model order, with
    their QoS (rule 4.18)."""
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
            qos=qos.get(d.name, DEFAULT_QOS),
        )
    return topic_objs


def _relations(c: _Checked, topic_objs: dict[str, Topic]):
    """The input, derived and output relations of checked rows (a row
    relating whole arrays gives one relation per element, rule 4.15)."""
    inputs = c.fields("inputs")
    irs = tuple(
        InputRelation(topic_objs[r.topic.name], path, r.ctrl_field, Pos(r.node.line, r.node.col),
                      fallback=fallback_of(r, inputs[r.ctrl_field].prim), written=written,
                      input_index=index, row=r.row)
        for r in c.in_rels if not r.is_derived
        for path, index, written in (r.elements or [(r.path, r.ctrl_index, r.written)])
    )
    drs = tuple(
        DerivedRelation(topic_objs[r.topic.name], r.derived, r.ctrl_field, Pos(r.node.line, r.node.col))
        for r in c.in_rels if r.is_derived
    )
    ors = tuple(
        OutputRelation(r.ctrl_field, topic_objs[r.topic.name], path, Pos(r.node.line, r.node.col),
                       written=written, output_index=index, row=(r.row[1], r.row[0]) if r.row else None)
        for r in c.out_rels
        for path, index, written in (r.elements or [(r.path, r.ctrl_index, r.written)])
    )
    return irs, drs, ors


def _sorted(diags: list[Diagnostic], file: str) -> list[Diagnostic]:
    """``diags`` without duplicates, those of the model file first, each
    file's by position."""
    unique = list(dict.fromkeys(diags))
    return sorted(
        unique,
        key=lambda d: (d.file != file, d.file, d.line or 0, d.col or 0),
    )

"""Rule 4.18 (quality of service): a topic's ``qos`` for ROS 2.

Spelling, in ROS 2's vocabulary (rclcpp's ``rclcpp::QoS`` and the rmw
profiles of ``rmw/qos_profiles.h``)::

    qos: sensor_data                         # rclcpp::SensorDataQoS
    qos: default                             # rclcpp::QoS (the default)
    qos: {reliability: best_effort}          # volatile, the default durability
    qos: {durability: transient_local}       # reliable, the default reliability
    qos: {profile: sensor_data, durability: transient_local}

The history is always KEEP_LAST of depth the topic's ``queue_size`` (rule
4.4): the model has one depth, not two.  A profile gives the reliability
and durability of its rmw profile (``rmw_qos_profile_default``: reliable,
volatile; ``rmw_qos_profile_sensor_data``: best effort, volatile; each
profile's own depth, 10 and 5, is replaced by ``queue_size``, as
``rclcpp::SensorDataQoS().keep_last(queue_size)`` does); the mapping's
``reliability`` and ``durability`` override it.

The target ROS 1 has no QoS (roscpp's TCPROS is reliable and volatile): a
valid ``qos`` is read, and the front end warns that the ROS 1 target
ignores it (:attr:`pyrosgen.frontend.model.NodeModel.warnings`; the ROS 2
front end drops the warning).  A ``qos`` that is not valid is refused for
both targets: one model file, one meaning.
"""

from __future__ import annotations

from pyrosgen.errors import Diagnostic, show
from pyrosgen.frontend.checker import Checker, TopicDecl
from pyrosgen.frontend.model import DEFAULT_QOS, Qos
from pyrosgen.frontend.names import did_you_mean
from pyrosgen.frontend.yamlsrc import YBad, YMap, YNode, YScalar

__all__ = ["RULE", "PROFILES", "RELIABILITIES", "DURABILITIES", "QOS_KEYS", "check_qos", "ros1_qos_warning"]

RULE = "4.18"
#: the profiles a ``qos`` may name, as rclcpp's classes and rmw's profiles set them
PROFILES = {"default": DEFAULT_QOS, "sensor_data": Qos(reliability="best_effort", durability="volatile")}
RELIABILITIES = ("reliable", "best_effort")
DURABILITIES = ("volatile", "transient_local")
QOS_KEYS = ("profile", "reliability", "durability")
_EXAMPLE = "(e.g. qos: sensor_data, or qos: {reliability: best_effort, durability: transient_local})"


def _word(ck: Checker, node: YNode, what: str, allowed) -> str | None:
    """The value at ``node``, one of ``allowed`` (reported otherwise)."""
    if isinstance(node, YScalar) and node.kind == "str" and node.value in allowed:
        return node.value
    if isinstance(node, YScalar) and node.kind == "str":
        got = show(node.value)
    else:
        got = node.describe()
    ck.err_rule(RULE, node, f"{what} must be one of {', '.join(allowed)}, got {got}"
                            f"{did_you_mean(node.value, allowed) if isinstance(node, YScalar) else ''}")
    return None


def _qos_of(ck: Checker, d: TopicDecl, qnode: YNode) -> Qos | None:
    """The QoS written at ``qnode`` for topic ``d``, or ``None`` (reported)."""
    what = f"{d.what}.qos"
    if isinstance(qnode, YScalar) and qnode.kind == "str":
        prof = _word(ck, qnode, f"{what} (a profile)", tuple(PROFILES))
        return PROFILES[prof] if prof is not None else None
    if not isinstance(qnode, YMap):
        ck.err_rule(RULE, qnode, f"{what} must be a profile name ({', '.join(PROFILES)}) or a mapping of "
                                 f"{', '.join(QOS_KEYS)}, got {qnode.describe()} {_EXAMPLE}")
        return None
    ok = True
    for k in qnode.keys():
        if k not in QOS_KEYS:
            ok = False
            extra = " (the history depth is the topic's queue_size)" if k in ("depth", "history") else ""
            ck.err_rule(RULE, qnode.key_node(k), f"{what}: unknown key {show(k)}{did_you_mean(k, QOS_KEYS)}; "
                                                 f"expected {', '.join(QOS_KEYS)}{extra}")
    base, values = DEFAULT_QOS, {}
    pnode = qnode.get("profile")
    if pnode is not None and not isinstance(pnode, YBad):
        prof = _word(ck, pnode, f"{what}.profile", tuple(PROFILES))
        ok = ok and prof is not None
        base = PROFILES.get(prof, DEFAULT_QOS) if prof is not None else DEFAULT_QOS
    for key, allowed in (("reliability", RELIABILITIES), ("durability", DURABILITIES)):
        vnode = qnode.get(key)
        if vnode is None or isinstance(vnode, YBad):
            continue
        v = _word(ck, vnode, f"{what}.{key}", allowed)
        ok = ok and v is not None
        if v is not None:
            values[key] = v
    if not ok:
        return None
    return Qos(reliability=values.get("reliability", base.reliability),
               durability=values.get("durability", base.durability))


def check_qos(ck: Checker, decls: list[TopicDecl]) -> dict[str, tuple[Qos, YNode]]:
    """Rule 4.18: each topic's ``qos``, when it has one and it is valid, by
    topic name, with the node it is written at; every problem goes to
    ``ck``."""
    out: dict[str, tuple[Qos, YNode]] = {}
    for d in decls:
        qnode = d.node.get("qos")
        if qnode is None or isinstance(qnode, YBad):
            continue
        q = _qos_of(ck, d, qnode)
        if q is not None:
            out[d.name] = (q, qnode)
    return out


def ros1_qos_warning(file: str, topic: str, q: Qos, node: YNode) -> Diagnostic:
    """The warning of a ``qos`` read for the target ROS 1 (rule 4.18)."""
    return Diagnostic(
        file, node.line, node.col,
        f"topic {show(topic)}: qos ({q.reliability}, {q.durability}) is for the target ros2 (--ros2); the ROS 1 "
        "target ignores it: roscpp's TCPROS transport is reliable and volatile",
        severity="warning", rule=RULE)

"""The C API over rcl (ROS 2) of a generated node: the same header as the
roscpp wrapper's (``ros_api.h.j2``: the API the glue calls) and a C
implementation over rcl (``rcl_api.c.j2``), rendered from the model Coq
printed (its topics, types, queue sizes and period), the message
definitions of the front end's ROS 2 reading (the conversions between the
rosidl C messages and the glue's structs) and the topics' QoS (rule 4.18).

:func:`check_rcl_wrapper` holds the rendered wrapper to the proved model:
it subscribes and advertises exactly the proved topics, with their rosidl
types, C structs and queue sizes, and sleeps with the proved period; and
to the QoS record (:func:`qos_text`, the file ``<node>.qos`` of a ROS 2
build): each subscription and publisher has exactly the recorded history
(KEEP_LAST), depth, reliability and durability.

The QoS is not in the model Coq proves things about (it decides which
messages arrive: an assumption on the environment, DESIGN.md section 6.1),
so it reaches the wrapper from the model file: the front end's reading,
written as the record ``<node>.qos``, which ``build --ros2`` compares with
the second reading's (:func:`pyrosgen.nversion.qos.qos_text`) and with the
proved topics (:func:`parse_qos_text`), and ``verify`` re-derives.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from pyrosgen.errors import DetailedFailure
from pyrosgen.frontend.model import DEFAULT_QOS, NodeModel, Qos
from pyrosgen.proof.modeltext import ProvedModel, parse_model_text
from pyrosgen.frontend.msgmodel import PRIMITIVES
from pyrosgen.render import render, ros_name, source_label
from pyrosgen.ros.wrapper import _reject_paths

__all__ = ["Ros2WrapperFiles", "ros2_wrapper_files", "render_rcl_wrapper", "rosidl_header",
           "check_rcl_wrapper", "Ros2WrapperMismatch", "message_packages", "QOS_HEADER", "qos_text",
           "parse_qos_text", "qos_file_name"]

_C_IDENT = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")

#: rosidl's C sequence type of each primitive (``rosidl_runtime_c__<name>__Sequence``)
ROSIDL_SEQ = {"bool": "boolean", "int8": "int8", "uint8": "uint8", "int16": "int16", "uint16": "uint16",
              "int32": "int32", "uint32": "uint32", "int64": "int64", "uint64": "uint64",
              "float32": "float", "float64": "double"}


class Ros2WrapperMismatch(DetailedFailure):
    """The rcl wrapper does not implement the proved model (exit 2)."""


# -- the QoS record (rule 4.18) -------------------------------------------

#: The first line of a QoS record (``pyrosgen.nversion.qos.QOS_HEADER``).
QOS_HEADER = "pyrosgen-qos 1"
#: rmw's constants (``rmw/types.h``) of each reliability and durability of rule 4.18
RMW_RELIABILITY = {"reliable": "RMW_QOS_POLICY_RELIABILITY_RELIABLE",
                   "best_effort": "RMW_QOS_POLICY_RELIABILITY_BEST_EFFORT"}
RMW_DURABILITY = {"volatile": "RMW_QOS_POLICY_DURABILITY_VOLATILE",
                  "transient_local": "RMW_QOS_POLICY_DURABILITY_TRANSIENT_LOCAL"}
_QOS_LINE = re.compile(r"topic (\S+) (subscribe|publish) keep_last ([1-9][0-9]{0,4}) "
                       r"(reliable|best_effort) (volatile|transient_local)")


def qos_file_name(node: str) -> str:
    """The QoS record of a ROS 2 build, ``<node>.qos``."""
    return f"{_ident(node)}.qos"


def qos_text(model: NodeModel) -> str:
    """The QoS record of ``model`` (the front end's reading, rule 4.18): a
    header line, then one line per topic in the model's order, ``topic NAME
    DIRECTION keep_last DEPTH RELIABILITY DURABILITY`` (the depth is the
    queue size)."""
    lines = [QOS_HEADER] + [f"topic {t.name} {t.direction} keep_last {t.queue_size} {t.qos.reliability} "
                            f"{t.qos.durability}" for t in model.topics]
    return "".join(line + "\n" for line in lines)


def parse_qos_text(text: str, proved: ProvedModel) -> dict[str, Qos]:
    """The QoS of each proved topic by name, from the record ``text``
    (:func:`qos_text`); ``ValueError`` unless the record is well formed and
    names exactly the proved topics, in the proved order, with their
    directions and their queue sizes as depths."""
    lines = text.split("\n")
    if not text.endswith("\n") or lines[0] != QOS_HEADER:
        raise ValueError(f"not a QoS record: its first line is not {QOS_HEADER!r} or it does not end with a newline")
    rows = lines[1:-1]
    if len(rows) != len(proved.topics):
        raise ValueError(f"{len(rows)} topics, the proved model has {len(proved.topics)}")
    out: dict[str, Qos] = {}
    for i, (row, t) in enumerate(zip(rows, proved.topics), start=2):
        m = _QOS_LINE.fullmatch(row)
        if m is None:
            raise ValueError(f"line {i}: {row[:120]!r} is not 'topic NAME DIRECTION keep_last DEPTH "
                             "RELIABILITY DURABILITY'")
        if (m.group(1), m.group(2), int(m.group(3))) != (t.name, t.direction, t.queue):
            raise ValueError(f"line {i}: {m.group(1)} {m.group(2)} depth {m.group(3)}, the proved topic is "
                             f"{t.name} {t.direction} queue {t.queue}")
        out[t.name] = Qos(reliability=m.group(4), durability=m.group(5))
    return out


def _ident(name: str) -> str:
    if not _C_IDENT.match(name):
        raise ValueError(f"refusing to print {name!r} as a C identifier")
    return name


def snake(type_name: str) -> str:
    """rosidl's file name of a message type (``TwistStamped`` ->
    ``twist_stamped``, ``PointCloud2`` -> ``point_cloud2``), as
    ``rosidl_pycommon.convert_camel_case_to_lower_case_underscore``."""
    value = re.sub(r"(.)([A-Z][a-z]+)", r"\1_\2", type_name)
    value = re.sub(r"([a-z0-9])([A-Z])", r"\1_\2", value)
    return value.lower()


def rosidl_header(ros_type: str) -> str:
    """``geometry_msgs/TwistStamped`` -> ``geometry_msgs/msg/twist_stamped.h``."""
    pkg, typ = ros_type.split("/", 1)
    return f"{_ident(pkg)}/msg/{snake(_ident(typ))}.h"


def rosidl_c_type(ros_type: str) -> str:
    """``geometry_msgs/TwistStamped`` -> ``geometry_msgs__msg__TwistStamped``."""
    pkg, typ = ros_type.split("/", 1)
    return f"{_ident(pkg)}__msg__{_ident(typ)}"


@dataclass(frozen=True)
class Ros2WrapperFiles:
    types_header: str   #: Coq-printed message structs
    api_header: str     #: the C API prototypes (the roscpp wrapper's)
    api_source: str     #: the C implementation over rcl


def ros2_wrapper_files(model: NodeModel) -> Ros2WrapperFiles:
    n = _ident(model.name)
    return Ros2WrapperFiles(f"{n}_types.h", f"{n}_ros.h", f"{n}_rcl.c")


def message_packages(model: NodeModel) -> list[str]:
    """The ROS 2 packages of every message type the node's structs hold."""
    return sorted({_ident(m.name.split("/", 1)[0]) for m in model.messages if "/" in m.name})


def _context(model: NodeModel, proved: ProvedModel, qos: dict[str, Qos]) -> dict:
    files = ros2_wrapper_files(model)
    by_name = {m.name: m for m in model.messages}
    messages = []
    for m in model.messages:
        if m.is_seq and m.seq_of[0] not in PRIMITIVES:
            # of strings (ros_string<M> elements) or of messages
            elem_c = _ident(next(f for f in m.fields if f.name == "data").c_type.removeprefix("struct "))
            rosidl = ("rosidl_runtime_c__String__Sequence" if m.seq_of[0] == "string"
                      else f"{rosidl_c_type(m.seq_of[0])}__Sequence")
            messages.append({"c_name": _ident(m.c_name), "bounded": "seqelem", "capacity": int(m.capacity),
                             "elem": m.seq_of[0], "elem_c": elem_c, "rosidl": rosidl, "fields": []})
            continue
        if m.is_string:
            messages.append({"c_name": _ident(m.c_name), "bounded": "string", "capacity": int(m.capacity),
                             "rosidl": "rosidl_runtime_c__String", "fields": []})
            continue
        if m.is_seq and m.seq_of[0] in ROSIDL_SEQ:
            messages.append({"c_name": _ident(m.c_name), "bounded": "seq", "capacity": int(m.capacity),
                             "elem": m.seq_of[0], "rosidl": f"rosidl_runtime_c__{ROSIDL_SEQ[m.seq_of[0]]}__Sequence",
                             "fields": []})
            continue
        if m.is_bounded or "/" not in m.name:
            raise ValueError(f"{m.name}: no rcl conversion for this type in this version")
        messages.append({"bounded": None,
            "c_name": _ident(m.c_name),
            "rosidl": rosidl_c_type(m.name),
            "fields": [{"name": _ident(f.name), "kind": f.kind, "array_len": f.array_len,
                        "c_name": by_name[f.msg].c_name if f.kind == "msg" else None} for f in m.fields],
        })
    msgs = {m.name: m for m in model.messages}
    by_c_name = {m.c_name: m.name for m in model.messages}
    topics = []
    for t in proved.topics:
        pkg, typ = t.ros_type.split("/", 1)
        q = qos[t.name]
        for n in (t.c_name, t.subscribe_fn, t.advertise_fn, t.publish_fn, t.struct):
            _ident(n)
        topics.append({
            "name": ros_name(t.name), "c_name": t.c_name, "direction": t.direction, "queue": int(t.queue),
            "type_name": f"{_ident(pkg)}/{_ident(typ)}", "pkg": pkg, "type": typ,
            "rosidl": rosidl_c_type(t.ros_type), "c_struct": t.struct,
            "subscribe_fn": t.subscribe_fn, "advertise_fn": t.advertise_fn, "publish_fn": t.publish_fn,
            # policy reject (rule 4.15): (C access path, maximum), as the roscpp wrapper's
            "rejects": (_reject_paths(msgs, by_c_name.get(t.struct, "")) if t.direction == "subscribe" else []),
            # rule 4.18: the QoS (the depth is the queue size)
            "reliability": RMW_RELIABILITY[q.reliability], "durability": RMW_DURABILITY[q.durability],
            "qos_text": f"{q.reliability}, {q.durability}",
            # for ros_api.h.j2
            "msg_type": t.ros_type, "queue_size": int(t.queue),
        })
    subs = [t for t in topics if t["direction"] == "subscribe"]
    pubs = [t for t in topics if t["direction"] == "publish"]
    return {
        "source": source_label(model.source.name),
        "node": model,
        "header_name": files.api_header,
        "types_header": files.types_header,
        "guard": f"PYROSGEN_{model.name.upper()}_ROS_H",
        # the topics' types, and the element types of sequences of messages (their __Sequence functions)
        "rosidl_headers": sorted({rosidl_header(t["type_name"]) for t in topics}
                                 | {rosidl_header(m.seq_of[0]) for m in model.messages
                                    if m.is_seq and "/" in m.seq_of[0]}),
        "messages": messages,
        "subs": subs,
        "pubs": pubs,
        "msg_c": {t["name"]: t["c_struct"] for t in topics},
        "period_ns": int(proved.period_ms) * 1000000,
    }


class _T(dict):
    """A dict whose keys read as attributes (the templates use ``t.name``)."""

    __getattr__ = dict.__getitem__


def render_rcl_wrapper(model: NodeModel, proved: ProvedModel, *, qos: dict[str, Qos]) -> dict[str, str]:
    """The C API header and its rcl implementation, by file name; the topics
    and the period from ``proved`` (the model Coq printed), the QoS of each
    topic (rule 4.18) from ``qos``, by topic name: the QoS record read back
    (:func:`parse_qos_text`; a required argument, since the proved model
    has no QoS: ``build --ros2`` and ``verify`` both render from the
    record)."""
    missing = [t.name for t in proved.topics if t.name not in qos]
    if missing:
        raise ValueError(f"no QoS for the proved topic {missing[0]}")
    ctx = _context(model, proved, qos)
    ctx["subs"] = [_T(t) for t in ctx["subs"]]
    ctx["pubs"] = [_T(t) for t in ctx["pubs"]]
    ctx["messages"] = [_T(m, fields=[_T(f) for f in m["fields"]]) for m in ctx["messages"]]
    files = ros2_wrapper_files(model)
    return {
        files.api_header: render("ros_api.h.j2", **ctx),
        files.api_source: render("rcl_api.c.j2", **ctx),
    }


_SUB = re.compile(r'rcl_subscription_init\(&g_sub_(\w+), &g_node,\s*ROSIDL_GET_MSG_TYPE_SUPPORT\((\w+), msg, (\w+)\),'
                  r'\s*"([^"]*)", &options\)')
_PUB = re.compile(r'rcl_publisher_init\(&g_pub_(\w+), &g_node,\s*ROSIDL_GET_MSG_TYPE_SUPPORT\((\w+), msg, (\w+)\),'
                  r'\s*"([^"]*)", &options\)')
_SETUP = re.compile(r"^void (ros_(?:subscribe|advertise)_\w+)\((?:void \(\*cb\)\(struct (\w+) \*\)|void)\)\n\{\n",
                    re.M)
_OPTIONS = re.compile(r"\boptions\.([\w.]+)\s*=\s*([^;]*);")
_PERIOD = re.compile(r"^#define PYROSGEN_PERIOD_NS (\d+)LL$", re.M)


def _setups(text: str) -> dict[str, tuple[str | None, list[tuple[str, str]]]]:
    """Each ``ros_subscribe_<c>``/``ros_advertise_<c>`` of the wrapper: the
    struct of its callback and every assignment to its ``options`` (the QoS
    it asks for), in order, the first being its declaration from rcl's
    default options (``("init", "rcl_subscription_get_default_options()")``)."""
    out = {}
    for m in _SETUP.finditer(text):
        end = text.find("\n}\n", m.end())
        body = text[m.end(): end if end >= 0 else len(text)]
        kind = "subscription" if m.group(1).startswith("ros_subscribe_") else "publisher"
        init = re.match(rf"    rcl_{kind}_options_t options = (rcl_{kind}_get_default_options\(\));\n", body)
        out[m.group(1)] = (m.group(2), [("init", init.group(1) if init else "other")]
                           + [(k, v.strip()) for k, v in _OPTIONS.findall(body)])
    return out


def _qos_problems(fn: str, t, got: list[tuple[str, str]], q: Qos) -> list[str]:
    """Rule 4.18: the QoS a topic's setup function asks for is exactly the
    default options' (``rcl_*_get_default_options``, rmw's default profile)
    with history KEEP_LAST, the proved queue size as depth, and the
    recorded reliability and durability."""
    kind = "subscription" if t.direction == "subscribe" else "publisher"
    want = [("init", f"rcl_{kind}_get_default_options()"),
            ("qos.history", "RMW_QOS_POLICY_HISTORY_KEEP_LAST"), ("qos.depth", str(t.queue)),
            ("qos.reliability", RMW_RELIABILITY[q.reliability]), ("qos.durability", RMW_DURABILITY[q.durability])]
    if got == want:
        return []
    depth = dict(got).get("qos.depth")
    if depth is not None and depth != str(t.queue) and [k for k, _ in got] == [k for k, _ in want]:
        return [f"  {fn}: history depth {depth}, the proved queue size is {t.queue}"]
    if [k for k, _ in got] == [k for k, _ in want]:
        shown = "; ".join(f"options {k} is {g}, not {w}" for (k, g), (_, w) in zip(got, want) if g != w)
    else:
        shown = "sets options " + (", ".join(f"{k} = {v}" for k, v in got) or "none") + ", not " + \
            ", ".join(f"{k} = {v}" for k, v in want)
    return [f"  {fn}: {shown} (the QoS of {t.name}: KEEP_LAST {t.queue}, {q.reliability}, {q.durability}, "
            "rule 4.18)"]


# The ROS time a stamp holds (rule 4.13): the seconds and nanoseconds of
# ros_now(), which outside a callback reads the ROS clock once after each
# spin (g_now_state), and ROS 2's time message converted field by field, sec
# to sec, nanosec to nanosec (the glue stores (int)ros_time_sec() into the
# int32 sec).
_NOW_BODY = """unsigned long long ros_now(void)
{
    if (g_now_state != 1) {
        if (g_now_state == 0) {
            g_now_ns = ros_time_ns();
        } else {
            unsigned long long rcv = g_rx_ns > 0 ? (unsigned long long)g_rx_ns : system_ns();
            g_now_ns = g_sim_time ? sim_at(rcv) : rcv;
        }
        g_now_state = 1;
    }
    return g_now_ns;
}"""
_NOW_DEF = re.compile("^" + re.escape(_NOW_BODY) + "$", re.M)
_SEC_DEF = re.compile(r"^unsigned int ros_time_sec\(void\)\n\{\n"
                      r"    return \(unsigned int\)\(ros_now\(\) / 1000000000ULL\);\n\}$", re.M)
_NSEC_DEF = re.compile(r"^unsigned int ros_time_nsec\(void\)\n\{\n"
                       r"    return \(unsigned int\)\(ros_now\(\) % 1000000000ULL\);\n\}$", re.M)
_TIME_CONV = {
    "to_c": re.compile(r"^static inline void to_c_builtin_interfaces_Time\(const builtin_interfaces__msg__Time \*r, "
                       r"struct builtin_interfaces_Time \*c\)\n\{\n    c->sec = r->sec;\n"
                       r"    c->nanosec = r->nanosec;\n\}$", re.M),
    "from_c": re.compile(r"^static inline void from_c_builtin_interfaces_Time\(const struct builtin_interfaces_Time \*c, "
                         r"builtin_interfaces__msg__Time \*r\)\n\{\n    r->sec = c->sec;\n"
                         r"    r->nanosec = c->nanosec;\n\}$", re.M),
}


def _stamp_problems(text: str, pm: ProvedModel) -> list[str]:
    """What in the wrapper departs from the ROS time a stamp holds (rule
    4.13): ``ros_now`` defined once (the ROS clock read at the first call
    after a spin, kept until the next), ``ros_time_sec`` and
    ``ros_time_nsec`` defined once, returning the seconds and nanoseconds
    of ``ros_now()``; and, for a model of ROS 2's time message, its
    conversions copying ``sec`` and ``nanosec`` each into itself."""
    problems = []
    if pm.stamps:
        if len(_NOW_DEF.findall(text)) != 1 or len(re.findall(r"\bros_now\s*\(void\)", text)) != 1:
            problems.append("  the wrapper does not define ros_now() once, reading the ROS clock at the first call "
                            "after a spin")
        if len(_SEC_DEF.findall(text)) != 1 or len(re.findall(r"\bros_time_sec\s*\(", text)) != 1:
            problems.append("  the wrapper does not define ros_time_sec() once, returning the seconds of ros_now()")
        if len(_NSEC_DEF.findall(text)) != 1 or len(re.findall(r"\bros_time_nsec\s*\(", text)) != 1:
            problems.append("  the wrapper does not define ros_time_nsec() once, returning the nanoseconds of ros_now()")
    if "builtin_interfaces_Time" in pm.messages:
        for what, pat in _TIME_CONV.items():
            if len(pat.findall(text)) != 1 or len(re.findall(rf"\b{what}_builtin_interfaces_Time\s*\(", text)) < 1:
                problems.append(f"  the wrapper does not define {what}_builtin_interfaces_Time once, copying sec "
                                "to sec and nanosec to nanosec")
    return problems


def check_rcl_wrapper(text: str, proved_model_text: str, *, wrapper_name: str, qos_record: str | None = None) -> None:
    """Raise :class:`Ros2WrapperMismatch` unless the rcl wrapper ``text``
    subscribes and advertises exactly the proved model's topics (names,
    ROS types, C structs of the callbacks, queue sizes as history depths)
    with the QoS of ``qos_record`` (:func:`qos_text`; ``None``: every topic
    the default, reliable and volatile, rule 4.18), sleeps with its period,
    and gives a stamp the ROS time (rule 4.13, :func:`_stamp_problems`)."""
    pm = parse_model_text(proved_model_text)
    problems: list[str] = []
    want = {(t.direction, t.c_name, t.ros_type, t.name) for t in pm.topics}
    got = {("subscribe", c, f"{p}/{ty}", n) for c, p, ty, n in _SUB.findall(text)}
    got |= {("publish", c, f"{p}/{ty}", n) for c, p, ty, n in _PUB.findall(text)}
    for w in sorted(want - got):
        problems.append(f"  the proved topic {w[3]} ({w[0]}, {w[2]}) is not registered so")
    for g in sorted(got - want):
        problems.append(f"  registers {g[3]} ({g[0]}, {g[2]}), which is not a proved topic")
    try:
        qos = (parse_qos_text(qos_record, pm) if qos_record is not None
               else {t.name: DEFAULT_QOS for t in pm.topics})
    except ValueError as exc:
        raise Ros2WrapperMismatch(f"{wrapper_name}: the QoS record does not fit the proved model", [f"  {exc}"]) \
            from None
    setups = _setups(text)
    for t in pm.topics:
        fn = t.subscribe_fn if t.direction == "subscribe" else t.advertise_fn
        if fn not in setups:
            problems.append(f"  no {fn} with a history depth")
            continue
        struct, options = setups[fn]
        problems += _qos_problems(fn, t, options, qos[t.name])
        if t.direction == "subscribe" and struct != t.struct:
            problems.append(f"  {fn}: callback of struct {struct}, the proved struct is {t.struct}")
    periods = _PERIOD.findall(text)
    if periods != [str(pm.period_ms * 1000000)]:
        problems.append(f"  period {periods or 'missing'} ns, the proved period is {pm.period_ms} ms")
    problems += _stamp_problems(text, pm)
    if problems:
        raise Ros2WrapperMismatch(f"{wrapper_name} does not implement the proved model", problems)

"""The validated node model: small immutable classes the emitters consume.

A :class:`NodeModel` is only ever built by :func:`pyrosgen.frontend.validate.load_model` (see
:mod:`pyrosgen.frontend.validate`), after every rule of DESIGN.md section 4 has been
checked, so emitters may rely on it: names are safe C/Coq identifiers, every
controller input (each element of an array input, rule 4.15) is fed by
exactly one relation (an input relation or a derived input, rule 4.12),
relation types match, fallbacks have the type of their input, field paths
name carried scalar leaves, and all derived C names are distinct.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path
from typing import NamedTuple

from pyrosgen.errors import Diagnostic
from pyrosgen.frontend.msgmodel import C_TYPES, SIMULINK_TYPES, FieldPath, MsgType, leaf_paths, msg_c_name

__all__ = [
    "Pos",
    "ControllerField",
    "MAX_CONTROLLER_ARRAY",
    "IOStruct",
    "Controller",
    "Scalar",
    "Block",
    "Diagram",
    "BLOCK_KINDS",
    "STATE_KINDS",
    "SIGNAL_TYPES",
    "Topic",
    "InputRelation",
    "DerivedRelation",
    "DERIVED_KINDS",
    "DERIVED_PRIMS",
    "SEQUENCE_DERIVED",
    "ON_TIMEOUT_POLICIES",
    "MAX_TIMEOUT_MS",
    "OutputRelation",
    "StringConstant",
    "NodeModel",
    "is_direct",
]

SUBSCRIBE = "subscribe"
PUBLISH = "publish"


class Pos(NamedTuple):
    """A 1-based ``(line, col)`` position in the model file (``(0, 0)`` when
    the object was not read from a file)."""

    line: int
    col: int


_NOPOS = Pos(0, 0)


def is_direct(path: FieldPath | str, timed: bool) -> bool:
    """Whether an input relation on message leaf ``path`` (a
    :class:`FieldPath`, or a path as the model text prints it:
    ``ranges.data[5]``) of a topic that is ``timed`` or not (rule 4.12) is
    *direct* (rule 4.16, ``NodeModel.is_direct``): its topic is not timed
    and its path has an index step (an element of a fixed-size array, of
    a variable-length array or of a string: ``ranges.data[5]``,
    ``pose.covariance[35]``, ``header.frame_id.data[3]``; not
    ``ranges.len``, not ``twist.linear.x``).  The topic's callback writes
    a direct relation's controller input straight from ``*msg``;
    ``input_glue`` does not copy it.  The one definition of the rule in
    Python: :meth:`NodeModel.is_direct` and the certificate's
    (``ProvedModel.is_direct``) both call it."""
    if isinstance(path, FieldPath):
        indexed = any(isinstance(s, int) and not isinstance(s, bool) for s in path.steps)
    else:  # the model text's path: C identifiers, dots and [i]
        indexed = "[" in path
    return not timed and indexed


#: The largest size of a controller array (rule 4.15; ``Wellformed``'s
#: bound on a controller field's ``FTarray``).
MAX_CONTROLLER_ARRAY = 65536


class ControllerField(NamedTuple):
    """A field of ``Controller_U`` or ``Controller_Y``: ``(name, prim)``, or
    ``(name, prim, size)`` for a one-dimensional array of ``size``
    elements of ``prim`` (rule 4.15: ``real32_T Scan[1081];``)."""

    name: str
    prim: str
    size: int | None = None

    @property
    def is_array(self) -> bool:
        """Whether the field is an array of :attr:`size` elements."""
        return self.size is not None

    @property
    def c_type(self) -> str:
        """The C type of the field (of one element of an array)."""
        return C_TYPES[self.prim]

    @property
    def simulink_type(self) -> str:
        """The Simulink (``rtwtypes.h``) type name of the field (of one
        element of an array)."""
        return SIMULINK_TYPES[self.prim]

    @property
    def type_text(self) -> str:
        """The type as a model writes it: ``float64``, ``float32[1081]``."""
        return self.prim if self.size is None else f"{self.prim}[{self.size}]"

    @property
    def c_decl(self) -> str:
        """The C declaration of the field: ``double In1``, ``float Scan[1081]``."""
        return f"{self.c_type} {self.name}" + ("" if self.size is None else f"[{self.size}]")

    @property
    def leaves(self) -> tuple[str, ...]:
        """The scalar leaves of the field as C accesses relative to the
        struct: ``('In1',)``, ``('Scan[0]', ..., 'Scan[1080]')``."""
        if self.size is None:
            return (self.name,)
        return tuple(f"{self.name}[{i}]" for i in range(self.size))


@dataclass(frozen=True)
class IOStruct:
    """The controller's input or output structure.

    ``var_name`` is the global (``Controller_U``), ``struct_name`` its type
    (``ExtU_Controller_T``), ``fields`` in declaration order (= C order).
    """

    var_name: str
    struct_name: str
    fields: tuple[ControllerField, ...]

    def field(self, name: str) -> ControllerField | None:
        """The field called ``name``, or ``None``."""
        for f in self.fields:
            if f.name == name:
                return f
        return None

    @property
    def names(self) -> tuple[str, ...]:
        """The field names in declaration order."""
        return tuple(f.name for f in self.fields)

    @property
    def arrays(self) -> tuple[ControllerField, ...]:
        """The array fields (rule 4.15), in declaration order."""
        return tuple(f for f in self.fields if f.is_array)


#: The block kinds of a diagram (rule 4.11), as the model spells them.
BLOCK_KINDS = (
    "Constant", "Gain", "Sum", "Product", "Divide", "Abs", "MinMax", "Saturation",
    "RelationalOperator", "Logic", "Switch", "UnitDelay", "DiscreteIntegrator",
)

#: The blocks with memory: their output in a step is their state at the
#: start of the step (so they break algebraic loops).
STATE_KINDS = ("UnitDelay", "DiscreteIntegrator")

#: The types a diagram's signals may have (``Diagram.sig_prim``).
SIGNAL_TYPES = ("bool", "int32", "uint32", "int64", "uint64", "float32", "float64")


@dataclass(frozen=True)
class Scalar:
    """A constant of a diagram or a fallback of an input relation (rule
    4.12): ``prim`` is its type (one of :data:`SIGNAL_TYPES` in a diagram,
    any ROS primitive for a fallback); ``n`` is its value for the integer
    types (in the type's range: negative for a negative ``int32``), 0 or 1 for
    ``bool``, and the IEEE 754 bit pattern for ``float32``/``float64``
    (the decimal of the model rounded once to the type, to nearest even).
    ``text`` is the model's text (for messages and comments)."""

    prim: str
    n: int
    text: str = field(default="", compare=False)


@dataclass(frozen=True)
class Block:
    """A block of a diagram (rule 4.11), after validation.

    ``name`` is its output signal, ``kind`` one of :data:`BLOCK_KINDS`,
    ``prim`` its output type; ``inputs`` are the signals it reads, in the
    model's order (a Switch's are ``(a, control, b)``).  The other fields
    are its parameters, ``None`` when the kind has none:

    - ``op``: MinMax ``min``/``max``; RelationalOperator ``== != < <= > >=``
      (``~=`` is stored as ``!=``); Logic ``AND OR NAND NOR XOR NOT``;
      Switch ``u2 >= threshold``, ``u2 > threshold`` or ``u2 ~= 0``;
    - ``signs``: a Sum's ``+``/``-`` per input;
    - ``value``: a Constant's value; ``gain``: a Gain's factor, and a
      DiscreteIntegrator's gain (rounded to the type, for information);
    - ``lower``/``upper``: a Saturation's bounds, a DiscreteIntegrator's
      limits (both or neither);
    - ``threshold``: a Switch's (``u2 ~= 0``: none);
    - ``initial``: a UnitDelay's or DiscreteIntegrator's initial state;
    - ``kt``: a DiscreteIntegrator's gain times the sample time, rounded
      once from the exact product (``Diagram.Kintegrator``);
    - ``input_prim``: the type of a RelationalOperator's inputs, of a
      Switch's control input.
    """

    name: str
    kind: str
    prim: str
    inputs: tuple[str, ...]
    op: str | None = None
    signs: str | None = None
    value: Scalar | None = None
    gain: Scalar | None = None
    lower: Scalar | None = None
    upper: Scalar | None = None
    threshold: Scalar | None = None
    initial: Scalar | None = None
    kt: Scalar | None = None
    input_prim: str | None = None
    pos: Pos = field(default=_NOPOS, compare=False, repr=False)

    @property
    def is_state(self) -> bool:
        """Whether the block has memory (UnitDelay, DiscreteIntegrator)."""
        return self.kind in STATE_KINDS


@dataclass(frozen=True)
class Diagram:
    """A controller written as a block diagram (rule 4.11;
    ``coq/theories/ctrl/Diagram.v`` says what it means).

    ``blocks`` are in the model's order; ``inports`` are the controller
    inputs the diagram reads (by a block or an outport), in field order;
    ``outports`` give each controller output field, in field order, with
    the signal it takes; ``order`` is the evaluation order of the blocks
    without memory (each after the blocks it reads, the model's order
    where it allows); ``period_ms`` is the node's period (the integrators'
    sample time).
    """

    blocks: tuple[Block, ...]
    inports: tuple[ControllerField, ...]
    outports: tuple[tuple[ControllerField, str], ...]
    order: tuple[str, ...]
    period_ms: int

    def block(self, name: str) -> Block:
        """The block called ``name`` (``KeyError`` if none)."""
        for b in self.blocks:
            if b.name == name:
                return b
        raise KeyError(name)

    @property
    def states(self) -> tuple[Block, ...]:
        """The blocks with memory, in the model's order."""
        return tuple(b for b in self.blocks if b.is_state)

    def evaluation_order(self) -> tuple[str, ...]:
        """Every signal in the order a step computes it: the inports, the
        states' outputs, then :attr:`order` (``Diagram.dg_eqs``)."""
        return tuple(f.name for f in self.inports) + tuple(b.name for b in self.states) + self.order

    def signal_type(self, name: str) -> str:
        """The type of signal ``name`` (``KeyError`` if none)."""
        for f in self.inports:
            if f.name == name:
                return f.prim
        return self.block(name).prim


@dataclass(frozen=True)
class Controller:
    """The Simulink-style controller: ``<name>_initialize()``, ``<name>_step()``
    reading ``inputs`` and writing ``outputs``.  ``diagram`` is the block
    diagram that defines it (rule 4.11), or ``None`` for a controller that
    the user brings as C."""

    name: str
    inputs: IOStruct
    outputs: IOStruct
    diagram: Diagram | None = None

    @property
    def state_var(self) -> str:
        """The state global of a diagram's C: ``<name>_DW``."""
        return f"{self.name}_DW"

    @property
    def state_struct(self) -> str:
        """Its struct: ``DW_<name>_T``."""
        return f"DW_{self.name}_T"

    @property
    def step_fn(self) -> str:
        """``<name>_step``."""
        return f"{self.name}_step"

    @property
    def initialize_fn(self) -> str:
        """``<name>_initialize``."""
        return f"{self.name}_initialize"


class TopicNames:
    """The C names the generator derives from a topic's C name ``c_name``
    (``ROSGen.glue.Generator``): shared by the front end's :class:`Topic`
    and the proved model's topics (:mod:`pyrosgen.proof.modeltext`)."""

    c_name: str

    @property
    def msg_var(self) -> str:
        """Global holding the last message received: ``<c>_msg``."""
        return f"{self.c_name}_msg"

    @property
    def callback(self) -> str:
        """Subscription callback: ``<c>_callback``."""
        return f"{self.c_name}_callback"

    @property
    def output_glue(self) -> str:
        """Output glue of a published topic: ``output_glue_<c>``."""
        return f"output_glue_{self.c_name}"

    @property
    def subscribe_fn(self) -> str:
        """ROS API call subscribing to the topic: ``ros_subscribe_<c>``."""
        return f"ros_subscribe_{self.c_name}"

    @property
    def advertise_fn(self) -> str:
        """ROS API call advertising the topic: ``ros_advertise_<c>``."""
        return f"ros_advertise_{self.c_name}"

    @property
    def publish_fn(self) -> str:
        """ROS API call publishing on the topic: ``ros_publish_<c>``."""
        return f"ros_publish_{self.c_name}"

    @property
    def cmd_var(self) -> str:
        """Message built by the output glue before publishing: ``<c>_cmd``."""
        return f"{self.c_name}_cmd"

    @property
    def time_var(self) -> str:
        """Receipt time (ns) of the newest message on a timed topic: ``<c>_time``."""
        return f"{self.c_name}_time"

    @property
    def new_var(self) -> str:
        """Whether a message arrived on a timed topic since the previous
        cycle: ``<c>_new``."""
        return f"{self.c_name}_new"

    @property
    def rcvd_var(self) -> str:
        """Whether a message ever arrived on a timed topic: ``<c>_rcvd``."""
        return f"{self.c_name}_rcvd"

    def timed_names(self) -> tuple[str, ...]:
        """The globals the glue keeps for a *timed* topic (one with a
        timeout or a derived input, rule 4.12)."""
        return (self.time_var, self.new_var, self.rcvd_var)



@dataclass(frozen=True)
class StringConstant:
    """A constant string of a published topic (rule 4.14): every message
    the node publishes on the topic carries ``value`` in the ``string``
    field at ``path`` (names and constant indices from the message, e.g.
    ``('header', 'frame_id')``)."""

    path: tuple[str | int, ...]
    value: str
    pos: Pos = field(default=_NOPOS, compare=False, repr=False)

    @property
    def data(self) -> bytes:
        """The bytes the field holds: ``value`` in UTF-8."""
        return self.value.encode("utf-8")

    @property
    def path_text(self) -> str:
        """The path as a model writes it: ``header.frame_id``, ``a[2].b``."""
        out = ""
        for s in self.path:
            out += f"[{s}]" if isinstance(s, int) else ("." if out else "") + s
        return out


@dataclass(frozen=True)
class Qos:
    """A topic's quality of service for ROS 2 (rule 4.18): what its
    subscription or publisher asks of DDS.  The history is always KEEP_LAST
    of depth the topic's ``queue_size`` (rule 4.4: the one depth); the
    defaults are rclcpp's (``rmw_qos_profile_default``): reliable,
    volatile.  ROS 1 has no QoS (roscpp's TCPROS is reliable and volatile):
    the ROS 1 target ignores it, with a warning."""

    reliability: str = "reliable"    #: ``reliable`` or ``best_effort``
    durability: str = "volatile"     #: ``volatile`` or ``transient_local``

    @property
    def is_default(self) -> bool:
        return self == DEFAULT_QOS


#: rclcpp's default QoS (``rmw_qos_profile_default`` but for its depth 10:
#: the depth is the topic's ``queue_size``).
DEFAULT_QOS = Qos()


@dataclass(frozen=True)
class Topic(TopicNames):
    """A topic the node subscribes to or publishes.

    ``name`` is the ROS graph name (``/landshark/gps_velocity``), ``c_name``
    its C name (``landshark_gps_velocity``), ``direction`` is ``'subscribe'``
    or ``'publish'``, ``msg_type`` the ROS type (``geometry_msgs/TwistStamped``).
    """

    name: str
    c_name: str
    direction: str
    msg_type: str
    queue_size: int
    pos: Pos = field(default=_NOPOS, compare=False, repr=False)
    #: the topic's ``timeout_ms`` (rule 4.12), ``None`` when it has none
    timeout_ms: int | None = None
    #: ``stamp`` (rule 4.13): a published message carries the cycle's ROS
    #: time in ``header.stamp`` (``stamp: now``), or the stamp of the newest
    #: message of the subscribed topic named ``stamp_from``
    stamped: bool = False
    stamp_from: str | None = None
    #: the topic's ``on_timeout`` policy, ``'hold'`` or ``'zero'`` (the
    #: default), when it has a timeout; ``None`` otherwise
    on_timeout: str | None = None
    #: the constant strings of a published topic (rule 4.14), in the
    #: order the model writes them
    strings: tuple[StringConstant, ...] = ()
    #: the topic's QoS for ROS 2 (rule 4.18); :data:`DEFAULT_QOS` when the
    #: model gives none
    qos: Qos = DEFAULT_QOS

    @property
    def is_subscribed(self) -> bool:
        """Whether the node subscribes to this topic."""
        return self.direction == SUBSCRIBE

    @property
    def is_published(self) -> bool:
        """Whether the node publishes this topic."""
        return self.direction == PUBLISH

    @property
    def msg_struct(self) -> str:
        """The C struct name of the message type (``geometry_msgs_TwistStamped``)."""
        return msg_c_name(self.msg_type)

    def derived_names(self) -> tuple[str, ...]:
        """Every C name derived from this topic (whatever its direction)."""
        return (
            self.msg_var,
            self.callback,
            self.output_glue,
            self.subscribe_fn,
            self.advertise_fn,
            self.publish_fn,
            self.cmd_var,
        )


#: Longest accepted ``timeout_ms`` (one day; rule 4.12).
MAX_TIMEOUT_MS = 86_400_000

#: A topic's ``on_timeout`` policies (rule 4.12); ``zero`` is the default.
ON_TIMEOUT_POLICIES = ("hold", "zero")

#: The kinds of derived inputs (rule 4.12), as the model spells them.
DERIVED_KINDS = ("is_new", "received", "age_ms")

#: The type of the controller input each derived kind feeds.
DERIVED_PRIMS = {"is_new": "bool", "received": "bool", "age_ms": "uint32"}

#: The ``derived`` kinds that go with a ``field`` naming a variable-length
#: array or a string (rule 4.15), each the leaf of the bounded struct it
#: reads and that leaf's type: they are ordinary input relations on that
#: leaf (``ranges.len``, ``ranges.truncated``).
SEQUENCE_DERIVED = {"length": ("len", "uint32"), "truncated": ("truncated", "bool")}


@dataclass(frozen=True)
class InputRelation:
    """An SI row: field ``path`` of the last message on ``topic`` (a
    subscribed :class:`Topic`) feeds controller input ``input_field``.

    ``fallback`` is the value the input gets when the topic's newest
    message is older than its ``timeout_ms`` (or none arrived yet; rule
    4.12): a :class:`Scalar` of the input's type (``zero``: the type's
    zero, ``+0.0`` for floats), or ``None`` when the input keeps the
    newest message's field (``hold``, or a topic without a timeout)."""

    topic: Topic
    path: FieldPath
    input_field: str
    pos: Pos = field(default=_NOPOS, compare=False, repr=False)
    fallback: Scalar | None = None
    #: the field as the model writes it when that is not ``path`` (rule
    #: 4.15: ``ranges[540]`` for the leaf ``ranges.data[540]``, ``ranges
    #: (length)`` for ``ranges.len``), else ``None``
    written: str | None = field(default=None, compare=False)
    #: the element of controller input array ``input_field`` that the
    #: relation feeds (rule 4.15: ``Scan[540]``), ``None`` for a scalar input
    input_index: int | None = None
    #: for one of the element relations a whole-array row expands into
    #: (rule 4.15: ``{field: ranges, input: Scan}``), the row as the model
    #: writes it, ``(field, input)``: ``('ranges', 'Scan')``; else ``None``
    row: tuple[str, str] | None = field(default=None, compare=False)

    @property
    def field_text(self) -> str:
        """The field as the model writes it."""
        return self.written or str(self.path)

    @property
    def input_target(self) -> str:
        """The controller input fed, as the model text prints it: ``In1``,
        ``Scan[540]``."""
        return self.input_field if self.input_index is None else f"{self.input_field}[{self.input_index}]"

    @property
    def input_elem(self) -> tuple[int, ...]:
        """The path inside the controller input (``NodeModel.ir_elem``):
        ``()`` for a scalar, ``(540,)`` for an element."""
        return () if self.input_index is None else (self.input_index,)


@dataclass(frozen=True)
class DerivedRelation:
    """A derived input (rule 4.12): controller input ``input_field`` gets
    a fact about the messages on ``topic`` (a subscribed :class:`Topic`),
    not one of their fields.  ``kind`` is one of :data:`DERIVED_KINDS`:
    ``is_new`` (``bool``: a message arrived since the previous cycle),
    ``received`` (``bool``: one ever arrived), ``age_ms`` (``uint32``:
    milliseconds since the newest one's receipt, saturating at
    4294967295, also when none arrived yet)."""

    topic: Topic
    kind: str
    input_field: str
    pos: Pos = field(default=_NOPOS, compare=False, repr=False)


@dataclass(frozen=True)
class OutputRelation:
    """A PO row: controller output ``output_field`` feeds field ``path`` of
    each message published on ``topic`` (a published :class:`Topic`); an
    element or the length of a published variable-length array or string
    is a leaf of its bounded struct (``data.data[3]``, ``data.len``, rule
    4.15)."""

    output_field: str
    topic: Topic
    path: FieldPath
    pos: Pos = field(default=_NOPOS, compare=False, repr=False)
    #: the field as the model writes it when that is not ``path`` (rule
    #: 4.15: ``data[3]`` for the leaf ``data.data[3]``, ``data (length)``
    #: for ``data.len``), else ``None``
    written: str | None = field(default=None, compare=False)
    #: the element of controller output array ``output_field`` that the
    #: relation reads (rule 4.15: ``Cmd[3]``), ``None`` for a scalar output
    output_index: int | None = None
    #: for one of the element relations a whole-array row expands into
    #: (rule 4.15: ``{output: Cmd, field: data}``), the row as the model
    #: writes it, ``(output, field)``: ``('Cmd', 'data')``; else ``None``
    row: tuple[str, str] | None = field(default=None, compare=False)

    @property
    def field_text(self) -> str:
        """The field as the model writes it."""
        return self.written or str(self.path)

    @property
    def output_source(self) -> str:
        """The controller output read, as the model text prints it:
        ``Out1``, ``Cmd[3]``."""
        return self.output_field if self.output_index is None else f"{self.output_field}[{self.output_index}]"

    @property
    def output_elem(self) -> tuple[int, ...]:
        """The path inside the controller output (``NodeModel.or_elem``):
        ``()`` for a scalar, ``(3,)`` for an element."""
        return () if self.output_index is None else (self.output_index,)


@dataclass(frozen=True)
class NodeModel:
    """A validated ROS node model (DESIGN.md section 4).

    ``messages`` lists every carried message type the node uses, transitively,
    each after the types it contains (``time``/``duration`` included when
    used).  ``source`` is the model file, ``msg_paths`` the resolved custom
    message folders.
    """

    name: str
    period_ms: int
    controller: Controller
    topics: tuple[Topic, ...]
    input_relations: tuple[InputRelation, ...]
    output_relations: tuple[OutputRelation, ...]
    messages: tuple[MsgType, ...]
    source: Path
    msg_paths: tuple[Path, ...] = ()
    #: derived inputs (rule 4.12), in the model's order; they are not
    #: among :attr:`input_relations`
    derived_relations: tuple[DerivedRelation, ...] = ()
    #: what the front end warns about without refusing the model (rule 4.18:
    #: a ``qos`` read for the target ROS 1, which ignores it); the commands
    #: print them
    warnings: tuple[Diagnostic, ...] = field(default=(), compare=False)

    @property
    def subscribed(self) -> tuple[Topic, ...]:
        """Subscribed topics, in declaration order."""
        return tuple(t for t in self.topics if t.is_subscribed)

    @property
    def published(self) -> tuple[Topic, ...]:
        """Published topics, in declaration order."""
        return tuple(t for t in self.topics if t.is_published)

    def topic(self, name: str) -> Topic:
        """The topic with graph name ``name`` (``KeyError`` if none)."""
        for t in self.topics:
            if t.name == name:
                return t
        raise KeyError(name)

    def message(self, name: str) -> MsgType:
        """The carried message type ``name`` (``KeyError`` if not used)."""
        for m in self.messages:
            if m.name == name:
                return m
        raise KeyError(name)

    def leaf_paths(self, msg_name: str) -> tuple[FieldPath, ...]:
        """Every carried scalar leaf of message type ``msg_name``."""
        return leaf_paths(msg_name, {m.name: m for m in self.messages})

    def read_leaves(self, topic: Topic) -> tuple[FieldPath, ...]:
        """The leaves of subscribed ``topic``'s messages that the node reads
        through the topic's global ``<c>_msg``, in the order of
        :meth:`leaf_paths`: those its non-direct input relations name
        (:meth:`glue_relations`; a direct one, rule 4.16, is written by the
        callback straight into the controller's inputs) and the
        ``sec``/``nsec`` (ROS 2: ``nanosec``) of a stamp copied from it
        (rule 4.13).  Its
        callback copies these and only these into ``<c>_msg``
        (``Generator.read_leaves``, ``NodeModel.read_paths``, which
        exclude the direct relations)."""
        read = {tuple(r.path.steps) for r in self.glue_relations if r.topic.name == topic.name}
        for _, (src, stamp) in self.stamp_from:
            if src == topic.c_name:
                # ROS 1's nsec, ROS 2's nanosec: the time type has one of them
                read |= {(*stamp, "sec"), (*stamp, "nsec"), (*stamp, "nanosec")}
        return tuple(p for p in self.leaf_paths(topic.msg_type) if tuple(p.steps) in read)

    def is_direct(self, r: InputRelation) -> bool:
        """Whether input relation ``r`` is *direct* (rule 4.16,
        ``NodeModel.is_direct``, :func:`is_direct`): its topic is not
        timed (:attr:`timed_topics`) and its path has an index step.  The
        topic's callback copies it from ``*msg`` into the controller's
        inputs; ``input_glue`` does not, and its leaf is not copied into
        the topic's global for it."""
        return is_direct(r.path, r.topic.name in self._timed_names)

    def direct_relations(self, topic: Topic | str) -> tuple[InputRelation, ...]:
        """The direct input relations (rule 4.16) of subscribed ``topic``
        (a Topic or its graph name), in model order: what its callback
        copies into the controller's inputs after its copies into
        ``<c>_msg`` (``NodeModel.direct_of``)."""
        name = topic if isinstance(topic, str) else topic.name
        return tuple(r for r in self.input_relations if r.topic.name == name and self.is_direct(r))

    @property
    def glue_relations(self) -> tuple[InputRelation, ...]:
        """The input relations that are not direct (rule 4.16), in model
        order: those ``input_glue`` copies from the topics' globals into
        the controller's inputs (``NodeModel.glue_inrels``)."""
        return tuple(r for r in self.input_relations if not self.is_direct(r))

    @cached_property
    def _timed_names(self) -> frozenset[str]:
        """The graph names of :attr:`timed_topics` (computed once: every
        relation asks)."""
        return frozenset(t.name for t in self.timed_topics)

    @property
    def timed_topics(self) -> tuple[Topic, ...]:
        """The *timed* topics (rule 4.12), in declaration order: those with
        a ``timeout_ms`` or a derived input.  The glue keeps the globals
        :meth:`Topic.timed_names` for each."""
        derived = {r.topic.name for r in self.derived_relations}
        return tuple(t for t in self.topics if t.timeout_ms is not None or t.name in derived)

    @property
    def timeouts(self) -> tuple[tuple[str, int], ...]:
        """``(topic C name, timeout_ms)`` of each topic with a timeout, in
        topic order (``NodeModel.nm_timeouts``)."""
        return tuple((t.c_name, t.timeout_ms) for t in self.topics if t.timeout_ms is not None)

    @property
    def fallbacks(self) -> tuple[tuple[str, Scalar], ...]:
        """``(controller input, value when stale)`` of each input relation
        with a fallback, in relation order (``NodeModel.nm_fallbacks``)."""
        return tuple((r.input_field, r.fallback) for r in self.input_relations if r.fallback is not None)

    @property
    def stamps(self) -> tuple[tuple[str, tuple[str, ...]], ...]:
        """``(topic C name, path of the stamp)`` of each stamped topic
        (rule 4.13), in topic order (``NodeModel.nm_stamps``); the path is
        always ``header.stamp``."""
        return tuple((t.c_name, ("header", "stamp")) for t in self.topics if t.stamped)

    @property
    def stamp_from(self) -> tuple[tuple[str, tuple[str, tuple[str, ...]]], ...]:
        """``(topic C name, (source topic C name, path of its stamp))`` of
        each topic whose stamp is copied from a subscribed topic (rule
        4.13), in topic order (``NodeModel.nm_stamp_from``)."""
        by_name = {t.name: t for t in self.topics}
        return tuple((t.c_name, (by_name[t.stamp_from].c_name, ("header", "stamp")))
                     for t in self.topics if t.stamped and t.stamp_from is not None)

    @property
    def strings(self) -> tuple[tuple[str, tuple[str | int, ...], bytes], ...]:
        """``(topic C name, path of the string field, its bytes)`` of each
        constant string (rule 4.14), in topic order, then in the order the
        model writes them (``NodeModel.nm_strings``)."""
        return tuple((t.c_name, s.path, s.data) for t in self.topics for s in t.strings)

    @property
    def bounded_fields(self) -> tuple[tuple[str, str, MsgType], ...]:
        """``(message type, field name, bounded struct)`` of each carried
        string (rules 4.14, 4.15) and variable-length array (rule 4.15),
        in the order of :attr:`messages`."""
        by_name = {m.name: m for m in self.messages}
        return tuple((m.name, f.name, by_name[f.msg]) for m in self.messages if not m.is_bounded
                     for f in m.fields if f.kind == "msg" and f.msg in by_name and by_name[f.msg].is_bounded)

    def derived_relation(self, input_field: str) -> DerivedRelation:
        """The derived relation feeding controller input ``input_field``."""
        for r in self.derived_relations:
            if r.input_field == input_field:
                return r
        raise KeyError(input_field)

    def input_relation(self, input_field: str) -> InputRelation:
        """The relation feeding controller input ``input_field`` (a scalar,
        or an element of an array written ``Scan[540]``)."""
        for r in self.input_relations:
            if r.input_target == input_field:
                return r
        raise KeyError(input_field)

    def output_relations_of(self, topic: Topic | str) -> tuple[OutputRelation, ...]:
        """The output relations writing into ``topic`` (a Topic or its name)."""
        name = topic if isinstance(topic, str) else topic.name
        return tuple(r for r in self.output_relations if r.topic.name == name)

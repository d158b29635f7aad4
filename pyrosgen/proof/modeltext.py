"""The node model as canonical text, read from the YAML by the front end, to
compare with the text Coq prints from the model term its theorem is about
(``ROSGen.glue.ModelText.print_model``; grammar there).

This closes a seam of the chain (DESIGN.md section 7): the per-node ``.v``
file is written by :mod:`pyrosgen.proof.coqmodel`, and the theorem is about
whatever model that file contains.  If the emitter (or someone editing the
file) swapped two relations, Coq would prove the theorem about the wrong
model.  ``pyrosgen generate`` therefore has Coq print the model it proved
things about and refuses (exit 2, nothing written) unless it is, line for
line, the model this module reads from the front end's :class:`NodeModel`
-- built here directly from the validated model, not from the emitter's
Coq literals, so that an emitter bug cannot hide itself.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

from pyrosgen.errors import DetailedFailure
from pyrosgen.frontend.model import DERIVED_KINDS, NodeModel, TopicNames, is_direct
from pyrosgen.frontend.msgmodel import MsgField, msg_c_name

__all__ = [
    "HEADER", "model_text", "ModelMismatch", "compare_model_texts", "diagram_text", "compare_diagram_texts",
    "ProvedTopic", "ProvedModel", "parse_model_text", "MalformedModelText", "bytes_text", "parse_bytes_text",
]

#: First line of the text (its format version).
HEADER = "pyrosgen-model 1"


class ModelMismatch(DetailedFailure):
    """The model Coq proved things about is not the model of the YAML file
    (exit code 2: pyrosgen's own chain is broken, or the ``.v`` was edited)."""


def _ftype(f: MsgField) -> str:
    base = f.prim if f.kind == "prim" else f"msg {msg_c_name(f.msg)}"
    return base if f.array_len is None else f"array {f.array_len} {base}"


def _path(steps) -> str:
    out = ""
    for s in steps:
        if isinstance(s, int) and not isinstance(s, bool):
            out += f"[{s}]"
        else:
            out += ("." if out else "") + s
    return out


def ctrl_ftype_text(f) -> str:
    """A controller field's type as ``ModelText`` prints it: ``float64``,
    ``array 1081 float32`` (rule 4.15)."""
    return f.prim if getattr(f, "size", None) is None else f"array {f.size} {f.prim}"


def _path_tail(steps) -> str:
    """A path inside a controller field, printed after its name: ``[540]``
    (``ModelText``: the field's name then the path's text), ``""`` for none."""
    out = _path(steps)
    return out if not out or out.startswith("[") else "." + out


def model_text(model: NodeModel) -> str:
    """The canonical text of ``model`` (the same grammar as Coq's
    ``print_model``)."""
    c = model.controller
    lines = [
        HEADER,
        f"node {model.name}",
        f"period_ms {model.period_ms}",
        f"controller {c.name}",
        f"inputs {c.inputs.var_name} {c.inputs.struct_name}",
        *(f"input {f.name} {ctrl_ftype_text(f)}" for f in c.inputs.fields),
        f"outputs {c.outputs.var_name} {c.outputs.struct_name}",
        *(f"output {f.name} {ctrl_ftype_text(f)}" for f in c.outputs.fields),
    ]
    for m in model.messages:
        lines.append(f"message {m.c_name}")
        lines += [f"field {f.name} {_ftype(f)}" for f in m.fields]
    lines += [
        f"topic {t.name} {t.c_name} {t.direction} {t.msg_type} {t.queue_size}" for t in model.topics
    ]
    lines += [f"input_relation {r.topic.c_name} {_path(r.path.steps)} {r.input_field}{_path_tail(r.input_elem)}"
              for r in model.input_relations]
    lines += [f"output_relation {r.output_field}{_path_tail(r.output_elem)} {r.topic.c_name} {_path(r.path.steps)}"
              for r in model.output_relations]
    # rule 4.12: timeouts (topic order), fallbacks (input-relation order),
    # derived inputs (the model's order)
    lines += [f"timeout {c_name} {ms}" for c_name, ms in model.timeouts]
    lines += [f"fallback {f} {_val_text(s)}" for f, s in model.fallbacks]
    lines += [f"derived_input {r.topic.c_name} {r.kind} {r.input_field}" for r in model.derived_relations]
    # rule 4.13: stamped topics (topic order)
    lines += [f"stamp {c_name} {_path(path)}" for c_name, path in model.stamps]
    lines += [f"stamp_from {c_name} {src} {_path(path)}" for c_name, (src, path) in model.stamp_from]
    # rule 4.14: constant strings (topic order, then the model's order)
    lines += [f"string {c_name} {_path(path)} {bytes_text(data)}" for c_name, path, data in model.strings]
    return "".join(line + "\n" for line in lines)


def bytes_text(data) -> str:
    """The bytes of a constant string as ``ModelText.bytes_text`` prints
    them: decimals joined by ``,``, or ``-`` for none."""
    return ",".join(str(b) for b in data) if len(data) else "-"


_BYTES_TEXT = re.compile(r"-|(?:0|[1-9][0-9]{0,2})(?:,(?:0|[1-9][0-9]{0,2}))*")


def parse_bytes_text(text: str) -> bytes:
    """The bytes of :func:`bytes_text`'s ``text``; ``ValueError`` if it is
    not such a text."""
    if not _BYTES_TEXT.fullmatch(text):
        raise ValueError(text)
    if text == "-":
        return b""
    return bytes(int(b) for b in text.split(","))  # ValueError past 255


def _compare_texts(expected: str, proved: str, what: str, message: str, limit: int) -> None:
    """Raise :class:`ModelMismatch` naming each differing line unless the
    two texts are equal (``what``: what the proved text is called)."""
    if proved == expected:
        return
    exp, got = expected.splitlines(), proved.splitlines()
    diffs = []
    for i in range(max(len(exp), len(got))):
        a = exp[i] if i < len(exp) else "(nothing)"
        b = got[i] if i < len(got) else "(nothing)"
        if a != b:
            diffs.append(f"  item {i + 1}: the model file says {a!r}; {what} says {b!r}")
    shown = diffs[:limit] + ([f"  ... {len(diffs) - limit} more"] if len(diffs) > limit else [])
    raise ModelMismatch(f"{message} ({len(diffs)} differing items)", shown)


def compare_model_texts(expected: str, proved: str, *, vfile: str, limit: int = 8) -> None:
    """Raise :class:`ModelMismatch` unless ``proved`` (printed by Coq from
    the model term of ``vfile``) is ``expected`` (read from the YAML)."""
    _compare_texts(expected, proved, "the proved model",
                   f"the model proved in {vfile} is not the model of the YAML file", limit)


class MalformedModelText(DetailedFailure):
    """A model text that does not follow the grammar of ``print_model``
    (exit code 2: Coq's printer and this reader disagree, or the file was
    edited)."""


@dataclass(frozen=True)
class ProvedTopic(TopicNames):
    """A ``topic`` line of the proved model."""

    name: str        #: ROS name
    c_name: str      #: C identifier of the topic
    direction: str   #: ``subscribe`` or ``publish``
    ros_type: str    #: ``pkg/Type``
    queue: int

    @property
    def struct(self) -> str:
        """The message struct: ``pkg_Type`` (``Wellformed.topic_ok``)."""
        return self.ros_type.replace("/", "_")

    @property
    def queue_size(self) -> int:
        return self.queue

    @property
    def msg_type(self) -> str:
        return self.ros_type

    @property
    def cpp_type(self) -> str:
        """The roscpp C++ type: ``pkg::Type``."""
        return self.ros_type.replace("/", "::")


@dataclass
class ProvedModel:
    """A model text printed by Coq (``ROSGen.glue.ModelText.print_model``),
    read back: what the per-node theorem is about."""

    name: str = ""
    period_ms: int = 0
    controller: str = ""
    inputs_var: str = ""
    inputs_struct: str = ""
    #: (field, type as printed: ``float64``, ``array 1081 float32``, rule 4.15)
    inputs: list[tuple[str, str]] = field(default_factory=list)
    outputs_var: str = ""
    outputs_struct: str = ""
    outputs: list[tuple[str, str]] = field(default_factory=list)
    messages: dict[str, list[tuple[str, str]]] = field(default_factory=dict)  #: struct -> (field, ftype)
    topics: list[ProvedTopic] = field(default_factory=list)
    #: (topic C name, path, controller input)
    input_relations: list[tuple[str, str, str]] = field(default_factory=list)
    #: (controller output, topic C name, path)
    output_relations: list[tuple[str, str, str]] = field(default_factory=list)
    #: (topic C name, timeout in ms), rule 4.12
    timeouts: list[tuple[str, int]] = field(default_factory=list)
    #: (controller input, its value when stale as ``DiagramText.val_text``
    #: prints it: decimal integers, ``0x`` and the bits of a float)
    fallbacks: list[tuple[str, str]] = field(default_factory=list)
    #: (topic C name, ``is_new``/``received``/``age_ms``, controller input)
    derived_inputs: list[tuple[str, str, str]] = field(default_factory=list)
    #: (topic C name, path of the stamp), rule 4.13
    stamps: list[tuple[str, str]] = field(default_factory=list)
    #: (topic C name, source topic C name, path of the source's stamp)
    stamp_from: list[tuple[str, str, str]] = field(default_factory=list)
    #: (topic C name, path of the string field, the constant's bytes), rule 4.14
    strings: list[tuple[str, str, bytes]] = field(default_factory=list)

    def topic(self, c_name: str) -> ProvedTopic:
        for t in self.topics:
            if t.c_name == c_name:
                return t
        raise MalformedModelText(f"the proved model has no topic {c_name!r}")

    @property
    def timed(self) -> frozenset[str]:
        """The C names of the timed topics (rule 4.12): those with a
        timeout or a derived input."""
        return frozenset({c for c, _ in self.timeouts} | {c for c, _, _ in self.derived_inputs})

    def is_direct(self, topic_c: str, path: str) -> bool:
        """Whether the input relation on ``path`` of topic ``topic_c`` is
        direct (rule 4.16, :func:`pyrosgen.frontend.model.is_direct`): its
        callback writes it into the controller's inputs, ``input_glue``
        does not."""
        return is_direct(path, topic_c in self.timed)

    def input_type(self, target: str) -> str:
        """The type of controller input ``target`` as a relation names it
        (``In1``, ``Scan[540]``, rule 4.15): ``float64``, ``float32`` (an
        element's), ``float32[1081]`` (a whole array's); ``?`` if none."""
        return _target_type(self.inputs, target)

    def output_type(self, target: str) -> str:
        """As :meth:`input_type`, for a controller output."""
        return _target_type(self.outputs, target)


def _target_type(fields: list[tuple[str, str]], target: str) -> str:
    m = re.fullmatch(r"(\w+)(\[[0-9]+\])?", target)
    t = dict(fields).get(m.group(1)) if m else None
    if t is None:
        return "?"
    parts = t.split(" ")
    if len(parts) == 3 and parts[0] == "array":
        return parts[2] if m.group(2) else f"{parts[2]}[{parts[1]}]"
    return "?" if m.group(2) else t


#: A value as ``DiagramText.val_text`` prints it (a fallback's, rule 4.12).
_VAL_TEXT = re.compile(r"-?[0-9]+|0x[0-9a-fA-F]{8}|0x[0-9a-fA-F]{16}")


def parse_model_text(text: str, *, origin: str = "the proved model text") -> ProvedModel:
    """Read a model text printed by Coq; raise :class:`MalformedModelText`
    on anything outside the grammar of ``print_model``."""
    lines = text.splitlines()
    if not lines or lines[0] != HEADER:
        raise MalformedModelText(f"{origin} does not start with {HEADER!r}")
    pm = ProvedModel()
    arity = {"node": 2, "period_ms": 2, "controller": 2, "inputs": 3, "input": 3, "outputs": 3,
             "output": 3, "message": 2, "topic": 6, "input_relation": 4, "output_relation": 4,
             "timeout": 3, "fallback": 3, "derived_input": 4, "stamp": 3, "stamp_from": 4, "string": 4}
    message: list[tuple[str, str]] | None = None
    seen: set[str] = set()
    for n, line in enumerate(lines[1:], start=2):
        parts = line.split(" ")
        kw = parts[0]
        if kw == "field" and len(parts) >= 3 and message is not None:
            message.append((parts[1], " ".join(parts[2:])))
            continue
        if kw in ("input", "output") and len(parts) == 5 and parts[2] == "array":
            # an array field (rule 4.15): input Scan array 1081 float32
            if not re.fullmatch(r"[1-9][0-9]{0,4}", parts[3]) or not 1 <= int(parts[3]) <= 65536 or not parts[4]:
                raise MalformedModelText(f"{origin}, line {n}: not an item of the grammar: {line!r}")
            parts = [kw, parts[1], " ".join(parts[2:])]
        if arity.get(kw) != len(parts) or any(not p for p in parts):
            raise MalformedModelText(f"{origin}, line {n}: not an item of the grammar: {line!r}")
        seen.add(kw)
        try:
            if kw == "node":
                pm.name = parts[1]
            elif kw == "period_ms":
                pm.period_ms = int(parts[1])
            elif kw == "controller":
                pm.controller = parts[1]
            elif kw == "inputs":
                pm.inputs_var, pm.inputs_struct = parts[1], parts[2]
            elif kw == "input":
                pm.inputs.append((parts[1], parts[2]))
            elif kw == "outputs":
                pm.outputs_var, pm.outputs_struct = parts[1], parts[2]
            elif kw == "output":
                pm.outputs.append((parts[1], parts[2]))
            elif kw == "message":
                message = pm.messages.setdefault(parts[1], [])
            elif kw == "topic":
                if parts[3] not in ("subscribe", "publish"):
                    raise ValueError(parts[3])
                pm.topics.append(ProvedTopic(parts[1], parts[2], parts[3], parts[4], int(parts[5])))
            elif kw == "input_relation":
                pm.input_relations.append((parts[1], parts[2], parts[3]))
            elif kw == "output_relation":
                pm.output_relations.append((parts[1], parts[2], parts[3]))
            elif kw == "timeout":
                pm.timeouts.append((parts[1], int(parts[2])))
            elif kw == "fallback":
                if not _VAL_TEXT.fullmatch(parts[2]):
                    raise ValueError(parts[2])
                pm.fallbacks.append((parts[1], parts[2]))
            elif kw == "stamp":
                pm.stamps.append((parts[1], parts[2]))
            elif kw == "stamp_from":
                pm.stamp_from.append((parts[1], parts[2], parts[3]))
            elif kw == "string":
                pm.strings.append((parts[1], parts[2], parse_bytes_text(parts[3])))
            else:
                if parts[2] not in DERIVED_KINDS:
                    raise ValueError(parts[2])
                pm.derived_inputs.append((parts[1], parts[2], parts[3]))
        except ValueError:
            raise MalformedModelText(f"{origin}, line {n}: not an item of the grammar: {line!r}") from None
    missing = [k for k in ("node", "period_ms", "controller", "inputs", "outputs") if k not in seen]
    if missing:
        raise MalformedModelText(f"{origin} has no {', '.join(missing)} line")
    return pm


# --------------------------------------------------------------------------
# The controller's block diagram (coq/theories/ctrl/DiagramText.v)

DIAGRAM_HEADER = "pyrosgen-diagram 1"

_RELOP_TEXT = {"==": "==", "!=": "!=", "<": "<", ">": ">", "<=": "<=", ">=": ">="}
_CRIT_TEXT = {"u2 >= threshold": ">=", "u2 > threshold": ">", "u2 ~= 0": "~=0"}


def _val_text(s) -> str:
    """A constant as ``DiagramText.val_text`` prints it."""
    if s.prim == "float64":
        return f"0x{s.n:016x}"
    if s.prim == "float32":
        return f"0x{s.n:08x}"
    return str(s.n)


def _block_text(b) -> str:
    k, ins = b.kind, list(b.inputs)
    if k == "Constant":
        return f"const {_val_text(b.value)}"
    if k == "Gain":
        return f"gain {_val_text(b.gain)} {ins[0]}"
    if k == "Sum":
        return "sum " + " ".join(f"{sg}{a}" for sg, a in zip(b.signs, ins))
    if k in ("Product", "Divide"):
        return f"{k.lower()} {ins[0]} {ins[1]}"
    if k == "Abs":
        return f"abs {ins[0]}"
    if k == "MinMax":
        return " ".join([b.op, *ins])
    if k == "Saturation":
        return f"saturation {_val_text(b.lower)} {_val_text(b.upper)} {ins[0]}"
    if k == "RelationalOperator":
        return f"relational {_RELOP_TEXT[b.op]} {b.input_prim} {ins[0]} {ins[1]}"
    if k == "Logic":
        return " ".join(["logic", b.op, *ins])
    if k == "Switch":
        thr = "0" if b.op == "u2 ~= 0" else _val_text(b.threshold)
        return f"switch {_CRIT_TEXT[b.op]} {b.input_prim} {thr} {ins[0]} {ins[1]} {ins[2]}"
    raise ValueError(f"block {b.name!r} of kind {k!r}")


def diagram_text(model: NodeModel) -> str:
    """The canonical text of the model's block diagram (the grammar of
    Coq's ``DiagramText.print_diagram``), from the front end's reading:
    the equations in the order the emitter gives them (the inputs read,
    then the states' outputs, then the other blocks in evaluation order)."""
    c = model.controller
    d = c.diagram
    lines = [
        DIAGRAM_HEADER,
        f"controller {c.name}",
        f"inputs {c.inputs.var_name} {c.inputs.struct_name}",
        *(f"input {f.name} {f.prim}" for f in c.inputs.fields),
        f"outputs {c.outputs.var_name} {c.outputs.struct_name}",
        *(f"output {f.name} {f.prim}" for f in c.outputs.fields),
        f"states {c.name}_DW DW_{c.name}_T",
    ]
    for st in d.states:
        line = f"state {st.name} {st.prim} {_val_text(st.initial)} {st.inputs[0]}"
        if st.kind == "UnitDelay":
            line += " delay"
        else:
            line += f" integrator {_val_text(st.kt)}"
            if st.lower is not None:
                line += f" {_val_text(st.lower)} {_val_text(st.upper)}"
        lines.append(line)
    lines += [f"eq {f.name} {f.prim} inport {f.name}" for f in d.inports]
    lines += [f"eq {st.name} {st.prim} state {st.name}" for st in d.states]
    lines += [f"eq {b.name} {b.prim} {_block_text(b)}" for b in (d.block(n) for n in d.order)]
    lines += [f"out {f.name} {s}" for f, s in d.outports]
    return "".join(line + "\n" for line in lines)


def compare_diagram_texts(expected: str, proved: str, *, vfile: str, limit: int = 8) -> None:
    """Raise :class:`ModelMismatch` unless ``proved`` (printed by Coq from
    ``Ctrl.the_diagram`` of ``vfile``) is ``expected`` (read from the YAML)."""
    _compare_texts(expected, proved, "the proved diagram",
                   f"the controller diagram proved in {vfile} is not the diagram of the YAML file", limit)

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

from pyrosgen.errors import DetailedFailure
from pyrosgen.frontend.model import NodeModel
from pyrosgen.frontend.msgmodel import MsgField, msg_c_name

__all__ = ["HEADER", "model_text", "ModelMismatch", "compare_model_texts"]

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
        *(f"input {f.name} {f.prim}" for f in c.inputs.fields),
        f"outputs {c.outputs.var_name} {c.outputs.struct_name}",
        *(f"output {f.name} {f.prim}" for f in c.outputs.fields),
    ]
    for m in model.messages:
        lines.append(f"message {m.c_name}")
        lines += [f"field {f.name} {_ftype(f)}" for f in m.fields]
    lines += [
        f"topic {t.name} {t.c_name} {t.direction} {t.msg_type} {t.queue_size}" for t in model.topics
    ]
    lines += [f"input_relation {r.topic.c_name} {_path(r.path.steps)} {r.input_field}"
              for r in model.input_relations]
    lines += [f"output_relation {r.output_field} {r.topic.c_name} {_path(r.path.steps)}"
              for r in model.output_relations]
    return "".join(line + "\n" for line in lines)


def compare_model_texts(expected: str, proved: str, *, vfile: str, limit: int = 8) -> None:
    """Raise :class:`ModelMismatch` unless ``proved`` (printed by Coq from
    the model term of ``vfile``) is ``expected`` (read from the YAML)."""
    if proved == expected:
        return
    exp, got = expected.splitlines(), proved.splitlines()
    diffs = []
    for i in range(max(len(exp), len(got))):
        a = exp[i] if i < len(exp) else "(nothing)"
        b = got[i] if i < len(got) else "(nothing)"
        if a != b:
            diffs.append(f"  item {i + 1}: the model file says {a!r}; the proved model says {b!r}")
    shown = diffs[:limit] + ([f"  ... {len(diffs) - limit} more"] if len(diffs) > limit else [])
    raise ModelMismatch(
        f"the model proved in {vfile} is not the model of the YAML file ({len(diffs)} differing items)",
        shown,
    )

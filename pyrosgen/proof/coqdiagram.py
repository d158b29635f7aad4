"""The Coq emitter of block diagrams: a node model's
:class:`~pyrosgen.frontend.model.Diagram` (rule 4.11) as a term of
``ROSGen.ctrl.Diagram`` (``coq/theories/ctrl/Diagram.v``).

:func:`emit_diagram` returns the text of one definition,

    Definition the_diagram : diagram := mkdiagram ... .

to be placed in a Coq file after these lines, which it assumes (and no
more)::

    From Coq Require Import String List ZArith.
    From ROSGen Require Import Syntax Values FloatBits NodeModel Diagram.
    Import ListNotations.
    Local Open Scope string_scope.

``String`` gives the string literals (every identifier is a plain
``"..."`` literal, read in ``string_scope``), ``List`` with
``ListNotations`` the ``[a; b]`` lists, ``ZArith`` the ``%Z`` delimiter:
every integer is written with an explicit ``%Z`` (``Vint 5%Z``,
``Vint (-5)%Z``, ``float64_of_bits 0x3FF0000000000000%Z``), so that the
text means the same whichever of ``Z_scope``/``nat_scope`` is open.

As :mod:`pyrosgen.proof.coqmodel` does for the node model, every
identifier is checked again against the C identifier regex before it is
printed, and comments are reduced to safe characters; what the diagram
must satisfy is checked by Coq (``Diagram.dg_wf``), not here.  The
literal helpers are :mod:`pyrosgen.proof.coqmodel`'s (the constants'
:func:`~pyrosgen.proof.coqmodel.coq_val` too, re-exported here); the pipeline
(:mod:`pyrosgen.generate`) hands the emitted text to
:func:`~pyrosgen.proof.coqmodel.render_node_file`.
"""

from __future__ import annotations

from pyrosgen.frontend.model import Block, NodeModel
from pyrosgen.proof.coqmodel import EmitError, coq_comment, coq_ident, coq_prim, coq_val

__all__ = ["DIAGRAM_DEF", "ASSUMED_PRELUDE", "EmitError", "emit_diagram", "coq_val"]


#: The name of the emitted definition.
DIAGRAM_DEF = "the_diagram"

#: The lines the emitted text assumes before it (see the module's docstring).
ASSUMED_PRELUDE = (
    "From Coq Require Import String List ZArith.\n"
    "From ROSGen Require Import Syntax Values FloatBits NodeModel Diagram.\n"
    "Import ListNotations.\n"
    "Local Open Scope string_scope.\n"
)

_RELOPS = {"==": "Req", "!=": "Rne", "<": "Rlt", ">": "Rgt", "<=": "Rle", ">=": "Rge"}
_LOGOPS = {"AND": "Land", "OR": "Lor", "NAND": "Lnand", "NOR": "Lnor", "XOR": "Lxor", "NOT": "Lnot"}
_CRITERIA = {"u2 >= threshold": "Cge", "u2 > threshold": "Cgt", "u2 ~= 0": "Cne0"}
def _sig(name: str) -> str:
    return coq_ident(name, "signal name")


def _sigs(names) -> str:
    return "[" + "; ".join(_sig(n) for n in names) + "]"


def _p(text: str) -> str:
    """``text`` in parentheses when it is an application."""
    return f"({text})" if " " in text else text


def _block_term(b: Block) -> str:
    """The ``Diagram.block`` of a block without memory."""
    k = b.kind
    ins = b.inputs
    if k == "Constant":
        return f"Bconst ({coq_val(b.value)})"
    if k == "Gain":
        return f"Bgain ({coq_val(b.gain)}) {_sig(ins[0])}"
    if k == "Sum":
        if b.signs is None or len(b.signs) != len(ins) or set(b.signs) - {"+", "-"}:
            raise EmitError(f"refusing to print Sum {b.name!r}: bad signs {b.signs!r}")
        terms = "; ".join(f"({'true' if sg == '+' else 'false'}, {_sig(a)})" for sg, a in zip(b.signs, ins))
        return f"Bsum [{terms}]"
    if k == "Product":
        return f"Bproduct {_sig(ins[0])} {_sig(ins[1])}"
    if k == "Divide":
        return f"Bdivide {_sig(ins[0])} {_sig(ins[1])}"
    if k == "Abs":
        return f"Babs {_sig(ins[0])}"
    if k == "MinMax":
        if b.op not in ("min", "max"):
            raise EmitError(f"refusing to print MinMax {b.name!r}: function {b.op!r}")
        return f"Bminmax {'true' if b.op == 'max' else 'false'} {_sigs(ins)}"
    if k == "Saturation":
        return f"Bsaturation ({coq_val(b.lower)}) ({coq_val(b.upper)}) {_sig(ins[0])}"
    if k == "RelationalOperator":
        if b.op not in _RELOPS:
            raise EmitError(f"refusing to print RelationalOperator {b.name!r}: operator {b.op!r}")
        return f"Brelational {_RELOPS[b.op]} {coq_prim(b.input_prim)} {_sig(ins[0])} {_sig(ins[1])}"
    if k == "Logic":
        if b.op not in _LOGOPS:
            raise EmitError(f"refusing to print Logic {b.name!r}: operator {b.op!r}")
        return f"Blogical {_LOGOPS[b.op]} {_sigs(ins)}"
    if k == "Switch":
        if b.op not in _CRITERIA:
            raise EmitError(f"refusing to print Switch {b.name!r}: criterion {b.op!r}")
        thr = "Vint 0%Z" if b.op == "u2 ~= 0" else coq_val(b.threshold)
        a, c, bb = ins
        return f"Bswitch {_CRITERIA[b.op]} {coq_prim(b.input_prim)} ({thr}) {_sig(a)} {_sig(c)} {_sig(bb)}"
    raise EmitError(f"refusing to print block {b.name!r} of kind {k!r}")


def _state_term(b: Block) -> str:
    """The ``Diagram.state_decl`` of a UnitDelay or DiscreteIntegrator."""
    if b.kind == "UnitDelay":
        kind = "Kdelay"
    elif b.kind == "DiscreteIntegrator":
        lim = "None" if b.lower is None else f"(Some ({coq_val(b.lower)}, {coq_val(b.upper)}))"
        kind = f"(Kintegrator ({coq_val(b.kt)}) {lim})"
    else:
        raise EmitError(f"refusing to print block {b.name!r} of kind {b.kind!r} as a state")
    return (f"mkstate {_sig(b.name)} {coq_prim(b.prim)} ({coq_val(b.initial)}) "
            f"{_sig(b.inputs[0])} {kind}")


def _describe(b: Block) -> str:
    """A one-line comment for a block: its kind and parameters as written."""
    parts = [b.kind]
    if b.op:
        parts.append(b.op)
    if b.signs:
        parts.append(f"signs {b.signs}")
    for key in ("value", "gain", "lower", "upper", "threshold", "initial"):
        v = getattr(b, key)
        if v is not None and v.text:
            parts.append(f"{key} {v.text}")
    return coq_comment(", ".join(parts))


def emit_diagram(model: NodeModel) -> str:
    """The Coq definition ``the_diagram : diagram`` of the model's block
    diagram (``model.controller.diagram``, which must not be ``None``).

    ``dg_eqs`` lists, in evaluation order: one ``Binport`` equation per
    controller input the diagram reads (field order), one ``Bstate``
    equation per UnitDelay or DiscreteIntegrator (the model's order), then
    the other blocks, each after the blocks it reads (the model's order
    where it allows).  A DiscreteIntegrator's ``kt`` is its gain times the
    sample time ``node.period_ms / 1000``, rounded once to the type from
    the exact product (the front end's :class:`~pyrosgen.frontend.model.Scalar`).
    """
    c = model.controller
    d = c.diagram
    if d is None:
        raise EmitError("refusing to emit a diagram: the controller has no blocks")
    nl = "\n"
    ind = "    "

    def fields(fs) -> str:
        return "[" + "; ".join(f"({coq_ident(f.name, 'controller field')}, {coq_prim(f.prim)})" for f in fs) + "]"

    eqs = []
    for f in d.inports:
        eqs.append(f"mkeq {_sig(f.name)} {coq_prim(f.prim)} (Binport {coq_ident(f.name, 'controller input')})")
    for b in d.states:
        eqs.append(f"mkeq {_sig(b.name)} {coq_prim(b.prim)} (Bstate {_sig(b.name)})"
                   f"  (* {_describe(b)} *)")
    blocks = {b.name: b for b in d.blocks}
    for name in d.order:
        b = blocks[name]
        eqs.append(f"mkeq {_sig(b.name)} {coq_prim(b.prim)} ({_block_term(b)})"
                   f"  (* {_describe(b)} *)")
    states = [_state_term(b) for b in d.states]
    outs = [f"({coq_ident(f.name, 'controller output')}, {_sig(s)})" for f, s in d.outports]

    def lst(items: list[str]) -> str:
        if not items:
            return "[]"
        body = (";" + nl + ind + "   ").join(items)
        return f"[{body}]"

    # An item's trailing comment must not swallow the ';' that follows it.
    def lst_commented(items: list[str]) -> str:
        if not items:
            return "[]"
        lines = []
        for i, it in enumerate(items):
            sep = "" if i == len(items) - 1 else ";"
            if "  (* " in it:
                code, comment = it.split("  (* ", 1)
                lines.append(f"{code}{sep}  (* {comment}")
            else:
                lines.append(f"{it}{sep}")
        return "[" + (nl + ind + " ").join(lines) + "]"

    return (
        f"Definition {DIAGRAM_DEF} : diagram := mkdiagram" + nl
        + f"{ind}{coq_ident(c.name, 'controller name')}" + nl
        + f"{ind}{coq_ident(c.inputs.var_name, 'controller input variable')} "
          f"{coq_ident(c.inputs.struct_name, 'controller input struct')}" + nl
        + f"{ind}{fields(c.inputs.fields)}" + nl
        + f"{ind}{coq_ident(c.outputs.var_name, 'controller output variable')} "
          f"{coq_ident(c.outputs.struct_name, 'controller output struct')}" + nl
        + f"{ind}{fields(c.outputs.fields)}" + nl
        + f"{ind}{coq_ident(c.state_var, 'state variable')} {coq_ident(c.state_struct, 'state struct')}" + nl
        + f"{ind}(* states *)" + nl
        + f"{ind}{lst(states)}" + nl
        + f"{ind}(* equations, in evaluation order *)" + nl
        + f"{ind}{lst_commented(eqs)}" + nl
        + f"{ind}(* outputs: field, signal *)" + nl
        + f"{ind}{lst(outs)}." + nl
    )

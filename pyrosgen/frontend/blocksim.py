"""A reference interpreter of block diagrams: ``Diagram.dg_step`` in Python.

:func:`step` computes one step of a :class:`~pyrosgen.frontend.model.Diagram`
exactly as ``coq/theories/ctrl/Diagram.v`` defines it (``eval_block``,
``eval_eqs``, ``next_state``, ``saturate``, ``compare``, ``logic``), so
that the C that Coq generates from a diagram can be tested against it bit
for bit (differential tests) and that the meaning of a model can be tried
without Coq.

Values (inputs, outputs, states, signals) are Python ``int``:

- ``bool``: 0 or 1 (any non-zero input counts as true, as C's does);
- ``int32``/``int64``: the signed value, ``uint32``/``uint64``: the
  unsigned one; arithmetic wraps around (two's complement);
- ``float32``/``float64``: the IEEE 754 **bit pattern** (so that ``-0.0``
  and NaN payloads are exact); :func:`value_of` and :func:`python_of`
  convert from and to Python numbers.

Floats follow ``FloatOps`` (:mod:`pyrosgen.frontend.ieee`): round to
nearest even, comparisons unordered on NaN, a NaN result is the first NaN
operand made quiet or the default NaN; Abs clears the sign bit, negation
flips it.
"""

from __future__ import annotations

from fractions import Fraction

from pyrosgen.frontend import ieee
from pyrosgen.frontend.model import Block, Diagram

__all__ = ["initial_state", "step", "signals", "value_of", "python_of", "run"]

_BITS = {"int32": 32, "uint32": 32, "int64": 64, "uint64": 64}
_SIGNED = ("int32", "int64")
_FLOATS = ("float32", "float64")


# --------------------------------------------------------------------------
# Values


def _wrap(q: str, n: int) -> int:
    """``wrap_signed`` / ``wrap_unsigned`` of the type's width."""
    bits = _BITS[q]
    m = n % (1 << bits)
    if q in _SIGNED and m >= 1 << (bits - 1):
        m -= 1 << bits
    return m


def value_of(q: str, x) -> int:
    """The value of type ``q`` of a Python number: a float is rounded to
    the type (``float32``: once, to nearest even, from its exact value),
    a bool or an int must be in the type's range."""
    if q in _FLOATS:
        f = ieee.fmt(q)
        if isinstance(x, float):
            if x != x:
                b = ieee.bits_of_double(x)
                if q == "float64":
                    return b
                # a NaN as binary32: its sign, quiet, the top bits of its payload
                return ((b >> 32) & f.sign_bit) | f.exp_mask | f.quiet_bit | ((b >> 29) & f.frac_mask)
            if x in (float("inf"), float("-inf")):
                return (f.sign_bit if x < 0 else 0) | f.inf
            neg = x < 0 or (x == 0 and ieee.bits_of_double(x) >> 63 == 1)
            return ieee.round_fraction(abs(Fraction(x)), neg, f)
        if isinstance(x, int):
            return ieee.round_fraction(abs(Fraction(x)), x < 0, f)
        raise TypeError(f"value_of: {x!r} is not a number")
    if q == "bool":
        return 1 if x else 0
    n = int(x)
    if _wrap(q, n) != n:
        raise ValueError(f"value_of: {x!r} is out of the range of {q}")
    return n


def python_of(q: str, v: int):
    """A value as a Python number: ``float`` for the floats (exact),
    ``bool`` for ``bool``, ``int`` otherwise."""
    if q in _FLOATS:
        return ieee.as_double(ieee.fmt(q), v) if not ieee.is_nan(ieee.fmt(q), v) else float("nan")
    if q == "bool":
        return v != 0
    return v


# --------------------------------------------------------------------------
# Operations of Diagram.v


def _arith(op: str, q: str, a: int, b: int) -> int:
    """``Diagram.arith``: wrap-around integers, IEEE floats."""
    if q in _FLOATS:
        return ieee.fop(ieee.fmt(q), op, a, b)
    if op == "+":
        return _wrap(q, a + b)
    if op == "-":
        return _wrap(q, a - b)
    if op == "*":
        return _wrap(q, a * b)
    raise ValueError(f"integer division is not a diagram operation ({q})")


def _negate(q: str, a: int) -> int:
    if q in _FLOATS:
        return ieee.fneg(ieee.fmt(q), a)
    return _wrap(q, -a)


def _compare(op: str, q: str, a: int, b: int) -> bool:
    """``Diagram.compare``: C's comparison in the type (IEEE for floats)."""
    if q in _FLOATS:
        return ieee.fcmp(ieee.fmt(q), op, a, b)
    return {
        "==": a == b, "!=": a != b, "<": a < b, "<=": a <= b, ">": a > b, ">=": a >= b,
    }[op]


def _truth(q: str, v: int) -> bool:
    """``Diagram.truth``: non-zero (a float zero of either sign is false, a NaN true)."""
    if q in _FLOATS:
        return not ieee.is_zero(ieee.fmt(q), v)
    return v != 0


def _logic(op: str, bs: list[bool]) -> bool:
    if op == "AND":
        return all(bs)
    if op == "OR":
        return any(bs)
    if op == "NAND":
        return not all(bs)
    if op == "NOR":
        return not any(bs)
    if op == "XOR":
        return sum(bs) % 2 == 1
    if op == "NOT":
        return not all(bs)
    raise ValueError(f"unknown logical operator {op!r}")


def _saturate(q: str, lo: int, hi: int, a: int) -> int:
    """``hi`` if ``a > hi``, else ``lo`` if ``a < lo``, else ``a`` (a NaN passes)."""
    if _compare(">", q, a, hi):
        return hi
    if _compare("<", q, a, lo):
        return lo
    return a


# --------------------------------------------------------------------------
# A step


def _eval_block(b: Block, env: dict[str, int]) -> int:
    """``Diagram.eval_block`` of a block without memory."""
    q = b.prim
    k = b.kind
    ins = [env[s] for s in b.inputs]
    if k == "Constant":
        return b.value.n
    if k == "Gain":
        return _arith("*", q, ins[0], b.gain.n)
    if k == "Sum":
        acc = ins[0] if b.signs[0] == "+" else _negate(q, ins[0])
        for sign, v in zip(b.signs[1:], ins[1:]):
            acc = _arith("+" if sign == "+" else "-", q, acc, v)
        return acc
    if k == "Product":
        return _arith("*", q, ins[0], ins[1])
    if k == "Divide":
        return _arith("/", q, ins[0], ins[1])
    if k == "Abs":
        return ieee.fabs(ieee.fmt(q), ins[0])
    if k == "MinMax":
        cmp = ">" if b.op == "max" else "<"
        x = ins[0]
        for v in ins[1:]:
            if _compare(cmp, q, v, x):
                x = v
        return x
    if k == "Saturation":
        return _saturate(q, b.lower.n, b.upper.n, ins[0])
    if k == "RelationalOperator":
        return 1 if _compare(b.op, b.input_prim, ins[0], ins[1]) else 0
    if k == "Logic":
        return 1 if _logic(b.op, [_truth("bool", v) for v in ins]) else 0
    if k == "Switch":
        a, c, bb = ins
        if b.op == "u2 >= threshold":
            passes = _compare(">=", b.input_prim, c, b.threshold.n)
        elif b.op == "u2 > threshold":
            passes = _compare(">", b.input_prim, c, b.threshold.n)
        else:
            passes = _truth(b.input_prim, c)
        return a if passes else bb
    raise ValueError(f"unknown block kind {k!r}")


def _check(diagram: Diagram, state: dict, inputs: dict) -> None:
    for st in diagram.states:
        if st.name not in state:
            raise KeyError(f"state {st.name!r} missing")
    for f in diagram.inports:
        if f.name not in inputs:
            raise KeyError(f"input {f.name!r} missing")


def signals(diagram: Diagram, state: dict[str, int], inputs: dict[str, int]) -> dict[str, int]:
    """Every signal of a step from ``state`` with ``inputs``
    (``Diagram.step_signals``), in evaluation order."""
    _check(diagram, state, inputs)
    env: dict[str, int] = {}
    for f in diagram.inports:
        env[f.name] = inputs[f.name]
    for st in diagram.states:
        env[st.name] = state[st.name]
    blocks = {b.name: b for b in diagram.blocks}
    for name in diagram.order:
        env[name] = _eval_block(blocks[name], env)
    return env


def _next_state(st: Block, old: int, env: dict[str, int]) -> int:
    """``Diagram.next_state``."""
    if st.kind == "UnitDelay":
        return env[st.inputs[0]]
    q = st.prim
    x = _arith("+", q, old, _arith("*", q, st.kt.n, env[st.inputs[0]]))
    if st.lower is not None:
        x = _saturate(q, st.lower.n, st.upper.n, x)
    return x


def initial_state(diagram: Diagram) -> dict[str, int]:
    """``Diagram.dg_init``: each state's initial value."""
    return {st.name: st.initial.n for st in diagram.states}


def step(diagram: Diagram, state: dict[str, int], inputs: dict[str, int]) -> tuple[dict[str, int], dict[str, int]]:
    """``Diagram.dg_step``: from ``state`` (state name -> value) and
    ``inputs`` (controller input field -> value; the fields the diagram
    does not read may be absent), the next state and the outputs
    (controller output field -> value)."""
    env = signals(diagram, state, inputs)
    new = {st.name: _next_state(st, state[st.name], env) for st in diagram.states}
    outs = {f.name: env[s] for f, s in diagram.outports}
    return new, outs


def run(diagram: Diagram, inputs_seq) -> list[dict[str, int]]:
    """The outputs of consecutive steps from the initial state, one per
    element of ``inputs_seq``."""
    state = initial_state(diagram)
    out = []
    for u in inputs_seq:
        state, y = step(diagram, state, u)
        out.append(y)
    return out

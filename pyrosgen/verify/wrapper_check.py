"""The running node is the proved one: the C++ wrapper over roscpp
registers exactly the topics, message structs and queue sizes, and sleeps
with exactly the period, of the model that Coq proved things about.

The wrapper (``<node>_ros.cpp``) is rendered by Python from the front
end's model; the proof is about the model term of the per-node ``.v``,
whose canonical text Coq prints (``ROSGen.glue.ModelText``).  This check
reads that text and the rendered wrapper, and refuses (exit 2) a wrapper
that subscribes or advertises anything else, with another queue size or
another message struct, or sleeps with another period (DESIGN.md
section 7).
"""

from __future__ import annotations

import re
from fractions import Fraction

from pyrosgen.errors import DetailedFailure
from pyrosgen.proof.modeltext import MalformedModelText, ProvedTopic, parse_model_text

__all__ = ["ProvedTopic", "proved_interface", "check_wrapper", "WrapperMismatch"]


class WrapperMismatch(DetailedFailure):
    """The rendered wrapper does not implement the proved model's interface."""


def proved_interface(text: str) -> tuple[list[ProvedTopic], int]:
    """The topics and the period (ms) of a model text printed by Coq."""
    try:
        pm = parse_model_text(text)
    except MalformedModelText as exc:
        raise WrapperMismatch(str(exc)) from None
    return pm.topics, pm.period_ms


_SUB = re.compile(
    r"void ros_subscribe_(\w+)\(void \(\*cb\)\(struct (\w+) \*\)\)\s*\{.*?"
    r'->subscribe<[\w:]+>\("([^"]*)", (\d+), f\);', re.S)
_ADV = re.compile(
    r'void ros_advertise_(\w+)\(void\)\s*\{.*?ops\.init<[\w:]+>\("([^"]*)", (\d+)\);', re.S)
_PUB = re.compile(r"void ros_publish_(\w+)\(struct (\w+) \*msg\)")
_RATE = re.compile(r"ros::Rate\(ros::Duration\(([0-9.eE+-]+)\)\)")
_ANY_REG = re.compile(r"->subscribe<|ops\.init<|->advertise<")


def check_wrapper(cpp: str, proved_text: str, *, wrapper_name: str) -> None:
    """Raise :class:`WrapperMismatch` unless the wrapper source ``cpp``
    registers exactly the proved topics and sleeps with the proved period."""
    topics, period = proved_interface(proved_text)
    problems: list[str] = []
    want_sub = {(t.c_name, t.struct, t.name, t.queue) for t in topics if t.direction == "subscribe"}
    want_adv = {(t.c_name, t.name, t.queue) for t in topics if t.direction == "publish"}
    want_pub = {(t.c_name, t.struct) for t in topics if t.direction == "publish"}
    got_sub = {(m[0], m[1], m[2], int(m[3])) for m in _SUB.findall(cpp)}
    got_adv = {(m[0], m[1], int(m[2])) for m in _ADV.findall(cpp)}
    got_pub = set(_PUB.findall(cpp))
    for what, want, got in (("subscription", want_sub, got_sub), ("advertisement", want_adv, got_adv),
                            ("publisher", want_pub, got_pub)):
        for item in sorted(want - got):
            problems.append(f"  proved {what} {item} is not in the wrapper")
        for item in sorted(got - want):
            problems.append(f"  the wrapper's {what} {item} is not in the proved model")
    if len(_ANY_REG.findall(cpp)) != len(got_sub) + len(got_adv):
        problems.append("  the wrapper registers topics outside the ros_subscribe_/ros_advertise_ functions")
    rates = _RATE.findall(cpp)
    if len(rates) != 1:
        problems.append(f"  the wrapper creates {len(rates)} ros::Rate objects; expected one")
    elif Fraction(rates[0]) * 1000 != period:
        problems.append(f"  the wrapper sleeps {rates[0]} s per cycle; the proved period is {period} ms")
    if problems:
        raise WrapperMismatch(f"{wrapper_name} does not implement the proved model's interface", problems)

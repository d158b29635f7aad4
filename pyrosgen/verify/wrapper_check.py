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

It also checks the wrapper's ROS time, which the proof's environment model
assumes (``ros_now``, TIME_DESIGN): the wrapper keeps one variable
``g_now_ns`` that ``ros_now()`` returns; ``ros_init`` sets it to
``ros::Time::now()`` once the node handle exists, every subscription is
registered with a ``ros::MessageEvent`` whose callback sets it to the
event's receipt time before it converts the message and calls the glue's
callback, ``ros_spinOnce`` sets it to ``ros::Time::now()`` right after
``ros::spinOnce()`` returned, and nothing else assigns it;
``ros_time_sec()`` and ``ros_time_nsec()`` return its seconds (as an
``unsigned int``) and nanoseconds, the stamp of a published header.

With the glue and the wrapper's header (:func:`check_glue_externals`), the
ROS functions the glue declares are declared by the header with the same C
types (the two meet only at link time, where C checks nothing).
"""

from __future__ import annotations

import re
from fractions import Fraction

from pyrosgen.errors import DetailedFailure
from pyrosgen.proof.modeltext import MalformedModelText, ProvedTopic, parse_model_text

__all__ = ["ProvedTopic", "proved_interface", "check_wrapper", "check_glue_externals", "WrapperMismatch"]


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

# ROS time (ros_now): the one variable, its definition, and where it is set.
_NOW_VAR = re.compile(r"^unsigned long long g_now_ns = 0;$", re.M)
_NOW_DEF = re.compile(r"^unsigned long long ros_now\(void\)\n\{\n    return g_now_ns;\n\}$", re.M)
_SEC_DEF = re.compile(r"^unsigned int ros_time_sec\(void\)\n\{\n"
                      r"    return \(unsigned int\)\(g_now_ns / 1000000000ULL\);\n\}$", re.M)
_NSEC_DEF = re.compile(r"^unsigned int ros_time_nsec\(void\)\n\{\n"
                       r"    return \(unsigned int\)\(g_now_ns % 1000000000ULL\);\n\}$", re.M)
_NOW_SET = re.compile(r"\bg_now_ns\s*(?:=(?!=)|\+=|-=|\*=|/=|%=|&=|\|=|\^=|<<=|>>=|\+\+|--)|(?:\+\+|--)\s*g_now_ns\b|&\s*g_now_ns\b")
_NOW_INIT = re.compile(
    r"^void ros_init\(void\)\n\{\n(?:    [^\n]*\n)*?"
    r"    g_nh = new ros::NodeHandle\(\);\n    g_now_ns = ros::Time::now\(\)\.toNSec\(\);\n", re.M)
_NOW_SPIN = re.compile(
    r"^void ros_spinOnce\(void\)\n\{\n    ros::spinOnce\(\);\n"
    r"    g_now_ns = ros::Time::now\(\)\.toNSec\(\);\n\}$", re.M)
_NOW_SUB = re.compile(
    r"^void ros_subscribe_(\w+)\(void \(\*cb\)\(struct (\w+) \*\)\)\n\{\n"
    r"    boost::function<void\(const ros::MessageEvent<([\w:]+) const> &\)> f =\n"
    r"        \[cb\]\(const ros::MessageEvent<([\w:]+) const> &e\) \{\n"
    r"            g_now_ns = e\.getReceiptTime\(\)\.toNSec\(\);\n"
    r"            struct (\w+) c;\n"
    r"            std::memset\(&c, 0, sizeof c\);\n"
    r"            to_c\(\*e\.getConstMessage\(\), &c\);\n"
    r"            cb\(&c\);\n"
    r"        \};\n"
    r"    ros::Subscriber s = g_nh->subscribe<([\w:]+)>\(", re.M)


_COMMENT_OR_STRING = re.compile(r'("(?:\\.|[^"\\\n])*")|//[^\n]*|/\*.*?\*/', re.S)


def _strip_comments(cpp: str) -> str:
    """``cpp`` without its comments (string literals kept)."""
    return _COMMENT_OR_STRING.sub(lambda m: m.group(1) or "", cpp)


def _time_problems(cpp: str, n_subs: int) -> list[str]:
    """What in ``cpp`` departs from the ROS time the proof assumes."""
    problems: list[str] = []
    cpp = _strip_comments(cpp)
    if len(_NOW_VAR.findall(cpp)) != 1:
        problems.append("  the wrapper does not define its time once as `unsigned long long g_now_ns = 0;`")
    if len(_NOW_DEF.findall(cpp)) != 1 or len(re.findall(r"\bros_now\s*\(", cpp)) != 1:
        problems.append("  the wrapper does not define ros_now() once, returning g_now_ns")
    if len(_SEC_DEF.findall(cpp)) != 1 or len(re.findall(r"\bros_time_sec\s*\(", cpp)) != 1:
        problems.append("  the wrapper does not define ros_time_sec() once, returning the seconds of g_now_ns")
    if len(_NSEC_DEF.findall(cpp)) != 1 or len(re.findall(r"\bros_time_nsec\s*\(", cpp)) != 1:
        problems.append("  the wrapper does not define ros_time_nsec() once, returning the nanoseconds of g_now_ns")
    if not _NOW_INIT.search(cpp):
        problems.append("  ros_init does not set the time to ros::Time::now() once the node handle exists")
    if not _NOW_SPIN.search(cpp):
        problems.append("  ros_spinOnce does not set the time to ros::Time::now() right after ros::spinOnce()")
    subs = _NOW_SUB.findall(cpp)
    for c_name, struct, t1, t2, struct2, t3 in subs:
        if not (t1 == t2 == t3 and struct == struct2):
            problems.append(f"  ros_subscribe_{c_name}: the message event, the converted struct and the "
                            "subscription disagree on the message type")
    if len(subs) != n_subs:
        problems.append(f"  {n_subs - len(subs)} subscription(s) do not set the time to the message event's "
                        "receipt time before calling the glue's callback")
    sets = len(_NOW_SET.findall(_NOW_VAR.sub("", cpp)))
    if sets != 2 + n_subs:
        problems.append(f"  the wrapper sets its time in {sets} places; expected {2 + n_subs} "
                        f"(ros_init, ros_spinOnce and the {n_subs} subscription callback(s))")
    return problems


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
    problems += _time_problems(cpp, len(re.findall(r"^void ros_subscribe_\w+\(", cpp, re.M)))
    rates = _RATE.findall(cpp)
    if len(rates) != 1:
        problems.append(f"  the wrapper creates {len(rates)} ros::Rate objects; expected one")
    elif Fraction(rates[0]) * 1000 != period:
        problems.append(f"  the wrapper sleeps {rates[0]} s per cycle; the proved period is {period} ms")
    if problems:
        raise WrapperMismatch(f"{wrapper_name} does not implement the proved model's interface", problems)


_GLUE_PROTO = re.compile(r"^[A-Za-z_][^;{}()]*\b(ros_\w+)\(.*\);$", re.M)


def _walk(node):
    """``node`` and every node below it (pycparser)."""
    stack = [node]
    while stack:
        n = stack.pop()
        yield n
        stack.extend(child for _, child in n.children())


def _prototypes(text: str, what: str) -> dict[str, str]:
    """The top-level one-line prototypes of the ``ros_*`` functions in
    ``text``, by name, as a normalised C type (parameter names dropped)."""
    from pycparser import c_ast, c_generator, c_parser

    out: dict[str, str] = {}
    for m in _GLUE_PROTO.finditer(text):
        line, name = m.group(0), m.group(1)
        try:
            ast = c_parser.CParser().parse(line, filename=what)
        except Exception as exc:  # pycparser's ParseError and its lexer's errors
            raise WrapperMismatch(f"{what}: cannot read the prototype {line!r}: {exc}", []) from None
        if len(ast.ext) != 1 or not isinstance(ast.ext[0], c_ast.Decl) \
                or not isinstance(ast.ext[0].type, c_ast.FuncDecl) or ast.ext[0].name != name:
            continue
        decl = ast.ext[0]
        params = decl.type.args
        if params is not None:
            for node in _walk(params):
                if isinstance(node, c_ast.TypeDecl):
                    node.declname = None
                elif isinstance(node, c_ast.Decl):
                    node.name = None
        ret = decl.type.type
        while not isinstance(ret, c_ast.TypeDecl):
            ret = ret.type
        ret.declname = "ROSGEN_FN"
        text_ = c_generator.CGenerator().visit(decl.type)
        if name in out and out[name] != text_:
            raise WrapperMismatch(f"{what} declares {name} twice, with different types", [])
        out[name] = text_
    return out


def check_glue_externals(glue: str, header: str, *, glue_name: str, header_name: str) -> None:
    """Raise :class:`WrapperMismatch` unless every ROS function (``ros_*``)
    that the glue declares is declared by the wrapper's header with the
    same C type.  (The wrapper's definitions include the header, so the
    C++ compiler holds them to it; the glue is compiled on its own.)"""
    want = _prototypes(glue, glue_name)
    have = _prototypes(header, header_name)
    problems = []
    for name, t in want.items():
        if name not in have:
            problems.append(f"  {glue_name} declares {name}, which {header_name} does not declare")
        elif have[name] != t:
            problems.append(f"  {name}: {glue_name} declares {t.replace('ROSGEN_FN', name)}, "
                            f"{header_name} {have[name].replace('ROSGEN_FN', name)}")
    if problems:
        raise WrapperMismatch(f"{header_name} does not declare the ROS functions as the glue calls them", problems)

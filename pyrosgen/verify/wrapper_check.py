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

It also checks the conversion of each carried string (rule 4.14): for
every string struct ``ros_string<N>`` of the proved model, the wrapper
converts a received ``std::string`` by copying at most its first ``N``
bytes, setting ``len`` to their number and ``truncated`` when the string
was longer, and zeroing the bytes past ``len`` (the environment model's
well-typed message), and converts a published one back from the first
``len`` bytes, at most ``N``: exactly the text of
``pyrosgen/templates/ros_api.cpp.j2``, once each, and no other string
conversion.

And the conversion of each carried variable-length array (rule 4.15):
for every sequence struct ``ros_seq_<T>_<N>`` of the proved model, the
wrapper converts a received ``std::vector`` exactly as the environment
model's ``Environment.clamp`` says (policy truncate): ``len`` is the
size capped at ``N`` (the clamp), ``truncated`` is set when the vector
was longer (the flag), its first ``len`` elements are copied and every
other element of ``data`` is set to zero (the zero fill); and converts a
published one back from the first ``min(len, N)`` elements, which is
what the environment model's publication event keeps of the glue's
message (``Environment.clamp`` on publish, ``DDC.sent``; the length and
elements of a published array may come from the controller, rule 4.15):
the text of the template, once each, and no other vector conversion (a
published conversion without the ``min``, with another bound, from the
whole array or from another start is refused).  For a carried sequence
of strings (``ros_seq_string<M>_<N>``) or of messages
(``ros_seq_<pkg>_<Type>_<N>``), whose ``data`` holds element structs
(``Environment.clamp_bounded_elems``): ``len`` the size capped at ``N``,
``truncated`` set when longer, the first ``len`` elements each converted
by the element's own ``to_c`` (its strings and sequences capped in turn),
every other element zeroed (``memset`` of ``N - len`` elements); published,
the first ``min(len, N)`` elements each converted back; the same text
once each.  A proved model holding a struct of policy reject inside the
elements of such a sequence is refused whatever the wrapper (rule 4.15
refuses it: ``Environment.too_long`` tests every element the struct
holds, received or not).

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
    r"((?:            [^\n]*\breturn;\n)*)"
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


_REJECT_NAME = re.compile(r"ros_r(?:seq_\w+_|string)([1-9][0-9]*)")


def reject_checks(messages: dict[str, list[tuple[str, str]]], struct: str) -> list[tuple[str, int]]:
    """The sequences and strings of policy reject (rule 4.15: a struct
    ``ros_rseq_<T>_<N>`` or ``ros_rstring<N>``, ``Environment.reject_name``)
    in a message of the proved struct ``struct``, as (C++ access path, N),
    in the order of the fields (through nested messages and every element of
    fixed-size arrays of messages): those ``Environment.too_long`` reads."""
    out: list[tuple[str, int]] = []

    def go(name: str, prefix: str, depth: int) -> None:
        if depth > 64:
            return
        for fname, ftype in messages.get(name, []):
            m = re.fullmatch(r"(?:array ([1-9][0-9]*) )?msg (\w+)", ftype)
            if m is None:
                continue
            sub = m.group(2)
            idxs = [""] if m.group(1) is None else [f"[{i}]" for i in range(int(m.group(1)))]
            for ix in idxs:
                path = f"{prefix}{fname}{ix}"
                rj = _REJECT_NAME.fullmatch(sub)
                if rj is not None:
                    out.append((path, int(rj.group(1))))
                elif not sub.startswith(("ros_seq_", "ros_string")):
                    go(sub, path + ".", depth + 1)

    go(struct, "", 0)
    return out


def rejects_inside_elements(messages: dict[str, list[tuple[str, str]]]) -> list[tuple[str, str]]:
    """The structs of policy reject (``ros_rseq_...``, ``ros_rstring...``)
    that the proved model holds inside the elements of a sequence of
    strings or messages, each with that sequence: ``Environment.too_long``
    tests them in every element the sequence's struct holds, received or
    not, which no wrapper test of the received message can match (rule
    4.15 refuses such a model)."""
    out: list[tuple[str, str]] = []

    def inside(name: str, seen: set[str]) -> set[str]:
        found: set[str] = set()
        for _fname, ftype in messages.get(name, []):
            m = re.fullmatch(r"(?:array [1-9][0-9]* )?msg (\w+)", ftype)
            if m is None or m.group(1) in seen:
                continue
            sub = m.group(1)
            seen.add(sub)
            if _REJECT_NAME.fullmatch(sub):
                found.add(sub)
            found |= inside(sub, seen)
        return found

    for name, fields in sorted(messages.items()):
        if not name.startswith(("ros_seq_", "ros_rseq_")) or len(fields) != 3:
            continue
        m = re.fullmatch(r"array [1-9][0-9]* msg (\w+)", fields[2][1]) if fields[2][0] == "data" else None
        if m is None:
            continue
        elem = m.group(1)
        found = ({elem} if _REJECT_NAME.fullmatch(elem) else set()) | inside(elem, {elem})
        out += [(name, r) for r in sorted(found)]
    return out


def reject_lines(checks: list[tuple[str, int]]) -> str:
    """The one accepted text of a subscription callback's reject test (rule
    4.15, ``Environment.accepted``): first thing in the callback, before the
    receipt time or the conversion, one line per sequence or string of policy
    reject, returning without calling the glue's callback when it is longer
    than its maximum."""
    return "".join(f"            if (e.getConstMessage()->{path}.size() > {n}) return;\n" for path, n in checks)


def _time_problems(cpp: str, n_subs: int, messages: dict[str, list[tuple[str, str]]] | None = None) -> list[str]:
    """What in ``cpp`` departs from the ROS time the proof assumes, and
    from the reject tests of the proved model's ``messages``."""
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
    for c_name, struct, t1, t2, rejects, struct2, t3 in subs:
        if not (t1 == t2 == t3 and struct == struct2):
            problems.append(f"  ros_subscribe_{c_name}: the message event, the converted struct and the "
                            "subscription disagree on the message type")
        want = reject_lines(reject_checks(messages or {}, struct))
        if rejects != want:
            what = ", ".join(f"{p} longer than {n}" for p, n in reject_checks(messages or {}, struct)) or "nothing"
            problems.append(f"  ros_subscribe_{c_name}: the callback does not drop exactly the messages that rule "
                            f"4.15's policy reject drops (Environment.accepted: {what}), first thing, before the "
                            "receipt time and the conversion")
    if len(subs) != n_subs:
        problems.append(f"  {n_subs - len(subs)} subscription(s) do not set the time to the message event's "
                        "receipt time before calling the glue's callback")
    sets = len(_NOW_SET.findall(_NOW_VAR.sub("", cpp)))
    if sets != 2 + n_subs:
        problems.append(f"  the wrapper sets its time in {sets} places; expected {2 + n_subs} "
                        f"(ros_init, ros_spinOnce and the {n_subs} subscription callback(s))")
    return problems


def _string_capacity(fields: list[tuple[str, str]]) -> int | None:
    """The capacity of a proved message that is a carried string's struct
    (``Wellformed.string_msg``: ``len``, ``truncated``, ``data``), else
    ``None``."""
    if len(fields) == 3 and fields[0] == ("len", "uint32") and fields[1] == ("truncated", "bool"):
        m = re.fullmatch(r"array ([1-9][0-9]*) uint8", fields[2][1]) if fields[2][0] == "data" else None
        if m:
            return int(m.group(1))
    return None


def _string_to_c(struct: str, n: int) -> str:
    """The one accepted conversion of a received string into ``struct``."""
    return (f"inline void to_c(const std::string &r, struct {struct} *c)\n{{\n"
            f"    const std::size_t n = r.size();\n"
            f"    const std::size_t len = std::min<std::size_t>(n, {n});\n"
            f"    c->len = static_cast<unsigned int>(len);\n"
            f"    c->truncated = n > {n} ? 1 : 0;\n"
            f"    std::memcpy(c->data, r.data(), len);\n"
            f"    std::memset(c->data + len, 0, {n} - len);\n}}\n")


def _string_from_c(struct: str, n: int) -> str:
    """The one accepted conversion of ``struct`` into a published string."""
    return (f"inline void from_c(const struct {struct} *c, std::string &r)\n{{\n"
            f"    r.assign(reinterpret_cast<const char *>(c->data), std::min<std::size_t>(c->len, {n}));\n}}\n")


_STRING_CONV = re.compile(r"\b(?:to_c\s*\(\s*const\s+std::string\b[^)]*\bstruct\s+(\w+)"
                          r"|from_c\s*\(\s*const\s+struct\s+(\w+)\s*\*\s*\w*\s*,\s*std::string\b)")


def _string_problems(cpp: str, messages: dict[str, list[tuple[str, str]]]) -> list[str]:
    """What in ``cpp`` departs from the conversions of the proved model's
    carried strings (rule 4.14)."""
    cpp = _strip_comments(cpp)
    want = {name: n for name, fields in messages.items()
            if name.startswith(("ros_string", "ros_rstring")) and (n := _string_capacity(fields)) is not None}
    problems = []
    for name, n in sorted(want.items()):
        if cpp.count(_string_to_c(name, n)) != 1:
            problems.append(f"  the wrapper does not convert a received string into struct {name} once as rule 4.14 "
                            f"says (its first {n} bytes at most, truncated when longer, zero past len)")
        if cpp.count(_string_from_c(name, n)) != 1:
            problems.append(f"  the wrapper does not convert struct {name} into a published string once as rule 4.14 "
                            f"says (its first len bytes, {n} at most)")
    # declarations and definitions: two of each per proved string struct
    named = [a or b for a, b in _STRING_CONV.findall(cpp)]
    for name in sorted(set(named)):
        if name not in want:
            problems.append(f"  the wrapper converts strings to or from struct {name}, which is not a string "
                            "struct of the proved model")
        elif named.count(name) != 4:
            problems.append(f"  the wrapper has {named.count(name)} string conversions of struct {name}; "
                            "expected a declaration and a definition of each direction")
    return problems


#: roscpp's element type of a ``T[]`` of each primitive (``std::vector<...>``).
_CPP_ELEMENT = {"bool": "uint8_t", "int8": "int8_t", "uint8": "uint8_t", "int16": "int16_t",
                "uint16": "uint16_t", "int32": "int32_t", "uint32": "uint32_t", "int64": "int64_t",
                "uint64": "uint64_t", "float32": "float", "float64": "double"}

_SEQ_NAME = re.compile(r"ros_r?seq_(" + "|".join(_CPP_ELEMENT) + r")_([1-9][0-9]*)")


#: A carried sequence of strings, ``ros_seq_string<M>_<N>``, or of
#: messages, ``ros_seq_<pkg>_<Type>_<N>`` (rule 4.15).
_SEQ_STRING_NAME = re.compile(r"ros_r?seq_string([1-9][0-9]*)_([1-9][0-9]*)")
_SEQ_MSG_NAME = re.compile(r"ros_r?seq_([a-z][a-z0-9_]*_[A-Za-z][A-Za-z0-9]*)_([1-9][0-9]*)")


def _elem_cpp(elem: str) -> str | None:
    """The roscpp type of the element struct ``elem`` of a carried
    sequence of strings or messages: ``std::string`` for ``ros_string<M>``,
    ``ros::Time``, ``ros::Duration``, ``pkg::Type`` for ``pkg_Type``."""
    if re.fullmatch(r"ros_string[1-9][0-9]*", elem):
        return "std::string"
    if elem in ("ros_time", "ros_duration"):
        return {"ros_time": "ros::Time", "ros_duration": "ros::Duration"}[elem]
    pkg, _, typ = elem.rpartition("_")
    if not pkg or pkg == "ros" or pkg.startswith("ros_") or not re.fullmatch(r"[A-Za-z][A-Za-z0-9]*", typ):
        return None
    return f"{pkg}::{typ}"


def _seq_shape(name: str, fields: list[tuple[str, str]]) -> tuple[str, int] | None:
    """``(T, N)`` of a proved message that is a carried sequence's struct
    ``ros_seq_<T>_<N>`` (``len``, ``truncated``, ``data`` of ``N`` ``T``),
    else ``None``; for a sequence of strings or messages (rule 4.15),
    ``T`` is ``struct <elem>`` (``data`` of ``N`` structs ``elem``)."""
    if len(fields) != 3 or fields[0] != ("len", "uint32") or fields[1] != ("truncated", "bool"):
        return None
    m = _SEQ_NAME.fullmatch(name)
    if m is not None:
        prim, n = m.group(1), int(m.group(2))
        return (prim, n) if fields[2] == ("data", f"array {n} {prim}") else None
    ms = _SEQ_STRING_NAME.fullmatch(name)
    mm = _SEQ_MSG_NAME.fullmatch(name)
    if ms is not None:
        elem, n = f"ros_string{ms.group(1)}", int(ms.group(2))
    elif mm is not None and _elem_cpp(mm.group(1)) is not None:
        elem, n = mm.group(1), int(mm.group(2))
    else:
        return None
    return (f"struct {elem}", n) if fields[2] == ("data", f"array {n} msg {elem}") else None


def _seq_to_c_text(struct: str, cpp_elem: str, n: int, fill: str) -> str:
    """The accepted conversion of a received ``std::vector<cpp_elem>`` into
    ``struct`` (``Environment.clamp``): ``len`` the size capped at ``n``,
    ``truncated`` set when longer, then ``fill`` (the elements, then
    zeros)."""
    return (f"inline void to_c(const std::vector<{cpp_elem}> &r, struct {struct} *c)\n{{\n"
            f"    const std::size_t n = r.size();\n"
            f"    const std::size_t len = std::min<std::size_t>(n, {n});\n"
            f"    c->len = static_cast<unsigned int>(len);\n"
            f"    c->truncated = n > {n} ? 1 : 0;\n"
            f"{fill}}}\n")


def _seq_elems_to_c(struct: str, elem: str, n: int) -> str:
    """The one accepted conversion of a received vector of strings or
    messages into ``struct`` (``clamp_bounded_elems``): the first
    ``min(size, N)`` elements each converted by its own ``to_c``, the
    others zero."""
    return _seq_to_c_text(struct, _elem_cpp(elem), n,
                          "    for (std::size_t i = 0; i < len; ++i) to_c(r[i], &c->data[i]);\n"
                          f"    std::memset(c->data + len, 0, ({n} - len) * sizeof c->data[0]);\n")


def _seq_elems_from_c(struct: str, elem: str, n: int) -> str:
    """The one accepted conversion of ``struct`` into a published vector of
    strings or messages: its first ``min(len, N)`` elements, each converted."""
    return (f"inline void from_c(const struct {struct} *c, std::vector<{_elem_cpp(elem)}> &r)\n{{\n"
            f"    r.resize(std::min<std::size_t>(c->len, {n}));\n"
            f"    for (std::size_t i = 0; i < r.size(); ++i) from_c(&c->data[i], r[i]);\n}}\n")


def _seq_to_c(struct: str, prim: str, n: int) -> str:
    """The one accepted conversion of a received vector into ``struct``."""
    if prim.startswith("struct "):
        return _seq_elems_to_c(struct, prim[len("struct "):], n)
    return _seq_to_c_text(struct, _CPP_ELEMENT[prim], n,
                          "    std::copy(r.begin(), r.begin() + len, c->data);\n"
                          f"    std::fill(c->data + len, c->data + {n}, 0);\n")


def _seq_from_c(struct: str, prim: str, n: int) -> str:
    """The one accepted conversion of ``struct`` into a published vector."""
    if prim.startswith("struct "):
        return _seq_elems_from_c(struct, prim[len("struct "):], n)
    return (f"inline void from_c(const struct {struct} *c, std::vector<{_CPP_ELEMENT[prim]}> &r)\n{{\n"
            f"    r.assign(c->data, c->data + std::min<std::size_t>(c->len, {n}));\n}}\n")


_SEQ_CONV = re.compile(r"\b(?:to_c\s*\(\s*const\s+std::vector\s*<[^>]*>[^)]*\bstruct\s+(\w+)"
                       r"|from_c\s*\(\s*const\s+struct\s+(\w+)\s*\*\s*\w*\s*,\s*std::vector\b)")


def _seq_problems(cpp: str, messages: dict[str, list[tuple[str, str]]]) -> list[str]:
    """What in ``cpp`` departs from the conversions of the proved model's
    carried variable-length arrays (rule 4.15)."""
    cpp = _strip_comments(cpp)
    want = {name: shape for name, fields in messages.items() if (shape := _seq_shape(name, fields)) is not None}
    problems = []
    for name, (prim, n) in sorted(want.items()):
        if cpp.count(_seq_to_c(name, prim, n)) != 1:
            problems.append(f"  the wrapper does not convert a received {prim}[] into struct {name} once as rule 4.15 "
                            f"says (Environment.clamp: len the size capped at {n}, truncated when longer, the first "
                            "len elements copied, zero past len)")
        if cpp.count(_seq_from_c(name, prim, n)) != 1:
            problems.append(f"  the wrapper does not convert struct {name} into a published {prim}[] once as rule "
                            f"4.15 says (its first len elements, {n} at most)")
    named = [a or b for a, b in _SEQ_CONV.findall(cpp)]
    for name in sorted(set(named)):
        if name not in want:
            problems.append(f"  the wrapper converts vectors to or from struct {name}, which is not a sequence "
                            "struct of the proved model")
        elif named.count(name) != 4:
            problems.append(f"  the wrapper has {named.count(name)} vector conversions of struct {name}; "
                            "expected a declaration and a definition of each direction")
    return problems


def check_wrapper(cpp: str, proved_text: str, *, wrapper_name: str) -> None:
    """Raise :class:`WrapperMismatch` unless the wrapper source ``cpp``
    registers exactly the proved topics and sleeps with the proved period."""
    topics, period = proved_interface(proved_text)
    messages = parse_model_text(proved_text).messages
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
    problems += _time_problems(cpp, len(re.findall(r"^void ros_subscribe_\w+\(", cpp, re.M)),
                               messages)
    for seq, inner in rejects_inside_elements(messages):
        problems.append(f"  the proved model holds {inner}, of policy reject, inside the elements of {seq}: "
                        "Environment.too_long tests it in every element the struct holds, received or not, which "
                        "the wrapper cannot (rule 4.15 refuses such a model)")
    problems += _string_problems(cpp, messages)
    problems += _seq_problems(cpp, messages)
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

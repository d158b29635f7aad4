"""The wrapper check on variable-length arrays of messages and strings
(rule 4.15): the conversions of tests/ros/models/elem_seq.yaml's
``ros_seq_geometry_msgs_PoseStamped_3`` (``poses`` of a ``nav_msgs/Path``)
and ``ros_seq_string4_3`` (``name`` of a ``sensor_msgs/JointState``) are
held to exactly the text that does what ``Environment.clamp`` says
(``clamp_bounded_elems``: len = min(size, N), truncated = size > N, the
first len elements converted in turn, every other one zero; published:
the first min(len, N) elements), and a subscription to a message whose
array of messages or strings has policy reject tests its size first
thing (``Environment.too_long``, ``accepted``)."""

from __future__ import annotations

import pytest

import pyrosgen.ros.wrapper as wrapper
from pyrosgen.frontend.validate import load_model
from pyrosgen.proof.modeltext import model_text
from pyrosgen.verify.wrapper_check import WrapperMismatch, check_wrapper

from .conftest import ROOT, assert_wrapper_refused

MODEL = ROOT / "tests" / "ros" / "models" / "elem_seq.yaml"

_P = "struct ros_seq_geometry_msgs_PoseStamped_3 *c)\n{\n"
_S = "struct ros_seq_string4_3 *c)\n{\n"
_LEN = "    const std::size_t n = r.size();\n    const std::size_t len = std::min<std::size_t>(n, 3);\n"
_TRUNC = "    c->len = static_cast<unsigned int>(len);\n    c->truncated = n > 3 ? 1 : 0;\n"
_LOOP = "    for (std::size_t i = 0; i < len; ++i) to_c(r[i], &c->data[i]);\n"
_ZERO = "    std::memset(c->data + len, 0, (3 - len) * sizeof c->data[0]);\n"
_PUB = "    r.resize(std::min<std::size_t>(c->len, 3));\n"

MUTATIONS = {
    "messages: received array not clamped": (_P + _LEN, _P + _LEN.replace("std::min<std::size_t>(n, 3)", "n")),
    "messages: clamped to N-1": (_P + _LEN, _P + _LEN.replace("(n, 3)", "(n, 2)")),
    "messages: truncated never set": (_P + _LEN + _TRUNC, _P + _LEN + _TRUNC.replace("n > 3 ? 1 : 0", "0")),
    "messages: truncated at the maximum": (_P + _LEN + _TRUNC, _P + _LEN + _TRUNC.replace("n > 3", "n >= 3")),
    "messages: every element converted": (_P + _LEN + _TRUNC + _LOOP,
                                          _P + _LEN + _TRUNC + _LOOP.replace("i < len", "i < n")),
    "messages: elements not converted": (_P + _LEN + _TRUNC + _LOOP, _P + _LEN + _TRUNC),
    "messages: no zero fill past len": (_P + _LEN + _TRUNC + _LOOP + _ZERO, _P + _LEN + _TRUNC + _LOOP),
    "messages: zero fill of bytes, not elements": (_P + _LEN + _TRUNC + _LOOP + _ZERO,
                                                    _P + _LEN + _TRUNC + _LOOP
                                                    + _ZERO.replace("(3 - len) * sizeof c->data[0]", "3 - len")),
    "messages: published without the min": ("PoseStamped_3 *c, std::vector<geometry_msgs::PoseStamped> &r)\n{\n" + _PUB,
                                            "PoseStamped_3 *c, std::vector<geometry_msgs::PoseStamped> &r)\n{\n"
                                            + _PUB.replace("std::min<std::size_t>(c->len, 3)", "c->len")),
    "messages: published N+1": ("PoseStamped_3 *c, std::vector<geometry_msgs::PoseStamped> &r)\n{\n" + _PUB,
                                "PoseStamped_3 *c, std::vector<geometry_msgs::PoseStamped> &r)\n{\n"
                                + _PUB.replace("(c->len, 3)", "(c->len, 4)")),
    "strings: received array not clamped": (_S + _LEN, _S + _LEN.replace("std::min<std::size_t>(n, 3)", "n")),
    "strings: truncated never set": (_S + _LEN + _TRUNC, _S + _LEN + _TRUNC.replace("n > 3 ? 1 : 0", "0")),
    "strings: strings not converted": (_S + _LEN + _TRUNC + _LOOP, _S + _LEN + _TRUNC),
    "strings: no zero fill past len": (_S + _LEN + _TRUNC + _LOOP + _ZERO, _S + _LEN + _TRUNC + _LOOP),
    "strings: published without the min": ("string4_3 *c, std::vector<std::string> &r)\n{\n" + _PUB,
                                           "string4_3 *c, std::vector<std::string> &r)\n{\n"
                                           + _PUB.replace("std::min<std::size_t>(c->len, 3)", "c->len")),
    "element string not clamped": ("const std::size_t len = std::min<std::size_t>(n, 4);",
                                   "const std::size_t len = n;"),
}


def _rendered(m):
    return wrapper.render_wrapper(m)[wrapper.wrapper_files(m).api_source]


@pytest.fixture(scope="module")
def truncate():
    m = load_model(MODEL)
    cpp = _rendered(m)
    check_wrapper(cpp, model_text(m), wrapper_name="w.cpp")
    return cpp, model_text(m)


@pytest.mark.parametrize("name", sorted(MUTATIONS))
def test_mutated_conversion_is_refused(truncate, name):
    cpp, text = truncate
    assert_wrapper_refused(cpp, *MUTATIONS[name], text)


def reject_model(tmp_path):
    """elem_seq.yaml with policy reject on both arrays (poses, name): the
    truncated flags then read an element string's."""
    text = MODEL.read_text()
    for old, new in (
        ('max_length: {poses: 3, "poses[].header.frame_id": 4}}',
         'max_length: {poses: 3, "poses[].header.frame_id": 4}, policy: {poses: reject}}'),
        ('max_length: {name: 3, "name[]": 4}}', 'max_length: {name: 3, "name[]": 4}, policy: {name: reject}}'),
        ("{topic: /path, field: poses, derived: truncated, input: TP}",
         '{topic: /path, field: "poses[0].header.frame_id", derived: truncated, input: TP}'),
        ("{topic: /joints, field: name, derived: truncated, input: TJ}",
         '{topic: /joints, field: "name[1]", derived: truncated, input: TJ}'),
    ):
        assert old in text
        text = text.replace(old, new)
    p = tmp_path / "elem_seq_reject.yaml"
    p.write_text(text)
    return p


_POSES = "            if (e.getConstMessage()->poses.size() > 3) return;\n"
_NAMES = "            if (e.getConstMessage()->name.size() > 3) return;\n"
REJECT_MUTATIONS = {
    "no reject test of the poses": (_POSES, ""),
    "poses rejected at the maximum": (_POSES, _POSES.replace(" > 3", " >= 3")),
    "poses rejected above N+1": (_POSES, _POSES.replace(" > 3", " > 4")),
    "no reject test of the names": (_NAMES, ""),
    "reject test of an element's frame_id": (_POSES, _POSES + _POSES.replace("poses.size()",
                                                                          "poses[0].header.frame_id.size()")),
}


@pytest.fixture(scope="module")
def reject(tmp_path_factory):
    m = load_model(reject_model(tmp_path_factory.mktemp("elem_seq_reject")))
    assert {b.name for _, _, b in m.bounded_fields if b.reject} == {"ros_rseq_geometry_msgs_PoseStamped_3",
                                                                    "ros_rseq_string4_3"}
    cpp = _rendered(m)
    check_wrapper(cpp, model_text(m), wrapper_name="w.cpp")
    assert _POSES in cpp and _NAMES in cpp
    return cpp, model_text(m)


@pytest.mark.parametrize("name", sorted(REJECT_MUTATIONS))
def test_mutated_reject_test_is_refused(reject, name):
    cpp, text = reject
    assert_wrapper_refused(cpp, *REJECT_MUTATIONS[name], text)


def test_a_proved_model_with_reject_inside_elements_is_refused(truncate):
    """Defence in depth (the front end refuses such a model, rule 4.15): a
    proved model whose array elements hold a struct of policy reject is
    refused, whatever the wrapper."""
    cpp, text = truncate
    with pytest.raises(WrapperMismatch) as info:
        check_wrapper(cpp, text.replace("ros_string4", "ros_rstring4"), wrapper_name="w.cpp")
    assert any("ros_rstring4, of policy reject, inside the elements of ros_seq_geometry_msgs_PoseStamped_3" in ln
               for ln in info.value.lines), info.value.lines
    assert any("ros_rstring4, of policy reject, inside the elements of ros_seq_string4_3" in ln
               for ln in info.value.lines), info.value.lines

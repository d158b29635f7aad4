"""The running node is the proved one: the rendered C++ wrapper must
register exactly the proved model's topics (names, message structs, queue
sizes) and sleep with its period; ``pyrosgen build`` refuses (exit 2,
nothing written) a wrapper that does otherwise."""

from __future__ import annotations

import pytest

import pyrosgen.ros.wrapper as wrapper
from pyrosgen import cli
from pyrosgen.frontend.validate import load_model
from pyrosgen.proof.modeltext import model_text
from pyrosgen.verify.wrapper_check import WrapperMismatch, check_wrapper

from .conftest import LANDSHARK, LANDSHARK_CTL, MULTI, assert_wrapper_refused

MUTATIONS = {
    "subscribe queue q+1": ('"/landshark/gps_velocity", 1, f);', '"/landshark/gps_velocity", 2, f);'),
    "advertise queue q+1": ('ops.init<geometry_msgs::TwistStamped>("/landshark_control/base_velocity", 1);',
                            'ops.init<geometry_msgs::TwistStamped>("/landshark_control/base_velocity", 2);'),
    "wrong topic name": ('"/landshark/right_wheel_velocity", 1, f);', '"/landshark/right_wheel", 1, f);'),
    "wrong period": ("ros::Rate(ros::Duration(0.02))", "ros::Rate(ros::Duration(0.025))"),
    "extra subscription": ("    std::lock_guard<std::mutex> lock(g_subs_mutex);\n    g_sub_landshark_gps_velocity = s;",
                           "    std::lock_guard<std::mutex> lock(g_subs_mutex);\n    g_sub_landshark_gps_velocity = s;\n"
                           '    g_nh->subscribe<geometry_msgs::TwistStamped>("/other", 1, f);'),
}


#: Mutations of the conversions of a carried string (rule 4.14), on the
#: wrapper of examples/landshark/landshark_stamped.yaml (frame_id: base_link).
STRING_MUTATIONS = {
    "received string not clamped": ("std::min<std::size_t>(n, 128)", "n"),
    "published string not clamped": ("std::min<std::size_t>(c->len, 128)", "c->len"),
    "truncated never set": ("c->truncated = n > 128 ? 1 : 0;", "c->truncated = 0;"),
    "bytes past len not zeroed": ("    std::memset(c->data + len, 0, 128 - len);\n", ""),
    "received into 127 bytes": ("std::min<std::size_t>(n, 128)", "std::min<std::size_t>(n, 127)"),
}


@pytest.mark.parametrize("name", sorted(STRING_MUTATIONS))
def test_mutated_string_conversion_is_refused(name):
    m = load_model(LANDSHARK.parent / "landshark_stamped.yaml")
    cpp = wrapper.render_wrapper(m)[wrapper.wrapper_files(m).api_source]
    check_wrapper(cpp, model_text(m), wrapper_name="w.cpp")
    assert_wrapper_refused(cpp, *STRING_MUTATIONS[name], model_text(m))


#: Mutations of the conversions of a carried variable-length array (rule
#: 4.15), on the wrapper of examples/laser_guard/laser_guard.yaml (ranges:
#: at most 1081 float32): the environment model's Environment.clamp
#: without the clamp, the zero fill or the truncated flag, or otherwise off.
SEQUENCE_MUTATIONS = {
    "received array not clamped": ("const std::size_t len = std::min<std::size_t>(n, 1081);",
                                   "const std::size_t len = n;"),
    "no zero fill past len": ("    std::fill(c->data + len, c->data + 1081, 0);\n", ""),
    "zero fill one short": ("std::fill(c->data + len, c->data + 1081, 0);", "std::fill(c->data + len, c->data + 1080, 0);"),
    "truncated never set": ("c->truncated = n > 1081 ? 1 : 0;", "c->truncated = 0;"),
    "truncated at the maximum": ("c->truncated = n > 1081 ? 1 : 0;", "c->truncated = n >= 1081 ? 1 : 0;"),
    "copies the whole vector": ("std::copy(r.begin(), r.begin() + len, c->data);",
                                "std::copy(r.begin(), r.end(), c->data);"),
    "published array not clamped": ("std::min<std::size_t>(c->len, 1081)", "c->len"),
    "received into 1080 elements": ("std::min<std::size_t>(n, 1081)", "std::min<std::size_t>(n, 1080)"),
}


@pytest.mark.parametrize("name", sorted(SEQUENCE_MUTATIONS))
def test_mutated_sequence_conversion_is_refused(name):
    m = load_model(LANDSHARK.parents[1] / "laser_guard" / "laser_guard.yaml")
    cpp = wrapper.render_wrapper(m)[wrapper.wrapper_files(m).api_source]
    check_wrapper(cpp, model_text(m), wrapper_name="w.cpp")
    assert_wrapper_refused(cpp, *SEQUENCE_MUTATIONS[name], model_text(m))


#: Mutations of the conversion of a published variable-length array and
#: a published string written by the controller (rule 4.15, publish side),
#: on the wrapper of tests/ros/models/seq_echo.yaml (data: at most 4
#: float64; header.frame_id: 128 bytes): the environment model's
#: Environment.clamp on publish keeps the first min(len, N) elements.
PUBLISHED_MUTATIONS = {
    "published array without the min": ("std::min<std::size_t>(c->len, 4)", "c->len"),
    "published array bound N+1": ("std::min<std::size_t>(c->len, 4)", "std::min<std::size_t>(c->len, 5)"),
    "published array bound N-1": ("std::min<std::size_t>(c->len, 4)", "std::min<std::size_t>(c->len, 3)"),
    "published array ignores len": ("r.assign(c->data, c->data + std::min<std::size_t>(c->len, 4));",
                                    "r.assign(c->data, c->data + 4);"),
    "published array with max": ("std::min<std::size_t>(c->len, 4)", "std::max<std::size_t>(c->len, 4)"),
    "published array from element 1": ("r.assign(c->data, c->data + std::min<std::size_t>(c->len, 4));",
                                       "r.assign(c->data + 1, c->data + std::min<std::size_t>(c->len, 4));"),
    "published string without the min": ("std::min<std::size_t>(c->len, 128)", "c->len"),
    "published string bound 127": ("std::min<std::size_t>(c->len, 128)", "std::min<std::size_t>(c->len, 127)"),
}


@pytest.mark.parametrize("name", sorted(PUBLISHED_MUTATIONS))
def test_mutated_published_conversion_is_refused(name):
    m = load_model(LANDSHARK.parents[2] / "tests" / "ros" / "models" / "seq_echo.yaml")
    cpp = wrapper.render_wrapper(m)[wrapper.wrapper_files(m).api_source]
    check_wrapper(cpp, model_text(m), wrapper_name="w.cpp")
    assert_wrapper_refused(cpp, *PUBLISHED_MUTATIONS[name], model_text(m))


#: Mutations of the reject test of a subscription callback (rule 4.15,
#: policy reject), on the wrapper of tests/ros/models/scan_reject.yaml
#: (ranges: at most 4 float32, header.frame_id: 8 bytes, both of policy
#: reject): Environment.accepted drops a message holding either longer
#: than its maximum, before the receipt time and the conversion.
_RANGES = "            if (e.getConstMessage()->ranges.size() > 4) return;\n"
_FRAME = "            if (e.getConstMessage()->header.frame_id.size() > 8) return;\n"
_NOW = "            g_now_ns = e.getReceiptTime().toNSec();\n"
_CONV = "            to_c(*e.getConstMessage(), &c);\n"
REJECT_MUTATIONS = {
    "no reject test": (_RANGES, ""),
    "no reject test of the string": (_FRAME, ""),
    "reject at the maximum (>=)": (_RANGES, _RANGES.replace(" > 4", " >= 4")),
    "reject above N+1": (_RANGES, _RANGES.replace(" > 4", " > 5")),
    "reject tests the wrong field": (_RANGES, _RANGES.replace("ranges", "intensities")),
    "reject test after the receipt time": (_RANGES + _NOW, _NOW + _RANGES),
    "reject test after the conversion": (_RANGES + _NOW + "            struct sensor_msgs_LaserScan c;\n"
                                         "            std::memset(&c, 0, sizeof c);\n" + _CONV,
                                         _NOW + "            struct sensor_msgs_LaserScan c;\n"
                                         "            std::memset(&c, 0, sizeof c);\n" + _CONV + _RANGES),
    "reject test that does not return": (_RANGES, _RANGES.replace(" return;", " {}")),
    "reject test doubled": (_RANGES, _RANGES + _RANGES),
}


@pytest.mark.parametrize("name", sorted(REJECT_MUTATIONS))
def test_mutated_reject_test_is_refused(name):
    m = load_model(LANDSHARK.parents[2] / "tests" / "ros" / "models" / "scan_reject.yaml")
    cpp = wrapper.render_wrapper(m)[wrapper.wrapper_files(m).api_source]
    check_wrapper(cpp, model_text(m), wrapper_name="w.cpp")
    assert_wrapper_refused(cpp, *REJECT_MUTATIONS[name], model_text(m))


def _landshark():
    m = load_model(LANDSHARK)
    return m, wrapper.render_wrapper(m)[wrapper.wrapper_files(m).api_source]


@pytest.mark.parametrize("path", [LANDSHARK, MULTI], ids=["landshark", "multi"])
def test_rendered_wrappers_pass(path):
    m = load_model(path)
    check_wrapper(wrapper.render_wrapper(m)[wrapper.wrapper_files(m).api_source], model_text(m), wrapper_name="w")


@pytest.mark.parametrize("name", sorted(MUTATIONS))
def test_mutated_wrapper_is_refused(name):
    m, cpp = _landshark()
    assert_wrapper_refused(cpp, *MUTATIONS[name], model_text(m))


def test_proved_model_differs_from_wrapper():
    """Same wrapper, another proved model (queue 3 on a topic): refused."""
    m, cpp = _landshark()
    proved = model_text(m).replace("landshark_gps_velocity subscribe geometry_msgs/TwistStamped 1",
                                   "landshark_gps_velocity subscribe geometry_msgs/TwistStamped 3")
    assert proved != model_text(m)
    with pytest.raises(WrapperMismatch):
        check_wrapper(cpp, proved, wrapper_name="w.cpp")


def test_build_refuses_a_wrapper_that_is_not_the_proved_node(monkeypatch, capsys, tmp_path):
    original = wrapper.render_wrapper

    def mutated(model, proved=None):
        out = original(model, proved)
        src = wrapper.wrapper_files(model).api_source
        out[src] = out[src].replace("ros::Rate(ros::Duration(0.02))", "ros::Rate(ros::Duration(0.01))")
        return out

    monkeypatch.setattr(wrapper, "render_wrapper", mutated)
    out = tmp_path / "out"
    code = cli.main(["build", str(LANDSHARK), "--controller", str(LANDSHARK_CTL), "-o", str(out), "-q"])
    err = capsys.readouterr().err
    assert code == 2, err
    assert "does not implement the proved model's interface" in err and "proved period is 20 ms" in err
    assert not out.exists()


def test_wrapper_follows_the_proved_model():
    """Rendered with the proved model, the wrapper takes the topics' names,
    types, queue sizes and the period from it, not from the front end's
    model: a proved model that differs (here: another period and queue
    size) gives a wrapper that registers and sleeps as that model says."""
    from pyrosgen.proof.modeltext import parse_model_text

    m = load_model(LANDSHARK)
    text = model_text(m).replace("period_ms 20\n", "period_ms 40\n").replace(
        "/landshark/gps_velocity landshark_gps_velocity subscribe geometry_msgs/TwistStamped 1",
        "/landshark/gps_velocity landshark_gps_velocity subscribe geometry_msgs/TwistStamped 3")
    cpp = wrapper.render_wrapper(m, parse_model_text(text))[wrapper.wrapper_files(m).api_source]
    assert "ros::Rate(ros::Duration(0.04))" in cpp and '"/landshark/gps_velocity", 3, f);' in cpp
    check_wrapper(cpp, text, wrapper_name="w")
    with pytest.raises(WrapperMismatch):
        check_wrapper(cpp, model_text(m), wrapper_name="w")
    # the same proved model as the front end's: the same wrapper as before
    assert wrapper.render_wrapper(m, parse_model_text(model_text(m))) == wrapper.render_wrapper(m)

"""The wrapper's ROS time (``ros_now``), as the proof's environment model
assumes it, and the ROS functions the glue declares against the wrapper's
header (pyrosgen.verify.wrapper_check).

- every rendered wrapper (with or without subscriptions) defines
  ``ros_now`` (and ``ros_time_sec``/``ros_time_nsec``, the stamp's) and
  passes; its header declares ``unsigned long long ros_now(void);``
  whether or not the glue uses it;
- a wrapper whose time departs from the design is refused, each way:
  not set by ``ros_init``, set before ``ros::spinOnce()`` or not at all by
  ``ros_spinOnce``, a callback that sets it after the glue's callback or
  from the clock instead of the receipt time, or is registered without a
  ``ros::MessageEvent``, ``ros_now`` that reads the clock, an extra
  assignment, a second ``ros_now``,
  ``ros_time_sec``/``ros_time_nsec`` that read the clock, or swapped, or
  not the seconds and nanoseconds of the same time;
- the glue's prototypes of the ROS functions (as Coq prints them, e.g.
  ``unsigned long long ros_now(void);``) must be the header's: another
  result type, another parameter, a function the header lacks, refused.
"""

from __future__ import annotations

import pytest

import pyrosgen.ros.wrapper as wrapper
from pyrosgen.frontend.validate import load_model
from pyrosgen.proof.modeltext import model_text
from pyrosgen.verify.wrapper_check import WrapperMismatch, check_glue_externals, check_wrapper

from .conftest import LANDSHARK, MULTI, ROOT, assert_wrapper_refused

GOLDEN_GLUE = ROOT / "tests" / "generate" / "golden" / "landshark_controller_glue.c"

SPIN = "    ros::spinOnce();\n    g_now_ns = ros::Time::now().toNSec();\n"
CB_SET = "            g_now_ns = e.getReceiptTime().toNSec();\n"
CB_CALL = "            cb(&c);\n"

MUTATIONS = {
    "ros_init without the time": ("    g_now_ns = ros::Time::now().toNSec();\n    g_rate = new", "    g_rate = new"),
    "ros_init sets it before the node handle": (
        "    g_nh = new ros::NodeHandle();\n    g_now_ns = ros::Time::now().toNSec();\n",
        "    g_now_ns = ros::Time::now().toNSec();\n    g_nh = new ros::NodeHandle();\n"),
    "spin without the time": (SPIN, "    ros::spinOnce();\n"),
    "time read before the spin": (SPIN, "    g_now_ns = ros::Time::now().toNSec();\n    ros::spinOnce();\n"),
    "ros_now reads the clock": ("    return g_now_ns;\n", "    return ros::Time::now().toNSec();\n"),
    "ros_now in wall time": (SPIN, "    ros::spinOnce();\n    g_now_ns = ros::WallTime::now().toNSec();\n"),
    "callback: clock instead of receipt time": (CB_SET, "            g_now_ns = ros::Time::now().toNSec();\n"),
    "callback: time set after the glue's callback": (
        CB_SET + "            struct geometry_msgs_TwistStamped c;\n"
        "            std::memset(&c, 0, sizeof c);\n"
        "            to_c(*e.getConstMessage(), &c);\n" + CB_CALL,
        "            struct geometry_msgs_TwistStamped c;\n"
        "            std::memset(&c, 0, sizeof c);\n"
        "            to_c(*e.getConstMessage(), &c);\n" + CB_CALL + CB_SET),
    "callback: no message event": (
        "    boost::function<void(const ros::MessageEvent<geometry_msgs::TwistStamped const> &)> f =\n"
        "        [cb](const ros::MessageEvent<geometry_msgs::TwistStamped const> &e) {\n"
        + CB_SET + "            struct geometry_msgs_TwistStamped c;\n"
        "            std::memset(&c, 0, sizeof c);\n"
        "            to_c(*e.getConstMessage(), &c);\n",
        "    boost::function<void(const geometry_msgs::TwistStamped::ConstPtr &)> f =\n"
        "        [cb](const geometry_msgs::TwistStamped::ConstPtr &m) {\n"
        "            struct geometry_msgs_TwistStamped c;\n"
        "            std::memset(&c, 0, sizeof c);\n"
        "            to_c(*m, &c);\n"),
    "extra assignment in ros_rate_sleep": ("    g_rate->sleep();\n", "    g_rate->sleep();\n    g_now_ns += 1;\n"),
    "time reset by ros_ok": ("    return ros::ok() ? 1 : 0;\n", "    g_now_ns = 0;\n    return ros::ok() ? 1 : 0;\n"),
    "time initialised to another value": ("unsigned long long g_now_ns = 0;\n", "unsigned long long g_now_ns = 5;\n"),
    "ros_time_sec from the clock": ("    return (unsigned int)(g_now_ns / 1000000000ULL);\n",
                                    "    return (unsigned int)ros::Time::now().sec;\n"),
    "ros_time_nsec: microseconds": ("    return (unsigned int)(g_now_ns % 1000000000ULL);\n",
                                    "    return (unsigned int)(g_now_ns % 1000000ULL);\n"),
    "ros_time_sec and nsec swapped": ("    return (unsigned int)(g_now_ns / 1000000000ULL);\n}\n\n"
                                      "unsigned int ros_time_nsec(void)\n{\n"
                                      "    return (unsigned int)(g_now_ns % 1000000000ULL);\n",
                                      "    return (unsigned int)(g_now_ns % 1000000000ULL);\n}\n\n"
                                      "unsigned int ros_time_nsec(void)\n{\n"
                                      "    return (unsigned int)(g_now_ns / 1000000000ULL);\n"),
    "a second ros_now": ("int ros_ok(void)\n", "unsigned long long ros_now2(void) { return ros_now(); }\n\nint ros_ok(void)\n"),
}


def _landshark():
    m = load_model(LANDSHARK)
    return m, wrapper.render_wrapper(m)


@pytest.mark.parametrize("path", [LANDSHARK, MULTI], ids=["landshark", "multi"])
def test_rendered_wrappers_define_ros_now(path):
    m = load_model(path)
    files = wrapper.render_wrapper(m)
    names = wrapper.wrapper_files(m)
    cpp, h = files[names.api_source], files[names.api_header]
    assert "\nunsigned long long ros_now(void);\n" in h
    assert "\nunsigned int ros_time_sec(void);\nunsigned int ros_time_nsec(void);\n" in h
    assert "\nunsigned long long ros_now(void)\n{\n    return g_now_ns;\n}\n" in cpp
    check_wrapper(cpp, model_text(m), wrapper_name="w.cpp")


def test_a_node_without_subscriptions_has_ros_now():
    """The wrapper provides ros_now whatever the glue uses: here for a
    proved model that only publishes (LandShark's without its inputs)."""
    from pyrosgen.proof.modeltext import parse_model_text

    m = load_model(LANDSHARK)
    text = "\n".join(ln for ln in model_text(m).splitlines()
                     if " subscribe " not in ln and not ln.startswith("input_relation ")) + "\n"
    cpp = wrapper.render_wrapper(m, parse_model_text(text))[wrapper.wrapper_files(m).api_source]
    assert "\nvoid ros_subscribe_" not in cpp
    assert "\nunsigned long long ros_now(void)\n{\n    return g_now_ns;\n}\n" in cpp
    check_wrapper(cpp, text, wrapper_name="w.cpp")


@pytest.mark.parametrize("name", sorted(MUTATIONS))
def test_wrapper_time_mutation_is_refused(name):
    m, files = _landshark()
    assert_wrapper_refused(files[wrapper.wrapper_files(m).api_source], *MUTATIONS[name], model_text(m))


def test_comments_do_not_count():
    """A comment that mentions an assignment is not one."""
    m, files = _landshark()
    cpp = files[wrapper.wrapper_files(m).api_source]
    cpp = cpp.replace("void ros_rate_sleep(void)\n{\n",
                      "void ros_rate_sleep(void)\n{\n    // g_now_ns = 0; would break ros_now()\n", 1)
    check_wrapper(cpp, model_text(m), wrapper_name="w.cpp")


def _glue_with_now(proto: str = "unsigned long long ros_now(void);") -> str:
    glue = GOLDEN_GLUE.read_text()
    anchor = "void ros_spinOnce(void);\n"
    assert anchor in glue
    return glue.replace(anchor, anchor + proto + "\n", 1)


def test_glue_externals_agree_with_the_header():
    m, files = _landshark()
    h = files[wrapper.wrapper_files(m).api_header]
    # the glue as printed today (no ros_now) and with ros_now as Coq prints it
    check_glue_externals(GOLDEN_GLUE.read_text(), h, glue_name="g.c", header_name="h.h")
    check_glue_externals(_glue_with_now(), h, glue_name="g.c", header_name="h.h")


@pytest.mark.parametrize("proto, what", [
    ("int ros_now(void);", "int ros_now(void)"),
    ("unsigned int ros_now(void);", "unsigned int ros_now(void)"),
    ("long long ros_now(void);", "long long ros_now(void)"),
    ("unsigned long long ros_now(int);", "unsigned long long ros_now(int)"),
    ("unsigned long long ros_later(void);", "ros_later"),
])
def test_glue_externals_that_differ_are_refused(proto, what):
    m, files = _landshark()
    h = files[wrapper.wrapper_files(m).api_header]
    with pytest.raises(WrapperMismatch) as info:
        check_glue_externals(_glue_with_now(proto), h, glue_name="g.c", header_name="h.h")
    assert "does not declare the ROS functions as the glue calls them" in info.value.summary
    assert any(what in line for line in info.value.lines), info.value.lines


def test_header_without_ros_now_is_refused_for_a_glue_that_uses_it():
    m, files = _landshark()
    h = files[wrapper.wrapper_files(m).api_header].replace("unsigned long long ros_now(void);\n", "")
    check_glue_externals(GOLDEN_GLUE.read_text(), h, glue_name="g.c", header_name="h.h")
    with pytest.raises(WrapperMismatch) as info:
        check_glue_externals(_glue_with_now(), h, glue_name="g.c", header_name="h.h")
    assert "g.c declares ros_now, which h.h does not declare" in "\n".join(info.value.lines)


def test_glue_externals_other_functions():
    """A changed parameter of another ROS function is caught too."""
    m, files = _landshark()
    h = files[wrapper.wrapper_files(m).api_header]
    glue = GOLDEN_GLUE.read_text().replace(
        "void ros_publish_landshark_control_base_velocity(struct geometry_msgs_TwistStamped *);",
        "void ros_publish_landshark_control_base_velocity(struct geometry_msgs_Twist *);")
    with pytest.raises(WrapperMismatch):
        check_glue_externals(glue, h, glue_name="g.c", header_name="h.h")

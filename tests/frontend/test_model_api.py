"""The typed model built from the LandShark example and from ok_multi.yaml."""

from __future__ import annotations

import dataclasses

import pytest

from pyrosgen import (
    Controller,
    ControllerField,
    FieldPath,
    InputRelation,
    IOStruct,
    NodeModel,
    OutputRelation,
    Topic,
    load_model,
)

from support.frontend import LANDSHARK, MULTI, REPO


@pytest.fixture(scope="module")
def landshark() -> NodeModel:
    return load_model(LANDSHARK)


@pytest.fixture(scope="module")
def multi() -> NodeModel:
    return load_model(MULTI)


def test_landshark_is_table_1(landshark):
    m = landshark
    assert m.name == "landshark_controller"
    assert m.period_ms == 20
    assert m.controller == Controller(
        name="Controller",
        inputs=IOStruct(
            "Controller_U",
            "ExtU_Controller_T",
            (
                ControllerField("In1", "float64"),
                ControllerField("In2", "float64"),
                ControllerField("In3", "float64"),
            ),
        ),
        outputs=IOStruct("Controller_Y", "ExtY_Controller_T", (ControllerField("Out1", "float64"),)),
    )
    assert m.controller.step_fn == "Controller_step"
    assert m.controller.initialize_fn == "Controller_initialize"
    assert [(t.name, t.c_name, t.direction, t.msg_type, t.queue_size) for t in m.topics] == [
        ("/landshark/left_wheel_velocity", "landshark_left_wheel_velocity", "subscribe", "geometry_msgs/TwistStamped", 1),
        ("/landshark/right_wheel_velocity", "landshark_right_wheel_velocity", "subscribe", "geometry_msgs/TwistStamped", 1),
        ("/landshark/gps_velocity", "landshark_gps_velocity", "subscribe", "geometry_msgs/TwistStamped", 1),
        ("/landshark_control/base_velocity", "landshark_control_base_velocity", "publish", "geometry_msgs/TwistStamped", 1),
    ]
    x = FieldPath(("twist", "linear", "x"), "float64")
    assert [(r.topic.name, r.path, r.input_field) for r in m.input_relations] == [
        ("/landshark/left_wheel_velocity", x, "In1"),
        ("/landshark/right_wheel_velocity", x, "In2"),
        ("/landshark/gps_velocity", x, "In3"),
    ]
    assert [(r.output_field, r.topic.name, r.path) for r in m.output_relations] == [
        ("Out1", "/landshark_control/base_velocity", x)
    ]
    assert [t.name for t in m.messages] == [
        "time",
        "std_msgs/Header",
        "geometry_msgs/Vector3",
        "geometry_msgs/Twist",
        "geometry_msgs/TwistStamped",
    ]
    assert m.msg_paths == ()
    assert m.source == LANDSHARK


def test_topic_derived_names(landshark):
    t = landshark.topic("/landshark/left_wheel_velocity")
    assert t.msg_var == "landshark_left_wheel_velocity_msg"
    assert t.callback == "landshark_left_wheel_velocity_callback"
    assert t.subscribe_fn == "ros_subscribe_landshark_left_wheel_velocity"
    assert t.msg_struct == "geometry_msgs_TwistStamped"
    assert t.is_subscribed and not t.is_published
    p = landshark.topic("/landshark_control/base_velocity")
    assert p.output_glue == "output_glue_landshark_control_base_velocity"
    assert p.advertise_fn == "ros_advertise_landshark_control_base_velocity"
    assert p.publish_fn == "ros_publish_landshark_control_base_velocity"
    assert p.cmd_var == "landshark_control_base_velocity_cmd"
    assert landshark.subscribed == landshark.topics[:3]
    assert landshark.published == landshark.topics[3:]
    with pytest.raises(KeyError):
        landshark.topic("/nope")


def test_positions_are_kept(landshark):
    # Relations and topics remember where they were written (1-based).
    text = LANDSHARK.read_text().splitlines()
    for r in landshark.input_relations:
        assert r.input_field in text[r.pos.line - 1]
        assert text[r.pos.line - 1][r.pos.col - 1] == "{"
    for t in landshark.topics:
        assert t.name in text[t.pos.line - 1]
    # ... but positions do not take part in equality.
    r = landshark.input_relations[0]
    assert dataclasses.replace(r, pos=(0, 0)) == r


def test_model_is_immutable(landshark):
    with pytest.raises(dataclasses.FrozenInstanceError):
        landshark.name = "x"  # type: ignore[misc]
    with pytest.raises(dataclasses.FrozenInstanceError):
        landshark.topics[0].queue_size = 3  # type: ignore[misc]
    with pytest.raises(dataclasses.FrozenInstanceError):
        landshark.messages[0].fields = ()  # type: ignore[misc]
    assert isinstance(landshark.topics, tuple)
    assert isinstance(landshark.controller.inputs.fields, tuple)
    hash(landshark.topics[0])
    hash(landshark.input_relations[0])


def test_loading_twice_gives_equal_models(landshark):
    assert load_model(LANDSHARK) == landshark


def test_multi(multi):
    m = multi
    assert m.name == "multi_node" and m.period_ms == 10
    assert m.controller.inputs.var_name == "Fusion_U"
    assert m.controller.inputs.struct_name == "ExtU_Fusion_T"
    assert m.controller.outputs.struct_name == "ExtY_Fusion_T"
    u = {f.name: f.prim for f in m.controller.inputs.fields}
    assert u["OdomSeq"] == "uint32" and u["EStop"] == "bool" and u["FrontRange"] == "float32"
    assert m.controller.inputs.field("EStop").c_type == "unsigned char"
    assert m.controller.inputs.field("EStop").simulink_type == "boolean_T"
    assert len(m.subscribed) == 4 and len(m.published) == 2
    rel = m.input_relation("YawVar")
    assert isinstance(rel, InputRelation)
    assert rel.topic.name == "/odom" and str(rel.path) == "pose.covariance[35]"
    assert rel.path.steps == ("pose", "covariance", 35)
    assert str(m.input_relation("HoldSec").path) == "hold_time.sec"
    assert m.input_relation("HoldSec").path.prim == "int32"
    assert m.input_relation("RangeType").path.prim == "uint8"
    # Every controller input is fed exactly once.
    assert sorted(r.input_field for r in m.input_relations) == sorted(m.controller.inputs.names)
    # One output feeds several fields; Debug feeds none.
    status = m.output_relations_of("/fusion/status")
    assert [str(r.path) for r in status if r.output_field == "WheelCmd"] == [
        "wheel_speeds[0]",
        "wheel_speeds[1]",
        "wheels[1].velocity",
    ]
    assert all(isinstance(r, OutputRelation) for r in status)
    assert "Debug" not in {r.output_field for r in m.output_relations}
    names = [t.name for t in m.messages]
    for t in m.messages:
        for f in t.fields:
            if f.kind == "msg":
                assert names.index(f.msg) < names.index(t.name)
    assert "duration" in names and "robot_msgs/WheelState" in names
    assert len(m.leaf_paths("nav_msgs/Odometry")) == 88
    assert m.message("robot_msgs/EStop").c_name == "robot_msgs_EStop"
    assert m.msg_paths == ((MULTI.parent.parent / "msgs").resolve(),)


def test_example_copy_of_multi_is_the_same_model(multi):
    other = load_model(REPO / "examples" / "multi" / "multi_node.yaml")
    assert dataclasses.replace(other, source=multi.source, msg_paths=multi.msg_paths) == multi
    for name in ("EStop", "FusionStatus", "WheelState"):
        a = (REPO / "examples/multi/msg/robot_msgs/msg" / f"{name}.msg").read_text()
        b = (MULTI.parent.parent / "msgs/robot_msgs/msg" / f"{name}.msg").read_text()
        assert a == b


def test_topic_is_a_plain_value():
    t = Topic("/a/b", "a_b", "publish", "std_msgs/Float64", 3)
    assert t.derived_names() == (
        "a_b_msg",
        "a_b_callback",
        "output_glue_a_b",
        "ros_subscribe_a_b",
        "ros_advertise_a_b",
        "ros_publish_a_b",
        "a_b_cmd",
    )

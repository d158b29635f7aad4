"""The message-type layer on real ROS 1 Noetic types and on custom .msg files."""

from __future__ import annotations

from pathlib import Path

import pytest

from pyrosgen.errors import InvalidNodeModel
from pyrosgen.frontend.msgmodel import C_TYPES, DURATION, PRIMITIVES, SIMULINK_TYPES, TIME, FieldPath, leaf_count, leaf_paths, msg_c_name
from pyrosgen.frontend.msgload import MsgRegistry, PathError

from support.frontend import HERE

CUSTOM = HERE / "msgs"


@pytest.fixture(scope="module")
def reg() -> MsgRegistry:
    r = MsgRegistry()
    assert r.add_msg_dir(CUSTOM) == 3
    assert r.diagnostics == []
    return r


def fields(reg, name):
    t = reg.carried(name)
    assert t is not None
    return [(f.name, f.kind, f.prim or f.msg, f.array_len) for f in t.fields]


def leaves(reg, name):
    reg.used_types([name])
    return [(str(p), p.prim) for p in leaf_paths(name, reg.messages())]


# --------------------------------------------------------------------------
# Primitive table (DESIGN.md section 4)


def test_c_type_table_is_the_design_table():
    assert PRIMITIVES == (
        "bool", "int8", "uint8", "int16", "uint16", "int32", "uint32",
        "int64", "uint64", "float32", "float64",
    )
    assert C_TYPES == {
        "bool": "unsigned char",
        "int8": "signed char",
        "uint8": "unsigned char",
        "int16": "short",
        "uint16": "unsigned short",
        "int32": "int",
        "uint32": "unsigned int",
        "int64": "long long",
        "uint64": "unsigned long long",
        "float32": "float",
        "float64": "double",
    }
    assert SIMULINK_TYPES["bool"] == "boolean_T"
    assert SIMULINK_TYPES["float32"] == "real32_T"
    assert SIMULINK_TYPES["float64"] == "real_T"


def test_time_and_duration_pseudo_types():
    assert (TIME.name, TIME.c_name) == ("time", "ros_time")
    assert [(f.name, f.prim) for f in TIME.fields] == [("sec", "uint32"), ("nsec", "uint32")]
    assert (DURATION.name, DURATION.c_name) == ("duration", "ros_duration")
    assert [(f.name, f.prim) for f in DURATION.fields] == [("sec", "int32"), ("nsec", "int32")]
    assert TIME.is_pseudo and TIME.cpp_name == "ros::Time"
    assert msg_c_name("time") == "ros_time"
    assert msg_c_name("duration") == "ros_duration"
    assert msg_c_name("geometry_msgs/TwistStamped") == "geometry_msgs_TwistStamped"


# --------------------------------------------------------------------------
# Standard types


def test_twist_stamped(reg):
    assert fields(reg, "geometry_msgs/TwistStamped") == [
        ("header", "msg", "std_msgs/Header", None),
        ("twist", "msg", "geometry_msgs/Twist", None),
    ]
    # Header: frame_id (a string) is dropped; stamp is the time pseudo type.
    assert fields(reg, "std_msgs/Header") == [
        ("seq", "prim", "uint32", None),
        ("stamp", "msg", "time", None),
    ]
    assert leaves(reg, "geometry_msgs/TwistStamped") == [
        ("header.seq", "uint32"),
        ("header.stamp.sec", "uint32"),
        ("header.stamp.nsec", "uint32"),
        ("twist.linear.x", "float64"),
        ("twist.linear.y", "float64"),
        ("twist.linear.z", "float64"),
        ("twist.angular.x", "float64"),
        ("twist.angular.y", "float64"),
        ("twist.angular.z", "float64"),
    ]
    t = reg.carried("geometry_msgs/TwistStamped")
    assert t.c_name == "geometry_msgs_TwistStamped"
    assert t.cpp_name == "geometry_msgs::TwistStamped"
    assert t.package == "geometry_msgs" and t.short_name == "TwistStamped"


def test_odometry_nested_with_fixed_arrays(reg):
    assert fields(reg, "nav_msgs/Odometry") == [
        ("header", "msg", "std_msgs/Header", None),
        ("pose", "msg", "geometry_msgs/PoseWithCovariance", None),
        ("twist", "msg", "geometry_msgs/TwistWithCovariance", None),
    ]  # child_frame_id (string) dropped
    assert fields(reg, "geometry_msgs/PoseWithCovariance") == [
        ("pose", "msg", "geometry_msgs/Pose", None),
        ("covariance", "prim", "float64", 36),
    ]
    ls = leaves(reg, "nav_msgs/Odometry")
    assert len(ls) == 3 + (3 + 4 + 36) + (6 + 36)
    assert ("pose.covariance[35]", "float64") in ls
    assert ("pose.covariance[36]", "float64") not in ls
    assert ls.index(("pose.covariance[0]", "float64")) + 35 == ls.index(("pose.covariance[35]", "float64"))
    assert ("pose.pose.orientation.w", "float64") in ls
    assert ("twist.covariance[0]", "float64") in ls
    assert not any("frame_id" in p for p, _ in ls)


def test_imu(reg):
    assert [f[0] for f in fields(reg, "sensor_msgs/Imu")] == [
        "header",
        "orientation",
        "orientation_covariance",
        "angular_velocity",
        "angular_velocity_covariance",
        "linear_acceleration",
        "linear_acceleration_covariance",
    ]
    assert leaf_count("sensor_msgs/Imu", reg.messages()) == 3 + 4 + 9 + 3 + 9 + 3 + 9
    assert len(leaves(reg, "sensor_msgs/Imu")) == 40


def test_range_float32_uint8(reg):
    assert fields(reg, "sensor_msgs/Range") == [
        ("header", "msg", "std_msgs/Header", None),
        ("radiation_type", "prim", "uint8", None),
        ("field_of_view", "prim", "float32", None),
        ("min_range", "prim", "float32", None),
        ("max_range", "prim", "float32", None),
        ("range", "prim", "float32", None),
    ]
    t = reg.carried("sensor_msgs/Range")
    assert t.field("range").c_type == "float"
    assert t.field("radiation_type").c_type == "unsigned char"
    assert t.field("header").c_type == "struct std_msgs_Header"


def test_float64_and_aliases(reg):
    assert fields(reg, "std_msgs/Float64") == [("data", "prim", "float64", None)]
    # ROS 1 aliases: char is uint8, byte is int8.
    assert fields(reg, "std_msgs/Char") == [("data", "prim", "uint8", None)]
    assert fields(reg, "std_msgs/Byte") == [("data", "prim", "int8", None)]
    assert fields(reg, "std_msgs/Time") == [("data", "msg", "time", None)]
    assert fields(reg, "std_msgs/Duration") == [("data", "msg", "duration", None)]


def test_types_that_carry_nothing(reg):
    for name in ("std_msgs/String", "std_msgs/Empty", "diagnostic_msgs/KeyValue"):
        assert reg.raw(name) is not None
        assert reg.carried(name) is None
        assert not reg.is_broken(name)
    # Of a MultiArray only layout.data_offset survives (dim[] and data[] are
    # variable-length arrays).
    assert leaves(reg, "std_msgs/Float64MultiArray") == [("layout.data_offset", "uint32")]


def test_variable_length_arrays_are_dropped(reg):
    # JointState: header + name[] + position[] + velocity[] + effort[]
    assert fields(reg, "sensor_msgs/JointState") == [("header", "msg", "std_msgs/Header", None)]
    # LaserScan keeps its scalars, drops ranges[] and intensities[].
    names = [f[0] for f in fields(reg, "sensor_msgs/LaserScan")]
    assert "ranges" not in names and "intensities" not in names
    assert "angle_min" in names and "range_max" in names


def test_every_standard_type_is_consistent(reg):
    """For every ROS 1 Noetic type shipped by rosbags: leaf_count agrees with
    leaf_paths, and every leaf path resolves back to its own primitive."""
    checked = 0
    for name in reg.known_names():
        t = reg.carried(name)
        assert not reg.is_broken(name), name
        if t is None:
            continue
        assert t.fields
        used = reg.used_types([name])
        assert used[-1] == t
        seen = set()
        for u in used:  # dependency order
            for f in u.fields:
                if f.kind == "msg":
                    assert f.msg in seen, (name, f)
            seen.add(u.name)
        paths = leaf_paths(t, reg.messages())
        assert len(paths) == leaf_count(t, reg.messages())
        for p in paths:
            assert reg.walk_path(name, str(p)) == p
        checked += 1
    assert checked > 100


# --------------------------------------------------------------------------
# Custom .msg files


def test_custom_estop(reg):
    assert fields(reg, "robot_msgs/EStop") == [
        ("header", "msg", "std_msgs/Header", None),
        ("engaged", "prim", "bool", None),
        ("source", "prim", "uint8", None),
        ("hold_time", "msg", "duration", None),
    ]  # reason (string) and history (float32[]) dropped
    assert ("hold_time.sec", "int32") in leaves(reg, "robot_msgs/EStop")


def test_custom_nested_array_of_messages(reg):
    assert fields(reg, "robot_msgs/FusionStatus") == [
        ("header", "msg", "std_msgs/Header", None),
        ("yaw_variance", "prim", "float64", None),
        ("stopped", "prim", "bool", None),
        ("odom_seq", "prim", "uint32", None),
        ("wheel_speeds", "prim", "float32", 4),
        ("wheels", "msg", "robot_msgs/WheelState", 2),
    ]
    assert fields(reg, "robot_msgs/WheelState") == [
        ("velocity", "prim", "float32", None),
        ("current", "prim", "float32", None),
        ("temperature", "prim", "int16", None),
    ]
    ls = leaves(reg, "robot_msgs/FusionStatus")
    assert len(ls) == 3 + 1 + 1 + 1 + 4 + 2 * 3
    assert ls[-3:] == [
        ("wheels[1].velocity", "float32"),
        ("wheels[1].current", "float32"),
        ("wheels[1].temperature", "int16"),
    ]
    names = [m.name for m in reg.used_types(["robot_msgs/FusionStatus"])]
    assert names.index("robot_msgs/WheelState") < names.index("robot_msgs/FusionStatus")
    assert names.index("time") < names.index("std_msgs/Header")


def write_msgs(tmp_path: Path, files: dict[str, str | bytes]) -> Path:
    for rel, text in files.items():
        p = tmp_path / rel
        p.parent.mkdir(parents=True, exist_ok=True)
        if isinstance(text, bytes):
            p.write_bytes(text)
        else:
            p.write_text(text)
    return tmp_path


def test_custom_dropped_kinds(tmp_path):
    root = write_msgs(
        tmp_path,
        {
            "kinds/msg/All.msg": (
                "string<=10 bounded_string\n"
                "float64[<=5] bounded_array\n"
                "string[3] strings\n"
                "geometry_msgs/Point[] points\n"
                "geometry_msgs/Point[2] two_points\n"
                "Empty0[4] empties\n"
                "char c\n"
                "byte b\n"
                "time t\n"
                "int64 CONSTANT=5\n"
                "uint64 big\n"
            ),
            "kinds/msg/Empty0.msg": "# nothing\n",
        },
    )
    r = MsgRegistry()
    assert r.add_msg_dir(root) == 2
    assert r.diagnostics == []
    assert fields(r, "kinds/All") == [
        ("two_points", "msg", "geometry_msgs/Point", 2),
        ("c", "prim", "uint8", None),
        ("b", "prim", "int8", None),
        ("t", "msg", "time", None),
        ("big", "prim", "uint64", None),
    ]
    assert r.carried("kinds/Empty0") is None
    with pytest.raises(PathError, match="variable-length array"):
        r.walk_path("kinds/All", "bounded_array[0]")
    with pytest.raises(PathError, match="is a string"):
        r.walk_path("kinds/All", "bounded_string")
    with pytest.raises(PathError, match="is a string"):
        r.walk_path("kinds/All", "strings[1]")
    with pytest.raises(PathError, match="carries no field"):
        r.walk_path("kinds/All", "empties[0].x")
    with pytest.raises(PathError, match="no field 'CONSTANT'"):
        r.walk_path("kinds/All", "CONSTANT")
    assert r.walk_path("kinds/All", "two_points[1].z") == FieldPath(("two_points", 1, "z"), "float64")


def test_custom_same_as_standard_is_accepted(tmp_path):
    # Redefining a standard type identically is harmless.
    root = write_msgs(tmp_path, {"std_msgs/msg/Float64.msg": "float64 data\n"})
    r = MsgRegistry()
    r.add_msg_dir(root)
    assert r.diagnostics == []
    assert fields(r, "std_msgs/Float64") == [("data", "prim", "float64", None)]


def test_custom_errors_name_the_msg_file(tmp_path):
    root = write_msgs(
        tmp_path,
        {
            "p/msg/Bin.msg": b"float64 x\x00\n",
            "p/msg/Ctl.msg": "float64 x\x07\n",
            "p/msg/Ok.msg": "float64 x\nq/Missing m\n",
        },
    )
    r = MsgRegistry()
    r.add_msg_dir(root)
    msgs = {Path(d.file).name: d for d in r.diagnostics}
    assert "NUL byte" in msgs["Bin.msg"].message
    assert "non-printable" in msgs["Ctl.msg"].message
    assert r.carried("p/Ok") is None and r.is_broken("p/Ok")
    d = [d for d in r.diagnostics if d.file.endswith("Ok.msg")]
    assert len(d) == 1 and d[0].line == 2 and "unknown message type 'q/Missing'" in d[0].message


def test_too_many_msg_files(tmp_path, monkeypatch):
    import pyrosgen.frontend.msgload as mt  # where the limit is applied

    monkeypatch.setattr(mt, "MAX_MSG_FILES", 2)
    root = write_msgs(tmp_path, {f"p/msg/T{i}.msg": "float64 x\n" for i in range(3)})
    with pytest.raises(InvalidNodeModel, match="more than 2 .msg files"):
        MsgRegistry().add_msg_dir(root)


# --------------------------------------------------------------------------
# Field paths


def test_field_path_rendering_and_c_access(reg):
    p = reg.walk_path("nav_msgs/Odometry", "pose.covariance[35]")
    assert p == FieldPath(("pose", "covariance", 35), "float64")
    assert str(p) == "pose.covariance[35]"
    assert p.c_type == "double"
    assert p.c_access("odom_msg") == "odom_msg.pose.covariance[35]"
    assert p.c_access("msg", arrow=True) == "msg->pose.covariance[35]"
    q = reg.walk_path("robot_msgs/FusionStatus", "wheels[1].velocity")
    assert str(q) == "wheels[1].velocity" and q.prim == "float32"
    assert q.c_access("m", arrow=True) == "m->wheels[1].velocity"
    assert reg.walk_path("geometry_msgs/TwistStamped", "header.stamp.nsec").prim == "uint32"
    assert reg.walk_path("robot_msgs/EStop", "hold_time.nsec").prim == "int32"


@pytest.mark.parametrize(
    "path, fragment",
    [
        ("pose.covariance[36]", "out of range"),
        ("pose.covariance", "is an array (float64[36])"),
        ("pose.covariance.x", "e.g. 'pose.covariance[0].x'"),
        ("pose[0]", "is not an array"),
        ("child_frame_id", "is a string"),
        ("header.frame_id", "is a string"),
        ("pose.pose", "whole sub-message (geometry_msgs/Pose)"),
        ("header", "whole sub-message (std_msgs/Header)"),
        ("pose.pose.position.x.y", "it has no field 'y'"),
        ("pose.pose.positio.x", "did you mean 'position'?"),
        ("", "is empty"),
        ("a..b", "malformed"),
        ("a.", "malformed"),
        (".a", "malformed"),
        ("pose.covariance[1][2]", "malformed"),
        ("pose.covariance[ 1]", "malformed"),
        ("pose.covariance[1234567890]", "malformed"),
        ("pose.covariance[0x1]", "malformed"),
        ("pose/pose", "malformed"),
    ],
)
def test_bad_paths(reg, path, fragment):
    with pytest.raises(PathError) as info:
        reg.walk_path("nav_msgs/Odometry", path)
    assert fragment in info.value.args[0]


def test_type_name_checks(reg):
    assert reg.check_type_name("geometry_msgs/TwistStamped") is None
    assert reg.check_type_name("robot_msgs/EStop") is None
    assert "did you mean 'geometry_msgs/Twist'" in reg.check_type_name("geometry_msgs/Twst")
    assert "did you mean 'std_msgs/Header'" in reg.check_type_name("Header")
    assert "not of the form package/Type" in reg.check_type_name("time")
    assert "not of the form package/Type" in reg.check_type_name("a/b/c/d")
    # rosbags' ROS 2 builtin types are not ROS 1 message types.
    assert "unknown message type" in reg.check_type_name("builtin_interfaces/Time")


@pytest.mark.parametrize("depth", [31, 40, 1100])
def test_deeply_nested_custom_messages(tmp_path, depth):
    from pyrosgen.frontend.msgmodel import MAX_MSG_DEPTH

    files = {f"p/msg/M{i}.msg": f"M{i + 1} next\nfloat64 v\n" for i in range(depth - 1)}
    files[f"p/msg/M{depth - 1}.msg"] = "float64 v\n"
    root = write_msgs(tmp_path, files)
    r = MsgRegistry()
    r.add_msg_dir(root)
    t = r.carried("p/M0")
    if depth <= MAX_MSG_DEPTH:
        assert t is not None and r.diagnostics == []
        assert leaf_count(t, r.messages()) == depth
        assert str(leaf_paths(t, r.messages())[0]) == ".".join(["next"] * (depth - 1) + ["v"])
    else:
        assert t is None and r.is_broken("p/M0")
        assert len(r.diagnostics) == 1
        assert f"nested more than {MAX_MSG_DEPTH} levels deep" in r.diagnostics[0].message
        assert r.diagnostics[0].line == 1

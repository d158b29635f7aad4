"""The ament_cmake package of a ROS 2 node (``pyrosgen build --ros2``,
DESIGN.md section 5, "The ROS 2 package").

``OUT/<package>/`` holds what a ROS 2 user builds with colcon:

- ``package.xml`` (format 3: ``ament_cmake`` as build tool, a ``<depend>``
  on rcl, rcutils, rmw, rosidl_runtime_c and each message package the
  node's structs use, rosgraph_msgs (``/clock``) and builtin_interfaces
  included; ``<build_type>ament_cmake</build_type>``);
- ``CMakeLists.txt``: with ament_cmake, ``find_package`` of each and the
  modern ``<pkg>::<pkg>__rosidl_typesupport_c`` targets; without it (the
  wheels of the Python package index have no ament_cmake), a fallback
  branch that takes the wheels' prefix from ``-DPYROSGEN_ROS2_PREFIX=`` or
  the environment and links as :func:`pyrosgen.ros2.build.link_flags`
  does; the same sources and flags as ``build --ros2``, the layout check as
  a build step; the node installed to ``lib/<package>``, the launch file to
  ``share/<package>/launch``;
- ``launch/<node>.launch.xml`` (ROS 2's XML launch format): arguments
  ``use_sim_time``, ``ns`` and one remapping per topic, as the ROS 1
  launch file offers them;
- copies of the glue, the rcl wrapper, the layout check, the headers
  (``src/``, ``include/``) and the controller (``controller/``).

The three text files are rendered from the proved node
(:func:`pyrosgen.ros.wrapper.proved_node`) and the build record
(:func:`pyrosgen.ros.wrapper.package_record`, kept in the manifest as
``build.package``), so that ``pyrosgen verify`` renders them again
(:mod:`pyrosgen.verify.package_check`).
"""

from __future__ import annotations

import re

from pyrosgen.frontend.model import NodeModel
from pyrosgen.render import render, source_label
from pyrosgen.ros import wrapper as ros
from pyrosgen.ros2.wrapper import message_packages

__all__ = ["ROS_PACKAGES", "RESERVED_NAMES", "ros2_message_packages", "ros2_package_paths", "render_ros2_package",
           "render_ros2_msg_package", "render_ros2_package_record"]

#: The entries of a ``build --ros2`` folder that a custom message package's
#: folder (``OUT/<pkg>/``, next to the node's package) cannot take.
RESERVED_NAMES = ("bin", "controller", "lib", "obj", "python", "rosidl")

#: The ROS 2 packages every node is built on (its C libraries).
ROS_PACKAGES = ("rcl", "rcutils", "rmw", "rosidl_runtime_c")


def ros2_message_packages(model: NodeModel | ros.ProvedNode) -> list[str]:
    """The message packages a node links: those of its structs, and
    rosgraph_msgs (``/clock`` under ``use_sim_time``) with
    builtin_interfaces (its stamp)."""
    return sorted({*message_packages(model), "rosgraph_msgs", "builtin_interfaces"})


def ros2_package_paths(model: NodeModel | ros.ProvedNode) -> dict[str, str]:
    """Package-relative paths of the node package's sources (the keys of
    :func:`pyrosgen.ros.wrapper.catkin_paths`)."""
    paths = ros.catkin_paths(model)
    n = model.name
    return {**paths, "wrapper": f"src/{n}_rcl.c", "launch": f"launch/{n}.launch.xml"}


def render_ros2_package(model: NodeModel | ros.ProvedNode, include_dirs: list[str],
                        controller: ros.CatkinController, maintainer: str = ros.DEFAULT_MAINTAINER,
                        custom_pkgs: list[str] = ()) -> dict[str, str]:
    """``package.xml``, ``CMakeLists.txt`` and ``launch/<node>.launch.xml``
    of the node's ament_cmake package, by package-relative path; the
    controller's sources under ``controller/`` compiled as ``build --ros2``
    compiles them.  ``custom_pkgs``: the node's custom message packages
    (:func:`render_ros2_msg_package`, written next to it), whose libraries
    the package finds, without ament_cmake, in the ``build --ros2`` folder
    that holds it."""
    who = ros.check_package_words(include_dirs, controller, maintainer)
    msg_pkgs = ros2_message_packages(model)
    custom = sorted(custom_pkgs)
    for p in custom:
        ros._check_ident(p)
        if p not in msg_pkgs:
            raise ValueError(f"custom_pkgs: {p!r} is not a message package of the node")
    for t in model.topics:
        ros._check_ident(t.c_name)
    ctx = {
        "source": source_label(model.source.name),
        "package": ros.catkin_package_name(model),
        "node": model,
        "ros_pkgs": list(ROS_PACKAGES),
        "msg_pkgs": msg_pkgs,
        "installed_msg_pkgs": [p for p in msg_pkgs if p not in custom],
        "custom_pkgs": custom,
        "include_dirs": include_dirs,
        "controller": controller,
        "glue_cflags": ros.GLUE_CFLAGS,
        "ieee_cflags": ros.IEEE_CFLAGS if controller.generated else (),
        "topics": list(model.topics),
        "maintainer_name": who[0],
        "maintainer_email": who[1],
        **ros2_package_paths(model),
    }
    return {
        "package.xml": render("ros2_package.xml.j2", **ctx),
        "CMakeLists.txt": render("ros2_CMakeLists.txt.j2", **ctx),
        ctx["launch"]: render("ros2_node.launch.xml.j2", **ctx),
    }


def render_ros2_msg_package(source: str, node: str, pkg: str, msgs: dict[str, str],
                            maintainer: str = ros.DEFAULT_MAINTAINER) -> dict[str, str]:
    """``package.xml`` and ``CMakeLists.txt`` of the ROS 2 interface package
    ``pkg`` (``rosidl_generate_interfaces``; without ament_cmake, nothing to
    build: ``build --ros2`` compiled its messages) whose ``.msg`` files are
    ``msgs`` (file name -> text), a custom message package of node ``node``;
    ``source``: the model file's name."""
    from pyrosgen.ros2.rosidl import msg_dependencies

    ros._check_ident(pkg)
    ros._check_ident(node)
    for m in msgs:
        if not re.fullmatch(r"[A-Za-z][A-Za-z0-9_]*\.msg", m):
            raise ValueError(f"refusing to print {m!r} in CMakeLists.txt")
    deps = sorted(msg_dependencies(pkg, [msgs[m] for m in sorted(msgs)]))
    for d in deps:
        ros._check_ident(d)
    who = ros.parse_maintainer(maintainer)
    if who is None:
        raise ValueError(f"refusing to print {maintainer!r} as a maintainer")
    ctx = {"source": source_label(source), "package": pkg, "node": node, "deps": deps, "msgs": sorted(msgs),
           "maintainer_name": who[0], "maintainer_email": who[1]}
    return {"package.xml": render("ros2_msg_package.xml.j2", **ctx),
            "CMakeLists.txt": render("ros2_msg_CMakeLists.txt.j2", **ctx)}


def render_ros2_package_record(node: ros.ProvedNode, record: object) -> dict[str, str]:
    """:func:`render_ros2_package` of ``node`` with the recorded ``record``
    (:func:`pyrosgen.ros.wrapper.package_record`, its ``custom_pkgs`` the
    node's custom message packages); ``ValueError`` naming the field if it
    is not one."""
    ctl = ros.controller_of_record(record)
    assert isinstance(record, dict)
    return render_ros2_package(node, record["include_dirs"], ctl, record["maintainer"], record["custom_pkgs"])

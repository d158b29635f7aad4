"""``pyrosgen build MODEL.yaml --ros2 [--controller DIR] -o OUT``: a ROS 2
node over rcl, from the same model and the same proved glue as the ROS 1
build (:mod:`pyrosgen.ros.build`).

The steps (each one progress line):

1. front end: the ROS 2 installation (:func:`pyrosgen.ros2.env.find_ros2`,
   exit 2 naming ``make ros2-deps`` when missing), the model read with ROS
   2's message definitions (:func:`pyrosgen.ros2.frontend.load_model_ros2`,
   rule 4.17), the controller folder;
2. generate: the pipeline of :mod:`pyrosgen.generate` (coqc proves the
   node's DDC theorem on the ROS 2 message structs, Coq prints the C), or
   the previous build's proof in ``OUT`` when nothing it is made from
   changed (:func:`pyrosgen.ros.build.prove`, the target in its key);
3. wrapper: the C API over rcl rendered from the model Coq printed
   (:func:`pyrosgen.ros2.wrapper.render_rcl_wrapper`), held to it by
   :func:`pyrosgen.ros2.wrapper.check_rcl_wrapper` and the glue's externals
   by the ROS 1 build's check; the topics' QoS (rule 4.18) from the model
   file, read by the front end and again by :mod:`pyrosgen.nversion.qos`,
   written as the record ``<node>.qos`` that the wrapper check holds the
   wrapper to;
4. layout check: the controller header against the structs Coq printed;
   the ament_cmake package ``OUT/<package>/`` (:mod:`pyrosgen.ros2.package`:
   ``package.xml``, ``CMakeLists.txt``, ``launch/<node>.launch.xml`` and
   copies of the sources), rendered from the proved model and the build
   record kept in the manifest (``build.package``), which ``verify``
   renders again;
5. compile the glue: the ROS 1 build's flags (``gcc -std=c11 -O2 -Wall
   -Wextra -Werror -pedantic``);
6. compile the controller, as the ROS 1 build does;
7. compile the wrapper: the glue's flags, ``-I`` every
   ``<prefix>/include/<pkg>`` of the installation;
8. link ``bin/<node>`` against rcl, rcutils, rmw, rosidl_runtime_c and the
   message packages' rosidl libraries, with libpython3.11 (librcl loads a
   ``rosidl_generator_py`` library that needs it) and a DT_RPATH to
   ``<prefix>/lib`` and every ``site-packages/ros_*.libs`` folder (the
   wheels' own RPATHs point nowhere once installed); write ``<node>.target``
   (the target, covered by the certificate) and the certificate; install.

Steps 5 to 8 are the ROS 1 build's (:class:`pyrosgen.ros.build.NodeCompiler`):
reproducible commands recorded in the manifest (``build.commands``, which
``verify --rebuild`` runs again), objects and the binary reused from the
previous build when their inputs are unchanged.  Nothing partial:
everything is built in a staging folder and moved into ``OUT`` only when
every step succeeded (the ROS 1 build's installer).
"""

from __future__ import annotations

import shutil
import sys
import tempfile
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

from pyrosgen.frontend.model import NodeModel
from pyrosgen.generate import GenerateResult
from pyrosgen.proof.coqmodel import node_file_names
from pyrosgen.ros import layout
from pyrosgen.ros import wrapper as ros
from pyrosgen.ros.build import (
    BuildError, ControllerOptions, NodeCompiler, _Cache, _compiler_identity, _existing_ancestor, _shown_argv, _tool,
    check_build_request, controller_setup, copy_package_sources, find_controller, finish_build, prove, proved_node_of,
    write_wrapper,
)
from pyrosgen.ros2.env import Ros2Install, find_ros2
from pyrosgen.ros2.frontend import load_model_ros2
from pyrosgen.ros2.package import (RESERVED_NAMES, ROS_PACKAGES, render_ros2_msg_package, render_ros2_package_record,
                                   ros2_message_packages, ros2_package_paths)
from pyrosgen.ros2.rosidl import build_custom_types, custom_packages
from pyrosgen.ros2.wrapper import (Ros2WrapperMismatch, check_rcl_wrapper, parse_qos_text, qos_file_name, qos_text,
                                   render_rcl_wrapper, ros2_wrapper_files)
from pyrosgen.nversion.qos import check_qos_record

__all__ = ["STEPS", "TARGET_TEXT", "Ros2BuildResult", "build_ros2", "link_flags"]

STEPS = 8
#: What ``<node>.target`` says (the certificate covers it).
TARGET_TEXT = "target: ros2 (ROS 2 Kilted, rcl, rmw_fastrtps_cpp)\n"
PYTHON_LIB = f"python{sys.version_info.major}.{sys.version_info.minor}"


@dataclass
class Ros2BuildResult:
    model: NodeModel
    out_dir: Path
    binary: Path
    generated: GenerateResult
    files: list[tuple[Path, bool]]
    warnings: list[str] = field(default_factory=list)
    times: dict[str, float] = field(default_factory=dict)
    steps: list[tuple[str, bool]] = field(default_factory=list)


def compile_flags(inst: Ros2Install) -> list[str]:
    return [a for d in inst.include_dirs() for a in ("-I", str(d))]


def link_flags(inst: Ros2Install, model: NodeModel | ros.ProvedNode) -> list[str]:
    """The libraries of a node and where it finds them at run time (one
    ``-Wl,-rpath`` a folder, as ``verify --rebuild`` reads them)."""
    libs = [f"-l{p}" for p in ROS_PACKAGES]
    # rosgraph_msgs: /clock under use_sim_time (builtin_interfaces: its stamp)
    for pkg in ros2_message_packages(model):
        libs += [f"-l{pkg}__rosidl_typesupport_c", f"-l{pkg}__rosidl_generator_c"]
    return ["-L", str(inst.lib_dir), "-Wl,--disable-new-dtags", *(f"-Wl,-rpath,{p}" for p in inst.library_path()),
            *libs, "-Wl,--no-as-needed", f"-l{PYTHON_LIB}", "-Wl,--as-needed"]


def build_ros2(model_path: str | Path, controller_dir: str | Path | None, out_dir: str | Path, *,
               progress: Callable[[str], None] | None = None, keep_work: bool = False, driver=None,
               wp: bool = False, options: ControllerOptions | None = None,
               install: Ros2Install | None = None) -> Ros2BuildResult:
    """Build the ROS 2 node of the model file ``model_path``; see the module
    documentation.  Raises what :func:`pyrosgen.ros.build.build`
    raises, and :class:`pyrosgen.ros2.env.Ros2Missing` (exit 2)."""
    say = progress or (lambda _line: None)
    t_start = time.monotonic()
    times: dict[str, float] = {}
    say(f"[1/{STEPS}] front end: reading {model_path} for the target ros2")
    inst = install or find_ros2()
    model = load_model_ros2(model_path, inst)
    out_dir, opts, diagram = check_build_request(model, out_dir, controller_dir, options)
    check_custom_package_names(model)
    ctl = find_controller(model, controller_dir) if not diagram else None
    times["front end"] = time.monotonic() - t_start
    base = _existing_ancestor(out_dir.parent if out_dir.name else out_dir)
    try:
        work = Path(tempfile.mkdtemp(prefix=f".pyrosgen-build-{model.name}-", dir=str(base)))
    except OSError as exc:
        raise BuildError(f"cannot create a work directory in {base}: {exc.strerror or exc}") from None
    try:
        (work / "out").mkdir()
        gen, installed, warnings, steps = _build_in(model, ctl, opts, diagram, inst, out_dir, work, say,
                                                          times, keep_work=keep_work, driver=driver, wp=wp)
    finally:
        if keep_work:
            say(f"work directory kept: {work}")
        else:
            shutil.rmtree(work, ignore_errors=True)
    times["total"] = time.monotonic() - t_start
    return Ros2BuildResult(model=model, out_dir=out_dir, binary=out_dir / "bin" / model.name, generated=gen,
                           files=installed, warnings=warnings, times=times, steps=steps)


def _build_in(model, ctl, opts, diagram, inst, out_dir, work, say, times, *, keep_work, driver, wp):
    """Steps 2 to 8 in ``work/out``, then installed into ``out_dir``."""
    stage = work / "out"
    node = model.name
    names = ros2_wrapper_files(model)
    glue_c, check_c = f"{node}_glue.c", f"{node}_layout_check.c"
    cc, cxx = _tool("CC", "gcc"), _tool("CXX", "g++")
    t = time.monotonic()
    cache = _Cache(out_dir)
    gen = prove(model, out_dir, stage, cache, say, keep_work=keep_work, driver=driver, wp=wp,
                msg_root=inst.share_dir, target="ros2", steps=STEPS)
    times["generate"] = time.monotonic() - t
    types_h = (stage / names.types_header).read_text(encoding="ascii")
    # the wrapper, the layout check and the package files are rendered from
    # the proved model alone (verify renders them again from it)
    proved, pnode = proved_node_of(gen, model)
    if diagram:
        cdir = work / "controller"
        cdir.mkdir()
        (cdir / f"{model.controller.name}.c").write_bytes((stage / node_file_names(node).controller_c).read_bytes())
        (cdir / layout.controller_header_name(model)).write_text(
            layout.render_reference_header(pnode, types_h), encoding="ascii")
        ctl = find_controller(model, cdir)
    assert ctl is not None
    warnings, user_includes, ctl_includes = controller_setup(model, ctl, opts)

    # 3. the rcl wrapper, from the model Coq printed; the controller's copy
    say(f"[3/{STEPS}] wrapper: C API over rcl ({names.api_source})")
    t = time.monotonic()
    # rule 4.18: the QoS record, read twice (front end, nversion), the wrapper held to it
    qos_record = qos_text(model)
    check_qos_record(model.source, qos_record, what="the front end's QoS record")
    (stage / qos_file_name(node)).write_text(qos_record, encoding="utf-8")
    try:  # the record read back, as verify renders the wrapper from it
        qos = parse_qos_text(qos_record, proved)
    except ValueError as exc:
        raise Ros2WrapperMismatch(f"{qos_file_name(node)} does not fit the proved model", [f"  {exc}"]) from None
    write_wrapper(stage, glue_c, names.api_header, names.api_source, render_rcl_wrapper(pnode, proved, qos=qos),
                  lambda text, fname: check_rcl_wrapper(text, gen.proved_model, wrapper_name=fname,
                                                        qos_record=qos_record))
    (stage / "controller").mkdir()
    for p in ctl.files:
        dest = stage / "controller" / ctl.rel(p)
        dest.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(p, dest)
    times["wrapper"] = time.monotonic() - t

    # 4. layout check, and the ament_cmake package
    say(f"[4/{STEPS}] layout check: {ctl.header.name} against {names.types_header}")
    t = time.monotonic()
    (stage / check_c).write_text(layout.render_layout_check(pnode, types_h, names.types_header), encoding="ascii")
    layout_cmds = layout.check_layout(model, stage / check_c, ctl.path, work, types_h, cc=cc,
                                      shown_check=str(out_dir / check_c), includes=ctl_includes)
    package = write_ros2_package(pnode, stage, ctl, opts, user_includes, {
        "glue": stage / glue_c, "wrapper": stage / names.api_source, "layout_check": stage / check_c,
        "types_header": stage / names.types_header, "api_header": stage / names.api_header}, generated=diagram,
        model=model)
    times["layout check"] = time.monotonic() - t

    steps: list[tuple[str, bool]] = []
    cc_id, cxx_id = _compiler_identity(cc), _compiler_identity(cxx)
    ref = str(work / "layout-reference")
    comp = NodeCompiler(stage, out_dir, ctl, cache, say, warnings, steps, commands=[
        ["layout-reference" + a[len(ref):] if a == ref or a.startswith(ref + "/") else a
         for a in _shown_argv(c, stage, ctl.path)] for c in layout_cmds])
    # 5. glue
    t = time.monotonic()
    comp.compile(5, "compile glue", cc, cc_id, [*ros.GLUE_CFLAGS, "-I", str(stage)], stage / glue_c,
                 f"{node}_glue.o", [stage / names.types_header], user=False)
    times["glue"] = time.monotonic() - t
    # 6. controller
    t = time.monotonic()
    comp.compile_controller(6, (cc, cc_id), (cxx, cxx_id), opts, ctl_includes, generated=diagram)
    times["controller"] = time.monotonic() - t
    # 7. wrapper (and the custom messages' code, from rosidl's generators)
    t = time.monotonic()
    custom = build_custom_types(model, inst, stage, cc=cc, cxx=cxx, say=lambda line: say(f"[7/{STEPS}] {line}"))
    if custom:
        times["rosidl"], t = time.monotonic() - t, time.monotonic()
    comp.compile(7, "compile wrapper", cc, cc_id, [*ros.GLUE_CFLAGS, "-I", str(stage),
                                                   *(custom.compile_flags if custom else ()), *compile_flags(inst)],
                 stage / names.api_source, f"{node}_rcl.o", [stage / names.types_header, stage / names.api_header],
                 user=False)
    times["wrapper compile"] = time.monotonic() - t
    # 8. link, target, certificate, install
    t = time.monotonic()
    linker = cxx if any(s.suffix in (".cpp", ".cc", ".cxx") for s in ctl.sources) else cc
    comp.link(8, model, linker, cxx_id if linker is cxx else cc_id, ["-pthread", *opts.ldflags],
              [*(custom.link_flags if custom else ()), *link_flags(inst, pnode), *opts.libs, "-lm"],
              own_libs=(*ROS_PACKAGES, PYTHON_LIB))
    (stage / f"{node}.target").write_text(TARGET_TEXT, encoding="ascii")
    installed = finish_build(gen, node, stage, out_dir, work, cache, say,
                             {"target": "ros2", "package": package, "commands": comp.commands}, STEPS)
    times["link and install"] = time.monotonic() - t
    return gen, installed, warnings, steps


def check_custom_package_names(model: NodeModel) -> None:
    """A custom message package's interface package is written next to the
    node's (``OUT/<pkg>/``): its name cannot be the node package's nor an
    entry of the build folder (:data:`RESERVED_NAMES`); a user error (rule
    4.17) naming the package's folder."""
    from pyrosgen.errors import Diagnostic, InvalidNodeModel

    taken = {ros.catkin_package_name(model): "the node's package", **{n: "a folder of the build"
                                                                       for n in RESERVED_NAMES}}
    problems = [Diagnostic(str(files[0].parent.parent), None, None,
                           f"the custom message package {pkg!r} takes the name of {taken[pkg]} ({pkg}/ in the "
                           "output folder, next to its interface package): rename the package (target ros2)",
                           rule="4.17")
                for pkg, files in custom_packages(model).items() if pkg in taken]
    if problems:
        raise InvalidNodeModel(problems)


def write_ros2_package(node: ros.ProvedNode, stage: Path, ctl, opts: ControllerOptions, user_includes: list[str],
                       sources: dict[str, Path], generated: bool, model: NodeModel | None = None) -> dict:
    """Write the node's ament_cmake package into ``stage/<package>/``
    (:mod:`pyrosgen.ros2.package`) and, for each custom message package of
    the front end's ``model``, its interface package ``stage/<pkg>/``
    (``package.xml``, ``CMakeLists.txt``, ``msg/``); return the record they
    are rendered from (the manifest's ``build.package``)."""
    pkg_dir = stage / ros.catkin_package_name(node)
    include_dirs, controller = copy_package_sources(pkg_dir, ros2_package_paths(node), sources, ctl, opts,
                                                    user_includes, generated)
    custom = custom_packages(model) if model is not None else {}
    record = ros.package_record(include_dirs, controller, sorted(custom), opts.maintainer)
    for rel, text in render_ros2_package_record(node, record).items():
        dest = pkg_dir / rel
        dest.parent.mkdir(parents=True, exist_ok=True)
        dest.write_text(text, encoding="utf-8")
    for pkg, files in sorted(custom.items()):
        (stage / pkg / "msg").mkdir(parents=True)
        msgs = {}
        for f in files:
            shutil.copyfile(f, stage / pkg / "msg" / f.name)
            msgs[f.name] = (stage / pkg / "msg" / f.name).read_text(encoding="utf-8", errors="replace")
        for rel, text in render_ros2_msg_package(model.source.name, node.name, pkg, msgs, opts.maintainer).items():
            (stage / pkg / rel).write_text(text, encoding="utf-8")
    return record

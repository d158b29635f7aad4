"""``pyrosgen build MODEL.yaml --ros2 [--controller DIR] -o OUT``: a ROS 2
node over rcl, from the same model and the same proved glue as the ROS 1
build (:mod:`pyrosgen.ros.build`).

The steps (each one progress line):

1. front end: the ROS 2 installation (:func:`pyrosgen.ros2.env.find_ros2`,
   exit 2 naming ``make ros2-deps`` when missing), the model read with ROS
   2's message definitions (:func:`pyrosgen.ros2.frontend.load_model_ros2`,
   rule 4.17), the controller folder;
2. generate: the pipeline of :mod:`pyrosgen.generate` (coqc proves the
   node's DDC theorem on the ROS 2 message structs, Coq prints the C);
3. wrapper: the C API over rcl rendered from the model Coq printed
   (:func:`pyrosgen.ros2.wrapper.render_rcl_wrapper`), held to it by
   :func:`pyrosgen.ros2.wrapper.check_rcl_wrapper` and the glue's externals
   by the ROS 1 build's check; the topics' QoS (rule 4.18) from the model
   file, read by the front end and again by :mod:`pyrosgen.nversion.qos`,
   written as the record ``<node>.qos`` that the wrapper check holds the
   wrapper to;
4. layout check: the controller header against the structs Coq printed;
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

Nothing partial: everything is built in a staging folder and moved into
``OUT`` only when every step succeeded (the ROS 1 build's installer).
"""

from __future__ import annotations

import re
import shutil
import sys
import tempfile
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

from pyrosgen.frontend.model import NodeModel
from pyrosgen.generate import GenerateResult, generate_model
from pyrosgen.proof.coqmodel import node_file_names
from pyrosgen.proof.modeltext import parse_model_text
from pyrosgen.ros import layout
from pyrosgen.ros.wrapper import IEEE_CFLAGS
from pyrosgen.ros.build import (
    CONTROLLER_CFLAGS, CONTROLLER_CXXFLAGS, CXX_SUFFIXES, GLUE_CFLAGS, BuildError, BuildToolError,
    ControllerError, ControllerOptions, check_build_request, _all_files, _clip, _existing_ancestor, _install, _run, _tool,
    find_controller,
)
from pyrosgen.ros2.env import Ros2Install, find_ros2
from pyrosgen.ros2.frontend import load_model_ros2
from pyrosgen.ros2.rosidl import build_custom_types
from pyrosgen.ros2.wrapper import (Ros2WrapperMismatch, check_rcl_wrapper, message_packages, parse_qos_text,
                                   qos_file_name, qos_text, render_rcl_wrapper, ros2_wrapper_files)
from pyrosgen.nversion.qos import check_qos_record
from pyrosgen.verify.certificate import certificate_files, write_certificate
from pyrosgen.verify.wrapper_check import check_glue_externals

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


def compile_flags(inst: Ros2Install) -> list[str]:
    return [a for d in inst.include_dirs() for a in ("-I", str(d))]


def link_flags(inst: Ros2Install, model: NodeModel) -> list[str]:
    """The libraries of a node and where it finds them at run time."""
    rpath = ":".join(str(p) for p in inst.library_path())
    libs = ["-lrcl", "-lrcutils", "-lrmw", "-lrosidl_runtime_c"]
    # rosgraph_msgs: /clock under use_sim_time (builtin_interfaces: its stamp)
    for pkg in sorted({*message_packages(model), "rosgraph_msgs", "builtin_interfaces"}):
        libs += [f"-l{pkg}__rosidl_typesupport_c", f"-l{pkg}__rosidl_generator_c"]
    return ["-L", str(inst.lib_dir), "-Wl,--disable-new-dtags", f"-Wl,-rpath,{rpath}", *libs,
            "-Wl,--no-as-needed", f"-l{PYTHON_LIB}", "-Wl,--as-needed"]


def build_ros2(model_path: str | Path, controller_dir: str | Path | None, out_dir: str | Path, *,
               progress: Callable[[str], None] | None = None, keep_work: bool = False, driver=None,
               wp: bool = False, options: ControllerOptions | None = None,
               install: Ros2Install | None = None) -> Ros2BuildResult:
    """Build the ROS 2 node of the model file ``model_path``; see the
    module documentation.  Raises what :func:`pyrosgen.ros.build.build`
    raises, and :class:`pyrosgen.ros2.env.Ros2Missing` (exit 2)."""
    say = progress or (lambda _line: None)
    t_start = time.monotonic()
    times: dict[str, float] = {}
    say(f"[1/{STEPS}] front end: reading {model_path} for the target ros2")
    inst = install or find_ros2()
    model = load_model_ros2(model_path, inst)
    out_dir, opts, diagram = check_build_request(model, out_dir, controller_dir, options)
    ctl = find_controller(model, controller_dir) if not diagram else None
    cc, cxx = _tool("CC", "gcc"), _tool("CXX", "g++")
    names = ros2_wrapper_files(model)
    node = model.name
    glue_c = f"{node}_glue.c"
    check_c = f"{node}_layout_check.c"
    times["front end"] = time.monotonic() - t_start

    base = _existing_ancestor(out_dir.parent if out_dir.name else out_dir)
    try:
        work = Path(tempfile.mkdtemp(prefix=f".pyrosgen-build-{node}-", dir=str(base)))
    except OSError as exc:
        raise BuildError(f"cannot create a work directory in {base}: {exc.strerror or exc}") from None
    stage = work / "out"
    warnings: list[str] = []

    def shown(text: str) -> str:
        return text.replace(str(stage), str(out_dir))

    def run_compiler(argv: list[str], what: str, src: Path, user: bool) -> None:
        r = _run(argv, what, cwd=stage)
        if r.returncode != 0:
            msg = _clip(shown(r.stderr + r.stdout))
            if user:
                raise ControllerError(f"{src}: error: the controller source does not compile "
                                      f"({argv[0]} exit status {r.returncode})", msg.splitlines())
            raise BuildToolError(f"{argv[0]} failed on generated code {out_dir / src.name} "
                                 f"(exit status {r.returncode})", msg.splitlines())
        if user and (r.stderr.strip() or r.stdout.strip()):
            warnings.extend(_clip(r.stderr + r.stdout).splitlines())

    try:
        stage.mkdir()
        t = time.monotonic()

        def sub(line: str) -> None:
            say(f"[2/{STEPS}] generate: " + re.sub(r"^\[\d+/\d+\] ", "", line).replace(str(stage), str(out_dir)))

        gen = generate_model(model, stage, progress=sub, keep_work=keep_work, driver=driver, wp=wp,
                             msg_root=inst.share_dir, target="ros2")
        times["generate"] = time.monotonic() - t
        types_h = (stage / names.types_header).read_text(encoding="ascii")
        if diagram:
            cdir = work / "controller"
            cdir.mkdir()
            (cdir / f"{model.controller.name}.c").write_bytes(
                (stage / node_file_names(node).controller_c).read_bytes())
            (cdir / layout.controller_header_name(model)).write_text(
                layout.render_reference_header(model, types_h), encoding="ascii")
            ctl = find_controller(model, cdir)
        assert ctl is not None
        warnings += [f"pyrosgen: note: {p}: left out of the build: {why}" for p, why in ctl.left_out]
        user_includes = [str(Path(i) if Path(i).is_absolute() else (ctl.path / i).absolute()) for i in opts.includes]
        ctl_includes = [a for inc in ctl.include_dirs for a in ("-I", str(inc.absolute()))] + \
            [a for inc in user_includes for a in ("-I", inc)]

        # 3. the rcl wrapper, from the model Coq printed
        say(f"[3/{STEPS}] wrapper: C API over rcl ({names.api_source})")
        t = time.monotonic()
        proved = parse_model_text(gen.proved_model)
        # rule 4.18: the QoS record, read twice (front end, nversion), the wrapper held to it
        qos_record = qos_text(model)
        check_qos_record(model_path, qos_record, what="the front end's QoS record")
        (stage / qos_file_name(node)).write_text(qos_record, encoding="utf-8")
        try:  # the record read back, as verify renders the wrapper from it
            qos = parse_qos_text(qos_record, proved)
        except ValueError as exc:
            raise Ros2WrapperMismatch(f"{qos_file_name(node)} does not fit the proved model", [f"  {exc}"]) from None
        for fname, text in render_rcl_wrapper(model, proved, qos=qos).items():
            if fname == names.api_source:
                check_rcl_wrapper(text, gen.proved_model, wrapper_name=fname, qos_record=qos_record)
            if fname == names.api_header:
                check_glue_externals((stage / glue_c).read_text(encoding="utf-8"), text,
                                     glue_name=glue_c, header_name=fname)
            (stage / fname).write_text(text, encoding="ascii")
        (stage / "controller").mkdir()
        for p in ctl.files:
            dest = stage / "controller" / ctl.rel(p)
            dest.parent.mkdir(parents=True, exist_ok=True)
            shutil.copyfile(p, dest)
        times["wrapper"] = time.monotonic() - t

        # 4. layout check
        say(f"[4/{STEPS}] layout check: {ctl.header.name} against {names.types_header}")
        t = time.monotonic()
        (stage / check_c).write_text(layout.render_layout_check(model, types_h, names.types_header), encoding="ascii")
        layout.check_layout(model, stage / check_c, ctl.path, work, types_h, cc=cc,
                            shown_check=str(out_dir / check_c), includes=ctl_includes)
        times["layout check"] = time.monotonic() - t

        obj = work / "obj"
        obj.mkdir()
        objects: list[Path] = []
        # 5. glue
        t = time.monotonic()
        say(f"[5/{STEPS}] compile glue: {' '.join(cc)} {glue_c}")
        o = obj / f"{node}_glue.o"
        run_compiler([*cc, *GLUE_CFLAGS, "-I", str(stage), "-c", str(stage / glue_c), "-o", str(o)],
                     f"compiling {glue_c}", stage / glue_c, user=False)
        objects.append(o)
        times["glue"] = time.monotonic() - t
        # 6. controller
        t = time.monotonic()
        for src in ctl.sources:
            cxx_src = src.suffix in CXX_SUFFIXES
            flags = ([*CONTROLLER_CXXFLAGS, *opts.cxxflags] if cxx_src else
                     [f"-std={opts.std}", *CONTROLLER_CFLAGS, *opts.cflags,
                      *(IEEE_CFLAGS if diagram else ())]) + ctl_includes
            o = obj / ("controller_" + ctl.rel(src).replace("/", "__").rsplit(".", 1)[0] + ".o")
            tool = cxx if cxx_src else cc
            say(f"[6/{STEPS}] compile controller: {' '.join(tool)} {src.name}")
            run_compiler([*tool, *flags, "-c", str(src.absolute()), "-o", str(o)],
                         f"compiling {src.name}", ctl.path / ctl.rel(src), user=True)
            objects.append(o)
        times["controller"] = time.monotonic() - t
        # 7. wrapper (and the custom messages' code, from rosidl's generators)
        t = time.monotonic()
        custom = build_custom_types(model, inst, stage, cc=cc, cxx=cxx, say=lambda line: say(f"[7/{STEPS}] {line}"))
        if custom:
            times["rosidl"], t = time.monotonic() - t, time.monotonic()
        say(f"[7/{STEPS}] compile wrapper: {' '.join(cc)} {names.api_source}")
        o = obj / f"{node}_rcl.o"
        run_compiler([*cc, *GLUE_CFLAGS, "-I", str(stage), *(custom.compile_flags if custom else ()),
                      *compile_flags(inst), "-c", str(stage / names.api_source),
                      "-o", str(o)], f"compiling {names.api_source}", stage / names.api_source, user=False)
        objects.append(o)
        times["wrapper compile"] = time.monotonic() - t
        # 8. link, target, certificate, install
        t = time.monotonic()
        (stage / "bin").mkdir()
        binary = stage / "bin" / node
        linker = cxx if any(s.suffix in CXX_SUFFIXES for s in ctl.sources) else cc
        say(f"[8/{STEPS}] link: bin/{node}")
        argv = [*linker, "-pthread", *opts.ldflags, *(str(x) for x in objects), "-o", str(binary),
                *(custom.link_flags if custom else ()), *link_flags(inst, model), *opts.libs, "-lm"]
        r = _run(argv, f"linking {node}", cwd=stage)
        if r.returncode != 0:
            msg = _clip(shown(r.stderr + r.stdout))
            ctl_names = (model.controller.step_fn, model.controller.initialize_fn,
                         model.controller.inputs.var_name, model.controller.outputs.var_name)
            if any(f"undefined reference to `{n}'" in msg for n in ctl_names) or "cannot find -l" in msg \
                    and not any(f"cannot find -l{lib}" in msg for lib in ("rcl", "rcutils", "rmw", PYTHON_LIB)):
                raise ControllerError(f"{ctl.path}: error: the controller does not link", msg.splitlines())
            raise BuildToolError(f"linking {node} failed (exit status {r.returncode})", msg.splitlines())
        (stage / f"{node}.target").write_text(TARGET_TEXT, encoding="ascii")
        cert_files = set(certificate_files(node))
        covered = [f for f in _all_files(stage) if f not in cert_files]
        write_certificate(gen.record, stage, covered)
        (stage / STAMP_ROS2).write_text("\n".join(sorted(_all_files(stage) + [STAMP_ROS2])) + "\n",
                                        encoding="utf-8")
        say(f"[8/{STEPS}] installing into {out_dir}")
        old = _old_files(out_dir)
        installed = _install(stage, out_dir, old, work / "backup", on_wait=lambda: say(
            f"[8/{STEPS}] waiting for another pyrosgen run writing into {out_dir}"))
        times["link and install"] = time.monotonic() - t
    finally:
        if keep_work:
            say(f"work directory kept: {work}")
        else:
            shutil.rmtree(work, ignore_errors=True)
    times["total"] = time.monotonic() - t_start
    return Ros2BuildResult(model=model, out_dir=out_dir, binary=out_dir / "bin" / node, generated=gen,
                           files=installed, warnings=warnings, times=times)


#: The files the previous ROS 2 build installed (removed when no longer produced).
STAMP_ROS2 = ".pyrosgen-build-ros2.txt"


def _old_files(out_dir: Path) -> list[str]:
    try:
        return [line for line in (out_dir / STAMP_ROS2).read_text(encoding="utf-8").splitlines() if line]
    except OSError:
        return []

"""``pyrosgen verify`` of a ``build`` folder: every file that goes into
the node is rendered again from the proved model and compared byte for byte.

The re-print check (:mod:`pyrosgen.verify.recheck`) holds the top-level
glue and types header to what the proof prints.  This check holds the rest
of what ``pyrosgen build`` and ``catkin`` compile to the same source:

- the C API over roscpp, ``<node>_ros.h`` and ``<node>_ros.cpp``, and the
  layout check ``<node>_layout_check.c``: rendered again from the proved
  model alone (:func:`pyrosgen.ros.wrapper.proved_node`; the model text
  Coq printed, read back) and the printed types header, so that every
  behaviour of the wrapper is the reviewed template's;
- the catkin package ``<package>/``: its copies of the glue, the types
  header, the wrapper and the layout check are the top-level files;
  ``package.xml``, ``CMakeLists.txt`` and ``launch/<node>.launch`` are
  rendered again from the proved model and the manifest's ``build.package``
  record (sources, flags, include folders, maintainer); the package's copy
  of the controller is the top-level ``controller/``; the package holds no
  other file (listed in the manifest or not); each message package of
  custom messages is rendered again from its ``.msg`` files;
- a generated (block-diagram) controller: ``controller/<Controller>.c`` is
  the printed controller, ``controller/<Controller>.h`` the reference
  header rendered from the proved model; a hand-written controller is held
  by its recorded digests (the hashes check);
- each custom message's ``.msg``: it declares every field the proved model
  carries, with the proved type;
- the flags: the recorded compile commands compile the glue with
  ``GLUE_CFLAGS`` and a generated controller with ``-ffp-contract=off
  -fexcess-precision=standard`` and without any flag that changes
  floating-point semantics (:func:`pyrosgen.ros.build.check_flags`).

A folder of ``build --ros2`` (its ``<node>.target``) is checked the same
way (:func:`_check_node_files`, shared by both targets): the rcl wrapper
``<node>_rcl.c`` and its header, rendered again by
:func:`pyrosgen.ros2.wrapper.render_rcl_wrapper`, and the ament_cmake
package (:mod:`pyrosgen.ros2.package`) in place of the roscpp wrapper and
the catkin package; no custom message package.

Every file is read through :func:`pyrosgen.verify.folder.read_file` (a
relative name, a regular file, no link, bounded size).  The node binary is
held by its recorded digest only.
"""

from __future__ import annotations

import os
import re
import stat
from pathlib import Path

from pyrosgen.errors import PyrosgenError
from pyrosgen.proof.modeltext import MalformedModelText, parse_model_text
from pyrosgen.ros import layout
from pyrosgen.ros import wrapper as ros
from pyrosgen.verify.certificate import ProofRecord
from pyrosgen.verify.check import Check
from pyrosgen.verify.folder import read_file

__all__ = ["is_build_folder", "check_package"]


def is_build_folder(rec: ProofRecord, files: dict[str, str]) -> bool:
    """Whether the folder holds what ``pyrosgen build`` adds (a build
    record, a binary, a wrapper, a package): then :func:`check_package`
    must hold."""
    return rec.build is not None or any(
        n.startswith("bin/") or n.endswith(("_ros.cpp", "_ros.h", "_layout_check.c", "/package.xml",
                                            "/CMakeLists.txt")) for n in files)


class _Problems(list):
    compared = 0  #: files compared

    def add(self, name: str, why: str) -> None:
        self.append(f"  {name}: {why}")


def _read(folder: Path, name: str, problems: _Problems) -> bytes | None:
    try:
        return read_file(folder, name)
    except FileNotFoundError:
        problems.add(name, "missing")
    except PyrosgenError as exc:  # verify.folder.UnsafeFile
        problems.add(name, str(exc))
    except OSError as exc:
        problems.add(name, f"cannot read: {exc.strerror or exc}")
    return None


def _compare(folder: Path, files: dict[str, str], name: str, want: bytes | str | None, what: str,
             problems: _Problems) -> None:
    """``folder/name`` is covered by the manifest and equals ``want``."""
    if want is None:
        return
    if isinstance(want, str):
        want = want.encode("utf-8")
    problems.compared += 1
    if name not in files:
        problems.add(name, "not covered by the manifest")
    have = _read(folder, name, problems)
    if have is not None and have != want:
        a, b = have.decode("utf-8", "replace").splitlines(), want.decode("utf-8", "replace").splitlines()
        k = next((i for i in range(min(len(a), len(b))) if a[i] != b[i]), min(len(a), len(b)))
        problems.add(name, f"not {what} (line {k + 1}: {a[k] if k < len(a) else '(nothing)'!r}, "
                           f"rendered {b[k] if k < len(b) else '(nothing)'!r})")


def _check_commands(build: dict, package: dict, glue: str, generated: bool, problems: _Problems) -> None:
    """The recorded commands compile the glue with the glue's flags and a
    generated controller with the IEEE flags and no flag of
    :data:`pyrosgen.ros.build.FP_FLAGS`; the recorded controller flags pass
    :func:`pyrosgen.ros.build.check_flags`."""
    from pyrosgen.ros.build import CONTROLLER_CFLAGS, BuildError, ControllerOptions, check_flags, fp_flag_problem

    try:
        check_flags(ControllerOptions(std=package["std"], cflags=tuple(package["cflags"]),
                                      ldflags=tuple(package["ldflags"])), generated=generated)
    except BuildError as exc:
        problems.add("build.package", str(exc))
    cmds = build.get("commands")
    if not isinstance(cmds, list) or not all(isinstance(c, list) and all(isinstance(w, str) for w in c)
                                             for c in cmds):
        problems.add("build.commands", "not a list of commands")
        return
    compiled = {}
    for c in cmds:
        if "-c" in c and c.index("-c") + 1 < len(c):
            compiled.setdefault(c[c.index("-c") + 1], []).append(c)
    glue_cmds = compiled.get(glue, [])
    if len(glue_cmds) != 1:
        problems.add("build.commands", f"{len(glue_cmds)} commands compile {glue}, not one")
    for c in glue_cmds:
        if c[1:1 + len(ros.GLUE_CFLAGS)] != list(ros.GLUE_CFLAGS) or any(fp_flag_problem(w) for w in c[1:]):
            problems.add("build.commands", f"{glue} is not compiled with {' '.join(ros.GLUE_CFLAGS)} alone")
    if generated:
        for src, cs in compiled.items():
            if not src.startswith("controller/"):
                continue
            want = [f"-std={package['std']}", *CONTROLLER_CFLAGS, *package["cflags"], *ros.IEEE_CFLAGS]
            for c in cs:
                bad = [w for w in c[1:] if fp_flag_problem(w)]
                if bad or c[1:1 + len(want)] != want:
                    problems.add("build.commands", f"the generated controller {src} is not compiled with "
                                 f"{' '.join(ros.IEEE_CFLAGS)} after the user's flags"
                                 + (f" ({', '.join(bad)} refused)" if bad else ""))


#: The ROS 1 aliases of ``.msg`` files, as the front end reads them.
_MSG_ALIASES = {"char": "uint8", "byte": "int8"}
_MSG_FIELD = re.compile(r"^([A-Za-z][A-Za-z0-9_/]*)(\[([0-9]*)\])?\s+([A-Za-z][A-Za-z0-9_]*)$")


def _msg_fields(text: str) -> dict[str, tuple[str, str | None]]:
    """The fields of a ``.msg`` text: name -> (type, array suffix: ``None``,
    ``''`` for ``[]``, the length of ``[N]``); constants and comments left out."""
    out: dict[str, tuple[str, str | None]] = {}
    for line in text.splitlines():
        code = line.split("#", 1)[0].strip()
        if not code or "=" in code:
            continue
        m = _MSG_FIELD.match(" ".join(code.split()))
        if m:
            out[m.group(4)] = (_MSG_ALIASES.get(m.group(1), m.group(1)), m.group(3))
    return out


def _declared(pkg: str, struct: str) -> str:
    """The ``.msg`` spelling of the proved message struct ``struct`` (a field
    of a message of package ``pkg``): ``pkg/Type`` (or ``Type`` in ``pkg``),
    ``time``, ``duration``, ``string`` and ``T[]`` for the bounded structs."""
    from pyrosgen.frontend.msgmodel import bounded_type, is_bounded_type

    if is_bounded_type(struct):
        b = bounded_type(struct)
        if b.is_string:
            return "string"
        elem = b.seq_of[0]
        return f"{elem}[]"
    return ros._proved_msg_name(struct)


def _check_custom_msgs(folder: Path, files: dict[str, str], pm, custom_pkgs: list[str],
                       problems: "_Problems") -> None:
    """Each proved message of a custom package is declared by the folder's
    ``<pkg>/msg/<Type>.msg`` (what catkin's message_generation compiles)
    with every carried field, of the proved type: a field whose type the
    ``.msg`` changed would still compile (C++ converts ``double`` to
    ``float`` silently) and change what the node reads."""
    for struct, fields in pm.messages.items():
        name = ros._proved_msg_name(struct)
        pkg, _, typ = name.partition("/")
        if pkg not in custom_pkgs or not typ:
            continue
        msg_name = f"{pkg}/msg/{typ}.msg"
        if msg_name not in files:
            problems.add(msg_name, f"not covered by the manifest (the proved model carries {name})")
            continue
        data = _read(folder, msg_name, problems)
        if data is None:
            continue
        declared = _msg_fields(data.decode("utf-8", "replace"))
        for fname, ftype in fields:
            m = re.fullmatch(r"(?:array ([1-9][0-9]*) )?(?:msg (\w+)|(\w+))", ftype)
            if m is None:
                problems.add(msg_name, f"the proved field {fname} has type {ftype!r}")
                continue
            want = _declared(pkg, m.group(2)) if m.group(2) else m.group(3)
            if want.endswith("[]"):
                want_t, want_n = want[:-2], ""
            else:
                want_t, want_n = want, m.group(1)
            have_t, have_n = declared.get(fname, (None, None))
            if have_t is not None and "/" not in have_t and "/" in want_t:
                have_t = "std_msgs/Header" if have_t == "Header" else f"{pkg}/{have_t}"
            if (have_t, have_n) != (want_t, want_n):
                shown = "not declared" if have_t is None else \
                    f"declared {have_t}{'' if have_n is None else f'[{have_n}]'}"
                problems.add(msg_name, f"field {fname}: {shown}, the proved model carries "
                                       f"{want_t}{'' if want_n is None else f'[{want_n}]'}")


def _unexpected_files(folder: Path, pkg: str, expected: set[str], problems: "_Problems", limit: int = 50) -> None:
    """Every entry under ``folder/pkg`` that is not one of the ``expected``
    names (a file of the package catkin would see: a header added to
    ``include/`` would shadow a system header of the wrapper's) is a
    problem, whether the manifest lists it or not; links are not followed."""
    root = folder / pkg
    try:
        if not stat.S_ISDIR(os.lstat(root).st_mode):
            problems.add(pkg, "not a folder")
            return
    except OSError:
        problems.add(pkg, "missing")
        return
    found = 0
    for dirpath, dirnames, filenames in os.walk(root, followlinks=False):
        rel_dir = Path(dirpath).relative_to(folder).as_posix()
        for n in sorted(filenames + [d for d in dirnames if os.path.islink(os.path.join(dirpath, d))]):
            name = f"{rel_dir}/{n}"
            if name not in expected:
                problems.add(name, "not a file of the node's package (the package holds only what build writes)")
                found += 1
                if found >= limit:
                    return


def check_package(folder: str | Path, rec: ProofRecord, files: dict[str, str], proved_text: str | None):
    """The ``package`` check of a build folder (see the module
    documentation), as a :class:`pyrosgen.verify.check.Check`; ``None``
    for a folder of ``pyrosgen generate`` (:func:`is_build_folder`)."""

    folder = Path(folder)
    if not is_build_folder(rec, files):
        return None
    if proved_text is None:
        return Check("package", False, "not run: no proved model text")
    if f"{rec.node}.target" in files:
        return _check_ros2_folder(folder, rec, files, proved_text)
    build = rec.build
    if not isinstance(build, dict) or not isinstance(build.get("package"), dict):
        return Check("package", False, "the folder holds a build but the manifest has no build record "
                     "(build.package): its package cannot be rendered again")
    problems = _Problems()
    try:
        pm, node = _proved(proved_text, rec)
        names = ros.wrapper_files(node)
        package = build["package"]
        files_of = _NodeFiles(api=(names.api_header, names.api_source), wrapper=ros.render_wrapper(node),
                              paths=ros.catkin_paths(node), texts=ros.render_package_record(node, package))
    except (MalformedModelText, ValueError, KeyError, TypeError) as exc:
        return Check("package", False, f"cannot render the node's files again: {exc}")
    failed = _check_node_files(folder, rec, files, pm, node, build, files_of, problems)
    if failed is not None:
        return failed
    # the message packages of custom messages, from their .msg files
    for cpkg in package["custom_pkgs"]:
        msgs = {}
        for n in sorted(files):
            if n.startswith(f"{cpkg}/msg/") and n.count("/") == 2 and n.endswith(".msg"):
                data = _read(folder, n, problems)
                if data is not None:
                    msgs[n.rsplit("/", 1)[1]] = data.decode("utf-8", "replace")
        try:
            for rel, text in ros.render_msg_package(rec.source_name, cpkg, msgs).items():
                _compare(folder, files, f"{cpkg}/{rel}", text, "rendered from its .msg files", problems)
        except ValueError as exc:
            problems.add(cpkg, f"cannot render the message package again: {exc}")
    _check_custom_msgs(folder, files, pm, package["custom_pkgs"], problems)
    generated = rec.controller is not None
    if problems:
        return Check("package", False, f"{len(problems)} problems with the files of the node (rendered again "
                     "from the proved model and compared)",
                     list(problems))
    return Check("package", True, f"{problems.compared} files of the node rendered again from the proved model and equal; "
                 "the glue" + (" and the generated controller" if generated else "") + " compiled with "
                 + " ".join(ros.IEEE_CFLAGS))


def _proved(proved_text: str, rec: ProofRecord):
    """The proved model and node of the folder (``ValueError`` if its node
    is not the manifest's)."""
    pm = parse_model_text(proved_text, origin=rec.model_file)
    node = ros.proved_node(pm, rec.source_name)
    if node.name != rec.node:
        raise ValueError(f"the proved model's node is {node.name!r}, the manifest's {rec.node!r}")
    return pm, node


class _NodeFiles:
    """What a target renders from the proved node: the API header's and the
    wrapper's names (``api``), the wrapper files (``wrapper``, by name),
    the package's paths of the copies (``paths``) and the package's text
    files (``texts``, by package-relative path)."""

    def __init__(self, api: tuple[str, str], wrapper: dict[str, str], paths: dict[str, str],
                 texts: dict[str, str]):
        self.api, self.wrapper, self.paths, self.texts = api, wrapper, paths, texts


def _check_node_files(folder: Path, rec: ProofRecord, files: dict[str, str], pm, node, build: dict,
                      nf: _NodeFiles, problems: _Problems) -> Check | None:
    """What both targets' package checks compare: the wrapper and the
    layout check at the top, the node package's copies and text files, the
    controller (its copy, a generated one's source and header), no other
    file in the package, the recorded commands; a failed :class:`Check`
    if the layout check cannot be rendered again."""
    package = build["package"]
    generated = rec.controller is not None
    if package["generated"] != generated:
        return Check("package", False, "cannot render the node's files again: build.package.generated does not "
                     "say whether the controller is generated")
    names = ros.wrapper_files(node)
    glue = _read(folder, rec.glue_c, problems)
    types_raw = _read(folder, rec.types_h, problems)
    types_h = types_raw.decode("utf-8", "replace") if types_raw is not None else None
    try:
        check_c = layout.render_layout_check(node, types_h, names.types_header) if types_h is not None else None
        ref_h = layout.render_reference_header(node, types_h) if types_h is not None and generated else None
    except (PyrosgenError, ValueError) as exc:
        return Check("package", False, f"cannot render the layout check again: {exc}", list(problems))

    # the top-level files
    rendered = "rendered from the proved model"
    api_header, api_source = nf.api
    for name in nf.api:
        _compare(folder, files, name, nf.wrapper[name], rendered, problems)
    _compare(folder, files, f"{rec.node}_layout_check.c", check_c, rendered, problems)
    # the node's package
    pkg = ros.catkin_package_name(node)
    copies = {"glue": (glue, f"the top-level {rec.glue_c}"), "types_header": (types_raw, f"the top-level {rec.types_h}"),
              "wrapper": (nf.wrapper[api_source], rendered), "api_header": (nf.wrapper[api_header], rendered),
              "layout_check": (check_c, rendered)}
    for key, (want, what) in copies.items():
        _compare(folder, files, f"{pkg}/{nf.paths[key]}", want, what, problems)
    for rel, text in nf.texts.items():
        _compare(folder, files, f"{pkg}/{rel}", text, "rendered from the proved model and the build record", problems)
    # the controller: its package copy is the top-level one; a generated one is the proof's
    for name in sorted(files):
        if name.startswith("controller/"):
            _compare(folder, files, f"{pkg}/{name}", _read(folder, name, problems), f"the top-level {name}", problems)
    for src in [*package["c_sources"], *package["cxx_sources"]]:
        if src not in {n[len(pkg) + 1:] for n in files if n.startswith(pkg + "/controller/")}:
            problems.add(f"{pkg}/{src}", "a recorded controller source not covered by the manifest")
    if generated:
        c_name = rec.controller.get("c") if isinstance(rec.controller, dict) else None
        if isinstance(c_name, str):
            _compare(folder, files, f"controller/{pm.controller}.c", _read(folder, c_name, problems),
                     f"the printed {c_name}", problems)
        _compare(folder, files, f"controller/{layout.controller_header_name(node)}", ref_h,
                 "the reference header rendered from the proved model", problems)
        extra = [n for n in files if n.startswith("controller/")
                 and n not in (f"controller/{pm.controller}.c", f"controller/{layout.controller_header_name(node)}")]
        for n in extra:
            problems.add(n, "not a file of the generated controller")
    expected = {f"{pkg}/{nf.paths[key]}" for key in copies} | {f"{pkg}/{rel}" for rel in nf.texts} \
        | {f"{pkg}/{n}" for n in files if n.startswith("controller/")}
    _unexpected_files(folder, pkg, expected, problems)
    _check_commands(build, package, rec.glue_c, generated, problems)
    return None


#: What ``<node>.target`` of a ROS 2 build says (pyrosgen.ros2.build.TARGET_TEXT).
_ROS2_TARGET = "target: ros2 (ROS 2 Kilted, rcl, rmw_fastrtps_cpp)\n"


def _qos_record(folder: Path, rec: ProofRecord, files: dict[str, str], problems: "_Problems") -> str | None:
    """The QoS record ``<node>.qos`` of a ROS 2 build folder (rule 4.18),
    covered by the manifest; ``None`` (a problem) when it is missing."""
    from pyrosgen.ros2.wrapper import qos_file_name

    name = qos_file_name(rec.node)
    if name not in files:
        problems.add(name, "missing (or not covered by the manifest): a ROS 2 build's QoS record")
        return None
    data = _read(folder, name, problems)
    return data.decode("utf-8", errors="replace") if data is not None else None


def check_qos_of_model(folder: Path, rec: ProofRecord, model, model_path) -> None:
    """``verify --model`` of a ROS 2 build folder (rule 4.18): the folder's
    QoS record is the QoS of the model file, read by the front end
    (``model``, its :class:`NodeModel`) and read again independently
    (:func:`pyrosgen.nversion.qos.check_qos_record`).  Raises
    :class:`pyrosgen.nversion.check.NVersionMismatch` (exit 2)."""
    from pyrosgen.nversion.check import NVersionMismatch, differing_lines
    from pyrosgen.nversion.qos import check_qos_record
    from pyrosgen.ros2.wrapper import qos_file_name, qos_text

    name = qos_file_name(rec.node)
    try:
        record = read_file(folder, name, limit=1 << 20).decode("utf-8", errors="replace")
    except (OSError, PyrosgenError) as exc:  # missing, or verify.folder.UnsafeFile
        raise NVersionMismatch(f"{name}: cannot read the folder's QoS record: {exc}", []) from None
    lines = differing_lines(qos_text(model), record, what=f"the folder's {name}")
    if lines:
        raise NVersionMismatch(f"the folder's {name} is not the QoS of {Path(model_path).name} (rule 4.18)", lines)
    check_qos_record(model_path, record, what=f"the folder's {name}")


def _ros2_node_files(pm, node, package, qos) -> _NodeFiles:
    from pyrosgen.ros2.package import render_ros2_package_record, ros2_package_paths
    from pyrosgen.ros2.wrapper import render_rcl_wrapper, ros2_wrapper_files

    names = ros2_wrapper_files(node)
    return _NodeFiles(api=(names.api_header, names.api_source), wrapper=render_rcl_wrapper(node, pm, qos=qos),
                      paths=ros2_package_paths(node), texts=render_ros2_package_record(node, package))


def _check_ros2_msg_packages(folder: Path, rec: ProofRecord, files: dict[str, str], custom: list[str],
                             maintainer: str, problems: _Problems) -> None:
    """The interface package ``<pkg>/`` of each recorded custom message
    package: exactly ``package.xml`` and ``CMakeLists.txt``, rendered again
    from its ``msg/*.msg`` files, and these, each the same bytes as the copy
    rosidl's generators ran on (``rosidl/interfaces/<pkg>/msg/``, which
    ``check_rosidl_folder`` generates again); every package rosidl built is
    recorded."""
    from pyrosgen.ros2.package import render_ros2_msg_package

    built = {n.split("/")[2] for n in files if n.startswith("rosidl/interfaces/") and n.count("/") >= 4}
    for c in sorted(built - set(custom)):
        problems.add(f"rosidl/interfaces/{c}", "a custom message package that the build record does not name "
                                               "(build.package.custom_pkgs): its interface package is not checked")
    for c in custom:
        mine = sorted(n.rsplit("/", 1)[1] for n in files
                      if n.startswith(f"{c}/msg/") and n.count("/") == 2 and n.endswith(".msg"))
        theirs = sorted(n.rsplit("/", 1)[1] for n in files
                        if n.startswith(f"rosidl/interfaces/{c}/msg/") and n.count("/") == 4 and n.endswith(".msg"))
        if mine != theirs:
            problems.add(f"{c}/msg", f"holds {', '.join(mine) or 'no .msg file'}; rosidl built "
                                     f"{', '.join(theirs) or 'none'} (rosidl/interfaces/{c}/msg/)")
        msgs = {}
        for name in mine:
            data = _read(folder, f"{c}/msg/{name}", problems)
            if data is None:
                continue
            msgs[name] = data.decode("utf-8", "replace")
            twin = f"rosidl/interfaces/{c}/msg/{name}"
            if twin in files:
                _compare(folder, files, f"{c}/msg/{name}", _read(folder, twin, problems), f"the file rosidl built ({twin})",
                         problems)
        try:
            texts = render_ros2_msg_package(rec.source_name, rec.node, c, msgs, maintainer)
        except (ValueError, TypeError) as exc:
            problems.add(c, f"cannot render the interface package again: {exc}")
            continue
        for rel, text in texts.items():
            _compare(folder, files, f"{c}/{rel}", text, "rendered from its .msg files", problems)
        _unexpected_files(folder, c, {f"{c}/package.xml", f"{c}/CMakeLists.txt", *(f"{c}/msg/{m}" for m in mine)},
                          problems)


def _check_ros2_folder(folder: Path, rec: ProofRecord, files: dict[str, str], proved_text: str) -> Check:
    """A folder of ``pyrosgen build --ros2`` (rule 4.17): its ``<node>.target``
    says so; its build record says ``target: ros2``; the rcl wrapper
    ``<node>_rcl.c`` and the API header, the layout check, the ament_cmake
    package (its copies, ``package.xml``, ``CMakeLists.txt`` and
    ``launch/<node>.launch.xml``) and a generated controller are rendered
    again from the proved model and the build record (by the functions
    ``build --ros2`` renders them with) and compared byte for byte, as for
    ROS 1; the package holds no other file, and the folder none of a ROS 1
    build's (a ``.target`` cannot excuse them from the checks above) nor a
    second package (a ``package.xml`` or ``CMakeLists.txt`` elsewhere); the
    rcl wrapper is rendered with the QoS of the folder's record ``<node>.qos``
    (rule 4.18), and the rcl wrapper check (``check_rcl_wrapper``, with that
    record) runs too, as defence in depth; custom messages are generated
    again by rosidl from the folder's ``.msg`` files (``check_rosidl_folder``)."""
    from pyrosgen.ros2.wrapper import Ros2WrapperMismatch, check_rcl_wrapper

    target = f"{rec.node}.target"
    problems = _Problems()
    text = _read(folder, target, problems)
    if text is not None and text != _ROS2_TARGET.encode("ascii"):
        problems.add(target, f"says {text[:200]!r}, not {_ROS2_TARGET!r}")
    for n in sorted(n for n in files if n.endswith(("_ros.cpp", ".launch"))):
        problems.add(n, "a ROS 1 build's file in a folder built for ROS 2")
    build = rec.build
    if not isinstance(build, dict) or build.get("target") != "ros2" or not isinstance(build.get("package"), dict):
        problems.add(rec.node + ".manifest.json", "no ROS 2 build record (build.target ros2, build.package): "
                     "the node's package cannot be rendered again")
        return Check("package", False, f"{len(problems)} problems with the files of the ROS 2 node", list(problems))
    record = _qos_record(folder, rec, files, problems)
    if record is None:
        return Check("package", False, f"{len(problems)} problems with the files of the ROS 2 node", list(problems))
    from pyrosgen.ros2.wrapper import parse_qos_text

    try:
        pm, node = _proved(proved_text, rec)
        qos = parse_qos_text(record, pm)
    except ValueError as exc:
        problems.add(f"{rec.node}.qos", f"does not fit the proved model: {exc}")
        return Check("package", False, f"{len(problems)} problems with the files of the ROS 2 node", list(problems))
    except (MalformedModelText, KeyError, TypeError) as exc:
        return Check("package", False, f"cannot render the node's files again: {exc}", list(problems))
    try:
        nf = _ros2_node_files(pm, node, build["package"], qos)
    except (MalformedModelText, ValueError, KeyError, TypeError) as exc:
        return Check("package", False, f"cannot render the node's files again: {exc}", list(problems))
    pkg = ros.catkin_package_name(node)
    custom = list(build["package"]["custom_pkgs"])
    interface_files = {f"{c}/{f}" for c in custom for f in ("package.xml", "CMakeLists.txt")}
    for n in sorted(files):
        if n.endswith(("package.xml", "CMakeLists.txt")) and not n.startswith(f"{pkg}/") and n not in interface_files:
            problems.add(n, f"a package file outside the node's package {pkg}/ and its custom message packages "
                            "(a ROS 2 build writes these only)")
    failed = _check_node_files(folder, rec, files, pm, node, build, nf, problems)
    if failed is not None:
        return failed
    rcl = nf.api[1]
    data = _read(folder, rcl, problems) if rcl in files else None
    if data is not None:
        try:
            check_rcl_wrapper(data.decode("utf-8", errors="replace"), proved_text, wrapper_name=rcl,
                              qos_record=record)
        except Ros2WrapperMismatch as exc:
            problems.add(rcl, exc.summary + ("; " + "; ".join(x.strip() for x in exc.lines) if exc.lines else ""))
    # custom messages: generated again by rosidl from the folder's .msg files (pyrosgen/ros2/rosidl.py)
    from pyrosgen.ros2.rosidl import check_rosidl_folder

    for name, why in check_rosidl_folder(folder, files, proved_text):
        problems.add(name, why)
    _check_ros2_msg_packages(folder, rec, files, custom, build["package"]["maintainer"], problems)
    if problems:
        return Check("package", False, f"{len(problems)} problems with the files of the ROS 2 node (rendered again "
                     "from the proved model and compared)", list(problems))
    return Check("package", True, f"a ROS 2 build (target file as written by build --ros2): {problems.compared} "
                 "files of the node (the rcl wrapper, the ament_cmake package) rendered again from the proved "
                 f"model and equal, the wrapper with the QoS of {rec.node}.qos; no ROS 1 file; the glue"
                 + (" and the generated controller" if rec.controller else "")
                 + " compiled with " + " ".join(ros.IEEE_CFLAGS))

"""Custom message types for the target ``ros2`` (DESIGN.md rule 4.17):
rosidl's own generators, from the installed wheels, and gcc.

A model's ``msg_paths`` name folders of ``<pkg>/msg/<Type>.msg`` files.  For
ROS 2, ``pyrosgen build --ros2`` builds every custom package that they hold
as ``colcon build`` would build an interface package with
``rosidl_generate_interfaces``, without CMake (:func:`build_custom_types`):

1. generate (one run of the installation's interpreter,
   :data:`GENERATE_SCRIPT`): each ``.msg`` copied to
   ``rosidl/interfaces/<pkg>/msg/`` and translated into IDL
   (``rosidl_adapter``), its type description and hash
   (``rosidl_generator_type_description``), then the C structs and
   functions (``rosidl_generator_c``), the type supports for Fast DDS
   (``rosidl_typesupport_fastrtps_c``) and for introspection
   (``rosidl_typesupport_introspection_c``), the dispatching C type support
   (``rosidl_typesupport_c``), each into ``rosidl/<kind>/<pkg>/``, and the
   Python types (``rosidl_generator_py``) into ``python/<pkg>/``;
2. compile, per package in dependency order, the shared libraries
   ``lib/lib<pkg>__rosidl_generator_c.so``,
   ``__rosidl_typesupport_fastrtps_c`` (C++),
   ``__rosidl_typesupport_introspection_c``, ``__rosidl_typesupport_c``
   (C++), ``__rosidl_generator_py`` and the Python extension
   ``python/<pkg>/<pkg>_s__rosidl_typesupport_c<EXT_SUFFIX>``, each with
   a DT_RPATH to ``$ORIGIN`` (or ``lib/``) and the installation's library
   folders.

The node links the type supports directly (``--no-as-needed``): rmw asks
``rosidl_typesupport_c`` for the Fast DDS type support, which loads
``lib<pkg>__rosidl_typesupport_fastrtps_c.so`` by name (``dlopen``); already
loaded, it is found without a search path.  An rclpy peer imports the Python types
with ``PYTHONPATH=OUT/python`` and nothing else (:func:`peer_env`).

The generated sources are a function of the ``.msg`` files and the
installed generators: ``pyrosgen verify`` generates them again from the
copies in ``rosidl/interfaces`` and compares them byte for byte, and checks
that the C struct of every custom message the proved model carries declares
each carried field with the proved type (:func:`check_rosidl_folder`); the
libraries are covered by the certificate's hashes.
"""

from __future__ import annotations

import json
import re
import shutil
import tempfile
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from pyrosgen.frontend.model import NodeModel
from pyrosgen.ros.build import BuildToolError, _clip, _run
from pyrosgen.ros2.env import INSTALL_COMMAND, Ros2Install, Ros2Missing, ros2_env

__all__ = ["GENERATE_SCRIPT", "CustomTypes", "KINDS", "build_custom_types", "custom_packages", "msg_dependencies",
           "check_rosidl_folder", "generate_sources", "peer_env", "ROSIDL_DIR", "PYTHON_DIR", "LIB_DIR"]

#: The folders of a build (relative to ``OUT``).
ROSIDL_DIR, PYTHON_DIR, LIB_DIR = "rosidl", "python", "lib"
#: The generators run for each package: output folder -> rosidl's module.
KINDS = {"c": "rosidl_generator_c", "fastrtps_c": "rosidl_typesupport_fastrtps_c",
         "introspection_c": "rosidl_typesupport_introspection_c", "typesupport_c": "rosidl_typesupport_c"}

#: Run by the installation's interpreter: ``python -c GENERATE_SCRIPT ARGS``
#: with ARGS a JSON object {"out": build folder, "packages": [[pkg,
#: [Type, ...]], ...] in dependency order, "share": [the installation's
#: message package folders]}.  The ``rosidl`` command line of the wheels
#: cannot be used: the wheels register every generator twice (an
#: ``.egg-info`` and a ``.dist-info``), which it refuses ("Found duplicate
#: entry point"), and its translation step needs ``catkin_pkg``; the
#: generators' own classes are called instead, as it would call them.
GENERATE_SCRIPT = r"""
import contextlib, io, json, pathlib, sys
from rosidl_adapter.msg import convert_msg_to_idl
from rosidl_generator_type_description.cli import HashTypeDescription
from rosidl_generator_c.cli import GenerateC
from rosidl_typesupport_c.cli import GenerateCTypesupport
from rosidl_typesupport_fastrtps_c.cli import GenerateFastRTPSCTypesupport
from rosidl_typesupport_introspection_c.cli import GenerateIntrospectionCTypesupport
from rosidl_generator_py.cli import GeneratePython

args = json.loads(sys.argv[1])
out = pathlib.Path(args["out"])
inc = list(args["share"])
generators = [(GenerateC, "c"), (GenerateFastRTPSCTypesupport, "fastrtps_c"),
              (GenerateIntrospectionCTypesupport, "introspection_c"), (GenerateCTypesupport, "typesupport_c")]
for pkg, types in args["packages"]:
    src = out / "rosidl" / "interfaces" / pkg
    idl = []
    for t in types:
        try:
            with contextlib.redirect_stdout(io.StringIO()):
                convert_msg_to_idl(src, pkg, pathlib.Path("msg") / (t + ".msg"), src / "msg")
        except Exception as exc:
            print(f"MSGERROR {pkg}/msg/{t}.msg: {' '.join(str(exc).split())}", file=sys.stderr)
            sys.exit(3)
        idl.append(f"{src}:msg/{t}.idl")
    tds = HashTypeDescription("type_description").generate_type_hashes(pkg, idl, inc, output_path=src)
    for cls, kind in generators:
        kw = {"type_description_files": tds} if kind == "c" else {}
        cls(kind).generate(pkg, idl, inc, output_path=out / "rosidl" / kind / pkg, **kw)
    GeneratePython("py", typesupport_implementations=["rosidl_typesupport_c"]).generate(
        pkg, idl, inc, output_path=out / "python" / pkg)
    (out / "python" / pkg / "__init__.py").touch()
    inc.append(str(src))
"""

_FIELD = re.compile(r"\s*([A-Za-z][A-Za-z0-9_]*(?:/[A-Za-z][A-Za-z0-9_]*)?)(?:\[[^\]]*\])?\s+[A-Za-z0-9_]+")
_PRIMITIVE_NAMES = {"bool", "byte", "char", "int8", "uint8", "int16", "uint16", "int32", "uint32", "int64",
                    "uint64", "float32", "float64", "string", "wstring", "time", "duration"}


@dataclass(frozen=True)
class CustomTypes:
    """What the node is compiled and linked with to use the custom types."""

    packages: tuple[str, ...]          #: in dependency order
    compile_flags: tuple[str, ...]     #: ``-I`` the generated C headers (relative to the build folder)
    link_flags: tuple[str, ...]        #: ``-L``, ``-l`` and the DT_RPATH ``$ORIGIN/../lib``


def custom_packages(model: NodeModel) -> dict[str, list[Path]]:
    """The custom packages of the model's ``msg_paths``: name -> its
    ``.msg`` files (sorted)."""
    out: dict[str, list[Path]] = {}
    for folder in model.msg_paths:
        for f in sorted(Path(folder).glob("*/msg/*.msg")):
            out.setdefault(f.parent.parent.name, []).append(f)
    return dict(sorted(out.items()))


def _dependencies(pkg: str, files: list[Path]) -> set[str]:
    """The packages whose types the ``.msg`` files of ``pkg`` name."""
    return msg_dependencies(pkg, [f.read_text(encoding="utf-8") for f in files])


def msg_dependencies(pkg: str, texts: list[str]) -> set[str]:
    """The packages whose types the ``.msg`` texts of ``pkg`` name."""
    deps = set()
    for text in texts:
        for line in text.split("\n"):
            m = _FIELD.match(line.split("#", 1)[0])
            if m is None or "=" in line.split("#", 1)[0]:
                continue
            typ = m.group(1)
            if "/" in typ:
                deps.add(typ.split("/", 1)[0])
            elif typ not in _PRIMITIVE_NAMES:
                deps.add(pkg)
    deps.discard(pkg)
    return deps


def _order(packages: dict[str, list[Path]]) -> tuple[list[str], dict[str, set[str]]]:
    """The custom packages in dependency order and each one's dependencies
    (custom or installed); a cycle between custom packages is a user error."""
    from pyrosgen.errors import Diagnostic, InvalidNodeModel

    deps = {p: _dependencies(p, fs) for p, fs in packages.items()}
    order: list[str] = []
    state: dict[str, int] = {}

    def visit(p: str, chain: list[str]) -> None:
        if state.get(p) == 2:
            return
        if state.get(p) == 1:
            loop = " -> ".join([*chain[chain.index(p):], p])
            raise InvalidNodeModel([Diagnostic(str(packages[p][0]), None, None,
                                               f"the custom packages depend on each other ({loop}): rosidl builds "
                                               "one package after the packages it uses (target ros2)", rule="4.17")])
        state[p] = 1
        for d in sorted(deps[p]):
            if d in packages:
                visit(d, [*chain, p])
        state[p] = 2
        order.append(p)

    for p in packages:
        visit(p, [])
    return order, deps


def _check_generators(inst: Ros2Install) -> None:
    site = inst.site_packages()
    need = [*(site / m for m in ("rosidl_adapter", "rosidl_generator_type_description", "rosidl_generator_py",
                                 *KINDS.values())),
            inst.share_dir / "rosidl_generator_c", inst.prefix / "include" / "fastcdr" / "Cdr.h"]
    missing = [str(p) for p in need if not p.exists()]
    if missing:
        raise Ros2Missing(f"the ROS 2 installation at {inst.prefix} has no rosidl generators (missing {missing[0]}), "
                          f"which custom messages (msg_paths) need: install them with `{INSTALL_COMMAND}`")


def _share_dirs(inst: Ros2Install, custom: set[str]) -> list[str]:
    """The installed message packages (their ``.idl`` files, included by
    the custom ones, and ``.json`` type descriptions)."""
    return [str(p.parent) for p in sorted(inst.share_dir.glob("*/msg")) if p.parent.name not in custom
            and any(p.glob("*.idl"))]


def generate_sources(inst: Ros2Install, packages: dict[str, list[Path]], order: list[str], out: Path) -> None:
    """Copy the ``.msg`` files into ``out/rosidl/interfaces`` and run the
    generators (:data:`GENERATE_SCRIPT`) into ``out``.  A ``.msg`` file
    that rosidl refuses is a user error (exit 1) naming it."""
    from pyrosgen.errors import Diagnostic, InvalidNodeModel

    for pkg in order:
        dest = out / ROSIDL_DIR / "interfaces" / pkg / "msg"
        dest.mkdir(parents=True, exist_ok=True)
        for f in packages[pkg]:
            shutil.copyfile(f, dest / f.name)
    args = {"out": str(out), "share": _share_dirs(inst, set(order)),
            "packages": [[p, [f.stem for f in packages[p]]] for p in order]}
    env = ros2_env(install=inst)
    env["AMENT_PREFIX_PATH"] = str(inst.prefix)
    env["PYTHONDONTWRITEBYTECODE"] = "1"
    r = _run_env([str(inst.python), "-c", GENERATE_SCRIPT, json.dumps(args)], "generating the custom messages' code",
                 out, env)
    if r.returncode == 3 and "MSGERROR " in r.stderr:
        name, _, why = r.stderr.split("MSGERROR ", 1)[1].strip().partition(": ")
        pkg = name.split("/", 1)[0]
        src = next((f for f in packages.get(pkg, []) if name.endswith("/" + f.name)), Path(name))
        raise InvalidNodeModel([Diagnostic(str(src), None, None, f"rosidl refuses this message definition: {why}",
                                           rule="4.17")])
    if r.returncode != 0:
        raise BuildToolError(f"rosidl's generators failed on the custom messages (exit status {r.returncode})",
                             _clip(r.stderr + r.stdout).splitlines())


def _run_env(argv: list[str], what: str, cwd: Path, env: dict[str, str]):
    """:func:`pyrosgen.ros.build._run` in the environment ``env``."""
    import subprocess

    from pyrosgen import procs

    try:
        return procs.run(argv, timeout=900, cwd=cwd, env=env)
    except OSError as exc:
        raise BuildToolError(f"cannot run {argv[0]} ({what}): {exc.strerror or exc}") from None
    except subprocess.TimeoutExpired:
        raise BuildToolError(f"{argv[0]} did not finish {what} within 900 s") from None


def _python_info(inst: Ros2Install) -> tuple[list[str], str]:
    """``-I`` Python's and numpy's headers, and the extension suffix, of the
    installation's interpreter."""
    code = ("import json, sysconfig, numpy; print(json.dumps([sysconfig.get_paths()['include'], numpy.get_include(), "
            "sysconfig.get_config_var('EXT_SUFFIX')]))")
    r = _run([str(inst.python), "-c", code], "asking the ROS 2 interpreter for its headers")
    if r.returncode != 0:
        raise BuildToolError("the ROS 2 installation's interpreter cannot tell its headers",
                             _clip(r.stderr).splitlines())
    py_inc, np_inc, suffix = json.loads(r.stdout)
    if not (Path(py_inc) / "Python.h").is_file():
        raise Ros2Missing(f"no Python.h in {py_inc}: the Python types of the custom messages need Python's "
                          "headers (the Debian package python3-dev)")
    return ["-I", py_inc, "-I", np_inc], suffix


def _lib(pkg: str, kind: str) -> str:
    return f"{pkg}__rosidl_{kind}"


def _compile(argv: list[str], what: str, cwd: Path) -> None:
    r = _run(argv, what, cwd=cwd)
    if r.returncode != 0:
        raise BuildToolError(f"{argv[0]} failed {what} (exit status {r.returncode})",
                             _clip(r.stderr + r.stdout).splitlines())


def _compile_package(pkg: str, deps: set[str], inst: Ros2Install, out: Path, cc: list[str], cxx: list[str],
                     python: tuple[list[str], str]) -> None:
    gen, lib = out / ROSIDL_DIR, out / LIB_DIR
    # the generated sources and folders relative to ``out`` (the compilers run
    # there): their __FILE__ names, in the libraries, do not name the staging folder
    inc = ["-I", str(inst.prefix / "include"), *(a for d in inst.include_dirs() for a in ("-I", str(d))),
           "-I", f"{ROSIDL_DIR}/c"]
    ros_rpath = ":".join(str(p) for p in inst.library_path())

    def flags(rpath: str) -> list[str]:
        return ["-L", str(lib), "-L", str(inst.lib_dir), "-Wl,--disable-new-dtags", f"-Wl,-rpath,{rpath}:{ros_rpath}"]

    def so(name: str) -> list[str]:
        return ["-fPIC", "-shared", f"-Wl,-soname,lib{name}.so", "-o", str(lib / f"lib{name}.so")]

    c_flags, cxx_flags = ["-std=c11", "-O2", "-w"], ["-std=c++17", "-O2", "-w"]
    sources = {k: sorted(p.relative_to(out).as_posix() for p in (gen / k / pkg).rglob("*.c*")) for k in KINDS}
    dl = lambda kind: [f"-l{_lib(d, kind)}" for d in sorted(deps)]  # noqa: E731
    _compile([*cc, *c_flags, *inc, *sources["c"], *so(_lib(pkg, "generator_c")), *flags("$ORIGIN"),
              *dl("generator_c"), "-lrosidl_runtime_c", "-lrcutils"], f"compiling {pkg}'s C messages", out)
    _compile([*cxx, *cxx_flags, *inc, "-I", f"{ROSIDL_DIR}/fastrtps_c", *sources["fastrtps_c"],
              *so(_lib(pkg, "typesupport_fastrtps_c")), *flags("$ORIGIN"), f"-l{_lib(pkg, 'generator_c')}",
              *dl("typesupport_fastrtps_c"), *dl("generator_c"), "-lrosidl_runtime_c",
              "-lrosidl_typesupport_fastrtps_c", "-lfastcdr", "-lrcutils"],
             f"compiling {pkg}'s Fast DDS type support", out)
    _compile([*cc, *c_flags, *inc, "-I", f"{ROSIDL_DIR}/introspection_c", *sources["introspection_c"],
              *so(_lib(pkg, "typesupport_introspection_c")), *flags("$ORIGIN"), f"-l{_lib(pkg, 'generator_c')}",
              *dl("typesupport_introspection_c"), *dl("generator_c"), "-lrosidl_runtime_c"],
             f"compiling {pkg}'s introspection type support", out)
    _compile([*cxx, *cxx_flags, *inc, *sources["typesupport_c"], *so(_lib(pkg, "typesupport_c")), *flags("$ORIGIN"),
              f"-l{_lib(pkg, 'generator_c')}", "-lrosidl_runtime_c", "-lrosidl_typesupport_c", "-lrcutils"],
             f"compiling {pkg}'s C type support", out)
    py_inc, suffix = python
    pydir = out / PYTHON_DIR / pkg
    py_sources = sorted(p.relative_to(out).as_posix() for p in (pydir / "msg").glob("*_s.c"))
    _compile([*cc, *c_flags, *inc, *py_inc, *py_sources,
              *so(_lib(pkg, "generator_py")), *flags("$ORIGIN"), f"-l{_lib(pkg, 'generator_c')}",
              f"-l{_lib(pkg, 'typesupport_c')}", *dl("generator_py"), *dl("generator_c"), "-lrosidl_runtime_c"],
             f"compiling {pkg}'s Python support", out)
    ext = pydir / f"{pkg}_s__rosidl_typesupport_c{suffix}"
    _compile([*cc, *c_flags, *inc, *py_inc, f"{PYTHON_DIR}/{pkg}/_{pkg}_s.ep.rosidl_typesupport_c.c", "-fPIC",
              "-shared", "-o", str(ext), *flags("$ORIGIN/../../lib"), "-Wl,--no-as-needed",
              *(f"-l{_lib(pkg, k)}" for k in ("generator_py", "typesupport_c", "typesupport_fastrtps_c",
                                              "typesupport_introspection_c", "generator_c")),
              "-Wl,--as-needed", "-lrosidl_runtime_c"], f"compiling {pkg}'s Python extension", out)


def build_custom_types(model: NodeModel, inst: Ros2Install, out: Path, *, cc: list[str], cxx: list[str],
                       say: Callable[[str], None] = lambda _l: None) -> CustomTypes | None:
    """Generate and compile the custom packages of the model's
    ``msg_paths`` into the build folder ``out`` (the module documentation);
    ``None`` without custom messages.  Raises :class:`Ros2Missing` (exit 2)
    without the generators, :class:`BuildToolError` (exit 2) when one fails
    and :class:`pyrosgen.errors.InvalidNodeModel` (exit 1) for a ``.msg``
    file rosidl refuses or packages that depend on each other."""
    packages = custom_packages(model)
    if not packages:
        return None
    _check_generators(inst)
    order, deps = _order(packages)
    say(f"rosidl: generating {', '.join(order)} ({sum(len(v) for v in packages.values())} messages)")
    generate_sources(inst, packages, order, out)
    (out / LIB_DIR).mkdir(exist_ok=True)
    python = _python_info(inst)
    for pkg in order:
        say(f"rosidl: compiling {pkg}")
        _compile_package(pkg, deps[pkg], inst, out, cc, cxx, python)
    libs = [f"-l{_lib(p, k)}" for p in reversed(order) for k in ("typesupport_c", "generator_c")]
    preload = [f"-l{_lib(p, k)}" for p in reversed(order)
               for k in ("typesupport_fastrtps_c", "typesupport_introspection_c")]
    return CustomTypes(tuple(order), ("-I", f"{ROSIDL_DIR}/c"),
                       ("-L", str(out / LIB_DIR), "-Wl,-rpath,$ORIGIN/../lib", *libs,
                        "-Wl,--no-as-needed", *preload, "-Wl,--as-needed"))


def peer_env(out: Path, inst: Ros2Install | None = None) -> dict[str, str]:
    """The environment of an rclpy process that uses the custom types of
    the build in ``out``: :func:`pyrosgen.ros2.env.ros2_env` with
    ``PYTHONPATH`` to ``out/python``.  Nothing else: the Python extension
    finds the package's libraries by its DT_RPATH (``$ORIGIN/../../lib``)
    and loads its type supports, which rosidl's dispatch then finds loaded."""
    env = ros2_env(install=inst)
    old = env.get("PYTHONPATH", "")
    env["PYTHONPATH"] = ":".join([str(out / PYTHON_DIR), *([old] if old else [])])
    return env


# --------------------------------------------------------------------------
# pyrosgen verify: the generated files again, and the carried fields

#: rosidl's C type of each primitive
_C_TYPES = {"bool": "bool", "int8": "int8_t", "uint8": "uint8_t", "int16": "int16_t", "uint16": "uint16_t",
            "int32": "int32_t", "uint32": "uint32_t", "int64": "int64_t", "uint64": "uint64_t",
            "float32": "float", "float64": "double"}
_INTERFACE = re.compile(rf"{ROSIDL_DIR}/interfaces/([a-z][a-z0-9_]*)/msg/([A-Z][A-Za-z0-9]*)\.msg")
_MEMBER = re.compile(r"^  (\w+) (\w+)(?:\[(\d+)\])?;$", re.M)


def _rosidl_member(pm, ftype: str) -> tuple[str, str | None] | None:
    """The rosidl C member (type, array size) of a proved field type, or
    ``None`` when the type is not one pyrosgen prints."""
    from pyrosgen.frontend.msgmodel import is_bounded_type
    from pyrosgen.proof.modeltext import MalformedModelText
    from pyrosgen.ros.wrapper import _proved_msg_name
    from pyrosgen.ros2.wrapper import ROSIDL_SEQ, rosidl_c_type

    m = re.fullmatch(r"(?:array ([1-9][0-9]*) )?(?:msg (\w+)|(\w+))", ftype)
    if m is None:
        return None
    size, struct, prim = m.group(1), m.group(2), m.group(3)
    if prim is not None:
        return (_C_TYPES[prim], size) if prim in _C_TYPES else None
    if not is_bounded_type(struct):
        try:
            return rosidl_c_type(_proved_msg_name(struct)), size
        except (MalformedModelText, ValueError):
            return None
    if struct.startswith(("ros_string", "ros_rstring")):
        return "rosidl_runtime_c__String", size
    data = dict(pm.messages.get(struct, [])).get("data", "")
    elem = re.fullmatch(r"array [1-9][0-9]* (?:msg (\w+)|(\w+))", data)
    if elem is None:
        return None
    if elem.group(2) is not None:
        return (f"rosidl_runtime_c__{ROSIDL_SEQ[elem.group(2)]}__Sequence", size) if elem.group(2) in ROSIDL_SEQ \
            else None
    if elem.group(1).startswith(("ros_string", "ros_rstring")):
        return "rosidl_runtime_c__String__Sequence", size
    inner = _rosidl_member(pm, f"msg {elem.group(1)}")
    return (f"{inner[0]}__Sequence", size) if inner else None


def _check_structs(folder: Path, pm, custom: dict[str, str]) -> list[tuple[str, str]]:
    """Each carried field of each custom message the proved model holds is
    declared by rosidl's C struct with the proved type (a field whose type
    the ``.msg`` changed would still compile: C converts ``double`` to
    ``float`` silently)."""
    from pyrosgen.ros2.wrapper import rosidl_c_type, snake

    problems = []
    for struct, name in sorted(custom.items()):
        pkg, typ = name.split("/", 1)
        header = f"{ROSIDL_DIR}/c/{pkg}/msg/detail/{snake(typ)}__struct.h"
        try:
            text = (folder / header).read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError) as exc:
            problems.append((header, f"cannot read it: {getattr(exc, 'strerror', None) or exc}"))
            continue
        c = rosidl_c_type(name)
        body = re.search(rf"^typedef struct {c}\n\{{\n(.*?)^\}} {c};$", text, re.M | re.S)
        members = {n: (t, s) for t, n, s in _MEMBER.findall(body.group(1))} if body else {}
        if body is None:
            problems.append((header, f"declares no struct {c}"))
            continue
        for fname, ftype in pm.messages[struct]:
            want = _rosidl_member(pm, ftype)
            got = members.get(fname)
            if want is None:
                problems.append((header, f"the proved field {fname} has type {ftype!r}"))
            elif got is None or (got[0], got[1] or None) != want:
                shown = "not declared" if got is None else f"declared {got[0]}{f'[{got[1]}]' if got[1] else ''}"
                problems.append((header, f"{c}.{fname}: {shown}, the proved model carries {ftype} "
                                         f"({want[0]}{f'[{want[1]}]' if want[1] else ''})"))
    return problems


def check_rosidl_folder(folder: str | Path, files, proved_text: str,
                        install: Ros2Install | None = None) -> list[tuple[str, str]]:
    """The problems, as (file, why), with the custom messages of the ROS 2
    build folder ``folder`` (``files``: the names its manifest lists): the
    generated sources not those rosidl's generators make again from the
    folder's copies of the ``.msg`` files (``rosidl/interfaces``), a
    generated file the generators do not make, a custom message the proved
    model carries without its ``.msg`` file, a carried field that rosidl's
    C struct declares with another type (:func:`_check_structs`).  None
    without custom messages; :class:`Ros2Missing` (exit 2) without the
    ROS 2 installation or its generators when there are some."""
    from pyrosgen.errors import InvalidNodeModel
    from pyrosgen.frontend.msgmodel import is_bounded_type
    from pyrosgen.proof.modeltext import MalformedModelText, parse_model_text
    from pyrosgen.ros.wrapper import _proved_msg_name
    from pyrosgen.ros2.env import find_ros2

    folder = Path(folder)
    names = sorted(files)
    msgs = [n for n in names if _INTERFACE.fullmatch(n)]
    try:
        pm = parse_model_text(proved_text or "")
    except MalformedModelText:
        return []  # the proved model is reported by the other checks
    generated = [n for n in names if n.startswith((f"{ROSIDL_DIR}/", f"{PYTHON_DIR}/")) and n not in msgs
                 and not n.endswith(".so")]
    declared = {_INTERFACE.fullmatch(n).group(1) for n in msgs}
    if not msgs and not generated:
        # no custom message in the folder: none may be in the proved model either
        try:
            inst = install or find_ros2()
        except Ros2Missing:
            return []
        installed = {p.parent.name for p in inst.share_dir.glob("*/msg")}
        return [(f"{ROSIDL_DIR}/interfaces/{n.split('/')[0]}/msg/{n.split('/')[1]}.msg",
                 f"missing: the proved model carries {n}, which is not a type of the ROS 2 installation")
                for n in sorted({_proved_msg_name(s) for s in pm.messages if not is_bounded_type(s)})
                if "/" in n and n.split("/")[0] not in installed]
    inst = install or find_ros2()
    _check_generators(inst)
    custom = {s: _proved_msg_name(s) for s in pm.messages if not is_bounded_type(s)
              and _proved_msg_name(s).split("/", 1)[0] in declared}
    problems: list[tuple[str, str]] = []
    for s, name in custom.items():
        pkg, typ = name.split("/", 1)
        if f"{ROSIDL_DIR}/interfaces/{pkg}/msg/{typ}.msg" not in msgs:
            problems.append((f"{ROSIDL_DIR}/interfaces/{pkg}/msg/{typ}.msg",
                             f"missing: the proved model carries {name}"))
    with tempfile.TemporaryDirectory(prefix="pyrosgen-rosidl-") as tmp:
        src, out = Path(tmp) / "src", Path(tmp) / "out"
        packages: dict[str, list[Path]] = {}
        for n in msgs:
            m = _INTERFACE.fullmatch(n)
            dest = src / m.group(1) / "msg" / f"{m.group(2)}.msg"
            dest.parent.mkdir(parents=True, exist_ok=True)
            try:
                shutil.copyfile(folder / n, dest)
            except OSError as exc:
                problems.append((n, f"cannot read it: {exc.strerror or exc}"))
                continue
            packages.setdefault(m.group(1), []).append(dest)
        try:
            order, _deps = _order(packages)
            out.mkdir()
            generate_sources(inst, packages, order, out)
        except (InvalidNodeModel, BuildToolError) as exc:
            return [*problems, (f"{ROSIDL_DIR}/interfaces", f"rosidl's generators fail on the folder's .msg files: "
                                f"{' '.join(str(exc).split())[:300]}")]
        again = {p.relative_to(out).as_posix(): p for p in out.rglob("*") if p.is_file()}
        for n in sorted(set(again) - set(msgs)):
            if n not in names:
                problems.append((n, "missing: rosidl's generators make it from the folder's .msg files"))
                continue
            try:
                same = (folder / n).read_bytes() == again[n].read_bytes()
            except OSError as exc:
                problems.append((n, f"cannot read it: {exc.strerror or exc}"))
                continue
            if not same:
                problems.append((n, "differs from what rosidl's generators make from the folder's .msg files"))
        for n in generated:
            if n not in again:
                problems.append((n, "not a file rosidl's generators make from the folder's .msg files"))
    return problems + _check_structs(folder, pm, custom)

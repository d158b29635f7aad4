"""The ROS side of a generated node: the C API over roscpp (header and C++
implementation, with converters between roscpp messages and the C structs),
C++ classes for custom message types (through Debian's ``gencpp``), and the
catkin package files.

Everything here is rendered from jinja2 templates in ``pyrosgen/templates``;
the C structs themselves are *not* rendered here: they are printed by Coq
from the very composite definitions of the AST that the DDC theorem is about
(``<node>_types.h``), and the wrapper includes them.
"""

from __future__ import annotations

import re
import subprocess
from dataclasses import dataclass, field
from pathlib import Path

from pyrosgen.proof.modeltext import MalformedModelText, ProvedModel, ProvedTopic
from pyrosgen.render import render, source_label

from pyrosgen.errors import ToolFailure
from pyrosgen.frontend.model import Controller, ControllerField, IOStruct, NodeModel, Topic
from pyrosgen.frontend.msgmodel import (C_TYPES, DURATION, TIME, MsgField, MsgType, _elem_msg_name, bounded_type,
                                        is_bounded_type)

#: The pseudo message types (no ROS package) by name.
PSEUDO_TYPES = {"time": TIME, "duration": DURATION}
from pyrosgen import procs

_C_IDENT = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")

GENCPP = Path("/usr/lib/gencpp/gen_cpp.py")
GENCPP_TEMPLATES = Path("/usr/share/gencpp")
#: Where Debian's ros-*-msgs packages install the standard .msg files.
STANDARD_MSG_DIRS = Path("/usr/share")


class ToolError(ToolFailure):
    """An external tool (gencpp, a compiler, ...) failed: exit code 2."""


def _check_ident(name: str) -> str:
    if not _C_IDENT.match(name):
        raise ValueError(f"refusing to print {name!r} as a C identifier")
    return name


@dataclass(frozen=True)
class WrapperFiles:
    """The names of the files making up the C API over ROS of one node."""

    types_header: str   #: Coq-printed message structs
    api_header: str     #: the C API prototypes
    api_source: str     #: the C++ implementation over roscpp


def wrapper_files(model: NodeModel) -> WrapperFiles:
    n = _check_ident(model.name)
    return WrapperFiles(f"{n}_types.h", f"{n}_ros.h", f"{n}_ros.cpp")


def _messages_by_name(model: NodeModel) -> dict[str, MsgType]:
    return {m.name: m for m in model.messages}


def _reject_paths(msgs: dict[str, MsgType], name: str) -> list[tuple[str, int]]:
    """The sequences and strings of policy reject (rule 4.15) in a message
    of type ``name``, as (C++ access path, maximum), in field order,
    through nested messages and every element of fixed-size arrays of
    messages: the subscription callback drops a message in which one is
    longer than its maximum (``Environment.accepted``)."""
    out: list[tuple[str, int]] = []

    def go(t: MsgType, prefix: str) -> None:
        for f in t.fields:
            if f.kind != "msg":
                continue
            sub = bounded_type(f.msg) if is_bounded_type(f.msg) else msgs.get(f.msg)
            if sub is None:
                continue
            for ix in ([""] if f.array_len is None else [f"[{i}]" for i in range(f.array_len)]):
                path = f"{prefix}{_check_ident(f.name)}{ix}"
                if sub.is_bounded:
                    if sub.reject:
                        out.append((path, sub.capacity))
                else:
                    go(sub, path + ".")

    t = msgs.get(name)
    if t is not None:
        go(t, "")
    return out


def _context(model: NodeModel, proved: ProvedModel | None = None) -> dict:
    files = wrapper_files(model)
    msgs = _messages_by_name(model)
    if proved is not None:
        # the node registers and sleeps as the proved model says
        topics = list(proved.topics)
        msg_c = {t.name: t.struct for t in topics}
        msg_cpp = {t.name: t.cpp_type for t in topics}
        period_ms = proved.period_ms
    else:
        topics = list(model.topics)
        msg_c = {t.name: msgs[t.msg_type].c_name for t in topics}
        msg_cpp = {t.name: msgs[t.msg_type].cpp_name for t in topics}
        period_ms = model.period_ms
    subs = [t for t in topics if t.direction == "subscribe"]
    pubs = [t for t in topics if t.direction == "publish"]
    for t in topics:
        for name in (t.c_name, t.subscribe_fn, t.advertise_fn, t.publish_fn):
            _check_ident(name)
    for m in model.messages:
        _check_ident(m.c_name)
        for f in m.fields:
            _check_ident(f.name)
    by_c = {m.c_name: m.name for m in model.messages}
    cpp_headers = sorted({f"{m.name}.h" for m in model.messages if not m.is_pseudo})
    return {
        "source": source_label(model.source.name),
        "node": model,
        "header_name": files.api_header,
        "types_header": files.types_header,
        "guard": f"PYROSGEN_{model.name.upper()}_ROS_H",
        "cpp_headers": cpp_headers,
        "messages": list(model.messages),
        "subs": subs,
        "pubs": pubs,
        "msg_c": msg_c,
        "msg_cpp": msg_cpp,
        "rejects": {t.name: _reject_paths(msgs, by_c.get(msg_c[t.name], "")) for t in subs},
        "period_s": repr(period_ms / 1000.0),
    }


@dataclass(frozen=True)
class ProvedNode:
    """What the wrapper, the layout check and the catkin package are
    rendered from (:func:`proved_node`): the proved model, read back from
    the text Coq printed, in the shape of the front end's
    :class:`~pyrosgen.frontend.model.NodeModel` that the templates read
    (``name``, ``source``, ``controller``, ``messages``, ``topics``).
    ``pyrosgen build`` renders from it, and ``pyrosgen verify`` renders
    again from it and compares byte for byte: no YAML is needed, and nothing
    of the front end's reading reaches the node but what Coq printed."""

    name: str
    period_ms: int
    source: Path                      #: the model file's name (a label only)
    controller: Controller
    messages: tuple[MsgType, ...]     #: in the order Coq printed them (dependencies first)
    topics: tuple[ProvedTopic, ...]
    msg_paths: tuple[str, ...] = ()   #: none: custom message packages are named explicitly


def _proved_msg_name(struct: str) -> str:
    """The message type name of the proved struct ``struct``: ``pkg/Type``
    of ``pkg_Type``, ``time``, or the bounded struct's own name."""
    if is_bounded_type(struct):
        return struct
    name = _elem_msg_name(struct)
    if name is None:
        raise MalformedModelText(f"the proved model's struct {struct!r} names no message type")
    return name


def _proved_field(fname: str, ftype: str) -> MsgField:
    m = re.fullmatch(r"(?:array ([1-9][0-9]*) )?(?:msg (\w+)|(\w+))", ftype)
    if m is None:
        raise MalformedModelText(f"the proved model's field {fname!r} has type {ftype!r}")
    n = int(m.group(1)) if m.group(1) else None
    if m.group(2):
        return MsgField(fname, "msg", msg=_proved_msg_name(m.group(2)), array_len=n)
    if m.group(3) not in C_TYPES:
        raise MalformedModelText(f"the proved model's field {fname!r} has type {ftype!r}")
    return MsgField(fname, "prim", prim=m.group(3), array_len=n)


def _proved_io(var: str, struct: str, fields: list[tuple[str, str]]) -> IOStruct:
    out = []
    for fname, ftype in fields:
        m = re.fullmatch(r"(?:array ([1-9][0-9]*) )?(\w+)", ftype)
        if m is None or m.group(2) not in C_TYPES:
            raise MalformedModelText(f"the proved model's controller field {fname!r} has type {ftype!r}")
        out.append(ControllerField(fname, m.group(2), int(m.group(1)) if m.group(1) else None))
    return IOStruct(var, struct, tuple(out))


def proved_node(pm: ProvedModel, source_name: str) -> ProvedNode:
    """The :class:`ProvedNode` of the proved model ``pm`` (``source_name``:
    the model file's name, shown in the files' first comment).  Each message
    struct becomes the message type the front end would give it: a bounded
    struct (rule 4.14, 4.15) by its name, ``ros_time``/``ros_duration`` the
    pseudo types, ``pkg_Type`` the message ``pkg/Type`` with the proved
    fields; ``MalformedModelText`` for anything else."""
    messages = []
    for struct, fields in pm.messages.items():
        mfields = tuple(_proved_field(f, t) for f, t in fields)
        if is_bounded_type(struct):
            mt = bounded_type(struct)
        elif struct in ("ros_time", "ros_duration"):
            mt = PSEUDO_TYPES[_proved_msg_name(struct)]
        else:
            mt = MsgType(_proved_msg_name(struct), struct, mfields)
        if mt.fields != mfields or mt.c_name != struct:
            raise MalformedModelText(f"the proved model's struct {struct!r} does not have the fields of its kind")
        messages.append(mt)
    ctl = Controller(pm.controller, _proved_io(pm.inputs_var, pm.inputs_struct, pm.inputs),
                     _proved_io(pm.outputs_var, pm.outputs_struct, pm.outputs))
    return ProvedNode(pm.name, pm.period_ms, Path(source_name), ctl, tuple(messages), tuple(pm.topics))


def render_wrapper(model: NodeModel, proved: ProvedModel | None = None) -> dict[str, str]:
    """The C API header and its roscpp implementation, by file name.

    With ``proved`` (the model Coq printed, read back), the topics, their
    names, message types and queue sizes, and the period come from it; the
    message converters come from ``model``'s message definitions (a struct
    the proved model names that ``model`` does not define cannot compile)."""
    ctx = _context(model, proved)
    files = wrapper_files(model)
    return {
        files.api_header: render("ros_api.h.j2", **ctx),
        files.api_source: render("ros_api.cpp.j2", **ctx),
    }


def custom_message_files(model: NodeModel) -> dict[str, Path]:
    """The ``.msg`` files of the node's message types that come from the
    model's ``msg_paths`` (they have no installed roscpp headers), by type."""
    out: dict[str, Path] = {}
    for m in model.messages:
        if m.is_pseudo:
            continue
        for folder in model.msg_paths:
            f = Path(folder) / m.package / "msg" / f"{m.short_name}.msg"
            if f.is_file():
                out[m.name] = f
                break
    return out


def generate_custom_cpp(model: NodeModel, include_dir: Path) -> list[Path]:
    """Run Debian's gencpp on every custom message type the node uses, writing
    ``include_dir/<pkg>/<Type>.h``.  Returns the headers written."""
    custom = custom_message_files(model)
    if not custom:
        return []
    if not GENCPP.is_file():
        raise ToolError(f"gencpp not found at {GENCPP}: install python3-gencpp (make deps)")
    # Include paths: every custom package folder and the standard packages.
    includes: list[str] = []
    seen: set[str] = set()
    for folder in model.msg_paths:
        for pkg_msg in sorted(Path(folder).glob("*/msg")):
            key = f"{pkg_msg.parent.name}:{pkg_msg}"
            if key not in seen:
                seen.add(key)
                includes += ["-I", key]
    for std in sorted(STANDARD_MSG_DIRS.glob("*_msgs/msg")):
        includes += ["-I", f"{std.parent.name}:{std}"]
    written: list[Path] = []
    for name, path in sorted(custom.items()):
        pkg = name.split("/")[0]
        out = include_dir / pkg
        out.mkdir(parents=True, exist_ok=True)
        # gencpp is Debian's, built for Debian's interpreter.
        cmd = ["/usr/bin/python3", str(GENCPP), "-p", pkg, "-o", str(out), "-e", str(GENCPP_TEMPLATES), *includes, str(path)]
        try:
            r = procs.run(cmd, timeout=600)
        except subprocess.TimeoutExpired:
            raise ToolError(f"gencpp did not finish on {path} within 600 s") from None
        if r.returncode != 0:
            raise ToolError(f"gencpp failed on {path}:\n{r.stderr.strip() or r.stdout.strip()}")
        written.append(out / f"{path.stem}.h")
    return written


def ros_pkg_config_modules(model: NodeModel) -> list[str]:
    """pkg-config modules to compile and link the wrapper: roscpp and the
    standard message packages the node uses."""
    custom = custom_message_files(model)
    pkgs = sorted({m.package for m in model.messages
                   if not m.is_pseudo and m.name not in custom})
    return ["roscpp", *pkgs]


def subscribed(model: NodeModel) -> list[Topic]:
    return [t for t in model.topics if t.direction == "subscribe"]


def published(model: NodeModel) -> list[Topic]:
    return [t for t in model.topics if t.direction == "publish"]


def catkin_package_name(model: NodeModel) -> str:
    """A REP 144 package name for the node: lowercase letters, digits and
    underscores, starting with a letter."""
    name = re.sub(r"[^a-z0-9_]", "_", model.name.lower())
    if not name[:1].isalpha():
        name = "node_" + name
    return name


@dataclass(frozen=True)
class CatkinController:
    """How the catkin package compiles the controller, as ``pyrosgen build``
    does: its sources (package-relative), the C standard, the user's flags,
    include folders (absolute) and libraries."""

    c_sources: list[str] = field(default_factory=list)
    cxx_sources: list[str] = field(default_factory=list)
    std: str = "c11"
    cflags: list[str] = field(default_factory=list)
    cxxflags: list[str] = field(default_factory=list)
    includes: list[str] = field(default_factory=list)
    ldflags: list[str] = field(default_factory=list)
    libs: list[str] = field(default_factory=list)
    #: the controller is generated from a block diagram: compiled with
    #: :data:`IEEE_CFLAGS` after the user's flags
    generated: bool = False


_CMAKE_WORD = re.compile(r"^[A-Za-z0-9_=+,./:@%-]+$")


#: The flags ``pyrosgen build`` compiles the glue and the wrapper with (the
#: catkin package uses the same; pyrosgen.ros.build imports them).
#: ``-ffp-contract=off``: no fused multiply-add (``a*b+c`` rounded once) even
#: where the target has one (``-march=haswell``); ``-fexcess-precision=standard``:
#: no value kept wider than its type (C11 5.2.4.2.2; a no-op with x86-64's SSE
#: arithmetic, but GNU dialects default to ``fast``): the IEEE semantics of
#: the proofs, whatever flags the user adds (DESIGN.md section 7).
IEEE_CFLAGS = ("-ffp-contract=off", "-fexcess-precision=standard")
GLUE_CFLAGS = ("-std=c11", "-O2", "-Wall", "-Wextra", "-Werror", "-pedantic", *IEEE_CFLAGS)
WRAPPER_CXXFLAGS = ("-std=c++14", "-O2", "-Wall", "-Wextra", "-Werror", "-pthread")

_MSG_BUILTINS = {"bool", "int8", "uint8", "int16", "uint16", "int32", "uint32", "int64", "uint64",
                 "float32", "float64", "string", "time", "duration", "char", "byte"}


def _msg_deps(package: str, texts: list[str]) -> list[str]:
    """The message packages the ``.msg`` texts ``texts`` use."""
    deps: set[str] = set()
    for text in texts:
        for line in text.splitlines():
            line = line.split("#", 1)[0].strip()
            if not line or "=" in line:
                continue
            ty = line.split()[0].split("[", 1)[0]
            if "/" in ty:
                deps.add(ty.split("/", 1)[0])
            elif ty == "Header":
                deps.add("std_msgs")
    deps.discard(package)
    return sorted(deps)


def catkin_paths(model: NodeModel) -> dict[str, str]:
    """Package-relative paths of the node package's sources."""
    n = _check_ident(model.name)
    return {"glue": f"src/{n}_glue.c", "wrapper": f"src/{n}_ros.cpp", "layout_check": f"src/{n}_layout_check.c",
            "types_header": f"include/{n}_types.h", "api_header": f"include/{n}_ros.h",
            "launch": f"launch/{n}.launch"}


def custom_message_packages(model: NodeModel) -> dict[str, Path]:
    """The message packages of the node's custom messages: name -> the
    folder holding their ``.msg`` files."""
    out: dict[str, Path] = {}
    for name, f in custom_message_files(model).items():
        out.setdefault(name.split("/", 1)[0], f.parent)
    return out


#: The maintainer of the node's package.xml when ``build --maintainer`` gives none.
DEFAULT_MAINTAINER = "pyrosgen <nobody@example.com>"
_MAINTAINER = re.compile(r"^([A-Za-z0-9][A-Za-z0-9 .,'()_+-]{0,99}?) <([A-Za-z0-9._%+-]{1,64}@[A-Za-z0-9-]{1,63}"
                         r"(?:\.[A-Za-z0-9-]{1,63})+)>$")


def parse_maintainer(text: str) -> tuple[str, str] | None:
    """``(name, email)`` of ``"Name <email>"``, or ``None`` if it is not
    one: a name of letters, digits, spaces and ``. , ' ( ) _ + -`` (at most
    100 characters, nothing XML would read as markup) and an e-mail address
    of the usual shape."""
    m = _MAINTAINER.fullmatch(text) if isinstance(text, str) else None
    return (m.group(1), m.group(2)) if m else None


def check_package_words(include_dirs: list[str], ctl: CatkinController, maintainer: str) -> tuple[str, str]:
    """Check what a node's package (catkin's or ROS 2's) prints besides the
    proved model: package-relative paths, words of CMakeLists.txt, the
    maintainer (``ValueError`` naming the first that is not one); returns
    the maintainer's ``(name, email)``."""
    for p in [*include_dirs, *ctl.c_sources, *ctl.cxx_sources]:
        if not re.match(r"^[A-Za-z0-9_./-]+$", p) or ".." in p.split("/"):
            raise ValueError(f"refusing to print {p!r} as a package-relative path")
    for w in [ctl.std, *ctl.cflags, *ctl.cxxflags, *ctl.includes, *ctl.ldflags, *ctl.libs]:
        if not _CMAKE_WORD.match(w):
            raise ValueError(f"refusing to print {w!r} in CMakeLists.txt")
    who = parse_maintainer(maintainer)
    if who is None:
        raise ValueError(f"refusing to print {maintainer!r} as a maintainer")
    return who


def render_package(model: NodeModel | ProvedNode, include_dirs: list[str], controller: CatkinController,
                   custom_pkgs: list[str], maintainer: str = DEFAULT_MAINTAINER) -> dict[str, str]:
    """The text files of the node's catkin package, by package-relative path:
    ``package.xml`` (maintained by ``maintainer``, ``"Name <email>"``),
    ``CMakeLists.txt`` (the sources at the paths of :func:`catkin_paths`,
    the controller's under ``controller/``, compiled as ``build`` compiles
    them) and ``launch/<node>.launch``; ``custom_pkgs`` are the message
    packages written next to it (the node's custom messages)."""
    ctl = controller
    who = check_package_words(include_dirs, ctl, maintainer)
    # roscpp (whose own messages, roscpp/Logger, a node may use) is a dependency already
    msg_pkgs = sorted({m.package for m in model.messages
                       if not m.is_pseudo and m.package not in custom_pkgs} - {"roscpp"})
    for p in [*msg_pkgs, *custom_pkgs]:
        _check_ident(p)
    paths = catkin_paths(model)
    ctx = {
        "source": source_label(model.source.name),
        "package": catkin_package_name(model),
        "node": model,
        "msg_pkgs": msg_pkgs,
        "custom_pkgs": sorted(custom_pkgs),
        "include_dirs": include_dirs,
        "controller": ctl,
        "glue_cflags": GLUE_CFLAGS,
        "ieee_cflags": IEEE_CFLAGS if ctl.generated else (),
        "wrapper_cxxflags": [f for f in WRAPPER_CXXFLAGS if not f.startswith("-std=")],
        "topics": list(model.topics),
        "maintainer_name": who[0],
        "maintainer_email": who[1],
        **paths,
    }
    for t in model.topics:
        _check_ident(t.c_name)
    return {
        "package.xml": render("package.xml.j2", **ctx),
        "CMakeLists.txt": render("CMakeLists.txt.j2", **ctx),
        paths["launch"]: render("node.launch.j2", **ctx),
    }


def render_msg_package(source: str, pkg: str, msgs: dict[str, str]) -> dict[str, str]:
    """``package.xml`` and ``CMakeLists.txt`` of the message package
    ``pkg`` (``message_generation``) whose ``.msg`` files are ``msgs``
    (file name -> text); ``source``: the model file's name."""
    _check_ident(pkg)
    for m in msgs:
        if not re.fullmatch(r"[A-Za-z][A-Za-z0-9_]*\.msg", m):
            raise ValueError(f"refusing to print {m!r} in CMakeLists.txt")
    deps = _msg_deps(pkg, [msgs[m] for m in sorted(msgs)])
    for d in deps:
        _check_ident(d)
    mctx = {"source": source_label(source), "package": pkg, "deps": deps, "msgs": sorted(msgs)}
    return {"package.xml": render("msg_package.xml.j2", **mctx),
            "CMakeLists.txt": render("msg_CMakeLists.txt.j2", **mctx)}


def render_catkin(model: NodeModel, include_dirs: list[str],
                  controller: CatkinController | None = None, maintainer: str = DEFAULT_MAINTAINER) -> dict[str, str]:
    """:func:`render_package` of the front end's ``model`` (its custom
    message packages found on its ``msg_paths``) and, for each of these,
    :func:`render_msg_package` under the keys ``../<pkg>/package.xml`` and
    ``../<pkg>/CMakeLists.txt`` (a sibling package)."""
    custom = custom_message_packages(model)
    out = render_package(model, include_dirs, controller or CatkinController(), sorted(custom), maintainer)
    for pkg, msg_dir in sorted(custom.items()):
        texts = {f.name: f.read_text(encoding="utf-8", errors="replace") for f in sorted(msg_dir.glob("*.msg"))}
        for rel, text in render_msg_package(model.source.name, pkg, texts).items():
            out[f"../{pkg}/{rel}"] = text
    return out


#: The keys of the manifest's ``build.package`` record (:func:`package_record`).
PACKAGE_RECORD_KEYS = ("include_dirs", "c_sources", "cxx_sources", "std", "cflags", "cxxflags", "includes",
                       "ldflags", "libs", "generated", "custom_pkgs", "maintainer")


def package_record(include_dirs: list[str], controller: CatkinController, custom_pkgs: list[str],
                   maintainer: str) -> dict:
    """What the node's catkin package is rendered from besides the proved
    model: recorded in the manifest (``build.package``) so that ``pyrosgen
    verify`` renders the package again without the model file."""
    return {"include_dirs": list(include_dirs), "c_sources": list(controller.c_sources),
            "cxx_sources": list(controller.cxx_sources), "std": controller.std, "cflags": list(controller.cflags),
            "cxxflags": list(controller.cxxflags), "includes": list(controller.includes),
            "ldflags": list(controller.ldflags), "libs": list(controller.libs), "generated": controller.generated,
            "custom_pkgs": sorted(custom_pkgs), "maintainer": maintainer}


def render_package_record(node: ProvedNode, record: object) -> dict[str, str]:
    """:func:`render_package` of ``node`` with the recorded ``record``
    (:func:`package_record`); ``ValueError`` naming the field if the record
    is not one."""
    ctl = controller_of_record(record)
    return render_package(node, record["include_dirs"], ctl, record["custom_pkgs"], record["maintainer"])


def controller_of_record(record: object) -> CatkinController:
    """The :class:`CatkinController` of a recorded ``build.package``
    (:func:`package_record`), checked key by key (``ValueError`` naming the
    field)."""
    if not isinstance(record, dict) or sorted(record) != sorted(PACKAGE_RECORD_KEYS):
        raise ValueError(f"build.package: not a record of the keys {', '.join(PACKAGE_RECORD_KEYS)}")
    for k in PACKAGE_RECORD_KEYS:
        v = record[k]
        ok = (isinstance(v, bool) if k == "generated" else isinstance(v, str) if k in ("std", "maintainer")
              else isinstance(v, list) and len(v) <= 10000 and all(isinstance(x, str) and len(x) <= 4096 for x in v))
        if not ok:
            raise ValueError(f"build.package.{k}: malformed")
    ctl = CatkinController(c_sources=record["c_sources"], cxx_sources=record["cxx_sources"], std=record["std"],
                           cflags=record["cflags"], cxxflags=record["cxxflags"], includes=record["includes"],
                           ldflags=record["ldflags"], libs=record["libs"], generated=record["generated"])
    return ctl

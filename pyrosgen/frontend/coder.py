"""``pyrosgen init --controller DIR -o MODEL.yaml``: a node model skeleton
from the controller's Embedded Coder header.

Embedded Coder writes the controller's interface into ``<Model>.h``: the
structs ``ExtU_<Model>_T`` (root inports) and ``ExtY_<Model>_T`` (root
outports), the globals ``<Model>_U`` and ``<Model>_Y``, and the functions
``<Model>_initialize`` and ``<Model>_step``.  This module reads them with a
real C parser: the header is run through the C preprocessor (``cpp``,
with the include path that ``pyrosgen build`` uses: ``DIR``, each of its
subfolders holding a header, such as Embedded Coder's
``slprj/ert/_sharedutils/``, then each ``--include`` folder; and the minimal
standard headers of ``fake_libc/``, so that the system's headers and their
extensions never reach the parser; :mod:`pyrosgen.frontend.csource`),
then parsed by pycparser; typedefs are resolved
(``real_T`` -> ``double``) and each field's type is mapped to a ROS
primitive (rule 4.3), or to a one-dimensional array of one
(``real32_T Scan[1081];`` is ``float32[1081]``, of 1 to 65,536 elements,
rule 4.15).  Fields that cannot be carried (arrays of arrays, buses, i.e.
structs, ``creal_T``, pointers, ``char``) are reported with their field and
the reason, and the model is not written.

The period comes from the generated code's sample time where it can be
found, in any source or header of the folder, compiled or not:
``ert_main.c``'s "with period 0.02 seconds" (``build`` leaves
``ert_main.c`` out, as it defines ``main``, but init reads it), a "Sample time: [0.02s,
0.0s]" comment, a "Fixed-step size: 0.02" comment, or a ``#define`` whose
comment says "sample time".  Otherwise the skeleton says so and leaves the
period to the user.

The skeleton has the controller section filled in, in the header's field
order, each field with the header's comment; topics and relations are
commented placeholders.  It passes ``pyrosgen check`` once they are
filled in.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from fractions import Fraction
from pathlib import Path

from pyrosgen.errors import UserError, escape
from pyrosgen.frontend import csource

__all__ = ["CoderError", "CoderInterface", "read_controller", "find_period", "skeleton", "FAKE_LIBC"]

#: The largest controller array (rule 4.15).
MAX_ARRAY = 65536

#: Minimal standard headers used instead of the system's.
FAKE_LIBC = csource.FAKE_LIBC

#: Largest source file init reads (a header or a .c of Embedded Coder is
#: far smaller; a larger one is refused rather than read whole).
MAX_SOURCE_SIZE = 16 * 1024 * 1024

#: Longest sample time text read (``0.05``, ``5.0E-2``) and largest
#: exponent: ``1e999999999`` would take minutes to convert exactly.
_MAX_TIME_TEXT = 32
_MAX_TIME_EXPONENT = 20

#: The period range of rule 4.2 (milliseconds).
_MAX_PERIOD_MS = 3_600_000

#: Typedef names of Embedded Coder with a fixed meaning (checked before the
#: C type they stand for: ``boolean_T`` is an ``unsigned char``).
CODER_TYPES = {
    "boolean_T": "bool", "real_T": "float64", "real64_T": "float64", "real32_T": "float32",
    "int8_T": "int8", "uint8_T": "uint8", "int16_T": "int16", "uint16_T": "uint16",
    "int32_T": "int32", "uint32_T": "uint32", "int64_T": "int64", "uint64_T": "uint64",
    "_Bool": "bool", "bool": "bool",
}
#: C types (after typedefs) and their ROS primitive.
C_TYPES = {
    ("double",): "float64", ("float",): "float32", ("_Bool",): "bool",
    ("signed", "char"): "int8", ("unsigned", "char"): "uint8",
    ("short",): "int16", ("short", "int"): "int16", ("signed", "short"): "int16",
    ("unsigned", "short"): "uint16", ("unsigned", "short", "int"): "uint16",
    ("int",): "int32", ("signed", "int"): "int32", ("signed",): "int32",
    ("unsigned", "int"): "uint32", ("unsigned",): "uint32",
    ("long", "long"): "int64", ("long", "long", "int"): "int64", ("signed", "long", "long"): "int64",
    ("unsigned", "long", "long"): "uint64", ("unsigned", "long", "long", "int"): "uint64",
    ("int8_t",): "int8", ("uint8_t",): "uint8", ("int16_t",): "int16", ("uint16_t",): "uint16",
    ("int32_t",): "int32", ("uint32_t",): "uint32", ("int64_t",): "int64", ("uint64_t",): "uint64",
}
_WHY = {
    "creal_T": "a complex number (creal_T): ROS has no complex primitive",
    "creal32_T": "a complex number (creal32_T): ROS has no complex primitive",
    "char_T": "char_T: its signedness is the compiler's; use int8_T or uint8_T",
}


class CoderError(UserError):
    """The controller folder's header cannot give a model (exit 1)."""

    def __init__(self, summary: str, lines: list[str] | tuple[str, ...] = ()):
        self.summary = summary
        self.lines = tuple(lines)
        super().__init__(summary + "".join(f"\n  {ln}" for ln in self.lines))

    def report(self, ctx) -> list[str]:
        return [f"pyrosgen: error: {self.summary}", *(f"  {escape(ln, keep_quotes=True)}" for ln in self.lines)]


@dataclass
class CoderField:
    name: str
    where: str                #: ``file:line`` of its declaration
    prim: str | None          #: ROS primitive (of an array's elements), or None when it cannot be carried
    c_type: str               #: as written in the header
    comment: str = ""
    why: str = ""             #: the reason when ``prim`` is None
    size: int | None = None   #: the size of a one-dimensional array (rule 4.15), else None

    @property
    def type_text(self) -> str:
        """The type as a node model writes it: ``float64``, ``float32[1081]``."""
        return f"{self.prim}[{self.size}]" if self.size is not None else str(self.prim)


@dataclass
class CoderInterface:
    """The controller interface read from ``header``."""

    model: str
    header: Path
    inputs: list[CoderField]
    outputs: list[CoderField]
    functions: list[str] = field(default_factory=list)
    period_ms: int | None = None
    period_source: str = ""
    notes: list[str] = field(default_factory=list)


def _read_source(path: Path) -> str:
    """The text of the source file ``path``, refused (a user error) when it
    is larger than :data:`MAX_SOURCE_SIZE` (a sparse 20 GB file was read
    whole, MemoryError) or not a regular file."""
    import os
    import stat

    try:
        st = os.stat(path)
    except OSError as exc:
        raise CoderError(f"{path}: cannot be read: {exc.strerror or exc}") from None
    if not stat.S_ISREG(st.st_mode):
        raise CoderError(f"{path}: is not a regular file")
    if st.st_size > MAX_SOURCE_SIZE:
        raise CoderError(f"{path}: is {st.st_size:,} bytes; init reads source files of at most "
                         f"{MAX_SOURCE_SIZE // (1024 * 1024)} MiB (move it out of the controller folder)")
    try:
        with open(path, "rb") as fh:
            data = fh.read(MAX_SOURCE_SIZE + 1)
    except OSError as exc:
        raise CoderError(f"{path}: cannot be read: {exc.strerror or exc}") from None
    if len(data) > MAX_SOURCE_SIZE:
        raise CoderError(f"{path}: is larger than {MAX_SOURCE_SIZE // (1024 * 1024)} MiB; init reads source "
                         "files of at most that size")
    return data.decode("utf-8", errors="replace")


def _preprocess(header: Path, includes: list[Path]) -> str:
    try:
        return csource.preprocess(header, includes)
    except csource.PreprocessorError as exc:
        raise CoderError(str(exc), exc.lines) from None


def _comment(text: str, name: str) -> str:
    m = re.search(rf"\b{re.escape(name)}\s*(?:\[[^\]]*\])?\s*;[ \t]*/\*(.*?)\*/", text)
    return " ".join(m.group(1).split()) if m else ""


def _map_field(decl, typedefs: dict, raw_text: str) -> CoderField:
    name = decl.name
    where = f"{Path(decl.coord.file).name}:{decl.coord.line}" if decl.coord is not None else "?"
    written = _type_text(decl.type)
    comment = _comment(raw_text, name)
    prim, size, why = _map_type(decl.type, typedefs, written)
    if decl.bitsize is not None:
        # uint32_T A : 3; the layout of bitfields is the compiler's
        prim, size, why = None, None, (f"a bitfield of {_type_text(decl.bitsize)} bits: its layout is "
                                       "the compiler's; the glue carries whole fields")
    return CoderField(name, where, prim, written, comment, why, size)


def _array_size(dim) -> tuple[int | None, str]:
    """The size of a one-dimensional array from its dimension (an integer
    constant, as Embedded Coder writes it), or why it is not one."""
    from pycparser import c_ast

    if dim is None:
        return None, "an array without a size: a controller array has a fixed size (rule 4.15)"
    if not (isinstance(dim, c_ast.Constant) and dim.type in ("int", "unsigned int", "long int",
                                                             "unsigned long int")):
        return None, f"an array whose size ({_type_text(dim)}) is not an integer constant (rule 4.15)"
    m = re.fullmatch(r"(0[xX][0-9a-fA-F]+|[0-9]+)[uUlL]*", dim.value)
    if m is None:
        return None, f"an array whose size ({dim.value}) is not an integer constant (rule 4.15)"
    text = m.group(1)
    n = int(text, 16) if text[:2] in ("0x", "0X") else int(text, 8) if len(text) > 1 and text[0] == "0" \
        else int(text)
    if not 1 <= n <= MAX_ARRAY:
        return None, (f"an array of {n} elements: a controller array has 1 to {MAX_ARRAY} elements "
                      "(rule 4.15)")
    return n, ""


def _map_type(t, typedefs: dict, written: str, array_ok: bool = True) -> tuple[str | None, int | None, str]:
    """``(prim, size, why)`` of a field's type ``t``: a ROS primitive, or a
    one-dimensional array of one (``size`` its elements, rule 4.15); else
    ``prim`` is ``None`` and ``why`` says why."""
    from pycparser import c_ast

    if isinstance(t, c_ast.ArrayDecl):
        if not array_ok:
            return None, None, ("an array of arrays: a controller array has one dimension (rule 4.15); "
                                "flatten it")
        size, why = _array_size(t.dim)
        if size is None:
            return None, None, why
        prim, _, why = _map_type(t.type, typedefs, _type_text(t.type), array_ok=False)
        if prim is None:
            return None, None, why if why.startswith("an array of arrays") else f"an array whose elements are not carried: {why}"
        return prim, size, ""
    if isinstance(t, c_ast.PtrDecl):
        return None, None, "a pointer"
    if not isinstance(t, c_ast.TypeDecl):
        return None, None, f"an unsupported declaration ({type(t).__name__})"
    inner = t.type
    if isinstance(inner, (c_ast.Struct, c_ast.Union)):
        return None, None, "a bus (a struct): the glue carries scalar fields and arrays of them"
    if isinstance(inner, c_ast.Enum):
        return None, None, "an enumeration: its size is the compiler's"
    names = tuple(inner.names)
    seen = set()
    while True:
        if len(names) == 1 and names[0] in CODER_TYPES:
            return CODER_TYPES[names[0]], None, ""
        if len(names) == 1 and names[0] in _WHY:
            return None, None, _WHY[names[0]]
        if names in C_TYPES:
            return C_TYPES[names], None, ""
        if len(names) == 1 and names[0] in typedefs and names[0] not in seen:
            seen.add(names[0])
            target = typedefs[names[0]]
            if isinstance(target, c_ast.TypeDecl) and isinstance(target.type, c_ast.IdentifierType):
                names = tuple(target.type.names)
                continue
            if isinstance(target, c_ast.TypeDecl) and isinstance(target.type, (c_ast.Struct, c_ast.Union)):
                why = _WHY.get(written, f"a bus (struct type {written}): the glue carries scalar fields "
                                        "and arrays of them")
                return None, None, why
            if isinstance(target, c_ast.ArrayDecl):
                # an array type (typedef real_T vec6_T[6];)
                return _map_type(target, typedefs, written, array_ok)
            return None, None, f"type {written} is not a scalar"
        if "char" in names and "signed" not in names and "unsigned" not in names:
            return None, None, "plain char: its signedness is the compiler's"
        if "long" in names and names.count("long") == 1:
            return None, None, "long: its size differs between platforms"
        return None, None, f"type {' '.join(names)} has no ROS primitive"


def _type_text(t) -> str:
    from pycparser import c_generator

    try:
        return re.sub(r" \[", "[", " ".join(c_generator.CGenerator().visit(t).split())) or "?"
    except Exception:  # noqa: BLE001 - only for messages
        return "?"


def _struct_fields(decl) -> list | None:
    from pycparser import c_ast

    t = decl.type
    if isinstance(t, c_ast.TypeDecl) and isinstance(t.type, c_ast.Struct) and t.type.decls is not None:
        return list(t.type.decls)
    return None


_PERIOD_PATTERNS = [
    (re.compile(r"with[\s*]+period\s+([0-9.]+(?:[eE][+-]?[0-9]+)?)\s+seconds"), "the rate of rt_OneStep"),
    (re.compile(r"Sample time:\s*\[\s*([0-9.]+(?:[eE][+-]?[0-9]+)?)\s*s"), "a sample time comment"),
    (re.compile(r"Fixed-step size:\s*([0-9.]+(?:[eE][+-]?[0-9]+)?)"), "the fixed-step size"),
    (re.compile(r"#define\s+\w+\s+\(?\s*([0-9.]+(?:[eE][+-]?[0-9]+)?)\s*\)?\s*/\*[^*]*sample time", re.I),
     "a #define commented as the sample time"),
]


def _find_period(folder: Path, files: list[Path]) -> tuple[int | None, str, list[str]]:
    notes = []
    for pattern, what in _PERIOD_PATTERNS:
        for f in files:
            text = _read_source(f)
            m = pattern.search(text)
            if not m:
                continue
            line = text.count("\n", 0, m.start()) + 1
            where = f"{f.name}:{line}"
            exponent = re.search(r"[eE]([+-]?[0-9]+)$", m.group(1))
            if len(m.group(1)) > _MAX_TIME_TEXT or (exponent and abs(int(exponent.group(1))) > _MAX_TIME_EXPONENT):
                notes.append(f"{where}: sample time {m.group(1)[:_MAX_TIME_TEXT]}{'...' if len(m.group(1)) > _MAX_TIME_TEXT else ''} s "
                             "is not a number init reads (too long, or its exponent is beyond "
                             f"+/-{_MAX_TIME_EXPONENT}); period_ms left for you to set")
                return None, "", notes
            try:
                seconds = Fraction(m.group(1))
            except (ValueError, ZeroDivisionError):
                continue
            ms = seconds * 1000
            if ms > _MAX_PERIOD_MS:
                notes.append(f"{where}: sample time {m.group(1)} s is longer than {_MAX_PERIOD_MS:,} ms, the "
                             "longest period (rule 4.2); period_ms left for you to set")
                return None, "", notes
            if ms <= 0 or ms.denominator != 1:
                notes.append(f"{where}: sample time {m.group(1)} s is not a whole number of milliseconds; "
                             "period_ms left for you to set")
                return None, "", notes
            return int(ms), f"{what}, {where}: {m.group(1)} s", notes
    return None, "", notes


def find_period(folder: Path, files: list[Path]) -> tuple[int | None, str, list[str]]:
    """``(period_ms, where, notes)``: the controller's base rate from the
    first of ``files`` (sources or headers, compiled or not: ``build``
    asks too, ``ert_main.c`` included) that states it, the patterns tried
    in the order of :data:`_PERIOD_PATTERNS`; ``None`` when none does or
    it is not whole milliseconds (a note says so)."""
    return _find_period(folder, files)


def read_controller(folder: str | Path, name: str | None = None,
                    includes: list[str | Path] | tuple[str | Path, ...] = ()) -> CoderInterface:
    """Read the Embedded Coder interface of the controller in ``folder``
    (the model ``name``, or the only one whose header defines
    ``ExtU_<Model>_T`` and ``ExtY_<Model>_T``).  The folder is searched as
    ``pyrosgen build`` searches it (:mod:`pyrosgen.frontend.csource`): its
    subfolders too (``slprj/ert/_sharedutils``), every folder holding a
    header on the include path, then ``includes`` (``--include``: relative
    to ``folder``, or absolute)."""
    from pycparser import c_ast, c_parser

    try:
        from pycparser.c_parser import ParseError
    except ImportError:  # pycparser 2.x
        from pycparser.plyparser import ParseError

    folder = Path(folder)
    if not folder.is_dir():
        raise CoderError(f"{folder}: the controller folder does not exist or is not a folder")
    files = csource.controller_files(folder)
    headers = [p for p in files if p.suffix == ".h"]
    search = csource.include_dirs(folder, files)
    for inc in includes:
        d = Path(inc) if Path(inc).is_absolute() else folder / inc
        if not d.is_dir():
            raise CoderError(f"--include {inc}: {d} is not a folder")
        search.append(d)
    candidates: list[tuple[str, Path]] = []
    for h in headers:
        text = _read_source(h)
        for m in re.finditer(r"\bExtU_(\w+)_T\s*;", text):
            if re.search(rf"\bExtY_{re.escape(m.group(1))}_T\s*;", text):
                candidates.append((m.group(1), h))
    if name is not None:
        candidates = [c for c in candidates if c[0] == name]
    if not candidates:
        want = f"ExtU_{name}_T and ExtY_{name}_T" if name else "ExtU_<Model>_T and ExtY_<Model>_T"
        raise CoderError(f"{folder}: no header defines {want} (the Embedded Coder interface of a model "
                         "with root inports and outports)")
    models = sorted({c[0] for c in candidates})
    if len(models) > 1:
        raise CoderError(f"{folder}: several models ({', '.join(models)}); choose one with --name")
    model, header = candidates[0]
    raw = _read_source(header)
    text = _preprocess(header, [header.parent, *(d for d in search if d != header.parent)])
    try:
        ast = c_parser.CParser().parse(text, filename=str(header))
    except ParseError as exc:
        raise CoderError(f"{header}: error: cannot parse the preprocessed header: {exc}") from None
    typedefs: dict[str, object] = {}
    structs: dict[str, list] = {}
    externs: dict[str, str] = {}
    functions: list[str] = []
    for ext in ast.ext:
        if isinstance(ext, c_ast.Typedef):
            typedefs[ext.name] = ext.type
            fields = _struct_fields(ext)
            if fields is not None:
                structs[ext.name] = fields
        elif isinstance(ext, c_ast.Decl):
            if isinstance(ext.type, c_ast.FuncDecl):
                functions.append(ext.name)
            elif isinstance(ext.type, c_ast.TypeDecl) and isinstance(ext.type.type, c_ast.IdentifierType):
                externs[ext.name] = " ".join(ext.type.type.names)
    problems, sides = [], {}
    for side, tdname, var in (("inputs", f"ExtU_{model}_T", f"{model}_U"), ("outputs", f"ExtY_{model}_T", f"{model}_Y")):
        if tdname not in structs:
            raise CoderError(f"{header}: {tdname} is not a struct with fields")
        if externs.get(var) != tdname:
            problems.append(f"{header.name}: {var} is not declared as extern {tdname} {var};")
        fields = [_map_field(d, typedefs, raw) for d in structs[tdname]]
        for f in fields:
            if f.prim is None:
                problems.append(f"{f.where}: {tdname}.{f.name} ({f.c_type}): {f.why}")
        sides[side] = fields
    for fn in (f"{model}_initialize", f"{model}_step"):
        if fn not in functions:
            problems.append(f"{header.name}: no declaration of {fn}(void)")
    if problems:
        raise CoderError(f"{header}: the controller's interface cannot be carried as it is "
                         f"({len(problems)} problems)", problems)
    # every source, compiled or not: ert_main.c, which build leaves out, has the base rate
    period, period_source, notes = _find_period(folder, [header] + [p for p in files if p != header])
    return CoderInterface(model, header, sides["inputs"], sides["outputs"], functions, period, period_source, notes)


def _yaml_comment(text: str) -> str:
    return "".join(ch if ch.isprintable() and ch.isascii() else "?" for ch in text)


def _yaml_name(name: str) -> str:
    """A C name as a YAML plain scalar, quoted when YAML 1.1 would read it
    as something else than this text (``null``, ``on``, ``yes``, ``True``
    are a null and booleans)."""
    import yaml

    return name if yaml.safe_load(name) == name else f"'{name}'"


def skeleton(iface: CoderInterface, folder: Path, node_name: str | None = None) -> str:
    """The text of the node model skeleton."""
    m = iface.model
    node = node_name or re.sub(r"[^a-z0-9_]", "_", m.lower()) + "_node"
    if not re.fullmatch(r"[a-z][a-z0-9_]*", node):
        node = "controller_node"
    src = _yaml_comment(str(iface.header.relative_to(folder) if iface.header.is_relative_to(folder) else iface.header.name))
    out = [
        f"# Node model skeleton written by `pyrosgen init` from the Embedded Coder header {src}",
        f"# of the controller folder (ExtU_{m}_T, ExtY_{m}_T, {m}_initialize, {m}_step).",
        "# Declare the topics, relate their fields to the controller's inputs and outputs,",
        "# then: pyrosgen check THIS_FILE",
        "node:",
        f"  name: {node}",
    ]
    if iface.period_ms is not None:
        out.append(f"  period_ms: {iface.period_ms}    # from {_yaml_comment(iface.period_source)}")
    else:
        out.append("  period_ms:    # the sample time was not found in the controller folder: "
                   "set the period in milliseconds")
    out += ["controller:", f"  name: {_yaml_name(m)}", "  inputs:", f"    name: {m}_U", "    fields:"]
    width = max(len(_yaml_name(f.name)) for f in iface.inputs + iface.outputs) + 1
    twidth = max(8, *(len(f.type_text) for f in iface.inputs + iface.outputs))
    for f in iface.inputs:
        out.append(f"      {_yaml_name(f.name) + ':':<{width}} {f.type_text:<{twidth}}  # {_yaml_comment(f.c_type)}"
                   + (f": {_yaml_comment(f.comment)}" if f.comment else ""))
    out += ["  outputs:", f"    name: {m}_Y", "    fields:"]
    for f in iface.outputs:
        out.append(f"      {_yaml_name(f.name) + ':':<{width}} {f.type_text:<{twidth}}  # {_yaml_comment(f.c_type)}"
                   + (f": {_yaml_comment(f.comment)}" if f.comment else ""))
    first_out = iface.outputs[0]
    arrays = [f for f in iface.inputs + iface.outputs if f.size is not None]
    out += [
        "topics:",
        "  # one line per topic, for example:",
        "  # - {name: /sensor, direction: subscribe, type: geometry_msgs/TwistStamped, queue_size: 1}",
        "  # - {name: /command, direction: publish, type: geometry_msgs/TwistStamped, queue_size: 1}",
        *(["  # an array is related to a variable-length array of as many elements at most, e.g.",
           "  # - {name: /scan, direction: subscribe, type: sensor_msgs/LaserScan, queue_size: 1, "
           f"max_length: {{ranges: {arrays[0].size}}}}}"] if arrays else []),
        "relations:",
        "  inputs:      # every controller input (each element of an array) is fed by exactly one message field:",
        *(_input_placeholder(f) for f in iface.inputs),
        "  outputs:     # controller outputs into fields of published messages, for example:",
        _output_placeholder(first_out),
    ]
    return "\n".join(out) + "\n"


def _input_placeholder(f: CoderField) -> str:
    """A commented relation feeding controller input ``f``: a scalar from a
    scalar field, an array (rule 4.15) from a whole array of as many
    elements, or element by element."""
    if f.size is None:
        return f"    # - {{topic: /sensor, field: twist.linear.x, input: {_yaml_name(f.name)}}}"
    field = "header.frame_id" if f.prim == "uint8" else "ranges"
    what = "a string of at most" if f.prim == "uint8" else "a whole array of"
    return (f"    # - {{topic: /scan, field: {field}, input: {_yaml_name(f.name)}}}    # {f.type_text}: {what} "
            f"{f.size} {f.prim} (max_length {f.size}), or element by element: input: \"{f.name}[0]\"")


def _output_placeholder(f: CoderField) -> str:
    """A commented relation writing controller output ``f`` into a field."""
    if f.size is None:
        return f"    # - {{output: {_yaml_name(f.name)}, topic: /command, field: twist.linear.x}}"
    return (f"    # - {{output: {_yaml_name(f.name)}, topic: /command, field: data}}    # {f.type_text}: into a whole array "
            f"of {f.size} {f.prim} (max_length {f.size}; its length from a uint32 output, derived: length), "
            f"or element by element: output: \"{f.name}[0]\"")

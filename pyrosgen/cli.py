"""The ``pyrosgen`` command line.

``main(argv)`` returns the exit code: 0 success, 1 invalid model or other user
error (bad usage, unreadable file), 2 proof or tool failure and internal
errors.  Each subcommand is a function ``cmd_<name>(args) -> int`` registered
in :func:`build_parser`; further commands (``generate``, ``build``,
``diagram``) are added the same way.

Unexpected exceptions print ``pyrosgen: internal error: ...`` and exit 2; set
``PYROSGEN_DEBUG=1`` to get the Python traceback instead.
"""

from __future__ import annotations

import argparse
import contextlib
import os
import signal
import sys
from collections.abc import Callable, Sequence

from pyrosgen import console
from pyrosgen.errors import Context, PyrosgenError, UserError

__all__ = ["main", "build_parser", "EXIT_OK", "EXIT_USER", "EXIT_TOOL"]

EXIT_OK = 0
EXIT_USER = 1
EXIT_TOOL = 2


class _UsageError(Exception):
    """Bad command-line usage (exit 1, it is a user error)."""


class _Parser(argparse.ArgumentParser):
    """An ArgumentParser that raises instead of exiting on bad usage."""

    def error(self, message: str):  # noqa: D102 - argparse hook
        raise _UsageError(f"{self.format_usage()}{self.prog}: error: {message}")


def _plural(n: int, word: str) -> str:
    return f"{n} {word}" if n == 1 else f"{n} {word}s"


def _rows(relations) -> str:
    """`` (from N rows)`` when whole-array rows (rule 4.15) expanded into
    more relations than the model writes, else ``""``."""
    rows = len({r.pos for r in relations})
    return f" (from {_plural(rows, 'row')})" if rows != len(relations) else ""


def _print_warnings(model) -> None:
    """The front end's warnings about a valid model (rule 4.18: a ``qos``
    that the target ROS 1 ignores), on standard error."""
    for w in model.warnings:
        _print_err(str(w))


def cmd_check(args: argparse.Namespace) -> int:
    """``pyrosgen check MODEL.yaml``: validate only."""
    from pyrosgen.ros2.cli import load_for_target  # --ros2: ROS 2's messages (rule 4.17)

    model = load_for_target(args)
    _print_warnings(model)
    d = model.controller.diagram
    ctrl = (f"; controller: a block diagram of {_plural(len(d.blocks), 'block')}"
            f" ({_plural(len(d.states), 'state')})" if d is not None else "")
    timed = model.timed_topics
    if timed:
        ctrl += (f"; freshness: {_plural(len(timed), 'timed topic')}, "
                 f"{_plural(len(model.derived_relations), 'derived input')}")
    if model.stamps:
        ctrl += f"; stamped: {_plural(len(model.stamps), 'published topic')}"
    consts = [(t, s) for t in model.topics for s in t.strings]
    if consts:
        from pyrosgen.errors import show

        ctrl += f"; {_plural(len(consts), 'constant string')}: " + ", ".join(
            f"{t.name} {s.path_text} = {show(s.value)}" for t, s in consts)
    seqs = [(owner, fname, b) for owner, fname, b in model.bounded_fields if b.is_seq]
    if seqs:
        ctrl += f"; {_plural(len(seqs), 'variable-length array')}: " + ", ".join(
            f"{owner} {fname} ({b.seq_of[0]}[], at most {b.capacity}"
            + (f" of at most {b.elem_string_capacity} bytes" if b.elem_string_capacity is not None else "")
            + f"{', policy reject' if b.reject else ''})" for owner, fname, b in seqs)
    arrays = [(side, f) for side, io in (("input", model.controller.inputs), ("output", model.controller.outputs))
              for f in io.arrays]
    if arrays:
        ctrl += f"; {_plural(len(arrays), 'controller array')}: " + ", ".join(
            f"{side} {f.name} ({f.type_text})" for side, f in arrays)
    qos = [t for t in model.topics if not t.qos.is_default]
    if qos and getattr(args, "ros2", False):  # rule 4.18 (ROS 1: the warnings above)
        ctrl += "; QoS other than the default: " + ", ".join(
            f"{t.name} ({t.qos.reliability}, {t.qos.durability})" for t in qos)
    from pyrosgen.frontend.msgdeb import missing_headers

    # the model is valid; building it for ROS 1 needs roscpp's headers (not for ROS 2: rosidl's from the wheels)
    for m in ([] if getattr(args, "ros2", False) else missing_headers(model)):
        _print_err(f"{args.model}:{m.pos.line}:{m.pos.col}: note: {m.message()} (pyrosgen build needs it)")
    print(
        f"{args.model}: ok: node {model.name}, {_plural(len(model.topics), 'topic')}, "
        f"{_plural(len(model.input_relations), 'input relation')}{_rows(model.input_relations)}, "
        f"{_plural(len(model.output_relations), 'output relation')}{_rows(model.output_relations)}{ctrl}"
    )
    return EXIT_OK


def cmd_diagram(args: argparse.Namespace) -> int:
    """``pyrosgen diagram MODEL.yaml -o FILE``: draw the node's data flow."""
    from pathlib import Path

    from pyrosgen import diagram
    from pyrosgen.errors import escape
    from pyrosgen.frontend.validate import load_model

    try:
        fmt = diagram.output_format(args.output, args.format)
    except ValueError as exc:
        _print_err(f"pyrosgen diagram: error: {exc}")
        return EXIT_USER
    if Path(args.output).is_dir():
        _print_err(f"pyrosgen diagram: error: {escape(args.output)} is a directory; give a file name")
        return EXIT_USER
    model = load_model(args.model)
    try:
        diagram.write_diagram(model, args.output, fmt)
    except OSError as exc:
        _print_err(f"pyrosgen diagram: error: cannot write {escape(args.output)}: {exc.strerror or exc}")
        return EXIT_USER
    print(f"{escape(args.output)}: {fmt} diagram of node {model.name}")
    return EXIT_OK


def _progress(args: argparse.Namespace) -> Callable[[str], None] | None:
    if args.quiet:
        return None

    def say(line: str) -> None:
        _print_err(f"pyrosgen: {line}")

    return say


@contextlib.contextmanager
def _stopped_by_signals():
    """SIGTERM and SIGHUP stop a long command as Ctrl-C does: the work
    folder is removed, the tools' process groups are stopped
    (:mod:`pyrosgen.procs`), nothing is written, exit status 130."""

    def _terminated(signum, frame):
        raise KeyboardInterrupt

    previous = {}
    for sig in (signal.SIGTERM, signal.SIGHUP):
        try:
            previous[sig] = signal.signal(sig, _terminated)
        except ValueError:  # not in the main thread
            pass
    try:
        yield
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)


def cmd_generate(args: argparse.Namespace) -> int:
    """``pyrosgen generate MODEL.yaml -o DIR``: emit the Coq file, check the
    proof, write the C (see :mod:`pyrosgen.generate`)."""
    from pyrosgen.generate import generate

    with _stopped_by_signals():
        if getattr(args, "ros2", False):  # the target ROS 2 (pyrosgen.ros2, rule 4.17)
            from pyrosgen.ros2.cli import generate_ros2

            res = generate_ros2(args, _progress(args))
        else:
            res = generate(args.model, args.output, progress=_progress(args), keep_work=args.keep_work,
                           wp=args.wp)
    _print_warnings(res.model)
    print(f"pyrosgen: generated node {res.model.name} into {res.out_dir}")
    for path, rewritten in res.files:
        print(f"  {'written' if rewritten else 'unchanged':<10}{path}")
    print(f"  theorem   {res.theorem}: {res.theorem_kind}")
    print(f"            checked by coqc and coqchk; Print Assumptions: {res.assumptions}")
    _print_controller_theorems(res)
    if res.validation is not None:
        print(f"  printer   C text = AST dump (pycparser): {res.validation.summary()}")
    if res.wp is not None:
        print(f"  WP        {res.wp.summary()}")
    t = res.times
    # coqchk runs alongside the printing: "checking" ends when both did
    shown = {"checking": "checking alongside"}
    phases = ", ".join(f"{shown.get(k, k)} {t[k]:.2f} s"
                       for k in ("front end", "coqc", "printing", "checking", "wp") if k in t)
    print(f"  time      {phases}; total {t.get('total', 0.0):.2f} s")
    return EXIT_OK


def _print_controller_theorems(g) -> None:
    """The theorems about a block-diagram controller, if the node has one."""
    ctrl = getattr(g.record, "controller", None) if g.record is not None else None
    if ctrl:
        print(f"  theorem   {ctrl['wf']}: the diagram is well formed; its C ({ctrl['c']}) computes its step")
        print(f"  theorem   {ctrl['e2e']}: the node with the diagram as controller (T2 end to end)")
        if ctrl.get("linked"):
            print(f"  theorem   {ctrl['linked']}: the glue and the generated controller linked, one program (T8)")


def cmd_build(args: argparse.Namespace) -> int:
    """``pyrosgen build MODEL.yaml --controller DIR -o OUT``: generate and
    prove the glue, then compile and link a runnable ROS node (see
    :mod:`pyrosgen.ros.build`)."""
    import shlex

    from pyrosgen.ros.build import ControllerOptions, build

    def words(values: list[str] | None) -> tuple[str, ...]:
        return tuple(w for v in values or () for w in shlex.split(v))

    try:
        options = ControllerOptions(std=args.std, cflags=words(args.cflags), cxxflags=words(args.cxxflags),
                                    includes=tuple(args.include or ()), ldflags=words(args.ldflags),
                                    libs=words(args.libs),
                                    **({"maintainer": args.maintainer} if args.maintainer is not None else {}))
    except ValueError as exc:  # shlex: an unclosed quote
        raise UserError(f"controller flags: {exc}") from None
    if getattr(args, "ros2", False):  # the target ROS 2: a node over rcl (pyrosgen.ros2.build)
        from pyrosgen.ros2.cli import build_ros2_command

        with _stopped_by_signals():
            return build_ros2_command(args, options, _progress(args))
    with _stopped_by_signals():
        res = build(args.model, args.controller, args.output, progress=_progress(args), keep_work=args.keep_work,
                    wp=args.wp, options=options)
    _print_warnings(res.model)
    for line in res.warnings:
        _print_err(line)
    print(f"pyrosgen: built node {res.model.name} into {res.out_dir}")
    print(f"  binary    {res.binary}")
    rebuilt = [name for name, r in res.steps if r]
    reused = [name for name, r in res.steps if not r]
    print(f"  compiled  {', '.join(rebuilt) if rebuilt else 'nothing (all up to date)'}")
    if reused:
        print(f"  reused    {', '.join(reused)}")
    changed = sum(1 for _, w in res.files if w)
    print(f"  files     {changed} written, {len(res.files) - changed} unchanged")
    g = res.generated
    print(f"  generated {', '.join(p.name for p, _ in g.files)}")
    print(f"  theorem   {g.theorem}: {g.theorem_kind}")
    print(f"            checked by coqc and coqchk; Print Assumptions: {g.assumptions}")
    if g.wp is not None:
        print(f"  WP        {g.wp.summary()}")
    _print_controller_theorems(g)
    print(f"  layout    {res.model.controller.name}.h agrees with the glue (sizes, offsets, types)")
    t = res.times
    phases = ", ".join(f"{k} {t[k]:.2f} s" for k in (
        "generate", "wrapper", "layout check", "glue", "wrapper compile", "controller", "link and install") if k in t)
    print(f"  time      {phases}; total {t.get('total', 0.0):.2f} s")
    print(f"  run       ROS_MASTER_URI=http://127.0.0.1:11311 {res.binary}")
    return EXIT_OK


def _print_checks(report) -> None:
    for c in report.checks:
        print(f"  {'ok' if c.ok else 'FAILED':<8}{c.name:<9} {c.summary}")
        for line in c.details:
            print(f"          {line.strip()}")


def _positive_seconds(text: str) -> float:
    """``--timeout``'s value: a positive number of seconds."""
    try:
        v = float(text)
    except ValueError:
        v = float("nan")
    if not (0 < v < 1e7):
        raise argparse.ArgumentTypeError(f"{text!r}: not a positive number of seconds")
    return v


def cmd_verify(args: argparse.Namespace) -> int:
    """``pyrosgen verify OUT``: re-check an output folder on its own (see
    :mod:`pyrosgen.verify.recheck`)."""
    from pyrosgen.verify.recheck import VerifyFailed, verify_folder

    try:
        with _stopped_by_signals():
            report = verify_folder(args.folder, node=args.node, model=args.model, wp=args.wp,
                                   kernel=args.kernel, progress=_progress(args), timeout=args.timeout,
                                   rebuild=args.rebuild)
    except VerifyFailed as exc:
        print(f"pyrosgen: {exc.verify_report.folder} does NOT verify (node {exc.verify_report.node})")
        _print_checks(exc.verify_report)
        raise
    print(f"pyrosgen: {report.folder} verifies (node {report.node}); {report.seconds:.1f} s")
    _print_checks(report)
    return EXIT_OK


def cmd_init(args: argparse.Namespace) -> int:
    """``pyrosgen init --controller DIR -o MODEL.yaml``: a node model
    skeleton from the controller's Embedded Coder header (see
    :mod:`pyrosgen.frontend.coder`)."""
    import tempfile
    from pathlib import Path

    from pyrosgen.frontend.coder import read_controller, skeleton

    out = Path(args.output)
    if (out.exists() or out.is_symlink()) and not args.force:
        raise UserError(f"{out}: exists; pyrosgen init does not overwrite a model (use --force)")
    if out.exists() and not out.is_file():
        raise UserError(f"{out}: exists and is not a regular file")
    if not out.parent.is_dir():
        raise UserError(f"{out.parent}: the folder of the output file does not exist")
    iface = read_controller(args.controller, args.name, tuple(args.include or ()))
    text = skeleton(iface, Path(args.controller), args.node)
    fd, tmp = tempfile.mkstemp(prefix=f".{out.name}.", suffix=".tmp", dir=str(out.parent))
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as f:
            f.write(text)
        os.replace(tmp, out)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise
    print(f"pyrosgen: wrote {out}: controller {iface.model} from {iface.header}")
    print(f"  inputs    {len(iface.inputs)}: {', '.join(f'{f.name} ({f.type_text})' for f in iface.inputs)}")
    print(f"  outputs   {len(iface.outputs)}: {', '.join(f'{f.name} ({f.type_text})' for f in iface.outputs)}")
    if iface.period_ms is not None:
        print(f"  period    {iface.period_ms} ms, from {iface.period_source}")
    else:
        print("  period    not found in the controller folder: set period_ms")
    for note in iface.notes:
        print(f"  note      {note}")
    print(f"  next      declare the topics and relations in {out}, then: pyrosgen check {out}")
    return EXIT_OK


def cmd_library(args: argparse.Namespace) -> int:
    """``pyrosgen library``: the ROSGen library this pyrosgen checks proofs
    with: its folder and identity (as certificates record it)."""
    from pyrosgen import __version__
    from pyrosgen.proof.coqdriver import CoqDriver

    drv = CoqDriver()
    if args.path:
        print(drv.theories)
        return EXIT_OK
    drv.check_library()
    print(f"ROSGen library of pyrosgen {__version__}")
    print(f"  folder          {drv.theories}")
    print(f"  sources SHA-256 {drv.library_digest()}")
    return EXIT_OK


def version_text() -> str:
    """``pyrosgen X.Y.Z (ROSGen library <first 16 hex digits of its SHA-256>)``:
    the library identity a certificate records (``pyrosgen library`` shows
    it whole), computed from the library's sources, without building it."""
    from pyrosgen import __version__, resources
    from pyrosgen.proof.coqdriver import COQLIB_ENV, CoqDriver

    try:
        env = os.environ.get(COQLIB_ENV)
        theories = env if env else resources.coq_dir() / "theories"
        digest = CoqDriver(theories).library_digest()[:16]
    except OSError as exc:
        digest = f"unreadable: {exc.strerror or exc}"
    return f"pyrosgen {__version__} (ROSGen library {digest})"


class _Version(argparse.Action):
    """``--version``: print :func:`version_text` and exit 0."""

    def __init__(self, option_strings, dest=argparse.SUPPRESS, default=argparse.SUPPRESS, help=None):
        super().__init__(option_strings=option_strings, dest=dest, default=default, nargs=0, help=help)

    def __call__(self, parser, namespace, values, option_string=None):
        print(version_text())
        parser.exit(0)


def cmd_completion(args: argparse.Namespace) -> int:
    """``pyrosgen completion``: print the bash completion script (see
    :mod:`pyrosgen.completion`)."""
    from pyrosgen.completion import bash_script

    sys.stdout.write(bash_script(build_parser()))
    return EXIT_OK


_EXAMPLES = {
    "pyrosgen": """examples:
  pyrosgen check examples/landshark/landshark_controller.yaml
  pyrosgen generate examples/landshark/landshark_controller.yaml -o build/landshark
  pyrosgen build examples/landshark/landshark_controller.yaml --controller examples/landshark/controller -o build/landshark
  pyrosgen diagram examples/landshark/landshark_controller.yaml -o landshark.svg
  pyrosgen verify build/landshark

exit codes: 0 success, 1 invalid model or usage, 2 proof or tool failure.
'pyrosgen COMMAND --help' shows each command's options.""",
    "check": """examples:
  pyrosgen check examples/landshark/landshark_controller.yaml
  pyrosgen check my_node.yaml && echo valid

Every problem is reported as FILE:LINE:COL: error: MESSAGE; exit 1 if any.""",
    "diagram": """examples:
  pyrosgen diagram examples/landshark/landshark_controller.yaml -o landshark.svg
  pyrosgen diagram examples/multi/multi_node.yaml -o multi.dot      # Graphviz source
  pyrosgen diagram my_node.yaml -o out.img --format png""",
    "generate": """examples:
  pyrosgen generate examples/landshark/landshark_controller.yaml -o build/landshark
  pyrosgen generate examples/multi/multi_node.yaml -o build/multi --wp     # also Frama-C WP
  pyrosgen -v generate my_node.yaml -o out --keep-work                     # show commands, keep the Coq work dir

writes DIR/<node>.v, <node>_types.h, <node>_glue.c, <node>.sexp, <node>.model,
<node>.certificate.md, <node>.manifest.json, <node>.sha256 (and <node>_wp.c with --wp)
only if the node's DDC theorem was checked and is closed under the global context.""",
    "init": """examples:
  pyrosgen init --controller examples/landshark/controller -o my_node.yaml
  pyrosgen init --controller codegen/Robot_ert_rtw --name Robot -o robot.yaml
  pyrosgen init --controller codegen/Robot_ert_rtw --include ../slprj/ert/_sharedutils -o robot.yaml""",
    "verify": """examples:
  pyrosgen verify build/landshark                       # hashes, coqc/coqchk, re-printed C, wrapper
  pyrosgen verify build/landshark --model examples/landshark/landshark_controller.yaml --wp
  pyrosgen verify build/landshark --rebuild             # also rebuild bin/<node>, compare bit for bit

exit codes: 0 every check holds, 1 a check failed (each is named) or not an
output folder, 2 a tool is missing.""",
    "completion": """examples:
  source <(pyrosgen completion)                        # this shell
  pyrosgen completion > ~/.local/share/bash-completion/completions/pyrosgen   # every new shell""",
    "build": """examples:
  pyrosgen build examples/landshark/landshark_controller.yaml \\
      --controller examples/landshark/controller -o build/landshark
  ROS_MASTER_URI=http://127.0.0.1:11311 build/landshark/bin/landshark_controller""",
}


def build_parser() -> argparse.ArgumentParser:
    """The argument parser with one subparser per command."""
    from pyrosgen.ros2.cli import ROS2_HELP  # the --ros2 option (pyrosgen.ros2)

    parser = _Parser(
        prog="pyrosgen",
        description="Generate proven glue code for ROS 1 nodes from a node model.",
        epilog=_EXAMPLES["pyrosgen"],
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("-v", "--verbose", action="store_true",
                        help="show every external command (coqc, coqchk, ocamlopt, gcc, ...) as it runs")
    parser.add_argument("--version", action=_Version,
                        help="show pyrosgen's version and its ROSGen library's identity, and exit")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    sub.required = True

    p = sub.add_parser("check", epilog=_EXAMPLES["check"], formatter_class=argparse.RawDescriptionHelpFormatter, help="validate a node model", description="Validate a node model file.")
    p.add_argument("model", metavar="MODEL.yaml", help="the node model file")
    p.add_argument("--ros2", action="store_true", help=ROS2_HELP)
    p.set_defaults(func=cmd_check)

    p = sub.add_parser(
        "diagram",
        epilog=_EXAMPLES["diagram"], formatter_class=argparse.RawDescriptionHelpFormatter,
        help="draw a node's data flow with Graphviz",
        description="Draw the data flow of a node (topics, callbacks, glue, controller) with Graphviz.",
    )
    p.add_argument("model", metavar="MODEL.yaml", help="the node model file")
    p.add_argument("-o", "--output", required=True, metavar="FILE", help="output file (.svg, .png, .pdf or .dot)")
    p.add_argument("--format", choices=("svg", "png", "pdf", "dot"), help="output format (default: from the suffix of FILE)")
    p.set_defaults(func=cmd_diagram)

    p = sub.add_parser(
        "generate",
        epilog=_EXAMPLES["generate"], formatter_class=argparse.RawDescriptionHelpFormatter,
        help="emit the Coq file, check the proof, write the C",
        description=(
            "Generate the glue of a node: the per-node Coq file, checked by coqc "
            "(generate accepts the model; the node's theorem is proved, closed under "
            "the global context), and the C printed by Coq from the proved program."
        ),
    )
    p.add_argument("model", metavar="MODEL.yaml", help="the node model file")
    p.add_argument("-o", "--output", metavar="DIR", required=True, help="output directory")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress lines")
    p.add_argument(
        "--keep-work", action="store_true",
        help="keep the temporary work directory (next to DIR) for inspection",
    )
    p.add_argument(
        "--wp", action="store_true",
        help="also prove ACSL contracts generated from the model on the printed C with Frama-C WP",
    )
    p.add_argument("--ros2", action="store_true", help=ROS2_HELP)
    p.set_defaults(func=cmd_generate)

    p = sub.add_parser(
        "build",
        epilog=_EXAMPLES["build"], formatter_class=argparse.RawDescriptionHelpFormatter,
        help="generate, prove and compile a runnable ROS node",
        description=(
            "Build a ROS node: generate and prove the glue (as generate does), render "
            "the C API over roscpp, check the controller header's layout against the "
            "glue, compile and link OUT/bin/<node>, and write a catkin package in OUT."
        ),
    )
    p.add_argument("model", metavar="MODEL.yaml", help="the node model file")
    p.add_argument("--controller", metavar="DIR", default=None,
                   help="folder of the controller: <Controller>.h and its .c sources "
                        "(not for a model whose controller is a block diagram: its C is generated)")
    p.add_argument("-o", "--output", metavar="OUT", required=True, help="output directory")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress lines")
    p.add_argument(
        "--keep-work", action="store_true",
        help="keep the temporary work directory (next to OUT) for inspection",
    )
    p.add_argument(
        "--wp", action="store_true",
        help="also prove ACSL contracts generated from the model on the printed C with Frama-C WP",
    )
    p.add_argument("--ros2", action="store_true", help=ROS2_HELP)
    g = p.add_argument_group("compiling the controller (also written into the catkin package); "
                             "write flags with '=': --cflags=-DX=1, --libs=-lrt")
    g.add_argument("--std", default="c11", metavar="STD", help="C standard of the controller's .c files (default c11)")
    g.add_argument("--cflags", action="append", metavar="FLAGS", help="extra flags for the controller's .c files")
    g.add_argument("--cxxflags", action="append", metavar="FLAGS", help="extra flags for the controller's .cpp files")
    g.add_argument("--include", action="append", metavar="DIR",
                   help="an include folder for the controller (relative to its folder, or absolute)")
    g.add_argument("--ldflags", action="append", metavar="FLAGS", help="extra link flags")
    g.add_argument("--libs", action="append", metavar="LIBS", help="extra libraries, e.g. -lrt")
    p.add_argument("--maintainer", metavar="'NAME <EMAIL>'", default=None,
                   help="the maintainer written into the catkin package's package.xml "
                        "(default: 'pyrosgen <nobody@example.com>')")
    p.set_defaults(func=cmd_build)

    p = sub.add_parser(
        "verify",
        epilog=_EXAMPLES["verify"], formatter_class=argparse.RawDescriptionHelpFormatter,
        help="re-check an output folder on its own",
        description=(
            "Re-check an output folder of generate or build, read as hostile input: the "
            "recorded hashes, the library identity, the .v against the template before "
            "anything compiles it, coqc and coqchk of the .v with its theorems' statements "
            "and assumptions confirmed by Coq, the C re-printed from the proof "
            "and compared with the files, the wrapper against the proved model; with "
            "--model, the proved model against a model file; with --wp, Frama-C WP. "
            "The folder is not written."
        ),
    )
    p.add_argument("folder", metavar="OUT", help="output folder of pyrosgen generate or build")
    p.add_argument("--node", metavar="NAME", help="the node to check when OUT holds several")
    p.add_argument("--model", metavar="MODEL.yaml", help="also check that the proved model is this file's")
    p.add_argument("--wp", action="store_true", help="also re-run Frama-C WP on the folder's ACSL contracts")
    p.add_argument("--kernel", action="store_true",
                   help="coqchk re-checks the node's vm_compute steps in its own conversion, not in Coq's "
                        "bytecode machine (independent of it; slower for large models)")
    p.add_argument("--timeout", metavar="SECONDS", type=_positive_seconds, default=600.0,
                   help="stop each tool run (coqc, coqchk, the OCaml compiler, the printer) after SECONDS "
                        "and fail its check (default 600)")
    p.add_argument("--rebuild", action="store_true",
                   help="also compile the node's binary again from the folder's files with the recorded "
                        "compile commands (checked word by word first) and compare it with bin/NODE bit for bit")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress lines")
    p.set_defaults(func=cmd_verify)

    p = sub.add_parser(
        "init",
        epilog=_EXAMPLES["init"], formatter_class=argparse.RawDescriptionHelpFormatter,
        help="write a node model skeleton from a controller's Embedded Coder header",
        description=(
            "Read the Embedded Coder interface of the controller in DIR (ExtU_<Model>_T, "
            "ExtY_<Model>_T, <Model>_U, <Model>_Y, <Model>_initialize, <Model>_step) with a C "
            "parser and write a node model with the controller section filled in and the "
            "period from the sample time where it is found; topics and relations are left "
            "as commented placeholders."
        ),
    )
    p.add_argument("--controller", metavar="DIR", required=True, help="the controller folder (Embedded Coder output)")
    p.add_argument("-o", "--output", metavar="MODEL.yaml", required=True, help="the model file to write")
    p.add_argument("--name", metavar="MODEL", help="the Simulink model, when DIR holds several")
    p.add_argument("--node", metavar="NAME", help="the node's name (default: <model>_node)")
    p.add_argument("--include", action="append", metavar="DIR",
                   help="an include folder for the controller's headers (relative to its folder, or absolute; "
                        "as for build; its subfolders holding headers, e.g. slprj/ert/_sharedutils, are searched "
                        "without it)")
    p.add_argument("--force", action="store_true", help="overwrite MODEL.yaml if it exists")
    p.set_defaults(func=cmd_init)

    p = sub.add_parser(
        "library", help="show the Coq library proofs are checked with",
        description="Show the ROSGen library's folder and the SHA-256 of its sources (a certificate's library identity).",
    )
    p.add_argument("--path", action="store_true", help="print only the folder (for coqc -R FOLDER ROSGen)")
    p.set_defaults(func=cmd_library)

    p = sub.add_parser(
        "completion", help="print the bash completion script",
        epilog=_EXAMPLES["completion"], formatter_class=argparse.RawDescriptionHelpFormatter,
        description="Print a bash completion script generated from pyrosgen's options "
                    "(make deps installs it into .venv/share/bash-completion/completions/pyrosgen).",
    )
    p.set_defaults(func=cmd_completion)

    from pyrosgen.system.cli import add_parser as add_system_parser

    add_system_parser(sub, _Parser)
    return parser


def _print_err(text: str) -> None:
    text = console.colourize(text)
    sys.stderr.write(text if text.endswith("\n") else text + "\n")
    sys.stderr.flush()


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; return the exit code."""
    ctx = Context()
    try:
        parser = build_parser()
        try:
            args = parser.parse_args(list(argv) if argv is not None else None)
        except _UsageError as exc:
            _print_err(str(exc))
            return EXIT_USER
        except SystemExit as exc:  # --help / --version
            return int(exc.code or 0) if not isinstance(exc.code, str) else EXIT_USER
        console.VERBOSE = bool(getattr(args, "verbose", False))
        func: Callable[[argparse.Namespace], int] = args.func
        writes = func in (cmd_generate, cmd_build) or getattr(func, "writes_output", False)
        ctx = Context(command=func.__name__.removeprefix("cmd_"), model=str(getattr(args, "model", "") or ""),
                      output=str(args.output) if writes else "")
        return func(args)
    except PyrosgenError as exc:
        # The one handler of the error family (pyrosgen.errors): the
        # exception's report, and the exit code of its base (1 for a user
        # error, 2 for a proof or tool failure).
        for line in exc.report(ctx):
            _print_err(line)
        return exc.exit_code
    except KeyboardInterrupt:
        _print_err("pyrosgen: interrupted")
        return 130
    except BaseException as exc:  # noqa: BLE001 - never a bare traceback
        if os.environ.get("PYROSGEN_DEBUG") == "1":
            raise
        detail = " ".join(f"{type(exc).__name__}: {exc}".split())
        _print_err(
            f"pyrosgen: internal error: {detail} (set PYROSGEN_DEBUG=1 for a traceback)"
        )
        return EXIT_TOOL


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())

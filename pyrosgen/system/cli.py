"""``pyrosgen system check|generate|build|verify|diagram SYSTEM.yaml
[--ros2]``: the command line of
systems (DESIGN.md sections 8 and 10), registered by
:func:`pyrosgen.cli.build_parser` through :func:`add_parser`."""

from __future__ import annotations

import argparse
import sys

__all__ = ["add_parser", "cmd_system_check", "cmd_system_generate", "cmd_system_build", "cmd_system_diagram",
           "cmd_system_verify"]

_EPILOG = """examples:
  pyrosgen system check examples/system_chain/system.yaml
  pyrosgen system generate examples/system_chain/system.yaml -o build/system_chain -j 2
  pyrosgen system generate SYSTEM.yaml -o OUT --cache /var/cache/pyrosgen   # a cache shared by CI jobs
  pyrosgen system build examples/system_chain/system.yaml -o build/system_chain -j 2
  pyrosgen system diagram examples/system_chain/system.yaml -o chain.svg --chain 1
  pyrosgen system verify build/system_chain --system examples/system_chain/system.yaml
  pyrosgen system build examples/system_chain/system.yaml -o build/chain2 --ros2   # ROS 2 (rcl)

generate writes OUT/<node>/ (each node's generate output; the folder is the
node's resolved name, '/' as '.'), OUT/<system>.certificate.md,
OUT/<system>.system.json and OUT/<system>.launch (with --ros2,
OUT/<system>.launch.xml, ROS 2's XML launch format), only if every node was
proved; an unchanged node is copied from the cache, not proved again."""


_ROS2_HELP = ("the target ROS 2 (Kilted, rcl), as for a single node (rule 4.17): every node read with ROS 2's "
              "message definitions, generated and built for ROS 2 (an ament_cmake package each), the QoS of "
              "every topic checked across nodes (rule 10.11), a launch file in ROS 2's XML format")


def _plural(n: int, word: str) -> str:
    return f"{n} {word}" if n == 1 else f"{n} {word}s"


def _jobs(text: str) -> int:
    try:
        n = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number of jobs: {text!r}") from None
    if not 1 <= n <= 256:
        raise argparse.ArgumentTypeError("the number of jobs is from 1 to 256")
    return n


def _target(args: argparse.Namespace) -> str:
    return "ros2" if getattr(args, "ros2", False) else "ros1"


def cmd_system_check(args: argparse.Namespace) -> int:
    """Check the system file, every node model and the rules across them."""
    from pyrosgen.system.checks import check_system
    from pyrosgen.system.model import load_system

    sysm = load_system(args.model, _target(args))
    graph = check_system(sysm)
    topics = set(graph.publishers) | set(graph.subscribers)
    print(f"{args.model}: ok: system {sysm.name}{' (target ros2)' if sysm.target == 'ros2' else ''}, "
          f"{_plural(len(sysm.nodes), 'node')}, "
          f"{_plural(len(topics), 'topic')}, {_plural(len(graph.links), 'link')}, "
          f"{_plural(len(graph.chains), 'chain')} from an external input to an external output"
          + (" (truncated)" if graph.chains_truncated else ""))
    return 0


def cmd_system_generate(args: argparse.Namespace) -> int:
    """Generate and prove every node (in parallel, cached), write the
    system's certificate."""
    from pathlib import Path

    from pyrosgen.system.generate import generate_system

    say = (lambda line: (sys.stderr.write(line + "\n"), sys.stderr.flush())) if not args.quiet else None
    res = generate_system(args.model, args.output, jobs=args.jobs,
                          cache=Path(args.cache) if args.cache else None, use_cache=not args.no_cache,
                          progress=say, target=_target(args))
    print(f"pyrosgen: system written to {res.out_dir}: {_plural(len(res.nodes), 'node')} "
          f"({res.hits} from the cache, {len(res.nodes) - res.hits} proved), {', '.join(res.files)}; "
          f"{res.seconds:.1f} s")
    return 0


cmd_system_generate.writes_output = True  # type: ignore[attr-defined]


def cmd_system_build(args: argparse.Namespace) -> int:
    """Build every node (in parallel, cached) and the system's files; OUT/src
    is a catkin workspace's source folder."""
    from pathlib import Path

    from pyrosgen.system.generate import generate_system

    say = (lambda line: (sys.stderr.write(line + "\n"), sys.stderr.flush())) if not args.quiet else None
    res = generate_system(args.model, args.output, jobs=args.jobs,
                          cache=Path(args.cache) if args.cache else None, use_cache=not args.no_cache,
                          progress=say, build=True, target=_target(args))
    print(f"pyrosgen: system built in {res.out_dir}: {_plural(len(res.nodes), 'node')} "
          f"({res.hits} from the cache, {len(res.nodes) - res.hits} built), {', '.join(res.files)}; "
          f"{res.seconds:.1f} s")
    if _target(args) == "ros2":
        print(f"  ament: in {res.out_dir}, colcon build --base-paths src (its links kept: a node's package "
              "finds its custom messages in its own folder), then ros2 launch "
              f"{res.out_dir}/{next((f for f in res.files if f.endswith('.launch.xml')), '<system>.launch.xml')}; or each node's binary {res.out_dir}/<node>/bin/<name> with "
              "the ROS arguments the launch file gives it (--ros-args -r __ns:=... -r FROM:=TO)")
    else:
        print(f"  catkin: catkin_make -C WS with {res.out_dir}/src as WS/src, or each node's binary "
              f"{res.out_dir}/<node>/bin/<name>")
    return 0


cmd_system_build.writes_output = True  # type: ignore[attr-defined]


def cmd_system_verify(args: argparse.Namespace) -> int:
    """Re-check a system's output folder against its system file."""
    from pyrosgen.system.verify import verify_system

    say = (lambda line: (sys.stderr.write(line + "\n"), sys.stderr.flush())) if not args.quiet else None
    rep = verify_system(args.folder, args.system, jobs=args.jobs, progress=say, target=_target(args))
    print(f"pyrosgen: {rep.folder} verifies (system {rep.system}); {rep.seconds:.1f} s")
    for line in rep.lines():
        print(line)
    return 0


def cmd_system_diagram(args: argparse.Namespace) -> int:
    """Draw the system's nodes and topics (one chain with ``--chain``)."""
    from pyrosgen import diagram
    from pyrosgen.errors import UserError, escape
    from pyrosgen.system.checks import check_system
    from pyrosgen.system.diagram import write_system_diagram
    from pyrosgen.system.model import load_system

    try:
        fmt = diagram.output_format(args.output, args.format)
    except ValueError as exc:
        raise UserError(str(exc)) from None
    sysm = load_system(args.model, _target(args))
    graph = check_system(sysm)
    try:
        write_system_diagram(sysm, graph, args.output, fmt, args.chain)
    except OSError as exc:
        raise UserError(f"cannot write {escape(args.output)}: {exc.strerror or exc}") from None
    return 0


def add_parser(sub, parser_class) -> None:
    """Register ``system`` and its commands on the subparsers ``sub``."""
    p = sub.add_parser(
        "system", help="check or generate a system of nodes",
        description="Systems of nodes (DESIGN.md section 10): a YAML file naming the nodes (each a node model, "
                    "its namespace and remappings) and the external topics.",
        epilog=_EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    ss = p.add_subparsers(dest="system_command", metavar="COMMAND", parser_class=parser_class)
    ss.required = True
    c = ss.add_parser("check", help="validate a system file and the nodes it names",
                      description="Validate a system file, every node model it names, and the rules across "
                                  "nodes (DESIGN.md rules 10.1 to 10.9).")
    c.add_argument("model", metavar="SYSTEM.yaml", help="the system file")
    c.add_argument("--ros2", action="store_true", help=_ROS2_HELP)
    c.set_defaults(func=cmd_system_check)
    g = ss.add_parser("generate", help="generate and prove every node, in parallel, cached",
                      description="Check the system, then generate and prove every node as pyrosgen generate "
                                  "does, in parallel processes, with a content-addressed cache, into OUT/<node>/; "
                                  "write the system's certificate (its chains and the transport assumption), "
                                  "its graph and a launch file.",
                      epilog=_EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    g.add_argument("model", metavar="SYSTEM.yaml", help="the system file")
    g.add_argument("-o", "--output", metavar="OUT", required=True, help="output directory")
    g.add_argument("-j", "--jobs", type=_jobs, default=None, metavar="N",
                   help="nodes proved at once (default: the number of cores)")
    g.add_argument("--cache", metavar="DIR", default=None,
                   help="the node cache (default: nodes/ in $PYROSGEN_CACHE or ~/.cache/pyrosgen)")
    g.add_argument("--no-cache", action="store_true", help="prove every node, read and write no cache")
    g.add_argument("-q", "--quiet", action="store_true", help="no progress lines")
    g.add_argument("--ros2", action="store_true", help=_ROS2_HELP)
    g.set_defaults(func=cmd_system_generate)
    b = ss.add_parser("build", help="build every node (in parallel, cached) and the system's files",
                      description="As system generate, with each node built as pyrosgen build does (its binary "
                                  "and catkin package in OUT/<node>/); OUT/src links every node's package, the "
                                  "source folder of a catkin workspace.", epilog=_EPILOG,
                      formatter_class=argparse.RawDescriptionHelpFormatter)
    b.add_argument("model", metavar="SYSTEM.yaml", help="the system file")
    b.add_argument("-o", "--output", metavar="OUT", required=True, help="output directory")
    b.add_argument("-j", "--jobs", type=_jobs, default=None, metavar="N",
                   help="nodes built at once (default: the number of cores)")
    b.add_argument("--cache", metavar="DIR", default=None,
                   help="the node cache (default: nodes/ in $PYROSGEN_CACHE or ~/.cache/pyrosgen)")
    b.add_argument("--no-cache", action="store_true", help="build every node, read and write no cache")
    b.add_argument("-q", "--quiet", action="store_true", help="no progress lines")
    b.add_argument("--ros2", action="store_true", help=_ROS2_HELP)
    b.set_defaults(func=cmd_system_build)
    v = ss.add_parser("verify", help="re-check a system's output folder against its system file",
                      description="Re-check OUT against SYSTEM.yaml: the system's files rendered again and "
                                  "compared byte for byte, each node folder as 'pyrosgen verify FOLDER --model "
                                  "MODEL' does, and the system's proof compiled again against the nodes' .v.")
    v.add_argument("folder", metavar="OUT", help="output folder of pyrosgen system generate")
    v.add_argument("--system", metavar="SYSTEM.yaml", required=True, help="the system file OUT was generated from")
    v.add_argument("-j", "--jobs", type=_jobs, default=None, metavar="N",
                   help="nodes checked at once (default: the number of cores)")
    v.add_argument("-q", "--quiet", action="store_true", help="no progress lines")
    v.add_argument("--ros2", action="store_true", help=_ROS2_HELP)
    v.set_defaults(func=cmd_system_verify)
    d = ss.add_parser("diagram", help="draw the nodes and the topics between them with Graphviz",
                      description="Draw the system's nodes and the topics between them (from the model, before "
                                  "anything runs), and with --chain N one chain with the relations it passes "
                                  "through in every node.")
    d.add_argument("model", metavar="SYSTEM.yaml", help="the system file")
    d.add_argument("-o", "--output", required=True, metavar="FILE", help="output file (.svg, .png, .pdf or .dot)")
    d.add_argument("--format", choices=("svg", "png", "pdf", "dot"), help="output format (default: from the suffix)")
    d.add_argument("--chain", type=_jobs, metavar="N", help="highlight chain N (as numbered in the certificate)")
    d.add_argument("--ros2", action="store_true", help=_ROS2_HELP)
    d.set_defaults(func=cmd_system_diagram)

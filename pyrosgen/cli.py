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
import os
import sys
from collections.abc import Callable, Sequence

from .errors import InvalidNodeModel, PyrosgenError

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


def cmd_check(args: argparse.Namespace) -> int:
    """``pyrosgen check MODEL.yaml``: validate only."""
    from .model import load_model

    model = load_model(args.model)
    print(
        f"{args.model}: ok: node {model.name}, {_plural(len(model.topics), 'topic')}, "
        f"{_plural(len(model.input_relations), 'input relation')}, "
        f"{_plural(len(model.output_relations), 'output relation')}"
    )
    return EXIT_OK


def build_parser() -> argparse.ArgumentParser:
    """The argument parser with one subparser per command."""
    parser = _Parser(
        prog="pyrosgen",
        description="Generate proven glue code for ROS 1 nodes from a node model.",
    )
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    sub.required = True

    p = sub.add_parser("check", help="validate a node model", description="Validate a node model file.")
    p.add_argument("model", metavar="MODEL.yaml", help="the node model file")
    p.set_defaults(func=cmd_check)
    return parser


def _print_err(text: str) -> None:
    sys.stderr.write(text if text.endswith("\n") else text + "\n")
    sys.stderr.flush()


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; return the exit code."""
    try:
        parser = build_parser()
        try:
            args = parser.parse_args(list(argv) if argv is not None else None)
        except _UsageError as exc:
            _print_err(str(exc))
            return EXIT_USER
        except SystemExit as exc:  # --help / --version
            return int(exc.code or 0) if not isinstance(exc.code, str) else EXIT_USER
        func: Callable[[argparse.Namespace], int] = args.func
        return func(args)
    except InvalidNodeModel as exc:
        _print_err(str(exc))
        return EXIT_USER
    except PyrosgenError as exc:
        _print_err(f"pyrosgen: error: {' '.join(str(exc).split())}")
        return EXIT_TOOL
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

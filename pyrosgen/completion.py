"""``pyrosgen completion``: a bash completion script generated from the
command line's argument parser (:func:`pyrosgen.cli.build_parser`).

The script is static text: a TAB runs a small bash function, not Python,
so it answers at once and needs no package (argcomplete would start
Python and import pyrosgen on each TAB, and needs a global hook or an
``eval`` per command).  Being generated from the parser, it knows every
subcommand and option the parser knows; ``make deps`` writes it into the
virtual environment (``.venv/share/bash-completion/completions/pyrosgen``),
and ``pyrosgen completion`` prints it for any other place.

What it completes: the subcommands; each subcommand's options; an
option's choices (``--format svg``); folders for an option or argument
whose metavar is ``DIR`` or ``OUT`` (``--controller``, ``-o`` of
``generate`` and ``build``, ``--include``); file names for the others that
name a file (``MODEL.yaml``, ``FILE``); nothing for free text (``--cflags``,
``--name``).
"""

from __future__ import annotations

import argparse
import shlex

__all__ = ["bash_script"]

#: Metavars that name a folder, and those that name a file.
_DIR_METAVARS = ("DIR", "OUT")
_FILE_METAVARS = ("MODEL.yaml", "FILE")


def _kind(action: argparse.Action) -> str:
    """How the value of ``action`` is completed: ``'dir'``, ``'file'``,
    ``'choices'`` or ``'none'`` (free text)."""
    if action.choices:
        return "choices"
    metavar = action.metavar if isinstance(action.metavar, str) else action.dest.upper()
    if metavar in _DIR_METAVARS:
        return "dir"
    if metavar in _FILE_METAVARS:
        return "file"
    return "none"


def _takes_value(action: argparse.Action) -> bool:
    return action.nargs != 0


def _words(ws) -> str:
    return shlex.quote(" ".join(ws))


def _reply(kind: str, choices=()) -> str:
    if kind == "dir":
        return 'COMPREPLY=($(compgen -d -- "$cur"))'
    if kind == "file":
        return 'COMPREPLY=($(compgen -f -- "$cur"))'
    if kind == "choices":
        return f'COMPREPLY=($(compgen -W {_words(str(c) for c in choices)} -- "$cur"))'
    return "COMPREPLY=()"


def _command_case(name: str, parser: argparse.ArgumentParser) -> list[str]:
    """The ``case`` branch of one subcommand."""
    options, by_kind = [], {}
    positional = "none"
    for a in parser._actions:
        if a.option_strings:
            options += a.option_strings
            if _takes_value(a):
                key = (_kind(a), tuple(a.choices or ()))
                by_kind.setdefault(key, []).extend(a.option_strings)
        elif positional == "none":
            positional = _kind(a)
    lines = [f"        {name})", '            case "$prev" in']
    for (kind, choices), opts in by_kind.items():
        lines.append(f"                {'|'.join(opts)}) {_reply(kind, choices)}; return ;;")
    lines += [
        "            esac",
        '            if [[ "$cur" == -* ]]; then',
        f'                COMPREPLY=($(compgen -W {_words(options)} -- "$cur"))',
        "            else",
        f"                {_reply(positional)}",
        "            fi",
        "            ;;",
    ]
    return lines


def bash_script(parser: argparse.ArgumentParser) -> str:
    """The bash completion script of ``parser`` (the ``pyrosgen`` parser:
    top-level options, then one subcommand)."""
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    top_options = [s for a in parser._actions if a.option_strings for s in a.option_strings]
    commands = list(sub.choices)
    out = [
        "# bash completion for pyrosgen: generated from its argument parser by `pyrosgen completion`.",
        "# Enable it with:  source <this file>   (make deps writes it into",
        "# .venv/share/bash-completion/completions/pyrosgen)",
        "_pyrosgen() {",
        "    local cur prev cmd i",
        '    cur="${COMP_WORDS[COMP_CWORD]}"',
        '    prev="${COMP_WORDS[COMP_CWORD-1]}"',
        "    # --option=VALUE: bash splits the word at '='",
        '    if [[ "$cur" == "=" ]]; then cur=""; elif [[ "$prev" == "=" ]]; then prev="${COMP_WORDS[COMP_CWORD-2]}"; fi',
        '    cmd=""',
        "    for ((i = 1; i < COMP_CWORD; i++)); do",
        '        case "${COMP_WORDS[i]}" in',
        "            -*) ;;",
        '            *) cmd="${COMP_WORDS[i]}"; break ;;',
        "        esac",
        "    done",
        '    case "$cmd" in',
        '        "")',
        '            if [[ "$cur" == -* ]]; then',
        f'                COMPREPLY=($(compgen -W {_words(top_options)} -- "$cur"))',
        "            else",
        f'                COMPREPLY=($(compgen -W {_words(commands)} -- "$cur"))',
        "            fi",
        "            ;;",
    ]
    for name, p in sub.choices.items():
        out += _command_case(name, p)
    out += [
        "        *) COMPREPLY=() ;;",
        "    esac",
        "}",
        "complete -o filenames -F _pyrosgen pyrosgen",
    ]
    return "\n".join(out) + "\n"

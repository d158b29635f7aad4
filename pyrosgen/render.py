"""The one place where templates are rendered.

Every generated text that is not printed by Coq (the per-node Coq file, the
C++ wrapper, the catkin files, the layout check, the certificate, the ACSL
contracts, the differential-test harness, the Graphviz diagram) comes from a
jinja2 template rendered here, with one environment: ``StrictUndefined`` (a
missing variable is an error, not an empty string), ``trim_blocks``,
``lstrip_blocks``, ``keep_trailing_newline``, no autoescape (each template
receives values already checked or escaped for its language, DESIGN.md
rule 4.10).  The loader looks in the package's templates, then in the Coq
library's templates (:mod:`pyrosgen.resources`); their names do not clash.

Each template starts with a comment listing its context variables.
"""

from __future__ import annotations

import functools
import re
from typing import Any, Callable

import jinja2

from pyrosgen import resources

__all__ = ["environment", "render", "ros_name", "source_label"]

#: What may appear inside a C/C++ string literal in generated code: a
#: validated ROS graph name.  Checked again when printed (defence in depth).
_ROS_NAME = re.compile(r"^/?[A-Za-z][A-Za-z0-9_]*(/[A-Za-z][A-Za-z0-9_]*)*$")


def ros_name(value: str) -> str:
    """The ``ros_name`` filter: ``value`` unchanged if it is a ROS graph
    name, otherwise ``ValueError`` (the front end let something through)."""
    if not isinstance(value, str) or not _ROS_NAME.match(value):
        raise ValueError(f"refusing to print {value!r} as a ROS name")
    return value


_LABEL_SAFE = re.compile(r"[A-Za-z0-9._+-]")


def source_label(name: str) -> str:
    """A file name (user input) as it may appear in a comment of any
    generated language (C, C++, CMake, XML, Coq, shell): letters, digits,
    ``. _ + -`` as they are, every other character, and a ``-`` after a
    ``-`` (XML comments), as ``\\xNN`` / ``\\uNNNN``.  A name with a
    newline, ``*/``, ``-->``, ``$(...)`` or a backtick cannot end its
    comment or start a command (DESIGN.md rule 4.10)."""
    out = []
    for i, ch in enumerate(str(name)):
        if _LABEL_SAFE.fullmatch(ch) and not (ch == "-" and i and name[i - 1] == "-"):
            out.append(ch)
        else:
            out.append(f"\\x{ord(ch):02x}" if ord(ch) < 256 else f"\\u{ord(ch):04x}")
    return "".join(out)


@functools.lru_cache(maxsize=None)
def environment() -> jinja2.Environment:
    """The project's jinja2 environment (one per process)."""
    env = jinja2.Environment(
        loader=jinja2.ChoiceLoader([
            jinja2.FileSystemLoader(str(resources.templates_dir())),
            jinja2.FileSystemLoader(str(resources.coq_templates_dir())),
        ]),
        undefined=jinja2.StrictUndefined,
        trim_blocks=True,
        lstrip_blocks=True,
        keep_trailing_newline=True,
        autoescape=False,
    )
    env.filters["ros_name"] = ros_name
    return env


@functools.lru_cache(maxsize=None)
def _finalized(finalize: Callable[[Any], Any]) -> jinja2.Environment:
    # An overlay shares the loader and options of the environment and only
    # adds a finalizer that every {{ expression }} goes through.
    return environment().overlay(finalize=finalize)


def render(template: str, /, *, finalize: Callable[[Any], Any] | None = None, **context: Any) -> str:
    """Render ``template`` (a file name of the templates folders) with
    ``context``; ``finalize`` escapes every printed expression (the
    diagram: nothing from the model is printed raw)."""
    env = environment() if finalize is None else _finalized(finalize)
    return env.get_template(template).render(**context)

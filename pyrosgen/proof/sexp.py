"""The S-expression dump of a Clight program (``<node>.sexp``).

The grammar is in ``coq/theories/clight/Dump.v`` (and ``coq/README.md``):
``(program (externs IDENT...) (main IDENT) item...)`` with struct, global
variable, external function and internal function items.  This module
parses it (:func:`parse_sexp`) and indexes its items
(:func:`program_items`); the printer validation (:mod:`pyrosgen.verify.printer_validation`)
and the differential tests (:mod:`pyrosgen.verify.difftest`) read the dump through
it.

Lists are Python lists, atoms ``str``, double-quoted strings
:class:`SString` (a ``str`` subclass, so that a topic name ``"/x"`` and an
atom ``x`` stay distinct).
"""

from __future__ import annotations

__all__ = ["SString", "parse_sexp", "program_items", "SexpError"]


class SexpError(ValueError):
    """The text is not a well-formed S-expression / dump."""


class SString(str):
    """A double-quoted string of the dump (distinct from an atom)."""


def parse_sexp(text: str):
    """Parse one S-expression: lists become Python lists, atoms ``str``,
    quoted strings :class:`SString`.  Iterative (no recursion limit).
    Raises :class:`SexpError` (a ``ValueError``) on malformed input."""
    stack: list[list] = [[]]
    i, n = 0, len(text)
    while i < n:
        c = text[i]
        if c.isspace():
            i += 1
        elif c == "(":
            stack.append([])
            i += 1
        elif c == ")":
            if len(stack) < 2:
                raise SexpError(f"unbalanced ')' at offset {i}")
            done = stack.pop()
            stack[-1].append(done)
            i += 1
        elif c == '"':
            j, buf = i + 1, []
            while True:
                if j >= n:
                    raise SexpError("unterminated string")
                if text[j] == "\\":
                    if j + 1 >= n or text[j + 1] not in '"\\':
                        raise SexpError(f"bad escape at offset {j}")
                    buf.append(text[j + 1])
                    j += 2
                elif text[j] == '"':
                    break
                else:
                    buf.append(text[j])
                    j += 1
            stack[-1].append(SString("".join(buf)))
            i = j + 1
        else:
            j = i
            while j < n and not text[j].isspace() and text[j] not in '()"':
                j += 1
            stack[-1].append(text[i:j])
            i = j
    if len(stack) != 1:
        raise SexpError("unbalanced '('")
    if len(stack[0]) != 1:
        raise SexpError(f"expected one S-expression, got {len(stack[0])}")
    return stack[0][0]


def program_items(tree) -> dict:
    """Index the items of a parsed ``(program ...)`` dump.

    Returns a dict with ``externs`` (list of names), ``main``, ``structs``
    (name -> list of ``(member, type)``), ``gvars`` (name -> type),
    ``externals`` (name -> ``[ef, params, result]``), ``functions`` (name ->
    the whole item) and ``order`` (``(kind, name)`` in dump order); all in
    dump order.
    """
    if not (isinstance(tree, list) and len(tree) >= 3 and tree[0] == "program"):
        raise SexpError("not a (program ...) dump")
    if not (isinstance(tree[1], list) and tree[1][:1] == ["externs"]
            and isinstance(tree[2], list) and tree[2][:1] == ["main"] and len(tree[2]) == 2):
        raise SexpError("a dump starts with (externs ...) (main ...)")
    out = {"externs": tree[1][1:], "main": tree[2][1], "structs": {}, "gvars": {},
           "externals": {}, "functions": {}, "order": []}
    for item in tree[3:]:
        if not (isinstance(item, list) and len(item) >= 2 and isinstance(item[1], str)):
            raise SexpError(f"malformed item {item!r:.80}")
        kind, name = item[0], item[1]
        out["order"].append((kind, name))
        if kind == "struct":
            out["structs"][name] = [(m[0], m[1]) for m in item[2:]]
        elif kind == "gvar":
            out["gvars"][name] = item[2]
        elif kind == "external":
            out["externals"][name] = item[2:]
        elif kind == "function":
            out["functions"][name] = item
        else:
            raise SexpError(f"unknown item {kind}")
    return out

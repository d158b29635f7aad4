"""The per-node ``.v`` of a received folder, checked before anything
compiles it.

``pyrosgen verify`` compiles the folder's ``.v`` with ``coqc`` and runs
the OCaml that it extracts: a ``.v`` of the folder's choosing could run a
command (``Extract Constant ... "Sys.command ..."``), write files
(``Redirect``, ``Extraction "/abs"``), add an axiom or state a weaker
theorem.  So before ``coqc`` runs, :func:`check_structure` requires the
``.v`` to be ``coq/templates/node.v.j2`` rendered for the node's name with
only its *literal* parts free:

- the bodies of the definitions ``messages`` and ``model`` (and, for a
  block-diagram controller, ``Ctrl.the_diagram``) are free, but may only
  be made of the literal syntax the emitter writes
  (:mod:`pyrosgen.proof.coqmodel`, :mod:`pyrosgen.proof.coqdiagram`,
  ``coq/templates/node_model.v.j2``): identifiers of :data:`LITERAL_IDENTS`,
  string and numeral literals and the punctuation of :data:`LITERAL_PUNCT`;
- comments are free (printable ASCII);
- every other token must be the template's, in its order: the theorem
  names come from the node's name, the statements, proofs, ``Print
  Assumptions`` and the ``Extraction "job.ml"`` line are the template's.

The file is read by a small Coq lexer (:func:`tokens`: nested comments
with strings inside them, strings with ``""`` escapes, identifiers, qualified
identifiers, numerals, punctuation, the ``.`` that ends a sentence); a
character it does not know (anything outside printable ASCII and the
newline, a numeral with a suffix, ...) is refused, so that the lexer never
reads a token where Coq would read another.

With the model (``verify --model``), :func:`check_rendering` requires more:
the ``.v`` is, byte for byte, the one ``pyrosgen generate`` renders from it.

Every refusal is a :class:`VFileError` whose lines are
``FILE:LINE:COL: error: ...``.
"""

from __future__ import annotations

import re
from collections.abc import Iterator
from dataclasses import dataclass

import jinja2

from pyrosgen.errors import UserError

__all__ = ["VFileError", "Token", "tokens", "skeleton", "check_structure", "check_rendering",
           "LITERAL_IDENTS", "LITERAL_PUNCT", "MAX_PLAIN_NUMERAL", "MAX_ZRANGE"]

#: The identifiers the literal bodies may use: the constructors, record
#: fields and functions the emitter writes (coqmodel.py, coqdiagram.py,
#: node_model.v.j2), the bound variable ``i`` of the ``map`` of a whole
#: array, the definition ``messages`` and the scope keys ``list`` and ``Z``.
LITERAL_IDENTS = frozenset("""
    mkmsgdef mktopic mkinrel mkinrel_at mkoutrel mkoutrel_at mkdrel map zrange fun i messages list Z
    FTprim FTmsg FTarray PIndex PField Subscribe Publish
    Pbool Pint8 Puint8 Pint16 Puint16 Pint32 Puint32 Pint64 Puint64 Pfloat32 Pfloat64
    nm_name nm_period_ms nm_ctrl nm_in_var nm_in_struct nm_inputs nm_out_var nm_out_struct nm_outputs
    nm_msgs nm_topics nm_inrels nm_outrels nm_timeouts nm_fallbacks nm_drels nm_stamps nm_stamp_from nm_strings
    Dis_new Dreceived Dage_ms
    Vint Vlong Vfloat Vsingle float64_of_bits float32_of_bits true false None Some
    mkeq mkstate Binport Bstate Bconst Bgain Bsum Bproduct Bdivide Babs Bminmax Bsaturation Brelational
    Blogical Bswitch Kdelay Kintegrator Req Rne Rlt Rgt Rle Rge Land Lor Lnand Lnor Lxor Lnot Cge Cgt Cne0
    Aadd Asub Amul Adiv
""".split())

#: The punctuation the literal bodies may use.
LITERAL_PUNCT = frozenset(["[", "]", "(", ")", ";", ",", "++", "%", "=>", ":=", "{|", "|}", "-"])

#: The largest numeral without ``%Z`` in a literal body: the front end's
#: bounds on what the emitter writes so (a period of at most 3,600,000 ms;
#: queue sizes, array lengths and indices are smaller); the integers of
#: constants, timeouts and string bytes carry ``%Z``.  And the largest
#: ``zrange n``: a controller array's 65,536 elements.  A hostile ``.v``
#: cannot ask for an array of 10^12 elements (with ``--model`` nothing but
#: the rendering of the model passes anyway).
MAX_PLAIN_NUMERAL = 3_600_000
MAX_ZRANGE = 65_536

#: Multi-character punctuation the lexer reads as one token (longest first).
_MULTI = (":=", "=>", "++", "{|", "|}", "->", "<-", "<->", "/\\", "\\/", "|-", "::", "..", "<>", "<=", ">=",
          "&&", "||", ":>", ".(", "@{", "%%")
_MULTI = tuple(sorted(_MULTI, key=len, reverse=True))
_IDENT = re.compile(r"[A-Za-z_][A-Za-z0-9_']*(?:\.[A-Za-z_][A-Za-z0-9_']*)*")
_NUM = re.compile(r"0[xX][0-9A-Fa-f]+|[0-9]+")
_PUNCT = set("()[]{};,:=+-*/\\|<>&%@!?#$^~'`.")

#: Sentinels standing for the free bodies in the rendered skeleton.
_FREE = {"PYROSGEN_FREE_MESSAGES": "messages", "PYROSGEN_FREE_MODEL": "model",
         "PYROSGEN_FREE_DIAGRAM": "Ctrl.the_diagram"}


class VFileError(UserError):
    """The folder's ``.v`` is not the template's (exit 1): ``summary`` and
    located ``lines``."""

    def __init__(self, summary: str, lines: list[str] | tuple[str, ...] = ()):
        self.summary = summary
        self.lines = tuple(lines)
        super().__init__(summary + "".join(f"\n{ln}" for ln in self.lines))


@dataclass(frozen=True)
class Token:
    kind: str   #: ``comment``, ``string``, ``ident``, ``num``, ``punct``, ``dot`` (the end of a sentence)
    text: str
    line: int
    col: int

    def show(self) -> str:
        if self.kind == "dot":
            return "'.' (the end of a sentence)"
        t = self.text if len(self.text) <= 40 else self.text[:37] + "..."
        return f"{self.kind} {t!r}"


def tokens(text: str, name: str = "<.v>") -> Iterator[Token]:
    """Coq's tokens of ``text``, comments included; :class:`VFileError` at
    the first character the lexer does not know."""
    i, n, line, bol = 0, len(text), 1, 0

    def err(k: int, what: str) -> VFileError:
        ln = text.count("\n", 0, k) + 1
        col = k - (text.rfind("\n", 0, k) + 1) + 1
        return VFileError(f"{name} is not a .v that pyrosgen writes", [f"{name}:{ln}:{col}: error: {what}"])

    def string_end(k: int) -> int:
        """The index after the string starting at ``text[k] == '"'``."""
        k += 1
        while True:
            j = text.find('"', k)
            if j < 0:
                raise err(k - 1, "a string that does not end")
            if text.startswith('""', j):
                k = j + 2
                continue
            return j + 1

    while i < n:
        ch = text[i]
        if ch == "\n":
            line, bol = line + 1, i + 1
            i += 1
            continue
        if ch == " ":
            i += 1
            continue
        if not (" " <= ch <= "~"):
            raise err(i, f"the character {ch!r}: a .v that pyrosgen writes is printable ASCII")
        start, col = i, i - bol + 1
        if text.startswith("(*", i):
            depth, k = 1, i + 2
            while depth:
                if k >= n:
                    raise err(start, "a comment that does not end")
                if text.startswith("(*", k):
                    depth, k = depth + 1, k + 2
                elif text.startswith("*)", k):
                    depth, k = depth - 1, k + 2
                elif text[k] == '"':
                    k = string_end(k)
                else:
                    k += 1
            kind = "comment"
            i = k
        elif ch == '"':
            i = string_end(i)
            kind = "string"
        elif m := _IDENT.match(text, i):
            i = m.end()
            kind = "ident"
        elif m := _NUM.match(text, i):
            i = m.end()
            kind = "num"
            if i < n and (text[i].isalnum() or text[i] in "_'"):
                raise err(start, f"the numeral {text[start:i + 1]!r}...: not one that pyrosgen writes")
        elif ch == "." and (i + 1 == n or text[i + 1] in " \n"):
            i += 1
            kind = "dot"
        elif ch in _PUNCT:
            multi = next((p for p in _MULTI if text.startswith(p, i)), None)
            i += len(multi) if multi else 1
            kind = "punct"
        else:
            raise err(i, f"the character {ch!r}")
        tok = Token(kind, text[start:i], line, col)
        line += tok.text.count("\n")
        if "\n" in tok.text:
            bol = start + tok.text.rfind("\n") + 1
        yield tok


_STUB = ('{% macro messages(m) %}PYROSGEN_FREE_MESSAGES{% endmacro %}\n'
         '{% macro node_model(m, msgs) %}PYROSGEN_FREE_MODEL{% endmacro %}\n')


def skeleton(node: str, *, ddc_available: bool, diagram: bool, target: str = "ros1") -> str:
    """``coq/templates/node.v.j2`` rendered for ``node`` and ``target``
    (``ros1`` or ``ros2``: the ``.v`` names it) with a sentinel in place of
    each free body."""
    from pyrosgen.proof.coqmodel import NODE_TEMPLATE, coq_string, coq_target, node_file_names, template_env

    base = template_env()
    env = base.overlay(loader=jinja2.ChoiceLoader([jinja2.DictLoader({"node_model.v.j2": _STUB}), base.loader]))
    names = node_file_names(node)
    return env.get_template("node.v.j2").render(
        template=NODE_TEMPLATE, source="x", m=None, names=names,
        guard=coq_string(names.guard, "include guard"), ddc_available=bool(ddc_available),
        target=coq_target(target),
        diagram="Definition the_diagram : diagram := mkdiagram PYROSGEN_FREE_DIAGRAM.\n" if diagram else "")


def _code(toks: Iterator[Token]) -> list[Token]:
    return [t for t in toks if t.kind != "comment"]


def check_structure(text: str, name: str, node: str, *, ddc_available: bool, diagram: bool,
                    target: str = "ros1") -> int:
    """Require ``text`` (the folder's ``.v``, shown as ``name``) to be the
    template rendered for ``node`` and ``target`` with only the literal
    bodies free (see the module's documentation); return the number of
    tokens checked."""
    want = _code(tokens(skeleton(node, ddc_available=ddc_available, diagram=diagram, target=target),
                        "the template"))
    have = _code(tokens(text, name))
    k = 0

    def refuse(t: Token | None, what: str) -> VFileError:
        if t is None:
            last = have[-1] if have else Token("dot", "", 1, 1)
            return VFileError(f"{name} is not the template's .v of node {node}",
                              [f"{name}:{last.line}:{last.col}: error: the file ends where {what}"])
        return VFileError(f"{name} is not the template's .v of node {node}",
                          [f"{name}:{t.line}:{t.col}: error: {what}"])

    for w in want:
        if w.kind == "ident" and w.text in _FREE:
            where = _FREE[w.text]
            count = 0
            while k < len(have) and have[k].kind != "dot":
                t = have[k]
                if not ((t.kind == "ident" and t.text in LITERAL_IDENTS) or t.kind in ("string", "num")
                        or (t.kind == "punct" and t.text in LITERAL_PUNCT)):
                    raise refuse(t, f"{t.show()} in the body of {where}, where only literals are allowed "
                                    "(the constructors pyrosgen writes, strings, numerals)")
                if t.kind == "num":
                    after_zrange = k > 0 and have[k - 1].text == "zrange"
                    typed = k + 1 < len(have) and have[k + 1].text == "%" or (
                        k + 2 < len(have) and have[k + 1].text == ")" and have[k + 2].text == "%")
                    bound = MAX_ZRANGE if after_zrange else None if typed else MAX_PLAIN_NUMERAL
                    value = int(t.text, 16) if t.text[:2] in ("0x", "0X") else int(t.text)
                    if bound is not None and value > bound:
                        raise refuse(t, f"the numeral {t.text} in the body of {where}: more than "
                                        f"{bound:,}, the largest that pyrosgen writes there")
                k += 1
                count += 1
            if count == 0:
                raise refuse(have[k] if k < len(have) else None, f"the body of {where} is empty")
            continue
        t = have[k] if k < len(have) else None
        if t is None:
            raise refuse(None, f"the template has {w.show()} (line {w.line} of the template)")
        if (t.kind, t.text) != (w.kind, w.text):
            raise refuse(t, f"{t.show()} where the template has {w.show()}")
        k += 1
    if k < len(have):
        raise refuse(have[k], f"{have[k].show()} after the template's last sentence")
    return k


def check_rendering(text: str, name: str, model_path: str, rendered: str) -> None:
    """Require ``text`` to be ``rendered``, the ``.v`` that ``pyrosgen
    generate`` renders from ``model_path``, byte for byte."""
    if text == rendered:
        return
    a, b = text.splitlines(), rendered.splitlines()
    k = next((i for i in range(min(len(a), len(b))) if a[i] != b[i]), min(len(a), len(b)))
    col = next((j for j in range(min(len(a[k]) if k < len(a) else 0, len(b[k]) if k < len(b) else 0))
                if a[k][j] != b[k][j]), 0) if k < len(a) and k < len(b) else 0
    shown = (lambda s: s if len(s) <= 120 else s[:117] + "...")
    raise VFileError(f"{name} is not the .v that pyrosgen generate renders from {model_path}", [
        f"{name}:{k + 1}:{col + 1}: error: the folder's {shown(a[k]) if k < len(a) else '(end of file)'!r}",
        f"{name}:{k + 1}:{col + 1}: note: rendered     {shown(b[k]) if k < len(b) else '(end of file)'!r}"])

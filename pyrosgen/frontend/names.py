"""Rules for the names that reach generated C, C++ and Coq text.

Nothing from the node model reaches generated text unchecked: every name is an
ASCII C identifier, is not a C, C++ or Coq keyword, is not reserved by the C
or C++ standards, and is at most :data:`MAX_NAME_LEN` characters long.  Topic
names follow the ROS 1 graph-resource-name rules.
"""

from __future__ import annotations

import difflib
import re

__all__ = [
    "MAX_NAME_LEN",
    "C_KEYWORDS",
    "CXX_KEYWORDS",
    "COQ_KEYWORDS",
    "C_IDENT_RE",
    "identifier_problem",
    "topic_name_problem",
    "topic_c_name",
    "did_you_mean",
]

#: Longest identifier we emit (C guarantees 63 significant initial characters
#: for internal identifiers).
MAX_NAME_LEN = 63

#: An ASCII C identifier.
C_IDENT_RE = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")

#: Keywords of C (C89 to C23), including the underscore-capital ones.
C_KEYWORDS = frozenset(
    """
    auto break case char const continue default do double else enum extern float
    for goto if inline int long register restrict return short signed sizeof static
    struct switch typedef union unsigned void volatile while
    _Alignas _Alignof _Atomic _BitInt _Bool _Complex _Decimal128 _Decimal32
    _Decimal64 _Generic _Imaginary _Noreturn _Static_assert _Thread_local
    alignas alignof bool constexpr false nullptr static_assert thread_local true
    typeof typeof_unqual
    """.split()
)

#: Keywords and alternative operator tokens of C++ (up to C++23), plus the
#: identifiers with a special meaning that we also keep out.
CXX_KEYWORDS = frozenset(
    """
    alignas alignof and and_eq asm auto bitand bitor bool break case catch char
    char8_t char16_t char32_t class compl concept const consteval constexpr
    constinit const_cast continue co_await co_return co_yield decltype default
    delete do double dynamic_cast else enum explicit export extern false float for
    friend goto if inline int long mutable namespace new noexcept not not_eq
    nullptr operator or or_eq private protected public register reinterpret_cast
    requires return short signed sizeof static static_assert static_cast struct
    switch template this thread_local throw true try typedef typeid typename union
    unsigned using virtual void volatile wchar_t while xor xor_eq
    final override import module
    """.split()
)

#: Coq identifiers refused in generated ``.v`` files: the words Coq 8.16 really
#: reserves (measured: ``Definition w := 0.`` fails for each), plus the
#: vernacular commands that open or close definitions and proofs (so that no
#: model name can look like a proof command, or like the words the proof
#: gate greps for).  Commands that are ordinary identifiers in practice and
#: plausible port names (``Reset``, ``Load``, ``Check``) stay allowed.
COQ_KEYWORDS = frozenset(
    """
    _ as at by cofix else end exists exists2 fix for forall fun if IF in
    lazymatch let match mod multimatch return then using where with struct
    Prop SProp Set Type
    Abort Admit Admitted admit Axiom Axioms CoFixpoint CoInductive Class
    Conjecture Corollary Defined Definition End Example Export Fact Fixpoint
    Hypotheses Hypothesis Import Inductive Instance Lemma Let Ltac Module
    Notation Parameter Parameters Proof Proposition Qed Record Remark Require
    Section Structure Theorem Variable Variables Variant
    """.split()
)


def did_you_mean(word: str, candidates) -> str:
    """`` (did you mean 'x'?)`` when a candidate is close to ``word``, else ``''``."""
    from pyrosgen.errors import show

    if not isinstance(word, str):
        return ""
    close = difflib.get_close_matches(word, list(candidates), n=1, cutoff=0.6)
    if close:
        return f" (did you mean {show(close[0])}?)"
    return ""


def identifier_problem(name: str, *, coq: bool = True, global_scope: bool = False) -> str | None:
    """Why ``name`` cannot be used as an identifier in generated code, or ``None``.

    ``coq`` also refuses Coq keywords; ``global_scope`` also refuses a leading
    underscore (reserved for file-scope identifiers by the C standard).
    """
    if not name:
        return "it is empty"
    if not C_IDENT_RE.fullmatch(name):
        return "it is not a C identifier (letters, digits and '_', not starting with a digit)"
    if len(name) > MAX_NAME_LEN:
        return f"it is longer than {MAX_NAME_LEN} characters ({len(name)})"
    if name in C_KEYWORDS:
        return "it is a C keyword"
    if name in CXX_KEYWORDS:
        return "it is a C++ keyword"
    if coq and name in COQ_KEYWORDS:
        return "it is a Coq keyword"
    if name.startswith("_") and len(name) > 1 and (name[1] == "_" or name[1].isupper()):
        return "it is reserved by the C standard (starts with '__' or '_' and a capital)"
    if "__" in name:
        return "it is reserved by the C++ standard (contains '__')"
    if global_scope and name.startswith("_"):
        return "it is reserved by the C standard at file scope (starts with '_')"
    return None


_SEGMENT_RE = re.compile(r"[A-Za-z][A-Za-z0-9_]*")


def topic_name_problem(name: str) -> str | None:
    """Why ``name`` is not an acceptable ROS 1 topic name, or ``None``.

    Accepted: global (``/a/b_c``) and relative (``a/b``) names whose segments
    are ``[A-Za-z][A-Za-z0-9_]*``.  Refused: private names (``~a``), empty
    segments (``//``), a trailing ``/``, and any other character.
    """
    if not name:
        return "it is empty"
    if name.startswith("~"):
        return "private names (~name) are not supported; use a global or relative name"
    if name == "/":
        return "it names the root namespace, not a topic"
    if name.endswith("/"):
        return "it ends with '/'"
    body = name[1:] if name.startswith("/") else name
    if "//" in name:
        return "it contains an empty segment ('//')"
    for seg in body.split("/"):
        if not _SEGMENT_RE.fullmatch(seg):
            return (
                f"segment {_q(seg)} is not a ROS name "
                "(a letter followed by letters, digits and '_')"
            )
    return None


def _q(s: str) -> str:
    from pyrosgen.errors import show

    return show(s)


def topic_c_name(name: str) -> str:
    """The C name of a topic: leading ``/`` stripped, ``/`` turned into ``_``.

    ``/landshark/left_wheel_velocity`` becomes ``landshark_left_wheel_velocity``.
    """
    return name.lstrip("/").replace("/", "_")

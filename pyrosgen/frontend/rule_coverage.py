"""Rule 4.8 (coverage), with rule 4.15's elements: every controller input,
and every element of an array input, is fed by exactly one input relation;
a published field is written at most once.
"""

from __future__ import annotations

from pyrosgen.errors import show
from pyrosgen.frontend.checker import Checker, Rel


def check_fed(ck: Checker, in_rels: list[Rel], ufields, inputs) -> None:
    """Rules 4.8 and 4.15: every controller input, and every element of an
    array input, is fed by exactly one relation (an input relation,
    element by element for a whole array, or a derived input)."""
    fed: dict[tuple[str, int | None], Rel] = {}
    for r in in_rels:
        if r.ctrl_field is None:
            continue
        f = inputs[r.ctrl_field] if inputs is not None else None
        if f is not None and f.is_array and r.ctrl_index is None and r.elements is None:
            # a refused relation to a whole array: it stands for all of it
            for i in range(f.size):
                fed.setdefault((r.ctrl_field, i), r)
            continue
        twice: dict[int, list[int | None]] = {}
        for _, index in r.leaves():
            key = (r.ctrl_field, index)
            if key in fed:
                twice.setdefault(fed[key].node.line, []).append(index)
            else:
                fed[key] = r
        if not twice:
            continue
        r.ok = False
        line, indices = next(iter(twice.items()))
        if indices == [None]:
            ck.err_rule("4.8", r.ctrl_node,
                        f"controller input {show(r.ctrl_field)} is fed twice (first by the relation at line {line})")
        elif r.elements is None:
            ck.err_rule("4.15", r.ctrl_node,
                        f"element {indices[0]} of controller input {show(r.ctrl_field)} is fed twice (first by "
                        f"the relation at line {line}); each element of a controller array is fed exactly once")
        else:
            lines = sorted(twice)
            where = f"line {lines[0]}" if len(lines) == 1 else f"lines {', '.join(map(str, lines))}"
            ck.err_rule("4.15", r.ctrl_node,
                        f"elements {index_ranges(i for ix in twice.values() for i in ix)} of controller input "
                        f"{show(r.ctrl_field)} are fed twice (also by the relations at {where}); each element "
                        "of a controller array is fed exactly once")
    if ufields is None or not ck.inputs_listed:
        return
    for knode, f in ufields:
        if not f.is_array:
            if (f.name, None) not in fed:
                ck.err_rule("4.8", knode, f"controller input {show(f.name)} is not fed by any input relation")
            continue
        missing = [i for i in range(f.size) if (f.name, i) not in fed]
        if len(missing) == f.size:
            ck.err_rule("4.15", knode, f"controller input {show(f.name)} ({f.type_text}) is not fed by any input "
                                       f"relation (relate a whole array to it, or each element {f.name}[i])")
        elif len(missing) == 1:
            ck.err_rule("4.15", knode, f"element {missing[0]} of controller input {show(f.name)} ({f.type_text}) "
                                       "is not fed by any input relation; each element of a controller array is "
                                       "fed exactly once")
        elif missing:
            ck.err_rule("4.15", knode, f"elements {index_ranges(missing)} of controller input {show(f.name)} "
                                       f"({f.type_text}) are not fed by any input relation; each element of a "
                                       "controller array is fed exactly once")


def index_ranges(indices) -> str:
    """Sorted indices as ranges: ``0..2, 5, 7..9``."""
    out, run = [], []
    for i in sorted(indices):
        if run and i == run[-1] + 1:
            run.append(i)
            continue
        if run:
            out.append(str(run[0]) if len(run) == 1 else f"{run[0]}..{run[-1]}")
        run = [i]
    if run:
        out.append(str(run[0]) if len(run) == 1 else f"{run[0]}..{run[-1]}")
    return ", ".join(out)


def check_written_once(ck: Checker, out_rels: list[Rel]) -> None:
    """Rule 4.8: a published field (each element of a whole array, rule
    4.15) is written by at most one output relation."""
    written: dict[tuple[str, str], Rel] = {}
    for r in out_rels:
        if r.topic is None or r.path is None:
            continue
        twice: dict[int, list[str]] = {}
        for leaf, _ in r.leaves():
            key = (r.topic.name, str(leaf))
            if key in written:
                twice.setdefault(written[key].node.line, []).append(str(leaf))
            else:
                written[key] = r
        for line, leaves in twice.items():
            if r.elements is not None:
                ck.err_rule("4.8", r.path_node,
                            f"field {show(r.row[0])} of topic {show(r.topic.name)} is fed twice: elements "
                            f"{index_ranges(i for p, i, _ in r.elements if str(p) in leaves)} are also written "
                            f"by the relation at line {line}")
            else:
                ck.err_rule("4.8", r.path_node,
                            f"field {show(r.written or str(r.path))} of topic {show(r.topic.name)} is fed twice "
                            f"(first by the relation at line {line})")
            r.ok = False

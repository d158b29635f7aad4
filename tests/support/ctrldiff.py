"""Three-way differential runs of a block-diagram controller.

The same input rows go through:

- Coq's own semantics, ``Diagram.dg_step`` folded from ``dg_init`` over
  the rows, extracted to OCaml (``ExtrOcamlBasic``, Coq's integers kept as
  their inductive types: the extracted code computes what the Coq
  functions compute) and run;
- the controller C that ``pyrosgen generate`` printed, compiled by gcc
  (``-O2 -ffp-contract=off``, and ``-O0`` under ASan/UBSan), stepped by a
  harness that includes it;
- the reference interpreter ``pyrosgen.frontend.blocksim``.

Each prints, per step, the outputs (field order) then the next state
(state order): integers and ``bool`` in decimal, floats as their IEEE bit
pattern ``0x`` + 16 or 8 hex digits, the format of Coq's
``DiagramText.val_text``.  :func:`compare` accepts a difference only where
both sides are NaNs: C leaves NaN payloads unspecified and gcc may swap
the operands of ``+`` and ``*`` (DESIGN.md section 6.2).
"""

from __future__ import annotations

import random
import struct
from pathlib import Path

from pyrosgen.frontend import blocksim
from pyrosgen.frontend.model import NodeModel
from pyrosgen.proof.coqdiagram import emit_diagram
from pyrosgen.proof.coqdriver import DEFAULT_THEORIES

from support.generate import run

C_TYPES = {"bool": "unsigned char", "int32": "int", "uint32": "unsigned int", "int64": "long long",
           "uint64": "unsigned long long", "float32": "float", "float64": "double"}
COQ_VAL = {"bool": "Vint z", "int32": "Vint z", "uint32": "Vint z", "int64": "Vlong z",
           "uint64": "Vlong z", "float32": "Vsingle (float32_of_bits z)",
           "float64": "Vfloat (float64_of_bits z)"}
RANGES = {"bool": (0, 255), "int32": (-(1 << 31), (1 << 31) - 1), "uint32": (0, (1 << 32) - 1),
          "int64": (-(1 << 63), (1 << 63) - 1), "uint64": (0, (1 << 64) - 1)}

F64_EDGES = [0x0, 0x8000000000000000, 0x7FF0000000000000, 0xFFF0000000000000, 0x7FF8000000000000,
             0x7FF0000000000123, 0xFFF8000000000456, 0x1, 0x000FFFFFFFFFFFFF, 0x0010000000000000,
             0x7FEFFFFFFFFFFFFF, 0xFFEFFFFFFFFFFFFF, 0x3FF0000000000000, 0xBFF0000000000000,
             0x3FE0000000000000, 0x4000000000000000]
F32_EDGES = [0x0, 0x80000000, 0x7F800000, 0xFF800000, 0x7FC00000, 0x7F800123, 0xFFC00456, 0x1,
             0x007FFFFF, 0x7F7FFFFF, 0xFF7FFFFF, 0x3F800000, 0xBF800000, 0x3F000000]


def _f64(x: float) -> int:
    return struct.unpack("<Q", struct.pack("<d", x))[0]


def _f32(x: float) -> int:
    return struct.unpack("<I", struct.pack("<f", x))[0]


def random_value(prim: str, rng: random.Random) -> int:
    """A value of ``prim`` (floats: a bit pattern): an edge value a third
    of the time, a small number a third, anything the rest."""
    k = rng.random()
    if prim == "float64":
        if k < 0.33:
            return rng.choice(F64_EDGES)
        return _f64(rng.uniform(-3, 3)) if k < 0.66 else rng.getrandbits(64)
    if prim == "float32":
        if k < 0.33:
            return rng.choice(F32_EDGES)
        return _f32(rng.uniform(-3, 3)) if k < 0.66 else rng.getrandbits(32)
    lo, hi = RANGES[prim]
    if prim == "bool":
        return rng.choice([0, 1, 1, 0, 2, 255])
    if k < 0.33:
        return rng.choice([lo, hi, 0, 1, -1 if lo < 0 else 2, lo + 1, hi - 1])
    return rng.randint(-1000, 1000) if k < 0.66 and lo < 0 else rng.randint(lo, hi)


def input_rows(model: NodeModel, steps: int, seed: int) -> list[list[int]]:
    rng = random.Random(seed)
    fields = model.controller.inputs.fields
    return [[random_value(f.prim, rng) for f in fields] for _ in range(steps)]


def _fmt(prim: str, v: int) -> str:
    if prim == "float64":
        return f"0x{v:016x}"
    if prim == "float32":
        return f"0x{v:08x}"
    return str(v)


def _is_nan(prim: str, text: str) -> bool:
    if prim not in ("float32", "float64"):
        return False
    b = int(text, 16)
    return (b & 0x7FF0000000000000 == 0x7FF0000000000000 and b & 0xFFFFFFFFFFFFF != 0) if prim == "float64" \
        else (b & 0x7F800000 == 0x7F800000 and b & 0x7FFFFF != 0)


def columns(model: NodeModel) -> list[tuple[str, str]]:
    """(name, prim) of each printed column: outputs, then states."""
    d = model.controller.diagram
    return [(f.name, f.prim) for f in model.controller.outputs.fields] + [(b.name, b.prim) for b in d.states]


# --------------------------------------------------------------------------
# blocksim


def run_blocksim(model: NodeModel, rows: list[list[int]]) -> list[str]:
    d = model.controller.diagram
    fields = model.controller.inputs.fields
    state = blocksim.initial_state(d)
    out = []
    for row in rows:
        u = {f.name: (v if f.prim != "bool" else v) for f, v in zip(fields, row)}
        state, y = blocksim.step(d, state, u)
        cols = [_fmt(f.prim, y[f.name]) for f in model.controller.outputs.fields]
        cols += [_fmt(b.prim, state[b.name]) for b in d.states]
        out.append(" ".join(cols))
    return out


# --------------------------------------------------------------------------
# C


def _harness(model: NodeModel, controller_c: Path) -> str:
    c = model.controller
    d = c.diagram
    lines = [f'#include "{controller_c.name}"', "#include <stdio.h>", "#include <string.h>", "",
             "int main(void)", "{", "    char line[4096];", f"    {c.name}_initialize();",
             "    while (fgets(line, sizeof line, stdin)) {", "        char *p = line;",
             "        unsigned long long w; long long s; int n;"]
    for f in c.inputs.fields:
        t = C_TYPES[f.prim]
        if f.prim in ("float32", "float64"):
            size = 8 if f.prim == "float64" else 4
            lines += [f"        sscanf(p, \"%llu%n\", &w, &n); p += n;",
                      f"        {{ {'unsigned long long' if size == 8 else 'unsigned int'} b = ({'unsigned long long' if size == 8 else 'unsigned int'})w; "
                      f"memcpy(&{c.inputs.var_name}.{f.name}, &b, {size}); }}"]
        elif f.prim in ("uint64", "uint32"):
            lines += ["        sscanf(p, \"%llu%n\", &w, &n); p += n;", f"        {c.inputs.var_name}.{f.name} = ({t})w;"]
        else:
            lines += ["        sscanf(p, \"%lld%n\", &s, &n); p += n;", f"        {c.inputs.var_name}.{f.name} = ({t})s;"]
    lines.append(f"        {c.name}_step();")
    outs = [(f"{c.outputs.var_name}.{f.name}", f.prim) for f in c.outputs.fields]
    outs += [(f"{c.name}_DW.{b.name}", b.prim) for b in d.states]
    for i, (lv, prim) in enumerate(outs):
        sep = '" "' if i else '""'
        if prim == "float64":
            lines.append(f"        {{ unsigned long long b; memcpy(&b, &{lv}, 8); printf(\"%s0x%016llx\", {sep}, b); }}")
        elif prim == "float32":
            lines.append(f"        {{ unsigned int b; memcpy(&b, &{lv}, 4); printf(\"%s0x%08x\", {sep}, b); }}")
        elif prim in ("uint64", "uint32", "bool"):
            lines.append(f"        printf(\"%s%llu\", {sep}, (unsigned long long){lv});")
        else:
            lines.append(f"        printf(\"%s%lld\", {sep}, (long long){lv});")
    lines += ["        printf(\"\\n\");", "    }", "    return 0;", "}", ""]
    return "\n".join(lines)


def build_c(model: NodeModel, controller_c: Path, work: Path, flags: list[str], name: str) -> Path:
    h = work / f"{name}.c"
    h.write_text(_harness(model, controller_c), encoding="ascii")
    exe = work / name
    run(["gcc", "-std=c11", *flags, "-I", str(controller_c.parent), str(h), "-o", str(exe), "-lm"])
    return exe


def run_c(exe: Path, rows: list[list[int]], env=None) -> list[str]:
    import subprocess

    text = "".join(" ".join(str(v) for v in row) + "\n" for row in rows)
    p = subprocess.run([str(exe)], input=text, capture_output=True, text=True, timeout=300, env=env)
    assert p.returncode == 0, p.stderr
    assert "runtime error" not in p.stderr, p.stderr
    return p.stdout.splitlines()


# --------------------------------------------------------------------------
# Coq, extracted


_DRIVER = """\
let rec pos_of_bits = function
  | [] -> Extr.XH
  | b :: rest -> let p = pos_of_bits rest in if b then Extr.XI p else Extr.XO p

(* a positive from its binary digits, most significant first *)
let positive_of digits =
  match digits with
  | [] -> failwith "zero"
  | _ :: rest -> pos_of_bits (List.rev rest)

let z_of_string s =
  let neg = String.length s > 0 && s.[0] = '-' in
  let s = if neg then String.sub s 1 (String.length s - 1) else s in
  (* decimal string to binary digits, by repeated halving *)
  let digits = ref (List.init (String.length s) (fun i -> Char.code s.[i] - 48)) in
  let bits = ref [] in
  let is_zero l = List.for_all (fun d -> d = 0) l in
  while not (is_zero !digits) do
    let carry = ref 0 in
    let q = List.map (fun d -> let v = !carry * 10 + d in carry := v mod 2; v / 2) !digits in
    bits := (!carry = 1) :: !bits;
    digits := q
  done;
  if !bits = [] then Extr.Z0
  else
    let p = positive_of !bits in
    if neg then Extr.Zneg p else Extr.Zpos p

let () =
  let rows = ref [] in
  (try
     while true do
       let line = input_line stdin in
       let words = List.filter (fun w -> w <> "") (String.split_on_char ' ' line) in
       rows := List.map z_of_string words :: !rows
     done
   with End_of_file -> ());
  print_string (Extr.run_rows (List.rev !rows))
"""


def _coq_file(model: NodeModel) -> str:
    c = model.controller
    d = c.diagram
    fields = c.inputs.fields
    # one Z per input field, in field order: the inputs struct
    args = " ".join(f"z{i}" for i in range(len(fields)))
    u = "; ".join(f'("{f.name}", MVscalar ({COQ_VAL[f.prim].replace("z", f"z{i}")}))'
                  for i, f in enumerate(fields))
    cols = [f'field_val y "{f.name}"' for f in c.outputs.fields] + [f'field_val s "{b.name}"' for b in d.states]
    return f"""From Coq Require Import String List ZArith.
From Coq Require Import extraction.ExtrOcamlBasic extraction.ExtrOcamlNativeString.
From ROSGen Require Import Syntax Values FloatBits NodeModel Diagram DiagramText Printer.
Import ListNotations.
Local Open Scope string_scope.

{emit_diagram(model)}

Definition inputs_of (zs : list Z) : mval :=
  match zs with
  | [{args.replace(' ', '; ')}] => MVstruct [{u}]
  | _ => MVstruct []
  end.

Definition line (s y : mval) : string :=
  String.concat " " (map val_text [{'; '.join(cols)}]).

Fixpoint go (s : mval) (rows : list (list Z)) : list string :=
  match rows with
  | [] => []
  | r :: rows' => let (s', y) := dg_step the_diagram s (inputs_of r) in line s' y :: go s' rows'
  end.

Definition run_rows (rows : list (list Z)) : string := concat_lines (go (dg_init the_diagram) rows).

Extraction "extr.ml" run_rows.
"""


def build_coq(model: NodeModel, work: Path) -> Path:
    v = work / "Extr.v"
    v.write_text(_coq_file(model), encoding="ascii")
    run(["coqc", "-R", str(DEFAULT_THEORIES), "ROSGen", "Extr.v"], cwd=work)
    (work / "driver.ml").write_text(_DRIVER, encoding="ascii")
    run(["ocamlfind", "ocamlopt", "-w", "-a", "extr.mli", "extr.ml", "driver.ml", "-o", "coq_step"], cwd=work)
    return work / "coq_step"


def compare(model: NodeModel, a: list[str], b: list[str], names=("a", "b")) -> list[str]:
    """The differences between two runs (empty: they agree), NaN payloads
    excepted."""
    cols = columns(model)
    diffs = []
    if len(a) != len(b):
        diffs.append(f"{names[0]} printed {len(a)} steps, {names[1]} {len(b)}")
    for i, (la, lb) in enumerate(zip(a, b)):
        for (name, prim), x, y in zip(cols, la.split(), lb.split()):
            if x != y and not (_is_nan(prim, x) and _is_nan(prim, y)):
                diffs.append(f"step {i}: {name}: {names[0]} {x}, {names[1]} {y}")
    return diffs

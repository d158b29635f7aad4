"""Helpers for the tests of the Coq C printer (ROSGen.Printer).

- run the fast printing path (coq/extraction/print_program.sh);
- evaluate Coq string expressions with coqc + vm_compute;
- parse the S-expression dump (grammar in coq/theories/clight/Printer.v);
- generate a C harness that prints every global of a printed program in the
  format of the Coq side's renderer (coq/tests/PrinterExamples.v, [render_mval]):
  one line ``path = value`` per scalar leaf, integers in decimal, floats as
  their IEEE bit pattern in hex.
"""

from __future__ import annotations

import re
import shutil
import subprocess
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
COQ_DIR = ROOT / "coq"
THEORIES = COQ_DIR / "theories"
PRINT_SCRIPT = COQ_DIR / "extraction" / "print_program.sh"
EXAMPLES_V = COQ_DIR / "tests" / "PrinterExamples.v"

GCC_STRICT = ["gcc", "-std=c11", "-Wall", "-Wextra", "-Werror", "-pedantic"]


def run(cmd: list[str], cwd: Path | None = None, timeout: int = 900) -> subprocess.CompletedProcess:
    """Run a command; raise with its output if it fails."""
    proc = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True, timeout=timeout, check=False)
    if proc.returncode != 0:
        raise AssertionError(
            f"command failed ({proc.returncode}): {' '.join(map(str, cmd))}\n"
            f"--- stdout ---\n{proc.stdout}\n--- stderr ---\n{proc.stderr}")
    return proc


def build_coq_library() -> None:
    """Build the ROSGen library (incremental; a no-op when up to date)."""
    run(["make", "--no-print-directory", "-C", str(COQ_DIR), "build"], timeout=3600)


def print_via_extraction(v_file: Path, prefix: Path) -> tuple[str, str]:
    """Print ``the_program`` of ``v_file``: returns (C text, S-expression dump)."""
    run(["sh", str(PRINT_SCRIPT), "-o", str(prefix), str(v_file)])
    return (Path(str(prefix) + ".c").read_text(), Path(str(prefix) + ".sexp").read_text())


_COQ_STRING = re.compile(r'^\s+= "((?:[^"]|"")*)"\s*\n\s+: (?:String\.)?string', re.M)


def coq_eval_strings(v_file: Path, exprs: list[str], workdir: Path) -> list[str]:
    """Compile a copy of ``v_file`` in ``workdir`` and return the values of
    the Coq string expressions ``exprs`` (which may refer to its definitions
    unqualified), each computed by ``Eval vm_compute``."""
    workdir.mkdir(parents=True, exist_ok=True)
    shutil.copy(v_file, workdir / "Ex.v")
    base = ["coqc", "-q", "-R", str(THEORIES), "ROSGen", "-R", str(workdir), "PT"]
    run(base + ["Ex.v"], cwd=workdir)
    lines = ["From Coq Require Import String.", "Local Open Scope string_scope.",
             "Require Import PT.Ex."]
    lines += [f"Eval vm_compute in ({e})." for e in exprs]
    (workdir / "Dump.v").write_text("\n".join(lines) + "\n")
    out = run(base + ["Dump.v"], cwd=workdir).stdout
    values = [m.group(1).replace('""', '"') for m in _COQ_STRING.finditer(out)]
    if len(values) != len(exprs):
        raise AssertionError(f"expected {len(exprs)} strings from coqc, got {len(values)}:\n{out}")
    return values


# ---------------------------------------------------------------------------
# S-expressions: the parser lives in pyrosgen.proof.sexp (shared with the printer
# validation and the differential tests); re-exported here.

from pyrosgen.proof.sexp import SString, parse_sexp, program_items  # noqa: E402,F401


# ---------------------------------------------------------------------------
# Harness

def _dump_code(path: str, ty, structs: dict) -> list[str]:
    """C statements printing the scalar leaves of the object ``path`` of
    sexp type ``ty``."""
    if isinstance(ty, list) and ty[0] == "struct":
        code = []
        for fname, fty in structs[ty[1]]:
            code += _dump_code(f"{path}.{fname}", fty, structs)
        return code
    if isinstance(ty, list) and ty[0] == "array":
        code = []
        for k in range(int(ty[2])):
            code += _dump_code(f"{path}[{k}]", ty[1], structs)
        return code
    label = f'"{path} = '
    if isinstance(ty, list) and ty[0] == "int":
        if ty[2] == "signed":
            return [f'printf({label}%lld\\n", (long long)({path}));']
        return [f'printf({label}%llu\\n", (unsigned long long)({path}));']
    if isinstance(ty, list) and ty[0] == "long":
        if ty[1] == "signed":
            return [f'printf({label}%lld\\n", (long long)({path}));']
        return [f'printf({label}%llu\\n", (unsigned long long)({path}));']
    if ty == ["float", "F64"]:
        return [f'{{ unsigned long long b_; memcpy(&b_, &({path}), 8); '
                f'printf({label}0x%016llx\\n", b_); }}']
    if ty == ["float", "F32"]:
        return [f'{{ unsigned int b_; memcpy(&b_, &({path}), 4); '
                f'printf({label}0x%08x\\n", b_); }}']
    if isinstance(ty, list) and ty[0] == "ptr":
        return [f'printf({label}%s\\n", ({path}) ? "ptr" : "0");']
    raise ValueError(f"cannot dump type {ty}")


def harness_source(c_file: Path, items: dict, stubs: str, entry: str | None = None,
                   entry_returns_int: bool = True) -> str:
    """A C file that includes the printed program ``c_file``, defines the
    ``stubs`` (externs and external functions), calls ``entry`` (default:
    the program's main) and prints every global variable."""
    entry = entry or items["main"]
    body = []
    if entry_returns_int:
        body.append(f'printf("result = %d\\n", {entry}());')
    else:
        body.append(f"{entry}();")
    for name, ty in items["gvars"].items():
        body += _dump_code(name, ty, items["structs"])
    return "\n".join([
        "#include <stdio.h>",
        "#include <string.h>",
        f'#include "{c_file}"',
        stubs,
        "int main(void)",
        "{",
        *("    " + line for line in body),
        "    return 0;",
        "}",
        "",
    ])


def compile_and_run(harness: str, workdir: Path, opt: str = "-O0", name: str = "harness") -> str:
    """Compile the harness (it includes the printed C) and run it."""
    src = workdir / f"{name}.c"
    src.write_text(harness)
    exe = workdir / f"{name}{opt}"
    run(["gcc", "-std=c11", opt, "-Wall", "-Wextra", "-Werror", str(src), "-o", str(exe)])
    return run([str(exe)]).stdout

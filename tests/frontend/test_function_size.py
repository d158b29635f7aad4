"""DESIGN.md section 3: no function of the front end (``pyrosgen/frontend/``)
is longer than 100 lines.  A data table is an assignment, not a function,
and is not counted; a method or a nested function is a function.
"""

from __future__ import annotations

import ast
from pathlib import Path

FRONTEND = Path(__file__).resolve().parents[2] / "pyrosgen" / "frontend"

#: The longest function the front end may have, in lines (its decorators,
#: signature, docstring and body).
MAX_FUNCTION_LINES = 100


def long_functions(folder: Path, limit: int) -> list[str]:
    """``file:line: name has N lines`` for each function of the modules of
    ``folder`` longer than ``limit`` lines."""
    out = []
    for path in sorted(folder.glob("*.py")):
        tree = ast.parse(path.read_text(encoding="utf-8"), str(path))
        for node in ast.walk(tree):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                start = node.decorator_list[0].lineno if node.decorator_list else node.lineno
                n = node.end_lineno - start + 1
                if n > limit:
                    out.append(f"{path.name}:{node.lineno}: {node.name} has {n} lines")
    return out


def test_no_function_of_the_front_end_is_over_100_lines():
    assert len(list(FRONTEND.glob("rule_*.py"))) >= 10  # the rule modules are where they are looked for
    assert long_functions(FRONTEND, MAX_FUNCTION_LINES) == []


def test_the_check_has_teeth(tmp_path):
    """101 lines of function are found, 100 are not; a 200-line table is
    not a function; a long method is found inside its class."""
    table = "T = (\n" + "    1,\n" * 200 + ")\n"
    (tmp_path / "m.py").write_text("def f():\n" + "    x = 1\n" * 100 + "\n" + table)
    assert long_functions(tmp_path, 100) == ["m.py:1: f has 101 lines"]
    (tmp_path / "m.py").write_text("def f():\n" + "    x = 1\n" * 99 + "\n" + table)
    assert long_functions(tmp_path, 100) == []
    (tmp_path / "m.py").write_text("class C:\n    @staticmethod\n    def g():\n" + "        x = 1\n" * 99)
    assert long_functions(tmp_path, 100) == ["m.py:3: g has 101 lines"]

"""Helpers of the validation tests (printer validation, differential
tests, Frama-C WP)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
LANDSHARK = REPO / "examples" / "landshark" / "landshark_controller.yaml"
MULTI = REPO / "examples" / "multi" / "multi_node.yaml"

#: The example models: key -> (model file, node name).
EXAMPLES = {
    "landshark": (LANDSHARK, "landshark_controller"),
    "multi": (MULTI, "multi_node"),
}

#: Models with timed topics (rule 4.12: timeouts, fallbacks, derived
#: inputs): key -> (model file, node name).
TIMED_EXAMPLES = {
    "velocity_guard": (REPO / "examples" / "velocity_guard" / "velocity_guard.yaml", "velocity_guard"),
    "fresh_policies": (REPO / "tests" / "generate" / "models" / "ok_fresh_policies.yaml", "fresh_policies"),
    "fresh_constants": (REPO / "tests" / "generate" / "models" / "ok_fresh_constants.yaml", "fresh_constants"),
    "fresh_flags": (REPO / "tests" / "generate" / "models" / "ok_fresh_flags.yaml", "fresh_flags"),
}


@dataclass
class GeneratedNode:
    """One generated node: the output directory of ``pyrosgen generate``."""

    key: str
    node: str
    out: Path
    result: object

    @property
    def glue(self) -> Path:
        return self.out / f"{self.node}_glue.c"

    @property
    def header(self) -> Path:
        return self.out / f"{self.node}_types.h"

    @property
    def sexp(self) -> Path:
        return self.out / f"{self.node}.sexp"

    @property
    def vfile(self) -> Path:
        return self.out / f"{self.node}.v"

    def texts(self) -> tuple[str, str, str]:
        """(glue, header, dump) texts."""
        return self.glue.read_text(), self.header.read_text(), self.sexp.read_text()

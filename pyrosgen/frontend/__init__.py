"""The front end: YAML with positions (:mod:`yamlsrc`), the rules for names
(:mod:`names`), message types (the model :mod:`msgmodel`, the loader :mod:`msgload`), the node model
(:mod:`model`) and its rules (:mod:`validate`, DESIGN.md section 4); a controller
written as a block diagram (:mod:`blocks`, rule 4.11), the IEEE 754 bit patterns its
constants are (:mod:`ieee`), and its reference interpreter (:mod:`blocksim`).

:func:`load_model` reads, parses and validates a model file.  The model
module imports nothing from validation: the validator builds the model,
never the reverse.
"""

from pyrosgen.frontend.validate import load_model

__all__ = ["load_model"]

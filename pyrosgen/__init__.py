"""pyrosgen: generator of proven glue code for ROS 1 nodes.

The front end (this package's model layer) reads a node model file, checks it
against the rules of DESIGN.md section 4 and returns a typed, immutable
:class:`NodeModel`::

    from pyrosgen import load_model
    model = load_model("examples/landshark/landshark_controller.yaml")
"""

from pyrosgen.errors import Diagnostic, InvalidNodeModel, PyrosgenError
from pyrosgen.frontend.model import (
    Block,
    Controller,
    ControllerField,
    Diagram,
    InputRelation,
    IOStruct,
    NodeModel,
    OutputRelation,
    Pos,
    Scalar,
    Topic,
)
from pyrosgen.frontend.validate import load_model
from pyrosgen.frontend.msgmodel import C_TYPES, PRIMITIVES, FieldPath, MsgField, MsgType, leaf_paths

__version__ = "0.1.0"

__all__ = [
    "C_TYPES",
    "PRIMITIVES",
    "Block",
    "Controller",
    "ControllerField",
    "Diagnostic",
    "Diagram",
    "FieldPath",
    "IOStruct",
    "InputRelation",
    "InvalidNodeModel",
    "MsgField",
    "MsgType",
    "NodeModel",
    "OutputRelation",
    "Pos",
    "PyrosgenError",
    "Scalar",
    "Topic",
    "leaf_paths",
    "load_model",
]

"""Behaviour trees: Nav2 XML and btnav YAML trees built on py_trees with BT.CPP semantics.

```python
from btnav.bt import load_tree
from btnav.core.clock import SimClock

clock = SimClock()
root = load_tree("trees/navigate.yaml", clock=clock)   # or a Nav2 .xml, or text
root.tick_once()
```
"""

from .base import ControlNode, DecoratorNode, LeafNode, halt, is_skipped
from .display import tree_text
from .document import TreeDocument, parse_xml_text, read_document
from .errors import TreeError, UnknownNodeError
from .loader import build_tree, load_document, load_tree, unknown_nodes
from .registry import node_class, node_types
from .yaml_tree import parse_yaml_text, yaml_to_document

__all__ = [
    "ControlNode",
    "DecoratorNode",
    "LeafNode",
    "TreeDocument",
    "TreeError",
    "UnknownNodeError",
    "build_tree",
    "halt",
    "is_skipped",
    "load_document",
    "load_tree",
    "node_class",
    "node_types",
    "parse_xml_text",
    "parse_yaml_text",
    "read_document",
    "tree_text",
    "unknown_nodes",
    "yaml_to_document",
]

"""btnav's YAML spelling of a BehaviorTree.CPP tree, translated to Nav2's XML elements.

```yaml
main_tree: NavigateToPose          # optional when there is one tree
trees:
  NavigateToPose:
    RecoveryNode:                  # a node is a one-key mapping: type -> ports
      name: NavigateRecovery
      number_of_retries: 6
      children:                    # controls: a list of nodes
        - RateController:
            hz: 1.0
            child:                 # decorators: one node
              ComputePathToPose: {goal: "{goal}", path: "{path}"}
        - GoalUpdated              # a node without ports may be a bare name
```

A file may also be a single node (a one-tree file; its tree ID is `MainTree`).
`"{key}"` is a blackboard reference exactly as in the XML; other values become
the XML attribute text (`true`/`false` for booleans, `a;b;c` for lists, as
BT.CPP reads vectors). `SubTree: {ID: Other, port: "{key}"}` includes a tree.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from os import PathLike
from typing import Any

from ..core.suggest import best_match
from ..core.yaml_io import YamlMap, YamlSeq, load_yaml_text
from .document import Origin, TreeDocument
from .errors import TreeError

TOP_KEYS = ("main_tree", "trees")
DEFAULT_TREE_ID = "MainTree"


def parse_yaml_text(text: str | bytes, file: str | PathLike[str] | None = None) -> TreeDocument:
    """Parse a YAML tree file's text (YAML errors carry file and line)."""
    return yaml_to_document(load_yaml_text(text, file), file)


def yaml_to_document(doc: Any, file: str | PathLike[str] | None = None) -> TreeDocument:
    """Translate loaded YAML (from `core.yaml_io`, so lines are known) into a TreeDocument."""
    return _Translator(None if file is None else str(file)).document(doc)


def attribute_text(value: Any) -> str | None:
    """A YAML scalar as BT.CPP attribute text; None when it has no XML spelling."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float, str)):
        return value if isinstance(value, str) else repr(value)
    if isinstance(value, list):
        parts = [attribute_text(v) for v in value]
        if any(p is None or isinstance(v, (list, dict)) for p, v in zip(parts, value, strict=True)):
            return None
        return ";".join(p for p in parts if p is not None)
    return None


class _Translator:
    def __init__(self, file: str | None) -> None:
        self.file = file
        self.origins: dict[ET.Element, Origin] = {}

    def error(self, message: str, line: int | None, key: str | None = None, **kw: Any) -> TreeError:
        return TreeError(message, file=self.file, line=line, key=key, **kw)

    def document(self, doc: Any) -> TreeDocument:
        if not isinstance(doc, YamlMap) or not doc:
            raise self.error(
                "a tree file is a mapping: `trees:` (and `main_tree:`), or a single node",
                getattr(doc, "line", None),
            )
        root = ET.Element("root", {"BTCPP_format": "4"})
        if any(k in doc for k in TOP_KEYS):
            for key in doc:
                if key not in TOP_KEYS:
                    raise self.error(
                        f"unknown key '{key}' (a tree file has: {', '.join(TOP_KEYS)})",
                        doc.line_of(key),
                        str(key),
                        suggestion=best_match(str(key), TOP_KEYS),
                    )
            trees = doc.get("trees")
            if not isinstance(trees, YamlMap) or not trees:
                raise self.error(
                    "`trees` must map each tree ID to its root node", doc.line_of("trees"), "trees"
                )
            for tree_id, body in trees.items():
                self.tree(root, str(tree_id), body, trees.line_of(tree_id), f"trees.{tree_id}")
            if "main_tree" in doc:
                main = doc["main_tree"]
                if not isinstance(main, str) or main not in trees:
                    raise self.error(
                        f"main_tree '{main}' is not one of the trees: {', '.join(map(str, trees))}",
                        doc.line_of("main_tree"),
                        "main_tree",
                        suggestion=best_match(str(main), [str(t) for t in trees]),
                    )
                root.set("main_tree_to_execute", main)
            elif len(trees) > 1:
                raise self.error(
                    f"several trees ({', '.join(map(str, trees))}): say which runs with `main_tree`",
                    doc.line,
                )
            else:
                root.set("main_tree_to_execute", str(next(iter(trees))))
        else:
            self.tree(root, DEFAULT_TREE_ID, doc, doc.line, None)
            root.set("main_tree_to_execute", DEFAULT_TREE_ID)
        return TreeDocument(root=root, file=self.file, origins=self.origins)

    def tree(
        self, root: ET.Element, tree_id: str, body: Any, line: int | None, key: str | None
    ) -> None:
        bt = ET.SubElement(root, "BehaviorTree", {"ID": tree_id})
        self.origins[bt] = Origin(line=line, key=key)
        self.node(bt, body, line, key)

    def node(self, parent: ET.Element, value: Any, line: int | None, key: str | None) -> None:
        """Append the element for one YAML node (`Type: {...}` or a bare `Type`) to `parent`."""
        if isinstance(value, str):
            node_type, body, node_line = value, None, line
        elif isinstance(value, YamlMap) and len(value) == 1:
            node_type = next(iter(value))
            body, node_line = value[node_type], value.line_of(node_type)
        elif isinstance(value, YamlMap) and value:
            keys = ", ".join(map(str, value))
            raise self.error(
                f"a node is a one-key mapping `Type: {{ports}}`, this one has keys {keys} "
                "(indent the ports under the node type?)",
                value.line,
                key,
            )
        else:
            raise self.error(
                "a node is a one-key mapping `Type: {ports}` or a bare node type name",
                getattr(value, "line", line),
                key,
            )
        node_type = str(node_type)
        key = f"{key}.{node_type}" if key else node_type
        if body is None:
            body = YamlMap(file=self.file, line=node_line)
        if not isinstance(body, YamlMap):
            raise self.error(
                f"the value of '{node_type}' must be a mapping of its ports (and children/child)",
                node_line,
                key,
            )
        elem = ET.SubElement(parent, node_type)
        origin = Origin(line=node_line, key=key)
        self.origins[elem] = origin
        for port, port_value in body.items():
            port_line = body.line_of(port)
            port = str(port)
            if port == "children":
                if not isinstance(port_value, YamlSeq):
                    raise self.error(
                        "`children` is a list of nodes (one `- Type: {...}` per child)",
                        port_line,
                        f"{key}.children",
                    )
                for i, item in enumerate(port_value):
                    self.node(elem, item, port_value.line_of(i), f"{key}.children[{i}]")
            elif port == "child":
                if isinstance(port_value, YamlSeq):
                    raise self.error(
                        "`child` is one node; a list of nodes goes under `children`",
                        port_line,
                        f"{key}.child",
                    )
                self.node(elem, port_value, port_line, f"{key}.child")
            else:
                text = attribute_text(port_value)
                if text is None:
                    raise self.error(
                        f"port '{port}' of {node_type} needs a value: a number, a string, a "
                        'boolean, a list of those or a "{blackboard_key}"',
                        port_line,
                        f"{key}.{port}",
                    )
                elem.set(port, text)
                origin.attr_lines[port] = port_line if port_line is not None else node_line

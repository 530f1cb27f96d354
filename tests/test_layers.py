"""Imports point down the layers of the architecture, never up (docs/architecture.md)."""

from __future__ import annotations

import ast
from pathlib import Path

SRC = Path(__file__).resolve().parents[1] / "src" / "btnav"

#: Bottom to top; a package may import its own layer and those below it.
LAYERS: list[set[str]] = [
    {"core"},
    {"maps", "params", "plugins", "description"},
    {"sim"},
    {"costmap"},
    {"planning", "control", "behaviors", "localization", "slam", "odometry", "exploration"}
    | {"route", "docking", "collision_monitor"},
    {"nav"},
    {"bt"},
    {"navigators"},
    {"mission"},
    {"batch"},
    {"cli", "viz", "testing"},
]
LEVEL = {name: i for i, layer in enumerate(LAYERS) for name in layer}


def package_of(path: Path) -> str:
    rel = path.relative_to(SRC).parts
    return rel[0].removesuffix(".py")


def imported_packages(path: Path) -> set[str]:
    tree = ast.parse(path.read_text(), filename=str(path))
    depth = len(path.relative_to(SRC).parts) - 1  # folders below btnav/
    out: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            if node.level == 0 and node.module and node.module.startswith("btnav."):
                out.add(node.module.split(".")[1])
            elif node.level > depth and node.level - depth == 1:
                # `from ..x import y` from btnav/pkg/mod.py: x is a sibling package
                if node.module:
                    out.add(node.module.split(".")[0])
                else:
                    out.update(alias.name for alias in node.names)
        elif isinstance(node, ast.Import):
            out.update(a.name.split(".")[1] for a in node.names if a.name.startswith("btnav."))
    return out


def test_imports_point_down():
    wrong = []
    for path in sorted(SRC.rglob("*.py")):
        if path.parent == SRC and path.name == "__init__.py":
            continue
        here = package_of(path)
        for pkg in imported_packages(path):
            if pkg in LEVEL and here in LEVEL and LEVEL[pkg] > LEVEL[here]:
                wrong.append(f"{path.relative_to(SRC)} imports btnav.{pkg}")
    assert wrong == [], "upward imports:\n" + "\n".join(wrong)


def test_every_package_has_a_layer():
    packages = {p.name for p in SRC.iterdir() if p.is_dir() and (p / "__init__.py").exists()}
    packages |= {p.stem for p in SRC.glob("*.py") if p.stem != "__init__"}
    assert packages <= set(LEVEL), f"no layer for: {sorted(packages - set(LEVEL))}"

"""The trees btnav ships (`trees/`): Nav2's default trees in YAML, found by bare name.

Wherever a tree is named (a mission's `tree:`, bt_navigator's
`default_nav_to_pose_bt_xml`, `btnav tree show`), `find_tree` turns the name into a
file: an existing path is that file (a Nav2 `.xml` works as it is); otherwise a bare
name, with or without Nav2's `.xml` (or `.yaml`), is the bundled tree of that name:

    navigate_to_pose_w_replanning_and_recovery      -> trees/navigate_to_pose_w_replanning_and_recovery.yaml
    navigate_to_pose_w_replanning_and_recovery.xml  -> the same file
    navigate_w_replanning_and_recovery              -> the same file (Nav2's name before Humble)

`python -m btnav.bt.bundled NAV2_BEHAVIOR_TREES_DIR` regenerates `trees/*.yaml` from
Nav2's XML files with `btnav tree import`'s importer and the credit header.
"""

from __future__ import annotations

import sys
from collections.abc import Sequence
from os import PathLike
from pathlib import Path

from ..core.files import read_bytes
from ..core.resources import bundled_dir
from ..core.suggest import close_matches
from .errors import TreeError, UnknownNodeError
from .xml_to_yaml import import_xml

TREE_SUFFIXES = (".yaml", ".yml", ".xml")

#: Nav2's older names of its default trees -> the bundled name.
ALIASES = {
    "navigate_w_replanning_and_recovery": "navigate_to_pose_w_replanning_and_recovery",
}

#: Where the bundled trees come from.
NAV2_REPOSITORY = "https://github.com/ros-navigation/navigation2"
NAV2_COMMIT = "a3a97043ee93d92fe8d70ec56d183933169beb1c"
NAV2_TREES_PATH = "nav2_bt_navigator/behavior_trees"
#: btnav's own bundled trees (not imported from Nav2's files).
BTNAV_TREES = ("explore",)
#: In Nav2's behavior_trees folder but not a tree: Groot's node palette.
NAV2_NODE_MODEL = "nav2_tree_nodes.xml"


def trees_dir() -> Path:
    return bundled_dir("trees")


def bundled_trees() -> dict[str, Path]:
    """Every bundled tree by bare name (file stem), sorted."""
    folder = trees_dir()
    if not folder.is_dir():
        return {}
    return {p.stem: p for p in sorted(folder.glob("*.yaml"))}


def _bare_name(name: str) -> str | None:
    """`name` without a known suffix, when it is a bare name (no folder part); else None."""
    name = name.strip()
    if not name or "/" in name or "\\" in name:
        return None
    stem = name
    for suffix in TREE_SUFFIXES:
        if stem.lower().endswith(suffix):
            stem = stem[: -len(suffix)]
            break
    return stem or None


def find_tree(name: str | PathLike[str], *, base_dir: str | PathLike[str] | None = None) -> Path:
    """The tree file `name` means: an existing file (relative to `base_dir`), else a bundled tree.

    An unknown name is an `UnknownNodeError` listing the close bundled names.
    """
    text = str(name)
    path = Path(text)
    if base_dir is not None and not path.is_absolute():
        path = Path(base_dir) / path
    if path.is_file():
        return path
    stem = _bare_name(text)
    trees = bundled_trees()
    if stem is not None:
        stem = ALIASES.get(stem, stem)
        if stem in trees:
            return trees[stem]
    if path.is_dir():
        raise TreeError("is a directory, not a tree file", file=path)
    known = ", ".join(trees) or "none"
    what = "no tree file" if stem is None else "no tree file or bundled tree"
    typed = Path(text.strip()).name
    same = _bundled_named_like(typed, trees)
    if same is not None:
        # A bundled tree's name with a folder or another suffix: a "did you mean" with
        # that name would read as the very name they typed, so say what differs.
        why = "no folder" if stem is None else f"a tree file ends in {', '.join(TREE_SUFFIXES)}"
        raise UnknownNodeError(
            f"{what} '{text}'; to use the bundled tree of that name, write its bare name "
            f"'{same}' ({why})",
            file=path if stem is None else None,
        )
    near = close_matches(stem or path.stem, [*trees, *ALIASES])
    raise UnknownNodeError(
        f"{what} '{text}'; bundled trees: {known}",
        file=path if stem is None else None,
        suggestion=near[0] if near else None,
    )


def _bundled_named_like(typed: str, trees: dict[str, Path]) -> str | None:
    """The bundled tree (or alias) whose name `typed` (a file name) starts with, up to a suffix."""
    for tree in sorted([*trees, *ALIASES], key=len, reverse=True):
        if typed == tree or typed.startswith(tree + "."):
            return ALIASES.get(tree, tree)
    return None


# --- making trees/ from Nav2's files --------------------------------------------------


def nav2_header(xml_name: str) -> list[str]:
    """The credit lines at the top of a bundled tree made from Nav2's `xml_name`."""
    return [
        f"Nav2's {xml_name} in btnav's YAML spelling.",
        f"Source: {NAV2_REPOSITORY}, {NAV2_TREES_PATH}/{xml_name}",
        f"at commit {NAV2_COMMIT}.",
        "Copyright the Nav2 authors, licensed under the Apache License 2.0.",
        "Made by `btnav tree import` (python -m btnav.bt.bundled regenerates trees/); do not edit.",
    ]


def nav2_tree_files(nav2_trees: str | PathLike[str]) -> list[Path]:
    """Nav2's tree files in its behavior_trees folder (the node palette excluded), sorted."""
    return sorted(p for p in Path(nav2_trees).glob("*.xml") if p.name != NAV2_NODE_MODEL)


def bundled_yaml(xml_path: str | PathLike[str]) -> str:
    """The bundled YAML for one of Nav2's tree files: the import with its credit header."""
    path = Path(xml_path)
    text = read_bytes(path, error_cls=TreeError, what="tree file")
    return import_xml(text, path, header=nav2_header(path.name))


def write_bundled_trees(
    nav2_trees: str | PathLike[str], out_dir: str | PathLike[str] | None = None
) -> list[Path]:
    """Import every Nav2 tree file into `out_dir` (default: the bundled trees folder)."""
    out = Path(out_dir) if out_dir is not None else trees_dir()
    out.mkdir(parents=True, exist_ok=True)
    written = []
    for xml_path in nav2_tree_files(nav2_trees):
        target = out / f"{xml_path.stem}.yaml"
        target.write_text(bundled_yaml(xml_path), encoding="utf-8")
        written.append(target)
    return written


def main(argv: Sequence[str] | None = None) -> int:
    args = list(sys.argv[1:] if argv is None else argv)
    if len(args) not in (1, 2):
        print(
            "usage: python -m btnav.bt.bundled NAV2_BEHAVIOR_TREES_DIR [OUT_DIR]", file=sys.stderr
        )
        return 2
    for path in write_bundled_trees(*args):
        print(f"wrote {path}")
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())

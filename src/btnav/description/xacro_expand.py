"""xacro to URDF with xacrodoc, keeping the user's file and line for every element and error.

xacrodoc compiles xacro without ROS (args, properties, math, macros, conditionals,
includes, `$(find pkg)` through its own package finder). Three things are added here,
for the length of one expansion only (the hooks are undone afterwards):

- every file xacro reads is parsed by `source_lines.parse_with_lines`, so each element
  carries its place through macro expansion and includes;
- the xacro steps that handle an element (macro calls, includes, properties, macro
  definitions, evaluating an element) note the place of the element that failed on the
  exception, so the error names the line in the user's file, with the macro calls and
  includes it came through;
- xacro's warnings (printed to stderr by xacro itself) become `BtnavWarning`s.

xacro keeps its state in module globals (the file stack, the include list), so an
expansion is not thread-safe; btnav runs one at a time.
"""

from __future__ import annotations

import os
import re
import warnings
import xml.dom.minidom
from collections.abc import Callable, Iterator, Mapping
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from ..core.errors import BtnavWarning
from ..core.suggest import best_match
from .errors import DescriptionError
from .packages import PackagePaths
from .source_lines import LINE_ATTR, SourceFiles, parse_with_lines

#: How many "in macro ... called at ..." steps an error message names.
MAX_CONTEXT = 3


def _src(node: Any) -> str:
    has = getattr(node, "hasAttribute", None)
    return node.getAttribute(LINE_ATTR) if has is not None and has(LINE_ATTR) else ""


def _names(table: Any) -> list[str]:
    """The names defined in an xacro symbol or macro table and its parents (not the globals)."""
    out: list[str] = []
    while isinstance(table, dict) and getattr(table, "parent", None) is not None:
        out += [str(k) for k in dict.keys(table) if not str(k).startswith("*")]
        table = table.parent
    return out


def _mark(exc: BaseException, src: str, **notes: Any) -> None:
    """Note on `exc` the place of the innermost element that failed (the first noted wins)."""
    if not getattr(exc, "btnav_src", ""):
        exc.btnav_src = src  # type: ignore[attr-defined]
        for k, v in notes.items():
            setattr(exc, f"btnav_{k}", v)


def _context(exc: BaseException, text: str) -> None:
    exc.btnav_context = [*getattr(exc, "btnav_context", []), text]  # type: ignore[attr-defined]


class _Hooks:
    """The wrapped xacro functions of one expansion (see the module docstring)."""

    def __init__(self, xacro: Any, sources: SourceFiles, root: str) -> None:
        self.x = xacro
        self.sources = sources
        self.root = root
        self.saved: dict[str, Callable[..., Any]] = {}

    def install(self) -> None:
        x = self.x
        for name in (
            "parse",
            "eval_all",
            "handle_macro_call",
            "process_include",
            "grab_macro",
            "grab_property",
            "check_attrs",
            "warning",
            "print_location",
        ):
            self.saved[name] = getattr(x, name)
            setattr(x, name, getattr(self, name))

    def uninstall(self) -> None:
        for name, fn in self.saved.items():
            setattr(self.x, name, fn)

    def place(self, src: str) -> str:
        file, line = self.sources.decode(src)
        return f"{file}:{line}" if file else "?"

    # -- reading files ------------------------------------------------------------------

    def parse(self, inp: Any, filename: str | None = None) -> Any:
        if inp is None:  # an include: read it with its lines
            assert filename is not None
            path = os.path.join(self.x.root_dir, filename)
            try:
                data = Path(path).read_bytes()
            except OSError as e:
                self.x.filestack.pop()  # as xacro does: not "in file" the missing one
                raise self.x.XacroException(f"{e.strerror}: {path}", exc=e) from None
            return parse_with_lines(data, path, self.sources.add(os.path.normpath(path)))
        if isinstance(inp, str | bytes):  # the top file's text, from xacrodoc
            data = inp.encode() if isinstance(inp, str) else inp
            return parse_with_lines(data, self.root, self.sources.add(self.root))
        return self.saved["parse"](inp, filename)

    # -- noting where things fail --------------------------------------------------------

    def eval_all(self, node: Any, macros: Any, symbols: Any) -> None:
        try:
            self.saved["eval_all"](node, macros, symbols)
        except Exception as exc:
            if not getattr(exc, "btnav_src", ""):
                # Processed xacro children are gone from the tree: the first one left is the
                # inline one (xacro:if, xacro:arg, xacro:insert_block, ...) that failed.
                child = node.firstChild if hasattr(node, "firstChild") else None
                while child is not None:
                    if child.nodeType == child.ELEMENT_NODE and child.tagName.startswith("xacro:"):
                        break
                    child = child.nextSibling
                _mark(exc, _src(child) or _src(node), symbols=_names(symbols))
            raise

    def handle_macro_call(self, node: Any, macros: Any, symbols: Any) -> Any:
        src = ""
        if node.tagName.startswith("xacro:") and node.hasAttribute(LINE_ATTR):
            src = node.getAttribute(LINE_ATTR)
            node.removeAttribute(LINE_ATTR)  # or xacro takes it for a macro parameter
        name = node.tagName[6:]
        try:
            return self.saved["handle_macro_call"](node, macros, symbols)
        except Exception as exc:
            if getattr(exc, "btnav_src", ""):
                _context(exc, f"in macro '{name}' called at {self.place(src)}")
            else:
                _mark(exc, src, macros=_names(macros), symbols=_names(symbols))
            raise

    def process_include(self, elt: Any, macros: Any, symbols: Any, func: Any) -> None:
        src, spec = _src(elt), elt.getAttribute("filename")
        try:
            self.saved["process_include"](elt, macros, symbols, func)
        except Exception as exc:
            if getattr(exc, "btnav_src", ""):
                _context(exc, f"in the file included at {self.place(src)}")
            else:
                _mark(exc, src, include=spec)
            raise

    def grab_macro(self, elt: Any, macros: Any) -> None:
        src = _src(elt)
        try:
            self.saved["grab_macro"](elt, macros)
        except Exception as exc:
            _mark(exc, src)
            raise

    def grab_property(self, elt: Any, table: Any) -> None:
        src = _src(elt)
        try:
            self.saved["grab_property"](elt, table)
        except Exception as exc:
            _mark(exc, src, symbols=_names(table))
            raise

    def check_attrs(self, tag: Any, required: list[str], optional: list[str]) -> Any:
        src = _src(tag)
        if src:  # not one of the tag's attributes as far as xacro is concerned
            tag.removeAttribute(LINE_ATTR)
        try:
            return self.saved["check_attrs"](tag, required, optional)
        finally:
            if src:
                tag.setAttribute(LINE_ATTR, src)

    # -- xacro's own output ---------------------------------------------------------------

    def warning(self, *args: Any, **kwargs: Any) -> None:
        stack = self.x.filestack or [None]
        warnings.warn(
            BtnavWarning(f"xacro: {' '.join(str(a) for a in args)}", file=stack[-1] or self.root),
            stacklevel=3,
        )

    def print_location(self) -> None:
        pass


@contextmanager
def _hooked(sources: SourceFiles, root: str) -> Iterator[Any]:
    import xacro

    hooks = _Hooks(xacro, sources, root)
    hooks.install()
    try:
        xacro.init_stacks(root)  # relative includes are found beside the top file
        yield xacro
    finally:
        hooks.uninstall()
        xacro.init_stacks(None)
        xacro.all_includes = []


def _chain(exc: BaseException) -> Iterator[BaseException]:
    seen: set[int] = set()
    e: BaseException | None = exc
    while e is not None and id(e) not in seen:
        seen.add(id(e))
        yield e
        e = getattr(e, "exc", None) or e.__cause__ or e.__context__


def _error(exc: Exception, sources: SourceFiles, root: str, packages: PackagePaths) -> Exception:
    """A located `DescriptionError` for what failed while expanding."""
    from xacro.substitution_args import ArgException
    from xacrodoc.packages import PackageNotFoundError

    file, line = sources.decode(getattr(exc, "btnav_src", ""))
    file = file or root
    suggestion = None
    chain = list(_chain(exc))
    missing_pkg = next((e for e in chain if isinstance(e, PackageNotFoundError)), None)
    missing_arg = next((e for e in chain if isinstance(e, ArgException)), None)
    missing_file = next((e for e in chain if isinstance(e, FileNotFoundError)), None)
    undefined = next((e for e in chain if isinstance(e, NameError)), None)
    text = " ".join(str(exc).split())
    if isinstance(exc, DescriptionError):
        err: DescriptionError = exc
    elif missing_pkg is not None:
        err = packages.not_found(str(missing_pkg.args[0]) if missing_pkg.args else "?")
    elif missing_arg is not None:
        name = str(missing_arg.args[0]) if missing_arg.args else "?"
        err = DescriptionError(
            f"xacro arg '{name}' has no value: declare it with a default "
            f'(<xacro:arg name="{name}" default="..."/>) or give it (`xacro_args: '
            f"{{{name}: ...}}` in the world's robot, `--arg {name}=...`)"
        )
    elif getattr(exc, "btnav_include", None) is not None and missing_file is not None:
        err = DescriptionError(
            f"cannot include '{exc.btnav_include}': no such file {missing_file.filename}"  # type: ignore[attr-defined]
        )
    elif text.startswith("unknown macro name: xacro:"):
        name = text.removeprefix("unknown macro name: xacro:")
        known = sorted(set(getattr(exc, "btnav_macros", [])))
        suggestion = best_match(name, known)
        shown = f"; defined: {', '.join(known)}" if known and not suggestion else ""
        err = DescriptionError(f"unknown xacro macro '{name}'{shown}")
    elif undefined is not None:
        m = re.search(r"name '([^']+)' is not defined", str(undefined))
        name = m.group(1) if m else str(undefined)
        expr = re.search(r"when evaluating expression '([^']*)'", text)
        suggestion = best_match(name, getattr(exc, "btnav_symbols", []))
        err = DescriptionError(
            f"'{name}' is not defined (no xacro property by that name)"
            + (f" in ${{{expr.group(1)}}}" if expr else "")
        )
    else:
        err = DescriptionError(f"xacro: {text}")
    context = getattr(exc, "btnav_context", [])[:MAX_CONTEXT]
    message = err.message + "".join(f"; {c}" for c in context)
    return DescriptionError(
        message,
        file=err.file or file,
        line=err.line or (line if err.file is None else None),
        suggestion=err.suggestion or suggestion,
    )


def expand_xacro(
    path: Path,
    data: bytes,
    sources: SourceFiles,
    packages: PackagePaths,
    args: Mapping[str, str] | None = None,
) -> xml.dom.minidom.Document:
    """The URDF (or SDF) document `data` (the file `path`) expands to, every element placed."""
    from xacrodoc import XacroDoc

    root = str(path)
    packages.install(path)
    with _hooked(sources, root):
        try:
            return XacroDoc.from_string(data, subargs=dict(args or {}), resolve_packages=False).dom
        except Exception as exc:
            raise _error(exc, sources, root, packages) from None

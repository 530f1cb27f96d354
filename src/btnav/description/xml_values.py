"""Numbers and names read from description elements, each mistake naming its file and line."""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET

from .errors import DescriptionError
from .source_lines import SourceFiles


def error(
    message: str,
    element: ET.Element | None,
    sources: SourceFiles,
    suggestion: str | None = None,
) -> DescriptionError:
    """A `DescriptionError` placed at `element` in the user's file."""
    file, line = sources.place(element)
    top = sources.files[0] if sources.files else None
    return DescriptionError(message, file=file or top, line=line, suggestion=suggestion)


def tag(element: ET.Element) -> str:
    """The element's name without a namespace."""
    return element.tag.rsplit("}", 1)[-1] if isinstance(element.tag, str) else ""


def floats(
    text: str | None, n: int, what: str, element: ET.Element, sources: SourceFiles
) -> tuple[float, ...]:
    """`n` whitespace-separated finite numbers (`"0 0 0.1"`), or a located error."""
    parts = (text or "").split()
    if len(parts) != n:
        got = f"'{text.strip()}'" if text and text.strip() else "nothing"
        raise error(f"{what} needs {n} number{'s' if n > 1 else ''}, got {got}", element, sources)
    out = []
    for part in parts:
        try:
            value = float(part)
        except ValueError:
            raise error(f"malformed number '{part}' in {what}", element, sources) from None
        if not math.isfinite(value):
            raise error(f"{what} must be finite, got '{part}'", element, sources)
        out.append(value)
    return tuple(out)


def number(
    text: str | None,
    what: str,
    element: ET.Element,
    sources: SourceFiles,
    *,
    positive: bool = False,
) -> float:
    (value,) = floats(text, 1, what, element, sources)
    if positive and value <= 0.0:
        raise error(f"{what} must be positive, got {value:g}", element, sources)
    return value


def child_number(
    parent: ET.Element | None,
    path: str,
    sources: SourceFiles,
    default: float | None = None,
    *,
    positive: bool = False,
) -> float | None:
    """The number in the text of `parent/path` (SDF style), or `default` when absent."""
    if parent is None:
        return default
    found = parent.find(path)
    if found is None or not (found.text or "").strip():
        return default
    return number(found.text, f"<{path}>", found, sources, positive=positive)


def child_text(parent: ET.Element | None, path: str) -> str | None:
    if parent is None:
        return None
    found = parent.find(path)
    return None if found is None or found.text is None else found.text.strip()


def required(element: ET.Element, attr: str, sources: SourceFiles) -> str:
    value = element.get(attr)
    if value is None or not value.strip():
        raise error(f"<{tag(element)}> needs a '{attr}' attribute", element, sources)
    return value.strip()

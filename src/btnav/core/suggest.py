"""Did-you-mean for every "unknown name" error in btnav."""

from __future__ import annotations

import difflib
from collections.abc import Iterable


def close_matches(name: str, candidates: Iterable[str], n: int = 3) -> list[str]:
    """The candidates closest to `name`, best first; case and `-`/`_`/`::`/`/` differences count as equal.

    `name` itself is never among them: "did you mean 'x'?" after typing x helps nobody.
    """
    names = sorted(set(candidates) - {name})
    if not names:
        return []

    def norm(s: str) -> str:
        return s.lower().replace("-", "_").replace("::", "/")

    normed = {norm(c): c for c in names}
    key = norm(name)
    exact = [normed[key]] if key in normed else []
    fuzzy = difflib.get_close_matches(key, list(normed), n=n, cutoff=0.6)
    out = exact + [normed[f] for f in fuzzy if normed[f] not in exact]
    # A name whose tail matches (`Spin` for `nav2_behaviors/Spin`) is close too.
    tail = key.rsplit("/", 1)[-1]
    out += [c for k, c in normed.items() if k.rsplit("/", 1)[-1] == tail and c not in out]
    return out[:n]


def best_match(name: str, candidates: Iterable[str]) -> str | None:
    """The single closest spelling, or None when nothing is close."""
    found = close_matches(name, candidates, n=1)
    return found[0] if found else None


def unknown_name_message(kind: str, name: str, candidates: Iterable[str], limit: int = 12) -> str:
    """`unknown planner 'Navfn'; known: a, b, c` (the full list when it is short)."""
    names = sorted(set(candidates))
    if not names:
        return f"unknown {kind} '{name}' (none are known)"
    shown = ", ".join(names[:limit]) + (
        f", ... ({len(names)} in all)" if len(names) > limit else ""
    )
    return f"unknown {kind} '{name}'; known: {shown}"

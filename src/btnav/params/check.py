"""`btnav params check FILE`: what btnav makes of a Nav2 params file, before running anything.

It prints the servers, the plugin each section resolves to (a btnav class, or
"not implemented yet"), the placeholders, and every key or section it ignores;
it exits 0 when the file loads and 2 on a mistake (the one-line located error).
"""

from __future__ import annotations

import sys
from os import PathLike
from typing import TextIO

from ..core.errors import ERROR_PREFIX, BtnavError
from .loader import load_params
from .paramsfile import ParamsFile


def format_report(params: ParamsFile) -> str:
    """The report `params check` prints for a loaded file."""
    lines = [f"params: {params.path}", ""]
    lines.append(f"servers ({len(params.servers)}):")
    width = max((len(s.key) for s in params.servers.values()), default=0)
    for server in params.servers.values():
        where = f"line {server.line}" if server.line else ""
        lines.append(f"  {server.key:<{width}}  {where}")
        for plugin in server.plugins.values():
            origin = " (Nav2 default)" if plugin.defaulted else ""
            lines.append(
                f"    {plugin.kind:<22} {plugin.name} -> {plugin.type}{origin}: {plugin.status}"
            )
    if params.placeholders:
        lines += ["", f"placeholders ({len(params.placeholders)}):"]
        for ph in params.placeholders:
            where = f"line {ph.line}: " if ph.line else ""
            lines.append(f"  {where}{ph.key}: {ph.text} -> {ph.resolved}")
    lines += ["", f"ignored ({len(params.ignored)}):"]
    for ignored in sorted(params.ignored, key=lambda e: (e.line or 0, e.key)):
        lines.append(f"  {ignored}")
    plugins = params.plugins()
    done = sum(1 for p in plugins if p.implemented)
    lines += [
        "",
        f"OK: {len(params.servers)} servers, {len(plugins)} plugin sections "
        f"({done} implemented, {len(plugins) - done} not implemented yet), "
        f"{len(params.ignored)} ignored entries",
    ]
    return "\n".join(lines)


def check_report(path: str | PathLike[str]) -> str:
    """Load `path` and describe it; a mistake raises the located `BtnavError`."""
    return format_report(load_params(path))


def check_main(
    path: str | PathLike[str], out: TextIO | None = None, err: TextIO | None = None
) -> int:
    """Print the report and return 0, or print the one-line error and return 2."""
    out = out or sys.stdout
    err = err or sys.stderr
    try:
        report = check_report(path)
    except BtnavError as exc:
        print(f"{ERROR_PREFIX}{exc}", file=err)
        return 2
    print(report, file=out)
    return 0

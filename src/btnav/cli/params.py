"""`btnav params check [--strict] FILE`: what btnav makes of a Nav2 params file, before running.

It prints the servers, the plugin each section resolves to (a btnav class, or
"not implemented yet"), the placeholders, and every key or section it ignores; each
key Nav2 itself skips (a ROS 1 name, an older distribution's, a BT port) is one
`btnav: warning:` line on stderr. It exits 0 when the file loads and 2 on a mistake
(the one-line located error); with `--strict` a key Nav2 skips is such a mistake.
"""

from __future__ import annotations

import sys
from os import PathLike
from typing import TextIO

from ..core.errors import ERROR_PREFIX, WARNING_PREFIX, BtnavError
from ..params.check import ParamsCheck, check_params
from . import EXIT_OK, EXIT_USER_ERROR


def format_report(check: ParamsCheck) -> str:
    """The report `params check` prints for a loaded file."""
    params = check.params
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
    ignored = check.ignored
    lines += ["", f"ignored ({len(ignored)}):"]
    lines += [f"  {entry}" for entry in ignored]
    skipped = len(check.skipped)
    lines += [
        "",
        f"OK: {len(params.servers)} servers, {len(check.plugins)} plugin sections "
        f"({len(check.implemented)} implemented, {len(check.not_implemented)} not implemented "
        f"yet), {len(ignored)} ignored entries, {skipped} key{'s' if skipped != 1 else ''} "
        "Nav2 skips too" + (" (warned on stderr)" if skipped else ""),
    ]
    return "\n".join(lines)


#: What `--strict` says in its error: why a key Nav2 skips is one.
STRICT = "--strict"


def check_report(path: str | PathLike[str], *, strict: bool = False) -> str:
    """Load `path` and describe it; a mistake raises the located `BtnavError`."""
    return format_report(check_params(path, strict=STRICT if strict else None))


def check_main(
    path: str | PathLike[str],
    out: TextIO | None = None,
    err: TextIO | None = None,
    *,
    strict: bool = False,
) -> int:
    """Print a warning per key Nav2 skips and the report, and return 0; or print the
    one-line error and return 2 (`strict`: a key Nav2 skips is an error)."""
    out = out or sys.stdout
    err = err or sys.stderr
    try:
        check = check_params(path, strict=STRICT if strict else None)
    except BtnavError as exc:
        print(f"{ERROR_PREFIX}{exc}", file=err)
        return EXIT_USER_ERROR
    for skipped in check.skipped:
        print(f"{WARNING_PREFIX}{skipped}", file=err)
    print(format_report(check), file=out)
    return EXIT_OK

"""What `btnav params check FILE` finds in a Nav2 params file, before running anything.

Loading already validates every section and resolves every plugin; a check adds the
tallies a user reads first (how many plugin sections btnav implements, how many keys
it ignores, how many Nav2 skips too) and orders the ignored entries as the file does.
A mistake raises the located `BtnavError` of `load_params`; so does the first key Nav2
skips, in a strict check. Printing the report is `btnav.cli.params`'s job.
"""

from __future__ import annotations

from dataclasses import dataclass
from os import PathLike

from .loader import load_params
from .paramsfile import IgnoredEntry, ParamsFile, PluginSection, SkippedKey


@dataclass(frozen=True)
class ParamsCheck:
    """A loaded params file seen as `params check` reports it."""

    params: ParamsFile

    @property
    def plugins(self) -> list[PluginSection]:
        return self.params.plugins()

    @property
    def implemented(self) -> list[PluginSection]:
        return [p for p in self.plugins if p.implemented]

    @property
    def not_implemented(self) -> list[PluginSection]:
        """Sections whose plugin btnav has no class for yet (they load, and are not run)."""
        return [p for p in self.plugins if not p.implemented]

    @property
    def ignored(self) -> list[IgnoredEntry]:
        """Every ignored key or section, in file order (entries without a line first)."""
        return sorted(self.params.ignored, key=lambda e: (e.line or 0, e.key))

    @property
    def skipped(self) -> list[SkippedKey]:
        """Every key Nav2 does not read (so neither does btnav), in file order."""
        return self.params.skipped


def check_params(path: str | PathLike[str], *, strict: str | None = None) -> ParamsCheck:
    """Load `path` for a check; a mistake raises the located `BtnavError`, and so does the
    first key Nav2 skips when `strict` names what asked for that. No warnings are issued:
    the caller reports `skipped` itself."""
    return ParamsCheck(load_params(path, strict=strict, warn=False))

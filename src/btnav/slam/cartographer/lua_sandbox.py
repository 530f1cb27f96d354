"""The sandboxed Lua that runs a Cartographer `.lua` configuration (lupa underneath).

A configuration is a program, so it runs in a real Lua, but in a sandbox: no `os`, `io`,
`require`, `dofile` or `load`, a cap on instructions and memory, and `include` resolved
as `cartographer_node`'s FileResolver does (the first folder of `dirs` holding the file).
Each chunk is named `btnav#<i>` so a Lua error maps back to the file and line it came
from. What the configuration returns comes back as plain Python (dicts, lists, scalars).
"""

from __future__ import annotations

import re
from collections.abc import Callable
from pathlib import Path
from typing import Any

from ...core.errors import BtnavError
from ...core.suggest import best_match
from .options import Key, spell

__all__ = [
    "FORBIDDEN",
    "MAX_INSTRUCTIONS",
    "MAX_MEMORY",
    "CartographerConfigError",
    "LuaRun",
]

#: What a runaway configuration may spend before it is stopped (a real one needs ~1e4 steps).
MAX_INSTRUCTIONS, MAX_MEMORY = 10_000_000, 64 * 2**20
#: Names a configuration may not touch; reaching for one says why instead of "nil value".
FORBIDDEN = ("os", "io", "require", "dofile", "loadfile", "load", "loadstring", "package",
             "debug", "collectgarbage", "coroutine", "python", "module", "setfenv", "getfenv", "read")  # fmt: skip


class CartographerConfigError(BtnavError):
    """A Cartographer configuration btnav cannot run or accept (file, line, dotted key)."""


_BOOT = """function(resolve, forbidden, limit)
  local load, error, type, pairs, getinfo = load, error, type, pairs, debug.getinfo
  local function copy(t) local c = {} for k, v in pairs(t) do c[k] = v end return c end
  local env = {
    math = copy(math), string = copy(string), table = copy(table),
    pairs = pairs, ipairs = ipairs, next = next, type = type, tostring = tostring,
    tonumber = tonumber, select = select, error = error, assert = assert, rawget = rawget,
    rawset = rawset, rawequal = rawequal, rawlen = rawlen, setmetatable = setmetatable,
    getmetatable = getmetatable, unpack = table.unpack or unpack, _VERSION = _VERSION,
    print = function() end,
  }
  env._G = env
  local function run(code, chunkname)
    local chunk, err = load(code, chunkname, "t", env)
    if not chunk then error(err, 0) end
    return chunk()
  end
  env.include = function(name)
    local caller = getinfo(2, "Sl")
    return run(resolve(name, caller.short_src, caller.currentline))
  end
  env.choose = function(condition, a, b)
    if type(condition) ~= "boolean" then error("choose(condition, a, b) needs a boolean condition", 2) end
    if condition then return a end
    return b
  end
  setmetatable(env, {__index = function(_, name)
    if forbidden[name] then
      error("'" .. name .. "' is not available: btnav runs Cartographer configurations in a "
        .. "sandbox (no os, io, require, dofile, load; only include reads files)", 2)
    end
  end})
  debug.sethook(function() error("still running after " .. limit .. " Lua steps: an endless loop?", 2) end, "", limit)
  local function aliases(root)
    local paths, out = {}, {}
    local function walk(t, path)
      if paths[t] then return end
      paths[t] = path
      for k, v in pairs(t) do
        if type(k) == "string" and type(v) == "table" then walk(v, path .. "\\1" .. k) end
      end
    end
    walk(root, "")
    for name, v in pairs(env) do
      if type(name) == "string" and type(v) == "table" and paths[v] then out[name] = paths[v] end
    end
    return out
  end
  return run, aliases
end"""
_CHUNK = re.compile(r"^btnav#(\d+):(\d+): (.*)", re.S)


def _lupa(file: Path) -> Any:
    """The Lua Cartographer links (5.2), else the nearest lupa ships."""
    import importlib

    for name in ("lupa.lua52", "lupa.lua53", "lupa.lua54", "lupa"):
        try:
            return importlib.import_module(name)
        except ImportError:
            continue
    raise CartographerConfigError(
        "reading Cartographer's .lua configuration needs the Lua runtime lupa: "
        "pip install 'btnav[cartographer]'",
        file=file,
    )


class LuaRun:
    """One sandboxed Lua state running one configuration and the files it includes."""

    def __init__(self, file: Path, dirs: list[Path]) -> None:
        self.lupa = _lupa(file)
        self.dirs = dirs
        self.files: list[Path] = [file]
        self.texts: list[str] = [_read(file, None, None)]
        self.included_by: dict[Path, tuple[Path, int]] = {}
        lua = self.lupa.LuaRuntime(
            register_eval=False, register_builtins=False, unpack_returned_tuples=True,
            max_memory=MAX_MEMORY,
        )  # fmt: skip
        forbidden = lua.table_from({n: True for n in FORBIDDEN})
        self._run, self._aliases = lua.eval(_BOOT)(self._include, forbidden, MAX_INSTRUCTIONS)
        self.aliases: dict[str, Key] = {}

    def _include(self, name: Any, src: str, line: int) -> tuple[str, str]:
        """`include "x.lua"`: the first folder that has it, as Cartographer's FileResolver."""
        m = re.match(r"btnav#(\d+)", src)
        by, at = (self.files[int(m.group(1))] if m else None), line
        if not isinstance(name, str) or not name:
            raise CartographerConfigError("include takes a file name", file=by, line=at)
        found = next((d / name for d in self.dirs if (d / name).is_file()), None)
        if found is None:
            loaded = {f.name for f in self.files}
            names = sorted({p.name for d in self.dirs for p in d.glob("*.lua")} - loaded)
            where = ", ".join(str(d) for d in self.dirs)
            raise CartographerConfigError(
                f'include "{name}": no such file in {where}', file=by, line=at,
                suggestion=best_match(name, names),
            )  # fmt: skip
        found = found.resolve()
        if found in self.included_by or found == self.files[0].resolve():
            first = self.included_by.get(found)
            before = f" (first by {first[0]}:{first[1]})" if first else ""
            raise CartographerConfigError(
                f'include "{name}": {found} is already included{before}; Cartographer refuses '
                "to include a file twice", file=by, line=at,
            )  # fmt: skip
        self.included_by[found] = (by or self.files[0], at)
        self.files.append(found)
        self.texts.append(_read(found, by, at))
        return self.texts[-1], f"=btnav#{len(self.files) - 1}"

    def options(self) -> Any:
        """Run the file; the table it returns, as Python, and the globals naming its parts."""
        try:
            result = self._run(self.texts[0], "=btnav#0")
            if self.lupa.lua_type(result) != "table":
                raise CartographerConfigError(
                    "returns no table: a Cartographer configuration ends with `return options`",
                    file=self.files[0],
                )
            self.aliases = {
                name: tuple(p for p in path.split("\1") if p)
                for name, path in self._aliases(result).items()
            }
            return _to_python(result, self.lupa.lua_type, (), self.files[0], [100_000])
        except self.lupa.LuaMemoryError:
            raise CartographerConfigError(
                f"uses more than {MAX_MEMORY >> 20} MB of memory", file=self.files[0]
            ) from None
        except self.lupa.LuaError as err:
            text = str(err).split("\nstack traceback:", 1)[0]
            if m := _CHUNK.match(text):
                file, line, text = self.files[int(m.group(1))], int(m.group(2)), m.group(3)
                raise CartographerConfigError(text, file=file, line=line) from None
            raise CartographerConfigError(text, file=self.files[0]) from None


def _read(file: Path, by: Path | None, line: int | None) -> str:
    try:
        return file.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as err:
        raise CartographerConfigError(f"cannot read {file}: {err}", file=by, line=line) from None


def _to_python(
    value: Any, lua_type: Callable[[Any], str | None], path: Key, file: Path, budget: list[int]
) -> Any:
    """A Lua value as Python: tables with keys 1..n become lists, other tables dicts.

    `budget` counts values down: a table that holds itself (or shares one table many
    times over) would otherwise unfold without end."""
    budget[0] -= 1
    kind = lua_type(value)
    if kind is None:
        return value
    if kind != "table":
        raise CartographerConfigError(f"is a {kind}: a configuration holds data", file=file, key=spell(path))  # fmt: skip
    if len(path) > 40 or budget[0] < 0:
        raise CartographerConfigError("tables nest too deep (a table inside itself?)", file=file, key=spell(path[:3]))  # fmt: skip
    items = sorted(value.items(), key=lambda kv: (isinstance(kv[0], str), kv[0]))
    keys = [k for k, _ in items]
    if keys and keys == list(range(1, len(keys) + 1)):
        return [_to_python(v, lua_type, (*path, str(k)), file, budget) for k, v in items]
    return {k: _to_python(v, lua_type, (*path, str(k)), file, budget) for k, v in items}

"""A package's public names, each imported from its module on first use (PEP 562).

A package whose `__init__` imported every module would make a light import (the pytest
plugin, a Ray worker unpickling a batch job) pay for the whole navigation stack. Such a
package lists its names and their modules, and sets
`__getattr__ = lazy_names(__name__, {"Name": "module", ...})`.
"""

from __future__ import annotations

import sys
from collections.abc import Callable, Mapping
from importlib import import_module
from typing import Any


def lazy_names(package: str, names: Mapping[str, str]) -> Callable[[str], Any]:
    """The module `__getattr__` for `package`: `names[name]` is the submodule holding it;
    the value is kept in the package's namespace once imported."""

    def __getattr__(name: str) -> Any:
        module = names.get(name)
        if module is None:
            raise AttributeError(f"module '{package}' has no attribute {name!r}")
        value = getattr(import_module(f".{module}", package), name)
        setattr(sys.modules[package], name, value)
        return value

    return __getattr__

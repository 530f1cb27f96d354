"""Resolving the sections a `*_plugins` list names to a plugin class, or "not implemented yet".

The section's `plugin:` type is looked up in btnav's registry; a registered
plugin validates the rest of the section with its own `Params` model. A Nav2
type btnav knows but has no plugin for is accepted and its keys are listed as
ignored. An old type name Nav2 can no longer load (`nav2_recoveries/Spin`) is an
error naming the new one; any other type is an error naming the closest known type,
as is a listed name without a section (unless Nav2 supplies the type by default). A
section whose keys are another plugin's (`plugin:` switched to DWB over MPPI's keys)
is one line that says so and names the fix, not a list of every key the new plugin
lacks. Otherwise a key the plugin does not read is skipped, as Nav2 skips it (one
warning), unless it is a near miss of one of its keys.
"""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from typing import Any

import pydantic

from .. import plugins as registry
from ..core.errors import ParamsError
from ..core.resources import bundled_dir
from ..core.suggest import best_match
from ..core.validation import field_names
from ..core.yaml_io import YamlMap, YamlSeq
from .ignored import entry, ignored_keys
from .legacy_keys import legacy_plugin_type, plugin_scope
from .nav2_known import class_name, known_plugin_type, known_plugin_types
from .paramsfile import IgnoredEntry, PluginSection, SkippedKey
from .schema import ParamsModel, validate_section
from .servers import PluginList
from .tree import line_of


class NoParams(ParamsModel):
    """The schema of a plugin class without a `Params` model: it takes no keys."""


#: A section with at least this many unknown keys, most of them another plugin's, was
#: written for that plugin; fewer unknown keys are typos, reported one by one.
MIN_FOREIGN_KEYS = 3
#: How many of the other plugin's keys the message names before "... N more".
SHOWN_FOREIGN_KEYS = 3
#: Bundled params files holding a plugin's documented section: (short name, file).
EXAMPLE_SECTIONS: dict[str, tuple[str, str]] = {
    "nav2_mppi_controller/MPPIController": ("MPPI's", "nav2_params.yaml"),
    "dwb_core/DWBLocalPlanner": ("DWB's", "nav2_params_dwb.yaml"),
    "nav2_regulated_pure_pursuit_controller/RegulatedPurePursuitController": (
        "Regulated Pure Pursuit's",
        "nav2_params_rpp.yaml",
    ),
}


def _list_line(doc: Mapping[str, Any], plist: PluginList, name: str) -> int | None:
    names = doc.get(plist.key)
    if isinstance(names, YamlSeq) and name in names:
        return names.line_of(names.index(name))
    return line_of(doc, plist.key) if plist.key in doc else getattr(doc, "line", None)


def resolve_plugin(
    plist: PluginList,
    name: str,
    doc: Mapping[str, Any],
    defaults_apply: bool,
    path: Sequence[str],
    file: str | None,
    skipped: list[SkippedKey] | None = None,
) -> tuple[PluginSection, list[IgnoredEntry]]:
    """The plugin section `name` of a server whose (expanded) parameters are `doc`; the
    keys Nav2 would skip go to `skipped` (None: they are errors, as before)."""
    key_path = [*path, name]
    section = doc.get(name)
    if section is not None and not isinstance(section, Mapping):
        raise ParamsError(
            f"'{name}' is listed in {plist.key}, so it must be a section with 'plugin:', "
            "not a single value",
            file=file,
            line=line_of(doc, name),
            key=key_path,
        )
    type_name = section.get("plugin") if section is not None else None
    defaulted = False
    if type_name is None:
        default = plist.default_types.get(name) if defaults_apply else None
        if default is None:
            if section is None:
                sections = [str(k) for k, v in doc.items() if isinstance(v, Mapping)]
                raise ParamsError(
                    f"'{name}' is listed in {plist.key} but there is no section '{name}:' "
                    "giving its plugin type",
                    file=file,
                    line=_list_line(doc, plist, name),
                    key=[*path, plist.key],
                    suggestion=best_match(name, sections),
                )
            raise ParamsError(
                f"section '{name}' has no 'plugin:' key naming its {plist.kind.replace('_', ' ')} type",
                file=file,
                line=line_of(doc, name),
                key=key_path,
            )
        type_name, defaulted = default, True
    if not isinstance(type_name, str) or not type_name.strip():
        raise ParamsError(
            f"'plugin' must name a {plist.kind.replace('_', ' ')} type, got {type_name!r}",
            file=file,
            line=line_of(section, "plugin"),
            key=[*key_path, "plugin"],
        )
    body = YamlMap(file=file, line=getattr(section, "line", None))
    for key, value in (section or {}).items():
        if key != "plugin":
            body[key] = value
            body.key_lines[key] = line_of(section, key)  # type: ignore[assignment]
    line = line_of(doc, name) if section is not None else _list_line(doc, plist, name)
    plugin_line = line_of(section, "plugin") if section is not None else line
    renamed = legacy_plugin_type(type_name)
    if renamed is not None:
        raise ParamsError(
            renamed.message(type_name),
            file=file,
            line=plugin_line,
            key=[*key_path, "plugin"],
        )
    cls = _registered(plist, type_name)
    if cls is not None:
        model = getattr(cls, "Params", None)
        if not (isinstance(model, type) and issubclass(model, pydantic.BaseModel)):
            model = NoParams
        try:
            params = validate_section(model, body, key_prefix=key_path, file=file)
        except ParamsError:
            # Another plugin's section is one mistake, said once; else Nav2's way per key.
            foreign = _foreign_section(plist, cls, model, body)
            if foreign is not None:
                raise _foreign_error(type_name, cls, *foreign, file, line, key_path) from None
            if skipped is None:
                raise
            params = validate_section(
                model,
                body,
                key_prefix=key_path,
                file=file,
                skipped=skipped,
                scope=plugin_scope(plist.kind, type_name),
            )
        found = PluginSection(
            name, plist.kind, type_name, cls, params, ".".join(key_path), line, plist.key, defaulted
        )
        return found, ignored_keys(params, body, list(key_path), file)
    if known_plugin_type(plist.kind, type_name) is None:
        raise _unknown_type(plist, type_name, file, plugin_line, [*key_path, "plugin"])
    found = PluginSection(
        name, plist.kind, type_name, None, None, ".".join(key_path), line, plist.key, defaulted
    )
    ignored = []
    if body:
        why = f"{class_name(type_name)} is not implemented yet, so its keys are not read"
        ignored.append(entry(list(key_path), line, why, file, body))
    return found, ignored


def _registered(plist: PluginList, type_name: str) -> type | None:
    """The registered class for `type_name`, or None (a kind btnav does not implement)."""
    if not plist.implemented:
        return None
    registry.load_entry_points()
    if registry.is_registered(plist.kind, type_name):
        return registry.lookup(plist.kind, type_name)  # type: ignore[no-any-return]
    return None


def _unknown_type(
    plist: PluginList, type_name: str, file: str | None, line: int | None, key: list[str]
) -> ParamsError:
    nav2 = list(known_plugin_types(plist.kind))
    registered = registry.names(plist.kind, aliases=True) if plist.implemented else []
    what = plist.kind.replace("_", " ")
    message = f"unknown {what} plugin '{type_name}'"
    if nav2:
        message += f"; Nav2's are {', '.join(class_name(t) for t in nav2)}"
    if registered:
        message += f"; registered in btnav: {', '.join(registered)}"
    return ParamsError(
        message, file=file, line=line, key=key, suggestion=best_match(type_name, nav2 + registered)
    )


def _unknown_keys(model: type[pydantic.BaseModel], body: Mapping[str, Any]) -> list[str] | None:
    """The section's top-level keys `model` refuses as unknown; None if it cannot tell
    (its own checks stopped before looking at the keys one by one)."""
    try:
        model.model_validate(body)
    except pydantic.ValidationError as exc:
        errors = exc.errors(include_url=False)
        if any(not e["loc"] for e in errors):
            return None
        refused = {
            str(e["loc"][0])
            for e in errors
            if e["type"] == "extra_forbidden" and len(e["loc"]) == 1
        }
        return [str(k) for k in body if str(k) in refused]
    except Exception:  # a third-party model that fails its own way: no opinion
        return None
    return []


def _foreign_section(
    plist: PluginList, cls: type, model: type[pydantic.BaseModel], body: Mapping[str, Any]
) -> tuple[str, list[str]] | None:
    """(other plugin, its keys) when most keys `model` refuses are valid keys of another
    registered plugin of the same kind: the section was written for that plugin."""
    unknown = _unknown_keys(model, body)
    if unknown is None:  # its own checks failed first: judge the keys by its field names
        known = set(field_names(model))
        unknown = [str(k) for k in body if str(k) not in known]
    if len(unknown) < MIN_FOREIGN_KEYS:
        return None
    best: tuple[str, list[str]] | None = None
    for name in registry.names(plist.kind):
        other = registry.lookup(plist.kind, name)
        other_model = getattr(other, "Params", None)
        if other is cls or not (
            isinstance(other_model, type) and issubclass(other_model, pydantic.BaseModel)
        ):
            continue
        refused = _unknown_keys(other_model, body)
        if refused is None or 4 * len(refused) > len(body):
            continue  # the other plugin would refuse much of the section too
        theirs = [k for k in unknown if k not in refused]
        if 2 * len(theirs) > len(unknown) and (best is None or len(theirs) > len(best[1])):
            best = (name, theirs)
    return best


def _foreign_error(
    type_name: str,
    cls: type,
    other: str,
    keys: list[str],
    file: str | None,
    line: int | None,
    key_path: list[str],
) -> ParamsError:
    """One line: whose keys these are, which plugin the section names, and the two fixes."""
    spelling = "::" if "::" in type_name else "/"
    other_name = other.replace("/", spelling)
    shown = ", ".join(keys[:SHOWN_FOREIGN_KEYS])
    if len(keys) > SHOWN_FOREIGN_KEYS:
        shown += f", ... {len(keys) - SHOWN_FOREIGN_KEYS} more"
    primary = str(getattr(cls, "plugin_name", registry.canonical(type_name)))
    example = EXAMPLE_SECTIONS.get(primary)
    if example is not None:
        whose, example_file = example
        fix = f"replace the section with {whose} ({_shown_path(example_file)} has one)"
    else:
        fix = f"replace the section with {class_name(type_name)}'s keys"
    return ParamsError(
        f"this section holds {other_name}'s keys ({shown}) but its plugin is {type_name}: "
        f"{fix} or set plugin back",
        file=file,
        line=line,
        key=key_path,
    )


def _shown_path(name: str) -> str:
    """A bundled params file as a user can type it from here: relative when it is below."""
    path = bundled_dir("params") / name
    try:
        rel = os.path.relpath(path)
    except ValueError:  # another drive (Windows)
        return str(path)
    return rel if not rel.startswith("..") else str(path)

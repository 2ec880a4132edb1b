"""The registry of failure modes: what a scenario may name in ``[failure.policy]`` and ``[failure.<mode>]``.

A mode registers itself where it is defined (the built-in modes at the end of their modules, a user's mode
in the user's code) with `register_mode`; the scenario validation (`floebreak.config.scenario`), the profiles
(`floebreak.config.profiles.build_model`) and `floebreak.api.build_model_for` read it, so adding a mode
touches no
other file. A registration holds:

- the mode class (a frozen dataclass with ``name`` and ``evaluate``, `failure.base.FailureMode`);
- ``settings``: the frozen dataclass of its settings, or None. Its fields are the keys of the scenario table
  ``[failure.<name>]`` (validated with the fields' types; a field's docstring, the string literal right
  below it, is its description in ``floebreak schema``), so a new setting is one new field with its default;
- ``material``: settings fields read from the scenario's ``[ice]`` section (same key), not from the table;
- ``thesis``: the settings of the ``thesis`` profile (thesis-literal values, each citing its erratum);
- ``create``: how the mode is built from the settings of every registered mode, by mode name (default:
  ``mode(settings[name])``, or ``mode()`` without settings); a mode that shares another's settings (local
  cracking uses bending's) says so here.

Where modes come from — resolved by the registry itself, so no import line anywhere is needed:

- the built-in modes: the modules of `BUILTIN_MODULES`, imported on the registry's first read;
- installed packages: the entry points of the group ``floebreak.failure_modes`` (`ENTRY_POINT_GROUP`), also
  on the first read; each names a module (``my_mode = "my_pkg.my_mode"``, which calls `register_mode` when
  imported) or a mode class (``halving = "my_pkg.modes:Halving"``, registered with the dataclass type of its
  ``settings`` field, if any, as its settings);
- a scenario's ``[failure] plugins = ["my_pkg.my_mode"]``: modules on the path, resolved by
  `resolve_plugins` whenever a scenario is read (`floebreak.config.scenario.Scenario.from_dict`): in the
  parent
  and in every study worker (pool or Dask), which receive the scenario as a dict and read it there.

A module is resolved once per process (again only after its modes were unregistered). A module that cannot
be imported, registers no mode, or takes a name already registered is an InputError naming the key
(``failure.plugins``, or the entry point) and the module; what it registered before failing is removed.

The registry is the package's one piece of module state: it is the extension point, filled on first use
(like an entry-point table), read-only for the engine, and a test or session removes what it added with
`unregister_mode` or the `registered_mode` context manager.
"""

from __future__ import annotations

import dataclasses
import importlib
import importlib.metadata
import sys
import typing
from collections.abc import Callable, Iterable, Iterator, Mapping
from contextlib import contextmanager
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any

from floebreak.errors import InputError

# keys of [failure] that are not modes (the dispatch's own); no mode may take these names
DISPATCH_KEYS = ("policy", "shoulder_region_start", "flip_uncracked_at_shoulder", "plugins")
ENTRY_POINT_GROUP = "floebreak.failure_modes"
# the built-in modes' modules, in their registration order (resolved like plugins on the first read)
BUILTIN_MODULES = (
    "floebreak.failure.bending",
    "floebreak.failure.cracking",
    "floebreak.failure.none",
    "floebreak.failure.rotation",
    "floebreak.failure.local_cracking",
)


@dataclass(frozen=True, eq=False)
class ModeSpec:
    """One registered failure mode (see the module docstring)."""

    name: str
    mode: type
    settings: type | None
    material: tuple[str, ...]
    thesis: Mapping[str, Any]
    create: Callable[[Mapping[str, Any]], Any]

    def setting_names(self) -> tuple[str, ...]:
        """The fields of the settings dataclass (empty without settings)."""
        return tuple(f.name for f in dataclasses.fields(self.settings)) if self.settings else ()

    def table_keys(self) -> tuple[str, ...]:
        """The keys of the scenario table ``[failure.<name>]``: the settings minus the [ice] material."""
        return tuple(k for k in self.setting_names() if k not in self.material)

    def make_settings(self, values: Mapping[str, Any]) -> Any:
        """The settings dataclass from `values` (an unknown key: InputError ``failure.<name>.<key>``)."""
        if self.settings is None:
            if values:
                raise InputError(f"failure.{self.name}", "this mode has no settings", value=dict(values))
            return None
        known = self.setting_names()
        for key in values:
            if key not in known:
                raise InputError(f"failure.{self.name}.{key}", "unknown key", allowed=", ".join(known))
        return self.settings(**values)


_MODES: dict[str, ModeSpec] = {}
# resolved modules and entry points → the modes each registered; whether the built-ins and entry points are
_RESOLVED: dict[str, tuple[str, ...]] = {}
_DISCOVERED: list[bool] = []


def register_mode(
    mode: type,
    *,
    settings: type | None = None,
    material: tuple[str, ...] = (),
    thesis: Mapping[str, Any] | None = None,
    create: Callable[[Mapping[str, Any]], Any] | None = None,
) -> ModeSpec:
    """Register `mode` under ``mode.name`` (a new name; see the module docstring for the arguments)."""
    name = getattr(mode, "name", None)
    if not isinstance(name, str) or not name.isidentifier() or not callable(getattr(mode, "evaluate", None)):
        raise TypeError(f"{mode!r} is not a failure mode: it needs a class attribute `name` and `evaluate`")
    if name in _MODES or name in DISPATCH_KEYS:
        raise ValueError(f"failure mode name {name!r} is taken (unregister_mode({name!r}) first)")
    if settings is not None and not dataclasses.is_dataclass(settings):
        raise TypeError(f"settings of {name!r} must be a dataclass, got {settings!r}")
    thesis = dict(thesis or {})
    fields = {f.name for f in dataclasses.fields(settings)} if settings is not None else set()
    for item in dataclasses.fields(settings) if settings is not None else ():
        if item.default is dataclasses.MISSING and item.default_factory is dataclasses.MISSING:
            raise TypeError(f"setting {item.name!r} of {name!r} needs a default (scenarios may omit it)")
    for key in (*material, *thesis):
        if key not in fields:
            raise ValueError(f"{key!r} (material or thesis value of {name!r}) is not a field of its settings")
    if create is None:
        create = (lambda s: mode(s[name])) if settings is not None else (lambda s: mode())
    spec = ModeSpec(name, mode, settings, tuple(material), MappingProxyType(thesis), create)
    _MODES[name] = spec
    return spec


def unregister_mode(name: str) -> None:
    """Remove a registered mode (a user's; the engine never does)."""
    get_mode(name)
    del _MODES[name]
    for source, names in list(_RESOLVED.items()):
        if name in names:
            del _RESOLVED[source]  # resolved again (re-imported) if a scenario names it again


@contextmanager
def registered_mode(mode: type, **registration: Any) -> Iterator[ModeSpec]:
    """`register_mode` for the duration of a ``with`` block (tests, notebooks)."""
    spec = register_mode(mode, **registration)
    try:
        yield spec
    finally:
        unregister_mode(spec.name)


def mode_names() -> tuple[str, ...]:
    """The registered modes' names, in registration order (the built-ins, then the installed packages' and
    the plugins' modes, then those registered in code)."""
    _discover()
    return tuple(_MODES)


def get_mode(name: str) -> ModeSpec:
    """The registration of mode `name` (InputError listing the registered names if there is none)."""
    _discover()
    spec = _MODES.get(name)
    if spec is None:
        raise InputError(f"failure.{name}", "unknown failure mode", allowed=", ".join(_MODES))
    return spec


def resolve_plugins(modules: Iterable[str], key: str = "failure.plugins") -> tuple[str, ...]:
    """Import each plugin module (a dotted name on the path) so that its modes are registered; the names of
    the modes they registered. Resolves the built-ins and entry points first; see the module docstring for
    the errors (InputError naming `key` and the module)."""
    _discover()
    names: list[str] = []
    for module in modules:
        if not isinstance(module, str) or not all(part.isidentifier() for part in module.split(".")):
            raise InputError(
                key, f"{module!r} is not a module name", allowed="dotted module names on the path"
            )
        names += _resolve(module, key, lambda module=module: _import(module))
    return tuple(names)


def _discover() -> None:
    """Resolve the built-in modules and the installed packages' entry points, once per process."""
    if _DISCOVERED:
        return
    for module in BUILTIN_MODULES:
        _resolve(module, "failure", lambda module=module: _import(module))
    for point in importlib.metadata.entry_points(group=ENTRY_POINT_GROUP):
        key = f"entry point {point.name!r} of {ENTRY_POINT_GROUP}"
        _resolve(point.value, key, lambda point=point: _register_object(point.load()))
    _DISCOVERED.append(True)


def _import(module: str) -> None:
    """Import `module`; re-run it if it was imported before but its modes were unregistered since."""
    loaded = sys.modules.get(module)
    if loaded is not None and not any(spec.mode.__module__ == module for spec in _MODES.values()):
        importlib.reload(loaded)
    else:
        importlib.import_module(module)


def _register_object(target: Any) -> None:
    """An entry point's object: a module (imported, it registered its modes) or a mode class to register."""
    if isinstance(target, type):
        hints = typing.get_type_hints(target) if dataclasses.is_dataclass(target) else {}
        settings = hints.get("settings")
        register_mode(target, settings=settings if dataclasses.is_dataclass(settings) else None)


def _resolve(source: str, key: str, load: Callable[[], None]) -> tuple[str, ...]:
    """Run `load` for `source` (a module or entry point) unless resolved before; record the modes it
    registered (or, for a module imported before, the registered modes defined in it)."""
    if source in _RESOLVED:
        return _RESOLVED[source]
    before = set(_MODES)
    try:
        load()
    except Exception as error:
        for name in set(_MODES) - before:  # nothing half-registered stays
            del _MODES[name]
        raise InputError(key, f"plugin {source!r} failed to load: {type(error).__name__}: {error}") from None
    module = source.partition(":")[0]
    added = tuple(name for name in _MODES if name not in before) or tuple(
        name for name, spec in _MODES.items() if spec.mode.__module__ == module
    )
    if not added:
        raise InputError(
            key,
            f"plugin {source!r} registers no failure mode",
            allowed="a module that calls floebreak.register_mode, or a failure mode class",
        )
    _RESOLVED[source] = added
    return added

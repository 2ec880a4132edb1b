"""The registry of failure modes: what a scenario may name in ``[failure.policy]`` and ``[failure.<mode>]``.

A mode registers itself where it is defined (the built-in modes at the end of their modules, a user's mode
in the user's code) with `register_mode`; the scenario validation (`floebreak.scenario`), the profiles
(`floebreak.profiles.build_model`) and `floebreak.api.build_model_for` read it, so adding a mode touches no
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

The registry is the package's one piece of module state: it is the extension point, filled at import (like
an entry-point table), read-only for the engine, and a test or session removes what it added with
`unregister_mode` or the `registered_mode` context manager.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Iterator, Mapping
from contextlib import contextmanager
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any

from floebreak.errors import InputError

# keys of [failure] that are not modes (the dispatch's own); no mode may take these names
DISPATCH_KEYS = ("policy", "shoulder_region_start", "flip_uncracked_at_shoulder")


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


@contextmanager
def registered_mode(mode: type, **registration: Any) -> Iterator[ModeSpec]:
    """`register_mode` for the duration of a ``with`` block (tests, notebooks)."""
    spec = register_mode(mode, **registration)
    try:
        yield spec
    finally:
        unregister_mode(spec.name)


def mode_names() -> tuple[str, ...]:
    """The registered modes' names, in registration order."""
    return tuple(_MODES)


def get_mode(name: str) -> ModeSpec:
    """The registration of mode `name` (InputError listing the registered names if there is none)."""
    spec = _MODES.get(name)
    if spec is None:
        raise InputError(f"failure.{name}", "unknown failure mode", allowed=", ".join(_MODES))
    return spec

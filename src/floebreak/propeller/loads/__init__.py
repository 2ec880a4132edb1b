"""Propeller load models: what one cusp does to a blade. A model is one object behind `LoadModel`; the
built-in models (`fem`, `milling`) are listed in `BUILTIN`, an installed package adds one through the entry
point group ``floebreak.load_models`` (``name = "my_pkg.loads:MODEL"``, an object or a class to
instantiate). Every place that picks a load model by name (the propeller analysis, the command line, the
voyage tables) looks it up here (docs/architecture.md, "Extension points")."""

from __future__ import annotations

import functools
import importlib
from typing import Any, Protocol

import numpy as np

from floebreak.errors import InputError
from floebreak.propeller.spec import PropellerSpec

ENTRY_POINT_GROUP = "floebreak.load_models"
# name → "module:object" of the built-in models (a list here, not entry points: a source checkout on the path
# has no installed entry points)
BUILTIN = {
    "milling": "floebreak.propeller.loads.milling:MODEL",
    "fem": "floebreak.propeller.loads.fem:MODEL",
}


class LoadModel(Protocol):
    """One per-cusp load model of the propeller analysis (`floebreak.propeller.pipeline`)."""

    name: str
    label: str  # a few words for titles
    description: str  # the summary's ``load_model.description``
    rpm_text: str  # how its loads depend on the propeller's speed (voyage tables)
    needs_tables: bool  # it interpolates FEM tables (`FemTable`s, given or shipped)
    places_on_blade: bool  # it uses the transport's engaged interval on the blade

    def pitches(self, propeller: PropellerSpec, tables: dict) -> tuple[float, ...]:
        """The pitches [%] it gives loads at (those of `tables` for a table model)."""
        ...

    def cusp_loads(
        self, columns: dict, tables: dict, options: dict, propeller: PropellerSpec, speed_m_s, engaged=None
    ) -> dict[str, np.ndarray]:
        """Per cusp (`cusp_columns`, transit order): `propeller.cusps.cusp_geometry`'s columns and, per pitch
        label, ``force_n_<pitch>`` [N], ``torque_nm_<pitch>`` [N·m, signed as the FEM tables] and
        ``beyond_table_<pitch>``. `engaged`: (r_in, r_out) per cusp on the blade, NaN: tip placement."""
        ...


def _load(target: str) -> Any:
    module, _, attribute = target.partition(":")
    value = getattr(importlib.import_module(module), attribute)
    return value() if isinstance(value, type) else value


@functools.cache
def _entry_points() -> dict[str, str]:
    from importlib.metadata import entry_points

    return {point.name: point.value for point in entry_points(group=ENTRY_POINT_GROUP)}


def load_model_names() -> tuple[str, ...]:
    """The built-in models, then those of installed packages."""
    return (*BUILTIN, *(name for name in _entry_points() if name not in BUILTIN))


@functools.cache
def get_load_model(name: str, key: str = "load_model") -> LoadModel:
    """The load model `name`; an unknown name is an InputError on `key` listing the known ones."""
    target = BUILTIN.get(name) or _entry_points().get(name)
    if target is None:
        raise InputError(key, f"unknown value {name!r}", value=name, allowed=", ".join(load_model_names()))
    model = _load(target)
    for attribute in (
        "name",
        "label",
        "description",
        "rpm_text",
        "needs_tables",
        "places_on_blade",
        "pitches",
        "cusp_loads",
    ):
        if not hasattr(model, attribute):
            raise InputError(key, f"load model {name!r} ({target}) has no {attribute!r}", value=name)
    return model

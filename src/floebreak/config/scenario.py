"""Scenario files: one TOML file describes a run (field, ice, ship, failure switches, profile, seed).

Validated with pydantic v2; every section forbids unknown keys, numbers are strict (a string is not a number),
and every validation error becomes an `InputError` naming the dotted key (``ice.thickness_m``) and the allowed
values or range. Command-line overrides ``--set ice.thickness_m=0.8`` parse the value with `tomllib`
(``0.8`` → float, ``"x"``/``x`` → string, ``[0.75, 1.25]`` → list) and are validated like the file. An
override that names a field source (``--set 'field.file="field.parquet"'``) replaces the file's source and
the keys only that source takes, so a run directory's ``scenario.resolved.toml`` reruns on its own
``field.parquet`` (relative paths are relative to the scenario file, as in the file itself); likewise
``ice.thickness_m``/``thickness_range_m`` and ``ship.hull``/``file``.

`Scenario.resolved()` fills in every profile-dependent default (field-generation switches, the observation's
mean thickness, the hull), so ``scenario.resolved.toml`` in a run directory reproduces the run on its own.
Physical parameters cite thesis / physics-notes sections in their descriptions; units are in the key names.
"""

from __future__ import annotations

import ast
import dataclasses
import datetime as _dt
import functools
import hashlib
import inspect
import itertools
import json
import re
import textwrap
import tomllib
import typing
import warnings
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Annotated, Any, Literal

import tomli_w
from pydantic import (
    AllowInfNan,
    BaseModel,
    ConfigDict,
    Field,
    Strict,
    ValidationError,
    ValidationInfo,
    create_model,
    field_validator,
    model_validator,
)
from pydantic_core import PydanticCustomError

from floebreak import constants as c
from floebreak.engine.motion import BUILTIN as BUILTIN_ICE_MOTIONS
from floebreak.engine.motion import ice_motion_names
from floebreak.errors import InputError, field_bounds
from floebreak.io.toml_text import loads_toml
from floebreak.ship.agulhas_ii import AGULHAS_II
from floebreak.ship.hulls import HULLS, hull_parameter_ranges
from floebreak.ship.propulsion import SURGE_ADDED_MASS, Propulsion

REFERENCE_OBSERVATION = "2019-12-18T20:20"  # thesis §5.3 reference scenario (Table 1, first row)

# the reference scenario (thesis §5.3: obs 2019-12-18T20:20 on the thesis' field, h = 1 m, Agulhas II);
# examples/reference.toml holds the same text
REFERENCE_TOML = """\
profile = "default"            # or "thesis"
seed = 1

[field]
observation = "2019-12-18T20:20"
# or: file = "field.parquet", or: floes = [{x_m = 20.0, y_m = 0.0, diameter_m = 10.0}]
length_m = 385.0               # the thesis' field (inferred, docs/validation.md)
width_m = 100.0
generator = "circles"          # or "voronoi"

[ice]
thickness_m = 1.0              # or: thickness_range_m = [0.75, 1.25]
fracture_toughness_pa_sqrt_m = 145.7e3

[ship]
hull = "agulhas_ii"            # or "polarstern", or: file = "bow.csv"
step_m = 0.25

[failure.cracking]
criterion = "tensile_stress"   # point_load | line_load | tensile_stress | flexural_stress
size_effect_law = "BZ"         # BZ | BZ1 | BZ2
"""

# strict scalars: TOML gives real types, so "1.0" (a string) is a type error, not a number; TOML's inf and
# nan are refused (every number of a scenario is finite)
Float = Annotated[float, Strict(), AllowInfNan(False)]
Int = Annotated[int, Strict()]
Bool = Annotated[bool, Strict()]

# Physical ranges of the scenario's numbers, all in this one place (the physics trusts validated input).
# They are wide — what the models can be asked, not what is typical — and each excludes values that only
# a typo gives and that would exhaust the machine or break the geometry:
POSITION_LIMIT_M = 1.0e6  # |x|, |y| of floes and the bow ≤ 1 000 km
THICKNESS_M = (0.01, 10.0)  # level sea ice: from nilas (centimetres) to multi-year ice (metres)
DIAMETER_M = (0.01, 10_000.0)  # floe diameters
FIELD_LENGTH_M = (1.0, 1.0e6)  # generated field length (the floe count is bounded by simulation.max_pieces)
FIELD_WIDTH_M = (1.0, 1.0e5)
STEP_M = (1.0e-3, 10.0)  # bow advance per step: below 1 mm a transit takes millions of steps
SPEED_M_S = c.SHIP_SPEED_RANGE_M_S  # ship speed
# p_h sets how many uniforms are drawn per floe (random numbers = floes × p_h)
THICKNESS_SUMMANDS = (1, 10_000)
THRUST_N = 1.0e8  # |thrust|: 100 MN, ≈ 10 × the bollard pull of the most powerful icebreakers
PROPELLER_COUNT = c.PROPELLER_COUNT_RANGE
WALL_S_MAX = 30 * 86_400.0  # simulation.max_wall_s: a month
SEED_MAX = 2**63 - 1  # seeds are TOML integers: signed 64 bit (TOML 1.0)
Thickness = Annotated[Float, Field(ge=THICKNESS_M[0], le=THICKNESS_M[1])]


def _cross(key: str, message: str, allowed: str | None = None) -> PydanticCustomError:
    """A cross-field error; `key` (relative to the section) becomes the reported field."""
    return PydanticCustomError("floebreak_cross", message, {"key": key, "allowed": allowed})


class _Section(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True, validate_default=True)


def _resolve_path(value: Path | None, info: ValidationInfo) -> Path | None:
    if value is None:
        return None
    base = (info.context or {}).get("base_dir")
    path = Path(value).expanduser()
    if not path.is_absolute() and base is not None:
        path = Path(base) / path
    return path


class InlineFloe(_Section):
    """A circular floe given in the scenario file (becomes a 64-gon inscribed in the circle)."""

    x_m: Float = Field(
        ge=-POSITION_LIMIT_M,
        le=POSITION_LIMIT_M,
        description="centre x in the field frame [m] (bow stem tip at x = 0 at the start)",
    )
    y_m: Float = Field(
        ge=-POSITION_LIMIT_M, le=POSITION_LIMIT_M, description="centre y in the field frame [m] (to port)"
    )
    diameter_m: Float = Field(ge=DIAMETER_M[0], le=DIAMETER_M[1], description="diameter [m]")
    thickness_m: Float | None = Field(
        None,
        ge=THICKNESS_M[0],
        le=THICKNESS_M[1],
        description="thickness [m]; default: ice.thickness_m (or ice.thickness_range_m)",
    )


class FieldSection(_Section):
    """The floe field: generated from an ice observation (thesis §2.1), read from a file, or given inline.

    Exactly one source: `observation` (thesis Table 1 key), `diameter_classes_m` + `percentages` +
    `concentration` (a user observation), `file` (GeoParquet written by floebreak), or `floes` (inline).
    """

    observation: str | None = Field(
        None, description="thesis Table 1 observation key (`floebreak observations`), e.g. 2019-12-18T20:20"
    )
    concentration: Float | None = Field(
        None,
        gt=0.0,
        le=1.0,
        description="ice concentration, fraction in (0, 1]; overrides the observation's (thesis §2.1)",
    )
    diameter_classes_m: list[Annotated[Float, Field(ge=DIAMETER_M[0], le=DIAMETER_M[1])]] | None = Field(
        None, description="user observation: equivalent-diameter classes [m]"
    )
    percentages: list[Annotated[Float, Field(ge=0.0, le=100.0)]] | None = Field(
        None, description="user observation: share of floes per diameter class [%], summing to 100"
    )
    file: Path | None = Field(None, description="GeoParquet floe field (columns floe_id, thickness_m)")
    floes: list[InlineFloe] | None = Field(None, description="inline circular floes")
    length_m: Float | None = Field(
        None,
        ge=FIELD_LENGTH_M[0],
        le=FIELD_LENGTH_M[1],
        description=f"generated field length along x [m] (default {c.REFERENCE_FIELD_LENGTH_M:g}, the "
        "thesis' field, docs/validation.md)",
    )
    width_m: Float | None = Field(
        None,
        ge=FIELD_WIDTH_M[0],
        le=FIELD_WIDTH_M[1],
        description=f"generated field width along y [m] (default {c.REFERENCE_FIELD_WIDTH_M:g}, the "
        "thesis' field, docs/validation.md)",
    )
    generator: Literal["circles", "voronoi", "sqp"] = Field(
        "circles", description="floe placement: circles (relaxation), voronoi (angular), sqp (thesis)"
    )
    floe_area_factor: Float | None = Field(
        None,
        gt=0.0,
        le=1.0,
        description="mean floe area A = factor · π d² (default 0.25; thesis profile 0.5, erratum 1) [-]",
    )
    clustering: Float = Field(
        0.05, ge=0.0, le=10.0, description="clustering tendency of the circle placement [-]"
    )

    _resolve_file = field_validator("file")(_resolve_path)

    @field_validator("observation")
    @classmethod
    def _known_observation(cls, value: str | None) -> str | None:
        if value is None:
            return None
        from floebreak.ice.observations import thesis_observations

        keys = list(thesis_observations())
        if value not in keys:
            raise PydanticCustomError(
                "unknown_observation",
                "unknown observation {value!r}; allowed: {allowed}",
                {"value": value, "allowed": ", ".join(keys)},
            )
        return value

    @model_validator(mode="after")
    def _one_source(self) -> FieldSection:
        user = self.diameter_classes_m is not None or self.percentages is not None
        sources = [
            name
            for name, given in (
                ("observation", self.observation is not None),
                ("diameter_classes_m", user),
                ("file", self.file is not None),
                ("floes", self.floes is not None),
            )
            if given
        ]
        if len(sources) > 1:
            raise _cross(sources[1], f"give only one field source, got {' and '.join(sources)}")
        if user:
            if self.diameter_classes_m is None or self.percentages is None or self.concentration is None:
                raise _cross(
                    "diameter_classes_m",
                    "a user observation needs concentration, diameter_classes_m and percentages",
                )
            if len(self.diameter_classes_m) != len(self.percentages):
                raise _cross("percentages", "needs one percentage per diameter class")
        generated = not sources or sources[0] in ("observation", "diameter_classes_m")
        if not generated:
            for key in ("length_m", "width_m", "concentration", "floe_area_factor"):
                if getattr(self, key) is not None:
                    raise _cross(key, f"only for generated fields, not with {sources[0]}")
        if self.floes is not None and not self.floes:
            raise _cross("floes", "is empty; give at least one floe")
        return self

    @property
    def source(self) -> Literal["observation", "user_observation", "file", "floes"]:
        if self.file is not None:
            return "file"
        if self.floes is not None:
            return "floes"
        if self.diameter_classes_m is not None:
            return "user_observation"
        return "observation"


class IceSection(_Section):
    """Ice thickness and material (thesis §2.1, §4; physics-notes §0 for values the thesis does not give)."""

    thickness_m: Float | None = Field(
        None,
        ge=THICKNESS_M[0],
        le=THICKNESS_M[1],
        description="thickness of every floe [m]; default: the observation's mean thickness",
    )
    thickness_range_m: tuple[Thickness, Thickness] | None = Field(
        None, description="bounded random thickness [h_min, h_max] [m] (thesis §5.3.3, Bates distribution)"
    )
    thickness_summands: Int | None = Field(
        None,
        ge=THICKNESS_SUMMANDS[0],
        le=THICKNESS_SUMMANDS[1],
        description="p_h of the Bates thickness (default 12; thesis profile 1180, erratum 6) [-], 1 to "
        "10 000: the spread (h_max − h_min)/√(12 p_h) is then ≥ 0.3 % of the range (3 mm for a 1 m range), "
        "below what ice thickness is measured to; for a constant thickness give ice.thickness_m",
    )
    fracture_toughness_pa_sqrt_m: Float = Field(
        c.FRACTURE_TOUGHNESS_PA_SQRT_M,
        ge=1.0e3,
        le=1.0e7,
        description="K_Ic [Pa·√m] (thesis Table 4; sea ice ≈ 50–300 kPa·√m)",
    )
    flexural_strength_pa: Float = Field(
        c.FLEXURAL_STRENGTH_PA,
        ge=1.0e3,
        le=1.0e8,
        description="σ_f [Pa] (physics-notes §0; not given in the thesis; sea ice ≈ 0.3–0.7 MPa)",
    )
    crushing_strength_pa: Float = Field(
        c.CRUSHING_STRENGTH_PA,
        ge=1.0e3,
        le=1.0e8,
        description="σ_c [Pa] (thesis Alg. 3: 1280 kPa; sea ice ≈ 1–10 MPa)",
    )
    contact_coefficient: Float = Field(
        c.CONTACT_COEFFICIENT, gt=0.0, le=10.0, description="k_c (thesis Alg. 3) [-]"
    )
    friction_coefficient: Float = Field(
        c.FRICTION_COEFFICIENT, ge=0.0, le=2.0, description="μ ice–hull (thesis Alg. 3) [-]"
    )
    youngs_modulus_pa: Float = Field(
        c.YOUNGS_MODULUS_PA, ge=1.0e6, le=1.0e11, description="E [Pa] (thesis §4.1.1; sea ice ≈ 1–10 GPa)"
    )
    poisson_ratio: Float = Field(c.POISSON_RATIO, gt=0.0, lt=0.5, description="ν (thesis §4.1.1) [-]")

    @model_validator(mode="after")
    def _thickness(self) -> IceSection:
        if self.thickness_m is not None and self.thickness_range_m is not None:
            raise _cross("thickness_range_m", "give either thickness_m or thickness_range_m, not both")
        if self.thickness_range_m is not None:
            low, high = self.thickness_range_m
            if not 0.0 < low <= high:
                raise _cross("thickness_range_m", f"[{low:g}, {high:g}] m is not 0 < h_min ≤ h_max")
        return self


class PropulsionSection(_Section):
    """The ship's propulsion in ice (docs/model.md, "Ship surge"): with it, the ship's speed follows from
    the ice force; without it, the ship sails at the prescribed ship.speed_m_s (`ship.propulsion`)."""

    model: Literal["bollard_pull", "power", "table"] = Field(
        "bollard_pull",
        description="net thrust T_net(V): bollard_pull (Juva & Riska 2002: T_B·(1 − V/3V_ow − 2V²/3V_ow²)), "
        "power (min(T_B, η_D·P_D/V) less R_ow ∝ V²) or table (speeds_m_s, net_thrust_n)",
    )
    bollard_pull_n: Float | None = Field(
        None, gt=0.0, le=THRUST_N, description="bollard pull T_B [N] (models bollard_pull, power)"
    )
    open_water_speed_m_s: Float | None = Field(
        None,
        gt=0.0,
        le=SPEED_M_S[1],
        description="open-water speed V_ow [m/s], where thrust and open-water resistance balance "
        "(models bollard_pull, power)",
    )
    delivered_power_w: Float | None = Field(
        None, gt=0.0, le=1.0e9, description="delivered power P_D [W] (model power)"
    )
    propulsive_efficiency: Float | None = Field(
        None, gt=0.0, le=1.0, description="quasi-propulsive efficiency η_D [-] (model power)"
    )
    speeds_m_s: list[Annotated[Float, Field(ge=0.0, le=SPEED_M_S[1])]] | None = Field(
        None, description="speeds of the net-thrust table [m/s], rising strictly from 0 (model table)"
    )
    net_thrust_n: list[Annotated[Float, Field(ge=-THRUST_N, le=THRUST_N)]] | None = Field(
        None,
        description="net thrust T_net = T − R_ow at speeds_m_s [N], falling strictly from the bollard pull "
        "(> 0) to ≤ 0 (model table)",
    )
    added_mass_coefficient: Float = Field(
        SURGE_ADDED_MASS,
        ge=0.0,
        le=1.0,
        description="surge added mass / displacement [-] (default 0.05: Söding 1982 via Fossen 2011; "
        "0.05–0.1 for ships)",
    )
    # the displacement last: pydantic reports errors in field order, so a value out of range above is
    # named first, before a missing displacement
    displacement_kg: Float = Field(
        gt=0.0,
        le=1.0e9,
        description="displacement Δ [kg] (Agulhas II: 13 687 t); the effective mass is "
        "Δ·(1 + added_mass_coefficient)",
    )

    @model_validator(mode="after")
    def _complete(self) -> PropulsionSection:
        used = _PROPULSION_KEYS[self.model]
        for name in sorted(set().union(*_PROPULSION_KEYS.values()) - used):
            if getattr(self, name) is not None:
                raise _cross(name, f"not used by model = {self.model!r}", ", ".join(sorted(used)))
        try:
            self.to_propulsion()
        except InputError as error:
            message = str(error).removeprefix(f"{error.field}: ")
            raise _cross(error.field.removeprefix("ship.propulsion."), message, error.allowed) from None
        return self

    def to_propulsion(self) -> Propulsion:
        """The `floebreak.ship.propulsion.Propulsion` of this table (which checks the table's shape)."""
        return Propulsion(
            model=self.model,
            displacement_kg=self.displacement_kg,
            added_mass_coefficient=self.added_mass_coefficient,
            bollard_pull_n=self.bollard_pull_n,
            open_water_speed_m_s=self.open_water_speed_m_s,
            delivered_power_w=self.delivered_power_w,
            propulsive_efficiency=self.propulsive_efficiency,
            speeds_m_s=tuple(self.speeds_m_s or ()),
            net_thrust_n=tuple(self.net_thrust_n or ()),
        )


# the keys each propulsion model takes (the others must be left out)
_PROPULSION_KEYS = {
    "bollard_pull": {"bollard_pull_n", "open_water_speed_m_s"},
    "power": {"bollard_pull_n", "open_water_speed_m_s", "delivered_power_w", "propulsive_efficiency"},
    "table": {"speeds_m_s", "net_thrust_n"},
}


class ShipSection(_Section):
    """The ship: a built-in parametric hull (physics-notes §6.3) or a bow CSV file; the step (thesis §3.2)."""

    hull: str | None = Field(None, description=f"built-in hull: {', '.join(HULLS)} (default agulhas_ii)")
    file: Path | None = Field(None, description="bow CSV file (`Bow.from_csv` formats)")
    hull_parameters: dict[str, Annotated[float, AllowInfNan(False)] | int | str] = Field(
        default_factory=dict,
        description="keyword overrides of the parametric hull (e.g. beam_m [m]); each is range-checked "
        f"(`floebreak.ship.hulls.parametric_bow`: {hull_parameter_ranges()})",
    )
    waterlines: Literal["follow_thickness", "fixed"] | None = Field(
        None,
        description="ice waterlines of a built-in hull: follow the ice thickness (default profile) or fixed "
        "at waterline_ice_thickness_m (thesis profile; thesis §3.1, Table 2)",
    )
    waterline_ice_thickness_m: Float = Field(
        1.0,
        ge=THICKNESS_M[0],
        le=THICKNESS_M[1],
        description="ice thickness the fixed waterlines are built for [m] (thesis §5.3: 1.0 m)",
    )
    step_m: Float = Field(
        0.25, ge=STEP_M[0], le=STEP_M[1], description="bow advance per step [m] (thesis §3.2)"
    )
    x_start_m: Float = Field(
        0.0, ge=-POSITION_LIMIT_M, le=POSITION_LIMIT_M, description="stem tip position at the start [m]"
    )
    x_end_m: Float | None = Field(
        None,
        ge=-POSITION_LIMIT_M,
        le=POSITION_LIMIT_M,
        description="stem tip position at the end [m]; default: the hull has passed the field",
    )
    initial_contact: Literal["shift_field", "shift_floes"] = Field(
        "shift_field", description="how floes touching the bow at the start are moved ahead (thesis §3.2)"
    )
    speed_m_s: Float = Field(
        c.SHIP_SPEED_IN_ICE_M_S,
        gt=SPEED_M_S[0],
        le=SPEED_M_S[1],
        description="ship speed in ice [m/s]: time base of the propeller load rates (with ship.propulsion: "
        "the speed entering the field), not used by the quasi-static breaking (default 3 m/s, thesis §6.3 "
        "Eq. 28); at most 20 m/s ≈ 39 kn, above any ice-going ship's top speed in open water",
    )
    propulsion: PropulsionSection | None = Field(
        None,
        description="propulsion in ice: the ship's speed then follows from the ice force, entering the field "
        "at speed_m_s (docs/model.md, Ship surge); default: the prescribed constant speed_m_s",
    )

    _resolve_file = field_validator("file")(_resolve_path)

    @field_validator("hull")
    @classmethod
    def _known_hull(cls, value: str | None) -> str | None:
        if value is not None and value not in HULLS:
            raise PydanticCustomError(
                "unknown_hull",
                "unknown hull {value!r}; allowed: {allowed}",
                {"value": value, "allowed": ", ".join(HULLS)},
            )
        return value

    @model_validator(mode="after")
    def _one_bow(self) -> ShipSection:
        if self.hull is not None and self.file is not None:
            raise _cross("file", "give either hull or file, not both")
        if self.file is not None and self.hull_parameters:
            raise _cross("hull_parameters", "only for built-in hulls, not with file")
        if self.x_end_m is not None and not self.x_end_m > self.x_start_m:
            raise _cross("x_end_m", f"{self.x_end_m:g} m is not after x_start_m = {self.x_start_m:g} m")
        return self


# The flat [failure] keys of earlier versions and the mode table key each stands for: a scenario
# file and `--set` may still use them; the scenario stores and writes the table form.
FLAT_FAILURE_KEYS: dict[str, tuple[str, str]] = {
    "crack_criterion": ("cracking", "criterion"),
    "size_effect_law": ("cracking", "size_effect_law"),
    "stress_mode": ("cracking", "stress_mode"),
    "next_crack_angle_deg": ("cracking", "next_crack_angle_deg"),
    "wedge_angle_deg": ("bending", "wedge_angle_deg"),
}

PolicyModes = list[str]


class FailureSection(_Section):
    """Failure modes and their dispatch (thesis §3.2, §4; physics-notes §3–4; docs/model.md §10).

    Besides the keys below, one table ``[failure.<mode>]`` per registered failure mode that has settings
    (``floebreak.failure.mode_names()``; e.g. ``[failure.cracking] criterion = "line_load"``), validated
    against the mode's settings dataclass; the flat keys of `FLAT_FAILURE_KEYS` stand for table keys.
    """

    model_config = ConfigDict(extra="allow", frozen=True, validate_default=True)

    plugins: list[str] | None = Field(
        None,
        description="modules on the path that register failure modes when imported (e.g. "
        '["my_pkg.my_mode"]), resolved when the scenario is read, in every study worker too '
        "(floebreak.failure.registry; installed packages use the entry points floebreak.failure_modes)",
    )
    policy: dict[str, PolicyModes | dict[str, PolicyModes]] | None = Field(
        None,
        description="modes tried in order per failure class (unbreakable, bending, cracking), as a list or "
        "per bow region {stem = [...], shoulder = [...]}; classes and regions left out keep the default",
    )
    shoulder_region_start: Float = Field(
        0.5, ge=0.0, le=1.0, description="fraction of stem→shoulder length where the shoulder begins [-]"
    )
    flip_uncracked_at_shoulder: Bool = Field(
        True,
        description="the default policy rotates (flips) a floe in which no crack starts at the shoulder",
    )

    @model_validator(mode="before")
    @classmethod
    def _mode_tables(cls, data: Any) -> Any:
        if not isinstance(data, Mapping) or all(key in cls.model_fields for key in data):
            return data
        own = {key: value for key, value in data.items() if key in cls.model_fields}
        return {**own, **_validated_mode_tables(data, tuple(cls.model_fields))}

    @field_validator("policy")
    @classmethod
    def _known_modes(cls, value: dict | None) -> dict | None:
        return None if value is None else _normalised_policy(value)

    def mode_tables(self) -> dict[str, dict[str, Any]]:
        """The given mode tables, mode name → {setting: value} (flat keys translated)."""
        return {name: dict(table) for name, table in (self.model_extra or {}).items()}


def resolve_scenario_plugins(data: Mapping[str, Any]) -> None:
    """Register the failure modes of a raw scenario's ``[failure] plugins`` (and of the installed packages'
    entry points) before the scenario is validated, which reads the registry: `Scenario.from_dict` calls it,
    so every process that reads a scenario — a study's workers too — resolves them
    (`floebreak.failure.registry.resolve_plugins`; InputError naming ``failure.plugins`` and the module)."""
    from floebreak.failure.registry import resolve_plugins

    failure = data.get("failure")
    plugins = failure.get("plugins") if isinstance(failure, Mapping) else None
    if plugins is not None and not isinstance(plugins, list):
        raise InputError("failure.plugins", "must be a list of module names", value=plugins)
    resolve_plugins(plugins or ())


def _validated_mode_tables(data: Mapping[str, Any], own_keys: tuple[str, ...]) -> dict[str, dict[str, Any]]:
    """The mode tables of a raw [failure] section, with the flat keys moved into them, each validated."""
    from floebreak.failure import get_mode, mode_names

    with_settings = [name for name in mode_names() if get_mode(name).settings is not None]
    tables: dict[str, dict[str, Any]] = {}
    for key, value in data.items():
        if key in own_keys or key in FLAT_FAILURE_KEYS:
            continue
        if key not in with_settings:
            allowed = ", ".join([*own_keys, *with_settings, *FLAT_FAILURE_KEYS])
            raise _cross(
                key, "unknown key (neither a dispatch key nor a failure mode with settings)", allowed
            )
        if not isinstance(value, Mapping):
            raise _cross(key, f"must be a table of {key}'s settings", ", ".join(get_mode(key).table_keys()))
        tables[key] = dict(value)
    origin = _move_flat_keys(data, tables)
    return {mode: _validated_table(get_mode(mode), table, origin) for mode, table in tables.items()}


def _move_flat_keys(data: Mapping[str, Any], tables: dict[str, dict[str, Any]]) -> dict[tuple[str, str], str]:
    """The one reader of the flat [failure] keys of earlier versions (`FLAT_FAILURE_KEYS`): each given is
    moved into its mode's table in `tables`, with a FutureWarning naming the table key (shown to users by
    default, unlike a DeprecationWarning); returns (mode, setting) → the flat key, for error messages."""
    origin: dict[tuple[str, str], str] = {}
    for flat, (mode, setting) in FLAT_FAILURE_KEYS.items():
        if flat in data:
            if setting in tables.get(mode, {}):
                raise _cross(flat, f"give either {flat} or {mode}.{setting}, not both")
            warnings.warn(
                f"failure.{flat} is deprecated: write {setting} = … in the table [failure.{mode}] "
                f"(failure.{mode}.{setting})",
                FutureWarning,
                stacklevel=2,
            )
            tables.setdefault(mode, {})[setting] = data[flat]
            origin[(mode, setting)] = flat
    return origin


def _validated_table(
    spec: Any, table: dict[str, Any], origin: Mapping[tuple[str, str], str]
) -> dict[str, Any]:
    """`table` checked against the mode's settings: the keys and types (a pydantic model built from the
    settings dataclass), then the dataclass's own range checks; errors name the scenario key."""

    def key_of(setting: str) -> str:
        return origin.get((spec.name, setting), f"{spec.name}.{setting}")

    try:
        values = _table_model(spec).model_validate(table).model_dump(exclude_unset=True)
    except ValidationError as error:
        first = error.errors(include_url=False)[0]
        setting = str(first["loc"][0]) if first["loc"] else ""
        if first["type"] == "extra_forbidden":
            message = f"is read from ice.{setting}" if setting in spec.material else "unknown key"
            raise _cross(key_of(setting), message, ", ".join(spec.table_keys())) from None
        interval = allowed_interval(_table_model(spec).model_json_schema(), first["loc"])
        raise _cross(key_of(setting), f"{first['msg']} (got {first.get('input')!r})", interval) from None
    try:
        spec.make_settings(values)
    except InputError as error:
        setting = error.field.rsplit(".", 1)[-1]
        message = str(error).removeprefix(f"{error.field}: ")
        raise _cross(key_of(setting) if setting in values else spec.name, message) from None
    return values


@functools.lru_cache(maxsize=64)
def _table_model(spec: Any) -> type[BaseModel]:
    """A pydantic model of the scenario table ``[failure.<mode>]``: the settings dataclass's fields (minus
    the [ice] material) with their types, defaults and docstrings, strict and closed."""
    return settings_table_model(spec.settings, f"failure.{spec.name}", spec.table_keys())


def settings_table_model(settings: type, title: str, keys: Iterable[str] | None = None) -> type[BaseModel]:
    """A pydantic model of a scenario table holding the fields `keys` (default all) of the settings
    dataclass `settings`, with their types, defaults, docstrings and `Bounds`, strict and closed."""
    hints = typing.get_type_hints(settings)
    docs = attribute_docstrings(settings)
    bounds = field_bounds(settings)
    fields: dict[str, Any] = {}
    for item in dataclasses.fields(settings):
        if keys is None or item.name in keys:
            default = item.default if item.default is not dataclasses.MISSING else item.default_factory()
            limits = bounds[item.name].pydantic_constraints() if item.name in bounds else {}
            fields[item.name] = (hints[item.name], Field(default, description=docs.get(item.name), **limits))
    config = ConfigDict(extra="forbid", strict=True, frozen=True, allow_inf_nan=False)  # finite, as Float
    return create_model(title, __config__=config, **fields)


def validated_ice_motion(table: Mapping[str, Any]) -> dict[str, Any]:
    """``[ice_motion]`` checked: keys and types (a model of `IceMotionSettings`), then its own range and
    cross-field checks; errors name ``ice_motion.<key>``."""
    from floebreak.dynamics.settings import IceMotionSettings

    model = settings_table_model(IceMotionSettings, "ice_motion")
    try:
        values = model.model_validate(dict(table)).model_dump(exclude_unset=True)
    except ValidationError as error:
        first = error.errors(include_url=False)[0]
        key = str(first["loc"][0]) if first["loc"] else ""
        if first["type"] == "extra_forbidden":
            raise _cross(key, "unknown key", ", ".join(model.model_fields)) from None
        interval = allowed_interval(model.model_json_schema(), first["loc"])
        raise _cross(key, f"{first['msg']} (got {first.get('input')!r})", interval) from None
    try:
        IceMotionSettings(**values)
    except InputError as error:
        message = str(error).removeprefix(f"{error.field}: ")
        raise _cross(error.field.removeprefix("ice_motion."), message, error.allowed) from None
    return values


def attribute_docstrings(cls: type) -> dict[str, str]:
    """Field name → the string literal right below the field in the class body (PEP 257 attribute
    docstrings); empty where the source is not available."""
    try:
        tree = ast.parse(textwrap.dedent(inspect.getsource(cls)))
    except (OSError, TypeError, SyntaxError):
        return {}
    body = tree.body[0].body if tree.body and isinstance(tree.body[0], ast.ClassDef) else []
    docs = {}
    for node, after in itertools.pairwise(body):
        if (
            isinstance(node, ast.AnnAssign)
            and isinstance(node.target, ast.Name)
            and isinstance(after, ast.Expr)
            and isinstance(after.value, ast.Constant)
            and isinstance(after.value.value, str)
        ):
            docs[node.target.id] = inspect.cleandoc(after.value.value)
    return docs


def _normalised_policy(policy: Mapping[str, Any]) -> dict[str, dict[str, list[str]]]:
    """``[failure.policy]`` through `failure.dispatch.normalise_policy` (the registered modes), its errors as
    the scenario's (naming the key); lists, as a TOML file holds them."""
    from floebreak.failure import mode_names, normalise_policy

    try:
        normalised = normalise_policy(policy, mode_names())
    except InputError as error:
        message = str(error).removeprefix(f"{error.field}: ")  # its "(allowed: …)" is not repeated
        raise _cross(error.field.removeprefix("failure.policy."), message, error.allowed) from None
    return {name: {region: list(m) for region, m in regions.items()} for name, regions in normalised.items()}


class PropellerSection(_Section):
    """How the cusps meet the propellers (docs/propeller.md §6; used by the propeller rates only)."""

    fraction_reaching: Float | None = Field(
        None,
        gt=0.0,
        le=1.0,
        description="fraction of the cusps that reach a propeller, in (0, 1]: an override (default: the "
        "transport model decides per cusp; thesis profile: every cusp reaches, thesis §6.2)",
    )
    count: Int = Field(
        AGULHAS_II.propeller_count,
        ge=PROPELLER_COUNT[0],
        le=PROPELLER_COUNT[1],
        description="number of propellers sharing the cusps (default 2: Agulhas II, thesis §6.1) [-], "
        "1 to 8: ice-going ships have 1 to 4",
    )


class SimulationSection(_Section):
    """Guards of the stepping engine (not physics) and where it places failure events."""

    max_pieces: Int | None = Field(
        None,
        ge=1,
        le=100_000_000,
        description="most pieces a run may create, initial floes included; beyond it the run stops with "
        "exit code 2 (default 1 000 000: ≈ 1.2 GB of memory; thin ice breaks into many small pieces) [-]",
    )
    max_wall_s: Float | None = Field(
        None,
        gt=0.0,
        le=WALL_S_MAX,
        description="most wall time a run's stepping may take [s]; beyond it the run stops with exit code 2 "
        "(default 600 s + 60 s per km of transit, ≥ 6 × the slowest measured run: it stops only a runaway)",
    )
    event_location: Literal["step_end", "root"] | None = Field(
        None,
        description="where a piece fails between two contact searches (docs/model.md §9): at the search "
        "position (step_end, the thesis' stepping, §3.2) or located by a bracketing search (root), so that "
        "ship.step_m only sets how often contacts are searched; default: the profile's (§11)",
    )
    event_tolerance_m: Float | None = Field(
        None,
        gt=0.0,
        le=STEP_M[1],
        description="search tolerance of a located failure (event_location = root) [m]; default 0.01 m "
        "(docs/validation.md, convergence)",
    )
    ice_motion: str | None = Field(
        None,
        description="how the ice moves (docs/model.md, Ice motion): static (never, the thesis) or dynamic "
        "(rigid bodies pushed by the hull and by each other, settings in [ice_motion]), or a motion an "
        "installed package adds (floebreak.ice_motions); default static",
        examples=list(BUILTIN_ICE_MOTIONS),
    )
    pose_interval_steps: Int | None = Field(
        None,
        ge=1,
        le=1_000_000,
        description="under ice_motion = dynamic: record the moved pieces' poses every this many steps (and "
        "at the last) into poses.parquet, for floebreak animate; default: none recorded [-]",
    )

    @field_validator("ice_motion")
    @classmethod
    def _known_ice_motion(cls, value: str | None) -> str | None:
        if value is not None and value not in BUILTIN_ICE_MOTIONS and value not in ice_motion_names():
            raise ValueError("Input should be " + " or ".join(map(repr, ice_motion_names())))
        return value


class Scenario(_Section):
    """A complete run description: profile, seed and the field / ice / ship / failure sections."""

    profile: Literal["default", "thesis"] = Field(
        "default",
        description="model profile: default (corrected physics) or thesis (literal, docs/model.md §11)",
    )
    seed: Int = Field(
        1,
        ge=0,
        le=SEED_MAX,
        description="seed of numpy.random.default_rng for the field generation, 0 to 2⁶³ − 1 (TOML integer)",
    )
    name: str = Field("", description="free-text name shown in reports")
    field: FieldSection = Field(default_factory=FieldSection)
    ice: IceSection = Field(default_factory=IceSection)
    ship: ShipSection = Field(default_factory=ShipSection)
    failure: FailureSection = Field(default_factory=FailureSection)
    propeller: PropellerSection = Field(default_factory=PropellerSection)
    simulation: SimulationSection = Field(default_factory=SimulationSection)
    ice_motion: dict[str, Any] | None = Field(
        None,
        description="settings of the rigid-body ice motion under simulation.ice_motion = dynamic "
        "(floebreak.dynamics.IceMotionSettings: drag, added mass, friction, restitution, awake window, time "
        "step; docs/model.md, Ice motion); keys left out keep their defaults",
    )

    @field_validator("ice_motion")
    @classmethod
    def _ice_motion_table(cls, value: dict[str, Any] | None) -> dict[str, Any] | None:
        return None if value is None else validated_ice_motion(value)

    def ice_motion_settings(self) -> Any:
        """The `IceMotionSettings` of ``[ice_motion]`` (defaults where not given)."""
        from floebreak.dynamics.settings import IceMotionSettings

        return IceMotionSettings(**(self.ice_motion or {}))

    # --- construction -----------------------------------------------------------------------------
    @classmethod
    def from_dict(
        cls, data: Mapping[str, Any], base_dir: str | Path | None = None, overrides: Iterable[str] = ()
    ) -> Scenario:
        """Validate a plain dict (as read from TOML), after applying ``--set`` overrides."""
        data = apply_overrides(data, overrides)
        resolve_scenario_plugins(data)
        try:
            return cls.model_validate(data, context={"base_dir": base_dir})
        except ValidationError as error:
            raise input_error_from_validation(error, cls) from None

    @classmethod
    def from_toml_text(
        cls, text: str, base_dir: str | Path | None = None, overrides: Iterable[str] = (), source: str = ""
    ) -> Scenario:
        try:
            # a UTF-8 BOM (Windows editors) is no statement
            data = loads_toml(text.removeprefix("\ufeff"), "scenario", source)
        except tomllib.TOMLDecodeError as error:
            where = f"{source}: " if source else ""
            raise InputError("scenario", f"{where}malformed TOML: {error}", allowed="a TOML file") from None
        return cls.from_dict(data, base_dir=base_dir, overrides=overrides)

    @classmethod
    def from_toml(cls, path: str | Path, overrides: Iterable[str] = ()) -> Scenario:
        """Read a scenario file; relative `file` paths are relative to the scenario file's directory."""
        path = Path(path)
        try:
            text = path.read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError) as error:
            raise InputError(
                "scenario", f"cannot read {str(path)!r}: {error}", allowed="a readable TOML file"
            ) from None
        if _holds_no_key(text, str(path)):  # the defaults are not the reference scenario: say so
            raise InputError(
                "scenario",
                f"{str(path)!r} is an empty scenario (no keys)",
                allowed="a scenario with its keys; start from examples/reference.toml",
            )
        return cls.from_toml_text(text, base_dir=path.parent, overrides=overrides, source=str(path))

    @classmethod
    def reference(cls, overrides: Iterable[str] = ()) -> Scenario:
        """The reference scenario (thesis §5.3)."""
        return cls.from_toml_text(REFERENCE_TOML, overrides=overrides, source="reference scenario")

    # --- resolution and output ------------------------------------------------------------------
    def resolved(self) -> Scenario:
        """The same scenario with every profile- and source-dependent default filled in."""
        from floebreak.config.profiles import field_switches

        switches = field_switches(self.profile)
        field, ice, ship = self.field, self.ice, self.ship
        field_update: dict[str, Any] = {}
        if field.source in ("observation", "user_observation"):
            if field.source == "observation" and field.observation is None:
                field_update["observation"] = REFERENCE_OBSERVATION
            if field.length_m is None:
                field_update["length_m"] = c.REFERENCE_FIELD_LENGTH_M
            if field.width_m is None:
                field_update["width_m"] = c.REFERENCE_FIELD_WIDTH_M
            if field.floe_area_factor is None:
                field_update["floe_area_factor"] = switches.floe_area_factor
        ice_update: dict[str, Any] = {}
        if ice.thickness_summands is None:
            ice_update["thickness_summands"] = switches.thickness_summands
        if ice.thickness_m is None and ice.thickness_range_m is None and field.source == "observation":
            from floebreak.ice.observations import get_observation

            key = field_update.get("observation", field.observation)
            ice_update["thickness_m"] = get_observation(key).mean_thickness_m
        ship_update: dict[str, Any] = {}
        if ship.hull is None and ship.file is None:
            ship_update["hull"] = "agulhas_ii"
        return self.model_copy(
            update={
                "field": field.model_copy(update=field_update),
                "ice": ice.model_copy(update=ice_update),
                "ship": ship.model_copy(update=ship_update),
            }
        )

    def to_dict(self) -> dict[str, Any]:
        """JSON-compatible dict without unset (None) keys; an all-default [simulation] section is left out
        (scenario hashes stay those of the versions without it)."""
        data = self.model_dump(mode="json", exclude_none=True)
        if not data.get("simulation"):
            data.pop("simulation", None)
        return data

    def to_toml(self) -> str:
        return tomli_w.dumps(self.to_dict())

    def hash(self) -> str:
        """SHA-256 of the canonical JSON of this scenario (hash the resolved scenario for a run id)."""
        return hashlib.sha256(json.dumps(self.to_dict(), sort_keys=True).encode()).hexdigest()


def _holds_no_key(text: str, source: str) -> bool:
    """Whether TOML `text` parses to no key at all (empty, blank or comments only); malformed text is left
    to `Scenario.from_toml_text`'s message."""
    try:
        return loads_toml(text.removeprefix("\ufeff"), "scenario", source) == {}
    except tomllib.TOMLDecodeError:
        return False


def json_schema() -> dict[str, Any]:
    """The JSON schema of a scenario file (units in the descriptions), with the table of every registered
    failure mode that has settings and the flat failure keys."""
    from floebreak.failure import get_mode, mode_names

    schema = Scenario.model_json_schema()
    failure = schema["$defs"]["FailureSection"]
    failure["additionalProperties"] = False  # the mode tables below are the only other keys
    for name in mode_names():
        spec = get_mode(name)
        if spec.settings is not None:
            table = _table_model(spec).model_json_schema()
            table["description"] = f"settings of the failure mode {name!r} ({spec.settings.__name__})"
            failure["properties"][name] = table
    for flat, (mode, setting) in FLAT_FAILURE_KEYS.items():
        failure["properties"][flat] = {
            "description": f"deprecated: the same as {mode}.{setting} (the earlier spelling)",
            "deprecated": True,
        }
    from floebreak.dynamics.settings import IceMotionSettings

    motion = settings_table_model(IceMotionSettings, "ice_motion").model_json_schema()
    motion["description"] = schema["properties"]["ice_motion"]["description"]
    schema["properties"]["ice_motion"] = motion
    return schema


def schema_rows(schema: Mapping[str, Any]) -> list[dict[str, str]]:
    """Every key of a scenario's JSON schema (`json_schema`) as a row: dotted key, type, default, allowed
    range and description (whose brackets give the unit), in the schema's order."""
    defs = schema.get("$defs", {})
    rows: list[dict[str, str]] = []

    def resolve(node: Mapping[str, Any]) -> Mapping[str, Any]:
        while "$ref" in node:
            node = defs[node["$ref"].rsplit("/", 1)[-1]]
        for option in node.get("anyOf", []):
            if option.get("type") != "null":
                return {**resolve(option), **{k: v for k, v in node.items() if k != "anyOf"}}
        return node

    def walk(node: Mapping[str, Any], prefix: str) -> None:
        for name, child in resolve(node).get("properties", {}).items():
            child = resolve(child)
            key = f"{prefix}{name}"
            if "properties" in child:
                walk(child, f"{key}.")
                continue
            rows.append(_schema_row(key, child))

    walk(schema, "")
    return rows


def _schema_row(key: str, node: Mapping[str, Any]) -> dict[str, str]:
    """One `schema_rows` row of a leaf key."""
    low = node.get("minimum", node.get("exclusiveMinimum"))
    high = node.get("maximum", node.get("exclusiveMaximum"))
    if "enum" in node:
        allowed = ", ".join(map(str, node["enum"]))
    elif low is not None or high is not None:
        left = "(" if "exclusiveMinimum" in node else "["
        right = ")" if "exclusiveMaximum" in node else "]"
        allowed = (
            f"{left}{'-inf' if low is None else f'{low:g}'}, {'inf' if high is None else f'{high:g}'}{right}"
        )
    else:
        allowed = ""
    default = node.get("default", "")
    return {
        "key": key,
        "type": str(node.get("type", "")),
        "default": "" if default is None else json.dumps(default, ensure_ascii=False),
        "allowed": allowed,
        "description": " ".join(str(node.get("description", "")).split()),
    }


# --- overrides ----------------------------------------------------------------------------------------

_KEY = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*(\.[A-Za-z_][A-Za-z0-9_]*)*$")
_BARE = re.compile(r"^[A-Za-z0-9_.:+\-]+$")


def parse_override(expression: str) -> tuple[list[str], Any]:
    """``a.b=value`` → (["a", "b"], value); the value is parsed as a TOML value, bare words as strings."""
    key, sep, text = expression.partition("=")
    key, text = key.strip(), text.strip()
    if not sep or not _KEY.match(key) or not text:
        raise InputError(
            "--set",
            f"{expression!r} is not KEY=VALUE",
            value=expression,
            allowed="dotted.key=value, e.g. ice.thickness_m=0.8 or ship.hull=polarstern",
        )
    try:
        value = loads_toml(f"v = {text}", "--set", expression)["v"]
    except tomllib.TOMLDecodeError:
        if not _BARE.match(text):
            raise InputError(
                "--set",
                f"{expression!r}: {text!r} is not a TOML value",
                value=expression,
                allowed='a number, true/false, "string", a bare word, or [list]',
            ) from None
        value = text
    if isinstance(value, _dt.date | _dt.time):  # TOML dates (e.g. observation keys) stay text
        value = text
    return key.split("."), value


# Keys that exclude each other (the validators refuse both): an override of one replaces the scenario's
# other, with the keys only that one takes, so `--set` can switch a run to another source — e.g. a run
# directory's resolved scenario onto its own field.parquet, or a fixed thickness to a random one.
_GENERATED_ONLY = ("length_m", "width_m", "concentration", "floe_area_factor")
_REPLACES: dict[tuple[str, str], tuple[str, ...]] = {
    ("field", "observation"): ("diameter_classes_m", "percentages", "file", "floes"),
    ("field", "diameter_classes_m"): ("observation", "file", "floes"),
    ("field", "percentages"): ("observation", "file", "floes"),
    ("field", "file"): ("observation", "diameter_classes_m", "percentages", "floes", *_GENERATED_ONLY),
    ("field", "floes"): ("observation", "diameter_classes_m", "percentages", "file", *_GENERATED_ONLY),
    ("ice", "thickness_m"): ("thickness_range_m",),
    ("ice", "thickness_range_m"): ("thickness_m",),
    ("ship", "hull"): ("file",),
    ("ship", "file"): ("hull", "hull_parameters"),
}


def apply_overrides(data: Mapping[str, Any], overrides: Iterable[str]) -> dict[str, Any]:
    """A deep copy of `data` with each ``a.b=value`` override set.

    An override of one of two keys that exclude each other (a field source: ``field.file``, ``field.floes``,
    ``field.observation``, ``field.diameter_classes_m``/``percentages``; ``ice.thickness_m`` or
    ``ice.thickness_range_m``; ``ship.hull`` or ``ship.file``) first removes from `data` the other and the
    keys only it takes (a file's field has no ``length_m``); two overrides that exclude each other still
    conflict. Likewise an override of a flat failure key or of its mode table key (`FLAT_FAILURE_KEYS`)
    replaces the other spelling.
    """
    result = json.loads(json.dumps(data, default=str)) if data else {}
    overrides = list(overrides)
    parsed = [parse_override(expression) for expression in overrides]
    for path, _ in parsed:
        replaced = _REPLACES.get(tuple(path)) if len(path) == 2 else None
        section = result.get(path[0]) if replaced else None
        if isinstance(section, dict):
            if tuple(path) == ("field", "observation") and "diameter_classes_m" in section:
                section.pop("concentration", None)  # the user observation's, not a change of the named one
            for key in replaced:
                section.pop(key, None)
    for path, _ in parsed:
        _drop_other_spelling(result, path)
    for expression, (path, value) in zip(overrides, parsed, strict=True):
        node = result
        for i, part in enumerate(path[:-1]):
            child = node.setdefault(part, {})
            if not isinstance(child, dict):
                raise InputError(
                    "--set",
                    f"{'.'.join(path[: i + 1])} is not a table",
                    value=expression,
                    allowed="a table key",
                )
            node = child
        node[path[-1]] = value
    return result


def _drop_other_spelling(data: dict[str, Any], path: list[str]) -> None:
    """Before an override of a flat failure key (``failure.crack_criterion``) or of the table key it stands
    for (``failure.cracking.criterion``), remove the other spelling from `data` (giving both is an error)."""
    section = data.get("failure")
    if not isinstance(section, dict) or path[0] != "failure":
        return
    if len(path) == 2 and path[1] in FLAT_FAILURE_KEYS:
        mode, setting = FLAT_FAILURE_KEYS[path[1]]
        table = section.get(mode)
        if isinstance(table, dict):
            table.pop(setting, None)
    elif len(path) == 3:
        for flat, target in FLAT_FAILURE_KEYS.items():
            if target == (path[1], path[2]):
                section.pop(flat, None)


# --- pydantic errors → InputError -------------------------------------------------------------------


def _model_at(model: type[BaseModel], loc: tuple) -> type[BaseModel] | None:
    """The pydantic model class that holds the last element of `loc` (for listing allowed keys)."""
    current: Any = model
    for part in loc[:-1]:
        if isinstance(part, int):
            continue
        if not (isinstance(current, type) and issubclass(current, BaseModel)):
            return None
        info = current.model_fields.get(part)
        if info is None:
            return None
        current = _inner_model(info.annotation)
    return current if isinstance(current, type) and issubclass(current, BaseModel) else None


def _inner_model(annotation: Any) -> Any:
    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        return annotation
    for arg in getattr(annotation, "__args__", ()) or ():
        found = _inner_model(arg)
        if found is not None:
            return found
    return None


def _dotted(loc: Iterable[Any]) -> str:
    text = ""
    for part in loc:
        if isinstance(part, int):
            text += f"[{part}]"
        elif not str(part).startswith(("function-", "tuple[", "list[", "float", "int", "str", "bool")):
            text += ("." if text else "") + str(part)
    return text or "scenario"


def input_error_from_validation(error: ValidationError, model: type[BaseModel] = Scenario) -> InputError:
    """The first pydantic error as an InputError naming the dotted key, with allowed values where known."""
    first = error.errors(include_url=False)[0]
    loc = tuple(first["loc"])
    kind = first["type"]
    message = str(first["msg"]).removeprefix("Value error, ")
    allowed = None
    ctx = first.get("ctx") or {}
    if kind == "floebreak_cross":
        loc = (*loc, ctx["key"])
        allowed = ctx.get("allowed")
    elif kind == "extra_forbidden":
        holder = _model_at(model, loc)
        if holder is not None:
            allowed = ", ".join(holder.model_fields)
        message = "unknown key"
    elif kind in ("unknown_observation", "unknown_hull"):
        message = f"unknown value {ctx['value']!r}"
        allowed = ctx["allowed"]
    elif kind in _BOUND_ERRORS:
        allowed = allowed_interval(json_schema() if model is Scenario else model.model_json_schema(), loc)
    key = _dotted(loc)
    value = first.get("input")
    if kind not in ("extra_forbidden", "missing", "unknown_observation", "unknown_hull") and not isinstance(
        value, dict | list
    ):
        message = f"{message} (got {value!r})"
    return InputError(key, message, value=value, allowed=allowed)


_BOUND_ERRORS = ("greater_than", "greater_than_equal", "less_than", "less_than_equal")


def allowed_interval(schema: Mapping[str, Any], loc: Iterable[Any]) -> str | None:
    """The interval of the number at `loc` (a pydantic error location) in a JSON schema, e.g. ``[0.01, 10]``
    or ``(0, 60]``; None where the schema gives no bound there."""
    defs = schema.get("$defs", {})
    node = _schema_node(schema, defs)
    for part in loc:
        if isinstance(part, int):
            items = node.get("prefixItems") or []
            node = items[part] if part < len(items) else node.get("items", {})
        elif part in node.get("properties", {}):
            node = node["properties"][part]
        else:
            continue  # pydantic's own steps (function-after[...], float, ...)
        node = _schema_node(node, defs)
    low, high = (
        node.get("minimum", node.get("exclusiveMinimum")),
        node.get("maximum", node.get("exclusiveMaximum")),
    )
    if low is None or high is None:
        return None
    left = "(" if "exclusiveMinimum" in node else "["
    right = ")" if "exclusiveMaximum" in node else "]"
    return f"{left}{low:g}, {high:g}{right}"


def _schema_node(node: Mapping[str, Any], defs: Mapping[str, Any]) -> Mapping[str, Any]:
    """`node` with its $ref followed and an optional (``anyOf`` with null) reduced to the other option."""
    if "$ref" in node:
        node = defs[node["$ref"].rsplit("/", 1)[-1]]
    options = [option for option in node.get("anyOf", []) if option.get("type") != "null"]
    return _schema_node(options[0], defs) if len(options) == 1 else node

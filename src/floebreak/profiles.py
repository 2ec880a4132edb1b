"""Model profiles: `default` (corrected physics, physics-notes) and `thesis` (the thesis' literal choices).

A profile is a complete `simulation.Model` plus the field-generation switches of the same errata. Each thesis
switch names its erratum (physics-notes §5); `docs/model.md` §9 lists them with the reasons.
"""

from __future__ import annotations

from dataclasses import dataclass
from types import MappingProxyType
from typing import Any

from floebreak import constants as c
from floebreak.errors import InputError
from floebreak.failure import (
    Bending,
    BendingSettings,
    Cracking,
    CrackingSettings,
    DirectRotation,
    FailureModel,
    LocalCracking,
)
from floebreak.mechanics.classify import ClassificationParams
from floebreak.mechanics.contact import ContactParams
from floebreak.simulation import Model

PROFILES = ("default", "thesis")


@dataclass(frozen=True)
class FieldSwitches:
    """Field-generation choices that differ between profiles (errata 1 and 6)."""

    floe_area_factor: float = c.FLOE_AREA_FACTOR
    thickness_summands: int = c.THICKNESS_SUMMANDS_DEFAULT
    thickness_sum_from_zero: bool = False


# thesis-literal switches, erratum by erratum (physics-notes §5)
THESIS_SWITCHES: MappingProxyType[str, Any] = MappingProxyType(
    {
        "contact.area_model": "single_psi",  # Eq. 6 with one ψ per zone (notes §2.2)
        "contact.force_signs": "thesis_alg3",  # erratum 9: Alg. 3 friction sign of F_h
        "bending.capacity_model": "thesis_per_wedge",  # erratum 13: F_v against one 5° wedge
        "bending.breaking_length_mode": "max_moment",  # erratum 11: max-moment distance
        "bending.loading_radius_model": "sector_area_clipped",  # notes §1.7: r clipped to the Erceg table
        "cracking.bz2_mode": "thesis",  # erratum 15
        "cracking.tada_labels": "thesis_alg7",  # erratum 16, as run (Alg. 7: swapped, exponent 3)
        "cracking.line_load_divide_by_thickness": False,  # erratum 17
        "field.floe_area_factor": 0.5,  # erratum 1
        "field.thickness_summands": c.THICKNESS_SUMMANDS_THESIS,  # erratum 6
        "field.thickness_sum_from_zero": True,  # erratum 6
    }
)


def _split(switches: dict[str, Any], prefix: str) -> dict[str, Any]:
    return {k.split(".", 1)[1]: v for k, v in switches.items() if k.startswith(prefix + ".")}


def profile_switches(profile: str) -> dict[str, Any]:
    if profile not in PROFILES:
        raise InputError("profile", f"unknown profile {profile!r}", allowed=", ".join(PROFILES))
    return dict(THESIS_SWITCHES) if profile == "thesis" else {}


def build_model(
    profile: str = "default",
    *,
    contact: dict[str, Any] | None = None,
    classification: dict[str, Any] | None = None,
    bending: dict[str, Any] | None = None,
    cracking: dict[str, Any] | None = None,
    failure: dict[str, Any] | None = None,
) -> Model:
    """The `Model` of `profile`, with explicit overrides (plain dicts of dataclass fields) applied last."""
    switches = profile_switches(profile)
    bending_settings = BendingSettings(**{**_split(switches, "bending"), **(bending or {})})
    cracking_settings = CrackingSettings(
        **{**_split(switches, "cracking"), **(cracking or {}), "bending": bending_settings}
    )
    failure_model = FailureModel(
        bending=Bending(bending_settings),
        cracking=Cracking(cracking_settings),
        local_cracking=LocalCracking(bending_settings),
        rotation=DirectRotation(),
        **(failure or {}),
    )
    return Model(
        contact=ContactParams(**{**_split(switches, "contact"), **(contact or {})}),
        classification=ClassificationParams(**(classification or {})),
        failure=failure_model,
    )


def field_switches(profile: str) -> FieldSwitches:
    return FieldSwitches(**_split(profile_switches(profile), "field"))

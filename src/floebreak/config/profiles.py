"""Model profiles: `default` (corrected physics, physics-notes) and `thesis` (the thesis' literal choices).

A profile is a complete `simulation.Model` plus the field-generation switches of the same errata. Each thesis
switch names its erratum (physics-notes §5); `docs/model.md` §11 lists them with the reasons.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any

from floebreak import constants as c
from floebreak.engine.loop import Model
from floebreak.errors import InputError
from floebreak.failure import FailureModel, complete_policy, get_mode, mode_names
from floebreak.failure.dispatch import StatedPolicy
from floebreak.mechanics.classify import ClassificationParams
from floebreak.mechanics.contact import ContactParams

PROFILES = ("default", "thesis")


@dataclass(frozen=True)
class FieldSwitches:
    """Field-generation choices that differ between profiles (errata 1 and 6)."""

    floe_area_factor: float = c.FLOE_AREA_FACTOR
    thickness_summands: int = c.THICKNESS_SUMMANDS_DEFAULT
    thickness_sum_from_zero: bool = False


# thesis-literal switches of contact and field generation, erratum by erratum (physics-notes §5); each
# failure mode's own are in its module (its registration's `thesis`)
THESIS_SWITCHES: MappingProxyType[str, Any] = MappingProxyType(
    {
        "contact.area_model": "single_psi",  # Eq. 6 with one ψ per zone (notes §2.2)
        "contact.force_signs": "thesis_alg3",  # erratum 9: Alg. 3 friction sign of F_h
        "ship.waterlines": "fixed",  # thesis §3.1, Table 2: waterlines fixed for every ice thickness
        "field.floe_area_factor": 0.5,  # erratum 1
        "field.thickness_summands": c.THICKNESS_SUMMANDS_THESIS,  # erratum 6
        "field.thickness_sum_from_zero": True,  # erratum 6
        # thesis §3.2: the floe breaks at the step's bow position (its rows were scored with this stepping)
        "simulation.event_location": "step_end",
    }
)
# where the default profile places a failure between two contact searches (docs/model.md §9, §11)
DEFAULT_EVENT_LOCATION = "step_end"


# The thesis profile's dispatch: a bending-class floe at the stem that lies wholly within its breaking radius
# (it cannot bend: shorter than its breaking length, a rigid body — physics-notes §3.2) is rotated whole
# instead of cracked: flipped (thesis §3.2 "If none of them occurs, the floe fails by direct rotation";
# §5.3.1 "larger already bent floes fail by direct rotation"; Table 5: 40 % of the pieces flipped).
THESIS_POLICY: MappingProxyType[str, Any] = MappingProxyType({"bending": {"stem": ("bending", "rotation")}})


def _split(switches: dict[str, Any], prefix: str) -> dict[str, Any]:
    return {k.split(".", 1)[1]: v for k, v in switches.items() if k.startswith(prefix + ".")}


def profile_switches(profile: str) -> dict[str, Any]:
    """Every switch of `profile` as ``section.key`` (``<mode>.<setting>`` for failure modes)."""
    if profile not in PROFILES:
        raise InputError("profile", f"unknown profile {profile!r}", allowed=", ".join(PROFILES))
    if profile == "default":
        return {}
    modes = {f"{name}.{k}": v for name in mode_names() for k, v in get_mode(name).thesis.items()}
    return {**THESIS_SWITCHES, **modes}


def build_failure_model(
    profile: str,
    modes: Mapping[str, Mapping[str, Any]] | None = None,
    policy: StatedPolicy | None = None,
    flip_uncracked_at_shoulder: bool = True,
    shoulder_region_start: float = 0.5,
) -> FailureModel:
    """The registered modes with `profile`'s settings and `modes`' overrides (mode → setting → value,
    applied last), and `policy` (failure class → region → modes) completed with the default."""
    profile_switches(profile)  # an unknown profile → InputError
    modes = dict(modes or {})
    for name in modes:
        get_mode(name)  # an unknown mode → InputError listing the registered ones
    specs = [get_mode(name) for name in mode_names()]
    settings = {
        spec.name: spec.make_settings(
            {**(spec.thesis if profile == "thesis" else {}), **modes.get(spec.name, {})}
        )
        for spec in specs
    }
    full_policy = complete_policy(
        THESIS_POLICY if profile == "thesis" else None,
        policy,
        flip_uncracked_at_shoulder=flip_uncracked_at_shoulder,
        modes=mode_names(),
    )
    used = {name for regions in full_policy.values() for names in regions.values() for name in names}
    instances = {spec.name: spec.create(settings) for spec in specs if spec.name in used}
    return FailureModel(instances, full_policy, shoulder_region_start)


def build_model(
    profile: str = "default",
    *,
    contact: Mapping[str, Any] | None = None,
    classification: Mapping[str, Any] | None = None,
    modes: Mapping[str, Mapping[str, Any]] | None = None,
    failure: Mapping[str, Any] | None = None,
) -> Model:
    """The `Model` of `profile`, with explicit overrides (plain dicts of dataclass fields) applied last.

    `modes` maps a registered mode's name to its settings (``{"cracking": {"criterion": "line_load"}}``);
    `failure` holds the dispatch: ``policy``, ``flip_uncracked_at_shoulder``, ``shoulder_region_start``
    (`build_failure_model`).
    """
    switches = profile_switches(profile)
    return Model(
        contact=ContactParams(**{**_split(switches, "contact"), **(contact or {})}),
        classification=ClassificationParams(**(classification or {})),
        failure=build_failure_model(profile, modes, **(failure or {})),
    )


def field_switches(profile: str) -> FieldSwitches:
    return FieldSwitches(**_split(profile_switches(profile), "field"))

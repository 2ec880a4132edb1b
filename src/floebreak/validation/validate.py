"""`floebreak validate thesis`: the designs the scoreboard needs, run on the study machinery.

Every configuration (a profile, or a profile with a named *variant* of scenario keys) runs the thesis' §5.3
design points (`POINTS`: the one-factor sweeps of Tables 5–8, the Polarstern of §5.1 and the h = 0.4 m of
§6.2) on the same random fields — one study, ``OUT/study``, with common fields, so that every trend is a
paired difference on the same fields — and the single floes of thesis Figs. 15–16 (``OUT/single_floe``).
Both are ordinary study directories: resumable, `--workers` / `--scheduler` as `floebreak study`.
`floebreak.validation.scoreboard` turns them into the scoreboard.
"""

from __future__ import annotations

import copy
import re
from dataclasses import dataclass, field
from typing import Any

from floebreak.config.profiles import PROFILES
from floebreak.config.scenario import parse_override
from floebreak.errors import InputError
from floebreak.studies.design import StudySpec, Sweep

POINTS: dict[str, dict[str, Any]] = {  # design point → scenario keys changed from the reference (§5.3)
    "reference": {},
    "K120": {"ice.fracture_toughness_pa_sqrt_m": 120e3},
    "K230": {"ice.fracture_toughness_pa_sqrt_m": 230e3},
    "point_load": {"failure.cracking.criterion": "point_load"},
    "line_load": {"failure.cracking.criterion": "line_load"},
    "flexural_stress": {"failure.cracking.criterion": "flexural_stress"},
    "h0.8": {"ice.thickness_m": 0.8},
    "h1.2": {"ice.thickness_m": 1.2},
    "h_random": {"ice.thickness_m": None, "ice.thickness_range_m": [0.75, 1.25]},
    "BZ1": {"failure.cracking.size_effect_law": "BZ1"},
    "BZ2": {"failure.cracking.size_effect_law": "BZ2"},
    "polarstern": {"ship.hull": "polarstern"},  # §5.1, Fig. 13
    "h0.4": {"ice.thickness_m": 0.4},  # §6.2: the observation's mean thickness
}


@dataclass(frozen=True)
class Sample:
    """A sample of random fields the must-hold rows are asserted on: a root seed and an observation of thesis
    Table 1 (the field's floe sizes and cover), and the number of common fields."""

    name: str
    seed: int
    observation: str
    n_fields: int


# The sample every reading and measure was chosen on (docs/validation.md, "Selection log"): root seed 2023 on
# the thesis' reference observation.
CHOICE_SAMPLE = Sample("choice", 2023, "2019-12-18T20:20", 16)
# The holdout, used for no choice: a root seed no study of the project has run (seeds used: 5, 7, 11, 99,
# 100–163, 200–215, 300–307, 2023–2026), and the one observation of Table 1 besides those used for choices
# whose floes are the thesis' classes only (d ≤ 15 m, so they fit its 100 m field; the others carry 60 m or
# 300 m floes, 88–90 % of their ice area, a regime the thesis did not study). As many fields as the choice
# sample, so that `make validate` stays within about 12 min on 2 cores; at 19 % cover a field holds 40 % of
# the reference's affected area, so its changes are noisier (docs/validation.md gives the standard errors).
HOLDOUT_SAMPLE = Sample("holdout", 31, "2020-01-03T13:40", 16)
HOLDOUT_SUFFIX = "@holdout"

SINGLE_FLOE_CASES = ((10.0, 0.8), (20.0, 1.0))  # (d [m], h [m]) of thesis Figs. 15 and 16
SINGLE_FLOE_POSITIONS = ("a", "b", "c", "d", "e")
GROUP_SEPARATOR = " | "
_NAME = re.compile(r"^[A-Za-z0-9_-]+$")
_NEXT_KEY = re.compile(r",(?=\s*[A-Za-z_][A-Za-z0-9_]*(?:\.[A-Za-z_][A-Za-z0-9_]*)*\s*=)")


@dataclass(frozen=True)
class Config:
    """A scored configuration: a profile plus the scenario keys of a named variant (none for the profile)."""

    profile: str
    variant: str = ""
    overrides: dict[str, Any] = field(default_factory=dict)

    @property
    def name(self) -> str:
        return f"{self.profile}+{self.variant}" if self.variant else self.profile


def parse_variant(text: str) -> tuple[str, dict[str, Any]]:
    """``NAME:KEY=VALUE[,KEY=VALUE ...]`` → (NAME, {dotted key: parsed value}); values as in ``--set``."""
    name, sep, body = text.partition(":")
    name = name.strip()
    if not sep or not _NAME.match(name) or not body.strip():
        raise InputError(
            "--variant",
            f"{text!r} is not NAME:KEY=VALUE[,KEY=VALUE]",
            value=text,
            allowed="e.g. perwedge:failure.wedge_angle_deg=10 (NAME of letters, digits, _ and -)",
        )
    overrides = {}
    for expression in _NEXT_KEY.split(body):
        path, value = parse_override(expression.strip())
        overrides[".".join(path)] = value
    return name, overrides


def make_configs(profile: str, variants: list[str]) -> list[Config]:
    """The configurations of `--profile default|thesis|both` and every `--variant` (on each profile)."""
    if profile not in (*PROFILES, "both"):
        raise InputError(
            "--profile", f"unknown profile {profile!r}", value=profile, allowed="default, thesis, both"
        )
    profiles = list(PROFILES) if profile == "both" else [profile]
    parsed = [parse_variant(text) for text in variants]
    names = [name for name, _ in parsed]
    if len(set(names)) != len(names):
        raise InputError("--variant", f"repeated variant name in {names}", allowed="distinct names")
    configs = [Config(p) for p in profiles]
    configs += [Config(p, name, overrides) for p in profiles for name, overrides in parsed]
    return configs


def _sweep(config: Config, point: str, keys: dict[str, Any]) -> Sweep:
    parameters = {"profile": [config.profile]}
    parameters.update({key: [value] for key, value in config.overrides.items()})
    parameters.update({key: [value] for key, value in keys.items()})
    return Sweep(name=f"{config.name}{GROUP_SEPARATOR}{point}", mode="zip", parameters=parameters)


def thesis_validation_spec(
    configs: list[Config], base: dict[str, Any], n_fields: int, seed: int, points: dict[str, dict] = POINTS
) -> StudySpec:
    """One study: every configuration × design point on the same `n_fields` fields (common fields)."""
    if n_fields < 1:
        raise InputError("--n-fields", f"{n_fields} < 1", value=n_fields, allowed="an integer ≥ 1")
    sweeps = [_sweep(config, point, keys) for config in configs for point, keys in points.items()]
    return StudySpec(
        name="validate thesis",
        root_seed=seed,
        n_fields=n_fields,
        common_fields=True,
        base=base,
        sweeps=sweeps,
    )


def single_floe_keys(position: str, diameter_m: float, thickness_m: float) -> dict[str, Any]:
    """Scenario keys of one single-floe case (thesis §5.2, Fig. 14): an inline floe ahead of the bow."""
    from floebreak.ship.hulls import get_hull
    from floebreak.studies.single_floe import floe_centre_m

    half_breadth = float(get_hull("agulhas_ii", ice_thickness_m=thickness_m).half_breadth_m)
    x, y = floe_centre_m(position, diameter_m, half_breadth)
    return {
        "field": {"floes": [{"x_m": x, "y_m": y, "diameter_m": diameter_m}]},
        "ice.thickness_m": thickness_m,
        "ship.hull": "agulhas_ii",
    }


def single_floe_spec(configs: list[Config], base: dict[str, Any]) -> StudySpec:
    """The single floes of thesis Figs. 15–16 at the five positions of Fig. 14, per configuration."""
    sweeps = [
        _sweep(config, f"single d{d:g} h{h:g} {position}", single_floe_keys(position, d, h))
        for config in configs
        for d, h in SINGLE_FLOE_CASES
        for position in SINGLE_FLOE_POSITIONS
    ]
    base = copy.deepcopy(base)
    base.pop("field", None)
    return StudySpec(
        name="validate thesis: single floes", n_fields=1, common_fields=True, base=base, sweeps=sweeps
    )


def split_group(group: str) -> tuple[str, str]:
    """``"thesis+perwedge | K120"`` → ("thesis+perwedge", "K120")."""
    config, _, point = group.partition(GROUP_SEPARATOR)
    return config, point

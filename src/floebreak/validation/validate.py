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
import datetime
import math
import re
import tomllib
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


# The scoreboard's stepping, both profiles: failures located between contact searches (root) at the reference
# ship.step_m 0.25 m. The thesis gives no x_step; at step_end the rows move with the step (n_cusp +11 % in
# `thesis` from 0.25 to 0.0625 m), located events are converged at 0.25 m (docs/explanation/validation.md,
# "The scoreboard's stepping"; its convergence table). A later --set replaces it.
SCOREBOARD_STEPPING = ('simulation.event_location="root"',)


@dataclass(frozen=True)
class RegisteredSample:
    """A sample of the samples registry (``validation/samples.toml``): what defines its fields, the profiles
    it is scored in, and when it was registered (and whether it had been run before that)."""

    name: str
    seed: int
    observation: str
    n_fields: int
    length_m: float
    width_m: float
    profiles: tuple[str, ...]
    registered: datetime.date
    run_before_registration: bool = False
    note: str = ""
    generator: str = "circles"  # the field generator (`field.generator`) of its fields


SAMPLE_KEYS = {"name": str, "seed": int, "observation": str, "n_fields": int, "length_m": float,
               "width_m": float, "profiles": list, "registered": datetime.date,
               "run_before_registration": bool, "note": str, "generator": str}  # fmt: skip
OPTIONAL_SAMPLE_KEYS = ("run_before_registration", "note", "generator")
SAMPLE_GENERATORS = ("circles", "voronoi", "sqp")


def _registered_sample(entry: dict[str, Any], where: str) -> RegisteredSample:
    from floebreak.ice.observations import thesis_observations

    unknown = set(entry) - set(SAMPLE_KEYS)
    missing = set(SAMPLE_KEYS) - set(entry) - set(OPTIONAL_SAMPLE_KEYS)
    if unknown or missing:
        raise InputError(where, f"unknown keys {sorted(unknown)}, missing keys {sorted(missing)}",
                         allowed=", ".join(SAMPLE_KEYS))  # fmt: skip
    for key, kind in SAMPLE_KEYS.items():
        value = entry.get(key)
        ok = isinstance(value, kind) and not (kind is int and isinstance(value, bool))
        if kind is float:
            ok = isinstance(value, int | float) and not isinstance(value, bool)
            ok = ok and math.isfinite(value) and value > 0
        if key in entry and not ok:
            raise InputError(f"{where}.{key}", f"{value!r} is not a {kind.__name__}", value=value)
    observations = thesis_observations()
    if entry["n_fields"] < 1 or entry["observation"] not in observations:
        raise InputError(where, "n_fields ≥ 1 and an observation of thesis Table 1 needed",
                         allowed=f"observations {', '.join(observations)}")  # fmt: skip
    if not entry["profiles"] or not set(entry["profiles"]) <= set(PROFILES):
        raise InputError(f"{where}.profiles", f"{entry['profiles']!r}", allowed=", ".join(PROFILES))
    if entry.get("generator", "circles") not in SAMPLE_GENERATORS:
        generator = entry["generator"]
        raise InputError(f"{where}.generator", f"{generator!r}", allowed=", ".join(SAMPLE_GENERATORS))
    values = {key: entry[key] for key in SAMPLE_KEYS if key in entry}
    values.update(profiles=tuple(entry["profiles"]), length_m=float(entry["length_m"]),
                  width_m=float(entry["width_m"]))  # fmt: skip
    return RegisteredSample(**values)


def parse_samples(text: str, source: str = "--samples") -> dict[str, RegisteredSample]:
    """The samples of a registry's TOML text by name, checked (known keys, types, a Table 1 observation,
    known profiles, unique names); an error names `source` and the sample."""
    try:
        entries = tomllib.loads(text).get("sample", [])
    except tomllib.TOMLDecodeError as error:
        raise InputError(source, f"not TOML: {error}") from None
    samples: dict[str, RegisteredSample] = {}
    for index, entry in enumerate(entries):
        sample = _registered_sample(entry, f"{source}: sample {entry.get('name', index)!r}")
        if sample.name in samples:
            raise InputError(source, f"sample {sample.name!r} registered twice", allowed="unique names")
        samples[sample.name] = sample
    return samples


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


def sample_lines(
    n_fields: int, seed: int, observation: str, length_m: float, width_m: float, registry: dict
) -> list[str]:
    """What a `validate thesis` call scores and which committed tally it compares with: its sample size
    (fields, root seed, observation, field size) and the registered sample (`parse_samples`) it is, or,
    where it is none, the registered sample of the same seed and observation (else the first) whose
    committed tally it would need to match, with what differs."""
    lines = [
        f"sample: {n_fields} field(s) per design point, root seed {seed}, observation {observation}, "
        f"field {length_m:g} m × {width_m:g} m"
    ]
    mine = {"n_fields": n_fields, "seed": seed, "observation": observation, "length_m": float(length_m),
            "width_m": float(width_m)}  # fmt: skip
    for sample in registry.values():
        if all(getattr(sample, key) == value for key, value in mine.items()):
            lines.append(f"this is the registered sample {sample.name!r}: compare with its committed tally")
            return lines
    if registry:
        same = [s for s in registry.values() if (s.seed, s.observation) == (seed, observation)]
        ref = (same or list(registry.values()))[0]
        differs = ", ".join(f"{key} {value!r} (its {getattr(ref, key)!r})" for key, value in mine.items()
                            if getattr(ref, key) != value)  # fmt: skip
        lines.append(
            f"not a registered sample: the committed tallies are of registered samples, e.g. {ref.name!r} "
            f"with {ref.n_fields} fields; this differs in {differs}, so its tally is not comparable "
            f"(--sample {ref.name} scores that one)"
        )
    return lines

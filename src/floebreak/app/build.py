"""Scenario → the run's parts: the initial floe field, the bow and the physics model (the first step of
`floebreak.app.run.run`; a study builds each common field once with `build_field` and `field_key`)."""

from __future__ import annotations

import hashlib
import json
import os
from collections.abc import Iterable, Mapping
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import shapely

from floebreak import constants as c
from floebreak.config.scenario import Scenario
from floebreak.engine.loop import MAX_PIECES_DEFAULT
from floebreak.errors import InputError
from floebreak.ice.budget import FieldBudget, check_floe_sizes
from floebreak.ice.field import FloeField, circle_polygons, first_overlap

if TYPE_CHECKING:
    from floebreak.engine.loop import Model

# where generate_field's own field names belong in a scenario
_GENERATION_KEYS = {
    "thickness_m": "ice.thickness_m",
    "thickness_range_m": "ice.thickness_range_m",
    "thickness_min_m": "ice.thickness_range_m",
    "thickness_max_m": "ice.thickness_range_m",
    "thickness_summands": "ice.thickness_summands",
    "max_floes": "simulation.max_pieces",
}


def _prefixed(key: str, error: InputError) -> InputError:
    """`error` re-labelled with the scenario key `key`."""
    message = str(error).removeprefix(f"{error.field}: ")
    return InputError(key, message, value=error.value, allowed=error.allowed)


def waterline_rule(scenario: Scenario) -> str:
    """ "follow_thickness" or "fixed": the scenario's `ship.waterlines`, else its profile's."""
    from floebreak.config.profiles import profile_switches

    return scenario.ship.waterlines or profile_switches(scenario.profile).get(
        "ship.waterlines", "follow_thickness"
    )


def event_location(scenario: Scenario) -> str:
    """ "step_end" or "root": the scenario's `simulation.event_location`, else its profile's."""
    from floebreak.config.profiles import DEFAULT_EVENT_LOCATION, profile_switches

    return scenario.simulation.event_location or profile_switches(scenario.profile).get(
        "simulation.event_location", DEFAULT_EVENT_LOCATION
    )


def ice_motion_params(scenario: Scenario) -> dict[str, Any]:
    """The `SimulationParams` of the ice motion: ``simulation.ice_motion`` (default static) and, when
    dynamic, the ``[ice_motion]`` settings and the ship's speed."""
    motion = scenario.simulation.ice_motion or "static"
    if motion == "static":
        return {}
    settings = scenario.ice_motion_settings()
    propulsion = scenario.ship.propulsion  # under dynamic ice the surge runs in the loop (app/surge.py)
    return {
        "ice_motion": motion,
        "ice_motion_settings": settings,
        "speed_m_s": scenario.ship.speed_m_s,
        "propulsion": None if propulsion is None else propulsion.to_propulsion(),
    }


def _bow_thickness_m(scenario: Scenario, floe_field: FloeField | None = None) -> float:
    """Δz of a built-in hull's waterlines: the ice thickness, or the fixed design value (thesis §3.1)."""
    if waterline_rule(scenario) == "fixed":
        return scenario.ship.waterline_ice_thickness_m
    return _mean_thickness_m(scenario, floe_field)


def _mean_thickness_m(scenario: Scenario, floe_field: FloeField | None = None) -> float:
    ice = scenario.ice
    if ice.thickness_m is not None:
        return ice.thickness_m
    if ice.thickness_range_m is not None:
        return 0.5 * (ice.thickness_range_m[0] + ice.thickness_range_m[1])
    if floe_field is not None and floe_field.n_floes:
        return float(np.mean(floe_field.thickness_m))
    return 1.0


def _draw_thickness(scenario: Scenario, n: int, rng: np.random.Generator) -> np.ndarray:
    from floebreak.config.profiles import field_switches
    from floebreak.ice.thickness import bounded_random_thickness_m

    low, high = scenario.ice.thickness_range_m
    summands = scenario.ice.thickness_summands or field_switches(scenario.profile).thickness_summands
    from_zero = field_switches(scenario.profile).thickness_sum_from_zero
    return bounded_random_thickness_m(rng, low, high, n, summands, thesis_sum_from_zero=from_zero)


def _observation(scenario: Scenario):
    from floebreak.ice.observations import Observation, get_observation

    spec = scenario.field
    try:
        if spec.source == "observation":
            observation = get_observation(spec.observation)
            if spec.concentration is not None:
                observation = replace(observation, concentration=spec.concentration)
            return observation
        mean = _mean_thickness_m(scenario)
        if scenario.ice.thickness_m is None and scenario.ice.thickness_range_m is None:
            raise InputError(
                "ice.thickness_m",
                "a user observation needs a thickness",
                allowed="ice.thickness_m or ice.thickness_range_m",
            )
        return Observation(
            concentration=spec.concentration,
            mean_thickness_m=mean,
            diameter_classes_m=tuple(spec.diameter_classes_m),
            percentages=tuple(spec.percentages),
        )
    except InputError as error:
        if error.field.startswith(("field.", "ice.")):
            raise
        raise _prefixed(f"field.{error.field}", error) from None


def field_key(scenario: Scenario) -> str | None:
    """What `build_field` reads of a resolved scenario with a generated field, as a hash (two scenarios with
    the same key get the same field); None for a field from a file or inline floes (nothing random)."""
    if scenario.field.source not in ("observation", "user_observation"):
        return None
    ice = scenario.ice
    inputs = {
        "profile": scenario.profile,
        "seed": scenario.seed,
        "field": scenario.field.model_dump(mode="json"),
        "ice": [ice.thickness_m, ice.thickness_range_m, ice.thickness_summands],
    }
    return hashlib.sha256(json.dumps(inputs, sort_keys=True).encode()).hexdigest()


def build_field(scenario: Scenario, rng: np.random.Generator) -> FloeField:
    """The initial floe field of a resolved scenario (generated, read from a file, or inline)."""
    from floebreak.config.profiles import field_switches

    spec, ice = scenario.field, scenario.ice
    if spec.source in ("observation", "user_observation"):
        from floebreak.ice.generation import generate_field

        switches = field_switches(scenario.profile)
        thesis_thickness = ice.thickness_range_m is not None and switches.thickness_sum_from_zero
        try:
            floe_field = generate_field(
                _observation(scenario),
                spec.length_m,
                spec.width_m,
                rng,
                generator=spec.generator,
                thickness_m=ice.thickness_m if not thesis_thickness else _mean_thickness_m(scenario),
                thickness_range_m=None if thesis_thickness else ice.thickness_range_m,
                thickness_summands=ice.thickness_summands or switches.thickness_summands,
                floe_area_factor=spec.floe_area_factor or switches.floe_area_factor,
                clustering=spec.clustering,
                seed=scenario.seed,
                max_floes=scenario.simulation.max_pieces or MAX_PIECES_DEFAULT,
                budget=FieldBudget.of_run(
                    scenario.simulation.max_pieces, scenario.simulation.max_wall_s, spec.length_m
                ),
            )
        except InputError as error:
            if error.field.startswith(("field.", "ice.")):
                raise
            raise _prefixed(_GENERATION_KEYS.get(error.field, f"field.{error.field}"), error) from None
        if thesis_thickness:  # thesis' literal Bates sum from i = 0 (erratum 6), drawn after the placement
            floe_field = floe_field.with_thickness(_draw_thickness(scenario, floe_field.n_floes, rng))
        return floe_field
    if spec.source == "file":
        from floebreak.output.field_files import load_field

        floe_field = load_field(spec.file, field="field.file")
        check_floe_sizes(floe_field.polygons, f"field.file: {str(spec.file)!r}")
    else:
        floe_field = _inline_field(scenario)
    if ice.thickness_m is not None:
        floe_field = floe_field.with_thickness(ice.thickness_m)
    elif ice.thickness_range_m is not None:
        floe_field = floe_field.with_thickness(_draw_thickness(scenario, floe_field.n_floes, rng))
    return floe_field


def _inline_field(scenario: Scenario) -> FloeField:
    floes = scenario.field.floes
    centres = np.array([[f.x_m, f.y_m] for f in floes], dtype=float)
    radii = np.array([0.5 * f.diameter_m for f in floes], dtype=float)
    polygons = circle_polygons(centres, radii, c.CIRCLE_POLYGON_VERTICES)
    overlap = first_overlap(polygons)
    if overlap is not None:
        raise InputError(
            f"field.floes[{overlap[1]}]",
            f"overlaps field.floes[{overlap[0]}]",
            allowed="floes that do not overlap (distance between centres ≥ sum of radii)",
        )
    fallback = scenario.ice.thickness_m
    thickness = []
    for i, floe in enumerate(floes):
        h = floe.thickness_m if floe.thickness_m is not None else fallback
        if h is None and scenario.ice.thickness_range_m is None:
            raise InputError(
                f"field.floes[{i}].thickness_m",
                "no thickness for this floe",
                allowed="thickness_m per floe, or ice.thickness_m / ice.thickness_range_m",
            )
        thickness.append(h if h is not None else 1.0)  # a range is drawn afterwards
    return FloeField(
        polygons=polygons,
        thickness_m=np.array(thickness),
        diameter_class_m=2.0 * radii,
        floe_id=np.arange(len(floes)),
        domain_m=tuple(float(v) for v in shapely.total_bounds(polygons)),
        metadata={"source": "inline floes (scenario)", "vertices": c.CIRCLE_POLYGON_VERTICES},
    )


def build_bow(scenario: Scenario, floe_field: FloeField | None = None):
    """The bow of a resolved scenario: a built-in hull at the ice thickness, or a CSV file."""
    ship = scenario.ship
    if ship.file is not None:
        from floebreak.ship.bow import Bow

        try:
            return Bow.from_csv(ship.file)
        except InputError as error:  # keep the file, row and line the bow's reader names
            where = error.field.replace(Path(ship.file).name, str(ship.file), 1)
            message = str(error).removeprefix(f"{error.field}: ")
            raise InputError(
                "ship.file", f"{where}: {message}", value=error.value, allowed=error.allowed
            ) from None
    from floebreak.ship.hulls import get_hull

    try:
        return get_hull(
            ship.hull or "agulhas_ii",
            ice_thickness_m=_bow_thickness_m(scenario, floe_field),
            **ship.hull_parameters,
        )
    except InputError as error:
        # a parameter the user gave is named; a check of the bow they make (e.g. a waterline crossing
        # itself, reported on the bow's own node arrays) names the parameters as a whole
        key = error.field.rsplit(".", 1)[-1]
        given = ship.hull_parameters
        where = "ship.hull_parameters" if given else "ship.hull"
        raise _prefixed(f"{where}.{key}" if key in given else where, error) from None


def build_model_for(scenario: Scenario) -> Model:
    """The physics `Model`: the scenario's profile with the [ice] values, the mode tables
    ``[failure.<mode>]`` and the dispatch keys of [failure] applied (modes from the failure registry)."""
    from floebreak.config.profiles import build_model
    from floebreak.failure import get_mode, mode_names

    ice, failure = scenario.ice, scenario.failure
    tables = failure.mode_tables()
    modes = {}
    for name in mode_names():
        spec = get_mode(name)
        modes[name] = {**{key: getattr(ice, key) for key in spec.material}, **tables.get(name, {})}
    return build_model(
        scenario.profile,
        contact={
            "crushing_strength_pa": ice.crushing_strength_pa,
            "contact_coefficient": ice.contact_coefficient,
            "friction_coefficient": ice.friction_coefficient,
        },
        classification={"youngs_modulus_pa": ice.youngs_modulus_pa, "poisson_ratio": ice.poisson_ratio},
        modes=modes,
        failure={
            "policy": failure.policy,
            "shoulder_region_start": failure.shoulder_region_start,
            "flip_uncracked_at_shoulder": failure.flip_uncracked_at_shoulder,
        },
    )


def as_scenario(
    scenario: Scenario | Mapping[str, Any] | str | os.PathLike[str] | None, overrides: Iterable[str] = ()
) -> Scenario:
    """A Scenario from a Scenario, a dict, a TOML file path, or None (the reference scenario), with
    ``"a.b=value"`` overrides applied (relative paths in a file's overrides are relative to the file)."""
    overrides = list(overrides)
    if scenario is None:
        return Scenario.reference(overrides)
    if isinstance(scenario, Scenario):
        return Scenario.from_dict(scenario.to_dict(), overrides=overrides) if overrides else scenario
    if isinstance(scenario, Mapping):
        return Scenario.from_dict(scenario, overrides=overrides)
    return Scenario.from_toml(scenario, overrides=overrides)


# the contact-search step from which moving ice's cusp statistics stop changing (docs/model.md, "Search-step
# convergence under moving ice")
MOVING_ICE_CONVERGED_STEP_M = 0.0625


def set_up_warnings(scenario: Scenario, bow) -> list[str]:
    """What in a resolved scenario's set-up biases the run's statistics (the run's ``warnings``)."""
    return [*_narrow_field_warnings(scenario, bow), *_moving_ice_step_warnings(scenario)]


def _moving_ice_step_warnings(scenario: Scenario) -> list[str]:
    """Moving ice at a contact-search step coarser than the converged one overstates the cusps."""
    step_m = scenario.ship.step_m
    if scenario.simulation.ice_motion != "dynamic" or step_m <= MOVING_ICE_CONVERGED_STEP_M:
        return []
    return [
        f"ship.step_m = {step_m:g} m under moving ice (simulation.ice_motion = dynamic): the cusp statistics "
        f"are not converged in the search step (at 0.25 m, cusps +4 to +7 % and cusp area +6 to +10 % "
        f"against the finest steps, in two samples of 16 fields; docs/model.md, 'Search-step convergence "
        f"under moving ice'); use ship.step_m ≤ {MOVING_ICE_CONVERGED_STEP_M:g} m for converged "
        f"statistics (about 2.7 × the CPU time)"
    ]


def _narrow_field_warnings(scenario: Scenario, bow) -> list[str]:
    """A generated field narrower than the beam plus twice its largest floe inflates the flipped ice."""
    spec = scenario.field
    if spec.source not in ("observation", "user_observation"):
        return []
    observation = _observation(scenario)
    largest_m = max(
        d for d, p in zip(observation.diameter_classes_m, observation.percentages, strict=True) if p > 0
    )
    beam_m = 2.0 * bow.half_breadth_m
    needed_m = beam_m + 2.0 * largest_m
    if spec.width_m >= needed_m:
        return []
    # floes lie wholly inside the field: the centres of the largest class then all lie within B/2 + d/2 of
    # the track, so every one of them is in the bow's path and none grazes the shoulder (docs/validation.md)
    return [
        f"field.width_m = {spec.width_m:g} m is narrower than the beam plus twice the largest floe "
        f"({beam_m:.1f} m + 2 × {largest_m:g} m = {needed_m:.1f} m): every floe of the largest class lies in "
        "the bow's path, which inflates the flipped ice (docs/validation.md, 'The width'); use "
        f"field.width_m ≥ {needed_m:.1f} m for the statistics of an open ice field"
    ]

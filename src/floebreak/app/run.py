"""One run: scenario → field + bow + model → `simulate` (with a ContactRecorder) → `Result` → run directory.

``floebreak.run(scenario)`` is the Python API (no files touched); ``Result.write(out)`` writes the run
directory atomically (temporary sibling, renamed when complete; a failed run leaves no half directory):

- ``summary.json``: thesis Tables 5–8 columns (n_cusp, A_cusp^tot, n_flip, A_flip^tot, V̄_cusp, Ā_cusp), the
  area balance, contact/break counters, the maximum crushing force, wall time, provenance;
- ``cusps.parquet``, ``flipped.parquet``, ``remaining.parquet``, ``field.parquet`` (the initial field as
  simulated, i.e. after any shift for no initial contact): GeoParquet, ``"crs": null``, one row per piece;
- ``contacts.parquet``: one row per floe–panel contact evaluation (`floebreak.results.CONTACT_COLUMNS`);
- ``pieces.parquet``: every piece that existed in the run (initial floes, broken pieces, cusps, flipped and
  remaining pieces; GeoParquet, field frame; the geometry is empty for a piece created and broken at one bow
  position, which is never in the field between two steps) with ``piece_id``, ``parent_piece_id`` (−1 for
  initial floes), ``parent_floe_id``, ``fate`` (``broken``/``cusp``/``flipped``/``remaining``),
  ``created_step`` (−1 for initial floes), ``ended_step`` (the step it broke or left the field; −1 if it
  remains), ``thickness_m``, ``area_m2``, ``ended_by`` (the failure mode that broke the piece or took it out
  whole, "" if none; `floebreak.results.failure_chain` rebuilds a piece's chain); the metadata adds
  ``x_start_m``, ``step_m``, ``n_steps`` (bow x at step s = x_start_m + s·step_m). Enough to replay the
  transit (``floebreak animate``);
- ``scenario.resolved.toml`` (every default filled in), ``figures/*.png``, ``report.html``.

Every file carries provenance (floebreak and library versions, the resolved scenario, its hash, the seed).
The only randomness is ``numpy.random.default_rng(seed)``, used for the field only, so the same scenario and
seed give identical Parquet contents. ``wall_time_s`` covers field generation (unless a field built beforehand
is given) and simulation, not writing.
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
import time
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, replace
from functools import cached_property
from pathlib import Path
from typing import Any

import numpy as np
import shapely

from floebreak import constants as c
from floebreak.errors import InputError
from floebreak.ice.field import FloeField, circle_polygons, first_overlap
from floebreak.io.atomic import atomic_directory
from floebreak.io.checksums import with_checksum
from floebreak.io.contacts import ContactFile, read_contacts, write_contacts
from floebreak.io.geoparquet import row_groups, write_geoparquet, write_geoparquet_groups
from floebreak.io.jsonable import jsonable, to_json
from floebreak.io.provenance import floebreak_version, provenance
from floebreak.io.storage import as_storage_error, probe_directory
from floebreak.io.writers import write_json
from floebreak.results import (
    ContactRecorder,
    ContactRecords,
    empty_contacts,
    oriented_box_dimensions_m,
    piece_table,
    summary,
)
from floebreak.scenario import Scenario
from floebreak.simulation import (
    EVENT_TOLERANCE_M,
    MAX_PIECES_DEFAULT,
    Callback,
    Model,
    SimulationParams,
    SimulationResult,
    simulate,
)

PIECE_FILES = {"cusp": "cusps.parquet", "flipped": "flipped.parquet", "remaining": "remaining.parquet"}
PIECES_FILE = "pieces.parquet"  # every piece with its life span (replay / `floebreak animate`)
CONTACTS_FILE = "contacts.parquet"
FIGURES = {
    "breaking_pattern": "breaking_pattern.png",
    "cusp_volume_spectrum": "cusp_volume_spectrum.png",
    "crushing_force_spectrum": "crushing_force_spectrum.png",
    "field": "field.png",
}
# the run directory's figures of a longer field or transit show its first this many metres: its whole length
# would be a sliver of pixels, and drawing it holds every polygon once more (benchmarks/README.md, memory)
FIGURE_WINDOW_M = 2000.0


def plot_field_figure(floe_field: FloeField, title: str | None = None):
    """The figure of a floe field: a field longer than `FIGURE_WINDOW_M` shows its first `FIGURE_WINDOW_M`
    (the title says so), so that a figure's memory does not grow with the field (issue 20)."""
    from floebreak.plotting.field import plot_field

    x0, _, x1, _ = floe_field.domain_m
    window = None if x1 - x0 <= FIGURE_WINDOW_M else (x0, x0 + FIGURE_WINDOW_M)
    return plot_field(floe_field, title=title, x_window_m=window)


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


# --- scenario → field, bow, model ------------------------------------------------------------------


def waterline_rule(scenario: Scenario) -> str:
    """ "follow_thickness" or "fixed": the scenario's `ship.waterlines`, else its profile's."""
    from floebreak.profiles import profile_switches

    return scenario.ship.waterlines or profile_switches(scenario.profile).get(
        "ship.waterlines", "follow_thickness"
    )


def event_location(scenario: Scenario) -> str:
    """ "step_end" or "root": the scenario's `simulation.event_location`, else its profile's."""
    from floebreak.profiles import DEFAULT_EVENT_LOCATION, profile_switches

    return scenario.simulation.event_location or profile_switches(scenario.profile).get(
        "simulation.event_location", DEFAULT_EVENT_LOCATION
    )


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
    from floebreak.ice.thickness import bounded_random_thickness_m
    from floebreak.profiles import field_switches

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
    from floebreak.profiles import field_switches

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
            )
        except InputError as error:
            if error.field.startswith(("field.", "ice.")):
                raise
            raise _prefixed(_GENERATION_KEYS.get(error.field, f"field.{error.field}"), error) from None
        if thesis_thickness:  # thesis' literal Bates sum from i = 0 (erratum 6), drawn after the placement
            floe_field = floe_field.with_thickness(_draw_thickness(scenario, floe_field.n_floes, rng))
        return floe_field
    if spec.source == "file":
        from floebreak.io.field_files import load_field

        floe_field = load_field(spec.file, field="field.file")
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
    from floebreak.failure import get_mode, mode_names
    from floebreak.profiles import build_model

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


# --- the result -----------------------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class Result:
    """A finished run: the resolved scenario, the simulation result, contact records and the summary.

    ``cusps``/``flipped``/``remaining`` are column dicts (geometry included, see `floebreak.results
    .piece_table`); ``contacts`` holds one row per floe–panel contact evaluation: kept in memory, or, for a
    run with a spool (`run`), read back from the spool's ``contacts.parquet`` when asked for.
    """

    scenario: Scenario  # resolved
    simulation: SimulationResult
    contact_records: ContactRecords
    summary: dict[str, Any]
    contacts_file: Path | None = None  # the spooled records, if the run streamed them (`run`)

    @cached_property
    def contacts(self) -> dict[str, np.ndarray]:
        """The contact records as numpy columns (`floebreak.results.CONTACT_COLUMNS`)."""
        if self.contact_records.columns is not None:
            return self.contact_records.columns
        return read_contacts(self.contacts_file)

    @property
    def field(self) -> FloeField:
        """The initial field as simulated (after any shift for no initial contact)."""
        return self.simulation.field

    @cached_property
    def cusps(self) -> dict[str, Any]:
        return piece_table(self.simulation, "cusp")

    @cached_property
    def flipped(self) -> dict[str, Any]:
        return piece_table(self.simulation, "flipped")

    @cached_property
    def remaining(self) -> dict[str, Any]:
        return piece_table(self.simulation, "remaining")

    @cached_property
    def pieces(self) -> dict[str, Any]:
        """Every piece of the run with its life span (`pieces_table`), for replaying the transit."""
        return pieces_table(self.simulation, self.contact_records)

    @cached_property
    def crushing_forces_n(self) -> np.ndarray:
        """Total crushing force of each contact-zone evaluation [N] (thesis Fig. 13)."""
        return self.contact_records.crushing_forces_n

    def provenance(self, kind: str) -> dict[str, Any]:
        return _provenance(self.scenario, kind)

    # --- figures (matplotlib Figures; the caller closes or saves them) -------------------------------
    def plot_breaking_pattern(self, title: str | None = None):
        """Thesis colour code: blue remaining, orange flipped, red cusps; bow outline at start and end.
        A field longer than `FIGURE_WINDOW_M`: its first `FIGURE_WINDOW_M` (the title says so), bow outline at
        the start."""
        from floebreak.plotting.pattern import plot_breaking_pattern

        sim = self.simulation
        upper_x = np.asarray(sim.bow.upper_xy_m)[:, 0]
        x_last = sim.params.x_start_m + (sim.n_steps - 1) * sim.params.step_m
        pieces = _total_bounds(sim.piece_bounds_m) if sim.piece_id.size else np.array(sim.field.domain_m)
        xlim = (
            min(pieces[0], sim.params.x_start_m + upper_x.min()) - 2.0,
            max(pieces[2], x_last + upper_x.max()) + 2.0,
        )  # both bow outlines (start and end) inside the frame
        title = title or self._title("breaking pattern")
        field_x0, _, field_x1, _ = sim.field.domain_m
        if field_x1 - field_x0 <= FIGURE_WINDOW_M:
            return plot_breaking_pattern(sim, title=title, xlim=xlim)
        window = (xlim[0], field_x0 + FIGURE_WINDOW_M)  # from the bow at the start to 2 km into the field
        return plot_breaking_pattern(sim, title=title, x_window_m=window, bow_at_end=False)

    def plot_cusp_volume_spectrum(self):
        """Cusp-volume probability density (thesis Fig. 17 style)."""
        from floebreak.plotting.spectra import plot_cusp_volume_spectrum

        sim = self.simulation
        cusp = sim.mask("cusp")  # area × thickness, as the cusps table's, without decoding the polygons
        return plot_cusp_volume_spectrum(sim.piece_area_m2[cusp] * sim.thickness_m[cusp])

    def plot_crushing_force_spectrum(self):
        """Crushing-force probability density per contact evaluation (thesis Fig. 13)."""
        from floebreak.plotting.spectra import plot_crushing_force_spectrum

        return plot_crushing_force_spectrum(self.crushing_forces_n)

    def plot_field(self):
        """The initial floe field (`plot_field_figure`)."""
        return plot_field_figure(self.field, title=self._title("initial floe field"))

    def _title(self, what: str) -> str:
        name = self.scenario.name or (self.scenario.field.observation or self.scenario.field.source)
        return f"{what}: {name}, profile {self.scenario.profile}, seed {self.scenario.seed}"

    # --- writing ----------------------------------------------------------------------------------
    def write(
        self,
        out: str | os.PathLike[str],
        overwrite: bool = False,
        report: bool = True,
        figures: bool = True,
        directory_name: str | None = None,
    ) -> Path:
        """Write the run directory `out` atomically; refuses an existing `out` unless `overwrite`.

        `directory_name`: the name the report shows (default `out`'s), for a caller that writes into a
        temporary directory of its own and renames it afterwards.
        """
        return write_run_directory(
            self, out, overwrite=overwrite, report=report, figures=figures, directory_name=directory_name
        )


def run(
    scenario: Scenario | Mapping[str, Any] | str | os.PathLike[str] | None = None,
    *,
    overrides: Iterable[str] = (),
    callbacks: Iterable[Callback] = (),
    floe_field: FloeField | None = None,
    spool: str | os.PathLike[str] | None = None,
) -> Result:
    """Run a scenario (a `Scenario`, a dict, a TOML path; None = the reference scenario) and return a Result.

    `overrides` are ``"a.b=value"`` strings (as ``--set``); `callbacks` receive the engine's events. No files
    are written; call ``result.write(out)`` for a run directory. `floe_field`: the field `build_field` gives
    for this scenario, built beforehand (a study builds each common field once, `floebreak.studies.runner`);
    the field is the only use of the scenario's random numbers, so the run is the same as with None, except
    that ``wall_time_s`` then leaves out the field's generation. `spool`: an existing directory into which
    the contact records stream (``contacts.parquet``, in row groups) instead of staying in memory (a long
    transit makes ≈ 20 000 rows per km); the Result reads them back from there when asked for, and
    `Result.write` copies the file, so the directory must outlive the Result's use of its records.
    """
    started = time.perf_counter()
    if spool is not None and not Path(spool).is_dir():
        raise InputError("spool", f"{str(spool)!r} is not a directory", allowed="an existing directory")
    scenario = as_scenario(scenario, overrides).resolved()
    if floe_field is None:
        floe_field = build_field(scenario, np.random.default_rng(scenario.seed))
    bow = build_bow(scenario, floe_field)
    model = build_model_for(scenario)
    ship = scenario.ship
    params = SimulationParams(
        step_m=ship.step_m,
        x_start_m=ship.x_start_m,
        x_end_m=ship.x_end_m,
        initial_contact=ship.initial_contact,
        max_pieces=scenario.simulation.max_pieces or MAX_PIECES_DEFAULT,
        max_wall_s=scenario.simulation.max_wall_s,
        event_location=event_location(scenario),
        event_tolerance_m=scenario.simulation.event_tolerance_m or EVENT_TOLERANCE_M,
    )
    contacts_file = (
        None
        if spool is None
        else ContactFile(Path(spool) / CONTACTS_FILE, _provenance(scenario, "contacts"), empty_contacts())
    )
    recorder = ContactRecorder(sink=None if contacts_file is None else contacts_file.write)
    try:
        simulation = simulate(floe_field, bow, model, params, callbacks=[recorder, *callbacks])
        records = recorder.records()  # the last chunk of records too
    except BaseException:
        if contacts_file is not None:
            contacts_file.discard()
        raise
    if contacts_file is not None:
        contacts_file.close()
    stats = summary(simulation, records)
    shift = simulation.field.metadata.get("shifts_m", [])
    head = {
        "floebreak_version": floebreak_version(),
        "profile": scenario.profile,
        "seed": scenario.seed,
        "scenario_hash": scenario.hash(),
        "model_hash": model.fingerprint(),
    }
    tail = {
        "field_shift_m": float(sum(s["dx_m"] for s in shift)) if shift else 0.0,
        "bow": getattr(bow, "name", "bow"),
        "warnings": set_up_warnings(scenario, bow),
        "wall_time_s": time.perf_counter() - started,
    }
    path = None if contacts_file is None else contacts_file.path
    return Result(scenario, simulation, records, {**head, **stats, **tail}, contacts_file=path)


def set_up_warnings(scenario: Scenario, bow) -> list[str]:
    """What in a resolved scenario's set-up biases the run's statistics (the run's ``warnings``)."""
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


def _total_bounds(bounds: np.ndarray) -> np.ndarray:
    """(x_min, y_min, x_max, y_max) of rows of bounds, NaN rows (empty pieces) skipped, as
    ``shapely.total_bounds`` of the pieces."""
    if np.isnan(bounds).all():
        return np.full(4, np.nan)
    return np.concatenate([np.nanmin(bounds[:, :2], axis=0), np.nanmax(bounds[:, 2:], axis=0)])


def _provenance(scenario: Scenario, kind: str) -> dict[str, Any]:
    """The provenance of a file of the run of the resolved `scenario`."""
    return provenance(
        kind=kind,
        seed=scenario.seed,
        profile=scenario.profile,
        scenario_hash=scenario.hash(),
        scenario=scenario.to_dict(),
    )


# --- the run directory ------------------------------------------------------------------------------


def field_table(floe_field: FloeField) -> dict[str, Any]:
    """Columns of the initial field in the layout of the piece tables (step −1, no failure mode)."""
    polygons = floe_field.polygons
    area = floe_field.area_m2
    length, width = oriented_box_dimensions_m(polygons)
    centroids = shapely.get_coordinates(shapely.centroid(polygons)) if polygons.size else np.zeros((0, 2))
    n = floe_field.n_floes
    return {
        "geometry": polygons,
        "floe_id": floe_field.floe_id,
        "area_m2": area,
        "thickness_m": floe_field.thickness_m,
        "volume_m3": area * floe_field.thickness_m,
        "diameter_class_m": floe_field.diameter_class_m,
        "centroid_x_m": centroids[:, 0],
        "centroid_y_m": centroids[:, 1],
        "bbox_length_m": length,
        "bbox_width_m": width,
        "step": np.full(n, -1, dtype=np.int64),
        "bow_x_m": np.full(n, np.nan),
        "parent_floe_id": floe_field.floe_id,
        "parent_piece_id": np.full(n, -1, dtype=np.int64),
        "failure_mode": np.array([""] * n, dtype=object),
    }


def pieces_table(
    simulation: SimulationResult,
    contacts: Mapping[str, np.ndarray] | ContactRecords,
    geometry: bool = True,
) -> dict[str, Any]:
    """Columns of every piece of the run (fates "broken", "cusp", "flipped", "remaining"), geometry included.

    ``created_step``: −1 for initial floes, else the step at which the parent broke (the engine adds the
    children in the same step, `floebreak.simulation.simulate`). ``ended_step``: the step a cusp or flipped
    piece left the field (`SimulationResult.step`), the step a broken piece broke, −1 for remaining pieces.
    `SimulationResult.step` of a broken piece is its creation step, and a child that rotated away later
    carries its leaving step, so the break step is taken from the recorded contact evaluations: a piece
    fails at most once, in its one evaluation with an outcome other than "no_failure". (Fallback without a
    record: the earliest step among its children, which is exact whenever one child stayed in the field or
    broke again.) `contacts`: the records' columns, or what `ContactRecorder.records` keeps of them.
    `geometry=False`: no ``geometry`` column (for a writer that takes the polygons a row group at a time).
    """
    if isinstance(contacts, ContactRecords):
        failed_piece, failed_step = contacts.failed_piece_id, contacts.failed_step
    else:
        failed = np.asarray(contacts["outcome"]) != "no_failure"
        failed_piece = np.asarray(contacts["piece_id"])[failed]
        failed_step = np.asarray(contacts["step"])[failed]
    fate = simulation.fate
    n = len(fate)
    ended = np.full(n, -1, dtype=np.int64)
    gone = (fate == "cusp") | (fate == "flipped")
    ended[gone] = simulation.step[gone]
    parents = simulation.parent_piece_id
    broken = np.flatnonzero(fate == "broken")
    if broken.size:
        never = np.iinfo(np.int64).max
        break_step = np.full(n, never, dtype=np.int64)
        np.minimum.at(break_step, failed_piece, failed_step)
        children_step = np.full(n, never, dtype=np.int64)
        child = parents >= 0
        np.minimum.at(children_step, parents[child], simulation.step[child])
        ended[broken] = np.where(break_step[broken] != never, break_step[broken], children_step[broken])
    created = np.where(parents >= 0, ended[np.maximum(parents, 0)], -1).astype(np.int64)
    columns = {
        "piece_id": simulation.piece_id,
        "parent_piece_id": parents,
        "parent_floe_id": simulation.parent_floe_id,
        "fate": np.asarray(fate, dtype=object),
        "created_step": created,
        "ended_step": ended,
        "thickness_m": simulation.thickness_m,
        "area_m2": simulation.piece_area_m2,
        "ended_by": simulation.ended_by,
    }
    return {"geometry": simulation.polygon, **columns} if geometry else columns


def _write_table(path: Path, columns: Mapping[str, Any], metadata: Mapping[str, Any]) -> None:
    rest = {k: v for k, v in columns.items() if k != "geometry"}
    write_geoparquet(path, columns["geometry"], rest, metadata)


def _write_piece_file(path: Path, sim: SimulationResult, fate: str, metadata: Mapping[str, Any]) -> None:
    """The table of the pieces with `fate` (`piece_table`), built and written one row group at a time."""
    ids = np.flatnonzero(sim.mask(fate))

    def table_of(group: np.ndarray) -> tuple[np.ndarray, dict[str, Any]]:
        columns = piece_table(sim, fate, group)
        return columns.pop("geometry"), columns

    groups = [ids[rows] for rows in row_groups(len(ids))]
    write_geoparquet_groups(path, groups, sim.polygons, table_of, metadata)


def _save_png(figure, path: Path, meta: Mapping[str, Any]) -> None:
    text = {"Software": f"floebreak {meta['floebreak_version']}", "Description": to_json(dict(meta))}
    figure.savefig(path, format="png", dpi=150, metadata=text)


def check_output_directory(out: str | os.PathLike[str], overwrite: bool) -> Path:
    """Refuse (InputError on key "out") an existing `out` without `overwrite` or a missing parent; raise
    StorageError if the parent cannot be written (full, read-only, no permission)."""
    out = Path(out)
    if out.exists() and not overwrite:
        raise InputError("out", f"{str(out)!r} exists", allowed="a new path, or pass --overwrite")
    if out.exists() and not out.is_dir():
        raise InputError("out", f"{str(out)!r} is a file", allowed="a directory path")
    parent = out.parent if str(out.parent) else Path(".")
    if not parent.is_dir():
        raise InputError("out", f"directory {str(parent)!r} does not exist", allowed="an existing directory")
    probe_directory(parent, out)  # a full, read-only or pseudo file system: StorageError before the run
    return out


def write_run_directory(
    result: Result,
    out: str | os.PathLike[str],
    overwrite: bool = False,
    report: bool = True,
    figures: bool = True,
    directory_name: str | None = None,
) -> Path:
    """Write the run directory (see the module docstring) atomically and return its path.

    `figures=False` skips ``figures/`` (and the report then has none): for large studies and tests.
    """
    out = check_output_directory(out, overwrite)
    try:
        _write_run_files(result, out, overwrite, report, figures, directory_name)
    except OSError as error:
        storage = as_storage_error(error, out)
        if storage is None:
            raise
        raise storage from None
    return out


def _write_run_files(
    result: Result, out: Path, overwrite: bool, report: bool, figures: bool, directory_name: str | None
) -> None:
    with atomic_directory(out, overwrite=overwrite, field="out") as temp:
        field_meta = {
            **result.provenance("floe_field"),
            "domain_m": list(result.field.domain_m),
            "field": dict(result.field.metadata),
        }
        _write_table(temp / "field.parquet", field_table(result.field), field_meta)
        sim = result.simulation
        for fate, name in PIECE_FILES.items():
            _write_piece_file(temp / name, sim, fate, result.provenance(fate))
        if result.contacts_file is not None and result.contact_records.columns is None:
            shutil.copyfile(result.contacts_file, temp / CONTACTS_FILE)  # the records streamed there
        else:
            write_contacts(temp / CONTACTS_FILE, result.contacts, result.provenance("contacts"))
        stepping = {"x_start_m": sim.params.x_start_m, "step_m": sim.params.step_m, "n_steps": sim.n_steps}
        columns = pieces_table(sim, result.contact_records, geometry=False)
        write_geoparquet_groups(
            temp / PIECES_FILE,
            row_groups(len(sim.piece_id)),
            sim.polygons,
            lambda rows: (sim.polygons(rows), {k: v[rows] for k, v in columns.items()}),
            {**result.provenance("pieces"), **stepping},
        )
        summary_doc = jsonable({**result.summary, "provenance": result.provenance("summary")})
        write_json(temp / "summary.json", summary_doc)
        header = (
            f"# resolved scenario written by floebreak {floebreak_version()}; "
            f"scenario_hash = {result.summary['scenario_hash']}\n"
        )
        (temp / "scenario.resolved.toml").write_text(header + result.scenario.to_toml(), encoding="utf-8")
        if figures:
            folder = temp / "figures"
            folder.mkdir()
            meta = result.provenance("figure")
            for key, name in FIGURES.items():
                _save_png(getattr(result, f"plot_{key}")(), folder / name, meta)
        if report:
            from floebreak.report import write_report

            write_report(temp, directory_name=directory_name or out.name)
        summary_doc["files"] = file_checksums(temp)  # a resumed study re-runs a run whose files differ
        summary_doc = with_checksum(summary_doc)  # ... or whose summary was edited
        write_json(temp / "summary.json", summary_doc)


def file_checksums(run_dir: Path, names: Iterable[str] | None = None) -> dict[str, str]:
    """SHA-256 of the files `names` (relative paths; default: every file but the top ``summary.json``,
    which records them) of a run directory; a missing file gets "missing"."""
    run_dir = Path(run_dir)
    if names is None:
        files = (p for p in run_dir.rglob("*") if p.is_file() and p != run_dir / "summary.json")
        names = [p.relative_to(run_dir).as_posix() for p in files]
    sums = {}
    for name in sorted(names):
        digest = hashlib.sha256()
        try:
            with (run_dir / name).open("rb") as file:
                for block in iter(lambda: file.read(1 << 20), b""):
                    digest.update(block)
        except FileNotFoundError:
            sums[name] = "missing"
            continue
        sums[name] = digest.hexdigest()
    return sums

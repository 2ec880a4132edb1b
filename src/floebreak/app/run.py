"""One run: scenario → field + bow + model (`floebreak.app.build`) → `simulate` (with a ContactRecorder) →
`Result` → run directory (`floebreak.output.run_directory`, whose docstring lists the files).

``floebreak.run(scenario)`` is the Python API (no files touched); ``Result.write(out)`` writes the run
directory atomically. The only randomness is ``numpy.random.default_rng(seed)``, used for the field only, so
the same scenario and seed give identical Parquet contents. ``wall_time_s`` covers field generation (unless
a field built beforehand is given) and simulation, not writing.

The names of `build` and `run_directory` are importable from here too (`floebreak.api` re-exports the
curated ones).
"""

from __future__ import annotations

import os
import time
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path
from typing import Any

import numpy as np
import shapely

from floebreak.app.build import (
    as_scenario,
    build_bow,
    build_field,
    build_model_for,
    event_location,
    ice_motion_params,
    set_up_warnings,
)
from floebreak.app.build import field_key as field_key  # re-exported (`as`), as the names below
from floebreak.app.build import waterline_rule as waterline_rule
from floebreak.config.scenario import Scenario
from floebreak.engine.loop import (
    EVENT_TOLERANCE_M,
    MAX_PIECES_DEFAULT,
    Callback,
    SimulationParams,
    SimulationResult,
    simulate,
)
from floebreak.engine.records import ContactRecorder, ContactRecords, empty_contacts, piece_table, summary
from floebreak.errors import InputError
from floebreak.ice.field import FloeField, diameter_classes_m
from floebreak.io.contacts import ContactFile, read_contacts
from floebreak.io.provenance import floebreak_version, provenance
from floebreak.output.figure_process import FigureCall, FigureWorker, draw_figure
from floebreak.output.pose_file import PoseRecorder, check_pose_interval
from floebreak.output.run_directory import CONTACTS_FILE, pieces_table, write_run_directory
from floebreak.output.run_directory import FIGURES as FIGURES
from floebreak.output.run_directory import PIECE_FILES as PIECE_FILES
from floebreak.output.run_directory import PIECES_FILE as PIECES_FILE
from floebreak.output.run_directory import check_output_directory as check_output_directory
from floebreak.output.run_directory import field_table as field_table
from floebreak.output.run_directory import file_checksums as file_checksums
from floebreak.output.surge_file import surge_summary
from floebreak.plotting.pattern_data import breaking_pattern

# the run directory's figures of a longer field or transit show its first this many metres: its whole length
# would be a sliver of pixels, and drawing it holds every polygon once more (benchmarks/README.md, memory)
FIGURE_WINDOW_M = 2000.0


def plot_field_figure(floe_field: FloeField, title: str | None = None):
    """The figure of a floe field (`field_figure_call`)."""
    return draw_figure(field_figure_call(floe_field, title))


def field_figure_call(floe_field: FloeField, title: str | None = None) -> FigureCall:
    """The plotting call of a floe field's figure: a field longer than `FIGURE_WINDOW_M` shows its first
     `FIGURE_WINDOW_M` (the title says so), so that a figure's memory does not grow with the field
    ."""
    x0, _, x1, _ = floe_field.domain_m
    if x1 - x0 <= FIGURE_WINDOW_M:
        return "field", "plot_field", (floe_field,), {"title": title, "x_window_m": None}
    window = (x0, x0 + FIGURE_WINDOW_M)
    # the call carries the floes the figure draws, not the whole field (a figure worker is sent it), and
    # the field's diameter classes, so that the colours and the legend are the whole field's
    bounds = shapely.bounds(floe_field.polygons).reshape(-1, 4)
    shown = floe_field.subset((bounds[:, 0] <= window[1]) & (bounds[:, 2] >= window[0]))
    kwargs = {"title": title, "x_window_m": window, "classes_m": diameter_classes_m(floe_field)}
    return "field", "plot_field", (shown,), kwargs


@dataclass(frozen=True, eq=False)
class Result:
    """A finished run: the resolved scenario, the simulation result, contact records and the summary.

    ``cusps``/``flipped``/``remaining`` are column dicts (geometry included, see `floebreak.engine.records
    .piece_table`); ``contacts`` holds one row per floe–panel contact evaluation: kept in memory, or, for a
    run with a spool (`run`), read back from the spool's ``contacts.parquet`` when asked for.
    """

    scenario: Scenario  # resolved
    simulation: SimulationResult
    contact_records: ContactRecords
    summary: dict[str, Any]
    contacts_file: Path | None = None  # the spooled records, if the run streamed them (`run`)
    poses: PoseRecorder | None = None  # the moved pieces' poses (simulation.pose_interval_steps)

    @cached_property
    def contacts(self) -> dict[str, np.ndarray]:
        """The contact records as numpy columns (`floebreak.engine.records.CONTACT_COLUMNS`)."""
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
    def figure_call(self, key: str) -> FigureCall:
        """The plotting call, as plain data, of the figure `key` (of `FIGURES`; `plot_<key>` draws it)."""
        return getattr(self, f"_{key}_call")()

    def plot_breaking_pattern(self, title: str | None = None):
        """Thesis colour code: blue remaining, orange flipped, red cusps; bow outline at start and end.
        A field longer than `FIGURE_WINDOW_M`: its first `FIGURE_WINDOW_M` (the title says so), bow outline at
        the start."""
        return draw_figure(self._breaking_pattern_call(title))

    def _breaking_pattern_call(self, title: str | None = None) -> FigureCall:
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
        # the call carries what the figure draws (`BreakingPattern`), not the run's result: a figure worker
        # is sent it
        if field_x1 - field_x0 <= FIGURE_WINDOW_M:
            kwargs = {"title": title, "xlim": xlim}
            return "pattern", "plot_breaking_pattern", (breaking_pattern(sim),), kwargs
        window = (xlim[0], field_x0 + FIGURE_WINDOW_M)  # from the bow at the start to 2 km into the field
        kwargs = {"title": title, "bow_at_end": False}
        return "pattern", "plot_breaking_pattern", (breaking_pattern(sim, window),), kwargs

    def plot_cusp_volume_spectrum(self):
        """Cusp-volume probability density (thesis Fig. 17 style)."""
        return draw_figure(self._cusp_volume_spectrum_call())

    def _cusp_volume_spectrum_call(self) -> FigureCall:
        sim = self.simulation
        cusp = sim.mask("cusp")  # area × thickness, as the cusps table's, without decoding the polygons
        return "spectra", "plot_cusp_volume_spectrum", (sim.piece_area_m2[cusp] * sim.thickness_m[cusp],), {}

    def plot_crushing_force_spectrum(self):
        """Crushing-force probability density per contact evaluation (thesis Fig. 13)."""
        return draw_figure(self._crushing_force_spectrum_call())

    def _crushing_force_spectrum_call(self) -> FigureCall:
        return "spectra", "plot_crushing_force_spectrum", (self.crushing_forces_n,), {}

    def plot_field(self):
        """The initial floe field (`plot_field_figure`)."""
        return draw_figure(self._field_call())

    def _field_call(self) -> FigureCall:
        return _run_field_figure_call(self.scenario, self.field)

    def _title(self, what: str) -> str:
        return _title(self.scenario, what)

    # --- writing ----------------------------------------------------------------------------------
    def write(
        self,
        out: str | os.PathLike[str],
        overwrite: bool = False,
        report: bool = True,
        figures: bool = True,
        directory_name: str | None = None,
        figure_worker: FigureWorker | None = None,
    ) -> Path:
        """Write the run directory `out` atomically; refuses an existing `out` unless `overwrite`.

        `directory_name`: the name the report shows (default `out`'s), for a caller that writes into a
        temporary directory of its own and renames it afterwards. `figure_worker`: the process forked
        before the run to draw the figures (`floebreak.output.run_directory.figure_worker`; the one given to
        `run`, if any).
        """
        return write_run_directory(
            self,
            out,
            overwrite=overwrite,
            report=report,
            figures=figures,
            directory_name=directory_name,
            figure_worker=figure_worker,
        )


def run(
    scenario: Scenario | Mapping[str, Any] | str | os.PathLike[str] | None = None,
    *,
    overrides: Iterable[str] = (),
    callbacks: Iterable[Callback] = (),
    floe_field: FloeField | None = None,
    spool: str | os.PathLike[str] | None = None,
    figure_worker: FigureWorker | None = None,
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
    `figure_worker` (`floebreak.output.run_directory.figure_worker`): it is sent the field's figure once it
    has imported matplotlib, to draw while the engine runs; give it to `Result.write` too.
    """
    started = time.perf_counter()
    if spool is not None and not Path(spool).is_dir():
        raise InputError("spool", f"{str(spool)!r} is not a directory", allowed="an existing directory")
    scenario = as_scenario(scenario, overrides).resolved()
    if floe_field is None:
        floe_field = build_field(scenario, np.random.default_rng(scenario.seed))
    bow = build_bow(scenario, floe_field)
    model = build_model_for(scenario)
    params = _simulation_params(scenario)
    contacts_file = (
        None
        if spool is None
        else ContactFile(Path(spool) / CONTACTS_FILE, _provenance(scenario, "contacts"), empty_contacts())
    )
    recorder = ContactRecorder(sink=None if contacts_file is None else contacts_file.write)
    interval = scenario.simulation.pose_interval_steps
    check_pose_interval(interval, params.ice_motion)
    poses = None if interval is None else PoseRecorder(interval)
    extra = [] if poses is None else [poses]
    if figure_worker is not None:  # the figure of the field as simulated, unless the engine shifts it
        call = _run_field_figure_call(scenario, floe_field)
        extra.append(figure_worker.ahead_callback("field", call, _provenance(scenario, "figure")))
    try:
        simulation = simulate(floe_field, bow, model, params, callbacks=[recorder, *extra, *callbacks])
        records = recorder.records()  # the last chunk of records too
        if poses is not None:
            poses.finish(simulation.n_steps)
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
        # where failures happen between contact searches: not in the scenario hash when the profile sets it
        "event_location": params.event_location,
        "event_tolerance_m": params.event_tolerance_m,
    }
    tail = {
        "field_shift_m": float(sum(s["dx_m"] for s in shift)) if shift else 0.0,
        "bow": getattr(bow, "name", "bow"),
        "warnings": set_up_warnings(scenario, bow),
        "wall_time_s": time.perf_counter() - started,
    }
    path = None if contacts_file is None else contacts_file.path
    result = Result(scenario, simulation, records, {**head, **stats, **tail}, contacts_file=path, poses=poses)
    result.summary.update(surge_summary(result))  # only with ship.propulsion (app/surge.py)
    return result


def _simulation_params(scenario: Scenario) -> SimulationParams:
    """The engine's parameters of the resolved `scenario`."""
    ship = scenario.ship
    return SimulationParams(
        step_m=ship.step_m,
        x_start_m=ship.x_start_m,
        x_end_m=ship.x_end_m,
        initial_contact=ship.initial_contact,
        max_pieces=scenario.simulation.max_pieces or MAX_PIECES_DEFAULT,
        max_wall_s=scenario.simulation.max_wall_s,
        event_location=event_location(scenario),
        event_tolerance_m=scenario.simulation.event_tolerance_m or EVENT_TOLERANCE_M,
        **ice_motion_params(scenario),
    )


def _title(scenario: Scenario, what: str) -> str:
    name = scenario.name or (scenario.field.observation or scenario.field.source)
    return f"{what}: {name}, profile {scenario.profile}, seed {scenario.seed}"


def _run_field_figure_call(scenario: Scenario, floe_field: FloeField) -> FigureCall:
    """The plotting call of the run directory's field figure (`field_figure_call`, titled)."""
    return field_figure_call(floe_field, title=_title(scenario, "initial floe field"))


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

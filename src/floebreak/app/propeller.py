"""A propeller analysis of a run's or study's cusps: read the run directories (`floebreak.output.run_files`),
analyse (`floebreak.propeller.pipeline.analyse_cusp_loads`, pure), draw (`floebreak.plotting.propeller`) and
write (`floebreak.output.propeller_files`). Files: docs/propeller.md "Output directory"."""

from __future__ import annotations

import os
from collections.abc import Callable
from pathlib import Path
from typing import Any

from floebreak.app.figure_calls import drawn, figures_in_worker
from floebreak.app.inputs import measured_series, resolve_fem_tables
from floebreak.config.analysis import propeller_defaults
from floebreak.errors import InputError
from floebreak.io.jsonable import jsonable
from floebreak.output.propeller_files import write_propeller_files
from floebreak.output.run_files import cusp_files, load_cusps, parquet_metadata, read_resolved_scenario
from floebreak.propeller import pipeline
from floebreak.propeller.design_loads import design_load_tables
from floebreak.propeller.iceclass import WEIBULL_SHAPE
from floebreak.propeller.load_models import check_choice
from floebreak.propeller.loads import get_load_model, load_model_names
from floebreak.propeller.pipeline import PropellerResult
from floebreak.propeller.ruleform import result_load_count
from floebreak.propeller.runs import RunInputs, run_inputs, transit_distance_m
from floebreak.propeller.spectra import DENSITY_THRESHOLD_PER_KNM, figure_curves, spectrum_curves
from floebreak.propeller.spread import BAND_KEYS


def run_transit_distance_m(run_dir: str | os.PathLike[str]) -> float | None:
    """A run directory's transit distance in ice [m] (`floebreak.propeller.runs.transit_distance_m`), None
    without the metadata."""
    run_dir = Path(run_dir)
    return transit_distance_m(
        parquet_metadata(run_dir / "field.parquet"), parquet_metadata(run_dir / "pieces.parquet")
    )


def read_runs(root, *, pool: bool = False, **basis_overrides) -> RunInputs:
    """Cusps and exposures of the run directory `root`, or of every run below it (`load_cusps`); pooling
    and `basis_overrides` as `floebreak.propeller.runs.run_inputs`."""
    root = Path(root)
    cusps = load_cusps(root)
    runs = {}
    for run, path in cusp_files(root).items():
        run_dir = path.parent
        runs[run] = (run_dir, read_resolved_scenario(run_dir), run_transit_distance_m(run_dir))
    return run_inputs(root, cusps, runs, pool=pool, **basis_overrides)


def read_run_dirs(run_dirs, *, pool: bool = False, **basis_overrides) -> RunInputs:
    """Cusps and exposures of the given run directories (e.g. a voyage's complete runs; run_id = the
    directory's name); pooling and `basis_overrides` as `read_runs`."""
    import pyarrow as pa

    run_dirs = [Path(d) for d in run_dirs]
    if not run_dirs:
        raise InputError("run_dirs", "no run directory", allowed="one or more run directories")
    cusps = pa.concat_tables([load_cusps(d) for d in run_dirs])
    runs = {d.name: (d, read_resolved_scenario(d), run_transit_distance_m(d)) for d in run_dirs}
    return run_inputs(run_dirs[0].parent, cusps, runs, pool=pool, **basis_overrides)


def analyse_propeller(
    cusps,
    *,
    load_model: str = "milling",
    fem_table=None,
    torque_csv=None,
    torque_unit: str | None = None,
    flip_measured_sign: bool = False,
    **options,
) -> PropellerResult:
    """`floebreak.propeller.pipeline.analyse_cusp_loads` with its input files read first: `fem_table` as
    `floebreak.app.inputs.resolve_fem_tables` (paths, {pitch: path}, FemTables; the shipped tables for the
    FEM load model without one), `torque_csv` a path or a `TorqueSeries` (`measured_series`, with
    `torque_unit` and `flip_measured_sign`). Other `options`: those of the pure function."""
    fem = (
        fem_table is not None
        or get_load_model(check_choice("load_model", load_model, load_model_names())).needs_tables
    )
    return pipeline.analyse_cusp_loads(
        cusps,
        load_model=load_model,
        fem_tables=resolve_fem_tables(fem_table) if fem else None,
        measured=measured_series(torque_csv, torque_unit, flip_measured_sign),
        **options,
    )


def analyse_runs(inputs: RunInputs, **options) -> PropellerResult:
    """`analyse_propeller` of `inputs` (`read_runs`, `read_run_dirs`) with their exposures; the runs'
    scenario profile sets the load model and transport unless given (`config.analysis.propeller_defaults`)."""
    load_model, transport = propeller_defaults(inputs.profile)
    options.setdefault("load_model", load_model)
    options.setdefault("transport", transport)
    return analyse_propeller(inputs.cusps, exposures=inputs.exposures, **options)


def write_propeller(
    result: PropellerResult,
    out_dir: str | os.PathLike[str],
    *,
    overwrite: bool = False,
    record: dict | None = None,
    progress: Callable[[str, int, int], None] | None = None,
    figure_worker: Any = None,
) -> Path:
    """Draw `result`'s figures, compute its design-load tables and write both with it to the new directory
    `out_dir` atomically; return it. `record` adds to the provenance (e.g. the input files); `progress`
    as `floebreak.output.propeller_files.write_propeller_files`'. `figure_worker`
    (`floebreak.output.run_directory.figure_worker`): a process that draws the figures while the tables are
    written (the same files)."""
    calls = propeller_figure_calls(result)
    options = {"overwrite": overwrite, "record": record, "progress": progress}
    options["extra_summary"] = {"design_loads": design_load_summary(result)}
    if figure_worker is not None:
        alongside = figures_in_worker(calls, figure_worker)
        return write_propeller_files(result, out_dir, {}, figures_alongside=alongside, **options)
    return write_propeller_files(result, out_dir, drawn(calls), **options)


def design_load_summary(result: PropellerResult) -> list[dict] | None:
    """The summary's "design_loads" entry: per propeller the design-load table with the basis of every
    number (`floebreak.propeller.design_loads.design_load_tables`); None without a polar class."""
    tables = design_load_tables(result)
    if not tables:
        return None
    bands = {
        (b["propeller"], b["pitch_percent"]): b
        for b in (result.summary.get("spread") or {}).get("design_torque_kn_m", [])
        if "median" in b
    }
    out = [table.as_dict() for table in tables]
    for entry in out:  # the design torque's median and 5–95 % band over the transport's draws and fields
        for row in entry["rows"]:
            found = bands.get((entry["propeller"], row["pitch_percent"]))
            row["design_torque_band_kn_m"] = None if found is None else [found[k] for k in BAND_KEYS]
    return out


def propeller_figures(result: PropellerResult) -> dict[str, Any]:
    """The analysis' figures (file name → matplotlib Figure), drawn by `floebreak.plotting.propeller`."""
    return drawn(propeller_figure_calls(result))


def propeller_figure_calls(result: PropellerResult) -> dict[str, Any]:
    """The analysis' figures as plain data (file name → `floebreak.output.figure_process.FigureCall` of
    `floebreak.plotting.propeller`), to draw here or in a figure worker."""

    def call(function: str, *args) -> tuple:
        return ("propeller", function, args, {})

    out = {}
    o = result.options
    if result.tables:  # the FEM tables' curves; the milling model has none
        out["volume_loads.png"] = call("plot_volume_loads", result.tables, o["interpolation"], o["beyond"])
    # the spectra as plain arrays: a figure process then imports no xarray (nor dask, where installed)
    curves = {quantity: spectrum_curves(result.spectra, quantity) for quantity in ("force", "torque")}
    for quantity, name in (("force", "load"), ("torque", "torque")):
        shown = figure_curves(quantity, _magnitudes_per_run(result, quantity))  # bins from the data
        for log in (False, True):
            scale = "log" if log else "linear"
            out[f"{name}_spectrum_{scale}.png"] = call("plot_spectrum", shown, log)
    torque = {p: result.amplitudes(p).torque_nm for p in result.pitches}
    out["rule_form.png"] = call("plot_rule_form", torque, result.exceedance, WEIBULL_SHAPE[o["weibull"]])
    if result.measured is not None:
        m = result.measured
        for log in (False, True):
            out[f"torque_comparison_{'log' if log else 'linear'}.png"] = call(
                "plot_measured_comparison",
                *(m.edges_knm, m.density_per_knm, curves["torque"], log, DENSITY_THRESHOLD_PER_KNM),
            )
    if result.rule is not None:
        force = {p: result.amplitudes(p).force_n for p in result.pitches}
        n_ice = result_load_count(result).n_ice_low
        out["ice_class_exceedance.png"] = (
            "propeller",
            "plot_rule_exceedance",
            (force, torque, result.rule, WEIBULL_SHAPE[o["weibull"]]),
            {"n_ice": n_ice},
        )
    return out


def _magnitudes_per_run(result: PropellerResult, quantity: str) -> dict[float, dict[str, Any]]:
    """{pitch: {run_id: |F| [kN] or |Q| [kN·m]}} of the result's cusps, as the spectra files count them."""
    import numpy as np

    run_id = np.asarray(result.loads["run_id"])
    out = {}
    for pitch in result.pitches:
        amp = result.amplitudes(pitch)
        values = np.abs(np.asarray(amp.force_n if quantity == "force" else amp.torque_nm, dtype=float)) / 1e3
        out[float(pitch)] = {str(r): values[run_id == r] for r in np.unique(run_id)}
    return out


def propeller_analysis(
    cusps,
    out_dir: str | os.PathLike[str],
    *,
    overwrite: bool = False,
    pool: bool = False,
    speed_m_s: float | None = None,
    fraction_reaching: float | None = None,
    n_propellers: int | None = None,
    **options,
) -> Path:
    """Analyse and write: `cusps` is a run or study directory (its transit distances and scenarios give
    the rates; several runs need equal scenarios but for seed and field, or `pool=True`) or a table
    (`options["exposures"]` then gives the rates). `options`: those of `analyse_propeller`; a directory's
    scenario profile sets the load model and transport unless given (`config.analysis.propeller_defaults`)."""
    record: dict[str, Any] = {}
    if isinstance(cusps, str | os.PathLike):
        inputs = read_runs(
            cusps,
            pool=pool,
            speed_m_s=speed_m_s,
            fraction_reaching=fraction_reaching,
            n_propellers=n_propellers,
        )
        if "exposures" in options:
            raise InputError("exposures", "given with a directory, which has its own", allowed="one of them")
        options["exposures"] = inputs.exposures
        load_model, transport = propeller_defaults(inputs.profile)
        options.setdefault("load_model", load_model)
        options.setdefault("transport", transport)
        cusps = inputs.cusps
        record = {"runs": sorted(inputs.run_dirs), "pooled_differing_keys": list(inputs.differing_keys)}
        if inputs.missing_transit:
            record["no_transit_distance"] = list(inputs.missing_transit)
    fem = options.get("fem_table")
    record["fem_tables"] = None if fem is None else jsonable(fem if isinstance(fem, dict) else str(fem))
    record["torque_csv"] = None if options.get("torque_csv") is None else str(options["torque_csv"])
    result = analyse_propeller(cusps, **options)
    return write_propeller(result, out_dir, overwrite=overwrite, record=record)

"""Write a shaft analysis (floebreak.shaft.analysis.ShaftResult, its torque densities, summary and figures)
into a directory, atomically. Computing the analysis and drawing its figures are `floebreak.app.shaft`'s.

Files (docs/shaft.md): shaft_series.nc / .csv (time series per excitation case), shaft_spectra.nc / .csv
(probability densities of load, shaft and measured torque on common bins), modes.csv, rainflow.csv (the
shaft torque's rainflow histogram), summary.json and figures/. NetCDF through xarray's public
``Dataset.to_netcdf`` with CF-1.8 attributes and UDUNITS units; the spectra as spectra.nc of the propeller
analysis (a ``torque_knm`` bin-centre coordinate with CF bounds ``torque_knm_bounds(torque_knm, nv)``,
densities in ``kN-1 m-1``). Every file carries the provenance record (`floebreak.io.provenance`): the
summary's ``provenance`` key, a NetCDF ``provenance`` attribute (JSON), a CSV ``# provenance:`` line.
"""

from __future__ import annotations

import json
import os
from collections.abc import Callable, Mapping
from contextlib import AbstractContextManager, nullcontext
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from floebreak.io.atomic import atomic_directory
from floebreak.io.figures import save_figures
from floebreak.io.jsonable import jsonable
from floebreak.io.provenance import provenance
from floebreak.io.writers import write_csv, write_json, write_netcdf

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from floebreak.shaft.analysis import ShaftResult
    from floebreak.shaft.fatigue import RainflowHistogram


def series_dataset(result: ShaftResult):
    """CF-1.8 dataset of the load and shaft torque per case [kN m] over time [s]."""
    import xarray as xr

    line = result.line
    drive = {}
    if result.rpm is not None:
        drive = {
            "rpm": (("case", "time"), result.rpm, {"units": "1/min", "long_name": "propeller speed"}),
            "motor_torque": (
                ("case", "time"),
                result.motor_torque_n_m / 1e3,
                {"units": "kN m", "long_name": "motor torque (torque-limited PI speed controller)"},
            ),
        }
    return xr.Dataset(
        data_vars={
            **drive,
            "load_torque": (
                ("case", "time"),
                result.load_torque_n_m / 1e3,
                {
                    "units": "kN m",
                    "long_name": "propeller load torque: mean hydrodynamic plus blade-impact ice torque",
                },
            ),
            "shaft_torque": (
                ("case", "time"),
                result.shaft_torque_n_m / 1e3,
                {
                    "units": "kN m",
                    "long_name": f"shaft torque at station {result.station}",
                },
            ),
        },
        coords={
            "time": (
                "time",
                result.time_s,
                {
                    "units": "s",
                    "standard_name": "time",
                    "axis": "T",
                    "long_name": "time since the series start",
                },
            ),
            "case": (
                "case",
                np.asarray(result.cases, dtype=np.int32),
                {
                    "units": "1",
                    "long_name": "ice excitation case (physics-notes §7.3, as recalled)",
                },
            ),
        },
        attrs={
            "Conventions": "CF-1.8",
            "title": "floebreak propeller load torque and shaft torque",
            "source": "floebreak shaft analysis (openTorsion shaft-line model)",
            "shaft_line": line.name,
            "station": result.station,
            "rpm": line.rpm,
            "blades": result.blades,
            "ship_speed_m_s": result.speed_m_s,
            "mean_torque_knm": line.mean_torque() / 1e3,
            "samples_per_blade_passage": result.samples_per_blade_passage,
            "shaft_model": result.model,
        },
    )


def drive_columns(result: ShaftResult) -> dict[str, np.ndarray]:
    """The drive model's propeller rpm and motor torque [kN m] per case (none for the linear model)."""
    if result.rpm is None:
        return {}
    out = {f"rpm_case{c}": r for c, r in zip(result.cases, result.rpm, strict=True)}
    for c, q in zip(result.cases, result.motor_torque_n_m, strict=True):
        out[f"motor_torque_knm_case{c}"] = q / 1e3
    return out


def spectra_dataset(edges_knm, densities: dict[str, dict]):
    """CF-1.8 dataset of the torque densities [kN-1 m-1] on common bins: the ``torque_knm`` coordinate
    (bin centres, signed torque) with its CF bounds ``torque_knm_bounds(torque_knm, nv)``, as spectra.nc."""
    import xarray as xr

    edges_knm = np.asarray(edges_knm, dtype=float)
    return xr.Dataset(
        data_vars={
            f"density_{name}": (
                "torque_knm",
                d["density"],
                {"units": "kN-1 m-1", "long_name": f"probability density of the {name} torque"},
            )
            for name, d in densities.items()
        },
        coords={
            "torque_knm": (
                "torque_knm",
                0.5 * (edges_knm[:-1] + edges_knm[1:]),
                {"units": "kN m", "long_name": "torque Q, bin centre", "bounds": "torque_knm_bounds"},
            ),
            "torque_knm_bounds": (
                ("torque_knm", "nv"),
                np.stack([edges_knm[:-1], edges_knm[1:]], axis=1),
                {"units": "kN m"},
            ),
        },
        attrs={"Conventions": "CF-1.8", "title": "floebreak torque spectra: propeller load, shaft, measured"},
    )


def shaft_provenance(result: ShaftResult, summary: Mapping[str, Any]) -> dict[str, Any]:
    """The provenance record of a shaft analysis: versions plus its line, station, model and inputs."""
    return provenance(
        command="shaft_analysis",
        shaft_line=result.line.name,
        shaft_line_source=result.line.source,
        station=result.station,
        shaft_model=result.model,
        cases=list(result.cases),
        run_dir=summary.get("run_dir"),
        measured_source=summary.get("measured_source"),
    )


def _write_tables(tmp: Path, result: ShaftResult, series, edges, densities, rainflow, note: str) -> None:
    """shaft_series.csv, shaft_spectra.csv, modes.csv and rainflow.csv, each with the provenance `note`."""
    write_csv(
        tmp / "shaft_series.csv",
        {
            "time_s": result.time_s,
            **{
                k.replace("load_", "load_torque_knm_").replace("shaft_", "shaft_torque_knm_"): v
                for k, v in series.items()
                if k != "measured"
            },
            **drive_columns(result),
        },
        [
            f"floebreak shaft analysis: line {result.line.name}, station {result.station}",
            "load = hydrodynamic + ice torque at the propeller; shaft = torque at the station",
            f"shaft model: {result.model}"
            + (", rpm = propeller speed [1/min]" if result.rpm is not None else ""),
            note,
        ],
    )
    write_csv(
        tmp / "shaft_spectra.csv",
        {
            "torque_bin_lower_knm": edges[:-1],
            "torque_bin_upper_knm": edges[1:],
            **{f"density_per_knm_{k}": d["density"] for k, d in densities.items()},
        },
        ["probability densities of the torque series on common bins [1/(kN m)]", note],
    )
    write_csv(
        tmp / "modes.csv",
        {
            "mode": np.arange(1, result.modes.frequency_hz.size + 1),
            "frequency_hz": result.modes.frequency_hz,
            "damping_ratio": result.modes.damping_ratio,
            **{f"shape_{e.name}": result.modes.shapes[:, i] for i, e in enumerate(result.line.elements)},
        },
        ["free-free torsional modes of the shaft line; shapes: angle amplitude, largest = 1", note],
    )
    if rainflow is not None:
        write_csv(
            tmp / "rainflow.csv",
            {
                "range_lower_knm": rainflow.range_edges_n_m[:-1] / 1e3,
                "range_upper_knm": rainflow.range_edges_n_m[1:] / 1e3,
                "cycles": rainflow.counts,
            },
            [
                f"rainflow cycles (ASTM E1049-85, package rainflow; half cycles 0.5) of the shaft torque at "
                f"{result.station}, excitation case {result.cases[0]}",
                note,
            ],
        )


def write_shaft_files(
    result: ShaftResult,
    out_dir: str | os.PathLike[str],
    *,
    series: Mapping[str, np.ndarray],
    edges: np.ndarray,
    densities: Mapping[str, dict],
    summary: dict[str, Any],
    figures: Mapping[str, Figure],
    rainflow: RainflowHistogram | None = None,
    overwrite: bool = False,
    progress: Callable[[str, int, int], None] | None = None,
    figures_alongside: Callable[[Path], AbstractContextManager] | None = None,
) -> Path:
    """Write `result`, its torque `series` [kN m] (``load_case<n>``, ``shaft_case<n>``, ``measured``), their
    densities on the common bin `edges`, the `rainflow` histogram, `summary` (with the provenance added)
    and `figures` (file name → Figure, in ``figures/``) to `out_dir` atomically; return it. `progress(stage,
    done, total)`, if given, is told after the NetCDF files, the CSV tables and each figure.
    `figures_alongside(folder)` instead of `figures`: a context that draws the figures into the new
    directory ``figures/`` while the tables are written (e.g. in other processes), done when it exits."""
    total = 2 + len(figures)
    summary = dict(summary)
    with atomic_directory(out_dir, overwrite=overwrite) as tmp:
        tmp = Path(tmp)
        prov = shaft_provenance(result, summary)
        prov_text = json.dumps(jsonable(prov), sort_keys=True)
        engine = ""
        with nullcontext() if figures_alongside is None else figures_alongside(tmp / "figures"):
            for ds, name in (
                (series_dataset(result), "shaft_series.nc"),
                (spectra_dataset(edges, densities), "shaft_spectra.nc"),
            ):
                ds.attrs["provenance"] = prov_text
                engine = write_netcdf(ds, tmp / name)
            if progress is not None:
                progress("NetCDF files", 1, total)
            _write_tables(tmp, result, series, edges, densities, rainflow, f"provenance: {prov_text}")
            if progress is not None:
                progress("CSV tables", 2, total)
        if figures_alongside is None:
            save_figures(figures, tmp / "figures", progress, done=2)
        summary["netcdf_engine"] = engine
        summary["provenance"] = prov
        written = sorted(p.relative_to(tmp).as_posix() for p in tmp.rglob("*") if p.is_file())
        summary["files"] = [*written, "summary.json"]
        write_json(tmp / "summary.json", summary)
    return Path(out_dir)

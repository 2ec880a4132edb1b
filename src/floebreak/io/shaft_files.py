"""Write a shaft analysis (floebreak.shaft.analysis.ShaftResult) into a directory, atomically.

Files (docs/shaft.md): shaft_series.nc / .csv (time series per excitation case), shaft_spectra.nc / .csv
(probability densities of load, shaft and measured torque on common bins), modes.csv, summary.json and
figures/. NetCDF through xarray's public ``Dataset.to_netcdf`` with CF-1.8 attributes and units.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from floebreak.errors import InputError
from floebreak.io.atomic import atomic_directory
from floebreak.io.figures import save_figure
from floebreak.io.jsonable import jsonable
from floebreak.io.writers import write_csv, write_json, write_netcdf
from floebreak.propeller.measured import TorqueSeries, read_torque_csv
from floebreak.propeller.spectra import DENSITY_THRESHOLD_PER_KNM
from floebreak.shaft.analysis import (
    ShaftResult,
    run_cusp_inputs,
    run_ship_speed_m_s,
    shaft_response,
    torque_densities,
)
from floebreak.shaft.excitation import EXCITATION_CASES
from floebreak.shaft.line import load_shaft_line


def series_dataset(result: ShaftResult):
    """CF-1.8 dataset of the load and shaft torque per case [kN m] over time [s]."""
    import xarray as xr

    line = result.line
    return xr.Dataset(
        data_vars={
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
        },
    )


def spectra_dataset(edges_knm, densities: dict[str, dict]):
    import xarray as xr

    centre = 0.5 * (edges_knm[:-1] + edges_knm[1:])
    return xr.Dataset(
        data_vars={
            f"density_{name}": (
                "bin",
                d["density"],
                {"units": "1/(kN m)", "long_name": f"probability density of {name} torque"},
            )
            for name, d in densities.items()
        },
        coords={
            "torque_bin_lower": ("bin", edges_knm[:-1], {"units": "kN m"}),
            "torque_bin_upper": ("bin", edges_knm[1:], {"units": "kN m"}),
            "torque": ("bin", centre, {"units": "kN m", "long_name": "torque bin centre"}),
        },
        attrs={"Conventions": "CF-1.8", "title": "floebreak torque spectra: propeller load, shaft, measured"},
    )


THESIS_MEASURED = {  # thesis §6.2 / Fig. 35, Agulhas II port shaft, 18/12/2019 20:20-20:30
    "range_knm": [-100.0, 400.0],
    "above_threshold_knm": [58.0, 152.0],
    "source": "thesis §6.2 (measured shaft torque, including hydrodynamic torque)",
}


def shaft_summary(result: ShaftResult, densities: dict[str, dict], extra: dict | None = None) -> dict:
    """The summary.json content: line, modes, excitation, Q_peak per case, spectra ranges."""
    line = result.line
    elements = []
    for e, j in zip(line.elements, line.inertias_kg_m2, strict=True):
        elements.append(
            {
                "name": e.name,
                "inertia_kg_m2": j,
                "shaft": e.shaft,
                "stiffness_n_m_per_rad": e.stiffness_n_m_per_rad,
                "damping_ratio": e.damping_ratio,
            }
        )
    for e, c in zip(elements, line.damping_n_m_s_per_rad, strict=False):
        e["damping_n_m_s_per_rad"] = c
    blade_rate = result.blades * line.rpm / 60.0
    return jsonable(
        {
            "shaft_line": {
                "name": line.name,
                "source": line.source,
                "elements": elements,
                "propeller_dry_inertia_kg_m2": line.elements[-1].inertia_kg_m2,
                "entrained_water_fraction": line.entrained_water_fraction,
                "speed_control_bandwidth_hz": line.speed_control_bandwidth_hz,
                "speed_control_damping_ratio": line.speed_control_damping_ratio,
                "hydrodynamic_damping": line.hydrodynamic_damping,
            },
            "operating_point": {
                "rpm": line.rpm,
                "mean_torque_knm": line.mean_torque() / 1e3,
                "rated_power_w": line.rated_power_w,
                "blade_passage_frequency_hz": blade_rate,
            },
            "modes_free_free": {
                "natural_frequencies_hz": result.modes.frequency_hz,
                "damping_ratios": result.modes.damping_ratio,
                "mode_shapes": result.modes.shapes,
                "frequency_over_blade_passage": result.modes.frequency_hz / blade_rate,
            },
            "station": result.station,
            "excitation": {
                "cases": {c: EXCITATION_CASES[c].__dict__ for c in result.cases},
                "note": "rule cases as recalled (physics-notes §7.3): verify against the rule text",
                "n_cusps": result.n_cusps,
                "overlap": result.overlap,
                "ship_speed_m_s": result.speed_m_s,
                "samples_per_blade_passage": result.samples_per_blade_passage,
                "time_step_s": float(result.time_s[1] - result.time_s[0]) if result.time_s.size > 1 else None,
                "duration_s": float(result.time_s[-1]) if result.time_s.size else 0.0,
            },
            "q_peak_knm": {
                c: {
                    (k[:-4] + "_knm" if k.endswith("_n_m") else k): (v / 1e3 if k.endswith("_n_m") else v)
                    for k, v in p.items()
                }
                for c, p in result.peaks().items()
            },
            "spectra_above_threshold_knm": {
                n: {"intervals": d["intervals_knm"], "envelope": d["envelope_knm"]}
                for n, d in densities.items()
            },
            "density_threshold_per_knm": DENSITY_THRESHOLD_PER_KNM,
            "thesis_measured": THESIS_MEASURED,
            **(extra or {}),
        }
    )


def write_shaft_analysis(
    result: ShaftResult,
    out_dir: str | os.PathLike[str],
    *,
    measured: TorqueSeries | None = None,
    bin_knm: float = 10.0,
    overwrite: bool = False,
    extra_summary: dict | None = None,
) -> Path:
    """Write `result` (and the comparison with `measured`) to `out_dir` atomically; return it."""
    from floebreak.plotting import shaft as figs

    primary = result.cases[0]
    series = {f"load_case{c}": q / 1e3 for c, q in zip(result.cases, result.load_torque_n_m, strict=True)}
    series |= {f"shaft_case{c}": q / 1e3 for c, q in zip(result.cases, result.shaft_torque_n_m, strict=True)}
    if measured is not None:
        series["measured"] = measured.torque_nm / 1e3
    edges, densities = torque_densities(series, bin_knm)
    summary = shaft_summary(result, densities, extra_summary)
    with atomic_directory(out_dir, overwrite=overwrite) as tmp:
        tmp = Path(tmp)
        engine = write_netcdf(series_dataset(result), tmp / "shaft_series.nc")
        write_netcdf(spectra_dataset(edges, densities), tmp / "shaft_spectra.nc")
        write_csv(
            tmp / "shaft_series.csv",
            {
                "time_s": result.time_s,
                **{
                    k.replace("load_", "load_torque_knm_").replace("shaft_", "shaft_torque_knm_"): v
                    for k, v in series.items()
                    if k != "measured"
                },
            },
            [
                f"floebreak shaft analysis: line {result.line.name}, station {result.station}",
                "load = mean hydrodynamic + ice torque at the propeller; shaft = torque at the station",
            ],
        )
        write_csv(
            tmp / "shaft_spectra.csv",
            {
                "torque_bin_lower_knm": edges[:-1],
                "torque_bin_upper_knm": edges[1:],
                **{f"density_per_knm_{k}": d["density"] for k, d in densities.items()},
            },
            ["probability densities of the torque series on common bins [1/(kN m)]"],
        )
        write_csv(
            tmp / "modes.csv",
            {
                "mode": np.arange(1, result.modes.frequency_hz.size + 1),
                "frequency_hz": result.modes.frequency_hz,
                "damping_ratio": result.modes.damping_ratio,
                **{f"shape_{e.name}": result.modes.shapes[:, i] for i, e in enumerate(result.line.elements)},
            },
            ["free-free torsional modes of the shaft line; shapes: angle amplitude, largest = 1"],
        )
        _write_figures(figs, tmp / "figures", result, primary, series, edges, densities, measured)
        summary["netcdf_engine"] = engine
        written = sorted(p.relative_to(tmp).as_posix() for p in tmp.rglob("*") if p.is_file())
        summary["files"] = [*written, "summary.json"]
        write_json(tmp / "summary.json", summary)
    return Path(out_dir)


def _write_figures(figs, fig_dir: Path, result, primary, series, edges, densities, measured) -> None:
    fig_dir.mkdir()
    t = result.time_s
    save_figure(
        figs.plot_series(
            t,
            {f"propeller load, case {primary}": series[f"load_case{primary}"]},
            f"propeller load torque Q(t) = Q_mean + Q_ice(t), case {primary}",
        ),
        fig_dir / "excitation_series.png",
    )
    save_figure(
        figs.plot_series(
            t,
            {
                "propeller load": series[f"load_case{primary}"],
                f"shaft at {result.station}": series[f"shaft_case{primary}"],
            },
            f"propeller load and shaft torque, case {primary}",
        ),
        fig_dir / "shaft_series.png",
    )
    save_figure(
        figs.plot_modes(
            [e.name for e in result.line.elements], result.modes.frequency_hz, result.modes.shapes
        ),
        fig_dir / "mode_shapes.png",
    )
    for log in (False, True):
        scale = "log" if log else "linear"
        shown = {
            "propeller load": densities[f"load_case{primary}"]["density"],
            f"shaft ({result.station})": densities[f"shaft_case{primary}"]["density"],
        }
        save_figure(
            figs.plot_densities(
                edges, shown, log, DENSITY_THRESHOLD_PER_KNM, f"torque spectra, case {primary}"
            ),
            fig_dir / f"shaft_spectrum_{scale}.png",
        )
        if measured is not None:
            compared = {
                f"simulated shaft ({result.station}), case {primary}": shown[f"shaft ({result.station})"],
                "measured shaft": densities["measured"]["density"],
            }
            save_figure(
                figs.plot_densities(
                    edges,
                    compared,
                    log,
                    DENSITY_THRESHOLD_PER_KNM,
                    f"shaft torque: simulated vs measured ({Path(measured.source).name})",
                ),
                fig_dir / f"shaft_comparison_{scale}.png",
            )


@dataclass(frozen=True)
class PreparedShaftAnalysis:
    """A computed shaft analysis, validated and ready to write (`write`)."""

    result: ShaftResult
    measured: TorqueSeries | None
    extra_summary: dict

    def write(self, out_dir: str | os.PathLike[str], overwrite: bool = False) -> Path:
        return write_shaft_analysis(
            self.result,
            out_dir,
            measured=self.measured,
            overwrite=overwrite,
            extra_summary=self.extra_summary,
        )


def shaft_analysis_of_run(
    run_dir: str | os.PathLike[str],
    shaft_line: str | os.PathLike[str],
    *,
    station: str | None = None,
    rpm: float | None = None,
    speed_m_s: float | None = None,
    mean_torque_knm: float | None = None,
    cases=(1, 2, 3, 4),
    fem_table=None,
    pitch_percent: float | None = None,
    torque_csv: str | os.PathLike[str] | None = None,
    interpolation: str = "newton",
    beyond: str = "power_law",
    samples_per_blade_passage: int = 40,
) -> PreparedShaftAnalysis:
    """Read a run's cusps, the shaft line and the measured series; compute the shaft analysis. Nothing is
    written (write with ``.write(out_dir)``). The ship speed: `speed_m_s`, else the run's resolved
    scenario's ``ship.speed_m_s``, else an InputError asking for it."""
    line = load_shaft_line(shaft_line)
    if speed_m_s is None:
        speed_m_s = run_ship_speed_m_s(run_dir)
        if speed_m_s is None:
            raise InputError(
                "speed_m_s",
                f"not given, and {str(run_dir)!r} has no ship.speed_m_s in scenario.resolved.toml",
                allowed="--speed-m-s SPEED (ship speed > 0 m/s)",
            )
    measured = None if torque_csv is None else read_torque_csv(torque_csv)
    cusps = run_cusp_inputs(
        run_dir, fem_table=fem_table, pitch_percent=pitch_percent, interpolation=interpolation, beyond=beyond
    )
    result = shaft_response(
        cusps["bow_x_m"],
        cusps["torque_n_m"],
        cusps["thickness_m"],
        line,
        speed_m_s=speed_m_s,
        rpm=rpm,
        station=station,
        cases=tuple(cases or ()),
        mean_torque_n_m=None if mean_torque_knm is None else 1e3 * mean_torque_knm,
        samples_per_blade_passage=samples_per_blade_passage,
    )
    extra = {
        "run_dir": Path(run_dir).name,
        "fem_pitch_percent": cusps["pitch_percent"],
        "interpolation": interpolation,
        "beyond": beyond,
        "measured_source": None if measured is None else measured.source,
    }
    return PreparedShaftAnalysis(result, measured, extra)

"""Writing a propeller analysis (a `floebreak.propeller.pipeline.PropellerResult` and its figures, drawn by
`floebreak.plotting.propeller`): CSV tables, the CF-1.8 NetCDF spectra, figures and summary.json, as one
atomic directory (`floebreak.io.atomic.atomic_directory`: on any error nothing appears). Reading, analysing
and drawing are `floebreak.app.propeller`'s. Files: docs/propeller.md "Output directory".
"""

from __future__ import annotations

import json
import os
from collections.abc import Callable, Mapping
from contextlib import AbstractContextManager, nullcontext
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from floebreak.io.atomic import atomic_directory
from floebreak.io.figures import save_figures
from floebreak.io.jsonable import jsonable
from floebreak.io.provenance import provenance
from floebreak.io.writers import write_csv, write_json, write_netcdf

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from floebreak.propeller.pipeline import PropellerResult


def _per_cusp_columns(loads: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """The per-cusp table in the CSV's units (kN, kN·m, kJ)."""
    out = {}
    for k, v in loads.items():
        if k.startswith("force_n_"):
            out["force_kn_" + k[len("force_n_") :]] = v / 1e3
        elif k.startswith("torque_nm_"):
            out["torque_knm_" + k[len("torque_nm_") :]] = v / 1e3
        elif k == "kinetic_energy_j":
            out["kinetic_energy_kj"] = v / 1e3
        else:
            out[k] = v
    return out


def _class_rows(class_tables) -> dict[str, np.ndarray]:
    rows: dict[str, list] = {}
    for run, table in class_tables.items():
        rows.setdefault("run_id", []).extend([run] * len(table["class_index"]))
        for k, v in table.items():
            rows.setdefault(k, []).extend(np.asarray(v).tolist())
    return {k: np.asarray(v, dtype=object) if k == "run_id" else np.asarray(v) for k, v in rows.items()}


def _spectrum_rows(ds, quantity: str) -> dict[str, np.ndarray]:
    """Long table of one spectrum: pitch, bin edges, density and (with a time base) counts per hour/km."""
    unit = "kn" if quantity == "force" else "knm"
    bounds = ds[f"{quantity}_{unit}_bounds"].values  # the CF bin bounds of `propeller.spectra`
    edges = np.r_[bounds[:, 0], bounds[-1:, 1]] if bounds.size else np.zeros(1)
    n_bins, pitches = edges.size - 1, ds["pitch"].values
    columns = {
        "pitch_percent": np.repeat(pitches.astype(float), n_bins),
        f"{quantity}_lower_{unit}": np.tile(edges[:-1], pitches.size),
        f"{quantity}_upper_{unit}": np.tile(edges[1:], pitches.size),
        f"density_per_{unit}": ds[f"{quantity}_density"].values.reshape(-1),
    }
    for per in ("hour", "km"):
        name = f"{quantity}_rate_per_{per}"
        if name in ds:
            columns[f"loads_per_{per}_per_propeller"] = ds[name].values.reshape(-1)
    return columns


def _exceedance_rows(exceedance: dict, quantity: str) -> dict[str, np.ndarray]:
    unit = "kn" if quantity == "force" else "knm"
    parts = [(k, v) for k, v in exceedance.items() if k.startswith(quantity + "_")]
    return {
        "pitch_percent": np.concatenate(
            [np.full(v["level"].size, float(k.split("_p")[-1])) for k, v in parts]
        ),
        f"{quantity}_level_{unit}": np.concatenate([v["level"] for _, v in parts]),
        "exceedances_per_hour_per_propeller": np.concatenate([v["per_hour"] for _, v in parts]),
        "exceedances_per_km_per_propeller": np.concatenate([v["per_km"] for _, v in parts]),
    }


def _write_tables(result: PropellerResult, tmp: Path) -> None:
    o = result.options
    write_csv(
        tmp / "cusp_loads.csv",
        _per_cusp_columns(result.loads),
        [
            f"floebreak propeller loads per cusp in transit order; interpolation={o['interpolation']}, "
            f"beyond={o['beyond']} (beyond_table_* columns), volume_basis={o['volume_basis']}",
            "force_kn/torque_knm signed as in the FEM table; kinetic_energy_kj = 1/2 rho V v^2 (thesis Eqs. "
            "27-28); loads_per_propeller = fraction_reaching / n_propellers (empty without a time base)",
        ],
    )
    write_csv(
        tmp / "volume_classes.csv",
        _class_rows(result.class_tables),
        ["cusp volume classes by bounding-box volume (thesis Alg. 1, Tables 10/11 structure)"],
    )
    for quantity, name in (("force", "load"), ("torque", "torque")):
        write_csv(
            tmp / f"{name}_spectrum.csv",
            _spectrum_rows(result.spectra, quantity),
            ["probability densities mean over runs; loads per hour/km on one propeller, all runs pooled"],
        )
        if result.exceedance:
            write_csv(
                tmp / f"{name}_exceedance.csv",
                _exceedance_rows(result.exceedance, quantity),
                ["number of loads >= level on one propeller per hour in ice and per km of transit"],
            )
    if result.measured is not None:
        m = result.measured
        write_csv(
            tmp / "measured_torque_spectrum.csv",
            {
                "torque_lower_knm": m.edges_knm[:-1],
                "torque_upper_knm": m.edges_knm[1:],
                "density_per_knm": m.density_per_knm,
            },
            [f"probability density of the measured torque series {m.series.source}"],
        )


def write_propeller_files(
    result: PropellerResult,
    out_dir: str | os.PathLike[str],
    figures: Mapping[str, Figure],
    *,
    overwrite: bool = False,
    record: dict | None = None,
    extra_summary: Mapping | None = None,
    progress: Callable[[str, int, int], None] | None = None,
    figures_alongside: Callable[[Path], AbstractContextManager] | None = None,
) -> Path:
    """Write `result` and its `figures` (file name → Figure, saved in ``figures/``) to the new directory
    `out_dir` atomically and return it. `record` adds to the provenance (e.g. the input files),
    `extra_summary` to summary.json (e.g. the design-load tables the application layer computed).
    `progress(stage, done, total)`, if given, is told after the tables and after each figure.
    `figures_alongside(folder)` instead of `figures`: a context that draws the figures into the new
    directory ``figures/`` while the tables are written (e.g. in other processes), done when it exits."""
    prov = provenance(command="propeller_analysis", **jsonable(result.options), **(record or {}))
    ds = result.spectra.copy()
    ds.attrs.update(
        {
            "title": "floebreak propeller-ice load and torque spectra",
            "institution": "floebreak",
            "source": "floebreak propeller analysis (thesis chapter 6; docs/propeller.md)",
            "references": "docs/propeller.md",
            "interpolation": result.options["interpolation"],
            "beyond_table": result.options["beyond"],
            "volume_basis": result.options["volume_basis"],
            "provenance": json.dumps(jsonable(prov), sort_keys=True),
        }
    )
    summary = {"provenance": prov, **result.summary, **(extra_summary or {})}
    with atomic_directory(out_dir, overwrite=overwrite) as tmp:
        tmp = Path(tmp)
        with nullcontext() if figures_alongside is None else figures_alongside(tmp / "figures"):
            _write_tables(result, tmp)
            summary["netcdf_engine"] = write_netcdf(ds, tmp / "spectra.nc")
            if progress is not None:
                progress("tables", 1, 1 + len(figures))
        if figures_alongside is None:
            save_figures(figures, tmp / "figures", progress, done=1)
        written = sorted(p.relative_to(tmp).as_posix() for p in tmp.rglob("*") if p.is_file())
        summary["files"] = [*written, "summary.json"]
        write_json(tmp / "summary.json", summary)
    return Path(out_dir)

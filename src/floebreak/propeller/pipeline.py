"""Propeller analysis of a run or study: cusps → force/torque per cusp → spectra, comparison, rule check.

The one entry point with side effects. Everything is validated before anything is written; the output
directory is written atomically (floebreak.io.atomic.atomic_directory). See docs/propeller.md.
"""

from __future__ import annotations

import csv
import json
import math
import os
from pathlib import Path
from typing import Any

import numpy as np

from floebreak.errors import InputError, require_range
from floebreak.io.atomic import atomic_directory
from floebreak.io.figures import save_figure
from floebreak.io.provenance import provenance
from floebreak.propeller.cusps import (
    DEFAULT_CLASS_EDGES_M3,
    box_dimensions,
    check_class_edges,
    class_means,
    cusp_columns,
    kinetic_energy_j,
    load_cusps,
    volume_class,
)
from floebreak.propeller.fem import FemTable, resolve_fem_tables
from floebreak.propeller.iceclass import WEIBULL_SHAPE, check_polar_class, ur_i3_loads
from floebreak.propeller.interpolation import VolumeInterpolant, check_options
from floebreak.propeller.measured import TorqueSeries, read_torque_csv
from floebreak.propeller.spec import PropellerSpec, propeller_pitch_angle_deg
from floebreak.propeller.spectra import (
    DENSITY_THRESHOLD_PER_KNM,
    bin_edges,
    density,
    envelope,
    fitting_width,
    ranges_above,
    spectra_dataset,
)

VOLUME_BASES = ("box", "actual")

__all__ = ["load_cusps", "load_spectra", "propeller_analysis", "propeller_loads", "torque_ranges_above"]


def _pitch_label(pitch: float) -> str:
    return f"p{pitch:g}"


def propeller_loads(
    columns: dict[str, np.ndarray],
    tables: dict[float, FemTable],
    *,
    interpolation: str = "newton",
    beyond: str = "clamp",
    volume_basis: str = "box",
    cusp_speed_m_s: float = 3.0,
) -> dict[str, np.ndarray]:
    """Per-cusp table (pure): box dimensions, class, kinetic energy, and per pitch force [N], torque [N·m]
    and whether the volume lies beyond the table. `columns` as returned by `cusp_columns`."""
    check_options(interpolation, beyond)
    if volume_basis not in VOLUME_BASES:
        raise InputError(
            "volume_basis",
            f"unknown value {volume_basis!r}",
            value=volume_basis,
            allowed=", ".join(VOLUME_BASES),
        )
    longer, shorter, box_volume = box_dimensions(
        columns["bbox_length_m"], columns["bbox_width_m"], columns["thickness_m"]
    )
    v = box_volume if volume_basis == "box" else columns["volume_m3"]
    out: dict[str, np.ndarray] = {
        "run_id": columns["run_id"],
        "area_m2": columns["area_m2"],
        "thickness_m": columns["thickness_m"],
        "volume_m3": columns["volume_m3"],
        "bbox_longer_m": longer,
        "bbox_shorter_m": shorter,
        "box_volume_m3": box_volume,
        "kinetic_energy_j": kinetic_energy_j(columns["volume_m3"], cusp_speed_m_s),
    }
    for pitch, table in tables.items():
        label = _pitch_label(pitch)
        f = VolumeInterpolant.through_origin(table.volume_m3, table.force_n, interpolation, beyond)
        q = VolumeInterpolant.through_origin(table.volume_m3, table.torque_nm, interpolation, beyond)
        out[f"force_n_{label}"] = f(v)
        out[f"torque_nm_{label}"] = q(v)
        out[f"beyond_table_{label}"] = v > table.max_volume_m3
    return out


def load_spectra(
    loads: dict[str, np.ndarray],
    tables: dict[float, FemTable],
    force_bin_kn: float = 10.0,
    torque_bin_knm: float = 10.0,
    attrs: dict | None = None,
):
    """Spectra dataset (pure) of |F| [kN] and |Q| [kN·m] per pitch from a `propeller_loads` table: each
    run's density and their mean, every run weighted equally (thesis Figs. 32–33; see `spectra_dataset`)."""
    run_id = loads["run_id"]
    runs = sorted(set(run_id.tolist()))
    force_kn = {}
    torque_knm = {}
    for pitch in tables:
        label = _pitch_label(pitch)
        f, q = loads[f"force_n_{label}"], loads[f"torque_nm_{label}"]
        force_kn[pitch] = {r: np.abs(f[run_id == r]) / 1e3 for r in runs}
        torque_knm[pitch] = {r: np.abs(q[run_id == r]) / 1e3 for r in runs}
    return spectra_dataset(force_kn, torque_knm, force_bin_kn, torque_bin_knm, attrs=attrs)


def torque_ranges_above(ds, threshold_per_knm: float = DENSITY_THRESHOLD_PER_KNM) -> dict[str, dict]:
    """Per pitch label ("p0", "p95"): the torque intervals [kN·m] whose run-averaged density exceeds
    `threshold_per_knm` (the thesis' "probability density above 0.1 %", §6.2) and their envelope."""
    q_edges = np.r_[ds["torque_bin_lower_knm"].values, ds["torque_bin_upper_knm"].values[-1:]]
    out = {}
    for pitch in ds["pitch"].values:
        intervals = ranges_above(q_edges, ds["torque_density"].sel(pitch=pitch).values, threshold_per_knm)
        out[_pitch_label(float(pitch))] = {"intervals_knm": intervals, "envelope_knm": envelope(intervals)}
    return out


def _write_csv(path: Path, columns: dict[str, Any], comments: list[str] = ()) -> None:
    names = list(columns)
    n = len(next(iter(columns.values()))) if columns else 0
    with open(path, "w", newline="", encoding="utf-8") as handle:
        for line in comments:
            handle.write(f"# {line}\n")
        writer = csv.writer(handle)
        writer.writerow(names)
        for i in range(n):
            row = []
            for name in names:
                value = columns[name][i]
                if isinstance(value, bool | np.bool_):
                    row.append("true" if value else "false")
                elif isinstance(value, float | np.floating):
                    row.append("" if not math.isfinite(value) else format(float(value), ".10g"))
                else:
                    row.append(str(value))
            writer.writerow(row)


def _clean(value: Any) -> Any:
    if isinstance(value, dict):
        return {str(k): _clean(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_clean(v) for v in value]
    if isinstance(value, np.ndarray):
        return _clean(value.tolist())
    if isinstance(value, np.generic):
        return _clean(value.item())
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, Path):
        return str(value)
    return value


def _finite_range(values) -> list[float] | None:
    values = np.asarray(values, dtype=float)
    values = values[np.isfinite(values)]
    return [float(values.min()), float(values.max())] if values.size else None


def _write_netcdf(ds, path: Path) -> str:
    """NetCDF4 via h5netcdf (needs h5py); NetCDF3 via scipy when h5netcdf/h5py are missing.

    NetCDF4 is written through xarray's h5netcdf store, which is what ``ds.to_netcdf(path,
    engine="h5netcdf")`` does for a dataset of numpy arrays (the same bytes), without asking dask which
    scheduler is active (``to_netcdf`` and the store's default write lock do: that imports dask and
    dask.distributed, ≈ 0.4 s, although nothing here is a dask array). The store gets xarray's HDF5 lock
    (HDF5 calls serialised across threads, as by default). A dataset with dask (chunked) variables still
    goes through ``to_netcdf``.
    """
    import importlib.util

    has_h5 = all(importlib.util.find_spec(m) is not None for m in ("h5netcdf", "h5py"))
    engine = "h5netcdf" if has_h5 else "scipy"
    if engine != "h5netcdf" or any(v.chunks is not None for v in ds.variables.values()):
        ds.to_netcdf(path, engine=engine)
        return engine
    try:  # xarray internals: if a future xarray moves them, fall back to the public call
        from xarray.backends import H5NetCDFStore
        from xarray.backends.locks import HDF5_LOCK
    except ImportError:
        ds.to_netcdf(path, engine=engine)
        return engine
    store = H5NetCDFStore.open(os.fspath(path), mode="w", lock=HDF5_LOCK)  # a str path, as to_netcdf
    try:
        ds.dump_to_store(store)  # numpy variables are written as they are stored
    finally:
        store.close()
    return engine


def propeller_analysis(
    cusps,
    out_dir: str | os.PathLike[str],
    *,
    fem_table=None,
    torque_csv: str | os.PathLike[str] | None = None,
    polar_class: str | None = None,
    propeller: PropellerSpec = PropellerSpec(),  # noqa: B008 - frozen dataclass, immutable default
    interpolation: str = "newton",
    beyond: str = "clamp",
    overwrite: bool = False,
    volume_basis: str = "box",
    volume_class_edges_m3=DEFAULT_CLASS_EDGES_M3,
    cusp_speed_m_s: float = 3.0,
    force_bin_kn: float = 10.0,
    torque_bin_knm: float = 10.0,
    torque_unit: str | None = None,
    flip_measured_sign: bool = False,
    weibull: str = "open",
) -> Path:
    """Write the propeller analysis of `cusps` (a dict of arrays / pyarrow.Table, or a run or study
    directory) to `out_dir` and return it. See docs/propeller.md for the files."""
    # ---- validate everything before writing anything
    if isinstance(cusps, str | os.PathLike):
        cusps = load_cusps(cusps)
    columns = cusp_columns(cusps)
    if not isinstance(propeller, PropellerSpec):
        raise InputError("propeller", f"{type(propeller).__name__} is not a PropellerSpec")
    check_options(interpolation, beyond)
    edges_m3 = check_class_edges(volume_class_edges_m3)
    require_range("cusp_speed_m_s", cusp_speed_m_s, low=0.0, low_inclusive=True, unit="m/s")
    require_range("force_bin_kn", force_bin_kn, low=0.0, unit="kN")
    require_range("torque_bin_knm", torque_bin_knm, low=0.0, unit="kN m")
    if weibull not in WEIBULL_SHAPE:
        raise InputError("weibull", f"unknown propeller type {weibull!r}", allowed=", ".join(WEIBULL_SHAPE))
    tables = resolve_fem_tables(fem_table, propeller.pitch_percent)
    rule = ur_i3_loads(propeller, check_polar_class(polar_class)) if polar_class is not None else None
    series: TorqueSeries | None = None
    if torque_csv is not None:
        series = read_torque_csv(torque_csv, torque_unit=torque_unit, flip_sign=flip_measured_sign)

    # ---- compute (pure)
    loads = propeller_loads(
        columns,
        tables,
        interpolation=interpolation,
        beyond=beyond,
        volume_basis=volume_basis,
        cusp_speed_m_s=cusp_speed_m_s,
    )
    loads["volume_class"] = volume_class(loads["box_volume_m3"], edges_m3)
    runs = sorted(set(columns["run_id"].tolist()))
    table_info = {}
    for pitch, table in tables.items():
        label = _pitch_label(pitch)
        f, q = loads[f"force_n_{label}"], loads[f"torque_nm_{label}"]
        table_sign_f = np.sign(np.sum(table.force_n))
        table_sign_q = np.sign(np.sum(table.torque_nm))
        table_info[label] = {
            "pitch_percent": pitch,
            "source": table.source,
            "volume_m3": table.volume_m3,
            "force_n": table.force_n,
            "torque_nm": table.torque_nm,
            "max_volume_m3": table.max_volume_m3,
            "n_beyond_table": int(loads[f"beyond_table_{label}"].sum()),
            "n_without_load": int((~np.isfinite(f)).sum()),
            "n_sign_reversed_force": int(np.sum(np.sign(f[np.isfinite(f)]) == -table_sign_f)),
            "n_sign_reversed_torque": int(np.sum(np.sign(q[np.isfinite(q)]) == -table_sign_q)),
            "force_range_kn": _finite_range(np.abs(f) / 1e3),
            "torque_range_knm": _finite_range(np.abs(q) / 1e3),
        }
        if rule is not None:
            loads[f"exceeds_backward_force_{label}"] = np.abs(f) > rule.backward_force_n
            loads[f"exceeds_forward_force_{label}"] = np.abs(f) > rule.forward_force_n
            loads[f"exceeds_max_torque_{label}"] = np.abs(q) > rule.max_torque_nm
            table_info[label]["rule_exceedances"] = {
                k: int(loads[f"{k}_{label}"].sum())
                for k in ("exceeds_backward_force", "exceeds_forward_force", "exceeds_max_torque")
            }
    prov = provenance(
        command="propeller_analysis",
        interpolation=interpolation,
        beyond=beyond,
        volume_basis=volume_basis,
        fem_tables=[t.source for t in tables.values()],
        torque_csv=None if series is None else series.source,
    )
    ds = load_spectra(
        loads,
        tables,
        force_bin_kn,
        torque_bin_knm,
        attrs={
            "title": "floebreak propeller-ice load and torque spectra",
            "method": "histogram densities of |F| and |Q| per pitch; mean over runs (equal weight per run)",
            "interpolation": interpolation,
            "beyond_table": beyond,
            "volume_basis": volume_basis,
            "provenance": json.dumps(_clean(prov), sort_keys=True),
        },
    )
    simulated_ranges = torque_ranges_above(ds)
    measured = None
    if series is not None:
        q_meas_knm = series.torque_nm / 1e3
        m_edges = bin_edges(q_meas_knm, fitting_width(q_meas_knm, torque_bin_knm))
        m_dens = density(q_meas_knm, m_edges)
        m_intervals = ranges_above(m_edges, m_dens, DENSITY_THRESHOLD_PER_KNM)
        measured = {
            "source": series.source,
            "n_samples": int(series.time_s.size),
            "duration_s": series.duration_s,
            "sign_flipped": bool(flip_measured_sign),
            "torque_range_knm": _finite_range(q_meas_knm),
            "intervals_above_threshold_knm": m_intervals,
            "envelope_above_threshold_knm": envelope(m_intervals),
        }
    class_tables = {
        r: class_means(
            *(
                loads[k][columns["run_id"] == r]
                for k in ("bbox_longer_m", "bbox_shorter_m", "thickness_m", "box_volume_m3")
            ),
            edges_m3,
        )
        for r in runs
    }
    class_tables["ALL"] = class_means(
        loads["bbox_longer_m"],
        loads["bbox_shorter_m"],
        loads["thickness_m"],
        loads["box_volume_m3"],
        edges_m3,
    )

    summary = {
        "provenance": prov,
        "options": {
            "interpolation": interpolation,
            "beyond": beyond,
            "volume_basis": volume_basis,
            "volume_class_edges_m3": edges_m3,
            "cusp_speed_m_s": cusp_speed_m_s,
            "force_bin_kn": ds.attrs["force_bin_width_kn"],  # as used: wider for far loads (`fitting_width`)
            "torque_bin_knm": ds.attrs["torque_bin_width_knm"],
            "density_threshold_per_knm": DENSITY_THRESHOLD_PER_KNM,
            "polar_class": polar_class,
            "weibull": weibull,
        },
        "propeller": {
            **propeller.__dict__,
            "pitch_m": propeller.pitch_m,
            "pitch_angle_07R_deg": propeller_pitch_angle_deg(propeller, "r07"),
            "pitch_angle_thesis_deg": propeller_pitch_angle_deg(propeller, "thesis_r_prop"),
        },
        "n_cusps": int(columns["volume_m3"].size),
        "n_cusps_per_run": {r: int(np.sum(columns["run_id"] == r)) for r in runs},
        "n_runs": len(runs),
        "n_above_last_class_edge": int(np.sum(loads["box_volume_m3"] > edges_m3[-1])),
        "kinetic_energy_kj": {
            "total": float(loads["kinetic_energy_j"].sum() / 1e3),
            "max": float(loads["kinetic_energy_j"].max() / 1e3) if loads["kinetic_energy_j"].size else None,
            "note": "energy (Eqs. 27-28), not comparable with torque (erratum 25)",
        },
        "pitches": table_info,
        "simulated_torque_above_threshold": simulated_ranges,
        "measured_torque": measured,
        "ice_class": None if rule is None else rule.as_dict(),
    }

    # ---- write
    from floebreak.plotting import propeller as figs

    with atomic_directory(out_dir, overwrite=overwrite) as tmp:
        tmp = Path(tmp)
        per_cusp = {}
        for k, v in loads.items():
            if k.startswith("force_n_"):
                per_cusp["force_kn_" + k[len("force_n_") :]] = v / 1e3
            elif k.startswith("torque_nm_"):
                per_cusp["torque_knm_" + k[len("torque_nm_") :]] = v / 1e3
            elif k == "kinetic_energy_j":
                per_cusp["kinetic_energy_kj"] = v / 1e3
            else:
                per_cusp[k] = v
        _write_csv(
            tmp / "cusp_loads.csv",
            per_cusp,
            [
                f"floebreak propeller loads per cusp; interpolation={interpolation}, beyond={beyond} "
                f"(beyond_table_* columns), volume_basis={volume_basis}",
                "force_kn/torque_knm signed as in the FEM table; "
                "kinetic_energy_kj = 1/2 rho V v^2 (thesis Eqs. 27-28)",
            ],
        )
        class_rows: dict[str, list] = {}
        for r, table in class_tables.items():
            n = len(table["class_index"])
            class_rows.setdefault("run_id", []).extend([r] * n)
            for k, v in table.items():
                class_rows.setdefault(k, []).extend(np.asarray(v).tolist())
        _write_csv(
            tmp / "volume_classes.csv",
            {
                k: np.asarray(v, dtype=object) if k == "run_id" else np.asarray(v)
                for k, v in class_rows.items()
            },
            ["cusp volume classes by bounding-box volume (thesis Alg. 1, Tables 10/11 structure)"],
        )
        engine = _write_netcdf(ds, tmp / "spectra.nc")
        summary["netcdf_engine"] = engine
        long = {
            "pitch_percent": [],
            "bin": [],
            "force_bin_lower_kn": [],
            "force_bin_upper_kn": [],
            "force_density_per_kn": [],
            "torque_bin_lower_knm": [],
            "torque_bin_upper_knm": [],
            "torque_density_per_knm": [],
        }
        # each variable read once (an xarray lookup per value cost ≈ 0.2 s for two pitches)
        edges = {
            name: ds[name].values
            for name in (
                "force_bin_lower_kn",
                "force_bin_upper_kn",
                "torque_bin_lower_knm",
                "torque_bin_upper_knm",
            )
        }
        for pitch in ds["pitch"].values:
            force_density = ds["force_density"].sel(pitch=pitch).values
            torque_density = ds["torque_density"].sel(pitch=pitch).values
            for b in ds["bin"].values:
                long["pitch_percent"].append(float(pitch))
                long["bin"].append(int(b))
                for k, values in edges.items():
                    long[k].append(float(values[b]))
                long["force_density_per_kn"].append(float(force_density[b]))
                long["torque_density_per_knm"].append(float(torque_density[b]))
        _write_csv(
            tmp / "spectra.csv",
            {k: np.asarray(v) for k, v in long.items()},
            ["probability densities of |F| and |Q|, mean over runs; see spectra.nc for per-run values"],
        )
        fig_dir = tmp / "figures"
        fig_dir.mkdir()
        save_figure(figs.plot_volume_loads(tables, interpolation, beyond), fig_dir / "volume_loads.png")
        for quantity in ("force", "torque"):
            name = "load" if quantity == "force" else "torque"
            for log in (False, True):
                scale = "log" if log else "linear"
                save_figure(figs.plot_spectrum(ds, quantity, log), fig_dir / f"{name}_spectrum_{scale}.png")
        if series is not None:
            _write_csv(
                tmp / "measured_torque_spectrum.csv",
                {
                    "torque_bin_lower_knm": m_edges[:-1],
                    "torque_bin_upper_knm": m_edges[1:],
                    "density_per_knm": m_dens,
                },
                [f"probability density of the measured torque series {series.source}"],
            )
            for log in (False, True):
                scale = "log" if log else "linear"
                save_figure(
                    figs.plot_measured_comparison(m_edges, m_dens, ds, log, DENSITY_THRESHOLD_PER_KNM),
                    fig_dir / f"torque_comparison_{scale}.png",
                )
        if rule is not None:
            f_by_pitch = {p: loads[f"force_n_{_pitch_label(p)}"] for p in tables}
            q_by_pitch = {p: loads[f"torque_nm_{_pitch_label(p)}"] for p in tables}
            save_figure(
                figs.plot_rule_exceedance(f_by_pitch, q_by_pitch, rule, WEIBULL_SHAPE[weibull]),
                fig_dir / "ice_class_exceedance.png",
            )
        written = sorted(p.relative_to(tmp).as_posix() for p in tmp.rglob("*") if p.is_file())
        summary["files"] = [*written, "summary.json"]
        (tmp / "summary.json").write_text(
            json.dumps(_clean(summary), indent=2, sort_keys=True) + "\n", encoding="utf-8"
        )
        _normal_permissions(tmp)
    return Path(out_dir)


def _normal_permissions(root: Path) -> None:
    """The temporary directory is private (0700); give the finished one the umask's modes."""
    umask = os.umask(0)
    os.umask(umask)
    for path in [root, *root.rglob("*")]:
        path.chmod((0o777 if path.is_dir() else 0o666) & ~umask)

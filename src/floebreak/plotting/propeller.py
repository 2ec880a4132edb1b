"""Propeller figures: volume–load curves (thesis Figs. 30–31), load and torque spectra (Figs. 32–33),
measured vs simulated torque (Fig. 35, A.3), the UR I3 Weibull exceedance overlay and the rule-form fit
with exceedance rates (notes §7.3). Each function takes computed data and returns a Figure."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from floebreak.plotting.common import (
    SPECTRUM_MARGINS_IN,
    add_legend,
    legend_font_pt,
    new_figure,
    page_fonts,
    place_axes,
)
from floebreak.propeller.iceclass import empirical_exceedance, weibull_exceedance
from floebreak.propeller.interpolation import VolumeInterpolant
from floebreak.propeller.rates import weighted_exceedance
from floebreak.propeller.ruleform import fit_rule_form
from floebreak.propeller.spectra import SpectrumCurves, pitch_label

PITCH_COLOURS = ("#4c72b0", "#d62728", "#2ca02c", "#9467bd", "#8c564b")


def _colour(i: int) -> str:
    return PITCH_COLOURS[i % len(PITCH_COLOURS)]


def plot_volume_loads(
    tables, method: str = "newton", beyond: str = "power_law", v_max_m3: float | None = None
) -> Figure:
    """Force and torque vs cusp volume for each 1-D FEM table: points, chosen interpolant (solid), the other
    method (dashed), to 2.5 × the largest table volume so that the policy beyond the table shows; N-D
    tables as points only."""
    with page_fonts(11.0):
        return _draw_volume_loads(tables, method, beyond, v_max_m3)


def _draw_volume_loads(tables, method: str, beyond: str, v_max_m3: float | None) -> Figure:
    figure = Figure(figsize=(11.0, 4.0))
    place_axes(figure, 0.95, 0.62, 0.1, 0.5, columns=2, gap=1.15)  # fixed: see SPECTRUM_MARGINS_IN
    axes = figure.subplots(1, 2)
    other = "pchip" if method == "newton" else "newton"
    top = v_max_m3 or np.nanmax([t.max_volume_m3 for t in tables.values()]) * 2.5
    v = np.linspace(0.0, top, 300)
    for i, (pitch, table) in enumerate(tables.items()):
        for ax, values, scale in ((axes[0], table.force_n, 1e3), (axes[1], table.torque_nm, 1e3)):
            if tuple(table.dimensions) != ("volume",):
                ax.plot(
                    table.volume_m3,
                    values / scale,
                    "o",
                    color=_colour(i),
                    label=f"P = {pitch:g} % (N-D table points)",
                )
                continue
            chosen = VolumeInterpolant.through_origin(table.volume_m3, values, method, beyond)
            alt = VolumeInterpolant.through_origin(table.volume_m3, values, other, beyond)
            ax.plot(v, chosen(v) / scale, color=_colour(i), label=f"P = {pitch:g} % ({method})")
            ax.plot(v, alt(v) / scale, color=_colour(i), ls="--", lw=0.8, label=f"P = {pitch:g} % ({other})")
            ax.plot(np.r_[0.0, table.volume_m3], np.r_[0.0, values] / scale, "o", color=_colour(i))
    for ax, label in ((axes[0], "force F [kN]"), (axes[1], "torque Q [kN m]")):
        ax.axvline(np.nanmax([t.max_volume_m3 for t in tables.values()]), color="0.5", lw=0.6, ls=":")
        ax.set_xlabel("cusp volume V [m³]")
        ax.set_ylabel(label)
        add_legend(ax)
    figure.suptitle(f"Volume–load interpolation through (0, 0); beyond the table: {beyond}")
    return figure


def plot_spectrum(curves: SpectrumCurves, log: bool = False) -> Figure:
    """Probability density of |F| (`curves` of "force") or |Q| ("torque") per pitch, run-averaged
    (`floebreak.propeller.spectra.spectrum_curves`)."""
    figure, ax = new_figure(7.5, 4.0, SPECTRUM_MARGINS_IN)
    quantity = curves.quantity
    unit = "kN" if quantity == "force" else "kN m"
    any_data = False
    for i, (pitch, dens) in enumerate(zip(curves.pitch_percent, curves.density, strict=True)):
        if np.all(~np.isfinite(dens)):
            continue
        any_data = True
        ax.stairs(
            np.nan_to_num(dens), curves.edges, color=_colour(i), label=f"P = {pitch:g} %", fill=False, lw=1.2
        )
    if not any_data:
        ax.text(0.5, 0.5, "no loads", transform=ax.transAxes, ha="center")
    if log and any_data:
        ax.set_yscale("log")
    name = "force |F|" if quantity == "force" else "torque |Q|"
    ax.set_xlabel(f"{name} [{unit}]")
    ax.set_ylabel(f"probability density [1/{unit}]")
    what = "Load" if quantity == "force" else "Torque"
    bins = f"; {len(curves.edges) - 1} bins of {np.diff(curves.edges)[0]:.3g} {unit}" if any_data else ""
    ax.set_title(f"{what} spectrum (mean over {curves.n_runs} run(s){bins})")
    if any_data:
        ax.set_xlim(curves.edges[0], curves.edges[-1])  # the data's range, not from 0
        ax.legend()
    return figure


def plot_measured_comparison(
    measured_edges_knm,
    measured_density,
    torque: SpectrumCurves,
    log: bool = True,
    threshold_per_knm: float = 1e-3,
) -> Figure:
    """Measured shaft-torque density vs simulated |Q| densities (`torque`: the "torque" `SpectrumCurves`;
    thesis Fig. 35 log, Fig. 37 linear)."""
    figure, ax = new_figure(8.0, 4.0)
    ax.stairs(measured_density, measured_edges_knm, color="k", lw=1.4, label="measured (shaft)")
    for i, (pitch, dens) in enumerate(zip(torque.pitch_percent, torque.density, strict=True)):
        if np.any(np.isfinite(dens)):
            label = f"simulated P = {pitch:g} % (|Q|)"
            ax.stairs(np.nan_to_num(dens), torque.edges, color=_colour(i), label=label)
    ax.axhline(threshold_per_knm, color="0.5", ls=":", lw=0.8, label=f"{threshold_per_knm:g} per kN m")
    if log:
        ax.set_yscale("log")
    ax.set_xlabel("torque [kN m]")
    ax.set_ylabel("probability density [1/(kN m)]")
    ax.set_title("Measured vs simulated torque spectra")
    ax.legend(fontsize=8)
    return figure


def plot_rule_exceedance(
    force_n: dict, torque_nm: dict, rule, shape: float = 0.75, n_ice: float | None = None
) -> Figure:
    """Empirical exceedance of |F|/F_b and |Q|/Q_max per pitch and, with the rule's number of loads
    `n_ice` (`floebreak.propeller.ruleform.rule_n_ice`), the rule's exceedance exp(−x^k ln N_ice) (notes
    §7.3), one curve per panel: the rule's, not one per pitch. Without `n_ice` no rule curve is drawn and
    the title says so. One legend for both panels, below them."""
    with page_fonts(11.0):
        return _draw_rule_exceedance(force_n, torque_nm, rule, shape, n_ice)


def _draw_rule_exceedance(force_n: dict, torque_nm: dict, rule, shape: float, n_ice: float | None) -> Figure:
    figure = Figure(figsize=(11.0, 5.0), constrained_layout=True)
    axes = figure.subplots(1, 2)
    for ax, data, cap, label in (
        (axes[0], force_n, rule.backward_force_n, "|F| / F_b"),
        (axes[1], torque_nm, rule.max_torque_nm, "|Q| / Q_max"),
    ):
        x_top = 1.0
        for i, (pitch, values) in enumerate(data.items()):
            v, p = empirical_exceedance(np.abs(values))
            if v.size < 2:
                continue
            x = v / cap
            x_top = max(x_top, float(x.max()))
            ax.step(x, p, where="post", color=_colour(i), label=f"simulated P = {pitch:g} % (n = {v.size})")
        if n_ice is not None:
            xs = np.linspace(0.0, x_top * 1.05, 200)
            ax.plot(
                xs,
                weibull_exceedance(xs, n_ice, shape),
                color="k",
                ls="--",
                lw=0.9,
                label=f"UR I3 exp(−x^{shape:g} ln N_ice), N_ice = {n_ice:.3g}",
            )
            ax.set_ylim(bottom=0.1 / n_ice)  # down to the rule maximum's 1/N_ice, not the curve's tail
        ax.axvline(1.0, color="k", lw=0.8, ls=":", label=f"rule maximum ({rule.polar_class})")
        ax.set_yscale("log")
        ax.set_xlabel(label)
        ax.set_ylabel("P(X ≥ x)")
    handles, labels = axes[0].get_legend_handles_labels()
    unique = dict(zip(labels, handles, strict=True))
    figure.legend(
        list(unique.values()),
        list(unique.keys()),
        loc="outside lower center",
        ncols=2,
        frameon=False,
        fontsize=legend_font_pt(figure),
    )
    title = "Simulated loads against the IACS UR I3 exceedance shape"
    if n_ice is None:
        title += " (no rule curve: the rule's N_ice is not given)"
    figure.suptitle(title)
    return figure


def _exceedance_points(values_knm, weights) -> tuple[np.ndarray, np.ndarray, float]:
    """Sorted |values| > 0, their P(X ≥ value) (weighted: the weights' share at or above) and N (the
    number of values, or the sum of the weights)."""
    values_knm = np.abs(np.asarray(values_knm, dtype=float))
    if weights is None:
        v, p = empirical_exceedance(values_knm)
        return v[v > 0], p[v > 0], float(np.sum(v > 0))
    w = np.asarray(weights, dtype=float)
    keep = np.isfinite(values_knm) & (values_knm > 0) & (w > 0)
    v, w = values_knm[keep], w[keep]
    levels = np.sort(v)
    return levels, weighted_exceedance(v, w, levels) / w.sum(), float(w.sum())


def plot_rule_form(amplitudes: dict, exceedance: dict, rule_shape: float = 0.75, weights=None) -> Figure:
    """Left: empirical P(X ≥ x) of |Q| per pitch, the fitted rule form exp(−(x/x_max)^k ln N) and the
    rule's shape (k = 0.75 open, 1.0 ducted) through the same x_max (notes §7.3). Right: exceedances per
    hour on one propeller (`exceedance`: tables of `analyse_propeller`, empty without a time base).

    amplitudes: {pitch_percent or case name: torque [N·m] per cusp}; weights: None, or the same keys with
    the loads each cusp stands for (a weighted fit and empirical exceedance, N = Σ weights)."""
    with page_fonts(11.0):
        return _draw_rule_form(amplitudes, exceedance, rule_shape, weights)


def _draw_rule_form(amplitudes: dict, exceedance: dict, rule_shape: float, weights) -> Figure:
    figure = Figure(figsize=(11.0, 4.5), constrained_layout=True)
    axes = figure.subplots(1, 2)
    for i, (pitch, values) in enumerate(amplitudes.items()):
        w = None if weights is None else weights[pitch]
        v, p, n = _exceedance_points(np.asarray(values, dtype=float) / 1e3, w)
        name = pitch if isinstance(pitch, str) else f"P = {pitch:g} %"
        key = pitch if isinstance(pitch, str) else pitch_label(float(pitch))
        table = exceedance.get(f"torque_{key}")
        # the counted rates need no fit; a table of zero rates (no loads) has nothing to draw on a log axis
        if table is not None and np.any(np.asarray(table["per_hour"], dtype=float) > 0):
            axes[1].step(table["level"], table["per_hour"], where="post", color=_colour(i), label=name)
        if v.size < 10 or np.ptp(v) <= 0:
            continue
        axes[0].step(v, p, where="post", color=_colour(i), label=f"simulated {name} (n = {v.size})")
        fit = fit_rule_form(np.abs(values) / 1e3, weights=w)
        x = np.linspace(0.0, v.max() * 1.2, 200)
        x_max = fit.x_max(n)
        axes[0].plot(
            x, fit.exceedance(x), color=_colour(i), ls="--", lw=0.9, label=f"fit k = {fit.shape_k:.2f}"
        )
        rule = np.exp(-((x / x_max) ** rule_shape) * np.log(n))
        axes[0].plot(x, rule, color=_colour(i), ls=":", lw=0.9, label=f"rule shape k = {rule_shape:g}")
    axes[0].set_yscale("log")
    axes[0].set_xlabel("torque |Q| [kN m]")
    axes[0].set_ylabel("P(X ≥ x)")
    if axes[0].lines:
        add_legend(axes[0])
    else:
        axes[0].text(
            0.5, 0.5, "no fit: fewer than 10 distinct loads", transform=axes[0].transAxes, ha="center"
        )
    axes[1].set_xlabel("torque level [kN m]")
    axes[1].set_ylabel("exceedances per hour\n(one propeller) [1/h]")
    if axes[1].lines:
        axes[1].set_yscale("log")
        add_legend(axes[1])
    else:
        timed = any(key.startswith("torque_") for key in exceedance)
        text = "no loads" if timed else "no time base (transit distance unknown)"
        axes[1].text(0.5, 0.5, text, transform=axes[1].transAxes, ha="center")
    figure.suptitle("Torque exceedance against the rule form (fitted by maximum likelihood)")
    return figure

"""Spectra of a run: crushing forces at the bow (thesis Fig. 13) and cusp volumes (thesis Fig. 17)."""

from __future__ import annotations

import numpy as np

from floebreak.plotting.common import CUSP_COLOUR, SPECTRUM_MARGINS_IN, new_figure


def _density_bars(ax, values, bin_width, colour, label):
    """Histogram of the probability density of `values` (bins of `bin_width` from 0) as filled stairs,
    with a legend entry `label`; "no data" and no legend for no values (a run without cusps)."""
    values = np.asarray(values, dtype=float)
    if values.size == 0:
        ax.text(0.5, 0.5, "no data", transform=ax.transAxes, ha="center")
        return
    top = max(values.max(), bin_width)
    density, edges = np.histogram(values, bins=np.arange(0.0, top + bin_width, bin_width), density=True)
    ax.stairs(density, edges, fill=True, facecolor=colour, edgecolor="k", linewidth=0.3, label=label)
    ax.legend()


def plot_crushing_force_spectrum(crushing_force_n, label: str = "floebreak", bin_width_kn: float = 100.0):
    """Probability density of the crushing force per contact evaluation (thesis Fig. 13), in kN."""
    figure, ax = new_figure(7.0, 4.0, SPECTRUM_MARGINS_IN)
    _density_bars(ax, np.asarray(crushing_force_n) / 1e3, bin_width_kn, "#4c72b0", label)
    ax.set_xlabel("crushing force F_c [kN]")
    ax.set_ylabel("probability density [1/kN]")
    ax.set_title("Crushing-force spectrum at the bow")
    return figure


def plot_cusp_volume_spectrum(volumes_m3, label: str = "cusps", bin_width_m3: float = 1.0):
    """Probability density of cusp volumes (thesis Fig. 17 style)."""
    figure, ax = new_figure(7.0, 4.0, SPECTRUM_MARGINS_IN)
    _density_bars(ax, volumes_m3, bin_width_m3, CUSP_COLOUR, f"{label} (n = {len(volumes_m3)})")
    ax.set_xlabel("cusp volume V [m³]")
    ax.set_ylabel("probability density [1/m³]")
    ax.set_title("Cusp-volume spectrum")
    return figure

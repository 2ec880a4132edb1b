"""The terminal tables and lines of the commands: a run's summary, a propeller analysis (spectra, rule form,
design loads, model) and a shaft analysis."""

from __future__ import annotations

import math
from pathlib import Path

from rich.markup import escape
from rich.table import Table

from floebreak.cli.common import console, err_console


def summary_table(summary: dict, label: str) -> Table:
    table = Table(title=label)
    table.add_column("quantity")
    table.add_column("value", justify="right")
    rows = (
        ("floes (initial)", "n_floes_initial", "{:d}"),
        (r"initial ice area \[m²]", "initial_ice_area_m2", "{:.1f}"),
        ("cusps n_cusp", "n_cusps", "{:d}"),
        (r"cusp area A_cusp^tot \[m²]", "cusp_area_m2", "{:.1f}"),
        (r"mean cusp volume \[m³]", "mean_cusp_volume_m3", "{:.2f}"),
        ("flipped n_flip", "n_flipped", "{:d}"),
        (r"flipped area A_flip^tot \[m²]", "flipped_area_m2", "{:.1f}"),
        (r"remaining ice area \[m²]", "remaining_ice_area_m2", "{:.1f}"),
        ("area balance (rel. error)", "area_balance_rel_error", "{:.1e}"),
        (r"max crushing force \[MN]", "crushing_force_max_n", "{:.2f}"),
        (r"wall time \[s]", "wall_time_s", "{:.1f}"),
    )
    for name, key, fmt in rows:
        value = summary.get(key)
        if key == "crushing_force_max_n" and value is not None:
            value = value / 1e6
        text = "–" if value is None or value != value else fmt.format(value)
        table.add_row(name, text)
    return table


def fmt(value, spec: str) -> str:
    return "–" if value is None or value != value else format(value, spec)


def propeller_table(summary: dict) -> Table:
    """Per pitch: cusps with a load, beyond the FEM table, the |Q| ranges with density > 0.1 % per kN·m
    (thesis §6.2) and the maximum |Q|."""
    options = summary["options"]
    from floebreak.propeller.loads import get_load_model

    model = get_load_model(options.get("load_model", "fem"))
    if model.needs_tables:
        beyond = f"beyond table: {options['beyond']}"
        title = f"propeller spectra ({model.label}, {options['interpolation']}, {beyond})"
    else:
        title = f"propeller spectra ({model.label})"
    table = Table(title=title)
    for name in (r"pitch \[%]", "cusps", "beyond table", r"|Q| density > 0.1 %/kN·m \[kN·m]"):
        table.add_column(name, justify="left" if "density" in name else "right")
    table.add_column(r"max |Q| \[kN·m]", justify="right")
    for label, info in summary["pitches"].items():
        intervals = summary["simulated_torque_above_threshold"][label]["intervals_knm"]
        ranges = "–" if not intervals else f"{intervals[0][0]:g}–{intervals[-1][1]:g}"
        if len(intervals) > 1:  # bins below the threshold inside the envelope
            ranges += f" ({len(intervals)} parts)"
        q_range = info["torque_range_knm"]
        table.add_row(
            f"{info['pitch_percent']:g}",
            str(summary["n_cusps"] - info["n_without_load"]),
            f"{info['n_beyond_table']} ({100 * info['fraction_beyond_table']:.0f} %)",
            ranges,
            "–" if q_range is None else f"{q_range[1]:.0f}",
        )
    return table


def rule_form_table(summary: dict) -> Table | None:
    """Per pitch: the rule-form fit of |Q| (k with 95 % interval against the rule's k) and the expected
    largest |Q| per hour and over the operating profile (notes §7.3)."""
    rule_form = summary.get("rule_form") or {}
    table = Table(title=f"rule form P(Q ≥ q) = exp(−(q/q_max)^k ln N) fitted to |Q|, {MEAN_PROPELLER}")
    for name in (
        r"pitch \[%]",
        "k (95 % CI)",
        "rule k",
        r"fitted |Q| \[kN·m]",
        r"q_max per h \[kN·m]",
        r"q_max profile, mean propeller \[kN·m]",
    ):
        table.add_column(name, justify="right")
    rows = 0
    for label, info in summary["pitches"].items():
        fit = (rule_form.get(label) or {}).get("torque_knm") or {}
        if "k" not in fit:
            continue
        rows += 1
        table.add_row(
            f"{info['pitch_percent']:g}",
            f"{fit['k']:.2f} ({fit['k_ci95'][0]:.2f}–{fit['k_ci95'][1]:.2f})",
            f"{fit['rule_k']:g}",
            "–" if not fit.get("validity_range") else "{:.0f}–{:.0f}".format(*fit["validity_range"]),
            fmt(fit.get("x_max_per_hour"), ".0f"),
            fmt(fit.get("x_max_lifetime"), ".0f"),
        )
    return table if rows else None


MEAN_PROPELLER = "all cusps, mean propeller"
WHICH_DESIGN_TORQUE = (
    "q_max profile (rule-form table): the fit to all cusps at the mean propeller's rate; design ice torque Q "
    "(design-load tables): per propeller, its own cusps and rate (x_max over the profile), else its largest "
    "simulated load"
)


def design_load_tables(summary: dict) -> list[Table]:
    """Per propeller, one column per pitch: the design ice torque and blade force against the rule's
    Q_max and F_b, their ratios and the simulated blade impacts against N_ice, both per blade (the basis:
    `design_basis_lines`). Quantities as rows, so that the table fits 80 columns."""
    out = []
    for entry in summary.get("design_loads") or []:
        table = Table(title=f"design loads, {entry['propeller']}, against IACS UR I3 {entry['polar_class']}")
        table.add_column("quantity", overflow="fold")
        for row in entry["rows"]:
            table.add_column(f"pitch {row['pitch_percent']:g} %", justify="right", overflow="fold")
        table.add_column("unit", overflow="fold")
        absent = summary.get("no_load_reason")  # zero loads for want of cusps: say so, not 0
        for label, key, spec, unit in DESIGN_ROWS:
            cells = [absent if absent and key in SIMULATED else fmt(row[key], spec) for row in entry["rows"]]
            table.add_row(label, *cells, unit)
            if key == "design_torque_kn_m" and any(r.get("design_torque_band_kn_m") for r in entry["rows"]):
                bands = [band_cell(r.get("design_torque_band_kn_m")) for r in entry["rows"]]
                table.add_row("  median (5–95 %)", *bands, unit)
        origin = []
        for row in entry["rows"]:
            basis = row["basis"]["design Q"]
            n_sim = basis.split(" simulated loads")[0].rsplit(" ", 1)[-1]
            origin.append(
                "x_max over profile, this propeller"
                if basis.startswith("rule-form")
                else f"largest of {n_sim}"
            )
        table.add_row("design values from", *origin, "")
        out.append(table)
    return out


def band_cell(band) -> str:
    """[p5, median, p95] as "median (p5–p95)", "–" without."""
    return "–" if not band else f"{band[1]:.0f} ({band[0]:.0f}–{band[2]:.0f})"


def spread_line(summary: dict) -> str | None:
    """Loads per hour on one propeller as median and 5–95 % band (summary.json "spread"), None without."""
    spread = summary.get("spread") or {}
    rate = spread.get("loads_per_hour_per_propeller")
    if not rate:
        return None
    draws = "draws of the flow transport's parameters" if spread.get("transport") == "flow" else "draw"
    return (
        f"loads per hour on one propeller over {spread['n_runs']} field(s) × {spread['n_draws_per_run']} "
        f"{draws}: median {rate['median']:.0f}, 5–95 % {rate['p5']:.0f}–{rate['p95']:.0f} "
        f"({rate['n_samples']} samples)"
    )


SIMULATED = {
    "design_torque_kn_m",
    "torque_ratio",
    "design_force_kn",
    "force_ratio",
    "blade_impacts_per_hour",
    "blade_impacts_profile",
    "impacts_ratio_low",
    "impacts_ratio_high",
}
DESIGN_ROWS = (  # label, key of summary.json's design_loads rows, format, unit
    ("design ice torque Q", "design_torque_kn_m", ".0f", "kN·m"),
    ("rule Q_max", "rule_max_torque_kn_m", ".0f", "kN·m"),
    ("Q / Q_max", "torque_ratio", ".2f", "-"),
    ("design blade force F", "design_force_kn", ".0f", "kN"),
    ("rule F_b (backward)", "rule_backward_force_kn", ".0f", "kN"),
    ("F / F_b", "force_ratio", ".2f", "-"),
    ("blade impacts per hour", "blade_impacts_per_hour", ".0f", "1/h per blade"),
    ("rule cycles per hour, k1 low", "rule_blade_cycles_per_hour_low", ".0f", "1/h per blade"),
    ("rule cycles per hour, k1 high", "rule_blade_cycles_per_hour_high", ".0f", "1/h per blade"),
    ("blade impacts over profile", "blade_impacts_profile", ".3g", "per blade"),
    ("rule N_ice, k1 low", "rule_n_ice", ".3g", "per blade"),
    ("rule N_ice, k1 high", "rule_n_ice_high", ".3g", "per blade"),
    ("impacts / N_ice, k1 low", "impacts_ratio_low", ".2f", "-"),
    ("impacts / N_ice, k1 high", "impacts_ratio_high", ".2f", "-"),
)


def design_basis_lines(summary: dict) -> list[str]:
    """The basis of the design-load tables' numbers, each distinct text once; the design values' by kind
    (extrapolated, or why not), the counts stripped (full texts per row: summary.json "design_loads")."""
    seen: dict[str, None] = {}
    for entry in summary.get("design_loads") or []:
        for row in entry["rows"]:
            for key in ("rule Q_max", "rule F_b", "rule N_ice", "blade impacts"):
                seen.setdefault(f"{key}: {row['basis'][key]}", None)
            for key in ("design Q", "design F"):
                text = row["basis"][key]
                if text.startswith("rule-form"):
                    text = "rule-form x_max over the operating profile's loads (notes §7.3)"
                else:
                    text = "largest simulated load (not extrapolated" + text.split("(not extrapolated", 1)[1]
                seen.setdefault(f"design values: {text}", None)
    return list(seen)


def model_line(summary: dict) -> str:
    """The per-cusp torque model and which cusps reach a propeller (fractions per propeller)."""
    model = summary.get("load_model") or {}
    transport = summary.get("transport") or {}
    rule = transport.get("rule")
    fraction = transport.get("fraction_reaching")
    reach = "–" if fraction is None else f"{fraction:.3g}"
    if rule in ("hull", "flow"):
        per = ", ".join(f"{f:.3g}" for f in transport.get("fraction_reaching_per_propeller", []))
        reach = f"{reach} (transport model; per propeller {per})"
    elif rule == "override":
        reach += " (override)"
    else:
        reach += " (every cusp)"
    placement = f" ({model['placement']})" if model.get("placement") else ""
    return (
        f"per-cusp loads: {model.get('name', '–')} model{placement}; fraction of cusps reaching a propeller: "
        f"{reach}; rated torque {model.get('rated_torque_knm', math.nan):.1f} kN·m"
    )


def print_propeller_summary(summary: dict, folder: Path, quiet: bool) -> None:
    """The propeller summary table, the time base, warnings (always) and the files written."""
    if not quiet:
        console.print(propeller_table(summary))
        rule_table = rule_form_table(summary)
        if rule_table is not None:
            console.print(rule_table)
        for table in design_load_tables(summary):
            console.print(table)
        for line in design_basis_lines(summary):
            console.print(f"  {line}", highlight=False, soft_wrap=True)
        if rule_table is not None and summary.get("design_loads"):
            console.print(f"  {WHICH_DESIGN_TORQUE}", highlight=False, soft_wrap=True)
        if summary.get("ice_class") is None:
            console.print("design-load table: add --polar-class (e.g. PC5)", highlight=False)
        console.print(model_line(summary), highlight=False, soft_wrap=True)
        rates = summary.get("rates")
        if rates:
            console.print(
                f"time base: {rates['transit_m']:.0f} m of transit, {rates['hours_in_ice']:.3f} h in ice; "
                f"{rates['loads_per_hour_per_propeller']:.0f} loads per hour and "
                f"{rates['loads_per_km_per_propeller']:.0f} per km on one propeller",
                highlight=False,
            )
        if spread_line(summary):
            console.print(spread_line(summary), highlight=False, soft_wrap=True)
        for label, info in (summary.get("rule_form") or {}).items():
            miner = info.get("miner") if isinstance(info, dict) else None
            if miner:
                life = miner["damage_lifetime"]
                over = "" if life is None else f", {life:.3g} over the operating profile"
                console.print(
                    f"Miner sum ({miner['quantity']}, pitch {label[1:]} %): "
                    f"{miner['damage_per_hour']:.3g} per hour{over}",
                    highlight=False,
                )
    for warning in summary.get("warnings", []):
        err_console.print(f"[bold yellow]warning:[/] {escape(warning)}", soft_wrap=True, highlight=False)
    console.print(
        f"written: {folder}/ (spectra.nc, load_/torque_spectrum.csv, *_exceedance.csv, cusp_loads.csv, "
        "summary.json, figures/)",
        soft_wrap=True,
        highlight=False,
    )


def print_pooling(inputs) -> None:
    n_runs = len(inputs.run_dirs)
    differing = f" (differing in {', '.join(inputs.differing_keys)})" if inputs.differing_keys else ""
    if n_runs > 1:
        console.print(f"pooled {n_runs} runs{differing}", highlight=False)


def shaft_tables(summary: dict) -> tuple[Table, Table]:
    """The shaft line's design numbers (first natural frequency, blade-passage frequency, resonance margin,
    Miner's damage) and, per excitation case, Q_peak, the shaft minimum, the drive's min rpm and peak
    motor torque. Columns fold instead of cutting when the output is piped (80 columns)."""
    resonance, fatigue = summary["resonance"], summary["fatigue"]
    margin = min(min(row) for row in resonance["margin"])
    inside = margin < resonance["required_margin"]
    if fatigue["damage"] is not None:
        damage = (
            f"{fatigue['damage']:.3g} ({fatigue['histogram']['n_cycles']:g} cycles, case {fatigue['case']})"
        )
    else:
        damage = "no S–N curve given" if fatigue["sn_curve"] is None else fatigue["note"]
    line = Table(title=f"shaft line {summary['shaft_line']['name']}, station {summary['station']}")
    line.add_column("quantity", overflow="fold")
    line.add_column("value", justify="right", overflow="fold")
    line.add_column("unit", overflow="fold")
    op = summary["operating_point"]
    line.add_row(
        "first natural frequency", f"{summary['modes_free_free']['natural_frequencies_hz'][0]:.2f}", "Hz"
    )
    line.add_row(
        f"blade-passage frequency at {op['rpm']:g} rpm", f"{op['blade_passage_frequency_hz']:.2f}", "Hz"
    )
    line.add_row(
        f"resonance margin (required {100 * resonance['required_margin']:.0f} %)",
        f"{100 * margin:.1f}" + (" [bold yellow]WARNING[/]" if inside else ""),
        "%",
    )
    line.add_row("Miner's damage, shaft torque", escape(damage), "-")
    cases = Table(title=f"shaft torque per excitation case ({summary['shaft_model']} model)")
    for name in ("case", r"Q_peak \[kN·m]", r"shaft min \[kN·m]", r"min rpm \[1/min]", r"peak motor \[kN·m]"):
        cases.add_column(name, justify="right", overflow="fold")
    drive = (summary.get("drive") or {}).get("cases", {})
    for case, peak in summary["q_peak_knm"].items():
        d = drive.get(case) or {}
        cases.add_row(
            case,
            fmt(peak["q_peak_knm"], ".0f"),
            fmt(peak["q_min_knm"], ".0f"),
            fmt(d.get("min_rpm"), ".1f"),
            fmt(d.get("peak_motor_torque_knm"), ".0f"),
        )
    return line, cases

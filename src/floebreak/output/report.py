"""A self-contained HTML report of a run directory: summary, figures (embedded as base64 PNG), the resolved
scenario and the provenance, on one page a user can mail to a colleague."""

from __future__ import annotations

import base64
import html
import json
import os
from pathlib import Path
from typing import Any

from floebreak.errors import InputError
from floebreak.io.atomic import atomic_path

# summary rows shown first, with labels (thesis Tables 5–8 notation where it exists)
_SUMMARY_ROWS = (
    ("n_floes_initial", "floes in the initial field", ""),
    ("initial_ice_area_m2", "initial ice area", "m²"),
    ("n_cusps", "n_cusp (cusps)", ""),
    ("cusp_area_m2", "A_cusp^tot (total cusp area)", "m²"),
    ("mean_cusp_area_m2", "Ā_cusp (mean cusp area)", "m²"),
    ("mean_cusp_volume_m3", "V̄_cusp (mean cusp volume)", "m³"),
    ("n_flipped", "n_flip (flipped floes)", ""),
    ("flipped_area_m2", "A_flip^tot (total flipped area)", "m²"),
    ("remaining_ice_area_m2", "remaining ice area", "m²"),
    ("area_balance_rel_error", "area balance, relative error", ""),
    ("n_contacts", "contact evaluations", ""),
    ("n_breaks", "breaks", ""),
    ("crushing_force_max_n", "maximum crushing force", "N"),
    ("wall_time_s", "wall time", "s"),
)

_FIGURE_CAPTIONS = {
    "breaking_pattern.png": "Breaking pattern: blue ice in the field, orange flipped, red cusps; bow ice "
    "waterlines at the start (dashed) and the end (solid).",
    "cusp_volume_spectrum.png": "Cusp-volume spectrum (thesis Fig. 17 style).",
    "crushing_force_spectrum.png": "Crushing-force spectrum per contact evaluation (thesis Fig. 13).",
    "field.png": "Initial floe field, coloured by diameter class.",
}

_STYLE = """
body { font-family: system-ui, sans-serif; margin: 2em auto; max-width: 60em; color: #222; }
table { border-collapse: collapse; margin: 0.5em 0 1.5em; }
td, th { border: 1px solid #ccc; padding: 0.2em 0.6em; text-align: left; }
td.num { text-align: right; font-variant-numeric: tabular-nums; }
pre { background: #f6f6f6; padding: 0.8em; overflow-x: auto; font-size: 0.85em; }
figure { margin: 1em 0 2em; } img { max-width: 100%; } figcaption { font-size: 0.9em; color: #555; }
"""


def _format(value: Any) -> str:
    if value is None:
        return "–"
    if isinstance(value, bool):
        return str(value)
    if isinstance(value, int):
        return f"{value:d}"
    if isinstance(value, float):
        return f"{value:.3e}" if value != 0 and (abs(value) < 1e-2 or abs(value) >= 1e6) else f"{value:.4g}"
    if isinstance(value, dict):
        return ", ".join(f"{k}: {_format(v)}" for k, v in value.items())
    return str(value)


def _page_head(title: str) -> list[str]:
    esc = html.escape
    return [
        "<!DOCTYPE html>",
        '<html lang="en"><head><meta charset="utf-8">',
        f"<title>{esc(title)}</title><style>{_STYLE}</style></head><body>",
        f"<h1>{esc(title)}</h1>",
    ]


def render_report(
    run_dir: str | os.PathLike[str],
    directory_name: str | None = None,
    analyses: dict[str, Path] | None = None,
) -> str:
    """The HTML text of the report of run directory `run_dir` (InputError if it is not a run directory).

    `directory_name` is the name shown for the run directory (default: its current name; a run being
    written in a temporary directory passes its final name). `analyses`: the propeller analyses shown,
    their path relative to the run directory → the folder to read (default `analysis_folders(run_dir)`;
    an analysis being written passes its temporary folder under its final name)."""
    run_dir = Path(run_dir)
    analyses = analysis_folders(run_dir) if analyses is None else analyses
    summary_path = run_dir / "summary.json"
    if not summary_path.is_file():
        raise InputError(
            "run_dir",
            f"{str(run_dir)!r} has no summary.json",
            allowed="a run directory written by `floebreak run` or `floebreak demo`",
        )
    try:
        summary = json.loads(summary_path.read_text(encoding="utf-8"))
    except (OSError, json.JSONDecodeError) as error:
        raise InputError("run_dir", f"{str(summary_path)!r} is not readable JSON ({error})") from None
    provenance = summary.pop("provenance", {})
    scenario_path = run_dir / "scenario.resolved.toml"
    scenario_text = scenario_path.read_text(encoding="utf-8") if scenario_path.is_file() else "(missing)"
    esc = html.escape
    title = f"floebreak run {summary.get('scenario_hash', '')[:12]}"
    parts = [
        *_page_head(title),
        f"<p>profile <b>{esc(str(summary.get('profile')))}</b>, seed <b>{esc(str(summary.get('seed')))}</b>, "
        f"floebreak {esc(str(summary.get('floebreak_version')))}; "
        f"directory <code>{esc(directory_name or run_dir.name)}</code>"
        "</p>",
        "<h2>Summary</h2><table><tr><th>quantity</th><th>value</th><th>unit</th><th>key</th></tr>",
    ]
    shown = set()
    for key, label, unit in _SUMMARY_ROWS:
        if key in summary:
            shown.add(key)
            parts.append(
                f"<tr><td>{esc(label)}</td><td class='num'>{esc(_format(summary[key]))}</td>"
                f"<td>{esc(unit)}</td><td><code>{esc(key)}</code></td></tr>"
            )
    hashes = {key: summary[key] for key in _HASH_KEYS if key in summary}
    for key, value in summary.items():
        if key not in shown and key not in hashes:
            parts.append(
                f"<tr><td>{esc(key)}</td><td class='num'>{esc(_format(value))}</td><td></td>"
                f"<td><code>{esc(key)}</code></td></tr>"
            )
    parts.append("</table><h2>Figures</h2>")
    figures = run_dir / "figures"
    names = sorted(p.name for p in figures.glob("*.png")) if figures.is_dir() else []
    order = [n for n in _FIGURE_CAPTIONS if n in names] + [n for n in names if n not in _FIGURE_CAPTIONS]
    for name in order:
        data = base64.b64encode((figures / name).read_bytes()).decode("ascii")
        caption = _FIGURE_CAPTIONS.get(name, name)
        parts.append(
            f"<figure><img alt='{esc(name)}' src='data:image/png;base64,{data}'>"
            f"<figcaption>{esc(caption)}</figcaption></figure>"
        )
    if not order:
        parts.append("<p>(no figures)</p>")
    for name, folder in analyses.items():
        parts += propeller_section(folder, name)
        parts += shaft_section(folder / "shaft", name)
    parts += [
        "<h2>Scenario (resolved)</h2>",
        f"<details><summary>scenario.resolved.toml</summary><pre>{esc(scenario_text)}</pre></details>",
        *_provenance_parts(hashes, provenance, analyses),
        "</body></html>",
    ]
    return "\n".join(parts) + "\n"


def analysis_folders(run_dir: Path) -> dict[str, Path]:
    """The propeller analyses inside run directory `run_dir` (folders up to three levels down whose
    summary.json is a propeller analysis'), by their path relative to it, "propeller" (the demo's) first;
    temporary folders (hidden names) are left out."""
    found = {}
    for depth in ("*", "*/*", "*/*/*"):
        for path in sorted(Path(run_dir).glob(f"{depth}/summary.json")):
            relative = path.parent.relative_to(run_dir)
            if any(part.startswith(".") for part in relative.parts):
                continue
            summary = _section_summary(path.parent)
            if summary is not None and "pitches" in summary and "options" in summary:
                found[relative.as_posix()] = path.parent
    return dict(sorted(found.items(), key=lambda item: (item[0] != "propeller", item[0])))


def _titled(title: str, name: str | None) -> str:
    """A section's title; an analysis folder other than the demo's "propeller" is named in it."""
    return title if name in (None, "propeller") else f"{title} ({name}/)"


def _provenance_parts(hashes: dict | None, provenance: dict | None, analyses: dict[str, Path]) -> list[str]:
    """The page's last section, collapsed: the run's hashes and provenance (none on an analysis' own page:
    None), and the provenance of its propeller and shaft `analyses` where present."""
    esc = html.escape

    def block(title: str, *records: dict) -> str:
        pre = "".join(f"<pre>{esc(json.dumps(r, indent=2, sort_keys=True))}</pre>" for r in records)
        return f"<details><summary>{esc(title)}</summary>{pre}</details>"

    parts = ["<h2>Provenance</h2>"]
    if hashes is not None and provenance is not None:
        parts.append(
            block("Hashes of the run's files, scenario and model; library versions", hashes, provenance)
        )
    for name, folder in analyses.items():
        for where, title in (
            (folder, "Provenance of the propeller files"),
            (folder / "shaft", "Provenance of the shaft files"),
        ):
            summary = _section_summary(where)
            if summary is not None:
                parts.append(block(_titled(title, name), summary.get("provenance", {})))
    return parts


# summary keys shown in the collapsed provenance block at the end, not in the summary table
_HASH_KEYS = ("scenario_hash", "model_hash", "summary_sha256", "files")


_PROPELLER_FIGURES = {
    "torque_spectrum_log.png": "Torque spectrum |Q| per pitch (thesis Fig. 33 style, log scale).",
    "load_spectrum_log.png": "Blade-load spectrum |F| per pitch (thesis Fig. 32 style, log scale).",
    "rule_form.png": "Torque exceedance against the rule form exp(−(x/x_max)^k ln N): simulated, fitted, and "
    "the rule's shape through the same x_max; right: exceedances per hour on one propeller.",
    "ice_class_exceedance.png": "Loads against the IACS UR I3 maxima (as recalled, notes §7.2).",
    "volume_loads.png": "FEM table interpolation and the policy beyond the table.",
}


def _embedded_figure(path: Path, caption: str) -> str:
    data = base64.b64encode(path.read_bytes()).decode("ascii")
    return (
        f"<figure><img alt='{html.escape(path.name)}' src='data:image/png;base64,{data}'>"
        f"<figcaption>{html.escape(caption)}</figcaption></figure>"
    )


def _propeller_rows(summary: dict) -> list[str]:
    """One table row per pitch: cusps beyond the table, max |Q|, rule-form fit of |Q| and rates."""
    esc = html.escape
    rows = [
        "<table><tr><th>pitch [%]</th><th>beyond FEM table</th><th>max |Q| [kN·m]</th>"
        "<th>fit k (95 % CI)</th><th>rule k</th><th>|Q| max per hour [kN·m] (95 % CI)</th>"
        "<th>|Q| max over the profile, all cusps, mean propeller [kN·m]</th></tr>"
    ]
    for label, info in summary.get("pitches", {}).items():
        fit = ((summary.get("rule_form") or {}).get(label) or {}).get("torque_knm") or {}
        k = "–" if "k" not in fit else f"{fit['k']:.3f} ({fit['k_ci95'][0]:.3f}–{fit['k_ci95'][1]:.3f})"
        hour = "–"
        if "x_max_per_hour" in fit:
            low, high = fit["x_max_per_hour_ci95"]
            hour = f"{fit['x_max_per_hour']:.0f} ({low:.0f}–{high:.0f})"
        life = "–" if "x_max_lifetime" not in fit else f"{fit['x_max_lifetime']:.0f}"
        q = info.get("torque_range_knm")
        cells = [
            _format(info["pitch_percent"]),  # a voyage's "operated" case is a name
            f"{info['n_beyond_table']} ({100 * info['fraction_beyond_table']:.0f} %)",
            "–" if not q else f"{q[1]:.0f}",
            k,
            _format(fit.get("rule_k")),
            hour,
            life,
        ]
        rows.append("<tr>" + "".join(f"<td class='num'>{esc(c)}</td>" for c in cells) + "</tr>")
    rows.append("</table>")
    return rows


_DESIGN_ROWS = (  # label, key of summary.json's design_loads rows, unit
    ("design ice torque Q, this propeller", "design_torque_kn_m", "kN·m"),
    ("rule Q_max", "rule_max_torque_kn_m", "kN·m"),
    ("Q / Q_max", "torque_ratio", "–"),
    ("design blade force F", "design_force_kn", "kN"),
    ("rule F_b (backward)", "rule_backward_force_kn", "kN"),
    ("rule F_f (forward, for reference)", "rule_forward_force_kn", "kN"),
    ("F / F_b", "force_ratio", "–"),
    ("largest simulated |Q|", "max_abs_torque_kn_m", "kN·m"),
    ("largest simulated |F|", "max_abs_force_kn", "kN"),
    ("cusps over the operating profile (this propeller)", "n_loads_profile", "–"),
    ("simulated impacts per hour on one blade", "blade_impacts_per_hour", "1/h"),
    ("rule load cycles per hour on one blade, k₁ low", "rule_blade_cycles_per_hour_low", "1/h"),
    ("rule load cycles per hour on one blade, k₁ high", "rule_blade_cycles_per_hour_high", "1/h"),
    ("simulated impacts on one blade over the profile", "blade_impacts_profile", "–"),
    ("rule N_ice per blade, k₁ low", "rule_n_ice", "–"),
    ("rule N_ice per blade, k₁ high", "rule_n_ice_high", "–"),
    ("impacts / N_ice, k₁ low", "impacts_ratio_low", "–"),
    ("impacts / N_ice, k₁ high", "impacts_ratio_high", "–"),
)


WHICH_DESIGN_TORQUE = (
    "Which design torque is which: the per-pitch table's |Q| max over the profile is the rule-form fit "
    "to all cusps at the mean propeller's rate; each design-load table's design ice torque Q is that "
    "propeller's own (its cusps and rate: x_max over the profile, else its largest simulated load)"
)


def _band(band) -> str:
    """[p5, median, p95] as "median (p5–p95)", "–" without."""
    return "–" if not band else f"{band[1]:.4g} ({band[0]:.4g}–{band[2]:.4g})"


def _spread_part(summary: dict) -> list[str]:
    """Loads per hour on one propeller as median and 5–95 % band (summary.json "spread")."""
    spread = summary.get("spread") or {}
    rate = spread.get("loads_per_hour_per_propeller")
    if not rate:
        return []
    draws = "draws of the flow transport's parameters" if spread.get("transport") == "flow" else "draw"
    return [
        f"<p>Loads per hour on one propeller over {spread['n_runs']} field(s) × {spread['n_draws_per_run']} "
        f"{html.escape(draws)}: median <b>{rate['median']:.4g}</b>, 5–95 % band {rate['p5']:.4g}–"
        f"{rate['p95']:.4g} ({rate['n_samples']} samples).</p>"
    ]


def design_load_parts(design_loads: list[dict] | None) -> list[str]:
    """HTML of the design-load tables (summary.json "design_loads", one per propeller; quantities as rows,
    one column per pitch) and the basis of every number; a hint without a polar class (None)."""
    esc = html.escape
    if not design_loads:
        return [
            "<p>Design-load table: the analysis was run without a polar class "
            "(<code>--polar-class</code>, <code>polar_class=</code>).</p>"
        ]
    parts = []
    for entry in design_loads:
        rows = entry["rows"]
        title = f"Design loads, {entry['propeller']}, against IACS UR I3 {entry['polar_class']}"
        parts.append(
            f"<h3>{esc(title)}</h3><table><tr><th>quantity</th>"
            + "".join(f"<th>pitch {row['pitch_percent']:g} %</th>" for row in rows)
            + "<th>unit</th></tr>"
        )
        for label, key, unit in _DESIGN_ROWS:
            # an analysis written by an earlier version may lack a quantity: shown as –, not an error
            cells = "".join(f"<td class='num'>{esc(_format(row.get(key)))}</td>" for row in rows)
            parts.append(f"<tr><td>{esc(label)}</td>{cells}<td>{esc(unit)}</td></tr>")
            if key == "design_torque_kn_m" and any(r.get("design_torque_band_kn_m") for r in rows):
                cells = "".join(
                    f"<td class='num'>{esc(_band(r.get('design_torque_band_kn_m')))}</td>" for r in rows
                )
                parts.append(
                    f"<tr><td>design ice torque Q, median (5–95 %)</td>{cells}<td>{esc(unit)}</td></tr>"
                )
        parts.append("</table><details><summary>Basis of each number</summary><ul>")
        for row in rows:
            for number, text in row["basis"].items():
                parts.append(f"<li>pitch {row['pitch_percent']:g} %, {esc(number)}: {esc(text)}</li>")
        parts.append("</ul></details>")
    return parts


def _section_summary(folder: Path) -> dict | None:
    """The summary.json of an analysis folder (propeller, shaft), None if there is none."""
    path = folder / "summary.json"
    if not path.is_file():
        return None
    try:
        return json.loads(path.read_text(encoding="utf-8"))
    except (OSError, json.JSONDecodeError) as error:
        raise InputError("run_dir", f"{str(path)!r} is not readable JSON ({error})") from None


def propeller_section(folder: Path, name: str | None = None) -> list[str]:
    """HTML parts of the propeller section when `folder` holds a propeller analysis (summary.json):
    warnings, rates, the per-pitch table and the figures; nothing otherwise. `name`: the folder's name
    in the heading (none for the demo's "propeller")."""
    summary = _section_summary(folder)
    return (
        []
        if summary is None
        else propeller_parts(summary, folder / "figures", title=_titled("Propeller loads", name))
    )


def propeller_parts(
    summary: dict, figures: Path, captions: dict[str, str] | None = None, title: str = "Propeller loads"
) -> list[str]:
    """HTML parts of a propeller section from a summary in the shape `analyse_propeller` writes (warnings,
    rates, pitches, rule_form): warnings, time base, per-pitch table, and the `captions`' figures found in
    `figures` (default: the propeller analysis' figures)."""
    esc = html.escape
    parts = [f"<h2>{esc(title)}</h2>"]
    parts += [f"<p style='color:#a00'><b>Warning:</b> {esc(w)}</p>" for w in summary.get("warnings", [])]
    rates = summary.get("rates")
    if rates:
        bases = sorted(
            {
                f"speed {r['speed_m_s']:g} m/s, fraction reaching {r['fraction_reaching']:g}, "
                f"{r['n_propellers']} propeller(s)"
                for r in rates["per_run"].values()
            }
        )
        parts.append(
            f"<p>Time base: {rates['transit_m']:.0f} m of transit, {rates['hours_in_ice']:.4g} h in ice "
            f"({esc('; '.join(bases))}): <b>{rates['loads_per_hour_per_propeller']:.4g}</b> "
            f"loads per hour and <b>{rates['loads_per_km_per_propeller']:.4g}</b> per km on one propeller</p>"
        )
    else:
        parts.append("<p>No time base (transit distance unknown): densities only, no rates.</p>")
    parts += _spread_part(summary)
    parts += _load_model_part(summary.get("load_model") or {})
    parts += _propeller_rows(summary)
    if "design_loads" in summary:  # a propeller analysis' (a voyage's pooled loads have none)
        parts += design_load_parts(summary["design_loads"])
        if summary["design_loads"]:
            parts.append(f"<p>{esc(WHICH_DESIGN_TORQUE)}.</p>")
    rule = summary.get("rule_form") or {}
    if rule.get("rule_n_ice") is not None:
        parts.append(
            f"<p>Rule N_ice = {rule['rule_n_ice']:.4g} to "
            f"{rule.get('rule_n_ice_high') or rule['rule_n_ice']:.4g}"
            f" load cycles per blade ({esc(_format(rule['rule_n_ice_inputs']))}; "
            "UR I3 as recalled, verify against the rule text).</p>"
        )
    for name, caption in (_PROPELLER_FIGURES if captions is None else captions).items():
        if (figures / name).is_file():
            parts.append(_embedded_figure(figures / name, caption))
    return parts


def _load_model_part(model: dict) -> list[str]:
    """The per-cusp load model and where it places each cusp on the blade (`load_model` of a propeller
    analysis' summary.json: "name"; of a voyage's: "load_model"), as the terminal states them."""
    name = model.get("name") or model.get("load_model")
    if not name:
        return []
    placement = f" ({model['placement']})" if model.get("placement") else ""
    return [f"<p>Per-cusp loads: {html.escape(f'{name} model{placement}')}</p>"]


_SHAFT_FIGURES = {
    "shaft_series.png": "Propeller load and shaft torque at the station, first excitation case; below: "
    "the seconds around the peak.",
    "excitation_series.png": "Propeller load torque Q(t) = Q_mean + Q_ice(t), first excitation case.",
    "shaft_spectrum_log.png": "Torque spectra: propeller load and shaft (log scale).",
    "shaft_spectrum_linear.png": "Torque spectra: propeller load and shaft (linear scale).",
    "shaft_comparison_log.png": "Shaft torque: simulated against measured (log scale).",
    "shaft_comparison_linear.png": "Shaft torque: simulated against measured (linear scale).",
    "mode_shapes.png": "Free-free torsional modes of the shaft line.",
    "campbell.png": "Campbell diagram: blade-passage orders against the natural frequencies; the band is "
    "the required resonance margin around the operating speed.",
    "rainflow_histogram.png": "Rainflow cycles of the shaft torque (ASTM E1049-85) per 10 kN·m range bin.",
}


def _shaft_rows(summary: dict) -> list[str]:
    """The shaft line's design numbers and, per excitation case, Q_peak, the shaft minimum and the drive's
    outcome (min rpm, peak motor torque)."""
    esc = html.escape
    resonance, fatigue, op = summary["resonance"], summary.get("fatigue") or {}, summary["operating_point"]
    margin = min(min(row) for row in resonance["margin"])
    damage = fatigue.get("damage")
    rows = [
        (
            "first natural frequency (free-free)",
            summary["modes_free_free"]["natural_frequencies_hz"][0],
            "Hz",
        ),
        (f"blade-passage frequency at {op['rpm']:g} rpm", op["blade_passage_frequency_hz"], "Hz"),
        (f"resonance margin (required {100 * resonance['required_margin']:.0f} %)", 100 * margin, "%"),
        ("Miner's damage, shaft torque", "no S–N curve given" if damage is None else damage, "–"),
    ]
    parts = ["<table><tr><th>quantity</th><th>value</th><th>unit</th></tr>"]
    parts += [
        f"<tr><td>{esc(label)}</td><td class='num'>{esc(_format(value))}</td><td>{esc(unit)}</td></tr>"
        for label, value, unit in rows
    ]
    parts.append(
        "</table><table><tr><th>case</th><th>Q_peak [kN·m]</th><th>shaft min [kN·m]</th>"
        "<th>min rpm [1/min]</th><th>peak motor torque [kN·m]</th></tr>"
    )
    drive = (summary.get("drive") or {}).get("cases", {})
    for case, peak in summary["q_peak_knm"].items():
        d = drive.get(case) or {}
        cells = [
            case,
            peak["q_peak_knm"],
            peak["q_min_knm"],
            d.get("min_rpm"),
            d.get("peak_motor_torque_knm"),
        ]
        parts.append("<tr>" + "".join(f"<td class='num'>{esc(_format(c))}</td>" for c in cells) + "</tr>")
    parts.append("</table>")
    spread = summary.get("q_peak_spread")
    if spread and spread.get("q_peak_knm"):
        q = spread["q_peak_knm"]
        parts.append(
            f"<p>Q_peak of case {esc(str(spread['case']))} over {spread['n_draws']} draws of the flow "
            f"transport's parameters: median <b>{q['median']:.4g}</b> kN·m, 5–95 % band {q['p5']:.4g}–"
            f"{q['p95']:.4g} kN·m.</p>"
        )
    return parts


def shaft_section(folder: Path, name: str | None = None) -> list[str]:
    """HTML parts of the "Shaft line" section when `folder` holds a shaft analysis (summary.json): the
    warnings, the design numbers (`_shaft_rows`), the fatigue note and the figures (the shaft files'
    provenance: the page's last section); nothing otherwise. `name`: the propeller analysis' folder in
    the heading, as `propeller_section`."""
    summary = _section_summary(folder)
    if summary is None:
        return []
    esc = html.escape
    parts = [
        f"<h2>{esc(_titled('Shaft line', name))}</h2>",
        f"<p>Line <b>{esc(summary['shaft_line']['name'])}</b>, station <b>{esc(summary['station'])}</b>, "
        f"{esc(summary['shaft_model'])} model"
        + (
            f"; measured: <code>{esc(summary['measured_source'])}</code>"
            if summary.get("measured_source")
            else ""
        )
        + ".</p>",
    ]
    parts += [f"<p style='color:#a00'><b>Warning:</b> {esc(w)}</p>" for w in summary.get("warnings", [])]
    parts += _shaft_rows(summary)
    if (summary.get("fatigue") or {}).get("note"):
        parts.append(f"<p>Fatigue: {esc(summary['fatigue']['note'])}.</p>")
    for name, caption in _SHAFT_FIGURES.items():
        if (folder / "figures" / name).is_file():
            parts.append(_embedded_figure(folder / "figures" / name, caption))
    return parts


def render_voyage_report(
    title: str, notes: list[str], propeller: dict, figures: Path, captions: dict[str, str]
) -> str:
    """The HTML text of a voyage's report: its notes and its propeller section (`propeller_parts` of the
    voyage's pooled loads in the propeller summary's shape, with the voyage's figures)."""
    esc = html.escape
    parts = [*_page_head(title), "<h2>Notes</h2><ul>"]
    parts += [f"<li>{esc(note)}</li>" for note in notes]
    parts.append("</ul>")
    parts += propeller_parts(propeller, figures, captions)
    parts.append("</body></html>")
    return "\n".join(parts) + "\n"


def render_analysis_report(folder: str | os.PathLike[str], directory_name: str | None = None) -> str:
    """The HTML text of the report of a propeller analysis `folder` (`floebreak propeller --out`): the
    runs it analysed, its propeller and design-load section, its shaft section (folder/shaft: shaft
    line, excitation cases, Campbell and rainflow) and the provenance. `directory_name` as
    `render_report`'s."""
    folder = Path(folder)
    summary = _section_summary(folder)
    if summary is None or "pitches" not in summary:
        raise InputError(
            "out",
            f"{str(folder)!r} has no propeller summary.json",
            allowed="a directory written by `floebreak propeller`",
        )
    esc = html.escape
    name = directory_name or folder.name
    runs = (summary.get("provenance") or {}).get("runs") or []
    shown = ", ".join(str(r) for r in runs[:5]) + (f" and {len(runs) - 5} more" if len(runs) > 5 else "")
    parts = [
        *_page_head(f"floebreak propeller analysis {name}"),
        f"<p>directory <code>{esc(name)}</code>; {len(runs)} run(s) analysed"
        + (f": <code>{esc(shown)}</code>" if runs else "")
        + f"; floebreak {esc(str((summary.get('provenance') or {}).get('floebreak_version')))}</p>",
        *propeller_parts(summary, folder / "figures"),
        *shaft_section(folder / "shaft"),
        *_provenance_parts(None, None, {"propeller": folder}),
        "</body></html>",
    ]
    return "\n".join(parts) + "\n"


def write_text_report(text: str, path: str | os.PathLike[str]) -> Path:
    """Write a rendered report `text` to `path` atomically."""
    path = Path(path)
    with atomic_path(path, field="out") as temp:
        temp.write_text(text, encoding="utf-8")
    return path


def write_report(
    run_dir: str | os.PathLike[str],
    out: str | os.PathLike[str] | None = None,
    directory_name: str | None = None,
) -> Path:
    """Write the report of `run_dir` to `out` (default ``run_dir/report.html``) atomically; of a propeller
    analysis' directory (`floebreak propeller --out`), its `render_analysis_report`."""
    summary = _section_summary(Path(run_dir))
    analysis = summary is not None and "pitches" in summary
    text = (render_analysis_report if analysis else render_report)(run_dir, directory_name)
    path = Path(out) if out is not None else Path(run_dir) / "report.html"
    with atomic_path(path, field="out") as temp:
        temp.write_text(text, encoding="utf-8")
    return path

"""Every command's options, defined once (the same help wherever an option appears), and the parsing of the
repeatable KEY=VALUE ones."""

from __future__ import annotations

from enum import StrEnum
from pathlib import Path
from typing import Annotated

import typer

from floebreak.errors import InputError

PolarClassOption = Annotated[str | None, typer.Option("--polar-class", help="IACS polar class, e.g. PC5")]
FractionReachingOption = Annotated[
    float | None,
    typer.Option("--fraction-reaching", help="fraction of cusps reaching a propeller (0, 1]"),
]
PropellersOption = Annotated[int | None, typer.Option("--propellers", help="number of propellers")]
ShaftLineOption = Annotated[
    str | None,
    typer.Option("--shaft-line", help="shaft torque too (OUT/shaft/): agulhas_ii or FILE.toml"),
]
TransportParameterOption = Annotated[
    list[str] | None,
    typer.Option(
        "--transport-parameter",
        help="cusp transport setting as KEY=VALUE (repeatable; docs/model.md 'Cusp transport under the "
        "hull'): slip_factor, drag_coefficient, shoulder_region_start, shoulder_cusps_submerge (true|false), "
        "hull.beam_m, hull.draught_m, hull.bilge_radius_m, hull.bow_length_m, "
        "hull.propeller_plane_aft_of_stem_m, hull.run_length_m, arrangement.tip_clearance_m",
    ),
]


def transport_values(items: list[str] | None) -> dict[str, str]:
    """`--transport-parameter KEY=VALUE …` → {KEY: VALUE} (checked by `transport_settings`)."""
    from floebreak.propeller.transport import TRANSPORT_KEYS

    values: dict[str, str] = {}
    for item in items or ():
        key, sep, text = item.partition("=")
        if not sep:
            allowed = f"KEY=VALUE, KEY one of {', '.join(TRANSPORT_KEYS)}"
            raise InputError("--transport-parameter", f"{item!r}", value=item, allowed=allowed)
        values[key.strip()] = text.strip()
    return values


def transport_option(items: list[str] | None):
    """`--transport-parameter KEY=VALUE …` → validated `TransportSettings` (defaults for keys not given)."""
    from floebreak.propeller.transport import transport_settings

    return transport_settings(transport_values(items))


def operating_profile(hours_per_year: float | None, years: float | None):
    """`--hours-in-ice-per-year` and `--years` → an `OperatingProfile` (both) or None (neither)."""
    from floebreak.propeller.ruleform import OperatingProfile

    if (hours_per_year is None) != (years is None):
        raise InputError(
            "--years", "give both --hours-in-ice-per-year and --years", allowed="both or neither"
        )
    return None if years is None else OperatingProfile(hours_per_year, years)


class GeneratorName(StrEnum):
    circles = "circles"
    voronoi = "voronoi"
    sqp = "sqp"


SetOption = Annotated[
    list[str] | None,
    typer.Option("--set", help="override a scenario key, e.g. --set ice.thickness_m=0.8 (repeatable)"),
]

OverwriteOption = Annotated[bool, typer.Option("--overwrite", help="replace an existing output directory")]

QuietOption = Annotated[bool, typer.Option("--quiet", "-q", help="no progress bar and no summary table")]

# the `propeller` command's options (named here so that its signature stays readable)
FemTableOption = Annotated[
    list[str] | None,
    typer.Option(
        "--fem-table",
        help="own FEM table CSV as PITCH=FILE (pitch in %; repeatable, one per pitch); FILE alone if it "
        "has a '# pitch_percent:' line",
    ),
]

BeyondOption = Annotated[str, typer.Option("--beyond", help="power_law | clamp | extrapolate | flag")]

PoolOption = Annotated[
    bool, typer.Option("--pool", help="pool runs whose scenarios differ in more than seed and field")
]

SpeedOption = Annotated[
    float | None, typer.Option("--speed-m-s", help="ship speed in ice [m/s] (default: the scenario's)")
]

LoadModelOption = Annotated[
    str | None,
    typer.Option(
        "--load-model",
        help="per-cusp loads: milling (blade milling model) | fem (FEM tables); default: the runs' profile "
        "(default → milling, thesis → fem); --fem-table implies fem",
    ),
]

TransportOption = Annotated[
    str | None,
    typer.Option(
        "--transport",
        help="which cusps reach a propeller: flow (cusps followed under the hull) | hull (kinematic "
        "transport) | all (every cusp); default: the runs' profile (default → flow, thesis → all); also the "
        "shaft's drive model; --fraction-reaching overrides them",
    ),
]

RatedTorqueOption = Annotated[
    float | None,
    typer.Option(
        "--rated-torque-knm",
        help="the drive's rated torque [kN m] for the warnings (default: 4.5 MW / (2π · rpm), the built-in "
        "Agulhas II line: 306.9 kN m)",
    ),
]

GeometryOption = Annotated[
    list[str] | None,
    typer.Option(
        "--propeller-geometry",
        help="propeller as KEY=VALUE (repeatable): radius_m, max_pitch_m, pitch_percent, rpm, blades, "
        "expanded_area_ratio, hub_ratio, blade_thickness_07_m, bollard_pitch_m (default: Agulhas II)",
    ),
]

HoursPerYearOption = Annotated[
    float | None, typer.Option("--hours-in-ice-per-year", help="operating profile [h/a]")
]

YearsOption = Annotated[float | None, typer.Option("--years", help="operating profile: years in service")]

SnCurveOption = Annotated[
    str | None,
    typer.Option(
        "--sn-curve",
        help="Basquin S–N curve for Miner's sum, QUANTITY,M,AMPLITUDE,CYCLES, e.g. torque,5,1000,1e7 "
        "(N = CYCLES·(AMPLITUDE/x)^M; amplitude in kN·m for torque, kN for force)",
    ),
]

StationOption = Annotated[
    str | None, typer.Option("--station", help="shaft measurement station (default: the line's)")
]

RpmOption = Annotated[float | None, typer.Option("--rpm", help="propeller speed [1/min] (shaft analysis)")]

MeanTorqueOption = Annotated[
    float | None, typer.Option("--mean-torque-knm", help="mean hydrodynamic torque [kN m] (shaft)")
]

ShaftModelOption = Annotated[
    str | None,
    typer.Option(
        "--shaft-model",
        help="drive (transport + milling + torque-limited motor) | linear (every cusp, FEM, constant rpm); "
        "default: the run's profile's (default → drive, thesis → linear)",
    ),
]

TorqueLimitOption = Annotated[
    float | None,
    typer.Option("--torque-limit-knm", help="motor torque limit [kN m] (drive model; default 1.6 × rated)"),
]

ExcitationOption = Annotated[
    str,
    typer.Option(
        "--excitation",
        help="simulation (the cusps) | rule (also the ice-class rule's four cases and their resonance sweep "
        "beside it; shaft)",
    ),
]
WakeFractionOption = Annotated[
    float | None,
    typer.Option("--wake-fraction", help="wake fraction w in [0, 1) (default: Holtrop & Mennen's; shaft)"),
]
OpenWaterTableOption = Annotated[
    Path | None,
    typer.Option(
        "--open-water-table",
        help="open-water curves CSV: columns pitch_ratio, J, K_T, K_Q (or 10K_Q) (default: the B-series)",
    ),
]
ExcitationCasesOption = Annotated[
    str, typer.Option("--excitation-cases", help="ice excitation cases, first plotted, e.g. 1,2,3,4")
]

# the options every command that runs a study shares (study, voyage, validate)
WorkersOption = Annotated[
    int | None, typer.Option("--workers", help="local worker processes (default: cores)")
]
SchedulerOption = Annotated[
    str | None,
    typer.Option("--scheduler", help="Dask scheduler tcp://HOST:PORT, or 'local' (LocalCluster)"),
]
OutOption = Annotated[Path, typer.Option("--out", help="output directory (re-running resumes it)")]
ProfileOption = Annotated[str, typer.Option("--profile", help="default | thesis | both")]
FieldsOption = Annotated[int, typer.Option("--n-fields", help="common random fields per design point (≥ 1)")]
SeedOption = Annotated[int, typer.Option("--seed", help="root seed of the fields")]
EveryRunSetOption = Annotated[
    list[str] | None,
    typer.Option("--set", help="override a scenario key for every run, KEY=VALUE (repeatable)"),
]
LengthOption = Annotated[
    float | None, typer.Option("--length-m", help="field length [m] (default: the thesis' inferred length)")
]

"""Options shared by `floebreak propeller` and `floebreak voyage` (one definition, the same help), and the
parsing of the repeatable KEY=VALUE ones."""

from __future__ import annotations

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

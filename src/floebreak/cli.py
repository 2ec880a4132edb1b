"""The floebreak command line: a thin typer layer over the public functions."""

from __future__ import annotations

import sys
from enum import StrEnum
from pathlib import Path
from typing import Annotated

import numpy as np
import typer
from rich.console import Console
from rich.table import Table

from floebreak.errors import InputError
from floebreak.ice.observations import Observation, get_observation, thesis_observations

app = typer.Typer(no_args_is_help=True, add_completion=False, help=__doc__, pretty_exceptions_enable=False)
console = Console()
err_console = Console(stderr=True)


@app.command()
def observations() -> None:
    """Print the built-in ice observations (thesis Table 1, expedition Agu19/20)."""
    table = Table(title="Ice observations Agu19/20 (thesis Table 1); diameter shares are % of floe count")
    table.add_column("key")
    table.add_column(r"concentration \[%]", justify="right")
    table.add_column(r"mean thickness \[m]", justify="right")
    table.add_column(r"diameter class \[m]: share of floes \[%]")
    for key, obs in thesis_observations().items():
        shares = ", ".join(
            f"{d:g}: {p:g}" for d, p in zip(obs.diameter_classes_m, obs.percentages, strict=True)
        )
        table.add_row(key, f"{100 * obs.concentration:g}", f"{obs.mean_thickness_m:g}", shares)
    console.print(table)


class GeneratorName(StrEnum):
    circles = "circles"
    voronoi = "voronoi"
    sqp = "sqp"


def _parse_floats(text: str | None, field: str) -> tuple[float, ...] | None:
    if text is None:
        return None
    try:
        return tuple(float(v) for v in text.replace(";", ",").split(",") if v.strip())
    except ValueError:
        raise InputError(field, f"{text!r} is not a comma-separated list of numbers") from None


@app.command()
def field(
    out: Annotated[Path, typer.Option("--out", help="output GeoParquet file (e.g. field.parquet)")],
    obs: Annotated[
        str | None, typer.Option("--obs", help="observation key from `floebreak observations`")
    ] = None,
    length: Annotated[float, typer.Option("--length", help="field length along x [m]")] = 400.0,
    width: Annotated[float, typer.Option("--width", help="field width along y [m]")] = 50.0,
    seed: Annotated[int, typer.Option("--seed", help="random seed")] = 1,
    generator: Annotated[GeneratorName, typer.Option("--generator")] = GeneratorName.circles,
    thickness: Annotated[float | None, typer.Option("--thickness", help="constant thickness [m]")] = None,
    thickness_range: Annotated[
        str | None, typer.Option("--thickness-range", help="random thickness range 'MIN,MAX' [m]")
    ] = None,
    concentration: Annotated[
        float | None, typer.Option("--concentration", help="user observation: ice concentration (0, 1]")
    ] = None,
    mean_thickness: Annotated[
        float | None, typer.Option("--mean-thickness", help="user observation: mean thickness [m]")
    ] = None,
    diameters: Annotated[
        str | None, typer.Option("--diameters", help="user observation: diameter classes 'D1,D2,...' [m]")
    ] = None,
    percentages: Annotated[
        str | None,
        typer.Option("--percentages", help="user observation: share of floes per class 'P1,P2,...' [%]"),
    ] = None,
    figure: Annotated[Path | None, typer.Option("--figure", help="also write a figure (PNG/PDF/SVG)")] = None,
    geojson: Annotated[Path | None, typer.Option("--geojson", help="also write GeoJSON")] = None,
) -> None:
    """Generate a random floe field from an ice observation and save it as GeoParquet."""
    from floebreak.ice.generation import generate_field
    from floebreak.io.field_files import export_geojson, save_field

    observation = _observation_from_options(obs, concentration, mean_thickness, diameters, percentages)
    trange = _parse_floats(thickness_range, "thickness_range")
    if trange is not None and len(trange) != 2:
        raise InputError(
            "thickness_range", f"{thickness_range!r} needs two values MIN,MAX", allowed="MIN,MAX [m]"
        )
    for path, name in ((out, "out"), (figure, "figure"), (geojson, "geojson")):
        if path is not None and not path.parent.exists():
            raise InputError(
                name, f"directory {str(path.parent)!r} does not exist", allowed="an existing directory"
            )
    floe_field = generate_field(
        observation,
        length_m=length,
        width_m=width,
        rng=np.random.default_rng(seed),
        generator=generator.value,
        thickness_m=thickness,
        thickness_range_m=trange,
        seed=seed,
    )
    save_field(floe_field, out, field="out")
    written = [str(out)]
    if geojson is not None:
        export_geojson(floe_field, geojson, field="geojson")
        written.append(str(geojson))
    if figure is not None:
        from floebreak.io.figures import save_figure
        from floebreak.plotting.field import plot_field

        save_figure(plot_field(floe_field), figure, field="figure")
        written.append(str(figure))
    console.print(
        f"{floe_field.n_floes} floes, concentration {100 * floe_field.concentration:.2f} % "
        f"(target {100 * observation.concentration:g} %) → {', '.join(written)}"
    )


def _observation_from_options(obs, concentration, mean_thickness, diameters, percentages) -> Observation:
    user_values = (concentration, mean_thickness, diameters, percentages)
    if obs is not None:
        if any(v is not None for v in user_values):
            raise InputError("obs", "give either --obs or a user observation, not both")
        return get_observation(obs)
    if any(v is None for v in user_values):
        raise InputError(
            "obs",
            "no observation given",
            allowed="--obs KEY, or all of --concentration --mean-thickness --diameters --percentages",
        )
    return Observation(
        concentration=concentration,
        mean_thickness_m=mean_thickness,
        diameter_classes_m=_parse_floats(diameters, "diameters"),
        percentages=_parse_floats(percentages, "percentages"),
    )


REFERENCE_OBSERVATION = "2019-12-18T20:20"  # thesis §5.3 reference scenario


@app.command()
def demo(
    out: Annotated[Path, typer.Option("--out", help="output directory")] = Path("demo-output"),
    overwrite: Annotated[
        bool, typer.Option("--overwrite", help="replace an existing output directory")
    ] = False,
    seed: Annotated[int, typer.Option("--seed", help="random seed")] = 1,
) -> None:
    """Reference scenario: the thesis' floe field (obs 2019-12-18T20:20, 400 m × 50 m, h = 1 m) and the bow.

    Writes field.parquet, field.geojson and figures/ into OUT (atomically: a failed demo leaves nothing).
    """
    import time

    from floebreak.ice.generation import generate_field
    from floebreak.io.atomic import atomic_directory
    from floebreak.io.field_files import export_geojson, save_field
    from floebreak.io.figures import save_figure
    from floebreak.plotting.field import plot_field

    started = time.perf_counter()
    observation = get_observation(REFERENCE_OBSERVATION)
    with console.status("generating the reference floe field …"):
        floe_field = generate_field(
            observation, 400.0, 50.0, np.random.default_rng(seed), thickness_m=1.0, seed=seed
        )
    with atomic_directory(out, overwrite=overwrite, field="out") as temp:
        save_field(floe_field, temp / "field.parquet")
        export_geojson(floe_field, temp / "field.geojson")
        (temp / "figures").mkdir()
        save_figure(plot_field(floe_field), temp / "figures" / "field.png")
        try:
            from floebreak.plotting.bow import plot_bow
            from floebreak.ship.hulls import agulhas_ii

            save_figure(plot_bow(agulhas_ii(ice_thickness_m=1.0)), temp / "figures" / "bow_agulhas_ii.png")
        except ImportError:  # pragma: no cover - the bow module ships with the package
            pass
    table = Table(title=f"floebreak demo: reference floe field (obs {REFERENCE_OBSERVATION}, seed {seed})")
    table.add_column("quantity")
    table.add_column("value", justify="right")
    table.add_row("floes", f"{floe_field.n_floes}")
    table.add_row(r"ice area \[m²]", f"{floe_field.ice_area_m2:.1f}")
    table.add_row(
        r"concentration \[%] (target)",
        f"{100 * floe_field.concentration:.2f} ({100 * observation.concentration:g})",
    )
    table.add_row(r"thickness \[m]", "1.0")
    table.add_row(r"wall time \[s]", f"{time.perf_counter() - started:.1f}")
    console.print(table)
    console.print(f"written: {out}/field.parquet, field.geojson, figures/")


@app.callback()
def _root() -> None:
    """floebreak: ship bow breaking sea-ice floes, and the cusps' propeller–ice loads."""


def main() -> None:
    """Entry point. A user error (InputError) prints one line naming the field and exits with code 2."""
    try:
        app()
    except InputError as error:
        err_console.print(f"[bold red]error:[/] {error}")
        sys.exit(2)

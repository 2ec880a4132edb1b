"""The one check that a CSV input is comma-separated (voyage logs, measured torque series)."""

from __future__ import annotations

from floebreak.errors import InputError


def check_comma_separated(where: str, header: list[str], raw: str) -> None:
    """A file separated by semicolons or tabs (a spreadsheet's export where the decimal mark is a comma) is
    read as one column: name the separator (InputError at `where`), not a missing column or its "unit"."""
    if len(header) != 1:
        return
    for separator, name in ((";", "semicolons"), ("\t", "tabs")):
        if separator in raw:
            raise InputError(
                where,
                f"the columns are separated by {name}, not by commas (a spreadsheet export for a locale with "
                "a decimal comma?)",
                allowed="a comma-separated file with decimal points (e.g. 0.5, not 0,5): export as CSV with "
                "',' as the separator and '.' as the decimal mark",
            )

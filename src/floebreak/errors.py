"""Errors that floebreak reports to users.

`InputError` is raised for anything a user can fix (a value out of range, a malformed file, an
unknown key). Its message always names the offending field and the allowed values or range, and
the CLI turns it into exit code 2. Everything else is a bug and exits with code 1.
"""

from __future__ import annotations

import dataclasses
import functools
import typing
from dataclasses import dataclass
from typing import Any


class InputError(ValueError):
    """A user input is invalid. The message names the field and what is allowed."""

    def __init__(self, field: str, message: str, *, value: Any = None, allowed: str | None = None):
        self.field = field
        self.value = value
        self.allowed = allowed
        text = f"{field}: {message}"
        if allowed is not None and allowed not in message:
            text += f" (allowed: {allowed})"
        super().__init__(text)


def csv_where(source: str, column: str | None = None, row: int | None = None, line: int | None = None) -> str:
    """The InputError key of a place in a CSV file, the same for every CSV reader: the file, the data row
    (counted from 1 after the header; comment and blank lines not counted) with its line in the file, and the
    column — ``log.csv, row 2 (line 3), column 'x_m'``; ``log.csv, header (line 1)`` for the header."""
    text = source
    if row is not None:
        text += f", row {row} (line {line})"
    elif line is not None:
        text += f", header (line {line})"
    if column is not None:
        text += f", column {column!r}"
    return text


def require_range(
    field: str,
    value: float,
    *,
    low: float | None = None,
    high: float | None = None,
    low_inclusive: bool = False,
    high_inclusive: bool = True,
    unit: str = "",
) -> float:
    """Return `value` as float if it lies in the interval, else raise InputError naming `field`.

    The interval is (low, high] by default; NaN is always rejected.
    """
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise InputError(field, f"{value!r} is not a number", value=value) from None
    left = "[" if low_inclusive else "("
    right = "]" if high_inclusive else ")"
    lo_text = "-inf" if low is None else f"{low:g}"
    hi_text = "inf" if high is None else f"{high:g}"
    interval = f"{left}{lo_text}, {hi_text}{right}" + (f" {unit}" if unit else "")
    ok = number == number  # NaN check
    if ok and low is not None:
        ok = number >= low if low_inclusive else number > low
    if ok and high is not None:
        ok = number <= high if high_inclusive else number < high
    if not ok:
        raise InputError(field, f"{number:g} is outside {interval}", value=number, allowed=interval)
    return number


@dataclass(frozen=True)
class Bounds:
    """The allowed interval of a setting, carried in its type: ``x: Annotated[float, Bounds(0.0, 60.0)]``.

    One source for the range check of a settings dataclass (`check_bounds`, from its ``__post_init__``) and
    for the scenario table built from it (`floebreak.config.scenario`: validation and ``floebreak schema``).
    """

    low: float
    high: float
    low_inclusive: bool = True
    high_inclusive: bool = True
    unit: str = ""

    def check(self, field: str, value: float) -> float:
        return require_range(
            field,
            value,
            low=self.low,
            high=self.high,
            low_inclusive=self.low_inclusive,
            high_inclusive=self.high_inclusive,
            unit=self.unit,
        )

    def pydantic_constraints(self) -> dict[str, float]:
        """The keyword arguments of ``pydantic.Field`` (ge/gt, le/lt) for this interval."""
        return {
            "ge" if self.low_inclusive else "gt": self.low,
            "le" if self.high_inclusive else "lt": self.high,
        }


@functools.cache
def field_bounds(cls: type) -> dict[str, Bounds]:
    """Field name → its `Bounds`, for the fields of dataclass `cls` annotated with one."""
    hints = typing.get_type_hints(cls, include_extras=True)
    found = {}
    for field in dataclasses.fields(cls):
        for extra in getattr(hints[field.name], "__metadata__", ()):
            if isinstance(extra, Bounds):
                found[field.name] = extra
    return found


def check_bounds(settings: Any, prefix: str) -> None:
    """Range-check every `Bounds`-annotated field of the dataclass instance `settings`; an InputError names
    ``<prefix>.<field>``, the value and the interval."""
    for name, bounds in field_bounds(type(settings)).items():
        bounds.check(f"{prefix}.{name}", getattr(settings, name))

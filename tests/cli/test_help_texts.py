"""Help texts: every command's --help names its arguments in capitals, shows no `<bool>` or
`{ARG}` placeholders, prints units such as [m] (not eaten as markup) and has no double spaces in its texts;
Python errors name the Python parameter; a semicolon-separated torque CSV gets a clear error."""

from __future__ import annotations

import re

import pytest
import typer.main
from typer.testing import CliRunner

from floebreak.app.inputs import read_torque_csv
from floebreak.cli import app
from floebreak.errors import InputError
from floebreak.io.atomic import atomic_directory


def _commands(command, path=()):
    yield path, command
    for name, sub in getattr(command, "commands", {}).items():
        yield from _commands(sub, (*path, name))


COMMANDS = list(_commands(typer.main.get_command(app)))


@pytest.mark.parametrize("path", [p for p, _ in COMMANDS], ids=lambda p: " ".join(p) or "floebreak")
def test_help_has_no_placeholders_and_no_double_spaces(path):
    result = CliRunner().invoke(app, [*path, "--help"], env={"COLUMNS": "240"})
    assert result.exit_code == 0, result.output
    text = result.output
    assert "<bool>" not in text
    usage = next(line for line in text.splitlines() if "Usage:" in line)
    assert not re.search(r"\{[^}]*\}", usage), usage
    assert "thin typer" not in text
    command = dict(COMMANDS)[path]
    ctx = command.make_context("floebreak", [], resilient_parsing=True)
    texts = [command.help or ""] + [getattr(p, "help", None) or "" for p in command.get_params(ctx)]
    for piece in texts:
        assert "  " not in re.sub(r"\s*\n\s*", " ", piece), piece
    for param in command.get_params(ctx):
        if param.param_type_name == "argument":
            assert param.metavar == param.metavar.upper() and param.metavar in usage


def test_units_in_brackets_are_printed():
    text = CliRunner().invoke(app, ["field", "--help"], env={"COLUMNS": "240"}).output
    assert "field length along x [m]" in text


def test_the_top_level_description_is_for_users():
    text = CliRunner().invoke(app, ["--help"], env={"COLUMNS": "240"}).output
    assert "floebreak demo --out demo-output" in text and "typer" not in text


def test_python_errors_name_the_python_parameter(tmp_path):
    with pytest.raises(InputError) as info, atomic_directory(tmp_path):
        pass
    assert "overwrite=True" in str(info.value) and "pass --overwrite" not in str(info.value)


@pytest.mark.parametrize(("separator", "name"), [(";", "semicolons"), ("\t", "tabs")])
def test_a_torque_csv_not_separated_by_commas_is_named(tmp_path, separator, name):
    path = tmp_path / "torque.csv"
    path.write_text(
        f"time_s{separator}torque_kNm\n0{separator}100,5\n0.1{separator}101,0\n", encoding="utf-8"
    )
    with pytest.raises(InputError, match=f"separated by {name}, not by commas") as info:
        read_torque_csv(path)
    assert info.value.field.startswith("torque_csv")

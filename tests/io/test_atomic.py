"""Atomic writes (`floebreak.io.atomic`): all or nothing, and results readable like any other file."""

from __future__ import annotations

import os
import stat

import pytest

from floebreak.io.atomic import atomic_directory, atomic_path


def umask() -> int:
    value = os.umask(0)
    os.umask(value)
    return value


def test_atomic_file_gets_the_umask_mode_not_the_private_temporary_one(tmp_path):
    target = tmp_path / "report.html"
    with atomic_path(target) as temp:
        temp.write_text("x")
    assert target.read_text() == "x"
    assert stat.S_IMODE(target.stat().st_mode) == 0o666 & ~umask()


def test_atomic_directory_gets_the_umask_mode(tmp_path):
    target = tmp_path / "run"
    with atomic_directory(target) as temp:
        (temp / "a.txt").write_text("a")
    assert stat.S_IMODE(target.stat().st_mode) == 0o777 & ~umask()


def test_a_failed_write_leaves_nothing(tmp_path):
    target = tmp_path / "out.txt"
    with pytest.raises(RuntimeError), atomic_path(target) as temp:
        temp.write_text("half")
        raise RuntimeError("boom")
    assert list(tmp_path.iterdir()) == []
    with pytest.raises(RuntimeError), atomic_directory(tmp_path / "dir") as temp:
        (temp / "half.txt").write_text("half")
        raise RuntimeError("boom")
    assert list(tmp_path.iterdir()) == []

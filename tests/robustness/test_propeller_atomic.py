"""`floebreak propeller RUN --out P --shaft-line …` writes P (with shaft/) as one directory: a full disk
while the shaft analysis is written is exit 3 and leaves no P at all; a normal run has both."""

from __future__ import annotations

import errno

import floebreak.app.propeller_output
import floebreak.app.shaft


def test_a_full_disk_in_the_shaft_files_leaves_no_propeller_directory(
    cli, tmp_path, monkeypatch, small_run_dir
):
    def full(result, out_dir, **kwargs):
        out_dir.mkdir()
        (out_dir / "shaft_series.nc").write_bytes(b"half")
        raise OSError(errno.ENOSPC, "No space left on device", str(out_dir / "shaft_series.nc"))

    monkeypatch.setattr(floebreak.app.shaft, "write_shaft_analysis", full)
    out = tmp_path / "p"
    code, stdout, err = cli("propeller", small_run_dir, "--out", out, "--shaft-line", "agulhas_ii", "-q")
    assert code == 3, err
    assert "No space left on device" in err and "Traceback" not in err
    assert not out.exists()
    assert list(tmp_path.iterdir()) == []  # no temporary left either
    assert "written" not in stdout


def test_too_little_free_space_is_refused_before_writing(cli, tmp_path, monkeypatch, small_run_dir):
    monkeypatch.setattr(floebreak.app.propeller_output, "MIN_FREE_BYTES", 2**62)
    out = tmp_path / "p"
    code, _, err = cli("propeller", small_run_dir, "--out", out, "-q")
    assert code == 3, err
    assert "No space left on device" in err and "MB needed" in err
    assert not out.exists()


def test_the_propeller_directory_holds_the_shaft_analysis(cli, tmp_path, small_run_dir):
    out = tmp_path / "p"
    code, stdout, err = cli("propeller", small_run_dir, "--out", out, "--shaft-line", "agulhas_ii", "-q")
    assert code == 0, err
    assert (out / "summary.json").is_file() and (out / "shaft" / "summary.json").is_file()
    assert not stdout.startswith("1 run")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["p"]

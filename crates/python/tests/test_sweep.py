"""Sweeps: the same rows from `wearsim sweep`, from wornjoint.sweep on threads and on Dask."""

import csv
import subprocess

import pytest

import wornjoint

SWEEP = """
scene = "slider-crank"
samples = 16
seed = 2026
metrics = [
    "response.joints.rod-slider.max_penetration_m",
    "response.joints.rod-slider.normal_force_all.max",
    "response.dissipated_per_cycle_j",
]

[run]
cycles = 1

[[vary]]
path = "clearance_joints.rod-slider.clearance"
distribution = "uniform"
low = 2e-4
high = 5e-4

[[vary]]
path = "drivers.crank-speed.law.rate"
distribution = "normal"
mean = 200.0
sd = 20.0

[[vary]]
path = ["clearance_joints.rod-slider.bearing_material.youngs_modulus", "clearance_joints.rod-slider.pin_material.youngs_modulus"]
name = "youngs_modulus"
distribution = "log-normal"
median = 207e9
sigma = 0.3
"""


def rows(path):
    """The rows without the wall-time column (the one column that may differ)."""
    with open(path, newline="") as f:
        table = list(csv.reader(f))
    assert table[0][-1] == "wall_time_s"
    return [r[:-1] for r in table]


def assert_progress_lines(err, label, total):
    """Progress on a standard error that is not a terminal: every update a line of its own
    (none runs into the next), counting up to the total."""
    assert "\r" not in err, repr(err)
    lines = [l for l in err.splitlines() if l.startswith(label + ":")]
    assert lines, repr(err)
    assert all(l.count("samples") == 1 for l in lines), lines
    counts = [int(l.split(": ")[1].split("/")[0]) for l in lines]
    assert counts == sorted(counts) and counts[-1] == total, lines
    assert lines[-1].startswith(f"{label}: {total}/{total} samples"), lines


@pytest.fixture(scope="module")
def sweep_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("sweep") / "ps.toml"
    path.write_text(SWEEP)
    return path


def test_sixteen_samples_same_rows_on_every_engine(sweep_file, tmp_path, wearsim, capfd):
    cli = tmp_path / "cli"
    subprocess.run([wearsim, "sweep", str(sweep_file), "--out", str(cli)], check=True, capture_output=True)
    expected = rows(cli / "samples.csv")
    assert len(expected) == 17
    assert expected[0][:4] == ["sample", "clearance_joints.rod-slider.clearance", "drivers.crank-speed.law.rate", "youngs_modulus"]
    status = expected[0].index("status")
    assert sum(r[status] == "ok" for r in expected[1:]) == 16, expected

    capfd.readouterr()
    local = wornjoint.sweep(sweep_file, out=tmp_path / "local")
    assert_progress_lines(capfd.readouterr().err, "sweep ps", 16)
    assert rows(tmp_path / "local" / "samples.csv") == expected
    assert len(local) == 16 and (local["status"] == "ok").all()
    assert (tmp_path / "local" / "scatter.png").is_file()
    assert (tmp_path / "local" / "histograms.png").is_file()

    from distributed import Client, LocalCluster

    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        with Client(cluster) as client:
            assert len(client.scheduler_info()["workers"]) == 2
            capfd.readouterr()
            dask = wornjoint.sweep(sweep_file, client, out=tmp_path / "dask")
            assert_progress_lines(capfd.readouterr().err, "sweep ps", 16)
    assert rows(tmp_path / "dask" / "samples.csv") == expected
    assert dask.drop(columns="wall_time_s").equals(local.drop(columns="wall_time_s"))


def test_bad_sweep_names_the_field(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text(SWEEP.replace("sd = 20.0", "sd = -20.0"))
    with pytest.raises(wornjoint.SweepError, match=r"vary\[1\]\.sd") as e:
        wornjoint.sweep(path)
    assert isinstance(e.value, ValueError)
    path.write_text(SWEEP.replace("crank-speed.law", "crank.law"))
    with pytest.raises(wornjoint.SweepError, match=r"vary\[1\]\.path"):
        wornjoint.sweep(path)


def test_failed_sample_is_a_row_and_resume_skips_rows(tmp_path):
    path = tmp_path / "grid.toml"
    path.write_text(
        """
scene = "slider-crank"
metrics = ["response.joints.rod-slider.max_penetration_m"]
[run]
cycles = 1
[[vary]]
path = "clearance_joints.rod-slider.clearance"
values = [4e-4, -1e-4, 5e-4]
[[vary]]
path = "drivers.crank-speed.law.rate"
values = [200.0]
"""
    )
    out = tmp_path / "out"
    first = wornjoint.sweep(path, out=out)
    assert list(first["status"]) == ["ok", "failed", "ok"]
    assert "clearance_joints[0].clearance" in first["error"][1]
    # Drop the last row, resume: only it runs again, and the file is whole again.
    table = rows(out / "samples.csv")
    with open(out / "samples.csv") as f:
        lines = f.read().splitlines()
    (out / "samples.csv").write_text("\n".join(lines[:-1]) + "\n")
    again = wornjoint.sweep(path, out=out, resume=True)
    assert rows(out / "samples.csv") == table
    assert again["wall_time_s"][0] == first["wall_time_s"][0]

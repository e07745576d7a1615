"""Scenes, runs and errors of the wornjoint package, against `wearsim run`."""

import csv
import json
import subprocess
import threading
import time

import numpy as np
import pytest

import wornjoint


def strip_wall_times(value):
    """The summary without its wall times (the only numbers that differ between runs)."""
    if isinstance(value, dict):
        return {k: strip_wall_times(v) for k, v in value.items() if "wall_time" not in k}
    if isinstance(value, list):
        return [strip_wall_times(v) for v in value]
    return value


def read_csv(path):
    """Columns of a wearsim CSV, names without units, values parsed exactly."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    names = [h.split(" [")[0] for h in rows[0]]
    data = np.array([[float(x) for x in r] for r in rows[1:]])
    return {n: data[:, k] for k, n in enumerate(names)}


def assert_same_table(array, path):
    columns = read_csv(path)
    assert list(array.dtype.names) == list(columns)
    for name, values in columns.items():
        # Bit for bit: the CSV holds shortest round-trip decimals.
        assert np.array_equal(array[name], values), name


def test_scenes_and_load():
    names = wornjoint.scenes()
    assert "lgres" in names and "slider-crank" in names
    scene = wornjoint.load("lgres")
    assert isinstance(scene, dict) and scene.name == "lgres"
    assert [j["name"] for j in scene["clearance_joints"]] == ["A", "B"]
    assert scene["clearance_joints"][0]["clearance"] == 0.0005
    # A variant has its base merged in.
    c02 = wornjoint.load("lgres-c02")
    assert c02["clearance_joints"][0]["clearance"] == 0.0002
    assert len(c02["bodies"]) == 5
    with pytest.raises(wornjoint.SceneError, match="no built-in scene"):
        wornjoint.load("no-such-scene")


def test_run_equals_wearsim_bit_for_bit(tmp_path, wearsim):
    out = tmp_path / "cli"
    subprocess.run(
        [wearsim, "run", "lgres", "--cycles", "1", "--stages", "0", "--out", str(out)],
        check=True,
        capture_output=True,
    )
    r = wornjoint.run("lgres", cycles=1, stages=0)
    cli = json.loads((out / "summary.json").read_text())
    assert r.summary["response"]["dissipated_per_cycle_j"] == cli["response"]["dissipated_per_cycle_j"]
    assert strip_wall_times(r.summary) == strip_wall_times(cli)
    assert_same_table(r.response, out / "response.csv")
    assert_same_table(r.contact, out / "contact.csv")
    assert r.worn_response is None and r.wear == {}
    # An edited dict runs the same as the file it came from.
    again = wornjoint.run(wornjoint.load("lgres"), cycles=1, stages=0)
    assert np.array_equal(again.contact["B_Fn"], r.contact["B_Fn"])


def test_a_result_shows_its_report_in_a_notebook(tmp_path, wearsim):
    scene = tmp_path / "short.toml"
    scene.write_text(
        'extends = "slider-crank"\n'
        "[[clearance_joints]]\n"
        'name = "rod-slider"\n'
        "wear = { k_d = 1.8e-13, width = 0.02, cells = 360 }\n"
        "[run]\ncycles = 2\nwear_stages = 1\ncycles_per_stage = 2\namplification = 750.0\n"
    )
    r = wornjoint.run(scene, out=tmp_path / "out")
    html = r._repr_html_()
    assert html is r.report_html(), "drawn once, then kept"
    assert html.startswith('<div class="wj-report">') and html.rstrip().endswith("</div>")
    for heading in ("Contact force peaks", "Energy books, per cycle", "Wear", "Figures"):
        assert f"<h2>{heading}</h2>" in html, heading
    assert "<h2>Files</h2>" not in html, "the notebook has no files beside it"
    assert "http://" not in html and "https://" not in html
    # The same figures as the run's own report.html, embedded.
    page = (tmp_path / "out" / "report.html").read_text()
    figures = [f for f in page.split('src="')[1:]]
    assert len(figures) >= 8
    assert html.count('src="data:image/') == page.count('src="data:image/')
    # The verdict cells are the page's (the wall times differ between the two drawings).
    assert html.count('<td class="ok">') + html.count('<td class="bad">') == page.count(
        '<td class="ok">'
    ) + page.count('<td class="bad">')


def test_wear_stage_equals_wearsim(tmp_path, wearsim):
    # The machinery (a wear stage of sub-steps on two trajectories, its files), not the whole
    # life: the default LGRES stage with 1/40 of its amplification, a few sub-steps.
    scene = tmp_path / "short-stage.toml"
    scene.write_text('extends = "lgres"\n[run]\namplification = 500.0\n')
    out = tmp_path / "cli"
    args = ["--cycles", "1", "--stages", "1", "--out", str(out)]
    subprocess.run([wearsim, "run", str(scene), *args], check=True, capture_output=True)
    r = wornjoint.run(scene, cycles=1, stages=1)
    assert r.summary["wear"]["substeps_per_stage"][0] >= 2, "a stage of sub-steps"
    cli = json.loads((out / "summary.json").read_text())
    assert strip_wall_times(r.summary) == strip_wall_times(cli)
    for joint in ("A", "B"):
        w = read_csv(out / f"wear_{joint}_stage1.csv")
        assert r.wear[joint]["bearing"].shape == (1, len(w["angle"]))
        assert np.array_equal(r.wear[joint]["bearing"][0], w["bearing_depth"])
        assert np.array_equal(r.wear[joint]["pin"][0], w["pin_depth"])
        assert np.array_equal(r.wear[joint]["angle_deg"], w["angle"])
    assert_same_table(r.worn_contact, out / "contact_worn.csv")


def test_a_life_to_the_limit_is_a_distribution_frame(tmp_path):
    # The worn slider-crank run until 0.6 mm, k_d scattering by 0.4 in ln k_d.
    scene = tmp_path / "life.toml"
    scene.write_text(
        'extends = "slider-crank"\n'
        "[[clearance_joints]]\n"
        'name = "rod-slider"\n'
        "wear = { k_d = 1.8e-13, width = 0.02, cells = 360, k_d_scatter = 0.4 }\n"
        "[run]\ncycles = 1\nwear_stages = 1\ncycles_per_stage = 2\namplification = 1e5\n"
        "animation = false\nclearance_limit = 0.0006\nuntil_limit = true\nmax_cycles = 2e5\n"
    )
    out = tmp_path / "out"
    r = wornjoint.run(scene, out=out)
    limit = r.summary["wear"]["joints"][0]["clearance_limit"]
    frame = r.frame("life_distribution")
    assert list(frame.columns) == ["cycles", "failed_rod-slider"]
    # The lognormal's distribution function passes 10 % and 50 % at B10 and B50.
    for b, p in ((limit["b10_cycles"], 0.1), (limit["b50_cycles"], 0.5)):
        assert abs(np.interp(np.log(b), np.log(frame["cycles"]), frame["failed_rod-slider"]) - p) < 2e-3
    # The same numbers as the run's life_distribution.csv, bit for bit.
    assert_same_table(r.life_distribution, out / "life_distribution.csv")
    assert (out / "life_distribution.png").is_file()
    # Without a limit there is none.
    assert wornjoint.run("slider-crank", cycles=1, stages=0).life_distribution is None


def test_bad_values_name_the_field():
    scene = wornjoint.load("lgres")
    scene["clearance_joints"][0]["clearance"] = -0.0005
    with pytest.raises(wornjoint.SceneError) as e:
        wornjoint.run(scene, cycles=1, stages=0)
    assert isinstance(e.value, ValueError)
    assert "clearance_joints[0].clearance = -0.0005: must be positive" in str(e.value)

    scene = wornjoint.load("lgres")
    scene["bodies"][1]["mass"] = "heavy"
    with pytest.raises(ValueError, match=r"bodies\[1\]\.mass"):
        wornjoint.run(scene)
    scene = wornjoint.load("lgres")
    scene["bodies"][0]["colour"] = "red"
    with pytest.raises(wornjoint.SceneError, match="colour"):
        scene.check()
    scene = wornjoint.load("lgres")
    scene["solver"]["rtol"] = object()
    with pytest.raises(wornjoint.SceneError, match=r"solver\.rtol"):
        wornjoint.run(scene)
    with pytest.raises(wornjoint.SceneError, match="solver.rtol"):
        wornjoint.run("slider-crank", rtol=-1.0)
    with pytest.raises(wornjoint.SceneError, match=r"run\.wear_tolerance = 2"):
        wornjoint.run("slider-crank", wear_tolerance=2.0)


def test_run_failure_raises_run_error():
    with pytest.raises(wornjoint.RunError, match="max_steps") as e:
        wornjoint.run("slider-crank", cycles=1, max_steps=10)
    assert not isinstance(e.value, ValueError)


def test_runs_release_the_gil():
    done = threading.Event()
    results = []

    def work():
        results.append(wornjoint.run("lgres", cycles=1, stages=0))
        done.set()

    t = threading.Thread(target=work)
    t.start()
    ticks = 0
    while not done.is_set():
        ticks += 1
        time.sleep(0.001)
    t.join()
    # Held GIL: this loop could not run while the simulation (about a second) does.
    assert ticks > 50, ticks
    # Two threads at once give the same numbers as one.
    pair = []
    threads = [threading.Thread(target=lambda: pair.append(wornjoint.run("slider-crank", cycles=1))) for _ in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    one = wornjoint.run("slider-crank", cycles=1)
    for r in pair:
        assert np.array_equal(r.contact["rod-slider_Fn"], one.contact["rod-slider_Fn"])

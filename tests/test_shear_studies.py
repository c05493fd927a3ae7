"""Sheared studies (``shear_rate``, a grid column) and the flow curve ``hardspheres plot flow`` draws.

Checked here: the key's parsing (one rate or a list, the default measures,
the rescaling's interval per task), bad specs refused naming the key, one
tiny task run to its row, and the flow curve written from a small results
table (no simulation in the picture: it reads results).
"""

import pandas as pd
import pytest
from helpers import hs_cmd

from hardspheres.errors import StudyError
from hardspheres.studies import parse_study, tasks

BASE = {"packing": 0.3, "n": 64, "output": "x"}


def test_a_shear_rate_list_is_a_grid_column_with_its_measures():
    study = parse_study({**BASE, "shear_rate": [0.1, 2.0], "seeds": 2})
    assert study["shear_rate"] == [0.1, 2.0] and study["measure"] == ["viscosity", "temperature"]
    ts = tasks(study)
    assert [(t["shear_rate"], t["rescale_interval"], t["seed"]) for t in ts] == [
        (0.1, 0.05, 0), (0.1, 0.05, 1), (2.0, 0.005, 0), (2.0, 0.005, 1)
    ]  # fmt: skip
    assert len({t["key"] for t in ts}) == 4
    plain = tasks(parse_study(BASE))[0]
    assert "shear_rate" not in plain and "rescale_interval" not in plain  # (its key is unchanged)
    one = tasks(parse_study({**BASE, "shear_rate": -0.5, "rescale_interval": 0.02}))
    assert [(t["shear_rate"], t["rescale_interval"]) for t in one] == [(-0.5, 0.02)]


def test_a_sheared_granular_task_has_no_thermostat():
    from hardspheres.studies.task import _build

    ts = tasks(parse_study({**BASE, "shear_rate": 0.5, "restitution": [0.9, 1.0]}))
    assert [(t["restitution"], "rescale_interval" in t) for t in ts] == [(0.9, False), (1.0, True)]
    sim = _build(ts[0])
    assert sim.container.shear_rate == 0.5 and sim.thermostat is None and sim.inelastic


@pytest.mark.parametrize(
    ("extra", "words"),
    [
        ({"shear_rate": 0}, ["shear_rate = 0", "other than 0"]),
        ({"shear_rate": "fast"}, ["shear_rate = 'fast'"]),
        ({"shear_rate": []}, ["shear_rate is an empty list"]),
        ({"shear_rate": [0.5, 0.5]}, ["shear_rate lists a rate twice"]),
        ({"shear_rate": 0.5, "container": "sphere"}, ['shear_rate needs container = "box"']),
        ({"shear_rate": 0.5, "method": "ecmc"}, ['shear_rate needs method = "edmd"']),
        ({"shear_rate": 0.5, "pressure": 2.0}, ["shear_rate needs constant volume"]),
        ({"shear_rate": 0.5, "restitution": 0.8, "kicks": 1.0, "kick_interval": 0.05},
         ["shear_rate needs no kicks"]),
        ({"rescale_interval": 0.1}, ["rescale_interval is for a sheared box"]),
        ({"shear_rate": 0.5, "rescale_interval": -1}, ["rescale_interval = -1"]),
        ({"measure": ["viscosity"]}, ["viscosity is measured in a sheared box"]),
        ({"shear_rate": 0.5, "dimensions": 2, "measure": ["normal_stress_2"]}, ["3-D only"]),
        ({"shear_rate": 0.5, "measure": ["a2"]}, ["a2 is not measured in a sheared gas"]),
    ],
)  # fmt: skip
def test_bad_shear_specs_are_refused_naming_the_key(extra, words):
    with pytest.raises(StudyError) as e:
        parse_study({**BASE, **extra})
    assert "\n" not in str(e.value)
    for w in words:
        assert w in str(e.value), str(e.value)


def test_a_tiny_sheared_task_runs_to_its_row(tmp_path):
    from hardspheres.dense import PeculiarRescale
    from hardspheres.studies.task import _build, run_task

    spec = {**BASE, "output": str(tmp_path), "shear_rate": 0.5, "equilibrate": 5, "collisions": 30,
            "blocks": 4, "measure": ["viscosity", "normal_stress_1", "temperature"]}  # fmt: skip
    (task,) = tasks(parse_study(spec))
    sim = _build(task)
    assert sim.container.shear_rate == 0.5 and isinstance(sim.thermostat, PeculiarRescale)
    assert (sim.thermostat.kT, sim.thermostat.interval) == (1.0, 0.05)
    row = run_task(task)
    assert row["shear_rate"] == 0.5 and row["viscosity"] > 0 and row["viscosity_err"] > 0
    assert abs(row["temperature"] - 1.0) < 0.05 and "normal_stress_1_err" in row
    assert run_task(task) == pytest.approx(row)  # (the row file: not run again)


def _table(path, rates=(0.05, 0.2, 1.0, 2.0), packings=(0.3,), seeds=(0, 1)):
    """A sheared study's results table, written by hand: eta thinning with g."""
    rows = [
        {"method": "edmd", "container": "box", "dimensions": 3, "aspect": "", "packing": phi, "n": 64,
         "radius_ratio": 1.0, "mass_ratio": 1.0, "shear_rate": g, "seed": s,
         "viscosity": (1.0 + phi) / (1.0 + 0.1 * g) + 0.01 * s, "viscosity_err": 0.02,
         "temperature": 1.0, "temperature_err": 0.001}
        for phi in packings for g in rates for s in seeds
    ]  # fmt: skip
    pd.DataFrame(rows).to_csv(path, index=False)
    return path


def test_the_flow_curve_is_drawn_on_log_axes_when_the_rates_span_a_decade(tmp_path, monkeypatch):
    pytest.importorskip("matplotlib")
    from hardspheres.viz import plots

    figures = []
    save = plots._save
    monkeypatch.setattr(plots, "_save", lambda fig, path, dpi: figures.append(fig) or save(fig, path, dpi))
    table = _table(tmp_path / "results.csv", packings=(0.2, 0.3))
    out = plots.plot_flow(table, tmp_path / "flow.png")
    assert out.read_bytes()[:4] == b"\x89PNG"
    ax = figures[-1].axes[0]
    assert ax.get_xscale() == "log" and ax.get_yscale() == "linear"  # (eta within a decade)
    assert len(ax.get_legend().get_texts()) == 2  # a series per packing
    plots.plot_flow(_table(tmp_path / "narrow.csv", rates=(0.5, 1.0, 2.0)), tmp_path / "narrow.png")
    assert figures[-1].axes[0].get_xscale() == "linear"
    thinning = pd.read_csv(_table(tmp_path / "wide.csv", rates=(0.01, 1.0, 100.0)))
    thinning["viscosity"] = 1.0 / (1.0 + thinning["shear_rate"])
    plots.plot_flow(thinning, tmp_path / "thinning.png")
    assert figures[-1].axes[0].get_xscale() == "log" and figures[-1].axes[0].get_yscale() == "log"


def test_plot_flow_command_writes_the_picture_or_refuses_in_one_line(tmp_path):
    pytest.importorskip("matplotlib")
    _table(tmp_path / "results.csv")
    r = hs_cmd("plot", "flow", "results.csv", "-o", "flow.svg", cwd=tmp_path, check=True)
    assert "wrote flow.svg" in r.stdout and (tmp_path / "flow.svg").stat().st_size > 0
    pd.DataFrame({"packing": [0.3], "n": [64], "seed": [0], "Z": [2.0], "Z_err": [0.1]}).to_csv(
        tmp_path / "plain.csv", index=False
    )
    bad = hs_cmd("plot", "flow", "plain.csv", "-o", "bad.png", cwd=tmp_path)
    assert bad.returncode == 1 and bad.stdout == "" and "Traceback" not in bad.stderr
    assert len(bad.stderr.strip().splitlines()) == 1 and "sheared study" in bad.stderr


def test_a_results_csv_with_the_cubes_empty_aspect_is_plotted(tmp_path):
    """A 3-D study's results.csv holds aspect "" (the cube), which pandas reads back as NaN."""
    pytest.importorskip("matplotlib")
    from hardspheres.viz import plots

    table = _table(tmp_path / "results.csv", packings=(0.2, 0.3))
    assert plots.read_table(table)["aspect"].tolist() == [""] * 16
    plots.plot_sweep(table, tmp_path / "sweep.png", x="packing", y="viscosity")


def test_the_sweeps_progress_names_each_tasks_grid_point():
    """The tasks of a shear_rate (or restitution) list were all said alike: 'box packing=0.3 n=64 seed=0'."""
    from hardspheres.studies.dispatch import _describe

    ts = tasks(parse_study({**BASE, "shear_rate": [0.1, 1.0], "restitution": 0.9, "dimensions": 2}))
    said = [_describe(t) for t in ts]
    assert said == [
        "box packing=0.3 n=64 seed=0 dimensions=2 restitution=0.9 shear_rate=0.1",
        "box packing=0.3 n=64 seed=0 dimensions=2 restitution=0.9 shear_rate=1",
    ]
    assert _describe(tasks(parse_study(BASE))[0]) == "box packing=0.3 n=64 seed=0"

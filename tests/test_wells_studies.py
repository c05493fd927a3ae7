"""Studies with a square well (``well``: [lambda, eps] or a list, grid columns ``well_lambda``, ``well_eps``).

Checked here: the key's parsing (one well or a list, the default
measures), bad specs refused naming the key, one tiny task run to its row.
"""

import pytest

from hardspheres.errors import StudyError
from hardspheres.studies import parse_study, tasks
from hardspheres.studies.spec import GRID

BASE = {"packing": 0.2, "n": 64, "output": "x"}


def test_a_well_list_is_a_grid_with_its_measures():
    study = parse_study({**BASE, "well": [[1.5, 1.0], [1.5, 0.5]], "seeds": 2})
    assert study["well"] == [(1.5, 1.0), (1.5, 0.5)]
    assert study["measure"] == ["Z", "potential_energy", "mean_temperature"]
    ts = tasks(study)
    assert [(t["well_lambda"], t["well_eps"], t["seed"]) for t in ts] == [
        (1.5, 1.0, 0), (1.5, 1.0, 1), (1.5, 0.5, 0), (1.5, 0.5, 1)
    ]  # fmt: skip
    assert len({t["key"] for t in ts}) == 4 and {"well_lambda", "well_eps"} <= set(GRID)
    one = parse_study({**BASE, "well": [1.25, 2]})
    assert one["well"] == [(1.25, 2.0)]
    plain = tasks(parse_study(BASE))[0]
    assert "well_lambda" not in plain  # (studies without a well keep their tasks' keys)


@pytest.mark.parametrize(
    ("extra", "words"),
    [
        ({"well": [1.0, 1.0]}, ["well = [1.0, 1.0] is not allowed", "lambda > 1"]),
        ({"well": [1.5, -1.0]}, ["well = [1.5, -1.0]", "depth eps > 0"]),
        ({"well": [1.5]}, ["well = [1.5]"]),
        ({"well": "deep"}, ["well = 'deep'"]),
        ({"well": [[1.5, 1.0], [1.5, 1.0]]}, ["well lists a well twice"]),
        ({"well": [1.5, 1.0], "restitution": 0.9}, ["well needs elastic collisions"]),
        ({"well": [1.5, 1.0], "pressure": 2.0}, ["well needs constant volume"]),
        ({"well": [1.5, 1.0], "method": "ecmc"}, ['well needs method = "edmd"']),
        ({"well": [1.5, 1.0], "shear_rate": 0.5}, ["well needs no shear"]),
        ({"measure": ["potential_energy"]}, ["potential_energy is measured with a well"]),
    ],
)  # fmt: skip
def test_bad_well_specs_are_refused_naming_the_key(extra, words):
    with pytest.raises(StudyError) as e:
        parse_study({**BASE, **extra})
    assert "\n" not in str(e.value)
    for w in words:
        assert w in str(e.value), str(e.value)


def test_a_tiny_well_task_runs_to_its_row(tmp_path):
    from hardspheres.studies.task import _build, run_task

    spec = {**BASE, "output": str(tmp_path), "well": [1.5, 0.5], "equilibrate": 5, "collisions": 40,
            "blocks": 4, "measure": ["Z", "potential_energy", "mean_temperature", "energy_drift"]}  # fmt: skip
    (task,) = tasks(parse_study(spec))
    sim = _build(task)
    assert sim.steps == ((1.5, -0.5),)
    row = run_task(task)
    assert (row["well_lambda"], row["well_eps"]) == (1.5, 0.5)
    assert row["potential_energy"] < 0 and row["potential_energy_err"] > 0  # per sphere
    assert row["mean_temperature"] > 0 and abs(row["energy_drift"]) < 1e-12
    assert row["Z"] == row["Z"]  # (a number)
    assert run_task(task) == pytest.approx(row)  # (the row file: not run again)

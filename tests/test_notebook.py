"""Jupyter: the viewer inline for simulations and frames, progress bars, the compile note."""

import io

import numpy as np
import pytest

import hardspheres as hs
from hardspheres import progress, simulation
from hardspheres.core import warmup


@pytest.fixture
def shell():
    interactiveshell = pytest.importorskip("IPython.core.interactiveshell")
    sh = interactiveshell.InteractiveShell.instance()
    hs._register_notebook_display(sh)
    yield sh
    interactiveshell.InteractiveShell.clear_instance()


def _html(sh, obj):
    data, _ = sh.display_formatter.format(obj)
    return data.get("text/html")


def test_simulation_and_frames_show_the_viewer(shell, tmp_path):
    box = hs.PeriodicBox(8.0)
    sim = hs.Simulation(hs.random_spheres(50, 0.2, box, seed=1), box)
    page = _html(shell, sim)
    assert page.startswith('<div class="hardspheres-viewer"><iframe srcdoc=')
    assert "50 spheres" in page
    assert "three" in page.lower() and len(page) > 300_000  # three.js embedded: works offline

    sim.writers.append(hs.GSDWriter(tmp_path / "t.gsd", every=0.1))
    sim.run(until=1.0)
    sim.writers[0].close()
    frames = hs.read_trajectory(tmp_path / "t.gsd")  # a trajectory read back
    assert "<iframe" in _html(shell, frames)
    # the plain repr is still there for the terminal
    assert repr(frames).startswith("Frames(n=50")


def test_a_failing_picture_falls_back_to_the_repr(shell):
    bad = hs.Frames([0.0], np.zeros((1, 1, 3)), np.ones((1, 1, 3)), [0.5], [1.0], ["a"], box=4.0)
    bad.positions = None  # cannot be drawn
    assert _html(shell, bad) is None


def test_progress_bar_draws_in_a_notebook():
    class OutStream(io.StringIO):  # what ipykernel gives a cell as stderr
        pass

    OutStream.__module__ = "ipykernel.iostream"
    out = OutStream()
    bar = progress.Progress(10.0, stream=out)
    assert bar.on and bar.every >= 0.25
    bar.update(10.0, label="t=10")
    assert "\r[" in out.getvalue() and "done" in out.getvalue()
    assert not progress.Progress(10.0, stream=io.StringIO()).on  # a file or pipe: silent


def test_first_simulation_announces_the_compilation(monkeypatch, capsys):
    monkeypatch.setattr(simulation, "_WARM", set())
    monkeypatch.setattr(
        warmup, "is_cold", lambda dimensions=3, inelastic=False, sheared=False, stepped=False: True
    )
    monkeypatch.setattr(
        warmup, "_compile", lambda dimensions=3, inelastic=False, sheared=False, stepped=False: None
    )
    box = hs.PeriodicBox(8.0)
    hs.Simulation(hs.random_spheres(20, 0.1, box, seed=1), box)
    hs.Simulation(hs.random_spheres(20, 0.1, box, seed=2), box)
    err = capsys.readouterr().err
    assert err.count("compiling the event core") == 1 and "done in" in err

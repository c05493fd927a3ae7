"""Clustering measures: S(k) at the box's smallest wave vectors and the local density.

Analytic cases: a square lattice commensurate with the box has S = 0 at
every non-reciprocal wave vector and every local packing fraction equal to
the mean; all spheres at one point give S = N.  The direct sum agrees with
the analysis package's S(k) (freud) where both apply.
"""

import sys

import numpy as np
import pytest

import hardspheres as hs
from hardspheres.analysis.granular import LocalDensity, LowKStructureFactor, shell_vectors
from hardspheres.errors import AnalysisInputError, MissingExtraError, PeriodicBoxRequired


def _square(m=10, spacing=2.0):
    """``m * m`` disks of diameter 1 on a square lattice filling the box exactly."""
    side = m * spacing
    g = (np.arange(m) + 0.5) * spacing - side / 2
    x, y = np.meshgrid(g, g, indexing="ij")
    pos = np.stack([x.ravel(), y.ravel()], axis=1)
    state = hs.State(
        masses=np.ones(m * m), radii=np.full(m * m, 0.5), positions=pos, velocities=np.zeros_like(pos)
    )
    return state, (side, side)


def test_shell_vectors_of_a_cube_and_a_rectangle():
    k, shell = shell_vectors((10.0, 10.0, 10.0), 2)
    assert len(k) == 3 + 6 and list(np.bincount(shell)) == [3, 6]  # |n| = 1, then sqrt 2
    assert np.allclose(np.linalg.norm(k[shell == 0], axis=1), 2 * np.pi / 10)
    k, shell = shell_vectors((10.0, 20.0), 1)  # the longer side's vector alone
    assert np.allclose(k, [[0.0, 2 * np.pi / 20]])


def test_a_lattice_has_no_long_wave_fluctuation_and_a_point_has_all():
    state, box = _square()
    s = LowKStructureFactor(shells=3).compute(state, box)
    assert np.all(s.S < 1e-20)
    assert np.isnan(s.times).all() and s.S_frames.shape == (1, 3)
    clump = np.zeros((1, 50, 2))
    assert LowKStructureFactor().compute(clump, box).S[0] == pytest.approx(50.0)


def test_low_k_agrees_with_the_analysis_package():
    pytest.importorskip("freud")
    from hardspheres.analysis.structure import StructureFactor

    box = hs.PeriodicBox.for_packing(300, 0.1)  # (freud's direct S(k): 3-D only)
    sim = hs.Simulation(hs.random_spheres(300, 0.1, box, seed=2), box)
    k1 = 2 * np.pi / box.sides[0]
    ours = LowKStructureFactor().compute(sim)
    theirs = StructureFactor(bins=1, k_min=0.9 * k1, k_max=1.1 * k1).compute(sim)
    assert ours.S[0] == pytest.approx(theirs.S[0], rel=1e-4)


@pytest.mark.parametrize("method", ["cells", "voronoi"])
def test_local_density_of_a_lattice_is_the_mean(method):
    if method == "voronoi":
        pytest.importorskip("freud")
    state, box = _square()
    dens = LocalDensity(method=method, cell=4.0, bins=10).compute(state, box)  # 2 x 2 disks a cell
    phi = 100 * np.pi * 0.25 / (box[0] * box[1])
    assert dens.method == method
    assert np.allclose(dens.values, phi, rtol=1e-9)
    assert dens.counts.sum() == 100


def test_local_density_sees_a_cluster():
    """Half the disks packed in one corner: their cells are denser than the others'."""
    state, box = _square()
    pos = state.positions.copy()
    pos[:50] = pos[:50] * 0.55 - 4.0  # squeezed towards a corner, still apart
    dense = hs.State.from_arrays(
        masses=state.masses, radii=state.radii, positions=pos, velocities=state.velocities
    )
    values = LocalDensity(method="cells", cell=5.0).compute(dense, box).values[0]
    assert values[:50].mean() > 2 * values[50:].mean()


def test_voronoi_without_freud_names_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "freud", None)
    state, box = _square()
    with pytest.raises(MissingExtraError, match="analysis"):
        LocalDensity(method="voronoi").compute(state, box)
    assert LocalDensity().compute(state, box).method == "cells"  # auto falls back


def test_bad_input_is_refused():
    with pytest.raises(AnalysisInputError, match="method"):
        LocalDensity(method="grid")
    with pytest.raises(AnalysisInputError, match="shells"):
        LowKStructureFactor(shells=0)
    with pytest.raises(AnalysisInputError, match="cell"):
        LocalDensity(cell=-1.0)
    sim = hs.Simulation(
        hs.random_spheres(20, 0.1, hs.SphericalContainer(5.0), seed=1), hs.SphericalContainer(5.0)
    )
    with pytest.raises(PeriodicBoxRequired):
        LowKStructureFactor().compute(sim)


def _floats(b64, shape):
    import base64

    return np.frombuffer(base64.b64decode(b64), "<f4").reshape(shape)


@pytest.fixture(scope="module")
def clumped_frames():
    """The square lattice with half its disks squeezed into a corner, two frames."""
    from hardspheres.io.trajectory import frames_from_simulation

    state, box = _square()
    pos = state.positions.copy()
    pos[:50] = pos[:50] * 0.55 - 4.0
    dense = hs.State.from_arrays(
        masses=state.masses, radii=state.radii, positions=pos, velocities=state.velocities
    )
    sim = hs.Simulation(dense, hs.PeriodicBox(box))
    return frames_from_simulation(sim, until=0.1, every=0.1)


def test_viewer_colours_by_local_density(clumped_frames, tmp_path):
    from helpers import embedded_data

    from hardspheres.viz.viewer import write_viewer

    data = embedded_data(write_viewer(clumped_frames, tmp_path / "d.html", color_by="density").read_text())
    sc = data["scalar"]
    assert sc["name"] == "density" and sc["range"] == [0.0, 0.9069]
    values = _floats(sc["values"], (data["nframes"], data["n"]))
    assert values[0, :50].mean() > 2 * values[0, 50:].mean()
    circle = hs.CircularContainer(6.0)
    from hardspheres.io.trajectory import frames_from_simulation

    frames = frames_from_simulation(
        hs.Simulation(hs.random_spheres(20, 0.2, circle, seed=1), circle), until=0.1, every=0.1
    )
    with pytest.raises(ValueError, match="periodic box"):
        write_viewer(frames, tmp_path / "c.html", color_by="density")


def test_render_colours_by_local_density(clumped_frames, tmp_path):
    pytest.importorskip("matplotlib")
    from PIL import Image

    from hardspheres.viz.render import render_still

    out = render_still(clumped_frames, tmp_path / "d.png", size=(640, 360), color_by="density", time=0.0)
    img = np.asarray(Image.open(out).convert("RGB"))
    assert img.shape == (360, 640, 3) and len(np.unique(img.reshape(-1, 3), axis=0)) > 20


def test_commands_colour_by_density(tmp_path, capsys):
    """``render``/``view --color density`` from a trajectory; a sphere is refused in one line."""
    from hardspheres.cli.commands import main

    box = hs.PeriodicBox.for_packing(100, 0.25, (1.0, 1.0))
    sim = hs.Simulation(hs.random_spheres(100, 0.25, box, seed=3), box, restitution=0.8)
    sim.writers.append(hs.GSDWriter(tmp_path / "run.gsd", every=0.5, events=False))
    sim.run(until=1.0)
    sim.writers[0].close()
    gsd = str(tmp_path / "run.gsd")
    assert main(["render", gsd, "--color", "density", "-o", str(tmp_path / "r.png")]) == 0
    assert main(["view", gsd, "--color", "density", "-o", str(tmp_path / "v.html")]) == 0
    ball = hs.SphericalContainer(6.0)
    other = hs.Simulation(hs.random_spheres(30, 0.2, ball, seed=1), ball)
    other.writers.append(hs.GSDWriter(tmp_path / "ball.gsd", every=0.5, events=False))
    other.run(until=0.5)
    other.writers[0].close()
    capsys.readouterr()
    assert (
        main(["render", str(tmp_path / "ball.gsd"), "--color", "density", "-o", str(tmp_path / "b.png")]) == 1
    )
    err = capsys.readouterr().err
    assert "periodic box" in err and "Traceback" not in err and len(err.strip().splitlines()) == 1

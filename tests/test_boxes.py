"""Rectangular periodic boxes: their shapes, their dynamics against the cube's, their files.

The strongest check of a rectangular box's per-axis arithmetic (cells,
neighbour lists, images, minimum image) is a box that must behave as a
cube: a cube's spheres and their copy one edge along an axis, in a box
twice as long on that axis, move as the cube's spheres do (each copy's
neighbours across the long box are the other copy's, as the cube's own
images were).  Floating point rounds differently (a coordinate L larger),
so the agreement is to rounding amplified by a few collisions per sphere.
"""

import numpy as np
import pytest

import hardspheres as hs
from hardspheres.builders import random_spheres
from hardspheres.containers import BoxShapeError, PeriodicBox, from_fields, from_record
from hardspheres.core import _core as core
from hardspheres.core.engine import Engine


@pytest.mark.parametrize(
    "sides,why",
    [
        ((1.0,), "1 sides"),
        ((1.0, 2.0, 3.0, 4.0), "4 sides"),
        ((1.0, 0.0, 3.0), "Ly = 0.0"),
        ((1.0, -2.0, 3.0), "Ly = -2.0"),
        ((1.0, float("nan"), 3.0), "Ly = nan"),
        ("abc", "'abc'"),
        (0.0, "0.0"),
    ],
)
def test_bad_shapes_are_refused_saying_what_is_allowed(sides, why):
    with pytest.raises(BoxShapeError) as e:
        PeriodicBox(sides)
    text = str(e.value)
    assert "\n" not in text and why in text and "three (Lx, Ly, Lz)" in text
    assert isinstance(e.value, ValueError)


def test_a_side_narrower_than_three_diameters_is_refused():
    with pytest.raises(BoxShapeError, match="every side must be at least 6"):
        Engine([1.0], [1.0], [[0.0, 0.0, 0.0]], [[1.0, 0.0, 0.0]], box=(20.0, 5.0, 20.0))


def test_three_equal_sides_are_the_cube():
    assert PeriodicBox((3.0, 3.0, 3.0)) == PeriodicBox(3.0)
    assert PeriodicBox((3.0, 3.0, 3.0)).record().tolist() == PeriodicBox(3.0).record().tolist()


def test_geometry_per_axis():
    b = PeriodicBox((2.0, 4.0, 8.0))
    assert b.volume == 64.0 and b.sides == (2.0, 4.0, 8.0) and not b.cube
    assert b.gsd_box == [2.0, 4.0, 8.0, 0.0, 0.0, 0.0]
    assert b.wrap(np.array([[1.5, 2.5, -4.5]])).tolist() == [[-0.5, -1.5, 3.5]]
    assert b.image_counts(np.array([[1.5, 2.5, -4.5]])).tolist() == [[1, 1, -1]]
    assert b.displacement(np.array([0.9, 1.9, 3.9]), np.array([-0.9, -1.9, -3.9])).tolist() == pytest.approx(
        [-0.2, -0.2, -0.2]
    )
    assert from_record(b.record()) == b
    assert from_fields(b.fields()) == b
    assert from_fields({f"hardspheres/{k}": [v] for k, v in b.fields().items()}) == b
    assert from_record(np.array(["PeriodicBox", "2.5"])) == PeriodicBox(2.5)  # files from before


def _doubled(s, L, axis):
    """The cube's spheres and their copy one edge along ``axis``: arrays for the long box."""
    shift = np.zeros(3)
    shift[axis] = L
    sides = [L, L, L]
    sides[axis] = 2 * L
    pos = PeriodicBox(tuple(sides)).wrap(np.concatenate([s.positions, s.positions + shift]))
    twice = [np.concatenate([a, a]) for a in (s.masses, s.radii, s.velocities)]
    return twice[0], twice[1], pos, twice[2], tuple(sides)


@pytest.mark.parametrize("phi", [0.2, 0.45])  # cells; neighbour lists
@pytest.mark.parametrize("axis", [0, 1, 2])
def test_a_doubled_cube_moves_as_the_cube(phi, axis):
    n = 256  # (4 k^3: a whole FCC lattice)
    L = (n * np.pi / (6 * phi)) ** (1 / 3)
    s = random_spheres(n, phi, box=L, seed=11 + axis)
    cube = Engine(s.masses, s.radii, s.positions, s.velocities, box=L)
    m, r, x, v, sides = _doubled(s, L, axis)
    long = Engine(m, r, x, v, box=sides)
    assert (long.scalars[core.F_SHELL] > 0) == (cube.scalars[core.F_SHELL] > 0) == (phi > 0.3)
    assert long.counts[core.C_GRID + axis] > cube.counts[core.C_GRID + axis]
    ev = cube.advance(collisions=3 * n)  # a few collisions per sphere
    t = float(ev["time"][-1])
    long.advance(until=t)
    # (the copies' last events may fall an ulp after t)
    assert 0 <= 2 * cube.counters["collisions"] - long.counters["collisions"] <= 2
    box = PeriodicBox(L)
    xa, xl = cube.positions_at(t), long.positions_at(t)
    for half in (xl[:n], xl[n:]):
        assert np.max(np.abs(box.displacement(half, xa))) < 1e-7 * L
        assert np.max(np.abs(long.velocities[:n] - cube.velocities)) < 1e-6
    # unwrapped: the same displacements from the start
    ua, ul = cube.unwrapped_at(t), long.unwrapped_at(t)
    assert np.max(np.abs((ul[:n] - x[:n]) - (ua - s.positions))) < 1e-7 * L
    assert long.max_overlap() < 1e-9


@pytest.mark.parametrize("phi", [0.2, 0.45])
def test_rectangular_box_conserves_and_checkpoints_bit_for_bit(phi):
    sides = (9.0, 11.0, 16.0)
    s = random_spheres(700, phi, box=sides, seed=3)
    assert np.all(np.abs(s.positions) <= 0.5 * np.array(sides))
    a = Engine(s.masses, s.radii, s.positions, s.velocities, box=sides)
    p0, e0 = s.masses @ s.velocities, a.kinetic_energy()
    a.advance(collisions=20000, record=False)
    assert abs(a.kinetic_energy() / e0 - 1) < 1e-12
    assert np.max(np.abs(s.masses @ a.velocities - p0)) < 1e-10 * np.sum(s.masses)
    assert a.max_overlap() < 1e-9
    b = Engine.restore({k: np.copy(v) for k, v in a.checkpoint().items()})
    assert b.container == PeriodicBox(sides)
    ea, eb = a.advance(collisions=3000), b.advance(collisions=3000)
    assert all(np.array_equal(ea[k], eb[k]) for k in ea.dtype.names)
    assert np.array_equal(a.positions_at(), b.positions_at())


def test_a_checkpoint_from_before_the_per_axis_grid_still_loads():
    """Files before rectangular boxes saved 8 counts and 42 scalars (a cube's grid)."""
    s = random_spheres(200, 0.3, box=10.0, seed=1)
    a = Engine(s.masses, s.radii, s.positions, s.velocities, box=10.0)
    a.advance(collisions=500)
    old = {k: np.copy(v) for k, v in a.checkpoint().items()}
    old["counts"] = old["counts"][: core.C_HEAP_SIZE]
    old["scalars"] = old["scalars"][: core.F_BUCKET_RATE]
    b = Engine.restore(old)
    ea, eb = a.advance(collisions=2000), b.advance(collisions=2000)
    assert all(np.array_equal(ea[k], eb[k]) for k in ea.dtype.names)


def test_a_damaged_side_is_refused():
    sides = (9.0, 11.0, 16.0)
    s = random_spheres(100, 0.2, box=sides, seed=3)
    a = Engine(s.masses, s.radii, s.positions, s.velocities, box=sides)
    data = {k: np.copy(v) for k, v in a.checkpoint().items()}
    data["scalars"][core.F_EDGE + 2] = 15.0
    with pytest.raises(hs.CheckpointError, match="sides disagree"):
        Engine.restore(data)


def test_growth_in_a_rectangular_box_rebuilds_and_never_overlaps():
    sides = (10.0, 14.0, 24.0)
    s = random_spheres(800, 0.3, box=sides, seed=5)
    a = Engine(s.masses, s.radii, s.positions, s.velocities, box=sides)
    a.set_growth(0.05)
    a.advance(collisions=30000, record=False)
    assert a.max_overlap() < 1e-9


def test_a_simulation_in_a_rectangular_box_writes_reads_saves_and_measures(tmp_path):
    box = PeriodicBox((8.0, 9.0, 14.0))
    state = hs.random_spheres(300, 0.3, box=box.sides, seed=1)
    sim = hs.Simulation(state, box)
    gsd_path, xyz_path = tmp_path / "t.gsd", tmp_path / "t.xyz"
    with hs.GSDWriter(gsd_path, every=0.5) as g, hs.XYZWriter(xyz_path, every=0.5) as x:
        sim.writers.extend([g, x])
        sim.run(until=2.0)
        sim.observables.reset()
        sim.run(until=12.0)
    sim.writers.clear()
    obs = sim.observables
    p = obs.pressure_tensor()
    np.testing.assert_allclose(p, p.T)
    # trace: the mechanical pressure (2 E_kin / 3 + W / 3t) / V (as for the cube)
    mech = (2.0 * sim.engine.kinetic_energy() / 3.0 + obs._delta()[4] / (3.0 * obs.elapsed)) / box.volume
    assert np.trace(p) / 3.0 == pytest.approx(mech, rel=1e-9)
    for k in range(3):  # isotropic, whatever the sides
        assert p[k, k] == pytest.approx(obs.pressure(), abs=5 * obs.error("pressure_xx") + 1e-3)
    sim.save(tmp_path / "c.npz")
    back = hs.Simulation.load(tmp_path / "c.npz")
    assert back.container == box
    sim.run(collisions=2000)
    back.run(collisions=2000)
    assert np.array_equal(sim.state().positions, back.state().positions)
    for path in (gsd_path, xyz_path):
        frames = hs.read_trajectory(path)
        assert frames.container == box
        assert np.all(np.abs(frames.positions) <= 0.5 * np.array(box.sides) + 1e-12)
    frames = hs.read_trajectory(gsd_path)
    assert frames.images is not None
    import gsd.hoomd

    with gsd.hoomd.open(gsd_path) as f:
        assert list(f[0].configuration.box) == [8.0, 9.0, 14.0, 0.0, 0.0, 0.0]
    rdf = hs.RDF().compute(frames)
    assert rdf.r.max() < 4.0  # half the shortest side
    msd = hs.MSD().compute(frames)
    assert np.all(np.isfinite(msd.msd))


@pytest.mark.parametrize("lattice", ["fcc", "hcp"])
def test_crystals_fill_rectangular_boxes_with_twelve_neighbours_and_stay_crystals(lattice):
    from hardspheres.builders import crystal

    state, box = crystal(lattice, (4, 3, 3), 0.6, seed=2)
    assert state.n == 4 * 36 and state.n * np.pi / 6 / box.volume == pytest.approx(0.6)
    d = np.linalg.norm(box.displacement(state.positions[:, None], state.positions[None]), axis=2)
    np.fill_diagonal(d, np.inf)
    near = np.isclose(d, d.min(), rtol=1e-9)
    assert np.all(near.sum(axis=1) == 12) and d.min() > 1.0
    sim = hs.Simulation(state, box)
    sim.run(collisions=20 * state.n)
    assert sim.engine.max_overlap() < 1e-9
    # still on its sites (no melting at 0.6): every sphere within a third of a spacing
    disp = box.displacement(sim.state(unwrapped=True).positions, state.positions)
    drift = disp.mean(axis=0)
    assert np.max(np.linalg.norm(disp - drift, axis=1)) < d.min() / 3


def test_a_bad_crystal_is_refused():
    from hardspheres.builders import BuildError, crystal

    for args in (("bcc", (2, 2, 2), 0.5), ("fcc", (2, 0, 2), 0.5), ("fcc", (2, 2, 2), 0.75)):
        with pytest.raises(BuildError):
            crystal(*args)

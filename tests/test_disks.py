"""Disks above the core: builders, simulation, observables, files and structure in 2-D."""

import numpy as np
import pytest

import hardspheres as hs
from hardspheres.builders import BuildError, hexagonal
from hardspheres.containers import CircularContainer, PeriodicBox

HEX_BOX = PeriodicBox((30.0, 30.0 * np.sqrt(3.0) / 2.0))


def _min_distance(container, x):
    d = np.linalg.norm(container.displacement(x[:, None], x[None]), axis=2)
    np.fill_diagonal(d, np.inf)
    return d.min()


@pytest.mark.parametrize("container", [HEX_BOX, CircularContainer(18.0)], ids=["box", "circle"])
@pytest.mark.parametrize("packing", [0.1, 0.5, 0.72])
def test_random_disks_up_to_072_do_not_overlap(container, packing):
    s = hs.random_spheres(600, packing, container, seed=3, radius_ratio=1.05, mass_ratio=2.0)
    assert s.positions.shape == (600, 2) and s.velocities.shape == (600, 2) and s.dimensions == 2
    assert hs.containers.packing_fraction(s.radii, container) == pytest.approx(packing)
    assert _min_distance(container, s.positions) > 2 * s.radii.max()
    assert not np.any(container.outside(s.positions, s.radii))
    assert np.allclose(s.masses @ s.velocities, 0.0, atol=1e-12)
    with pytest.raises(BuildError, match="0.72"):
        hs.random_spheres(100, 0.8, container)


def test_the_hexagonal_crystal_fills_a_sqrt3_over_2_box_with_six_neighbours():
    s, box = hexagonal((10, 10), 0.8)
    assert box.sides[1] / box.sides[0] == pytest.approx(np.sqrt(3.0) / 2.0)
    assert hs.containers.packing_fraction(s.radii, box) == pytest.approx(0.8)
    d = np.linalg.norm(box.displacement(s.positions[:, None], s.positions[None]), axis=2)
    np.fill_diagonal(d, np.inf)
    assert np.all(np.isclose(d, d.min(), rtol=1e-9).sum(axis=1) == 6)
    for bad in ((10, 9), (0, 4)):
        with pytest.raises(BuildError):
            hexagonal(bad, 0.8)


def test_a_disk_fluid_measures_in_two_dimensions(tmp_path):
    s = hs.random_spheres(400, 0.3, HEX_BOX, seed=1)
    sim = hs.Simulation(s, HEX_BOX)
    sim.run(collisions=20000)
    obs = sim.observables.reset()
    sim.run(collisions=100000)
    # 2 N - 2 degrees of freedom: kT from the kinetic energy exactly
    assert obs.temperature() == pytest.approx(2 * sim.engine.kinetic_energy() / (2 * 400 - 2))
    # Z = 1 + sum r.dp / (2 N kT t): the box's pressure over n kT / A
    assert obs.Z() == pytest.approx(obs.pressure() * HEX_BOX.volume / (400 * obs.temperature()))
    # Henderson's equation of state (Mol. Phys. 30, 971 (1975)) is good to 0.3% here
    phi = 0.3
    assert obs.Z() == pytest.approx((1 + phi**2 / 8) / (1 - phi) ** 2, rel=0.02)
    p = obs.pressure_tensor()
    assert p.shape == (2, 2)
    mech = (sim.engine.kinetic_energy() + obs._delta()[4] / (2.0 * obs.elapsed)) / HEX_BOX.volume
    assert np.trace(p) / 2 == pytest.approx(mech, rel=1e-9)
    assert sim.packing == pytest.approx(0.3)
    sim.save(tmp_path / "c.npz")
    back = hs.Simulation.load(tmp_path / "c.npz")
    assert back.container == HEX_BOX
    sim.run(collisions=1000)
    back.run(collisions=1000)
    assert np.array_equal(sim.state().positions, back.state().positions)
    assert sim.state().positions.shape == (400, 2) and sim.state(unwrapped=True).images.shape == (400, 2)


@pytest.mark.parametrize("container", [HEX_BOX, CircularContainer(15.0)], ids=["box", "circle"])
def test_gsd_writes_2d_as_hoomd_and_both_files_read_back(tmp_path, container):
    import gsd.hoomd

    s = hs.random_spheres(200, 0.3, container, seed=2)
    sim = hs.Simulation(s, container)
    with hs.GSDWriter(tmp_path / "t.gsd", every=0.5) as g, hs.XYZWriter(tmp_path / "t.xyz", every=0.5) as x:
        sim.writers.extend([g, x])
        sim.run(until=3.0)
    with gsd.hoomd.open(tmp_path / "t.gsd") as f:
        assert f[0].configuration.dimensions == 2 and f[0].configuration.box[2] == 0.0
        assert np.all(np.asarray(f[-1].particles.position)[:, 2] == 0.0)
    for path in ("t.gsd", "t.xyz"):
        frames = hs.read_trajectory(tmp_path / path)
        assert frames.container == container
        assert frames.positions.shape[1:] == (200, 2)
        np.testing.assert_array_equal(frames.positions[-1], sim.state().positions)


def test_hexatic_order_tells_the_crystal_from_the_liquid():
    s, box = hexagonal((16, 16), 0.75, seed=1)
    sim = hs.Simulation(s, box)
    sim.run(collisions=100 * s.n)
    crystal = hs.Hexatic().compute(sim)
    assert crystal.order > 0.75 and crystal.psi6.shape == (s.n,)
    liquid = hs.Simulation(hs.random_spheres(256, 0.4, box, seed=2), box)
    liquid.run(collisions=50 * 256)
    fluid = hs.Hexatic().compute(liquid)
    assert fluid.order < 0.3
    # g6: long-ranged in the crystal, decaying in the liquid
    far = crystal.r > 0.3 * min(box.sides)
    assert np.mean(crystal.g6[far]) > 0.5 > np.mean(fluid.g6[far])
    rdf = hs.RDF().compute(liquid)
    assert rdf.packing == pytest.approx(0.4)

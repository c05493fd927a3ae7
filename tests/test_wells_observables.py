"""Observables of a stepped run (square wells): the potential energy, the energy drift, C_V.

Small boxes, fixed seeds: the potential energy is ``-eps`` times the bonded
pairs exactly, ``K + U`` is conserved to rounding, the heat capacity from
the kinetic-energy fluctuations (Lebowitz-Percus-Verlet) is above the hard
spheres' ``f / 2``.
"""

import math

import numpy as np
import pytest

import hardspheres as hs
from hardspheres.errors import NoMeasurementError
from hardspheres.observables import MIN_FLUCTUATION_BLOCKS

EPS, LAM = 0.5, 1.5  # supercritical (kT / eps about 2.5; the critical point near 1.2)


def well_run(until: float = 20.0, every: float | None = 0.2, container=None, n: int = 64, seed: int = 2):
    box = container if container is not None else hs.PeriodicBox(8.0)
    s = hs.random_spheres(n, 0.2, container=box, seed=seed)
    sim = hs.Simulation(s, box, steps=[(LAM, -EPS)])
    sim.run(until=5.0)
    sim.observables.reset(every=every)
    sim.run(until=5.0 + until)
    return sim


def bonded_pairs(sim) -> int:
    """Pairs closer than lambda sigma, by brute force over the minimum images."""
    st = sim.state()
    x, r = st.positions, st.radii
    sides = getattr(sim.container, "sides", None)
    count = 0
    for i in range(sim.n - 1):
        dx = x[i] - x[i + 1 :]
        if sim.container.periodic:
            dx -= np.asarray(sides) * np.round(dx / np.asarray(sides))
        d = np.sqrt(np.sum(dx * dx, axis=1))
        count += int(np.sum(d < LAM * (r[i] + r[i + 1 :])))
    return count


def test_potential_energy_is_minus_eps_per_bonded_pair_and_energy_is_conserved():
    sim = well_run()
    obs = sim.observables
    assert sim.engine.counters["captures"] > 0 and sim.engine.counters["releases"] > 0
    assert sim.potential_energy() == -EPS * bonded_pairs(sim) == -EPS * len(sim.engine.pair_states)
    assert abs(obs.energy_drift()) < 1e-12
    u = obs.potential_energy()
    assert obs.n_blocks >= MIN_FLUCTUATION_BLOCKS
    assert u.mean < 0 and 0 < u.sem < abs(u.mean)
    assert u.mean == pytest.approx(np.mean([r[-1] for r in obs._samples[1:]]))
    summary = obs.summary()
    assert summary["potential_energy"] == u.mean and summary["potential_energy_error"] == u.sem
    assert abs(summary["energy_drift"]) < 1e-12


def test_z_divides_by_the_mean_kT_of_the_blocks():
    sim = well_run()
    obs = sim.observables
    f = sim.container.degrees_of_freedom(sim.n)
    e = sim.total_energy()
    # the kinetic integral's mean kT against the energy's: 2 (E - <U>) / f, to the sampling error
    kT = 2.0 * (e - obs.potential_energy().mean) / f
    z, p = obs.Z(), obs.pressure()
    kT_mean = p * sim.container.volume / (sim.n * z)
    assert kT_mean == pytest.approx(kT, rel=0.05)
    assert math.isfinite(obs.estimate("Z").sem)


def test_heat_capacity_is_above_the_hard_spheres_and_needs_blocks():
    sim = well_run()
    cv = sim.observables.heat_capacity()
    f = sim.container.degrees_of_freedom(sim.n)
    assert cv.mean > 0.5 * f / sim.n  # a well adds to the kinetic part
    assert 0 < cv.sem < cv.mean
    assert sim.observables.summary()["heat_capacity"] == cv.mean
    few = well_run(until=3.0, every=0.5)
    with pytest.raises(NoMeasurementError, match="blocks sampled"):
        few.observables.heat_capacity()
    assert "heat_capacity" not in few.observables.summary()


def test_in_a_spherical_container():
    sim = well_run(container=hs.SphericalContainer(5.0), n=40)
    obs = sim.observables
    assert abs(obs.energy_drift()) < 1e-12
    assert obs.potential_energy().mean < 0
    assert sim.potential_energy() == -EPS * bonded_pairs(sim)
    assert math.isfinite(obs.Z())


def test_hard_spheres_have_no_potential_energy():
    box = hs.PeriodicBox(8.0)
    sim = hs.Simulation(hs.random_spheres(32, 0.2, container=box, seed=1), box)
    sim.run(until=2.0)
    with pytest.raises(NoMeasurementError, match="hard spheres"):
        sim.observables.potential_energy()
    with pytest.raises(NoMeasurementError, match="hard spheres"):
        sim.observables.heat_capacity()
    assert "potential_energy" not in sim.observables.summary()
    assert abs(sim.observables.energy_drift()) < 1e-12


def test_a_checkpoint_keeps_the_samples(tmp_path):
    sim = well_run(until=5.0)
    sim.save(tmp_path / "w.npz")
    back = hs.Simulation.load(tmp_path / "w.npz")
    assert back.observables.n_blocks == sim.observables.n_blocks
    assert back.observables.potential_energy().mean == sim.observables.potential_energy().mean


def test_the_energy_moment_is_refused_with_steps_and_the_momentum_one_kept():
    sim = well_run(until=2.0)
    with pytest.raises(NoMeasurementError, match="thermal conductivity is not built for steps"):
        sim.observables.helfand_moments("energy")
    t, m = sim.observables.helfand_moments("momentum")
    assert m.shape == (len(t), 3)


def test_heat_capacity_agrees_with_the_energy_temperature_slope():
    """Lebowitz-Percus-Verlet against the thermodynamic route: ``dE / dT`` between two energies.

    The slope of the chord is the mean of ``C_V`` over the interval, so it
    lies between the fluctuation values at its ends (``C_V`` falls with
    ``kT`` in this supercritical fluid), to their errors; ``E`` is exact
    and the mean ``kT`` good to 0.5%, so the slope to about 2%.
    """
    box = hs.PeriodicBox.for_packing(256, 0.2)
    runs = []
    for scale in (0.9, 1.1):
        sim = hs.Simulation(hs.random_spheres(256, 0.2, box, seed=1), box, steps=[(1.5, -0.5)])
        sim.engine.rescale_velocities(scale)
        sim.run(until=30.0)
        sim.observables.reset()
        sim.run(until=230.0)
        obs = sim.observables
        runs.append((sim.total_energy(), obs.mean_temperature(), obs.heat_capacity()))
    (e1, t1, c1), (e2, t2, c2) = runs
    slope = (e2 - e1) / (256 * (t2 - t1))  # 1.79 (kT 0.79 .. 1.12)
    assert c1.mean > c2.mean > 1.5  # (above the hard spheres' 3/2)
    assert c2.mean - 2.0 * c2.sem < slope < c1.mean + 2.0 * c1.sem

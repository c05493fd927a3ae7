"""Driven granular gases: the random-kick (white-noise) thermostat and its energy tally.

:class:`hardspheres.dense.RandomKicks` gives every sphere a Gaussian velocity
kick of variance ``strength * interval`` per component every ``interval``,
less the mass-weighted mean kick.  Checked here: the mean injection rate
``(N - 1) d m strength / 2`` (elastic collisions conserve energy, so the
kinetic energy grows by it on average), the tally (kinetic plus dissipated
less injected energy conserved to rounding), the momentum, checkpoints
resuming bit for bit, and bad input.
"""

import math

import numpy as np
import pytest

import hardspheres as hs
from hardspheres.dense import RandomKicks, thermostat_from_state
from hardspheres.errors import ArgumentError


def _gas(n, phi, dims, seed=1, restitution=1.0, kT=1.0):
    box = hs.PeriodicBox.for_packing(n, phi, (1.0, 1.0) if dims == 2 else None)
    state = hs.random_spheres(n, phi, box, seed=seed, kT=kT)
    return hs.Simulation(state, box, restitution=restitution)


@pytest.mark.parametrize("dims", [2, 3])
def test_kicks_inject_the_analytic_rate(dims):
    """d<E_kin>/dt = (N - 1) d m strength / 2: kinetic energy from nearly at rest, 400 spheres."""
    n, strength, interval, t = 400, 2.0, 0.01, 1.0
    sim = _gas(n, 0.05, dims, kT=1e-6)
    kicks = RandomKicks(strength, interval, seed=3)
    sim.set_thermostat(kicks)
    e0 = sim.engine.kinetic_energy()
    sim.run(until=t + interval / 2)
    assert kicks.kicks == 100
    expected = kicks.injection_rate(sim.engine.masses, dims) * t
    assert expected == pytest.approx((n - 1) * dims * strength / 2 * t)
    gained = sim.engine.kinetic_energy() - e0
    # the final kinetic energy is a sum of d N squares of normals: relative sd sqrt(2 / (d N))
    sd = math.sqrt(2.0 / (dims * n))
    assert abs(gained / expected - 1.0) < 4 * sd
    assert kicks.injected == pytest.approx(gained, rel=1e-12)
    assert sim.observables.injected() == pytest.approx(gained, rel=1e-12)
    assert sim.engine.max_overlap() <= 1e-9


def test_driven_granular_gas_balances_energy_and_momentum():
    """Inelastic disks, kicked: kinetic + dissipated - injected is the initial energy to rounding."""
    sim = _gas(200, 0.1, 2, restitution=0.8)
    p0 = (sim.engine.masses[:, None] * sim.engine.velocities).sum(axis=0)
    sim.set_thermostat(RandomKicks(strength=1.0, interval=0.05, seed=2))
    sim.observables.reset()
    sim.run(until=20.0)
    obs = sim.observables
    assert obs.injected() > 2 * sim.engine.kinetic_energy() > 0
    assert obs.dissipated() > 0
    assert abs(obs.energy_balance()) < 1e-12
    p1 = (sim.engine.masses[:, None] * sim.engine.velocities).sum(axis=0)
    assert np.allclose(p1, p0, atol=1e-12)
    summary = obs.summary()
    assert summary["injected"] == obs.injected()
    assert abs(summary["energy_balance"]) < 1e-12


def test_injected_counts_from_when_the_thermostat_is_set():
    sim = _gas(100, 0.1, 2, restitution=0.9)
    sim.run(until=1.0)  # cools, no driving
    kicks = RandomKicks(strength=1.0, interval=0.1, seed=1)
    sim.set_thermostat(kicks)
    sim.run(until=3.0)
    assert sim.observables.injected() == kicks.injected > 0
    assert abs(sim.observables.energy_balance()) < 1e-12
    sim.set_thermostat(None)  # what it injected stays counted
    sim.run(until=4.0)
    assert sim.observables.injected() == kicks.injected
    assert abs(sim.observables.energy_balance()) < 1e-12


def test_kicks_are_reproducible_and_resume_bit_for_bit(tmp_path):
    def make():
        return _gas(150, 0.1, 2, seed=4, restitution=0.7).set_thermostat(RandomKicks(0.5, 0.03, seed=9))

    a, b = make(), make()
    a.run(until=2.0)
    b.run(until=2.0)
    assert np.array_equal(a.engine.velocities, b.engine.velocities)
    a.save(tmp_path / "a.npz")
    c = hs.Simulation.load(tmp_path / "a.npz")
    assert isinstance(c.thermostat, RandomKicks)
    a.run(until=4.0)
    c.run(until=4.0)
    assert np.array_equal(a.engine.velocities, c.engine.velocities)
    assert a.thermostat.kicks == c.thermostat.kicks > 100
    assert a.thermostat.injected == c.thermostat.injected
    again = thermostat_from_state(a.thermostat.state())
    assert again.state() == a.thermostat.state()


@pytest.mark.parametrize(
    ("args", "word"),
    [
        ((0.0, 0.1), "strength"),
        ((-1.0, 0.1), "strength"),
        ((1.0, 0.0), "interval"),
        ((math.nan, 1.0), "strength"),
    ],
)
def test_bad_kicks_are_refused(args, word):
    with pytest.raises(ArgumentError, match=word):
        RandomKicks(*args)

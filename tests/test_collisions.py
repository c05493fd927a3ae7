"""Event-record statistics: free flights against the exact mean free time, recollisions, contact forces."""

import math

import numpy as np
import pytest

import hardspheres as hs
from hardspheres.analysis.collisions import (
    ContactForces,
    EventRecorder,
    FreeFlights,
    Recollisions,
    mean_free_time_from_z,
)
from hardspheres.errors import NotComputedError
from hardspheres.events import from_columns


def _recorder(events, n, t0, t1):
    rec = EventRecorder()
    rec.observe(events)
    rec.n, rec.t0, rec.t1 = n, t0, t1
    return rec


def constructed():
    """Three spheres: (0,1) at t = 1, (1,2) at 2, (0,1) at 4, a reflection at 5 (ignored), (0,2) at 7."""
    ev = from_columns(
        time=[1.0, 2.0, 4.0, 5.0, 7.0],
        kind=[1, 1, 1, 0, 1],
        i=[0, 1, 0, 2, 0],
        j=[1, 2, 1, -1, 2],
        impulse=[1.0, 2.0, 3.0, 9.0, 4.0],
        dp=[[1, 0, 0], [0, 2, 0], [3, 0, 0], [9, 0, 0], [0, 0, 4]],
    )
    return _recorder(ev, 3, 0.0, 10.0)


def test_free_flights_of_a_constructed_record():
    ff = FreeFlights().compute(constructed())
    # sphere 0: 1, 4, 7 -> 3, 3; sphere 1: 1, 2, 4 -> 1, 2; sphere 2: 2, 7 -> 5
    assert sorted(ff.flights.tolist()) == [1.0, 2.0, 3.0, 3.0, 5.0]
    assert ff.per_sphere.tolist() == [3, 3, 2]
    assert ff.rate == pytest.approx(2 * 4 / (3 * 10.0)) and ff.mean == pytest.approx(1 / ff.rate)


def test_recollisions_of_a_constructed_record():
    rc = Recollisions().compute(constructed())
    assert rc.intervals.tolist() == [3.0] and rc.fraction_repeated == 0.25
    assert rc.within(2.9) == 0.0 and rc.within(3.0) == 0.25


def test_contact_forces_sum_the_impulses_of_each_pair():
    cf = ContactForces().compute(constructed())
    assert cf.pairs.tolist() == [[0, 1], [0, 2], [1, 2]]
    np.testing.assert_allclose(cf.forces, [0.4, 0.4, 0.2])
    np.testing.assert_allclose(cf.vectors, [[0.4, 0, 0], [0, 0, 0.4], [0, 0.2, 0]])
    assert cf.counts.tolist() == [2, 1, 1]
    assert ContactForces(min_collisions=2).compute(constructed()).pairs.tolist() == [[0, 1]]


@pytest.mark.parametrize("phi", [0.05, 0.3])
def test_mean_free_time_matches_the_exact_one_from_z(phi):
    """1 / rate = sigma sqrt(pi m / kT) / (6 (Z - 1)), the two from the same run, within 4 errors."""
    n = 500
    box = hs.PeriodicBox.for_packing(n, phi).length
    sim = hs.Simulation(hs.random_spheres(n, phi, box=box, seed=8), hs.PeriodicBox(box))
    sim.run(collisions=5 * n)
    sim.observables.reset()
    rec = EventRecorder()
    sim.writers.append(rec)
    sim.run(collisions=200 * n)
    obs = sim.observables
    z, z_err = obs.compressibility(), obs.error("compressibility")
    kT = obs.temperature()
    ff = FreeFlights().compute(rec)
    exact = mean_free_time_from_z(z, kT=kT)
    err = math.hypot(ff.mean_error, exact * z_err / (z - 1))
    assert abs(ff.mean - exact) <= 4 * err
    assert ff.per_sphere.sum() == 2 * rec.collisions
    # complete flights are slightly short: a long one is the likelier to be cut by the ends
    assert ff.flight_mean < ff.mean


def test_bad_input():
    with pytest.raises(TypeError, match="need an EventRecorder or Frames"):
        FreeFlights().compute(np.zeros(3))
    with pytest.raises(ValueError, match="no collisions recorded"):
        FreeFlights().compute(_recorder(from_columns(time=[1.0], kind=[0], i=[0]), 1, 0.0, 2.0))
    with pytest.raises(ValueError, match="Z must be > 1"):
        mean_free_time_from_z(1.0)
    with pytest.raises(ValueError, match="min_collisions must be"):
        ContactForces(min_collisions=0)
    with pytest.raises(NotComputedError):
        FreeFlights().mean  # noqa: B018

"""DynamO's sheared granular test on the compiled core (docs/validation/shear.md, validation/shear_dynamo.py).

N = 1372 spheres from an FCC lattice at number density 0.5, restitution
0.9, Lees-Edwards shear at g = 1 (DynamO's default rate, in units of the
diameter), no thermostat: the steady state's mean free time is DynamO's
0.113195634 within its tolerance, 1% (``src/dynamo/tests/shearing_test.cpp``).
"""

import math

import pytest

import hardspheres as hs


@pytest.mark.slow
def test_the_sheared_granular_gas_has_dynamos_mean_free_time():
    state, box = hs.crystal("fcc", (7, 7, 7), math.pi / 12.0, seed=2)
    sim = hs.Simulation(state, box.sheared_by(1.0), restitution=0.9)
    sim.run(collisions=500_000)
    t0, c0 = sim.time, sim.counters["collisions"]
    sim.run(collisions=1_000_000)
    mft = (sim.time - t0) * sim.n / (2.0 * (sim.counters["collisions"] - c0))
    assert mft == pytest.approx(0.113195634, rel=0.01)
    assert sim.engine.max_overlap() < 1e-9

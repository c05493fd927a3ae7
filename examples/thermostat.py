"""A thermostat: an Andersen heat bath brings a hot gas to kT = 1, then NVE again.

    python examples/thermostat.py [--quick]
"""

import sys

import numpy as np

import hardspheres as hs
from hardspheres.dense import Andersen

quick = "--quick" in sys.argv
n = 108 if quick else 500
box = hs.PeriodicBox.for_packing(n, 0.2)
state = hs.random_spheres(n, 0.2, box, seed=1)
state.velocities *= 2.0  # four times too hot
sim = hs.Simulation(state, box)
print(f"start: kT = {sim.observables.temperature():.3f}")
sim.set_thermostat(Andersen(kT=1.0, rate=0.5, seed=1))
for _ in range(5):
    sim.run(until=sim.time + (0.5 if quick else 2.0))
    print(f"t = {sim.time:5.1f}: kT = {sim.observables.temperature():.3f}")
sim.set_thermostat(None)  # NVE from here: the energy stays
e0 = sim.state().kinetic_energy()
sim.run(collisions=10 * n)
print(f"NVE: energy changed by {abs(sim.state().kinetic_energy() / e0 - 1):.1e} (rounding)")
assert np.isfinite(e0)

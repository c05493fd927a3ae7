"""A first simulation: 500 spheres at packing 0.3 in a periodic box, with error bars.

    python examples/first_simulation.py [--quick]
"""

import sys

import hardspheres as hs
from hardspheres import eos

quick = "--quick" in sys.argv
n = 108 if quick else 500
box = hs.PeriodicBox.for_packing(n, 0.3)
sim = hs.Simulation(hs.random_spheres(n, 0.3, box, seed=1), box)
sim.run(collisions=20 * n)  # equilibrate
obs = sim.observables.reset(every=0.1)  # average from here
sim.run(collisions=(20 if quick else 200) * n)
z = obs.estimate("Z")
print(f"N = {n}, t = {sim.time:.2f}, {sim.counters['collisions']} collisions")
print(f"Z = {z.mean:.4f} +- {z.sem:.4f}, Hansen-Goos {float(eos.hansen_goos(0.3)):.4f}")
for key, value in obs.summary().items():
    print(f"  {key}: {value}")
sim.save("first_simulation.npz")  # resume with hs.Simulation.load("first_simulation.npz")

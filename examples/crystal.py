"""Slow compression past freezing, then a run: the fluid crystallises (Steinhardt q6).

    python examples/crystal.py [--quick]
"""

import sys

import hardspheres as hs

quick = "--quick" in sys.argv
box = hs.PeriodicBox(14.0)
sim = hs.Simulation(hs.random_spheres(500, 0.3, box, seed=1), box)
sim.compress(packing=0.56, rate=1e-2 if quick else 1e-3)
for step in range(2 if quick else 10):
    obs = sim.observables.reset()
    sim.run(collisions=20_000 if quick else 200_000)
    order = hs.BondOrder(num_neighbors=12).compute(sim)
    print(
        f"{sim.counters['collisions']:>9} collisions: Z = {obs.Z():.2f}, "
        f"mean q6 = {order.mean_q:.3f}, crystal-like {order.crystal_fraction:.0%}"
    )

"""A jammed packing by fast Lubachevsky-Stillinger compression, written as a scenario.

    python examples/jammed_packing.py [--quick]     # writes jammed.txt
"""

import sys

import hardspheres as hs

quick = "--quick" in sys.argv
n, L = (256, 11.4) if quick else (1000, 18.0)
box = hs.PeriodicBox(L)
sim = hs.Simulation(hs.random_spheres(n, 0.3, box, seed=1), box)
res = sim.compress(packing=0.74, rate=0.03 if quick else 0.01, pressure=1e3 if quick else 1e4)
phi_j = res.packing * res.pressure / (res.pressure - 3)  # where Z ~ 3 phi_J / (phi_J - phi) diverges
order = hs.BondOrder(num_neighbors=12).compute(sim)
print(f"stopped by {res.reason} (jammed: {res.jammed}) at packing {res.packing:.4f}, Z = {res.pressure:.3g}")
print(f"phi_J = {phi_j:.4f}; mean q6 = {order.mean_q:.3f}, crystal-like {order.crystal_fraction:.1%}")
with open("jammed.txt", "w") as fh:  # the assignment's format: any command reads it
    fh.write(sim.state().to_text())
print("wrote jammed.txt: hardspheres view jammed.txt --box", L, "--until 0.01 --color q6 -o jammed.html")

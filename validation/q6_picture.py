"""docs/images/dense_q6.png: a jammed packing beside a crystal, coloured by q6.

    python validation/q6_picture.py [OUT.png]

Fast compression of 1000 spheres (rate 0.01, to Z = 1e4) against slow
compression of 500 spheres to packing 0.56 (rate 1e-3) and 1.5 million
collisions at that packing; each sphere coloured by its Steinhardt q6.
"""
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

import hardspheres as hs

out = sys.argv[1] if len(sys.argv) > 1 else "docs/images/dense_q6.png"
jam = hs.Simulation(hs.random_spheres(1000, 0.3, box=18.0, seed=1), hs.PeriodicBox(18.0))
res_j = jam.compress(packing=0.74, rate=0.01, pressure=1e4)
xtal = hs.Simulation(hs.random_spheres(500, 0.3, box=14.0, seed=1), hs.PeriodicBox(14.0))
xtal.compress(packing=0.56, rate=1e-3)
xtal.run(collisions=1_500_000)

fig = plt.figure(figsize=(9.6, 7.2), dpi=100)  # 960 x 720, as the other pictures
for k, (sim, title) in enumerate([
        (jam, f"fast (rate 0.01): jammed at {res_j.packing:.3f}"),
        (xtal, "slow (rate 0.001) to 0.56, then a run: crystal")]):
    order = hs.BondOrder(num_neighbors=12).compute(sim)
    pos = sim.state().positions
    ax = fig.add_subplot(1, 2, k + 1, projection="3d")
    sc = ax.scatter(pos[:, 0], pos[:, 1], pos[:, 2], c=order.q, cmap="viridis",
                    vmin=0.2, vmax=0.6, s=18, edgecolors="0.2", linewidths=0.2)
    ax.set_title(f"{title}\nmean q6 {order.mean_q:.2f}, crystal-like {order.crystal_fraction:.0%}",
                 fontsize=9)
    ax.set_axis_off()
fig.colorbar(sc, ax=fig.axes, shrink=0.6, label="Steinhardt q6 (12 neighbours)")
fig.savefig(out)
print("wrote", out)

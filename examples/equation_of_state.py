"""Z(phi) with blocking error bars against Hansen-Goos, and a plot of it.

    python examples/equation_of_state.py [--quick]     # writes eos.png
"""

import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import hardspheres as hs  # noqa: E402
from hardspheres import eos  # noqa: E402

quick = "--quick" in sys.argv
n, measured = (108, 30) if quick else (500, 400)
packings = [0.1, 0.3] if quick else [0.1, 0.2, 0.3, 0.4, 0.45]
rows = []
for phi in packings:
    box = hs.PeriodicBox.for_packing(n, phi)
    sim = hs.Simulation(hs.random_spheres(n, phi, box, seed=1), box)
    sim.run(collisions=30 * n)
    obs = sim.observables.reset(every=0.2)
    sim.run(collisions=measured * n)
    z = obs.estimate("Z")
    rows.append((phi, z.mean, z.sem))
    hg = float(eos.hansen_goos(phi))
    print(f"phi = {phi:.2f}: Z = {z.mean:.4f} +- {z.sem:.4f}, Hansen-Goos {hg:.4f}")

phi, Z, err = np.array(rows).T
x = np.linspace(0, max(packings) + 0.03, 100)
fig, ax = plt.subplots(figsize=(5, 3.5), constrained_layout=True)
ax.plot(x, eos.hansen_goos(x), "r-", label="Hansen-Goos (2016)")
ax.errorbar(phi, Z, err, fmt="o", label=f"hardspheres, N = {n}")
ax.set(xlabel="packing fraction", ylabel="Z = PV/NkT")
ax.legend()
fig.savefig("eos.png", dpi=120)
print("wrote eos.png")

"""Diffusion (MSD) and shear viscosity (Einstein-Helfand), D extrapolated to N -> infinity.

    python examples/transport.py [--quick]
"""

import math
import sys

import hardspheres as hs
from hardspheres.io.trajectory import frames_from_simulation
from hardspheres.studies.validate import published_diffusion

quick = "--quick" in sys.argv
n, duration = (108, 60.0) if quick else (500, 150.0)
phi = 0.5 * math.pi / 6  # number density 0.5
box = hs.PeriodicBox.for_packing(n, phi)
sim = hs.Simulation(hs.random_spheres(n, phi, box, seed=3), box)
sim.run(collisions=50 * n)
obs = sim.observables.reset(every=0.05)
frames = frames_from_simulation(sim, until=sim.time + duration, every=0.1)
D, D_err = hs.MSD().compute(frames).diffusion()
eta, eta_err = hs.ShearViscosity().compute(sim).value()
D_inf = hs.yeh_hummer(D, box.length, eta)
print(f"D(N = {n}) = {D:.4f} +- {D_err:.4f}, eta = {eta:.3f} +- {eta_err:.3f}")
print(f"D(N = inf) = {D_inf:.4f} (Yeh-Hummer)")
for ref, ref_err, source in published_diffusion(phi):
    print(f"published: {ref:.4f} +- {ref_err:.4f} ({source})")

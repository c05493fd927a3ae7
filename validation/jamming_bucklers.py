"""theta of P(f) with and without the forces on spheres of d + 1 contacts (docs/validation/glass-jamming.md).

Reads the packings ``validation/jamming.py --save DIR`` wrote, runs each
2000 collisions per sphere at fixed radii (new velocities, seed 0) for the
forces, and fits P(f) ~ f^theta pooled over them, with all the non-rattlers'
forces and without those on spheres with exactly 4 contacts (contacts at
gaps below 1e-4).

    python3 validation/jamming_bucklers.py 'DIR/jam_1000_*.npz'
"""

import sys

import glob

import numpy as np

import hardspheres as hs
from hardspheres.analysis.jamming import *
from hardspheres.analysis.collisions import *

pool = {False: [], True: []}
for f in sorted(glob.glob(sys.argv[1])):
    d = np.load(f)
    n = len(d["radii"])
    sim = hs.Simulation.from_arrays(
        np.ones(n),
        d["radii"],
        d["positions"],
        np.random.default_rng(0).normal(size=(n, 3)),
        hs.PeriodicBox(float(d["box"])),
    )
    rec = EventRecorder()
    sim.writers.append(rec)
    sim.run(collisions=2000 * n)
    cf = ContactForces().compute(rec)
    c = Contacts(tolerance=1e-4).compute(sim)
    nb = int(((c.contacts == 4) & ~c.rattler).sum())
    print(f, "spheres with 4 contacts", nb)
    for wb in (False, True):
        p = cf.pairs
        drop = c.rattler | ((c.contacts == 4) if wb else False)
        keep = ~(drop[p[:, 0]] | drop[p[:, 1]])
        x = cf.forces[keep]
        pool[wb].append(x / x.mean())
for wb in (False, True):
    x = np.concatenate(pool[wb])
    for hi in (0.1, 0.3, 0.5):
        used = x[x <= hi]
        a = power_law_exponent(used, 0, hi)
        from hardspheres.analysis.jamming import _bootstrap

        print(
            "without_bucklers" if wb else "all",
            hi,
            round(a - 1, 3),
            round(_bootstrap(used, lambda s: power_law_exponent(s, 0, hi)), 3),
            len(used),
        )

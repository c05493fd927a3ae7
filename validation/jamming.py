"""Jammed packings: isostaticity after rattler removal, g(h) and P(f) exponents, phi_J.

Equal spheres in a periodic box, a fluid at packing 0.3 compressed
(Lubachevsky-Stillinger, ``Simulation.compress``) at rate 1e-2 to Z = 1e3,
1e-3 to Z = 1e5 and 1e-4 to Z > 1e6; then run at fixed radii for
``--per-sphere`` collisions per sphere with an EventRecorder, for the
time-averaged contact forces (Donev, Torquato and Stillinger, PRE 71,
011105 (2005)).  Per packing: z after rattler removal (contacts at gap
1e-4, and from the forces), the rattler fraction, phi_J from the
free-volume fit; pooled over the packings: gamma of g(h) ~ h^-gamma and
theta of P(f) ~ f^theta, against Charbonneau, Corwin, Parisi and Zamponi,
PRL 109, 205501 (2012) (gamma = 0.41, theta = 0.42).

    python3 validation/jamming.py --n 1000 --seeds 1 2 3 4
"""

import argparse
import json
import time

import numpy as np

import hardspheres as hs
from hardspheres.analysis.collisions import ContactForces, EventRecorder
from hardspheres.analysis.jamming import (
    Contacts,
    JammingPoint,
    force_exponent,
    power_law_exponent,
    _bootstrap,
)

STAGES = ((1e-2, 1e3), (1e-3, 1e5), (1e-4, 1e6))


def packing(n, seed, per_sphere, save=None):
    box = hs.PeriodicBox.for_packing(n, 0.3).length
    sim = hs.Simulation(hs.random_spheres(n, 0.3, box=box, seed=seed), hs.PeriodicBox(box))
    sim.run(collisions=2 * n)
    history = []
    t0 = time.time()
    for rate, pressure in STAGES:
        res = sim.compress(rate=rate, pressure=pressure, progress=lambda p, z, c: history.append((p, z)))
    seconds = time.time() - t0
    rec = EventRecorder()
    sim.writers.append(rec)
    sim.run(collisions=per_sphere * n)
    forces = ContactForces().compute(rec)
    by_gap = Contacts(tolerance=1e-4, h_max=0.1).compute(sim)
    by_force = Contacts(tolerance=1e-4, h_max=0.1).compute(sim, forces=forces)
    phi, z = np.array(history).T
    jp = JammingPoint().compute(phi, z)
    if save:
        st = sim.state()
        np.savez(save, positions=st.positions, radii=st.radii, box=box, history=np.array(history))
    return (
        {
            "n": n,
            "seed": seed,
            "packing": res.packing,
            "Z": res.pressure,
            "compress_seconds": round(seconds, 1),
            "z_gap": by_gap.z,
            "z_force": by_force.z,
            "z_isostatic": by_gap.z_isostatic,
            "rattlers_gap": by_gap.rattler_fraction,
            "rattlers_force": by_force.rattler_fraction,
            "phi_J": jp.phi_J,
            "phi_J_error": jp.error,
            "d_fit": jp.d_fit,
        },
        by_gap,
        forces,
    )


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=1000)
    ap.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3, 4])
    ap.add_argument("--per-sphere", type=int, default=2000, help="collisions per sphere for the forces")
    ap.add_argument("--save", help="folder for the packings (npz)")
    args = ap.parse_args()
    rows, gaps, fs = [], [], []
    for seed in args.seeds:
        save = f"{args.save}/jam_{args.n}_{seed}.npz" if args.save else None
        row, c, f = packing(args.n, seed, args.per_sphere, save)
        print(json.dumps(row), flush=True)
        rows.append(row)
        gaps.append(c.backbone_gaps())
        p = f.pairs
        keep = ~(c.rattler[p[:, 0]] | c.rattler[p[:, 1]])
        fs.append(f.forces[keep] / f.forces[keep].mean())
    h, x = np.concatenate(gaps), np.concatenate(fs)
    for lo, hi in ((1e-4, 1e-2), (1e-4, 1e-3), (1e-3, 1e-2), (1e-5, 1e-2)):
        used = h[(h > lo) & (h <= hi)]
        a = power_law_exponent(used, lo, hi)
        print(
            f"gamma in ({lo:g}, {hi:g}]: {1 - a:.3f} +- {_bootstrap(used, lambda s: power_law_exponent(s, lo, hi)):.3f} ({len(used)} gaps)"
        )
    for lo, hi in ((0.0, 0.1), (0.0, 0.3), (0.0, 0.5), (0.01, 0.3), (0.03, 0.5)):
        used = x[(x > lo) & (x <= hi)]
        a = power_law_exponent(used, lo, hi)
        print(
            f"theta in ({lo:g}, {hi:g}] <f>: {a - 1:.3f} +- {_bootstrap(used, lambda s: power_law_exponent(s, lo, hi)):.3f} ({len(used)} forces)"
        )
    z = np.array([(r["z_gap"], r["z_force"], r["z_isostatic"]) for r in rows])
    print(
        "mean z (gap, force, isostatic):",
        z.mean(axis=0).round(4).tolist(),
        "spread",
        z.std(axis=0, ddof=1).round(4).tolist() if len(z) > 1 else "",
    )


if __name__ == "__main__":
    main()

"""Jammed disks: isostaticity, rattlers, phi_J, g(h) and P(f) in 2-D (docs/validation/glass-jamming.md).

50:50 binary disks of diameters 1.4 : 1 (largest diameter 0.8: when these
runs were made the engine's growth limit for disks counted a unit z cell
width, fixed since in a0a36f7) in a square periodic box, from a fluid compressed at rate
1e-2 to Z = 1e3 and 1e-3 to Z > 1e6, then 2000 collisions per disk at fixed
radii for the forces.  Per packing: z after rattler removal (fewer than 3
contacts), by gaps below 1e-4 and by forces, the rattler fraction, phi_J of
the free-volume fit ``Z = 2 phi_J / (phi_J - phi)``; pooled: gamma of g(h)
and theta of P(f), with all forces between non-rattlers and without those
on disks of exactly 3 contacts.

    python3 validation/jamming_disks.py --n 1024 --seeds 1 2 3 4 5 6 7 8
"""

import argparse
import json
import math
import time

import numpy as np

import hardspheres as hs
from hardspheres.analysis.collisions import ContactForces, EventRecorder
from hardspheres.analysis.jamming import Contacts, JammingPoint, _bootstrap, power_law_exponent


def binary_disks(n, seed):
    r_big = 0.4
    area = 0.5 * n * math.pi * (r_big**2 + (r_big / 1.4) ** 2)
    side = math.sqrt(area / 0.84)
    box = hs.PeriodicBox((side, side))
    s = hs.random_spheres(n, 0.3, box, seed=seed)
    radii = np.where(np.arange(n) % 2 == 0, 1.0, 1.0 / 1.4) * s.radii.max()
    return hs.Simulation.from_arrays(s.masses, radii, s.positions, s.velocities, box)


def packing(n, seed, per):
    sim = binary_disks(n, seed)
    sim.run(collisions=2 * n)
    history = []
    t0 = time.time()
    for rate, pressure in ((1e-2, 1e3), (1e-3, 1e6)):
        res = sim.compress(rate=rate, pressure=pressure, progress=lambda p, z, c: history.append((p, z)))
    rec = EventRecorder()
    sim.writers.append(rec)
    sim.run(collisions=per * n)
    forces = ContactForces().compute(rec)
    gap = Contacts(tolerance=1e-4, h_max=0.1).compute(sim)
    frc = Contacts(tolerance=1e-4, h_max=0.1).compute(sim, forces=forces)
    phi, z = np.array(history).T
    jp = JammingPoint(dim=2).compute(phi, z)
    row = {
        "seed": seed,
        "packing": round(res.packing, 6),
        "Z": float(f"{res.pressure:.4g}"),
        "z_gap": round(gap.z, 4),
        "z_force": round(frc.z, 4),
        "z_isostatic": round(gap.z_isostatic, 4),
        "rattlers_gap": round(gap.rattler_fraction, 4),
        "rattlers_force": round(frc.rattler_fraction, 4),
        "phi_J": round(jp.phi_J, 6),
        "d_fit": round(jp.d_fit, 3),
        "seconds": round(time.time() - t0, 1),
    }
    return row, gap, forces


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=1024)
    ap.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3, 4])
    ap.add_argument("--per-sphere", type=int, default=2000)
    args = ap.parse_args()
    rows, gaps, pooled = [], [], {False: [], True: []}
    for seed in args.seeds:
        row, c, f = packing(args.n, seed, args.per_sphere)
        print(json.dumps(row), flush=True)
        rows.append(row)
        gaps.append(c.backbone_gaps())
        p = f.pairs
        for wb in (False, True):
            drop = c.rattler | ((c.contacts == 3) if wb else False)
            keep = ~(drop[p[:, 0]] | drop[p[:, 1]])
            pooled[wb].append(f.forces[keep] / f.forces[keep].mean())
    h = np.concatenate(gaps)
    for lo, hi in ((1e-4, 1e-2), (1e-4, 1e-3), (1e-3, 1e-2)):
        used = h[(h > lo) & (h <= hi)]
        a = power_law_exponent(used, lo, hi)
        e = _bootstrap(used, lambda s, lo=lo, hi=hi: power_law_exponent(s, lo, hi))
        print(f"gamma in ({lo:g}, {hi:g}]: {1 - a:.3f} +- {e:.3f} ({len(used)} gaps)")
    for wb in (False, True):
        x = np.concatenate(pooled[wb])
        for hi in (0.1, 0.3):
            used = x[x <= hi]
            a = power_law_exponent(used, 0.0, hi)
            e = _bootstrap(used, lambda s, hi=hi: power_law_exponent(s, 0.0, hi))
            label = "without disks of 3 contacts" if wb else "all non-rattlers"
            print(f"theta, f/<f> <= {hi:g}, {label}: {a - 1:.3f} +- {e:.3f} ({len(used)} forces)")
    z = np.array([(r["z_gap"], r["z_force"], r["z_isostatic"]) for r in rows])
    print("mean z (gap, force, isostatic):", z.mean(axis=0).round(4).tolist())
    print(
        "mean rattlers (gap, force):",
        np.mean([(r["rattlers_gap"], r["rattlers_force"]) for r in rows], axis=0).round(4).tolist(),
    )
    print(
        "phi_J:",
        round(float(np.mean([r["phi_J"] for r in rows])), 5),
        "+-",
        round(float(np.std([r["phi_J"] for r in rows], ddof=1) / math.sqrt(len(rows))), 5)
        if len(rows) > 1
        else "",
    )


if __name__ == "__main__":
    main()

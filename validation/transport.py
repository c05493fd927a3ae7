"""Transport validation: D, eta, lambda of the hard-sphere fluid, extrapolated to N -> infinity.

For each packing fraction and system size: equilibrate, then one production
run recording frames (for the MSD and VACF) while the observables sample the
Helfand moments (for eta and lambda) and Z.  D is extrapolated to an
infinite system two ways: Yeh-Hummer from each N with the measured eta
(:func:`hardspheres.transport.yeh_hummer`), and a straight line in 1/L
through all sizes.  Everything is printed as a markdown table, with the
Enskog values (theory, not data) for scale.

usage:
    python3 validation/transport.py                       # ~30 min on 2 cores
    python3 validation/transport.py --sizes 108 256 --time 100 --packings 0.3   # minutes

Units: sigma = m = kT = 1.
"""

import argparse
import math
import sys
import time

import numpy as np

import hardspheres as hs
from hardspheres.trajectory import FrameRecorder
from hardspheres.transport import (
    MSD,
    VACF,
    ShearViscosity,
    ThermalConductivity,
    enskog,
    yeh_hummer,
)


def record(sim, duration, every):
    rec = FrameRecorder(every, events=False)
    sim.writers.append(rec)
    sim.run(until=sim.time + duration)
    sim.writers.remove(rec)
    return rec.frames()


def measure(phi, n, t_run, seed, every=0.1, vacf_mft=300.0):
    L = (n * math.pi / (6.0 * phi)) ** (1.0 / 3.0)
    sim = hs.Simulation(hs.random_spheres(n, phi, box=L, seed=seed), hs.PeriodicBox(L))
    obs = sim.observables
    sim.run(collisions=50 * n)  # melt the lattice and equilibrate
    obs.reset()
    sim.run(collisions=5 * n)
    mft = obs.mean_free_time()
    # the VACF needs frames a tenth of a mean free time apart: a run of its own,
    # 300 mean free times (3000 frames), integrated to 50 (its tail is slow)
    vacf_frames = record(sim, vacf_mft * mft, 0.1 * mft)
    obs.reset(every=0.25 * mft)  # Helfand moments resolved to a quarter mean free time
    frames = record(sim, t_run, every)
    z = obs.estimate("compressibility")
    out = {"phi": phi, "n": n, "L": L, "Z": z.mean, "Z_err": z.sem,
           "collisions": sim.counters["collisions"]}
    out["D_msd"], out["D_msd_err"] = MSD().compute(frames).diffusion()
    out["D_vacf"], out["D_vacf_err"] = VACF(blocks=3).compute(vacf_frames).diffusion()
    out["eta"], out["eta_err"] = ShearViscosity().compute(sim).value()
    out["lambda"], out["lambda_err"] = ThermalConductivity().compute(sim).value()
    out["D_yh"] = yeh_hummer(out["D_msd"], L, out["eta"], obs.temperature())
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--packings", type=float, nargs="+", default=[0.3, 0.45])
    ap.add_argument("--sizes", type=int, nargs="+", default=[256, 500, 1372])
    ap.add_argument("--time", type=float, default=300.0, help="production run [sigma sqrt(m/kT)]")
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args(argv)
    print("| phi | N | Z | D (MSD) | D (VACF) | D_inf (Yeh-Hummer) | D/D_E | eta | eta/eta_E "
          "| lambda | lambda/lambda_E |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for phi in args.packings:
        e = enskog(phi)
        rows = []
        for n in args.sizes:
            t0 = time.perf_counter()
            r = measure(phi, n, args.time, args.seed)
            rows.append(r)
            print(f"| {phi} | {n} | {r['Z']:.4f} +- {r['Z_err']:.4f} "
                  f"| {r['D_msd']:.4f} +- {r['D_msd_err']:.4f} "
                  f"| {r['D_vacf']:.4f} +- {r['D_vacf_err']:.4f} "
                  f"| {r['D_yh']:.4f} | {r['D_msd'] / e['D']:.3f} "
                  f"| {r['eta']:.3f} +- {r['eta_err']:.3f} | {r['eta'] / e['eta']:.3f} "
                  f"| {r['lambda']:.3f} +- {r['lambda_err']:.3f} "
                  f"| {r['lambda'] / e['lambda']:.3f} |", flush=True)
            print(f"<!-- {r['collisions']} collisions in {time.perf_counter() - t0:.0f} s -->",
                  flush=True)
        if len(rows) > 1:
            inv_l = np.array([1.0 / r["L"] for r in rows])
            d = np.array([r["D_msd"] for r in rows])
            w = 1.0 / np.array([r["D_msd_err"] for r in rows]) ** 2
            slope, d_inf = np.polyfit(inv_l, d, 1, w=np.sqrt(w))
            eta = np.mean([r["eta"] for r in rows])
            print(f"\nphi = {phi}: D_inf from a line in 1/L: {d_inf:.4f} (D/D_E {d_inf / e['D']:.3f}); "
                  f"slope {slope:.3f}, Yeh-Hummer slope -2.837297 kT/(6 pi eta) = "
                  f"{-2.837297 / (6 * math.pi * eta):.3f}; Enskog D_E {e['D']:.4f}, "
                  f"eta_E {e['eta']:.4f}, lambda_E {e['lambda']:.4f}\n", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())

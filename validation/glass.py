"""A glass former: the 50:50 binary mixture of diameters 1 and 1.4, compressed, then run at constant energy.

For each packing fraction: N spheres (masses 1, kT = 1) on random sites at
packing 0.1 are compressed (Lubachevsky-Stillinger, ``--rate``) to phi, run
``--equilibrate`` collisions per sphere, then run at constant energy with
frames on the multiple-origin log schedule (``writers.LogOrigins``: lags
from 0.01 to ``--until``, a new origin every ``--every``); then
F_s(k, t) at k = 2 pi / sigma_mean (sigma_mean = 1.2), tau_alpha (F_s =
1/e), alpha_2, and chi_4 of the overlap (a = 0.3), and D from the MSD.
Units: the small diameter, the mass, kT.

    python3 validation/glass.py --n 500 --phi 0.50 0.55 0.58 --until 1000 --every 10 \
        --origins 100 --equilibrate 10000 --json C.json
"""

import argparse
import json
import math
import time

import numpy as np

import hardspheres as hs
from hardspheres.analysis.dynamics import NonGaussian, Overlap, SelfIntermediate
from hardspheres.io.trajectory import FrameRecorder
from hardspheres.writers import LogOrigins

SIGMA_MEAN = 1.2


def binary(n, phi, seed=1, rate=0.01, equilibrate=200):
    """A 50:50 mixture of diameters 1 and 1.4 at packing ``phi`` in a periodic box."""
    vol = n / 2 * math.pi / 6 * (1.0 + 1.4**3)
    box = (vol / phi) ** (1 / 3)
    st = hs.random_spheres(n, 0.1 * phi / 0.5, box=box, seed=seed)  # equal spheres, dilute
    r = np.where(np.arange(n) % 2 == 0, 0.5, 0.7)
    scale = float(st.radii[0]) / 0.7  # the big ones no larger than the sites' spheres
    sim = hs.Simulation(
        hs.State.from_arrays(st.masses, r * scale, st.positions, st.velocities), hs.PeriodicBox(box)
    )
    sim.run(collisions=2 * n)
    res = sim.compress(packing=phi, rate=rate)
    assert res.reason == "packing", res
    sim.run(collisions=equilibrate * n)
    return sim, box


def run(n, phi, until, every, seed, rate, equilibrate, origins):
    t0 = time.time()
    sim, box = binary(n, phi, seed, rate, equilibrate)
    rec = FrameRecorder(trigger=LogOrigins(first=0.01, every=every, per_decade=8, until=until), events=False)
    sim.writers.append(rec)
    sim.observables.reset()
    sim.run(until=sim.time + max(until, origins * every))
    fr = rec.frames()
    sim_s = time.time() - t0
    t1 = time.time()
    k = 2 * math.pi / SIGMA_MEAN
    fs = SelfIntermediate(k=k, per_decade=8, origin_every=every).compute(fr)
    ov = Overlap(a=0.3, per_decade=8, origin_every=every).compute(fr)
    ng = NonGaussian(per_decade=8, origin_every=every).compute(fr)
    try:
        tau, tau_err = fs.tau_alpha()
    except ValueError:
        tau, tau_err = math.nan, math.nan
    sel = (ng.t > 0.3 * ng.t[-1]) & (ng.t < 0.6 * ng.t[-1])
    D = float(np.polyfit(ng.t[sel], ng.msd[sel], 1)[0] / 6) if sel.sum() >= 2 else math.nan
    t_peak, chi_peak = ov.peak()
    row = {
        "n": n,
        "phi": phi,
        "Z": sim.observables.compressibility(),
        "frames": len(fr.times),
        "tau_alpha": tau,
        "tau_alpha_error": tau_err,
        "chi4_peak_t": t_peak,
        "chi4_peak": chi_peak,
        "alpha2_max": float(np.max(ng.alpha2)),
        "D": D,
        "collisions": sim.counters["collisions"],
        "simulate_s": round(sim_s, 1),
        "analyse_s": round(time.time() - t1, 1),
    }
    curves = {
        "t": fs.t.tolist(),
        "Fs": fs.F[:, 0].tolist(),
        "Fs_err": fs.error[:, 0].tolist(),
        "chi4": ov.chi4.tolist(),
        "chi4_err": ov.chi4_error.tolist(),
        "chi4_t": ov.t.tolist(),
        "alpha2": ng.alpha2.tolist(),
    }
    return row, curves


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=1000)
    ap.add_argument("--phi", type=float, nargs="+", default=[0.50, 0.54, 0.56, 0.57, 0.58])
    ap.add_argument("--until", type=float, default=1000.0, help="longest lag")
    ap.add_argument("--every", type=float, default=None, help="time between origins (default until/10)")
    ap.add_argument("--origins", type=int, default=20, help="run at least this many origins")
    ap.add_argument("--rate", type=float, default=0.01)
    ap.add_argument("--equilibrate", type=int, default=200, help="collisions per sphere before the run")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--json", help="write the rows and curves here")
    args = ap.parse_args()
    out = []
    for phi in args.phi:
        every = args.every or args.until / 10
        row, curves = run(
            args.n, phi, args.until, every, args.seed, args.rate, args.equilibrate, args.origins
        )
        print(json.dumps(row), flush=True)
        out.append({"row": row, "curves": curves})
        if args.json:
            with open(args.json, "w") as fh:
                json.dump(out, fh)
    print("fits of tau_alpha(phi): python3 validation/glass_fit.py on the JSON files (--json)")


if __name__ == "__main__":
    main()

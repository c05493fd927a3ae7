"""Why theta of P(f) ~ f^theta comes out below 0.42: the packings and their forces.

Part 1 (``make``): equal spheres in a periodic box compressed as
validation/jamming.py does (rate 1e-2 to Z = 1e3, 1e-3 to 1e5, 1e-4 to
Z > 1e6; ``--fast``: 1e-3 straight from 1e3 to 1e6), then three
consecutive records at fixed radii of 200, 2000 and 20000 collisions per
sphere, each giving the time-averaged contact forces (Donev, Torquato and
Stillinger, PRE 71, 011105 (2005)).  Each packing and its forces go to
``DIR/theta_N_SEED.npz``.

Part 2 (``fit``): pooled over the packings, theta by maximum likelihood for
``f/<f>`` in ``(0, f_max]``, and the local exponent ``d ln G / d ln f - 1`` of
the cumulative ``G(f)`` (two points a factor 3 apart), for each record
length, with all forces between non-rattlers, with only the pairs that are
contacts by gap (``h <= 100 / Z``, 1e-4 at Z = 1e6), and without the forces on spheres of
exactly d + 1 contacts (bucklers, Charbonneau, Corwin, Parisi and Zamponi,
PRL 114, 125504 (2015)); and with the pairs of the network cut where it is
isostatic (``isostatic_tolerance``, ``force_exponent(contacts_only=True)``),
with and without bucklers.  ``stationarity``: whether the network changed
between the 2000- and the 20000-collision records.

    python3 validation/jamming_theta.py make --n 500 --seeds 1 2 3 4 5 6 --dir packs
    python3 validation/jamming_theta.py deepen 'packs/theta_500_?.npz' --pressure 1e7
    python3 validation/jamming_theta.py fit 'packs/theta_500_?.npz'
    python3 validation/jamming_theta.py fit 'packs/theta_500_?_z1e+07.npz'

``deepen`` compresses each packing on (rate 1e-3, new velocities) to Z >
1e7 and records its forces again, to see what the finite pressure does.
"""

import argparse
import glob
import json
import time

import numpy as np

import hardspheres as hs
from hardspheres.analysis.collisions import ContactForces, EventRecorder
from hardspheres.analysis.jamming import (
    Contacts,
    _bootstrap,
    force_exponent,
    isostatic_tolerance,
    power_law_exponent,
)

SLOW = ((1e-2, 1e3), (1e-3, 1e5), (1e-4, 1e6))
FAST = ((1e-2, 1e3), (1e-3, 1e6))
RECORDS = (200, 2000, 20000)


def make(n, seed, stages, out):
    box = hs.PeriodicBox.for_packing(n, 0.3).length
    sim = hs.Simulation(hs.random_spheres(n, 0.3, box=box, seed=seed), hs.PeriodicBox(box))
    sim.run(collisions=2 * n)
    history = []
    t0 = time.time()
    for rate, pressure in stages:
        res = sim.compress(rate=rate, pressure=pressure, progress=lambda p, z, c: history.append((p, z)))
    t1 = time.time()
    st = sim.state()
    data = {"positions": st.positions, "radii": st.radii, "box": box, "history": np.array(history)}
    data["Z"] = res.pressure
    for per in RECORDS:
        rec = EventRecorder()
        sim.writers.append(rec)
        sim.run(collisions=per * n)
        sim.writers.remove(rec)
        f = ContactForces().compute(rec)
        data[f"pairs_{per}"], data[f"forces_{per}"] = f.pairs, f.forces
        del rec
    np.savez(out, **data)
    print(
        json.dumps(
            {
                "n": n,
                "seed": seed,
                "packing": res.packing,
                "Z": res.pressure,
                "compress_s": round(t1 - t0, 1),
                "records_s": round(time.time() - t1, 1),
            }
        ),
        flush=True,
    )


def deepen(path, pressure, rate=1e-3):
    """The packing of ``path`` compressed on to Z > ``pressure``, then its records; written beside it."""
    d = np.load(path)
    n = len(d["radii"])
    rng = np.random.default_rng(0)
    v = rng.normal(size=(n, 3))
    v -= v.mean(axis=0)
    box = float(d["box"])
    sim = hs.Simulation.from_arrays(np.ones(n), d["radii"], d["positions"], v, hs.PeriodicBox(box))
    sim.run(collisions=20 * n)
    t0 = time.time()
    res = sim.compress(rate=rate, pressure=pressure)
    t1 = time.time()
    st = sim.state()
    data = {"positions": st.positions, "radii": st.radii, "box": box, "history": d["history"]}
    data["Z"] = res.pressure
    for per in RECORDS:
        rec = EventRecorder()
        sim.writers.append(rec)
        sim.run(collisions=per * n)
        sim.writers.remove(rec)
        f = ContactForces().compute(rec)
        data[f"pairs_{per}"], data[f"forces_{per}"] = f.pairs, f.forces
        del rec
    out = path.replace(".npz", f"_z{pressure:.0e}.npz")
    np.savez(out, **data)
    print(
        json.dumps(
            {
                "from": path,
                "packing": res.packing,
                "Z": res.pressure,
                "compress_s": round(t1 - t0, 1),
                "records_s": round(time.time() - t1, 1),
            }
        ),
        flush=True,
    )


def local_exponents(x, points):
    """``theta(f) = d ln G / d ln f - 1`` from G at f / sqrt(3) and f sqrt(3)."""
    x = np.sort(x)
    out = []
    for f in points:
        lo, hi = np.searchsorted(x, f / np.sqrt(3.0)), np.searchsorted(x, f * np.sqrt(3.0))
        if lo < 5:
            out.append((f, float("nan"), int(hi)))
            continue
        slope = np.log(hi / lo) / np.log(3.0)
        out.append((f, slope - 1.0, int(hi)))
    return out


def stationarity(files):
    """The same pairs in the 2000- and the 20000-collision records: did the network change?"""
    small = was_absent = was_small = was_big = 0
    changes = []
    for path in files:
        d = np.load(path)
        z_end = float(d["Z"]) if "Z" in d else float(d["history"][-1, 1])
        c = Contacts(tolerance=100.0 / z_end, h_max=100.0 / z_end).compute(
            d["positions"], radii=d["radii"], box=float(d["box"])
        )

        def forces(per, c=c, d=d):
            p, f = d[f"pairs_{per}"], d[f"forces_{per}"]
            keep = ~(c.rattler[p[:, 0]] | c.rattler[p[:, 1]])
            return {tuple(q): x / f[keep].mean() for q, x in zip(p[keep].tolist(), f[keep])}

        short, long = forces(2000), forces(20000)
        for pair, x in long.items():
            y = short.get(pair)
            if x < 0.03:
                small += 1
                was_absent += y is None
                was_small += y is not None and y <= 0.1
                was_big += y is not None and y > 0.1
            if x > 0.3 and y is not None:
                changes.append(abs(y - x) / x)
    print(
        f"forces below 0.03 <f> in the 20000-collision record: {small}; in the 2000-collision record "
        f"before it: absent {was_absent}, below 0.1 <f> {was_small}, above {was_big}; forces above "
        f"0.3 <f>: median relative change {np.median(changes):.4f}, 95th percentile "
        f"{np.quantile(changes, 0.95):.4f} ({len(changes)} pairs)"
    )


def tolerance_scan(files):
    """theta (f/<f> <= 0.1) and z with contacts at gaps below c / Z, c = 10, 30, 100, 300."""
    for c_tol in (10, 30, 100, 300):
        for per in (2000, 20000):
            xs, zs, ziso = [], [], []
            for path in files:
                d = np.load(path)
                z_end = float(d["Z"]) if "Z" in d else float(d["history"][-1, 1])
                tol = c_tol / z_end
                c = Contacts(tolerance=tol, h_max=tol).compute(
                    d["positions"], radii=d["radii"], box=float(d["box"])
                )
                zs.append(c.z)
                ziso.append(c.z_isostatic)
                net = {tuple(q) for q in c.pairs.tolist()}
                p, f = d[f"pairs_{per}"], d[f"forces_{per}"]
                keep = ~(c.rattler[p[:, 0]] | c.rattler[p[:, 1]]) & np.array(
                    [tuple(q) in net for q in p.tolist()]
                )
                xs.append(f[keep] / f[keep].mean())
            x = np.concatenate(xs)
            u = x[x <= 0.1]
            a = power_law_exponent(u, 0.0, 0.1)
            e = _bootstrap(u, lambda s: power_law_exponent(s, 0.0, 0.1))
            print(
                f"contacts at gaps < {c_tol}/Z, {per} per sphere: z {np.mean(zs):.4f} (isostatic "
                f"{np.mean(ziso):.4f}), theta <= 0.1: {a - 1:.3f} +- {e:.3f} ({len(u)})"
            )


def fit(pattern):
    files = sorted(glob.glob(pattern))
    sets = {}
    for path in files:
        d = np.load(path)
        z_end = float(d["Z"]) if "Z" in d else float(d["history"][-1, 1])
        tol = 100.0 / z_end  # contacts: gaps below 100 / Z (1e-4 at Z = 1e6)
        c = Contacts(tolerance=tol, h_max=tol).compute(d["positions"], radii=d["radii"], box=float(d["box"]))
        contact = {tuple(p) for p in c.pairs.tolist()}
        iso_tol = isostatic_tolerance(d["positions"], radii=d["radii"], box=float(d["box"]))
        iso = Contacts(tolerance=iso_tol, h_max=iso_tol).compute(
            d["positions"], radii=d["radii"], box=float(d["box"])
        )
        sets.setdefault("cut", []).append(iso_tol * z_end)

        class Rec:  # the stored forces, as force_exponent reads them
            _need = staticmethod(lambda: None)

        for per in RECORDS:
            Rec.pairs, Rec.forces = d[f"pairs_{per}"], d[f"forces_{per}"]
            for name, wb in (("isostatic cut", False), ("isostatic, no bucklers", True)):
                p, f = Rec.pairs, Rec.forces
                net = {tuple(q) for q in iso.pairs.tolist()}
                drop = iso.rattler | ((iso.contacts == iso.dim + 1) & ~iso.rattler if wb else False)
                keep = ~(drop[p[:, 0]] | drop[p[:, 1]]) & np.array([tuple(q) in net for q in p.tolist()])
                theta_all = force_exponent(Rec(), iso, f_max=100.0, without_bucklers=wb, contacts_only=True)
                assert theta_all[2] == keep.sum()  # the library's selection is this one
                sets.setdefault((per, name), []).append(f[keep] / f[keep].mean())
            p, f = d[f"pairs_{per}"], d[f"forces_{per}"]
            nonr = ~(c.rattler[p[:, 0]] | c.rattler[p[:, 1]])
            buck = (c.contacts == c.dim + 1) & ~c.rattler
            nob = nonr & ~(buck[p[:, 0]] | buck[p[:, 1]])
            bygap = nonr & np.array([tuple(q) in contact for q in p.tolist()])
            for name, keep in (("non-rattlers", nonr), ("contacts by gap", bygap), ("no bucklers", nob)):
                x = f[keep] / f[keep].mean()
                sets.setdefault((per, name), []).append(x)
    print(f"{len(files)} packings: {', '.join(files)}")
    stationarity(files)
    tolerance_scan(files)
    cut = sets.pop("cut")
    print(f"isostatic cut (isostatic_tolerance) at {min(cut):.0f}-{max(cut):.0f} / Z")
    for (per, name), xs in sets.items():
        x = np.concatenate(xs)
        fits = []
        for hi in (0.03, 0.1, 0.3):
            used = x[x <= hi]
            a = power_law_exponent(used, 0.0, hi)
            e = _bootstrap(used, lambda s, hi=hi: power_law_exponent(s, 0.0, hi))
            fits.append(f"<= {hi:g}: {a - 1:.3f} +- {e:.3f} ({len(used)})")
        loc = ", ".join(f"{f:g}: {t:.2f}" for f, t, _ in local_exponents(x, (0.01, 0.03, 0.1, 0.3)))
        print(
            f"{per:>5} per sphere, {name:22s} {len(x):6d} forces | theta "
            + "; ".join(fits)
            + f" | local {loc}"
        )


def main():
    ap = argparse.ArgumentParser()
    sub = ap.add_subparsers(dest="what", required=True)
    m = sub.add_parser("make")
    m.add_argument("--n", type=int, default=500)
    m.add_argument("--seeds", type=int, nargs="+", default=[1])
    m.add_argument("--fast", action="store_true")
    m.add_argument("--dir", default=".")
    dp = sub.add_parser("deepen")
    dp.add_argument("pattern")
    dp.add_argument("--pressure", type=float, default=1e7)
    f = sub.add_parser("fit")
    f.add_argument("pattern")
    args = ap.parse_args()
    if args.what == "deepen":
        for path in sorted(glob.glob(args.pattern)):
            deepen(path, args.pressure)
    elif args.what == "make":
        for seed in args.seeds:
            make(args.n, seed, FAST if args.fast else SLOW, f"{args.dir}/theta_{args.n}_{seed}.npz")
    else:
        fit(args.pattern)


if __name__ == "__main__":
    main()

"""Direct coexistence of hard-sphere crystal and fluid: bracketing the pressure by the drift.

For each pressure, an FCC slab ((100) or (111) normal to z,
hardspheres.analysis.coexistence.crystal_fluid_slab) beside a fluid slab
runs at constant normal pressure (hardspheres.Barostat, ``axes="z"``: the
cross-section stays the crystal's, so it is not strained); the crystal
fraction by local q6 (SlabProfile) is printed every ``--every`` time units,
and its slope over the second half of the run is the drift: positive (the
crystal grows) above the coexistence pressure, negative below.  The
published value: Fernandez, Martinez-Ruiz and Vega, Phys. Rev. Lett. 108,
165701 (2012), beta P sigma^3 = 11.5727(10), coexisting packings 0.4917
and 0.5433 (N >= 10^4 there).  Running time: about 1 minute per pressure
at the defaults (a 3 x 3 x 6 cell slab, 216 + about 200 spheres, t = 40) on
this shared machine; ``--cells 10 10 20 --until 2000`` is the scale of the
published target (N of about 1.6 x 10^4; days on one core, not run here).

usage: python3 validation/coexistence.py [--pressures 10.5 12.5] [--cells X Y Z] [--plane 100|111]
       [--until T] [--every T] [--seed S]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import hardspheres as hs
from hardspheres.analysis.coexistence import SlabProfile, crystal_fluid_slab


def drift(
    pressure: float, cells: tuple[int, int, int], plane: str, until: float, every: float, seed: int
) -> float:
    """The crystal fraction's slope [1/time] over the run's second half, printing its course."""
    state, box = crystal_fluid_slab(
        cells, plane=plane, crystal_packing=0.5433, fluid_packing=0.4917, seed=seed
    )
    sim = hs.Simulation(state, box)
    sim.set_barostat(hs.Barostat(pressure=pressure, kT=1.0, axes="z", seed=seed))
    profile = SlabProfile(bins=20)
    ts, fs = [], []
    t0 = time.time()
    while sim.time < until - 1e-9:
        sim.run(until=min(until, sim.time + every))
        profile.compute(sim)
        ts.append(sim.time)
        fs.append(profile.crystal_fraction)
        print(
            f"  beta P {pressure:g}  t {sim.time:7.1f}  crystal fraction {fs[-1]:.3f}  "
            f"packing {sim.packing:.4f}  Lz {sim.container.sides[2]:.3f}  ({time.time() - t0:.0f} s)",
            flush=True,
        )
    half = len(ts) // 2
    if fs[-1] < 0.02:  # melted away: no interface left to drift
        return float("nan")
    return float(np.polyfit(ts[half:], fs[half:], 1)[0])


def main() -> None:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("--pressures", type=float, nargs="+", default=[10.5, 12.5])
    ap.add_argument("--cells", type=int, nargs=3, default=[3, 3, 6])
    ap.add_argument("--plane", default="100", choices=["100", "111"])
    ap.add_argument("--until", type=float, default=40.0)
    ap.add_argument("--every", type=float, default=4.0)
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args()
    t0 = time.time()
    rows = []
    for p in args.pressures:
        rows.append((p, drift(p, tuple(args.cells), args.plane, args.until, args.every, args.seed)))
    print("\n| beta P sigma^3 | crystal fraction drift [1/time] | the crystal |")
    print("|---|---|---|")
    for p, d in rows:
        what = "melted away (no interface left)" if d != d else ("grows" if d > 0 else "melts")
        print(f"| {p:g} | {d:+.2e} | {what} |")
    grows = [p for p, d in rows if d > 0]
    melts = [p for p, d in rows if d <= 0 or d != d]
    if grows and melts and max(melts) < min(grows):
        lo, hi = max(melts), min(grows)
        print(f"\ncoexistence bracketed: {lo:g} < beta P sigma^3 < {hi:g} (published 11.5727(10))")
    else:
        print("\nnot bracketed by these pressures (published 11.5727(10))")
    print(f"total {time.time() - t0:.0f} s")


if __name__ == "__main__":
    main()

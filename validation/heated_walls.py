"""The thermal wall: elastic spheres relax to its temperature; a heated granular gas balances.

Equal spheres (sigma = m = 1) in a spherical container (3-D) or circle (2-D),
the wall a thermal wall at kT_w = 1 (:meth:`hardspheres.Simulation.set_wall_temperature`),
started at kT = 0.25.  Sampled every SAMPLE collisions per sphere after
WARM of them; errors by blocking.

* Elastic spheres (e = 1): the wall is a heat bath, so the kinetic
  temperature reaches kT_w exactly (no theory beyond detailed balance) and
  the velocities are Maxwellian: a_2 = <v^4> / (<v^2>^2 (1 + 2/d)) - 1,
  formed per sample from the N spheres' moments, is -2 / (N d + 2) for N
  independent Maxwellian velocities (|v_i|^2 / sum |v_j|^2 is Dirichlet
  distributed, independent of the sum), the same offset as at fixed energy.
* Granular gases (e = 0.9, 0.7): a steady state where the wall's heat
  balances what the collisions dissipate.  Printed: kT / kT_w, the heat
  over the dissipation in the sampled window (1 up to the change of the
  kinetic energy over it), and the profiles kT(r) / kT_w and n(r) / n_mean
  in shells of equal volume from the centre out (of the region the centres
  can reach).  No a_2 is printed for them: the gas is not homogeneous, and
  the kurtosis of its velocities mixes temperatures.  The gas is colder and
  denser away from the heated wall (the profile Grossman, Zhou and
  Ben-Naim, Phys. Rev. E 55, 4200 (1997), derived for a gas heated at its
  boundary).

    python3 validation/heated_walls.py     # validation/results/heated_walls.txt (about 10 minutes)
"""

import math
import os
import sys
import time

import numpy as np

import hardspheres as hs
from hardspheres.blocking import blocking
from hardspheres.fileio import atomic_write

N = {2: 400, 3: 400}
PHI = 0.1
WARM, SAMPLE, SAMPLES = 30.0, 2.0, 2000
SHELLS = 5


def run(d: int, e: float, seed: int = 1) -> dict:
    box = hs.CircularContainer(1.0) if d == 2 else hs.SphericalContainer(1.0)
    n = N[d]
    vol1 = math.pi / 4 if d == 2 else math.pi / 6  # a unit-diameter disk's area, sphere's volume
    radius = (n * vol1 / PHI / (math.pi if d == 2 else 4 * math.pi / 3)) ** (1 / d)
    box = hs.CircularContainer(radius) if d == 2 else hs.SphericalContainer(radius)
    state = hs.random_spheres(n, PHI, box, seed=seed, kT=0.25)
    sim = hs.Simulation(state, box, restitution=e, tc=1e-4).set_wall_temperature(1.0, seed=seed)
    sim.run(collisions=int(WARM * n / 2))
    heat0, lost0, e0 = sim.wall_heat, sim.dissipated, sim.engine.kinetic_energy()
    temps, a2s = [], []
    reach = radius - 0.5  # where the centres can be
    edges = reach * (np.arange(SHELLS + 1) / SHELLS) ** (1 / d)  # shells of equal volume
    shell_t, shell_n = np.zeros(SHELLS), np.zeros(SHELLS)
    t0 = time.process_time()
    for _ in range(SAMPLES):
        sim.run(collisions=max(1, int(SAMPLE * n / 2)))
        v = sim.engine.velocities
        v2 = np.sum(v * v, axis=1)
        temps.append(float(np.mean(v2)) / d)
        a2s.append(float(np.mean(v2 * v2) / (np.mean(v2) ** 2 * (1 + 2 / d)) - 1.0))
        r = np.linalg.norm(sim.engine.positions_at(), axis=1)
        k = np.clip(np.searchsorted(edges, r, side="right") - 1, 0, SHELLS - 1)
        for s in range(SHELLS):
            inside = k == s
            shell_n[s] += np.count_nonzero(inside)
            shell_t[s] += float(np.sum(v2[inside])) / d
    heat, lost = sim.wall_heat - heat0, sim.dissipated - lost0
    tb, ab = blocking(temps), blocking(a2s)
    return dict(
        d=d,
        e=e,
        n=n,
        kt=tb.mean,
        kt_err=tb.sem,
        converged=tb.converged and (ab.converged or e != 1.0),
        a2=ab.mean if e == 1.0 else math.nan,
        a2_err=ab.sem,
        balance=(heat / lost) if lost > 0 else math.nan,
        dE=(sim.engine.kinetic_energy() - e0) / max(lost, 1e-300) if lost > 0 else math.nan,
        profile_t=shell_t / np.maximum(shell_n, 1) / 1.0,
        profile_n=shell_n / (SAMPLES * n / SHELLS),
        cpu=time.process_time() - t0,
    )


def main() -> None:
    rows = []
    head = (
        f"thermal wall at kT_w = 1, packing {PHI}, {WARM:g} collisions per sphere to warm, "
        f"{SAMPLES} samples every {SAMPLE:g}; errors by blocking"
    )
    lines = [
        head,
        "d  e    N    kT/kT_w          a_2 (-2/(Nd+2))          heat/dissipated  "
        "kT(r)/kT_w centre->wall   n(r)/n",
    ]
    for d in (2, 3):
        for e in (1.0, 0.9, 0.7):
            r = run(d, e)
            rows.append(r)
            bal = "-" if math.isnan(r["balance"]) else f"{r['balance']:.4f}"
            offset = -2.0 / (r["n"] * d + 2)
            a2 = "-" if math.isnan(r["a2"]) else f"{r['a2']:+.4f}({r['a2_err']:.4f}) ({offset:+.4f})"
            flag = "" if r["converged"] else "  (an error without a plateau: a lower bound)"
            lines.append(
                f"{d}  {e:<4g} {r['n']:<4d} {r['kt']:.4f}({r['kt_err']:.4f})  "
                f"{a2:<24} {bal:<16} "
                + " ".join(f"{x:.3f}" for x in r["profile_t"])
                + "   "
                + " ".join(f"{x:.2f}" for x in r["profile_n"])
                + flag
            )
            print(lines[-1], flush=True)
    out = os.path.join(os.path.dirname(__file__), "results", "heated_walls.txt")
    with atomic_write(out, "w") as fh:
        fh.write("\n".join(lines) + "\n")
    print(f"wrote {out}", file=sys.stderr)


if __name__ == "__main__":
    main()

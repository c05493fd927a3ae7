"""A deep square well (eps = 5 kT) over 10^7 events: energy conserved to rounding, no bounce loop.

Spheres of diameter and mass one in a periodic box, ``hs.Simulation(...,
steps=[(1.5, -5.0)])``, brought to kT = 1 (``eps = 5 kT``) by an Andersen
thermostat over ``--equil`` events, then the thermostat is removed and the
run goes on at constant energy.  Two systems (``--start``):

* ``fluid``: N = 1000 placed at random at packing 0.3 (number density
  0.573).  Far below the critical temperature (about 0.24 eps) the spheres
  condense into bonded clusters, which go on growing at constant energy,
  each new bond giving its pair 5 units of kinetic energy: the temperature
  creeps up (``eps / kT`` is printed as the run goes);
* ``crystal``: N = 864 on an FCC lattice at number density 0.8, every
  nearest neighbour (1.21 apart) in the well: bonds break and re-form (a
  pair needs 5 kT along its line of centres to leave) while the crystal
  holds, so the temperature stays near 1.
``--events`` events (core collisions, captures, releases and bounces) in
chunks of ``--chunk``, each chunk recorded:

* the total energy ``E = K + U`` (``sim.total_energy()``, ``U = -eps`` times
  the bonded pairs) after each chunk against its start, relative to the
  kinetic energy then (``K`` is the larger: ``E`` itself can be near zero);
* that each chunk ended after exactly its events (a loop would stop the
  clock: the engine raises ``StuckError``, or a pair's events pile up at one
  time), with the clock advancing: the least time between two consecutive
  events of one pair in the whole run, and the number of such repeats at
  the same time (zero: no pair ever has two events at one instant);
* the counts of collisions, captures, releases and bounces, and the bonds at
  the end checked against the distances (each bonded pair inside
  ``1.5 sigma``, each other pair outside, no cores overlapping).

Output kept in validation/results/square_well_deep.txt (both starts)
(docs/validation/square-well.md, section 5).

usage:
    python3 validation/square_well_deep.py                  # about 75 s of CPU
    python3 validation/square_well_deep.py --start crystal
    python3 validation/square_well_deep.py --events 1e5 --equil 1e5   # a quick look
"""

import argparse
import math
import time

import numpy as np

import hardspheres as hs
from hardspheres.builders import crystal
from hardspheres.dense import Andersen

LAM, EPS, KEY = 1.5, 5.0, 1 << 20  # KEY: a pair (i, j) is i * KEY + j


def pair_gaps(ev: np.ndarray, last: dict[int, float]) -> tuple[float, int]:
    """The least time between consecutive events of one pair, and how many are at the same time.

    ``last`` maps a pair's key to its last event time before this chunk, and is updated.
    """
    pairs = ev[ev["j"] >= 0]
    key = np.minimum(pairs["i"], pairs["j"]).astype(np.int64) * KEY + np.maximum(pairs["i"], pairs["j"])
    order = np.argsort(key, kind="stable")  # within a pair: in time order
    k, t = key[order], pairs["time"][order]
    same = k[1:] == k[:-1]
    gaps = (t[1:] - t[:-1])[same]
    first = np.ones(len(k), bool)
    first[1:] = ~same
    before = np.array([t0 - last.get(int(kk), -np.inf) for kk, t0 in zip(k[first], t[first])])
    ends = np.ones(len(k), bool)
    ends[:-1] = ~same
    last.update(zip(k[ends].tolist(), t[ends].tolist()))
    allg = np.concatenate([gaps, before])
    return (float(allg.min()) if len(allg) else math.inf), int(np.sum(allg <= 0.0))


def check_bonds(sim: hs.Simulation) -> tuple[int, float]:
    """Every pair state against the distances: returns (bonds, least core distance)."""
    pos = np.asarray(sim.state().positions)
    side = np.asarray(sim.container.sides)
    states = sim.engine.pair_states
    least, bonds = math.inf, 0
    for i in range(len(pos) - 1):
        d = pos[i + 1 :] - pos[i]
        d -= side * np.round(d / side)
        r = np.sqrt(np.sum(d * d, axis=1))
        least = min(least, float(r.min()))
        inside = np.nonzero(r < LAM)[0] + i + 1
        bonded = {j for (a, j) in states if a == i}
        if bonded != set(inside.tolist()):
            raise AssertionError(f"sphere {i}: bonds {sorted(bonded)} but within the well {inside.tolist()}")
        bonds += len(bonded)
    if bonds != len(states) or sim.potential_energy() != -EPS * bonds:
        raise AssertionError("the bond count or the potential energy disagrees with the pair states")
    return bonds, least


def build(start: str, equil: float, seed: int) -> hs.Simulation:
    """The deep-well system at kT = 1 (thermostat removed): a condensing ``fluid`` or an FCC ``crystal``."""
    if start == "fluid":
        box = hs.PeriodicBox.for_packing(1000, 0.3)
        state = hs.random_spheres(1000, 0.3, box, seed=seed)
    else:
        state, box = crystal("fcc", (6, 6, 6), 0.8 * math.pi / 6.0, radius=0.5, kT=1.0, seed=seed)
    sim = hs.Simulation(state, box, steps=[(LAM, -EPS)])
    sim.set_thermostat(Andersen(kT=1.0, rate=2.0, seed=seed)).run(events=int(equil))
    sim.set_thermostat(None)
    n, kin = sim.n, sim.engine.kinetic_energy()
    print(
        f"{start}: N = {n}, number density {n / box.volume:.4f}, lambda = {LAM}, eps = {EPS};"
        f" Andersen at kT = 1 over {equil:.0e} events, then constant energy from"
        f" kT {2.0 * kin / (3.0 * n):.4f}, bonds/N {len(sim.engine.pair_states) / n:.4f}"
    )
    return sim


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--start", choices=("fluid", "crystal"), default="fluid", help="the system (see above)")
    ap.add_argument("--events", type=float, default=1e7, help="events in all, at constant energy")
    ap.add_argument("--chunk", type=float, default=1e6, help="events per recorded chunk")
    ap.add_argument("--equil", type=float, default=2e6, help="events with the thermostat, before")
    ap.add_argument("--seed", type=int, default=5)
    args = ap.parse_args()
    cpu = time.process_time()
    sim = build(args.start, args.equil, args.seed)
    n, e0, c0 = sim.n, sim.total_energy(), sim.engine.counters
    print("events      time       kT      eps/kT  bonds/N  (E - E0)/K")
    last: dict[int, float] = {}
    least, repeats, done, worst = math.inf, 0, 0, 0.0
    while done < args.events:
        step = int(min(args.chunk, args.events - done))
        ev = sim.engine.advance(events=step)
        if len(ev) != step:
            raise AssertionError(f"a chunk of {step} events ended after {len(ev)}")
        g, r = pair_gaps(ev, last)
        least, repeats, done = min(least, g), repeats + r, done + step
        kin = sim.engine.kinetic_energy()
        kt, drift = 2.0 * kin / (3.0 * n), (sim.total_energy() - e0) / kin
        worst = max(worst, abs(drift))
        print(
            f"{done:.3e}  {sim.time:9.3f}  {kt:7.4f}  {EPS / kt:6.3f}  {len(sim.engine.pair_states) / n:7.4f}"
            f"  {drift:+.2e}",
            flush=True,
        )
    c = {k: v - c0[k] for k, v in sim.engine.counters.items()}  # (the constant-energy run's)
    bonds, core = check_bonds(sim)
    print(
        f"events {done} ({c['collisions'] + c['captures'] + c['releases'] + c['bounces']} pair events):"
        f" {c['collisions']} collisions, {c['captures']} captures, {c['releases']} releases,"
        f" {c['bounces']} bounces"
    )
    print(f"largest |E - E0| / K over the run {worst:.2e}; total energy now {sim.total_energy():.6f}")
    print(f"least time between two events of one pair {least:.3e}; repeats at one time: {repeats}")
    print(f"bonds at the end {bonds} (all inside 1.5, all others outside); least distance {core:.6f}")
    print(f"CPU time {time.process_time() - cpu:.0f} s")


if __name__ == "__main__":
    main()

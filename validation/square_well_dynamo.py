"""DynamO's square-well regression test, rerun on the compiled event core: the mean free time.

DynamO (github.com/dynamomd/DynamO) checks its square well in
``src/dynamo/tests/squarewell_test.cpp`` (test case ``NVT_Simulation``):
N = 1372 spheres on an FCC 7 x 7 x 7 lattice, number density 0.5, well
width lambda = 1.5, depth 1, mass 1 (units: the diameter, the mass and
the well depth), velocities scaled to kT = 1 with zero momentum, an
Andersen thermostat at kT = 1 (``SysAndersen``: one random sphere gets a
Maxwell velocity per thermostat event; its event rate is retuned every
100 thermostat events so that thermostat events are 5 % of all events,
``setPoint = 0.05``), 300 000 events of equilibration, then 100 000
events measured; the test asserts ``OPMisc::getMFT() = 0.0368185`` within
8 % (5 % before April 2025).  ``getMFT`` is ``t N / (2 n_pair + n_single)``:
each pair event (core collision, capture, release, bounce) counts twice,
each thermostat event once, ``t`` the measured duration.

Here: the same system with ``hs.Simulation(..., steps=[(1.5, -1.0)])``
and :class:`hardspheres.dense.Andersen`, its rate retuned after each
chunk of events so that thermostat kicks are 5 % of all events (pair
events plus kicks), the same event counts (kicks included), several
seeds for an error bar.  Then one run is continued to see whether the
state drifts: at kT = 1 (below the lambda = 1.5 critical temperature)
the homogeneous fluid at density 0.5 can phase-separate, and its mean
free time and energy then move with time.

Output kept in validation/results/square_well_dynamo.txt
(docs/validation/square-well.md).

usage:
    python3 validation/square_well_dynamo.py                  # about 5 minutes of CPU
    python3 validation/square_well_dynamo.py --seeds 3 --long 0  # a quick look
"""

import argparse
import math
import time

import numpy as np

import hardspheres as hs
from hardspheres.builders import crystal
from hardspheres.dense import Andersen

LAM, EPS, RHO, KICKS = 1.5, 1.0, 0.5, 0.05  # KICKS: thermostat events / all events (DynamO's setPoint)
DYNAMO_MFT = 0.0368185


def pair_events(sim: hs.Simulation) -> int:
    """Core collisions, captures, releases and bounces so far."""
    c = sim.engine.counters
    return c["collisions"] + c["captures"] + c["releases"] + c["bounces"]


def window(
    sim: hs.Simulation, duration: float, blocks: int, samples: int, kT: float
) -> dict[str, np.ndarray]:
    """Run ``duration`` [time] in ``blocks`` equal blocks: per block Z, Z_ex, U/N, kT and the pair events.

    ``Z = (W + 2 int K dt) / (3 t N kT)`` with the set ``kT`` (the thermostat's), ``W`` the
    trace of the collisional virial (core collisions and every step event) and ``int K dt``
    from the engine's kinetic tally: both exact time integrals over the block (``Zex``: the
    virial part alone, ``W / (3 t N kT)``).  ``U/N`` is
    the average of ``samples`` values per block taken at evenly spaced times (an unbiased
    time average), and the block's kinetic ``kT = 2 <K> / (3 N)`` (the thermostat does not
    conserve momentum: 3 N degrees of freedom).
    """
    n, out = sim.n, {"Z": [], "Zex": [], "U": [], "kT": [], "t": [], "pairs": []}
    step = duration / (blocks * samples)
    for _ in range(blocks):
        t0, p0 = sim.time, pair_events(sim)
        tt0 = sim.engine.transport_tallies(t0)
        u = 0.0
        for k in range(samples):
            sim.run(until=t0 + (k + 0.5) * step)
            u += sim.potential_energy()
        sim.run(until=t0 + samples * step)
        t1 = sim.time
        tt1 = sim.engine.transport_tallies(t1)
        vir = float(np.sum(tt1["virial"][:3] - tt0["virial"][:3]))
        kin = float(np.sum(tt1["kinetic"][:3] - tt0["kinetic"][:3]))  # int sum m v^2 dt = int 2K dt
        out["Z"].append((vir + kin) / (3.0 * (t1 - t0) * n * kT))
        out["Zex"].append(vir / (3.0 * (t1 - t0) * n * kT))  # the excess part alone: Z - Z_ideal
        out["U"].append(u / samples / n)
        out["kT"].append(kin / (3.0 * n * (t1 - t0)))
        out["t"].append(t1 - t0)
        out["pairs"].append(pair_events(sim) - p0)
    return {k: np.array(v) for k, v in out.items()}


def build(seed: int) -> tuple[hs.Simulation, Andersen]:
    """DynamO's start: FCC 7x7x7 (N = 1372) at number density 0.5, kT = 1, Andersen at kT = 1."""
    state, box = crystal("fcc", (7, 7, 7), RHO * math.pi / 6.0, radius=0.5, kT=1.0, seed=seed)
    sim = hs.Simulation(state, box, steps=[(LAM, -EPS)])
    thermo = Andersen(kT=1.0, rate=0.6, seed=seed)
    sim.set_thermostat(thermo)
    return sim, thermo


def run_events(sim: hs.Simulation, thermo: Andersen, total: int, chunk: int = 5000) -> dict[str, float]:
    """Run until pair events + kicks reach ``total``, retuning the kick rate to 5 % of events.

    Returns the counts over the run: ``t`` (duration), ``pairs``, ``kicks``
    and ``mft = t N / (2 pairs + kicks)``.
    """
    t0, p0, k0 = sim.time, pair_events(sim), thermo.resampled
    while True:
        done = (pair_events(sim) - p0) + (thermo.resampled - k0)
        if done >= total:
            break
        ta, pa = sim.time, pair_events(sim)
        sim.run(events=int(min(chunk, math.ceil((total - done) * (1.0 - KICKS)))))
        rate = (pair_events(sim) - pa) / (sim.n * (sim.time - ta))  # pair events per sphere per time
        thermo.rate = KICKS / (1.0 - KICKS) * rate  # kicks per sphere per time
    t, pairs, kicks = sim.time - t0, pair_events(sim) - p0, thermo.resampled - k0
    return {"t": t, "pairs": pairs, "kicks": kicks, "mft": t * sim.n / (2 * pairs + kicks)}


def protocol(seed: int) -> dict[str, float]:
    """DynamO's protocol: 3e5 events of equilibration, then 1e5 measured."""
    sim, thermo = build(seed)
    run_events(sim, thermo, 300_000)
    sim.observables.reset()
    r = run_events(sim, thermo, 100_000)
    r["kT"] = sim.observables.temperature()
    r["u"] = sim.potential_energy() / sim.n
    r["seed"] = seed
    r["sim"] = sim
    r["thermo"] = thermo
    return r


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--seeds", type=int, default=10, help="independent runs of the protocol")
    ap.add_argument("--long", type=int, default=40, help="further blocks of events on the first seed")
    ap.add_argument(
        "--block",
        type=int,
        default=500_000,
        help="events (pairs + kicks), about, a block of the continued run",
    )
    args = ap.parse_args()
    cpu = time.process_time()
    print(
        f"N = 1372 (FCC 7x7x7), rho = {RHO}, lambda = {LAM}, eps = {EPS}, Andersen kT = 1,"
        " kicks = 5 % of events"
    )
    print("DynamO's protocol: 3e5 events (pairs + kicks) of equilibration, then 1e5 measured")
    print("seed  duration   pairs    kicks   MFT = tN/(2 pairs + kicks)   kT (end)  U/N (end)")
    rows = []
    for seed in range(1, args.seeds + 1):
        r = protocol(seed)
        rows.append(r)
        print(
            f"{seed:4d}  {r['t']:8.4f}  {r['pairs']:7d}  {r['kicks']:6d}   {r['mft']:.6f}"
            f"                 {r['kT']:.4f}  {r['u']:+.4f}",
            flush=True,
        )
    mft = np.array([r["mft"] for r in rows])
    mean = mft.mean()
    err = mft.std(ddof=1) / math.sqrt(len(mft)) if len(mft) > 1 else math.nan
    print(
        f"mean over {len(mft)} seeds: MFT = {mean:.5f} +- {err:.5f}"
        f" (standard error; spread {mft.std(ddof=1):.5f})"
    )
    print(f"DynamO's value 0.0368185: ratio {mean / DYNAMO_MFT:.4f} ({(mean / DYNAMO_MFT - 1) * 100:+.2f} %)")
    if args.long:
        sim, thermo = rows[0]["sim"], rows[0]["thermo"]
        dur = args.block * (1.0 - KICKS) / float(np.mean([r["pairs"] / r["t"] for r in rows]))  # [time]
        print(f"\nseed 1 continued: blocks of {dur:.1f} time units (about {args.block:.0e} events each)")
        print("events     time      MFT       U/N (time avg)  Z              <kT>")
        done = 400_000
        for _ in range(args.long):
            k0 = thermo.resampled
            w = window(sim, dur, 10, 50, 1.0)
            pairs, kicks = int(w["pairs"].sum()), thermo.resampled - k0
            done += pairs + kicks
            t = float(w["t"].sum())
            thermo.rate = KICKS / (1.0 - KICKS) * pairs / (sim.n * t)
            z = w["Z"].mean()
            z_err = w["Z"].std(ddof=1) / math.sqrt(len(w["Z"]))
            print(
                f"{done:9d}  {sim.time:8.2f}  {t * sim.n / (2 * pairs + kicks):.6f}  {w['U'].mean():+.4f}"
                f"          {z:+.4f}({z_err * 1e4:.0f})   {w['kT'].mean():.4f}",
                flush=True,
            )
    print(f"CPU time {time.process_time() - cpu:.0f} s")


if __name__ == "__main__":
    main()

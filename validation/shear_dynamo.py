"""DynamO's sheared granular test on the compiled core: the mean free time of a sheared inelastic gas.

DynamO's ``src/dynamo/tests/shearing_test.cpp`` (github.com/dynamomd/DynamO):
N = 1372 equal spheres on an FCC lattice (7 x 7 x 7 cells) at number
density 0.5 (packing pi/12 = 0.2618), restitution 0.9, Lees-Edwards
boundaries at DynamO's default rate (``BCLeesEdwards``' constructor: 1 per
unit time), velocities rescaled to kT = 1 and total momentum zero; 500000
events to the steady state, then 1000000, and the mean free time
``t N / (2 collisions)`` must be 0.113195634 within 1%.  DynamO's primary
cell is 1 x 1 x 1 with the diameter as its unit of length, so in units of
the diameter, the mass and the starting kT its rate is g = 1 and its
mean free time is read as is (the steady state forgets the starting kT:
the shear's work balances the dissipation).

Here: the same system (``hs.crystal("fcc", (7, 7, 7), pi/12)``, kT = 1,
total momentum zero), ``restitution=0.9``, a box sheared at g = 1, no
thermostat; 500000 collisions to the steady state, then 1000000
collisions, as DynamO's: its ``endEventCount`` counts ``Sim->eventCount``,
which only the interactions' ``runEvent`` (here ``IHardSphere``'s, one per
collision) increments; its neighbour list's cell crossings are virtual
events, neither counted there nor in ``OPMisc``'s mean free time
``t N / (2 N_pairs + N_single)`` (``N_single`` counts non-virtual events of
one sphere: none here).  Seeds of the starting velocities 1, 2, 3 (DynamO's
are drawn afresh each run).  Also printed: the peculiar kT at the end and
the viscosity ``-P_xy / g`` with its blocking error; with two seeds or
more, the mean over the runs and its standard error against DynamO's value.

usage:
    python3 validation/shear_dynamo.py              # about 40 s once the core is compiled
    python3 validation/shear_dynamo.py --seeds 1    # one run

Units: sigma = m = 1, kT = 1 at the start (rates in 1/time).
"""

import argparse
import math
import statistics
import time

import hardspheres as hs

#: DynamO's expected mean free time, and its tolerance (BOOST_CHECK_CLOSE, 1%).
DYNAMO_MFT = 0.113195634
TOLERANCE = 0.01


def run(seed: int) -> tuple[float, float, float, float, bool]:
    """``(mean free time, kT now, eta, its error, converged)`` of one run from the velocities' ``seed``."""
    state, box = hs.crystal("fcc", (7, 7, 7), math.pi / 12.0, seed=seed)
    assert state.n == 1372
    sim = hs.Simulation(state, box.sheared_by(1.0), restitution=0.9)
    sim.run(collisions=500_000)
    sim.observables.reset()
    t0, c0 = sim.time, sim.counters["collisions"]
    sim.run(collisions=1_000_000)
    span, collisions = sim.time - t0, sim.counters["collisions"] - c0
    eta = sim.observables.estimate("viscosity")
    return span * sim.n / (2.0 * collisions), sim.observables.temperature(), eta.mean, eta.sem, eta.converged


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--seeds", type=int, default=3, help="runs, seeds 1..SEEDS (default 3)")
    args = p.parse_args()
    print(f"DynamO's mean free time {DYNAMO_MFT} (within {TOLERANCE:.0%})")
    print("seed | mean free time | against DynamO | kT at the end | eta = -P_xy/g | wall [s]")
    mfts, kts = [], []
    for seed in range(1, args.seeds + 1):
        t0 = time.perf_counter()
        mft, kT, eta, err, converged = run(seed)
        mfts.append(mft)
        kts.append(kT)
        ok = "within" if abs(mft / DYNAMO_MFT - 1.0) <= TOLERANCE else "OUTSIDE"
        print(
            f"{seed} | {mft:.6f} | {100.0 * (mft / DYNAMO_MFT - 1.0):+.2f}% ({ok}) | {kT:.4f} | "
            f"{eta:.4f} +- {err:.4f}{'' if converged else ' (not converged)'} | "
            f"{time.perf_counter() - t0:.1f}",
            flush=True,
        )
    if len(mfts) >= 2:
        m, sd = statistics.fmean(mfts), statistics.stdev(mfts)
        se = sd / math.sqrt(len(mfts))
        print(
            f"mean over {len(mfts)} runs: {m:.6f} +- {se:.6f} (one run's spread {sd:.6f}): "
            f"{100.0 * (m / DYNAMO_MFT - 1.0):+.2f}% from DynamO's, {(m - DYNAMO_MFT) / se:+.1f} standard "
            f"errors of the mean, {(m - DYNAMO_MFT) / sd:+.1f} of one run's spread; "
            f"kT at the end {statistics.fmean(kts):.4f} +- {statistics.stdev(kts) / math.sqrt(len(kts)):.4f}"
        )


if __name__ == "__main__":
    main()

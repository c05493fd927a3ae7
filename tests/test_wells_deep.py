"""A deep square well (eps = 5 kT) on the compiled event core: energy to rounding, no bounce loop.

The small-scale twin of ``validation/square_well_deep.py`` (10^7 events,
docs/validation/square-well.md, section 5): 256 spheres at packing 0.2, a well
of width 1.5 and depth 5, brought to kT = 1 by an Andersen thermostat (the
fluid condenses), then 10^5 events at constant energy, the well still deep.
A bounce inside a deep well is the event most likely to loop (a bound pair
reflected at the edge it cannot climb); a loop would stop the clock, so the
events must keep to their count with every pair's events apart in time.
"""

import math

import numpy as np

import hardspheres as hs
from hardspheres.dense import Andersen

EPS, LAM = 5.0, 1.5


def _distances_match_states(sim: hs.Simulation) -> bool:
    """Each pair within ``LAM`` is bonded and every other is not; no cores overlap."""
    pos = np.asarray(sim.state().positions)
    side = np.asarray(sim.container.sides)
    inside = set()
    for i in range(len(pos) - 1):
        d = pos[i + 1 :] - pos[i]
        d -= side * np.round(d / side)
        r = np.sqrt(np.sum(d * d, axis=1))
        if r.min() <= 1.0 - 1e-9:
            return False
        inside |= {(i, int(j)) for j in np.nonzero(r < LAM)[0] + i + 1}
    return inside == set(sim.engine.pair_states)


def test_a_deep_well_conserves_energy_over_1e5_events_without_a_bounce_loop():
    """K + U constant to 1e-12 of K + |U|; 10^5 events, each pair's events apart in time; bonds as distances."""
    box = hs.PeriodicBox.for_packing(256, 0.2)
    sim = hs.Simulation(hs.random_spheres(256, 0.2, box, seed=3), box, steps=[(LAM, -EPS)])
    sim.set_thermostat(Andersen(kT=1.0, rate=2.0, seed=3)).run(events=100_000)
    sim.set_thermostat(None)
    e0, c0 = sim.total_energy(), sim.engine.counters
    ev = sim.engine.advance(events=100_000)
    assert len(ev) == 100_000 and np.all(np.diff(ev["time"]) >= 0.0) and ev["time"][-1] > ev["time"][0]
    c = {k: v - c0[k] for k, v in sim.engine.counters.items()}
    assert c["collisions"] + c["captures"] + c["releases"] + c["bounces"] == 100_000
    assert min(c["captures"], c["releases"]) > 500 and min(c["bounces"], c["collisions"]) > 20_000
    kin, pot = sim.engine.kinetic_energy(), sim.potential_energy()
    assert pot == -EPS * len(sim.engine.pair_states) and len(sim.engine.pair_states) > 256  # the well binds
    assert (
        EPS / (2.0 * kin / (3.0 * 256)) > 3.5
    )  # still deep (the bonds formed since heat the fluid a little)
    assert abs(kin + pot - e0) <= 1e-12 * (kin + abs(pot))
    # no loop: consecutive events of one pair are apart in time
    pairs = ev[ev["j"] >= 0]
    key = pairs["i"] * 256 + pairs["j"]
    order = np.argsort(key, kind="stable")
    same = key[order][1:] == key[order][:-1]
    assert np.all(np.diff(pairs["time"][order])[same] > 0.0)
    assert _distances_match_states(sim)
    assert math.isfinite(sim.time)

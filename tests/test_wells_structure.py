"""g(r) of a square-well fluid jumps at the well's edge by the Boltzmann factor.

The cavity function ``y(r) = g(r) exp(u(r) / kT)`` is continuous where the
potential steps (the contact theorem at a step), so
``g(lambda sigma-) / g(lambda sigma+) = exp(eps / kT)``.  Measured with
bins that end on the step (``dr = sigma / 20``, so ``lambda sigma = 1.5
sigma`` is an edge), each side's value extrapolated to the edge by a line
through its four nearest bins, and the ratio's error from its scatter over
16 blocks of frames; ``kT`` is the run's mean (the observables' kinetic
integral, over the same span).
"""

import numpy as np
import pytest

import hardspheres as hs

LAM, EPS = 1.5, 0.5  # supercritical: kT / eps about 1.8 here, the critical point near 1.2


def side_values(rdf, edge: float) -> tuple[float, float]:
    """g at the edge from inside and from outside: lines through the 4 bins on each side."""
    i = int(np.argmin(np.abs(rdf.edges - edge)))
    assert abs(rdf.edges[i] - edge) < 1e-5 * edge  # (freud's edges are single precision)
    inside, outside = slice(i - 4, i), slice(i, i + 4)
    g_in = np.polyfit(rdf.r[inside] - edge, rdf.g[inside], 1)[-1]
    g_out = np.polyfit(rdf.r[outside] - edge, rdf.g[outside], 1)[-1]
    return float(g_in), float(g_out)


def test_g_jumps_by_the_boltzmann_factor_at_the_well_edge():
    pytest.importorskip("freud")
    from hardspheres.analysis.structure import RDF

    box = hs.PeriodicBox(10.0)
    state = hs.random_spheres(256, 0.2, container=box, seed=5)
    sigma = 2.0 * float(state.radii[0])
    sim = hs.Simulation(state, box, steps=[(LAM, -EPS)])
    sim.run(until=30.0)  # about 120 collisions per sphere
    sim.observables.reset()
    frames = []
    for k in range(1200):  # a frame about every mean free time
        sim.run(until=30.0 + 0.25 * (k + 1))
        frames.append(sim.state().positions.copy())
    kT = sim.observables.mean_temperature()
    assert abs(sim.observables.energy_drift()) < 1e-12
    ratios = []
    for block in np.array_split(np.array(frames), 16):
        rdf = RDF(dr=sigma / 20, r_max=2.5 * sigma).compute(block, box=10.0, sigma=sigma)
        g_in, g_out = side_values(rdf, LAM * sigma)
        ratios.append(g_in / g_out)
    ratio, err = float(np.mean(ratios)), float(np.std(ratios, ddof=1) / np.sqrt(len(ratios)))
    expected = float(np.exp(EPS / kT))
    assert err < 0.03  # (so no jump, a ratio of 1, would be at least 24 errors away)
    assert abs(ratio - expected) < 4.0 * err, (ratio, err, expected)

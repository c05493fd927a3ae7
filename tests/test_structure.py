"""Structure: g(r), contact value against the virial, S(k), bond order (freud)."""

import math

import numpy as np
import pytest
from helpers import periodic_gas

import hardspheres as hs
from hardspheres.analysis.structure import RDF, BondOrder, NotComputedError, StructureFactor
from hardspheres.containers import PeriodicBoxRequired
from hardspheres.errors import AnalysisInputError
from hardspheres.io.trajectory import frames_from_simulation

pytest.importorskip("freud")


def test_ideal_gas_is_one():
    rng = np.random.default_rng(0)
    L = 10.0
    pos = rng.uniform(-L / 2, L / 2, size=(20, 1000, 3))
    rdf = RDF(r_max=4.0).compute(pos, box=L, sigma=1.0)
    assert rdf.frames == 20
    # 20 frames x 1000 points: ~3% noise per bin beyond r = 1
    sel = rdf.r > 1.0
    assert np.mean(rdf.g[sel]) == pytest.approx(1.0, abs=0.01)
    assert np.max(np.abs(rdf.g[sel] - 1.0)) < 0.2
    sk = StructureFactor(bins=20, k_max=10.0, k_min=2.0).compute(pos[:2], box=L)
    assert np.nanmean(sk.S) == pytest.approx(1.0, abs=0.1)


@pytest.fixture(scope="module")
def fluid():
    n, phi = 500, 0.3
    sim = periodic_gas(n, phi, seed=4)
    sim.run(collisions=20 * n)  # melt the lattice
    obs = sim.observables.reset()
    frames = frames_from_simulation(sim, until=sim.time + 8.0, every=0.1)
    return frames, obs.estimate("compressibility"), phi


def test_contact_value_matches_the_virial(fluid):
    frames, z, phi = fluid
    rdf = RDF().compute(frames)
    assert rdf.packing == pytest.approx(phi)
    g_sigma, err = rdf.contact_value()
    z_gr, z_gr_err = rdf.compressibility()
    # exact for hard spheres: Z = 1 + 4 phi g(sigma+) (the virial route)
    assert abs(z_gr - z.mean) < 3 * math.hypot(z_gr_err, z.sem) + 0.01 * z.mean
    assert 0 < err < 0.03 * g_sigma
    # no pair closer than contact (freud computes in single precision: pairs
    # touching at a frame's time may land in the bin just below sigma)
    dr = rdf.edges[1] - rdf.edges[0]
    assert np.all(rdf.g[rdf.r < rdf.sigma - dr] == 0.0)
    assert np.all(rdf.g[rdf.r < rdf.sigma] < 1e-3 * g_sigma)
    ax = rdf.plot()
    assert ax.get_xlabel() == "r / sigma"


def test_fluid_is_not_crystal_and_fcc_is(fluid):
    frames, _, _ = fluid
    bo = BondOrder().compute(frames.positions[::20], box=frames.box, sigma=1.0)
    assert bo.crystal_fraction < 0.05
    assert bo.mean_q < 0.45
    # a perfect FCC lattice: q6 = 0.5745 for 12 neighbours at one distance
    fcc = hs.random_spheres(256, 0.5, box=9.5, seed=1)
    bo = BondOrder().compute(fcc, box=9.5)
    assert bo.mean_q == pytest.approx(0.57452, abs=1e-4)
    assert bo.crystal_fraction == 1.0


def test_bond_order_of_bare_positions_needs_sigma_r_max_or_neighbours():
    """Bare positions carry no radii: a one-line error saying what to pass (was a raw TypeError)."""
    fcc = hs.random_spheres(256, 0.5, box=9.5, seed=1)
    positions = fcc.positions
    with pytest.raises(
        AnalysisInputError, match=r"^BondOrder: bare positions have no radii: pass sigma="
    ) as err:
        BondOrder().compute(positions, box=9.5)
    assert isinstance(err.value, ValueError) and "\n" not in str(err.value)
    # each of the three ways out gives the state's answer (r_max 1.4 sigma, or the 12 nearest)
    sigma = 2.0 * float(fcc.radii.max())
    want = BondOrder().compute(fcc, box=9.5).mean_q
    assert BondOrder().compute(positions, box=9.5, sigma=sigma).mean_q == want
    assert BondOrder(r_max=1.4 * sigma).compute(positions, box=9.5).mean_q == want
    assert BondOrder(num_neighbors=12).compute(positions, box=9.5).mean_q == pytest.approx(want, abs=1e-9)


def test_structure_factor_of_the_fluid(fluid):
    frames, _, _ = fluid
    sk = StructureFactor(bins=40, k_max=15.0).compute(frames.positions[::20], box=frames.box)
    # the main peak of the hard-sphere fluid near k sigma ~ 7 at packing 0.3,
    # and S(k) well below 1 at low k (compressibility ~0.1 by Carnahan-Starling)
    peak = sk.k[np.nanargmax(sk.S)]
    assert 5.5 < peak < 8.0
    assert np.nanmin(sk.S[sk.k < 3.0]) < 0.3


def test_bad_input():
    with pytest.raises(NotComputedError, match="compute"):
        RDF().g  # noqa: B018 - attribute only exists after compute
    sim = hs.Simulation.from_arrays([1.0], [0.5], [[0, 0, 0]], [[1, 0, 0]], hs.SphericalContainer(5.0))
    with pytest.raises(PeriodicBoxRequired):
        RDF().compute(sim)

"""Transport: MSD and VACF over all time origins, D, Yeh-Hummer, bad input."""

import math

import numpy as np
import pytest
from helpers import periodic_gas

import hardspheres as hs
from hardspheres.analysis.structure import NotComputedError
from hardspheres.analysis.transport import MSD, VACF, enskog, yeh_hummer
from hardspheres.containers import PeriodicBoxRequired
from hardspheres.io.trajectory import frames_from_simulation

pytest.importorskip("freud")


def test_free_gas_is_ballistic_exactly():
    """Spheres that never meet: MSD = <v^2> t^2 and C(t) = <v^2>, across many box crossings."""
    box, n = 10.0, 50
    rng = np.random.default_rng(1)
    st = hs.State.from_arrays(
        np.ones(n), np.full(n, 1e-4), rng.uniform(-5, 5, (n, 3)), rng.normal(size=(n, 3))
    )
    sim = hs.Simulation(st, hs.PeriodicBox(box))
    fr = frames_from_simulation(sim, until=20.0, every=0.25)
    assert sim.counters["collisions"] == 0
    assert np.abs(fr.images[-1]).max() >= 3  # crossed the box several times
    v2 = np.mean(np.sum(st.velocities**2, axis=1))
    msd = MSD().compute(fr)
    # freud works in single precision: ~1e-7 of the squared unwrapped positions
    scale = np.max(fr.unwrapped() ** 2)
    np.testing.assert_allclose(msd.msd, v2 * msd.t**2, rtol=1e-5, atol=1e-6 * scale)
    vacf = VACF().compute(fr)
    np.testing.assert_allclose(vacf.c, v2, rtol=1e-12)


@pytest.fixture(scope="module")
def fluid():
    n, phi = 256, 0.3
    sim = periodic_gas(n, phi, seed=7)
    sim.run(collisions=20 * n)
    # frames a fifth of a mean free time apart (the VACF integral needs them close)
    return frames_from_simulation(sim, until=sim.time + 60.0, every=0.02), phi, sim.container.length


def test_diffusion_two_routes_agree(fluid):
    fr, phi, _ = fluid
    D_msd, e_msd = MSD().compute(fr).diffusion()
    D_vacf, e_vacf = VACF().compute(fr).diffusion()
    assert 0 < e_msd < 0.1 * D_msd and 0 < e_vacf < 0.1 * D_vacf
    assert abs(D_msd - D_vacf) < 3 * math.hypot(e_msd, e_vacf)
    # Enskog is within ~25% of the true D at this density (D/D_E ~ 1.1-1.2)
    ratio = D_msd / enskog(phi)["D"]
    assert 0.95 < ratio < 1.4


def test_vacf_cut_is_where_the_running_integral_is_read(fluid):
    """diffusion(t_max) is the running integral at t_max; the default cut is half a segment."""
    fr, _, _ = fluid
    v = VACF(blocks=5).compute(fr)
    t, d = v.running_diffusion()
    for cut in (1.0, 5.0, 10.0):
        k = int(np.searchsorted(t, cut, side="right")) - 1
        assert v.diffusion(t_max=cut)[0] == pytest.approx(d[k], rel=1e-12)
    half = t[len(t) // 5 - 1] / 2
    k = int(np.searchsorted(t, half, side="right")) - 1
    assert v.diffusion()[0] == pytest.approx(d[k], rel=1e-12)
    with pytest.raises(ValueError, match="longer than a segment"):
        v.diffusion(t_max=2 * half + 1.0)


def test_vacf_needs_no_image_counts(fluid):
    """Only velocities enter the VACF: frames without images (old files) work."""
    fr, _, _ = fluid
    bare = fr.replace(images=None)
    np.testing.assert_array_equal(VACF().compute(bare).c, VACF().compute(fr).c)


def test_vacf_refuses_coarse_frames(fluid):
    fr, _, _ = fluid
    coarse = fr.replace(
        times=fr.times[::5], positions=fr.positions[::5], velocities=fr.velocities[::5], images=fr.images[::5]
    )
    with pytest.raises(ValueError, match="frames"):
        VACF().compute(coarse).diffusion()


def test_yeh_hummer_adds_the_hydrodynamic_term():
    assert yeh_hummer(0.2, 8.0, 0.5, kT=2.0) == pytest.approx(
        0.2 + 2.837297 * 2.0 / (6 * math.pi * 0.5 * 8.0)
    )


def test_bad_input(tmp_path):
    with pytest.raises(NotComputedError):
        MSD().diffusion()
    sim = hs.Simulation.from_arrays(
        [1.0, 1.0], [0.5, 0.5], [[0, 0, 0], [2, 0, 0]], [[1, 0, 0], [0, 1, 0]], hs.SphericalContainer(5.0)
    )
    fr = frames_from_simulation(sim, until=2.0, every=0.5)
    with pytest.raises(PeriodicBoxRequired, match="periodic box"):
        MSD().compute(fr)
    with pytest.raises(PeriodicBoxRequired):
        VACF().compute(fr)

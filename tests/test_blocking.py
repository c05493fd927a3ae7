"""Error bars: Flyvbjerg-Petersen blocking and the observables' sampled blocks."""

import math

import numpy as np
import pytest
from helpers import periodic_gas
from scipy.signal import lfilter

import hardspheres as hs
from hardspheres.blocking import blocking
from hardspheres.observables import NoMeasurementError


def ar1(phi, n, seed):
    """AR(1) series x_t = phi x_{t-1} + e_t (unit noise), in its stationary state."""
    e = np.random.default_rng(seed).normal(size=n + 2000)
    return lfilter([1.0], [1.0, -phi], e)[2000:]


def ar1_sem(phi, n):
    """Exact large-n standard error of the mean of an AR(1) series."""
    return math.sqrt(1.0 / (1.0 - phi**2) / n * (1.0 + phi) / (1.0 - phi))


def test_white_noise_is_std_over_sqrt_n():
    x = np.random.default_rng(3).normal(size=1 << 14)
    b = blocking(x)
    assert b.converged
    assert b.sem == pytest.approx(np.std(x) / math.sqrt(x.size - 1), rel=0.05)
    assert b.mean == pytest.approx(np.mean(x))


@pytest.mark.parametrize("phi", [0.5, 0.9])
def test_correlated_series_matches_the_exact_error(phi):
    n = 1 << 15
    ratios = [blocking(ar1(phi, n, seed)).sem / ar1_sem(phi, n) for seed in range(8)]
    # the naive error is sqrt((1 - phi) / (1 + phi)) of the truth: 0.58, 0.23
    assert np.mean(ratios) == pytest.approx(1.0, abs=0.1)


def test_no_plateau_is_reported():
    # a random walk has no finite correlation time
    x = np.cumsum(np.random.default_rng(4).normal(size=1 << 12))
    assert not blocking(x).converged


def test_too_few_samples():
    with pytest.raises(ValueError, match="at least two"):
        blocking([1.0])


def gas(n=200, phi=0.3, seed=2):
    return periodic_gas(n, phi, seed)


def test_summary_has_error_bars():
    sim = gas()
    sim.run(collisions=5000)
    obs = sim.observables.reset()
    sim.run(collisions=40000)
    s = obs.summary()
    assert s["blocks"] >= 32  # blocks of 500 to 1000 events (MIN_EVENTS)
    for name in ("pressure", "compressibility", "collision_rate", "mean_free_path"):
        assert 0.0 < s[f"{name}_error"] < 0.05 * s[name]
    # Carnahan-Starling at packing 0.3 (small N: within 5 error bars + 1%)
    zcs = (1 + 0.3 + 0.09 - 0.027) / 0.7**3
    assert abs(s["compressibility"] - zcs) < 5 * s["compressibility_error"] + 0.01 * zcs
    x = obs.blocks("compressibility")
    assert x.shape == (s["blocks"],)
    # sampling costs about a hundred events: the automatic grid keeps blocks long enough
    events = np.diff(np.array(obs._samples)[:, 1:3].sum(axis=1))
    assert events.min() >= obs.MIN_EVENTS / 2


def test_blocks_merge_to_the_coarser_grid_exactly():
    """Merging blocks gives what sampling at the doubled interval from the start gives."""
    a, b = gas(n=64, seed=5), gas(n=64, seed=5)
    a.observables.MAX_SAMPLES = 8
    oa = a.observables.reset(every=0.05)
    ob = b.observables.reset(every=0.05 * 16)
    a.run(until=5.0)
    b.run(until=5.0)
    assert oa.every == ob.every and oa.n_blocks <= 8
    sa, sb = np.array(oa._samples), np.array(ob._samples)
    n = min(len(sa), len(sb))
    np.testing.assert_allclose(sa[:n], sb[:n], rtol=1e-12)
    assert len(sa) == len(sb) == 7  # t = 0, 0.8, ..., 4.8


def test_results_before_measuring_raise():
    sim = gas(n=32)
    with pytest.raises(NoMeasurementError, match="run first"):
        sim.observables.compressibility()
    assert "pressure" not in sim.observables.summary()


def test_spherical_container_pressure_error_and_checkpoint(tmp_path):
    sim = hs.Simulation(hs.random_spheres(50, 0.1, container=10.0, seed=1), hs.SphericalContainer(10.0))
    obs = sim.observables.reset()
    sim.run(collisions=2000)
    assert obs.error("pressure") > 0
    sim.save(tmp_path / "c.npz")
    back = hs.Simulation.load(tmp_path / "c.npz")
    assert back.observables.n_blocks == obs.n_blocks
    sim.run(collisions=500)
    back.run(collisions=500)
    assert back.observables.error("pressure") == obs.error("pressure")


def test_unknown_average_is_named():
    sim = gas(n=32)
    sim.run(collisions=200)
    with pytest.raises(ValueError, match="choose one of pressure"):
        sim.observables.estimate("pressure_xy_typo")


def test_z_is_the_name_and_compressibility_its_alias(make_sim):
    """Issue 29 item 4: obs.estimate("Z") raised while the study files use "Z";
    in a sphere the summary did not say that its Z is the wall's PV/NkT."""
    import hardspheres as hs

    box = hs.PeriodicBox.for_packing(108, 0.2)
    sim = hs.Simulation(hs.random_spheres(108, 0.2, box, seed=2), box)
    obs = sim.run(collisions=2000).observables.reset()
    sim.run(collisions=8000)
    z = obs.estimate("Z")
    assert z.mean == obs.Z() == obs.compressibility() == obs.estimate("compressibility").mean
    assert np.array_equal(obs.blocks("Z"), obs.blocks("compressibility"))
    s = obs.summary()
    assert s["Z"] == s["compressibility"] == z.mean and s["Z_route"] == "virial" and "Z_note" not in s
    with pytest.raises(ValueError, match="choose one of pressure, Z"):
        obs.estimate("kappa")
    s = make_sim(n=30, packing=0.2).run(collisions=500).observables.summary()
    assert s["Z_route"] == "wall" and "surface term" in s["Z_note"]

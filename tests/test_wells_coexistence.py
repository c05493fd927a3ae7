"""A liquid slab beside its vapour: the builder, the profile, the plateaus and the critical fit."""

import math

import numpy as np
import pytest

import hardspheres as hs
from hardspheres.analysis.coexistence import (
    MIN_FRAMES,
    CoexistenceDensities,
    VapourLiquidProfile,
    critical_point,
    slab_centre,
    vapour_liquid_slab,
)
from hardspheres.core.contacts import closest_ratio
from hardspheres.dense import Andersen
from hardspheres.errors import AnalysisInputError, BuildError, NotComputedError


def synthetic(frames=256, liquid=0.65, vapour=0.03, z0=12.0, width=1.2, noise=0.01, seed=1, bins=64):
    """Profiles ``(z, (frames, bins))`` of a tanh interface with white noise."""
    z = (np.arange(bins) + 0.5) * 32.0 / bins
    rho = 0.5 * (liquid + vapour) - 0.5 * (liquid - vapour) * np.tanh((z - z0) / width)
    return z, rho + np.random.default_rng(seed).normal(0.0, noise, (frames, bins))


def test_the_slab_is_a_liquid_block_in_the_middle_of_an_empty_box():
    st, box = vapour_liquid_slab(300, 6.0, 30.0, density=0.7, kT=1.1, seed=2)
    h = 300 / (0.7 * 36.0)
    assert st.n == 300 and box.sides == (6.0, 6.0, 30.0)
    assert np.all(np.abs(st.positions[:, 2]) <= 0.5 * h + 1e-9)  # the block, centred on z = 0
    assert closest_ratio(st.positions, st.radii, np.array(box.sides)) >= 1.0 - 1e-12  # no overlap
    v = st.velocities
    assert np.allclose(v.sum(axis=0), 0.0, atol=1e-9)
    assert np.sum(v * v) / (3 * (st.n - 1)) == pytest.approx(1.1)  # kT exactly
    again, _ = vapour_liquid_slab(300, 6.0, 30.0, density=0.7, kT=1.1, seed=2)
    assert np.array_equal(st.positions, again.positions)  # deterministic


def test_bad_slabs_are_refused():
    for args, kwargs in (
        ((1, 6.0, 30.0), {}),
        ((300, 6.0, 12.0), {"density": 0.7}),  # the block (11.9) leaves no room for a vapour
        ((300, 6.0, 30.0), {"density": 1.2}),
        ((300, -6.0, 30.0), {}),
        ((300, 1.5, 300.0), {}),
    ):
        with pytest.raises(BuildError):
            vapour_liquid_slab(*args, **kwargs)


def test_the_slab_centre_is_found_across_the_periodic_boundary():
    z = np.array([9.0, 9.5, -9.5, -9.0, 9.25, -9.25])
    assert slab_centre(z, 20.0) == pytest.approx(-10.0)
    assert slab_centre(z + 3.0, 20.0) == pytest.approx(-7.0)


def test_a_profile_is_centred_on_the_slab_wherever_it_drifts():
    st, box = vapour_liquid_slab(200, 5.0, 24.0, density=0.7, seed=1)
    p0 = VapourLiquidProfile(bins=24).compute(st, box.sides)
    x = st.positions.copy()
    x[:, 2] = (x[:, 2] + 7.3 + 12.0) % 24.0 - 12.0  # the slab moved by 7.3, across the boundary
    p1 = VapourLiquidProfile(bins=24).compute(x, box.sides)
    assert np.allclose(p0.density, p1.density)
    assert p1.centres[0] == pytest.approx(p0.centres[0] + 7.3, abs=1e-9)
    assert np.sum(p0.density) * 2 * 25.0 * 0.5 == pytest.approx(200)  # every sphere counted
    p0.compute(x, box.sides, reset=False)
    assert p0.profiles.shape == (2, 24) and np.isnan(p0.times).all()


def test_profiles_of_a_run_accumulate_with_times():
    st, box = vapour_liquid_slab(200, 5.0, 24.0, density=0.7, seed=3)
    sim = hs.Simulation(st, box, steps=[(1.5, -1.0)])
    p = VapourLiquidProfile(bins=12)
    for k in range(3):
        sim.run(until=0.2 * (k + 1))
        p.compute(sim, reset=(k == 0))
    assert p.profiles.shape == (3, 12) and np.allclose(p.times, [0.2, 0.4, 0.6])
    with pytest.raises(AnalysisInputError, match="differs"):
        p.compute(st, (5.0, 5.0, 30.0), reset=False)


def test_bad_profiles_are_refused():
    with pytest.raises(AnalysisInputError):
        VapourLiquidProfile(bins=4)
    with pytest.raises(NotComputedError):
        VapourLiquidProfile().density
    disks = hs.PeriodicBox((10.0, 10.0))
    with pytest.raises(AnalysisInputError, match="3-D"):
        VapourLiquidProfile().compute(np.zeros((3, 2)), disks.sides)


def test_the_plateaus_of_a_known_profile():
    z, frames = synthetic()
    c = CoexistenceDensities().compute((z, frames))
    assert c.liquid == pytest.approx(0.65, abs=4 * c.liquid_error)
    assert c.vapour == pytest.approx(0.03, abs=4 * c.vapour_error)
    assert 5e-5 < c.liquid_error < 5e-4 and 5e-5 < c.vapour_error < 5e-4  # 0.01 / sqrt(bins x frames)
    assert c.interface == pytest.approx(12.0, abs=0.2) and c.width == pytest.approx(1.2, rel=0.2)
    assert c.liquid_bins[0] and not c.liquid_bins[len(z) // 2] and c.vapour_bins[-1]
    assert not (c.liquid_bins & c.vapour_bins).any()
    assert set(c.checks) == {f"{p}_{t}" for p in ("liquid", "vapour") for t in ("flat", "drift", "plateau")}


def test_too_few_frames_are_refused():
    z, frames = synthetic(frames=MIN_FRAMES - 1)
    with pytest.raises(AnalysisInputError, match="frames"):
        CoexistenceDensities().compute((z, frames))


def test_a_plateau_that_is_not_flat_is_refused():
    z, frames = synthetic(z0=14.0, width=2.5, noise=0.002)  # the tail reaches into the plateaus at margin 1
    with pytest.raises(AnalysisInputError, match="not flat"):
        CoexistenceDensities(margin=1.0).compute((z, frames))
    c = CoexistenceDensities(margin=4.0).compute((z, frames))  # wider margins: flat
    assert c.vapour == pytest.approx(0.03, abs=4 * c.vapour_error)


def test_a_drifting_run_is_refused():
    z, frames = synthetic(frames=512)
    frames[:, z > 14] += np.linspace(0.0, 0.01, 512)[:, None]  # the vapour fills as the run goes
    with pytest.raises(AnalysisInputError, match="drift"):
        CoexistenceDensities().compute((z, frames))


def test_no_interface_or_no_room_is_refused():
    z, frames = synthetic(liquid=0.3, vapour=0.3)
    with pytest.raises(AnalysisInputError, match="interface"):
        CoexistenceDensities().compute((z, frames))
    z, frames = synthetic(z0=28.0)  # the slab fills the box: no vapour plateau
    with pytest.raises(AnalysisInputError, match="vapour's plateau"):
        CoexistenceDensities().compute((z, frames))
    with pytest.raises(AnalysisInputError):
        CoexistenceDensities(margin=-1.0)


def test_a_slab_run_gives_a_profile_the_plateaus_read():
    st, box = vapour_liquid_slab(300, 6.0, 30.0, density=0.7, kT=1.0, seed=4)
    sim = hs.Simulation(st, box, steps=[(1.5, -1.0)])
    sim.set_thermostat(Andersen(kT=1.0, rate=0.5, seed=4))
    p = VapourLiquidProfile(bins=30)
    for k in range(1, 5):
        sim.run(until=0.5 * k)
        p.compute(sim, reset=(k == 1))
    assert p.density[0] > 0.5 and p.density[-1] < 0.1  # a slab and its (still thin) vapour
    with pytest.raises(AnalysisInputError, match="frames"):
        CoexistenceDensities().compute(p)


def test_the_critical_point_of_exact_densities():
    t = np.array([0.9, 0.95, 1.0, 1.05, 1.1])
    mid, half = 0.31 + 0.2 * (1.22 - t), 0.5 * 0.9 * (1.22 - t) ** 0.326
    err = np.full(5, 1e-3)
    cp = critical_point(t, mid + half, mid - half, err, err, samples=100, seed=2)
    assert cp.t_c == pytest.approx(1.22, abs=1e-4) and cp.rho_c == pytest.approx(0.31, abs=1e-4)
    assert cp.a == pytest.approx(0.2, abs=1e-3) and cp.b == pytest.approx(0.9, abs=1e-3)
    assert 0 < cp.t_c_error < 0.02 and 0 < cp.rho_c_error < 0.01 and cp.dof == 6
    assert cp.chi2 < 1e-6
    noisy = critical_point(t, mid + half + 0.002, mid - half, err, err, samples=100, seed=2)
    assert abs(noisy.t_c - 1.22) < 5 * noisy.t_c_error


def test_the_correction_to_scaling_recovers_a_corrected_law():
    """Densities with Wegner's term: the corrected fit finds T_c, the leading law alone puts it high."""
    t = np.array([0.9, 0.95, 1.0, 1.05, 1.1])
    dt = 1.22 - t
    mid, half = 0.31 + 0.2 * dt, 0.5 * 0.9 * dt**0.326 * (1.0 - 0.3 * dt**0.524)
    err = np.full(5, 1e-3)
    cp = critical_point(t, mid + half, mid - half, err, err, samples=50, seed=2, correction=0.524)
    assert cp.t_c == pytest.approx(1.22, abs=1e-4) and cp.rho_c == pytest.approx(0.31, abs=1e-4)
    assert cp.b1 == pytest.approx(-0.3, abs=1e-3) and cp.correction == 0.524 and cp.dof == 5
    plain = critical_point(t, mid + half, mid - half, err, err, samples=10, seed=2)
    assert plain.t_c > 1.23 and plain.b1 == 0.0 and plain.correction == 0.0
    with pytest.raises(AnalysisInputError, match="correction"):
        critical_point(t[:3], (mid + half)[:3], (mid - half)[:3], err[:3], err[:3], correction=0.524)
    with pytest.raises(AnalysisInputError, match="correction"):
        critical_point(t, mid + half, mid - half, err, err, correction=-1.0)


def test_bad_critical_fits_are_refused():
    t, r, e = np.array([1.0, 1.1]), np.array([0.6, 0.5]), np.full(2, 1e-3)
    with pytest.raises(AnalysisInputError, match="3 or more"):
        critical_point(t, r, r - 0.4, e, e)
    t3, r3, e3 = np.array([1.0, 1.05, 1.1]), np.array([0.6, 0.55, 0.5]), np.full(3, 1e-3)
    with pytest.raises(AnalysisInputError, match="exceed"):
        critical_point(t3, r3 - 0.6, r3, e3, e3)
    with pytest.raises(AnalysisInputError, match="errors"):
        critical_point(t3, r3, r3 - 0.4, 0 * e3, e3)
    assert math.isfinite(critical_point(t3, r3, r3 - 0.45, e3, e3, samples=10).t_c)


def slow(frames, tau, size, seed):
    """An AR(1) series of correlation time ``tau`` frames and standard deviation ``size``."""
    rng, a = np.random.default_rng(seed), math.exp(-1.0 / tau)
    x = np.empty(frames)
    x[0] = rng.normal()
    for k in range(1, frames):
        x[k] = a * x[k - 1] + math.sqrt(1 - a * a) * rng.normal()
    return size * x


def test_a_slow_plateau_in_a_short_run_is_refused_unless_asked():
    z, frames = synthetic(frames=512, seed=5)
    frames[:, z < 8] += slow(512, 40.0, 0.003, seed=6)[:, None]  # the liquid breathes slowly
    with pytest.raises(AnalysisInputError, match="no plateau"):
        CoexistenceDensities().compute((z, frames))
    c = CoexistenceDensities(min_blocks=6, strict=False).compute((z, frames))
    assert c.checks["vapour_plateau"] == 1.0 and c.checks["liquid_plateau"] in (0.0, 1.0)
    assert c.liquid == pytest.approx(0.65, abs=4 * c.liquid_error) and c.liquid_error > 3e-4
    with pytest.raises(AnalysisInputError, match="min_blocks"):
        CoexistenceDensities(min_blocks=2)

"""Dynamical correlators: exact limits (ballistic, diffusive), constructed trajectories, bad input."""

import math

import numpy as np
import pytest

import hardspheres as hs
from hardspheres.analysis.dynamics import (
    CollectiveIntermediate,
    NonGaussian,
    Overlap,
    SelfIntermediate,
    VanHove,
    lattice_vectors,
    log_lags,
)
from hardspheres.errors import NotComputedError, PeriodicBoxRequired
from hardspheres.io.trajectory import FrameRecorder, frames_from_simulation
from hardspheres.writers import LogOrigins

pytest.importorskip("scipy")


@pytest.fixture(scope="module")
def dilute():
    """A dilute gas (packing 1e-3) over 1/40 of its mean free time: free flight, few collisions."""
    n = 1000
    box = hs.PeriodicBox.for_packing(n, 1e-3).length
    sim = hs.Simulation(hs.random_spheres(n, 1e-3, box=box, seed=11), hs.PeriodicBox(box))
    v = sim.state().velocities.copy()
    fr = frames_from_simulation(sim, until=2.0, every=0.1)
    return fr, v, sim.counters["collisions"]


def test_free_flight_gives_the_exact_sample_average(dilute):
    """Before any collision dr_i = v_i t, so F_s = (1/N) sum sin(k v_i t)/(k v_i t) to rounding."""
    fr, v, collisions = dilute
    k = np.array([2 * np.pi, 5.0])
    fs = SelfIntermediate(k=k, lags=[0.1, 0.5, 1.0]).compute(fr)
    speed = np.linalg.norm(v, axis=1)
    if collisions == 0:
        for t, F in zip(fs.t, fs.F):
            exact = [np.mean(np.sinc(kk * speed * t / np.pi)) for kk in k]
            np.testing.assert_allclose(F, exact, rtol=0, atol=1e-12)
    assert collisions < 0.02 * fr.n  # what makes the next test's limit exact


def test_short_times_dilute_gaussian_limit(dilute):
    """F_s = exp(-k^2 kT t^2 / 2m) and alpha_2 = 0 within 4 sphere-sampling errors (Maxwell-Boltzmann)."""
    fr, v, _ = dilute
    kT = float(np.mean(fr.masses[:, None] * v**2))  # the temperature the gas was given
    fs = SelfIntermediate(k=[2 * np.pi, 10.0]).compute(fr)
    expected = np.exp(-np.outer(fs.t**2, fs.k**2) * kT / 2.0)
    assert np.all(np.abs(fs.F - expected) <= 4 * fs.particle_error + 1e-12)
    assert fs.F.min() < 0.2  # the test reached well into the decay
    ng = NonGaussian().compute(fr)
    assert np.all(np.abs(ng.alpha2) <= 4 * ng.alpha2_particle_error)
    np.testing.assert_allclose(ng.msd, 3 * kT * ng.t**2, rtol=8 * math.sqrt(2 / 3 / fr.n))


@pytest.fixture(scope="module")
def fluid():
    """A fluid at packing 0.2, 500 spheres, over about 300 mean free times."""
    n, phi = 500, 0.2
    box = hs.PeriodicBox.for_packing(n, phi).length
    sim = hs.Simulation(hs.random_spheres(n, phi, box=box, seed=5), hs.PeriodicBox(box))
    sim.run(collisions=5 * n)
    fr = frames_from_simulation(sim, until=sim.time + 60.0, every=0.25)
    return fr, box


def test_long_times_diffusive_limit(fluid):
    """At k = 2 pi / L, F_s ~ exp(-k^2 D t): -d ln F_s / dt = k^2 D at long times, D from the MSD of the same run."""
    fr, box = fluid
    msd = hs.MSD(blocks=4).compute(fr)
    D, D_err = msd.diffusion(t_min=5.0, t_max=15.0)
    k = 2 * np.pi / box
    fs = SelfIntermediate(k=k, lags=[6.0, 14.0], blocks=4).compute(fr)
    F, e = fs.F[:, 0], fs.error[:, 0]
    slope = -(math.log(F[1]) - math.log(F[0])) / (fs.t[1] - fs.t[0]) / k**2
    slope_err = math.hypot(e[0] / F[0], e[1] / F[1]) / (fs.t[1] - fs.t[0]) / k**2
    assert abs(slope - D) <= 4 * math.hypot(slope_err, D_err)
    assert 0.05 < F[-1] < 0.5  # well into the decay


def test_lattice_shell_agrees_with_the_isotropic_average(fluid):
    """F_s over the box's wave vectors in a shell equals the exact all-directions average, within error."""
    fr, box = fluid
    lags = [0.5, 2.0, 8.0]
    iso = SelfIntermediate(k=2 * np.pi, lags=lags).compute(fr)
    lat = SelfIntermediate(k=2 * np.pi, shell="lattice", max_vectors=200, lags=lags).compute(fr)
    bar = np.hypot(iso.particle_error, lat.particle_error)
    assert np.all(np.abs(iso.F - lat.F) <= 5 * bar)


def test_tau_alpha_is_where_fs_crosses_one_over_e(fluid):
    fr, _ = fluid
    fs = SelfIntermediate(k=2 * np.pi).compute(fr)
    tau, err = fs.tau_alpha()
    b = np.flatnonzero(fs.F[:, 0] <= math.exp(-1))[0]
    assert fs.t[b - 1] < tau <= fs.t[b] and err >= 0


def test_collective_at_lag_zero_is_the_structure_factor(fluid):
    """F(k, 0) = |rho_k|^2 / N averaged over frames and the shell's vectors."""
    fr, box = fluid
    ci = CollectiveIntermediate(k=2 * np.pi, lags=[1.0]).compute(fr)
    q = ci.vectors[0]
    pos = fr.positions
    rho = np.exp(1j * np.einsum("fnd,vd->fnv", pos, q)).sum(axis=1)
    np.testing.assert_allclose(ci.F[0, 0], np.mean(np.abs(rho) ** 2) / fr.n, rtol=1e-10)
    assert ci.normalized[0, 0] == 1.0


def _constructed(n=10, frames=5):
    """Unwrapped positions: sphere i moves by i * 0.1 per frame along x (box 100)."""
    t = np.arange(frames, dtype=float)
    x = np.zeros((frames, n, 3))
    x[:, :, 0] = np.outer(t, 0.1 * np.arange(n))
    return x, t


def test_overlap_and_chi4_on_a_constructed_trajectory():
    """Q counts spheres that moved less than a; chi_4 = N var Q over origins, exactly."""
    x, t = _constructed()
    ov = Overlap(a=0.25, lags=[1.0, 2.0]).compute(x, box=100.0, times=t)
    # lag 1: spheres 0, 1, 2 moved 0, 0.1, 0.2 < 0.25; lag 2: 0, 0.2
    np.testing.assert_allclose(ov.Q, [0.3, 0.2])
    np.testing.assert_allclose(ov.chi4, [0.0, 0.0], atol=1e-15)  # every origin the same
    assert ov.origins.tolist() == [4, 3]
    vh = VanHove(bins=20, r_max=2.0, lags=[1.0]).compute(x, box=100.0, times=t)
    assert math.isclose(float(np.sum(vh.P[0] * np.diff(vh.edges))), 1.0)


def test_chi4_is_n_times_the_variance_over_origins():
    """Origins that differ: at lag 1 half of them have all spheres still, half all moved."""
    n = 4
    t = np.arange(5.0)
    step = np.array([0.0, 1.0, 0.0, 1.0])  # frame-to-frame moves of every sphere
    x = np.zeros((5, n, 3))
    x[1:, :, 0] = np.cumsum(step)[:, None]
    ov = Overlap(a=0.5, lags=[1.0], blocks=1).compute(x, box=100.0, times=t)
    # per origin Q = 1, 0, 1, 0: mean 0.5, variance 0.25
    assert ov.Q[0] == 0.5 and ov.chi4[0] == n * 0.25


def test_log_origins_frames_give_every_lag_from_every_origin():
    """Frames on the multiple-origin log schedule: each lag is measured from each origin."""
    n, phi = 64, 0.1
    box = hs.PeriodicBox.for_packing(n, phi).length
    sim = hs.Simulation(hs.random_spheres(n, phi, box=box, seed=2), hs.PeriodicBox(box))
    rec = FrameRecorder(trigger=LogOrigins(first=0.01, every=1.0, per_decade=5, until=1.0))
    sim.writers.append(rec)
    sim.run(until=10.0)
    fr = rec.frames()
    assert len(fr.times) == 10 * 11 + 1  # 10 origins of 11 frames (the lag 1.0 is the next origin), and 10.0
    fs = SelfIntermediate(k=2 * np.pi, per_decade=5, origin_every=1.0).compute(fr)
    # the schedule's lags, each from all 10 origins; then longer ones between origins' frames
    np.testing.assert_allclose(fs.t[:11], 0.01 * 10 ** (np.arange(11) / 5))
    assert fs.origins[:11].tolist() == [10] * 11
    assert fs.t[-1] == pytest.approx(10.0) and fs.origins[-1] == 1


def test_log_lags_of_equally_spaced_frames():
    assert log_lags(np.linspace(0, 1, 11), per_decade=1).tolist() == pytest.approx([0.1, 1.0])


def test_lattice_vectors_are_in_the_shell_one_of_each_pair():
    q = lattice_vectors(2.0, [10.0, 10.0, 10.0])
    mag = np.linalg.norm(q, axis=1)
    assert np.all(np.abs(mag - 2.0) <= 0.5 * 2 * np.pi / 10 + 1e-12)
    assert not any(np.allclose(a, -b) for a in q for b in q)


# ---- bad input -------------------------------------------------------------------------
def test_k_below_the_box_wave_number_is_refused(fluid):
    fr, box = fluid
    with pytest.raises(ValueError, match=r"^k = 0\.1 is below 2 pi / L"):
        SelfIntermediate(k=0.1).compute(fr)
    with pytest.raises(ValueError, match="k = 0.1 is below"):
        CollectiveIntermediate(k=0.1).compute(fr)


def test_spherical_container_is_refused():
    sim = hs.Simulation(hs.random_spheres(20, 0.1, container=5.0, seed=1), hs.SphericalContainer(5.0))
    fr = frames_from_simulation(sim, until=1.0, every=0.5)
    for obj in (
        SelfIntermediate(k=10.0),
        Overlap(),
        NonGaussian(),
        VanHove(),
        CollectiveIntermediate(k=10.0),
    ):
        with pytest.raises(PeriodicBoxRequired, match="need a periodic box"):
            obj.compute(fr)


def test_too_few_frames_for_the_lag_is_refused(fluid):
    fr, _ = fluid
    with pytest.raises(ValueError, match=r"^lags: no pair of frames 100 apart"):
        Overlap(lags=[1.0, 100.0]).compute(fr)
    one = fr.replace(
        times=fr.times[:1], positions=fr.positions[:1], velocities=fr.velocities[:1], images=fr.images[:1]
    )
    with pytest.raises(ValueError, match="1 frame"):
        SelfIntermediate(k=2 * np.pi).compute(one)


def test_bad_parameters_are_refused_naming_them():
    with pytest.raises(ValueError, match="shell must be"):
        SelfIntermediate(k=1.0, shell="cube")
    with pytest.raises(ValueError, match="a must be"):
        Overlap(a=-1.0)
    with pytest.raises(ValueError, match="blocks must be"):
        Overlap(blocks=0)
    x, t = _constructed()
    with pytest.raises(ValueError, match="lags must be"):
        Overlap(lags=[-1.0]).compute(x, box=100.0, times=t)


def test_results_before_compute_raise():
    for obj in (SelfIntermediate(k=1.0), Overlap(), NonGaussian(), VanHove(), CollectiveIntermediate(k=1.0)):
        with pytest.raises(NotComputedError):
            obj.t  # noqa: B018
        with pytest.raises(NotComputedError):
            obj.plot()


def test_plots_return_axes(fluid):
    pytest.importorskip("matplotlib")
    import matplotlib

    matplotlib.use("Agg")
    fr, _ = fluid
    for obj in (
        SelfIntermediate(k=2 * np.pi),
        Overlap(),
        NonGaussian(),
        VanHove(),
        CollectiveIntermediate(k=2 * np.pi),
    ):
        ax = obj.compute(fr).plot()
        assert ax.get_xlabel()


def test_rectangular_box_and_a_gsd_path_read_a_frame_at_a_time(tmp_path):
    """PeriodicBox((Lx, Ly, Lz)): per-axis unwrapping; a .gsd path gives what its Frames give."""
    pytest.importorskip("gsd")
    box = hs.PeriodicBox((6.0, 7.0, 9.0))
    sim = hs.Simulation(hs.random_spheres(80, 0.2, box=(6.0, 7.0, 9.0), seed=3), box)
    path = tmp_path / "run.gsd"
    sim.writers.append(hs.GSDWriter(path, every=0.1))
    sim.run(until=3.0)
    sim.writers[-1].detach()
    fr = hs.read_trajectory(path)
    assert np.abs(fr.images).max() >= 1  # some crossed the box
    lengths = np.array([6.0, 7.0, 9.0])
    x = fr.positions + fr.images * lengths
    a = SelfIntermediate(k=2 * np.pi, lags=[0.5, 2.0]).compute(str(path))
    b = SelfIntermediate(k=2 * np.pi, lags=[0.5, 2.0]).compute(x, box=lengths, times=fr.times)
    c = SelfIntermediate(k=2 * np.pi, lags=[0.5, 2.0]).compute(fr)
    np.testing.assert_allclose(a.F, b.F, rtol=1e-12)
    np.testing.assert_allclose(c.F, b.F, rtol=1e-12)
    with pytest.raises(ValueError, match="below 2 pi / L"):
        SelfIntermediate(k=2 * np.pi / 10.0).compute(fr)  # below 2 pi / 9, the longest side
    SelfIntermediate(k=2 * np.pi / 8.0, lags=[0.5]).compute(fr)  # above it: allowed


# ---- two dimensions: disks in PeriodicBox((Lx, Ly)) ------------------------------------
@pytest.fixture(scope="module")
def dilute_disks():
    """A dilute disk gas (area fraction 1e-3) over a small part of its mean free time: no collision."""
    n = 1000
    side = math.sqrt(n * math.pi * 0.25 / 1e-3)
    box = hs.PeriodicBox((side, side))
    sim = hs.Simulation(hs.random_spheres(n, 1e-3, box, seed=11), box)
    v = sim.state().velocities.copy()
    fr = frames_from_simulation(sim, until=2.0, every=0.1)
    return fr, v, sim.counters["collisions"]


def test_disks_free_flight_gives_the_exact_sample_average(dilute_disks):
    """In 2-D the circle of directions averages exp(i k . dr) to J_0(k r): F_s = (1/N) sum J_0(k v_i t)."""
    from scipy.special import j0

    fr, v, collisions = dilute_disks
    assert collisions == 0 and fr.positions.shape[2] == 2
    k = np.array([2 * np.pi, 5.0])
    fs = SelfIntermediate(k=k, lags=[0.1, 0.5, 1.0]).compute(fr)
    speed = np.linalg.norm(v, axis=1)
    for t, F in zip(fs.t, fs.F):
        np.testing.assert_allclose(F, [np.mean(j0(kk * speed * t)) for kk in k], rtol=0, atol=1e-12)
    # the overlap counts the disks that flew less than a: Q = (1/N) #(|v_i| t < a), and with
    # every origin seeing the same flights, chi_4 = N var Q over origins is 0
    ov = Overlap(a=0.3, lags=[0.1, 0.5, 1.0], blocks=1).compute(fr)
    np.testing.assert_allclose(ov.Q, [np.mean(speed * t < 0.3) for t in ov.t], rtol=0, atol=1e-15)
    np.testing.assert_allclose(ov.chi4, 0.0, atol=1e-12)


def test_disks_short_times_dilute_gaussian_limit(dilute_disks):
    """2-D: F_s = exp(-k^2 kT t^2 / 2m), alpha_2 = <r^4> / (2 <r^2>^2) - 1 = 0, Q = 1 - exp(-a^2 m / (2 kT t^2))."""
    fr, v, _ = dilute_disks
    kT = float(np.mean(fr.masses[:, None] * v**2))  # the temperature the gas was given (2 N degrees)
    fs = SelfIntermediate(k=[2 * np.pi, 10.0]).compute(fr)
    expected = np.exp(-np.outer(fs.t**2, fs.k**2) * kT / 2.0)
    assert np.all(np.abs(fs.F - expected) <= 4 * fs.particle_error + 1e-12)
    assert fs.F.min() < 0.2  # the test reached well into the decay
    ng = NonGaussian().compute(fr)
    assert ng.dim == 2
    assert np.all(np.abs(ng.alpha2) <= 4 * ng.alpha2_particle_error)
    np.testing.assert_allclose(ng.msd, 2 * kT * ng.t**2, rtol=1e-12)  # <v^2> t^2, the same velocities
    a = 0.3
    ov = Overlap(a=a).compute(fr)
    q = 1.0 - np.exp(-(a**2) / (2.0 * kT * ov.t**2))  # the Rayleigh law of 2-D speeds
    assert np.all(np.abs(ov.Q - q) <= 4 * np.sqrt(q * (1 - q) / fr.n) + 1e-12)
    # the k-shells are circles: the box's wave vectors of |k| near 2 pi give the same F_s
    lags = [0.2, 0.5, 1.0]
    iso = SelfIntermediate(k=2 * np.pi, lags=lags).compute(fr)
    lat = SelfIntermediate(k=2 * np.pi, shell="lattice", max_vectors=200, lags=lags).compute(fr)
    assert np.all(np.abs(iso.F - lat.F) <= 5 * np.hypot(iso.particle_error, lat.particle_error))


@pytest.fixture(scope="module")
def disk_fluid():
    """A disk fluid at area fraction 0.3, 400 disks, over about 200 mean free times."""
    n, phi = 400, 0.3
    side = math.sqrt(n * math.pi * 0.25 / phi)
    box = hs.PeriodicBox((side, side))
    sim = hs.Simulation(hs.random_spheres(n, phi, box, seed=5), box)
    sim.run(collisions=5 * n)
    fr = frames_from_simulation(sim, until=sim.time + 60.0, every=0.25)
    return fr, side


def test_disks_long_times_diffusive_limit(disk_fluid):
    """2-D, k = 2 pi / L: -d ln F_s / dt = k^2 D at long times, D from the MSD of the same frames (MSD = 4 D t)."""
    fr, side = disk_fluid
    msd = hs.MSD(blocks=4).compute(fr)
    D, D_err = msd.diffusion(t_min=5.0, t_max=15.0)
    ng = NonGaussian(lags=[5.0, 15.0]).compute(fr)  # the same MSD, here per origin
    assert D == pytest.approx((ng.msd[1] - ng.msd[0]) / 10.0 / 4.0, rel=0.05)
    k = 2 * np.pi / side
    fs = SelfIntermediate(k=k, lags=[10.0, 40.0], blocks=4).compute(fr)
    F, e = fs.F[:, 0], fs.error[:, 0]
    slope = -(math.log(F[1]) - math.log(F[0])) / (fs.t[1] - fs.t[0]) / k**2
    slope_err = math.hypot(e[0] / F[0], e[1] / F[1]) / (fs.t[1] - fs.t[0]) / k**2
    assert abs(slope - D) <= 4 * math.hypot(slope_err, D_err)
    assert 0.05 < F[-1] < 0.5  # well into the decay


def test_disks_chi4_is_n_times_the_variance_of_q_over_origins(disk_fluid):
    """chi_4 of simulated disks against Q computed directly from the frames, origin by origin."""
    fr, side = disk_fluid
    lags = [0.5, 2.0, 8.0]
    ov = Overlap(a=0.3, lags=lags, blocks=1).compute(fr)
    x = fr.positions + fr.images * np.array([side, side])
    for lag, q, chi, count in zip(ov.t, ov.Q, ov.chi4, ov.origins):
        step = int(round(lag / 0.25))
        per = np.mean(np.sum((x[step:] - x[:-step]) ** 2, axis=2) < 0.09, axis=1)
        assert count == len(per)
        assert q == pytest.approx(per.mean(), rel=1e-12)
        assert chi == pytest.approx(fr.n * per.var(), rel=1e-9)
    assert np.all(ov.chi4 > 0)


def _fs_with(t, F, error):
    """A SelfIntermediate holding the given lags and F_s (one k), as if computed."""
    fs = SelfIntermediate(k=2 * np.pi)
    fs.t, fs.F, fs.error = (
        np.asarray(t, float),
        np.asarray(F, float)[:, None],
        np.asarray(error, float)[:, None],
    )
    fs._computed = True
    return fs


def test_tau_alpha_below_one_over_e_at_the_first_lag_is_refused():
    """README's first glass run: F_s = 0.13 at the first frame. t[0] is not tau_alpha."""
    from hardspheres.errors import AnalysisInputError

    fs = _fs_with([0.5, 1.0, 2.0], [0.13, 0.05, 0.01], [0.0, 0.0, 0.0])
    with pytest.raises(AnalysisInputError, match=r"first lag t = 0\.5.*shorter lags \(run --log-frames"):
        fs.tau_alpha()


def test_tau_alpha_between_the_last_two_lags_warns():
    from hardspheres.errors import ResolutionWarning

    fs = _fs_with([0.5, 1.0, 2.0], [0.9, 0.6, 0.3], [0.01, 0.01, 0.01])
    with pytest.warns(ResolutionWarning, match="last two lags"):
        tau, err = fs.tau_alpha()
    assert 1.0 < tau < 2.0 and err > 0


def test_tau_alpha_without_error_bars_has_a_nan_error_not_zero():
    """Lags from one origin have no error bar (NaN): the crossing's error is NaN, never 0."""
    fs = _fs_with([0.1, 0.2, 0.4, 0.8], [0.9, 0.5, 0.2, 0.1], [np.nan] * 4)
    tau, err = fs.tau_alpha()
    assert 0.2 < tau < 0.4 and math.isnan(err)


@pytest.mark.parametrize("where", ["first", "last"])
def test_chi4_largest_at_an_end_is_no_peak(where):
    from hardspheres.errors import AnalysisInputError

    ov = Overlap()
    ov.t = np.array([0.5, 1.0, 2.0, 4.0])
    ov.chi4 = np.array([0.155, 0.1, 0.05, 0.01]) if where == "first" else np.array([0.01, 0.05, 0.1, 0.2])
    ov._computed = True
    with pytest.raises(AnalysisInputError, match=f"largest at the {where} lag"):
        ov.peak()
    ov.chi4 = np.array([0.01, 0.2, 0.1, 0.05])
    t, c = ov.peak()
    assert 0.5 < t < 2.0 and c >= 0.2


def test_no_error_bar_is_printed_as_zero():
    from hardspheres.messages import plus_minus

    assert "+-" not in plus_minus(0.5, 0.0) and "+-" not in plus_minus(0.5, float("nan"))
    assert plus_minus(0.5, 0.01) == "0.5 +- 0.01"

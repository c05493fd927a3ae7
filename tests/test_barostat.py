"""The barostat: Monte Carlo volume moves between event-driven stretches (hardspheres.barostat)."""

import math

import numpy as np
import pytest

import hardspheres as hs
from hardspheres import eos
from hardspheres.barostat import Barostat, barostat_from_state
from hardspheres.blocking import blocking
from hardspheres.core.contacts import closest_ratio
from hardspheres.errors import BarostatError


def _two(gap=3.0, L=10.0, v=((0.3, 0.1, 0.0), (-0.3, -0.1, 0.0))):
    return hs.Simulation.from_arrays(
        masses=[1.0, 1.0],
        radii=[0.5, 0.5],
        positions=[[-0.5 * gap, 0.0, 0.0], [0.5 * gap, 0.0, 0.0]],
        velocities=v,
        container=hs.PeriodicBox(L),
    )


def test_one_move_of_two_spheres_follows_the_rule_exactly():
    # the first move replayed from the same generator: u, r, then the rule by hand
    seen = set()
    for seed in range(12):
        sim = _two()
        bar = Barostat(pressure=0.01, kT=1.0, every=0.5, step=0.4, seed=seed, approach=False)
        sim.set_barostat(bar)
        before = sim.state().positions
        sim.run(until=0.5)
        rng = np.random.Generator(np.random.PCG64(seed))
        u, r = rng.uniform(-0.4, 0.4), rng.random()
        L1 = 10.0 * math.exp(u / 3.0)
        log_acc = -0.01 * (L1**3 - 1000.0) + 3 * math.log(L1**3 / 1000.0)
        accept = log_acc >= 0.0 or r < math.exp(log_acc)
        seen.add(accept)
        assert bar.attempted == 1 and bar.accepted == int(accept)
        assert sim.container.length == (L1 if accept else 10.0)
        # the spheres moved freely for 0.5 (no collision), then were scaled with the box
        expected = (before + 0.5 * np.array([[0.3, 0.1, 0.0], [-0.3, -0.1, 0.0]])) * (
            L1 / 10.0 if accept else 1.0
        )
        np.testing.assert_allclose(sim.state().positions, expected, rtol=1e-14, atol=1e-14)
    assert seen == {True, False}  # both outcomes were checked


def test_a_move_that_makes_an_overlap_is_rejected():
    # at rest, 1 + 1e-6 diameters apart: squeezing ln V by more than 3e-6 overlaps them
    sim = _two(gap=1.000001, L=4.0, v=((0.0, 0.0, 0.0), (0.0, 0.0, 0.0)))
    bar = Barostat(pressure=1e3, kT=1.0, every=1.0, step=0.05, seed=1, approach=False)
    sim.set_barostat(bar)
    sim.run(until=200.0)
    assert bar.attempted == 200
    assert bar.accepted == 0  # expansions lose against the pressure, squeezes overlap
    assert bar.overlaps > 50
    assert sim.container.length == 4.0
    x = sim.state().positions
    assert closest_ratio(x, sim.engine.radii_at(), [4.0] * 3) == pytest.approx(1.000001, rel=1e-12)


def test_a_squeeze_that_fits_is_accepted_and_leaves_no_overlap():
    sim = _two(gap=1.05, L=4.0, v=((0.0, 0.0, 0.0), (0.0, 0.0, 0.0)))
    bar = Barostat(pressure=1e3, kT=1.0, every=1.0, step=0.05, seed=3, approach=False)
    sim.set_barostat(bar).run(until=400.0)
    assert 0 < bar.accepted < bar.attempted
    x = sim.state().positions
    ratio = closest_ratio(x, sim.engine.radii_at(), [sim.container.length] * 3)
    assert 1.0 <= ratio < 1.0 + 0.05 / 3  # squeezed to within one step of contact


def test_the_volume_is_distributed_as_the_npt_ensemble():
    # three point-like spheres: no overlaps, so the volume is Gamma(N + 1, beta P)
    # exactly: mean (N + 1) / (beta P), variance (N + 1) / (beta P)^2.  Fails
    # with N instead of N + 1 in the ln V random walk's rule (mean 3 / 1.5 = 2).
    sim = hs.Simulation.from_arrays(
        masses=[1.0] * 3,
        radii=[1e-3] * 3,
        positions=[[0.0, 0.0, 0.0], [0.4, 0.3, 0.1], [-0.2, 0.5, -0.4]],
        velocities=[[0.5, -0.2, 0.1], [-0.3, 0.4, 0.2], [-0.2, -0.2, -0.3]],
        container=hs.PeriodicBox(1.5),
    )
    bp = 1.5
    bar = Barostat(pressure=bp, kT=1.0, every=0.01, step=1.5, seed=7, approach=False)
    sim.set_barostat(bar)
    vols = []
    for _ in range(12000):
        sim.run(until=sim.time + 0.01)
        vols.append(sim.container.volume)
    v = np.array(vols[500:])
    b = blocking(v)
    assert abs(b.mean - 4.0 / bp) < 4.0 * b.sem
    assert abs(b.mean - 3.0 / bp) > 8.0 * b.sem  # the wrong Jacobian would be seen
    var = blocking((v - v.mean()) ** 2)
    assert abs(var.mean - 4.0 / bp**2) < 4.0 * var.sem
    assert 0.2 < bar.acceptance < 0.9


def test_resume_is_bit_for_bit(tmp_path):
    box = hs.PeriodicBox.for_packing(64, 0.35)
    state = hs.random_spheres(64, 0.35, box=box.length, seed=4)
    sim = hs.Simulation(state, box).set_barostat(Barostat(pressure=6.0, seed=5))
    sim.run(until=1.0)
    sim.save(tmp_path / "c.npz")
    sim.run(until=3.0)
    again = hs.Simulation.load(tmp_path / "c.npz").run(until=3.0)
    assert again.barostat.state() == sim.barostat.state()
    assert again.container == sim.container
    a, b = sim.state(), again.state()
    assert np.array_equal(a.positions, b.positions) and np.array_equal(a.velocities, b.velocities)
    assert np.array_equal(a.images, b.images)
    assert sim.barostat.accepted > 5
    # (stale predictions depend on the calendar's layout, made anew on resume: tests/test_reorder.py)
    ca, cb = again.counters, sim.counters
    assert {k: ca[k] for k in ca if k != "stale"} == {k: cb[k] for k in cb if k != "stale"}


def test_the_same_seed_gives_the_same_run():
    def run(seed):
        box = hs.PeriodicBox.for_packing(32, 0.3)
        sim = hs.Simulation(hs.random_spheres(32, 0.3, box=box.length, seed=1), box)
        sim.set_barostat(Barostat(pressure=4.0, seed=seed)).run(until=2.0)
        return sim.container.length, sim.state().positions

    (l1, x1), (l2, x2), (l3, _) = run(3), run(3), run(4)
    assert l1 == l2 and np.array_equal(x1, x2) and l3 != l1


def test_rescale_box_scales_the_unwrapped_centres():
    box = hs.PeriodicBox.for_packing(40, 0.2)
    sim = hs.Simulation(hs.random_spheres(40, 0.2, box=box.length, seed=2), box)
    sim.run(until=3.0)
    eng = sim.engine
    raw = eng.unwrapped_at()
    c = eng.counters["collisions"]
    eng.rescale_box(hs.PeriodicBox(box.length * 1.1), [1.1] * 3)
    np.testing.assert_allclose(eng.unwrapped_at(), raw * 1.1, rtol=1e-13, atol=1e-12)
    assert eng.counters["collisions"] == c and eng.container.length == box.length * 1.1
    with pytest.raises(ValueError):
        hs.Simulation(hs.random_spheres(5, 0.01, 10.0, seed=1), 10.0).engine.rescale_box(
            hs.PeriodicBox(3.0), [1.0] * 3
        )


def test_closest_ratio_against_brute_force():
    rng = np.random.default_rng(5)
    for n, L in ((2, 3.5), (30, 4.0), (200, 9.0)):
        x = rng.uniform(-L / 2, L / 2, (n, 3))
        r = rng.uniform(0.2, 0.5, n) * (L / 9.0 if n == 200 else 1.0)
        r = np.minimum(r, L / 6.001)
        d = x[:, None] - x[None]
        d -= L * np.round(d / L)
        ratio = np.sqrt((d**2).sum(-1)) / (r[:, None] + r[None])
        ratio[np.diag_indices(n)] = np.inf
        brute = ratio.min()
        got = closest_ratio(x, r, [L, L, L])
        assert got == brute if brute < 1.0 else got == brute or got == np.inf


@pytest.mark.parametrize(
    "kwargs, word",
    [
        ({"pressure": 0.0}, "pressure"),
        ({"pressure": float("nan")}, "pressure"),
        ({"pressure": "x"}, "pressure"),
        ({"pressure": 1.0, "kT": -1.0}, "kT"),
        ({"pressure": 1.0, "every": 0.0}, "every"),
        ({"pressure": 1.0, "step": float("inf")}, "step"),
        ({"pressure": 1.0, "axes": "xw"}, "axes"),
        ({"pressure": 1.0, "axes": "xx"}, "axes"),
        ({"pressure": 1.0, "seed": -1}, "seed"),
        ({"pressure": 1.0, "seed": 1.5}, "seed"),
        ({"pressure": True}, "pressure"),
        ({"pressure": -2.0}, "pressure"),
        ({"pressure": 1.0, "kT": float("inf")}, "kT"),
        ({"pressure": 1.0, "every": -1.0}, "every"),
        ({"pressure": 1.0, "step": "big"}, "step"),
        ({"pressure": 1.0, "axes": ""}, "axes"),
        ({"pressure": 1.0, "axes": 3}, "axes"),
        ({"pressure": 1.0, "seed": "one"}, "seed"),
    ],
)
def test_bad_options_name_the_argument(kwargs, word):
    with pytest.raises(BarostatError) as e:
        Barostat(**kwargs)
    msg = str(e.value)
    assert word in msg and "\n" not in msg


def test_refused_in_a_spherical_container():
    sim = hs.Simulation(hs.random_spheres(10, 0.1, hs.SphericalContainer(5.0), seed=1), 5.0)
    with pytest.raises(BarostatError) as e:
        sim.set_barostat(Barostat(pressure=1.0))
    assert "periodic box" in str(e.value) and "\n" not in str(e.value)
    assert isinstance(e.value, ValueError)


def test_refused_with_a_window():
    box = hs.PeriodicBox(6.0)
    sim = hs.Simulation(hs.random_spheres(10, 0.1, box=6.0, seed=1), box, window=1e-8)
    with pytest.raises(BarostatError, match="window"):
        sim.set_barostat(Barostat(pressure=1.0))


def test_damaged_barostat_in_a_checkpoint(tmp_path):
    box = hs.PeriodicBox(6.0)
    sim = hs.Simulation(hs.random_spheres(10, 0.1, box=6.0, seed=1), box)
    sim.set_barostat(Barostat(pressure=1.0)).run(until=0.5)
    sim.save(tmp_path / "c.npz")
    data = dict(np.load(tmp_path / "c.npz"))
    data["barostat"] = np.array('{"kind": "mc-volume"}')
    np.savez(tmp_path / "bad.npz", **data)
    with pytest.raises(hs.CheckpointError, match="bad barostat"):
        hs.Simulation.load(tmp_path / "bad.npz")


def test_state_round_trips():
    b = Barostat(pressure=2.5, kT=1.0, every=0.1, step=0.01, seed=9, approach=False)
    b2 = barostat_from_state(b.state())
    assert b2.state() == b.state() and repr(b2) == repr(b)


def test_one_move_of_one_side_follows_the_rule_exactly():
    # per-axis moves: the side drawn, u, r, then the same rule with V'/V = L_a'/L_a
    seen = set()
    for seed in range(12):
        sim = _two()
        bar = Barostat(pressure=0.01, kT=1.0, every=0.5, step=0.4, axes="xz", seed=seed, approach=False)
        sim.set_barostat(bar).run(until=0.5)
        rng = np.random.Generator(np.random.PCG64(seed))
        axis = "xz"[int(rng.integers(2))]
        u, r = rng.uniform(-0.4, 0.4), rng.random()
        la = 10.0 * math.exp(u)
        log_acc = -0.01 * (100.0 * la - 1000.0) + 3 * math.log(la / 10.0)
        accept = log_acc >= 0.0 or r < math.exp(log_acc)
        seen.add((axis, accept))
        expected = [10.0, 10.0, 10.0]
        if accept:
            expected["xyz".index(axis)] = la
        assert sim.container.sides == pytest.approx(tuple(expected), rel=1e-15)
        assert bar.accepted == int(accept)
    assert {a for a, _ in seen} == {"x", "z"} and {b for _, b in seen} == {True, False}


def _points(n, container, seed=0):
    rng = np.random.default_rng(seed)
    d = container.dimensions
    return hs.Simulation.from_arrays(
        masses=[1.0] * n,
        radii=[1e-3] * n,
        positions=rng.uniform(-0.4, 0.4, (n, d)) * np.array(container.sides),
        velocities=rng.normal(size=(n, d)),
        container=container,
    )


@pytest.mark.parametrize(
    "container, axes",
    [
        (hs.PeriodicBox((1.0, 1.2, 1.5)), "z"),
        (hs.PeriodicBox((1.2, 1.5)), None),
        (hs.PeriodicBox((1.2, 1.5)), "x"),
    ],
    ids=["slab-z", "disks-isotropic", "disks-x"],
)
def test_one_free_side_or_an_area_is_distributed_as_the_npt_ensemble(container, axes):
    # point-like particles: V (area in 2-D) is Gamma(N + 1, beta P) whether the
    # whole box scales or one side moves (the others fixed); N + 1 from the ln walk
    sim = _points(3, container, seed=2)
    bp = 1.5
    bar = Barostat(pressure=bp, kT=1.0, every=0.01, step=1.5, axes=axes, seed=11, approach=False)
    sim.set_barostat(bar)
    vols = []
    for _ in range(12000):
        sim.run(until=sim.time + 0.01)
        vols.append(sim.container.volume)
    v = np.array(vols[500:])
    b = blocking(v)
    assert abs(b.mean - 4.0 / bp) < 4.0 * b.sem
    assert abs(b.mean - 3.0 / bp) > 8.0 * b.sem
    if axes == "z":
        assert sim.container.sides[:2] == (1.0, 1.2)  # the cross-section never moves
    assert sim.container.dimensions == container.dimensions


def test_disks_at_constant_pressure_keep_apart_and_resume(tmp_path):
    box = hs.PeriodicBox((12.0, 12.0))
    sim = hs.Simulation(hs.random_spheres(60, 0.4, box, seed=3), box)
    sim.set_barostat(Barostat(pressure=4.0, axes="xy", seed=1)).run(until=3.0)
    assert sim.barostat.accepted >= 3 and sim.container.sides[0] != sim.container.sides[1]
    x = sim.state().positions
    assert x.shape == (60, 2)
    assert closest_ratio(x, sim.engine.radii_at(), sim.container.sides) >= 1.0
    sim.save(tmp_path / "d.npz")
    sim.run(until=5.0)
    again = hs.Simulation.load(tmp_path / "d.npz").run(until=5.0)
    assert again.container == sim.container and np.array_equal(again.state().positions, sim.state().positions)


def test_a_square_box_stays_two_dimensional():
    box = hs.PeriodicBox((10.0, 10.0))
    sim = hs.Simulation(hs.random_spheres(20, 0.2, box, seed=1), box)
    sim.set_barostat(Barostat(pressure=1.0, every=0.2, seed=2)).run(until=4.0)
    assert sim.barostat.accepted > 0 and sim.container.dimensions == 2
    s = sim.container.sides
    assert s[0] == pytest.approx(s[1], rel=1e-14)


def test_closest_ratio_of_disks_against_brute_force():
    rng = np.random.default_rng(8)
    L = np.array([9.0, 6.0])
    x = rng.uniform(-0.5, 0.5, (150, 2)) * L
    r = rng.uniform(0.1, 0.3, 150)
    d = x[:, None] - x[None]
    d -= L * np.round(d / L)
    ratio = np.sqrt((d**2).sum(-1)) / (r[:, None] + r[None])
    ratio[np.diag_indices(150)] = np.inf
    assert closest_ratio(x, r, L) == ratio.min()


def test_refused_in_a_circular_container_with_one_line():
    from hardspheres.containers import CircularContainer

    c = CircularContainer(8.0)
    sim = hs.Simulation(hs.random_spheres(10, 0.1, c, seed=1), c)
    with pytest.raises(BarostatError) as e:
        sim.set_barostat(Barostat(pressure=1.0))
    msg = str(e.value)
    assert "periodic box" in msg and "circular" in msg and "\n" not in msg


def test_a_z_move_refused_in_two_dimensions():
    box = hs.PeriodicBox((10.0, 10.0))
    sim = hs.Simulation(hs.random_spheres(10, 0.1, box, seed=1), box)
    with pytest.raises(BarostatError) as e:
        sim.set_barostat(Barostat(pressure=1.0, axes="z"))
    assert "'xy'" in str(e.value) and "\n" not in str(e.value)


def test_the_fluid_at_constant_pressure_against_hansen_goos():
    # the cheap version of validation/constant_pressure.py: 64 spheres at
    # beta P sigma^3 = 5, 8000 moves; the mean packing and N var(V)/<V>^2
    # within 3 blocked standard errors of the inverse of Hansen-Goos and of
    # 1 / (d(phi Z)/d phi) (a finite-N bias of O(1/N) is inside the errors)
    from hardspheres.eos import inverse_compressibility, packing_at_pressure

    phi0 = packing_at_pressure(5.0)
    box = hs.PeriodicBox.for_packing(64, phi0)
    sim = hs.Simulation(hs.random_spheres(64, phi0, box=box.length, seed=3), box)
    sim.run(collisions=20 * 64)
    bar = Barostat(pressure=5.0, kT=1.0, seed=3)
    sim.set_barostat(bar)
    bar.attach(sim)
    sim.run(until=bar.next_time + 999 * bar.every)
    vols = []
    for _ in range(8000):
        sim.run(until=bar.next_time)
        vols.append(sim.container.volume)
    v = np.array(vols)
    solid = sim.packing * sim.container.volume
    b = blocking(solid / v)
    assert abs(b.mean - phi0) < 3 * b.sem and b.sem < 0.005
    q = blocking(64 * (v - v.mean()) ** 2 / v.mean() ** 2)
    ref = 1.0 / float(inverse_compressibility(phi0))
    assert abs(q.mean - ref) < 3 * q.sem and q.sem < 0.4 * ref


def test_spheres_at_rest_need_a_kt():
    sim = _two(v=((0.0, 0.0, 0.0), (0.0, 0.0, 0.0)))
    with pytest.raises(BarostatError) as e:
        sim.set_barostat(Barostat(pressure=1.0)).run(until=1.0)
    assert "at rest" in str(e.value) and "kT" in str(e.value) and "\n" not in str(e.value)


def test_a_side_move_scales_that_side_only():
    # two spheres at rest 1 + 1e-6 diameters apart along x, at a pressure that
    # accepts every squeeze that fits: squeezing x always overlaps them (no
    # move accepted); squeezing y never does, so Ly shrinks to the engine's
    # bound (three diameters) while Lx, Lz and the pair's x distance stay exactly
    rest = ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0))
    sim = _two(gap=1.000001, L=4.0, v=rest)
    bar = Barostat(pressure=1e3, kT=1.0, every=1.0, step=0.05, axes="x", seed=1, approach=False)
    sim.set_barostat(bar).run(until=100.0)
    assert bar.accepted == 0 and bar.overlaps > 25 and sim.container.sides == (4.0, 4.0, 4.0)
    sim = _two(gap=1.000001, L=4.0, v=rest)
    x0 = sim.state().positions
    bar = Barostat(pressure=1e3, kT=1.0, every=1.0, step=0.05, axes="y", seed=1, approach=False)
    sim.set_barostat(bar).run(until=100.0)
    lx, ly, lz = sim.container.sides
    assert bar.overlaps == 0 and bar.accepted > 5 and lx == lz == 4.0 and 3.0 < ly < 3.0 * math.exp(0.05)
    x = sim.state().positions
    assert np.array_equal(x[:, 0], x0[:, 0]) and np.array_equal(x[:, 2], x0[:, 2])
    assert np.array_equal(x[:, 1], x0[:, 1])  # y = 0 scales to 0
    assert closest_ratio(x, sim.engine.radii_at(), sim.container.sides) == pytest.approx(1.000001, rel=1e-12)


def test_the_averages_are_of_the_box_after_each_move():
    # mean_volume, volume_variance and mean_packing against the volumes read
    # after each move (the product of the sides), with per-side moves
    box = hs.PeriodicBox.for_packing(40, 0.3, (1.0, 1.0, 1.4))
    sim = hs.Simulation(hs.random_spheres(40, 0.3, box, seed=2), box)
    bar = Barostat(pressure=4.0, kT=1.0, axes="xyz", seed=3)
    sim.set_barostat(bar)
    bar.attach(sim)
    vols = []
    for _ in range(300):
        sim.run(until=bar.next_time)
        vols.append(math.prod(sim.container.sides))
    v = np.array(vols)
    assert bar.samples == 300 and bar.accepted > 30 and len(set(sim.container.sides)) == 3
    assert bar.mean_volume == pytest.approx(v.mean(), rel=1e-12)
    assert bar.volume_variance == pytest.approx(v.var(ddof=1), rel=1e-9)
    assert bar.mean_packing == pytest.approx(np.mean(40 * math.pi / 6.0 / v), rel=1e-12)


def test_per_side_moves_resume_bit_for_bit(tmp_path):
    box = hs.PeriodicBox.for_packing(64, 0.35, (1.0, 1.0, 1.5))
    sim = hs.Simulation(hs.random_spheres(64, 0.35, box, seed=4), box)
    sim.set_barostat(Barostat(pressure=6.0, axes="xyz", seed=5)).run(until=1.0)
    sim.save(tmp_path / "c.npz")
    sim.run(until=3.0)
    again = hs.Simulation.load(tmp_path / "c.npz").run(until=3.0)
    assert again.barostat.state() == sim.barostat.state() and again.container == sim.container
    assert len(set(sim.container.sides)) == 3 and sim.barostat.accepted > 5
    a, b = sim.state(), again.state()
    assert np.array_equal(a.positions, b.positions) and np.array_equal(a.velocities, b.velocities)


@pytest.mark.parametrize(
    "dim, n, reference",
    [
        (3, 500, lambda: eos.packing_at_pressure(5.0)),  # Hansen-Goos: 0.3929
        (2, 400, lambda: eos.packing_at_pressure(5.0, eos.kolafa_rottner, bounds=(0.0, 0.7), dimensions=2)),
    ],
)
def test_from_packing_0_3_the_mean_is_the_equation_of_state_s_by_t_200(dim, n, reference):
    """`run --pressure 5 --until 200 --equilibrate 50` from 0.3 averaged 0.3186 against Hansen-Goos's 0.3932
    (compressions refused near contact: the approach crawled, and the mean included it).  Now the box is
    squeezed to the equation of state's packing first, and the averages start after."""
    box = hs.PeriodicBox.for_packing(n, 0.3) if dim == 3 else hs.PeriodicBox.for_packing(n, 0.3, (1, 1))
    sim = hs.Simulation(hs.random_spheres(n, 0.3, box, seed=1), box)
    bar = Barostat(pressure=5.0, seed=1)
    sim.set_barostat(bar).run(until=50.0)
    assert bar.squeezes > 0 and not bar.approaching and bar.target == pytest.approx(reference(), rel=1e-12)
    bar.reset_averages()
    sim.run(until=200.0)
    assert bar.mean_packing == pytest.approx(reference(), rel=0.01)


def test_the_approach_is_quick_and_not_averaged():
    box = hs.PeriodicBox.for_packing(500, 0.3)
    sim = hs.Simulation(hs.random_spheres(500, 0.3, box, seed=1), box)
    bar = Barostat(pressure=5.0, seed=1)
    sim.set_barostat(bar).run(until=20.0)  # there after about 2, Metropolis moves since
    assert not bar.approaching and sim.packing == pytest.approx(bar.target, rel=0.02)
    assert bar.samples == bar.attempted > 0  # only the Metropolis moves are samples
    # a checkpoint keeps the approach's state: the same moves after a resume
    mid = hs.PeriodicBox.for_packing(500, 0.3)
    a = hs.Simulation(hs.random_spheres(500, 0.3, mid, seed=1), mid).set_barostat(
        Barostat(pressure=5.0, seed=1)
    )
    a.run(until=0.2)  # the approach takes about 2 here
    assert a.barostat.approaching
    from hardspheres.barostat import barostat_from_state

    b = barostat_from_state(a.barostat.state())
    assert (b.target, b.approaching, b.squeezes) == (a.barostat.target, True, a.barostat.squeezes)


def test_a_drifting_packing_is_said_to_drift(capsys):
    """Without the approach, the old crawl from 0.3: the packing still rises over the averaged moves;
    `run`'s summary warns of it on stderr."""
    from hardspheres.cli.run import barostat_line

    box = hs.PeriodicBox.for_packing(300, 0.3)
    sim = hs.Simulation(hs.random_spheres(300, 0.3, box, seed=1), box)
    bar = Barostat(pressure=5.0, seed=1, approach=False)
    sim.set_barostat(bar).run(until=60.0)
    assert bar.drifting and bar.packing_drift > 0.01 * bar.mean_packing
    barostat_line(sim)
    assert capsys.readouterr().err.startswith("hardspheres run: warning: the packing drifts by +0.0")
    box = hs.PeriodicBox.for_packing(300, 0.3)
    sim = hs.Simulation(hs.random_spheres(300, 0.3, box, seed=1), box)
    bar = Barostat(pressure=0.5, seed=1)  # already denser than the equation of state's (0.07): no approach
    sim.set_barostat(bar).run(until=0.5)
    assert bar.target is not None and not bar.approaching and bar.squeezes == 0

"""The compiled engine against brute force, and long runs that must stay exact."""

import math

import numpy as np
import pytest
from numba import njit

from hardspheres import _core as core
from hardspheres import engine as engine_module
from hardspheres import reference
from hardspheres._core import collide, pair_time, reflect, wall_time
from hardspheres.builders import random_spheres
from hardspheres.engine import Engine


@njit  # no cache: numba would not see changes to the _core functions it calls
def brute_force(mass, rad, pos, vel, container, n_events, window):
    """The reference loop of hardspheres.reference, on arrays, compiled.

    Every wall and every pair predicted afresh after every event (O(N^2)),
    with the same arithmetic as the reference, so that larger N can be
    checked in reasonable time.
    """
    n = mass.shape[0]
    tloc = np.zeros(n)
    out_t = np.zeros(n_events)
    out = np.full((n_events, 3), -1, np.int64)
    clock = 0.0
    for e in range(n_events):
        soon = clock + window
        best, bk, bi, bj = np.inf, -1, -1, -1
        for i in range(n):
            te = tloc[i] + wall_time(pos[i, 0], pos[i, 1], pos[i, 2],
                                     vel[i, 0], vel[i, 1], vel[i, 2], container - rad[i])
            if te < soon:
                te = clock
            if te < best:
                best, bk, bi, bj = te, 0, i, -1
        for i in range(n):
            for j in range(i + 1, n):
                t0 = max(tloc[i], tloc[j])
                di, dj = t0 - tloc[i], t0 - tloc[j]
                te = t0 + pair_time(
                    (pos[i, 0] + vel[i, 0] * di) - (pos[j, 0] + vel[j, 0] * dj),
                    (pos[i, 1] + vel[i, 1] * di) - (pos[j, 1] + vel[j, 1] * dj),
                    (pos[i, 2] + vel[i, 2] * di) - (pos[j, 2] + vel[j, 2] * dj),
                    vel[i, 0] - vel[j, 0], vel[i, 1] - vel[j, 1], vel[i, 2] - vel[j, 2],
                    rad[i] + rad[j])
                if te < soon:
                    te = clock
                if te < best:
                    best, bk, bi, bj = te, 1, i, j
        if bk < 0:
            return out_t[:e], out[:e]
        clock = best
        for k in (bi, bj):
            if k >= 0:
                d = best - tloc[k]
                for a in range(3):
                    pos[k, a] += vel[k, a] * d
                tloc[k] = best
        if bk == 0:
            f = reflect(pos[bi, 0], pos[bi, 1], pos[bi, 2], vel[bi, 0], vel[bi, 1], vel[bi, 2])
            for a in range(3):
                vel[bi, a] -= f * pos[bi, a]
        else:
            dx = pos[bi, 0] - pos[bj, 0]
            dy = pos[bi, 1] - pos[bj, 1]
            dz = pos[bi, 2] - pos[bj, 2]
            k1, k2 = collide(mass[bi], mass[bj], dx, dy, dz, vel[bi, 0] - vel[bj, 0],
                             vel[bi, 1] - vel[bj, 1], vel[bi, 2] - vel[bj, 2])
            vel[bi, 0] -= k1 * dx
            vel[bi, 1] -= k1 * dy
            vel[bi, 2] -= k1 * dz
            vel[bj, 0] += k2 * dx
            vel[bj, 1] += k2 * dy
            vel[bj, 2] += k2 * dz
        out_t[e] = best
        out[e, 0], out[e, 1], out[e, 2] = bk, bi, bj
    return out_t, out


def mixed_scenario(seed, n):
    """``n`` spheres of radii spread 10x and masses spread 100x, at random."""
    rng = np.random.default_rng(seed)
    container = 30.0 * max(1.0, n ** (1 / 3))
    radii = rng.uniform(0.3, 3.0, n)
    masses = np.exp(rng.uniform(0.0, np.log(100.0), n))
    pos = np.zeros((n, 3))
    k = 0
    while k < n:
        x = rng.uniform(-container, container, 3)
        if np.linalg.norm(x) + radii[k] > container:
            continue
        if k and np.min(np.linalg.norm(pos[:k] - x, axis=1) - radii[:k]) < radii[k]:
            continue
        pos[k] = x
        k += 1
    vel = rng.normal(size=(n, 3))
    return masses, radii, pos, vel, container


def engine_events(masses, radii, pos, vel, container, n_events, window):
    eng = Engine(masses, radii, pos, vel, container=container, window=window, rebase=False)
    ev = eng.advance(events=n_events)
    return ev["time"], np.stack([ev["kind"], ev["i"], ev["j"]], axis=1)


@pytest.mark.parametrize("seed,n", [(1, 2), (2, 3), (3, 10), (4, 40), (5, 100), (6, 300),
                                    (7, 17), (8, 200)])
@pytest.mark.parametrize("window", [0.0, 1e-8])
def test_engine_matches_brute_force(seed, n, window):
    m, r, p, v, R = mixed_scenario(seed, n)
    t_ref, e_ref = brute_force(m, r, p.copy(), v.copy(), R, 1000, window)
    t_eng, e_eng = engine_events(m, r, p, v, R, 1000, window)
    assert len(t_ref) == len(t_eng) == 1000
    # same events, same order
    assert np.array_equal(e_ref, e_eng)
    # times to 1e-9 relative (they agree bit for bit: same arithmetic)
    np.testing.assert_allclose(t_eng, t_ref, rtol=1e-9, atol=0)
    assert np.array_equal(t_eng, t_ref)


@pytest.fixture
def lists(monkeypatch):
    """The core predicts against neighbour lists whatever the density."""
    monkeypatch.setattr(engine_module, "LISTS_FROM", 0.0)


@pytest.mark.parametrize("seed,n", [(1, 2), (3, 10), (5, 100), (6, 300), (8, 200)])
@pytest.mark.parametrize("window", [0.0, 1e-8])
def test_engine_with_lists_matches_brute_force(lists, seed, n, window):
    m, r, p, v, R = mixed_scenario(seed, n)
    t_ref, e_ref = brute_force(m, r, p.copy(), v.copy(), R, 1000, window)
    t_eng, e_eng = engine_events(m, r, p, v, R, 1000, window)
    assert np.array_equal(e_ref, e_eng)
    assert np.array_equal(t_eng, t_ref)


@pytest.mark.parametrize("phi,ratio", [(0.45, 1.0), (0.3, 1.0), (0.15, 3.0)])
@pytest.mark.parametrize("window", [0.0, 1e-8])
def test_dense_engine_with_lists_matches_brute_force(lists, phi, ratio, window):
    """Neighbour lists in fluids up to packing 0.45, event for event, bit for bit."""
    n = 300
    radius = 0.5 * (n / phi) ** (1 / 3)
    s = random_spheres(n, phi, container=radius, seed=11, radius_ratio=ratio)
    m, r, p, v = s.masses, s.radii, s.positions, s.velocities
    eng = Engine(m, r, p, v, container=radius, window=window, rebase=False)
    assert eng.scalars[core.F_SHELL] > 0.0
    t_ref, e_ref = brute_force(m, r, p.copy(), v.copy(), radius, 3000, window)
    t_eng, e_eng = engine_events(m, r, p, v, radius, 3000, window)
    assert np.array_equal(e_ref, e_eng)
    assert np.array_equal(t_eng, t_ref)


def test_lists_checkpoint_and_growth(lists):
    """Lists survive a checkpoint bit for bit, and growth rebuilds them as radii outgrow them."""
    s = random_spheres(400, 0.3, box=12.0, seed=2)
    a = Engine(s.masses, s.radii, s.positions, s.velocities, box=12.0)
    a.advance(collisions=3000)
    b = Engine.restore({k: np.copy(v) for k, v in a.checkpoint().items()})
    ea, eb = a.advance(collisions=3000), b.advance(collisions=3000)
    assert all(np.array_equal(ea[k], eb[k]) for k in ea.dtype.names)
    a.set_growth(0.05)
    a.advance(collisions=20000, record=False)
    assert a.scalars[core.F_SHELL] > 0.0
    assert a.max_overlap() < 1e-9


@pytest.mark.parametrize("seed", range(4))
def test_brute_force_is_the_reference(seed):
    """The compiled brute force used above is the pure-Python reference loop."""
    m, r, p, v, R = mixed_scenario(100 + seed, 8)
    t_bf, e_bf = brute_force(m, r, p.copy(), v.copy(), R, 300, 1e-8)
    got = []
    pl, vl = p.tolist(), v.tolist()
    for t, kind, i, j, _ in reference.events(m.tolist(), r.tolist(), pl, vl, R, math.inf):
        got.append((t, kind, i, j))
        if len(got) == 300:
            break
    assert [g[0] for g in got] == t_bf.tolist()
    assert [list(g[1:]) for g in got] == e_bf.tolist()


def test_long_run_stays_exact():
    """10^6 collisions of 10^4 spheres at packing 0.45: energy, overlaps, container."""
    n = 10_000
    radius = 0.5 * (n / 0.45) ** (1 / 3)
    s = random_spheres(n, 0.45, container=radius, seed=3)
    eng = Engine(s.masses, s.radii, s.positions, s.velocities, container=radius)
    e0 = eng.kinetic_energy()
    eng.advance(collisions=1_000_000, record=False)
    assert eng.counters["collisions"] == 1_000_000
    assert abs(eng.kinetic_energy() - e0) / e0 < 1e-10
    assert eng.max_overlap() < 1e-9
    assert eng.outside() == 0


def test_long_run_periodic_box():
    n = 4000
    s = random_spheres(n, 0.4, box=20.0, seed=4)
    eng = Engine(s.masses, s.radii, s.positions, s.velocities, box=20.0)
    p0 = s.masses @ s.velocities
    e0 = eng.kinetic_energy()
    eng.advance(collisions=200_000, record=False)
    assert abs(eng.kinetic_energy() - e0) / e0 < 1e-10
    np.testing.assert_allclose(s.masses @ eng.velocities, p0, atol=1e-9 * np.sum(s.masses))
    assert eng.max_overlap() < 1e-9


def test_polydisperse_mixture_stays_exact():
    """Largest radius 10x the smallest, masses 100x apart."""
    n = 3000
    s = random_spheres(n, 0.15, container=40.0, seed=5, radius_ratio=10.0, mass_ratio=100.0)
    eng = Engine(s.masses, s.radii, s.positions, s.velocities, container=40.0)
    e0 = eng.kinetic_energy()
    eng.advance(collisions=100_000, record=False)
    assert abs(eng.kinetic_energy() - e0) / e0 < 1e-10
    assert eng.max_overlap() < 1e-9
    assert eng.outside() == 0


def test_rebase_keeps_time_and_physics():
    """Moving the time origin changes nothing a user sees beyond rounding."""
    s = random_spheres(200, 0.3, container=8.0, seed=6)
    a = Engine(s.masses, s.radii, s.positions, s.velocities, container=8.0)
    b = Engine(s.masses, s.radii, s.positions, s.velocities, container=8.0, rebase=False)
    ea = a.advance(events=20_000)
    eb = b.advance(events=20_000)
    assert a.offset > 0.0 and b.offset == 0.0
    # identical until the first rebase, then the same events to rounding for a while
    first = 64 * 200
    assert np.array_equal(ea["time"][:first], eb["time"][:first])
    assert np.array_equal(ea["i"][:first + 50], eb["i"][:first + 50])
    np.testing.assert_allclose(ea["time"][:first + 50], eb["time"][:first + 50], rtol=1e-12)


def test_assignment_report_same_from_both_engines():
    """The assignment's report from the compiled engine equals the reference's."""
    import io
    import os

    from hardspheres.assignment import write_report
    from hardspheres.scenario import parse_scenario

    rng = np.random.default_rng(11)
    for trial in range(5):
        n = int(rng.integers(25, 60))
        m, r, p, v, R = mixed_scenario(200 + trial, n)
        text = "".join(f"{a!r} {b!r} {x[0]!r} {x[1]!r} {x[2]!r} {y[0]!r} {y[1]!r} {y[2]!r} s{k}\n"
                       for k, (a, b, x, y) in enumerate(zip(m.tolist(), r.tolist(),
                                                            p.tolist(), v.tolist())))
        outs = []
        for engine in ("reference", "compiled"):
            os.environ["HARDSPHERES_ENGINE"] = engine
            try:
                buf = io.StringIO()
                write_report(parse_scenario(text), R, 300.0, buf)
            finally:
                del os.environ["HARDSPHERES_ENGINE"]
            outs.append(buf.getvalue())
        assert outs[0].count("time of event") > 20
        assert outs[0] == outs[1]

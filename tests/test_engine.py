"""The compiled engine against the brute-force reference, and long runs that must stay exact."""

import math
import types

import numpy as np
import pytest
from numba import njit

from hardspheres.builders import random_spheres
from hardspheres.core import _core, reference
from hardspheres.core import _core as core
from hardspheres.core import engine as engine_module
from hardspheres.core.engine import Engine
from hardspheres.core.reference import Reference


def _compiled(fn):
    """A step of :mod:`hardspheres.core.reference`'s loop, compiled by numba.

    The same code object as the pure-Python step (no copy), its physics
    bound to the core's compiled kernels (the same functions of
    :mod:`hardspheres.physics`); not cached: numba's cache would not see
    changes to the kernels.
    """
    glob = dict(
        fn.__globals__,
        wall_time=_core.wall_time,
        pair_time=_core.pair_time,
        reflect=_core.reflect,
        collide=_core.collide,
        wall_time_grow=_core.wall_time_grow,
        pair_time_grow=_core.pair_time_grow,
        reflect_grow=_core.reflect_grow,
        collide_grow=_core.collide_grow,
        collide_inelastic=_core.collide_inelastic,
        reflect_inelastic=_core.reflect_inelastic,
    )
    if "box_exit" in fn.__code__.co_names:
        glob["box_exit"] = _compiled(reference.box_exit)
    if "_earlier" in fn.__code__.co_names:
        glob["_earlier"] = _compiled(reference._earlier)
    if "shear_offset" in fn.__code__.co_names:
        glob["shear_offset"] = _compiled(reference.shear_offset)
    return njit(types.FunctionType(fn.__code__, glob, fn.__name__, fn.__defaults__))


class CompiledReference(Reference):
    """The reference engine with its loop's steps compiled, on arrays, for larger N.

    Every wall and every pair predicted afresh after every event (O(N^2)),
    with the reference's own code and arithmetic, so that larger N can be
    checked in reasonable time.
    """

    _next_event = staticmethod(_compiled(reference.next_event))
    _next_event_periodic = staticmethod(_compiled(reference.next_event_periodic))
    _next_event_sheared = staticmethod(_compiled(reference.next_event_sheared))
    _move_sphere = staticmethod(_compiled(reference.move_sphere))
    _apply_event = staticmethod(_compiled(reference.apply_event))

    def __init__(self, *args, **kw):
        super().__init__(*args, **kw)
        n = self.n
        self.masses = np.array(self.masses, dtype=np.float64)
        self._radii = np.array(self._radii, dtype=np.float64)
        self._p = np.array(self._p, dtype=np.float64).reshape(n, 3)
        self._v = np.array(self._v, dtype=np.float64).reshape(n, 3)
        self._tloc = np.array(self._tloc, dtype=np.float64)


#: Each test so marked runs on the pure-Python reference and the compiled engine.
ENGINES = pytest.mark.parametrize("engine", [Reference, Engine], ids=["reference", "compiled"])


def same_events(a, b):
    """Two event records equal bit for bit, field by field."""
    return a.dtype == b.dtype and all(np.array_equal(a[f], b[f]) for f in a.dtype.names)


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


def run(engine, masses, radii, pos, vel, container, n_events, window):
    """``n_events`` events from ``engine`` (a class); the events and the engine after."""
    eng = engine(masses, radii, pos, vel, container=container, window=window, rebase=False)
    return eng.advance(events=n_events), eng


def assert_same_state(eng, ref, n):
    """The engine ``eng`` and the reference ``ref`` (``n`` spheres) agree bit for bit after a run."""
    assert np.array_equal(eng.velocities, ref.velocities)
    assert np.array_equal(eng.positions_at(), ref.positions_at(out=np.empty((n, 3))))
    for key in ("collisions", "reflections"):
        assert eng.counters[key] == ref.counters[key]
    assert (eng.time, eng.wall_impulse, eng.virial) == (ref.time, ref.wall_impulse, ref.virial)


@pytest.mark.parametrize("seed,n", [(1, 2), (2, 3), (3, 10), (4, 40), (5, 100), (6, 300), (7, 17), (8, 200)])
@pytest.mark.parametrize("window", [0.0, 1e-8])
def test_engine_matches_brute_force(seed, n, window):
    """Same events, same order, same times, impulses and velocities, bit for bit."""
    m, r, p, v, R = mixed_scenario(seed, n)
    ref_ev, ref = run(CompiledReference, m, r, p, v, R, 1000, window)
    eng_ev, eng = run(Engine, m, r, p, v, R, 1000, window)
    assert len(ref_ev) == len(eng_ev) == 1000
    assert same_events(eng_ev, ref_ev)
    assert_same_state(eng, ref, n)


@pytest.fixture
def lists(monkeypatch):
    """The core predicts against neighbour lists whatever the density."""
    monkeypatch.setattr(engine_module, "LISTS_FROM", 0.0)


@pytest.mark.parametrize("seed,n", [(1, 2), (3, 10), (5, 100), (6, 300), (8, 200)])
@pytest.mark.parametrize("window", [0.0, 1e-8])
def test_engine_with_lists_matches_brute_force(lists, seed, n, window):
    m, r, p, v, R = mixed_scenario(seed, n)
    ref_ev, ref = run(CompiledReference, m, r, p, v, R, 1000, window)
    eng_ev, eng = run(Engine, m, r, p, v, R, 1000, window)
    assert eng.scalars[core.F_SHELL] > 0.0
    assert same_events(eng_ev, ref_ev)
    assert np.array_equal(eng.velocities, ref.velocities)


@pytest.mark.parametrize("phi,ratio", [(0.45, 1.0), (0.3, 1.0), (0.15, 3.0)])
@pytest.mark.parametrize("window", [0.0, 1e-8])
def test_dense_engine_with_lists_matches_brute_force(lists, phi, ratio, window):
    """Neighbour lists in fluids up to packing 0.45, event for event, bit for bit."""
    n = 300
    radius = 0.5 * (n / phi) ** (1 / 3)
    s = random_spheres(n, phi, container=radius, seed=11, radius_ratio=ratio)
    m, r, p, v = s.masses, s.radii, s.positions, s.velocities
    ref_ev, ref = run(CompiledReference, m, r, p, v, radius, 3000, window)
    eng_ev, eng = run(Engine, m, r, p, v, radius, 3000, window)
    assert eng.scalars[core.F_SHELL] > 0.0
    assert same_events(eng_ev, ref_ev)
    assert np.array_equal(eng.velocities, ref.velocities)


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


def _recalendar(eng, buckets, rate):
    """``eng``'s event calendar made anew with ``buckets`` buckets ``1 / rate`` wide."""
    eng.calendar = np.full(buckets + 1 + 3 * eng.n, -1, eng.calendar.dtype)
    core.requeue(
        eng.heap,
        eng.heap_t,
        eng.heap_key,
        eng.calendar,
        eng.due,
        eng.book,
        eng.scalars,
        eng.counts,
        2.0,
        rate,
    )


@pytest.mark.parametrize(
    "buckets,rate",
    [
        (2, 0.0),  # a year of two buckets: most entries wait in the overflow list
        (64, 3e8),  # buckets narrower than the window: it reaches into later ones
        (2, 1e12),  # the window reaches past the year: into the overflow list
        (1024, 1e-6),  # one bucket: a plain heap
        (2, 1e17),  # bucket numbers past 2^52 (not exact as doubles): one heap (this hung)
    ],
)
@pytest.mark.parametrize("lists_on", [False, True])
def test_calendar_extremes_match_brute_force(monkeypatch, buckets, rate, lists_on):
    """However the calendar is cut into buckets, the same events as the reference, bit for bit."""
    if lists_on:
        monkeypatch.setattr(engine_module, "LISTS_FROM", 0.0)
    m, r, p, v, R = mixed_scenario(5, 100)
    ref_ev, ref = run(CompiledReference, m, r, p, v, R, 1500, 1e-8)
    eng = Engine(m, r, p, v, container=R, window=1e-8, rebase=False)
    _recalendar(eng, buckets, rate)
    eng_ev = eng.advance(events=1500)
    assert same_events(eng_ev, ref_ev)
    assert np.array_equal(eng.velocities, ref.velocities)
    # every sphere in exactly one place: the heap, a bucket or the overflow
    size = int(eng.counts[core.C_HEAP_SIZE])
    nb = len(eng.calendar) - 1 - 3 * eng.n
    where = eng.calendar[nb + 1 + core.CAL_BUCKET :: 3]
    assert np.sum(where == core.CAL_HEAP) == size and size > 0
    assert np.array_equal(np.sort(eng.heap[:size]), np.nonzero(where == core.CAL_HEAP)[0])
    queued = (where != core.CAL_HEAP) & (where != nb)  # (nb: the overflow list's slot)
    assert np.sum(queued) == eng.counts[core.C_QUEUED]


def test_calendar_when_nothing_will_happen():
    """Spheres at rest: no event ever, the calendar says so (and a kick wakes it)."""
    eng = Engine([1.0, 1.0], [1.0, 1.0], [[-5.0, 0, 0], [5.0, 0, 0]], np.zeros((2, 3)), box=30.0)
    assert eng.idle and len(eng.advance(until=100.0)) == 0
    eng.kick(1, 100.0, (-1.0, 0.0, 0.0))
    ev = eng.advance(until=200.0)  # (and again and again, across the box)
    assert ev["time"].tolist()[:2] == [108.0, 134.0] and not eng.idle


@pytest.mark.parametrize("seed", range(4))
def test_brute_force_is_the_reference(seed):
    """The compiled steps used above give the pure-Python reference's events, bit for bit."""
    m, r, p, v, R = mixed_scenario(100 + seed, 8)
    compiled, _ = run(CompiledReference, m, r, p, v, R, 300, 1e-8)
    pure, _ = run(Reference, m.tolist(), r.tolist(), p.tolist(), v.tolist(), R, 300, 1e-8)
    assert len(pure) == 300
    assert same_events(compiled, pure)


@ENGINES
def test_head_on_pair_and_wall(engine):
    """Two spheres meet head on at t = 4, then each reflects off the wall at t = 102."""
    eng = engine(
        [1.0, 1.0], [1.0, 1.0], [[-5.0, 0, 0], [5.0, 0, 0]], [[1.0, 0, 0], [-1.0, 0, 0]], container=100.0
    )
    assert eng.step(until=3.0) is None
    assert eng.step(until=10.0) == (4.0, 1, 0, 1)
    assert np.asarray(eng.velocities).tolist() == [[-1.0, 0, 0], [1.0, 0, 0]]
    ev = eng.advance(until=150.0)
    assert ev["time"].tolist() == [102.0, 102.0] and ev["kind"].tolist() == [0, 0]
    assert ev["i"].tolist() == [0, 1] and ev["j"].tolist() == [-1, -1]
    assert ev["dp"].tolist() == [[2.0, 0, 0], [-2.0, 0, 0]]
    assert eng.counters["collisions"] == 1 and eng.counters["reflections"] == 2
    assert eng.wall_impulse == 4.0 and eng.time == 102.0
    assert np.asarray(eng.positions_at(150.0)).tolist() == [[-51.0, 0, 0], [51.0, 0, 0]]
    assert eng.kinetic_energy() == 1.0


@ENGINES
def test_count_limits_and_stop_reasons(engine):
    from hardspheres.events import StopReason

    m, r, p, v, R = mixed_scenario(9, 12)
    eng = engine(m, r, p, v, container=R, window=0.0, rebase=False)
    ev = eng.advance(events=7)
    assert len(ev) == 7 and eng.last_done == 7 and eng.last_reason == StopReason.MAX_EVENTS
    c0 = eng.counters["collisions"]
    eng.advance(collisions=3, record=False)
    assert eng.counters["collisions"] == c0 + 3
    assert eng.last_reason == StopReason.MAX_COLLISIONS
    with pytest.raises(ValueError, match="NaN"):
        eng.advance(until=math.nan)


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
    assert np.array_equal(ea["i"][: first + 50], eb["i"][: first + 50])
    np.testing.assert_allclose(ea["time"][: first + 50], eb["time"][: first + 50], rtol=1e-12)


def test_assignment_report_same_from_both_engines():
    """The assignment's report from the compiled engine equals the reference's."""
    import io
    import os

    from hardspheres.cli.assignment import write_report
    from hardspheres.scenario import parse_scenario

    rng = np.random.default_rng(11)
    for trial in range(5):
        n = int(rng.integers(25, 60))
        m, r, p, v, R = mixed_scenario(200 + trial, n)
        text = "".join(
            f"{a!r} {b!r} {x[0]!r} {x[1]!r} {x[2]!r} {y[0]!r} {y[1]!r} {y[2]!r} s{k}\n"
            for k, (a, b, x, y) in enumerate(zip(m.tolist(), r.tolist(), p.tolist(), v.tolist()))
        )
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


def test_arrays_follow_the_core_order():
    """Engine.arrays hands the core its arrays in _core.ARRAYS' order (the core unpacks by position)."""
    eng = Engine(
        [1.0, 1.0], [1.0, 1.0], [[-5.0, 0, 0], [5.0, 0, 0]], [[1.0, 0, 0], [-1.0, 0, 0]], container=20.0
    )
    arrays = eng.arrays
    assert len(arrays) == len(_core.ARRAYS)
    for name, array in zip(_core.ARRAYS, arrays):
        assert array is getattr(eng, name), name


# ---- the engine's own order of the spheres (spatial reordering) --------------------


@pytest.mark.parametrize("lists_on", [False, True])
@pytest.mark.parametrize("window", [0.0, 1e-8])
def test_reordered_engine_matches_brute_force(monkeypatch, lists_on, window):
    """Sorted in space at the build and every 0.02 N events: the reference's events, bit for bit.

    A dense fluid (packing 0.45) in a sphere, so that ties in the window and
    neighbour lists both have work to do.
    """
    monkeypatch.setattr(engine_module, "LISTS_FROM", 0.0 if lists_on else 1.0)
    sorts = []
    monkeypatch.setattr(Engine, "_permute", _counting(Engine._permute, sorts))
    n = 300
    radius = 0.5 * (n / 0.45) ** (1 / 3)
    s = random_spheres(n, 0.45, container=radius, seed=12)
    m, r, p, v = s.masses, s.radii, s.positions, s.velocities
    ref_ev, ref = run(CompiledReference, m, r, p, v, radius, 3000, window)
    eng = Engine(m, r, p, v, container=radius, window=window, rebase=False, reorder=0.02)
    eng_ev = eng.advance(events=3000)
    assert len(sorts) >= 20  # (3000 events / 5 per sort, the build's included)
    assert not np.array_equal(eng.order, np.arange(n))  # the test can fail
    assert (eng.scalars[core.F_SHELL] > 0.0) == lists_on
    assert same_events(eng_ev, ref_ev)
    assert_same_state(eng, ref, n)


def _counting(fn, calls):
    """``fn`` that appends to ``calls`` whenever it is called."""

    def counted(self, *args, **kw):
        calls.append(1)
        return fn(self, *args, **kw)

    return counted


@pytest.mark.parametrize("packing", [0.1, 0.45])  # cells, neighbour lists
def test_no_record_same_events_and_not_limited_by_the_buffer(packing):
    """``run(..., record=False)`` writes every event to one row: the same
    dynamics bit for bit as a recorded run, and more events in one call than
    the record holds."""
    from hardspheres.events import StopReason

    n = 2000
    box = (n * math.pi / 6 / packing) ** (1 / 3)
    s = random_spheres(n, packing, box=box, seed=5)
    a = Engine(s.masses, s.radii, s.positions, s.velocities, box=box)
    b = Engine(s.masses, s.radii, s.positions, s.velocities, box=box)
    cap = len(a._event_buffers[0])
    a.advance(collisions=3 * cap, record=True)
    b.advance(collisions=3 * cap, record=False)
    assert np.array_equal(a.positions_at(), b.positions_at())
    assert np.array_equal(a.velocities, b.velocities)
    assert a.counters == b.counters
    done, reason = core.run(b.arrays, np.inf, 2 * cap, 2**62, b._event_buffers, False, (), ())
    assert (done, reason) == (2 * cap, StopReason.MAX_EVENTS)
    done, reason = core.run(a.arrays, np.inf, 2 * cap, 2**62, a._event_buffers, True, (), ())
    assert (done, reason) == (cap, StopReason.RECORD_FULL)


def test_calendar_made_anew_on_schedule_without_a_record(monkeypatch):
    """With no record kept the core is not stopped by the record's size; the
    engine still stops it when the calendar is due to be made anew (N events
    after the build, then 2N, 4N, ...), not later."""
    due = []

    def watched(self, first=False):
        if not first:
            due.append((self._since_queue, self._queue_every))
        return queue_anew(self, first)

    queue_anew = Engine._queue_anew
    monkeypatch.setattr(Engine, "_queue_anew", watched)
    n = 3000
    box = (n * math.pi / 6 / 0.3) ** (1 / 3)
    s = random_spheres(n, 0.3, box=box, seed=6)
    eng = Engine(s.masses, s.radii, s.positions, s.velocities, box=box, rebase=False, reorder=0)
    eng.advance(collisions=20 * n, record=False)
    assert [every for _, every in due] == [n, 2 * n, 4 * n, 8 * n]
    assert all(since == every for since, every in due)


def test_link_arrays_have_the_link_dtype_in_the_engine_and_int64_in_checkpoints():
    """The cell lists, heads, heap and calendar hold sphere indices as LINK; files keep int64 (one format)."""
    from hardspheres.core import engine as engine_module

    eng = engine_module.Engine(
        [1.0] * 3,
        [0.5] * 3,
        [[-2.0, 0, 0], [0.0, 0, 0], [2.0, 0, 0]],
        [[1.0, 0, 0], [0.0, 0, 0], [-1.0, 0, 0]],
        box=8.0,
    )
    for name in engine_module._LINKED + ("scratch", "calendar"):
        assert getattr(eng, name).dtype == engine_module.LINK, name
    data = eng.checkpoint()
    for name in engine_module._LINKED:
        assert data[name].dtype == np.int64, name
    again = engine_module.Engine.restore(data)
    assert again.cell_next.dtype == engine_module.LINK
    assert again.advance(events=50).tobytes() == eng.advance(events=50).tobytes()


def test_kick_at_the_engine_time_after_a_rebase():
    """A kick at ``eng.time`` is at the clock, even where offset + clock - offset rounds below it.

    (Regression: after the time origin moved, ``kick(i, eng.time, v)`` was
    refused one time in a few as "before the clock".)
    """
    from hardspheres.builders import random_arrays
    from hardspheres.containers import PeriodicBox

    box = PeriodicBox(12.0)
    eng = Engine(*random_arrays(64, 0.2, box, seed=3), container=box)
    for step in range(60):
        eng.advance(events=997)
        t = eng.time
        eng.kick(step % 64, t, (0.5, -0.25, 0.125))
        assert eng.time == t
    assert eng.offset > 0.0

"""The engine's own order of the spheres (Morton order, made anew as they move) changes no bit.

The engine keeps its per-sphere arrays sorted in space for the caches; tie
keys, the arithmetic of a collision (lower input index minus higher) and
everything it shows are on the input order, so a run sorted every few
events must be the unsorted run, bit for bit (and tests/test_engine.py
checks the sorted one against the brute-force reference).
"""

import numpy as np
import pytest

import hardspheres as hs
from hardspheres.builders import random_spheres
from hardspheres.core import _core as core
from hardspheres.core import engine as engine_module
from hardspheres.core.checkpoint import check_arrays
from hardspheres.core.engine import CheckpointError, Engine


def _pair(n, phi, box, window, growth, reorder, seed=3):
    """Two engines on one scenario: one in the input order, one sorted every ``reorder`` N events."""
    size = (n * (4 / 3) * np.pi * 0.5**3 / phi) ** (1 / 3)
    where = {"box": size} if box else {"container": 0.5 * size * (6 / np.pi) ** (1 / 3)}
    s = random_spheres(n, phi, seed=seed, radius_ratio=1.2, **where)
    engines = [
        Engine(s.masses, s.radii, s.positions, s.velocities, window=window, reorder=k, **where)
        for k in (0.0, reorder)
    ]
    if growth:
        for eng in engines:
            eng.set_growth(growth)
    return engines


def _same_state(a, b):
    """Everything the engines show, bit for bit."""
    assert a.time == b.time
    assert np.array_equal(a.positions_at(), b.positions_at())
    assert np.array_equal(a.unwrapped_at(), b.unwrapped_at())
    assert np.array_equal(a.velocities, b.velocities)
    assert np.array_equal(a.radii_at(), b.radii_at())
    assert np.array_equal(a.masses, b.masses)
    assert np.array_equal(a.images, b.images)
    # (but the stale predictions dropped: of two spheres holding the same
    # collision at the same time, one fresh, one stale, the calendar's layout
    # decides which comes out first; the events are the same either way)
    ca, cb = a.counters, b.counters
    assert {k: ca[k] for k in ca if k != "stale"} == {k: cb[k] for k in cb if k != "stale"}
    assert (a.wall_impulse, a.virial) == (b.wall_impulse, b.virial)
    ta, tb = a.transport_tallies(), b.transport_tallies()
    assert all(np.array_equal(ta[k], tb[k]) for k in ta)
    assert a.max_overlap() == b.max_overlap()


def _same_events(a, b):
    return a.dtype == b.dtype and all(np.array_equal(a[f], b[f]) for f in a.dtype.names)


@pytest.mark.parametrize("box", [True, False], ids=["box", "sphere"])
@pytest.mark.parametrize("lists", [False, True], ids=["cells", "lists"])
@pytest.mark.parametrize(
    "window,growth", [(0.0, 0.0), (1e-3, 0.0), (0.0, 0.02)], ids=["exact", "window", "growth"]
)
def test_sorting_changes_no_bit(monkeypatch, box, lists, window, growth):
    """Events, state and tallies of a run sorted every 0.1 N events are the unsorted run's."""
    if lists:
        monkeypatch.setattr(engine_module, "LISTS_FROM", 0.0)
    a, b = _pair(300, 0.3, box, window, growth, reorder=0.1)
    assert (a.scalars[core.F_SHELL] > 0.0) == lists
    orders = set()
    for _ in range(6):
        ea = a.advance(events=4000)
        eb = b.advance(events=4000)
        assert _same_events(ea, eb)
        orders.add(b.order.tobytes())
        _same_state(a, b)
    assert len(orders) == 6  # sorted anew as they moved (the test can fail)
    assert np.array_equal(a.order, np.arange(a.n))
    # a kick names a sphere in the input order
    t = a.time + 4 * np.spacing(a.time)  # (not before the clock after the offset's rounding)
    for eng in (a, b):
        eng.kick(7, t, (1.0, -2.0, 0.5))
    assert np.array_equal(a.advance(events=3000), b.advance(events=3000))
    _same_state(a, b)


def test_positions_of_a_few_spheres_in_the_input_order():
    a, b = _pair(200, 0.3, False, 0.0, 0.0, reorder=0.1)
    a.advance(events=2000)
    b.advance(events=2000)
    some = [3, 150, 0]
    pa = a.positions_at(spheres=some, out=np.zeros((200, 3)))
    pb = b.positions_at(spheres=some, out=np.zeros((200, 3)))
    assert np.array_equal(pa, pb) and np.any(pa[150] != 0.0)


def test_images_set_in_the_input_order():
    a, b = _pair(200, 0.3, True, 0.0, 0.0, reorder=0.1)
    images = np.arange(600, dtype=np.int64).reshape(200, 3)
    a.images = images
    b.images = images
    assert not np.array_equal(b.order, np.arange(200))
    assert np.array_equal(b.images, images) and np.array_equal(a.unwrapped_at(), b.unwrapped_at())


@pytest.mark.parametrize("lists", [False, True], ids=["cells", "lists"])
def test_sorted_checkpoint_resumes_bit_for_bit(monkeypatch, lists):
    """A sorted engine saved and restored goes on with the same events, in the same order of its own."""
    if lists:
        monkeypatch.setattr(engine_module, "LISTS_FROM", 0.0)
    a, b = _pair(300, 0.3, True, 1e-3, 0.0, reorder=0.1)
    a.advance(events=5000)
    b.advance(events=5000)
    saved = b.checkpoint()
    assert not np.array_equal(saved["book"][:, core.ORIGIN], np.arange(300))
    c = Engine.restore({k: np.array(v) for k, v in saved.items()})
    ea, eb, ec = (e.advance(events=6000) for e in (a, b, c))
    assert _same_events(ea, eb) and _same_events(eb, ec)
    assert np.array_equal(b.spheres, c.spheres) and np.array_equal(b.order, c.order)
    _same_state(a, c)


def _with_origin(saved, origin):
    book = saved["book"].copy()
    book[:, core.ORIGIN] = origin
    return dict(saved, book=book)


def test_checkpoint_order_is_checked():
    _, b = _pair(100, 0.3, True, 0.0, 0.0, reorder=0.1)
    b.advance(events=500)
    saved = b.checkpoint()
    check_arrays(saved)
    with pytest.raises(CheckpointError, match="permutation"):
        check_arrays(_with_origin(saved, np.zeros(100, np.int64)))
    with pytest.raises(CheckpointError, match="permutation"):
        Engine.restore(_with_origin(saved, np.arange(1, 101)))
    with pytest.raises(CheckpointError, match="reorder"):
        Engine.restore(dict(saved, reorder=np.array([np.nan, 0.0])))
    # a permutation, but not the one the tie keys were made with
    with pytest.raises(CheckpointError, match="key"):
        check_arrays(_with_origin(saved, np.roll(saved["book"][:, core.ORIGIN], 1)))


def test_checkpoint_without_order_is_the_input_order():
    """Checkpoints from before the engine's own order load as they were."""
    a, _ = _pair(100, 0.3, True, 0.0, 0.0, reorder=0.1)
    a.advance(events=500)
    saved = a.checkpoint()
    old = {k: v for k, v in saved.items() if k != "reorder"}
    old["book"] = saved["book"][:, : core.ORIGIN]
    c = Engine.restore(old)
    assert np.array_equal(c.order, np.arange(100))
    assert np.array_equal(a.advance(events=2000), c.advance(events=2000))


def test_reorder_option():
    s = random_spheres(50, 0.3, box=6.0, seed=1)
    for bad in (-1.0, np.nan, np.inf):
        with pytest.raises(ValueError, match="reorder"):
            Engine(s.masses, s.radii, s.positions, s.velocities, box=6.0, reorder=bad)
    eng = Engine(s.masses, s.radii, s.positions, s.velocities, box=6.0)
    assert eng._reorder_every == 0.0  # small: not sorted unless told
    eng = Engine(s.masses, s.radii, s.positions, s.velocities, box=6.0, reorder=1.0)
    assert not np.array_equal(eng.order, np.arange(50))


def test_simulation_sorted_saved_and_loaded(monkeypatch, tmp_path):
    """A Simulation whose engine sorts (as from REORDER_FROM spheres): its states, events and file."""
    s = random_spheres(400, 0.3, box=9.0, seed=5)
    plain = hs.Simulation(s, hs.PeriodicBox(9.0), window=1e-8)
    monkeypatch.setattr(engine_module, "REORDER_FROM", 0)
    monkeypatch.setattr(engine_module, "REORDER_EVERY", 0.5)
    sorted_ = hs.Simulation(s, hs.PeriodicBox(9.0), window=1e-8)
    assert sorted_.engine._reorder_every == 0.5 and plain.engine._reorder_every == 0.0
    for sim in (plain, sorted_):
        sim.run(collisions=3000)
    sorted_.save(tmp_path / "c.npz")
    back = hs.Simulation.load(tmp_path / "c.npz")
    assert not np.array_equal(back.engine.order, np.arange(400))
    events = [list(sim.iter_events(collisions=3000)) for sim in (plain, sorted_, back)]
    assert len(events[0]) >= 3000 and events[0] == events[1] == events[2]
    for sim in (sorted_, back):
        a, b = plain.state(unwrapped=True), sim.state(unwrapped=True)
        assert np.array_equal(a.positions, b.positions) and np.array_equal(a.velocities, b.velocities)
        assert np.array_equal(a.images, b.images) and np.array_equal(a.masses, b.masses)

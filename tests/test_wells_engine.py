"""Square wells and stepped potentials in the compiled event core, against the brute-force reference, bit for bit.

The stepped variant (``_core``, the second entry of ``axes``): each sphere's
bond table in its book row, every pair predicted by its state (core,
capture, release), a step's crossing or bounce by ``physics.cross_step``.
The reference (:mod:`hardspheres.core.reference`, ``steps=``) is the
definition: the same events, velocities, pair states and potential energy,
in spheres, circles and periodic boxes, 2-D and 3-D, window on and off.
"""

import numpy as np
import pytest

from hardspheres.containers import CircularContainer, PeriodicBox, SphericalContainer
from hardspheres.core import _core as core
from hardspheres.core import checkpoint
from hardspheres.core import engine as engine_module
from hardspheres.core.engine import Engine
from hardspheres.errors import ArgumentError, BoxShapeError, ShearError

from test_engine import CompiledReference, same_events
from test_reference_boxes import _pair

WELL = [(1.5, -1.0)]
SHOULDERED = [(1.6, 0.5), (1.3, -1.0), (1.1, -2.0)]  # a shoulder, then two wells
CASES = {
    "sphere, well": (SphericalContainer(9.0), WELL),
    "cube, three steps": (PeriodicBox(11.0), SHOULDERED),
    "circle, three steps": (CircularContainer(10.0), SHOULDERED),
    "square, well": (PeriodicBox((21.0, 21.0)), WELL),
}


def _both(container, steps, n=60, phi=0.2, seed=3, events=800, window=0.0):
    m, r, x, v = _pair(container, n, phi, seed=seed, ratio=1.2)
    kw = dict(container=container, window=window, steps=steps)
    eng = Engine(m, r, x, v, rebase=False, reorder=0.0, **kw)
    ref = CompiledReference(m, r, np.asarray(x).tolist(), np.asarray(v).tolist(), **kw)
    assert eng.pair_states == ref.pair_states  # (the states from the distances, as the reference's)
    return eng, ref, eng.advance(events=events), ref.advance(events=events)


@pytest.mark.parametrize("case", list(CASES))
def test_the_stepped_engine_is_the_reference_bit_for_bit(case):
    c, steps = CASES[case]
    eng, ref, a, b = _both(c, steps)
    assert eng.axes[1] == ((),) and eng.scalars[core.F_SHELL] == 0.0  # (the stepped variant, cells)
    assert len(a) == len(b) == 800 and same_events(a, b)
    n, d = eng.n, eng.dimensions
    assert np.array_equal(eng.velocities, np.asarray(ref.velocities, dtype=float).reshape(n, d))
    assert eng.pair_states == ref.pair_states and eng.counters == {**ref.counters, **_cells(eng)}
    assert eng.potential_energy() == ref.potential_energy() and eng.virial == ref.virial
    assert min(eng.counters[k] for k in ("captures", "releases", "bounces")) > 0


NARROW = [(1.2, -1.0)]  # (a box of few spheres still holds three cells of lists)
LISTED = {
    "sphere, well": (SphericalContainer(9.0), NARROW, 100),
    "cube, well": (PeriodicBox(16.0), NARROW, 150),
    "square, well": (PeriodicBox((21.0, 21.0)), NARROW, 100),
}


@pytest.mark.parametrize("case", list(LISTED))
def test_neighbour_lists_reach_the_outermost_step_and_give_the_references_bits(case, monkeypatch):
    """Lists in the stepped variant: each reach widened to the outer edge; the same events as the reference."""
    monkeypatch.setattr(engine_module, "LISTS_FROM", 0.0)
    monkeypatch.setattr(engine_module, "LISTS_FROM_2D", 0.0)
    c, steps, n = LISTED[case]
    eng, ref, a, b = _both(c, steps, n=n, phi=0.25, events=1000)
    assert eng.scalars[core.F_SHELL] > 0.0  # (lists)
    outer = steps[0][0]
    assert eng.scalars[core.F_HEADROOM] == outer
    assert len(a) == len(b) == 1000 and same_events(a, b)
    assert eng.pair_states == ref.pair_states and eng.potential_energy() == ref.potential_energy()
    assert eng.virial == ref.virial
    assert min(eng.counters[k] for k in ("captures", "releases", "bounces")) > 0


def _cells(eng):
    return {k: eng.counters[k] for k in ("crossings", "stale", "refreshed")}


def test_the_window_gives_the_references_bits_too():
    eng, ref, a, b = _both(PeriodicBox(11.0), WELL, window=1e-8, events=600)
    assert same_events(a, b) and eng.pair_states == ref.pair_states


@pytest.mark.parametrize("where", [PeriodicBox(11.0), SphericalContainer(9.0)])
def test_sorted_spheres_keep_their_bonds_and_energy_is_conserved(where):
    """Morton reordering renames the bond tables' partners: the same events; K + U conserved to rounding."""
    m, r, x, v = _pair(where, 200, 0.3, seed=5)
    a = Engine(m, r, x, v, container=where, steps=WELL, reorder=0.0)
    b = Engine(m, r, x, v, container=where, steps=WELL, reorder=1.0)
    assert same_events(a.advance(events=20000), b.advance(events=20000))
    assert a.pair_states == b.pair_states and not np.array_equal(b.order, np.arange(200))
    e0 = a.kinetic_energy() + a.potential_energy()
    a.advance(events=30000)
    assert abs(a.kinetic_energy() + a.potential_energy() - e0) <= 1e-12 * abs(e0)
    assert a.potential_energy() == -float(len(a.pair_states))  # (a well of depth 1: -1 per bonded pair)
    assert a.max_overlap() < 1e-9


def test_bond_tables_widen_as_they_fill(monkeypatch):
    """One entry per table at first: the core stops when one would overflow, the engine widens, the bits stay."""
    c = PeriodicBox(11.0)
    m, r, x, v = _pair(c, 120, 0.25, seed=8)
    wide = Engine(m, r, x, v, container=c, steps=SHOULDERED)
    monkeypatch.setattr(engine_module, "BONDS_FIRST", 1)
    narrow = Engine(m, r, x, v, container=c, steps=SHOULDERED)
    width0 = narrow.book.shape[1]
    assert same_events(wide.advance(events=8000), narrow.advance(events=8000))
    assert narrow.book.shape[1] > width0


def test_a_stepped_engine_resumes_from_its_checkpoint_and_damage_is_refused():
    c = CircularContainer(10.0)
    m, r, x, v = _pair(c, 60, 0.3, seed=13)
    a = Engine(m, r, x, v, container=c, steps=SHOULDERED)
    a.advance(events=3000)
    saved = a.checkpoint()
    b = Engine.restore({k: np.copy(w) for k, w in saved.items()})
    assert b.steps == a.steps and b.pair_states == a.pair_states
    assert same_events(a.advance(events=3000), b.advance(events=3000))
    bonded = np.nonzero(saved["book"][:, core.BONDS])[0]
    for damage in ("asymmetric", "species", "steps"):
        bad = {k: np.copy(w) for k, w in saved.items()}
        if damage == "asymmetric":
            bad["book"][bonded[0], core.BONDS + 1] ^= 1  # (another state on one side)
        elif damage == "species":
            bad["book"][0, core.SPECIES] = 7
        else:
            bad["scalars"][core.F_STEP + 1] = 0.5  # (species 0 with 0: its outermost lambda)
        with pytest.raises(checkpoint.CheckpointError, match="damaged checkpoint"):
            Engine.restore(bad)


@pytest.mark.parametrize(
    "kw, error, words",
    [
        (dict(steps=[(1.5, -1.0)] * 2), ArgumentError, "lambda decreasing"),
        (
            dict(steps=[(2.0, -1.0), (1.8, 1.0), (1.6, 1.0), (1.4, 1.0), (1.2, 1.0)]),
            ArgumentError,
            "at most 4",
        ),
        (dict(steps=WELL, restitution=0.9), ArgumentError, "restitution"),
    ],
)
def test_bad_steps_are_refused(kw, error, words):
    with pytest.raises(error, match=words):
        Engine(
            [1.0, 1.0],
            [0.5, 0.5],
            [[0.0, 0, 0], [3.0, 0, 0]],
            [[1.0, 0, 0], [0.0, 0, 0]],
            container=10.0,
            **kw,
        )


def test_steps_refuse_shear_growth_and_a_small_box():
    x, v = [[0.0, 0, 0], [3.0, 0, 0]], [[1.0, 0, 0], [0.0, 0, 0]]
    with pytest.raises(ShearError, match="sheared"):
        Engine([1.0, 1.0], [0.5, 0.5], x, v, container=PeriodicBox(10.0, shear_rate=0.1), steps=WELL)
    with pytest.raises(BoxShapeError, match="half the box"):
        Engine([1.0, 1.0], [0.5, 0.5], x, v, container=PeriodicBox(2.9), steps=WELL)
    eng = Engine([1.0, 1.0], [0.5, 0.5], x, v, container=10.0, steps=WELL)
    with pytest.raises(ArgumentError, match="grow"):
        eng.set_growth(0.1)


def test_hard_spheres_keep_their_loop():
    eng = Engine(
        [1.0, 1.0], [0.5, 0.5], [[0.0, 0, 0], [3.0, 0, 0]], [[1.0, 0, 0], [0.0, 0, 0]], container=10.0
    )
    assert eng.axes == ((), (), ()) and eng.steps == () and eng.potential_energy() == 0.0
    assert "captures" not in eng.counters and eng.book.shape[1] == core.BOOK_COLS


@pytest.mark.parametrize("where", [PeriodicBox(11.0), CircularContainer(10.0)], ids=["cube", "circle"])
def test_steps_per_pair_of_species_are_the_references(where):
    """A binary mixture: a well between 0 and 0, a deeper narrower one between 0 and 1, hard spheres 1 with 1."""
    table = {(0, 0): [(1.5, -1.0)], (0, 1): [(1.3, -2.0)], (1, 1): []}
    m, r, x, v = _pair(where, 60, 0.25, seed=4)
    species = np.random.default_rng(4).integers(0, 2, len(m))
    kw = dict(container=where, steps=table, species=species)
    eng = Engine(m, r, x, v, rebase=False, reorder=0.0, **kw)
    ref = CompiledReference(m, r, np.asarray(x).tolist(), np.asarray(v).tolist(), **kw)
    assert eng.pair_states == ref.pair_states
    assert same_events(eng.advance(events=800), ref.advance(events=800))
    assert eng.pair_states == ref.pair_states and eng.potential_energy() == ref.potential_energy()
    states = eng.pair_states
    assert not any(species[i] == species[j] == 1 for i, j in states)  # (no well between 1 and 1)
    assert {species[i] + species[j] for i, j in states} == {0, 1}
    assert np.array_equal(eng.species, species) and eng.step_table[(1, 0)] == ((1.3, -2.0),)


def test_species_without_a_table_and_bad_species_are_refused():
    x, v = [[0.0, 0, 0], [3.0, 0, 0]], [[1.0, 0, 0], [0.0, 0, 0]]
    with pytest.raises(ArgumentError, match="give each sphere's species"):
        Engine([1.0, 1.0], [0.5, 0.5], x, v, container=10.0, steps={(0, 1): [(1.5, -1.0)]})
    with pytest.raises(ArgumentError, match="one integer >= 0 per sphere"):
        Engine([1.0, 1.0], [0.5, 0.5], x, v, container=10.0, steps=WELL, species=[0, -1])
    with pytest.raises(ArgumentError, match="at most 4"):
        Engine([1.0, 1.0], [0.5, 0.5], x, v, container=10.0, steps={(0, 4): WELL}, species=[0, 4])


def test_a_simulation_takes_steps_per_pair_of_species_and_refuses_what_is_not_built():
    import hardspheres as hs

    box = PeriodicBox(12.0)
    state = hs.random_spheres(80, 0.2, box, seed=2)
    species = np.arange(80) % 2
    table = {(0, 0): [(1.5, -1.0)], (0, 1): [(1.3, -2.0)]}
    sim = hs.Simulation(state, box, steps=table, species=species)
    e0 = sim.total_energy()
    sim.run(until=5.0)
    assert abs(sim.total_energy() - e0) <= 1e-12 * abs(e0) and np.array_equal(sim.engine.species, species)
    assert not any(species[i] == species[j] == 1 for i, j in sim.engine.pair_states)
    with pytest.raises(ArgumentError, match="restitution"):
        sim.set_restitution(0.9)
    circle = CircularContainer(10.0)
    walled = hs.Simulation(hs.random_spheres(30, 0.1, circle, seed=1), circle, steps=WELL)
    with pytest.raises(ArgumentError, match="thermal wall"):
        walled.set_wall_temperature(1.0)

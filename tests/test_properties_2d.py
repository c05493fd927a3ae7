"""Property tests in two dimensions (hypothesis): disks in a circle.

The 3-D property tests (tests/test_properties.py) carried over to disks:
at every reported event a collision conserves the pair's energy and
momentum, leaves the pair receding and kicks along the line of centres; a
reflection off the circle keeps the speed and reverses the normal
velocity; no two disks overlap by more than 1e-9 of their contact distance
and none pokes out of the circle by more than 1e-9 of its radius.  Checked
on both engines, with exact times and the assignment's 1e-8 window, and the
compiled engine gives the reference's events bit for bit (cells and
neighbour lists).  Then the numerics' guarantees in 2-D: a cascade at one
instant runs to its end (Galperin's billiard counts pi), a frozen clock
stops the run, and exact ties (a symmetric four-disk collision) come out
the same from both engines.

Scenarios: 1 to 12 disks at scales from 1e-3 to 1e7 (speeds scaled
alike), masses over four decades, radii up to half a grid cell, some disks
at rest and some touching their neighbours exactly.
"""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import hardspheres as hs
from hardspheres import physics
from hardspheres.containers import CircularContainer
from hardspheres.core import engine as engine_module
from hardspheres.core import reference
from hardspheres.core.engine import Engine
from hardspheres.core.reference import Reference
from hardspheres.errors import StuckError

TOL = 1e-9  # overlap / outside, relative to contact distance / container radius
CONS = 1e-12  # conservation per event, relative
CELLS = 4  # grid of CELLS^2 cells inside the circle

ENGINES = pytest.mark.parametrize("engine", [Reference, Engine], ids=["reference", "compiled"])

speeds = st.floats(-1.0, 1.0).map(lambda x: 0.0 if abs(x) < 1e-100 else x)


@st.composite
def scenarios(draw, max_n=12):
    """``(masses, radii, positions, velocities, radius)``, disks as lists of floats."""
    n = draw(st.integers(1, max_n))
    scale = 10.0 ** draw(st.floats(-3.0, 7.0))
    half = scale / math.sqrt(2.0) * 0.98  # the grid's square lies inside the circle
    w = 2.0 * half / CELLS
    cells = draw(st.permutations(range(CELLS**2)))[:n]
    masses, radii, pos, vel = [], [], [], []
    for c in cells:
        centre = [-half + w * (0.5 + k) for k in (c % CELLS, c // CELLS)]
        if draw(st.integers(0, 3)) == 0:  # touches any such neighbour exactly
            r, p = 0.5 * w, centre
        else:
            r = w * draw(st.floats(0.02, 0.48))
            room = 0.5 * w - r
            p = [x + room * draw(st.floats(-1.0, 1.0)) for x in centre]
        masses.append(10.0 ** draw(st.floats(-2.0, 2.0)))
        radii.append(r)
        pos.append(p)
        if draw(st.integers(0, 5)) == 0:
            vel.append([0.0, 0.0])
        else:
            vel.append([scale * draw(speeds) for _ in range(2)])
    return masses, radii, pos, vel, scale


def norm(a):
    return math.hypot(a[0], a[1])


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1]


def sub(a, b):
    return [a[0] - b[0], a[1] - b[1]]


def check_event(kind, i, j, pos, before, after, masses, radii, radius, window):
    """One event in 2-D: ``pos`` the centres at its time, velocities ``before`` and ``after``."""
    for k in range(len(masses)):
        if k != i and k != j:
            assert after[k] == before[k], "an uninvolved disk changed velocity"
    who = [i] if j < 0 else [i, j]
    top = max(norm(before[k]) for k in who)
    assert top > 0.0
    unit = 2.0 ** -math.frexp(top)[1]  # a power of two: squares of tiny speeds do not underflow
    before = {k: [x * unit for x in before[k]] for k in who}
    after = {k: [x * unit for x in after[k]] for k in who}
    if kind == reference.COLLISION:
        mi, mj = masses[i], masses[j]
        e0 = 0.5 * (mi * dot(before[i], before[i]) + mj * dot(before[j], before[j]))
        e1 = 0.5 * (mi * dot(after[i], after[i]) + mj * dot(after[j], after[j]))
        assert abs(e1 - e0) <= CONS * e0
        scale_p = mi * norm(before[i]) + mj * norm(before[j])
        for a in range(2):
            assert (
                abs(mi * after[i][a] + mj * after[j][a] - mi * before[i][a] - mj * before[j][a])
                <= CONS * scale_p
            )
        dr = sub(pos[i], pos[j])
        sigma = radii[i] + radii[j]
        dv0, dv1 = sub(before[i], before[j]), sub(after[i], after[j])
        assert norm(dr) - sigma <= norm(dv0) / unit * window * 1.01 + TOL * sigma
        assert dot(dr, dv0) < 0.0
        assert dot(dr, dv1) >= -CONS * norm(dr) * norm(dv0)
        kick = sub(after[i], before[i])
        u = [x / norm(dr) for x in dr]
        assert norm(sub(kick, [dot(kick, u) * x for x in u])) <= CONS * norm(dv0)
    else:
        p, v0, v1 = pos[i], before[i], after[i]
        speed = norm(v0)
        assert abs(dot(v1, v1) - dot(v0, v0)) <= CONS * dot(v0, v0)
        u = [x / norm(p) for x in p]
        assert dot(v0, u) > 0.0  # it was moving out
        assert abs(dot(v1, u) + dot(v0, u)) <= CONS * speed
        kick = sub(v1, v0)
        assert norm(sub(kick, [dot(kick, u) * x for x in u])) <= CONS * speed
        assert radius - (norm(p) + radii[i]) <= speed / unit * window * 1.01 + TOL * radius


def check_state(pos, radii, radius):
    """No overlap beyond TOL of a contact distance, nothing outside the circle beyond TOL of R."""
    for k in range(len(pos)):
        assert norm(pos[k]) + radii[k] <= radius * (1.0 + TOL)
        for m in range(k + 1, len(pos)):
            assert norm(sub(pos[k], pos[m])) >= (radii[k] + radii[m]) * (1.0 - TOL)


def energy(masses, vel):
    return sum(0.5 * m * dot(v, v) for m, v in zip(masses, vel))


@ENGINES
@settings(max_examples=60, deadline=None)
@given(scn=scenarios(), window=st.sampled_from([0.0, reference.SIMULTANEOUS]))
def test_disks_conserve_and_keep_apart_and_inside(engine, scn, window):
    """150 events, exact times or the assignment's window."""
    masses, radii, pos, vel, radius = scn
    check_state(pos, radii, radius)
    eng = engine(masses, radii, pos, vel, container=CircularContainer(radius), window=window)
    assert eng.dimensions == 2
    e_start = energy(masses, vel)
    before = [list(v) for v in vel]
    last = 0.0
    for _ in range(150):
        ev = eng.step()
        if ev is None:
            break
        t, kind, i, j = ev
        assert t >= last
        last = t
        now = [[float(x) for x in row] for row in eng.positions_at(t)]
        after = [[float(x) for x in row] for row in eng.velocities]
        assert all(len(row) == 2 for row in now + after)
        check_event(kind, i, j, now, before, after, masses, radii, radius, window)
        check_state(now, radii, radius)
        before = after
    assert abs(energy(masses, before) - e_start) <= 1e-11 * e_start


@pytest.mark.parametrize("lists", [False, True], ids=["cells", "lists"])
@settings(max_examples=40, deadline=None)
@given(scn=scenarios(), window=st.sampled_from([0.0, reference.SIMULTANEOUS]))
def test_disks_engine_matches_the_reference(lists, scn, window):
    """Same events, order, times, impulses and velocities after, bit for bit, in cells and lists."""
    masses, radii, pos, vel, radius = scn
    c = CircularContainer(radius)
    saved = engine_module.LISTS_FROM_2D
    engine_module.LISTS_FROM_2D = 0.0 if lists else 2.0
    try:
        eng = Engine(masses, radii, pos, vel, container=c, window=window, rebase=False)
    finally:
        engine_module.LISTS_FROM_2D = saved
    ref = Reference(masses, radii, pos, vel, container=c, window=window)
    got, want = eng.advance(events=200), ref.advance(events=200)
    for field in got.dtype.names:
        assert got[field].tolist() == want[field].tolist(), field
    assert eng.velocities.tolist() == ref.velocities
    assert (eng.wall_impulse, eng.virial) == (ref.wall_impulse, ref.virial)


def galperin_2d(mass_ratio):
    """A light disk touching the circle, a heavy one touching it and pushing outwards."""
    return [1.0, mass_ratio], [1.0, 4.0], [[9.0, 0.0], [4.0, 0.0]], [[0.0, 0.0], [1.0, 0.0]]


@ENGINES
@pytest.mark.parametrize("ratio,count", [(1.0, 3), (100.0, 31), (1e4, 314)])
def test_galperin_cascade_in_a_circle_counts_pi(engine, ratio, count):
    """A cascade at one instant runs to its end in 2-D too: 3, 31, 314 events at t = 0."""
    m, r, x, v = galperin_2d(ratio)
    eng = engine(m, r, x, v, container=CircularContainer(10.0), window=reference.SIMULTANEOUS)
    events = eng.advance(until=1.0)
    times = np.asarray(events["time"])
    assert int(np.sum(times == 0.0)) == count


@pytest.mark.parametrize("window,gap", [(1e-8, 1e-9), (1e-8, 1e-3), (0.0, 1.0)])
def test_frozen_clock_stops_a_disk_run(window, gap):
    """A light disk trapped by a heavy one (mass ratio 1e200) against the circle: the run stops."""
    sim = hs.Simulation.from_arrays(
        [1e-100, 1e100],
        [1.0, 4.0],
        [[9.0 - gap, 0.0], [4.0 - 2 * gap, 0.0]],
        [[0.0, 0.0], [1.0, 0.0]],
        hs.CircularContainer(10.0),
        window=window,
    )
    with pytest.raises(StuckError, match="clock is stuck") as e:
        sim.run(until=10.0)
    assert e.value.reason == "frozen" and e.value.time < 2.0 * gap + 1e-8
    assert physics.frozen_limit(2) > 0


@pytest.mark.parametrize("window", [0.0, reference.SIMULTANEOUS])
@pytest.mark.parametrize("box", [False, True], ids=["circle", "box"])
def test_exact_ties_of_a_symmetric_four_disk_collision(window, box):
    """Four disks meet a fifth at rest from four sides at one instant: the tie is broken
    the same way by both engines, and the laws hold."""
    m = [1.0] * 5
    r = [0.5] * 5
    x = [[0.0, 0.0], [-2.0, 0.0], [2.0, 0.0], [0.0, -2.0], [0.0, 2.0]]
    v = [[0.0, 0.0], [1.0, 0.0], [-1.0, 0.0], [0.0, 1.0], [0.0, -1.0]]
    c = hs.PeriodicBox((20.0, 20.0)) if box else CircularContainer(10.0)
    eng = Engine(m, r, x, v, container=c, window=window, rebase=False)
    ref = Reference(m, r, x, v, container=c, window=window)
    got, want = eng.advance(events=40), ref.advance(events=40)
    for field in got.dtype.names:
        assert got[field].tolist() == want[field].tolist(), field
    assert eng.velocities.tolist() == ref.velocities
    assert float(np.asarray(got["time"])[0]) == 1.0  # all four arrive at t = 1 exactly
    assert abs(eng.kinetic_energy() - 2.0) <= 1e-15 * 2.0
    assert eng.max_overlap() < 1e-9

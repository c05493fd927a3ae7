"""Steps of the pair potential (square wells, shoulders): the kernels and the reference.

The kernels (:func:`~hardspheres.physics.cross_step`,
:func:`~hardspheres.physics.pair_time_out`) against exact rational
arithmetic and hand-derived cases; their conservation laws as properties,
in 2-D and 3-D (docs/numerics.md, "Steps: wells and shoulders").  The
brute-force reference with steps: two-sphere cases derived by hand, and a
deep-well liquid's energy over 10^4 events.
"""

import math
import random
from fractions import Fraction
from math import isqrt

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import hardspheres as hs
from hardspheres.core.reference import Reference, check_steps
from hardspheres.errors import ArgumentError, BoxShapeError, ShearError
from hardspheres.events import EventKind
from hardspheres.physics import collide, cross_step, pair_time_out, wall_time

U = 2.0**-53


def exact_sqrt(x: Fraction, bits: int = 200) -> Fraction:
    """``sqrt(x)`` to ``2^-bits`` relative (x >= 0), as a rational."""
    if x == 0:
        return Fraction(0)
    scale = 1 << (2 * bits)
    n = x.numerator * scale // x.denominator
    return Fraction(isqrt(n), 1 << bits)


def exact_factors(m1, m2, dr, dv, du):
    """The exact ``(k1, k2, crossed)`` of a step for the float inputs (rationals)."""
    m1, m2, du = Fraction(m1), Fraction(m2), Fraction(du)
    dr = [Fraction(x) for x in dr]
    dv = [Fraction(x) for x in dv]
    b = sum(x * y for x, y in zip(dr, dv))
    r2 = sum(x * x for x in dr)
    q = b * b - 2 * r2 * du * (1 / m1 + 1 / m2)
    if q <= 0:
        s = b / r2
        return 2 * m2 / (m1 + m2) * s, 2 * m1 / (m1 + m2) * s, False
    bp = exact_sqrt(q) * (1 if b > 0 else -1)
    f = 2 * du / (b + bp)
    return f / m1, f / m2, True


def kinetic(m1, m2, v1, v2):
    return (
        Fraction(m1) * sum(Fraction(x) ** 2 for x in v1) + Fraction(m2) * sum(Fraction(x) ** 2 for x in v2)
    ) / 2


def applied(m1, m2, dr, v1, v2, du, planar):
    """The velocities after the step, in floats as an engine forms them."""
    dv = [a - b for a, b in zip(v1, v2)]
    k1, k2, crossed = cross_step(m1, m2, *dr, *dv, du, planar)
    return [a - k1 * x for a, x in zip(v1, dr)], [b + k2 * x for b, x in zip(v2, dr)], crossed


# ---- hand-derived cases ----------------------------------------------------------


def test_head_on_capture_speeds_up_to_the_formula():
    # equal masses (mu = 1/2), normal speed 2 at the edge, depth 5/4:
    # sqrt(v^2 + 2 eps / mu) = sqrt(4 + 5) = 3
    k1, k2, crossed = cross_step(1.0, 1.0, -1.5, 0.0, 0.0, 2.0, 0.0, 0.0, -1.25)
    assert crossed and k1 == k2
    assert 2.0 - (k1 + k2) * -1.5 == 3.0


def test_release_slows_down_to_the_formula():
    # masses 1 and 3 (mu = 3/4), receding at 2, well depth 9/8:
    # sqrt(v^2 - 2 eps / mu) = sqrt(4 - 3) = 1
    k1, k2, crossed = cross_step(1.0, 3.0, 0.0, 1.5, 0.0, 0.0, 2.0, 0.0, 1.125)
    assert crossed
    assert 1.0 * k1 == pytest.approx(3.0 * k2, rel=4 * U)
    assert 2.0 - (k1 + k2) * 1.5 == pytest.approx(1.0, rel=4 * U)


@pytest.mark.parametrize("planar", [False, True])
def test_bounce_when_the_normal_energy_is_short_keeps_the_tangential_velocity(planar):
    # receding at normal speed 1 with tangential speed 7: the normal energy
    # mu vn^2 / 2 = 1/4 is short of eps = 1/2 (the tangential part does not count)
    dr = (1.5, 0.0, 0.0)
    dv = (1.0, 7.0, 0.0 if planar else 3.0)
    k1, k2, crossed = cross_step(1.0, 1.0, *dr, *dv, 0.5, planar)
    assert not crossed
    assert (k1, k2) == collide(1.0, 1.0, *dr, *dv, planar)
    assert dv[0] - (k1 + k2) * 1.5 == -1.0
    # at the threshold exactly (q = 0) it bounces too
    assert not cross_step(1.0, 1.0, *dr, *dv, 0.25, planar)[2]


def test_a_capture_and_a_bounce_pull_together_and_a_core_collision_pushes_apart():
    capture = cross_step(1.0, 2.0, -1.5, 0.0, 0.0, 1.0, 0.0, 0.0, -1.0)
    release = cross_step(1.0, 2.0, 1.5, 0.0, 0.0, 3.0, 0.0, 0.0, 1.0)
    bounce = cross_step(1.0, 2.0, 1.5, 0.0, 0.0, 0.1, 0.0, 0.0, 1.0)
    core = collide(1.0, 2.0, -1.0, 0.0, 0.0, 1.0, 0.0, 0.0)
    # v_1 - k1 dr: toward sphere 2 means k1 * dr . dr > 0 (virial -m1 k1 R2 < 0)
    assert capture[0] > 0 and release[0] > 0 and bounce[0] > 0
    assert core[0] < 0


def test_pair_time_out_is_the_larger_root():
    # inside an edge of 1.5 at 1.0: receding at 1/4 reaches it in 2,
    # approaching at 1/2 crosses the middle and reaches it in (1 + 1.5) / 0.5 = 5
    assert pair_time_out(1.0, 0.0, 0.0, 0.25, 0.0, 0.0, 1.5) == 2.0
    assert pair_time_out(1.0, 0.0, 0.0, -0.5, 0.0, 0.0, 1.5) == 5.0
    assert pair_time_out(1.5, 0.0, 0.0, 0.5, 0.0, 0.0, 1.5) == 0.0  # on the edge, leaving
    assert pair_time_out(1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.5) == math.inf


# ---- exact rationals ---------------------------------------------------------------


def test_cross_step_against_exact_rationals_at_shallow_wells():
    """Within a few ulps of the exact factors from eps = 1e-12 to 1e12 of the normal energy.

    The textbook ``(b + b') / R2`` form subtracts two nearly equal numbers
    at a shallow well; it is shown to be off there, so the test would catch
    a return to it.
    """
    rng = random.Random(41)
    worst = worst_textbook = 0.0
    for _ in range(400):
        m1, m2 = rng.uniform(0.5, 2.0), rng.uniform(0.5, 2.0)
        n = [rng.gauss(0, 1) for _ in range(3)]
        norm = math.sqrt(sum(x * x for x in n))
        dr = [1.5 * x / norm for x in n]
        # approaching (a capture), with a normal part of at least a third of
        # |dv| (a dot product's own rounding is not the kernel's to remove)
        dv = [rng.gauss(0, 1) - rng.uniform(0.5, 1.5) * x / norm for x in n]
        b = sum(x * y for x, y in zip(dr, dv))
        if b > -math.sqrt(sum(x * x for x in dv)) * 0.5:
            continue
        r2 = sum(x * x for x in dr)
        normal = 0.5 * (m1 * m2 / (m1 + m2)) * b * b / r2
        du = -normal * 10.0 ** rng.uniform(-12, 12)
        k1, k2, crossed = cross_step(m1, m2, *dr, *dv, du)
        e1, e2, ecross = exact_factors(m1, m2, dr, dv, du)
        assert crossed and ecross
        worst = max(worst, abs(Fraction(k1) - e1) / abs(e1), abs(Fraction(k2) - e2) / abs(e2))
        # the textbook form (m_j / (m_i + m_j)) (b - b') / R2, with b' = -sqrt(q)
        q = b * b - 2.0 * r2 * du * (1.0 / m1 + 1.0 / m2)
        text = m2 / (m1 + m2) * (b + math.sqrt(q)) / r2
        worst_textbook = max(worst_textbook, abs(Fraction(text) - e1) / abs(e1))
    assert worst < 8 * U
    assert worst_textbook > 1e-6


def test_pair_time_out_against_exact_rationals():
    rng = random.Random(7)
    for _ in range(300):
        edge = 1.5
        n = [rng.gauss(0, 1) for _ in range(3)]
        norm = math.sqrt(sum(x * x for x in n))
        r = edge * rng.uniform(0.0, 1.0)
        dr = [r * x / norm for x in n]
        dv = [rng.gauss(0, 1) * 10.0 ** rng.uniform(-3, 3) for _ in range(3)]
        t = pair_time_out(*dr, *dv, edge)
        assert t == wall_time(*dr, *dv, edge)
        a = sum(Fraction(x) ** 2 for x in dv)
        b = sum(Fraction(x) * Fraction(y) for x, y in zip(dr, dv))
        c = sum(Fraction(x) ** 2 for x in dr) - Fraction(edge) ** 2
        root = exact_sqrt(b * b - a * c)
        exact = (-b + root) / a  # the larger root
        # the roundings of c = |dr|^2 - edge^2 and b move the root by their
        # size over the discriminant's root (the problem's conditioning)
        cond = (sum(Fraction(x) ** 2 for x in dr) + Fraction(edge) ** 2) / (abs(b) + root)
        assert abs(Fraction(t) - exact) <= 8 * U * (exact + cond)


# ---- conservation, 2-D and 3-D -----------------------------------------------------

coord = st.floats(-2.0, 2.0, allow_nan=False)
speed = st.floats(-5.0, 5.0, allow_nan=False)
mass = st.floats(0.1, 10.0)


@settings(max_examples=300, deadline=None, derandomize=True)
@given(
    m1=mass,
    m2=mass,
    dr=st.tuples(coord, coord, coord),
    v1=st.tuples(speed, speed, speed),
    v2=st.tuples(speed, speed, speed),
    du=st.floats(-10.0, 10.0),
    planar=st.booleans(),
)
def test_energy_and_momentum_are_conserved_to_rounding(m1, m2, dr, v1, v2, du, planar):
    if planar:
        dr, v1, v2 = (dr[0], dr[1], 0.0), (v1[0], v1[1], 0.0), (v2[0], v2[1], 0.0)
    r2 = sum(x * x for x in dr)
    if r2 < 1e-2:
        return
    w1, w2, crossed = applied(m1, m2, dr, list(v1), list(v2), du, planar)
    if planar:
        assert w1[2] == v1[2] and w2[2] == v2[2]
    k0 = kinetic(m1, m2, v1, v2)
    k1 = kinetic(m1, m2, w1, w2)
    gained = -Fraction(du) if crossed else Fraction(0)
    scale = k0 + abs(Fraction(du)) + Fraction(1, 10**6)
    assert abs(k1 - k0 - gained) <= 64 * U * scale
    if not crossed:  # a bounce only where the normal energy is short
        b = sum(Fraction(x) * (Fraction(p) - Fraction(q)) for x, p, q in zip(dr, v1, v2))
        mu = Fraction(m1) * Fraction(m2) / (Fraction(m1) + Fraction(m2))
        assert mu * b * b / (2 * sum(Fraction(x) ** 2 for x in dr)) <= Fraction(du) * (1 + 64 * U) + Fraction(
            1, 10**12
        )
    for ax in range(3):
        p0 = Fraction(m1) * Fraction(v1[ax]) + Fraction(m2) * Fraction(v2[ax])
        p1 = Fraction(m1) * Fraction(w1[ax]) + Fraction(m2) * Fraction(w2[ax])
        ps = Fraction(m1) * (abs(Fraction(v1[ax])) + abs(Fraction(w1[ax])))
        ps += Fraction(m2) * (abs(Fraction(v2[ax])) + abs(Fraction(w2[ax])))
        assert abs(p1 - p0) <= 8 * U * ps


# ---- the reference with steps --------------------------------------------------------


def two(dr, v1, v2, steps, d=3, m=(1.0, 1.0), wall=20.0):
    """Two spheres of radius 1/2 (sigma = 1) in a container: sphere 0 at ``-dr``, sphere 1 at the origin."""
    box = hs.SphericalContainer(wall) if d == 3 else hs.CircularContainer(wall)
    pos = [[-x for x in dr], [0.0] * d]
    return Reference(list(m), [0.5, 0.5], pos, [list(v1), list(v2)], box, steps=steps)


@pytest.mark.parametrize("d", [2, 3])
def test_reference_head_on_capture_core_collision_and_release(d):
    z = [0.0] * (d - 1)
    # relative speed 2, mu = 1/2, eps = 5/4: inside at sqrt(4 + 2 eps / mu) = 3
    ref = two([4.0] + z, [1.0] + z, [-1.0] + z, [(1.5, -1.25)], d)
    assert ref.pair_states == {} and ref.potential_energy() == 0.0
    t, kind, i, j = ref.step()
    assert (t, kind, i, j) == (1.25, EventKind.CAPTURE, 0, 1)  # (4 - 1.5) / 2
    assert ref.velocities[0][0] == 1.5 and ref.velocities[1][0] == -1.5
    assert ref.pair_states == {(0, 1): 1} and ref.potential_energy() == -1.25
    assert ref.virial == pytest.approx(-0.75, rel=4 * U)  # -m k R2 = -(1/3)(9/4): attraction
    t, kind, _, _ = ref.step()
    assert kind == EventKind.COLLISION and t == pytest.approx(1.25 + 0.5 / 3, rel=4 * U)
    assert ref.pair_states == {(0, 1): 1}  # a core collision leaves the state alone
    t, kind, _, _ = ref.step()
    assert kind == EventKind.RELEASE and t == pytest.approx(1.25 + 1.0 / 3, rel=4 * U)
    # back out at sqrt(9 - 5) / 2 = 1 each
    assert ref.velocities[0][0] == pytest.approx(-1.0, rel=8 * U)
    assert ref.pair_states == {} and ref.potential_energy() == 0.0
    assert ref.counters["captures"] == ref.counters["releases"] == ref.counters["collisions"] == 1


@pytest.mark.parametrize("d", [2, 3])
def test_reference_bounce_when_the_normal_energy_is_short(d):
    z = [0.0] * (d - 1)
    # inside the well at 1.2, receding at relative speed 1 (normal energy 1/4 < eps = 1),
    # with a tangential velocity that must not change
    ref = two([1.2] + z, [-0.5, 3.0] + z[1:], [0.5, 3.0] + z[1:], [(1.5, -1.0)], d)
    assert ref.pair_states == {(0, 1): 1}
    t, kind, _, _ = ref.step()
    assert kind == EventKind.BOUNCE and t == pytest.approx(0.3, rel=4 * U)
    assert ref.velocities[0][:2] == [0.5, 3.0] and ref.velocities[1][:2] == [-0.5, 3.0]
    assert ref.pair_states == {(0, 1): 1} and ref.counters["bounces"] == 1
    # and a shoulder (U > 0) too high to climb: bounced from outside
    ref = two([3.0] + z, [0.5] + z, [-0.5] + z, [(1.5, 1.0)], d)
    t, kind, _, _ = ref.step()
    assert kind == EventKind.BOUNCE and t == 1.5
    assert ref.pair_states == {} and ref.velocities[0][0] == -0.5


def test_reference_steps_are_checked():
    pos, vel = [[-2.0, 0.0, 0.0], [2.0, 0.0, 0.0]], [[1.0, 0.0, 0.0], [-1.0, 0.0, 0.0]]
    with pytest.raises(ArgumentError, match="lambda decreasing"):
        check_steps([(1.2, -1.0), (1.5, -1.0)])
    with pytest.raises(ArgumentError, match="above 1"):
        check_steps([(0.9, -1.0)])
    with pytest.raises(ArgumentError, match="restitution"):
        Reference([1, 1], [0.5, 0.5], pos, vel, 10.0, restitution=0.9, steps=[(1.5, -1.0)])
    with pytest.raises(BoxShapeError, match="half the box"):
        Reference([1, 1], [0.5, 0.5], [[0.0] * 3, [1.2, 0, 0]], vel, hs.PeriodicBox(2.5), steps=[(1.5, -1.0)])
    with pytest.raises(ShearError, match="sheared"):
        Reference(
            [1, 1],
            [0.5, 0.5],
            [[0.0] * 3, [1.2, 0, 0]],
            vel,
            hs.PeriodicBox(8.0),
            shear_rate=0.1,
            steps=[(1.5, -1.0)],
        )
    ref = Reference([1, 1], [0.5, 0.5], pos, vel, 10.0, steps=[(1.5, -1.0)])
    with pytest.raises(ArgumentError, match="grow"):
        ref.set_growth(0.1)
    # no steps: hard spheres, the counters of before
    assert set(Reference([1, 1], [0.5, 0.5], pos, vel, 10.0, steps=[]).counters) == {
        "collisions",
        "reflections",
        "crossings",
        "stale",
        "refreshed",
    }


def liquid(d, seed, eps=5.0, n=32):
    """``n`` spheres (sigma = 1) with a well of depth ``eps`` [kT] at 1.5 sigma in a periodic box, kT ~ 1."""
    rng = random.Random(seed)
    if d == 3:
        side, a = 5.0, 2.5  # f.c.c., 2 x 2 x 2 cells: neighbours at 1.77, outside the wells
        base = [(0, 0, 0), (0.5, 0.5, 0), (0.5, 0, 0.5), (0, 0.5, 0.5)]
        cells = [(x, y, z) for x in range(2) for y in range(2) for z in range(2)]
        pos = [[(c[ax] + b[ax]) * a - side / 2 + 0.1 for ax in range(3)] for c in cells for b in base]
        box = hs.PeriodicBox(side)
    else:
        side, a = 9.0, 1.5
        pos = [[(k % 6) * a - side / 2 + 0.1, (k // 6) * a - side / 2 + 0.1] for k in range(n)]
        box = hs.PeriodicBox((side, side))
    vel = [[rng.gauss(0, 1) for _ in range(d)] for _ in range(n)]
    mean = [sum(v[ax] for v in vel) / n for ax in range(d)]
    vel = [[v[ax] - mean[ax] for ax in range(d)] for v in vel]
    return Reference([1.0] * n, [0.5] * n, pos, vel, box, steps=[(1.5, -eps)])


@pytest.mark.parametrize("d", [2, 3])
def test_reference_deep_well_conserves_energy_without_a_bounce_loop(d):
    """eps = 5 kT, N = 32, 10^4 events: K + U constant to rounding, U = -eps * bonds exactly, no loop."""
    ref = liquid(d, seed=d)
    e0 = ref.kinetic_energy() + ref.potential_energy()
    scale = ref.kinetic_energy() + 5.0 * len(ref.masses)
    p0 = np.sum(np.asarray(ref.velocities), axis=0)
    ev = ref.advance(events=10_000)
    assert len(ev) == 10_000
    c = ref.counters
    assert min(c["captures"], c["releases"], c["bounces"], c["collisions"]) > 100
    assert ref.potential_energy() == -5.0 * len(ref.pair_states)
    assert len(ref.pair_states) > 10  # the well binds
    e1 = ref.kinetic_energy() + ref.potential_energy()
    assert abs(e1 - e0) <= 1e-12 * scale
    assert np.abs(np.sum(np.asarray(ref.velocities), axis=0) - p0).max() < 1e-12
    # no pair stays on an edge: each pair's consecutive events are apart in time
    pairs = ev[ev["j"] >= 0]
    for key in {(int(a), int(b)) for a, b in zip(pairs["i"], pairs["j"])}:
        times = pairs["time"][(pairs["i"] == key[0]) & (pairs["j"] == key[1])]
        assert np.all(np.diff(times) > 0.0)
    # no overlap of the cores, and every state matches the distances
    pos = np.asarray(ref.positions_at())
    side = np.asarray(ref.container.sides)
    for i in range(len(pos)):
        for j in range(i + 1, len(pos)):
            dr = pos[i] - pos[j]
            dr -= side * np.round(dr / side)
            dist = math.sqrt(float(dr @ dr))
            assert dist > 1.0 - 1e-9
            assert (dist < 1.5 + 1e-9) if (i, j) in ref.pair_states else (dist > 1.5 - 1e-9)


@pytest.mark.parametrize("d", [2, 3])
def test_reference_three_steps_with_a_shoulder(d):
    """A shoulder, then two wells: every state reached, K + U conserved, states matching the distances."""
    steps = [(1.6, 0.5), (1.3, -1.0), (1.1, -2.0)]
    base = liquid(d, seed=10 + d)
    ref = Reference(
        base.masses,
        [0.5] * len(base.masses),
        base.positions_at(),
        base.velocities,
        base.container,
        steps=steps,
    )
    e0 = ref.kinetic_energy() + ref.potential_energy()
    seen = set()
    for _ in range(30):
        ref.advance(events=100)
        seen |= set(ref.pair_states.values())
        counts = [list(ref.pair_states.values()).count(s) for s in (1, 2, 3)]
        assert ref.potential_energy() == 0.5 * counts[0] - 1.0 * counts[1] - 2.0 * counts[2]
    assert seen == {1, 2, 3}
    assert ref.counters["bounces"] > 0
    assert abs(ref.kinetic_energy() + ref.potential_energy() - e0) <= 1e-12 * (ref.kinetic_energy() + 100.0)
    pos = np.asarray(ref.positions_at())
    side = np.asarray(ref.container.sides)
    for (i, j), s in ref.pair_states.items():
        dr = pos[i] - pos[j]
        dr -= side * np.round(dr / side)
        dist = math.sqrt(float(dr @ dr))
        assert steps[s - 1][0] + 1e-9 > dist > (steps[s][0] if s < 3 else 1.0) - 1e-9

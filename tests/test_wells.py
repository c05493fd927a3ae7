"""Steps of the pair potential (square wells, shoulders): the kernels and the reference.

The kernels (:func:`~hardspheres.physics.cross_step`,
:func:`~hardspheres.physics.pair_time_out`) against exact rational
arithmetic and hand-derived cases; their conservation laws as properties,
in 2-D and 3-D (docs/numerics.md, "Steps: wells and shoulders").
"""

import math
from fractions import Fraction
from math import isqrt

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

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
    import random

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
    import random

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

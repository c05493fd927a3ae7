"""Cases with answers derived by hand, and event times against exact arithmetic.

Through the library (:class:`hardspheres.Simulation`), the physics kernels
(:mod:`hardspheres.physics`) and the assignment's program
(:func:`hardspheres.cli.run_spheres`, both engines).  The last part checks
``docs/numerics.md``'s claim that :func:`~hardspheres.physics.pair_time` and
:func:`~hardspheres.physics.wall_time` agree with exact rational arithmetic on
ill-conditioned inputs.
"""

import io
import json
import math
from fractions import Fraction
from math import isqrt

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import hardspheres as hs
from hardspheres.cli import run_spheres
from hardspheres.core.reference import SIMULTANEOUS
from hardspheres.physics import collide, pair_time, pair_time_grow, reflect, wall_time

ENGINES = pytest.mark.parametrize("engine", ["reference", "compiled"])


def sim(masses, radii, positions, velocities, container, window=0.0):
    return hs.Simulation.from_arrays(
        masses, radii, positions, velocities, hs.SphericalContainer(container), window=window
    )


def report(argv, text, monkeypatch, engine, fmt="text"):
    """The assignment's program in-process; text report or the JSONL events."""
    monkeypatch.setenv("HARDSPHERES_ENGINE", engine)
    out = io.StringIO()
    extra = ["--format", "jsonl"] if fmt == "jsonl" else []
    assert run_spheres(extra + [str(a) for a in argv], io.BytesIO(text.encode()), out) == 0
    if fmt == "jsonl":
        return [json.loads(x) for x in out.getvalue().splitlines()][1:]
    return out.getvalue()


def blocks(text):
    """Event blocks of a text report: ``[(time text, [lines])]``."""
    out = []
    for chunk in text.split("\ntime of event: ")[1:]:
        lines = chunk.rstrip("\n").split("\n")
        out.append((lines[0], lines[1:]))
    return out


# ---- collisions --------------------------------------------------------------------


def test_equal_masses_head_on_swap_velocities():
    """Gap 12 - 2 = 10 closing at 4: contact at t = 2.5, at x = 1.5 and 3.5."""
    assert pair_time(-12.0, 0.0, 0.0, 4.0, 0.0, 0.0, 2.0) == 2.5
    k1, k2 = collide(2.0, 2.0, -2.0, 0.0, 0.0, 4.0, 0.0, 0.0)
    assert (3.0 - k1 * -2.0, -1.0 + k2 * -2.0) == (-1.0, 3.0)

    s = sim([2.0, 2.0], [1.0, 1.0], [[-6, 0, 0], [6, 0, 0]], [[3, 0, 0], [-1, 0, 0]], 100.0)
    evs = list(s.iter_events(until=3.0))
    assert [(e.time, e.kind, e.i, e.j) for e in evs] == [(2.5, "collision", 0, 1)]
    assert evs[0].impulse == 8.0  # m |dv| = 2 * 4
    st_ = s.run(until=3.0).state()
    assert st_.velocities.tolist() == [[-1.0, 0.0, 0.0], [3.0, 0.0, 0.0]]
    assert st_.positions.tolist() == [[1.0, 0.0, 0.0], [5.0, 0.0, 0.0]]


@pytest.mark.parametrize(
    "m1,m2,v1,v2", [(2.0, 5.0, 3.0, -4.0), (1.0, 1e3, 1.0, 0.0), (1e3, 1.0, 0.5, -2.0), (3.0, 7.0, 0.0, -1.0)]
)
def test_unequal_masses_one_dimensional(m1, m2, v1, v2):
    """v1' = ((m1 - m2) v1 + 2 m2 v2)/(m1 + m2), v2' = ((m2 - m1) v2 + 2 m1 v1)/(m1 + m2)."""
    w1 = ((m1 - m2) * v1 + 2 * m2 * v2) / (m1 + m2)
    w2 = ((m2 - m1) * v2 + 2 * m1 * v1) / (m1 + m2)
    # radii 1 and 2, centres 14 apart: contact after 11 / (v1 - v2)
    s = sim([m1, m2], [1.0, 2.0], [[-10, 0, 0], [4, 0, 0]], [[v1, 0, 0], [v2, 0, 0]], 1e4)
    evs = list(s.iter_events(until=11.0 / (v1 - v2) * 1.5))
    assert len(evs) == 1 and evs[0].kind == "collision"
    assert evs[0].time == pytest.approx(11.0 / (v1 - v2), rel=1e-15)
    v = s.state().velocities
    assert v[:, 0].tolist() == pytest.approx([w1, w2], rel=1e-14, abs=1e-14)
    assert v[:, 1:].tolist() == [[0.0, 0.0], [0.0, 0.0]]
    assert evs[0].impulse == pytest.approx(m1 * abs(w1 - v1), rel=1e-14)
    if (m1, m2, v1, v2) == (2.0, 5.0, 3.0, -4.0):
        assert (w1, w2) == (-7.0, 0.0)


def test_equal_masses_oblique_leave_at_right_angles():
    """Impact parameter 1 with contact distance 2: line of centres at 30 degrees.

    Contact at x = -sqrt(3) (t = 10 - sqrt(3)), normal n = (sqrt(3), 1, 0)/2; the
    sphere at rest takes (v.n) n = (3/4, sqrt(3)/4, 0), the mover keeps
    (1/4, -sqrt(3)/4, 0).
    """
    s = sim([1.0, 1.0], [1.0, 1.0], [[-10, 0, 0], [0, 1, 0]], [[1, 0, 0], [0, 0, 0]], 100.0)
    evs = list(s.iter_events(until=9.0))
    assert len(evs) == 1 and evs[0].time == pytest.approx(10 - math.sqrt(3), rel=1e-15)
    v = s.state().velocities
    r3 = math.sqrt(3.0)
    np.testing.assert_allclose(v, [[0.25, -r3 / 4, 0], [0.75, r3 / 4, 0]], rtol=0, atol=1e-15)
    assert abs(v[0] @ v[1]) < 1e-15


# ---- walls -------------------------------------------------------------------------


def test_wall_chord_through_the_centre():
    """r = 1 in R = 11 (reach 10) from the origin at speed 5: walls at 2, 6, 10, ...

    Contact at p = (6, 8, 0), n = p / 10, v.n = 5: v' = v - 2 (v.n) n = (-3, -4, 0).
    """
    assert wall_time(0.0, 0.0, 0.0, 3.0, 4.0, 0.0, 10.0) == 2.0
    k = reflect(6.0, 8.0, 0.0, 3.0, 4.0, 0.0)
    assert (3.0 - k * 6.0, 4.0 - k * 8.0) == (-3.0, -4.0)
    assert wall_time(6.0, 8.0, 0.0, -3.0, -4.0, 0.0, 10.0) == 4.0  # a diameter

    s = sim([1.0], [1.0], [[0, 0, 0]], [[3, 4, 0]], 11.0)
    evs = [(e.time, e.kind, e.i) for e in s.iter_events(until=11.0)]
    assert evs == [(2.0, "reflection", 0), (6.0, "reflection", 0), (10.0, "reflection", 0)]
    st_ = s.state()  # at 11: one unit of time back along the last chord
    assert st_.positions.tolist() == [[3.0, 4.0, 0.0]]
    assert st_.velocities.tolist() == [[-3.0, -4.0, 0.0]]


def test_wall_chord_off_centre():
    """From (0, 6, 0) along x at speed 1, reach 10: the wall at (8, 6, 0) at t = 8.

    n = (0.8, 0.6, 0), v.n = 0.8: v' = (1, 0, 0) - 1.6 n = (-0.28, -0.96, 0).
    The angle with the wall is kept, so every later chord has the first
    chord's length, 2 * 8 = 16: walls at 8, 24, 40, ...
    """
    assert wall_time(0.0, 6.0, 0.0, 1.0, 0.0, 0.0, 10.0) == 8.0
    k = reflect(8.0, 6.0, 0.0, 1.0, 0.0, 0.0)
    assert 1.0 - k * 8.0 == pytest.approx(-0.28, abs=1e-16)
    assert 0.0 - k * 6.0 == pytest.approx(-0.96, abs=1e-16)

    s = sim([1.0], [1.0], [[0, 6, 0]], [[1, 0, 0]], 11.0)
    evs = list(s.iter_events(until=56.5))
    assert [e.time for e in evs] == pytest.approx([8.0, 24.0, 40.0, 56.0], rel=1e-14)
    assert all(e.kind == "reflection" for e in evs)
    # impulse on the sphere: 2 m (v.n) = 1.6 each time
    assert [e.impulse for e in evs] == pytest.approx([1.6] * 4, rel=1e-14)
    v = s.state().velocities[0]
    assert np.linalg.norm(v) == pytest.approx(1.0, rel=1e-15)
    p = s.state().positions[0] - 0.5 * v  # back to the last contact
    assert np.linalg.norm(p) == pytest.approx(10.0, rel=1e-14)


@ENGINES
def test_wall_chord_in_the_report(engine, monkeypatch):
    out = report([11, 11], "1 1 0 0 0 3 4 0 ball\n", monkeypatch, engine)
    assert blocks(out) == [
        (
            "2",
            ["reflecting ball", "ball m=1 R=1 p=(6,8,0) v=(-3,-4,0)", "energy: 12.5", "momentum: (-3,-4,0)"],
        ),
        ("6", ["reflecting ball", "ball m=1 R=1 p=(-6,-8,0) v=(3,4,0)", "energy: 12.5", "momentum: (3,4,0)"]),
        (
            "10",
            ["reflecting ball", "ball m=1 R=1 p=(6,8,0) v=(-3,-4,0)", "energy: 12.5", "momentum: (-3,-4,0)"],
        ),
    ]


# ---- Newton's cradle ---------------------------------------------------------------

CRADLE = "1 1 -5 0 0 1 0 0 a\n1 1 0 0 0 0 0 0 b\n1 1 2 0 0 0 0 0 c\n1 1 4 0 0 0 0 0 d\n"


@ENGINES
def test_newtons_cradle_in_the_report(engine, monkeypatch):
    """a hits the touching line b-c-d at t = 3: three collisions at that time.

    Each passes all the momentum on (equal masses, head on): at the end a, b,
    c rest and d moves off with a's velocity.
    """
    out = report([100, 10], CRADLE, monkeypatch, engine)
    got = blocks(out)
    assert [(t, lines[0]) for t, lines in got] == [
        ("3", "colliding a b"),
        ("3", "colliding b c"),
        ("3", "colliding c d"),
    ]
    assert got[-1][1][1:] == [
        "a m=1 R=1 p=(-2,0,0) v=(0,0,0)",
        "b m=1 R=1 p=(0,0,0) v=(0,0,0)",
        "c m=1 R=1 p=(2,0,0) v=(0,0,0)",
        "d m=1 R=1 p=(4,0,0) v=(1,0,0)",
        "energy: 0.5",
        "momentum: (1,0,0)",
    ]
    # the momentum moves down the line one sphere per event
    movers = [[ln.split()[0] for ln in lines[1:5] if not ln.endswith("v=(0,0,0)")] for _, lines in got]
    assert movers == [["b"], ["c"], ["d"]]


@pytest.mark.parametrize("window", [0.0, SIMULTANEOUS])
def test_newtons_cradle_in_the_library(window):
    s = sim(
        [1.0] * 4,
        [1.0] * 4,
        [[-5, 0, 0], [0, 0, 0], [2, 0, 0], [4, 0, 0]],
        [[1, 0, 0], [0, 0, 0], [0, 0, 0], [0, 0, 0]],
        100.0,
        window=window,
    )
    evs = [(e.time, e.kind, e.i, e.j) for e in s.iter_events(until=10.0)]
    assert evs == [(3.0, "collision", 0, 1), (3.0, "collision", 1, 2), (3.0, "collision", 2, 3)]
    assert s.state().velocities.tolist() == [[0, 0, 0], [0, 0, 0], [0, 0, 0], [1, 0, 0]]


@ENGINES
def test_newtons_cradle_with_gaps_inside_the_window(engine, monkeypatch):
    """Gaps of 3e-9 m at speed 1: each next contact is 3e-9 s later, inside 1e-8 s.

    The clock does not advance, so all three are reported at t = 3 exactly.
    """
    text = (
        f"1 1 -5 0 0 1 0 0 a\n1 1 0 0 0 0 0 0 b\n1 1 {2 + 3e-9!r} 0 0 0 0 0 c\n1 1 {4 + 6e-9!r} 0 0 0 0 0 d\n"
    )
    evs = report([100, 10], text, monkeypatch, engine, fmt="jsonl")
    assert [(e["time"], e["spheres"]) for e in evs] == [
        (3.0, ["a", "b"]),
        (3.0, ["b", "c"]),
        (3.0, ["c", "d"]),
    ]
    assert evs[-1]["v"] == [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]]


# ---- the 1e-8 s rule -----------------------------------------------------------------


def two_pairs(delta):
    """Pair a-b meets at t = 1; pair c-d (50 m away) at t = 1 + delta."""
    x = 2.0 + delta
    return f"1 1 -2 0 0 1 0 0 a\n1 1 2 0 0 -1 0 0 b\n1 1 {-x!r} 50 0 1 0 0 c\n1 1 {x!r} 50 0 -1 0 0 d\n"


@ENGINES
def test_events_within_the_window_are_simultaneous(engine, monkeypatch):
    evs = report([1000, 5], two_pairs(0.5e-8), monkeypatch, engine, fmt="jsonl")
    assert [(e["time"], e["spheres"]) for e in evs] == [(1.0, ["a", "b"]), (1.0, ["c", "d"])]
    # processed at the clock, a hair before contact: still exchanged exactly
    assert evs[1]["v"] == [[-1.0, 0.0, 0.0], [1.0, 0.0, 0.0]]
    text = report([1000, 5], two_pairs(0.5e-8), monkeypatch, engine)
    assert [t for t, _ in blocks(text)] == ["1", "1"]


@ENGINES
def test_events_beyond_the_window_are_separate(engine, monkeypatch):
    evs = report([1000, 5], two_pairs(2e-8), monkeypatch, engine, fmt="jsonl")
    assert [e["spheres"] for e in evs] == [["a", "b"], ["c", "d"]]
    assert evs[0]["time"] == 1.0
    assert abs(evs[1]["time"] - (1.0 + 2e-8)) < 1e-15


@ENGINES
def test_window_is_measured_from_the_clock(engine, monkeypatch):
    """Events at 1, 1 + 0.6e-8, 1 + 1.2e-8: the second joins the first (the
    clock stays at 1), the third is 1.2e-8 after the clock and is separate."""
    text = two_pairs(0.6e-8) + (f"1 1 {-(2 + 1.2e-8)!r} -50 0 1 0 0 e\n1 1 {2 + 1.2e-8!r} -50 0 -1 0 0 f\n")
    evs = report([1000, 5], text, monkeypatch, engine, fmt="jsonl")
    assert [e["spheres"] for e in evs] == [["a", "b"], ["c", "d"], ["e", "f"]]
    assert evs[0]["time"] == evs[1]["time"] == 1.0
    assert abs(evs[2]["time"] - (1.0 + 1.2e-8)) < 1e-15


@ENGINES
def test_simultaneous_reflection_goes_before_collision(engine, monkeypatch):
    """The pair (input first) and the reflection of c (input last) both at t = 1."""
    text = "1 1 -2 0 0 1 0 0 a\n1 1 2 0 0 -1 0 0 b\n1 1 0 0 50 0 0 1 c\n"
    out = report([52, 1.5], text, monkeypatch, engine)
    assert [(t, lines[0]) for t, lines in blocks(out)] == [("1", "reflecting c"), ("1", "colliding a b")]


# ---- event times against exact rational arithmetic -------------------------------------
#
# pair_time and wall_time receive floats; the quadratic's coefficients
# a = |dv|^2, b = dr.dv, c = |dr|^2 - sigma^2 are rounded before any root is
# taken, and for ill-conditioned inputs that rounding alone can move the root
# by many ulps whatever the formula.  So the inputs here are small integers
# (|x| < 2^11) times powers of two, for which every coefficient and b^2 - ac
# are exact in doubles: what is left is the root formula, which must be within
# 2 ulps of the exact root.  The same inputs through the textbook formula
# (-b -+ sqrt(b^2 - ac)) / a lose up to millions of ulps, so the tests can fail.


def _sqrt(q, bits=200):
    """sqrt of a Fraction to ``bits`` bits (relative), as a Fraction."""
    if q == 0:
        return Fraction(0)
    p, d = q.numerator, q.denominator
    k = max(0, bits - (p.bit_length() - d.bit_length()) // 2)
    return Fraction(isqrt(p * d << (2 * k)), d << k)


def exact_pair_time(dx, dy, dz, dvx, dvy, dvz, sigma):
    d = [Fraction(x) for x in (dx, dy, dz)]
    w = [Fraction(x) for x in (dvx, dvy, dvz)]
    b = sum(x * y for x, y in zip(d, w))
    if b >= 0:
        return math.inf
    c = sum(x * x for x in d) - Fraction(sigma) ** 2
    if c <= 0:
        return Fraction(0)
    a = sum(x * x for x in w)
    disc = b * b - a * c
    if disc <= 0:
        return math.inf
    return (-b - _sqrt(disc)) / a


def exact_wall_time(px, py, pz, vx, vy, vz, reach):
    p = [Fraction(x) for x in (px, py, pz)]
    v = [Fraction(x) for x in (vx, vy, vz)]
    a = sum(x * x for x in v)
    b = sum(x * y for x, y in zip(p, v))
    c = sum(x * x for x in p) - Fraction(reach) ** 2
    assert c <= 0 and a > 0  # inside, moving
    return (-b + _sqrt(b * b - a * c)) / a


def ulps(got, exact):
    """Distance of float ``got`` from the exact value, in ulps of the exact value."""
    if exact == math.inf or got == math.inf:
        return 0 if got == exact else math.inf
    if exact == 0:
        return 0 if got == 0 else math.inf
    return float(abs(Fraction(got) - exact) / Fraction(math.ulp(float(exact))))


def naive_pair_time(dx, dy, dz, dvx, dvy, dvz, sigma):
    a = dvx * dvx + dvy * dvy + dvz * dvz
    b = dx * dvx + dy * dvy + dz * dvz
    c = dx * dx + dy * dy + dz * dz - sigma * sigma
    return (-b - math.sqrt(b * b - a * c)) / a


def naive_wall_time(px, py, pz, vx, vy, vz, reach):
    a = vx * vx + vy * vy + vz * vz
    b = px * vx + py * vy + pz * vz
    c = px * px + py * py + pz * pz - reach * reach
    return (-b + math.sqrt(b * b - a * c)) / a


def scaled(args, length, speed):
    """Lengths times ``length``, speeds times ``speed`` (powers of two: exact)."""
    (x, y, z, u, v, w, s) = args
    return (x * length, y * length, z * length, u * speed, v * speed, w * speed, s * length)


PAIR_CASES = {
    # nearly touching (|dr|^2 - sigma^2 = 1) and approaching fast, obliquely:
    # the textbook smaller root cancels catastrophically
    "nearly-touching": (-2000.0, -1.0, 0.0, 3.0, 7.0, 0.0, 2000.0),
    "touching-gap-1": (-2040.0, 0.0, -1.0, 1789.0, 1.0, 5.0, 2040.0),
    # nearly grazing: impact parameter 2047 with contact distance 2048
    "nearly-grazing": (-2000.0, 2047.0, 0.0, 1.0, 0.0, 0.0, 2048.0),
    "grazing-oblique": (-1500.0, 1100.0, 1001.0, 3.0, -1.0, 0.0, 1999.0),
    # far away (1e3 contact distances) and fast (2e3 distances per unit time)
    "far-and-fast": (-2047.0, 1.0, -1.0, 2047.0, 0.0, 1.0, 2.0),
    "slow-and-near": (-3.0, 1.0, 0.0, 1.0, 0.0, 0.0, 2.0),
}

SCALES = [
    (1.0, 1.0),
    (2.0**60, 1.0),
    (2.0**-60, 1.0),
    (2.0**150, 2.0**140),
    (2.0**-150, 2.0**-160),
    (2.0**23, 2.0**-10),
    (2.0**-33, 2.0**10),
    # speeds whose squares underflow (|v|^2 < 1e-200 is solved rescaled)
    (1.0, 2.0**-400),
    (2.0**-10, 2.0**-600),
    (2.0**20, 2.0**-900),
]


@pytest.mark.parametrize("scale", SCALES, ids=lambda s: f"{s[0]:.0e}/{s[1]:.0e}")
@pytest.mark.parametrize("name", list(PAIR_CASES))
def test_pair_time_against_exact_roots(name, scale):
    args = scaled(PAIR_CASES[name], *scale)
    exact = exact_pair_time(*args)
    assert 0 < exact < math.inf
    assert ulps(pair_time(*args), exact) <= 2.0


@pytest.mark.parametrize("scale", SCALES, ids=lambda s: f"{s[0]:.0e}/{s[1]:.0e}")
@pytest.mark.parametrize("name", list(PAIR_CASES))
def test_growing_pair_time_without_growth_against_exact_roots(name, scale):
    """pair_time_grow at growth 0 solves pair_time's quadratic, at every scale.

    (Speeds whose squares underflow were taken for spheres at rest before.)
    """
    dx, dy, dz, dvx, dvy, dvz, sigma = scaled(PAIR_CASES[name], *scale)
    exact = exact_pair_time(dx, dy, dz, dvx, dvy, dvz, sigma)
    got = pair_time_grow(dx, dy, dz, dvx, dvy, dvz, sigma, 0.0, math.inf)
    assert ulps(got, exact) <= 4.0


def test_pair_time_cases_are_nasty_for_the_textbook_formula():
    """The cancelling cases really cancel: the textbook root is far off."""
    for name in ("nearly-touching", "touching-gap-1"):
        args = PAIR_CASES[name]
        assert ulps(naive_pair_time(*args), exact_pair_time(*args)) > 1e4, name


WALL_CASES = {
    # at 1 length unit from the wall, moving out fast: textbook root cancels
    # (|p|^2 = reach^2 - 1)
    "near-wall-outward": (1989.0, 63.0, 3.0, 2047.0, 5.0, -3.0, 1990.0),
    "near-wall-outward-oblique": (1988.0, 100.0, 44.0, 1000.0, 1001.0, 7.0, 1991.0),
    # moving in from near the wall: a whole chord
    "near-wall-inward": (1999.0, 0.0, 1.0, -2047.0, 3.0, 0.0, 2000.0),
    "on-wall-inward": (1200.0, 1600.0, 0.0, -5.0, 1.0, 0.0, 2000.0),
    # nearly tangent to the wall, just inside it
    "tangent": (0.0, 1999.0, 0.0, 1.0, 0.0, 0.0, 2000.0),
    "tangent-oblique": (3.0, 1999.0, 0.0, 2047.0, -1.0, 0.0, 2000.0),
    "from-centre": (0.0, 0.0, 0.0, 3.0, 4.0, 12.0, 2047.0),
    "off-centre": (5.0, -7.0, 11.0, -1.0, 2.0, 2.0, 20.0),
}


@pytest.mark.parametrize("scale", SCALES, ids=lambda s: f"{s[0]:.0e}/{s[1]:.0e}")
@pytest.mark.parametrize("name", list(WALL_CASES))
def test_wall_time_against_exact_roots(name, scale):
    args = scaled(WALL_CASES[name], *scale)
    exact = exact_wall_time(*args)
    assert ulps(wall_time(*args), exact) <= 2.0


def test_wall_time_cases_are_nasty_for_the_textbook_formula():
    for name in ("near-wall-outward", "near-wall-outward-oblique"):
        args = WALL_CASES[name]
        assert ulps(naive_wall_time(*args), exact_wall_time(*args)) > 1e4, name


small = st.integers(-2047, 2047)
power = st.integers(-120, 120)
speed_power = st.integers(-1000, 120)  # down to speeds whose squares underflow


@settings(max_examples=300, deadline=None)
@given(
    d=st.tuples(small, small, small),
    w=st.tuples(small, small, small),
    sigma=st.integers(0, 2047),
    k=power,
    m=speed_power,
)
def test_pair_time_exact_for_any_exact_coefficients(d, w, sigma, k, m):
    k = min(k, m + 900)  # times stay below the largest double
    args = scaled((*map(float, d), *map(float, w), float(sigma)), 2.0**k, 2.0**m)
    exact = exact_pair_time(*args)
    got = pair_time(*args)
    assert ulps(got, exact) <= 2.0, (args, got, float(exact) if exact != math.inf else exact)


@settings(max_examples=300, deadline=None)
@given(
    p=st.tuples(small, small, small),
    w=st.tuples(small, small, small),
    extra=st.integers(0, 2047),
    k=power,
    m=speed_power,
)
def test_wall_time_exact_for_any_exact_coefficients(p, w, extra, k, m):
    k = min(k, m + 900)
    if w == (0, 0, 0):
        assert wall_time(*map(float, p), 0.0, 0.0, 0.0, 1.0) == math.inf
        return
    n = sum(x * x for x in p)
    reach = math.isqrt(n) + extra
    if reach * reach < n:
        reach += 1  # inside or on the wall
    args = scaled((*map(float, p), *map(float, w), float(reach)), 2.0**k, 2.0**m)
    exact = exact_wall_time(*args)
    got = wall_time(*args)
    assert ulps(got, exact) <= 2.0, (args, got, float(exact))


# ---- regressions ------------------------------------------------------------------------


@ENGINES
@pytest.mark.parametrize("speed", ["1e-100", "1e-170", "1e-300"])
def test_tiny_outward_speed_at_the_wall_reflects_now(engine, speed, monkeypatch):
    """Touching the wall and moving out: a reflection at t = 0, however slow.

    (|v|^2 underflowed to 0 below ~1e-162 m/s and wall_time said "never".)
    """
    out = report([10, 1], f"1 1 9 0 0 {speed} 0 0 a\n", monkeypatch, engine)
    assert blocks(out) == [
        (
            "0",
            [
                "reflecting a",
                f"a m=1 R=1 p=(9,0,0) v=(-{speed},0,0)",
                blocks(out)[0][1][2],
                f"momentum: (-{speed},0,0)",
            ],
        )
    ]


def test_tiny_speeds_keep_spheres_in_and_apart():
    """At 1e-215 m/s events are ~1e215 s apart, but they still happen."""
    v = 1.2558692501600596e-215
    assert wall_time(0.0, -0.377, -0.377, v, v, 0.0, 0.8) == pytest.approx(
        float(exact_wall_time(0.0, -0.377, -0.377, v, v, 0.0, 0.8)), rel=1e-15
    )
    assert pair_time(-3.0, 0.0, 0.0, 1e-250, 0.0, 0.0, 2.0) == pytest.approx(1e250, rel=1e-15)
    s = sim(
        [1.0, 1.0], [0.2, 0.2], [[0.0, -0.4, -0.4], [0.5, 0.1, -0.4]], [[v, v, 0.0], [0.0, 0.0, 0.0]], 1.0
    )
    evs = list(s.iter_events(events=6))
    assert len(evs) == 6 and evs[0].kind == "collision"
    eng = s.engine
    assert eng.outside() == 0 and eng.max_overlap() <= 1e-9


def test_engine_breaks_exact_ties_in_tie_order():
    """Sphere 0 is hit from the side and meets two touching neighbours at once.

    Its root with sphere 2 (gap 2e-15) is positive but rounds to the same
    time as its root with sphere 3 (gap 0): a tie, so (0, 2) goes first, as
    in the reference.  The engine used to prune (0, 2) as "surely later".
    """
    from hardspheres.core.engine import Engine
    from hardspheres.core.reference import Reference

    r = 5.902408432445262
    a, b = 11.804816864890526, 11.804816864890523
    pos = [[0.0, a, 0.0], [0.0, -b, -b], [0.0, a, a], [0.0, 0.0, 0.0], [0.0, 0.0, -b], [a, -b, -b]]
    vel = [[0.0, 0.0, 0.0]] * 5 + [[0.0, 31.295728444953568, 0.0]]
    R = 31.295728444953568
    for window in (0.0, SIMULTANEOUS):
        runs = [
            engine([1.0] * 6, [r] * 6, pos, vel, container=R, window=window, rebase=False).advance(events=8)
            for engine in (Reference, Engine)
        ]
        want, got = (
            list(zip(ev["time"].tolist(), ev["kind"].tolist(), ev["i"].tolist(), ev["j"].tolist()))
            for ev in runs
        )
        assert got == want
        assert [e[2:] for e in got[1:4]] == [(0, 5), (0, 2), (0, 3)]
        assert got[1][0] == got[2][0] == got[3][0]

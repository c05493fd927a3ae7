"""Faults of the numerics (issue 9, items 7-10): hangs, a cliff, overflow, cancellation.

Each test failed before its fix: a run that never ended (checked in a
subprocess with a time limit, so that the old code fails instead of
hanging the suite), an event missed or a sphere escaping, or a count of
predictions proportional to the number of spheres.  Roots are compared
with exact rational arithmetic (as in ``test_analytic.py``).
"""

import importlib.util
import io
import json
import math
import random
import subprocess
import sys
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest
from helpers import spheres_cmd
from hypothesis import example, given, settings
from hypothesis import strategies as st

import hardspheres as hs
from hardspheres import physics
from hardspheres.cli import run_spheres
from hardspheres.core import reference
from hardspheres.core.engine import Engine
from hardspheres.physics import pair_time, pair_time_within, wall_time
from hardspheres.scenario import (
    ScenarioError,
    StuckError,
    check_scenario,
    parse_scenario,
)

ROOT = Path(__file__).resolve().parent.parent


def _sibling(name):
    """A sibling test module (pytest runs with --import-mode=importlib)."""
    spec = importlib.util.spec_from_file_location(f"_{name}", Path(__file__).with_name(f"{name}.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


# exact rational roots and the compiled brute-force loop
_analytic = _sibling("test_analytic")
exact_pair_time, exact_wall_time, ulps = (
    _analytic.exact_pair_time,
    _analytic.exact_wall_time,
    _analytic.ulps,
)
_test_engine = _sibling("test_engine")
CompiledReference, same_events = _test_engine.CompiledReference, _test_engine.same_events
ENGINES = pytest.mark.parametrize("engine", ["reference", "compiled"])


def spheres(argv, text, engine, monkeypatch, fmt="jsonl"):
    """``spheres`` in-process: ``(status, events, stderr text)``."""
    monkeypatch.setenv("HARDSPHERES_ENGINE", engine)
    out, err = io.StringIO(), io.StringIO()
    monkeypatch.setattr(sys, "stderr", err)
    extra = ["--format", "jsonl"] if fmt == "jsonl" else []
    status = run_spheres(extra + [str(a) for a in argv], io.BytesIO(text.encode()), out)
    lines = out.getvalue().splitlines()
    return status, [json.loads(x) for x in lines[1:]] if fmt == "jsonl" else lines, err.getvalue()


def ends(code, timeout=60):
    """Run ``code`` in a fresh interpreter; its result, or fail if it does not end."""
    try:
        done = subprocess.run(
            [sys.executable, "-c", code], capture_output=True, text=True, timeout=timeout, cwd=ROOT
        )
    except subprocess.TimeoutExpired:
        pytest.fail(f"did not end within {timeout} s")
    return done


# ---- 7: nothing repeats forever -------------------------------------------------------

TANGENT = "100 10 0 0 100 1 0 0 tangent\n"


def test_sphere_moving_along_the_wall_is_refused_in_one_line():
    """The hook's case: it printed ``reflecting tangent`` at t = 0 forever."""
    done = spheres_cmd("110", "50", input=TANGENT)
    assert done.returncode == 1
    err = done.stderr.strip().splitlines()
    assert len(err) == 1 and "line 1" in err[0] and "'tangent'" in err[0]
    assert "along" in err[0] and "Traceback" not in done.stderr


def test_tangent_sphere_inside_or_moving_off_the_wall_is_accepted():
    """Only exactly along the wall at contact is refused."""
    check_scenario(parse_scenario("100 10 0 0 99 1 0 0 inside\n"), 110.0)
    check_scenario(parse_scenario("100 10 0 0 100 1 0 -0.001 inward\n"), 110.0)
    check_scenario(parse_scenario("100 10 0 0 100 1 0 0.001 outward\n"), 110.0)
    check_scenario(parse_scenario("100 10 0 0 100 0 0 0 resting\n"), 110.0)
    with pytest.raises(ScenarioError, match="moves along it"):
        check_scenario(parse_scenario(TANGENT), 110.0)


@ENGINES
def test_sliding_sphere_stops_the_run_in_both_engines(engine):
    """Past the input check (library use), the run stops instead of looping."""
    p, v = [[0.0, 0.0, 100.0]], [[1.0, 0.0, 0.0]]
    cls = reference.Reference if engine == "reference" else Engine
    with pytest.raises(StuckError, match="moves along it") as e:
        cls([100.0], [10.0], p, v, container=110.0, window=1e-8).advance(until=50.0)
    assert (e.value.reason, e.value.time, e.value.sphere) == ("sliding", 0.0, 0)
    assert isinstance(e.value, ValueError)


def galperin(mass_ratio):
    """A light sphere touching the wall, a heavy one touching it and pushing.

    Along a diameter this is Galperin's billiard: a mass ratio of 100^k gives
    the first k + 1 digits of pi as the number of events, all at t = 0 here.
    """
    return f"1 1 9 0 0 0 0 0 light\n{mass_ratio!r} 4 4 0 0 1 0 0 heavy\n"


@ENGINES
@pytest.mark.parametrize("ratio,count", [(1.0, 3), (100.0, 31), (1e4, 314)])
def test_galperin_cascade_at_one_instant_counts_pi(engine, ratio, count, monkeypatch):
    """A genuine cascade at one instant runs to its end (the limit is far)."""
    status, events, _ = spheres([10, 1], galperin(ratio), engine, monkeypatch)
    assert status == 0
    assert len(events) == count and {e["time"] for e in events} == {0.0}


@ENGINES
def test_light_sphere_trapped_by_a_heavy_one_stops_with_a_frozen_clock(engine, monkeypatch):
    """Mass ratio 1e200: ~1e100 events at t = 0.  Before: no end (8 CPU-minutes+)."""
    text = "1e-100 1 9 0 0 0 0 0 light\n1e100 4 4 0 0 1 0 0 heavy\n"
    status, events, err = spheres([10, 1], text, engine, monkeypatch)
    assert status == 1
    assert len(events) == physics.frozen_limit(2)
    assert err.count("\n") == 1 and "clock is stuck at t = 0" in err and "'light'" in err


@pytest.mark.parametrize("window,gap", [(1e-8, 1e-9), (1e-8, 1e-3), (1e-8, 1.0), (0.0, 1.0)])
def test_frozen_clock_with_gaps_stops_the_library_run(window, gap):
    """With gaps the clock first creeps, then freezes; the library raises.

    (Within the window the light sphere is soon stuck at one instant; with
    exact times it takes 3.7 million collisions for the clock to stall.)"""
    sim = hs.Simulation.from_arrays(
        [1e-100, 1e100],
        [1.0, 4.0],
        [[9.0 - gap, 0, 0], [4.0 - 2 * gap, 0, 0]],
        [[0, 0, 0], [1.0, 0, 0]],
        hs.SphericalContainer(10.0),
        window=window,
    )
    with pytest.raises(StuckError, match="clock is stuck") as e:
        sim.run(until=10.0)
    assert e.value.reason == "frozen" and e.value.time < 2.0 * gap + 1e-8


def test_nan_until_returns():
    """``until=nan`` ran forever (the core never found an event past it)."""
    done = ends(
        "import hardspheres as hs, numpy as np\n"
        "s = hs.Simulation.from_arrays([1, 1], [1, 1], [[-5, 0, 0], [5, 0, 0]],"
        " [[1, 0, 0], [-1, 0, 0]], hs.SphericalContainer(20.0))\n"
        "try:\n    s.run(until=float('nan'))\nexcept ValueError as e:\n"
        "    print('refused', e)\n"
        "from hardspheres.core import _core\n"
        "e = s._engine\n"
        "print(_core.run(e.arrays, np.nan, 10**9, 10**9, e._event_buffers, True, (), ()))\n"
    )
    assert done.returncode == 0, done.stderr
    refused, core_returns = done.stdout.splitlines()
    assert refused.startswith("refused") and "NaN" in refused.replace("nan", "NaN")
    assert core_returns == "(0, 0)"


# ---- 8: an event re-predicts only what it touched ---------------------------------------


def touching_lattice(k, seed=0):
    """``k^3`` spheres of radius 0.5 exactly touching on a simple cubic lattice."""
    rng = np.random.default_rng(seed)
    g = np.arange(k) - (k - 1) / 2.0
    pos = np.array(np.meshgrid(g, g, g, indexing="ij")).reshape(3, -1).T.copy()
    vel = np.round(rng.uniform(-1, 1, pos.shape), 3)
    return np.ones(len(pos)), np.full(len(pos), 0.5), pos, vel


def test_touching_lattice_refreshes_no_sphere_per_event():
    """All 1000 spheres sit in the window at t = 0; an event there predicted all
    of them again (65 ms per event at 10^5 spheres).  Now: only those touched."""
    m, r, p, v = touching_lattice(10)
    eng = Engine(m, r, p, v, container=20.0, window=1e-8, rebase=False)
    ev = eng.advance(events=2000)
    assert len(ev["time"]) == 2000 and np.all(ev["time"] == 0.0)
    assert eng.counters["refreshed"] == 0


@pytest.mark.parametrize("k,seed", [(3, 1), (4, 2), (5, 3)])
def test_touching_lattice_same_events_as_brute_force(k, seed):
    """The cascade at t = 0 and what follows, event for event, bit for bit."""
    m, r, p, v = touching_lattice(k, seed)
    n_events = 600
    want = CompiledReference(m, r, p, v, container=8.0, window=1e-8).advance(events=n_events)
    eng = Engine(m, r, p, v, container=8.0, window=1e-8, rebase=False)
    assert same_events(eng.advance(events=n_events), want)
    assert np.sum(want["time"] == 0.0) > k**3 // 2  # a real cascade at t = 0


def test_touching_lattice_jsonl_same_from_both_engines(monkeypatch):
    pos, vel = (a.tolist() for a in touching_lattice(3, 4)[2:])
    text = "".join(
        f"1 0.5 {x!r} {y!r} {z!r} {a!r} {b!r} {c!r} s{i}\n"
        for i, ((x, y, z), (a, b, c)) in enumerate(zip(pos, vel))
    )
    got = {e: spheres([4, 2], text, e, monkeypatch) for e in ("reference", "compiled")}
    assert got["reference"][0] == 0 and len(got["reference"][1]) > 27
    assert got["reference"] == got["compiled"]


# ---- 9: no overflow inside the accepted range --------------------------------------------


@ENGINES
def test_fast_sphere_in_a_huge_container_reflects(engine, monkeypatch):
    """|v| |p| ~ 1e160: b^2 overflowed and the sphere flew out to x = 1e101."""
    status, events, _ = spheres(["1e100", "1e41"], "1 1 0 0 0 1e60 0 0 a\n", engine, monkeypatch)
    assert status == 0
    times = [e["time"] for e in events]
    want = [(1e100 - 1) / 1e60 * (2 * k + 1) for k in range(5)]
    assert times == pytest.approx(want, rel=1e-14)
    assert all(abs(e["p"][0][0]) == pytest.approx(1e100 - 1, rel=1e-14) for e in events)


@ENGINES
def test_huge_spheres_collide(engine, monkeypatch):
    """Radius 1e99 at -+5e99 moving at 1e99 toward each other: contact at t = 4."""
    text = "1 1e99 -5e99 0 0 1e99 0 0 a\n1 1e99 5e99 0 0 -1e99 0 0 b\n"
    status, events, _ = spheres(["1e100", "10"], text, engine, monkeypatch)
    assert status == 0 and events[0]["kind"] == "collision"
    assert events[0]["time"] == 4.0
    assert np.allclose(events[0]["p"], [[-1e99, 0, 0], [1e99, 0, 0]], rtol=1e-15, atol=0)


@ENGINES
def test_far_apart_and_slow_still_meet(engine, monkeypatch):
    """Lengths 1e100, speed 1e-101: the old 2^600 rescaling of tiny speeds overflowed."""
    text = "1 1e99 -5e99 0 0 1e-101 0 0 a\n1 1e99 5e99 0 0 -1e-101 0 0 b\n"
    status, events, _ = spheres(["1e100", "1e201"], text, engine, monkeypatch)
    assert status == 0 and events[0]["kind"] == "collision"
    assert events[0]["time"] == pytest.approx(4e200, rel=1e-15)


edge = st.integers(-2047, 2047)


@settings(max_examples=300, deadline=None)
@given(
    d=st.tuples(edge, edge, edge),
    w=st.tuples(edge, edge, edge),
    sigma=st.integers(0, 2047),
    k=st.integers(-340, 330),
    m=st.integers(-1000, 330),
)
# |dv|^2 subnormal (2^-1058), |dr|^2 large: in RANGE_LO..RANGE_HI, 4.8e7 ulps off (issue 29)
@example(d=(-2000, 3, 0), w=(449, 0, 0), sigma=7, k=197, m=-538)
def test_pair_time_exact_over_the_whole_accepted_range(d, w, sigma, k, m):
    """Lengths 2^-340..2^341 (past 1e-100..1e100), speeds 2^-1000..2^341."""
    k = max(min(k, m + 1000), m - 1000)  # times stay normal doubles
    L, V = 2.0**k, 2.0**m
    args = (*(x * L for x in d), *(x * V for x in w), sigma * L)
    exact = exact_pair_time(*args)
    assert ulps(pair_time(*args), exact) <= 2.0


@settings(max_examples=300, deadline=None)
@given(
    p=st.tuples(edge, edge, edge),
    w=st.tuples(edge, edge, edge),
    extra=st.integers(0, 2047),
    k=st.integers(-340, 330),
    m=st.integers(-1000, 330),
)
# hypothesis seed 9 (issue 29): |v|^2 subnormal, 1.3e10 ulps off
@example(p=(0, 0, 0), w=(0, 0, 449), extra=1, k=197, m=-538)
def test_wall_time_exact_over_the_whole_accepted_range(p, w, extra, k, m):
    if w == (0, 0, 0):
        return
    k = max(min(k, m + 1000), m - 1000)
    n = sum(x * x for x in p)
    reach = math.isqrt(n) + extra
    if reach * reach < n:
        reach += 1
    L, V = 2.0**k, 2.0**m
    args = (*(x * L for x in p), *(x * V for x in w), reach * L)
    assert ulps(wall_time(*args), exact_wall_time(*args)) <= 2.0


@pytest.mark.parametrize("m", range(-575, -505, 3))
def test_subnormal_squared_speeds_solve_exactly(m):
    """|v|^2 from 2^-1150 (zero) through the subnormals to 2^-1010, lengths
    large enough that |v|^2 |p|^2 is inside RANGE_LO..RANGE_HI: the product
    alone let a subnormal |v|^2 through, with as few as 10 significant bits
    (issue 29).  Both roots within 2 ulps of the exact ones."""
    V = 2.0**m
    for k in range(-340, 331, 23):
        L = 2.0**k
        wall = (3 * L, -5 * L, 0.0, 449 * V, 7 * V, -3 * V, 1001 * L)
        assert ulps(wall_time(*wall), exact_wall_time(*wall)) <= 2.0, (m, k)
        pair = (-2000 * L, 3 * L, -2 * L, 449 * V, 0.0, 1 * V, 7 * L)
        assert ulps(pair_time(*pair), exact_pair_time(*pair)) <= 2.0, (m, k)


@ENGINES
def test_subnormal_squared_speed_reflects_on_time_from_spheres(engine, monkeypatch):
    """The issue's accepted input: 4.02533e+218 printed where the exact time
    is 4.02532e+218 (|v|^2 = 2.5e-319 is subnormal)."""
    reach, speed = 2.008672555323738e59, 4.990093392593999e-160
    text = f"1 0 0 0 0 0 0 {speed!r} a\n"
    status, events, _ = spheres([reach, 5e218], text, engine, monkeypatch)
    assert status == 0 and [e["kind"] for e in events] == ["reflection"]
    exact = Fraction(reach) / Fraction(speed)
    assert ulps(events[0]["time"], exact) <= 1.0
    status, lines, _ = spheres([reach, 5e218], text, engine, monkeypatch, fmt="text")
    assert "time of event: 4.02532e+218" in lines


@ENGINES
def test_subnormal_squared_relative_speed_collides_on_time(engine, monkeypatch):
    """The same for a grazing pair: 451 2^-539 m/s across 2000 2^197 m, offset
    3.4 of 3.5.  |dv|^2 rounds up by 2e-6 of itself, and the compiled core's
    branch-free pre-test took the pair for a sure miss."""
    L, V = 2.0**197, 2.0**-539
    text = f"1 {1.75 * L!r} {-2000 * L!r} 0 0 {451 * V!r} 0 0 a\n1 {1.75 * L!r} 0 {3.4 * L!r} 0 0 0 0 b\n"
    status, events, _ = spheres([1e64, 1e223], text, engine, monkeypatch)
    assert status == 0 and events and events[0]["kind"] == "collision"
    exact = exact_pair_time(-2000 * L, -3.4 * L, 0.0, 451 * V, 0.0, 0.0, 3.5 * L)
    assert ulps(events[0]["time"], exact) <= 2.0


# ---- 10: no cancellation when the contact distance is small -------------------------------


def _unit(rng):
    v = [rng.gauss(0.0, 1.0) for _ in range(3)]
    n = math.sqrt(sum(x * x for x in v))
    return [x / n for x in v]


@pytest.mark.parametrize("ratio", [10.0**-e for e in range(1, 13)])
def test_pair_time_exact_for_small_contact_distances(ratio):
    """Contact distance / separation from 1e-1 to 1e-12, impact parameter up to
    0.9 contact distances, arbitrary floats: within 4 ulps of the exact root.
    With b^2 - a c: 600 ulps at 1e-2, 6e6 at 1e-6, "never" below 1e-8."""
    rng = random.Random(int(-math.log10(ratio)))
    for _ in range(100):
        e, q = _unit(rng), _unit(rng)
        dot = sum(x * y for x, y in zip(e, q))
        q = [y - dot * x for x, y in zip(e, q)]
        qn = math.sqrt(sum(y * y for y in q))
        sigma = ratio * rng.uniform(0.5, 1.0)
        imp = rng.uniform(0.0, 0.9) * sigma
        dr = [-x + imp * y / qn for x, y in zip(e, q)]
        speed = rng.uniform(0.1, 10.0)
        dv = [speed * x for x in e]
        args = (*dr, *dv, sigma)
        exact = exact_pair_time(*args)
        assert 0 < exact < math.inf
        assert ulps(pair_time(*args), exact) <= 4.0, args


@ENGINES
@pytest.mark.parametrize("radius", ["1e-10", "1e-13"])
def test_small_spheres_far_apart_collide_head_on(engine, radius, monkeypatch):
    """The issue's case (radius 1e-10 at distance 1): the collision was missed."""
    text = f"1 {radius} -0.5 0 0 1 0 0 a\n1 {radius} 0.5 0 0 -1 0 0 b\n"
    status, events, _ = spheres([1, 1], text, engine, monkeypatch)
    assert status == 0 and [e["kind"] for e in events] == ["collision"]
    r = float(radius)
    assert events[0]["time"] == pytest.approx(0.5 - r, rel=1e-15)


def test_compiled_core_does_not_drop_what_the_kernel_finds():
    """The core's branch-free pre-test must reject no pair the kernel accepts:
    many small spheres far apart, against the brute-force loop."""
    rng = np.random.default_rng(5)
    n = 60
    pos = rng.uniform(-40.0, 40.0, (n, 3))
    vel = rng.normal(size=(n, 3))
    rad = np.full(n, 1e-9)
    want = CompiledReference(np.ones(n), rad, pos, vel, container=100.0).advance(events=300)
    eng = Engine(np.ones(n), rad, pos, vel, container=100.0, rebase=False)
    assert same_events(eng.advance(events=300), want)


@settings(max_examples=500, deadline=None)
@given(
    st.lists(st.floats(-1e3, 1e3, allow_subnormal=False), min_size=6, max_size=6),
    st.floats(1e-6, 1e3),
    st.integers(-30, 30),
)
def test_miss_margin_covers_both_discriminants(x, sigma, shift):
    """What the core rejects as a miss (b^2 - a c below -MISS_MARGIN |dv|^2 |dr|^2),
    the kernel finds to miss too, in either form of the discriminant."""
    dx, dy, dz, dvx, dvy, dvz = x
    dx, dy, dz = (math.ldexp(c, shift) for c in (dx, dy, dz))
    b = dx * dvx + dy * dvy + dz * dvz
    a = dvx * dvx + dvy * dvy + dvz * dvz
    r2 = dx * dx + dy * dy + dz * dz
    c = r2 - sigma * sigma
    if b < 0.0 and c > 0.0 and b * b - a * c < -physics.MISS_MARGIN * (a * r2):
        assert pair_time(dx, dy, dz, dvx, dvy, dvz, sigma) == math.inf
        d = [Fraction(t) for t in (dx, dy, dz)]
        w = [Fraction(t) for t in (dvx, dvy, dvz)]
        exact = sum(p * q for p, q in zip(d, w)) ** 2 - sum(q * q for q in w) * (
            sum(p * p for p in d) - Fraction(sigma) ** 2
        )
        assert exact < 0


# ---- issue 10, item 3: one body for both pair predictions ---------------------------------


@settings(max_examples=300, deadline=None)
@given(st.lists(st.floats(-1e6, 1e6), min_size=6, max_size=6), st.floats(0.0, 1e3))
def test_pair_time_is_pair_time_within_without_horizon(x, sigma):
    assert pair_time(*x, sigma) == pair_time_within(*x, sigma, math.inf) or math.isnan(pair_time(*x, sigma))


_OLD = {
    "masses": "mass",
    "spheres": "S",
    "book": "K",
    "due": "T",
    "cell_next": "nxt",
    "cell_prev": "prv",
    "heap_t": "HT",
    "heap_key": "HKEY",
    "scalars": "f",
    "counts": "c",
    "cell_head": "head",
    "images": "img",
}


def test_checkpoint_from_before_the_new_counters_resumes():
    """Engine checkpoints saved with 6 counters and 9 scalars (and the arrays' old names) resume alike."""
    m, r, p, v = touching_lattice(3, 7)
    eng = Engine(m, r, p, v, container=5.0, window=1e-8)
    eng.advance(events=50)
    data = eng.checkpoint()
    old = {_OLD.get(k, k): v for k, v in data.items()}
    old.update(c=data["counts"][:6].copy(), f=data["scalars"][:9].copy())
    a, b = Engine.restore(data), Engine.restore(old)
    ea, eb = a.advance(events=200), b.advance(events=200)
    assert all(np.array_equal(ea[k], eb[k]) for k in ea.dtype.names)

"""Property tests on random scenarios (hypothesis).

At every reported event: a collision conserves the pair's energy and
momentum and leaves the pair receding; a reflection keeps the speed, reverses
the normal velocity and keeps the tangential one; no two spheres overlap by
more than 1e-9 of their contact distance and none pokes out of the container
by more than 1e-9 of its radius.  Checked for both engines (the reference
:class:`hardspheres.core.reference.Reference` and the compiled one), with exact
times (the library's) and the assignment's 1e-8 s window; and the two give
the same events.

Scenarios: 1 to 12 spheres at scales from 1e-3 to 1e7 (speeds scaled alike),
masses over four decades, radii up to half a grid cell, some spheres at rest
and some touching their neighbours exactly (radius half a cell, centred).
"""

import io
import math
import os

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from hardspheres.cli import run_spheres
from hardspheres.core import engine as engine_module
from hardspheres.core import reference
from hardspheres.core.engine import Engine
from hardspheres.core.reference import Reference
from hardspheres.scenario import check_scenario, parse_scenario

TOL = 1e-9  # overlap / outside, relative to contact distance / container radius
CONS = 1e-12  # conservation per event, relative
CELLS = 3  # grid of CELLS^3 cells inside the container

#: Each test so marked runs on the pure-Python reference and the compiled engine.
ENGINES = pytest.mark.parametrize("engine", [Reference, Engine], ids=["reference", "compiled"])


speeds = st.floats(-1.0, 1.0).map(lambda x: 0.0 if abs(x) < 1e-100 else x)


@st.composite
def scenarios(draw, max_n=12):
    """``(masses, radii, positions, velocities, container)`` as lists of floats."""
    n = draw(st.integers(1, max_n))
    scale = 10.0 ** draw(st.floats(-3.0, 7.0))
    container = scale
    half = container / math.sqrt(3.0) * 0.98  # the grid's cube lies inside
    w = 2.0 * half / CELLS
    cells = draw(st.permutations(range(CELLS**3)))[:n]
    masses, radii, pos, vel = [], [], [], []
    for c in cells:
        centre = [-half + w * (0.5 + k) for k in (c % CELLS, c // CELLS % CELLS, c // CELLS**2)]
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
            vel.append([0.0, 0.0, 0.0])
        else:  # speeds down to 1e-103 (|v|^2 underflows), not subnormal
            vel.append([scale * draw(speeds) for _ in range(3)])
    return masses, radii, pos, vel, container


def as_text(masses, radii, pos, vel):
    return "".join(
        f"{m!r} {r!r} {p[0]!r} {p[1]!r} {p[2]!r} {v[0]!r} {v[1]!r} {v[2]!r} s{k}\n"
        for k, (m, r, p, v) in enumerate(zip(masses, radii, pos, vel))
    )


def norm(a):
    return math.hypot(a[0], a[1], a[2])  # no underflow for tiny speeds


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def sub(a, b):
    return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]


def check_event(kind, i, j, pos, before, after, masses, radii, container, window):
    """One event: ``pos`` the centres at its time, velocities ``before`` and ``after``.

    Conservation is checked on velocities divided by the largest involved
    speed (a power of two), so that squares of tiny speeds do not underflow.
    """
    n = len(masses)
    for k in range(n):
        if k != i and k != j:
            assert after[k] == before[k], "an uninvolved sphere changed velocity"
    who = [i] if j < 0 else [i, j]
    top = max(norm(before[k]) for k in who)
    assert top > 0.0
    unit = 2.0 ** -math.frexp(top)[1]
    before = {k: [x * unit for x in before[k]] for k in who}
    after = {k: [x * unit for x in after[k]] for k in who}
    if kind == reference.COLLISION:
        mi, mj = masses[i], masses[j]
        e0 = 0.5 * (mi * dot(before[i], before[i]) + mj * dot(before[j], before[j]))
        e1 = 0.5 * (mi * dot(after[i], after[i]) + mj * dot(after[j], after[j]))
        assert abs(e1 - e0) <= CONS * e0
        scale_p = mi * norm(before[i]) + mj * norm(before[j])
        for a in range(3):
            p0 = mi * before[i][a] + mj * before[j][a]
            p1 = mi * after[i][a] + mj * after[j][a]
            assert abs(p1 - p0) <= CONS * scale_p
        dr = sub(pos[i], pos[j])
        sigma = radii[i] + radii[j]
        dv0, dv1 = sub(before[i], before[j]), sub(after[i], after[j])
        # at contact (or, within the window, a little before it)
        assert norm(dr) - sigma <= norm(dv0) / unit * window * 1.01 + TOL * sigma
        # approaching before, receding after; the impulse is along the line of centres
        assert dot(dr, dv0) < 0.0
        assert dot(dr, dv1) >= -CONS * norm(dr) * norm(dv0)
        kick = sub(after[i], before[i])
        u = [x / norm(dr) for x in dr]
        off_line = sub(kick, [dot(kick, u) * x for x in u])
        assert norm(off_line) <= CONS * norm(dv0)
    else:
        p, v0, v1 = pos[i], before[i], after[i]
        speed = norm(v0)
        assert abs(dot(v1, v1) - dot(v0, v0)) <= CONS * dot(v0, v0)
        u = [x / norm(p) for x in p]
        assert dot(v0, u) > 0.0  # it was moving out
        assert abs(dot(v1, u) + dot(v0, u)) <= CONS * speed
        kick = sub(v1, v0)
        off_normal = sub(kick, [dot(kick, u) * x for x in u])
        assert norm(off_normal) <= CONS * speed
        # at the wall (or, within the window, a little inside it)
        assert container - (norm(p) + radii[i]) <= speed / unit * window * 1.01 + TOL * container


def check_state(pos, radii, container):
    """No overlap beyond TOL of a contact distance, nothing outside beyond TOL of R."""
    n = len(pos)
    for k in range(n):
        assert norm(pos[k]) + radii[k] <= container * (1.0 + TOL)
        for m in range(k + 1, n):
            sigma = radii[k] + radii[m]
            assert norm(sub(pos[k], pos[m])) >= sigma * (1.0 - TOL)


def total_energy(masses, vel):
    return sum(0.5 * m * dot(v, v) for m, v in zip(masses, vel))


@ENGINES
@settings(max_examples=80, deadline=None)
@given(scn=scenarios(), window=st.sampled_from([0.0, reference.SIMULTANEOUS]))
def test_conserves_and_keeps_spheres_apart(engine, scn, window):
    """150 events, exact times (the library's default) or the assignment's window."""
    masses, radii, pos, vel, container = scn
    # the scenario is one the program accepts
    check_scenario(parse_scenario(as_text(masses, radii, pos, vel)), container)
    check_state(pos, radii, container)
    eng = engine(masses, radii, pos, vel, container=container, window=window)
    e_start = total_energy(masses, vel)
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
        check_event(kind, i, j, now, before, after, masses, radii, container, window)
        check_state(now, radii, container)
        before = after
    assert abs(total_energy(masses, before) - e_start) <= 1e-11 * e_start


@settings(max_examples=80, deadline=None)
@given(scn=scenarios(), window=st.sampled_from([0.0, reference.SIMULTANEOUS]))
def test_engine_matches_the_reference(scn, window):
    """Same events, same order, same times, impulses and velocities after, bit for bit."""
    masses, radii, pos, vel, container = scn
    eng = Engine(masses, radii, pos, vel, container=container, window=window, rebase=False)
    ref = Reference(masses, radii, pos, vel, container=container, window=window)
    got, want = eng.advance(events=200), ref.advance(events=200)
    assert got.dtype == want.dtype
    for field in got.dtype.names:
        assert got[field].tolist() == want[field].tolist(), field
    assert eng.velocities.tolist() == ref.velocities
    assert (eng.wall_impulse, eng.virial) == (ref.wall_impulse, ref.virial)


@settings(max_examples=40, deadline=None)
@given(scn=scenarios(), window=st.sampled_from([0.0, reference.SIMULTANEOUS]))
def test_engine_with_lists_matches_the_reference(scn, window):
    """As above, with the core predicting against neighbour lists (dense fluids' way)."""
    masses, radii, pos, vel, container = scn
    saved = engine_module.LISTS_FROM
    engine_module.LISTS_FROM = 0.0
    try:
        eng = Engine(masses, radii, pos, vel, container=container, window=window, rebase=False)
    finally:
        engine_module.LISTS_FROM = saved
    ref = Reference(masses, radii, pos, vel, container=container, window=window)
    got, want = eng.advance(events=200), ref.advance(events=200)
    for field in got.dtype.names:
        assert got[field].tolist() == want[field].tolist(), field
    assert eng.velocities.tolist() == ref.velocities


@settings(max_examples=40, deadline=None)
@given(scn=scenarios(max_n=8))
def test_report_same_from_both_engines(scn):
    """The assignment's text report, byte for byte, from either engine.

    (``os.environ`` by hand: pytest's monkeypatch fixture is function-scoped
    and hypothesis runs many examples per call.)
    """
    masses, radii, pos, vel, container = scn
    data = as_text(masses, radii, pos, vel).encode()
    outs = []
    saved = os.environ.get("HARDSPHERES_ENGINE")
    try:
        for engine in ("reference", "compiled"):
            os.environ["HARDSPHERES_ENGINE"] = engine
            out = io.StringIO()
            assert run_spheres([repr(container), "2"], io.BytesIO(data), out) == 0
            outs.append(out.getvalue())
    finally:
        if saved is None:
            os.environ.pop("HARDSPHERES_ENGINE", None)
        else:
            os.environ["HARDSPHERES_ENGINE"] = saved
    assert outs[0] == outs[1]

"""Lees-Edwards shear: the sheared box, and the brute-force reference that runs it.

Analytic cases (a centre crossing a y face, two spheres meeting across the
moving face at a time known in closed form, at several offsets and both
signs of the rate), conservation (momentum along y and z to rounding, the
exact balance of the peculiar kinetic energy against the shear stress's
work), no overlap over long runs (fixed seeds), and the sheared box's
file records and refusals.  docs/numerics.md, "Lees-Edwards shear".
"""

import math

import numpy as np
import pytest

import hardspheres as hs
from hardspheres.containers import PeriodicBox, from_fields, from_record
from hardspheres.core import _core as core
from hardspheres.core.engine import Engine
from hardspheres.core.reference import Reference, next_event_sheared, shear_offset
from hardspheres.errors import ShearError

from test_engine import CompiledReference, same_events
from test_planar import disks


def _rows(d, *rows):
    return [list(r[:d]) for r in rows]


# ---- the box -----------------------------------------------------------------------


def test_a_sheared_box_reads_back_from_its_record_and_fields():
    for box in (
        PeriodicBox(7.0, shear_rate=0.5),
        PeriodicBox((7.0, 8.0), -0.25),
        PeriodicBox((6, 7, 8), 1e-3),
    ):
        assert from_record(box.record()) == box
        assert from_fields(box.fields()) == box
        assert box.sheared and box.boundary_speed == box.shear_rate * box.sides[1]
    plain = PeriodicBox(7.0)
    assert plain == PeriodicBox(7.0, shear_rate=0.0) and not plain.sheared
    assert repr(plain) == "PeriodicBox(length=7.0)" and len(plain.record()) == 2
    assert "shear_rate" not in plain.fields()
    assert repr(PeriodicBox(3.0, 0.1)) == "PeriodicBox(length=3.0, shear_rate=0.1)"
    assert (
        PeriodicBox(3.0, -0.0).shear_rate == 0.0 and math.copysign(1, PeriodicBox(3.0, -0.0).shear_rate) == 1
    )


@pytest.mark.parametrize("bad", [math.nan, math.inf, "fast", True, None])
def test_a_shear_rate_that_is_not_a_finite_number_is_refused_in_one_line(bad):
    with pytest.raises(ShearError, match="shear_rate") as info:
        PeriodicBox(5.0, shear_rate=bad)
    assert "\n" not in str(info.value)


def test_the_box_refuses_the_unsheared_core_parameters_in_one_line():
    box = PeriodicBox(8.0, shear_rate=0.1)
    with pytest.raises(ShearError, match="runs on the event-driven engine") as info:
        box.core_params()  # (the engine asks with shear=True)
    assert "\n" not in str(info.value)


def test_the_sheared_nearest_image_shifts_x_by_the_offset_across_y():
    box = PeriodicBox((10.0, 8.0, 9.0), shear_rate=0.3)
    a = np.array([[1.0, 3.5, 0.0]])
    b = np.array([[-2.0, -3.5, 0.0]])  # its image above: (-2 + offset, 4.5)
    d = box.displacement(a, b, offset=2.5)
    assert np.allclose(d, [[0.5, -1.0, 0.0]], rtol=0, atol=1e-15)
    assert np.array_equal(box.displacement(a, b), PeriodicBox((10.0, 8.0, 9.0)).displacement(a, b))


# ---- the offset and the crossings -------------------------------------------------


def test_shear_offset_wraps_into_the_box_exactly():
    assert shear_offset(0.0, 2.0, 10.0, 7.0) == 4.0
    assert shear_offset(9.5, 1.0, 10.0, 1.0) == 0.5
    assert shear_offset(0.0, -1.0, 10.0, 3.0) == 7.0
    for t in (1e3, 1e6, 1e9):
        assert 0.0 <= shear_offset(0.25, 3.0, 10.0, t) <= 10.0


def test_numbas_float_remainder_is_pythons_bit_for_bit():
    """The offset's ``%`` (docs/numerics.md): the compiled core will take the same bits."""
    from numba import njit

    rem = njit(lambda a, b: a % b)
    rng = np.random.default_rng(3)
    a = rng.uniform(-1.0, 1.0, 20000) * 10.0 ** rng.integers(-20, 20, 20000)
    b = rng.uniform(0.1, 100.0, 20000)
    for x, y in zip(a.tolist(), b.tolist()):
        r = x % y
        assert r == rem(x, y) and math.copysign(1.0, r) == math.copysign(1.0, rem(x, y))
    assert rem(-1e-18, 3.0) == -1e-18 % 3.0 == 3.0


@pytest.mark.parametrize("d", [2, 3])
def test_a_centre_crossing_the_upper_face_loses_g_ly_and_shifts_by_the_offset(d):
    box = PeriodicBox((10.0, 8.0, 9.0)[:d], shear_rate=0.25)  # g L_y = 2
    ref = Reference([1.0], [0.5], _rows(d, [1.0, 3.0, 0.0]), _rows(d, [0.5, 1.0, 0.0]), container=box)
    assert ref.advance(until=1.5).size == 0  # a crossing is no event
    # at t = 1 it leaves at y = 4, x = 1.5; the offset is then 2: x -> -0.5, v_x -> 0.5 - 2
    assert ref.velocities == _rows(d, [-1.5, 1.0, 0.0])
    assert ref.positions_at(1.5) == _rows(d, [-1.25, -3.5, 0.0])
    assert ref.images == _rows(d, [0, 1, 0]) and ref.x_shifts == [2.0]
    assert ref.shear_offset(1.5) == 3.0


@pytest.mark.parametrize("d", [2, 3])
def test_a_centre_crossing_the_lower_face_gains_g_ly_and_shifts_back(d):
    box = PeriodicBox((10.0, 8.0, 9.0)[:d], shear_rate=0.25)
    ref = Reference(
        [1.0], [0.5], _rows(d, [1.0, -3.0, 0.0]), _rows(d, [0.5, -1.0, 0.0]), container=box, offset=3.0
    )
    ref.advance(until=1.5)
    # at t = 1, x = 1.5 and the offset 3 + 2 = 5: x -> 6.5 -> -3.5 (one side back), v_x -> 2.5
    assert ref.velocities == _rows(d, [2.5, -1.0, 0.0])
    assert ref.positions_at(1.5) == _rows(d, [-2.25, 3.5, 0.0])
    assert ref.images == _rows(d, [1, -1, 0]) and ref.x_shifts == [-5.0]
    # unwrapped: continuous (1.5 at the crossing, then 0.5 further at 2.5)
    assert ref.positions_at(1.5)[0][0] + 10.0 * ref.images[0][0] + ref.x_shifts[0] == 2.75


def test_positions_between_events_past_an_uncrossed_face_are_the_shifted_image():
    box = PeriodicBox((10.0, 8.0), shear_rate=0.25)
    ref = Reference([1.0], [0.5], [[1.0, 3.0]], [[0.5, 1.0]], container=box)
    # not advanced: the centre at t = 1.5 is past the face, shown as its image then
    assert ref.positions_at(1.5) == [[-1.25, -3.5]]


# ---- a collision across the moving face -------------------------------------------


@pytest.mark.parametrize("d", [2, 3])
@pytest.mark.parametrize(
    "rate,offset,xb,expect", [(0.1, 0.0, -3.0, 3.0), (0.1, 9.5, -3.0, 3.5), (-0.1, 0.0, 3.0, 3.0)]
)
def test_two_spheres_meet_across_the_moving_face_when_predicted(d, rate, offset, xb, expect):
    """A at rest below the upper face, B at rest above the lower one: B's image above slides into A.

    The image is at ``(xb + offset + g L_y t, 5.4)``, so with ``|dy| = 0.9``
    the spheres (diameter 1) touch at ``|dx| = sqrt(0.19)``: at ``t =
    expect - sqrt(0.19)``.  Nothing crosses a face, so no event bounds the
    images' sweep: every image ahead is tried.
    """
    box = PeriodicBox((10.0, 10.0, 10.0)[:d], shear_rate=rate)
    ref = Reference(
        [1.0, 1.0],
        [0.5, 0.5],
        _rows(d, [0.0, 4.5, 0.0], [xb, -4.6, 0.0]),
        _rows(d, [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]),
        container=box,
        offset=offset,
    )
    t, kind, i, j = ref.step()
    assert (kind, i, j) == (1, 0, 1)
    h = math.sqrt(0.19)
    assert t == pytest.approx(expect - h, rel=0, abs=1e-14)
    # head on in the image's frame (it moves at g L_y = +-1 along x): equal masses swap the normal speeds
    sign = 1.0 if rate > 0 else -1.0
    n = np.array([sign * h, -0.9])
    vn = np.dot([-sign, 0.0], n)
    va = -vn * n
    v = np.asarray(ref.velocities, dtype=float)
    assert np.allclose(v[0, :2], va, rtol=0, atol=1e-14)
    assert np.allclose(v[1, :2], -va, rtol=0, atol=1e-14)
    assert v[0, 1] + v[1, 1] == pytest.approx(0.0, abs=1e-16)


def test_the_shear_rate_given_to_the_reference_is_the_boxs():
    s = hs.random_spheres(30, 0.2, container=PeriodicBox(9.0), seed=2)
    runs = []
    for box, rate in ((PeriodicBox(9.0, 0.2), None), (PeriodicBox(9.0), 0.2)):
        ref = Reference(
            s.masses, s.radii, s.positions.tolist(), s.velocities.tolist(), container=box, shear_rate=rate
        )
        runs.append(ref.advance(events=200))
        assert ref.container == PeriodicBox(9.0, 0.2) and ref.shear_rate == 0.2
    assert all(np.array_equal(runs[0][f], runs[1][f]) for f in runs[0].dtype.names)
    with pytest.raises(ShearError, match="sheared at"):
        Reference(
            s.masses, s.radii, s.positions, s.velocities, container=PeriodicBox(9.0, 0.2), shear_rate=0.1
        )
    with pytest.raises(ShearError, match="cannot be sheared"):
        Reference([1.0], [1.0], [[0, 0, 0]], [[1, 0, 0]], container=20.0, shear_rate=0.1)
    ref = Reference(s.masses, s.radii, s.positions, s.velocities, container=PeriodicBox(9.0, 0.2))
    with pytest.raises(ShearError, match="cannot grow"):
        ref.set_growth(0.1)


# ---- long runs: conservation, no overlap, the energy balance --------------------------


def _system(d, n, phi, rate, seed):
    sides = (11.0, 13.0, 12.0)[:d]
    plain = PeriodicBox(sides)
    scale = (n * (math.pi / 6 if d == 3 else math.pi / 4) / (phi * plain.volume)) ** (1 / d)
    box = PeriodicBox(tuple(x * scale for x in sides), shear_rate=rate)
    if d == 2:
        m, r, x, v = disks(n, phi, box, seed, ratio=1.3)
    else:
        s = hs.random_spheres(n, phi, container=box, seed=seed, radius_ratio=1.3)
        m, r, x, v = s.masses, s.radii, s.positions, s.velocities
    return box, np.asarray(m, float), np.asarray(r, float), np.asarray(x, float), np.asarray(v, float)


def peculiar_energy(ref, t):
    """``sum m c^2 / 2`` at ``t``, ``c = v - g y e_x`` (at an event time: the velocities then)."""
    x = np.asarray(ref.positions_at(t), dtype=float)
    c = np.asarray(ref.velocities, dtype=float).copy()
    c[:, 0] -= ref.shear_rate * x[:, 1]
    return 0.5 * float(np.sum(np.asarray(ref.masses)[:, None] * c * c))


CASES = [
    (3, 60, 0.3, 0.2, 1, 0.0),
    (3, 100, 0.3, -0.5, 2, 3.7),
    (2, 80, 0.5, 0.3, 3, 0.0),
    (2, 60, 0.4, 1.0, 4, 5.1),
]


@pytest.mark.parametrize("d,n,phi,rate,seed,offset", CASES)
def test_long_sheared_runs_conserve_what_they_must_and_never_overlap(d, n, phi, rate, seed, offset):
    box, m, r, x, v = _system(d, n, phi, rate, seed)
    ref = CompiledReference(m, r, x.tolist(), v.tolist(), container=box, offset=offset)
    p0 = np.sum(m[:, None] * v, axis=0)
    e0 = peculiar_energy(ref, 0.0)
    sigma = r[:, None] + r[None, :]
    for _ in range(6):
        ev = ref.advance(events=500)
        assert len(ev) == 500
        t = ref.time
        pos = np.asarray(ref.positions_at(), dtype=float)
        dist = np.linalg.norm(box.displacement(pos[:, None], pos[None, :], ref.shear_offset()), axis=2)
        np.fill_diagonal(dist, np.inf)
        assert np.min(dist / sigma) > 1.0 - 1e-9
        # each collision at contact, at its nearest image
        last = ev[-1]
        i, j = int(last["i"]), int(last["j"])
        assert abs(dist[i, j] / sigma[i, j] - 1.0) < 1e-9
        p = np.sum(m[:, None] * np.asarray(ref.velocities, dtype=float), axis=0)
        scale = float(np.sum(m * np.linalg.norm(v, axis=1)))
        assert np.all(np.abs(p[1:] - p0[1:]) < 1e-12 * scale)  # y (and z): conserved
        # the peculiar kinetic energy changes by the shear stress's work, -g int V P_xy dt
        tal = ref.stress_tallies(t)
        work = -rate * (tal["kinetic"][3] + tal["virial"][3])
        e = peculiar_energy(ref, t)
        assert abs((e - e0) - work) < 1e-11 * e
    # along x: each crossing of the upper face takes g L_y m, of the lower gives it
    net = np.asarray(ref.images, dtype=float)[:, 1]
    assert abs(p[0] - (p0[0] - box.boundary_speed * np.sum(m * net))) < 1e-12 * scale


def test_the_compiled_steps_are_the_reference_bit_for_bit():
    box, m, r, x, v = _system(3, 40, 0.2, 0.4, 7)
    runs = []
    for cls in (Reference, CompiledReference):
        ref = cls(m, r, x.tolist(), v.tolist(), container=box, offset=1.25)
        runs.append(
            (ref.advance(events=300), np.asarray(ref.velocities, dtype=float), ref.images, ref.x_shifts)
        )
    (a, va, ia, sa), (b, vb, ib, sb) = runs
    assert all(np.array_equal(a[f], b[f]) for f in a.dtype.names)
    assert np.array_equal(va, vb) and ia == [list(row) for row in ib] and sa == sb


def test_unsheared_stress_tallies_are_the_engines_transport_tallies():
    """At g = 0 the reference's tallies are the compiled core's: the virial bit for bit, the kinetic to rounding."""
    box, m, r, x, v = _system(3, 60, 0.25, 0.0, 5)
    eng = Engine(m, r, x, v, container=box, rebase=False, reorder=0.0)
    ref = CompiledReference(m, r, x.tolist(), v.tolist(), container=box)
    a, b = eng.advance(events=800), ref.advance(events=800)
    assert np.array_equal(a["time"], b["time"])
    te, tr = eng.transport_tallies(eng.time + 0.5), ref.stress_tallies(ref.time + 0.5)
    assert np.array_equal(te["virial"], tr["virial"])
    assert np.allclose(te["kinetic"], tr["kinetic"], rtol=1e-12, atol=1e-12 * np.max(np.abs(te["kinetic"])))


def test_the_sheared_search_finds_every_image_that_slides_past():
    """Unbounded sweep: nothing crosses, so the first image ahead is met, at every offset."""
    edges = (10.0, 10.0, 0.0)
    h = math.sqrt(0.19)  # |dx| at contact (|dy| = 0.9, contact distance 1)
    for off in np.linspace(0.0, 10.0, 81):
        if abs((off + 5.0) % 10.0 - 5.0) < h:
            continue  # they would overlap at the start
        p = [[0.0, 4.5, 0.0], [0.0, -4.6, 0.0]]
        v = [[0.0, 0.0, 0.0], [0.0, 0.0, 0.0]]
        t, kind, i, j = next_event_sheared(p, v, [0.0, 0.0], [0.5, 0.5], edges, 0.0, 0.0, 0.0, True, off, 1.0)
        assert (kind, i, j) == (1, 0, 1)
        assert t == pytest.approx((-h - off) % 10.0, abs=1e-12)


# ---- observables and thermostats of a sheared run ------------------------------------


def _flowing(d, n, phi, rate, seed, kT=1.0):
    """A sheared system at rest on average, with the streaming profile imposed, on the compiled reference."""
    box, m, r, x, v = _system(d, n, phi, rate, seed)
    v = v - np.sum(m[:, None] * v, axis=0) / np.sum(m)  # no drift: the peculiar momentum stays put
    v *= math.sqrt(kT / (np.sum(m[:, None] * v * v) / (d * n - d)))
    v[:, 0] += rate * x[:, 1]
    return box, CompiledReference(m, r, x.tolist(), v.tolist(), container=box)


def test_peculiar_rescale_sets_the_peculiar_temperature_and_keeps_the_profile():
    from hardspheres.dense import PeculiarRescale
    from hardspheres.observables import ShearFlow, peculiar_velocities

    box, ref = _flowing(2, 60, 0.3, 0.2, 11, kT=2.5)
    flow = ShearFlow(ref)
    ref.advance(until=0.7)
    th = PeculiarRescale(kT=1.5, interval=1.0)
    th.apply(flow, 0.7)
    x = np.asarray(ref.positions_at(0.7))
    c = peculiar_velocities(x, np.asarray(ref.velocities), 0.2)
    m = np.asarray(ref.masses)
    assert np.sum(m[:, None] * c * c) / (2 * 60 - 2) == pytest.approx(1.5, rel=1e-12)
    assert th.next_time == 1.7 and flow.temperature() == pytest.approx(1.5, rel=1e-12)


def test_peculiar_andersen_draws_the_peculiar_velocity_and_is_andersen_without_shear():
    from hardspheres.dense import Andersen, PeculiarAndersen, thermostat_from_state
    from hardspheres.observables import ShearFlow

    box, ref = _flowing(3, 40, 0.2, 0.3, 12)
    flow = ShearFlow(ref)
    th, twin = PeculiarAndersen(kT=2.0, rate=0.5, seed=4), Andersen(kT=2.0, rate=0.5, seed=4)
    th.attach(flow)
    ref.advance(until=th.next_time)
    t = th.next_time
    before = np.asarray(ref.velocities).copy()
    th.apply(flow, t)
    moved = np.flatnonzero(np.any(np.asarray(ref.velocities) != before, axis=1))
    assert moved.size == 1
    i = int(moved[0])
    # the same draw as Andersen's, plus the streaming velocity at the sphere's centre
    rng = np.random.Generator(np.random.PCG64(4))
    rng.exponential(1.0 / (0.5 * 40))
    assert int(rng.integers(40)) == i
    c = rng.normal(size=3) * math.sqrt(2.0 / ref.masses[i])
    y = np.asarray(ref.positions_at(t))[i, 1]
    assert np.allclose(np.asarray(ref.velocities)[i], c + [0.3 * y, 0.0, 0.0], rtol=1e-15, atol=0)
    back = thermostat_from_state(th.state())
    assert type(back) is PeculiarAndersen and back.state() == th.state()
    assert twin.state().replace('"andersen"', '"peculiar_andersen"') != th.state()  # it has drawn once


def test_shear_flow_refuses_what_it_cannot_measure():
    from hardspheres.errors import NoMeasurementError
    from hardspheres.observables import ShearFlow

    s = hs.random_spheres(20, 0.2, container=PeriodicBox(9.0), seed=1)
    with pytest.raises(ShearError, match="needs a sheared box"):
        ShearFlow(Reference(s.masses, s.radii, s.positions, s.velocities, container=PeriodicBox(9.0)))
    box, ref = _flowing(2, 40, 0.2, 0.1, 13)
    flow = ShearFlow(ref, every=1.0)
    flow.run(5.0)
    assert flow.n_blocks == 5
    with pytest.raises(NoMeasurementError, match="5 blocks sampled: an error bar needs 16"):
        flow.viscosity()
    with pytest.raises(NoMeasurementError, match="a profile needs 16"):
        flow.profile()


def test_the_streaming_profile_of_a_thermostatted_elastic_fluid_is_linear_with_slope_g():
    """2-D, 100 disks at packing 0.3, g = 0.05 (g L_y ~ 1 thermal speed), isokinetic at kT = 1.

    The profile's slowest fluctuations relax over ``L_y^2 / nu``, tens of
    time units: over 300 of them the slope is known to about 4%
    (0.0508 +- 0.0016 and 0.0510 +- 0.0016 over 600 with two other seeds),
    so 20% is 4 or 5 standard errors.
    """
    import warnings

    from hardspheres.dense import PeculiarRescale
    from hardspheres.errors import DriftWarning
    from hardspheres.observables import ShearFlow

    box, ref = _flowing(2, 100, 0.3, 0.05, 14)
    flow = ShearFlow(ref, thermostat=PeculiarRescale(1.0, 0.5), layers=6)
    flow.run(300.0)
    y, u, err = flow.profile()
    slope, icpt = np.polyfit(y, u, 1)
    assert slope == pytest.approx(0.05, rel=0.2)
    assert abs(icpt) < 0.05  # the peculiar momentum is zero and stays so
    with warnings.catch_warnings():
        warnings.simplefilter("error", DriftWarning)
        eta = flow.viscosity()
        kt = flow.estimate("temperature")
    assert eta.mean > 0 and eta.sem < 0.3 * eta.mean
    assert kt.mean == pytest.approx(1.0, rel=0.02)
    n1 = flow.normal_stress_differences()
    assert len(n1) == 1 and np.isfinite(n1[0].mean)
    p = flow.pressure_tensor()
    assert p.shape == (2, 2) and p[0, 1] == p[1, 0] < 0
    pytest.importorskip("matplotlib")
    ax = flow.plot_profile()
    assert len(ax.lines) >= 1 and "g = 0.05" in ax.get_title()


def test_an_unthermostatted_elastic_fluid_heats_and_its_averages_warn():
    from hardspheres.errors import DriftWarning
    from hardspheres.observables import ShearFlow

    box, ref = _flowing(2, 60, 0.3, 0.3, 15)
    flow = ShearFlow(ref)
    flow.run(40.0)
    assert flow.temperature() > 1.2
    with pytest.warns(DriftWarning, match="the temperature drifts by"):
        flow.viscosity()


@pytest.mark.parametrize("d", [2, 3])
def test_a_sheared_granular_gas_balances_dissipation_against_the_stress_work(d):
    """Inelastic collisions across the moving faces: the peculiar energy changes by the work less the loss."""
    box, m, r, x, v = _system(d, 60, 0.25, 0.4, 16 + d)
    ref = CompiledReference(m, r, x.tolist(), v.tolist(), container=box, restitution=0.8)
    e0 = peculiar_energy(ref, 0.0)
    for _ in range(4):
        ref.advance(events=1000)
        t = ref.time
        tal = ref.stress_tallies(t)
        work = -0.4 * (tal["kinetic"][3] + tal["virial"][3])
        e = peculiar_energy(ref, t)
        assert ref.dissipated > 0.1 * e0
        assert abs((e - e0) - (work - ref.dissipated)) < 1e-11 * (e0 + ref.dissipated)


def _brute_next(ref, reach=8):
    """The reference's next collision or crossing with every image ``|k_x| <= reach`` tried, unpruned."""
    from hardspheres.core.reference import box_exit
    from hardspheres.physics import pair_time

    p, v, tl, rad = ref._p, ref._v, ref._tloc, ref._radii
    lx, ly, lz = ref._edges
    planar = ref.dimensions == 2
    best = (math.inf, 9, 0, 0)
    for i in range(ref.n):
        tw, face = box_exit(p[i], v[i], tl[i], ref._edges, ref._now)
        if face >= 0:
            best = min(best, (tw, 2, i, face))
    for i in range(ref.n):
        for j in range(i + 1, ref.n):
            t0 = max(tl[i], tl[j])
            xi = [p[i][k] + v[i][k] * (t0 - tl[i]) for k in range(3)]
            xj = [p[j][k] + v[j][k] * (t0 - tl[j]) for k in range(3)]
            delta = shear_offset(ref._off0, ref._speed, lx, t0)
            for ky in (-1, 0, 1):
                dvx = v[i][0] - (v[j][0] + ky * ref._speed)
                for kx in range(-reach, reach + 1):
                    for kz in (0,) if planar else (-1, 0, 1):
                        dx = xi[0] - (xj[0] + (kx * lx + ky * delta))
                        dy = xi[1] - (xj[1] + ky * ly)
                        dz = xi[2] - (xj[2] + kz * lz)
                        te = t0 + pair_time(
                            dx, dy, dz, dvx, v[i][1] - v[j][1], v[i][2] - v[j][2], rad[i] + rad[j], planar
                        )
                        best = min(best, (max(te, ref._clock), 1, i, j))
    return best


@pytest.mark.parametrize("d,phi,rate,seed", [(2, 0.05, 1.0, 1), (2, 0.03, 2.0, 4), (3, 0.05, 1.0, 3)])
def test_images_that_slid_far_since_the_pairs_last_event_are_found(d, phi, rate, seed):
    """Half the spheres at rest for long: their images slide many box lengths between their events.

    Every next event is checked against a search with every image within 8
    box lengths along x, unpruned.  (The search once swept the images the
    wrong way: it missed the collision at step 1 of the first case and at
    step 4 of the second.)
    """
    box, m, r, x, v = _system(d, 24, phi, rate, seed)
    v[:12] = 0.0
    ref = Reference(m, r, x.tolist(), v.tolist(), container=box, offset=2.9)
    for _ in range(150):
        assert ref._next() == _brute_next(ref)
        ref.step()


# ---- the compiled core's sheared variant against the reference ------------------------


def _engine_and_reference(d, n, phi, rate, seed, offset, window=0.0, events=2000):
    box, m, r, x, v = _system(d, n, phi, rate, seed)
    eng = Engine(m, r, x, v, container=box, window=window, rebase=False, reorder=0.0, shear_offset=offset)
    ref = CompiledReference(m, r, x.tolist(), v.tolist(), container=box, window=window, offset=offset)
    return eng, ref, eng.advance(events=events), ref.advance(events=events)


def _same_state(eng, ref):
    n, d = eng.n, eng.dimensions
    assert np.array_equal(eng.velocities, np.asarray(ref.velocities, dtype=float).reshape(n, d))
    assert np.array_equal(eng.positions_at(), np.asarray(ref.positions_at(), dtype=float).reshape(n, d))
    assert np.array_equal(eng.images[:, :d], np.asarray(ref.images)[:, :d])
    assert eng.time == ref.time and eng.shear_offset() == ref.shear_offset()
    assert eng.counters["collisions"] == ref.counters["collisions"]


@pytest.mark.parametrize("d,n,phi,rate,seed,offset", CASES)
@pytest.mark.parametrize("window", [0.0, 1e-8])
def test_the_engine_shears_as_the_reference_bit_for_bit(d, n, phi, rate, seed, offset, window):
    """The same events, velocities, centres, images and offset, in 2-D and 3-D, both signs of the rate."""
    eng, ref, a, b = _engine_and_reference(d, n, phi, rate, seed, offset, window)
    assert eng.axes[0] == ((),) and eng.scalars[core.F_SHELL] == 0.0  # (the sheared variant, cells)
    assert len(a) == len(b) == 2000 and same_events(a, b)
    _same_state(eng, ref)
    assert np.any(np.asarray(ref.images)[:, 1] != 0)  # (centres did cross the sliding faces)
    assert eng.max_overlap() < 1e-9


@pytest.mark.parametrize("cells", [3, 5])
def test_a_few_wide_cells_or_many_narrow_ones_give_the_same_bits(cells, monkeypatch):
    """The strip across the face is found at every cell width (a dilute gas: many cells per side)."""
    d, n, phi, rate, seed, offset = 3, 60, 0.05, 0.7, 6, 1.3
    box, m, r, x, v = _system(d, n, phi, rate, seed)
    eng = Engine(m, r, x, v, container=box, rebase=False, reorder=0.0, shear_offset=offset)
    if cells == 3:  # the fewest cells a side: every other cell row is a boundary row
        eng.counts[core.C_GRID : core.C_GRID + 3] = 3
        eng.counts[core.C_CELLS] = 3
        for ax in range(3):
            eng.scalars[core.F_WIDTH + ax] = eng._edges[ax] / 3
        eng.scalars[core.F_W] = eng.scalars[core.F_WIDTH]
        eng.cell_head = np.full(27, -1, eng.cell_head.dtype)
        eng._build()
    assert np.all(eng._cells >= cells)
    ref = CompiledReference(m, r, x.tolist(), v.tolist(), container=box, offset=offset)
    assert same_events(eng.advance(events=1500), ref.advance(events=1500))
    _same_state(eng, ref)


def test_rebased_sheared_runs_stay_exact_physics():
    """With rebases (the offset's origin moved) the bits may part from the reference's; the physics may not."""
    d, n, phi, rate, seed, offset = CASES[2]
    box, m, r, x, v = _system(d, n, phi, rate, seed)
    eng = Engine(m, r, x, v, container=box, shear_offset=offset)
    p0 = np.sum(m[:, None] * v, axis=0)
    for _ in range(10):
        eng.advance(events=3000)
        assert eng.max_overlap() < 1e-9
    p = np.sum(m[:, None] * eng.velocities, axis=0)
    scale = float(np.sum(m * np.linalg.norm(v, axis=1)))
    assert abs(p[1] - p0[1]) < 1e-12 * scale
    net = eng.images[:, 1].astype(float)
    assert abs(p[0] - (p0[0] - box.boundary_speed * np.sum(m * net))) < 1e-11 * scale
    assert eng.shear_offset() == pytest.approx(
        shear_offset(offset, box.boundary_speed, box.sides[0], eng.time)
    )


def test_a_sheared_engine_resumes_from_its_checkpoint_bit_for_bit():
    d, n, phi, rate, seed, offset = CASES[1]
    box, m, r, x, v = _system(d, n, phi, rate, seed)
    a = Engine(m, r, x, v, container=box, shear_offset=offset)
    a.advance(events=2000)
    b = Engine.restore({k: np.copy(w) for k, w in a.checkpoint().items()})
    assert b.shear_rate == rate and b.axes[0] == ((),) and b.shear_offset() == a.shear_offset()
    assert same_events(a.advance(events=2000), b.advance(events=2000))
    assert np.array_equal(a.velocities, b.velocities)


def test_a_sheared_engine_refuses_growth_and_a_bad_offset():
    box, m, r, x, v = _system(2, 20, 0.2, 0.5, 1)
    eng = Engine(m, r, x, v, container=box)
    with pytest.raises(ValueError, match="sheared"):
        eng.set_growth(0.1)
    with pytest.raises(ShearError, match="offset"):
        Engine(m, r, x, v, container=box, shear_offset=math.nan)


def test_unsheared_engines_keep_their_loop():
    box, m, r, x, v = _system(3, 40, 0.2, 0.0, 2)
    eng = Engine(m, r, x, v, container=box)
    assert eng.axes == ((), (), ()) and eng.shear_offset() == 0.0 and eng.shear_rate == 0.0


@pytest.mark.parametrize("d,n,phi,rate,seed,offset", CASES)
def test_the_engines_peculiar_stress_tallies_are_the_references(d, n, phi, rate, seed, offset):
    """The collisional virial tensor bit for bit; the peculiar kinetic integral to rounding (per flight, summed otherwise)."""
    eng, ref, a, b = _engine_and_reference(d, n, phi, rate, seed, offset, events=1500)
    for t in (eng.time, eng.time + 0.37):
        ta, tb = eng.stress_tallies(t), ref.stress_tallies(t)
        assert np.array_equal(ta["virial"], tb["virial"])
        assert np.allclose(
            ta["kinetic"], tb["kinetic"], rtol=1e-12, atol=1e-13 * np.max(np.abs(tb["kinetic"]))
        )
    assert eng.stress_tallies(eng.time + 0.37)["kinetic"][3] != eng.stress_tallies()["kinetic"][3]
    again = Engine.restore({k: np.copy(w) for k, w in eng.checkpoint().items()})
    assert np.array_equal(again.stress_tallies()["kinetic"], eng.stress_tallies()["kinetic"])


# ---- Simulation in a sheared box ----------------------------------------------------


def _sheared_simulation(n=200, phi=0.3, rate=0.5, seed=1):
    from hardspheres.dense import PeculiarRescale

    box = PeriodicBox.for_packing(n, phi, (1.0, 1.0, 1.0)).sheared_by(rate)
    sim = hs.Simulation(hs.random_spheres(n, phi, box, seed=seed), box)
    return sim.set_thermostat(PeculiarRescale(1.0, 0.5))


def test_a_sheared_simulation_measures_the_viscosity_with_peculiar_velocities(tmp_path):
    sim = _sheared_simulation()
    sim.run(until=10.0)
    sim.observables.reset()
    sim.run(until=60.0)
    out = sim.observables.summary()
    assert out["temperature"] == pytest.approx(1.0, rel=1e-12)  # (the thermostat's, peculiar)
    assert out["shear_rate"] == 0.5 and out["viscosity"] > 0.0 and np.isfinite(out["viscosity_error"])
    assert "normal_stress_1" in out and "normal_stress_2" in out
    assert sim.engine.max_overlap() < 1e-9
    sim.save(tmp_path / "s.npz")
    again = hs.Simulation.load(tmp_path / "s.npz")
    assert again.container.shear_rate == 0.5 and again.engine.shear_offset() == sim.engine.shear_offset()
    sim.run(until=70.0)
    again.run(until=70.0)
    assert np.array_equal(sim.engine.velocities, again.engine.velocities)


def test_a_sheared_simulation_refuses_a_thermostat_that_fights_the_flow():
    from hardspheres.dense import Andersen

    sim = _sheared_simulation(n=50)
    with pytest.raises(ShearError, match="PeculiarRescale"):
        sim.set_thermostat(Andersen(1.0, 0.1))


@pytest.mark.parametrize("d,n,phi,rate,seed,offset", CASES)
def test_a_sheared_granular_gas_and_a_thermostatted_flow_are_the_references(d, n, phi, rate, seed, offset):
    """The inelastic rule in the sheared variant, and peculiar kicks (ShearFlow's thermostat): bit for bit."""
    from hardspheres.dense import PeculiarRescale
    from hardspheres.observables import ShearFlow

    box, m, r, x, v = _system(d, n, phi, rate, seed)
    rule = dict(restitution=0.8, tc=1e-4)
    eng = Engine(m, r, x, v, container=box, rebase=False, reorder=0.0, shear_offset=offset, **rule)
    ref = CompiledReference(m, r, x.tolist(), v.tolist(), container=box, offset=offset, **rule)
    assert same_events(eng.advance(events=1500), ref.advance(events=1500))
    assert eng.dissipated == ref.dissipated > 0.0
    eng = Engine(m, r, x, v, container=box, rebase=False, reorder=0.0, shear_offset=offset)
    ref = CompiledReference(m, r, x.tolist(), v.tolist(), container=box, offset=offset)
    for engine in (eng, ref):
        ShearFlow(engine, thermostat=PeculiarRescale(kT=1.0, interval=0.3)).run(4.0)
    _same_state(eng, ref)


def test_the_barostat_refuses_a_sheared_box_and_steps():
    from hardspheres.errors import BarostatError

    box = PeriodicBox.for_packing(50, 0.2, (1.0, 1.0, 1.0))
    sheared = hs.Simulation(hs.random_spheres(50, 0.2, box, seed=1), box.sheared_by(0.1))
    with pytest.raises(BarostatError, match="sheared"):
        sheared.set_barostat(hs.Barostat(pressure=1.0))
    wells = hs.Simulation(hs.random_spheres(50, 0.2, box, seed=1), box, steps=[(1.5, -1.0)])
    with pytest.raises(BarostatError, match="steps"):
        wells.set_barostat(hs.Barostat(pressure=1.0))

"""Two dimensions in the event core: disks in a circle and in a periodic rectangle.

The engine keeps a disk as a sphere whose z and vz are exactly 0 and its
cells as one layer (the 9 cells around a disk's, not 27); the reference
(:mod:`hardspheres.core.reference`) runs the same kernels on ``[x, y, 0]``.
These tests hold the engine to the reference bit for bit in a circle (cells
and neighbour lists, simultaneity window on and off, reordered or not),
and check the laws in both containers: energy and momentum conserved, no
overlaps, no escapes, z never leaving 0.
"""

import numpy as np
import pytest

import hardspheres as hs
from hardspheres.containers import BoxShapeError, CircularContainer, PeriodicBox, from_fields, from_record
from hardspheres.core import _core as core
from hardspheres.core.engine import Engine
from hardspheres.core.reference import Reference

from test_engine import CompiledReference, same_events


def disks(n, phi, container, seed, ratio=1.0):
    """``n`` disks of area fraction ``phi`` on a random subset of a triangular lattice's sites."""
    rng = np.random.default_rng(seed)
    rel = rng.uniform(1.0, ratio, n) if ratio > 1 else np.ones(n)
    area = container.volume
    radii = rel * np.sqrt(phi * area / (np.pi * np.sum(rel**2)))
    rmax = radii.max()
    if container.periodic:
        lx, ly = container.sides
        m = 1.1 * n  # sites: rows nearly a triangular lattice's apart, an even number of them
        kx = max(1, int(round(np.sqrt(m * np.sqrt(3) * lx / (2 * ly)))))
        ky = 2 * int(np.ceil(m / kx / 2))
        ax, ay = lx / kx, ly / ky
        sites = np.array(
            [[(i + 0.5 * (j % 2)) * ax - lx / 2, j * ay - ly / 2] for j in range(ky) for i in range(kx)]
        )
        assert min(ax, np.hypot(ax / 2, ay)) > 2 * rmax * (1 + 1e-9)
    else:
        R = container.radius - rmax
        a = 2 * R  # the widest spacing that holds n sites (about 2n)
        while True:
            k = int(R / a) + 2
            grid = [
                [(i + 0.5 * (j % 2)) * a, j * a * np.sqrt(3) / 2]
                for j in range(-k, k + 1)
                for i in range(-k, k + 1)
            ]
            sites = np.array(grid)
            sites = sites[np.linalg.norm(sites, axis=1) <= R * (1 - 1e-9)]
            if len(sites) >= n + min(n, 20) or (len(sites) >= n and 0.97 * a < 2.05 * rmax):
                break
            a *= 0.97
        assert a > 2 * rmax * (1 + 1e-9)
    assert len(sites) >= n
    pos = sites[np.sort(rng.choice(len(sites), n, replace=False))]
    vel = rng.normal(size=(n, 2))
    masses = np.exp(rng.uniform(0, np.log(ratio), n)) if ratio > 1 else np.ones(n)
    return masses, radii, pos, vel


def assert_same(eng, ref, n):
    assert np.array_equal(eng.velocities, np.array(ref.velocities).reshape(n, 2))
    assert np.array_equal(eng.positions_at(), np.array(ref.positions_at()).reshape(n, 2))
    for key in ("collisions", "reflections"):
        assert eng.counters[key] == ref.counters[key]
    assert (eng.time, eng.wall_impulse, eng.virial) == (ref.time, ref.wall_impulse, ref.virial)


@pytest.mark.parametrize("n,phi", [(2, 0.01), (5, 0.1), (30, 0.3), (90, 0.55)])
@pytest.mark.parametrize("window", [0.0, 1e-8])
def test_engine_matches_the_pure_python_reference_in_a_circle(n, phi, window):
    c = CircularContainer(10.0)
    m, r, x, v = disks(n, phi, c, seed=n, ratio=1.2)
    ref = Reference(m, r, x.tolist(), v.tolist(), container=c, window=window)
    eng = Engine(m, r, x, v, container=c, window=window, rebase=False)
    assert eng.dimensions == ref.dimensions == 2
    assert (eng.scalars[core.F_SHELL] > 0) == (phi > 0.5)
    a, b = eng.advance(events=300), ref.advance(events=300)
    assert same_events(a, b)
    assert_same(eng, ref, n)


@pytest.mark.parametrize("phi", [0.25, 0.6])  # cells; neighbour lists
@pytest.mark.parametrize("window", [0.0, 1e-8])
@pytest.mark.parametrize("reorder", [0.0, 2.0])
def test_engine_matches_the_compiled_reference_in_a_circle(phi, window, reorder):
    c = CircularContainer(12.0)
    n = 300
    m, r, x, v = disks(n, phi, c, seed=7, ratio=1.1)
    eng = Engine(m, r, x, v, container=c, window=window, rebase=False, reorder=reorder)
    assert (eng.scalars[core.F_SHELL] > 0) == (phi > 0.5)
    assert eng.counts[core.C_GRID + 2] == 1 and eng.counts[core.C_GRID] > 3
    ref = CompiledReference(m, r, x, v, container=c, window=window)
    a, b = eng.advance(events=5000), ref.advance(events=5000)
    assert same_events(a, b)
    assert_same(eng, ref, n)


@pytest.mark.parametrize("phi", [0.3, 0.65])  # cells; neighbour lists
@pytest.mark.parametrize("sides", [(30.0, 30.0), (24.0, 36.0)])
def test_disks_in_a_periodic_box_keep_the_laws(phi, sides):
    box = PeriodicBox(sides)
    m, r, x, v = disks(900, phi, box, seed=3, ratio=1.1)
    eng = Engine(m, r, x, v, container=box)
    p0, e0 = m @ eng.velocities, eng.kinetic_energy()
    eng.advance(collisions=60000, record=False)
    assert abs(eng.kinetic_energy() / e0 - 1) < 1e-12
    assert np.max(np.abs(m @ eng.velocities - p0)) < 1e-10 * np.sum(m)
    assert eng.max_overlap() < 1e-9
    assert np.all(eng.spheres[:, core.Z] == 0.0) and np.all(eng.spheres[:, core.VZ] == 0.0)
    x = eng.positions_at()
    assert x.shape == (900, 2) and np.all(np.abs(x) <= 0.5 * np.array(sides))
    assert eng.unwrapped_at().shape == (900, 2) and eng.images.shape == (900, 2)
    b = Engine.restore({k: np.copy(a) for k, a in eng.checkpoint().items()})
    assert b.container == box and b.dimensions == 2
    assert same_events(eng.advance(collisions=3000), b.advance(collisions=3000))


def test_disks_never_leave_the_circle_and_growth_never_overlaps():
    c = CircularContainer(15.0)
    m, r, x, v = disks(500, 0.4, c, seed=4)
    eng = Engine(m, r, x, v, container=c)
    e0 = eng.kinetic_energy()
    eng.advance(collisions=40000, record=False)
    assert eng.outside() == 0 and eng.max_overlap() < 1e-9
    assert abs(eng.kinetic_energy() / e0 - 1) < 1e-12
    eng.set_growth(0.02)
    eng.advance(collisions=40000, record=False)
    assert eng.outside() == 0 and eng.max_overlap() < 1e-9


def test_mixed_dimensions_are_refused():
    with pytest.raises(BoxShapeError, match="3 components but the container is 2-D"):
        Engine([1.0], [0.5], [[0.0, 0.0, 0.0]], [[1.0, 0.0, 0.0]], container=CircularContainer(5.0))
    with pytest.raises(BoxShapeError, match="2 components but the container is 3-D"):
        Engine([1.0], [0.5], [[0.0, 0.0]], [[1.0, 0.0]], box=5.0)
    with pytest.raises(BoxShapeError, match="3 components but the container is 2-D"):
        Reference([1.0], [0.5], [[0.0, 0.0, 0.0]], [[1.0, 0.0, 0.0]], container=CircularContainer(5.0))
    for bad in ((1.0,), (1.0, 2.0, 3.0, 4.0)):
        with pytest.raises(BoxShapeError, match=r"two \(Lx, Ly: 2-D\)"):
            PeriodicBox(bad)


def test_two_dimensional_containers_geometry_and_files():
    b = PeriodicBox((3.0, 4.0))
    assert (b.dimensions, b.volume, b.degrees_of_freedom(10), b.gsd_box) == (
        2,
        12.0,
        18,
        [3.0, 4.0, 0.0, 0.0, 0.0, 0.0],
    )
    assert b.pressure(10, 1.0, 2.0, 0.0, 8.0) == pytest.approx((10 + 8.0 / 4.0) / 12.0)
    assert from_record(b.record()) == b and from_fields(b.fields()) == b
    c = CircularContainer(2.0)
    assert (c.dimensions, c.degrees_of_freedom(10), c.gsd_box) == (2, 20, [4.0, 4.0, 0.0, 0.0, 0.0, 0.0])
    assert c.wall_area == pytest.approx(4 * np.pi) and c.volume == pytest.approx(4 * np.pi)
    assert from_record(c.record()) == c and from_fields(c.fields()) == c
    assert c.outside(np.array([[1.5, 0.0], [0.0, 0.0]]), np.array([0.6, 0.5])).tolist() == [True, False]
    assert hs.CircularContainer is CircularContainer


@pytest.mark.parametrize(
    "container,phi",
    [
        (PeriodicBox((30.0, 26.0)), 0.3),  # cells
        (PeriodicBox((30.0, 26.0)), 0.68),  # neighbour lists
        (CircularContainer(14.0), 0.3),
        (CircularContainer(14.0), 0.6),
    ],
)
def test_the_2d_core_never_reads_z(container, phi):
    """True 2-D: with z and vz made NaN behind the engine's back, every bit is the same.

    (On the flat 3-D core of before, the NaN reached every pair time.)
    """
    m, r, x, v = disks(400, phi, container, seed=11, ratio=1.1)
    runs = []
    for poison in (False, True):
        eng = Engine(m, r, x, v, container=container)
        if poison:
            eng.spheres[:, core.Z] = np.nan
            eng.spheres[:, core.VZ] = np.nan
            eng.shells[:, core.SHELL_Z] = np.nan
        ev = eng.advance(collisions=8000)
        if container.periodic:
            eng.set_growth(0.01)
            ev = np.concatenate([ev, eng.advance(collisions=2000)])
        runs.append((ev, eng.positions_at(), eng.velocities, eng.virial, eng.wall_impulse, eng.max_overlap()))
    (a, xa, va, *ra), (b, xb, vb, *rb) = runs
    assert same_events(a, b)
    assert np.array_equal(xa, xb) and np.array_equal(va, vb)
    assert ra == rb and not np.isnan(ra).any()


def test_the_dimension_reaches_the_core_as_a_type():
    """``Engine.axes`` is ``d`` empty tuples among the core's arrays (numba folds its length).

    The collision rule after it is a type too: ``()`` for elastic spheres.
    """
    for container, d in ((PeriodicBox((10.0, 10.0)), 2), (CircularContainer(5.0), 2), (PeriodicBox(10.0), 3)):
        k = 2 if d == 2 else 1
        x = [[-2.0, 0, 0][:d], [2.0, 0, 0][:d]][:k]
        v = [[1.0, 0, 0][:d], [-1.0, 0, 0][:d]][:k]
        eng = Engine([1.0] * k, [0.5] * k, x, v, container=container)
        axes = core.ARRAYS.index("axes")
        assert eng.axes == ((),) * d and eng.arrays[axes] is eng.axes
        assert core.ARRAYS[-1] == "rule" and eng.arrays[-1] == () == eng.rule
        assert "axes" not in eng.checkpoint() and "rule" not in eng.checkpoint()

"""The numpy engine (hardspheres.core.scan.Scan) against the brute-force reference, bit for bit."""

from __future__ import annotations

import random

import pytest

from hardspheres.containers import CircularContainer, SphericalContainer
from hardspheres.core.reference import Reference
from hardspheres.core.scan import Scan
from hardspheres.errors import ArgumentError

pytestmark = pytest.mark.integration


def _system(n: int, seed: int, d: int, lattice: bool):
    """``n`` spheres of radius 0.5 or 1, masses 1 or 2; on a lattice with speeds in {-1, 0, 0.5, 1}: many ties."""
    rnd = random.Random(seed)
    wall = 10.0 * n ** (1 / d)
    pos: list[list[float]] = []
    radii: list[float] = []
    while len(pos) < n:
        k = len(pos)
        if lattice:
            p = [(k % 7) * 3.0 - 9, (k // 7 % 7) * 3.0 - 9, (k // 49) * 3.0 - 9][:d]
        else:
            p = [rnd.uniform(-0.6 * wall, 0.6 * wall) for _ in range(d)]
        r = rnd.choice([0.5, 1.0, 1.0])
        if all(sum((a - b) ** 2 for a, b in zip(p, q)) > (r + s) ** 2 for q, s in zip(pos, radii)):
            pos.append(p)
            radii.append(r)
    vel = [
        [rnd.choice([-1.0, 0.0, 1.0, 0.5]) if lattice else rnd.gauss(0, 1) for _ in range(d)]
        for _ in range(n)
    ]
    masses = [rnd.choice([1.0, 2.0]) for _ in range(n)]
    return masses, radii, pos, vel, (SphericalContainer(wall) if d == 3 else CircularContainer(wall))


@pytest.mark.parametrize("d", [3, 2])
@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize("window", [0.0, 1e-8, 0.3])
def test_scan_equals_the_reference_bit_for_bit(d, seed, window):
    """Same events, velocities and positions; lattices with equal speeds make ties, a wide window many at once."""
    masses, radii, pos, vel, where = _system(30, seed, d, lattice=seed % 2 == 1)
    ref = Reference(masses, radii, pos, vel, container=where, window=window)
    scan = Scan(masses, radii, pos, vel, container=where, window=window)
    a, b = ref.advance(events=400), scan.advance(events=400)
    assert len(a) == 400
    assert a.tobytes() == b.tobytes()
    assert ref.velocities == scan.velocities
    assert ref.positions_at() == scan.positions_at()
    assert ref.counters == scan.counters


def test_scan_rescaled_pairs_and_resting_spheres():
    """Speeds of 1e-160 (the kernels' rescaled path, taken by the scalar kernel) and spheres at rest."""
    pos = [[-5.0, 0, 0], [5.0, 0, 0], [0.0, 4.0, 0.0], [0.0, -4.0, 0.0]]
    vel = [[1e-160, 0, 0], [-1e-160, 0, 0], [0.0, 0.0, 0.0], [0.0, 1e-150, 0.0]]
    args = ([1.0] * 4, [1.0] * 4, pos, vel)
    ref, scan = Reference(*args, container=100.0), Scan(*args, container=100.0)
    a, b = ref.advance(events=20), scan.advance(events=20)
    assert len(a) == 20 and a.tobytes() == b.tobytes()
    assert a["time"][0] > 1e150  # the rescaled path was taken


def test_scan_refuses_what_it_does_not_do():
    with pytest.raises(ArgumentError, match="periodic box"):
        Scan([1.0], [0.5], [[0.0, 0.0, 0.0]], [[1.0, 0.0, 0.0]], box=10.0)
    scan = Scan([1.0], [0.5], [[0.0, 0.0, 0.0]], [[1.0, 0.0, 0.0]], container=10.0)
    with pytest.raises(ArgumentError, match="no growth"):
        scan.set_growth(0.1)


def test_the_assignment_program_runs_scan_while_the_cache_is_cold(monkeypatch):
    """More than SMALL spheres and no compiled core in the cache: Scan, not a compilation."""
    import hardspheres.core.warmup as warmup
    from hardspheres.cli.assignment import SMALL, choose_engine

    monkeypatch.delenv("HARDSPHERES_ENGINE", raising=False)
    monkeypatch.setattr(
        warmup, "is_cold", lambda dimensions=3, inelastic=False, sheared=False, stepped=False: True
    )
    assert choose_engine(SMALL) == "reference"
    assert choose_engine(SMALL + 1) == choose_engine(1000) == "scan"
    monkeypatch.setattr(
        warmup, "is_cold", lambda dimensions=3, inelastic=False, sheared=False, stepped=False: False
    )
    assert choose_engine(SMALL + 1) == "compiled"

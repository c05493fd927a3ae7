"""The scenario builder: N exact, no overlaps, inside the container, seeds reproducible.

Overlaps are checked independently of the engine, with scipy's k-d tree
(periodic ``boxsize`` for the box), pair by pair against the radii's sums.
"""

import tracemalloc

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from scipy.spatial import cKDTree

import hardspheres as hs
from hardspheres import builders
from hardspheres.builders import BuildError, random_arrays
from helpers import hs_cmd


def _where(n, packing, box, radius_ratio=1.0):
    """A container whose largest spheres have a radius of about 0.5 (as the benchmark's)."""
    scale = (1.0 + radius_ratio**3) / 2.0 if radius_ratio != 1.0 else 1.0
    volume = n * scale * (np.pi / 6.0) / packing
    if box:
        return hs.PeriodicBox(volume ** (1.0 / 3.0))
    return hs.SphericalContainer((volume * 3.0 / (4.0 * np.pi)) ** (1.0 / 3.0))


def overlapping_pairs(positions, radii, where):
    """Pairs closer than the sum of their radii, less a relative 1e-12."""
    x = np.asarray(positions, dtype=float)
    if where.periodic:
        L = where.length
        x = np.mod(x + 0.5 * L, L)
        x[x >= L] -= L  # mod can round up to L
        tree = cKDTree(x, boxsize=L)
    else:
        tree = cKDTree(x)
    pairs = tree.query_pairs(2.0 * radii.max(), output_type="ndarray")
    if len(pairs) == 0:
        return pairs
    d = where.displacement(x[pairs[:, 0]], x[pairs[:, 1]])
    dist = np.linalg.norm(d, axis=1)
    contact = radii[pairs[:, 0]] + radii[pairs[:, 1]]
    return pairs[dist < contact * (1.0 - 1e-12)]


def check_valid(n, packing, where, m, r, x, v, radius_ratio=1.0):
    assert m.shape == (n,) and r.shape == (n,) and x.shape == (n, 3) and v.shape == (n, 3)
    assert not where.outside(x, r, tol=0.0).any()
    assert len(overlapping_pairs(x, r, where)) == 0
    assert np.sum(4.0 / 3.0 * np.pi * r**3) / where.volume == pytest.approx(packing, rel=1e-12)
    assert r.max() / r.min() <= radius_ratio * (1.0 + 1e-12)
    assert np.abs(m @ v).max() <= 1e-9 * np.sqrt(n)  # zero total momentum


@pytest.mark.parametrize("box", [False, True], ids=["sphere", "box"])
@pytest.mark.parametrize("packing", [0.1, 0.3, 0.45, 0.55])
def test_large_systems_are_valid(packing, box):
    n = 60_000
    where = _where(n, packing, box)
    check_valid(n, packing, where, *random_arrays(n, packing, where, seed=11))


@pytest.mark.parametrize("ratio", [1.4, 10.0])
def test_mixtures_are_valid(ratio):
    n, packing = 20_000, 0.15
    for box in (False, True):
        where = _where(n, packing, box, ratio)
        check_valid(
            n,
            packing,
            where,
            *random_arrays(n, packing, where, seed=2, radius_ratio=ratio),
            radius_ratio=ratio,
        )


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    n=st.integers(1, 3000),
    packing=st.floats(1e-6, 0.3),
    box=st.booleans(),
    ratio=st.sampled_from([1.0, 1.4]),
    seed=st.integers(0, 2**32 - 1),
)
def test_any_request_is_valid_or_refused_in_one_line(n, packing, box, ratio, seed):
    where = _where(n, packing, box, ratio)
    try:
        out = random_arrays(n, packing, where, seed=seed, radius_ratio=ratio)
    except BuildError as e:
        assert "\n" not in str(e) and str(e)
        return
    check_valid(n, packing, where, *out, radius_ratio=ratio)


@pytest.mark.parametrize("box", [False, True], ids=["sphere", "box"])
def test_seeds_reproduce(box):
    where = _where(5000, 0.3, box)
    a = random_arrays(5000, 0.3, where, seed=7, radius_ratio=1.4, mass_ratio=3.0)
    b = random_arrays(5000, 0.3, where, seed=7, radius_ratio=1.4, mass_ratio=3.0)
    c = random_arrays(5000, 0.3, where, seed=8, radius_ratio=1.4, mass_ratio=3.0)
    assert all(np.array_equal(p, q) for p, q in zip(a, b))
    assert not np.array_equal(a[2], c[2])
    state = hs.random_spheres(5000, 0.3, where, seed=7, radius_ratio=1.4, mass_ratio=3.0)
    assert all(
        np.array_equal(p, q)
        for p, q in zip(a, (state.masses, state.radii, state.positions, state.velocities))
    )


@pytest.mark.parametrize("box", [False, True], ids=["sphere", "box"])
def test_dense_lattices_leave_a_gap_between_neighbours(box):
    """Spheres placed at the contact spacing rattle for ever without moving (issue 14)."""
    n, packing = 20_000, 0.45
    where = _where(n, packing, box)
    _, r, x, _ = random_arrays(n, packing, where, seed=3)
    tree = cKDTree(np.mod(x + 0.5 * where.length, where.length), boxsize=where.length) if box else cKDTree(x)
    d, _ = tree.query(np.mod(x + 0.5 * where.length, where.length) if box else x, k=2)
    assert d[:, 1].min() > 2.0 * r[0] * 1.02


@pytest.mark.parametrize("kw", [{"box": 10.0}, {"container": 10.0}], ids=["box", "sphere"])
@pytest.mark.parametrize("n", [1, 2, 50, 2000])
def test_lattice_is_sized_by_n_not_by_the_container(n, kw):
    """random_spheres(50, 1e-7, box=10) once built 3.7e8 lattice sites (9 GB)."""
    tracemalloc.start()
    try:
        state = hs.random_spheres(n, 1e-7, seed=1, **kw)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert state.n == n
    assert peak < 2e6 + 2000 * n  # bytes: a few lattice sites per sphere at most


def test_box_lattice_holds_at_most_a_few_sites_per_sphere():
    for n in (1, 7, 50, 999, 10**6):
        k, edge = builders._box_lattice(n, 10.0, 1e-6)
        assert n <= 4 * k**3 <= 2 * builders.SITES_PER_SPHERE * n + 32
        assert edge * k == pytest.approx(10.0)


def test_impossible_packing_is_refused_in_one_line():
    where = _where(5000, 0.7, True)
    with pytest.raises(BuildError) as e:
        random_arrays(5000, 0.7, where, seed=1)
    assert "\n" not in str(e.value) and "lower the packing" in str(e.value)


def test_oversized_n_is_refused_before_allocating():
    """Issue 29 item 8: --n 1e10 ended in numpy's 33-line "Unable to allocate
    74.5 GiB" traceback; now one line saying what fits in this machine."""
    from hardspheres.builders import BuildError, machine_memory, random_arrays

    mem = machine_memory()
    n = int(mem // 190 * 2)
    with pytest.raises(BuildError, match="GiB.*at most about") as e:
        random_arrays(n, 0.3, 20.0)
    assert "\n" not in str(e.value)
    for argv in (
        ("generate", "--n", "1e10", "--container", 20, "--packing", 0.3),
        ("bench", "--n", "1e10", "--packing", 0.3, "--collisions", 1000),
    ):
        done = hs_cmd(*argv)
        assert done.returncode == 1 and done.stderr.count("\n") == 1 and "at most about" in done.stderr, argv
        assert "Traceback" not in done.stderr


def test_binary_mixture_and_the_uniform_ratio_named_for_what_it_is():
    """Issue 29 item 4: radius_ratio meant uniform polydispersity (only --help said
    so), and the commonest mixture, two sizes at a number fraction, had no builder."""
    s = hs.random_spheres(200, 0.3, box=12.0, seed=3, binary=(1.4, 0.25))
    r = np.sort(np.unique(np.round(s.radii, 12)))
    assert len(r) == 2 and r[1] / r[0] == pytest.approx(1.4) and np.sum(s.radii > r[0] * 1.2) == 50
    assert float(np.sum(4 / 3 * np.pi * s.radii**3)) / 12.0**3 == pytest.approx(0.3)
    d = cKDTree((s.positions + 6.0) % 12.0, boxsize=12.0).query_pairs(2 * r[1])
    assert all(
        np.linalg.norm(((s.positions[i] - s.positions[j]) + 6) % 12 - 6) >= s.radii[i] + s.radii[j]
        for i, j in d
    )
    new = hs.random_spheres(50, 0.2, box=10.0, seed=1, uniform_radius_ratio=2.0)
    old = hs.random_spheres(50, 0.2, box=10.0, seed=1, radius_ratio=2.0)
    assert np.array_equal(new.radii, old.radii) and np.array_equal(new.positions, old.positions)
    for kw in ({"binary": (0.5, 0.5)}, {"binary": (2.0, 1.5)}, {"binary": (2.0, 0.5), "radius_ratio": 2.0}):
        with pytest.raises(BuildError):
            hs.random_spheres(20, 0.2, box=10.0, **kw)
    done = hs_cmd("generate", "--n", 40, "--box", 8, "--packing", 0.2, "--binary", 1.4, 0.5)
    assert done.returncode == 0, done.stderr
    radii = sorted({line.split()[1] for line in done.stdout.splitlines() if line.strip()})
    assert len(radii) == 2
    assert (
        hs_cmd("generate", "--n", 40, "--box", 8, "--packing", 0.2, "--uniform-radius-ratio", 2).returncode
        == 0
    )


def test_the_perfect_crystals_are_at_the_package_root():
    """``hs.crystal`` (FCC, HCP) and ``hs.hexagonal`` (disks) beside ``hs.random_spheres``."""
    for name in ("crystal", "hexagonal", "random_spheres"):
        assert name in hs.__all__ and name in dir(hs), name
        assert getattr(hs, name) is getattr(builders, name)
    state, box = hs.crystal("fcc", (2, 2, 2), 0.5)
    assert state.n == 32 and box.sides == (box.sides[0],) * 3
    disks, box2d = hs.hexagonal((4, 4), 0.7)
    assert disks.n == 16 and disks.dimensions == 2 and len(box2d.sides) == 2


def test_the_user_guide_crystal_example_matches_speedy(tmp_path, monkeypatch, capsys):
    """The guide's crystal example (docs/guide/containers.md) runs and lands on Speedy's equation of state."""
    import re
    from pathlib import Path

    text = (Path(__file__).resolve().parents[1] / "docs" / "guide" / "containers.md").read_text()
    block = next(b for b in re.findall(r"```python\n(.*?)```", text, re.S) if "hs.crystal(" in b)
    monkeypatch.chdir(tmp_path)
    scope: dict = {}
    exec(compile(block, "containers.md", "exec"), scope)
    m = re.search(r"Z = (\d+\.\d+) \+- (\d+\.\d+); Speedy: (\d+\.\d+)", capsys.readouterr().out)
    assert m, "the example printed no comparison"
    z, sem, speedy = (float(g) for g in m.groups())
    assert abs(z - speedy) < 4 * sem
    assert scope["disks"].n == 1024

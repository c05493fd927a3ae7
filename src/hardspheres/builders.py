"""Scenario builders: many spheres at a chosen packing fraction.

Random insertion jams far below the densities people study, so spheres are
put on the sites of a face-centred cubic lattice (a random subset of its
sites), which reaches packing fractions up to 0.74 times the part of the
container the lattice can fill.  The lattice is sized by N, not by the
container: at most :data:`SITES_PER_SPHERE` sites per sphere, and never the
contact spacing unless nothing wider holds N (:func:`_target_sites`), so
neighbours start apart and the lattice melts within a few collisions per
sphere at fluid densities (15-20 at PHI = 0.45; benchmarks/README.md).
Memory goes with N (120-190 bytes per sphere at the peak), whatever the
container.  A few spheres (up to :data:`INSERTION_MAX`) whose lattice does
not fit the container are placed at random and pushed apart until none
overlap instead.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from .containers import MAX_PACKING, Container, as_container
from .containers import MAX_PACKING_2D as _MAX_PACKING_2D
from .errors import BuildError  # noqa: F401 (re-exported)
from .maxwell import maxwell_boltzmann
from .state import State

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

#: Random placement is tried for up to this many spheres when the lattice does not fit.
INSERTION_MAX = 500


#: The lattice holds at most this many sites per sphere (a random subset of
#: them is filled): memory in proportion to N, not to the container.
SITES_PER_SPHERE = 2


def _target_sites(n: int, most: float) -> float:
    """Sites to aim for when ``most`` fit at the contact spacing (``most >= n``).

    :data:`SITES_PER_SPHERE` per sphere where the container has room, else
    the geometric mean of ``n`` and ``most``: both a gap between neighbours
    (the spacing above contact by ``(most / n)^(1/6)``) and vacancies (a
    fraction ``1 - (n / most)^(1/2)``), so the lattice melts within a few
    collisions per sphere.  At the contact spacing itself, neighbours touch
    to within rounding and rattle at collision rates 10^7 times the fluid's
    without moving (measured: benchmarks/README.md, "A fluid to time").
    """
    return min(SITES_PER_SPHERE * n, np.sqrt(float(n) * max(most, n)))


#: Sites of the enclosing cube's lattice made per slab (bounds the memory of the filter).
_SLAB_SITES = 1 << 20

# the four sites of an FCC cell of edge 1, in the order the lattice lists them
_BASE = np.array([[0, 0, 0], [0.5, 0.5, 0], [0.5, 0, 0.5], [0, 0.5, 0.5]])


def _fcc(k: Any, a: Any, index: np.ndarray | None = None) -> np.ndarray:  # k, a: a number or a triple
    """FCC sites of ``k^3`` cubic cells of edge ``a``, centred on the origin.

    Site ``4 c + b`` is corner ``b`` of :data:`_BASE` in cell ``c`` (cells in
    x-major order); ``index`` picks some of the ``4 k^3`` sites (all if
    ``None``), so that only the sites used are ever made.  ``k`` and ``a``
    may be triples (cells per axis and their sides: a rectangular box).
    """
    kx, ky, kz = (k, k, k) if np.ndim(k) == 0 else (int(x) for x in k)
    if index is None:
        index = np.arange(4 * kx * ky * kz)
    cell, corner = np.divmod(np.asarray(index, dtype=np.int64), 4)
    cx, rest = np.divmod(cell, ky * kz)
    cy, cz = np.divmod(rest, kz)
    sites = np.stack((cx, cy, cz), axis=-1).astype(np.float64)
    del cell, cx, cy, cz, rest
    sites += _BASE[corner]
    if np.ndim(k) == 0:
        sites *= a  # in place, the same operations as sites * a - 0.5 k a + 0.25 a
        sites -= 0.5 * k * a
        sites += 0.25 * a
    else:
        a = np.asarray(a, dtype=np.float64)
        sites *= a
        sites -= 0.5 * np.asarray([kx, ky, kz]) * a
        sites += 0.25 * a
    return sites


def _whole_cells(sites: float) -> int:
    """Fewest cubic FCC cells per edge, ``k``, whose ``4 k^3`` sites number at least ``sites``."""
    k = max(1, int(np.ceil((sites / 4.0) ** (1.0 / 3.0))))
    while 4 * k**3 < sites:
        k += 1
    while k > 1 and 4 * (k - 1) ** 3 >= sites:
        k -= 1
    return k


def _box_lattice(n: int, side: float, a_min: float) -> tuple[int, float]:
    """``(k, edge)``: cells per edge of the periodic box's lattice and their edge.

    As few cells as hold :func:`_target_sites`, but no more than fit at the
    contact spacing ``a_min`` (whole cells tile the box, so the lattice
    continues across it).
    """
    k_max = int(np.floor(side / a_min))
    k = min(k_max, _whole_cells(_target_sites(n, 4 * k_max**3)))
    return k, (side / k if k >= 1 else 0.0)


def _rect_lattice(n: int, sides: ArrayLike, a_min: float) -> tuple[tuple[int, ...], tuple[float, ...]]:
    """``(k, edges)``: FCC cells per axis of a rectangular box's lattice and their sides.

    As in :func:`_box_lattice`: nearly cubic cells, as few as hold
    :func:`_target_sites` and none narrower than ``a_min``; whole cells tile
    each side.
    """
    sides = np.asarray(sides, dtype=np.float64)
    k_max = np.floor(sides / a_min).astype(np.int64)
    if np.any(k_max < 1):
        return (0, 0, 0), (0.0, 0.0, 0.0)
    want = _target_sites(n, 4 * int(np.prod(k_max)))
    cell = (float(np.prod(sides)) * 4.0 / want) ** (1.0 / 3.0)
    k = np.minimum(k_max, np.maximum(1, np.ceil(sides / cell).astype(np.int64)))
    while 4 * int(np.prod(k)) < want and np.any(k < k_max):
        # the axis whose cells are widest gets one more
        grow = np.where(k < k_max, sides / k, 0.0)
        k[int(np.argmax(grow))] += 1
    return tuple(int(x) for x in k), tuple(float(x) for x in sides / k)


def _ball_sites(k: int, a: float, where: Container, rmax: float) -> np.ndarray:
    """The sites of :func:`_fcc` ``(k, a)`` where a sphere of radius ``rmax`` is inside ``where``.

    Made slab by slab of cells, so that memory goes with the sites kept.
    """
    per_slab = 4 * k * k
    step = max(1, _SLAB_SITES // per_slab) * per_slab
    kept = []
    for start in range(0, 4 * k**3, step):
        sites = _fcc(k, a, np.arange(start, min(start + step, 4 * k**3)))
        kept.append(sites[~where.outside(sites, np.full(len(sites), rmax), tol=-1e-12)])
    return np.concatenate(kept) if kept else np.zeros((0, 3))


def _sphere_lattice(n: int, where: Container, rmax: float, a_min: float) -> np.ndarray:
    """Sites for ``n`` spheres of largest radius ``rmax`` in a spherical container.

    The spacing starts where the ball of reachable centres holds about
    :func:`_target_sites` (never below ``a_min``, the contact spacing) and
    shrinks until at least ``n`` sites fit, down to ``a_min``; returns the
    sites of the last try.
    """
    reach = where.half_width - rmax
    a = a_min
    if n and reach > 0.0:
        ball = 16.0 * np.pi * reach**3 / 3.0  # 4 sites per a^3 in the ball of radius reach
        a = max(a_min, (ball / _target_sites(n, ball / a_min**3)) ** (1.0 / 3.0))
    while True:
        k = int(np.ceil(2.0 * where.half_width / a)) + 1 if n else 1
        sites = _ball_sites(k, a, where, rmax)
        if len(sites) >= n or a <= a_min:
            return sites
        # as many more sites as lacked, and a tenth more (half the spacing if none fit):
        # the lattice never grows past a few sites per sphere before it holds N
        shrink = (len(sites) / (1.1 * n)) ** (1.0 / 3.0) if len(sites) else 0.5
        a = max(a_min, a * shrink)


def _insert(
    rng: np.random.Generator, radii: np.ndarray, container: Container, sweeps: int = 20000
) -> np.ndarray | None:
    """Random positions pushed apart until no two spheres overlap; ``None`` if they jam.

    The spheres start at random (inside the container) and every overlapping
    pair (nearest images in a periodic box), and every sphere poking through
    a wall, is moved apart by its overlap, sweep after sweep: a few hundred
    sweeps suffice for a handful of spheres at fluid packing fractions.
    """
    n = len(radii)
    grow = radii * (1.0 + 1e-6)  # keep a rounding margin at contact
    wall = 0.0 if container.periodic else container.core_params()["wall_radius"]
    if container.periodic:
        h = container.half_width if container.cube else 0.5 * np.array(container.sides)  # type: ignore[attr-defined]
        x = rng.uniform(-h, h, (n, 3))
    else:
        reach = wall - grow
        if np.any(reach < 0):
            return None
        x = rng.normal(size=(n, 3))
        x *= (reach * rng.uniform(size=n) ** (1.0 / 3.0) / np.linalg.norm(x, axis=1))[:, None]
    contact = grow[:, None] + grow[None, :]
    np.fill_diagonal(contact, 0.0)
    for _ in range(sweeps):
        d = container.displacement(x[:, None, :], x[None, :, :])
        dist = np.linalg.norm(d, axis=2)
        np.fill_diagonal(dist, np.inf)
        overlap = np.maximum(contact - dist, 0.0)
        out = np.zeros(n) if container.periodic else np.maximum(np.linalg.norm(x, axis=1) - reach, 0.0)
        if overlap.max() <= 0.0 and out.max() <= 0.0:
            return x
        dist = np.where(dist == 0.0, 1.0, dist)
        x += 0.55 * np.einsum("ij,ijk->ik", overlap / dist, d)  # half each, a little more
        if container.periodic:
            x = container.wrap(x)
        else:
            norm = np.linalg.norm(x, axis=1)
            far = norm > reach
            x[far] *= (reach[far] / norm[far])[:, None]
    return None


def _radii(rng: np.random.Generator, n: int, ratio: float) -> np.ndarray:
    if ratio == 1.0:
        return np.ones(n)
    return rng.uniform(1.0, ratio, n)


def random_spheres(
    n: int,
    packing: float,
    container: Container | float | None = None,
    box: float | tuple[float, ...] | None = None,
    seed: int | None = 0,
    radius_ratio: float = 1.0,
    mass_ratio: float = 1.0,
    kT: float = 1.0,
    *,
    uniform_radius_ratio: float | None = None,
    binary: tuple[float, float] | None = None,
) -> State:
    """N non-overlapping spheres filling the fraction ``packing`` of a container.

    Args:
        n: number of spheres.
        packing: volume fraction of the container the spheres fill.
        container: the :class:`~hardspheres.containers.Container` (or the
            radius of a spherical container [length]), or
        box: the edge of a periodic cubic box, or its sides ``(Lx, Ly, Lz)`` [length].
        seed: random seed (same seed, same scenario).
        uniform_radius_ratio: largest over smallest radius, radii uniform
            in between (uniform polydispersity; 1 = equal spheres).
        radius_ratio: the old name of ``uniform_radius_ratio``, kept.
        binary: ``(size_ratio, fraction)``: a binary mixture, the large
            spheres ``size_ratio`` times the small ones' radius and
            ``round(fraction n)`` of them in number (at random places).
            Not with a uniform radius ratio.
        mass_ratio: largest over smallest mass; masses are log-uniform in
            between (1 = all masses 1) [mass].
        kT: temperature of the Maxwell-Boltzmann velocities [energy].

    Returns:
        A :class:`State` with spheres named ``s0 ... s{n-1}``.

    Raises:
        BuildError: if the lattice cannot hold the spheres at that packing,
            or an argument is out of range (``kT < 0``, NaN, ...).

    Example:
        >>> from hardspheres import SphericalContainer
        >>> s = random_spheres(100, 0.3, SphericalContainer(10.0), seed=1)
        >>> s.n, round(float((s.radii ** 3).sum() / 10.0 ** 3), 6)
        (100, 0.3)
    """
    masses, radii, positions, velocities = random_arrays(
        n,
        packing,
        container,
        box,
        seed=seed,
        radius_ratio=radius_ratio,
        mass_ratio=mass_ratio,
        kT=kT,
        uniform_radius_ratio=uniform_radius_ratio,
        binary=binary,
    )
    return State.from_arrays(masses, radii, positions, velocities)


#: Bytes per sphere at the builder's peak (the lattice included), and a
#: run's: the engine's arrays, event calendar and cells or lists.
BUILD_BYTES_PER_SPHERE = 190


def machine_memory() -> int | None:
    """This machine's physical memory [bytes], or ``None`` where it cannot be read."""
    import os

    try:
        return int(os.sysconf("SC_PAGE_SIZE")) * int(os.sysconf("SC_PHYS_PAGES"))
    except (AttributeError, ValueError, OSError):
        return None


def _check_memory(n: int) -> None:
    """Refuse, before allocating, ``n`` spheres that cannot fit in this machine's memory."""
    mem = machine_memory()
    need = BUILD_BYTES_PER_SPHERE * n
    if mem is not None and need > mem:
        raise BuildError(
            f"n = {n:.3g} spheres need about {need / 2**30:.3g} GiB to build, and this machine has "
            f"{mem / 2**30:.3g} GiB: at most about {mem // BUILD_BYTES_PER_SPHERE:.2g} spheres fit"
        )


def random_arrays(
    n: int,
    packing: float,
    container: Container | float | None = None,
    box: float | tuple[float, ...] | None = None,
    seed: int | None = 0,
    radius_ratio: float = 1.0,
    mass_ratio: float = 1.0,
    kT: float = 1.0,
    *,
    uniform_radius_ratio: float | None = None,
    binary: tuple[float, float] | None = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """:func:`random_spheres` as bare arrays, without names or a :class:`State`.

    For millions of spheres (the benchmark): no Python object per sphere, and
    memory in proportion to N (120-190 bytes per sphere at the peak, the
    lattice included).  Same arguments, same spheres for the same seed.

    Longer than 80 lines with this docstring (about 65 of code).

    Returns:
        ``(masses, radii, positions, velocities)``: ``(N,)`` [mass], ``(N,)``
        [length], ``(N, 3)`` [length], ``(N, 3)`` [length/time].

    Example:
        >>> m, r, x, v = random_arrays(100, 0.3, 10.0, seed=1)
        >>> x.shape, bool((r == r[0]).all())
        ((100, 3), True)
    """
    if (container is None) == (box is None):
        raise BuildError("give exactly one of container and box")
    if not (isinstance(n, (int, np.integer)) and n >= 0):
        raise BuildError(f"n must be a whole number >= 0, got {n!r}")
    n = int(n)
    _check_memory(n)
    if uniform_radius_ratio is not None:
        if radius_ratio != 1.0:
            raise BuildError("give uniform_radius_ratio or its old name radius_ratio, not both")
        radius_ratio = uniform_radius_ratio
    if binary is not None:
        try:
            size_ratio, fraction = (float(x) for x in binary)
        except (TypeError, ValueError):
            raise BuildError(f"binary must be (size_ratio, fraction), got {binary!r}") from None
        if not (size_ratio >= 1.0 and np.isfinite(size_ratio) and 0.0 <= fraction <= 1.0):
            raise BuildError(
                f"binary: size ratio >= 1 and number fraction in [0, 1], got {size_ratio:g}, {fraction:g}"
            )
        if radius_ratio != 1.0:
            raise BuildError("give a binary mixture or a uniform radius ratio, not both")
    try:
        where = as_container(container, box)
    except ValueError as e:
        raise BuildError(str(e)) from None
    if getattr(where, "dimensions", 3) == 2:
        pair = None if binary is None else (size_ratio, fraction)
        return _random_disks(n, packing, where, seed, radius_ratio, mass_ratio, kT, pair)
    if not (0.0 < packing < MAX_PACKING):
        raise BuildError(f"packing fraction must be in (0, {MAX_PACKING:.4f}), got {packing}")
    if not (radius_ratio >= 1.0 and mass_ratio >= 1.0) or not np.isfinite(radius_ratio * mass_ratio):
        raise BuildError("radius and mass ratios must be >= 1")
    rng = np.random.default_rng(seed)
    volume = where.volume
    if binary is None:
        rel = _radii(rng, n, radius_ratio)
    else:
        rel = np.ones(n)
        rel[rng.permutation(n)[: int(round(fraction * n))]] = size_ratio
    scale = (packing * volume / ((4.0 / 3.0) * np.pi * np.sum(rel**3))) ** (1.0 / 3.0)
    radii = rel * scale
    rmax = float(radii.max()) if n else 0.0
    narrowest = min(where.sides) if where.periodic else 0.0  # type: ignore[attr-defined]
    if where.periodic and n and 6.0 * rmax > narrowest:
        raise BuildError(
            f"a periodic box must be at least three times the largest diameter wide "
            f"({6.0 * rmax:.3g}), not {narrowest:g}: lower the "
            "packing or raise N"
        )
    # contact spacing: nearest sites (a / sqrt 2) one largest diameter apart
    a_min = 2.0 * np.sqrt(2.0) * rmax * (1.0 + 1e-9)
    sites: np.ndarray | None = None
    k: int | tuple[int, ...] = 0
    edge: float | tuple[float, ...] = 0.0
    if n == 0:
        sites = np.zeros((0, 3))
        count = 0
    elif where.periodic and where.cube:  # type: ignore[attr-defined]
        k, edge = _box_lattice(n, 2.0 * where.half_width, a_min)
        count = 4 * k**3 if k >= 1 else 0
    elif where.periodic:
        k, edge = _rect_lattice(n, where.sides, a_min)  # type: ignore[attr-defined]
        count = 4 * int(np.prod(k))
    else:
        sites = _sphere_lattice(n, where, rmax, a_min)
        count = len(sites)
    positions = None
    if count < n and n <= INSERTION_MAX:
        positions = _insert(rng, radii, where)
    if positions is None and count < n:
        hint = f" (about {packing * count / n:.3g} fits)" if count else ""
        raise BuildError(
            f"only {count} lattice sites fit for {n} spheres at packing {packing}"
            + (" and random placement found no room" if n <= INSERTION_MAX else "")
            + f"; lower the packing{hint} or the radius ratio, or raise N"
        )
    if positions is None:
        chosen = np.sort(rng.choice(count, size=n, replace=False)) if n else np.zeros(0, int)
        positions = _fcc(k, edge, chosen) if sites is None else sites[chosen]
        del sites
    if mass_ratio == 1.0:
        masses = np.ones(n)
    else:
        masses = np.exp(rng.uniform(0.0, np.log(mass_ratio), n))
    velocities = maxwell_boltzmann(rng, masses, kT)
    return masses, radii, positions, velocities


# the lattices' cells: sides in nearest-neighbour distances, and sites in fractions of them
_CELLS = {
    # the cubic cell of FCC, side sqrt(2) neighbour distances
    "fcc": (np.sqrt(2.0) * np.ones(3), _BASE),
    # the orthorhombic cell of HCP: a, sqrt(3) a, sqrt(8/3) a, layers A B A ... along z
    "hcp": (
        np.array([1.0, np.sqrt(3.0), np.sqrt(8.0 / 3.0)]),
        np.array([[0.0, 0.0, 0.0], [0.5, 0.5, 0.0], [0.5, 5.0 / 6.0, 0.5], [0.0, 1.0 / 3.0, 0.5]]),
    ),
}


def crystal(
    lattice: str,
    cells: tuple[int, int, int],
    packing: float,
    radius: float = 0.5,
    kT: float = 1.0,
    seed: int | None = 0,
) -> tuple[State, Container]:
    """A perfect FCC or HCP crystal filling a periodic box of whole cells.

    Args:
        lattice: ``"fcc"`` (cubic cells of 4 sites) or ``"hcp"``
            (orthorhombic cells of 4 sites, sides ``a, sqrt(3) a, sqrt(8/3) a``
            for neighbours ``a`` apart: the box is not a cube).
        cells: cells per axis.
        packing: volume fraction, up to close packing (``pi / sqrt(18)``).
        radius: the spheres' radius [length].
        kT: temperature of the Maxwell-Boltzmann velocities [energy].
        seed: random seed of the velocities.

    Returns:
        ``(state, box)``: the spheres and their :class:`~hardspheres.PeriodicBox`.

    Example:
        >>> s, box = crystal("hcp", (4, 2, 2), 0.5)
        >>> s.n, [round(x, 4) for x in box.sides]
        (64, [4.5594, 3.9486, 3.7227])
    """
    from .containers import PeriodicBox

    if lattice not in _CELLS:
        raise BuildError(f"lattice {lattice!r}: give 'fcc' or 'hcp'")
    try:
        k = np.array([int(c) for c in cells])
    except (TypeError, ValueError):
        raise BuildError(f"cells {cells!r}: give three whole numbers >= 1") from None
    if k.shape != (3,) or np.any(k < 1):
        raise BuildError(f"cells {cells!r}: give three whole numbers >= 1")
    if not (0.0 < packing <= MAX_PACKING):
        raise BuildError(f"packing fraction must be in (0, {MAX_PACKING:.6f}] for a crystal, got {packing}")
    if not (radius > 0.0 and np.isfinite(radius)):
        raise BuildError(f"radius must be a finite number > 0, got {radius}")
    unit, base = _CELLS[lattice]
    a = 2.0 * radius * (MAX_PACKING / packing) ** (1.0 / 3.0)  # neighbour distance
    side = unit * a
    idx = np.stack(np.meshgrid(*(np.arange(x) for x in k), indexing="ij"), axis=-1).reshape(-1, 1, 3)
    frac = (idx + base[None, :, :]).reshape(-1, 3)
    sides = k * side
    positions = frac * side - 0.5 * sides + 0.25 * side  # off the box's faces
    box = PeriodicBox(tuple(float(x) for x in sides))
    positions = box.wrap(positions)
    n = len(positions)
    rng = np.random.default_rng(seed)
    masses = np.ones(n)
    velocities = maxwell_boltzmann(rng, masses, kT)
    return State.from_arrays(masses, np.full(n, float(radius)), positions, velocities), box


#: The densest packing of equal disks (the triangular lattice), :data:`hardspheres.containers.MAX_PACKING_2D`.
MAX_PACKING_2D = _MAX_PACKING_2D

#: Random disks are built up to this area fraction (a random subset of a
#: triangular lattice's sites; denser: compress, or the hexagonal crystal).
RANDOM_DISKS_MAX = 0.72


def _triangular(kx: int, ky: int, ax: float, ay: float, shift: np.ndarray) -> np.ndarray:
    """``kx`` by ``ky`` sites, rows ``ay`` apart, odd rows shifted by half of ``ax``, minus ``shift``."""
    j, i = np.divmod(np.arange(kx * ky), kx)
    return np.column_stack([(i + 0.5 * (j % 2)) * ax, j * ay]) - shift


def _disk_sites(n: int, where: Container, rmax: float) -> np.ndarray | None:
    """Sites of a triangular lattice for ``n`` disks of largest radius ``rmax``, about 2 per disk.

    A periodic box: whole rows (an even number) tiling it, their spacing as
    near the triangular lattice's as the box allows; a circle: the lattice
    inside ``R - rmax``.  ``None`` if fewer than ``n`` sites fit without
    two disks touching.
    """
    a_min = 2.0 * rmax * (1.0 + 1e-9)
    if where.periodic:
        lx, ly = where.sides  # type: ignore[attr-defined]
        most = max(1, int(lx / a_min)) * max(2, 2 * int(ly / (a_min * np.sqrt(3.0))))
        m = _target_sites(n, max(most, n))
        kx = max(1, int(round(np.sqrt(m * np.sqrt(3.0) * lx / (2.0 * ly)))))
        ky = max(2, 2 * int(np.ceil(m / kx / 2.0)))
        while kx * ky >= n:
            ax, ay = lx / kx, ly / ky
            if min(ax, np.hypot(0.5 * ax, ay)) >= a_min:
                return _triangular(kx, ky, ax, ay, np.array([0.5 * lx - 0.25 * ax, 0.5 * ly - 0.5 * ay]))
            # too close along one way: fewer sites that way
            if ax < np.hypot(0.5 * ax, ay):
                kx -= 1
            else:
                ky -= 2
        return None
    reach = where.radius - rmax  # type: ignore[attr-defined]
    if reach <= 0.0:
        return None if n else np.zeros((0, 2))
    a = max(a_min, np.sqrt(2.0 * np.pi * reach * reach / (np.sqrt(3.0) * max(2 * n, 1))))
    while True:
        k = int(reach / a) + 2
        sites = _triangular(
            2 * k + 1,
            2 * k + 2,
            a,
            a * np.sqrt(3.0) / 2.0,
            np.array([k * a, (k + 1) * a * np.sqrt(3.0) / 2.0]),
        )
        sites = sites[np.linalg.norm(sites, axis=1) <= reach * (1.0 - 1e-12)]
        if len(sites) >= n:
            return sites
        if a <= a_min:
            return None
        a = max(a_min, a * 0.97)


def _random_disks(
    n: int,
    packing: float,
    where: Container,
    seed: int | None,
    radius_ratio: float,
    mass_ratio: float,
    kT: float,
    binary: tuple[float, float] | None = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """:func:`random_arrays` in 2-D: disks on a random subset of a triangular lattice's sites.

    ``binary = (size_ratio, fraction)`` as for spheres: ``round(fraction n)``
    disks (at random) ``size_ratio`` times the others' radius.
    """
    if not (0.0 < packing <= RANDOM_DISKS_MAX):
        raise BuildError(
            f"area fraction must be in (0, {RANDOM_DISKS_MAX}] for random disks, got {packing}; "
            "denser: compress, or crystal('hexagonal', ...)"
        )
    if not (radius_ratio >= 1.0 and mass_ratio >= 1.0) or not np.isfinite(radius_ratio * mass_ratio):
        raise BuildError("radius and mass ratios must be >= 1")
    rng = np.random.default_rng(seed)
    if binary is None:
        rel = _radii(rng, n, radius_ratio)
    else:
        rel = np.ones(n)
        rel[rng.permutation(n)[: int(round(binary[1] * n))]] = binary[0]
    radii = rel * np.sqrt(packing * where.volume / (np.pi * np.sum(rel**2))) if n else rel
    rmax = float(radii.max()) if n else 0.0
    if where.periodic and n and 6.0 * rmax > min(where.sides):  # type: ignore[attr-defined]
        raise BuildError(
            f"a periodic box must be at least three times the largest diameter wide ({6.0 * rmax:.3g}), "
            f"not {min(where.sides):g}: lower the packing or raise N"  # type: ignore[attr-defined]
        )
    sites = _disk_sites(n, where, rmax) if n else np.zeros((0, 2))
    if sites is None:
        raise BuildError(
            f"no triangular lattice holds {n} disks at area fraction {packing} in this container; "
            "lower the packing or the radius ratio, or change the box's shape"
        )
    chosen = np.sort(rng.choice(len(sites), size=n, replace=False)) if n else np.zeros(0, int)
    positions = where.wrap(sites[chosen])
    masses = np.ones(n) if mass_ratio == 1.0 else np.exp(rng.uniform(0.0, np.log(mass_ratio), n))
    velocities = maxwell_boltzmann(rng, masses, kT, dimensions=2)
    return masses, radii, positions, velocities


def hexagonal(
    cells: tuple[int, int], packing: float, radius: float = 0.5, kT: float = 1.0, seed: int | None = 0
) -> tuple[State, Container]:
    """A perfect hexagonal (triangular) crystal of disks filling a periodic 2-D box.

    ``cells = (nx, ny)``: ``nx`` disks per row, ``ny`` rows (even); the box
    is ``nx a`` by ``ny a sqrt(3)/2`` for neighbours ``a`` apart, so
    ``nx = ny`` gives the ``sqrt(3)/2`` box the crystal needs.

    Example:
        >>> s, box = hexagonal((4, 4), 0.7)
        >>> s.n, round(box.sides[1] / box.sides[0], 6)
        (16, 0.866025)
    """
    from .containers import PeriodicBox

    try:
        nx, ny = (int(c) for c in cells)
    except (TypeError, ValueError):
        raise BuildError(f"cells {cells!r}: give two whole numbers, the second even") from None
    if nx < 1 or ny < 2 or ny % 2:
        raise BuildError(f"cells {cells!r}: give two whole numbers >= 1, the second even (rows pair up)")
    if not (0.0 < packing <= MAX_PACKING_2D):
        raise BuildError(f"area fraction must be in (0, {MAX_PACKING_2D:.6f}] for a crystal, got {packing}")
    if not (radius > 0.0 and np.isfinite(radius)):
        raise BuildError(f"radius must be a finite number > 0, got {radius}")
    a = 2.0 * radius * np.sqrt(MAX_PACKING_2D / packing)
    ay = a * np.sqrt(3.0) / 2.0
    box = PeriodicBox((nx * a, ny * ay))
    positions = box.wrap(
        _triangular(nx, ny, a, ay, np.array([0.5 * nx * a - 0.25 * a, 0.5 * ny * ay - 0.5 * ay]))
    )
    n = nx * ny
    masses = np.ones(n)
    velocities = maxwell_boltzmann(np.random.default_rng(seed), masses, kT, dimensions=2)
    return State.from_arrays(masses, np.full(n, float(radius)), positions, velocities), box

"""Scenario builders: many spheres at a chosen packing fraction.

Random insertion jams far below the densities people study, so spheres are
put on the sites of a face-centred cubic lattice (a random subset of the
sites that fit), which reaches packing fractions up to 0.74 times the part
of the container the lattice can fill.  At fluid densities the lattice melts
within a few collisions per sphere.  A few spheres (up to
:data:`INSERTION_MAX`) whose lattice does not fit the container are placed
at random and pushed apart until none overlap instead.
"""

from __future__ import annotations

import numpy as np

from .containers import Container, as_container
from .maxwell import maxwell_boltzmann
from .state import State


#: Random placement is tried for up to this many spheres when the lattice does not fit.
INSERTION_MAX = 500


class BuildError(ValueError):
    """The requested scenario cannot be built; the message says what to change."""


def _fcc(k, a):
    """FCC sites of ``k^3`` cubic cells of edge ``a``, centred on the origin."""
    base = np.array([[0, 0, 0], [0.5, 0.5, 0], [0.5, 0, 0.5], [0, 0.5, 0.5]])
    g = np.arange(k)
    cells = np.stack(np.meshgrid(g, g, g, indexing="ij"), axis=-1).reshape(-1, 1, 3)
    sites = (cells + base).reshape(-1, 3) * a
    return sites - 0.5 * k * a + 0.25 * a


def _insert(rng, radii, container, sweeps=20000):
    """Random positions pushed apart until no two spheres overlap; ``None`` if they jam.

    The spheres start at random (inside the container) and every overlapping
    pair (nearest images in a periodic box), and every sphere poking through
    a wall, is moved apart by its overlap, sweep after sweep: a few hundred
    sweeps suffice for a handful of spheres at fluid packing fractions.
    """
    n = len(radii)
    grow = radii * (1.0 + 1e-6)  # keep a rounding margin at contact
    params = container.core_params()
    wall = params["wall_radius"]
    if container.periodic:
        h = container.half_width
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
        out = (np.zeros(n) if container.periodic
               else np.maximum(np.linalg.norm(x, axis=1) - reach, 0.0))
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


def _radii(rng, n, ratio):
    if ratio == 1.0:
        return np.ones(n)
    return rng.uniform(1.0, ratio, n)


def random_spheres(n: int, packing: float, container: Container | float | None = None,
                   box: float | None = None, seed: int | None = 0, radius_ratio: float = 1.0,
                   mass_ratio: float = 1.0, kT: float = 1.0) -> State:
    """N non-overlapping spheres filling the fraction ``packing`` of a container.

    Args:
        n: number of spheres.
        packing: volume fraction of the container the spheres fill.
        container: the :class:`~hardspheres.containers.Container` (or the
            radius of a spherical container [length]), or
        box: the edge of a periodic cubic box [length].
        seed: random seed (same seed, same scenario).
        radius_ratio: largest over smallest radius; radii are uniform in
            between (1 = equal spheres).
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
    if (container is None) == (box is None):
        raise BuildError("give exactly one of container and box")
    if not (isinstance(n, (int, np.integer)) and n >= 0):
        raise BuildError(f"n must be a whole number >= 0, got {n!r}")
    try:
        where = as_container(container, box)
    except ValueError as e:
        raise BuildError(str(e)) from None
    if not (0.0 < packing < 0.74):
        raise BuildError(f"packing fraction must be in (0, 0.74), got {packing}")
    if not (radius_ratio >= 1.0 and mass_ratio >= 1.0) or not np.isfinite(
            radius_ratio * mass_ratio):
        raise BuildError("radius and mass ratios must be >= 1")
    rng = np.random.default_rng(seed)
    volume = where.volume
    rel = _radii(rng, n, radius_ratio)
    scale = (packing * volume / ((4.0 / 3.0) * np.pi * np.sum(rel ** 3))) ** (1.0 / 3.0)
    radii = rel * scale
    rmax = radii.max() if n else 0.0
    # lattice constant: nearest sites (a / sqrt 2) one largest diameter apart
    a = 2.0 * np.sqrt(2.0) * rmax * (1.0 + 1e-9)
    if where.periodic:
        # whole cells that tile the box, so the lattice continues across it
        side = 2.0 * where.half_width
        k = int(np.floor(side / a))
        sites = _fcc(k, side / k) if k >= 1 else np.zeros((0, 3))
    else:
        # a lattice over the enclosing cube, less the sites whose sphere pokes out
        k = int(np.ceil(2.0 * where.half_width / a)) + 1 if n else 1
        sites = _fcc(k, a)
        sites = sites[~where.outside(sites, np.full(len(sites), rmax), tol=-1e-12)]
    if where.periodic and n and 6.0 * rmax > 2.0 * where.half_width:
        raise BuildError(f"a periodic box must be at least three largest diameters wide "
                         f"({6.0 * rmax:.3g}), not {2.0 * where.half_width:g}: lower the "
                         "packing or raise N")
    positions = None
    if len(sites) < n and n <= INSERTION_MAX:
        positions = _insert(rng, radii, where)
    if positions is None and len(sites) < n:
        hint = (f" (about {packing * len(sites) / n:.3g} fits)" if len(sites) else "")
        raise BuildError(
            f"only {len(sites)} lattice sites fit for {n} spheres at packing {packing}"
            + (" and random placement found no room" if n <= INSERTION_MAX else "")
            + f"; lower the packing{hint} or the radius ratio, or raise N")
    if positions is None:
        chosen = rng.choice(len(sites), size=n, replace=False) if n else np.zeros(0, int)
        positions = sites[np.sort(chosen)]
    if mass_ratio == 1.0:
        masses = np.ones(n)
    else:
        masses = np.exp(rng.uniform(0.0, np.log(mass_ratio), n))
    velocities = maxwell_boltzmann(rng, masses, kT)
    return State.from_arrays(masses, radii, positions, velocities)

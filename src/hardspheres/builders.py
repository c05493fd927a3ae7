"""Scenario builders: many spheres at a chosen packing fraction.

Random insertion jams far below the densities people study, so spheres are
put on the sites of a face-centred cubic lattice (a random subset of the
sites that fit), which reaches packing fractions up to 0.74 times the part
of the container the lattice can fill.  At fluid densities the lattice melts
within a few collisions per sphere.  A few spheres (up to
:data:`INSERTION_MAX`) whose lattice does not fit the container are placed
at random and pushed apart until none overlap instead.
"""

import numpy as np

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


def _insert(rng, radii, container, box, sweeps=20000):
    """Random positions pushed apart until no two spheres overlap; ``None`` if they jam.

    The spheres start at random (inside the container) and every overlapping
    pair, and every sphere poking through the wall, is moved apart by its
    overlap, sweep after sweep: a few hundred sweeps suffice for a handful
    of spheres at fluid packing fractions.
    """
    n = len(radii)
    grow = radii * (1.0 + 1e-6)  # keep a rounding margin at contact
    if box is None:
        reach = container - grow
        if np.any(reach < 0):
            return None
        x = rng.normal(size=(n, 3))
        x *= (reach * rng.uniform(size=n) ** (1.0 / 3.0) / np.linalg.norm(x, axis=1))[:, None]
    else:
        x = rng.uniform(-0.5 * box, 0.5 * box, (n, 3))
    contact = grow[:, None] + grow[None, :]
    np.fill_diagonal(contact, 0.0)
    for _ in range(sweeps):
        d = x[:, None, :] - x[None, :, :]
        if box is not None:
            d -= box * np.round(d / box)
        dist = np.linalg.norm(d, axis=2)
        np.fill_diagonal(dist, np.inf)
        overlap = np.maximum(contact - dist, 0.0)
        wall = (np.maximum(np.linalg.norm(x, axis=1) - reach, 0.0) if box is None
                else np.zeros(n))
        if overlap.max() <= 0.0 and wall.max() <= 0.0:
            return x
        dist = np.where(dist == 0.0, 1.0, dist)
        x += 0.55 * np.einsum("ij,ijk->ik", overlap / dist, d)  # half each, a little more
        if box is None:
            norm = np.linalg.norm(x, axis=1)
            far = norm > reach
            x[far] *= (reach[far] / norm[far])[:, None]
        else:
            x -= box * np.floor(x / box + 0.5)
    return None


def _radii(rng, n, ratio):
    if ratio == 1.0:
        return np.ones(n)
    return rng.uniform(1.0, ratio, n)


def maxwell_boltzmann(rng, masses, kT=1.0):
    """Velocities drawn at temperature ``kT`` [energy], total momentum zero.

    The draw is rescaled so that the kinetic energy is exactly
    ``3/2 (N - 1) kT`` (zero momentum removes three degrees of freedom).

    Returns:
        ``(N, 3)`` velocities [length/time].

    Raises:
        BuildError: ``kT`` is not a finite number >= 0.
    """
    if not (np.isfinite(kT) and kT >= 0):
        raise BuildError(f"kT must be a finite number >= 0 [energy], got {kT!r}")
    n = len(masses)
    v = rng.normal(size=(n, 3)) * np.sqrt(kT / masses)[:, None]
    if n > 1:
        v -= (masses @ v) / masses.sum()
        ke = 0.5 * np.sum(masses * np.sum(v * v, axis=1))
        if ke > 0:
            v *= np.sqrt(1.5 * (n - 1) * kT / ke)
    else:
        v[:] = 0.0
    return v


def random_spheres(n, packing, container=None, box=None, seed=0, radius_ratio=1.0,
                   mass_ratio=1.0, kT=1.0):
    """N non-overlapping spheres filling the fraction ``packing`` of a container.

    Args:
        n: number of spheres.
        packing: volume fraction of the container the spheres fill.
        container: radius of the spherical container [length], or
        box: edge of the periodic cubic box [length].
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
        >>> s = random_spheres(100, 0.3, container=10.0, seed=1)
        >>> s.n, round(float((s.radii ** 3).sum() / 10.0 ** 3), 6)
        (100, 0.3)
    """
    if (container is None) == (box is None):
        raise BuildError("give exactly one of container and box")
    for what, x in (("container", container), ("box", box)):
        if x is not None and not (np.isfinite(x) and x > 0):
            raise BuildError(f"{what} must be a finite number > 0 [length], got {x!r}")
    if not (isinstance(n, (int, np.integer)) and n >= 0):
        raise BuildError(f"n must be a whole number >= 0, got {n!r}")
    if not (0.0 < packing < 0.74):
        raise BuildError(f"packing fraction must be in (0, 0.74), got {packing}")
    if not (radius_ratio >= 1.0 and mass_ratio >= 1.0) or not np.isfinite(
            radius_ratio * mass_ratio):
        raise BuildError("radius and mass ratios must be >= 1")
    rng = np.random.default_rng(seed)
    volume = (4.0 / 3.0) * np.pi * container ** 3 if box is None else box ** 3
    rel = _radii(rng, n, radius_ratio)
    scale = (packing * volume / ((4.0 / 3.0) * np.pi * np.sum(rel ** 3))) ** (1.0 / 3.0)
    radii = rel * scale
    rmax = radii.max() if n else 0.0
    # lattice constant: nearest sites (a / sqrt 2) one largest diameter apart
    a = 2.0 * np.sqrt(2.0) * rmax * (1.0 + 1e-9)
    if box is None:
        k = int(np.ceil(2.0 * container / a)) + 1 if n else 1
        sites = _fcc(k, a)
        reach = container - rmax
        sites = sites[np.linalg.norm(sites, axis=1) <= reach * (1.0 - 1e-12)]
    else:
        k = int(np.floor(box / a))
        if k < 1:
            sites = np.zeros((0, 3))
        else:
            sites = _fcc(k, box / k)
    if box is not None and n and 6.0 * rmax > box:
        raise BuildError(f"a periodic box must be at least three largest diameters wide "
                         f"({6.0 * rmax:.3g}), not {box:g}: lower the packing or raise N")
    positions = None
    if len(sites) < n and n <= INSERTION_MAX:
        positions = _insert(rng, radii, container, box)
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

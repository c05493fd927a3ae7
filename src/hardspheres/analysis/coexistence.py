"""Direct coexistence: an FCC slab against a fluid slab in an elongated box, and their profiles along it.

:func:`crystal_fluid_slab` builds the box: an FCC crystal with its (100) or
(111) planes normal to z, and beside it (along z) a fluid at its own
packing, melted first in a periodic box of its own; its spheres that
overlap the crystal's faces are taken out.  Run it at constant normal
pressure (``hs.Barostat(pressure=P, axes="z")``: the cross-section stays
the crystal's) and the crystal grows above the coexistence pressure and
melts below it (Fernandez et al., Phys. Rev. Lett. 108, 165701 (2012):
``beta P sigma^3 = 11.5727(10)``; validation/coexistence.py).
:func:`slab_profile` bins the spheres along z: the packing of each bin and
the fraction of crystal-like spheres by local q6 bond order
(:class:`hardspheres.analysis.structure.BondOrder`, ten Wolde et al.), so
the crystal's extent is ``crystal_like.sum() / N`` of the box.

Example:
    >>> state, box = crystal_fluid_slab((3, 3, 4), plane="100", fluid_packing=0.45, seed=1)
    >>> box.sides[2] > box.sides[0] == box.sides[1], state.n > 144
    (True, True)
"""

from __future__ import annotations

import math

import numpy as np

from ..builders import crystal
from ..containers import MAX_PACKING, PeriodicBox
from ..errors import AnalysisInputError, BuildError
from ..simulation import Simulation
from ..state import State
from .structure import BondOrder


#: The densest fluid placed at random (lattice sites fit up to about 0.48 in a cube,
#: less in some slabs); denser is compressed.
FLUID_START_MAX = 0.42


def _fcc_111(cells: tuple[int, int, int], packing: float) -> tuple[np.ndarray, tuple[float, float, float]]:
    """FCC sites with (111) planes normal to z: ``cells`` = (per row, rows (even), layers (of 3))."""
    nx, ny, nz = cells
    if ny % 2 or nz % 3:
        raise BuildError(f"cells {cells!r} for plane 111: rows even and layers a multiple of 3 (ABC)")
    a = (MAX_PACKING / packing) ** (1.0 / 3.0)  # neighbour distance, diameter 1
    ay = a * math.sqrt(3.0) / 2.0
    dz = a * math.sqrt(2.0 / 3.0)
    sides = (nx * a, ny * ay, nz * dz)
    layers = []
    for k in range(nz):
        shift = np.array([0.5 * sides[0], 0.5 * sides[1]]) - (k % 3) * np.array([0.5 * a, ay / 3.0])
        j, i = np.divmod(np.arange(nx * ny), nx)
        xy = np.column_stack([(i + 0.5 * (j % 2)) * a, j * ay]) - shift
        layers.append(np.column_stack([xy, np.full(nx * ny, (k + 0.5) * dz - 0.5 * sides[2])]))
    return np.concatenate(layers), sides


def crystal_fluid_slab(
    cells: tuple[int, int, int],
    plane: str = "100",
    crystal_packing: float = 0.545,
    fluid_packing: float = 0.49,
    fluid_length: float | None = None,
    seed: int = 0,
    fill: bool = True,
) -> tuple[State, PeriodicBox]:
    """An FCC slab and a fluid slab side by side along z in one periodic box (diameter 1, mass 1, kT = 1).

    Args:
        cells: the crystal's cells: cubic FCC cells (x, y, z) for ``plane =
            "100"``; for ``"111"`` (spheres per row, rows (even), layers (a
            multiple of 3)).
        plane: ``"100"`` or ``"111"``, the crystal plane normal to z.
        crystal_packing: the crystal's packing (coexistence: 0.5433).
        fluid_packing: the fluid's (coexistence: 0.4917), at most 0.5:
            built by :func:`equilibrated_fluid` in a periodic box of its
            own with the crystal's cross-section (compressed there from
            :data:`FLUID_START_MAX` when above it), before the two are joined.
        fluid_length: the fluid slab's length along z (default: the
            crystal's).
        seed: seeds the fluid's placement and every velocity.
        fill: the fluid's spheres that overlap the crystal's faces are taken
            out, which leaves the fluid short of ``fluid_packing`` (by about
            half a layer at each face); with ``fill`` (the default) the fluid
            is built a second time with as many spheres more as the first
            lost, so that the fluid slab holds ``fluid_packing`` on average
            (denser in its middle at first, until it spreads into the faces'
            hollows: a few time units).

    Returns:
        ``(state, box)``: the crystal's spheres first, then the fluid's.
    """
    if plane == "100":
        st, cbox = crystal("fcc", cells, crystal_packing, seed=seed)
        xc, sides = st.positions, tuple(float(x) for x in cbox.gsd_box[:3])
    elif plane == "111":
        xc, sides = _fcc_111(cells, crystal_packing)
    else:
        raise BuildError(f"plane {plane!r}: give '100' or '111'")
    if not 0.0 < fluid_packing <= 0.5:
        raise BuildError(f"fluid_packing must be in (0, 0.5], got {fluid_packing!r}")
    lx, ly, lc = (float(s) for s in sides)
    lf = lc if fluid_length is None else float(fluid_length)
    total = lc + lf
    box = PeriodicBox((lx, ly, total))
    xc = np.array(xc, dtype=float)
    xc[:, 2] += -0.5 * total + 0.5 * lc  # the crystal at the bottom
    xc = box.wrap(xc)
    packing = fluid_packing
    for _ in range(2 if fill else 1):
        xf = equilibrated_fluid((lx, ly, lf), packing, seed=seed)
        xf[:, 2] += -0.5 * total + lc + 0.5 * lf
        xf = box.wrap(xf)
        clash = _clashes(box, xc, xf, lc)
        # the fluid's spheres that overlap the crystal's faces go (no gap: a gap
        # lets the crystal expand into it and melt before the fluid fills it);
        # with ``fill`` the fluid is built again with as many more spheres
        packing = (len(xf) + len(clash)) * math.pi / 6.0 / (lx * ly * lf)
    xf = np.delete(xf, clash, axis=0)
    x = np.concatenate([xc, xf])
    n = len(x)
    rng = np.random.default_rng(seed)
    v = rng.normal(size=(n, 3))
    v -= v.mean(axis=0)
    v *= math.sqrt(3.0 * (n - 1) / float(np.sum(v * v)))  # kT = 1 exactly
    return State.from_arrays(np.ones(n), np.full(n, 0.5), x, v), box


def equilibrated_fluid(
    sides: tuple[float, float, float], packing: float, seed: int = 0, collisions_per_sphere: float = 30.0
) -> np.ndarray:
    """Centres of a fluid of diameter-1 spheres at ``packing`` in a periodic box of ``sides``.

    Random spheres start on lattice sites, which fit only up to about
    0.48: they are placed at :data:`FLUID_START_MAX` at most (smaller
    radii when ``packing`` is above it; 5 % lower again, as often as the
    sites of a small or flat box need), melted by ``collisions_per_sphere``
    collisions per sphere, compressed (Lubachevsky-Stillinger, radii
    growing: :meth:`Simulation.compress`) until their diameter is 1 (to a
    part in 10^9 above, then set to 1 exactly: no overlap), and run as many
    collisions again at diameter 1.

    Returns:
        ``(n, 3)`` centres, ``n = round(packing V / (pi / 6))``.
    """
    volume = float(np.prod(sides))
    n = int(round(packing * volume / (math.pi / 6.0)))
    if n < 2:
        raise BuildError(f"fluid box {sides!r} at packing {packing!r} holds fewer than 2 spheres")
    box = PeriodicBox(tuple(float(x) for x in sides))
    target = n * math.pi / 6.0 / volume  # the packing of n spheres of diameter 1
    start = min(target, FLUID_START_MAX)
    from ..builders import random_spheres

    while True:
        try:
            placed = random_spheres(n, start, box, seed=seed)
            break
        except BuildError:  # the lattice's sites do not fit this box's shape: place them smaller
            if start < 0.2:
                raise
            start *= 0.95
    sim = Simulation(placed, box)
    sim.run(collisions=int(collisions_per_sphere * n))  # the lattice it starts from melts
    if start < target:
        res = sim.compress(packing=target * (1.0 + 1e-9), rate=0.01)
        if res.reason != "packing":
            raise BuildError(f"the fluid's compression to {target:.4f} stopped on {res.reason!r}")
        st = sim.state()
        st = State.from_arrays(st.masses, np.full(n, 0.5), st.positions, st.velocities)
        sim = Simulation(st, box)
        sim.run(collisions=int(collisions_per_sphere * n))  # at diameter 1
    return np.array(sim.state().positions, dtype=float)


def _clashes(box: PeriodicBox, xc: np.ndarray, xf: np.ndarray, lc: float) -> np.ndarray:
    """Indices of the fluid's centres ``xf`` closer than 1 to a crystal centre ``xc`` across its faces."""
    total = box.sides[2]
    near_c = np.flatnonzero(_face_distance(xc[:, 2], lc, total) < 1.0)
    near_f = np.flatnonzero(_face_distance(xf[:, 2], lc, total) < 1.0)
    d = box.displacement(xf[near_f][:, None, :], xc[near_c][None, :, :])
    return near_f[(np.sum(d * d, axis=-1) < 1.0).any(axis=1)]


def _face_distance(z: np.ndarray, lc: float, total: float) -> np.ndarray:
    """Distance along z to the nearer of the crystal's two faces (at ``-total/2`` and ``-total/2 + lc``)."""
    low = -0.5 * total
    a = np.abs(z - low)
    a = np.minimum(a, total - a)
    b = np.abs(z - (low + lc))
    return np.minimum(a, np.minimum(b, total - b))


class SlabProfile:
    """Packing and crystal fraction in bins along z of a periodic box (see the module docstring).

    Attributes (after :meth:`compute`): ``z`` bin centres, ``packing`` per
    bin, ``crystal`` (fraction of crystal-like spheres per bin),
    ``crystal_like`` per sphere, ``crystal_fraction`` of all spheres.
    """

    def __init__(self, bins: int = 40) -> None:
        if not (isinstance(bins, int) and bins >= 2):
            raise AnalysisInputError(f"bins must be a whole number >= 2, got {bins!r}")
        self.bins = bins

    def compute(self, sim: Simulation) -> SlabProfile:
        """The profiles of ``sim`` now; returns self."""
        box = sim.container
        if not isinstance(box, PeriodicBox) or box.dimensions != 3:
            raise AnalysisInputError(
                f"SlabProfile needs the slab's 3-D periodic box, got {box!r}: "
                "build one with crystal_fluid_slab"
            )
        sides = box.sides
        st = sim.state()
        z = st.positions[:, 2] + 0.5 * sides[2]
        edges = np.linspace(0.0, sides[2], self.bins + 1)
        which = np.clip(np.digitize(z, edges) - 1, 0, self.bins - 1)
        vol = sides[0] * sides[1] * sides[2] / self.bins
        solid = np.bincount(which, weights=4.0 / 3.0 * math.pi * st.radii**3, minlength=self.bins)
        order = BondOrder(num_neighbors=12).compute(sim)
        like = np.asarray(order.crystal_like, dtype=bool)
        count = np.bincount(which, minlength=self.bins)
        hits = np.bincount(which, weights=like.astype(float), minlength=self.bins)
        self.z = 0.5 * (edges[1:] + edges[:-1]) - 0.5 * sides[2]
        self.packing = solid / vol
        self.crystal = np.where(count > 0, hits / np.maximum(count, 1), 0.0)
        self.crystal_like = like
        self.crystal_fraction = float(like.mean())
        return self

    def plateaus(self, solid: float = 0.95, fluid: float = 0.05) -> tuple[float, float]:
        """Mean packing of the bins well inside the crystal and well inside the fluid (after :meth:`compute`).

        A bin is inside the crystal when it and both its neighbours (along
        z, periodic) have a crystal fraction of at least ``solid``; inside
        the fluid when all three are at most ``fluid``: the interfaces'
        bins are left out.

        Returns:
            ``(crystal's packing, fluid's packing)``, NaN for a phase with
            no such bin.
        """
        c = self.crystal
        three = np.stack([c, np.roll(c, 1), np.roll(c, -1)])
        inside_c, inside_f = three.min(axis=0) >= solid, three.max(axis=0) <= fluid
        s = float(self.packing[inside_c].mean()) if inside_c.any() else math.nan
        f = float(self.packing[inside_f].mean()) if inside_f.any() else math.nan
        return s, f

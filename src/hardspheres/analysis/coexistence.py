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
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from ..builders import crystal
from ..containers import MAX_PACKING, PeriodicBox
from ..errors import AnalysisInputError, BuildError
from ..simulation import Simulation
from ..blocking import MIN_BLOCKS, blocking
from ..state import State
from .compute import Compute
from .structure import BondOrder, configurations

if TYPE_CHECKING:
    from matplotlib.axes import Axes

    from .structure import Edge, Source


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


# ---------------------------------------------------------------------------
# A liquid slab beside its vapour (square wells and other attractive steps)
# ---------------------------------------------------------------------------

#: The densest liquid block :func:`vapour_liquid_slab` builds [1/length^3] (packing 0.47).
LIQUID_START_MAX = 0.9


def vapour_liquid_slab(
    n: int, width: float, length: float, density: float = 0.65, kT: float = 1.0, seed: int = 0
) -> tuple[State, PeriodicBox]:
    """A liquid block of ``n`` spheres across the middle of a long periodic box, empty around it.

    The box is ``width x width x length`` (z the long side); the block fills
    its cross-section at number density ``density`` between ``z = -h/2`` and
    ``h/2``, ``h = n / (density width^2)``: a hard-sphere fluid built by
    :func:`equilibrated_fluid` in a periodic box of its own, ``width x width
    x h``.  Run it with an attractive step below the critical temperature
    (``hs.Simulation(state, box, steps=[(1.5, -1.0)])`` and a thermostat,
    :class:`hardspheres.dense.Andersen`) and the block evaporates into the
    empty space until a vapour stands at each face: the slab's profile
    (:class:`VapourLiquidProfile`) then gives both coexistence densities.
    Diameter 1, mass 1; Maxwell velocities at ``kT`` exactly, total momentum 0.

    Args:
        n: spheres, at least 2.
        width: the box's cross-section side [length] (x and y).
        length: the box's long side [length] (z); the block must leave at
            least 2 of it empty.
        density: the block's number density [1/length^3], at most
            :data:`LIQUID_START_MAX`; start near the liquid's coexistence
            density (for ``lambda = 1.5``: about 0.5-0.75 at ``kT / eps`` =
            1.1-0.8).
        kT: the velocities' temperature [energy].
        seed: seeds the block's placement and the velocities.

    Returns:
        ``(state, box)``, the block centred on ``z = 0``.

    Example:
        >>> state, box = vapour_liquid_slab(200, 5.0, 24.0, density=0.7, seed=1)
        >>> state.n, box.sides, bool(abs(state.positions[:, 2]).max() < 6.0)
        (200, (5.0, 5.0, 24.0), True)
    """
    if not (isinstance(n, (int, np.integer)) and n >= 2):
        raise BuildError(f"n must be a whole number >= 2, got {n!r}")
    for name, value in (("width", width), ("length", length), ("kT", kT)):
        if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
            raise BuildError(f"{name} must be a number > 0, got {value!r}")
    if not (isinstance(density, (int, float)) and 0.0 < density <= LIQUID_START_MAX):
        raise BuildError(f"density must be in (0, {LIQUID_START_MAX}], got {density!r}")
    width, length = float(width), float(length)
    h = n / (density * width * width)
    if h > length - 2.0:
        raise BuildError(
            f"the liquid block is {h:.4g} long and the box {length:.4g}: give a longer box "
            "(at least the block + 2), a wider one or fewer spheres"
        )
    if width < 2.0:
        raise BuildError(f"width {width!r} is below 2 diameters: give a wider box")
    x = equilibrated_fluid((width, width, h), density * math.pi / 6.0, seed=seed)
    box = PeriodicBox((width, width, length))
    x = box.wrap(x)
    rng = np.random.default_rng(seed)
    v = rng.normal(size=(n, 3))
    v -= v.mean(axis=0)
    v *= math.sqrt(3.0 * (n - 1) * kT / float(np.sum(v * v)))  # kT exactly
    return State.from_arrays(np.ones(n), np.full(n, 0.5), x, v), box


def slab_centre(z: np.ndarray, length: float) -> float:
    """The centre of a slab along a periodic axis [length]: the circular mean of the centres ``z``.

    Each centre is an angle ``2 pi z / length``; the mean of their unit
    vectors points at the slab (a uniform vapour adds nothing to it on
    average), and its angle back in length units is the centre, in
    ``[-length/2, length/2)``.

    Example:
        >>> round(slab_centre(np.array([9.0, 9.5, -9.5, -9.0]), 20.0), 6)  # a slab across the boundary
        -10.0
    """
    theta = 2.0 * math.pi * np.asarray(z, float) / length
    c = math.atan2(float(np.sin(theta).mean()), float(np.cos(theta).mean()))
    out = c * length / (2.0 * math.pi)
    return out - length if out >= 0.5 * length else out


class VapourLiquidProfile(Compute):
    """The number density along z of a liquid slab and its vapour, each frame centred on the slab.

    Each configuration's slab centre is found along z (:func:`slab_centre`:
    the slab drifts, the more so under a thermostat that does not conserve
    momentum), the centres are measured from it and folded (``|z|``, the
    two interfaces on top of each other), and their number density is
    binned from the slab's middle (``|z| = 0``) to the vapour's
    (``|z| = L_z / 2``).  Frames accumulate over calls (``reset=False``):
    sample a run at evenly spaced times and pass the profile to
    :class:`CoexistenceDensities`.

    Args:
        bins: bins over the half box, at least 8.

    After :meth:`compute`:
        z: ``(bins,)`` float, the bins' centres, distance from the slab's centre [length].
        density: ``(bins,)`` float, the mean number density over the frames [1/length^3].
        profiles: ``(F, bins)`` float, each frame's number density [1/length^3].
        centres: ``(F,)`` float, each frame's slab centre along z [length].
        times: ``(F,)`` float, the frames' times (``nan`` when not known).

    Example:
        >>> state, box = vapour_liquid_slab(200, 5.0, 24.0, density=0.7, seed=1)
        >>> p = VapourLiquidProfile(bins=12).compute(state, box.sides)
        >>> p.density.round(2).tolist()[:3], float(p.density[-1])  # the block, then empty space
        ([0.78, 0.6, 0.68], 0.0)
    """

    _results = ("z", "density", "profiles", "centres", "times")

    def __init__(self, bins: int = 100) -> None:
        if not (isinstance(bins, int) and bins >= 8):
            raise AnalysisInputError(f"bins must be a whole number >= 8, got {bins!r}")
        self.bins = bins
        self._frames: list[np.ndarray] = []
        self._centres: list[float] = []
        self._times: list[float] = []
        self._sides: tuple[float, ...] | None = None

    def compute(self, source: Source, box: Edge | None = None, reset: bool = True) -> VapourLiquidProfile:
        """Add the profiles of ``source``'s configurations (a 3-D periodic box); returns self.

        ``reset=False`` keeps the frames of earlier calls (the same box).
        """
        from .granular import _times

        L, pos, _ = configurations(source, box)
        sides = tuple(float(s) for s in PeriodicBox(L).sides)
        if len(sides) != 3 or pos.shape[-1] != 3 or pos.shape[1] == 0:
            raise AnalysisInputError(f"a slab profile needs spheres in a 3-D periodic box, got sides {sides}")
        if reset or self._sides is None:
            self._frames, self._centres, self._times, self._sides = [], [], [], sides
        elif sides != self._sides:
            raise AnalysisInputError(
                f"box {sides} differs from the earlier frames' {self._sides}: reset=True"
            )
        lz = sides[2]
        edges = np.linspace(0.0, 0.5 * lz, self.bins + 1)
        shell = 2.0 * sides[0] * sides[1] * (edges[1] - edges[0])  # both sides of the centre
        for x in pos:
            c = slab_centre(x[:, 2], lz)
            s = np.abs((x[:, 2] - c + 0.5 * lz) % lz - 0.5 * lz)
            self._frames.append(np.histogram(s, bins=edges)[0] / shell)
            self._centres.append(c)
        self._times.extend(_times(source, len(pos)).tolist())
        self.z = 0.5 * (edges[1:] + edges[:-1])
        self.profiles = np.array(self._frames)
        self.density = self.profiles.mean(axis=0)
        self.centres = np.array(self._centres)
        self.times = np.array(self._times)
        self._computed = True
        return self

    def plot(self, ax: Axes | None = None) -> Axes:
        """The mean density against the distance from the slab's centre; returns the Axes."""
        ax = self._axes(ax)
        ax.plot(self.z, self.density, drawstyle="steps-mid")
        ax.set_xlabel(r"$|z - z_{\rm slab}|$ [$\sigma$]")
        ax.set_ylabel(r"$\rho\sigma^3$")
        return ax


#: Fewest frames :class:`CoexistenceDensities` takes (blocking needs a long series).
MIN_FRAMES = 64
#: Fewest bins each plateau needs.
MIN_PLATEAU_BINS = 4
#: tanh((z - z0) / w) goes from 0.1 to 0.9 of the way across over 2 artanh(0.8) widths.
_TANH_10_90 = 2.0 * math.atanh(0.8)


def _crossing(z: np.ndarray, rho: np.ndarray, level: float) -> float:
    """The first ``z`` (linear between bins) where ``rho`` falls below ``level``, outward from the centre."""
    below = np.flatnonzero(rho < level)
    if len(below) == 0 or below[0] == 0:
        return math.nan
    k = int(below[0])
    return float(z[k - 1] + (z[k] - z[k - 1]) * (rho[k - 1] - level) / (rho[k - 1] - rho[k]))


def _interface(z: np.ndarray, rho: np.ndarray, lo: float, hi: float) -> tuple[float, float]:
    """``(z0, w)``: the midpoint crossing and the tanh width from the 10-90 % crossings [length]."""
    d = hi - lo
    z0 = _crossing(z, rho, lo + 0.5 * d)
    w = (_crossing(z, rho, lo + 0.1 * d) - _crossing(z, rho, lo + 0.9 * d)) / _TANH_10_90
    return z0, w


class CoexistenceDensities(Compute):
    """The liquid's and the vapour's densities from the plateaus of a :class:`VapourLiquidProfile`.

    The interface is located on the mean profile: its middle ``z0`` where
    the density crosses halfway between the two phases, its width ``w`` from
    the 10 % and 90 % crossings as if the profile were ``tanh((|z| - z0) /
    w)`` (twice, the plateaus first estimated from the innermost and
    outermost tenth of the half box, then from the plateaus found).  The
    liquid's plateau is the bins with ``|z| <= z0 - margin w``, the
    vapour's those with ``|z| >= z0 + margin w``; each frame's mean over a
    plateau is a time series whose blocked mean and error
    (:func:`hardspheres.blocking.blocking`) are the result.

    It refuses (:class:`~hardspheres.errors.AnalysisInputError`), rather than
    give a number that means nothing, when: fewer than :data:`MIN_FRAMES`
    frames; no interface (the profile does not fall); a plateau with fewer
    than :data:`MIN_PLATEAU_BINS` bins (a box too short, a slab too thick or
    too thin, or interfaces too wide); a plateau that is not flat (its inner
    and outer halves differ by more than ``tolerance`` joint errors: the
    interface's tail reaches into it, raise ``margin``); a drift (the two
    halves of the run differ by more than ``tolerance`` joint errors); or
    blocking without a plateau (run longer).

    Args:
        margin: the plateaus start this many interface widths from ``z0``.
        tolerance: joint errors allowed in the flatness and drift tests.
        min_blocks: fewest blocks a blocking level needs to decide the
            plateau (:func:`hardspheres.blocking.blocking`; 16 by default).
            The plateaus' densities are slow, a correlation time of order
            100 time units at N = 2000: runs shorter than about 50 of them
            find no plateau at 16 blocks.  A lower value (6, say) lets a
            run of about 15 correlation times decide, and its errors are
            then themselves uncertain by about ``1 / sqrt(2 (blocks - 1))``
            (a third at 6 blocks).
        strict: refuse when blocking finds no plateau (the default).  With
            ``False`` the error is then the largest of the levels with
            ``min_blocks`` blocks or more (blocking's estimate without a
            plateau: rough, and low if the series is slower still), and
            ``checks`` records it (``"liquid_plateau"``, ``"vapour_plateau"``:
            1 found, 0 not).

    After :meth:`compute`:
        liquid: float, the liquid's number density [1/length^3].
        liquid_error: float, its blocking error [1/length^3].
        vapour: float, the vapour's number density [1/length^3].
        vapour_error: float, its blocking error [1/length^3].
        interface: float, ``z0``, the interfaces' distance from the slab's centre [length].
        width: float, ``w``, the interface's tanh width [length].
        liquid_bins: ``(bins,)`` bool, the bins of the liquid's plateau.
        vapour_bins: ``(bins,)`` bool, the bins of the vapour's plateau.
        checks: dict, each test's value in joint errors (``"liquid_flat"``,
        ``"vapour_flat"``, ``"liquid_drift"``, ``"vapour_drift"``).

    Example:
        >>> z = np.linspace(0.25, 29.75, 60)
        >>> rho = 0.35 - 0.3 * np.tanh((z - 12.0) / 1.5)  # liquid 0.65, vapour 0.05
        >>> frames = rho + np.random.default_rng(1).normal(0, 0.01, (200, 60))
        >>> c = CoexistenceDensities().compute((z, frames))
        >>> round(c.liquid, 3), round(c.vapour, 3), round(c.width, 1)
        (0.65, 0.05, 1.5)
    """

    _results = (
        "liquid",
        "liquid_error",
        "vapour",
        "vapour_error",
        "interface",
        "width",
        "liquid_bins",
        "vapour_bins",
        "checks",
    )

    def __init__(
        self, margin: float = 3.0, tolerance: float = 3.0, min_blocks: int = MIN_BLOCKS, strict: bool = True
    ) -> None:
        for name, value in (("margin", margin), ("tolerance", tolerance)):
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise AnalysisInputError(f"{name} must be a number > 0, got {value!r}")
        if not (isinstance(min_blocks, (int, np.integer)) and min_blocks >= 4):
            raise AnalysisInputError(f"min_blocks must be a whole number >= 4, got {min_blocks!r}")
        self.margin, self.tolerance, self.min_blocks = float(margin), float(tolerance), int(min_blocks)
        self.strict = bool(strict)

    def compute(self, profile: VapourLiquidProfile | tuple[np.ndarray, np.ndarray]) -> CoexistenceDensities:
        """The two densities of ``profile`` (or of ``(z, profiles (F, bins))``); returns self."""
        z, frames = (profile.z, profile.profiles) if isinstance(profile, VapourLiquidProfile) else profile
        z, frames = np.asarray(z, float), np.atleast_2d(np.asarray(frames, float))
        if frames.shape[1] != len(z) or len(z) < 8:
            raise AnalysisInputError(
                f"profiles of shape {frames.shape} for {len(z)} bins: give (frames, bins)"
            )
        if len(frames) < MIN_FRAMES:
            raise AnalysisInputError(
                f"{len(frames)} frames: at least {MIN_FRAMES} needed for an error bar; run longer"
            )
        rho = frames.mean(axis=0)
        tenth = max(1, len(z) // 10)
        hi, lo = float(rho[:tenth].mean()), float(rho[-tenth:].mean())
        for _ in range(2):
            z0, w = _interface(z, rho, lo, hi)
            if not (math.isfinite(z0) and math.isfinite(w) and hi > lo):
                raise AnalysisInputError(
                    "no interface: the density does not fall from the slab to the vapour"
                )
            liq, vap = z <= z0 - self.margin * w, z >= z0 + self.margin * w
            for name, bins in (("liquid", liq), ("vapour", vap)):
                if bins.sum() < MIN_PLATEAU_BINS:
                    raise AnalysisInputError(
                        f"the {name}'s plateau has {int(bins.sum())} bins (interface at {z0:.3g}, width "
                        f"{w:.3g}): at least {MIN_PLATEAU_BINS} needed; a longer box, smaller bins "
                        "or a lower margin"
                    )
            hi, lo = float(rho[liq].mean()), float(rho[vap].mean())
        self.interface, self.width, self.liquid_bins, self.vapour_bins = z0, w, liq, vap
        self.checks: dict[str, float] = {}
        for name, bins in (("liquid", liq), ("vapour", vap)):
            mean, err = self._plateau(name, frames[:, bins])
            setattr(self, name, mean)
            setattr(self, f"{name}_error", err)
        self._computed = True
        return self

    def _plateau(self, name: str, frames: np.ndarray) -> tuple[float, float]:
        """A plateau's blocked mean over frames ``(F, bins)`` and its error; refused unless flat, steady."""
        series, mb = frames.mean(axis=1), self.min_blocks
        b = blocking(series, mb)
        k = frames.shape[1] // 2
        inner, outer = frames[:, :k].mean(axis=1), frames[:, frames.shape[1] - k :].mean(axis=1)
        step = blocking(inner - outer, mb)
        flat = step.mean / step.sem if step.sem > 0 else 0.0
        half = len(series) // 2
        a, c = blocking(series[:half], mb), blocking(series[half:], mb)
        joint = math.hypot(a.sem, c.sem)
        drift = (c.mean - a.mean) / joint if joint > 0 else 0.0
        self.checks[f"{name}_flat"], self.checks[f"{name}_drift"] = flat, drift
        self.checks[f"{name}_plateau"] = float(b.converged)
        if abs(flat) > self.tolerance:
            raise AnalysisInputError(
                f"the {name}'s plateau is not flat: its inner half minus its outer half is {step.mean:.3g} "
                f"+- {step.sem:.2g} ({flat:+.1f} errors); raise margin or check the run"
            )
        if abs(drift) > self.tolerance:
            raise AnalysisInputError(
                f"the {name}'s density drifts: the run's second half minus its first is "
                f"{c.mean - a.mean:.3g} "
                f"({drift:+.1f} joint errors); equilibrate longer"
            )
        if self.strict and not b.converged:
            raise AnalysisInputError(
                f"the {name}'s density: blocking found no plateau in {len(series)} frames "
                f"(levels of {mb} blocks or more); run longer"
            )
        return b.mean, b.sem

    def plot(self, ax: Axes | None = None, profile: VapourLiquidProfile | None = None) -> Axes:
        """The two densities as bands over their plateaus (and ``profile``'s mean); returns the Axes."""
        ax = self._axes(ax)
        if profile is not None:
            profile.plot(ax)
        for name, colour in (("liquid", "tab:blue"), ("vapour", "tab:orange")):
            value, err = getattr(self, name), getattr(self, f"{name}_error")
            lo, hi = self.interface - self.margin * self.width, self.interface + self.margin * self.width
            span = (
                (0.0, lo) if name == "liquid" else (hi, ax.get_xlim()[1] if profile is not None else 2 * hi)
            )
            ax.fill_between(span, value - err, value + err, color=colour, alpha=0.4)
            ax.hlines(value, *span, color=colour, label=f"{name} {value:.4f} +- {err:.4f}")
        ax.axvline(self.interface, color="0.6", lw=0.8)
        ax.set_xlabel(r"$|z - z_{\rm slab}|$ [$\sigma$]")
        ax.set_ylabel(r"$\rho\sigma^3$")
        ax.legend()
        return ax


@dataclass(frozen=True)
class CriticalPoint:
    """A critical point fitted to coexistence densities (:func:`critical_point`).

    Attributes:
        t_c: float, the critical temperature [energy, kT].
        t_c_error: float, its error from resampling the densities [energy].
        rho_c: float, the critical number density [1/length^3].
        rho_c_error: float, its error [1/length^3].
        a: float, the rectilinear diameter's slope [1/(length^3 energy)].
        b: float, the order parameter's amplitude [1/(length^3 energy^beta)].
        beta: float, the exponent used (fixed) [1].
        chi2: float, the fit's chi-squared over ``dof`` degrees of freedom.
        dof: int, data minus parameters (2 per temperature; 4 parameters, 5 with the correction).
        correction: float, the correction-to-scaling exponent used (fixed; 0: none) [1].
        b1: float, its amplitude, relative to ``b`` [1/energy^correction] (0: none).
    """

    t_c: float
    t_c_error: float
    rho_c: float
    rho_c_error: float
    a: float
    b: float
    beta: float
    chi2: float
    dof: int
    correction: float = 0.0
    b1: float = 0.0


def _fit_given_tc(
    tc: float,
    t: np.ndarray,
    rl: np.ndarray,
    rv: np.ndarray,
    el: np.ndarray,
    ev: np.ndarray,
    beta: float,
    correction: float = 0.0,
) -> tuple[float, np.ndarray]:
    """chi^2 and (rho_c, A, B[, B B1]) of the fit at a fixed ``tc``: linear least squares."""
    dt = tc - t
    s = 0.5 * dt**beta
    one = np.ones_like(t)
    columns = [[one, dt, s], [one, dt, -s]]
    if correction:
        columns[0].append(s * dt**correction)
        columns[1].append(-s * dt**correction)
    design = np.vstack([np.column_stack(columns[0]), np.column_stack(columns[1])])
    y, err = np.concatenate([rl, rv]), np.concatenate([el, ev])
    coef, *_ = np.linalg.lstsq(design / err[:, None], y / err, rcond=None)
    return float(np.sum(((design @ coef - y) / err) ** 2)), coef


def _best_tc(
    t: np.ndarray,
    rl: np.ndarray,
    rv: np.ndarray,
    el: np.ndarray,
    ev: np.ndarray,
    beta: float,
    correction: float = 0.0,
) -> tuple[float, float, np.ndarray]:
    """The ``tc`` above every ``t`` with the least chi^2: a scan, then golden sections."""
    top, span = float(t.max()), float(t.max() - t.min())
    grid = top + np.geomspace(1e-4 * span, 3.0 * span, 200)
    chi = [_fit_given_tc(g, t, rl, rv, el, ev, beta, correction)[0] for g in grid]
    k = int(np.argmin(chi))
    a, c = grid[max(k - 1, 0)], grid[min(k + 1, len(grid) - 1)]
    golden = (math.sqrt(5.0) - 1.0) / 2.0
    for _ in range(60):
        x1, x2 = c - golden * (c - a), a + golden * (c - a)
        fit1 = _fit_given_tc(x1, t, rl, rv, el, ev, beta, correction)[0]
        if fit1 < _fit_given_tc(x2, t, rl, rv, el, ev, beta, correction)[0]:
            c = x2
        else:
            a = x1
    tc = float(0.5 * (a + c))
    chi2, coef = _fit_given_tc(tc, t, rl, rv, el, ev, beta, correction)
    return tc, chi2, coef


def critical_point(
    kT: ArrayLike,
    liquid: ArrayLike,
    vapour: ArrayLike,
    liquid_error: ArrayLike,
    vapour_error: ArrayLike,
    beta: float = 0.326,
    samples: int = 2000,
    seed: int = 0,
    correction: float = 0.0,
) -> CriticalPoint:
    """The critical point from coexistence densities: rectilinear diameter and scaling law, fitted jointly.

    ``(rho_l + rho_v) / 2 = rho_c + A (T_c - T)`` and ``rho_l - rho_v = B
    (T_c - T)^beta`` with ``beta`` fixed (3-D Ising: 0.326), weighted by the
    densities' errors: linear in ``rho_c, A, B`` at a given ``T_c``, whose
    best value is searched above the highest temperature.  With
    ``correction`` (Wegner's first correction to scaling, 3-D Ising
    ``Delta = 0.524``: Wegner, Phys. Rev. B 5, 4529 (1972); Pelissetto and
    Vicari, Phys. Rep. 368, 549 (2002)), the scaling law becomes ``B (T_c -
    T)^beta (1 + B1 (T_c - T)^Delta)``: what temperatures far below ``T_c``
    need, where the leading law alone bends ``T_c`` upwards.  The errors of
    ``T_c`` and ``rho_c``: the fit repeated on ``samples`` sets of densities
    drawn from normal distributions of the given errors (their standard
    deviations).

    Args:
        kT: the temperatures [energy], at least 3.
        liquid: the liquid's densities [1/length^3].
        vapour: the vapour's [1/length^3].
        liquid_error: their errors [1/length^3], > 0.
        vapour_error: the vapour's errors [1/length^3], > 0.
        beta: the order parameter's exponent.
        samples: resampled fits for the errors (at least 10).
        seed: seeds the resampling.
        correction: the correction-to-scaling exponent ``Delta`` (0: none).

    Example:
        >>> t = np.array([0.9, 0.95, 1.0, 1.05, 1.1])
        >>> mid, half = 0.31 + 0.2 * (1.22 - t), 0.5 * 0.9 * (1.22 - t) ** 0.326
        >>> cp = critical_point(t, mid + half, mid - half, np.full(5, 1e-3), np.full(5, 1e-3), samples=50)
        >>> round(cp.t_c, 3), round(cp.rho_c, 3)
        (1.22, 0.31)
    """
    arrays = [np.asarray(x, float).reshape(-1) for x in (kT, liquid, vapour, liquid_error, vapour_error)]
    t, rl, rv, el, ev = arrays
    if len({len(x) for x in arrays}) != 1 or len(t) < 3:
        raise AnalysisInputError(
            "give 3 or more temperatures, each with both densities and errors; "
            f"got {[len(x) for x in arrays]}"
        )
    if not all(np.all(np.isfinite(x)) for x in arrays) or np.any(el <= 0) or np.any(ev <= 0):
        raise AnalysisInputError("densities and errors must be finite numbers, the errors > 0")
    if np.any(rl <= rv):
        raise AnalysisInputError("every liquid density must exceed its vapour's")
    if not (isinstance(samples, int) and samples >= 10):
        raise AnalysisInputError(f"samples must be a whole number >= 10, got {samples!r}")
    if not (math.isfinite(correction) and correction >= 0.0) or (correction and len(t) < 4):
        raise AnalysisInputError(f"correction must be >= 0 (0: none), with 4+ temperatures: {correction!r}")
    tc, chi2, coef = _best_tc(t, rl, rv, el, ev, beta, correction)
    rng = np.random.default_rng(seed)
    draws = np.empty((samples, 2))
    for k in range(samples):
        tk, _, ck = _best_tc(t, rng.normal(rl, el), rng.normal(rv, ev), el, ev, beta, correction)
        draws[k] = tk, ck[0]
    sd = draws.std(axis=0, ddof=1)
    return CriticalPoint(
        tc,
        float(sd[0]),
        float(coef[0]),
        float(sd[1]),
        float(coef[1]),
        float(coef[2]),
        beta,
        chi2,
        2 * len(t) - (5 if correction else 4),
        correction,
        float(coef[3] / coef[2]) if correction else 0.0,
    )

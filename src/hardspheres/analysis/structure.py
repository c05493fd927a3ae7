"""Structure: g(r) and its contact value, S(k), bond-orientational order.

Compute objects in the style of freud: ``compute()`` returns the object,
results read before it raise :class:`NotComputedError`, ``plot(ax=None)``
returns matplotlib Axes.  The heavy lifting is freud's (optional dependency
``pip install hardspheres[analysis]``): :class:`freud.density.RDF`,
:class:`freud.diffraction.StaticStructureFactorDirect`,
:class:`freud.order.Steinhardt` and :class:`freud.order.SolidLiquid`; freud
takes our box as it is (a cube centred on the origin).  Configurations come
from a :class:`hardspheres.Frames` (every frame is averaged), a
:class:`hardspheres.Simulation` (its state now), or positions and a box edge.

They need a periodic box: in a spherical container the wall makes the
density non-uniform, and g(r) or S(k) normalised by the bulk density would
mislead.

Example:
    >>> import hardspheres as hs
    >>> sim = hs.Simulation(hs.random_spheres(256, 0.5, box=9.5, seed=1), hs.PeriodicBox(9.5))
    >>> fcc = BondOrder().compute(sim)       # a perfect FCC lattice at t = 0
    >>> round(fcc.mean_q, 3), fcc.crystal_fraction
    (0.575, 1.0)
"""

from __future__ import annotations

from collections.abc import Iterator
from types import ModuleType
from typing import TYPE_CHECKING, Any, cast

import numpy as np

from ..containers import PeriodicBox, require_periodic
from ..errors import AnalysisInputError
from ..errors import NotComputedError  # noqa: F401 (re-exported)
from .compute import Compute

_Computed = Compute  # the name the analyses used before analysis/compute.py

if TYPE_CHECKING:
    from typing import TypeAlias

    from matplotlib.axes import Axes
    from numpy.typing import ArrayLike

    from ..frames import Frames
    from ..simulation import Simulation
    from ..state import State

    #: What the compute methods accept (frames, a simulation, a state or bare positions).
    Source: TypeAlias = Frames | Simulation | State | ArrayLike
    #: A periodic box's edge (a cube) or its sides [length].
    Edge: TypeAlias = float | tuple[float, ...]
    #: ``(L, positions (F, N, d), radii (N,) or None)``.
    Configurations: TypeAlias = tuple[Edge, np.ndarray, np.ndarray | None]


def _freud() -> ModuleType:
    from ..extras import need

    return need("freud", "this structural analysis (freud)")


def configurations(source: Source, box: Edge | None = None) -> Configurations:
    """``(L, positions (F, N, 3), radii (N,))`` from what the compute methods accept.

    Args:
        source: :class:`hardspheres.Frames` (periodic box), a
            :class:`hardspheres.Simulation` (its state now), a
            :class:`hardspheres.State` with ``box``, or positions ``(N, 3)``
            or ``(F, N, 3)`` with ``box`` (radii then unknown: ``None``).
        box: periodic box edge [length], for a State or bare positions.

    Raises:
        PeriodicBoxRequired: the configurations are not in a periodic box.
    """
    from ..frames import Frames
    from ..simulation import Simulation
    from ..state import State

    if isinstance(source, Frames):
        require_periodic(source.container if source.box is not None else None, "g(r), S(k) and bond order")
        L = cast(PeriodicBox, source.container).length
        return L, np.asarray(source.positions, float), np.asarray(source.radii, float)
    if isinstance(source, Simulation):
        require_periodic(source.container, "g(r), S(k) and bond order")
        L = cast(PeriodicBox, source.container).length
        st = source.state()
        return L, st.positions[None], st.radii
    if box is None:
        require_periodic(None, "g(r), S(k) and bond order")
    L = PeriodicBox(cast("Edge", box)).length  # None raised above
    if isinstance(source, State):
        return L, source.positions[None], source.radii
    pos = np.asarray(source, float)
    return L, pos.reshape((-1,) + pos.shape[-2:]), None


def _local_configurations(source: Source, box: Edge | None = None) -> Configurations:
    """:func:`configurations`, and for local analyses also a spherical container.

    A :class:`hardspheres.Simulation` or :class:`hardspheres.Frames` in a
    spherical container gets a box ``4 R`` wide: no sphere sees an image
    within a neighbour shell, so a periodic neighbour search is an open one.
    """
    from ..frames import Frames
    from ..simulation import Simulation

    container = getattr(source, "container", None)
    if isinstance(source, (Frames, Simulation)) and container is not None and not container.periodic:
        if isinstance(source, Frames):
            return (
                4.0 * container.bounding_radius,
                np.asarray(source.positions, float),
                np.asarray(source.radii, float),
            )
        st = source.state()
        return 4.0 * container.bounding_radius, st.positions[None], st.radii
    return configurations(source, box)


def _wrap(x: np.ndarray, L: Edge) -> np.ndarray:
    """Centres wrapped into the box, as freud takes them: ``(N, 3)`` (2-D: z = 0)."""
    x = PeriodicBox(L).wrap(x)
    if x.shape[-1] == 2:
        return np.concatenate([x, np.zeros(x.shape[:-1] + (1,))], axis=-1)
    return x


def _freud_box(freud: ModuleType, L: Edge) -> Any:
    """freud's box of a cube's edge or a box's sides ``L`` (two sides: a 2-D box)."""
    sides = PeriodicBox(L).sides
    if len(sides) == 2:
        return freud.box.Box(sides[0], sides[1], is2D=True)
    return freud.box.Box(*sides)


def _psi6_frames(
    freud: ModuleType, L: Edge, pos: np.ndarray, refusal: str
) -> Iterator[tuple[Any, np.ndarray]]:
    """Per configuration of ``pos`` (disks in the 2-D box ``L``): freud's system and each disk's psi6
    over its 6 nearest neighbours (a copy).  The one home of psi6 for :class:`Hexatic` and
    :func:`local_psi6`; refuses at once, with ``refusal``, a box that is not 2-D."""
    if PeriodicBox(L).dimensions != 2:
        raise AnalysisInputError(refusal)
    fbox = _freud_box(freud, L)
    hexatic = freud.order.Hexatic(k=6)

    def frames() -> Iterator[tuple[Any, np.ndarray]]:
        for x in pos:
            system = (fbox, _wrap(x, L))
            hexatic.compute(system, neighbors={"num_neighbors": 6})
            yield system, np.asarray(hexatic.particle_order).copy()

    return frames()


def _shortest(L: Edge) -> float:
    """The shortest side of the box ``L`` (a cube's edge, or the sides) [length]."""
    return min(PeriodicBox(L).sides)


def _contact_distance(radii: np.ndarray | None) -> float:
    if radii is None or len(radii) == 0:
        raise AnalysisInputError("sphere radii unknown: pass sigma (the contact distance)")
    d = 2.0 * np.asarray(radii)
    if np.ptp(d) > 1e-12 * d.max():
        raise AnalysisInputError(
            "spheres of different sizes have one contact value per pair of sizes; pass sigma to choose one"
        )
    return float(d[0])


class RDF(Compute):
    """Radial distribution function g(r), averaged over configurations (freud).

    Args:
        dr: bin width [length]; default a fiftieth of the contact distance.
        r_max: largest r [length]; default ``min(5 sigma, L/2)``.

    Bin edges are multiples of ``dr`` from 0 and the contact distance is
    made an edge, so no bin straddles contact (where g jumps from 0).

    Attributes (after :meth:`compute`): ``r`` bin centres, ``g``, ``edges``,
    ``sigma`` the contact distance, ``frames`` configurations averaged.
    """

    _results = ("r", "g", "edges", "sigma", "frames", "n", "packing")

    def __init__(self, dr: float | None = None, r_max: float | None = None) -> None:
        self.dr, self.r_max = dr, r_max

    def compute(self, source: Source, box: Edge | None = None, sigma: float | None = None) -> RDF:
        """Average g(r) over ``source``'s configurations; returns self.

        Args:
            sigma: contact distance [length]; default twice the radius of
                the (equal) spheres.
        """
        freud = _freud()
        L, pos, radii = configurations(source, box)
        sig = float(sigma) if sigma is not None else _contact_distance(radii)
        # dr divides sigma exactly (up to rounding), so sigma is a bin edge
        per = max(1, round(sig / self.dr)) if self.dr else 50
        dr = sig / per
        r_max = min(self.r_max or 5.0 * sig, 0.5 * _shortest(L) * (1.0 - 1e-9))
        bins = int(r_max / dr)
        rdf = freud.density.RDF(bins=bins, r_max=bins * dr)
        fbox = _freud_box(freud, L)
        for k, x in enumerate(pos):
            rdf.compute((fbox, _wrap(x, L)), reset=(k == 0))
        self.r = np.asarray(rdf.bin_centers, float).copy()
        self.edges = np.asarray(rdf.bin_edges, float).copy()
        self.g = np.asarray(rdf.rdf, float).copy()
        self.sigma, self.frames, self.n = sig, len(pos), pos.shape[1]
        box_ = PeriodicBox(L)
        self.dimensions = box_.dimensions
        if box_.dimensions == 2:  # disks: the area fraction
            self.packing = self.n * np.pi * sig**2 / (4.0 * box_.volume)
        else:
            self.packing = self.n * np.pi * sig**3 / (6.0 * box_.volume)
        self._computed = True
        return self

    def contact_value(self, width: float = 0.1) -> tuple[float, float]:
        """g(sigma+): a quadratic fitted to the bins in ``[sigma, sigma (1 + width)]``.

        Returns:
            ``(g_sigma, error)``: the fit's value at contact and its standard
            error from the scatter of the bins about the fit.
        """
        self._need()
        lo, hi = self.sigma * (1 - 1e-9), self.sigma * (1.0 + width)
        sel = (self.edges[:-1] >= lo) & (self.edges[1:] <= hi * (1 + 1e-9))
        if sel.sum() < 4:
            raise AnalysisInputError(
                "fewer than 4 bins to fit the contact value: use a smaller dr or a larger width"
            )
        x = self.r[sel] / self.sigma - 1.0
        coef, cov = np.polyfit(x, self.g[sel], 2, cov=True)
        return float(coef[-1]), float(np.sqrt(cov[-1, -1]))

    def Z(self) -> tuple[float, float]:  # noqa: N802 (the physicists' name)
        """``Z = 1 + 4 phi g(sigma)`` (equal spheres; disks: ``1 + 2 phi g(sigma)``), with its error
        from the contact fit."""
        g, err = self.contact_value()
        c = 2.0 if self.dimensions == 2 else 4.0
        return 1.0 + c * self.packing * g, c * self.packing * err

    def compressibility(self) -> tuple[float, float]:
        """The old name of :meth:`Z` (the compressibility factor, not kappa_T)."""
        return self.Z()

    def plot(self, ax: Axes | None = None) -> Axes:
        """g(r) against r / sigma; returns the Axes."""
        ax = self._axes(ax)
        ax.plot(self.r / self.sigma, self.g)
        ax.axhline(1.0, color="grey", lw=0.5)
        ax.set_xlabel("r / sigma")
        ax.set_ylabel("g(r)")
        ax.set_title(f"g(r), packing {self.packing:.3g}, {self.frames} frames")
        return ax


class StructureFactor(Compute):
    """Static structure factor S(k) from the box's own wave vectors (freud, direct).

    Args:
        bins: number of ``|k|`` bins.
        k_max: largest ``|k|`` [1/length]; default ``20 / sigma`` (sigma = 1 if
            radii are unknown).
        k_min: smallest ``|k|`` [1/length]; default half the box's smallest
            wave vector ``2 pi / L`` (so only the forward peak at k = 0,
            ``S = N``, is left out).

    Attributes (after :meth:`compute`): ``k`` bin centres, ``S``.
    """

    _results = ("k", "S", "sigma", "frames")

    def __init__(self, bins: int = 100, k_max: float | None = None, k_min: float | None = None) -> None:
        self.bins, self.k_max, self.k_min = bins, k_max, k_min

    def compute(self, source: Source, box: Edge | None = None) -> StructureFactor:
        """Average S(k) over ``source``'s configurations; returns self."""
        freud = _freud()
        L, pos, radii = configurations(source, box)
        sig = 2.0 * float(np.max(radii)) if radii is not None and len(radii) else 1.0
        k_max = self.k_max or 20.0 / sig
        k_min = np.pi / _shortest(L) if self.k_min is None else self.k_min
        sf = freud.diffraction.StaticStructureFactorDirect(self.bins, k_max, k_min)
        fbox = _freud_box(freud, L)
        for k, x in enumerate(pos):
            sf.compute((fbox, _wrap(x, L)), reset=(k == 0))
        self.k = np.asarray(sf.bin_centers, float).copy()
        self.S = np.asarray(sf.S_k, float).copy()
        self.sigma, self.frames = sig, len(pos)
        self._computed = True
        return self

    def plot(self, ax: Axes | None = None) -> Axes:
        """S(k) against k sigma; returns the Axes."""
        ax = self._axes(ax)
        ax.plot(self.k * self.sigma, self.S)
        ax.axhline(1.0, color="grey", lw=0.5)
        ax.set_xlabel("k sigma")
        ax.set_ylabel("S(k)")
        return ax


class Hexatic(Compute):
    """The hexatic order of disks: local psi6, the global ``|Psi6|`` and its correlation g6(r) (freud).

    ``psi6(j) = (1/6) sum_k exp(6 i theta_jk)`` over the 6 nearest neighbours
    of disk j (``theta_jk`` the bond's angle); ``|Psi6| = |mean_j psi6(j)|``
    is 1 in a perfect hexagonal crystal and near 0 in a liquid;
    ``g6(r) = <psi6(j)* psi6(k)>`` over pairs ``r`` apart decays
    exponentially in the liquid, algebraically (as ``r^(-1/4)`` or slower)
    in the hexatic phase and not at all in the crystal (Bernard and Krauth,
    PRL 107, 155704 (2011); Engel et al., PRE 87, 042134 (2013)).

    Attributes (after :meth:`compute`, last configuration): ``psi6``
    (complex per disk), ``order`` (``|Psi6|``), ``orders`` per
    configuration, ``r`` and ``g6`` (averaged over configurations).
    """

    _results = ("psi6", "order", "orders", "r", "g6")

    def __init__(self, bins: int = 100, r_max: float | None = None) -> None:
        self.bins, self.r_max = int(bins), r_max

    def compute(self, source: Source, box: Edge | None = None) -> Hexatic:
        """psi6, ``|Psi6|`` and g6(r) of ``source``'s configurations (a 2-D periodic box); returns self."""
        freud = _freud()
        L, pos, radii = configurations(source, box)
        refusal = "the hexatic order is of disks: give a 2-D periodic box, PeriodicBox((Lx, Ly))"
        frames = _psi6_frames(freud, L, pos, refusal)
        r_max = self.r_max or 0.45 * _shortest(L)
        corr = freud.density.CorrelationFunction(bins=self.bins, r_max=r_max)
        orders = []
        for k, (system, psi) in enumerate(frames):
            orders.append(float(abs(psi.mean())))
            corr.compute(
                system, values=psi, query_points=system[1], query_values=np.conj(psi), reset=(k == 0)
            )
        self.psi6 = psi
        self.orders = np.array(orders)
        self.order = orders[-1]
        self.r = np.asarray(corr.bin_centers, float).copy()
        self.g6 = np.real(np.asarray(corr.correlation)).copy()
        self._computed = True
        return self

    def plot(self, ax: Axes | None = None) -> Axes:
        """g6(r) on log-log axes; returns the Axes."""
        ax = self._axes(ax)
        ax.loglog(self.r, np.abs(self.g6))
        ax.set_xlabel("r")
        ax.set_ylabel("|g6(r)|")
        ax.set_title(f"|Psi6| = {self.order:.3f}")
        return ax


class BondOrder(Compute):
    """Steinhardt q_l per sphere and the fraction of crystal-like spheres (freud).

    Neighbours are the spheres within ``r_max`` (default 1.4 sigma, about
    the first minimum of g(r) in the dense fluid and the crystal), or the
    ``num_neighbors`` nearest (e.g. 12, as in a close-packed crystal).  A sphere
    is crystal-like when at least ``solid_threshold`` of its bonds are
    coherent, ``q6(i) . q6(j) > q_threshold`` (normalised): the criterion of
    P. R. ten Wolde, M. J. Ruiz-Montero and D. Frenkel, J. Chem. Phys. 104,
    9932 (1996), with the thresholds 0.7 and 7 of S. Auer and D. Frenkel,
    Nature 409, 1020 (2001).

    Unlike g(r) and S(k), bond order is local, so it is also computed in a
    spherical container (a :class:`hardspheres.Simulation` or
    :class:`hardspheres.Frames` in one): the spheres then sit in a freud box
    four container radii wide, where no sphere sees an image.

    Attributes (after :meth:`compute`, last configuration): ``q`` per
    sphere, ``mean_q``, ``crystal_like`` (bool per sphere),
    ``crystal_fraction``; per configuration, ``qs`` ``(F, N)``,
    ``mean_qs`` and ``crystal_fractions``.

    Example:
        A jammed packing is amorphous, a slowly compressed one crystallises
        (docs/validation/dense.md)::

            order = hs.BondOrder(num_neighbors=12).compute(sim)
            order.mean_q, order.crystal_fraction
    """

    _results = ("q", "mean_q", "crystal_like", "crystal_fraction", "crystal_fractions", "qs", "mean_qs")

    def __init__(
        self,
        l: int = 6,  # noqa: E741 (freud's name for the order)
        r_max: float | None = None,
        q_threshold: float = 0.7,
        solid_threshold: int = 7,
        num_neighbors: int | None = None,
    ) -> None:
        if r_max is not None and num_neighbors is not None:
            raise AnalysisInputError("BondOrder: give r_max or num_neighbors, not both")
        if num_neighbors is not None and not (
            isinstance(num_neighbors, (int, np.integer)) and num_neighbors > 0
        ):
            raise AnalysisInputError(
                f"BondOrder: num_neighbors must be a whole number > 0, got {num_neighbors!r}"
            )
        self.l, self.r_max, self.num_neighbors = l, r_max, num_neighbors
        self.q_threshold, self.solid_threshold = q_threshold, solid_threshold

    def compute(self, source: Source, box: Edge | None = None, sigma: float | None = None) -> BondOrder:
        """Bond order of each of ``source``'s configurations; returns self.

        Args:
            source: frames, a simulation, a state or bare positions.
            box: the periodic box's edge or sides [length], for a state or
                bare positions.
            sigma: the contact distance [length] that sets the default
                ``r_max`` (1.4 sigma); default: the largest diameter.  Bare
                positions carry no radii, so they need ``sigma``, an
                ``r_max`` or ``num_neighbors``.

        Raises:
            AnalysisInputError: bare positions with none of ``sigma``,
                ``r_max`` and ``num_neighbors``.
        """
        freud = _freud()
        L, pos, radii = _local_configurations(source, box)
        if self.num_neighbors is not None:
            neighbors: dict[str, float] = {"num_neighbors": int(self.num_neighbors)}
        elif self.r_max:
            neighbors = {"r_max": self.r_max}
        elif sigma is not None:
            neighbors = {"r_max": 1.4 * float(sigma)}
        elif radii is None:  # bare positions
            raise AnalysisInputError(
                "BondOrder: bare positions have no radii: pass sigma= (the contact distance), "
                "or give BondOrder r_max= or num_neighbors="
            )
        else:
            neighbors = {"r_max": 1.4 * (2.0 * float(np.max(radii)))}
        fbox = _freud_box(freud, L)
        st = freud.order.Steinhardt(self.l)
        sl = freud.order.SolidLiquid(
            self.l, q_threshold=self.q_threshold, solid_threshold=self.solid_threshold
        )
        fractions, qs, crystal = [], [], None
        for x in pos:
            system = (fbox, _wrap(x, L))
            st.compute(system, neighbors=neighbors)
            sl.compute(system, neighbors=neighbors)
            crystal = np.asarray(sl.num_connections) >= self.solid_threshold
            fractions.append(float(np.mean(crystal)))
            qs.append(np.nan_to_num(np.asarray(st.particle_order, float)))
        self.qs = np.array(qs)
        self.mean_qs = self.qs.mean(axis=1)
        self.q = self.qs[-1].copy()
        self.mean_q = float(np.mean(self.q))
        self.crystal_like = crystal
        self.crystal_fraction = fractions[-1]
        self.crystal_fractions = np.array(fractions)
        self._computed = True
        return self

    def plot(self, ax: Axes | None = None) -> Axes:
        """Histogram of q_l per sphere; returns the Axes."""
        ax = self._axes(ax)
        ax.hist(self.q, bins=50, range=(0, 1))
        ax.set_xlabel(f"q{self.l}")
        ax.set_ylabel("spheres")
        ax.set_title(f"crystal-like: {self.crystal_fraction:.1%}")
        return ax


def local_psi6(source: Source, box: Edge | None = None) -> np.ndarray:
    """``(F, N)`` complex local psi6 of each disk in each configuration (6 nearest neighbours, freud).

    What :class:`Hexatic` computes per disk, for every configuration and
    without g6(r): for pictures (the viewer's colour by ``|psi6|``).
    ``source`` as for :class:`Hexatic`, or :class:`hardspheres.Frames` and
    :class:`hardspheres.Simulation` in a :class:`~hardspheres.CircularContainer`
    (whose disks sit in a box ``4 R`` wide: no disk sees an image among its
    neighbours, so the periodic search is an open one).

    Example:
        >>> from hardspheres.builders import hexagonal
        >>> s, box = hexagonal((6, 6), 0.7)
        >>> psi = local_psi6(s, box=box.sides)
        >>> psi.shape, round(float(abs(psi).min()), 6)
        ((1, 36), 1.0)
    """
    from ..frames import Frames
    from ..simulation import Simulation

    freud = _freud()
    container = source.container if isinstance(source, (Frames, Simulation)) else None
    L: Edge
    if container is not None and not container.periodic and container.dimensions == 2:
        w = 4.0 * container.bounding_radius
        L = (w, w)
        frames = source.positions if isinstance(source, Frames) else source.state().positions[None]  # type: ignore[union-attr]
        pos = np.asarray(frames, float)
    else:
        L, pos, _ = configurations(source, box)
    refusal = "psi6 is of disks: give a 2-D periodic box, PeriodicBox((Lx, Ly)), or a circle"
    return np.array([psi for _, psi in _psi6_frames(freud, L, pos, refusal)], complex).reshape(pos.shape[:2])


def psi6_magnitudes(positions: np.ndarray, container: Any) -> np.ndarray:
    """``(F, N)`` ``|psi6|`` of disks at ``positions`` ``(F, N, 2)`` in ``container`` (for pictures).

    :func:`local_psi6`'s magnitudes: in a 2-D periodic box with its sides,
    in a circle (or open space, ``container=None``) in a box wide enough
    that no disk sees an image.
    """
    if container is not None and container.periodic:
        return np.abs(local_psi6(positions, box=tuple(container.sides)))
    reach = float(np.max(np.abs(positions))) if positions.size else 1.0
    if container is not None:
        reach = max(reach, float(container.bounding_radius))
    return np.abs(local_psi6(positions, box=(4.0 * reach + 4.0, 4.0 * reach + 4.0)))

"""Jammed packings: contact network, rattlers, coordination, g(h), P(f) and phi_J.

Compute objects in the style of freud (``compute()`` returns the object,
results read before it raise :class:`NotComputedError`, ``plot(ax=None)``
returns Axes), in any dimension (positions ``(N, d)``), periodic box:

* :class:`Contacts`: the contact network, at a gap tolerance (pairs whose
  gap ``h = r_ij / (R_i + R_j) - 1`` is at most ``tolerance``) or from the
  time-averaged collision forces
  (:class:`~hardspheres.analysis.collisions.ContactForces`); rattlers
  removed iteratively (a sphere with fewer than ``d + 1`` contacts cannot
  be held in place; removing it can leave a neighbour with too few); the
  mean coordination ``z`` of the rest and the rattler fraction.  An
  isostatic packing has ``N_c = d (N' - 1) + 1`` contacts among its ``N'``
  non-rattlers in a periodic box (``d`` translations are free), so ``z =
  2d`` up to ``O(1/N')``; ``z_isostatic`` is that count.
* the small-argument power laws of the gap distribution ``g(h) ~
  h^(-gamma)`` among non-rattlers (:meth:`Contacts.gap_exponent`) and of the
  force distribution ``P(f) ~ f^theta`` (:func:`force_exponent`), both by
  maximum likelihood (the exponent of a power-law density truncated to the
  range fitted), with bootstrap error bars (fixed seed).  The reference
  values are those of P. Charbonneau, E. I. Corwin, G. Parisi and F.
  Zamponi, Phys. Rev. Lett. 109, 205501 (2012): ``gamma = 0.41`` and, for
  the extended forces, ``theta = 0.42``.
* :class:`JammingPoint`: ``phi_J`` from the pressure along a compression,
  the free-volume form ``Z = d phi_J / (phi_J - phi)``, which is linear in
  ``1/Z``: ``d / Z = 1 - phi / phi_J``.

Example:
    >>> import numpy as np
    >>> # a simple-cubic crystal at contact: 6 contacts each, nothing rattles
    >>> g = np.arange(4.0)
    >>> pos = np.stack(np.meshgrid(g, g, g, indexing="ij"), -1).reshape(-1, 3)
    >>> c = Contacts(tolerance=1e-9).compute(pos, radii=np.full(64, 0.5), box=4.0)
    >>> c.z, c.rattler_fraction
    (6.0, 0.0)
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import TYPE_CHECKING, NamedTuple, cast

import numpy as np

from ..errors import AnalysisInputError, NotComputedError, PeriodicBoxRequired
from .compute import Compute

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from numpy.typing import ArrayLike

    from ..containers import PeriodicBox
    from ..simulation import Simulation
    from ..state import State
    from .collisions import ContactForces


def _packing(
    source: Simulation | State | ArrayLike,
    box: float | ArrayLike | None = None,
    radii: ArrayLike | None = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(positions (N, d) wrapped into [0, L), radii (N,), lengths (d,))`` of a packing."""
    from ..simulation import Simulation
    from ..state import State

    rad: ArrayLike | None
    if isinstance(source, Simulation):
        c = source.container
        if not c.periodic:
            raise PeriodicBoxRequired(
                "jamming analyses need a periodic box (a wall changes the contact counts); "
                "compress in hs.PeriodicBox(L)"
            )
        st = source.state()
        pos, rad = st.positions, st.radii
        sides = getattr(c, "sides", None)
        box = cast("PeriodicBox", c).length if sides is None else sides
    elif isinstance(source, State):
        pos, rad = source.positions, source.radii
    else:
        pos, rad = np.asarray(source, float), radii
    if box is None:
        raise PeriodicBoxRequired("jamming analyses need a periodic box: pass box (its edge)")
    if rad is None:
        raise AnalysisInputError("radii: pass the spheres' radii with bare positions")
    pos = np.asarray(pos, float)
    if pos.ndim != 2:
        raise AnalysisInputError(f"positions must be (N, d), got shape {pos.shape}; pass one configuration")
    rad = np.asarray(rad, float).reshape(-1)
    if len(rad) != len(pos):
        raise AnalysisInputError(
            f"radii: {len(rad)} radii for {len(pos)} spheres; pass one radius per sphere"
        )
    lengths = np.broadcast_to(np.asarray(box, float), (pos.shape[1],)).copy()
    return np.mod(pos, lengths), rad, lengths


def near_pairs(
    positions: np.ndarray, radii: np.ndarray, lengths: ArrayLike, h_max: float
) -> tuple[np.ndarray, np.ndarray]:
    """``(pairs (M, 2), gaps (M,))`` of the pairs with gap ``r/(R_i + R_j) - 1 <= h_max`` (periodic)."""
    from ..extras import need

    cKDTree = need("scipy.spatial", "finding contacts").cKDTree
    lengths = np.asarray(lengths, float)
    x = np.mod(positions, lengths)
    # cKDTree wants points in [0, L): mod can round up to L
    x[x >= lengths] = 0.0
    tree = cKDTree(x, boxsize=lengths)
    # candidates by a padded cut: the tree's own distance can round above
    # 2 R (1 + h) for a pair whose gap below is exactly h_max; the gaps below
    # decide
    cut = 2.0 * float(radii.max()) * (1.0 + h_max) * (1.0 + 1e-9)
    pairs = tree.query_pairs(cut, output_type="ndarray")
    if len(pairs) == 0:
        return np.zeros((0, 2), np.int64), np.zeros(0)
    pairs = np.sort(pairs, axis=1)
    dx = x[pairs[:, 0]] - x[pairs[:, 1]]
    dx -= lengths * np.round(dx / lengths)
    h = np.sqrt(np.einsum("md,md->m", dx, dx)) / (radii[pairs[:, 0]] + radii[pairs[:, 1]]) - 1.0
    keep = h <= h_max
    order = np.lexsort((pairs[keep, 1], pairs[keep, 0]))
    return pairs[keep][order], h[keep][order]


def remove_rattlers(pairs: ArrayLike, n: int, dim: int) -> tuple[np.ndarray, np.ndarray]:
    """Non-rattlers: iteratively drop spheres with fewer than ``dim + 1`` contacts.

    Returns:
        ``(rattler (N,) bool, contacts (N,) of the remaining network)``.

    Example:
        >>> # four disks each touching the other three, a fifth touching one of them
        >>> pairs = [[0, 1], [0, 2], [0, 3], [1, 2], [1, 3], [2, 3], [3, 4]]
        >>> r, c = remove_rattlers(pairs, 5, 2)
        >>> r.tolist(), c.tolist()
        ([False, False, False, False, True], [3, 3, 3, 3, 0])
    """
    pairs = np.asarray(pairs, np.int64).reshape(-1, 2)
    alive = np.ones(len(pairs), bool)
    rattler = np.zeros(n, bool)
    while True:
        count = np.bincount(pairs[alive].ravel(), minlength=n)
        new = (count < dim + 1) & ~rattler
        if not new.any():
            return rattler, count
        rattler |= new
        alive &= ~(rattler[pairs[:, 0]] | rattler[pairs[:, 1]])


def _bootstrap(
    samples: np.ndarray, fit: Callable[[np.ndarray], float], reps: int = 200, seed: int = 0
) -> float:
    rng = np.random.default_rng(seed)
    vals = [fit(rng.choice(samples, len(samples), replace=True)) for _ in range(reps)]
    vals = [v for v in vals if math.isfinite(v)]
    return float(np.std(vals, ddof=1)) if len(vals) > 1 else math.nan


def power_law_exponent(x: ArrayLike, lo: float, hi: float) -> float:
    """Maximum-likelihood ``alpha`` of a density ``~ x^(alpha - 1)`` on ``[lo, hi]`` (truncated).

    The cumulative count then grows as ``x^alpha``.  The mean
    log-likelihood is ``ln a + (a - 1) <ln x> - ln(hi^a - lo^a)``; its
    derivative in ``a`` is zeroed by bisection.

    Example:
        >>> rng = np.random.default_rng(1)
        >>> round(power_law_exponent(rng.uniform(0, 1, 100000) ** (1 / 0.5), 0.0, 1.0), 2)
        0.5
    """
    x = np.asarray(x, float)
    x = x[(x > lo) & (x <= hi)]
    if len(x) < 2:
        return math.nan
    mean_log = float(np.mean(np.log(x / hi)))  # <= 0

    def score(a: float) -> float:
        # d/da of the mean log-likelihood of a x^(a-1) / (hi^a - lo^a) (scaled by hi)
        r = lo / hi
        if r <= 0:
            return 1.0 / a + mean_log
        ra = r**a
        return 1.0 / a + mean_log - (-ra * math.log(r)) / (1.0 - ra)

    a_lo, a_hi = 1e-4, 50.0
    if score(a_lo) * score(a_hi) > 0:
        return math.nan
    for _ in range(200):
        mid = 0.5 * (a_lo + a_hi)
        if score(a_lo) * score(mid) <= 0:
            a_hi = mid
        else:
            a_lo = mid
    return 0.5 * (a_lo + a_hi)


class Contacts(Compute):
    """The contact network of a packing, its rattlers and coordination.

    Args:
        tolerance: largest gap ``h = r_ij / (R_i + R_j) - 1`` of a contact
            (relative to the contact distance).  Near jamming at reduced
            pressure Z the gaps of contacts are of order ``d / Z`` and the
            next ones follow g(h); the default ``1e-4`` suits ``Z >~ 10^6``;
            see :meth:`plot` (the cumulative ``Z(h)`` has a plateau at the
            contacts' ``z``).
        h_max: largest gap kept for :meth:`gap_exponent` and the plots.

    Attributes (after :meth:`compute`): ``n``, ``dim``, ``pairs`` (contacts,
    ``(M, 2)``), ``near`` and ``gaps`` (all pairs with ``h <= h_max``),
    ``rattler`` (bool per sphere), ``rattler_fraction``, ``contacts`` (per
    sphere in the network without rattlers), ``z`` (mean over
    non-rattlers), ``z_isostatic`` (``2 (d (N' - 1) + 1) / N'``),
    ``z_all`` (mean over all spheres before removal).
    """

    _results = (
        "n",
        "dim",
        "pairs",
        "near",
        "gaps",
        "rattler",
        "rattler_fraction",
        "contacts",
        "z",
        "z_isostatic",
        "z_all",
    )

    def __init__(self, tolerance: float = 1e-4, h_max: float = 0.5) -> None:
        for name, v in (("tolerance", tolerance), ("h_max", h_max)):
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v >= 0):
                raise AnalysisInputError(f"{name} must be a finite number >= 0, got {v!r}")
        self.tolerance, self.h_max = float(tolerance), float(max(h_max, tolerance))

    def compute(
        self,
        source: Simulation | State | ArrayLike,
        box: float | ArrayLike | None = None,
        radii: ArrayLike | None = None,
        forces: ContactForces | None = None,
    ) -> Contacts:
        """The network of ``source`` (a Simulation, a State with ``box``, or positions, ``radii``, ``box``).

        Args:
            forces: a computed :class:`~hardspheres.analysis.collisions.ContactForces`
                of the same packing: its pairs are the contacts (instead of
                the tolerance); the gaps are still measured.

        Returns:
            self
        """
        pos, rad, lengths = _packing(source, box, radii)
        n, dim = len(pos), pos.shape[1]
        self.near, self.gaps = near_pairs(pos, rad, lengths, self.h_max)
        if forces is not None:
            forces._need()
            if forces.n != n:
                raise AnalysisInputError(
                    f"forces: {forces.n} spheres, the packing has {n}; pass this packing's forces"
                )
            self.pairs = np.sort(np.asarray(forces.pairs, np.int64), axis=1)
        else:
            self.pairs = self.near[self.gaps <= self.tolerance]
        self.rattler, self.contacts = remove_rattlers(self.pairs, n, dim)
        keep = ~self.rattler
        n_kept = int(keep.sum())
        self.n, self.dim = n, dim
        self.rattler_fraction = float(1.0 - n_kept / n) if n else math.nan
        self.z = float(self.contacts[keep].mean()) if n_kept else math.nan
        self.z_isostatic = 2.0 * (dim * (n_kept - 1) + 1) / n_kept if n_kept else math.nan
        self.z_all = 2.0 * len(self.pairs) / n if n else math.nan
        self._computed = True
        return self

    def backbone_gaps(self) -> np.ndarray:
        """Gaps of the pairs of non-rattlers that are not contacts (``tolerance < h <= h_max``)."""
        self._need()
        both = ~(self.rattler[self.near[:, 0]] | self.rattler[self.near[:, 1]])
        return self.gaps[both & (self.gaps > self.tolerance)]

    def gap_exponent(self, h_min: float | None = None, h_max: float = 1e-2) -> tuple[float, float, int]:
        """``gamma`` of ``g(h) ~ h^(-gamma)`` among non-rattlers, for gaps in ``(h_min, h_max]``.

        Maximum likelihood of a power-law density on that range (the
        cumulative ``Z(h) - z ~ h^(1 - gamma)``, the form Charbonneau et al.
        fit), with a bootstrap error bar (200 resamples, seed 0).
        ``h_min`` defaults to the tolerance (the gaps just above the contacts).

        Returns:
            ``(gamma, error, count)``: the exponent, its error and the gaps used.
        """
        h = self.backbone_gaps()
        lo = self.tolerance if h_min is None else float(h_min)
        if not 0 <= lo < h_max:
            raise AnalysisInputError(f"h_min must be >= 0 and below h_max = {h_max:g}, got {lo:g}")
        used = h[(h > lo) & (h <= h_max)]
        if len(used) < 10:
            raise AnalysisInputError(
                f"{len(used)} gaps in ({lo:g}, {h_max:g}]: widen the range (h_min, h_max) "
                "or use a larger packing"
            )
        alpha = power_law_exponent(used, lo, h_max)
        err = _bootstrap(used, lambda s: power_law_exponent(s, lo, h_max))
        return 1.0 - alpha, err, len(used)

    def cumulative(self) -> tuple[np.ndarray, np.ndarray]:
        """``(h, Z(h))``: twice the pairs of non-rattlers with gap below h, per non-rattler."""
        self._need()
        both = ~(self.rattler[self.near[:, 0]] | self.rattler[self.near[:, 1]])
        h = np.sort(self.gaps[both])
        kept = max(1, int((~self.rattler).sum()))
        return h, 2.0 * np.arange(1, len(h) + 1) / kept

    def plot(self, ax: Axes | None = None) -> Axes:
        """The cumulative ``Z(h) - z`` against h (log-log); returns the Axes."""
        ax = self._axes(ax)
        h, zh = self.cumulative()
        sel = (h > self.tolerance) & (zh > self.z)
        ax.loglog(h[sel], zh[sel] - self.z)
        ax.set_xlabel("gap h = r / (R_i + R_j) - 1")
        ax.set_ylabel("Z(h) - z")
        ax.set_title(
            f"z = {self.z:.4g} (isostatic {self.z_isostatic:.4g}), rattlers {self.rattler_fraction:.1%}"
        )
        return ax


def isostatic_tolerance(
    source: Simulation | State | ArrayLike,
    box: float | ArrayLike | None = None,
    radii: ArrayLike | None = None,
    h_max: float = 1e-2,
) -> float:
    """The smallest gap tolerance at which the non-rattlers' contacts are isostatic.

    At infinite pressure a jammed packing's network of non-rattlers is
    isostatic, ``d (N' - 1) + 1`` contacts in a periodic box; at a finite
    reduced pressure Z the gaps of weak contacts (about ``d / Z`` over
    ``f / <f>``) and those of the nearest non-contacts overlap, and no
    tolerance separates them cleanly.  This one takes the pairs in order of
    their gap and stops at the first that makes the network (after rattler
    removal) isostatic: 36-85 / Z at Z = 10^6 and 133-352 / Z at Z = 10^7
    for 500 spheres (docs/validation/glass-jamming.md, "Marginal stability").

    Args:
        source, box, radii: the packing, as :meth:`Contacts.compute` takes it.
        h_max: largest gap considered.

    Returns:
        The tolerance (a gap), for ``Contacts(tolerance=...)``.

    Raises:
        ValueError: no gap up to ``h_max`` makes the network isostatic.

    Example:
        >>> # the triangular crystal of disks at contact: isostatic with its contacts
        >>> from hardspheres.builders import MAX_PACKING_2D, hexagonal
        >>> s, box = hexagonal((6, 6), MAX_PACKING_2D)
        >>> isostatic_tolerance(s.positions, box=box.sides, radii=s.radii) < 1e-9
        True
    """
    pos, rad, lengths = _packing(source, box, radii)
    n, dim = len(pos), pos.shape[1]
    pairs, gaps = near_pairs(pos, rad, lengths, h_max)
    order = np.argsort(gaps, kind="stable")
    start = max(1, min(len(order), int(0.8 * dim * n)))  # well below d N contacts: not yet isostatic
    for k in range(start, len(order) + 1):
        rattler, count = remove_rattlers(pairs[order[:k]], n, dim)
        kept = int((~rattler).sum())
        if kept and int(count[~rattler].sum()) // 2 >= dim * (kept - 1) + 1:
            return float(gaps[order[k - 1]])
    raise AnalysisInputError(f"h_max: no gap up to {h_max:g} makes the network isostatic; raise h_max")


def force_exponent(
    forces: ContactForces,
    contacts: Contacts | None = None,
    f_min: float = 0.0,
    f_max: float = 0.3,
    without_bucklers: bool = False,
    contacts_only: bool = False,
) -> tuple[float, float, int]:
    """``theta`` of ``P(f) ~ f^theta`` at small ``f / <f>``, in ``(f_min, f_max]``.

    Args:
        forces: a computed :class:`~hardspheres.analysis.collisions.ContactForces`.
        contacts: a computed :class:`Contacts` of the same packing: only the
            forces between non-rattlers are used (as Charbonneau et al. do).
        f_min, f_max: the range of ``f / <f>`` fitted.
        without_bucklers: also leave out the forces on spheres with exactly
            ``d + 1`` contacts in ``contacts``'s network (the candidates for
            bucklers, whose weak forces are localized rather than extended;
            needs ``contacts``).
        contacts_only: use only the forces of pairs that are contacts of
            ``contacts``'s network (needs ``contacts``).  Near jamming at a
            finite pressure the record also holds pairs that are not
            contacts of the jammed network but collide now and then (their
            number grows with the record); their small forces flatten
            P(f) at small f.  With ``contacts`` cut where the network is
            isostatic (:func:`isostatic_tolerance`), theta of 8 packings of
            500 spheres at Z = 10^6 and 10^7 for f/<f> <= 0.1 is 0.32-0.43
            (+- 0.06) with records of 2000 and 20000 collisions per sphere;
            with every colliding pair it falls from 0.28-0.34 to -0.04-0.19
            between those records (docs/validation/glass-jamming.md, "Marginal stability").

    Maximum likelihood of a power-law density on the range, bootstrap error
    (200 resamples, seed 0).

    Returns:
        ``(theta, error, count)``.
    """
    forces._need()
    f = np.asarray(forces.forces, float)
    if contacts is not None:
        contacts._need()
        p = forces.pairs
        drop = contacts.rattler
        if without_bucklers:
            drop = drop | (contacts.contacts == contacts.dim + 1)
        keep = ~(drop[p[:, 0]] | drop[p[:, 1]])
        if contacts_only:
            net = set(map(tuple, np.sort(contacts.pairs, axis=1).tolist()))
            keep &= np.fromiter((tuple(q) in net for q in np.sort(p, axis=1).tolist()), bool, len(p))
        f = f[keep]
    elif without_bucklers or contacts_only:
        name = "without_bucklers" if without_bucklers else "contacts_only"
        raise AnalysisInputError(f"{name}: pass contacts (the network that says who has d + 1 contacts)")
    if len(f) == 0:
        raise AnalysisInputError(
            "forces: no contact forces between non-rattlers; pass a jammed packing (compress it further)"
        )
    x = f / f.mean()
    used = x[(x > f_min) & (x <= f_max)]
    if len(used) < 10:
        raise AnalysisInputError(f"{len(used)} forces in ({f_min:g}, {f_max:g}] of the mean: widen f_max")
    alpha = power_law_exponent(used, f_min, f_max)
    err = _bootstrap(used, lambda s: power_law_exponent(s, f_min, f_max))
    return alpha - 1.0, err, len(used)


class JammingPoint(Compute):
    """``phi_J`` from ``(phi, Z)`` along a compression: ``Z = d phi_J / (phi_J - phi)``.

    The free-volume form holds near jamming (Z large); ``d / Z - 1 =
    -phi / phi_J`` is fitted by least squares (no intercept) to the points
    with ``Z >= z_min`` (default: the two decades of Z below the largest,
    the end of the compression, where the form holds and the packing
    fraction is that of the packing reached; earlier, faster stages of a
    compression head for other jamming points).  The error is the fit's standard error.  ``d_fit``
    and ``phi_J_free`` come from also fitting the prefactor (``1/Z = a + b
    phi``, ``phi_J = -a / b``, ``d = 1 / a``): ``d_fit`` near ``d`` says the
    form applies.

    Args:
        dim: dimension ``d``.
        z_min: smallest Z used (default ``max(Z) / 100``, at least 10).

    Attributes (after :meth:`compute`): ``phi_J``, ``error``, ``d_fit``,
    ``phi_J_free``, ``points`` (used).
    """

    _results = ("phi_J", "error", "d_fit", "phi_J_free", "points", "phi", "Z")

    def __init__(self, dim: int = 3, z_min: float | None = None) -> None:
        self.dim, self.z_min = int(dim), z_min

    def compute(self, phi: ArrayLike, Z: ArrayLike) -> JammingPoint:
        """Fit to packing fractions ``phi`` and reduced pressures ``Z`` (``compress(progress=...)``'s)."""
        phi, Z = np.asarray(phi, float), np.asarray(Z, float)
        if phi.shape != Z.shape:
            raise AnalysisInputError(f"phi and Z: {phi.shape} and {Z.shape} values; pass one Z per phi")
        ok = np.isfinite(phi) & np.isfinite(Z)
        if not ok.any():
            raise AnalysisInputError("Z: no finite values; pass the measured reduced pressures")
        z_min = max(float(np.max(Z[ok])) / 100.0, 10.0) if self.z_min is None else float(self.z_min)
        sel = ok & (Z >= z_min)
        if sel.sum() < 3:
            raise AnalysisInputError(
                f"Z: {int(sel.sum())} points with Z >= z_min = {z_min:g}; compress further or lower z_min"
            )
        p, z = phi[sel], Z[sel]
        y = self.dim / z - 1.0
        u = -float(np.dot(p, y) / np.dot(p, p))  # 1 / phi_J
        res = y + u * p
        du = math.sqrt(float(np.dot(res, res)) / (len(p) - 1) / float(np.dot(p, p)))
        self.phi_J, self.error = 1.0 / u, du / u**2
        b, a = np.polyfit(p, 1.0 / z, 1)
        self.d_fit, self.phi_J_free = 1.0 / a, -a / b
        self.points, self.phi, self.Z = int(sel.sum()), p, z
        self._computed = True
        return self

    def plot(self, ax: Axes | None = None) -> Axes:
        """``d / Z`` against ``phi`` with the fitted line (zero at phi_J); returns the Axes."""
        ax = self._axes(ax)
        ax.plot(self.phi, self.dim / self.Z, ".", label="compression")
        x = np.linspace(self.phi.min(), self.phi_J, 50)
        ax.plot(x, 1.0 - x / self.phi_J, "--", label=f"phi_J = {self.phi_J:.5f}")
        ax.set_xlabel("packing fraction")
        ax.set_ylabel("d / Z")
        ax.legend()
        return ax


class PackingSummary(NamedTuple):
    """What :func:`summarize_packing` finds (``nan`` where it cannot say).

    ``z_low``/``z_high`` and ``rattlers_low``/``rattlers_high``: with
    contacts at gaps below ``30 / Z`` and ``100 / Z``.
    """

    z_low: float
    z_high: float
    z_isostatic: float
    rattlers_low: float
    rattlers_high: float
    phi_J: float
    phi_J_error: float
    fit_points: int

    @property
    def short_of_isostatic(self) -> bool:
        """z below isostatic at both contact tolerances, so the compression stopped short of jamming.

        Too fast a compression leaves the contact network hypostatic (at
        ``rate = 0.01``, 2-4% short of isostatic; at 0.001 within 1%): the
        spheres are stuck, not jammed.  ``False`` when z is not known.
        """
        return bool(self.z_high < self.z_isostatic)  # NaN compares False


#: Contact tolerances of :func:`summarize_packing`, times the reduced pressure Z.
CONTACT_GAPS_Z = (30.0, 100.0)


def summarize_packing(
    sim: Simulation,
    phi: ArrayLike = (),
    Z: ArrayLike = (),
    pressure: float | None = None,
) -> PackingSummary:
    """z, the rattler fraction and phi_J of a compressed packing in a periodic box.

    Near jamming the gaps of a sphere to its contacts shrink as ``1 / Z``
    (free volume: about ``d / Z`` of the contact distance) while the other
    gaps follow g(h), so a contact is a gap below ``c / Z``.  At ``Z ~
    10^5 - 10^6`` there is no clean plateau between the two: z is given for
    ``c = 30`` and ``c = 100`` (docs/validation/glass-jamming.md, "Isostaticity": isostatic
    within 1% between them at ``Z > 10^6``).  ``phi_J`` is
    :class:`JammingPoint`'s fit to the compression's ``(phi, Z)`` when it
    reached ``Z >= 100`` (``nan`` otherwise).

    Args:
        sim: the packing (its state now).
        phi, Z: the compression's packing fractions and reduced pressures.
        pressure: the packing's Z (default the last of ``Z``); without one
            (or below 1e3) z is not computed.

    Raises:
        PeriodicBoxRequired: not a periodic box.
    """
    if not sim.container.periodic:
        raise PeriodicBoxRequired("jamming analyses need a periodic box")
    Z = np.asarray(Z, float)
    phi = np.asarray(phi, float)
    dim = sim.state().positions.shape[1]
    pressure = float(Z[-1]) if pressure is None and len(Z) else pressure
    z = [math.nan, math.nan]
    ratt = [math.nan, math.nan]
    z_iso = math.nan
    if pressure is not None and pressure >= 1e3:
        for k, c in enumerate(CONTACT_GAPS_Z):
            net = Contacts(tolerance=c / pressure, h_max=c / pressure).compute(sim)
            z[k], ratt[k], z_iso = net.z, net.rattler_fraction, net.z_isostatic
    phi_j = err = math.nan
    points = 0
    if len(Z) and np.nanmax(Z) >= 100:
        try:
            jp = JammingPoint(dim=dim).compute(phi, Z)
            phi_j, err, points = jp.phi_J, jp.error, jp.points
        except ValueError:
            pass
    return PackingSummary(z[0], z[1], z_iso, ratt[0], ratt[1], phi_j, err, points)


__all__ = [
    "Contacts",
    "JammingPoint",
    "CONTACT_GAPS_Z",
    "PackingSummary",
    "NotComputedError",
    "force_exponent",
    "isostatic_tolerance",
    "near_pairs",
    "power_law_exponent",
    "remove_rattlers",
    "summarize_packing",
]

"""Dynamics of glass formers: F_s(k, t), F(k, t), alpha_2, G_s(r, t), Q(t), chi_4 and tau_alpha.

Compute objects in the style of freud (``compute()`` returns the object,
results read before it raise :class:`NotComputedError`, ``plot(ax=None)``
returns Axes), for a trajectory in a periodic box in any dimension
(positions ``(N, d)``):

* :class:`SelfIntermediate`: the self-intermediate scattering function
  ``F_s(k, t) = < (1/N) sum_i exp(i k . (r_i(t0 + t) - r_i(t0))) >``, its
  fluctuation ``chi_s(t) = N var F_s`` and :meth:`~SelfIntermediate.tau_alpha`
  (``F_s = 1/e``);
* :class:`CollectiveIntermediate`: ``F(k, t) = < rho_k(t0 + t) rho_-k(t0) > / N``
  (``F(k, 0) = S(k)``);
* :class:`NonGaussian`: the MSD and ``alpha_2(t) = d <dr^4> / ((d + 2) <dr^2>^2) - 1``;
* :class:`VanHove`: the self van Hove function ``G_s(r, t)``;
* :class:`Overlap`: ``Q(t) = < (1/N) sum_i Theta(a - |dr_i|) >`` and the
  four-point susceptibility ``chi_4(t) = N (<Q^2> - <Q>^2)``.

**Wave vectors (the k-shells).** ``F_s`` is averaged over *all* directions
of ``|k| = k`` exactly (``shell="isotropic"``, the default): the average of
``exp(i k . dr)`` over the sphere of directions is ``sin(k r) / (k r)`` in
3-D and ``J_0(k r)`` in 2-D, so no finite set of vectors is chosen and
there is no shell width.  ``shell="lattice"`` instead averages over the
box's own wave vectors ``2 pi n / L`` with ``| |k| - k | <= dk / 2`` (``dk``
default ``2 pi / L``, the lattice spacing), at most ``max_vectors`` of them
(a seeded, fixed choice), as :class:`CollectiveIntermediate` must (the
density ``rho_k`` is only periodic for lattice vectors).  Below ``2 pi / L``
there is no lattice vector, and displacements of the order of the box
are not those of an infinite system: ``k < 2 pi / L`` is refused (``L``
the longest side of a rectangular box, :attr:`PeriodicBox.sides
<hardspheres.containers.PeriodicBox.sides>`).

**Lags and origins.** Frames may be equally spaced, log-spaced from one
origin (:class:`hardspheres.writers.LogSpaced`) or log-spaced from many
(:class:`hardspheres.writers.LogOrigins`, the multiple-origin schedule).
Default lags are ``per_decade`` per decade on a log scale, each the time
between the first frame and another (so every lag has at least one pair of
frames).  For each lag every pair of frames that far apart (to ``1e-6`` of
the lag) whose first frame is a time origin is used; the origins are every
frame, or frames at least ``origin_every`` [time] apart (the time-origin
stride).  A lag with no pair is refused, naming ``lags``.

**Error bars.** The origins of each lag are split into ``blocks``
consecutive groups; the error is the standard deviation of the groups'
means over ``sqrt(groups)`` (``nan`` with fewer than two origins).  Groups
of consecutive origins are nearly independent once they are longer than
the relaxation time; with origins close together the bar is an estimate.

**Memory.** Only two frames are held at a time (a trajectory file is read
frame by frame: pass its path), plus a few numbers per lag and origin:
``N = 10^4`` spheres over ``10^4`` frames need a few megabytes beyond the
source.  :class:`CollectiveIntermediate` keeps ``rho_k`` per frame and wave
vector (``16 F K`` bytes).

Example:
    >>> import hardspheres as hs
    >>> from hardspheres.io.trajectory import frames_from_simulation
    >>> sim = hs.Simulation(hs.random_spheres(108, 0.3, box=7.0, seed=1), hs.PeriodicBox(7.0))
    >>> fr = frames_from_simulation(sim, until=2.0, every=0.05)
    >>> fs = SelfIntermediate(k=2 * 3.14159).compute(fr)
    >>> bool(fs.F[0, 0] < 1.0) and fs.t.shape == (fs.F.shape[0],)
    True
"""

from __future__ import annotations

import math
import os
import warnings
from collections.abc import Callable, Iterator
from typing import TYPE_CHECKING, Any, cast

import numpy as np

from ..errors import (
    AnalysisInputError,
    NotComputedError,
    PeriodicBoxRequired,
    ResolutionWarning,
    TrajectoryError,
)
from .compute import Compute

if TYPE_CHECKING:
    from typing import TypeAlias

    from matplotlib.axes import Axes
    from numpy.typing import ArrayLike

    from ..containers import Container, PeriodicBox
    from ..frames import Frames

    #: What the correlators accept (Frames, a ``.gsd`` path, or unwrapped positions ``(F, N, d)``).
    Source: TypeAlias = "Frames | str | os.PathLike[str] | ArrayLike | _Source"
    #: ``(lag, origins i, frames j)`` for each lag.
    Plan: TypeAlias = list[tuple[float, np.ndarray, np.ndarray]]

#: F_s at the alpha-relaxation time, ``1/e``.
INV_E = math.exp(-1.0)


# ---- the frames ---------------------------------------------------------------------
class _Source:
    """Frames one at a time: ``times (F,)``, ``lengths (d,)``, ``unwrapped(f) (N, d)``."""

    def __init__(
        self,
        times: ArrayLike,
        lengths: ArrayLike,
        get: Callable[[int], np.ndarray],
        radii: ArrayLike | None,
        masses: ArrayLike | None,
        n: int,
    ) -> None:
        self.times = np.asarray(times, float)
        self.lengths = np.asarray(lengths, float)
        self._get = get
        self.radii = None if radii is None else np.asarray(radii, float)
        self.masses = None if masses is None else np.asarray(masses, float)
        self.n = int(n)

    @property
    def dim(self) -> int:
        return len(self.lengths)

    def unwrapped(self, f: int) -> np.ndarray:
        return self._get(int(f))


def box_sides(container: Container, dim: int) -> np.ndarray:
    """The box's sides ``(d,)``: ``sides`` (rectangular boxes), else the cube's ``length``."""
    sides = getattr(container, "sides", None)
    if sides is None:
        sides = cast("PeriodicBox", container).length
    return np.broadcast_to(np.asarray(sides, float).reshape(-1), (dim,)).copy()


def _source(
    source: Source, what: str, box: float | ArrayLike | None = None, times: ArrayLike | None = None
) -> _Source:
    """A :class:`_Source` from Frames, a GSD path, or unwrapped positions ``(F, N, d)``."""
    from ..frames import Frames

    if isinstance(source, _Source):
        return source
    if isinstance(source, (str, os.PathLike)):
        return _gsd_source(os.fspath(source), what)
    if isinstance(source, Frames):
        c = source.container
        if c is None or not c.periodic:
            raise PeriodicBoxRequired(
                f"{what} need a periodic box (in a spherical container the wall bounds the "
                "displacements); simulate in hs.PeriodicBox(L)"
            )
        if source.images is None:
            raise PeriodicBoxRequired(
                f"{what} need image counts: a periodic-box run recorded with GSDWriter or "
                "frames_from_simulation (XYZ files carry none, nor GSD files without particles/image)"
            )
        pos, img = source.positions, source.images
        dim = pos.shape[-1]
        lengths = box_sides(c, dim)
        return _Source(
            source.times,
            lengths,
            lambda f: pos[f] + img[f] * lengths,
            source.radii,
            source.masses,
            source.n,
        )
    if times is None or box is None:
        raise AnalysisInputError(
            f"{what}: pass Frames, a .gsd trajectory, or unwrapped positions (F, N, d) with times and box"
        )
    pos = np.asarray(source, float)
    if pos.ndim != 3:
        raise AnalysisInputError(
            f"{what}: positions must be (frames, N, d), got shape {pos.shape}; "
            "stack one (N, d) array per frame"
        )
    lengths = np.broadcast_to(np.asarray(box, float), (pos.shape[-1],)).copy()
    return _Source(times, lengths, lambda f: pos[f], None, None, pos.shape[1])


def _gsd_source(path: str, what: str) -> _Source:
    """Frames of a GSD trajectory read on demand (the file stays open for the object's life)."""
    from ..extras import need

    gsd_hoomd = need("gsd.hoomd", f"{what} of a GSD trajectory")
    from ..containers import from_fields

    try:
        traj = gsd_hoomd.open(path, mode="r")
    except (OSError, RuntimeError) as e:
        raise TrajectoryError(f"{path}: cannot read as GSD ({e}); give a complete .gsd file") from None
    if len(traj) == 0:
        raise TrajectoryError(f"{path}: no frames; read a trajectory its run wrote frames to")
    first = traj[0]
    if "hardspheres/time" not in first.log:  # HOOMD-blue's schema: read whole, as read_trajectory does
        traj.close()
        from ..io.trajectory import read_trajectory

        return _source(read_trajectory(path), what)
    container = from_fields(first.log)
    if not container.periodic:
        raise PeriodicBoxRequired(f"{what} need a periodic box; {path} is in a {container.label}")
    if "hardspheres/images" not in first.log:
        raise PeriodicBoxRequired(f"{what} need image counts; {path} has none")
    n = int(first.particles.N)
    dim = int(getattr(first.configuration, "dimensions", 3) or 3)
    lengths = box_sides(container, dim)
    # times from the per-frame log (one small read per frame)
    times = np.array(
        [float(traj.read_frame(f).log["hardspheres/time"][0]) for f in range(len(traj))]
        if hasattr(traj, "read_frame")
        else [float(traj[f].log["hardspheres/time"][0]) for f in range(len(traj))]
    )

    def get(f: int) -> np.ndarray:
        fr = traj[f]
        x = np.asarray(fr.particles.position, float).reshape(n, 3)[:, :dim]
        im = np.asarray(fr.particles.image, np.int64).reshape(n, 3)[:, :dim]
        return x + im * lengths

    return _Source(
        times,
        lengths,
        get,
        np.asarray(first.particles.diameter, float) / 2.0,
        np.asarray(first.particles.mass, float),
        n,
    )


# ---- lags and origins ---------------------------------------------------------------
def log_lags(times: ArrayLike, per_decade: float = 10) -> np.ndarray:
    """Log-spaced lags of frames at ``times``: about ``per_decade`` per decade.

    Each lag is the time from the first frame to another frame (the one
    nearest, on a log scale, to each point of a log grid from the shortest
    to the longest such time), so that each has at least one pair of frames.

    Example:
        >>> log_lags(np.arange(101.0), per_decade=2).tolist()
        [1.0, 3.0, 10.0, 32.0, 100.0]
    """
    t = np.asarray(times, float)
    cand = np.unique(t[1:] - t[0])
    cand = cand[cand > 0]
    if len(cand) == 0:
        raise AnalysisInputError("lags: the frames span no time; record at least two frames")
    lo, hi = cand[0], cand[-1]
    num = max(2, int(round(per_decade * math.log10(hi / lo))) + 1) if hi > lo else 1
    grid = np.geomspace(lo, hi, num)
    idx = np.abs(np.log(cand)[None, :] - np.log(grid)[:, None]).argmin(axis=1)
    return cand[np.unique(idx)]


def _origins(times: np.ndarray, origin_every: float | None) -> np.ndarray:
    """Indices of the frames used as time origins: all, or greedily ``origin_every`` apart."""
    if not origin_every:
        return np.arange(len(times))
    every = float(origin_every)
    if not (math.isfinite(every) and every > 0):
        raise AnalysisInputError(f"origin_every must be a finite time > 0, got {origin_every!r}")
    keep, last = [], -math.inf
    for k, t in enumerate(times):
        if t >= last + every * (1.0 - 1e-9):
            keep.append(k)
            last = t
    return np.array(keep, np.int64)


def _pairs(times: np.ndarray, origins: np.ndarray, lag: float) -> tuple[np.ndarray, np.ndarray]:
    """``(i, j)`` frame indices with ``t_j - t_i = lag`` (to 1e-6 of it), ``i`` an origin."""
    t0 = times[origins]
    tol = 1e-6 * lag
    j = np.searchsorted(times, t0 + lag - tol)
    ok = j < len(times)
    jj = np.minimum(j, len(times) - 1)
    ok &= np.abs(times[jj] - t0 - lag) <= tol
    return origins[ok], jj[ok]


def _plan(
    src: _Source,
    what: str,
    lags: ArrayLike | None,
    per_decade: float,
    origin_every: float | None,
    min_frames: int = 2,
) -> Plan:
    times = src.times
    if len(times) < min_frames:
        raise AnalysisInputError(f"{what}: {len(times)} frame(s); record at least {min_frames}")
    if np.any(np.diff(times) <= 0):
        raise AnalysisInputError(
            f"{what}: frame times must increase; pass the frames in time order, each time once"
        )
    if lags is None:
        lags = log_lags(times, per_decade)
    else:
        lags = np.atleast_1d(np.asarray(lags, float))
        if lags.size == 0 or not np.all(np.isfinite(lags)) or np.any(lags <= 0):
            raise AnalysisInputError(f"lags must be finite times > 0, got {lags.tolist()}")
    origins = _origins(times, origin_every)
    plan = []
    for lag in lags:
        i, j = _pairs(times, origins, float(lag))
        if len(i) == 0:
            raise AnalysisInputError(
                f"lags: no pair of frames {lag:g} apart (the frames span {times[-1] - times[0]:g}"
                f"{' with origins every %g' % origin_every if origin_every else ''}); "
                "ask for shorter lags or record a longer run"
            )
        plan.append((float(lag), i, j))
    return plan


def _block_stats(
    values: ArrayLike, blocks: int, stat: Callable[..., Any] = np.mean
) -> tuple[Any, Any]:  # numbers, or arrays per column
    """``(statistic of all, error from the groups' spread)`` of per-origin ``values (O, ...)``."""
    values = np.asarray(values, float)
    whole = stat(values, axis=0)
    g = min(int(blocks), len(values))
    if g < 2:
        return whole, np.full_like(np.asarray(whole, float), np.nan)
    parts = [stat(p, axis=0) for p in np.array_split(values, g)]
    return whole, np.std(parts, axis=0, ddof=1) / math.sqrt(g)


def _sigma(src: _Source) -> float:
    if src.radii is None or len(src.radii) == 0:
        return 1.0
    return 2.0 * float(np.mean(src.radii))


def _check_k(k: ArrayLike, lengths: np.ndarray, name: str = "k") -> np.ndarray:
    ks = np.atleast_1d(np.asarray(k, float))
    kmin = 2.0 * math.pi / float(np.max(lengths))
    if ks.size == 0 or not np.all(np.isfinite(ks)):
        raise AnalysisInputError(f"{name} must be finite wave numbers [1/length], got {ks.tolist()}")
    bad = ks[ks < kmin * (1.0 - 1e-9)]
    if bad.size:
        raise AnalysisInputError(
            f"{name} = {bad[0]:g} is below 2 pi / L = {kmin:.4g}, the smallest wave number the box has; "
            "give a larger k (or a larger box)"
        )
    return ks


def lattice_vectors(
    k: float, lengths: ArrayLike, dk: float | None = None, max_vectors: int = 200, seed: int = 0
) -> np.ndarray:
    """Wave vectors ``2 pi n / L`` of the box with ``| |q| - k | <= dk / 2``: ``(K, d)``.

    Only one of each pair ``q, -q`` is kept (the correlators are real).  At
    most ``max_vectors``: a fixed random choice (``seed``) if there are more.

    Example:
        >>> import math
        >>> lattice_vectors(2 * math.pi, [1.0, 1.0, 1.0], dk=1.0).round(6).tolist()
        [[0.0, 0.0, 6.283185], [0.0, 6.283185, 0.0], [6.283185, 0.0, 0.0]]
    """
    lengths = np.asarray(lengths, float)
    step = 2.0 * math.pi / lengths
    dk = float(step.min()) if dk is None else float(dk)
    if not (math.isfinite(dk) and dk > 0):
        raise AnalysisInputError(f"dk must be a finite wave number > 0, got {dk!r}")
    hi = k + 0.5 * dk
    axes = [np.arange(-int(hi / s), int(hi / s) + 1) for s in step]
    grid = np.stack(np.meshgrid(*axes, indexing="ij"), -1).reshape(-1, len(lengths))
    q = grid * step
    mag = np.linalg.norm(q, axis=1)
    sel = np.abs(mag - k) <= 0.5 * dk * (1.0 + 1e-9)
    # one of q, -q: the first nonzero component positive
    first = np.array([row[np.flatnonzero(row)[0]] if row.any() else 0 for row in grid])
    sel &= first > 0
    q = q[sel]
    if len(q) == 0:
        raise AnalysisInputError(f"k: no wave vector of the box within dk = {dk:g} of {k:g}; widen dk")
    if len(q) > max_vectors:
        rng = np.random.default_rng(seed)
        q = q[np.sort(rng.choice(len(q), int(max_vectors), replace=False))]
    return q


def _phases(x: np.ndarray, q: np.ndarray, lengths: ArrayLike) -> np.ndarray:
    """``exp(i q . x)`` ``(N, V)`` for lattice vectors ``q = 2 pi n / L`` (integer ``n``).

    By axes: ``prod_a w_a^(n_a)`` with ``w_a = exp(2 pi i x_a / L_a)``, its
    powers made by repeated multiplication (``|n_a|`` is a few): a complex
    product per element and axis instead of a complex exponential (5-10x
    faster); the rounding grows with ``|n|``, ~1e-15 per power.
    """
    step = 2.0 * math.pi / np.asarray(lengths, float)
    n = np.rint(q / step).astype(np.int64)
    out: np.ndarray | None = None
    for a in range(x.shape[1]):
        top = int(np.abs(n[:, a]).max())
        w = np.exp(1j * step[a] * x[:, a])
        pw = np.empty((x.shape[0], 2 * top + 1), complex)
        pw[:, top] = 1.0
        for m in range(1, top + 1):
            pw[:, top + m] = pw[:, top + m - 1] * w
            pw[:, top - m] = np.conj(pw[:, top + m])
        f = pw[:, n[:, a] + top]
        out = f if out is None else out * f
    return cast(np.ndarray, out)  # x has at least one axis


def _isotropic(kr: np.ndarray, dim: int) -> np.ndarray:
    """The average of ``cos(k . dr)`` over directions at ``|k| |dr| = kr``."""
    if dim == 3:
        return np.sinc(kr / math.pi)  # sin(x)/x
    if dim == 2:
        from ..extras import need

        return need("scipy.special", "an isotropic average in two dimensions").j0(kr)
    return np.cos(kr)


class _Dynamic(Compute):
    """Shared parameters of the correlators: lags, origins and error groups."""

    def __init__(
        self,
        lags: ArrayLike | None = None,
        per_decade: float = 10,
        origin_every: float | None = None,
        blocks: int = 5,
    ) -> None:
        if int(blocks) != blocks or blocks < 1:
            raise AnalysisInputError(f"blocks must be a whole number >= 1, got {blocks!r}")
        if not (isinstance(per_decade, (int, float)) and per_decade > 0):
            raise AnalysisInputError(f"per_decade must be a number > 0, got {per_decade!r}")
        self.lags, self.per_decade, self.origin_every, self.blocks = lags, per_decade, origin_every, blocks

    def _prepare(
        self, source: Source, what: str, box: float | ArrayLike | None = None, times: ArrayLike | None = None
    ) -> tuple[_Source, Plan]:
        src = _source(source, what, box, times)
        plan = _plan(src, what, self.lags, self.per_decade, self.origin_every)
        return src, plan

    @staticmethod
    def _displacements(src: _Source, i: np.ndarray, j: np.ndarray) -> Iterator[np.ndarray]:
        """Displacements of the pairs ``(i[m], j[m])``, one ``(N, d)`` at a time (frames cached)."""
        cache: dict[int, np.ndarray] = {}
        for a, b in zip(i.tolist(), j.tolist()):
            if a not in cache:
                cache.clear()
                cache[a] = src.unwrapped(a)
            yield src.unwrapped(b) - cache[a]


def _as_k(k: ArrayLike) -> np.ndarray:
    return np.atleast_1d(np.asarray(k, float))


class SelfIntermediate(_Dynamic):
    """Self-intermediate scattering function F_s(k, t), its fluctuation and tau_alpha.

    Args:
        k: wave number(s) [1/length] (e.g. ``2 pi / sigma``, near the first
            peak of S(k)); each at least ``2 pi / L``.
        shell: ``"isotropic"`` (every direction of ``|k|``: ``sin(kr)/kr``
            in 3-D, ``J_0(kr)`` in 2-D) or ``"lattice"`` (the box's wave
            vectors in a shell ``dk`` wide, at most ``max_vectors``).
        lags, per_decade, origin_every, blocks: see the module docstring.

    Attributes (after :meth:`compute`): ``t`` lags ``(T,)``, ``k`` ``(K,)``,
    ``F`` ``(T, K)``, ``error`` ``(T, K)`` (from the spread over origins),
    ``particle_error`` ``(T, K)`` (the spread over spheres, ``sqrt(var_i /
    N)`` at one origin: the bar to use when the origins are not independent,
    e.g. a run shorter than the relaxation, or ballistic flight), ``chi``
    ``(T, K)`` (``N var F_s`` over origins), ``origins`` ``(T,)`` origins per
    lag, ``n``, ``dim``.

    Example:
        ``F_s`` of a run's frames at the first peak of S(k)::

            fs = hs.SelfIntermediate(k=2 * np.pi).compute("run.gsd")
            fs.tau_alpha(), fs.plot()
    """

    _results = ("t", "k", "F", "error", "particle_error", "chi", "origins", "n", "dim")

    def __init__(
        self,
        k: ArrayLike,
        shell: str = "isotropic",
        dk: float | None = None,
        max_vectors: int = 50,
        lags: ArrayLike | None = None,
        per_decade: float = 10,
        origin_every: float | None = None,
        blocks: int = 5,
    ) -> None:
        super().__init__(lags, per_decade, origin_every, blocks)
        if shell not in ("isotropic", "lattice"):
            raise AnalysisInputError(f"shell must be 'isotropic' or 'lattice', got {shell!r}")
        self.k_asked, self.shell, self.dk, self.max_vectors = _as_k(k), shell, dk, max_vectors

    def compute(
        self, source: Source, box: float | ArrayLike | None = None, times: ArrayLike | None = None
    ) -> SelfIntermediate:
        """F_s of ``source``; returns self.

        ``source``: :class:`hardspheres.Frames`, the path of a ``.gsd``
        trajectory (read a frame at a time), or unwrapped positions
        ``(F, N, d)`` with ``box`` [length] and ``times`` [time].

        Raises:
            PeriodicBoxRequired: not a periodic box.
            ValueError: a ``k`` below ``2 pi / L``, too few frames, or a lag
                no pair of frames has (the message names the argument).
        """
        src, plan = self._prepare(source, "intermediate scattering functions", box, times)
        ks = _check_k(self.k_asked, src.lengths)
        vecs = None
        if self.shell == "lattice":
            vecs = [lattice_vectors(k, src.lengths, self.dk, self.max_vectors) for k in ks]
        F, err, perr, chi, count = [], [], [], [], []
        for _, i, j in plan:
            per = np.empty((len(i), len(ks)))
            spread = np.empty((len(i), len(ks)))
            for m, dx in enumerate(self._displacements(src, i, j)):
                if vecs is None:
                    r = np.sqrt(np.einsum("nd,nd->n", dx, dx))
                    c = _isotropic(np.outer(ks, r), src.dim)
                else:
                    c = np.stack([_phases(dx, q, src.lengths).real.mean(axis=1) for q in vecs])
                per[m], spread[m] = c.mean(axis=1), c.var(axis=1)
            f, e = _block_stats(per, self.blocks)
            F.append(f)
            err.append(e)
            perr.append(np.sqrt(spread.mean(axis=0) / src.n))
            chi.append(src.n * per.var(axis=0))
            count.append(len(i))
        self.t = np.array([lag for lag, _, _ in plan])
        self.k, self.F, self.error = ks, np.array(F), np.array(err)
        self.particle_error = np.array(perr)
        self.chi, self.origins = np.array(chi), np.array(count)
        self.n, self.dim = src.n, src.dim
        self._computed = True
        return self

    def tau_alpha(self, level: float = INV_E, k_index: int = 0) -> tuple[float, float]:
        """The alpha-relaxation time: the first lag where F_s falls to ``level`` (1/e).

        Interpolated linearly in ``log t`` between the lags on either side;
        the error comes from doing the same to ``F +- error`` (NaN when the
        lags there have too few origins for an error bar).

        Returns:
            ``(tau, error)`` [time].

        Raises:
            AnalysisInputError: F_s stays above ``level`` over the lags (run
                longer), or is below it already at the first lag (the
                crossing is earlier than the frames resolve: record frames
                at shorter lags, e.g. ``run --log-frames``).

        Warns:
            ResolutionWarning: the crossing is between the last two lags,
                the ones with the fewest time origins.
        """
        self._need()
        return _crossing(self.t, self.F[:, k_index], self.error[:, k_index], level, "F_s")

    def plot(self, ax: Axes | None = None) -> Axes:
        """F_s(k, t) against log t, with error bars; returns the Axes."""
        ax = self._axes(ax)
        for c, k in enumerate(self.k):
            ax.errorbar(self.t, self.F[:, c], yerr=self.error[:, c], label=f"k = {k:.3g}", capsize=2)
        ax.axhline(INV_E, color="grey", lw=0.5, ls=":")
        ax.set_xscale("log")
        ax.set_xlabel("t")
        ax.set_ylabel("F_s(k, t)")
        ax.legend()
        return ax


def _crossing(t: np.ndarray, f: np.ndarray, e: np.ndarray, level: float, what: str) -> tuple[float, float]:
    def cross(y: np.ndarray) -> float:
        below = np.flatnonzero(y <= level)
        if len(below) == 0:
            return math.nan
        b = below[0]
        if b == 0:
            return float(t[0])
        x0, x1 = math.log(t[b - 1]), math.log(t[b])
        y0, y1 = y[b - 1], y[b]
        return math.exp(x0 + (y0 - level) / (y0 - y1) * (x1 - x0))

    tau = cross(f)
    if math.isnan(tau):
        raise AnalysisInputError(
            f"{what} stays above {level:.4g} up to t = {t[-1]:g}: no alpha relaxation in the lags; "
            "record a longer run"
        )
    b = int(np.flatnonzero(f <= level)[0])
    if b == 0:
        raise AnalysisInputError(
            f"{what} is {f[0]:.3g}, already below {level:.4g}, at the first lag t = {t[0]:g}: the "
            "crossing is earlier than the frames resolve; record frames at shorter lags "
            "(run --log-frames, writers.LogOrigins)"
        )
    if b == len(t) - 1:
        warnings.warn(
            ResolutionWarning(
                f"{what} crosses {level:.4g} only between the last two lags (t = {t[-2]:g} .. {t[-1]:g}), "
                "the ones with the fewest time origins; record a longer run"
            ),
            stacklevel=3,
        )
    if not (np.isfinite(e[b - 1]) and np.isfinite(e[b])):
        return tau, math.nan  # too few origins there for an error bar
    hi, lo = cross(f + e), cross(f - e)
    spread = [abs(x - tau) for x in (hi, lo) if not math.isnan(x)]
    return tau, (max(spread) if spread else math.nan)


class NonGaussian(_Dynamic):
    """Mean squared displacement and the non-Gaussian parameter alpha_2(t).

    ``alpha_2 = d <dr^4> / ((d + 2) <dr^2>^2) - 1``: zero when displacements
    are Gaussian (ballistic flight with Maxwell-Boltzmann velocities, and
    diffusion at long times), positive in between in a glass former.

    Attributes (after :meth:`compute`): ``t``, ``msd``, ``msd_error``,
    ``alpha2``, ``alpha2_error`` (spread over origins),
    ``alpha2_particle_error`` (spread over spheres at one origin, by the
    delta method; see :class:`SelfIntermediate`), ``origins``.
    """

    _results = ("t", "msd", "msd_error", "alpha2", "alpha2_error", "alpha2_particle_error", "origins", "dim")

    def compute(
        self, source: Source, box: float | ArrayLike | None = None, times: ArrayLike | None = None
    ) -> NonGaussian:
        """alpha_2 of ``source`` (as :meth:`SelfIntermediate.compute`); returns self."""
        src, plan = self._prepare(source, "non-Gaussian parameters", box, times)
        d = src.dim
        names = ("msd", "msd_error", "alpha2", "alpha2_error", "origins", "alpha2_particle_error")
        out: dict[str, list] = {k: [] for k in names}

        def alpha(m: ArrayLike, axis: int = 0) -> np.ndarray:
            m = np.asarray(m)
            r2, r4 = np.mean(m[..., 0], axis=axis), np.mean(m[..., 1], axis=axis)
            return d * r4 / ((d + 2) * r2 * r2) - 1.0

        for _, i, j in plan:
            per = np.empty((len(i), 2))
            pvar = np.empty(len(i))
            for m, dx in enumerate(self._displacements(src, i, j)):
                r2 = np.einsum("nd,nd->n", dx, dx)
                m2, m4 = r2.mean(), (r2 * r2).mean()
                per[m] = m2, m4
                # delta method: alpha_2's variance from the spheres' spread of (r^2, r^4)
                grad = np.array([-2.0 * m4 / m2**3, 1.0 / m2**2]) * d / (d + 2) if m2 > 0 else np.zeros(2)
                cov = np.cov(np.stack([r2, r2 * r2])) if len(r2) > 1 else np.zeros((2, 2))
                pvar[m] = grad @ cov @ grad / len(r2)
            msd, msd_e = _block_stats(per[:, 0], self.blocks)
            a2, a2_e = _block_stats(per, self.blocks, stat=alpha)
            for key, v in zip(out, (msd, msd_e, a2, a2_e, len(i), math.sqrt(pvar.mean()))):
                out[key].append(float(v))
        self.t = np.array([lag for lag, _, _ in plan])
        for key, v in out.items():
            setattr(self, key, np.array(v))
        self.dim = d
        self._computed = True
        return self

    def plot(self, ax: Axes | None = None) -> Axes:
        """alpha_2 against log t; returns the Axes."""
        ax = self._axes(ax)
        ax.errorbar(self.t, self.alpha2, yerr=self.alpha2_error, capsize=2)
        ax.axhline(0.0, color="grey", lw=0.5)
        ax.set_xscale("log")
        ax.set_xlabel("t")
        ax.set_ylabel("alpha_2(t)")
        return ax


class VanHove(_Dynamic):
    """Self van Hove function G_s(r, t): the distribution of the distance moved in t.

    ``G_s(r, t)`` is normalised so that ``int G_s S_d r^(d-1) dr = 1`` (``S_d``
    the area of the unit sphere: ``4 pi`` in 3-D, ``2 pi`` in 2-D), so it is
    ``(2 pi <dx^2>)^(-d/2) exp(-r^2 / (2 <dx^2>))`` for Gaussian displacements.

    Args:
        bins: number of bins of r.
        r_max: largest r [length]; default twice the largest displacement's
            root mean square over the lags, at least ``sigma``.

    Attributes (after :meth:`compute`): ``t`` ``(T,)``, ``r`` bin centres
    ``(R,)``, ``edges``, ``G`` ``(T, R)``, ``P`` ``(T, R)`` (the probability
    density of ``|dr|``, ``G S_d r^(d-1)``).
    """

    _results = ("t", "r", "edges", "G", "P", "dim")

    def __init__(
        self,
        bins: int = 100,
        r_max: float | None = None,
        lags: ArrayLike | None = None,
        per_decade: float = 4,
        origin_every: float | None = None,
    ) -> None:
        super().__init__(lags, per_decade, origin_every, 1)
        self.bins, self.r_max = int(bins), r_max

    def compute(
        self, source: Source, box: float | ArrayLike | None = None, times: ArrayLike | None = None
    ) -> VanHove:
        """G_s of ``source`` (as :meth:`SelfIntermediate.compute`); returns self."""
        src, plan = self._prepare(source, "van Hove functions", box, times)
        d = src.dim
        r_max = self.r_max
        if r_max is None:
            lag, i, j = plan[-1]
            dx = next(self._displacements(src, i[:1], j[:1]))
            r_max = max(_sigma(src), 4.0 * math.sqrt(float(np.einsum("nd,nd->n", dx, dx).mean())))
        edges = np.linspace(0.0, float(r_max), self.bins + 1)
        counts = np.zeros((len(plan), self.bins))
        total = np.zeros(len(plan))
        for row, (_, i, j) in enumerate(plan):
            for dx in self._displacements(src, i, j):
                r = np.sqrt(np.einsum("nd,nd->n", dx, dx))
                counts[row] += np.histogram(r, edges)[0]
                total[row] += len(r)
        width = np.diff(edges)
        self.P = counts / total[:, None] / width
        self.r = 0.5 * (edges[1:] + edges[:-1])
        shell = 2.0 * math.pi ** (d / 2.0) / math.gamma(d / 2.0) * self.r ** (d - 1)
        self.G = self.P / shell
        self.t, self.edges, self.dim = np.array([lag for lag, _, _ in plan]), edges, d
        self._computed = True
        return self

    def plot(self, ax: Axes | None = None) -> Axes:
        """``S_d r^(d-1) G_s(r, t)`` (the density of ``|dr|``) for each lag; returns the Axes."""
        ax = self._axes(ax)
        for row, t in enumerate(self.t):
            ax.plot(self.r, self.P[row], label=f"t = {t:.3g}")
        ax.set_xlabel("r")
        ax.set_ylabel("S_d r^(d-1) G_s(r, t)")
        ax.legend(fontsize="small")
        return ax


class Overlap(_Dynamic):
    """The overlap Q(t) with cut-off a and the four-point susceptibility chi_4(t) = N var Q.

    ``Q = (1/N) sum_i Theta(a - |r_i(t0 + t) - r_i(t0)|)`` for each origin
    ``t0``; ``Q(t)`` is its mean over origins, ``chi_4(t) = N (<Q^2> - <Q>^2)``
    (self part only, at fixed N and E: the fluctuations of the ensemble of
    origins of one run).  chi_4 peaks near tau_alpha in a glass former.

    Args:
        a: cut-off [length]; default ``0.3 sigma`` (sigma the mean diameter),
            the usual choice (about the cage size).

    Attributes (after :meth:`compute`): ``t``, ``Q``, ``Q_error``,
    ``chi4``, ``chi4_error``, ``origins``, ``a``, ``n``.
    """

    _results = ("t", "Q", "Q_error", "chi4", "chi4_error", "origins", "a", "n")

    def __init__(
        self,
        a: float | None = None,
        lags: ArrayLike | None = None,
        per_decade: float = 10,
        origin_every: float | None = None,
        blocks: int = 5,
    ) -> None:
        super().__init__(lags, per_decade, origin_every, blocks)
        if a is not None and not (math.isfinite(a) and a > 0):
            raise AnalysisInputError(f"a must be a finite length > 0, got {a!r}")
        self.a_asked = a

    def compute(
        self, source: Source, box: float | ArrayLike | None = None, times: ArrayLike | None = None
    ) -> Overlap:
        """Q and chi_4 of ``source`` (as :meth:`SelfIntermediate.compute`); returns self."""
        src, plan = self._prepare(source, "overlaps", box, times)
        a = float(self.a_asked) if self.a_asked is not None else 0.3 * _sigma(src)
        n = src.n
        Q: list[float]
        Qe: list[float]
        C: list[float]
        Ce: list[float]
        count: list[float]
        Q, Qe, C, Ce, count = [], [], [], [], []
        for _, i, j in plan:
            per = np.empty(len(i))
            for m, dx in enumerate(self._displacements(src, i, j)):
                per[m] = np.mean(np.einsum("nd,nd->n", dx, dx) < a * a)
            q, qe = _block_stats(per, self.blocks)
            c, ce = _block_stats(per, self.blocks, stat=lambda v, axis=0: n * np.var(v, axis=axis))
            for lst, v in zip((Q, Qe, C, Ce, count), (q, qe, c, ce, len(i))):
                lst.append(float(v))
        self.t = np.array([lag for lag, _, _ in plan])
        self.Q, self.Q_error, self.chi4, self.chi4_error = map(np.array, (Q, Qe, C, Ce))
        self.origins, self.a, self.n = np.array(count), a, n
        self._computed = True
        return self

    def peak(self) -> tuple[float, float]:
        """``(t*, chi_4(t*))``: the lag where chi_4 is largest (a parabola in log t through the top three).

        Raises:
            AnalysisInputError: chi_4 is largest at the first lag (the peak is
                earlier than the frames resolve: record frames at shorter
                lags, e.g. ``run --log-frames``) or at the last (still
                growing: record a longer run); neither is a peak.
        """
        self._need()
        b = int(np.argmax(self.chi4))
        if b == 0 or b == len(self.t) - 1:
            first = b == 0
            raise AnalysisInputError(
                f"chi_4 is largest at the {'first' if first else 'last'} lag t = {self.t[b]:g}: no peak "
                + (
                    "within the lags; it is earlier than the frames resolve: record frames at shorter "
                    "lags (run --log-frames, writers.LogOrigins)"
                    if first
                    else "within the lags; chi_4 still grows: record a longer run"
                )
            )
        if 0 < b < len(self.t) - 1:
            x = np.log(self.t[b - 1 : b + 2])
            c = np.polyfit(x, self.chi4[b - 1 : b + 2], 2)
            if c[0] < 0:
                xs = -c[1] / (2 * c[0])
                return float(math.exp(xs)), float(np.polyval(c, xs))
        return float(self.t[b]), float(self.chi4[b])

    def plot(self, ax: Axes | None = None) -> Axes:
        """chi_4 against log t, with error bars; returns the Axes."""
        ax = self._axes(ax)
        ax.errorbar(self.t, self.chi4, yerr=self.chi4_error, capsize=2)
        ax.set_xscale("log")
        ax.set_xlabel("t")
        ax.set_ylabel(f"chi_4(t), a = {self.a:.3g}")
        return ax


class CollectiveIntermediate(_Dynamic):
    """Collective intermediate scattering function ``F(k, t) = <rho_k(t0 + t) rho_-k(t0)> / N``.

    ``rho_k = sum_i exp(i k . r_i)`` over the box's wave vectors in the
    shell ``| |q| - k | <= dk / 2`` (``dk`` default ``2 pi / L``; at most
    ``max_vectors``, a fixed choice).  ``F(k, 0) = S(k)``.

    Attributes (after :meth:`compute`): ``t`` (lag 0 first), ``k``, ``F``
    ``(T, K)``, ``error``, ``normalized`` (``F / F(k, 0)``), ``vectors``
    (the wave vectors used, per k).
    """

    _results = ("t", "k", "F", "error", "normalized", "vectors")

    def __init__(
        self,
        k: ArrayLike,
        dk: float | None = None,
        max_vectors: int = 100,
        lags: ArrayLike | None = None,
        per_decade: float = 10,
        origin_every: float | None = None,
        blocks: int = 5,
    ) -> None:
        super().__init__(lags, per_decade, origin_every, blocks)
        self.k_asked, self.dk, self.max_vectors = _as_k(k), dk, max_vectors

    def compute(
        self, source: Source, box: float | ArrayLike | None = None, times: ArrayLike | None = None
    ) -> CollectiveIntermediate:
        """F(k, t) of ``source`` (as :meth:`SelfIntermediate.compute`); returns self."""
        src, plan = self._prepare(source, "intermediate scattering functions", box, times)
        ks = _check_k(self.k_asked, src.lengths)
        vecs = [lattice_vectors(k, src.lengths, self.dk, self.max_vectors) for k in ks]
        allv = np.concatenate(vecs)
        split = np.cumsum([len(v) for v in vecs])[:-1]
        rho = np.empty((len(src.times), len(allv)), complex)
        for f in range(len(src.times)):
            rho[f] = _phases(src.unwrapped(f), allv, src.lengths).sum(axis=0)
        n = src.n

        def corr(i: np.ndarray, j: np.ndarray) -> np.ndarray:
            c = (rho[j] * np.conj(rho[i])).real / n  # (O, V)
            return np.stack([p.mean(axis=1) for p in np.split(c, split, axis=1)], axis=1)

        all_f = np.arange(len(src.times))
        rows = [(0.0, all_f, all_f)] + plan
        F, E = [], []
        for _, i, j in rows:
            f, e = _block_stats(corr(i, j), self.blocks)
            F.append(f)
            E.append(e)
        self.t = np.array([lag for lag, _, _ in rows])
        self.k, self.F, self.error, self.vectors = ks, np.array(F), np.array(E), vecs
        self.normalized = self.F / self.F[0]
        self._computed = True
        return self

    def plot(self, ax: Axes | None = None) -> Axes:
        """F(k, t) / S(k) against log t (lag 0 left out); returns the Axes."""
        ax = self._axes(ax)
        for c, k in enumerate(self.k):
            ax.errorbar(
                self.t[1:],
                self.normalized[1:, c],
                yerr=self.error[1:, c] / self.F[0, c],
                label=f"k = {k:.3g}",
            )
        ax.set_xscale("log")
        ax.set_xlabel("t")
        ax.set_ylabel("F(k, t) / S(k)")
        ax.legend()
        return ax


__all__ = [
    "INV_E",
    "CollectiveIntermediate",
    "NonGaussian",
    "NotComputedError",
    "Overlap",
    "SelfIntermediate",
    "VanHove",
    "box_sides",
    "lattice_vectors",
    "log_lags",
]

"""Transport: self-diffusion from the mean squared displacement and the velocity autocorrelation.

* :class:`MSD`: the mean squared displacement over all time origins (the
  FFT algorithm of freud's :class:`freud.msd.MSD` in its ``"window"`` mode,
  done here with numpy in double precision: no optional package needed) of
  the unwrapped positions (exact image counts, :meth:`hardspheres.Frames.unwrapped`),
  and D from its slope, ``MSD = 2 d D t`` at long times (``6 D t`` in 3-D,
  ``4 D t`` for disks).
* :class:`VACF`: the velocity autocorrelation over all time origins and
  ``D = (1/d) int C(t) dt`` (Green-Kubo), cut where :meth:`VACF.diffusion`
  says (at least 150 mean free times in a dense fluid: its long-time tail
  holds ~2% of D).  The same FFT correlation as the MSD's, a chunk of
  spheres at a time (bounded memory); it needs only the velocities (no
  image counts).
* :func:`yeh_hummer`: the finite-size correction of D in a periodic box.
* :func:`enskog`: the Enskog transport coefficients, the usual yardstick.

Error bars: the trajectory is cut into ``blocks`` equal segments, D is
measured on each, and the error is their standard deviation over
``sqrt(blocks)``; D itself is measured on the whole trajectory.

Both need a periodic box (:class:`~hardspheres.containers.PeriodicBoxRequired`
otherwise): in a container the displacement is bounded and D would be zero.

Disks (a 2-D box): ``MSD = 4 D t`` and ``D = 1/2 int C(t) dt`` (``2 d D t``
and ``1/d``, ``d = 2``), but in two dimensions D does not exist as a
number.  The VACF's hydrodynamic long-time tail decays as ``C(t) ~ 1/t``
(Alder and Wainwright, Phys. Rev. A 1, 18 (1970); Ernst, Hauge and van
Leeuwen, Phys. Rev. Lett. 25, 1254 (1970)), not ``t^(-3/2)`` as in 3-D, so
its integral, and the MSD's slope, grow as ``ln t`` without limit in an
infinite system; a periodic box of side ``L`` cuts the tail off once sound
or shear has crossed it, so D levels off at a value that grows as ``ln L``.
What this module reports for disks is therefore D *at a time scale, in
that box*: :meth:`MSD.diffusion` the slope over its fit window (by default
0.2-0.5 of a segment), :meth:`VACF.diffusion` the integral to ``t_max``,
both with the same blocks' error bars, which measure the noise, not the
drift with ``t``.  Report the window (or ``t_max``) and ``L`` with the
number, look at :meth:`VACF.running_diffusion` (a straight line against
``ln t`` where the tail dominates), and do not extrapolate with
:func:`yeh_hummer`, which is the 3-D cube's correction.

Example:
    >>> import hardspheres as hs
    >>> from hardspheres.io.trajectory import frames_from_simulation
    >>> sim = hs.Simulation(hs.random_spheres(108, 0.3, box=7.0, seed=1), hs.PeriodicBox(7.0))
    >>> fr = frames_from_simulation(sim, until=4.0, every=0.05)
    >>> msd = MSD().compute(fr)
    >>> msd.t.shape == msd.msd.shape == (81,)
    True
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, cast

import numpy as np

from ..containers import require_periodic
from ..eos import carnahan_starling_contact
from ..errors import AnalysisInputError, NotComputedError
from .compute import Compute

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from ..frames import Frames
    from ..simulation import Simulation

#: Yeh-Hummer constant for the cubic box, ``xi`` (the Madelung-like constant of
#: the periodic Oseen tensor): I.-C. Yeh and G. Hummer, J. Phys. Chem. B 108,
#: 15873 (2004), Eq. 12.
XI_CUBIC = 2.837297


def yeh_hummer(D: float, box: float, eta: float, kT: float = 1.0) -> float:
    """Self-diffusion extrapolated to an infinite system: ``D + xi kT / (6 pi eta L)``.

    I.-C. Yeh and G. Hummer, J. Phys. Chem. B 108, 15873 (2004): the
    hydrodynamic self-interaction with the periodic images slows a sphere
    in a cubic box of edge ``L`` by ``xi kT / (6 pi eta L)``, ``xi =
    2.837297``.

    Args:
        D: self-diffusion coefficient measured in the box [length^2/time].
        box: box edge ``L`` [length].
        eta: shear viscosity [mass/(length time)] (e.g. from :func:`enskog`
            times a correction, or measured).
        kT: temperature [energy].

    Example:
        >>> round(yeh_hummer(0.1, 10.0, 1.0), 6)
        0.115052
    """
    return D + XI_CUBIC * kT / (6.0 * math.pi * eta * box)


def enskog(packing: float, sigma: float = 1.0, kT: float = 1.0, mass: float = 1.0) -> dict[str, float]:
    """Enskog's transport coefficients of equal hard spheres.

    With ``g`` the contact value by Carnahan-Starling, ``(1 - phi/2) /
    (1 - phi)^3``, and ``b rho = 4 phi`` (from S. Chapman and T. G.
    Cowling, *The Mathematical Theory of Non-uniform Gases*, 3rd ed.,
    Cambridge 1970, ch. 16):

    all in the first Sonine approximation (the dilute values ``D_0``,
    ``eta_0``, ``lambda_0`` without their higher-order corrections of 1-3%):

    * self-diffusion ``D_E = 3 / (8 rho sigma^2 g) sqrt(kT / (pi m))``;
    * shear viscosity ``eta_E = eta_0 (1/g + 4/5 b rho + 4/25 (1 + 12/pi)
      (b rho)^2 g)`` (``(1/g)(1 + 2/5 b rho g)^2`` plus 3/5 of the bulk
      viscosity ``16/(5 pi) (b rho)^2 g eta_0``; DynamO's ``Enskog.h``
      writes the same), ``eta_0 = 5 / (16 sigma^2) sqrt(m kT / pi)``;
    * thermal conductivity ``lambda_E = lambda_0 (1/g + 6/5 b rho + 9/25
      (1 + 32/(9 pi)) (b rho)^2 g)``, ``lambda_0 = 75 k / (64 sigma^2)
      sqrt(kT / (pi m))``.

    Returns:
        dict ``D``, ``eta``, ``lambda`` (k = 1 units), ``g`` (contact value).

    Example:
        >>> e = enskog(0.3)
        >>> round(e["g"], 4), round(e["D"], 4)
        (2.4781, 0.149)
    """
    rho = 6.0 * packing / (math.pi * sigma**3)
    g = float(carnahan_starling_contact(packing))
    brho = 4.0 * packing
    D0 = 3.0 / (8.0 * rho * sigma**2) * math.sqrt(kT / (math.pi * mass))
    eta0 = 5.0 / (16.0 * sigma**2) * math.sqrt(mass * kT / math.pi)
    lam0 = 75.0 / (64.0 * sigma**2) * math.sqrt(kT / (math.pi * mass))
    return {
        "D": D0 / g,
        "g": g,
        "eta": eta0 * (1.0 / g + 0.8 * brho + 0.16 * (1.0 + 12.0 / math.pi) * brho**2 * g),
        "lambda": lam0 * (1.0 / g + 1.2 * brho + 0.36 * (1.0 + 32.0 / (9.0 * math.pi)) * brho**2 * g),
    }


def _trajectory(
    source: Frames, what: str, positions: bool = True
) -> tuple[np.ndarray, np.ndarray | None, np.ndarray, float | np.ndarray | None]:
    """``(t (F,), unwrapped positions (F, N, 3), velocities (F, N, 3), L)`` of Frames.

    With ``positions=False`` the positions are not unwrapped (``None``): the
    velocity autocorrelation needs only the velocities.
    """
    from ..frames import Frames

    if not isinstance(source, Frames):
        raise TypeError(f"{what} need a Frames (a trajectory: read_trajectory or frames_from_simulation)")
    require_periodic(source.container if source.box is not None else None, what)
    t = np.asarray(source.times, float)
    if len(t) < 3:
        raise AnalysisInputError(f"{what}: {len(t)} frames; record at least three")
    dt = np.diff(t)
    if np.ptp(dt) > 1e-6 * dt.mean():
        raise AnalysisInputError(
            f"{what}: frames must be equally spaced in time; record them with a fixed every="
        )
    x = source.unwrapped() if positions else None
    return t - t[0], x, np.asarray(source.velocities, float), source.box


def _autocorrelation(x: np.ndarray) -> np.ndarray:
    """``(F,)`` mean over spheres and axes of ``<x(t0) . x(t0 + t)>`` over all origins t0.

    FFT with zero padding (Wiener-Khinchin), divided by the number of
    origins at each lag: the same algorithm freud's MSD uses.
    """
    f, n = x.shape[0], x.shape[1]
    size = 1 << math.ceil(math.log2(2 * f))
    acf = np.zeros(f)
    # spheres in chunks: the padded spectrum of all of them at once would take
    # 16 * size * N * 3 bytes (1.6 GB for 20000 frames of 500 spheres)
    step = max(1, (1 << 23) // (size * x.shape[2]))
    for k in range(0, n, step):
        spec = np.fft.rfft(x[:, k : k + step], n=size, axis=0)
        acf += np.fft.irfft(spec * np.conj(spec), n=size, axis=0)[:f].sum(axis=(1, 2))
    return acf / n / (f - np.arange(f))


def _segments(f: int, blocks: int) -> list[slice]:
    size = f // blocks
    return [slice(k * size, (k + 1) * size) for k in range(blocks)]


class _Blocked(Compute):
    """A compute object whose error bar is the spread over ``blocks`` segments of the run."""

    def __init__(self, blocks: int = 5) -> None:
        self.blocks = blocks

    def _blocks(self) -> tuple[list[slice], np.ndarray]:
        """``(segments, tseg)``: the ``blocks`` slices of the lags ``t``, and one segment's lags."""
        segs = _segments(len(self.t), self.blocks)
        return segs, self.t[: segs[0].stop - segs[0].start]


def _line_slope(t: np.ndarray, y: np.ndarray) -> float:
    return np.polyfit(t, y, 1)[0]


def plateau_window(
    t: np.ndarray,
    curve: np.ndarray,
    tseg: np.ndarray,
    seg_curves: list[np.ndarray],
    starts: np.ndarray,
    ratio: float,
    min_points: int = 8,
) -> tuple[float, float, tuple[float, float], bool]:
    """The fit window of a curve that grows linearly after a transient: the plateau test.

    Candidate windows ``[t0, ratio t0]`` for ``t0`` in ``starts`` (rising),
    each fitted by a straight line on the whole run (``curve`` at lags
    ``t``) and on each segment (``seg_curves`` at lags ``tseg``).  The
    window chosen is the first whose slope the next window's does not
    exceed by more than one standard error of their difference (taken
    segment by segment, so that the noise the windows share cancels).
    Slopes still rising (a transient not yet over, as the stress
    correlations at packing 0.45 past 25 mean free times) are not taken;
    a fall is no reason to go on (the slopes of long lags in short segments
    fall, and are noisy).  One standard error, not two: a bias is worse
    than noise here (at packing 0.45, N = 500, t = 3000, the viscosity's
    windows from 10 and 20 mean free times differ by 1.5 of it, and two
    would take the lower, 1.8% low).

    Returns:
        ``(slope, error, (t_lo, t_hi), plateau)``: the slope on the whole
        run, its error from the segments' spread, the window, and whether a
        plateau was found (if not, the last window that fits, and the slope
        may still be biased).

    Raises:
        ValueError: no candidate window holds ``min_points`` lags.
    """
    fits = []
    for t0 in starts:
        t1 = ratio * t0
        sel, sel_s = (t >= t0) & (t <= t1), (tseg >= t0) & (tseg <= t1)
        if sel_s.sum() < min_points or t1 > 0.5 * tseg[-1]:
            continue
        per = np.array([_line_slope(tseg[sel_s], c[sel_s]) for c in seg_curves])
        fits.append((_line_slope(t[sel], curve[sel]), per, (float(t0), float(t1))))
    if not fits:
        raise AnalysisInputError(
            f"no fit window holds {min_points} lags within half a segment: run longer or use fewer blocks"
        )
    k_best, plateau = len(fits) - 1, False
    for k in range(len(fits) - 1):
        (v0, p0, _), (v1, p1, _) = fits[k], fits[k + 1]
        d = p1 - p0
        sem_d = np.std(d, ddof=1) / math.sqrt(len(d)) if len(d) > 1 else math.inf
        if v1 - v0 <= sem_d:
            k_best, plateau = k, True
            break
    v, per, window = fits[k_best]
    err = float(np.std(per, ddof=1) / math.sqrt(len(per))) if len(per) > 1 else math.nan
    return float(v), err, window, plateau


class MSD(_Blocked):
    """Mean squared displacement over all time origins (FFT) and D from its slope.

    Args:
        blocks: segments the trajectory is cut into for the error bar of D.

    Attributes (after :meth:`compute`): ``t`` lag times, ``msd``.
    """

    _results = ("t", "msd")

    def compute(self, frames: Frames) -> MSD:
        """MSD of a periodic-box trajectory (equally spaced frames); returns self.

        Raises:
            PeriodicBoxRequired: the trajectory is not in a periodic box.
        """
        t, x, _, _ = _trajectory(frames, "mean squared displacements")
        x = cast(np.ndarray, x)  # positions=True: unwrapped
        self.t, self.msd = t, self._msd(x)
        self._x = x
        self._computed = True
        return self

    @staticmethod
    def _msd(x: np.ndarray) -> np.ndarray:
        """``(F,)`` mean over spheres of ``|r(t0 + t) - r(t0)|^2`` over all origins (FFT, float64)."""
        x = np.asarray(x, float)
        x = x - x[:1]  # the MSD is blind to a shift per sphere: small numbers, less rounding
        f, n = x.shape[:2]
        sq = np.append(np.sum(x * x, axis=(1, 2)) / n, 0.0)  # mean over spheres of |r(t0)|^2
        s2 = _autocorrelation(x)  # mean over spheres of r(t0) . r(t0 + t)
        q = 2.0 * sq.sum()
        s1 = np.zeros(f)
        for m in range(f):  # mean of |r(t0)|^2 + |r(t0 + t)|^2 over the f - m origins
            q -= sq[m - 1] + sq[f - m]
            s1[m] = q / (f - m)
        return s1 - 2.0 * s2

    def _window(self, t: np.ndarray, t_min: float | None, t_max: float | None) -> np.ndarray:
        t_max = 0.5 * t[-1] if t_max is None else t_max
        t_min = 0.2 * t[-1] if t_min is None else t_min
        sel = (t >= t_min) & (t <= t_max)
        if sel.sum() < 2:
            raise AnalysisInputError(
                f"fewer than two lags in [{t_min:g}, {t_max:g}]: record more frames or widen the fit window"
            )
        return sel

    def diffusion(self, t_min: float | None = None, t_max: float | None = None) -> tuple[float, float]:
        """D from a straight line fitted to the MSD for lags in ``[t_min, t_max]``.

        The default window is 0.2 to 0.5 of one segment's length (of
        ``1/blocks`` of the run): past the ballistic start, before the
        noisy long lags.  Both ends should be many mean free times.

        Disks: ``MSD = 4 D t``, and the slope grows as ``ln t`` (the
        module's "Disks"): D at the window's time scale, in this box.

        Returns:
            ``(D, error)`` [length^2/time]: D from the whole trajectory, the
            error from the segments' spread.
        """
        self._need()
        segs, tseg = self._blocks()
        t_lo = 0.2 * tseg[-1] if t_min is None else t_min
        t_hi = 0.5 * tseg[-1] if t_max is None else t_max
        sel = self._window(self.t, t_lo, t_hi)
        two_d = 2.0 * self._x.shape[2]  # MSD = 2 d D t in d dimensions
        D = np.polyfit(self.t[sel], self.msd[sel], 1)[0] / two_d
        per = []
        sel_s = self._window(tseg, t_lo, t_hi)
        for s in segs:
            m = self._msd(self._x[s])
            per.append(np.polyfit(tseg[sel_s], m[sel_s], 1)[0] / two_d)
        err = float(np.std(per, ddof=1) / math.sqrt(len(per))) if len(per) > 1 else math.nan
        return float(D), err

    def plot(self, ax: Axes | None = None) -> Axes:
        """MSD against lag time, log-log, with the ballistic and diffusive lines; returns Axes."""
        ax = self._axes(ax)
        ax.loglog(self.t[1:], self.msd[1:], label="MSD")
        D, _ = self.diffusion()
        two_d = 2 * self._x.shape[2]
        ax.loglog(self.t[1:], two_d * D * self.t[1:], "--", label=f"{two_d} D t, D = {D:.4g}")
        ax.set_xlabel("t")
        ax.set_ylabel("mean squared displacement")
        ax.legend()
        return ax


class VACF(_Blocked):
    """Velocity autocorrelation ``C(t) = <v(0)·v(t)>`` over all origins, and D by Green-Kubo.

    Args:
        blocks: segments the trajectory is cut into for the error bar of D.

    Attributes (after :meth:`compute`): ``t`` lag times, ``c``.
    """

    _results = ("t", "c")

    def compute(self, frames: Frames) -> VACF:
        """VACF of a periodic-box trajectory (equally spaced frames); returns self."""
        t, _, v, _ = _trajectory(frames, "velocity autocorrelations", positions=False)
        self.t, self._v = t, v
        self.c = _autocorrelation(v)
        self._computed = True
        return self

    def diffusion(self, t_max: float | None = None) -> tuple[float, float]:
        """``D = (1/d) int_0^t_max C(t) dt`` (trapezoid), default ``t_max`` half a segment.

        C(t) falls steeply over the first mean free time, and the trapezoid
        overestimates the integral unless frames resolve that fall: at
        packing 0.45, frames 0.1 mean free time apart give D within 1.5% of
        the MSD's, 3 mean free times apart 40% above it.

        The cut ``t_max``: in a dense fluid C(t) is negative (the cage) up to
        about 40 mean free times, then positive (the hydrodynamic long-time
        tail, ~t^-3/2 until the box cuts it off) to about 160, and that tail
        holds about 2% of D.  At packing 0.45, N = 500 (2000 mean free times,
        ``python3 validation/transport.py --vacf``; docs/validation/transport.md) the
        integral to 50 mean free times is 2.1% (2.1 standard errors) below
        the MSD's D, to 100 0.3% below, to 150 and 250 within 0.3%; at
        N = 1372 (2500 mean free times) 1.1% below at 50, within 0.25% from
        100 to 300, the error growing with the cut.
        So integrate to at least 150 mean free times (half a segment by
        default: with 5 blocks, a run of 1500 mean free times or more);
        :meth:`running_diffusion` shows where the integral levels off.
        The integral is D in this box, like the MSD's: correct both for the
        box with :func:`yeh_hummer`.

        Disks: ``D = 1/2 int C dt``, and the tail ``C ~ 1/t`` makes the
        integral grow as ``ln t_max`` (the module's "Disks"): the value is
        D to ``t_max`` in this box, with no plateau to find and no
        Yeh-Hummer correction.

        Returns:
            ``(D, error)`` [length^2/time].

        Raises:
            ValueError: C falls by more than 20% between the first two frames
                (record frames closer together).
        """
        self._need()
        if self.c[1] < 0.8 * self.c[0]:
            raise AnalysisInputError(
                f"the VACF falls to {self.c[1] / self.c[0]:.2f} of C(0) in one frame: the "
                "integral would be biased high; record frames at most a tenth of a mean free "
                "time apart (or use MSD().diffusion())"
            )
        segs, tseg = self._blocks()
        t_max = 0.5 * tseg[-1] if t_max is None else t_max
        if t_max > tseg[-1]:
            raise AnalysisInputError(
                f"t_max {t_max:g} is longer than a segment ({tseg[-1]:g}): use fewer blocks or a longer run"
            )
        k = int(np.searchsorted(self.t, t_max, side="right"))
        d = self._v.shape[2]  # C = <v(0) . v(t)> = d D'(t) in d dimensions
        D = np.trapezoid(self.c[:k], self.t[:k]) / d
        per = [np.trapezoid(_autocorrelation(self._v[s])[:k], tseg[:k]) / d for s in segs]
        err = float(np.std(per, ddof=1) / math.sqrt(len(per))) if len(per) > 1 else math.nan
        return float(D), err

    def running_diffusion(self) -> tuple[np.ndarray, np.ndarray]:
        """``(t, D(t))``: ``(1/d) int_0^t C dt'`` for every cut ``t`` (trapezoid, as :meth:`diffusion`).

        Where it levels off is where the cut may go (see :meth:`diffusion`);
        for disks it never levels off but rises as ``ln t`` once the tail
        dominates, until the box's size cuts the tail.
        """
        self._need()
        steps = 0.5 * (self.c[1:] + self.c[:-1]) * np.diff(self.t)
        return self.t, np.concatenate([[0.0], np.cumsum(steps)]) / self._v.shape[2]

    def plot(self, ax: Axes | None = None) -> Axes:
        """C(t) / C(0) against t; returns Axes."""
        ax = self._axes(ax)
        ax.plot(self.t, self.c / self.c[0])
        ax.axhline(0.0, color="grey", lw=0.5)
        ax.set_xlabel("t")
        ax.set_ylabel("C(t) / C(0)")
        return ax


def _msd_fft(x: np.ndarray) -> np.ndarray:
    """``(F,)`` mean over columns of ``<(x(t0 + t) - x(t0))^2>`` over all origins, float64.

    The FFT algorithm (V. Calandrini et al., Collection SFN 12, 201 (2011)),
    as in freud's window MSD, for any number of columns.
    """
    x = np.asarray(x, float).reshape(x.shape[0], 1, -1)
    f = x.shape[0]
    d = np.sum(x * x, axis=(1, 2))
    d = np.append(d, 0.0)
    s2 = _autocorrelation(x)  # summed over the columns
    q = 2.0 * d.sum()
    s1 = np.zeros(f)
    for m in range(f):
        q -= d[m - 1] + d[f - m]
        s1[m] = q / (f - m)
    return (s1 - 2.0 * s2) / x.shape[2]


class _EinsteinHelfand(_Blocked):
    """Transport coefficient from the growth of a Helfand moment sampled by the Observables."""

    _results = ("t", "msd")
    _kind = ""

    def compute(self, sim: Simulation) -> _EinsteinHelfand:
        """Use the Helfand moments ``sim.observables`` sampled since its reset; returns self.

        Raises:
            PeriodicBoxRequired: not a periodic box.
            ValueError: fewer than 32 samples (run longer, or reset the
                observables with a smaller ``every``).
        """
        obs = sim.observables
        t, g = obs.helfand_moments(self._kind)
        if len(t) < 32:
            raise AnalysisInputError(
                f"{len(t)} samples of the Helfand moments (32 at least, a few "
                "hundred for an error bar): run longer, or start with "
                "observables.reset(every=T), T about a mean free time"
            )
        self._check(sim)
        self._g, self.t = g, t - t[0]
        self.msd = _msd_fft(g)
        self._scale = self._prefactor(sim)
        self.mean_free_time = obs.mean_free_time()
        self._merges = obs.merges
        self.window: tuple[float, float] | None = None
        self.plateau: bool | None = None
        self._computed = True
        return self

    def _check(self, sim: Simulation) -> None:
        pass

    def value(self, t_min: float | None = None, t_max: float | None = None) -> tuple[float, float]:
        """The coefficient from a line fitted to the moment's mean square growth.

        Lags in ``[t_min, t_max]``; by default chosen from the data by
        :func:`plateau_window`: windows ``[t0, 5 t0]`` with ``t0`` = 5, 10,
        20, ... mean free times (up to half a segment), the first whose
        slope the next one's does not exceed.  (The fixed 5 to 25 mean free
        times used before was biased at packing 0.45: 3.03 +- 0.03 against
        3.20 +- 0.07 from 20 to 100, N = 500, t = 3000; the stress
        correlations there decay past 25 mean free times.)  The window is kept in :attr:`window` and
        whether a plateau was found in :attr:`plateau` (``False`` also when
        segments shorter than 50 mean free times leave only the fixed window
        of 5 to 25 mean free times, unchecked).

        Returns ``(value, error)``; the error from the spread over
        ``blocks`` segments of the run.

        Raises:
            ValueError: the segments are too short for any window, or the
                samples too coarse for it (said which, and what helps).
        """
        self._need()
        segs, tseg = self._blocks()
        if t_min is None and t_max is None:
            return self._auto_value(segs, tseg)
        t_lo = 5.0 * self.mean_free_time if t_min is None else t_min
        t_hi = 25.0 * self.mean_free_time if t_max is None else t_max
        sel = (self.t >= t_lo) & (self.t <= t_hi)
        sel_s = (tseg >= t_lo) & (tseg <= t_hi)
        if sel_s.sum() < 2:
            raise AnalysisInputError(
                f"fewer than two lags in [{t_lo:g}, {t_hi:g}] per segment: run longer or use fewer blocks"
            )
        val = np.polyfit(self.t[sel], self.msd[sel], 1)[0] * self._scale
        per = [np.polyfit(tseg[sel_s], _msd_fft(self._g[s])[sel_s], 1)[0] * self._scale for s in segs]
        err = float(np.std(per, ddof=1) / math.sqrt(len(per)))
        self.window, self.plateau = (float(t_lo), float(t_hi)), None
        return float(val), err

    def _auto_value(self, segs: list[slice], tseg: np.ndarray) -> tuple[float, float]:
        mft = self.mean_free_time
        if not math.isfinite(mft) or mft <= 0:
            raise AnalysisInputError(
                "no collisions since the observables' reset: no mean free time to fit over; run longer first"
            )
        starts = 5.0 * mft * 2.0 ** np.arange(40)
        starts = starts[starts <= tseg[-1]]
        step = self.t[1] - self.t[0]
        try:
            v, err, window, plateau = plateau_window(
                self.t, self.msd, tseg, [_msd_fft(self._g[s]) for s in segs], starts, 5.0
            )
        except ValueError:
            if step > 5.0 * mft / 8.0:
                merged = getattr(self, "_merges", 0)
                why = (
                    f" (merged {merged} times: more than max_samples samples)"
                    if merged
                    else " (the interval given to observables.reset)"
                )
                raise AnalysisInputError(
                    f"the Helfand moments were sampled every {step:g} = {step / mft:.2g} mean free times"
                    f"{why}; the fit needs lags of about a mean free time: "
                    "observables.reset(every=T, max_samples=M) with T about a mean free time and "
                    "M above the run's length over T"
                ) from None
            # segments too short for the plateau test (under 50 mean free
            # times): the fixed window, 5 to 25 mean free times, unchecked
            v, err = self.value(5.0 * mft, 25.0 * mft)
            self.plateau = False
            return v, err
        self.window, self.plateau = window, plateau
        return v * self._scale, err * self._scale

    def plot(self, ax: Axes | None = None) -> Axes:
        """The running coefficient (mean square growth over ``2 t``, scaled) against t; returns Axes."""
        ax = self._axes(ax)
        t = self.t[1:]
        ax.plot(t, self.msd[1:] * self._scale / t)
        ax.set_xlabel("t")
        ax.set_ylabel(f"{self._kind} Helfand moment: running coefficient")
        return ax


class ShearViscosity(_EinsteinHelfand):
    """Shear viscosity by Einstein-Helfand: ``eta = lim <dG_ab(t)^2> / (2 V kT t)``.

    ``G_ab(t) - G_ab(0) = int_0^t V P_ab dt'`` for ab = xy, xz, yz, from the
    event core's exact running tallies (the kinetic tensor integrated between
    collisions and the collisional transfer ``r_ij dp_i``, minimum image:
    the periodic Helfand moment of S. Viscardy and P. Gaspard, Phys. Rev. E
    68, 041204 (2003)), sampled on the observables' time grid.  Run with
    ``sim.observables.reset()`` at the start of the production run.

    Example:
        >>> import hardspheres as hs
        >>> sim = hs.Simulation(hs.random_spheres(108, 0.3, box=7.0, seed=1), hs.PeriodicBox(7.0))
        >>> _ = sim.run(until=5.0).observables.reset(every=0.1)  # ~a mean free time
        >>> _ = sim.run(until=45.0)
        >>> eta, err = ShearViscosity().compute(sim).value()
        >>> eta > 0
        True
    """

    _kind = "momentum"

    @staticmethod
    def _prefactor(sim: Simulation) -> float:
        return 1.0 / (2.0 * sim.container.volume * sim.observables.temperature())


class ThermalConductivity(_EinsteinHelfand):
    """Thermal conductivity by Einstein-Helfand: ``lambda = lim <dH_a^2> / (2 V kT^2 t)`` (k = 1).

    ``H_a = sum_i x_ia E_i`` in its periodic form: the energy current
    ``sum v E`` integrated between collisions plus the collisional transfer
    ``r_ij dE_i``.  Equal masses only: with total momentum zero the mean
    enthalpy term ``h sum v_i`` then vanishes.
    """

    _kind = "energy"

    def _check(self, sim: Simulation) -> None:
        m = sim.engine.masses
        if np.ptp(m) > 1e-12 * m.max():
            raise AnalysisInputError(
                "thermal conductivity by Einstein-Helfand is implemented for equal masses only; "
                "give every sphere one mass"
            )

    @staticmethod
    def _prefactor(sim: Simulation) -> float:
        kT = sim.observables.temperature()
        return 1.0 / (2.0 * sim.container.volume * kT * kT)


__all__ = [
    "MSD",
    "VACF",
    "XI_CUBIC",
    "NotComputedError",
    "ShearViscosity",
    "ThermalConductivity",
    "enskog",
    "yeh_hummer",
]

"""The pressure from event chains, per axis, with blocking error bars.

In straight event-chain Monte Carlo along ``+e_a`` the pressure is
measured by the chains themselves (Michel, Kapfer and Krauth, J. Chem.
Phys. 140, 054116 (2014); Li et al., J. Chem. Phys. 157, 234111 (2022),
Eq. 20-21)::

    beta P_aa = (N / V) (1 + sum of the lifting separations along a
                             / total chain displacement along a)

where a lifting separation is ``x_j - x_i`` at the contact that passes the
motion from ``i`` to ``j``.  The scalar pressure is the same ratio over all
axes (their displacements are equal within one chain), ``Z = beta P V /
N``.

Error bars: the running totals are sampled every ``every`` rounds (a round
is one chain per axis), and blocking (:mod:`hardspheres.blocking`) of the
per-block values gives the standard error; blocks merge by two when
:attr:`ChainObservables.MAX_SAMPLES` is reached, and while they hold fewer
than :attr:`ChainObservables.MIN_EVENTS` lifts, as
:class:`hardspheres.Observables`' do.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any, Protocol

import numpy as np

from ..blocking import Blocking, blocking
from ..errors import ArgumentError, NoMeasurementError

if TYPE_CHECKING:
    from ..containers import PeriodicBox


class ChainView(Protocol):
    """What the observables read of an :class:`~hardspheres.mc.chain.EventChain` (no import circle)."""

    @property
    def container(self) -> PeriodicBox: ...

    @property
    def n(self) -> int: ...

    @property
    def kT(self) -> float: ...  # noqa: N802

    @property
    def time(self) -> float: ...

    def totals(self) -> np.ndarray: ...


_EVENTS, _CHAINS = 0, 1
_AXES = "xyz"


class ChainObservables:
    """Averages over the chains since the last :meth:`reset`, from the core's running totals.

    Read it as :class:`hardspheres.Observables`: :meth:`estimate`,
    :meth:`error`, :meth:`blocks`, :meth:`summary`, :meth:`pressure`,
    :meth:`Z`, :meth:`pressure_tensor` (its diagonal).  The names are
    ``"pressure"``, ``"Z"`` and ``"pressure_xx"``, ``"pressure_yy"``
    (``"pressure_zz"`` in 3-D) [energy/length^d, at the chain's ``kT``].

    Example:
        >>> import hardspheres as hs
        >>> from hardspheres.eos import kolafa_rottner
        >>> box = hs.PeriodicBox.for_packing(400, 0.3, (1.0, 1.0))
        >>> chain = hs.EventChain(hs.random_spheres(400, 0.3, box, seed=1), box, seed=1)
        >>> obs = chain.run(chains=200).observables.reset()
        >>> z = chain.run(chains=4000).observables.estimate("Z")
        >>> abs(z.mean - float(kolafa_rottner(0.3))) < 3 * z.sem
        True
    """

    #: Samples kept before neighbouring blocks merge.
    MAX_SAMPLES = 65536
    #: Blocks merge while they hold fewer lifts than this.
    MIN_EVENTS = 500

    def __init__(self, chain: ChainView) -> None:
        self._chain = chain
        self.reset()

    @property
    def width(self) -> int:
        """Numbers per sample (events, chains, lift sums (d), displacements (d))."""
        return 2 + 2 * self._chain.container.dimensions

    def reset(self, every: int | None = None) -> ChainObservables:
        """Start averaging afresh from now; returns self.

        Args:
            every: rounds (one chain per axis) per block at the start
                (default 1, doubled while blocks hold fewer than
                :attr:`MIN_EVENTS` lifts).
        """
        if every is not None and not (isinstance(every, int) and every >= 1):
            raise ArgumentError(f"every must be a whole number of rounds >= 1, got {every!r}")
        self.merges = 0
        self._auto = every is None
        self.every = 1 if every is None else every
        self._mark = self._chain.totals()
        self.origin = int(self._mark[_CHAINS])
        self._samples: list[np.ndarray] | np.ndarray = [self._mark.copy()]
        return self

    def checkpoint(self) -> dict[str, np.ndarray]:
        """The arrays :meth:`restore` takes back (a checkpoint keeps the blocks)."""
        return {
            "obs_samples": self._sample_array(),
            "obs_schedule": np.array([self.every, self.origin, int(self._auto), self.merges], np.int64),
        }

    def restore(self, arrays: dict[str, np.ndarray]) -> bool:
        """Take back what :meth:`checkpoint` gave; ``False`` (and a fresh start) if it does not fit."""
        samples = arrays.get("obs_samples")
        schedule = arrays.get("obs_schedule")
        if (
            samples is None
            or schedule is None
            or samples.dtype != np.float64
            or samples.ndim != 2
            or samples.shape[1] != self.width
            or samples.shape[0] < 1
            or not np.all(np.isfinite(samples))
            or schedule.shape != (4,)
            or schedule.dtype != np.int64
            or schedule[0] < 1
        ):
            return False
        self._samples = samples.copy()
        self._mark = samples[0].copy()
        self.every, self.origin, auto, self.merges = (int(x) for x in schedule)
        self._auto = bool(auto)
        return True

    def take(self, rows: np.ndarray) -> None:
        """Record the core's rows of running totals (the chain calls this after each run of the core)."""
        d = self._chain.container.dimensions
        samples = self._samples_list()
        for row in rows:
            if (int(row[_CHAINS]) - self.origin) % (d * self.every):
                continue  # written before a merge doubled the blocks
            sparse = self._auto and len(samples) > 2 and row[_EVENTS] - samples[-1][_EVENTS] < self.MIN_EVENTS
            samples.append(row.copy())
            full = len(samples) > self.MAX_SAMPLES
            if full or sparse:
                self.merges += full
                # neighbouring blocks merge: every other sample from the mark (an odd last block waits)
                if len(samples) % 2 == 0:
                    samples.pop()
                samples[:] = samples[::2]
                self.every *= 2

    def _samples_list(self) -> list[np.ndarray]:
        if isinstance(self._samples, np.ndarray):
            self._samples = list(self._samples)
        return self._samples

    def _sample_array(self) -> np.ndarray:
        return np.array(self._samples, dtype=np.float64).reshape(-1, self.width)

    @property
    def n_blocks(self) -> int:
        """Number of complete blocks since :meth:`reset`."""
        return len(self._samples) - 1

    def _measured(self, delta: np.ndarray) -> dict[str, np.ndarray]:
        """The observables from differences of running totals (rows: blocks)."""
        chain = self._chain
        d = chain.container.dimensions
        rho = chain.n / chain.container.volume
        lifts = delta[..., 2 : 2 + d]
        disp = delta[..., 2 + d : 2 + 2 * d]
        with np.errstate(divide="ignore", invalid="ignore"):
            z = 1.0 + lifts.sum(axis=-1) / disp.sum(axis=-1)
            out = {"pressure": chain.kT * rho * z, "Z": z}
            for a in range(d):
                out[f"pressure_{_AXES[a] * 2}"] = chain.kT * rho * (1.0 + lifts[..., a] / disp[..., a])
        return out

    def _whole(self, name: str) -> float:
        delta = self._chain.totals() - self._mark
        if not delta[2 + self._chain.container.dimensions :].sum() > 0:
            raise NoMeasurementError("no chain has moved since reset(); run first")
        values = self._measured(delta)
        if name not in values:
            raise ArgumentError(f"no average {name!r} here: choose one of {', '.join(values)}")
        return float(values[name])

    def blocks(self, name: str) -> np.ndarray:
        """``(n_blocks,)`` the values of ``name`` over each block of equal length."""
        values = self._measured(np.diff(self._sample_array(), axis=0))
        if name not in values:
            raise ArgumentError(f"no average {name!r} here: choose one of {', '.join(values)}")
        return values[name]

    def estimate(self, name: str) -> Blocking:
        """Mean since :meth:`reset` and its blocking error (``sem`` nan with fewer than two blocks).

        The mean is the ratio of the totals (all the chains since reset);
        the error comes from the blocks (:func:`hardspheres.blocking.blocking`).

        Raises:
            NoMeasurementError: no chain has moved since reset.
        """
        mean = self._whole(name)
        x = self.blocks(name)
        x = x[np.isfinite(x)]  # a first block cut by reset() may miss an axis
        if x.size < 2:
            return Blocking(mean, math.nan, 0, 0, False, np.zeros(0), np.zeros(0))
        return blocking(x)._replace(mean=mean)

    def error(self, name: str) -> float:
        """Standard error of ``name``'s average (``nan`` with fewer than two blocks)."""
        return self.estimate(name).sem

    def pressure(self) -> float:
        """Pressure ``kT beta P`` [energy/length^d] since :meth:`reset`."""
        return self._whole("pressure")

    def Z(self) -> float:  # noqa: N802 (the physicists' name)
        """``Z = beta P V / N`` since :meth:`reset`."""
        return self._whole("Z")

    def compressibility(self) -> float:
        """The old name of :meth:`Z` (as :meth:`hardspheres.Observables.compressibility`)."""
        return self.Z()

    def pressure_tensor(self) -> np.ndarray:
        """``(d, d)``: the diagonal ``P_aa`` from the chains along each axis (straight chains: no more)."""
        d = self._chain.container.dimensions
        return np.diag([self._whole(f"pressure_{_AXES[a] * 2}") for a in range(d)])

    def summary(self) -> dict[str, Any]:
        """Dict of the averages since reset, each with ``_error`` and ``_converged`` as in Observables."""
        delta = self._chain.totals() - self._mark
        out: dict[str, Any] = {
            "time": self._chain.time,
            "events": int(delta[_EVENTS]),
            "chains": int(delta[_CHAINS]),
            "kT": self._chain.kT,
            "blocks": self.n_blocks,
            "sample_interval": self.every,
        }
        if delta[2 + self._chain.container.dimensions :].sum() > 0:
            d = self._chain.container.dimensions
            for name in ("pressure", "Z", *(f"pressure_{_AXES[a] * 2}" for a in range(d))):
                est = self.estimate(name)
                out[name] = est.mean
                out[f"{name}_error"] = est.sem
                out[f"{name}_converged"] = est.converged
            out["Z_route"] = "event chains"
        return out

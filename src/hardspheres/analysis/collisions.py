"""Statistics of the event record: free flights, collisions per sphere, recollisions, contact forces.

An event-driven run knows every collision and the impulse it carried
(:data:`~hardspheres.events.EVENT_DTYPE`: ``time, kind, i, j, impulse,
dp``).  These compute objects (freud style: ``compute()`` returns the
object, results before it raise :class:`NotComputedError`, ``plot(ax=None)``
returns Axes) read such a record:

* :class:`EventRecorder`: a writer (:class:`hardspheres.writers.Writer`)
  that keeps a run's events and the time span they cover (append it to
  ``sim.writers``); :class:`hardspheres.Frames` read from a trajectory
  recorded with events serve as well;
* :class:`FreeFlights`: the times between successive collisions of each
  sphere, their distribution and mean, the collisions per sphere, and the
  exact mean free time from ``Z`` (:func:`mean_free_time_from_z`);
* :class:`Recollisions`: how often the same pair collides again within a
  time ``t``, and how often with no other collision of either in between;
* :class:`ContactForces`: time-averaged contact forces ``f_ij = (sum of
  the impulses between i and j) / t``, as A. Donev, S. Torquato and F. H.
  Stillinger, Phys. Rev. E 71, 011105 (2005) measure them in near-jammed
  packings (their Sec. II: the force network of a hard-sphere packing is
  the time average of the collisional momentum transfer).

Example:
    >>> import hardspheres as hs
    >>> sim = hs.Simulation(hs.random_spheres(200, 0.3, box=9.0, seed=1), hs.PeriodicBox(9.0))
    >>> rec = EventRecorder()
    >>> sim.writers.append(rec)
    >>> _ = sim.run(until=5.0)
    >>> flights = FreeFlights().compute(rec)
    >>> bool(flights.mean > 0), int(flights.per_sphere.sum()) == 2 * rec.collisions
    (True, True)
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from ..errors import AnalysisInputError, NotComputedError
from ..events import EventKind, empty_events
from .compute import Compute

if TYPE_CHECKING:
    from matplotlib.axes import Axes

    from ..frames import Frames
    from ..simulation import Simulation
    from ..writers import SimulationView


def mean_free_time_from_z(
    z: float, sigma: float = 1.0, kT: float = 1.0, mass: float = 1.0, dim: int = 3
) -> float:
    """The mean free time of equal hard spheres from their reduced pressure ``Z = PV/(NkT)``.

    Both the collision rate per sphere and ``Z - 1`` are set by the contact
    value of g(r) (exactly, in equilibrium): in ``d`` dimensions the rate is
    ``Gamma = 2d (Z - 1) / sigma sqrt(kT / (pi m))``, so the mean free time
    is ``tau = sigma sqrt(pi m / kT) / (2 d (Z - 1))`` (3-D: Gamma = 4 sigma^2
    rho g(sigma) sqrt(pi kT / m) and Z - 1 = 2 pi rho sigma^3 g(sigma) / 3;
    J.-P. Hansen and I. R. McDonald, *Theory of Simple Liquids*, 3rd ed.,
    Academic Press 2006, Secs. 2.5 and 8.2).

    Example:
        >>> round(mean_free_time_from_z(2.0), 6)  # Z = 2: 1/6 sqrt(pi)
        0.295409
    """
    if not z > 1:
        raise AnalysisInputError(f"Z must be > 1 (a gas with collisions), got {z!r}")
    if dim == 3:  # the 3-D relation's home
        from ..eos import collision_rate_from_z

        return float(1.0 / collision_rate_from_z(z, sigma, kT, mass))
    return float(sigma * math.sqrt(math.pi * mass / kT) / (2.0 * dim * (z - 1.0)))


class EventRecorder:
    """A writer that keeps every event of the runs it is attached to.

    Append it to ``sim.writers``; after the run, :attr:`events` holds the
    events (:data:`~hardspheres.events.EVENT_DTYPE`), :attr:`t0` and
    :attr:`t1` the time span recorded [time].  It never writes frames
    (``next_time`` is ``inf``) and never changes the simulation.

    Memory: 56 bytes per event (10^7 events: 560 MB).
    """

    next_time = math.inf
    wants_events = True

    def __init__(self) -> None:
        self._blocks: list[np.ndarray] = []
        self.t0 = math.nan
        self.t1 = math.nan
        self.n = 0
        #: dimensions of the simulation recorded (the events' ``dp`` always have 3 components)
        self.dim = 3
        self._sim: SimulationView | None = None

    def attach(self, sim: SimulationView) -> None:
        if math.isnan(self.t0):
            self.t0 = float(sim.time)
        self._sim = sim
        self.n = int(sim.n)
        self.dim = int(sim.engine.dimensions)

    def write(self, sim: SimulationView, t: float) -> None:
        pass

    def observe(self, events: np.ndarray) -> None:
        if len(events):
            self._blocks.append(np.array(events, copy=True))

    def detach(self) -> None:
        pass

    @property
    def events(self) -> np.ndarray:
        """All events recorded, in order."""
        if len(self._blocks) > 1:
            self._blocks = [np.concatenate(self._blocks)]
        return self._blocks[0] if self._blocks else empty_events()

    @property
    def duration(self) -> float:
        """Time recorded, from the first attach to the simulation's clock now [time]."""
        if self._sim is not None:
            self.t1 = float(self._sim.time)
        return self.t1 - self.t0

    @property
    def collisions(self) -> int:
        """Collisions recorded."""
        return int(np.count_nonzero(self.events["kind"] == EventKind.COLLISION))


def _record(source: EventRecorder | Frames, what: str) -> tuple[np.ndarray, float, int]:
    """``(collision events, duration, n)`` of an :class:`EventRecorder` or Frames (with events)."""
    from ..frames import Frames

    if isinstance(source, EventRecorder):
        ev, duration, n = source.events, source.duration, source.n
    elif isinstance(source, Frames):
        ev, n = source.events, source.n
        duration = float(source.times[-1] - source.times[0]) if len(source.times) else 0.0
    else:
        raise TypeError(f"{what} need an EventRecorder or Frames with events, got {type(source).__name__}")
    ev = ev[ev["kind"] == EventKind.COLLISION]
    if len(ev) == 0:
        raise AnalysisInputError(
            f"{what}: no collisions recorded; run longer with an EventRecorder in sim.writers "
            "(or record the trajectory with events=True)"
        )
    if not duration > 0:
        raise AnalysisInputError(
            f"{what}: the record spans no time; record events over a run that advances the clock"
        )
    return ev, duration, n


def _dimensions(source: EventRecorder | Frames) -> int:
    """Dimensions of the spheres whose events ``source`` holds (2 for disks: their ``dp`` have z = 0)."""
    if isinstance(source, EventRecorder):
        return source.dim
    return int(np.shape(source.positions)[2])


def _per_sphere_stream(ev: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Each collision seen from both spheres, sorted by sphere then time: ``(sphere, time, partner, row)``."""
    sphere = np.concatenate([ev["i"], ev["j"]])
    partner = np.concatenate([ev["j"], ev["i"]])
    time = np.concatenate([ev["time"], ev["time"]])
    row = np.concatenate([np.arange(len(ev)), np.arange(len(ev))])
    order = np.lexsort((row, time, sphere))
    return sphere[order], time[order], partner[order], row[order]


class FreeFlights(Compute):
    """Free-flight times (between successive collisions of a sphere) and collisions per sphere.

    A sphere's flight before its first recorded collision, and after its
    last, are cut by the record's ends and left out (they would bias the
    mean short).

    Args:
        bins: histogram bins of the free-flight time.

    Attributes (after :meth:`compute`): ``flights`` (all complete
    free-flight times), ``rate`` (collisions per sphere per unit time,
    ``2 C / (N t)``), ``mean`` the mean free time ``1 / rate`` (unbiased),
    ``mean_error`` (its standard error, from the spread of the flights),
    ``flight_mean`` (the mean of the complete flights: low by about ``1 /
    K`` for ``K`` collisions per sphere, since a long flight is the likelier
    to be cut by the record's ends), ``per_sphere`` (collisions of each
    sphere), ``t`` bin centres and ``density`` (the histogram of the
    complete flights, normalised).

    Example:
        The mean free time against the exact one from the pressure::

            obs = sim.observables
            FreeFlights().compute(rec).mean, mean_free_time_from_z(obs.Z())
    """

    _results = ("flights", "mean", "mean_error", "flight_mean", "per_sphere", "rate", "t", "density")

    def __init__(self, bins: int = 60) -> None:
        self.bins = int(bins)

    def compute(self, source: EventRecorder | Frames) -> FreeFlights:
        """Statistics of ``source``'s collisions (an :class:`EventRecorder` or Frames); returns self."""
        ev, duration, n = _record(source, "free-flight statistics")
        sphere, time, _, _ = _per_sphere_stream(ev)
        same = sphere[1:] == sphere[:-1]
        self.flights = np.diff(time)[same]
        if len(self.flights) == 0:
            raise AnalysisInputError("free-flight statistics: no sphere collided twice; run longer")
        self.per_sphere = np.bincount(sphere, minlength=n)
        self.rate = 2.0 * len(ev) / (n * duration)
        self.mean = 1.0 / self.rate
        self.flight_mean = float(self.flights.mean())
        spread = self.flights.std(ddof=1) if len(self.flights) > 1 else math.nan
        self.mean_error = float(spread / math.sqrt(len(self.flights)))
        top = float(np.quantile(self.flights, 0.999))
        hist, edges = np.histogram(self.flights, bins=self.bins, range=(0.0, top))
        self.t = 0.5 * (edges[1:] + edges[:-1])
        self.density = hist / (len(self.flights) * np.diff(edges))
        self._computed = True
        return self

    def plot(self, ax: Axes | None = None) -> Axes:
        """The free-flight time distribution (log y) with the exponential of the same mean; returns Axes."""
        ax = self._axes(ax)
        ax.semilogy(self.t, self.density, ".", label="free flights")
        ax.semilogy(self.t, np.exp(-self.t / self.mean) / self.mean, "--", label="exp(-t / mean)")
        ax.set_xlabel("free-flight time")
        ax.set_ylabel("probability density")
        ax.legend()
        return ax


class Recollisions(Compute):
    """Recollisions: the same pair colliding again.

    (Two hard spheres that have just collided part on straight lines: they
    can meet again only after one of them has collided with another sphere,
    or, in a small periodic box, as images.)

    Attributes (after :meth:`compute`): ``intervals`` (for every collision
    of a pair that collided before, the time since its previous collision),
    ``fraction_repeated`` (the fraction of collisions that repeat a pair
    seen before in the record), ``collisions``.
    """

    _results = ("intervals", "fraction_repeated", "collisions")

    def compute(self, source: EventRecorder | Frames) -> Recollisions:
        """Recollisions in ``source``'s record; returns self."""
        ev, _, n = _record(source, "recollision statistics")
        key = ev["i"].astype(np.int64) * max(n, 1) + ev["j"]
        order = np.lexsort((np.arange(len(ev)), ev["time"], key))
        k, t = key[order], ev["time"][order]
        again = k[1:] == k[:-1]
        self.intervals = np.diff(t)[again]
        self.collisions = len(ev)
        self.fraction_repeated = float(again.sum() / len(ev))
        self._computed = True
        return self

    def within(self, t: float) -> float:
        """Fraction of all collisions that are a recollision of the same pair within ``t`` [time]."""
        self._need()
        return float(np.count_nonzero(self.intervals <= t) / self.collisions)

    def plot(self, ax: Axes | None = None) -> Axes:
        """Fraction of collisions recolliding within t, against t (log); returns Axes."""
        ax = self._axes(ax)
        s = np.sort(self.intervals)
        ax.semilogx(s, np.arange(1, len(s) + 1) / self.collisions)
        ax.set_xlabel("t")
        ax.set_ylabel("recollisions within t (fraction of collisions)")
        return ax


class ContactForces(Compute):
    """Time-averaged contact forces of a near-jammed packing (Donev, Torquato and Stillinger 2005).

    ``f_ij = (sum of |impulse| over the collisions of i and j) / t`` over a
    record of duration ``t`` at fixed radii.  Near jamming the collisions
    concentrate on the contacts of the packing, and these forces balance
    on every non-rattler (to the sampling noise); pairs that collide
    only now and then (rattlers, nearly touching neighbours) get small
    forces.  ``min_collisions`` drops pairs seen fewer times.

    Attributes (after :meth:`compute`): ``pairs`` ``(M, 2)``, ``forces``
    ``(M,)`` [force], ``vectors`` ``(M, d)`` (sum of the ``dp`` sphere ``i``
    received over ``t``), ``counts`` collisions per pair, ``n``, ``duration``.
    """

    _results = ("pairs", "forces", "vectors", "counts", "n", "duration")

    def __init__(self, min_collisions: int = 1) -> None:
        if int(min_collisions) != min_collisions or min_collisions < 1:
            raise AnalysisInputError(f"min_collisions must be a whole number >= 1, got {min_collisions!r}")
        self.min_collisions = int(min_collisions)

    def compute(self, source: EventRecorder | Frames) -> ContactForces:
        """Forces from ``source``'s record (an :class:`EventRecorder` or Frames); returns self."""
        ev, duration, n = _record(source, "contact forces")
        key = ev["i"].astype(np.int64) * max(n, 1) + ev["j"]
        uniq, inv, counts = np.unique(key, return_inverse=True, return_counts=True)
        total = np.bincount(inv, weights=ev["impulse"], minlength=len(uniq))
        dim = _dimensions(source)
        dp = np.stack([np.bincount(inv, weights=ev["dp"][:, c], minlength=len(uniq)) for c in range(dim)], 1)
        keep = counts >= self.min_collisions
        self.pairs = np.stack([uniq // n, uniq % n], axis=1)[keep]
        self.forces = total[keep] / duration
        self.vectors = dp[keep] / duration
        self.counts = counts[keep]
        self.n, self.duration = n, duration
        self._computed = True
        return self

    def plot(self, ax: Axes | None = None) -> Axes:
        """Distribution of f / <f> (log-log); returns Axes."""
        ax = self._axes(ax)
        f = self.forces / self.forces.mean()
        edges = np.geomspace(max(f.min(), 1e-6), f.max(), 40)
        hist, _ = np.histogram(f, edges)
        ax.loglog(np.sqrt(edges[1:] * edges[:-1]), hist / (len(f) * np.diff(edges)), ".")
        ax.set_xlabel("f / <f>")
        ax.set_ylabel("P(f)")
        return ax


def packing_contact_forces(sim: Simulation, per_sphere: int = 2000, min_collisions: int = 1) -> ContactForces:
    """The contact forces of ``sim``'s packing now: a copy run ``per_sphere`` collisions per sphere.

    The copy runs at fixed radii with an :class:`EventRecorder`, and
    :class:`ContactForces` averages its collisions; ``sim`` is left as it is.
    2000 collisions per sphere by default: with 200 a contact sees about 70
    collisions and the weak forces are missed (docs/validation,
    "Marginal stability").

    Raises:
        AnalysisInputError: the copy made no collision (nothing to average).
    """
    from ..simulation import Simulation

    if int(per_sphere) != per_sphere or per_sphere < 1:
        raise AnalysisInputError(f"per_sphere must be a whole number >= 1, got {per_sphere!r}")
    copy = Simulation(sim.state(), sim.container)
    rec = EventRecorder()
    copy.writers.append(rec)
    copy.run(collisions=int(per_sphere) * sim.n)
    if not rec.collisions:
        raise AnalysisInputError("contact forces: the packing's copy made no collision; give it velocities")
    return ContactForces(min_collisions).compute(rec)


__all__ = [
    "ContactForces",
    "packing_contact_forces",
    "EventRecorder",
    "FreeFlights",
    "NotComputedError",
    "Recollisions",
    "mean_free_time_from_z",
]

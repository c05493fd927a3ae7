"""Dense matter: compression (Lubachevsky-Stillinger growth) and thermostats.

* :func:`compress` grows every radius in proportion (the contact distances
  linear in time, the Lubachevsky-Stillinger collision rule in the event
  core) while velocities are rescaled to keep ``kT`` fixed, and stops at a
  target packing fraction, a reduced pressure (jamming) or a collision
  count.  :meth:`Simulation.compress <hardspheres.Simulation.compress>`
  calls it.
* :class:`Andersen` resamples one sphere's velocity at random times (a
  Poisson process, seeded: a run is reproducible and a checkpoint resumes
  it bit for bit); :class:`VelocityRescale` rescales all velocities to
  ``kT`` at fixed intervals; :class:`RandomKicks` gives every sphere a
  random (white-noise) velocity kick at fixed intervals, driving a granular
  gas to a steady state.  Set one with :meth:`Simulation.set_thermostat
  <hardspheres.Simulation.set_thermostat>`; without one a run is NVE,
  exactly as before.
* Under shear (Lees-Edwards boundaries) a thermostat must act on the
  peculiar velocities ``c = v - g y e_x`` (the velocity less the streaming
  profile), so that it does not fight the flow: :class:`PeculiarRescale`
  (isokinetic) and :class:`PeculiarAndersen` (stochastic); which
  steady state each gives is stated on each.  An elastic fluid heats up
  under shear without one; inelastic collisions need none.

Units: the compression ``rate`` is the growth speed of the largest
diameter in units of the thermal speed ``sqrt(kT / m)`` (``m`` the mean
mass): ``dD/dt`` for equal spheres with ``kT = m = 1``.  The LS program of
Skoge, Donev, Stillinger & Torquato (PRE 74, 041127 (2006); ``box.C`` of
their ``spheres`` code) grows each radius at ``growthrate`` g (``r = r0 +
g t``) and rescales the velocities to a mean ``|v|^2 = 1`` with ``m = 1``,
i.e. ``kT/m = 1/3`` in three dimensions; its g is therefore ``rate = 2 g /
sqrt(1/3) = 2 sqrt(3) g``.
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable
from typing import TYPE_CHECKING, NamedTuple, Protocol, runtime_checkable

import numpy as np
from numpy.typing import ArrayLike

from .containers import MAX_PACKING, MAX_PACKING_2D, packing_fraction  # noqa: F401 (re-exported)
from .errors import CompressionError  # noqa: F401 (re-exported)
from .errors import ArgumentError
from .events import StopReason
from .scenario import StuckError
from .writers import SimulationView

if TYPE_CHECKING:
    from .observables import Observables

#: Densest packing of equal spheres (FCC/HCP), :data:`hardspheres.containers.MAX_PACKING`.
MAX_PACKING_EQUAL = MAX_PACKING

#: Default reduced pressure ``Z = PV/(NkT)`` at which compression stops as
#: jammed (Z diverges as the packing approaches jamming: ``Z ~ 3 phi_J /
#: (phi_J - phi)``, so 1e3 is within ~0.002 of it).
DEFAULT_PRESSURE = 1e3


class CompressResult(NamedTuple):
    """How a compression ended.

    Attributes:
        packing: packing fraction reached.
        pressure: reduced pressure ``Z = PV/(NkT)`` over the last stretch.
        collisions: collisions during the compression.
        reason: ``"packing"`` (target reached), ``"pressure"`` (``Z``
            passed the threshold: jammed), ``"collisions"`` (the limit) or
            ``"stuck"`` (the core found the spheres locked: jammed).
        jammed: ``reason`` is ``"pressure"`` or ``"stuck"``.
    """

    packing: float
    pressure: float
    collisions: int
    reason: str
    jammed: bool


class ObservedSimulation(SimulationView, Protocol):
    """What :func:`compress` and the thermostats use of a simulation: a writer's view and its observables."""

    @property
    def observables(self) -> Observables: ...


def max_packing(radii: ArrayLike, dimensions: int = 3) -> float:
    """Largest packing the geometry allows, for :func:`compress`'s check.

    Equal spheres: ``pi/sqrt(18) = 0.7405`` (Kepler, Hales); equal disks
    (``dimensions = 2``): ``pi/(2 sqrt 3) = 0.9069``.  Mixtures can pack
    denser; only the trivial bound 1 is applied to them.
    """
    r = np.asarray(radii, dtype=np.float64)
    if r.size and np.all(r == r[0]):
        return MAX_PACKING_2D if dimensions == 2 else MAX_PACKING_EQUAL
    return 1.0


def _kT(sim: ObservedSimulation) -> float:
    return sim.observables.temperature()


def compress(
    sim: ObservedSimulation,
    packing: float | None = None,
    rate: float = 1e-3,
    pressure: float | None = DEFAULT_PRESSURE,
    collisions: int | None = None,
    progress: Callable[[float, float, int], None] | None = None,
) -> CompressResult:
    """Compress ``sim`` by growing its spheres; see :meth:`Simulation.compress`.

    Longer than 80 lines: the compression loop (growth, the kT rescale, Z
    and the stopping tests) shares its running sums; its checks come first."""
    eng = sim.engine
    if eng.window > 0.0:
        raise CompressionError("compress: not with a simultaneity window (window=0)")
    if not (isinstance(rate, (int, float)) and math.isfinite(rate) and rate > 0):
        raise CompressionError(f"rate must be a number > 0, got {rate}")
    if pressure is not None and not (math.isfinite(pressure) and pressure > 0):
        raise CompressionError(f"pressure must be a number > 0, got {pressure}")
    if collisions is not None and int(collisions) <= 0:
        raise CompressionError(f"collisions must be > 0, got {collisions}")
    if packing is None and pressure is None and collisions is None:
        raise CompressionError("give packing, pressure or collisions: the compression never ends otherwise")
    n = sim.n
    if n == 0:
        raise CompressionError("compress: no spheres")
    radii = eng.radii_at()
    phi0 = packing_fraction(radii, sim.container)
    if packing is not None:
        top = max_packing(radii, sim.container.dimensions)
        if not (math.isfinite(packing) and 0 < packing < top):
            raise CompressionError(
                f"packing {packing:g} is not below {top:.4f}, the densest the geometry allows"
                if math.isfinite(packing) and packing >= top
                else f"packing must be a number in (0, {top:.4f}), got {packing}"
            )
        if packing <= phi0:
            raise CompressionError(f"packing {packing:g} is not above the present packing {phi0:.6g}")
    kT = _kT(sim)
    if not kT > 0:
        raise CompressionError("compress: the spheres are at rest (kT = 0); give them velocities")
    vth = math.sqrt(kT / float(np.mean(eng.masses)))
    rmax = float(radii.max())
    speed = 0.5 * rate * vth  # dR_max/dt
    t_target = math.inf
    if packing is not None:
        # radii grow in proportion: the packing goes as R^d (d = 3 spheres, 2 disks)
        t_target = sim.time + ((packing / phi0) ** (1.0 / sim.container.dimensions) - 1.0) * rmax / speed
    # collisions per sphere between velocity rescales: each collision heats
    # by ~4 rate (relative); a rescale costs about N predictions
    per_sphere = min(8.0, max(0.5, 0.01 / rate))
    chunk = max(int(per_sphere * n), 200)
    left = math.inf if collisions is None else int(collisions)
    eng.set_growth(speed / rmax)
    c_start = eng.counters["collisions"]
    z = math.nan
    reason = None
    try:
        while reason is None:
            t0, c0 = eng.time, eng.counters["collisions"]
            w0, j0 = eng.virial, eng.wall_impulse
            try:
                eng.advance(until=t_target, collisions=int(min(chunk, left)), record=False)
            except StuckError:
                reason = "stuck"
            done = eng.counters["collisions"] - c0
            left -= done
            reached = eng.last_reason == StopReason.UNTIL and t_target < math.inf
            if reached:
                eng.move_clock(t_target)
            dt = eng.time - t0
            kt_end = _kT(sim)
            kt_mean = 0.5 * (kT + kt_end)
            if dt > 0:  # the container knows its pressure: the virial in a box, the wall in a sphere
                p = sim.container.pressure(n, kt_mean, dt, eng.wall_impulse - j0, eng.virial - w0)
                z = p * sim.container.volume / (n * kt_mean)
            if kt_end > 0:
                eng.rescale_velocities(math.sqrt(kT / kt_end))
            phi = packing_fraction(eng.radii_at(), sim.container)
            if progress is not None:
                progress(phi, z, eng.counters["collisions"] - c_start)
            if reason is not None:
                break
            if reached:
                reason = "packing"
            elif pressure is not None and z >= pressure:
                reason = "pressure"
            elif left <= 0:
                reason = "collisions"
    finally:
        eng.set_growth(0.0)
        sim.observables.reset()
    phi = packing_fraction(eng.radii, sim.container)
    return CompressResult(
        phi, float(z), eng.counters["collisions"] - c_start, reason, reason in ("pressure", "stuck")
    )


# ---- thermostats ----------------------------------------------------------------


@runtime_checkable
class Thermostat(Protocol):
    """What :class:`hardspheres.Simulation` calls on its thermostat (its own slot, not a writer).

    A thermostat acts on the state: at :attr:`next_time` the simulation calls
    :meth:`apply`, before any writer due at the same time writes, so writers
    only ever observe.

    Attributes:
        next_time: when it next acts [time] (``None`` until attached).
    """

    next_time: float | None

    def attach(self, sim: ObservedSimulation) -> None:
        """Called as each run starts."""

    def apply(self, sim: ObservedSimulation, t: float) -> None:
        """Act on ``sim``'s spheres at time ``t``."""

    def state(self) -> str:
        """JSON text from which :func:`thermostat_from_state` rebuilds it exactly."""


class Andersen:
    """Andersen thermostat: at random times one sphere gets a Maxwell velocity.

    The new velocity has ``d`` components (3, or 2 for disks), each drawn
    from the normal distribution of variance ``kT / m``: ``d/2 kT`` per
    sphere on average, as :meth:`Observables.temperature
    <hardspheres.observables.Observables.temperature>` counts ``d``
    degrees of freedom per sphere.

    Args:
        kT: temperature [energy].
        rate: resamplings per sphere per unit time [1/time] (the whole
            system: ``rate * N``; the times between them are exponential).
        seed: seed of the generator (numpy's PCG64): the same seed gives the
            same run, and a checkpoint resumes it bit for bit.
    """

    def __init__(self, kT: float = 1.0, rate: float = 0.1, seed: int = 0) -> None:
        if not (math.isfinite(kT) and kT > 0):
            raise ArgumentError(f"kT must be a number > 0, got {kT}")
        if not (math.isfinite(rate) and rate > 0):
            raise ArgumentError(f"rate must be a number > 0, got {rate}")
        self.kT, self.rate, self.seed = float(kT), float(rate), int(seed)
        self._rng = np.random.Generator(np.random.PCG64(self.seed))
        self.next_time: float | None = None
        self.resampled = 0

    def attach(self, sim: ObservedSimulation) -> None:
        """Called as each run starts: schedules the first resampling."""
        if self.next_time is None:
            self.next_time = sim.time + self._rng.exponential(1.0 / (self.rate * sim.n))

    def apply(self, sim: ObservedSimulation, t: float) -> None:
        """Resample one sphere's velocity at ``t`` (the simulation calls this at :attr:`next_time`)."""
        eng = sim.engine
        i = int(self._rng.integers(sim.n))
        v = self._rng.normal(size=sim.container.dimensions) * math.sqrt(self.kT / eng.masses[i])
        eng.kick(i, t, v)
        self.resampled += 1
        self.next_time = t + self._rng.exponential(1.0 / (self.rate * sim.n))

    def state(self) -> str:
        """JSON text of everything needed to resume exactly."""
        return json.dumps(
            {
                "kind": "andersen",
                "kT": self.kT,
                "rate": self.rate,
                "seed": self.seed,
                "next_time": self.next_time,
                "resampled": self.resampled,
                "rng": self._rng.bit_generator.state,
            }
        )


class VelocityRescale:
    """Rescale all velocities to ``kT`` every ``interval`` [time]."""

    def __init__(self, kT: float = 1.0, interval: float = 1.0) -> None:
        if not (math.isfinite(kT) and kT > 0):
            raise ArgumentError(f"kT must be a number > 0, got {kT}")
        if not (math.isfinite(interval) and interval > 0):
            raise ArgumentError(f"interval must be a number > 0, got {interval}")
        self.kT, self.interval = float(kT), float(interval)
        self.next_time: float | None = None

    def attach(self, sim: ObservedSimulation) -> None:
        """Called as each run starts: schedules the first rescale."""
        if self.next_time is None:
            self.next_time = sim.time + self.interval

    def apply(self, sim: ObservedSimulation, t: float) -> None:
        """Rescale every velocity at ``t`` (the simulation calls this at :attr:`next_time`)."""
        eng = sim.engine
        eng.move_clock(t)
        kt = _kT(sim)
        if kt > 0:
            eng.rescale_velocities(math.sqrt(self.kT / kt))
        self.next_time = t + self.interval

    def state(self) -> str:
        return json.dumps(
            {"kind": "rescale", "kT": self.kT, "interval": self.interval, "next_time": self.next_time}
        )


class RandomKicks:
    """White-noise driving: every ``interval`` each sphere's velocity gets a random kick.

    The kick of sphere ``i`` is ``xi_i - sum_j m_j xi_j / M``: ``xi_i`` has
    ``d`` independent normal components of variance ``strength * interval``
    and the mass-weighted mean is taken off, so the total momentum does not
    change.  As ``interval -> 0`` this is the random force of Williams and
    MacKintosh (Phys. Rev. E 54, R9 (1996)) and of van Noije, Ernst, Trizac
    and Pagonabarraga (Phys. Rev. E 59, 4326 (1999)), ``dv_i/dt = (collisions)
    + xi_i(t)`` with ``<xi_ia(t) xi_jb(t')> = strength delta_ij delta_ab
    delta(t - t')`` (``strength`` is their ``xi_0^2``; a diffusion in
    velocity of coefficient ``strength / 2``).  It injects on average
    ``(N - 1) d m strength / 2`` of kinetic energy per unit time (equal
    masses ``m``), whatever the velocities; inelastic collisions dissipate
    it, and the gas reaches a steady state where the two balance
    (docs/guide/granular.md, "Driven steady states").  Choose ``interval``
    a small fraction of the mean free time, so that spheres fly freely
    between kicks on a scale much finer than between collisions.

    :attr:`injected` tallies the energy the kicks gave (the kinetic energy
    after each kick less before it, exactly), so that kinetic plus
    dissipated less injected energy is conserved to rounding
    (:meth:`Observables.energy_balance
    <hardspheres.observables.Observables.energy_balance>`).

    Args:
        strength: ``xi_0^2``, the variance of the velocity kicks per
            component per unit time [length^2/time^3].
        interval: time between kicks [time].
        seed: seed of the generator (numpy's PCG64): the same seed gives
            the same run, and a checkpoint resumes it bit for bit.

    Example:
        >>> import hardspheres as hs
        >>> from hardspheres.dense import RandomKicks
        >>> box = hs.PeriodicBox.for_packing(200, 0.1, (1.0, 1.0))
        >>> sim = hs.Simulation(hs.random_spheres(200, 0.1, box, seed=1), box, restitution=0.9)
        >>> kicks = RandomKicks(strength=0.5, interval=0.25, seed=1)
        >>> _ = sim.set_thermostat(kicks).run(until=2.0)
        >>> kicks.kicks, abs(sim.observables.energy_balance()) < 1e-12
        (8, True)
    """

    def __init__(self, strength: float, interval: float, seed: int = 0) -> None:
        if not (isinstance(strength, (int, float)) and math.isfinite(strength) and strength > 0):
            raise ArgumentError(
                f"strength must be a number > 0 (the kicks' variance per unit time), got {strength}"
            )
        if not (isinstance(interval, (int, float)) and math.isfinite(interval) and interval > 0):
            raise ArgumentError(f"interval must be a time > 0, got {interval}")
        self.strength, self.interval, self.seed = float(strength), float(interval), int(seed)
        self._rng = np.random.Generator(np.random.PCG64(self.seed))
        self.next_time: float | None = None
        #: kicks given (each kicks every sphere)
        self.kicks = 0
        #: kinetic energy the kicks gave so far [energy]
        self.injected = 0.0

    def injection_rate(self, masses: ArrayLike, dimensions: int = 3) -> float:
        """Mean energy the kicks inject per unit time into ``masses`` in ``dimensions`` [energy/time].

        ``sum_i m_i (1 - m_i / M) d strength / 2``: ``(N - 1) d m strength
        / 2`` for equal masses (taking off the mean kick removes one
        sphere's share), whatever the velocities.
        """
        m = np.asarray(masses, dtype=np.float64)
        total = float(m.sum())
        if not total > 0:
            return 0.0
        return float(np.sum(m * (1.0 - m / total))) * dimensions * self.strength / 2.0

    def attach(self, sim: ObservedSimulation) -> None:
        """Called as each run starts: schedules the first kick."""
        if self.next_time is None:
            self.next_time = sim.time + self.interval

    def apply(self, sim: ObservedSimulation, t: float) -> None:
        """Kick every sphere at ``t`` (the simulation calls this at :attr:`next_time`)."""
        eng = sim.engine
        n, d = sim.n, sim.container.dimensions
        if n:
            m = np.asarray(eng.masses, dtype=np.float64)
            xi = self._rng.normal(size=(n, d)) * math.sqrt(self.strength * self.interval)
            xi -= (m @ xi) / m.sum()
            before = eng.kinetic_energy()
            v = eng.velocities + xi
            for i in range(n):  # each sphere predicted afresh (the engine's public kick)
                eng.kick(i, t, v[i])
            self.injected += eng.kinetic_energy() - before
        self.kicks += 1
        self.next_time = t + self.interval

    def state(self) -> str:
        """JSON text of everything needed to resume exactly."""
        return json.dumps(
            {
                "kind": "kicks",
                "strength": self.strength,
                "interval": self.interval,
                "seed": self.seed,
                "next_time": self.next_time,
                "kicks": self.kicks,
                "injected": self.injected,
                "rng": self._rng.bit_generator.state,
            }
        )


def _stream(sim: ObservedSimulation, t: float) -> tuple[float, np.ndarray]:
    """The shear rate ``g`` [1/time] and the streaming velocity along x of every sphere at ``t``."""
    g = float(getattr(sim.container, "shear_rate", 0.0))
    if not g:
        return 0.0, np.zeros(sim.n)
    x = np.asarray(sim.engine.positions_at(t), dtype=np.float64).reshape(sim.n, -1)
    return g, g * x[:, 1]


class PeculiarRescale:
    """Isokinetic thermostat on the peculiar velocities: every ``interval``, ``c -> c sqrt(kT / kT_c)``.

    At each action every sphere's peculiar velocity ``c = v - g y e_x``
    (``y`` its centre then) is scaled by one factor so that ``sum m c^2 /
    (d N - d)`` is ``kT``, and ``v = g y e_x + c`` is given back (one kick
    per sphere): the streaming profile is kept, the heat of the flow
    removed.  Without shear it is :class:`VelocityRescale`.

    **Steady state.**  Rescaled often (``interval`` well below the heating
    time ``kT / (d kT/dt)``) this is the Gaussian isokinetic thermostat
    applied to the peculiar momenta, as in the SLLOD algorithm: it gives
    the isokinetic nonequilibrium steady state, whose configurational
    distribution tends to the canonical one at ``kT`` as ``g -> 0``, so
    ``eta(g) = -P_xy / g`` tends to the equilibrium (Green-Kubo, or
    Einstein-Helfand) viscosity at that temperature (Evans and Morriss,
    *Statistical Mechanics of Nonequilibrium Liquids*, 2nd ed., Cambridge
    (2008), chapters 5 and 6).  It assumes the profile is linear
    ("profile-biased"): at large rates a thermostat that imposes the
    profile can stabilise layered "string" phases that a profile-unbiased
    one would not (Evans and Morriss, ch. 6; DynamO's ``BC/LEBC.hpp``
    notes the same): check that the profile measured
    (:meth:`hardspheres.observables.ShearFlow.profile`) is linear.  Between
    actions the fluid heats by ``2 eta g^2 V / (d N) dt`` in ``kT``, so the
    mean ``kT`` sits slightly above the target.

    Args:
        kT: the temperature of the peculiar velocities [energy].
        interval: the time between actions [time].
    """

    def __init__(self, kT: float = 1.0, interval: float = 0.1) -> None:
        if not (math.isfinite(kT) and kT > 0):
            raise ArgumentError(f"kT must be a number > 0, got {kT}")
        if not (math.isfinite(interval) and interval > 0):
            raise ArgumentError(f"interval must be a number > 0, got {interval}")
        self.kT, self.interval = float(kT), float(interval)
        self.next_time: float | None = None

    def attach(self, sim: ObservedSimulation) -> None:
        """Called as each run starts: schedules the first action."""
        if self.next_time is None:
            self.next_time = sim.time + self.interval

    def apply(self, sim: ObservedSimulation, t: float) -> None:
        """Rescale the peculiar velocities at ``t`` (the run calls this at :attr:`next_time`)."""
        eng = sim.engine
        eng.move_clock(t)
        g, u = _stream(sim, t)
        v = np.asarray(eng.velocities, dtype=np.float64).reshape(sim.n, -1).copy()
        c = v.copy()
        c[:, 0] -= u
        m = np.asarray(eng.masses, dtype=np.float64)
        kt = float(np.sum(m[:, None] * c * c)) / max(sim.container.degrees_of_freedom(sim.n), 1)
        if kt > 0:
            c *= math.sqrt(self.kT / kt)
            c[:, 0] += u
            for i in range(sim.n):
                eng.kick(i, t, c[i])
        self.next_time = t + self.interval

    def state(self) -> str:
        """JSON text of everything needed to resume exactly."""
        return json.dumps(
            {
                "kind": "peculiar_rescale",
                "kT": self.kT,
                "interval": self.interval,
                "next_time": self.next_time,
            }
        )


class PeculiarAndersen(Andersen):
    """Andersen thermostat on the peculiar velocities: at random times one sphere gets ``c`` from Maxwell.

    As :class:`Andersen` (one sphere at a time, at exponentially
    distributed intervals, ``rate`` per sphere per unit time, seeded), but
    the new velocity is ``g y e_x + c`` with ``c`` drawn at ``kT`` and ``y``
    the sphere's centre then: a bath that moves with the streaming profile.
    Without shear it is :class:`Andersen`, draw for draw.

    **Steady state.**  Without shear, Andersen's stochastic collisions give
    the canonical ensemble (H. C. Andersen, J. Chem. Phys. 72, 2384
    (1980)).  Under shear each kick also resets the sphere's momentum to
    the profile's, a second, artificial momentum exchange besides the
    collisions: the steady state is a nonequilibrium one held at ``kT``
    whose stress includes the bath's drag, so ``eta = -P_xy / g`` is the
    fluid's own only while ``rate`` is far below the collision rate (the
    kicks then carry a small fraction of the momentum).  Like
    :class:`PeculiarRescale` it assumes the linear profile (Evans and
    Morriss, *Statistical Mechanics of Nonequilibrium Liquids*, ch. 6).

    Args:
        kT: temperature of the peculiar velocities [energy].
        rate: resamplings per sphere per unit time [1/time].
        seed: seed of the generator.
    """

    def apply(self, sim: ObservedSimulation, t: float) -> None:
        """Resample one sphere's peculiar velocity at ``t`` (the run calls this at :attr:`next_time`)."""
        eng = sim.engine
        i = int(self._rng.integers(sim.n))
        c = self._rng.normal(size=sim.container.dimensions) * math.sqrt(self.kT / eng.masses[i])
        g = float(getattr(sim.container, "shear_rate", 0.0))
        if g:
            eng.move_clock(t)
            y = float(np.asarray(eng.positions_at(t), dtype=np.float64).reshape(sim.n, -1)[i, 1])
            c[0] += g * y
        eng.kick(i, t, c)
        self.resampled += 1
        self.next_time = t + self._rng.exponential(1.0 / (self.rate * sim.n))

    def state(self) -> str:
        """JSON text of everything needed to resume exactly."""
        d = json.loads(super().state())
        d["kind"] = "peculiar_andersen"
        return json.dumps(d)


def thermostat_from_state(text: str) -> Andersen | VelocityRescale | RandomKicks | PeculiarRescale:
    """The thermostat that :meth:`Andersen.state`, :meth:`VelocityRescale.state`,
    :meth:`RandomKicks.state` or a peculiar one's ``state`` saved."""
    d = json.loads(text)
    th: Andersen | VelocityRescale | RandomKicks | PeculiarRescale
    if d["kind"] in ("andersen", "peculiar_andersen"):
        th = (Andersen if d["kind"] == "andersen" else PeculiarAndersen)(d["kT"], d["rate"], d["seed"])
        th._rng.bit_generator.state = d["rng"]
        th.resampled = d["resampled"]
    elif d["kind"] == "kicks":
        th = RandomKicks(d["strength"], d["interval"], d["seed"])
        th._rng.bit_generator.state = d["rng"]
        th.kicks, th.injected = int(d["kicks"]), float(d["injected"])
    elif d["kind"] == "peculiar_rescale":
        th = PeculiarRescale(d["kT"], d["interval"])
    else:
        th = VelocityRescale(d["kT"], d["interval"])
    th.next_time = d["next_time"]
    return th

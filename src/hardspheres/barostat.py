"""Constant pressure: Monte Carlo volume moves between exact event-driven stretches.

:class:`Barostat` holds the pressure ``P`` of a run in a periodic box.  At
fixed intervals of time it tries one volume move: every centre is scaled
with the box (the affine map ``x -> s x``), velocities kept, and the move
is accepted with the Metropolis probability of the isobaric-isothermal
ensemble for hard spheres,

    ``min(1, exp(-beta P (V' - V) + (N + 1) ln(V'/V)))``  and no overlap,

where the proposal is a random walk in ``ln V`` (isotropic moves) or in
``ln L_a`` of one box side (per-axis moves; ``ln L_a' - ln L_a = ln V'/V``,
the same rule), so the Jacobian adds one to ``N``: Frenkel & Smit,
*Understanding Molecular Simulation* (2nd ed., Academic Press 2002),
section 5.4.2 (NPT Monte Carlo; Algorithm 11 and the ``ln V`` variant of
the acceptance rule, eq. 5.4.13).  Per axis: with the sides sampled
independently, the box's measure is ``dLx dLy dLz = V d(ln Lx) d(ln Ly)
d(ln Lz)``, so the weight of ``(ln Lx, ln Ly, ln Lz)`` is ``exp(-beta P V)
V^(N+1)``, and a symmetric step in one ``ln L_a`` (the side drawn at
random, the others fixed) is accepted by the rule above with ``V'/V =
L_a'/L_a``: the rectangular-box NPT of Allen & Tildesley, *Computer
Simulation of Liquids* (2nd ed., OUP 2017), section 4.5, in ``ln L``.  A
slab that moves only its long side (``axes="z"``) samples the ensemble at
constant normal pressure and fixed cross-section (``N P_zz A T``), the
ensemble of direct-coexistence runs.  In 2-D ``V`` is the area and ``P``
the two-dimensional pressure (``beta P sigma^2``).  A move that makes two spheres overlap is
rejected (hard spheres: ``U' = infinity``); one that expands every side
cannot make an overlap and is not checked.  Between moves the spheres run
exactly (:class:`hardspheres.core.engine.Engine`); the engine is made
anew for the new box after an accepted move
(:meth:`~hardspheres.core.engine.Engine.rescale_box`), which is exact: the
event-driven dynamics needs only the state now.

Why this samples NPT: event-driven runs at fixed volume keep the uniform
measure over non-overlapping configurations (Liouville's theorem; the
energy is all kinetic and constant), and the move obeys detailed balance
with respect to ``exp(-beta P V) V^N`` times that measure; the velocities
are left alone and enter nothing.  The scheme is the hybrid MD/MC of the
hard-sphere literature (e.g. Frenkel & Smit, ch. 5.4 and 6.2; the volume
moves of Eppenga & Frenkel, Mol. Phys. 52, 1303 (1984)).

``beta = 1 / kT``: the thermostat's ``kT`` if the simulation has one, else
the kinetic temperature when the barostat is first attached (constant in a
run without a thermostat), or the ``kT`` given.  In reduced units (``kT =
1``, diameter 1) ``pressure`` is ``beta P sigma^3``.

The approach (isotropic moves, equal spheres or disks): from below, the
volume moves crawl (a compression is refused as soon as one pair would
overlap, so each accepted move changes ``ln V`` by about ``1 / (N (Z -
1))``: hundreds of mean free times from packing 0.3 to ``beta P = 5``).
So when first attached below the packing the equation of state gives at
``P`` (:func:`hardspheres.eos.packing_at_pressure`: Hansen-Goos for
spheres, Kolafa-Rottner for disks, in the fluid's range), the barostat
first squeezes the box to it, ten squeezes per mean free time, each closing
nine tenths of the narrowest gap between two spheres (no overlap, no
Metropolis test: the approach is not a sample).  Not from above (a crystal
is denser than the fluid at its pressure; expansions are not refused), not
with per-side moves (a slab keeps its cross-section).  Then the
Metropolis moves above, with the step and interval of the packing reached.
The averages (:attr:`Barostat.mean_packing`, ...) take only the moves after
the approach, and :attr:`Barostat.drifting` says when the packing still
drifts over them.

Deterministic given ``seed`` (numpy's PCG64); :meth:`Barostat.state` is
saved in checkpoints (:meth:`hardspheres.Simulation.save`), so a resumed
run makes the same moves bit for bit.  Refused in a spherical or circular
container (:class:`~hardspheres.errors.BarostatError`).

Example:
    >>> import hardspheres as hs
    >>> from hardspheres.barostat import Barostat
    >>> box = hs.PeriodicBox.for_packing(108, 0.3)
    >>> sim = hs.Simulation(hs.random_spheres(108, 0.3, box=box.length, seed=1), box)
    >>> sim.set_barostat(Barostat(pressure=5.0, seed=2)).run(until=2.0).time
    2.0
    >>> sim.barostat.attempted > 0, 0.3 < sim.packing < 0.5
    (True, True)
"""

from __future__ import annotations

import json
import math
from typing import TYPE_CHECKING, Protocol, cast

import numpy as np

from .errors import BarostatError

if TYPE_CHECKING:
    from .containers import Container, PeriodicBox
    from .core.engine import Engine
    from .dense import ObservedSimulation, Thermostat

    class HeldSimulation(ObservedSimulation, Protocol):
        """What a barostat uses of a simulation: a thermostat's view, the packing, a box it may replace."""

        container: Container

        @property
        def packing(self) -> float: ...

        @property
        def thermostat(self) -> Thermostat | None: ...


#: Moves per unit of the auto interval, the mean free time of the fluid
#: (Enskog, from Carnahan-Starling at the packing when first attached)
#: divided by this.
MOVES_PER_FREE_TIME = 1.0

#: Squeezes per mean free time while approaching the equation of state's packing.
APPROACH_MOVES_PER_FREE_TIME = 10.0

#: Each squeeze of the approach closes this fraction of the narrowest gap.
APPROACH_GAP_FRACTION = 0.9

#: No approach when the packing is already within this (relative) of the equation of state's.
APPROACH_TOLERANCE = 2e-3

#: Most block means of the packing kept for its trend (:attr:`Barostat.drifting`).
DRIFT_BLOCKS = 16

#: A trend of the packing over the averaged moves beyond this (relative) is a drift.
DRIFT_TOLERANCE = 0.01

#: The default step is this over ``N (Z - 1)``, since squeezing ``ln V`` by ``d``
#: makes an overlap with a probability of about ``N (Z - 1) d`` (the pairs
#: within ``d / 3`` of contact; Eppenga & Frenkel 1984), so steps of this
#: size are accepted about half the time in dense matter.  ``Z`` is the
#: packing's when first attached (not the pressure's: a run far from its
#: equilibrium would get steps too small to get there).
STEP_SCALE = 3.0

_AXES = "xyz"


def _sides(container: Container) -> tuple[float, ...]:
    """The periodic box's sides ``(Lx, Ly, Lz)``, or ``(Lx, Ly)`` in 2-D [length]."""
    sides = getattr(container, "sides", None)
    if sides is None:
        return (float(cast(float, cast("PeriodicBox", container).length)),) * 3  # a cube
    return tuple(float(x) for x in sides)


def _box_like(container: Container, sides: list[float]) -> Container:
    """A periodic box of the same kind as ``container`` with ``sides`` (three equal: the cube)."""
    return cast("type[PeriodicBox]", type(container))(tuple(sides))


def require_box(container: Container | None, what: str = "constant pressure") -> None:
    """:class:`BarostatError` unless ``container`` is a periodic box."""
    if container is None or not container.periodic:
        desc = getattr(container, "description", "this container")
        raise BarostatError(
            f"{what} needs a periodic box (its volume moves scale the box), not a {desc}; "
            "simulate in hs.PeriodicBox(L), or hs.PeriodicBox((Lx, Ly)) for disks"
        )


class Barostat:
    """Hold the pressure with Monte Carlo volume moves (see the module docstring).

    Args:
        pressure: ``P`` [energy/length^3] (``beta P sigma^3`` with ``kT = 1``
            and diameter 1), > 0.
        kT: ``1 / beta`` [energy]; ``None``: the thermostat's, or the
            kinetic temperature when first attached.
        every: time between moves [time]; ``None``: the fluid's Enskog mean
            free time at the packing when first attached, over
            :data:`MOVES_PER_FREE_TIME`.
        step: largest change of ``ln V`` (isotropic) or of ``ln L_a`` (per
            axis) per move; ``None``: ``min(0.5 / sqrt(N), 3 / (N (Z -
            1)))`` when first attached, ``Z`` the equation of state's at the
            packing then (squeezing by more than about ``1 / (N (Z - 1))``
            makes an overlap almost surely).
        approach: when first attached below the equation of state's
            packing at ``P``, squeeze to it first (isotropic moves, equal
            spheres or disks; see the module docstring); ``False``:
            Metropolis moves from the start.
        axes: ``None`` (isotropic: every side scaled alike), or the sides
            that move one at a time (a random one per move): ``"xyz"`` (or
            ``"xy"`` in 2-D) lets a crystal relax its shape, ``"z"`` changes
            only the long side of a slab along z.  Letters of the box's own
            axes (``"xy"`` in 2-D).
        seed: seed of the generator: the same seed gives the same run.

    Attributes:
        attempted: moves tried.
        accepted: moves accepted.
        overlaps: moves rejected because two spheres would overlap.
        next_time: when it next acts [time] (``None`` until attached).
        samples: moves since :meth:`reset_averages` (after the approach),
            each a sample of the box after its move (equally spaced in
            time), for :attr:`mean_volume`, :attr:`volume_variance` and
            :attr:`mean_packing`.
        target: the equation of state's packing the approach goes to
            (``None``: no approach).
        approaching: whether the approach is still under way.
        squeezes: the approach's moves.
    """

    def __init__(
        self,
        pressure: float,
        kT: float | None = None,
        every: float | None = None,
        step: float | None = None,
        axes: str | None = None,
        seed: int = 0,
        approach: bool = True,
    ) -> None:
        self.pressure = _positive(pressure, "pressure")
        self.approach = bool(approach)
        self.target: float | None = None
        self.approaching = False
        self.squeezes = 0
        self._auto = (step is None, every is None)
        self.kT = None if kT is None else _positive(kT, "kT")
        self.every = None if every is None else _positive(every, "every")
        self.step = None if step is None else _positive(step, "step")
        if axes is not None:
            if (
                not isinstance(axes, str)
                or not axes
                or any(a not in _AXES for a in axes)
                or (len(set(axes)) != len(axes))
            ):
                raise BarostatError(
                    f"axes must be None (isotropic) or distinct letters of 'xyz', got {axes!r}"
                )
        self.axes = axes
        bad_seed = BarostatError(f"seed must be a whole number >= 0, got {seed!r}")
        try:
            self.seed = int(seed)
        except (TypeError, ValueError, OverflowError):
            raise bad_seed from None
        if self.seed != seed or self.seed < 0:
            raise bad_seed
        self._rng = np.random.Generator(np.random.PCG64(self.seed))
        self.next_time: float | None = None
        self.attempted = self.accepted = self.overlaps = 0
        self._solid = math.nan  # the spheres' own volume (set when attached)
        self.reset_averages()

    def reset_averages(self) -> Barostat:
        """Start the averages afresh (after an equilibration, say); returns self."""
        self.samples = 0
        self._sums = [0.0, 0.0, 0.0]  # sums of V, (V - V0)^2 and solid / V; V0 the first V
        self._v0: float | None = None
        # the packing's block means, for its trend: blocks of _block samples, at most
        # DRIFT_BLOCKS (pairs merged, the size doubled, when full); the block being filled
        self._blocks: list[float] = []
        self._block = 1
        self._filling = [0.0, 0]
        return self

    def _trend(self) -> tuple[float, float]:
        """``(change, its standard error)`` of the packing over the blocks, from a straight line fit."""
        y = np.array(self._blocks)
        m = len(y)
        if m < DRIFT_BLOCKS // 4:
            return math.nan, math.nan
        x = np.arange(m, dtype=float) - (m - 1) / 2.0
        slope = float(x @ (y - y.mean()) / (x @ x))
        resid = y - y.mean() - slope * x
        se = math.sqrt(float(resid @ resid) / (m - 2) / float(x @ x))
        return slope * m, se * m

    @property
    def packing_drift(self) -> float:
        """The packing's change over the samples, from a straight line fitted to its block means.

        NaN before :data:`DRIFT_BLOCKS` / 4 blocks.
        """
        return self._trend()[0]

    @property
    def drifting(self) -> bool:
        """Whether the packing drifts over the averaged moves (a trend the mean should not hide).

        True when the change fitted to the block means is over 4 of its
        standard errors (from their scatter about the line) and over
        :data:`DRIFT_TOLERANCE` of the mean packing: an approach not over, or
        fluctuations slower than the run (the volume moves relax the box
        slowly), either way a mean uncertain at that level.  ``False`` when
        too few moves to tell.
        """
        change, err = self._trend()
        return bool(abs(change) > 4.0 * err and abs(change) > DRIFT_TOLERANCE * self.mean_packing)

    @property
    def mean_volume(self) -> float:
        """Mean volume (area in 2-D) over the samples [length^d] (NaN before any)."""
        return self._sums[0] / self.samples if self.samples else math.nan

    @property
    def volume_variance(self) -> float:
        """Variance of the volume over the samples [length^2d] (NaN before two).

        Shifted by the first sample, so no cancellation between large sums.
        """
        if self.samples < 2:
            return math.nan
        d = self._sums[0] / self.samples - cast(float, self._v0)  # set by the first sample
        return (self._sums[1] / self.samples - d * d) * self.samples / (self.samples - 1)

    @property
    def mean_packing(self) -> float:
        """Mean packing fraction (area fraction in 2-D) over the samples (NaN before any)."""
        return self._sums[2] / self.samples if self.samples else math.nan

    def _sample(self, volume: float) -> None:
        if self._v0 is None:
            self._v0 = volume
        phi = self._solid / volume
        self.samples += 1
        self._sums[0] += volume
        self._sums[1] += (volume - self._v0) ** 2
        self._sums[2] += phi
        self._filling[0] += phi
        self._filling[1] += 1
        if self._filling[1] == self._block:
            self._blocks.append(self._filling[0] / self._block)
            self._filling = [0.0, 0]
            if len(self._blocks) == DRIFT_BLOCKS:
                b = self._blocks
                self._blocks = [0.5 * (b[k] + b[k + 1]) for k in range(0, len(b), 2)]
                self._block *= 2

    def __repr__(self) -> str:
        return (
            f"Barostat(pressure={self.pressure!r}, kT={self.kT!r}, every={self.every!r}, "
            f"step={self.step!r}, axes={self.axes!r}, seed={self.seed!r}, approach={self.approach!r})"
        )

    @property
    def acceptance(self) -> float:
        """Fraction of moves accepted (NaN before any)."""
        return self.accepted / self.attempted if self.attempted else math.nan

    def check(self, sim: HeldSimulation) -> None:
        """:class:`BarostatError` if ``sim`` cannot be held at constant pressure."""
        require_box(sim.container)
        if getattr(sim.container, "shear_rate", 0.0):
            raise BarostatError(
                "barostat: not in a sheared box (its volume moves would move the flow); give shear_rate=0"
            )
        if getattr(sim.engine, "steps", ()):
            raise BarostatError(
                "barostat: not with steps (square wells) yet; its volume moves would change bonds"
            )
        if sim.engine.window > 0.0:
            raise BarostatError("barostat: not with a simultaneity window (window=0)")
        d = len(_sides(sim.container))
        if self.axes is not None and any(_AXES.index(a) >= d for a in self.axes):
            raise BarostatError(
                f"axes={self.axes!r} in a {d}-D box: use letters of {_AXES[:d]!r} (or None: isotropic)"
            )
        if sim.n < 1:
            raise BarostatError("barostat: no spheres")

    def attach(self, sim: HeldSimulation) -> None:
        """Called as each run starts: fixes ``kT``, ``every``, ``step`` (once) and the first move."""
        self.check(sim)
        self._solid = float(sim.packing) * float(sim.container.volume)
        if self.kT is None:
            th_kT = getattr(sim.thermostat, "kT", None)
            self.kT = float(th_kT) if th_kT is not None else float(sim.observables.temperature())
            if not (math.isfinite(self.kT) and self.kT > 0):
                raise BarostatError("barostat: the spheres are at rest (kT = 0); give them velocities or kT")
        if self.next_time is None and self.approach and self.axes is None:
            self.target = _eos_packing(sim, self.pressure, self.kT)
            self.approaching = self.target is not None and (
                float(sim.packing) < self.target * (1.0 - APPROACH_TOLERANCE)
            )
        self._scales(sim)
        if self.next_time is None:
            self.next_time = sim.time + self._interval()

    def _interval(self) -> float:
        every = cast(float, self.every)
        return every / APPROACH_MOVES_PER_FREE_TIME if self.approaching and self._auto[1] else every

    def _scales(self, sim: HeldSimulation) -> None:
        """``step`` and ``every`` from the packing now, where not given."""
        n = sim.n
        if self.step is None or self.every is None:
            from .eos import carnahan_starling, collision_rate_from_z

            kT = cast(float, self.kT)  # set before
            radii = sim.engine.radii_at()
            phi = min(float(sim.packing), 0.7)
            sigma = 2.0 * float(np.mean(radii))
            m = float(np.mean(sim.engine.masses))
            if len(_sides(sim.container)) == 3:
                z = float(carnahan_starling(phi)) if phi < 0.55 else 3.0 / (1.0 - phi / 0.74048)
                nu = collision_rate_from_z(z, sigma, kT, m) if sigma > 0 else 0.0
            else:  # disks: Henderson's Z, and Enskog's rate in 2-D (2/3 of the 3-D formula's)
                phi = min(phi, 0.88)
                z = (1.0 + phi * phi / 8.0) / (1.0 - phi) ** 2 if phi < 0.7 else 2.0 / (1.0 - phi / 0.9069)
                nu = collision_rate_from_z(z, sigma, kT, m) * 2.0 / 3.0 if sigma > 0 else 0.0
            if self.step is None:
                self.step = min(0.5 / math.sqrt(n), STEP_SCALE / max(n * (z - 1.0), 1.0))
            if self.every is None:
                free = 1.0 / nu if nu > 0 else sigma / math.sqrt(kT / m) if sigma > 0 else 1.0
                self.every = free / MOVES_PER_FREE_TIME

    def apply(self, sim: HeldSimulation, t: float) -> bool:
        """Try one volume move at ``t`` (the simulation calls this at :attr:`next_time`)."""
        eng = sim.engine
        eng.move_clock(t)
        box = sim.container
        sides = _sides(box)
        rng = self._rng
        axis = -1 if self.axes is None else _AXES.index(self.axes[int(rng.integers(len(self.axes)))])
        step = cast(float, self.step)  # kT, every and step are set when attached
        u = float(rng.uniform(-step, step))
        r = float(rng.random())
        if self.approaching:
            return self._squeeze(sim, eng, t, box, sides)
        self.attempted += 1
        self.next_time = t + cast(float, self.every)
        accepted = self._move(sim, eng, t, box, sides, axis, u, r)
        self._sample(float(sim.container.volume))
        return accepted

    def _squeeze(
        self, sim: HeldSimulation, eng: Engine, t: float, box: Container, sides: tuple[float, ...]
    ) -> bool:
        """One move of the approach: toward :attr:`target`, without overlap (the random draws are kept)."""
        from .core.contacts import closest_ratio

        d = len(sides)
        self.squeezes += 1
        want = (float(sim.packing) / cast(float, self.target)) ** (1.0 / d)  # linear factor to the target
        radii = eng.radii_at()
        bound = 6.0 * float(radii.max()) * (1.0 + 1e-9) / min(sides)  # the engine's least box
        f = want
        if want < 1.0:
            x = eng.positions_at(t)
            ratio = closest_ratio(x, radii, np.array(sides))
            # close APPROACH_GAP_FRACTION of the narrowest gap (ratio - 1 of the contact distance)
            f = max(want, 1.0 / (1.0 + APPROACH_GAP_FRACTION * (ratio - 1.0)), bound)
            # checked as a volume move is (the search above sees every pair nearer than a cell, not
            # always the nearest beyond): halved until no pair overlaps, or skipped
            while f < 1.0 and closest_ratio(x * f, radii, np.array(sides) * f) < 1.0:
                f = 1.0 - 0.5 * (1.0 - f)
                if 1.0 - f < 1e-12:
                    f = 1.0
        if f != 1.0:
            new = [x * f for x in sides]
            new_box = _box_like(box, new)
            eng.rescale_box(new_box, [f] * d)
            sim.container = new_box
        if f == want or f == bound:
            self.approaching = False  # there (or at the engine's least box: no further)
            if self._auto[0]:
                self.step = None
            if self._auto[1]:
                self.every = None
            self._scales(sim)  # the Metropolis moves' step and interval at the packing reached
        self.next_time = t + self._interval()
        return f != 1.0

    def _move(
        self,
        sim: HeldSimulation,
        eng: Engine,
        t: float,
        box: Container,
        sides: tuple[float, ...],
        axis: int,
        u: float,
        r: float,
    ) -> bool:
        d = len(sides)
        if axis < 0:
            factors = [math.exp(u / d)] * d
        else:
            factors = [1.0] * d
            factors[axis] = math.exp(u)
        new = [x * f for x, f in zip(sides, factors)]
        radii = eng.radii_at()
        if min(new) < 6.0 * float(radii.max()) * (1.0 + 1e-9):
            return False  # outside the engine's boxes (three times the largest diameter a side)
        v_old = math.prod(sides)
        v_new = math.prod(new)
        log_acc = -self.pressure * (v_new - v_old) / cast(float, self.kT) + (sim.n + 1) * math.log(
            v_new / v_old
        )
        if log_acc < 0.0 and not r < math.exp(log_acc):
            return False
        if min(factors) < 1.0:
            from .core.contacts import closest_ratio

            x = eng.positions_at(t) * np.array(factors)
            if closest_ratio(x, radii, np.array(new)) < 1.0:
                self.overlaps += 1
                return False
        new_box = _box_like(box, new)
        eng.rescale_box(new_box, factors)
        sim.container = new_box
        self.accepted += 1
        return True

    def state(self) -> str:
        """JSON text from which :func:`barostat_from_state` rebuilds it exactly."""
        return json.dumps(
            {
                "kind": "mc-volume",
                "pressure": self.pressure,
                "kT": self.kT,
                "every": self.every,
                "step": self.step,
                "axes": self.axes,
                "seed": self.seed,
                "approach": [self.approach, self.target, self.approaching, self.squeezes, *self._auto],
                "next_time": self.next_time,
                "attempted": self.attempted,
                "accepted": self.accepted,
                "overlaps": self.overlaps,
                "samples": self.samples,
                "sums": self._sums,
                "blocks": [self._blocks, self._block, self._filling],
                "v0": self._v0,
                "rng": self._rng.bit_generator.state,
            }
        )


def barostat_from_state(text: str) -> Barostat:
    """The barostat :meth:`Barostat.state` saved."""
    d = json.loads(text)
    if d.get("kind") != "mc-volume":
        raise BarostatError(f"unknown barostat {d.get('kind')!r}")
    b = Barostat(d["pressure"], d["kT"], d["every"], d["step"], d["axes"], d["seed"])
    b._rng.bit_generator.state = d["rng"]
    if "approach" in d:  # (checkpoints before the approach: none)
        a = d["approach"]
        b.approach, b.target, b.approaching, b.squeezes = bool(a[0]), a[1], bool(a[2]), int(a[3])
        b._auto = (bool(a[4]), bool(a[5]))
    b.next_time = d["next_time"]
    b.attempted, b.accepted, b.overlaps = int(d["attempted"]), int(d["accepted"]), int(d["overlaps"])
    b.samples = int(d.get("samples", 0))  # (checkpoints before the averages: none)
    b._sums = [float(x) for x in d.get("sums", [0.0, 0.0, 0.0])]
    if "blocks" in d:  # (checkpoints before the trend: it starts afresh)
        blocks, size, filling = d["blocks"]
        b._blocks, b._block, b._filling = (
            [float(x) for x in blocks],
            int(size),
            [float(filling[0]), int(filling[1])],
        )
    b._v0 = None if d.get("v0") is None else float(d["v0"])
    return b


def _eos_packing(sim: HeldSimulation, pressure: float, kT: float | None) -> float | None:
    """The fluid's packing at ``pressure`` by the equation of state (equal sizes only; else ``None``).

    Hansen-Goos (spheres, packings up to 0.55) or Kolafa-Rottner (disks, up
    to 0.70): ``None`` outside, or for a mixture.
    """
    from .eos import hansen_goos, kolafa_rottner, packing_at_pressure

    radii = sim.engine.radii_at()
    if kT is None or len(radii) == 0 or float(radii.min()) != float(radii.max()) or radii[0] <= 0:
        return None
    d = len(_sides(sim.container))
    sigma = 2.0 * float(radii[0])
    reduced = pressure * sigma**d / kT
    eos, top = (hansen_goos, 0.55) if d == 3 else (kolafa_rottner, 0.70)
    try:
        return packing_at_pressure(reduced, eos, bounds=(0.0, top), dimensions=d)
    except ValueError:
        return None  # beyond the fluid's range: no approach


def _positive(x: float, what: str) -> float:
    try:
        v = float(x)
    except (TypeError, ValueError):
        v = math.nan
    if isinstance(x, bool) or not (math.isfinite(v) and v > 0):
        raise BarostatError(f"{what} must be a finite number > 0, got {x!r}")
    return v

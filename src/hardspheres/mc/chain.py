"""EventChain: straight event-chain Monte Carlo of hard spheres and disks.

Event-chain Monte Carlo (ECMC; Bernard, Krauth and Wilson, PRE 80, 056704
(2009); Bernard and Krauth, PRL 107, 155704 (2011)) samples the equilibrium
distribution without a global calendar: one sphere moves at a time, exactly
to its next contact, and the motion passes to the sphere it touches.  It is
the field's fastest sampler of dense disks (Li et al., J. Chem. Phys. 157,
234111 (2022)) and faster than event-driven dynamics at equilibrating dense
spheres (Isobe and Krauth, J. Chem. Phys. 143, 084509 (2015)).

:class:`EventChain` takes the state and container a
:class:`~hardspheres.Simulation` takes, runs chains in the compiled core
(:mod:`hardspheres.mc._core`), calls the same writers (GSD and XYZ frames at
chain ends), measures the pressure per axis with blocking errors
(:class:`~hardspheres.mc.observables.ChainObservables`), saves checkpoints
that resume bit for bit, and hands its state to the event core and back
(:meth:`EventChain.to_simulation`, :meth:`EventChain.from_simulation`).

Its clock, :attr:`EventChain.time`, counts chains: frames fall at chain ends
(a fixed amount of Monte Carlo time), never at lifting events, whose
configurations always hold a touching pair and so are not samples of the
equilibrium distribution.

Example:
    >>> import hardspheres as hs
    >>> box = hs.PeriodicBox((12.0, 12.0))
    >>> chain = hs.EventChain(hs.random_spheres(64, 0.5, box, seed=1), box, seed=1)
    >>> chain.run(chains=100).time, chain.counters["chains"]
    (100.0, 100)
    >>> sim = chain.to_simulation(kT=1.0, seed=2)   # on to the dynamics
    >>> back = hs.EventChain.from_simulation(sim.run(collisions=500))
    >>> back.n
    64
"""

from __future__ import annotations

import math
import os
from typing import TYPE_CHECKING, Any, cast

import numpy as np

from ..containers import TOUCH_TOL, Container, PeriodicBox, as_container, from_record
from ..errors import (
    ArgumentError,
    BoxShapeError,
    CheckpointError,
    PeriodicBoxRequired,
    ScenarioError,
)
from ..fileio import atomic_write
from ..state import State
from . import _core as core
from .observables import ChainObservables

if TYPE_CHECKING:
    from ..simulation import Simulation
    from ..writers import SimulationView, Writer

#: The default chain length over ``V^(1/d)``, as in Li et al.'s straight ECMC
#: (github jellyfysh/HistoricDisks, ``CPP/StraightECMC``), which moves each chain
#: ``3.125 sqrt(N) lambda_0`` with ``lambda_0 = 0.0768 / sqrt(N)`` in a box of
#: unit area, that is 0.24 of the side of a square box.
CHAIN_FRACTION = 0.24

#: Each variant's name and its number in the compiled core.  Straight chains along the axes in turn
#: (Bernard, Krauth and Wilson 2009; Li et al. 2022's StraightECMC), Newtonian chains (Klement and
#: Engel, J. Chem. Phys. 150, 174108 (2019)) and forward chains (Michel, Durmus and Senecal, J.
#: Comput. Graph. Stat. 29, 689 (2020)).
VARIANTS = {"straight": core.STRAIGHT, "newtonian": core.NEWTONIAN, "forward": core.FORWARD}

#: The ``format`` array of an event-chain checkpoint, and its version.
FORMAT = "hardspheres-ecmc-checkpoint"
VERSION = 1

#: Lifts per call of the compiled core at most: a stop request is seen within one.
_CHUNK = 1 << 20
#: Rows of running totals the core may write per call.
_ROWS = 4096


class EventChain:
    """Hard spheres (or disks) sampled by event-chain Monte Carlo: straight, Newtonian or forward chains.

    Args:
        state: the spheres at the start (:class:`hardspheres.State`):
            their positions and radii (any radii: polydisperse); masses and
            names are kept, velocities are not used.
        container: a :class:`~hardspheres.PeriodicBox`, square or
            rectangular, 2-D or 3-D, each side at least three times the largest
            diameter (the cells).
        chain_length: distance each chain moves [length] (default
            :data:`CHAIN_FRACTION` ``V^(1/d)``, Li et al.'s choice).
        kT: the temperature [energy]: pressures are ``kT beta P``, and
            :meth:`to_simulation` draws velocities at it.
        seed: seed of the random choice of each chain's first sphere (and
            of the directions and velocities of the other variants).
        variant: ``"straight"`` (the default: each chain along +x, +y
            (+z) in turn), ``"newtonian"`` (each chain starts one sphere
            at random with a Maxwell-Boltzmann velocity of mean square
            speed 1, every sphere's velocity drawn afresh per chain; a
            lift is an elastic collision of equal masses, and the sphere
            hit moves on with its new velocity; the chain length is a
            time) or ``"forward"`` (a direction at random per chain; at a
            lift the sphere hit moves on along a direction whose part
            across the contact is kept and whose part along it is drawn
            afresh).  Every variant is exact and measures the pressure
            (docs/numerics.md).

    Attributes:
        container: the box.
        names: the spheres' names.
        observables: :class:`~hardspheres.mc.observables.ChainObservables`,
            the pressure since its last ``reset()``.
        writers: frame writers (:class:`hardspheres.GSDWriter`,
            :class:`hardspheres.XYZWriter`), their ``every`` in chains.

    Raises:
        PeriodicBoxRequired: a spherical or circular container.
        BoxShapeError: a box side shorter than three times the largest diameter.
        ScenarioError: overlapping spheres, or a state of another dimension.
        ArgumentError: a chain length or kT that is not a finite number > 0,
            or an unknown variant.
    """

    #: Set to end the current run at its next chunk of events.
    stop_requested: bool = False

    def __init__(
        self,
        state: State,
        container: Container | float,
        chain_length: float | None = None,
        kT: float = 1.0,  # noqa: N803 (the physicists' name)
        seed: int = 0,
        variant: str = "straight",
    ) -> None:
        if variant not in VARIANTS:
            raise ArgumentError(
                f"variant {variant!r} is not an event-chain variant; choose one of {', '.join(VARIANTS)}"
            )
        container = _periodic(as_container(container))
        state.check()
        d = container.dimensions
        if state.dimensions != d:
            raise ScenarioError(
                f"a state of {state.dimensions}-D positions in a {d}-D box; give positions with {d} columns"
            )
        if state.n == 0:
            raise ScenarioError("no spheres: event chains need at least one")
        self.container: PeriodicBox = container
        self.names = list(state.names)
        self.masses = np.asarray(state.masses, dtype=np.float64).copy()
        self.kT = _positive(kT, "kT", "[energy]")
        self.writers: list[Writer] = []
        self.stop_requested = False
        self._run_end = math.inf
        n = state.n
        self._radii = np.ascontiguousarray(state.radii, dtype=np.float64)
        self._pos = np.ascontiguousarray(container.wrap(state.positions), dtype=np.float64)
        images = container.image_counts(state.positions)
        if state.images is not None:
            images = images + np.asarray(state.images, dtype=np.int64).reshape(images.shape)
        self._images = np.ascontiguousarray(images, dtype=np.int64)
        self._ints = np.zeros(core.N_INTS, np.int64)
        self._ints[core.I_ACTIVE] = -1
        self._floats = np.zeros(core.N_FLOATS)
        default = CHAIN_FRACTION * container.volume ** (1.0 / d)
        self._floats[core.F_LENGTH] = (
            default if chain_length is None else _positive(chain_length, "chain_length", "[length]")
        )
        self._tally = np.zeros((4, d))
        self._rng = np.array([_seed_word(seed)], dtype=np.uint64)
        self.variant = variant
        self._vel = np.zeros((n, d))  # Newtonian: velocities; forward: the active sphere's direction
        self._stamp = np.full(n, -1, np.int64)  # Newtonian: the chain each velocity was drawn for
        self._cells()
        if n > 1:
            worst = self._max_overlap()
            if worst > TOUCH_TOL:
                raise ScenarioError(
                    f"spheres overlap by up to {worst:.3g} of their contact distance; move them apart"
                )
        self.observables = ChainObservables(self)

    # ---- the cells -------------------------------------------------------------
    def _cells(self, capacity: int = 0) -> None:
        """Size the grid (at least 3 cells per axis, each a largest diameter wide) and fill it."""
        c = self.container
        d = c.dimensions
        sides = np.array(c.sides[:d], dtype=np.float64)
        rmax = float(self._radii.max())
        widest = 2.0 * rmax * (1.0 + 1e-9)  # the largest contact distance, and a margin for rounding
        if widest > 0 and np.any(sides < 3.0 * widest):
            a = int(np.argmin(sides))
            raise BoxShapeError(
                f"box side L{'xyz'[a]} = {sides[a]:g} is shorter than three times the largest diameter "
                f"({3 * 2 * rmax:g}); use a larger box"
            )
        base = widest if widest > 0 else (c.volume / self.n) ** (1.0 / d)
        ncell = np.maximum(3, np.floor(sides / base)).astype(np.int64)
        limit = 4 * self.n + 27  # no more cells than this: a dilute gas needs no fine grid
        for _ in range(8):  # (coarser cells are still at least ``widest`` wide)
            if int(np.prod(ncell)) <= limit:
                break
            ncell = np.maximum(3, np.floor(ncell * (limit / np.prod(ncell)) ** (1.0 / d))).astype(np.int64)
        self._sides = sides
        self._ncell = ncell
        self._scale = ncell / sides  # (one division, kept: every cell index multiplies by it)
        total = int(np.prod(ncell))
        self._cell = np.zeros(self.n, np.int64)
        self._slot = np.zeros(self.n, np.int64)
        cap = max(capacity, 15)  # a cell's count and 15 spheres: one 64-byte line
        while True:
            self._members = np.zeros((total, 1 + cap), np.int32)
            most = core.build_cells(
                self._pos, sides, self._scale, ncell, self._members, self._cell, self._slot, self._axes
            )
            if most <= cap:
                return
            cap = 2 * most

    @property
    def _axes(self) -> tuple:
        return ((),) * self.container.dimensions

    def _max_overlap(self) -> float:
        return float(
            core.max_overlap(
                self._pos, self._radii, self._sides, self._scale, self._ncell, self._members, self._axes
            )
        )

    # ---- what writers and observables read ----------------------------------------
    @property
    def n(self) -> int:
        """Number of spheres."""
        return int(self._radii.shape[0])

    @property
    def chain_length(self) -> float:
        """Distance each chain moves [length]."""
        return float(self._floats[core.F_LENGTH])

    @property
    def time(self) -> float:
        """Chains done, the Monte Carlo clock (whole at chain ends, a fraction in between)."""
        done = float(self._ints[core.I_CHAINS])
        if self._ints[core.I_ACTIVE] >= 0:
            done += 1.0 - float(self._floats[core.F_LEFT]) / self.chain_length
        return done

    @property
    def counters(self) -> dict[str, int]:
        """Lifting events (also under ``"collisions"``, the name writers read) and chains done."""
        events = int(self._ints[core.I_EVENTS])
        return {"events": events, "chains": int(self._ints[core.I_CHAINS]), "collisions": events}

    @property
    def run_end(self) -> float:
        """Where the current run was asked to end [chains] (``inf`` when it ends by a count of events)."""
        return self._run_end

    def totals(self) -> np.ndarray:
        """The running totals now: events, chains, lift sums (d), chain displacements (d)."""
        t = self._tally
        return np.concatenate(
            [self._ints[[core.I_EVENTS, core.I_CHAINS]].astype(np.float64), t[0] + t[1], t[2] + t[3]]
        )

    def state(self, time: float | None = None, unwrapped: bool = False) -> State:
        """The spheres now as a :class:`State` (velocities zero: Monte Carlo has none).

        Args:
            time: must be the clock (:attr:`time`) if given: the past is not kept.
            unwrapped: positions not wrapped into the box.
        """
        if time is not None and time != self.time:
            raise ArgumentError(f"time {time!r} is not the chain's clock ({self.time!r}); states are of now")
        sides = self._sides
        pos = self._pos + self._images * sides if unwrapped else self._pos.copy()
        return State(
            self.masses.copy(),
            self._radii.copy(),
            pos,
            np.zeros_like(self._pos),
            list(self.names),
            self.time,
            self._images.copy(),
        )

    # ---- running -----------------------------------------------------------------
    def run(self, chains: int | None = None, events: int | None = None, brute: bool = False) -> EventChain:
        """Run so many chains, or so many lifting events, whichever first.

        Writers in :attr:`writers` are attached as the run starts and write
        a frame at the first chain end at or after each of their
        ``next_time`` [chains].  A chain in progress when the events run
        out is finished by the next run.

        Args:
            chains: chains to complete.
            events: lifting events to make.
            brute: search every sphere for the next contact instead of the
                cells (the reference the cells are tested against: the same
                bits, O(N) per event).

        Returns:
            self
        """
        if chains is None and events is None:
            raise ArgumentError("give chains or events: the run never ends otherwise")
        chains_left = math.inf if chains is None else _count(chains, "chains")
        events_left = math.inf if events is None else _count(events, "events")
        self._run_end = self.time + chains_left if chains is not None else math.inf
        view = cast("SimulationView", self)
        for w in self.writers:
            w.attach(view)
        rows = np.empty((_ROWS, self.observables.width))
        while chains_left > 0 and events_left > 0 and not self.stop_requested:
            budget = chains_left
            now = self.time
            for w in self.writers:
                if w.next_time < math.inf:
                    budget = min(budget, max(math.ceil(w.next_time - now), 1))
            max_chains = int(min(budget, 1 << 62))
            max_events = int(min(events_left, _CHUNK))
            c0, e0 = self.counters["chains"], self.counters["events"]
            reason, written = self._core(max_events, max_chains, rows, brute)
            self.observables.take(rows[:written])
            chains_left -= self.counters["chains"] - c0
            events_left -= self.counters["events"] - e0
            if reason == core.CELL_FULL:
                self._cells(capacity=2 * (self._members.shape[1] - 1))
            for w in self.writers:
                if w.next_time <= self.time and self._ints[core.I_ACTIVE] < 0:
                    w.write(view, self.time)
        return self

    def _core(self, max_events: int, max_chains: int, rows: np.ndarray, brute: bool) -> tuple[int, int]:
        """One call of the compiled loop of this variant."""
        common = (
            self._pos,
            self._radii,
            self._images,
            self._sides,
            self._scale,
            self._ncell,
            self._members,
            self._cell,
            self._slot,
            self._ints,
            self._floats,
            self._tally,
            self._rng,
        )
        schedule = (max_events, max_chains, self.observables.every, self.observables.origin, rows, brute)
        if self.variant == "straight":
            return core.run(*common, self._axes, *schedule)
        return core.run_free(*common, self._vel, self._stamp, self._axes, VARIANTS[self.variant], *schedule)

    def request_stop(self) -> None:
        """End the current run early, at its next chunk of events (safe from a signal handler)."""
        self.stop_requested = True

    # ---- the other engine --------------------------------------------------------
    def to_simulation(self, kT: float | None = None, seed: int | None = 0, window: float = 0.0) -> Simulation:  # noqa: N803
        """The spheres as a :class:`~hardspheres.Simulation`, velocities drawn at ``kT``.

        Args:
            kT: temperature of the Maxwell-Boltzmann velocities [energy]
                (default: the chain's :attr:`kT`); total momentum zero.
            seed: seed of the velocities.
            window: the simulation's simultaneity window [time].
        """
        from ..maxwell import maxwell_boltzmann
        from ..simulation import Simulation

        kT = self.kT if kT is None else _positive(kT, "kT", "[energy]")
        st = self.state()
        st.velocities = maxwell_boltzmann(
            np.random.default_rng(seed), st.masses, kT, dimensions=self.container.dimensions
        )
        st.time = 0.0
        return Simulation(st, self.container, window=window)

    @classmethod
    def from_simulation(
        cls, sim: Simulation, chain_length: float | None = None, seed: int = 0, variant: str = "straight"
    ) -> EventChain:
        """An event chain from a :class:`~hardspheres.Simulation`'s spheres now, at its kinetic ``kT``."""
        kT = sim.observables.temperature()
        return cls(
            sim.state(),
            sim.container,
            chain_length=chain_length,
            kT=kT if kT > 0 else 1.0,
            seed=seed,
            variant=variant,
        )

    # ---- checkpoints ---------------------------------------------------------------
    def save(self, path: str | os.PathLike, lock: bool = True) -> None:
        """Write a checkpoint; :meth:`load` resumes it bit for bit.

        An ``.npz`` (``format`` :data:`FORMAT`, ``version`` :data:`VERSION`)
        written through :func:`hardspheres.fileio.atomic_write`: a temporary
        in the same folder, renamed, under the file's lock.

        Raises:
            FileInUseError: another writer holds ``path``.
            OSError: naming ``path``.
        """
        arrays = {
            "format": np.array(FORMAT),
            "version": np.array(VERSION),
            "names": np.array(self.names, dtype=str).reshape(-1),
            "container": self.container.record(),
            "masses": self.masses,
            "radii": self._radii,
            "positions": self._pos,
            "images": self._images,
            "ints": self._ints,
            "floats": self._floats,
            "tally": self._tally,
            "rng": self._rng,
            "kT": np.array(self.kT),
            "variant": np.array(self.variant),
            "velocities": self._vel,
            "stamps": self._stamp,
            **self.observables.checkpoint(),
        }
        with atomic_write(path, "wb", lock=lock) as fh:
            np.savez(fh, **arrays)

    @classmethod
    def load(cls, path: str | os.PathLike) -> EventChain:
        """Resume a checkpoint written by :meth:`save`; every array is checked first.

        Raises:
            CheckpointError: not an event-chain checkpoint of this version,
                or truncated or damaged (one line says which).
            OSError: the file cannot be read.
        """
        data = _read(path)
        try:
            container = _periodic(from_record(data["container"]))
            d = container.dimensions
            n = data["radii"].shape[0] if data["radii"].ndim == 1 else -1
            variant = str(data.get("variant", "straight"))
            if variant not in VARIANTS:
                raise CheckpointError(f"unknown variant {variant!r}")
            if data["ints"].shape == (core.N_INTS - 1,):  # written before the cell steps were counted
                data["ints"] = np.append(data["ints"], 0)
            data.setdefault("velocities", np.zeros((n, d)))
            data.setdefault("stamps", np.full(n, -1, np.int64))
            expect = {
                "masses": (np.float64, (n,)),
                "radii": (np.float64, (n,)),
                "positions": (np.float64, (n, d)),
                "images": (np.int64, (n, d)),
                "ints": (np.int64, (core.N_INTS,)),
                "floats": (np.float64, (core.N_FLOATS,)),
                "tally": (np.float64, (4, d)),
                "rng": (np.uint64, (1,)),
                "kT": (np.float64, ()),
                "velocities": (np.float64, (n, d)),
                "stamps": (np.int64, (n,)),
            }
            for key, (dtype, shape) in expect.items():
                a = data[key]
                if a.dtype != dtype or a.shape != shape:
                    raise CheckpointError(f"{key!r} is {a.dtype}{list(a.shape)}, expected {list(shape)}")
                if a.dtype.kind == "f" and not np.all(np.isfinite(a)):
                    raise CheckpointError(f"{key!r} is not finite")
            names = data["names"]
            if names.dtype.kind != "U" or names.shape != (n,) or len(set(names.tolist())) != n:
                raise CheckpointError(f"not {n} distinct names")
            ints = data["ints"]
            if not (-1 <= ints[core.I_ACTIVE] < n and ints[core.I_EVENTS] >= 0 and ints[core.I_CHAINS] >= 0):
                raise CheckpointError("bad chain counters")
            if not data["floats"][core.F_LENGTH] > 0 or not 0 <= data["floats"][core.F_LEFT]:
                raise CheckpointError("bad chain length")
            half = 0.5 * np.array(container.sides[:d])
            if np.any(data["positions"] < -half) or np.any(data["positions"] >= half):
                raise CheckpointError("positions outside the box")
            state = State(data["masses"], data["radii"], data["positions"], np.zeros((n, d)), names.tolist())
            chain = cls(
                state,
                container,
                chain_length=float(data["floats"][core.F_LENGTH]),
                kT=float(data["kT"]),
                variant=variant,
            )
        except (KeyError, IndexError, ValueError, TypeError) as e:
            why = str(e).splitlines()[0] if str(e) else type(e).__name__
            raise CheckpointError(f"{path}: damaged checkpoint: {why}") from None
        chain._images[:] = data["images"]
        chain._ints[:] = data["ints"]
        chain._floats[:] = data["floats"]
        chain._tally[:] = data["tally"]
        chain._rng[:] = data["rng"]
        chain._vel[:] = data["velocities"]
        chain._stamp[:] = data["stamps"]
        chain.observables = ChainObservables(chain)
        chain.observables.restore(data)
        return chain


def _read(path: str | os.PathLike) -> dict[str, np.ndarray]:
    """The arrays of an event-chain checkpoint, its format and version checked (and removed)."""
    import zipfile

    try:
        with np.load(path, allow_pickle=False) as z:
            if not hasattr(z, "files"):
                raise CheckpointError(f"{path}: a bare .npy array, not a checkpoint")
            data = {k: z[k] for k in z.files}
    except (FileNotFoundError, PermissionError, IsADirectoryError):
        raise
    except (OSError, ValueError, EOFError, zipfile.BadZipFile, KeyError, RuntimeError) as e:
        raise CheckpointError(f"{path}: not a checkpoint, or truncated or damaged ({e})") from None
    fmt, version = data.pop("format", None), data.pop("version", None)
    if fmt is None or fmt.shape != () or str(fmt) != FORMAT:
        raise CheckpointError(
            f"{path}: not an event-chain checkpoint (no format {FORMAT!r}); "
            "give a file written by EventChain.save or sample --checkpoint"
        )
    if version is None or version.shape != () or version.dtype.kind not in "iu" or int(version) != VERSION:
        raise CheckpointError(f"{path}: event-chain checkpoint version {version} is not {VERSION}")
    return data


def _periodic(container: Container) -> PeriodicBox:
    if not isinstance(container, PeriodicBox):
        raise PeriodicBoxRequired(
            f"event-chain Monte Carlo needs a periodic box, not a {container.description} "
            "(no lifting rule at a curved wall here); use hs.PeriodicBox"
        )
    return container


def _positive(x: Any, what: str, unit: str) -> float:
    try:
        v = float(x)
    except (TypeError, ValueError):
        v = math.nan
    if not (math.isfinite(v) and v > 0):
        raise ArgumentError(f"{what} must be a finite number > 0 {unit}, got {x!r}")
    return v


def _count(x: Any, what: str) -> int:
    try:
        v = int(x)
        ok = v == x and v >= 0
    except (TypeError, ValueError, OverflowError):
        ok = False
    if not ok:
        raise ArgumentError(f"{what} must be a whole number >= 0, got {x!r}")
    return v


def _seed_word(seed: int) -> np.uint64:
    """The core's 64-bit random state from a seed (numpy's SeedSequence)."""
    try:
        words = np.random.SeedSequence(seed).generate_state(1, np.uint64)
    except (TypeError, ValueError):
        raise ArgumentError(f"seed must be a whole number >= 0, got {seed!r}") from None
    return words[0]


__all__ = ["CHAIN_FRACTION", "VARIANTS", "EventChain"]

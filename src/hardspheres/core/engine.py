"""The engine: owns the arrays of the compiled event core and drives it.

:class:`Engine` is the one place that knows the core's array layout; the
public API (:mod:`hardspheres.simulation`), the assignment's program and the
benchmark all go through it.
"""

from __future__ import annotations

import operator
from collections.abc import Callable, Iterable, Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from .. import events as _events
from ..containers import MAX_PACKING, Container, as_container, from_record, require_periodic
from ..eos import carnahan_starling, collision_rate_from_z
from ..errors import ArgumentError, BoxShapeError, CheckpointError, ShearError  # noqa: F401 (re-exported)
from ..events import StopReason
from ..scenario import StuckError
from ..state import kinetic_energy
from . import _core as core
from . import checkpoint

#: Default number of events the core records per call.
CHUNK = 1 << 14

#: The time origin moves to the clock after this many events per sphere.
REBASE_EVERY = 64
#: The event calendar's buckets are made so wide that about this many
#: entries come due in one (benchmarks/README.md: how it was chosen).
CAL_PER_BUCKET = 2.0

#: Neighbour distance over the sum of two reaches (``_core.F_SHELL``): a sphere
#: may move half a reach from its shell centre before its list is made anew.
SHELL = 1.5

#: Packing fraction from which the core predicts against neighbour lists
#: rather than cells (benchmarks/README.md, "neighbour lists": they pay in
#: dense fluids, where spheres rattle in their cages, and cost at low density,
#: where spheres leave their shells more often than they collide).
LISTS_FROM = 0.35
#: The same for disks (area fraction); an estimate, not measured yet.
LISTS_FROM_2D = 0.5


#: Room to grow while growing: the cells and lists are made for radii this
#: much larger (reach over radius), then made anew.  More room, rarer
#: rebuilds but more pairs per prediction; :meth:`Engine._headroom` balances
#: the two within these bounds.
HEADROOM_MIN, HEADROOM_MAX = 1.002, 1.05


#: Spatial reordering (benchmarks/README.md, "Spatial reordering"): from this
#: many spheres the engine keeps its per-sphere arrays in Morton order of the
#: spheres' places (near in space, near in memory: fewer cache misses where
#: the arrays outgrow the caches), sorted at the build ...
REORDER_FROM = 1 << 13
#: ... and again after this many collisions and reflections per sphere (the
#: spheres diffuse out of their places slowly).
REORDER_EVERY = 10.0

# the core's arrays that the engine shows in the input order under their own
# names (properties): kept in the engine's order under these
_INTERNAL = {"masses": "_masses", "images": "_images"}
#: The dtype of the sphere indices the core links by (cell lists and heads,
#: the calendar's heap and lists, the work space): int32 (N < 2^29: the
#: calendar's slots reach 4N), half the bytes of int64.  The core reads each
#: into an int64 scalar where it loads it (``np.int64(cell_next[j])``), so its
#: helpers are compiled once, for int64 indices, as before (benchmarks/README.md,
#: "Memory: bytes per sphere").  Checkpoints keep them as int64 either way.
LINK = np.int32
_LINKED = ("cell_next", "cell_prev", "cell_head", "heap")


# the dimension as the core takes it: a tuple of d empty tuples, whose length
# numba folds (each d compiles a loop of its own; _core, "the arrays")
_AXES = {2: ((),) * 2, 3: ((),) * 3}
#: ... and in a sheared box: the first axis's entry is ``((),)`` (the core's
#: sheared variant, ``len(axes[0]) == 1``; the dimension is still ``len(axes)``)
_SHEARED_AXES = {2: (((),), ()), 3: (((),), (), ())}
#: ... and with steps (square wells): the second's (``len(axes[1]) == 1``)
_STEPPED_AXES = {2: ((), ((),)), 3: ((), ((),), ())}
#: Entries of a new bond table per sphere (widened on demand, doubling).
BONDS_FIRST = 8


def _core_params(container: Container) -> dict:
    """What the core reads of ``container`` (a sheared box's too: the engine runs Lees-Edwards boundaries)."""
    if getattr(container, "shear_rate", 0.0):
        return container.core_params(shear=True)  # type: ignore[call-arg]
    return container.core_params()


# the collision rule as the core takes it: elastic (), inelastic ((),) (each its own loop)
_RULES = {False: (), True: ((),)}

# the engine's arrays, by name, as the core takes them (one C call)
_core_arrays = operator.attrgetter(*(_INTERNAL.get(k, k) for k in core.ARRAYS))


def _spread_bits(q: np.ndarray) -> np.ndarray:
    """The low 21 bits of each ``q`` (uint64) spread out to every third bit (Morton codes)."""
    q = q & np.uint64(0x1FFFFF)
    for shift, mask in (
        (32, 0x1F00000000FFFF),
        (16, 0x1F0000FF0000FF),
        (8, 0x100F00F00F00F00F),
        (4, 0x10C30C30C30C30C3),
        (2, 0x1249249249249249),
    ):
        q = (q | (q << np.uint64(shift))) & np.uint64(mask)
    return q


class Engine:
    """Exact event-driven dynamics of hard spheres, compiled.

    Args:
        masses: ``(N,)`` [mass], > 0.
        radii: ``(N,)`` [length], >= 0.
        positions: ``(N, 3)`` centres at time 0 [length].
        velocities: ``(N, 3)`` [length/time].
        container: the :class:`~hardspheres.containers.Container`, or the
            radius of a spherical container centred at the origin [length].
        box: instead of ``container``, the edge of a periodic cubic box
            centred at the origin, or its sides ``(Lx, Ly, Lz)`` [length].
        window: simultaneity window [time]: events less than this after the
            last event happen at its time (the assignment uses 1e-8 s; 0
            means exact times).
        time: the time the positions are given at [time].
        rebase: move the time origin forward now and then, for precision
            in long runs (off: the same arithmetic as the reference loop).
        reorder: keep the spheres in Morton order of their places inside,
            sorted at the build and again after this many collisions and
            reflections per sphere; 0: never; ``None`` (default):
            :data:`REORDER_EVERY` from :data:`REORDER_FROM` spheres.  Only
            speed depends on it: every event, every array shown and every
            sphere index (``kick``, event records) is the same, in the input
            order, bit for bit.
        restitution: normal restitution coefficient ``e`` of every pair,
            ``0 < e <= 1`` (1: elastic hard spheres; below 1: a granular gas,
            compiled as the core's inelastic variant, see :meth:`set_restitution`).
        wall_restitution: the container wall's (default: ``restitution``).
        tc: the TC model's duration [time]: a collision or reflection less
            than ``tc`` after either sphere's previous one is elastic (0: off).
        wall_temperature: a thermal wall's temperature ``kT_w`` [energy]: a
            sphere meeting the container's wall leaves it with a velocity
            drawn at ``kT_w`` (a heated container; 0: off, the wall reflects
            with ``wall_restitution``; see :meth:`set_wall_temperature`).
        wall_seed: the thermal wall's generator seed, ``0 <= seed < 2^32``.
        shear_offset: a sheared box's Lees-Edwards offset at ``time``
            [length]: how far along x the images above the box are ahead of
            it (a :class:`~hardspheres.containers.PeriodicBox` with
            ``shear_rate``: the core's sheared variant, cells only).
        steps: a stepped pair potential ``[(lambda_k, U_k), ...]``,
            outermost first (a square well of depth ``eps``: ``[(lambda,
            -eps)]``; at most four steps): each pair ``(i, j)`` has the
            potential energy ``U_k`` inside ``lambda_k (R_i + R_j)`` (and
            outside the next edge), 0 outside every edge.  The core's stepped
            variant (not with shear, restitution below 1 or
            growth); each pair's state starts from the distances, as the
            reference's.  Per pair of species: a dict ``{(s, t): [(lambda_k,
            U_k), ...]}`` (each unordered pair once; left out: hard spheres).
        species: ``(N,)`` each sphere's species ``0..3`` (with a table of
            steps per pair of species).

    Example:
        >>> eng = Engine([1.0, 1.0], [1.0, 1.0], [[-5.0, 0, 0], [5.0, 0, 0]],
        ...              [[1.0, 0, 0], [-1.0, 0, 0]], container=100.0)
        >>> ev = eng.advance(until=10.0)
        >>> ev["time"].tolist(), ev["kind"].tolist()
        ([4.0], [1])
    """

    def __init__(
        self,
        masses: ArrayLike,
        radii: ArrayLike,
        positions: ArrayLike,
        velocities: ArrayLike,
        container: Container | float | None = None,
        box: float | tuple[float, ...] | None = None,
        window: float = 0.0,
        time: float = 0.0,
        rebase: bool = True,
        reorder: float | None = None,
        restitution: float = 1.0,
        wall_restitution: float | None = None,
        tc: float = 0.0,
        wall_temperature: float = 0.0,
        wall_seed: int = 0,
        shear_offset: float = 0.0,
        steps: Any = None,
        species: ArrayLike | None = None,
    ) -> None:
        self.container: Container = as_container(container, box)
        self._masses = np.array(masses, dtype=np.float64).reshape(-1)
        if self._masses.shape[0] >= 2**29:
            raise ArgumentError(f"{self._masses.shape[0]} spheres: the engine takes fewer than 2^29")
        n = self._masses.shape[0]
        d = self.dimensions
        # one 64-byte row per sphere: x y z vx vy vz t_own radius (in 2-D z = vz = 0, never read)
        self.spheres = np.zeros((n, core.SPHERE_COLS))
        self.spheres[:, core.X : core.X + d] = _columns(positions, n, d, "positions")
        self.spheres[:, core.VX : core.VX + d] = _columns(velocities, n, d, "velocities")
        self.spheres[:, core.RADIUS] = np.asarray(radii, dtype=np.float64).reshape(n)
        self.book = np.zeros((n, core.BOOK_COLS), np.int64)
        self.due = np.zeros((n, core.DUE_COLS))
        self.shells = np.zeros((n, core.SHELL_COLS))
        self.neighbours = np.zeros((n, 0), np.int32)  # widened as needed (_build, advance)
        self.cell_next = np.zeros(n, LINK)
        self.cell_prev = np.zeros(n, LINK)
        self.heap = np.zeros(n, LINK)
        self.heap_t = np.zeros(n)
        self.heap_key = np.zeros(n, np.int64)
        self.calendar = np.full(core.calendar_size(n), -1, LINK)  # the buckets' lists
        self.scratch = np.zeros(2 * n + 2, LINK)
        self._images = np.zeros((n, 3), np.int64)  # periodic images (crossings of the box)
        # the engine's order: sphere i here is sphere order[i] of the input
        # (book[:, ORIGIN]; _rank the other way round, None while the two agree)
        self.book[:, core.ORIGIN] = np.arange(n)
        self._rank: np.ndarray | None = None
        if reorder is None:
            reorder = REORDER_EVERY if n >= REORDER_FROM else 0.0
        reorder = float(reorder)
        if not (reorder >= 0.0 and np.isfinite(reorder)):
            raise ArgumentError(
                f"reorder must be a finite number >= 0 (collisions per sphere), got {reorder}"
            )
        self._reorder_every = reorder
        self._since_reorder = 0
        self.scalars = np.zeros(core.N_SCALARS)
        self.counts = np.zeros(core.N_COUNTS, np.int64)
        self.offset = float(time)  # absolute time of the core's time origin
        self.scalars[core.F_OFFSET] = self.offset  # the core's copy (rebase keeps it)
        self.scalars[core.F_WINDOW] = window
        self.hit_t = np.zeros(0)
        self.set_restitution(restitution, wall_restitution, tc)
        self.set_wall_temperature(wall_temperature, wall_seed)
        self._set_steps(steps, species)
        self._grid(n)
        self._set_shear(shear_offset)
        self._into_box()
        self._event_buffers = _events.empty_buffers(CHUNK)
        self._since_rebase = 0
        self._rebase_on = rebase
        self.last_reason, self.last_done = StopReason.UNTIL, 0
        if self._reorder_every and n > 1:
            self._permute(self._morton(self._inside_at(0.0)), built=False)
        if self.scalars[core.F_NSTEP]:
            self._bond_from_distances()
        self._build()

    @property
    def n(self) -> int:
        """Number of spheres."""
        return self._masses.shape[0]

    @property
    def dimensions(self) -> int:
        """The dimension of space, ``d`` (the container's): 2 or 3."""
        return int(getattr(self.container, "dimensions", 3))

    @property
    def axes(self) -> tuple[tuple[()], ...]:
        """The dimension as the compiled core takes it: ``d`` empty tuples (the first ``((),)``: sheared)."""
        if self.scalars[core.F_SHEAR] != 0.0:
            return _SHEARED_AXES[self.dimensions]  # type: ignore[return-value]
        if self.scalars[core.F_NSTEP] != 0.0:
            return _STEPPED_AXES[self.dimensions]  # type: ignore[return-value]
        return _AXES[self.dimensions]

    # ---- steps (square wells) ---------------------------------------------------
    def _set_steps(self, steps: Any, species: ArrayLike | None) -> None:
        """The stepped potential into the scalars, the species and bond tables into the book (none: none)."""
        if steps is None or len(steps) == 0:
            if species is not None:
                raise ArgumentError("species are for the steps' table: give steps too")
            return
        from .reference import step_table

        table = step_table(steps)
        n = self.n
        if species is None:
            if len(table) > 1 or (0, 0) not in table:
                raise ArgumentError("steps per pair of species: give each sphere's species too")
            kinds = np.zeros(n, np.int64)
        else:
            kinds = np.asarray(species).reshape(-1)
            if kinds.shape[0] != n or kinds.dtype.kind not in "iu" or (n and kinds.min() < 0):
                raise ArgumentError(f"species: give one integer >= 0 per sphere ({n})")
            kinds = kinds.astype(np.int64)
        n_species = max(int(kinds.max()) if n else 0, *(s for s, _ in table)) + 1
        if n_species > core.SPECIES_MAX:
            raise ArgumentError(f"{n_species} species: the engine takes at most {core.SPECIES_MAX}")
        most = max(len(lams) for lams, _ in table.values())
        if most > core.STEP_MAX:
            raise ArgumentError(f"{most} steps: the engine takes at most {core.STEP_MAX}")
        if not most:
            return  # (steps for no pair: hard spheres)
        if getattr(self.container, "shear_rate", 0.0):
            raise ShearError("steps in a sheared box are not built yet: give shear_rate=0 or no steps")
        if self.inelastic:
            raise ArgumentError("steps with restitution below 1 are not built yet: give restitution=1")
        outer = max(lams[0] for lams, _ in table.values() if lams)
        edges = self._edges_of_container()
        if edges and n:
            reach = outer * 2.0 * float(np.max(self.spheres[:, core.RADIUS]))
            side = min(edges)
            if not reach < 0.5 * side:
                raise BoxShapeError(
                    f"the outermost step reaches {reach:g}, not less than half the box's side {side:g}: "
                    "give a larger box or a narrower step"
                )
        f = self.scalars
        f[core.F_NSTEP], f[core.F_NSPECIES] = most, n_species
        for (s, t), (lams, us) in table.items():
            base = core.F_STEP + (s * core.SPECIES_MAX + t) * core.STEP_STRIDE
            f[base] = len(lams)
            for k, (lam, u) in enumerate(zip(lams, us)):
                f[base + 1 + 2 * k], f[base + 2 + 2 * k] = lam, u
        self.book = np.concatenate([self.book, np.zeros((n, 2 + BONDS_FIRST), np.int64)], axis=1)
        self.book[:, core.SPECIES] = kinds

    def _edges_of_container(self) -> list[float]:
        """The periodic box's sides (empty: a container with a wall)."""
        params = _core_params(self.container)
        return [float(e) for e in params["edges"] if e] if not params["wall_radius"] else []

    def _pair_steps(self, s: int, t: int) -> tuple[tuple[float, float], ...]:
        """The steps ``((lambda_k, U_k), ...)`` of species ``s`` and ``t``."""
        f = self.scalars
        base = core.F_STEP + (s * core.SPECIES_MAX + t) * core.STEP_STRIDE
        return tuple((float(f[base + 1 + 2 * k]), float(f[base + 2 + 2 * k])) for k in range(int(f[base])))

    @property
    def steps(self) -> tuple[tuple[float, float], ...]:
        """The stepped pair potential ``((lambda_k, U_k), ...)`` of species 0 with itself, outermost first."""
        return self._pair_steps(0, 0) if self.scalars[core.F_NSTEP] else ()

    @property
    def step_table(self) -> dict[tuple[int, int], tuple[tuple[float, float], ...]]:
        """The steps of every pair of species ``{(s, t): ((lambda_k, U_k), ...)}`` (empty: hard spheres)."""
        m = int(self.scalars[core.F_NSPECIES]) if self.scalars[core.F_NSTEP] else 0
        return {(s, t): self._pair_steps(s, t) for s in range(m) for t in range(m)}

    @property
    def species(self) -> np.ndarray:
        """``(N,)`` each sphere's species, in the input order (zeros without steps)."""
        if not self.scalars[core.F_NSTEP]:
            return np.zeros(self.n, np.int64)
        return self._shown(self.book[:, core.SPECIES])

    def _bond_from_distances(self) -> None:
        """Each pair's state from the distances now (the reference's ``step_state``, the same arithmetic)."""
        n = self.n
        x = self.spheres[:, core.X : core.X + 3]
        r = self.spheres[:, core.RADIUS]
        kinds = self.book[:, core.SPECIES]
        edges = self._edges[:3]
        width = self.book.shape[1] - core.BONDS - 1
        rows: list[list[int]] = [[] for _ in range(n)]
        tables = {(s, t): [lam for lam, _ in steps] for (s, t), steps in self.step_table.items()}
        for i in range(n - 1):
            d2 = np.zeros(n - 1 - i)
            for ax in range(3):
                dx = x[i, ax] - x[i + 1 :, ax]
                if edges[ax]:
                    dx = dx - edges[ax] * np.round(dx / edges[ax])
                d2 = d2 + dx * dx
            sigma = r[i] + r[i + 1 :]
            state = np.zeros(n - 1 - i, np.int64)
            others = kinds[i + 1 :]
            for t in np.unique(others).tolist():
                mine = others == t
                for lam in tables[(int(kinds[i]), t)]:
                    edge = lam * sigma[mine]
                    state[mine] += d2[mine] < edge * edge
            for q in np.nonzero(state)[0]:
                j, st = i + 1 + int(q), int(state[q])
                rows[i].append((j << 3) | st)
                rows[j].append((i << 3) | st)
        longest = max((len(row) for row in rows), default=0)
        if longest > width:
            extra = max(longest - width, width)
            self.book = np.concatenate([self.book, np.zeros((n, extra), np.int64)], axis=1)
        self.book[:, core.BONDS :] = 0
        for i, row in enumerate(rows):
            self.book[i, core.BONDS] = len(row)
            self.book[i, core.BONDS + 1 : core.BONDS + 1 + len(row)] = row

    def _widen_bonds(self) -> None:
        """Twice as many entries per bond table (the tables stay as they are)."""
        width = self.book.shape[1] - core.BONDS - 1
        self.book = np.concatenate([self.book, np.zeros((self.n, width), np.int64)], axis=1)

    def _bonds(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Every bond once: ``(a, b, state)`` in engine indices, ``a < b``."""
        width = self.book.shape[1] - core.BONDS - 1
        count = self.book[:, core.BONDS]
        held = np.arange(width)[None, :] < count[:, None]
        entries = self.book[:, core.BONDS + 1 :][held]
        a = np.repeat(np.arange(self.n), count)
        b, state = entries >> 3, entries & 7
        once = a < b
        return a[once], b[once], state[once]

    def potential_energy(self) -> float:
        """The stepped potential's energy now [mass*length^2/time^2] (0 for hard spheres).

        Formed afresh from the count of pairs in each step of each pair of
        species, in a fixed order (the reference's): it cannot drift.
        """
        if not self.scalars[core.F_NSTEP]:
            return 0.0
        a, b, state = self._bonds()
        kinds = self.book[:, core.SPECIES]
        sa, sb = kinds[a], kinds[b]
        lo, hi = np.minimum(sa, sb), np.maximum(sa, sb)
        m = int(self.scalars[core.F_NSPECIES])
        counts = np.bincount((lo * m + hi) * core.STEP_MAX + state - 1, minlength=m * m * core.STEP_MAX)
        u = 0.0
        for s in range(m):
            for t in range(s, m):
                for k, (_, energy) in enumerate(self._pair_steps(s, t)):
                    u += int(counts[(s * m + t) * core.STEP_MAX + k]) * energy
        return u

    @property
    def pair_states(self) -> dict[tuple[int, int], int]:
        """Each pair ``(i, j)`` of input indices, ``i < j``, in a step, and its state (edges it is inside)."""
        out: dict[tuple[int, int], int] = {}
        order = self.order
        for a, b, st in zip(*(x.tolist() for x in self._bonds())):
            i, j = int(order[a]), int(order[b])
            out[(min(i, j), max(i, j))] = st
        return out

    def _set_shear(self, offset: float) -> None:
        """A sheared box's boundary speed and offset at the time origin (``offset`` now) [length]."""
        rate = float(getattr(self.container, "shear_rate", 0.0))
        if not rate:
            return
        offset = float(offset)
        if not np.isfinite(offset):
            raise ShearError(f"shear offset {offset!r}: give a finite length")
        lx, ly = self._edges[0], self._edges[1]
        self.scalars[core.F_SHEAR] = rate * ly
        self.scalars[core.F_SHEAR_G] = rate
        self.scalars[core.F_SHEAR0] = (offset + self.scalars[core.F_SHEAR] * 0.0) % lx

    @property
    def shear_rate(self) -> float:
        """The shear rate ``g`` of a sheared box [1/time]; 0 when not sheared."""
        return float(getattr(self.container, "shear_rate", 0.0))

    def shear_offset(self, t: float | None = None) -> float:
        """A sheared box's Lees-Edwards offset at absolute time ``t`` (default: now) [length] (0: unsheared).

        How far along x the images above the box are ahead of it:
        ``(offset0 + g L_y (t - origin)) mod L_x``, the core's arithmetic.
        """
        f = self.scalars
        if f[core.F_SHEAR] == 0.0:
            return 0.0
        t = (self.time if t is None else t) - self.offset
        return float((f[core.F_SHEAR0] + f[core.F_SHEAR] * t) % f[core.F_EDGE])

    @property
    def rule(self) -> tuple[tuple[()], ...]:
        """The collision rule as the compiled core takes it: ``()`` elastic, ``((),)`` inelastic."""
        return _RULES[bool(self.hit_t.shape[0]) or (self.inelastic and self.n == 0)]

    @property
    def inelastic(self) -> bool:
        """Whether the kinetic energy changes at events: a restitution below 1 or a thermal wall."""
        f = self.scalars
        return bool(
            f[core.F_RESTITUTION] != 1.0 or f[core.F_WALL_RESTITUTION] != 1.0 or f[core.F_WALL_KT] > 0.0
        )

    @property
    def wall_temperature(self) -> float:
        """The thermal wall's temperature ``kT_w`` [energy]; 0 when not a thermal wall."""
        return float(self.scalars[core.F_WALL_KT])

    @property
    def wall_heat(self) -> float:
        """Kinetic energy the thermal wall gave the spheres so far [energy]; negative if it took."""
        return float(self.scalars[core.F_WALL_HEAT])

    def set_wall_temperature(self, kt: float = 0.0, seed: int | None = None) -> None:
        """A thermal wall at temperature ``kt`` from now (0: the wall reflects again).

        A sphere meeting the wall is re-emitted with the normal speed drawn
        from the flux-weighted distribution and the tangential velocity from
        the Maxwellian at ``kt`` (:func:`hardspheres.physics.thermal_wall`):
        the wall of a heated container (Grossman, Zhou and Ben-Naim, Phys.
        Rev. E 55, 4200 (1997)).  Compiled in the core's inelastic variant.
        The draws come from a counter-based generator: ``seed`` and the
        number of draws made are all its state (checkpoints carry both).

        Args:
            kt: the wall's temperature [energy], finite, ``>= 0``.
            seed: the generator's seed, ``0 <= seed < 2^32`` (``None``: keep
                the current seed and count of draws).

        Raises:
            ArgumentError: a negative or infinite ``kt``, a seed out of range,
                a thermal wall without a wall (a periodic box), or while the
                radii grow.

        Example:
            >>> eng = Engine([1.0], [1.0], [[0.0, 0, 0]], [[1.0, 0, 0]], container=5.0,
            ...              wall_temperature=2.0, wall_seed=7)
            >>> _ = eng.advance(until=100.0)
            >>> eng.counters["reflections"] > 10 and eng.wall_heat != 0.0
            True
        """
        kt = float(kt)
        if not (kt >= 0.0 and np.isfinite(kt)):
            raise ArgumentError(f"wall temperature must be a finite energy >= 0 (0: off), got {kt}")
        if kt > 0.0 and not self.container.wall_area > 0:
            raise ArgumentError("a wall temperature needs a wall: use a spherical or circular container")
        if kt > 0.0 and self.scalars[core.F_NSTEP]:
            raise ArgumentError(
                "a thermal wall with steps (square wells) is not built yet: give no wall temperature"
            )
        if kt > 0.0 and self.scalars[core.F_GROW]:
            raise ArgumentError("a thermal wall while the radii grow: stop the growth first")
        if seed is not None:
            if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or not 0 <= seed < 2**32:
                raise ArgumentError(f"wall seed must be an integer in [0, 2^32), got {seed!r}")
            self.counts[core.C_WALL_SEED] = int(seed)
            self.counts[core.C_WALL_DRAWS] = 0
        self.scalars[core.F_WALL_KT] = kt
        self._set_hit_t()

    @property
    def restitution(self) -> float:
        """Normal restitution coefficient between spheres (1: elastic)."""
        return float(self.scalars[core.F_RESTITUTION])

    @property
    def wall_restitution(self) -> float:
        """Normal restitution coefficient at the container's wall (1: elastic)."""
        return float(self.scalars[core.F_WALL_RESTITUTION])

    @property
    def tc(self) -> float:
        """The TC model's duration [time] (0: off)."""
        return float(self.scalars[core.F_TC])

    @property
    def dissipated(self) -> float:
        """Kinetic energy dissipated by inelastic collisions and reflections so far [mass*length^2/time^2]."""
        return float(self.scalars[core.F_DISSIPATED])

    def set_restitution(self, restitution: float = 1.0, wall: float | None = None, tc: float = 0.0) -> None:
        """The collision rule from now: restitution between spheres, at the ``wall``, the TC model's ``tc``.

        ``wall`` defaults to ``restitution``.  With both 1 the core runs its
        elastic loop (the bits of elastic hard spheres); below 1 its inelastic
        one, which keeps each sphere's time of its last collision or
        reflection (for the TC model; from now, none yet).  Predictions do not
        depend on the rule, so nothing is predicted again.

        Raises:
            ArgumentError: a coefficient outside ``(0, 1]``, a negative or
                infinite ``tc``, or inelastic while the radii grow.
        """
        e = float(restitution)
        ew = e if wall is None else float(wall)
        tc = float(tc)
        for name, value in (("restitution", e), ("wall restitution", ew)):
            if not 0.0 < value <= 1.0:
                raise ArgumentError(f"{name} must be in (0, 1] (1: elastic), got {value}")
        if not (tc >= 0.0 and np.isfinite(tc)):
            raise ArgumentError(f"tc must be a finite time >= 0 (0: no TC model), got {tc}")
        inelastic = e != 1.0 or ew != 1.0
        if inelastic and self.scalars[core.F_NSTEP]:
            raise ArgumentError("steps with restitution below 1 are not built yet: give restitution=1")
        if inelastic and self.scalars[core.F_GROW]:
            raise ArgumentError("restitution below 1 while the radii grow: stop the growth first")
        f = self.scalars
        f[core.F_RESTITUTION], f[core.F_WALL_RESTITUTION], f[core.F_TC] = e, ew, tc
        self._set_hit_t()

    def _set_hit_t(self) -> None:
        """Each sphere's last collision (the inelastic variant's array), kept, made or dropped."""
        if not self.inelastic:
            self.hit_t = np.zeros(0)
        elif self.hit_t.shape[0] != self.n:
            self.hit_t = np.full(self.n, -np.inf)

    @property
    def order(self) -> np.ndarray:
        """``(N,)`` int64: the input index of the engine's sphere ``i`` (a view: do not write)."""
        return self.book[:, core.ORIGIN]

    def _set_rank(self) -> None:
        """The input order's sphere ``k`` is the engine's ``_rank[k]`` (None: the same order)."""
        n = self.n
        order = self.order
        if np.array_equal(order, np.arange(n)):
            self._rank = None
        else:
            self._rank = np.empty(n, np.int64)
            self._rank[order] = np.arange(n)

    def _shown(self, a: np.ndarray) -> np.ndarray:
        """A per-sphere array of the engine's order in the input order (itself while they agree)."""
        return a if self._rank is None else a[self._rank]

    @property
    def masses(self) -> np.ndarray:
        """``(N,)`` masses [mass] (do not write)."""
        return self._shown(self._masses)

    @property
    def images(self) -> np.ndarray:
        """``(N, d)`` int64: each sphere's crossings of the periodic box per axis (a copy to write back)."""
        d = self.dimensions
        return self._shown(self._images if d == 3 else self._images[:, :d])

    @images.setter
    def images(self, value: ArrayLike) -> None:
        d = self.dimensions
        self._images[:, :d] = np.asarray(value, dtype=np.int64).reshape(-1, d)[self.order]

    @property
    def velocities(self) -> np.ndarray:
        """``(N, d)`` velocities now [length/time] (do not write)."""
        return self._shown(self.spheres[:, core.VX : core.VX + self.dimensions])

    @property
    def radii(self) -> np.ndarray:
        """``(N,)`` radii at the time origin [length] (do not write; :meth:`radii_at` for now)."""
        return self._shown(self.spheres[:, core.RADIUS])

    # ---- the engine's order of the spheres ------------------------------------
    def _inside_at(self, t: float) -> np.ndarray:
        """``(N, 3)`` centres at core time ``t`` in the engine's order (wrapped into a box)."""
        out = np.zeros((self.n, 3))  # (2-D: the third column stays 0)
        core.positions_at(self.axes, self.spheres, t, out, self._edges, self._delta(t))
        return out

    def _delta(self, t: float) -> float:
        """The Lees-Edwards offset at core time ``t`` (0.0 unsheared)."""
        f = self.scalars
        return float((f[core.F_SHEAR0] + f[core.F_SHEAR] * t) % f[core.F_EDGE]) if f[core.F_SHEAR] else 0.0

    @property
    def _edges(self) -> np.ndarray:
        """The box's sides as the core reads them (zeros: no box), a view."""
        return self.scalars[core.F_EDGE : core.F_EDGE + 3]

    @property
    def _cells(self) -> np.ndarray:
        """Cells per axis, a view."""
        return self.counts[core.C_GRID : core.C_GRID + 3]

    def _morton(self, x: np.ndarray) -> np.ndarray:
        """The engine's spheres in Morton (Z-curve) order of their places ``x``.

        The centres are quantised to a grid of ``2^b`` per axis over the cells'
        span (about one sphere per grid cell, ``b <= 21``), the three
        coordinates' bits interleaved; ties keep the order they had.

        Returns:
            ``perm``: the sphere that comes ``k``-th (an index of the engine's order).
        """
        n = self.n
        bits = int(min(21, max(1, np.ceil(np.log2(max(n, 2)) / 3.0))))
        lo = self.scalars[core.F_LOW : core.F_LOW + 3]
        span = self.scalars[core.F_WIDTH : core.F_WIDTH + 3] * self._cells
        q = np.floor((x - lo) * ((1 << bits) / span))
        q = np.clip(np.nan_to_num(q), 0, (1 << bits) - 1).astype(np.uint64)
        code = (
            _spread_bits(q[:, 0])
            | (_spread_bits(q[:, 1]) << np.uint64(1))
            | (_spread_bits(q[:, 2]) << np.uint64(2))
        )
        return np.argsort(code, kind="stable")

    def _permute(self, perm: ArrayLike, built: bool = True) -> None:
        """Put the spheres in the order ``perm`` (``perm[k]``: the sphere that comes ``k``-th).

        Every per-sphere array moves with its spheres and every sphere
        index in them is renamed (partners, neighbour lists); the cell lists
        and the calendar are made anew from them.  Nothing is predicted
        again and no number changes, so the run goes on with the same events
        bit for bit (the tie keys are on input indices, ``order``).
        ``built``: the derived arrays exist (else only the physical state moves).
        """
        n = self.n
        perm = np.asarray(perm, dtype=np.int64)
        new = np.empty(n, np.int64)
        new[perm] = np.arange(n)  # old index -> new
        self.spheres = self.spheres[perm]
        self._masses = self._masses[perm]
        self._images = self._images[perm]
        if self.hit_t.shape[0]:
            self.hit_t = self.hit_t[perm]
        book = self.book[perm]  # (with the input indices, ORIGIN)
        self.book = book
        self._set_rank()
        if not built:
            return
        self.due = self.due[perm]
        if self.shells.shape[0]:
            self.shells = self.shells[perm]
        partner = book[:, core.PARTNER]
        book[:, core.PARTNER] = np.where(partner >= 0, new[np.maximum(partner, 0)], partner)
        if self.scalars[core.F_NSTEP]:  # the bond tables' partners renamed
            held = np.arange(book.shape[1] - core.BONDS - 1)[None, :] < book[:, core.BONDS][:, None]
            entries = book[:, core.BONDS + 1 :]
            entries[held] = (new[entries[held] >> 3] << 3) | (entries[held] & 7)
        nb = self.neighbours[perm]
        used = np.arange(nb.shape[1])[None, :] < book[:, core.NEIGHBOURS][:, None]
        entries = nb[used].astype(np.int64)
        nb[used] = ((new[entries >> 5] << 5) | (entries & 31)).astype(np.int32)
        # each list in the new order too (entries past a list's length are never read)
        nb[~used] = np.iinfo(np.int32).max
        nb.sort(axis=1)
        self.neighbours = nb
        # the cell lists, each in the new order
        cell = book[:, core.CELL]
        by = np.argsort(cell, kind="stable")
        c = cell[by]
        same = c[1:] == c[:-1]
        self.cell_next = np.full(n, -1, LINK)
        self.cell_prev = np.full(n, -1, LINK)
        self.cell_next[by[:-1][same]] = by[1:][same]
        self.cell_prev[by[1:][same]] = by[:-1][same]
        first = np.concatenate(([True], ~same))
        self.cell_head[:] = -1
        self.cell_head[c[first]] = by[first]
        # the calendar, with the buckets as wide as they were
        self.calendar = np.full(core.calendar_size(n), -1, LINK)
        heap = (self.heap, self.heap_t, self.heap_key, self.calendar)
        core.requeue(
            *heap,
            self.due,
            self.book,
            self.scalars,
            self.counts,
            CAL_PER_BUCKET,
            float(self.scalars[core.F_BUCKET_RATE]),
        )

    def _reorder(self) -> None:
        """The spheres in Morton order of their places now (see :meth:`_permute`)."""
        self._since_reorder = 0
        if self.n > 1:
            perm = self._morton(self._inside_at(self.scalars[core.F_CLOCK]))
            if not np.array_equal(perm, np.arange(self.n)):
                self._permute(perm)

    def _kinetic_sums(self) -> None:
        """The core's kinetic tensor and energy current, summed in the input order."""
        if self._rank is None:
            core.kinetic_sums(self.axes, self.spheres, self._masses, self.scalars)
        else:
            core.kinetic_sums(self.axes, self.spheres[self._rank], self._masses[self._rank], self.scalars)

    @property
    def box(self) -> float | None:
        """Edge of the periodic box (the x side) as the core reads it [length], or ``None`` (no box)."""
        box = float(self.scalars[core.F_BOX])
        return box if box else None

    @property
    def sides(self) -> np.ndarray | None:
        """``(d,)`` sides of the periodic box as the core reads them [length], or ``None`` (no box)."""
        return self._edges[: self.dimensions].copy() if self.scalars[core.F_BOX] else None

    def _grid(self, n: int, headroom: float = 1.0) -> None:
        radii = self.radii_at() if n else self.radii
        sigma = 2.0 * float(radii.max()) * headroom if n else 0.0
        params = _core_params(self.container)
        spans, edges = params["spans"], params["edges"]
        self.scalars[core.F_CONTAINER] = params["wall_radius"]
        self.scalars[core.F_BOX] = params["box"]
        box = min(edges)  # (0: no box)
        # neighbour lists in dense fluids (cells at least as wide as the
        # largest neighbour distance, SHELL largest diameters), else cells
        # at least as wide as the largest contact distance; with a small
        # relative margin for rounding, and a few cells per sphere at most
        phi = self._packing(radii) if n else 0.0
        shell = SHELL if phi >= (LISTS_FROM if self.dimensions == 3 else LISTS_FROM_2D) else 0.0
        if getattr(self.container, "shear_rate", 0.0):
            shell = 0.0  # a sheared box: cells (the strip across a sliding face), no lists yet
        if self.scalars[core.F_NSTEP]:
            # steps: cells, and each sphere's reach for its list, widened to the outermost step
            outer = max((steps[0][0] for steps in self.step_table.values() if steps), default=1.0)
            sigma *= outer
            headroom *= outer
        if box and shell and shell * sigma * 3.0 > box:
            shell = 0.0  # a box too small for three cells of lists: cells
        reach = sigma * shell if shell else sigma
        # cells per axis: at most about 2 N^(1/3) + 1 along the longest side
        d = self.dimensions
        longest = max(spans[:d])
        for ax, (span, edge) in enumerate(zip(spans, edges)):
            nc = int(span / (reach * (1.0 + 1e-6))) if sigma > 0.0 else 1
            most = int(np.ceil(2.0 * max(n, 1) ** (1.0 / d) * (span / longest))) + 1
            nc = max(1, min(nc, most, 1 << 10 if d == 3 else 1 << 15))
            if ax >= d:
                nc = 1  # 2-D: one layer of cells (the core visits the 9 cells around a disk's)
            if edge and nc < 3:
                if sigma * 3.0 > edge:
                    raise BoxShapeError(
                        f"periodic box side {edge:g} is smaller than three times the largest diameter "
                        f"({sigma:g}); every side must be at least {3.0 * sigma:g}"
                    )
                nc = 3
            self.counts[core.C_GRID + ax] = nc
            self.scalars[core.F_EDGE + ax] = edge
            self.scalars[core.F_LOW + ax] = -0.5 * span
            self.scalars[core.F_WIDTH + ax] = span / nc
        self.scalars[core.F_SHELL] = shell
        self.scalars[core.F_HEADROOM] = headroom
        # shells are read with neighbour lists alone: none kept for cells (32 bytes a sphere)
        self.shells = np.zeros((self.n if shell else 0, core.SHELL_COLS))
        self.counts[core.C_CELLS] = self.counts[core.C_GRID]
        self.scalars[core.F_LO] = self.scalars[core.F_LOW]
        self.scalars[core.F_W] = self.scalars[core.F_WIDTH]
        self.cell_head = np.full(int(np.prod(self._cells)), -1, LINK)

    def _into_box(self) -> None:
        """The centres into the periodic box, whole sides at a time (the image counts the other way).

        Once, at the start: from then on a centre moves by a side exactly when
        it leaves the box (``_core._box_exit``), as the reference's does.
        """
        if self.scalars[core.F_SHEAR] != 0.0:
            # a centre outside along y is an image: moved by whole sides in
            # y, by the offset in x and by the boundary speed in v_x (the
            # reference's arithmetic, DynamO's applyBC)
            lx, ly, lo = self._edges[0], self._edges[1], self.scalars[core.F_LOW + 1]
            now_off = (self.scalars[core.F_SHEAR0] + self.scalars[core.F_SHEAR] * 0.0) % lx
            for k in range(self.n):
                m = np.floor((self.spheres[k, core.Y] - lo) / ly)
                if m:
                    self.spheres[k, core.Y] -= m * ly
                    self.spheres[k, core.X] -= m * now_off
                    self.spheres[k, core.VX] -= m * self.scalars[core.F_SHEAR]
                    self._images[k, 1] += int(m)
        for ax in range(self.dimensions):
            edge = self.scalars[core.F_EDGE + ax]
            if not edge:
                continue
            x = self.spheres[:, core.X + ax]
            k = np.floor((x - self.scalars[core.F_LOW + ax]) / edge)
            moved = k != 0.0
            x[moved] -= k[moved] * edge
            self._images[moved, ax] += k[moved].astype(np.int64)

    def _build(self) -> None:
        while True:
            longest = core.build(self.arrays, CAL_PER_BUCKET)
            if longest <= self.neighbours.shape[1]:
                break
            # room for the longest list and more: lists change as spheres move
            self.neighbours = np.zeros((self.n, longest + longest // 2 + 4), np.int32)
        self.scalars[core.F_T_KIN] = self.scalars[core.F_CLOCK]
        self._kinetic_sums()
        self._queue_anew(first=True)

    def _queue_anew(self, first: bool = False) -> None:
        """When the calendar is next made anew: N events after a build, then 2N, 4N, ...

        Its bucket width comes from the predictions; right after a build
        (a lattice, say) they can be far from those of the fluid it turns
        into, so it is made anew as the run goes on (O(N) each time).
        """
        if first:
            self._queue_every = max(self.n, 16)
        else:
            self._requeue()
            self._queue_every *= 2
        self._since_queue = 0

    def _widen_lists(self) -> None:
        """Twice as many entries per neighbour list (the lists stay as they are)."""
        wider = np.zeros((self.n, 2 * self.neighbours.shape[1] + 8), np.int32)
        wider[:, : self.neighbours.shape[1]] = self.neighbours
        self.neighbours = wider

    @property
    def arrays(self) -> tuple[np.ndarray, ...]:
        """The core's arrays as one argument, in ``core.ARRAYS``' order (made anew per call)."""
        return _core_arrays(self)

    # ---- time -------------------------------------------------------------
    @property
    def time(self) -> float:
        """Time of the last processed event (or the start) [time]."""
        return self.offset + self.scalars[core.F_CLOCK]

    def _rebase(self) -> None:
        """The time origin to the clock, every prediction made afresh from the moved centres.

        (A prediction shifted to the new origin would round otherwise than
        one made after the move: which of two equal entries, one stale, the
        calendar gives first would then change bits, and it depends on the
        calendar's layout and the spheres' order.  A prediction per sphere
        every REBASE_EVERY events per sphere.)
        """
        if self.scalars[core.F_SHEAR]:  # the open flights closed where the centres move to the clock
            core.close_flights(
                self.axes, self.spheres, self._masses, self.scalars, self.scalars[core.F_CLOCK]
            )
        t = core.rebase(self.axes, self.spheres, self.due, self.heap_t, self.scalars)
        self.offset += t
        self.hit_t -= t  # (the inelastic rule's last collisions: the same shift as every time)
        core.predict_all(self.arrays)
        self._requeue()
        self._since_rebase = 0

    def _requeue(self) -> None:
        """The event calendar made anew (its buckets from the predictions now)."""
        heap = (self.heap, self.heap_t, self.heap_key, self.calendar)
        core.requeue(*heap, self.due, self.book, self.scalars, self.counts, CAL_PER_BUCKET, 0.0)

    @property
    def window(self) -> float:
        """The simultaneity window [time]."""
        return float(self.scalars[core.F_WINDOW])

    # ---- growth and velocities -----------------------------------------------
    @property
    def growth(self) -> float:
        """Radii's relative growth rate now: ``dR_i/dt / R_i`` [1/time] (0: off)."""
        g = self.scalars[core.F_GROW]
        return float(g / (1.0 + g * self.scalars[core.F_CLOCK])) if g else 0.0

    def set_growth(self, rate: float) -> None:
        """Grow every radius from now at ``dR_i/dt = rate * R_i(now)`` [1/time]; 0 stops.

        Radii then grow linearly in time (each at its own constant speed,
        so mixtures keep their ratios), with the Lubachevsky-Stillinger
        collision rule.  Everything is predicted afresh.
        """
        rate = float(rate)
        if not (rate >= 0.0 and np.isfinite(rate)):
            raise ArgumentError(f"growth rate must be a finite number >= 0, got {rate}")
        if rate and self.scalars[core.F_NSTEP]:
            raise ArgumentError("radii cannot grow with steps (square wells): grow hard spheres first")
        if rate and self.scalars[core.F_SHEAR]:
            raise ArgumentError("radii cannot grow in a sheared box: grow them unsheared first")
        if rate and self.inelastic:
            raise ArgumentError(
                "radii cannot grow with restitution below 1 or a thermal wall: grow elastic spheres first"
            )
        self._rebase()  # radii to the clock
        self.scalars[core.F_GROW] = rate
        self._regrid()

    def _regrid(self) -> None:
        """Cells for the radii now (with room to grow), everything predicted afresh."""
        self._grid(self.n, self._headroom())
        self._build()

    def _packing(self, radii: np.ndarray) -> float:
        """Packing fraction of spheres of ``radii`` (area fraction in 2-D)."""
        if self.dimensions == 2:
            return float(np.sum(radii**2)) * np.pi / self.container.volume
        return float(np.sum(radii**3)) * (4.0 / 3.0) * np.pi / self.container.volume

    def _headroom(self) -> float:
        """Room to grow for the cells and lists made now (reach over radius; 1 without growth).

        A rebuild (about as dear as a few events per sphere) against the
        extra pairs (a fraction ``1.5 (h - 1)`` on average over the radii's
        way through the room, for lists of volume ``h^3``): the sum is least
        near ``h - 1 = sqrt(8 g / nu)``, ``g`` the growth rate and ``nu``
        the collision rate per sphere, taken from the Enskog estimate
        ``nu = 6 (Z - 1) sqrt(kT / (pi m)) / sigma`` with Carnahan-Starling's
        ``Z`` at the packing now, the mean mass and diameter, and kT from
        the velocities.  A function of the state alone, so a resumed run
        makes its rebuilds at the same times as the run it continues.
        """
        g = float(self.scalars[core.F_GROW])
        if not g or self.n == 0:
            return 1.0
        r = self.radii_at()
        d = self.dimensions
        phi = self._packing(r)
        if d == 3:
            z = float(carnahan_starling(min(phi, MAX_PACKING)))
        else:  # Henderson's hard-disk equation of state: an estimate, for the rate only
            phi = min(phi, 0.89)
            z = (1.0 + phi * phi / 8.0) / (1.0 - phi) ** 2
        m = float(np.mean(self.masses))
        kt = float(np.sum(self.masses * np.sum(self.velocities**2, axis=1))) / (d * self.n)
        sigma = 2.0 * float(np.mean(r))
        # (in 2-D Enskog's rate is (Z - 1) sqrt(pi kT / m) / sigma: the 3-D formula's order of magnitude)
        nu = collision_rate_from_z(z, sigma, kt, m) if sigma > 0.0 and m > 0.0 else 0.0
        room = np.sqrt(8.0 * g / nu) if nu > 0.0 else np.inf
        return 1.0 + min(max(room, HEADROOM_MIN - 1.0), HEADROOM_MAX - 1.0)

    def _grid_limit(self) -> float:
        """Absolute time the growing radii outgrow the cells or their neighbour lists' reach.

        ``inf``: never.
        """
        g = self.scalars[core.F_GROW]
        if not g or self.n == 0:
            return np.inf
        if not self.scalars[core.F_SHELL]:
            if np.all(self._cells == 1) and self.box is None:
                return np.inf
            rmax = float(self.radii.max())
            if rmax <= 0.0:
                return np.inf
            # (2-D: the one layer of cells along z is not a width the disks fill)
            widths = self.scalars[core.F_WIDTH : core.F_WIDTH + self.dimensions]
            w = float(np.min(widths)) / (1.0 + 1e-6)
            return self.offset + (w / (2.0 * rmax) - 1.0) / g
        r = self.spheres[:, core.RADIUS]  # (the engine's order, as the shells')
        grows = r > 0.0
        if not np.any(grows):
            return np.inf
        ratio = float(np.min(self.shells[grows, core.REACH] / r[grows]))
        return self.offset + (ratio - 1.0) / g

    def move_clock(self, t: float) -> None:
        """Move the clock to absolute time ``t`` (no event may be pending before it)."""
        t = float(t) - self.offset
        if self.n and self.heap_t[0] < t:
            raise ArgumentError("events are pending before that time: advance to it first")
        if t > self.scalars[core.F_CLOCK]:
            self.scalars[core.F_CLOCK] = t

    def radii_at(self, t: float | None = None) -> np.ndarray:
        """``(N,)`` radii at absolute time ``t`` (default: now) [length]."""
        g = self.scalars[core.F_GROW]
        if not g:
            return self.radii.copy()
        t = self.time if t is None else t
        return self.radii * (1.0 + g * (t - self.offset))

    def _settle_kinetic_integrals(self) -> None:
        """Every centre at the clock, and the kinetic integrals (the kinetic
        tensor's and the heat current's time integrals) brought up to it, before
        velocities or the box change under them."""
        self._rebase()
        f = self.scalars
        dt = f[core.F_CLOCK] - f[core.F_T_KIN]
        f[core.F_KIN_INT : core.F_KIN_INT + 6] += f[core.F_KIN_T : core.F_KIN_T + 6] * dt
        f[core.F_HEAT_INT : core.F_HEAT_INT + 3] += f[core.F_HEAT_KIN : core.F_HEAT_KIN + 3] * dt
        f[core.F_T_KIN] = f[core.F_CLOCK]

    def rescale_velocities(self, factor: float) -> None:
        """Multiply every velocity by ``factor`` now; everything is predicted afresh."""
        self._settle_kinetic_integrals()
        self.spheres[:, core.VX : core.VZ + 1] *= factor
        self._kinetic_sums()
        self._build()

    def kick(self, i: int, t: float, velocity: Iterable[float]) -> None:
        """Sphere ``i`` takes ``velocity`` (``d`` components) at absolute time ``t``.

        ``t`` is compared with :attr:`time` as given (absolute); a ``t`` at or
        after it whose distance from the time origin rounds below the clock
        (``offset + clock - offset`` can) is the clock itself.
        """
        if not float(t) >= self.time:  # (nan too)
            raise ArgumentError("a kick cannot be before the clock: give a time at or after it")
        t = max(float(t) - self.offset, float(self.scalars[core.F_CLOCK]))
        v = [float(x) for x in velocity]
        if len(v) != self.dimensions:
            raise BoxShapeError(f"a velocity of {len(v)} components in {self.dimensions}-D space")
        vx, vy, vz = (v + [0.0])[:3]
        i = int(i)
        core.kick(self.arrays, i if self._rank is None else int(self._rank[i]), t, vx, vy, vz)

    def rescale_box(self, container: Container, factors: ArrayLike) -> None:
        """Put the spheres in ``container``, a periodic box ``factors`` times this one's sides, now.

        ``factors``: one per side (``d`` of them: two in 2-D).

        Every centre is scaled with the box about its centre (the affine map
        of a constant-pressure volume move: ``x -> factors * x`` per axis,
        the images kept, so unwrapped centres scale too); velocities, radii,
        counters and tallies are kept, and the cells, lists and predictions
        are made afresh for the new box (exact: the state now is all the
        dynamics needs).  The caller checks that no pair overlaps after the
        move (:mod:`hardspheres.barostat` does).
        """
        if self.box is None or not container.periodic:
            raise ArgumentError("rescale_box: the engine and the new container must be periodic boxes")
        if self.scalars[core.F_GROW]:
            raise ArgumentError("rescale_box: not while the radii grow (set_growth(0) first)")
        scale = np.ones(3)
        given = np.asarray(factors, dtype=np.float64).reshape(-1)
        scale[: given.size] = given  # (2-D: two factors; z stays 0)
        self._settle_kinetic_integrals()
        self.spheres[:, core.X : core.Z + 1] *= scale
        self.container = container
        self._grid(self.n)
        self._build()

    # ---- running ----------------------------------------------------------
    def advance(
        self,
        until: float = np.inf,
        events: int | None = None,
        collisions: int | None = None,
        record: bool = True,
    ) -> np.ndarray:
        """Process events up to time ``until`` or a count limit.

        Longer than 80 lines with this docstring (under 80 of code): the
        loop around the core's calls keeps the calendar's requeue schedule,
        the rebase and the record in the order the core needs them.

        Args:
            until: absolute time [time]; events after it are left pending.
            events: stop after this many collisions and reflections.
            collisions: stop after this many collisions.
            record: return the events processed (else an empty record).

        Returns:
            The events processed, in order: an array of
            :data:`~hardspheres.events.EVENT_DTYPE` (empty if not ``record``).

        Raises:
            ValueError: ``until`` is NaN.
            StuckError: the next event would repeat without end (a sphere
                sliding along the wall, or a frozen clock).  Events before
                it are returned first, and the call after raises.
        """
        if np.isnan(until):
            raise ArgumentError("until must be a time, not NaN")
        max_events = np.iinfo(np.int64).max if events is None else int(events)
        max_coll = np.iinfo(np.int64).max if collisions is None else int(collisions)
        chunks = []
        coll0 = int(self.counts[core.C_COLLISIONS])
        done_total = 0
        buffers = self._event_buffers
        while True:
            limit = self._grid_limit()
            if limit < until:
                stop = limit
            else:
                stop = until
            rebase_due = REBASE_EVERY * max(self.n, 16) if self._rebase_on else np.iinfo(np.int64).max
            left_ev = min(max_events - done_total, rebase_due - self._since_rebase)
            # the calendar made anew on time (with no record kept, the core
            # would otherwise run on past it: the record no longer limits it)
            left_ev = min(left_ev, max(self._queue_every - self._since_queue, 1))
            if self._reorder_every:
                reorder_due = max(int(self._reorder_every * self.n), 1)
                left_ev = min(left_ev, reorder_due - self._since_reorder)
            left_coll = max_coll - (int(self.counts[core.C_COLLISIONS]) - coll0)
            done, reason = core.run(
                self.arrays, stop - self.offset, left_ev, left_coll, buffers, record, *self.axes[:2]
            )
            done_total += done
            self._since_rebase += done
            self._since_queue += done
            self._since_reorder += done
            if self._since_queue >= self._queue_every:
                self._queue_anew()
            if self._reorder_every and self._since_reorder >= reorder_due:
                self._reorder()
            if record and done:
                chunks.append(_events.from_buffers(buffers, done, self.offset))
            if self._since_rebase >= rebase_due:
                self._rebase()
            if reason == core.STOP_LISTS_FULL:
                self._widen_lists()
                continue
            if reason == core.STOP_BONDS_FULL:
                self._widen_bonds()
                continue
            if reason == StopReason.FROZEN or reason == StopReason.SLIDING:
                if done_total == 0:
                    self.last_reason, self.last_done = StopReason(reason), 0
                    raise StuckError(
                        "frozen" if reason == StopReason.FROZEN else "sliding",
                        float(self.offset + self.heap_t[0]),
                        int(self.order[self.heap[0]]),
                        inelastic=self.inelastic,  # (the messages then say how to resolve it)
                    )
                break  # the events before it first; the next call raises
            if reason == StopReason.UNTIL and stop < until:
                # growing radii reached the cells' width: move the clock
                # there (nothing happens before), and coarser cells
                if self.scalars[core.F_CLOCK] < limit - self.offset:
                    self.scalars[core.F_CLOCK] = limit - self.offset
                if self._rebase_on:  # (off: the reference's arithmetic, which has no such moment)
                    self._rebase()
                nc = int(np.prod(self._cells))
                self._regrid()
                if int(np.prod(self._cells)) >= nc and self._grid_limit() <= limit:
                    raise ArgumentError(
                        "the spheres have grown too large for the periodic box (three diameters at "
                        "least): stop the growth sooner or take a larger box"
                    )
                continue
            if reason == StopReason.UNTIL or reason == StopReason.MAX_COLLISIONS:
                break
            if reason == StopReason.MAX_EVENTS and done_total >= max_events:
                break
        self.last_reason = StopReason(reason)
        self.last_done = done_total
        if len(chunks) == 1:
            return chunks[0]
        return np.concatenate(chunks) if chunks else _events.empty_events()

    def step(self, until: float = np.inf) -> tuple[float, int, int, int] | None:
        """Process the next event if it is at or before ``until`` (absolute) [time].

        Returns:
            ``(time, kind, i, j)``, or ``None`` if the next event is after
            ``until``; raises as :meth:`advance` does.
        """
        ev = self.advance(until=until, events=1)
        if len(ev) == 0:
            return None
        return float(ev["time"][0]), int(ev["kind"][0]), int(ev["i"][0]), int(ev["j"][0])

    # ---- checkpoints -------------------------------------------------------
    # the core's arrays but its work space and the calendar (made anew on restore)
    _SAVED = tuple(name for name in core.ARRAYS if name not in ("scratch", "calendar", "axes", "rule"))

    def checkpoint(self) -> dict[str, Any]:
        """Everything needed to resume bit for bit, as a dict of arrays.

        The event calendar is saved as one heap over all spheres (sorted by
        time and tie key) and made anew on :meth:`restore`: the order of
        events does not depend on how the calendar is laid out.
        """
        out = {k: getattr(self, _INTERNAL.get(k, k)) for k in self._SAVED}
        n = self.n
        t, key = checkpoint.calendar_entries(self.due, self.book, n)
        order = np.lexsort((key, t))
        book = self.book.copy()
        book[order, core.HEAP_POS] = np.arange(n)
        out["heap"], out["heap_t"], out["heap_key"], out["book"] = order, t[order], key[order], book
        if not self.shells.shape[0]:  # (cells: files keep a zero row a sphere, as before)
            out["shells"] = np.zeros((n, core.SHELL_COLS))
        for k in _LINKED:  # (files keep int64: the same format at any N)
            out[k] = out[k].astype(np.int64)
        # the calendar's own counters and width (the last of each) are made anew on restore
        # (the per-axis grid after them; zeros in their place)
        out["counts"] = self.counts.copy()
        out["counts"][core.C_HEAP_SIZE : core.C_GRID] = 0
        out["scalars"] = self.scalars.copy()
        out["scalars"][core.F_BUCKET_RATE] = 0.0
        # the last two: the core's wall radius and box edge, NaN when absent
        # (files before the container record had only these)
        params = _core_params(self.container)
        out["meta"] = np.array(
            [
                self.offset,
                float(self._since_rebase),
                float(self._rebase_on),
                params["wall_radius"] or np.nan,
                params["box"] or np.nan,
            ]
        )
        out["container"] = self.container.record()
        # the engine's order (``order``, saved above) and when it is next sorted
        out["reorder"] = np.array([self._reorder_every, float(self._since_reorder)])
        return out

    @classmethod
    def restore(cls, data: dict[str, np.ndarray], before_core: Callable[[int], None] | None = None) -> Engine:
        """An engine from :meth:`checkpoint`'s arrays, in exactly the saved state.

        Every array is checked first (:func:`hardspheres.core.checkpoint.check_arrays`): the compiled
        core trusts its indices, so a damaged file must not reach it.
        ``before_core(d)``, if given, is called with the dimension before
        the compiled core is first called (e.g. to announce its compilation).

        Raises:
            CheckpointError: an array is missing or inconsistent.
        """
        data = checkpoint.current_names(data)
        checkpoint.check_arrays(data)  # the saved layout as it is, before any migration
        data, kinetic_sums_missing = checkpoint.migrate(data)
        eng = cls.__new__(cls)
        n = len(data["masses"])
        for k in cls._SAVED:
            setattr(eng, _INTERNAL.get(k, k), np.array(data[k], dtype=LINK if k in _LINKED else None))
        if not eng.scalars[core.F_SHELL]:  # (cells: no shells kept)
            eng.shells = np.zeros((0, core.SHELL_COLS))
        eng._reorder_every, eng._since_reorder = data["reorder"][0], int(data["reorder"][1])
        eng._set_rank()
        offset, since, rebase_on, radius, box = data["meta"].tolist()
        eng.offset = offset
        eng._since_rebase = int(since)
        eng._rebase_on = bool(rebase_on)
        if "container" in data:
            try:
                eng.container = from_record(data["container"])
            except (ValueError, TypeError):
                raise CheckpointError("damaged checkpoint: no valid container") from None
            params = _core_params(eng.container)
            if (
                params["wall_radius"] != eng.scalars[core.F_CONTAINER]
                or params["box"] != eng.scalars[core.F_BOX]
            ):
                raise CheckpointError("damaged checkpoint: the container disagrees with the core's")
        else:
            eng.container = as_container(None if np.isnan(radius) else radius, None if np.isnan(box) else box)
        eng.scratch = np.zeros(2 * eng.n + 2, LINK)
        eng._event_buffers = _events.empty_buffers(CHUNK)
        if before_core is not None:
            before_core(eng.dimensions)
        if kinetic_sums_missing:  # a checkpoint from before the transport tallies
            eng._kinetic_sums()
        edges = np.array(_core_params(eng.container)["edges"])
        if np.any(eng.scalars[core.F_EDGE : core.F_EDGE + 3] != edges):
            raise CheckpointError("damaged checkpoint: the box's sides disagree with the core's")
        eng.calendar = np.full(core.calendar_size(n), -1, LINK)
        eng._requeue()
        eng._queue_anew(first=True)
        eng.last_reason, eng.last_done = StopReason.UNTIL, 0
        return eng

    # ---- state ------------------------------------------------------------
    def positions_at(
        self, t: float | None = None, out: np.ndarray | None = None, spheres: Sequence[int] | None = None
    ) -> np.ndarray:
        """``(N, d)`` centres of all spheres at absolute time ``t`` (default: now) [length].

        In a periodic box the centres are wrapped into the box.  With
        ``spheres`` (indices), only their rows of ``out`` are filled (the
        same bits), in time independent of the number of spheres.
        """
        if self.dimensions == 3:
            return self._positions_at(t, out, spheres)
        return _planar(self._positions_at(t, None, spheres), out, spheres, self.n)

    def _positions_at(
        self, t: float | None, out: np.ndarray | None, spheres: Sequence[int] | None
    ) -> np.ndarray:
        """:meth:`positions_at` with three columns (in 2-D the last is 0)."""
        t = self.time if t is None else t
        out = np.zeros((self.n, 3)) if out is None else out
        if spheres is not None and self.box is None:
            t -= self.offset
            rank = self._rank
            for k in spheres:  # a few: Python floats beat numpy's set-up
                row = k if rank is None else rank[k]
                x, y, z, vx, vy, vz, tk = self.spheres[row, :7].tolist()
                dt = t - tk
                out[k] = (x + vx * dt, y + vy * dt, z + vz * dt)
            return out
        if self._rank is None:
            core.positions_at(
                self.axes, self.spheres, t - self.offset, out, self._edges, self._delta(t - self.offset)
            )
        else:
            out[self.order] = self._inside_at(t - self.offset)
        return out

    def unwrapped_at(self, t: float | None = None, out: np.ndarray | None = None) -> np.ndarray:
        """``(N, d)`` unwrapped centres at absolute time ``t`` (default: now) [length].

        Periodic box: the centre in the box plus ``images * box``, with
        :attr:`img` the exact count of box crossings of each sphere; in a
        spherical container the same as :meth:`positions_at`.  A sheared box:
        along y and z the same; along x the shifts by the offset at each
        crossing of a y face are not added (not kept by the core yet), so x
        is unwrapped by whole sides only.
        """
        if self.dimensions == 3:
            return self._unwrapped_at(t, out)
        return _planar(self._unwrapped_at(t, None), out, None, self.n)

    def _unwrapped_at(self, t: float | None, out: np.ndarray | None) -> np.ndarray:
        t = self.time if t is None else t
        out = np.zeros((self.n, 3)) if out is None else out
        if self._rank is None:
            core.unwrapped_at(self.axes, self.spheres, self._images, t - self.offset, out, self._edges)
        else:
            inside = np.zeros((self.n, 3))
            core.unwrapped_at(self.axes, self.spheres, self._images, t - self.offset, inside, self._edges)
            out[self.order] = inside
        return out

    @property
    def idle(self) -> bool:
        """Whether nothing will ever happen again (no spheres, or no event or crossing ahead)."""
        return self.n == 0 or not self.heap_t[0] < np.inf

    @property
    def counters(self) -> dict[str, int]:
        """Dict of event counts: collisions, reflections, crossings (of a cell,
        or, with neighbour lists, of a sphere's shell), stale (predictions
        dropped), refreshed (made afresh by the window rule)."""
        c = self.counts
        out = {
            "collisions": int(c[core.C_COLLISIONS]),
            "reflections": int(c[core.C_REFLECTIONS]),
            "crossings": int(c[core.C_CROSSINGS]),
            "stale": int(c[core.C_STALE]),
            "refreshed": int(c[core.C_REFRESHED]),
        }
        if self.scalars[core.F_NSTEP]:  # (with steps, as the reference's)
            out.update(
                captures=int(c[core.C_STEP_EVENTS]),
                releases=int(c[core.C_STEP_EVENTS + 1]),
                bounces=int(c[core.C_STEP_EVENTS + 2]),
            )
        return out

    def transport_tallies(self, t: float | None = None) -> dict[str, np.ndarray]:
        """The transport tallies at absolute time ``t`` (default: now; periodic box).

        Returns:
            dict of arrays: ``virial`` (6,) the collisional virial tensor
            ``sum r_ij dp_i``; ``kinetic`` (6,) ``int sum m v v dt``;
            ``heat_collisional`` (3,) ``sum r_ij dE_i``; ``heat_kinetic``
            (3,) ``int sum v E dt``.  Tensors in the order xx yy zz xy xz yz;
            all summed since the engine was built.
        """
        f = self.scalars
        dt = (self.time if t is None else t) - self.offset - f[core.F_T_KIN]
        return {
            "virial": f[core.F_VIR_T : core.F_VIR_T + 6].copy(),
            "kinetic": (f[core.F_KIN_INT : core.F_KIN_INT + 6] + dt * f[core.F_KIN_T : core.F_KIN_T + 6]),
            "heat_collisional": f[core.F_HEAT_COLL : core.F_HEAT_COLL + 3].copy(),
            "heat_kinetic": (
                f[core.F_HEAT_INT : core.F_HEAT_INT + 3] + dt * f[core.F_HEAT_KIN : core.F_HEAT_KIN + 3]
            ),
        }

    def stress_tallies(self, t: float | None = None) -> dict[str, np.ndarray]:
        """The stress tallies at absolute time ``t`` (default: now; periodic box), since the engine was built.

        Returns:
            dict of ``(6,)`` arrays (xx yy zz xy xz yz): ``virial`` the
            collisional virial tensor ``sum r_ij dp_i`` [mass*length^2/time]
            and ``kinetic`` the time integral of ``sum m c c``
            [mass*length^2/time], ``c = v - g y e_x`` the peculiar velocities
            (the velocities when not sheared: :meth:`transport_tallies`'),
            each flight integrated exactly, as the reference's
            (:meth:`hardspheres.core.reference.Reference.stress_tallies`; equal
            to rounding).

        Raises:
            PeriodicBoxRequired: not a periodic box.
        """
        require_periodic(self.container, "the stress tallies")
        if not self.scalars[core.F_SHEAR]:
            tal = self.transport_tallies(t)
            return {"virial": tal["virial"], "kinetic": tal["kinetic"]}
        t = (self.time if t is None else t) - self.offset
        out = np.zeros(6)
        core.peculiar_kinetic(self.axes, self.spheres, self._masses, self.scalars, t, out)
        return {"virial": self.scalars[core.F_VIR_T : core.F_VIR_T + 6].copy(), "kinetic": out}

    @property
    def wall_impulse(self) -> float:
        """Total impulse delivered to the container wall [mass*length/time]."""
        return float(self.scalars[core.F_WALL_IMPULSE])

    @property
    def virial(self) -> float:
        """Sum over collisions of ``r_ij . dp_i`` [mass*length^2/time]."""
        return float(self.scalars[core.F_VIRIAL])

    # ---- checks -----------------------------------------------------------
    def max_overlap(self, t: float | None = None) -> float:
        """Largest overlap over all pairs, relative to the pair's contact distance."""
        t = self.time if t is None else t
        x = self._inside_at(t - self.offset)  # pairs across the box compare by minimum image
        if self.scalars[core.F_SHEAR]:
            return float(
                core.max_overlap_sheared(
                    self.axes, x, self.spheres, self.book, self.cell_head, self.cell_next, self._cells,
                    self._edges, self._delta(t - self.offset),
                )
            )  # fmt: skip
        g = self.scalars[core.F_GROW]
        scale = 1.0 + g * (t - self.offset) if g else 1.0
        return float(
            core.max_overlap(
                self.axes,
                x,
                self.spheres,
                self.book,
                self.cell_head,
                self.cell_next,
                self._cells,
                self._edges,
                scale,
            )
        )

    def outside(self, t: float | None = None, tol: float = 1e-9) -> int:
        """Number of spheres poking out of the container by more than ``tol`` of its size."""
        return int(np.sum(self.container.outside(self.positions_at(t), self.radii_at(t), tol)))

    def kinetic_energy(self) -> float:
        """Total kinetic energy [mass*length^2/time^2]."""
        return float(kinetic_energy(self.masses, self.velocities))


def _planar(full: np.ndarray, out: np.ndarray | None, spheres: Sequence[int] | None, n: int) -> np.ndarray:
    """The first two columns of ``full`` (2-D), into ``out`` if given (only rows ``spheres``)."""
    if out is None:
        out = np.empty((n, 2))
    rows = slice(None) if spheres is None else list(spheres)
    out[rows] = full[rows, :2]
    return out


def _columns(a: ArrayLike, n: int, d: int, what: str) -> np.ndarray:
    """``a`` as ``(n, d)`` float64; :class:`BoxShapeError` if it has another number of components."""
    a = np.asarray(a, dtype=np.float64)
    if a.size != n * d or (a.ndim == 2 and a.shape[1] != d):
        width = a.shape[-1] if a.ndim >= 1 and a.size else "?"
        raise BoxShapeError(
            f"{what} have {width} components but the container is {d}-D: give ({n}, {d}) arrays "
            "(2-D containers: PeriodicBox((Lx, Ly)), CircularContainer; 3-D: the others)"
        )
    return a.reshape(n, d)

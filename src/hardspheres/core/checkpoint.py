"""Checkpoints: the file format, its version, the checks and the migrations, in one place.

A checkpoint is an ``.npz`` of named arrays: ``format`` (:data:`FORMAT`),
``version`` (:data:`VERSION`), the simulation's own arrays (names, clock,
observables, thermostat; :meth:`hardspheres.Simulation.save`) and the
engine's (:meth:`hardspheres.core.engine.Engine.checkpoint`).  Reading one
(:func:`read`) checks the format and version; :func:`check_arrays` checks
every array the compiled core will index or compute with before it sees
them; :func:`migrate` brings an older layout to today's.

Versions:

* 1: every layout written up to the layout by families (2026-12-01), told
  apart by their arrays (see :func:`migrate`).
* 2: the arrays of the layout by families, all present (up to 2026-12-06).
* 3: version 2's and the collision rule (restitution coefficients and the
  TC model's ``t_c`` among the scalars, ``hit_t``).  A version-2 file is
  elastic (:func:`migrate`).
* 4: today's: the arrays :meth:`Engine.checkpoint
  <hardspheres.core.engine.Engine.checkpoint>` writes now, all present:
  version 3's and the thermal wall (its temperature and the energy it gave
  among the scalars, its generator's seed and count of draws among the
  counts).  A version-3 file has no thermal wall (:func:`migrate`).
"""

from __future__ import annotations

import os
import zipfile
from collections.abc import Mapping
from typing import TYPE_CHECKING, NoReturn, overload

import numpy as np

from ..errors import CheckpointError
from . import _core as core

if TYPE_CHECKING:
    from numpy.typing import ArrayLike, DTypeLike

#: The ``format`` array of every checkpoint.
FORMAT = "hardspheres-checkpoint"
#: The version this hardspheres writes.
VERSION = 4
#: The versions it reads (older ones migrated by :func:`migrate`).
READS = (1, 2, 3, 4)


def read(path: str | os.PathLike[str]) -> dict[str, np.ndarray]:
    """The arrays of a checkpoint file, after checking its format and version (``version`` removed)."""
    with open(path, "rb") as fh:  # (a missing file: FileNotFoundError, named by the caller)
        head = fh.read(6)
    if not head.startswith((b"PK", b"\x93NUMPY")):  # numpy would take anything else for a pickle
        raise CheckpointError(
            f"{path}: not a checkpoint (no .npz archive: "
            f"{'an empty file' if not head else 'it starts with ' + repr(head)}); "
            "give a file written by --checkpoint or Simulation.save"
        )
    try:
        with np.load(path, allow_pickle=False) as z:
            if not hasattr(z, "files"):
                raise CheckpointError("a bare .npy array")  # (worded below, with the path)
            data = {k: z[k] for k in z.files}
    except OSError as e:
        if isinstance(e, (FileNotFoundError, PermissionError, IsADirectoryError)):
            raise
        raise CheckpointError(f"{path}: not a readable checkpoint ({_why(e)})") from None
    except (ValueError, EOFError, zipfile.BadZipFile, KeyError, RuntimeError) as e:
        raise CheckpointError(f"{path}: not a checkpoint, or truncated or damaged ({_why(e)})") from None
    fmt = data.pop("format", None)
    version = data.pop("version", None)
    if fmt is not None and fmt.shape == () and str(fmt) == "hardspheres-ecmc-checkpoint":
        raise CheckpointError(
            f"{path}: an event-chain checkpoint; resume it with hardspheres sample --resume "
            "or EventChain.load, or turn it into a simulation with EventChain.to_simulation"
        )
    if fmt is None or fmt.shape != () or str(fmt) != FORMAT:
        raise CheckpointError(
            f"{path}: not a hardspheres checkpoint (no format "
            f"{FORMAT!r}); give a file written by "
            "--checkpoint or Simulation.save"
        )
    if (
        version is None
        or version.shape != ()
        or version.dtype.kind not in "iu"
        or (int(version) not in READS)
    ):
        raise CheckpointError(
            f"{path}: checkpoint version {version} is not one this hardspheres reads "
            f"({', '.join(map(str, READS))}): open it with the hardspheres that wrote it"
        )
    return data


def _why(err: BaseException) -> str:
    """A short reason from an exception: its first line, cut to 80 characters."""
    text = (str(err).splitlines() or [type(err).__name__])[0]
    return text if len(text) <= 80 else text[:77] + "..."


#: The arrays' names in checkpoints written before they were named for what they hold.
_OLD_NAMES = {
    "mass": "masses",
    "S": "spheres",
    "K": "book",
    "T": "due",
    "nxt": "cell_next",
    "prv": "cell_prev",
    "HT": "heap_t",
    "HKEY": "heap_key",
    "f": "scalars",
    "c": "counts",
    "head": "cell_head",
    "img": "images",
}


@overload
def current_names(data: dict[str, np.ndarray]) -> dict[str, np.ndarray]: ...
@overload
def current_names(data: Mapping[str, np.ndarray]) -> Mapping[str, np.ndarray]: ...
def current_names(data: Mapping[str, np.ndarray]) -> Mapping[str, np.ndarray]:
    """``data`` with the arrays of an older checkpoint under today's names."""
    if not any(k in data for k in _OLD_NAMES):
        return data
    return {_OLD_NAMES.get(k, k): v for k, v in data.items()}


def _bad(what: str) -> NoReturn:
    raise CheckpointError(f"damaged checkpoint: {what}")


def _array(data: Mapping[str, np.ndarray], key: str, dtype: DTypeLike, shape: tuple[int, ...]) -> np.ndarray:
    if key not in data:
        _bad(f"no array {key!r}")
    a = np.asarray(data[key])
    if a.dtype != dtype or a.shape != shape:
        _bad(f"{key!r} is {a.dtype}{list(a.shape)}, expected {np.dtype(dtype)}{list(shape)}")
    return a


def check_arrays(data: Mapping[str, np.ndarray]) -> None:
    """Check :meth:`Engine.checkpoint`'s arrays before the compiled core sees them.

    Everything the core indexes with is checked (heap, cell lists, partners,
    cell coordinates, counts), and everything it computes with is finite
    where it must be, so that a damaged or crafted file is refused rather
    than crashing the interpreter or running on NaNs.  O(N).

    Args:
        data: mapping of array name to array, as :meth:`Engine.checkpoint`
            returns it (or as read back from a file).

    Raises:
        CheckpointError: naming the first problem found.
    """
    data = current_names(data)
    masses = np.asarray(data.get("masses", np.zeros((0, 0))))
    if masses.ndim != 1:
        _bad("'masses' is not a list of masses")
    n = masses.shape[0]
    _array(data, "masses", np.float64, (n,))
    spheres = _array(data, "spheres", np.float64, (n, core.SPHERE_COLS))
    book = np.asarray(data.get("book", np.zeros((0, 0), np.int64)))
    if "book" not in data:
        _bad("no array 'book'")
    stepped = scalars_of(data).shape[0] > core.F_NSTEP and scalars_of(data)[core.F_NSTEP] != 0.0
    if book.dtype != np.int64 or (
        book.shape not in ((n, core.BOOK_COLS), (n, core.ORIGIN), (n, core.NEIGHBOURS))
        and not (stepped and book.ndim == 2 and book.shape[0] == n and book.shape[1] > core.BONDS + 1)
    ):
        # (13 columns: from before the engine's own order; 12: before the neighbour lists)
        _bad(f"'book' is {book.dtype}{list(book.shape)}, expected int64{[n, core.BOOK_COLS]}")
    due = _array(data, "due", np.float64, (n, core.DUE_COLS))
    cell_next = _array(data, "cell_next", np.int64, (n,))
    cell_prev = _array(data, "cell_prev", np.int64, (n,))
    heap = _array(data, "heap", np.int64, (n,))
    heap_t = _array(data, "heap_t", np.float64, (n,))
    heap_key = _array(data, "heap_key", np.int64, (n,))
    scalars = np.asarray(data.get("scalars", np.zeros(0)))
    if (
        scalars.dtype != np.float64
        or scalars.ndim != 1
        or not core.F_WINDOW < scalars.shape[0] <= core.N_SCALARS
    ):
        _bad(f"'scalars' is {scalars.dtype}{list(scalars.shape)}, expected float64[{core.N_SCALARS}]")
    if "images" in data:  # periodic image counts, where the core keeps them
        _array(data, "images", np.int64, (n, 3))
    # the engine's order of the spheres: the input index of each (before it, the input order)
    order = book[:, core.ORIGIN] if book.shape[1] > core.ORIGIN else np.arange(n, dtype=np.int64)
    if not np.array_equal(np.sort(order), np.arange(n)):
        _bad("the spheres' input indices are not a permutation of the spheres")
    if "reorder" in data:
        every, since = _array(data, "reorder", np.float64, (2,)).tolist()
        if not (np.isfinite(every) and every >= 0 and np.isfinite(since) and 0 <= since < 2**62):
            _bad("the reordering's interval or count is not a finite number >= 0")
    if "counts" not in data:
        _bad("no array 'counts'")
    counts = np.asarray(data["counts"])
    if counts.dtype != np.int64 or counts.ndim != 1 or not core.C_SERIAL < counts.shape[0] <= core.N_COUNTS:
        _bad(f"'counts' is {counts.dtype}{list(counts.shape)}, expected int64[{core.N_COUNTS}]")
    meta = _array(data, "meta", np.float64, (5,))
    grid = counts[core.C_GRID : core.C_GRID + 3] if counts.shape[0] > core.C_GRID + 2 else counts[[0, 0, 0]]
    if not np.all((grid >= 1) & (grid <= 1 << 10)):
        _bad(f"{grid.tolist()} cells per axis")
    if grid[0] != counts[core.C_CELLS]:
        _bad("the cells per axis disagree")
    cell_head = _array(data, "cell_head", np.int64, (int(np.prod(grid)),))
    _check_state(masses, spheres, due, heap_t, scalars, counts, meta)
    _check_rule(data, scalars, n)
    if scalars.shape[0] > core.F_NSTEP and scalars[core.F_NSTEP]:
        _check_bonds(book, scalars, counts, n)
    if n == 0:
        if np.any(cell_head != -1):
            _bad("cells hold spheres that do not exist")
        return
    _check_cells(book, grid, cell_head, cell_next, cell_prev, n)
    _check_calendar(data, book, due, heap, heap_t, heap_key, scalars, order, n)


def _check_state(
    masses: np.ndarray,
    spheres: np.ndarray,
    due: np.ndarray,
    heap_t: np.ndarray,
    scalars: np.ndarray,
    counts: np.ndarray,
    meta: np.ndarray,
) -> None:
    """The physical state and the core's numbers: finite, positive where they must be."""
    if not np.all(np.isfinite(masses) & (masses > 0)):
        _bad("a masses is not a finite number > 0")
    if not np.all(np.isfinite(spheres)):
        _bad("a position, velocity, time or radius is not finite")
    if np.any(spheres[:, core.RADIUS] < 0):
        _bad("a negative radius")
    if np.any(np.isnan(due)) or np.any(np.isnan(heap_t)):
        _bad("a predicted time is NaN")
    if not np.all(np.isfinite(scalars)) or scalars[core.F_W] <= 0 or scalars[core.F_WINDOW] < 0:
        _bad("the scalars (clock, grid, window) are not finite and positive where needed")
    if np.any(counts < 0):
        _bad("a negative counter")
    offset, since, rebase_on, container, box = meta.tolist()
    if not (np.isfinite(offset) and np.isfinite(since) and since >= 0):
        _bad("the time origin is not finite")
    if np.isnan(container) == np.isnan(box):
        _bad("neither or both of container and box")
    size = box if np.isnan(container) else container
    if not (np.isfinite(size) and size > 0):
        _bad("the container size is not a finite number > 0")
    if (scalars[core.F_BOX] if np.isnan(container) else scalars[core.F_CONTAINER]) != size:
        _bad("the container size disagrees with the core's")


def _check_rule(data: Mapping[str, np.ndarray], scalars: np.ndarray, n: int) -> None:
    """The collision rule: restitutions in (0, 1], ``t_c >= 0``, each sphere's last collision if inelastic."""
    if scalars.shape[0] <= core.F_RESTITUTION:
        if "hit_t" in data and np.asarray(data["hit_t"]).size:
            _bad("last collision times without a restitution coefficient")
        return  # (before the inelastic rule: elastic)
    e, ew, tc = scalars[core.F_RESTITUTION], scalars[core.F_WALL_RESTITUTION], scalars[core.F_TC]
    if not (0.0 < e <= 1.0 and 0.0 < ew <= 1.0 and tc >= 0.0 and scalars[core.F_DISSIPATED] >= 0.0):
        _bad("a restitution coefficient is not in (0, 1], or t_c or the energy dissipated is negative")
    kt = scalars[core.F_WALL_KT] if scalars.shape[0] > core.F_WALL_KT else 0.0
    heat = scalars[core.F_WALL_HEAT] if scalars.shape[0] > core.F_WALL_HEAT else 0.0
    if not (kt >= 0.0 and np.isfinite(kt) and np.isfinite(heat)):
        _bad("the wall temperature is negative or not finite, or the heat it gave is not finite")
    counts = np.asarray(data["counts"])
    if counts.shape[0] > core.C_WALL_DRAWS and not (
        0 <= counts[core.C_WALL_SEED] < 2**32 and counts[core.C_WALL_DRAWS] >= 0
    ):
        _bad("the thermal wall's seed is not in [0, 2^32) or its count of draws is negative")
    inelastic = e != 1.0 or ew != 1.0 or kt > 0.0
    hit_t = _array(data, "hit_t", np.float64, (n if inelastic else 0,))
    if np.any(np.isnan(hit_t)) or np.any(hit_t == np.inf):
        _bad("a last collision time is NaN or +inf")


def scalars_of(data: Mapping[str, np.ndarray]) -> np.ndarray:
    """The ``scalars`` array of ``data`` as float64 (empty if absent: the caller refuses that)."""
    try:
        return np.asarray(data.get("scalars", np.zeros(0)), dtype=np.float64).reshape(-1)
    except (ValueError, TypeError):
        return np.zeros(0)


def _check_bonds(book: np.ndarray, scalars: np.ndarray, counts: np.ndarray, n: int) -> None:
    """The steps and the bond tables: steps in order, species in range, entries in range and symmetric."""
    k, m = scalars[core.F_NSTEP], scalars[core.F_NSPECIES]
    if not (k == int(k) and 1 <= k <= core.STEP_MAX and m == int(m) and 1 <= m <= core.SPECIES_MAX):
        _bad(f"{k} steps and {m} species, expected 1 to {core.STEP_MAX} and 1 to {core.SPECIES_MAX}")
    m = int(m)
    nsteps = np.zeros((m, m), np.int64)
    for s in range(m):
        for t in range(m):
            base = core.F_STEP + (s * core.SPECIES_MAX + t) * core.STEP_STRIDE
            kst = scalars[base]
            if not (kst == int(kst) and 0 <= kst <= k):
                _bad(f"{kst} steps for species {s} and {t}")
            kst = int(kst)
            lams = scalars[base + 1 : base + 1 + 2 * kst : 2]
            us = scalars[base + 2 : base + 2 + 2 * kst : 2]
            if not (np.all(np.isfinite(lams)) and np.all(np.isfinite(us)) and np.all(lams > 1.0)) or np.any(
                np.diff(lams) >= 0.0
            ):
                _bad("the steps are not finite with lambda decreasing from the outermost and above 1")
            nsteps[s, t] = kst
    if not np.array_equal(nsteps, nsteps.T):
        _bad("the steps of a pair of species differ with its order")
    species = book[:, core.SPECIES]
    if np.any((species < 0) | (species >= m)):
        _bad("a species out of range")
    width = book.shape[1] - core.BONDS - 1
    count = book[:, core.BONDS]
    if np.any((count < 0) | (count > width)):
        _bad("a bond table longer than its row")
    held = np.arange(width)[None, :] < count[:, None]
    entries = book[:, core.BONDS + 1 :]
    rows = np.repeat(np.arange(n), count)
    partner, state = entries[held] >> 3, entries[held] & 7
    if np.any((partner < 0) | (partner >= n) | (partner == rows) | (state < 1)):
        _bad("a bond entry out of range")
    if np.any(state > nsteps[species[rows], species[np.clip(partner, 0, n - 1)]]):
        _bad("a bond entry out of range")
    there = np.sort((rows * n + partner) * 8 + state)
    back = np.sort((partner * n + rows) * 8 + state)
    if not np.array_equal(there, back) or np.any(np.diff(there // 8) == 0):
        _bad("the bond tables are not symmetric")


def _check_cells(
    book: np.ndarray,
    grid: np.ndarray,
    cell_head: np.ndarray,
    cell_next: np.ndarray,
    cell_prev: np.ndarray,
    n: int,
) -> None:
    """The cells: coordinates in the grid, and each cell's list holds exactly its spheres."""
    cxyz = book[:, core.CELL_X : core.CELL_Z + 1]
    if np.any((cxyz < 0) | (cxyz >= grid[None, :])):
        _bad("a cell coordinate outside the grid")
    if np.any(book[:, core.CELL] != (cxyz[:, 2] * grid[1] + cxyz[:, 1]) * grid[0] + cxyz[:, 0]):
        _bad("a cell index disagrees with its coordinates")
    for name, a in (("cell_head", cell_head), ("cell_next", cell_next), ("cell_prev", cell_prev)):
        if np.any((a < -1) | (a >= n)):
            _bad(f"{name!r} points outside the spheres")
    seen = np.zeros(n, bool)
    for cell in np.nonzero(cell_head >= 0)[0].tolist():
        j, before = int(cell_head[cell]), -1
        while j >= 0:
            if seen[j] or book[j, core.CELL] != cell or cell_prev[j] != before:
                _bad("the cell lists are inconsistent")
            seen[j] = True
            before, j = j, int(cell_next[j])
    if not np.all(seen):
        _bad("a sphere is in no cell list")


def _check_calendar(
    data: Mapping[str, np.ndarray],
    book: np.ndarray,
    due: np.ndarray,
    heap: np.ndarray,
    heap_t: np.ndarray,
    heap_key: np.ndarray,
    scalars: np.ndarray,
    order: np.ndarray,
    n: int,
) -> None:
    """The calendar: a heap over all spheres, each entry its sphere's earlier event (or crossing)."""
    ids = np.arange(n)
    if not np.array_equal(np.sort(heap), ids) or np.any(book[heap, core.HEAP_POS] != ids):
        _bad("the event calendar is not a permutation of the spheres")
    kind, partner = book[:, core.EVENT_KIND], book[:, core.PARTNER]
    stepped = scalars.shape[0] > core.F_NSTEP and scalars[core.F_NSTEP] != 0.0
    pair_kinds = (core.COLLISION, core.CAPTURE, core.RELEASE) if stepped else (core.COLLISION,)
    coll = np.isin(kind, pair_kinds)  # (every pair event ties as a collision)
    if np.any(~np.isin(kind, (core.REFLECTION, core.NONE, *pair_kinds))):
        _bad("an unknown event kind")
    if np.any(coll & ((partner < 0) | (partner >= n) | (partner == ids))):
        _bad("a collision partner outside the spheres")
    # (tie keys are on the input indices)
    mine, theirs = order, order[np.where(coll, partner, ids)]
    lo, hi = np.minimum(mine, theirs), np.maximum(mine, theirs)
    key = np.where(
        coll,
        tie_key(core.COLLISION, lo, hi, n),
        np.where(
            kind == core.REFLECTION, tie_key(core.REFLECTION, mine, -1, n), tie_key(core.NONE, n, n - 1, n)
        ),
    )
    if np.any(book[:, core.EVENT_KEY] != key):
        _bad("an event key disagrees with its event")
    shell = scalars[core.F_SHELL] if scalars.shape[0] > core.F_SHELL else 0.0
    if shell:  # neighbour lists
        if not shell > 1.0:
            _bad("the shell factor is not > 1")
        if "neighbours" not in data or book.shape[1] <= core.NEIGHBOURS:
            _bad("no neighbour lists")
        _check_lists(data, book, n)
        code = book[:, core.CROSS_FACE]  # (-1..5 before the box's faces were events: not read)
        box_face = (code >= core.BOX_FACE) & (code < core.BOX_FACE + 6)
        if np.any(((code < -1) | (code >= 6)) & ~box_face):
            _bad("an unknown box crossing")
    else:  # cells
        code = book[:, core.CROSS_FACE]
        if np.any((code < -1) | (code >= 6)) or np.any((code == -1) & (due[:, core.CROSS_T] < np.inf)):
            _bad("an unknown cell crossing")
    entry_t, entry_key = calendar_entries(due, book, n)
    pos = book[:, core.HEAP_POS]
    if np.any(heap_t[pos] != entry_t) or np.any(heap_key[pos] != entry_key):
        _bad("the event calendar disagrees with the predictions")
    k = np.arange(1, n)
    p = (k - 1) >> 1
    if np.any((heap_t[k] < heap_t[p]) | ((heap_t[k] == heap_t[p]) & (heap_key[k] < heap_key[p]))):
        _bad("the event calendar is out of order")


def _check_lists(data: Mapping[str, np.ndarray], book: np.ndarray, n: int) -> None:
    """The shells and neighbour lists: finite, in range, symmetric."""
    shells = _array(data, "shells", np.float64, (n, core.SHELL_COLS))
    neighbours = np.asarray(data["neighbours"])
    if neighbours.dtype != np.int32 or neighbours.ndim != 2 or neighbours.shape[0] != n:
        _bad(f"'neighbours' is {neighbours.dtype}{list(neighbours.shape)}, expected int32[{n}, k]")
    if not np.all(np.isfinite(shells)) or np.any(shells[:, core.REACH] < 0):
        _bad("a shell is not finite")
    length = book[:, core.NEIGHBOURS]
    if np.any((length < 0) | (length > neighbours.shape[1])):
        _bad("a neighbour list longer than its row")
    rows = np.repeat(np.arange(n), length)
    used = np.arange(neighbours.shape[1])[None, :] < length[:, None]
    entries = neighbours[used].astype(np.int64)
    j, code = entries >> 5, entries & 31
    if np.any((j < 0) | (j >= n) | (j == rows) | (code > 26)):
        _bad("a neighbour outside the spheres")
    there = np.sort(rows * n + j)
    back = np.sort(j * n + rows)
    if not np.array_equal(there, back) or np.any(np.diff(there) == 0):
        _bad("the neighbour lists are not symmetric")


def migrate(data: dict[str, np.ndarray]) -> tuple[dict[str, np.ndarray], bool]:
    """Versions 1 to 3's layouts brought to today's (version 4), array by array.

    Version 1 covers every layout written up to the layout by families
    (2026-12-01); they are told apart by which arrays they hold and their
    shapes, each step below named for what its layout lacked.  Returns the
    arrays and whether the core's kinetic sums must be computed afresh (the
    layouts before the transport tallies).
    """
    data = dict(data)
    n = len(data["masses"])
    if "images" not in data:  # before image counts
        data["images"] = np.zeros((n, 3), np.int64)
    if "shells" not in data:  # before the neighbour lists: cells alone
        data["shells"] = np.zeros((n, core.SHELL_COLS))
        data["neighbours"] = np.zeros((n, 0), np.int32)
    if "reorder" not in data:  # before the spheres were kept in Morton order
        data["reorder"] = np.array([0.0, 0.0])
    book = np.asarray(data["book"])
    if book.shape[1] < core.BOOK_COLS:  # before the lists' column or the input index
        saved_cols = book.shape[1]
        book = np.concatenate([book, np.zeros((n, core.BOOK_COLS - saved_cols), np.int64)], axis=1)
        if saved_cols <= core.ORIGIN:  # kept in the input order
            book[:, core.ORIGIN] = np.arange(n)
        data["book"] = book
    counts = np.asarray(data["counts"])
    saved_counts = counts.shape[0]
    if saved_counts < core.N_COUNTS:  # before the last counters
        counts = np.concatenate([counts, np.zeros(core.N_COUNTS - saved_counts, np.int64)])
    if saved_counts <= core.C_GRID:  # before the per-axis grid: a cube's
        counts[core.C_GRID : core.C_GRID + 3] = counts[core.C_CELLS]
    data["counts"] = counts
    scalars = np.asarray(data["scalars"], dtype=np.float64)
    saved = scalars.shape[0]
    if saved < core.N_SCALARS:  # before the last scalars
        scalars = np.concatenate([scalars, np.zeros(core.N_SCALARS - saved)])
    if saved <= core.F_T_KIN:  # before the transport tallies
        scalars[core.F_T_KIN] = scalars[core.F_CLOCK]
    if saved <= core.F_OFFSET:  # before the frozen-clock streak
        scalars[core.F_OFFSET] = float(data["meta"][0])
        scalars[core.F_STREAK] = scalars[core.F_CLOCK]
    if saved <= core.F_EDGE:  # before the per-axis grid: a cube's
        scalars[core.F_EDGE : core.F_EDGE + 3] = scalars[core.F_BOX]
        scalars[core.F_LOW : core.F_LOW + 3] = scalars[core.F_LO]
        scalars[core.F_WIDTH : core.F_WIDTH + 3] = scalars[core.F_W]
    if saved <= core.F_RESTITUTION:  # before the inelastic rule: elastic spheres and walls
        scalars[core.F_RESTITUTION] = scalars[core.F_WALL_RESTITUTION] = 1.0
    if "hit_t" not in data:
        data["hit_t"] = np.zeros(0)
    data["scalars"] = scalars
    return data, saved <= core.F_T_KIN


def calendar_entries(due: np.ndarray, book: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]:
    """Each sphere's calendar entry: the earlier of its event and its crossing, ``(times, keys)``."""
    order = book[:, core.ORIGIN] if book.shape[1] > core.ORIGIN else np.arange(n)
    cross_key = tie_key(core.CROSSING, order, -1, n)
    key = book[:, core.EVENT_KEY]
    ev_t, cr_t = due[:, core.EVENT_T], due[:, core.CROSS_T]
    first = (cr_t < ev_t) | ((cr_t == ev_t) & (cross_key < key))
    return np.where(first, cr_t, ev_t), np.where(first, cross_key, key)


def tie_key(kind: int, a: ArrayLike, b: ArrayLike, n: int) -> np.ndarray:
    """The core's tie key, on arrays (its Python source, not a second copy)."""
    return core._key.py_func(kind, a, b, n)

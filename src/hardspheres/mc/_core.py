"""The compiled straight event-chain core: O(1) work per event, with cells.

Private: use :class:`hardspheres.mc.EventChain`.  Everything here is
numba-compiled (``cache=True``), without ``fastmath``, and the one root it
solves is :func:`hardspheres.physics.pair_time_within`'s, called with the
active sphere's unit velocity along the chain's axis.

The algorithm (Bernard, Krauth and Wilson, PRE 80, 056704 (2009)):

* A **chain** picks one sphere at random, the *active* one, and moves it
  along ``+e_a`` (``a`` the chain's axis: x, y, (z), x, ... from one chain
  to the next, as in Li et al.'s straight ECMC).  When it touches a sphere
  ``j`` it stops there (a *lifting event*) and ``j`` moves on, until the
  chain has moved a total distance ``chain_length``.  Every move is the
  exact distance to the next contact: no overlap is ever made.
* The **lifting distance** of ``i`` moving along ``+e`` toward ``j`` is the
  smaller root of ``|dr - s e|^2 = sigma^2`` (``dr = r_j - r_i``, ``b = dr
  . e > 0``): ``s = c / (b + sqrt(sigma^2 - perp^2))`` with ``c = |dr|^2 -
  sigma^2`` and ``perp^2`` the square of ``dr``'s components across ``e``.
  That is :func:`~hardspheres.physics.pair_time_within` with ``r_i - r_j``
  and ``v_i - v_j = e``: no subtraction of nearly equal numbers, and far
  from contact its discriminant is ``sigma^2 - perp^2`` formed from the
  perpendicular components directly (docs/numerics.md, "The lifting
  distance").  A pair with ``perp^2 >= sigma^2`` never meets (a graze is
  no contact).
* **The image ahead.**  In a periodic box the sphere ``j`` met first is
  ``j``'s first image *ahead* of ``i``: ``b = x_j - x_i``, plus the side if
  that is not positive (both centres are wrapped into ``[-L/2, L/2)``);
  across the axis the nearest image.  So a chain may be longer than the box.
* **Cells.**  A grid of at least three cells per axis, each at least the
  largest contact distance wide, so a sphere ``j`` that ``i`` can touch
  lies in the three rows (nine in 3-D) around ``i``'s along the axis.  The
  search scans the columns ahead of ``i``, one at a time, and stops when
  the nearest contact found (or the chain's end) is nearer than anything
  in the next column could be.  The cell index is monotonic in the
  coordinate (floating-point rounding is), so a sphere in an earlier
  column is behind ``i``.
* **Ties** order by ``(s, j)``: the least distance, then the lowest index.
  So the result does not depend on the order in which the cells are
  scanned, and :func:`run` with ``brute=True`` (every ``j`` of the system
  tried, no cells) gives the same bits.
* **The pressure tallies.**  For each axis: the sum of the lifting
  separations ``x_j - x_i = sqrt(sigma^2 - perp^2)`` at contact, and the
  total chain displacement, both Neumaier-compensated.  ``beta P_aa = (N/V)
  (1 + lifts_a / displacement_a)`` (Li et al., J. Chem. Phys. 157, 234111
  (2022), Eq. 20-21).

The random numbers are SplitMix64 (Steele, Lea and Flood, OOPSLA 2014), one
``uint64`` of state kept with the arrays, so a checkpoint resumes bit for
bit.

The arrays (owned by :class:`~hardspheres.mc.chain.EventChain`):

    pos     float64 (N, d)  centres, wrapped into [-L/2, L/2) per axis [length]
    radii   float64 (N,)    [length]
    images  int64   (N, d)  box crossings per axis
    sides   float64 (d,)    the box [length]
    scale   float64 (d,)    cells per length, ``ncell / sides``
    ncell   int64   (d,)    cells per axis (>= 3)
    members int32   (C, 1 + cap) per cell: its count, then its spheres (one
                            cache line for a cell of up to 15)
    cell    int64   (N,)    each sphere's cell
    slot    int64   (N,)    its place in ``members``
    ints    int64   (N_INTS,)   active sphere (-1: between chains), events, chains
    floats  float64 (N_FLOATS,) distance left in the chain, chain length
    tally   float64 (4, d)  lift sums, their compensations, displacements, theirs
    rng     uint64  (1,)    SplitMix64 state
    axes    ((),) * d       the dimension as a type: ``len(axes)`` folds at compile time
"""

import hashlib
import math
import os

import numba
import numba.core.cpu
import numpy as np

from .. import physics
from ..core import _core as edmd  # registers physics' kernels with numba

INF = math.inf

#: ``ints``: the active sphere (-1 between chains), events (lifts) and chains done.
I_ACTIVE, I_EVENTS, I_CHAINS = range(3)
N_INTS = 3
#: ``floats``: what is left of the chain in progress, the chain length [length].
F_LEFT, F_LENGTH = range(2)
N_FLOATS = 2
#: ``tally`` rows.
T_LIFT, T_LIFT_C, T_DISP, T_DISP_C = range(4)

#: Why :func:`run` returned.
DONE = 0  # the events or chains asked for are done
ROWS_FULL = 1  # the sample buffer is full: take the rows and call again
CELL_FULL = 2  # a cell would overflow: grow ``members`` and call again (nothing was moved)

#: The column scan stops when the next column's spheres are surely farther
#: than the best contact: its edge minus ``SCAN_TOL`` times the side
#: (covers the rounding of the cell index and of the edge, a few ulps).
SCAN_TOL = 2.0**-40

#: A pair whose lead along the axis, less its contact distance, exceeds the
#: best lift by more than ``SKIP`` times their sum is not solved: its lift is
#: at least that difference, and the kernel's rounding is below ``100 u``
#: of it (so it could not have come out equal to the best: the tie rule, and
#: the brute force's agreement, are kept).
SKIP = 1e-12

# SplitMix64's constants
_GAMMA = np.uint64(0x9E3779B97F4A7C15)
_MIX1 = np.uint64(0xBF58476D1CE4E5B9)
_MIX2 = np.uint64(0x94D049BB133111EB)
_S30 = np.uint64(30)
_S27 = np.uint64(27)
_S31 = np.uint64(31)
_S11 = np.uint64(11)


def _cache_dir():
    """Where numba caches this module's machine code: keyed to its source and the kernels'."""
    if os.environ.get("NUMBA_CACHE_DIR"):
        return numba.config.CACHE_DIR
    digest = hashlib.sha256()
    for path in (__file__, physics.__file__):
        with open(path, "rb") as fh:
            digest.update(fh.read())
    return os.path.join(os.path.dirname(__file__), "__pycache__", f"numba-{digest.hexdigest()[:16]}")


_CACHE_DIR = _cache_dir()


# numba's private switch for its runtime, as in the event core: nothing here
# allocates, and without the runtime no array is reference-counted as it is
# passed on (24 atomic decrements in the chain loop with it, 1187 instructions
# per lift at N = 870 under cachegrind)
_NO_NRT = {"_nrt": False} if hasattr(numba.core.cpu.CPUTargetOptions, "_nrt") else {}


def _compiler(**options):
    """``njit(cache=True, **options)`` caching in :data:`_CACHE_DIR` (no fastmath, no runtime)."""

    def decorate(fn):
        saved = numba.config.CACHE_DIR
        numba.config.CACHE_DIR = _CACHE_DIR
        try:
            return numba.njit(cache=True, nogil=True, error_model="numpy", **_NO_NRT, **options)(fn)
        finally:
            numba.config.CACHE_DIR = saved

    return decorate


_jit = _compiler()
_kernel = _compiler(inline="always")
_pair_time_within = edmd.pair_time_within


@_kernel
def next_u64(rng):
    """SplitMix64: the next 64 random bits (``rng[0]`` advanced)."""
    s = rng[0] + _GAMMA
    rng[0] = s
    z = (s ^ (s >> _S30)) * _MIX1
    z = (z ^ (z >> _S27)) * _MIX2
    return z ^ (z >> _S31)


@_kernel
def below(rng, n):
    """A uniform integer in ``[0, n)`` from 53 random bits (bias below ``n 2^-53``)."""
    u = np.float64(next_u64(rng) >> _S11) * (1.0 / 9007199254740992.0)
    k = np.int64(u * n)
    return k if k < n else n - 1


@_kernel
def lift(dxa, dp1, dp2, sigma, horizon, axes):
    """Distance ``i`` moves along the axis before touching ``j`` (``inf``: never, or past ``horizon``).

    ``dxa > 0``: ``j``'s lead along the axis (the image ahead); ``dp1, dp2``:
    ``r_j - r_i`` across it (nearest image; ``dp2`` unread in 2-D);
    ``sigma``: the contact distance [length].
    """
    if len(axes) == 2:
        perp2 = dp1 * dp1
    else:
        perp2 = dp1 * dp1 + dp2 * dp2
    if perp2 >= sigma * sigma:
        return INF
    return _pair_time_within(-dxa, -dp1, -dp2, 1.0, 0.0, 0.0, sigma, horizon, len(axes) == 2)


@_kernel
def ahead(xj, xi, side):
    """``j``'s lead along the axis: ``x_j - x_i``, plus ``side`` if not positive."""
    d = xj - xi
    if d <= 0.0:
        d += side
    return d


@_kernel
def across(xj, xi, side):
    """``x_j - x_i`` to the nearest image, in ``[-side/2, side/2]``."""
    d = xj - xi
    if d > 0.5 * side:
        d -= side
    elif d < -0.5 * side:
        d += side
    return d


@_kernel
def cell_coord(x, side, scale, n):
    """The cell of coordinate ``x`` in ``[-side/2, side/2)`` along an axis of ``n`` cells.

    ``(x + side/2) scale``, rounded down, with ``scale = n / side`` (computed
    once, :func:`hardspheres.mc.chain.EventChain` keeps it): monotonic in ``x``
    (so a sphere in an earlier column is behind), the same bits wherever it is
    computed.
    """
    c = np.int64((x + 0.5 * side) * scale)
    if c < 0:
        return 0
    if c >= n:
        return n - 1
    return c


@_kernel
def cell_of(pos, i, sides, scale, ncell, axes):
    """The flat cell index of sphere ``i``."""
    c = cell_coord(pos[i, 0], sides[0], scale[0], ncell[0]) * ncell[1] + cell_coord(
        pos[i, 1], sides[1], scale[1], ncell[1]
    )
    if len(axes) == 3:
        c = c * ncell[2] + cell_coord(pos[i, 2], sides[2], scale[2], ncell[2])
    return c


@_jit
def build_cells(pos, sides, scale, ncell, members, cell, slot, axes):
    """Put every sphere in its cell; returns the largest count (> the capacity: nothing valid)."""
    members[:, 0] = 0
    cap = members.shape[1] - 1
    most = 0
    for i in range(pos.shape[0]):
        c = cell_of(pos, i, sides, scale, ncell, axes)
        k = members[c, 0]
        if k < cap:
            members[c, 1 + k] = i
        cell[i] = c
        slot[i] = k
        members[c, 0] = k + 1
        if k + 1 > most:
            most = k + 1
    return most


@_kernel
def consider(j, xa, x1, x2, ri, a, p1, p2, pos, radii, sides, best, jbest, axes):
    """``(s, j)`` of the lift toward ``j`` if it beats ``(best, jbest)`` by the tie rule, else those.

    ``xa, x1, x2``: the moving sphere's centre along the axis and across it
    (``x2`` unread in 2-D); ``ri``: its radius [length].
    """
    dxa = ahead(pos[j, a], xa, sides[a])
    sigma = ri + radii[j]
    if dxa - sigma > best + SKIP * (dxa + sigma):
        return best, jbest  # the lift is at least dxa - sigma: surely beyond the best
    dp1 = across(pos[j, p1], x1, sides[p1])
    dp2 = 0.0
    if len(axes) == 3:
        dp2 = across(pos[j, p2], x2, sides[p2])
    s = lift(dxa, dp1, dp2, sigma, best, axes)
    if s < best or (s == best and jbest >= 0 and j < jbest):
        return s, j
    return best, jbest


@_kernel
def stride(b, ncell, axes):
    """The step of the flat cell index along axis ``b``."""
    if b == len(axes) - 1:
        return np.int64(1)
    if b == 0 and len(axes) == 3:
        return ncell[1] * ncell[2]
    return ncell[len(axes) - 1]


@_kernel
def wrapped_row(r, n):
    """Row ``r`` of ``n`` (``-1`` and ``n`` wrapped around)."""
    if r < 0:
        return r + n
    if r >= n:
        return r - n
    return r


@_kernel
def search_cells(i, a, left, pos, radii, rmax, sides, scale, ncell, members, axes):
    """The next lift of ``i`` along ``a`` within ``left``: ``(s, j)``, ``j = -1`` for none (cells)."""
    d = len(axes)
    p1 = (a + 1) % d
    p2 = (a + 2) % d
    na = ncell[a]
    n1 = ncell[p1]
    n2 = ncell[p2] if d == 3 else 1
    side = sides[a]
    ca = cell_coord(pos[i, a], side, scale[a], na)
    c1 = cell_coord(pos[i, p1], sides[p1], scale[p1], n1)
    c2 = cell_coord(pos[i, p2], sides[p2], scale[p2], n2) if d == 3 else 0
    # the strides of the flat index along a, p1, p2
    sa = stride(a, ncell, axes)
    s1 = stride(p1, ncell, axes)
    s2 = stride(p2, ncell, axes) if d == 3 else 0
    vlo, vhi = (-1, 2) if d == 3 else (0, 1)
    width = side / na
    reach = radii[i] + rmax
    tol = SCAN_TOL * side
    best = left
    jbest = np.int64(-1)
    xi, x1, ri = pos[i, a], pos[i, p1], radii[i]
    x2 = pos[i, p2] if d == 3 else 0.0
    # the rows around i across the axis, as offsets of the flat index (the same for every column)
    o_lo, o_mid, o_hi = wrapped_row(c1 - 1, n1) * s1, c1 * s1, wrapped_row(c1 + 1, n1) * s1
    q_lo, q_mid, q_hi = 0, 0, 0
    if d == 3:
        q_lo, q_mid, q_hi = wrapped_row(c2 - 1, n2) * s2, c2 * s2, wrapped_row(c2 + 1, n2) * s2
    for k in range(na):
        col = ca + k
        if col >= na:
            col -= na
        base = col * sa
        for u in range(3):
            ou = o_lo if u == 0 else (o_mid if u == 1 else o_hi)
            for v in range(vlo, vhi):
                ov = q_mid if v == 0 else (q_lo if v < 0 else q_hi)
                c = base + ou + ov
                for m in range(1, 1 + members[c, 0]):
                    j = np.int64(members[c, m])
                    if j != i:
                        best, jbest = consider(
                            j, xi, x1, x2, ri, a, p1, p2, pos, radii, sides, best, jbest, axes
                        )
        # everything in the columns after k is at least this far
        edge = (ca + k + 1) * width - 0.5 * side
        if best <= edge - xi - reach - tol:
            break
    return best, jbest


@_kernel
def search_all(i, a, left, pos, radii, sides, axes):
    """:func:`search_cells` by brute force: every sphere tried (the reference)."""
    d = len(axes)
    p1 = (a + 1) % d
    p2 = (a + 2) % d
    best = left
    jbest = np.int64(-1)
    xa, x1, ri = pos[i, a], pos[i, p1], radii[i]
    x2 = pos[i, p2] if d == 3 else 0.0
    for j in range(pos.shape[0]):
        if j != i:
            best, jbest = consider(j, xa, x1, x2, ri, a, p1, p2, pos, radii, sides, best, jbest, axes)
    return best, jbest


@_kernel
def separation(i, j, a, pos, radii, sides, axes):
    """``x_j - x_i`` along ``a`` at contact, ``sqrt(sigma^2 - perp^2)``, from the components across."""
    d = len(axes)
    p1 = (a + 1) % d
    dp1 = across(pos[j, p1], pos[i, p1], sides[p1])
    perp2 = dp1 * dp1
    if d == 3:
        p2 = (a + 2) % d
        dp2 = across(pos[j, p2], pos[i, p2], sides[p2])
        perp2 += dp2 * dp2
    sigma = radii[i] + radii[j]
    q = sigma * sigma - perp2
    return math.sqrt(q) if q > 0.0 else 0.0


@_kernel
def add(tally, row, a, x):
    """``tally[row, a] += x``, Neumaier-compensated (the compensation in ``tally[row + 1, a]``)."""
    s = tally[row, a]
    t = s + x
    if abs(s) >= abs(x):
        tally[row + 1, a] += (s - t) + x
    else:
        tally[row + 1, a] += (x - t) + s
    tally[row, a] = t


@_kernel
def wrapped(x, side, image):
    """``(x, image)`` with ``x`` moved by whole sides into ``[-side/2, side/2)``."""
    half = 0.5 * side
    if x >= half:
        k = math.floor((x + half) / side)
        x -= k * side
        image += np.int64(k)
        while x >= half:
            x -= side
            image += 1
        while x < -half:
            x += side
            image -= 1
    return x, image


@_kernel
def move(i, a, s, pos, images, sides, scale, ncell, members, cell, slot, axes):
    """Move ``i`` by ``s`` along ``a`` and into its new cell; ``False`` if that cell is full (nothing moved)."""
    x, image = wrapped(pos[i, a] + s, sides[a], images[i, a])
    old = pos[i, a]
    pos[i, a] = x
    c = cell_of(pos, i, sides, scale, ncell, axes)
    c0 = cell[i]
    if c != c0:
        k = members[c, 0]
        if k >= members.shape[1] - 1:
            pos[i, a] = old
            return False
        # out of the old cell: its last member takes i's slot
        last = members[c0, 0] - 1
        q = slot[i]
        moved = members[c0, 1 + last]
        members[c0, 1 + q] = moved
        slot[moved] = q
        members[c0, 0] = last
        members[c, 1 + k] = i
        members[c, 0] = k + 1
        slot[i] = k
        cell[i] = c
    images[i, a] = image
    return True


@_jit
def run(
    pos,
    radii,
    images,
    sides,
    scale,
    ncell,
    members,
    cell,
    slot,
    ints,
    floats,
    tally,
    rng,
    axes,
    max_events,
    max_chains,
    every,
    origin,
    rows,
    brute,
):
    """Run chains until ``max_events`` lifts or ``max_chains`` chains end, whichever first.

    Longer than 80 lines with this docstring: the one loop, with its stops.

    A chain in progress when the events run out stays in progress (``ints``
    and ``floats`` hold it).  After every ``every`` rounds of ``d`` chains
    (one per axis) counted from ``origin`` chains the running totals are
    written to the next row of ``rows``: ``events, chains, lift sums (d), displacements (d)``.

    Returns:
        ``(reason, rows written)``: :data:`DONE`, :data:`ROWS_FULL` or
        :data:`CELL_FULL`.
    """
    d = len(axes)
    n = pos.shape[0]
    rmax = 0.0
    for k in range(n):
        rmax = max(rmax, radii[k])
    length = floats[F_LENGTH]
    written = 0
    events = 0
    chains = 0
    while events < max_events and chains < max_chains:
        if ints[I_ACTIVE] < 0:  # a new chain: a sphere at random, the next axis
            ints[I_ACTIVE] = below(rng, n)
            floats[F_LEFT] = length
        i = ints[I_ACTIVE]
        a = ints[I_CHAINS] % d
        left = floats[F_LEFT]
        if brute:
            s, j = search_all(i, a, left, pos, radii, sides, axes)
        else:
            s, j = search_cells(i, a, left, pos, radii, rmax, sides, scale, ncell, members, axes)
        if not move(i, a, s, pos, images, sides, scale, ncell, members, cell, slot, axes):
            return CELL_FULL, written
        add(tally, T_DISP, a, s)
        if j >= 0:  # a lift: j moves on
            add(tally, T_LIFT, a, separation(i, j, a, pos, radii, sides, axes))
            floats[F_LEFT] = left - s
            ints[I_ACTIVE] = j
            ints[I_EVENTS] += 1
            events += 1
        else:  # the chain's end
            floats[F_LEFT] = 0.0
            ints[I_ACTIVE] = -1
            ints[I_CHAINS] += 1
            chains += 1
            if (ints[I_CHAINS] - origin) % (d * every) == 0:
                r = rows[written]
                r[0] = ints[I_EVENTS]
                r[1] = ints[I_CHAINS]
                for b in range(d):
                    r[2 + b] = tally[T_LIFT, b] + tally[T_LIFT_C, b]
                    r[2 + d + b] = tally[T_DISP, b] + tally[T_DISP_C, b]
                written += 1
                if written >= rows.shape[0]:
                    return ROWS_FULL, written
    return DONE, written


@_jit
def max_overlap(pos, radii, sides, scale, ncell, members, axes):
    """The largest ``(sigma - |r|) / sigma`` over neighbouring pairs (``-inf``: no pair near), with cells."""
    d = len(axes)
    n2 = ncell[2] if d == 3 else 1
    wlo, whi = (-1, 2) if d == 3 else (0, 1)
    worst = -INF
    for i in range(pos.shape[0]):
        c0 = cell_coord(pos[i, 0], sides[0], scale[0], ncell[0])
        c1 = cell_coord(pos[i, 1], sides[1], scale[1], ncell[1])
        c2 = cell_coord(pos[i, 2], sides[2], scale[2], n2) if d == 3 else 0
        for u in range(-1, 2):
            for v in range(-1, 2):
                for w in range(wlo, whi):
                    x = (c0 + u) % ncell[0]
                    y = (c1 + v) % ncell[1]
                    c = x * ncell[1] + y
                    if d == 3:
                        c = c * n2 + (c2 + w) % n2
                    for m in range(1, 1 + members[c, 0]):
                        j = members[c, m]
                        if j <= i:
                            continue
                        r2 = 0.0
                        for b in range(d):
                            e = across(pos[j, b], pos[i, b], sides[b])
                            r2 += e * e
                        sigma = radii[i] + radii[j]
                        if sigma > 0.0:
                            worst = max(worst, (sigma - math.sqrt(r2)) / sigma)
    return worst

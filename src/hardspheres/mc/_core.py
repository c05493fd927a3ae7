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
    ints    int64   (N_INTS,)   active sphere (-1: between chains), events, chains, cell steps
    floats  float64 (N_FLOATS,) distance left in the chain, chain length
    tally   float64 (4, d)  lift sums, their compensations, displacements, theirs
    rng     uint64  (1,)    SplitMix64 state
    axes    ((),) * d       the dimension as a type: ``len(axes)`` folds at compile time
"""

import math

import numba
import numba.core.cpu
import numpy as np

from .. import physics
from .._jitcache import cache_dir, cached_compiler, source_digest
from ..core import _core as edmd  # registers physics' kernels with numba

INF = math.inf

#: ``ints``: the active sphere (-1 between chains), events (lifts), chains done, and (chains in
#: any direction) the steps that ended at a cell's edge.
I_ACTIVE, I_EVENTS, I_CHAINS, I_STEPS = range(4)
N_INTS = 4
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


# cached as the event core is (hardspheres._jitcache): keyed to this file and the kernels
_DIGEST = source_digest(__file__, physics.__file__)
_CACHE_DIR = cache_dir(__file__, _DIGEST)
_cached = cached_compiler(__file__, _DIGEST)


# numba's private switch for its runtime, as in the event core: nothing here
# allocates, and without the runtime no array is reference-counted as it is
# passed on (24 atomic decrements in the chain loop with it, 1187 instructions
# per lift at N = 870 under cachegrind)
_NO_NRT = {"_nrt": False} if hasattr(numba.core.cpu.CPUTargetOptions, "_nrt") else {}


def _compiler(**options):
    """``njit(**options)`` cached in :data:`_CACHE_DIR` (no fastmath, no runtime)."""
    return _cached(nogil=True, error_model="numpy", **_NO_NRT, **options)


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


# ---- chains in any direction: Newtonian and forward event chains --------------------------------
#
# The active sphere moves along a vector ``v`` (Newtonian: its own velocity;
# forward: a unit direction), one *step* at a time: a step ends at the next
# lift, at the chain's end or where the centre leaves its cell (plus
# :data:`STEP_SLACK` of a cell), so every sphere it can touch lies in the
# ``3^d`` cells around its own, each at the image of ``j`` that lies there.
# Tallies: per axis, the lifts' ``(r_j - r_i)_a v_a`` and the steps'
# ``t v_a^2`` (docs/numerics.md, "The pressure of chains in any direction").
# Vectors are passed as scalars ``v0, v1, v2`` (``v2`` zero in 2-D): no
# array is made in the loop.

#: The variants (``EventChain(variant=...)``).
STRAIGHT, NEWTONIAN, FORWARD = range(3)

#: A step may carry the centre this fraction of a cell past the cell's edge
#: (so it leaves the cell whatever the rounding): far below the cells' margin
#: over the largest contact distance (1e-9 of it), so no contact is missed.
STEP_SLACK = 2.0**-36


@_kernel
def uniform(rng):
    """A uniform float in ``(0, 1]`` from 53 random bits."""
    return (np.float64(next_u64(rng) >> _S11) + 1.0) * (1.0 / 9007199254740992.0)


@_kernel
def gaussian(rng):
    """A standard normal number (Box-Muller, the cosine branch)."""
    u = uniform(rng)
    w = uniform(rng)
    return math.sqrt(-2.0 * math.log(u)) * math.cos(2.0 * math.pi * w)


@_kernel
def draw_velocity(vel, k, rng, unit, axes):
    """``vel[k]``: Gaussian components of variance ``1/d`` (mean square speed 1), or normalised (``unit``)."""
    d = len(axes)
    while True:
        q = 0.0
        for b in range(d):
            x = gaussian(rng) * math.sqrt(1.0 / d)
            vel[k, b] = x
            q += x * x
        if not unit:
            return
        if q > 1e-200:
            r = math.sqrt(q)
            for b in range(d):
                vel[k, b] /= r
            return


@_kernel
def row_shift(c, u, n, side):
    """The neighbouring row ``c + u`` (``u`` in -1, 0, 1) wrapped, and the image shift of its spheres [length]."""
    r = c + u
    if r < 0:
        return r + n, -side
    if r >= n:
        return r - n, side
    return r, 0.0


@_kernel
def consider_vec(j, i, sx, sy, sz, v0, v1, v2, pos, radii, best, jbest, axes):
    """``(t, j)`` of the contact of ``i`` (moving along ``v``) with ``j``'s image shifted by ``s``, if it beats the best."""
    d = len(axes)
    dx = pos[j, 0] + sx - pos[i, 0]
    dy = pos[j, 1] + sy - pos[i, 1]
    dz = pos[j, 2] + sz - pos[i, 2] if d == 3 else 0.0
    t = _pair_time_within(-dx, -dy, -dz, v0, v1, v2, radii[i] + radii[j], best, d == 2)
    if t < best or (t == best and jbest >= 0 and j < jbest):
        return t, j
    return best, jbest


@_kernel
def exit_time(i, v0, v1, v2, pos, sides, scale, ncell, axes):
    """Time until ``i``'s centre leaves its cell along ``v``, plus :data:`STEP_SLACK` of a cell."""
    t = INF
    slack = INF
    for b in range(len(axes)):
        vb = v0 if b == 0 else (v1 if b == 1 else v2)
        if vb == 0.0:
            continue
        width = sides[b] / ncell[b]
        c = cell_coord(pos[i, b], sides[b], scale[b], ncell[b])
        if vb > 0.0:
            tb = ((c + 1) * width - 0.5 * sides[b] - pos[i, b]) / vb
        else:
            tb = (c * width - 0.5 * sides[b] - pos[i, b]) / vb
        t = min(t, max(tb, 0.0))
        slack = min(slack, STEP_SLACK * width / abs(vb))
    return t + slack


@_kernel
def image_row(cb, kb, nb, side):
    """The shift of the image of a sphere in row ``kb`` that lies in the rows around ``cb`` (``nan``: none)."""
    for u in range(-1, 2):
        r, s = row_shift(cb, u, nb, side)
        if r == kb:
            return s
    return math.nan


@_kernel
def search_near(i, v0, v1, v2, horizon, pos, radii, sides, scale, ncell, members, cell, brute, axes):
    """The first contact of ``i`` moving along ``v`` within ``horizon``: ``(t, j, sx, sy, sz)``.

    ``j = -1``: none.  Candidates are the spheres in the ``3^d`` cells
    around ``i``'s, each at its image in that block (shift ``s``); with
    ``brute`` every sphere is tried and its image found from its cell: the
    same candidates, the same bits.
    """
    d = len(axes)
    n0, n1 = ncell[0], ncell[1]
    n2 = ncell[2] if d == 3 else 1
    c0 = cell_coord(pos[i, 0], sides[0], scale[0], n0)
    c1 = cell_coord(pos[i, 1], sides[1], scale[1], n1)
    c2 = cell_coord(pos[i, 2], sides[2], scale[2], n2) if d == 3 else 0
    best = horizon
    jbest = np.int64(-1)
    bx, by, bz = 0.0, 0.0, 0.0
    if brute:
        for j in range(pos.shape[0]):
            if j == i:
                continue
            cj = cell[j]  # j's row along each axis, from its flat index
            sz = 0.0
            if d == 3:
                sz = image_row(c2, cj % n2, n2, sides[2])
                cj //= n2
            sy = image_row(c1, cj % n1, n1, sides[1])
            sx = image_row(c0, cj // n1, n0, sides[0])
            if math.isnan(sx) or math.isnan(sy) or math.isnan(sz):
                continue
            t, jj = consider_vec(j, i, sx, sy, sz, v0, v1, v2, pos, radii, best, jbest, axes)
            if jj != jbest or t != best:
                best, jbest, bx, by, bz = t, jj, sx, sy, sz
        return best, jbest, bx, by, bz
    wlo, whi = (-1, 2) if d == 3 else (0, 1)
    for u in range(-1, 2):
        r0, sx = row_shift(c0, u, n0, sides[0])
        for v in range(-1, 2):
            r1, sy = row_shift(c1, v, n1, sides[1])
            for w in range(wlo, whi):
                sz = 0.0
                c = r0 * n1 + r1
                if d == 3:
                    r2, sz = row_shift(c2, w, n2, sides[2])
                    c = c * n2 + r2
                for m in range(1, 1 + members[c, 0]):
                    j = np.int64(members[c, m])
                    if j != i:
                        t, jj = consider_vec(j, i, sx, sy, sz, v0, v1, v2, pos, radii, best, jbest, axes)
                        if jj != jbest or t != best:
                            best, jbest, bx, by, bz = t, jj, sx, sy, sz
    return best, jbest, bx, by, bz


@_kernel
def wrapped_any(x, side, image):
    """``(x, image)`` with ``x`` moved by whole sides into ``[-side/2, side/2)``, either way."""
    half = 0.5 * side
    if x >= half or x < -half:
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
def move_vec(i, t, v0, v1, v2, pos, images, sides, scale, ncell, members, cell, slot, axes):
    """Move ``i`` by ``t v`` and into its new cell; ``False`` if that cell is full (nothing moved)."""
    d = len(axes)
    x0, m0 = wrapped_any(pos[i, 0] + t * v0, sides[0], images[i, 0])
    x1, m1 = wrapped_any(pos[i, 1] + t * v1, sides[1], images[i, 1])
    x2, m2 = 0.0, np.int64(0)
    if d == 3:
        x2, m2 = wrapped_any(pos[i, 2] + t * v2, sides[2], images[i, 2])
    c = cell_coord(x0, sides[0], scale[0], ncell[0]) * ncell[1] + cell_coord(x1, sides[1], scale[1], ncell[1])
    if d == 3:
        c = c * ncell[2] + cell_coord(x2, sides[2], scale[2], ncell[2])
    c0 = cell[i]
    if c != c0:
        k = members[c, 0]
        if k >= members.shape[1] - 1:
            return False
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
    pos[i, 0], pos[i, 1] = x0, x1
    images[i, 0], images[i, 1] = m0, m1
    if d == 3:
        pos[i, 2] = x2
        images[i, 2] = m2
    return True


@_kernel
def lift_newtonian(i, j, e0, e1, e2, vel, axes):
    """An elastic collision of equal masses along the unit normal ``e`` (i to j): the normal components swap."""
    d = len(axes)
    dot = (vel[j, 0] - vel[i, 0]) * e0 + (vel[j, 1] - vel[i, 1]) * e1
    if d == 3:
        dot += (vel[j, 2] - vel[i, 2]) * e2
    vel[i, 0] += e0 * dot
    vel[i, 1] += e1 * dot
    vel[j, 0] -= e0 * dot
    vel[j, 1] -= e1 * dot
    if d == 3:
        vel[i, 2] += e2 * dot
        vel[j, 2] -= e2 * dot


@_kernel
def lift_forward(i, j, e0, e1, e2, vel, rng, axes):
    """Forward lifting: ``j`` goes on along ``c e + sqrt(1 - c^2) t``, ``t`` the old direction's part across ``e``.

    ``c = v' . e`` is drawn with density proportional to ``c`` times its
    marginal under uniform directions, ``c (1 - c^2)^((d - 3)/2)`` on
    (0, 1]: ``c = sqrt(1 - u^2)`` in 2-D, ``sqrt(u)`` in 3-D (``u``
    uniform); the direction across ``e`` is kept (Michel, Durmus and
    Senecal, J. Comput. Graph. Stat. 29, 689 (2020)).
    """
    d = len(axes)
    a0, a1 = vel[i, 0], vel[i, 1]
    a2 = vel[i, 2] if d == 3 else 0.0
    par = a0 * e0 + a1 * e1 + a2 * e2
    t0, t1, t2 = a0 - par * e0, a1 - par * e1, a2 - par * e2
    tq = t0 * t0 + t1 * t1 + t2 * t2
    if tq <= 1e-300:  # head on (measure zero): across e, toward the axis e leans on least
        if d == 2:
            t0, t1 = -e1, e0
        elif abs(e0) <= abs(e1) and abs(e0) <= abs(e2):
            t0, t1, t2 = 1.0 - e0 * e0, -e0 * e1, -e0 * e2
        elif abs(e1) <= abs(e2):
            t0, t1, t2 = -e1 * e0, 1.0 - e1 * e1, -e1 * e2
        else:
            t0, t1, t2 = -e2 * e0, -e2 * e1, 1.0 - e2 * e2
        tq = t0 * t0 + t1 * t1 + t2 * t2
    tn = math.sqrt(tq)
    u = uniform(rng)
    if d == 2:
        c = math.sqrt((1.0 - u) * (1.0 + u))
        s = u
    else:
        c = math.sqrt(u)
        s = math.sqrt(1.0 - u)
    b0 = c * e0 + s * t0 / tn
    b1 = c * e1 + s * t1 / tn
    b2 = c * e2 + s * t2 / tn
    r = math.sqrt(b0 * b0 + b1 * b1 + b2 * b2)
    vel[j, 0] = b0 / r
    vel[j, 1] = b1 / r
    if d == 3:
        vel[j, 2] = b2 / r


@_jit
def run_free(
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
    vel,
    stamp,
    axes,
    variant,
    max_events,
    max_chains,
    every,
    origin,
    rows,
    brute,
):
    """:func:`run` for chains in any direction (:data:`NEWTONIAN`, :data:`FORWARD`).

    Longer than 80 lines with this docstring: the one loop, with its stops.

    ``vel (N, d)``: the velocities (Newtonian: ``vel[k]`` is fresh when
    ``stamp[k]`` is the chain's number, else drawn when first needed, the
    same law as drawing them all as the chain starts) or the active
    sphere's direction (forward, in ``vel[active]``).  The chain length is
    a time (Newtonian, mean square speed 1) or a distance (forward, unit
    speed).
    """
    d = len(axes)
    n = pos.shape[0]
    length = floats[F_LENGTH]
    written = 0
    events = 0
    chains = 0
    while events < max_events and chains < max_chains:
        if ints[I_ACTIVE] < 0:  # a new chain: a sphere at random, its velocity or direction at random
            k = below(rng, n)
            ints[I_ACTIVE] = k
            floats[F_LEFT] = length
            draw_velocity(vel, k, rng, variant == FORWARD, axes)
            stamp[k] = ints[I_CHAINS]
        i = ints[I_ACTIVE]
        v0, v1 = vel[i, 0], vel[i, 1]
        v2 = vel[i, 2] if d == 3 else 0.0
        left = floats[F_LEFT]
        horizon = min(left, exit_time(i, v0, v1, v2, pos, sides, scale, ncell, axes))
        t, j, sx, sy, sz = search_near(
            i, v0, v1, v2, horizon, pos, radii, sides, scale, ncell, members, cell, brute, axes
        )
        e0, e1, e2 = 0.0, 0.0, 0.0
        if j >= 0:  # the separation at contact, before i moves (its image may change)
            e0 = pos[j, 0] + sx - pos[i, 0] - t * v0
            e1 = pos[j, 1] + sy - pos[i, 1] - t * v1
            if d == 3:
                e2 = pos[j, 2] + sz - pos[i, 2] - t * v2
        if not move_vec(i, t, v0, v1, v2, pos, images, sides, scale, ncell, members, cell, slot, axes):
            return CELL_FULL, written
        add(tally, T_DISP, 0, t * v0 * v0)
        add(tally, T_DISP, 1, t * v1 * v1)
        if d == 3:
            add(tally, T_DISP, 2, t * v2 * v2)
        if j >= 0:  # a lift: j moves on
            add(tally, T_LIFT, 0, e0 * v0)
            add(tally, T_LIFT, 1, e1 * v1)
            if d == 3:
                add(tally, T_LIFT, 2, e2 * v2)
            r = math.sqrt(e0 * e0 + e1 * e1 + e2 * e2)
            e0, e1, e2 = e0 / r, e1 / r, e2 / r
            if variant == NEWTONIAN:
                if stamp[j] != ints[I_CHAINS]:
                    draw_velocity(vel, j, rng, False, axes)
                    stamp[j] = ints[I_CHAINS]
                lift_newtonian(i, j, e0, e1, e2, vel, axes)
            else:
                lift_forward(i, j, e0, e1, e2, vel, rng, axes)
            floats[F_LEFT] = left - t
            ints[I_ACTIVE] = j
            ints[I_EVENTS] += 1
            events += 1
        elif horizon < left:  # the centre left its cell: a step, and the chain goes on
            floats[F_LEFT] = left - t
            ints[I_STEPS] += 1
        else:  # the chain's end
            floats[F_LEFT] = 0.0
            ints[I_ACTIVE] = -1
            ints[I_CHAINS] += 1
            chains += 1
            if (ints[I_CHAINS] - origin) % (d * every) == 0:
                row = rows[written]
                row[0] = ints[I_EVENTS]
                row[1] = ints[I_CHAINS]
                for b in range(d):
                    row[2 + b] = tally[T_LIFT, b] + tally[T_LIFT_C, b]
                    row[2 + d + b] = tally[T_DISP, b] + tally[T_DISP_C, b]
                written += 1
                if written >= rows.shape[0]:
                    return ROWS_FULL, written
    return DONE, written

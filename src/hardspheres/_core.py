"""The compiled event core: O(log N) work per event.

Private: use :class:`hardspheres.engine.Engine` (or the public
:class:`hardspheres.Simulation`).  Everything here is numba-compiled, without
``fastmath``, from the scalar kernels of :mod:`hardspheres.physics`.

Design (the classic one-event-per-sphere scheme of Rapaport and
Lubachevsky, as in the fastest public codes):

* **Local times.**  Sphere ``i`` is stored as its centre at its own time
  ``t_i`` (the time of its last collision or reflection); its centre at time
  ``t`` is ``x_i + v_i (t - t_i)``.  An event touches only the spheres
  involved.  Each sphere's record is one 64-byte row of ``S``:
  ``x y z vx vy vz t_i R_i``.
* **Cells.**  A cubic grid of ``nc^3`` cells, each at least as wide as the
  largest contact distance, covers the container (or the periodic box); a
  sphere is predicted only against the spheres in the 27 cells around its
  own.  Leaving a cell is an event of its own; after it, only the 9 cells
  that came into reach are searched.
* **Calendar.**  Each sphere keeps its earliest collision or reflection
  (time, kind, partner, the partner's event count) and its next cell
  crossing; an indexed binary heap orders the spheres by the earlier of
  the two.  A prediction whose partner has had an event since is stale: it
  is dropped, and the sphere predicted afresh, when it reaches the top.
* **Predictions that do not depend on when they are made.**  A pair is
  predicted from the later of its two spheres' own times, a wall from the
  sphere's own time, with the lower index's centre minus the higher's: the
  brute-force reference (:mod:`hardspheres.reference`) does the same, so
  the two agree bit for bit.
* **Ties.**  Events order by ``(time, kind, i, j)``: reflections before
  collisions, lower index first.  With a simultaneity ``window > 0`` (the
  assignment's 1e-8 s), events less than ``window`` after the last one
  happen *at* its time, and whenever that time (the anchor) moves, every
  sphere whose event falls in the new window is predicted afresh
  (:func:`refresh_window`), so the tie order decides among them exactly as
  in the reference.  An event at the anchor's own instant changes no other
  prediction: only the spheres it touched are predicted again.
* **Events that would not end** stop the loop (see :func:`run`): a
  reflection that would change nothing, and a clock that does not advance
  over ``physics.frozen_limit(N)`` collisions and reflections.
* **Time origin.**  :func:`rebase` moves the time origin to the clock, so
  long runs keep the precision of short ones.
"""

import hashlib
import os

import numba
import numba.core.cpu
import numba.extending
import numpy as np

from . import events, physics


def _cache_dir():
    """Where numba caches this module's machine code, keyed to the kernels' source.

    numba's on-disk cache checks only the stamp of the file that defines a
    function, so loops compiled with an older ``physics.py`` inlined would
    be reused after it changed.  A directory named after a hash of both
    files keeps them apart.  ``NUMBA_CACHE_DIR``, if set, is the user's
    choice and is left alone.
    """
    if os.environ.get("NUMBA_CACHE_DIR"):
        return numba.config.CACHE_DIR
    digest = hashlib.sha256()
    for path in (__file__, physics.__file__, events.__file__):
        with open(path, "rb") as fh:
            digest.update(fh.read())
    return os.path.join(os.path.dirname(__file__), "__pycache__",
                        f"numba-{digest.hexdigest()[:16]}")


_CACHE_DIR = _cache_dir()

# numba's private switch for its runtime (see below); a numba without it
# still compiles the core, only slower
_NO_NRT = ({"_nrt": False} if hasattr(numba.core.cpu.CPUTargetOptions, "_nrt") else {})


def _compiler(**options):
    """``njit(cache=True, **options)`` caching in :data:`_CACHE_DIR`."""
    def decorate(fn):
        saved = numba.config.CACHE_DIR
        numba.config.CACHE_DIR = _CACHE_DIR  # read when the cache is set up
        try:
            return numba.njit(cache=True, nogil=True, error_model="numpy", **_NO_NRT,
                              **options)(fn)
        finally:
            numba.config.CACHE_DIR = saved
    return decorate


# error_model="numpy": IEEE division (x/0 = inf) without a zero check per division.
# _nrt=False: nothing here allocates, and without numba's runtime no array
# argument is reference-counted (an atomic increment and decrement per array
# per call: 18% of the run time at N = 1e4 before; +9..19% collisions/s).
_jit = _compiler()
# The event loop's helpers are inlined into it (numba IR inlining): a call
# passes every array as a struct of 7-9 words on the stack, 50-60 words for
# a scan, which cost more than the few pairs a scan meets at low density
# (+13..14% collisions/s at N = 1e4; the first compilation takes 13 s, not 5).
_inline = _compiler(inline="always")

# the kernels are inlined into the loops that call them (numba IR inlining)
_kernel = _compiler(inline="always")
# kernels that other kernels call: numba compiles such a call of the plain
# Python function (physics.py stays free of numba, for spheres' start-up)
for _callee in (physics.order_one, physics.pair_time_within, physics.wall_time_grow):
    numba.extending.register_jitable(inline="always")(_callee)
pair_time_within = _kernel(physics.pair_time_within)
pair_time = _kernel(physics.pair_time)
wall_time = _kernel(physics.wall_time)
collide = _kernel(physics.collide)
reflect = _kernel(physics.reflect)
pair_time_grow = _kernel(physics.pair_time_grow)
wall_time_grow = _kernel(physics.wall_time_grow)
collide_grow = _kernel(physics.collide_grow)
reflect_grow = _kernel(physics.reflect_grow)
frozen_limit_of = _kernel(physics.frozen_limit)

#: Event kinds (also the tie order at equal times): the public ones are
#: :class:`hardspheres.events.EventKind`'s numbers; crossings and "nothing"
#: are the core's own.
WALL = int(events.EventKind.REFLECTION)
COLLISION = int(events.EventKind.COLLISION)
CROSS = 2
NONE = 3

#: Why :func:`run` returned: :class:`hardspheres.events.StopReason`'s numbers.
STOP_UNTIL = int(events.StopReason.UNTIL)
STOP_MAX_EVENTS = int(events.StopReason.MAX_EVENTS)
STOP_MAX_COLLISIONS = int(events.StopReason.MAX_COLLISIONS)
STOP_RECORD_FULL = int(events.StopReason.RECORD_FULL)

# columns of S (float64 per sphere)
X, Y, Z, VX, VY, VZ, TL, RAD = 0, 1, 2, 3, 4, 5, 6, 7
# columns of T (float64 per sphere)
EV_T, CR_T = 0, 1
# columns of K (int64 per sphere)
(COUNT, CX, CY, CZ, CELL, EV_KEY, EV_KIND, EV_PARTNER, EV_PCOUNT, CR_CODE,
 FRESH, HPOS) = range(12)
K_COLS = 12

# indices into the float64 array `f` of scalars
F_CLOCK = 0      # time of the last processed event (relative to the origin)
F_ANCHOR = 1     # time of the last collision or reflection
F_CONTAINER = 2  # container radius (0 for a periodic box)
F_BOX = 3        # periodic box edge (0 for a spherical container)
F_LO = 4         # grid origin (lower corner) per axis
F_W = 5          # cell width
F_WINDOW = 6     # simultaneity window
F_WALL_IMPULSE = 7   # sum of impulse magnitudes delivered to the wall
F_VIRIAL = 8         # sum over collisions of r_ij . dp_i
# transport tallies (periodic box; 6 tensor components in the order xx yy zz xy xz yz)
F_VIR_T = 9      # collisional virial tensor, sum over collisions of r_ij dp_i
F_KIN_T = 15     # kinetic tensor now, sum_i m_i v_i v_i
F_KIN_INT = 21   # its time integral up to F_T_KIN
F_T_KIN = 27     # time the integrals were last brought up to date
F_HEAT_COLL = 28  # heat Helfand moment, collisional part: sum over collisions of r_ij dE_i
F_HEAT_KIN = 31  # energy current now, sum_i v_i E_i (E_i = m_i v_i^2 / 2)
F_HEAT_INT = 34  # its time integral up to F_T_KIN
F_OFFSET = 37    # absolute time of the time origin (the engine's offset)
F_STREAK = 38    # time of the first event of the current C_FROZEN streak
F_GROW = 39     # growth: radius_i(t) = R_i (1 + F_GROW t), t from the origin (0: off)
F_NF = 40

# indices into the int64 array `c` of counters
C_NC = 0         # cells per axis
C_COLL = 1       # collisions processed
C_WALL = 2       # reflections processed
C_CROSS = 3      # cell crossings processed
C_STALE = 4      # stale predictions discarded
C_SERIAL = 5     # collisions and reflections processed (freshness stamps)
C_FROZEN = 6     # collisions and reflections in a row with the clock not advancing
C_REFRESHED = 7  # predictions made afresh by the window rule (refresh_window)
C_NC_ = 8

# stop reasons of run() beyond 0..3 (see its docstring)
STOP_FROZEN = int(events.StopReason.FROZEN)
STOP_SLIDING = int(events.StopReason.SLIDING)


# ---- the calendar: an indexed binary heap over spheres -------------------------
# The heap keeps each entry's time and tie key beside the sphere's index
# (arrays HT, HKEY, heap by heap position), so sifting reads contiguous memory.

@_inline
def _sift_up(heap, HT, HKEY, K, k):
    i, t, key = heap[k], HT[k], HKEY[k]
    while k > 0:
        parent = (k - 1) >> 1
        tp = HT[parent]
        if t < tp or (t == tp and key < HKEY[parent]):
            p = heap[parent]
            heap[k], HT[k], HKEY[k] = p, tp, HKEY[parent]
            K[p, HPOS] = k
            k = parent
        else:
            break
    heap[k], HT[k], HKEY[k] = i, t, key
    K[i, HPOS] = k


@_inline
def _sift_down(heap, HT, HKEY, K, k, n):
    i, t, key = heap[k], HT[k], HKEY[k]
    while True:
        child = 2 * k + 1
        if child >= n:
            break
        tc, kc = HT[child], HKEY[child]
        if child + 1 < n:
            t2, k2 = HT[child + 1], HKEY[child + 1]
            if t2 < tc or (t2 == tc and k2 < kc):
                child += 1
                tc, kc = t2, k2
        if tc < t or (tc == t and kc < key):
            c = heap[child]
            heap[k], HT[k], HKEY[k] = c, tc, kc
            K[c, HPOS] = k
            k = child
        else:
            break
    heap[k], HT[k], HKEY[k] = i, t, key
    K[i, HPOS] = k


@_inline
def _schedule(heap, HT, HKEY, T, K, i):
    """Sphere ``i``'s heap entry becomes the earlier of its event and its crossing."""
    n = heap.shape[0]
    cross_key = _key(CROSS, i, -1, n)
    if T[i, CR_T] < T[i, EV_T] or (T[i, CR_T] == T[i, EV_T] and cross_key < K[i, EV_KEY]):
        t, key = T[i, CR_T], cross_key
    else:
        t, key = T[i, EV_T], K[i, EV_KEY]
    k = K[i, HPOS]
    HT[k] = t
    HKEY[k] = key
    if k > 0 and (t < HT[(k - 1) >> 1] or (t == HT[(k - 1) >> 1] and key < HKEY[(k - 1) >> 1])):
        _sift_up(heap, HT, HKEY, K, k)
    else:
        _sift_down(heap, HT, HKEY, K, k, n)


@_inline
def _key(kind, a, b, n):
    # tie order at equal times: kind, then first sphere, then second
    return (kind * (n + 1) + a) * (n + 1) + (b + 1)


# ---- cells ---------------------------------------------------------------------

@_inline
def cell_of(x, lo, w, nc):
    """Cell coordinate of ``x`` along one axis, clamped to the grid."""
    k = int(np.floor((x - lo) / w))
    if k < 0:
        return 0
    if k >= nc:
        return nc - 1
    return k


@_inline
def _cell_insert(head, nxt, prv, K, i, c):
    K[i, CELL] = c
    h = head[c]
    nxt[i] = h
    prv[i] = -1
    if h >= 0:
        prv[h] = i
    head[c] = i


@_inline
def _cell_remove(head, nxt, prv, K, i):
    c = K[i, CELL]
    a, b = prv[i], nxt[i]
    if a >= 0:
        nxt[a] = b
    else:
        head[c] = b
    if b >= 0:
        prv[b] = a


# ---- predictions ---------------------------------------------------------------

@_inline
def _crossing(S, K, T, f, nc, i, t):
    """Store the time sphere ``i`` leaves its cell, from time ``t``."""
    lo, w, box = f[F_LO], f[F_W], f[F_BOX]
    dt_i = t - S[i, TL]
    best = np.inf
    code = -1
    for ax in range(3):
        v = S[i, VX + ax]
        k = K[i, CX + ax]
        x = S[i, X + ax] + v * dt_i
        if v > 0.0:
            if box == 0.0 and k == nc - 1:
                continue
            d = (lo + (k + 1) * w - x) / v
            up = 1
        elif v < 0.0:
            if box == 0.0 and k == 0:
                continue
            d = (lo + k * w - x) / v
            up = 0
        else:
            continue
        if d < 0.0:
            d = 0.0
        if d < best:
            best = d
            code = 2 * ax + up
    T[i, CR_T] = t + best
    K[i, CR_CODE] = code


@_inline
def _scan(S, K, T, head, nxt, f, c, i, zlo, zhi, ylo, yhi, xlo, xhi):
    """Improve sphere ``i``'s stored event with the pairs in a block of cells.

    The block is given by offsets from ``i``'s cell, e.g. -1..1 on every
    axis for the full 27 cells.
    """
    n = S.shape[0]
    nc = c[C_NC]
    box = f[F_BOX]
    now = f[F_ANCHOR]
    soon = now + f[F_WINDOW]
    clock = f[F_CLOCK]
    grow = f[F_GROW]
    best_t = T[i, EV_T]
    best_key = K[i, EV_KEY]
    best_p = -1
    ti = S[i, TL]
    cx0, cy0, cz0 = K[i, CX], K[i, CY], K[i, CZ]
    # exactly 1.0, but not to the compiler: it would otherwise see that the
    # kernel's own first test (receding: inf) decides both branches below
    # and test it first again, on its own
    one = 1.0 if nc > 0 else 2.0
    # the sphere's own layer and row first: the earliest event is mostly
    # there, and the pairs after it are rejected by the horizon
    for qz in range(zhi - zlo + 1):
        oz = zlo if zlo == zhi else (qz if qz < 2 else -1)
        nz = cz0 + oz
        sz = 0.0
        if nz < 0:
            if box == 0.0:
                continue
            nz += nc
            sz = -box
        elif nz >= nc:
            if box == 0.0:
                continue
            nz -= nc
            sz = box
        for qy in range(yhi - ylo + 1):
            oy = ylo if ylo == yhi else (qy if qy < 2 else -1)
            ny = cy0 + oy
            sy = 0.0
            if ny < 0:
                if box == 0.0:
                    continue
                ny += nc
                sy = -box
            elif ny >= nc:
                if box == 0.0:
                    continue
                ny -= nc
                sy = box
            for ox in range(xlo, xhi + 1):
                nx = cx0 + ox
                sx = 0.0
                if nx < 0:
                    if box == 0.0:
                        continue
                    nx += nc
                    sx = -box
                elif nx >= nc:
                    if box == 0.0:
                        continue
                    nx -= nc
                    sx = box
                j = head[(nz * nc + ny) * nc + nx]
                while j >= 0:
                    if j != i:
                        tj = S[j, TL]
                        t0 = ti if ti > tj else tj
                        di = t0 - ti
                        dj = t0 - tj
                        # i minus j, each from its own time.  IEEE subtraction
                        # is exactly antisymmetric and pair_time even in
                        # (dr, dv), so this is bit for bit what the lower
                        # index minus the higher gives: the same result
                        # whichever sphere predicts the pair.
                        # pairs that surely meet after the best event so far
                        # are not solved (the window's "now" is never later);
                        # two ulps of best_t more, as a root that rounds to
                        # best_t ties with it and the tie order decides
                        horizon = ((best_t - t0) + 4.5e-16 * abs(best_t)
                                   if best_t >= soon else np.inf)
                        dx = (S[i, X] + S[i, VX] * di) - (S[j, X] + S[j, VX] * dj + sx)
                        dy = (S[i, Y] + S[i, VY] * di) - (S[j, Y] + S[j, VY] * dj + sy)
                        dz = (S[i, Z] + S[i, VZ] * di) - (S[j, Z] + S[j, VZ] * dj + sz)
                        dvx = S[i, VX] - S[j, VX]
                        dvy = S[i, VY] - S[j, VY]
                        dvz = S[i, VZ] - S[j, VZ]
                        sigma = S[i, RAD] + S[j, RAD]
                        if grow != 0.0:
                            # growing (the one branch a plain run pays here)
                            dt = pair_time_grow(dx, dy, dz, dvx, dvy, dvz,
                                                sigma * (1.0 + grow * t0), sigma * grow,
                                                horizon)
                        # pair_time_within's own tests up to the root,
                        # the same expressions, combined without branches (half
                        # the pairs recede, at random, and a branch on that
                        # mispredicts half the time): a pair they reject is
                        # inf for it too.  The rest, NaNs and the pairs it
                        # rescales (|dv|^2 |dr|^2 out of range) go through it.
                        # The miss test is b^2 - a c < 0 by a margin that
                        # covers its rounding and that of the kernel's own
                        # discriminant (physics.MISS_MARGIN).
                        b = dx * dvx + dy * dvy + dz * dvz
                        a = dvx * dvx + dvy * dvy + dvz * dvz
                        r2 = dx * dx + dy * dy + dz * dz
                        cc = r2 - sigma * sigma
                        ar2 = a * r2
                        recede = b >= 0.0
                        beyond = cc > -2.0 * b * horizon * (1.0 + 1e-12)
                        touch = cc <= 0.0
                        miss = b * b - a * cc < -physics.MISS_MARGIN * ar2
                        # (past RANGE_HI no test here rejects wrongly: an
                        # overflow makes them false, or NaN, so the kernel
                        # decides; below RANGE_LO, b may underflow)
                        if grow != 0.0:
                            pass
                        elif (ar2 < physics.RANGE_LO) | ((recede ^ True) & (
                                touch | ((beyond ^ True) & (miss ^ True)))):
                            dt = pair_time_within(dx, dy, dz, dvx * one, dvy * one, dvz * one,
                                                  sigma, horizon)
                        else:
                            dt = np.inf
                        if dt < np.inf:
                            te = t0 + dt
                            if te < soon:
                                te = now
                            if te < clock:
                                te = clock  # a root rounded into the past
                            if te <= best_t:
                                kk = _key(COLLISION, min(i, j), max(i, j), n)
                                if te < best_t or kk < best_key:
                                    best_t, best_key, best_p = te, kk, j
                    j = nxt[j]
    if best_p >= 0:
        T[i, EV_T] = best_t
        K[i, EV_KEY] = best_key
        K[i, EV_KIND] = COLLISION
        K[i, EV_PARTNER] = best_p
        K[i, EV_PCOUNT] = K[best_p, COUNT]


@_inline
def predict(S, K, T, head, nxt, f, c, i, t):
    """Find sphere ``i``'s earliest collision or reflection and its next crossing.

    A collision or reflection less than the simultaneity window after the
    anchor (the last collision or reflection) is put at the anchor itself:
    it happens now.  Does not touch the heap.
    """
    n = S.shape[0]
    T[i, EV_T] = np.inf
    K[i, EV_KEY] = _key(NONE, n, n - 1, n)
    K[i, EV_KIND] = NONE
    K[i, EV_PARTNER] = -1
    if f[F_BOX] == 0.0:
        # the wall, from the sphere's own time
        grow = f[F_GROW]
        if grow != 0.0:
            dt = wall_time_grow(S[i, X], S[i, Y], S[i, Z], S[i, VX], S[i, VY], S[i, VZ],
                                f[F_CONTAINER] - S[i, RAD] * (1.0 + grow * S[i, TL]),
                                S[i, RAD] * grow)
        else:
            dt = wall_time(S[i, X], S[i, Y], S[i, Z], S[i, VX], S[i, VY], S[i, VZ],
                           f[F_CONTAINER] - S[i, RAD])
        if dt < np.inf:
            te = S[i, TL] + dt
            if te < f[F_ANCHOR] + f[F_WINDOW]:
                te = f[F_ANCHOR]
            if te < f[F_CLOCK]:
                te = f[F_CLOCK]
            T[i, EV_T] = te
            K[i, EV_KEY] = _key(WALL, i, -1, n)
            K[i, EV_KIND] = WALL
    _scan(S, K, T, head, nxt, f, c, i, -1, 1, -1, 1, -1, 1)
    _crossing(S, K, T, f, c[C_NC], i, t)


@_inline
def _advance(S, i, t):
    dt = t - S[i, TL]
    S[i, X] += S[i, VX] * dt
    S[i, Y] += S[i, VY] * dt
    S[i, Z] += S[i, VZ] * dt
    S[i, TL] = t


@_jit
def build(S, K, T, head, nxt, prv, heap, HT, HKEY, f, c):
    """Fill the cells, predict every sphere from the clock, build the heap."""
    n = S.shape[0]
    nc = c[C_NC]
    lo, w = f[F_LO], f[F_W]
    head[:] = -1
    t = f[F_CLOCK]
    for i in range(n):
        _advance(S, i, t)
        K[i, CX] = cell_of(S[i, X], lo, w, nc)
        K[i, CY] = cell_of(S[i, Y], lo, w, nc)
        K[i, CZ] = cell_of(S[i, Z], lo, w, nc)
        _cell_insert(head, nxt, prv, K, i, (K[i, CZ] * nc + K[i, CY]) * nc + K[i, CX])
    for i in range(n):
        predict(S, K, T, head, nxt, f, c, i, t)
    for i in range(n):
        heap[i] = i
        K[i, HPOS] = i
        cross_key = _key(CROSS, i, -1, n)
        if T[i, CR_T] < T[i, EV_T] or (T[i, CR_T] == T[i, EV_T] and cross_key < K[i, EV_KEY]):
            HT[i], HKEY[i] = T[i, CR_T], cross_key
        else:
            HT[i], HKEY[i] = T[i, EV_T], K[i, EV_KEY]
    for k in range(n // 2 - 1, -1, -1):
        _sift_down(heap, HT, HKEY, K, k, n)


@_jit
def refresh_window(S, K, T, head, nxt, heap, HT, HKEY, f, c, stack):
    """Predict afresh, at the clock, every sphere whose event is within the window.

    This is what makes the engine follow the assignment's rule exactly: of
    the events less than ``window`` after the clock, the first in tie order
    happens now, whatever order their earlier predictions put them in.
    The heap is walked from the root, pruning subtrees that start past the
    window, so the cost is proportional to the number refreshed.
    """
    n = heap.shape[0]
    if n == 0:
        return
    t = f[F_CLOCK]
    limit = t + f[F_WINDOW]
    serial = c[C_SERIAL]
    top = 0
    found = 0
    if HT[0] < limit:
        stack[0] = 0
        top = 1
    while top > 0:
        top -= 1
        k = stack[top]
        stack[n + found] = heap[k]
        found += 1
        for child in (2 * k + 1, 2 * k + 2):
            if child < n and HT[child] < limit:
                stack[top] = child
                top += 1
    for q in range(found):
        i = stack[n + q]
        if K[i, FRESH] != serial:
            K[i, FRESH] = serial
            c[C_REFRESHED] += 1
            predict(S, K, T, head, nxt, f, c, i, t)
            _schedule(heap, HT, HKEY, T, K, i)


# ---- transport tallies -----------------------------------------------------------

@_inline
def _kinetic_terms(f, m, vx, vy, vz, sign):
    """Add ``sign`` times one sphere's share to the kinetic tensor and energy current now."""
    f[F_KIN_T] += sign * m * vx * vx
    f[F_KIN_T + 1] += sign * m * vy * vy
    f[F_KIN_T + 2] += sign * m * vz * vz
    f[F_KIN_T + 3] += sign * m * vx * vy
    f[F_KIN_T + 4] += sign * m * vx * vz
    f[F_KIN_T + 5] += sign * m * vy * vz
    e = 0.5 * m * (vx * vx + vy * vy + vz * vz)
    f[F_HEAT_KIN] += sign * vx * e
    f[F_HEAT_KIN + 1] += sign * vy * e
    f[F_HEAT_KIN + 2] += sign * vz * e


@_inline
def _transfer(S, mass, f, a, b, te, dx, dy, dz, k1, k2):
    """Before the velocities of ``a`` and ``b`` change at ``te``: the transport tallies.

    The Helfand moments of momentum (``sum m x v``) and energy (``sum x E``)
    change by free flight, ``int sum m v v dt`` and ``int sum v E dt``,
    integrated exactly here (the sums are constant between collisions), and
    at a collision by ``r_ab dp_a`` and ``r_ab dE_a`` (minimum image:
    the moments' periodic form).  Their growth gives the shear viscosity
    and the thermal conductivity by the Einstein-Helfand route.  Reads the
    velocities only: the caller changes them.
    """
    dtk = te - f[F_T_KIN]
    for q in range(6):
        f[F_KIN_INT + q] += f[F_KIN_T + q] * dtk
    for q in range(3):
        f[F_HEAT_INT + q] += f[F_HEAT_KIN + q] * dtk
    f[F_T_KIN] = te
    ma, mb = mass[a], mass[b]
    px, py, pz = -ma * k1 * dx, -ma * k1 * dy, -ma * k1 * dz  # impulse on a
    f[F_VIR_T] += dx * px
    f[F_VIR_T + 1] += dy * py
    f[F_VIR_T + 2] += dz * pz
    f[F_VIR_T + 3] += dx * py
    f[F_VIR_T + 4] += dx * pz
    f[F_VIR_T + 5] += dy * pz
    ax, ay, az = S[a, VX], S[a, VY], S[a, VZ]
    bx, by, bz = S[b, VX], S[b, VY], S[b, VZ]
    _kinetic_terms(f, ma, ax, ay, az, -1.0)
    _kinetic_terms(f, mb, bx, by, bz, -1.0)
    ax2, ay2, az2 = ax - k1 * dx, ay - k1 * dy, az - k1 * dz
    _kinetic_terms(f, ma, ax2, ay2, az2, 1.0)
    _kinetic_terms(f, mb, bx + k2 * dx, by + k2 * dy, bz + k2 * dz, 1.0)
    de = 0.5 * ma * ((ax2 * ax2 + ay2 * ay2 + az2 * az2) - (ax * ax + ay * ay + az * az))
    f[F_HEAT_COLL] += dx * de
    f[F_HEAT_COLL + 1] += dy * de
    f[F_HEAT_COLL + 2] += dz * de


@_jit
def kinetic_sums(S, mass, f):
    """Set the kinetic tensor and the energy current from the velocities now."""
    for q in range(6):
        f[F_KIN_T + q] = 0.0
    for q in range(3):
        f[F_HEAT_KIN + q] = 0.0
    for i in range(S.shape[0]):
        _kinetic_terms(f, mass[i], S[i, VX], S[i, VY], S[i, VZ], 1.0)


# ---- the event loop ------------------------------------------------------------

@_jit
def run(S, mass, K, T, head, nxt, prv, heap, HT, HKEY, f, c, stack, img, until, max_events,
        max_collisions, rec_t, rec_kind, rec_i, rec_j, rec_imp, rec_dp):
    """Process events in order until one of the limits.

    ``img`` ``(N, 3)`` int64 counts each sphere's crossings of the periodic
    box (the image it is in: unwrapped centre = stored centre + img * box).
    ``rec_dp`` ``(cap, 3)`` receives the impulse vector of sphere ``i``.
    In a periodic box each collision also adds to the transport tallies
    (``F_VIR_T`` ... ``F_HEAT_INT``, see :func:`_transfer`).

    Stops before the first event after ``until``, after ``max_events``
    collisions and reflections, or after ``max_collisions`` collisions,
    whichever comes first; up to ``len(rec_t)`` collisions and reflections
    are recorded (time, kind, i, j, impulse magnitude), and the run also
    stops when the record is full.

    Returns:
        ``(recorded, reason)``, reason a :class:`hardspheres.events.StopReason`
        number: 0 = ``until`` reached (or nothing will
        ever happen, or ``until`` is NaN), 1 = ``max_events``, 2 =
        ``max_collisions``, 3 = record full, 4 (:data:`STOP_FROZEN`) = the
        next collision or reflection would be one more than
        ``physics.frozen_limit(N)`` in a row with the clock not advancing
        (by more than ``physics.FROZEN_RELATIVE`` of its value), 5
        (:data:`STOP_SLIDING`) = the next event is a reflection that would
        not change the velocity (a sphere at the wall moving along it).
        For 4 and 5 the event is left pending and sphere ``heap[0]`` is the
        one involved.

    The simultaneity window is applied when a prediction is made, with
    the anchor of that time: so all spheres with an event in the window
    are predicted afresh (:func:`refresh_window`) when the anchor moves,
    and only then; an event at the anchor's own instant leaves every other
    prediction as valid as it was, and only the spheres it touched are
    predicted again.
    """
    n = S.shape[0]
    if n == 0:
        return 0, STOP_UNTIL
    nc = c[C_NC]
    box = f[F_BOX]
    window = f[F_WINDOW]
    cap = rec_t.shape[0]
    done = 0
    coll0 = c[C_COLL]
    frozen_limit = frozen_limit_of(n)
    while True:
        if done >= max_events:
            return done, STOP_MAX_EVENTS
        if c[C_COLL] - coll0 >= max_collisions:
            return done, STOP_MAX_COLLISIONS
        if done >= cap:
            return done, STOP_RECORD_FULL
        i = heap[0]
        te = HT[0]
        if not te <= until or te == np.inf:  # NaN `until` too
            return done, STOP_UNTIL
        if HKEY[0] != K[i, EV_KEY]:
            # leaving the cell: not an event of the physics (the clock
            # moves, the anchor of the simultaneity window does not)
            f[F_CLOCK] = te
            code = K[i, CR_CODE]
            ax = code >> 1
            step = 1 if (code & 1) else -1
            k = K[i, CX + ax] + step
            if k < 0 or k >= nc:
                # periodic wrap: shift the stored centre by one box edge
                k = (k + nc) % nc
                S[i, X + ax] -= step * box
                img[i, ax] += step
            K[i, CX + ax] = k
            _cell_remove(head, nxt, prv, K, i)
            _cell_insert(head, nxt, prv, K, i, (K[i, CZ] * nc + K[i, CY]) * nc + K[i, CX])
            c[C_CROSS] += 1
            # only the 9 cells that came into reach can hold new partners
            zl = step if ax == 2 else -1
            yl = step if ax == 1 else -1
            xl = step if ax == 0 else -1
            zh = step if ax == 2 else 1
            yh = step if ax == 1 else 1
            xh = step if ax == 0 else 1
            _scan(S, K, T, head, nxt, f, c, i, zl, zh, yl, yh, xl, xh)
            _crossing(S, K, T, f, nc, i, te)
            _schedule(heap, HT, HKEY, T, K, i)
            continue
        kind = K[i, EV_KIND]
        # the spheres to predict afresh after the event (one place for all
        # kinds: the prediction is compiled into this loop only once)
        p0, p1, tp = i, -1, te
        stale = False
        if kind == COLLISION:
            j = K[i, EV_PARTNER]
            if K[j, COUNT] != K[i, EV_PCOUNT]:
                # stale: the partner has changed course since
                c[C_STALE] += 1
                stale = True
                tp = f[F_CLOCK]
        anchor = f[F_ANCHOR]
        if not stale and kind != NONE:
            # a collision or reflection: count those in a row during which
            # the clock has not advanced (physics.FROZEN_RELATIVE)
            if te - f[F_STREAK] <= physics.FROZEN_RELATIVE * abs(te + f[F_OFFSET]):
                if c[C_FROZEN] >= frozen_limit:
                    return done, STOP_FROZEN
            else:
                c[C_FROZEN] = 0
                f[F_STREAK] = te
        if kind == COLLISION and not stale:
            c[C_FROZEN] += 1
            f[F_CLOCK] = te
            f[F_ANCHOR] = te
            _advance(S, i, te)
            _advance(S, j, te)
            a, b = (i, j) if i < j else (j, i)
            dx = S[a, X] - S[b, X]
            dy = S[a, Y] - S[b, Y]
            dz = S[a, Z] - S[b, Z]
            if box != 0.0:
                # the partner may be an image across the box
                dx -= box * np.round(dx / box)
                dy -= box * np.round(dy / box)
                dz -= box * np.round(dz / box)
            if f[F_GROW] != 0.0:
                k1, k2 = collide_grow(mass[a], mass[b], dx, dy, dz, S[a, VX] - S[b, VX],
                                      S[a, VY] - S[b, VY], S[a, VZ] - S[b, VZ],
                                      (S[a, RAD] + S[b, RAD]) * f[F_GROW])
            else:
                k1, k2 = collide(mass[a], mass[b], dx, dy, dz, S[a, VX] - S[b, VX],
                                 S[a, VY] - S[b, VY], S[a, VZ] - S[b, VZ])
            if box != 0.0:
                _transfer(S, mass, f, a, b, te, dx, dy, dz, k1, k2)
            S[a, VX] -= k1 * dx
            S[a, VY] -= k1 * dy
            S[a, VZ] -= k1 * dz
            S[b, VX] += k2 * dx
            S[b, VY] += k2 * dy
            S[b, VZ] += k2 * dz
            d2 = dx * dx + dy * dy + dz * dz
            f[F_VIRIAL] -= mass[a] * k1 * d2
            K[a, COUNT] += 1
            K[b, COUNT] += 1
            c[C_COLL] += 1
            c[C_SERIAL] += 1
            K[a, FRESH] = c[C_SERIAL]
            K[b, FRESH] = c[C_SERIAL]
            p0, p1 = a, b
            rec_t[done] = te
            rec_kind[done] = COLLISION
            rec_i[done] = a
            rec_j[done] = b
            rec_imp[done] = -mass[a] * k1 * np.sqrt(d2)
            rec_dp[done, 0] = -mass[a] * k1 * dx
            rec_dp[done, 1] = -mass[a] * k1 * dy
            rec_dp[done, 2] = -mass[a] * k1 * dz
            done += 1
        elif kind == WALL:
            clock0 = f[F_CLOCK]
            f[F_CLOCK] = te
            f[F_ANCHOR] = te
            _advance(S, i, te)
            px, py, pz = S[i, X], S[i, Y], S[i, Z]
            if f[F_GROW] != 0.0:
                k = reflect_grow(px, py, pz, S[i, VX], S[i, VY], S[i, VZ],
                                 S[i, RAD] * f[F_GROW])
            else:
                k = reflect(px, py, pz, S[i, VX], S[i, VY], S[i, VZ])
            if k == 0.0:
                # nothing would change, and the same reflection would come
                # again: not an event (the clock keeps its time)
                f[F_CLOCK] = clock0
                f[F_ANCHOR] = anchor
                return done, STOP_SLIDING
            c[C_FROZEN] += 1
            S[i, VX] -= k * px
            S[i, VY] -= k * py
            S[i, VZ] -= k * pz
            imp = mass[i] * k * np.sqrt(px * px + py * py + pz * pz)
            f[F_WALL_IMPULSE] += imp
            K[i, COUNT] += 1
            c[C_WALL] += 1
            c[C_SERIAL] += 1
            K[i, FRESH] = c[C_SERIAL]
            rec_t[done] = te
            rec_kind[done] = WALL
            rec_i[done] = i
            rec_j[done] = -1
            rec_imp[done] = imp
            rec_dp[done, 0] = -mass[i] * k * px
            rec_dp[done, 1] = -mass[i] * k * py
            rec_dp[done, 2] = -mass[i] * k * pz
            done += 1
        elif not stale:
            return done, STOP_UNTIL
        for q in range(1 if p1 < 0 else 2):
            x = p0 if q == 0 else p1
            predict(S, K, T, head, nxt, f, c, x, tp)
            _schedule(heap, HT, HKEY, T, K, x)
        if stale:
            continue
        if window > 0.0 and te != anchor:
            refresh_window(S, K, T, head, nxt, heap, HT, HKEY, f, c, stack)


@_jit
def kick(S, mass, K, T, head, nxt, heap, HT, HKEY, f, c, i, t, vx, vy, vz):
    """Give sphere ``i`` a new velocity at time ``t`` (not before the clock).

    The clock moves to ``t``; predictions that involve ``i`` go stale (its
    event count moves on) and ``i`` is predicted afresh.  For thermostats.
    """
    f[F_CLOCK] = t
    _advance(S, i, t)
    # the transport tallies' kinetic sums: integrated up to t, then i's terms swapped
    dtk = t - f[F_T_KIN]
    for q in range(6):
        f[F_KIN_INT + q] += f[F_KIN_T + q] * dtk
    for q in range(3):
        f[F_HEAT_INT + q] += f[F_HEAT_KIN + q] * dtk
    f[F_T_KIN] = t
    _kinetic_terms(f, mass[i], S[i, VX], S[i, VY], S[i, VZ], -1.0)
    _kinetic_terms(f, mass[i], vx, vy, vz, 1.0)
    S[i, VX] = vx
    S[i, VY] = vy
    S[i, VZ] = vz
    K[i, COUNT] += 1
    c[C_SERIAL] += 1
    K[i, FRESH] = c[C_SERIAL]
    predict(S, K, T, head, nxt, f, c, i, t)
    _schedule(heap, HT, HKEY, T, K, i)


# ---- state and checks ------------------------------------------------------------

@_jit
def positions_at(S, t, out, box):
    """Centres of all spheres at time ``t`` into ``out`` (wrapped into the box)."""
    n = S.shape[0]
    for i in range(n):
        dt = t - S[i, TL]
        for k in range(3):
            x = S[i, X + k] + S[i, VX + k] * dt
            if box != 0.0:
                x -= box * np.floor(x / box + 0.5)
            out[i, k] = x


@_jit
def unwrapped_at(S, img, t, out, box):
    """Unwrapped centres at time ``t`` into ``out``: the stored centre plus its image's shift."""
    n = S.shape[0]
    for i in range(n):
        dt = t - S[i, TL]
        for k in range(3):
            out[i, k] = (S[i, X + k] + S[i, VX + k] * dt) + img[i, k] * box


@_jit
def rebase(S, T, HT, f):
    """Move the time origin to the clock: advance everyone, shift all times."""
    t = f[F_CLOCK]
    n = S.shape[0]
    for i in range(n):
        _advance(S, i, t)
        S[i, TL] = 0.0
        T[i, EV_T] -= t
        T[i, CR_T] -= t
        HT[i] -= t
    f[F_ANCHOR] -= t
    f[F_T_KIN] -= t
    f[F_STREAK] -= t
    f[F_OFFSET] += t
    f[F_CLOCK] = 0.0
    grow = f[F_GROW]
    if grow != 0.0:
        # radii to the new origin; the growth speed of each stays the same
        factor = 1.0 + grow * t
        for i in range(n):
            S[i, RAD] *= factor
        f[F_GROW] = grow / factor
    return t


@_jit
def max_overlap(x, S, K, head, nxt, nc, box, scale):
    """Largest ``1 - d / (R_i + R_j)`` over touching-or-overlapping pairs (0 if none).

    ``x`` are the centres at one time, ``scale`` the radii's factor then
    (1 without growth); neighbours are found through the engine's cells.
    """
    n = x.shape[0]
    worst = 0.0
    for i in range(n):
        for oz in range(-1, 2):
            nz = K[i, CZ] + oz
            for oy in range(-1, 2):
                ny = K[i, CY] + oy
                for ox in range(-1, 2):
                    nx = K[i, CX] + ox
                    if box == 0.0 and (nx < 0 or ny < 0 or nz < 0 or
                                       nx >= nc or ny >= nc or nz >= nc):
                        continue
                    j = head[((nz % nc) * nc + (ny % nc)) * nc + (nx % nc)]
                    while j >= 0:
                        if j > i:
                            dx = x[i, 0] - x[j, 0]
                            dy = x[i, 1] - x[j, 1]
                            dz = x[i, 2] - x[j, 2]
                            if box != 0.0:
                                dx -= box * np.round(dx / box)
                                dy -= box * np.round(dy / box)
                                dz -= box * np.round(dz / box)
                            sigma = (S[i, RAD] + S[j, RAD]) * scale
                            if sigma > 0.0:
                                ov = 1.0 - np.sqrt(dx * dx + dy * dy + dz * dz) / sigma
                                if ov > worst:
                                    worst = ov
                        j = nxt[j]
    return worst

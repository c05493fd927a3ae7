"""The compiled event core: O(log N) work per event.

Private: use :class:`hardspheres.engine.Engine` (or the public
:class:`hardspheres.Simulation`).  Everything here is numba-compiled, without
``fastmath``, from the scalar kernels of :mod:`hardspheres.physics`.

Design (the classic one-event-per-sphere scheme of Rapaport and
Lubachevsky, as in the fastest public codes):

* **Local times.**  Sphere ``i`` is stored as ``pos[i]`` at its own time
  ``tloc[i]``; its centre at time ``t`` is ``pos[i] + vel[i] * (t - tloc[i])``.
  An event touches only the spheres involved.
* **Cells.**  A cubic grid of ``nc^3`` cells of width ``w >= `` the largest
  contact distance covers the container (or the periodic box); a sphere is
  predicted only against the spheres in the 27 cells around its own, and
  leaving a cell is an event of its own (kind :data:`CROSS`).
* **Calendar.**  Each sphere keeps its earliest event (time, kind, partner);
  an indexed binary heap over spheres orders them.  Each sphere counts its
  velocity changes; an event with a partner whose count has moved on since
  the prediction is stale, and is re-predicted when it reaches the top.
* **Ties.**  Events order by ``(time, kind, i, j)``: reflections before
  collisions, lower index first.  With a simultaneity ``window > 0`` (the
  assignment's 1e-8 s), after each event every sphere whose event falls
  within ``window`` of the clock is predicted afresh, and events closer than
  ``window`` happen *now*, at the clock; see :func:`refresh_window`.
* **Time origin.**  :func:`rebase` moves the time origin to the clock, so
  long runs keep the precision of short ones (the engine calls it
  periodically; times reported add the offset back).
"""

import numpy as np
from numba import njit

from . import physics

_jit = njit(cache=True, nogil=True)

pair_time = _jit(physics.pair_time)
wall_time = _jit(physics.wall_time)
collide = _jit(physics.collide)
reflect = _jit(physics.reflect)

#: Event kinds (also the tie order at equal times).
WALL = 0
COLLISION = 1
CROSS = 2
NONE = 3

# indices into the float64 array `f` of scalars
F_CLOCK = 0      # time of the last processed event (relative to the origin)
F_ANCHOR = 1     # time of the last real event (collision or reflection)
F_CONTAINER = 2  # container radius (0 for a periodic box)
F_BOX = 3        # periodic box edge (0 for a spherical container)
F_LO = 4         # grid origin (lower corner) per axis
F_W = 5          # cell width
F_WINDOW = 6     # simultaneity window
F_WALL_IMPULSE = 7   # sum of impulse magnitudes delivered to the wall
F_VIRIAL = 8         # sum over collisions of r_ij . dp_i
F_NF = 9

# indices into the int64 array `c` of counters
C_NC = 0         # cells per axis
C_COLL = 1       # collisions processed
C_WALL = 2       # reflections processed
C_CROSS = 3      # cell crossings processed
C_STALE = 4      # stale predictions discarded
C_SERIAL = 5     # real events processed (for freshness stamps)
C_NC_ = 6


@_jit
def _less(ev_t, ev_key, a, b):
    ta, tb = ev_t[a], ev_t[b]
    return ta < tb or (ta == tb and ev_key[a] < ev_key[b])


@_jit
def _sift_up(heap, hpos, ev_t, ev_key, k):
    i = heap[k]
    while k > 0:
        parent = (k - 1) >> 1
        p = heap[parent]
        if _less(ev_t, ev_key, i, p):
            heap[k] = p
            hpos[p] = k
            k = parent
        else:
            break
    heap[k] = i
    hpos[i] = k


@_jit
def _sift_down(heap, hpos, ev_t, ev_key, k, n):
    i = heap[k]
    while True:
        child = 2 * k + 1
        if child >= n:
            break
        if child + 1 < n and _less(ev_t, ev_key, heap[child + 1], heap[child]):
            child += 1
        cidx = heap[child]
        if _less(ev_t, ev_key, cidx, i):
            heap[k] = cidx
            hpos[cidx] = k
            k = child
        else:
            break
    heap[k] = i
    hpos[i] = k


@_jit
def heap_update(heap, hpos, ev_t, ev_key, i):
    """Restore heap order after sphere ``i``'s event changed."""
    k = hpos[i]
    n = heap.shape[0]
    if k > 0 and _less(ev_t, ev_key, i, heap[(k - 1) >> 1]):
        _sift_up(heap, hpos, ev_t, ev_key, k)
    else:
        _sift_down(heap, hpos, ev_t, ev_key, k, n)


@_jit
def heap_build(heap, hpos, ev_t, ev_key):
    n = heap.shape[0]
    for k in range(n):
        heap[k] = k
        hpos[k] = k
    for k in range(n // 2 - 1, -1, -1):
        _sift_down(heap, hpos, ev_t, ev_key, k, n)


@_jit
def cell_of(x, lo, w, nc):
    """Cell coordinate of ``x`` along one axis, clamped to the grid."""
    k = int(np.floor((x - lo) / w))
    if k < 0:
        return 0
    if k >= nc:
        return nc - 1
    return k


@_jit
def _cell_insert(head, nxt, prv, cell, i, c):
    cell[i] = c
    h = head[c]
    nxt[i] = h
    prv[i] = -1
    if h >= 0:
        prv[h] = i
    head[c] = i


@_jit
def _cell_remove(head, nxt, prv, cell, i):
    c = cell[i]
    a, b = prv[i], nxt[i]
    if a >= 0:
        nxt[a] = b
    else:
        head[c] = b
    if b >= 0:
        prv[b] = a


@_jit
def _key(kind, a, b, n):
    # tie order at equal times: kind, then first sphere, then second
    return (kind * (n + 1) + a) * (n + 1) + (b + 1)


@_jit
def predict(pos, vel, tloc, rad, count, cc, head, nxt,
            ev_t, ev_key, ev_kind, ev_partner, ev_pcount, f, c, i, t):
    """Find sphere ``i``'s earliest event from time ``t`` and store it.

    A collision or reflection less than the simultaneity window after the
    anchor (the last real event) is put at the anchor itself: it happens
    now.  Does not touch the heap.
    """
    n = pos.shape[0]
    nc = c[C_NC]
    lo, w, box = f[F_LO], f[F_W], f[F_BOX]
    dt_i = t - tloc[i]
    xi = pos[i, 0] + vel[i, 0] * dt_i
    yi = pos[i, 1] + vel[i, 1] * dt_i
    zi = pos[i, 2] + vel[i, 2] * dt_i
    vxi, vyi, vzi = vel[i, 0], vel[i, 1], vel[i, 2]
    ri = rad[i]
    now = f[F_ANCHOR]
    soon = now + f[F_WINDOW]
    clock = f[F_CLOCK]

    best_t = np.inf
    best_key = _key(NONE, n, n - 1, n)
    best_kind = NONE
    best_p = -1

    # the container
    if box == 0.0:
        # predicted from the sphere's own time: independent of `t`
        dt = wall_time(pos[i, 0], pos[i, 1], pos[i, 2], vxi, vyi, vzi, f[F_CONTAINER] - ri)
        if dt < np.inf:
            te = tloc[i] + dt
            if te < soon:
                te = now
            if te < clock:
                te = clock  # a root rounded into the past
            best_t, best_key, best_kind, best_p = te, _key(WALL, i, -1, n), WALL, -1

    # leaving the cell: code = 2 * axis + (1 if upward)
    cx0, cy0, cz0 = cc[i, 0], cc[i, 1], cc[i, 2]
    dtc = np.inf
    code = -1
    for ax in range(3):
        if ax == 0:
            x, v, k = xi, vxi, cx0
        elif ax == 1:
            x, v, k = yi, vyi, cy0
        else:
            x, v, k = zi, vzi, cz0
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
        if d < dtc:
            dtc = d
            code = 2 * ax + up
    if code >= 0:
        te = t + dtc
        kk = _key(CROSS, i, -1, n)
        if te < best_t or (te == best_t and kk < best_key):
            best_t, best_key, best_kind, best_p = te, kk, CROSS, code

    # the neighbours in the 27 cells around
    for oz in range(-1, 2):
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
        for oy in range(-1, 2):
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
            for ox in range(-1, 2):
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
                        # predicted from the later of the two spheres' own
                        # times, lower index minus higher: the same bits
                        # whoever predicts it, and whenever
                        ti, tj = tloc[i], tloc[j]
                        t0 = ti if ti > tj else tj
                        di, dj = t0 - ti, t0 - tj
                        if i < j:
                            a, b, sa, sb = i, j, 0.0, 1.0
                        else:
                            a, b, sa, sb = j, i, 1.0, 0.0
                        da = di if a == i else dj
                        db = dj if b == j else di
                        dt = pair_time(
                            (pos[a, 0] + vel[a, 0] * da + sx * sa) - (pos[b, 0] + vel[b, 0] * db + sx * sb),
                            (pos[a, 1] + vel[a, 1] * da + sy * sa) - (pos[b, 1] + vel[b, 1] * db + sy * sb),
                            (pos[a, 2] + vel[a, 2] * da + sz * sa) - (pos[b, 2] + vel[b, 2] * db + sz * sb),
                            vel[a, 0] - vel[b, 0], vel[a, 1] - vel[b, 1], vel[a, 2] - vel[b, 2],
                            rad[a] + rad[b])
                        if dt < np.inf:
                            te = t0 + dt
                            if te < soon:
                                te = now
                            if te < clock:
                                te = clock  # a root rounded into the past
                            if te <= best_t:
                                kk = _key(COLLISION, min(i, j), max(i, j), n)
                                if te < best_t or kk < best_key:
                                    best_t, best_key, best_kind, best_p = te, kk, COLLISION, j
                    j = nxt[j]

    ev_t[i] = best_t
    ev_key[i] = best_key
    ev_kind[i] = best_kind
    ev_partner[i] = best_p
    if best_kind == COLLISION:
        ev_pcount[i] = count[best_p]


@_jit
def _advance(pos, vel, tloc, i, t):
    dt = t - tloc[i]
    pos[i, 0] += vel[i, 0] * dt
    pos[i, 1] += vel[i, 1] * dt
    pos[i, 2] += vel[i, 2] * dt
    tloc[i] = t


@_jit
def build(pos, vel, tloc, rad, count, cc, cell, head, nxt, prv,
          ev_t, ev_key, ev_kind, ev_partner, ev_pcount, heap, hpos, f, c):
    """Fill the cells, predict every sphere from the clock, build the heap."""
    n = pos.shape[0]
    nc = c[C_NC]
    lo, w = f[F_LO], f[F_W]
    head[:] = -1
    t = f[F_CLOCK]
    for i in range(n):
        _advance(pos, vel, tloc, i, t)
        cc[i, 0] = cell_of(pos[i, 0], lo, w, nc)
        cc[i, 1] = cell_of(pos[i, 1], lo, w, nc)
        cc[i, 2] = cell_of(pos[i, 2], lo, w, nc)
        _cell_insert(head, nxt, prv, cell, i, (cc[i, 2] * nc + cc[i, 1]) * nc + cc[i, 0])
    for i in range(n):
        predict(pos, vel, tloc, rad, count, cc, head, nxt,
                ev_t, ev_key, ev_kind, ev_partner, ev_pcount, f, c, i, t)
    heap_build(heap, hpos, ev_t, ev_key)


@_jit
def refresh_window(pos, vel, tloc, rad, count, cc, head, nxt,
                   ev_t, ev_key, ev_kind, ev_partner, ev_pcount, heap, hpos, f, c,
                   fresh, stack):
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
    if ev_t[heap[0]] < limit:
        stack[0] = 0
        top = 1
    while top > 0:
        top -= 1
        k = stack[top]
        stack[n + found] = heap[k]
        found += 1
        for child in (2 * k + 1, 2 * k + 2):
            if child < n and ev_t[heap[child]] < limit:
                stack[top] = child
                top += 1
    for q in range(found):
        i = stack[n + q]
        if fresh[i] != serial:
            fresh[i] = serial
            predict(pos, vel, tloc, rad, count, cc, head, nxt,
                    ev_t, ev_key, ev_kind, ev_partner, ev_pcount, f, c, i, t)
            heap_update(heap, hpos, ev_t, ev_key, i)


@_jit
def run(pos, vel, tloc, mass, rad, count, cc, cell, head, nxt, prv,
        ev_t, ev_key, ev_kind, ev_partner, ev_pcount, heap, hpos, f, c,
        fresh, stack, until, max_events, max_collisions,
        rec_t, rec_kind, rec_i, rec_j, rec_imp):
    """Process events in order until one of the limits.

    Stops before the first event after ``until``, after ``max_events`` real
    events (collisions and reflections), or after ``max_collisions``
    collisions, whichever comes first; up to ``len(rec_t)`` real events are
    recorded (time, kind, i, j, impulse magnitude), and the run also stops
    when the record is full.

    Returns:
        ``(recorded, reason)``: reason 0 = ``until`` reached (or nothing will
        ever happen), 1 = ``max_events``, 2 = ``max_collisions``,
        3 = record full.
    """
    n = pos.shape[0]
    if n == 0:
        return 0, 0
    nc = c[C_NC]
    lo, w, box = f[F_LO], f[F_W], f[F_BOX]
    window = f[F_WINDOW]
    cap = rec_t.shape[0]
    done = 0
    coll0 = c[C_COLL]
    while True:
        if done >= max_events:
            return done, 1
        if c[C_COLL] - coll0 >= max_collisions:
            return done, 2
        if done >= cap:
            return done, 3
        i = heap[0]
        te = ev_t[i]
        if te > until or te == np.inf:
            return done, 0
        kind = ev_kind[i]
        if kind == COLLISION:
            j = ev_partner[i]
            if count[j] != ev_pcount[i]:
                # stale: the partner has changed course since
                c[C_STALE] += 1
                predict(pos, vel, tloc, rad, count, cc, head, nxt, ev_t, ev_key, ev_kind,
                        ev_partner, ev_pcount, f, c, i, f[F_CLOCK])
                heap_update(heap, hpos, ev_t, ev_key, i)
                continue
            f[F_CLOCK] = te
            f[F_ANCHOR] = te
            _advance(pos, vel, tloc, i, te)
            _advance(pos, vel, tloc, j, te)
            a, b = (i, j) if i < j else (j, i)
            dx = pos[a, 0] - pos[b, 0]
            dy = pos[a, 1] - pos[b, 1]
            dz = pos[a, 2] - pos[b, 2]
            if box != 0.0:
                # the partner may be an image across the box
                dx -= box * np.round(dx / box)
                dy -= box * np.round(dy / box)
                dz -= box * np.round(dz / box)
            k1, k2 = collide(mass[a], mass[b], dx, dy, dz,
                             vel[a, 0] - vel[b, 0], vel[a, 1] - vel[b, 1], vel[a, 2] - vel[b, 2])
            vel[a, 0] -= k1 * dx
            vel[a, 1] -= k1 * dy
            vel[a, 2] -= k1 * dz
            vel[b, 0] += k2 * dx
            vel[b, 1] += k2 * dy
            vel[b, 2] += k2 * dz
            d2 = dx * dx + dy * dy + dz * dz
            f[F_VIRIAL] -= mass[a] * k1 * d2
            count[a] += 1
            count[b] += 1
            c[C_COLL] += 1
            c[C_SERIAL] += 1
            fresh[a] = c[C_SERIAL]
            fresh[b] = c[C_SERIAL]
            predict(pos, vel, tloc, rad, count, cc, head, nxt, ev_t, ev_key, ev_kind,
                    ev_partner, ev_pcount, f, c, a, te)
            heap_update(heap, hpos, ev_t, ev_key, a)
            predict(pos, vel, tloc, rad, count, cc, head, nxt, ev_t, ev_key, ev_kind,
                    ev_partner, ev_pcount, f, c, b, te)
            heap_update(heap, hpos, ev_t, ev_key, b)
            rec_t[done] = te
            rec_kind[done] = COLLISION
            rec_i[done] = a
            rec_j[done] = b
            rec_imp[done] = -mass[a] * k1 * np.sqrt(d2)
            done += 1
            if window > 0.0:
                refresh_window(pos, vel, tloc, rad, count, cc, head, nxt, ev_t, ev_key,
                               ev_kind, ev_partner, ev_pcount, heap, hpos, f, c, fresh, stack)
        elif kind == WALL:
            f[F_CLOCK] = te
            f[F_ANCHOR] = te
            _advance(pos, vel, tloc, i, te)
            px, py, pz = pos[i, 0], pos[i, 1], pos[i, 2]
            k = reflect(px, py, pz, vel[i, 0], vel[i, 1], vel[i, 2])
            vel[i, 0] -= k * px
            vel[i, 1] -= k * py
            vel[i, 2] -= k * pz
            imp = mass[i] * k * np.sqrt(px * px + py * py + pz * pz)
            f[F_WALL_IMPULSE] += imp
            count[i] += 1
            c[C_WALL] += 1
            c[C_SERIAL] += 1
            fresh[i] = c[C_SERIAL]
            predict(pos, vel, tloc, rad, count, cc, head, nxt, ev_t, ev_key, ev_kind,
                    ev_partner, ev_pcount, f, c, i, te)
            heap_update(heap, hpos, ev_t, ev_key, i)
            rec_t[done] = te
            rec_kind[done] = WALL
            rec_i[done] = i
            rec_j[done] = -1
            rec_imp[done] = imp
            done += 1
            if window > 0.0:
                refresh_window(pos, vel, tloc, rad, count, cc, head, nxt, ev_t, ev_key,
                               ev_kind, ev_partner, ev_pcount, heap, hpos, f, c, fresh, stack)
        elif kind == CROSS:
            # not an event of the physics: the clock moves, the anchor of
            # the simultaneity window does not
            f[F_CLOCK] = te
            code = ev_partner[i]
            ax = code >> 1
            step = 1 if (code & 1) else -1
            k = cc[i, ax] + step
            if k < 0 or k >= nc:
                # periodic wrap: shift the stored position by one box edge
                k = (k + nc) % nc
                pos[i, ax] -= step * box
            cc[i, ax] = k
            _cell_remove(head, nxt, prv, cell, i)
            _cell_insert(head, nxt, prv, cell, i, (cc[i, 2] * nc + cc[i, 1]) * nc + cc[i, 0])
            c[C_CROSS] += 1
            predict(pos, vel, tloc, rad, count, cc, head, nxt, ev_t, ev_key, ev_kind,
                    ev_partner, ev_pcount, f, c, i, te)
            heap_update(heap, hpos, ev_t, ev_key, i)
        else:
            return done, 0


@_jit
def positions_at(pos, vel, tloc, t, out, box):
    """Centres of all spheres at time ``t`` into ``out`` (wrapped into the box)."""
    n = pos.shape[0]
    for i in range(n):
        dt = t - tloc[i]
        for k in range(3):
            x = pos[i, k] + vel[i, k] * dt
            if box != 0.0:
                x -= box * np.floor(x / box + 0.5)
            out[i, k] = x


@_jit
def rebase(pos, vel, tloc, ev_t, f):
    """Move the time origin to the clock: advance everyone, shift all times."""
    t = f[F_CLOCK]
    n = pos.shape[0]
    for i in range(n):
        _advance(pos, vel, tloc, i, t)
        tloc[i] = 0.0
        ev_t[i] -= t
    f[F_ANCHOR] -= t
    f[F_CLOCK] = 0.0
    return t


@_jit
def max_overlap(x, rad, cc, head, nxt, nc, box):
    """Largest ``1 - d / (R_i + R_j)`` over touching-or-overlapping pairs (0 if none).

    ``x`` are the centres at one time; neighbours are found through the
    engine's cells.
    """
    n = x.shape[0]
    worst = 0.0
    for i in range(n):
        for oz in range(-1, 2):
            nz = cc[i, 2] + oz
            for oy in range(-1, 2):
                ny = cc[i, 1] + oy
                for ox in range(-1, 2):
                    nx = cc[i, 0] + ox
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
                            sigma = rad[i] + rad[j]
                            if sigma > 0.0:
                                ov = 1.0 - np.sqrt(dx * dx + dy * dy + dz * dz) / sigma
                                if ov > worst:
                                    worst = ov
                        j = nxt[j]
    return worst

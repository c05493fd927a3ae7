"""The brute-force reference event loop: simple, obviously right, O(N^2) per event.

After every event it predicts every wall and every pair afresh, takes the
earliest, and processes it.  It is the definition the fast engine
(:mod:`hardspheres._core`) is tested against, and it runs the assignment's
program for small inputs, where it is faster than loading the compiled core.

Arithmetic shared with the engine, so that both give bit-identical results:

* each sphere is kept as its centre ``p`` at its own time ``tloc`` (the time
  of its last event); its centre at ``t`` is ``p + v * (t - tloc)``;
* a pair is predicted from the later of its two spheres' times, a wall from
  the sphere's own time, so a prediction does not depend on when it is made.

Rules of the assignment (``shared/conformance/README.md``):

* an event less than :data:`SIMULTANEOUS` after the last event (the clock)
  happens now, at the clock;
* among events at the same time, reflections go before collisions, lower
  input index first, pairs ``(i, j)`` with ``i < j`` in input order;
* events at times ``<= end`` are reported, none after.

And two of the model's own (both engines stop the same way, with
:class:`~hardspheres.scenario.StuckError`, before the event):

* a reflection that would not change the velocity (a sphere at the wall
  moving along it) is not an event: it would come again at once, forever;
* more than :func:`~hardspheres.physics.frozen_limit` collisions and
  reflections in a row with the clock not advancing: it is stuck.

Pure Python floats throughout (no numpy): see :mod:`hardspheres.physics`.
"""

from .physics import (
    FROZEN_RELATIVE,
    INF,
    collide,
    frozen_limit,
    pair_time,
    reflect,
    wall_time,
)
from .scenario import StuckError

#: Events closer than this to the current time happen now [time].
SIMULTANEOUS = 1e-8

#: Event kinds.
REFLECTION = 0
COLLISION = 1


def next_event(p, v, tloc, radii, container, clock, window=SIMULTANEOUS):
    """Earliest event as ``(t, kind, i, j)`` (``j = -1`` for walls).

    Events before ``clock + window`` are put at ``clock``; returns
    ``(inf, -1, -1, -1)`` when nothing will ever happen.
    """
    n = len(p)
    soon = clock + window
    best = INF
    best_kind, best_i, best_j = -1, -1, -1
    for i in range(n):
        pi, vi = p[i], v[i]
        te = tloc[i] + wall_time(pi[0], pi[1], pi[2], vi[0], vi[1], vi[2],
                                 container - radii[i])
        if te < soon:
            te = clock
        if te < best:
            best, best_kind, best_i, best_j = te, REFLECTION, i, -1
    for i in range(n):
        pi, vi, ri, ti = p[i], v[i], radii[i], tloc[i]
        for j in range(i + 1, n):
            pj, vj, tj = p[j], v[j], tloc[j]
            t0 = ti if ti > tj else tj
            di, dj = t0 - ti, t0 - tj
            te = t0 + pair_time(
                (pi[0] + vi[0] * di) - (pj[0] + vj[0] * dj),
                (pi[1] + vi[1] * di) - (pj[1] + vj[1] * dj),
                (pi[2] + vi[2] * di) - (pj[2] + vj[2] * dj),
                vi[0] - vj[0], vi[1] - vj[1], vi[2] - vj[2], ri + radii[j])
            if te < soon:
                te = clock
            if te < best:
                best, best_kind, best_i, best_j = te, COLLISION, i, j
    return best, best_kind, best_i, best_j


def advance(p, v, tloc, i, t):
    """Move sphere ``i`` along its line to time ``t``."""
    pi, vi = p[i], v[i]
    dt = t - tloc[i]
    pi[0] += vi[0] * dt
    pi[1] += vi[1] * dt
    pi[2] += vi[2] * dt
    tloc[i] = t


def positions_at(p, v, tloc, t):
    """Centres of all spheres at time ``t``, as a new list of lists."""
    out = []
    for pi, vi, ti in zip(p, v, tloc):
        dt = t - ti
        out.append([pi[0] + vi[0] * dt, pi[1] + vi[1] * dt, pi[2] + vi[2] * dt])
    return out


def apply_event(kind, i, j, p, v, masses):
    """Change the velocities for one event.

    Returns:
        The magnitude of the impulse the event gives sphere ``i`` [mass*length/time].
    """
    if kind == REFLECTION:
        pi, vi = p[i], v[i]
        k = reflect(pi[0], pi[1], pi[2], vi[0], vi[1], vi[2])
        vi[0] -= k * pi[0]
        vi[1] -= k * pi[1]
        vi[2] -= k * pi[2]
        return masses[i] * k * (pi[0] * pi[0] + pi[1] * pi[1] + pi[2] * pi[2]) ** 0.5
    pi, pj, vi, vj = p[i], p[j], v[i], v[j]
    dx, dy, dz = pi[0] - pj[0], pi[1] - pj[1], pi[2] - pj[2]
    k1, k2 = collide(masses[i], masses[j], dx, dy, dz,
                     vi[0] - vj[0], vi[1] - vj[1], vi[2] - vj[2])
    vi[0] -= k1 * dx
    vi[1] -= k1 * dy
    vi[2] -= k1 * dz
    vj[0] += k2 * dx
    vj[1] += k2 * dy
    vj[2] += k2 * dz
    return -masses[i] * k1 * (dx * dx + dy * dy + dz * dz) ** 0.5


def events(masses, radii, positions, velocities, container, end,
           window=SIMULTANEOUS):
    """Run the brute-force loop, yielding ``(t, kind, i, j, state)`` per event.

    ``positions`` and ``velocities`` are lists of ``[x, y, z]`` lists at time
    0, changed in place; ``state()`` returns the centres of all spheres at
    the event's time (``velocities`` then hold the velocities just after it).

    Example:
        >>> p = [[-5.0, 0.0, 0.0], [5.0, 0.0, 0.0]]
        >>> v = [[1.0, 0.0, 0.0], [-1.0, 0.0, 0.0]]
        >>> [e[:2] for e in events([1.0, 1.0], [1.0, 1.0], p, v, 100.0, 5.0)]
        [(4.0, 1)]
        >>> v
        [[-1.0, 0.0, 0.0], [1.0, 0.0, 0.0]]
    """
    p, v = positions, velocities
    tloc = [0.0] * len(p)
    clock = 0.0
    limit = frozen_limit(len(p))
    frozen = 0  # collisions and reflections in a row with the clock not advancing
    streak = 0.0  # time of the first of them
    while True:
        t, kind, i, j = next_event(p, v, tloc, radii, container, clock, window)
        if kind < 0 or not t <= end:
            return
        if t - streak <= FROZEN_RELATIVE * abs(t):
            if frozen >= limit:
                raise StuckError("frozen", t, i)
        else:
            frozen = 0
            streak = t
        if kind == REFLECTION:
            pi, vi = p[i], v[i]
            dt = t - tloc[i]
            if reflect(pi[0] + vi[0] * dt, pi[1] + vi[1] * dt, pi[2] + vi[2] * dt,
                       vi[0], vi[1], vi[2]) == 0.0:
                raise StuckError("sliding", t, i)
        frozen += 1
        clock = t
        advance(p, v, tloc, i, t)
        if j >= 0:
            advance(p, v, tloc, j, t)
        apply_event(kind, i, j, p, v, masses)
        yield t, kind, i, j, lambda: positions_at(p, v, tloc, t)

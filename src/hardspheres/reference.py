"""The brute-force reference event loop: simple, obviously right, O(N^2) per event.

After every event it predicts every wall and every pair afresh from the
current positions, takes the earliest, and advances *all* spheres to it.  It
is the definition the fast engine (:mod:`hardspheres._core`) is tested
against, and it runs the assignment's program for small inputs, where it is
faster than importing and loading the compiled core.

Rules of the assignment (``shared/conformance/README.md``):

* an event less than :data:`SIMULTANEOUS` after the current time happens now:
  the clock and the positions do not move;
* among events happening at the same time, reflections go before
  collisions, lower input index first, pairs ``(i, j)`` with ``i < j`` in
  input order;
* events at times ``<= end`` are reported, none after.

Pure Python floats throughout (no numpy): see :mod:`hardspheres.physics`.
"""

from .physics import INF, collide, pair_time, reflect, wall_time

#: Events closer than this to the current time happen now [time].
SIMULTANEOUS = 1e-8

#: Event kinds.
REFLECTION = 0
COLLISION = 1


def next_event(p, v, radii, container):
    """Earliest event from now as ``(dt, kind, i, j)`` (``j = -1`` for walls).

    ``dt`` is 0 for events within :data:`SIMULTANEOUS` of now; returns
    ``(inf, -1, -1, -1)`` when nothing will ever happen.
    """
    n = len(p)
    best = INF
    best_kind, best_i, best_j = -1, -1, -1
    now_found = False
    for i in range(n):
        pi, vi = p[i], v[i]
        dt = wall_time(pi[0], pi[1], pi[2], vi[0], vi[1], vi[2], container - radii[i])
        if dt < SIMULTANEOUS:
            return 0.0, REFLECTION, i, -1
        if dt < best:
            best, best_kind, best_i, best_j = dt, REFLECTION, i, -1
    for i in range(n):
        pi, vi, ri = p[i], v[i], radii[i]
        for j in range(i + 1, n):
            pj, vj = p[j], v[j]
            dt = pair_time(pi[0] - pj[0], pi[1] - pj[1], pi[2] - pj[2],
                           vi[0] - vj[0], vi[1] - vj[1], vi[2] - vj[2], ri + radii[j])
            if dt < SIMULTANEOUS and not now_found:
                now_found = True
                best, best_kind, best_i, best_j = 0.0, COLLISION, i, j
            elif dt < best:
                best, best_kind, best_i, best_j = dt, COLLISION, i, j
    return best, best_kind, best_i, best_j


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


def events(masses, radii, positions, velocities, container, end):
    """Run the brute-force loop, yielding ``(t, kind, i, j)`` after each event.

    ``positions`` and ``velocities`` are lists of ``[x, y, z]`` lists, updated
    in place: when an event is yielded they hold the state just after it.

    Example:
        >>> p = [[-5.0, 0.0, 0.0], [5.0, 0.0, 0.0]]
        >>> v = [[1.0, 0.0, 0.0], [-1.0, 0.0, 0.0]]
        >>> [e[:2] for e in events([1.0, 1.0], [1.0, 1.0], p, v, 100.0, 5.0)]
        [(4.0, 1)]
        >>> v
        [[-1.0, 0.0, 0.0], [1.0, 0.0, 0.0]]
    """
    t = 0.0
    p, v = positions, velocities
    while True:
        dt, kind, i, j = next_event(p, v, radii, container)
        if kind < 0 or t + dt > end:
            return
        if dt > 0.0:
            t += dt
            for pk, vk in zip(p, v):
                pk[0] += vk[0] * dt
                pk[1] += vk[1] * dt
                pk[2] += vk[2] * dt
        apply_event(kind, i, j, p, v, masses)
        yield t, kind, i, j

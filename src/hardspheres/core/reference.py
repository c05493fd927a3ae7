"""The brute-force reference engine: simple, obviously right, O(N^2) per event.

:class:`Reference` speaks the compiled :class:`~hardspheres.core.engine.Engine`'s
interface (as DynamO keeps its brute-force scheduler behind the same
interface as its fast ones): the same constructor, :meth:`~Reference.step`,
:meth:`~Reference.advance`, :meth:`~Reference.positions_at`, ``velocities``,
``counters``, so the assignment's program has one loop for both and the
tests run one test on either.  After every event it predicts every wall and
every pair afresh, takes the earliest, and processes it.  It is the
definition the engine is tested against, and it runs the assignment's
program for small inputs, where it is faster than loading the compiled core.

Arithmetic shared with the engine, so that both give bit-identical results
(from time 0, engine built with ``rebase=False``):

* each sphere is kept as its centre ``p`` at its own time ``tloc`` (the time
  of its last event); its centre at ``t`` is ``p + v * (t - tloc)``;
* a pair is predicted from the later of its two spheres' times, a wall from
  the sphere's own time, so a prediction does not depend on when it is made;
* periodic boxes: a centre is kept in the box by moving it one side back
  at the instant it leaves (:func:`box_exit`, from the sphere's own centre
  and time; the core's ``_box_exit``), a pair is predicted at each of the
  images next to it (``x_i - (x_j + k L)``, ``k`` in -1, 0, 1 per axis) and
  collides at its nearest image (``dx - L round(dx / L)``);
* growth: radii ``R_i (1 + g t)`` with ``t`` from the time origin, which
  :meth:`Reference.set_growth` moves to the clock as the engine's does
  (every centre moved there, the radii to their values then).

The engine equals it bit for bit when built with ``rebase=False`` at time
0 (no moves of the time origin but those of ``set_growth``), in containers
and boxes, in two and three dimensions, in cell and list modes
(tests/test_engine.py, tests/test_planar.py, tests/test_reference_boxes.py).

Rules of the assignment (``tests/data/assignment/README.md``):

* an event less than the window (the program's :data:`SIMULTANEOUS`) after
  the last event (the clock) happens now, at the clock;
* among events at the same time, reflections go before collisions, lower
  input index first, pairs ``(i, j)`` with ``i < j`` in input order;
* events at times ``<= until`` are processed, none after.

And two of the model's own (both engines stop the same way, with
:class:`~hardspheres.scenario.StuckError`, before the event):

* a reflection that would not change the velocity (a sphere at the wall
  moving along it) is not an event: it would come again at once, forever;
* more than :func:`~hardspheres.physics.frozen_limit` collisions and
  reflections in a row with the clock not advancing: it is stuck.

Pure Python floats throughout (no numpy, which the assignment's program does
not load for small inputs; only :meth:`Reference.advance`'s event record and
:meth:`Reference.kinetic_energy` load it).  The loop's steps are module
functions (:func:`next_event`, :func:`move_sphere`, :func:`apply_event`) on
sequences of ``[x, y, z]``: lists here, numpy arrays where the tests compile
the same functions with numba to check the engine at larger ``N``.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

from ..containers import Container, as_container, require_periodic
from ..errors import ArgumentError, BoxShapeError, ShearError
from ..events import EventKind, StopReason
from ..physics import (
    FROZEN_RELATIVE,
    INF,
    collide,
    collide_grow,
    collide_inelastic,
    cross_step,
    frozen_limit,
    pair_time,
    pair_time_grow,
    pair_time_out,
    reflect,
    reflect_grow,
    reflect_inelastic,
    thermal_wall,
    wall_time,
    wall_time_grow,
)
from ..scenario import StuckError

if TYPE_CHECKING:
    import numpy as np

#: The assignment's simultaneity window: events closer than this to the
#: current time happen now [time].
SIMULTANEOUS = 1e-8

#: Event kinds (:class:`~hardspheres.events.EventKind`'s numbers, as plain
#: ints for the loop's speed).
REFLECTION = int(EventKind.REFLECTION)
COLLISION = int(EventKind.COLLISION)
#: A centre leaving the periodic box (moved by one side; not an event of the physics).
CROSSING = 2
#: A stepped pair potential's kinds (:class:`~hardspheres.events.EventKind`):
#: a pair crossed a step inward, outward, or bounced at it.  The predictions
#: use ``CAPTURE`` for "reaches its inner edge" and ``RELEASE`` for "reaches
#: its outer edge"; whether it crosses is decided when the event is processed.
CAPTURE = int(EventKind.CAPTURE)
RELEASE = int(EventKind.RELEASE)
BOUNCE = int(EventKind.BOUNCE)

_NEVER = 1 << 62  # no count limit


def next_event(
    p: list[list[float]],
    v: list[list[float]],
    tloc: list[float],
    radii: list[float],
    wall: float,
    clock: float,
    window: float,
    grow: float = 0.0,
    planar: bool = False,
) -> tuple[float, int, int, int]:
    """Earliest event in the spherical (or circular) container as ``(t, kind, i, j)`` (``j = -1`` for walls).

    Args:
        p, v: ``N`` centres (at each sphere's own time) and velocities.
        tloc: ``N`` times of the spheres' last events [time].
        radii: ``N`` radii [length] at the time origin (time 0).
        wall: the container's radius [length].
        clock: the time of the last event [time].
        window: events before ``clock + window`` are put at ``clock`` [time].
        grow: the radii grow as ``radii * (1 + grow * t)`` [1/time] (0: they do not).
        planar: 2-D (the kernels read no z).

    Returns:
        ``(t, kind, i, j)``, or ``(inf, -1, -1, -1)`` when nothing will ever
        happen.
    """
    n = len(p)
    soon = clock + window
    best = INF
    best_kind, best_i, best_j = -1, -1, -1
    for i in range(n):
        pi, vi = p[i], v[i]
        if grow == 0.0:
            te = tloc[i] + wall_time(pi[0], pi[1], pi[2], vi[0], vi[1], vi[2], wall - radii[i], planar)
        else:  # (the core's arithmetic: wall_time_grow is wall_time at growth 0)
            reach = wall - radii[i] * (1.0 + grow * tloc[i])
            te = tloc[i] + wall_time_grow(
                pi[0], pi[1], pi[2], vi[0], vi[1], vi[2], reach, radii[i] * grow, planar
            )
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
            dx = (pi[0] + vi[0] * di) - (pj[0] + vj[0] * dj)
            dy = (pi[1] + vi[1] * di) - (pj[1] + vj[1] * dj)
            dz = (pi[2] + vi[2] * di) - (pj[2] + vj[2] * dj)
            sigma = ri + radii[j]
            if grow == 0.0:
                te = t0 + pair_time(dx, dy, dz, vi[0] - vj[0], vi[1] - vj[1], vi[2] - vj[2], sigma, planar)
            else:
                te = t0 + pair_time_grow(
                    dx,
                    dy,
                    dz,
                    vi[0] - vj[0],
                    vi[1] - vj[1],
                    vi[2] - vj[2],
                    sigma * (1.0 + grow * t0),
                    sigma * grow,
                    INF,
                    planar,
                )
            if te < soon:
                te = clock
            if te < best:
                best, best_kind, best_i, best_j = te, COLLISION, i, j
    return best, best_kind, best_i, best_j


def box_exit(
    pi: list[float], vi: list[float], ti: float, edges: tuple[float, float, float], now: float
) -> tuple[float, int]:
    """When and by which face a centre next leaves the periodic box: ``(t, 2 * axis + up)``.

    From the sphere's stored centre ``pi`` at its own time ``ti`` alone (the
    box spans ``[-L/2, L/2)`` per periodic axis), never before ``now``: the
    core's ``_box_exit``, to the bit.
    """
    best = INF
    code = -1
    for ax in range(3):
        edge = edges[ax]
        vel = vi[ax]
        if edge == 0.0 or vel == 0.0:
            continue
        lo = -0.5 * edge
        if vel > 0.0:
            tw = ti + ((lo + edge) - pi[ax]) / vel
            up = 1
        else:
            tw = ti + (lo - pi[ax]) / vel
            up = 0
        if tw < best:
            best = tw
            code = 2 * ax + up
    if best < now:
        best = now
    return best, code


def _earlier(t: float, kind: int, i: int, j: int, bt: float, bk: int, bi: int, bj: int) -> bool:
    """Whether ``(t, kind, i, j)`` comes before ``(bt, bk, bi, bj)`` (the tie order)."""
    if t != bt:
        return t < bt
    if kind != bk:
        return kind < bk
    if i != bi:
        return i < bi
    return j < bj


def next_event_periodic(
    p: list[list[float]],
    v: list[list[float]],
    tloc: list[float],
    radii: list[float],
    edges: tuple[float, float, float],
    clock: float,
    window: float,
    grow: float,
    now: float,
    planar: bool = False,
) -> tuple[float, int, int, int]:
    """Earliest event in the periodic box as ``(t, kind, i, j)``: a collision or a centre leaving the box.

    Longer than 80 lines with this docstring (under 70 of code): every
    pair's images and the pruning that keeps it affordable, in one loop.

    Each centre is kept in the box by moving it one side when it leaves
    (kind :data:`CROSSING`, ``j`` the face: ``2 * axis + up``), so every
    pair has at most one image within reach of a contact until the next
    such move, among the ``3^d`` next to it; all are tried.  Pairs and
    images that cannot meet before the earliest event found so far (a
    bound with a margin of 1e-9 over the window's end) are skipped; that
    changes only the work.

    Args:
        p, v, tloc, radii, clock, window, grow: as :func:`next_event`.
        edges: the box's sides ``(Lx, Ly, Lz)`` [length] (``Lz = 0`` in 2-D).
        now: the time of the last move or event [time] (a move is never earlier).
        planar: 2-D (the kernels read no z).
    """
    n = len(p)
    soon = clock + window
    best, best_kind, best_i, best_j = INF, -1, -1, -1
    for i in range(n):
        tw, face = box_exit(p[i], v[i], tloc[i], edges, now)
        if face >= 0 and _earlier(tw, CROSSING, i, face, best, best_kind, best_i, best_j):
            best, best_kind, best_i, best_j = tw, CROSSING, i, face
    m0 = 1 if edges[0] != 0.0 else 0
    m1 = 1 if edges[1] != 0.0 else 0
    m2 = 1 if edges[2] != 0.0 else 0
    for i in range(n):
        pi, vi, ri, ti = p[i], v[i], radii[i], tloc[i]
        for j in range(i + 1, n):
            pj, vj, tj = p[j], v[j], tloc[j]
            t0 = ti if ti > tj else tj
            di, dj = t0 - ti, t0 - tj
            xi, yi, zi = pi[0] + vi[0] * di, pi[1] + vi[1] * di, pi[2] + vi[2] * di
            xj, yj, zj = pj[0] + vj[0] * dj, pj[1] + vj[1] * dj, pj[2] + vj[2] * dj
            dvx, dvy, dvz = vi[0] - vj[0], vi[1] - vj[1], vi[2] - vj[2]
            sigma = ri + radii[j]
            # how far each axis may close before the earliest event so far
            bound = (best if best > soon else soon) - t0
            if bound < 0.0:
                bound = 0.0
            reach = sigma * (1.0 + grow * (t0 + bound)) if grow != 0.0 else sigma
            for kx in range(-m0, m0 + 1):
                sx = kx * edges[0]
                if abs(xi - (xj + sx)) > (reach + abs(dvx) * bound) * (1.0 + 1e-9):
                    continue
                for ky in range(-m1, m1 + 1):
                    sy = ky * edges[1]
                    if abs(yi - (yj + sy)) > (reach + abs(dvy) * bound) * (1.0 + 1e-9):
                        continue
                    for kz in range(-m2, m2 + 1):
                        sz = kz * edges[2]
                        dx, dy, dz = xi - (xj + sx), yi - (yj + sy), zi - (zj + sz)
                        if abs(dz) > (reach + abs(dvz) * bound) * (1.0 + 1e-9):
                            continue
                        if grow == 0.0:
                            te = t0 + pair_time(dx, dy, dz, dvx, dvy, dvz, sigma, planar)
                        else:
                            s0, u = sigma * (1.0 + grow * t0), sigma * grow
                            te = t0 + pair_time_grow(dx, dy, dz, dvx, dvy, dvz, s0, u, INF, planar)
                        if te < soon:
                            te = clock
                        if _earlier(te, COLLISION, i, j, best, best_kind, best_i, best_j):
                            best, best_kind, best_i, best_j = te, COLLISION, i, j
    return best, best_kind, best_i, best_j


# ---- steps: square wells and shoulders --------------------------------------------
# A stepped pair potential: a hard core at sigma = R_i + R_j, then edges at
# lambda_k sigma (k = 0 the outermost), the pair's state the number of edges
# it is inside (0: outside every step).  docs/design/interactions.md,
# sections 2-4, and docs/numerics.md, "Steps: wells and shoulders".


def step_table(
    steps: Sequence[Sequence[float]] | Mapping[tuple[int, int], Sequence[Sequence[float]]],
) -> dict[tuple[int, int], tuple[tuple[float, ...], tuple[float, ...]]]:
    """Steps for every pair of species: ``{(s, t): (lambdas, energies)}``, symmetric.

    ``steps`` is one list ``[(lambda_k, U_k), ...]`` for every pair (one
    species, or all alike), or a dict ``{(s, t): [(lambda_k, U_k), ...]}``
    per pair of species (each unordered pair once; a pair left out, or
    given ``[]``, is hard spheres).

    Raises:
        ArgumentError: steps out of order (:func:`check_steps`), a species
            pair given twice or with a negative species.

    Example:
        >>> step_table({(0, 1): [(1.5, -1.0)]})[(1, 0)]
        ((1.5,), (-1.0,))
    """
    if not isinstance(steps, Mapping):
        return {(0, 0): check_steps(steps)}
    out: dict[tuple[int, int], tuple[tuple[float, ...], tuple[float, ...]]] = {}
    for key, rows in steps.items():
        try:
            s, t = (int(x) for x in key)
        except (TypeError, ValueError):
            raise ArgumentError(f"steps key {key!r}: give a pair of species (s, t)") from None
        if s < 0 or t < 0 or (s, t) in out:
            raise ArgumentError(f"steps key {key!r}: give each pair of species >= 0 once")
        out[(s, t)] = out[(t, s)] = check_steps(rows) if len(rows) else ((), ())
    return out


def check_steps(steps: Sequence[Sequence[float]]) -> tuple[tuple[float, ...], tuple[float, ...]]:
    """The steps ``[(lambda_k, U_k), ...]`` (outermost first) as ``(lambdas, energies)``.

    ``U_k`` [energy] is the potential energy of a pair inside edge ``k``
    (and outside edge ``k + 1``); outside every edge it is 0.

    Raises:
        ArgumentError: not pairs of finite numbers with ``lambda_0 > lambda_1
            > ... > 1``.

    Example:
        >>> check_steps([(1.5, -1.0)])
        ((1.5,), (-1.0,))
    """
    lams: list[float] = []
    energies: list[float] = []
    for row in steps:
        if len(row) != 2:
            raise ArgumentError(f"step {tuple(row)!r}: give (lambda, energy) pairs, outermost first")
        lam, u = float(row[0]), float(row[1])
        if not (math.isfinite(lam) and math.isfinite(u)) or lam <= 1.0 or (lams and lam >= lams[-1]):
            raise ArgumentError(
                f"step ({lam}, {u}): give finite (lambda, energy) pairs with lambda decreasing from the "
                "outermost and above 1 (the core)"
            )
        lams.append(lam)
        energies.append(u)
    return tuple(lams), tuple(energies)


def step_state(d2: float, sigma: float, lams: Sequence[float]) -> int:
    """A pair's state at squared distance ``d2`` [length^2]: how many edges ``lambda_k sigma`` it is inside.

    Example:
        >>> step_state(1.2**2, 1.0, (1.5, 1.25)), step_state(2.0**2, 1.0, (1.5,))
        (2, 0)
    """
    k = 0
    for lam in lams:
        r = lam * sigma
        if d2 < r * r:
            k += 1
    return k


def pair_step_time(
    dx: float,
    dy: float,
    dz: float,
    dvx: float,
    dvy: float,
    dvz: float,
    sigma: float,
    lams: Sequence[float],
    state: int,
    planar: bool = False,
) -> tuple[float, int]:
    """A stepped pair's next event from now: ``(dt, kind)``, ``kind`` -1 for none.

    The inner edge (the core, kind ``COLLISION``, in the innermost state;
    else the next step in, ``CAPTURE``) from outside with
    :func:`~hardspheres.physics.pair_time`; when the chord misses it, the
    outer edge (``RELEASE``, states >= 1) from inside with
    :func:`~hardspheres.physics.pair_time_out`.
    """
    inner = sigma if state == len(lams) else lams[state] * sigma
    t = pair_time(dx, dy, dz, dvx, dvy, dvz, inner, planar)
    if t < INF:
        return t, (COLLISION if state == len(lams) else CAPTURE)
    if state == 0:
        return INF, -1
    return pair_time_out(dx, dy, dz, dvx, dvy, dvz, lams[state - 1] * sigma, planar), RELEASE


def _tie(kind: int) -> int:
    """The kind an event ties as: every pair event as a collision."""
    return COLLISION if kind >= CAPTURE else kind


def next_event_stepped(
    p: list[list[float]],
    v: list[list[float]],
    tloc: list[float],
    radii: list[float],
    wall: float,
    edges: tuple[float, float, float],
    clock: float,
    window: float,
    now: float,
    planar: bool,
    table: Sequence[Sequence[Sequence[float]]],
    states: dict[tuple[int, int], int],
    species: Sequence[int],
) -> tuple[float, int, int, int]:
    """:func:`next_event` (``edges`` zeros) or :func:`next_event_periodic` with steps.

    Longer than 80 lines with this docstring: the container's walls, the
    box's crossings and every pair's images in one loop, as those two.

    A pair in a step (``states[(i, j)] >= 1``) is predicted at its nearest
    image alone (the outermost edge is within half the box: no other image
    can reach it first); a pair outside every step at each image next to it,
    pruned as :func:`next_event_periodic` with the outermost edge for the
    contact distance.  Kinds as :func:`pair_step_time`; all pair events tie
    as collisions.  ``table[s][t]``: the edges' factors ``lambda_k`` of a
    pair of species ``s`` and ``t`` (empty: hard spheres for that pair);
    ``species``: each sphere's.
    """
    n = len(p)
    soon = clock + window
    best, best_kind, best_i, best_j = INF, -1, -1, -1
    periodic = edges[0] != 0.0
    for i in range(n):
        if periodic:
            te, face = box_exit(p[i], v[i], tloc[i], edges, now)
            if face >= 0 and _earlier(te, CROSSING, i, face, best, _tie(best_kind), best_i, best_j):
                best, best_kind, best_i, best_j = te, CROSSING, i, face
            continue
        pi, vi = p[i], v[i]
        te = tloc[i] + wall_time(pi[0], pi[1], pi[2], vi[0], vi[1], vi[2], wall - radii[i], planar)
        if te < soon:
            te = clock
        if _earlier(te, REFLECTION, i, -1, best, _tie(best_kind), best_i, best_j):
            best, best_kind, best_i, best_j = te, REFLECTION, i, -1
    m = [1 if edges[ax] != 0.0 else 0 for ax in range(3)]
    for i in range(n):
        pi, vi, ri, ti = p[i], v[i], radii[i], tloc[i]
        for j in range(i + 1, n):
            pair_lams = table[species[i]][species[j]]  # the pair's species' edges, outermost first
            outer = pair_lams[0] if pair_lams else 1.0
            pj, vj, tj = p[j], v[j], tloc[j]
            t0 = ti if ti > tj else tj
            di, dj = t0 - ti, t0 - tj
            xi = (pi[0] + vi[0] * di, pi[1] + vi[1] * di, pi[2] + vi[2] * di)
            xj = (pj[0] + vj[0] * dj, pj[1] + vj[1] * dj, pj[2] + vj[2] * dj)
            dv = (vi[0] - vj[0], vi[1] - vj[1], vi[2] - vj[2])
            sigma = ri + radii[j]
            state = states.get((i, j), 0)
            if state or not periodic:
                # the nearest image (the only one in a container)
                d = [0.0, 0.0, 0.0]
                for ax in range(3):
                    raw = xi[ax] - xj[ax]
                    k = round(raw / edges[ax]) if m[ax] else 0
                    d[ax] = xi[ax] - (xj[ax] + k * edges[ax]) if k else raw
                dt, kind = pair_step_time(
                    d[0], d[1], d[2], dv[0], dv[1], dv[2], sigma, pair_lams, state, planar
                )
                te = t0 + dt
                if kind >= 0 and te < soon:
                    te = clock
                if kind >= 0 and _earlier(te, COLLISION, i, j, best, _tie(best_kind), best_i, best_j):
                    best, best_kind, best_i, best_j = te, kind, i, j
                continue
            bound = (best if best > soon else soon) - t0
            if bound < 0.0:
                bound = 0.0
            reach = outer * sigma
            for kx in range(-m[0], m[0] + 1):
                dx = xi[0] - (xj[0] + kx * edges[0])
                if abs(dx) > (reach + abs(dv[0]) * bound) * (1.0 + 1e-9):
                    continue
                for ky in range(-m[1], m[1] + 1):
                    dy = xi[1] - (xj[1] + ky * edges[1])
                    if abs(dy) > (reach + abs(dv[1]) * bound) * (1.0 + 1e-9):
                        continue
                    for kz in range(-m[2], m[2] + 1):
                        dz = xi[2] - (xj[2] + kz * edges[2])
                        if abs(dz) > (reach + abs(dv[2]) * bound) * (1.0 + 1e-9):
                            continue
                        dt, kind = pair_step_time(
                            dx, dy, dz, dv[0], dv[1], dv[2], sigma, pair_lams, 0, planar
                        )
                        te = t0 + dt
                        if kind >= 0 and te < soon:
                            te = clock
                        if kind >= 0 and _earlier(te, COLLISION, i, j, best, _tie(best_kind), best_i, best_j):
                            best, best_kind, best_i, best_j = te, kind, i, j
    return best, best_kind, best_i, best_j


def shear_offset(offset0: float, speed: float, lx: float, t: float) -> float:
    """The Lees-Edwards offset at time ``t``: ``(offset0 + speed t) mod lx``, in ``[0, lx]`` [length].

    ``speed`` is the boundary speed ``g L_y`` [length/time], ``t`` the time
    from the instant the offset was ``offset0`` [time].  Python's float
    ``%`` (and numba's, the same bits) is C's exact ``fmod`` followed, for a
    negative remainder, by ``+ lx`` (one rounding, which may give ``lx``
    itself: the same images); so the only other rounding is that of
    ``offset0 + speed t``.  DynamO's ``BCLeesEdwards::update`` keeps the same
    quantity (``_dxd``), reduced with ``floor``.

    Example:
        >>> shear_offset(0.5, 2.0, 3.0, 1.5), shear_offset(0.0, -1.0, 3.0, 1.0)
        (0.5, 2.0)
    """
    return (offset0 + speed * t) % lx


def next_event_sheared(
    p: list[list[float]],
    v: list[list[float]],
    tloc: list[float],
    radii: list[float],
    edges: tuple[float, float, float],
    clock: float,
    window: float,
    now: float,
    planar: bool,
    offset0: float,
    speed: float,
) -> tuple[float, int, int, int]:
    """:func:`next_event_periodic` in a box sheared by Lees-Edwards boundaries (no growth).

    Longer than 80 lines with this docstring (under 70 of code): every
    pair's images, sliding ones included, and their pruning, in one loop.

    The image of ``j`` across a y face (``ky = +-1``) is at ``x_j + kx L_x +
    ky delta(t0)``, ``y_j + ky L_y``, moving at ``v_xj + ky speed`` along x,
    where ``delta(t0)`` is :func:`shear_offset` at the later of the two own
    times ``t0`` (so a prediction does not depend on when it is made); the
    pair is formed as ``x_i - (x_j + s)`` with ``s = kx L_x + ky delta`` and
    ``dv_x = v_xi - (v_xj + ky speed)``.  Those images slide past ``i``
    with no event of either sphere, so the ``kx`` tried are every one whose
    image can come within contact along x before the earliest event found
    so far (the crossings, found first, bound it), or, with no such event,
    within the time the pair can stay within contact along y and z, or one
    sweep of ``2 L_x`` plus the contact distances, from the clock on (an
    image met between ``t0`` and the clock would have been a collision
    then): a superset of the images that can meet first, which changes no
    bit (the earliest event wins).

    Args:
        p, v, tloc, radii, edges, clock, window, now, planar: as
            :func:`next_event_periodic`.
        offset0: the offset at time 0 [length].
        speed: the boundary speed ``g L_y`` [length/time].
    """
    n = len(p)
    soon = clock + window
    best, best_kind, best_i, best_j = INF, -1, -1, -1
    for i in range(n):
        tw, face = box_exit(p[i], v[i], tloc[i], edges, now)
        if face >= 0 and _earlier(tw, CROSSING, i, face, best, best_kind, best_i, best_j):
            best, best_kind, best_i, best_j = tw, CROSSING, i, face
    lx, ly, lz = edges[0], edges[1], edges[2]
    m2 = 0 if planar else 1
    for i in range(n):
        pi, vi, ri, ti = p[i], v[i], radii[i], tloc[i]
        for j in range(i + 1, n):
            pj, vj, tj = p[j], v[j], tloc[j]
            t0 = ti if ti > tj else tj
            di, dj = t0 - ti, t0 - tj
            xi, yi, zi = pi[0] + vi[0] * di, pi[1] + vi[1] * di, pi[2] + vi[2] * di
            xj, yj, zj = pj[0] + vj[0] * dj, pj[1] + vj[1] * dj, pj[2] + vj[2] * dj
            dvy, dvz = vi[1] - vj[1], vi[2] - vj[2]
            sigma = ri + radii[j]
            bound = (best if best > soon else soon) - t0
            if bound < 0.0:
                bound = 0.0
            delta = shear_offset(offset0, speed, lx, t0)
            for ky in range(-1, 2):
                sy = ky * ly
                dy0 = yi - (yj + sy)
                if abs(dy0) > (sigma + abs(dvy) * bound) * (1.0 + 1e-9):
                    continue
                dvx = vi[0] - (vj[0] + ky * speed)
                base = ky * delta
                # the images that can come within reach along x from the clock on
                # (none met the pair between t0 and the clock: it would have collided)
                start = clock - t0 if clock > t0 else 0.0
                span = bound
                if span == INF:
                    if dvy != 0.0:
                        span = (abs(dy0) + sigma) / abs(dvy) * (1.0 + 1e-9)
                    if not planar and dvz != 0.0:
                        dz0 = abs(zi - zj)
                        dz0 = dz0 if dz0 < lz - dz0 else lz - dz0
                        tz = (dz0 + sigma) / abs(dvz) * (1.0 + 1e-9)
                        span = tz if tz < span else span
                    if span == INF and dvx != 0.0:
                        span = start + (2.0 * lx + 2.0 * sigma) / abs(dvx)
                if span < start:
                    continue  # out of reach along y or z before the clock, for good
                # dx(t0 + s) = x_i - (x_j + base) - kx L_x + dv_x s: kx near u0 + dv_x s / L_x
                u0 = (xi - (xj + base)) / lx
                ua = u0 + (dvx * start) / lx if dvx != 0.0 else u0
                ub = u0 + (dvx * span) / lx if dvx != 0.0 else u0
                lo = ua if ua < ub else ub
                hi = ub if ua < ub else ua
                margin = sigma / lx * (1.0 + 1e-9)
                for kx in range(int(math.floor(lo - margin)) - 1, int(math.ceil(hi + margin)) + 2):
                    sx = kx * lx + base
                    dx = xi - (xj + sx)
                    if abs(dx) > (sigma + abs(dvx) * bound) * (1.0 + 1e-9):
                        continue
                    for kz in range(-m2, m2 + 1):
                        sz = kz * lz
                        dz = zi - (zj + sz)
                        if abs(dz) > (sigma + abs(dvz) * bound) * (1.0 + 1e-9):
                            continue
                        te = t0 + pair_time(dx, dy0, dz, dvx, dvy, dvz, sigma, planar)
                        if te < soon:
                            te = clock
                        if _earlier(te, COLLISION, i, j, best, best_kind, best_i, best_j):
                            best, best_kind, best_i, best_j = te, COLLISION, i, j
    return best, best_kind, best_i, best_j


def peculiar_segment(
    m: float, y0: float, vx: float, vy: float, vz: float, g: float, tau: float, out: list[float]
) -> None:
    """Add one sphere's ``int m c_a c_b dt`` over a free flight of ``tau`` to ``out`` (xx yy zz xy xz yz).

    ``c = v - g y e_x`` is the peculiar velocity: along the flight ``c_x =
    c_x0 - g v_y s`` (``c_x0 = v_x - g y0``, ``y0`` the centre's y at its
    start), ``c_y = v_y``, ``c_z = v_z``, so the integrals are polynomials
    in ``tau`` (exact up to rounding).  ``g = 0``: ``m v_a v_b tau``.
    [mass*length^2/time]
    """
    cx = vx - g * y0
    s = g * vy  # d c_x / dt = -s
    mt = m * tau
    out[0] += mt * (cx * cx - s * cx * tau + s * s * tau * tau / 3.0)
    out[1] += mt * vy * vy
    out[2] += mt * vz * vz
    half = cx - 0.5 * s * tau  # c_x averaged over the flight
    out[3] += mt * half * vy
    out[4] += mt * half * vz
    out[5] += mt * vy * vz


def move_sphere(
    p: list[list[float]], v: list[list[float]], tloc: list[float], i: int, t: float, planar: bool = False
) -> None:
    """Move sphere ``i`` along its line to time ``t`` (its centre and own time change; 2-D: not z)."""
    pi, vi = p[i], v[i]
    dt = t - tloc[i]
    pi[0] += vi[0] * dt
    pi[1] += vi[1] * dt
    if not planar:
        pi[2] += vi[2] * dt
    tloc[i] = t


def apply_event(
    kind: int,
    i: int,
    j: int,
    p: list[list[float]],
    v: list[list[float]],
    masses: list[float],
    radii: Sequence[float] = (),
    edges: tuple[float, float, float] = (0.0, 0.0, 0.0),
    grow: float = 0.0,
    planar: bool = False,
    restitution: float = 1.0,
    inelastic: bool = False,
    offset: float = 0.0,
    speed: float = 0.0,
) -> tuple[float, float, float, float, float, float, float, float, float]:
    """Change the velocities for one event (its spheres moved to its time).

    Longer than 80 lines with this docstring (under 60 of code): one step
    of the loop, compiled whole by the tests, for every container and rule.

    ``radii`` (at the time origin) and ``grow`` as :func:`next_event`
    (needed only while growing); ``edges``: the periodic box's sides (zeros:
    none), the pair taken at its nearest image; ``planar``: 2-D (z is
    neither read nor changed); ``inelastic``: the inelastic rule (the
    core's inelastic variant), with ``restitution`` the coefficient of this
    event (the pair's or the wall's, 1 where the TC model makes it elastic);
    ``speed``: a sheared box's boundary speed ``g L_y`` (0: not sheared),
    with ``offset`` its Lees-Edwards offset now: the pair is then taken at
    the image across the y face it is nearest to (``ky = round(dy / L_y)``:
    ``dy - ky L_y``, ``dx - ky offset``, then the nearest image along x),
    whose velocity along x is ``v_xj + ky speed``.

    Returns:
        ``(impulse, dpx, dpy, dpz, virial, lost, dx, dy, dz)``: the
        magnitude and the vector of the momentum sphere ``i`` receives
        [mass*length/time], for a collision ``r_ij . dp_i``
        [mass*length^2/time] (0 for a reflection), the kinetic energy
        dissipated (0 unless ``inelastic``), with the core's arithmetic, and
        for a collision ``r_ij`` at contact [length] (zeros for a reflection).
    """
    lost = 0.0
    if kind == REFLECTION:
        pi, vi = p[i], v[i]
        px, py, pz = pi[0], pi[1], pi[2]
        if grow != 0.0:
            k = reflect_grow(px, py, pz, vi[0], vi[1], vi[2], radii[i] * grow, planar)
        elif inelastic:
            k, lost = reflect_inelastic(masses[i], px, py, pz, vi[0], vi[1], vi[2], restitution, planar)
        else:
            k = reflect(px, py, pz, vi[0], vi[1], vi[2], planar)
        vi[0] -= k * px
        vi[1] -= k * py
        mi = masses[i]
        if planar:
            imp = mi * k * math.sqrt(px * px + py * py)
            return imp, -mi * k * px, -mi * k * py, 0.0, 0.0, lost, 0.0, 0.0, 0.0
        vi[2] -= k * pz
        imp = mi * k * math.sqrt(px * px + py * py + pz * pz)
        return imp, -mi * k * px, -mi * k * py, -mi * k * pz, 0.0, lost, 0.0, 0.0, 0.0
    pi, pj, vi, vj = p[i], p[j], v[i], v[j]
    dx, dy, dz = pi[0] - pj[0], pi[1] - pj[1], pi[2] - pj[2]
    if speed != 0.0:
        # Lees-Edwards: the image across the nearest y face, then along x
        ky = float(round(dy / edges[1]))
        dy -= edges[1] * ky
        dx -= ky * offset
        dx -= edges[0] * round(dx / edges[0])
        if edges[2] != 0.0:
            dz -= edges[2] * round(dz / edges[2])
        dvx = vi[0] - (vj[0] + ky * speed)
    else:
        if edges[0] != 0.0:
            # the nearest image (the core's arithmetic: round half to even)
            dx -= edges[0] * round(dx / edges[0])
            dy -= edges[1] * round(dy / edges[1])
            if edges[2] != 0.0:
                dz -= edges[2] * round(dz / edges[2])
        dvx = vi[0] - vj[0]
    dvy, dvz = vi[1] - vj[1], vi[2] - vj[2]
    if grow != 0.0:
        u = (radii[i] + radii[j]) * grow
        k1, k2 = collide_grow(masses[i], masses[j], dx, dy, dz, dvx, dvy, dvz, u, planar)
    elif inelastic:
        k1, k2, lost = collide_inelastic(masses[i], masses[j], dx, dy, dz, dvx, dvy, dvz, restitution, planar)
    else:
        k1, k2 = collide(masses[i], masses[j], dx, dy, dz, dvx, dvy, dvz, planar)
    vi[0] -= k1 * dx
    vi[1] -= k1 * dy
    vj[0] += k2 * dx
    vj[1] += k2 * dy
    mi = masses[i]
    if planar:
        d2 = dx * dx + dy * dy
        return -mi * k1 * math.sqrt(d2), -mi * k1 * dx, -mi * k1 * dy, 0.0, -mi * k1 * d2, lost, dx, dy, 0.0
    vi[2] -= k1 * dz
    vj[2] += k2 * dz
    d2 = dx * dx + dy * dy + dz * dz
    imp = -mi * k1 * math.sqrt(d2)
    return imp, -mi * k1 * dx, -mi * k1 * dy, -mi * k1 * dz, -mi * k1 * d2, lost, dx, dy, dz


def _sheared(where: Container, shear_rate: float | None) -> tuple[Container, float]:
    """The container sheared at ``shear_rate`` (``None``: its own rate), and that rate [1/time]."""
    own = float(getattr(where, "shear_rate", 0.0))
    if shear_rate is None:
        return where, own
    rate = float(shear_rate)
    if not math.isfinite(rate):
        raise ShearError(f"shear_rate {shear_rate!r}: give a finite number [1/time] (0: no shear)")
    if own and rate != own:
        raise ShearError(f"shear_rate {rate:g} but the box is sheared at {own:g}; give one of them")
    if rate and not where.periodic:
        raise ShearError(f"a {where.description} cannot be sheared: give a hs.PeriodicBox")
    if rate != own:
        where = where.sheared_by(rate)  # type: ignore[attr-defined]  # a box's
    return where, rate


def _row(row: Sequence[float], d: int, what: str) -> list[float]:
    """A centre or velocity as ``[x, y, z]`` floats (``z = 0`` in 2-D); ValueError if not ``d`` numbers."""
    out = [float(x) for x in row]
    if len(out) != d:
        raise BoxShapeError(f"{what} have {len(out)} components but the container is {d}-D; give {d}")
    return out + [0.0] if d == 2 else out


class Reference:
    """Exact event-driven dynamics of hard spheres, by brute force, in pure Python.

    The arguments, and the methods that run and read, are
    :class:`~hardspheres.core.engine.Engine`'s (growth too, :meth:`set_growth`;
    not its cells, kicks, checkpoints or overlap checks); arrays come back
    as lists.

    Args:
        masses: ``N`` [mass], > 0.
        radii: ``N`` [length], >= 0.
        positions: ``N`` centres ``[x, y, z]`` at time ``time`` [length] (copied).
        velocities: ``N`` velocities ``[vx, vy, vz]`` [length/time] (copied).
        container: the :class:`~hardspheres.containers.Container` (a sphere,
            a circle or a periodic box), or a sphere's radius [length].
        box: instead of ``container``, a periodic box's edge or sides [length].
        window: simultaneity window [time] (the assignment's program uses
            :data:`SIMULTANEOUS`; 0 means exact times).
        time: the time the positions are given at [time].
        rebase: ignored (the engine's option; this loop keeps absolute times).
        restitution, wall_restitution, tc: the collision rule, as the
            engine's (restitution between spheres and at the wall, the TC
            model's duration), with the core's arithmetic.
        wall_temperature, wall_seed: a thermal wall, as the engine's
            (:func:`~hardspheres.physics.thermal_wall`, the same draws).
        shear_rate: Lees-Edwards shear of a periodic box, ``g`` [1/time]
            (flow along x, gradient along y); default: the box's own
            (:attr:`PeriodicBox.shear_rate
            <hardspheres.containers.PeriodicBox.shear_rate>`), 0 for none.
            0 runs exactly the unsheared loop.
        offset: the Lees-Edwards offset at ``time`` [length]: how far along
            x the images above the box are ahead of it (DynamO's ``DXD``).

    The sheared box (docs/numerics.md, "Lees-Edwards shear"): the images
    across the y faces slide at ``+-g L_y`` (:func:`next_event_sheared`); a
    centre leaving through a y face is moved to that instant, by ``-+L_y``
    in y and ``-+offset`` in x, and its ``v_x`` changes by ``-+g L_y``.  In
    a periodic box the reference also keeps the stress tallies
    (:meth:`stress_tallies`: the collisional virial tensor and the time
    integral of the kinetic tensor of the peculiar velocities).

    Example:
        >>> ref = Reference([1.0, 1.0], [1.0, 1.0], [[-5.0, 0, 0], [5.0, 0, 0]],
        ...                 [[1.0, 0, 0], [-1.0, 0, 0]], container=100.0)
        >>> ref.step(until=10.0)
        (4.0, 1, 0, 1)
        >>> ref.velocities, ref.step(until=10.0)
        ([[-1.0, 0.0, 0.0], [1.0, 0.0, 0.0]], None)
    """

    def __init__(
        self,
        masses: Sequence[float],
        radii: Sequence[float],
        positions: Sequence[Sequence[float]],
        velocities: Sequence[Sequence[float]],
        container: Container | float | None = None,
        box: float | None = None,
        window: float = 0.0,
        time: float = 0.0,
        rebase: bool = False,
        restitution: float = 1.0,
        wall_restitution: float | None = None,
        tc: float = 0.0,
        shear_rate: float | None = None,
        offset: float = 0.0,
        steps: Sequence[Sequence[float]] | Mapping[tuple[int, int], Sequence[Sequence[float]]] | None = None,
        wall_temperature: float = 0.0,
        wall_seed: int = 0,
        species: Sequence[int] | None = None,
    ) -> None:
        where, own = _sheared(as_container(container, box), shear_rate)
        self.container: Container = where
        params = where.core_params(shear=True) if own else where.core_params()  # type: ignore[call-arg]
        self._wall = params["wall_radius"]
        #: the periodic box's sides as the core reads them (zeros: a container)
        self._edges: tuple[float, float, float] = tuple(float(e) for e in params["edges"])  # type: ignore[assignment]
        #: the dimension of space (the container's); in 2-D each centre and
        #: velocity is kept as ``[x, y, 0.0]``: the same kernels, z terms exactly 0
        self.dimensions = d = int(getattr(where, "dimensions", 3))
        self.masses = [float(m) for m in masses]
        self._radii = [float(r) for r in radii]
        self._p = [_row(row, d, "positions") for row in positions]
        self._v = [_row(row, d, "velocities") for row in velocities]
        n = len(self.masses)
        if not len(self._radii) == len(self._p) == len(self._v) == n:
            raise ArgumentError(
                f"{n} masses but {len(self._radii)} radii, {len(self._p)} positions "
                f"and {len(self._v)} velocities; give one of each per sphere"
            )
        #: crossings of the periodic box per axis (the engine's ``images``)
        self._img = [[0, 0, 0] for _ in range(n)]
        self._set_shear(own, offset, float(time))
        for k, pk in enumerate(self._p):  # into the box, whole sides at a time (the engine's _into_box)
            for ax in range(d):
                edge = self._edges[ax]
                if edge:
                    m = math.floor((pk[ax] - (-0.5 * edge)) / edge)
                    if m:
                        pk[ax] -= m * edge
                        self._img[k][ax] += m
        self._window = float(window)
        self._tloc = [float(time)] * n
        self._clock = float(time)
        self._now = self._clock  # the last event or move across the box
        self._origin = 0.0  # the time origin (moved as the engine's, by set_growth)
        self._grow = 0.0  # radii grow as radii * (1 + grow * t), t from the origin
        self._limit = frozen_limit(n)
        self._frozen = 0  # collisions and reflections in a row with the clock not advancing
        self._streak = self._clock  # time of the first of them
        self._coll = self._refl = 0
        self._wall_impulse = self._virial = 0.0
        self.last_reason, self.last_done = StopReason.UNTIL, 0
        self._set_rule(restitution, wall_restitution, tc)
        self._set_wall(wall_temperature, wall_seed)
        self._inelastic = self._e != 1.0 or self._ew != 1.0 or self._kt_wall > 0.0
        # the stress tallies (periodic box, xx yy zz xy xz yz): collisional virial, the time integral
        # of the peculiar kinetic tensor of the closed flights, when each open flight began
        self._vir_t = [0.0] * 6
        self._kin_t = [0.0] * 6
        self._kt = [self._clock] * n
        self._crossed = -INF  # every crossing of a face up to this time is made
        self._set_steps(steps, species)

    def _set_rule(self, restitution: float, wall_restitution: float | None, tc: float) -> None:
        """The collision rule (the engine's set_restitution, which checks the same)."""
        self._e = float(restitution)
        self._ew = self._e if wall_restitution is None else float(wall_restitution)
        self._tc = float(tc)
        for name, value in (("restitution", self._e), ("wall restitution", self._ew)):
            if not 0.0 < value <= 1.0:
                raise ArgumentError(f"{name} must be in (0, 1] (1: elastic), got {value}")
        if not (self._tc >= 0.0 and math.isfinite(self._tc)):
            raise ArgumentError(f"tc must be a finite time >= 0 (0: no TC model), got {self._tc}")
        #: each sphere's time of its last collision or reflection (inelastic rule; the TC model)
        self._last = [-INF] * len(self.masses)
        self._dissipated = 0.0

    def _set_wall(self, kt: float, seed: int) -> None:
        """The thermal wall (the engine's set_wall_temperature, which checks the same)."""
        self._kt_wall = float(kt)
        if not (self._kt_wall >= 0.0 and math.isfinite(self._kt_wall)):
            raise ArgumentError(
                f"wall temperature must be a finite energy >= 0 (0: off), got {self._kt_wall}"
            )
        if self._kt_wall > 0.0 and not self._wall:
            raise ArgumentError("a wall temperature needs a wall: use a spherical or circular container")
        if isinstance(seed, bool) or not 0 <= int(seed) < 2**32 or int(seed) != seed:
            raise ArgumentError(f"wall seed must be an integer in [0, 2^32), got {seed!r}")
        self._wall_seed, self._draws, self._wall_heat = int(seed), 0, 0.0

    def _thermal(self, i: int, planar: bool) -> tuple[float, float, float, float]:
        """Sphere ``i`` (at the wall) re-emitted by the thermal wall: ``(impulse, dp...)``; heat tallied."""
        vi, mi, pi = self._v[i], self.masses[i], self._p[i]
        wx, wy, wz, imp, gain = thermal_wall(
            mi, pi[0], pi[1], pi[2], vi[0], vi[1], vi[2], self._kt_wall, self._wall_seed, self._draws, planar
        )
        dpx, dpy = mi * (wx - vi[0]), mi * (wy - vi[1])
        dpz = 0.0 if planar else mi * (wz - vi[2])
        vi[0], vi[1] = wx, wy
        if not planar:
            vi[2] = wz
        self._draws += 1
        self._wall_heat += gain
        return imp, dpx, dpy, dpz

    def _set_shear(self, rate: float, offset: float, time: float) -> None:
        """Lees-Edwards: ``g``, the boundary speed ``g L_y``, the offset at time 0; centres into the box.

        A centre given outside the box along y is an image: it is moved by
        whole sides along y, its x by the offset then and its ``v_x`` by the
        boundary speed (DynamO's ``applyBC(pos, vel)``).
        """
        self._g = rate + 0.0
        self._speed = rate * self._edges[1] if rate else 0.0
        self._off0 = 0.0
        #: each centre's accumulated x shift at y crossings (unwrapped x: ``x + images_x L_x + shift``)
        self._xshift = [0.0] * len(self._p)
        if not rate:
            return
        off = float(offset)
        if not math.isfinite(off):
            raise ShearError(f"offset {offset!r}: give a finite length")
        lx, ly = self._edges[0], self._edges[1]
        self._off0 = shear_offset(off, self._speed, lx, -time)
        now_off = shear_offset(self._off0, self._speed, lx, time)
        for k, pk in enumerate(self._p):
            m = math.floor((pk[1] - (-0.5 * ly)) / ly)
            if m:
                pk[1] -= m * ly
                pk[0] -= m * now_off
                self._v[k][0] -= m * self._speed
                self._img[k][1] += m
                self._xshift[k] += m * now_off

    def _set_steps(
        self,
        steps: Sequence[Sequence[float]] | Mapping[tuple[int, int], Sequence[Sequence[float]]] | None,
        species: Sequence[int] | None = None,
    ) -> None:
        """The stepped pair potential (none: hard spheres) and every pair's state at the start.

        Each pair's state is the number of edges ``lambda_k (R_i + R_j)`` of
        its pair of species that its centres are inside (strictly) at its
        nearest image, kept in a dict for the pairs in a step;
        ``bonded[(s, t, k)]`` counts the pairs of species ``s <= t`` in state
        ``k + 1``.
        """
        self._lams: tuple[float, ...] = ()  # (any steps: the first pair of species')
        self._us: tuple[float, ...] = ()
        self._states: dict[tuple[int, int], int] = {}
        self._bonded: dict[tuple[int, int, int], int] = {}
        self._stepc = {CAPTURE: 0, RELEASE: 0, BOUNCE: 0}
        self._species = [0] * len(self._p)
        self._table: list[list[tuple[float, ...]]] = [[()]]
        self._energies: list[list[tuple[float, ...]]] = [[()]]
        if steps is None or len(steps) == 0:
            if species is not None:
                raise ArgumentError("species are for the steps' table: give steps too")
            return
        table = step_table(steps)
        if species is not None:
            self._species = [int(x) for x in species]
            if len(self._species) != len(self._p) or min(self._species, default=0) < 0:
                raise ArgumentError(f"species: give one integer >= 0 per sphere ({len(self._p)})")
        elif len(table) > 1 or (0, 0) not in table:
            raise ArgumentError("steps per pair of species: give each sphere's species too")
        n_species = max([*self._species, *(s for s, _ in table)], default=0) + 1
        self._table = [[table.get((s, t), ((), ()))[0] for t in range(n_species)] for s in range(n_species)]
        self._energies = [
            [table.get((s, t), ((), ()))[1] for t in range(n_species)] for s in range(n_species)
        ]
        lams = max((row for rows in self._table for row in rows), key=lambda r: r[0] if r else 0.0)
        if not lams:
            return  # (steps for no pair: hard spheres)
        if self._speed:
            raise ShearError("steps in a sheared box are not built yet: give shear_rate=0 or no steps")
        if self._inelastic:
            raise ArgumentError("steps with restitution below 1 are not built yet: give restitution=1")
        edges = self._edges
        if edges[0] and self._radii:
            reach = lams[0] * 2.0 * max(self._radii)
            side = min(e for e in edges if e)
            if not reach < 0.5 * side:
                raise BoxShapeError(
                    f"the outermost step reaches {reach:g}, not less than half the box's side {side:g}: "
                    "give a larger box or a narrower step"
                )
        self._lams = lams
        for s in range(n_species):
            for t in range(s, n_species):
                for k in range(len(self._table[s][t])):
                    self._bonded[(s, t, k)] = 0
        p, radii, sp = self._p, self._radii, self._species
        for i in range(len(p)):
            for j in range(i + 1, len(p)):
                d2 = 0.0
                for ax in range(3):
                    dx = p[i][ax] - p[j][ax]
                    if edges[ax]:
                        dx -= edges[ax] * round(dx / edges[ax])
                    d2 += dx * dx
                state = step_state(d2, radii[i] + radii[j], self._table[sp[i]][sp[j]])
                if state:
                    self._states[(i, j)] = state
                    self._bonded[self._bond_key(i, j, state)] += 1

    def _bond_key(self, i: int, j: int, state: int) -> tuple[int, int, int]:
        """The count a pair in ``state`` belongs to: its species in order, and its step."""
        s, t = self._species[i], self._species[j]
        return (s, t, state - 1) if s <= t else (t, s, state - 1)

    @property
    def steps(self) -> tuple[tuple[float, float], ...]:
        """The stepped pair potential ``((lambda_k, U_k), ...)`` of species 0 with itself, outermost first."""
        return tuple(zip(self._table[0][0], self._energies[0][0]))

    @property
    def pair_states(self) -> dict[tuple[int, int], int]:
        """Each pair ``(i, j)``, ``i < j``, in a step, and its state (edges it is inside); a copy."""
        return dict(self._states)

    def potential_energy(self) -> float:
        """The stepped potential's energy now [mass*length^2/time^2] (0 for hard spheres).

        Formed afresh from the count of pairs in each step, in a fixed
        order, never accumulated: it cannot drift.
        """
        u = 0.0
        for (s, t, k), count in sorted(self._bonded.items()):
            u += count * self._energies[s][t][k]
        return u

    def _pot(self, i: int, j: int, state: int) -> float:
        """The potential energy of the pair ``(i, j)`` in ``state``."""
        return self._energies[self._species[i]][self._species[j]][state - 1] if state else 0.0

    # ---- what the engine also tells ---------------------------------------------
    @property
    def n(self) -> int:
        """Number of spheres."""
        return len(self.masses)

    @property
    def velocities(self) -> list[list[float]]:
        """``N`` velocities now [length/time] (in 3-D the loop's own lists: do not write)."""
        if self.dimensions == 2:
            return [v[:2] for v in self._v]
        return self._v

    @property
    def time(self) -> float:
        """Time of the last processed event (or the start) [time]."""
        return self._origin + self._clock

    @property
    def images(self) -> list[list[int]]:
        """``N`` crossings of the periodic box per axis (``d`` each)."""
        return [row[: self.dimensions] for row in self._img]

    @property
    def shear_rate(self) -> float:
        """Lees-Edwards shear rate ``g`` [1/time], 0 if not sheared."""
        return self._g

    def shear_offset(self, t: float | None = None) -> float:
        """The Lees-Edwards offset at time ``t`` (default: now) [length] (0 when not sheared).

        How far along x the images above the box (across its upper y face)
        are ahead of it: ``(offset0 + g L_y t) mod L_x`` (:func:`shear_offset`).
        """
        if not self._speed:
            return 0.0
        t = self.time if t is None else t
        return shear_offset(self._off0, self._speed, self._edges[0], t - self._origin)

    @property
    def x_shifts(self) -> list[float]:
        """``N`` shifts along x made at y crossings [length]; ``x + images_x L_x + shift`` is continuous."""
        return list(self._xshift)

    def stress_tallies(self, t: float | None = None) -> dict[str, Any]:
        """The stress tallies at absolute time ``t`` (default: now; periodic box), since the start.

        Returns:
            dict of ``(6,)`` arrays (xx yy zz xy xz yz): ``virial`` the
            collisional virial tensor ``sum r_ij dp_i`` over collisions
            [mass*length^2/time], and ``kinetic`` the time integral of ``sum
            m c c`` [mass*length^2/time], ``c = v - g y e_x`` the peculiar
            velocities (the velocities themselves when not sheared), each
            flight integrated exactly (:func:`peculiar_segment`).  The
            pressure tensor averaged over ``[t1, t2]`` is ``(kinetic + virial)``
            differenced over it, divided by ``(t2 - t1) V``.

        Raises:
            PeriodicBoxRequired: not a periodic box.
        """
        import numpy as np

        require_periodic(self.container, "the stress tallies")
        t = (self.time if t is None else float(t)) - self._origin
        kin = list(self._kin_t)
        for k in range(self.n):
            self._flight(k, t, kin)
        return {"virial": np.array(self._vir_t), "kinetic": np.array(kin)}

    def _flight(self, k: int, t: float, out: list[float]) -> None:
        """Add sphere ``k``'s open flight, up to ``t`` (from the origin), to the kinetic integral ``out``."""
        p, v = self._p[k], self._v[k]
        start = self._kt[k]
        if t == start:
            return
        y0 = p[1] + v[1] * (start - self._tloc[k])
        peculiar_segment(
            self.masses[k], y0, v[0], v[1], 0.0 if self.dimensions == 2 else v[2], self._g, t - start, out
        )

    def _close_flight(self, k: int, t: float) -> None:
        """Sphere ``k``'s open flight integrated up to ``t``, before its velocity changes there."""
        if self._edges[0]:
            self._flight(k, t, self._kin_t)
            self._kt[k] = t

    @property
    def growth(self) -> float:
        """Radii's relative growth rate now: ``dR_i/dt / R_i`` [1/time] (0: off)."""
        g = self._grow
        return g / (1.0 + g * self._clock) if g else 0.0

    def set_growth(self, rate: float) -> None:
        """Grow every radius from now at ``dR_i/dt = rate * R_i(now)`` [1/time], as the engine's.

        With the engine's arithmetic: the time origin moves to the clock
        (every centre moved there, the radii to their values now), then the
        radii grow linearly.
        """
        rate = float(rate)
        if not (rate >= 0.0 and math.isfinite(rate)):
            raise ArgumentError(f"growth rate must be a finite number >= 0, got {rate}")
        if rate and self._inelastic:
            raise ArgumentError(
                "radii cannot grow with restitution below 1 or a thermal wall: grow elastic spheres first"
            )
        if rate and self._g:
            raise ShearError("radii cannot grow in a sheared box: compress without shear, then shear")
        if rate and self._lams:
            raise ArgumentError("radii cannot grow with steps yet: compress hard spheres, then add the steps")
        t = self._clock
        if self._edges[0]:
            for k in range(len(self._p)):
                self._close_flight(k, t)
                self._kt[k] = 0.0
        if self._speed:  # the offset's origin moves with the time origin
            self._off0 = shear_offset(self._off0, self._speed, self._edges[0], t)
        for k in range(len(self._p)):
            self._move_sphere(self._p, self._v, self._tloc, k, t, self.dimensions == 2)
            self._tloc[k] = 0.0
            self._last[k] -= t  # (the engine's rebase: the same shift)
        self._streak -= t
        self._crossed = -INF
        self._origin += t
        self._clock = 0.0
        self._now = 0.0
        if self._grow:
            factor = 1.0 + self._grow * t
            for k in range(len(self._radii)):
                self._radii[k] *= factor
        self._grow = rate

    @property
    def window(self) -> float:
        """The simultaneity window [time]."""
        return self._window

    @property
    def counters(self) -> dict[str, int]:
        """Events so far: collisions, reflections (crossings, stale, refreshed: 0, no cells).

        With steps also ``captures``, ``releases`` and ``bounces``.
        """
        out = {
            "collisions": self._coll,
            "reflections": self._refl,
            "crossings": 0,
            "stale": 0,
            "refreshed": 0,
        }
        if self._lams:
            out.update(
                captures=self._stepc[CAPTURE], releases=self._stepc[RELEASE], bounces=self._stepc[BOUNCE]
            )
        return out

    @property
    def wall_impulse(self) -> float:
        """Total impulse delivered to the container wall [mass*length/time]."""
        return self._wall_impulse

    @property
    def dissipated(self) -> float:
        """Kinetic energy dissipated by inelastic collisions and reflections so far [mass*length^2/time^2]."""
        return self._dissipated

    @property
    def wall_heat(self) -> float:
        """Kinetic energy the thermal wall gave the spheres so far [mass*length^2/time^2]."""
        return self._wall_heat

    @property
    def restitution(self) -> float:
        """Normal restitution coefficient between spheres (1: elastic)."""
        return self._e

    @property
    def wall_restitution(self) -> float:
        """Normal restitution coefficient at the container's wall (1: elastic)."""
        return self._ew

    @property
    def tc(self) -> float:
        """The TC model's duration [time] (0: off)."""
        return self._tc

    @property
    def virial(self) -> float:
        """Sum over collisions of ``r_ij . dp_i`` [mass*length^2/time]."""
        return self._virial

    @property
    def idle(self) -> bool:
        """Whether nothing will ever happen again."""
        return self._next()[1] < 0

    def radii_at(self, t: float | None = None) -> list[float]:
        """``N`` radii at time ``t`` (default: now) [length]."""
        g = self._grow
        if not g:
            return list(self._radii)
        t = self.time if t is None else t
        return [r * (1.0 + g * (t - self._origin)) for r in self._radii]

    def positions_at(
        self, t: float | None = None, out: Any = None, spheres: Sequence[int] | None = None
    ) -> Any:
        """Centres of all spheres at time ``t`` (default: now) [length].

        Into ``out`` (a list of ``N`` rows, or an ``(N, 3)`` array) if given;
        with ``spheres`` (indices), only their rows.
        """
        t = self.time if t is None else t
        t -= self._origin
        p, v, tloc = self._p, self._v, self._tloc
        if out is None:
            out = [None] * len(p)
        edges = self._edges
        for k in range(len(p)) if spheres is None else spheres:
            pk, vk = p[k], v[k]
            dt = t - tloc[k]
            row = [pk[0] + vk[0] * dt, pk[1] + vk[1] * dt, pk[2] + vk[2] * dt]
            if self._speed:  # past a y face not yet crossed: its image, shifted by the offset then
                ky = math.floor(row[1] / edges[1] + 0.5)
                if ky:
                    row[0] -= ky * shear_offset(self._off0, self._speed, edges[0], t)
            if edges[0]:  # into the box (the core's positions_at)
                for ax in range(3):
                    if edges[ax]:
                        row[ax] -= edges[ax] * math.floor(row[ax] / edges[ax] + 0.5)
            out[k] = row[:2] if self.dimensions == 2 else row
        return out

    def move_clock(self, t: float) -> None:
        """Move the clock to absolute time ``t``, as the engine's (no event may be pending before it).

        Crossings of the box's faces before ``t`` are made first.

        Raises:
            ArgumentError: an event is due before ``t``: advance to it first.
        """
        t = float(t) - self._origin
        nt, kind, _, _ = self._next_physical(t)
        if kind >= 0 and kind != CROSSING and nt < t:
            raise ArgumentError("events are pending before that time: advance to it first")
        if t > self._clock:
            self._clock = self._now = t

    def kick(self, i: int, t: float, velocity: Sequence[float]) -> None:
        """Sphere ``i`` takes ``velocity`` (``d`` components) at absolute time ``t``, as the engine's.

        The clock moves to ``t`` (crossings of the box's faces before it are
        made first); for thermostats.

        Raises:
            ArgumentError: ``t`` is before the clock.
            BoxShapeError: ``velocity`` has not ``d`` components.
        """
        t = float(t) - self._origin
        if t < self._clock:
            raise ArgumentError("a kick cannot be before the clock: give a time at or after it")
        vel = _row(velocity, self.dimensions, "velocities")
        i = int(i)
        if not t <= self._crossed:  # (a thermostat kicks many spheres at one instant)
            self._next_physical(t)
        self._clock = self._now = t
        self._close_flight(i, t)
        self._move_sphere(self._p, self._v, self._tloc, i, t, self.dimensions == 2)
        for ax in range(self.dimensions):
            self._v[i][ax] = vel[ax]

    def kinetic_energy(self) -> float:
        """Total kinetic energy [mass*length^2/time^2]."""
        import numpy as np

        from ..state import kinetic_energy

        return float(kinetic_energy(np.asarray(self.masses), np.asarray(self._v)))

    # ---- running ------------------------------------------------------------------
    # the loop's steps (the tests swap in the same functions compiled)
    _next_event = staticmethod(next_event)
    _next_event_periodic = staticmethod(next_event_periodic)
    _next_event_sheared = staticmethod(next_event_sheared)
    _next_event_stepped = staticmethod(next_event_stepped)
    _move_sphere = staticmethod(move_sphere)
    _apply_event = staticmethod(apply_event)

    def _next(self) -> tuple[float, int, int, int]:
        """The next event or move across the box, ``(t, kind, i, j)`` (times from the origin)."""
        if self._lams:
            return self._next_event_stepped(
                self._p,
                self._v,
                self._tloc,
                self._radii,
                self._wall,
                self._edges,
                self._clock,
                self._window,
                self._now,
                self.dimensions == 2,
                self._table,
                self._states,
                self._species,
            )
        if self._speed:
            return self._next_event_sheared(
                self._p,
                self._v,
                self._tloc,
                self._radii,
                self._edges,
                self._clock,
                self._window,
                self._now,
                self.dimensions == 2,
                self._off0,
                self._speed,
            )
        if self._edges[0]:
            return self._next_event_periodic(
                self._p,
                self._v,
                self._tloc,
                self._radii,
                self._edges,
                self._clock,
                self._window,
                self._grow,
                self._now,
                self.dimensions == 2,
            )
        return self._next_event(
            self._p,
            self._v,
            self._tloc,
            self._radii,
            self._wall,
            self._clock,
            self._window,
            self._grow,
            self.dimensions == 2,
        )

    def _next_physical(self, until: float) -> tuple[float, int, int, int]:
        """The next collision or reflection, after the moves across the box before it up to ``until``."""
        while True:
            t, kind, i, j = self._next()
            if kind != CROSSING or not t <= until:
                if not t <= until:
                    self._crossed = until  # every crossing up to it made
                return t, kind, i, j
            # the centre leaves the box: one side back (the core's crossing of a box face)
            ax, step = j >> 1, (1 if j & 1 else -1)
            if ax == 1 and self._speed:
                self._cross_sheared(i, t, step)
                continue
            self._p[i][ax] -= step * self._edges[ax]
            self._img[i][ax] += step
            self._now = t

    def _cross_sheared(self, i: int, t: float, step: int) -> None:
        """Sphere ``i`` leaves a sheared box through a y face (``step``: +1 the upper) at ``t``.

        Moved to ``t`` (its own time), then by ``-step L_y`` in y and
        ``-step offset(t)`` in x (then into the box along x), and ``v_x``
        changes by ``-step g L_y``: DynamO's ``BCLeesEdwards::applyBC(pos,
        vel)``.  Not an event of the physics: the peculiar velocity is the
        same on both sides.
        """
        self._close_flight(i, t)
        p, edges = self._p, self._edges
        self._move_sphere(p, self._v, self._tloc, i, t, self.dimensions == 2)
        pi = p[i]
        off = shear_offset(self._off0, self._speed, edges[0], t)
        pi[1] -= step * edges[1]
        pi[0] -= step * off
        self._v[i][0] -= step * self._speed
        self._img[i][1] += step
        self._xshift[i] += step * off
        m = math.floor((pi[0] - (-0.5 * edges[0])) / edges[0])
        if m:
            pi[0] -= m * edges[0]
            self._img[i][0] += m
        self._now = t

    def _step_factors(self, kind: int, i: int, j: int, t: float) -> tuple[Any, ...]:
        """A step event's factors from the pair at ``t`` (before the spheres move there).

        The centres at ``t`` are those :func:`move_sphere` will give, to the
        bit; the pair at its nearest image (:func:`apply_event`'s
        arithmetic).  ``kind``: ``CAPTURE`` for the inner edge, ``RELEASE``
        for the outer.

        Returns:
            ``(k1, k2, crossed, old, new, dx, dy, dz)``.

        Raises:
            StuckError: a bounce that would change nothing (``dr . dv = 0``:
                the pair sliding along the edge).
        """
        p, v, tloc, edges = self._p, self._v, self._tloc, self._edges
        pi, pj, vi, vj = p[i], p[j], v[i], v[j]
        di, dj = t - tloc[i], t - tloc[j]
        d = [(pi[ax] + vi[ax] * di) - (pj[ax] + vj[ax] * dj) for ax in range(3)]
        if self.dimensions == 2:
            d[2] = pi[2] - pj[2]
        for ax in range(3):
            if edges[ax]:
                d[ax] -= edges[ax] * round(d[ax] / edges[ax])
        old = self._states.get((i, j), 0)
        new = old + 1 if kind == CAPTURE else old - 1
        du = self._pot(i, j, new) - self._pot(i, j, old)
        k1, k2, crossed = cross_step(
            self.masses[i],
            self.masses[j],
            d[0],
            d[1],
            d[2],
            vi[0] - vj[0],
            vi[1] - vj[1],
            vi[2] - vj[2],
            du,
            self.dimensions == 2,
        )
        if not crossed and k1 == 0.0:
            raise StuckError("sliding", t + self._origin, i, inelastic=False)
        return k1, k2, crossed, old, new, d[0], d[1], d[2]

    def _apply_step(self, i: int, j: int, cross: tuple[Any, ...]) -> tuple[Any, ...]:
        """A step event's velocity change and state change: ``(kind, imp, dp..., virial, dr...)``.

        ``imp = -m_i k1 |dr|`` is the momentum sphere ``i`` receives along
        ``dr`` (negative: towards ``j``, for the three step events).
        """
        k1, k2, crossed, old, new, dx, dy, dz = cross
        vi, vj = self._v[i], self._v[j]
        vi[0] -= k1 * dx
        vi[1] -= k1 * dy
        vj[0] += k2 * dx
        vj[1] += k2 * dy
        planar = self.dimensions == 2
        if not planar:
            vi[2] -= k1 * dz
            vj[2] += k2 * dz
        kind = BOUNCE
        if crossed:
            kind = CAPTURE if new > old else RELEASE
            if old:
                self._bonded[self._bond_key(i, j, old)] -= 1
            if new:
                self._bonded[self._bond_key(i, j, new)] += 1
                self._states[(i, j)] = new
            else:
                del self._states[(i, j)]
        mi = self.masses[i]
        d2 = dx * dx + dy * dy if planar else dx * dx + dy * dy + dz * dz
        imp = -mi * k1 * math.sqrt(d2)
        return (
            kind,
            imp,
            -mi * k1 * dx,
            -mi * k1 * dy,
            0.0 if planar else -mi * k1 * dz,
            -mi * k1 * d2,
            dx,
            dy,
            dz,
        )

    def _add_virial(self, dx: float, dy: float, dz: float, px: float, py: float, pz: float) -> None:
        """A collision's terms ``r_a dp_b`` of the virial tensor (the core's, in its arithmetic)."""
        vt = self._vir_t
        vt[0] += dx * px
        vt[1] += dy * py
        vt[3] += dx * py
        if self.dimensions == 3:
            vt[2] += dz * pz
            vt[4] += dx * pz
            vt[5] += dy * pz

    def _coefficient(self, kind: int, i: int, j: int, t: float) -> float:
        """The restitution of this event: the wall's or the pair's, 1 within tc of a last collision."""
        last, tc = self._last, self._tc
        if kind == REFLECTION:
            return 1.0 if t - last[i] < tc else self._ew
        return 1.0 if (t - last[i] < tc or t - last[j] < tc) else self._e

    def _process(self, until: float) -> tuple[float, int, int, int, float, float, float, float] | None:
        """The next event up to ``until``, processed: ``(t, kind, i, j, impulse, dp..., virial)``.

        ``None`` if it is after ``until`` (or there is none).

        Raises:
            StuckError: it would be the reflection of a sphere sliding along
                the wall, or one too many in a row with the clock frozen.
        """
        t, kind, i, j = self._next_physical(until - self._origin)
        if kind < 0 or kind == CROSSING or not t <= until - self._origin:
            return None
        if t - self._streak <= FROZEN_RELATIVE * abs(t + self._origin):
            if self._frozen >= self._limit:
                raise StuckError("frozen", t + self._origin, i, inelastic=self._inelastic)
        else:
            self._frozen = 0
            self._streak = t
        p, v, tloc = self._p, self._v, self._tloc
        # the inelastic rule's coefficient of this event: 1 within tc of either
        # sphere's last collision or reflection (the TC model; the core's test)
        inelastic = self._inelastic and not self._grow
        e = self._coefficient(kind, i, j, t) if inelastic else 1.0
        if kind == REFLECTION:
            pi, vi = p[i], v[i]
            dt = t - tloc[i]
            planar = self.dimensions == 2
            px, py = pi[0] + vi[0] * dt, pi[1] + vi[1] * dt
            pz = 0.0 if planar else pi[2] + vi[2] * dt
            if self._grow:
                k = reflect_grow(px, py, pz, vi[0], vi[1], vi[2], self._radii[i] * self._grow, planar)
            elif inelastic and self._kt_wall > 0.0:
                k = 1.0  # (a thermal wall: the velocity is drawn below)
            elif inelastic:
                k = reflect_inelastic(self.masses[i], px, py, pz, vi[0], vi[1], vi[2], e, planar)[0]
            else:
                k = reflect(px, py, pz, vi[0], vi[1], vi[2], planar)
            if k == 0.0:
                raise StuckError("sliding", t + self._origin, i, inelastic=self._inelastic)
        cross = self._step_factors(kind, i, j, t) if kind >= CAPTURE else None
        self._frozen += 1
        self._clock = self._now = t
        planar = self.dimensions == 2
        if j >= 0 and self._edges[0]:
            self._close_flight(i, t)
            self._close_flight(j, t)
        self._move_sphere(p, v, tloc, i, t, planar)
        if j >= 0:
            self._move_sphere(p, v, tloc, j, t, planar)
        off = shear_offset(self._off0, self._speed, self._edges[0], t) if self._speed else 0.0
        rule = (self._grow, planar, e, inelastic, off, self._speed)
        if cross is not None:
            kind, imp, dpx, dpy, dpz, vir, dx, dy, dz = self._apply_step(i, j, cross)
            lost = 0.0
        elif kind == REFLECTION and inelastic and self._kt_wall > 0.0:
            imp, dpx, dpy, dpz = self._thermal(i, planar)
            vir = lost = dx = dy = dz = 0.0
        else:
            imp, dpx, dpy, dpz, vir, lost, dx, dy, dz = self._apply_event(
                kind, i, j, p, v, self.masses, self._radii, self._edges, *rule
            )
        if j >= 0 and self._edges[0]:
            self._add_virial(dx, dy, dz, dpx, dpy, dpz)
        if inelastic:
            self._dissipated += lost
            self._last[i] = t
            if j >= 0:
                self._last[j] = t
        if kind == REFLECTION:
            self._refl += 1
            self._wall_impulse += imp
        elif kind == COLLISION:
            self._coll += 1
            self._virial += vir
        else:  # a step's capture, release or bounce
            self._stepc[kind] += 1
            self._virial += vir
        return t + self._origin, kind, i, j, imp, dpx, dpy, dpz

    def step(self, until: float = INF) -> tuple[float, int, int, int] | None:
        """Process the next event if it is at or before ``until`` [time].

        Returns:
            ``(time, kind, i, j)`` of the event (``kind`` an
            :class:`~hardspheres.events.EventKind` number, ``j = -1`` for a
            reflection), or ``None`` if the next one is after ``until``.

        Raises:
            StuckError: the next event would repeat without end (a sphere
                sliding along the wall, or a frozen clock).
        """
        done = self._process(until)
        return None if done is None else done[:4]

    def advance(
        self,
        until: float = INF,
        events: int | None = None,
        collisions: int | None = None,
        record: bool = True,
    ) -> np.ndarray:
        """Process events up to time ``until`` or a count limit, as the engine's ``advance``.

        Returns:
            The events processed, in order: an array of
            :data:`~hardspheres.events.EVENT_DTYPE` (empty if not ``record``).

        Raises:
            ValueError: ``until`` is NaN.
            StuckError: as :meth:`step`; events before it are returned first,
                and the call after raises.
        """
        import numpy as np

        from ..events import EVENT_DTYPE

        if until != until:
            raise ArgumentError("until must be a time, not NaN")
        max_events = _NEVER if events is None else int(events)
        max_coll = _NEVER if collisions is None else int(collisions)
        rows = []
        done = coll = 0
        reason = StopReason.UNTIL
        while True:
            if done >= max_events:
                reason = StopReason.MAX_EVENTS
                break
            if coll >= max_coll:
                reason = StopReason.MAX_COLLISIONS
                break
            try:
                ev = self._process(until)
            except StuckError as e:
                if done == 0:
                    self.last_reason = StopReason.FROZEN if e.reason == "frozen" else StopReason.SLIDING
                    self.last_done = 0
                    raise
                reason = StopReason.FROZEN if e.reason == "frozen" else StopReason.SLIDING
                break
            if ev is None:
                break
            done += 1
            coll += ev[1] == COLLISION
            if record:
                rows.append((*ev[:5], ev[5:8]))
        self.last_reason, self.last_done = reason, done
        return np.array(rows, dtype=EVENT_DTYPE)

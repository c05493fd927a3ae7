"""The physics of perfectly elastic spheres, as small pure scalar functions.

Every function here takes and returns plain floats, so that the same source
runs unchanged as Python (the small-input path of ``spheres``, which must not
pay numba's start-up) and compiled by numba inside the event core
(:mod:`hardspheres._core`).  The two give bit-identical results: both use
IEEE-754 double arithmetic in the same order, and the core is compiled without
``fastmath`` (so no reassociation and no fused multiply-add).

Conventions (dimensions in brackets):

* positions ``p`` [length], velocities ``v`` [length/time], masses [mass];
* times returned are *durations from now* [time], ``inf`` for never;
* quadratic roots use the numerically stable form (no subtraction of nearly
  equal numbers), see :func:`pair_time` and :func:`wall_time`.
"""

import math

INF = math.inf

#: Below this squared speed [length^2/time^2] the quadratics' coefficients
#: (|v|^2, p.v and their squares) underflow: the velocity is scaled up by
#: :data:`TINY_SCALE` (a power of two, so exactly) and the time scaled back.
#: Above it nothing changes (the results are bit for bit those without it).
TINY_V2 = 1e-200
TINY_SCALE = 2.0 ** 600


def pair_time(dx, dy, dz, dvx, dvy, dvz, sigma):
    """Time until two spheres reach contact distance ``sigma``.

    Args:
        dx, dy, dz: separation ``r_i - r_j`` now [length].
        dvx, dvy, dvz: relative velocity ``v_i - v_j`` [length/time].
        sigma: contact distance ``R_i + R_j`` [length].

    Returns:
        The smallest ``t >= 0`` with ``|dr + t dv| = sigma`` if the spheres are
        approaching (``dr . dv < 0``), else ``inf`` [time].  A pair that is
        touching or overlapping within rounding and approaching collides at 0.

    Example:
        >>> pair_time(-10.0, 0.0, 0.0, 2.0, 0.0, 0.0, 2.0)
        4.0
    """
    b = dx * dvx + dy * dvy + dz * dvz
    if b > 0.0:
        return INF
    a = dvx * dvx + dvy * dvy + dvz * dvz
    scale = 1.0
    if a < TINY_V2:  # |dv|^2, b and b^2 may underflow: solve for dv * 2^600
        scale = TINY_SCALE
        dvx, dvy, dvz = dvx * scale, dvy * scale, dvz * scale
        a = dvx * dvx + dvy * dvy + dvz * dvz
        b = dx * dvx + dy * dvy + dz * dvz
    if b >= 0.0:
        return INF
    c = (dx * dx + dy * dy + dz * dz) - sigma * sigma
    if c <= 0.0:
        return 0.0
    disc = b * b - a * c
    if disc <= 0.0:
        return INF
    # smaller root of a t^2 + 2 b t + c = 0 with b < 0, without cancellation
    return c / (math.sqrt(disc) - b) * scale


def pair_time_within(dx, dy, dz, dvx, dvy, dvz, sigma, horizon):
    """:func:`pair_time`, or ``inf`` early if the pair surely meets after ``horizon``.

    The root is at least ``c / (-2 b)``; a pair with ``c > -2 b horizon (1 +
    1e-12)`` cannot meet by ``horizon`` [time], and its exact time is not
    computed (no square root, no division).  Otherwise the result is
    bit-identical to :func:`pair_time`'s.

    Example:
        >>> pair_time_within(-10.0, 0.0, 0.0, 2.0, 0.0, 0.0, 2.0, 2.0)
        inf
        >>> pair_time_within(-10.0, 0.0, 0.0, 2.0, 0.0, 0.0, 2.0, 5.0)
        4.0
    """
    b = dx * dvx + dy * dvy + dz * dvz
    if b > 0.0:
        return INF
    a = dvx * dvx + dvy * dvy + dvz * dvz
    scale = 1.0
    if a < TINY_V2:  # as in pair_time
        scale = TINY_SCALE
        dvx, dvy, dvz = dvx * scale, dvy * scale, dvz * scale
        a = dvx * dvx + dvy * dvy + dvz * dvz
        b = dx * dvx + dy * dvy + dz * dvz
    if b >= 0.0:
        return INF
    c = (dx * dx + dy * dy + dz * dz) - sigma * sigma
    if c <= 0.0:
        return 0.0
    if c > -2.0 * b * (horizon / scale) * (1.0 + 1e-12):
        return INF
    disc = b * b - a * c
    if disc <= 0.0:
        return INF
    return c / (math.sqrt(disc) - b) * scale


def wall_time(px, py, pz, vx, vy, vz, reach):
    """Time until a sphere's centre reaches distance ``reach`` from the origin.

    Args:
        px, py, pz: centre now [length].
        vx, vy, vz: velocity [length/time].
        reach: container radius minus sphere radius [length].

    Returns:
        The larger root ``t >= 0`` of ``|p + t v| = reach`` [time]; ``0`` for
        a sphere at or beyond ``reach`` that moves outward, ``inf`` for a
        sphere at rest.

    Example:
        >>> wall_time(0.0, 0.0, 0.0, 2.0, 0.0, 0.0, 10.0)
        5.0
    """
    a = vx * vx + vy * vy + vz * vz
    scale = 1.0
    if a < TINY_V2:  # |v|^2 and b^2 would underflow: solve for v * 2^600
        if vx == 0.0 and vy == 0.0 and vz == 0.0:
            return INF
        scale = TINY_SCALE
        vx, vy, vz = vx * scale, vy * scale, vz * scale
        a = vx * vx + vy * vy + vz * vz
    b = px * vx + py * vy + pz * vz
    c = (px * px + py * py + pz * pz) - reach * reach
    if c >= 0.0 and b > 0.0:
        return 0.0
    disc = b * b - a * c
    if disc < 0.0:
        disc = 0.0
    if b <= 0.0:
        return (math.sqrt(disc) - b) / a * scale
    # b > 0 and c < 0: larger root = c / (smaller root's numerator)
    return -c / (math.sqrt(disc) + b) * scale


def collide(m1, m2, dx, dy, dz, dvx, dvy, dvz):
    """Velocity changes of an elastic collision (assignment §2.3.1).

    Args:
        m1, m2: masses [mass].
        dx, dy, dz: ``r_1 - r_2`` at contact [length].
        dvx, dvy, dvz: ``v_1 - v_2`` before the collision [length/time].

    Returns:
        ``(k1, k2)`` [1/time]: the new velocities are ``v_1 - k1 * dr`` and
        ``v_2 + k2 * dr``.  The impulse on sphere 1 is ``-m1 * k1 * dr``.

    Example:
        >>> collide(1.0, 1.0, -2.0, 0.0, 0.0, 3.0, 0.0, 0.0)
        (-1.5, -1.5)
    """
    s = (dvx * dx + dvy * dy + dvz * dz) / (dx * dx + dy * dy + dz * dz)
    msum = m1 + m2
    return 2.0 * m2 / msum * s, 2.0 * m1 / msum * s


def reflect(px, py, pz, vx, vy, vz):
    """Factor of a reflection off the container at centre ``p``.

    Returns:
        ``k`` [1/time] such that the new velocity is ``v - k * p``, i.e. the
        mirror image of ``v`` in the plane tangent at the contact point.

    Example:
        >>> reflect(5.0, 0.0, 0.0, 2.0, 1.0, 0.0)
        0.8
    """
    return 2.0 * (vx * px + vy * py + vz * pz) / (px * px + py * py + pz * pz)

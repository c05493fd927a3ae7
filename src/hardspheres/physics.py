"""The physics of hard spheres (elastic, inelastic, and steps: square wells), as small pure scalar functions.

Every function here takes and returns plain floats, so that the same source
runs unchanged as Python (the small-input path of ``spheres``, which must not
pay numba's start-up) and compiled by numba inside the event core
(:mod:`hardspheres.core._core`).  The two give bit-identical results: both use
IEEE-754 double arithmetic in the same order, and the core is compiled without
``fastmath`` (so no reassociation and no fused multiply-add).

Conventions (dimensions in brackets):

* positions ``p`` [length], velocities ``v`` [length/time], masses [mass];
* times returned are *durations from now* [time], ``inf`` for never;
* quadratic roots use the numerically stable form (no subtraction of nearly
  equal numbers), see :func:`pair_time` and :func:`wall_time`.
* ``planar=True`` (disks, 2-D): the z components are not read, and no
  term of z is formed (the same arithmetic as in 3-D with z left out, so a
  2-D result equals the 3-D one with z = 0 up to the sign of a zero).
"""

import math

INF = math.inf

#: The quadratics' coefficients are solved as given while ``|dv|^2 |dr|^2``
#: (``|v|^2 (|p|^2 + reach^2)`` for the wall) lies in ``[RANGE_LO,
#: RANGE_HI]`` [length^4/time^2]: then ``b^2``, ``a c`` and ``a sigma^2`` are
#: normal doubles (at most that product).  Outside it (speeds or lengths
#: near the ends of the double range, a sphere at rest) lengths and speeds
#: are each scaled by a power of two (exact) to order 1 first, and the time
#: scaled back: inside it, the results are bit for bit those without it.
RANGE_LO = 1e-200
RANGE_HI = 1e300

#: ... and while ``|dv|^2`` and ``|dr|^2`` (``|v|^2`` and ``|p|^2 + reach^2``)
#: are each at least ``SQUARES_LO`` [length^2/time^2, length^2]: the product
#: alone let a subnormal ``|v|^2`` through (2^-1058, with 17 significant
#: bits: wall times 10^10 ulps off, issue 29).  Above ``SQUARES_LO`` the
#: subnormal parts of a sum of squares (each off by at most 2^-1075) move it
#: by less than 2^-110 of itself.
SQUARES_LO = 1e-290

#: :func:`pair_time_within` takes the discriminant ``b^2 - a c`` as Lagrange's
#: ``|dv|^2 sigma^2 - |dr x dv|^2`` when ``|dr|^2 > LAGRANGE_RATIO sigma^2``
#: (more than 4 contact distances apart), where ``b^2 - a c`` would cancel;
#: nearer, as ``b^2 - a c`` (it then loses at most 4 bits, and the official
#: examples keep their bits: see docs/numerics.md).
LAGRANGE_RATIO = 16.0

#: The compiled core rejects a pair without calling :func:`pair_time_within`
#: when ``b^2 - a c < -MISS_MARGIN |dv|^2 |dr|^2`` (computed as ``b*b - a*c``):
#: the rounding of that expression and of either form of the discriminant is
#: below ``25 u |dv|^2 |dr|^2`` (``u = 2^-53``), so such a pair misses for the
#: kernel too.
MISS_MARGIN = 1e-13


def order_one(
    x: float, y: float, z: float, length: float, vx: float, vy: float, vz: float, speed: float
) -> tuple[float, float, float, float, float, float, float, float, int]:
    """Lengths and speeds scaled to order 1, each by a power of two (exact).

    The quadratics' rare path outside :data:`RANGE_LO`..:data:`RANGE_HI`:
    ``x, y, z, length`` [length] are divided by ``2^er`` and ``vx, vy, vz,
    speed`` [length/time] by ``2^ev``, where ``2^er`` and ``2^ev`` bound the
    largest of each; a time ``t'`` solved from the scaled values is ``t'
    2^shift`` with ``shift = er - ev``.  (The compiled core registers this
    function with numba, so the kernels stay plain Python here.)

    Returns:
        ``(x, y, z, length, vx, vy, vz, speed, shift)``, scaled.

    Example:
        >>> order_one(3.0, 0.0, 0.0, 1.0, 0.0, 0.5, 0.0, 0.0)
        (0.75, 0.0, 0.0, 0.25, 0.0, 0.5, 0.0, 0.0, 2)
    """
    er = math.frexp(max(abs(x), abs(y), abs(z), abs(length)))[1]
    ev = math.frexp(max(abs(vx), abs(vy), abs(vz), abs(speed)))[1]
    return (
        math.ldexp(x, -er),
        math.ldexp(y, -er),
        math.ldexp(z, -er),
        math.ldexp(length, -er),
        math.ldexp(vx, -ev),
        math.ldexp(vy, -ev),
        math.ldexp(vz, -ev),
        math.ldexp(speed, -ev),
        er - ev,
    )


def scaled_time(t: float, shift: int) -> float:
    """``t 2^shift`` (:func:`order_one`'s time scaled back), ``inf`` past the largest double.

    ``math.ldexp`` raises ``OverflowError`` there, where the compiled core's
    gives ``inf``; a sphere nearly at rest (after an inelastic collapse, say)
    meets the wall that late.  Otherwise the bits of ``math.ldexp``.

    Example:
        >>> scaled_time(3.0, 2), scaled_time(1.0, 2000)
        (12.0, inf)
    """
    if t > 0.0 and math.frexp(t)[1] + shift > 1024:
        return INF
    return math.ldexp(t, shift)


#: The clock "does not advance" over events less than this fraction of its
#: own value apart (see :func:`frozen_limit`).
FROZEN_RELATIVE = 2.0**-30


def frozen_limit(n: int) -> int:
    """How many collisions and reflections in a row may leave the clock where it was.

    One more stops a run (both engines), counting from the first event of
    the streak at time ``t0``; an event at ``t > t0 + FROZEN_RELATIVE |t|``
    starts a new streak.  A genuine cascade of ``n`` touching spheres at
    one instant takes far fewer (a simple cubic lattice of 91125: 37 per
    sphere), and ``frozen_limit(n)`` events of a genuine gas take at least
    2000 mean free times, which the clock outgrows only past 10^12 of them;
    a light sphere trapped between a wall and a sphere 10^200 times heavier
    would take ~10^100.
    """
    return 100_000 + 1000 * n


def pair_time(
    dx: float, dy: float, dz: float, dvx: float, dvy: float, dvz: float, sigma: float, planar: bool = False
) -> float:
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
    return pair_time_within(dx, dy, dz, dvx, dvy, dvz, sigma, INF, planar)


def pair_time_within(
    dx: float,
    dy: float,
    dz: float,
    dvx: float,
    dvy: float,
    dvz: float,
    sigma: float,
    horizon: float,
    planar: bool = False,
) -> float:
    """:func:`pair_time`, or ``inf`` early if the pair surely meets after ``horizon``.

    The root is at least ``c / (-2 b)``; a pair with ``c > -2 b horizon (1 +
    1e-12)`` cannot meet by ``horizon`` [time], and its exact time is not
    computed (no square root, no division).  Otherwise the result is
    :func:`pair_time`'s (``horizon = inf``).

    The quadratic is ``a t^2 + 2 b t + c = 0`` with ``a = |dv|^2``,
    ``b = dr . dv``, ``c = |dr|^2 - sigma^2``; its discriminant ``b^2 - a c``
    is computed as ``a sigma^2 - |dr x dv|^2`` (Lagrange's identity), which
    does not cancel when ``sigma`` is small against ``|dr|``.

    Example:
        >>> pair_time_within(-10.0, 0.0, 0.0, 2.0, 0.0, 0.0, 2.0, 2.0)
        inf
        >>> pair_time_within(-10.0, 0.0, 0.0, 2.0, 0.0, 0.0, 2.0, 5.0)
        4.0
    """
    if planar:
        # (2-D: z is not read)
        dz = dvz = 0.0
        b = dx * dvx + dy * dvy
    else:
        b = dx * dvx + dy * dvy + dz * dvz
    if b > 0.0:
        return INF
    if planar:
        a = dvx * dvx + dvy * dvy
        r2 = dx * dx + dy * dy
    else:
        a = dvx * dvx + dvy * dvy + dvz * dvz
        r2 = dx * dx + dy * dy + dz * dz
    shift = 0
    if not RANGE_LO <= a * r2 <= RANGE_HI or a < SQUARES_LO or r2 < SQUARES_LO:
        dx, dy, dz, sigma, dvx, dvy, dvz, _, shift = order_one(dx, dy, dz, sigma, dvx, dvy, dvz, 0.0)
        horizon = math.ldexp(horizon, -shift)
        if planar:
            a = dvx * dvx + dvy * dvy
            b = dx * dvx + dy * dvy
            r2 = dx * dx + dy * dy
        else:
            a = dvx * dvx + dvy * dvy + dvz * dvz
            b = dx * dvx + dy * dvy + dz * dvz
            r2 = dx * dx + dy * dy + dz * dz
    if b >= 0.0:
        return INF
    c = r2 - sigma * sigma
    if c <= 0.0:
        return 0.0
    if c > -2.0 * b * horizon * (1.0 + 1e-12):
        return INF
    s2 = sigma * sigma
    if r2 > LAGRANGE_RATIO * s2:
        # far apart: b^2 and a c agree to many digits, so take
        # b^2 - a c = |dv|^2 sigma^2 - |dr x dv|^2 (Lagrange's identity)
        uz = dx * dvy - dy * dvx
        if planar:
            disc = a * s2 - uz * uz
        else:
            ux = dy * dvz - dz * dvy
            uy = dz * dvx - dx * dvz
            disc = a * s2 - (ux * ux + uy * uy + uz * uz)
    else:
        disc = b * b - a * c
    if disc <= 0.0:
        return INF
    # smaller root of a t^2 + 2 b t + c = 0 with b < 0, without cancellation
    t = c / (math.sqrt(disc) - b)
    return t if shift == 0 else scaled_time(t, shift)


def wall_time(
    px: float, py: float, pz: float, vx: float, vy: float, vz: float, reach: float, planar: bool = False
) -> float:
    """Time until a sphere's centre reaches distance ``reach`` from the origin.

    Args:
        px, py, pz: centre now [length].
        vx, vy, vz: velocity [length/time].
        reach: container radius minus sphere radius [length].

    Returns:
        The larger root ``t >= 0`` of ``|p + t v| = reach`` [time]; ``0`` for
        a sphere at or beyond ``reach`` that moves outward or along the wall,
        ``inf`` for a sphere at rest.

    Example:
        >>> wall_time(0.0, 0.0, 0.0, 2.0, 0.0, 0.0, 10.0)
        5.0
    """
    return wall_time_grow(px, py, pz, vx, vy, vz, reach, 0.0, planar)


def collide(
    m1: float,
    m2: float,
    dx: float,
    dy: float,
    dz: float,
    dvx: float,
    dvy: float,
    dvz: float,
    planar: bool = False,
) -> tuple[float, float]:
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
    if planar:
        s = (dvx * dx + dvy * dy) / (dx * dx + dy * dy)
    else:
        s = (dvx * dx + dvy * dy + dvz * dz) / (dx * dx + dy * dy + dz * dz)
    msum = m1 + m2
    return 2.0 * m2 / msum * s, 2.0 * m1 / msum * s


def reflect(px: float, py: float, pz: float, vx: float, vy: float, vz: float, planar: bool = False) -> float:
    """Factor of a reflection off the container at centre ``p``.

    Returns:
        ``k`` [1/time] such that the new velocity is ``v - k * p``, i.e. the
        mirror image of ``v`` in the plane tangent at the contact point.

    Example:
        >>> reflect(5.0, 0.0, 0.0, 2.0, 1.0, 0.0)
        0.8
    """
    if planar:
        return 2.0 * (vx * px + vy * py) / (px * px + py * py)
    return 2.0 * (vx * px + vy * py + vz * pz) / (px * px + py * py + pz * pz)


# ---- steps: square wells and shoulders ------------------------------------------
# A pair potential made of steps: a hard core at sigma, then edges at radii
# r_k with a constant potential energy between them.  A pair meets an edge
# from outside with pair_time (sigma replaced by the edge's radius) and from
# inside with pair_time_out; at the edge its velocities change by
# cross_step (docs/numerics.md, "Steps: wells and shoulders").


def pair_time_out(
    dx: float, dy: float, dz: float, dvx: float, dvy: float, dvz: float, edge: float, planar: bool = False
) -> float:
    """Time until a pair *inside* a sphere of radius ``edge`` reaches it (leaving a well).

    The geometry of a sphere inside the spherical container, with the pair's
    relative motion for the sphere's: the *larger* root of ``|dr + t dv| =
    edge``, computed by :func:`wall_time` unchanged (its discriminant ``b^2 +
    a |c|`` is a sum, and its root is formed without cancellation for both
    signs of ``b = dr . dv``).

    Args:
        dx, dy, dz: separation ``r_i - r_j`` now [length], ``|dr| <= edge``.
        dvx, dvy, dvz: relative velocity ``v_i - v_j`` [length/time].
        edge: the step's radius ``lambda sigma`` [length].

    Returns:
        The time to the edge [time]: ``0`` for a pair at or beyond it and
        receding, ``inf`` for a pair at rest relative to each other.

    Example:
        >>> pair_time_out(1.0, 0.0, 0.0, 0.25, 0.0, 0.0, 1.5)
        2.0
        >>> pair_time_out(1.0, 0.0, 0.0, -0.5, 0.0, 0.0, 1.5)
        5.0
    """
    return wall_time(dx, dy, dz, dvx, dvy, dvz, edge, planar)


def cross_step(
    m1: float,
    m2: float,
    dx: float,
    dy: float,
    dz: float,
    dvx: float,
    dvy: float,
    dvz: float,
    du: float,
    planar: bool = False,
) -> tuple[float, float, bool]:
    """Velocity changes of a pair at a step of the potential: it crosses, or bounces back.

    The impulse acts along ``dr``; momentum, the centre of mass's motion and
    the tangential relative velocity are unchanged, and the normal kinetic
    energy changes by ``-du``.  With ``b = dr . dv``, ``R2 = |dr|^2`` and
    ``q = b^2 - 2 R2 du (1/m1 + 1/m2)``: if ``q > 0`` the pair crosses, its
    new ``b' = sign(b) sqrt(q)``, with ``k1 = 2 du / (m1 (b + b'))`` (``b``
    and ``b'`` of one sign: no cancellation, docs/numerics.md, "Steps:
    wells and shoulders"); otherwise (``q <= 0``: the normal kinetic energy
    ``mu (dv . n)^2 / 2`` does not pay for ``du``) it bounces elastically,
    :func:`collide`'s factors bit for bit.

    Args:
        m1, m2: masses [mass].
        dx, dy, dz: ``r_1 - r_2`` at the edge [length].
        dvx, dvy, dvz: ``v_1 - v_2`` before [length/time].
        du: the potential energy after minus before the crossing
            [mass*length^2/time^2]: ``-eps`` entering a well of depth ``eps``,
            ``+eps`` leaving it.

    Returns:
        ``(k1, k2, crossed)``: the new velocities are ``v_1 - k1 * dr`` and
        ``v_2 + k2 * dr`` (``k`` [1/time]); ``crossed`` False for a bounce.

    Example:
        >>> cross_step(1.0, 1.0, -1.5, 0.0, 0.0, 2.0, 0.0, 0.0, -1.25)  # normal speed 2 -> 3
        (0.3333333333333333, 0.3333333333333333, True)
        >>> cross_step(1.0, 1.0, 1.5, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0)  # short of 1: back at speed 1
        (0.6666666666666666, 0.6666666666666666, False)
    """
    if planar:
        b = dx * dvx + dy * dvy
        r2 = dx * dx + dy * dy
    else:
        b = dx * dvx + dy * dvy + dz * dvz
        r2 = dx * dx + dy * dy + dz * dz
    q = b * b - 2.0 * r2 * du * (1.0 / m1 + 1.0 / m2)
    if q > 0.0:
        bp = math.copysign(math.sqrt(q), b)
        f = 2.0 * du / (b + bp)
        return f / m1, f / m2, True
    k1, k2 = collide(m1, m2, dx, dy, dz, dvx, dvy, dvz, planar)
    return k1, k2, False


# ---- inelastic collisions (granular gases) -------------------------------------
# A normal restitution coefficient ``e`` (0 < e <= 1) scales the normal
# relative speed after a collision: ``vn' = -e vn``.  The core compiles these
# kernels into its inelastic variant only (``_core``, "the collision rule");
# at ``e = 1`` each gives the bits of its elastic twin (``1.0 + 1.0`` is
# ``2.0`` exactly, and the operations are the same, in the same order).


def collide_inelastic(
    m1: float,
    m2: float,
    dx: float,
    dy: float,
    dz: float,
    dvx: float,
    dvy: float,
    dvz: float,
    e: float,
    planar: bool = False,
) -> tuple[float, float, float]:
    """Velocity changes of a collision with normal restitution ``e``, and the energy it dissipates.

    The normal relative velocity is reversed and scaled by ``e``; momentum
    is conserved.  With ``s = dv . dr / |dr|^2``: ``k1 = (1 + e) m2 / (m1 + m2) s``,
    ``k2 = (1 + e) m1 / (m1 + m2) s``, and the kinetic energy lost is
    ``(1 - e^2) / 2 * mu * (dv . n)^2`` (``mu = m1 m2 / (m1 + m2)``,
    ``n = dr / |dr|``), formed as ``(1 - e)(1 + e)`` and ``s (dv . dr)``:
    products of numbers of one sign, without cancellation
    (docs/numerics.md, "Inelastic collisions").

    Args:
        m1, m2: masses [mass].
        dx, dy, dz: ``r_1 - r_2`` at contact [length].
        dvx, dvy, dvz: ``v_1 - v_2`` before the collision [length/time].
        e: normal restitution coefficient, ``0 < e <= 1`` (1: elastic).

    Returns:
        ``(k1, k2, lost)``: the new velocities are ``v_1 - k1 * dr`` and
        ``v_2 + k2 * dr`` (``k`` [1/time]); ``lost`` the kinetic energy
        dissipated [mass*length^2/time^2].

    Example:
        >>> collide_inelastic(1.0, 1.0, -2.0, 0.0, 0.0, 3.0, 0.0, 0.0, 0.5)
        (-1.125, -1.125, 1.6875)
    """
    if planar:
        dot = dvx * dx + dvy * dy
        r2 = dx * dx + dy * dy
    else:
        dot = dvx * dx + dvy * dy + dvz * dz
        r2 = dx * dx + dy * dy + dz * dz
    s = dot / r2
    msum = m1 + m2
    f = 1.0 + e
    lost = 0.5 * ((1.0 - e) * f) * (m1 / msum * m2) * (s * dot)
    return f * m2 / msum * s, f * m1 / msum * s, lost


def reflect_inelastic(
    m: float, px: float, py: float, pz: float, vx: float, vy: float, vz: float, e: float, planar: bool = False
) -> tuple[float, float]:
    """Factor of a reflection off the container with restitution ``e``, and the energy it dissipates.

    The radial velocity is reversed and scaled by ``e``: the new velocity is
    ``v - k p`` with ``k = (1 + e) (v . p) / |p|^2``; the kinetic energy lost
    is ``(1 - e^2) / 2 * m * (v . p)^2 / |p|^2`` (the wall does not move).

    Args:
        m: the sphere's mass [mass].
        px, py, pz: its centre at contact [length] (the container's centre at 0).
        vx, vy, vz: its velocity before [length/time].
        e: the wall's restitution coefficient, ``0 < e <= 1`` (1: elastic).

    Returns:
        ``(k, lost)``: ``k`` [1/time] and the energy lost [mass*length^2/time^2].

    Example:
        >>> reflect_inelastic(1.0, 5.0, 0.0, 0.0, 2.0, 1.0, 0.0, 0.5)
        (0.6, 1.5)
    """
    if planar:
        dot = vx * px + vy * py
        p2 = px * px + py * py
    else:
        dot = vx * px + vy * py + vz * pz
        p2 = px * px + py * py + pz * pz
    f = 1.0 + e
    lost = 0.5 * ((1.0 - e) * f) * m * (dot / p2 * dot)
    return f * dot / p2, lost


# ---- the thermal wall (a heated container) --------------------------------------
# A sphere that meets a thermal wall leaves it with a velocity drawn afresh
# at the wall's temperature: the normal component from the flux-weighted
# (Rayleigh) distribution, the tangential ones from the Maxwellian.  The
# draws come from a counter-based generator: draw ``n`` of a run with seed
# ``s`` is a pure function of ``(s, n)``, computed in int64 without
# overflow (every product below 2^63), so Python and the compiled core
# give the same bits and a checkpoint carries the whole generator in two
# integers.

#: 2 pi, as the draws use it.
TWO_PI = 6.283185307179586


def mix32(x: int) -> int:
    """A 32-bit integer hash (C. Wellons' ``lowbias32``), exact in int64.

    Args:
        x: an integer in ``[0, 2^32)``.

    Returns:
        Its hash, in ``[0, 2^32)``.

    Example:
        >>> mix32(0), mix32(1)
        (0, 2261973619)
    """
    x ^= x >> 16
    x = (x * 0x21F0AAAD) & 0xFFFFFFFF
    x ^= x >> 15
    x = (x * 0x735A2D97) & 0xFFFFFFFF
    x ^= x >> 15
    return x


def uniform_draw(seed: int, draw: int, k: int) -> float:
    """Number ``k`` of draw ``draw`` of the generator with ``seed``: uniform in ``(0, 1)``.

    52 random bits ``n`` give ``(n + 1/2) / 2^52``: never 0 or 1.

    Args:
        seed: the generator's seed, ``0 <= seed < 2^32``.
        draw: the draw's number, ``0 <= draw < 2^63``.
        k: which number of the draw, ``0 <= k < 2^30``.

    Example:
        >>> 0.0 < uniform_draw(7, 0, 0) < 1.0
        True
    """
    h = mix32(mix32(seed) ^ (draw & 0xFFFFFFFF))
    h = mix32(h ^ (draw >> 32))
    a = mix32(h ^ (2 * k + 1))
    b = mix32(h ^ (2 * k + 2))
    return ((a >> 6) * 67108864.0 + (b >> 6) + 0.5) * 2.0**-52


def thermal_wall(
    m: float,
    px: float,
    py: float,
    pz: float,
    vx: float,
    vy: float,
    vz: float,
    kt: float,
    seed: int,
    draw: int,
    planar: bool = False,
) -> tuple[float, float, float, float, float]:
    """A sphere re-emitted by a thermal wall at temperature ``kt``.

    With ``n = p / |p|`` the outward normal and ``s = sqrt(kt / m)``, the
    new velocity is ``-c n + (g - (g . n) n)``: ``c = s sqrt(-2 ln u_0)``
    (the flux-weighted speed towards the inside, density ``c / s^2
    exp(-c^2 / 2 s^2)``) and ``g`` a Maxwellian velocity of variance ``s^2``
    per axis (Box-Muller), its normal part removed.  The sphere's momentum
    changes by ``m (v' - v)``; the wall receives the normal impulse ``m (v .
    n + c)``.  Elastic spheres between thermal walls relax to the
    Maxwellian at ``kt`` (docs/numerics.md, "The thermal wall").

    Args:
        m: the sphere's mass [mass].
        px, py, pz: its centre at contact [length] (the container's centre at 0).
        vx, vy, vz: its velocity before [length/time].
        kt: the wall's temperature [energy], ``> 0``.
        seed, draw: the generator's seed and the draw's number (:func:`uniform_draw`).

    Returns:
        ``(vx', vy', vz', impulse, gain)``: the new velocity (``vz' = 0`` if
        ``planar``), the normal impulse given to the wall
        [mass*length/time] and the kinetic energy the sphere gained
        [mass*length^2/time^2] (negative if it was hotter than the wall).

    Example:
        >>> w = thermal_wall(1.0, 4.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 7, 0)
        >>> w[0] < 0.0 and w[3] > 1.0  # inward, and more than the incoming momentum
        True
    """
    s = math.sqrt(kt / m)
    c = s * math.sqrt(-2.0 * math.log(uniform_draw(seed, draw, 0)))
    r = s * math.sqrt(-2.0 * math.log(uniform_draw(seed, draw, 1)))
    a = TWO_PI * uniform_draw(seed, draw, 2)
    gx = r * math.cos(a)
    gy = r * math.sin(a)
    if planar:
        p = math.sqrt(px * px + py * py)
        nx, ny = px / p, py / p
        gn = gx * nx + gy * ny
        vn = vx * nx + vy * ny
        wx = (gx - gn * nx) - c * nx
        wy = (gy - gn * ny) - c * ny
        gain = 0.5 * m * ((wx * wx + wy * wy) - (vx * vx + vy * vy))
        return wx, wy, 0.0, m * (vn + c), gain
    p = math.sqrt(px * px + py * py + pz * pz)
    nx, ny, nz = px / p, py / p, pz / p
    rz = s * math.sqrt(-2.0 * math.log(uniform_draw(seed, draw, 3)))
    gz = rz * math.cos(TWO_PI * uniform_draw(seed, draw, 4))
    gn = gx * nx + gy * ny + gz * nz
    vn = vx * nx + vy * ny + vz * nz
    wx = (gx - gn * nx) - c * nx
    wy = (gy - gn * ny) - c * ny
    wz = (gz - gn * nz) - c * nz
    gain = 0.5 * m * ((wx * wx + wy * wy + wz * wz) - (vx * vx + vy * vy + vz * vz))
    return wx, wy, wz, m * (vn + c), gain


# ---- growth (Lubachevsky-Stillinger) ------------------------------------------
# Radii grow linearly in time, so a contact distance is ``s + u t`` and a
# container's reach ``reach - w t``: the meeting times stay roots of a
# quadratic.  These kernels are used only while growing; a run without
# growth never calls them (its arithmetic is the functions above).

#: After a growing collision or reflection the contact opens at least this
#: fraction of the speeds involved (rounding could otherwise leave a pair
#: closing at exactly the growth speed, colliding again at once).
GROW_MARGIN = 1e-9


def pair_time_grow(
    dx: float,
    dy: float,
    dz: float,
    dvx: float,
    dvy: float,
    dvz: float,
    s: float,
    u: float,
    horizon: float,
    planar: bool = False,
) -> float:
    """Time until two spheres meet while their contact distance grows.

    Longer than 80 lines with this docstring (under 60 of code): one compiled
    kernel whose steps share the rescaled coordinates.

    Args:
        dx, dy, dz: separation ``r_i - r_j`` now [length].
        dvx, dvy, dvz: relative velocity ``v_i - v_j`` [length/time].
        s: contact distance now [length].
        u: its growth speed ``ds/dt >= 0`` [length/time].
        horizon: :func:`pair_time_within`'s early exit [time] (used only
            where the root is bounded below by ``c / (-2 b)``).

    Returns:
        The first ``t >= 0`` with ``|dr + t dv| = s + u t`` [time], ``inf``
        for never.  The quadratic ``a t^2 + 2 b t + c`` has ``a = |dv|^2 -
        u^2``, ``b = dr . dv - s u``, ``c = |dr|^2 - s^2``; far from contact
        its discriminant is taken as ``|s dv - u dr|^2 - |dr x dv|^2`` (the
        Lagrange identity of :func:`pair_time_within`, extended), and every
        root is formed without cancellation.  With ``u = 0`` the root is
        :func:`pair_time`'s up to rounding.

    Example:
        >>> pair_time_grow(-10.0, 0.0, 0.0, 1.0, 0.0, 0.0, 2.0, 1.0, math.inf)
        4.0
    """
    if planar:
        dz = dvz = 0.0
        b0 = dx * dvx + dy * dvy
        a0 = dvx * dvx + dvy * dvy
        r2 = dx * dx + dy * dy
    else:
        b0 = dx * dvx + dy * dvy + dz * dvz
        a0 = dvx * dvx + dvy * dvy + dvz * dvz
        r2 = dx * dx + dy * dy + dz * dz
    shift = 0
    a2, l2 = a0 + u * u, r2 + s * s
    if not RANGE_LO <= a2 * l2 <= RANGE_HI or a2 < SQUARES_LO or l2 < SQUARES_LO:
        if dvx == 0.0 and dvy == 0.0 and dvz == 0.0 and u == 0.0:
            return INF  # at rest (a0 alone underflows for speeds below 1e-154)
        dx, dy, dz, s, dvx, dvy, dvz, u, shift = order_one(dx, dy, dz, s, dvx, dvy, dvz, u)
        horizon = math.ldexp(horizon, -shift)
        if planar:
            b0 = dx * dvx + dy * dvy
            a0 = dvx * dvx + dvy * dvy
            r2 = dx * dx + dy * dy
        else:
            b0 = dx * dvx + dy * dvy + dz * dvz
            a0 = dvx * dvx + dvy * dvy + dvz * dvz
            r2 = dx * dx + dy * dy + dz * dz
    a = a0 - u * u
    b = b0 - s * u
    s2 = s * s
    c = r2 - s2
    if c <= 0.0:
        if b < 0.0:
            return 0.0
        if a >= 0.0:
            return INF
        # apart faster than the growth now, caught up later: the later root
        disc = b * b - a * c
        t = (b + math.sqrt(disc)) / (-a) if disc > 0.0 else b / (-a)
        return t if shift == 0 else scaled_time(t, shift)
    if b >= 0.0 and a >= 0.0:
        return INF
    if a >= 0.0 and c > -2.0 * b * horizon * (1.0 + 1e-12):
        return INF
    if a >= 0.0 and b * b - a * c < -MISS_MARGIN * (a0 + u * u) * (r2 + s2):
        # a sure miss (the core's reject test, see MISS_MARGIN): |b| and
        # |a c| are at most (a0 + u^2)(r2 + s^2) (Cauchy-Schwarz), and so
        # are either discriminant's terms, so their rounding is far below
        # the margin and the discriminant below is negative too
        return INF
    if r2 > LAGRANGE_RATIO * s2:
        uz = dx * dvy - dy * dvx
        wx = s * dvx - u * dx
        wy = s * dvy - u * dy
        if planar:
            disc = (wx * wx + wy * wy) - uz * uz
        else:
            ux = dy * dvz - dz * dvy
            uy = dz * dvx - dx * dvz
            wz = s * dvz - u * dz
            disc = (wx * wx + wy * wy + wz * wz) - (ux * ux + uy * uy + uz * uz)
    else:
        disc = b * b - a * c
    if disc <= 0.0:
        if a >= 0.0:
            return INF
        disc = 0.0
    if b < 0.0:
        t = c / (math.sqrt(disc) - b)
    else:
        # a < 0, c > 0: the one positive root
        t = (b + math.sqrt(disc)) / (-a)
    return t if shift == 0 else scaled_time(t, shift)


def wall_time_grow(
    px: float,
    py: float,
    pz: float,
    vx: float,
    vy: float,
    vz: float,
    reach: float,
    w: float,
    planar: bool = False,
) -> float:
    """:func:`wall_time` for a sphere whose radius grows at speed ``w`` [length/time].

    ``reach`` [length] is the container radius minus the sphere's radius
    now; it shrinks as ``reach - w t``.  Returns the first ``t >= 0`` with
    ``|p + t v| = reach - w t`` [time] (``0`` at or beyond it and not
    moving inward faster than the wall closes).

    Example:
        >>> wall_time_grow(0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 10.0, 1.0)
        5.0
    """
    if planar:
        pz = vz = 0.0
        a0 = vx * vx + vy * vy
        pp = px * px + py * py
    else:
        a0 = vx * vx + vy * vy + vz * vz
        pp = px * px + py * py + pz * pz
    shift = 0
    a2, l2 = a0 + w * w, pp + reach * reach
    if not RANGE_LO <= a2 * l2 <= RANGE_HI or a2 < SQUARES_LO or l2 < SQUARES_LO:
        if vx == 0.0 and vy == 0.0 and vz == 0.0 and w == 0.0:
            return INF  # at rest (a0 alone underflows for speeds below 1e-154)
        px, py, pz, reach, vx, vy, vz, w, shift = order_one(px, py, pz, reach, vx, vy, vz, w)
        if planar:
            a0 = vx * vx + vy * vy
            pp = px * px + py * py
        else:
            a0 = vx * vx + vy * vy + vz * vz
            pp = px * px + py * py + pz * pz
    a = a0 - w * w
    if planar:
        b = px * vx + py * vy + reach * w
    else:
        b = px * vx + py * vy + pz * vz + reach * w
    c = pp - reach * reach
    if c >= 0.0 and b > 0.0:
        return 0.0
    disc = b * b - a * c
    if disc < 0.0:
        disc = 0.0
    if b > 0.0:
        t = -c / (math.sqrt(disc) + b)
    elif a > 0.0:
        t = (math.sqrt(disc) - b) / a
    else:
        t = 0.0
    return t if shift == 0 else scaled_time(t, shift)


def collide_grow(
    m1: float,
    m2: float,
    dx: float,
    dy: float,
    dz: float,
    dvx: float,
    dvy: float,
    dvz: float,
    u: float,
    planar: bool = False,
) -> tuple[float, float]:
    """:func:`collide` with the Lubachevsky-Stillinger rule.

    The normal relative speed is reflected in the frame of the growing
    contact: ``vn' - u = -(vn - u)`` (``vn = dv . n`` with ``n = dr/|dr|``,
    ``u`` the contact distance's growth speed [length/time]), so the pair
    separates faster than the contact grows (by at least
    :data:`GROW_MARGIN` of the speeds).  ``u = 0`` is the elastic rule.

    Example:
        >>> collide_grow(1.0, 1.0, -2.0, 0.0, 0.0, 3.0, 0.0, 0.0, 1.0)
        (-2.0, -2.0)
    """
    if planar:
        d = math.sqrt(dx * dx + dy * dy)
        vn = (dvx * dx + dvy * dy) / d
    else:
        d = math.sqrt(dx * dx + dy * dy + dz * dz)
        vn = (dvx * dx + dvy * dy + dvz * dz) / d
    gap = vn - u  # < 0: closing
    change = -2.0 * gap
    least = -gap + GROW_MARGIN * (abs(vn) + u)
    if change < least:
        change = least
    s = change / (2.0 * d)  # the elastic rule's s is vn / d
    s = -s
    msum = m1 + m2
    return 2.0 * m2 / msum * s, 2.0 * m1 / msum * s


def reflect_grow(
    px: float, py: float, pz: float, vx: float, vy: float, vz: float, w: float, planar: bool = False
) -> float:
    """:func:`reflect` off a wall closing at speed ``w`` relative to the sphere.

    The radial speed is reflected in the frame of the wall: the new inward
    speed exceeds ``w`` by what the old outward speed did (by at least
    :data:`GROW_MARGIN` of the speeds).

    Example:
        >>> reflect_grow(5.0, 0.0, 0.0, 2.0, 1.0, 0.0, 1.0)
        1.2
    """
    if planar:
        d = math.sqrt(px * px + py * py)
        vr = (vx * px + vy * py) / d
    else:
        d = math.sqrt(px * px + py * py + pz * pz)
        vr = (vx * px + vy * py + vz * pz) / d
    change = 2.0 * (vr + w)
    least = vr + w + GROW_MARGIN * (abs(vr) + w)
    if change < least:
        change = least
    return change / d

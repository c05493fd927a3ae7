"""The compiled event core: O(log N) work per event.

Private: use :class:`hardspheres.core.engine.Engine` (or the public
:class:`hardspheres.Simulation`).  Everything here is numba-compiled, without
``fastmath``, from the scalar kernels of :mod:`hardspheres.physics`.

Design (the classic one-event-per-sphere scheme of Rapaport and
Lubachevsky, as in the fastest public codes):

* **Local times.**  Sphere ``i`` is stored as its centre at its own time
  ``t_i`` (the time of its last collision or reflection); its centre at time
  ``t`` is ``x_i + v_i (t - t_i)``.  An event touches only the spheres
  involved.  Each sphere's record is one 64-byte row of ``spheres``:
  ``x y z vx vy vz t_i R_i``.
* **Neighbour lists with shells** (as in Smallenburg's "Single" EDMD).
  Each sphere has a shell centre (its centre when it was last listed) and a
  reach ``a_i >= R_i``; spheres ``i, j`` are neighbours while their shell
  centres are nearer than ``s (a_i + a_j)`` (``s = F_SHELL``, 1.5), and a
  sphere stays within ``(s - 1) a_i`` of its shell centre, so two spheres
  that are not neighbours cannot touch.  A sphere is predicted only against
  its neighbours.  Leaving its shell is an event of its own: a new shell
  where it is, its list made anew from the 27 cells (each at least
  ``2 s a_max`` wide) around the new centre, in both directions (the lists
  are symmetric), and the sphere predicted afresh.
* **Calendar.**  Each sphere keeps its earliest collision or reflection
  (time, kind, partner, the partner's event count) and the time it leaves
  its shell; an event calendar orders the spheres by the earlier of the
  two: buckets of time, the current one an indexed binary heap (O(1) per
  event on average, see "the calendar" below).  A prediction whose partner has had an event since is stale: it
  is dropped, and the sphere predicted afresh, when it reaches the top.
* **Predictions that do not depend on when they are made.**  A pair is
  predicted from the later of its two spheres' own times, a wall from the
  sphere's own time, with the lower index's centre minus the higher's: the
  brute-force reference (:mod:`hardspheres.core.reference`) does the same, so
  the two agree bit for bit.
* **Ties.**  Events order by ``(time, kind, i, j)``: reflections before
  collisions, lower index first: the spheres' input indices (``book``'s
  ``ORIGIN``), whatever order the engine keeps them in.  With a
  simultaneity ``window > 0`` (the assignment's 1e-8 s), events less than
  ``window`` after the last one happen *at* its time, and whenever that
  time (the anchor) moves, every sphere whose event falls in the new window
  is predicted afresh (:func:`refresh_window`), so the tie order decides
  among them exactly as in the reference.  An event at the anchor's own
  instant changes no other prediction: only the spheres it touched are
  predicted again.
* **Events that would not end** stop the loop (see :func:`run`): a
  reflection that would change nothing, and a clock that does not advance
  over ``physics.frozen_limit(N)`` collisions and reflections.
* **Time origin.**  :func:`rebase` moves the time origin to the clock, so
  long runs keep the precision of short ones.
"""

import numba
import numba.core.cpu
import numba.extending
import numpy as np
from llvmlite import ir
from numba.core import cgutils, types

from .. import events, physics
from .._jitcache import cache_dir, cached_compiler, source_digest


# Cached in a folder keyed to a digest of this file and the two it inlines
# (physics' kernels, the events' codes), stamped with it: the cache is valid
# wherever the package is installed (hardspheres._jitcache).
_DIGEST = source_digest(__file__, physics.__file__, events.__file__)
_CACHE_DIR = cache_dir(__file__, _DIGEST)
_cached = cached_compiler(__file__, _DIGEST)

# numba's private switch for its runtime (see below); a numba without it
# still compiles the core, only slower
_NO_NRT = {"_nrt": False} if hasattr(numba.core.cpu.CPUTargetOptions, "_nrt") else {}


def _compiler(**options):
    """``njit(**options)`` with the core's options, cached in :data:`_CACHE_DIR`."""
    return _cached(nogil=True, error_model="numpy", **_NO_NRT, **options)


# error_model="numpy": IEEE division (x/0 = inf) without a zero check per division.
# _nrt=False: nothing here allocates, and without numba's runtime no array
# argument is reference-counted per call.
_jit = _compiler()
# functions kept out of line but called from compiled code only: no Python wrapper
_jit_inner = _compiler(no_cpython_wrapper=True, no_cfunc_wrapper=True)
# The event loop's helpers are inlined into it: a call would pass every
# array as a struct of 7-9 words on the stack.  LLVM inlines them
# (forceinline: numba compiles each helper once and marks it alwaysinline);
# numba's IR inlining (inline="always") ran at the same speed but copied
# and typed each helper again at every call site: the first compilation
# took about 200 s instead of about 25 s.  (What each of these
# choices gained: benchmarks/README.md, "history of the core's speed".)
# They are called from compiled code only, so numba builds no Python
# wrapper for them (about a tenth of the first compilation, and no change
# to the loops' machine code).
_inline = _compiler(forceinline=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)

# the kernels too are inlined by LLVM, not copied into each caller as numba
# IR: they compile once each, the first compilation is about a fifth shorter,
# and the loops run 3-9% fewer instructions per collision (numba's IR copies
# were optimised less well), with the same bits (benchmarks/README.md)
_kernel = _compiler(forceinline=True)
# kernels that other kernels call: numba compiles such a call of the plain
# Python function (physics.py stays free of numba, for spheres' start-up)
for _callee in (
    physics.order_one,
    physics.scaled_time,
    physics.pair_time_within,
    physics.wall_time_grow,
    physics.mix32,
    physics.uniform_draw,
    physics.collide,
):
    numba.extending.register_jitable(forceinline=True, error_model="numpy", **_NO_NRT)(_callee)
pair_time_within = _kernel(physics.pair_time_within)
pair_time = _kernel(physics.pair_time)
wall_time = _kernel(physics.wall_time)
collide = _kernel(physics.collide)
reflect = _kernel(physics.reflect)
pair_time_grow = _kernel(physics.pair_time_grow)
wall_time_grow = _kernel(physics.wall_time_grow)
collide_grow = _kernel(physics.collide_grow)
reflect_grow = _kernel(physics.reflect_grow)
collide_inelastic = _kernel(physics.collide_inelastic)
reflect_inelastic = _kernel(physics.reflect_inelastic)
thermal_wall = _kernel(physics.thermal_wall)
cross_step = _kernel(physics.cross_step)
frozen_limit_of = _kernel(physics.frozen_limit)


@numba.extending.intrinsic
def _prefetch(typingctx, array, index):
    """Ask the CPU to start loading the cache line of ``array[index]`` (a row's first element).

    A hint (x86 ``prefetcht0``): nothing is read or changed.  The list scan
    calls it for every neighbour in a list before looking at any, so that
    the rows of spheres scattered over memory load side by side rather than
    one after another (benchmarks/README.md, "Where the time goes").
    """
    sig = types.void(array, index)

    def codegen(context, builder, signature, args):
        arrayty = signature.args[0]
        ary = context.make_array(arrayty)(context, builder, args[0])
        first = [args[1]] + [context.get_constant(types.intp, 0)] * (arrayty.ndim - 1)
        ptr = cgutils.get_item_pointer(context, builder, arrayty, ary, first, wraparound=False)
        bytes_ptr = ir.IntType(8).as_pointer()
        i32 = ir.IntType(32)
        fnty = ir.FunctionType(ir.VoidType(), [bytes_ptr, i32, i32, i32])
        fn = cgutils.get_or_insert_function(builder.module, fnty, "llvm.prefetch.p0i8")
        # read, highest locality, data cache
        builder.call(fn, [builder.bitcast(ptr, bytes_ptr), i32(0), i32(3), i32(1)])
        return context.get_dummy_value()

    return sig, codegen


#: Event kinds (also the tie order at equal times): the public ones are
#: :class:`hardspheres.events.EventKind`'s numbers; crossings and "nothing"
#: are the core's own.
REFLECTION = int(events.EventKind.REFLECTION)
COLLISION = int(events.EventKind.COLLISION)
CROSSING = 2
NONE = 3
CAPTURE = int(events.EventKind.CAPTURE)  # (the stepped variant's: a pair crosses a step inward,
RELEASE = int(events.EventKind.RELEASE)  # outward, or is reflected at it)
BOUNCE = int(events.EventKind.BOUNCE)

#: Why :func:`run` returned: :class:`hardspheres.events.StopReason`'s numbers.
STOP_UNTIL = int(events.StopReason.UNTIL)
STOP_MAX_EVENTS = int(events.StopReason.MAX_EVENTS)
STOP_MAX_COLLISIONS = int(events.StopReason.MAX_COLLISIONS)
STOP_RECORD_FULL = int(events.StopReason.RECORD_FULL)

# ---- the arrays -------------------------------------------------------------------
# The engine (hardspheres.core.engine.Engine) owns them, under the same names; per
# sphere i (N rows each):
#
#   masses     float64 (N,)              [mass]
#   spheres    float64 (N, SPHERE_COLS)  one 64-byte row: centre and velocity
#                                        at the sphere's own time, that time, radius
#   due        float64 (N, DUE_COLS)     when its next event and its shell crossing are due
#   book       int64   (N, BOOK_COLS)    bookkeeping: course changes, cell, the
#                                        predicted event, heap position, list length,
#                                        input index (ORIGIN)
#   shells     float64 (N, SHELL_COLS)   shell centre and reach
#   neighbours int32   (N, cap)          neighbour list: 32 j + image code (see _pair_code)
#   images     int64   (N, 3)            crossings of the periodic box per axis
#   cell_next, cell_prev  int32 (N,)     the doubly linked list of the cell of its shell centre
#
# and for the whole system:
#
#   cell_head  int32   (ncx ncy ncz,)    first sphere of each cell (-1: empty)
#   heap       int32   (N,)              the calendar's current bucket: spheres by heap
#   heap_t, heap_key                     position, with the entry's time and tie key beside
#   calendar   int32   (NB + 1 + 3N,)    the calendar's later buckets: first sphere of each
#                                        bucket's list, then of the overflow list (-1: empty),
#                                        then per sphere its links (CAL_NEXT, CAL_PREV, CAL_BUCKET:
#                                        its list's slot)
#   scalars    float64 (N_SCALARS,)      clock, geometry, running totals (F_*)
#   counts     int64   (N_COUNTS,)       grid size and event counts (C_*)
#   scratch    int32   (2N + 2,)         work space (refresh_window, _relist)
#   axes       ((),) * d                 the dimension, as a type: d = len(axes), 2 or 3
#   hit_t      float64 (N,) or (0,)      inelastic rule: each sphere's time of its last
#                                        collision or reflection (-inf: none yet; the TC
#                                        model's clock); (0,) and never read when elastic
#   rule       () or ((),)               the collision rule, as a type: elastic (), or
#                                        inelastic ((),), len(rule) == 1
#
# The dimension is a compile-time constant: ``len(axes)`` of a tuple of d
# empty tuples is folded by numba, so every ``if len(axes) == 3`` below
# decides when the machine code is made, and each d gets a loop of its own
# (compiled on first use of that d).  In 2-D no z term is formed and z is
# never read: the stored z and vz are 0 and stay so; there is one layer of
# cells (9 around a disk, no third layer), and the image code of a pair
# has z digit 0 (no shift).
#
# The collision rule is a compile-time variant too (granular gases): ``rule``
# is ``()`` for elastic spheres and ``((),)`` for inelastic ones, and
# ``len(rule) == 1`` is folded like ``len(axes)``.  Only :func:`run` reads it
# (a collision's and a reflection's velocity change); the elastic loop's
# machine code is that of before, and the inelastic loop has its own:
# restitution ``F_RESTITUTION`` between spheres and ``F_WALL_RESTITUTION``
# at the container's wall, the TC model (a collision or reflection less
# than ``F_TC`` after either sphere's previous one, ``hit_t``, is elastic:
# Luding and McNamara, Granular Matter 1, 113 (1998)), and the energy
# dissipated summed in ``F_DISSIPATED``.  Predictions do not depend on the
# rule.  The inelastic loop also runs the thermal wall (a heated container,
# ``F_WALL_KT > 0``): a sphere meeting the wall is re-emitted with a velocity
# drawn at that temperature (physics.thermal_wall; draw ``C_WALL_DRAWS`` of
# the counter-based generator seeded ``C_WALL_SEED``), the energy it gains
# summed in ``F_WALL_HEAT``.


#: The order in which :func:`build`, :func:`run`, :func:`refresh_window` and
#: :func:`kick` take the arrays above, as one plain tuple (the engine's
#: ``Engine.arrays``).  One argument rather than 16; a plain tuple, as numba
#: types it about as fast as 16 arrays and unpacks it at no cost per event,
#: where a named tuple cost 3-4 us more per call (benchmarks/core_call.py,
#: benchmarks/README.md "the core's arguments").
ARRAYS = (
    "spheres",
    "masses",
    "book",
    "due",
    "shells",
    "neighbours",
    "cell_head",
    "cell_next",
    "cell_prev",
    "heap",
    "heap_t",
    "heap_key",
    "scalars",
    "counts",
    "scratch",
    "images",
    "calendar",
    "axes",
    "hit_t",
    "rule",
)


# columns of `spheres`
X, Y, Z, VX, VY, VZ = 0, 1, 2, 3, 4, 5  # centre and velocity at T_OWN
T_OWN = 6  # the sphere's own time: of its last collision or reflection (or rebase)
RADIUS = 7  # radius at the time origin (see F_GROW)
SPHERE_COLS = 8
# columns of `due`
EVENT_T = 0  # time of the predicted collision or reflection (inf: none)
CROSS_T = 1  # time it leaves its shell (inf: never)
DUE_COLS = 2
# columns of `shells`
SHELL_X, SHELL_Y, SHELL_Z = 0, 1, 2  # shell centre: the sphere's centre when it was last listed
REACH = 3  # the radius its neighbour list is made for (>= its radius until the next build)
SHELL_COLS = 4
# columns of `book`
CHANGES = 0  # collisions and reflections (and kicks) so far: a prediction's stamp
CELL_X, CELL_Y, CELL_Z = 1, 2, 3  # cell coordinates of its shell centre
CELL = 4  # cell index, (CELL_Z * ncy + CELL_Y) * ncx + CELL_X (nc per axis: C_GRID)
EVENT_KEY = 5  # tie key of the predicted event (see _key)
EVENT_KIND = 6  # its kind: REFLECTION, COLLISION or NONE
PARTNER = 7  # its partner (-1 for a reflection or none)
PARTNER_CHANGES = 8  # the partner's CHANGES when predicted (stale if it moved on)
CROSS_FACE = 9  # cells: which face it leaves by, 2 * axis + (1 up, 0 down); -1 none
# (neighbour lists: BOX_FACE + that code when it next leaves the periodic box before its shell)
FRESH = 10  # C_SERIAL when last predicted (refresh_window predicts once per serial)
HEAP_POS = 11  # position of the sphere's entry in the heap
NEIGHBOURS = 12  # lists: length of its neighbour list (the first entries of its row)
# its input index: the engine keeps the spheres in an order of its own (near
# in space, near in memory); tie keys, a collision's a - b and the event record
# are on input indices, never on i (here, in a row the event touches anyway)
ORIGIN = 13
BOOK_COLS = 14
# the stepped variant (``len(axes[1]) == 1``): each sphere's species in its
# book row at SPECIES, and its bond table from BONDS on: the count, then
# ``partner << 3 | state`` for each partner in a step (state 1..K, the edges
# the pair is inside; the partner an engine index, renamed when the spheres
# are reordered)
SPECIES = BOOK_COLS
BONDS = BOOK_COLS + 1
# a stepped prediction's partner carries its kind above bit KIND_SHIFT (_store)
KIND_SHIFT = 29
#: CROSS_FACE of a sphere (neighbour lists) that leaves the periodic box before its shell
BOX_FACE = 8

# indices into `scalars`
F_CLOCK = 0  # time of the last processed event (relative to the origin)
F_ANCHOR = 1  # time of the last collision or reflection
F_CONTAINER = 2  # container radius (0 for a periodic box)
F_BOX = 3  # periodic box edge (0 for a spherical container)
F_LO = 4  # grid origin (lower corner) per axis
F_W = 5  # cell width
F_WINDOW = 6  # simultaneity window
F_WALL_IMPULSE = 7  # sum of impulse magnitudes delivered to the wall
F_VIRIAL = 8  # sum over collisions of r_ij . dp_i
# transport tallies (periodic box; 6 tensor components in the order xx yy zz xy xz yz)
F_VIR_T = 9  # collisional virial tensor, sum over collisions of r_ij dp_i
F_KIN_T = 15  # kinetic tensor now, sum_i m_i v_i v_i
F_KIN_INT = 21  # its time integral up to F_T_KIN
F_T_KIN = 27  # time the integrals were last brought up to date
F_HEAT_COLL = 28  # heat Helfand moment, collisional part: sum over collisions of r_ij dE_i
F_HEAT_KIN = 31  # energy current now, sum_i v_i E_i (E_i = m_i v_i^2 / 2)
F_HEAT_INT = 34  # its time integral up to F_T_KIN
F_OFFSET = 37  # absolute time of the time origin (the engine's offset)
F_STREAK = 38  # time of the first event of the current C_FROZEN streak
F_GROW = 39  # growth: radius_i(t) = R_i (1 + F_GROW t), t from the origin (0: off)
F_SHELL = 40  # neighbour distance over the sum of two reaches (> 1; 1.5 unless the box is small)
F_HEADROOM = 41  # reach over radius at a build (> 1 while growing: room to grow)
F_BUCKET_RATE = 42  # the calendar: buckets per unit time (one over a bucket's width)
# per axis (x, y, z): F_BOX, F_LO and F_W above are the x axis's (F_BOX != 0: periodic)
F_EDGE = 43  # periodic box side per axis (0 for a spherical container)
F_LOW = 46  # grid origin (lower corner) per axis
F_WIDTH = 49  # cell width per axis
# the inelastic rule (read only by the inelastic variant; 1, 1, 0 for elastic spheres)
F_RESTITUTION = 52  # normal restitution coefficient between spheres, 0 < e <= 1
F_WALL_RESTITUTION = 53  # the container wall's
F_TC = 54  # the TC model's duration: a collision this soon after either sphere's last is elastic
F_DISSIPATED = 55  # kinetic energy dissipated by inelastic collisions and reflections so far
F_WALL_KT = 56  # the thermal wall's temperature (energy; 0: not a thermal wall; inelastic variant only)
F_WALL_HEAT = 57  # kinetic energy the thermal wall gave the spheres so far (negative: took)
# Lees-Edwards shear (read only by the sheared variant, ``len(axes[0]) == 1``; 0, 0 otherwise)
F_SHEAR = 58  # the boundary speed w = g L_y: the images across the upper y face move at +w along x
F_SHEAR0 = 59  # the offset at the time origin, in [0, L_x]: delta(t) = (F_SHEAR0 + w t) % L_x
F_SHEAR_G = 60  # the shear rate g (w = g L_y)
F_PEC_INT = 61  # the time integral of sum m c c (c = v - g y e_x) over the closed flights (xx yy zz xy xz yz)
# steps (the stepped variant), per pair of species (s, t): from F_STEP + (s SPECIES_MAX + t) STEP_STRIDE,
# the number of steps K_st, then lambda_k and U_k for k = 0..K_st - 1, outermost first
F_NSTEP = 67  # the most steps of any pair (0: hard spheres, not the stepped variant)
F_NSPECIES = 68  # the species
F_STEP = 69
STEP_MAX = 4
SPECIES_MAX = 4
STEP_STRIDE = 1 + 2 * STEP_MAX
N_SCALARS = F_STEP + SPECIES_MAX * SPECIES_MAX * STEP_STRIDE

# indices into `counts`
C_CELLS = 0  # cells per axis (nc)
C_COLLISIONS = 1  # collisions processed
C_REFLECTIONS = 2  # reflections processed
C_CROSSINGS = 3  # shell crossings processed (neighbour lists made anew)
C_STALE = 4  # stale predictions discarded
C_SERIAL = 5  # collisions and reflections processed (freshness stamps)
C_FROZEN = 6  # collisions and reflections in a row with the clock not advancing
C_REFRESHED = 7  # predictions made afresh by the window rule (refresh_window)
C_HEAP_SIZE = 8  # the calendar: entries in the heap (the current bucket)
C_BUCKET = 9  # the current bucket (floor of time * F_BUCKET_RATE)
C_QUEUED = 10  # entries in the buckets' lists (not the heap, not the overflow)
C_GRID = 11  # cells per axis (x, y, z); C_CELLS is the x axis's
C_WALL_SEED = 14  # the thermal wall's generator: its seed (0 <= seed < 2^32)
C_WALL_DRAWS = 15  # ... and the draws made so far (the next draw's number)
C_STEP_EVENTS = 16  # the stepped variant: captures, releases and bounces so far
N_COUNTS = 19

# stop reasons of run() beyond 0..3 (see its docstring)
STOP_FROZEN = int(events.StopReason.FROZEN)
STOP_SLIDING = int(events.StopReason.SLIDING)
STOP_LISTS_FULL = 6  # the core's own: a neighbour list would overflow (the engine widens them)
STOP_BONDS_FULL = 7  # the core's own: a bond table would overflow (the engine widens them)


# ---- the calendar: buckets of time and a binary heap of the current one ----------
# An O(1) event calendar (Paul, J. Comput. Phys. 221, 615 (2007)): time is cut
# into buckets of width 1 / F_BUCKET_RATE; each sphere's entry (the earlier of
# its event and its crossing) sits in the bucket of its time.  Only the current
# bucket (C_BUCKET) is ordered, in an indexed binary heap (heap, heap_t,
# heap_key by heap position, C_HEAP_SIZE entries); the later buckets are
# unordered doubly linked lists whose heads are `calendar`'s first NB entries (bucket b in slot b mod NB, NB a power of two:
# a year of NB buckets); entries a year or more ahead (and those that never
# happen) wait in the overflow list (`calendar`'s last entry) and come into the
# year as it moves on.  Every entry outside the heap is later than every
# entry in it (the bucket of a time never decreases with the time), so
# heap[0] is the earliest entry overall, in the same (time, tie key) order as
# one heap over all spheres: the order of events does not depend on the
# calendar.  The heap is never empty while there are spheres (_refill).

# per sphere i, after the heads: calendar[NB + 1 + 3 i + CAL_NEXT, CAL_PREV, CAL_BUCKET]
CAL_NEXT, CAL_PREV = 0, 1  # next and previous sphere in its bucket's list
CAL_BUCKET = 2  # its list's slot: 0..NB-1 a bucket of the year, NB the overflow list (CAL_HEAP: in the heap)
CAL_HEAP = -1  # CAL_BUCKET of an entry in the heap (the current bucket)
# a current bucket past every finite time: one plain heap.  2^52: bucket
# numbers (and a year past them) stay exact as doubles, so comparing them with
# floor(t * rate) is exact (at 4e18 a year of 2 buckets rounded away)
CAL_ALL = 1 << 52
CAL_BUCKETS_PER_SPHERE = 2  # buckets in a year per sphere (rounded up to a power of two)


@_inline
def _year(calendar, book):
    """Buckets in the calendar's year (NB)."""
    return calendar.shape[0] - 1 - 3 * book.shape[0]


@_inline
def _sift_up(heap, heap_t, heap_key, book, k):
    i, t, key = np.int64(heap[k]), heap_t[k], heap_key[k]
    while k > 0:
        parent = (k - 1) >> 1
        tp = heap_t[parent]
        if t < tp or (t == tp and key < heap_key[parent]):
            p = np.int64(heap[parent])
            heap[k], heap_t[k], heap_key[k] = p, tp, heap_key[parent]
            book[p, HEAP_POS] = k
            k = parent
        else:
            break
    heap[k], heap_t[k], heap_key[k] = i, t, key
    book[i, HEAP_POS] = k


@_inline
def _sift_down(heap, heap_t, heap_key, book, k, n):
    i, t, key = np.int64(heap[k]), heap_t[k], heap_key[k]
    while True:
        child = 2 * k + 1
        if child >= n:
            break
        tc, kc = heap_t[child], heap_key[child]
        if child + 1 < n:
            t2, k2 = heap_t[child + 1], heap_key[child + 1]
            if t2 < tc or (t2 == tc and k2 < kc):
                child += 1
                tc, kc = t2, k2
        if tc < t or (tc == t and kc < key):
            jc = np.int64(heap[child])
            heap[k], heap_t[k], heap_key[k] = jc, tc, kc
            book[jc, HEAP_POS] = k
            k = child
        else:
            break
    heap[k], heap_t[k], heap_key[k] = i, t, key
    book[i, HEAP_POS] = k


@_inline
def _entry(due, book, i, n):
    """Sphere ``i``'s calendar entry: the earlier of its event and its crossing, ``(t, key)``."""
    cross_key = _key(CROSSING, book[i, ORIGIN], -1, n)
    if due[i, CROSS_T] < due[i, EVENT_T] or (
        due[i, CROSS_T] == due[i, EVENT_T] and cross_key < book[i, EVENT_KEY]
    ):
        return due[i, CROSS_T], cross_key
    return due[i, EVENT_T], book[i, EVENT_KEY]


@_inline
def _resift(heap, heap_t, heap_key, book, k, size):
    """Restore the heap order around position ``k`` after its entry changed."""
    t, key = heap_t[k], heap_key[k]
    if k > 0 and (t < heap_t[(k - 1) >> 1] or (t == heap_t[(k - 1) >> 1] and key < heap_key[(k - 1) >> 1])):
        _sift_up(heap, heap_t, heap_key, book, k)
    else:
        _sift_down(heap, heap_t, heap_key, book, k, size)


@_inline
def _file(heap, heap_t, heap_key, calendar, book, scalars, counts, i, t, key):
    """File sphere ``i`` (in neither heap nor list) under time ``t``."""
    nb = _year(calendar, book)
    cur = counts[C_BUCKET]
    fb = np.floor(t * scalars[F_BUCKET_RATE])
    if fb <= cur or cur == CAL_ALL:  # (CAL_ALL: every entry, even later ones, in the heap)
        k = counts[C_HEAP_SIZE]
        counts[C_HEAP_SIZE] = k + 1
        heap[k], heap_t[k], heap_key[k] = i, t, key
        calendar[nb + 1 + 3 * i + CAL_BUCKET] = CAL_HEAP
        _sift_up(heap, heap_t, heap_key, book, k)
        return
    if fb < cur + nb:  # (NaN: overflow)
        slot = np.int64(fb) & (nb - 1)
        counts[C_QUEUED] += 1
    else:
        slot = nb  # the overflow list
    calendar[nb + 1 + 3 * i + CAL_BUCKET] = slot
    h = np.int64(calendar[slot])
    calendar[nb + 1 + 3 * i + CAL_NEXT] = h
    calendar[nb + 1 + 3 * i + CAL_PREV] = -1
    if h >= 0:
        calendar[nb + 1 + 3 * h + CAL_PREV] = i
    calendar[slot] = i


@_inline
def _unlink(calendar, book, counts, i):
    """Take sphere ``i`` out of its bucket's (or the overflow) list."""
    nb = _year(calendar, book)
    slot = np.int64(calendar[nb + 1 + 3 * i + CAL_BUCKET])
    if slot != nb:
        counts[C_QUEUED] -= 1
    p, q = np.int64(calendar[nb + 1 + 3 * i + CAL_PREV]), np.int64(calendar[nb + 1 + 3 * i + CAL_NEXT])
    if p >= 0:
        calendar[nb + 1 + 3 * p + CAL_NEXT] = q
    else:
        calendar[slot] = q
    if q >= 0:
        calendar[nb + 1 + 3 * q + CAL_PREV] = p


@_inline
def _take_overflow(heap, heap_t, heap_key, calendar, due, book, scalars, counts, everything):
    """Move the overflow entries within a year of the current bucket (or all) into the calendar."""
    nb = _year(calendar, book)
    n = book.shape[0]
    limit = counts[C_BUCKET] + nb
    rate = scalars[F_BUCKET_RATE]
    i = np.int64(calendar[nb])
    while i >= 0:
        nxt = np.int64(calendar[nb + 1 + 3 * i + CAL_NEXT])
        t, key = _entry(due, book, i, n)
        if everything or np.floor(t * rate) < limit:
            _unlink(calendar, book, counts, i)
            if everything:
                k = counts[C_HEAP_SIZE]
                counts[C_HEAP_SIZE] = k + 1
                heap[k], heap_t[k], heap_key[k] = i, t, key
                calendar[nb + 1 + 3 * i + CAL_BUCKET] = CAL_HEAP
                _sift_up(heap, heap_t, heap_key, book, k)
            else:
                _file(heap, heap_t, heap_key, calendar, book, scalars, counts, i, t, key)
        i = nxt


@_inline
def _refill(heap, heap_t, heap_key, calendar, due, book, scalars, counts):
    """While the heap is empty: on to the next bucket, its list into the heap."""
    nb = _year(calendar, book)
    n = book.shape[0]
    while counts[C_HEAP_SIZE] == 0 and n > 0:
        if counts[C_QUEUED] == 0:
            # the year is empty: on to the overflow's earliest bucket (or,
            # if nothing will ever happen, everything into the heap)
            rate = scalars[F_BUCKET_RATE]
            first = np.inf
            i = np.int64(calendar[nb])
            while i >= 0:
                t, key = _entry(due, book, i, n)
                fb = np.floor(t * rate)
                if fb < first:
                    first = fb
                i = np.int64(calendar[nb + 1 + 3 * i + CAL_NEXT])
            if first < CAL_ALL:
                counts[C_BUCKET] = np.int64(first)
                _take_overflow(heap, heap_t, heap_key, calendar, due, book, scalars, counts, False)
            else:
                # (and from now on every entry into the heap: one plain heap
                # until the next requeue)
                counts[C_BUCKET] = CAL_ALL
                _take_overflow(heap, heap_t, heap_key, calendar, due, book, scalars, counts, True)
            continue
        cur = counts[C_BUCKET] + 1
        counts[C_BUCKET] = cur
        if (cur & (nb - 1)) == 0:
            # a new year: the overflow entries that fall in it come in
            _take_overflow(heap, heap_t, heap_key, calendar, due, book, scalars, counts, False)
        slot = cur & (nb - 1)
        i = np.int64(calendar[slot])
        calendar[slot] = -1
        while i >= 0:
            nxt = np.int64(calendar[nb + 1 + 3 * i + CAL_NEXT])
            counts[C_QUEUED] -= 1
            t, key = _entry(due, book, i, n)
            k = counts[C_HEAP_SIZE]
            counts[C_HEAP_SIZE] = k + 1
            heap[k], heap_t[k], heap_key[k] = i, t, key
            calendar[nb + 1 + 3 * i + CAL_BUCKET] = CAL_HEAP
            _sift_up(heap, heap_t, heap_key, book, k)
            i = nxt


@_inline
def _schedule(heap, heap_t, heap_key, calendar, due, book, scalars, counts, i):
    """Sphere ``i``'s calendar entry becomes the earlier of its event and its crossing."""
    n = book.shape[0]
    nb = _year(calendar, book)
    t, key = _entry(due, book, i, n)
    if calendar[nb + 1 + 3 * i + CAL_BUCKET] == CAL_HEAP:
        k = book[i, HEAP_POS]
        if np.floor(t * scalars[F_BUCKET_RATE]) <= counts[C_BUCKET]:
            # still in the current bucket: moved within the heap
            heap_t[k] = t
            heap_key[k] = key
            _resift(heap, heap_t, heap_key, book, k, counts[C_HEAP_SIZE])
            return
        # out of the heap: its last entry takes the place
        last = counts[C_HEAP_SIZE] - 1
        counts[C_HEAP_SIZE] = last
        if k != last:
            j = np.int64(heap[last])
            heap[k], heap_t[k], heap_key[k] = j, heap_t[last], heap_key[last]
            book[j, HEAP_POS] = k
            _resift(heap, heap_t, heap_key, book, k, last)
    else:
        _unlink(calendar, book, counts, i)
    _file(heap, heap_t, heap_key, calendar, book, scalars, counts, i, t, key)
    _refill(heap, heap_t, heap_key, calendar, due, book, scalars, counts)


@_jit
def requeue(heap, heap_t, heap_key, calendar, due, book, scalars, counts, per_bucket, rate):
    """The calendar made anew from the predictions (``due``, ``book``).

    Buckets ``1 / rate`` wide if ``rate > 0``, else so wide that about
    ``per_bucket`` entries come due in one (from the mean time of the finite
    entries ahead of the clock).  ``calendar``: :func:`calendar_size`.
    """
    n = book.shape[0]
    nb = _year(calendar, book)
    clock = scalars[F_CLOCK]
    total = 0.0
    finite = 0
    for i in range(n):
        t, key = _entry(due, book, i, n)
        if t < np.inf and t > clock:
            total += t - clock
            finite += 1
    if rate > 0.0:
        pass
    elif finite > 0 and total > 0.0:
        rate = finite * finite / (per_bucket * total)
    else:
        rate = 1.0
    if not (rate > 0.0 and rate < 1e300):
        rate = 1.0
    scalars[F_BUCKET_RATE] = rate
    fc = np.floor(clock * rate)
    counts[C_BUCKET] = np.int64(fc) if abs(fc) < CAL_ALL else CAL_ALL
    counts[C_HEAP_SIZE] = 0
    counts[C_QUEUED] = 0
    for s in range(nb + 1):
        calendar[s] = -1
    for i in range(n):
        t, key = _entry(due, book, i, n)
        _file(heap, heap_t, heap_key, calendar, book, scalars, counts, i, t, key)
    _refill(heap, heap_t, heap_key, calendar, due, book, scalars, counts)


def calendar_size(n):
    """Entries of the ``calendar`` array for ``n`` spheres.

    A power of two buckets and the overflow list (their heads), then three
    links per sphere (kept here, 24 bytes apart, rather than in ``book``'s
    wide rows: fewer cache misses where N is large).
    """
    nb = 1
    while nb < CAL_BUCKETS_PER_SPHERE * n:
        nb *= 2
    return nb + 1 + 3 * n


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
def _cell_step(k, o, nc, box):
    """Cell coordinate ``k + o`` along one axis (``o`` in -1..1).

    Returns ``(coordinate, shift, exists)``: in a periodic box the
    coordinate wraps, and ``shift`` (-box, 0 or box) moves a centre in the
    wrapped cell next to cell ``k``; in a container a cell past the grid
    does not exist.
    """
    m = k + o
    if m < 0:
        return m + nc, -box, box != 0.0
    if m >= nc:
        return m - nc, box, box != 0.0
    return m, 0.0, True


@_inline
def _block_cell(kx, ky, kz, q, ncx, ncy, ncz, bx, by, bz):
    """Cell ``q`` (0..26, z slowest) of the 3x3x3 block around cell ``(kx, ky, kz)``; -1: none.

    ``ncx, ncy, ncz``: cells per axis; ``bx, by, bz`` != 0: periodic along
    that axis (in 2-D, z is one layer of cells, not periodic: 9 cells).
    """
    nz, _, zthere = _cell_step(kz, q // 9 - 1, ncz, bz)
    ny, _, ythere = _cell_step(ky, (q // 3) % 3 - 1, ncy, by)
    nx, _, xthere = _cell_step(kx, q % 3 - 1, ncx, bx)
    if zthere and ythere and xthere:
        return (nz * ncy + ny) * ncx + nx
    return -1


@_inline
def _block_range(axes):
    """The cells ``q`` of the 3x3x3 block to visit: all 27, or in 2-D the middle layer's 9.

    In 2-D there is one layer of cells and no box along z: only ``q`` in
    9..17 (z offset 0) are looked at.
    """
    if len(axes) == 2:
        return 9, 18
    return 0, 27


@_inline
def _cell_insert(cell_head, cell_next, cell_prev, book, i, ncx, ncy):
    """Sphere ``i`` into the cell its book names (``CELL_X``, ``CELL_Y``, ``CELL_Z``)."""
    cell = (book[i, CELL_Z] * ncy + book[i, CELL_Y]) * ncx + book[i, CELL_X]
    book[i, CELL] = cell
    h = np.int64(cell_head[cell])
    cell_next[i] = h
    cell_prev[i] = -1
    if h >= 0:
        cell_prev[h] = i
    cell_head[cell] = i


@_inline
def _cell_remove(cell_head, cell_next, cell_prev, book, i):
    cell = book[i, CELL]
    a, b = np.int64(cell_prev[i]), np.int64(cell_next[i])
    if a >= 0:
        cell_next[a] = b
    else:
        cell_head[cell] = b
    if b >= 0:
        cell_prev[b] = a


# ---- predictions ---------------------------------------------------------------


@_inline
def _crossing(spheres, book, due, scalars, counts, i, t, axes):
    """Store the time sphere ``i`` leaves its cell, from time ``t`` (cell mode)."""
    box = scalars[F_BOX]
    dt_i = t - spheres[i, T_OWN]
    best = np.inf
    code = -1
    # periodic box: the box's faces are the sphere's own, at the time
    # _box_exit gives (looked at only from the cells along them)
    wrap_t = np.inf
    wrap_code = -1
    for ax in range(len(axes)):
        lo, w, nc = scalars[F_LOW + ax], scalars[F_WIDTH + ax], counts[C_GRID + ax]
        v = spheres[i, VX + ax]
        k = book[i, CELL_X + ax]
        x = spheres[i, X + ax] + v * dt_i
        if v > 0.0:
            if k == nc - 1:
                edge = scalars[F_EDGE + ax]
                if edge != 0.0:
                    tw = spheres[i, T_OWN] + ((lo + edge) - spheres[i, X + ax]) / v
                    if tw < wrap_t:
                        wrap_t, wrap_code = tw, 2 * ax + 1
                continue
            d = (lo + (k + 1) * w - x) / v
            up = 1
        elif v < 0.0:
            if k == 0:
                if box != 0.0 and scalars[F_EDGE + ax] != 0.0:
                    tw = spheres[i, T_OWN] + (lo - spheres[i, X + ax]) / v
                    if tw < wrap_t:
                        wrap_t, wrap_code = tw, 2 * ax
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
    due[i, CROSS_T] = t + best
    book[i, CROSS_FACE] = code
    if wrap_code >= 0:
        if wrap_t < t:
            wrap_t = t
        if wrap_t < due[i, CROSS_T]:
            due[i, CROSS_T] = wrap_t
            book[i, CROSS_FACE] = wrap_code


@_inline
def _box_exit(spheres, shells, scalars, i, t, axes):
    """When and where sphere ``i``'s centre next leaves the periodic box, if before its shell.

    Returns ``(time, face)``, ``face = 2 * axis + (1 up, 0 down)``, or
    ``(inf, -1)`` where no face is within its shell (neighbour lists: it
    leaves its shell first).  The time is the sphere's own, from its
    stored centre and time alone (``t_i + (face - x_i) / v``), never before
    ``t``: the brute-force reference moves its centre by one box side at
    the same instant, so both keep the same centres bit for bit
    (:mod:`hardspheres.core.reference`, :func:`~hardspheres.core.reference.box_exit`).
    The cells' :func:`_crossing` computes the same times.
    """
    best = np.inf
    code = -1
    delta = (scalars[F_SHELL] - 1.0) * shells[i, REACH] * (1.0 + 1e-9)
    for ax in range(len(axes)):
        edge = scalars[F_EDGE + ax]
        v = spheres[i, VX + ax]
        if edge == 0.0 or v == 0.0:
            continue
        lo = scalars[F_LOW + ax]
        near = shells[i, SHELL_X + ax]
        if (near + delta < lo + edge) if v > 0.0 else (near - delta > lo):
            continue  # (the face is beyond its shell)
        if v > 0.0:
            tw = spheres[i, T_OWN] + ((lo + edge) - spheres[i, X + ax]) / v
            up = 1
        else:
            tw = spheres[i, T_OWN] + (lo - spheres[i, X + ax]) / v
            up = 0
        if tw < best:
            best = tw
            code = 2 * ax + up
    if best < t:
        best = t
    return best, code


@_inline
def _shell_exit(spheres, shells, due, scalars, i, t, axes):
    """Store the time sphere ``i`` leaves its shell, from time ``t``.

    The shell is the ball of radius ``(F_SHELL - 1) * reach`` around the
    sphere's shell centre; inf if it stands still or has no reach.
    """
    delta = (scalars[F_SHELL] - 1.0) * shells[i, REACH]
    dt_i = t - spheres[i, T_OWN]
    dx = (spheres[i, X] + spheres[i, VX] * dt_i) - shells[i, SHELL_X]
    dy = (spheres[i, Y] + spheres[i, VY] * dt_i) - shells[i, SHELL_Y]
    vx, vy = spheres[i, VX], spheres[i, VY]
    if len(axes) == 3:
        dz = (spheres[i, Z] + spheres[i, VZ] * dt_i) - shells[i, SHELL_Z]
        vz = spheres[i, VZ]
        a = vx * vx + vy * vy + vz * vz
        b = dx * vx + dy * vy + dz * vz
        c = delta * delta - (dx * dx + dy * dy + dz * dz)  # >= 0 inside (up to rounding)
    else:
        a = vx * vx + vy * vy
        b = dx * vx + dy * vy
        c = delta * delta - (dx * dx + dy * dy)
    if not (a > 0.0 and delta > 0.0):
        due[i, CROSS_T] = np.inf
        return
    if c <= 0.0:
        due[i, CROSS_T] = t
        return
    # the positive root of a tau^2 + 2 b tau - c = 0, without cancellation
    q = np.sqrt(b * b + a * c)
    if b >= 0.0:
        tau = c / (b + q)
    else:
        tau = (q - b) / a
    due[i, CROSS_T] = t + tau


@_inline
def _pair(
    spheres,
    book,
    i,
    oi,
    j,
    sx,
    sy,
    sz,
    shifted,
    ti,
    now,
    soon,
    clock,
    grow,
    one,
    n,
    best_t,
    best_key,
    best_p,
    vs,
    axes,
):
    """Sphere ``i``'s best event so far improved with the pair ``(i, j)``.

    Longer than 80 lines: the innermost loop's body, its branch-free
    pre-test and the comments that say why each expression is as it is.

    ``j`` seen at its image shifted by ``(sx, sy, sz)`` (``shifted``: not
    all zero), moving ``vs`` faster along x (a sheared box's image across a
    y face, ``ky w``; read only by the sheared variant); ``oi`` is ``i``'s
    input index (``book[i, ORIGIN]``: tie keys are on input indices);
    returns the new ``(best_t, best_key, best_p)``.
    """
    tj = spheres[j, T_OWN]
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
    horizon = (best_t - t0) + 4.5e-16 * abs(best_t) if best_t >= soon else np.inf
    planar = len(axes) == 2  # (a constant: 2-D reads and forms no z)
    xi = spheres[i, X] + spheres[i, VX] * di
    yi = spheres[i, Y] + spheres[i, VY] * di
    xj = spheres[j, X] + spheres[j, VX] * dj
    yj = spheres[j, Y] + spheres[j, VY] * dj
    zi = zj = dz = dvz = 0.0
    if not planar:
        zi = spheres[i, Z] + spheres[i, VZ] * di
        zj = spheres[j, Z] + spheres[j, VZ] * dj
    if not shifted:
        # (no shift added: xj + 0.0 differs from xj only in the sign of a
        # zero, and so would dx; no time the kernels give depends on the
        # sign of a zero difference, docs/numerics.md "Signed zeros")
        dx = xi - xj
        dy = yi - yj
        if not planar:
            dz = zi - zj
    elif oi > book[j, ORIGIN]:
        # across the periodic box the subtraction is not antisymmetric:
        # the lower input index minus the higher's image, negated (the
        # reference's arithmetic, whichever sphere predicts the pair)
        dx = -(xj - (xi - sx))
        dy = -(yj - (yi - sy))
        if not planar:
            dz = -(zj - (zi - sz))
    else:
        dx = xi - (xj + sx)
        dy = yi - (yj + sy)
        if not planar:
            dz = zi - (zj + sz)
    if len(axes[0]) == 1 and shifted:
        # sheared: the image moves vs faster along x; formed as the
        # reference forms it for the lower input index, negated if i is higher
        if oi > book[j, ORIGIN]:
            dvx = -(spheres[j, VX] - (spheres[i, VX] - vs))
        else:
            dvx = spheres[i, VX] - (spheres[j, VX] + vs)
    else:
        dvx = spheres[i, VX] - spheres[j, VX]
    dvy = spheres[i, VY] - spheres[j, VY]
    if not planar:
        dvz = spheres[i, VZ] - spheres[j, VZ]
    sigma = spheres[i, RADIUS] + spheres[j, RADIUS]
    if grow != 0.0:
        # growing (the one branch a plain run pays here)
        dt = pair_time_grow(
            dx, dy, dz, dvx, dvy, dvz, sigma * (1.0 + grow * t0), sigma * grow, horizon, planar
        )
    # pair_time_within's own tests up to the root,
    # the same expressions, combined without branches (half
    # the pairs recede, at random, and a branch on that
    # mispredicts half the time): a pair they reject is
    # inf for it too.  The rest, NaNs and the pairs it
    # rescales (|dv|^2 |dr|^2 out of range) go through it.
    # The miss test is b^2 - a c < 0 by a margin that
    # covers its rounding and that of the kernel's own
    # discriminant (physics.MISS_MARGIN).
    if planar:
        b = dx * dvx + dy * dvy
        a = dvx * dvx + dvy * dvy
        r2 = dx * dx + dy * dy
    else:
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
    # decides; below RANGE_LO, b may underflow, and a
    # |dv|^2 or |dr|^2 below SQUARES_LO may be subnormal:
    # the kernel rescales those)
    if grow != 0.0:
        pass
    elif (
        (ar2 < physics.RANGE_LO)
        | (a < physics.SQUARES_LO)
        | (r2 < physics.SQUARES_LO)
        | ((recede ^ True) & (touch | ((beyond ^ True) & (miss ^ True))))
    ):
        dt = pair_time_within(dx, dy, dz, dvx * one, dvy * one, dvz * one, sigma, horizon, planar)
    else:
        dt = np.inf
    if dt < np.inf:
        te = t0 + dt
        if te < soon:
            te = now
        if te < clock:
            te = clock  # a root rounded into the past
        if te <= best_t:
            oj = book[j, ORIGIN]
            kk = _key(COLLISION, min(oi, oj), max(oi, oj), n)
            if te < best_t or kk < best_key:
                best_t, best_key, best_p = te, kk, j
    return best_t, best_key, best_p


@_inline
def _store(due, book, i, best_t, best_key, best_p, axes):
    if best_p >= 0:
        due[i, EVENT_T] = best_t
        book[i, EVENT_KEY] = best_key
        if len(axes[1]) == 1:
            # stepped: the partner carries the pair event's kind
            p = best_p & ((1 << KIND_SHIFT) - 1)
            book[i, EVENT_KIND] = best_p >> KIND_SHIFT
            book[i, PARTNER] = p
            book[i, PARTNER_CHANGES] = book[p, CHANGES]
            return
        book[i, EVENT_KIND] = COLLISION
        book[i, PARTNER] = best_p
        book[i, PARTNER_CHANGES] = book[best_p, CHANGES]


@_inline
def _bond_state(book, i, j):
    """The stepped variant: the state of the pair ``(i, j)`` (0: outside every step), from ``i``'s table."""
    for q in range(book[i, BONDS]):
        e = book[i, BONDS + 1 + q]
        if (e >> 3) == j:
            return e & 7
    return 0


@_inline
def _bond_set(book, i, j, state):
    """The stepped variant: set the pair's state in ``i``'s table (0: remove it; swap-remove)."""
    cnt = book[i, BONDS]
    for q in range(cnt):
        if (book[i, BONDS + 1 + q] >> 3) == j:
            if state == 0:
                book[i, BONDS + 1 + q] = book[i, BONDS + cnt]
                book[i, BONDS + cnt] = 0
                book[i, BONDS] = cnt - 1
            else:
                book[i, BONDS + 1 + q] = (j << 3) | state
            return
    if state != 0:
        book[i, BONDS + 1 + cnt] = (j << 3) | state
        book[i, BONDS] = cnt + 1


@_inline
def _steps_of(book, i, j):
    """Where the steps of the pair ``(i, j)``'s species begin among the scalars (at their count)."""
    return F_STEP + (book[i, SPECIES] * SPECIES_MAX + book[j, SPECIES]) * STEP_STRIDE


@_inline
def _step_energy(scalars, base, state):
    """The potential energy of a pair in ``state`` (0: outside every step), its steps from ``base``."""
    return 0.0 if state == 0 else scalars[base + 2 * state]


@_inline
def _pair_stepped(
    spheres,
    book,
    scalars,
    i,
    oi,
    j,
    sx,
    sy,
    sz,
    shifted,
    ti,
    now,
    soon,
    clock,
    n,
    best_t,
    best_key,
    best_p,
    axes,
):
    """The stepped variant's :func:`_pair`: the pair's next event by its state (the reference's ``pair_step_time``).

    Longer than 80 lines: :func:`_pair`'s image arithmetic written out again
    (the hard-sphere kernel stays as it is), then the state's edges.

    The inner edge from outside (the core, ``COLLISION``, in the innermost
    state; else the next step in, ``CAPTURE``) with ``pair_time``; when the
    chord misses it, the outer edge from inside (``RELEASE``) with
    ``pair_time_out``.  All pair events tie as collisions; the returned
    partner carries the kind above bit ``KIND_SHIFT``.
    """
    tj = spheres[j, T_OWN]
    t0 = ti if ti > tj else tj
    di = t0 - ti
    dj = t0 - tj
    planar = len(axes) == 2
    xi = spheres[i, X] + spheres[i, VX] * di
    yi = spheres[i, Y] + spheres[i, VY] * di
    xj = spheres[j, X] + spheres[j, VX] * dj
    yj = spheres[j, Y] + spheres[j, VY] * dj
    zi = zj = dz = dvz = 0.0
    if not planar:
        zi = spheres[i, Z] + spheres[i, VZ] * di
        zj = spheres[j, Z] + spheres[j, VZ] * dj
    if not shifted:
        dx = xi - xj
        dy = yi - yj
        if not planar:
            dz = zi - zj
    elif oi > book[j, ORIGIN]:
        dx = -(xj - (xi - sx))
        dy = -(yj - (yi - sy))
        if not planar:
            dz = -(zj - (zi - sz))
    else:
        dx = xi - (xj + sx)
        dy = yi - (yj + sy)
        if not planar:
            dz = zi - (zj + sz)
    dvx = spheres[i, VX] - spheres[j, VX]
    dvy = spheres[i, VY] - spheres[j, VY]
    if not planar:
        dvz = spheres[i, VZ] - spheres[j, VZ]
    sigma = spheres[i, RADIUS] + spheres[j, RADIUS]
    state = _bond_state(book, i, j)
    base = _steps_of(book, i, j)
    if state == np.int64(scalars[base]):
        inner = sigma
        kind = COLLISION
    else:
        inner = scalars[base + 1 + 2 * state] * sigma
        kind = CAPTURE
    dt = pair_time(dx, dy, dz, dvx, dvy, dvz, inner, planar)
    if not dt < np.inf:
        if state == 0:
            return best_t, best_key, best_p
        dt = wall_time(dx, dy, dz, dvx, dvy, dvz, scalars[base + 1 + 2 * (state - 1)] * sigma, planar)
        kind = RELEASE
    te = t0 + dt
    if te < soon:
        te = now
    if te < clock:
        te = clock  # a root rounded into the past
    if te <= best_t:
        oj = book[j, ORIGIN]
        kk = _key(COLLISION, min(oi, oj), max(oi, oj), n)
        if te < best_t or kk < best_key:
            best_t, best_key, best_p = te, kk, j | (np.int64(kind) << KIND_SHIFT)
    return best_t, best_key, best_p


# ---- gates: a variant's code reached through an argument, so that numba
# drops it before typing from the other variants (it folds len() of an
# argument, not of an entry of one): their first compilation stays as short
# as before the variants came
@_inline
def _stepped_gate(
    pot,
    spheres,
    book,
    scalars,
    i,
    oi,
    j,
    sx,
    sy,
    sz,
    shifted,
    ti,
    now,
    soon,
    clock,
    n,
    best_t,
    best_key,
    best_p,
    axes,
):
    """:func:`_pair_stepped` in the stepped variant (``pot = ((),)``); nothing in the others."""
    if len(pot) == 1:
        return _pair_stepped(
            spheres, book, scalars, i, oi, j, sx, sy, sz, shifted, ti, now, soon, clock, n, best_t, best_key, best_p,
            axes,
        )  # fmt: skip
    return best_t, best_key, best_p


@_inline
def _step_gate(pot, masses, book, scalars, counts, a, b, kind, dx, dy, dz, dvx, dvy, dvz, planar):
    """The stepped variant: the pair at a step's edge crosses it or bounces back (the reference's steps).

    Returns ``(k1, k2, kind)``: the velocity factors and the event's kind
    (``CAPTURE``, ``RELEASE`` or ``BOUNCE``), or kind -1 (the pair slides
    along the edge: nothing to change) or -2 (a bond table is full: the
    engine widens them); nothing changed then.
    """
    if len(pot) != 1:
        return 0.0, 0.0, COLLISION
    old = _bond_state(book, a, b)
    new = old + 1 if kind == CAPTURE else old - 1
    base = _steps_of(book, a, b)
    du = _step_energy(scalars, base, new) - _step_energy(scalars, base, old)
    k1, k2, crossed = cross_step(masses[a], masses[b], dx, dy, dz, dvx, dvy, dvz, du, planar)
    if not crossed:
        return k1, k2, (-1 if k1 == 0.0 else BOUNCE)
    width = book.shape[1] - BONDS - 1
    if old == 0 and (book[a, BONDS] >= width or book[b, BONDS] >= width):
        return k1, k2, -2
    _bond_set(book, a, b, new)
    _bond_set(book, b, a, new)
    return k1, k2, kind


@_inline
def _scan_start(spheres, book, due, scalars, i):
    """What a scan of sphere ``i``'s pairs starts from.

    Returns ``(now, soon, clock, grow, best_t, best_key, t_i)``: the anchor,
    the end of its window, the clock, the growth rate, the sphere's event so
    far (time and tie key) and its own time.
    """
    now = scalars[F_ANCHOR]
    return (
        now,
        now + scalars[F_WINDOW],
        scalars[F_CLOCK],
        scalars[F_GROW],
        due[i, EVENT_T],
        book[i, EVENT_KEY],
        spheres[i, T_OWN],
    )


# image code -> box edges per axis: code = 9 (sx + 1) + 3 (sy + 1) + (sz + 1)
# (a table: decoding the code by division cost about 30 instructions per pair)
_IMAGE_STEPS = np.array([[a - 1.0, b - 1.0, c - 1.0] for a in range(3) for b in range(3) for c in range(3)])


@_inline
def _scan_list(spheres, book, due, neighbours, scalars, i, axes):
    """Improve sphere ``i``'s stored event with the pairs of its neighbour list."""
    n = spheres.shape[0]
    bx, by, bz = scalars[F_EDGE], scalars[F_EDGE + 1], scalars[F_EDGE + 2]
    now, soon, clock, grow, best_t, best_key, ti = _scan_start(spheres, book, due, scalars, i)
    best_p = -1
    # exactly 1.0, but not to the compiler: it would otherwise see that the
    # kernel's own first test (receding: inf) decides both branches below
    # and test it first again, on its own
    one = 1.0 if n > 0 else 2.0
    oi = book[i, ORIGIN]
    for q in range(book[i, NEIGHBOURS]):
        _prefetch(spheres, neighbours[i, q] >> 5)
    for q in range(book[i, NEIGHBOURS]):
        entry = neighbours[i, q]
        j = entry >> 5
        code = entry & 31
        # the image of j next to i (periodic box): -1, 0, 1 box edges per axis
        sx = _IMAGE_STEPS[code, 0] * bx
        sy = _IMAGE_STEPS[code, 1] * by
        sz = _IMAGE_STEPS[code, 2] * bz if len(axes) == 3 else 0.0
        if len(axes[1]) == 1:
            best_t, best_key, best_p = _stepped_gate(
                axes[1], spheres, book, scalars, i, oi, j, sx, sy, sz, code != 13, ti, now, soon, clock, n,
                best_t, best_key, best_p, axes,
            )  # fmt: skip
        else:
            best_t, best_key, best_p = _pair(
                spheres,
                book,
                i,
                oi,
                j,
                sx,
                sy,
                sz,
                code != 13,
                ti,
                now,
                soon,
                clock,
                grow,
                one,
                n,
                best_t,
                best_key,
                best_p,
                0.0,
                axes,
            )
    _store(due, book, i, best_t, best_key, best_p, axes)


@_inline
def _cell_near(k, o, nc):
    """Cell coordinate ``k + o`` along one axis (``o`` in -1..1), and whether it is in the grid.

    The cells this side of the box alone (no wrap): those across a
    periodic box's face are :func:`_scan_across`'s.
    """
    m = k + o
    return m, m >= 0 and m < nc


@_inline
def _scan_cells(
    spheres, book, due, cell_head, cell_next, scalars, counts, i, zlo, zhi, ylo, yhi, xlo, xhi, axes
):
    """Improve sphere ``i``'s stored event with the pairs in a block of cells.

    Longer than 80 lines: the pair kernel's call written out, argument by
    argument, and the test for the cells across the box.

    The block is given by offsets from ``i``'s cell, e.g. -1..1 on every
    axis for the full 27 cells.  The cells this side of the box here, with
    no shift at all (a container has no others); in a periodic box, those
    across its faces (a sphere in a cell along a face) in
    :func:`_scan_across`, called rather than inlined: the pair kernel's
    shifted arithmetic costs the loop here nothing, not even a flag.
    """
    n = spheres.shape[0]
    ncx, ncy, ncz = counts[C_GRID], counts[C_GRID + 1], counts[C_GRID + 2]
    now, soon, clock, grow, best_t, best_key, ti = _scan_start(spheres, book, due, scalars, i)
    best_p = -1
    cx0, cy0, cz0 = book[i, CELL_X], book[i, CELL_Y], book[i, CELL_Z]
    one = 1.0 if ncx > 0 else 2.0  # (see _scan_list)
    oi = book[i, ORIGIN]
    # the sphere's own layer and row first: the earliest event is mostly
    # there, and the pairs after it are rejected by the horizon.  One layer
    # of cells along z (disks): that layer alone, the 9 cells around a
    # disk's (the layers above and below do not exist this side of the box,
    # and there is no box along z)
    layers = 1 if len(axes) == 2 else zhi - zlo + 1
    for qz in range(layers):
        oz = 0 if len(axes) == 2 else (zlo if zlo == zhi else (qz if qz < 2 else -1))
        nz, there = _cell_near(cz0, oz, ncz)
        if not there:
            continue
        for qy in range(yhi - ylo + 1):
            oy = ylo if ylo == yhi else (qy if qy < 2 else -1)
            ny, there = _cell_near(cy0, oy, ncy)
            if not there:
                continue
            for ox in range(xlo, xhi + 1):
                nx, there = _cell_near(cx0, ox, ncx)
                if not there:
                    continue
                j = np.int64(cell_head[(nz * ncy + ny) * ncx + nx])
                while j >= 0:
                    if j != i and len(axes[1]) == 1:
                        best_t, best_key, best_p = _stepped_gate(
                            axes[1], spheres, book, scalars, i, oi, j, 0.0, 0.0, 0.0, False, ti, now, soon, clock,
                            n, best_t, best_key, best_p, axes,
                        )  # fmt: skip
                    elif j != i:
                        best_t, best_key, best_p = _pair(
                            spheres,
                            book,
                            i,
                            oi,
                            j,
                            0.0,
                            0.0,
                            0.0,
                            False,
                            ti,
                            now,
                            soon,
                            clock,
                            grow,
                            one,
                            n,
                            best_t,
                            best_key,
                            best_p,
                            0.0,
                            axes,
                        )
                    j = np.int64(cell_next[j])
    if scalars[F_BOX] != 0.0 and (
        (cx0 == 0 and xlo < 0)
        or (cx0 == ncx - 1 and xhi > 0)
        or (cy0 == 0 and ylo < 0)
        or (cy0 == ncy - 1 and yhi > 0)
        or (len(axes) == 3 and ((cz0 == 0 and zlo < 0) or (cz0 == ncz - 1 and zhi > 0)))
    ):
        # a cell of the block lies across the periodic box
        best_t, best_key, best_p = _scan_across(
            spheres,
            book,
            due,
            cell_head,
            cell_next,
            scalars,
            counts,
            i,
            zlo,
            zhi,
            ylo,
            yhi,
            xlo,
            xhi,
            now,
            soon,
            clock,
            grow,
            one,
            best_t,
            best_key,
            best_p,
            axes[0],
            axes[1],
            axes,
        )
    _store(due, book, i, best_t, best_key, best_p, axes)


@_jit_inner
def _scan_across(
    spheres,
    book,
    due,
    cell_head,
    cell_next,
    scalars,
    counts,
    i,
    zlo,
    zhi,
    ylo,
    yhi,
    xlo,
    xhi,
    now,
    soon,
    clock,
    grow,
    one,
    best_t,
    best_key,
    best_p,
    flow,
    pot,
    axes,
):
    """:func:`_scan_cells`'s cells across the periodic box: sphere ``i``'s best event so far improved.

    Longer than 80 lines: the pair kernel's call written out, argument by
    argument, and the hand-off of a sheared box's rows across a y face.

    The cells of the block whose coordinate wraps along some axis, each
    centre in them seen at its image next to ``i`` (shifted by a box side
    per wrapped axis); returns the new ``(best_t, best_key, best_p)``.
    Which cells a scan looks at first does not change its result (the
    earliest event by time and tie key).
    """
    n = spheres.shape[0]
    ncx, ncy, ncz = counts[C_GRID], counts[C_GRID + 1], counts[C_GRID + 2]
    bx, by, bz = scalars[F_EDGE], scalars[F_EDGE + 1], scalars[F_EDGE + 2]
    cx0, cy0, cz0 = book[i, CELL_X], book[i, CELL_Y], book[i, CELL_Z]
    ti = spheres[i, T_OWN]
    oi = book[i, ORIGIN]
    strip = False  # (sheared: a row across a y face is the strip's, below)
    for oz in range(0, 1) if len(axes) == 2 else range(zlo, zhi + 1):
        nz, sz, there = _cell_step(cz0, oz, ncz, bz)
        if not there:
            continue
        across_z = nz != cz0 + oz
        for oy in range(ylo, yhi + 1):
            ny, sy, there = _cell_step(cy0, oy, ncy, by)
            if not there:
                continue
            if len(flow) == 1 and ny != cy0 + oy:
                strip = True
                continue
            across = across_z or ny != cy0 + oy
            for ox in range(xlo, xhi + 1):
                nx, sx, there = _cell_step(cx0, ox, ncx, bx)
                if not there or not (across or nx != cx0 + ox):
                    continue  # (this side of the box: _scan_cells's)
                j = np.int64(cell_head[(nz * ncy + ny) * ncx + nx])
                while j >= 0:
                    if j != i and len(pot) == 1:
                        best_t, best_key, best_p = _stepped_gate(
                            pot, spheres, book, scalars, i, oi, j, sx, sy, sz, True, ti, now, soon, clock,
                            n, best_t, best_key, best_p, axes,
                        )  # fmt: skip
                    elif j != i:
                        best_t, best_key, best_p = _pair(
                            spheres,
                            book,
                            i,
                            oi,
                            j,
                            sx,
                            sy,
                            sz,
                            True,
                            ti,
                            now,
                            soon,
                            clock,
                            grow,
                            one,
                            n,
                            best_t,
                            best_key,
                            best_p,
                            0.0,
                            axes,
                        )
                    j = np.int64(cell_next[j])
    if len(flow) == 1 and strip:
        best_t, best_key, best_p = _strip_gate(
            flow,
            spheres, book, due, cell_head, cell_next, scalars, counts, i, now, soon, clock, one, best_t, best_key,
            best_p, axes,
        )  # fmt: skip
    return best_t, best_key, best_p


@_inline
def _strip_gate(
    flow, spheres, book, due, cell_head, cell_next, scalars, counts, i, now, soon, clock, one, best_t, best_key, best_p,
    axes,
):  # fmt: skip
    """:func:`_scan_strip` in the sheared variant (``flow = ((),)``); nothing in the others."""
    if len(flow) == 1:
        return _scan_strip(
            spheres, book, due, cell_head, cell_next, scalars, counts, i, now, soon, clock, one, best_t, best_key,
            best_p, axes,
        )  # fmt: skip
    return best_t, best_key, best_p


@_jit_inner
def _scan_strip(
    spheres,
    book,
    due,
    cell_head,
    cell_next,
    scalars,
    counts,
    i,
    now,
    soon,
    clock,
    one,
    best_t,
    best_key,
    best_p,
    axes,
):
    """A sheared box: sphere ``i`` (in the first or last row of cells along y) against the strip across the face.

    Longer than 80 lines: the reference's choice of images, written out.

    The images across a y face slide along x with no event, so a sphere in
    a boundary row looks at every cell of the opposite row (the three
    layers around its own along z), as DynamO's sheared cells do, each
    centre there at every image along x that can come within contact from
    the clock to the earlier of its best event so far and its next
    crossing (where it is predicted afresh): the reference's images
    (:func:`hardspheres.core.reference.next_event_sheared`), swept over the
    core's own bound.  A superset of the images that can meet first, so the
    earliest event, and every bit, is the reference's.  Returns the new
    ``(best_t, best_key, best_p)``.
    """
    n = spheres.shape[0]
    planar = len(axes) == 2
    ncx, ncy, ncz = counts[C_GRID], counts[C_GRID + 1], counts[C_GRID + 2]
    lx, ly, lz = scalars[F_EDGE], scalars[F_EDGE + 1], scalars[F_EDGE + 2]
    w = scalars[F_SHEAR]
    cy0, cz0 = book[i, CELL_Y], book[i, CELL_Z]
    # i in the first row: the strip is the last row's, seen below the box (ky = -1)
    ky = -1 if cy0 == 0 else 1
    ny = ncy - 1 if cy0 == 0 else 0
    sy = ky * ly
    vs = ky * w
    ti = spheres[i, T_OWN]
    oi = book[i, ORIGIN]
    until = best_t if best_t < due[i, CROSS_T] else due[i, CROSS_T]
    for oz in range(0, 1) if planar else range(-1, 2):
        nz, sz, there = _cell_step(cz0, oz, ncz, lz)
        if not there:
            continue
        for nx in range(ncx):
            j = np.int64(cell_head[(nz * ncy + ny) * ncx + nx])
            while j >= 0:
                tj = spheres[j, T_OWN]
                t0 = ti if ti > tj else tj
                di, dj = t0 - ti, t0 - tj
                xi = spheres[i, X] + spheres[i, VX] * di
                xj = spheres[j, X] + spheres[j, VX] * dj
                dy0 = (spheres[i, Y] + spheres[i, VY] * di) - ((spheres[j, Y] + spheres[j, VY] * dj) + sy)
                dvx = spheres[i, VX] - (spheres[j, VX] + vs)
                dvy = spheres[i, VY] - spheres[j, VY]
                dvz = 0.0 if planar else spheres[i, VZ] - spheres[j, VZ]
                sigma = spheres[i, RADIUS] + spheres[j, RADIUS]
                bound = (until if until > soon else soon) - t0
                if bound < 0.0:
                    bound = 0.0
                j_next = np.int64(cell_next[j])
                if abs(dy0) > (sigma + abs(dvy) * bound) * (1.0 + 1e-9):
                    j = j_next
                    continue
                delta = (scalars[F_SHEAR0] + w * t0) % lx
                base = ky * delta
                start = clock - t0 if clock > t0 else 0.0
                span = bound
                if span == np.inf:
                    if dvy != 0.0:
                        span = (abs(dy0) + sigma) / abs(dvy) * (1.0 + 1e-9)
                    if not planar and dvz != 0.0:
                        dz0 = abs(
                            (spheres[i, Z] + spheres[i, VZ] * di) - (spheres[j, Z] + spheres[j, VZ] * dj)
                        )
                        dz0 = dz0 if dz0 < lz - dz0 else lz - dz0
                        tz = (dz0 + sigma) / abs(dvz) * (1.0 + 1e-9)
                        span = tz if tz < span else span
                    if span == np.inf and dvx != 0.0:
                        span = start + (2.0 * lx + 2.0 * sigma) / abs(dvx)
                if span < start:
                    j = j_next
                    continue  # out of reach along y or z before the clock, for good
                u0 = (xi - (xj + base)) / lx
                ua = u0 + (dvx * start) / lx if dvx != 0.0 else u0
                ub = u0 + (dvx * span) / lx if dvx != 0.0 else u0
                lo = ua if ua < ub else ub
                hi = ub if ua < ub else ua
                margin = sigma / lx * (1.0 + 1e-9)
                for kx in range(int(np.floor(lo - margin)) - 1, int(np.ceil(hi + margin)) + 2):
                    sx = kx * lx + base
                    dx = xi - (xj + sx)
                    if abs(dx) > (sigma + abs(dvx) * bound) * (1.0 + 1e-9):
                        continue
                    best_t, best_key, best_p = _pair(
                        spheres, book, i, oi, j, sx, sy, sz, True, ti, now, soon, clock, 0.0, one, n, best_t,
                        best_key, best_p, vs, axes,
                    )  # fmt: skip
                j = j_next
    return best_t, best_key, best_p


@_inline
def predict(spheres, book, due, shells, neighbours, cell_head, cell_next, scalars, counts, i, t, axes):
    """Find sphere ``i``'s earliest collision or reflection and its next crossing.

    Against its neighbours and leaving its shell (``F_SHELL > 0``), or
    against the 27 cells around it and leaving its cell.

    A collision or reflection less than the simultaneity window after the
    anchor (the last collision or reflection) is put at the anchor itself:
    it happens now.  Does not touch the heap.
    """
    n = spheres.shape[0]
    due[i, EVENT_T] = np.inf
    book[i, EVENT_KEY] = _key(NONE, n, n - 1, n)
    book[i, EVENT_KIND] = NONE
    book[i, PARTNER] = -1
    if scalars[F_BOX] == 0.0:
        # the wall, from the sphere's own time
        # (wall_time is wall_time_grow at growth 0: the same bits without growth)
        grow = scalars[F_GROW]
        dt = wall_time_grow(
            spheres[i, X],
            spheres[i, Y],
            spheres[i, Z],
            spheres[i, VX],
            spheres[i, VY],
            spheres[i, VZ],
            scalars[F_CONTAINER] - spheres[i, RADIUS] * (1.0 + grow * spheres[i, T_OWN]),
            spheres[i, RADIUS] * grow,
            len(axes) == 2,
        )
        if dt < np.inf:
            te = spheres[i, T_OWN] + dt
            if te < scalars[F_ANCHOR] + scalars[F_WINDOW]:
                te = scalars[F_ANCHOR]
            if te < scalars[F_CLOCK]:
                te = scalars[F_CLOCK]
            due[i, EVENT_T] = te
            book[i, EVENT_KEY] = _key(REFLECTION, book[i, ORIGIN], -1, n)
            book[i, EVENT_KIND] = REFLECTION
    if scalars[F_SHELL] > 0.0:
        _scan_list(spheres, book, due, neighbours, scalars, i, axes)
        _shell_exit(spheres, shells, due, scalars, i, t, axes)
        if scalars[F_BOX] != 0.0:
            # leaving the periodic box, if before its shell (CROSS_FACE >= 0)
            wrap_t, wrap_code = _box_exit(spheres, shells, scalars, i, t, axes)
            book[i, CROSS_FACE] = -1
            if wrap_t < due[i, CROSS_T]:
                due[i, CROSS_T] = wrap_t
                book[i, CROSS_FACE] = BOX_FACE + wrap_code
    elif len(axes[0]) == 1:
        # sheared: the crossing first (the strip's images are swept up to it)
        _crossing(spheres, book, due, scalars, counts, i, t, axes)
        _scan_cells(spheres, book, due, cell_head, cell_next, scalars, counts, i, -1, 1, -1, 1, -1, 1, axes)
    else:
        _scan_cells(spheres, book, due, cell_head, cell_next, scalars, counts, i, -1, 1, -1, 1, -1, 1, axes)
        _crossing(spheres, book, due, scalars, counts, i, t, axes)


@_jit_inner
def predict_one(spheres, book, due, shells, neighbours, cell_head, cell_next, scalars, counts, i, t, axes):
    """:func:`predict`, called rather than inlined: for the callers outside the event loop.

    (Each inlined copy holds both scans and costs compile time.)
    """
    predict(spheres, book, due, shells, neighbours, cell_head, cell_next, scalars, counts, i, t, axes)


@_inline
def _close_flight(spheres, masses, scalars, i, t, axes):
    """Sheared: sphere ``i``'s flight, from its own time to ``t``, added to the peculiar kinetic integral.

    Along the flight ``c_x = v_x - g y(s)`` falls linearly, so ``int m c c
    ds`` is a polynomial in the flight's length (the reference's
    ``peculiar_segment``; called before the sphere's velocity or centre
    changes: a collision, a crossing of a y face, a kick, a rebase).
    """
    tau = t - spheres[i, T_OWN]
    if tau == 0.0:
        return
    g = scalars[F_SHEAR_G]
    vx, vy = spheres[i, VX], spheres[i, VY]
    vz = 0.0 if len(axes) == 2 else spheres[i, VZ]
    cx = vx - g * spheres[i, Y]
    sl = g * vy
    mt = masses[i] * tau
    scalars[F_PEC_INT] += mt * (cx * cx - sl * cx * tau + sl * sl * tau * tau / 3.0)
    scalars[F_PEC_INT + 1] += mt * vy * vy
    scalars[F_PEC_INT + 2] += mt * vz * vz
    half = cx - 0.5 * sl * tau
    scalars[F_PEC_INT + 3] += mt * half * vy
    scalars[F_PEC_INT + 4] += mt * half * vz
    scalars[F_PEC_INT + 5] += mt * vy * vz


@_inline
def _offset(scalars, t):
    """A sheared box's Lees-Edwards offset at time ``t`` (from the origin): the reference's arithmetic."""
    return (scalars[F_SHEAR0] + scalars[F_SHEAR] * t) % scalars[F_EDGE]


@_inline
def _wrap_gate(flow, spheres, masses, book, images, scalars, counts, i, t, step, axes):
    """:func:`_wrap_sheared` in the sheared variant (``flow = ((),)``); nothing in the others."""
    if len(flow) == 1:
        _wrap_sheared(spheres, masses, book, images, scalars, counts, i, t, step, axes)


@_jit_inner
def _wrap_sheared(spheres, masses, book, images, scalars, counts, i, t, step, axes):
    """A sheared box: sphere ``i`` leaves through a y face (``step`` +1: the upper) at its time ``t``.

    Moved to ``t`` (its own time), then by ``-step L_y`` in y and ``-step
    delta(t)`` in x (then into the box along x, whole sides), and its
    ``v_x`` by ``-step w``: the reference's ``_cross_sheared``, the same
    arithmetic.  Its x cell is found afresh (the caller sets its y cell and
    relinks it) and its terms of the kinetic tallies are swapped, as a kick's.
    """
    dtk = t - scalars[F_T_KIN]
    for q in range(6):
        scalars[F_KIN_INT + q] += scalars[F_KIN_T + q] * dtk
    for q in range(len(axes)):
        scalars[F_HEAT_INT + q] += scalars[F_HEAT_KIN + q] * dtk
    scalars[F_T_KIN] = t
    _kinetic_terms(scalars, masses[i], spheres[i, VX], spheres[i, VY], spheres[i, VZ], -1.0, axes)
    _close_flight(spheres, masses, scalars, i, t, axes)
    _advance(spheres, i, t, axes)
    lx = scalars[F_EDGE]
    off = _offset(scalars, t)
    spheres[i, Y] -= step * scalars[F_EDGE + 1]
    spheres[i, X] -= step * off
    spheres[i, VX] -= step * scalars[F_SHEAR]
    images[i, 1] += step
    m = np.floor((spheres[i, X] - scalars[F_LOW]) / lx)
    if m != 0.0:
        spheres[i, X] -= m * lx
        images[i, 0] += np.int64(m)
    book[i, CELL_X] = cell_of(spheres[i, X], scalars[F_LOW], scalars[F_WIDTH], counts[C_GRID])
    _kinetic_terms(scalars, masses[i], spheres[i, VX], spheres[i, VY], spheres[i, VZ], 1.0, axes)


@_inline
def _advance(spheres, i, t, axes):
    dt = t - spheres[i, T_OWN]
    spheres[i, X] += spheres[i, VX] * dt
    spheres[i, Y] += spheres[i, VY] * dt
    if len(axes) == 3:
        spheres[i, Z] += spheres[i, VZ] * dt
    spheres[i, T_OWN] = t


@_inline
def _pair_code(scalars, shells, i, j, axes):
    """Image code of ``j`` next to ``i`` (periodic box), and whether their shells are neighbours.

    The code is ``9 (kx + 1) + 3 (ky + 1) + (kz + 1)`` with ``j``'s image
    shifted by ``k`` box edges per axis (the minimum image of the shell
    centres); neighbours: shell centres nearer than ``F_SHELL`` times the
    sum of the two reaches (a hair more, for rounding).
    """
    code = 0
    r2 = 0.0
    for ax in range(len(axes)):
        box = scalars[F_EDGE + ax]
        half = 0.5 * box
        d = shells[i, SHELL_X + ax] - shells[j, SHELL_X + ax]
        k = 0
        if box != 0.0:
            if d > half:
                k = 1
                d -= box
            elif d < -half:
                k = -1
                d += box
        code = 3 * code + (k + 1)
        r2 += d * d
    if len(axes) == 2:
        code = 3 * code + 1  # (no shift along z)
    cut = scalars[F_SHELL] * (shells[i, REACH] + shells[j, REACH]) * (1.0 + 1e-9)
    return code, r2 < cut * cut


@_inline
def _set_shell(
    spheres, shells, book, cell_head, cell_next, cell_prev, images, scalars, counts, i, t, insert, axes
):
    """Sphere ``i``'s shell centre becomes its centre at ``t``, in its cell.

    In a periodic box the centre is in the box (up to rounding: it moves by
    a side when it leaves, :func:`_box_exit`); ``insert``: the sphere is in
    no cell list yet.
    """
    dt = t - spheres[i, T_OWN]
    for ax in range(len(axes)):
        lo, w, nc = scalars[F_LOW + ax], scalars[F_WIDTH + ax], counts[C_GRID + ax]
        x = spheres[i, X + ax] + spheres[i, VX + ax] * dt
        shells[i, SHELL_X + ax] = x
        book[i, CELL_X + ax] = cell_of(x, lo, w, nc)
    if not insert:
        _cell_remove(cell_head, cell_next, cell_prev, book, i)
    _cell_insert(cell_head, cell_next, cell_prev, book, i, counts[C_GRID], counts[C_GRID + 1])


@_inline
def _nearest(d, box):
    """The difference ``d`` of two centres in the box, to the nearest image."""
    if box != 0.0:
        if d > 0.5 * box:
            return d - box
        if d < -0.5 * box:
            return d + box
    return d


@_inline
def _relist(
    spheres,
    book,
    shells,
    neighbours,
    cell_head,
    cell_next,
    cell_prev,
    images,
    scalars,
    counts,
    scratch,
    i,
    t,
    axes,
):
    """Sphere ``i`` left its shell at ``t``: a new shell, and its neighbour list anew.

    Longer than 80 lines: the candidates' search (its 3-D and 2-D
    distances side by side, the dimension a compile-time constant), then the
    old lists left and the new ones made, in one pass that changes nothing
    if a list would overflow.

    Returns False, changing nothing, if a list would overflow (the engine
    widens the lists and calls again).
    """
    cap = neighbours.shape[1]
    n = spheres.shape[0]
    # the candidates first, into scratch (nothing changes if they do not fit)
    bx, by, bz = scalars[F_EDGE], scalars[F_EDGE + 1], scalars[F_EDGE + 2]
    lx, ly, lz = scalars[F_LOW], scalars[F_LOW + 1], scalars[F_LOW + 2]
    ncx, ncy, ncz = counts[C_GRID], counts[C_GRID + 1], counts[C_GRID + 2]
    dt = t - spheres[i, T_OWN]
    # (in a periodic box the centre is in the box, up to rounding: cell_of clamps)
    cx = spheres[i, X] + spheres[i, VX] * dt
    cy = spheres[i, Y] + spheres[i, VY] * dt
    kx = cell_of(cx, lx, scalars[F_WIDTH], ncx)
    ky = cell_of(cy, ly, scalars[F_WIDTH + 1], ncy)
    cz, kz = 0.0, 0
    if len(axes) == 3:
        cz = spheres[i, Z] + spheres[i, VZ] * dt
        kz = cell_of(cz, lz, scalars[F_WIDTH + 2], ncz)
    found = 0
    cut0 = scalars[F_SHELL] * (1.0 + 1e-9)
    q0, q1 = _block_range(axes)
    for q in range(q0, q1):
        cell = _block_cell(kx, ky, kz, q, ncx, ncy, ncz, bx, by, bz)
        if cell < 0:
            continue
        j = np.int64(cell_head[cell])
        while j >= 0:
            if j != i:
                ddx = _nearest(cx - shells[j, SHELL_X], bx)
                ddy = _nearest(cy - shells[j, SHELL_Y], by)
                if len(axes) == 3:
                    ddz = _nearest(cz - shells[j, SHELL_Z], bz)
                    r2 = ddx * ddx + ddy * ddy + ddz * ddz
                else:
                    r2 = ddx * ddx + ddy * ddy
                cut = cut0 * (shells[i, REACH] + shells[j, REACH])
                if r2 < cut * cut:
                    if found >= cap or book[j, NEIGHBOURS] >= cap:
                        # j's list may already hold i: only a guess, on the safe side
                        return False
                    scratch[found] = j
                    found += 1
            j = np.int64(cell_next[j])
    # nc < 3 in a periodic box would visit a cell twice: guarded by the engine (nc >= 3)
    # i leaves its old neighbours' lists
    for q in range(book[i, NEIGHBOURS]):
        j = neighbours[i, q] >> 5
        m = book[j, NEIGHBOURS]
        for r in range(m):
            if (neighbours[j, r] >> 5) == i:
                neighbours[j, r] = neighbours[j, m - 1]
                book[j, NEIGHBOURS] = m - 1
                break
    _set_shell(
        spheres, shells, book, cell_head, cell_next, cell_prev, images, scalars, counts, i, t, False, axes
    )
    book[i, NEIGHBOURS] = 0
    for q in range(found):
        j = np.int64(scratch[q])
        code, near = _pair_code(scalars, shells, i, j, axes)
        if near:
            neighbours[i, book[i, NEIGHBOURS]] = (j << 5) | code
            book[i, NEIGHBOURS] += 1
            neighbours[j, book[j, NEIGHBOURS]] = (i << 5) | (26 - code)
            book[j, NEIGHBOURS] += 1
    return n >= 0


@_jit
def build(arrays, per_bucket):
    """Cells (and shells and neighbour lists) from the clock, every prediction, the calendar.

    ``per_bucket``: the calendar's entries per bucket (see :func:`requeue`).

    Returns the longest neighbour list (0 without lists); if it is longer
    than ``neighbours.shape[1]``, nothing was predicted: call again with
    wider lists.
    """
    spheres, masses, book, due, shells, neighbours, cell_head, cell_next = arrays[:8]
    cell_prev, heap, heap_t, heap_key, scalars, counts, scratch, images = arrays[8:16]
    calendar, axes = arrays[16], arrays[17]
    n = spheres.shape[0]
    cell_head[:] = -1
    t = scalars[F_CLOCK]
    longest = 0
    if scalars[F_SHELL] == 0.0:
        # cells alone
        for i in range(n):
            # (the centres at t; the stored ones, at their own times, are kept)
            dt = t - spheres[i, T_OWN]
            for ax in range(len(axes)):
                lo, w, nc = scalars[F_LOW + ax], scalars[F_WIDTH + ax], counts[C_GRID + ax]
                book[i, CELL_X + ax] = cell_of(spheres[i, X + ax] + spheres[i, VX + ax] * dt, lo, w, nc)
            _cell_insert(cell_head, cell_next, cell_prev, book, i, counts[C_GRID], counts[C_GRID + 1])
    else:
        longest = _build_lists(
            spheres, book, shells, neighbours, cell_head, cell_next, cell_prev, images, scalars, counts, axes
        )
        if longest > neighbours.shape[1]:
            return longest
    for i in range(n):
        predict_one(spheres, book, due, shells, neighbours, cell_head, cell_next, scalars, counts, i, t, axes)
    requeue(heap, heap_t, heap_key, calendar, due, book, scalars, counts, per_bucket, 0.0)
    return longest


@_inline
def _build_lists(
    spheres, book, shells, neighbours, cell_head, cell_next, cell_prev, images, scalars, counts, axes
):
    """Shells from the clock (in the box), cells by shell centre, every neighbour list.

    Returns the longest list (the lists are only filled up to their width).
    """
    n = spheres.shape[0]
    ncx, ncy, ncz = counts[C_GRID], counts[C_GRID + 1], counts[C_GRID + 2]
    bx, by, bz = scalars[F_EDGE], scalars[F_EDGE + 1], scalars[F_EDGE + 2]
    t = scalars[F_CLOCK]
    grow = scalars[F_GROW]
    rmax = 0.0
    for i in range(n):
        rmax = max(rmax, spheres[i, RADIUS])
    for i in range(n):
        # (the centres stay at their own times: the engine put them in the box)
        # the reach: the radius now with the growth headroom, and no less than
        # half the largest (a sphere of radius 0 still needs a shell)
        shells[i, REACH] = max(spheres[i, RADIUS], 0.5 * rmax) * (1.0 + grow * t) * scalars[F_HEADROOM]
        _set_shell(
            spheres, shells, book, cell_head, cell_next, cell_prev, images, scalars, counts, i, t, True, axes
        )
    cap = neighbours.shape[1]
    longest = 0
    for i in range(n):
        book[i, NEIGHBOURS] = 0
    for i in range(n):
        kx, ky, kz = book[i, CELL_X], book[i, CELL_Y], book[i, CELL_Z]
        q0, q1 = _block_range(axes)
        for q in range(q0, q1):
            cell = _block_cell(kx, ky, kz, q, ncx, ncy, ncz, bx, by, bz)
            if cell < 0:
                continue
            j = np.int64(cell_head[cell])
            while j >= 0:
                if j > i:
                    code, near = _pair_code(scalars, shells, i, j, axes)
                    if near:
                        a, b = book[i, NEIGHBOURS], book[j, NEIGHBOURS]
                        if a < cap and b < cap:
                            neighbours[i, a] = (j << 5) | code
                            neighbours[j, b] = (i << 5) | (26 - code)
                        book[i, NEIGHBOURS] = a + 1
                        book[j, NEIGHBOURS] = b + 1
                        longest = max(longest, a + 1, b + 1)
                j = np.int64(cell_next[j])
    return longest


@_jit
def refresh_window(arrays):
    """Predict afresh, at the clock, every sphere whose event is within the window.

    This is what makes the engine follow the assignment's rule exactly: of
    the events less than ``window`` after the clock, the first in tie order
    happens now, whatever order their earlier predictions put them in.
    The heap is walked from the root, pruning subtrees that start past the
    window, so the cost is proportional to the number refreshed; the
    calendar's later buckets are looked at only if the window reaches them.
    """
    spheres, masses, book, due, shells, neighbours, cell_head, cell_next = arrays[:8]
    cell_prev, heap, heap_t, heap_key, scalars, counts, scratch, images = arrays[8:16]
    calendar, axes = arrays[16], arrays[17]
    n = heap.shape[0]
    if n == 0:
        return
    size = counts[C_HEAP_SIZE]
    t = scalars[F_CLOCK]
    limit = t + scalars[F_WINDOW]
    serial = counts[C_SERIAL]
    top = 0
    found = 0
    if heap_t[0] < limit:
        scratch[0] = 0
        top = 1
    while top > 0:
        top -= 1
        k = np.int64(scratch[top])
        scratch[n + found] = heap[k]
        found += 1
        for child in (2 * k + 1, 2 * k + 2):
            if child < size and heap_t[child] < limit:
                scratch[top] = child
                top += 1
    # the window past the current bucket (rare: a bucket is much wider)
    nb = _year(calendar, book)
    cur = counts[C_BUCKET]
    last = np.floor(limit * scalars[F_BUCKET_RATE])
    if last > cur:
        whole = last >= cur + nb  # (then the overflow too)
        span = nb - 1 if whole else np.int64(last - cur)
        for q in range(span + 1):
            if q < span:
                j = np.int64(calendar[(cur + 1 + q) & (nb - 1)])
            else:
                j = np.int64(calendar[nb]) if whole else -1
            while j >= 0:
                tj, kj = _entry(due, book, j, n)
                if tj < limit:
                    scratch[n + found] = j
                    found += 1
                j = np.int64(calendar[nb + 1 + 3 * j + CAL_NEXT])
    for q in range(found):
        i = np.int64(scratch[n + q])
        if book[i, FRESH] != serial:
            book[i, FRESH] = serial
            counts[C_REFRESHED] += 1
            predict_one(
                spheres, book, due, shells, neighbours, cell_head, cell_next, scalars, counts, i, t, axes
            )
            _schedule(heap, heap_t, heap_key, calendar, due, book, scalars, counts, i)


# ---- transport tallies -----------------------------------------------------------


@_inline
def _kinetic_terms(scalars, m, vx, vy, vz, sign, axes):
    """Add ``sign`` times one sphere's share to the kinetic tensor and energy current now.

    (2-D: the components with z stay 0.)
    """
    scalars[F_KIN_T] += sign * m * vx * vx
    scalars[F_KIN_T + 1] += sign * m * vy * vy
    scalars[F_KIN_T + 3] += sign * m * vx * vy
    if len(axes) == 3:
        scalars[F_KIN_T + 2] += sign * m * vz * vz
        scalars[F_KIN_T + 4] += sign * m * vx * vz
        scalars[F_KIN_T + 5] += sign * m * vy * vz
        e = 0.5 * m * (vx * vx + vy * vy + vz * vz)
    else:
        e = 0.5 * m * (vx * vx + vy * vy)
    scalars[F_HEAT_KIN] += sign * vx * e
    scalars[F_HEAT_KIN + 1] += sign * vy * e
    if len(axes) == 3:
        scalars[F_HEAT_KIN + 2] += sign * vz * e


@_inline
def _transfer(spheres, masses, scalars, a, b, te, dx, dy, dz, k1, k2, axes):
    """Before the velocities of ``a`` and ``b`` change at ``te``: the transport tallies.

    The Helfand moments of momentum (``sum m x v``) and energy (``sum x E``)
    change by free flight, ``int sum m v v dt`` and ``int sum v E dt``,
    integrated exactly here (the sums are constant between collisions), and
    at a collision by ``r_ab dp_a`` and ``r_ab dE_a`` (minimum image:
    the moments' periodic form).  Their growth gives the shear viscosity
    and the thermal conductivity by the Einstein-Helfand route.  Reads the
    velocities only: the caller changes them.
    """
    dtk = te - scalars[F_T_KIN]
    for q in range(6):
        scalars[F_KIN_INT + q] += scalars[F_KIN_T + q] * dtk
    for q in range(len(axes)):
        scalars[F_HEAT_INT + q] += scalars[F_HEAT_KIN + q] * dtk
    scalars[F_T_KIN] = te
    ma, mb = masses[a], masses[b]
    px, py = -ma * k1 * dx, -ma * k1 * dy  # impulse on a
    scalars[F_VIR_T] += dx * px
    scalars[F_VIR_T + 1] += dy * py
    scalars[F_VIR_T + 3] += dx * py
    ax, ay = spheres[a, VX], spheres[a, VY]
    bx, by = spheres[b, VX], spheres[b, VY]
    ax2, ay2 = ax - k1 * dx, ay - k1 * dy
    if len(axes) == 3:
        pz = -ma * k1 * dz
        scalars[F_VIR_T + 2] += dz * pz
        scalars[F_VIR_T + 4] += dx * pz
        scalars[F_VIR_T + 5] += dy * pz
        az, bz = spheres[a, VZ], spheres[b, VZ]
        az2 = az - k1 * dz
        bz2 = bz + k2 * dz
        de = 0.5 * ma * ((ax2 * ax2 + ay2 * ay2 + az2 * az2) - (ax * ax + ay * ay + az * az))
    else:
        az = bz = az2 = bz2 = 0.0
        de = 0.5 * ma * ((ax2 * ax2 + ay2 * ay2) - (ax * ax + ay * ay))
    _kinetic_terms(scalars, ma, ax, ay, az, -1.0, axes)
    _kinetic_terms(scalars, mb, bx, by, bz, -1.0, axes)
    _kinetic_terms(scalars, ma, ax2, ay2, az2, 1.0, axes)
    _kinetic_terms(scalars, mb, bx + k2 * dx, by + k2 * dy, bz2, 1.0, axes)
    scalars[F_HEAT_COLL] += dx * de
    scalars[F_HEAT_COLL + 1] += dy * de
    if len(axes) == 3:
        scalars[F_HEAT_COLL + 2] += dz * de


@_jit
def kinetic_sums(axes, spheres, masses, scalars):
    """Set the kinetic tensor and the energy current from the velocities now."""
    for q in range(6):
        scalars[F_KIN_T + q] = 0.0
    for q in range(3):
        scalars[F_HEAT_KIN + q] = 0.0
    for i in range(spheres.shape[0]):
        _kinetic_terms(scalars, masses[i], spheres[i, VX], spheres[i, VY], spheres[i, VZ], 1.0, axes)


# ---- the event loop ------------------------------------------------------------


@_jit
def run(arrays, until, max_events, max_collisions, buffers, record, flow, pot):
    """Process events in order until one of the limits.

    Longer than 80 lines: the event loop, kept as one compiled function
    with its helpers inlined into it (benchmarks/README.md measures that);
    it is split only where an A/B shows no loss.

    ``flow`` and ``pot`` are ``axes[0]`` and ``axes[1]`` (the sheared and
    stepped variants' markers) as arguments of their own: numba drops the
    branches on them before typing, so each variant's code is typed only in
    its own loop.

    ``arrays`` is the tuple of the engine's arrays in :data:`ARRAYS`'s order; ``buffers`` the tuple of
    :func:`hardspheres.events.empty_buffers` (``rec_t, rec_kind, rec_i,
    rec_j, rec_imp, rec_dp``, one row per event).

    ``images`` ``(N, 3)`` int64 counts each sphere's crossings of the periodic
    box (the image it is in: unwrapped centre = stored centre + images * box).
    ``rec_dp`` ``(cap, 3)`` receives the impulse vector of sphere ``i``.
    In a periodic box each collision also adds to the transport tallies
    (``F_VIR_T`` ... ``F_HEAT_INT``, see :func:`_transfer`).

    Stops before the first event after ``until``, after ``max_events``
    collisions and reflections, or after ``max_collisions`` collisions,
    whichever comes first.  If ``record``, up to ``len(rec_t)`` collisions
    and reflections are recorded (time, kind, i, j, impulse magnitude), and
    the run also stops when the record is full; if not, every event is
    written to the record's first row (a caller that wants no record does
    not sweep the buffer through the cache: about 1 MB per 16384 events)
    and the record does not limit the run.

    Returns:
        ``(done, reason)``: the collisions and reflections processed, and
        a :class:`hardspheres.events.StopReason` number: 0 = ``until`` reached (or nothing will
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
    spheres, masses, book, due, shells, neighbours, cell_head, cell_next = arrays[:8]
    cell_prev, heap, heap_t, heap_key, scalars, counts, scratch, images = arrays[8:16]
    calendar, axes, hit_t, rule = arrays[16], arrays[17], arrays[18], arrays[19]
    planar = len(axes) == 2  # (a constant: see "the arrays")
    rec_t, rec_kind, rec_i, rec_j, rec_imp, rec_dp = buffers
    n = spheres.shape[0]
    if n == 0:
        return 0, STOP_UNTIL
    box = scalars[F_BOX]
    window = scalars[F_WINDOW]
    cap = rec_t.shape[0]
    done = 0
    coll0 = counts[C_COLLISIONS]
    frozen_limit = frozen_limit_of(n)
    while True:
        if done >= max_events:
            return done, STOP_MAX_EVENTS
        if counts[C_COLLISIONS] - coll0 >= max_collisions:
            return done, STOP_MAX_COLLISIONS
        if record and done >= cap:
            return done, STOP_RECORD_FULL
        row = done if record else 0
        i = np.int64(heap[0])
        te = heap_t[0]
        if not te <= until or te == np.inf:  # NaN `until` too
            return done, STOP_UNTIL
        # the spheres to predict afresh after the event (one place for all
        # kinds: the prediction is compiled into this loop only once)
        p0, p1, tp = i, -1, te
        stale = False
        if heap_key[0] != book[i, EVENT_KEY] and scalars[F_SHELL] == 0.0:
            # leaving the cell: not an event of the physics (the clock
            # moves, the anchor of the simultaneity window does not)
            scalars[F_CLOCK] = te
            code = book[i, CROSS_FACE]
            ax = code >> 1
            nc = counts[C_GRID + ax]
            step = 1 if (code & 1) else -1
            k = book[i, CELL_X + ax] + step
            wrap = k < 0 or k >= nc
            if wrap:
                # periodic wrap: shift the stored centre by one box side
                k = (k + nc) % nc
                if len(flow) == 1 and ax == 1:
                    _wrap_gate(flow, spheres, masses, book, images, scalars, counts, i, te, step, axes)
                else:
                    spheres[i, X + ax] -= step * scalars[F_EDGE + ax]
                    images[i, ax] += step
            book[i, CELL_X + ax] = k
            _cell_remove(cell_head, cell_next, cell_prev, book, i)
            _cell_insert(cell_head, cell_next, cell_prev, book, i, counts[C_GRID], counts[C_GRID + 1])
            counts[C_CROSSINGS] += 1
            if wrap:
                # its centre changed (by a side): its predictions and its
                # partners' with it are made anew, from the new centre
                book[i, CHANGES] += 1
                predict_one(
                    spheres, book, due, shells, neighbours, cell_head, cell_next, scalars, counts, i, te, axes
                )
                _schedule(heap, heap_t, heap_key, calendar, due, book, scalars, counts, i)
                continue
            # only the 9 cells that came into reach can hold new partners
            zl = step if ax == 2 else -1
            yl = step if ax == 1 else -1
            xl = step if ax == 0 else -1
            zh = step if ax == 2 else 1
            yh = step if ax == 1 else 1
            xh = step if ax == 0 else 1
            if len(flow) == 1:
                # sheared: the crossing first (the strip's images are swept up to it)
                _crossing(spheres, book, due, scalars, counts, i, te, axes)
            _scan_cells(
                spheres, book, due, cell_head, cell_next, scalars, counts, i, zl, zh, yl, yh, xl, xh, axes
            )
            if len(flow) != 1:
                _crossing(spheres, book, due, scalars, counts, i, te, axes)
            _schedule(heap, heap_t, heap_key, calendar, due, book, scalars, counts, i)
            continue
        if heap_key[0] != book[i, EVENT_KEY]:
            # leaving its shell: not an event of the physics (the clock
            # moves, the anchor of the simultaneity window does not); a new
            # shell and neighbour list, and the sphere predicted afresh.
            # Or leaving the periodic box (CROSS_FACE >= 0): its centre
            # moves by a side first (and back if the list would overflow)
            face = book[i, CROSS_FACE] - BOX_FACE
            ax, step, x_before = 0, 0, 0.0
            if face >= 0:
                ax = face >> 1
                step = 1 if (face & 1) else -1
                x_before = spheres[i, X + ax]
                spheres[i, X + ax] -= step * scalars[F_EDGE + ax]
            if not _relist(
                spheres,
                book,
                shells,
                neighbours,
                cell_head,
                cell_next,
                cell_prev,
                images,
                scalars,
                counts,
                scratch,
                i,
                te,
                axes,
            ):
                if face >= 0:
                    spheres[i, X + ax] = x_before
                return done, STOP_LISTS_FULL
            if face >= 0:
                images[i, ax] += step
                book[i, CHANGES] += 1
            scalars[F_CLOCK] = te
            counts[C_CROSSINGS] += 1
            kind = CROSSING
            stale = True  # (not an event: predict i, then on)
        else:
            kind = book[i, EVENT_KIND]
        if kind == COLLISION or (len(pot) == 1 and kind >= CAPTURE):
            j = book[i, PARTNER]
            if book[j, CHANGES] != book[i, PARTNER_CHANGES]:
                # stale: the partner has changed course since
                counts[C_STALE] += 1
                stale = True
                tp = scalars[F_CLOCK]
        anchor = scalars[F_ANCHOR]
        if not stale and kind != NONE:
            # a collision or reflection: count those in a row during which
            # the clock has not advanced (physics.FROZEN_RELATIVE)
            if te - scalars[F_STREAK] <= physics.FROZEN_RELATIVE * abs(te + scalars[F_OFFSET]):
                if counts[C_FROZEN] >= frozen_limit:
                    return done, STOP_FROZEN
            else:
                counts[C_FROZEN] = 0
                scalars[F_STREAK] = te
        if (kind == COLLISION or (len(pot) == 1 and kind >= CAPTURE)) and not stale:
            clock_before = scalars[F_CLOCK]  # (the stepped variant's, should it stop here)
            counts[C_FROZEN] += 1
            scalars[F_CLOCK] = te
            scalars[F_ANCHOR] = te
            if len(flow) == 1:
                _close_flight(spheres, masses, scalars, i, te, axes)
                _close_flight(spheres, masses, scalars, j, te, axes)
            _advance(spheres, i, te, axes)
            _advance(spheres, j, te, axes)
            # lower input index minus higher (the tie rule's order)
            a, b = (i, j) if book[i, ORIGIN] < book[j, ORIGIN] else (j, i)
            dx = spheres[a, X] - spheres[b, X]
            dy = spheres[a, Y] - spheres[b, Y]
            dz = dvz = 0.0
            if not planar:
                dz = spheres[a, Z] - spheres[b, Z]
            ky = 0.0
            if box != 0.0:
                # the partner may be an image across the box
                # (the sides read here: kept out of the loop's registers)
                bx, by, bz = scalars[F_EDGE], scalars[F_EDGE + 1], scalars[F_EDGE + 2]
                if len(flow) == 1:
                    # sheared: the image across the nearest y face, then along x
                    ky = np.round(dy / by)
                    dy -= by * ky
                    dx -= ky * _offset(scalars, te)
                    dx -= bx * np.round(dx / bx)
                else:
                    dx -= bx * np.round(dx / bx)
                    dy -= by * np.round(dy / by)
                if not planar:
                    dz -= bz * np.round(dz / bz)
            if len(flow) == 1:
                dvx = spheres[a, VX] - (spheres[b, VX] + ky * scalars[F_SHEAR])
            else:
                dvx = spheres[a, VX] - spheres[b, VX]
            dvy = spheres[a, VY] - spheres[b, VY]
            if not planar:
                dvz = spheres[a, VZ] - spheres[b, VZ]
            step_kind = COLLISION
            if len(pot) == 1 and kind != COLLISION:
                # stepped: the pair at a step's edge crosses it or bounces back
                # (the reference's _step_factors and _apply_step)
                k1, k2, step_kind = _step_gate(
                    pot, masses, book, scalars, counts, a, b, kind, dx, dy, dz, dvx, dvy, dvz, planar
                )
                if step_kind < 0:  # the pair slides along the edge, or a bond table is full
                    scalars[F_CLOCK] = clock_before
                    scalars[F_ANCHOR] = anchor
                    return done, STOP_SLIDING if step_kind == -1 else STOP_BONDS_FULL
            elif scalars[F_GROW] != 0.0:
                u = (spheres[a, RADIUS] + spheres[b, RADIUS]) * scalars[F_GROW]
                k1, k2 = collide_grow(masses[a], masses[b], dx, dy, dz, dvx, dvy, dvz, u, planar)
            elif len(rule) == 1:
                # inelastic (a constant: see "the arrays"); the TC model: elastic
                # if either sphere's last collision or reflection is nearer than F_TC
                e = scalars[F_RESTITUTION]
                tc = scalars[F_TC]
                if te - hit_t[a] < tc or te - hit_t[b] < tc:
                    e = 1.0
                k1, k2, lost = collide_inelastic(masses[a], masses[b], dx, dy, dz, dvx, dvy, dvz, e, planar)
                scalars[F_DISSIPATED] += lost
                hit_t[a] = te
                hit_t[b] = te
            else:
                k1, k2 = collide(masses[a], masses[b], dx, dy, dz, dvx, dvy, dvz, planar)
            if box != 0.0:
                _transfer(spheres, masses, scalars, a, b, te, dx, dy, dz, k1, k2, axes)
            spheres[a, VX] -= k1 * dx
            spheres[a, VY] -= k1 * dy
            spheres[b, VX] += k2 * dx
            spheres[b, VY] += k2 * dy
            if planar:
                d2 = dx * dx + dy * dy
            else:
                spheres[a, VZ] -= k1 * dz
                spheres[b, VZ] += k2 * dz
                d2 = dx * dx + dy * dy + dz * dz
            scalars[F_VIRIAL] -= masses[a] * k1 * d2
            book[a, CHANGES] += 1
            book[b, CHANGES] += 1
            if step_kind == COLLISION:
                counts[C_COLLISIONS] += 1
            else:
                counts[C_STEP_EVENTS + step_kind - CAPTURE] += 1
            counts[C_SERIAL] += 1
            book[a, FRESH] = counts[C_SERIAL]
            book[b, FRESH] = counts[C_SERIAL]
            p0, p1 = a, b
            rec_t[row] = te
            rec_kind[row] = step_kind
            rec_i[row] = book[a, ORIGIN]
            rec_j[row] = book[b, ORIGIN]
            rec_imp[row] = -masses[a] * k1 * np.sqrt(d2)
            rec_dp[row, 0] = -masses[a] * k1 * dx
            rec_dp[row, 1] = -masses[a] * k1 * dy
            rec_dp[row, 2] = 0.0 if planar else -masses[a] * k1 * dz
            done += 1
        elif kind == REFLECTION:
            clock0 = scalars[F_CLOCK]
            scalars[F_CLOCK] = te
            scalars[F_ANCHOR] = te
            _advance(spheres, i, te, axes)
            px, py = spheres[i, X], spheres[i, Y]
            pz = vz = 0.0
            if not planar:
                pz, vz = spheres[i, Z], spheres[i, VZ]
            lost = wx = wy = wz = imp_wall = gain = 0.0  # (the inelastic rule's)
            if scalars[F_GROW] != 0.0:
                k = reflect_grow(
                    px,
                    py,
                    pz,
                    spheres[i, VX],
                    spheres[i, VY],
                    vz,
                    spheres[i, RADIUS] * scalars[F_GROW],
                    planar,
                )
            elif len(rule) == 1:
                if scalars[F_WALL_KT] > 0.0:
                    # the thermal wall: a velocity drawn afresh (k: any nonzero)
                    wx, wy, wz, imp_wall, gain = thermal_wall(
                        masses[i],
                        px,
                        py,
                        pz,
                        spheres[i, VX],
                        spheres[i, VY],
                        vz,
                        scalars[F_WALL_KT],
                        counts[C_WALL_SEED],
                        counts[C_WALL_DRAWS],
                        planar,
                    )
                    k = 1.0
                else:
                    e = scalars[F_WALL_RESTITUTION]
                    if te - hit_t[i] < scalars[F_TC]:
                        e = 1.0  # (the TC model, as for a collision)
                    k, lost = reflect_inelastic(
                        masses[i], px, py, pz, spheres[i, VX], spheres[i, VY], vz, e, planar
                    )
            else:
                k = reflect(px, py, pz, spheres[i, VX], spheres[i, VY], vz, planar)
            if k == 0.0:
                # nothing would change, and the same reflection would come
                # again: not an event (the clock keeps its time)
                scalars[F_CLOCK] = clock0
                scalars[F_ANCHOR] = anchor
                return done, STOP_SLIDING
            counts[C_FROZEN] += 1
            thermal = False
            if len(rule) == 1 and scalars[F_GROW] == 0.0:
                scalars[F_DISSIPATED] += lost
                hit_t[i] = te
                if scalars[F_WALL_KT] > 0.0:
                    # the thermal wall: the drawn velocity, and a factor
                    # 0 for the reflection's own update below (v - 0.0 is v)
                    thermal = True
                    counts[C_WALL_DRAWS] += 1
                    scalars[F_WALL_HEAT] += gain
                    wx, spheres[i, VX] = masses[i] * (wx - spheres[i, VX]), wx
                    wy, spheres[i, VY] = masses[i] * (wy - spheres[i, VY]), wy
                    if not planar:
                        wz, spheres[i, VZ] = masses[i] * (wz - spheres[i, VZ]), wz
                    k = px = py = pz = 0.0
            spheres[i, VX] -= k * px
            spheres[i, VY] -= k * py
            if planar:
                imp = masses[i] * k * np.sqrt(px * px + py * py)
            else:
                spheres[i, VZ] -= k * pz
                imp = masses[i] * k * np.sqrt(px * px + py * py + pz * pz)
            scalars[F_WALL_IMPULSE] += imp
            book[i, CHANGES] += 1
            counts[C_REFLECTIONS] += 1
            counts[C_SERIAL] += 1
            book[i, FRESH] = counts[C_SERIAL]
            rec_t[row] = te
            rec_kind[row] = REFLECTION
            rec_i[row] = book[i, ORIGIN]
            rec_j[row] = -1
            rec_imp[row] = imp
            rec_dp[row, 0] = -masses[i] * k * px
            rec_dp[row, 1] = -masses[i] * k * py
            rec_dp[row, 2] = 0.0 if planar else -masses[i] * k * pz
            if thermal:
                # (the inelastic loop's: its normal impulse and momentum change)
                scalars[F_WALL_IMPULSE] += imp_wall
                rec_imp[row] = imp_wall
                rec_dp[row, 0] = wx
                rec_dp[row, 1] = wy
                rec_dp[row, 2] = 0.0 if planar else wz
            done += 1
        elif not stale:
            return done, STOP_UNTIL
        for q in range(1 if p1 < 0 else 2):
            x = p0 if q == 0 else p1
            predict(
                spheres, book, due, shells, neighbours, cell_head, cell_next, scalars, counts, x, tp, axes
            )
            _schedule(heap, heap_t, heap_key, calendar, due, book, scalars, counts, x)
        if stale:
            continue
        if window > 0.0 and te != anchor:
            refresh_window(arrays)


@_jit
def kick(arrays, i, t, vx, vy, vz):
    """Give sphere ``i`` a new velocity at time ``t`` (not before the clock).

    The clock moves to ``t``; predictions that involve ``i`` go stale (its
    event count moves on) and ``i`` is predicted afresh.  For thermostats.
    """
    spheres, masses, book, due, shells, neighbours, cell_head, cell_next = arrays[:8]
    cell_prev, heap, heap_t, heap_key, scalars, counts, scratch, images = arrays[8:16]
    calendar, axes = arrays[16], arrays[17]
    scalars[F_CLOCK] = t
    if len(axes[0]) == 1:
        _close_flight(spheres, masses, scalars, i, t, axes)
    _advance(spheres, i, t, axes)
    # the transport tallies' kinetic sums: integrated up to t, then i's terms swapped
    dtk = t - scalars[F_T_KIN]
    for q in range(6):
        scalars[F_KIN_INT + q] += scalars[F_KIN_T + q] * dtk
    for q in range(len(axes)):
        scalars[F_HEAT_INT + q] += scalars[F_HEAT_KIN + q] * dtk
    scalars[F_T_KIN] = t
    _kinetic_terms(scalars, masses[i], spheres[i, VX], spheres[i, VY], spheres[i, VZ], -1.0, axes)
    _kinetic_terms(scalars, masses[i], vx, vy, vz, 1.0, axes)
    spheres[i, VX] = vx
    spheres[i, VY] = vy
    if len(axes) == 3:
        spheres[i, VZ] = vz
    book[i, CHANGES] += 1
    counts[C_SERIAL] += 1
    book[i, FRESH] = counts[C_SERIAL]
    predict_one(spheres, book, due, shells, neighbours, cell_head, cell_next, scalars, counts, i, t, axes)
    _schedule(heap, heap_t, heap_key, calendar, due, book, scalars, counts, i)


# ---- state and checks ------------------------------------------------------------


@_jit
def positions_at(axes, spheres, t, out, edges, delta=0.0):
    """Centres of all spheres at time ``t`` into ``out`` (wrapped into the box; ``edges`` its sides, 0: none).

    ``out`` has 3 columns; in 2-D only the first two are written.  A sheared
    box (``delta`` its offset at ``t``): a centre past a y face it has not
    crossed yet is seen at its image, shifted by ``delta`` (the reference's).
    """
    n = spheres.shape[0]
    for i in range(n):
        dt = t - spheres[i, T_OWN]
        if len(axes[0]) == 1:
            y = spheres[i, Y] + spheres[i, VY] * dt
            ky = np.floor(y / edges[1] + 0.5)
            x = spheres[i, X] + spheres[i, VX] * dt
            if ky != 0.0:
                x -= ky * delta
            out[i, 0] = x - edges[0] * np.floor(x / edges[0] + 0.5)
            out[i, 1] = y - edges[1] * np.floor(y / edges[1] + 0.5)
            if len(axes) == 3:
                z = spheres[i, Z] + spheres[i, VZ] * dt
                out[i, 2] = z - edges[2] * np.floor(z / edges[2] + 0.5)
            continue
        for k in range(len(axes)):
            box = edges[k]
            x = spheres[i, X + k] + spheres[i, VX + k] * dt
            if box != 0.0:
                x -= box * np.floor(x / box + 0.5)
            out[i, k] = x


@_jit
def unwrapped_at(axes, spheres, images, t, out, edges):
    """Unwrapped centres at time ``t`` into ``out``: the stored centre plus its image's shift (2-D: two columns)."""
    n = spheres.shape[0]
    for i in range(n):
        dt = t - spheres[i, T_OWN]
        for k in range(len(axes)):
            out[i, k] = (spheres[i, X + k] + spheres[i, VX + k] * dt) + images[i, k] * edges[k]


@_jit
def predict_all(arrays):
    """Every sphere predicted afresh at the clock (the cells and lists as they are; no calendar)."""
    spheres, masses, book, due, shells, neighbours, cell_head, cell_next = arrays[:8]
    scalars, counts, axes = arrays[12], arrays[13], arrays[17]
    t = scalars[F_CLOCK]
    for i in range(spheres.shape[0]):
        predict_one(spheres, book, due, shells, neighbours, cell_head, cell_next, scalars, counts, i, t, axes)


@_jit
def rebase(axes, spheres, due, heap_t, scalars):
    """Move the time origin to the clock: advance everyone, shift all times."""
    t = scalars[F_CLOCK]
    n = spheres.shape[0]
    for i in range(n):
        _advance(spheres, i, t, axes)
        spheres[i, T_OWN] = 0.0
        due[i, EVENT_T] -= t
        due[i, CROSS_T] -= t
        heap_t[i] -= t
    scalars[F_ANCHOR] -= t
    scalars[F_T_KIN] -= t
    scalars[F_STREAK] -= t
    scalars[F_OFFSET] += t
    if len(axes[0]) == 1:
        scalars[F_SHEAR0] = _offset(scalars, t)  # (the reference's when its origin moves)
    scalars[F_CLOCK] = 0.0
    grow = scalars[F_GROW]
    if grow != 0.0:
        # radii to the new origin; the growth speed of each stays the same
        factor = 1.0 + grow * t
        for i in range(n):
            spheres[i, RADIUS] *= factor
        scalars[F_GROW] = grow / factor
    return t


@_jit
def max_overlap(axes, x, spheres, book, cell_head, cell_next, grid, edges, scale):
    """Largest ``1 - d / (R_i + R_j)`` over touching-or-overlapping pairs (0 if none).

    ``x`` are the centres at one time, ``scale`` the radii's factor then
    (1 without growth); neighbours are found through the engine's cells
    (``grid`` cells per axis; ``edges`` the box's sides, 0: no box).
    """
    n = x.shape[0]
    worst = 0.0
    ncx, ncy, ncz = grid[0], grid[1], grid[2]
    bx, by, bz = edges[0], edges[1], edges[2]
    for i in range(n):
        for oz in range(0, 1) if len(axes) == 2 else range(-1 if ncz > 1 else 0, 2 if ncz > 1 else 1):
            nz = book[i, CELL_Z] + oz
            for oy in range(-1, 2):
                ny = book[i, CELL_Y] + oy
                for ox in range(-1, 2):
                    nx = book[i, CELL_X] + ox
                    if bx == 0.0 and (nx < 0 or ny < 0 or nz < 0 or nx >= ncx or ny >= ncy or nz >= ncz):
                        continue
                    j = np.int64(cell_head[((nz % ncz) * ncy + (ny % ncy)) * ncx + (nx % ncx)])
                    while j >= 0:
                        if j > i:
                            dx = x[i, 0] - x[j, 0]
                            dy = x[i, 1] - x[j, 1]
                            if bx != 0.0:
                                dx -= bx * np.round(dx / bx)
                                dy -= by * np.round(dy / by)
                            r2 = dx * dx + dy * dy
                            if len(axes) == 3:
                                dz = x[i, 2] - x[j, 2]
                                if bz != 0.0:
                                    dz -= bz * np.round(dz / bz)
                                r2 = dx * dx + dy * dy + dz * dz
                            sigma = (spheres[i, RADIUS] + spheres[j, RADIUS]) * scale
                            if sigma > 0.0:
                                ov = 1.0 - np.sqrt(r2) / sigma
                                if ov > worst:
                                    worst = ov
                        j = np.int64(cell_next[j])
    return worst


@_jit
def max_overlap_sheared(axes, x, spheres, book, cell_head, cell_next, grid, edges, delta):
    """:func:`max_overlap` in a sheared box (``delta`` its offset at the time of ``x``).

    A pair across a y face is taken at the image there (``dy`` to the
    nearest, ``dx`` shifted by the offset, then to the nearest image along
    x: the collision's arithmetic), and a sphere in a boundary row of cells
    looks at the whole opposite row (the images there slide along x).
    """
    n = x.shape[0]
    worst = 0.0
    ncx, ncy, ncz = grid[0], grid[1], grid[2]
    bx, by, bz = edges[0], edges[1], edges[2]
    for i in range(n):
        for oz in range(0, 1) if len(axes) == 2 else range(-1, 2):
            nz = (book[i, CELL_Z] + oz + ncz) % ncz
            for oy in range(-1, 2):
                ny = book[i, CELL_Y] + oy
                across = ny < 0 or ny >= ncy
                ny = (ny + ncy) % ncy
                for q in range(ncx if across else 3):
                    nx = q if across else (book[i, CELL_X] + q - 1 + ncx) % ncx
                    j = np.int64(cell_head[(nz * ncy + ny) * ncx + nx])
                    while j >= 0:
                        if j > i:
                            dx = x[i, 0] - x[j, 0]
                            dy = x[i, 1] - x[j, 1]
                            ky = np.round(dy / by)
                            dy -= by * ky
                            dx -= ky * delta
                            dx -= bx * np.round(dx / bx)
                            r2 = dx * dx + dy * dy
                            if len(axes) == 3:
                                dz = x[i, 2] - x[j, 2]
                                dz -= bz * np.round(dz / bz)
                                r2 = dx * dx + dy * dy + dz * dz
                            sigma = spheres[i, RADIUS] + spheres[j, RADIUS]
                            if sigma > 0.0:
                                ov = 1.0 - np.sqrt(r2) / sigma
                                if ov > worst:
                                    worst = ov
                        j = np.int64(cell_next[j])
    return worst


@_jit
def close_flights(axes, spheres, masses, scalars, t):
    """Sheared: every sphere's flight up to ``t`` added to the peculiar kinetic integral (before a rebase)."""
    for i in range(spheres.shape[0]):
        _close_flight(spheres, masses, scalars, i, t, axes)


@_jit
def peculiar_kinetic(axes, spheres, masses, scalars, t, out):
    """Sheared: the time integral of ``sum m c c`` up to ``t`` into ``out`` (6,): closed flights and open ones.

    The open flights are added to a copy (``out``); the core's tally is not changed.
    """
    for q in range(6):
        out[q] = scalars[F_PEC_INT + q]  # (kept here meanwhile)
    for i in range(spheres.shape[0]):
        _close_flight(spheres, masses, scalars, i, t, axes)
    for q in range(6):
        total = scalars[F_PEC_INT + q]
        scalars[F_PEC_INT + q] = out[q]
        out[q] = total

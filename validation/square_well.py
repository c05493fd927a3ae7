"""The square well at low density on the brute-force reference: Z - 1 against the exact B2.

The compiled event core does not have steps yet; the brute-force reference
does (``Reference(..., steps=[(lambda, -eps)])``, pure Python, every pair
predicted after every event), so the system is small: N = 32 spheres (or
disks) of diameter, mass one, a well of width lambda = 1.5 and depth eps,
in a periodic box at a low number density, started on a lattice with
Maxwell velocities scaled to kT = 1 (total momentum zero), run at constant energy.

``--compiled``: the same comparison on the compiled event core
(``hs.Simulation(..., steps=[(lambda, -eps)])``) with N = 2000 spheres
in 3-D, held at kT = 1 by an Andersen thermostat, at four densities;
the measured ``Z_ex`` is compared with ``B2 (N-1)/V`` and with ``B2 (N-1)/V
+ B3 rho^2`` (``B4 rho^3`` is not known here and not subtracted), ``B3``
computed here to rounding (:func:`b3`: the Mayer-function integral
``B3 = -(1/3) int int f12 f13 f23``, written as sums of sphere-sphere lens
volumes; hard spheres give ``5 pi^2 / 18``).  Measured: ``Z_ex = W / (3 t
N kT)`` with the set ``kT = 1`` and ``W`` the engine's virial tally over 64 blocks of equal time
(:func:`square_well_dynamo.window`).  Its output is kept in
validation/results/square_well_compiled.txt.

At low density, ``Z - 1 = B2 rho + O(rho^2)`` with (sigma = 1, beta = 1/kT)

* 3-D: ``B2 = (2 pi / 3) (1 - (lambda^3 - 1) (exp(beta eps) - 1))``;
* 2-D: ``B2 = (pi / 2) (1 - (lambda^2 - 1) (exp(beta eps) - 1))``

(``B2 = -(1/2) int f(r) d^d r``, the Mayer function ``f`` being -1 inside
the core and ``exp(beta eps) - 1`` in the well).  Measured: the excess
``Z_ex = W / (d t N kT)`` from the virial ``W`` (the sum of ``r_ij . dp_i``
over core collisions, captures, releases and bounces: ``Reference.virial``)
over the time ``t``, with ``kT = 2 <K> / (d (N - 1))`` from the exact time
average of the kinetic energy (``K = E - U``, ``U`` stepping at captures and
releases).  Each sphere sees ``N - 1`` partners in the volume ``V``, so the
comparison is with ``B2 (N - 1) / V``; the next term, ``B3 rho^2``, is
not subtracted (two densities each, to see it if it were above the error
bars).  Errors: 10 blocks of events after equilibration.  Its output is
kept in validation/results/square_well.txt (docs/validation/square-well.md).

usage:
    python3 validation/square_well.py              # about 7 minutes on a loaded core
    python3 validation/square_well.py --scale 0.2  # a quick look
    python3 validation/square_well.py --compiled   # N = 2000 on the compiled core, B2 and B3
    python3 validation/square_well.py --compiled --rho 0.02 --another 1   # one row, another seed
"""

import argparse
import math
import random
import time

import numpy as np

import hardspheres as hs
from hardspheres.core.reference import Reference
from hardspheres.events import EventKind

N, LAM, EPS = 32, 1.5, 1.0


def b2(d: int, beta_eps: float) -> float:
    """The square well's exact second virial coefficient (sigma = 1) [length^d]."""
    if d == 3:
        return 2.0 * math.pi / 3.0 * (1.0 - (LAM**3 - 1.0) * math.expm1(beta_eps))
    return math.pi / 2.0 * (1.0 - (LAM**2 - 1.0) * math.expm1(beta_eps))


def b3(beta_eps: float, lam: float = LAM) -> float:
    """The square well's third virial coefficient in 3-D (sigma = 1) [length^6], to rounding.

    With ``f = a1 [r < 1] + a2 [r < lam]`` (``a2 = exp(beta eps) - 1``, ``a1 = -1 - a2``),
    ``int f(r13) f(r23) d^3 r3 = sum_ij a_i a_j V_lens(R_i, R_j, r12)``, a polynomial in
    ``r12`` between the breakpoints ``0, lam - 1, 1, lam``, integrated exactly by
    Gauss-Legendre quadrature.

    Example:
        >>> round(b3(0.0) / (5 * math.pi**2 / 18), 12)  # hard spheres
        1.0
    """
    c = math.expm1(beta_eps)
    terms = ((-1.0 - c, 1.0), (c, lam))

    def lens(r1: float, r2: float, d: np.ndarray) -> np.ndarray:
        s = r1 + r2
        v = np.pi * (s - d) ** 2 * (d * d + 2.0 * d * s - 3.0 * (r1 - r2) ** 2) / (12.0 * d)
        v = np.where(d <= abs(r1 - r2), 4.0 / 3.0 * np.pi * min(r1, r2) ** 3, v)
        return np.where(d >= s, 0.0, v)

    x, w = np.polynomial.legendre.leggauss(32)
    total = 0.0
    for lo, hi in ((0.0, lam - 1.0), (lam - 1.0, 1.0), (1.0, lam)) if lam < 2.0 else ((0.0, 1.0), (1.0, lam)):
        if hi <= lo:
            continue
        r = 0.5 * (hi - lo) * x + 0.5 * (hi + lo)
        f = np.where(r < 1.0, -1.0, c)
        inner = sum(ai * aj * lens(ri, rj, r) for ai, ri in terms for aj, rj in terms)
        total += 0.5 * (hi - lo) * float(np.sum(w * 4.0 * np.pi * r * r * f * inner))
    return -total / 3.0


def compiled(rho: float, events: float, seed: int, n: int = 2000) -> dict[str, float]:
    """One density on the compiled core at kT = 1 (Andersen): blocked Z_ex against B2 and B3."""
    from square_well_dynamo import pair_events, window

    from hardspheres.blocking import blocking
    from hardspheres.builders import crystal
    from hardspheres.dense import Andersen

    k = 8  # FCC 8 x 8 x 8 = 2048 sites; n of them kept, chosen at random
    state, box = crystal("fcc", (k, k, k), rho * 4 * k**3 / n * math.pi / 6.0, radius=0.5, seed=seed)
    keep = np.sort(np.random.default_rng(seed).choice(state.n, n, replace=False))
    sim = hs.Simulation.from_arrays(
        state.masses[keep],
        state.radii[keep],
        state.positions[keep],
        state.velocities[keep],
        box,
        steps=[(LAM, -EPS)],
    )
    sim.set_thermostat(Andersen(kT=1.0, rate=0.05, seed=seed))
    t0, p0 = sim.time, pair_events(sim)
    sim.run(events=int(events / 5))
    rate = (pair_events(sim) - p0) / (sim.time - t0)
    w = window(sim, events / rate, 64, 4, 1.0)
    b = blocking(w["Zex"])
    half = len(w["Zex"]) // 2
    joint = math.hypot(blocking(w["Zex"][:half]).sem, blocking(w["Zex"][half:]).sem)
    volume = float(np.prod(box.sides))
    return {
        "rho": n / volume,
        "z_ex": b.mean,
        "err": b.sem,
        "converged": b.converged,
        "halves": (w["Zex"][half:].mean() - w["Zex"][:half].mean()) / joint,
        "b2": b2(3, EPS) * (n - 1) / volume,
        "b3": b3(EPS) * (n / volume) ** 2,
        "kT": float(np.sum(w["kT"] * w["t"]) / np.sum(w["t"])),
        "events": float(w["pairs"].sum()),
    }


def main_compiled(scale: float, densities: list[float] | None = None, another: int = 0) -> None:
    """The ``--compiled`` table (``another``: a different seed for each row)."""
    cpu = time.process_time()
    print(f"N = 2000, 3-D, lambda = {LAM}, eps = {EPS}, Andersen kT = 1; B3(kT = 1) = {b3(EPS):.6f}")
    print("rho     Z_ex measured        B2 (N-1)/V   + B3 rho^2   z(B2)   z(B2+B3)  halves  <kT>    events")
    for k, rho in enumerate((0.005, 0.01, 0.02, 0.05)):
        if densities and rho not in densities:
            continue
        r = compiled(rho, 6e6 * scale, seed=31 + k + 100 * another)
        flag = "" if r["converged"] else "  (blocking without plateau)"
        flag += "  DRIFT" if abs(r["halves"]) > 3 else ""
        print(
            f"{r['rho']:.4f}  {r['z_ex']:+.5f} +- {r['err']:.5f}   {r['b2']:+.5f}"
            f"     {r['b2'] + r['b3']:+.5f}     {(r['z_ex'] - r['b2']) / r['err']:+5.1f}"
            f"   {(r['z_ex'] - r['b2'] - r['b3']) / r['err']:+5.1f}"
            f"     {r['halves']:+4.1f}   {r['kT']:.4f}  {r['events']:.1e}{flag}",
            flush=True,
        )
    print(f"CPU time {time.process_time() - cpu:.0f} s")


def start(d: int, rho: float, seed: int) -> Reference:
    """N spheres on a simple lattice in a periodic box at number density ``rho``, kT = 1."""
    rng = random.Random(seed)
    side = (N / rho) ** (1.0 / d)
    per = math.ceil(N ** (1.0 / d))
    a = side / per
    sites = [[(k // per**ax) % per * a - side / 2 + 0.25 * a for ax in range(d)] for k in range(per**d)]
    pos = rng.sample(sites, N)
    vel = [[rng.gauss(0.0, 1.0) for _ in range(d)] for _ in range(N)]
    mean = [sum(v[ax] for v in vel) / N for ax in range(d)]
    vel = [[v[ax] - mean[ax] for ax in range(d)] for v in vel]
    scale = math.sqrt(d * (N - 1) / sum(x * x for v in vel for x in v))  # kT = 1 exactly
    vel = [[x * scale for x in v] for v in vel]
    box = hs.PeriodicBox(side if d == 3 else (side, side))
    return Reference([1.0] * N, [0.5] * N, pos, vel, box, steps=[(LAM, -EPS)])


def block(ref: Reference, events: int) -> tuple[float, float, float]:
    """``events`` events: ``(virial, duration, time integral of U)``."""
    t0, w0, u = ref.time, ref.virial, ref.potential_energy()
    ev = ref.advance(events=events)
    u_int, last = 0.0, t0
    for t, kind in zip(ev["time"], ev["kind"]):
        u_int += u * (t - last)
        last = t
        if kind == EventKind.CAPTURE:
            u -= EPS
        elif kind == EventKind.RELEASE:
            u += EPS
    u_int += u * (ref.time - last)
    assert u == ref.potential_energy()
    return ref.virial - w0, ref.time - t0, u_int


def measure(d: int, rho: float, events: int, seed: int) -> dict[str, float]:
    """One state point: the measured excess Z against B2 (N - 1) / V."""
    ref = start(d, rho, seed)
    energy = ref.kinetic_energy() + ref.potential_energy()
    ref.advance(events=events // 5)  # equilibration
    rows = [block(ref, events // 10) for _ in range(10)]
    w, t, u = (np.array(c) for c in zip(*rows))
    kin = energy - u.sum() / t.sum()
    kt = 2.0 * kin / (d * (N - 1))
    zex = w / (d * t * N * kt)
    side = ref.container.sides[0]
    volume = side**d
    drift = abs(ref.kinetic_energy() + ref.potential_energy() - energy) / energy
    return {
        "d": d,
        "rho": rho,
        "kT": kt,
        "beta_eps": EPS / kt,
        "z_ex": float(zex.mean()),
        "err": float(zex.std(ddof=1) / math.sqrt(len(zex))),
        "exact": b2(d, EPS / kt) * (N - 1) / volume,
        "bonded": len(ref.pair_states),
        "drift": drift,
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--scale", type=float, default=1.0, help="fraction of the events (1: 10 minutes)")
    ap.add_argument("--compiled", action="store_true", help="N = 2000 on the compiled core, B2 and B3")
    ap.add_argument("--rho", type=float, nargs="*", help="with --compiled: only these of its densities")
    ap.add_argument("--another", type=int, default=0, help="with --compiled: another seed (1, 2, ...)")
    args = ap.parse_args()
    if args.compiled:
        main_compiled(args.scale, args.rho, args.another)
        return
    print(f"N = {N}, lambda = {LAM}, eps = {EPS} (kT = 1 at the start), sigma = m = 1")
    print("d  rho    kT      beta_eps  Z_ex measured      B2 (N-1)/V   z      |E drift|")
    for d, rho, events in ((3, 0.01, 60_000), (3, 0.02, 60_000), (2, 0.02, 60_000), (2, 0.04, 60_000)):
        t = time.time()
        r = measure(d, rho, int(events * args.scale), seed=d * 100 + int(rho * 1000))
        z = (r["z_ex"] - r["exact"]) / r["err"]
        print(
            f"{d}  {rho:.3f}  {r['kT']:.4f}  {r['beta_eps']:.4f}    {r['z_ex']:+.5f}({r['err'] * 1e5:.0f})"
            f"   {r['exact']:+.5f}     {z:+.1f}   {r['drift']:.1e}   ({time.time() - t:.0f} s)",
            flush=True,
        )


if __name__ == "__main__":
    main()

"""The lambda = 1.5 square-well fluid's equation of state (Z, U/N) at a few state points.

N = 500 spheres (FCC 5 x 5 x 5 start, diameter, mass and well depth one)
in a periodic box, ``hs.Simulation(..., steps=[(1.5, -1.0)])`` held at
``kT`` by :class:`hardspheres.dense.Andersen`; after an equilibration of
``--equil`` events, a measured window of about ``--events`` events in 256
blocks of equal time: ``Z = (W + 2 int K dt) / (3 t N kT)`` with the set
``kT`` (``W`` the collisional virial, core and step events) and ``U/N``
sampled at evenly spaced times (:func:`square_well_dynamo.window`).
Errors: Flyvbjerg-Petersen blocking of the 256 block values
(:func:`hardspheres.blocking.blocking`); drift: the two halves' means
compared (more than 3 joint errors apart: the row is flagged ``DRIFT``
and its average is not a result).

Reference: the equation of state of Espindola-Heredia, del Rio and
Malijevsky, J. Chem. Phys. 130, 024509 (2009), a fit for square wells of
variable range, as implemented in the ``teqp`` package (model
``SW_EspindolaHeredia2009``; ``Z = 1 + Ar01``, ``U/N = T Ar10``); it is
optional (``pip install teqp``): without it only the measured values are
printed.  Output kept in validation/results/square_well_eos.txt
(docs/validation/square-well.md).

usage:
    python3 validation/square_well_eos.py                      # about 6 minutes of CPU
    python3 validation/square_well_eos.py --events 1e6 --equil 2e5   # a quick look
    python3 validation/square_well_eos.py --cells 8 --points 0 1     # N = 2048: the size effect
"""

import argparse
import math
import time

import numpy as np

import hardspheres as hs
from hardspheres.blocking import blocking
from hardspheres.builders import crystal
from hardspheres.dense import Andersen
from square_well_dynamo import pair_events, window

LAM, EPS = 1.5, 1.0
POINTS = ((1.5, 0.3), (1.5, 0.5), (1.5, 0.7), (2.0, 0.8))  # (kT, number density), all above T_c


def reference(kt: float, rho: float) -> tuple[float, float] | None:
    """``(Z, U/N)`` of the published equation of state, or None without teqp."""
    try:
        import teqp
    except ImportError:
        return None
    model = teqp.make_model({"kind": "SW_EspindolaHeredia2009", "model": {"lambda": LAM}})
    z = np.array([1.0])
    return 1.0 + model.get_Ar01(kt, rho, z), kt * model.get_Ar10(kt, rho, z)


def measure(
    kt: float, rho: float, events: float, equil: float, seed: int, cells: int = 5
) -> dict[str, float]:
    """One state point: the blocked means of Z and U/N, their errors and the halves' test."""
    state, box = crystal("fcc", (cells,) * 3, rho * math.pi / 6.0, radius=0.5, kT=kt, seed=seed)
    sim = hs.Simulation(state, box, steps=[(LAM, -EPS)])
    sim.set_thermostat(Andersen(kT=kt, rate=0.5, seed=seed))
    t0, p0 = sim.time, pair_events(sim)
    sim.run(events=int(equil))
    rate = (pair_events(sim) - p0) / (sim.time - t0)  # pair events per unit time
    w = window(sim, events / rate, 256, 8, kt)
    out: dict[str, float] = {
        "kT": kt,
        "rho": rho,
        "time": float(w["t"].sum()),
        "events": float(w["pairs"].sum()),
    }
    for name in ("Z", "U"):
        b = blocking(w[name])
        half = len(w[name]) // 2
        a, c = w[name][:half], w[name][half:]
        joint = math.hypot(blocking(a).sem, blocking(c).sem)
        out[name], out[f"{name}_err"], out[f"{name}_conv"] = b.mean, b.sem, float(b.converged)
        out[f"{name}_halves"] = (c.mean() - a.mean()) / joint if joint > 0 else math.nan
    out["kT_meas"] = float(np.sum(w["kT"] * w["t"]) / np.sum(w["t"]))
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--events", type=float, default=6e6, help="pair events measured per state point")
    ap.add_argument("--equil", type=float, default=1e6, help="pair events of equilibration")
    ap.add_argument("--cells", type=int, default=5, help="FCC cells per side: N = 4 cells^3 (5: N = 500)")
    ap.add_argument("--points", type=int, nargs="*", help="which state points (0-3; default all)")
    args = ap.parse_args()
    cpu = time.process_time()
    print(
        f"N = {4 * args.cells**3}, lambda = {LAM}, eps = {EPS}, Andersen at kT;"
        f" {args.equil:.0e} events equilibration, {args.events:.1e} measured"
    )
    print(
        "kT   rho   Z measured         Z (EOS fit)  dev/err  U/N measured       U/N (EOS fit) dev/err  "
        "halves Z, U  <kT>     events"
    )
    for k, (kt, rho) in enumerate(POINTS):
        if args.points and k not in args.points:
            continue
        r = measure(kt, rho, args.events, args.equil, seed=11 + k, cells=args.cells)
        ref = reference(kt, rho)
        drift = max(abs(r["Z_halves"]), abs(r["U_halves"])) > 3.0
        flags = ("" if r["Z_conv"] and r["U_conv"] else " (blocking without plateau)") + (
            " DRIFT" if drift else ""
        )
        zr = f"{ref[0]:+.4f}     {(r['Z'] - ref[0]) / r['Z_err']:+6.1f}" if ref else "    -            "
        ur = f"{ref[1]:+.4f}      {(r['U'] - ref[1]) / r['U_err']:+6.1f}" if ref else "    -            "
        print(
            f"{kt:.1f}  {rho:.1f}   {r['Z']:+.4f} +- {r['Z_err']:.4f}  {zr}   "
            f"{r['U']:+.4f} +- {r['U_err']:.4f}  {ur}   {r['Z_halves']:+.1f} {r['U_halves']:+.1f}   "
            f"{r['kT_meas']:.4f}  {r['events']:.2e}{flags}",
            flush=True,
        )
    print(f"CPU time {time.process_time() - cpu:.0f} s")


if __name__ == "__main__":
    main()

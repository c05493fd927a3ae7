"""The FCC crystal's volume fluctuations at constant pressure against the run's length.

One run of validation/constant_pressure.py's crystal (N = 108, 3 x 3 x 3
FCC cells from Speedy's packing, one move per mean free time, the same
seeds), the box's sides read after each move; prints ``N var(V) / <V>^2``
with its blocked error and plateau over the first 10000, 20000, ... moves
and over consecutive windows, and the statistical inefficiencies (``n sem^2
/ var``, twice the integrated autocorrelation time) of ``ln V`` and ``ln
Lx`` in moves.  Shows whether the estimate has converged: a variance from a
run a few correlation times long is low.  About 2.5 minutes for 300000 moves
on one core of this (shared) machine; ``--npy`` saves the sides.

usage: python3 validation/constant_pressure_windows.py [--pressure P] [--axes xyz|none]
       [--moves M] [--equilibrate E] [--window W] [--npy FILE]
"""

from __future__ import annotations

import argparse

import numpy as np

import hardspheres as hs
from hardspheres import eos, fileio
from hardspheres.blocking import blocking
from hardspheres.builders import crystal


def fluct(v: np.ndarray, n: int) -> str:
    """``N var(V) / <V>^2`` +- its blocked error, and whether the blocking reached its plateau."""
    b = blocking(n * (v - v.mean()) ** 2 / v.mean() ** 2)
    return f"{b.mean:.4f} +- {b.sem:.4f} (plateau: {'yes' if b.converged else 'no'})"


def inefficiency(x: np.ndarray) -> float:
    """``n sem^2 / var`` of a series, by blocking [samples]."""
    return float(len(x) * blocking(x).sem ** 2 / np.var(x))


def main() -> None:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("--pressure", type=float, default=20.0, help="beta P sigma^3")
    ap.add_argument("--axes", default="xyz", help="'xyz' (per side) or 'none' (isotropic)")
    ap.add_argument("--moves", type=int, default=300000)
    ap.add_argument("--equilibrate", type=int, default=3000)
    ap.add_argument("--window", type=int, default=40000)
    ap.add_argument("--npy", help="save the sides after each move, (moves, 3)")
    args = ap.parse_args()
    axes = None if args.axes == "none" else args.axes
    phi0 = eos.packing_at_pressure(args.pressure, eos.speedy_fcc, (0.5, 0.74))
    state, box = crystal("fcc", (3, 3, 3), phi0, seed=1)
    sim = hs.Simulation(state, box)
    bar = hs.Barostat(pressure=args.pressure, kT=1.0, axes=axes, seed=1)
    sim.set_barostat(bar)
    bar.attach(sim)
    sim.run(until=bar.next_time + (args.equilibrate - 1) * bar.every)
    sides = np.empty((args.moves, 3))
    for k in range(args.moves):
        sim.run(until=bar.next_time)
        sides[k] = sim.container.sides
    n, v = sim.n, sides.prod(axis=1)
    ref = 1.0 / float(eos.inverse_compressibility(phi0, eos.speedy_fcc))
    print(f"beta P = {args.pressure:g}, axes = {args.axes}, reference {ref:.4f} (Speedy 1998)")
    m = 10000
    while m < args.moves:
        print(f"first {m}: {fluct(v[:m], n)}")
        m *= 2
    print(f"all {args.moves}: {fluct(v, n)}")
    for k in range(0, args.moves, args.window):
        w = v[k : k + args.window]
        if len(w) > 1:
            print(f"moves {k}-{k + len(w)}: {fluct(w, n)}")
    tau_v, tau_x = inefficiency(np.log(v)), inefficiency(np.log(sides[:, 0]))
    print(f"statistical inefficiency in moves: ln V {tau_v:.0f}, ln Lx {tau_x:.0f}")
    if args.npy:
        with fileio.atomic_write(args.npy, "wb") as fh:
            np.save(fh, sides)


if __name__ == "__main__":
    main()

"""Mixing per event of the three event-chain variants: straight, Newtonian, forward.

Hard disks at packing 0.70 in the crystal's box (``hexagonal((nx, ny), 0.70)``,
N = nx ny), from the perfect crystal, ``--equilibrate`` lifts per disk of
straight chains (seed 1); then, from that same configuration, each variant
(seed 2) runs ``--lifts`` lifts per disk, recording the pressure of blocks
of about ``--every`` lifts per disk (``Z = 1 + sum of (r_j - r_i) . v / sum
of t |v|^2`` over each, the chain's own blocks) and, at the first chain end
after every ``--psi6`` lifts per disk, ``|Psi6|`` (6 nearest neighbours,
freud).

The integrated autocorrelation time of each series (Sokal's window, c = 5)
``tau = 1/2 + sum of the autocorrelations``, times its interval, is tau in
lifts per disk (an average over a run of ``M`` lifts per disk has the
error of ``M / (2 tau)`` independent values).  A tau below one interval is
not resolved (the interval is too long) and is printed as an upper bound; a
run shorter than 100 tau is flagged (``short``): its tau is a lower bound.  CPU seconds and lifts per
CPU second are printed too (this machine is shared: read CPU figures as
rough; the ratios per lift are the measurement).

usage: nice -n 10 python3 benchmarks/ecmc_mixing.py [--cells 16 16] [--lifts 1500000]
    [--every 5] [--psi6 100] [--equilibrate 50000] [--variants straight newtonian forward]
    [--out validation/results/ecmc_mixing_256.csv]
"""

from __future__ import annotations

import argparse
import csv
import math
import time

import numpy as np

import hardspheres as hs
from hardspheres import fileio


def iat(x: np.ndarray) -> tuple[float, int]:
    """Integrated autocorrelation time in samples (Sokal's window, c = 5) and the window."""
    x = np.asarray(x, float) - np.mean(x)
    n = x.size
    f = np.fft.rfft(x, 2 * n)
    acf = np.fft.irfft(f * np.conj(f))[:n] / (n * np.var(x))
    tau = 0.5
    for t in range(1, n // 2):
        tau += acf[t]
        if t >= 5.0 * tau:
            return max(tau, 0.5), t
    return max(tau, 0.5), n // 2


def psi6(chain: hs.EventChain) -> float:
    """``|Psi6|`` over the 6 nearest neighbours of each disk (freud)."""
    import freud

    lx, ly = chain.container.sides[:2]
    pts = np.zeros((chain.n, 3))
    pts[:, :2] = chain.state().positions
    h = freud.order.Hexatic(k=6)
    h.compute((freud.box.Box(Lx=lx, Ly=ly, is2D=True), pts), neighbors={"num_neighbors": 6})
    return float(abs(np.mean(h.particle_order)))


def series(
    start: hs.State, box: hs.PeriodicBox, variant: str, lifts: int, every: int, psi6_every: int
) -> dict:
    """One variant's pressure and |Psi6| series and their correlation times (lifts per disk).

    The pressure series is the chain's own blocks (``observables.blocks("Z")``,
    a block of about ``every`` lifts per disk, merged by two as the run
    grows past 65536 blocks); ``|Psi6|`` is sampled at the first chain end
    after every ``psi6_every`` lifts per disk.
    """
    n = start.n
    chain = hs.EventChain(start, box, seed=2, variant=variant)
    chain.run(chains=40)  # lifts per chain of this variant, for the blocks' length
    per_round = 2 * chain.counters["events"] / 40
    t0 = time.process_time()
    chain.observables.reset(every=max(1, round(every * n / per_round)))
    base = chain.counters["events"]
    psi, at_psi = [], []
    while chain.counters["events"] - base < lifts * n:
        chain.run(events=psi6_every * n).run(chains=1)
        psi.append(psi6(chain))
        at_psi.append((chain.counters["events"] - base) / n)
    cpu = time.process_time() - t0
    z = chain.observables.blocks("Z")
    marks = chain.observables.checkpoint()["obs_samples"][:, 0]
    out = {"variant": variant, "n": n, "lifts_per_disk": (chain.counters["events"] - base) / n, "cpu_s": cpu}
    out["lifts_per_cpu_s"] = (chain.counters["events"] - base) / cpu
    for name, x, step in (
        ("Z", z, float(np.mean(np.diff(marks))) / n),
        ("psi6", np.array(psi), (at_psi[-1] - at_psi[0]) / (len(at_psi) - 1)),
    ):
        tau, window = iat(x)
        out[f"{name}_mean"] = float(np.mean(x))
        out[f"{name}_sem"] = float(np.std(x, ddof=1) * math.sqrt(2.0 * tau / x.size))
        out[f"{name}_samples"] = len(x)
        out[f"{name}_interval"] = step
        out[f"tau_{name}"] = tau * step  # the integrated time, in lifts per disk
        out[f"tau_{name}_window"] = window * step
        out[f"tau_{name}_error"] = tau * step * math.sqrt(2.0 * (2 * window + 1) / x.size)  # Sokal's
        out[f"tau_{name}_resolved"] = tau > 1.0
        out[f"tau_{name}_short"] = len(x) < 100 * tau
    out["Z_mean"] = chain.observables.Z()  # (the ratio of the sums; its error from the blocks as above)
    return out


def show(r: dict, name: str) -> str:
    """tau of ``name`` as printed: an upper bound where not resolved, ``(short)`` where the run is."""
    s = f"{r[f'tau_{name}']:.3g} +- {r[f'tau_{name}_error']:.2g}"
    if not r[f"tau_{name}_resolved"]:
        s = f"< {r[f'{name}_interval']:.3g}"
    return s + (" (short)" if r[f"tau_{name}_short"] else "")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cells", type=int, nargs=2, default=(16, 16))
    ap.add_argument("--packing", type=float, default=0.70)
    ap.add_argument("--lifts", type=int, default=1_500_000, help="lifts per disk per variant")
    ap.add_argument("--every", type=int, default=5, help="lifts per disk per block of the pressure")
    ap.add_argument("--psi6", type=int, default=100, help="lifts per disk between |Psi6| samples")
    ap.add_argument("--equilibrate", type=int, default=50_000, help="straight lifts per disk first")
    ap.add_argument("--variants", nargs="+", default=["straight", "newtonian", "forward"])
    ap.add_argument("--out")
    args = ap.parse_args()
    state, box = hs.hexagonal(tuple(args.cells), args.packing)
    n = state.n
    t0 = time.process_time()
    eq = hs.EventChain(state, box, seed=1)
    eq.run(events=args.equilibrate * n).run(chains=1)
    start = eq.state()
    cpu = time.process_time() - t0
    print(f"N = {n}, packing {args.packing}, box {box.sides[0]:.4f} x {box.sides[1]:.4f}; "
          f"{args.equilibrate} straight lifts per disk first ({cpu:.0f} CPU s)")  # fmt: skip
    print("| variant | lifts per disk | Z | tau of Z (lifts per disk) | <\\|Psi6\\|> | tau of \\|Psi6\\| "
          "(lifts per disk) | CPU s with the sampling |")  # fmt: skip
    print("|---|---|---|---|---|---|---|")
    rows = []
    for variant in args.variants:
        r = series(start, box, variant, args.lifts, args.every, args.psi6)
        rows.append(r)

        z = f"{r['Z_mean']:.4f}({round(r['Z_sem'] * 1e4)})"
        psi = f"{r['psi6_mean']:.3f}({round(r['psi6_sem'] * 1e3)})"
        print(f"| {variant} | {r['lifts_per_disk']:.3g} | {z} | {show(r, 'Z')} | {psi} | {show(r, 'psi6')} "
              f"| {r['cpu_s']:.0f} |", flush=True)  # fmt: skip
    if args.out:
        with fileio.atomic_write(args.out, "w", newline="") as fh:
            w = csv.DictWriter(fh, fieldnames=list(rows[0]))
            w.writeheader()
            w.writerows(rows)
    print(f"CPU seconds in all: {time.process_time() - t0:.0f}")
    if any(math.isnan(r["tau_Z"]) for r in rows):
        print("a series was constant: no tau")


if __name__ == "__main__":
    main()

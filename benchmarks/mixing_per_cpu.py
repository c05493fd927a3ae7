"""Mixing per CPU second: event chains against event-driven dynamics, the pressure and |Psi6|.

Hard disks in the crystal's box (``hexagonal((nx, ny), packing)``, N = nx
ny): from the perfect crystal, ``--equilibrate`` lifts per disk of straight
event chains (seed 1).  From that same configuration each engine then runs
on its own for ``--cpu`` CPU seconds (one figure for both, or ECMC's and
EDMD's):

* ``ecmc``: ``hs.EventChain`` (straight, the default chain length; seed 2);
* ``edmd``: ``hs.Simulation``, event-driven molecular dynamics (velocities
  drawn at kT = 1, seed 2; ``EventChain.to_simulation``).

Each first runs a tenth of its budget (at least 2 CPU s) unmeasured, to
settle the velocities and to time itself; then its run is cut into
``--samples`` equal intervals (whole rounds of chains, one chain per axis;
or equal spans of time), about ``cpu / samples`` CPU seconds each.  Per
interval: the pressure of that interval (the engine's own blocks,
``observables.blocks("Z")``: the chains' lifting separations, the
dynamics' collision virial) and, at its end, ``|Psi6|`` (``hs.Hexatic``, 6
nearest neighbours).  The clock (``time.process_time``) runs only while
the engine does: computing ``|Psi6|`` is not counted (both engines would
pay the same).

The integrated autocorrelation time of each series (Sokal's window, c = 5),
``tau = 1/2 + sum of the autocorrelations`` samples, times the CPU seconds
per interval, is tau in CPU seconds: an average over a run of ``T`` CPU
seconds has the error of ``T / (2 tau)`` independent values, so the engine
with the smaller tau mixes more per CPU second.  Its error is Sokal's
``tau sqrt(2 (2W + 1) / n)`` (W the window, n the samples).  Only a tau
that means something is printed as a number: below one interval it is not
resolved (``< interval``); a run shorter than 50 tau, or a window that did
not close, gives a lower bound (``> tau``); a series whose halves differ
by more than 3 errors drifts (``drift``: tau is inflated by the drift, and
the means are not equilibrium values).

usage: nice -n 19 python3 benchmarks/mixing_per_cpu.py [--cells 29 30] [--packing 0.70]
    [--cpu 300 [EDMD's]] [--samples 4000] [--equilibrate 200000] [--engines ecmc edmd] [--out FILE]
"""

from __future__ import annotations

import argparse
import csv
import math
import os
import sys
import time

import numpy as np

import hardspheres as hs
from hardspheres import fileio

ENGINES = ("ecmc", "edmd")
MIN_RUN = 50.0  # run lengths in tau below which tau is a lower bound


def iat(x: np.ndarray) -> tuple[float, int, bool]:
    """tau in samples (Sokal's window, c = 5), the window, and whether the window closed."""
    x = np.asarray(x, float) - np.mean(x)
    n = x.size
    if n < 8 or not np.var(x) > 0:
        return math.nan, 0, False
    f = np.fft.rfft(x, 2 * n)
    acf = np.fft.irfft(f * np.conj(f))[:n] / (n * np.var(x))
    tau = 0.5
    for t in range(1, n // 2):
        tau += acf[t]
        if t >= 5.0 * tau:
            return max(tau, 0.5), t, True
    return max(tau, 0.5), n // 2, False


def psi6(state: hs.State, box: hs.PeriodicBox) -> float:
    """``|Psi6|`` of the disks (``hs.Hexatic``: 6 nearest neighbours)."""
    return hs.Hexatic(bins=4, r_max=2.0).compute(state, box.length).order


class Engine:
    """One engine behind one interface: advance by whole intervals, read the pressure blocks."""

    def __init__(self, name: str, start: hs.State, box: hs.PeriodicBox) -> None:
        self.name, self.box, self.n = name, box, start.n
        if name == "ecmc":
            self.sim = hs.EventChain(start, box, seed=2, variant="straight")
        else:
            self.sim = hs.EventChain(start, box, seed=2).to_simulation(kT=1.0, seed=2)
        self.d = box.dimensions

    def position(self) -> float:
        """Where the run is, in its own unit: rounds of chains, or time."""
        if self.name == "ecmc":
            return self.sim.counters["chains"] / self.d
        return self.sim.time

    def advance(self, span: float) -> None:
        """Run ``span`` rounds (ECMC, whole) or time units (EDMD) from now."""
        if self.name == "ecmc":
            self.sim.run(chains=self.d * max(1, round(span)))
        else:
            self.sim.run(until=self.sim.time + span)

    def lifts_or_collisions(self) -> int:
        c = self.sim.counters
        return int(c["events"] if self.name == "ecmc" else c["collisions"])


def series(name: str, start: hs.State, box: hs.PeriodicBox, cpu: float, samples: int) -> dict:
    """One engine's pressure and |Psi6| series and their correlation times in CPU seconds."""
    eng = Engine(name, start, box)
    # settle and time: about a tenth of the budget, in growing steps
    warm, step, t0 = max(2.0, 0.1 * cpu), 1.0, time.process_time()
    p0 = eng.position()
    while time.process_time() - t0 < warm:
        eng.advance(step)
        step *= 2.0 if time.process_time() - t0 < 0.5 * warm else 1.0
    per_cpu = (eng.position() - p0) / (time.process_time() - t0)  # rounds or time per CPU s
    span = per_cpu * cpu / samples
    if name == "ecmc":
        span = max(1, round(span))
        eng.sim.observables.reset(every=int(span))
    else:
        eng.sim.observables.reset(every=span)
    p0, e0 = eng.position(), eng.lifts_or_collisions()
    psi, engine_cpu = [], 0.0
    for _ in range(samples):
        t = time.process_time()
        eng.advance(span)
        engine_cpu += time.process_time() - t
        psi.append(psi6(eng.sim.state(), box))
    z = np.asarray(eng.sim.observables.blocks("Z"), float)[:samples]
    n = eng.n
    out = {"engine": name, "n": n, "packing": None, "cpu_s": engine_cpu, "samples": samples,
           "interval_cpu_s": engine_cpu / samples, "run": eng.position() - p0,
           "unit": "rounds" if name == "ecmc" else "time",
           "events_per_disk": (eng.lifts_or_collisions() - e0) / n,
           "events_per_cpu_s": (eng.lifts_or_collisions() - e0) / engine_cpu}  # fmt: skip
    for key, x in (("Z", z), ("psi6", np.array(psi))):
        tau, window, closed = iat(x)
        dt = out["interval_cpu_s"] * samples / x.size  # CPU s per sample of this series
        half = x.size // 2
        sem = float(np.std(x, ddof=1) * math.sqrt(2.0 * tau / x.size)) if math.isfinite(tau) else math.nan
        sem_half = sem * math.sqrt(2.0)
        out[f"{key}_mean"] = float(np.mean(x))
        out[f"{key}_sem"] = sem
        out[f"{key}_halves"] = (float(np.mean(x[:half])), float(np.mean(x[half:])))
        out[f"{key}_drift"] = bool(
            abs(np.mean(x[:half]) - np.mean(x[half:])) > 3.0 * math.hypot(sem_half, sem_half)
        )
        out[f"tau_{key}"] = tau * dt  # CPU s
        out[f"tau_{key}_error"] = tau * dt * math.sqrt(2.0 * (2 * window + 1) / x.size)
        out[f"tau_{key}_resolved"] = bool(tau > 1.0)
        out[f"tau_{key}_closed"] = closed
        out[f"tau_{key}_runs"] = engine_cpu / (tau * dt) if tau > 0 else math.nan  # run length in tau
        out[f"{key}_interval"] = dt
    out["Z_mean"] = eng.sim.observables.Z()  # the ratio of the sums over the whole run
    return out


def reliable(r: dict, key: str) -> bool:
    """Whether tau of ``key`` is a number worth printing (resolved, window closed, >= 50 tau, no drift)."""
    return bool(
        r[f"tau_{key}_resolved"]
        and r[f"tau_{key}_closed"]
        and r[f"tau_{key}_runs"] >= MIN_RUN
        and not r[f"{key}_drift"]
    )


def show(r: dict, key: str) -> str:
    """tau of ``key`` in CPU s as printed: a number only where it means something."""
    tau, err = r[f"tau_{key}"], r[f"tau_{key}_error"]
    if not math.isfinite(tau):
        return "constant series: no tau"
    if not r[f"tau_{key}_resolved"]:
        return f"< {r[f'{key}_interval']:.2g} (not resolved)"
    s = f"{tau:.3g} +- {err:.2g}"
    if not r[f"tau_{key}_closed"] or r[f"tau_{key}_runs"] < MIN_RUN:
        s = f"> {tau:.3g} (run {r[f'tau_{key}_runs']:.0f} tau: a lower bound)"
    if r[f"{key}_drift"]:
        s += " (drift)"
    return s


def ratios(rows: list[dict]) -> list[str]:
    """EDMD's tau over ECMC's, for each observable where both are numbers."""
    by = {r["engine"]: r for r in rows}
    if set(by) != set(ENGINES):
        return []
    out = []
    for key, label in (("Z", "the pressure"), ("psi6", "|Psi6|")):
        a, b = by["edmd"], by["ecmc"]
        if reliable(a, key) and reliable(b, key):
            q = a[f"tau_{key}"] / b[f"tau_{key}"]
            e = q * math.hypot(
                a[f"tau_{key}_error"] / a[f"tau_{key}"], b[f"tau_{key}_error"] / b[f"tau_{key}"]
            )
            out.append(f"tau of {label}, EDMD / ECMC: {q:.3g} +- {e:.2g} (CPU s per CPU s)")
        elif (
            reliable(b, key)
            and a[f"tau_{key}_resolved"]
            and not a[f"{key}_drift"]
            and math.isfinite(a[f"tau_{key}"])
        ):
            q = a[f"tau_{key}"] / b[f"tau_{key}"]
            out.append(
                f"tau of {label}, EDMD / ECMC: > {q:.3g} (EDMD's tau a lower bound: its run is too short)"
            )
        else:
            out.append(f"tau of {label}, EDMD / ECMC: not shown (a tau above is not a reliable number)")
    return out


def fail(msg: str) -> None:
    print(f"mixing_per_cpu.py: {msg}", file=sys.stderr)
    sys.exit(1)


FIELDS = [
    "engine", "n", "packing", "cpu_s", "samples", "interval_cpu_s", "run", "unit", "events_per_disk",
    "events_per_cpu_s", "Z_mean", "Z_sem", "Z_drift", "tau_Z", "tau_Z_error", "tau_Z_resolved",
    "tau_Z_closed", "tau_Z_runs", "psi6_mean", "psi6_sem", "psi6_drift", "tau_psi6", "tau_psi6_error",
    "tau_psi6_resolved", "tau_psi6_closed", "tau_psi6_runs",
]  # fmt: skip


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cells", type=int, nargs=2, default=(29, 30))
    ap.add_argument("--packing", type=float, default=0.70)
    ap.add_argument(
        "--cpu",
        type=float,
        nargs="+",
        default=[300.0],
        help="CPU seconds measured, each engine (or ECMC, EDMD)",
    )
    ap.add_argument("--samples", type=int, default=4000, help="intervals (samples of each series) per engine")
    ap.add_argument("--equilibrate", type=int, default=200_000, help="straight lifts per disk first")
    ap.add_argument("--engines", nargs="+", choices=ENGINES, default=list(ENGINES))
    ap.add_argument(
        "--out", help="CSV the rows are added to (a row of the same engine, N and packing replaced)"
    )
    args = ap.parse_args()
    if len(args.cpu) > 2 or not all(c > 0 and math.isfinite(c) for c in args.cpu):
        fail(f"--cpu {' '.join(map(str, args.cpu))}: give seconds > 0, one for both or ECMC's and EDMD's")
    cpu = {"ecmc": args.cpu[0], "edmd": args.cpu[-1]}
    if not 100 <= args.samples <= 60_000:
        fail(f"--samples {args.samples}: give 100 to 60000 intervals per engine")
    if args.equilibrate < 0:
        fail(f"--equilibrate {args.equilibrate}: give lifts per disk >= 0")
    try:
        state, box = hs.hexagonal(tuple(args.cells), args.packing)
    except ValueError as e:
        fail(f"--cells {args.cells[0]} {args.cells[1]} --packing {args.packing}: {e}")
    n = state.n
    t0 = time.process_time()
    eq = hs.EventChain(state, box, seed=1)
    eq.run(events=args.equilibrate * n).run(chains=1)
    start = eq.state()
    print(f"N = {n}, packing {args.packing}, box {box.sides[0]:.4f} x {box.sides[1]:.4f}; "
          f"{args.equilibrate} straight lifts per disk first ({time.process_time() - t0:.0f} CPU s); "
          f"CPU s per engine {cpu}, each in {args.samples} intervals")  # fmt: skip
    print("| engine | N | packing | CPU s | events per disk | Z | tau of Z (CPU s) | <\\|Psi6\\|> "
          "| tau of \\|Psi6\\| (CPU s) | events per CPU s |")  # fmt: skip
    print("|---|---|---|---|---|---|---|---|---|---|")
    rows = []
    for name in args.engines:
        r = series(name, start, box, cpu[name], args.samples)
        r["packing"] = args.packing
        rows.append(r)
        z = f"{r['Z_mean']:.4f}({round(r['Z_sem'] * 1e4)})"
        psi = f"{r['psi6_mean']:.3f}({round(r['psi6_sem'] * 1e3)})"
        print(f"| {name} | {n} | {args.packing:.3f} | {r['cpu_s']:.0f} | {r['events_per_disk']:.3g} "
              f"| {z} | {show(r, 'Z')} | {psi} | {show(r, 'psi6')} | {r['events_per_cpu_s']:.3g} |",
              flush=True)  # fmt: skip
    for line in ratios(rows):
        print(line)
    if args.out:
        old = []
        if os.path.exists(args.out):
            with open(args.out, newline="") as fh:
                old = list(csv.DictReader(fh))
        mine = {(r["engine"], str(r["n"]), f"{args.packing:g}") for r in rows}
        keep = [o for o in old if (o["engine"], o["n"], f"{float(o['packing']):g}") not in mine]
        with fileio.atomic_write(args.out, "w", newline="") as fh:
            w = csv.DictWriter(fh, FIELDS, extrasaction="ignore")
            w.writeheader()
            w.writerows(keep + rows)
    print(f"CPU seconds in all: {time.process_time() - t0:.0f}")


if __name__ == "__main__":
    main()

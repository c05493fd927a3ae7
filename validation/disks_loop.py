"""The hard-disk pressure loop (liquid-hexatic, area fraction 0.69-0.72) against published data.

Our event-driven MD against the sets of jellyfysh/HistoricDisks
(github.com/jellyfysh/HistoricDisks, commit 3afcb07, ``DigitizedData/``),
at the same N and box aspect ratio, at every packing they publish:

* small: N = 870 in the 29 : 30 sqrt(3)/2 box (29 disks per row, 30 rows:
  ``builders.hexagonal((29, 30), phi)``'s box), against Li, Nishikawa,
  Hoellmer, Maggs & Krauth, "Hard-disk computer simulations - a historic
  perspective", J. Chem. Phys. 157, 234111 (2022): ``ThisWork.csv``, set
  "ECMC, rift formula, N = 870, Aspect ratio = (29 : 30 sqrt(3)/2)",
  packings 0.690-0.718;
* large: N = 128^2 = 16384 in the sqrt(3)/2 box (``hexagonal((128, 128))``),
  against the same paper's set "MPMC, rift formula, N = 128^2, Aspect
  ratio = (1 : sqrt(3)/2)", packings 0.698-0.716.  Zollweg & Chester, PRB
  46, 11186 (1992), Table I (``Zollweg_1992.csv``, 128^2, same box) is
  drawn for context, not scored (other packings).

Each packing starts (``--start``) from random disks (``random``, the
default: ``hardspheres.random_spheres``), from a fluid at packing 0.60 grown
to the packing (``compressed``), or from the perfect hexagonal crystal
(``crystal``), equilibrates ``--equilibrate`` collisions per disk, then
measures ``--measure`` collisions per disk: ``beta P sigma^2 = Z 4 phi /
pi`` (sigma the diameter, the HistoricDisks unit ``beta P (2 sigma)^2``
with their sigma a radius), Z from the collision virial with its blocked
standard error (``hardspheres.observables``), scored by ``z = (ours -
theirs) / sqrt(err_ours^2 + err_theirs^2)``.  With ``--chunks K`` (K >=
20) the measurement is recorded in K pieces (beta P sigma^2 and |Psi6| of
each, in ``<csv>_series.csv``) and the error bar is the larger of the
run's and the chunk series' (:func:`chunk_errors`), with the series'
correlation times.  ``--seeds`` runs independent copies.  Rows are appended
to ``--csv`` as each run finishes (a rerun skips the packing, start and
seed already there), so a long run can be stopped and resumed.  ``plot``
draws the loop from the CSVs, ``table`` prints their tables, ``rescore``
recomputes the chunk errors from the series file, ``score`` combines all
runs of a packing over the CSVs given (weighted by length, :func:`score`),
``stays`` reads the series as a switching between two pressure levels
(stays, switches, time on each: :func:`stay_times`), and ``rate`` times
collisions per second at one size and packing (``--size``, ``--order``,
``--measure`` per disk, ``--repeat`` times).

usage:
    python3 validation/disks_loop.py small --csv validation/results/disks_loop_870.csv
    python3 validation/disks_loop.py small --csv validation/results/disks_loop_870_long.csv \
        --equilibrate 20000 --measure 200000 --chunks 40 --order 0.712 --start compressed
    python3 validation/disks_loop.py large --csv validation/results/disks_loop_16384.csv
    python3 validation/disks_loop.py large --csv validation/results/disks_loop_16384_crystal.csv \
        --equilibrate 5000 --measure 20000 --chunks 20 --order 0.716 --start crystal
    python3 validation/disks_loop.py plot --csv A.csv B.csv --png docs/images/disks_loop.png
    python3 validation/disks_loop.py score --csv A.csv B.csv
    python3 validation/disks_loop.py stays --csv validation/results/disks_loop_870_long.csv
    python3 validation/disks_loop.py rate --size large --order 0.716 --measure 300 --repeat 3

Running time (this machine, 2 cores shared, load 3-8): small with the
defaults (5000 + 50000 collisions per disk, 15 packings) about 25 min;
small with 20000 + 200000 per disk 140-330 s per packing and start; large
with ``--equilibrate 5000 --measure 40000`` 15-35 min per packing, with
``--equilibrate 5000 --measure 20000`` about 17 min.  Each run prints its
own running time.
"""

import argparse
import csv
import math
import os
import time

import hardspheres as hs
from hardspheres import fileio
from hardspheres.blocking import blocking
from hardspheres.builders import hexagonal

# (packing, beta P sigma^2, its error), sigma the diameter: copied from
# jellyfysh/HistoricDisks at commit 3afcb07 (DigitizedData/ThisWork.csv:
# "original data provided by the authors" of Li et al. 2022).
LI_870 = [
    (0.690, 8.969476, 0.000097),
    (0.692, 9.036875, 0.000060),
    (0.694, 9.08915, 0.00012),
    (0.696, 9.12293, 0.00012),
    (0.698, 9.13490, 0.00015),
    (0.700, 9.12956, 0.00017),
    (0.702, 9.11236, 0.00021),
    (0.704, 9.09028, 0.00038),
    (0.706, 9.06621, 0.00034),
    (0.708, 9.04532, 0.00089),
    (0.710, 9.0272, 0.0010),
    (0.712, 9.0122, 0.0022),
    (0.714, 9.0158, 0.0018),
    (0.716, 9.0450, 0.0026),
    (0.718, 9.0818, 0.0048),
]
LI_16384 = [
    (0.698, 9.17441, 0.00057),
    (0.704, 9.18700, 0.00091),
    (0.708, 9.17512, 0.00088),
    (0.712, 9.16590, 0.00094),
    (0.716, 9.1560, 0.0018),
]
# Zollweg & Chester 1992, Table I, 128^2, sqrt(3)/2 box (DigitizedData/Zollweg_1992/
# Zollweg_1992.csv): reduced density rho* and beta P V0 / N (V0 = N sqrt(3)/2 sigma^2),
# converted here to packing pi rho*/4 and beta P sigma^2 = (beta P V0/N) 2/sqrt(3).
_ZC = [(0.879, 7.762, 0.003), (0.885, 7.890, 0.004), (0.891, 7.940, 0.008), (0.898, 7.952, 0.008),
       (0.904, 7.941, 0.005), (0.91, 7.978, 0.007), (0.917, 8.034, 0.005)]  # fmt: skip
ZOLLWEG_16384 = [(math.pi * r / 4.0, p * 2.0 / math.sqrt(3.0), e * 2.0 / math.sqrt(3.0)) for r, p, e in _ZC]

SIZES = {
    "small": {"cells": (29, 30), "reference": LI_870, "label": "Li et al. 2022, ECMC"},
    "large": {"cells": (128, 128), "reference": LI_16384, "label": "Li et al. 2022, MPMC"},
}
FIELDS = [
    "n",
    "phi",
    "bp",
    "error",
    "Z",
    "Z_error",
    "psi6",
    "ref",
    "ref_error",
    "z",
    "equilibrate",
    "measure",
    "wall_s",
    "bp_first_half",
    "bp_second_half",
    "compressed",
    "start",
    "seed",
    "chunks",
    "error_run",
    "error_chunks",
    "chunks_converged",
    "tau_bp",
    "tau_psi6",
    "psi6_mean",
]
SERIES_FIELDS = ["phi", "start", "seed", "chunk", "per_disk", "bp", "psi6"]


START_PACKING = 0.60  # ``--start compressed``: the fluid grown to the packing


def _start(cells: tuple[int, int], phi: float, seed: int, start: str) -> hs.Simulation:
    """The simulation at ``phi`` from one of :data:`STARTS`.

    ``random``: random disks at ``phi`` (``hs.random_spheres``: at these
    packings a triangular lattice with vacancies, aligned with the box,
    which melts at once); ``compressed``: a fluid at packing 0.60 (500
    collisions per disk), grown to ``phi`` (``Simulation.compress``, rate
    10^-3); ``crystal``: the perfect hexagonal crystal filling the box
    (``builders.hexagonal``), the ordered side.
    """
    state, box = hexagonal(cells, phi, seed=seed)
    n = cells[0] * cells[1]
    if start == "crystal":
        return hs.Simulation(state, box)
    if start == "compressed":
        sim = hs.Simulation(hs.random_spheres(n, START_PACKING, box, seed=seed), box)
        sim.run(collisions=500 * n)
        res = sim.compress(packing=phi, rate=1e-3, pressure=None)
        if res.reason != "packing" or abs(sim.packing - phi) > 1e-9:
            raise RuntimeError(f"compression to {phi} stopped at {sim.packing} ({res.reason})")
        return sim
    if start != "random":
        raise ValueError(f"start {start!r}: give one of {', '.join(STARTS)}")
    return hs.Simulation(hs.random_spheres(n, phi, box, seed=seed), box)


STARTS = ("random", "compressed", "crystal")


def autocorrelation_time(x: list[float]) -> float:
    """Integrated autocorrelation time of a series, in samples (Sokal's window, c = 5).

    ``tau = 1/2 + sum_{t=1}^{W} rho(t)``, ``W`` the first lag with ``W >= 5
    tau``; the error of a mean is ``std sqrt(2 tau / n)``.  Returns ``nan``
    for fewer than 8 samples; a tau above n/10 is not to be trusted (the
    series is too short to see its own correlation).
    """
    n = len(x)
    if n < 8:
        return math.nan
    m = sum(x) / n
    d = [v - m for v in x]
    c0 = sum(v * v for v in d) / n
    if c0 == 0.0:
        return 0.5
    tau = 0.5
    for t in range(1, n // 2):
        tau += sum(d[i] * d[i + t] for i in range(n - t)) / (n * c0)
        if t >= 5.0 * tau:
            break
    return max(tau, 0.5)


def chunk_errors(bp: list[float], psi6: list[float], per_chunk: float) -> dict:
    """The error of the mean of a chunk series, and its correlation times in collisions per disk.

    ``error_chunks``: the larger of Flyvbjerg-Petersen blocking over the
    chunks (levels down to 8 blocks) and ``std sqrt(2 tau / n)``, tau the
    chunks' integrated autocorrelation time (:func:`autocorrelation_time`).
    """
    blocked = blocking(bp, min_blocks=8)
    mean = sum(bp) / len(bp)
    std = math.sqrt(sum((b - mean) ** 2 for b in bp) / (len(bp) - 1))
    tau, tau6 = autocorrelation_time(bp), autocorrelation_time(psi6)
    return {"error_chunks": max(blocked.sem, std * math.sqrt(2.0 * tau / len(bp))),
            "chunks_converged": float(blocked.converged), "tau_bp": tau * per_chunk,
            "tau_psi6": tau6 * per_chunk, "psi6_mean": sum(psi6) / len(psi6)}  # fmt: skip


def measure(
    cells: tuple[int, int],
    phi: float,
    equilibrate: int,
    collisions: int,
    seed: int,
    start: str = "random",
    chunks: int = 2,
) -> tuple[dict, list[dict]]:
    """One packing: start, equilibrate, measure; beta P sigma^2 with its error, and |Psi6|.

    The measurement runs in ``chunks`` equal pieces; after each, the
    piece's own beta P sigma^2 (from the running time average) and |Psi6|
    are recorded: the series (the second value returned).  With 20 chunks
    or more the error bar is the larger of the run's blocked standard
    error and the chunk series' (blocking over the chunks,
    ``hardspheres.blocking``, and ``std sqrt(2 tau / n)`` with tau the
    chunks' integrated autocorrelation time): a slow exchange between
    liquid-like and ordered states that the run's own blocks are too short
    to see shows there, as long as the run is longer than it.
    """
    t0 = time.time()
    sim = _start(cells, phi, seed, start)
    n = cells[0] * cells[1]
    sim.run(collisions=equilibrate * n)
    obs = sim.observables.reset()
    t_start = sim.time
    scale = 4.0 * phi / math.pi
    ends = [collisions * n * k // chunks for k in range(1, chunks + 1)]
    series, done, z_prev, t_prev = [], 0, 0.0, 0.0
    for k, end in enumerate(ends):
        sim.run(collisions=end - done)
        done = end
        z_cum, t_cum = obs.Z(), sim.time - t_start
        z_k = (z_cum * t_cum - z_prev * t_prev) / (t_cum - t_prev)  # Z is a time average
        series.append({"phi": phi, "start": start, "seed": seed, "chunk": k, "per_disk": end / n,
                       "bp": z_k * scale, "psi6": hs.Hexatic().compute(sim).order})  # fmt: skip
        z_prev, t_prev = z_cum, t_cum
        if k == chunks // 2 - 1:
            z_first, t_half = z_cum, t_cum
    z, err = obs.Z(), obs.error("Z")
    t_all = sim.time - t_start
    z_second = (z * t_all - z_first * t_half) / (t_all - t_half)
    row = {"n": n, "phi": phi, "bp": z * scale, "error": err * scale, "Z": z, "Z_error": err,
           "psi6": series[-1]["psi6"], "equilibrate": equilibrate, "measure": collisions,
           "bp_first_half": z_first * scale, "bp_second_half": z_second * scale,
           "compressed": float(start == "compressed"), "start": start, "seed": seed, "chunks": chunks,
           "error_run": err * scale}  # fmt: skip
    if chunks >= 20:
        row.update(chunk_errors([s["bp"] for s in series], [s["psi6"] for s in series], collisions / chunks))
        row["error"] = max(row["error"], row["error_chunks"])
    row["wall_s"] = time.time() - t0
    return row, series


def _read(path: str) -> list[dict]:
    """A CSV's rows, numbers as floats; ``start`` kept a word (older files: from ``compressed``)."""
    if not os.path.exists(path):
        return []
    with open(path, newline="") as f:
        rows = [{k: (v if k == "start" else float(v)) for k, v in row.items() if v not in (None, "")}
                for row in csv.DictReader(f)]  # fmt: skip
    for r in rows:
        r.setdefault("start", "compressed" if r.get("compressed") else "random")
        r["seed"] = int(r.get("seed", 1))
        if "chunk" in r:
            r["chunk"] = int(r["chunk"])
    return rows


def series_path(path: str) -> str:
    """Where the chunk series of the runs in CSV ``path`` go: ``..._series.csv`` beside it."""
    root, ext = os.path.splitext(path)
    return f"{root}_series{ext}"


def _write(path: str, rows: list[dict], fields: list[str] = FIELDS) -> None:
    with fileio.atomic_write(path, "w", newline="") as f:
        w = csv.DictWriter(f, fields, restval="")
        w.writeheader()
        w.writerows(rows)


def run(
    size: str,
    path: str,
    equilibrate: int,
    collisions: int,
    order: list[float] | None,
    start: str = "random",
    seeds: list[int] | None = None,
    chunks: int = 2,
) -> None:
    t0 = time.time()
    spec = SIZES[size]
    rows = _read(path)
    spath = series_path(path)
    series = _read(spath)
    done = {(round(r["phi"], 6), r["start"], int(r["seed"])) for r in rows}
    reference = {p: (v, e) for p, v, e in spec["reference"]}
    for phi in order or list(reference):
        for seed in seeds or [1]:
            if (round(phi, 6), start, seed) in done:
                continue
            row, ser = measure(spec["cells"], phi, equilibrate, collisions, seed, start, chunks)
            ref, ref_err = reference[phi]
            row.update(ref=ref, ref_error=ref_err, z=(row["bp"] - ref) / math.hypot(row["error"], ref_err))
            rows.append(row)
            rows.sort(key=lambda r: (r["phi"], r["start"], r["seed"]))
            if chunks >= 20:  # the series first: a row on file means its series is too
                series.extend(ser)
                _write(spath, series, SERIES_FIELDS)
            _write(path, rows)
            extra = ""
            if "tau_bp" in row:
                extra = (f", chunk error {row['error_chunks']:.4f} (run's {row['error_run']:.4f}), "
                         f"tau {row['tau_bp']:.0f} (Psi6 {row['tau_psi6']:.0f}) per disk")  # fmt: skip
            print(f"phi {phi:.3f} {start} seed {seed}: {row['bp']:.4f} +- {row['error']:.4f} against "
                  f"{ref:.4f} +- {ref_err:.4f}, z {row['z']:+.2f}, |Psi6| {row['psi6']:.3f}, "
                  f"halves {_halves(row)}{extra}, {row['wall_s']:.0f} s", flush=True)  # fmt: skip
    table(rows)
    print(f"running time: {time.time() - t0:.0f} s")


def rescore(path: str) -> None:
    """Recompute the chunk errors (and z) of CSV ``path``'s rows from their series file."""
    rows, series = _read(path), _read(series_path(path))
    for r in rows:
        if "tau_bp" not in r:
            continue
        run_key = (r["phi"], r["start"], r["seed"])
        ser = sorted(
            (s for s in series if (s["phi"], s["start"], s["seed"]) == run_key), key=lambda s: s["chunk"]
        )
        r.update(chunk_errors([s["bp"] for s in ser], [s["psi6"] for s in ser], r["measure"] / r["chunks"]))
        r["error"] = max(r["error_run"], r["error_chunks"])
        r["z"] = (r["bp"] - r["ref"]) / math.hypot(r["error"], r["ref_error"])
    _write(path, rows)
    table(rows)


def two_levels(values: list[float], sweeps: int = 50) -> tuple[float, float]:
    """The low and high level of a bistable series: two-means clustering, from its minimum and maximum."""
    lo, hi = min(values), max(values)
    for _ in range(sweeps):
        mid = 0.5 * (lo + hi)
        low = [v for v in values if v < mid]
        high = [v for v in values if v >= mid]
        if not low or not high:
            break
        lo, hi = sum(low) / len(low), sum(high) / len(high)
    return lo, hi


def stays(bp: list[float], lo: float, hi: float) -> list[tuple[str, int]]:
    """The stays of a chunk series on the two levels: (``low`` or ``high``, chunks), in order.

    With hysteresis: the state changes to high when a chunk is above ``lo +
    3/4 (hi - lo)``, to low when below ``lo + 1/4 (hi - lo)``; the first
    chunk's state is its nearer level.  The last stay is cut by the end of
    the run (censored).
    """
    up, down = lo + 0.75 * (hi - lo), lo + 0.25 * (hi - lo)
    state = "low" if bp[0] < 0.5 * (lo + hi) else "high"
    states, lengths = [state], [0]
    for b in bp:
        if state == "low" and b > up:
            state = "high"
        elif state == "high" and b < down:
            state = "low"
        if state != states[-1]:
            states.append(state)
            lengths.append(0)
        lengths[-1] += 1
    return list(zip(states, lengths, strict=True))


def stay_times(paths: list[str]) -> dict[tuple[int, float], dict]:
    """Two-level analysis of the chunk series of CSVs ``paths``' runs, by N and packing.

    For each packing: the levels (:func:`two_levels` over the chunks of all
    its runs), and per run and pooled the fraction of time on the low level,
    the number of switches and the mean stay on each level, estimated as
    the time spent on it over the number of times it was left (the
    maximum-likelihood mean of exponential stays with the last one cut
    off; with no exit, the time spent is only a lower bound).  ``tau_c``:
    the integrated correlation time of a two-state Markov process with
    these mean stays, ``tau_low tau_high / (tau_low + tau_high)``; the
    error of a mean over a run of T is then ``(hi - lo) sqrt(p (1 - p) 2
    tau_c / T)``, p the low fraction.  Of runs with the same start and seed
    (one trajectory) only the longest is read.
    """
    runs: dict[tuple[int, float], dict[tuple, list[dict]]] = {}
    per_chunk: dict[tuple, float] = {}
    longest: dict[tuple, dict] = {}  # one trajectory per start and seed (see score)
    for path in paths:
        if not path.endswith("_series.csv"):
            for r in _read(path):
                same = (int(r["n"]), round(r["phi"], 6), r["start"], r["seed"])
                if "tau_bp" in r and (same not in longest or _length(r) > _length(longest[same])):
                    longest[same] = r | {"path": path}
    for path in dict.fromkeys(r["path"] for r in longest.values()):
        ser = _read(series_path(path))
        for r in (r for r in longest.values() if r["path"] == path):
            key = (path, r["phi"], r["start"], r["seed"])
            chunks = sorted((s for s in ser if (s["phi"], s["start"], s["seed"]) == key[1:]),
                            key=lambda s: s["chunk"])  # fmt: skip
            runs.setdefault((int(r["n"]), round(r["phi"], 6)), {})[key] = chunks
            per_chunk[key] = r["measure"] / r["chunks"]
    out = {}
    for n_phi, group in sorted(runs.items()):
        lo, hi = two_levels([s["bp"] for g in group.values() for s in g])
        pooled = {"low": 0.0, "high": 0.0, "exits_low": 0, "exits_high": 0}
        per_run = []
        for key, chunks in group.items():
            st = stays([s["bp"] for s in chunks], lo, hi)
            t = {"low": 0.0, "high": 0.0}
            for s, k in st:
                t[s] += k * per_chunk[key]
            exits = {"low": sum(s == "low" for s, _ in st[:-1]), "high": sum(s == "high" for s, _ in st[:-1])}
            per_run.append({"run": key, "stays": [(s, k * per_chunk[key]) for s, k in st], "low": t["low"],
                            "high": t["high"], "switches": len(st) - 1})  # fmt: skip
            for s in ("low", "high"):
                pooled[s] += t[s]
                pooled[f"exits_{s}"] += exits[s]
        tau = {s: pooled[s] / max(pooled[f"exits_{s}"], 1) for s in ("low", "high")}
        total = pooled["low"] + pooled["high"]
        out[n_phi] = {"lo": lo, "hi": hi, "runs": per_run, "time": total, "p_low": pooled["low"] / total,
                    "exits_low": pooled["exits_low"], "exits_high": pooled["exits_high"],
                    "tau_low": tau["low"], "tau_high": tau["high"],
                    "tau_c": tau["low"] * tau["high"] / (tau["low"] + tau["high"])}  # fmt: skip
    return out


def print_stays(paths: list[str]) -> None:
    """The two-level tables of :func:`stay_times` (levels, stays, switches, low fraction)."""
    ref = {(870, p): v for p, v, _ in LI_870} | {(16384, p): v for p, v, _ in LI_16384}
    for (n, phi), a in stay_times(paths).items():
        gap = a["hi"] - a["lo"]
        print(f"\nN {n}, packing {phi:.3f}: levels {a['lo']:.4f}, {a['hi']:.4f} (gap {gap:.4f})")
        print("| run | stays (l low, h high: collisions per disk) | switches | low fraction |")
        print("|---|---|---|---|")
        for r in a["runs"]:
            path, _, start, seed = r["run"]
            text = ", ".join(f"{s[0]}: {k:.0f}" for s, k in r["stays"])
            low = r["low"] / (r["low"] + r["high"])
            print(f"| {os.path.basename(path)} {start} seed {seed} | {text} | {r['switches']} | {low:.2f} |")
        bound = {s: (">" if a[f"exits_{s}"] == 0 else "") for s in ("low", "high")}
        print(f"pooled over {a['time']:.3g} collisions per disk: low fraction {a['p_low']:.3f}, "
              f"exits low {a['exits_low']}, high {a['exits_high']}; mean stay "
              f"low {bound['low']}{a['tau_low']:.3g}, high {bound['high']}{a['tau_high']:.3g}; "
              f"tau_c {a['tau_c']:.3g} collisions per disk")  # fmt: skip
        if (n, phi) in ref and gap > 0:
            p_ref = (a["hi"] - ref[n, phi]) / gap
            print(f"the published {ref[n, phi]:.4f}: low fraction {p_ref:.3f} between these levels")


def rate(size: str, phi: float, per_disk: int, repeat: int, start: str = "random", seed: int = 1) -> None:
    """Collisions per second of the runs at one size and packing: ``repeat`` runs of ``per_disk`` each.

    After the start and 20 collisions per disk (the compiled core loaded);
    wall-clock and CPU seconds (``time.process_time``, less sensitive to
    the other jobs on the machine) and the load average around each run.
    """
    cells = SIZES[size]["cells"]
    n = cells[0] * cells[1]
    sim = _start(cells, phi, seed, start)
    sim.run(collisions=20 * n)
    for _ in range(repeat):
        load0 = os.getloadavg()[0]
        wall, cpu = time.perf_counter(), time.process_time()
        sim.run(collisions=per_disk * n)
        wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
        c = per_disk * n
        print(f"N {n}, packing {phi:.3f}, {start}: {c} collisions in {wall:.2f} s wall, {cpu:.2f} s CPU: "
              f"{c / wall:.3g} per s wall, {c / cpu:.3g} per CPU s; load {load0:.2f} -> "
              f"{os.getloadavg()[0]:.2f}", flush=True)  # fmt: skip


def _length(r: dict) -> float:
    return r["equilibrate"] + r["measure"]


def score(paths: list[str]) -> None:
    """One estimate per N and packing from every run in CSVs ``paths``, weighted by its length.

    The mean of the runs weighted by their measured collisions per disk
    ``w``; its error the larger of the runs' own errors combined, ``sqrt(sum
    w^2 e^2) / sum w`` (each ``e`` a run's error bar: with chunks, the larger
    of its blocked error and its chunk series', :func:`chunk_errors`), and
    the spread of the runs about the mean, ``sqrt(k / (k - 1) sum w^2 (b -
    mean)^2) / sum w`` for k runs; z against the published value.  Runs
    with the same start and seed follow the same trajectory (a shorter one
    is the longer one's beginning, whatever the split into equilibration
    and measurement): only the longest is counted.
    """
    longest: dict[tuple, dict] = {}
    for p in paths:
        if not p.endswith("_series.csv"):
            for r in _read(p):
                key = (int(r["n"]), round(r["phi"], 6), r["start"], r["seed"])
                if key not in longest or _length(r) > _length(longest[key]):
                    longest[key] = r
    groups: dict[tuple[int, float], list[dict]] = {}
    for r in longest.values():
        groups.setdefault((int(r["n"]), round(r["phi"], 6)), []).append(r)
    print("| N | packing | runs | collisions per disk measured | ours, beta P sigma^2 "
          "| from the runs' errors | from their spread | published | z |")  # fmt: skip
    print("|---|---|---|---|---|---|---|---|---|")
    for (n, phi), g in sorted(groups.items()):
        w = [r["measure"] for r in g]
        total = sum(w)
        mean = sum(wi * r["bp"] for wi, r in zip(w, g, strict=True)) / total
        within = math.sqrt(sum((wi * r["error"]) ** 2 for wi, r in zip(w, g, strict=True))) / total
        k = len(g)
        dev = sum((wi * (r["bp"] - mean)) ** 2 for wi, r in zip(w, g, strict=True))
        between = math.sqrt(k / (k - 1) * dev) / total if k > 1 else math.nan
        err = max(within, between) if k > 1 else within
        ref, ref_err = g[0]["ref"], g[0]["ref_error"]
        z = (mean - ref) / math.hypot(err, ref_err)
        print(f"| {n} | {phi:.3f} | {k} | {total:.3g} | {mean:.4f} +- {err:.4f} | {within:.4f} | "
              f"{between:.4f} | {ref:.4f} +- {ref_err:.4f} | {z:+.2f} |")  # fmt: skip


BUDGET_EQUILIBRATE, BUDGET_MEASURE = 5, 50  # a run: 5 correlation times dropped, 50 measured


def budget(paths: list[str], rate: float, starts: int = 2) -> None:
    """What runs at N = 16384 would cost, scaled from the N = 870 series of CSVs ``paths``.

    For each packing of :data:`LI_16384` measured at N = 870: the
    correlation time there, the larger of the two-state ``tau_c``
    (:func:`stay_times`) and the longest ``tau_bp`` of its runs (the chunk
    series' integrated time); scaled to 16384 disks by ``16384 / 870``
    (the assumption: ordered and liquid-like regions rearrange over the
    box, diffusively, in a time ~ L^2 ~ N at fixed packing); per start
    ``BUDGET_EQUILIBRATE`` correlation times dropped and ``BUDGET_MEASURE``
    measured (enough blocks for an error bar good to about 15%), for
    ``starts`` starts; core-hours at ``rate`` collisions per CPU second.
    """
    small = SIZES["small"]["cells"][0] * SIZES["small"]["cells"][1]
    large = SIZES["large"]["cells"][0] * SIZES["large"]["cells"][1]
    lengths = stay_times(paths)
    taus: dict[float, float] = {}
    for p in paths:
        if not p.endswith("_series.csv"):
            for r in _read(p):
                if "tau_bp" in r and int(r["n"]) == small:
                    phi = round(r["phi"], 6)
                    taus[phi] = max(taus.get(phi, 0.0), r["tau_bp"])
    per = BUDGET_EQUILIBRATE + BUDGET_MEASURE
    print(f"scaled by {large} / {small} = {large / small:.1f}; {starts} starts x ({BUDGET_EQUILIBRATE} + "
          f"{BUDGET_MEASURE}) correlation times; {rate:.3g} collisions per CPU second")  # fmt: skip
    print("| packing | tau at N = 870: two-state, chunk series | at N = 16384 | collisions per disk, "
          "all starts | core-hours |")  # fmt: skip
    print("|---|---|---|---|---|")
    total = 0.0
    for phi, _, _ in LI_16384:
        if phi not in taus:
            print(f"| {phi:.3f} | not measured | | | |")
            continue
        tau_c = lengths[small, phi]["tau_c"] if (small, phi) in lengths else math.nan
        tau = max(taus[phi], tau_c) * large / small
        per_disk = starts * per * tau
        hours = per_disk * large / rate / 3600.0
        total += hours
        print(f"| {phi:.3f} | {tau_c:.3g}, {taus[phi]:.3g} | {tau:.3g} | {per_disk:.3g} | {hours:.0f} |")
    print(f"all measured packings: {total:.0f} core-hours")


def _halves(r: dict) -> str:
    """The first and second halves of the measurement (a drift shows there), if recorded."""
    if "bp_first_half" not in r:
        return "-"
    return f"{r['bp_first_half']:.4f}, {r['bp_second_half']:.4f}"


def table(rows: list[dict]) -> None:
    """The Markdown tables of one CSV's rows: the runs; the runs of one packing and length together.

    Together: their mean, its error the larger of their errors combined and
    their standard error about the mean; the spread's z the largest minus
    the smallest over their combined error (above 3: the runs disagree,
    their error bars are too small).  Then the chunk errors, if recorded.
    """
    print(
        "| N | packing | start | ours, beta P sigma^2 | published | z | \\|Psi6\\| | collisions per disk",
        end="",
    )
    print(" | first, second half |")
    print("|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        seed = f", seed {r['seed']:.0f}" if r["seed"] != 1 else ""
        print(f"| {r['n']:.0f} | {r['phi']:.3f} | {r['start']}{seed} | {r['bp']:.4f} +- {r['error']:.4f} | "
              f"{r['ref']:.4f} +- {r['ref_error']:.4f} | {r['z']:+.2f} | {r['psi6']:.3f} | "
              f"{r['equilibrate']:.0f} + {r['measure']:.0f} | {_halves(r)} |")  # fmt: skip
    if rows:
        worst = max(rows, key=lambda r: abs(r["z"]))
        print(f"\nlargest |z| {abs(worst['z']):.2f} (packing {worst['phi']:.3f}); |z| <= 3 at "
              f"{sum(abs(r['z']) <= 3 for r in rows)} of {len(rows)} runs")  # fmt: skip
    groups: dict[tuple, list[dict]] = {}
    for r in rows:
        groups.setdefault((r["n"], r["phi"], r["equilibrate"], r["measure"]), []).append(r)
    groups = {k: g for k, g in groups.items() if len(g) > 1}
    if groups:
        print(
            "\n| N | packing | runs (starts, seeds) | mean of the runs | z of their spread | z of the mean |"
        )
        print("|---|---|---|---|---|---|")
        for (n, phi, _, _), g in groups.items():
            bp = [r["bp"] for r in g]
            mean = sum(bp) / len(bp)
            spread = math.sqrt(sum((b - mean) ** 2 for b in bp) / (len(bp) - 1) / len(bp))
            err = max(math.sqrt(sum(r["error"] ** 2 for r in g)) / len(g), spread)
            lo, hi = min(g, key=lambda r: r["bp"]), max(g, key=lambda r: r["bp"])
            z_spread = (hi["bp"] - lo["bp"]) / math.hypot(hi["error"], lo["error"])
            z = (mean - g[0]["ref"]) / math.hypot(err, g[0]["ref_error"])
            score = f"{z:+.2f}" if z_spread <= 3.0 else "- (the runs disagree)"
            print(f"| {n:.0f} | {phi:.3f} | {len(g)} | {mean:.4f} +- {err:.4f} | {z_spread:.2f} | {score} |")
    chunked = [r for r in rows if "tau_bp" in r]
    if chunked:
        print("\n| N | packing | start | chunk error | run's error | chunk blocks converged | tau of beta P, "
              "of \\|Psi6\\| (collisions per disk) | mean \\|Psi6\\| |")  # fmt: skip
        print("|---|---|---|---|---|---|---|---|")
        for r in chunked:
            print(f"| {r['n']:.0f} | {r['phi']:.3f} | {r['start']} | {r['error_chunks']:.4f} | "
                  f"{r['error_run']:.4f} | {'yes' if r['chunks_converged'] else 'no'} | "
                  f"{r['tau_bp']:.0f}, {r['tau_psi6']:.0f} | {r['psi6_mean']:.3f} |")  # fmt: skip


STYLE = {
    "random": ("o", "random start"),
    "compressed": ("^", "compressed from 0.60"),
    "crystal": ("s", "crystal"),
}
COLOURS = ("tab:red", "tab:blue", "tab:purple", "tab:orange", "tab:cyan", "tab:brown")


def _ecmc_points(paths: list[str]) -> dict[str, list[dict]]:
    """validation/ecmc_loop.py's runs in the published boxes: the longest of each packing and start."""
    longest: dict[tuple[str, float, str], dict] = {}
    for path in paths:
        with open(path, newline="") as f:
            for r in csv.DictReader(f):
                size = {"crystal": "small", "large": "large"}.get(r["box"])
                if size is None:
                    continue  # (the 1 : 1 box: no event dynamics there)
                row = {"phi": float(r["phi"]), "bp": float(r["bp"]), "error": float(r["error"]),
                       "length": float(r["equilibrate"]) + float(r["lifts"])}  # fmt: skip
                k = (size, round(row["phi"], 6), r["start"])
                if k not in longest or row["length"] > longest[k]["length"]:
                    longest[k] = row
    out: dict[str, list[dict]] = {"small": [], "large": []}
    for (size, _, _), row in longest.items():
        out[size].append(row)
    return out


def plot(paths: list[str], png: str, ecmc: list[str] | None = None) -> None:
    """The loop at both sizes: our runs over the published sets; ``ecmc``: event-chain CSVs drawn too."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5), layout="constrained")
    sets = [
        ("small", LI_870, "N = 870, 29 : 30 sqrt(3)/2 box", []),
        ("large", LI_16384, "N = 128^2 = 16384, sqrt(3)/2 box", [("Zollweg & Chester 1992", ZOLLWEG_16384)]),
    ]
    rows = [r for p in paths if not p.endswith("_series.csv") for r in _read(p)]  # a glob takes the series
    chains = _ecmc_points([p for p in ecmc or [] if not p.endswith("_series.csv")])
    for ax, (size, ref, title, extra) in zip(axes, sets, strict=True):
        n = SIZES[size]["cells"][0] * SIZES[size]["cells"][1]
        p, v, e = zip(*ref, strict=True)
        ax.errorbar(p, v, e, fmt="-", color="0.5", lw=1.5, label=SIZES[size]["label"])
        for name, data in extra:
            p, v, e = zip(*[d for d in data if 0.688 <= d[0] <= 0.722], strict=True)
            ax.errorbar(p, v, e, fmt="s", ms=3, color="tab:green", mfc="none", capsize=2, label=name)

        def key(r: dict) -> tuple[float, float, str]:
            return (r["equilibrate"] + r["measure"], r["equilibrate"], r["start"])

        mine = [r for r in rows if r["n"] == n]

        def same(r: dict) -> tuple[float, str, int]:
            return (round(r["phi"], 6), r["start"], r["seed"])

        # a run is superseded where a longer one has the same packing, start and seed (score's rule)
        longest: dict[tuple[float, str, int], float] = {}
        for r in mine:
            longest[same(r)] = max(longest.get(same(r), 0.0), key(r)[0])
        for k, run_key in enumerate(sorted({key(r) for r in mine})):
            ours = [r for r in mine if key(r) == run_key]
            marker, start = STYLE[run_key[2]]
            label = f"hardspheres EDMD, {start}, {run_key[1]:.0f} + {run_key[0] - run_key[1]:.0f} per disk"
            for short in (False, True):  # superseded points open and faded
                pts = [r for r in ours if (run_key[0] < longest[same(r)]) == short]
                if not pts:
                    continue
                ax.errorbar(
                    [r["phi"] + 0.00025 * k + 0.0001 * (r["seed"] - 1) for r in pts],
                    [r["bp"] for r in pts],
                    [r["error"] for r in pts],
                    fmt=marker,
                    ms=4,
                    color=COLOURS[k % len(COLOURS)],
                    mfc="none" if short else None,
                    alpha=0.55 if short else 1.0,
                    capsize=3,
                    label=label,
                )
                label = "_nolegend_"
        if chains[size]:
            pts = chains[size]
            ax.errorbar([r["phi"] - 0.0003 for r in pts], [r["bp"] for r in pts], [r["error"] for r in pts],
                        fmt="D", ms=3.5, color="black", capsize=2,
                        label="hardspheres event chains, longest run of each start")  # fmt: skip
        ax.set(title=title, xlabel="packing fraction", ylabel="beta P sigma^2 (sigma: diameter)")
        ax.legend(fontsize=6.5, loc="best")
    with fileio.atomic_path(png) as tmp:
        fig.savefig(tmp, dpi=110, format="png")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    what = ["small", "large", "plot", "table", "rescore", "stays", "rate", "score", "budget"]
    ap.add_argument("what", choices=what)
    ap.add_argument("--csv", nargs="+", help="the CSV(s) written or read (all but rate)")
    ap.add_argument("--size", choices=list(SIZES), default="large", help="rate: the system")
    ap.add_argument("--equilibrate", type=int, default=5000, help="collisions per disk before measuring")
    ap.add_argument("--measure", type=int, default=50000, help="collisions per disk measured")
    ap.add_argument("--order", type=float, nargs="+", help="packings to run, in this order (default: all)")
    ap.add_argument("--repeat", type=int, default=3, help="rate: timed runs of --measure per disk")
    ap.add_argument("--rate", type=float, default=5e5, help="budget: collisions per CPU second at 16384")
    ap.add_argument("--png", default="docs/images/disks_loop.png")
    ap.add_argument("--ecmc", nargs="+", help="plot: validation/ecmc_loop.py CSVs drawn over the loop too")
    ap.add_argument("--start", choices=STARTS, default="random", help="the start (see _start)")
    ap.add_argument("--compressed", action="store_true", help="the same as --start compressed")
    ap.add_argument("--seeds", type=int, nargs="+", help="independent runs at each packing (default: 1)")
    ap.add_argument(
        "--chunks",
        type=int,
        default=2,
        help="pieces of the measurement recorded (>= 20: series, chunk error)",
    )
    args = ap.parse_args()
    if args.chunks < 2 or args.chunks % 2:
        ap.error(f"--chunks {args.chunks}: give an even number >= 2")
    start = "compressed" if args.compressed else args.start
    if args.what != "rate" and not args.csv:
        ap.error(f"{args.what}: give --csv")
    if args.what == "plot":
        plot(args.csv, args.png, args.ecmc)
    elif args.what == "table":
        for p in args.csv:
            if not p.endswith("_series.csv"):
                table(_read(p))
    elif args.what == "rate":
        rate(args.size, args.order[0] if args.order else 0.716, args.measure, args.repeat, start)
    elif args.what == "budget":
        budget(args.csv, args.rate)
    elif args.what == "score":
        score(args.csv)
    elif args.what == "stays":
        print_stays(args.csv)
    elif args.what == "rescore":
        for p in args.csv:
            if not p.endswith("_series.csv") and os.path.exists(series_path(p)):
                rescore(p)
    else:
        run(
            args.what, args.csv[0], args.equilibrate, args.measure, args.order, start, args.seeds, args.chunks
        )


if __name__ == "__main__":
    main()

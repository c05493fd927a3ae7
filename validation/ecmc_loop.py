"""The hard-disk pressure loop at N = 870 (and 128^2) by straight event chains, against Li et al. 2022.

870 disks (diameter 1) in a periodic box of the published shapes: ``crystal``,
the 29 : 30 sqrt(3)/2 box of the 29 x 30 triangular crystal
(``hs.hexagonal((29, 30), phi)``), or ``square`` (1 : 1); or ``large``:
128^2 = 16384 disks in the 1 : sqrt(3)/2 box of the 128 x 128 crystal.
Straight event chains (``hs.EventChain``, variant "straight", chain length
0.24 of the box's square root: Li et al.'s StraightECMC), from these starts:

* ``liquid``: random disks at packing 0.60, 500 collisions per disk of event
  dynamics, grown to the packing (``Simulation.compress``, rate 10^-3), then
  handed to the chains (``EventChain.from_simulation``);
* ``crystal``: the perfect triangular crystal filling the crystal box
  (``hs.hexagonal``); in the square box, where no crystal fits,
  ``hs.random_spheres`` at the packing (a triangular lattice with vacancies,
  aligned with the box);
* ``solid``: the liquid start's disks grown to 0.74 instead, 2x10^5 lifts
  per disk of chains there (a solid that chooses its own fit to the box),
  then expanded to the packing (every position scaled by the ratio of the
  boxes' sides): the ordered start of the square box, where the lattice
  start can stay stuck in a strained crystal.

Each run: ``--equilibrate`` lifts per disk, then ``--lifts`` lifts per disk
measured in ``--chunks`` equal pieces; per chunk its own beta P sigma^2 (from
the chains' running totals) and ``|Psi6|`` at the chunk's end (a chain end).
The error is the larger of the run's blocking error (``observables``) and
the chunk series' (blocking over the chunks down to 8 blocks, and ``std
sqrt(2 tau / n)`` with tau their integrated autocorrelation time), as in
validation/disks_loop.py.  ``z = (ours - theirs) / sqrt(err_ours^2 +
err_theirs^2)``.

The published values: jellyfysh/HistoricDisks at commit 3afcb07,
``DigitizedData/ThisWork.csv`` ("original data provided by the authors" of
B. Li, Y. Nishikawa, P. Hoellmer, L. Carillo, A. C. Maggs and W. Krauth, J.
Chem. Phys. 157, 234111 (2022)), the sets "ECMC, rift formula, N = 870",
aspect ratios 29 : 30 sqrt(3)/2 and 1 : 1, and at 128^2 "MPMC, rift
formula, N = 128^2" (validation/disks_loop.py's ``LI_16384``), in ``beta P
(2 sigma)^2`` with sigma a radius: our ``beta P d^2``, d the diameter.

Results: one row per run appended to ``--csv`` (default
validation/results/ecmc_loop_870.csv; the chunk series beside it, ``_series``)
and the table to ``.md`` beside it, each rewritten atomically after every
run; a rerun skips the (box, packing, start, seed) already there.  ``--budget``
CPU seconds and ``--deadline`` wall seconds: no run starts that the rates so
far say would not finish within them.  ``--checkpoint DIR``: each run is
saved in DIR after its equilibration and after every chunk (the chains,
``EventChain.save``, and the series so far), and a run found there is
resumed from its last chunk, bit for bit (a run of half a CPU-hour or more
then survives an interruption); the files go once its row is
written.  A run resumes into any length of the same ``--equilibrate`` and
lifts per chunk (``--lifts / --chunks``) that it has not passed: the
first k chunks of a longer run are a run of k chunks.  ``table`` prints the table of the CSV again;
``plot`` draws the runs of one or more CSVs over the published loop, one panel per box
(where a longer run has the same box, packing and start, the shorter is drawn open and faded);
``states`` splits one packing's chunk series between the two states of the loop's minimum.

usage:
    nice -n 10 python3 validation/ecmc_loop.py run [--box crystal|square|large] [--packings 0.700 0.716 ...]
        [--starts liquid crystal solid] [--equilibrate 300000] [--lifts 3000000] [--chunks 40] [--budget 3600]
        [--deadline 4200] [--csv FILE] [--checkpoint DIR]
    python3 validation/ecmc_loop.py table [--csv FILE]
    python3 validation/ecmc_loop.py plot --csv FILE [FILE ...] [--png docs/images/ecmc_loop.png]
    python3 validation/ecmc_loop.py states --csv FILE --packings 0.718 [--seed 2] [--split 9.1]
"""

from __future__ import annotations

import argparse
import csv
import json
import math
import os
import time
from typing import TYPE_CHECKING

import numpy as np

import hardspheres as hs
from hardspheres import fileio
from hardspheres.blocking import blocking

try:
    from disks_loop import LI_870 as LI_870_CRYSTAL_BOX  # run as a script: validation/ is on the path
    from disks_loop import LI_16384
except ImportError:  # loaded from a file (the tests)
    import sys

    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from disks_loop import LI_870 as LI_870_CRYSTAL_BOX
    from disks_loop import LI_16384

if TYPE_CHECKING:
    import matplotlib.axes

CELLS = (29, 30)
N = CELLS[0] * CELLS[1]
CRYSTAL_CELLS = {"crystal": CELLS, "large": (128, 128)}  # the boxes a perfect crystal fills

# (packing, beta P d^2, its error): jellyfysh/HistoricDisks at commit 3afcb07,
# DigitizedData/ThisWork.csv, "ECMC, rift formula, N = 870", the two boxes (the
# crystal box's set is validation/disks_loop.py's LI_870).
LI_870 = {
    "crystal": LI_870_CRYSTAL_BOX,
    "square": [
        (0.690, 8.969898, 0.000075), (0.692, 9.03666, 0.00011), (0.694, 9.089054, 0.000083),
        (0.696, 9.12212, 0.00016), (0.698, 9.13414, 0.00022), (0.700, 9.12966, 0.00015),
        (0.702, 9.11472, 0.00016), (0.704, 9.09681, 0.00035), (0.706, 9.08175, 0.00031),
        (0.708, 9.07174, 0.00036), (0.710, 9.06469, 0.00043), (0.712, 9.0541, 0.0013),
        (0.714, 9.0310, 0.0032), (0.716, 9.0272, 0.0049), (0.718, 9.0507, 0.0040),
    ],
}  # fmt: skip
LI = {**LI_870, "large": LI_16384}
BOXES = {"crystal": "29 : 30 sqrt(3)/2", "square": "1 : 1", "large": "128 : 128 sqrt(3)/2"}
STARTS = ("liquid", "crystal", "solid")
START_PACKING = 0.60
SOLID_PACKING = 0.74  # the solid start: grown to here, chains, then expanded
SOLID_LIFTS = 200_000  # lifts per disk of chains at SOLID_PACKING
FIELDS = [
    "box", "phi", "start", "seed", "bp", "error", "error_run", "error_chunks", "chunks_converged",
    "ref", "ref_error", "z", "bp_first_half", "bp_second_half", "psi6_mean", "psi6_last",
    "tau_bp", "tau_psi6", "equilibrate", "lifts", "chunks", "cpu_s", "cpu_s_start", "wall_s",
]  # fmt: skip
SERIES_FIELDS = ["box", "phi", "start", "seed", "chunk", "per_disk", "bp", "psi6"]


def size(box: str) -> int:
    """The number of disks in ``box``: 870, or 128^2 in the ``large`` box."""
    cells = CRYSTAL_CELLS.get(box, CELLS)
    return cells[0] * cells[1]


def reference(box: str, phi: float) -> tuple[float, float]:
    """Li et al.'s beta P d^2 and its error at ``phi`` in ``box`` (``nan`` if not published)."""
    for p, v, e in LI[box]:
        if abs(p - phi) < 1e-9:
            return v, e
    return math.nan, math.nan


def make_box(box: str, phi: float) -> hs.PeriodicBox:
    """The periodic box of the disks (diameter 1) of ``box`` at area fraction ``phi``."""
    if box in CRYSTAL_CELLS:
        return hs.hexagonal(CRYSTAL_CELLS[box], phi)[1]
    return hs.PeriodicBox.for_packing(N, phi, (1.0, 1.0))


def grown(box: str, phi: float, seed: int) -> hs.Simulation:
    """Random disks at packing 0.60, 500 collisions per disk of event dynamics, grown to ``phi``."""
    n, pbox = size(box), make_box(box, phi)
    sim = hs.Simulation(hs.random_spheres(n, START_PACKING, pbox, seed=seed), pbox)
    sim.run(collisions=500 * n)
    res = sim.compress(packing=phi, rate=1e-3, pressure=None)
    if res.reason != "packing" or abs(sim.packing - phi) > 1e-9:
        raise RuntimeError(f"compression to {phi} stopped at {sim.packing} ({res.reason})")
    return sim


def start_chain(box: str, phi: float, start: str, seed: int) -> hs.EventChain:
    """Straight event chains at ``phi`` from one of :data:`STARTS`."""
    pbox = make_box(box, phi)
    if start == "liquid":
        return hs.EventChain.from_simulation(grown(box, phi, seed), seed=seed, variant="straight")
    if start == "solid":
        chain = hs.EventChain.from_simulation(grown(box, SOLID_PACKING, seed), seed=seed, variant="straight")
        chain.run(events=SOLID_LIFTS * size(box)).run(chains=1)
        dense = chain.state()
        scale = np.asarray(pbox.sides) / np.asarray(chain.container.sides)  # the same shape: one factor
        state = hs.State.from_arrays(dense.masses, dense.radii, dense.positions * scale, dense.velocities)
        return hs.EventChain(state, pbox, seed=seed, variant="straight")
    if box in CRYSTAL_CELLS:
        state = hs.hexagonal(CRYSTAL_CELLS[box], phi)[0]
    else:
        state = hs.random_spheres(N, phi, pbox, seed=seed)
    return hs.EventChain(state, pbox, seed=seed, variant="straight")


def autocorrelation_time(x: np.ndarray) -> float:
    """Integrated autocorrelation time in samples (Sokal's window, c = 5); ``nan`` below 8 samples."""
    x = np.asarray(x, float)
    n = x.size
    if n < 8 or np.var(x) == 0.0:
        return math.nan if n < 8 else 0.5
    d = x - x.mean()
    c0 = np.dot(d, d) / n
    tau = 0.5
    for t in range(1, n // 2):
        tau += np.dot(d[:-t], d[t:]) / (n * c0)
        if t >= 5.0 * tau:
            break
    return max(tau, 0.5)


def psi6(chain: hs.EventChain) -> float:
    """``|Psi6|`` of the disks now (``hs.Hexatic``: 6 nearest neighbours)."""
    return hs.Hexatic(bins=4, r_max=2.0).compute(chain.state(), chain.container.length).order


class CheckpointProblem(ValueError):
    """A checkpoint that cannot be resumed: other run lengths than asked for now, or damaged."""


def checkpoint_path(folder: str, box: str, phi: float, start: str, seed: int) -> str:
    """The checkpoint's record (JSON) of one run in ``folder``; the chains beside it."""
    return os.path.join(folder, f"{box}_{phi:.4f}_{start}_{seed}.json")


def save_checkpoint(path: str, chain: hs.EventChain, record: dict) -> None:
    """The chains, then the record naming them (so a crash between leaves the last pair whole)."""
    chain_path = f"{os.path.splitext(path)[0]}_chunk{record['chunk']}.npz"
    chain.save(chain_path)
    old = read_checkpoint(path)
    record = {**record, "chain": os.path.basename(chain_path)}
    with fileio.atomic_write(path, "w") as fh:
        json.dump(record, fh)
    if old and old["chain"] != record["chain"]:
        remove_quietly(os.path.join(os.path.dirname(path), old["chain"]))


def read_checkpoint(path: str) -> dict | None:
    if not os.path.exists(path):
        return None
    try:
        with open(path) as fh:
            rec = json.load(fh)
        if not {"lengths", "chunk", "series", "base", "last", "chain"} <= set(rec):
            raise ValueError("fields missing")
        return rec
    except (ValueError, OSError) as e:
        raise CheckpointProblem(f"{path} is not a checkpoint of this script ({e}): remove it") from None


def remove_quietly(path: str) -> None:
    try:
        os.remove(path)
    except FileNotFoundError:
        pass


def drop_checkpoint(folder: str | None, box: str, phi: float, start: str, seed: int) -> None:
    """Remove a finished run's checkpoint (its row is written)."""
    if folder is None:
        return
    path = checkpoint_path(folder, box, phi, start, seed)
    rec = read_checkpoint(path)
    if rec:
        remove_quietly(os.path.join(folder, rec["chain"]))
    remove_quietly(path)


def measure(
    box: str,
    phi: float,
    start: str,
    seed: int,
    equilibrate: int,
    lifts: int,
    chunks: int,
    folder: str | None = None,
) -> tuple[dict, list[dict]]:
    """One run: its row and its chunk series; with ``folder``, saved after every chunk and resumed."""
    t0, w0 = time.process_time(), time.time()
    path = checkpoint_path(folder, box, phi, start, seed) if folder else None
    n = size(box)
    lengths = {"equilibrate": equilibrate, "lifts": lifts, "chunks": chunks}
    rec = read_checkpoint(path) if path else None
    if rec is not None:
        was = rec["lengths"]
        if not (
            was["equilibrate"] == equilibrate
            and was["lifts"] * n // was["chunks"] == lifts * n // chunks
            and rec["chunk"] <= chunks
        ):
            raise CheckpointProblem(
                f"{path} was written with {was} and is at chunk {rec['chunk']}: rerun with the same "
                "--equilibrate and lifts per chunk and at least as many chunks, or remove it"
            )
        try:
            chain = hs.EventChain.load(os.path.join(folder, rec["chain"]))
        except (ValueError, OSError) as e:
            raise CheckpointProblem(
                f"{path}: its chains do not load ({e}): remove it to start afresh"
            ) from None
        series, k0 = rec["series"], rec["chunk"]
        base, last = np.array(rec["base"]), np.array(rec["last"])
        cpu_before, wall_before, cpu_start = rec["cpu_s"], rec["wall_s"], rec["cpu_s_start"]
        print(f"resuming {box} {phi:.3f} {start} at chunk {k0} of {chunks} ({path})", flush=True)
    else:
        chain = start_chain(box, phi, start, seed)
        cpu_start = time.process_time() - t0
        cpu_before = wall_before = 0.0
        chain.run(events=equilibrate * n).run(chains=1)
        chain.observables.reset()
        series, k0 = [], 0
        base = chain.totals()
        last = base
    phi_true = float(np.sum(math.pi * chain.state().radii ** 2) / chain.container.volume)
    scale = 4.0 * phi_true / math.pi  # Z to beta P d^2

    def keep(k: int) -> None:
        if path is not None:
            save_checkpoint(path, chain, {
                "lengths": lengths, "chunk": k, "series": series, "base": base.tolist(),
                "last": last.tolist(), "cpu_s": cpu_before + time.process_time() - t0,
                "wall_s": wall_before + time.time() - w0, "cpu_s_start": cpu_start,
            })  # fmt: skip

    if rec is None:
        keep(0)
    now = last
    for k in range(k0, chunks):
        chain.run(events=lifts * n // chunks).run(chains=1)
        now = chain.totals()
        d = now - last
        z_k = 1.0 + d[2:4].sum() / d[4:6].sum()
        series.append({"box": box, "phi": phi, "start": start, "seed": seed, "chunk": k,
                       "per_disk": (now[0] - base[0]) / n, "bp": z_k * scale,
                       "psi6": psi6(chain)})  # fmt: skip
        last = now
        keep(k + 1)
    est = chain.observables.estimate("Z")
    bp = np.array([s["bp"] for s in series])
    half = (now - base) / 2.0
    mid = [s for s in series if s["per_disk"] * n <= half[0]]
    blocked = blocking(bp, min_blocks=8)
    tau = autocorrelation_time(bp)
    err_chunks = max(blocked.sem, float(np.std(bp, ddof=1)) * math.sqrt(2.0 * tau / bp.size))
    ref, ref_err = reference(box, phi)
    row = {"box": box, "phi": phi, "start": start, "seed": seed, "bp": est.mean * scale,
           "error_run": est.sem * scale, "error_chunks": err_chunks,
           "chunks_converged": int(blocked.converged),
           "ref": ref, "ref_error": ref_err, "psi6_mean": float(np.mean([s["psi6"] for s in series])),
           "psi6_last": series[-1]["psi6"], "tau_bp": tau * lifts / chunks,
           "tau_psi6": autocorrelation_time(np.array([s["psi6"] for s in series])) * lifts / chunks,
           "equilibrate": equilibrate, "lifts": lifts, "chunks": chunks}  # fmt: skip
    row["error"] = max(row["error_run"], err_chunks)
    row["z"] = (row["bp"] - ref) / math.hypot(row["error"], ref_err)
    k = len(mid)
    row["bp_first_half"] = float(np.mean(bp[:k])) if k else math.nan  # (chunks of equal lifts: a mean)
    row["bp_second_half"] = float(np.mean(bp[k:])) if k < len(bp) else math.nan
    row["cpu_s"] = cpu_before + time.process_time() - t0
    row["cpu_s_start"] = cpu_start
    row["wall_s"] = wall_before + time.time() - w0
    return row, series


def read(path: str) -> list[dict]:
    if not os.path.exists(path):
        return []
    with open(path, newline="") as fh:
        rows = list(csv.DictReader(fh))
    for r in rows:
        for k, v in r.items():
            if k not in ("box", "start"):
                r[k] = float(v) if v not in ("", None) else math.nan
    return rows


def write(path: str, rows: list[dict], fields: list[str]) -> None:
    with fileio.atomic_write(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fields, restval="")
        w.writeheader()
        w.writerows(rows)


def tau(r: dict, key: str) -> str:
    """A correlation time as printed: below one chunk it is not resolved (an upper bound)."""
    chunk = r["lifts"] / r["chunks"]
    return f"< {chunk:.2g}" if r[key] <= chunk else f"{r[key]:.2g}"


def table(rows: list[dict]) -> str:
    """The Markdown table of the runs, and a summary line."""
    out = [
        "| box | packing | start | beta P d^2 | Li et al. 2022 | z | first, second half | <\\|Psi6\\|> "
        "| tau of beta P, \\|Psi6\\| (lifts per disk) | lifts per disk | CPU s |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in sorted(rows, key=lambda r: (r["box"], r["phi"], r["start"])):
        conv = "" if r["chunks_converged"] else "*"
        out.append(
            f"| {BOXES[r['box']]} | {r['phi']:.3f} | {r['start']} "
            f"| {r['bp']:.4f}({round(r['error'] * 1e4)}){conv} "
            f"| {r['ref']:.4f}({round(r['ref_error'] * 1e4)}) | {r['z']:+.2f} "
            f"| {r['bp_first_half']:.4f}, {r['bp_second_half']:.4f} | {r['psi6_mean']:.3f} "
            f"| {tau(r, 'tau_bp')}, {tau(r, 'tau_psi6')} | {r['equilibrate']:.0f} + {r['lifts']:.0f} "
            f"| {r['cpu_s']:.0f} |"
        )
    if rows:
        worst = max(abs(r["z"]) for r in rows)
        cpu = sum(r["cpu_s"] for r in rows)
        out.append("")
        out.append(
            f"{len(rows)} runs; largest |z| {worst:.2f}; {sum(abs(r['z']) <= 3 for r in rows)} of "
            f"{len(rows)} within 3; CPU {cpu:.0f} s ({cpu / 3600:.2f} CPU-hours) in all."
        )
        pairs = []
        for key in sorted({(r["box"], round(r["phi"], 6)) for r in rows}):
            two = {r["start"]: r for r in rows if (r["box"], round(r["phi"], 6)) == key}
            a = two.get("liquid")
            for other in ("crystal", "solid"):
                if a is not None and other in two:
                    b = two[other]
                    where = f"{key[1]:.3f}" + {"square": " (1 : 1)", "large": " (128^2)"}.get(key[0], "")
                    where += " solid" if other == "solid" else ""
                    pairs.append(f"{where}: {(a['bp'] - b['bp']) / math.hypot(a['error'], b['error']):+.2f}")
        if pairs:
            out.append("liquid against crystal (or solid) start, z: " + "; ".join(pairs) + ".")
        out.append(
            "beta P d^2 with its error in the 4th decimal in brackets; * marks a chunk series whose blocking "
            "had no plateau (its error a lower bound)."
        )
    return "\n".join(out)


PLOT_STYLE = {
    "liquid": ("^", "tab:blue", -0.0003),
    "crystal": ("s", "tab:red", 0.0003),
    "solid": ("D", "tab:green", 0.0006),
}


def draw(ax: matplotlib.axes.Axes, rows: list[dict], box: str) -> None:
    """Li et al.'s loop in ``box`` and the runs of ``rows`` in it on the axes ``ax``."""
    p, v, e = zip(*LI[box], strict=True)
    kind = "MPMC, N = 128^2" if box == "large" else "ECMC, N = 870"
    ax.errorbar(p, v, e, fmt="-", color="0.5", lw=1.5, label=f"Li et al. 2022 ({kind})")
    mine = [r for r in rows if r["box"] == box]

    def same(r: dict) -> tuple[float, str]:
        return (round(r["phi"], 6), r["start"])

    longest: dict[tuple[float, str], float] = {}
    for r in mine:
        longest[same(r)] = max(longest.get(same(r), 0.0), r["equilibrate"] + r["lifts"])
    for start, (marker, colour, dx) in PLOT_STYLE.items():
        for short in (False, True):  # superseded runs open and faded
            pts = [
                r
                for r in mine
                if r["start"] == start and (r["equilibrate"] + r["lifts"] < longest[same(r)]) == short
            ]
            if pts:
                ax.errorbar(
                    [r["phi"] + dx for r in pts],
                    [r["bp"] for r in pts],
                    [r["error"] for r in pts],
                    fmt=marker,
                    ms=4,
                    color=colour,
                    mfc="none" if short else None,
                    alpha=0.5 if short else 1.0,
                    capsize=3,
                    label=f"hs.EventChain, {start} start" + (", shorter runs" if short else ""),
                )
    top = max(v) + 0.15  # a run far above the loop (a stuck start) is named at the top, not drawn
    off = [r for r in mine if r["bp"] - r["error"] > top]
    for r in off:
        text = f"{r['start']} start: {r['bp']:.3f}, off the scale"
        ax.annotate(text, (r["phi"], top), (r["phi"] - 0.008, top - 0.03),
                    fontsize=7, arrowprops={"arrowstyle": "->", "color": "0.3"})  # fmt: skip
    if off:
        ax.set_ylim(top=top + 0.01)
    ax.set(title=f"{size(box)} disks, {BOXES[box]} box", xlabel="packing fraction", ylabel="beta P d^2")
    ax.legend(fontsize=7, loc="best")


def plot(rows: list[dict], png: str) -> None:
    """Both boxes' panels (:func:`draw`) written to ``png``."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    boxes = [b for b in BOXES if b != "large" or any(r["box"] == "large" for r in rows)]
    fig, axes = plt.subplots(1, len(boxes), figsize=(5.5 * len(boxes), 4.5), layout="constrained")
    for ax, box in zip(axes, boxes, strict=True):
        draw(ax, rows, box)
    with fileio.atomic_path(png) as tmp:
        fig.savefig(tmp, dpi=110, format="png")
    plt.close(fig)


def states(rows: list[dict], series: list[dict], box: str, phi: float, seed: int, split: float) -> str:
    """Each start's chunks split at ``split`` in beta P d^2: switches, shares, and the starts' average.

    Near the loop's minimum a run moves between a more ordered, lower-pressure
    state and a less ordered one; a chunk above ``split`` counts as the
    latter.  The average of the two starts' results carries half their
    errors combined.
    """
    out = []
    for start in STARTS:
        s = [
            c
            for c in series
            if (c["box"], round(c["phi"], 6), c["start"], int(c["seed"])) == (box, round(phi, 6), start, seed)
        ]
        if not s:
            continue
        bp = np.array([c["bp"] for c in s])
        ps = np.array([c["psi6"] for c in s])
        high = bp > split
        switches = int(np.sum(high[1:] != high[:-1]))
        line = f"{start}: {bp.size} chunks, {switches} switches, {high.mean():.0%} above {split}"
        for name, part in (("above", high), ("below", ~high)):
            if part.any():
                line += f"; {name}: beta P d^2 {bp[part].mean():.3f}, |Psi6| {ps[part].mean():.3f}"
        out.append(line)
    two = [r for r in rows if (r["box"], round(r["phi"], 6), int(r["seed"])) == (box, round(phi, 6), seed)]
    if len({r["start"] for r in two}) == 2 and len(two) == 2:
        mean = (two[0]["bp"] + two[1]["bp"]) / 2
        err = math.hypot(two[0]["error"], two[1]["error"]) / 2
        ref, ref_err = reference(box, phi)
        out.append(
            f"the two starts' average: {mean:.4f} +- {err:.4f}, "
            f"z = {(mean - ref) / math.hypot(err, ref_err):+.2f}"
        )
    return "\n".join(out) if out else f"no chunks of {box} {phi} seed {seed}"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("command", choices=["run", "table", "plot", "states"])
    ap.add_argument("--split", type=float, default=9.1, help="states: beta P d^2 between the two states")
    ap.add_argument("--csv", nargs="+", default=["validation/results/ecmc_loop_870.csv"])
    ap.add_argument("--png", default="docs/images/ecmc_loop.png", help="plot: the picture written")
    ap.add_argument("--box", choices=list(BOXES), default="crystal")
    ap.add_argument("--packings", type=float, nargs="+", default=[0.700, 0.716, 0.708, 0.712, 0.704])
    ap.add_argument("--starts", nargs="+", choices=STARTS, default=["liquid", "crystal"])
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--equilibrate", type=int, default=300_000, help="lifts per disk before measuring")
    ap.add_argument("--lifts", type=int, default=3_000_000, help="lifts per disk measured")
    ap.add_argument("--chunks", type=int, default=40)
    ap.add_argument("--budget", type=float, default=math.inf, help="CPU seconds for this invocation")
    ap.add_argument("--deadline", type=float, default=math.inf, help="wall seconds for this invocation")
    ap.add_argument(
        "--checkpoint", metavar="DIR", help="save each run after every chunk here; resume from it"
    )
    args = ap.parse_args()
    if args.checkpoint:
        try:
            os.makedirs(args.checkpoint, exist_ok=True)
        except OSError as e:
            raise SystemExit(f"ecmc_loop.py: --checkpoint {args.checkpoint}: cannot make it ({e})") from None
    if args.command == "plot":
        for path in args.csv:
            if not os.path.exists(path):
                ap.error(f"--csv {path}: no such file")
        plot([r for path in args.csv for r in read(path)], args.png)
        return
    if len(args.csv) != 1:
        ap.error(f"{args.command}: give one --csv (plot takes several)")
    csv_path = args.csv[0]
    rows = read(csv_path)
    root, ext = os.path.splitext(csv_path)
    series_path, md_path = f"{root}_series{ext}", f"{root}.md"
    if args.command == "table":
        print(table(rows))
        return
    if args.command == "states":
        print(states(rows, read(series_path), args.box, args.packings[0], args.seed, args.split))
        return
    series = read(series_path)
    done = {(r["box"], round(r["phi"], 6), r["start"], int(r["seed"])) for r in rows}
    t0, w0 = time.process_time(), time.time()
    per_lift, share = math.nan, 1.0
    for phi in args.packings:
        for start in args.starts:
            if (args.box, round(phi, 6), start, args.seed) in done:
                continue
            spent = time.process_time() - t0
            guess = per_lift * (args.equilibrate + args.lifts) * size(args.box)
            guess = guess if math.isfinite(guess) else 0.0
            if spent + guess > args.budget or time.time() - w0 + guess / share > args.deadline:
                print(f"budget: {spent:.0f} CPU s spent, the next run would take about {guess:.0f}; stopping")
                print(table(rows))
                return
            try:
                row, s = measure(
                    args.box,
                    phi,
                    start,
                    args.seed,
                    args.equilibrate,
                    args.lifts,
                    args.chunks,
                    args.checkpoint,
                )
            except CheckpointProblem as e:
                raise SystemExit(f"ecmc_loop.py: {e}") from None
            per_lift = (row["cpu_s"] - row["cpu_s_start"]) / (
                (args.equilibrate + args.lifts) * size(args.box)
            )
            share = max(0.1, (time.process_time() - t0) / (time.time() - w0))  # CPU per wall second here
            rows.append(row)
            series.extend(s)
            write(csv_path, rows, FIELDS)
            write(series_path, series, SERIES_FIELDS)
            with fileio.atomic_write(md_path, "w") as fh:
                fh.write(table(rows) + "\n")
            try:
                drop_checkpoint(args.checkpoint, args.box, phi, start, args.seed)
            except CheckpointProblem:
                pass  # (the row is written; a damaged record stays for the user to see)
            print(table([row]).splitlines()[2], flush=True)
    print(table(rows))


if __name__ == "__main__":
    main()

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

Each packing starts from random disks (``hardspheres.random_spheres``, a
random half of a triangular lattice, which melts at once), equilibrates
``--equilibrate`` collisions per disk, then measures ``--measure`` collisions
per disk: ``beta P sigma^2 = Z 4 phi / pi`` (sigma the diameter, the
HistoricDisks unit ``beta P (2 sigma)^2`` with their sigma a radius), Z from
the collision virial with its blocked standard error
(``hardspheres.observables``), scored by ``z = (ours - theirs) /
sqrt(err_ours^2 + err_theirs^2)``.  Rows are appended to ``--csv`` as each
packing finishes (a rerun skips the packings already there), so a long run
can be stopped and resumed.  ``--plot`` draws the loop from the CSV.

usage:
    python3 validation/disks_loop.py small --csv validation/results/disks_loop_870.csv
    python3 validation/disks_loop.py large --csv validation/results/disks_loop_16384.csv
    python3 validation/disks_loop.py plot --csv A.csv B.csv --png docs/images/disks_loop.png

Running time (this machine, 2 cores shared, load 3-6): small with the
defaults (5000 + 50000 collisions per disk, 15 packings) about 25 min;
large with ``--equilibrate 5000 --measure 30000`` about 15 min per packing.
Each run prints its own running time.
"""

import argparse
import csv
import math
import os
import time

import hardspheres as hs
from hardspheres import fileio
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
]


def measure(
    cells: tuple[int, int], phi: float, equilibrate: int, collisions: int, seed: int, compressed: bool = False
) -> dict:
    """One packing: equilibrate, measure; beta P sigma^2 with its error, and |Psi6| at the end.

    ``compressed``: start from a fluid at packing 0.60 (500 collisions per
    disk), grown to ``phi`` (``Simulation.compress``, rate 10^-3), rather
    than from random disks at ``phi`` (a triangular lattice with vacancies
    at these packings, aligned with the box).
    """
    t0 = time.time()
    _, box = hexagonal(cells, phi)
    n = cells[0] * cells[1]
    if compressed:
        sim = hs.Simulation(hs.random_spheres(n, 0.60, box, seed=seed), box)
        sim.run(collisions=500 * n)
        res = sim.compress(packing=phi, rate=1e-3, pressure=None)
        if res.reason != "packing" or abs(sim.packing - phi) > 1e-9:
            raise RuntimeError(f"compression to {phi} stopped at {sim.packing} ({res.reason})")
    else:
        sim = hs.Simulation(hs.random_spheres(n, phi, box, seed=seed), box)
    sim.run(collisions=equilibrate * n)
    obs = sim.observables.reset()
    t_start = sim.time
    sim.run(collisions=collisions * n // 2)
    z_first, t_half = obs.Z(), sim.time - t_start
    sim.run(collisions=collisions * n - collisions * n // 2)
    z, err = obs.Z(), obs.error("Z")
    t_all = sim.time - t_start
    z_second = (z * t_all - z_first * t_half) / (t_all - t_half)  # Z is a time average
    scale = 4.0 * phi / math.pi
    psi6 = hs.Hexatic().compute(sim).order
    return {"n": n, "phi": phi, "bp": z * scale, "error": err * scale, "Z": z, "Z_error": err, "psi6": psi6,
            "equilibrate": equilibrate, "measure": collisions, "wall_s": time.time() - t0,
            "bp_first_half": z_first * scale, "bp_second_half": z_second * scale,
            "compressed": float(compressed)}  # fmt: skip


def series(size: str, phi: float, chunks: int, per: int, path: str) -> None:
    """One long run as a time series: beta P sigma^2 and |Psi6| over chunks of ``per`` collisions per disk.

    The random start of :func:`measure`, 5000 collisions per disk, then
    ``chunks`` chunks; prints one line per chunk and writes them to ``path``
    (CSV), then the mean over the chunks with the standard error of the
    chunk means.
    """
    t0 = time.time()
    cells = SIZES[size]["cells"]
    _, box = hexagonal(cells, phi)
    n = cells[0] * cells[1]
    sim = hs.Simulation(hs.random_spheres(n, phi, box, seed=1), box)
    sim.run(collisions=5000 * n)
    scale = 4.0 * phi / math.pi
    out = []
    for k in range(chunks):
        obs = sim.observables.reset()
        sim.run(collisions=per * n)
        out.append((k, obs.Z() * scale, hs.Hexatic().compute(sim).order))
        print(f"chunk {k}: beta P sigma^2 {out[-1][1]:.4f}, |Psi6| {out[-1][2]:.3f}", flush=True)
        with fileio.atomic_write(path, "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(["chunk", "bp", "psi6"])
            w.writerows(out)
    bp = [o[1] for o in out]
    mean = sum(bp) / len(bp)
    sem = math.sqrt(sum((b - mean) ** 2 for b in bp) / (len(bp) - 1) / len(bp)) if len(bp) > 1 else math.nan
    print(f"N = {n}, packing {phi}: mean over {len(bp)} chunks of {per} collisions per disk", end=" ")
    print(f"{mean:.4f} +- {sem:.4f}")
    print(f"running time: {time.time() - t0:.0f} s")


def _read(path: str) -> list[dict]:
    if not os.path.exists(path):
        return []
    with open(path, newline="") as f:
        return [{k: float(v) for k, v in row.items() if v not in (None, "")} for row in csv.DictReader(f)]


def _write(path: str, rows: list[dict]) -> None:
    with fileio.atomic_write(path, "w", newline="") as f:
        w = csv.DictWriter(f, FIELDS, restval="")
        w.writeheader()
        w.writerows(rows)


def run(
    size: str,
    path: str,
    equilibrate: int,
    collisions: int,
    order: list[float] | None,
    compressed: bool = False,
) -> None:
    t0 = time.time()
    spec = SIZES[size]
    rows = _read(path)
    done = {round(r["phi"], 6) for r in rows}
    reference = {p: (v, e) for p, v, e in spec["reference"]}
    for phi in order or list(reference):
        if round(phi, 6) in done:
            continue
        row = measure(spec["cells"], phi, equilibrate, collisions, seed=1, compressed=compressed)
        ref, ref_err = reference[phi]
        row.update(ref=ref, ref_error=ref_err, z=(row["bp"] - ref) / math.hypot(row["error"], ref_err))
        rows.append(row)
        rows.sort(key=lambda r: r["phi"])
        _write(path, rows)
        print(f"phi {phi:.3f}: {row['bp']:.4f} +- {row['error']:.4f} against {ref:.4f} +- {ref_err:.4f}, "
              f"z {row['z']:+.2f}, |Psi6| {row['psi6']:.3f}, {row['wall_s']:.0f} s", flush=True)  # fmt: skip
    table(rows)
    print(f"running time: {time.time() - t0:.0f} s")


def _halves(r: dict) -> str:
    """The first and second halves of the measurement (a drift shows there), if recorded."""
    if "bp_first_half" not in r:
        return "-"
    return f"{r['bp_first_half']:.4f}, {r['bp_second_half']:.4f}"


def table(rows: list[dict]) -> None:
    """The Markdown table of one CSV's rows."""
    print("| N | packing | ours, beta P sigma^2 | published | z | \\|Psi6\\| | collisions per disk", end="")
    print(" | first, second half |")
    print("|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['n']:.0f} | {r['phi']:.3f} | {r['bp']:.4f} +- {r['error']:.4f} | {r['ref']:.4f} +- "
              f"{r['ref_error']:.4f} | {r['z']:+.2f} | {r['psi6']:.3f} | "
              f"{r['equilibrate']:.0f} + {r['measure']:.0f} | {_halves(r)} |")  # fmt: skip
    if rows:
        worst = max(rows, key=lambda r: abs(r["z"]))
        print(f"\nlargest |z| {abs(worst['z']):.2f} (packing {worst['phi']:.3f}); |z| <= 3 at "
              f"{sum(abs(r['z']) <= 3 for r in rows)} of {len(rows)} packings")  # fmt: skip


def plot(paths: list[str], png: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(10, 4), layout="constrained")
    sets = [
        ("small", LI_870, "N = 870, 29 : 30 sqrt(3)/2 box", []),
        ("large", LI_16384, "N = 128^2 = 16384, sqrt(3)/2 box", [("Zollweg & Chester 1992", ZOLLWEG_16384)]),
    ]
    rows = [r for p in paths for r in _read(p)]
    for ax, (size, ref, title, extra) in zip(axes, sets, strict=True):
        n = SIZES[size]["cells"][0] * SIZES[size]["cells"][1]
        p, v, e = zip(*ref, strict=True)
        ax.errorbar(p, v, e, fmt="-", color="0.5", lw=1.5, label=SIZES[size]["label"])
        for name, data in extra:
            p, v, e = zip(*[d for d in data if 0.688 <= d[0] <= 0.722], strict=True)
            ax.errorbar(p, v, e, fmt="s", ms=3, color="tab:green", mfc="none", capsize=2, label=name)

        def key(r: dict) -> tuple[float, float, float]:
            return (r.get("compressed", 0.0), r["equilibrate"], r["measure"])

        mine = [r for r in rows if r["n"] == n]
        for k, run_key in enumerate(sorted({key(r) for r in mine})):
            ours = [r for r in mine if key(r) == run_key]
            start = "compressed from 0.60" if run_key[0] else "random start"
            ax.errorbar(
                [r["phi"] + 0.0003 * k for r in ours],
                [r["bp"] for r in ours],
                [r["error"] for r in ours],
                fmt="os^"[k % 3],
                ms=4,
                color=("tab:red", "tab:blue", "tab:purple")[k % 3],
                capsize=3,
                label=f"hardspheres EDMD, {start}, {run_key[1]:.0f} + {run_key[2]:.0f} per disk",
            )
        ax.set(title=title, xlabel="packing fraction", ylabel="beta P sigma^2 (sigma: diameter)")
        ax.legend(fontsize=7, loc="best")
    with fileio.atomic_path(png) as tmp:
        fig.savefig(tmp, dpi=110, format="png")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("what", choices=["small", "large", "plot", "table", "series"])
    ap.add_argument("--csv", nargs="+", required=True)
    ap.add_argument("--equilibrate", type=int, default=5000, help="collisions per disk before measuring")
    ap.add_argument("--measure", type=int, default=50000, help="collisions per disk measured")
    ap.add_argument("--order", type=float, nargs="+", help="packings to run, in this order (default: all)")
    ap.add_argument("--png", default="docs/images/disks_loop.png")
    ap.add_argument("--size", choices=list(SIZES), default="small", help="series: the system")
    ap.add_argument("--chunks", type=int, default=40, help="series: chunks")
    ap.add_argument("--per", type=int, default=5000, help="series: collisions per disk per chunk")
    ap.add_argument("--compressed", action="store_true", help="start from a fluid at 0.60, grown")
    args = ap.parse_args()
    if args.what == "series":
        series(args.size, args.order[0], args.chunks, args.per, args.csv[0])
    elif args.what == "plot":
        plot(args.csv, args.png)
    elif args.what == "table":
        for p in args.csv:
            table(_read(p))
    else:
        run(args.what, args.csv[0], args.equilibrate, args.measure, args.order, args.compressed)


if __name__ == "__main__":
    main()

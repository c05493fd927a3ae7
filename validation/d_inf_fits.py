"""D_inf at packing 0.3 from the fit over all system sizes, and its spread across fitting choices.

The infinite-system self-diffusion at packing 0.3, from the
eight runs of docs/validation/transport.md (N = 500 to 4000, validation/results/
transport_030_runs.csv), by every reasonable way of extrapolating them:

* a straight line in 1/L through all sizes, weighted by 1/err^2 or not;
* the same line through each size's mean;
* the line leaving out one size at a time, and through the two largest;
* the line with its slope fixed at Yeh and Hummer's -xi kT / (6 pi eta)
  (the mean eta of the runs), i.e. the weighted mean of the runs'
  Yeh-Hummer values, and their plain mean.

Each is printed with its standard error and its difference from Pieprzyk et
al.'s and Heyes & Cass's tables (interpolated, as validate --transport
does); the last line gives the spread across the choices.

usage:
    python3 validation/d_inf_fits.py        # instant: no simulation
"""

import csv
import math
from pathlib import Path

import numpy as np

from hardspheres.analysis.transport import XI_CUBIC
from hardspheres.studies.validate import published_diffusion

HERE = Path(__file__).resolve().parent
RUNS = HERE / "results" / "transport_030_runs.csv"
PHI = 0.3


def read_runs(path: Path = RUNS) -> dict[str, np.ndarray]:
    with open(path) as fh:
        rows = list(csv.DictReader(line for line in fh if not line.startswith("#")))
    return {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}


def line(x: np.ndarray, y: np.ndarray, err: np.ndarray | None = None) -> tuple[float, float, float]:
    """Intercept and its standard error of a straight line (weighted by 1/err^2 if given)."""
    if err is None:
        (slope, icept), cov = np.polyfit(x, y, 1, cov=True)
    else:
        (slope, icept), cov = np.polyfit(x, y, 1, w=1.0 / err, cov="unscaled")
    return float(icept), math.sqrt(cov[1, 1]), float(slope)


def fits(r: dict[str, np.ndarray]) -> list[tuple[str, float, float]]:
    """(label, D_inf, error) for every fitting choice."""
    x, y, e, n = 1.0 / r["L"], r["D"], r["D_err"], r["n"]
    out = []
    d, s, k = line(x, y, e)
    out.append((f"line in 1/L, all 8 runs, weighted (slope {k:.3f})", d, s))
    d, s, k = line(x, y)
    out.append((f"line in 1/L, all 8 runs, unweighted (slope {k:.3f})", d, s))
    sizes = sorted(set(n))
    mx = np.array([x[n == m][0] for m in sizes])
    my = np.array([y[n == m].mean() for m in sizes])
    me = np.array([math.sqrt(np.sum(e[n == m] ** 2)) / np.sum(n == m) for m in sizes])
    d, s, k = line(mx, my, me)
    out.append((f"line in 1/L through the 4 sizes' means, weighted (slope {k:.3f})", d, s))
    for drop in sizes:
        keep = n != drop
        d, s, k = line(x[keep], y[keep], e[keep])
        out.append((f"line, weighted, without N = {int(drop)} (slope {k:.3f})", d, s))
    keep = n >= 2744
    d, s, k = line(x[keep], y[keep], e[keep])
    out.append((f"line through the two largest, N = 2744 and 4000 (slope {k:.3f})", d, s))
    eta = float(np.mean(r["eta"]))
    yh = y + XI_CUBIC / (6.0 * math.pi * eta * r["L"])
    w = 1.0 / e**2
    out.append(
        (
            f"Yeh-Hummer slope fixed ({-XI_CUBIC / (6 * math.pi * eta):.3f}, eta {eta:.3f}), weighted",
            float(np.sum(w * yh) / np.sum(w)),
            1.0 / math.sqrt(np.sum(w)),
        )
    )
    out.append(
        ("Yeh-Hummer, plain mean of the 8 runs", float(yh.mean()), float(yh.std(ddof=1) / math.sqrt(len(yh))))
    )
    return out


def main() -> None:
    refs = [(d, src.split(",")[0].split(" (")[0]) for d, _, src in published_diffusion(PHI)]
    runs = read_runs()
    rows = fits(runs)
    sizes = ", ".join(str(int(m)) for m in sorted(set(runs["n"])))
    print(f"D_inf at packing {PHI} from {len(runs['n'])} runs, N = {sizes}")
    print(" | ".join(["fit", "D_inf"] + [f"vs {name} ({d:.5f})" for d, name in refs]))
    for label, d, s in rows:
        print(
            " | ".join([label, f"{d:.4f} +- {s:.4f}"] + [f"{100 * (d / ref - 1):+.2f}%" for ref, _ in refs])
        )
    groups = (
        ("the fits over all sizes", [r for r in rows if "without" not in r[0] and "two largest" not in r[0]]),
        ("the lines leaving one size out", [r for r in rows if "without" in r[0]]),
    )
    for what, group in groups:
        ds = np.array([d for _, d, _ in group])
        against = "; ".join(
            f"{100 * (ds.min() / ref - 1):+.1f}% to {100 * (ds.max() / ref - 1):+.1f}% against {name}"
            for ref, name in refs
        )
        print(f"spread across {what} ({len(group)}): D_inf = {ds.min():.4f} to {ds.max():.4f}, {against}")


if __name__ == "__main__":
    main()

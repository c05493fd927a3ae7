"""The glass-former figures of docs/glass.md from validation/glass.py's JSON files.

python3 validation/glass_plots.py RUN.json [RUN2.json ...] --out docs/images
"""

import argparse
import json
import math
from pathlib import Path

import numpy as np


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("json", nargs="+")
    ap.add_argument("--out", default="docs/images")
    args = ap.parse_args()
    runs = []
    for p in args.json:
        runs += json.loads(Path(p).read_text())
    runs.sort(key=lambda r: r["row"]["phi"])
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out = Path(args.out)
    fig, ax = plt.subplots(figsize=(6.4, 4.4), layout="constrained")
    for r in runs:
        c = r["curves"]
        ax.errorbar(c["t"], c["Fs"], yerr=c["Fs_err"], label=f"phi = {r['row']['phi']:.2f}", capsize=1.5)
    ax.axhline(math.exp(-1), color="grey", lw=0.5, ls=":")
    ax.set_xscale("log")
    ax.set_xlabel("t  [sqrt(m sigma_s^2 / kT)]")
    ax.set_ylabel("F_s(k = 2 pi / 1.2, t)")
    ax.legend(fontsize="small")
    fig.savefig(out / "glass_fs.png", dpi=100)

    fig, ax = plt.subplots(figsize=(6.4, 4.4), layout="constrained")
    for r in runs:
        c = r["curves"]
        ax.errorbar(
            c["chi4_t"], c["chi4"], yerr=c["chi4_err"], label=f"phi = {r['row']['phi']:.2f}", capsize=1.5
        )
        if math.isfinite(r["row"]["tau_alpha"]):
            ax.axvline(r["row"]["tau_alpha"], lw=0.5, ls=":", color=ax.lines[-1].get_color())
    ax.set_xscale("log")
    ax.set_xlabel("t  (dotted: tau_alpha)")
    ax.set_ylabel("chi_4(t) = N var Q, a = 0.3")
    ax.legend(fontsize="small")
    fig.savefig(out / "glass_chi4.png", dpi=100)

    rows = [r["row"] for r in runs if math.isfinite(r["row"]["tau_alpha"])]
    phi = np.array([r["phi"] for r in rows])
    tau = np.array([r["tau_alpha"] for r in rows])
    err = np.array([r["tau_alpha_error"] for r in rows])
    fig, ax = plt.subplots(figsize=(6.4, 4.4), layout="constrained")
    ax.errorbar(phi, tau, yerr=err, fmt="o", label="tau_alpha (F_s = 1/e)")
    if len(rows) >= 3:
        from scipy.optimize import curve_fit

        p, _ = curve_fit(
            lambda x, l0, A, p0: l0 + A / (p0 - x), phi, np.log(tau), p0=(0.0, 1.0, 0.64), maxfev=20000
        )
        x = np.linspace(phi.min() - 0.01, phi.max() + 0.005, 100)
        ax.plot(
            x,
            np.exp(p[0] + p[1] / (p[2] - x)),
            "--",
            label=f"tau_0 exp(A / (phi_0 - phi)), phi_0 = {p[2]:.3f}",
        )
    ax.set_yscale("log")
    ax.set_xlabel("packing fraction phi")
    ax.set_ylabel("tau_alpha")
    ax.legend(fontsize="small")
    fig.savefig(out / "glass_tau.png", dpi=100)
    print("wrote", *(str(out / f) for f in ("glass_fs.png", "glass_chi4.png", "glass_tau.png")))


if __name__ == "__main__":
    main()

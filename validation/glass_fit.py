"""Fits of tau_alpha(phi) from validation/glass.py's JSON (docs/validation/glass-jamming.md, "Slow dynamics").

For each trial divergence point phi_x on a fine grid the two other
parameters follow by weighted linear least squares (weights from the errors
of ln tau_alpha); the profile of chi^2 over phi_x gives the best value and
its range (chi^2 within 1 of the least).  Forms:

* Vogel-Fulcher-Tammann-like (the one Brambilla et al., PRL 102, 085703
  (2009) fit above the mode-coupling range): ln tau = l0 + A / (phi_0 - phi);
* mode-coupling power law: ln tau = l0 - gamma ln(phi_c - phi).

    python3 validation/glass_fit.py RUN.json [RUN2.json ...] [--max-phi 0.58]
"""

import argparse
import json
import math
from pathlib import Path

import numpy as np


def profile(phi, y, w, basis, grid):
    best = None
    chi = []
    for px in grid:
        X = np.stack([np.ones_like(phi), basis(px, phi)], 1)
        W = np.sqrt(w)[:, None]
        coef, *_ = np.linalg.lstsq(X * W, y * W[:, 0], rcond=None)
        c2 = float(np.sum(w * (y - X @ coef) ** 2))
        chi.append(c2)
        if best is None or c2 < best[0]:
            best = (c2, px, coef)
    chi = np.array(chi)
    ok = grid[chi <= best[0] + 1.0]
    return best, (ok.min(), ok.max())


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("json", nargs="+")
    ap.add_argument("--max-phi", type=float, default=1.0)
    args = ap.parse_args()
    rows = [r["row"] for p in args.json for r in json.loads(Path(p).read_text())]
    rows = sorted(
        (r for r in rows if math.isfinite(r["tau_alpha"]) and r["phi"] <= args.max_phi),
        key=lambda r: r["phi"],
    )
    phi = np.array([r["phi"] for r in rows])
    tau = np.array([r["tau_alpha"] for r in rows])
    err = np.array([r["tau_alpha_error"] for r in rows])
    y, w = np.log(tau), (tau / err) ** 2
    for name, basis in (
        ("VFT  ln tau = l0 + A/(phi_0 - phi)", lambda px, p: 1.0 / (px - p)),
        ("MCT  ln tau = l0 - gamma ln(phi_c - phi)", lambda px, p: -np.log(px - p)),
    ):
        grid = np.linspace(phi.max() + 1e-4, 0.75, 6000)
        (c2, px, coef), (lo, hi) = profile(phi, y, w, basis, grid)
        print(
            f"{name}: divergence at {px:.4f} (chi^2 + 1 range {lo:.4f} - {hi:.4f}), "
            f"l0 = {coef[0]:.3f}, {'A' if 'VFT' in name else 'gamma'} = {coef[1]:.3f}, "
            f"chi^2 = {c2:.2f} for {len(phi) - 3} degrees of freedom; phi = {phi.tolist()}"
        )


if __name__ == "__main__":
    main()

"""Our jamming traces read the way Skoge et al. (2006) read theirs in their Fig. 5.

    python validation/skoge_fig5.py validation/results/jam10k_trace_{0.1,0.01,0.003,0.001}.csv

Skoge, Donev, Stillinger & Torquato, PRE 74, 041127 (2006) (preprint
arXiv:cond-mat/0608362v1, Eqs. 3-4, p. 10; Fig. 5, p. 13) plot the estimated
jamming density phi_J~ = phi / (1 - d/p) against phi during LS growth.  For
amorphous (not partially crystallised) runs in d = 3 they report a bump of
phi_J~ near phi_G ~ 0.59 and larger peak heights at smaller expansion rates;
partial crystallisation shows as a jump of phi_J~.  For each trace (columns
phi, Z, collisions; from ``validation/compress.py jam``) this prints, for
phi >= 0.5: the peak of phi_J~ (a centred 9-point running mean), where it is,
the final phi_J~, and the largest rise of the running mean after the peak
(a jump would show there).
"""

import sys

import pandas as pd


def main(paths):
    print("| trace | peak phi_J~ | at phi | Z there | final phi_J~ | largest rise after the peak |")
    print("|---|---|---|---|---|---|")
    for path in paths:
        d = pd.read_csv(path)
        d = d[d.phi >= 0.5].reset_index(drop=True)
        raw = d.phi / (1.0 - 3.0 / d.Z)
        pj = raw.rolling(9, center=True).mean()
        i = int(pj.idxmax())
        rise = pj[i:].diff().max()
        rise_text = "-" if pd.isna(rise) else f"{rise:.4f}"
        print(f"| {path} | {pj[i]:.4f} | {d.phi[i]:.3f} | {d.Z[i]:.0f} | {raw.iloc[-1]:.4f} | {rise_text} |")


if __name__ == "__main__":
    main(sys.argv[1:])

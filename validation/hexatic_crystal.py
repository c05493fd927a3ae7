"""|Psi6| of the hexagonal hard-disk crystal: by packing, system size and neighbour definition.

A criterion one may meet is |Psi6| > 0.9 at area fraction 0.75 after 100
collisions per disk.  This script measures what the crystal gives, with every common
definition of the neighbours of psi6(j) = (1/n_j) sum_k exp(6 i theta_jk):

* ``6NN``: the 6 nearest neighbours (``hs.Hexatic``, freud ``num_neighbors=6``);
* ``Voronoi``: the Voronoi (Delaunay) neighbours, as Bernard & Krauth and
  jellyfysh/HistoricDisks (``Python/analysis/psi6.py``) use;
* ``Voronoi-weighted``: each bond weighted by its Voronoi edge length
  (freud ``Hexatic(weighted=True)``; the Minkowski-weighted psi6 of Mickel et
  al., J. Chem. Phys. 138, 044501 (2013));

both ``|<psi6>|`` (the global order, hs.Hexatic's ``order``) and ``<|psi6|>``
(the mean local order).  Each row: a perfect crystal
(``builders.hexagonal``), K stretches of 100 collisions per disk, the
values after the first stretch and their mean over the K.  With
``--historicdisks FILE`` (HistoricDisks' ``Python/analysis/psi6.py``, not
part of this project) its Delaunay psi6 is computed on the same
configurations as an independent check.  Prints a Markdown table and its
running time (about 2 min on this machine).

usage: python3 validation/hexatic_crystal.py [--stretches K] [--historicdisks FILE]
"""

import argparse
import importlib.util
import time

import freud
import numpy as np

import hardspheres as hs
from hardspheres.builders import hexagonal

ROWS = [((32, 32), p) for p in (0.72, 0.73, 0.75, 0.78, 0.80, 0.85, 0.88)] + [
    ((16, 16), 0.75),
    ((64, 64), 0.75),
]


def values(sim: hs.Simulation, historic) -> list[float]:  # noqa: ANN001 (a module or None)
    """|<psi6>| and <|psi6|> by the three definitions (and HistoricDisks' global |<psi6>|)."""
    sides = np.array(sim.container.sides)
    x = sim.state().positions
    box = freud.box.Box(Lx=sides[0], Ly=sides[1], is2D=True)
    points = np.column_stack([box.wrap(np.column_stack([x, np.zeros(len(x))]))[:, :2], np.zeros(len(x))])
    nn = hs.Hexatic().compute(sim).psi6
    vor = freud.locality.Voronoi().compute((box, points))
    out = []
    for psi in (
        nn,
        freud.order.Hexatic(k=6).compute((box, points), neighbors=vor.nlist).particle_order,
        freud.order.Hexatic(k=6, weighted=True).compute((box, points), neighbors=vor.nlist).particle_order,
    ):
        out += [abs(np.mean(psi)), np.mean(np.abs(psi))]
    if historic is not None:
        xw = x % sides
        per = np.concatenate([xw + np.array([i, j]) * sides for i in (0, -1, 1) for j in (0, -1, 1)])
        cx = historic.hexatic(per)[0][: len(x)]
        out.append(abs(np.mean(cx)))
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--stretches", type=int, default=3)
    ap.add_argument("--historicdisks", help="HistoricDisks' Python/analysis/psi6.py, for a cross-check")
    args = ap.parse_args()
    historic = None
    if args.historicdisks:
        spec = importlib.util.spec_from_file_location("historic_psi6", args.historicdisks)
        historic = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(historic)
    t0 = time.time()
    head = (
        "| N | packing | 6NN \\|<psi6>\\| | 6NN <\\|psi6\\|> | Voronoi \\|<psi6>\\| | Voronoi <\\|psi6\\|> "
    )
    head += "| Voronoi-weighted \\|<psi6>\\| | Voronoi-weighted <\\|psi6\\|> |"
    head += " HistoricDisks \\|<psi6>\\| |" if historic else ""
    print(head)
    print("|---" * (9 if historic else 8) + "|")
    for cells, phi in ROWS:
        s, box = hexagonal(cells, phi, seed=1)
        sim = hs.Simulation(s, box)
        vals = []
        for _ in range(args.stretches):
            sim.run(collisions=100 * s.n)
            vals.append(values(sim, historic))
        first, mean = vals[0], np.mean(vals, axis=0)
        cols = " | ".join(f"{a:.3f} ({b:.3f})" for a, b in zip(first, mean, strict=True))
        print(f"| {s.n} | {phi} | {cols} |", flush=True)
    print(f"\neach cell: after 100 collisions per disk (mean over {args.stretches} x 100 per disk)")
    print(f"running time: {time.time() - t0:.0f} s")


if __name__ == "__main__":
    main()

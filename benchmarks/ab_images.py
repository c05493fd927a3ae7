"""A/B cost of a core change, in one process: base and new engines interleaved.

The machine is shared, so separate runs of ``hardspheres bench`` scatter by
a factor of two.  Here both versions of the package are imported into one
process (the base one under another name), run the same system for the
same number of collisions in alternation, and are timed by CPU time
(``time.process_time``); the result is the median over pairs of the ratio.

usage: python3 benchmarks/ab_images.py BASE_SRC [pairs] [N] [packing] [collisions]
  BASE_SRC: a ``src`` directory of the base commit, e.g. from
  ``git archive be21aa8 src | tar -x -C /tmp/base``.  The new code is this
  checkout's (PYTHONPATH).
"""

import importlib.util
import os
import shutil
import sys
import tempfile
import time

import numpy as np


def load_as(src, name):
    """Import the package ``hardspheres`` found in ``src`` as ``name``."""
    tmp = tempfile.mkdtemp()
    shutil.copytree(os.path.join(src, "hardspheres"), os.path.join(tmp, name),
                    ignore=shutil.ignore_patterns("__pycache__"))
    spec = importlib.util.spec_from_file_location(name, os.path.join(tmp, name, "__init__.py"),
                                                  submodule_search_locations=[os.path.join(tmp, name)])
    mod = importlib.util.module_from_spec(spec)
    sys.modules[name] = mod
    spec.loader.exec_module(mod)
    return mod


def engine(pkg, n, packing, seed=0):
    builders = importlib.import_module(f"{pkg.__name__}.builders")
    eng_mod = importlib.import_module(f"{pkg.__name__}.engine")
    edge = (n * (4.0 / 3.0) * np.pi * 0.125 / packing) ** (1.0 / 3.0)
    st = builders.random_spheres(n, packing, box=edge, seed=seed)
    eng = eng_mod.Engine(st.masses, st.radii, st.positions, st.velocities, box=edge)
    eng.advance(collisions=n, record=False)
    return eng


def main():
    base_src = sys.argv[1]
    pairs = int(sys.argv[2]) if len(sys.argv) > 2 else 20
    n = int(sys.argv[3]) if len(sys.argv) > 3 else 10000
    packing = float(sys.argv[4]) if len(sys.argv) > 4 else 0.3
    coll = int(sys.argv[5]) if len(sys.argv) > 5 else 300000
    import hardspheres as new
    base = load_as(base_src, "hardspheres_base")
    print(f"base: {base.__file__}\nnew:  {new.__file__}", flush=True)
    engines = {"base": engine(base, n, packing), "new": engine(new, n, packing)}
    ratios = []
    rates = {"base": [], "new": []}
    for k in range(pairs):
        order = ("base", "new") if k % 2 == 0 else ("new", "base")
        for tag in order:
            t0 = time.process_time()
            engines[tag].advance(collisions=coll, record=False)
            rates[tag].append(coll / (time.process_time() - t0))
        ratios.append(rates["new"][-1] / rates["base"][-1])
        print(f"pair {k}: base {rates['base'][-1]:.4g} new {rates['new'][-1]:.4g} "
              f"new/base {ratios[-1]:.4f}", flush=True)
    r = np.array(ratios)
    print(f"N={n} packing={packing}, {pairs} pairs of {coll} collisions (CPU time): "
          f"median base {np.median(rates['base']):.4g}/s, new {np.median(rates['new']):.4g}/s; "
          f"median new/base {np.median(r):.4f}, quartiles {np.percentile(r, 25):.4f} "
          f"{np.percentile(r, 75):.4f}; load {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()

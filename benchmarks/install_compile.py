"""The first run after ``pip install``: with the event core compiled at install, and without.

For each way (``precompiled``: the build step of ``setup.py`` as shipped;
``jit``: the same with ``HARDSPHERES_PRECOMPILE=0``), builds the wheel of the
tree (``pip wheel --no-deps``, timed), installs it in a new virtual
environment (``--system-site-packages``, for numpy and numba), and runs in a
new process, from the installed package, a first simulation in 3-D (the
README's: 500 spheres at packing 0.3, 20000 collisions) and one in 2-D (400
disks at 0.5, 20000 collisions).  Prints the wheel's build seconds and size,
then each first run's CPU and wall seconds, imports included.  No
``NUMBA_CACHE_DIR``: the cache is the installed package's own.

usage: install_compile.py [TREE] [--ways precompiled,jit]
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

FIRST = """
import json, sys, time
t0, c0 = time.perf_counter(), time.process_time()
import hardspheres as hs
if sys.argv[1] == "3":
    box = hs.PeriodicBox.for_packing(500, 0.3)
    sim = hs.Simulation(hs.random_spheres(500, 0.3, box, seed=1), box)
else:
    box = hs.PeriodicBox.for_packing(400, 0.5, (1, 1))
    sim = hs.Simulation(hs.random_spheres(400, 0.5, box, seed=1), box)
sim.run(collisions=20_000)
print(json.dumps({"file": hs.__file__, "wall": time.perf_counter() - t0, "cpu": time.process_time() - c0}))
"""


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("tree", nargs="?", default=os.path.join(os.path.dirname(__file__), ".."))
    p.add_argument("--ways", default="precompiled,jit")
    a = p.parse_args()
    tree = os.path.abspath(a.tree)
    env = {k: v for k, v in os.environ.items() if k not in ("NUMBA_CACHE_DIR", "PYTHONPATH")}
    for way in a.ways.split(","):
        with tempfile.TemporaryDirectory(prefix=f"install-{way}-") as tmp:
            build_env = dict(env, HARDSPHERES_PRECOMPILE="0" if way == "jit" else "1")
            t0 = time.perf_counter()
            subprocess.run(
                [sys.executable, "-m", "pip", "wheel", "-q", "--disable-pip-version-check", "--no-deps"]
                + ["-w", tmp, tree],
                env=build_env,
                check=True,
            )
            built = time.perf_counter() - t0
            wheel = next(os.path.join(tmp, f) for f in os.listdir(tmp) if f.endswith(".whl"))
            venv = os.path.join(tmp, "venv")
            subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", venv], check=True)
            python = os.path.join(venv, "bin", "python")
            subprocess.run(
                [python, "-m", "pip", "install", "-q", "--disable-pip-version-check", "--no-deps", wheel],
                env=env,
                check=True,
            )
            print(
                f"{way}: pip wheel {built:.1f} s wall, wheel {os.path.getsize(wheel) / 1e6:.1f} MB",
                flush=True,
            )
            for d in ("3", "2", "3"):
                out = subprocess.run(
                    [python, "-c", FIRST, d], env=env, cwd=tmp, capture_output=True, text=True, check=True
                )
                got = json.loads(out.stdout)
                assert got["file"].startswith(venv), got["file"]
                print(
                    f"  {d}-D first simulation: cpu {got['cpu']:.2f} s, wall {got['wall']:.2f} s", flush=True
                )


if __name__ == "__main__":
    main()

"""A 16-task study on a LocalCluster of one worker, then of two: wall time and speed-up.

    python benchmarks/sweep.py [--n 2000] [--collisions 3000]

Each task: N equal spheres in a periodic box, 100 collisions per sphere to
equilibrate, then COLLISIONS per sphere measured in 10 blocks (4 packings x
4 seeds).  Workers are single-threaded processes; each is warmed up (the
compiled core loaded) before the clock starts.  Prints one line per cluster
size, the speed-up, whether both runs gave the same bits, and the load
average of the machine before and after (other work on the machine slows
the two-worker run most).
"""

import argparse
import logging
import os
import tempfile
import time


def _warm():
    import hardspheres as hs
    sim = hs.Simulation(hs.random_spheres(64, 0.3, box=5.0, seed=0), hs.PeriodicBox(5.0))
    sim.run(collisions=100)
    return os.getpid()


def main():
    from distributed import Client, LocalCluster

    from hardspheres.studies import sweep

    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--n", type=int, default=2000)
    p.add_argument("--collisions", type=int, default=3000)
    args = p.parse_args()
    results, times = {}, {}
    print(f"load average before: {os.getloadavg()[0]:.2f} (1 min), cores: {os.cpu_count()}")
    for workers in (1, 2):
        with tempfile.TemporaryDirectory() as folder:
            spec = {"output": folder, "packing": [0.2, 0.3, 0.4, 0.45], "n": args.n,
                    "seeds": 4, "equilibrate": 100, "collisions": args.collisions,
                    "blocks": 10, "measure": ["Z", "collision_rate"]}
            with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                              dashboard_address=":0", silence_logs=logging.ERROR) as cluster, \
                    Client(cluster) as client:
                client.run(_warm)
                t0 = time.perf_counter()
                df = sweep(spec, client=client)
                times[workers] = time.perf_counter() - t0
            results[workers] = df
        print(f"{workers} worker(s): 16 tasks in {times[workers]:.1f} s "
              f"({16 / times[workers]:.3f} tasks/s)", flush=True)
    same = results[1].equals(results[2])
    print(f"speed-up 2 workers / 1 worker: {times[1] / times[2]:.2f}x; "
          f"same bits: {'yes' if same else 'NO'}")
    print(f"load average after: {os.getloadavg()[0]:.2f} (1 min)")


if __name__ == "__main__":
    main()

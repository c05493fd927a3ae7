"""``hardspheres run``: a scenario run to an end time, with the trimmings.

Progress bar on stderr (only on a terminal), trajectory frames, a checkpoint
at the end or on Ctrl-C, and a summary.
"""

import signal
import sys
import time

from .containers import PeriodicBox, SphericalContainer
from .simulation import Simulation


class Progress:
    """A one-line progress bar on a terminal; silent otherwise."""

    def __init__(self, total, stream=sys.stderr):
        self.total = total
        self.stream = stream
        self.on = stream.isatty()
        self.t0 = time.perf_counter()

    def update(self, done, note=""):
        if not self.on:
            return
        frac = min(1.0, done / self.total) if self.total else 1.0
        bar = "#" * int(30 * frac)
        self.stream.write(f"\r[{bar:<30}] {frac:6.1%} {note}")
        self.stream.flush()

    def close(self):
        if self.on:
            self.stream.write("\n")
            self.stream.flush()


def _simulation(args):
    if args.resume:
        if args.scenario:
            raise ValueError("give a scenario or --resume, not both")
        return Simulation.load(args.resume)
    if not args.scenario:
        raise ValueError("give a scenario file (or --resume CHECKPOINT)")
    if args.container is None and args.box is None:
        raise ValueError("give --container RADIUS or --box LENGTH")
    container = (SphericalContainer(args.container) if args.container is not None
                 else PeriodicBox(args.box))
    source = sys.stdin.buffer.read() if args.scenario == "-" else args.scenario
    if isinstance(source, bytes) and b"\n" not in source:
        source += b"\n"
    return Simulation.from_scenario(source, container)


def _writer(path, every):
    from .trajectory import GSDWriter, XYZWriter
    if path.endswith(".gsd"):
        return GSDWriter(path, every)
    if path.endswith((".xyz", ".extxyz")):
        return XYZWriter(path, every)
    raise ValueError(f"trajectory {path!r}: use a .gsd or .xyz file name")


def run_command(args):
    """Run ``hardspheres run``; returns the exit status."""
    sim = _simulation(args)
    if args.until <= sim.time:
        raise ValueError(f"--until {args.until} is not after the simulation's time {sim.time}")
    writer = None
    if args.trajectory:
        every = args.every or (args.until - sim.time) / 100.0
        writer = _writer(args.trajectory, every)
        sim.writers.append(writer)
    e0 = sim.state().kinetic_energy()
    c0 = dict(sim.counters)
    sim.observables.reset()

    def on_sigint(signum, frame):
        sim.stop_requested = True

    old = signal.signal(signal.SIGINT, on_sigint)
    progress = Progress(args.until - sim.time)
    start_time, t0 = sim.time, time.perf_counter()
    try:
        steps = 200
        for k in range(1, steps + 1):
            sim.run(until=start_time + (args.until - start_time) * k / steps)
            if getattr(sim, "stop_requested", False):
                break
            progress.update(sim.time - start_time, f"t={sim.time:.6g}")
    finally:
        signal.signal(signal.SIGINT, old)
        progress.close()
        if writer is not None:
            writer.close()
    wall = time.perf_counter() - t0
    interrupted = getattr(sim, "stop_requested", False)
    if args.checkpoint:
        sim.stop_requested = False
        sim.save(args.checkpoint)
    c1 = sim.counters
    events = (c1["collisions"] - c0["collisions"]) + (c1["reflections"] - c0["reflections"])
    e1 = sim.state().kinetic_energy()
    summary = sim.observables.summary()
    lines = [
        f"time {sim.time:.9g}" + (" (interrupted)" if interrupted else ""),
        f"events {events}: {c1['collisions'] - c0['collisions']} collisions, "
        f"{c1['reflections'] - c0['reflections']} reflections",
        f"energy drift {abs(e1 - e0) / e0 if e0 else 0.0:.3g} (relative)",
    ]
    if "pressure" in summary:
        lines.append(f"pressure {summary['pressure']:.6g}, "
                     f"Z = PV/NkT {summary['compressibility']:.6g}, "
                     f"kT {summary['temperature']:.6g}")
        lines.append(f"collision rate {summary['collision_rate']:.6g} per sphere per unit time, "
                     f"mean free path {summary['mean_free_path']:.6g}")
    lines.append(f"{events / wall if wall > 0 else 0.0:.4g} events/s over {wall:.3g} s")
    if args.checkpoint:
        lines.append(f"checkpoint {args.checkpoint}")
    if args.trajectory:
        lines.append(f"trajectory {args.trajectory}")
    print("\n".join(lines))
    if interrupted:
        print("interrupted" + (f"; resume with --resume {args.checkpoint}"
                               if args.checkpoint else ""), file=sys.stderr)
        return 130
    return 0

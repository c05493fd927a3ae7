"""``hardspheres run``: a scenario run to an end time, with the trimmings.

Progress bar on stderr (only on a terminal), trajectory frames, a checkpoint
at the end or on Ctrl-C, and a summary.

Faults: every output is checked before the run starts (the checkpoint's
folder is writable and no other writer holds it; an existing trajectory is
continued on ``--resume`` if it ends where the checkpoint starts, else
refused unless ``--overwrite``).  SIGINT and SIGTERM stop the run at the
next chunk of events; the checkpoint is then written with both signals
deferred (a second Ctrl-C does not lose it), and the exit status is
128 + the signal's number.  A trajectory that cannot be written (a full
disk) ends the run, but the checkpoint is still written.
"""

import os
import signal
import sys
import time

from .containers import PeriodicBox, SphericalContainer
from .fileio import PathLock
from .messages import oserror_line
from .simulation import Simulation

#: Signals that stop a run cleanly (checkpoint written).
STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM)


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


def _writer(args, sim, every):
    """The trajectory writer: continuing the file on resume, refusing to clobber it."""
    from .trajectory import GSDWriter, NotAContinuation, XYZWriter
    path = args.trajectory
    if path.endswith(".gsd"):
        cls = GSDWriter
    elif path.endswith((".xyz", ".extxyz")):
        cls = XYZWriter
    else:
        raise ValueError(f"trajectory {path!r}: use a .gsd or .xyz file name")
    exists = os.path.exists(path) and os.path.getsize(path) > 0
    if exists and not args.overwrite and not args.resume:
        raise ValueError(f"trajectory {path} exists; give --overwrite to replace it, "
                         "or another file name")
    writer = cls(path, every, append=bool(args.resume) and not args.overwrite)
    writer.until = args.until  # the run goes there in pieces: a cut-short file shows
    try:
        writer.attach(sim)
    except NotAContinuation as e:
        writer.close()
        raise ValueError(f"{e}, or give --overwrite to replace it") from None
    except BaseException:
        writer.close()
        raise
    return writer


class _Stopper:
    """SIGINT and SIGTERM set a flag (and the simulation's stop request) instead of raising.

    Installed for the whole run, checkpoint included, so that a signal
    never interrupts a save; :attr:`signum` is the first signal received.
    """

    def __init__(self, sim):
        self.sim = sim
        self.signum = None
        self._old = {}

    def _handle(self, signum, frame):
        if self.signum is None:
            self.signum = signum
        self.sim.stop_requested = True

    def __enter__(self):
        for s in STOP_SIGNALS:
            self._old[s] = signal.signal(s, self._handle)
        return self

    def __exit__(self, *exc):
        for s, old in self._old.items():
            signal.signal(s, old)
        return False


def run_command(args):
    """Run ``hardspheres run``; returns the exit status."""
    sim = _simulation(args)
    if args.until <= sim.time:
        raise ValueError(f"--until {args.until} is not after the simulation's time {sim.time}")
    # every output is checked (and locked) before the run starts
    lock = PathLock(args.checkpoint) if args.checkpoint else None
    try:
        return _run(args, sim, lock)
    finally:
        if lock is not None:
            lock.release()


def _run(args, sim, lock):
    writer = None
    e0 = sim.state().kinetic_energy()
    c0 = dict(sim.counters)
    sim.observables.reset()
    failure = None
    progress = Progress(args.until - sim.time)
    start_time, t0 = sim.time, time.perf_counter()
    with _Stopper(sim) as stopper:
        try:
            if args.trajectory:
                every = args.every or (args.until - sim.time) / 100.0
                writer = _writer(args, sim, every)
                sim.writers.append(writer)
            steps = 200
            for k in range(1, steps + 1):
                sim.run(until=start_time + (args.until - start_time) * k / steps)
                if stopper.signum is not None:
                    break
                progress.update(sim.time - start_time, f"t={sim.time:.6g}")
            if writer is not None and writer.last_time is not None and (
                    writer.last_time < sim.time):
                writer.write(sim, sim.time)  # the file ends where the checkpoint starts
        except OSError as e:
            if writer is None or e.filename != writer.path:
                raise
            failure = e  # the trajectory's disk: still write the checkpoint
        finally:
            progress.close()
            if writer is not None:
                if writer in sim.writers:
                    sim.writers.remove(writer)
                try:
                    writer.close()
                except OSError as e:
                    failure = failure or e
        wall = time.perf_counter() - t0
        signum = stopper.signum
        if args.checkpoint:
            sim.stop_requested = False
            sim._save(args.checkpoint, lock=False)
    c1 = sim.counters
    events = (c1["collisions"] - c0["collisions"]) + (c1["reflections"] - c0["reflections"])
    e1 = sim.state().kinetic_energy()
    summary = sim.observables.summary()
    lines = [
        f"time {sim.time:.9g}" + (" (interrupted)" if signum is not None else "")
        + (" (stopped: trajectory not written)" if failure is not None else ""),
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
    resume = f"; resume with --resume {args.checkpoint}" if args.checkpoint else ""
    if failure is not None:
        print(f"hardspheres run: {oserror_line(failure)}{resume}", file=sys.stderr)
        return 1
    if signum is not None:
        name = signal.Signals(signum).name
        print(f"interrupted ({name}){resume}", file=sys.stderr)
        return 128 + signum
    return 0

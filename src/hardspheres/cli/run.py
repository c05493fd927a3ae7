"""``hardspheres run``: a scenario run to an end time, with the trimmings.

Progress bar on stderr (only on a terminal: rate and time left; a writer
redrawn by its trigger as the run goes), trajectory
frames, a checkpoint at the end or on Ctrl-C, an optional equilibration
before the averages start, and a summary of what was measured, with its
statistical errors when the observables give them.

Faults: every output is checked before the run starts (the checkpoint's
folder is writable and no other writer holds it; an existing trajectory is
continued on ``--resume`` if it ends where the checkpoint starts, else
refused unless ``--overwrite``).  SIGINT and SIGTERM stop the run at the
next chunk of events; the checkpoint is then written with both signals
deferred (a second Ctrl-C does not lose it), and the exit status is
128 + the signal's number.  A trajectory that cannot be written (a full
disk) ends the run, but the checkpoint is still written.
"""

from __future__ import annotations

import argparse
import math
import os
import shutil
import signal
import sys
import time
from collections.abc import Callable
from types import FrameType
from typing import TYPE_CHECKING, Any, Literal

from ..errors import UsageError
from ..fileio import PathLock
from ..messages import oserror_line
from ..progress import Progress
from .options import (
    count,
    finite,
    nonnegative,
    positive,
    refuse_existing,
    restitution,
    shear_rate,
    where_args,
)
from .source import given_container, starting_simulation

if TYPE_CHECKING:
    import numpy as np

    from ..containers import Container
    from ..dense import RandomKicks
    from ..io.trajectory import GSDWriter, XYZWriter
    from ..simulation import Simulation
    from ..writers import SimulationView, Trigger
    from .options import Subcommands

#: Signals that stop a run cleanly (checkpoint written).
STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM)

#: Warn when a trajectory is expected to grow past this many bytes.
LARGE_TRAJECTORY = 1e9

# bytes per sphere per frame (position and velocity, float64) and per event
# (time, kind, i, j, impulse as float64) in a GSD trajectory
_FRAME_BYTES_PER_SPHERE = 48
_EVENT_BYTES = 40


class ProgressWriter:
    """The progress bar of a run as a :class:`~hardspheres.writers.Writer`.

    Its trigger (a :class:`~hardspheres.writers.Periodic` one by default:
    ``steps`` updates over the run) says when the bar is redrawn; the run
    itself goes in one :meth:`Simulation.run <hardspheres.Simulation.run>`.

    Args:
        progress: the :class:`~hardspheres.progress.Progress` bar (its total
            is the run's length [time]).
        start: the run's start [time]; ``progress`` counts from it.
        steps: updates over the run (ignored with ``trigger``).
        trigger: when to update (:mod:`hardspheres.writers`).
        first: called once, as ``first(events, elapsed)``, at the first update
            after the start (events and simulated time so far).
    """

    wants_events = False
    next_collisions = math.inf

    def __init__(
        self,
        progress: Progress,
        start: float,
        steps: int = 200,
        trigger: Trigger | None = None,
        first: Callable[[int, float], None] | None = None,
    ) -> None:
        from ..writers import Periodic

        self.progress = progress
        self.start = start
        self.trigger = trigger if trigger is not None else Periodic(progress.total / steps)
        self.first = first
        self._events0: int | None = None

    @property
    def next_time(self) -> float:
        """When the bar is next redrawn [time] (``inf`` before it is attached)."""
        return self.trigger.next_time if self._events0 is not None else math.inf

    def attach(self, sim: SimulationView) -> None:
        """Start (once): the trigger, from now; the first redraw is a step later."""
        if self._events0 is None:
            self._events0 = _events_so_far(sim)
            self.trigger.start(sim.time, sim.counters["collisions"])
            while self.trigger.next_time <= sim.time:
                self.trigger.fired()

    def write(self, sim: SimulationView, t: float) -> None:
        """Redraw the bar at the clock ``t`` [time]."""
        self.trigger.fired()
        assert self._events0 is not None  # attach() came first
        done = _events_so_far(sim) - self._events0
        if self.first is not None and t > self.start:
            first, self.first = self.first, None
            first(done, t - self.start)
        self.progress.update(t - self.start, done, f"t={t:.6g}")

    def observe(self, events: np.ndarray) -> None:
        pass

    def detach(self) -> None:
        """Clear the bar."""
        self.progress.close()


def _check_args(args: argparse.Namespace) -> None:
    """Every argument of ``run`` checked before any work."""
    if args.resume:
        if args.scenario:
            raise UsageError("give a scenario or --resume, not both")
        if given_container(args) or args.dimensions is not None:
            raise UsageError(
                "--container/--circle/--box/--dimensions cannot change a resumed run: the checkpoint "
                "keeps its container (leave them out)"
            )
        if args.pressure is not None or args.pressure_axes is not None:
            raise UsageError(
                "--pressure/--pressure-axes cannot change a resumed run: the checkpoint "
                "keeps its barostat (leave them out)"
            )
        if args.restitution is not None or args.wall_restitution is not None or args.tc is not None:
            raise UsageError(
                "--restitution/--wall-restitution/--tc cannot change a resumed run: the checkpoint "
                "keeps its collision rule (leave them out)"
            )
        if args.wall_temperature is not None or args.wall_seed is not None:
            raise UsageError(
                "--wall-temperature/--wall-seed cannot change a resumed run: the checkpoint keeps its "
                "thermal wall (leave them out)"
            )
        if args.kicks is not None:
            raise UsageError(
                "--kicks cannot change a resumed run: the checkpoint keeps its driving, "
                "kicks included (leave it out)"
            )
        if args.shear_rate is not None or args.shear_temperature is not None:
            raise UsageError(
                "--shear-rate/--shear-temperature cannot change a resumed run: the checkpoint keeps its "
                "shear and its thermostat (leave them out)"
            )
        if args.well is not None or args.step is not None:
            raise UsageError(
                "--well/--step cannot change a resumed run: the checkpoint keeps its pair potential "
                "(leave them out)"
            )
    elif not args.scenario:
        raise UsageError("give a scenario file (or --resume CHECKPOINT)")
    elif not given_container(args):
        raise UsageError("give --container RADIUS, --circle RADIUS or --box L [LY [LZ]]")
    if args.pressure_axes is not None and args.pressure is None:
        raise UsageError("--pressure-axes is for constant pressure: give --pressure P too")
    _check_kicks(args)
    _check_wall(args)
    _check_shear(args)
    _check_steps(args)
    if args.trajectory is None:
        for option, value in (
            ("--every", args.every),
            ("--events", args.events),
            ("--log-frames", args.log_frames),
        ):
            if value:
                raise UsageError(f"{option} is for the trajectory: give --trajectory FILE.gsd")
    else:
        suffix = os.path.splitext(args.trajectory)[1].lower()
        if suffix not in (".gsd", ".xyz", ".extxyz"):
            raise UsageError(f"--trajectory {args.trajectory!r}: use a .gsd or .xyz file name")
        if args.events and suffix != ".gsd":
            raise UsageError("--events needs a .gsd trajectory (XYZ files hold no events)")


_ELASTIC_KICKS = (
    "--kicks drives a granular gas: give --restitution below 1 too (elastic spheres, kicked, heat "
    "without end)"
)


def _check_kicks(args: argparse.Namespace) -> None:
    """The white-noise driving's options: ``--kicks`` with its interval, not with a barostat."""
    if args.kicks is None:
        for option, value in (("--kick-interval", args.kick_interval), ("--kick-seed", args.kick_seed)):
            if value is not None:
                raise UsageError(f"{option} is for the white-noise kicks: give --kicks STRENGTH too")
        return
    if args.kick_interval is None:
        raise UsageError(
            "--kicks needs --kick-interval T, the time between kicks: a small fraction of the mean "
            "free time (1/20 of it; the summary says if it is too long)"
        )
    if args.wall_temperature:
        raise UsageError(
            "--kicks with --wall-temperature: one way of heating at a time (the summary weighs one "
            "heat source against the dissipation); give one or the other"
        )
    if (args.restitution or 1.0) >= 1.0 and (args.wall_restitution or 1.0) >= 1.0:
        raise UsageError(_ELASTIC_KICKS)
    if args.pressure is not None:
        raise UsageError(
            "--kicks with --pressure: the barostat holds kT = 1 and the kicks heat; give one or the other"
        )


_HEATS = (
    "a sheared elastic fluid heats without end (the shear's work stays in it): give "
    "--shear-temperature KT to hold its peculiar temperature, or --restitution below 1 (a granular "
    "gas, whose collisions take the heat out)"
)


def _check_shear(args: argparse.Namespace) -> None:
    """The shear's options: ``--shear-rate`` in a periodic box, held at a temperature if elastic."""
    if args.shear_rate is None:
        for option, value in (
            ("--shear-temperature", args.shear_temperature),
            ("--rescale-interval", args.rescale_interval),
        ):
            if value is not None and not args.resume:
                raise UsageError(f"{option} is for a sheared box: give --shear-rate G too")
        return
    if getattr(args, "box", None) is None:
        raise UsageError(
            "--shear-rate shears a periodic box (Lees-Edwards boundaries): give --box L [LY [LZ]] "
            "(a container's wall cannot slide)"
        )
    if args.shear_temperature is None and args.rescale_interval is not None:
        raise UsageError("--rescale-interval is for --shear-temperature: give --shear-temperature KT too")
    granular = (args.restitution or 1.0) < 1.0
    if args.shear_temperature is None and not granular:
        raise UsageError(_HEATS)
    if args.shear_temperature is not None:
        if granular:
            raise UsageError(
                "--shear-temperature with --restitution below 1: a sheared granular gas reaches its own "
                "steady state (the shear heats, the collisions cool); leave out --shear-temperature"
            )
        if args.rescale_interval is None:
            raise UsageError(
                "--shear-temperature needs --rescale-interval T, the time between rescalings: short "
                "against the heating time (1/10 of the mean free time to start; the summary says if "
                "it is too long)"
            )
    for option, value in (("--kicks", args.kicks), ("--pressure", args.pressure)):
        if value is not None:
            raise UsageError(
                f"--shear-rate with {option}: "
                + (
                    "the kicks act on the whole velocity, flow included; give one or the other"
                    if option == "--kicks"
                    else "the barostat's volume moves would change the sheared box; give one or the other"
                )
            )


def _check_steps(args: argparse.Namespace) -> None:
    """The pair potential's options, ``--well LAMBDA EPS`` or ``--step LAMBDA U`` repeated, as ``args.steps``.

    Refused with what the stepped core does not run yet: restitution below
    1, a thermal wall, shear, a barostat.
    """
    from ..core.reference import check_steps
    from ..errors import ArgumentError

    args.steps = None
    if args.well is None and args.step is None:
        return
    if args.well is not None and args.step is not None:
        raise UsageError("--well is one step: give --well LAMBDA EPS or --step LAMBDA U (repeated), not both")
    if args.well is not None:
        lam, eps = args.well
        if not (math.isfinite(lam) and lam > 1.0 and math.isfinite(eps) and eps > 0.0):
            raise UsageError(
                f"--well {args.well[0]:g} {args.well[1]:g}: give the width LAMBDA > 1 (in contact distances) "
                "and the depth EPS > 0 (for a shoulder, --step LAMBDA U with U > 0)"
            )
        steps = [(lam, -eps)]
    else:
        steps = [tuple(row) for row in args.step]
    try:
        check_steps(steps)
    except ArgumentError as e:
        raise UsageError(f"--step: {e}") from None
    if len(steps) > MOST_STEPS:
        raise UsageError(f"--step given {len(steps)} times: at most {MOST_STEPS} steps")
    what = "--well" if args.well is not None else "--step"
    for option, given in (
        ("--restitution below 1", (args.restitution or 1.0) < 1.0),
        ("--wall-restitution below 1", (args.wall_restitution or 1.0) < 1.0),
        ("--wall-temperature", args.wall_temperature is not None),
        ("--shear-rate", args.shear_rate is not None),
        ("--pressure", args.pressure is not None),
    ):
        if given:
            raise UsageError(f"{what} with {option}: not built yet (elastic spheres at constant volume only)")
    args.steps = steps


#: Steps the core takes at most (``--step`` repeated).
MOST_STEPS = 4


def add_shear(sim: Simulation, args: argparse.Namespace) -> None:
    """Hold the peculiar temperature ``--shear-temperature`` asks for (the box is sheared already)."""
    if getattr(args, "shear_temperature", None) is None:
        return
    from ..dense import PeculiarRescale

    sim.set_thermostat(PeculiarRescale(args.shear_temperature, args.rescale_interval))


def _check_wall(args: argparse.Namespace) -> None:
    """The thermal wall's options: ``--wall-temperature`` with a wall, not with a barostat."""
    if args.wall_temperature is None:
        if args.wall_seed is not None:
            raise UsageError("--wall-seed is for the thermal wall: give --wall-temperature KT too")
        return
    if args.wall_seed is not None and args.wall_seed >= 2**32:
        raise UsageError(f"--wall-seed {args.wall_seed}: give a seed below 2^32 = {2**32}")
    if getattr(args, "box", None) is not None:
        raise UsageError(
            "--wall-temperature heats the container's wall, and a periodic box has none: "
            "give --container R or --circle R"
        )
    if args.wall_restitution is not None:
        raise UsageError(
            "--wall-temperature replaces the wall's restitution (the wall re-emits at KT): "
            "leave out --wall-restitution"
        )
    if args.pressure is not None:
        raise UsageError(
            "--wall-temperature with --pressure: the barostat holds kT = 1 and the wall its own KT; "
            "give one or the other"
        )


def add_wall(sim: Simulation, args: argparse.Namespace) -> None:
    """Make the wall the thermal wall ``--wall-temperature`` asks for."""
    if args.wall_temperature is not None:
        sim.set_wall_temperature(args.wall_temperature, 0 if args.wall_seed is None else args.wall_seed)


def add_kicks(sim: Simulation, args: argparse.Namespace) -> None:
    """Set the white-noise kicks ``--kicks`` asks for (after ``--restitution``: a granular gas only)."""
    if args.kicks is None:
        return
    if not sim.inelastic:  # (a wall's restitution alone, and no wall)
        raise UsageError(_ELASTIC_KICKS)
    from ..dense import RandomKicks

    seed = 0 if args.kick_seed is None else args.kick_seed
    sim.set_thermostat(RandomKicks(args.kicks, args.kick_interval, seed=seed))


def _kicks(sim: Simulation) -> RandomKicks | None:
    """The simulation's white-noise kicks, if it is driven by them (a resumed run's included)."""
    from ..dense import RandomKicks

    th = sim.thermostat
    return th if isinstance(th, RandomKicks) else None


def _injected(sim: Simulation) -> float:
    """What the simulation's kicks and thermal wall injected so far (0 without them) [energy]."""
    kicks = _kicks(sim)
    return (kicks.injected if kicks is not None else 0.0) + sim.wall_heat


#: A kick interval longer than this many mean free times is warned of
#: (the kicks stand for a continuous random force: many per free flight).
LONGEST_KICK_INTERVAL = 0.2


#: Lags per decade of ``--log-frames``.
LOG_FRAMES_PER_DECADE = 10


def frame_schedule(args: argparse.Namespace, span: float) -> tuple[Trigger, int]:
    """``(trigger, frames)``: when the trajectory's frames are written over a run of ``span`` [s].

    Evenly every ``--every`` (default ``span / 100``), or with ``--log-frames
    FIRST`` on the multiple-origin log schedule
    (:class:`hardspheres.writers.LogOrigins`): lags ``FIRST .. --every``
    from an origin every ``--every`` (default ``span / 10``).  ``frames`` is
    about how many are written (for the size checks).
    """
    from ..writers import LogOrigins, Periodic

    if args.log_frames is None:
        every = args.every or span / 100.0
        return Periodic(every), int(span / every) + 1
    every = args.every or span / 10.0
    if args.log_frames >= every:
        raise UsageError(
            f"--log-frames {args.log_frames:g} is not shorter than the time between origins "
            f"(--every {every:g}); give a shorter first lag or a longer --every"
        )
    trigger = LogOrigins(args.log_frames, every, per_decade=LOG_FRAMES_PER_DECADE, until=every)
    per_origin = 2 + math.ceil(LOG_FRAMES_PER_DECADE * math.log10(every / args.log_frames))
    return trigger, (int(span / every) + 1) * per_origin


def _writer(args: argparse.Namespace, sim: Simulation, trigger: Trigger) -> GSDWriter | XYZWriter:
    """The trajectory writer: continuing the file on resume, refusing to clobber it."""
    from ..io.trajectory import GSDWriter, NotAContinuation, XYZWriter

    path = args.trajectory
    exists = os.path.exists(path) and os.path.getsize(path) > 0
    if exists and not args.resume:
        refuse_existing("--trajectory", path, args.overwrite)
    append = bool(args.resume) and not args.overwrite
    writer: GSDWriter | XYZWriter
    if path.lower().endswith(".gsd"):
        writer = GSDWriter(path, events=args.events, append=append, trigger=trigger)
    else:
        writer = XYZWriter(path, append=append, trigger=trigger)
    writer.until = args.until  # the run goes there in pieces: a cut-short file shows
    try:
        writer.attach(sim)
    except NotAContinuation as e:
        writer.close()
        raise UsageError(f"{e}, or give --overwrite to replace it") from None
    except BaseException:
        writer.close()
        raise
    return writer


class _Stopper:
    """SIGINT and SIGTERM set a flag (and the simulation's stop request) instead of raising.

    Installed for the whole run, checkpoint included, so that a signal
    never interrupts a save; :attr:`signum` is the first signal received.
    """

    def __init__(self, sim: Simulation) -> None:
        self.sim = sim
        self.signum: int | None = None
        self._old: dict[int, Any] = {}

    def _handle(self, signum: int, frame: FrameType | None) -> None:
        if self.signum is None:
            self.signum = signum
        self.sim.request_stop()

    def __enter__(self) -> _Stopper:
        for s in STOP_SIGNALS:
            self._old[s] = signal.signal(s, self._handle)
        return self

    def __exit__(self, *exc: object) -> Literal[False]:
        for s, old in self._old.items():
            signal.signal(s, old)
        return False


def _events_so_far(sim: SimulationView) -> int:
    c = sim.counters
    return c["collisions"] + c["reflections"]


def estimate_trajectory_bytes(
    n: int, frames: int, events_per_time: float, duration: float, with_events: bool
) -> float:
    """Expected size of a GSD trajectory [bytes]: frames, plus events if stored."""
    size: float = frames * (n * _FRAME_BYTES_PER_SPHERE + 200)
    if with_events:
        size += events_per_time * duration * _EVENT_BYTES
    return size


def _bytes(x: float) -> str:
    for unit, scale in (("GB", 1e9), ("MB", 1e6), ("kB", 1e3)):
        if x >= scale:
            return f"{x / scale:.3g} {unit}"
    return f"{x:.0f} bytes"


def _warn_size(
    args: argparse.Namespace,
    sim: Simulation,
    frames: int,
    start_time: float,
    first_step_events: int,
    first_step_time: float,
) -> None:
    """Warn once on stderr when the trajectory will be large (or will not fit)."""
    rate = first_step_events / first_step_time if first_step_time > 0 else 0.0
    size = estimate_trajectory_bytes(sim.n, frames, rate, args.until - start_time, args.events)
    folder = os.path.dirname(os.path.abspath(args.trajectory))
    try:
        free: float = shutil.disk_usage(folder).free
    except OSError:
        free = math.inf
    if size > free:
        print(
            f"hardspheres run: warning: {args.trajectory} will grow to about {_bytes(size)} "
            f"but only {_bytes(free)} is free there; use a larger --every"
            + (" or leave out --events" if args.events else ""),
            file=sys.stderr,
        )
    elif size > LARGE_TRAJECTORY:
        print(
            f"hardspheres run: warning: {args.trajectory} will grow to about {_bytes(size)} "
            f"({frames} frames" + (", with events" if args.events else "") + ")",
            file=sys.stderr,
        )


def _value(summary: dict[str, Any], key: str, fmt: str = ".6g") -> str:
    """``mean +- error`` when the observables give an error, else the mean."""
    mean = summary[key]
    err = summary.get(f"{key}_error")
    if err is None:
        return f"{mean:{fmt}}"
    if not math.isfinite(err):
        return f"{mean:{fmt}} (error unknown: run longer)"
    if err <= 0:  # no spread at all (one sphere: no collision): not an error bar of 0
        return f"{mean:{fmt}} (no error bar)"
    text = f"{mean:{fmt}} +- {err:.2g}"
    if summary.get(f"{key}_converged") is False:
        text += " (error not converged: a lower bound)"
    return text


def summary_lines(
    sim: Simulation, summary: dict[str, Any], averaged_from: float, equilibrated: str, resumed: bool = False
) -> list[str]:
    """The physics lines of the summary, labelled for what they are."""
    lines: list[str] = []
    if sim.inelastic and summary:
        return _granular_lines(sim, summary, averaged_from)
    if "pressure" not in summary:
        return lines
    since = f"averages over t = {averaged_from:.6g} .. {sim.time:.6g}" + (
        f" (after equilibrating: {equilibrated})"
        if equilibrated
        else " (from the resumed checkpoint on; not equilibrated in this run)"
        if resumed
        else " (from the start, not equilibrated in this run: a start far from equilibrium, "
        "such as a lattice, is in them; see --equilibrate)"
    )
    lines.append(since)
    kT = f"kT {summary['temperature']:.6g}"
    if "mean_temperature" in summary:  # (a sheared run's: the flow's kinetic energy is not heat)
        kT = f"peculiar kT {summary['mean_temperature']:.6g} (mean; {summary['temperature']:.6g} now)"
        if not _sheared(sim):  # (a stepped run's: the kinetic energy changes at captures and releases)
            kT = kT.removeprefix("peculiar ")
    if sim.container.wall_area > 0:
        lines.append(f"wall pressure {_value(summary, 'pressure')}, {kT}")
        term = (
            "circle: it includes a line-tension term"
            if sim.container.dimensions == 2
            else "sphere: it includes a surface term"
        )
        lines.append(
            f"PV/NkT {_value(summary, 'Z')} (wall pressure of a finite {term}, so it is not the "
            "bulk Z; use --box for bulk)"
        )
    else:
        lines.append(f"pressure {_value(summary, 'pressure')} (virial), {kT}")
        lines.append(f"Z = PV/NkT {_value(summary, 'Z')}")
    if sim.n < 2:
        # no advice that cannot help: a sphere alone never collides (issue 29)
        lines.append("collision rate 0 per sphere per unit time (one sphere: it never collides)")
        lines.append("mean free path inf (one sphere: it never collides)")
        return lines
    lines.append(f"collision rate {_value(summary, 'collision_rate')} per sphere per unit time")
    lines.append(f"mean free path {_value(summary, 'mean_free_path')}")
    if _sheared(sim):
        lines += shear_lines(sim, summary)
    if sim.steps:
        lines += step_lines(sim, summary)
    return lines


def _steps_text(steps: tuple[tuple[float, float], ...]) -> str:
    """``square well lambda 1.5, eps 1`` or the steps' list."""
    if len(steps) == 1 and steps[0][1] < 0:
        return f"square well lambda {steps[0][0]:g}, eps {-steps[0][1]:g}"
    return "steps " + ", ".join(f"(lambda {lam:g}, U {u:g})" for lam, u in steps)


def step_lines(sim: Simulation, summary: dict[str, Any]) -> list[str]:
    """A stepped run's lines: the potential, the potential energy per sphere, the heat capacity."""
    n = sim.n
    lines = [f"pair potential: {_steps_text(sim.steps)}"]
    if "potential_energy" in summary:
        per = {
            "u": summary["potential_energy"] / n,
            "u_error": summary["potential_energy_error"] / n,
            "u_converged": summary.get("potential_energy_converged"),
        }
        lines.append(
            f"potential energy per sphere U/N {_value(per, 'u')} (sampled at {summary['blocks']} block ends)"
        )
    if "heat_capacity" in summary:
        lines.append(
            f"heat capacity per sphere C_V/Nk {_value(summary, 'heat_capacity')} (from the kinetic-energy "
            "fluctuations at constant energy)"
        )
    return lines


def _sheared(sim: Simulation) -> bool:
    return bool(getattr(sim.container, "shear_rate", 0.0))


def _kinetic_integral(sim: Simulation) -> np.ndarray | None:
    """A sheared run's time integral of ``sum m c c`` so far (peculiar velocities; ``None`` unsheared)."""
    if not _sheared(sim):
        return None
    return sim.engine.stress_tallies(sim.time)["kinetic"].copy()


def _mean_peculiar_kT(sim: Simulation, kinetic0: np.ndarray, since: float) -> float:
    """The peculiar kT averaged over ``since .. now`` [energy], from the engine's kinetic integral."""
    d = sim.container.dimensions
    k = sim.engine.stress_tallies(sim.time)["kinetic"] - kinetic0
    return float(k[:d].sum()) / ((sim.time - since) * sim.container.degrees_of_freedom(sim.n))


#: The fluid may heat by at most this fraction of kT between two rescalings
#: of ``--shear-temperature`` (else a warning: the mean kT sits above the target).
MOST_HEATING_PER_RESCALE = 0.05

_SHEAR_NAMES = ("viscosity", "normal_stress_1", "normal_stress_2")


def _shear_estimates(sim: Simulation) -> dict[str, Any]:
    """The shear's averages with their blocking errors, as the summary gives them (a granular gas's too)."""
    out: dict[str, Any] = {}
    names = _SHEAR_NAMES if sim.container.dimensions == 3 else _SHEAR_NAMES[:2]
    for name in names:
        try:
            est = sim.observables.estimate(name)
        except ValueError:  # nothing measured since the averages started
            return {}
        out[name], out[f"{name}_error"], out[f"{name}_converged"] = est.mean, est.sem, est.converged
    return out


def shear_lines(sim: Simulation, summary: dict[str, Any]) -> list[str]:
    """A sheared run's lines: the rate and thermostat, the viscosity, the normal stress differences.

    Each with its blocking error (``(error not converged: a lower bound)``
    when the blocking has not converged).  A rescaling interval so long
    that the fluid heats by more than :data:`MOST_HEATING_PER_RESCALE` of
    kT between two rescalings is warned of on stderr.
    """
    from ..dense import PeculiarRescale

    g = float(sim.container.shear_rate)  # type: ignore[attr-defined]
    th = sim.thermostat
    held = (
        f"; peculiar kT held at {th.kT:g} by rescaling every {th.interval:g}"
        if isinstance(th, PeculiarRescale)
        else ""
    )
    lx = sim.container.sides[0]  # type: ignore[attr-defined]
    offset = sim.engine.shear_offset(sim.time)
    offset = 0.0 if abs(offset - lx * round(offset / lx)) < 1e-9 * lx else offset  # (a whole L_x: none)
    lines = [
        f"sheared at rate {g:g} (Lees-Edwards; flow along x, gradient along y): the images above "
        f"shifted by {offset:.6g} along x now{held}"
    ]
    if "viscosity" not in summary:
        summary = {**summary, **_shear_estimates(sim)}
    if "viscosity" not in summary:
        return lines + ["viscosity: nothing measured since the averages started"]
    lines.append(f"viscosity eta = -P_xy/g {_value(summary, 'viscosity')}")
    n2 = f"; N2 = P_yy - P_zz {_value(summary, 'normal_stress_2')}" if "normal_stress_2" in summary else ""
    lines.append(f"normal stress differences: N1 = P_xx - P_yy {_value(summary, 'normal_stress_1')}{n2}")
    eta = summary["viscosity"]
    if isinstance(th, PeculiarRescale) and math.isfinite(eta) and eta > 0:
        # between rescalings kT rises by 2 eta g^2 V / (d N) per unit time
        d, n = sim.container.dimensions, sim.n
        heating = 2.0 * eta * g * g * sim.container.volume * th.interval / (d * n * th.kT)
        if heating > MOST_HEATING_PER_RESCALE:
            print(
                f"hardspheres run: warning: the fluid heats by {heating:.2g} of kT between rescalings "
                f"(eta {eta:.3g}): the mean peculiar kT sits above {th.kT:g}; give --rescale-interval "
                f"{th.interval * 0.01 / heating:.2g} or less (1% of kT)",
                file=sys.stderr,
            )
    return lines


def _granular_lines(sim: Simulation, summary: dict[str, Any], averaged_from: float) -> list[str]:
    """A cooling gas's summary: its temperature, how fast it cools (Haff's law), its a2.

    A sheared one is heated by the shear: its peculiar temperature and the
    shear's lines instead (no Haff's law, and no a2 of a flowing gas).
    """
    if _sheared(sim):
        mean = (
            f"{summary['mean_temperature']:.6g} on average over t = {averaged_from:.6g} .. {sim.time:.6g}, "
            if "mean_temperature" in summary
            else ""
        )
        return [
            f"granular temperature (peculiar) kT {mean}{summary['temperature']:.6g} at t = {sim.time:.6g}: "
            "heated by the shear"
        ] + shear_lines(sim, {})
    lines = [f"granular temperature kT {summary['temperature']:.6g} at t = {sim.time:.6g}"]
    kicks = _kicks(sim)
    if sim.wall_temperature > 0.0:
        kt_w = sim.wall_temperature
        gave, lost = summary.get("injected", 0.0), summary.get("dissipated", 0.0)
        lines.append(
            f"heated by a thermal wall at kT_w {kt_w:g} (kT/kT_w {summary['temperature'] / kt_w:.4g} now): "
            f"over t = {averaged_from:.6g} .. {sim.time:.6g} the wall gave {gave:.6g} "
            f"and the collisions dissipated {lost:.6g} (equal in a steady state)"
        )
        # (no a2: a gas heated at its wall is colder and denser inside, and the
        # kurtosis of all its velocities mixes those temperatures)
        return lines
    if kicks is not None:
        lines += _driven_lines(sim, kicks, summary, averaged_from)
    elif "cooling_per_collision" in summary:
        haff = (1.0 - sim.restitution**2) / sim.container.dimensions
        lines.append(
            f"cooling over t = {averaged_from:.6g} .. {sim.time:.6g}: {summary['cooling_rate']:.4g} per "
            f"unit time on average, {summary['cooling_per_collision']:.4g} per collision per sphere "
            f"(Haff's law to first order, (1 - e^2)/d: {haff:.4g})"
        )
    if "a2" in summary:
        lines.append(
            f"a2 (velocity kurtosis) {summary['a2']:.3g} now (one snapshot: an error of order "
            f"1/sqrt(N) = {1.0 / math.sqrt(sim.n):.2g})"
        )
    return lines


def _driven_lines(
    sim: Simulation, kicks: RandomKicks, summary: dict[str, Any], averaged_from: float
) -> list[str]:
    """A driven gas's summary: what the kicks injected against what the collisions dissipated.

    A kick interval longer than :data:`LONGEST_KICK_INTERVAL` mean free
    times (measured over the averages) is warned of on stderr.
    """
    injected, dissipated = summary.get("injected", 0.0), summary.get("dissipated", 0.0)
    span = f"over t = {averaged_from:.6g} .. {sim.time:.6g}"
    lines = [
        f"driven by white-noise kicks (strength {kicks.strength:g}, every {kicks.interval:g}): "
        f"{span} injected {injected:.6g}, dissipated {dissipated:.6g}"
        + (f", their ratio {injected / dissipated:.4g} (1 in a steady state)" if dissipated > 0 else "")
    ]
    try:
        free_time = sim.observables.mean_free_time()
    except ValueError:  # no collision since the averages started: nothing to compare with
        return lines
    if math.isfinite(free_time) and kicks.interval > LONGEST_KICK_INTERVAL * free_time:
        print(
            f"hardspheres run: warning: the kicks come every {kicks.interval / free_time:.2g} mean free "
            f"times (the mean free time is {free_time:.4g} {span}): they stand for a continuous random "
            f"force only if many fall within a free flight; give --kick-interval {free_time / 20:.2g} "
            "(1/20 of it) or less",
            file=sys.stderr,
        )
    return lines


def _equilibrate(sim: Simulation, args: argparse.Namespace, progress: Progress, start_time: float) -> str:
    """Run the equilibration the arguments ask for; returns its description or ''."""
    if args.equilibrate is None and args.equilibrate_time is None:
        return ""
    if args.equilibrate_time is not None:  # ends before --until: run() checked
        what = f"{args.equilibrate_time:g} time units"
        sim.run(until=sim.time + args.equilibrate_time)
    else:
        collisions = args.equilibrate * sim.n // 2  # each collision counts for two spheres
        what = f"{args.equilibrate} collisions per sphere"
        sim.run(until=args.until, collisions=collisions)
        if sim.time >= args.until:
            raise UsageError(
                f"--equilibrate {args.equilibrate} did not finish before --until "
                f"{args.until:g} (at {sim.counters['collisions']} collisions): "
                "raise --until or lower --equilibrate"
            )
    progress.update(sim.time - start_time, _events_so_far(sim), "equilibrated")
    return f"{what}, to t = {sim.time:.6g}"


def run(args: argparse.Namespace) -> int:
    """Run ``hardspheres run``; returns the exit status."""
    _check_args(args)
    sim = starting_simulation(args)
    add_wall(sim, args)
    add_kicks(sim, args)
    add_shear(sim, args)
    if args.pressure is not None:
        from ..barostat import Barostat

        sim.set_barostat(Barostat(pressure=args.pressure, axes=args.pressure_axes))
    if args.until <= sim.time:
        raise UsageError(
            f"--until {args.until:g} is not after the simulation's time {sim.time:.9g}; give a later --until"
        )
    if args.every is not None and args.every > args.until - sim.time:
        raise UsageError(
            f"--every {args.every:g} is longer than the run "
            f"({args.until - sim.time:.6g}): the trajectory would hold one frame"
        )
    if args.equilibrate_time is not None and sim.time + args.equilibrate_time >= args.until:
        raise UsageError(
            f"--equilibrate-time {args.equilibrate_time:g} reaches past "
            f"--until {args.until:g}: nothing left to average"
        )
    # a resumed run keeps saving to its checkpoint unless told otherwise
    checkpoint = args.checkpoint or args.resume
    # every output is checked (and locked) before the run starts
    lock = PathLock(checkpoint) if checkpoint else None
    try:
        return _run(args, sim, checkpoint)
    finally:
        if lock is not None:
            lock.release()


def _check_trajectory_size(args: argparse.Namespace, sim: Simulation) -> None:
    """Before the first frame: refuse frames that cannot fit on the disk, warn if they are large.

    The frames alone (the events' share is known only once the run has
    started, and is warned of then).
    """
    _, frames = frame_schedule(args, args.until - sim.time)
    every = args.every or (args.until - sim.time) / 100.0
    size = estimate_trajectory_bytes(sim.n, frames, 0.0, args.until - sim.time, False)
    folder = os.path.dirname(os.path.abspath(args.trajectory))
    try:
        free: float = shutil.disk_usage(folder).free
    except OSError:
        free = math.inf
    if size > 1000.0 * free:
        # hopeless: refused before anything is written
        raise UsageError(
            f"--trajectory {args.trajectory}: {frames:.3g} frames (--every {every:g}) would take about "
            f"{_bytes(size)}, and only {_bytes(free)} is free there; use a larger --every"
        )
    if size > free:
        print(
            f"hardspheres run: warning: {args.trajectory} will grow to about {_bytes(size)} "
            f"but only {_bytes(free)} is free there; use a larger --every",
            file=sys.stderr,
        )
    elif size > LARGE_TRAJECTORY:
        print(
            f"hardspheres run: warning: {args.trajectory} will grow to about {_bytes(size)} "
            f"({frames} frames)",
            file=sys.stderr,
        )


def _run(args: argparse.Namespace, sim: Simulation, checkpoint: str | None) -> int:
    writer = bar = None
    if args.trajectory:
        _check_trajectory_size(args, sim)
    e0, dissipated0, injected0 = sim.state().kinetic_energy(), sim.dissipated, _injected(sim)
    u0 = sim.potential_energy()
    c0 = dict(sim.counters)
    failure = None
    start_time = sim.time
    progress = Progress(args.until - start_time)
    t0 = time.perf_counter()
    equilibrated = ""
    averaged_from, kinetic0 = sim.time, None
    with _Stopper(sim) as stopper:
        try:
            writer, warn = _trajectory_writer(args, sim, start_time)
            if writer is not None:
                sim.writers.append(writer)
            bar = ProgressWriter(progress, start_time, first=warn)
            sim.writers.append(bar)
            equilibrated = _equilibrate(sim, args, progress, start_time)
            averaged_from, kinetic0 = _start_averages(sim)
            if stopper.signum is None:
                sim.run(until=args.until)
            if writer is not None and writer.last_time is not None and (writer.last_time < sim.time):
                writer.write(sim, sim.time)  # the file ends where the checkpoint starts
        except OSError as e:
            if writer is None or e.filename != writer.path:
                raise
            failure = e  # the trajectory's disk: still write the checkpoint
        finally:
            for w in (bar, writer):
                if w is not None and w in sim.writers:
                    sim.writers.remove(w)
            progress.close()
            if writer is not None:
                try:
                    writer.close()
                except OSError as e:
                    failure = failure or e
        wall = time.perf_counter() - t0
        signum = stopper.signum
        if checkpoint:
            sim.stop_requested = False
            sim.save(checkpoint, lock=False)
    c1 = sim.counters
    events, events_text = _events(c0, c1)
    e1 = sim.state().kinetic_energy()
    summary = _summary(sim, averaged_from, kinetic0) if sim.time > averaged_from and e1 > 0 else {}
    lines = [
        f"time {sim.time:.9g}"
        + (" (interrupted)" if signum is not None else "")
        + (" (stopped: trajectory not written)" if failure is not None else ""),
        f"{sim.n} {'disks' if sim.container.dimensions == 2 else 'spheres'}, "
        f"{_container_text(sim.container)}",
        events_text,
        _energy_line(sim, e0, e1, dissipated0, injected0, u0),
    ]
    lines += summary_lines(sim, summary, averaged_from, equilibrated, resumed=bool(args.resume))
    if args.trajectory and equilibrated:
        lines.append(
            f"trajectory: frames from t = {start_time:.6g}, so they include the equilibration "
            f"(averages start at t = {averaged_from:.6g})"
        )
    if sim.barostat is not None:
        lines.append(barostat_line(sim))
    if e1 == 0:
        lines.append("all spheres at rest: no pressure or rates")
    lines += _last_lines(args, checkpoint, events, wall)
    print("\n".join(lines))
    return _exit_status(failure, signum, checkpoint)


def _last_lines(args: argparse.Namespace, checkpoint: str | None, events: int, wall: float) -> list[str]:
    """The summary's last lines: the rate of events, where the checkpoint and the trajectory went."""
    lines = [f"{events / wall if wall > 0 else 0.0:.4g} events/s over {wall:.3g} s (compilation excluded)"]
    if checkpoint:
        lines.append(f"checkpoint {checkpoint}")
    if args.trajectory:
        lines.append(f"trajectory {args.trajectory}" + (" (with events)" if args.events else ""))
    return lines


def _events(c0: dict[str, int], c1: dict[str, int]) -> tuple[int, str]:
    """The events between two counters, and the summary's line of them (with a stepped run's kinds)."""
    steps = [k for k in ("captures", "releases", "bounces") if k in c1]
    kinds = ["collisions", "reflections", *steps]
    counts = {k: c1[k] - c0.get(k, 0) for k in kinds}
    return sum(counts.values()), f"events {sum(counts.values())}: " + ", ".join(
        f"{counts[k]} {k}" for k in kinds
    )


def _start_averages(sim: Simulation) -> tuple[float, np.ndarray | None]:
    """Start the averages now: ``(the time, a sheared run's kinetic integral then)``."""
    sim.observables.reset()
    if sim.barostat is not None:
        sim.barostat.reset_averages()
    return sim.time, _kinetic_integral(sim)


def _summary(sim: Simulation, averaged_from: float, kinetic0: np.ndarray | None) -> dict[str, Any]:
    """The observables' summary, with a sheared run's mean peculiar kT (``mean_temperature``)."""
    summary = sim.observables.summary()
    if kinetic0 is not None:
        summary["mean_temperature"] = _mean_peculiar_kT(sim, kinetic0, averaged_from)
    return summary


def _energy_line(
    sim: Simulation, e0: float, e1: float, dissipated0: float, injected0: float = 0.0, u0: float = 0.0
) -> str:
    """The energy check: the drift of an elastic run, the balance of a granular one (driven or not).

    A stepped run's is of the total energy ``K + U`` (``u0`` its potential
    energy at the start), relative to the kinetic energy at the start.
    """
    if not sim.inelastic:
        if _sheared(sim):  # (no drift to show: not conserved)
            return "energy: the shear works on the fluid and the thermostat takes the heat out"
        if sim.steps:
            drift = abs(e1 + sim.potential_energy() - e0 - u0) / e0 if e0 else 0.0
            return f"total energy (kinetic + potential) drift {drift:.3g} (relative to the kinetic energy)"
        return f"energy drift {abs(e1 - e0) / e0 if e0 else 0.0:.3g} (relative)"
    lost = sim.dissipated - dissipated0
    if _sheared(sim):
        return (
            f"granular (restitution {sim.restitution:g}), sheared: dissipated {lost:.6g} "
            f"({lost / e0 if e0 else 0.0:.3g} of the energy at the start), which the shear's work "
            "supplies (no energy balance shown)"
        )
    kicks = _kicks(sim)
    gained = _injected(sim) - injected0
    balance = abs(e1 + lost - gained - e0) / e0 if e0 else 0.0
    rule = f"restitution {sim.restitution:g}"
    if sim.wall_temperature > 0.0:
        rule += f", thermal wall kT_w {sim.wall_temperature:g}"
    elif sim.container.wall_area > 0:
        rule += f", wall {sim.wall_restitution:g}"
    if sim.tc:
        rule += f", tc {sim.tc:g}"
    if kicks is not None or sim.wall_temperature > 0.0:
        return (
            f"granular ({rule}), driven: injected {gained:.6g}, dissipated {lost:.6g} "
            f"({lost / e0 if e0 else 0.0:.3g} times the energy at the start); kinetic + dissipated - "
            f"injected energy drift {balance:.3g} (relative)"
        )
    return (
        f"granular ({rule}): dissipated {lost:.6g} ({lost / e0 if e0 else 0.0:.3g} of the energy at the "
        f"start); kinetic + dissipated energy drift {balance:.3g} (relative)"
    )


def _trajectory_writer(args: argparse.Namespace, sim: Simulation, start_time: float) -> tuple:
    """The run's trajectory writer (or ``None``) and the size check after the first progress step."""
    if not args.trajectory:
        return None, None
    trigger, frames = frame_schedule(args, args.until - start_time)
    writer = _writer(args, sim, trigger)

    def warn(events: int, elapsed: float) -> None:
        if args.events:  # the frames alone were checked before the first
            _warn_size(args, sim, frames, start_time, events, elapsed)

    return writer, warn


def _exit_status(failure: OSError | None, signum: int | None, checkpoint: str | None) -> int:
    """The run's exit status, saying on stderr why it is not 0 (and how to resume)."""
    resume = f"; resume with --resume {checkpoint}" if checkpoint else ""
    if failure is not None:
        print(f"hardspheres run: {oserror_line(failure)}{resume}", file=sys.stderr)
        return 1
    if signum is not None:
        name = signal.Signals(signum).name
        print(f"interrupted ({name}){resume}", file=sys.stderr)
        return 128 + signum
    return 0


def barostat_line(sim: Simulation) -> str:
    """The summary's line on constant pressure: the pressure held, the moves, the mean packing.

    A packing that drifts over the averaged moves is warned of on stderr.
    """
    b = sim.barostat
    assert b is not None
    if b.drifting:
        print(
            f"hardspheres run: warning: the packing drifts by {b.packing_drift:+.4f} over the averaged "
            f"moves (mean {b.mean_packing:.6g}): the mean is uncertain at that level; run longer",
            file=sys.stderr,
        )
    moves = "isotropic" if b.axes is None else f"sides {b.axes}"
    mean = (
        f"mean packing {b.mean_packing:.6g} over {b.samples} moves"
        if b.samples
        else "no move since the averages started"
    )
    approach = ""
    if b.target is not None and b.squeezes:
        approach = (
            f"; {'still approaching' if b.approaching else 'approached'} the equation of state's "
            f"packing {b.target:.4f} ({b.squeezes} squeezes, not averaged)"
        )
    return (
        f"constant pressure {b.pressure:g} (barostat, {moves} moves): {b.accepted} of "
        f"{b.attempted} moves accepted ({b.acceptance:.0%}); {mean}{approach}"
    )


def _container_text(container: Container) -> str:
    return container.description


def add_parser(sub: Subcommands) -> argparse.ArgumentParser:
    """Add the subcommand to ``sub`` (the ``hardspheres`` parser's subparsers)."""
    p = sub.add_parser("run", help="run a scenario, with trajectory, checkpoints, summary")
    p.add_argument("scenario", nargs="?", help="scenario file in the assignment's format ('-' for stdin)")
    where_args(p, "spherical container radius [m]", "periodic box [m]")
    p.add_argument("--until", type=positive, required=True, help="end time [s]")
    eq = p.add_mutually_exclusive_group()
    eq.add_argument(
        "--equilibrate",
        type=count,
        metavar="COLLISIONS",
        help="collisions per sphere to run before the averages start",
    )
    eq.add_argument(
        "--equilibrate-time", type=positive, metavar="T", help="time [s] to run before the averages start"
    )
    _trajectory_args(p)
    p.add_argument(
        "--checkpoint",
        help="save the run here at the end or on Ctrl-C (with --resume: the resumed file, unless given)",
    )
    p.add_argument(
        "--resume",
        help="continue from this checkpoint instead of a scenario "
        "(an existing --trajectory that ends where it starts is continued)",
    )
    p.add_argument(
        "--overwrite", action="store_true", help="replace an existing --trajectory file (refused otherwise)"
    )
    p.add_argument(
        "--pressure",
        type=positive,
        metavar="P",
        help="hold the pressure P [energy/length^3] (beta P sigma^3 with kT = 1, diameter 1) by "
        "Monte Carlo volume moves of the periodic box (hardspheres.Barostat)",
    )
    p.add_argument(
        "--pressure-axes",
        metavar="AXES",
        help="with --pressure: move these sides one at a time instead of scaling the box "
        "('xyz' or 'xy': a crystal's shape relaxes; 'z': only a slab's long side)",
    )
    _rule_args(p)
    _step_args(p)
    p.set_defaults(func=run)
    return p


def _step_args(p: argparse.ArgumentParser) -> None:
    """The pair potential's options (square wells, stepped potentials)."""
    p.add_argument(
        "--well",
        nargs=2,
        type=finite,
        metavar=("LAMBDA", "EPS"),
        help="a square well around every sphere: pairs closer than LAMBDA contact distances (LAMBDA > 1) "
        "gain the energy -EPS [J] (the summary gives the potential energy and the heat capacity; "
        "elastic spheres at constant volume; the checkpoint keeps it)",
    )
    p.add_argument(
        "--step",
        nargs=2,
        type=finite,
        action="append",
        metavar=("LAMBDA", "U"),
        help="one step of a stepped pair potential: the energy U [J] inside LAMBDA contact distances "
        "(and outside the next step's); repeat it, outermost first, up to 4 times (--well L E is "
        "--step L -E)",
    )


def _trajectory_args(p: argparse.ArgumentParser) -> None:
    """The trajectory's options."""
    p.add_argument("--trajectory", help="write frames to this .gsd (or .xyz) file")
    p.add_argument(
        "--every",
        type=positive,
        help="time between trajectory frames [s] (default: the run / 100); with --log-frames, "
        "between time origins (default: the run / 10)",
    )
    p.add_argument(
        "--log-frames",
        type=positive,
        metavar="FIRST",
        help="frames at log-spaced lags FIRST, ..., --every (10 per decade) from a new time origin "
        "every --every: what F_s, tau_alpha and chi_4 need (plot fs, plot chi4) to resolve short "
        "times with few frames",
    )
    p.add_argument(
        "--events",
        action="store_true",
        help="also store every event in the .gsd (large: about 40 bytes each)",
    )


def _rule_args(p: argparse.ArgumentParser) -> None:
    """The collision rule's options (granular gases)."""
    p.add_argument(
        "--restitution",
        type=restitution,
        metavar="E",
        help="normal restitution coefficient of every collision, in (0, 1]: below 1 a granular gas, "
        "which cools (default 1: elastic)",
    )
    p.add_argument(
        "--wall-restitution",
        type=restitution,
        metavar="E",
        help="the container wall's restitution coefficient (default: --restitution)",
    )
    p.add_argument(
        "--tc",
        type=nonnegative,
        metavar="T",
        help="the TC model [s]: a collision within T of either sphere's previous one is elastic, "
        "which resolves inelastic collapse (a small fraction of the mean free time; default 0: off)",
    )
    p.add_argument(
        "--wall-temperature",
        type=positive,
        metavar="KT",
        help="make the container's wall a thermal wall at temperature KT [J]: a sphere that meets it "
        "leaves with a velocity drawn at KT (a heated granular gas, or a heat bath for elastic "
        "spheres; --container or --circle; the checkpoint keeps it)",
    )
    p.add_argument(
        "--wall-seed",
        type=count,
        metavar="SEED",
        help="with --wall-temperature: the seed of the wall's random numbers (default 0; below 2^32)",
    )
    p.add_argument(
        "--kicks",
        type=positive,
        metavar="STRENGTH",
        help="drive the granular gas with white noise (hardspheres.dense.RandomKicks): every "
        "--kick-interval each sphere's velocity gets a Gaussian kick of variance STRENGTH x interval "
        "per component, less the mean kick [m^2/s^3]; with --restitution below 1 it reaches a steady "
        "state (the checkpoint keeps the kicks)",
    )
    p.add_argument(
        "--kick-interval",
        type=positive,
        metavar="T",
        help="with --kicks: the time between kicks [s], a small fraction of the mean free time (1/20)",
    )
    p.add_argument(
        "--kick-seed",
        type=count,
        metavar="SEED",
        help="with --kicks: the seed of the kicks' random numbers (default 0; the same seed, the same run)",
    )
    p.add_argument(
        "--shear-rate",
        type=shear_rate,
        metavar="G",
        help="shear the periodic box at rate G [1/s] by Lees-Edwards boundaries (--box; flow along x, "
        "gradient along y): the summary gives the viscosity -P_xy/G and the normal stress "
        "differences (the checkpoint keeps the shear)",
    )
    p.add_argument(
        "--shear-temperature",
        type=positive,
        metavar="KT",
        help="with --shear-rate: hold the temperature of the peculiar velocities (less the flow G y) "
        "at KT [J] by rescaling them (hardspheres.dense.PeculiarRescale); an elastic fluid needs it, "
        "the shear heats it",
    )
    p.add_argument(
        "--rescale-interval",
        type=positive,
        metavar="T",
        help="with --shear-temperature: the time between rescalings [s], short against the heating "
        "time (1/10 of the mean free time to start)",
    )

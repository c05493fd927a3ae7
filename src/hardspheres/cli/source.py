"""The simulation a command starts from, and the frames a picture is drawn from.

:func:`starting_simulation` is the one place a command turns its arguments
(a scenario file or stdin, ``--container``/``--box``, or ``--resume``) into a
:class:`~hardspheres.Simulation`: the scenario is parsed once and checked
against the container before the event core is compiled, so bad input is
refused in one line without waiting for the compiler.

Disks (``--circle R``, ``--box LX LY``, or ``--box L --dimensions 2``) are
read from the same nine-field scenario lines as spheres, with ``z = 0`` and
``vz = 0`` on every line (:meth:`State.from_scenario
<hardspheres.State.from_scenario>` refuses any other, naming the line).
"""

from __future__ import annotations

import argparse
import math
import sys
import warnings
from collections.abc import Callable
from typing import TYPE_CHECKING

from ..errors import UsageError
from ..messages import quote
from .options import compile_first, note, suffix

if TYPE_CHECKING:
    from ..containers import Container
    from ..frames import Frames
    from ..simulation import Simulation


def given_container(args: argparse.Namespace) -> bool:
    """Whether ``--container``, ``--circle`` or ``--box`` is given."""
    return any(getattr(args, k, None) is not None for k in ("container", "circle", "box"))


def container_from(args: argparse.Namespace) -> Container:
    """The container ``--container R``, ``--circle R`` or ``--box L [LY [LZ]]`` names (one is given),
    checked against ``--dimensions``.

    Raises:
        ValueError: ``--dimensions`` does not match the container (one line naming both).
    """
    from ..containers import CircularContainer, PeriodicBox, SphericalContainer

    d = getattr(args, "dimensions", None)
    if args.container is not None:
        if d == 2:
            raise UsageError(
                "--container is a sphere (3-D), not --dimensions 2: for disks give --circle R or --box LX LY"
            )
        return SphericalContainer(args.container)
    if getattr(args, "circle", None) is not None:
        if d == 3:
            raise UsageError(
                "--circle is a circle (2-D), not --dimensions 3: for spheres give --container R or --box L"
            )
        return CircularContainer(args.circle)
    sides = [float(x) for x in args.box]
    if len(sides) == 1:
        return PeriodicBox((sides[0], sides[0]) if d == 2 else sides[0])
    if d is not None and d != len(sides):
        raise UsageError(
            f"--box {' '.join(f'{x:g}' for x in sides)} has {len(sides)} sides: a {len(sides)}-D box, "
            f"not --dimensions {d} (leave --dimensions out, or give {d} sides)"
        )
    return PeriodicBox(tuple(sides))


def starting_simulation(args: argparse.Namespace, scenario: str | None = None) -> Simulation:
    """The simulation a command starts from; the core is compiled after the input is read.

    Args:
        args: the parsed arguments: ``resume`` (a checkpoint, if the command
            takes one), ``container`` or ``box``, and the scenario file
            (``-`` for stdin) as ``scenario`` unless given here.
        scenario: the scenario file, when the command names it otherwise.

    Raises:
        ScenarioError: the scenario cannot be read or does not fit the container.
        ValueError: the scenario holds no spheres.
    """
    from ..scenario import check_scenario, parse_scenario
    from ..simulation import Simulation
    from ..state import State

    if getattr(args, "resume", None):
        sim = Simulation.load(args.resume)
        sheared = bool(getattr(sim.container, "shear_rate", 0.0))
        compile_first(sim.container.dimensions, inelastic=sim.inelastic, sheared=sheared)
        return sim
    name = scenario if scenario is not None else args.scenario
    container = container_from(args)
    if name == "-":
        data = sys.stdin.buffer.read()
    else:
        with open(name, "rb") as fh:
            data = fh.read()
    scn = parse_scenario(data)  # bad input is refused before the compilation
    if len(scn) == 0:
        raise UsageError(f"{name}: no spheres in the scenario; add a line per sphere")
    check_scenario(scn, container)
    if (
        container.dimensions == 3
        and len(scn) > 1
        and all(p[2] == 0.0 and v[2] == 0.0 for p, v in zip(scn.positions, scn.velocities))
    ):
        note(
            f"note: every sphere of {name} has z = 0 and vz = 0: run as a flat layer of spheres (3-D, "
            "kT over 3 degrees of freedom each); for disks give --circle R or --box LX LY"
        )
    g = getattr(args, "shear_rate", None)  # (run's option: a periodic box, checked)
    if g is not None:
        container = container.sheared_by(g)  # type: ignore[attr-defined]
    e = getattr(args, "restitution", None)  # (the collision rule: run's options)
    inelastic = (1.0 if e is None else e) < 1.0 or (getattr(args, "wall_restitution", None) or 1.0) < 1.0
    # before any clock starts, the variant the run needs: no rate includes compilation
    compile_first(container.dimensions, inelastic=inelastic, sheared=g is not None)
    return Simulation(
        State.from_scenario(scn, dimensions=container.dimensions),
        container,
        restitution=1.0 if e is None else e,
        wall_restitution=getattr(args, "wall_restitution", None),
        tc=getattr(args, "tc", None) or 0.0,
        steps=getattr(args, "steps", None),  # (run's --well/--step, checked)
    )


TRAJECTORY_SUFFIXES = (".gsd", ".xyz", ".extxyz")


def check_source(args: argparse.Namespace) -> None:
    """Check the input's options (trajectory or scenario) before any work."""
    if suffix(args.input) in TRAJECTORY_SUFFIXES:
        given = [
            o
            for o, v in (
                ("--container", args.container),
                ("--circle", args.circle),
                ("--box", args.box),
                ("--dimensions", args.dimensions),
                ("--until", args.until),
                ("--every", args.every),
            )
            if v
        ]
        if given:
            raise UsageError(
                f"{'/'.join(given)} {'is' if len(given) == 1 else 'are'} for "
                "scenarios, not trajectories "
                f"({args.input} holds its own): leave them out"
            )
        return
    if args.until is None or not given_container(args):
        raise UsageError(
            f"{quote(args.input)} is not a trajectory (.gsd, .xyz), so it is read as a "
            "scenario: give --container R (or --circle R, or --box L [LY [LZ]]) and --until T"
        )
    if args.every is not None and args.every > args.until:
        raise UsageError(
            f"--every {args.every:g} is longer than the run (--until "
            f"{args.until:g}): there would be one frame"
        )


#: The events a command that runs a scenario on the spot keeps in memory, at
#: most about twice this many (evenly thinned past it): the viewer shows
#: 200000 at most, a still none.
MAX_EVENTS_KEPT = 200_000

#: Bytes a frame of one sphere takes in memory while it is recorded (a
#: position, a velocity and a periodic image, 3 components of 8 bytes each).
FRAME_BYTES_PER_SPHERE = 72


def frames_from_args(args: argparse.Namespace, most: Callable[[int], int] | None = None) -> Frames:
    """Frames from a trajectory file, or from a scenario run on the spot.

    Args:
        args: the command's arguments (``input``, and for a scenario
            ``until``, ``every`` and the container).
        most: for a scenario, the most frames the command can use for ``n``
            spheres (the viewer's page holds at most 600): past it, frames
            are kept on a coarser grid (a whole multiple of ``--every``) and
            a note says so.  Without it, frames that cannot fit in half of
            this machine's memory are refused before the run.

    The run's events are kept evenly thinned past :data:`MAX_EVENTS_KEPT`,
    so memory stays bounded however long the run.
    """
    from ..io.trajectory import frames_from_simulation, read_trajectory

    path = args.input
    if suffix(path) in TRAJECTORY_SUFFIXES:
        from ..io.trajectory import TruncatedTrajectory

        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", TruncatedTrajectory)
            frames = read_trajectory(path)
        for w in caught:  # one line each, not Python's two-line warning format
            print(f"hardspheres {args.command}: warning: {w.message}", file=sys.stderr)
        return frames
    try:
        sim = starting_simulation(args, scenario=path)
    except ValueError as e:
        raise UsageError(f"{path}: {str(e).removeprefix(path + ': ')}") from None
    span = args.until - sim.time
    every = args.every or span / 200
    frames = math.floor(span / every) + 1  # and the last, at --until, when off the grid
    if most is not None:
        cap = max(2, most(sim.n))
        if frames > cap:
            stride = math.ceil((frames - 1) / (cap - 1))
            print(
                f"hardspheres {args.command}: note: --every {every:g} gives {frames:.3g} frames and "
                f"{cap} are shown, so one is kept every {every * stride:.6g} (memory stays bounded)",
                file=sys.stderr,
            )
            every *= stride
    else:
        from ..builders import machine_memory

        mem = machine_memory()
        need = float(frames) * sim.n * FRAME_BYTES_PER_SPHERE
        if mem is not None and need > mem / 2:
            fit = max(2, int(mem / 2 / (sim.n * FRAME_BYTES_PER_SPHERE)))
            raise UsageError(
                f"--every {every:g}: {frames:.3g} frames of {sim.n} spheres would take about "
                f"{need / 2**30:.3g} GiB in memory, and this machine has {mem / 2**30:.3g} GiB: "
                f"use --every {span / (fit - 1):.3g} or more"
            )
    return frames_from_simulation(sim, until=args.until, every=every, max_events=MAX_EVENTS_KEPT)

"""``hardspheres sample``: a scenario sampled by event-chain Monte Carlo, with its pressure.

The equilibrium twin of ``run``: the same scenario files and ``--box``,
``--trajectory`` and ``--checkpoint`` options, but the spheres move by
straight event chains (:class:`hardspheres.EventChain`), not by dynamics.
Its clock counts chains: ``--chains`` ends the run, ``--every`` spaces the
frames, ``--equilibrate`` chains come before the averages.  The summary
gives the pressure per axis and ``Z`` with blocking errors.  Ctrl-C or
SIGTERM stops at the next chunk of events, writes the checkpoint and exits
with 128 + the signal's number.
"""

from __future__ import annotations

import argparse
import math
import os
import signal
import sys
from types import FrameType
from typing import TYPE_CHECKING, Any

from ..errors import UsageError
from .options import count, positive, where_args, whole

if TYPE_CHECKING:
    from ..io.trajectory import GSDWriter, XYZWriter
    from ..mc.chain import EventChain
    from .options import Subcommands


def add_parser(sub: Subcommands) -> argparse.ArgumentParser:
    """Add the subcommand to ``sub`` (the ``hardspheres`` parser's subparsers)."""
    p = sub.add_parser(
        "sample",
        help="sample a scenario by event-chain Monte Carlo (periodic box): pressure per axis, frames",
    )
    p.add_argument("scenario", nargs="?", help="scenario file (- for stdin); not with --resume")
    where_args(p, "spherical container radius [m] (refused: event chains need a box)", "periodic box [m]")
    p.add_argument("--chains", type=whole(1), required=True, help="chains to run (>= 1)")
    p.add_argument(
        "--equilibrate", type=count, default=0, help="chains run before the averages start (default 0)"
    )
    p.add_argument(
        "--chain-length",
        type=positive,
        help="distance each chain moves [m] (default 0.24 V^(1/d), Li et al. 2022's)",
    )
    p.add_argument("--kT", type=positive, default=1.0, help="temperature [J]: pressures are kT beta P")
    p.add_argument("--seed", type=count, default=0, help="random seed (>= 0)")
    p.add_argument(
        "--variant",
        choices=["straight", "newtonian", "forward"],
        help="the chains: straight along the axes in turn (default), Newtonian or forward",
    )
    p.add_argument("--trajectory", metavar="FILE", help="frames to FILE (.gsd or .xyz) at chain ends")
    p.add_argument("--every", type=whole(1), help="chains between frames (default: 100 frames over the run)")
    p.add_argument("--checkpoint", metavar="FILE", help="write a checkpoint (.npz) at the end or on Ctrl-C")
    p.add_argument("--resume", metavar="CHECKPOINT", help="continue from a checkpoint of sample")
    p.add_argument("--overwrite", action="store_true", help="replace an existing trajectory")
    p.set_defaults(func=run)
    return p


def _check_args(args: argparse.Namespace) -> None:
    given = any(getattr(args, k) is not None for k in ("container", "circle", "box"))
    if args.resume:
        if args.scenario or given:
            raise UsageError("--resume continues a checkpoint: leave out the scenario and --box")
        if args.variant is not None:
            raise UsageError("--resume continues the checkpoint's own variant: leave out --variant")
    elif not args.scenario:
        raise UsageError("give a scenario file (or --resume CHECKPOINT)")
    elif not given:
        raise UsageError("give --box L [LY [LZ]]: event chains run in a periodic box")
    elif args.box is None:
        raise UsageError(
            "--container/--circle: event chains run in a periodic box (no lifting rule at a curved "
            "wall here); give --box L [LY [LZ]]"
        )
    if args.trajectory is None:
        if args.every is not None:
            raise UsageError("--every is for the trajectory: give --trajectory FILE.gsd")
    elif os.path.splitext(args.trajectory)[1].lower() not in (".gsd", ".xyz", ".extxyz"):
        raise UsageError(f"--trajectory {args.trajectory!r}: use a .gsd or .xyz file name")


def _starting_chain(args: argparse.Namespace) -> EventChain:
    from ..mc.chain import EventChain

    if args.resume:
        return EventChain.load(args.resume)
    from ..scenario import check_scenario, parse_scenario
    from ..state import State
    from .source import container_from

    container = container_from(args)
    if args.scenario == "-":
        data = sys.stdin.buffer.read()
    else:
        with open(args.scenario, "rb") as fh:
            data = fh.read()
    scn = parse_scenario(data)
    if len(scn) == 0:
        raise UsageError(f"{args.scenario}: no spheres in the scenario; add a line per sphere")
    check_scenario(scn, container)
    state = State.from_scenario(scn, dimensions=container.dimensions)
    return EventChain(
        state,
        container,
        chain_length=args.chain_length,
        kT=args.kT,
        seed=args.seed,
        variant=args.variant or "straight",
    )


def _writer(args: argparse.Namespace, chain: EventChain) -> GSDWriter | XYZWriter | None:
    from ..io.trajectory import GSDWriter, NotAContinuation, XYZWriter

    path = args.trajectory
    if path is None:
        return None
    exists = os.path.exists(path) and os.path.getsize(path) > 0
    if exists and not args.overwrite and not args.resume:
        raise UsageError(f"trajectory {path} exists; give --overwrite to replace it, or another file name")
    append = bool(args.resume) and not args.overwrite
    every = args.every or max(1, (args.equilibrate + args.chains) // 100)
    writer: GSDWriter | XYZWriter
    if path.lower().endswith(".gsd"):
        writer = GSDWriter(path, every, events=False, append=append)
    else:
        writer = XYZWriter(path, every, append=append)
    try:
        writer.attach(chain)  # type: ignore[arg-type]  # an EventChain reads as a simulation view
    except NotAContinuation as e:
        writer.close()
        raise UsageError(f"{e}, or give --overwrite to replace it") from None
    except BaseException:
        writer.close()
        raise
    return writer


def _value(summary: dict[str, Any], key: str) -> str:
    mean, err = summary[key], summary.get(f"{key}_error", math.nan)
    if not math.isfinite(err):
        return f"{mean:.6g} (error unknown: run longer)"
    text = f"{mean:.6g} +- {err:.2g}"
    if summary.get(f"{key}_converged") is False:
        text += " (error not converged: a lower bound)"
    return text


def run(args: argparse.Namespace) -> int:
    """Run ``hardspheres sample``; returns the exit status."""
    _check_args(args)
    chain = _starting_chain(args)
    caught: list[int] = []

    def stop(signum: int, frame: FrameType | None) -> None:
        caught.append(signum)
        chain.request_stop()

    old = {s: signal.signal(s, stop) for s in (signal.SIGINT, signal.SIGTERM)}
    writer = None
    try:
        writer = _writer(args, chain)
        if writer is not None:
            chain.writers.append(writer)
        e0 = chain.counters["events"]
        if args.equilibrate:
            chain.run(chains=args.equilibrate)
        chain.observables.reset()
        if not caught:
            chain.run(chains=args.chains)
        if writer is not None and writer.last_time is not None and writer.last_time < chain.time:
            writer.write(chain, chain.time)  # type: ignore[arg-type]  # the file ends where the checkpoint starts
    finally:
        if writer is not None:
            writer.close()
        if args.checkpoint or args.resume:
            chain.stop_requested = False
            chain.save(args.checkpoint or args.resume)
        for s, handler in old.items():
            signal.signal(s, handler)
    events = chain.counters["events"] - e0
    box = chain.container
    lines = [
        f"chains {chain.time:.9g}" + (" (interrupted)" if caught else ""),
        f"{chain.n} {'disks' if box.dimensions == 2 else 'spheres'}, {box.description}",
        f"events {events} (lifts)",
    ]
    summary = chain.observables.summary()
    if "Z" in summary:
        lines.append(
            f"averages over {summary['chains']} chains"
            + (f" (after {args.equilibrate} chains of equilibration)" if args.equilibrate else "")
        )
        lines.append(f"Z = beta P V / N {_value(summary, 'Z')}")
        lines.append(f"pressure {_value(summary, 'pressure')} at kT {chain.kT:.6g}")
        for a in "xyz"[: box.dimensions]:
            lines.append(f"pressure_{a}{a} {_value(summary, f'pressure_{a}{a}')}")
    print("\n".join(lines))
    return 128 + caught[0] if caught else 0

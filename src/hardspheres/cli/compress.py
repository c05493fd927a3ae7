"""The ``compress`` command, and ``generate --packing``: a fluid grown to a packing.

The compression itself is :func:`hardspheres.dense.compress` (and
:meth:`hardspheres.Simulation.compress`); this module adds the progress
bar, the command's checks and its one-line report.
"""

from __future__ import annotations

import argparse
import math
import sys
from collections.abc import Callable
from typing import TYPE_CHECKING, TextIO

from ..builders import random_spheres
from ..dense import CompressionError, compress, max_packing
from ..fileio import atomic_write
from ..messages import plus_minus
from ..progress import Progress
from ..simulation import Simulation
from ..errors import UsageError
from .options import positive, where_args, whole
from .source import starting_simulation

if TYPE_CHECKING:
    from ..analysis.jamming import PackingSummary
    from ..containers import Container
    from ..state import State
    from .options import Subcommands


def compression_progress(
    phi0: float,
    packing: float | None = None,
    pressure: float | None = None,
    stream: TextIO | None = None,
    enabled: bool | None = None,
) -> tuple[Progress, Callable[[float, float, int], None]]:
    """A progress bar (on a terminal) and the ``progress`` callback of :func:`compress`.

    The bar shows the packing fraction, the reduced pressure ``Z`` and the
    collisions per second; its fraction done is the packing's way from
    ``phi0`` to ``packing``, or without a target packing ``log Z / log
    pressure``.

    Returns:
        ``(bar, show)``: close ``bar`` (:class:`hardspheres.progress.Progress`)
        at the end; pass ``show`` as ``progress=``.
    """
    bar = Progress(1.0, stream=stream, enabled=enabled, unit="collisions")

    def show(phi: float, z: float, coll: int) -> None:
        if packing is not None and packing > phi0:
            done = (phi - phi0) / (packing - phi0)
        elif pressure is not None and pressure > 1 and z > 1:
            done = math.log(z) / math.log(pressure)
        else:
            done = 0.0
        bar.update(max(0.0, min(1.0, done)), label=f"packing {phi:.5f}  Z {z:.4g}", events=coll)

    return bar, show


def start_packing(packing: float) -> float:
    """The packing :func:`generate_compressed` starts from (a lattice melt)."""
    return min(packing * 0.9, 0.2)


def generate_compressed(
    n: int,
    packing: float,
    container: Container,
    seed: int = 0,
    rate: float = 0.01,
    radius_ratio: float = 1.0,
    mass_ratio: float = 1.0,
    kT: float = 1.0,
    progress: Callable[[float, float, int], None] | None = None,
) -> State:
    """A random fluid (or mixture) at ``packing``, grown from a dilute lattice melt.

    The spheres start on random lattice sites (FCC; disks: triangular) in
    ``container`` at packing :func:`start_packing`
    (``min(0.9 packing, 0.2)``), run ``2 N`` collisions to lose the lattice,
    and are compressed at ``rate``; ``progress`` is passed to
    :func:`compress` (``progress(packing, Z, collisions)``).

    Raises:
        CompressionError: the spheres jammed before ``packing``.
    """
    start = start_packing(packing)
    state = random_spheres(
        n, start, container, seed=seed, radius_ratio=radius_ratio, mass_ratio=mass_ratio, kT=kT
    )
    sim = Simulation(state, container)
    names = list(state.names)
    if n > 1:
        sim.run(collisions=2 * n)
    if packing > start:
        res = sim.compress(packing=packing, rate=rate, progress=progress)
        if res.reason != "packing":
            raise CompressionError(
                f"--packing {packing:g}: the spheres jammed at {res.packing:.4f} "
                f"(Z = {res.pressure:.3g}); lower --packing or --rate"
            )
    out = sim.state()
    out.names = names
    return out


def run(args: argparse.Namespace) -> int:
    """``hardspheres compress``; returns the exit status."""
    if args.packing is None and args.collisions is None and args.pressure is None:
        raise CompressionError("give --packing, --pressure or --collisions")
    if not args.scenario and not args.resume:
        raise UsageError("give a scenario file to compress (or --resume CHECKPOINT)")
    sim = starting_simulation(args)
    phi0 = sim.packing
    target = args.packing
    if target is not None:
        top = max_packing(sim.engine.radii_at(), sim.container.dimensions)
        if target >= top:
            raise CompressionError(
                f"--packing {target:g} is not below {top:.4f}, the densest the geometry allows"
            )
        if target <= phi0:
            raise CompressionError(f"--packing {target:g} is not above the scenario's packing {phi0:.6g}")
    progress, show = compression_progress(phi0, target, args.pressure)
    history: list[tuple[float, float]] = []

    def record(phi: float, z: float, coll: int) -> None:
        history.append((phi, z))
        show(phi, z, coll)

    try:
        res = compress(
            sim,
            packing=target,
            rate=args.rate,
            pressure=args.pressure,
            collisions=args.collisions,
            progress=record,
        )
    finally:
        progress.close()
    text = sim.state().to_text()
    with atomic_write(args.output, "w") as fh:
        fh.write(text)
    if args.checkpoint:
        sim.save(args.checkpoint)
    summary = None
    if sim.container.periodic and max((z for _, z in history), default=0.0) >= 100:
        from ..analysis.jamming import summarize_packing

        phi, z = zip(*history)
        summary = summarize_packing(sim, phi, z, pressure=res.pressure)
    short = summary is not None and summary.short_of_isostatic
    if res.jammed:
        what = (
            f"{'stopped' if short else 'jammed'} at packing {res.packing:.6f}: Z = {res.pressure:.4g} "
            f"passed --pressure {args.pressure:g}" + (" (not jammed: short of isostatic)" if short else "")
        )
    elif res.reason == "collisions":
        what = f"stopped after {res.collisions} collisions at packing {res.packing:.6f}"
    else:
        what = f"packing {res.packing:.6f} reached, Z = {res.pressure:.4g}"
    print(f"{what}; {res.collisions} collisions; wrote {args.output}", file=sys.stdout)
    if summary is not None:
        print(jamming_line(summary), file=sys.stdout)
    if short:
        assert summary is not None
        print(
            f"hardspheres compress: warning: {short_of_isostatic(summary, args.rate, args.pressure)}",
            file=sys.stderr,
        )
    return 0


def short_of_isostatic(s: PackingSummary, rate: float, pressure: float) -> str:
    """What to say of a packing whose z after rattler removal is below isostatic, and what to do."""
    further = " or further (--pressure 1e6)" if pressure < 1e6 else ""
    return (
        f"z = {s.z_low:.3f} to {s.z_high:.3f} is short of isostatic ({s.z_isostatic:.3f}): the spheres "
        f"are stuck, not jammed (--rate {rate:g} is too fast); compress more slowly "
        f"(--rate {rate / 10:g}){further}"
    )


def jamming_line(s: PackingSummary) -> str:
    """The report's jamming line: z and rattlers (Z >= 1e3) and phi_J from the compression's (phi, Z)."""
    from ..analysis.jamming import CONTACT_GAPS_Z

    parts = []
    if math.isfinite(s.z_low):
        lo, hi = CONTACT_GAPS_Z
        parts.append(
            f"z = {s.z_low:.3f} to {s.z_high:.3f} after removing {s.rattlers_low:.1%} to "
            f"{s.rattlers_high:.1%} rattlers (contacts: gaps below {lo:g}/Z to {hi:g}/Z of the "
            f"contact distance; isostatic {s.z_isostatic:.3f})"
        )
    else:
        parts.append("z: not at Z < 1e3 (no contacts yet)")
    if math.isfinite(s.phi_J):
        parts.append(
            f"phi_J = {plus_minus(s.phi_J, s.phi_J_error, '.6f', '.1g')} (Z = d phi_J / (phi_J - phi) fitted "
            f"to {s.fit_points} points)"
        )
    else:
        parts.append("phi_J: the compression did not reach Z = 100")
    return "jamming: " + "; ".join(parts)


def add_parser(sub: Subcommands) -> argparse.ArgumentParser:
    """Add the subcommand to ``sub`` (the ``hardspheres`` parser's subparsers)."""
    p = sub.add_parser(
        "compress",
        help="grow the spheres of a scenario to a packing fraction "
        "(Lubachevsky-Stillinger); writes a scenario",
    )
    p.add_argument("scenario", nargs="?", help="scenario file ('-' for stdin)")
    where_args(p, "spherical container radius [m]", "periodic box [m]")
    p.add_argument(
        "--packing", type=positive, help="target packing fraction (below 0.7405 for equal spheres)"
    )
    p.add_argument(
        "--rate",
        type=positive,
        default=1e-3,
        help="growth speed of the largest diameter per thermal speed "
        "sqrt(kT/m) (default 0.001, slow enough to jam isostatic; 1e-1 fast, 1e-4 slow; "
        "Skoge et al.'s program's growthrate g is 2 sqrt(3) g)",
    )
    p.add_argument(
        "--pressure",
        type=positive,
        default=1e3,
        help="stop as jammed when Z = PV/NkT passes this (default 1e3)",
    )
    p.add_argument(
        "--collisions", type=whole(1), help="stop after this many collisions (a whole number; 1e5 is fine)"
    )
    p.add_argument("-o", "--output", required=True, help="write the compressed scenario here")
    p.add_argument("--checkpoint", help="also save a checkpoint here (run --resume reads it)")
    p.add_argument("--resume", help="compress from this checkpoint instead of a scenario")
    p.set_defaults(func=run)
    return p

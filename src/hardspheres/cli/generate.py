"""``hardspheres generate``: a scenario of N spheres (or disks) at a packing fraction, on stdout.

Disks (``--circle R``, ``--box LX LY``, ``--box L --dimensions 2``) are
written as nine-field lines with ``z = 0`` and ``vz = 0``, which ``run``,
``compress`` and the pictures read back as disks given the same container.
"""

from __future__ import annotations

import argparse
import sys
from typing import TYPE_CHECKING

from ..errors import UsageError
from .options import check_packing, count, packing, positive, ratio, where_args, whole

if TYPE_CHECKING:
    from .options import Subcommands


def add_parser(sub: Subcommands) -> argparse.ArgumentParser:
    """Add the subcommand to ``sub`` (the ``hardspheres`` parser's subparsers)."""
    p = sub.add_parser("generate", help="write a scenario of N spheres at a packing fraction")
    p.add_argument("--n", type=whole(1), required=True, help="number of spheres (>= 1)")
    where_args(p, "spherical container radius [m]", "periodic box [m]", required=True)
    p.add_argument(
        "--packing",
        type=packing,
        required=True,
        help="volume fraction filled by the spheres (< 0.74; disks: area fraction, at most 0.72)",
    )
    p.add_argument("--seed", type=count, default=0, help="random seed (>= 0)")
    p.add_argument(
        "--uniform-radius-ratio",
        "--radius-ratio",
        dest="radius_ratio",
        type=ratio,
        default=1.0,
        help="largest over smallest radius, radii uniform in between (uniform polydispersity; "
        "--radius-ratio is its old name)",
    )
    p.add_argument(
        "--binary",
        nargs=2,
        type=float,
        metavar=("SIZE_RATIO", "FRACTION"),
        help="a binary mixture: large spheres SIZE_RATIO times the small ones' radius, "
        "FRACTION of them in number",
    )
    p.add_argument(
        "--mass-ratio", type=ratio, default=1.0, help="largest over smallest mass (log-uniform in between)"
    )
    p.add_argument(
        "--method",
        choices=["lattice", "compress"],
        default="lattice",
        help="lattice: FCC sites at random (default; melts within a few "
        "collisions below 0.5); compress: a random fluid grown to the packing "
        "(Lubachevsky-Stillinger), for dense fluids and mixtures",
    )
    p.add_argument(
        "--rate",
        type=positive,
        default=0.01,
        help="--method compress: growth rate (default 0.01, see compress)",
    )
    p.set_defaults(func=run)
    return p


def run(args: argparse.Namespace) -> int:
    """Run the subcommand on its parsed arguments; returns the exit status."""
    from ..builders import random_spheres
    from .source import container_from

    container = container_from(args)
    check_packing(args.packing, container.dimensions)
    common = dict(  # one of --container, --circle, --box is given (argparse's group)
        container=container,
        seed=args.seed,
        radius_ratio=args.radius_ratio,
        mass_ratio=args.mass_ratio,
    )
    if args.binary is not None:
        if args.method == "compress":
            raise UsageError("--binary is built on the lattice: leave out --method compress")
        common["binary"] = tuple(args.binary)
    if args.method == "compress":
        from .compress import compression_progress, generate_compressed, start_packing

        bar, show = compression_progress(start_packing(args.packing), args.packing)
        try:
            state = generate_compressed(args.n, args.packing, rate=args.rate, progress=show, **common)
        finally:
            bar.close()
    else:
        state = random_spheres(args.n, args.packing, **common)
    sys.stdout.write(state.to_text())
    return 0

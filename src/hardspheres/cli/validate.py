"""``hardspheres validate``: the equation of state (or transport) against published values, run as a study."""

from __future__ import annotations

import argparse
import sys
from typing import TYPE_CHECKING

from ..errors import UsageError
from .options import compile_first, count, dask_args, packings, positive, whole

if TYPE_CHECKING:
    from .options import Subcommands


def add_parser(sub: Subcommands) -> argparse.ArgumentParser:
    """Add the subcommand to ``sub`` (the ``hardspheres`` parser's subparsers)."""
    p = sub.add_parser(
        "validate",
        help="equation of state (z-scores against Hansen-Goos and KLM) and "
        "collision rate against theory, run as a study",
    )
    p.add_argument("--n", type=whole(2), default=None, help="spheres (default 4000)")
    p.add_argument(
        "--collisions",
        type=whole(1),
        default=None,
        help="collisions per sphere measured at each packing (default 500)",
    )
    p.add_argument(
        "--equilibrate",
        type=count,
        default=None,
        help="collisions per sphere before measuring (default 200: the FCC "
        "start takes about 75 to melt at packing 0.49)",
    )
    p.add_argument(
        "--packings",
        type=packings,
        default=None,
        help="comma-separated packing fractions (default 0.1,0.2,0.3,0.4,0.45,0.49)",
    )
    p.add_argument(
        "--csv",
        default=None,
        help="CSV output (default validation.csv; with --transport validation-transport.csv)",
    )
    p.add_argument(
        "--transport",
        action="store_true",
        help="instead: D, eta, lambda against published molecular dynamics "
        "(z-scores; N 500 and 1372 at packings 0.2618, 0.3, 0.45: 20 million "
        "collisions, minutes; "
        "with --quick N 256 at 0.3, seconds); see docs/validation.md",
    )
    p.add_argument(
        "--time",
        type=positive,
        default=None,
        help="--transport: production run per size [sigma sqrt(m/kT)] (default about 7000 mean free times)",
    )
    p.add_argument("--seed", type=count, default=0, help="random seed (>= 0)")
    p.add_argument("--seeds", type=whole(1), default=1, help="runs per packing, seeds SEED.. (default 1)")
    p.add_argument(
        "--quick",
        action="store_true",
        help="a few seconds: N 500, 100 collisions per sphere (50 to equilibrate) at packings 0.1,0.3,0.45",
    )
    p.add_argument(
        "--output",
        metavar="DIR",
        help="keep the study here (a rerun skips finished runs); default: temporary",
    )
    dask_args(p, "an existing Dask scheduler", "run here, one packing after another")
    p.set_defaults(func=run)
    return p


def run(args: argparse.Namespace) -> int:
    """Run the subcommand on its parsed arguments; returns the exit status."""
    from ..studies.validate import PACKINGS, validate, verdict

    compile_first()
    if args.transport:
        return _validate_transport(args)
    if args.time is not None:
        raise UsageError(
            "--time applies to --transport only (the equation of state measures --collisions per sphere)"
        )
    if args.csv is None:
        args.csv = "validation.csv"
    if args.quick:  # a smoke test of the whole path, seconds (N = 500 crystallizes at 0.49)
        for key, value in (
            ("n", 500),
            ("collisions", 100),
            ("equilibrate", 50),
            ("packings", [0.1, 0.3, 0.45]),
        ):
            if getattr(args, key) is None:
                setattr(args, key, value)
    client = None
    if args.scheduler:
        from ..studies import connect

        client = connect(args.scheduler, timeout=args.timeout)
    try:
        rows = validate(
            packings=args.packings or PACKINGS,
            csv_path=args.csv,
            out=sys.stdout,
            n=4000 if args.n is None else args.n,
            collisions=500 if args.collisions is None else args.collisions,
            equilibrate=args.equilibrate if args.equilibrate is not None else 200,
            seed=args.seed,
            seeds=args.seeds,
            client=client,
            serial=args.serial,
            workers=args.workers,
            folder=args.output,
            progress=sys.stderr if sys.stderr.isatty() else None,
        )
    finally:
        if client is not None:
            client.close()
    print(f"wrote {args.csv}")
    for line in verdict(rows):
        print(line)
    return 0


def _validate_transport(args: argparse.Namespace) -> int:
    from ..studies.validate import TRANSPORT_PACKINGS, validate_transport

    for key in ("collisions", "equilibrate", "seeds", "scheduler", "output"):
        if getattr(args, key) not in (None, 1, False):
            raise UsageError(
                f"--{key} does not apply to --transport (which takes --n, "
                "--packings, --time, --quick, --seed, --workers, --csv)"
            )
    packings = args.packings or ((0.3,) if args.quick else TRANSPORT_PACKINGS)
    sizes = (args.n,) if args.n is not None else ((256,) if args.quick else (500, 1372))
    # about 7000 mean free times by default (validate_transport); --quick: 30 time
    # units, 300 mean free times at 0.3
    duration = args.time if args.time is not None else (30.0 if args.quick else None)
    csv_path = args.csv or "validation-transport.csv"
    rows, scores = validate_transport(
        packings=packings,
        sizes=sizes,
        duration=duration,
        seed=args.seed,
        out=sys.stdout,
        csv_path=csv_path,
        workers=args.workers or 1,
    )
    print(f"wrote {csv_path}")
    return 0

"""The ``hardspheres`` command and its subcommands (argument handling only).

Each subcommand parses its arguments and calls the library; errors from the
library that are the user's to fix (:class:`ValueError` and its kin) print
as one line on stderr with exit status 1.
"""

import argparse
import sys


class _Parser(argparse.ArgumentParser):
    def error(self, message):
        self.print_usage(sys.stderr)
        raise SystemExit(f"{self.prog}: {message}")


def _positive(text):
    import math
    x = float(text)
    if not math.isfinite(x) or x <= 0.0:
        raise argparse.ArgumentTypeError(f"must be a finite number > 0, got {text!r}")
    return x


def _ratio(text):
    x = _positive(text)
    if x < 1.0:
        raise argparse.ArgumentTypeError(f"must be >= 1, got {text!r}")
    return x


def _count(text):
    x = int(text)
    if x < 0:
        raise argparse.ArgumentTypeError(f"must be >= 0, got {text!r}")
    return x


def cmd_generate(args):
    from .builders import random_spheres
    if args.box is not None:
        state = random_spheres(args.n, args.packing, box=args.box, seed=args.seed,
                               radius_ratio=args.radius_ratio, mass_ratio=args.mass_ratio)
    else:
        state = random_spheres(args.n, args.packing, container=args.container,
                               seed=args.seed, radius_ratio=args.radius_ratio,
                               mass_ratio=args.mass_ratio)
    sys.stdout.write(state.to_text())
    return 0


def cmd_bench(args):
    from .bench import main
    main(args.n, args.packing, args.collisions, seed=args.seed,
         radius_ratio=args.radius_ratio, mass_ratio=args.mass_ratio, box=args.box)
    return 0


def build_parser():
    p = _Parser(prog="hardspheres",
                description="Exact event-driven simulation of perfectly elastic spheres.")
    sub = p.add_subparsers(dest="command", required=True, parser_class=_Parser)

    g = sub.add_parser("generate", help="write a scenario of N spheres at a packing fraction")
    g.add_argument("--n", type=_count, required=True, help="number of spheres")
    where = g.add_mutually_exclusive_group(required=True)
    where.add_argument("--container", type=_positive, help="spherical container radius [m]")
    where.add_argument("--box", type=_positive, help="periodic cubic box edge [m]")
    g.add_argument("--packing", type=_positive, required=True,
                   help="volume fraction filled by the spheres (< 0.74)")
    g.add_argument("--seed", type=int, default=0)
    g.add_argument("--radius-ratio", type=_ratio, default=1.0,
                   help="largest over smallest radius (uniform in between)")
    g.add_argument("--mass-ratio", type=_ratio, default=1.0,
                   help="largest over smallest mass (log-uniform in between)")
    g.set_defaults(func=cmd_generate)

    b = sub.add_parser("bench", help="measure collisions per second")
    b.add_argument("--n", type=_count, required=True)
    b.add_argument("--packing", type=_positive, required=True)
    b.add_argument("--collisions", type=_count, required=True,
                   help="collisions timed (after N warm-up collisions)")
    b.add_argument("--seed", type=int, default=0)
    b.add_argument("--radius-ratio", type=_ratio, default=1.0)
    b.add_argument("--mass-ratio", type=_ratio, default=1.0)
    b.add_argument("--box", action="store_true",
                   help="periodic box instead of the spherical container")
    b.set_defaults(func=cmd_bench)

    for extra in _EXTRA:
        extra(sub)
    return p


#: Functions adding further subcommands: ``f(subparsers)``.
_EXTRA = []


def main(argv):
    """Run ``hardspheres ARGV``; returns the exit status."""
    args = build_parser().parse_args(argv)
    try:
        return args.func(args)
    except (ValueError, OSError) as e:
        print(f"hardspheres {args.command}: {e}", file=sys.stderr)
        return 1

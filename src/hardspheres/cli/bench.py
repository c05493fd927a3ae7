"""``hardspheres bench``: the collisions per second of one system, printed."""

from __future__ import annotations

import argparse
import json
from typing import TYPE_CHECKING, Any

from ..core.bench import bench
from .options import check_packing, compile_first, count, packing, ratio, warmup, whole

if TYPE_CHECKING:
    from .options import Subcommands


def main(n: int, packing: float, collisions: int, **kw: Any) -> dict[str, Any]:
    """Print the figures, the JSON object last."""
    res = bench(n, packing, collisions, **kw)
    ens = res["enskog_collision_rate"]
    disks = " disks" if res["dimensions"] == 2 else ""
    print(
        f"N={n}{disks} packing={packing}: setup {res['setup_s']:.1f} s (generation "
        f"{res['generate_s']:.1f} s; CPU {res['setup_cpu_s']:.1f} s), peak "
        f"{res['setup_peak_rss_mb']:.0f} MB after setup"
    )
    enskog = f" (Enskog-CS {ens:.4g})" if ens else ""
    if res["warmup_blocks"]:
        print(
            f"warm-up: {res['warmup_per_sphere']:g} collisions per sphere in "
            f"{res['warmup_s']:.1f} s, {'settled' if res['settled'] else 'NOT settled'}; "
            f"per sphere per unit time over its last block: collisions "
            f"{res['warmup_collision_rate']:.4g}{enskog}, cell crossings "
            f"{res['warmup_crossing_rate']:.4g}"
        )
    else:
        print("warm-up: none (the lattice as built is timed, not a fluid)")
    print(
        f"timed: per sphere per unit time, collisions {res['collision_rate']:.4g}{enskog}, "
        f"cell crossings {res['crossing_rate']:.4g}"
    )
    print(
        f"timed: {res['collisions_per_s'] / 1e6:.3f} M collisions/s, "
        f"{res['events_per_s'] / 1e6:.3f} M events/s, peak {res['peak_rss_mb']:.0f} MB"
    )
    print(json.dumps(res))
    return res


def add_parser(sub: Subcommands) -> argparse.ArgumentParser:
    """Add the subcommand to ``sub`` (the ``hardspheres`` parser's subparsers)."""
    p = sub.add_parser("bench", help="measure collisions per second")
    p.add_argument("--n", type=whole(2), required=True, help="number of spheres (>= 2)")
    p.add_argument("--packing", type=packing, required=True)
    p.add_argument(
        "--collisions",
        type=whole(1),
        required=True,
        help="collisions timed, after the warm-up (2e6 is fine)",
    )
    p.add_argument("--seed", type=count, default=0, help="random seed (>= 0)")
    p.add_argument("--radius-ratio", type=ratio, default=1.0)
    p.add_argument("--mass-ratio", type=ratio, default=1.0)
    p.add_argument(
        "--box",
        action="store_true",
        help="periodic box (a cube; a square with --dimensions 2) instead of the spherical container "
        "(the circle with --dimensions 2)",
    )
    p.add_argument(
        "--dimensions",
        type=int,
        choices=(2, 3),
        default=3,
        help="3 (spheres, default) or 2 (disks of radius 0.5; --packing is the area fraction, at most 0.72)",
    )
    p.add_argument(
        "--warmup",
        type=warmup,
        default=None,
        metavar="auto|PER_SPHERE",
        help="collisions per sphere run before the clock starts; 'auto' "
        "(default): in blocks of 2 per sphere (and 1e5 at least) until the "
        "collision and cell-crossing rates settle to 1%% or their noise, "
        "at most 100 per sphere (or 10 blocks)",
    )
    p.set_defaults(func=run)
    return p


def run(args: argparse.Namespace) -> int:
    """Run the subcommand on its parsed arguments; returns the exit status."""
    check_packing(args.packing, args.dimensions)
    compile_first()
    main(
        args.n,
        args.packing,
        args.collisions,
        seed=args.seed,
        radius_ratio=args.radius_ratio,
        mass_ratio=args.mass_ratio,
        box=args.box,
        warmup=args.warmup,
        dimensions=args.dimensions,
    )
    return 0

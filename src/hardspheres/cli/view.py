"""``hardspheres view``: a self-contained interactive viewer page, flat for disks (and a screenshot)."""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

from ..errors import UsageError
from .options import picture_args, refuse_existing, require_suffix, size_slice_args, cut_of
from .source import check_source, frames_from_args

if TYPE_CHECKING:
    from .options import Subcommands


def add_parser(sub: Subcommands) -> argparse.ArgumentParser:
    """Add the subcommand to ``sub`` (the ``hardspheres`` parser's subparsers)."""
    p = sub.add_parser("view", help="write a self-contained interactive 3-D viewer (HTML)")
    picture_args(p, "viewer.html", "the page to write (.html)")
    p.add_argument("--title")
    p.add_argument(
        "--screenshot", metavar="PNG", help="also open the page in headless Chromium, play it 1 s, save a PNG"
    )
    size_slice_args(
        p,
        "screenshot size WIDTHxHEIGHT (default 960x640)",
        "start with a cut-away plane: VALUE hides the spheres whose centre has z > VALUE, x=VALUE "
        "(or y=) those with x > VALUE, a slab along z seen side-on (the page's cut slider and axis "
        "menu move it)",
    )
    p.add_argument(
        "--color",
        choices=["speed", "mass", "q6", "psi6", "density"],
        default="speed",
        help="colour the spheres by speed (default), mass, or Steinhardt bond "
        "order q6 over 12 neighbours (crystal-like spheres near 0.5-0.57, a "
        "fluid or jammed packing 0.3-0.45; needs freud); disks by their local "
        "hexatic order |psi6| over 6 neighbours (1 in a hexagonal crystal; needs freud); "
        "in a periodic box by the local packing fraction, density (Voronoi with freud, else cells)",
    )
    p.set_defaults(func=run)
    return p


def run(args: argparse.Namespace) -> int:
    """Run the subcommand on its parsed arguments; returns the exit status."""
    require_suffix("-o", args.output, (".html", ".htm"), "the viewer is a web page and")
    if args.screenshot:
        require_suffix("--screenshot", args.screenshot, (".png",), "the screenshot")
    check_source(args)
    refuse_existing("-o", args.output, args.overwrite)
    if args.screenshot:
        refuse_existing("--screenshot", args.screenshot, args.overwrite)
    from ..viz.screenshot import screenshot
    from ..viz.viewer import write_viewer

    from ..frames import frame_indices

    # the page shows at most frame_indices' frames: only those are recorded
    frames = frames_from_args(args, most=lambda n: len(frame_indices(2**62, n)))
    cut, cut_axis = cut_of(args.slice)
    write_viewer(
        frames, args.output, title=args.title or args.input, cut=cut, cut_axis=cut_axis, color_by=args.color
    )
    noun = "disks" if frames.positions.shape[-1] == 2 else "spheres"
    print(f"wrote {args.output} ({frames.n} {noun}, {len(frames.times)} frames)")
    if args.screenshot:
        try:
            screenshot(args.output, args.screenshot, size=args.size or (960, 640))
        except ValueError as e:
            raise UsageError(
                f"--screenshot {args.screenshot}: {str(e).removeprefix('screenshot: ')}"
            ) from None
        print(f"wrote {args.screenshot}")
    return 0

"""``hardspheres render``: a movie or a still picture of frames, headless."""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

from ..errors import UsageError
from .options import (
    MOVIES,
    STILLS,
    cut_of,
    finite,
    note,
    picture_args,
    refuse_existing,
    require_suffix,
    size_slice_args,
    suffix,
    whole,
)
from .source import check_source, frames_from_args

if TYPE_CHECKING:
    from .options import Subcommands


def add_parser(sub: Subcommands) -> argparse.ArgumentParser:
    """Add the subcommand to ``sub`` (the ``hardspheres`` parser's subparsers)."""
    p = sub.add_parser(
        "render", help="render an animation (.gif, .mp4) or a still (.png, .pdf, .svg), headless"
    )
    picture_args(p, "movie.gif", "movie (.gif; .mp4 with ffmpeg) or still (.png, .pdf, .svg)")
    p.add_argument(
        "--fps", type=whole(1, 100), default=20, help="movie frames per second (1 to 100, default 20)"
    )
    p.add_argument("--time", type=finite, help="still: draw the frame nearest this time (default: the last)")
    p.add_argument(
        "--color",
        choices=["speed", "mass", "q6", "psi6", "density"],
        default="speed",
        help="colour by speed (default), mass, for spheres the bond order q6 over 12 neighbours "
        "(crystal-like near 0.5-0.57, a fluid 0.3-0.45), for disks the local hexatic order "
        "|psi6| (q6 and psi6 need freud), or in a periodic box the local packing fraction, "
        "density (Voronoi with freud, else cells: the clusters of a granular gas)",
    )
    size_slice_args(
        p,
        "WIDTHxHEIGHT in pixels (default 1280x720 still, 960x540 movie)",
        "cut-away: VALUE draws only the spheres whose centre has z <= VALUE (the inside of a full "
        "container); x=VALUE (or y=) those with x <= VALUE: a slab along z seen side-on "
        "(the camera turns to the cut's face)",
    )
    p.set_defaults(func=run)
    return p


def run(args: argparse.Namespace) -> int:
    """Run the subcommand on its parsed arguments; returns the exit status."""
    require_suffix("-o", args.output, MOVIES + STILLS, "a movie or a still")
    still = suffix(args.output) in STILLS
    if args.time is not None and not still:
        raise UsageError("--time picks the frame of a still picture: use -o NAME.png")
    if not still and suffix(args.output) != ".gif":
        from ..extras import need

        animation = need("matplotlib.animation", "a movie")
        if not animation.FFMpegWriter.isAvailable():
            raise UsageError(
                f"-o {args.output}: {suffix(args.output)} needs the ffmpeg program, "
                "which was not found on PATH; install it or write a .gif"
            )
        if args.size and (args.size[0] % 2 or args.size[1] % 2):
            raise UsageError(f"--size: {suffix(args.output)} needs an even width and height")
    check_source(args)
    refuse_existing("-o", args.output, args.overwrite)
    from ..viz.render import render_movie, render_still

    frames = frames_from_args(args)
    size = args.size or ((1280, 720) if still else (960, 540))
    cut, cut_axis = cut_of(args.slice)
    if still:
        render_still(
            frames, args.output, time=args.time, size=size, cut=cut, cut_axis=cut_axis, color_by=args.color
        )
    else:
        from ..progress import duration

        def estimate(n_frames: int, seconds: float) -> None:
            note(f"rendering {n_frames} frames to {args.output}, about {duration(seconds)}")

        render_movie(
            frames,
            args.output,
            fps=args.fps,
            size=size,
            on_estimate=estimate,
            color_by=args.color,
            cut=cut,
            cut_axis=cut_axis,
        )
    print(f"wrote {args.output}")
    return 0

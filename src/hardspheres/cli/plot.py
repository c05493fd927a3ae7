"""``hardspheres plot``: plots of a trajectory, a scenario's run, or a study's tables."""

from __future__ import annotations

import argparse
import sys
import warnings
from types import ModuleType
from typing import TYPE_CHECKING

from ..errors import ResolutionWarning, UsageError
from .options import STILLS, picture_args, positive, refuse_existing, require_suffix, suffix
from .source import TRAJECTORY_SUFFIXES, check_source, frames_from_args, starting_simulation

if TYPE_CHECKING:
    from ..frames import Frames
    from ..simulation import Simulation
    from .options import Subcommands


def add_parser(sub: Subcommands) -> argparse.ArgumentParser:
    """Add the subcommand to ``sub`` (the ``hardspheres`` parser's subparsers)."""
    p = sub.add_parser(
        "plot",
        help="plots (.png, .pdf, .svg): conservation, speeds, eos, transport, sweep, flow, gr, msd, "
        "fs, chi4, contacts",
    )
    p.add_argument(
        "what",
        choices=[
            "conservation",
            "speeds",
            "eos",
            "transport",
            "sweep",
            "flow",
            "gr",
            "msd",
            "fs",
            "chi4",
            "contacts",
        ],
        help="energy/momentum over time, speeds vs Maxwell-Boltzmann, "
        "the validate CSV vs Carnahan-Starling, the validate --transport CSV "
        "vs published values, a study's results "
        "(--x PARAMETER --y OBSERVABLE), a sheared study's flow curve (viscosity against shear "
        "rate), g(r) (periodic box), the "
        "mean squared displacement with D (periodic box), F_s(k, t) with "
        "tau_alpha, chi_4(t) of the overlap (periodic box), or a packing's "
        "contacts Z(h) and forces P(f) (a scenario with --box)",
    )
    p.add_argument(
        "--from",
        dest="since",
        type=float,
        default=None,
        metavar="T",
        help="gr, msd, fs, chi4, conservation, speeds: use only the frames at times >= T "
        "(e.g. after an equilibration the trajectory includes)",
    )
    p.add_argument("--k", type=positive, help="fs: wave number [1/m] (default 2 pi / mean diameter)")
    p.add_argument("--a", type=positive, help="chi4: overlap cut-off [m] (default 0.3 mean diameter)")
    picture_args(p, "plot.png", "the plot to write (.png, .pdf, .svg)")
    p.add_argument("--x", default="packing", help="sweep: parameter on the x axis (default packing)")
    p.add_argument("--y", default="Z", help="sweep: observable on the y axis (default Z)")
    p.set_defaults(func=run)
    return p


def run(args: argparse.Namespace) -> int:
    """Run the subcommand on its parsed arguments; returns the exit status."""
    require_suffix("-o", args.output, STILLS, "a plot")
    from ..extras import need
    from ..viz import plots

    need("matplotlib", "hardspheres plot")  # before a simulation, not after
    if args.what not in ("eos", "transport", "sweep", "flow", "contacts"):
        check_source(args)  # the input's options first, then the output
    refuse_existing("-o", args.output, args.overwrite)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", ResolutionWarning)
        _plot(args, plots)
    for w in caught:  # one line each, not Python's two-line warning format
        if issubclass(w.category, ResolutionWarning):
            print(f"hardspheres plot: warning: {w.message}", file=sys.stderr)
        else:
            warnings.showwarning(w.message, w.category, w.filename, w.lineno)
    print(f"wrote {args.output}")
    return 0


def _plot(args: argparse.Namespace, plots: ModuleType) -> None:
    if args.what == "eos":
        plots.plot_eos(args.input, args.output)
    elif args.what == "transport":
        plots.plot_transport(args.input, args.output)
    elif args.what == "sweep":
        plots.plot_sweep(args.input, args.output, x=args.x, y=args.y)
    elif args.what == "flow":
        plots.plot_flow(args.input, args.output)
    elif args.what == "contacts":
        from ..analysis.collisions import packing_contact_forces

        sim = _packing_sim(args)
        plots.plot_contacts(sim, args.output, packing_contact_forces(sim))
    else:
        check_source(args)
        frames = frames_from_args(args)
        if args.since is not None:
            frames = frames.since(args.since)
        if args.what == "conservation":
            plots.plot_conservation(frames, args.output)
        elif args.what == "gr":
            plots.plot_gr(frames, args.output)
        elif args.what == "msd":
            _plot_msd(args, plots, frames)
        elif args.what == "fs":
            plots.plot_fs(frames, args.output, k=args.k)
        elif args.what == "chi4":
            plots.plot_chi4(frames, args.output, a=args.a)
        else:
            plots.plot_speeds(frames, args.output)


def _plot_msd(args: argparse.Namespace, plots: ModuleType, frames: Frames) -> None:
    """``plot msd``: the plot, and D on stdout with the frames it is from."""
    from ..analysis.transport import MSD
    from ..messages import plus_minus

    msd = MSD().compute(frames)
    D, err = msd.diffusion()
    plots.plot_msd(frames, args.output, msd=msd)
    t = frames.times
    print(
        f"D = {plus_minus(D, err)} from the frames t = {t[0]:.6g} .. {t[-1]:.6g} "
        + (
            f"(from --from {args.since:g})"
            if args.since is not None
            else "(all of them: a run's trajectory includes its --equilibrate part; --from T leaves it out)"
        )
    )


def _packing_sim(args: argparse.Namespace) -> Simulation:
    """The packing a scenario file holds, in its periodic box (``--box``), for ``plot contacts``."""

    if args.box is None or suffix(args.input) in TRAJECTORY_SUFFIXES:
        raise UsageError("plot contacts: give a packing's scenario file (as compress writes) and --box L")
    try:
        return starting_simulation(args, scenario=args.input)
    except ValueError as e:
        raise UsageError(f"{args.input}: {str(e).removeprefix(args.input + ': ')}") from None

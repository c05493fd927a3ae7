"""The ``hardspheres`` command and its subcommands (argument handling only).

Each subcommand parses its arguments and calls the library; errors from the
library that are the user's to fix (:class:`ValueError` and its kin) print
as one line on stderr with exit status 1.
"""

import argparse
import re
import sys
import warnings

from ..messages import QUOTE_LIMIT, oserror_line, quote


class _Parser(argparse.ArgumentParser):
    """argparse with one-line errors: ``hardspheres run: argument --n: ...``."""

    def error(self, message):
        # argparse echoes arguments as 'text': cut long ones (a 10 MB argument)
        message = re.sub(r"'([^']{%d})[^']+'" % QUOTE_LIMIT, r"'\1'...", message)
        raise SystemExit(f"{self.prog}: {message} (see {self.prog} --help)")


def _number(text):
    """``float(text)`` for a plain decimal number (:func:`~hardspheres.scenario.plain_float`), else NaN."""
    import math

    from ..scenario import plain_float

    x = plain_float(text)
    return math.nan if x is None else x


def _positive(text):
    import math

    x = _number(text)
    if not math.isfinite(x) or x <= 0.0:
        raise argparse.ArgumentTypeError(f"must be a finite number > 0, got {quote(text)}")
    return x


def _ratio(text):
    x = _positive(text)
    if x < 1.0:
        raise argparse.ArgumentTypeError(f"must be a number >= 1, got {quote(text)}")
    return x


def _whole(lowest, highest=None):
    """A whole number in ``[lowest, highest]``; integral floats as physicists type them
    (``1e5``, ``2.0``) are accepted."""
    import math

    def parse(text):
        x = _number(text)
        bound = f">= {lowest}" if highest is None else f"from {lowest} to {highest}"
        if not math.isfinite(x) or x != math.floor(x) or x < lowest or (highest is not None and x > highest):
            raise argparse.ArgumentTypeError(
                f"must be a whole number {bound} (1e5 is fine), got {quote(text)}"
            )
        return int(x)

    parse.__name__ = "whole number"
    return parse


_count = _whole(0)


def _packing(text):
    import math

    x = _number(text)
    if not math.isfinite(x) or not 0.0 < x < 0.74:
        raise argparse.ArgumentTypeError(
            f"must be a packing fraction between 0 and 0.74 (exclusive), got {quote(text)}"
        )
    return x


def _warmup(text):
    """``auto`` or collisions per sphere (a finite number >= 0)."""
    import math

    if text.strip().lower() == "auto":
        return None
    x = _number(text)
    if not math.isfinite(x) or x < 0.0:
        raise argparse.ArgumentTypeError(f"must be 'auto' or collisions per sphere >= 0, got {quote(text)}")
    return x


def _packings(text):
    """Comma-separated packing fractions, every one checked before any is run."""
    values = []
    for part in text.split(","):
        try:
            values.append(_packing(part.strip()))
        except argparse.ArgumentTypeError:
            raise argparse.ArgumentTypeError(
                f"must be comma-separated packing fractions between 0 and 0.74 "
                f"(e.g. 0.1,0.3), got {quote(part.strip())} in {quote(text)}"
            ) from None
    return values


def _time(text):
    import math

    x = _number(text)
    if not math.isfinite(x):
        raise argparse.ArgumentTypeError(f"must be a finite number, got {quote(text)}")
    return x


def _size(text):
    """``WIDTHxHEIGHT`` in pixels."""
    w, _, h = text.lower().partition("x")
    try:
        size = (int(w), int(h))
    except ValueError:
        size = (0, 0)
    if not (16 <= size[0] <= 8192 and 16 <= size[1] <= 8192):
        raise argparse.ArgumentTypeError(
            f"must be WIDTHxHEIGHT in pixels, each 16 to 8192 (e.g. 1280x720), got {quote(text)}"
        )
    return size


def _suffix(path):
    import os

    return os.path.splitext(path)[1].lower()


def _require_suffix(option, path, allowed, what):
    """Refuse an output name whose extension is not one of ``allowed`` (before any work)."""
    if _suffix(path) not in allowed:
        got = _suffix(path) or "no extension"
        raise ValueError(f"{option} {quote(path)}: {what} must end in {', '.join(allowed)} (got {got})")


def _note(text):
    """A one-line note on stderr (not an error)."""
    print(text, file=sys.stderr, flush=True)


def _compile_first():
    """Compile the event core now if needed (said on stderr), so no timing includes it."""
    from ..core.warmup import ensure_compiled

    ensure_compiled()


def cmd_generate(args):
    from ..builders import random_spheres

    common = dict(  # container or box: exactly one is given (argparse's group)
        container=args.container,
        box=args.box,
        seed=args.seed,
        radius_ratio=args.radius_ratio,
        mass_ratio=args.mass_ratio,
    )
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


def cmd_compress(args):
    from .compress import compress_command

    return compress_command(args)


def cmd_bench(args):
    from .bench import main

    _compile_first()
    main(
        args.n,
        args.packing,
        args.collisions,
        seed=args.seed,
        radius_ratio=args.radius_ratio,
        mass_ratio=args.mass_ratio,
        box=args.box,
        warmup=args.warmup,
    )
    return 0


def cmd_validate(args):
    from ..studies.validate import PACKINGS, validate, verdict

    _compile_first()
    if args.transport:
        return _validate_transport(args)
    if args.time is not None:
        raise ValueError(
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


def _validate_transport(args):
    from ..studies.validate import TRANSPORT_PACKINGS, validate_transport

    for key in ("collisions", "equilibrate", "seeds", "scheduler", "output"):
        if getattr(args, key) not in (None, 1, False):
            raise ValueError(
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


_TRAJECTORY_SUFFIXES = (".gsd", ".xyz", ".extxyz")


def _check_source(args):
    """Check the input's options (trajectory or scenario) before any work."""
    if _suffix(args.input) in _TRAJECTORY_SUFFIXES:
        given = [
            o
            for o, v in (
                ("--container", args.container),
                ("--box", args.box),
                ("--until", args.until),
                ("--every", args.every),
            )
            if v
        ]
        if given:
            raise ValueError(
                f"{'/'.join(given)} {'is' if len(given) == 1 else 'are'} for "
                "scenarios, not trajectories "
                f"({args.input} holds its own)"
            )
        return
    if args.until is None or (args.container is None and args.box is None):
        raise ValueError(
            f"{quote(args.input)} is not a trajectory (.gsd, .xyz), so it is read as a "
            "scenario: give --container R (or --box L) and --until T"
        )
    if args.every is not None and args.every > args.until:
        raise ValueError(
            f"--every {args.every:g} is longer than the run (--until "
            f"{args.until:g}): there would be one frame"
        )


def _frames(args):
    """Frames from a trajectory file, or from a scenario run on the spot."""
    from ..io.trajectory import frames_from_simulation, read_trajectory

    path = args.input
    if _suffix(path) in _TRAJECTORY_SUFFIXES:
        from ..io.trajectory import TruncatedTrajectory

        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", TruncatedTrajectory)
            frames = read_trajectory(path)
        for w in caught:  # one line each, not Python's two-line warning format
            print(f"hardspheres {args.command}: warning: {w.message}", file=sys.stderr)
        return frames
    from ..containers import PeriodicBox, SphericalContainer
    from ..scenario import check_scenario, parse_scenario
    from ..simulation import Simulation

    container = SphericalContainer(args.container) if args.container is not None else PeriodicBox(args.box)
    with open(path, "rb") as fh:
        data = fh.read()
    try:
        scn = parse_scenario(data)  # bad input is refused before the compilation
        if len(scn) == 0:
            raise ValueError("no spheres in the scenario")
        check_scenario(scn, container)
        _compile_first()
        sim = Simulation.from_scenario(data if data.endswith(b"\n") else data + b"\n", container)
    except ValueError as e:
        raise ValueError(f"{path}: {e}") from None
    return frames_from_simulation(sim, until=args.until, every=args.every or args.until / 200)


def cmd_view(args):
    _require_suffix("-o", args.output, (".html", ".htm"), "the viewer is a web page and")
    if args.screenshot:
        _require_suffix("--screenshot", args.screenshot, (".png",), "the screenshot")
    _check_source(args)
    from ..viz.screenshot import screenshot
    from ..viz.viewer import write_viewer

    frames = _frames(args)
    write_viewer(frames, args.output, title=args.title or args.input, cut=args.slice, color_by=args.color)
    print(f"wrote {args.output} ({frames.n} spheres, {len(frames.times)} frames)")
    if args.screenshot:
        try:
            screenshot(args.output, args.screenshot, size=args.size or (960, 640))
        except ValueError as e:
            raise ValueError(
                f"--screenshot {args.screenshot}: {str(e).removeprefix('screenshot: ')}"
            ) from None
        print(f"wrote {args.screenshot}")
    return 0


_MOVIES = (".gif", ".mp4", ".m4v", ".mov", ".mkv", ".webm")
_STILLS = (".png", ".pdf", ".svg")


def cmd_render(args):
    _require_suffix("-o", args.output, _MOVIES + _STILLS, "a movie or a still")
    still = _suffix(args.output) in _STILLS
    if args.time is not None and not still:
        raise ValueError("--time picks the frame of a still picture: use -o NAME.png")
    if not still and _suffix(args.output) != ".gif":
        from matplotlib import animation

        if not animation.FFMpegWriter.isAvailable():
            raise ValueError(
                f"-o {args.output}: {_suffix(args.output)} needs the ffmpeg program, "
                "which was not found on PATH; install it or write a .gif"
            )
        if args.size and (args.size[0] % 2 or args.size[1] % 2):
            raise ValueError(f"--size: {_suffix(args.output)} needs an even width and height")
    _check_source(args)
    from ..viz.render import render_movie, render_still

    frames = _frames(args)
    size = args.size or ((1280, 720) if still else (960, 540))
    if still:
        render_still(frames, args.output, time=args.time, size=size, cut=args.slice)
    else:
        from ..progress import duration

        def estimate(n_frames, seconds):
            _note(f"rendering {n_frames} frames to {args.output}, about {duration(seconds)}")

        render_movie(frames, args.output, fps=args.fps, size=size, cut=args.slice, on_estimate=estimate)
    print(f"wrote {args.output}")
    return 0


def cmd_plot(args):
    _require_suffix("-o", args.output, _STILLS, "a plot")
    from ..viz import plots

    if args.what == "eos":
        plots.plot_eos(args.input, args.output)
    elif args.what == "transport":
        plots.plot_transport(args.input, args.output)
    elif args.what == "sweep":
        plots.plot_sweep(args.input, args.output, x=args.x, y=args.y)
    elif args.what == "contacts":
        plots.plot_contacts(_packing_sim(args), args.output)
    else:
        _check_source(args)
        frames = _frames(args)
        if args.what == "conservation":
            plots.plot_conservation(frames, args.output)
        elif args.what == "gr":
            plots.plot_gr(frames, args.output)
        elif args.what == "msd":
            plots.plot_msd(frames, args.output)
        elif args.what == "fs":
            plots.plot_fs(frames, args.output, k=args.k)
        elif args.what == "chi4":
            plots.plot_chi4(frames, args.output, a=args.a)
        else:
            plots.plot_speeds(frames, args.output)
    print(f"wrote {args.output}")
    return 0


def _packing_sim(args):
    """The packing a scenario file holds, in its periodic box (``--box``), for ``plot contacts``."""
    from ..containers import PeriodicBox
    from ..simulation import Simulation

    if args.box is None or _suffix(args.input) in _TRAJECTORY_SUFFIXES:
        raise ValueError("plot contacts: give a packing's scenario file (as compress writes) and --box L")
    _compile_first()
    try:
        return Simulation.from_scenario(args.input, PeriodicBox(args.box))
    except ValueError as e:
        raise ValueError(f"{args.input}: {e}") from None


def _picture_args(q, output_default, output_help):
    q.add_argument("input", help="trajectory (.gsd, .xyz) or scenario file")
    q.add_argument("-o", "--output", default=output_default, help=output_help)
    _where_args(q, "scenario: container radius [m]", "scenario: periodic box edge [m]")
    q.add_argument("--until", type=_positive, help="scenario: end time [s]")
    q.add_argument(
        "--every", type=_positive, help="scenario: time between frames [s] (default: --until / 200)"
    )


def _where_args(q, container_help, box_help, required=False):
    """``--container R`` or ``--box L`` (at most one; exactly one if ``required``)."""
    where = q.add_mutually_exclusive_group(required=required)
    where.add_argument("--container", type=_positive, help=container_help)
    where.add_argument("--box", type=_positive, help=box_help)


def _size_slice_args(q, size_help, slice_help):
    """``--size WIDTHxHEIGHT`` (:func:`_size`) and ``--slice Z`` (cut-away plane) of a picture."""
    q.add_argument("--size", type=_size, help=size_help)
    q.add_argument("--slice", type=_time, metavar="Z", help=slice_help)


def _dask_args(q, scheduler_help, serial_help):
    """Where a study runs: ``--scheduler``, ``--workers``, ``--serial``, ``--timeout``."""
    q.add_argument("--scheduler", metavar="tcp://HOST:PORT", help=scheduler_help)
    q.add_argument("--workers", type=_count, help="worker processes of the LocalCluster")
    q.add_argument("--serial", action="store_true", help=serial_help)
    q.add_argument(
        "--timeout", type=_positive, default=10.0, help="seconds to wait for --scheduler (default 10)"
    )


def cmd_run(args):
    from .run import run_command

    return run_command(args)


def _version():
    from ..version import package_version

    return f"%(prog)s {package_version()}"


def cmd_sweep(args):
    from .sweep import main

    return main(args)


def build_parser():
    p = _Parser(prog="hardspheres", description="Exact event-driven simulation of perfectly elastic spheres.")
    p.add_argument("--version", action="version", version=_version())
    sub = p.add_subparsers(dest="command", required=True, parser_class=_Parser)

    g = sub.add_parser("generate", help="write a scenario of N spheres at a packing fraction")
    g.add_argument("--n", type=_whole(1), required=True, help="number of spheres (>= 1)")
    _where_args(g, "spherical container radius [m]", "periodic cubic box edge [m]", required=True)
    g.add_argument(
        "--packing", type=_packing, required=True, help="volume fraction filled by the spheres (< 0.74)"
    )
    g.add_argument("--seed", type=_count, default=0, help="random seed (>= 0)")
    g.add_argument(
        "--radius-ratio", type=_ratio, default=1.0, help="largest over smallest radius (uniform in between)"
    )
    g.add_argument(
        "--mass-ratio", type=_ratio, default=1.0, help="largest over smallest mass (log-uniform in between)"
    )
    g.add_argument(
        "--method",
        choices=["lattice", "compress"],
        default="lattice",
        help="lattice: FCC sites at random (default; melts within a few "
        "collisions below 0.5); compress: a random fluid grown to the packing "
        "(Lubachevsky-Stillinger), for dense fluids and mixtures",
    )
    g.add_argument(
        "--rate",
        type=_positive,
        default=0.01,
        help="--method compress: growth rate (default 0.01, see compress)",
    )
    g.set_defaults(func=cmd_generate)

    k = sub.add_parser(
        "compress",
        help="grow the spheres of a scenario to a packing fraction "
        "(Lubachevsky-Stillinger); writes a scenario",
    )
    k.add_argument("scenario", nargs="?", help="scenario file ('-' for stdin)")
    _where_args(k, "spherical container radius [m]", "periodic cubic box edge [m]")
    k.add_argument(
        "--packing", type=_positive, help="target packing fraction (below 0.7405 for equal spheres)"
    )
    k.add_argument(
        "--rate",
        type=_positive,
        required=True,
        help="growth speed of the largest diameter per thermal speed "
        "sqrt(kT/m) (1e-1 fast, 1e-4 slow; Skoge et al.'s program's "
        "growthrate g is 2 sqrt(3) g)",
    )
    k.add_argument(
        "--pressure",
        type=_positive,
        default=1e3,
        help="stop as jammed when Z = PV/NkT passes this (default 1e3)",
    )
    k.add_argument("--collisions", type=_positive, help="stop after this many collisions")
    k.add_argument("-o", "--output", required=True, help="write the compressed scenario here")
    k.add_argument("--checkpoint", help="also save a checkpoint here (run --resume reads it)")
    k.add_argument("--resume", help="compress from this checkpoint instead of a scenario")
    k.set_defaults(func=cmd_compress)

    b = sub.add_parser("bench", help="measure collisions per second")
    b.add_argument("--n", type=_whole(2), required=True, help="number of spheres (>= 2)")
    b.add_argument("--packing", type=_packing, required=True)
    b.add_argument(
        "--collisions",
        type=_whole(1),
        required=True,
        help="collisions timed, after the warm-up (2e6 is fine)",
    )
    b.add_argument("--seed", type=_count, default=0, help="random seed (>= 0)")
    b.add_argument("--radius-ratio", type=_ratio, default=1.0)
    b.add_argument("--mass-ratio", type=_ratio, default=1.0)
    b.add_argument("--box", action="store_true", help="periodic box instead of the spherical container")
    b.add_argument(
        "--warmup",
        type=_warmup,
        default=None,
        metavar="auto|PER_SPHERE",
        help="collisions per sphere run before the clock starts; 'auto' "
        "(default): in blocks of 2 per sphere (and 1e5 at least) until the "
        "collision and cell-crossing rates settle to 1%% or their noise, "
        "at most 100 per sphere (or 10 blocks)",
    )
    b.set_defaults(func=cmd_bench)

    r = sub.add_parser("run", help="run a scenario, with trajectory, checkpoints, summary")
    r.add_argument("scenario", nargs="?", help="scenario file in the assignment's format ('-' for stdin)")
    _where_args(r, "spherical container radius [m]", "periodic cubic box edge [m]")
    r.add_argument("--until", type=_positive, required=True, help="end time [s]")
    eq = r.add_mutually_exclusive_group()
    eq.add_argument(
        "--equilibrate",
        type=_count,
        metavar="COLLISIONS",
        help="collisions per sphere to run before the averages start",
    )
    eq.add_argument(
        "--equilibrate-time", type=_positive, metavar="T", help="time [s] to run before the averages start"
    )
    r.add_argument("--trajectory", help="write frames to this .gsd (or .xyz) file")
    r.add_argument(
        "--every", type=_positive, help="time between trajectory frames [s] (default: the run / 100)"
    )
    r.add_argument(
        "--events",
        action="store_true",
        help="also store every event in the .gsd (large: about 40 bytes each)",
    )
    r.add_argument(
        "--checkpoint",
        help="save the run here at the end or on Ctrl-C (with --resume: the resumed file, unless given)",
    )
    r.add_argument(
        "--resume",
        help="continue from this checkpoint instead of a scenario "
        "(an existing --trajectory that ends where it starts is continued)",
    )
    r.add_argument(
        "--overwrite", action="store_true", help="replace an existing --trajectory file (refused otherwise)"
    )
    r.set_defaults(func=cmd_run)

    s = sub.add_parser(
        "sweep", help="run a study (a parameter grid in a TOML file) on Dask; reruns skip finished tasks"
    )
    s.add_argument("study", help="study file (TOML)")
    _dask_args(
        s,
        "an existing Dask scheduler (default: a LocalCluster, one worker per core)",
        "run the tasks here, one by one, no Dask",
    )
    s.set_defaults(func=cmd_sweep)

    v = sub.add_parser(
        "validate",
        help="equation of state (z-scores against Hansen-Goos and KLM) and "
        "collision rate against theory, run as a study",
    )
    v.add_argument("--n", type=_whole(2), default=None, help="spheres (default 4000)")
    v.add_argument(
        "--collisions",
        type=_whole(1),
        default=None,
        help="collisions per sphere measured at each packing (default 500)",
    )
    v.add_argument(
        "--equilibrate",
        type=_count,
        default=None,
        help="collisions per sphere before measuring (default 200: the FCC "
        "start takes about 75 to melt at packing 0.49)",
    )
    v.add_argument(
        "--packings",
        type=_packings,
        default=None,
        help="comma-separated packing fractions (default 0.1,0.2,0.3,0.4,0.45,0.49)",
    )
    v.add_argument(
        "--csv",
        default=None,
        help="CSV output (default validation.csv; with --transport validation-transport.csv)",
    )
    v.add_argument(
        "--transport",
        action="store_true",
        help="instead: D, eta, lambda against published molecular dynamics "
        "(z-scores; N 500 and 1372 at packings 0.2618, 0.3, 0.45: 20 million "
        "collisions, minutes; "
        "with --quick N 256 at 0.3, seconds); see docs/validation.md",
    )
    v.add_argument(
        "--time",
        type=_positive,
        default=None,
        help="--transport: production run per size [sigma sqrt(m/kT)] (default about 7000 mean free times)",
    )
    v.add_argument("--seed", type=_count, default=0, help="random seed (>= 0)")
    v.add_argument("--seeds", type=_whole(1), default=1, help="runs per packing, seeds SEED.. (default 1)")
    v.add_argument(
        "--quick",
        action="store_true",
        help="a few seconds: N 500, 100 collisions per sphere (50 to equilibrate) at packings 0.1,0.3,0.45",
    )
    v.add_argument(
        "--output",
        metavar="DIR",
        help="keep the study here (a rerun skips finished runs); default: temporary",
    )
    _dask_args(v, "an existing Dask scheduler", "run here, one packing after another")
    v.set_defaults(func=cmd_validate)

    w = sub.add_parser("view", help="write a self-contained interactive 3-D viewer (HTML)")
    _picture_args(w, "viewer.html", "the page to write (.html)")
    w.add_argument("--title")
    w.add_argument(
        "--screenshot", metavar="PNG", help="also open the page in headless Chromium, play it 1 s, save a PNG"
    )
    _size_slice_args(
        w,
        "screenshot size WIDTHxHEIGHT (default 960x640)",
        "start with the cut-away plane at z = Z (spheres above it hidden; the page's cut slider moves it)",
    )
    w.add_argument(
        "--color",
        choices=["speed", "mass", "q6"],
        default="speed",
        help="colour the spheres by speed (default), mass, or Steinhardt bond "
        "order q6 over 12 neighbours (crystal-like spheres near 0.5-0.57, a "
        "fluid or jammed packing 0.3-0.45; needs freud)",
    )
    w.set_defaults(func=cmd_view)

    m = sub.add_parser(
        "render", help="render an animation (.gif, .mp4) or a still (.png, .pdf, .svg), headless"
    )
    _picture_args(m, "movie.gif", "movie (.gif; .mp4 with ffmpeg) or still (.png, .pdf, .svg)")
    m.add_argument(
        "--fps", type=_whole(1, 100), default=20, help="movie frames per second (1 to 100, default 20)"
    )
    m.add_argument("--time", type=_time, help="still: draw the frame nearest this time (default: the last)")
    _size_slice_args(
        m,
        "WIDTHxHEIGHT in pixels (default 1280x720 still, 960x540 movie)",
        "cut-away: draw only the spheres whose centre has z <= Z (the inside of a full container)",
    )
    m.set_defaults(func=cmd_render)

    pl = sub.add_parser(
        "plot",
        help="plots (.png, .pdf, .svg): conservation, speeds, eos, transport, sweep, gr, msd, "
        "fs, chi4, contacts",
    )
    pl.add_argument(
        "what",
        choices=[
            "conservation",
            "speeds",
            "eos",
            "transport",
            "sweep",
            "gr",
            "msd",
            "fs",
            "chi4",
            "contacts",
        ],
        help="energy/momentum over time, speeds vs Maxwell-Boltzmann, "
        "the validate CSV vs Carnahan-Starling, the validate --transport CSV "
        "vs published values, a study's results "
        "(--x PARAMETER --y OBSERVABLE), g(r) (periodic box), the "
        "mean squared displacement with D (periodic box), F_s(k, t) with "
        "tau_alpha, chi_4(t) of the overlap (periodic box), or a packing's "
        "contacts Z(h) and forces P(f) (a scenario with --box)",
    )
    pl.add_argument("--k", type=_positive, help="fs: wave number [1/m] (default 2 pi / mean diameter)")
    pl.add_argument("--a", type=_positive, help="chi4: overlap cut-off [m] (default 0.3 mean diameter)")
    _picture_args(pl, "plot.png", "the plot to write (.png, .pdf, .svg)")
    pl.add_argument("--x", default="packing", help="sweep: parameter on the x axis (default packing)")
    pl.add_argument("--y", default="Z", help="sweep: observable on the y axis (default Z)")
    pl.set_defaults(func=cmd_plot)
    return p


def main(argv):
    """Run ``hardspheres ARGV``; returns the exit status."""
    args = build_parser().parse_args(argv)
    try:
        return args.func(args)
    except BrokenPipeError:
        raise  # the caller exits quietly
    except OSError as e:
        if e.filename is None:
            raise  # stdout's: the caller names it
        print(f"hardspheres {args.command}: {oserror_line(e)}", file=sys.stderr)
        return 1
    except ValueError as e:
        print(f"hardspheres {args.command}: {_one_line(e)}", file=sys.stderr)
        return 1


def _one_line(err):
    """An error's message on one line (a library's message may hold newlines)."""
    return " ".join(str(err).split("\n"))

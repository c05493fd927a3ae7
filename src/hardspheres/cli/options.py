"""What every subcommand of ``hardspheres`` shares: the parser class, argument types, option groups.

Argument types raise :class:`argparse.ArgumentTypeError` with a message that
names what is allowed; :class:`Parser` turns it into one line on stderr and
exit status 1 (``hardspheres run: argument --n: ...``).
"""

from __future__ import annotations

import argparse
import re
import sys
from collections.abc import Callable, Sequence
from typing import Any, NoReturn, Protocol

from ..containers import MAX_PACKING, MAX_PACKING_2D
from ..errors import UsageError
from ..messages import QUOTE_LIMIT, quote

#: Picture suffixes: movies and stills.
MOVIES = (".gif", ".mp4", ".m4v", ".mov", ".mkv", ".webm")
STILLS = (".png", ".pdf", ".svg")


class Subcommands(Protocol):
    """What each subcommand's ``add_parser`` is given: the ``hardspheres`` parser's subparsers."""

    def add_parser(self, name: str, **kwargs: Any) -> argparse.ArgumentParser: ...


class Parser(argparse.ArgumentParser):
    """argparse with one-line errors: ``hardspheres run: argument --n: ...``."""

    def error(self, message: str) -> NoReturn:
        # argparse echoes arguments as 'text': cut long ones (a 10 MB argument)
        message = re.sub(r"'([^']{%d})[^']+'" % QUOTE_LIMIT, r"'\1'...", message)
        raise SystemExit(f"{self.prog}: {message} (see {self.prog} --help)")


def number(text: str) -> float:
    """``float(text)`` for a plain decimal number (:func:`~hardspheres.scenario.plain_float`), else NaN."""
    import math

    from ..scenario import plain_float

    x = plain_float(text)
    return math.nan if x is None else x


def positive(text: str) -> float:
    import math

    x = number(text)
    if not math.isfinite(x) or x <= 0.0:
        raise argparse.ArgumentTypeError(f"must be a finite number > 0, got {quote(text)}")
    return x


def restitution(text: str) -> float:
    """A restitution coefficient: a number in (0, 1] (1: elastic)."""
    import math

    x = number(text)
    if not math.isfinite(x) or not 0.0 < x <= 1.0:
        raise argparse.ArgumentTypeError(f"must be a number in (0, 1] (1: elastic), got {quote(text)}")
    return x


def shear_rate(text: str) -> float:
    """A shear rate [1/time]: a finite number other than 0 (either sign: the flow's direction)."""
    import math

    x = number(text)
    if not math.isfinite(x) or x == 0.0:
        raise argparse.ArgumentTypeError(
            f"must be a finite number other than 0 (leave the option out for no shear), got {quote(text)}"
        )
    return x


def nonnegative(text: str) -> float:
    import math

    x = number(text)
    if not math.isfinite(x) or x < 0.0:
        raise argparse.ArgumentTypeError(f"must be a finite number >= 0, got {quote(text)}")
    return x


def ratio(text: str) -> float:
    x = positive(text)
    if x < 1.0:
        raise argparse.ArgumentTypeError(f"must be a number >= 1, got {quote(text)}")
    return x


def whole(lowest: int, highest: int | None = None) -> Callable[[str], int]:
    """A whole number in ``[lowest, highest]``; integral floats as physicists type them
    (``1e5``, ``2.0``) are accepted."""
    import math

    def parse(text: str) -> int:
        x = number(text)
        bound = f">= {lowest}" if highest is None else f"from {lowest} to {highest}"
        if not math.isfinite(x) or x != math.floor(x) or x < lowest or (highest is not None and x > highest):
            raise argparse.ArgumentTypeError(
                f"must be a whole number {bound} (1e5 is fine), got {quote(text)}"
            )
        return int(x)

    parse.__name__ = "whole number"
    return parse


count = whole(0)


def packing(text: str) -> float:
    """A packing fraction (an area fraction for disks): in (0, 0.9069), the disks' limit.

    The limit of the command's dimension (0.7405 for spheres) is checked
    once the container is known (:func:`check_packing`).
    """
    import math

    x = number(text)
    if not math.isfinite(x) or not 0.0 < x < MAX_PACKING_2D:
        raise argparse.ArgumentTypeError(
            f"must be a packing fraction between 0 and {MAX_PACKING:.4f} (spheres) or "
            f"{MAX_PACKING_2D:.4f} (disks), exclusive, got {quote(text)}"
        )
    return x


def check_packing(value: float, dimensions: int, option: str = "--packing") -> None:
    """:class:`UsageError` unless ``value`` is below the densest packing in ``dimensions`` (2 or 3)."""
    top, what = (MAX_PACKING_2D, "disks") if dimensions == 2 else (MAX_PACKING, "spheres")
    if value >= top:
        raise UsageError(
            f"{option} {value:g} is not below {top:.4f}, the densest packing of equal {what}; give less"
        )


def warmup(text: str) -> float | None:
    """``auto`` or collisions per sphere (a finite number >= 0)."""
    import math

    if text.strip().lower() == "auto":
        return None
    x = number(text)
    if not math.isfinite(x) or x < 0.0:
        raise argparse.ArgumentTypeError(f"must be 'auto' or collisions per sphere >= 0, got {quote(text)}")
    return x


def packings(text: str) -> list[float]:
    """Comma-separated packing fractions, every one checked before any is run."""
    values = []
    for part in text.split(","):
        try:
            x = packing(part.strip())
            if x >= MAX_PACKING:  # (the validation's runs are of spheres)
                raise argparse.ArgumentTypeError(part)
            values.append(x)
        except argparse.ArgumentTypeError:
            raise argparse.ArgumentTypeError(
                f"must be comma-separated packing fractions between 0 and {MAX_PACKING:.4f} "
                f"(e.g. 0.1,0.3), got {quote(part.strip())} in {quote(text)}"
            ) from None
    return values


def finite(text: str) -> float:
    import math

    x = number(text)
    if not math.isfinite(x):
        raise argparse.ArgumentTypeError(f"must be a finite number, got {quote(text)}")
    return x


#: The cut-away plane's axes (``--slice AXIS=VALUE``).
SLICE_AXES = ("x", "y", "z")


def slice_plane(text: str) -> tuple[str, float]:
    """``--slice``: ``VALUE`` (the plane ``z = VALUE``) or ``AXIS=VALUE`` with ``AXIS`` x, y or z.

    Returns ``(axis, value)``; the spheres whose centre has that coordinate
    ``<= value`` are drawn.
    """
    import math

    axis, eq, value = text.strip().partition("=")
    if not eq:
        axis, value = "z", text
    axis = axis.strip().lower()
    allowed = (
        f"give VALUE (the plane z = VALUE) or AXIS=VALUE with AXIS x, y or z (e.g. x=0), got {quote(text)}"
    )
    if axis not in SLICE_AXES:
        raise argparse.ArgumentTypeError(allowed)
    x = number(value.strip())
    if math.isnan(x):
        raise argparse.ArgumentTypeError(allowed)
    if not math.isfinite(x):
        raise argparse.ArgumentTypeError(f"the plane's {axis} must be a finite number, got {quote(text)}")
    return axis, x


def size(text: str) -> tuple[int, int]:
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


def suffix(path: str) -> str:
    import os

    return os.path.splitext(path)[1].lower()


def require_suffix(option: str, path: str, allowed: Sequence[str], what: str) -> None:
    """Refuse an output name whose extension is not one of ``allowed`` (before any work)."""
    if suffix(path) not in allowed:
        got = suffix(path) or "no extension"
        raise UsageError(f"{option} {quote(path)}: {what} must end in {', '.join(allowed)} (got {got})")


def note(text: str) -> None:
    """A one-line note on stderr (not an error)."""
    print(text, file=sys.stderr, flush=True)


def compile_first(dimensions: int = 3, inelastic: bool = False, sheared: bool = False) -> None:
    """Compile the event core's variant a run needs now if needed (said on stderr), so no timing includes it.

    Args:
        dimensions: 3, or 2 for disks.
        inelastic: the inelastic collision rule's variant.
        sheared: the Lees-Edwards variant (a sheared box).
    """
    from ..core.warmup import ensure_compiled

    ensure_compiled(dimensions=dimensions, inelastic=inelastic, sheared=sheared)


def picture_args(q: argparse.ArgumentParser, output_default: str | None, output_help: str) -> None:
    q.add_argument("input", help="trajectory (.gsd, .xyz) or scenario file")
    q.add_argument("-o", "--output", default=output_default, help=output_help)
    where_args(q, "scenario: spherical container radius [m]", "scenario: periodic box [m]")
    q.add_argument("--until", type=positive, help="scenario: end time [s]")
    q.add_argument(
        "--every", type=positive, help="scenario: time between frames [s] (default: --until / 200)"
    )
    q.add_argument("--overwrite", action="store_true", help="replace an existing -o file (refused otherwise)")


def refuse_existing(option: str, path: str | None, overwrite: bool) -> None:
    """:class:`UsageError` if the output ``path`` exists (and is not empty) and ``overwrite`` is not given.

    The one rule of every command's outputs (``run --trajectory``, ``view``,
    ``render`` and ``plot`` ``-o``): checked before any work.
    """
    import os

    if path and not overwrite and os.path.isfile(path) and os.path.getsize(path) > 0:
        raise UsageError(f"{option} {path} exists; give --overwrite to replace it, or another file name")


#: The commands whose ``--box`` takes a box's sides (``bench --box`` is a switch).
SIDES_COMMANDS = ("generate", "run", "compress", "view", "render", "plot")

BOX_HELP = (
    "one number L: a cube of edge L (a square with --dimensions 2); two, LX LY: a 2-D box "
    "of disks; three, LX LY LZ: a rectangular box"
)


class BoxSides(argparse.Action):
    """``--box L``, ``--box LX LY`` or ``--box LX LY LZ``: 1 to 3 sides, each > 0."""

    def __call__(
        self,
        parser: argparse.ArgumentParser,
        namespace: argparse.Namespace,
        values: Any,
        option_string: str | None = None,
    ) -> None:
        sides = list(values)
        if not 1 <= len(sides) <= 3:
            raise argparse.ArgumentError(self, f"takes 1 to 3 sides ({BOX_HELP}), got {len(sides)} numbers")
        setattr(namespace, self.dest, sides)


def sides_last(argv: Sequence[str]) -> list[str]:
    """``argv`` with each ``--box`` and the numbers after it moved to the end.

    ``--box`` takes one to three numbers, so argparse would also swallow a
    file name typed after them (``run --box 10 s.txt``); moved to the end,
    the sides take only the numbers, as ``--box L`` always did.  Only for
    :data:`SIDES_COMMANDS`, and never past a ``--``.
    """
    from ..scenario import plain_float

    argv = [str(a) for a in argv]
    if not argv or argv[0] not in SIDES_COMMANDS or "--" in argv:
        return argv
    rest, moved = [argv[0]], []
    i = 1
    while i < len(argv):
        if argv[i] != "--box":
            rest.append(argv[i])
            i += 1
            continue
        k = 0
        while i + 1 + k < len(argv) and plain_float(argv[i + 1 + k]) is not None:
            k += 1
        if k == 0:  # argparse names what is wrong
            rest.append(argv[i])
            i += 1
            continue
        moved += argv[i : i + 1 + k]
        i += 1 + k
    return rest + moved


def dimensions_arg(q: argparse.ArgumentParser, help: str | None = None) -> None:
    """``--dimensions {2,3}``: the dimension of space (default: what the container says)."""
    q.add_argument(
        "--dimensions",
        type=int,
        choices=(2, 3),
        help=help
        or "2 (disks) or 3 (spheres); by default what the container says (--circle and "
        "--box LX LY: 2; --container and --box L: 3); with --box L, 2 makes a square",
    )


def where_args(
    q: argparse.ArgumentParser, container_help: str, box_help: str, required: bool = False
) -> None:
    """``--container R``, ``--circle R`` or ``--box L [LY [LZ]]`` (at most one; exactly one if
    ``required``), and ``--dimensions``."""
    where = q.add_mutually_exclusive_group(required=required)
    where.add_argument("--container", type=positive, metavar="R", help=container_help + " (3-D)")
    where.add_argument(
        "--circle",
        type=positive,
        metavar="R",
        help=("scenario: " if container_help.startswith("scenario: ") else "")
        + "circular container radius [m] (2-D: disks; a scenario's z and vz are 0)",
    )
    where.add_argument(
        "--box",
        type=positive,
        nargs="+",
        action=BoxSides,
        metavar="L",
        help=f"{box_help}: {BOX_HELP} (a disk scenario's z and vz are 0)",
    )
    dimensions_arg(q)


def size_slice_args(q: argparse.ArgumentParser, size_help: str, slice_help: str) -> None:
    """``--size WIDTHxHEIGHT`` (:func:`size`) and ``--slice [AXIS=]VALUE`` (:func:`slice_plane`)."""
    q.add_argument("--size", type=size, help=size_help)
    q.add_argument("--slice", type=slice_plane, metavar="[AXIS=]VALUE", help=slice_help)


def cut_of(plane: tuple[str, float] | None) -> tuple[float | None, str]:
    """``(cut, cut_axis)`` of a picture function from ``--slice``'s ``(axis, value)`` (or ``None``)."""
    return (None, "z") if plane is None else (plane[1], plane[0])


def dask_args(q: argparse.ArgumentParser, scheduler_help: str, serial_help: str) -> None:
    """Where a study runs: ``--scheduler``, ``--workers``, ``--serial``, ``--timeout``."""
    q.add_argument("--scheduler", metavar="tcp://HOST:PORT", help=scheduler_help)
    q.add_argument("--workers", type=count, help="worker processes of the LocalCluster")
    q.add_argument("--serial", action="store_true", help=serial_help)
    q.add_argument(
        "--timeout", type=positive, default=10.0, help="seconds to wait for --scheduler (default 10)"
    )


def version_action() -> str:
    from ..version import package_version

    return f"%(prog)s {package_version()}"


def one_line(err: BaseException) -> str:
    """An error's message on one line (a library's message may hold newlines)."""
    return " ".join(str(err).split("\n"))

"""Command-line programs: ``spheres`` (the assignment's) and ``hardspheres``.

Everything here is at the edge: arguments, stdin, stdout, exit codes.  Bad
input gives one line on stderr and exit status 1, never a traceback; Ctrl-C
exits 130 and a closed stdout (``| head``) exits quietly.

Contract: nothing imports this family (but ``python -m hardspheres``).  All
argument parsing, printing to stdout and ``sys.exit`` live here, with one
module per command family: ``assignment`` (the ``spheres`` program),
``commands`` (the ``hardspheres`` parser), ``run``, ``compress``, ``sweep``
and ``bench``.  The ``spheres`` program starts without numpy: this module,
``assignment``, :mod:`hardspheres.scenario`, :mod:`hardspheres.containers`,
:mod:`hardspheres.errors` and :mod:`hardspheres.io.report` import none.
"""

from __future__ import annotations

import io
import math
import os
import sys
from collections.abc import Callable, Sequence
from typing import IO

from ..errors import UsageError  # noqa: F401 (re-exported)
from ..io.report import PROMPT
from ..messages import oserror_line, quote
from ..scenario import (
    MAX_MAGNITUDE,
    ScenarioError,
    StuckError,
    check_scenario,
    parse_scenario,
    plain_float,
)

USAGE = "usage: spheres [--format text|jsonl] RADIUS END_TIME < scenario.txt"
HELP = f"""{USAGE}

The bouncing-spheres assignment's program: reads spheres from stdin, one per line
    mass radius x y z vx vy vz name
(SI units), and reports every collision and every reflection off the spherical
container of radius RADIUS [m] centred on the origin, up to END_TIME [s].

options:
  --format text|jsonl  text: the assignment's report (default); jsonl: one JSON
                       object per event, every digit kept, no prompt
  -h, --help           show this help and exit
  --version            show the version and exit

Bad input exits 1 with one line on stderr.  More: the hardspheres command.
"""
FORMATS = ("text", "jsonl")


def _positive_number(token: str, what: str, allow_zero: bool, limit: float = math.inf) -> float:
    x = plain_float(token)
    if x is None or not math.isfinite(x) or x < 0.0 or (x == 0.0 and not allow_zero):
        bound = ">= 0" if allow_zero else "> 0"
        raise UsageError(f"{what} must be a finite number {bound}, got {quote(token)}")
    if x > limit:
        raise UsageError(f"{what} must be at most {limit:g}, got {quote(token)}")
    return x


def parse_spheres_args(argv: Sequence[str]) -> tuple[float, float, str]:
    """``(container_radius, end_time, format)`` from the arguments of ``spheres``.

    Two positional arguments, and optionally ``--format text|jsonl``
    (``--format=jsonl``) anywhere: the default is the assignment's report.
    """
    argv = list(argv)
    fmt = "text"
    for k, arg in enumerate(argv):
        if arg == "--format" or arg.startswith("--format="):
            if "=" in arg:
                value = arg.split("=", 1)[1]
                del argv[k]
            elif k + 1 < len(argv):
                value = argv[k + 1]
                del argv[k : k + 2]
            else:
                raise UsageError("--format needs a value: text or jsonl")
            if value not in FORMATS:
                raise UsageError(f"--format must be text or jsonl, got {quote(value)}")
            fmt = value
            break
    for arg in argv:
        if arg.split("=", 1)[0] in ("--thermostat", "--andersen", "--rescale", "--compress"):
            raise UsageError(
                f"{arg.split('=', 1)[0]}: the assignment's program runs NVE only "
                "(thermostats and compression: the hardspheres library)"
            )
    if len(argv) != 2:
        raise UsageError(f"expected 2 arguments (RADIUS END_TIME), got {len(argv)}")
    return (
        _positive_number(argv[0], "argument 1 (RADIUS)", False, MAX_MAGNITUDE),
        _positive_number(argv[1], "argument 2 (END_TIME)", True),
        fmt,
    )


def _help_or_version(argv: Sequence[str], stdout: IO[str]) -> bool:
    """Answer ``--help``/``-h`` or ``--version`` (only as the sole argument); True if done."""
    if len(argv) != 1 or argv[0] not in ("-h", "--help", "--version"):
        return False
    if argv[0] == "--version":
        from ..version import package_version

        stdout.write(f"spheres (hardspheres {package_version()})\n")
    else:
        stdout.write(HELP)
    stdout.flush()
    return True


def run_spheres(argv: Sequence[str], stdin: IO[bytes], stdout: IO[str]) -> int:
    """The assignment's program on given streams; returns the exit status."""
    if _help_or_version(list(argv), stdout):
        return 0
    try:
        container, end, fmt = parse_spheres_args(argv)
    except UsageError:
        fmt = "text"
    if fmt == "text":  # a machine-readable stream has no prompt
        stdout.write(PROMPT)
        stdout.flush()
    try:
        container, end, fmt = parse_spheres_args(argv)
        scn = parse_scenario(stdin)  # a line at a time: stops at the first bad line
        check_scenario(scn, container)
    except (UsageError, ScenarioError) as e:
        hint = f" ({USAGE})" if isinstance(e, UsageError) else ""
        print(f"spheres: {e}{hint}", file=sys.stderr)
        return 1
    from .assignment import write_report

    try:
        write_report(scn, container, end, stdout, fmt)
    except StuckError as e:
        stdout.flush()
        print(f"spheres: {e}", file=sys.stderr)
        return 1
    stdout.flush()
    return 0


def _stdout_name() -> str:
    """What stdout is, for a message: ``stdout`` and its file where the OS says."""
    try:
        target = os.readlink(f"/proc/self/fd/{sys.stdout.fileno()}")
    except (OSError, ValueError, AttributeError):
        return "stdout"
    return f"stdout ({target})" if target.startswith("/") else "stdout"


def _drop_stdout() -> None:
    """Point stdout at /dev/null, so Python's flush at exit does not fail again."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
    except (OSError, ValueError, AttributeError):
        pass


def _checked_stdout() -> None:
    """Make every byte written to stdout count, or fail.

    With ``PYTHONUNBUFFERED`` (or ``-u``) stdout's text layer writes to the
    raw file directly and ignores a short write (a disk filling up): the
    output is cut and the exit status 0.  A buffered layer in between
    retries short writes, so a full disk raises ENOSPC.
    """
    out = sys.stdout
    raw = getattr(out, "buffer", None)
    if isinstance(raw, io.RawIOBase):
        sys.stdout = io.TextIOWrapper(
            io.BufferedWriter(raw),
            encoding=out.encoding,
            errors=out.errors,
            line_buffering=bool(out.line_buffering),
            write_through=True,
        )


def _guarded(main: Callable[[], int], prog: str) -> int:
    """Run ``main()`` mapping Ctrl-C to 130 and a closed stdout to a quiet exit.

    stdout is flushed and checked here: a write that fails (a full disk:
    ENOSPC) exits 1 with one line naming stdout's file, not a traceback
    and not a silent exit 0 with the output cut short.
    """
    try:
        status = main()
        sys.stdout.flush()
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        status = 130
    except BrokenPipeError:
        # stdout's reader went away (e.g. `| head`): stop quietly, and keep
        # Python from complaining again when it flushes stdout at exit
        _drop_stdout()
        status = 141
    except OSError as e:  # only stdout's reach here: the commands name their files
        name = (
            oserror_line(e)
            if e.filename is not None
            else (f"cannot write to {_stdout_name()}: {oserror_line(e)}")
        )
        _drop_stdout()
        print(f"{prog}: {name}", file=sys.stderr)
        status = 1
    return status


def spheres_main(argv: Sequence[str] | None = None) -> None:
    """Entry point of the ``spheres`` console script."""
    argv = sys.argv[1:] if argv is None else argv
    _checked_stdout()
    sys.exit(_guarded(lambda: run_spheres(argv, sys.stdin.buffer, sys.stdout), "spheres"))

"""Command-line programs: ``spheres`` (the assignment's) and ``hardspheres``.

Everything here is at the edge: arguments, stdin, stdout, exit codes.  Bad
input gives one line on stderr and exit status 1, never a traceback; Ctrl-C
exits 130 and a closed stdout (``| head``) exits quietly.
"""

import math
import os
import sys

from .report import PROMPT, TextReport
from .scenario import (MAX_MAGNITUDE, ScenarioError, StuckError, check_scenario,
                       parse_scenario)

USAGE = "usage: spheres [--format text|jsonl] RADIUS END_TIME < scenario.txt"
FORMATS = ("text", "jsonl")


class UsageError(ValueError):
    """Bad command-line arguments."""


def _positive_number(token, what, allow_zero, limit=math.inf):
    try:
        x = float(token)
    except ValueError:
        x = math.nan
    if "_" in token or not token.isascii():  # float() takes 1_0 and non-ASCII digits
        x = math.nan
    if not math.isfinite(x) or x < 0.0 or (x == 0.0 and not allow_zero):
        bound = ">= 0" if allow_zero else "> 0"
        raise UsageError(f"{what} must be a finite number {bound}, got {token!r}")
    if x > limit:
        raise UsageError(f"{what} must be at most {limit:g}, got {token!r}")
    return x


def parse_spheres_args(argv):
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
                del argv[k:k + 2]
            else:
                raise UsageError("--format needs a value: text or jsonl")
            if value not in FORMATS:
                raise UsageError(f"--format must be text or jsonl, got {value!r}")
            fmt = value
            break
    for arg in argv:
        if arg.split("=", 1)[0] in ("--thermostat", "--andersen", "--rescale", "--compress"):
            raise UsageError(f"{arg.split('=', 1)[0]}: the assignment's program runs NVE only "
                             "(thermostats and compression: the hardspheres library)")
    if len(argv) != 2:
        raise UsageError(f"expected 2 arguments (RADIUS END_TIME), got {len(argv)}")
    return (_positive_number(argv[0], "argument 1 (RADIUS)", False, MAX_MAGNITUDE),
            _positive_number(argv[1], "argument 2 (END_TIME)", True), fmt)


def run_spheres(argv, stdin, stdout):
    """The assignment's program on given streams; returns the exit status."""
    try:
        container, end, fmt = parse_spheres_args(argv)
    except UsageError:
        fmt = "text"
    if fmt == "text":  # a machine-readable stream has no prompt
        stdout.write(PROMPT)
        stdout.flush()
    try:
        container, end, fmt = parse_spheres_args(argv)
        scn = parse_scenario(stdin.read())
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


def _guarded(main):
    """Run ``main()`` mapping Ctrl-C to 130 and a closed stdout to a quiet exit."""
    try:
        status = main()
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        status = 130
    except BrokenPipeError:
        # stdout's reader went away (e.g. `| head`): stop quietly, and keep
        # Python from complaining again when it flushes stdout at exit
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        status = 141
    return status


def spheres_main(argv=None):
    """Entry point of the ``spheres`` console script."""
    argv = sys.argv[1:] if argv is None else argv
    sys.exit(_guarded(lambda: run_spheres(argv, sys.stdin.buffer, sys.stdout)))


def hardspheres_main(argv=None):
    """Entry point of the ``hardspheres`` console script (subcommands)."""
    from .commands import main
    argv = sys.argv[1:] if argv is None else argv
    sys.exit(_guarded(lambda: main(argv)))

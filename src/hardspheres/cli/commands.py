"""The ``hardspheres`` command: one module per subcommand, each an ``add_parser``/``run`` pair.

Each subcommand parses its arguments and calls the library; errors from the
library that are the user's to fix (:class:`ValueError` and its kin) print
as one line on stderr with exit status 1.
"""

from __future__ import annotations

import argparse
import signal
import sys
from collections.abc import Sequence

from ..errors import MissingExtraError
from ..messages import oserror_line
from . import (
    _checked_stdout,
    _guarded,
    bench,
    compress,
    generate,
    plot,
    render,
    run,
    sample,
    sweep,
    validate,
    view,
)
from .options import Parser, one_line, sides_last, version_action

#: The subcommands, in the order ``--help`` lists them.
SUBCOMMANDS = (generate, compress, bench, run, sample, sweep, validate, view, render, plot)


def build_parser() -> argparse.ArgumentParser:
    """The ``hardspheres`` parser, each subcommand added by its own module."""
    p = Parser(prog="hardspheres", description="Exact event-driven simulation of perfectly elastic spheres.")
    p.add_argument("--version", action="version", version=version_action())
    sub = p.add_subparsers(dest="command", required=True, parser_class=Parser)
    for command in SUBCOMMANDS:
        command.add_parser(sub)
    return p


def main(argv: Sequence[str]) -> int:
    """Run ``hardspheres ARGV``; returns the exit status."""
    args = build_parser().parse_args(sides_last(argv))
    try:
        return args.func(args)
    except BrokenPipeError:
        raise  # the caller exits quietly
    except OSError as e:
        if e.filename is None:
            raise  # stdout's: the caller names it
        print(f"hardspheres {args.command}: {oserror_line(e)}", file=sys.stderr)
        return 1
    except (ValueError, MissingExtraError) as e:
        print(f"hardspheres {args.command}: {one_line(e)}", file=sys.stderr)
        return 1


def hardspheres_main(argv: Sequence[str] | None = None) -> None:
    """Entry point of the ``hardspheres`` console script (subcommands)."""
    argv = sys.argv[1:] if argv is None else argv
    _checked_stdout()
    status = _guarded(lambda: main(argv), "hardspheres")
    # the command is done (a run's checkpoint written): a late Ctrl-C or
    # SIGTERM while the interpreter shuts down must not change the status
    for signum in (signal.SIGINT, signal.SIGTERM):
        signal.signal(signum, signal.SIG_IGN)
    sys.exit(status)

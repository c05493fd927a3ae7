"""``hardspheres sweep``: a study file run on Dask (or here), its tables named on stdout."""

from __future__ import annotations

import argparse
import signal
import sys
import threading
from pathlib import Path
from types import FrameType
from typing import TYPE_CHECKING, Any, Literal, TextIO

from ..studies import StudyError, connect, load_study, sweep
from .options import dask_args

if TYPE_CHECKING:
    from .options import Subcommands


def run(args: argparse.Namespace, stdout: TextIO = sys.stdout) -> int:
    """``hardspheres sweep STUDY [--scheduler ADDRESS] [--workers N] [--serial]``.

    Ctrl-C (SIGINT) raises KeyboardInterrupt (exit 130, ``interrupted``) and
    is also remembered: should any layer below swallow the
    KeyboardInterrupt and return, the sweep still exits 130, never 0.
    """
    with _RememberCtrlC() as ctrl_c:
        status = _run(args, stdout)
    if ctrl_c.came:
        raise KeyboardInterrupt  # came, and was swallowed below: an interrupted sweep is not a success
    return status


class _RememberCtrlC:
    """SIGINT raises KeyboardInterrupt as Python's own handler does, and sets :attr:`came` (main thread)."""

    def __init__(self) -> None:
        self.came = False
        self._old: Any = None
        # only where Ctrl-C raises KeyboardInterrupt (not where it is ignored: a background job)
        self._on = (
            threading.current_thread() is threading.main_thread()
            and signal.getsignal(signal.SIGINT) is signal.default_int_handler
        )

    def _handle(self, signum: int, frame: FrameType | None) -> None:
        self.came = True
        raise KeyboardInterrupt

    def __enter__(self) -> _RememberCtrlC:
        if self._on:
            self._old = signal.signal(signal.SIGINT, self._handle)
        return self

    def __exit__(self, *exc: object) -> Literal[False]:
        if self._on:
            signal.signal(signal.SIGINT, self._old)
        return False


def _run(args: argparse.Namespace, stdout: TextIO) -> int:
    client = None
    if args.scheduler:
        if args.serial:
            raise StudyError("--serial runs here; it takes no --scheduler")
        client = connect(args.scheduler, timeout=args.timeout)
        print(f"scheduler {args.scheduler}", file=stdout, flush=True)
    try:
        study = load_study(args.study)
        df = sweep(args.study, client=client, serial=args.serial, workers=args.workers, out=stdout)
    finally:
        if client is not None:
            client.close()
    folder = Path(study["output"])
    print(
        f"{len(df)} rows: {folder / 'results.parquet'} (and .csv); "
        f"summary: {folder / 'summary.parquet'} (and .csv)",
        file=stdout,
    )
    return 0


def add_parser(sub: Subcommands) -> argparse.ArgumentParser:
    """Add the subcommand to ``sub`` (the ``hardspheres`` parser's subparsers)."""
    p = sub.add_parser(
        "sweep", help="run a study (a parameter grid in a TOML file) on Dask; reruns skip finished tasks"
    )
    p.add_argument("study", help="study file (TOML)")
    dask_args(
        p,
        "an existing Dask scheduler (default: a LocalCluster, one worker per core)",
        "run the tasks here, one by one, no Dask",
    )
    p.set_defaults(func=run)
    return p

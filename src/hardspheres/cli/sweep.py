"""``hardspheres sweep``: a study file run on Dask (or here), its tables named on stdout."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import TYPE_CHECKING, TextIO

from ..studies import StudyError, connect, load_study, sweep
from .options import dask_args

if TYPE_CHECKING:
    from .options import Subcommands


def run(args: argparse.Namespace, stdout: TextIO = sys.stdout) -> int:
    """``hardspheres sweep STUDY [--scheduler ADDRESS] [--workers N] [--serial]``."""
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

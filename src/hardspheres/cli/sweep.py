"""``hardspheres sweep``: a study file run on Dask (or here), its tables named on stdout."""

import sys
from pathlib import Path

from ..studies import StudyError, connect, load_study, sweep


def main(args, stdout=sys.stdout):
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

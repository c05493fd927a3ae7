"""A study's output folder: where a task's row and checkpoint live, written atomically.

``rows/KEY.parquet`` holds each finished task's row (:func:`row_path`),
``tasks/KEY/`` its checkpoint; tables are written as ``.parquet`` and
``.csv`` (:func:`write_table`).
"""

import json
from pathlib import Path


def atomic(path, write):
    """Call ``write(tmp_path)`` then rename onto ``path`` (:func:`fileio.atomic_path`).

    No lock: a task's files have one writer at a time (Dask reruns a task
    only after its worker is gone).

    Raises:
        OSError: naming ``path``.
    """
    from ..fileio import atomic_path

    with atomic_path(path, lock=False) as tmp:
        write(tmp)


def write_json(path, obj):
    def w(tmp):
        with open(tmp, "w", encoding="utf-8") as fh:
            json.dump(obj, fh)

    atomic(path, w)


def write_table(df, stem):
    """``df`` as ``stem.parquet`` and ``stem.csv``, each written atomically."""
    atomic(f"{stem}.parquet", lambda tmp: df.to_parquet(tmp, index=False))
    atomic(f"{stem}.csv", lambda tmp: df.to_csv(tmp, index=False))


def row_path(task):
    return Path(task["folder"]) / "rows" / f"{task['key']}.parquet"

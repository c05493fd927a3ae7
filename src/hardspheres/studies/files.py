"""A study's output folder: where a task's row and checkpoint live, written atomically.

``rows/KEY.parquet`` holds each finished task's row (:func:`row_path`),
``tasks/KEY/`` its checkpoint; tables are written as ``.parquet`` and
``.csv`` (:func:`write_table`).
"""

from __future__ import annotations

import json
import os
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    import pandas as pd

    from .spec import Task

#: A file's path, as the writers take it.
PathLike = str | os.PathLike[str]


def atomic(path: PathLike, write: Callable[[str], object]) -> None:
    """Call ``write(tmp_path)`` then rename onto ``path`` (:func:`fileio.atomic_path`).

    No lock: a task's files have one writer at a time (Dask reruns a task
    only after its worker is gone).

    Raises:
        OSError: naming ``path``.
    """
    from ..fileio import atomic_path

    with atomic_path(path, lock=False) as tmp:
        write(tmp)


def write_json(path: PathLike, obj: Any) -> None:
    """``obj`` as JSON in ``path``, written atomically."""

    def w(tmp: str) -> None:
        with open(tmp, "w", encoding="utf-8") as fh:
            json.dump(obj, fh)

    atomic(path, w)


def write_table(df: pd.DataFrame, stem: PathLike) -> None:
    """``df`` as ``stem.parquet`` and ``stem.csv``, each written atomically."""
    atomic(f"{stem}.parquet", lambda tmp: df.to_parquet(tmp, index=False))
    atomic(f"{stem}.csv", lambda tmp: df.to_csv(tmp, index=False))


def row_path(task: Task) -> Path:
    """Where ``task``'s row is written when it finishes (``rows/KEY.parquet``)."""
    return Path(task["folder"]) / "rows" / f"{task['key']}.parquet"

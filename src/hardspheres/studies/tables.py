"""A study's results as tables: the rows of the finished tasks, and their summary over seeds."""

from __future__ import annotations

import math
from collections.abc import Iterable
from typing import TYPE_CHECKING, Any

from .files import row_path
from .spec import GRID, GRID_DEFAULTS

if TYPE_CHECKING:
    import pandas as pd

    from .spec import Task


def measured(df: pd.DataFrame) -> list[str]:
    """Observable columns of a results table (those with a ``NAME_err`` beside them)."""
    return [c for c in df.columns if f"{c}_err" in df.columns]


def summarize(df: pd.DataFrame) -> pd.DataFrame:
    """Mean and standard error over seeds, one row per parameter point.

    For each observable ``X``: ``X`` is the mean over seeds; ``X_err`` its
    standard error, from the spread over seeds (``std / sqrt(seeds)``)
    when there are 2 seeds or more, else from the blocks of the one run;
    ``X_err_blocks`` the standard error from the blocks of the runs
    (``sqrt(sum err_i^2) / seeds``).  ``seeds`` counts the runs.

    Args:
        df: results, one row per task (as :func:`sweep` returns).

    Returns:
        A :class:`pandas.DataFrame` sorted by the grid parameters.
    """
    import numpy as np
    import pandas as pd

    params = [c for c in GRID if c != "seed" and c in df.columns]
    obs = measured(df)
    rows: list[dict[str, Any]] = []
    for point, g in df.groupby(params, sort=True):
        point = point if isinstance(point, tuple) else (point,)
        row = dict(zip(params, point))
        k = len(g)
        row["seeds"] = float(k)
        for m in obs:
            v = g[m].to_numpy(float)
            e = g[f"{m}_err"].to_numpy(float)
            row[m] = float(v.mean())
            blocks_err = float(np.sqrt(np.sum(e * e)) / k)
            row[f"{m}_err"] = float(v.std(ddof=1) / math.sqrt(k)) if k > 1 else blocks_err
            row[f"{m}_err_blocks"] = blocks_err
        rows.append(row)
    return pd.DataFrame(rows)


def collect(all_tasks: Iterable[Task]) -> pd.DataFrame:
    """The rows of the finished tasks among ``all_tasks``, sorted by the grid parameters (empty: none)."""
    import pandas as pd

    frames = [pd.read_parquet(row_path(t)) for t in all_tasks if row_path(t).exists()]
    if not frames:
        return pd.DataFrame()
    df = pd.concat(frames, ignore_index=True)
    for k, v in GRID_DEFAULTS.items():  # rows written before the column existed
        df[k] = df[k].fillna(v) if k in df.columns else v
    df["dimensions"] = df["dimensions"].astype(int)
    return df.sort_values([c for c in GRID if c in df.columns], kind="stable").reset_index(drop=True)

"""CSV tables: a header of column names, one row per point, floats written
with 17 significant digits (they read back bit for bit), integer columns as
integers."""

from __future__ import annotations

import csv
import pathlib
from typing import Any

import numpy as np


def _fmt(v: Any) -> str:
    return format(float(v), ".17g")


def write_csv(
    path: pathlib.Path, columns: tuple[str, ...], table: np.ndarray, int_cols: tuple = ()
) -> None:
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(columns)
        for row in table:
            w.writerow(
                [str(int(v)) if c in int_cols else _fmt(v) for c, v in zip(columns, row)]
            )


__all__ = ["write_csv"]

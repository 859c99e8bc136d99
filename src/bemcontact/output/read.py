"""Reading result files back (the CSV tables written by :mod:`bemcontact.output.write`)."""

from __future__ import annotations

import csv
import os

import numpy as np

from ..errors import ConfigError


def read_csv(path: str | os.PathLike) -> dict[str, np.ndarray]:
    """Columns of a CSV file written here, by header name (float64; ``state``
    as int8)."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if not rows:
        raise ConfigError(f"{os.fspath(path)}: empty CSV file")
    header, body = rows[0], rows[1:]
    data = np.array(body, dtype=float).reshape(len(body), len(header))
    out = {h: np.ascontiguousarray(data[:, i]) for i, h in enumerate(header)}
    if "state" in out:
        out["state"] = out["state"].astype(np.int8)
    return out



__all__ = ["read_csv"]

"""The results of a sweep: one row per point (the swept values, the status
and the key outputs), written as ``table.csv`` (and ``table.parquet`` when
pyarrow is installed), and the summary figure ``sweep.png`` (each key
output against each swept parameter; needs matplotlib)."""

from __future__ import annotations

import csv
import importlib.util
import os
import pathlib
import secrets
from typing import Any

import numpy as np

#: The key outputs of a point, in the table's order (after the swept keys).
OUTPUTS = (
    "status", "error", "converged", "normal_force", "tangential_force", "force_x", "force_y",
    "force_z", "newton_iterations", "increments", "stick", "slip", "open", "peak_pressure",
    "slip_area", "contact_area", "seconds", "directory",
)
#: Outputs drawn against each swept parameter in ``sweep.png``.
FIGURE_OUTPUTS = ("normal_force", "tangential_force", "slip_area", "peak_pressure",
                  "newton_iterations")


#: Outputs of a point whose last step rolls (columns after :data:`OUTPUTS`
#: when any point rolls): the creep force on the second body in the rolling
#: frame, its ratios to μ F_n (the creep–force curve), the spin moment, the
#: frictional power and the adhesion area.
ROLLING_OUTPUTS = ("creep_force_x", "creep_force_y", "creep_ratio_x", "creep_ratio_y",
                   "spin_moment", "frictional_power", "adhesion_area")
#: Rolling outputs drawn in ``sweep.png`` when the points roll.
ROLLING_FIGURE_OUTPUTS = ("creep_ratio_x", "creep_ratio_y")

#: Outputs repeated per contact pair of an assembly, as ``pair<k>.<name>``
#: columns (k from 1, in the problem's order) after :data:`OUTPUTS`; the
#: columns of :data:`OUTPUTS` hold the first pair's.
PAIR_OUTPUTS = ("normal_force", "tangential_force", "stick", "slip", "open", "peak_pressure",
                "slip_area", "contact_area")


def _pair_outputs(pr) -> dict[str, Any]:
    fr = pr.frame
    state = np.asarray(fr.state)
    w = np.asarray(fr.weights)
    counts = fr.counts()
    return {
        "normal_force": float(pr.normal_force),
        "tangential_force": float(pr.tangential_force),
        "stick": counts.get("stick", 0), "slip": counts.get("slip", 0),
        "open": counts.get("open", 0),
        "peak_pressure": float(np.max(fr.pressure)) if fr.pressure.size else 0.0,
        "slip_area": float(w[state == 2].sum()),
        "contact_area": float(w[state != 0].sum()),
    }


def outputs(result) -> dict[str, Any]:
    """The key outputs of a :class:`~bemcontact.contact.ContactResult`
    (an assembly's: its first pair's, and every pair's as ``pair<k>.*``)."""
    out = {
        "converged": bool(result.converged),
        **_pair_outputs(result),
        "force_x": float(result.contact_force[0]),
        "force_y": float(result.contact_force[1]),
        "force_z": float(result.contact_force[2]),
        "newton_iterations": int(result.newton_iterations),
        "increments": len(result.steps),
    }
    pairs = getattr(result, "pairs", [])
    if len(pairs) > 1:
        for k, pr in enumerate(pairs, 1):
            out.update({f"pair{k}.{n}": v for n, v in _pair_outputs(pr).items()})
    return out


def grid_outputs(result) -> dict[str, Any]:
    """The key outputs of a contact solved on the grid (a
    :class:`~bemcontact.multiscale.pair.GridResult`), as :func:`outputs`':
    counts of cells, areas from the cells' area, forces in global components
    at the last step; an assembly's (a
    :class:`~bemcontact.multiscale.assembly.GridAssemblyResult`) per pair
    as ``pair<k>.<name>``."""
    pairs = getattr(result, "pairs", None)
    if pairs is None:
        return _grid_pair_outputs(result)
    out: dict[str, Any] = {
        "converged": bool(result.converged),
        "newton_iterations": int(sum(r.iterations for p in pairs for r in p.records)),
        "increments": len(pairs[0].records),
    }
    for k, pr in enumerate(pairs, 1):
        out.update({f"pair{k}.{n}": v for n, v in _grid_pair_outputs(pr).items()})
    return out


def _grid_pair_outputs(result) -> dict[str, Any]:
    last = result.history[-1]
    state = np.asarray(last.state)
    cell = result.grid.cell_area
    force = np.asarray(last.force) @ result.axes
    return {
        "converged": bool(result.converged),
        "normal_force": float(last.force[2]),
        "tangential_force": float(np.hypot(last.force[0], last.force[1])),
        "stick": int((state == 1).sum()), "slip": int((state == 2).sum()),
        "open": int((state == 0).sum()),
        "peak_pressure": float(np.max(last.p[:, 2], initial=0.0)),
        "slip_area": float((state == 2).sum() * cell),
        "contact_area": float((state != 0).sum() * cell),
        "force_x": float(force[0]), "force_y": float(force[1]), "force_z": float(force[2]),
        "newton_iterations": int(sum(r.iterations for r in result.records)),
        "increments": len(result.records),
        **_rolling_outputs(last.rolling),
    }


def _rolling_outputs(rolling: dict | None) -> dict[str, Any]:
    if rolling is None:
        return {}
    power = rolling["frictional_power"]
    return {
        "creep_force_x": rolling["creep_force"][0], "creep_force_y": rolling["creep_force"][1],
        "creep_ratio_x": rolling["creep_force_ratio"][0],
        "creep_ratio_y": rolling["creep_force_ratio"][1],
        "spin_moment": rolling["spin_moment"],
        "frictional_power": rolling["frictional_work_per_distance"] if power is None else power,
        "adhesion_area": rolling["adhesion_area"],
    }


def _pair_columns(rows: list[dict]) -> list[str]:
    """The ``pair<k>.*`` columns the rows hold, pair by pair."""
    k = 1
    cols: list[str] = []
    while any(f"pair{k}.normal_force" in r for r in rows):
        cols += [f"pair{k}.{n}" for n in PAIR_OUTPUTS]
        k += 1
    return cols


def _cell(v: Any) -> str:
    if v is None:
        return ""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        return repr(v)
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_cell(x) for x in v) + "]"
    return str(v)


def _atomic(path: pathlib.Path, write) -> None:
    tmp = path.with_name(f".{path.name}.{secrets.token_hex(4)}.tmp")
    try:
        write(tmp)
        os.replace(tmp, path)
    finally:
        tmp.unlink(missing_ok=True)


def write_table(out: pathlib.Path, keys: list[str], rows: list[dict]) -> list[pathlib.Path]:
    """``table.csv`` (and ``table.parquet`` with pyarrow) in ``out``: one
    row per point, ``point``, the swept keys, then :data:`OUTPUTS` (and an
    assembly's ``pair<k>.*`` columns, :data:`PAIR_OUTPUTS`)."""
    rolls = [c for c in ROLLING_OUTPUTS if any(c in r for r in rows)]
    cols = ["point", *keys, *OUTPUTS, *rolls, *_pair_columns(rows)]

    def csv_file(tmp):
        with open(tmp, "w", newline="", encoding="utf-8") as f:
            w = csv.writer(f)
            w.writerow(cols)
            for r in rows:
                w.writerow([_cell(r.get(c)) for c in cols])

    files = [out / "table.csv"]
    _atomic(files[0], csv_file)
    try:
        import pyarrow
        import pyarrow.parquet
    except ImportError:
        return files

    def column(values):
        values = [_cell(v) if isinstance(v, (list, tuple)) else v for v in values]
        try:
            return pyarrow.array(values)
        except (TypeError, ValueError, OverflowError):  # mixed types: as text
            return pyarrow.array([None if v is None else _cell(v) for v in values])

    table = pyarrow.table({c: column([r.get(c) for r in rows]) for c in cols})
    files.append(out / "table.parquet")
    _atomic(files[1], lambda tmp: pyarrow.parquet.write_table(table, tmp))
    return files


def read_table(path: str | os.PathLike) -> list[dict[str, str]]:
    """The rows of a ``table.csv`` as strings (column -> text)."""
    with open(path, newline="", encoding="utf-8") as f:
        return list(csv.DictReader(f))


def numeric_keys(keys: list[str], rows: list[dict]) -> list[str]:
    """The swept keys whose values are all numbers (they can be an axis)."""
    return [k for k in keys if rows and all(
        isinstance(r.get(k), (int, float)) and not isinstance(r.get(k), bool) for r in rows)]


def write_figure(out: pathlib.Path, keys: list[str], rows: list[dict]) -> pathlib.Path | None:
    """``sweep.png``: each of :data:`FIGURE_OUTPUTS` against each numeric
    swept key (one line per combination of the other keys; failed points
    left out).  None without matplotlib or without a numeric key."""
    axes_keys = numeric_keys(keys, rows)
    if not axes_keys or importlib.util.find_spec("matplotlib") is None:
        return None
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ok = [r for r in rows if r.get("status") == "ok"]
    drawn = [*FIGURE_OUTPUTS, *(c for c in ROLLING_FIGURE_OUTPUTS
                                if ok and all(c in r for r in ok))]
    fig, axes = plt.subplots(len(drawn), len(axes_keys), squeeze=False,
                             figsize=(4.2 * len(axes_keys), 2.4 * len(drawn)))
    for j, k in enumerate(axes_keys):
        others = [o for o in keys if o != k]
        lines: dict[str, list[dict]] = {}
        for r in ok:
            lines.setdefault(", ".join(f"{o} = {_cell(r.get(o))}" for o in others), []).append(r)
        for i, name in enumerate(drawn):
            ax = axes[i][j]
            for label, rs in lines.items():
                rs = sorted(rs, key=lambda r: r[k])
                ax.plot([r[k] for r in rs], [r[name] for r in rs], "o-", label=label or None)
            ax.set_xlabel(k, fontsize=8)
            ax.set_ylabel("F_x / (μ F_n)" if name == "creep_ratio_x" else "F_y / (μ F_n)"
                          if name == "creep_ratio_y" else name.replace("_", " "), fontsize=8)
            ax.tick_params(labelsize=7)
        if others and len(lines) <= 8:
            axes[0][j].legend(fontsize=6)
    fig.tight_layout()
    path = out / "sweep.png"
    _atomic(path, lambda tmp: fig.savefig(tmp, dpi=100, format="png"))
    plt.close(fig)
    return path


__all__ = ["FIGURE_OUTPUTS", "OUTPUTS", "PAIR_OUTPUTS", "ROLLING_OUTPUTS", "numeric_keys", "outputs", "read_table", "write_figure",
           "write_table"]

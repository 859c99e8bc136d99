"""The files of a contact solved on the contact grid (method
``"multiscale"``: :class:`~bemcontact.multiscale.pair.GridResult`), written
all or nothing as :func:`~bemcontact.output.write.write_results` writes a
full result:

* ``summary.json``: the method (requested, used, why, the applicability
  checks), the grid, each body's correction and its error estimate, and per
  load step the contact force, the rigid displacement of body 2 relative to
  body 1, the contact area, the cells closed, in stick and in slip, the peak
  pressure and the checks of the contact conditions;
* ``grid.csv``: per cell its centre (global), pressure, tangential traction
  (global), gap, relative tangential displacement and state, at the last step;
  when that step rolls, also the micro-slip per rolled distance (global) and
  the frictional power density (per unit rolling speed without ``speed``);
* ``grid.vtu``: the cells as quadrilaterals with those fields as cell data,
  and each body's surface stresses there (``<body>_stress``, 6 components,
  ``<body>_von_mises``, ``<body>_tresca``, ``<body>_max_principal``);
* ``<body>.vtu`` (``<body>_body.vtu`` for a body named ``grid``): each
  body's displacement and traction on its own (coarse) mesh at the last
  step, by superposition (:meth:`~bemcontact.multiscale.pair.GridResult.
  body_fields`);
* the stress files of :mod:`bemcontact.output.stresses`;
* ``grid_tractions.png``: pressure and tangential traction maps (with
  matplotlib).

An assembly (:class:`~bemcontact.multiscale.assembly.GridAssemblyResult`)
writes each pair's ``grid.csv``, ``grid.vtu`` and ``grid_tractions.png``
under the stem of the full path's pair files (``<stem>_grid.csv``, ...),
every ``<body>.vtu`` once (a shared body's fields superposed over its
pairs), and in ``summary.json`` per pair its grid summary with ``files``
its stem, the couplings and the sweeps.
"""

from __future__ import annotations

import os
import pathlib
from collections.abc import Mapping
from typing import Any

import numpy as np

from ..errors import ConfigError
from ..multiscale.assembly import GridAssemblyResult
from ..multiscale.pair import GridResult
from .layout import pair_stems
from .rundir import RunDirectory
from .vtu import write_body_vtu, write_vtu
from ..stresses import measures
from .stresses import file_names, stress_fields, stress_summary, write_stress_files
from .tables import write_csv
from .write import OutputOptions, figures_by_default, require_matplotlib, summary, write_json

#: Columns of ``grid.csv``.
GRID_COLUMNS = ("x", "y", "z", "pressure", "tx", "ty", "tz", "gap", "slip_x", "slip_y",
                "slip_z", "state")
#: Columns ``grid.csv`` adds when its step rolls.
ROLLING_COLUMNS = ("microslip_x", "microslip_y", "microslip_z", "power_density")


def _fields(result: GridResult):
    s = result.history[-1]
    A = result.axes
    traction = np.zeros_like(s.p)
    traction[:, :2] = s.p[:, :2]
    slip = np.zeros_like(s.k)
    slip[:, :2] = s.k[:, :2]
    out = {"pressure": s.p[:, 2], "tangential_traction": traction @ A, "gap": s.k[:, 2],
           "slip": slip @ A, "state": s.state.astype(np.int32)}
    if s.slip is not None:
        micro = np.zeros_like(s.k)
        micro[:, :2] = s.slip
        speed = s.rolling.get("speed_used", 1.0)
        out["microslip"] = micro @ A
        out["frictional_power_density"] = -np.einsum("ij,ij->i", s.p[:, :2], s.slip) * speed
    return out


def write_grid_results(result, out_dir: str | os.PathLike | RunDirectory,
                       problem_echo: Mapping[str, Any] | None = None,
                       options: OutputOptions | None = None, *,
                       force: bool = False) -> list[pathlib.Path]:
    """Write the files of the module docstring into ``out_dir`` and return
    their paths (an assembly: each pair's grid files under its pair's stem,
    ``<stem>_grid.csv`` ...)."""
    if not isinstance(result, (GridResult, GridAssemblyResult)):
        raise ConfigError(f"write_grid_results: expected a GridResult, got "
                          f"{type(result).__name__}")
    opt = OutputOptions(figures=figures_by_default()) if options is None else options
    if opt.figures:
        require_matplotlib("write_grid_results: figures")
    pairs = _pair_files(result)
    files = ["summary.json"]
    files += ([f"{pre}grid.vtu" for _, pre in pairs] + [f"{_stem(n)}.vtu" for n in result.names]
              if opt.vtu else [])
    files += [f"{pre}grid.csv" for _, pre in pairs] if opt.csv else []
    files += [f"{pre}grid_tractions.png" for _, pre in pairs] if opt.figures else []
    fields, skipped = stress_fields(result, opt)  # before anything is written: may refuse
    files += file_names(fields, opt)
    rundir = out_dir if isinstance(out_dir, RunDirectory) else RunDirectory(out_dir, force=force)
    with rundir.staging() as tmp:
        data = {**result.summary(), "names": list(result.names)}
        if isinstance(result, GridAssemblyResult):
            for entry, (_, pre) in zip(data["pairs"], pairs):
                entry["files"] = pre.removesuffix("_")
        data["stresses"] = stress_summary(result, fields, skipped)
        write_json(tmp / "summary.json", summary(data, problem_echo))
        write_stress_files(tmp, fields, opt, (problem_echo or {}).get("units"))
        for r, pre in pairs:
            _write_pair(tmp, r, pre, opt, (problem_echo or {}).get("units"))
        if opt.vtu:
            for name in result.names:
                write_body_vtu(tmp / f"{_stem(name)}.vtu", result.body_fields(name))
    out = pathlib.Path(rundir.given)
    return [out / name for name in files]


def _pair_files(result) -> list[tuple[GridResult, str]]:
    """(pair result, the prefix of its grid files) of each pair: '' for two
    bodies, ``<stem>_`` in an assembly (the stems of the full path's pair
    files, :func:`~.layout.pair_stems`)."""
    if isinstance(result, GridResult):
        return [(result, "")]
    stems = pair_stems([(r.names, regions) for r, regions in zip(result.pairs, result.regions)])
    return [(r, f"{stem}_") for r, stem in zip(result.pairs, stems)]


def _write_pair(tmp: pathlib.Path, result: GridResult, pre: str, opt: OutputOptions,
                units) -> None:
    """One grid's ``grid.csv``, ``grid.vtu`` and figure (names after ``pre``)."""
    f = _fields(result)
    if opt.csv:
        table = np.column_stack([result.points, f["pressure"], f["tangential_traction"],
                                 f["gap"], f["slip"], f["state"].astype(float)])
        columns = GRID_COLUMNS
        if "microslip" in f:
            table = np.column_stack([table, f["microslip"], f["frictional_power_density"]])
            columns = columns + ROLLING_COLUMNS
        write_csv(tmp / f"{pre}grid.csv", columns, table, ("state",))
    if opt.vtu:
        points, quads = _quads(result)
        cells = dict(f)
        for name in result.names:  # each body's surface stresses at the cells
            stress = result.surface_stresses(name)
            cells[f"{name}_stress"] = stress
            cells.update({f"{name}_{k}": v for k, v in measures(stress).items()})
        write_vtu(tmp / f"{pre}grid.vtu", points, [("quad", quads)], {},
                  cell_data={k: [np.asarray(v)] for k, v in cells.items()})
    if opt.figures:
        _figure(tmp / f"{pre}grid_tractions.png", result, f, units)


def _stem(body: str) -> str:
    """A body's VTU file stem: its name, unless that is the grid's."""
    return f"{body}_body" if body == "grid" else body


def _quads(result: GridResult):
    g = result.grid
    x = g.origin[0] + g.dx * np.arange(g.nx + 1)
    y = g.origin[1] + g.dy * np.arange(g.ny + 1)
    X, Y = np.meshgrid(x, y, indexing="ij")
    local = np.stack([X.ravel(), Y.ravel(), np.zeros(X.size)], axis=1)
    points = result.origin + local @ result.axes
    i, j = np.divmod(np.arange(g.size), g.ny)
    corner = lambda a, b: (i + a) * (g.ny + 1) + (j + b)  # noqa: E731
    quads = np.stack([corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)], axis=1)
    return points, quads


def _figure(path: pathlib.Path, result: GridResult, f, units) -> None:
    from matplotlib.figure import Figure

    from .plot import save_png

    g = result.grid
    stress = (units or {}).get("stress", "")
    length = (units or {}).get("length", "")
    extent = (g.origin[0], g.origin[0] + g.nx * g.dx, g.origin[1], g.origin[1] + g.ny * g.dy)
    q = np.linalg.norm(f["tangential_traction"], axis=1)
    last = result.history[-1]
    rolls = last.rolling is not None
    # a fixed layout (a constrained one measured every label and took as long
    # as the drawing)
    fig = Figure(figsize=(20 if rolls else 10, 4.2))
    axes = fig.subplots(1, 4 if rolls else 2)
    fig.subplots_adjust(left=0.04 if rolls else 0.07, right=0.98, bottom=0.12, top=0.86,
                        wspace=0.3)
    panels = [(axes[0], f["pressure"], "pressure", f"pressure [{stress}]" if stress else ""),
              (axes[1], q, "tangential traction",
               f"tangential traction [{stress}]" if stress else "")]
    if rolls:
        panels.append((axes[2], np.linalg.norm(f["microslip"], axis=1),
                       "micro-slip per rolled distance", "|s|"))
    for ax, values, name, label in panels:
        im = ax.imshow(values.reshape(g.nx, g.ny).T, origin="lower", extent=extent,
                       cmap="viridis")
        ax.set_title(name)
        fig.colorbar(im, ax=ax, label=label or name)
    if rolls:
        _adhesion_map(fig, axes[3], result, extent)
    for ax in axes:
        ax.set_xlabel(f"t1 [{length}]" if length else "t1")
        ax.set_ylabel(f"t2 [{length}]" if length else "t2")
    fig.suptitle(f"the contact grid, {g.nx} × {g.ny} cells of {g.dx:.3g}"
                 + (f" {length}" if length else "") + f", step {result.history[-1].label}")
    save_png(fig, path)


def _adhesion_map(fig, ax, result: GridResult, extent) -> None:
    """The adhesion/slip map of a rolling step, the rolling direction an
    arrow from the trailing to the leading edge."""
    from matplotlib.colors import ListedColormap

    g = result.grid
    last = result.history[-1]
    ax.imshow(last.state.reshape(g.nx, g.ny).T, origin="lower", extent=extent, vmin=0, vmax=2,
              cmap=ListedColormap(["#f0f0f0", "#2b83ba", "#d7191c"]), interpolation="nearest")
    direction = np.asarray(last.rolling["direction"]) @ result.axes[:2].T
    span = 0.35 * min(extent[1] - extent[0], extent[3] - extent[2])
    cx, cy = 0.5 * (extent[0] + extent[1]), 0.5 * (extent[2] + extent[3])
    ax.annotate("", xy=(cx + span * direction[0], cy + span * direction[1]),
                xytext=(cx - span * direction[0], cy - span * direction[1]),
                arrowprops={"arrowstyle": "->", "lw": 2.0, "color": "k"})
    ax.text(cx + span * direction[0], cy + span * direction[1], " rolling", fontsize=8)
    ratio = last.rolling["creep_force_ratio"]
    ax.set_title(f"adhesion (blue) and slip (red), F/(μF_n) = [{ratio[0]:.3g}, {ratio[1]:.3g}]",
                 fontsize=9)


def report(result, note: str, unit: str, force, tolerance: float) -> str:
    """The lines ``bemcontact run`` prints for a contact solved on the grid
    (``force(value, floor, unit)`` formats a force); an assembly's per pair."""
    s = result.summary()
    several = isinstance(result, GridAssemblyResult)
    pairs = s["pairs"] if several else [s]
    grids = result.pairs if several else [result]
    est = max(c["estimate"] for p in pairs for c in p["corrections"].values())
    newton = [n for p in pairs for n in p["newton_iterations"]]
    first = pairs[0]
    lines = [
        f"converged on the contact grid in {sum(newton)} Newton iteration(s), "
        f"{len(first['steps'])} load step(s) in {len(first['newton_iterations'])} "
        f"increment(s), {s['timings']['total']:.2f} s", f"  {note}",
        f"  the bodies' corrections: error estimate {est:.1g}"]
    if several:
        est_c = max((c["estimate"] for c in s["couplings"]), default=0.0)
        lines.append(f"  the couplings through shared bodies: error estimate {est_c:.1g}")
    for k, (p, g) in enumerate(zip(pairs, grids)):
        pad = "  " if several else ""
        if several:
            lines.append(f"  pair {'/'.join(g.names)}:")
        last = p["steps"][-1]
        floor = 10.0 * tolerance * max(abs(last["normal_force"]), 1e-300)
        lines += [
            f"  {pad}normal force      {force(last['normal_force'], floor, unit)}",
            f"  {pad}tangential force  {force(last['tangential_force'], floor, unit)}",
            f"  {pad}grid ({g.grid.size} cells): {last['cells']['closed']} closed, "
            f"{last['cells']['stick']} stick, {last['cells']['slip']} slip"]
        if "rolling" in last:
            lines.append(
                f"  {pad}rolling ({last['rolling']['mode']}): creep force "
                f"[{', '.join(force(v, floor, unit) for v in last['rolling']['creep_force'])}]"
                f" = [{', '.join(f'{v:.4g}' for v in last['rolling']['creep_force_ratio'])}] "
                f"mu Fn at creepage "
                f"[{', '.join(f'{v:.4g}' for v in last['rolling']['creepage'])}], "
                f"spin {last['rolling']['spin']:.4g}")
    return "\n".join(lines)


__all__ = ["GRID_COLUMNS", "ROLLING_COLUMNS", "report", "write_grid_results"]

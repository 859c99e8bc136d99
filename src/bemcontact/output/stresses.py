"""The stress files of a run: ``[[output.stresses]]`` and the default probes.

For each :class:`~bemcontact.stresses.StressField` (stem
``stresses_<body>_<label>``):

* ``<stem>.csv``: columns :data:`~bemcontact.stresses.COLUMNS` (x, y, z in
  length units; the six components, von Mises and Tresca = (σ1 − σ3)/2 in
  stress units, tension positive, compression negative), one row per point in
  the probe's lattice order;
* ``<stem>.vtu``: the points for ParaView (quadrilaterals for a plane or a
  section, hexahedra for a box, a polyline for a line or profile) with the
  tensor (``stress``, 6 components, xx yy zz xy yz xz), ``von_mises``,
  ``tresca`` and the ``principal`` stresses as point data;
* ``<stem>.png`` (figures on): von Mises on a plane or section, the
  components and von Mises against the distance on a line or profile.

``summary.json`` gets ``stresses``: per field its request, number of points
and the largest von Mises, Tresca and principal (σ1) stresses with their
points, per step; per body the largest over its fields (``maximum``) and on
its surface (``surface``).
"""

from __future__ import annotations

import pathlib

import numpy as np

from ..errors import ConfigError
from ..stresses import COLUMNS, StressField, default_requests, evaluate_all, surface_maxima
from .vtu import write_vtu
from .tables import write_csv


def stress_fields(result, options) -> tuple[list[StressField], list[str]]:
    """The fields a run writes: the ``[[output.stresses]]`` requests, or the
    default probes without them (when ``options.default_stresses``), and the
    lines saying which bodies got no default probes and why.  Raises
    :class:`ConfigError` for a request on an unknown body or with points
    outside its body (before anything is written)."""
    if options.stresses:
        names = set(getattr(result, "names", ()))
        for r in options.stresses:
            if r.body not in names:
                raise ConfigError(f"output.stresses {r.label!r}: unknown body {r.body!r}; the "
                                  f"bodies are {sorted(names)}", location={"field": "body"})
        return evaluate_all(result, [(r, None) for r in options.stresses]), []
    if not options.default_stresses:
        return [], []
    requests, skipped = default_requests(result)
    return evaluate_all(result, requests), skipped


def stem(f: StressField) -> str:
    return f"stresses_{f.request.body}_{f.request.label}"


def _figures(fields: list[StressField], options) -> list[tuple[str, list[StressField]]]:
    """(file name, its fields): one figure per asked-for field, or per body
    for the default probes (section 1 with the depth profile beside it)."""
    if not options.figures:
        return []
    if options.stresses:  # a field of one point has nothing to draw
        return [(f"{stem(f)}.png", [f]) for f in fields if max(f.lattice.shape) > 1]
    bodies: dict[str, list[StressField]] = {}
    for f in fields:
        bodies.setdefault(f.request.body, []).append(f)
    return [(f"stresses_{b}.png", [f for f in fs if f.request.label in ("section1", "profile")])
            for b, fs in bodies.items()]


def file_names(fields: list[StressField], options) -> list[str]:
    out = []
    for f in fields:
        out += [f"{stem(f)}.csv"] if options.csv else []
        out += [f"{stem(f)}.vtu"] if options.vtu else []
    return out + [name for name, _ in _figures(fields, options)]


def stress_summary(result, fields: list[StressField], skipped: list[str]) -> dict:
    """``summary.json``'s ``stresses``: fields, per-body maxima, skipped, and
    per body the maxima of its surface stresses (``surface``)."""
    bodies: dict[str, dict] = {}
    for f in fields:
        for measure, m in (f.maxima[-1] if f.maxima else {}).items():
            best = bodies.setdefault(f.request.body, {}).get(measure)
            if best is None or m["value"] > best["value"]:
                bodies[f.request.body][measure] = {**m, "label": f.request.label}
    return {"fields": [f.summary() for f in fields], "maximum": bodies, "skipped": skipped,
            "surface": surface_maxima(result)}


def write_stress_files(directory: pathlib.Path, fields: list[StressField],
                       options, units) -> None:
    """Write each field's files (module docstring) into ``directory``."""
    for f in fields:
        base = directory / stem(f)
        if options.csv:
            write_csv(base.with_suffix(".csv"), COLUMNS, f.table())
        if options.vtu:
            write_vtu(base.with_suffix(".vtu"), f.points, _cells(f.lattice.shape),
                      {"stress": f.stresses, "von_mises": f.von_mises, "tresca": f.tresca,
                       "principal": f.principal})
    for name, group in _figures(fields, options):
        _figure(directory / name, group, units or {})


def _cells(shape: tuple[int, ...]):
    """VTU cells joining a lattice's points: its directions with more than
    one point make a polyline, quadrilaterals or hexahedra."""
    idx = np.arange(int(np.prod(shape))).reshape([n for n in shape if n > 1] or [1])
    if idx.ndim == 1 and idx.size > 1:
        return [("line", np.stack([idx[:-1], idx[1:]], axis=1))]
    if idx.ndim == 2:
        return [("quad", np.stack([idx[:-1, :-1].ravel(), idx[1:, :-1].ravel(),
                                   idx[1:, 1:].ravel(), idx[:-1, 1:].ravel()], axis=1))]
    if idx.ndim == 3:
        nx, ny, nz = idx.shape
        return [("hexahedron", np.stack([
            idx[a:a + nx - 1, b:b + ny - 1, c:c + nz - 1].ravel()
            for a, b, c in ((0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0),
                            (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1))], axis=1))]
    return [("vertex", idx.reshape(-1, 1))]


def _layout(plane: StressField | None, line: StressField | None):
    """The figure and its axes (the plane's, its colorbar's, the line's; None
    where not drawn), placed in inches: the plane's panel as wide as its
    equal aspect makes it (no blank band beside it), the line's beside it
    sharing the depth axis when both are drawn.  A fixed layout: a
    constrained one measured every label and took as long as the drawing."""
    H, bottom, top = 4.8, 0.6, 0.4
    h = H - bottom - top
    boxes, x = {}, 0.0
    if plane is not None:
        lat = plane.lattice
        a, b = [k for k, n in enumerate(lat.shape) if n > 1][:2]
        du, dv = (float(np.ptp(lat.coordinates[k])) for k in (a, b))
        width = min(max(h * du / dv, 1.6), 7.5) if dv > 0 else h
        if line is not None:  # the colorbar on the left, the profile on the right
            boxes["bar"] = (0.95, 0.18)
            x = 0.95 + 0.18 + 0.8
            boxes["plane"] = (x, width)
            x += width + 0.3
        else:
            boxes["plane"] = (0.85, width)
            boxes["bar"] = (0.85 + width + 0.25, 0.18)
            x = 0.85 + width + 0.25 + 0.18 + 1.0
    if line is not None:
        x = x if plane is not None else 0.85  # a line alone: its own axis labels' margin
        boxes["line"] = (x, 4.0)
        x += 4.0 + 0.25
    from matplotlib.figure import Figure

    fig = Figure(figsize=(x, H))

    def add(name, **kw):
        if name not in boxes:
            return None
        left, w = boxes[name]
        return fig.add_axes((left / x, bottom / H, w / x, h / H), **kw)

    ax_plane, ax_bar = add("plane"), add("bar")
    return fig, ax_plane, ax_bar, add("line", sharey=ax_plane)


def _figure(path: pathlib.Path, fields: list[StressField], units) -> None:
    """A plane's von Mises map and a line's stresses against its distance,
    side by side when both are given (a section and its depth profile,
    sharing the depth axis)."""
    from matplotlib.ticker import MaxNLocator

    from .plot import save_png

    stress, length = units.get("stress", ""), units.get("length", "")
    su, lu = (f" [{stress}]" if stress else ""), (f" [{length}]" if length else "")
    planes = [f for f in fields if sum(n > 1 for n in f.lattice.shape) >= 2]
    lines = [f for f in fields if sum(n > 1 for n in f.lattice.shape) == 1]
    both = bool(planes and lines)
    fig, ax_plane, ax_bar, ax_line = _layout(planes[0] if planes else None,
                                             lines[0] if lines else None)
    if planes:
        f = planes[0]
        ax = ax_plane
        lat = f.lattice
        dims = [k for k, n in enumerate(lat.shape) if n > 1]
        # the lattice without its one-point directions; a full box: the middle
        # slice across its last direction (its largest value marked there)
        vm = f.von_mises.reshape([lat.shape[k] for k in dims])
        if len(dims) == 3:
            vm = vm[:, :, vm.shape[2] // 2]
        a, b = dims[:2]
        X, Y = np.meshgrid(lat.coordinates[a], lat.coordinates[b], indexing="ij")
        m = ax.contourf(X, Y, vm, levels=20, cmap="magma_r")
        fig.colorbar(m, cax=ax_bar, label=f"von Mises{su}", location="left" if both else "right")
        i, j = np.unravel_index(int(np.argmax(vm)), vm.shape)
        ax.plot(lat.coordinates[a][i], lat.coordinates[b][j], "c+", ms=14, mew=2,
                label=f"max {vm[i, j]:.4g}{' ' + stress if stress else ''}")
        ax.legend(loc="lower right", fontsize=8)
        if lat.names[b] == "depth":
            ax.invert_yaxis()
        ax.set_xlabel(f"{lat.names[a]}{lu}")
        ax.set_ylabel(f"{lat.names[b]}{lu}")
        ax.set_aspect("equal")
        ax.set_title(f"{f.request.body}: von Mises on {f.request.label}")
    if lines:
        f = lines[0]
        ax = ax_line
        k = [k for k, n in enumerate(f.lattice.shape) if n > 1][0]
        x = f.lattice.coordinates[k]
        curves = [(f.stresses[:, j], name, "-", 1.2) for j, name in
                  enumerate(("σxx", "σyy", "σzz", "σxy", "σyz", "σxz"))]
        curves += [(f.von_mises, "von Mises", "k-", 2.0), (f.tresca, "Tresca", "k--", 1.5)]
        for values, name, style, lw in curves:
            if both:  # the depth profile: depth down the shared vertical axis
                ax.plot(values, x, style, lw=lw, label=name)
            else:
                ax.plot(x, values, style, lw=lw, label=name)
        ax.xaxis.set_major_locator(MaxNLocator(5))
        if both:
            ax.tick_params(labelleft=False)  # the depths: the section's axis
            ax.axvline(0.0, color="0.6", lw=0.6)
            ax.set_xlabel(f"stress{su}")
            ax.set_title(f"{f.request.body}: {f.request.label}")
        else:
            ax.axhline(0.0, color="0.6", lw=0.6)
            ax.set_xlabel(f"{f.lattice.names[k]}{lu}")
            ax.set_ylabel(f"stress{su}")
            ax.set_title(f"{f.request.body}: {f.request.label} ({f.request.kind})")
        ax.legend(ncol=2, fontsize=8)
    save_png(fig, path)


__all__ = ["file_names", "stress_fields", "stress_summary", "write_stress_files"]

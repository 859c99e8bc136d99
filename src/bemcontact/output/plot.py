"""Figures of contact results (matplotlib, an optional dependency imported
inside the functions; figures are drawn off-screen with the Agg renderer and
no pyplot state is touched).

A result is given either as a :class:`~bemcontact.contact.results.ContactResult` or
as a directory written by :func:`bemcontact.output.write.write_results` (the CLI's
``--out``), from whose ``<body>_interface.csv`` files the same figure is
rebuilt (an assembly's: its first pair's, or a pair's
:class:`~bemcontact.contact.results.PairResult`).
"""

from __future__ import annotations

import json
import math
import os
import pathlib
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from ..contact.results import ContactResult, FrameResult, PairResult
from ..errors import ConfigError

Source = ContactResult | PairResult | str | os.PathLike


@dataclass(frozen=True)
class InterfaceLine:
    """One body's interface nodes on a line.

    body: body name.  axis: the coordinate along the line (0, 1, 2).
    across: the other in-plane coordinate; ``row`` its value on the line.
    coordinate: (n,) position along the line, increasing.
    displacement: (n, 3) displacement of those nodes.
    """

    body: str
    axis: int
    across: int
    row: float
    coordinate: np.ndarray
    displacement: np.ndarray


def _interface_points(source: Source) -> list[tuple[str, np.ndarray, np.ndarray]]:
    """(body name, points (n, 3), displacement (n, 3)) of both interfaces
    (of an assembly: of its first pair, as ``ContactResult.interfaces``)."""
    if isinstance(source, (ContactResult, PairResult)):
        return [(i.body, i.points, i.displacement) for i in source.interfaces]
    if not isinstance(source, (str, os.PathLike)):
        raise ConfigError(
            "expected a ContactResult, PairResult or a results directory, got "
            f"{type(source).__name__}"
        )
    from .read import read_csv

    d = pathlib.Path(source)
    if not d.is_dir():
        raise ConfigError(f"{os.fspath(source)}: not a results directory")
    names: list[str] = []
    prefix = ""
    summary = d / "summary.json"
    if summary.is_file():
        s = json.loads(summary.read_text())
        names = list(s.get("names", []))
        pairs = s.get("pairs") or []
        if pairs and isinstance(pairs[0], Mapping) and "files" in pairs[0]:  # an assembly
            names, prefix = list(pairs[0]["bodies"]), f"{pairs[0]['files']}_"
    if not names:
        names = sorted(p.name[: -len("_interface.csv")] for p in d.glob("*_interface.csv"))
    if not names:
        raise ConfigError(f"{os.fspath(source)}: no <body>_interface.csv files")
    out = []
    for n in names:
        f = d / f"{prefix}{n}_interface.csv"
        if not f.is_file():
            raise ConfigError(f"{f}: missing (the directory's summary.json names body {n!r})")
        c = read_csv(f)
        try:
            pts = np.column_stack([c["x"], c["y"], c["z"]])
            u = np.column_stack([c["ux"], c["uy"], c["uz"]])
        except KeyError as exc:
            raise ConfigError(f"{f}: no column {exc.args[0]!r}") from None
        out.append((n, pts, u))
    return out


def _rows(values: np.ndarray, tol: float) -> tuple[np.ndarray, np.ndarray]:
    """Distinct values (within tol) in increasing order, and how many nodes
    each holds."""
    v = np.sort(values)
    start = np.concatenate([[True], np.diff(v) > tol])
    idx = np.flatnonzero(start)
    return v[idx], np.diff(np.append(idx, v.size))


def interface_line(
    source: Source, axis: int = 0, through: float | None = None
) -> list[InterfaceLine]:
    """Both bodies' interface displacements along one line of the (flat)
    contact interface.

    The interface plane is the pair of coordinate axes in which the interface
    nodes spread most; the line runs along ``axis`` at the other in-plane
    coordinate ``through`` (default: a quarter into the range of that
    coordinate covered by both bodies' nodes, off the symmetry line of symmetric problems, where the
    in-plane displacement across the line vanishes).  The meshes need not
    match and need not have nodes on the line: each body's nodal
    displacements are interpolated linearly (Delaunay triangulation of its
    interface nodes in the plane, :class:`scipy.interpolate.LinearNDInterpolator`),
    exact for the linear fields and O(h^2) otherwise, at that body's distinct
    node coordinates along ``axis`` which fall inside its node cloud.  Both
    bodies are thus compared on the same line, as in the founding paper's
    Figure 1.  Near the edges the nodes are partially discontinuous (shifted
    into the elements, docs/theory.md), so the line stops about h/6 short of
    the interface's edges.
    """
    from scipy.interpolate import LinearNDInterpolator

    bodies = _interface_points(source)
    if axis not in (0, 1, 2):
        raise ConfigError(f"axis must be 0, 1 or 2 (x, y, z), got {axis!r}")
    allp = np.vstack([p for _, p, _ in bodies])
    extent = allp.max(axis=0) - allp.min(axis=0)
    normal = int(np.argmin(extent))
    if axis == normal:
        raise ConfigError(
            f"axis {'xyz'[axis]} is normal to the contact interface; choose an in-plane axis"
        )
    across = 3 - axis - normal
    # default line: a quarter into the range both bodies' nodes cover
    lo = max(float(p[:, across].min()) for _, p, _ in bodies)
    hi = min(float(p[:, across].max()) for _, p, _ in bodies)
    width = float(extent[across])
    target = lo + 0.25 * (hi - lo) if through is None else float(through)
    tol = 1e-9 * max(width, 1e-300)
    lines = []
    for name, p, u in bodies:
        plane = p[:, [axis, across]]
        coords, _ = _rows(p[:, axis], tol)
        samples = np.column_stack([coords, np.full(coords.size, target)])
        values = LinearNDInterpolator(plane, u)(samples)
        ok = np.isfinite(values).all(axis=1)
        if not ok.any():
            raise ConfigError(
                f"{name}: the line {'xyz'[across]} = {target:g} misses its interface nodes "
                f"({'xyz'[across]} from {p[:, across].min():g} to {p[:, across].max():g})"
            )
        lines.append(InterfaceLine(name, axis, across, target, coords[ok], values[ok]))
    return lines


def plot_interface_line(
    results: Mapping[str, Source],
    path: str | os.PathLike,
    component: int = 1,
    axis: int = 0,
    through: float | None = None,
    *,
    length_unit: str = "mm",
) -> pathlib.Path:
    """The founding paper's Figure 1: per result one panel with the
    displacement component ``component`` (default 1, u_y) of both bodies'
    interface nodes along a line of the interface (see
    :func:`interface_line` for ``axis`` and ``through``).  ``results`` maps a
    panel title (e.g. "similar", "dissimilar") to a ContactResult or a
    results directory.  Writes a PNG to ``path`` and returns it."""
    from matplotlib.figure import Figure

    if not results:
        raise ConfigError("plot_interface_line: no results given")
    if component not in (0, 1, 2):
        raise ConfigError(f"component must be 0, 1 or 2 (x, y, z), got {component!r}")
    c = "xyz"[component]
    fig = Figure(figsize=(5.0 * len(results), 4.0), layout="constrained")
    axes = fig.subplots(1, len(results), squeeze=False)[0]
    for ax, (title, source) in zip(axes, results.items()):
        for line, marker in zip(interface_line(source, axis, through), ("o", "s")):
            ax.plot(
                line.coordinate, line.displacement[:, component], marker=marker, markersize=4,
                label=line.body,
            )
        ax.set_title(f"{title} ({'xyz'[line.across]} = {line.row:.4g} {length_unit})")
        ax.set_xlabel(f"{'xyz'[axis]} ({length_unit})")
        ax.set_ylabel(f"$u_{c}$ ({length_unit})")
        ax.axhline(0.0, color="0.7", linewidth=0.8)
        ax.grid(True, alpha=0.3)
        ax.legend()
    return save_png(fig, path)


def save_png(fig, path: str | os.PathLike) -> pathlib.Path:
    """Write ``fig`` as PNG to ``path`` through a temporary file in the same
    directory (an interrupted write never leaves a partial PNG)."""
    out = pathlib.Path(path)
    if not out.parent.is_dir():
        raise ConfigError(f"{os.fspath(path)}: the directory {os.fspath(out.parent)!r} does not exist")
    tmp = out.with_name(f".{out.name}.tmp-{os.getpid()}")
    try:
        fig.savefig(tmp, dpi=150, format="png")
        os.replace(tmp, out)
    finally:
        if tmp.exists():
            tmp.unlink()
    return out


def _suffix(unit: str) -> str:
    return f" ({unit})" if unit else ""


def _closed_center(xy: np.ndarray, frame: FrameResult) -> np.ndarray:
    """The pressure-weighted centroid of the closed nodes (plane coordinates)."""
    closed = frame.state > 0
    load = frame.weights * np.maximum(frame.pressure, 0.0)
    w = np.where(closed & np.isfinite(frame.pressure), load, 0.0)
    if not w.sum() > 0:
        w = closed.astype(float)
    return (w[:, None] * xy).sum(axis=0) / w.sum()


def axisymmetry(frame: FrameResult, min_nodes: int = 12) -> tuple[np.ndarray, float] | None:
    """Whether the contact on ``frame`` is axisymmetric: (centre, scatter) or
    None if fewer than ``min_nodes`` nodes are closed.

    centre: the pressure-weighted centroid of the closed nodes in the frame's
    plane coordinates (those of :func:`plot_frame_tractions`).  scatter: the
    RMS deviation of the closed nodes' pressure from its mean over rings of
    equal node count (about 8 nodes each, ordered by the distance r from the
    centre), divided by the peak pressure, plus the relative excess of the
    closed zone's largest r over the radius of the disc of its area (0 for
    a disc, 0.25 for a square).  :data:`AXISYMMETRIC_SCATTER` separates a
    sphere on a block (0.07 at h = a / 4) from the two cubes' square
    contact (0.26)."""
    closed = (frame.state > 0) & np.isfinite(frame.pressure)
    if closed.sum() < min_nodes:
        return None
    xy, _, _ = _plane_coordinates(frame.points, frame.normals)
    c = _closed_center(xy, frame)
    r = np.hypot(*(xy[closed] - c).T)
    p = frame.pressure[closed][np.argsort(r)]
    rings = np.array_split(p, max(3, p.size // 8))
    dev = np.concatenate([ring - ring.mean() for ring in rings])
    peak = float(np.abs(p).max()) or 1.0
    disc = math.sqrt(float(frame.weights[closed].sum()) / math.pi)
    excess = max(0.0, float(r.max()) / disc - 1.0) if disc > 0 else 1.0
    return c, float(np.sqrt(np.mean(dev**2))) / peak + excess


#: Largest :func:`axisymmetry` scatter of a contact drawn as a radial profile.
AXISYMMETRIC_SCATTER = 0.15


def plot_radial_profile(
    source: ContactResult | PairResult | FrameResult,
    path: str | os.PathLike,
    *,
    pressure=None,
    traction=None,
    component: int | None = 0,
    center=(0.0, 0.0),
    title: str = "",
    length_unit: str = "mm",
    stress_unit: str = "MPa",
) -> pathlib.Path:
    """Contact pressure and tangential traction at the frame nodes against
    their distance r from ``center`` (in the frame's plane: x-y for a frame
    normal to z; ``None``: the closed nodes' pressure-weighted centroid),
    with analytic curves.

    ``pressure`` and ``traction``: optional callables r -> analytic values
    (e.g. ``reference.hertz(...).pressure`` and a Cattaneo–Mindlin traction),
    drawn as lines over the plotted range.  The traction plotted is the
    ``component`` (0: x, 1: y) of the traction on body 1 (the frame's
    tangential traction acts on body 2; body 1 receives the opposite), so a
    tangential force pulling body 2 in +x shows positive; ``None``: its
    magnitude |q|.  Nodes are marked by state (stick, slip, open); r runs
    to 1.3 times the largest r of a closed node.  Without friction (|q|
    below 1e-6 of the peak pressure and no ``traction`` curve) the traction
    panel, which would be flat zero, is left out.  Units label the axes
    (``""``: none).  Writes a PNG to ``path`` and returns it."""
    from matplotlib.figure import Figure

    from ..contact.law import SLIP, STICK

    frame = source.frame if isinstance(source, (ContactResult, PairResult)) else source
    if not isinstance(frame, FrameResult):
        raise ConfigError(
            "plot_radial_profile: expected a ContactResult or FrameResult, got "
            f"{type(source).__name__} (a PairResult is accepted too)"
        )
    if component not in (0, 1, None):
        raise ConfigError(f"component must be 0 or 1 (x, y) or None (|q|), got {component!r}")
    closed = frame.state > 0
    if not closed.any():
        raise ConfigError("plot_radial_profile: no frame node is in contact")
    xy, _, _ = _plane_coordinates(frame.points, frame.normals)
    c = _closed_center(xy, frame) if center is None else np.asarray(center, dtype=float)
    r = np.hypot(xy[:, 0] - c[0], xy[:, 1] - c[1])
    rmax = 1.3 * r[closed].max()
    shown = r <= rmax
    grid = np.linspace(0.0, rmax, 400)
    if component is None:
        q, qlabel = np.linalg.norm(frame.tangential_traction, axis=1), "$|q|$"
    else:
        q, qlabel = -frame.tangential_traction[:, component], f"$q_{'xy'[component]}$ on body 1"
    panels = [(frame.pressure, pressure, "pressure $p$")]
    peak = float(np.nanmax(np.abs(frame.pressure[closed]))) if closed.any() else 0.0
    if traction is not None or np.nanmax(np.abs(q)) > 1e-6 * peak:
        panels.append((q, traction, qlabel))
    fig = Figure(figsize=(5.0 * len(panels), 4.0), layout="constrained")
    axes = fig.subplots(1, len(panels), squeeze=False)[0]
    # without friction every closed node counts as slipping: mark them "closed"
    marks = ((((STICK,), "o", "stick"), ((SLIP,), "^", "slip")) if len(panels) == 2
             else (((STICK, SLIP), "o", "closed"),)) + (((0,), "x", "open"),)
    for ax, (values, exact, label) in zip(axes, panels):
        for st, marker, lab in marks:
            m = shown & np.isin(frame.state, st)
            if m.any():
                ax.plot(r[m], values[m], marker, markersize=3, linestyle="none", label=lab)
        if exact is not None:
            ax.plot(grid, np.asarray(exact(grid), dtype=float), "k-", linewidth=1.2, label="analytic")
        ax.set_xlim(0.0, rmax)
        ax.set_xlabel("r" + _suffix(length_unit))
        ax.set_ylabel(label + _suffix(stress_unit))
        ax.grid(True, alpha=0.3)
        ax.legend()
    if title:
        fig.suptitle(title)
    return save_png(fig, path)


def plot_force_displacement(
    displacement,
    force,
    path: str | os.PathLike,
    *,
    analytic=None,
    title: str = "",
    xlabel: str = "platen displacement $U_x$ (mm)",
    ylabel: str = "tangential force $Q$ (N)",
) -> pathlib.Path:
    """A force–displacement curve (e.g. the fretting loop of a load history:
    the platen's translation and force per load step), computed points
    joined in order, with an optional analytic curve ``analytic = (u, f)``.
    Writes a PNG to ``path`` and returns it."""
    from matplotlib.figure import Figure

    u = np.asarray(displacement, dtype=float).ravel()
    f = np.asarray(force, dtype=float).ravel()
    if u.size != f.size or u.size < 2:
        raise ConfigError(
            f"plot_force_displacement: need as many displacements as forces (>= 2), got "
            f"{u.size} and {f.size}"
        )
    fig = Figure(figsize=(5.5, 4.5), layout="constrained")
    ax = fig.subplots()
    if analytic is not None:
        ua, fa = (np.asarray(v, dtype=float).ravel() for v in analytic)
        ax.plot(ua, fa, "k-", linewidth=1.2, label="analytic")
    ax.plot(u, f, "o-", markersize=4, linewidth=0.8, label="bemcontact")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.axhline(0.0, color="0.7", linewidth=0.8)
    ax.axvline(0.0, color="0.7", linewidth=0.8)
    ax.grid(True, alpha=0.3)
    ax.legend()
    if title:
        ax.set_title(title)
    return save_png(fig, path)


def _plane_coordinates(points: np.ndarray, normals: np.ndarray) -> tuple[np.ndarray, str, str]:
    """2D coordinates of frame points in the plane of their mean normal: the
    two global axes closest to that plane when it is a coordinate plane
    (labels x, y, z), else an orthonormal in-plane basis (labels s, t)."""
    n = normals[np.isfinite(normals).all(axis=1)].mean(axis=0) if normals.size else np.zeros(3)
    if not np.isfinite(n).all() or np.linalg.norm(n) == 0.0:
        n = np.array([0.0, 0.0, 1.0])
    n = n / np.linalg.norm(n)
    a = int(np.argmax(np.abs(n)))
    if abs(n[a]) > 0.999:
        i, j = [b for b in range(3) if b != a]
        return points[:, [i, j]], "xyz"[i], "xyz"[j]
    e1 = np.cross(n, np.eye(3)[int(np.argmin(np.abs(n)))])
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(n, e1)
    return np.column_stack([points @ e1, points @ e2]), "s", "t"


def contact_window(xy: np.ndarray, state: np.ndarray, weights: np.ndarray,
                   margin: float = 0.25) -> tuple[float, float, float, float]:
    """The part of the frame plane a map shows, (xmin, xmax, ymin, ymax):
    the closed nodes' bounding box widened on each side by ``margin`` times
    its larger side (at least two node spacings), within the frame's
    bounding box; the whole frame when no node is closed."""
    lo, hi = xy.min(axis=0), xy.max(axis=0)
    closed = state > 0
    if not closed.any():
        return float(lo[0]), float(hi[0]), float(lo[1]), float(hi[1])
    clo, chi = xy[closed].min(axis=0), xy[closed].max(axis=0)
    spacing = 2.0 * math.sqrt(float(np.median(weights[closed]))) if weights.size else 0.0
    pad = max(margin * float((chi - clo).max()), spacing)
    wlo, whi = np.maximum(clo - pad, lo), np.minimum(chi + pad, hi)
    return float(wlo[0]), float(whi[0]), float(wlo[1]), float(whi[1])


def _triangulation(xy: np.ndarray, cells):
    """The frame's triangles (its cells, quads split) or a Delaunay
    triangulation of its nodes; None for fewer than 3 nodes in a line."""
    from matplotlib.tri import Triangulation

    if cells:
        kind, conn = cells[0]
        conn = np.asarray(conn)
        if kind == "quad":
            conn = np.vstack([conn[:, [0, 1, 2]], conn[:, [0, 2, 3]]])
        if kind in ("quad", "triangle") and conn.size:
            return Triangulation(xy[:, 0], xy[:, 1], conn)
    try:
        return Triangulation(xy[:, 0], xy[:, 1])
    except (ValueError, RuntimeError):
        return None


#: Outline styles of :func:`plot_frame_tractions`: the contact zone's edge
#: (closed inside) and the stick zone's edge (stick inside, slip outside).
CONTACT_EDGE = {"colors": "white", "linewidths": 1.6, "linestyles": "solid"}
STICK_EDGE = {"colors": "#ff3030", "linewidths": 1.4, "linestyles": "dashed"}


def frame_tractions_figure(
    source: ContactResult | PairResult | FrameResult,
    *,
    cells=None,
    length_unit: str = "",
    stress_unit: str = "",
    force_unit: str = "",
    margin: float = 0.25,
):
    """The figure of :func:`plot_frame_tractions` (a matplotlib ``Figure``,
    150 dpi), e.g. to be measured or changed before saving."""
    from matplotlib.figure import Figure
    from matplotlib.lines import Line2D

    from ..contact.law import SLIP, STICK

    if isinstance(source, (ContactResult, PairResult)):
        fr = source.frame
    elif isinstance(source, FrameResult):
        fr = source
    else:
        raise ConfigError(
            "plot_frame_tractions: expected a ContactResult, PairResult or FrameResult, got "
            f"{type(source).__name__}"
        )
    xy, lx, ly = _plane_coordinates(fr.points, fr.normals)
    tri = _triangulation(xy, cells)
    closed = fr.state > 0
    p = np.where(np.isfinite(fr.pressure), fr.pressure, 0.0)
    tt = fr.tangential_traction
    q = np.linalg.norm(np.where(np.isfinite(tt), tt, 0.0), axis=1)
    peak = float(np.abs(p).max())
    panels = [(p, "contact pressure", "p")]
    if q.max() > 1e-6 * peak:  # without friction the |q| panel would be flat zero
        panels.append((q, "tangential traction", "|q|"))
    x0, x1, y0, y1 = contact_window(xy, fr.state, fr.weights, margin)
    lu, su = _suffix(length_unit), _suffix(stress_unit)
    fig = Figure(figsize=(5.2 * len(panels), 4.6), dpi=150, layout="constrained")
    axes = fig.subplots(1, len(panels), squeeze=False)[0]
    stick, slip = fr.state == STICK, fr.state == SLIP
    for ax, (values, label, symbol) in zip(axes, panels):
        if tri is not None:  # flat: one colour per triangle, the mean of its nodes
            art = ax.tripcolor(tri, values, shading="flat", cmap="viridis", vmin=0.0)
            if closed.any() and not closed.all():
                ax.tricontour(tri, closed.astype(float), levels=[0.5], **CONTACT_EDGE)
            if stick.any() and slip.any():
                ax.tricontour(tri, stick.astype(float), levels=[0.5], **STICK_EDGE)
        else:
            art = ax.scatter(xy[:, 0], xy[:, 1], c=values, s=12, cmap="viridis", vmin=0.0)
        fig.colorbar(art, ax=ax, label=symbol + su, shrink=0.9)
        ax.set_xlim(x0, x1)
        ax.set_ylim(y0, y1)
        ax.set_aspect("equal")
        ax.set_xlabel(lx + lu)
        ax.set_ylabel(ly + lu)
        ax.set_title(label)
    counts = fr.counts()
    n_closed = counts["stick"] + counts["slip"]
    if closed.any() and not closed.all():
        handles = [Line2D([], [], color=CONTACT_EDGE["colors"],
                          linewidth=CONTACT_EDGE["linewidths"],
                          label=f"contact edge: closed inside ({n_closed} nodes), "
                          f"open outside ({counts['open']})")]
    else:  # no edge to draw: say why
        handles = [Line2D([], [], linestyle="none", label=f"all {fr.state.size} nodes "
                          + ("open" if not closed.any() else "closed"))]
    if stick.any() and slip.any():
        handles.append(Line2D([], [], color=STICK_EDGE["colors"], linestyle="--",
                              linewidth=STICK_EDGE["linewidths"],
                              label=f"stick edge: stick inside ({counts['stick']}), "
                              f"slip outside ({counts['slip']})"))
    elif closed.any() and len(panels) == 2:  # (without friction every closed node slips)
        handles.append(Line2D([], [], linestyle="none",
                              label=f"all closed nodes {'stick' if stick.any() else 'slip'}"))
    fig.legend(handles=handles, loc="outside lower center", ncols=len(panels),
               facecolor="0.55", framealpha=1.0, labelcolor="white", fontsize="small",
               handlelength=2.5)
    if isinstance(source, (ContactResult, PairResult)):
        fu = f" {force_unit}" if force_unit else ""
        # below 1e-6 of the contact force: round-off of the solve, not a result
        small = source.tangential_force <= 1e-6 * float(np.linalg.norm(source.contact_force))
        tangential = "0" if small else f"{source.tangential_force:.4g}{fu}"
        which = f" {source.label}" if isinstance(source, PairResult) else ""
        fig.suptitle(f"contact frame{which}: normal force {source.normal_force:.4g}{fu}, "
                     f"tangential force {tangential}")
    return fig


def plot_frame_tractions(
    source: ContactResult | PairResult | FrameResult,
    path: str | os.PathLike,
    *,
    cells=None,
    length_unit: str = "",
    stress_unit: str = "",
    force_unit: str = "",
    margin: float = 0.25,
) -> pathlib.Path:
    """Maps of the contact pressure and of the tangential traction magnitude
    on the contact frame (the contact law's nodes), seen along the frame's
    mean normal, zoomed to the contact zone (:func:`contact_window`: the
    closed nodes plus ``margin``), with the contact zone's and the stick
    zone's edges drawn as outlines (contours of the nodes' states, with a
    legend) and units on the axes and colour bars (``""``: none).

    Each triangle is filled with one colour (flat shading: the mean of its
    nodes' values, so every colour is on the colour bar); quads are split
    into two triangles.  Without friction (|q| below 1e-6 of the peak
    pressure) the |q| map is left out.  ``cells``: the frame's elements as
    meshio-style ``[(kind, conn)]`` (``write_results`` passes them),
    otherwise a Delaunay triangulation of the nodes is drawn.  A result
    or a pair (:class:`~bemcontact.contact.results.PairResult`, one of an
    assembly's) adds its forces to the title, a pair its label too.
    Writes a PNG to ``path`` and returns it."""
    return save_png(frame_tractions_figure(
        source, cells=cells, length_unit=length_unit, stress_unit=stress_unit,
        force_unit=force_unit, margin=margin), path)


__all__ = [
    "InterfaceLine",
    "interface_line",
    "plot_interface_line",
    "plot_radial_profile",
    "plot_force_displacement",
    "plot_frame_tractions",
    "frame_tractions_figure",
    "contact_window",
    "axisymmetry",
    "AXISYMMETRIC_SCATTER",
    "save_png",
]

"""Figures of contact results (matplotlib, an optional dependency imported
inside the functions; figures are drawn off-screen with the Agg renderer and
no pyplot state is touched).

A result is given either as a :class:`~bemcontact.contact.results.ContactResult` or
as a directory written by :func:`bemcontact.output.write.write_results` (the CLI's
``--out``), from whose ``<body>_interface.csv`` files the same figure is
rebuilt.
"""

from __future__ import annotations

import json
import os
import pathlib
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from ..contact.results import ContactResult, FrameResult
from ..errors import ConfigError

Source = ContactResult | str | os.PathLike


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
    """(body name, points (n, 3), displacement (n, 3)) of both interfaces."""
    if isinstance(source, ContactResult):
        return [(i.body, i.points, i.displacement) for i in source.interfaces]
    if not isinstance(source, (str, os.PathLike)):
        raise ConfigError(
            f"expected a ContactResult or a results directory, got {type(source).__name__}"
        )
    from .read import read_csv

    d = pathlib.Path(source)
    if not d.is_dir():
        raise ConfigError(f"{os.fspath(source)}: not a results directory")
    names: list[str] = []
    summary = d / "summary.json"
    if summary.is_file():
        names = list(json.loads(summary.read_text()).get("names", []))
    if not names:
        names = sorted(p.name[: -len("_interface.csv")] for p in d.glob("*_interface.csv"))
    if not names:
        raise ConfigError(f"{os.fspath(source)}: no <body>_interface.csv files")
    out = []
    for n in names:
        f = d / f"{n}_interface.csv"
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


def plot_radial_profile(
    source: ContactResult | FrameResult,
    path: str | os.PathLike,
    *,
    pressure=None,
    traction=None,
    component: int = 0,
    center=(0.0, 0.0),
    title: str = "",
    length_unit: str = "mm",
    stress_unit: str = "MPa",
) -> pathlib.Path:
    """Contact pressure and tangential traction at the frame nodes against
    their distance r from ``center`` (in the x-y plane), with analytic curves.

    ``pressure`` and ``traction``: optional callables r -> analytic values
    (e.g. ``reference.hertz(...).pressure`` and a Cattaneo–Mindlin traction),
    drawn as lines over the plotted range.  The traction plotted is the
    ``component`` (0: x, 1: y) of the traction on body 1 (the frame's
    tangential traction acts on body 2; body 1 receives the opposite), so a
    tangential force pulling body 2 in +x shows positive.  Nodes are marked
    by state (stick, slip); open nodes beyond the contact are left out.
    Writes a PNG to ``path`` and returns it."""
    from matplotlib.figure import Figure

    from ..contact.law import SLIP, STICK

    frame = source.frame if isinstance(source, ContactResult) else source
    if not isinstance(frame, FrameResult):
        raise ConfigError(
            f"plot_radial_profile: expected a ContactResult or FrameResult, got {type(source).__name__}"
        )
    if component not in (0, 1):
        raise ConfigError(f"component must be 0 or 1 (x, y), got {component!r}")
    r = np.hypot(frame.points[:, 0] - center[0], frame.points[:, 1] - center[1])
    closed = frame.state > 0
    if not closed.any():
        raise ConfigError("plot_radial_profile: no frame node is in contact")
    rmax = 1.15 * r[closed].max()
    shown = r <= rmax
    grid = np.linspace(0.0, rmax, 400)
    q = -frame.tangential_traction[:, component]
    panels = [("pressure", frame.pressure, pressure, "$p$"),
              ("traction", q, traction, f"$q_{'xy'[component]}$ on body 1")]
    fig = Figure(figsize=(10.0, 4.0), layout="constrained")
    axes = fig.subplots(1, 2)
    for ax, (name, values, exact, label) in zip(axes, panels):
        for st, marker, lab in ((STICK, "o", "stick"), (SLIP, "^", "slip"), (0, "x", "open")):
            m = shown & (frame.state == st)
            if m.any():
                ax.plot(r[m], values[m], marker, markersize=3, linestyle="none", label=lab)
        if exact is not None:
            ax.plot(grid, np.asarray(exact(grid), dtype=float), "k-", linewidth=1.2, label="analytic")
        ax.set_xlabel(f"r ({length_unit})")
        ax.set_ylabel(f"{label} ({stress_unit})")
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


def plot_frame_tractions(
    source: ContactResult,
    path: str | os.PathLike,
    *,
    cells=None,
    length_unit: str = "",
    stress_unit: str = "",
) -> pathlib.Path:
    """Maps of the contact pressure and of the tangential traction magnitude
    on the contact frame (the contact law's nodes), seen along the frame's
    mean normal, with the nodes' states (stick ``o``, slip ``^``) marked.

    ``cells``: the frame's elements as meshio-style ``[(kind, conn)]``
    (``io`` passes them); the fields are then drawn over the elements
    (linear interpolation on their triangles), otherwise as coloured nodes.
    Writes a PNG to ``path`` and returns it."""
    from matplotlib.figure import Figure
    from matplotlib.tri import Triangulation

    from ..contact.law import SLIP, STICK

    if not isinstance(source, ContactResult):
        raise ConfigError(
            f"plot_frame_tractions: expected a ContactResult, got {type(source).__name__}"
        )
    fr = source.frame
    xy, lx, ly = _plane_coordinates(fr.points, fr.normals)
    tri = None
    if cells:
        kind, conn = cells[0]
        conn = np.asarray(conn)
        if kind == "quad":
            conn = np.vstack([conn[:, [0, 1, 2]], conn[:, [0, 2, 3]]])
        if kind in ("quad", "triangle") and conn.size:
            tri = Triangulation(xy[:, 0], xy[:, 1], conn)
    q = np.linalg.norm(fr.tangential_traction, axis=1)
    lu = f" ({length_unit})" if length_unit else ""
    su = f" ({stress_unit})" if stress_unit else ""
    fig = Figure(figsize=(10.0, 4.4), layout="constrained")
    axes = fig.subplots(1, 2)
    for ax, values, label in zip(axes, (fr.pressure, q), ("contact pressure p", "|q| tangential")):
        v = np.where(np.isfinite(values), values, 0.0)
        if tri is not None:
            art = ax.tripcolor(tri, v, shading="gouraud", cmap="viridis")
        else:
            art = ax.scatter(xy[:, 0], xy[:, 1], c=v, s=12, cmap="viridis")
        fig.colorbar(art, ax=ax, label=label + su)
        for st, marker in ((STICK, "o"), (SLIP, "^")):
            m = fr.state == st
            if m.any() and m.sum() <= 2000:
                ax.plot(xy[m, 0], xy[m, 1], marker, markersize=2.0, color="w", alpha=0.7,
                        linestyle="none", label="stick" if st == STICK else "slip")
        ax.set_aspect("equal")
        ax.set_xlabel(lx + lu)
        ax.set_ylabel(ly + lu)
        ax.set_title(label)
    counts = fr.counts()
    fig.suptitle(
        f"contact frame: normal force {source.normal_force:.6g}, tangential force "
        f"{source.tangential_force:.6g}; " + ", ".join(f"{v} {k}" for k, v in counts.items())
    )
    return save_png(fig, path)


__all__ = [
    "InterfaceLine",
    "interface_line",
    "plot_interface_line",
    "plot_radial_profile",
    "plot_force_displacement",
    "plot_frame_tractions",
    "save_png",
]

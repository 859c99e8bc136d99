"""Sizes refused before the work they would cost: a generated mesh before
gmsh meshes it (its element estimate), and a body before its frame, memory
estimate or solve is computed (what any solve of it holds at least).  A
200,000-element body on a 25 GB machine is one line in seconds, not a
minute of frame integration ending in a refusal."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..contact.memory import allowed, available_text, least_body_bytes, machine_memory
from ..mesh import MAX_ELEMENTS, SurfaceMesh
from .checks import Checker

_FIX = "raise fine_size or shrink the refined zone"


def _solid_estimate(source: str, f: dict) -> float:
    """About how many tetrahedra a generated solid has: sizes h(d) as the
    mesher's, regular tetrahedra of volume h³ / (6√2), the solid within
    distance d of the refined point taken as a half ball (2π/3 d³; a ball's
    two poles: twice) up to the whole volume.  From above, as
    :func:`~bemcontact.mesh.shapes.element_estimate`."""
    if source == "cap":
        R, H = f["radius"], f["height"]
        volume = math.pi * H * H * (3 * R - H) / 3.0
    elif source == "punch":
        volume = math.pi * f["radius"] ** 2 * f["height"]
    elif source == "ball":
        volume = 2.0 * math.pi * f["radius"] ** 3 / 3.0  # per pole
    else:
        a, b, d = (hi - lo for lo, hi in zip(f["lower"], f["upper"]))
        volume = abs(a * b * d)
    d_max = (3.0 * volume / (2.0 * math.pi)) ** (1.0 / 3.0)
    d = np.linspace(0.0, d_max, 4001)
    mid = 0.5 * (d[1:] + d[:-1])
    h = np.minimum(f["coarse_size"], f["fine_size"] + f["growth"] * np.maximum(
        0.0, mid - (f.get("fine_radius") or 0.0)))
    dV = 2.0 * math.pi * mid * mid * np.diff(d)
    return float(np.sum(dV / (h**3 / (6.0 * math.sqrt(2.0))))) * (2 if source == "ball" else 1)


def check_generated_size(c: Checker, where: str, source: str, f: dict, t: dict, *,
                         solid: bool = False) -> None:
    """Refuse, before meshing, a generated mesh with more elements than
    bemcontact accepts or than any solve of it could hold in this
    machine's memory (:func:`~bemcontact.mesh.shapes.element_estimate`;
    a cap with fine_size = 0.02 over its whole surface meshed for
    minutes); ``solid``: the solid's tetrahedra for a finite-element body
    (its sparse factor's memory: about 95 (3n)^(4/3) entries for n nodes,
    :meth:`~bemcontact.fem.FiniteElementBody.condensation_bytes`)."""
    from ..mesh.shapes import element_estimate

    if solid:
        cells = _solid_estimate(source, f)
        nodes = cells * (1.4 if f["order"] == 2 else 0.2)
        need = 8.0 * 95.0 * (3.0 * nodes) ** (4.0 / 3.0)
        _, avail = machine_memory()
        if need > allowed(avail):
            c.fail(f"{where}.fine_size", f"gives about {cells:.3g} tetrahedra ({nodes:.3g} "
                   f"nodes), whose sparse factor needs about {need / 1e9:.3g} GB, more than "
                   f"{available_text(avail)}", t["fine_size"], _FIX)
        return

    rim = 0.0
    if source == "cap":
        R, H = f["radius"], f["height"]
        area = 2.0 * math.pi * R * H + math.pi * H * max(2.0 * R - H, 0.0)
    elif source == "punch":
        r, H = f["radius"], f["height"]
        area, rim = 2.0 * math.pi * r * r + 2.0 * math.pi * r * H, r
    elif source == "ball":  # two hemispheres, each graded toward its pole
        area = 2.0 * math.pi * f["radius"] ** 2
    else:
        a, b, d = (hi - lo for lo, hi in zip(f["lower"], f["upper"]))
        area = 2.0 * abs(a * b + b * d + d * a)
    estimate = element_estimate(area, f["fine_size"], f["coarse_size"], f["growth"],
                                f.get("fine_radius") or 0.0, rim) * (2 if source == "ball" else 1)
    nodes = estimate * (2.0 if f["order"] == 2 else 0.5)
    if estimate > MAX_ELEMENTS:
        c.fail(f"{where}.fine_size", f"gives about {estimate:.3g} elements, more than the "
               f"{MAX_ELEMENTS:,} bemcontact accepts", t["fine_size"], _FIX)
    need = least_body_bytes(nodes)
    _, avail = machine_memory()
    if need > allowed(avail):
        c.fail(f"{where}.fine_size", f"gives about {estimate:.3g} elements "
               f"({nodes:.3g} nodes), whose solve needs at least {need / 1e9:.3g} GB, "
               f"more than {available_text(avail)}", t["fine_size"], _FIX)


def check_body_size(c: Checker, where: str, mesh: SurfaceMesh, value: Any) -> None:
    """Refuse a body whose every solve needs more than this machine's
    available memory (its compressed system matrix and H-LU, from its node
    count: :func:`~bemcontact.contact.memory.least_body_bytes`), before the
    frame and the full estimate are computed."""
    need = least_body_bytes(mesh.n_nodes)
    _, avail = machine_memory()
    if need > allowed(avail):
        c.fail(where, f"{mesh.n_elements:,} elements and {mesh.n_nodes:,} nodes: any solve of "
               f"this body needs at least {need / 1e9:,.3g} GB (estimated peak memory), "
               f"more than {available_text(avail)}", value,
               "use a coarser mesh or a machine with more memory")


__all__ = ["check_body_size", "check_generated_size"]

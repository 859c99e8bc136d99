"""Sizes refused before the work they would cost: a generated mesh before
gmsh meshes it (its element estimate), and a body before its frame, memory
estimate or solve is computed (what any solve of it holds at least).  A
200,000-element body on a 25 GB machine is one line in seconds, not a
minute of frame integration ending in a refusal."""

from __future__ import annotations

import math
from typing import Any

from ..contact.memory import allowed, available_text, least_body_bytes, machine_memory
from ..mesh import MAX_ELEMENTS, SurfaceMesh
from .checks import Checker

_FIX = "raise fine_size or shrink the refined zone"


def check_generated_size(c: Checker, where: str, source: str, f: dict, t: dict) -> None:
    """Refuse, before meshing, a generated mesh with more elements than
    bemcontact accepts or than any solve of it could hold in this
    machine's memory (:func:`~bemcontact.mesh.shapes.element_estimate`;
    a cap with fine_size = 0.02 over its whole surface meshed for
    minutes)."""
    from ..mesh.shapes import element_estimate

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

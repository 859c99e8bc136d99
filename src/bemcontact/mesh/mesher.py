"""gmsh meshing shared by the mesh makers (:mod:`~bemcontact.mesh.shapes`,
:mod:`~bemcontact.mesh.curved`): loading gmsh (the optional dependency),
meshing a model under a size function with Ctrl-C honoured, the checks of
the makers' arguments, and the size-by-distance functions of graded meshes
(``fine_size`` near the contact zone, growing by ``growth`` per unit
distance up to ``coarse_size``, or a ``size_profile``).
"""

from __future__ import annotations

import contextlib
import math
import os
import signal
import tempfile
import threading
from collections.abc import Callable, Iterator
from dataclasses import dataclass

import numpy as np

from ..errors import ConfigError, MeshError
from .read import read_mesh
from .surface import SurfaceMesh

#: gmsh element type codes of triangles (3- and 6-node).
_GMSH_TRIANGLES = (2, 9)


#: How to get gmsh (the ``gmsh`` extra).
GMSH_INSTALL = 'pip install "bemcontact[gmsh]"'


def load_gmsh():
    """The gmsh module; :class:`ConfigError` (one line naming the install
    command) if it is not installed or its libraries cannot be loaded."""
    try:
        import gmsh
    except ImportError:
        raise ConfigError(
            f"needs gmsh to generate this mesh, which is not installed; {GMSH_INSTALL}, or "
            "give the mesh as a file"
        ) from None
    except OSError as exc:  # the gmsh wheel's system libraries (e.g. libGLU) are missing
        raise ConfigError(
            f"needs gmsh to generate this mesh, which is installed but cannot be loaded "
            f"({exc}); install the system library it names, or give the mesh as a file"
        ) from None
    return gmsh


@dataclass(frozen=True)
class SolidMesh:
    """A solid meshed with linear tetrahedra by gmsh (for a finite-element
    body): ``nodes`` (n, 3), ``cells`` (c, 4), ``volumes`` (volume region
    name -> its cells' indices), ``regions`` (boundary region name -> a
    function of boundary faces' centroids (f, 3) choosing the region's
    faces), ``source`` (the maker's name)."""

    nodes: np.ndarray
    cells: np.ndarray
    volumes: dict
    regions: dict
    source: str


def the_rest(centroids: np.ndarray) -> np.ndarray:
    """A :class:`SolidMesh` region choice taking every face (the faces no
    earlier region took)."""
    return np.ones(len(centroids), dtype=bool)


def solid_with_gmsh(build, sizes: tuple[float, float], name: str,
                    size: Callable[[float, float, float], float], regions: dict) -> SolidMesh:
    """Mesh the volumes of the model made by ``build(gmsh)`` (geometry and
    named physical volume groups) with linear tetrahedra under the size
    function ``size`` (clamped to ``sizes``), Ctrl-C honoured as for
    :func:`mesh_with_gmsh`; ``regions``: the boundary regions (see
    :class:`SolidMesh`)."""
    gmsh = load_gmsh()
    with _interrupt_deferred() as interrupted, _model(gmsh, build, name, *sizes, size,
                                                      interrupted, 1):
        gmsh.model.mesh.generate(3)
        tags, xyz, _ = gmsh.model.mesh.getNodes()
        index = np.full(int(tags.max()) + 1, -1, dtype=np.int64)
        index[tags.astype(np.int64)] = np.arange(tags.size)
        nodes = xyz.reshape(-1, 3)
        cells, volumes = [], {}
        count = 0
        for dim, group in gmsh.model.getPhysicalGroups(3):
            label = gmsh.model.getPhysicalName(dim, group)
            mine = []
            for ent in gmsh.model.getEntitiesForPhysicalGroup(dim, group):
                etypes, _, enodes = gmsh.model.mesh.getElements(3, ent)
                for et, en in zip(etypes, enodes):
                    if int(et) != 4:  # pragma: no cover - gmsh behaviour
                        raise MeshError(f"{name}: gmsh made volume elements of type {et}")
                    mine.append(index[en.astype(np.int64)].reshape(-1, 4))
            block = np.vstack(mine)
            cells.append(block)
            volumes[label] = np.arange(count, count + len(block))
            count += len(block)
    C = np.vstack(cells)
    used = np.unique(C)
    local = np.full(nodes.shape[0], -1, dtype=np.int64)
    local[used] = np.arange(used.size)
    return SolidMesh(np.ascontiguousarray(nodes[used]), local[C], volumes, regions, name)


def mesh_with_gmsh(
    build,
    mesh_size: float | tuple[float, float],
    order: int,
    name: str,
    size: Callable[[float, float, float], float] | None = None,
) -> SurfaceMesh:
    """Mesh the surfaces of the model made by ``build(gmsh)`` (geometry,
    physical groups, mesher options) and read them back, outward oriented
    and checked.

    Without ``size`` the elements have the uniform size ``mesh_size``.  With
    ``size(x, y, z) -> float`` (a graded mesh) that function is the only
    source of element sizes and ``mesh_size`` is the pair (smallest, largest)
    of its values, to which gmsh clamps.
    """
    gmsh = load_gmsh()
    if order not in (1, 2):
        raise ConfigError(f"{name}: order must be 1 or 2, got {order!r}")
    if size is None:
        if not mesh_size > 0:
            raise ConfigError(f"{name}: mesh_size must be > 0, got {mesh_size!r}")
        smallest = largest = mesh_size
    else:
        smallest, largest = mesh_size  # validated by the caller
    with _interrupt_deferred() as interrupted:
        mesh = _generate(gmsh, build, smallest, largest, order, name, size, interrupted)
    mesh.source = name
    return mesh.oriented().check()


@contextlib.contextmanager
def _interrupt_deferred() -> Iterator[Callable[[], bool]]:
    """Ctrl-C while gmsh meshes.  Python sees the signal only in the size
    callback, where a KeyboardInterrupt raised into gmsh's C++ is ignored
    ("Exception ignored on calling ctypes callback") and the run would carry
    on for minutes.  Here the signal is only noted; the callback then answers
    the coarse size, so gmsh ends in moments, and the KeyboardInterrupt is
    raised when it has (from the main thread; elsewhere signals are not
    Python's)."""
    if threading.current_thread() is not threading.main_thread():
        yield lambda: False
        return
    caught: list[int] = []
    previous = signal.signal(signal.SIGINT, lambda signum, frame: caught.append(signum))
    try:
        yield lambda: bool(caught)
    finally:
        signal.signal(signal.SIGINT, previous)
    if caught:
        if callable(previous):
            previous(signal.SIGINT, None)  # default: raises KeyboardInterrupt
        elif previous != signal.SIG_IGN:
            raise KeyboardInterrupt


@contextlib.contextmanager
def _model(gmsh, build, name, smallest, largest, size, interrupted, order) -> Iterator[None]:
    """gmsh initialized (not interruptible: it would take SIGINT for the
    whole process), the model ``build(gmsh)`` made, its sizes and element
    order set; finalized on leaving."""
    gmsh.initialize(interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add(name)
        build(gmsh)
        gmsh.model.occ.synchronize()
        _sizes(gmsh, smallest, largest, size, interrupted)
        gmsh.option.setNumber("Mesh.ElementOrder", order)
        yield
    finally:
        gmsh.finalize()


def _generate(gmsh, build, smallest, largest, order, name, size, interrupted) -> SurfaceMesh:
    with _model(gmsh, build, name, smallest, largest, size, interrupted, order):
        gmsh.option.setNumber("Mesh.SecondOrderLinear", 0)
        gmsh.model.mesh.generate(2)
        if gmsh.option.getNumber("Mesh.RecombineAll") and _has_triangles(gmsh):
            # Blossom recombination can leave a triangle on a face whose
            # boundary has an odd number of edges; the "blossom full-quad"
            # variant gives quadrilaterals only.
            gmsh.model.mesh.clear()
            gmsh.option.setNumber("Mesh.RecombinationAlgorithm", 3)
            gmsh.model.mesh.generate(2)
            if _has_triangles(gmsh):  # pragma: no cover - gmsh behaviour
                raise MeshError(f"{name}: gmsh left triangles in a quadrilateral mesh")
        with tempfile.TemporaryDirectory() as tmp:
            path = os.path.join(tmp, f"{name}.msh")
            gmsh.write(path)
            mesh = read_mesh(path)
    return mesh


def _sizes(gmsh, smallest, largest, size, interrupted) -> None:
    """Element sizes: ``size(x, y, z)`` the only source (clamped), or uniform."""
    gmsh.option.setNumber("Mesh.MeshSizeMin", smallest)
    gmsh.option.setNumber("Mesh.MeshSizeMax", largest)
    if size is not None:
        for option in (
            "Mesh.MeshSizeExtendFromBoundary",
            "Mesh.MeshSizeFromPoints",
            "Mesh.MeshSizeFromCurvature",
        ):
            gmsh.option.setNumber(option, 0)
        gmsh.model.mesh.setSizeCallback(
            lambda dim, tag, x, y, z, lc: largest if interrupted() else float(size(x, y, z)))


def _has_triangles(gmsh) -> bool:
    return any(int(t) in _GMSH_TRIANGLES for t in gmsh.model.mesh.getElementTypes(2))


# ---------------------------------------------------------------- validation
def check_number(name: str, arg: str, value, *, allow_zero: bool = False) -> float:
    """``value`` as a float, finite and > 0 (>= 0 with ``allow_zero``)."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ConfigError(f"{name}: {arg} must be a number, got {value!r}") from None
    if not math.isfinite(v) or v < 0 or (v == 0 and not allow_zero):
        want = ">= 0" if allow_zero else "> 0"
        raise ConfigError(f"{name}: {arg} must be a finite number {want}, got {value!r}")
    return v


def check_point(name: str, arg: str, value) -> tuple[float, float, float]:
    try:
        p = tuple(float(v) for v in value)
    except (TypeError, ValueError):
        raise ConfigError(f"{name}: {arg} must be 3 numbers (x, y, z), got {value!r}") from None
    if len(p) != 3 or not all(math.isfinite(v) for v in p):
        raise ConfigError(f"{name}: {arg} must be 3 finite numbers (x, y, z), got {value!r}")
    return p  # type: ignore[return-value]


def check_axis(name: str, axis) -> int:
    if isinstance(axis, bool) or axis not in (1, -1):
        raise ConfigError(
            f"{name}: axis must be +1 or -1 (the direction along z from the contact "
            f"face into the body), got {axis!r}"
        )
    return int(axis)


def check_grading(name: str, fine_size, coarse_size, growth) -> tuple[float, float, float]:
    fine = check_number(name, "fine_size", fine_size)
    coarse = check_number(name, "coarse_size", coarse_size)
    if fine > coarse:
        raise ConfigError(
            f"{name}: fine_size = {fine_size!r} must not exceed coarse_size = {coarse_size!r}"
        )
    return fine, coarse, check_number(name, "growth", growth)


def expect_regions(mesh: SurfaceMesh, names: set[str], name: str) -> SurfaceMesh:
    if set(mesh.region_names) != names:  # pragma: no cover - gmsh behaviour
        raise MeshError(f"{name}: unexpected regions {mesh.region_names}, expected {sorted(names)}")
    return mesh



# ------------------------------------------------------------- graded meshes
def size_ramp(fine: float, coarse: float, growth: float, start: float) -> Callable[[float], float]:
    """Element size at distance d: ``fine`` up to ``start``, then growing by
    ``growth`` per unit distance, capped at ``coarse``."""
    return lambda d: min(coarse, fine + growth * max(0.0, d - start))


def element_estimate(area: float, fine_size: float, coarse_size: float, growth: float,
                     fine_radius: float = 0.0, rim: float = 0.0) -> float:
    """About how many triangles a mesh graded by the distance d from a point
    (or, with ``rim`` > 0, from a circle of that radius) has on a surface of
    ``area``, before meshing: sizes h(d) as the mesher's (``fine_size`` up to
    ``fine_radius``, then growing by ``growth`` per unit distance up to
    ``coarse_size``), triangles of area (√3/4) h², and the surface within
    distance d taken as 2πd² + 4π rim d (twice a flat disc, or a band on both
    sides of the rim) up to the whole ``area``.  An estimate from above (the
    refined zone is counted as large as it can be), to refuse a mesh no solve
    could hold before the mesher spends minutes on it."""
    a4 = 4.0 * math.pi * rim
    d_max = (-a4 + math.sqrt(a4 * a4 + 8.0 * math.pi * area)) / (4.0 * math.pi)
    d = np.linspace(0.0, d_max, 4001)
    mid = 0.5 * (d[1:] + d[:-1])
    h = np.minimum(coarse_size, fine_size + growth * np.maximum(0.0, mid - fine_radius))
    dA = (4.0 * math.pi * mid + a4) * np.diff(d)
    return float(np.sum(dA / (math.sqrt(3.0) / 4.0 * h * h)))


def _size_profile(name: str, knots, fine: float, coarse: float) -> list[tuple[float, float]]:
    """Checked ``size_profile`` knots: (distance, size) pairs, distances
    starting at 0 and strictly increasing, sizes within [fine, coarse]."""
    try:
        pts = [(float(d), float(h)) for d, h in knots]
    except (TypeError, ValueError):
        raise ConfigError(
            f"{name}: size_profile must be (distance, size) pairs, got {knots!r}"
        ) from None
    if not pts or pts[0][0] != 0.0:
        raise ConfigError(f"{name}: size_profile must start at distance 0, got {knots!r}")
    for (d0, _), (d1, _) in zip(pts, pts[1:]):
        if not d1 > d0:
            raise ConfigError(
                f"{name}: size_profile distances must increase strictly, got {d0!r} then {d1!r}"
            )
    for d, h in pts:
        if not (math.isfinite(d) and math.isfinite(h) and fine <= h <= coarse):
            raise ConfigError(
                f"{name}: size_profile size {h!r} at distance {d!r} must lie between "
                f"fine_size = {fine!r} and coarse_size = {coarse!r}"
            )
    return pts


def _profile_ramp(knots, coarse: float, growth: float) -> Callable[[float], float]:
    """Element size at distance d: linear between the knots, then growing by
    ``growth`` per unit distance from the last one, capped at ``coarse``."""
    ds = [d for d, _ in knots]
    hs = [h for _, h in knots]
    last_d, last_h = ds[-1], hs[-1]

    def size(d: float) -> float:
        if d >= last_d:
            return min(coarse, last_h + growth * (d - last_d))
        return float(np.interp(d, ds, hs))

    return size


def around(ramp: Callable[[float], float], point) -> Callable[[float, float, float], float]:
    """The size function of a mesh graded by the distance from ``point``
    (``ramp``: size against distance), as :func:`mesh_with_gmsh` takes it."""
    px, py, pz = point
    return lambda x, y, z: ramp(math.sqrt((x - px) ** 2 + (y - py) ** 2 + (z - pz) ** 2))


def grading_ramp(name, fine, coarse, growth, fine_radius, size_profile):
    """The size-by-distance function of a graded mesh: the uniform fine zone
    of radius ``fine_radius``, or the knots of ``size_profile``."""
    if (fine_radius is None) == (size_profile is None):
        raise ConfigError(f"{name}: give exactly one of fine_radius and size_profile")
    if size_profile is None:
        return size_ramp(fine, coarse, growth, check_number(name, "fine_radius", fine_radius, allow_zero=True))
    return _profile_ramp(_size_profile(name, size_profile, fine, coarse), coarse, growth)


__all__ = [
    "GMSH_INSTALL", "around", "check_axis", "check_grading", "check_number", "check_point",
    "element_estimate", "expect_regions", "grading_ramp", "load_gmsh", "mesh_with_gmsh", "size_ramp",
    "SolidMesh", "solid_with_gmsh", "the_rest",
]

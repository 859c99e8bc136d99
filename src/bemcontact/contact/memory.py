"""Peak-memory estimate of a contact solve, from the sizes alone (before
anything large is allocated): used by ``bemcontact check`` and by
:meth:`~bemcontact.contact.ContactProblem.solve`, which refuses a solve that
cannot fit in the machine's memory, or in what a limit on the process (a
control group's, ``ulimit -v``: :func:`process_limits`) leaves of it.

The model follows the arrays the solve holds (8-byte doubles; N_a body
nodes, n_a contact nodes, m active frame nodes, S load states):

* the frame build (:class:`~bemcontact.contact.ContactFrame`), from the sizes
  known before it (E_a elements of the contact surfaces, k nodes per element,
  f frame element corners, q = order^2 quadrature points per fan triangle):
  arrays per quadrature point of every clipped element pair (points, local
  coordinates, metrics, the bases) and the entries of D, of the frame mass
  and their sparse assembly, :data:`FRAME_POINT` + :data:`FRAME_ENTRY` f k
  bytes per point, at :data:`FRAME_FAN` (sqrt(E_1) + sqrt(E_2))^2 fan
  triangles (the clipped pairs of two meshes over one area; measured on
  box pairs in general position and Hertz's sphere on a block, below);

* condensation of body a: its system matrix (3N_a + 6)^2 (dense, LU in place;
  compressed: the H-matrix and its H-LU, each the measured fraction of the
  dense matrix at that size, docs/benchmarks.md), the dense G columns of the
  contact dofs 3N_a x 3n_a, the right-hand-side block 3N_a x (S + 3m + controls)
  solved in place and kept as the response X_a, the dense Cholesky factor of
  the contact mass (n_a <= 6,000) and the blocks of :meth:`TractionModes.right`;
  the responses of the bodies condensed before it stay;
* Newton: the interface flexibility K (3m)^2, every body's response, the
  closed nodes' matrix with its kept LU and the copy of K's rows it is built
  from (3 x (3m)^2 when every node is closed), and the predictor's coarse
  flexibilities (clusters of 4 nodes: (3m)^2 (1/16 + 1/256 + ...) = (3m)^2/15);
* the process itself (its resident memory when the estimate is made).

Measured against the peak resident memory (docs/benchmarks.md): within the
tolerance the tests and benchmarks record.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np

from ..errors import ConfigError, ResourceLimitWarning
from ..mesh.element import CORNERS
from ..bem.compressed import compressed_fraction
from .modes import CHUNK, DENSE_MASS

_DOUBLE = 8.0

#: Frame build: bytes per quadrature point, fixed and per (frame corner x
#: element node) entry, fitted to tracemalloc peaks of ContactFrame (bytes
#: per point: quad4 1,213, tri3 872, quad8 1,985, tri6 1,335; the fit
#: gives 1,218, 882, 1,986, 1,314), and fan triangles per
#: (sqrt(E_1) + sqrt(E_2))^2: box pairs 21 x 21 on 16 x 16 quad4 1.89,
#: 80 x 80 on 61 x 61 quad4 1.97, 41 x 41 on 30 x 30 tri3 1.89, 21 on 16
#: tri6 1.82 (commensurate grids 1.3-1.5; sphere on block h = 0.1, 0.07:
#: 1.04, 1.31, the cap only partly facing the block).  Measured peak over
#: the estimate: box pairs in general position 0.93-0.98 (quad4 21/16
#: 113.1 of 120.1 MB, 80/61 1,710 of 1,744 MB; tri3 41/30 599 of 640 MB),
#: commensurate grids 0.73, sphere_on_block at fine_size 0.1, 0.07, 0.05
#: 0.52, 0.65, 0.76 (172 of 333, 319 of 491, 565 of 746 MB).
FRAME_POINT = 450.0
FRAME_ENTRY = 48.0
FRAME_FAN = 2.0


def least_body_bytes(nodes: float) -> float:
    """Bytes that any solve of a body of ``nodes`` nodes holds at least: its
    compressed system matrix and H-LU factors (the measured compressed
    fraction of the dense matrix at that size, the largest size's beyond).
    Used before meshing, from an element estimate."""
    n3 = 3.0 * float(nodes)
    return _DOUBLE * 2.0 * compressed_fraction(int(nodes)) * n3 * n3


def _statm() -> tuple[float, float]:
    """(mapped, resident) bytes of this process ((0, 0) where /proc is
    unavailable)."""
    try:
        import os

        page = float(os.sysconf("SC_PAGE_SIZE"))
        with open("/proc/self/statm") as f:
            size, resident = f.read().split()[:2]
        return float(size) * page, float(resident) * page
    except (OSError, ValueError, AttributeError):
        return 0.0, 0.0


def resident_bytes() -> float:
    """This process's resident memory now (0 where /proc is unavailable)."""
    return _statm()[1]


def _meminfo() -> tuple[float, float]:
    """(MemTotal, MemAvailable) bytes from /proc/meminfo ((inf, inf) where
    it cannot be read)."""
    try:
        info = {}
        with open("/proc/meminfo") as f:
            for line in f:
                key, _, rest = line.partition(":")
                info[key] = float(rest.split()[0]) * 1024.0
        return info["MemTotal"], info.get("MemAvailable", info["MemTotal"])
    except (OSError, KeyError, ValueError, IndexError):
        return float("inf"), float("inf")


def _read_number(path: str) -> float | None:
    try:
        with open(path) as f:
            text = f.read().strip()
        return None if text == "max" else float(text)
    except (OSError, ValueError):
        return None


def _inactive_file(path: str, key: str) -> float:
    """Reclaimable page cache of a control group (its memory.stat's ``key``)."""
    try:
        with open(path) as f:
            for line in f:
                name, _, value = line.partition(" ")
                if name == key:
                    return float(value)
    except (OSError, ValueError):
        pass
    return 0.0


def _cgroup_dirs() -> list[tuple[str, str]]:
    """(directory, version) of this process's memory control group: v2
    (the unified hierarchy's path in /proc/self/cgroup, or its root) and v1
    (the memory controller's path, or its root)."""
    dirs = []
    try:
        with open("/proc/self/cgroup") as f:
            for line in f:
                _, controllers, path = line.rstrip("\n").split(":", 2)
                if controllers == "":
                    dirs.append((f"/sys/fs/cgroup{path.rstrip('/')}", "v2"))
                elif "memory" in controllers.split(","):
                    dirs.append((f"/sys/fs/cgroup/memory{path.rstrip('/')}", "v1"))
    except (OSError, ValueError):
        pass
    return dirs + [("/sys/fs/cgroup", "v2"), ("/sys/fs/cgroup/memory", "v1")]


#: A solve is refused when its estimated peak exceeds the available memory
#: by more than this factor, the estimate's uncertainty (measured peaks
#: within -8 % to +11 % of it, docs/benchmarks.md); it is warned about
#: from 0.9 of it.
MARGIN = 1.25


class Limit(NamedTuple):
    """A limit on this process's memory (:func:`process_limits`)."""

    room: float
    what: str
    kind: str  # "address space" or "control group"


def process_limits(total: float) -> list[Limit]:
    """The limits on this process's memory below the machine's ``total``,
    each as a :class:`Limit`: the room is what the solve's peak (this process's
    resident memory included, as :class:`MemoryEstimate` counts it) may
    reach under the limit, and ``what`` names the limit.  Read: the
    address-space limit (``ulimit -v``, RLIMIT_AS: its room is the limit
    less the address space mapped but not resident) and the control group's
    memory limit (cgroup v2 ``memory.max`` or v1 ``memory.limit_in_bytes``,
    as on a batch scheduler's or a container's share of a node: the limit
    less what the group uses besides this process and its reclaimable page
    cache)."""
    limits = []
    size, resident = _statm()
    try:
        import resource

        soft = resource.getrlimit(resource.RLIMIT_AS)[0]
        unlimited = soft == resource.RLIM_INFINITY
    except (ImportError, AttributeError, OSError, ValueError):  # not a Unix: no such limit
        soft, unlimited = 0, True
    if not unlimited and size and soft < total:
        limits.append(Limit(max(float(soft) - size + resident, 0.0),
                            f"this process's address-space limit (ulimit -v) of "
                            f"{soft / 1e9:.1f} GB", "address space"))
    for folder, version in _cgroup_dirs():
        if version == "v2":
            limit = _read_number(f"{folder}/memory.max")
            used = _read_number(f"{folder}/memory.current")
            cache = _inactive_file(f"{folder}/memory.stat", "inactive_file")
        else:
            limit = _read_number(f"{folder}/memory.limit_in_bytes")
            used = _read_number(f"{folder}/memory.usage_in_bytes")
            cache = _inactive_file(f"{folder}/memory.stat", "total_inactive_file")
        if limit is not None and used is not None and limit < total:
            limits.append(Limit(max(limit - used + cache + resident, 0.0),
                                f"its control group's memory limit of {limit / 1e9:.1f} GB",
                                "control group"))
            break
    return limits


def machine_memory() -> tuple[float, float]:
    """(total, available) bytes: the physical memory (/proc/meminfo), and
    what a solve may use, the machine's available memory or less under a
    limit on this process (:func:`process_limits`); (inf, inf) where none of
    it can be read."""
    total, available = _meminfo()
    rooms = [limit.room for limit in process_limits(total)]
    return total, min([available] + rooms)


def binding_limit(available: float) -> Limit | None:
    """The limit on this process (:func:`process_limits`) that gives
    :func:`machine_memory`'s ``available``, or None when the machine's
    available memory does."""
    total, free = _meminfo()
    for limit in process_limits(total):
        if limit.room < free and abs(limit.room - available) <= 0.05 * max(available, 1.0):
            return limit
    return None


def allowed(available: float) -> float:
    """The largest estimated peak a solve may have with ``available`` bytes
    (:func:`machine_memory`'s): :data:`MARGIN` times them, or the bytes
    themselves under an address-space limit (``ulimit -v``), where going
    over it does not end in a MemoryError: the BLAS library retries a
    failed mapping of its work buffers forever (OpenBLAS 0.3.30, SciPy's:
    a solve hung in ``splu``) and the OpenMP runtime exits when it cannot
    create a thread (both measured)."""
    limit = binding_limit(available)
    if limit is not None and limit.kind == "address space":
        return available
    return MARGIN * available


def _amount(size: float) -> str:
    """Bytes for a message: GB to one decimal from 0.1 GB, MB below."""
    return f"{size / 1e9:.1f} GB" if size >= 1e8 else f"{size / 1e6:.3g} MB"


def available_text(available: float) -> str:
    """``available`` bytes (:func:`machine_memory`'s) in words for a
    message: "this machine's 12.5 GB of available memory", or, when a limit
    on this process gives that figure, "the 1.2 GB that this process's
    address-space limit (ulimit -v) of 3.0 GB leaves"."""
    limit = binding_limit(available)
    if limit is not None:
        return f"the {_amount(available)} that {limit.what} leaves"
    return f"this machine's {_amount(available)} of available memory"


def frame_bytes(elements, element_nodes: int, corners: int, order: int = 6) -> float:
    """Peak bytes of the frame build for contact surfaces of ``elements``
    (E_1, E_2) elements with at most ``element_nodes`` nodes and ``corners``
    corners each, at quadrature ``order`` (the frame's, 6): FRAME_FAN
    (sqrt(E_1) + sqrt(E_2))^2 order^2 points of FRAME_POINT + FRAME_ENTRY
    corners element_nodes bytes."""
    e1, e2 = (float(e) for e in elements)
    points = FRAME_FAN * (np.sqrt(e1) + np.sqrt(e2)) ** 2 * order * order
    return float(points * (FRAME_POINT + FRAME_ENTRY * corners * element_nodes))


@dataclass
class MemoryEstimate:
    """Bytes at the peaks of the solve's phases; ``peak`` is the largest,
    process included.  ``phases``: name -> bytes (``frame``,
    ``condensation of <body>``, ``newton``); ``process``: the resident
    memory when estimated."""

    phases: dict = field(default_factory=dict)
    process: float = 0.0

    @property
    def peak(self) -> float:
        return self.process + max(self.phases.values(), default=0.0)

    def text(self) -> str:
        worst = max(self.phases, key=self.phases.get) if self.phases else "-"
        return f"{self.peak / 1e9:.2f} GB (at the {worst})"


def estimate(bodies, nodes, m: int, states: int, controls, linear,
             frame: float = 0.0) -> MemoryEstimate:
    """The estimate for ``bodies`` (each a
    :class:`~bemcontact.contact.flexibility.Body`: its ``condensation_bytes``),
    ``nodes`` their contact node counts, ``m`` active frame nodes, ``states``
    load states, ``controls`` the force-controlled components per body,
    ``linear`` the condensation's
    :class:`~bemcontact.linalg.LinearSolverOptions` and ``frame`` the frame
    build's bytes (:func:`frame_bytes`)."""
    out = MemoryEstimate(process=resident_bytes())
    out.phases["frame"] = float(frame)
    kept = 0.0
    m3 = 3 * m
    for body, nc, ctl in zip(bodies, nodes, controls):
        # the body's own (its condensation_bytes), and the modes' mass
        # factor of its contact surface
        peak, response = body.condensation_bytes(int(nc), m3, states, ctl, linear, CHUNK)
        chol = float(nc) ** 2 if nc <= DENSE_MASS else 0.0
        out.phases[f"condensation of {body.name}"] = peak + _DOUBLE * chol + kept
        kept += response
    out.phases["newton"] = _DOUBLE * (4.0 + 1.0 / 15.0) * float(m3 + 12) ** 2 + kept
    return out


def frames_peak(meshes, pairs, links) -> float:
    """Peak bytes of the frame builds of ``pairs`` (the largest pair's),
    from the contact surfaces' element counts alone (:func:`frame_bytes`);
    ``meshes`` the bodies' surface meshes, ``links[p]`` pair p's body
    indices."""
    peak = 0.0
    for p, link in zip(pairs, links):
        counts, k, corners = [], 0, 0
        for a, s in zip(link, (p.surface1, p.surface2)):
            m = meshes[a]
            counts.append(int(np.count_nonzero(m.element_region == m.region_names.index(s))))
            k, corners = max(k, m.elements.shape[1]), max(corners, CORNERS[m.element_type])
        peak = max(peak, frame_bytes(counts, k, corners))
    return peak


def guard(est: MemoryEstimate, fix: str, warn: bool = False) -> None:
    """Refuse (ConfigError, one line naming ``fix``) what ``est`` says
    exceeds the available memory by more than the estimate's uncertainty;
    with ``warn``, a ResourceLimitWarning when it comes within 90 %."""
    available = machine_memory()[1]
    if est.peak > allowed(available):
        raise ConfigError(
            f"the solve needs about {est.text()}, more than {available_text(available)}; "
            f"use {fix}"
        )
    if warn and est.peak > 0.9 * available:
        warnings.warn(
            f"the solve needs about {est.text()}, close to {available_text(available)}",
            ResourceLimitWarning,
            stacklevel=4,
        )


__all__ = [
    "MARGIN", "frames_peak", "guard", "Limit", "MemoryEstimate", "allowed", "available_text", "binding_limit", "estimate",
    "frame_bytes", "least_body_bytes", "machine_memory", "process_limits", "resident_bytes",
]

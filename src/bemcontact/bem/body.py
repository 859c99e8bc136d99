"""An elastic body: a closed surface mesh, a material and boundary conditions
(:mod:`.conditions`, with the conventions for signs and units), and the mixed
boundary value problem of one body, solved by the bordered solve of
:mod:`bemcontact.linalg.bordered` (dense LU, or compressed operators and GMRES).
"""


from __future__ import annotations

import copy
import hashlib
import time
from collections.abc import Mapping, Sequence

import numpy as np

from ..errors import ConfigError
from ..linalg.bordered import solve_bordered
from .compressed import CompressedSystem, compressed_fraction
from ..linalg.options import LinearSolverOptions
from ..linalg.threads import blas_threads
from ..mesh import SurfaceMesh
from .conditions import (
    BoundaryCondition, Control, Displacement, Force, Pressure, CONDITION_KINDS,
)
from .discretization import Discretization, DiscretizationOptions, discretize
from .material import LinearElastic
from .solution import BodySolution
from .operators import QuadratureOptions, assemble_influence, assemble_system


class ElasticBody:
    """A homogeneous linear elastic body bounded by a closed surface.

    Parameters
    ----------
    mesh:
        Closed, outward-oriented :class:`~bemcontact.mesh.SurfaceMesh`
        (checked with :meth:`SurfaceMesh.check`).
    material:
        :class:`~bemcontact.bem.material.LinearElastic`.
    boundary_conditions:
        Region name -> a boundary condition or a list of them (at most one
        prescription per component).  Regions not listed are traction free.
    quadrature, discretization:
        Integration and node-layout options.
    name:
        Used in messages.
    """

    def __init__(
        self,
        mesh: SurfaceMesh,
        material: LinearElastic,
        boundary_conditions: Mapping[str, BoundaryCondition | Sequence[BoundaryCondition]]
        | None = None,
        *,
        quadrature: QuadratureOptions | None = None,
        discretization: DiscretizationOptions | None = None,
        name: str = "body",
    ) -> None:
        if not isinstance(mesh, SurfaceMesh):
            raise ConfigError(f"{name}: mesh must be a SurfaceMesh, got {type(mesh).__name__}")
        if not isinstance(material, LinearElastic):
            raise ConfigError(
                f"{name}: material must be a LinearElastic, got {type(material).__name__}"
            )
        self.name = name
        self.mesh = mesh.check()
        self.material = material
        self.quadrature = quadrature or QuadratureOptions()
        self.discretization_options = discretization or DiscretizationOptions()
        self.boundary_conditions = self.checked_conditions(boundary_conditions or {})
        self._disc: Discretization | None = None

    def checked_conditions(
        self, conditions: Mapping[str, BoundaryCondition | Sequence[BoundaryCondition]],
        where: str = "",
    ) -> dict[str, tuple[BoundaryCondition, ...]]:
        """Validate a region -> condition(s) mapping for this body (known
        regions, known kinds, one prescription per component)."""
        name = f"{where}{self.name}"
        mesh = self.mesh
        if not isinstance(conditions, Mapping):
            raise ConfigError(
                f"{name}: boundary conditions must be a mapping region -> condition(s), got "
                f"{type(conditions).__name__}"
            )
        out: dict[str, tuple[BoundaryCondition, ...]] = {}
        for region, bcs in conditions.items():
            if region not in mesh.region_names:
                raise ConfigError(
                    f"{name}: boundary condition on unknown region {region!r}; the mesh has "
                    f"regions {list(mesh.region_names)}"
                )
            items = tuple(bcs) if isinstance(bcs, (list, tuple)) else (bcs,)
            taken: dict[int, str] = {}
            for bc in items:
                if not isinstance(bc, CONDITION_KINDS):
                    raise ConfigError(
                        f"{name}: region {region!r}: {bc!r} is not a Displacement, Traction, "
                        "Pressure or Force"
                    )
                for c in self._components(bc):
                    kind = type(bc).__name__
                    if c in taken:
                        raise ConfigError(
                            f"{name}: region {region!r}: component {'xyz'[c]} is prescribed "
                            f"twice ({taken[c]} and {kind}); give each component one condition"
                        )
                    taken[c] = kind
            out[region] = items
        return out

    @staticmethod
    def _components(bc: BoundaryCondition) -> list[int]:
        if isinstance(bc, Pressure):
            return [0, 1, 2]
        if callable(bc.value):
            return [0, 1, 2]
        return [c for c in range(3) if bc.value[c] is not None]

    @property
    def discretization(self) -> Discretization:
        if self._disc is None:
            self._disc = discretize(self.mesh, self.discretization_options)
        return self._disc

    # -- what the contact solver asks of a body (bemcontact.contact.flexibility.Body)
    @property
    def trace(self) -> Discretization:
        """The body's surface with its functional nodes (for the contact
        frame): the BEM discretization itself."""
        return self.discretization

    @property
    def region_names(self) -> tuple[str, ...]:
        return self.mesh.region_names

    @property
    def contact_compliance(self) -> float:
        """(1 - nu^2) / E: the body's share of 1/E* (the contact modulus)."""
        return (1 - self.material.poisson_ratio**2) / self.material.youngs_modulus

    def condense(self, nodes: np.ndarray, threads: int | None = None, states=None,
                 progress=None, linear: LinearSolverOptions | None = None, modes=None, *,
                 load_fields: np.ndarray | None = None):
        """This body's flexibility on its contact ``nodes``
        (:func:`~bemcontact.bem.condensation.condense`)."""
        from .condensation import condense

        return condense(self, nodes, threads, states, progress, linear, modes,
                        load_fields=load_fields)

    def translated(self, origin: np.ndarray) -> ElasticBody:
        """A copy whose mesh is translated by ``-origin`` (the mesh checks
        hold as they are; the conditions are the caller's to translate)."""
        m = self.mesh
        c = copy.copy(self)
        c.mesh = SurfaceMesh(m.nodes - origin, m.elements, m.element_type, m.regions,
                             source=m.source)
        c._disc = None
        return c

    def same_model(self, other) -> bool:
        """Whether ``other`` is the same elastic model (name and
        :meth:`model_key`: mesh, material, quadrature and discretization
        options): its condensation can be reused for this body."""
        return (isinstance(other, ElasticBody) and self.name == other.name
                and self.model_key() == other.model_key())

    def boundary_data(
        self, conditions: Mapping[str, tuple[BoundaryCondition, ...]] | None = None
    ) -> tuple[np.ndarray, np.ndarray]:
        """(known_u (3N,) bool, values (3N,)): per dof, whether the displacement
        is prescribed, and the prescribed displacement or traction, for this
        body's conditions or the (checked) ``conditions`` given.  Force-
        controlled dofs count as known displacement with value 0 here (their
        common translation is added by the solvers, see :meth:`controls`)."""
        d = self.discretization
        N = d.n_points
        known_u = np.zeros((N, 3), dtype=bool)
        values = np.zeros((N, 3))
        conditions = self.boundary_conditions if conditions is None else conditions
        for region, items in conditions.items():
            idx = np.flatnonzero(d.region == self.mesh.region_names.index(region))
            X, n = d.points[idx], d.normals[idx]
            for bc in items:
                if isinstance(bc, Force):
                    for c in self._components(bc):
                        known_u[idx, c] = True
                        values[idx, c] = 0.0
                    continue
                if isinstance(bc, Pressure):
                    values[idx] = -bc.pressure * n
                    continue
                if callable(bc.value):
                    args = (X,) if isinstance(bc, Displacement) else (X, n)
                    try:
                        v = np.asarray(bc.value(*args), dtype=float)
                    except Exception as exc:
                        raise ConfigError(
                            f"{self.name}: region {region!r}: the {type(bc).__name__} callable "
                            f"failed: {type(exc).__name__}: {exc}"
                        ) from exc
                    if v.shape != (idx.size, 3):
                        raise ConfigError(
                            f"{self.name}: region {region!r}: the {type(bc).__name__} callable "
                            f"returned shape {v.shape}, expected {(idx.size, 3)}"
                        )
                    mask = ~np.isnan(v)
                    if np.isinf(v).any():
                        raise ConfigError(
                            f"{self.name}: region {region!r}: the {type(bc).__name__} callable "
                            "returned infinite values"
                        )
                else:
                    v = np.array([np.nan if c is None else c for c in bc.value])[None, :].repeat(
                        idx.size, 0
                    )
                    mask = ~np.isnan(v)
                sub_known = known_u[idx]
                sub_vals = values[idx]
                sub_vals[mask] = v[mask]
                if isinstance(bc, Displacement):
                    sub_known[mask] = True
                known_u[idx] = sub_known
                values[idx] = sub_vals
        return known_u.ravel(), values.ravel()

    def controls(
        self, conditions: Mapping[str, tuple[BoundaryCondition, ...]] | None = None
    ) -> list[Control]:
        """The force-controlled components, in region order then x, y, z."""
        d = self.discretization
        conditions = self.boundary_conditions if conditions is None else conditions
        out = []
        for region, items in conditions.items():
            idx = np.flatnonzero(d.region == self.mesh.region_names.index(region))
            for bc in items:
                if isinstance(bc, Force):
                    for c in self._components(bc):
                        out.append(Control(region, c, 3 * idx + c, float(bc.value[c])))
        return out

    def control_indicators(self, controls: Sequence[Control]) -> np.ndarray:
        """(3N, k): a unit translation of each controlled component (its
        dofs set to 1).  B of the mixed system maps it to minus the column of
        the platen's translation, -H E."""
        E = np.zeros((3 * self.discretization.n_points, len(controls)))
        for k, c in enumerate(controls):
            E[c.dofs, k] = 1.0
        return E

    def control_rows(self, controls: Sequence[Control]) -> np.ndarray:
        """(k, 3N): the resultant of the (unknown) tractions on each
        controlled component, ∫ t_c dS = sum_p w_p t_pc."""
        w = self.discretization.weights
        R = np.zeros((len(controls), 3 * self.discretization.n_points))
        for i, c in enumerate(controls):
            R[i, c.dofs] = w[c.dofs // 3]
        return R

    def assemble(self, threads: int | None = None) -> tuple[np.ndarray, np.ndarray]:
        """Influence matrices (H, G) of this body (see
        :func:`~bemcontact.bem.operators.assemble_influence`)."""
        m = self.material
        return assemble_influence(
            self.discretization, m.shear_modulus, m.poisson_ratio, self.quadrature, threads
        )

    def condensation_bytes(self, contact_nodes: int, modes: int, states: int, controls: int,
                           linear: LinearSolverOptions, chunk: int) -> tuple[float, float]:
        """(peak, kept) bytes of condensing this body on ``modes`` traction
        modes of ``contact_nodes`` nodes for ``states`` load states and
        ``controls`` platen translations, the right-hand sides formed in
        blocks of ``chunk`` columns: its system (dense, or the measured
        compressed fraction with the H-LU's factors), G's contact columns,
        the responses (kept afterwards) and the blocks."""
        N = self.discretization.n_points
        N3, n3 = 3 * N, 3 * contact_nodes
        if linear.use_hmatrix(N):
            system = 2.0 * compressed_fraction(N) * N3 * N3
        else:
            system = float(N3 + 6) ** 2
        response = float(N3) * (states + modes + controls)
        blocks = 2.0 * n3 * min(chunk, N3) + float(min(chunk, N3)) * modes
        return 8.0 * (system + float(N3) * n3 + response + blocks), 8.0 * response

    def condition_kinds(self, conditions=None) -> np.ndarray:
        """(3N,) int8 per dof of the trace: 0 traction (or free), 1
        displacement, 2 force (a platen's translation)."""
        known_u, _ = self.boundary_data(conditions)
        k = known_u.astype(np.int8)
        for c in self.controls(conditions):
            k[c.dofs] = 2
        return k

    def load_values(self, conditions=None) -> np.ndarray:
        """(3N,) the prescribed displacement or traction per dof of the trace
        (0 on force-controlled dofs)."""
        return self.boundary_data(conditions)[1]

    def model_key(self) -> str:
        """A hex SHA-256 of what this body's responses depend on besides its
        conditions: mesh, material, quadrature and discretization options."""
        h = hashlib.sha256()
        m = self.mesh
        for part in (m.nodes, m.elements, m.element_region):
            a = np.ascontiguousarray(part)
            h.update(f"{a.dtype.str}{a.shape}".encode())
            h.update(a.tobytes())
        h.update(repr((m.element_type, tuple(m.region_names), self.material, self.quadrature,
                       self.discretization_options)).encode())
        return h.hexdigest()

    def stresses(self, solution: BodySolution, points) -> np.ndarray:
        """Stresses (n, 6) at interior ``points`` (n, 3) of this body with
        the boundary ``solution`` (:func:`~bemcontact.bem.interior.interior_stresses`)."""
        from .interior import interior_stresses

        return interior_stresses(solution, points, self.material)

    def surface_stresses(self, solution: BodySolution) -> np.ndarray:
        """Stresses (N, 6) at the functional nodes of this body's boundary
        ``solution`` (:func:`~bemcontact.bem.surface_stress.surface_stresses`)."""
        from .surface_stress import surface_stresses

        return surface_stresses(solution, self.material)

    def mixed_system(self, known_u: np.ndarray, W: np.ndarray,
                     linear: LinearSolverOptions, threads: int | None, border: int,
                     dofs: np.ndarray | None = None):
        """The mixed system of this body, the one assembly path of its solves
        (:meth:`solve`, :func:`~bemcontact.bem.condensation.condense`):
        ``(A, B W, G[:, dofs], compressed)`` for the prescribed-displacement
        dofs ``known_u``, the boundary-value columns ``W``; dense (A in
        place, with room for ``border`` bordering columns) or compressed
        (:class:`~bemcontact.bem.compressed.CompressedSystem`) as ``linear``
        chooses for the body's size; G's columns only with ``dofs``."""
        d, m = self.discretization, self.material
        if linear.use_hmatrix(d.n_points):
            A = CompressedSystem(d, m.shear_modulus, m.poisson_ratio, known_u, W,
                                 self.quadrature, linear.hmatrix, threads)
            return A, A.BW, None if dofs is None else A.g_columns(dofs), True
        A, BW, Gc = assemble_system(d, m.shear_modulus, m.poisson_ratio, known_u, W, dofs,
                                    self.quadrature, threads, border=border)
        return A, BW, Gc, False

    def rigid_modes(self) -> np.ndarray:
        """(3N, 6) rigid-body displacement modes at the functional nodes:
        translations x, y, z, then rotations about x, y, z through the
        weighted centroid."""
        d = self.discretization
        N = d.n_points
        c = d.weights @ d.points / d.weights.sum()
        x = d.points - c
        R = np.zeros((N, 3, 6))
        for j in range(3):
            R[:, j, j] = 1.0
            e = np.zeros(3)
            e[j] = 1.0
            R[:, :, 3 + j] = np.cross(e, x)
        return R.reshape(3 * N, 6)

    def solve(
        self, threads: int | None = None, linear: LinearSolverOptions | None = None
    ) -> BodySolution:
        """Assemble and solve the mixed boundary value problem.

        ``linear`` chooses dense LAPACK LU or H-matrix operators with GMRES
        (:class:`~bemcontact.linalg.LinearSolverOptions`; default "auto":
        dense for small bodies).  A body with no prescribed displacement is
        determined up to a rigid motion; its tractions must then be
        self-equilibrated, and the solution with zero weighted mean
        translation and rotation is returned.
        """
        linear = linear or LinearSolverOptions()
        if not isinstance(linear, LinearSolverOptions):
            raise ConfigError(
                f"{self.name}: linear must be LinearSolverOptions, got {type(linear).__name__}"
            )
        d = self.discretization
        t0 = time.perf_counter()
        known_u, values = self.boundary_data()
        controls = self.controls()
        free = not known_u.any()
        # b = B values; the columns of A for a unit translation of each platen
        # are H E (E on displacement-given dofs, so B E = -H E)
        W = np.column_stack([values, self.control_indicators(controls)])
        A, BW, _, compressed = self.mixed_system(known_u, W, linear, threads,
                                                 border=6 if free else len(controls))
        t1 = time.perf_counter()
        if free:
            # rigid modes as extra unknowns, zero weighted mean motion as rows
            modes = self.rigid_modes()
            cols, rows, f = modes, (modes * np.repeat(d.weights, 3)[:, None]).T, np.zeros(6)
        elif controls:
            # the platens' translations as extra unknowns, their resultants as rows
            cols, rows = -BW[:, 1:], self.control_rows(controls)
            f = np.array([c.force for c in controls])
        else:
            cols = rows = f = None
        timings = {"assembly": t1 - t0}
        with blas_threads(threads):
            x, y, solver = solve_bordered(
                A, BW[:, 0], cols, rows, f, backend="gmres" if compressed else "lu",
                linear=linear, exact_rhs=lambda Bs: Bs @ values, where=self.name,
                timings=timings,
            )
        timings["solve"] = time.perf_counter() - t1  # (dense: getrf, gecon, getrs)
        if compressed:
            solver.update(A.stats())
        return self._solution(x, y, known_u, values, controls, timings, solver)

    def _solution(self, x, y, known_u, values, controls, timings, solver) -> BodySolution:
        d = self.discretization
        values = values.copy()
        if controls:
            for c, U in zip(controls, y):
                values[c.dofs] = U
        u = np.where(known_u, values, x)
        t = np.where(known_u, x, values)
        return BodySolution(
            points=d.points,
            normals=d.normals,
            displacement=u.reshape(-1, 3),
            traction=t.reshape(-1, 3),
            weights=d.weights,
            region=d.region,
            region_names=self.mesh.region_names,
            discretization=d,
            timings=timings,
            solver=solver,
        )


__all__ = ["ElasticBody", "BodySolution"]

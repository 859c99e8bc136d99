"""An elastic body: a closed surface mesh, a material and boundary conditions.

Boundary conditions are given per region and per global component.  A
component with no prescribed value is traction free.  Displacements are in
length units, tractions in stress units; traction is the force per area the
*surroundings exert on the body*, t = sigma n with n the outward normal, so a
pressure p (> 0 compressive) is t = -p n.
"""

from __future__ import annotations

import time
import warnings
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, Union

import numpy as np
import scipy.linalg

from .errors import AccuracyWarning, ConfigError
from .material import LinearElastic
from .hmatrix import CompressedSystem, LinearSolverOptions, solve_mixed
from .mesh import SurfaceMesh
from .operators import (
    Discretization,
    DiscretizationOptions,
    QuadratureOptions,
    assemble_influence,
    assemble_system,
    blas_threads,
    discretize,
)

ComponentValue = Union[float, None]
FieldValue = Union[Sequence[ComponentValue], Callable[[np.ndarray], Any]]


def _check_value(kind: str, value: Any, allow_callable: bool = True) -> Any:
    if callable(value):
        if not allow_callable:
            raise ConfigError(f"{kind}: value must be 3 components (numbers or None), got a callable")
        return value
    try:
        seq = list(value)
    except TypeError:
        raise ConfigError(
            f"{kind}: value must be 3 components (numbers or None) or a callable of the "
            f"points, got {value!r}"
        ) from None
    if len(seq) != 3:
        raise ConfigError(f"{kind}: value must have 3 components (x, y, z), got {value!r}")
    out = []
    for c in seq:
        if c is None:
            out.append(None)
            continue
        if isinstance(c, bool) or not isinstance(c, (int, float, np.floating, np.integer)):
            raise ConfigError(f"{kind}: component {c!r} is not a number or None")
        if not np.isfinite(c):
            raise ConfigError(f"{kind}: component {c!r} is not finite")
        out.append(float(c))
    return tuple(out)


@dataclass(frozen=True)
class Displacement:
    """Prescribed displacement components (global x, y, z); ``None`` leaves a
    component free (traction free unless a :class:`Traction` sets it).  The
    value may be a callable ``f(points (n, 3)) -> (n, 3)`` (NaN entries mean
    free)."""

    value: FieldValue

    def __post_init__(self) -> None:
        object.__setattr__(self, "value", _check_value("Displacement", self.value))


@dataclass(frozen=True)
class Traction:
    """Prescribed traction components (global x, y, z; force per area acting on
    the body); ``None`` leaves a component free.  May be a callable
    ``f(points, normals) -> (n, 3)``."""

    value: FieldValue

    def __post_init__(self) -> None:
        object.__setattr__(self, "value", _check_value("Traction", self.value))


@dataclass(frozen=True)
class Pressure:
    """Normal pressure p (> 0 pushes on the body): t = -p n on all components."""

    pressure: float

    def __post_init__(self) -> None:
        p = self.pressure
        if isinstance(p, bool) or not isinstance(p, (int, float, np.floating)) or not np.isfinite(p):
            raise ConfigError(f"Pressure: pressure must be a finite number, got {p!r}")


@dataclass(frozen=True)
class Force:
    """Force control: the prescribed resultant (global x, y, z components,
    force units) of the tractions on a region that moves as a *rigid
    translation* in those components (a rigid platen pushed with a given
    force).  The platen's translation is an unknown of the solve, reported as
    the region's controlled displacement.  ``None`` leaves a component to
    other conditions."""

    value: Sequence[ComponentValue]

    def __post_init__(self) -> None:
        object.__setattr__(self, "value", _check_value("Force", self.value, allow_callable=False))


def Fixed() -> Displacement:
    """All displacement components zero (clamped)."""
    return Displacement((0.0, 0.0, 0.0))


BoundaryCondition = Union[Displacement, Traction, Pressure, Force]
_KINDS = (Displacement, Traction, Pressure, Force)


@dataclass(frozen=True)
class Control:
    """One force-controlled component of a region: its dofs (indices into the
    3N unknowns), the prescribed resultant ``force`` and the labels."""

    region: str
    component: int
    dofs: np.ndarray
    force: float


@dataclass
class BodySolution:
    """Nodal results of one elastic solve (N functional nodes).

    Attributes
    ----------
    points, normals: (N, 3) collocation points and outward unit normals.
    displacement, traction: (N, 3) global components.
    weights: (N,) ∫ phi_i dS.
    region: (N,) region index per node; ``region_names`` the names.
    discretization: the :class:`~bemcontact.operators.Discretization`.
    timings: seconds per stage (assembly, solve; dense: also factor, the LAPACK
        getrf alone, inside solve).
    solver: how the system was solved: ``method`` ("dense" or "hmatrix"), and
        for "hmatrix" the GMRES ``iterations`` and ``residuals`` and the
        compression figures of :meth:`~bemcontact.hmatrix.CompressedSystem.stats`.
    """

    points: np.ndarray
    normals: np.ndarray
    displacement: np.ndarray
    traction: np.ndarray
    weights: np.ndarray
    region: np.ndarray
    region_names: tuple[str, ...]
    discretization: Discretization
    timings: dict[str, float] = field(default_factory=dict)
    solver: dict = field(default_factory=dict)

    def nodes_of(self, region: str) -> np.ndarray:
        if region not in self.region_names:
            raise ConfigError(f"unknown region {region!r}; regions are {list(self.region_names)}")
        return np.flatnonzero(self.region == self.region_names.index(region))

    def reaction(self, region: str) -> np.ndarray:
        """Resultant force (3,) the surroundings exert on ``region``: ∫ t dS."""
        i = self.nodes_of(region)
        return self.weights[i] @ self.traction[i]

    def reactions(self) -> dict[str, np.ndarray]:
        return {r: self.reaction(r) for r in self.region_names}


class ElasticBody:
    """A homogeneous linear elastic body bounded by a closed surface.

    Parameters
    ----------
    mesh:
        Closed, outward-oriented :class:`~bemcontact.mesh.SurfaceMesh`
        (checked with :meth:`SurfaceMesh.check`).
    material:
        :class:`~bemcontact.material.LinearElastic`.
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
                if not isinstance(bc, _KINDS):
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
        :func:`~bemcontact.operators.assemble_influence`)."""
        m = self.material
        return assemble_influence(
            self.discretization, m.shear_modulus, m.poisson_ratio, self.quadrature, threads
        )

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
        (:class:`~bemcontact.hmatrix.LinearSolverOptions`; default "auto":
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
        if linear.use_hmatrix(d.n_points):
            return self._solve_compressed(threads, linear)
        t0 = time.perf_counter()
        known_u, values = self.boundary_data()
        controls = self.controls()
        n = 3 * d.n_points
        free = not known_u.any()
        E = self.control_indicators(controls)
        k = 6 if free else E.shape[1]
        m = self.material
        # A in place (with room for the border), b = B values, B E = -H E
        A, BW, _ = assemble_system(
            d, m.shear_modulus, m.poisson_ratio, known_u, np.column_stack([values, E]),
            quadrature=self.quadrature, threads=threads, border=k,
        )
        t1 = time.perf_counter()
        b = BW[:, 0]
        if free:
            # rigid modes as extra unknowns, zero weighted mean motion as rows
            modes = self.rigid_modes()
            A[:n, n:] = modes
            A[n:, :n] = (modes * np.repeat(d.weights, 3)[:, None]).T
            b = np.concatenate([b, np.zeros(6)])
        elif controls:
            # the platens' translations as extra unknowns, their resultants as rows
            A[:n, n:] = -BW[:, 1:]
            A[n:, :n] = self.control_rows(controls)
            b = np.concatenate([b, [c.force for c in controls]])
        timings = {"assembly": t1 - t0}
        with blas_threads(threads):
            x = self._lu_solve(A, b, timings)
        timings["solve"] = time.perf_counter() - t1  # getrf, gecon, getrs (and the border)
        return self._solution(x, known_u, values, controls, timings, {"method": "dense"})

    def _solve_compressed(self, threads, linear: LinearSolverOptions) -> BodySolution:
        d = self.discretization
        t0 = time.perf_counter()
        known_u, values = self.boundary_data()
        controls = self.controls()
        m = self.material
        n = 3 * d.n_points
        # columns of A for a unit translation of each platen: H E (E on
        # displacement-given dofs, so B E = -H E)
        W = np.column_stack([values, self.control_indicators(controls)])
        op = CompressedSystem(
            d, m.shear_modulus, m.poisson_ratio, known_u, W, self.quadrature, linear.hmatrix,
            threads,
        )
        BW = op.BW
        t1 = time.perf_counter()
        if not known_u.any():
            modes = self.rigid_modes()
            w3 = np.repeat(d.weights, 3)
            cols, rows, f = modes, (modes * w3[:, None]).T, np.zeros(6)
        elif controls:
            cols, rows = -BW[:, 1:], self.control_rows(controls)
            f = np.array([c.force for c in controls])
        else:
            cols = rows = f = None
        x, info = solve_mixed(
            op, BW[:, 0], cols, rows, f, tolerance=linear.tolerance,
            max_iterations=linear.max_iterations, restart=linear.restart,
            where=f"{self.name}: ",
        )
        t2 = time.perf_counter()
        exact = op.residual_check(x, values, cols, linear.check_nodes)
        if exact > linear.accuracy:
            warnings.warn(
                f"{self.name}: the H-matrix solution's residual in the exact system is "
                f"{exact:.2e} (sampled at {linear.check_nodes} nodes), above the requested "
                f"accuracy {linear.accuracy:.1e}: lower HMatrixOptions.eps (now "
                f"{linear.hmatrix.eps:.1e}) or use method='dense'",
                AccuracyWarning, stacklevel=3,
            )
        solver = {"method": "hmatrix", "iterations": info.iterations,
                  "residuals": info.residuals, "exact_residual": exact, **op.stats()}
        return self._solution(x, known_u, values, controls,
                              {"assembly": t1 - t0, "solve": t2 - t1}, solver)

    def _solution(self, x, known_u, values, controls, timings, solver) -> BodySolution:
        d = self.discretization
        n = 3 * d.n_points
        values = values.copy()
        if controls:
            for c, U in zip(controls, x[n:]):
                values[c.dofs] = U
        x = x[:n]
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

    def _lu_factor(self, A: np.ndarray, timings: dict | None = None) -> tuple[np.ndarray, np.ndarray]:
        """LU factors of the Fortran-ordered A (LAPACK getrf, in place over A)
        with a singularity check (condition estimate gecon); ``timings``, if
        given, receives the getrf seconds as ``"factor"``."""
        if not A.flags.f_contiguous:
            A = np.asfortranarray(A)
        anorm = scipy.linalg.lapack.dlange("1", A)
        t0 = time.perf_counter()
        lu, piv, info = scipy.linalg.lapack.dgetrf(A, overwrite_a=True)
        if timings is not None:
            timings["factor"] = time.perf_counter() - t0
        rcond = 0.0
        if info == 0:
            rcond, _ = scipy.linalg.lapack.dgecon(lu, anorm, norm="1")
        if info != 0 or not rcond >= 1e-14:
            raise ConfigError(
                f"{self.name}: the linear system is singular (reciprocal condition {rcond:.2e}): "
                "the boundary conditions do not fix the body against rigid motion; prescribe "
                "displacement components that stop translation and rotation"
            )
        return lu, piv

    def _lu_solve(self, A: np.ndarray, b: np.ndarray, timings: dict | None = None) -> np.ndarray:
        lu, piv = self._lu_factor(A, timings)
        x, info = scipy.linalg.lapack.dgetrs(lu, piv, b)
        return x


__all__ = [
    "ElasticBody",
    "BodySolution",
    "Displacement",
    "Traction",
    "Pressure",
    "Force",
    "Fixed",
]

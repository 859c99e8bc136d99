"""A finite-element body: a volume mesh, a material and boundary conditions
on the regions of its boundary, in contact through the same frame and
multipliers as a BEM body (the body seam,
:class:`~bemcontact.contact.flexibility.Body`).  Its stiffness is assembled
by scikit-fem; its flexibility on the contact nodes comes from one sparse
Cholesky factorization (:mod:`.condensation`).

The conditions are those of a BEM body, on the same kind of regions
(:mod:`bemcontact.bem.conditions`), read on the body's trace
(:mod:`.trace`): a displacement fixes the volume nodes under the region, a
traction or pressure loads them with its consistent nodal forces, a force
moves them together (a platen).  A volume node on the boundary between a
displaced region and another is held by the displacement.  A body force
(:class:`~bemcontact.fem.loads.BodyForce`: gravity, a steady rotation)
loads every volume node by its consistent nodal forces, in every load
state (ramped with the bodies' conditions over the first step)."""

from __future__ import annotations

import copy
import hashlib
from collections.abc import Mapping, Sequence

import numpy as np

from ..bem.body import ElasticBody
from ..bem.conditions import BoundaryCondition
from ..errors import ConfigError
from .material import MATERIAL_TYPES, elasticity_tensor, isotropic_estimate
from .loads import BodyForce, densities
from .mesh import VolumeMesh
from .trace import trace_discretization


class FiniteElementBody:
    """A linear elastic body meshed in volume (see the module docstring).

    Parameters
    ----------
    volume: :class:`~bemcontact.fem.mesh.VolumeMesh`.
    material: :class:`~bemcontact.bem.material.LinearElastic` or
        :class:`~bemcontact.fem.material.AnisotropicElastic` for the whole
        body, or a mapping volume region -> material (one for every region
        of ``volume.volume_names``: a coating and its substrate).
    boundary_conditions: region name -> condition(s), as for
        :class:`~bemcontact.bem.body.ElasticBody`; regions not listed are
        traction free.
    name: used in messages.
    density: mass per volume (≥ 0), a number for the whole body or a
        mapping volume region -> density; needed by ``body_force``.
    body_force: :class:`~bemcontact.fem.loads.BodyForce` (gravity, a steady
        rotation), or None.
    """

    def __init__(self, volume: VolumeMesh, material,
                 boundary_conditions: Mapping[str, BoundaryCondition | Sequence[BoundaryCondition]]
                 | None = None, *, name: str = "body", density=None,
                 body_force: BodyForce | None = None) -> None:
        if not isinstance(volume, VolumeMesh):
            raise ConfigError(f"{name}: a finite-element body needs a VolumeMesh, got "
                              f"{type(volume).__name__}")
        self.name, self.volume = name, volume
        self.materials = _materials(name, volume, material)
        #: the body's one material, or None with several
        self.material = material if not isinstance(material, Mapping) else (
            next(iter(self.materials.values())) if len(self.materials) == 1 else None)
        self.mesh, surface_to_volume = volume.boundary()
        self._disc, self.volume_node = trace_discretization(self.mesh, surface_to_volume)
        self.boundary_conditions = self.checked_conditions(boundary_conditions or {})
        #: volume region -> density, or None
        self.density = densities(name, volume.volume_names, density)
        if body_force is not None and not isinstance(body_force, BodyForce):
            raise ConfigError(f"{name}: body_force must be a BodyForce, got "
                              f"{type(body_force).__name__}")
        if body_force is not None and not body_force.is_zero and self.density is None:
            raise ConfigError(f"{name}: a body force needs the density of the body (density=, "
                              "a number or one per volume region)")
        if body_force is not None and self.density is not None:
            missing = [r for r in volume.volume_names if r not in self.density]
            if missing:
                raise ConfigError(f"{name}: volume region {missing[0]!r} has no density (a body "
                                  "force needs one for every region)",
                                  location={"region": missing[0]})
        self.body_force = body_force

    # the conditions are read on the trace exactly as a BEM body reads its own
    checked_conditions = ElasticBody.checked_conditions
    _components = staticmethod(ElasticBody._components)
    boundary_data = ElasticBody.boundary_data
    controls = ElasticBody.controls
    condition_kinds = ElasticBody.condition_kinds
    load_values = ElasticBody.load_values

    @property
    def discretization(self):
        return self._disc

    @property
    def trace(self):
        """The boundary with its functional nodes (:mod:`.trace`)."""
        return self._disc

    @property
    def region_names(self) -> tuple[str, ...]:
        return self.mesh.region_names

    @property
    def contact_compliance(self) -> float:
        """(1 - nu^2) / E of the materials at the boundary, averaged over
        its area (an anisotropic one's isotropic estimate): the body's share
        of 1/E* in the estimates of a contact's size and stiffness."""
        v = self.volume
        m = v.skfem
        P = m.p.T[v.faces]
        area = np.linalg.norm(np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0]), axis=1)
        per = np.zeros(len(v.volume_names))
        np.add.at(per, v.cell_region[v.face_cell], area)
        c = 0.0
        for r, name in enumerate(v.volume_names):
            iso = isotropic_estimate(self.materials[name])
            c += per[r] * (1 - iso.poisson_ratio**2) / iso.youngs_modulus
        return float(c / per.sum())

    @property
    def n_dofs(self) -> int:
        return 3 * self.volume.n_nodes

    def describe(self) -> str:
        """One line: the cells, elements, nodes and dofs, the materials."""
        v = self.volume
        kind = {("tet4", 1): "tet4", ("tet4", 2): "tet10", ("hex8", 1): "hex8",
                ("hex8", 2): "hex27"}[v.cell_type, v.order]
        mats = []
        for r, m in self.materials.items():
            what = (f"E = {m.youngs_modulus:g}, nu = {m.poisson_ratio:g}"
                    if hasattr(m, "youngs_modulus") else "anisotropic")
            mats.append(what if len(self.materials) == 1 else f"{r}: {what}")
        f = self.body_force
        loads = "" if f is None or f.is_zero else "; body force" + (
            f" g = {list(f.gravity)}" if any(f.gravity) else "") + (
            f" ω = {list(f.angular_velocity)}" if any(f.angular_velocity) else "")
        return (f"finite elements, {v.skfem.t.shape[1]:,} {kind} cells, {v.n_nodes:,} nodes "
                f"({self.n_dofs:,} dofs), {'; '.join(mats)}{loads}")

    def stiffness(self):
        """The stiffness matrix (3n, 3n), scipy CSR, dof 3i + c component c
        of volume node i.  Assembled per volume region from the nine scalar
        matrices G_kl = ∫ ∂_k φ_a ∂_l φ_b (scikit-fem, one cheap form each)
        as K^(ij) = Σ_kl C_ikjl G_kl, C the region's elasticity tensor."""
        import scipy.sparse
        from skfem import Basis, BilinearForm, asm

        v = self.volume
        basis = v.basis()
        order = v.dof_order
        blocks = [[None] * 3 for _ in range(3)]
        for r, name in enumerate(v.volume_names):
            cells = np.flatnonzero(v.cell_region == r)
            sub = basis if len(v.volume_names) == 1 else Basis(v.skfem, basis.elem, elements=cells)
            G = [[None] * 3 for _ in range(3)]
            for k in range(3):
                for l_ in range(k, 3):
                    form = BilinearForm(lambda u, w_, w, k=k, l_=l_: w_.grad[k] * u.grad[l_])
                    G[k][l_] = asm(form, sub).tocsr()[order][:, order]
                    G[l_][k] = G[k][l_].T.tocsr()
            C = elasticity_tensor(self.materials[name])
            scale = np.abs(C).max()
            for i in range(3):
                for j in range(3):
                    for k in range(3):
                        for l_ in range(3):
                            c = C[i, k, j, l_]
                            if abs(c) > 1e-14 * scale:
                                term = c * G[k][l_]
                                blocks[i][j] = term if blocks[i][j] is None else blocks[i][j] + term
        K = None
        for i in range(3):
            for j in range(3):
                if blocks[i][j] is None:
                    continue
                unit = scipy.sparse.csr_array(([1.0], ([i], [j])), shape=(3, 3))
                term = scipy.sparse.kron(blocks[i][j], unit, format="csr")
                K = term if K is None else K + term
        return K.tocsr(), basis

    def condense(self, nodes: np.ndarray, threads=None, states=None, progress=None,
                 linear=None, modes=None, *, load_fields=None):
        """This body's flexibility on its contact ``nodes``
        (:func:`~bemcontact.fem.condensation.condense`)."""
        from .condensation import condense

        return condense(self, nodes, states, progress, modes, load_fields=load_fields)

    def condensation_bytes(self, contact_nodes: int, modes: int, states: int, controls: int,
                           linear, chunk: int) -> tuple[float, float]:
        """(peak, kept) bytes of :meth:`condense`: the sparse factor, held
        once, as 30 n^(4/3) entries for n dofs plus its dense trailing
        triangle on the k contact dofs (nested dissection's growth in 3D; the
        constant measured from CHOLMOD's symbolic analysis in the ordering
        used: 22 to 29 on boxes of linear and quadratic tetrahedra and
        hexahedra of 26,000 to 196,000 dofs), the contact flexibility and
        its product with the frame (two k × k arrays) and the responses
        kept; benchmarks/fem_sparse_solvers.py measures the whole peak."""
        n = self.n_dofs
        kept = 8.0 * 3 * contact_nodes * (modes + states + controls + 6)
        dense = (3.0 * contact_nodes) ** 2
        factor = 30.0 * n ** (4.0 / 3.0) + dense / 2.0
        return 8.0 * (factor + 2.0 * dense + n * (states + controls)) + kept, kept

    def stresses(self, solution, points) -> np.ndarray:
        """Stresses (n, 6) at ``points`` (n, 3) inside this body for its
        ``solution`` (:func:`~bemcontact.fem.fields.point_stresses`)."""
        from .fields import point_stresses

        return point_stresses(self, _volume_displacement(self, solution), points)

    def surface_stresses(self, solution) -> np.ndarray:
        """Stresses (N, 6) at the functional nodes of ``solution``
        (:func:`~bemcontact.fem.fields.trace_stresses`)."""
        from .fields import trace_stresses

        return trace_stresses(self, _volume_displacement(self, solution))

    def volume_fields(self, solution):
        """The volume mesh's VTU content for ``solution``
        (:func:`~bemcontact.fem.fields.volume_fields`)."""
        from .fields import volume_fields

        return volume_fields(self, _volume_displacement(self, solution))

    def model_key(self) -> str:
        """A hex SHA-256 of the volume mesh, its regions, the material and
        the body force with its densities (a load of the condensation: its
        response is part of it)."""
        h = hashlib.sha256()
        m = self.volume.skfem
        for part in (m.p, m.t, self.volume.face_region):
            a = np.ascontiguousarray(part)
            h.update(f"{a.dtype.str}{a.shape}".encode())
            h.update(a.tobytes())
        a = np.ascontiguousarray(self.volume.cell_region)
        h.update(a.tobytes())
        h.update(repr(("fem", self.volume.cell_type, self.volume.order, self.region_names,
                       self.volume.volume_names, sorted(self.materials.items()))).encode())
        if self.body_force is not None and not self.body_force.is_zero:
            h.update(repr((self.body_force, sorted(self.density.items()))).encode())
        return h.hexdigest()

    def same_model(self, other) -> bool:
        return (isinstance(other, FiniteElementBody) and self.name == other.name
                and self.model_key() == other.model_key())

    def translated(self, origin: np.ndarray) -> FiniteElementBody:
        """A copy whose meshes are translated by ``-origin``."""
        v = self.volume
        c = copy.copy(self)
        vol = copy.copy(v)
        vol.skfem = type(v.skfem)(np.ascontiguousarray(v.skfem.p - np.asarray(origin, dtype=float)[:, None]),
                                  v.skfem.t)
        vol._basis = None
        c.volume = vol
        if self.body_force is not None:
            c.body_force = self.body_force.translated(origin)
        c.mesh, s2v = vol.boundary()
        c._disc, c.volume_node = trace_discretization(c.mesh, s2v)
        return c


def _volume_displacement(body, solution) -> np.ndarray:
    u = getattr(solution, "volume_displacement", None)
    if u is None or u.shape != (body.volume.n_nodes, 3):
        raise ConfigError(f"{body.name}: the solution holds no volume displacement of this "
                          "body (a finite-element body's own solution does)")
    return u


def _materials(name: str, volume: VolumeMesh, material) -> dict:
    """Volume region -> material, one for every region of ``volume``."""
    if not isinstance(material, Mapping):
        material = {r: material for r in volume.volume_names}
    out = {}
    for r, m in material.items():
        if r not in volume.volume_names:
            raise ConfigError(f"{name}: the volume mesh has no volume region {r!r} (its "
                              f"regions: {', '.join(volume.volume_names)})",
                              location={"region": r})
        if not isinstance(m, MATERIAL_TYPES):
            raise ConfigError(f"{name}: the material of {r!r} must be a LinearElastic or an "
                              f"AnisotropicElastic, got {type(m).__name__}", location={"region": r})
        out[r] = m
    missing = [r for r in volume.volume_names if r not in out]
    if missing:
        raise ConfigError(f"{name}: volume region {missing[0]!r} has no material (give one "
                          f"for each of {', '.join(volume.volume_names)})",
                          location={"region": missing[0]})
    return out


__all__ = ["FiniteElementBody"]

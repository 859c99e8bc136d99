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
displaced region and another is held by the displacement."""

from __future__ import annotations

import copy
import hashlib
from collections.abc import Mapping, Sequence

import numpy as np

from ..bem.body import ElasticBody
from ..bem.conditions import BoundaryCondition
from ..bem.material import LinearElastic
from ..errors import ConfigError
from .mesh import VolumeMesh
from .trace import trace_discretization


class FiniteElementBody:
    """A linear elastic body meshed in volume (see the module docstring).

    Parameters
    ----------
    volume: :class:`~bemcontact.fem.mesh.VolumeMesh`.
    material: :class:`~bemcontact.bem.material.LinearElastic`.
    boundary_conditions: region name -> condition(s), as for
        :class:`~bemcontact.bem.body.ElasticBody`; regions not listed are
        traction free.
    name: used in messages.
    """

    def __init__(self, volume: VolumeMesh, material: LinearElastic,
                 boundary_conditions: Mapping[str, BoundaryCondition | Sequence[BoundaryCondition]]
                 | None = None, *, name: str = "body") -> None:
        if not isinstance(volume, VolumeMesh):
            raise ConfigError(f"{name}: a finite-element body needs a VolumeMesh, got "
                              f"{type(volume).__name__}")
        if not isinstance(material, LinearElastic):
            raise ConfigError(f"{name}: material must be a LinearElastic, got "
                              f"{type(material).__name__}")
        self.name, self.volume, self.material = name, volume, material
        self.mesh, surface_to_volume = volume.boundary()
        self._disc, self.volume_node = trace_discretization(self.mesh, surface_to_volume)
        self.boundary_conditions = self.checked_conditions(boundary_conditions or {})

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
        """(1 - nu^2) / E: the body's share of 1/E*."""
        return (1 - self.material.poisson_ratio**2) / self.material.youngs_modulus

    @property
    def n_dofs(self) -> int:
        return 3 * self.volume.n_nodes

    def stiffness(self):
        """The stiffness matrix (3n, 3n), scipy CSR, dof 3i + c component c
        of volume node i.  Assembled from the nine scalar matrices
        G_kl = ∫ ∂_k φ_a ∂_l φ_b (scikit-fem, one cheap form each) as
        K^(ij) = Σ_kl C_ikjl G_kl: the elasticity tensor enters only in the
        combination (isotropic here: λ G_ij + μ G_ji + μ δ_ij Σ_k G_kk)."""
        import scipy.sparse
        from skfem import BilinearForm, asm

        basis = self.volume.basis()
        order = self.volume.dof_order
        G = [[None] * 3 for _ in range(3)]
        for k in range(3):
            for l_ in range(k, 3):
                form = BilinearForm(lambda u, v, w, k=k, l_=l_: v.grad[k] * u.grad[l_])
                G[k][l_] = asm(form, basis).tocsr()[order][:, order]
                G[l_][k] = G[k][l_].T.tocsr()
        E, nu = self.material.youngs_modulus, self.material.poisson_ratio
        lam, mu = E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))
        lap = G[0][0] + G[1][1] + G[2][2]
        K = None
        for i in range(3):
            for j in range(3):
                block = lam * G[i][j] + mu * G[j][i] + (mu * lap if i == j else 0)
                unit = scipy.sparse.csr_array(([1.0], ([i], [j])), shape=(3, 3))
                term = scipy.sparse.kron(block, unit, format="csr")
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
        """(peak, kept) bytes of :meth:`condense`: the Cholesky factor of
        the stiffness, taken as 40 n^(4/3) entries for n dofs (nested
        dissection's growth in 3D, its constant from the measured peaks:
        0.73 GB at 27,783 dofs, 6.1 GB at 199,287; benchmarks/
        fem_sparse_solvers.py), 1.5 of it for the workspace, a block of
        right-hand sides and the contact responses kept."""
        n = self.n_dofs
        kept = 8.0 * 3 * contact_nodes * (modes + states + controls + 6)
        factor = 40.0 * n ** (4.0 / 3.0)
        return 8.0 * (1.5 * factor + 2.0 * n * 256) + kept, kept

    def model_key(self) -> str:
        """A hex SHA-256 of the volume mesh, its regions and the material."""
        h = hashlib.sha256()
        m = self.volume.skfem
        for part in (m.p, m.t, self.volume.face_region):
            a = np.ascontiguousarray(part)
            h.update(f"{a.dtype.str}{a.shape}".encode())
            h.update(a.tobytes())
        h.update(repr(("fem", self.volume.cell_type, self.volume.order, self.region_names,
                       self.material)).encode())
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
        c.mesh, s2v = vol.boundary()
        c._disc, c.volume_node = trace_discretization(c.mesh, s2v)
        return c


__all__ = ["FiniteElementBody"]

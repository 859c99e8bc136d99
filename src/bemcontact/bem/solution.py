"""The fields of one elastic body at its functional nodes: what a one-body
solve and the contact solver's recovery return."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import ConfigError
from .discretization import Discretization


@dataclass
class BodySolution:
    """Nodal results of one elastic solve (N functional nodes).

    Attributes
    ----------
    points, normals: (N, 3) collocation points and outward unit normals.
    displacement, traction: (N, 3) global components.
    weights: (N,) ∫ phi_i dS.
    region: (N,) region index per node; ``region_names`` the names.
    discretization: the :class:`~bemcontact.bem.discretization.Discretization`.
    timings: seconds per stage (assembly, solve; dense: also factor, the LAPACK
        getrf alone, inside solve).
    solver: how the system was solved: ``method`` ("dense" or "hmatrix"), and
        for "hmatrix" the GMRES ``iterations`` and ``residuals`` and the
        compression figures of :meth:`~bemcontact.linalg.CompressedSystem.stats`.
    whole_boundary: whether the fields cover the body's whole boundary.
    volume_force: the forces on the body's volume (a finite-element body's
        body force, :class:`~bemcontact.fem.loads.BodyForce`): their
        resultant (3,) and magnitude ∫ |f| dV, which its tractions balance;
        None without.
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
    #: the fields cover the body's whole boundary, so its tractions balance
    #: (False for a body seen through part of its surface, e.g. a half-space
    #: patch whose reaction is at infinity)
    whole_boundary: bool = True
    volume_force: tuple[np.ndarray, float] | None = None

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


__all__ = ["BodySolution"]

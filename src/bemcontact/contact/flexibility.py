"""The body seam: what the contact solver needs from a body, and nothing
more.  A body reduced to its contact nodes (condensed on the frame's traction
modes) hands the interface system its *flexibility*: its contact
displacements per traction-mode amplitude, per load state, per free rigid
mode and per platen translation, the resultants of its force-controlled
components, and the recovery of its own fields from given tractions.  How
it was made (a dense or compressed BEM condensation,
:class:`~bemcontact.bem.condensation.CondensedBody`; a half-space operator;
a finite-element body) stays behind the protocol: the interface system,
the first-touch predictor and the recovery use only these members.

Shapes: n_c contact nodes (3 n_c contact dofs, interleaved x, y, z, global
components), ``r`` traction modes, S load states, nf free rigid modes, nc
force-controlled components."""

from __future__ import annotations

from typing import Any, Protocol, runtime_checkable

import numpy as np


@runtime_checkable
class Flexibility(Protocol):
    """A body's response on its contact dofs (see the module docstring)."""

    #: the body's name (messages, results)
    name: str
    #: the frame's traction modes it was condensed on (their ``B``, the
    #: nodal forces per mode amplitude, (3 n_c, r)); their ``size`` is r
    modes: Any
    #: (nf, S): the work of the given loads in each free rigid mode
    known_modal_force: np.ndarray
    #: (nc, S): the prescribed resultant of each controlled component per state
    forces: np.ndarray
    #: the force-controlled components (``region``, ``component``)
    controls: list
    #: seconds spent making it: ``assembly`` and ``condensation``
    timings: dict
    #: how it was made (JSON-ready: ``method`` and its figures), for the summary
    solver: dict

    @property
    def points(self) -> np.ndarray:
        """(n_c, 3) positions of the contact nodes."""

    @property
    def F(self) -> np.ndarray:
        """(3 n_c, r) contact displacements per traction-mode amplitude."""

    @property
    def u0(self) -> np.ndarray:
        """(3 n_c, S) contact displacements per load state."""

    @property
    def Rc(self) -> np.ndarray:
        """(3 n_c, nf) contact displacements per free rigid-mode amplitude."""

    @property
    def Yc(self) -> np.ndarray:
        """(3 n_c, nc) contact displacements per platen translation."""

    @property
    def CX(self) -> np.ndarray:
        """(nc, r) controlled resultants per traction-mode amplitude."""

    @property
    def CY(self) -> np.ndarray:
        """(nc, nc) controlled resultants per platen translation (rows and
        columns of a translation that strains nothing exactly zero)."""

    def control_resultants(self, ell: np.ndarray) -> np.ndarray:
        """(nc,) controlled resultants of the load weights ``ell`` (S,)."""

    def solution(self, lam: np.ndarray, alpha: np.ndarray, U: np.ndarray,
                 ell: np.ndarray) -> tuple[Any, dict[str, np.ndarray]]:
        """The body's fields (a :class:`~bemcontact.bem.body.BodySolution`)
        for the mode amplitudes ``lam``, rigid-mode amplitudes ``alpha``,
        platen translations ``U`` and load weights ``ell``, and per
        force-controlled region its translation (3,) (NaN where not
        controlled)."""


@runtime_checkable
class Body(Protocol):
    """What :class:`~bemcontact.contact.ContactProblem` asks of a body:
    its name, its surface with functional nodes (``trace``: a
    :class:`~bemcontact.bem.discretization.Discretization`, the contact
    frame is built on it), its boundary conditions, its share of the
    contact modulus, its :class:`Flexibility` on given contact nodes, the
    memory that takes and a key of its model.
    :class:`~bemcontact.bem.body.ElasticBody` is one; any object with these
    members is another (a flexibility given as a matrix, a half-space
    operator, a finite-element body)."""

    name: str
    #: region -> conditions (checked), the body's own
    boundary_conditions: Any

    @property
    def trace(self) -> Any:
        """The surface (mesh, points, normals, weights, region of each node)."""

    @property
    def region_names(self) -> tuple[str, ...]:
        """The names of the surface's regions."""

    @property
    def contact_compliance(self) -> float:
        """(1 - nu^2) / E, the body's share of 1/E* (augmentation scale)."""

    def checked_conditions(self, conditions, where: str = "") -> dict:
        """``conditions`` (region -> condition(s)) checked for this body."""

    def condition_kinds(self, conditions=None) -> np.ndarray:
        """(3N,) int8 per dof of the trace: 0 traction (or free), 1
        displacement, 2 force-controlled."""

    def load_values(self, conditions=None) -> np.ndarray:
        """(3N,) the prescribed displacement or traction per dof of the trace."""

    def controls(self, conditions=None) -> list:
        """The force-controlled components."""

    def condense(self, nodes: np.ndarray, threads=None, states=None, progress=None,
                 linear=None, modes=None, *, load_fields=None) -> Flexibility:
        """The body's flexibility on its contact ``nodes`` (trace node
        indices) for the load ``states`` and the frame's traction ``modes``."""

    def condensation_bytes(self, contact_nodes: int, modes: int, states: int, controls: int,
                           linear, chunk: int) -> tuple[float, float]:
        """(peak, kept) bytes of :meth:`condense` (the memory guard's estimate)."""

    def model_key(self) -> str:
        """A key of what the body's responses depend on besides its
        conditions (a cache of flexibilities keys on it)."""

    def translated(self, origin: np.ndarray) -> Body:
        """A copy of the body translated by ``-origin``."""

    def same_model(self, other) -> bool:
        """Whether ``other``'s flexibility can stand for this body's."""


__all__ = ["Body", "Flexibility"]

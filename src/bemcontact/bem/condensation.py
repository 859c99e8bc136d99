"""Condensation: a BEM body reduced to its contact surface (the partitioned
step of the LLM method), its system assembled and factored once: the body's
interface flexibility, handed to the contact solver through the members of
the flexibility protocol (:class:`~bemcontact.contact.flexibility.Flexibility`)
and recovering its own fields from given contact tractions."""

from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import scipy.linalg

from ..errors import ConfigError
from ..linalg.bordered import solve_bordered
from ..linalg.options import LinearSolverOptions
from ..progress import ProgressEvent, Reporter
from .solution import BodySolution


@dataclass
class CondensedBody:
    """One body reduced to its contact surface (the partitioned step).  For
    contact tractions t_c = T c (3 n_c, interleaved xyz per node: the
    traction modes T, :mod:`bemcontact.contact.modes`, times their
    amplitudes c; without modes T = I, one mode per contact dof), load
    weights ell (S,) over the boundary-condition states, free rigid-mode
    amplitudes alpha and platen translations U (force control),

        x = x0 ell + X c + Rf alpha + Y U,   u_c = x[dofs]

    where x is the BEM unknown vector (displacement at traction-given dofs,
    traction at displacement-given dofs), x0 (n, S) the response to each
    state's boundary data, Rf the rigid modes the supports leave free
    (floating bodies; alpha fixed by the body's equilibrium), Y the response
    to a unit translation of each force-controlled component (U fixed by
    ``C x = forces ell``), F = X[dofs] the interface flexibility (contact
    displacements per mode amplitude).
    """

    body: Any
    nodes: np.ndarray
    dofs: np.ndarray
    known_u: np.ndarray
    values: np.ndarray  # (3N, S) boundary values per state
    x0: np.ndarray  # (n, S)
    X: np.ndarray
    Rf: np.ndarray
    known_modal_force: np.ndarray  # (nf, S) ∫ Rf . t_known dS per state
    controls: list
    Y: np.ndarray  # (n, nc)
    C: np.ndarray  # (nc, n) resultant rows of the controlled components
    forces: np.ndarray  # (nc, S) prescribed resultants per state
    timings: dict
    solver: dict = field(default_factory=dict)  # linear solver used, sizes and residuals
    modes: Any = None  # TractionModes, or None: unit tractions per contact dof

    def recombined(self, body, coef: np.ndarray, values: np.ndarray, controls,
                   forces: np.ndarray) -> CondensedBody:
        """This condensation for other loads: the load fields ``values`` =
        the condensed ones times ``coef`` (each new load a combination of
        the condensed), their ``controls`` and platen ``forces``; nothing
        solved again."""
        return dataclasses.replace(
            self, body=body, values=values, x0=self.x0 @ coef,
            known_modal_force=self.known_modal_force @ coef, controls=controls, forces=forces,
            timings={"assembly": 0.0, "condensation": 0.0})

    def tractions(self, c: np.ndarray) -> np.ndarray:
        """Contact tractions (3 n_c,) of the mode amplitudes ``c``."""
        return c if self.modes is None else self.modes.tractions(c)

    @property
    def F(self) -> np.ndarray:
        return self.X[self.dofs]

    @property
    def u0(self) -> np.ndarray:
        return self.x0[self.dofs]

    @property
    def Rc(self) -> np.ndarray:
        return self.Rf[self.dofs]

    @property
    def Yc(self) -> np.ndarray:
        return self.Y[self.dofs]

    # -- the flexibility protocol's members besides F, u0, Rc, Yc, modes
    @property
    def name(self) -> str:
        return self.body.name

    @property
    def points(self) -> np.ndarray:
        """(n_c, 3) positions of the contact nodes."""
        return self.body.discretization.points[self.nodes]

    @property
    def CX(self) -> np.ndarray:
        """(nc, modes) resultant of each controlled component per mode amplitude."""
        return self.C @ self.X

    def control_resultants(self, ell: np.ndarray) -> np.ndarray:
        """(nc,) the controlled components' resultants of the load weights ``ell``."""
        return self.C @ (self.x0 @ ell)

    @property
    def CY(self) -> np.ndarray:
        """(nc, nc) resultants per platen translation; a translation that
        strains nothing (the body is held only by the contact in that
        direction) has none, exactly, so an open contact shows as a
        singular Newton matrix."""
        CY = self.C @ self.Y
        E = self.body.material.youngs_modulus
        for k_ in range(len(self.controls)):
            size = math.sqrt(self.C[k_].sum())
            if abs(CY[k_, k_]) <= 1e-8 * E * size:
                CY[k_, :] = 0.0
                CY[:, k_] = 0.0
        return CY

    def solution(self, lam: np.ndarray, alpha: np.ndarray, U: np.ndarray,
                 ell: np.ndarray) -> tuple[BodySolution, dict[str, np.ndarray]]:
        """The body's fields for the frame tractions ``lam`` (mode
        amplitudes), free rigid-mode amplitudes ``alpha``, platen
        translations ``U`` and load weights ``ell``, and the translation of
        each force-controlled region (NaN in components not controlled)."""
        b, d = self.body, self.body.discretization
        tc = self.tractions(lam)
        x = self.x0 @ ell + self.X @ lam
        if alpha.size:
            x = x + self.Rf @ alpha
        if U.size:
            x = x + self.Y @ U
        vals = self.values @ ell
        controlled: dict[str, np.ndarray] = {}
        for ctl, Uk in zip(self.controls, U):
            vals[ctl.dofs] = Uk
            controlled.setdefault(ctl.region, np.full(3, np.nan))[ctl.component] = Uk
        u = np.where(self.known_u, vals, x)
        t = np.where(self.known_u, x, vals)
        t[self.dofs] = tc
        sol = BodySolution(
            points=d.points, normals=d.normals, displacement=u.reshape(-1, 3),
            traction=t.reshape(-1, 3), weights=d.weights, region=d.region,
            region_names=b.mesh.region_names, discretization=d,
            timings=dict(self.timings),
        )
        return sol, controlled


def condense(
    body, nodes: np.ndarray, threads: int | None = None, states=None,
    progress: Reporter | None = None, linear: LinearSolverOptions | None = None,
    modes=None, *, load_fields: np.ndarray | None = None,
) -> CondensedBody:
    """Assemble the body's BEM system once, factor it, and solve for the
    response to unit tractions at each contact dof (``nodes``: the contact
    functional nodes, which must carry no boundary condition), to each
    boundary-condition state in ``states`` (checked condition mappings with
    the same kind per dof; default: the body's own) and to unit platen
    translations of the force-controlled components.  ``progress`` receives
    the start and end events of the ``assembly`` and ``condensation`` stages
    (:mod:`bemcontact.progress`).  ``linear`` chooses dense operators (LAPACK
    LU) or compressed ones (H-matrix, H-LU with one step of iterative
    refinement; :class:`~bemcontact.linalg.LinearSolverOptions`).
    ``modes`` (the contact frame's traction modes: ``size`` columns, their
    right-hand sides ``right(G, out=)`` and ``tractions(c)``;
    :class:`~bemcontact.contact.modes.TractionModes`): condense on
    the contact traction fields of the frame's tractions instead of on unit
    tractions at each contact dof (the contact solver's choice)."""
    d = body.discretization
    t0 = time.perf_counter()
    what = f"{body.name}: {d.n_points:,} nodes, {nodes.size:,} on the contact surface"
    if progress is not None:
        progress(ProgressEvent("start", "assembly", f"assembly {what}"))
    states = [body.boundary_conditions] if states is None else list(states)
    data = [body.boundary_data(c) for c in states]
    known_u = data[0][0]  # the same for every state (checked by ContactProblem.states)
    controls = body.controls(states[0])
    values = np.column_stack([v for _, v in data])
    forces = np.array([[c.force for c in body.controls(st)] for st in states]).reshape(
        len(states), len(controls)
    ).T
    if load_fields is not None:
        values = np.asarray(load_fields, dtype=float).reshape(3 * d.n_points, -1)
        forces = np.zeros((len(controls), values.shape[1]))
        states = [states[0]] * values.shape[1]
    dofs = (3 * nodes[:, None] + np.arange(3)).ravel()
    if known_u[dofs].any() or np.any(values[dofs] != 0):
        raise ConfigError(
            f"{body.name}: the contact surface also has a boundary condition; remove it "
            "(the contact decides the tractions there)"
        )
    # rigid modes the supports leave free
    ku = np.flatnonzero(known_u)
    R = body.rigid_modes()
    Rn = R / np.linalg.norm(R, axis=0)
    if ku.size:
        Z = scipy.linalg.null_space(Rn[ku], rcond=1e-9)
    else:
        Z = np.eye(6)
    Rf = Rn @ Z
    nf = Rf.shape[1]
    # A in place (bordered by the free modes); B values = b0 per state, B E =
    # -Hc for the platens, the contact columns of B = G (traction-given dofs)
    S = len(states)
    n = 3 * d.n_points
    lin = linear or LinearSolverOptions()
    W = np.column_stack([values, body.control_indicators(controls)])
    C = (Rf * np.repeat(d.weights, 3)[:, None]).T  # equilibrium rows of the free modes
    A, BW, Gc, compressed = body.mixed_system(known_u, W, lin, threads, border=nf, dofs=dofs)
    t1 = time.perf_counter()
    if progress is not None:
        progress(ProgressEvent("end", "assembly", f"assembly {what}", seconds=t1 - t0))
        progress(ProgressEvent("start", "condensation", f"condensation {body.name}"))
    # the right-hand sides in one Fortran-ordered block, solved in place
    # (the largest arrays of the run: 3N x 3m each, so no copies of them)
    ncol = dofs.size if modes is None else modes.size
    rhs = np.empty((n, S + ncol + BW.shape[1] - S), order="F")
    rhs[:, :S] = BW[:, :S]
    rhs[:, S + ncol :] = BW[:, S:]
    if modes is None:
        rhs[:, S : S + ncol] = Gc
    else:
        modes.right(Gc, out=rhs[:, S : S + ncol])
    del Gc
    right = (lambda G: G) if modes is None else modes.right
    # the free modes bordered by their equilibrium rows (zero right-hand side)
    sol, _, solver_info = solve_bordered(
        A, rhs, Rf, C, backend="hlu" if compressed else "lu", linear=lin,
        exact_rhs=lambda Bs: np.column_stack([Bs @ W[:, :S], right(Bs[:, dofs]), Bs @ W[:, S:]]),
        where=body.name, overwrite_rhs=True,
    )
    del rhs
    del A
    x0 = np.ascontiguousarray(sol[:n, :S])
    X = sol[:n, S : S + ncol]  # a view: no copy of the largest block
    Y = np.ascontiguousarray(sol[:n, S + ncol :])
    Rf[ku] = 0.0  # exactly zero on supported dofs
    # work of the given tractions in the free modes: ∫ Rf . t_known dS
    modal = np.zeros((nf, S))
    if nf:
        for s_ in range(S):
            tk = np.where(known_u, 0.0, values[:, s_]).reshape(-1, 3)
            _, _, W, tq = d.interpolate(tk)
            for i in range(nf):
                _, _, _, rq = d.interpolate(Rf[:, i].reshape(-1, 3))
                modal[i, s_] = float(np.einsum("eq,eqk,eqk->", W, rq, tq))
    t2 = time.perf_counter()
    if progress is not None:
        progress(ProgressEvent("end", "condensation", f"condensation {body.name}",
                               seconds=t2 - t1))
    return CondensedBody(
        body, nodes, dofs, known_u, values, x0, X, Rf, modal, controls, Y,
        body.control_rows(controls), forces,
        {"assembly": t1 - t0, "condensation": t2 - t1}, solver_info, modes,
    )


__all__ = ["CondensedBody", "condense"]

"""A finite-element body reduced to its contact nodes: its stiffness
factored once (sparse Cholesky, CHOLMOD through cvxopt, in a METIS
nested-dissection ordering with the contact dofs last; docs/decisions.md
says why): the factor's trailing block is the Cholesky factor of the Schur
complement on the contact dofs, whose inverse is the body's flexibility
there, without a solve per contact dof; its responses to each load state
and platen translation are solved whole, and its fields recovered by one
more solve from given frame tractions (the members of
:class:`~bemcontact.contact.flexibility.Flexibility`).

Volume dofs: ``3 i + c`` is component c of volume node i.  A trace
functional node moves as its volume node (``body.volume_node``); its nodal
forces (a traction's consistent forces, the frame's multipliers ``B``) add
onto that node.

Rigid modes the supports leave free (a body held only by its contacts)
make the stiffness singular.  They are removed by pinning as many dofs as
there are free modes, chosen by a pivoted QR of the modes so that the pins
hold exactly those modes and nothing else (statically determinate): a
response is then the body's deformation plus a rigid motion, and for the
equilibrated loads of a solution (the contact solver's equilibrium rows)
the pins carry no force, so the fields are exact."""

from __future__ import annotations

import math
import time
from typing import Any

import numpy as np
import scipy.linalg
import scipy.sparse

from ..errors import ConfigError
from ..progress import ProgressEvent
from .fields import VolumeSolution
from .loads import nodal_body_forces
from .supernodal import factor_entries, trailing_block
from .trace import trace_mass

class SchurFactor:
    """The sparse Cholesky factor of the SPD stiffness of the solved dofs,
    CHOLMOD's (through cvxopt), in a nested-dissection ordering of the other
    dofs (METIS, through pymetis; of their nodes' graph when ``groups``
    labels each dof's node) with the contact dofs ``last`` (indices into the
    matrix) ordered after all of them: the factor's trailing block
    is then the Cholesky factor of the Schur complement on the contact dofs,
    whose inverse is the flexibility there (:meth:`contact_inverse`), with
    no solve per contact dof."""

    def __init__(self, A, last: np.ndarray, groups: np.ndarray | None = None) -> None:
        try:
            import cvxopt
            import cvxopt.cholmod as cholmod
            import pymetis  # noqa: F401 (used by _dissection; checked here)
        except ImportError:
            raise ConfigError(
                "a finite-element body needs cvxopt (CHOLMOD) and pymetis (METIS); "
                'pip install "bemcontact[fem]"') from None
        A = scipy.sparse.csr_array(A)
        n = A.shape[0]
        rest = np.setdiff1d(np.arange(n), last)
        self.perm = np.concatenate([rest[_dissection(A, rest, groups)],
                                    np.asarray(last, dtype=np.int64)])
        self.n, self.n_last = n, int(np.asarray(last).size)
        low = scipy.sparse.tril(A).tocsc()
        cols = np.repeat(np.arange(n, dtype=np.int64), np.diff(low.indptr))
        M = cvxopt.spmatrix(cvxopt.matrix(low.data.astype(float)),
                            cvxopt.matrix(low.indices.astype(np.int64)),
                            cvxopt.matrix(cols), (n, n))
        del low, cols
        # the given ordering exactly: no other method tried, no postordering
        cholmod.options.update(nmethods=1, postorder=False, supernodal=2)
        self._M, self._cvxopt, self._cholmod = M, cvxopt, cholmod
        self._numeric()

    def _numeric(self) -> None:
        """Factor (supernodal: a symbolic analysis in the given ordering, then
        the numbers)."""
        self._F = self._cholmod.symbolic(self._M, p=self._cvxopt.matrix(self.perm))
        try:
            self._cholmod.numeric(self._M, self._F)
        except ArithmeticError:
            raise ConfigError("the finite-element stiffness is not positive definite (a "
                              "material or the supports leave it singular)") from None

    @property
    def entries(self) -> int | None:
        """The values the factor holds (its memory is 8 bytes each), None
        when its layout is not the supernodal one read in place."""
        return factor_entries(self._F)

    def solve(self, b: np.ndarray) -> np.ndarray:
        x = self._cvxopt.matrix(np.asfortranarray(b, dtype=float))
        self._cholmod.solve(self._F, x)
        return np.asarray(x).reshape(b.shape)

    def contact_inverse(self) -> np.ndarray:
        """(A^-1) on the ``last`` dofs (k, k), in their given order: the
        inverse of the Schur complement L_cc L_ccᵀ, L_cc the factor's
        trailing block, read in place from the supernodal factor
        (:func:`~bemcontact.fem.supernodal.trailing_block`) and inverted in
        place (LAPACK's trtri, then lauum: L_cc^-ᵀ L_cc^-1), so that the
        dense part of the peak is one k × k array and the factor stays as it
        is for the solves."""
        Lcc = trailing_block(self._F, self.perm, self.n_last)
        if Lcc is None:  # a factor of another layout: read it through cvxopt
            Lcc = self._trailing_block_read_out()
        inv, info = scipy.linalg.lapack.dtrtri(Lcc, lower=1, overwrite_c=1)
        if info != 0:
            raise ConfigError("the finite-element Schur complement on the contact dofs is "
                              "singular (a contact node the supports do not hold)")
        out, info = scipy.linalg.lapack.dlauum(inv, lower=1, overwrite_c=1)
        del inv, Lcc
        return _symmetrized(out)

    def _trailing_block_read_out(self) -> np.ndarray:
        """The trailing block through cvxopt's ``getfactor``, which moves the
        factor's values out (CHOLMOD's factor_to_sparse): the matrix is
        factored again after it, and the factor is held twice meanwhile."""
        k, off = self.n_last, self.n - self.n_last
        L = self._cholmod.getfactor(self._F)
        tail = L[off:, off:]  # the trailing columns only, not a copy of all of L
        del L
        ptr, rows, vals = (np.asarray(a).ravel() for a in tail.CCS)
        del tail
        Lcc = np.zeros((k, k), order="F")
        for j in range(k):
            a, b = ptr[j], ptr[j + 1]
            Lcc[rows[a:b], j] = vals[a:b]
        del ptr, rows, vals
        self._numeric()
        return Lcc


def _dissection(A, rest: np.ndarray, groups: np.ndarray | None) -> np.ndarray:
    """A METIS nested-dissection ordering of the ``rest`` rows of ``A``
    (positions into ``rest``): of the graph of their ``groups`` (a label
    per row of A: a node's dofs), each group's rows kept together, which
    orders a graph a third the size and gives the factor bigger supernodes
    (7 % fewer entries, measured on a box of 199,287 dofs), or of the rows
    themselves without groups."""
    import pymetis

    if rest.size <= 1:
        return np.arange(rest.size)
    B = abs(A[rest][:, rest])
    if groups is not None:
        labels, g = np.unique(np.asarray(groups)[rest], return_inverse=True)
        P = scipy.sparse.csr_array((np.ones(rest.size), (g, np.arange(rest.size))),
                                   shape=(labels.size, rest.size))
        B = P @ B @ P.T
    G = scipy.sparse.csr_array(B)
    G.setdiag(0.0)
    G.eliminate_zeros()
    if not G.nnz:
        return np.arange(rest.size)
    order = np.asarray(pymetis.nested_dissection(
        pymetis.CSRAdjacency(G.indptr, G.indices))[0], dtype=np.int64)
    if groups is None:
        return order
    rank = np.empty(order.size, dtype=np.int64)
    rank[order] = np.arange(order.size)
    return np.lexsort((np.arange(rest.size), rank[g]))


def _symmetrized(a: np.ndarray, block: int = 512) -> np.ndarray:
    """``a`` (k, k) with its upper triangle replaced by its lower one's
    transpose, in place, a block of rows at a time."""
    k = a.shape[0]
    for j0 in range(0, k, block):
        j1 = min(j0 + block, k)
        d = a[j0:j1, j0:j1]
        d[...] = np.tril(d) + np.tril(d, -1).T
        a[j0:j1, j1:] = a[j1:, j0:j1].T
    return a


class FiniteElementFlexibility:
    """A finite-element body's flexibility on its contact nodes (made by
    :func:`condense`; the protocol's members)."""

    def __init__(self, **kw: Any) -> None:
        self.__dict__.update(kw)

    name = property(lambda self: self.body.name)
    points = property(lambda self: self.body.trace.points[self.nodes])
    F = property(lambda self: self._F)
    u0 = property(lambda self: self._u[self.contact_vdofs][:, : self._S])
    Rc = property(lambda self: self.Rf[self.contact_vdofs])
    Yc = property(lambda self: self._u[self.contact_vdofs][:, self._S:])
    CX = property(lambda self: self._CX)

    @property
    def CY(self) -> np.ndarray:
        """(nc, nc) controlled resultants per platen translation; a
        translation that strains nothing has none, exactly (as for a BEM
        body, :attr:`~bemcontact.bem.condensation.CondensedBody.CY`)."""
        CY = self._R[:, self._S:].copy()
        E = 1.0 / self.body.contact_compliance
        for k_, ctl in enumerate(self.controls):
            size = math.sqrt(self.body.trace.weights[ctl.dofs // 3].sum())
            if abs(CY[k_, k_]) <= 1e-8 * E * size:
                CY[k_, :] = 0.0
                CY[:, k_] = 0.0
        return CY

    def recombined(self, body, coef: np.ndarray, values: np.ndarray, controls,
                   forces: np.ndarray) -> FiniteElementFlexibility:
        """This condensation for other loads (as
        :meth:`~bemcontact.bem.condensation.CondensedBody.recombined`): the
        load responses, forces and held displacements combined by ``coef``."""
        S = self._S
        new = FiniteElementFlexibility(**self.__dict__)
        new.body, new.values, new.controls, new.forces = body, values, controls, forces
        states_u, states_R = self._u[:, :S] @ coef, self._R[:, :S] @ coef
        new.f_states, new.g_states = self.f_states @ coef, self.g_states @ coef
        new.known_modal_force = self.known_modal_force @ coef
        if self._body is not None:  # the body force, on in every state
            u_b, f_b, R_b, m_b = self._body
            states_u = states_u + u_b[:, None]
            states_R = states_R + R_b[:, None]
            new.f_states = new.f_states + f_b[:, None]
            new.known_modal_force = new.known_modal_force + m_b[:, None]
            new._body = None
        new.body_weights = np.ones(coef.shape[1]) if self.f_body.any() else self.body_weights @ coef
        new._u = np.hstack([states_u, self._u[:, S:]])
        new._R = np.hstack([states_R, self._R[:, S:]])
        new._S = coef.shape[1]
        new.timings = {"assembly": 0.0, "condensation": 0.0}
        return new

    def control_resultants(self, ell: np.ndarray) -> np.ndarray:
        return self._R[:, : self._S] @ ell

    def solution(self, lam, alpha, U, ell):
        """The body's fields on its trace for frame tractions ``lam``,
        free rigid-mode amplitudes ``alpha``, platen translations ``U`` and
        load weights ``ell`` (one solve), and each controlled region's
        translation."""
        b, d = self.body, self.body.trace
        f = self.f_states @ ell + self.Pc @ (self.modes.B @ lam)
        g = self.g_states @ ell
        for k_, Uk in enumerate(U):
            g = g + Uk * self.indicators[:, k_]
        u = self._solve(f[:, None], g[:, None])[:, 0]
        if alpha.size:
            u = u + self.Rf @ alpha
        r = self.K @ u - f  # the supports' and platens' forces on the body
        vd = self.trace_vdofs
        disp = u[vd]
        t = np.where(self.known_u, 0.0, self.values @ ell)
        # a held volume dof's force shared by the held trace dofs on it, by weight
        ku = np.flatnonzero(self.known_u)
        w = np.repeat(d.weights, 3)
        total = np.zeros(b.n_dofs)
        np.add.at(total, vd[ku], w[ku])
        t[ku] = r[vd[ku]] / total[vd[ku]]
        t[self.dofs] = self.modes.tractions(lam)
        controlled: dict[str, np.ndarray] = {}
        for ctl, Uk in zip(self.controls, U):
            controlled.setdefault(ctl.region, np.full(3, np.nan))[ctl.component] = Uk
        volume_force = None
        if self.f_body.any():  # the body force's share of f: its resultant and size
            fb = self.f_body.reshape(-1, 3) * float(self.body_weights @ ell)
            volume_force = (fb.sum(axis=0), float(np.linalg.norm(fb, axis=1).sum()))
        sol = VolumeSolution(points=d.points, normals=d.normals, volume_force=volume_force,
                             displacement=disp.reshape(-1, 3), traction=t.reshape(-1, 3),
                             weights=d.weights, region=d.region, region_names=b.region_names,
                             discretization=d, timings=dict(self.timings),
                             solver=dict(self.solver), volume_displacement=u.reshape(-1, 3))
        return sol, controlled

    def _solve(self, f: np.ndarray, g: np.ndarray) -> np.ndarray:
        """Full displacements (n, k) for nodal forces ``f`` and the held
        dofs' displacements ``g`` (n, k; read on the held dofs)."""
        u = np.zeros_like(f)
        u[self.held] = g[self.held]
        rhs = f[self.solved] - self.K_sh @ g[self.held]
        u[self.solved] = self.factor.solve(rhs)
        return u


def _volume_dofs(body, trace_dofs: np.ndarray) -> np.ndarray:
    return 3 * body.volume_node[trace_dofs // 3] + trace_dofs % 3


def condense(body, nodes: np.ndarray, states=None, progress=None, modes=None, *,
             load_fields=None) -> FiniteElementFlexibility:
    """Assemble and factor the body's stiffness and condense it on its
    contact ``nodes`` (trace functional nodes, no condition on them) for the
    load ``states`` and the frame's traction ``modes`` (required: the
    contact solver's)."""
    if modes is None:
        raise ConfigError(f"{body.name}: a finite-element body is condensed on the frame's "
                          "traction modes (condense(..., modes=...))")
    d = body.trace
    t0 = time.perf_counter()
    what = f"{body.name}: {body.n_dofs:,} finite-element dofs, {nodes.size:,} contact nodes"
    if progress is not None:
        progress(ProgressEvent("start", "assembly", f"assembly {what}"))
    states = [body.boundary_conditions] if states is None else list(states)
    data = [body.boundary_data(c) for c in states]
    known_u = data[0][0]
    controls = body.controls(states[0])
    values = np.column_stack([v for _, v in data])
    forces = np.array([[c.force for c in body.controls(st)] for st in states]).reshape(
        len(states), len(controls)).T
    if load_fields is not None:
        values = np.asarray(load_fields, dtype=float).reshape(3 * d.n_points, -1)
        forces = np.zeros((len(controls), values.shape[1]))
    S = values.shape[1]
    dofs = (3 * nodes[:, None] + np.arange(3)).ravel()
    if known_u[dofs].any() or np.any(values[dofs] != 0):
        raise ConfigError(f"{body.name}: the contact surface also has a boundary condition; "
                          "remove it (the contact decides the tractions there)")
    n = body.n_dofs
    vd = _volume_dofs(body, np.arange(3 * d.n_points))
    # held volume dofs and their displacement per state; platens' indicators
    ku = np.flatnonzero(known_u)
    held = np.zeros(n, dtype=bool)
    held[vd[ku]] = True
    g_states = np.zeros((n, S))
    g_states[vd[ku]] = values[ku]
    indicators = np.zeros((n, len(controls)))
    for k_, ctl in enumerate(controls):
        indicators[vd[ctl.dofs], k_] = 1.0
        g_states[vd[ctl.dofs]] = 0.0
    # the tractions' consistent nodal forces
    M = trace_mass(d)
    T = np.where(known_u[:, None], 0.0, values).reshape(d.n_points, 3 * S)
    f_trace = (M @ T).reshape(3 * d.n_points, S)
    f_states = np.zeros((n, S))
    np.add.at(f_states, vd, f_trace)
    # the body force is on in every state; the load fields of a reusable
    # condensation hold none: its response is kept apart and added to each
    # state by recombined
    f_body = nodal_body_forces(body)
    if load_fields is None:
        f_states += f_body[:, None]
    K, _ = body.stiffness()
    # free rigid modes, and the pins that hold them
    X = body.volume.node_points
    x = X - X.mean(axis=0)
    R = np.zeros((X.shape[0], 3, 6))
    for j in range(3):
        R[:, j, j] = 1.0
        e = np.zeros(3)
        e[j] = 1.0
        R[:, :, 3 + j] = np.cross(e, x)
    R = R.reshape(n, 6)
    Rn = R / np.linalg.norm(R, axis=0)
    Z = scipy.linalg.null_space(Rn[held], rcond=1e-9) if held.any() else np.eye(6)
    Rf = Rn @ Z
    Rf[held] = 0.0
    nf = Rf.shape[1]
    solved = ~held
    if nf:
        free_idx = np.flatnonzero(solved)
        _, _, piv = scipy.linalg.qr(Rf[free_idx].T, mode="economic", pivoting=True)
        solved[free_idx[piv[:nf]]] = False
    fixed = ~solved
    K = K.tocsr()
    Kss = K[solved][:, solved]
    K_sh = K[solved][:, fixed].tocsr()
    t1 = time.perf_counter()
    contact_vdofs = vd[dofs]
    index = np.full(n, -1, dtype=np.int64)
    index[np.flatnonzero(solved)] = np.arange(int(solved.sum()))
    cs = index[contact_vdofs]  # each contact dof's solved index (-1: pinned)
    factor = SchurFactor(Kss, cs[cs >= 0], groups=np.flatnonzero(solved) // 3)
    Pc = scipy.sparse.csr_array((np.ones(dofs.size), (contact_vdofs, np.arange(dofs.size))),
                                shape=(n, dofs.size))
    flex = FiniteElementFlexibility(
        body=body, nodes=nodes, dofs=dofs, known_u=known_u, values=values, controls=controls,
        forces=forces, modes=modes, K=K, K_sh=K_sh, held=fixed, solved=solved, factor=factor,
        f_states=f_states, g_states=g_states, indicators=indicators, Rf=Rf, Pc=Pc,
        contact_vdofs=contact_vdofs, trace_vdofs=vd, _S=S,
        known_modal_force=Rf.T @ f_states, _body=None, f_body=f_body,
        body_weights=np.ones(S) if load_fields is None else np.zeros(S),
    )
    if progress is not None:
        progress(ProgressEvent("end", "assembly", f"assembly {what}", seconds=t1 - t0))
        progress(ProgressEvent("start", "condensation", f"condensation {body.name}"))
    # reactions on the controlled components: C (K u - f)
    Crows = scipy.sparse.csr_array(indicators.T) @ K if controls else None
    # load states and platens (kept whole: recovery), then the modes (contact rows)
    apart = load_fields is not None and f_body.any()
    cols_f = np.hstack([f_states, np.zeros((n, len(controls)))]
                       + ([f_body[:, None]] if apart else []))
    cols_g = np.hstack([g_states, indicators] + ([np.zeros((n, 1))] if apart else []))
    u = flex._solve(cols_f, cols_g)
    R = (Crows @ u - indicators.T @ cols_f) if controls else np.zeros((0, u.shape[1]))
    # the body force's response, force, reactions and modal force, or None
    flex._body = (u[:, -1], f_body, R[:, -1], Rf.T @ f_body) if apart else None
    flex._u, flex._R = (u[:, :-1], R[:, :-1]) if apart else (u, R)
    # the flexibility on the contact dofs (the Schur complement's inverse;
    # a pinned dof does not move), its responses to the modes, and by
    # reciprocity the platens' reactions to them: C K u_m = -(Y on the
    # contact dofs)ᵀ B_m (no contact dof is a platen's)
    kept = np.flatnonzero(cs >= 0)
    if kept.size == dofs.size:
        S_cc = factor.contact_inverse()
    else:  # a pinned contact dof does not move
        S_cc = np.zeros((dofs.size, dofs.size))
        S_cc[np.ix_(kept, kept)] = factor.contact_inverse()
    B = modes.B.tocsc()
    F = np.asarray((B.T @ S_cc).T)
    flex._F = F
    flex._CX = -np.asarray((B.T @ flex.Yc).T) if controls else np.zeros((0, modes.size))
    t2 = time.perf_counter()
    flex.timings = {"assembly": t1 - t0, "condensation": t2 - t1}
    flex.solver = {"method": "fem (sparse Cholesky)", "dofs": int(n), "pins": int(nf)}
    if progress is not None:
        progress(ProgressEvent("end", "condensation", f"condensation {body.name}",
                               seconds=t2 - t1))
    return flex


__all__ = ["FiniteElementFlexibility", "SchurFactor", "condense"]

"""Results of a solved interface system: the frame's tractions, gaps, slips
and states, each body's full solution recovered from its condensed response,
each body's interface against the other, and the contact forces."""

from __future__ import annotations

import numpy as np

from ..mesh.element import element_geometry
from .search import locate
from .results import ContactResult, FrameResult, InterfaceResult, PairResult


class Recovery:
    """The results of an :class:`~bemcontact.contact.interface.InterfaceSystem`
    at its solutions: each body's fields from its flexibility
    (:class:`~bemcontact.contact.flexibility.Flexibility`), the frame's and
    the interfaces' fields; where each contact node sits on the other side's
    surface is geometry, computed once per solve (:meth:`located`)."""

    def __init__(self, system) -> None:
        self.system = system
        self._located: dict[tuple[int, int], tuple] = {}

    def __call__(self, z, ell, steps) -> ContactResult:
        """The :class:`ContactResult` at the solution ``z`` for the load
        weights ``ell``: frame tractions, gaps, slips and states of every
        pair (judged against the law's stick reference, the increment's),
        each body's full solution, the interface of each body against the
        other in each pair, forces, and the Newton ``steps``."""
        system = self.system
        fs = system.frames
        lam, parts = system.split(z)
        kk = system.k(z, ell)
        lam3 = lam.reshape(-1, 3)
        # the state and the slip increment as the law judges them (in a
        # steady rolling step against the convected slip); the gap and the
        # slip from the physical map
        kl = system.law_k(z, ell)
        state = system.law.state(lam3, kl)
        # the slip increment kk - k_prev is the law's kl - reference
        k_prev = system.law.reference + (kk[:, :2] - kl[:, :2])
        k_init = system.k0X.reshape(-1, 3)
        sols = []
        controlled: dict[str, dict[str, np.ndarray]] = {}
        for i, c in enumerate(system.cb):
            sol, moved = c.solution(lam, parts[2 * i], parts[2 * i + 1], ell)
            sols.append(sol)
            if moved:
                controlled[c.name] = moved
        names = [c.name for c in system.cb]
        pairs = []
        for p, (fr, act, link) in enumerate(zip(fs.frames, fs.act, fs.links)):
            nodes = fs.slice(p)
            pairs.append(_pair(self, p, fr, act, lam3[nodes], kk[nodes], k_init[nodes],
                               k_prev[nodes], state[nodes], system.a[nodes],
                               [sols[a] for a in link], [names[a] for a in link]))
        first = pairs[0]
        return ContactResult(
            converged=all(s.converged for s in steps) and len(steps) > 0,
            newton_iterations=sum(s.iterations for s in steps),
            steps=steps,
            normal_force=first.normal_force,
            tangential_force=first.tangential_force,
            contact_force=first.contact_force,
            bodies=tuple(sols),
            names=tuple(names),
            interfaces=first.interfaces,
            frame=first.frame,
            pairs=pairs,
            control_displacements=controlled,
        )

    def located(self, p: int, side: int, sols):
        """Where each contact node of side ``side`` of pair ``p`` sits on the
        other side's contact surface: (element (n,), inside (n,), point
        (n, 3), the other body's functional basis there (n, k)); ``sols``
        the two bodies' solutions (their surface traces)."""
        if (p, side) not in self._located:
            fr = self.system.frames.frames[p]
            od = sols[1 - side].discretization
            X = sols[side].points[fr.nodes(side)]
            el, xi, inside = locate(od, fr.surface_elements(1 - side), X, fr.search_distance)
            xo, _, _ = element_geometry(od.mesh, el, xi)
            self._located[p, side] = (el, inside, xo, od.basis_at(el, xi))
        return self._located[p, side]


def _pair(rec, p, fr, act, lam3, kk, k_init, k_prev, state_act, a, sols,
          names) -> PairResult:
    """Pair p's frame fields, forces and interfaces (its active nodes'
    tractions ``lam3``, relative displacements ``kk``, their initial values
    ``k_init`` and those at the increment's start ``k_prev``, states and
    weights ``a``; its two bodies' solutions and names)."""
    system = rec.system
    Q = fr.Q[act]

    # frame results (inactive nodes: open, zero traction, NaN gap)
    def full(v, fill=0.0):
        out = np.full((fr.n_frame,) + v.shape[1:], fill, dtype=v.dtype)
        out[act] = v
        return out

    t_glob = np.einsum("jcl,jl->jc", Q[:, :, :2], lam3[:, :2])
    slip = np.einsum("jcl,jl->jc", Q[:, :, :2], kk[:, :2] - k_init[:, :2])
    increment = np.einsum("jcl,jl->jc", Q[:, :, :2], kk[:, :2] - k_prev)
    nodes = system.frames.slice(p)
    frame_res = FrameResult(
        points=fr.points,
        normals=fr.Q[:, :, 2],
        pressure=full(lam3[:, 2]),
        tangential_traction=full(t_glob),
        gap=full(kk[:, 2], np.nan),
        slip=full(slip),
        state=full(state_act.astype(np.int8), np.int8(0)),
        weights=fr.weights,
        slip_increment=full(increment),
        friction=full(np.asarray(system.law.mu[nodes], dtype=float)),
        augmentation=full(np.asarray(system.law.r[nodes], dtype=float), np.inf),
    )
    F = np.einsum("j,jcl,jl->c", a, Q, lam3)  # force on body 2
    # what the coupling transmits to each body (-lam to body 1, +lam to body
    # 2, weighted by the integrals of the frame basis over that body's
    # contact surface, c_j = sum_p D[p, j]), and what it does not: the
    # coverage difference of the two surfaces (0 for a mortar frame whose
    # surfaces both cover every frame node's support)
    tg = np.einsum("jcl,jl->jc", Q, lam3)
    c = [np.asarray(fr.D[side].sum(axis=0)).ravel()[act] for side in range(2)]
    transmitted = np.array([-(c[0] @ tg), c[1] @ tg])
    untransmitted = float(np.abs(c[1] - c[0]) @ np.linalg.norm(tg, axis=1))
    nbar = np.einsum("j,jc->c", a, Q[:, :, 2])
    nbar /= max(float(np.linalg.norm(nbar)), np.finfo(float).tiny)
    Fn = float(F @ nbar)
    Ft = float(np.linalg.norm(F - Fn * nbar))
    ifaces = tuple(_interface(rec, p, side, sols, names[side], frame_res.state, act)
                   for side in range(2))
    return PairResult(
        names=(names[0], names[1]),
        surfaces=(ifaces[0].surface, ifaces[1].surface),
        normal_force=Fn, tangential_force=Ft, contact_force=F,
        interfaces=ifaces, frame=frame_res, transmitted=transmitted,
        untransmitted=untransmitted,
    )


def _interface(rec, p, side, sols, name, frame_state, act) -> InterfaceResult:
    """The contact nodes of side ``side`` of pair ``p``: tractions,
    pointwise gap and slip against the other side's surface, the state of
    the frame node most strongly coupled to each node, and whether it is
    coupled to an active frame node (``act``) at all."""
    fr = rec.system.frames.frames[p]
    sol, other_sol = sols[side], sols[1 - side]
    d = sol.discretization
    nodes = fr.nodes(side)
    X = d.points[nodes]
    n = d.normals[nodes]
    u = sol.displacement[nodes]
    t = sol.traction[nodes]
    tn = np.einsum("pc,pc->p", t, n)
    # pointwise gap and slip against the other body's surface
    od = other_sol.discretization
    el, inside, xo, phi = rec.located(p, side, sols)
    k = od.mesh.elements.shape[1]
    uo = np.einsum("pk,pkc->pc", phi, other_sol.displacement[od.fconn[el, :k]])
    rel = (xo + uo) - (X + u)
    gap = np.where(inside, np.einsum("pc,pc->p", rel, n), np.nan)
    du = u - uo
    slip = du - np.einsum("pc,pc->p", du, n)[:, None] * n
    slip[~inside] = np.nan
    # state: that of the frame node most strongly coupled to the node
    D = abs(fr.D[side]).tocsr()
    strongest = np.asarray(D.argmax(axis=1)).ravel()
    coupled = np.asarray(D.sum(axis=1)).ravel() > 0
    paired = np.asarray(D[:, act].sum(axis=1)).ravel() > 0
    # nodes off the other body's surface are open whatever their coupling
    state = np.where(coupled & inside, frame_state[strongest], 0).astype(np.int8)
    return InterfaceResult(
        body=name, surface=sol.region_names[int(d.region[nodes[0]])], nodes=nodes,
        points=X, normals=n, displacement=u, traction=t, pressure=-tn,
        tangential_traction=t - tn[:, None] * n, gap=gap, slip=slip, state=state,
        weights=d.weights[nodes], paired=paired,
    )


__all__ = ["Recovery"]

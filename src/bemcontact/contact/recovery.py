"""Results of a solved interface system: the frame's tractions, gaps, slips
and states, each body's full solution recovered from its condensed response,
each body's interface against the other, and the contact forces."""

from __future__ import annotations

import numpy as np

from ..bem.body import BodySolution
from . import law
from .results import ContactResult, FrameResult, InterfaceResult


def recover(system, z, ell, k_prev, steps, bodies) -> ContactResult:
    """The :class:`ContactResult` at the solution ``z`` of ``system`` (an
    :class:`~bemcontact.contact.interface.InterfaceSystem`) for the load
    weights ``ell``: frame tractions, gaps, slips and states (judged against
    the increment's starting slip ``k_prev``), each body's full solution
    (one product per body with its condensed response), the interface of
    each body against the other, forces, and the Newton ``steps``."""
    fr = system.frame
    lam, parts = system.split(z)
    kk = system.k(z, ell)
    lam3 = lam.reshape(-1, 3)
    state_act = law.contact_state(lam3, kk, k_prev, system.mu_nodes, system.r, system.r)
    act = system.act
    Q = fr.Q[act]
    mfull = fr.n_frame
    # frame results (inactive nodes: open, zero traction, NaN gap)
    def full(v, fill=0.0):
        out = np.full((mfull,) + v.shape[1:], fill, dtype=v.dtype)
        out[act] = v
        return out

    t_glob = np.einsum("jcl,jl->jc", Q[:, :, :2], lam3[:, :2])
    k_init = system.k0X.reshape(-1, 3)
    slip = np.einsum("jcl,jl->jc", Q[:, :, :2], kk[:, :2] - k_init[:, :2])
    frame_res = FrameResult(
        points=fr.points,
        normals=fr.Q[:, :, 2],
        pressure=full(lam3[:, 2]),
        tangential_traction=full(t_glob),
        gap=full(kk[:, 2], np.nan),
        slip=full(slip),
        state=full(state_act.astype(np.int8), np.int8(0)),
        weights=fr.weights,
    )
    F = np.einsum("j,jcl,jl->c", system.a, Q, lam3)  # force on body 2
    nbar = np.einsum("j,jc->c", system.a, Q[:, :, 2])
    nbar /= np.linalg.norm(nbar)
    Fn = float(F @ nbar)
    Ft = float(np.linalg.norm(F - Fn * nbar))
    sols, ifaces = [], []
    controlled: dict[str, dict[str, np.ndarray]] = {}
    state_full = frame_res.state
    for i, (c, b) in enumerate(zip(system.cb, bodies)):
        d = b.discretization
        tc = c.tractions(lam)
        al, U = parts[2 * i], parts[2 * i + 1]
        x = c.x0 @ ell + c.X @ lam
        if al.size:
            x = x + c.Rf @ al
        if U.size:
            x = x + c.Y @ U
        vals = c.values @ ell
        for ctl, Uk in zip(c.controls, U):
            vals[ctl.dofs] = Uk
            controlled.setdefault(b.name, {}).setdefault(
                ctl.region, np.full(3, np.nan)
            )[ctl.component] = Uk
        u = np.where(c.known_u, vals, x)
        t = np.where(c.known_u, x, vals)
        t[c.dofs] = tc
        sols.append(
            BodySolution(
                points=d.points, normals=d.normals, displacement=u.reshape(-1, 3),
                traction=t.reshape(-1, 3), weights=d.weights, region=d.region,
                region_names=b.mesh.region_names, discretization=d,
                timings=dict(c.timings),
            )
        )
    for i, (c, b) in enumerate(zip(system.cb, bodies)):
        ifaces.append(_interface(system, i, sols[i], sols[1 - i], state_full))
    return ContactResult(
        converged=all(s.converged for s in steps) and len(steps) > 0,
        newton_iterations=sum(s.iterations for s in steps),
        steps=steps,
        normal_force=Fn,
        tangential_force=Ft,
        contact_force=F,
        bodies=(sols[0], sols[1]),
        names=(bodies[0].name, bodies[1].name),
        interfaces=(ifaces[0], ifaces[1]),
        frame=frame_res,
        control_displacements=controlled,
    )


def _interface(system, i, sol, other_sol, frame_state) -> InterfaceResult:
    """Body ``i``'s contact nodes: tractions, pointwise gap and slip
    against the other body's surface, and the state of the frame node most
    strongly coupled to each node."""
    fr = system.frame
    c = system.cb[i]
    b = c.body
    d = b.discretization
    nodes = c.nodes
    X = d.points[nodes]
    n = d.normals[nodes]
    u = sol.displacement[nodes]
    t = sol.traction[nodes]
    tn = np.einsum("pc,pc->p", t, n)
    # pointwise gap and slip against the other body's surface
    od = system.cb[1 - i].body.discretization
    el, inside, xo, phi = system.located(i)
    k = od.mesh.elements.shape[1]
    uo = np.einsum("pk,pkc->pc", phi, other_sol.displacement[od.fconn[el, :k]])
    rel = (xo + uo) - (X + u)
    gap = np.where(inside, np.einsum("pc,pc->p", rel, n), np.nan)
    du = u - uo
    slip = du - np.einsum("pc,pc->p", du, n)[:, None] * n
    slip[~inside] = np.nan
    # state: that of the frame node most strongly coupled to the node
    D = abs(fr.D[i]).tocsr()
    strongest = np.asarray(D.argmax(axis=1)).ravel()
    coupled = np.asarray(D.sum(axis=1)).ravel() > 0
    # nodes off the other body's surface are open whatever their coupling
    state = np.where(coupled & inside, frame_state[strongest], 0).astype(np.int8)
    return InterfaceResult(
        body=b.name, surface=b.mesh.region_names[int(d.region[nodes[0]])], nodes=nodes,
        points=X, normals=n, displacement=u, traction=t, pressure=-tn,
        tangential_traction=t - tn[:, None] * n, gap=gap, slip=slip, state=state,
        weights=d.weights[nodes],
    )


__all__ = ["recover"]

"""The contact frame: an independent surface between the two contact
surfaces, its local bases, and the coupling of each body's interface nodes to
it (founding paper, eqs. 10-16; docs/frame.md).

Frame discretization (the rule, see docs/frame.md for the comparison)
--------------------------------------------------------------------
* Geometry: the frame's elements are those of the *coarser* of the two
  contact surfaces (larger mean element area; ties broken by the node count,
  then by the geometry itself, never by which body is called "1"), so
  swapping the bodies gives the same frame.  With ``between`` (the default of
  :class:`~bemcontact.contact.ContactPair`) they are moved *between* the two
  surfaces, as the founding paper keeps the frame: each frame node midway
  between its owner-surface point and that point's projection on the other
  surface, its normal bisecting the two surfaces' outward normals, n = (n_1 -
  n_2)/|n_1 - n_2|; the mortar integrals are taken in the planes of those
  bisecting normals, so opposite points are paired across the frame, not
  along one body's normal.  Otherwise the frame lies on the owner's surface
  with its normals (a curved owner then tilts the contact normal by r/R
  against the true contact surface: docs/frame.md).
* Interpolation: continuous, *linear* (P1 on triangles, Q1 on quadrilaterals)
  on the corner nodes of those elements, whatever the bodies' element order:
  nonnegative basis functions, so nodal weights ∫N_j > 0 and a nodal
  complementarity condition means something, and constants are represented,
  which is all the patch test needs.
* Unknowns per frame node j: the contact traction lam_j acting on body 2
  (body 1 receives -lam_j) and the relative displacement k_j of body 2 with
  respect to body 1, both in the node's local basis Q_j = [t1 t2 n], n from
  body 1 into body 2.
* Coupling (rule ``"mortar"``): the localized multipliers of body a are its
  nodal contact forces f_a = M_a t_a (energy-consistent lumping, eqs. 15-16,
  M_a = ∫ phi_p phi_q).  They are tied to the frame by the area-consistent
  matrices D_a[p, j] = ∫ phi_p N_j dS, integrated exactly over the
  intersections of body elements and frame elements (polygon clipping in the
  frame element's plane):

      f_2 = D_2 Q lam,   f_1 = -D_1 Q lam                 (frame equilibrium)
      a_j k_j = Q_j^T [D_2^T x_2 - D_1^T x_1]_j           (weighted gap / slip)

  with a_j = ∫ N_j dS over the common area, or, projected (the default),
  the nodal values of the relative displacement's L2 projection on the
  frame basis, with M_f = ∫ N_i N_j over the common area:

      k_j = Q_j^T [M_f^-1 (D_2^T x_2 - D_1^T x_1)]_j      (projected)

  The weighted form spreads each node's contact and stick condition over
  its support (two elements), which smears the contact edge and the
  stick-slip front; the projected form keeps them nodal (docs/frame.md).
  Because sum_p phi_p = 1, sum_p D_1[p, j] = sum_q D_2[q, j] = a_j for
  *any* pair of meshes, which is the frame-equilibrium condition (*) of
  docs/frame.md: the contact patch test is passed to quadrature precision on
  arbitrary non-matching meshes, with either form (the projection
  reproduces the linear relative displacement of the patch test exactly).
* Rule ``"collocation"`` (the paper's point evaluation, kept for comparison):
  D_a[p, j] = w_p N_j(xi_p), with xi_p the projection of body node p on the
  frame and w_p = ∫ phi_p.  Condition (*) then fails on non-matching meshes,
  and so does the patch test.
"""


from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse

from ..bem.discretization import Discretization
from ..errors import ConfigError
from ..mesh.element import CORNERS, REFERENCE_NODES, element_geometry, inverse_map, lagrange_basis
from .search import (
    candidate_pairs, clip_polygons, locate, polygon_areas, tangent_basis, triangle_rule,
)

_LINEAR = {"tri": ("tri3", 0), "quad": ("quad4", 2)}


# --------------------------------------------------------------------------- frame


@dataclass
class _Surface:
    disc: Discretization
    elements: np.ndarray  # contact elements
    nodes: np.ndarray  # contact functional nodes (sorted)
    local: np.ndarray  # functional node -> row in nodes (or -1)


def _surface(disc: Discretization, region: str, who: str) -> _Surface:
    mesh = disc.mesh
    if region not in mesh.region_names:
        raise ConfigError(
            f"{who}: unknown contact surface {region!r}; the mesh has regions "
            f"{list(mesh.region_names)}"
        )
    rid = mesh.region_names.index(region)
    elements = np.flatnonzero(mesh.element_region == rid)
    nodes = np.flatnonzero(disc.region == rid)
    local = np.full(disc.n_points, -1, dtype=np.int64)
    local[nodes] = np.arange(nodes.size)
    return _Surface(disc, elements, nodes, local)


#: A frame node counts as covered (:attr:`ContactFrame.covered`) when the
#: other surface covers at least this fraction of each of its elements and
#: of its neighbours' elements.
COVERED = 0.999

#: A contact surface is flat when its element normals (at the centroids)
#: deviate from their mean by less than this (1 - cos of the angle: about
#: 1.4e-5 rad); a sphere of radius R meshed at h has angles of order h/R.
FLAT_TOLERANCE = 1e-10


def _is_flat(sf: _Surface) -> bool:
    mesh = sf.disc.mesh
    cen = np.tile(np.array([1 / 3, 1 / 3]) if mesh.element_type.startswith("tri") else np.zeros(2),
                  (sf.elements.size, 1))
    _, n, _ = mesh.map(sf.elements, cen)
    mean = n.sum(axis=0)
    norm = np.linalg.norm(mean)
    return bool(norm > 0 and (1.0 - (n @ (mean / norm)).min()) < FLAT_TOLERANCE)


def _smooth_normals(disc: Discretization, elements: np.ndarray, xi: np.ndarray) -> np.ndarray:
    """Unit normals (P, 3) interpolated from the functional nodes' normals
    (averaged over the elements at shared nodes) at ``xi`` in ``elements``:
    close to the smooth surface's normal, unlike a flat element's own."""
    k = disc.mesh.elements.shape[1]
    phi = disc.basis_at(elements, xi)
    n = np.einsum("pk,pkc->pc", phi, disc.normals[disc.fconn[elements, :k]])
    return n / np.linalg.norm(n, axis=1)[:, None]


class ContactFrame:
    """The contact frame of a pair of contact surfaces and the coupling
    matrices of both bodies (see the module docstring for the rule).

    Attributes (m frame nodes, n_a contact nodes of body a)
    ----------
    owner: 0 or 1, the body whose contact surface carries the frame.
    points: (m, 3) frame node positions.  Q: (m, 3, 3) local bases, columns
    (t1, t2, n), n from body 1 into body 2.  weights: (m,) a_j = ∫ N_j over
    the common area.  size: (m,) h_j = sqrt(A_j), A_j = ∫ N_j over the
    frame surface's elements around node j, whether the other body covers
    them or not (a node the other body barely reaches keeps its element
    size: sqrt(a_j) would make its penalty c E*/h_j arbitrarily large).
    nodes: (n_1,), (n_2,) the contact functional nodes of each body.
    D: (n_1, m), (n_2, m) coupling matrices (``scipy.sparse`` CSR arrays).
    M: (n_1, n_1), (n_2, n_2) consistent interface mass matrices (sparse CSC).
    mass: (m, m) the frame's consistent mass ∫ N_i N_j over the common area
    (sparse CSC; its row sums are the weights).  projected: whether the
    nodal law acts on the projected relative displacement M_f^-1 ∫ N [u]
    (True, rule "mortar") or on the weighted one diag(a)^-1 ∫ N [u].
    covered: (m,) whether the other surface covers each node's frame
    elements and its neighbours' (to :data:`COVERED`).
    projection: per body, (element of the frame-owner surface, xi) of each
    contact node's projection on the frame (xi_p), and whether it falls on
    the frame.
    """

    def __init__(
        self,
        disc1: Discretization,
        surface1: str,
        disc2: Discretization,
        surface2: str,
        rule: str = "mortar",
        *,
        names: tuple[str, str] = ("body 1", "body 2"),
        quadrature_order: int = 6,
        search_distance: float | None = None,
        owner: int | None = None,
        between: bool | str = False,
        projected: bool = True,
    ) -> None:
        if rule not in ("mortar", "collocation"):
            raise ConfigError(f"frame rule must be 'mortar' or 'collocation', got {rule!r}")
        if search_distance is not None and not (
            isinstance(search_distance, (int, float)) and 0 < search_distance < np.inf
        ):
            raise ConfigError(
                f"frame search_distance must be a finite number > 0 or None, got {search_distance!r}"
            )
        if owner not in (None, 0, 1):
            raise ConfigError(f"frame owner must be None, 0 or 1, got {owner!r}")
        if between not in (True, False, "auto"):
            raise ConfigError(f"frame between must be True, False or 'auto', got {between!r}")
        self.rule = rule
        #: the nodal law acts on the relative displacement projected on the
        #: frame basis (M_f k = ∫ N [u]) rather than weighted (a_j k_j = ∫ N_j [u])
        self.projected = bool(projected) and rule == "mortar"
        self.names = names
        s = (_surface(disc1, surface1, names[0]), _surface(disc2, surface2, names[1]))
        for a in range(2):
            if s[a].elements.size == 0:
                raise ConfigError(f"{names[a]}: contact surface is empty")
        self._s = s
        self.search_distance = self._search_distance(search_distance)
        #: (body 1, body 2): whether each contact surface is flat
        self.flat = (_is_flat(s[0]), _is_flat(s[1]))
        if between == "auto":
            # on the flat surface when one is (the small-slope contact plane of
            # Hertz and Cattaneo-Mindlin); between two curved ones (docs/frame.md)
            between = not any(self.flat)
            if owner is None and self.flat[0] != self.flat[1]:
                owner = 0 if self.flat[0] else 1
        self.between = bool(between)
        self.owner = self._choose_owner() if owner is None else owner
        self._build_frame_nodes()
        self._integrate(quadrature_order)
        self._project_nodes()
        if rule == "collocation":
            self._collocation_coupling()
        self._masses()

    # ---------------------------------------------------------------- choices
    def _search_distance(self, given: float | None) -> float:
        """Largest normal distance at which surface points are paired: the
        user's value, or a quarter of the largest contact element."""
        if given is not None:
            return float(given)
        sizes = []
        for sf in self._s:
            mesh = sf.disc.mesh
            C = mesh.nodes[mesh.elements[sf.elements, : CORNERS[mesh.element_type]]]
            sizes.append(float(np.max(C.max(axis=1) - C.min(axis=1))))
        return 0.25 * max(sizes)

    @property
    def placement(self) -> str:
        """Where the frame lies, in words: ``between the surfaces`` or ``on
        <body>'s surface``."""
        return "between the surfaces" if self.between else f"on {self.names[self.owner]}'s surface"

    def _choose_owner(self) -> int:
        keys = []
        for sf in self._s:
            mesh = sf.disc.mesh
            area = float(mesh.surface_quadrature(4, sf.elements).weights.sum())
            keys.append((area / sf.elements.size, -sf.nodes.size))
        if not np.isclose(keys[0][0], keys[1][0], rtol=1e-9):
            return 0 if keys[0][0] > keys[1][0] else 1
        if keys[0][1] != keys[1][1]:
            return 0 if keys[0][1] > keys[1][1] else 1
        # same size and count: order by the node coordinates (label independent)
        a = np.sort(self._s[0].disc.points[self._s[0].nodes].round(12), axis=None)
        b = np.sort(self._s[1].disc.points[self._s[1].nodes].round(12), axis=None)
        diff = np.flatnonzero(a != b)
        return 0 if diff.size == 0 or a[diff[0]] < b[diff[0]] else 1

    def _build_frame_nodes(self) -> None:
        sf = self._s[self.owner]
        mesh = sf.disc.mesh
        nc = CORNERS[mesh.element_type]
        corners = mesh.elements[sf.elements, :nc]
        geo, inv = np.unique(corners, return_inverse=True)
        self._fconn = inv.reshape(corners.shape)  # (m_e, nc) frame node ids
        self._linear = _LINEAR["tri" if mesh.element_type.startswith("tri") else "quad"][0]
        self._ref = REFERENCE_NODES[self._linear]
        m = geo.size
        self.points = mesh.nodes[geo].copy()
        # normals at frame nodes: average of the owner's element normals at its corners
        e_idx = np.repeat(sf.elements, nc)
        _, n_at, _ = mesh.map(e_idx, np.tile(REFERENCE_NODES[mesh.element_type][:nc], (len(sf.elements), 1)))
        acc = np.zeros((m, 3))
        np.add.at(acc, self._fconn.ravel(), n_at)
        n = acc / np.linalg.norm(acc, axis=1)[:, None]
        if self.between:
            self.points, n = self._between(self.points, n)
        if self.owner == 1:
            n = -n  # frame normal points from body 1 into body 2
        t1, t2 = tangent_basis(n)
        self.Q = np.stack([t1, t2, n], axis=2)
        self.n_frame = m

    # ------------------------------------------------------------- integrals
    def _integrate(self, order: int) -> None:
        own, oth = self._s[self.owner], self._s[1 - self.owner]
        do, dt = own.disc, oth.disc
        mo, mt = do.mesh, dt.mesh
        nco, nct = CORNERS[mo.element_type], CORNERS[mt.element_type]
        Eo, Et = own.elements, oth.elements
        # element planes of the owner (frame) elements
        cen_o = np.tile(np.array([1 / 3, 1 / 3]) if mo.element_type.startswith("tri") else np.zeros(2), (Eo.size, 1))
        c_o, n_o, _ = mo.map(Eo, cen_o)
        # the planes of the mortar integrals: the owner's element planes, or
        # the planes bisecting the two surfaces (pairing across the frame)
        if self.between:
            t1, t2 = tangent_basis(self._between(c_o, _smooth_normals(do, Eo, cen_o))[1])
        else:
            t1, t2 = tangent_basis(n_o)
        Co = mo.nodes[mo.elements[Eo, :nco]]  # (Eo, nco, 3)
        Ct = mt.nodes[mt.elements[Et, :nct]]
        # candidate pairs: the other element's corners, in the owner element's
        # plane, overlap its bounding rectangle (inflated by a quarter element)
        # and lie within the search distance along its normal
        pairs = candidate_pairs(Co, c_o, t1, t2, n_o, Ct, self.search_distance)
        search = self.search_distance
        rule_p, rule_w = triangle_rule(order)
        i, j = pairs[:, 0], pairs[:, 1]
        # skip elements far off the plane, or not facing each other (outward
        # normals of touching faces are opposite)
        near = np.abs(np.einsum("pkd,pd->pk", Ct[j] - c_o[i][:, None, :], n_o[i])).min(axis=1) <= search
        nt = np.cross(Ct[j][:, 1] - Ct[j][:, 0], Ct[j][:, 2] - Ct[j][:, 0])
        nt /= np.linalg.norm(nt, axis=1)[:, None]
        facing = np.einsum("pd,pd->p", nt, n_o[i])
        same_way = int(np.count_nonzero(near & (facing > 0.5)))
        sel = near & (facing <= -0.5)
        i, j = i[sel], j[sel]
        T = np.stack([t1[i], t2[i]], axis=2)  # (p, 3, 2)
        A = np.einsum("pkd,pdl->pkl", Co[i] - c_o[i][:, None, :], T)
        B = np.einsum("pkd,pdl->pkl", Ct[j] - c_o[i][:, None, :], T)
        # both counter-clockwise in the plane seen from the owner's normal side
        areaA = polygon_areas(A, np.full(len(A), A.shape[1]))
        A = np.where((areaA < 0)[:, None, None], A[:, ::-1], A)
        areaA = np.abs(areaA)
        areaB = polygon_areas(B, np.full(len(B), B.shape[1]))
        B = np.where((areaB < 0)[:, None, None], B[:, ::-1], B)
        P, cnt = clip_polygons(B, A)
        area = polygon_areas(P, cnt)
        ok = (cnt >= 3) & (area > 1e-14 * areaA)
        i, j, T, P, cnt = i[ok], j[ok], T[ok], P[ok], cnt[ok]
        covered = np.zeros(Eo.size)
        np.add.at(covered, i, area[ok] / areaA[ok])
        # fan triangles (P0, Pk, Pk+1), in pair then fan order
        K = P.shape[1] - 2
        k = np.arange(1, K + 1)
        p0 = P[:, :1, :]  # (p, 1, 2)
        pb = P[:, 1 : K + 1, :]
        pc = P[:, 2 : K + 2, :]
        ar = 0.5 * ((pb[..., 0] - p0[..., 0]) * (pc[..., 1] - p0[..., 1])
                    - (pb[..., 1] - p0[..., 1]) * (pc[..., 0] - p0[..., 0]))  # (p, K)
        tri = (k[None, :] + 1 < cnt[:, None]) & (ar > 0)
        pi_, ki = np.nonzero(tri)
        q = (p0[pi_] + rule_p[None, :, :1] * (pb[pi_, ki][:, None, :] - p0[pi_])
             + rule_p[None, :, 1:] * (pc[pi_, ki][:, None, :] - p0[pi_]))  # (t, nq, 2)
        nq = rule_p.shape[0]
        zs = [c_o[i[pi_]][:, None, :] + np.einsum("tql,tdl->tqd", q, T[pi_])]
        zs = [zs[0].reshape(-1, 3)] if len(pi_) else []
        ws = [(2 * ar[pi_, ki][:, None] * rule_w[None, :]).ravel()]
        fo = [np.repeat(i[pi_], nq)]
        ft = [np.repeat(j[pi_], nq)]
        if not zs and same_way:
            raise ConfigError(
                f"contact surfaces of {self.names[0]} and {self.names[1]} face the same way "
                "(their outward normals point in the same direction where they overlap), so "
                "they cannot touch; check the surface names"
            )
        if not zs:
            raise ConfigError(
                f"contact surfaces of {self.names[0]} and {self.names[1]} do not overlap: no "
                "element of one faces an element of the other; check the surface names and "
                "the positions of the bodies"
            )
        if covered.max() > 1 + 1e-6:
            raise ConfigError(
                f"contact surfaces of {self.names[0]} and {self.names[1]}: within the search "
                f"distance {self.search_distance:g}, more than one part of one surface faces "
                f"the same element of the other (coverage {covered.max():.3g}); give a smaller "
                "search_distance or narrower contact surfaces"
            )
        # nodes whose frame elements, and their neighbours' (one ring
        # further), the other surface covers (almost) whole
        part = covered < COVERED
        self.covered = np.ones(self.n_frame, dtype=bool)
        self.covered[self._fconn[part]] = False
        self.covered[self._fconn[(~self.covered)[self._fconn].any(axis=1)]] = False
        fo = np.concatenate(fo)
        ft = np.concatenate(ft)
        z = np.concatenate(zs)
        w = np.concatenate(ws)
        T = np.stack([t1[fo], t2[fo]], axis=2)  # (P, 3, 2)
        xo = inverse_map(do.mesh, Eo[fo], z, T)
        xt = inverse_map(dt.mesh, Et[ft], z, T)
        # surface measure of the owner surface over the plane
        _, a, b = element_geometry(do.mesh, Eo[fo], xo)
        cr = np.cross(a, b)
        pa = np.einsum("pdi,pd->pi", T, a)
        pb = np.einsum("pdi,pd->pi", T, b)
        w = w * np.linalg.norm(cr, axis=1) / np.abs(pa[:, 0] * pb[:, 1] - pa[:, 1] * pb[:, 0])
        # bases
        ko, kt = mo.elements.shape[1], mt.elements.shape[1]
        phio = do.basis_at(Eo[fo], xo)
        phit = dt.basis_at(Et[ft], xt)
        Nf, _, _ = lagrange_basis(self._linear, self._ref, xo)
        Nf = Nf[:, : self._ref.shape[0]]
        jf = self._fconn[fo]  # (P, nc)
        m = self.n_frame
        po = own.local[do.fconn[Eo[fo], :ko]]
        pt = oth.local[dt.fconn[Et[ft], :kt]]
        wN = w[:, None] * Nf  # (P, nf)

        def coupling(rows, phi, n_rows):
            # sum over quadrature points of w N_j phi_p into (p, j)
            val = wN[:, :, None] * phi[:, None, :]  # (P, nf, k)
            r = np.broadcast_to(rows[:, None, :], val.shape)
            c = np.broadcast_to(jf[:, :, None], val.shape)
            return scipy.sparse.coo_array((val.ravel(), (r.ravel(), c.ravel())),
                                          shape=(n_rows, m)).tocsr()

        Do = coupling(po, phio, own.nodes.size)
        Dt = coupling(pt, phit, oth.nodes.size)
        self.weights = np.zeros(m)
        np.add.at(self.weights, jf, w[:, None] * Nf)
        # the frame's consistent mass over the common area, ∫ N_i N_j (its
        # row sums are the weights)
        val = wN[:, :, None] * Nf[:, None, :]
        self.mass = scipy.sparse.coo_array(
            (val.ravel(), (np.broadcast_to(jf[:, :, None], val.shape).ravel(),
                           np.broadcast_to(jf[:, None, :], val.shape).ravel())), shape=(m, m)).tocsc()
        self.common_area = float(w.sum())
        D = [None, None]
        D[self.owner], D[1 - self.owner] = Do, Dt
        self.D = tuple(D)
        # frame nodes the other body does not reach carry no unknowns
        self.active = self.weights > 1e-12 * self.weights.max()
        self.size = np.sqrt(self._full_weights())

    def _between(self, x: np.ndarray, n: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Points of the owner's surface ``x`` (P, 3) with its outward normals
        ``n``, moved between the surfaces: midway to their projection y on
        the other surface, and the normals bisecting the outward normals,
        (n - n_y)/|n - n_y| (still pointing out of the owner; n_y from the
        other body's nodal normals: a flat element's own normal is off the
        surface's by O(h/R), and that noise times the gap would show as slip).  Points without
        a facing partner within the search distance keep theirs."""
        oth = self._s[1 - self.owner]
        el, xi, _ = locate(oth.disc, oth.elements, x, self.search_distance)
        y, _, _ = oth.disc.mesh.map(el, xi)
        ny = _smooth_normals(oth.disc, el, xi)
        # a point of a convex surface can fall between the normal prisms of two
        # elements of the other one (not inside either): its nearest point on
        # the least-outside element is its partner, if it lies that close
        d = y - x
        across = np.einsum("pc,pc->p", d, n)
        lateral = np.linalg.norm(d - across[:, None] * n, axis=1)
        ok = ((np.einsum("pc,pc->p", n, ny) < 0) & (np.abs(across) <= self.search_distance)
              & (lateral <= self.search_distance))
        b = n - ny
        b /= np.linalg.norm(b, axis=1)[:, None]
        return (np.where(ok[:, None], 0.5 * (x + y), x), np.where(ok[:, None], b, n))

    def _full_weights(self) -> np.ndarray:
        """(m,) the frame surface's element areas around each node, each
        element's area shared equally by its corners."""
        sf = self._s[self.owner]
        area = sf.disc.mesh.surface_quadrature(4, sf.elements).weights.sum(axis=1)
        nc = self._fconn.shape[1]
        out = np.zeros(self.n_frame)
        np.add.at(out, self._fconn, np.repeat(area[:, None] / nc, nc, axis=1))
        return out

    def _masses(self) -> None:
        """The consistent mass of each body's contact surface (sparse).  Every
        node of the named surface stays a contact node, though only those
        whose support reaches the frame are coupled (nonzero rows of D): the
        tractions t = M^-1 f of the coupled nodal forces f spread over the
        whole surface (M^-1 is not local), and that spread is what makes each
        body receive exactly the frame's resultant.  Truncating the surface
        to the elements that reach the frame breaks it (measured 0.33 % on
        the flat punch's block: docs/decisions.md)."""
        self.M = tuple(
            self._mass(sf.disc, sf.elements, sf.local[sf.disc.fconn[sf.elements, : sf.disc.mesh.elements.shape[1]]],
                       sf.nodes.size)
            for sf in self._s
        )

    @staticmethod
    def _mass(d: Discretization, elements: np.ndarray, rows: np.ndarray, n: int):
        """Consistent scalar mass ∫ phi_p phi_q (n, n), sparse, of the
        functional basis over ``elements`` (``rows``: their local node ids)."""
        k = d.mesh.elements.shape[1]
        _, _, W, phi = d.surface_quadrature(6)
        W, phi = W[elements], phi[elements, :, :k]
        Me = np.einsum("eq,eqa,eqb->eab", W, phi, phi)
        r = np.broadcast_to(rows[:, :, None], Me.shape)
        c = np.broadcast_to(rows[:, None, :], Me.shape)
        return scipy.sparse.coo_array((Me.ravel(), (r.ravel(), c.ravel())), shape=(n, n)).tocsc()

    # ------------------------------------------------------------ projection
    def _project_nodes(self) -> None:
        """xi_p: the frame element and local coordinates of every contact node
        of both bodies (orthogonal projection on the frame element's plane)."""
        own = self._s[self.owner]
        self.projection = tuple(
            locate(own.disc, own.elements, sf.disc.points[sf.nodes], self.search_distance)
            for sf in self._s
        )

    def frame_basis_at(self, a: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(frame nodes (n_a, nc), values N_j(xi_p) (n_a, nc), on_frame (n_a,))
        for the contact nodes of body a."""
        el, xi, ok = self.projection[a]
        own = self._s[self.owner]
        pos = np.searchsorted(own.elements, el)
        N, _, _ = lagrange_basis(self._linear, self._ref, xi)
        return self._fconn[pos], N[:, : self._ref.shape[0]], ok

    def offsets(self, a: int) -> np.ndarray:
        """(n_a, 3): vector from each contact node's projection on the frame
        surface to the node itself (zero for the owner's nodes; the local
        initial gap for the other body's)."""
        el, xi, _ = self.projection[a]
        own = self._s[self.owner]
        x, _, _ = element_geometry(own.disc.mesh, el, xi)
        return self._s[a].disc.points[self._s[a].nodes] - x

    def _collocation_coupling(self) -> None:
        D = []
        for a, sf in enumerate(self._s):
            j, N, ok = self.frame_basis_at(a)
            w = sf.disc.weights[sf.nodes] * ok
            val = w[:, None] * N
            r = np.broadcast_to(np.arange(sf.nodes.size)[:, None], val.shape)
            D.append(scipy.sparse.coo_array((val.ravel(), (r.ravel(), j.ravel())),
                                            shape=(sf.nodes.size, self.n_frame)).tocsr())
        self.D = tuple(D)

    # -------------------------------------------------------------- accessors
    def nodes(self, a: int) -> np.ndarray:
        """Contact functional nodes of body a (indices into its solution)."""
        return self._s[a].nodes

    def surface_elements(self, a: int) -> np.ndarray:
        return self._s[a].elements

    def coupling_check(self) -> float:
        """max_j |sum_p D_1[p, j] - sum_q D_2[q, j]| / a_j: condition (*) of
        the patch test (0 to round-off for the mortar rule)."""
        s1 = self.D[0].sum(axis=0)
        s2 = self.D[1].sum(axis=0)
        act = self.active
        return float(np.max(np.abs(s1 - s2)[act] / self.weights[act]))



__all__ = ["ContactFrame"]

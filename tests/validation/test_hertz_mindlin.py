"""Hertz, Cattaneo–Mindlin and Mindlin–Deresiewicz: a steel hemisphere
(R = 10 mm) pressed on a steel block (20 x 20 x 10 mm) by an approach of
0.03 mm (a ≈ 0.555 mm, a/R = a/L ≈ 0.055), then loaded tangentially through
its base by a force Q at constant approach (docs/validation.md).

Meshes graded to element size h within 0.7 mm of the contact point; the
analytic comparisons use the *computed* normal force P (Hertz a and p0 from
P).  Identical materials: the normal and tangential problems decouple, as
Cattaneo–Mindlin assume.  The tangential displacement of "distant points" of
Cattaneo–Mindlin is a half-space notion: the platen's translation U also
holds the linear elastic compliance of the finite bodies, measured from a
small all-stick step (Q = 0.02 mu P) and replaced by the contact's own
initial compliance S / (8 a) (Johnson §7.2)."""

from __future__ import annotations

import numpy as np
import pytest

from bemcontact.validation import cases
from bemcontact.validation.reference import contact as ref
from bemcontact.validation.reference import stress as stress_ref

pytestmark = pytest.mark.validation

SETUP = cases.SphereOnBlock()
SIZES = (0.1, 0.07, 0.05)
MU = 0.3


def _hertz(P):
    return ref.hertz(P, SETUP.radius, SETUP.contact_modulus)


@pytest.fixture(scope="module")
def frictionless():
    out = []
    for h in SIZES:
        res = cases.sphere_on_block(h).solve()
        out.append((h, res, cases.hertz_errors(res.frame, _hertz(res.normal_force))))
    return out


def test_hertz_invariants(frictionless):
    """Tier (a)/(b): converged, interface forces balance the frame force, no
    tension, no penetration where pressed, and nothing tangential: without
    friction the law's tangential equation is lam_t = 0, solved, as the
    normal one, to the Newton tolerance (1e-10 of the traction scale), so
    |q| is bounded as the tension is, by 1e-9 p_max (measured exactly 0,
    which the LU's pivoting gives but does not promise)."""
    for h, res, _ in frictionless:
        assert res.converged
        fr = res.frame
        F1 = res.bodies[0].weights[res.interfaces[0].nodes] @ res.interfaces[0].traction
        assert np.allclose(F1, -res.contact_force, atol=1e-8 * res.normal_force)
        assert fr.pressure.min() >= -1e-9 * fr.pressure.max()
        closed = fr.state > 0
        assert np.abs(fr.gap[closed]).max() <= 1e-9 * SETUP.radius
        assert np.abs(fr.tangential_traction).max() <= 1e-9 * fr.pressure.max()


def test_hertz_frictionless_matches_and_converges(frictionless):
    """Finest mesh (h = 0.05 mm, 22 elements across the contact diameter):
    contact radius and peak pressure within 3 % and the profile within 5 %
    (L2, r < 0.9 a) of Hertz for the computed force (the Hertz tiers);
    measured 0.7 %, 0.7 %, 2.3 %.  All three errors fall on every refinement,
    at fitted rates >= 1 (the profile's measured rate is printed)."""
    hs = [h for h, _, _ in frictionless]
    e = [x for _, _, x in frictionless]
    fin = e[-1]
    assert abs(fin.contact_radius) <= 0.03
    assert abs(fin.peak_pressure) <= 0.03
    assert fin.profile_l2 <= 0.05
    for name in ("contact_radius", "peak_pressure", "profile_l2"):
        err = [abs(getattr(x, name)) for x in e]
        assert all(b < a for a, b in zip(err, err[1:])), (name, err)
        rate = cases.fitted_rate(hs, err)
        print(f"{name}: errors {['%.4f' % v for v in err]} fitted rate {rate:.2f}")
        assert rate >= 1.0, (name, rate)


QUADRATIC_SIZES = (0.28, 0.2, 0.14)


@pytest.mark.slow
def test_hertz_on_quadratic_bodies():
    """Curved tri6 (order 2; 55-80 s for the three meshes, so slow): Hertz for the
    computed force, every error falling on every refinement, the finest
    within the Hertz tiers (3 % contact radius and peak, 5 % profile;
    measured -0.48 %, -0.38 %, 3.0 %), fitted rates >= 1 for the contact
    radius (measured 1.7) and >= 1.5 for the profile (measured 3.2,
    pre-asymptotic at 2-4 elements per contact radius: the frame's P1 basis
    on the element corners sets the contact resolution, docs/validation.md)."""
    e = []
    for h in QUADRATIC_SIZES:
        prob = cases.sphere_on_block(h, order=2)
        assert {b.mesh.element_type for b in prob.bodies} == {"tri6"}
        res = prob.solve()
        assert res.converged
        e.append(cases.hertz_errors(res.frame, _hertz(res.normal_force)))
    fin = e[-1]
    print("tri6:", [(f"{x.contact_radius:+.4f}", f"{x.peak_pressure:+.4f}", f"{x.profile_l2:.4f}")
                    for x in e])
    assert abs(fin.contact_radius) <= 0.03 and abs(fin.peak_pressure) <= 0.03, fin
    assert fin.profile_l2 <= 0.05, fin
    for name, least in (("contact_radius", 1.0), ("peak_pressure", 1.0), ("profile_l2", 1.5)):
        err = [abs(getattr(x, name)) for x in e]
        assert all(b < a for a, b in zip(err, err[1:])), (name, err)
        assert cases.fitted_rate(QUADRATIC_SIZES, err) >= least, (name, err)


def test_normal_force_control_from_the_first_touch(frictionless):
    """Force control from a point contact: the sphere's base pushed by the
    force the displacement-controlled solve needed for 0.03 mm (h = 0.1),
    starting with every node open (the apex only touches).  The first-touch
    predictor (a penalty patch balancing the force) makes the Newton matrix
    regular; the solve reproduces the displacement-controlled one: approach
    0.03 mm to 1e-7 and the same pressures to 1e-7 of the peak (two solves
    of one discrete problem, to the Newton tolerance; measured 1e-9), in
    <= 15 Newton iterations (measured 6, as under displacement control)."""
    h, res_d, _ = frictionless[0]
    R = -res_d.bodies[1].reaction("base")[2]  # the platen's force, not the frame's (BEM equilibrium)
    res = cases.sphere_on_block(h, normal_force=R).solve()
    assert res.converged and res.newton_iterations <= 15, res.newton_iterations
    approach = -res.control_displacements["sphere"]["base"][2]
    print(f"force control: approach {approach:.9f} mm in {res.newton_iterations} iterations")
    assert approach == pytest.approx(0.03, rel=1e-7)
    p_d, p_f = res_d.frame.pressure, res.frame.pressure
    assert np.abs(p_f - p_d).max() <= 1e-7 * p_d.max()


# ----------------------------------------------------------------- with friction

#: Loading history of the frictional solve (ratios of mu P): a small
#: all-stick step (the finite bodies' elastic compliance), Cattaneo–Mindlin
#: at 0.5 and 0.75, then one fretting cycle 0.75 -> -0.75 -> 0.75 in
#: N_LOOP increments per branch.
SMALL, RATIOS, N_LOOP = 0.02, (0.5, 0.75), 8


@pytest.fixture(scope="module")
def frictional(frictionless):
    """mu = 0.3 on the finest mesh, loads set from the frictionless P of the
    same mesh (the problems decouple: the frictional P equals it to 1e-5)."""
    h, res0, _ = frictionless[-1]
    P = res0.normal_force
    steps, q_max = cases.fretting_history(P, MU, SMALL, RATIOS, N_LOOP)
    res = cases.sphere_on_block(h, friction_coefficient=MU).solve(steps=steps)
    return h, P, q_max, res


#: The Cattaneo–Mindlin solve on the stick–slip ring mesh: P, the small
#: step, then 0.5 and 0.75 mu P in RING_INCREMENTS increments each (two
#: stall on this mesh: the residual cycles at 1e-2 while the slip zone
#: jumps by a ring of nodes).  Q is set from the uniform mesh's P (the
#: ring's P equals it to 1e-4); the analytic values use the step's own Q
#: and P.
RING_INCREMENTS = 4


@pytest.fixture(scope="module")
def ring(frictionless):
    P0 = frictionless[-1][1].normal_force
    ring = cases.STICK_SLIP_RING
    steps = cases.cattaneo_mindlin_history(P0, MU, SMALL, RATIOS, RING_INCREMENTS)
    fine = min(h for _, h in ring.size_profile)
    res = cases.sphere_on_block(fine, friction_coefficient=MU, setup=ring).solve(steps=steps)
    return P0, res


def test_frictional_solve_converges_in_few_iterations(frictional):
    """Every increment converges, in <= 15 Newton iterations (measured 5-13:
    the watchdog line search takes the full steps through the stick-to-slip
    transitions; a monotone search needed 20-50)."""
    *_, res = frictional
    assert res.converged
    its = [s.iterations for s in res.steps]
    print("Newton iterations per increment:", its)
    assert max(its) <= 15, its


def test_hertz_with_friction(frictional):
    """Step P with mu = 0.3: the same Hertz tolerances as without friction,
    the same force to 1e-4 (identical materials decouple; measured 1e-5) and
    tangential tractions <= 3 % of p0 (none in half-space theory; measured
    2.0 %, at the contact edge: the finite bodies and the two non-matching
    meshes couple the normal and tangential problems slightly)."""
    h, P, _, res = frictional
    s = res.history[0]
    hz = _hertz(s.normal_force)
    assert s.normal_force == pytest.approx(P, rel=1e-4)
    e = cases.hertz_errors(s.frame, hz)
    assert abs(e.contact_radius) <= 0.03 and abs(e.peak_pressure) <= 0.03
    assert e.profile_l2 <= 0.05
    assert np.abs(s.frame.tangential_traction).max() <= 0.03 * hz.peak_pressure


@pytest.mark.parametrize("k, ratio", [(2, 0.5), (3, 0.75)])
def test_cattaneo_mindlin(ring, k, ratio):
    """Q = 0.5 and 0.75 mu P at constant approach on the stick–slip ring
    mesh (cases.STICK_SLIP_RING: 0.03 mm on 0.39 <= r <= 0.50 mm, 0.05 mm
    elsewhere in the contact), against Cattaneo–Mindlin for the step's own
    Q and P:

    * stick radius (area of the stuck frame nodes) within 5 % of
      a (1 - Q/mu P)^(1/3) (measured +0.39 % and -0.81 %);
    * tangential approach within 5 % (measured -1.7 % and -1.6 %; the
      finite bodies' linear compliance is replaced by S/8a, see
      cases.tangential_approach, so this checks the slip-dependent part,
      10-17 % of the total);
    * traction profile (x traction on the block, frame-node weighted L2 on
      r < 0.9 a) within 10 % (measured 2.9 % and 2.3 %; 8.4 % and 5.5 %
      with the weighted gap; 4.25 % and 2.11 % on the uniform 0.05 mm mesh:
      the error sits at the stick–slip boundary, the square-root kink of the
      analytic traction, docs/validation.md)."""
    P0, res = ring
    Q, U = cases.platen_history(res)
    s = res.history[k]
    P = s.normal_force
    hz = _hertz(P)
    a = hz.contact_radius
    assert Q[k] == pytest.approx(ratio * MU * P0, rel=1e-9)
    assert Q[k] / (MU * P) == pytest.approx(ratio, rel=1e-3)
    c_exact = ref.cattaneo_mindlin_stick_radius(a, Q[k], MU, P)
    c = cases.stick_radius(s.frame)
    d_exact = ref.cattaneo_mindlin_displacement(Q[k], MU, P, a, SETUP.tangential_compliance_factor)
    d = cases.tangential_approach(Q, U, a, SETUP.tangential_compliance_factor)[k]
    r, _, qx, w, _ = cases.radial_profile(s.frame)
    inner = r < 0.9 * a
    l2 = cases.weighted_l2(qx[inner], ref.cattaneo_mindlin_traction(r[inner], hz, Q[k], MU), w[inner])
    print(f"Q/muP={Q[k] / (MU * P):.4f}: stick radius {c / c_exact - 1:+.4f}, approach "
          f"{d / d_exact - 1:+.4f}, profile L2 {l2:.4f}")
    assert abs(c / c_exact - 1) <= 0.05
    assert abs(d / d_exact - 1) <= 0.05
    assert l2 <= 0.10


@pytest.mark.parametrize("k, ratio, l2_tier", [(2, 0.5, 0.05), (3, 0.75, 0.03)])
def test_cattaneo_mindlin_on_the_plain_graded_mesh(frictional, k, ratio, l2_tier):
    """Cattaneo–Mindlin on the plain graded mesh (h = 0.05 mm within 0.7 mm,
    a/h = 11.1; no refinement ring), from the fretting solve's steps 0.5 and
    0.75 mu P, against the step's own Q and P:

    * stick radius within 1.5 % (measured +0.27 % and +1.1 %; -2 % with the
      weighted gap of the frame nodes, which needs the ring mesh);
    * tangential approach within 5 % (measured -0.90 % and -0.88 %: the
      all-stick step that measures the bodies' compliance also carries the
      first-touch node's released force, docs/benchmarks.md);
    * traction profile L2 (r < 0.9 a) within 5 % and 3 % (measured 4.25 % and
      2.11 %; 13.3 % and 7.2 % with the weighted gap).  The error sits at the
      stick-slip front, the square-root cusp of the analytic traction, and is
      first order in h: the benchmark's 3.9 % at a/h = 12.2 and 1.9 % at
      25.4 (docs/benchmarks.md) scale to 4.3 % here."""
    h, P0, q_max, res = frictional
    Q, U = cases.platen_history(res)
    s = res.history[k]
    P = s.normal_force
    hz = _hertz(P)
    a = hz.contact_radius
    assert Q[k] / (MU * P) == pytest.approx(ratio, rel=1e-3)
    c = cases.stick_radius(s.frame) / ref.cattaneo_mindlin_stick_radius(a, Q[k], MU, P) - 1
    S = SETUP.tangential_compliance_factor
    d = (cases.tangential_approach(Q, U, a, S)[k]
         / ref.cattaneo_mindlin_displacement(Q[k], MU, P, a, S) - 1)
    r, _, qx, w, _ = cases.radial_profile(s.frame)
    inner = r < 0.9 * a
    l2 = cases.weighted_l2(qx[inner], ref.cattaneo_mindlin_traction(r[inner], hz, Q[k], MU), w[inner])
    print(f"plain mesh, Q/muP={ratio}: stick radius {c:+.4f}, approach {d:+.4f}, profile L2 {l2:.4f}")
    assert abs(c) <= 0.015
    assert abs(d) <= 0.05
    assert l2 <= l2_tier


def test_ring_mesh_solve_converges_and_matches_hertz(ring):
    """The ring mesh's normal step: Hertz within the tiers 3 % / 3 % / 5 %
    (measured -0.15 % / +1.2 % / 2.2 %), every increment converged in <= 25
    Newton iterations (measured [11, 6, 5, 6, 7, 19, 13, 7, 7, 7]: the last
    increment to 0.5 mu P moves the slip front across the ring's finest
    elements)."""
    _, res = ring
    assert res.converged
    its = [s.iterations for s in res.steps]
    print("Newton iterations per increment:", its)
    assert max(its) <= 25, its
    s = res.history[0]
    e = cases.hertz_errors(s.frame, _hertz(s.normal_force))
    assert abs(e.contact_radius) <= 0.03 and abs(e.peak_pressure) <= 0.03
    assert e.profile_l2 <= 0.05


def test_fretting_loop(frictional):
    """One cycle Q* -> -Q* -> Q*, Q* = 0.75 mu P, 8 increments per branch:

    * dissipated energy (area of the computed (Q, U) polygon; the bodies'
      linear compliance adds no area) within 10 % of the closed-form
      Mindlin–Deresiewicz loop (measured -2.2 %, of
      which -1.7 % is the polygon's own quadrature error at 8 increments)
      and within 3 % of the analytic loop sampled at the same Q (measured
      -0.5 %);
    * the loop closes: U back at Q* equals U at the start to 1e-3 of U
      (Masing; measured 1.3e-5);
    * a stuck annulus re-forms at the reversal: in the first unloading
      increment at least 3/4 of the nodes that slipped at Q* stick again
      (Mindlin–Deresiewicz: slip only beyond 0.97 a; measured 245 of 273),
      and the slip zone grows again monotonically along each branch;
    * the branch ends mirror each other: the slip counts at -Q* and Q*
      agree to 5 % (measured 275 vs 273)."""
    h, P0, q_max, res = frictional
    Q, U = cases.platen_history(res)
    k0 = 1 + 1 + len(RATIOS) - 1  # the step at Q*
    loop_Q, loop_U = Q[k0:], U[k0:]
    assert loop_Q[0] == pytest.approx(q_max) and loop_Q[-1] == pytest.approx(q_max)
    assert loop_Q[N_LOOP] == pytest.approx(-q_max)
    poly_Q, poly_U = loop_Q[:-1], loop_U[:-1]
    W = 0.5 * abs(np.sum(poly_Q * np.roll(poly_U, -1) - np.roll(poly_Q, -1) * poly_U))
    P = res.history[k0].normal_force
    a = _hertz(P).contact_radius
    S = SETUP.tangential_compliance_factor
    W_closed = ref.fretting_loop_energy(q_max, MU, P, a, S)
    d_un = ref.mindlin_deresiewicz_unloading(loop_Q[: N_LOOP + 1], q_max, MU, P, a, S)
    d_re = -ref.mindlin_deresiewicz_unloading(-loop_Q[N_LOOP + 1 : -1], q_max, MU, P, a, S)
    aQ, aU = poly_Q, np.concatenate([d_un, d_re])
    W_poly = 0.5 * abs(np.sum(aQ * np.roll(aU, -1) - np.roll(aQ, -1) * aU))
    print(f"loop energy {W:.5g} N mm: closed form {W / W_closed - 1:+.4f}, "
          f"same-Q polygon {W / W_poly - 1:+.4f}; closure {(loop_U[-1] - loop_U[0]) / loop_U[0]:+.2e}")
    assert abs(W / W_closed - 1) <= 0.10
    assert abs(W / W_poly - 1) <= 0.03
    assert abs(loop_U[-1] - loop_U[0]) <= 1e-3 * abs(loop_U[0])
    states = [s.frame.state for s in res.history[k0:]]
    slipped = states[0] == 2
    restuck = slipped & (states[1] == 1)
    assert restuck.sum() >= 0.75 * slipped.sum(), (restuck.sum(), slipped.sum())
    slips = [int((st == 2).sum()) for st in states]
    print("slip counts along the loop:", slips, f"; restuck {restuck.sum()} of {slipped.sum()}")
    for branch in (slips[1 : N_LOOP + 1], slips[N_LOOP + 1 :]):
        assert all(b >= a_ for a_, b in zip(branch, branch[1:])), branch
    assert slips[N_LOOP] == pytest.approx(slips[0], rel=0.05)


# ------------------------------------------------------------ bodies that start apart

GAP, APPROACH2 = 0.01, 0.06


def test_two_spheres_close_from_an_initial_gap_and_match_hertz():
    """Two identical steel hemispheres (R = 10 mm) start 0.01 mm apart; the
    upper base is pushed down by gap + 0.06 mm (frictionless, displacement
    control).  The initial weighted gap at every active frame node is at
    least the apex gap (it comes from the geometry, along the frame
    normals; at the apex node it exceeds it by the curvature averaged over
    the node's support, <= h^2/R_eff), the contact closes, and the
    pressure matches Hertz with R_eff = R/2 for the computed force within
    the Hertz tiers 3 % / 3 % / 5 % (h = 0.05 mm, 22 elements across 2a;
    measured 6.6 % / 0.5 % / 9.3 % at h = 0.1 and 0.90 % / 0.41 % / 2.8 % at
    h = 0.05, in 9 Newton iterations).  The frame lies on one sphere (curved): without friction the
    r/R tilt of its normals changes nothing measurable."""
    prob = cases.two_spheres(0.05, gap=GAP, approach=APPROACH2)
    fr = prob.frame
    x = [b.discretization.points[fr.nodes(a)] for a, b in enumerate(prob.bodies)]
    act = fr.active
    k0 = (fr.D[1].T @ x[1] - fr.D[0].T @ x[0])[act] / fr.weights[act, None]
    g0 = np.einsum("jc,jc->j", k0, fr.Q[act, :, 2])
    apex = np.argmin(np.hypot(fr.points[act, 0], fr.points[act, 1]))
    # the weighted gap averages g(r) = gap + r^2/R over the apex node's support
    assert GAP <= g0[apex] <= GAP + 0.05**2 / SETUP.radius * 2
    assert g0.min() >= GAP * (1 - 1e-9)
    res = prob.solve()
    assert res.converged and res.newton_iterations <= 15
    hz = ref.hertz(res.normal_force, SETUP.radius / 2, SETUP.contact_modulus)
    e = cases.hertz_errors(res.frame, hz)
    print(f"two spheres: P {res.normal_force:.2f} N, a {hz.contact_radius:.4f} mm, errors a "
          f"{e.contact_radius:+.4f}, p0 {e.peak_pressure:+.4f}, L2 {e.profile_l2:.4f}; "
          f"{res.newton_iterations} iterations")
    assert abs(e.contact_radius) <= 0.03 and abs(e.peak_pressure) <= 0.03
    assert e.profile_l2 <= 0.05
    assert res.frame.pressure.min() >= -1e-9 * res.frame.pressure.max()


def test_hertz_stresses_below_the_contact_match_johnson_and_converge(frictionless):
    """Stresses inside the block on the axis (Somigliana's identity on the
    boundary solution), against Johnson's closed forms for a and p0 of
    Hertz at the computed force, 0.05a <= z <= 3a: σ_z and σ_r within 2 % of
    p0 on every mesh (the issue's tier; measured 0.60 / 0.35 / 0.26 % and
    0.90 / 0.56 / 0.32 % at h = 0.1 / 0.07 / 0.05), falling on every
    refinement at fitted rates >= 1 (measured 1.2 and 1.5: the boundary
    solution's own error); the largest τ1 = |σ_z − σ_r|/2 on the axis within
    2 % of Johnson's 0.310 p0 and its depth within 3 % of a of 0.481a
    (measured 0.3087 p0 at 0.478a on the coarsest mesh, 0.3100 at 0.481a
    on the finest)."""
    z = np.linspace(0.05, 3.0, 60)
    errors = []
    for h, res, _ in frictionless:
        hz = _hertz(res.normal_force)
        a, p0 = hz.contact_radius, hz.peak_pressure
        exact = stress_ref.hertz_axis_stresses(z * a, a, p0, 0.3)
        s = res.stresses("block", np.column_stack([0 * z, 0 * z, -z * a]))
        ez = np.abs(s[:, 2] - exact.sigma_z).max() / p0
        er = max(np.abs(s[:, k] - exact.sigma_r).max() for k in (0, 1)) / p0
        assert ez <= 0.02 and er <= 0.02, (h, ez, er)
        # τ1 near its maximum: a parabola through the largest sample and its neighbours
        zz = np.linspace(0.3, 0.7, 21)
        t = res.stresses("block", np.column_stack([0 * zz, 0 * zz, -zz * a]))
        tau = 0.5 * np.abs(t[:, 2] - 0.5 * (t[:, 0] + t[:, 1])) / p0
        k = int(np.argmax(tau))
        c = np.polyfit(zz[k - 1:k + 2], tau[k - 1:k + 2], 2)
        z_max = -c[1] / (2.0 * c[0])
        assert abs(np.polyval(c, z_max) - exact.max_shear / p0) <= 0.02 * exact.max_shear / p0
        assert abs(z_max - exact.max_shear_depth / a) <= 0.03
        errors.append((ez, er))
    hs = [h for h, _, _ in frictionless]
    for k, name in enumerate(("sigma_z", "sigma_r")):
        err = [e[k] for e in errors]
        assert all(b < a for a, b in zip(err, err[1:])), (name, err)
        rate = cases.fitted_rate(hs, err)
        print(f"{name}: errors {['%.4f' % v for v in err]} fitted rate {rate:.2f}")
        assert rate >= 1.0, (name, rate)


def _radial_surface_stress(res, body="block", region="zmax"):
    """(r, σ_r) at the functional nodes of ``body``'s ``region``."""
    sol = res.bodies[res.names.index(body)]
    nodes = sol.nodes_of(region)
    X = sol.points[nodes]
    r = np.hypot(X[:, 0], X[:, 1])
    s = res.surface_stresses(body)[nodes]
    c, d = X[:, 0] / np.maximum(r, 1e-300), X[:, 1] / np.maximum(r, 1e-300)
    return r, s[:, 0] * c * c + s[:, 1] * d * d + 2.0 * s[:, 3] * c * d


def test_hertz_surface_stress_matches_johnson_away_from_the_contact_edge(frictionless):
    """The block's radial surface stress σ_r (from its tractions and the
    tangential derivatives of its displacement) against Johnson's eq. 3.44
    for a and p0 of Hertz at the computed force: outside the contact (1.3a
    <= r <= 3a) within 1 % of p0 (measured 0.34 % on all three meshes);
    inside (r <= 0.8a, where σ_r is compressive, −0.8 p0 at the centre)
    within 5 % of p0, falling at a fitted rate >= 0.9 (measured 3.6 / 2.3 /
    1.6 % at h = 0.1 / 0.07 / 0.05, rate 1.1: the displacement's derivative is
    one order below the displacement). The tension at the contact edge,
    (1 − 2ν)p0/3 = 0.133 p0 in theory, sits on the square-root edge of the
    pressure and is smeared over an element by the discrete solution: the
    largest σ_r is 0.091 / 0.100 / 0.109 p0 (−32 / −25 / −18 %), rising on
    every refinement (asserted: rising, and at least 60 % of the theory). The
    grid path meets the 5 % asked at the edge (tests/unit/multiscale/test_stress.py)."""
    peaks, inside, hs = [], [], []
    for h, res, _ in frictionless:
        hz = _hertz(res.normal_force)
        a, p0 = hz.contact_radius, hz.peak_pressure
        r, sr = _radial_surface_stress(res)
        exact = stress_ref.hertz_surface_stresses(r, a, p0, 0.3).sigma_r
        inner, outer = r <= 0.8 * a, (r >= 1.3 * a) & (r <= 3 * a)
        inside.append(np.abs(sr[inner] - exact[inner]).max() / p0)
        assert np.abs(sr[outer] - exact[outer]).max() <= 0.01 * p0, h
        peaks.append(sr[r < 2 * a].max() / p0)
        hs.append(h)
    theory = (1.0 - 2.0 * 0.3) / 3.0
    assert max(inside) <= 0.05 and cases.fitted_rate(hs, inside) >= 0.9, inside
    assert all(b < a for a, b in zip(inside, inside[1:])), inside
    assert all(b > a for a, b in zip(peaks, peaks[1:])), peaks
    assert min(peaks) >= 0.6 * theory and max(peaks) <= theory, peaks


def test_far_from_the_contact_the_field_is_hertz_and_boussinesq(frictionless):
    """Inside the block on shells at 2a, 3a, 4a and 6a from the contact's
    centre (polar angles 0–80°, 8 azimuths): the stresses match the exact
    half-space Hertz field (Hamilton's with μ = 0) to 2.5e-3 p0 on every mesh
    (measured 1.0–1.4e-3 p0, the same on every mesh: the finite block's own
    smooth field, of the order of P/L² = 1.6e-3 p0 for its 20 mm width, not
    a discretization error), and at 6a, where Hertz's field is Boussinesq's
    point-load field to 7.5e-4 p0, σ_zz matches σ_z = −3Pz³/(2πρ⁵) to
    3.5e-3 p0 (a tenth of the stress there)."""
    th, ph = np.meshgrid(np.radians(np.linspace(0, 80, 9)), np.radians(np.linspace(0, 315, 8)))
    d = np.column_stack([(np.sin(th) * np.cos(ph)).ravel(), (np.sin(th) * np.sin(ph)).ravel(),
                         -np.cos(th).ravel()])
    for h, res, _ in frictionless:
        hz = _hertz(res.normal_force)
        a, p0, P = hz.contact_radius, hz.peak_pressure, res.normal_force
        for rho in (2.0, 3.0, 4.0, 6.0):
            X = d * rho * a
            s = res.stresses("block", X)
            exact = stress_ref.hamilton_sliding_sphere_stresses(X * [1, 1, -1], a, p0, 0.0, 0.3)
            exact[:, 4:] *= -1.0  # the block lies below z = 0: σ_yz, σ_xz change sign
            assert np.abs(s - exact).max() <= 2.5e-3 * p0, (h, rho)
        depth = -X[:, 2]
        boussinesq = -3.0 * P * depth**3 / (2.0 * np.pi * (6.0 * a) ** 5)
        assert np.abs(s[:, 2] - boussinesq).max() <= 3.5e-3 * p0, h

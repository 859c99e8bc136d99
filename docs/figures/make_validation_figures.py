"""The figures of docs/validation.md: each validation case computed with
bemcontact and drawn against its analytic solution.

    OMP_NUM_THREADS=1 .venv/bin/python docs/figures/make_validation_figures.py
    OMP_NUM_THREADS=1 .venv/bin/python docs/figures/make_validation_figures.py --only fretting_loop

writes into docs/figures/ (or ``--out DIR``):

* ``patch_test.png``: contact patch test, quad4 7x7 / quad4 11x11 (the pair
  of tests/validation/test_contact_patch.py's collocation test), pressure on
  both bodies' interface nodes and the frame against x, mortar rule vs the
  paper's collocation rule (exact: 10 MPa everywhere).
* ``two_cubes_figure1.png``: the founding paper's Figure 1 (u_y of both
  cubes along a line of the interface, similar and dissimilar materials),
  the problem files examples/two_cubes_*.toml (lower 6^3, upper 5^3 quad4)
  drawn by examples/two_cubes_figure.py's ``run``.
* ``hertz_pressure.png``: Hertz, hemisphere on block, frictionless, at
  the finest validation mesh h = 0.05 mm.
* ``hertz_convergence.png``: the Hertz errors (contact radius, peak, profile
  L2) at h = 0.1, 0.07, 0.05 mm (all three meshes re-solved, about 2.5 min on
  one core), log-log, with the fitted rates.
* ``cattaneo_mindlin_traction.png``: pressure and tangential traction q_x
  along r at Q = 0.5 mu P against Hertz and Cattaneo–Mindlin, on the
  stick–slip ring mesh (cases.STICK_SLIP_RING; about 2 min on one core).
* ``boussinesq_punch.png``: the flat punch on a block (the set-up of
  tests/validation/test_boussinesq.py) at rim sizes 0.07, 0.05 and 0.035 a:
  pressure along r against Boussinesq's, and the force error after the
  finite block's measured compliance is removed (about 4 min on one core).
* ``two_spheres_shear.png``: two identical hemispheres pressed together
  with mu = 0.3 at h = 0.1 mm: |q| / p0 with the frame on one sphere and
  between the surfaces (the default), and the pressure against Hertz.
* ``curvature_shear.png``: the shear under a normal load between identical
  steel bodies of different curvatures (mu = 0.3, 4 increments, a = 0.56 mm):
  the saddle field of the crossed cylinders (R = 10 mm, h = 0.05 mm) and the
  root mean square of |q| / p0 against a/h for crossed cylinders and
  spheres of different radii at two a/R, against two identical spheres
  (tests/validation/test_curved_pairs.py; about 6 min on 2 cores).
* ``cattaneo_mindlin_resolutions.png``: q_x along r at Q = 0.5 mu P on plain
  graded meshes (no ring) at a/h = 12 and 25, against Cattaneo–Mindlin (the
  benchmark's set-up; about 6 min on 2 cores, most of it a/h = 25).
* ``fretting_loop.png``: the platen's tangential force against the
  contact's tangential approach over the whole history (initial loading to
  Q* = 0.75 mu P, then Q* -> -Q* -> Q* in 8 increments per branch) against
  Cattaneo–Mindlin loading and the Mindlin–Deresiewicz loop.

The set-ups are those of tests/validation/test_hertz_mindlin.py (the same
mesh sizes, load history and measures, through bemcontact.validation.cases), so the
figures show the cases whose numbers docs/validation.md tables; the script
prints those numbers next to each figure.  The two frictional figures come
from one solve at h = 0.05 mm (22 increments, about 2 min on one core).
Whole run: about 5 min on one core (OMP_NUM_THREADS=1).
"""

from __future__ import annotations

import argparse
import functools
import importlib.util
import pathlib
import sys
import tempfile
import time

import numpy as np

import bemcontact as bc
from bemcontact.validation import cases
from bemcontact.output.write import OutputOptions, write_results
from bemcontact.output.plot import plot_force_displacement, plot_radial_profile, save_png
from bemcontact.problemfile import load_problem
from bemcontact.validation.reference import contact as ref

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parents[1]

# ---------------------------------------------------------------- the validation set-ups
# (tests/validation/test_hertz_mindlin.py)
SETUP = cases.SphereOnBlock()
SIZES = (0.1, 0.07, 0.05)
MU = 0.3
SMALL, RATIOS, N_LOOP = 0.02, (0.5, 0.75), 8

# (tests/validation/test_contact_patch.py)
P0 = 10.0
MAT1 = bc.LinearElastic(1.0e4, 0.3)
MAT2 = bc.LinearElastic(3.0e4, 0.2)
ROLLERS = {"xmin": bc.Displacement((0.0, None, None)), "ymin": bc.Displacement((None, 0.0, None))}
PATCH_PAIR = "quad4 7x7 / quad4 11x11"


# (tests/validation/test_boussinesq.py)
PUNCH = cases.PunchOnBlock()
PUNCH_RIMS = (0.07, 0.05, 0.035)
PUNCH_DELTA = 1.0e-3


def _hertz(P: float) -> ref.Hertz:
    return ref.hertz(P, SETUP.radius, SETUP.contact_modulus)


# ---------------------------------------------------------------- solves (cached)


@functools.lru_cache(maxsize=None)
def frictionless(h: float):
    res = cases.sphere_on_block(h).solve()
    return res, cases.hertz_errors(res.frame, _hertz(res.normal_force))


@functools.lru_cache(maxsize=None)
def frictional():
    """mu = 0.3 at h = 0.05 mm, the loads set from the frictionless P of the
    same mesh (as the validation test)."""
    h = SIZES[-1]
    P = frictionless(h)[0].normal_force
    steps, q_max = cases.fretting_history(P, MU, SMALL, RATIOS, N_LOOP)
    res = cases.sphere_on_block(h, friction_coefficient=MU).solve(steps=steps)
    return h, P, q_max, res


@functools.lru_cache(maxsize=None)
def punch(rim: float):
    """(result, block compliance, Boussinesq errors) of the set-up at rim
    size ``rim``."""
    problem = cases.punch_on_block(rim, PUNCH_DELTA, PUNCH)
    res = problem.solve()
    comp = cases.block_compliance(problem.bodies[0], PUNCH.radius)
    return res, comp, cases.boussinesq_errors(res, PUNCH, PUNCH_DELTA, comp)


@functools.lru_cache(maxsize=None)
def ring():
    """The Cattaneo–Mindlin solve of the validation test on the stick–slip
    ring mesh: P, the small step, 0.5 and 0.75 mu P (4 increments each)."""
    P = frictionless(SIZES[-1])[0].normal_force
    steps = cases.cattaneo_mindlin_history(P, MU, SMALL, RATIOS, increments=4)
    setup = cases.STICK_SLIP_RING
    fine = min(h for _, h in setup.size_profile)
    return P, cases.sphere_on_block(fine, friction_coefficient=MU, setup=setup).solve(steps=steps)


# ---------------------------------------------------------------- figures


def fig_hertz_pressure(out: pathlib.Path) -> pathlib.Path:
    from matplotlib.figure import Figure

    h = SIZES[-1]
    res, e = frictionless(h)
    hz = _hertz(res.normal_force)
    a, p0 = hz.contact_radius, hz.peak_pressure
    r, p, _, _, state = cases.radial_profile(res.frame)
    shown = r <= 1.3 * a
    grid = np.linspace(0.0, 1.3 * a, 400)
    fig = Figure(figsize=(10.0, 4.2), layout="constrained")
    ax, ax2 = fig.subplots(1, 2)
    closed = shown & (state > 0)
    ax.plot(r[closed], p[closed], "o", markersize=3, label="bemcontact (frame nodes in contact)")
    ax.plot(r[shown & (state == 0)], p[shown & (state == 0)], "x", markersize=3, label="open")
    ax.plot(grid, hz.pressure(grid), "k-", linewidth=1.2, label=f"Hertz, a = {a:.4f} mm")
    ax.axvline(a, color="0.6", linewidth=0.8, linestyle="--")
    ax.set_xlabel("r (mm)")
    ax.set_ylabel("contact pressure p (MPa)")
    ax.set_title("pressure")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="lower left", fontsize=8)
    ax2.plot(r[closed] / a, (p[closed] - hz.pressure(r[closed])) / p0, "o", markersize=3)
    ax2.axhline(0.0, color="k", linewidth=0.8)
    ax2.axvline(0.9, color="0.6", linewidth=0.8, linestyle="--")
    ax2.set_xlabel("r / a")
    ax2.set_ylabel("($p - p_{Hertz}$) / $p_0$")
    ax2.set_title(
        f"error: a {e.contact_radius:+.2%}, peak {e.peak_pressure:+.2%}, L2 (r < 0.9a) {e.profile_l2:.1%}",
        fontsize=10,
    )
    ax2.grid(True, alpha=0.3)
    fig.suptitle(
        f"Hertz, hemisphere R = 10 mm on block, frictionless, tri3 h = {h:g} mm: "
        f"P = {res.normal_force:.1f} N, $p_0$ = {p0:.0f} MPa"
    )
    print(f"  h = {h}: P = {res.normal_force:.2f} N, a = {a:.4f} mm, errors a "
          f"{e.contact_radius:+.4f}, p0 {e.peak_pressure:+.4f}, L2 {e.profile_l2:.4f}, "
          f"{res.newton_iterations} Newton iterations")
    return save_png(fig, out / "hertz_pressure.png")


def fig_hertz_convergence(out: pathlib.Path) -> pathlib.Path:
    from matplotlib.figure import Figure

    errors = {"contact radius": [], "peak pressure": [], "profile L2 (r < 0.9a)": []}
    for h in SIZES:
        res, e = frictionless(h)
        for k, v in zip(errors, (e.contact_radius, e.peak_pressure, e.profile_l2)):
            errors[k].append(abs(v))
        print(f"  h = {h}: P = {res.normal_force:.2f} N, errors a {e.contact_radius:+.4f}, "
              f"p0 {e.peak_pressure:+.4f}, L2 {e.profile_l2:.4f}, {res.newton_iterations} it.")
    hs = np.array(SIZES)
    fig = Figure(figsize=(6.0, 4.6), layout="constrained")
    ax = fig.subplots()
    for (name, err), m in zip(errors.items(), ("o", "s", "^")):
        rate = cases.fitted_rate(hs, err)
        ax.loglog(hs, 100 * np.array(err), m + "-", label=f"{name}: rate {rate:.1f}")
        print(f"  {name}: fitted rate {rate:.2f}")
    for tol in (3, 5):
        ax.axhline(tol, color="0.6", linewidth=0.8, linestyle=":")
    ax.text(hs[-1], 3, " 3 %", va="bottom", fontsize=8, color="0.4")
    ax.text(hs[-1], 5, " 5 %", va="bottom", fontsize=8, color="0.4")
    ax.set_xticks(hs, [f"{h:g}" for h in hs])
    ax.minorticks_off()
    ax.set_xlabel("element size h in the contact zone (mm)")
    ax.set_ylabel("relative error vs Hertz (%)")
    ax.set_title("Hertz, hemisphere on block: convergence (tri3)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=9)
    return save_png(fig, out / "hertz_convergence.png")


def fig_cattaneo_mindlin(out: pathlib.Path) -> pathlib.Path:
    P0, res = ring()
    Q, U = cases.platen_history(res)
    k = 2  # Q = 0.5 mu P
    s = res.history[k]
    P = s.normal_force
    hz = _hertz(P)
    ratio = Q[k] / (MU * P)
    c, c_exact = cases.stick_radius(s.frame), ref.cattaneo_mindlin_stick_radius(
        hz.contact_radius, Q[k], MU, P
    )
    r, _, qx, w, _ = cases.radial_profile(s.frame)
    inner = r < 0.9 * hz.contact_radius
    l2 = cases.weighted_l2(qx[inner], ref.cattaneo_mindlin_traction(r[inner], hz, Q[k], MU), w[inner])
    print(f"  Q = {ratio:.4f} mu P: stick radius {c:.4f} mm vs {c_exact:.4f} ({c / c_exact - 1:+.4f}), "
          f"traction L2 {l2:.4f}")
    return plot_radial_profile(
        s, out / "cattaneo_mindlin_traction.png", pressure=hz.pressure,
        traction=lambda x: ref.cattaneo_mindlin_traction(x, hz, Q[k], MU),
        title=(f"Cattaneo–Mindlin, μ = {MU}, Q = {ratio:.2f} μP, tri3 ring mesh "
               f"(0.03 mm on 0.39–0.50 mm, else 0.05)\n"
               f"stick radius {c:.3f} mm (analytic {c_exact:.3f}), $q_x$ L2 error (r < 0.9a) {l2:.1%}"),
    )


def _cm_plain(a_over_h: float):
    """Cattaneo–Mindlin on a plain graded mesh (no ring) at a/h: the set-up of
    benchmarks/hertz_mindlin_vs_tamaas.py (h = a/(a/h) within 1.1a, growth
    0.45; P, then Q = 0.02 and 0.5 mu P, the last in 4 increments)."""
    approach = 0.03
    a_guess = np.sqrt(SETUP.radius * approach)
    h = a_guess / a_over_h
    s = cases.SphereOnBlock(size_profile=((0.0, h), (1.1 * a_guess, h)), growth=0.45)
    p_guess = ref.hertz_force(approach, s.radius, s.contact_modulus)
    prob = cases.sphere_on_block(h, approach, friction_coefficient=MU, setup=s)
    steps = ([bc.LoadStep(label="P")]
             + cases.tangential_steps([SMALL * MU * p_guess], approach, increments=1)
             + cases.tangential_steps([0.5 * MU * p_guess], approach, increments=4))
    res = prob.solve(steps=steps)
    Q, _ = cases.platen_history(res)
    top = res.history[2]
    hz = _hertz(top.normal_force)
    return h, top, hz, Q[2]


def fig_cattaneo_mindlin_resolutions(out: pathlib.Path) -> pathlib.Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(10, 4), sharey=True)
    for ax, a_over_h in zip(axes, (12.0, 25.0)):
        h, top, hz, Q = _cm_plain(a_over_h)
        a = hz.contact_radius
        r, _, qx, w, _ = cases.radial_profile(top.frame)
        inner = r < 0.9 * a
        exact = ref.cattaneo_mindlin_traction(r[inner], hz, Q, MU)
        l2 = cases.weighted_l2(qx[inner], exact, w[inner])
        c = cases.stick_radius(top.frame)
        c_exact = ref.cattaneo_mindlin_stick_radius(a, Q, MU, top.normal_force)
        print(f"  a/h = {a / h:.1f}: q L2 {l2:.4f}, stick radius {c / c_exact - 1:+.4f}")
        scale = MU * hz.peak_pressure
        rr = np.linspace(0.0, 1.2 * a, 400)
        ax.plot(r / a, qx / scale, ".", ms=3, label="bemcontact (frame nodes)")
        ax.plot(rr / a, ref.cattaneo_mindlin_traction(rr, hz, Q, MU) / scale, "k-", lw=1,
                label="Cattaneo–Mindlin")
        ax.axvline(c_exact / a, color="0.6", ls=":", lw=1)
        ax.set_xlim(0, 1.2)
        ax.set_xlabel("r / a")
        ax.set_title(f"a/h = {a / h:.1f}: $q_x$ L2 (r < 0.9a) {l2:.1%}, "
                     f"stick radius {c / c_exact - 1:+.2%}", fontsize=9)
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("$q_x$ / (μ $p_0$)")
    axes[0].legend(fontsize=8)
    fig.suptitle(f"Cattaneo–Mindlin on plain graded meshes (no ring), μ = {MU}, Q = 0.5 μP",
                 fontsize=10)
    fig.tight_layout()
    path = out / "cattaneo_mindlin_resolutions.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def fig_fretting_loop(out: pathlib.Path) -> pathlib.Path:
    h, _, q_max, res = frictional()
    Q, U = cases.platen_history(res)
    k0 = 1 + 1 + len(RATIOS) - 1  # the step at Q*
    P = res.history[k0].normal_force
    a = _hertz(P).contact_radius
    S = SETUP.tangential_compliance_factor
    delta = cases.tangential_approach(Q, U, a, S)
    # analytic: Cattaneo–Mindlin loading 0 -> Q*, then the Mindlin–Deresiewicz loop
    ql = np.linspace(0.0, q_max, 100)
    dl = np.array([ref.cattaneo_mindlin_displacement(q, MU, P, a, S) for q in ql])
    qa = np.linspace(q_max, -q_max, 200)
    d_un = ref.mindlin_deresiewicz_unloading(qa, q_max, MU, P, a, S)
    ua = np.concatenate([dl, [np.nan], d_un, -d_un])
    fa = np.concatenate([ql, [np.nan], qa, -qa])
    loop_Q, loop_U = Q[k0:], U[k0:]
    poly_Q, poly_U = loop_Q[:-1], loop_U[:-1]
    W = 0.5 * abs(np.sum(poly_Q * np.roll(poly_U, -1) - np.roll(poly_Q, -1) * poly_U))
    W_closed = ref.fretting_loop_energy(q_max, MU, P, a, S)
    print(f"  loop energy {W:.5g} N mm vs closed form {W_closed:.5g} ({W / W_closed - 1:+.4f}); "
          f"closure {(loop_U[-1] - loop_U[0]) / loop_U[0]:+.1e}; Newton iterations per increment "
          f"{[st.iterations for st in res.steps]}")
    for kk, ratio in zip((2, 3), RATIOS):
        d_exact = ref.cattaneo_mindlin_displacement(Q[kk], MU, res.history[kk].normal_force,
                                                    _hertz(res.history[kk].normal_force).contact_radius, S)
        print(f"  tangential approach at Q = {ratio} mu P: {delta[kk]:.4e} mm vs {d_exact:.4e} "
              f"({delta[kk] / d_exact - 1:+.4f})")
    return plot_force_displacement(
        1e3 * delta, Q, out / "fretting_loop.png", analytic=(1e3 * ua, fa),
        title=(f"fretting loop, hemisphere on block, μ = {MU}\nQ* = {q_max / (MU * P):.2f} μP, "
               f"tri3 h = {h:g} mm; loop energy {W:.3g} N mm\n(Mindlin–Deresiewicz {W_closed:.3g} N mm)"),
        xlabel="contact tangential approach δ (μm)",
        ylabel="tangential force Q (N)",
    )


def _patch(rule: str):
    m1 = bc.box((0, 0, 0), (2, 2, 1), (7, 7, 2), element_type="quad4")
    m2 = bc.box((0, 0, 1), (2, 2, 2), (11, 11, 2), element_type="quad4")
    lower = bc.ElasticBody(
        m1, MAT1, {"zmin": bc.Displacement((None, None, 0.0)), **ROLLERS}, name="lower"
    )
    upper = bc.ElasticBody(m2, MAT2, {"zmax": bc.Pressure(P0), **ROLLERS}, name="upper")
    problem = bc.ContactProblem(lower, upper, bc.ContactPair("zmax", "zmin", 0.0, rule))
    return problem.solve(bc.SolverOptions(tolerance=1e-12))


def fig_patch_test(out: pathlib.Path) -> pathlib.Path:
    from matplotlib.figure import Figure

    fig = Figure(figsize=(10.0, 4.2), layout="constrained")
    axes = fig.subplots(1, 2, sharey=True)
    for ax, rule in zip(axes, ("mortar", "collocation")):
        res = _patch(rule)
        errs = []
        for face, m in zip(res.interfaces, ("o", "s")):
            ok = np.isfinite(face.pressure)
            ax.plot(face.points[ok, 0], face.pressure[ok], m, markersize=3, alpha=0.6,
                    label=f"{face.body} interface nodes")
            errs.append(np.abs(face.pressure[ok] / P0 - 1).max())
        fr = res.frame
        act = fr.weights > 0
        ax.plot(fr.points[act, 0], fr.pressure[act], "+", markersize=5, color="k", label="frame nodes")
        ax.axhline(P0, color="r", linewidth=1.0, label="exact 10 MPa")
        ax.set_title(f"{rule} rule: max |p/p0 − 1| = {max(errs):.1e}", fontsize=10)
        ax.set_xlabel("x (mm)")
        ax.grid(True, alpha=0.3)
        print(f"  {rule}: largest body pressure error {max(errs):.2e}, frame "
              f"{np.abs(fr.pressure[act] / P0 - 1).max():.2e}, {res.newton_iterations} Newton it.")
    axes[0].set_ylabel("contact pressure p (MPa)")
    axes[0].legend(fontsize=8, loc="lower center")
    fig.suptitle("contact patch test, frictionless, lower quad4 7×7 / upper quad4 11×11 "
                 "(E 1e4 / 3e4 MPa), p0 = 10 MPa on top")
    return save_png(fig, out / "patch_test.png")


def fig_two_cubes(out: pathlib.Path) -> pathlib.Path:
    spec = importlib.util.spec_from_file_location(
        "two_cubes_figure", ROOT / "examples" / "two_cubes_figure.py"
    )
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    png = out / "two_cubes_figure1.png"
    with tempfile.TemporaryDirectory() as tmp:
        dirs = []
        for case in ("similar", "dissimilar"):
            prob = load_problem(ROOT / "examples" / f"two_cubes_{case}.toml")
            res = prob.contact_problem().solve(prob.options, steps=list(prob.steps) or None)
            d = pathlib.Path(tmp) / case
            write_results(res, d, prob.echo, OutputOptions(vtu=False, figures=False))
            dirs.append(str(d))
            print(f"  {case}: normal force {res.normal_force:.3f} N, {res.frame.counts()}, "
                  f"{res.newton_iterations} Newton it.")
        values = mod.run(*dirs, str(png))
    for k, v in values.items():
        print(f"  {k} = {v:.4g} mm")
    return png


def fig_two_spheres_shear(out: pathlib.Path) -> pathlib.Path:
    """Two identical hemispheres pressed together with mu = 0.3 (the set-up
    of tests/validation/test_frame_between.py's defaults, h = 0.1 mm, 4
    increments): |q| / p0 against r for the frame between the surfaces
    (auto) and for the frame on one sphere; symmetry makes the exact shear
    zero."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(10.0, 4.2), layout="constrained")
    ax, ax2 = fig.subplots(1, 2)
    for on, label, m in (("coarser", "frame on one sphere", "s"), ("auto", "frame between (auto)", "o")):
        p = cases.two_spheres(0.1, gap=0.0, approach=0.06, friction_coefficient=0.3, frame_on=on)
        res = p.solve(bc.SolverOptions(load_steps=4))
        fr = res.frame
        r = np.hypot(fr.points[:, 0], fr.points[:, 1])
        p0 = fr.pressure.max()
        q = np.linalg.norm(fr.tangential_traction, axis=1) / p0
        closed = fr.state > 0
        print(f"  {label}: max |q| = {q.max():.4f} p0, P = {res.normal_force:.2f} N")
        ax.plot(r[closed], q[closed], m, markersize=2.5, label=f"{label}: max {q.max():.3f} p0")
        if on == "auto":
            ax2.plot(r[closed], fr.pressure[closed] / p0, "o", markersize=2.5, label="bemcontact")
            hz = ref.hertz(res.normal_force, cases.SphereOnBlock().radius / 2,
                           cases.SphereOnBlock().contact_modulus)
            grid = np.linspace(0.0, hz.contact_radius, 300)
            ax2.plot(grid, np.sqrt(1 - (grid / hz.contact_radius) ** 2), "k-", linewidth=1.2,
                     label="Hertz, R_eff = R/2")
    ax.axhline(0.01, color="0.6", linewidth=0.8, linestyle=":")
    ax.set_xlabel("r (mm)")
    ax.set_ylabel("|q| / p0 at closed frame nodes")
    ax.set_title("shear between identical spheres (exact: 0)", fontsize=10)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    ax2.set_xlabel("r (mm)")
    ax2.set_ylabel("p / p0")
    ax2.set_title("pressure, frame between", fontsize=10)
    ax2.grid(True, alpha=0.3)
    ax2.legend(fontsize=8)
    return save_png(fig, out / "two_spheres_shear.png")


def _curvature_case(kind: str, R: float, h: float):
    """(result, share, rms) of one frictional solve (mu = 0.3, 4 increments)
    at a = 0.556 mm: crossed cylinders of radius R, spheres R and 2R, or two
    identical spheres of radius R."""
    from bemcontact.validation import curved

    s = cases.SphereOnBlock(radius=R)
    if kind == "cylinders":
        p = curved.crossed_cylinders(h, 0.556**2 / R, setup=s, friction_coefficient=MU)
    else:
        R2 = 2 * R if kind == "spheres" else R
        p = cases.two_spheres(h, gap=0.0, approach=0.556**2 * (R + R2) / (R * R2), setup=s,
                              friction_coefficient=MU, upper_radius=R2)
    res = p.solve(bc.SolverOptions(load_steps=4))
    share, rms = curved.shear_pattern(res.frame, "saddle" if kind == "cylinders" else "radial")
    return res, share, rms


def fig_curvature_shear(out: pathlib.Path) -> pathlib.Path:
    """Identical steel bodies pressed together with mu = 0.3: the shear of
    different curvatures converges to a field of the pair's symmetry whose
    size is first order in a/R; that of mirror-image spheres is noise that
    falls under refinement."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(10.5, 4.4), layout="constrained")
    ax, ax2 = fig.subplots(1, 2)
    series = (("cylinders", 10.0, "crossed cylinders, a/R = 0.056", "o-"),
              ("cylinders", 20.0, "crossed cylinders, a/R = 0.028", "o--"),
              ("spheres", 10.0, "spheres R, 2R, a/R = 0.056", "s-"),
              ("spheres", 20.0, "spheres R, 2R, a/R = 0.028", "s--"),
              ("identical", 10.0, "identical spheres (exact: 0)", "^:"))
    for kind, R, label, style in series:
        aoh, rms_ = [], []
        for h in (0.1, 0.07, 0.05):
            res, share, rms = _curvature_case(kind, R, h)
            a = res.frame.points[res.frame.pressure > 0, :2]
            aoh.append(np.hypot(a[:, 0], a[:, 1]).max() / h)
            rms_.append(rms)
            print(f"  {label}: h = {h}: rms |q| {rms:.4f} p0, pattern share {share:.2f}")
            if kind == "cylinders" and R == 10.0 and h == 0.05:
                fr = res.frame
                c = fr.pressure > 0
                qn = fr.tangential_traction[c, :2] / fr.pressure.max()
                ax.quiver(fr.points[c, 0], fr.points[c, 1], qn[:, 0], qn[:, 1], angles="xy",
                          scale_units="xy", scale=0.02 / 0.1, width=0.003)
        ax2.plot(aoh, rms_, style, label=label)
    ax.set_aspect("equal")
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    ax.set_title("crossed cylinders (R = 10 mm, h = 0.05 mm): q at closed nodes\n"
                 "(arrow 0.1 mm = 0.02 p0): the saddle (x, -y)", fontsize=10)
    ax2.set_xlabel("a / h (closed frame radius / h)")
    ax2.set_ylabel("rms |q| / p0 over the contact")
    ax2.set_ylim(0.0, 0.0105)
    ax2.set_title("shear under normal load, identical steel, mu = 0.3", fontsize=10)
    ax2.grid(True, alpha=0.3)
    ax2.legend(fontsize=8, loc="upper left")
    return save_png(fig, out / "curvature_shear.png")


def fig_boussinesq(out: pathlib.Path) -> pathlib.Path:
    from matplotlib.figure import Figure

    a = PUNCH.radius
    fig = Figure(figsize=(10.0, 4.2), layout="constrained")
    ax, ax2 = fig.subplots(1, 2)
    rows = []
    for rim in PUNCH_RIMS:
        res, comp, e = punch(rim)
        rows.append((rim, e.force, e.profile_l2))
        print(f"  rim {rim:g} a: F = {res.normal_force:.3f} N, raw {e.raw_force:+.4f}, block "
              f"compliance {comp.compliance:.4e} mm/N (spread {comp.spread:.1e}), corrected "
              f"{e.force:+.4f}, profile L2 (r < 0.8a) {e.profile_l2:.4f}, "
              f"{res.newton_iterations} Newton it., "
              f"{res.timings['total']:.0f} s")
    res, _, e = punch(PUNCH_RIMS[-1])
    l2 = e.profile_l2
    r, p, _, _, state = cases.radial_profile(res.frame)
    under = r < a
    F = res.normal_force
    grid = np.linspace(0.0, 0.995 * a, 400)
    pm = F / (np.pi * a * a)
    ax.plot(r[under] / a, p[under] / pm, "o", markersize=2.5, label="bemcontact (frame nodes, r < a)")
    ax.plot(grid / a, ref.boussinesq_punch_pressure(grid, a, F) / pm, "k-", linewidth=1.2,
            label="Boussinesq, same F")
    ax.axvline(0.8, color="0.6", linewidth=0.8, linestyle="--")
    ax.set_ylim(0.0, 3.0)
    ax.set_xlabel("r / a")
    ax.set_ylabel("p / (F / π a²)")
    ax.set_title(f"pressure, rim size {PUNCH_RIMS[-1]:g} a: L2 (r < 0.8a) {l2:.1%}", fontsize=10)
    ax.grid(True, alpha=0.3)
    ax.legend(loc="upper left", fontsize=8)
    hs = np.array([x[0] for x in rows])
    for k, (name, m) in enumerate((("force, block corrected", "o"), ("profile L2 (r < 0.8a)", "s"))):
        e = np.array([abs(x[1 + k]) for x in rows])
        ax2.loglog(hs, 100 * e, m + "-", label=f"{name}: rate {cases.fitted_rate(hs, e):.1f}")
    ax2.axhline(2.0, color="0.6", linewidth=0.8, linestyle=":")
    ax2.set_xticks(hs, [f"{h:g}" for h in hs])
    ax2.minorticks_off()
    ax2.set_xlabel("element size at the rim (units of a)")
    ax2.set_ylabel("relative error vs Boussinesq (%)")
    ax2.set_title("convergence", fontsize=10)
    ax2.grid(True, which="both", alpha=0.3)
    ax2.legend(fontsize=8)
    fig.suptitle(
        f"Boussinesq flat punch (a = {a:g} mm, 10⁴ × stiffer) on a steel block "
        f"{2 * PUNCH.block_half_width:g} × {2 * PUNCH.block_half_width:g} × {PUNCH.block_depth:g} mm, "
        f"δ = {PUNCH_DELTA:g} mm, frictionless"
    )
    return save_png(fig, out / "boussinesq_punch.png")


FIGURES = {
    "patch_test": fig_patch_test,
    "two_cubes_figure1": fig_two_cubes,
    "hertz_pressure": fig_hertz_pressure,
    "hertz_convergence": fig_hertz_convergence,
    "cattaneo_mindlin_traction": fig_cattaneo_mindlin,
    "fretting_loop": fig_fretting_loop,
    "boussinesq_punch": fig_boussinesq,
    "two_spheres_shear": fig_two_spheres_shear,
    "curvature_shear": fig_curvature_shear,
    "cattaneo_mindlin_resolutions": fig_cattaneo_mindlin_resolutions,
}


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--only", action="append", choices=list(FIGURES), metavar="NAME",
                    help=f"regenerate only this figure (repeatable): {', '.join(FIGURES)}")
    ap.add_argument("--out", default=str(HERE), help="output directory (default: docs/figures)")
    args = ap.parse_args(argv)
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    total = time.perf_counter()
    for name in args.only or FIGURES:
        t0 = time.perf_counter()
        print(f"{name}:", flush=True)
        path = FIGURES[name](out)
        print(f"  wrote {path} in {time.perf_counter() - t0:.1f} s", flush=True)
    print(f"total {time.perf_counter() - total:.1f} s")


if __name__ == "__main__":
    main(sys.argv[1:])

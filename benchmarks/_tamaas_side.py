"""Tamaas side of ``benchmarks/hertz_mindlin_vs_tamaas.py``.

Solves the Hertz and Cattaneo–Mindlin problems with Tamaas (PyPI ``tamaas``,
benchmark-only dependency, AGPL-3.0; a manylinux wheel for CPython 3.11 /
x86_64) at a prescribed contact-zone resolution a/h and reports the error
against the analytic solutions and the CPU seconds of the solve.

What Tamaas solves here (Tamaas 2.9.0):

* Hertz: ``tamaas.PolonskyKeerRey`` on a ``basic_2d`` model (rigid paraboloid
  z = -r^2/(2R) on one elastic half-space of contact modulus E*), force
  controlled by the mean pressure P/L^2.  Two integral operators:
  ``method="dcfft"`` (default) registers Tamaas's non-periodic DC-FFT
  Boussinesq operator, so the answer is the true (isolated) half-space one and
  the grid only has to hold the contact (L = 3a); ``method="periodic"`` uses
  the default periodic operator (an array of spheres, period L; L = 8a by
  default, images bias p0 by ~+0.25 % at L = 8a, ~+0.04 % at L = 16a).
* Cattaneo–Mindlin: ``tamaas.PolonskyKeerTan`` (Coulomb friction, classical
  non-associated law) on a ``surface_2d`` model (3 traction components), with
  the whole mean traction (Q/L^2, 0, P/L^2) imposed in ONE solve.  For
  decoupled normal/tangential elasticity that single increment is exactly the
  Cattaneo problem (P then Q at constant P, monotonic Q: the final state only
  depends on the total slip).  Only a periodic operator exists for the
  tangential problem, so L = 8a by default.

Fairness (normal–tangential coupling).  The analytic Cattaneo–Mindlin solution
assumes the normal and tangential problems are decoupled, which holds for two
bodies of identical material (and approximately for Mindlin's
q_x-only traction).  Tamaas has one elastic half-space under a rigid surface;
its Boussinesq–Cerruti operator carries the (1 - 2 nu) coupling, which vanishes
only for nu = 0.5.  So with ``bodies="identical"`` (default) the Tamaas
half-space is given nu_T = 0.5 and E_T = 0.75 E* (so its contact modulus is the
problem's E* = E / (2 (1 - nu^2))): same a, p0, stick radius and traction as
the identical-bodies problem the analytic formula describes.  Its tangential
compliance is that of a nu = 0.5 half-space, so ``delta_t`` is compared with
the Mindlin formula for Tamaas's own half-space (S = (2 - nu_T) / G_T), not with
the two-body value.  ``bodies="rigid"`` keeps the real nu (rigid sphere on an
elastic half-space, E* = E / (1 - nu^2)): Tamaas then solves the coupled
problem, which is NOT Cattaneo–Mindlin (at nu = 0.3 the one-shot solve shows
large radial frictional tractions, q error ~100 %); it is there for
information only.

Stopping rule for PolonskyKeerTan.  Its returned "error" does not go to zero:
it stalls at a problem-dependent floor (3e-10 .. 3e-9 here) and is not
monotone (it dips below the floor before the load constraint is met), so a
tolerance either never stops the solver or stops it ~40 % short.  The solver
is not warm-startable (every solve restarts from zero).  So the tolerance is
set unreachable (1e-15) and the iteration count is the control: runs with
n = n0, n0*g, n0*g^2, ... iterations; n is accepted when its traction field
differs from the next run's by less than ``field_tol`` (1e-6, relative L2).
``cpu_seconds`` is that accepted run alone (what a user who knows n pays);
``cpu_seconds_search`` adds the whole search.

Loading history: Tamaas's friction solvers take one total load and keep no
state (no increments, no unloading), so Mindlin–Deresiewicz loops, or the
coupled (nu != 0.5) problem with P applied before Q, are out of their reach.

Grids: h = a_exact / (a/h); N = the smallest even 2^i 3^j 5^k 7^l >= (L/a)(a/h)
(FFTW-friendly; N = 76 was measured 2x slower than N = 80), L = N h, the apex
on a grid node.  Tamaas fields are nodal values of a spectral (trigonometric)
discretisation, not piecewise-constant panels.

Threads: the PyPI wheel is built with the sequential ("cpp") Thrust backend
and a statically linked FFTW 3.3.10 without threads or OpenMP, so Tamaas runs
on one thread whatever ``tamaas.initialize(n)``/OMP_NUM_THREADS say; CPU
seconds ~= wall seconds on an idle machine.

Units: any consistent set (the defaults below: mm, N, MPa).
"""

from __future__ import annotations

import contextlib
import importlib
import math
import os
import subprocess
import sys
import time

import numpy as np

TAMAAS_REQUIREMENT = "tamaas==2.9.0"

# Regularised lattice sum  lim_{r->0} [ sum_n 1/|r - n| - 1/r ]  over the unit
# square lattice with a neutralising background (zero-mean periodic field):
# 4 zeta(1/2) beta(1/2).  The periodic zero-mean displacement of a point load
# F with kernel C/r is u_per(r) = C F [1/r + ZETA_SQ / L + O(r^2 / L^3)], so the
# half-space displacement is u_per - C F ZETA_SQ / L near the load.
ZETA_SQ = -3.900264920001955


class TamaasMissing(ImportError):
    """Raised when the ``tamaas`` package cannot be imported."""


def _import_tamaas():
    try:
        return importlib.import_module("tamaas")
    except ImportError as exc:
        raise TamaasMissing(
            "the Tamaas comparison needs the PyPI package 'tamaas' "
            f"({TAMAAS_REQUIREMENT}; benchmark-only, AGPL-3.0). Install it into this "
            f"interpreter with:  {sys.executable} -m pip install {TAMAAS_REQUIREMENT}  "
            "(or call benchmarks._tamaas_side.ensure_tamaas()).  "
            f"Import error: {exc}"
        ) from exc


def ensure_tamaas(requirement: str = TAMAAS_REQUIREMENT):
    """Return the ``tamaas`` module, pip-installing ``requirement`` into the
    running interpreter (``sys.executable -m pip install``) first if needed."""
    try:
        return importlib.import_module("tamaas")
    except ImportError:
        pass
    cmd = [sys.executable, "-m", "pip", "install", requirement]
    print("tamaas not importable; installing: " + " ".join(cmd), flush=True)
    t0 = time.perf_counter()
    subprocess.run(cmd, check=True)
    print(f"installed {requirement} in {time.perf_counter() - t0:.1f} s", flush=True)
    importlib.invalidate_caches()
    return _import_tamaas()


def tamaas_available(install: bool) -> bool:
    """Whether Tamaas can run here (``install``: pip-install it first if
    missing); says why not on stdout, so a benchmark goes on with its own
    rows only."""
    try:
        ensure_tamaas() if install else tamaas_info()
    except (TamaasMissing, subprocess.CalledProcessError) as exc:
        print(f"Tamaas unavailable ({exc}); bemcontact rows only")
        return False
    return True


def tamaas_info() -> dict:
    tm = _import_tamaas()
    info = tm.TamaasInfo
    return {"version": tm.__version__, "backend": info.backend, "build_type": info.build_type,
            "has_mpi": bool(info.has_mpi)}


@contextlib.contextmanager
def _quiet_stdout():
    """Tamaas's C++ solvers print an 'Iter Cost_f Error' header to fd 1
    whatever the log level; send fd 1 to /dev/null meanwhile."""
    sys.stdout.flush()
    saved = os.dup(1)
    devnull = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(devnull, 1)
        yield
    finally:
        os.dup2(saved, 1)
        os.close(saved)
        os.close(devnull)


def _fft_size(n: int) -> int:
    """Smallest even m >= n whose prime factors are 2, 3, 5, 7 (FFTW-friendly)."""
    m = max(2, n + n % 2)
    while True:
        k = m
        for f in (2, 3, 5, 7):
            while k % f == 0:
                k //= f
        if k == 1:
            return m
        m += 2


def _grid(a: float, a_over_h: float, L_over_a: float):
    """h = a / a_over_h; N >= L_over_a * a_over_h, even (the paraboloid apex,
    at L/2, is then a grid point) and FFT-friendly; L = N h."""
    h = a / float(a_over_h)
    N = _fft_size(int(math.ceil(L_over_a * a_over_h - 1e-9)))
    L = N * h
    x = np.arange(N) * h - L / 2
    X, Y = np.meshgrid(x, x, indexing="ij")
    return h, N, L, np.hypot(X, Y)


def _paraboloid(L: float, N: int, R: float) -> np.ndarray:
    from tamaas.utils import hertz_surface

    return np.ascontiguousarray(hertz_surface([L, L], [N, N], R))


def _rel_l2(num, exact, mask) -> float:
    return float(np.sqrt(np.sum((num - exact)[mask] ** 2) / np.sum(exact[mask] ** 2)))


def _hertz_exact(R, E_star, P):
    a = (3.0 * P * R / (4.0 * E_star)) ** (1.0 / 3.0)
    return a, 3.0 * P / (2.0 * math.pi * a * a)


def _timed(fn):
    c0, w0 = time.process_time(), time.perf_counter()
    out = fn()
    return out, time.process_time() - c0, time.perf_counter() - w0


def hertz(R: float, E_star: float, P: float, a_over_h: float, *, method: str = "dcfft",
          L_over_a: float | None = None, tol: float = 1e-12, repeat: int = 3) -> dict:
    """Hertz with ``tamaas.PolonskyKeerRey``; grid spacing h = a_exact / a_over_h.

    ``method``: "dcfft" (non-periodic half-space, default L = 3a) or
    "periodic" (default L = 8a).  Errors: ``l2_error`` is the relative L2 error
    of the pressure over the nodes with r < 0.9 a_exact; ``a_num`` =
    sqrt(A_contact / pi) with A_contact = h^2 * (number of nodes with p > 0);
    ``a_fit`` from a least-squares fit of p^2 = p0^2 (1 - r^2/a^2);
    ``approach`` is the rigid-body approach delta (exact a^2 / R).  The solve
    is repeated ``repeat`` times on fresh models; the least CPU time is kept."""
    tm = _import_tamaas()
    tm.set_log_level(tm.LogLevel.error)
    if method not in ("dcfft", "periodic"):
        raise ValueError(f"method must be 'dcfft' or 'periodic', got {method!r}")
    if L_over_a is None:
        L_over_a = 3.0 if method == "dcfft" else 8.0
    a, p0 = _hertz_exact(R, E_star, P)
    h, N, L, r = _grid(a, a_over_h, L_over_a)

    surface = _paraboloid(L, N, R)
    cpu = wall = t_setup = math.inf
    for _ in range(max(1, repeat)):
        t0 = time.process_time()
        model = tm.ModelFactory.createModel(tm.model_type.basic_2d, [L, L], [N, N])
        model.E, model.nu = E_star, 0.0  # normal contact only depends on E* = E / (1 - nu^2)
        solver = tm.PolonskyKeerRey(model, surface, tol)
        solver.max_iter = 10000
        if method == "dcfft":
            tm.ModelFactory.registerNonPeriodic(model, "dcfft")
            solver.setIntegralOperator("dcfft")
        t_setup = min(t_setup, time.process_time() - t0)
        err, c, w = _timed(lambda: solver.solve(P / (L * L)))
        cpu, wall = min(cpu, c), min(wall, w)

    p = np.array(model.traction, copy=True).reshape(N, N)
    contact = p > 0
    c = N // 2
    if method == "dcfft":
        # the solver shifts the displacement so that the gap is 0 in contact;
        # the absolute half-space displacement is recovered post-solve:
        model.operators["dcfft"](model.traction, model.displacement)
        u = np.array(model.displacement).reshape(N, N)
        approach = float(u[c, c])
    else:
        u = np.array(model.displacement).reshape(N, N)
        approach = float(u[c, c] - u.mean() - P * ZETA_SQ / (math.pi * E_star * L))
    p_exact = p0 * np.sqrt(np.clip(1.0 - (r / a) ** 2, 0.0, None))
    fit = contact & (r < 0.9 * a)
    slope, icpt = np.polyfit(r[fit] ** 2, p[fit] ** 2, 1)
    return {
        "code": "tamaas", "problem": "hertz", "method": method,
        "a_over_h": float(a_over_h), "h": h, "n_grid": N, "n_nodes": N * N,
        "domain": L, "L_over_a": L / a,
        "a_num": math.sqrt(contact.sum() * h * h / math.pi), "a_fit": math.sqrt(-icpt / slope),
        "a_exact": a,
        "p0_num": float(p.max()), "p0_exact": p0,
        "l2_error": _rel_l2(p, p_exact, r < 0.9 * a),
        "force_num": float(p.sum() * h * h),
        "approach_num": approach, "approach_exact": a * a / R,
        "cpu_seconds": cpu, "wall_seconds": wall, "setup_cpu_seconds": t_setup,
        "solver": "PolonskyKeerRey" + ("+dcfft" if method == "dcfft" else ""),
        "solver_error": float(err), "tol": tol,
    }


def cattaneo_mindlin(R: float, E: float, nu: float, mu: float, P: float, Q_ratio: float,
                     a_over_h: float, *, bodies: str = "identical", L_over_a: float = 8.0,
                     iterations: int | None = None, field_tol: float = 1e-6,
                     n_start: int = 200, growth: float = 1.5, max_iterations: int = 20000,
                     slip_tol: float = 1e-6) -> dict:
    """Cattaneo–Mindlin (P, then Q = Q_ratio * mu * P) with
    ``tamaas.PolonskyKeerTan``; h = a_exact / a_over_h, periodic L = L_over_a * a.

    ``bodies``: "identical" (E* = E / (2 (1 - nu^2)); Tamaas half-space with
    nu_T = 0.5, E_T = 0.75 E*, decoupled like the analytic solution) or
    "rigid" (E* = E / (1 - nu^2), Tamaas with the real nu: coupled, not the
    Cattaneo–Mindlin problem).  ``iterations`` fixes the solver's iteration
    count (skips the convergence search described in the module docstring).

    ``c_num`` = sqrt(A_stick / pi), stick nodes: p > 0 and |q| < mu p (1 -
    slip_tol); ``q_l2_error``: relative L2 error of q_x (the component along Q)
    against Mindlin's q(r) over r < 0.9 a; ``delta_t_num``: tangential
    approach of the stick zone relative to distant points (periodic zero-mean
    displacement corrected by the lattice constant), compared with Mindlin's
    delta_t for Tamaas's half-space (S = (2 - nu_T) / G_T)."""
    tm = _import_tamaas()
    tm.set_log_level(tm.LogLevel.error)
    if not 0.0 <= Q_ratio < 1.0:
        raise ValueError("need 0 <= Q/(mu P) < 1 (partial slip)")
    if bodies == "identical":
        E_star = E / (2.0 * (1.0 - nu * nu))
        nu_T = 0.5
    elif bodies == "rigid":
        E_star = E / (1.0 - nu * nu)
        nu_T = nu
    else:
        raise ValueError(f"bodies must be 'identical' or 'rigid', got {bodies!r}")
    E_T = E_star * (1.0 - nu_T * nu_T)
    G_T = E_T / (2.0 * (1.0 + nu_T))

    a, p0 = _hertz_exact(R, E_star, P)
    Q = Q_ratio * mu * P
    c_exact = a * (1.0 - Q_ratio) ** (1.0 / 3.0)
    h, N, L, r = _grid(a, a_over_h, L_over_a)
    surface = _paraboloid(L, N, R)
    mean_traction = [Q / (L * L), 0.0, P / (L * L)]

    def run(n_iter: int):
        model = tm.ModelFactory.createModel(tm.model_type.surface_2d, [L, L], [N, N])
        model.E, model.nu = E_T, nu_T
        solver = tm.PolonskyKeerTan(model, surface, 1e-15, mu)  # unreachable: n_iter is the control
        solver.max_iter = int(n_iter)
        with _quiet_stdout():
            err, cpu, wall = _timed(lambda: solver.solve(mean_traction))
        t = np.array(model.traction, copy=True).reshape(N, N, 3)
        u = np.array(model.displacement, copy=True).reshape(N, N, 3)
        return {"n": int(n_iter), "t": t, "u": u, "cpu": cpu, "wall": wall, "err": float(err)}

    runs = []
    if iterations is not None:
        best = run(iterations)
        runs.append(best)
        field_change = float("nan")
    else:
        n = n_start
        runs.append(run(n))
        best, field_change = None, float("nan")
        while best is None:
            n = int(math.ceil(n * growth))
            if n > max_iterations:
                raise RuntimeError(
                    f"PolonskyKeerTan: traction field not converged to {field_tol} within "
                    f"{max_iterations} iterations (last change {field_change:.2e})")
            runs.append(run(n))
            prev, last = runs[-2]["t"], runs[-1]["t"]
            field_change = float(np.linalg.norm(prev - last) / np.linalg.norm(last))
            if field_change < field_tol:
                best = runs[-2]

    t, u = best["t"], best["u"]
    qx, qy, p = t[..., 0], t[..., 1], t[..., 2]
    qmag = np.hypot(qx, qy)
    contact = p > 0
    stick = contact & (qmag < mu * p * (1.0 - slip_tol))
    inner = r < 0.9 * a
    p_exact = p0 * np.sqrt(np.clip(1.0 - (r / a) ** 2, 0.0, None))
    q_exact = mu * p_exact - (c_exact / a) * mu * p0 * np.sqrt(
        np.clip(1.0 - (r / c_exact) ** 2, 0.0, None))
    cc = N // 2
    delta_t_num = float(u[cc, cc, 0] - u[..., 0].mean()
                        - Q * (2.0 - nu_T) * ZETA_SQ / (4.0 * math.pi * G_T * L))
    delta_t_exact = (3.0 * mu * P * (2.0 - nu_T) / (16.0 * G_T * a)
                     * (1.0 - (1.0 - Q_ratio) ** (2.0 / 3.0)))
    return {
        "code": "tamaas", "problem": "cattaneo_mindlin", "bodies": bodies,
        "a_over_h": float(a_over_h), "h": h, "n_grid": N, "n_nodes": N * N,
        "domain": L, "L_over_a": L / a,
        "E_star": E_star, "tamaas_E": E_T, "tamaas_nu": nu_T,
        "a_num": math.sqrt(contact.sum() * h * h / math.pi), "a_exact": a,
        "c_num": math.sqrt(stick.sum() * h * h / math.pi), "c_exact": c_exact,
        "p_l2_error": _rel_l2(p, p_exact, inner),
        "q_l2_error": _rel_l2(qx, q_exact, inner),
        "q_l2_error_magnitude": _rel_l2(qmag, q_exact, inner),
        "qy_over_qx_max": float(np.abs(qy).max() / np.abs(qx).max()),
        "force_num": [float(qx.sum() * h * h), float(qy.sum() * h * h), float(p.sum() * h * h)],
        "delta_t_num": delta_t_num, "delta_t_exact": delta_t_exact,
        "cpu_seconds": best["cpu"], "wall_seconds": best["wall"],
        "iterations": best["n"], "field_change": field_change,
        "cpu_seconds_search": float(sum(x["cpu"] for x in runs)),
        "runs": [(x["n"], round(x["cpu"], 3)) for x in runs],
        "solver": "PolonskyKeerTan (Coulomb, periodic surface_2d)",
        "solver_error": best["err"],
    }


def _table(rows, cols):
    head = " ".join(f"{name:>{w}}" for name, _, w in cols)
    lines = [head, "-" * len(head)]
    for row in rows:
        lines.append(" ".join(f"{fmt(row):>{w}}" for _, fmt, w in cols))
    return "\n".join(lines)


def main(argv=None) -> int:
    import argparse

    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--a-over-h", type=float, nargs="+", default=[12.0, 25.0])
    ap.add_argument("--install", action="store_true", help="pip-install tamaas if missing")
    args = ap.parse_args(argv)
    if args.install:
        ensure_tamaas()
    try:
        info = tamaas_info()
    except TamaasMissing as exc:
        print(exc, file=sys.stderr)
        return 2

    R, E, nu, P, mu, Q_ratio = 10.0, 210000.0, 0.3, 100.0, 0.3, 0.5  # mm, MPa, N
    E_star = E / (2.0 * (1.0 - nu * nu))  # two identical steel bodies
    print(f"Tamaas {info['version']} (backend {info['backend']}, single thread); "
          f"R = {R} mm, E = {E} MPa, nu = {nu}, E* = {E_star:.1f} MPa, P = {P} N, "
          f"mu = {mu}, Q = {Q_ratio} mu P")
    hz = [hertz(R, E_star, P, s, method=m) for s in args.a_over_h for m in ("dcfft", "periodic")]
    print("\nHertz (PolonskyKeerRey, tol 1e-12)")
    print(_table(hz, [
        ("a/h", lambda d: f"{d['a_over_h']:.0f}", 4),
        ("operator", lambda d: d["method"], 9),
        ("L/a", lambda d: f"{d['L_over_a']:.2f}", 6),
        ("N", lambda d: f"{d['n_grid']}^2", 7),
        ("a_num/a", lambda d: f"{d['a_num'] / d['a_exact']:.4f}", 8),
        ("a_fit/a", lambda d: f"{d['a_fit'] / d['a_exact']:.5f}", 8),
        ("p0_num/p0", lambda d: f"{d['p0_num'] / d['p0_exact']:.5f}", 9),
        ("p L2 err", lambda d: f"{d['l2_error']:.2e}", 9),
        ("delta err", lambda d: f"{d['approach_num'] / d['approach_exact'] - 1:+.1e}", 9),
        ("CPU s", lambda d: f"{d['cpu_seconds']:.3f}", 7),
        ("wall s", lambda d: f"{d['wall_seconds']:.3f}", 7),
    ]))
    cm = [cattaneo_mindlin(R, E, nu, mu, P, Q_ratio, s) for s in args.a_over_h]
    print("\nCattaneo–Mindlin (PolonskyKeerTan, periodic, half-space nu_T = 0.5, E_T = 0.75 E*)")
    print(_table(cm, [
        ("a/h", lambda d: f"{d['a_over_h']:.0f}", 4),
        ("L/a", lambda d: f"{d['L_over_a']:.2f}", 6),
        ("N", lambda d: f"{d['n_grid']}^2", 7),
        ("c_num/c", lambda d: f"{d['c_num'] / d['c_exact']:.4f}", 8),
        ("q L2 err", lambda d: f"{d['q_l2_error']:.2e}", 9),
        ("p L2 err", lambda d: f"{d['p_l2_error']:.2e}", 9),
        ("|qy|/qx", lambda d: f"{d['qy_over_qx_max']:.3f}", 8),
        ("dt err", lambda d: f"{d['delta_t_num'] / d['delta_t_exact'] - 1:+.1e}", 8),
        ("iters", lambda d: f"{d['iterations']}", 6),
        ("CPU s", lambda d: f"{d['cpu_seconds']:.2f}", 7),
        ("wall s", lambda d: f"{d['wall_seconds']:.2f}", 7),
        ("search CPU s", lambda d: f"{d['cpu_seconds_search']:.1f}", 12),
    ]))
    return 0


if __name__ == "__main__":
    sys.exit(main())

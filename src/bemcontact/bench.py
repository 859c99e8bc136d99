"""Benchmark cases behind ``bemcontact bench`` (speed and accuracy together).

``two_cubes``: the founding paper's two cubes, [0,2]³ (K×K×K quad4 elements,
E = 1e4, base fixed) under [0,2]²×[2,4] ((K−1)³ elements, E = 1e8 "dissimilar"
or 1e4 "similar", top pushed down 0.04), μ = 0.1, mortar frame: non-matching
interfaces.  The whole run is timed (mesh, frame, assembly, condensation,
Newton) and the normal force reported.

``one_body``: a unit cube of quad4 elements with about the requested number
of functional nodes under mixed boundary conditions whose exact solution is a
linear displacement field (displacement on the three ``min`` faces, traction
on the others), so the error is measured with the speed.

Each function returns a flat dict with the keys the benchmark tables use:
nodes, unknowns, assembly_s, factor_s, solve_s, newton_s, newton_iterations,
peak_rss_mb, compressed_mb, dense_mb, error, normal_force, threads, version (the
package's; benchmark scripts record the commit),
plus method details.  Keys that do not apply are None.
"""

from __future__ import annotations

import dataclasses
import math
import resource
import time

import numpy as np

from ._version import __version__
from .bem import Displacement, ElasticBody, LinearElastic, Traction
from .linalg import HMatrixOptions, LinearSolverOptions
from .mesh import box


def peak_rss_mb() -> float:
    """This process's peak resident set, in MB (10^6 bytes, the unit of
    ``dense_mb`` and ``compressed_mb``; Linux reports KiB)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024 / 1e6


def cube_divisions(nodes: int) -> int:
    """Elements per edge of the quad4 cube whose functional node count,
    6 n² + 36 n - 18 (edge and corner nodes are discontinuous), is nearest to
    ``nodes``."""
    n = (-36 + math.sqrt(36**2 + 24 * (nodes + 18))) / 12
    return max(2, round(n))


def linear_field_cube(nodes: int | None = None, *, divisions: int | None = None):
    """The benchmark body: a unit cube of quad4 elements with about ``nodes``
    functional nodes (or ``divisions`` elements per edge), displacement
    given on the three ``min`` faces and traction on the others from one
    linear displacement field.  Returns (body, displacement gradient, stress)."""
    E, nu = 1.0e4, 0.3
    mat = LinearElastic(E, nu)
    grad = np.array([[1e-3, 2e-4, -3e-4], [5e-4, -2e-3, 1e-4], [2e-4, 3e-4, 1.5e-3]])
    strain = 0.5 * (grad + grad.T)
    lam = E * nu / ((1 + nu) * (1 - 2 * nu))
    sigma = lam * np.trace(strain) * np.eye(3) + 2 * mat.shear_modulus * strain
    n = divisions if divisions is not None else cube_divisions(nodes)
    mesh = box((0, 0, 0), (1, 1, 1), n)
    bcs = {
        r: Displacement(lambda X: X @ grad.T) if r.endswith("min") else Traction(lambda X, n: n @ sigma)
        for r in mesh.region_names
    }
    return ElasticBody(mesh, mat, bcs, name="cube"), grad, sigma


def one_body(
    nodes: int,
    *,
    method: str = "auto",
    eps: float = 1e-7,
    threads: int | None = None,
    leaf_size: int | None = None,
    truncation: str | None = None,
    storage: str | None = None,
) -> dict:
    """Solve the linear-field cube with about ``nodes`` functional nodes
    (``leaf_size``, ``truncation``, ``storage``: the H-matrix's, default
    HMatrixOptions')."""
    body, grad, sigma = linear_field_cube(nodes)
    given = {"leaf_size": leaf_size, "truncation": truncation, "storage": storage}
    hopt = HMatrixOptions(eps=eps, **{k: v for k, v in given.items() if v is not None})
    # GMRES to eps/10: the compressed A itself is only eps-accurate, so a
    # smaller residual buys nothing (20k nodes, eps 1e-8: 1e-9 and 1e-11 give
    # the same error vs exact, 1.9e-6, in 84 and 100 iterations, measured)
    linear = LinearSolverOptions(method=method, hmatrix=hopt, tolerance=min(1e-10, eps * 0.1))
    t0 = time.perf_counter()
    sol = body.solve(threads=threads, linear=linear)
    total = time.perf_counter() - t0
    exact_u = sol.points @ grad.T
    err = max(
        np.abs(sol.traction - sol.normals @ sigma).max() / np.abs(sigma).max(),
        np.abs(sol.displacement - exact_u).max() / np.abs(exact_u).max(),
    )
    N = sol.points.shape[0]
    info = sol.solver
    hm = info.get("method") == "hmatrix"
    from ._native import core as _core_module
    _core = _core_module()

    return {
        "case": "one-body",
        "method": info.get("method"),
        "nodes": int(N),
        "unknowns": int(3 * N),
        "assembly_s": sol.timings["assembly"],
        # dense: LAPACK getrf alone (inside solve_s); H-matrix: no factorization (GMRES)
        "factor_s": sol.timings.get("factor"),
        "solve_s": sol.timings["solve"],
        "total_s": total,
        "gmres_iterations": info.get("iterations"),
        "exact_residual": info.get("exact_residual"),
        "newton_s": None,
        "newton_iterations": None,
        "peak_rss_mb": peak_rss_mb(),
        "compressed_mb": info.get("compressed_mb"),
        "dense_mb": 8.0 * (3 * N) ** 2 / 1e6,
        "mean_rank": info.get("mean_rank"),
        "eps": eps if hm else None,
        "leaf_size": hopt.leaf_size if hm else None,
        "truncation": hopt.truncation if hm else None,
        "storage": hopt.storage if hm else None,
        "error": float(err),
        "normal_force": None,
        "threads": threads if threads is not None else _core.max_threads(),
        "version": __version__,
    }


def two_cubes(divisions: int, case: str = "dissimilar", *, threads: int | None = None,
              method: str = "auto", eps: float = 1e-7) -> dict:
    """The paper's two cubes with K = ``divisions`` elements per lower-cube edge;
    ``method`` (auto, dense, hmatrix) and ``eps`` as for :func:`one_body`."""
    from ._native import core as _core_module
    _core = _core_module()
    from .bem import Displacement as Disp
    from .errors import ConfigError
    from .contact import ContactPair, ContactProblem, SolverOptions

    if case not in ("similar", "dissimilar"):
        raise ConfigError(f"two-cubes --case must be 'similar' or 'dissimilar', got {case!r}")
    n = int(divisions)
    if n < 2:
        raise ConfigError(f"two-cubes --divisions must be >= 2 (the upper cube has K - 1), got {n}")
    t0 = time.perf_counter()
    lower = ElasticBody(
        box((0, 0, 0), (2, 2, 2), n), LinearElastic(1.0e4, 0.3), {"zmin": Disp((0.0, 0.0, 0.0))},
        name="lower",
    )
    upper = ElasticBody(
        box((0, 0, 2), (2, 2, 4), n - 1),
        LinearElastic(1.0e8 if case == "dissimilar" else 1.0e4, 0.3),
        {"zmax": Disp((0.0, 0.0, -0.04))},
        name="upper",
    )
    problem = ContactProblem(lower, upper, ContactPair("zmax", "zmin", 0.1))
    base = SolverOptions().linear  # the condensation's defaults (leaf size)
    linear = dataclasses.replace(
        base, method=method, hmatrix=dataclasses.replace(base.hmatrix, eps=eps)
    )
    res = problem.solve(SolverOptions(threads=threads, linear=linear))
    total = time.perf_counter() - t0
    lin = list(res.linear.values())
    hm = any(v.get("method") == "hmatrix" for v in lin)
    t = res.timings
    nodes = sum(len(b.points) for b in res.bodies)
    big = max(len(b.points) for b in res.bodies)
    return {
        "case": f"two-cubes-{case}",
        "method": "hmatrix" if hm else "dense",
        "divisions": n,
        "nodes": int(nodes),
        "unknowns": int(3 * nodes),
        "frame_nodes": int(len(res.frame.points)),
        "assembly_s": t["assembly"],
        # dense: the LU is inside condensation_s; H-matrix: the H-LUs' seconds
        "factor_s": sum(v.get("factor_s", 0.0) for v in lin) if hm else None,
        "condensation_s": t["condensation"],
        "frame_s": t["frame"],
        "solve_s": None,
        "newton_s": t["newton"],
        "newton_iterations": int(res.newton_iterations),
        "newton_fraction": t["newton"] / total,
        "total_s": total,
        "peak_rss_mb": peak_rss_mb(),
        "compressed_mb": sum(v.get("compressed_mb", 0.0) for v in lin) if hm else None,
        "dense_mb": 8.0 * (3 * big) ** 2 / 1e6,
        "eps": eps if hm else None,
        "exact_residual": max(v.get("exact_residual", 0.0) for v in lin) if hm else None,
        "error": None,
        "normal_force": float(res.normal_force),
        "threads": threads if threads is not None else _core.max_threads(),
        "version": __version__,
    }


def hlu_factor(nodes: int, *, eps: float = 1e-7, rhs: int = 300,
               threads: int | None = None, leaf_size: int = 96) -> dict:
    """Build the linear-field cube's compressed A, factor it by H-LU and
    solve ``rhs`` random right-hand sides (one refinement step): seconds,
    memory and residuals (benchmarks/hlu_factor.py)."""
    from ._native import core as _core_module
    _core = _core_module()
    from .bem.compressed import CompressedSystem

    body, _, _ = linear_field_cube(nodes)
    d = body.discretization
    ku = body.boundary_data(body.boundary_conditions)[0]
    m = body.material
    th = threads if threads is not None else _core.max_threads()
    t0 = time.perf_counter()
    cs = CompressedSystem(d, m.shear_modulus, m.poisson_ratio, ku, None, body.quadrature,
                          HMatrixOptions(eps=eps, leaf_size=leaf_size), th)
    t1 = time.perf_counter()
    f = cs.factor()
    t2 = time.perf_counter()
    b = np.random.default_rng(0).standard_normal((cs.n, rhs))
    x = f.solve(b)
    r = b - cs.matvec(x)
    first = float(np.linalg.norm(r) / np.linalg.norm(b))
    x += f.solve(r)
    t3 = time.perf_counter()
    second = float(np.linalg.norm(b - cs.matvec(x)) / np.linalg.norm(b))
    return {
        "case": "hlu", "nodes": int(d.n_points), "unknowns": int(cs.n), "eps": eps,
        "leaf_size": leaf_size,
        "build_s": t1 - t0, "factor_s": t2 - t1, "solve_s": t3 - t2, "rhs": rhs,
        "compressed_mb": cs.stored_bytes / 1e6, "factor_mb": f.stored_bytes / 1e6,
        "dense_mb": cs.dense_bytes / 1e6, "max_rank": f.max_rank,
        "residual": first, "refined_residual": second, "peak_rss_mb": peak_rss_mb(),
        "threads": th, "version": __version__,
    }


__all__ = ["one_body", "two_cubes", "hlu_factor", "linear_field_cube", "cube_divisions",
           "peak_rss_mb"]

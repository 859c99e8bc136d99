"""The sparse solver of a finite-element body's condensation, chosen by
measurement (docs/decisions.md, "Finite-element bodies"): a box of Q1
hexahedra clamped at its base, its stiffness factored and solved for a unit
force at each dof of its top face (the contact nodes), the contact rows kept
(the flexibility), in blocks of 256 right-hand sides as bemcontact.fem does.
``schur`` is bemcontact's (bemcontact.fem.condensation.SchurFactor: CHOLMOD
through cvxopt in a METIS nested-dissection ordering with the contact dofs
last, the flexibility the inverse of the factor's trailing block, no solve
per contact dof); cholespy (CHOLMOD), pypardiso (MKL PARDISO) and SciPy's
SuperLU solve for each contact dof.  Each solver installed runs in its own
process (its peak RSS is its own); the flexibility's first entry shows they
agree.

    python benchmarks/fem_sparse_solvers.py [NX NZ ...]   (default 20 20  32 60)

NX x NX x NZ cells on a 2 x 2 x 2 box: 20 20 is 27,783 dofs and 441 contact
nodes; 32 60 is 199,287 dofs and 1,089 contact nodes (the issue's figure)."""

from __future__ import annotations

import json
import resource
import subprocess
import sys
import time

import numpy as np
import scipy.sparse as sp

from _common import machine_line

SOLVERS = ("schur", "cholespy", "pypardiso", "splu")
MODULES = {"splu": "scipy", "schur": "cvxopt"}
CHUNK = 256


def stiffness(nx: int, nz: int):
    import skfem

    m = skfem.MeshHex.init_tensor(np.linspace(0, 2, nx + 1), np.linspace(0, 2, nx + 1),
                                  np.linspace(0, 2, nz + 1))
    b = skfem.Basis(m, skfem.ElementHex1())
    G = [[skfem.asm(skfem.BilinearForm(lambda u, v, w, k=k, l_=l_: v.grad[k] * u.grad[l_]), b)
          for l_ in range(3)] for k in range(3)]
    E, nu = 1.0, 0.3
    lam, mu = E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))
    lap = G[0][0] + G[1][1] + G[2][2]
    K = sum(sp.kron(lam * G[i][j] + mu * G[j][i] + (mu * lap if i == j else 0),
                    sp.csr_array(([1.0], ([i], [j])), shape=(3, 3)), format="csr")
            for i in range(3) for j in range(3)).tocsr()
    bot = np.flatnonzero(m.p[2] < 1e-9)
    top = np.flatnonzero(m.p[2] > 2 - 1e-9)
    held = (3 * bot[:, None] + np.arange(3)).ravel()
    contact = (3 * top[:, None] + np.arange(3)).ravel()
    free = np.setdiff1d(np.arange(K.shape[0]), held)
    return K[free][:, free].tocsc(), np.searchsorted(free, contact), K.shape[0], top.size, free


def factor(name: str, K):
    if name == "cholespy":
        import cholespy

        C = K.tocoo()
        s = cholespy.CholeskySolverD(K.shape[0], C.row.astype(np.int32), C.col.astype(np.int32),
                                     C.data, cholespy.MatrixType.COO)

        def solve(B):
            X = np.zeros_like(B)
            s.solve(np.ascontiguousarray(B), X)
            return X
        return solve
    if name == "pypardiso":
        import pypardiso

        ps = pypardiso.PyPardisoSolver()
        ps.set_matrix_type(2)  # real SPD
        Ku = sp.triu(K, format="csr")
        ps.factorize(Ku)
        return lambda B: ps.solve(Ku, B)
    import scipy.sparse.linalg as spla

    return spla.splu(K).solve


def one(name: str, nx: int, nz: int) -> dict:
    t0 = time.perf_counter()
    c0 = time.process_time()
    entries = None
    K, pos, dofs, nodes, free = stiffness(nx, nz)
    t1 = time.perf_counter()
    if name == "schur":
        from bemcontact.fem.condensation import SchurFactor

        f = SchurFactor(K, pos, groups=free // 3)
        t2 = time.perf_counter()
        S = f.contact_inverse()  # "solves": reading the factor's trailing block
        entries = f.entries
    else:
        solve = factor(name, K)
        t2 = time.perf_counter()
        S = np.empty((pos.size, pos.size))
    for c in range(0, pos.size if name != "schur" else 0, CHUNK):
        B = np.zeros((K.shape[0], min(CHUNK, pos.size - c)))
        B[pos[c : c + CHUNK], np.arange(B.shape[1])] = 1.0
        S[:, c : c + CHUNK] = solve(B)[pos]
    t3 = time.perf_counter()
    return {"solver": name, "dofs": dofs, "contact_nodes": nodes, "assembly_s": t1 - t0,
            "factor_s": t2 - t1, "solves_s": t3 - t2, "wall_s": t3 - t0,
            "cpu_s": time.process_time() - c0,
            "peak_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
            "F00": float(S[0, 0]), "factor_entries": entries}


def main() -> None:
    if sys.argv[1:2] == ["--one"]:
        print(json.dumps(one(sys.argv[2], int(sys.argv[3]), int(sys.argv[4]))))
        return
    sizes = [int(a) for a in sys.argv[1:]] or [20, 20, 32, 60]
    print(machine_line())
    print("| dofs | contact nodes | solver | assembly s | factor s | solves s | wall s | peak RSS MB | F[0,0] |")
    print("|---|---|---|---|---|---|---|---|---|")
    for nx, nz in zip(sizes[::2], sizes[1::2]):
        for name in SOLVERS:
            mod = MODULES.get(name, name)
            try:
                __import__(mod)
            except ImportError:
                continue
            if name == "splu" and nx * nx * nz > 20000:
                continue  # hours at the large size
            out = subprocess.run([sys.executable, __file__, "--one", name, str(nx), str(nz)],
                                 capture_output=True, text=True, check=True).stdout
            r = json.loads(out.strip().splitlines()[-1])
            print(f"| {r['dofs']:,} | {r['contact_nodes']:,} | {name} | {r['assembly_s']:.1f} | "
                  f"{r['factor_s']:.1f} | {r['solves_s']:.1f} | {r['wall_s']:.1f} | "
                  f"{r['peak_rss_mb']:.0f} | {r['F00']:.6e} |", flush=True)


if __name__ == "__main__":
    main()

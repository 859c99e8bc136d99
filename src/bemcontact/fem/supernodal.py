"""The trailing block of a CHOLMOD supernodal Cholesky factor, read in
place.

cvxopt hands out a factor as a capsule around CHOLMOD's ``cholmod_factor``;
its only reader (``cholmod.getfactor``) converts the whole factor to a
sparse matrix, moving its values out, so the matrix would have to be
factored again and the factor be held twice.  A supernodal factor keeps
each supernode's columns as one dense column-major block: supernode ``s``
owns columns ``super[s] .. super[s+1]-1``, its row indices are
``s[pi[s] .. pi[s+1]-1]`` and its values start at ``x[px[s]]``, with the
row count as the leading dimension.  The columns of the trailing ``k``
dofs (ordered last) then have rows among the last ``k`` only, and are read
straight from those blocks.

The structure's layout is CHOLMOD's public one (``cholmod.h``, unchanged
from CHOLMOD 2 to 5); :func:`trailing_block` checks every field it can
against what the caller knows (size, kind, index and value types, the
permutation, the supernodes' bounds) and returns ``None`` when anything
differs, so that a factor of another layout is read the slow way, never
wrongly."""

from __future__ import annotations

import ctypes

import numpy as np

_SIZE, _PTR, _INT = ctypes.c_size_t, ctypes.c_void_p, ctypes.c_int


class _Factor(ctypes.Structure):
    """``cholmod_factor``, field for field."""

    _fields_ = ([("n", _SIZE), ("minor", _SIZE), ("Perm", _PTR), ("ColCount", _PTR),
                 ("IPerm", _PTR), ("nzmax", _SIZE)]
                + [(f, _PTR) for f in ("p", "i", "x", "z", "nz", "next", "prev")]
                + [(f, _SIZE) for f in ("nsuper", "ssize", "xsize", "maxcsize", "maxesize")]
                + [(f, _PTR) for f in ("super", "pi", "px", "s")]
                + [(f, _INT) for f in ("ordering", "is_ll", "is_super", "is_monotonic",
                                       "itype", "xtype", "dtype", "useGPU")])


_CAPSULE = b"CHOLMOD FACTOR D L"  # cvxopt's name for the factor of a real matrix
_LONG, _REAL, _DOUBLE = 2, 1, 0  # CHOLMOD's itype, xtype, dtype codes


def _factor(capsule) -> _Factor | None:
    api = ctypes.pythonapi
    api.PyCapsule_GetName.restype = ctypes.c_char_p
    api.PyCapsule_GetName.argtypes = [ctypes.py_object]
    api.PyCapsule_GetPointer.restype = ctypes.c_void_p
    api.PyCapsule_GetPointer.argtypes = [ctypes.py_object, ctypes.c_char_p]
    try:
        if api.PyCapsule_GetName(capsule) != _CAPSULE:
            return None
        return _Factor.from_address(api.PyCapsule_GetPointer(capsule, _CAPSULE))
    except (TypeError, ValueError):
        return None


def factor_entries(capsule) -> int | None:
    """The number of values a supernodal factor holds (CHOLMOD's ``xsize``),
    or None for a capsule that is not a real supernodal factor."""
    f = _factor(capsule)
    if f is None or not f.is_super:
        return None
    return int(f.xsize)


def _array(address: int, size: int, ctype) -> np.ndarray:
    return np.ctypeslib.as_array(ctypes.cast(address, ctypes.POINTER(ctype)), shape=(size,))


def trailing_block(capsule, perm: np.ndarray, k: int) -> np.ndarray | None:
    """The last ``k`` rows and columns (k, k) of the lower factor ``L`` of
    ``P A Pᵀ = L Lᵀ`` (its lower triangle; Fortran order, zeros above), read
    from cvxopt's supernodal factor ``capsule`` whose permutation must be
    ``perm``; ``None`` when the factor is not a numeric supernodal LLᵀ
    factor of that permutation in the layout expected."""
    L = _factor(capsule)
    n = perm.size
    if (L is None or L.n != n or not (L.is_super and L.is_ll) or L.itype != _LONG
            or L.xtype != _REAL or L.dtype != _DOUBLE or L.minor != n or not L.x
            or not 0 < k <= n):
        return None
    ns = int(L.nsuper)
    Perm = _array(L.Perm, n, ctypes.c_int64)
    sup = _array(L.super, ns + 1, ctypes.c_int64)
    pi = _array(L.pi, ns + 1, ctypes.c_int64)
    px = _array(L.px, ns + 1, ctypes.c_int64)
    if (not np.array_equal(Perm, perm) or sup[0] != 0 or sup[ns] != n or pi[ns] != L.ssize
            or px[ns] > L.xsize or np.any(np.diff(sup) <= 0)):
        return None
    s = _array(L.s, int(L.ssize), ctypes.c_int64)
    x = _array(L.x, int(L.xsize), ctypes.c_double)
    off = n - k
    out = np.zeros((k, k), order="F")
    for j in range(int(np.searchsorted(sup, off, side="right")) - 1, ns):
        c0, c1 = int(sup[j]), int(sup[j + 1])
        rows = s[pi[j]:pi[j + 1]]
        nr = rows.size
        if nr < c1 - c0 or np.any(rows[: c1 - c0] != np.arange(c0, c1)):
            return None  # a supernode's rows start with its own columns
        first = max(c0, off)
        block = x[px[j] + (first - c0) * nr: px[j] + (c1 - c0) * nr].reshape(c1 - first, nr).T
        below = rows >= off
        if not np.all(below[first - c0:]):
            return None  # the trailing columns' rows are trailing too
        out[rows[below] - off, first - off: c1 - off] = block[below]
    for j0 in range(0, k, 512):  # a diagonal block's upper triangle is not the factor's
        j1 = min(j0 + 512, k)
        out[:j0, j0:j1] = 0.0
        out[j0:j1, j0:j1] = np.tril(out[j0:j1, j0:j1])
    return out


__all__ = ["trailing_block"]

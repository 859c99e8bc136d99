"""An on-disk cache of condensed bodies: a body condensed once is
read back by any later process instead of assembled and factored again.

An entry is one file ``<key>.condensed``: a header line
``bemcontact-condensed <FORMAT_VERSION> <key> <sha256>\\n`` followed by a NumPy
``.npz`` archive (no pickles) of the
:class:`~bemcontact.bem.condensation.CondensedBody` arrays and its
metadata.  The key is the SHA-256 of everything the condensation depends on
(:func:`body_key`): the cache format version and the package version, the
body's model key (``model_key()``: its mesh, material, quadrature and node
layout), the kinds of its boundary conditions (known displacement
per dof, force-controlled dofs), the load fields condensed on, the contact
nodes and the frame's traction modes (the coupling B; the interface mass M
is the contact surface's own), the pair's frame settings, and the linear solver options.  The
checksum covers the archive: an entry that is truncated, altered, of another
version or filed under another key is detected, never used, and rebuilt
(written whole to a temporary file and renamed into place, so a reader
never sees half an entry).
"""

from __future__ import annotations

import hashlib
import io
import json
import os
import pathlib
import secrets
import zipfile

import numpy as np

from .._version import __version__
from ..bem.body import ElasticBody
from ..bem.condensation import CondensedBody, condense

#: Version of the entry format and of what the key covers; bumped when either changes.
FORMAT_VERSION = 1
_MAGIC = b"bemcontact-condensed"
_ARRAYS = ("nodes", "dofs", "known_u", "values", "x0", "X", "Rf", "known_modal_force", "Y",
           "C", "forces")


def _update(h, *parts) -> None:
    for p in parts:
        if isinstance(p, np.ndarray):
            a = np.ascontiguousarray(p)
            h.update(f"{a.dtype.str}{a.shape}".encode())
            h.update(a.tobytes())
        else:
            h.update(repr(p).encode())
        h.update(b"|")


def body_key(body, nodes, states, linear, modes, load_fields, frame_settings=()) -> str:
    """The content hash (hex SHA-256) of a condensation's inputs (module docstring)."""
    h = hashlib.sha256()
    known_u = body.condition_kinds(states[0]) > 0
    controls = [c.dofs for c in body.controls(states[0])]
    _update(h, FORMAT_VERSION, __version__, body.model_key(), known_u, len(controls), *controls,
            np.asarray(load_fields), np.asarray(nodes), linear, tuple(frame_settings))
    if modes is not None:
        B = modes.B.tocsr()
        # the mass M of the modes is the contact surface's own (its elements
        # and nodes are hashed above: mesh, nodes)
        _update(h, modes.n, modes.m, B.indptr, B.indices, B.data)
    return h.hexdigest()


class BodyCache:
    """Condensed bodies on disk in ``directory``; :meth:`condense` stands in
    for :func:`~bemcontact.contact.condense` (the ``condense_body`` of
    :meth:`~bemcontact.contact.ContactProblem.condense`).

    ``frame_settings``: the contact pair's frame settings, part of every key.
    Counters: ``hits`` (entries used), ``misses`` (no entry: condensed and
    written), ``rejected`` (a damaged or foreign entry found, rebuilt)."""

    def __init__(self, directory: str | os.PathLike, frame_settings=()) -> None:
        self.directory = pathlib.Path(directory)
        self.frame_settings = tuple(frame_settings)
        self.hits = self.misses = self.rejected = 0

    def path(self, key: str) -> pathlib.Path:
        return self.directory / f"{key}.condensed"

    def condense(self, body, nodes, threads=None, states=None, progress=None, linear=None,
                 modes=None, *, load_fields=None) -> CondensedBody:
        if not isinstance(body, ElasticBody):  # its own condensation, not stored
            return body.condense(nodes, threads, states, progress, linear, modes,
                                 load_fields=load_fields)
        states = [body.boundary_conditions] if states is None else list(states)
        if load_fields is None:
            load_fields = np.column_stack([body.boundary_data(s)[1] for s in states])
        key = body_key(body, nodes, states, linear, modes, load_fields, self.frame_settings)
        path = self.path(key)
        if path.exists():
            cb = self._read(path, key, body, states, modes)
            if cb is not None:
                self.hits += 1
                return cb
            self.rejected += 1
        else:
            self.misses += 1
        cb = condense(body, nodes, threads, states, progress, linear, modes,
                      load_fields=load_fields)
        self._write(path, key, cb)
        return cb

    # ---------------------------------------------------------------- entries
    def _write(self, path: pathlib.Path, key: str, cb: CondensedBody) -> None:
        buf = io.BytesIO()
        meta = json.dumps({"version": FORMAT_VERSION, "key": key, "body": cb.body.name,
                           "solver": cb.solver, "timings": cb.timings}, default=str)
        np.savez(buf, meta=np.frombuffer(meta.encode(), dtype=np.uint8),
                 **{a: np.asarray(getattr(cb, a)) for a in _ARRAYS})
        data = buf.getvalue()
        header = b"%s %d %s %s\n" % (_MAGIC, FORMAT_VERSION, key.encode(),
                                     hashlib.sha256(data).hexdigest().encode())
        self.directory.mkdir(parents=True, exist_ok=True)
        tmp = path.with_name(f".{path.name}.{secrets.token_hex(4)}.tmp")
        try:
            with open(tmp, "wb") as f:
                f.write(header + data)
            os.replace(tmp, path)
        finally:
            tmp.unlink(missing_ok=True)

    def _read(self, path: pathlib.Path, key: str, body, states, modes) -> CondensedBody | None:
        """The entry, or None when it is damaged, foreign or does not fit."""
        try:
            raw = path.read_bytes()
            header, _, data = raw.partition(b"\n")
            magic, version, k, digest = header.split(b" ")
            if (magic != _MAGIC or int(version) != FORMAT_VERSION or k.decode() != key
                    or hashlib.sha256(data).hexdigest().encode() != digest):
                return None
            with np.load(io.BytesIO(data), allow_pickle=False) as z:
                arr = {a: z[a] for a in _ARRAYS}
                meta = json.loads(bytes(z["meta"]).decode())
        except (OSError, ValueError, KeyError, zipfile.BadZipFile, UnicodeDecodeError):
            return None
        n = 3 * body.discretization.n_points
        if (meta.get("key") != key or arr["x0"].shape[0] != n
                or (modes is not None and arr["X"].shape != (n, modes.size))):
            return None
        controls = body.controls(states[0])
        cb = CondensedBody(
            body, arr["nodes"], arr["dofs"], arr["known_u"], arr["values"], arr["x0"], arr["X"],
            arr["Rf"], arr["known_modal_force"], controls, arr["Y"], arr["C"], arr["forces"],
            {"assembly": 0.0, "condensation": 0.0}, dict(meta.get("solver", {})), modes,
        )
        return cb


__all__ = ["BodyCache", "FORMAT_VERSION", "body_key"]

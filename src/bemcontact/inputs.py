"""Reading the user's input files safely: regular files only (a FIFO blocks
forever and a device never ends) and sizes checked before anything is read."""

from __future__ import annotations

import os
import stat

from .errors import ConfigError

#: Largest problem file read (TOML problem files are a few kB; meshes are separate files).
MAX_PROBLEM_BYTES = 10_000_000
#: Largest mesh file read (a 10-million-element gmsh file is about 1 GB).
MAX_MESH_BYTES = 2_000_000_000


def check_regular_file(path: str | os.PathLike, what: str, max_bytes: int) -> None:
    """Raise a one-line :class:`ConfigError` naming ``path`` unless it is a
    regular file of at most ``max_bytes`` (``what``: "problem file", ...)."""
    p = os.fspath(path)
    try:
        st = os.stat(p)
    except FileNotFoundError:
        raise ConfigError(f"{p}: cannot read the {what}: no such file") from None
    except OSError as exc:
        raise ConfigError(f"{p}: cannot read the {what}: {exc.strerror or exc}") from None
    if stat.S_ISDIR(st.st_mode):
        raise ConfigError(f"{p}: is a directory, not a {what}")
    if not stat.S_ISREG(st.st_mode):
        raise ConfigError(f"{p}: is not a regular file (a FIFO, socket or device); a {what} "
                          "must be a file")
    if st.st_size > max_bytes:
        raise ConfigError(f"{p}: {st.st_size / 1e6:,.0f} MB is too large for a {what} (at most "
                          f"{max_bytes / 1e6:,.0f} MB)")


__all__ = ["check_regular_file", "MAX_PROBLEM_BYTES", "MAX_MESH_BYTES"]

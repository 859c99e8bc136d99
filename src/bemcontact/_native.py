"""The one loader of the compiled core (``bemcontact._core``, built from
cpp/ by scikit-build-core and nanobind).  Imported lazily, so that the pure
Python parts (the problem-file schema, the docs build) work without it."""

from __future__ import annotations

import importlib
from typing import Any


def core():
    """The compiled extension module."""
    return importlib.import_module(f"{__package__}._core")


def build_info() -> dict[str, Any]:
    """How the compiled core was built: ``native`` (True: tuned with
    ``-march=native`` for the build machine, which another CPU may not run;
    False: the compiler's baseline target, as in wheels), ``compiler``,
    ``flags`` (the sources' compile flags), ``build_type``, ``processor`` and
    ``openmp`` (the ``_OPENMP`` date, None without OpenMP)."""
    return dict(core().build_info())

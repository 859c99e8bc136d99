"""The one loader of the compiled core (``bemcontact._core``, built from
cpp/ by scikit-build-core and nanobind).  Imported lazily, so that the pure
Python parts (the problem-file schema, the docs build) work without it."""

from __future__ import annotations

import importlib


def core():
    """The compiled extension module."""
    return importlib.import_module(f"{__package__}._core")

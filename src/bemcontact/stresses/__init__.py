"""Stresses where bodies fail: what is asked for (:mod:`.probes`: a line, a
plane or a box of points in a body), the fields and their measures and maxima
on a solved result (:mod:`.fields`), and the probes written without being
asked for, under the peak pressure (:mod:`.sections`).

The stresses themselves come from the result: Somigliana's identity on the
full path (:func:`bemcontact.bem.interior.interior_stresses`), Love's
half-space field of the grid tractions on the multiscale path
(:mod:`bemcontact.multiscale.stress`)."""

from .fields import (COLUMNS, MEASURES, Lattice, StressField, evaluate, evaluate_all, maxima,
                     measures, surface_maxima)
from .probes import MAX_POINTS, PROBE_KEYS, Box, Line, Plane, StressRequest
from .sections import default_requests

__all__ = ["Box", "COLUMNS", "Lattice", "Line", "MAX_POINTS", "MEASURES", "PROBE_KEYS", "Plane",
           "StressField", "StressRequest", "default_requests", "evaluate", "evaluate_all", "maxima",
           "measures", "surface_maxima"]

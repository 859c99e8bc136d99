"""The elastic half-space: the Boussinesq–Cerruti influence of
piecewise-constant tractions on a regular grid of rectangular cells in the
plane z = 0 (Love's rectangle integrals), one body or the relative
displacement of two, applied by FFT; and the subsurface stresses of those
tractions, by FFT per depth layer or at points.  Signs and formulas:
:mod:`bemcontact.halfspace.influence`, :mod:`bemcontact.halfspace.stress` and
docs/theory.md."""

from .grid import Grid, HalfSpaceOperator
from .influence import Compliance, influence_blocks, rectangle_integrals
from .measure import COMPONENTS, principal_stresses, stress_tensors, tresca, von_mises
from .stress import HalfSpaceStress, rectangle_stresses, stress_blocks

__all__ = ["COMPONENTS", "Compliance", "Grid", "HalfSpaceOperator", "HalfSpaceStress",
           "influence_blocks", "principal_stresses", "rectangle_integrals", "rectangle_stresses",
           "stress_blocks", "stress_tensors", "tresca", "von_mises"]

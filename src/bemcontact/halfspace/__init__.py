"""The elastic half-space: the Boussinesq–Cerruti influence of
piecewise-constant tractions on a regular grid of rectangular cells in the
plane z = 0 (Love's rectangle integrals), one body or the relative
displacement of two, applied by FFT.  Signs and formulas:
:mod:`bemcontact.halfspace.influence` and docs/theory.md."""

from .grid import Grid, HalfSpaceOperator
from .influence import Compliance, influence_blocks, rectangle_integrals

__all__ = ["Compliance", "Grid", "HalfSpaceOperator", "influence_blocks", "rectangle_integrals"]

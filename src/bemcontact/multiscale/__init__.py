"""Contact of bodies at the scale of their geometry with a contact zone at
the scale of the contact: each pair's flexibility on a regular grid of its
contact plane is the half-space operator of the pair (FFT) plus each body's
smooth correction for its finite geometry, and the interface system on the
grid is solved matrix-free (Newton–Krylov)."""

from .interface import GridInterface, GridRecord
from .operator import PairOperator
from .rolling import GridRolling

__all__ = ["GridInterface", "GridRecord", "GridRolling", "PairOperator"]

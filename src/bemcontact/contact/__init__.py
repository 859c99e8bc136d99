"""Contact between bodies (two, or an assembly of several pairs): the Coulomb law, the geometric search, the
contact frame, the pair, the condensation, the interface system and its
Newton solve, the problem with its load steps, and the results."""

from ..bem.condensation import CondensedBody, condense
from .flexibility import Flexibility
from .frame import ContactFrame
from .frames import FrameSet
from .options import SolverOptions
from .pair import ContactPair
from .history import LoadStep
from .rolling import Rolling
from .problem import ContactProblem
from .results import ContactResult, FrameResult, InterfaceResult, PairResult, StepRecord

__all__ = [
    "ContactPair", "ContactProblem", "LoadStep", "Rolling", "SolverOptions", "ContactFrame", "condense",
    "CondensedBody", "ContactResult", "FrameResult", "FrameSet", "InterfaceResult", "PairResult",
    "StepRecord", "Flexibility",
]

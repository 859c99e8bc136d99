"""One elastic body by the boundary element method: material, boundary
conditions, the collocation layout (discretization), the influence operators
(dense, or compressed as H-matrices) and the body with its mixed boundary value problem."""

from .body import BodySolution, ElasticBody
from .compressed import CompressedSystem, HFactor
from .conditions import Displacement, Fixed, Force, Pressure, Traction
from .discretization import Discretization, DiscretizationOptions, discretize
from .material import LinearElastic
from .operators import QuadratureOptions, assemble_influence, assemble_system, element_influence

__all__ = [
    "ElasticBody", "BodySolution", "Displacement", "Traction", "Pressure", "Force", "Fixed",
    "LinearElastic", "Discretization", "DiscretizationOptions", "discretize",
    "QuadratureOptions", "CompressedSystem", "HFactor", "assemble_influence", "assemble_system", "element_influence",
]

"""bemcontact: 3D frictional contact between linear elastic bodies with the
Boundary Element Method.

Conventions (units, signs, array shapes) are in docs/theory.md.
"""

from __future__ import annotations

from .body import BodySolution, Displacement, ElasticBody, Fixed, Force, Pressure, Traction
from .frame import ContactFrame
from .errors import (
    AccuracyWarning,
    BemcontactError,
    ConfigError,
    ConvergenceError,
    MaterialError,
    MeshError,
)
from .hmatrix import HMatrixOptions, LinearSolverOptions
from .material import LinearElastic
from .mesh import SurfaceMesh, box, read_mesh
from .problem import Problem, load_problem
from .results import ContactResult, FrameResult, InterfaceResult, StepRecord
from .solver import ContactPair, ContactProblem, LoadStep, SolverOptions, condense
from .operators import (
    Discretization,
    DiscretizationOptions,
    QuadratureOptions,
    assemble_influence,
    discretize,
)

__version__ = "0.1.0"

__all__ = [
    "__version__",
    "AccuracyWarning",
    "BemcontactError",
    "ConfigError",
    "ConvergenceError",
    "MaterialError",
    "MeshError",
    "LinearElastic",
    "SurfaceMesh",
    "box",
    "read_mesh",
    "QuadratureOptions",
    "DiscretizationOptions",
    "Discretization",
    "discretize",
    "assemble_influence",
    "ElasticBody",
    "BodySolution",
    "Displacement",
    "Traction",
    "Pressure",
    "Fixed",
    "Force",
    "ContactFrame",
    "ContactPair",
    "ContactProblem",
    "LoadStep",
    "SolverOptions",
    "condense",
    "ContactResult",
    "FrameResult",
    "InterfaceResult",
    "StepRecord",
    "HMatrixOptions",
    "LinearSolverOptions",
    "Problem",
    "load_problem",
]

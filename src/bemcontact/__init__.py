"""bemcontact: 3D frictional contact between linear elastic bodies with the
Boundary Element Method.

Conventions (units, signs, array shapes) are in docs/theory.md.
"""

from __future__ import annotations

from ._version import __version__
from .bem import (
    BodySolution,
    Discretization,
    DiscretizationOptions,
    Displacement,
    ElasticBody,
    Fixed,
    Force,
    LinearElastic,
    Pressure,
    QuadratureOptions,
    Traction,
    assemble_influence,
    discretize,
)
from .contact import (
    ContactFrame,
    ContactPair,
    ContactProblem,
    ContactResult,
    FrameResult,
    InterfaceResult,
    LoadStep,
    PairResult,
    Rolling,
    SolverOptions,
    StepRecord,
    condense,
)
from .errors import (
    AccuracyWarning,
    BemcontactError,
    BemcontactWarning,
    ConfigError,
    ConvergenceError,
    MaterialError,
    MeshError,
    OptionalDependencyWarning,
    ResourceLimitWarning,
)
from .linalg import HMatrixOptions, LinearSolverOptions
from .mesh import SurfaceMesh, box, read_mesh
from .problemfile import Problem, ProblemFile, load_problem

__all__ = [
    "__version__",
    "AccuracyWarning",
    "BemcontactError",
    "BemcontactWarning",
    "OptionalDependencyWarning",
    "ResourceLimitWarning",
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
    "Rolling",
    "ContactPair",
    "ContactProblem",
    "LoadStep",
    "SolverOptions",
    "condense",
    "ContactResult",
    "FrameResult",
    "PairResult",
    "InterfaceResult",
    "StepRecord",
    "HMatrixOptions",
    "LinearSolverOptions",
    "ProblemFile",
    "Problem",
    "load_problem",
]

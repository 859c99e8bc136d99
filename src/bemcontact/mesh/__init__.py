"""Surface meshes: element types and their basis, the mesh with its named
regions and checks, structured boxes, gmsh-generated shapes, file readers."""

from .element import (
    CENTROIDS, CORNERS, ELEMENT_TYPES, MAX_NODES, NODES_PER_ELEMENT, REFERENCE_NODES,
)
from .read import read_mesh
from .structured import box
from .surface import MAX_COORDINATE, MAX_ELEMENTS, SurfaceMesh, SurfaceQuadrature

__all__ = [
    "SurfaceMesh", "SurfaceQuadrature", "box", "read_mesh", "ELEMENT_TYPES", "NODES_PER_ELEMENT",
    "CORNERS", "MAX_NODES", "REFERENCE_NODES", "CENTROIDS", "MAX_COORDINATE", "MAX_ELEMENTS",
]

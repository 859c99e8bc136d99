"""Writes examples/meshes/block.msh with gmsh: the box [0, 2] x [0, 2] x
[0, 1] meshed with linear triangles of size 0.25, its faces in three named
physical surface groups (``bottom``, ``top``, ``sides``), which bemcontact
reads as regions.  Run it to regenerate the file (gmsh's mesher is
deterministic for a given version; the committed file is the reference)."""

from __future__ import annotations

import pathlib
import sys

import gmsh


def main(path: pathlib.Path) -> None:
    gmsh.initialize(["-noenv"])
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("block")
        box = gmsh.model.occ.addBox(0, 0, 0, 2, 2, 1)
        gmsh.model.occ.synchronize()
        faces = [t for _, t in gmsh.model.getBoundary([(3, box)], oriented=False)]
        groups = {"bottom": [], "top": [], "sides": []}
        for t in faces:
            z = gmsh.model.occ.getCenterOfMass(2, t)[2]
            groups["bottom" if z < 1e-9 else "top" if z > 1 - 1e-9 else "sides"].append(t)
        for name, tags in groups.items():
            gmsh.model.addPhysicalGroup(2, tags, name=name)
        gmsh.option.setNumber("Mesh.MeshSizeMax", 0.25)
        gmsh.option.setNumber("Mesh.MeshSizeMin", 0.25)
        gmsh.model.mesh.generate(2)
        gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
        gmsh.write(str(path))
    finally:
        gmsh.finalize()


if __name__ == "__main__":
    main(pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else pathlib.Path(__file__).with_name("block.msh"))

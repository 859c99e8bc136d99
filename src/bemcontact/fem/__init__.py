"""Finite-element bodies: a volume mesh (:mod:`.mesh`), its trace on the
boundary (:mod:`.trace`), the body (:mod:`.body`) and its condensation on
the contact nodes (:mod:`.condensation`), behind the same body seam as a
BEM body (:class:`~bemcontact.contact.flexibility.Body`)."""

from .body import FiniteElementBody
from .loads import BodyForce
from .material import AnisotropicElastic
from .mesh import VolumeMesh, box_volume, read_volume_mesh

__all__ = ["AnisotropicElastic", "BodyForce", "FiniteElementBody", "VolumeMesh", "box_volume",
           "read_volume_mesh"]

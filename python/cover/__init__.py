"""Cover: CSG solids without boundary evaluation (simplicial coverings).

numpy in, numpy out. Build a Model with load(), box(), sphere(), cylinder() or mesh(), combine
Models with | (union), & (intersection), - (difference) and ~ (complement) or union_all() and
intersection_all(), move them with translate(), scale(), rotate(), mirror() and transform(),
and query it:
classify(), winding(), volume(), bounds(), voxelize(), cast(), render(), evaluate(), clip(),
info(). subdivide() refines a polygon mesh given as arrays; modify() applies modeling operations
(pipes, extrusions, ...) to one; write_mesh() writes one in any format the CLI writes. See
docs/python.md.
"""

from ._cover import (
    CLASS_NAMES,
    Hits,
    InputError,
    Model,
    NotComputable,
    PreconditionError,
    __version__,
    box,
    cylinder,
    ffd,
    intersection_all,
    load,
    mesh,
    points,
    sphere,
    HalfedgeMesh,
    modify,
    subdivide,
    union_all,
    write_mesh,
)

__all__ = [
    "CLASS_NAMES",
    "Hits",
    "InputError",
    "Model",
    "NotComputable",
    "PreconditionError",
    "__version__",
    "box",
    "cylinder",
    "ffd",
    "intersection_all",
    "load",
    "mesh",
    "points",
    "sphere",
    "HalfedgeMesh",
    "modify",
    "subdivide",
    "union_all",
    "write_mesh",
]

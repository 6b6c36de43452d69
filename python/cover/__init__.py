"""Cover: CSG solids without boundary evaluation (simplicial coverings).

numpy in, numpy out. Build a Model with load(), box(), sphere(), cylinder() or mesh(), combine
Models with | (union), & (intersection), - (difference) and ~ (complement), and query it:
classify(), winding(), volume(), bounds(), voxelize(), cast(), render(), evaluate(), clip(),
info(). See docs/python.md.
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
    load,
    mesh,
    sphere,
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
    "load",
    "mesh",
    "sphere",
]

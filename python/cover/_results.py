"""Result classes of cover.Model's methods (numbers with their provenance)."""

from collections import namedtuple

__all__ = ["MeshResult", "VolumeResult", "VoxelLattice"]


class VolumeResult(float):
    """Model.volume()'s result: a float (the volume) with its provenance, as the C++
    VolumeResult and `cover volume --json`: volume, area (None where it would need
    evaluation), method ("covering", "rays", "bracket" or "brep"), error_bound (|volume -
    exact| <= error_bound; 0 for exact methods), rays (ray method) or cells (bracket) and
    target_met (whether the bound met the relative target)."""

    def __new__(cls, info):
        self = super().__new__(cls, info["volume"])
        self.volume = float(info["volume"])
        self.area = info.get("area")
        self.method = info["method"]
        self.error_bound = float(info["error_bound"])
        self.rays = info.get("rays")
        self.cells = info.get("cells")
        self.target_met = info.get("target_met", True)
        return self

    __str__ = float.__repr__  # print() and str() show the number, as for a float

    def __repr__(self):
        return (f"VolumeResult(volume={self.volume!r}, method={self.method!r}, "
                f"error_bound={self.error_bound!r}, area={self.area!r})")

    def as_dict(self):
        """The dict of `cover volume --json` (and of Model.volume_info())."""
        d = {"volume": self.volume, "area": self.area, "method": self.method,
             "error_bound": self.error_bound}
        if self.rays is not None:
            d["rays"] = self.rays
        if self.cells is not None:
            d["cells"] = self.cells
        if self.method in ("rays", "bracket"):
            d["target_met"] = self.target_met
        return d

    def __reduce__(self):
        return (VolumeResult, (self.as_dict(),))


class MeshResult(tuple):
    """Model.evaluate()'s result: the tuple (V, F) or (V, F, L) as before (it unpacks the same),
    with save(path) writing it as `cover evaluate -o path` would (every mesh format the CLI
    writes; the leaf ids, when present, as PLY face property, OBJ groups or glTF / 3MF
    materials)."""

    def save(self, path):
        """Writes the mesh atomically; the format follows the extension (cover.write_mesh)."""
        from ._cover import write_mesh

        write_mesh(path, self[0], self[1], self[2] if len(self) > 2 else None)


class VoxelLattice(namedtuple("VoxelLattice", "origin spacing dims cube_size")):
    """The global grid of Model.voxelize (Model.voxel_lattice's result), as the C++
    VoxelLattice: origin (the min corner of voxel (0, 0, 0)), spacing (the same on every axis),
    dims (NX, NY, NZ) and cube_size (the exact cube of a cubic grid made from bounds, which
    .binvox and the .raw sidecar record; None for grids made from voxel_size or dims). Voxel
    (i, j, k) is centred at origin + (i + 1/2, j + 1/2, k + 1/2) * spacing. Pass it to
    cover.write_voxels as lattice=."""

    __slots__ = ()

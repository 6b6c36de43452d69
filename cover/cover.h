#pragma once
// Cover's umbrella header: every public module header (installed under include/cover/).
// Link cover::cover (find_package(Cover)); the kernels are free functions on a Solid
// (DESIGN.md: the simplicial-coverings engine), grouped by module:
//   solid/     the non-evaluated solid, CSG operators, primitives, transforms, mesh and scene I/O
//   covering/  exact predicates, BVH, classification, rays, volume, bounds
//   raster/    voxelization, voxel formats, rendering
//   octree/    direct octrees and their formats
//   brep/      plane clip and patch, the half-edge kernel
//   boolean/   evaluation of the CSG result to a closed 2-manifold mesh

#include "boolean/evaluate.h"
#include "brep/clip.h"
#include "brep/halfedge.h"
#include "covering/bounds.h"
#include "covering/bvh.h"
#include "covering/classify.h"
#include "covering/predicates.h"
#include "covering/ray.h"
#include "covering/volume.h"
#include "octree/octree.h"
#include "octree/octree_io.h"
#include "raster/camera.h"
#include "raster/png.h"
#include "raster/render.h"
#include "raster/voxel_grid.h"
#include "raster/voxel_io.h"
#include "raster/voxel_surface.h"
#include "raster/voxelize.h"
#include "solid/atomic_file.h"
#include "solid/errors.h"
#include "solid/measure.h"
#include "solid/memory_limit.h"
#include "solid/mesh_io.h"
#include "solid/npy.h"
#include "solid/orient.h"
#include "solid/polygon_mesh.h"
#include "solid/primitives.h"
#include "solid/scene.h"
#include "solid/solid.h"
#include "solid/transform.h"
#include "solid/validate.h"

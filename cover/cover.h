#pragma once
// Cover's umbrella header: every public module header (installed under include/cover/).
// Link cover::cover (find_package(Cover)). Start with cover::Model (model/model.h): load a file
// or build primitives, combine with | & - ~, and call a method per kernel. Underneath, the
// kernels are free functions on a Solid ([Segura2004]; docs/design.md), by module:
//   model/     the cover::Model facade
//   solid/     the non-evaluated solid, CSG operators, primitives, transforms, mesh and scene I/O,
//              exact predicates, face triangulation
//   covering/  BVH, classification, rays, volume, bounds
//   raster/    voxelization, voxel formats, rendering
//   octree/    direct octrees and their formats
//   brep/      plane clip and patch, the half-edge kernel
//   boolean/   evaluation of the CSG result to a closed 2-manifold mesh

#include "model/model.h"
#include "boolean/evaluate.h"
#include "brep/clip.h"
#include "brep/halfedge.h"
#include "covering/bounds.h"
#include "covering/bvh.h"
#include "covering/classify.h"
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
#include "raster/zarr_io.h"
#include "solid/atomic_file.h"
#include "solid/errors.h"
#include "solid/measure.h"
#include "solid/memory_limit.h"
#include "solid/mesh_io.h"
#include "solid/npy.h"
#include "solid/orient.h"
#include "solid/polygon_mesh.h"
#include "solid/predicates.h"
#include "solid/primitives.h"
#include "solid/scene.h"
#include "solid/solid.h"
#include "solid/transform.h"
#include "solid/triangulate.h"
#include "solid/union_find.h"
#include "solid/validate.h"
#include "solid/voxel_bounds.h"

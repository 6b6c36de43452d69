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

#include "cover/boolean/evaluate.h"
#include "cover/brep/clip.h"
#include "cover/brep/halfedge.h"
#include "cover/covering/bounds.h"
#include "cover/covering/bvh.h"
#include "cover/covering/classify.h"
#include "cover/covering/ray.h"
#include "cover/covering/volume.h"
#include "cover/model/info.h"
#include "cover/model/model.h"
#include "cover/octree/octree.h"
#include "cover/octree/octree_io.h"
#include "cover/raster/camera.h"
#include "cover/raster/png.h"
#include "cover/raster/render.h"
#include "cover/raster/voxel_grid.h"
#include "cover/raster/voxel_io.h"
#include "cover/raster/voxel_surface.h"
#include "cover/raster/voxelize.h"
#include "cover/raster/zarr_io.h"
#include "cover/solid/errors.h"
#include "cover/solid/measure.h"
#include "cover/solid/mesh_io.h"
#include "cover/solid/npy.h"
#include "cover/solid/orient.h"
#include "cover/solid/polygon_mesh.h"
#include "cover/solid/predicates.h"
#include "cover/solid/primitives.h"
#include "cover/solid/scene.h"
#include "cover/solid/solid.h"
#include "cover/solid/transform.h"
#include "cover/solid/triangulate.h"
#include "cover/solid/validate.h"
#include "cover/solid/voxel_bounds.h"

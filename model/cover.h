#pragma once
// Cover's umbrella header: every public module header (installed under include/cover/).
// Link cover::cover (find_package(Cover)). Start with cover::Model (model/model.h): load a file
// or build primitives, combine with | & - ~, and call a method per kernel. Underneath, the
// kernels are free functions on a Solid ([Segura2004]; docs/design.md), by module:
//   model/     the cover::Model facade
//   solid/     the core: value types, the non-evaluated solid, CSG operators, primitives,
//              transforms, measures, exact predicates, errors
//   field/     field leaves (skeletal primitives, blends): certified sign, bounds, value;
//              warp leaves (twist, taper, bend): the maps, their inverses, sound enclosures
//   mesh/      the mesh toolkit: validation, orientation, repair, face triangulation
//   covering/  the prepared solid (BVH, open-leaf trees), classification, rays, volume, bounds
//   render/    cameras and ray-cast images
//   voxel/     voxelization, voxel grids, blocky boundary meshes
//   octree/    direct octrees
//   io/        every file format: meshes, scenes, PNG, .npy, voxel grids, octrees
//   brep/      plane clip and patch, the half-edge kernel
//   boolean/   evaluation of the CSG result to a closed 2-manifold mesh

#include "cover/boolean/evaluate.h"
#include "cover/brep/clip.h"
#include "cover/brep/halfedge.h"
#include "cover/covering/bounds.h"
#include "cover/covering/bvh.h"
#include "cover/covering/classify.h"
#include "cover/covering/prepared.h"
#include "cover/covering/ray.h"
#include "cover/covering/volume.h"
#include "cover/field/field.h"
#include "cover/field/warp.h"
#include "cover/io/mesh_io.h"
#include "cover/io/npy.h"
#include "cover/io/octree_io.h"
#include "cover/io/png.h"
#include "cover/io/scene.h"
#include "cover/io/voxel_io.h"
#include "cover/io/zarr_io.h"
#include "cover/mesh/orient.h"
#include "cover/mesh/triangulate.h"
#include "cover/mesh/validate.h"
#include "cover/model/info.h"
#include "cover/model/model.h"
#include "cover/modeler/dlfl.h"
#include "cover/modeler/ffd.h"
#include "cover/modeler/operators.h"
#include "cover/octree/octree.h"
#include "cover/points/point_set.h"
#include "cover/render/camera.h"
#include "cover/render/render.h"
#include "cover/solid/errors.h"
#include "cover/solid/measure.h"
#include "cover/solid/polygon_mesh.h"
#include "cover/solid/predicates.h"
#include "cover/solid/primitives.h"
#include "cover/solid/solid.h"
#include "cover/solid/transform.h"
#include "cover/solid/voxel_bounds.h"
#include "cover/subdivision/subdivide.h"
#include "cover/voxel/voxel_grid.h"
#include "cover/voxel/voxel_surface.h"
#include "cover/voxel/voxelize.h"

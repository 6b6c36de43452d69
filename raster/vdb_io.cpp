// OpenVDB export (raster/vdb_io.h): the one translation unit that includes OpenVDB.
//
// Leaves are built 8³ block by block from the bit grid: a block's 8 voxels along z are one byte
// of a column word (the block's z origin is a multiple of 8), so an empty block is skipped after
// 64 byte reads, a full one becomes a leaf filled at once (a tile after prune()), and a mixed one
// sets its voxels one by one.

#include "raster/vdb_io.h"

#include <string>

#include "solid/atomic_file.h"
#include "solid/errors.h"
#include "solid/mesh_io.h"

#ifdef COVER_WITH_OPENVDB
#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>
#endif

namespace cover {
namespace {

namespace fs = std::filesystem;

#ifdef COVER_WITH_OPENVDB
openvdb::BoolGrid::Ptr to_vdb(const VoxelGrid& grid) {
  const VoxelLattice& l = grid.lattice;
  openvdb::BoolGrid::Ptr vdb = openvdb::BoolGrid::create(false);
  vdb->setName("occupancy");
  const double h = l.spacing;
  openvdb::math::Transform::Ptr transform = openvdb::math::Transform::createLinearTransform(h);
  transform->postTranslate(
      openvdb::Vec3d(l.origin.x + 0.5 * h, l.origin.y + 0.5 * h, l.origin.z + 0.5 * h));
  vdb->setTransform(transform);
  vdb->insertMeta("cover_origin", openvdb::Vec3DMetadata(openvdb::Vec3d(l.origin.x, l.origin.y, l.origin.z)));
  vdb->insertMeta("cover_spacing", openvdb::DoubleMetadata(h));
  vdb->insertMeta("cover_dims", openvdb::Vec3IMetadata(openvdb::Vec3i(l.dims[0], l.dims[1], l.dims[2])));
  vdb->insertMeta("cover_tie_rule",
                  openvdb::StringMetadata("a centre c on a leaf surface takes the membership of "
                                          "c + (eps, eps^2, eps^3), eps -> 0+"));
  openvdb::BoolTree& tree = vdb->tree();
  using Leaf = openvdb::BoolTree::LeafNodeType;
  const int nx = grid.nx(), ny = grid.ny(), nz = grid.nz();
  for (int x0 = 0; x0 < nx; x0 += 8)
    for (int y0 = 0; y0 < ny; y0 += 8)
      for (int z0 = 0; z0 < nz; z0 += 8) {
        // bytes[dx][dy]: voxels z0..z0+7 of column (x0 + dx, y0 + dy); 0 outside the grid.
        uint8_t bytes[8][8] = {};
        bool any = false, all = x0 + 8 <= nx && y0 + 8 <= ny && z0 + 8 <= nz;
        for (int dx = 0; dx < 8 && x0 + dx < nx; ++dx)
          for (int dy = 0; dy < 8 && y0 + dy < ny; ++dy) {
            const uint64_t word = grid.bits[grid.column_word(x0 + dx, y0 + dy) + z0 / 64];
            uint8_t b = static_cast<uint8_t>(word >> (z0 % 64));
            if (z0 + 8 > nz) b &= static_cast<uint8_t>((1u << (nz - z0)) - 1);
            bytes[dx][dy] = b;
            any |= b != 0;
            all &= b == 0xff;
          }
        if (!any) continue;
        Leaf* leaf = tree.touchLeaf(openvdb::Coord(x0, y0, z0));
        if (all) {
          leaf->fill(true, true);
          continue;
        }
        for (int dx = 0; dx < 8; ++dx)
          for (int dy = 0; dy < 8; ++dy)
            for (int dz = 0; dz < 8; ++dz)
              if ((bytes[dx][dy] >> dz) & 1)
                leaf->setValueOn(static_cast<openvdb::Index>((dx << 6) | (dy << 3) | dz), true);
      }
  tree.prune();
  return vdb;
}
#endif

}  // namespace

bool is_vdb_extension(const fs::path& path) {
  return lower_extension(path) == ".vdb";
}

void write_vdb(const fs::path& path, const VoxelGrid& grid) {
  if (!grid.whole() || grid.bits.size() != grid.word_count())
    throw PreconditionError("write_vdb: a whole grid expected");
#ifdef COVER_WITH_OPENVDB
  openvdb::initialize();
  const openvdb::BoolGrid::Ptr vdb = to_vdb(grid);
  write_atomically(
      path,
      [&](const fs::path& temporary) {
        try {
          openvdb::io::File file(temporary.string());
          openvdb::GridPtrVec grids{vdb};
          file.write(grids);
          file.close();
          return true;
        } catch (const openvdb::Exception&) {
          return false;
        }
      },
      "the voxels");
#else
  throw InputError(path.string() + ": this Cover was built without OpenVDB (libopenvdb-dev)");
#endif
}

}  // namespace cover

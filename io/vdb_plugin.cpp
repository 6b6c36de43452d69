// The OpenVDB plugin cover_vdb.so (io/vdb_plugin.h): the one translation unit that includes
// OpenVDB, loaded by io/vdb_io.cpp on the first .vdb write.
//
// Leaves are built 8³ block by block from the bit grid: a block's 8 voxels along z are one byte
// of a column word (the block's z origin is a multiple of 8), so an empty block is skipped after
// 64 byte reads, a full one becomes a leaf filled at once (a tile after prune()), and a mixed one
// sets its voxels one by one.

#include "cover/io/vdb_plugin.h"

#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>

#include <cstdio>
#include <exception>

namespace {

openvdb::BoolGrid::Ptr to_vdb(const CoverVdbGrid& g) {
  openvdb::BoolGrid::Ptr vdb = openvdb::BoolGrid::create(false);
  vdb->setName("occupancy");
  const double h = g.spacing;
  openvdb::math::Transform::Ptr transform = openvdb::math::Transform::createLinearTransform(h);
  transform->postTranslate(
      openvdb::Vec3d(g.origin[0] + 0.5 * h, g.origin[1] + 0.5 * h, g.origin[2] + 0.5 * h));
  vdb->setTransform(transform);
  vdb->insertMeta("cover_origin",
                  openvdb::Vec3DMetadata(openvdb::Vec3d(g.origin[0], g.origin[1], g.origin[2])));
  vdb->insertMeta("cover_spacing", openvdb::DoubleMetadata(h));
  vdb->insertMeta("cover_dims",
                  openvdb::Vec3IMetadata(openvdb::Vec3i(g.dims[0], g.dims[1], g.dims[2])));
  vdb->insertMeta("cover_tie_rule",
                  openvdb::StringMetadata("a centre c on a leaf surface takes the membership of "
                                          "c + (eps, eps^2, eps^3), eps -> 0+"));
  openvdb::BoolTree& tree = vdb->tree();
  using Leaf = openvdb::BoolTree::LeafNodeType;
  const int nx = g.dims[0], ny = g.dims[1], nz = g.dims[2];
  auto column_word = [&](int i, int j) {
    return (static_cast<size_t>(i) * static_cast<size_t>(ny) + static_cast<size_t>(j)) *
           g.words_per_column;
  };
  for (int x0 = 0; x0 < nx; x0 += 8)
    for (int y0 = 0; y0 < ny; y0 += 8)
      for (int z0 = 0; z0 < nz; z0 += 8) {
        // bytes[dx][dy]: voxels z0..z0+7 of column (x0 + dx, y0 + dy); 0 outside the grid.
        uint8_t bytes[8][8] = {};
        bool any = false, all = x0 + 8 <= nx && y0 + 8 <= ny && z0 + 8 <= nz;
        for (int dx = 0; dx < 8 && x0 + dx < nx; ++dx)
          for (int dy = 0; dy < 8 && y0 + dy < ny; ++dy) {
            const uint64_t word = g.bits[column_word(x0 + dx, y0 + dy) + z0 / 64];
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

}  // namespace

extern "C" {

__attribute__((visibility("default"))) int cover_vdb_plugin_version(void) {
  return COVER_VDB_PLUGIN_VERSION;
}

__attribute__((visibility("default"))) int cover_vdb_write(const CoverVdbGrid* grid,
                                                           const char* path, char* message,
                                                           size_t capacity) {
  // No exception may cross the C boundary: each becomes the message.
  try {
    openvdb::initialize();
    openvdb::io::File file(path);
    openvdb::GridPtrVec grids{to_vdb(*grid)};
    file.write(grids);
    file.close();
    return 0;
  } catch (const std::exception& e) {
    if (capacity > 0) std::snprintf(message, capacity, "%s", e.what());
  } catch (...) {
    if (capacity > 0) std::snprintf(message, capacity, "unknown error in OpenVDB");
  }
  return 1;
}

}  // extern "C"

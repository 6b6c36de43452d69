#pragma once
// Expansion of voxel bits into bytes 0/1 (voxel_io.cpp, zarr_io.cpp): internal to raster/.

#include <cstddef>
#include <cstdint>
#include <cstring>

namespace cover::detail {

/// kExpand.bytes[b][i] = bit i of b: one lookup expands 8 voxel bits into 8 bytes of 0/1.
struct ExpandTable {
  uint8_t bytes[256][8];
  constexpr ExpandTable() : bytes{} {
    for (int b = 0; b < 256; ++b)
      for (int i = 0; i < 8; ++i) bytes[b][i] = static_cast<uint8_t>((b >> i) & 1);
  }
};
inline constexpr ExpandTable kExpand;

/// Writes bits 0..count−1 of the little-endian bit string `words` as bytes 0/1 to `out`.
inline void expand_bits(const uint64_t* words, size_t count, uint8_t* out) {
  size_t i = 0;
  for (; i + 8 <= count; i += 8)
    std::memcpy(out + i, kExpand.bytes[(words[i / 64] >> (i % 64)) & 0xff], 8);
  for (; i < count; ++i) out[i] = static_cast<uint8_t>((words[i / 64] >> (i % 64)) & 1);
}

}  // namespace cover::detail

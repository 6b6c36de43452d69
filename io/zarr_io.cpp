// Zarr v2 store writer (io/zarr_io.h).
//
// Notation: C = chunk edge; a brick is the chunk column (I, J): local grid of nx × ny × NZ voxels
// (nx, ny ≤ C at the far edges). Chunk (I, J, K) takes local z range [K·C, min(NZ, (K+1)·C)),
// expanded to C³ bytes (x slowest, z fastest; padding 0), compressed by zlib's compress2 (the
// zlib format numcodecs' Zlib codec reads).

#include "cover/io/zarr_io.h"

#include <zlib.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <exception>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "cover/io/atomic_file.h"
#include "cover/io/detail/bit_expand.h"
#include "cover/io/mesh_io.h"
#include "cover/solid/errors.h"
#include "cover/solid/memory_limit.h"
#include "cover/solid/parallel.h"

namespace cover {
namespace {

namespace fs = std::filesystem;

/// Shortest decimal text that reads back as exactly `value`.
std::string number(double value) {
  std::array<char, 32> buffer{};
  const auto result = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
  return std::string(buffer.data(), result.ptr);
}

std::string triple(double a, double b, double c) {
  return "[" + number(a) + ", " + number(b) + ", " + number(c) + "]";
}

/// Writes `size` bytes to a new file `file`; throws InputError naming `target` on failure.
void write_bytes(const fs::path& file, const void* data, size_t size, const fs::path& target) {
  std::FILE* f = std::fopen(file.c_str(), "wb");
  if (f == nullptr) throw InputError(target.string() + ": cannot write: " + std::strerror(errno));
  const bool written = size == 0 || std::fwrite(data, 1, size, f) == size;
  const int write_errno = errno;
  const bool closed = std::fclose(f) == 0;
  if (!written || !closed)
    throw InputError(target.string() +
                     ": cannot write: " + std::strerror(!written ? write_errno : errno));
}

std::string zarray(const VoxelLattice& l, int chunk, int level) {
  const std::string c = std::to_string(chunk);
  return "{\n  \"chunks\": [" + c + ", " + c + ", " + c +
         "],\n  \"compressor\": {\"id\": \"zlib\", \"level\": " + std::to_string(level) +
         "},\n  \"dimension_separator\": \".\",\n  \"dtype\": \"|u1\",\n  \"fill_value\": 0,\n"
         "  \"filters\": null,\n  \"order\": \"C\",\n  \"shape\": [" +
         std::to_string(l.dims[0]) + ", " + std::to_string(l.dims[1]) + ", " +
         std::to_string(l.dims[2]) + "],\n  \"zarr_format\": 2\n}\n";
}

std::string zattrs(const VoxelLattice& l) {
  const Vec3& o = l.origin;
  const std::string bounds =
      l.cube_size
          ? "{\"min\": " + triple(o.x, o.y, o.z) + ", \"size\": " + number(*l.cube_size) + "}"
          : "{\"min\": " + triple(o.x, o.y, o.z) + ", \"max\": " +
                triple(o.x + l.dims[0] * l.spacing, o.y + l.dims[1] * l.spacing,
                       o.z + l.dims[2] * l.spacing) +
                "}";
  return "{\n  \"bounds\": " + bounds +
         ",\n  \"centre\": \"origin + (i + 1/2, j + 1/2, k + 1/2) * spacing\",\n"
         "  \"dims\": [" +
         std::to_string(l.dims[0]) + ", " + std::to_string(l.dims[1]) + ", " +
         std::to_string(l.dims[2]) +
         "],\n  \"index\": \"[x, y, z]\",\n  \"origin\": " + triple(o.x, o.y, o.z) +
         ",\n  \"spacing\": " + number(l.spacing) +
         ",\n  \"tie_rule\": \"a centre c on a leaf surface takes the membership of "
         "c + (eps, eps^2, eps^3), eps -> 0+\",\n  \"value\": \"1 iff the voxel centre is "
         "inside the solid\"\n}\n";
}

/// True if any of bits [k0, k1) of the column is set.
bool any_bits(const uint64_t* column, int k0, int k1) {
  for (int k = k0; k < k1;) {
    const int w = k >> 6, b = k & 63;
    const int take = std::min(64 - b, k1 - k);
    const uint64_t mask = (take == 64 ? ~uint64_t{0} : ((uint64_t{1} << take) - 1)) << b;
    if (column[w] & mask) return true;
    k += take;
  }
  return false;
}

/// Writes bits [k0, k1) of the column as bytes 0/1 (a table lookup per 8 bits when k0 is a
/// multiple of 64, as with the default C = 128).
void expand_range(const uint64_t* column, int k0, int k1, uint8_t* out) {
  if ((k0 & 63) == 0) {
    detail::expand_bits(column + (k0 >> 6), static_cast<size_t>(k1 - k0), out);
    return;
  }
  for (int k = k0; k < k1; ++k)
    out[k - k0] = static_cast<uint8_t>((column[k >> 6] >> (k & 63)) & 1);
}

/// True if every bit [k0, k1) of the column is set.
bool all_bits(const uint64_t* column, int k0, int k1) {
  for (int k = k0; k < k1;) {
    const int w = k >> 6, b = k & 63;
    const int take = std::min(64 - b, k1 - k);
    const uint64_t mask = (take == 64 ? ~uint64_t{0} : ((uint64_t{1} << take) - 1)) << b;
    if ((column[w] & mask) != mask) return false;
    k += take;
  }
  return true;
}

/// True for the names Cover writes in a store: .zarray, .zattrs and chunks I.J.K.
bool own_store_name(const std::string& name) {
  if (name == ".zarray" || name == ".zattrs") return true;
  int dots = 0;
  bool digit = false;
  for (const char ch : name) {
    if (ch == '.') {
      if (!digit) return false;
      ++dots;
      digit = false;
    } else if (ch >= '0' && ch <= '9') {
      digit = true;
    } else {
      return false;
    }
  }
  return dots == 2 && digit;
}

}  // namespace

bool is_zarr_extension(const fs::path& path) { return lower_extension(path) == ".zarr"; }

double zarr_brick_bytes(const VoxelLattice& lattice, int chunk) {
  const double c = chunk, nz = std::max(lattice.dims[2], 1);
  const double bits = c * c * (std::ceil(nz / 64) * 8);  // the brick's words
  const double chunk_bytes = c * c * c;                  // one chunk expanded, and compressed
  // The voxelizer's scratch per brick: centres, triangle lists, a band's crossings (~16 bytes
  // per crossing, a few per column) and its column offsets; 1 MiB covers them at C ≤ 512.
  return bits + 2.01 * chunk_bytes + c * c * 64 + (1 << 20);
}

ZarrResult write_zarr(const fs::path& path, const VoxelLattice& lattice, const ZarrOptions& options,
                      const BrickFunction& brick) {
  const std::string name = path.string();
  if (options.chunk < 1)
    throw InputError(parameter("chunk") + ": expected a whole number ≥ 1, got " +
                     std::to_string(options.chunk));
  if (options.level < 1 || options.level > 9)
    throw InputError(name + ": zlib level must be 1 to 9, got " + std::to_string(options.level));
  for (const int d : lattice.dims)
    if (d < 1) throw PreconditionError("write_zarr: lattice dims must be ≥ 1");
  // C is at most the largest dim: a larger chunk only pads.
  const int c =
      std::min(options.chunk, std::max({lattice.dims[0], lattice.dims[1], lattice.dims[2]}));
  ZarrResult result;
  result.brick_bytes = zarr_brick_bytes(lattice, c);
  check_memory(result.brick_bytes, options.max_bytes, name + ": one brick of the Zarr store");
  const int threads = max_threads();
  int in_flight = options.bricks_in_flight > 0 ? options.bricks_in_flight : 2 * threads;
  const double fit = std::floor(static_cast<double>(options.max_bytes) / result.brick_bytes);
  in_flight = std::max(1, static_cast<int>(std::min<double>(in_flight, fit)));
  const std::array<int, 3> chunks = {(lattice.dims[0] + c - 1) / c, (lattice.dims[1] + c - 1) / c,
                                     (lattice.dims[2] + c - 1) / c};
  const size_t bricks = static_cast<size_t>(chunks[0]) * chunks[1];
  in_flight = static_cast<int>(std::min<size_t>(in_flight, bricks));
  result.bricks_in_flight = in_flight;
  result.chunks = static_cast<uint64_t>(bricks) * chunks[2];

  OutputFolder temporary(path, "the Zarr store", [](const fs::path& folder) {
    return refuse_unless_own_folder(folder, ".zarray", own_store_name, "a Zarr store");
  });
  const fs::path& target = path;
  const std::string array = zarray(lattice, c, options.level);
  write_bytes(temporary.path() / ".zarray", array.data(), array.size(), target);
  const std::string attrs = zattrs(lattice);
  write_bytes(temporary.path() / ".zattrs", attrs.data(), attrs.size(), target);

  // Workers: each takes the next brick until none is left, so at most in_flight bricks exist.
  std::atomic<size_t> next{0}, done{0};
  std::atomic<uint64_t> occupied{0}, written{0};
  std::atomic<bool> failed{false};
  std::exception_ptr error;
  std::mutex error_mutex;
  const std::thread::id caller = std::this_thread::get_id();
  const size_t chunk_bytes = static_cast<size_t>(c) * c * c;
  // A full chunk of 1s, compressed once (interior chunks are common and all alike).
  std::vector<uint8_t> full_chunk;
  {
    const std::vector<uint8_t> ones(chunk_bytes, 1);
    uLongf size = compressBound(static_cast<uLong>(chunk_bytes));
    full_chunk.resize(size);
    if (compress2(full_chunk.data(), &size, ones.data(), static_cast<uLong>(chunk_bytes),
                  options.level) != Z_OK)
      throw InputError(name + ": cannot write: zlib compression failed");
    full_chunk.resize(size);
  }
  parallel_for(static_cast<size_t>(in_flight), 1, [&](size_t, size_t) {
    VoxelGrid grid;
    std::vector<uint8_t> bytes(chunk_bytes);
    std::vector<uint8_t> packed(compressBound(static_cast<uLong>(chunk_bytes)));
    for (size_t b = next++; b < bricks && !failed; b = next++) {
      try {
        const int ci = static_cast<int>(b / chunks[1]), cj = static_cast<int>(b % chunks[1]);
        const IndexBox box{{ci * c, cj * c, 0},
                           {std::min(lattice.dims[0], (ci + 1) * c),
                            std::min(lattice.dims[1], (cj + 1) * c), lattice.dims[2]}};
        brick(box, grid);
        if (grid.box != box || grid.bits.size() != grid.word_count())
          throw PreconditionError("write_zarr: the brick function filled another box");
        occupied += grid.count();
        const int nx = grid.nx(), ny = grid.ny();
        for (int ck = 0; ck < chunks[2]; ++ck) {
          const int k0 = ck * c, k1 = std::min(lattice.dims[2], k0 + c);
          bool any = false, all = nx == c && ny == c && k1 - k0 == c;
          for (int x = 0; x < nx; ++x)
            for (int y = 0; y < ny; ++y) {
              const uint64_t* column = &grid.bits[grid.column_word(x, y)];
              any = any || any_bits(column, k0, k1);
              all = all && all_bits(column, k0, k1);
            }
          if (!any) continue;  // all 0: fill_value, no file
          const std::string file =
              temporary.path() /
              (std::to_string(ci) + "." + std::to_string(cj) + "." + std::to_string(ck));
          if (all) {  // all 1 (inside the solid): the same compressed bytes every time
            write_bytes(file, full_chunk.data(), full_chunk.size(), target);
            ++written;
            continue;
          }
          std::fill(bytes.begin(), bytes.end(), 0);
          for (int x = 0; x < nx; ++x)
            for (int y = 0; y < ny; ++y)
              expand_range(&grid.bits[grid.column_word(x, y)], k0, k1,
                           &bytes[(static_cast<size_t>(x) * c + y) * c]);
          uLongf size = static_cast<uLongf>(packed.size());
          if (compress2(packed.data(), &size, bytes.data(), static_cast<uLong>(chunk_bytes),
                        options.level) != Z_OK)
            throw InputError(name + ": cannot write: zlib compression failed");
          write_bytes(file, packed.data(), size, target);
          ++written;
        }
      } catch (...) {
        std::lock_guard<std::mutex> lock(error_mutex);
        if (!error) error = std::current_exception();
        failed = true;
      }
      const size_t finished = ++done;
      if (options.progress && std::this_thread::get_id() == caller && finished < bricks)
        options.progress(static_cast<double>(finished) / bricks);
    }
  });
  if (error) std::rethrow_exception(error);

  temporary.commit();
  if (options.progress) options.progress(1.0);
  result.occupied = occupied;
  result.chunks_written = written;
  return result;
}

ZarrResult write_zarr(const fs::path& path, const VoxelGrid& grid, const ZarrOptions& options) {
  if (!grid.whole()) throw PreconditionError("write_zarr: the grid must hold its whole lattice");
  // A brick spans every z, so its columns are the grid's columns, word for word.
  return write_zarr(path, grid.lattice, options, [&](const IndexBox& box, VoxelGrid& brick) {
    brick = empty_voxel_grid(grid.lattice, box);
    const size_t words = brick.words_per_column();
    for (int i = 0; i < brick.nx(); ++i)
      for (int j = 0; j < brick.ny(); ++j)
        std::copy_n(grid.bits.begin() +
                        static_cast<std::ptrdiff_t>(grid.column_word(box.lo[0] + i, box.lo[1] + j)),
                    words,
                    brick.bits.begin() + static_cast<std::ptrdiff_t>(brick.column_word(i, j)));
  });
}

}  // namespace cover

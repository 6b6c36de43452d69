// Voxel grid export: .binvox, .vti, .npy, .raw (+ .raw.json sidecar).
//
// Notation: NX, NY, NZ = the grid's dims (N for a cubic grid); W = grid.words_per_column() =
// ⌈NZ/64⌉. A column is the NZ bits over z of the voxels (x, y, ·), stored z-contiguous
// (voxel_grid.h). A slab is the voxels that share the outermost coordinate of a file's order.
// Files are streamed one slab at a time, so memory stays O(N²) bytes beside the grid (N = 2048:
// 4 MiB per byte slab; the grid itself holds N³/8 bytes).
//   [x][y][z] (.npy, .raw)  slab = fixed x; each column expands straight to NZ bytes.
//   x, z, y   (.binvox)     cubic only; slab = fixed x; 64×64 bit transposes turn the columns of
//                           one x into rows over y, which feed a run-length encoder whose runs
//                           cross slabs.
//   z, y, x   (.vti cells)  64 z-slabs at a time: 64×64 bit transposes turn blocks of 64 columns
//                           into rows over x (64·NY·⌈NX/64⌉ words), then each z-slab expands to
//                           bytes.
// Every file goes through write_atomically (io/atomic_file.h): a temporary beside FILE, renamed
// over it once complete (or with the command's other outputs); on any failure the temporary is
// removed and InputError names FILE.

#include "cover/io/voxel_io.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "cover/io/atomic_file.h"
#include "cover/io/detail/bit_expand.h"
#include "cover/io/mesh_io.h"
#include "cover/io/npy.h"
#include "cover/solid/errors.h"

namespace cover {
namespace {

namespace fs = std::filesystem;
using detail::expand_bits;

/// `text` in single quotes, non-printable bytes as \xHH (for error messages).
std::string quote(std::string_view text) {
  std::string out = "'";
  for (char ch : text) {
    const auto c = static_cast<unsigned char>(ch);
    if (c >= 0x20 && c < 0x7F && c != '\\') {
      out += ch;
    } else {
      constexpr char kHex[] = "0123456789abcdef";
      out += "\\x";
      out += kHex[c >> 4];
      out += kHex[c & 15];
    }
  }
  return out + "'";
}

/// Shortest decimal text that reads back as exactly `value` (locale-independent).
std::string number(double value) {
  std::array<char, 32> buffer{};
  const auto result = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
  return std::string(buffer.data(), result.ptr);
}

/// A temporary output file (write_atomically's) written through stdio; every failure throws
/// InputError "TARGET: cannot write: reason", naming the file the user asked for.
class OutputFile {
 public:
  OutputFile(const fs::path& temporary, const fs::path& target) : target_(target) {
    file_ = std::fopen(temporary.c_str(), "wb");
    if (file_ == nullptr) fail(errno);
  }
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;
  ~OutputFile() {
    if (file_ != nullptr) std::fclose(file_);
  }

  void write(const void* data, size_t size) {
    if (size != 0 && std::fwrite(data, 1, size, file_) != size) fail(errno);
  }
  void write(std::string_view text) { write(text.data(), text.size()); }

  /// Flushes and closes the file; throws if any write failed (e.g. a full disk).
  void finish() {
    std::FILE* file = std::exchange(file_, nullptr);
    const bool flushed = std::fflush(file) == 0 && std::ferror(file) == 0;
    const int flush_errno = errno;
    const bool closed = std::fclose(file) == 0;
    if (!flushed || !closed) fail(flushed ? errno : flush_errno);
  }

 private:
  [[noreturn]] void fail(int error) const {
    throw InputError(target_.string() + ": cannot write: " + std::strerror(error));
  }

  const fs::path& target_;
  std::FILE* file_ = nullptr;
};

/// Writes `path` atomically (io/atomic_file.h) with body(out).
template <class Body>
void write_file(const fs::path& path, const Body& body) {
  write_atomically(
      path,
      [&](const fs::path& temporary) {
        OutputFile out(temporary, path);
        body(out);
        out.finish();
        return true;
      },
      "the voxels");
}

/// Transposes a 64×64 bit matrix in place: bit c of a[r] ↔ bit r of a[c] (recursive block
/// swap, Hacker's Delight §7-3, with bit 0 as column 0).
void transpose64(std::array<uint64_t, 64>& a) {
  uint64_t mask = 0x00000000FFFFFFFFull;
  for (int j = 32; j != 0; j >>= 1, mask ^= mask << j) {
    for (int k = 0; k < 64; k = ((k | j) + 1) & ~j) {
      const uint64_t t = ((a[k] >> j) ^ a[k | j]) & mask;
      a[k] ^= t << j;
      a[k | j] ^= t;
    }
  }
}

/// Number of valid bits in word `w` of a row of n bits.
int bits_in_word(size_t w, int n) { return std::min(64, n - static_cast<int>(64 * w)); }

// ---- .npy and .raw: [x][y][z], z fastest ----

/// Streams the NX·NY·NZ bytes in [x][y][z] order, one x-slab (NY·NZ bytes) at a time.
void write_xyz_bytes(OutputFile& out, const VoxelGrid& grid) {
  const size_t nz = static_cast<size_t>(grid.nz());
  std::vector<uint8_t> slab(static_cast<size_t>(grid.ny()) * nz);
  for (int x = 0; x < grid.nx(); ++x) {
    for (int y = 0; y < grid.ny(); ++y)
      expand_bits(&grid.bits[grid.column_word(x, y)], nz, &slab[static_cast<size_t>(y) * nz]);
    out.write(slab.data(), slab.size());
  }
}

/// "[a, b, c]" of the grid's dims.
std::string dims_list(const VoxelGrid& grid, const char* open, const char* close) {
  return open + std::to_string(grid.nx()) + ", " + std::to_string(grid.ny()) + ", " +
         std::to_string(grid.nz()) + close;
}

void write_npy(OutputFile& out, const VoxelGrid& grid) {
  const std::array<uint64_t, 3> shape{static_cast<uint64_t>(grid.nx()),
                                      static_cast<uint64_t>(grid.ny()),
                                      static_cast<uint64_t>(grid.nz())};
  out.write(npy_header("|u1", shape));
  write_xyz_bytes(out, grid);
}

/// "[x, y, z]" of a point.
std::string point_list(const Vec3& p) {
  return "[" + number(p.x) + ", " + number(p.y) + ", " + number(p.z) + "]";
}

/// The .raw sidecar: dims, order, dtype, bounds and voxel size as JSON. Bounds are {"min",
/// "size"} for a cubic grid made from a cube (--res), else {"min", "max"} (max = min + dims·h).
std::string raw_sidecar(const VoxelGrid& grid) {
  const VoxelLattice& l = grid.lattice;
  const std::string bounds =
      l.cube_size
          ? "\"min\": " + point_list(l.origin) + ", \"size\": " + number(*l.cube_size)
          : "\"min\": " + point_list(l.origin) + ", \"max\": " +
                point_list({l.origin.x + l.dims[0] * l.spacing, l.origin.y + l.dims[1] * l.spacing,
                            l.origin.z + l.dims[2] * l.spacing});
  return "{\n  \"dims\": " + dims_list(grid, "[", "]") +
         ",\n  \"order\": \"xyz (z fastest)\",\n  \"dtype\": \"uint8\",\n"
         "  \"bounds\": {" +
         bounds + "},\n  \"voxel_size\": " + number(grid.voxel_size()) + "\n}\n";
}

// ---- .binvox: RLE over index x·N·N + z·N + y ----

/// binvox run-length encoder: (value, count 1..255) byte pairs; runs continue across calls.
class RunEncoder {
 public:
  explicit RunEncoder(OutputFile& out) : out_(out) { buffer_.reserve(kFlushBytes + 512); }

  /// Appends the bits 0..count−1 of `word` (in order of increasing bit index).
  void add_bits(uint64_t word, int count) {
    int pos = 0;
    while (pos < count) {
      const uint64_t rest = word >> pos;
      const int length = value_ ? std::countr_one(rest) : std::countr_zero(rest);
      if (length >= count - pos) {  // the run of value_ reaches past this word
        run_ += static_cast<uint64_t>(count - pos);
        return;
      }
      run_ += static_cast<uint64_t>(length);
      pos += length;
      emit_run();
      value_ = !value_;
    }
  }

  /// Emits the last run and everything still buffered.
  void finish() {
    emit_run();
    out_.write(buffer_.data(), buffer_.size());
    buffer_.clear();
  }

 private:
  static constexpr size_t kFlushBytes = size_t{1} << 20;

  void emit_run() {
    while (run_ > 0) {
      const auto count = static_cast<uint8_t>(std::min<uint64_t>(run_, 255));
      buffer_.push_back(value_ ? 1 : 0);
      buffer_.push_back(count);
      run_ -= count;
      if (buffer_.size() >= kFlushBytes) {
        out_.write(buffer_.data(), buffer_.size());
        buffer_.clear();
      }
    }
  }

  OutputFile& out_;
  std::vector<uint8_t> buffer_;
  bool value_ = false;  ///< value of the current run
  uint64_t run_ = 0;    ///< its length so far (0 before the first voxel)
};

void write_binvox(OutputFile& out, const VoxelGrid& grid) {
  const VoxelLattice& l = grid.lattice;
  const Vec3& min = l.origin;
  const int grid_n = grid.nx();
  const std::string n = std::to_string(grid_n);
  // binvox maps voxel index i to (i + ½)/N · scale + translate along each axis.
  const double scale = l.cube_size ? *l.cube_size : grid_n * l.spacing;
  out.write("#binvox 1\ndim " + n + " " + n + " " + n + "\ntranslate " + number(min.x) + " " +
            number(min.y) + " " + number(min.z) + "\nscale " + number(scale) + "\ndata\n");
  const size_t words = grid.words_per_column();
  // rows[z·W + w]: bits over y (bit t = y − 64w) of the x-slab being encoded.
  std::vector<uint64_t> rows(static_cast<size_t>(grid_n) * words);
  std::array<uint64_t, 64> block{};
  RunEncoder encoder(out);
  for (int x = 0; x < grid_n; ++x) {
    for (size_t zw = 0; zw < words; ++zw) {
      for (size_t yw = 0; yw < words; ++yw) {
        // block[t] = bits over z of column (x, 64·yw + t), word zw; zero past y = N − 1.
        for (int t = 0; t < 64; ++t) {
          const int y = static_cast<int>(64 * yw) + t;
          block[t] = y < grid_n ? grid.bits[grid.column_word(x, y) + zw] : 0;
        }
        transpose64(block);  // block[dz] = bits over y of row z = 64·zw + dz
        for (int dz = 0; dz < bits_in_word(zw, grid_n); ++dz)
          rows[(64 * zw + dz) * words + yw] = block[dz];
      }
    }
    for (size_t z = 0; z < static_cast<size_t>(grid_n); ++z)
      for (size_t yw = 0; yw < words; ++yw)
        encoder.add_bits(rows[z * words + yw], bits_in_word(yw, grid_n));
  }
  encoder.finish();
}

// ---- .vti: VTK XML ImageData, cells in x-fastest order ----

void write_vti(OutputFile& out, const VoxelGrid& grid) {
  const int nx = grid.nx(), ny = grid.ny(), nz = grid.nz();
  const std::string extent =
      "0 " + std::to_string(nx) + " 0 " + std::to_string(ny) + " 0 " + std::to_string(nz);
  const Vec3& min = grid.lattice.origin;
  const std::string h = number(grid.voxel_size());
  const std::string origin = number(min.x) + " " + number(min.y) + " " + number(min.z);
  const std::string spacing = h + " " + h + " " + h;
  std::string xml =
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"ImageData\" version=\"1.0\" byte_order=\"LittleEndian\" "
      "header_type=\"UInt64\">\n";
  xml += "  <ImageData WholeExtent=\"" + extent + "\" Origin=\"" + origin + "\" Spacing=\"" +
         spacing + "\">\n";
  xml += "    <Piece Extent=\"" + extent + "\">\n";
  xml +=
      "      <PointData>\n"
      "      </PointData>\n"
      "      <CellData Scalars=\"occupancy\">\n"
      "        <DataArray type=\"UInt8\" Name=\"occupancy\" format=\"appended\" "
      "RangeMin=\"0\" RangeMax=\"1\" offset=\"0\"/>\n"
      "      </CellData>\n"
      "    </Piece>\n"
      "  </ImageData>\n"
      "  <AppendedData encoding=\"raw\">\n"
      "   _";
  out.write(xml);
  // Raw appended block: UInt64 little-endian byte count, then the NX·NY·NZ cell values.
  const uint64_t total = grid.lattice.voxel_count();
  uint8_t count_bytes[8];
  for (int i = 0; i < 8; ++i) count_bytes[i] = static_cast<uint8_t>(total >> (8 * i));
  out.write(count_bytes, sizeof count_bytes);

  const size_t words = grid.words_per_column();
  const size_t xwords = (static_cast<size_t>(nx) + 63) / 64;
  const size_t rows = static_cast<size_t>(ny);
  // zrows[(dz·NY + y)·XW + w]: bits over x (bit t = x − 64w) of z-slab 64·zw + dz, row y.
  std::vector<uint64_t> zrows(64 * rows * xwords);
  std::vector<uint8_t> slab(rows * static_cast<size_t>(nx));
  std::array<uint64_t, 64> block{};
  for (size_t zw = 0; zw < words; ++zw) {
    for (size_t xw = 0; xw < xwords; ++xw) {
      for (int y = 0; y < ny; ++y) {
        // block[t] = bits over z of column (64·xw + t, y), word zw; zero past x = NX − 1.
        for (int t = 0; t < 64; ++t) {
          const int x = static_cast<int>(64 * xw) + t;
          block[t] = x < nx ? grid.bits[grid.column_word(x, y) + zw] : 0;
        }
        transpose64(block);  // block[dz] = bits over x of row y in z-slab 64·zw + dz
        for (int dz = 0; dz < 64; ++dz) zrows[(dz * rows + y) * xwords + xw] = block[dz];
      }
    }
    for (int dz = 0; dz < bits_in_word(zw, nz); ++dz) {
      for (size_t y = 0; y < rows; ++y)
        expand_bits(&zrows[(dz * rows + y) * xwords], nx, &slab[y * nx]);
      out.write(slab.data(), slab.size());
    }
  }
  out.write("\n  </AppendedData>\n</VTKFile>\n");
}

/// Rejects grids whose storage does not match their dims, or bricks (a caller's bug, not input).
void check_grid(const VoxelGrid& grid) {
  const VoxelLattice& l = grid.lattice;
  if (!grid.whole() || l.dims[0] <= 0 || l.dims[1] <= 0 || l.dims[2] <= 0 ||
      grid.bits.size() != grid.word_count())
    throw PreconditionError("write_voxels: a whole grid of positive dims expected, got a " +
                            std::to_string(grid.nx()) + "x" + std::to_string(grid.ny()) + "x" +
                            std::to_string(grid.nz()) + " region holding " +
                            std::to_string(grid.bits.size()) + " words");
  if (!(l.spacing > 0) || !std::isfinite(l.spacing) || !std::isfinite(l.origin.x) ||
      !std::isfinite(l.origin.y) || !std::isfinite(l.origin.z))
    throw PreconditionError("write_voxels: origin and spacing must be finite, spacing > 0");
}

}  // namespace

bool is_voxel_extension(const fs::path& path) {
  const std::string ext = lower_extension(path);
  return ext == ".binvox" || ext == ".vti" || ext == ".npy" || ext == ".raw";
}

void write_voxels(const fs::path& path, const VoxelGrid& grid) {
  const std::string ext = lower_extension(path);
  if (!is_voxel_extension(path))
    throw InputError(path.string() + ": unsupported voxel format " +
                     quote(path.extension().string()) + " (expected .binvox, .vti, .npy, .raw)");
  check_grid(grid);
  if (ext == ".binvox" && !grid.lattice.cubic())
    throw InputError(path.string() + ": .binvox holds cubic grids only (dim N N N), got " +
                     std::to_string(grid.nx()) + "x" + std::to_string(grid.ny()) + "x" +
                     std::to_string(grid.nz()) + " (use .npy, .raw, .vti or .zarr)");
  // .raw and its sidecar are committed together: no .raw is left without its description, and
  // a failure leaves both old files as they were.
  OutputBatch batch;
  if (ext == ".raw") {
    fs::path sidecar = path;
    sidecar += ".json";
    write_file(path, [&](OutputFile& out) { write_xyz_bytes(out, grid); });
    write_file(sidecar, [&](OutputFile& out) { out.write(raw_sidecar(grid)); });
  } else if (ext == ".npy") {
    write_file(path, [&](OutputFile& out) { write_npy(out, grid); });
  } else if (ext == ".binvox") {
    write_file(path, [&](OutputFile& out) { write_binvox(out, grid); });
  } else {
    write_file(path, [&](OutputFile& out) { write_vti(out, grid); });
  }
  batch.commit();
}

}  // namespace cover

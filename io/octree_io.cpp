#include "cover/io/octree_io.h"

#include <algorithm>
#include <bit>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <string>
#include <system_error>
#include <vector>

#include "cover/io/atomic_file.h"
#include "cover/io/mesh_io.h"
#include "cover/solid/errors.h"

namespace cover {
namespace {

namespace fs = std::filesystem;

/// Writes the text produced by `emit` into a file; false on any I/O error.
bool write_text(const fs::path& file, const std::function<void(std::ostream&)>& emit) {
  std::ofstream out(file, std::ios::binary);
  if (!out) return false;
  emit(out);
  out.close();
  return !out.fail();
}

/// Shortest decimal text that reads back as the same value (finite values only).
template <class T>
std::string number(T value) {
  char buf[32];
  const auto result = std::to_chars(buf, buf + sizeof buf, value);
  return std::string(buf, result.ptr);
}

// ---- .htg: VTK XML HyperTreeGrid, file version 1.0 ----------------------------------------------
// One tree (Dimensions 2 2 2: one root cell over the cube). The tree is described breadth first:
// "Descriptor" holds one bit per vertex above the deepest level (1 = refined), "NbVerticesByLevel"
// the vertex count per depth, and the CellData arrays one value per vertex in the same order. The
// octree's node array is already in that order (octree.h). Large arrays are inline base64 binary
// (uncompressed: a UInt64 byte count, then the data, as one base64 stream, in the byte order the
// file declares: the machine's); a Bit array packs 8 values per byte, most significant bit first
// (vtkBitArray's layout).

/// Writes, in base64, the stream of an 8-byte UInt64 `size` (the machine's byte order) followed
/// by `size` bytes that fill(offset, count, dst) produces, a chunk at a time: nothing of the
/// size of the array is allocated and nothing is appended a character at a time (bunny00's
/// depth-10 tree has 48 MB of cell data).
void base64_payload(std::ostream& out, uint64_t size,
                    const std::function<void(size_t, size_t, uint8_t*)>& fill) {
  static constexpr char kDigits[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  constexpr size_t kChunk = size_t{3} << 16;  // raw bytes per chunk, a multiple of 3
  std::vector<uint8_t> raw(kChunk);
  std::string text(kChunk / 3 * 4, '\0');
  const uint64_t total = 8 + size;
  for (uint64_t at = 0; at < total; at += kChunk) {
    const size_t len = static_cast<size_t>(std::min<uint64_t>(kChunk, total - at));
    size_t k = 0;
    for (; k < len && at + k < 8; ++k) raw[k] = static_cast<uint8_t>(size >> (8 * (at + k)));
    if (k < len) fill(static_cast<size_t>(at + k - 8), len - k, raw.data() + k);
    char* o = text.data();
    for (size_t i = 0; i < len; i += 3) {
      const size_t n = std::min<size_t>(3, len - i);
      uint32_t v = uint32_t{raw[i]} << 16;
      if (n > 1) v |= uint32_t{raw[i + 1]} << 8;
      if (n > 2) v |= raw[i + 2];
      *o++ = kDigits[(v >> 18) & 63];
      *o++ = kDigits[(v >> 12) & 63];
      *o++ = n > 1 ? kDigits[(v >> 6) & 63] : '=';
      *o++ = n > 2 ? kDigits[v & 63] : '=';
    }
    out.write(text.data(), o - text.data());
  }
}

/// A DataArray whose body `body` writes (one line, after the indentation).
void data_array(std::ostream& out, const std::string& indent, const std::string& type,
                const std::string& name, size_t tuples, const std::string& format,
                const std::function<void(std::ostream&)>& body) {
  out << indent << "<DataArray type=\"" << type << "\" Name=\"" << name << "\" NumberOfTuples=\""
      << tuples << "\" format=\"" << format << "\">\n"
      << indent << "  ";
  body(out);
  out << "\n" << indent << "</DataArray>\n";
}

void data_array(std::ostream& out, const std::string& indent, const std::string& type,
                const std::string& name, size_t tuples, const std::string& format,
                const std::string& body) {
  data_array(out, indent, type, name, tuples, format, [&](std::ostream& o) { o << body; });
}

void write_htg(std::ostream& out, const Octree& tree) {
  const size_t n = tree.nodes.size();
  int levels = 0;
  std::vector<int64_t> per_level;
  for (const Octree::Node& node : tree.nodes) {
    levels = std::max(levels, node.depth + 1);
    per_level.resize(static_cast<size_t>(levels), 0);
    ++per_level[node.depth];
  }
  // Descriptor: the vertices above the deepest level (at least the root).
  const size_t described = std::max<size_t>(1, n - static_cast<size_t>(per_level.back()));
  std::vector<uint8_t> bits((described + 7) / 8, 0);
  for (size_t i = 0; i < described; ++i)
    if (tree.nodes[i].first_child != 0) bits[i / 8] |= static_cast<uint8_t>(0x80u >> (i % 8));
  std::string counts;
  for (size_t l = 0; l < per_level.size(); ++l) {
    if (l > 0) counts += ' ';
    counts += std::to_string(per_level[l]);
  }
  out << "<?xml version=\"1.0\"?>\n"
      << "<VTKFile type=\"HyperTreeGrid\" version=\"1.0\" byte_order=\""
      << (std::endian::native == std::endian::little ? "LittleEndian" : "BigEndian")
      << "\" header_type=\"UInt64\">\n"
      << "  <HyperTreeGrid BranchFactor=\"2\" TransposedRootIndexing=\"0\" "
         "Dimensions=\"2 2 2\">\n"
      << "    <Grid>\n";
  const char* axes[3] = {"XCoordinates", "YCoordinates", "ZCoordinates"};
  for (int a = 0; a < 3; ++a)
    data_array(out, "      ", "Float64", axes[a], 2, "ascii",
               number(tree.bounds.min[a]) + " " + number(tree.bounds.min[a] + tree.bounds.size));
  out << "    </Grid>\n"
      << "    <Trees>\n"
      << "      <Tree Index=\"0\" NumberOfLevels=\"" << levels << "\" NumberOfVertices=\"" << n
      << "\">\n";
  data_array(out, "        ", "Bit", "Descriptor", described, "binary", [&](std::ostream& o) {
    base64_payload(o, bits.size(), [&](size_t at, size_t count, uint8_t* dst) {
      std::memcpy(dst, bits.data() + at, count);
    });
  });
  data_array(out, "        ", "Int64", "NbVerticesByLevel", per_level.size(), "ascii", counts);
  out << "        <CellData>\n";
  data_array(out, "          ", "UInt8", "state", n, "binary", [&](std::ostream& o) {
    base64_payload(o, n, [&](size_t at, size_t count, uint8_t* dst) {
      for (size_t i = 0; i < count; ++i) dst[i] = static_cast<uint8_t>(tree.nodes[at + i].state);
    });
  });
  data_array(out, "          ", "Float32", "occupancy", n, "binary", [&](std::ostream& o) {
    base64_payload(o, n * sizeof(float), [&](size_t at, size_t count, uint8_t* dst) {
      // Bytes at .. at + count of the floats, in the machine's order.
      for (size_t i = 0; i < count; ++i) {
        const size_t byte = at + i;
        const float value = tree.nodes[byte / sizeof(float)].occupancy;
        dst[i] = reinterpret_cast<const uint8_t*>(&value)[byte % sizeof(float)];
      }
    });
  });
  out << "        </CellData>\n"
      << "      </Tree>\n"
      << "    </Trees>\n"
      << "  </HyperTreeGrid>\n"
      << "</VTKFile>\n";
}

// ---- .bt: OctoMap binary tree -------------------------------------------------------------------
// Notation: res = h = the finest cell size; OctoMap's key k (0 ≤ k < 2^16 per axis) is the world
// interval [(k − 2^15)·res, (k − 2^15 + 1)·res); an OctoMap node of depth t (0..16) spans S =
// 2^(16−t) keys per axis from a multiple of S. The cube's min is m·res (m = min/res, a whole
// number, checked), so Cover's cell (i, j, k) of depth d spans the keys b + (i, j, k)·2^(D−d) +
// [0, 2^(D−d)), b = m + 2^15: its world place. b need not be a multiple of the cell's span, so a
// Cover cell may straddle OctoMap nodes: the OctoMap tree is walked from its root, and for each
// node the Cover nodes meeting it at its scale ("refs": Cover nodes of span ≤ S, or leaves, whose
// parent spans more; at most 8) tell its code: a node inside the cube whose refs all have one
// uniform code (every leaf below them occupied, or every one free) is a leaf of that code; a
// node outside the cube is absent; any other is resolved from its 8 children, bottom-up, and
// becomes a leaf when they are leaves of one code (a ref may reach beyond the node, so uniform
// refs are sufficient, not necessary). The result is the canonical pruned tree (every node whose
// 8 children are leaves of one code is a leaf; OctoMap's root is always inner), kept as its inner
// nodes, then written depth-first, as OcTree::writeBinary does: per inner node 2 bytes, 2 bits
// per child (01 occupied leaf, 10 free leaf, 11 inner, 00 none), then its inner children. The
// tests compare the bytes with liboctomap's own tree of the same leaves, fully pruned.

/// Codes: 0 none, 1 occupied leaf, 2 free leaf, 3 inner.
struct BtKeys {
  std::array<int64_t, 3> base;  ///< b: the key of the cube's min corner
  int depth;                    ///< D
};

/// b of a .bt of the cube `bounds` at `depth`; InputError naming `path` when the cube is not on
/// OctoMap's grid.
BtKeys bt_keys(const fs::path& path, const VoxelBounds& bounds, int depth) {
  const double res = std::ldexp(bounds.size, -depth);
  const int64_t span = int64_t{1} << depth;
  BtKeys keys{{0, 0, 0}, depth};
  const char* axes = "xyz";
  for (int a = 0; a < 3; ++a) {
    const double q = bounds.min[a] / res;
    if (!(std::abs(q) <= 65536) || q != std::nearbyint(q))
      throw InputError(path.string() +
                       ": OctoMap .bt puts cells at whole multiples of the "
                       "resolution size/2^depth = " +
                       number(res) + " from the origin; the cube's " + axes[a] + "min " +
                       number(bounds.min[a]) + " is " + number(q) + " of them (give " +
                       parameter("bounds") +
                       " with xmin, ymin, zmin whole multiples of "
                       "size/2^depth, or no " +
                       parameter("bounds") + ")");
    keys.base[a] = static_cast<int64_t>(q) + 32768;
    if (keys.base[a] < 0 || keys.base[a] + span > 65536)
      throw InputError(
          path.string() + ": OctoMap .bt keys reach ±32768 cells of size " + number(res) + " (±" +
          number(32768 * res) + ") from the origin; the cube's " + axes[a] + " range [" +
          number(bounds.min[a]) + ", " + number(bounds.min[a] + bounds.size) +
          "] is outside (use a smaller " + parameter("depth") + ", whose cells are larger)");
  }
  return keys;
}

/// Per Cover node: 1 if every leaf below it (itself, for a leaf) is occupied, 2 if every one is
/// free, 3 otherwise.
std::vector<uint8_t> bt_uniform_codes(const Octree& tree, double threshold) {
  std::vector<uint8_t> code(tree.nodes.size());
  for (size_t i = tree.nodes.size(); i-- > 0;) {  // breadth-first: children after parents
    const Octree::Node& node = tree.nodes[i];
    if (node.first_child == 0) {
      const bool occupied = node.state == CellState::kFull ||
                            (node.state == CellState::kPartial && node.occupancy >= threshold);
      code[i] = occupied ? 1 : 2;
      continue;
    }
    code[i] = code[node.first_child];
    for (uint32_t k = 1; k < 8; ++k)
      if (code[node.first_child + k] != code[i]) code[i] = 3;
  }
  return code;
}

/// A Cover node with its key box [lo, lo + span) per axis.
struct BtRef {
  uint32_t node;
  int64_t span;
  std::array<int64_t, 3> lo;
};

/// At most 8 refs (see above).
struct BtRefs {
  std::array<BtRef, 8> at;
  int count = 0;
};

/// An inner node of the OctoMap tree: its children's codes and, for inner children, their
/// records.
struct BtInner {
  uint8_t codes[8];
  uint32_t child[8];
};

class BtWriter {
 public:
  BtWriter(const Octree& tree, const BtKeys& keys, double threshold)
      : tree_(tree), keys_(keys), uniform_(bt_uniform_codes(tree, threshold)) {}

  /// The data section; `count` gets OctoMap's node count.
  std::string write(uint64_t& count) {
    BtRefs root;
    root.at[0] = {0, int64_t{1} << keys_.depth, keys_.base};
    root.count = 1;
    inner_.reserve(tree_.nodes.size() / 4);
    uint32_t record = 0;
    resolve(std::array<int64_t, 3>{0, 0, 0}, int64_t{1} << 16, root, true, record);
    count = 1;
    std::string out;
    out.reserve(2 * inner_.size());
    emit(record, out, count);
    return out;
  }

 private:
  static bool meets(const BtRef& r, const std::array<int64_t, 3>& o, int64_t size) {
    for (int a = 0; a < 3; ++a)
      if (!(r.lo[a] < o[a] + size && o[a] < r.lo[a] + r.span)) return false;
    return true;
  }

  /// Adds `r` (or, when it spans more than `size` and is inner, its children meeting the box)
  /// to `refs`.
  void add(const BtRef& r, const std::array<int64_t, 3>& o, int64_t size, BtRefs& refs) const {
    if (!meets(r, o, size)) return;
    const uint32_t child = tree_.nodes[r.node].first_child;
    if (child == 0 || r.span <= size) {  // distinct refs give distinct nodes: no duplicate
      if (refs.count == 8) throw InternalError("write_octree: more than 8 refs for a .bt node");
      refs.at[refs.count++] = r;
      return;
    }
    const int64_t half = r.span / 2;
    for (uint32_t k = 0; k < 8; ++k)
      add({child + k,
           half,
           {r.lo[0] + (k & 1) * half, r.lo[1] + ((k >> 1) & 1) * half,
            r.lo[2] + ((k >> 2) & 1) * half}},
          o, size, refs);
  }

  bool inside_cube(const std::array<int64_t, 3>& o, int64_t size) const {
    const int64_t span = int64_t{1} << keys_.depth;
    for (int a = 0; a < 3; ++a)
      if (o[a] < keys_.base[a] || o[a] + size > keys_.base[a] + span) return false;
    return true;
  }

  /// The code of the OctoMap node at `o` of span `size` whose refs are `refs`, bottom-up: 0
  /// outside the cube; a leaf code when every Cover leaf it meets has it (at once when its refs
  /// are uniform, else when its 8 children came out as leaves of one code; never the root);
  /// else 3, with its record in `record`.
  uint8_t resolve(const std::array<int64_t, 3>& o, int64_t size, const BtRefs& refs, bool root,
                  uint32_t& record) {
    if (refs.count == 0) return 0;
    if (!root && inside_cube(o, size)) {
      const uint8_t first = uniform_[refs.at[0].node];
      bool same = first != 3;
      for (int i = 1; i < refs.count && same; ++i) same = uniform_[refs.at[i].node] == first;
      if (same) return first;
    }
    const int64_t half = size / 2;
    BtInner node{};
    for (uint32_t k = 0; k < 8; ++k) {
      const std::array<int64_t, 3> c = {o[0] + (k & 1) * half, o[1] + ((k >> 1) & 1) * half,
                                        o[2] + ((k >> 2) & 1) * half};
      BtRefs child;
      for (int i = 0; i < refs.count; ++i) add(refs.at[i], c, half, child);
      node.codes[k] = resolve(c, half, child, false, node.child[k]);
    }
    if (!root && (node.codes[0] == 1 || node.codes[0] == 2) &&
        std::all_of(node.codes + 1, node.codes + 8, [&](uint8_t c) { return c == node.codes[0]; }))
      return node.codes[0];  // pruned: 8 leaves of one code
    record = static_cast<uint32_t>(inner_.size());
    inner_.push_back(node);
    return 3;
  }

  /// Writes inner node `record` and its inner descendants depth-first (OcTree::writeBinary's
  /// order): 2 bytes, 2 bits per child (bit 2c: free or inner, bit 2c + 1: occupied or inner).
  void emit(uint32_t record, std::string& out, uint64_t& count) const {
    const BtInner& node = inner_[record];
    uint8_t bytes[2] = {0, 0};
    for (int c = 0; c < 8; ++c) {
      const uint8_t code = node.codes[c];
      const uint8_t bits = code == 1 ? 2 : (code == 2 ? 1 : code);
      bytes[c / 4] |= static_cast<uint8_t>(bits << (2 * (c % 4)));
      if (code != 0) ++count;
    }
    out.push_back(static_cast<char>(bytes[0]));
    out.push_back(static_cast<char>(bytes[1]));
    for (int c = 0; c < 8; ++c)
      if (node.codes[c] == 3) emit(node.child[c], out, count);
  }

  const Octree& tree_;
  const BtKeys& keys_;
  std::vector<uint8_t> uniform_;
  std::vector<BtInner> inner_;  ///< inner nodes, children before parents
};

bool write_bt(const fs::path& file, const Octree& tree, const BtKeys& keys, double threshold) {
  uint64_t count = 0;
  const std::string data = BtWriter(tree, keys, threshold).write(count);
  std::ofstream stream(file, std::ios::binary);
  if (!stream) return false;
  // OcTree::writeBinary's header (AbstractOccupancyOcTree::binaryFileHeader, getTreeType()),
  // the resolution with all 17 digits.
  stream.precision(17);
  stream << "# Octomap OcTree binary file\n# (written by Cover)\nid OcTree\nsize " << count
         << "\nres " << tree.cell_size(tree.depth) << "\ndata\n";
  stream.write(data.data(), static_cast<std::streamsize>(data.size()));
  stream.close();
  return !stream.fail();
}

// ---- .json summary ------------------------------------------------------------------------------

void write_json(std::ostream& out, const Octree& tree, double threshold) {
  const auto leaves = tree.leaf_counts();
  const Vec3& m = tree.bounds.min;
  out << "{\n  \"bounds\": {\"min\": [" << number(m.x) << ", " << number(m.y) << ", " << number(m.z)
      << "], \"size\": " << number(tree.bounds.size) << "},\n"
      << "  \"depth\": " << tree.depth << ",\n"
      << "  \"nodes\": " << tree.nodes.size() << ",\n"
      << "  \"leaves\": {\"empty\": " << leaves[0] << ", \"full\": " << leaves[1]
      << ", \"partial\": " << leaves[2] << "},\n"
      << "  \"threshold\": " << number(threshold) << ",\n"
      << "  \"cell_fields\": [\"depth\", \"i\", \"j\", \"k\", \"state\", \"occupancy\"],\n"
      << "  \"cell_rule\": \"cell = [min + (i, j, k)*s, min + (i+1, j+1, k+1)*s], s = size/2^depth;"
         " state 0 empty, 1 full, 2 partial\",\n"
      << "  \"cells\": [";
  // One short array per leaf cell, in node order (about 25 bytes a cell: the integer corner at
  // its depth instead of 17-digit coordinates, which would take 844 MB for armadillo at depth
  // 10). Streamed: nothing but the current line is held.
  // Formatted with to_chars into 1 MiB chunks, not with snprintf and a stream write per cell
  // (bunny00 at depth 10 has 7.1 M leaves).
  bool first = true;
  std::string chunk;
  chunk.reserve(size_t{1} << 20);
  char line[128];
  for (const Octree::Node& node : tree.nodes) {
    if (node.first_child != 0) continue;
    const auto& ijk = node.cell;
    char* p = line;
    char* const end = line + sizeof line;
    *p++ = first ? '\n' : ',';
    if (!first) *p++ = '\n';
    *p++ = '[';
    for (const int v :
         {int{node.depth}, int{ijk[0]}, int{ijk[1]}, int{ijk[2]}, static_cast<int>(node.state)}) {
      p = std::to_chars(p, end, v).ptr;
      *p++ = ',';
    }
    p = std::to_chars(p, end - 1, node.occupancy).ptr;
    *p++ = ']';
    chunk.append(line, p);
    if (chunk.size() > (size_t{1} << 20) - sizeof line) {
      out.write(chunk.data(), static_cast<std::streamsize>(chunk.size()));
      chunk.clear();
    }
    first = false;
  }
  out.write(chunk.data(), static_cast<std::streamsize>(chunk.size()));
  out << (first ? "]\n}\n" : "\n]\n}\n");
}

}  // namespace

VoxelBounds octomap_bounds(const Bbox& box, int depth) {
  if (depth < 1 || depth > 16)
    throw PreconditionError("octomap_bounds: depth " + std::to_string(depth) + " is not 1 to 16");
  const Vec3 lo = box.empty() ? Vec3{-0.5, -0.5, -0.5} : box.min;
  double extent = 0;
  if (!box.empty())
    extent = std::max({box.max.x - box.min.x, box.max.y - box.min.y, box.max.z - box.min.z});
  if (!(extent > 0) || !std::isfinite(extent)) extent = 1;
  // n cells of side h from m·h hold [lo, hi] with `margin` cells per side when
  // m ≤ floor(lo/h) − margin and m + n ≥ ceil(hi/h) + margin, which needs (n − 2·margin)·h ≥
  // extent; OctoMap's keys need −2^15 ≤ m ≤ 2^15 − n. h = q·2^j with q ≤ 16 (4 significant
  // bits: m·h, min + i·h and OctoMap's (k − 2^15 + 1/2)·h are exact): the smallest such for
  // which some m exists, tried upwards from extent/(n − 2·margin).
  const double n = std::ldexp(1.0, depth);
  const int margin = depth >= 2 ? 1 : 0;
  const Vec3 hi = box.empty() ? Vec3{0.5, 0.5, 0.5} : box.max;
  int e = 0;
  const double f = std::frexp(extent / (n - 2 * margin), &e);  // = f·2^e, f in [0.5, 1)
  double q = std::ceil(16 * f);                                // h = q·2^(e − 4), q in 8..16
  for (;; q == 16 ? (q = 9, ++e) : ++q) {
    const double h = std::ldexp(q, e - 4);
    VoxelBounds bounds;
    bounds.size = n * h;
    bool fits = true;
    double m[3];
    for (int a = 0; a < 3; ++a) {
      // floor(lo/h) and ceil(hi/h) of the real quotients (k·h is exact; the division rounds).
      double below = std::floor(lo[a] / h), above = std::ceil(hi[a] / h);
      if (below * h > lo[a]) --below;
      if (above * h < hi[a]) ++above;
      const double top = std::min(below - margin, 32768 - n);
      const double bottom = std::max(above + margin - n, -32768.0);
      fits = fits && bottom <= top;
      m[a] = top;
    }
    if (!fits) continue;
    bounds.min = {m[0] * h, m[1] * h, m[2] * h};
    return bounds;
  }
}

void check_octomap_cube(const std::filesystem::path& path, const VoxelBounds& bounds, int depth) {
  bt_keys(path, bounds, depth);
}

bool is_octree_extension(const std::filesystem::path& path) {
  const std::string ext = lower_extension(path);
  return ext == ".htg" || ext == ".bt" || ext == ".json";
}

void write_octree(const std::filesystem::path& path, const Octree& tree, double threshold) {
  if (!(threshold >= 0 && threshold <= 1))
    throw InputError(parameter("threshold") + ": expected a number from 0 to 1, got " +
                     std::to_string(threshold));
  if (tree.nodes.empty()) throw InputError(path.string() + ": empty octree");
  const std::string ext = lower_extension(path);
  if (ext == ".htg") {
    write_atomically(
        path,
        [&](const fs::path& tmp) {
          return write_text(tmp, [&](std::ostream& out) { write_htg(out, tree); });
        },
        "the octree");
  } else if (ext == ".json") {
    write_atomically(
        path,
        [&](const fs::path& tmp) {
          return write_text(tmp, [&](std::ostream& out) { write_json(out, tree, threshold); });
        },
        "the octree");
  } else if (ext == ".bt") {
    if (tree.depth < 1 || tree.depth > 16)
      throw InputError(path.string() + ": OctoMap .bt needs a depth from 1 to 16, got " +
                       std::to_string(tree.depth));
    const BtKeys keys = bt_keys(path, tree.bounds, tree.depth);
    write_atomically(
        path, [&](const fs::path& tmp) { return write_bt(tmp, tree, keys, threshold); },
        "the octree");
  } else {
    throw InputError(path.string() + ": unsupported octree format (expected .htg, .bt, .json)");
  }
}

}  // namespace cover

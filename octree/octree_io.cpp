#include "octree/octree_io.h"

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

#include "solid/atomic_file.h"
#include "solid/errors.h"
#include "solid/mesh_io.h"

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
/// size of the array is allocated (bunny00's depth-10 tree: 48 MB of cell data, written in
/// 0.66 s through whole-array copies and a per-character append, 0.2 s this way).
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
// OctoMap's voxels are the cells of a grid through the origin with 2^16 keys per axis and no
// origin field, so the cube is written centred on the origin (x_octomap = x − cube centre): cell
// (i, j, k) of depth d then spans the keys 2^15 − 2^(D−1) + i·2^(D−d) + [0, 2^(D−d)), a node of
// OctoMap depth 16 − (D − d). For D < 16 the root cell straddles key 2^15 on every axis and is no
// OctoMap node: OctoMap's root has 8 children, and child o reaches the depth-1 cell o through a
// chain of single children (index o's complement: the corner at the centre) down to depth
// 17 − D. A root leaf is written as its 8 children.
// Written directly, as liboctomap's OcTree::writeBinary would write the tree it builds from these
// leaves (to maximum likelihood, then prune(): bottom-up, a node whose 8 children are leaves of
// one state becomes a leaf, level by level from depth 15, stopping at the first level where none
// does, the root never), node by node depth-first: per node 2 bytes, 2 bits per child (01
// occupied leaf, 10 free leaf, 11 inner, 00 none), then its inner children. Why not liboctomap:
// its tree, built leaf by leaf, took 3.3 s for bunny00 at depth 10 (9.5 M nodes) against a
// 1 s build; this writes it in a single pass over the nodes. The tests compare the bytes with
// liboctomap's.

/// Per node, its OctoMap child code after pruning: 1 occupied leaf, 2 free leaf, 3 inner.
std::vector<uint8_t> bt_codes(const Octree& tree, double threshold) {
  std::vector<uint8_t> code(tree.nodes.size());
  for (size_t i = 0; i < tree.nodes.size(); ++i) {
    const Octree::Node& node = tree.nodes[i];
    const bool occupied = node.state == CellState::kFull ||
                          (node.state == CellState::kPartial && node.occupancy >= threshold);
    code[i] = node.first_child != 0 ? 3 : (occupied ? 1 : 2);
  }
  // prune(): depth d of the tree is OctoMap depth 16 − D + d; from d = D − 1 (OctoMap 15) up to
  // d = 1, stopping at the first depth that prunes nothing (above d = 1 lie the chains and the
  // root, never pruned). Nodes are in breadth-first order, so depth d is one contiguous run.
  std::vector<size_t> first(tree.depth + 2, tree.nodes.size());
  for (size_t i = tree.nodes.size(); i-- > 0;) first[tree.nodes[i].depth] = i;
  for (int d = tree.depth; d > 0; --d) first[d - 1] = std::min(first[d - 1], first[d]);
  for (int d = tree.depth - 1; d >= 1; --d) {
    size_t pruned = 0;
    for (size_t i = first[d]; i < first[d + 1]; ++i) {
      const uint32_t c = tree.nodes[i].first_child;
      if (c == 0 || code[c] == 3) continue;
      bool same = true;
      for (uint32_t k = 1; k < 8 && same; ++k) same = code[c + k] == code[c];
      if (!same) continue;
      code[i] = code[c];
      ++pruned;
    }
    if (pruned == 0) break;
  }
  return code;
}

/// The 2 bytes of an OctoMap node whose children have the codes children[0..7].
void bt_node_bytes(const uint8_t (&children)[8], std::string& out) {
  uint8_t bytes[2] = {0, 0};
  for (int c = 0; c < 8; ++c) {
    // bit 2i: free or inner, bit 2i + 1: occupied or inner (code 1 occupied, 2 free, 3 inner).
    const uint8_t bits = children[c] == 1 ? 2 : (children[c] == 2 ? 1 : children[c]);
    bytes[c / 4] |= static_cast<uint8_t>(bits << (2 * (c % 4)));
  }
  out.push_back(static_cast<char>(bytes[0]));
  out.push_back(static_cast<char>(bytes[1]));
}

/// Node `i` (inner after pruning) and its inner descendants, depth-first.
void bt_write_node(const Octree& tree, const std::vector<uint8_t>& code, uint32_t i,
                   std::string& out, uint64_t& count) {
  const uint32_t c = tree.nodes[i].first_child;
  uint8_t children[8];
  for (uint32_t k = 0; k < 8; ++k) children[k] = code[c + k];
  bt_node_bytes(children, out);
  count += 8;
  for (uint32_t k = 0; k < 8; ++k)
    if (code[c + k] == 3) bt_write_node(tree, code, c + k, out, count);
}

bool write_bt(const fs::path& file, const Octree& tree, double threshold) {
  const int depth = tree.depth;
  const std::vector<uint8_t> code = bt_codes(tree, threshold);
  const Octree::Node& root = tree.nodes[0];
  std::string data;
  data.reserve(2 * tree.nodes.size() / 8 + 64);
  uint64_t count = 1;  // OctoMap's nodes: its root, then 8 per inner node
  // The depth-1 cells' codes (a root leaf: 8 leaves of its state).
  uint8_t top[8];
  for (uint32_t o = 0; o < 8; ++o) top[o] = root.first_child != 0 ? code[root.first_child + o]
                                                                    : (code[0] == 1 ? 1 : 2);
  if (depth == 16) {
    bt_node_bytes(top, data);
    count += 8;
    for (uint32_t o = 0; o < 8; ++o)
      if (top[o] == 3) bt_write_node(tree, code, root.first_child + o, data, count);
  } else {
    const uint8_t inner[8] = {3, 3, 3, 3, 3, 3, 3, 3};
    bt_node_bytes(inner, data);
    count += 8;
    for (uint32_t o = 0; o < 8; ++o) {
      // The chain of octant o: OctoMap depths 1 .. 16 − D, each node's one child at index ~o.
      for (int t = 1; t <= 16 - depth; ++t) {
        uint8_t one[8] = {0, 0, 0, 0, 0, 0, 0, 0};
        one[~o & 7] = t < 16 - depth ? 3 : top[o];
        bt_node_bytes(one, data);
        ++count;
      }
      if (top[o] == 3) bt_write_node(tree, code, root.first_child + o, data, count);
    }
  }
  std::ofstream stream(file, std::ios::binary);
  if (!stream) return false;
  // OcTree::writeBinary's header (AbstractOccupancyOcTree::binaryFileHeader, getTreeType()),
  // the resolution with all 17 digits.
  stream.precision(17);
  stream << "# Octomap OcTree binary file\n# (written by Cover)\nid OcTree\nsize " << count
         << "\nres " << tree.cell_size(depth) << "\ndata\n";
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
  // its depth instead of 17-digit coordinates; armadillo at depth 10 took 844 MB as objects with
  // coordinates). Streamed: nothing but the current line is held.
  // Formatted with to_chars into 1 MiB chunks (snprintf and a stream write per cell took
  // 1.2 s for bunny00's 7.1 M leaves at depth 10).
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
    for (const int v : {int{node.depth}, int{ijk[0]}, int{ijk[1]}, int{ijk[2]},
                        static_cast<int>(node.state)}) {
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

bool is_octree_extension(const std::filesystem::path& path) {
  const std::string ext = lower_extension(path);
  return ext == ".htg" || ext == ".bt" || ext == ".json";
}

void write_octree(const std::filesystem::path& path, const Octree& tree, double threshold) {
  if (!(threshold >= 0 && threshold <= 1))
    throw InputError("--threshold: expected a number from 0 to 1, got " +
                     std::to_string(threshold));
  if (tree.nodes.empty()) throw InputError(path.string() + ": empty octree");
  const std::string ext = lower_extension(path);
  if (ext == ".htg") {
    write_atomically(path, [&](const fs::path& tmp) {
      return write_text(tmp, [&](std::ostream& out) { write_htg(out, tree); });
    }, "the octree");
  } else if (ext == ".json") {
    write_atomically(path, [&](const fs::path& tmp) {
      return write_text(tmp, [&](std::ostream& out) { write_json(out, tree, threshold); });
    }, "the octree");
  } else if (ext == ".bt") {
    if (tree.depth < 1 || tree.depth > 16)
      throw InputError(path.string() + ": OctoMap .bt needs a depth from 1 to 16, got " +
                       std::to_string(tree.depth));
    write_atomically(path, [&](const fs::path& tmp) { return write_bt(tmp, tree, threshold); }, "the octree");
  } else {
    throw InputError(path.string() + ": unsupported octree format (expected .htg, .bt, .json)");
  }
}

}  // namespace cover

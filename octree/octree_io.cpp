#include "octree/octree_io.h"

#include <octomap/OcTree.h>

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

std::string base64(const std::vector<uint8_t>& bytes) {
  static constexpr char kDigits[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (size_t i = 0; i < bytes.size(); i += 3) {
    const size_t n = std::min<size_t>(3, bytes.size() - i);
    uint32_t v = uint32_t{bytes[i]} << 16;
    if (n > 1) v |= uint32_t{bytes[i + 1]} << 8;
    if (n > 2) v |= bytes[i + 2];
    out += kDigits[(v >> 18) & 63];
    out += kDigits[(v >> 12) & 63];
    out += n > 1 ? kDigits[(v >> 6) & 63] : '=';
    out += n > 2 ? kDigits[v & 63] : '=';
  }
  return out;
}

/// Inline binary payload: the byte count (UInt64) followed by `data`, in the machine's order.
std::string binary_payload(const void* data, size_t size) {
  std::vector<uint8_t> bytes(8 + size);
  const uint64_t count = size;
  std::memcpy(bytes.data(), &count, 8);
  if (size > 0) std::memcpy(bytes.data() + 8, data, size);
  return base64(bytes);
}

void data_array(std::ostream& out, const std::string& indent, const std::string& type,
                const std::string& name, size_t tuples, const std::string& format,
                const std::string& body) {
  out << indent << "<DataArray type=\"" << type << "\" Name=\"" << name << "\" NumberOfTuples=\""
      << tuples << "\" format=\"" << format << "\">\n"
      << indent << "  " << body << "\n"
      << indent << "</DataArray>\n";
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
  std::vector<uint8_t> state(n);
  std::vector<float> occupancy(n);
  for (size_t i = 0; i < n; ++i) {
    state[i] = static_cast<uint8_t>(tree.nodes[i].state);
    occupancy[i] = tree.nodes[i].occupancy;
  }
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
  data_array(out, "        ", "Bit", "Descriptor", described, "binary",
             binary_payload(bits.data(), bits.size()));
  data_array(out, "        ", "Int64", "NbVerticesByLevel", per_level.size(), "ascii", counts);
  out << "        <CellData>\n";
  data_array(out, "          ", "UInt8", "state", n, "binary", binary_payload(state.data(), n));
  data_array(out, "          ", "Float32", "occupancy", n, "binary",
             binary_payload(occupancy.data(), n * sizeof(float)));
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
// OctoMap depth 16 − (D − d). The root cell (d = 0 < D) is no OctoMap node; a root leaf is written
// as its 8 children.

/// An OcTree whose leaves are placed at any depth (OctoMap's updates address finest voxels).
class OcTreeWriter : public octomap::OcTree {
 public:
  explicit OcTreeWriter(double resolution) : octomap::OcTree(resolution) {}

  /// Makes the node at `depth` (0 = root) over `key` a leaf with value `log_odds`.
  void set_leaf(const octomap::OcTreeKey& key, unsigned depth, float log_odds) {
    if (root == nullptr) {
      root = new octomap::OcTreeNode();
      ++tree_size;
    }
    octomap::OcTreeNode* node = root;
    for (unsigned d = 0; d < depth; ++d) {
      const unsigned pos = octomap::computeChildIdx(key, static_cast<int>(tree_depth - 1 - d));
      node = nodeChildExists(node, pos) ? getNodeChild(node, pos) : createNodeChild(node, pos);
    }
    node->setLogOdds(log_odds);
  }

  /// The maximum-likelihood, pruned tree in OctoMap's binary format, as writeBinary() writes it
  /// but without liboctomap's progress line on stderr; the resolution with all 17 digits.
  bool write(std::ostream& s) {
    updateInnerOccupancy();
    toMaxLikelihood();
    prune();
    s.precision(17);
    s << binaryFileHeader << "\n# (written by Cover)\nid " << getTreeType() << "\nsize " << size()
      << "\nres " << getResolution() << "\ndata\n";
    writeBinaryData(s);
    return s.good();
  }
};

bool write_bt(const fs::path& file, const Octree& tree, double threshold) {
  const int depth = tree.depth;
  OcTreeWriter out(tree.cell_size(depth));
  const uint32_t base = (1u << 15) - (1u << (depth - 1));
  // Integer corners of every node, from the parent's (children follow their parent).
  std::vector<std::array<uint32_t, 3>> coord(tree.nodes.size());
  for (size_t i = 0; i < tree.nodes.size(); ++i) {
    const Octree::Node& node = tree.nodes[i];
    if (node.first_child != 0) {
      for (uint32_t c = 0; c < 8; ++c)
        coord[node.first_child + c] = {2 * coord[i][0] + (c & 1), 2 * coord[i][1] + ((c >> 1) & 1),
                                       2 * coord[i][2] + ((c >> 2) & 1)};
      continue;
    }
    const bool occupied = node.state == CellState::kFull ||
                          (node.state == CellState::kPartial && node.occupancy >= threshold);
    const float value = occupied ? out.getClampingThresMaxLog() : out.getClampingThresMinLog();
    const auto place = [&](const std::array<uint32_t, 3>& at, int d) {
      const uint32_t step = 1u << (depth - d);
      const octomap::OcTreeKey key(static_cast<uint16_t>(base + at[0] * step),
                                   static_cast<uint16_t>(base + at[1] * step),
                                   static_cast<uint16_t>(base + at[2] * step));
      out.set_leaf(key, static_cast<unsigned>(16 - (depth - d)), value);
    };
    if (node.depth > 0)
      place(coord[i], node.depth);
    else
      for (uint32_t c = 0; c < 8; ++c) place({c & 1, (c >> 1) & 1, (c >> 2) & 1}, 1);
  }
  std::ofstream stream(file, std::ios::binary);
  if (!stream || !out.write(stream)) return false;
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
  bool first = true;
  char line[128];
  for (const Octree::Node& node : tree.nodes) {
    if (node.first_child != 0) continue;
    const auto& ijk = node.cell;
    char* p = line;
    *p++ = first ? '\n' : ',';
    if (!first) *p++ = '\n';
    p += std::snprintf(p, 48, "[%d,%d,%d,%d,%d,", node.depth, int{ijk[0]}, int{ijk[1]},
                       int{ijk[2]}, static_cast<int>(node.state));
    p = std::to_chars(p, line + sizeof line - 1, node.occupancy).ptr;
    *p++ = ']';
    out.write(line, p - line);
    first = false;
  }
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

#include "cover/io/serialize.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <optional>
#include <tuple>
#include <utility>

#include "cover/field/field.h"
#include "cover/field/warp.h"
#include "cover/mesh/validate.h"
#include "cover/solid/errors.h"

namespace cover {
namespace {

static_assert(std::endian::native == std::endian::little, "the format is little-endian");
constexpr char kMagic[8] = {'C', 'O', 'V', 'E', 'R', 'S', 'O', 'L'};
constexpr uint32_t kVersion = 1;
constexpr uint32_t kFieldVersion = 2;  ///< solids with field leaves (format in serialize.h)
constexpr uint8_t kColourFlag = 16;    ///< a leaf's flag: its colour's 3 bytes follow

class Writer {
 public:
  template <typename T>
  void put(const T& v) {
    out_.append(reinterpret_cast<const char*>(&v), sizeof(T));
  }
  template <typename T>
  void put_array(const T* p, size_t n) {
    out_.append(reinterpret_cast<const char*>(p), n * sizeof(T));
  }
  void put_string(const std::string& s) {
    put(static_cast<uint32_t>(s.size()));
    out_ += s;
  }
  std::string take() { return std::move(out_); }

 private:
  std::string out_;
};

class Reader {
 public:
  Reader(std::string_view bytes, const std::string& what) : in_(bytes), what_(what) {}
  [[noreturn]] void fail(const std::string& why) const {
    throw InputError(what_ + ": not a Cover solid: " + why);
  }
  /// fail() naming the byte offset where the failed read began.
  [[noreturn]] void fail_here(const std::string& why) const {
    fail(why + " at byte " + std::to_string(pos_) + " of " + std::to_string(in_.size()));
  }
  template <typename T>
  T get() {
    need(sizeof(T), 1, "truncated");
    T v;
    std::memcpy(&v, in_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return v;
  }
  /// n values of T into `out` (resized only after the byte count is checked).
  template <typename Vector>
  void get_array(Vector& out, uint64_t n) {
    using T = typename Vector::value_type;
    need(sizeof(T), n, "truncated array");
    out.resize(n);
    if (n) std::memcpy(out.data(), in_.data() + pos_, n * sizeof(T));
    pos_ += n * sizeof(T);
  }
  std::string get_string() {
    const uint32_t n = get<uint32_t>();
    need(1, n, "truncated string");
    std::string s(in_.substr(pos_, n));
    pos_ += n;
    return s;
  }
  /// Fails unless `count` items of `size` bytes remain (no overflow: count is checked first).
  void need(size_t size, uint64_t count, const char* why) const {
    const uint64_t left = in_.size() - pos_;
    if (count > left / size) fail_here(why);
  }
  bool done() const { return pos_ == in_.size(); }
  /// Skips n bytes (checked by need() before).
  void skip(size_t n) { pos_ += n; }
  size_t pos() const { return pos_; }

 private:
  std::string_view in_;
  size_t pos_ = 0;
  const std::string& what_;
};

}  // namespace

std::string solid_to_bytes(const Solid& s) {
  Writer w;
  w.put_array(kMagic, 8);
  w.put(s.has_implicit_leaf() ? kFieldVersion : kVersion);
  w.put(static_cast<uint64_t>(s.vertices.size()));
  w.put(static_cast<uint64_t>(s.face_count()));
  w.put(static_cast<uint64_t>(s.face_vertices.size()));
  w.put(static_cast<uint64_t>(s.leaves.size()));
  w.put(static_cast<uint64_t>(s.tree.nodes.size()));
  w.put(s.tree.root);
  w.put_array(s.vertices.data(), s.vertices.size());
  w.put_array(s.face_start.data(), s.face_start.size());
  w.put_array(s.face_vertices.data(), s.face_vertices.size());
  w.put_array(s.face_leaf.data(), s.face_leaf.size());
  w.put_array(s.face_sign.data(), s.face_sign.size());
  for (const Leaf& leaf : s.leaves) {
    w.put_string(leaf.name);
    w.put_string(leaf.origin);
    w.put(leaf.first_face);
    w.put(leaf.face_count);
    w.put(leaf.first_vertex);
    w.put(leaf.vertex_count);
    w.put(static_cast<uint8_t>((leaf.flipped ? 1 : 0) | (leaf.open() ? 2 : 0) |
                               (leaf.is_field() ? 4 : 0) | (leaf.is_warp() ? 8 : 0) |
                               (leaf.colour ? kColourFlag : 0)));
    if (leaf.colour) w.put_array(leaf.colour->data(), 3);
  }
  for (const CsgNode& node : s.tree.nodes) {
    w.put(static_cast<uint8_t>(node.op));
    w.put(node.leaf);
    w.put(static_cast<uint32_t>(node.children.size()));
    w.put_array(node.children.data(), node.children.size());
  }
  if (!s.has_implicit_leaf()) return w.take();
  // Field leaves, in the order of their leaves (Leaf::field is that order: concatenation and
  // scenes number them so).
  for (const Leaf& leaf : s.leaves) {
    if (!leaf.is_field()) continue;
    const FieldLeaf& f = s.fields[leaf.field];
    w.put(static_cast<uint32_t>(f.primitives.size()));
    for (const FieldPrimitive& p : f.primitives) {
      w.put(static_cast<uint8_t>(p.kind));
      w.put(static_cast<uint32_t>(p.points.size()));
      w.put_array(p.points.data(), p.points.size());
      w.put(p.circle_radius);
      w.put(p.radius);
      w.put(p.influence);
      w.put(static_cast<int32_t>(p.exponent));
      w.put(static_cast<int32_t>(p.weight));
    }
  }
  for (const Leaf& leaf : s.leaves) {
    if (!leaf.is_warp()) continue;
    const WarpLeaf& x = s.warps[leaf.warp];
    w.put(static_cast<uint8_t>(x.kind));
    for (const Vec3& v : {x.point, x.direction, x.toward, x.frame[0], x.frame[1], x.frame[2]})
      w.put(v);
    for (double d :
         {x.degrees_per_unit, x.range[0], x.range[1], x.scale[0], x.scale[1], x.center, x.radius})
      w.put(d);
    const std::string child = solid_to_bytes(*x.child);
    w.put(static_cast<uint64_t>(child.size()));
    w.put_array(child.data(), child.size());
  }
  return w.take();
}

namespace {

std::string num(uint64_t v) { return std::to_string(v); }

/// "leaf L ('NAME')" for messages.
std::string leaf_label(const Solid& s, uint64_t l) {
  return "leaf " + num(l) + " ('" + s.leaves[l].name + "')";
}

/// The first edge {u, v} (u < v) of `mesh` traversed a different number of times in each
/// direction (face sides, false edges within one face included: they cancel), if any.
std::optional<std::pair<uint32_t, uint32_t>> unbalanced_edge(const PolygonMesh& mesh) {
  std::vector<std::tuple<uint32_t, uint32_t, int>> sides;  // (min, max, +1 for min → max)
  sides.reserve(mesh.face_vertices.size());
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    const auto face = mesh.face(f);
    for (size_t i = 0; i < face.size(); ++i) {
      const uint32_t a = face[i], b = face[(i + 1) % face.size()];
      if (a != b) sides.emplace_back(std::min(a, b), std::max(a, b), a < b ? 1 : -1);
    }
  }
  std::sort(sides.begin(), sides.end());
  for (size_t i = 0; i < sides.size();) {
    size_t j = i;
    int64_t net = 0;
    for (; j < sides.size() && std::get<0>(sides[j]) == std::get<0>(sides[i]) &&
           std::get<1>(sides[j]) == std::get<1>(sides[i]);
         ++j)
      net += std::get<2>(sides[j]);
    if (net != 0) return std::pair{std::get<0>(sides[i]), std::get<1>(sides[i])};
    i = j;
  }
  return std::nullopt;
}

/// A bound on the rounding error of signed_volume(mesh) (solid/measure.h: a Neumaier sum of
/// fan tetrahedra a·(b×c)/6 from the box centre): each term's vectors are at most the box
/// diagonal D long and are formed with a relative error of a few units in the last place, so
/// each term is off by less than 16u·D³/6 and the sum by less than T times that (T terms).
double volume_rounding_bound(const PolygonMesh& mesh) {
  Bbox box;
  size_t terms = 0;
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    const auto face = mesh.face(f);
    for (uint32_t v : face) box.add(mesh.vertices[v]);
    if (face.size() >= 3) terms += face.size() - 2;
  }
  if (box.empty()) return 0;
  const Vec3 d = box.max - box.min;
  const double diagonal = std::sqrt(dot(d, d));
  return static_cast<double>(terms) * 16 * std::numeric_limits<double>::epsilon() * diagonal *
         diagonal * diagonal;
}

/// A field leaf's primitives (format in serialize.h), checked as field::validate_placed does.
void read_field(Reader& r, FieldLeaf& f, const std::string& label) {
  const uint32_t n = r.get<uint32_t>();
  r.need(1 + 4 + 8 * 3 + 4 * 2, n, "truncated field");
  f.primitives.resize(n);
  for (FieldPrimitive& p : f.primitives) {
    const uint8_t kind = r.get<uint8_t>();
    if (kind > static_cast<uint8_t>(SkeletonKind::kMesh))
      r.fail_here(label + ": an unknown skeleton");
    p.kind = static_cast<SkeletonKind>(kind);
    const uint32_t points = r.get<uint32_t>();
    if (points > kMaxPolylinePoints) r.fail_here(label + ": too many skeleton points");
    r.get_array(p.points, points);
    p.circle_radius = r.get<double>();
    p.radius = r.get<double>();
    p.influence = r.get<double>();
    p.exponent = r.get<int32_t>();
    p.weight = r.get<int32_t>();
    if (p.kind == SkeletonKind::kMesh) p.mesh = index_skeleton_mesh(p.points);
  }
  if (const std::string problem = field::validate_placed(f); !problem.empty())
    r.fail(label + ": " + problem);
}

/// The checks of one leaf that loading makes (io/scene.h prepare_leaf, validate_mesh with
/// the loader's options): the open flag must be what the faces say (boundary edges), and a
/// closed leaf must be a consistently oriented 2-cycle (every edge balanced) with a signed
/// volume that is not negative beyond its rounding (outward), as prepare_leaf leaves it.
/// Fills leaf.boundary_edges from the faces.
void check_leaf(Solid& s, uint64_t l, bool flagged_open, const Reader& r) {
  Leaf& leaf = s.leaves[l];
  const PolygonMesh m = leaf_mesh(s, static_cast<uint32_t>(l));
  ValidateOptions vo;  // what loading validates (io/scene.cpp)
  vo.check_self_intersection = false;
  vo.full_report = false;
  const MeshReport report = validate_mesh(m, vo);
  if (flagged_open && report.boundary_edges == 0)
    r.fail(leaf_label(s, l) + ": flagged open, but its faces are closed (no boundary edge)");
  if (!flagged_open && report.boundary_edges > 0)
    r.fail(leaf_label(s, l) + ": flagged closed, but its faces have " +
           num(static_cast<uint64_t>(report.boundary_edges)) + " boundary edge(s)");
  leaf.boundary_edges = report.boundary_edges;
  if (report.boundary_edges > 0) return;  // open: inside where |w| > 1/2, either orientation
  if (!report.oriented || report.nonmanifold_edges > 0)
    if (const auto e = unbalanced_edge(m))
      r.fail(leaf_label(s, l) + ": edge " + num(e->first) + "-" + num(e->second) +
             " (leaf vertex indices) is not traversed equally often in each direction (not a "
             "consistently oriented closed surface)");
  if (report.volume < -volume_rounding_bound(m))
    r.fail(leaf_label(s, l) + ": inside-out (signed volume " + std::to_string(report.volume) +
           " < 0; a serialized leaf is outward)");
}

}  // namespace

namespace {

constexpr int kMaxWarpNesting = 64;

Solid read_solid(std::string_view bytes, const std::string& what, int depth);

/// A warp leaf (format in serialize.h), checked as field::validate checks it; its child read
/// by read_solid one level deeper. Returns the leaf's box.
Bbox read_warp(Reader& r, WarpLeaf& x, const std::string& label, const std::string& what,
               std::string_view bytes, int depth) {
  const uint8_t kind = r.get<uint8_t>();
  if (kind > static_cast<uint8_t>(WarpKind::kBend)) r.fail_here(label + ": an unknown warp");
  x.kind = static_cast<WarpKind>(kind);
  for (Vec3* v : {&x.point, &x.direction, &x.toward, &x.frame[0], &x.frame[1], &x.frame[2]})
    *v = r.get<Vec3>();
  for (double* d : {&x.degrees_per_unit, &x.range[0], &x.range[1], &x.scale[0], &x.scale[1],
                    &x.center, &x.radius})
    *d = r.get<double>();
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) {
      const double g = dot(x.frame[i], x.frame[k]);
      if (!(std::abs(g - (i == k ? 1.0 : 0.0)) <= 1e-6))
        r.fail(label + ": a warp frame that is not orthonormal");
    }
  const uint64_t n = r.get<uint64_t>();
  r.need(1, n, "truncated warp child");
  if (depth >= kMaxWarpNesting) r.fail(label + ": warps nested more than 64 deep");
  const size_t at = r.pos();
  Solid child = read_solid(bytes.substr(at, n), what + " (" + label + "'s child)", depth + 1);
  r.skip(n);
  const Bbox box = child.bbox();
  if (box.empty()) r.fail(label + ": a warp of an empty child");
  if (const std::string problem = field::validate(x, box); !problem.empty())
    r.fail(label + ": " + problem);
  x.child = std::make_shared<const Solid>(std::move(child));
  return field::forward_box(x, box);
}

}  // namespace

Solid solid_from_bytes(std::string_view bytes, const std::string& what) {
  return read_solid(bytes, what, 0);
}

namespace {

Solid read_solid(std::string_view bytes, const std::string& what, int depth) {
  Reader r(bytes, what);
  r.need(1, 8, "truncated");
  if (std::memcmp(bytes.data(), kMagic, 8) != 0) r.fail("wrong magic (the first 8 bytes)");
  r.get<uint64_t>();  // the magic
  const uint32_t version = r.get<uint32_t>();
  if (version != kVersion && version != kFieldVersion)
    r.fail("unsupported version (bytes 8 to 11)");
  const uint64_t nv = r.get<uint64_t>(), nf = r.get<uint64_t>(), ni = r.get<uint64_t>(),
                 nl = r.get<uint64_t>(), nn = r.get<uint64_t>();
  const uint32_t root = r.get<uint32_t>();
  if (nv > UINT32_MAX || nf >= UINT32_MAX || ni > UINT32_MAX || nl > UINT32_MAX || nn > UINT32_MAX)
    r.fail("counts beyond 32-bit indices (bytes 12 to 51)");
  Solid s;
  r.get_array(s.vertices, nv);
  r.get_array(s.face_start, nf + 1);
  r.get_array(s.face_vertices, ni);
  r.get_array(s.face_leaf, nf);
  r.get_array(s.face_sign, nf);
  for (uint64_t v = 0; v < nv; ++v)
    for (int a = 0; a < 3; ++a)
      if (!(std::abs(s.vertices[v][a]) <= kMaxCoordinate))
        r.fail("vertex " + num(v) + ": a coordinate that is not finite or outside ±2^64");
  if (s.face_start[0] != 0 || s.face_start[nf] != ni)
    r.fail("face offsets do not span the indices");
  for (uint64_t f = 0; f < nf; ++f) {
    if (s.face_start[f + 1] < s.face_start[f]) r.fail("face " + num(f) + ": offsets that decrease");
    if (s.face_start[f + 1] - s.face_start[f] < 3)
      r.fail("face " + num(f) + ": " + num(s.face_start[f + 1] - s.face_start[f]) +
             " vertices (at least 3 needed)");
    if (s.face_leaf[f] >= nl) r.fail("face " + num(f) + ": a leaf that does not exist");
    if (s.face_sign[f] != 1 && s.face_sign[f] != -1)
      r.fail("face " + num(f) + ": a sign other than ±1");
  }
  for (uint64_t i = 0; i < ni; ++i)
    if (s.face_vertices[i] >= nv) r.fail("face index " + num(i) + ": a vertex out of range");
  r.need(4 + 4 + 16 + 1, nl, "truncated leaves");
  s.leaves.resize(nl);
  std::vector<uint8_t> flagged_open(nl, 0);
  uint64_t next_face = 0, next_vertex = 0;  // leaves tile the faces and vertices in order
  for (uint64_t l = 0; l < nl; ++l) {
    const size_t at = r.pos();
    Leaf& leaf = s.leaves[l];
    leaf.name = r.get_string();
    leaf.origin = r.get_string();
    leaf.first_face = r.get<uint32_t>();
    leaf.face_count = r.get<uint32_t>();
    leaf.first_vertex = r.get<uint32_t>();
    leaf.vertex_count = r.get<uint32_t>();
    const uint8_t all_flags = r.get<uint8_t>();
    const uint8_t flags = all_flags & ~kColourFlag;
    if (all_flags & kColourFlag) {
      std::array<uint8_t, 3> rgb{};
      for (uint8_t& c : rgb) c = r.get<uint8_t>();
      leaf.colour = rgb;
    }
    const std::string label = "leaf " + num(l) + " (at byte " + num(at) + ")";
    if (version == kFieldVersion ? (flags > 3 && flags != 4 && flags != 8) : flags > 3)
      r.fail(label + ": flags other than 0..3" + (version == kFieldVersion ? ", 4 or 8" : ""));
    leaf.flipped = (flags & 1) != 0;
    flagged_open[l] = (flags & 2) != 0;
    if (flags == 4) {
      if (leaf.face_count != 0 || leaf.vertex_count != 0)
        r.fail(label + ": a field leaf with faces or vertices");
      leaf.field = static_cast<int32_t>(s.fields.size());
      s.fields.emplace_back();  // read after the nodes
    }
    if (flags == 8) {
      if (leaf.face_count != 0 || leaf.vertex_count != 0)
        r.fail(label + ": a warp leaf with faces or vertices");
      leaf.warp = static_cast<int32_t>(s.warps.size());
      s.warps.emplace_back();  // read after the fields
    }
    if (leaf.first_face != next_face || uint64_t{leaf.first_face} + leaf.face_count > nf ||
        leaf.first_vertex != next_vertex || uint64_t{leaf.first_vertex} + leaf.vertex_count > nv)
      r.fail(label + ": faces or vertices that do not follow the previous leaf's");
    next_face += leaf.face_count;
    next_vertex += leaf.vertex_count;
    for (uint32_t f = leaf.first_face; f < leaf.first_face + leaf.face_count; ++f) {
      if (s.face_leaf[f] != l) r.fail(label + ": face " + num(f) + " is tagged with another leaf");
      for (uint32_t v : s.face(f)) {
        if (v < leaf.first_vertex || v >= leaf.first_vertex + leaf.vertex_count)
          r.fail(label + ": face " + num(f) + " uses another leaf's vertex");
        leaf.bbox.add(s.vertices[v]);
      }
    }
  }
  if (next_face != nf || next_vertex != nv) r.fail("faces or vertices outside every leaf");
  r.need(9, nn, "truncated nodes");
  s.tree.nodes.resize(nn);
  std::vector<uint8_t> leaf_used(nl, 0);
  std::vector<uint32_t> operand_of(nn, 0);  // how many operations use each node
  for (uint64_t i = 0; i < nn; ++i) {
    const size_t at = r.pos();
    const std::string label = "node " + num(i) + " (at byte " + num(at) + ")";
    CsgNode& node = s.tree.nodes[i];
    const uint8_t op = r.get<uint8_t>();
    if (op > static_cast<uint8_t>(CsgOp::kComplement)) r.fail(label + ": an unknown operation");
    node.op = static_cast<CsgOp>(op);
    node.leaf = r.get<uint32_t>();
    const uint32_t children = r.get<uint32_t>();
    r.get_array(node.children, children);
    if (node.op == CsgOp::kLeaf) {
      if (node.leaf >= nl || children != 0) r.fail(label + ": a leaf node without its leaf");
      ++leaf_used[node.leaf];
    } else {
      const size_t least = node.op == CsgOp::kDifference ? 2 : 1;
      if (children < least || (node.op == CsgOp::kComplement && children != 1))
        r.fail(label + ": an operation with the wrong number of operands");
      for (uint32_t c : node.children) {
        if (c >= i) r.fail(label + ": an operand that does not come before its operation");
        ++operand_of[c];
      }
    }
  }
  for (uint64_t l = 0; l < nl; ++l) {
    Leaf& leaf = s.leaves[l];
    if (!leaf.is_field()) continue;
    read_field(r, s.fields[leaf.field], "leaf " + num(l));
    leaf.bbox = field_support_box(s.fields[leaf.field]);
  }
  for (uint64_t l = 0; l < nl; ++l) {
    Leaf& leaf = s.leaves[l];
    if (leaf.is_warp())
      leaf.bbox = read_warp(r, s.warps[leaf.warp], "leaf " + num(l), what, bytes, depth);
  }
  if (!r.done()) r.fail_here("trailing bytes");
  if (nn == 0 ? nl != 0 : root >= nn) r.fail("no root");
  for (uint64_t l = 0; l < nl; ++l)
    if (leaf_used[l] != 1) r.fail("leaf " + num(l) + " is used by no node or by several");
  // A tree: every node but the root is the operand of exactly one operation. Then each leaf has
  // one path from the root, and the sign of its faces is fixed by it (solid.h notation: a
  // complement or a difference's later operand reverses).
  for (uint64_t i = 0; i < nn; ++i)
    if (operand_of[i] != (i == root ? 0u : 1u))
      r.fail("node " + num(i) + " is the operand of " + num(operand_of[i]) +
             " operations (a tree needs " + (i == root ? "0: it is the root)" : "1)"));
  s.tree.root = root;
  std::vector<int8_t> parity(nn, 1);  // children come before their operation: walk down
  for (uint64_t i = nn; i-- > 0;) {
    const CsgNode& node = s.tree.nodes[i];
    for (size_t k = 0; k < node.children.size(); ++k) {
      const bool reverses =
          node.op == CsgOp::kComplement || (node.op == CsgOp::kDifference && k > 0);
      parity[node.children[k]] = static_cast<int8_t>(reverses ? -parity[i] : parity[i]);
    }
  }
  std::vector<int8_t> leaf_sign(nl, 1);
  for (uint64_t i = 0; i < nn; ++i)
    if (s.tree.nodes[i].op == CsgOp::kLeaf) leaf_sign[s.tree.nodes[i].leaf] = parity[i];
  for (uint64_t f = 0; f < nf; ++f)
    if (s.face_sign[f] != leaf_sign[s.face_leaf[f]])
      r.fail("face " + num(f) + ": sign " + std::to_string(s.face_sign[f]) +
             ", but its leaf's place in the expression gives " +
             std::to_string(leaf_sign[s.face_leaf[f]]));
  for (uint64_t l = 0; l < nl; ++l)
    if (!s.leaves[l].is_implicit()) check_leaf(s, l, flagged_open[l] != 0, r);
  return s;
}

}  // namespace

}  // namespace cover

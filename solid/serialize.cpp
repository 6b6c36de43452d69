#include "solid/serialize.h"

#include <bit>
#include <cmath>
#include <cstring>

#include "solid/errors.h"

namespace cover {
namespace {

static_assert(std::endian::native == std::endian::little, "the format is little-endian");
constexpr char kMagic[8] = {'C', 'O', 'V', 'E', 'R', 'S', 'O', 'L'};
constexpr uint32_t kVersion = 1;

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
    if (count > left / size) fail(why);
  }
  bool done() const { return pos_ == in_.size(); }

 private:
  std::string_view in_;
  size_t pos_ = 0;
  const std::string& what_;
};

}  // namespace

std::string solid_to_bytes(const Solid& s) {
  Writer w;
  w.put_array(kMagic, 8);
  w.put(kVersion);
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
    w.put(static_cast<uint8_t>((leaf.flipped ? 1 : 0) | (leaf.open() ? 2 : 0)));
  }
  for (const CsgNode& node : s.tree.nodes) {
    w.put(static_cast<uint8_t>(node.op));
    w.put(node.leaf);
    w.put(static_cast<uint32_t>(node.children.size()));
    w.put_array(node.children.data(), node.children.size());
  }
  return w.take();
}

Solid solid_from_bytes(std::string_view bytes, const std::string& what) {
  Reader r(bytes, what);
  r.need(1, 8, "truncated");
  if (std::memcmp(bytes.data(), kMagic, 8) != 0) r.fail("wrong magic");
  r.get<uint64_t>();  // the magic
  if (r.get<uint32_t>() != kVersion) r.fail("unsupported version");
  const uint64_t nv = r.get<uint64_t>(), nf = r.get<uint64_t>(), ni = r.get<uint64_t>(),
                 nl = r.get<uint64_t>(), nn = r.get<uint64_t>();
  const uint32_t root = r.get<uint32_t>();
  if (nv > UINT32_MAX || nf >= UINT32_MAX || ni > UINT32_MAX || nl > UINT32_MAX || nn > UINT32_MAX)
    r.fail("counts beyond 32-bit indices");
  Solid s;
  r.get_array(s.vertices, nv);
  r.get_array(s.face_start, nf + 1);
  r.get_array(s.face_vertices, ni);
  r.get_array(s.face_leaf, nf);
  r.get_array(s.face_sign, nf);
  for (const Vec3& v : s.vertices)
    for (int a = 0; a < 3; ++a)
      if (!(std::abs(v[a]) <= kMaxCoordinate)) r.fail("a vertex outside the supported range");
  if (s.face_start[0] != 0 || s.face_start[nf] != ni) r.fail("face offsets do not span the indices");
  for (uint64_t f = 0; f < nf; ++f) {
    if (s.face_start[f + 1] < s.face_start[f]) r.fail("face offsets that decrease");
    if (s.face_leaf[f] >= nl) r.fail("a face of a leaf that does not exist");
    if (s.face_sign[f] != 1 && s.face_sign[f] != -1) r.fail("a face sign other than ±1");
  }
  for (uint32_t v : s.face_vertices)
    if (v >= nv) r.fail("a vertex index out of range");
  r.need(4 + 4 + 16 + 1, nl, "truncated leaves");
  s.leaves.resize(nl);
  for (uint64_t l = 0; l < nl; ++l) {
    Leaf& leaf = s.leaves[l];
    leaf.name = r.get_string();
    leaf.origin = r.get_string();
    leaf.first_face = r.get<uint32_t>();
    leaf.face_count = r.get<uint32_t>();
    leaf.first_vertex = r.get<uint32_t>();
    leaf.vertex_count = r.get<uint32_t>();
    const uint8_t flags = r.get<uint8_t>();
    if (flags > 3) r.fail("leaf flags other than 0..3");
    leaf.flipped = (flags & 1) != 0;
    leaf.boundary_edges = (flags & 2) != 0 ? 1 : 0;  // open: the count itself is not kept
    if (uint64_t{leaf.first_face} + leaf.face_count > nf ||
        uint64_t{leaf.first_vertex} + leaf.vertex_count > nv)
      r.fail("a leaf's faces or vertices out of range");
    for (uint32_t f = leaf.first_face; f < leaf.first_face + leaf.face_count; ++f) {
      if (s.face_leaf[f] != l) r.fail("a leaf's faces tagged with another leaf");
      for (uint32_t v : s.face(f)) {
        if (v < leaf.first_vertex || v >= leaf.first_vertex + leaf.vertex_count)
          r.fail("a face using another leaf's vertex");
        leaf.bbox.add(s.vertices[v]);
      }
    }
  }
  uint64_t tagged = 0;
  for (const Leaf& leaf : s.leaves) tagged += leaf.face_count;
  if (tagged != nf) r.fail("faces outside every leaf");
  r.need(9, nn, "truncated nodes");
  s.tree.nodes.resize(nn);
  std::vector<uint8_t> leaf_used(nl, 0);
  for (uint64_t i = 0; i < nn; ++i) {
    CsgNode& node = s.tree.nodes[i];
    const uint8_t op = r.get<uint8_t>();
    if (op > static_cast<uint8_t>(CsgOp::kComplement)) r.fail("an unknown operation");
    node.op = static_cast<CsgOp>(op);
    node.leaf = r.get<uint32_t>();
    const uint32_t children = r.get<uint32_t>();
    r.get_array(node.children, children);
    if (node.op == CsgOp::kLeaf) {
      if (node.leaf >= nl || children != 0) r.fail("a leaf node without its leaf");
      ++leaf_used[node.leaf];
    } else {
      const size_t least = node.op == CsgOp::kDifference ? 2 : 1;
      if (children < least || (node.op == CsgOp::kComplement && children != 1))
        r.fail("an operation with the wrong number of operands");
      for (uint32_t c : node.children)
        if (c >= i) r.fail("an operand that does not come before its operation");
    }
  }
  if (nn == 0 ? nl != 0 : root >= nn) r.fail("no root");
  for (uint8_t used : leaf_used)
    if (used != 1) r.fail("a leaf used by no node or by several");
  s.tree.root = root;
  if (!r.done()) r.fail("trailing bytes");
  return s;
}

}  // namespace cover
